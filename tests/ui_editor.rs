//! The program editor inside the console: colours, error marks as you
//! type, go-to-error, open/save/save-as, the safety copy and its recovery,
//! and the emergency stop from the editor.

mod ui_support;

use std::path::Path;

use axterm::ui::PaneSetup;
use axterm::ui::app::{App, AppEvent, Effect};
use axterm::ui::editor::autosave::{AUTOSAVE_FILE, read_autosave};
use axterm::ui::theme::Role;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use ui_support::{console_with, key, key_with, screen};

const PROGRAM: &str = "Far = 51200\nLoop: MVP ABS, 0, Far // out\nWAIT POS, 0, 0\nJA Loop";

/// A console with its data directory in `dir`, the editor focused.
fn editor_console(dir: Option<&Path>) -> App {
    let mut app = console_with(&PaneSetup {
        history_dir: dir.map(Path::to_path_buf),
    });
    assert!(app.focus("editor"));
    app
}

/// Type text into the focused pane, newlines as Enter; carry out the
/// safety-copy timers the editor asks for, as the loop would when they
/// come due.
fn type_program(app: &mut App, text: &str) -> Vec<Effect> {
    let mut effects = Vec::new();
    for c in text.chars() {
        let event = if c == '\n' {
            key(KeyCode::Enter)
        } else {
            key(KeyCode::Char(c))
        };
        effects.extend(app.handle(event));
    }
    effects
}

/// Let the last safety-copy timer come due (the earlier ones are stale).
fn timers_due(app: &mut App, effects: &[Effect]) {
    for effect in effects {
        if let Effect::Wake { pane, tag, .. } = effect {
            app.handle(AppEvent::Wake {
                pane: *pane,
                tag: *tag,
            });
        }
    }
}

fn row_with<'a>(lines: &'a [String], text: &str) -> Option<(usize, &'a String)> {
    lines.iter().enumerate().find(|(_, l)| l.contains(text))
}

#[test]
fn source_is_coloured_by_what_each_word_is() {
    let mut app = editor_console(None);
    type_program(&mut app, PROGRAM);
    let mut terminal = Terminal::new(TestBackend::new(100, 30)).expect("backend");
    terminal.draw(|f| app.render(f)).expect("draw");
    let buffer = terminal.backend().buffer().clone();
    let theme = app.theme().clone();
    let find = |text: &str| -> (u16, u16) {
        for y in 0..30u16 {
            let row: String = (0..100u16)
                .map(|x| buffer[(x, y)].symbol().to_string())
                .collect();
            if let Some(at) = row.find(text) {
                let x = row.get(..at).map_or(0, |b| b.chars().count());
                return (u16::try_from(x).unwrap_or(0), y);
            }
        }
        panic!("{text} not on screen");
    };
    let fg = |role: Role| theme.style(role).fg;
    let cell = |at: (u16, u16)| Some(buffer[at].fg);
    assert_eq!(cell(find("MVP")), fg(Role::CodeMnemonic));
    assert_eq!(cell(find("Loop:")), fg(Role::CodeLabel));
    assert_eq!(cell(find("51200")), fg(Role::CodeNumber));
    assert_eq!(cell(find("// out")), fg(Role::CodeComment));
    assert_ne!(fg(Role::CodeMnemonic), fg(Role::CodeComment));
}

