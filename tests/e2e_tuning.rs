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

/// On the TMCM-1110: the CoolStep view (t), its watch (r, y) plots the
/// current and the load with the key under the plot and the energy
/// saved, and Esc stops the motor.
#[test]
fn a_coolstep_watch_from_the_tuning_pane_plots_and_esc_stops_the_motor() {
    let dir = tempfile::tempdir().expect("temp dir");
    let command = console_command(dir.path(), "--sim tmcm1110");
    let tmux = Tmux::start("coolstep", &command, dir.path());
    tmux.until("the console", |s| s.contains("poll 20 Hz"));
    tmux.keys(&["M-9"]);
    tmux.until("the sweep", |s| s.contains("from 200"));
    tmux.keys(&["t"]);
    tmux.until("the form read", |s| {
        s.contains("AP183 ") && !s.contains("AP183 -")
    });
    tmux.keys(&["r"]);
    tmux.until("the question", |s| s.contains("it moves the axis: y/n"));
    tmux.keys(&["y"]);
    let watching = tmux.until("the live plot", |s| {
        s.contains("CoolStep saved") && s.contains("• current")
    });
    assert!(watching.contains("load reading, % of 1023"), "{watching}");
    tmux.keys(&["Escape"]);
    tmux.until("the stop", |s| {
        s.contains("run ended, stopping (stopped by key): MST 0")
    });
    tmux.until("the motor standing", |s| s.contains("standing"));
    tmux.keys(&["F10"]);
    let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
    assert_terminal_restored(&after, 0);
}
