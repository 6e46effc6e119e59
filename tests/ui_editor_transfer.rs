//! Download, verify and upload from the editor pane, driven with the
//! app's own events (what the loop would deliver from a session): what
//! the pane asks for, the progress bar at 80×24, the messages, the marks.
//! The same against the simulator through the real loop is in
//! `ui_editor_transfer_sim.rs`.

mod ui_support;

use std::time::Duration;

use axterm::protocol::program::{
    Fact, FactValue, Phase, Progress, ReadProgram, TransferFailure, TransferJob, TransferReport,
    UploadExtent,
};
use axterm::protocol::tmcl::asm::{NoIncludes, ProgramWord, assemble, disassemble, format_image};
use axterm::protocol::tmcl::plan::TransferError;
use axterm::ui::PaneSetup;
use axterm::ui::app::{App, AppEvent, Effect};
use ratatui::crossterm::event::{Event, KeyCode, KeyModifiers};
use ui_support::{axes, console_with, key, key_with, screen, snapshot};

/// Twelve words: eleven moves and STOP; word N is on line N+1.
fn program_text() -> String {
    let mut text: String = (0..11)
        .map(|i| format!("MVP ABS, 0, {}\n", i * 10))
        .collect();
    text.push_str("STOP");
    text
}

fn words(text: &str) -> Vec<ProgramWord> {
    match assemble("untitled.tmc", text, &NoIncludes) {
        Ok(p) => p.words,
        Err(e) => panic!("{e:?}"),
    }
}

/// A connected console, the editor focused, `text` in it.
fn editor_with(text: &str) -> App {
    let mut app = console_with(&PaneSetup::default());
    app.handle(AppEvent::Snapshot(snapshot(axes(&["motor 0"]))));
    assert!(app.focus("editor"));
    app.handle(AppEvent::Terminal(Event::Paste(text.to_string())));
    app
}

/// The transfer the pane asked for: its pane, tag and job.
fn transfer_of(effects: &[Effect]) -> (usize, u64, TransferJob) {
    effects
        .iter()
        .find_map(|e| match e {
            Effect::Transfer { pane, tag, job } => Some((*pane, *tag, job.clone())),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no transfer asked for: {effects:?}"))
}

fn progress(pane: usize, tag: u64, phase: Phase, done: usize, total: usize) -> AppEvent {
    AppEvent::TransferProgress {
        pane,
        tag,
        progress: Progress {
            phase,
            done,
            total: Some(total),
        },
    }
}

fn ended(pane: usize, tag: u64, result: Result<TransferReport, TransferFailure>) -> AppEvent {
    AppEvent::Transferred { pane, tag, result }
}

fn failed(error: TransferError) -> Result<TransferReport, TransferFailure> {
    Err(error.into())
}

/// A verified download of `words` words, as TMCL's plan reports it.
fn report(words: usize) -> TransferReport {
    let mut report = TransferReport::new(1, words);
    report.facts = vec![Fact {
        key: "stopped_program",
        value: FactValue::Absent,
        said: None,
        told: None,
    }];
    report
}

/// An upload of `words` from module 1.
fn uploaded(words: &[ProgramWord]) -> TransferReport {
    let mut report = TransferReport::new(1, words.len());
    report.program = Some(ReadProgram {
        source: disassemble(words),
        image: Some(format_image(words)),
        units: words.len(),
    });
    report.elapsed = Duration::ZERO;
    report
}

fn row_with<'a>(lines: &'a [String], text: &str) -> Option<&'a String> {
    lines.iter().find(|l| l.contains(text))
}

