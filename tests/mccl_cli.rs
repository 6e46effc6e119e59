//! MCCL through the command-line front ends: `axterm encode mccl` prints
//! the bytes a line becomes; `exec` and `run` refuse a line that does not
//! parse or check before anything is sent (exit 2); and `exec` talks to a
//! controller played by a fake over TCP that answers with bytes written
//! out by hand from the manual (Ch2 echo, Ch8 `01 value` replies, the Ch13
//! prompt `>`, the Ch14 `?code` errors), not through axterm's codec.

mod cli_support;

use cli_support::{axterm, stderr, stdout};
use std::io::{BufRead, BufReader, Write};
use std::net::TcpListener;
use std::thread::JoinHandle;

#[test]
fn encode_prints_the_line_and_its_cr() {
    let out = axterm(&["encode", "mccl", "2MR1000,WS0.5,MR-1000,WS0.5,RP6"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "2MR1000,WS0.5,MR-1000,WS0.5,RP6\\r\n");
    // As the manual writes lines: lower case, blanks after commas, a
    // comment, Cyrillic look-alikes from the PDF text.
    let out = axterm(&["encode", "mccl", "lu\"STATUS\", 2rl@0 ;status of axis 2"]);
    assert_eq!(stdout(&out), "LU\"STATUS\",2RL@0\\r\n");
    let out = axterm(&["encode", "mccl", "1ТР.3"]);
    assert_eq!(stdout(&out), "1TP.3\\r\n");
}

#[test]
fn encode_refuses_what_does_not_parse_or_check() {
    for (line, why) in [
        ("1G0", "did you mean `1GO`?"),
        ("1DS0", "DS must be > 0, not 0"),
        ("1TP,RP2,RP3", "only one RP"),
        ("DM,HM", "DM and HM cannot be in the same command string"),
        (
            "1MN,MD5,1MR5",
            "MD must be the first command of a line (−4)",
        ),
        ("1FR0.00025", "FR takes an integer"),
        ("1EI9", "malfunction"),
        ("", "repeat the controller's last line"),
        ("BK\"wait\"", "single-steps"),
    ] {
        let out = axterm(&["encode", "mccl", line]);
        assert_eq!(out.status.code(), Some(2), "{line}");
        assert_eq!(stdout(&out), "", "{line}");
        assert!(stderr(&out).contains(why), "{line}: {}", stderr(&out));
    }
    let out = axterm(&["encode", "mccl", "--address", "3", "1TP"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no bus address"), "{}", stderr(&out));
}

/// A controller on a TCP port: for each line received it echoes the line,
/// sends the reply lines scripted for it and the prompt, each line ended
/// by CR LF [? the terminator is not stated; the console takes any]; `NO`
/// does nothing. It hands back every line received after the console's
/// connect probe (`NO`, `NO,NO,NO`, checked here).
struct Fake {
    address: String,
    thread: JoinHandle<Vec<String>>,
}

impl Fake {
    fn start(script: &[(&str, &[&str])]) -> Fake {
        let listener = TcpListener::bind("127.0.0.1:0").expect("a free port");
        let address = listener.local_addr().expect("bound").to_string();
        let script: Vec<(String, Vec<String>)> = script
            .iter()
            .map(|(line, replies)| {
                (
                    line.to_string(),
                    replies.iter().map(|r| r.to_string()).collect(),
                )
            })
            .collect();
        let thread = std::thread::spawn(move || {
            let mut received = Vec::new();
            let Ok((stream, _)) = listener.accept() else {
                return received;
            };
            let mut writer = stream.try_clone().expect("clone");
            let mut reader = BufReader::new(stream);
            let mut bytes = Vec::new();
            while matches!(reader.read_until(b'\r', &mut bytes), Ok(n) if n > 0) {
                let line = String::from_utf8_lossy(&bytes)
                    .trim_end_matches('\r')
                    .to_string();
                bytes.clear();
                let mut answer = format!("{line}\r\n");
                match script.iter().find(|(l, _)| *l == line) {
                    _ if line == "NO" || line == "NO,NO,NO" => {}
                    Some((_, replies)) => {
                        for reply in replies {
                            answer.push_str(&format!("{reply}\r\n"));
                        }
                    }
                    None => answer.push_str("?1\r\n"),
                }
                answer.push('>');
                received.push(line);
                if writer.write_all(answer.as_bytes()).is_err() {
                    break;
                }
            }
            received
        });
        Fake { address, thread }
    }

    fn received(self) -> Vec<String> {
        let mut lines = self.thread.join().expect("the fake");
        if !lines.is_empty() {
            let probe: Vec<String> = lines.drain(..2.min(lines.len())).collect();
            assert_eq!(probe, ["NO", "NO,NO,NO"], "the connect probe first");
        }
        lines
    }
}

fn exec(fake: &Fake, lines: &[&str]) -> std::process::Output {
    let mut args = vec!["exec", "--tcp", &fake.address, "--protocol", "mccl"];
    args.extend_from_slice(lines);
    axterm(&args)
}

#[test]
fn exec_moves_and_reads_back_the_position() {
    let fake = Fake::start(&[
        ("1MN", &[]),
        ("1MA1000", &[]),
        ("1WS", &[]),
        ("1TP", &["01 1000"]),
        ("1TP.3,TT.3", &["01 999.750", "01 1000.000"]),
    ]);
    let out = exec(&fake, &["1MN", "1ma1000", "1WS", "1TP", "1TP.3,TT.3"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "ok\nok\nok\n1000\n999.750 1000.000\n");
    assert_eq!(
        fake.received(),
        ["1MN", "1MA1000", "1WS", "1TP", "1TP.3,TT.3"]
    );
}

#[test]
fn after_hm_lines_go_in_hex_and_replies_read_in_hex() {
    let fake = Fake::start(&[
        ("HM", &[]),
        ("1MA3E8,MR-0FF", &[]),
        ("1TP,TS", &["01 fffffc18", "01 0000000a"]),
        ("DM", &[]),
        ("1TP", &["01 -1000"]),
    ]);
    let out = exec(&fake, &["HM", "1MA1000,MR-255", "1TP,TS", "DM", "1TP"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "ok\nok\n-1000 10\nok\n-1000\n");
    assert_eq!(
        fake.received(),
        ["HM", "1MA3E8,MR-0FF", "1TP,TS", "DM", "1TP"]
    );
}

#[test]
fn an_error_reply_stops_the_run_with_its_ch14_meaning() {
    let fake = Fake::start(&[("RM", &[]), ("1MN,2MN,3MN,MC10", &["?-6"])]);
    let out = exec(&fake, &["RM", "1MN,2MN,3MN,MC10", "1TP"]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(stdout(&out), "ok\n");
    assert_eq!(
        stderr(&out),
        "axterm exec: line 2: the controller refused 1MN,2MN,3MN,MC10: ?-6 (Macro Doesn't \
         Exist, Ch14)\n"
    );
    assert_eq!(
        fake.received(),
        ["RM", "1MN,2MN,3MN,MC10"],
        "1TP never sent"
    );
}

#[test]
fn an_answer_that_is_not_the_success_answer_is_an_error() {
    // A reply line where the line reports nothing.
    let fake = Fake::start(&[("1MN", &["01 5"])]);
    let out = exec(&fake, &["1MN"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("unreadable answer to 1MN: `01 5` answers no reporting command"),
        "{}",
        stderr(&out)
    );
    drop(fake.received());
}

#[test]
fn a_line_that_does_not_parse_or_check_sends_nothing() {
    let fake = Fake::start(&[]);
    let out = exec(&fake, &["1TP", "1MR1000,N0", "0SV100"]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains("line 2 `1MR1000,N0`: `N0`: no two-letter command — did you mean `NO`?"),
        "{err}"
    );
    assert!(
        err.contains("line 3 `0SV100`: `0SV100`: SV acts on one axis"),
        "{err}"
    );
    assert!(err.contains("nothing was sent"), "{err}");
    // Nothing connected: unblock the fake's accept.
    drop(std::net::TcpStream::connect(&fake.address));
    assert!(fake.received().is_empty());
}

#[test]
fn run_checks_the_whole_file_first() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let file = dir.path().join("cycle.txt");
    std::fs::write(
        &file,
        "# a cycle\n1MN\n2MR1000,WS0.5,RP-1 ;negative repeat\n",
    )
    .expect("write");
    let out = axterm(&[
        "run",
        "--protocol",
        "mccl",
        "--dry-run",
        file.to_str().expect("a path"),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out)
            .contains(":3: `RP-1`: RP must be 0..2147483647, not -1 (−3 Negative Repeat Count)"),
        "{}",
        stderr(&out)
    );
    let fake = Fake::start(&[]);
    let out = axterm(&[
        "run",
        "--tcp",
        &fake.address,
        "--protocol",
        "mccl",
        file.to_str().expect("a path"),
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    drop(std::net::TcpStream::connect(&fake.address));
    assert!(fake.received().is_empty(), "1MN was not sent either");
}

#[test]
fn exec_on_the_simulator_prints_the_position_moved_to_last() {
    // Issue 14's acceptance line: motor on, move, wait for the trajectory,
    // tell the position (a servo within a count of its target).
    let out = axterm(&["exec", "--sim", "mccl", "1MN", "1MA1000", "1WS", "1TP"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "ok\nok\nok\n1000\n");
}
