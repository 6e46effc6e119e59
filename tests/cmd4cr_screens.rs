//! The console on a real CMD-4CR session: the console's own loop drawing
//! into a `TestBackend`, the session on the in-process simulator with the
//! wire time of 9600 Bd, on tokio's paused clock. X is jogged from the
//! command pane, the axis pane shows it move with its MST lamps and the
//! refresh rate the line gives; the emergency-stop key stops it (ESTOP,
//! the four programs, ESTOP) and the screen confirms it; the EMG error
//! ESTOP latched on X is cleared with F8 (CLRX) and stays cleared. At
//! 80×24 and on a large screen. Then the parameter table on the same
//! simulator. And the real binary in tmux on `--sim cmd4cr`: X jogged, the
//! emergency-stop key, X stopped and the stop confirmed, the terminal
//! given back.

mod tmux_support;
mod ui_support;

use axterm::families::find_family;
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use tmux_support::{Tmux, assert_terminal_restored, console_command};
use ui_support::looped::{Rig, no_connector, press, press_with, run_console_on, type_line};
use ui_support::{console, sim_controller};

/// The words of `frame` after axis `name`'s label (cards: `X  pos 12`,
/// rows: `X  12→—`; cards sit side by side on a wide screen).
fn after_label<'a>(frame: &'a str, name: &str) -> Option<Vec<&'a str>> {
    frame.lines().find_map(|line| {
        let words: Vec<&str> = line.split_whitespace().collect();
        let at = words
            .iter()
            .position(|w| w.trim_start_matches(['│', '▶']) == name)?;
        Some(words.get(at + 1..)?.to_vec())
    })
}

/// The position shown for axis `name`.
fn position(frame: &str, name: &str) -> Option<i64> {
    let words = after_label(frame, name)?;
    let word = match words.first() {
        Some(&"pos") => words.get(1)?,
        other => other?,
    };
    word.split('→').next()?.parse().ok()
}