#[test]
fn download_sends_the_assembled_words_and_shows_its_progress_at_80x24() {
    let text = program_text();
    let mut app = editor_with(&text);
    let effects = app.handle(key(KeyCode::F(4)));
    let (pane, tag, job) = transfer_of(&effects);
    let TransferJob::Download { program: sent, .. } = job else {
        panic!("{job:?}")
    };
    assert_eq!(sent.image(), Some(format_image(&words(&text))));

    // Before the first word: a bar at 0.
    let lines = screen(&mut app, 80, 24);
    let bar = row_with(&lines, "download: starting — Esc cancels").expect("the bar");
    assert!(!bar.contains('█'), "{bar}");

    // Half stored: the left half filled, the right not.
    app.handle(progress(pane, tag, Phase::Storing, 6, 12));
    let lines = screen(&mut app, 80, 24);
    let bar = row_with(&lines, "download: storing 6/12 words — Esc cancels")
        .unwrap_or_else(|| panic!("{}", lines.join("\n")));
    let cells: Vec<char> = bar.chars().collect();
    // Inside the border: 78 cells, 39 filled (the label over the middle).
    assert_eq!(cells.get(1), Some(&'█'), "{bar}");
    assert_eq!(cells.get(10), Some(&'█'), "{bar}");
    assert_eq!(cells.get(77), Some(&' '), "{bar}");
    // Between the text and the bottom line.
    let bar_row = lines.iter().position(|l| l == bar).expect("bar row");
    let stop_row = lines
        .iter()
        .position(|l| l.contains(" 12 STOP"))
        .expect("STOP");
    assert!(stop_row < bar_row, "{}", lines.join("\n"));
    assert!(lines[bar_row + 2].starts_with("└"), "{}", lines.join("\n"));

    app.handle(progress(pane, tag, Phase::Verifying, 12, 12));
    let lines = screen(&mut app, 80, 24);
    let bar = row_with(&lines, "download: verifying 12/12 words").expect("verifying");
    assert_eq!(bar.chars().nth(77), Some('█'), "{bar}");

    app.handle(ended(pane, tag, Ok(report(12))));
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(all.contains("downloaded and verified 12 words"), "{all}");
    assert!(!all.contains("verifying 12/12"), "the bar is gone: {all}");
}

#[test]
fn a_program_that_does_not_assemble_is_not_sent() {
    let mut app = editor_with("MVP ABS, 0, 1\nMVP SIDEWAYS, 0, 1\nSTOP");
    let effects = app.handle(key(KeyCode::F(4)));
    assert!(
        !effects.iter().any(|e| matches!(e, Effect::Transfer { .. })),
        "{effects:?}"
    );
    let lines = screen(&mut app, 80, 24);
    let all = lines.join("\n");
    assert!(all.contains("does not assemble, nothing was sent"), "{all}");
    let marked = row_with(&lines, "MVP SIDEWAYS").expect("line 2");
    assert!(marked.contains("!  2"), "{marked}");
    // Verify refuses the same way.
    let effects = app.handle(key_with(KeyCode::F(4), KeyModifiers::SHIFT));
    assert!(!effects.iter().any(|e| matches!(e, Effect::Transfer { .. })));
}

#[test]
fn without_a_connection_nothing_is_asked() {
    let mut app = console_with(&PaneSetup::default());
    app.focus("editor");
    app.handle(AppEvent::Terminal(Event::Paste("STOP".into())));
    let effects = app.handle(key(KeyCode::F(4)));
    assert!(!effects.iter().any(|e| matches!(e, Effect::Transfer { .. })));
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(all.contains("not connected"), "{all}");
}

#[test]
fn a_failed_verification_names_the_address_and_marks_its_line() {
    let text = program_text();
    let mut app = editor_with(&text);
    let (pane, tag, _) = transfer_of(&app.handle(key(KeyCode::F(4))));
    let wrote = words(&text)[4];
    let read = ProgramWord {
        value: wrote.value ^ 1,
        ..wrote
    };
    app.handle(ended(
        pane,
        tag,
        failed(TransferError::Mismatch {
            address: 4,
            wrote,
            read,
        }),
    ));
    for (w, h) in [(80, 24), (200, 50)] {
        let lines = screen(&mut app, w, h);
        let all = lines.join("\n");
        assert!(
            all.contains("download failed at source line 5: word 4 differs: wrote MVP ABS, 0, 40"),
            "{all}"
        );
        let marked = row_with(&lines, "MVP ABS, 0, 40").expect("line 5");
        assert!(marked.contains("✗  5"), "{marked}");
        let other = row_with(&lines, "MVP ABS, 0, 30").expect("line 4");
        assert!(!other.contains('✗'), "{other}");
    }
    // Editing forgets the mark.
    app.handle(key(KeyCode::End));
    app.handle(key(KeyCode::Char(' ')));
    let lines = screen(&mut app, 80, 24);
    assert!(
        !lines.iter().any(|l| l.contains('✗')),
        "{}",
        lines.join("\n")
    );
}