#[test]
fn errors_are_marked_at_their_lines_as_you_type_and_the_cursor_goes_to_them() {
    let mut app = editor_console(None);
    type_program(
        &mut app,
        "MVP ABS, 0, 100\nMVP SIDEWAYS, 0, 1\nJA Nowhere\nSTOP",
    );
    for (w, h) in [(80, 24), (200, 50)] {
        let lines = screen(&mut app, w, h);
        let (_, second) = row_with(&lines, "MVP SIDEWAYS").expect("line 2 shown");
        assert!(second.contains("!  2"), "{second}");
        let (_, first) = row_with(&lines, "MVP ABS, 0, 100").expect("line 1 shown");
        assert!(!first.contains('!'), "{first}");
        let (_, third) = row_with(&lines, "JA Nowhere").expect("line 3 shown");
        assert!(third.contains("!  3"), "{third}");
    }
    // Go to the first error (from the last line: round to the top).
    app.handle(key_with(KeyCode::Char('g'), KeyModifiers::CONTROL));
    let lines = screen(&mut app, 80, 24);
    assert!(
        lines.iter().any(|l| l.contains("untitled.tmc:2:")),
        "{}",
        lines.join("\n")
    );
    app.handle(key_with(KeyCode::Char('g'), KeyModifiers::CONTROL));
    let lines = screen(&mut app, 80, 24);
    assert!(lines.iter().any(|l| l.contains("untitled.tmc:3:")));
    // Mending the line takes its mark away.
    app.handle(key(KeyCode::End));
    for _ in 0.."Nowhere".len() {
        app.handle(key(KeyCode::Backspace));
    }
    type_program(&mut app, "0");
    let lines = screen(&mut app, 80, 24);
    let (_, third) = row_with(&lines, "JA 0").expect("line 3");
    assert!(!third.contains('!'), "{third}");
}

#[test]
fn save_as_save_and_open_go_through_the_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("prog.tmc");
    let mut app = editor_console(None);
    type_program(&mut app, "MVP ABS, 0, 1");
    // F2 without a file asks for a name.
    app.handle(key(KeyCode::F(2)));
    let lines = screen(&mut app, 80, 24);
    assert!(lines.iter().any(|l| l.contains("save as:")));
    app.handle(AppEvent::Terminal(ratatui::crossterm::event::Event::Paste(
        path.display().to_string(),
    )));
    app.handle(key(KeyCode::Enter));
    assert_eq!(
        std::fs::read_to_string(&path).expect("saved"),
        "MVP ABS, 0, 1"
    );
    let lines = screen(&mut app, 200, 50);
    assert!(
        lines.iter().any(|l| l.contains("Program — prog.tmc ")),
        "{}",
        lines.join("\n")
    );
    // A change is marked, and F2 now saves without asking.
    type_program(&mut app, "\nSTOP");
    assert!(
        screen(&mut app, 200, 50)
            .iter()
            .any(|l| l.contains("prog.tmc*"))
    );
    app.handle(key(KeyCode::F(2)));
    assert_eq!(
        std::fs::read_to_string(&path).expect("saved"),
        "MVP ABS, 0, 1\nSTOP"
    );
    // Another file; opening it replaces the text.
    let other = dir.path().join("other.tmc");
    std::fs::write(&other, "ROL 0, 100\n").expect("write");
    app.handle(key(KeyCode::F(3)));
    app.handle(AppEvent::Terminal(ratatui::crossterm::event::Event::Paste(
        other.display().to_string(),
    )));
    app.handle(key(KeyCode::Enter));
    let lines = screen(&mut app, 80, 24);
    assert!(
        lines.iter().any(|l| l.contains("ROL 0, 100")),
        "{}",
        lines.join("\n")
    );
    assert!(!lines.iter().any(|l| l.contains("  2 STOP")));
    // A file that is not there is said, and changes nothing.
    app.handle(key(KeyCode::F(3)));
    type_program(&mut app, "missing.tmc");
    app.handle(key(KeyCode::Enter));
    let lines = screen(&mut app, 80, 24);
    assert!(lines.iter().any(|l| l.contains("cannot open missing.tmc")));
    assert!(lines.iter().any(|l| l.contains("ROL 0, 100")));
}

#[test]
fn opening_over_unsaved_changes_asks_first() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = editor_console(None);
    type_program(&mut app, "STOP");
    app.handle(key(KeyCode::F(3)));
    let lines = screen(&mut app, 80, 24);
    assert!(lines.iter().any(|l| l.contains("unsaved changes")));
    assert!(!lines.iter().any(|l| l.contains("open file:")));
    app.handle(key(KeyCode::F(3)));
    let lines = screen(&mut app, 80, 24);
    assert!(lines.iter().any(|l| l.contains("open file:")));
    // Esc leaves the prompt; the text is still there.
    app.handle(key(KeyCode::Esc));
    let lines = screen(&mut app, 80, 24);
    assert!(lines.iter().any(|l| l.contains("STOP")));
    drop(dir);
}

