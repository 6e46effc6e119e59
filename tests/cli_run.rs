//! `axterm run` as a script sees it: stdout, stderr and the exit code.

mod cli_support;
mod served_support;

use cli_support::{axterm, axterm_stdin, stderr, stdout};
use served_support::Served;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};

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
fn a_dry_run_checks_the_connection_options_as_a_run_would() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = script(dir.path(), "PX\n");
    let out = axterm(&[
        "run",
        "--dry-run",
        "--sim",
        "cmd4cr",
        "--input",
        "DI9=1",
        &file,
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("--input DI9=1: there is no input `DI9`"),
        "{}",
        stderr(&out)
    );
    let out = axterm(&[
        "run",
        "--dry-run",
        "--sim",
        "cmd4cr",
        "--address",
        "100",
        &file,
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("--address 100"), "{}", stderr(&out));
    let out = axterm(&[
        "run",
        "--dry-run",
        "--sim",
        "cmd4cr",
        "--input",
        "DI4=1",
        &file,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("nothing sent (dry run)"),
        "{}",
        stderr(&out)
    );
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

const COMMISSIONING: &str = "\
# axis 0 set-up
SAP 4, 0, 1234   // maximum speed
GAP 4, 0
:expect GAP 4, 0 == 1234
:expect GAP 4, 0 == 0x4D2
:echo speed set
VERSION
";

#[test]
fn a_file_runs_line_by_line_with_one_result_per_console_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = script(dir.path(), COMMISSIONING);
    let out = axterm(&["run", "--sim", "tmcm1110", &file]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "ok\n1234\nspeed set\n1110V112\n");
    assert_eq!(stderr(&out), "");
}

#[test]
fn standard_input_works_the_same() {
    let out = axterm_stdin(&["run", "--sim", "tmcm1110", "-"], COMMISSIONING);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "ok\n1234\nspeed set\n1110V112\n");
}

#[test]
fn a_failed_expect_stops_the_run_with_file_and_line() {
    let out = axterm_stdin(
        &["run", "--sim", "tmcm1110", "-"],
        "SAP 4, 0, 100\n:expect GAP 4, 0 == 200\n:echo not reached\n",
    );
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(stdout(&out), "ok\n");
    let err = stderr(&out);
    assert_eq!(
        err.lines().next(),
        Some("<stdin>:2: expected GAP 4, 0 == 200, got 100"),
        "{err}"
    );
    assert!(
        err.contains("axterm run: <stdin>: the run failed: stopping every axis:"),
        "{err}"
    );
}

#[test]
fn keep_going_runs_the_rest_and_still_exits_1() {
    let out = axterm_stdin(
        &["run", "--sim", "tmcm1110", "--keep-going", "-"],
        "SAP 4, 0, 100\n:expect GAP 4, 0 == 200\n5 6 0 300\n:echo reached\n",
    );
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(stdout(&out), "ok\nreached\n");
    let err = stderr(&out);
    assert!(
        err.contains("<stdin>:2: expected GAP 4, 0 == 200, got 100"),
        "{err}"
    );
    assert!(
        err.contains("<stdin>:3: module 1 rejected SAP 6, 0, 300: invalid value (status 4)"),
        "{err}"
    );
}

#[test]
fn wait_until_reads_until_the_move_is_done() {
    let out = axterm_stdin(
        &["run", "--sim", "tmcm1110", "-"],
        "MVP ABS, 0, 200\n:wait-until GAP 8, 0 == 1 timeout 1m\n:expect GAP 1, 0 == 200\n",
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "ok\n");
}

#[test]
fn wait_until_gives_up_at_its_timeout() {
    // The position is 0 and nothing moves: it never becomes 5.
    let out = axterm_stdin(
        &["run", "--sim", "tmcm1110", "-"],
        ":wait-until GAP 1, 0 == 5 timeout 50ms\n",
    );
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert_eq!(
        err.lines().next(),
        Some("<stdin>:1: GAP 1, 0 did not become 5 within 50 ms (last 0)"),
        "{err}"
    );
}

#[test]
fn json_output_has_an_object_per_console_line_and_echo() {
    let out = axterm_stdin(
        &["run", "--sim", "tmcm1110", "--format", "json", "-"],
        "GAP 4, 0\n:echo hello\n",
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let objects: Vec<serde_json::Value> = stdout(&out)
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect();
    assert_eq!(objects.len(), 2);
    assert_eq!(objects[0]["command"], "GAP 4, 0");
    assert_eq!(objects[0]["ok"], true);
    assert_eq!(objects[1]["echo"], "hello");
}

/// The batch of issue 11: a long move, then a wait for its end that gives
/// up long before it.
const FAILS_MID_MOVE: &str =
    "SAP 4, 0, 1500\nMVP ABS, 0, 512000000\n:wait-until GAP 8, 0 == 1 timeout 100ms\n";

/// The TMCL stop sequence as `run` reports it.
const STOPPED: [&str; 3] = ["  MST 0 → ok", "  STOPAPP → ok", "  MST 0 → ok"];

/// The report's stop lines: those after its first line, indented.
fn stop_lines(err: &str, heading: &str) -> Vec<String> {
    err.lines()
        .skip_while(|l| !l.ends_with(heading))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .map(str::to_string)
        .collect()
}

/// A follow-up run on the served simulator: waits (at most 10 s) for the
/// speed to become `speed`, then runs `expect`. Its exit code and standard
/// error.
fn speed_becomes(pty: &str, speed: i64, expect: &str) -> (Option<i32>, String) {
    let out = axterm_stdin(
        &["run", "--port", pty, "--no-stop-on-failure", "-"],
        &format!(":wait-until GAP 3, 0 == {speed} timeout 10s\n{expect}"),
    );
    (out.status.code(), stderr(&out))
}

#[test]
fn a_failed_wait_until_ends_the_run_with_the_stop_sequence_and_the_axis_at_speed_0() {
    let served = Served::start("tmcm1110", &[]);
    let dir = tempfile::tempdir().expect("temp dir");
    let file = script(dir.path(), FAILS_MID_MOVE);
    let out = axterm(&["run", "--port", &served.pty, &file]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(stdout(&out), "ok\nok\n");
    assert!(
        err.starts_with(&format!(
            "{file}:3: GAP 8, 0 did not become 1 within 100 ms (last 0)\n"
        )),
        "{err}"
    );
    assert_eq!(
        stop_lines(&err, "the run failed: stopping every axis:"),
        STOPPED,
        "{err}"
    );
    assert!(
        err.ends_with(&format!(
            "axterm run: {file}: stop confirmed: every stop line answered ok\n"
        )),
        "{err}"
    );
    // The simulator says: the motor comes to rest short of its target.
    let (code, err) = speed_becomes(&served.pty, 0, ":expect GAP 8, 0 == 0\n");
    assert_eq!(code, Some(0), "the motor still runs: {err}");
    let out = axterm(&["exec", "--port", &served.pty, "GAP 3, 0", "GAP 1, 0"]);
    let values: Vec<i64> = stdout(&out)
        .lines()
        .map(|l| l.parse().expect("a number"))
        .collect();
    assert_eq!(values[0], 0, "speed");
    assert!(values[1] > 0 && values[1] < 512_000_000, "{values:?}");
}

#[test]
fn no_stop_on_failure_leaves_the_axis_running() {
    let served = Served::start("tmcm1110", &[]);
    let out = axterm_stdin(
        &["run", "--port", &served.pty, "--no-stop-on-failure", "-"],
        FAILS_MID_MOVE,
    );
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(
            "axterm run: <stdin>: the run failed: the axes were left as they are (--no-stop-on-failure)"
        ),
        "{err}"
    );
    assert!(!err.contains("MST"), "{err}");
    let (code, err) = speed_becomes(&served.pty, 1500, "");
    assert_eq!(code, Some(0), "the motor should run on: {err}");
    // Stop it for good measure before the simulator goes.
    let out = axterm(&["exec", "--port", &served.pty, "MST 0"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

#[test]
fn ctrl_c_cancels_the_run_and_sends_the_stop_sequence() {
    let served = Served::start("tmcm1110", &[]);
    let dir = tempfile::tempdir().expect("temp dir");
    let file = script(
        dir.path(),
        "SAP 4, 0, 1500\nMVP ABS, 0, 512000000\n:echo moving\n:wait-until GAP 8, 0 == 1 timeout 10m\n",
    );
    let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["run", "--port", &served.pty, &file])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start axterm run");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    // The move is under way and the wait has begun.
    loop {
        let line = lines.next().expect("a line").expect("text");
        if line == "moving" {
            break;
        }
    }
    let (status, err) = cli_support::signal_and_wait(&mut child, libc::SIGINT);
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(
        err.contains(&format!("axterm run: {file}: stopped by Ctrl-C\n")),
        "{err}"
    );
    assert_eq!(
        stop_lines(&err, "the run was cancelled: stopping every axis:"),
        STOPPED,
        "{err}"
    );
    let (code, err) = speed_becomes(&served.pty, 0, ":expect GAP 8, 0 == 0\n");
    assert_eq!(code, Some(0), "the motor still runs: {err}");
}

#[test]
fn json_output_gives_each_stop_line_an_object() {
    let out = axterm_stdin(
        &["run", "--sim", "tmcm1110", "--format", "json", "-"],
        FAILS_MID_MOVE,
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let objects: Vec<serde_json::Value> = stdout(&out)
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect();
    let stops: Vec<&serde_json::Value> = objects.iter().filter(|o| o["stop"] == true).collect();
    let commands: Vec<&str> = stops
        .iter()
        .map(|o| o["command"].as_str().expect("command"))
        .collect();
    assert_eq!(commands, ["MST 0", "STOPAPP", "MST 0"]);
    assert!(stops.iter().all(|o| o["ok"] == true));
    assert_eq!(stops[0]["request"], "01 03 00 00 00 00 00 00 04");
}
