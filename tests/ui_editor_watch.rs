//! Watching user variables (TMCL bank 2) beside the program: chosen with
//! the watch key on a `GGP/SGP/AGP n, 2` line or typed at its prompt, read
//! at once and then with the program's registers, shown in the panel
//! beside the text (or in the bottom line when the pane is narrow), and
//! kept in the data directory for the next start. The console is driven
//! by keys and replies as the event loop would deliver them.

mod ui_support;

use std::path::Path;

use axterm::session::{LineResult, ReplyValue};
use axterm::ui::PaneSetup;
use axterm::ui::app::{App, AppEvent, Effect};
use axterm::ui::editor::watch::{WATCH_FILE, load_watch_list};
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use ui_support::{axes, console_with, key, key_with, screen, snapshot, type_text};

const PROGRAM: &str = "Count = 5\nLoop: GGP Count, 2\nCALC ADD, 1\nAGP Count, 2\nJA Loop";

/// A connected console with its data directory in `dir`, the editor
/// focused, `PROGRAM` typed in (the cursor on its last line).
fn editor(dir: &Path) -> App {
    let mut app = console_with(&PaneSetup {
        history_dir: Some(dir.to_path_buf()),
    });
    app.handle(AppEvent::Snapshot(snapshot(axes(&["motor 0"]))));
    assert!(app.focus("editor"));
    for c in PROGRAM.chars() {
        app.handle(if c == '\n' {
            key(KeyCode::Enter)
        } else {
            key(KeyCode::Char(c))
        });
    }
    app
}

fn watch_key() -> AppEvent {
    key_with(KeyCode::Char('t'), KeyModifiers::CONTROL)
}

/// Move the cursor up `n` lines.
fn up(app: &mut App, n: usize) {
    for _ in 0..n {
        app.handle(key(KeyCode::Up));
    }
}

/// The sends among `effects`: pane, tag, lines.
fn sends(effects: &[Effect]) -> Vec<(usize, u64, Vec<String>)> {
    effects
        .iter()
        .filter_map(|e| match e {
            Effect::Send { pane, tag, lines } => Some((*pane, *tag, lines.clone())),
            _ => None,
        })
        .collect()
}

fn reply(pane: usize, tag: u64, line: &str, value: i64) -> AppEvent {
    AppEvent::Reply {
        pane,
        tag,
        line: line.to_string(),
        result: Ok(LineResult {
            line: line.to_string(),
            request: Vec::new(),
            reply: Vec::new(),
            status: Some(100),
            value: ReplyValue::Number(value),
            elapsed: std::time::Duration::ZERO,
            attempts: 1,
        }),
    }
}

/// The row of the panel showing `#n`, right of the text.
fn panel_row(lines: &[String], n: u8) -> Option<String> {
    let label = format!(" #{n} ");
    lines
        .iter()
        .find(|l| l.contains(&label) && !l.contains("user variables"))
        .cloned()
}

