//! A session recorded in the real console (tmux) on a served simulator,
//! with an emergency stop in it, replayed by `axterm run` on another: the
//! stop is in the file as the stop lines it sent, and the replay ends with
//! no axis moving (exit 0). Synchronised on the screen and on the axis's
//! state, never on time.

mod cli_support;
mod served_support;
mod tmux_support;

use cli_support::{axterm_stdin, stderr};
use served_support::Served;
use tmux_support::{Tmux, assert_terminal_restored, console_command};

/// The speed the axes pane shows for the first axis.
fn speed(screen: &str) -> Option<i64> {
    let line = screen.lines().find(|l| l.contains(" spd "))?;
    let after = line.split(" spd ").nth(1)?;
    after.split_whitespace().next()?.parse().ok()
}

#[test]
fn a_recorded_emergency_stop_replays_as_its_stop_lines_and_leaves_no_axis_moving() {
    let served = Served::start("tmcm1110", &[]);
    let dir = tempfile::tempdir().expect("temp dir");
    let command = console_command(
        dir.path(),
        &format!("--port {} --protocol tmcl", served.pty),
    );
    let tmux = Tmux::start("record-stop", &command, dir.path());
    tmux.until("the console", |s| s.contains("poll 20 Hz"));
    tmux.type_text(":record rec.txt");
    tmux.keys(&["Enter"]);
    tmux.until("the recording to start", |s| {
        s.contains("recording the session to rec.txt")
    });
    tmux.type_text("ROR 0, 500");
    tmux.keys(&["Enter"]);
    tmux.until("the axis to turn", |s| speed(s).is_some_and(|v| v > 0));
    tmux.keys(&["F12"]);
    tmux.until("the stop to be confirmed and the axis to stand", |s| {
        s.contains("STOP confirmed: every stop line answered ok") && speed(s) == Some(0)
    });
    tmux.type_text(":record off");
    tmux.keys(&["Enter"]);
    tmux.until("the recording to end", |s| {
        s.contains("session recording ended")
    });
    tmux.keys(&["F10"]);
    let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
    assert_terminal_restored(&after, 0);

    let file = dir.path().join("rec.txt");
    let recorded = std::fs::read_to_string(&file).expect("the recording");
    assert!(
        recorded.contains(
            "ROR 0, 500\n# emergency stop here: the stop lines it sent\nMST 0\nSTOPAPP\nMST 0\n"
        ),
        "{recorded}"
    );

    let fresh = Served::start("tmcm1110", &[]);
    let file = file.to_string_lossy().into_owned();
    let replay = cli_support::axterm(&[
        "run",
        "--port",
        &fresh.pty,
        "--protocol",
        "tmcl",
        "--yes",
        &file,
    ]);
    let err = stderr(&replay);
    assert_eq!(replay.status.code(), Some(0), "{err}");
    assert!(!err.contains("still moves"), "{err}");
    let check = axterm_stdin(
        &["run", "--port", &fresh.pty, "--no-stop-on-failure", "-"],
        ":expect GAP 3, 0 == 0\n",
    );
    assert_eq!(
        check.status.code(),
        Some(0),
        "the replay left the axis turning: {}",
        stderr(&check)
    );
}