#[test]
fn the_safety_copy_follows_the_text_and_is_offered_again_at_start() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = editor_console(Some(dir.path()));
    let effects = type_program(&mut app, "MVP ABS, 0, 1\nSTOP");
    // Nothing written before the quiet period is over.
    assert!(read_autosave(dir.path()).is_none());
    // Every change asks for the timer again; only the last one writes.
    let wakes: Vec<&Effect> = effects
        .iter()
        .filter(|e| matches!(e, Effect::Wake { .. }))
        .collect();
    assert_eq!(wakes.len(), "MVP ABS, 0, 1\nSTOP".len());
    timers_due(&mut app, &effects[..effects.len() - 1]);
    assert!(read_autosave(dir.path()).is_none(), "a stale timer wrote");
    timers_due(&mut app, &effects);
    let copy = read_autosave(dir.path()).expect("the safety copy");
    assert_eq!(copy.text, "MVP ABS, 0, 1\nSTOP");
    assert_eq!(copy.file, None);

    // The console starts again (after a crash): the text is offered.
    let mut again = editor_console(Some(dir.path()));
    for (w, h) in [(80, 24), (200, 50)] {
        let lines = screen(&mut again, w, h);
        let all = lines.join("\n");
        assert!(
            all.contains("recovered unsaved text of untitled from"),
            "{all}"
        );
        assert!(
            all.contains("MVP ABS, 0, 1") && all.contains("STOP"),
            "{all}"
        );
    }
    let all = screen(&mut again, 200, 50).join("\n");
    assert!(all.contains("F2 to save, or discard with Esc"), "{all}");
    // Discarding forgets it, on screen and on disk.
    again.handle(key(KeyCode::Esc));
    let all = screen(&mut again, 80, 24).join("\n");
    assert!(
        !all.contains("recovered unsaved") && !all.contains("MVP ABS"),
        "{all}"
    );
    assert!(!dir.path().join(AUTOSAVE_FILE).exists());
}

#[test]
fn saving_recovered_text_writes_its_file_and_forgets_the_copy() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("prog.tmc");
    std::fs::write(&file, "STOP").expect("write");
    let mut app = editor_console(Some(dir.path()));
    app.handle(key(KeyCode::F(3)));
    type_program(&mut app, &file.display().to_string());
    app.handle(key(KeyCode::Enter));
    app.handle(key(KeyCode::Home));
    let effects = type_program(&mut app, "ROL 0, 5\n");
    timers_due(&mut app, &effects);
    let copy = read_autosave(dir.path()).expect("copy");
    assert_eq!(copy.file.as_deref(), Some(file.as_path()));

    let mut again = editor_console(Some(dir.path()));
    let all = screen(&mut again, 200, 50).join("\n");
    assert!(
        all.contains(&format!("recovered unsaved text of {}", file.display())),
        "{all}"
    );
    assert!(all.contains("prog.tmc*"), "{all}");
    again.handle(key(KeyCode::F(2)));
    assert_eq!(
        std::fs::read_to_string(&file).expect("file"),
        "ROL 0, 5\nSTOP"
    );
    assert!(!dir.path().join(AUTOSAVE_FILE).exists());
    let all = screen(&mut again, 200, 50).join("\n");
    assert!(!all.contains("recovered unsaved"), "{all}");
}

