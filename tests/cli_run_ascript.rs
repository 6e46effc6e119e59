//! `axterm run-ascript` as a script sees it: stdout, stderr and the exit
//! code, on the in-process CMD-4CR simulator (short programs: it runs on
//! the wall clock here, and every wait is a condition, never a time).

mod cli_support;
mod served_support;

use cli_support::{axterm, stderr, stdout};
use std::path::Path;
use std::process::Command;

fn program(dir: &Path, text: &str) -> String {
    let path = dir.join("program.asc");
    std::fs::write(&path, text).expect("write the program");
    path.to_string_lossy().into_owned()
}

#[test]
fn a_program_runs_from_the_host_statement_by_statement() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = program(
        dir.path(),
        "PRG 0\n    HSPD=50000\n    EO=1\n    X500\n    WAITX\n    V1=PX\n    IF V1=500\n        DO1=1\n    ENDIF\n    ECLEARX\nEND\n",
    );
    let out = axterm(&["run-ascript", "--sim", "cmd4cr", &file]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let lines: Vec<String> = stdout(&out).lines().map(str::to_string).collect();
    assert_eq!(
        lines,
        [
            "PRG 0 started from the host",
            "PRG 0 line 2: HSPD=50000 → ok",
            "PRG 0 line 3: EO=1 → ok",
            "PRG 0 line 4: X500 → ok",
            "PRG 0 line 8: DO1=1 → ok",
            "PRG 0 line 10: ECLEARX as CLRX → ok",
            "PRG 0 reached END (line 11)",
        ]
    );
    let err = stderr(&out);
    assert!(
        err.contains(&format!(
            "running {file} from the host on sim cmd4cr: PRG 0"
        )),
        "{err}"
    );
    assert!(err.contains("every program ran to its END"), "{err}");
}