#[test]
fn esc_cancels_and_the_text_is_locked_until_the_end() {
    let text = program_text();
    let mut app = editor_with(&text);
    let (pane, tag, _) = transfer_of(&app.handle(key(KeyCode::F(4))));
    app.handle(progress(pane, tag, Phase::Storing, 3, 12));
    // Typing does nothing to the text while the download runs.
    app.handle(key(KeyCode::Char('x')));
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(
        all.contains("the text is locked while the download runs"),
        "{all}"
    );
    assert!(!all.contains("STOPx"), "{all}");
    // A second download is not started.
    let effects = app.handle(key(KeyCode::F(4)));
    assert!(!effects.iter().any(|e| matches!(e, Effect::Transfer { .. })));
    // Esc asks to cancel, once.
    assert_eq!(app.handle(key(KeyCode::Esc)), [Effect::CancelTransfer]);
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(
        all.contains("download: storing 3/12 words — cancelling…"),
        "{all}"
    );
    assert!(app.handle(key(KeyCode::Esc)).is_empty());
    app.handle(ended(
        pane,
        tag,
        failed(TransferError::Cancelled {
            phase: Phase::Storing,
            done: 3,
            total: Some(12),
        }),
    ));
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(
        all.contains("cancelled: the module left download mode"),
        "{all}"
    );
    // Unlocked again.
    app.handle(key(KeyCode::Char('x')));
    assert!(screen(&mut app, 80, 24).join("\n").contains("STOPx"));
}

#[test]
fn the_emergency_stop_marks_the_transfer_as_cancelling() {
    let mut app = editor_with(&program_text());
    let (pane, tag, _) = transfer_of(&app.handle(key(KeyCode::F(4))));
    app.handle(progress(pane, tag, Phase::Storing, 3, 12));
    // The app stops; the session cancels the download itself.
    assert_eq!(app.handle(key(KeyCode::F(12))), [Effect::EmergencyStop]);
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(all.contains("cancelling…"), "{all}");
}

#[test]
fn verify_reads_back_as_many_words_and_reports_the_first_difference() {
    let text = program_text();
    let mut app = editor_with(&text);
    let effects = app.handle(key_with(KeyCode::F(4), KeyModifiers::SHIFT));
    let (pane, tag, job) = transfer_of(&effects);
    let TransferJob::Verify { program } = job else {
        panic!("{job:?}")
    };
    assert_eq!(program.image(), Some(format_image(&words(&text))));
    let module = words(&text);
    app.handle(ended(pane, tag, Ok(TransferReport::new(1, 12))));
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(
        all.contains("verified: module 1 holds these 12 words"),
        "{all}"
    );

    let held = ProgramWord {
        value: 999,
        ..module[7]
    };
    let (pane, tag, _) = transfer_of(&app.handle(key_with(KeyCode::F(4), KeyModifiers::SHIFT)));
    app.handle(ended(
        pane,
        tag,
        failed(TransferError::Differs {
            module: 1,
            address: 7,
            held,
            expected: module[7],
        }),
    ));
    let lines = screen(&mut app, 200, 50);
    let all = lines.join("\n");
    assert!(
        all.contains(
            // (cut at the pane's width)
            "verify failed at source line 8: word 7 differs: module 1 holds MVP ABS, 0, 999, \
             the source has MVP ABS, 0, 7"
        ),
        "{all}"
    );
    let marked = row_with(&lines, "MVP ABS, 0, 70").expect("line 8");
    assert!(marked.contains("✗  8"), "{marked}");
}

#[test]
fn upload_asks_before_replacing_unsaved_text_and_opens_a_new_buffer() {
    let mut app = editor_with("ROL 0, 5");
    let upload = || key_with(KeyCode::F(4), KeyModifiers::CONTROL);
    let effects = app.handle(upload());
    assert!(!effects.iter().any(|e| matches!(e, Effect::Transfer { .. })));
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(
        all.contains("unsaved changes: F2 saves them; Ctrl-F4 again uploads over them"),
        "{all}"
    );
    let (pane, tag, job) = transfer_of(&app.handle(upload()));
    assert_eq!(job, TransferJob::Upload(UploadExtent::UntilBlank));
    let text = program_text();
    app.handle(ended(pane, tag, Ok(uploaded(&words(&text)))));
    let all = screen(&mut app, 200, 50).join("\n");
    assert!(
        all.contains("uploaded 12 words from module 1 into a new unsaved buffer"),
        "{all}"
    );
    assert!(all.contains("Program — untitled*"), "{all}");
    assert!(!all.contains("ROL 0, 5"), "{all}");
    assert!(
        all.contains("MVP ABS, 0, 100") && all.contains("STOP"),
        "{all}"
    );
}

