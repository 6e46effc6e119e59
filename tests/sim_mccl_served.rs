//! `axterm sim mccl --pty` served by the real binary, driven by a raw
//! client that knows only what the MCCL manual says: a command line ends
//! with CR (Ch1), the controller echoes what it is sent (Ch2), sends `>`
//! when the line has completed (Ch13 PC), answers a Tell with `AA value`
//! (Ch8) and an error with `?` and a code (Ch2, Ch14); Escape aborts a
//! running line (Ch2). The bytes are written out here by hand, no axterm
//! code reads them. The simulator's own choices (CR LF after a line, the
//! offending command after the code) are its documented defaults.

mod served_support;

use std::io::{Read, Write};
use std::time::Duration;

use served_support::Served;

/// Only guards against a hung test; a healthy exchange takes milliseconds.
const GIVE_UP_AFTER: Duration = Duration::from_secs(30);

struct Port(serialport::TTYPort);

impl Port {
    fn open(path: &str) -> Port {
        Port(
            serialport::new(path, 115_200)
                .timeout(GIVE_UP_AFTER)
                .open_native()
                .expect("open the printed path as a serial port"),
        )
    }

    fn send(&mut self, bytes: &[u8]) {
        self.0.write_all(bytes).expect("write");
        self.0.flush().expect("flush");
    }

    /// Read until what came ends with `end`.
    fn read_until(&mut self, end: &str) -> String {
        let mut text = Vec::new();
        let mut byte = [0u8; 1];
        while !text.ends_with(end.as_bytes()) {
            self.0
                .read_exact(&mut byte)
                .expect("a byte before the time-out");
            text.push(byte[0]);
        }
        String::from_utf8_lossy(&text).into_owned()
    }

    /// Send a line and read everything up to its prompt.
    fn line(&mut self, line: &str) -> String {
        self.send(format!("{line}\r").as_bytes());
        self.read_until(">")
    }
}

#[test]
fn echo_prompt_and_a_tell_of_the_move() {
    let served = Served::start("mccl", &[]);
    let mut port = Port::open(&served.pty);
    assert_eq!(port.line("1MN"), "1MN\r\n>");
    assert_eq!(port.line("1MA1000"), "1MA1000\r\n>");
    assert_eq!(port.line("1WS"), "1WS\r\n>");
    let reply = port.line("1TP");
    let value: i64 = reply
        .strip_prefix("1TP\r\n01 ")
        .and_then(|r| r.strip_suffix("\r\n>"))
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no Tell reply in {reply:?}"));
    // A servo lands within its deadband (DB 5 counts by default).
    assert!((value - 1000).abs() <= 5, "1TP: {value}");
    // An unknown mnemonic: `?`, the code (1, unrecognized command) and the
    // command.
    assert_eq!(port.line("1XX"), "1XX\r\n?1 1XX\r\n>");
}

/// The values of the Tell lines in a reply (`03 1234` each, Ch8), after
/// the echo and before the prompt.
fn told_values(reply: &str, echo: &str) -> Vec<f64> {
    let body = reply
        .strip_prefix(&format!("{echo}\r\n"))
        .and_then(|r| r.strip_suffix(">"))
        .unwrap_or_else(|| panic!("no echo and prompt in {reply:?}"));
    body.split("\r\n")
        .filter(|l| !l.is_empty())
        .map(|l| {
            l.strip_prefix("03 ")
                .and_then(|v| v.parse().ok())
                .unwrap_or_else(|| panic!("not an axis-3 Tell line: {l:?}"))
        })
        .collect()
}

