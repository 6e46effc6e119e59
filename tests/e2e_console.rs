//! The real binary in a real pseudo-terminal (tmux): `axterm --sim
//! tmcm1110`, a move typed in the command pane, the position changing on
//! screen, the emergency stop, quitting, and the terminal given back (on
//! quit, on SIGTERM/SIGHUP, and after a panic inside the console).
//!
//! Synchronisation is by polling the screen (`tmux capture-pane`) until
//! the expected text appears, with one overall deadline so that a broken
//! build fails instead of hanging; nothing here measures how fast
//! anything is.

mod tmux_support;

use tmux_support::{Tmux, assert_terminal_restored, console_command};

/// The position the axes pane shows for the first axis.
fn position(screen: &str) -> Option<i64> {
    let line = screen.lines().find(|l| l.contains("▶motor 0"))?;
    let after = line.split("pos").nth(1)?;
    after.split_whitespace().next()?.parse().ok()
}

fn speed(screen: &str) -> Option<i64> {
    let line = screen.lines().find(|l| l.contains(" spd "))?;
    let after = line.split(" spd ").nth(1)?;
    after.split_whitespace().next()?.parse().ok()
}

#[test]
fn a_move_an_emergency_stop_and_the_terminal_given_back() {
    let dir = tempfile::tempdir().expect("temp dir");
    // After axterm: its exit code, the terminal's settings, an end marker;
    // then the shell waits so the screen can be read.
    let command = console_command(dir.path(), "--sim tmcm1110");
    let tmux = Tmux::start("move", &command, dir.path());
    let first = tmux.until("the console", |s| {
        s.contains("poll 20 Hz") && position(s) == Some(0)
    });
    assert!(first.contains("F12 STOP"), "{first}");

    tmux.type_text("MVP ABS, 0, 51200");
    tmux.keys(&["Enter"]);
    tmux.until("the axis to move toward its new target", |s| {
        s.contains("ok  (status 100: successfully executed, no error)")
            && position(s).is_some_and(|p| p > 0)
            && s.contains("tgt       51200")
    });

    tmux.keys(&["F12"]);
    let stopped = tmux.until("the stop to be confirmed and the axis to stand", |s| {
        s.contains("STOP confirmed: every stop line answered ok")
            && speed(s) == Some(0)
            && s.contains("standing")
    });
    assert!(
        stopped.contains("sent MST 0") && stopped.contains("sent STOPAPP"),
        "{stopped}"
    );
    assert!(stopped.contains("F12 EMERGENCY STOP"), "{stopped}");

    // A smaller terminal: the console follows, and still shows the stop key.
    tmux.resize(80, 24);
    tmux.until("the console at 80x24", |s| {
        let lines: Vec<&str> = s.lines().collect();
        lines.len() == 24
            && lines
                .first()
                .is_some_and(|l| l.chars().count() == 80 && l.contains("Axes —"))
            && lines.last().is_some_and(|l| l.starts_with(" F12 STOP "))
    });

    tmux.keys(&["F10"]);
    let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
    // The alternate screen was left: none of the console is on screen.
    assert!(
        !after.contains("F12 STOP") && !after.contains("Axes —"),
        "{after}"
    );
    assert_terminal_restored(&after, 0);
}

/// SIGTERM (a service manager) and SIGHUP (the SSH session dropped).
#[test]
fn a_termination_signal_gives_the_terminal_back_too() {
    for (name, signal) in [("sigterm", libc::SIGTERM), ("sighup", libc::SIGHUP)] {
        let dir = tempfile::tempdir().expect("temp dir");
        let binary = env!("CARGO_BIN_EXE_axterm");
        let command = format!(
            "AXTERM_DATA_DIR={data} {binary} --sim tmcm1110 & pid=$!; echo $pid > pid; wait $pid; echo AXTERM-EXIT-$?; stty -a; echo MARKER-END; sleep 600",
            data = dir.path().display(),
        );
        let tmux = Tmux::start(name, &command, dir.path());
        tmux.until("the console", |s| s.contains("poll 20 Hz"));
        let pid: i32 = std::fs::read_to_string(dir.path().join("pid"))
            .expect("pid file")
            .trim()
            .parse()
            .expect("a pid");
        // SAFETY: kill(2) with a pid we started and a valid signal number.
        let sent = unsafe { libc::kill(pid, signal) };
        assert_eq!(sent, 0, "{name} could not be sent");
        let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
        assert!(after.contains("AXTERM-EXIT-0"), "{name}: {after}");
        assert!(!after.contains("F12 STOP"), "{name}: {after}");
        let words: Vec<&str> = after.split_whitespace().collect();
        assert!(
            words.contains(&"icanon") && words.contains(&"echo"),
            "{name}: {after}"
        );
    }
}

/// A bug inside the console: the real binary panics in its loop (the
/// test-only `AXTERM_TEST_PANIC` makes `:connect` panic) with the terminal
/// in raw mode on the alternate screen. The panic hook gives the terminal
/// back before the message is printed, so the message is on the normal
/// screen for the technician to read, and the shell works again.
#[test]
fn a_panic_inside_the_console_gives_the_terminal_back_and_its_message_is_readable() {
    let dir = tempfile::tempdir().expect("temp dir");
    let binary = env!("CARGO_BIN_EXE_axterm");
    let command = format!(
        "echo BEFORE-AXTERM; RUST_BACKTRACE=0 AXTERM_TEST_PANIC=1 AXTERM_DATA_DIR={data} {binary} --sim tmcm1110; echo AXTERM-EXIT-$?; stty -a; echo MARKER-END; sleep 600",
        data = dir.path().display(),
    );
    let tmux = Tmux::start("panic", &command, dir.path());
    let console = tmux.until("the console", |s| s.contains("poll 20 Hz"));
    assert!(
        !console.contains("BEFORE-AXTERM"),
        "on the alternate screen: {console}"
    );
    tmux.type_text(":connect --sim tmcm1110");
    tmux.keys(&["Enter"]);
    let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
    // Rust's exit code for a panic in main.
    assert!(after.contains("AXTERM-EXIT-101"), "{after}");
    // The alternate screen was left: the normal screen, with what was on
    // it before, and none of the console.
    assert!(after.contains("BEFORE-AXTERM"), "{after}");
    assert!(
        !after.contains("F12 STOP") && !after.contains("Axes —"),
        "{after}"
    );
    // The message, after the terminal was given back, and in one piece:
    // raw mode would have printed it without carriage returns, as a
    // staircase.
    let message = after
        .lines()
        .find(|l| l.contains("AXTERM_TEST_PANIC is set"))
        .unwrap_or_else(|| panic!("no panic message:\n{after}"));
    assert!(
        message.starts_with("AXTERM_TEST_PANIC is set: a deliberate panic"),
        "{after}"
    );
    let panicked = after
        .lines()
        .find(|l| l.contains("panicked at"))
        .unwrap_or_else(|| panic!("no panic header:\n{after}"));
    assert!(panicked.starts_with("thread 'main'"), "{after}");
    // Cooked mode again.
    assert_terminal_restored(&after, 101);
}
