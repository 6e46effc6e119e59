//! The bring-up pane in the real console (tmux): a technician holds the
//! jog key until the carriage of the simulated stage reaches its right
//! end switch, sees the switch's lamp light, lets go, and the axis stands.
//! Synchronised on the screen; the keys come as a held key's repeats do.

mod tmux_support;

use tmux_support::{Tmux, assert_terminal_restored, console_command};

/// The speed the bring-up pane shows.
fn speed(screen: &str) -> Option<i64> {
    let line = screen.lines().find(|l| l.contains("  speed "))?;
    let after = line.split("  speed ").nth(1)?;
    after.split_whitespace().next()?.parse().ok()
}

#[test]
fn jogging_into_the_right_end_switch_lights_its_lamp_and_letting_go_stops() {
    let dir = tempfile::tempdir().expect("temp dir");
    let command = console_command(dir.path(), "--sim tmcm1110");
    let tmux = Tmux::start("bringup", &command, dir.path());
    tmux.until("the console", |s| s.contains("poll 20 Hz"));
    tmux.keys(&["M-8"]);
    tmux.until("the bring-up pane", |s| s.contains("standing by"));
    // The fastest jog speed of the list.
    tmux.keys(&["f", "f", "f", "f", "f"]);
    tmux.until("the fastest speed", |s| {
        s.contains("speed 2047 velocity units")
    });
    // The TMCM-1110 simulator's stage has its right end switch at
    // +200000 µsteps: hold Right until its lamp lights.
    let lit = tmux.until_found("the right end switch's lamp", || {
        tmux.keys(&["Right", "Right"]);
        let screen = tmux.screen();
        screen.contains("right limit●").then_some(screen)
    });
    assert!(lit.contains("JOGGING") || lit.contains("jog"), "{lit}");
    // Let go: the deadman stops the jog.
    tmux.until("the jog to stop and the axis to stand", |s| {
        s.contains("jog stopped") && speed(s) == Some(0)
    });
    tmux.keys(&["F10"]);
    let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
    assert_terminal_restored(&after, 0);
}