/// Jog X, stop everything with F12, clear X's errors with F8, at `size`.
async fn jog_stop_and_clear(size: (u16, u16), cards: bool) {
    let controller = sim_controller("cmd4cr", 9600).await;
    run_console_on(
        console(),
        size,
        Some(controller),
        no_connector(),
        async |mut rig: Rig| {
            let first = rig
                .screens
                .until_frame("the four axes polled, the refresh rate measured", |f| {
                    f.contains("poll 20 Hz → ")
                        && ["X", "Y", "Z", "U"]
                            .iter()
                            .all(|a| position(f, a) == Some(0))
                })
                .await;
            assert!(first.contains("F12 STOP"), "{first}");
            if cards {
                // Every lamp, dark; no load gauge on a CMD-4CR.
                for lamp in [
                    "L○",
                    "R○",
                    "H○",
                    "ALM○",
                    "SD○",
                    "INP○",
                    "EMG○",
                    "wait CSTA○",
                ] {
                    assert!(first.contains(lamp), "{lamp}:\n{first}");
                }
                assert!(!first.contains(" load "), "{first}");
            }

            type_line(&rig, "JX+");
            let moving = rig
                .screens
                .until_frame("X to move", |f| {
                    position(f, "X").is_some_and(|p| p > 0) && f.contains("  ok")
                })
                .await;
            assert!(
                moving.contains("@01JX+"),
                "the bytes sent are shown: {moving}"
            );
            if cards {
                // MST says so (bit 2), PSX reads HSPDX.
                rig.screens
                    .until_frame("X at its high speed", |f| {
                        f.contains("1000 at max speed") && f.contains("○ moving")
                    })
                    .await;
            }

            press(&rig, KeyCode::F(12));
            let stopped = rig
                .screens
                .until("STOP confirmed: every stop line answered ok")
                .await;
            // All motion first, then the four programs, then all motion
            // again (the first lines may have scrolled off a small pane).
            for line in ["sent SACTRL3=0", "sent ESTOP", "STOP: 6 sent, all ok"] {
                assert!(stopped.contains(line), "{line}:\n{stopped}");
            }
            let order: Vec<&str> = stopped
                .lines()
                .filter_map(|l| l.split_once("  sent ").map(|(_, rest)| rest))
                .filter(|rest| !rest.starts_with('@'))
                .filter_map(|rest| rest.split_whitespace().next())
                .collect();
            let full: Vec<String> = find_family("cmd4cr")
                .expect("registered")
                .console
                .emergency_stop(1)
                .into_iter()
                .map(|line| line.canonical)
                .collect();
            let full: Vec<&str> = full.iter().map(String::as_str).collect();
            assert!(
                !order.is_empty() && full.ends_with(&order),
                "{order:?}\n{stopped}"
            );
            // X stands; ESTOP latched the EMG error on it (it was moving).
            // A jog has no target: X has stopped (`v0/` on the compact
            // row), and nothing says "reached".
            let standing = rig
                .screens
                .until_frame("X standing with its EMG error", |f| {
                    f.contains("ERR EMG error")
                        && after_label(f, "X").is_some_and(|w| {
                            w.iter().any(|w| *w == "stopped" || w.starts_with("v0/"))
                        })
                })
                .await;
            let row = after_label(&standing, "X").unwrap_or_default();
            assert!(
                !row.iter().any(|w| w.contains('●') || *w == "reached"),
                "{standing}"
            );
            let x = position(&standing, "X").expect("X's position");
            assert!(x > 0, "{standing}");

            press(&rig, KeyCode::F(8));
            let cleared = rig
                .screens
                .until("the error flags of X are cleared in the controller")
                .await;
            assert!(cleared.contains("CLRX: ok"), "{cleared}");
            // Later polls of MSTX do not bring it back, and X stays put.
            type_line(&rig, "MSTX");
            let after = rig.screens.until("> MSTX").await;
            let after = if after.contains("ERR EMG error") {
                rig.screens
                    .until_frame("the error gone", |f| !f.contains("ERR EMG error"))
                    .await
            } else {
                after
            };
            assert_eq!(position(&after, "X"), Some(x), "{after}");
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
}

#[tokio::test(start_paused = true)]
async fn jog_stop_and_clear_at_80_by_24() {
    jog_stop_and_clear((80, 24), false).await;
}

#[tokio::test(start_paused = true)]
async fn jog_stop_and_clear_on_a_large_screen() {
    jog_stop_and_clear((200, 50), true).await;
}

#[tokio::test(start_paused = true)]
async fn the_parameter_table_of_the_simulator() {
    let controller = sim_controller("cmd4cr", 9600).await;
    run_console_on(
        console(),
        (120, 40),
        Some(controller),
        no_connector(),
        async |mut rig: Rig| {
            rig.screens.until("poll 20 Hz").await;
            press_with(&rig, KeyCode::Char('3'), KeyModifiers::ALT);
            let table = rig
                .screens
                .until_frame("the axis table read", |f| {
                    f.contains("HSPDX") && f.contains("POLX") && !f.contains("reading")
                })
                .await;
            assert!(table.contains("Axis X"), "{table}");
            let row = |frame: &str, name: &str| {
                frame
                    .lines()
                    .find(|l| l.contains(&format!(" {name} ")) && !l.contains("filter"))
                    .unwrap_or_else(|| panic!("no {name} row:\n{frame}"))
                    .to_string()
            };
            // Everything read: a per-axis speed of 0 names the global one.
            let table = rig
                .screens
                .until_frame("every parameter read", |f| {
                    f.contains("186 parameters") && !f.contains("busy")
                })
                .await;
            let hspd = row(&table, "HSPDX");
            assert!(
                hspd.contains(" 0 pps") && hspd.contains("global 1000"),
                "{hspd}"
            );
            // Numbers of five digits keep the columns in line.
            let heading = table
                .lines()
                .find(|l| l.contains("Name"))
                .unwrap_or_default();
            let at = |line: &str, word: &str| line.find(word).map(|b| line[..b].chars().count());
            assert_eq!(
                at(heading, "Value").map(|c| c + 5),
                at(&hspd, " pps"),
                "{table}"
            );
            // POL raw, with its field names under the table.
            press(&rig, KeyCode::Char('/'));
            type_line(&rig, "POLX");
            let pol = rig
                .screens
                .until("POL 7: pulse/direction output mode and logic (bits 0-2) = 7;")
                .await;
            assert!(row(&pol, "POLX").contains(" 7 "), "{pol}");
            // STORE keeps it (and every other setting of Table 2-19).
            press(&rig, KeyCode::Char('s'));
            rig.screens
                .until("STORE: stored in flash, with every setting of Table 2-19")
                .await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
}

/// The speed shown for axis `name`: on the `spd` row of its card, or in
/// its row (`v1000/1000`) when the pane has one row per axis.
fn speed(frame: &str, name: &str) -> Option<i64> {
    let lines: Vec<&str> = frame.lines().collect();
    let at = lines.iter().position(|line| {
        line.split_whitespace()
            .any(|w| w.trim_start_matches(['│', '▶']) == name)
    })?;
    let words = after_label(frame, name)?;
    let word = if words.first() == Some(&"pos") {
        let next: Vec<&str> = lines.get(at + 1)?.split_whitespace().collect();
        let spd = next.iter().position(|w| *w == "spd")?;
        next.get(spd + 1)?.to_string()
    } else {
        let v = words.iter().find(|w| w.starts_with('v'))?;
        v.trim_start_matches('v').split('/').next()?.to_string()
    };
    word.parse().ok()
}

#[test]
fn the_real_binary_jogs_x_and_the_stop_key_stops_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let command = console_command(dir.path(), "--sim cmd4cr");
    let tmux = Tmux::start("cmd4cr-jog", &command, dir.path());
    tmux.until("the console with four axes", |s| {
        s.contains("poll 20 Hz")
            && ["X", "Y", "Z", "U"]
                .iter()
                .all(|a| position(s, a) == Some(0))
    });
    tmux.type_text("JX+");
    tmux.keys(&["Enter"]);
    let moving = tmux.until("X to move", |s| {
        position(s, "X").is_some_and(|p| p > 0) && speed(s, "X").is_some_and(|v| v > 0)
    });
    assert!(moving.contains("@01JX+"), "{moving}");

    tmux.keys(&["F12"]);
    // ESTOP latches the EMG error on X, which was moving (MST bit 16).
    let stopped = tmux.until("the stop confirmed, X standing, its EMG error", |s| {
        s.contains("STOP confirmed: every stop line answered ok")
            && speed(s, "X") == Some(0)
            && s.contains("ERR EMG error")
    });
    // The status bar keeps the count: ESTOP, SACTRL0..3=0, ESTOP.
    assert!(stopped.contains("STOP: 6 sent, all ok"), "{stopped}");
    // Standing means standing: PX read twice answers the same, and the
    // pane shows it.
    let answers = |s: &str| -> Vec<i64> {
        s.split("@01PX\\r  got ")
            .skip(1)
            .filter_map(|rest| rest.split_whitespace().next()?.parse().ok())
            .collect()
    };
    let mut read = Vec::new();
    for n in 1..=2 {
        tmux.type_text("PX");
        tmux.keys(&["Enter"]);
        let screen = tmux.until("PX answered", |s| answers(s).len() >= n);
        read = answers(&screen);
    }
    assert!(read[0] > 0 && read[0] == read[1], "{read:?}");
    tmux.until("the pane at the position read", |s| {
        position(s, "X") == Some(read[0])
    });

    tmux.keys(&["F10"]);
    let after = tmux.until("axterm to exit", |s| s.contains("MARKER-END"));
    assert!(
        !after.contains("F12 STOP"),
        "the alternate screen was left: {after}"
    );
    assert_terminal_restored(&after, 0);
}
