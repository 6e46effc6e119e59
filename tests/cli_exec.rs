//! `axterm exec` as a script sees it: stdout, stderr and the exit code.

mod cli_support;

use cli_support::{axterm, stderr, stdout};

#[test]
fn a_value_out_of_range_is_refused_before_sending() {
    // A port that cannot exist: had anything been sent, opening it would
    // have failed with exit 3.
    let out = axterm(&[
        "exec",
        "--port",
        "/nonexistent/tty",
        "GAP 1, 0",
        "SAP 6, 0, 100000",
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_eq!(stdout(&out), "");
    let err = stderr(&out);
    assert!(err.contains("line 2 `SAP 6, 0, 100000`"), "{err}");
    assert!(err.contains("100000 outside 0..255"), "{err}");
    assert!(err.contains("nothing was sent"), "{err}");
}

#[test]
fn every_bad_line_is_named() {
    let out = axterm(&[
        "exec",
        "--sim",
        "tmcm1110",
        "MOVE 0, 10",
        "GAP 1, 0",
        "GAP 1",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
    let err = stderr(&out);
    assert!(err.contains("line 1 `MOVE 0, 10`"), "{err}");
    assert!(
        err.contains("line 3 `GAP 1`: GAP: missing <motor>"),
        "{err}"
    );
    assert!(!err.contains("line 2"), "{err}");
}

#[test]
fn exec_needs_a_connection() {
    let out = axterm(&["exec", "GAP 1, 0"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
    assert!(
        stderr(&out).contains("give a connection"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn an_unknown_simulator_or_protocol_is_a_usage_error() {
    let out = axterm(&["exec", "--sim", "tmcm9999", "GAP 1, 0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("known: tmcm1110"), "{}", stderr(&out));
    let out = axterm(&[
        "exec",
        "--tcp",
        "127.0.0.1:1",
        "--protocol",
        "modbus",
        "GAP 1, 0",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("known: tmcl"), "{}", stderr(&out));
}

#[test]
fn a_port_that_cannot_be_opened_exits_3_with_the_reason() {
    let out = axterm(&["exec", "--port", "/nonexistent/tty", "GAP 1, 0"]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert_eq!(stdout(&out), "");
    let said = stderr(&out);
    assert!(
        said.contains(
            "cannot open /nonexistent/tty at 9600 Bd: no such port (not plugged in? a wrong name?)"
        ),
        "{said}"
    );
    // What there is instead (no port at all in a container, some on a PC).
    assert!(
        said.contains("\n  no serial port is here at all")
            || said.contains("\n  /nonexistent/tty is not among the serial ports here"),
        "{said}"
    );
}

/// A pseudo-terminal held by this test (an exclusive open, as minicom or
/// another axterm would), and its path.
fn held_pty() -> (serialport::TTYPort, serialport::TTYPort, String) {
    use serialport::SerialPort;
    let (master, slave) = serialport::TTYPort::pair().expect("a pseudo-terminal");
    let path = slave.name().expect("the slave has a path");
    drop(slave);
    let held = serialport::new(&path, 9600)
        .open_native()
        .expect("the test holds it");
    (master, held, path)
}

#[test]
fn a_busy_port_names_the_program_that_holds_it() {
    let (_master, _held, path) = held_pty();
    let out = axterm(&["exec", "--port", &path, "GAP 1, 0"]);
    assert_eq!(out.status.code(), Some(3), "a link error: {}", stderr(&out));
    assert_eq!(stdout(&out), "");
    let comm = std::fs::read_to_string("/proc/self/comm").expect("own comm");
    assert_eq!(
        stderr(&out),
        format!(
            "axterm exec: cannot open {path} at 9600 Bd: the port is in use by another program\n  \
             held by {} (pid {})\n  \
             close it there, then try again\n",
            comm.trim(),
            std::process::id()
        )
    );
}

/// The port given to group dialout (gid 20, as udev does), and axterm run
/// as nobody: refused, with the device as `ls -l` shows it and the fix.
/// Needs root, to hand the port over and to start axterm as nobody (CI
/// runs as root); elsewhere it says so and checks nothing.
#[test]
fn a_port_refused_by_its_mode_says_who_may_use_it_and_the_fix() {
    use std::os::unix::fs::PermissionsExt;
    use std::os::unix::process::CommandExt;
    // SAFETY: geteuid only returns this process's id.
    if unsafe { libc::geteuid() } != 0 {
        eprintln!("not root: cannot start axterm as another user; not checked");
        return;
    }
    let (_master, slave) = serialport::TTYPort::pair().expect("a pseudo-terminal");
    let path = serialport::SerialPort::name(&slave).expect("the slave has a path");
    std::os::unix::fs::chown(&path, Some(0), Some(20)).expect("chown");
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o660)).expect("chmod");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["exec", "--port", &path, "GAP 1, 0"])
        .uid(65534)
        .gid(65534)
        .output()
        .expect("run axterm as nobody");
    assert_eq!(out.status.code(), Some(3), "a link error: {}", stderr(&out));
    let said = stderr(&out);
    let lines: Vec<&str> = said.lines().collect();
    assert_eq!(
        lines.first().copied(),
        Some(format!("axterm exec: cannot open {path} at 9600 Bd: permission denied").as_str()),
        "{said}"
    );
    assert!(
        lines
            .get(1)
            .is_some_and(|l| l.starts_with("  crw-rw---- root ")
                && l.ends_with(&format!(" {path}   (`ls -l {path}`)"))),
        "{said}"
    );
    assert!(
        lines
            .get(2)
            .is_some_and(|l| l.contains(" are not in group ")),
        "{said}"
    );
    assert!(
        lines
            .get(3)
            .is_some_and(|l| l.starts_with("  fix: `sudo usermod -aG ")
                && l.ends_with("$USER`, then log out and in again")),
        "{said}"
    );
}

#[test]
fn lines_run_in_order_with_one_result_each() {
    let out = axterm(&["exec", "--sim", "tmcm1110", "SAP 4, 0, 1234", "GAP 4, 0"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "ok\n1234\n");
    assert_eq!(stderr(&out), "");
}

#[test]
fn reads_print_their_values() {
    let out = axterm(&[
        "exec",
        "--sim",
        "tmcm1110",
        "VERSION",
        "GGP 0, 3",
        "SGP 0, 3, 4294967295",
        "GGP 0, 3",
        "RFS STATUS, 0",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "1110V112\n0\nok\n4294967295\n0\n");
}

#[test]
fn a_refusal_by_the_module_stops_the_run_and_exits_1() {
    // A raw frame passes the console's checks; the module refuses it.
    let out = axterm(&[
        "exec",
        "--sim",
        "tmcm1110",
        "GAP 4, 0",
        "5 6 0 300",
        "SAP 4, 0, 5",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let lines: Vec<String> = stdout(&out).lines().map(String::from).collect();
    assert_eq!(lines.len(), 1, "the third line must not run: {lines:?}");
    assert_eq!(
        stderr(&out),
        "axterm exec: line 2: module 1 rejected SAP 6, 0, 300: invalid value (status 4)\n"
    );
}

#[test]
fn json_gives_one_object_per_line() {
    let out = axterm(&[
        "exec",
        "--sim",
        "tmcm1110",
        "--format",
        "json",
        "SAP 4, 0, 1234",
        "gap 4 0",
        "5 6 0 300",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let objects: Vec<serde_json::Value> = stdout(&out)
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect();
    assert_eq!(objects.len(), 3);
    let gap = &objects[1];
    assert_eq!(gap["line"], "gap 4 0");
    assert_eq!(gap["command"], "GAP 4, 0");
    assert_eq!(gap["request"], "01 06 04 00 00 00 00 00 0B");
    assert_eq!(gap["reply"], "02 01 64 06 00 00 04 D2 43");
    assert_eq!(gap["status"], 100);
    assert_eq!(gap["value"], 1234);
    assert_eq!(gap["ok"], true);
    assert!(gap["elapsed_us"].is_u64(), "{gap}");
    assert_eq!(objects[0]["value"], serde_json::Value::Null);
    let refused = &objects[2];
    assert_eq!(refused["ok"], false);
    assert_eq!(refused["status"], 4);
    assert_eq!(refused["reply"], "02 01 04 05 00 00 00 00 0C");
    assert!(
        refused["error"]
            .as_str()
            .is_some_and(|e| e.contains("invalid value (status 4)")),
        "{refused}"
    );
}

#[test]
fn a_tcp_bridge_that_refuses_exits_3() {
    // Bind and drop a listener: nothing listens on that port any more.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let address = format!("127.0.0.1:{port}");
    let out = axterm(&["exec", "--tcp", &address, "GAP 1, 0"]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(
        stderr(&out).contains(&format!("cannot open tcp {address}")),
        "{}",
        stderr(&out)
    );
}
