//! The tuning pane in the real console (tmux): a technician opens
//! `axterm --sim mccl`, goes to the tuning pane (Alt-9), runs a step,
//! answers y, and sees the figures. Synchronised on the screen.

mod tmux_support;

use tmux_support::{Tmux, assert_terminal_restored, console_command};

#[test]
fn a_step_run_from_the_tuning_pane_shows_its_figures() {
    let dir = tempfile::tempdir().expect("temp dir");
    let command = console_command(dir.path(), "--sim mccl");
    let tmux = Tmux::start("tuning", &command, dir.path());
    tmux.until("the console", |s| s.contains("poll 20 Hz"));
    tmux.keys(&["M-9"]);
    tmux.until("the gains read", |s| s.contains("SG 0.04"));
    tmux.keys(&["r"]);
    tmux.until("the question", |s| s.contains("it moves the axis: y/n"));
    tmux.keys(&["y"]);
    let done = tmux.until("the figures", |s| s.contains("overshoot"));
    assert!(done.contains("rise time"), "{done}");
    tmux.keys(&["F10"]);
    let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
    assert_terminal_restored(&after, 0);
}