#[test]
fn a_bad_file_sends_nothing_and_every_problem_names_file_and_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = program(
        dir.path(),
        "PRG 0\n    V200=1\n    BUFON\n    X100\n    DELAY=V1+200\nEND\n",
    );
    // A port that cannot exist: opening it would have exited 3.
    let out = axterm(&["run-ascript", "--port", "/nonexistent/tty", &file]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_eq!(stdout(&out), "");
    let err = stderr(&out);
    let lines: Vec<&str> = err.lines().collect();
    assert!(
        lines[0].starts_with(&format!("{file}:2: Var Range Error")),
        "{err}"
    );
    assert!(
        lines[1].starts_with(&format!("{file}:5: Token Error")),
        "{err}"
    );
    assert!(err.contains("nothing was sent"), "{err}");
    // Compiles, but a move in buffer mode that I[X]:[Y]:[Z] cannot carry.
    let file = program(dir.path(), "PRG 0\n    BUFON\n    X100\nEND\n");
    let out = axterm(&["run-ascript", "--port", "/nonexistent/tty", &file]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).starts_with(&format!("{file}:3: `X100` cannot run from the host")),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_runtime_error_without_sub_31_fails_the_run_with_exit_1() {
    let dir = tempfile::tempdir().expect("temp dir");
    // HSPD from a variable that holds 0: the controller's range refuses it.
    let file = program(dir.path(), "PRG 0\n    HSPD=V5\n    DO1=1\nEND\n");
    let out = axterm(&["run-ascript", "--sim", "cmd4cr", &file]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.contains("PRG 0 line 2: `HSPD=V5` was refused"),
        "{text}"
    );
    assert!(!text.contains("DO1=1"), "{text}");
    let err = stderr(&out);
    assert!(err.contains("PRG 0 line 2:"), "{err}");
    // A failed run ends with the emergency stop.
    assert!(
        err.contains(&format!(
            "{file}: the run failed: stopping every axis:\n  ESTOP → ok\n"
        )),
        "{err}"
    );
    assert!(
        err.ends_with("stop confirmed: every stop line answered ok\n"),
        "{err}"
    );
    let out = axterm(&[
        "run-ascript",
        "--sim",
        "cmd4cr",
        "--no-stop-on-failure",
        &file,
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("the run failed: the axes were left as they are (--no-stop-on-failure)"),
        "{err}"
    );
    assert!(!err.contains("ESTOP"), "{err}");
}

#[test]
fn a_failed_program_stops_the_axis_it_left_moving() {
    // The joystick-free way to leave an axis running: a jog, then a
    // division by zero, a runtime error with no SUB 31 to handle it.
    let served = served_support::Served::start("cmd4cr", &[]);
    let dir = tempfile::tempdir().expect("temp dir");
    let file = program(
        dir.path(),
        "PRG 0\n    EO=1\n    HSPD=1000\n    JOGX+\n    V1=0\n    V2=5/V1\nEND\n",
    );
    let out = axterm(&["run-ascript", "--port", &served.pty, &file]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("the run failed: stopping every axis:"),
        "{err}"
    );
    assert!(err.contains("stop confirmed"), "{err}");
    // The controller says: the axis stands (MSTX bits 0-2 clear).
    let out = axterm(&[
        "exec",
        "--protocol",
        "cmd4cr",
        "--port",
        &served.pty,
        "MSTX",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let mst: i64 = stdout(&out).trim().parse().expect("a number");
    assert_eq!(mst & 0b111, 0, "MSTX {mst}: still moving");
}

#[test]
fn usage_and_connection_errors_have_their_exit_codes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = program(dir.path(), "PRG 0\n    DO1=1\nEND\nPRG 2\nEND\n");
    // A dry run checks, needs no connection and sends nothing.
    let out = axterm(&["run-ascript", "--dry-run", &file]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("PRG 0 and PRG 2 would start"),
        "{}",
        stderr(&out)
    );
    let out = axterm(&["run-ascript", "--dry-run", "--prg", "2", &file]);
    assert!(
        stderr(&out).contains("checks, PRG 2 would start"),
        "{}",
        stderr(&out)
    );
    // A dry run given a connection checks its options, and opens nothing.
    let out = axterm(&[
        "run-ascript",
        "--dry-run",
        "--sim",
        "cmd4cr",
        "--input",
        "ALMQ=1",
        &file,
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("--input ALMQ=1: there is no input `ALMQ`"),
        "{}",
        stderr(&out)
    );
    let out = axterm(&[
        "run-ascript",
        "--dry-run",
        "--port",
        "/nonexistent/tty",
        &file,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let out = axterm(&["run-ascript", "--dry-run", "--prg", "1", &file]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("there is no PRG 1"),
        "{}",
        stderr(&out)
    );
    // Another family's connection.
    let out = axterm(&["run-ascript", "--sim", "tmcm1110", &file]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("CMD-4CR's language"),
        "{}",
        stderr(&out)
    );
    // It speaks cmd4cr unless told otherwise: the port is what fails.
    let out = axterm(&["run-ascript", "--port", "/nonexistent/tty", &file]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    let out = axterm(&["run-ascript", "--sim", "cmd4cr", "no-such-file.asc"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn ctrl_c_ends_the_run_and_sends_the_emergency_stop() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let dir = tempfile::tempdir().expect("temp dir");
    let file = program(
        dir.path(),
        "PRG 0\n    EO=1\n    WHILE 1=1\n        X1000\n        WAITX\n        X0\n        WAITX\n    ENDWHILE\nEND\n",
    );
    let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["run-ascript", "--sim", "cmd4cr", &file])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start axterm run-ascript");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    // Wait until the loop has sent a move: the run is under way.
    loop {
        let line = lines.next().expect("a line").expect("text");
        if line.contains("X1000 → ok") {
            break;
        }
    }
    let (status, err) = cli_support::signal_and_wait(&mut child, libc::SIGINT);
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(
        err.contains(&format!("{file}: stopped by Ctrl-C\n")),
        "{err}"
    );
    let stops: Vec<&str> = err
        .lines()
        .skip_while(|l| !l.ends_with("the run was cancelled: stopping every axis:"))
        .skip(1)
        .collect();
    assert_eq!(
        stops,
        [
            "  ESTOP → ok",
            "  SACTRL0=0 → ok",
            "  SACTRL1=0 → ok",
            "  SACTRL2=0 → ok",
            "  SACTRL3=0 → ok",
            "  ESTOP → ok",
            &format!("axterm run-ascript: {file}: stop confirmed: every stop line answered ok"),
        ],
        "{err}"
    );
}
