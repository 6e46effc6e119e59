//! The console on a MultiFlex: a long line (Ch2's back-and-forth cycle
//! repeated for ever, `RP` without a count) holds the controller busy, the
//! console says so and that polling waits, and the emergency-stop key
//! aborts it (Escape, answered `?-7`) and stops the axes (`0AB`, the
//! background tasks ended), after which polling goes on and the axis
//! stands. Once on the console's own loop drawing into a `TestBackend`
//! (the in-process simulator at 115200 Bd, tokio's paused clock), once
//! with the real binary in tmux.

mod tmux_support;
mod ui_support;

use ratatui::crossterm::event::KeyCode;
use tmux_support::{Tmux, assert_terminal_restored, console_command};
use ui_support::looped::{Rig, no_connector, press, run_console_on, type_line};
use ui_support::{console, sim_controller};

const FOREVER: &str = "2MR1000,WS0.2,MR-1000,WS0.2,RP";

/// The row or card of axis `name` (`servo 2`): the text after its label,
/// and the next line from the label's column on (cards sit side by side
/// on a wide screen).
fn after_name(frame: &str, name: &str) -> Option<(String, Option<String>)> {
    let lines: Vec<Vec<char>> = frame.lines().map(|l| l.chars().collect()).collect();
    let label: Vec<char> = name.chars().collect();
    for (row, line) in lines.iter().enumerate() {
        for column in 0..line.len().saturating_sub(label.len()) {
            if line[column..column + label.len()] != label[..] {
                continue;
            }
            let before = column.checked_sub(1).map(|c| line[c]);
            if !matches!(before, Some('│' | '▶' | ' ')) {
                continue;
            }
            let rest: String = line[column + label.len()..].iter().collect();
            let first = rest.trim_start().chars().next();
            if rest.starts_with(' ')
                && first.is_some_and(|c| c == 'p' || c == '—' || c == '-' || c.is_ascii_digit())
            {
                let next = lines
                    .get(row + 1)
                    .map(|l| l.iter().skip(column).collect::<String>());
                return Some((rest, next));
            }
        }
    }
    None
}

/// The speed shown for `name`: `v0/—` in a row, `spd 0` in a card.
fn speed(frame: &str, name: &str) -> Option<i64> {
    let (rest, next) = after_name(frame, name)?;
    let words: Vec<&str> = rest.split_whitespace().collect();
    if words.first() == Some(&"pos") {
        let next = next?;
        let next: Vec<&str> = next.split_whitespace().collect();
        let at = next.iter().position(|w| *w == "spd")?;
        return next.get(at + 1)?.parse().ok();
    }
    let v = words.iter().find(|w| w.starts_with('v'))?;
    v.trim_start_matches('v').split('/').next()?.parse().ok()
}

/// The position shown for `name`: `-500→1000` in a row, `pos -500` in a
/// card.
fn position(frame: &str, name: &str) -> Option<i64> {
    let (rest, _) = after_name(frame, name)?;
    let words: Vec<&str> = rest.split_whitespace().collect();
    let word = match words.first() {
        Some(&"pos") => words.get(1)?,
        other => other?,
    };
    word.split('→').next()?.parse().ok()
}

async fn busy_line_stopped_by_the_stop_key(size: (u16, u16)) {
    let controller = sim_controller("mccl", 115_200).await;
    run_console_on(
        console(),
        size,
        Some(controller),
        no_connector(),
        async |mut rig: Rig| {
            rig.screens
                .until_frame("five axes polled", |f| {
                    f.contains("poll 20 Hz → ") && position(f, "step 5") == Some(0)
                })
                .await;
            type_line(&rig, "2MN");
            rig.screens.until("  ok").await;
            type_line(&rig, FOREVER);
            let busy = rig
                .screens
                .until_frame("the busy line and its keys", |f| {
                    f.contains(&format!("busy {FOREVER}: Esc aborts, Space pauses"))
                })
                .await;
            assert!(busy.contains("poll suspended"), "{busy}");
            press(&rig, KeyCode::F(12));
            let stopped = rig
                .screens
                .until("STOP confirmed: every stop line answered ok")
                .await;
            assert!(!stopped.contains("busy 2MR"), "{stopped}");
            // Polling goes on, and axis 2 stands where the stop left it.
            let standing = rig
                .screens
                .until_frame("axis 2 standing, polled again", |f| {
                    f.contains("poll 20 Hz → ") && speed(f, "servo 2") == Some(0)
                })
                .await;
            assert!(!standing.contains("poll suspended"), "{standing}");
        },
    )
    .await;
}

#[tokio::test(start_paused = true)]
async fn a_busy_line_is_aborted_and_the_axes_stopped_by_the_stop_key_at_80_by_24() {
    busy_line_stopped_by_the_stop_key((80, 24)).await;
}

#[tokio::test(start_paused = true)]
async fn a_busy_line_is_aborted_and_the_axes_stopped_by_the_stop_key_on_a_large_screen() {
    busy_line_stopped_by_the_stop_key((200, 50)).await;
}

#[test]
fn the_real_binary_stops_a_long_rp_line_with_the_stop_key() {
    let dir = tempfile::tempdir().expect("temp dir");
    let command = console_command(dir.path(), "--sim mccl");
    let tmux = Tmux::start("mccl-rp", &command, dir.path());
    tmux.until("the console with five axes", |s| {
        s.contains("poll 20 Hz") && position(s, "step 5") == Some(0)
    });
    tmux.type_text("2MN");
    tmux.keys(&["Enter"]);
    tmux.until("2MN answered", |s| s.contains("  ok"));
    tmux.type_text(FOREVER);
    tmux.keys(&["Enter"]);
    let busy = tmux.until("the line busy", |s| {
        s.contains(&format!("busy {FOREVER}")) && s.contains("poll susp")
    });
    assert!(busy.contains("Esc aborts, Space pauses"), "{busy}");

    tmux.keys(&["F12"]);
    let stopped = tmux.until("the stop confirmed, axis 2 standing", |s| {
        s.contains("STOP confirmed: every stop line answered ok")
            && !s.contains("busy 2MR")
            && speed(s, "servo 2") == Some(0)
    });
    // 0AB and the 21 tasks' ET.
    assert!(stopped.contains("STOP: 22 sent, all ok"), "{stopped}");
    // Standing: read twice, the same position.
    // The value shown under each `> 2TP`.
    let answers = |s: &str| -> Vec<i64> {
        let lines: Vec<&str> = s.lines().collect();
        lines
            .windows(2)
            .filter(|w| w[0].trim_matches(['│', ' ']) == "> 2TP")
            .filter_map(|w| w[1].trim_matches(['│', ' ']).parse().ok())
            .collect()
    };
    let mut read = Vec::new();
    for n in 1..=2 {
        tmux.type_text("2TP");
        tmux.keys(&["Enter"]);
        let screen = tmux.until("2TP answered", |s| answers(s).len() >= n);
        read = answers(&screen);
    }
    assert!(read.len() == 2 && read[0] == read[1], "{read:?}");

    tmux.keys(&["F10"]);
    let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
    assert_terminal_restored(&after, 0);
}
