//! `axterm sim tmcm1110` served over a real pseudo-terminal and over TCP,
//! driven by an independent client that only knows the TMCL wire format.

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use axterm::protocol::tmcl::{FRAME_LEN, Reply, Request, Status};
use axterm::sim::faults::{FaultInjector, FaultPlan};
use serialport::SerialPort;

/// Only guards against a hung test; a healthy exchange takes milliseconds.
const GIVE_UP_AFTER: Duration = Duration::from_secs(10);

struct Served {
    child: Child,
    endpoint: String,
}

impl Served {
    fn start(args: &[&str]) -> Served {
        Served::start_with(args, Stdio::inherit())
    }

    /// Started with its stderr kept, for [`Served::stderr`].
    fn start_keeping_stderr(args: &[&str]) -> Served {
        Served::start_with(args, Stdio::piped())
    }

    fn start_with(args: &[&str], stderr: Stdio) -> Served {
        let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(stderr)
            .spawn()
            .expect("start axterm sim");
        let stdout = child.stdout.take().expect("stdout");
        let mut first_line = String::new();
        BufReader::new(stdout)
            .read_line(&mut first_line)
            .expect("read the endpoint line");
        Served {
            child,
            endpoint: first_line.trim().to_string(),
        }
    }

    /// End it as a user would (SIGTERM) and return its exit code.
    fn terminate(mut self) -> Option<i32> {
        let pid = libc::pid_t::try_from(self.child.id()).expect("pid fits pid_t");
        // SAFETY: sends a signal to our own child process; nothing is shared.
        let sent = unsafe { libc::kill(pid, libc::SIGTERM) };
        assert_eq!(sent, 0, "kill(SIGTERM) failed");
        self.child.wait().ok().and_then(|s| s.code())
    }

    /// Wait for it to end on its own and return its exit code.
    fn wait(mut self) -> Option<i32> {
        self.child.wait().ok().and_then(|s| s.code())
    }

    /// What it wrote on stderr, once it has ended.
    fn stderr(&mut self) -> String {
        let mut text = String::new();
        if let Some(mut stderr) = self.child.stderr.take() {
            stderr.read_to_string(&mut text).expect("read stderr");
        }
        text
    }