#[test]
fn an_empty_module_leaves_the_text_alone() {
    let mut app = editor_with("");
    let (pane, tag, _) = transfer_of(&app.handle(key_with(KeyCode::F(4), KeyModifiers::CONTROL)));
    app.handle(ended(pane, tag, Ok(uploaded(&[]))));
    let all = screen(&mut app, 80, 24).join("\n");
    assert!(all.contains("module 1 holds no program"), "{all}");
}

/// The answer to one of the pane's lines, as the loop delivers it.
fn number_reply(pane: usize, tag: u64, line: &str, value: i64) -> AppEvent {
    AppEvent::Reply {
        pane,
        tag,
        line: line.into(),
        result: Ok(axterm::session::LineResult {
            line: line.into(),
            request: Vec::new(),
            reply: Vec::new(),
            status: Some(100),
            value: axterm::session::ReplyValue::Number(value),
            elapsed: Duration::ZERO,
            attempts: 1,
        }),
    }
}

/// The message timer the pane asked for, if any: its pane and tag.
fn message_timer(effects: &[Effect]) -> Option<(usize, u64)> {
    effects.iter().find_map(|e| match e {
        Effect::Wake { pane, tag, after } if *tag >= 1 << 47 && *tag < 1 << 48 => {
            assert_eq!(*after, axterm::ui::editor::MESSAGE_LIFETIME);
            Some((*pane, *tag))
        }
        _ => None,
    })
}

/// Issue: "downloaded and verified" stayed up through F5 while the
/// program's state waited behind it.
#[test]
fn the_programs_state_wins_over_an_older_message_and_messages_age_out() {
    let text = program_text();
    let mut app = editor_with(&text);
    let (pane, tag, _) = transfer_of(&app.handle(key(KeyCode::F(4))));
    let effects = app.handle(ended(pane, tag, Ok(report(12))));
    let downloaded_timer = message_timer(&effects).expect("the message ages out");
    let bottom = |app: &mut App| {
        let lines = screen(app, 80, 24);
        lines[lines.len() - 3].clone()
    };
    assert!(bottom(&mut app).contains("downloaded and verified"));
    // F5: the registers are read; once they come, they are what shows.
    let effects = app.handle(key(KeyCode::F(5)));
    let (pane, tag) = effects
        .iter()
        .filter_map(|e| match e {
            Effect::Send { pane, tag, lines } if lines.len() > 1 => Some((*pane, *tag)),
            _ => None,
        })
        .next()
        .expect("the register reads");
    for (line, value) in [
        ("GGP 128, 0", 1),
        ("GGP 130, 0", 1),
        ("APPSTATUS ACCU", 0),
        ("APPSTATUS X", 0),
    ] {
        app.handle(number_reply(pane, tag, line, value));
    }
    let line = bottom(&mut app);
    assert!(line.contains("running PC 1 ACC 0 X 0"), "{line}");
    assert!(!line.contains("downloaded"), "{line}");

    // A message newer than the state shows, then ages out.
    let effects = app.handle(key(KeyCode::F(9)));
    assert!(bottom(&mut app).contains("assembled: 12 words"));
    let (pane, timer) = message_timer(&effects).expect("the new message ages out");
    // The older message's timer takes nothing away.
    app.handle(AppEvent::Wake {
        pane: downloaded_timer.0,
        tag: downloaded_timer.1,
    });
    assert!(bottom(&mut app).contains("assembled: 12 words"));
    app.handle(AppEvent::Wake { pane, tag: timer });
    let line = bottom(&mut app);
    assert!(!line.contains("assembled"), "{line}");
    assert!(line.contains("running PC 1 ACC 0 X 0"), "{line}");
}