#[test]
fn f12_in_the_editor_still_stops_and_types_nothing() {
    let mut app = editor_console(None);
    type_program(&mut app, "STOP");
    assert_eq!(app.handle(key(KeyCode::F(12))), [Effect::EmergencyStop]);
    // With the file name prompt open too.
    app.handle(key(KeyCode::F(3)));
    app.handle(key(KeyCode::F(3)));
    assert!(
        screen(&mut app, 80, 24)
            .iter()
            .any(|l| l.contains("open file:"))
    );
    assert_eq!(app.handle(key(KeyCode::F(12))), [Effect::EmergencyStop]);
    app.handle(key(KeyCode::Esc));
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(all.contains("  1 STOP"), "{all}");
    assert!(
        all.contains("STOP sending") || all.contains("F12 STOP"),
        "{all}"
    );
}

#[test]
fn a_long_program_scrolls_to_keep_the_cursor_in_view() {
    let mut app = editor_console(None);
    let text: String = (0..60).map(|n| format!("ROL 0, {n}\n")).collect();
    type_program(&mut app, &text);
    let lines = screen(&mut app, 80, 24);
    assert!(
        lines.iter().any(|l| l.contains(" 60 ROL 0, 59")),
        "{}",
        lines.join("\n")
    );
    assert!(!lines.iter().any(|l| l.contains("  1 ROL 0, 0")));
    app.handle(key_with(KeyCode::Home, KeyModifiers::CONTROL));
    for _ in 0..4 {
        app.handle(key(KeyCode::PageUp));
    }
    let lines = screen(&mut app, 80, 24);
    assert!(
        lines.iter().any(|l| l.contains("  1 ROL 0, 0")),
        "{}",
        lines.join("\n")
    );
}

/// The module's answer to one register read.
fn number_reply(pane: usize, line: &str, value: i64) -> AppEvent {
    AppEvent::Reply {
        pane,
        tag: (1 << 48) + 1,
        line: line.to_string(),
        result: Ok(axterm::session::LineResult {
            line: line.to_string(),
            request: Vec::new(),
            reply: Vec::new(),
            status: Some(100),
            value: axterm::session::ReplyValue::Number(value),
            elapsed: std::time::Duration::ZERO,
            attempts: 1,
        }),
    }
}

#[test]
fn run_reads_the_registers_and_marks_the_line_the_program_counter_is_on() {
    let mut app = editor_console(None);
    type_program(&mut app, PROGRAM);
    let effects = app.handle(key(KeyCode::F(5)));
    let sends: Vec<(usize, Vec<String>)> = effects
        .iter()
        .filter_map(|e| match e {
            Effect::Send { pane, lines, .. } => Some((*pane, lines.clone())),
            _ => None,
        })
        .collect();
    assert_eq!(sends.len(), 2, "{effects:?}");
    assert_eq!(sends[0].1, ["RUNAPP"]);
    assert_eq!(
        sends[1].1,
        ["GGP 128, 0", "GGP 130, 0", "APPSTATUS ACCU", "APPSTATUS X"]
    );
    let pane = sends[0].0;
    // Running, at address 1: `WAIT POS, 0, 0`, source line 3.
    app.handle(number_reply(pane, "GGP 128, 0", 1));
    app.handle(number_reply(pane, "GGP 130, 0", 1));
    app.handle(number_reply(pane, "APPSTATUS ACCU", 7));
    let effects = app.handle(number_reply(pane, "APPSTATUS X", -3));
    // Still running: read again later.
    assert!(
        effects.iter().any(|e| matches!(e, Effect::Wake { .. })),
        "{effects:?}"
    );
    for (w, h) in [(80, 24), (200, 50)] {
        let lines = screen(&mut app, w, h);
        let (_, current) = row_with(&lines, "WAIT POS").expect("line 3");
        assert!(current.contains("▶  3"), "{current}");
        let (_, other) = row_with(&lines, "JA Loop").expect("line 4");
        assert!(!other.contains('▶'), "{other}");
        let all = lines.join("\n");
        assert!(all.contains("running PC 1 ACC 7 X -3"), "{all}");
    }
    // The timer comes due: the registers are read again; the program has
    // stopped at the jump, and nothing more is asked.
    let effects = app.handle(AppEvent::Wake {
        pane,
        tag: (1 << 48) + 2,
    });
    assert!(effects.iter().any(|e| matches!(e, Effect::Send { .. })));
    app.handle(number_reply(pane, "GGP 128, 0", 0));
    app.handle(number_reply(pane, "GGP 130, 0", 2));
    app.handle(number_reply(pane, "APPSTATUS ACCU", 7));
    let effects = app.handle(number_reply(pane, "APPSTATUS X", -3));
    assert!(!effects.iter().any(|e| matches!(e, Effect::Wake { .. })));
    let lines = screen(&mut app, 80, 24);
    let (_, current) = row_with(&lines, "JA Loop").expect("line 4");
    assert!(current.contains("▶  4"), "{current}");
}