    /// End it with SIGTERM; its exit code and what it wrote on stderr.
    fn terminate_and_read_stderr(mut self) -> (Option<i32>, String) {
        let stderr = self.child.stderr.take();
        let code = self.terminate();
        let mut text = String::new();
        if let Some(mut stderr) = stderr {
            stderr.read_to_string(&mut text).expect("read stderr");
        }
        (code, text)
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn request(command: u8, kind: u8, value: i32) -> [u8; FRAME_LEN] {
    Request {
        address: 1,
        command,
        kind,
        motor_bank: 0,
        value,
    }
    .to_bytes()
}

fn read_reply(port: &mut dyn Read) -> Reply {
    let mut frame = [0u8; FRAME_LEN];
    port.read_exact(&mut frame).expect("a 9-byte reply");
    Reply::from_bytes(&frame).expect("a reply with a good checksum")
}

fn transact(port: &mut (impl Read + Write), frame: [u8; FRAME_LEN]) -> Reply {
    port.write_all(&frame).expect("send");
    read_reply(port)
}

/// SAP/GAP/MVP/138 as the manual describes them (§3.6.5, §3.6.6, §3.6.4, §3.6.52).
fn run_sequence(port: &mut (impl Read + Write)) {
    const SAP: u8 = 5;
    const GAP: u8 = 6;
    const MVP: u8 = 4;
    const TARGET_EVENT: u8 = 138;

    let reply = transact(port, request(SAP, 4, 1000));
    assert_eq!((reply.status, reply.command), (Status::OK, SAP));
    assert_eq!((reply.host_address, reply.module_address), (2, 1));

    let reply = transact(port, request(GAP, 4, 0));
    assert_eq!((reply.status, reply.value), (Status::OK, 1000));

    let reply = transact(port, request(SAP, 6, 300));
    assert_eq!(reply.status, Status::INVALID_VALUE, "AP6 range is 0..255");

    let reply = transact(port, request(TARGET_EVENT, 0, 1));
    assert_eq!(
        (reply.status, reply.command, reply.value),
        (Status::OK, 138, 1)
    );

    let reply = transact(port, request(MVP, 1, 2000));
    assert_eq!((reply.status, reply.command), (Status::OK, MVP));

    // The second, unsolicited reply of 138 arrives when the target is reached.
    let reached = read_reply(port);
    assert_eq!(
        (reached.status, reached.command, reached.value),
        (Status::TARGET_REACHED, 138, 1)
    );
    let reply = transact(port, request(GAP, 8, 0));
    assert_eq!(reply.value, 1, "position reached flag");
    let reply = transact(port, request(GAP, 1, 0));
    assert_eq!(reply.value, 2000, "actual position");

    // A frame with a bad checksum gets status 1.
    let mut bad = request(GAP, 1, 0);
    bad[8] = bad[8].wrapping_add(1);
    let reply = transact(port, bad);
    assert_eq!(reply.status, Status::WRONG_CHECKSUM);
}

#[test]
fn pty_serves_a_steprocker_to_a_serial_client() {
    let served = Served::start(&["sim", "tmcm1110", "--pty"]);
    assert!(served.endpoint.starts_with('/'), "{}", served.endpoint);
    let mut port = serialport::new(&served.endpoint, 115_200)
        .timeout(GIVE_UP_AFTER)
        .open_native()
        .expect("open the printed path as a serial port");
    run_sequence(&mut port);
    drop(port);
    assert_eq!(served.terminate(), Some(0), "SIGTERM ends it cleanly");
}

#[test]
fn pty_survives_a_client_closing_and_another_opening() {
    let served = Served::start(&["sim", "tmcm1110", "--pty", "--address", "7"]);
    for _ in 0..2 {
        let mut port = serialport::new(&served.endpoint, 9600)
            .timeout(GIVE_UP_AFTER)
            .open_native()
            .expect("open");
        let mut frame = request(6, 4, 0);
        frame[0] = 7;
        frame[8] = axterm::protocol::tmcl::checksum(&frame[..8]);
        let reply = transact(&mut port, frame);
        assert_eq!((reply.status, reply.module_address), (Status::OK, 7));
    }
    assert_eq!(served.terminate(), Some(0));
}

#[test]
fn tcp_serves_a_steprocker_on_loopback() {
    let served = Served::start(&["sim", "tmcm1110", "--tcp", "127.0.0.1:0"]);
    let mut stream = std::net::TcpStream::connect(&served.endpoint).expect("connect");
    stream
        .set_read_timeout(Some(GIVE_UP_AFTER))
        .expect("timeout");
    run_sequence(&mut stream);
    drop(stream);
    assert_eq!(served.terminate(), Some(0));
}

/// A script may signal the simulator as soon as it has read the endpoint
/// line; the stop handlers are in place before that line is printed.
#[test]
fn sigterm_right_after_the_announcement_ends_cleanly() {
    for args in [
        &["sim", "tmcm1110", "--pty"][..],
        &["sim", "tmcm1110", "--tcp", "127.0.0.1:0"][..],
    ] {
        let served = Served::start(args);
        assert_eq!(served.terminate(), Some(0), "{args:?}");
    }
}

fn open_pty(path: &str, timeout: Duration) -> serialport::TTYPort {
    serialport::new(path, 9600)
        .timeout(timeout)
        .open_native()
        .expect("open the printed path as a serial port")
}

#[test]
fn a_served_sim_at_a_baud_rate_runs_the_whole_sequence() {
    let served = Served::start(&["sim", "tmcm1110", "--pty", "--baud", "115200"]);
    let mut port = open_pty(&served.endpoint, GIVE_UP_AFTER);
    run_sequence(&mut port);
    drop(port);
    assert_eq!(served.terminate(), Some(0));
}

/// The first seed whose injector drops the first reply and passes the
/// second, with `drop=0.5`: found with the same injector the server uses.
fn seed_dropping_only_the_first_reply() -> u64 {
    (0..1000)
        .find(|&seed| {
            let plan = FaultPlan::parse(&format!("drop=0.5,seed={seed}")).expect("plan");
            let mut injector = FaultInjector::new(&plan);
            injector.to_host(vec![1; FRAME_LEN]).is_none()
                && injector.to_host(vec![2; FRAME_LEN]).is_some()
        })
        .expect("a seed among the first thousand")
}

#[test]
fn a_dropped_reply_never_arrives_and_is_reported() {
    let spec = format!("drop=0.5,seed={}", seed_dropping_only_the_first_reply());
    let served = Served::start_keeping_stderr(&["sim", "tmcm1110", "--pty", "--fault", &spec]);
    // Showing that something never comes needs a bounded wait: nothing may
    // arrive for GAP 4 (max speed) within it. The wait also lets the
    // simulator take GAP 4 as a request of its own before the next one.
    let mut port = open_pty(&served.endpoint, Duration::from_millis(300));
    port.write_all(&request(6, 4, 0)).expect("send GAP 4");
    let mut buf = [0u8; FRAME_LEN];
    assert_eq!(
        port.read(&mut buf).map_err(|e| e.kind()),
        Err(std::io::ErrorKind::TimedOut),
        "GAP 4's reply was dropped"
    );
    // The line still works: GAP 5 (max acceleration, 100) gets its reply.
    port.set_timeout(GIVE_UP_AFTER).expect("timeout");
    let reply = transact(&mut port, request(6, 5, 0));
    assert_eq!((reply.command, reply.value), (6, 100), "GAP 5's reply");
    drop(port);
    let (code, stderr) = served.terminate_and_read_stderr();
    assert_eq!(code, Some(0));
    assert!(
        stderr.contains("faults injected: 2 requests, 2 replies: 1 dropped, 0 corrupted"),
        "{stderr}"
    );
}

#[test]
fn corrupted_replies_fail_their_checksum() {
    let served = Served::start(&[
        "sim",
        "tmcm1110",
        "--pty",
        "--baud",
        "115200",
        "--fault",
        "corrupt=1,seed=9",
    ]);
    let mut port = open_pty(&served.endpoint, GIVE_UP_AFTER);
    for _ in 0..5 {
        port.write_all(&request(6, 1, 0)).expect("send");
        let mut frame = [0u8; FRAME_LEN];
        port.read_exact(&mut frame).expect("a 9-byte reply");
        assert!(Reply::from_bytes(&frame).is_err(), "{frame:02X?}");
    }
    drop(port);
    assert_eq!(served.terminate(), Some(0));
}

#[test]
fn a_cut_pty_vanishes_like_an_unplugged_adapter() {
    let mut served = Served::start_keeping_stderr(&[
        "sim",
        "tmcm1110",
        "--pty",
        "--fault",
        "disconnect-after=1",
    ]);
    let mut port = open_pty(&served.endpoint, GIVE_UP_AFTER);
    assert_eq!(transact(&mut port, request(6, 1, 0)).status, Status::OK);
    port.write_all(&request(6, 1, 0)).expect("send");
    let mut buf = [0u8; FRAME_LEN];
    // A hung-up tty reads as end of file, or poll reports the hangup.
    match port.read(&mut buf) {
        Ok(0) => {}
        Err(e) => assert_eq!(e.kind(), std::io::ErrorKind::BrokenPipe, "{e}"),
        Ok(n) => panic!("{n} bytes after the cut: {:02X?}", &buf[..n]),
    }
    let stderr = served.stderr();
    assert!(
        stderr.contains("link cut after 1 request (injected fault)"),
        "{stderr}"
    );
    assert_eq!(served.wait(), Some(0), "it ends on its own");
}

#[test]
fn a_cut_tcp_connection_can_be_made_again() {
    let served = Served::start(&[
        "sim",
        "tmcm1110",
        "--tcp",
        "127.0.0.1:0",
        "--fault",
        "disconnect-after=1",
    ]);
    for _ in 0..2 {
        let mut stream = std::net::TcpStream::connect(&served.endpoint).expect("connect");
        stream
            .set_read_timeout(Some(GIVE_UP_AFTER))
            .expect("timeout");
        assert_eq!(transact(&mut stream, request(6, 1, 0)).status, Status::OK);
        stream.write_all(&request(6, 1, 0)).expect("send");
        let mut buf = [0u8; FRAME_LEN];
        match stream.read(&mut buf) {
            Ok(0) => {}
            Err(e) => assert_eq!(e.kind(), std::io::ErrorKind::ConnectionReset, "{e}"),
            Ok(n) => panic!("{n} bytes after the cut"),
        }
    }
    assert_eq!(served.terminate(), Some(0));
}

#[test]
fn a_bad_fault_spec_is_refused_before_serving() {
    let output = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["sim", "tmcm1110", "--pty", "--fault", "drop=0.5,corupt=1"])
        .output()
        .expect("run axterm sim");
    assert_eq!(output.status.code(), Some(2));
    assert!(output.stdout.is_empty(), "no endpoint announced");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("bad fault 'corupt=1': unknown fault 'corupt'"),
        "{stderr}"
    );
}