#[test]
fn pr_then_a_move_then_dr_reads_the_recording_back() {
    // Ch7 PR's own example: record 10 samples of a move of servo axis 3,
    // then display them through register 100 as the pointer. The 10
    // samples span 2.5 ms at the default 4 kHz loop (Ch5 HS): a steep
    // ramp (Ch5 SA, DS) makes them show motion.
    let served = Served::start("mccl", &[]);
    let mut port = Port::open(&served.pty);
    assert_eq!(
        port.line("3SA20000000,3DS20000000"),
        "3SA20000000,3DS20000000\r\n>"
    );
    assert_eq!(port.line("3DH0,3MN"), "3DH0,3MN\r\n>");
    assert_eq!(port.line("3PR10,3MA5000,3WS.1"), "3PR10,3MA5000,3WS.1\r\n>");
    assert_eq!(port.line("AL0,AR100"), "AL0,AR100\r\n>");
    let line = "3DR@100,AL@100,AA1,AR100,RP9";
    let actual = told_values(&port.line(line), line);
    assert_eq!(actual.len(), 10, "the first 10 recorded positions");
    assert!(actual.windows(2).all(|w| w[0] <= w[1]), "{actual:?}");
    // Ch7 DO and DQ (the DQ example's form): optimal positions lead the
    // actual ones; the output pushes forward.
    assert_eq!(port.line("AL0,AR100"), "AL0,AR100\r\n>");
    let line = "3DO@100,AL@100,AA1,AR100,RP9";
    let optimal = told_values(&port.line(line), line);
    assert_eq!(optimal.len(), 10);
    assert!(
        optimal.iter().zip(&actual).all(|(o, a)| o >= a) && optimal[9] > actual[9],
        "{optimal:?} vs {actual:?}"
    );
    let output = told_values(&port.line("3DQ9"), "3DQ9");
    assert!(output.len() == 1 && output[0] > 0.0, "{output:?}");
    // The move itself ended at its target (DB 5).
    let position = told_values(&port.line("3TP"), "3TP");
    assert!((position[0] - 5000.0).abs() <= 5.0, "{position:?}");
}

#[test]
fn the_repeat_line_runs_seven_cycles_and_escape_aborts_it() {
    let served = Served::start("mccl", &[]);
    let mut port = Port::open(&served.pty);
    assert_eq!(port.line("2MN"), "2MN\r\n>");
    // Ch2's line, run to its end: the prompt comes when the seventh cycle
    // is done, and axis 2 is back where it started.
    let line = "2MR1000,WS0.5,MR-1000,WS0.5,RP6";
    assert_eq!(port.line(line), format!("{line}\r\n>"));
    assert_eq!(port.line("2TT"), "2TT\r\n02 0\r\n>");
    // The same cycle counting its passes in R100: RP6 runs it 7 times.
    assert_eq!(port.line("AL0,AR100"), "AL0,AR100\r\n>");
    let counted = "2MR1000,WS0.1,MR-1000,WS0.1,AL@100,AA1,AR100,RP6";
    assert_eq!(port.line(counted), format!("{counted}\r\n>"));
    assert_eq!(port.line("TR100"), "TR100\r\n01 7\r\n>");
    // Escape aborts it: error -7, "Command Canceled by User" (Ch14), with
    // the command it was on.
    port.send(format!("{line}\r").as_bytes());
    assert_eq!(port.read_until("\r\n"), format!("{line}\r\n"));
    port.send(b"\x1b");
    let aborted = port.read_until(">");
    assert!(aborted.starts_with("?-7 "), "{aborted:?}");
    assert!(aborted.ends_with("\r\n>"), "{aborted:?}");
    assert_eq!(port.line("TE"), "TE\r\n-7\r\n>");
}

#[test]
fn a_macro_defined_lists_back_with_tm_and_runs_with_mc() {
    let served = Served::start("mccl", &[]);
    let mut port = Port::open(&served.pty);
    assert_eq!(port.line("2MN"), "2MN\r\n>");
    let define = "MD10,2MR500,WS0.1,MR-500,WS0.1";
    assert_eq!(port.line(define), format!("{define}\r\n>"));
    assert_eq!(
        port.line("TM10"),
        "TM10\r\nMC10,2MR500,WS0.1,MR-500,WS0.1\r\n>"
    );
    assert_eq!(port.line("MC10"), "MC10\r\n>");
    assert_eq!(port.line("2TT"), "2TT\r\n02 0\r\n>");
    assert_eq!(port.line("MC11"), "MC11\r\n?-6 MC11\r\n>");
}

