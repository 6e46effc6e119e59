//! The real console in a real pseudo-terminal (tmux) on a simulator served
//! over another pseudo-terminal (`axterm sim tmcm1110 --pty`): an axis set
//! turning, then SIGTERM or SIGHUP from outside. The console stops every
//! axis before it gives the terminal back, says so once it has, and the
//! axis is read back at rest by `axterm run` on the same served simulator.
//! Synchronised on the screen and on the axis's state, never on time.

mod cli_support;
mod served_support;
mod tmux_support;

use cli_support::{axterm_stdin, stderr};
use served_support::Served;
use tmux_support::{Tmux, assert_terminal_restored};

/// The speed the axes pane shows for the first axis.
fn speed(screen: &str) -> Option<i64> {
    let line = screen.lines().find(|l| l.contains(" spd "))?;
    let after = line.split(" spd ").nth(1)?;
    after.split_whitespace().next()?.parse().ok()
}

#[test]
fn a_console_ended_by_a_signal_stops_the_axis_and_gives_the_terminal_back() {
    for (name, signal) in [("sigterm", libc::SIGTERM), ("sighup", libc::SIGHUP)] {
        let served = Served::start("tmcm1110", &[]);
        let dir = tempfile::tempdir().expect("temp dir");
        let binary = env!("CARGO_BIN_EXE_axterm");
        let command = format!(
            "AXTERM_DATA_DIR={data} {binary} --port {pty} --protocol tmcl & pid=$!; echo $pid > pid; wait $pid; echo AXTERM-EXIT-$?; stty -a; echo MARKER-END; sleep 600",
            data = dir.path().display(),
            pty = served.pty,
        );
        let tmux = Tmux::start(&format!("signal-{name}"), &command, dir.path());
        tmux.until("the console", |s| s.contains("poll 20 Hz"));
        tmux.type_text("ROR 0, 500");
        tmux.keys(&["Enter"]);
        tmux.until("the axis to turn", |s| speed(s).is_some_and(|v| v > 0));
        let pid: i32 = std::fs::read_to_string(dir.path().join("pid"))
            .expect("pid file")
            .trim()
            .parse()
            .expect("a pid");
        // SAFETY: kill(2) with a pid we started and a valid signal number.
        let sent = unsafe { libc::kill(pid, signal) };
        assert_eq!(sent, 0, "{name} could not be sent");
        let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
        assert_terminal_restored(&after, 0);
        assert!(
            after.contains("the console was ended from outside: stopping every axis")
                && after.contains("stop confirmed: every stop line answered ok"),
            "{name}: {after}"
        );
        let check = axterm_stdin(
            &["run", "--port", &served.pty, "--no-stop-on-failure", "-"],
            ":wait-until GAP 3, 0 == 0 timeout 10s\n",
        );
        assert_eq!(
            check.status.code(),
            Some(0),
            "{name}: the axis still turns: {}",
            stderr(&check)
        );
    }
}