#[test]
fn stop_step_and_reset_send_their_control_commands() {
    let mut app = editor_console(None);
    type_program(&mut app, PROGRAM);
    for (code, line) in [(KeyCode::F(7), "STEPAPP"), (KeyCode::F(5), "RUNAPP")] {
        let effects = app.handle(key(code));
        assert!(
            matches!(effects.first(), Some(Effect::Send { lines, .. }) if lines == &[line]),
            "{effects:?}"
        );
    }
    let effects = app.handle(key_with(KeyCode::F(5), KeyModifiers::SHIFT));
    assert!(matches!(effects.first(), Some(Effect::Send { lines, .. }) if lines == &["STOPAPP"]));
    let effects = app.handle(key_with(KeyCode::F(7), KeyModifiers::SHIFT));
    assert!(matches!(effects.first(), Some(Effect::Send { lines, .. }) if lines == &["RESETAPP"]));
}

/// A console on `dir` whose safety copy holds `text` (typed, the timer
/// come due), then a fresh console on the same directory: the one that
/// recovers it.
fn crashed_with(dir: &Path, text: &str) -> App {
    let mut app = editor_console(Some(dir));
    let effects = type_program(&mut app, text);
    timers_due(&mut app, &effects);
    assert!(read_autosave(dir).is_some(), "the safety copy was written");
    editor_console(Some(dir))
}

#[test]
fn recovered_text_keeps_its_language_when_another_familys_module_connects() {
    let dir = tempfile::tempdir().expect("temp dir");
    let copy_of = |dir: &Path| read_autosave(dir).expect("copy");
    let mut again = crashed_with(dir.path(), "MVP ABS, 0, 1\nSTOP");
    assert_eq!(copy_of(dir.path()).language.as_deref(), Some("TMCL"));
    // The next connection is a CMD-4CR: the text stays TMCL, checks as
    // TMCL, and is not marked full of A-Script errors.
    let cmd4cr = axterm::ui::pane::Snapshot {
        family: axterm::families::find_family("cmd4cr").expect("cmd4cr"),
        ..ui_support::snapshot(ui_support::axes(&["X", "Y", "Z", "U"]))
    };
    again.handle(AppEvent::Snapshot(cmd4cr));
    let all = screen(&mut again, 150, 40).join("\n");
    assert!(all.contains("Program — untitled*"), "{all}");
    assert!(all.contains("assembles: 2 words"), "{all}");
    assert!(
        all.contains("(TMCL)"),
        "the banner says the language: {all}"
    );
    assert!(!all.contains("!  1"), "{all}");
}

#[test]
fn a_copy_from_before_languages_were_kept_comes_back_by_its_extension() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(
        dir.path().join(AUTOSAVE_FILE),
        r#"{"file": "prog.asc", "written": 0, "text": "PRG 0\n    V1=2\nEND"}"#,
    )
    .expect("write");
    let mut app = editor_console(Some(dir.path()));
    let all = screen(&mut app, 100, 30).join("\n");
    assert!(all.contains("Program (A-Script) — prog.asc*"), "{all}");
    assert!(all.contains("A-Script checks: PRG 0"), "{all}");
}

