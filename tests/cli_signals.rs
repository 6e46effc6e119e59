//! A run ended from outside: SIGTERM (a service manager, `kill`) and
//! SIGHUP (the SSH session dropped) end `axterm run` as Ctrl-C does, with
//! the family's stop sequence, in every family. Each family's simulator is
//! served on a real pseudo-terminal (`axterm sim KIND --pty`); the run
//! starts an axis moving and says so, the signal comes then, and the axis
//! is read back at rest by a second run. Synchronised on output and on the
//! axis's state, never on time.

mod cli_support;
mod motion_support;
mod served_support;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

use axterm::families::FAMILIES;
use cli_support::{axterm_stdin, stderr};
use motion_support::motion_of;
use served_support::Served;

/// The run of `file` on `served` ended by `signal` once it says `moving`:
/// its exit code and standard error.
fn run_until_signal(
    served: &Served,
    family: &str,
    file: &str,
    signal: i32,
) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args([
            "run",
            "--port",
            &served.pty,
            "--protocol",
            family,
            "--yes",
            file,
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start axterm run");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    // The axis moves and the run sleeps.
    loop {
        let line = lines
            .next()
            .expect("the run ended before it said `moving`")
            .expect("text");
        if line == "moving" {
            break;
        }
    }
    let (status, err) = cli_support::signal_and_wait(&mut child, signal);
    (status.code(), err)
}

fn a_signal_ends_the_run_with_the_stop_sequence_in_every_family(signal: i32, name: &str) {
    let dir = tempfile::tempdir().expect("temp dir");
    for family in FAMILIES {
        let motion = motion_of(family);
        let kind = family.simulators.first().expect("a simulator").name;
        let served = Served::start(kind, &[]);
        let file = dir.path().join(format!("{}.txt", family.name));
        std::fs::write(
            &file,
            format!("{}\n:echo moving\n:sleep 10m\n", motion.start),
        )
        .expect("write");
        let file = file.to_string_lossy().into_owned();
        let (code, err) = run_until_signal(&served, family.name, &file, signal);
        assert_eq!(code, Some(1), "{}: {err}", family.name);
        assert!(
            err.contains(&format!("axterm run: {file}: stopped by {name}\n"))
                && err.contains("the run was cancelled: stopping every axis:"),
            "{}: {err}",
            family.name
        );
        let check = axterm_stdin(
            &[
                "run",
                "--port",
                &served.pty,
                "--protocol",
                family.name,
                "--no-stop-on-failure",
                "-",
            ],
            &format!("{}\n", motion.wait_at_rest()),
        );
        assert_eq!(
            check.status.code(),
            Some(0),
            "{}: the axis still moves after {name}: {}",
            family.name,
            stderr(&check)
        );
    }
}

#[test]
fn sigterm_ends_a_run_with_the_stop_sequence_in_every_family() {
    a_signal_ends_the_run_with_the_stop_sequence_in_every_family(libc::SIGTERM, "SIGTERM");
}

#[test]
fn sighup_ends_a_run_with_the_stop_sequence_in_every_family() {
    a_signal_ends_the_run_with_the_stop_sequence_in_every_family(libc::SIGHUP, "SIGHUP");
}

/// `axterm exec` ended by SIGTERM while a line runs long (MCCL `WA`, a
/// wait the controller holds the line for) stops the axis its first line
/// set moving, as a cancelled run does.
#[test]
fn sigterm_ends_exec_with_the_stop_sequence() {
    let served = Served::start("mccl", &[]);
    let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args([
            "exec",
            "--port",
            &served.pty,
            "--protocol",
            "mccl",
            "--yes",
            "1MN,1VM,1DI0,1GO",
            "WA100",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start axterm exec");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    // The first line's answer: the axis moves, the wait holds the line.
    let first = lines.next().expect("a line").expect("text");
    assert_eq!(first, "ok");
    let (status, err) = cli_support::signal_and_wait(&mut child, libc::SIGTERM);
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(
        err.contains("axterm exec: stopped by SIGTERM\n") && err.contains("  0AB → ok\n"),
        "{err}"
    );
    let check = axterm_stdin(
        &[
            "run",
            "--port",
            &served.pty,
            "--protocol",
            "mccl",
            "--no-stop-on-failure",
            "-",
        ],
        ":wait-until 1TV == 0 timeout 10s\n",
    );
    assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));
}
