//! The real binary in tmux on two links, `--sim tmcm1110 --sim cmd4cr`:
//! motion started on both (the TMCM-1110's motor from module 1, the
//! CMD-4CR's X after `:module 2`), the emergency-stop key, both standing
//! and every stop line confirmed, the terminal given back.

mod tmux_support;

use tmux_support::{Tmux, assert_terminal_restored, console_command};

/// The words of the axes pane's row whose label is `label`.
fn row<'a>(screen: &'a str, label: &str) -> Option<Vec<&'a str>> {
    screen.lines().find_map(|line| {
        let inside = line.trim_start_matches('│').trim_start_matches([' ', '▶']);
        let rest = inside.strip_prefix(label)?.strip_prefix(' ')?;
        Some(rest.split_whitespace().collect())
    })
}

/// The speed shown in `label`'s row (`v500/1000`).
fn speed(screen: &str, label: &str) -> Option<i64> {
    row(screen, label)?
        .iter()
        .find_map(|w| w.strip_prefix('v')?.split('/').next()?.trim().parse().ok())
}

#[test]
fn the_stop_key_stops_the_axes_of_both_links() {
    let dir = tempfile::tempdir().expect("temp dir");
    let command = console_command(dir.path(), "--sim tmcm1110 --sim cmd4cr");
    let tmux = Tmux::start("links-stop", &command, dir.path());
    tmux.until("both links listed and polled", |s| {
        s.contains("link 1 sim tmcm1110")
            && s.contains("link 2 sim cmd4cr")
            && speed(s, "motor 0") == Some(0)
            && speed(s, "X") == Some(0)
    });
    tmux.type_text("ROR 0, 500");
    tmux.keys(&["Enter"]);
    tmux.until("the motor to turn", |s| {
        speed(s, "motor 0").is_some_and(|v| v > 0)
    });
    tmux.type_text(":module 2");
    tmux.keys(&["Enter"]);
    tmux.type_text("JX+");
    tmux.keys(&["Enter"]);
    let moving = tmux.until("X to move too", |s| {
        speed(s, "X").is_some_and(|v| v > 0) && speed(s, "motor 0").is_some_and(|v| v > 0)
    });
    assert!(moving.contains("sent @01JX+\\r  got OK"), "{moving}");

    tmux.keys(&["F12"]);
    // TMCL: MST 0, STOPAPP, MST 0; CMD-4CR: ESTOP, SACTRL0..3=0, ESTOP.
    let stopped = tmux.until("both standing, every stop line answered", |s| {
        s.contains("STOP: 9 sent, all ok")
            && speed(s, "motor 0") == Some(0)
            && speed(s, "X") == Some(0)
    });
    assert!(stopped.contains("ERR EMG error"), "{stopped}");

    tmux.keys(&["F10"]);
    let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
    assert_terminal_restored(&after, 0);
}