#[test]
fn esc_discards_the_recovered_copy_only_until_it_is_edited() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut again = crashed_with(dir.path(), "MVP ABS, 0, 1\nSTOP");
    // Typed into the recovered text: it is the user's work now.
    again.handle(key(KeyCode::End));
    let effects = type_program(&mut again, " // mine");
    timers_due(&mut again, &effects);
    again.handle(key(KeyCode::Esc));
    let all = screen(&mut again, 100, 30).join("\n");
    assert!(all.contains("MVP ABS, 0, 1 // mine"), "{all}");
    assert!(!all.contains("recovered unsaved"), "{all}");
    let copy = read_autosave(dir.path()).expect("still kept safe");
    assert_eq!(copy.text, "MVP ABS, 0, 1 // mine\nSTOP");
}

#[test]
fn the_recovery_banners_keys_fit_80_columns_whatever_the_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let deep = dir
        .path()
        .join("a-directory-with-a-long-name")
        .join("and-another-one-below-it")
        .join("the-program-of-the-machine.tmc");
    std::fs::create_dir_all(deep.parent().expect("parent")).expect("dirs");
    std::fs::write(&deep, "STOP").expect("write");
    let mut app = editor_console(Some(dir.path()));
    app.handle(key(KeyCode::F(3)));
    type_program(&mut app, &deep.display().to_string());
    app.handle(key(KeyCode::Enter));
    app.handle(key(KeyCode::Home));
    let effects = type_program(&mut app, "ROL 0, 5\n");
    timers_due(&mut app, &effects);
    let mut again = editor_console(Some(dir.path()));
    let lines = screen(&mut again, 80, 24);
    let banner = lines
        .iter()
        .find(|l| l.contains("recovered unsaved"))
        .unwrap_or_else(|| panic!("{}", lines.join("\n")));
    assert!(
        banner.contains("F2 to save, or discard with Esc"),
        "{banner}"
    );
}

/// The editor's title for an untitled text in `tool`'s language.
fn untitled_title(tool: &dyn axterm::protocol::program::ProgramTool, changed: &str) -> String {
    let first = axterm::ui::editor::language::default_tool().expect("a tool");
    if first.name() == tool.name() {
        format!("Program — untitled{changed}")
    } else {
        format!("Program ({}) — untitled{changed}", tool.name())
    }
}

/// A snapshot of a connected module of `family`.
fn connected(family: &'static axterm::protocol::Family) -> axterm::ui::pane::Snapshot {
    axterm::ui::pane::Snapshot {
        family,
        ..ui_support::snapshot(family.console.axes().to_vec())
    }
}

/// Esc on a recovered copy in another family's language, with a module
/// connected: the empty text is the connected family's again, not the
/// copy's (issue 19, point 7), for every family with programs.
#[test]
fn after_esc_on_a_recovered_copy_the_text_follows_the_connection_again() {
    for family in axterm::families::FAMILIES {
        let Some(own) = family.console.program() else {
            continue;
        };
        let tools = axterm::ui::editor::language::registered_tools();
        let other = tools
            .iter()
            .find(|t| t.name() != own.name())
            .expect("another language");
        let dir = tempfile::tempdir().expect("temp dir");
        let copy = axterm::ui::editor::autosave::Autosave::now(None, "some text".into())
            .in_language(other.name());
        axterm::ui::editor::autosave::write_autosave(dir.path(), &copy).expect("written");
        let mut app = editor_console(Some(dir.path()));
        app.handle(AppEvent::Snapshot(connected(family)));
        let all = screen(&mut app, 150, 40).join("\n");
        assert!(all.contains(&untitled_title(*other, "*")), "{all}");
        app.handle(key(KeyCode::Esc));
        let all = screen(&mut app, 150, 40).join("\n");
        assert!(all.contains("recovered text discarded"), "{all}");
        assert!(
            all.contains(&untitled_title(own, "")),
            "{}: the text is {} again:\n{all}",
            family.name,
            own.name()
        );
    }
}

