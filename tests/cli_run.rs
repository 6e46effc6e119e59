//! `axterm run` as a script sees it: stdout, stderr and the exit code.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

fn axterm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(args)
        .output()
        .expect("run axterm")
}

fn axterm_stdin(args: &[&str], input: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run axterm");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(input.as_bytes())
        .expect("write stdin");
    child.wait_with_output().expect("wait for axterm")
}

fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn script(dir: &Path, text: &str) -> String {
    let path = dir.join("commissioning.txt");
    std::fs::write(&path, text).expect("write script");
    path.to_string_lossy().into_owned()
}

#[test]
fn a_bad_line_anywhere_sends_nothing_and_every_bad_line_is_listed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = script(
        dir.path(),
        "# set up\nSAP 4, 0, 1000\n:sleep soon\nGAP 4, 0\nSAP 6, 0, 100000\n:expect GAP 4, 0\n",
    );
    // A port that cannot exist: opening it would have exited 3.
    let out = axterm(&["run", "--port", "/nonexistent/tty", &file]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_eq!(stdout(&out), "");
    let err = stderr(&out);
    let lines: Vec<&str> = err.lines().collect();
    assert!(lines[0].starts_with(&format!("{file}:3: ")), "{err}");
    assert!(lines[1].starts_with(&format!("{file}:5: ")), "{err}");
    assert!(lines[1].contains("0..255"), "{err}");
    assert!(lines[2].starts_with(&format!("{file}:6: ")), "{err}");
    assert!(lines[3].contains("nothing was sent"), "{err}");
}

#[test]
fn a_dry_run_checks_the_file_and_never_connects() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = script(dir.path(), "SAP 4, 0, 1000\n:expect GAP 4, 0 == 1000\n");
    let out = axterm(&["run", "--dry-run", "--port", "/nonexistent/tty", &file]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "");
    assert!(
        stderr(&out).contains("2 console lines valid"),
        "{}",
        stderr(&out)
    );
    // No connection at all is fine for a dry run.
    let out = axterm(&["run", "--dry-run", &file]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

#[test]
fn a_dry_run_still_refuses_a_bad_file() {
    let out = axterm_stdin(&["run", "--dry-run", "-"], "GAP 1, 0\nMVP ABS, 1, 5\n");
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).starts_with("<stdin>:2: "), "{}", stderr(&out));
}

#[test]
fn a_missing_file_is_a_usage_error() {
    let out = axterm(&["run", "--sim", "tmcm1110", "/nonexistent/file.txt"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("cannot read /nonexistent/file.txt"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_connection_that_cannot_be_opened_exits_3() {
    let out = axterm_stdin(&["run", "--port", "/nonexistent/tty", "-"], "GAP 1, 0\n");
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("cannot open /nonexistent/tty"),
        "{}",
        stderr(&out)
    );
}