#[test]
fn a_background_task_runs_while_other_commands_are_answered() {
    let served = Served::start("mccl", &[]);
    let mut port = Port::open(&served.pty);
    assert_eq!(port.line("AL0,AR100"), "AL0,AR100\r\n>");
    let task = "MD20,AL@100,AA1,AR100,WA0.01,JR-4";
    assert_eq!(port.line(task), format!("{task}\r\n>"));
    assert_eq!(port.line("GT20,AR150"), "GT20,AR150\r\n>");
    let count = |port: &mut Port| -> i64 {
        let reply = port.line("TR100");
        reply
            .strip_prefix("TR100\r\n01 ")
            .and_then(|r| r.strip_suffix("\r\n>"))
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{reply:?}"))
    };
    let first = count(&mut port);
    // The foreground waits for a move meanwhile (about 0.14 s).
    assert_eq!(port.line("1MN,1MR1000,1WS"), "1MN,1MR1000,1WS\r\n>");
    let second = count(&mut port);
    assert!(
        second > first,
        "the task kept counting: {first} then {second}"
    );
    assert_eq!(port.line("ET@150"), "ET@150\r\n>");
    assert_eq!(port.line("ET@150"), "ET@150\r\n?-20 ET@150\r\n>");
}

#[test]
fn an_eth_keeps_its_macros_in_the_eeprom_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("macros.json");
    let file = file.to_string_lossy().into_owned();
    {
        let served = Served::start("mccl-eth", &["--eeprom", &file]);
        let mut port = Port::open(&served.pty);
        assert_eq!(port.line("MD5,AL5,AR100"), "MD5,AL5,AR100\r\n>");
    }
    let served = Served::start("mccl-eth", &["--eeprom", &file]);
    let mut port = Port::open(&served.pty);
    assert_eq!(port.line("TM-1"), "TM-1\r\nMC5,AL5,AR100\r\n>");
    // A PCI keeps nothing: a memory file for it is refused, not ignored.
    let pci = std::process::Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["sim", "mccl", "--pty", "--eeprom", &file])
        .output()
        .expect("run axterm sim mccl");
    assert_eq!(pci.status.code(), Some(2));
    let said = String::from_utf8_lossy(&pci.stderr);
    assert!(
        said.contains("volatile") && said.contains("mccl-eth"),
        "{said}"
    );
}

#[test]
fn inputs_are_driven_while_it_serves() {
    let mut served = Served::start_driven("mccl", &["--input", "IN5=1"]);
    assert_eq!(
        served.next_answer(),
        "IN5 on (channel 5 reads on)",
        "the --input setting"
    );
    let mut port = Port::open(&served.pty);
    assert_eq!(port.line("TC5"), "TC5\r\n05 1\r\n>");
    assert_eq!(
        served.drive("LIM+1=1"),
        "LIM+1 on (channel 18), shared with axis 5"
    );
    assert_eq!(port.line("1TS28"), "1TS28\r\n01 1\r\n>");
}

/// `axterm sim mccl --tcp 127.0.0.1:0 EXTRA...`, ended when dropped.
struct ServedTcp {
    child: std::process::Child,
    endpoint: String,
}

impl ServedTcp {
    fn start(extra: &[&str]) -> ServedTcp {
        use std::io::BufRead;
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_axterm"))
            .args(["sim", "mccl", "--tcp", "127.0.0.1:0"])
            .args(extra)
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("start axterm sim");
        let stdout = child.stdout.take().expect("stdout");
        let mut first = String::new();
        std::io::BufReader::new(stdout)
            .read_line(&mut first)
            .expect("read the endpoint");
        ServedTcp {
            child,
            endpoint: first.trim().to_string(),
        }
    }
}

impl Drop for ServedTcp {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn tcp_at_a_baud_rate_with_a_stored_macro_corrupted() {
    // --fault corrupt-store=1: the first macro stored keeps a changed
    // parameter; only TM shows it.
    let served = ServedTcp::start(&["--baud", "115200", "--fault", "corrupt-store=1"]);
    let mut stream = std::net::TcpStream::connect(&served.endpoint).expect("connect");
    stream
        .set_read_timeout(Some(GIVE_UP_AFTER))
        .expect("timeout");
    let mut line = |text: &str| -> String {
        stream
            .write_all(format!("{text}\r").as_bytes())
            .expect("write");
        let mut got = Vec::new();
        let mut byte = [0u8; 1];
        while !got.ends_with(b">") {
            stream.read_exact(&mut byte).expect("a byte");
            got.push(byte[0]);
        }
        String::from_utf8_lossy(&got).into_owned()
    };
    assert_eq!(line("MD4,1MR1000"), "MD4,1MR1000\r\n>");
    assert_eq!(line("TM4"), "TM4\r\nMC4,1MR1001\r\n>");
    assert_eq!(line("MD5,1MR1000"), "MD5,1MR1000\r\n>");
    assert_eq!(line("TM5"), "TM5\r\nMC5,1MR1000\r\n>");
}