/// Text switched to another language with the language key comes back
/// in that language at the next start, whichever it is (issue 19,
/// point 7).
#[test]
fn text_switched_to_another_language_comes_back_in_it() {
    let tools = axterm::ui::editor::language::registered_tools();
    for tool in tools.iter().skip(1) {
        let dir = tempfile::tempdir().expect("temp dir");
        let mut app = editor_console(Some(dir.path()));
        let effects = type_program(&mut app, "MVP ABS, 0, 1");
        timers_due(&mut app, &effects);
        for _ in 0..tools.len() {
            let all = screen(&mut app, 150, 40).join("\n");
            if all.contains(&untitled_title(*tool, "*")) {
                break;
            }
            app.handle(key_with(KeyCode::Char('l'), KeyModifiers::CONTROL));
        }
        let again = &mut editor_console(Some(dir.path()));
        let all = screen(again, 150, 40).join("\n");
        assert!(all.contains(&untitled_title(*tool, "*")), "{all}");
        assert_eq!(
            read_autosave(dir.path())
                .and_then(|c| c.language)
                .as_deref(),
            Some(tool.name())
        );
    }
}

/// A line that does not check, in each family's program language.
fn bad_line(family: &str) -> &'static str {
    match family {
        // An unknown word is a comment in an SQPack macro file.
        "sixpack2" => "SendToPack(1,2,3",
        _ => "§§§ 1",
    }
}

/// F9's error about a line, then the line deleted: the error goes with
/// it (issue 19, point 9), in every family's language.
#[test]
fn an_error_message_goes_when_its_line_is_deleted() {
    for family in axterm::families::FAMILIES {
        let mut app = editor_console(None);
        app.handle(AppEvent::Snapshot(connected(family)));
        let line = bad_line(family.name);
        type_program(&mut app, line);
        app.handle(key(KeyCode::F(9)));
        let shown = screen(&mut app, 100, 30);
        let message = shown[shown.len() - 3]
            .trim_matches(|c| c == '│' || c == ' ')
            .to_string();
        assert!(!message.is_empty(), "{}: {}", family.name, shown.join("\n"));
        // F9 put the cursor on the error: from the end of the line, back.
        app.handle(key(KeyCode::End));
        for _ in line.chars() {
            app.handle(key(KeyCode::Backspace));
        }
        let all = screen(&mut app, 100, 30).join("\n");
        assert!(
            !all.contains(&message),
            "{}: {message:?} stayed:\n{all}",
            family.name
        );
    }
}

#[test]
fn save_as_over_another_existing_file_is_refused_unless_forced() {
    let dir = tempfile::tempdir().expect("temp dir");
    let other = dir.path().join("other.tmc");
    std::fs::write(&other, "ROL 0, 100\n").expect("write");
    let mut app = editor_console(None);
    type_program(&mut app, "MVP ABS, 0, 1");
    // F2 without a file asks for a name; an existing one is refused.
    app.handle(key(KeyCode::F(2)));
    app.handle(AppEvent::Terminal(ratatui::crossterm::event::Event::Paste(
        other.display().to_string(),
    )));
    app.handle(key(KeyCode::Enter));
    assert_eq!(
        std::fs::read_to_string(&other).expect("kept"),
        "ROL 0, 100\n"
    );
    let lines = screen(&mut app, 200, 50);
    assert!(
        lines
            .iter()
            .any(|l| l.contains("give --force to replace it")),
        "{}",
        lines.join("\n")
    );
    // `--force FILE` replaces it.
    app.handle(key(KeyCode::F(2)));
    app.handle(AppEvent::Terminal(ratatui::crossterm::event::Event::Paste(
        format!("--force {}", other.display()),
    )));
    app.handle(key(KeyCode::Enter));
    assert_eq!(
        std::fs::read_to_string(&other).expect("saved"),
        "MVP ABS, 0, 1"
    );
    // Its own file is saved over without asking.
    type_program(&mut app, "\nSTOP");
    app.handle(key(KeyCode::F(2)));
    assert_eq!(
        std::fs::read_to_string(&other).expect("saved"),
        "MVP ABS, 0, 1\nSTOP"
    );
}