#[test]
fn the_watch_key_on_a_variable_line_reads_it_now_and_with_every_register_read() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = editor(dir.path());
    // Line 2, `Loop: GGP Count, 2`: the constant resolved by the assembler.
    up(&mut app, 3);
    let effects = app.handle(watch_key());
    let sent = sends(&effects);
    assert_eq!(sent.len(), 1, "{effects:?}");
    let (pane, tag, lines) = sent[0].clone();
    assert_eq!(lines, ["GGP 5, 2"]);
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(
        all.contains("watching user variable #5 (GGP 5, 2)"),
        "{all}"
    );
    assert!(all.contains("user variables"), "{all}");
    app.handle(reply(pane, tag, "GGP 5, 2", 41));
    let lines = screen(&mut app, 80, 24);
    let row = panel_row(&lines, 5).unwrap_or_else(|| panic!("{}", lines.join("\n")));
    assert!(
        row.trim_end_matches('│').trim_end().ends_with("41"),
        "{row}"
    );
    // The text keeps its lines left of the panel.
    assert!(
        lines.iter().any(|l| l.contains("Loop: GGP Count, 2")),
        "{}",
        lines.join("\n")
    );

    // Run: the registers and the variable, read again while it runs.
    let effects = app.handle(key(KeyCode::F(5)));
    let sent = sends(&effects);
    assert_eq!(sent.len(), 2, "{effects:?}");
    assert_eq!(sent[0].2, ["RUNAPP"]);
    let (pane, tag, lines) = sent[1].clone();
    assert_eq!(
        lines,
        [
            "GGP 128, 0",
            "GGP 130, 0",
            "APPSTATUS ACCU",
            "APPSTATUS X",
            "GGP 5, 2"
        ]
    );
    for (line, value) in [("GGP 128, 0", 1), ("GGP 130, 0", 1), ("APPSTATUS ACCU", 42)] {
        app.handle(reply(pane, tag, line, value));
    }
    // Not again before the whole batch is in.
    let effects = app.handle(reply(pane, tag, "APPSTATUS X", 0));
    assert!(!effects.iter().any(|e| matches!(e, Effect::Wake { .. })));
    let effects = app.handle(reply(pane, tag, "GGP 5, 2", 42));
    let wake = effects.iter().find_map(|e| match e {
        Effect::Wake { pane, tag, .. } => Some((*pane, *tag)),
        _ => None,
    });
    let lines = screen(&mut app, 80, 24);
    let row = panel_row(&lines, 5).unwrap_or_else(|| panic!("{}", lines.join("\n")));
    assert!(
        row.trim_end_matches('│').trim_end().ends_with("42"),
        "{row}"
    );
    let (pane, tag) = wake.expect("read again while running");
    let effects = app.handle(AppEvent::Wake { pane, tag });
    assert_eq!(
        sends(&effects).first().map(|s| s.2.last().cloned()),
        Some(Some("GGP 5, 2".to_string()))
    );

    // Kept for the next start.
    assert_eq!(load_watch_list(dir.path(), "user_variables"), [5]);
    assert!(dir.path().join(WATCH_FILE).exists());
    let mut again = editor(dir.path());
    let lines = screen(&mut again, 80, 24);
    let row = panel_row(&lines, 5).unwrap_or_else(|| panic!("{}", lines.join("\n")));
    assert!(row.contains('—'), "not read yet: {row}");

    // The key again on the line: no longer watched, the panel gone.
    let effects = app.handle(watch_key());
    assert!(sends(&effects).is_empty(), "{effects:?}");
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(all.contains("user variable #5 no longer watched"), "{all}");
    assert!(!all.contains("user variables"), "{all}");
    assert!(load_watch_list(dir.path(), "user_variables").is_empty());
}

#[test]
fn on_a_line_without_a_variable_the_number_is_asked_for() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = editor(dir.path());
    // Line 3, `CALC ADD, 1`.
    up(&mut app, 2);
    assert!(sends(&app.handle(watch_key())).is_empty());
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(all.contains("watch user variable (0..255"), "{all}");
    type_text(&mut app, "x7");
    app.handle(key(KeyCode::Enter));
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(
        all.contains("user variables are numbered 0..255, not `x7`"),
        "{all}"
    );
    app.handle(watch_key());
    type_text(&mut app, "200");
    let effects = app.handle(key(KeyCode::Enter));
    assert_eq!(
        sends(&effects).first().map(|s| s.2.clone()),
        Some(vec!["GGP 200, 2".to_string()])
    );
    // The text was not touched.
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(
        all.contains("CALC ADD, 1 ") || all.contains("CALC ADD, 1│"),
        "{all}"
    );
    assert!(!all.contains("x7"), "{all}");
}

/// Too narrow for the panel: the values go to the bottom line.
#[test]
fn a_narrow_editor_shows_the_variables_in_its_bottom_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = editor(dir.path());
    up(&mut app, 3);
    let (pane, tag, _) = sends(&app.handle(watch_key()))[0].clone();
    app.handle(reply(pane, tag, "GGP 5, 2", -3));
    // Esc puts the message away.
    app.handle(key(KeyCode::Esc));
    let lines = screen(&mut app, 56, 20);
    let all = lines.join("\n");
    assert!(!all.contains("user variables"), "{all}");
    assert!(all.contains("│ #5=-3"), "{all}");
}

/// A new connection (another module) has values of its own: read once.
#[test]
fn a_new_connection_reads_the_watched_variables_afresh() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = editor(dir.path());
    up(&mut app, 3);
    let (pane, tag, _) = sends(&app.handle(watch_key()))[0].clone();
    app.handle(reply(pane, tag, "GGP 5, 2", 9));
    let effects = app.handle(AppEvent::Connected(snapshot(axes(&["motor 0"]))));
    let sent = sends(&effects);
    assert_eq!(
        sent.iter().map(|s| s.2.clone()).collect::<Vec<_>>(),
        [vec!["GGP 5, 2".to_string()]]
    );
    let lines = screen(&mut app, 80, 24);
    let row = panel_row(&lines, 5).unwrap_or_else(|| panic!("{}", lines.join("\n")));
    assert!(row.contains('—'), "{row}");
}
