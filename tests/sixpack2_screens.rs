//! The real binary in tmux on `--sim sixpack2` at 80×24: the six motors
//! in one row each; motor 1 set rotating from the command pane, the
//! emergency-stop key stops it (`ConstantRotation m 0` to all six, the
//! searches aborted, the rotations again: the protocol has no stop
//! command, digest D9), the screen saying the lines went out, none of
//! them acknowledged, and the motor standing; the terminal given back.

mod tmux_support;

use tmux_support::{Tmux, assert_terminal_restored, console_command};

/// The row of motor `m` (`│ m1   34941→— ○ v300/— const …`).
fn row(screen: &str, m: usize) -> Option<&str> {
    let name = format!("m{m}");
    screen.lines().find(|line| {
        line.split_whitespace()
            .take(2)
            .any(|w| w.trim_start_matches(['│', '▶']) == name)
    })
}

/// Motor `m`'s position and speed as its row shows them.
fn position_and_speed(screen: &str, m: usize) -> Option<(i64, i64)> {
    let row = row(screen, m)?;
    let words: Vec<&str> = row.split_whitespace().collect();
    let at = words.iter().position(|w| w.contains('→'))?;
    let position = words[at].split('→').next()?.parse().ok()?;
    let speed = words
        .iter()
        .skip(at)
        .find_map(|w| w.strip_prefix('v').filter(|rest| !rest.is_empty()))
        .or_else(|| {
            // `v 300/—`: the number after a lone `v`.
            let v = words.iter().skip(at).position(|w| *w == "v")?;
            words.get(at + v + 1).copied()
        })?;
    let speed = speed.split('/').next()?.parse().ok()?;
    Some((position, speed))
}

#[test]
fn the_real_binary_rotates_a_motor_and_the_stop_key_stops_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let command = console_command(dir.path(), "--sim sixpack2");
    let tmux = Tmux::start("sixpack2-stop", &command, dir.path());
    tmux.resize(80, 24);
    let first = tmux.until("the six motors polled", |s| {
        s.contains("poll 20 Hz") && (0..6).all(|m| position_and_speed(s, m) == Some((0, 0)))
    });
    assert!(first.contains("F12 STOP"), "{first}");

    tmux.type_text("ConstantRotation 1 300");
    tmux.keys(&["Enter"]);
    let rotating = tmux.until("motor 1 to rotate", |s| {
        row(s, 1).is_some_and(|r| r.contains("rotation●"))
            && position_and_speed(s, 1).is_some_and(|(p, v)| p > 0 && v == 300)
    });
    assert!(
        rotating.contains("sent 00 25 01 2C 01 00 00 00 00"),
        "the frame sent is shown: {rotating}"
    );
    assert!(
        (0..6)
            .filter(|&m| m != 1)
            .all(|m| position_and_speed(&rotating, m) == Some((0, 0))),
        "{rotating}"
    );

    tmux.keys(&["F12"]);
    let stopped = tmux.until("the stop sent and motor 1 standing", |s| {
        s.contains("STOP sent: all 18 stop lines went out, 18 of them never acknowledged")
            && position_and_speed(s, 1).is_some_and(|(_, v)| v == 0)
            && row(s, 1).is_some_and(|r| !r.contains("rotation●") && r.contains("stand"))
    });
    // The last stop frames, each with its bytes (the first ones scrolled
    // off the pane at 80×24).
    assert!(stopped.contains("sent ConstantRotation 5 0"), "{stopped}");
    assert!(
        stopped.contains("sent 00 25 05 00 00 00 00 00 00"),
        "{stopped}"
    );
    assert!(
        stopped.contains("STOP: 18 sent, 18 unacknowledged"),
        "the status bar: {stopped}"
    );

    tmux.keys(&["F10"]);
    let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
    assert!(!after.contains("F12 STOP"), "{after}");
    assert_terminal_restored(&after, 0);
}
