//! `axterm exec` as a script sees it: stdout, stderr and the exit code.

use std::process::{Command, Output};

fn axterm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(args)
        .output()
        .expect("run axterm")
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

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
    assert!(
        stderr(&out).contains("cannot open /nonexistent/tty at 9600 Bd"),
        "{}",
        stderr(&out)
    );
}
