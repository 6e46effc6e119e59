//! The command pane inside the console, driven by keys and replies as the
//! event loop would deliver them, drawn with ratatui's TestBackend.

mod fifo_support;
mod ui_support;

use std::time::Duration;

use axterm::files::Existing;
use axterm::protocol::console::{ReplyError, ReplyValue};
use axterm::session::run_end::{LinkAtStop, RunAftermath, RunEnding, RunStop, StopOnFailure};
use axterm::session::{LineResult, SessionError};
use axterm::ui::PaneSetup;
use axterm::ui::app::{App, AppEvent, Effect};
use ratatui::crossterm::event::KeyCode;
use ui_support::{axes, console, console_with, key, screen, snapshot, type_text};

fn connected() -> App {
    let mut app = console();
    app.handle(AppEvent::Snapshot(snapshot(axes(&["motor 0"]))));
    app
}

/// Type a line and press Enter; the effects.
fn enter(app: &mut App, line: &str) -> Vec<Effect> {
    let mut effects = type_text(app, line);
    effects.extend(app.handle(key(KeyCode::Enter)));
    effects
}

/// The pane and tag of the one line sent.
fn sent(effects: &[Effect]) -> (usize, u64, Vec<String>) {
    match effects {
        [Effect::Send { pane, tag, lines }] => (*pane, *tag, lines.clone()),
        other => panic!("expected one Send, got {other:?}"),
    }
}

fn ok(line: &str, value: ReplyValue) -> Result<LineResult, SessionError> {
    Ok(LineResult {
        line: line.into(),
        request: vec![0x01, 0x04, 0x00, 0x00, 0x00, 0x00, 0xC8, 0x00, 0xCD],
        reply: vec![0x02, 0x01, 0x64, 0x04, 0x00, 0x00, 0xC8, 0x00, 0x33],
        status: Some(100),
        value,
        elapsed: Duration::from_millis(3),
        attempts: 1,
    })
}

fn text(app: &mut App, width: u16, height: u16) -> String {
    screen(app, width, height).join("\n")
}

#[test]
fn a_typed_line_is_sent_and_its_answer_shown_with_status_meaning_and_bytes() {
    let mut app = connected();
    let (pane, tag, lines) = sent(&enter(&mut app, "MVP ABS, 0, 51200"));
    assert_eq!(lines, ["MVP ABS, 0, 51200"]);
    app.handle(AppEvent::Reply {
        pane,
        tag,
        line: "MVP ABS, 0, 51200".into(),
        result: ok("MVP ABS, 0, 51200", ReplyValue::None),
    });
    let screen = text(&mut app, 80, 24);
    assert!(screen.contains("> MVP ABS, 0, 51200"), "{screen}");
    assert!(
        screen.contains("ok  (status 100: successfully executed, no error)"),
        "{screen}"
    );
    assert!(
        screen.contains("sent 01 04 00 00 00 00 C8 00 CD  got 02 01 64 04 00 00 C8 00 33"),
        "{screen}"
    );
}

#[test]
fn errors_are_shown_in_plain_words() {
    let mut app = connected();
    let (pane, tag, _) = sent(&enter(&mut app, "SAP 6, 0, 200"));
    app.handle(AppEvent::Reply {
        pane,
        tag,
        line: "SAP 6, 0, 200".into(),
        result: Err(SessionError::Reply {
            error: Box::new(ReplyError::Rejected {
                module: "module 1".into(),
                line: "SAP 6, 0, 200".into(),
                status: 4,
                meaning: "invalid value".into(),
            }),
            request: vec![1, 5, 6, 0, 0, 0, 0, 200, 212],
            reply: vec![2, 1, 4, 5, 0, 0, 0, 200, 212],
            elapsed: Duration::ZERO,
        }),
    });
    let (pane, tag, _) = sent(&enter(&mut app, "SAP 6, 0, 999"));
    app.handle(AppEvent::Reply {
        pane,
        tag,
        line: "SAP 6, 0, 999".into(),
        result: Err(SessionError::Refused {
            line: "SAP 6, 0, 999".into(),
            message: "SAP 6 (Maximum current): value 999 outside 0..255".into(),
        }),
    });
    let screen = text(&mut app, 100, 30);
    assert!(
        screen.contains("error: module 1 rejected SAP 6, 0, 200: invalid value (status 4)"),
        "{screen}"
    );
    assert!(
        screen.contains("not sent: SAP 6 (Maximum current): value 999 outside 0..255"),
        "{screen}"
    );
}

#[test]
fn tab_completes_mnemonics_symbols_and_parameters_from_the_catalogue() {
    let mut app = connected();
    type_text(&mut app, "ms");
    app.handle(key(KeyCode::Tab));
    assert!(
        text(&mut app, 80, 24).contains("> MST "),
        "a unique mnemonic completes"
    );
    app.handle(key(KeyCode::Esc));

    type_text(&mut app, "MVP ");
    app.handle(key(KeyCode::Tab));
    let screen = text(&mut app, 80, 24);
    assert!(
        screen.contains("ABS 0   REL 1   COORD 2"),
        "the choices are listed: {screen}"
    );
    app.handle(key(KeyCode::Tab));
    assert!(text(&mut app, 80, 24).contains("> MVP ABS"));
    app.handle(key(KeyCode::Tab));
    assert!(
        text(&mut app, 80, 24).contains("> MVP REL"),
        "Tab again takes the next"
    );
    app.handle(key(KeyCode::Esc));

    type_text(&mut app, "SAP maxim");
    app.handle(key(KeyCode::Tab));
    let screen = text(&mut app, 120, 30);
    assert!(screen.contains("4 Maximum positioning speed"), "{screen}");
    assert!(screen.contains("5 Maximum acceleration"), "{screen}");
}

/// Type `SAP 4, 0, 100`, F1 on the 4: the command's syntax and the
/// parameter's row are shown, the line stays to be finished; then Esc
/// and `:help MVP`. The screen after F1.
fn help_on_sap_4_and_mvp(app: &mut App) -> String {
    type_text(app, "SAP 4, 0, 100");
    for _ in 0..8 {
        app.handle(key(KeyCode::Left));
    }
    app.handle(key(KeyCode::F(1)));
    let screen = text(app, 120, 30);
    assert!(
        screen.contains("SAP <parameter>, <motor>, <value>   (§3.6.5, instruction 5)"),
        "{screen}"
    );
    assert!(
        screen.contains(
            "axis parameter 4 “Maximum positioning speed”: 1..2047 int (vel), access RWE"
        ),
        "{screen}"
    );
    assert!(screen.contains("> SAP 4, 0, 100"), "{screen}");
    app.handle(key(KeyCode::Esc));
    enter(app, ":help MVP");
    let after = text(app, 120, 30);
    assert!(
        after.contains("<mode>: ABS (0), REL (1), COORD (2)"),
        "{after}"
    );
    screen
}

#[test]
fn f1_explains_the_word_under_the_cursor_and_help_takes_topics() {
    let mut app = connected();
    let screen = help_on_sap_4_and_mvp(&mut app);
    assert!(!screen.contains("not connected"), "{screen}");
    enter(&mut app, ":help");
    // The key lines come last, on screen however long the list grows;
    // the list's first entries are a page or two up.
    let screen = text(&mut app, 120, 40);
    assert!(screen.contains("F12 stops every axis"), "{screen}");
    let mut screen = String::new();
    for _ in 0..2 {
        app.handle(key(KeyCode::PageUp));
        screen = text(&mut app, 120, 40);
        if screen.contains(":poll RATE") {
            break;
        }
    }
    assert!(screen.contains(":poll RATE"), "{screen}");
}

#[test]
fn history_is_kept_per_family_in_the_data_directory() {
    let dir = tempfile::tempdir().expect("temp dir");
    let setup = PaneSetup {
        history_dir: Some(dir.path().to_path_buf()),
    };
    let mut app = console_with(&setup);
    app.handle(AppEvent::Snapshot(snapshot(axes(&["motor 0"]))));
    enter(&mut app, "GAP 1, 0");
    enter(&mut app, "GAP 3, 0");
    let saved = std::fs::read_to_string(dir.path().join("history-tmcl.txt")).expect("history");
    assert_eq!(saved, "GAP 1, 0\nGAP 3, 0\n");

    // A new console remembers; Up goes back, Down comes forward again.
    let mut app = console_with(&setup);
    app.handle(AppEvent::Snapshot(snapshot(axes(&["motor 0"]))));
    type_text(&mut app, "draft");
    app.handle(key(KeyCode::Up));
    assert!(text(&mut app, 80, 24).contains("> GAP 3, 0"));
    app.handle(key(KeyCode::Up));
    assert!(text(&mut app, 80, 24).contains("> GAP 1, 0"));
    app.handle(key(KeyCode::Down));
    app.handle(key(KeyCode::Down));
    assert!(text(&mut app, 80, 24).contains("> draft"));
}

#[test]
fn console_commands_become_requests() {
    let mut app = console();
    let mut s = snapshot(axes(&["X", "Y", "Z", "U"]));
    s.poll = None;
    app.handle(AppEvent::Snapshot(s));
    let poll = enter(&mut app, ":poll 10");
    assert!(
        matches!(&poll[..], [Effect::Poll(Some(c))] if c.fast == Duration::from_millis(100)),
        "{poll:?}"
    );
    assert_eq!(enter(&mut app, ":poll off"), [Effect::Poll(None)]);
    enter(&mut app, ":axis z");
    assert_eq!(app.snapshot().map(|s| s.axis), Some(2));
    enter(&mut app, ":axis 3");
    assert_eq!(app.snapshot().map(|s| s.axis), Some(3));
    assert_eq!(enter(&mut app, ":address 3"), [Effect::SetAddress(3)]);
    assert_eq!(
        enter(&mut app, ":connect --sim tmcm1110"),
        [Effect::Connect(vec!["--sim".into(), "tmcm1110".into()])]
    );
    assert_eq!(
        enter(&mut app, ":log traffic.log"),
        [Effect::Log(Some(("traffic.log".into(), Existing::Refuse)))]
    );
    assert_eq!(
        enter(&mut app, ":log --force traffic.log"),
        [Effect::Log(Some(("traffic.log".into(), Existing::Replace)))]
    );
    // No name: one of the time, `axterm-YYYYMMDD-HHMMSS.log`, here.
    let logged = enter(&mut app, ":log");
    let [Effect::Log(Some((auto, Existing::Refuse)))] = logged.as_slice() else {
        panic!(":log alone logs");
    };
    let auto = auto.to_string_lossy().into_owned();
    let digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
    let stamp = auto
        .strip_prefix("axterm-")
        .and_then(|s| s.strip_suffix(".log"))
        .and_then(|s| s.split_once('-'));
    assert!(
        stamp.is_some_and(|(day, time)| day.len() == 8
            && time.len() == 6
            && digits(day)
            && digits(time)),
        "{auto}"
    );
    assert_eq!(enter(&mut app, ":stop"), [Effect::EmergencyStop]);
    // Nothing is asked for a command that is wrong; it says why.
    assert!(enter(&mut app, ":axis W").is_empty());
    assert!(enter(&mut app, ":poll fast").is_empty());
    assert!(enter(&mut app, ":bogus").is_empty());
    let screen = text(&mut app, 120, 40);
    assert!(
        screen.contains("no axis `W`: this module has 0 (X), 1 (Y), 2 (Z), 3 (U)"),
        "{screen}"
    );
    assert!(screen.contains(":poll needs a rate in Hz"), "{screen}");
    assert!(
        screen.contains("unknown console command `:bogus`"),
        "{screen}"
    );
    assert_eq!(enter(&mut app, ":quit"), [Effect::Quit]);
    assert!(app.should_quit());
}

#[test]
fn run_checks_the_whole_file_first_and_then_sends_line_after_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let bad = dir.path().join("bad.txt");
    std::fs::write(&bad, "GAP 1, 0\nSAP 6, 0, 100000\n").expect("write");
    let mut app = connected();
    assert!(enter(&mut app, &format!(":run {}", bad.display())).is_empty());
    let screen = text(&mut app, 160, 40);
    assert!(screen.contains("bad.txt:2: "), "{screen}");
    assert!(screen.contains("nothing was sent"), "{screen}");

    let good = dir.path().join("good.txt");
    std::fs::write(
        &good,
        "# move\n:echo homing\nSAP 4, 0, 1000\n:expect GAP 4, 0 == 1000\n",
    )
    .expect("write");
    let (pane, tag, lines) = sent(&enter(&mut app, &format!(":run {}", good.display())));
    assert_eq!(lines, ["SAP 4, 0, 1000"]);
    let next = app.handle(AppEvent::Reply {
        pane,
        tag,
        line: "SAP 4, 0, 1000".into(),
        result: ok("SAP 4, 0, 1000", ReplyValue::None),
    });
    let (pane, tag, lines) = sent(&next);
    assert_eq!(lines, ["GAP 4, 0"]);
    let done = app.handle(AppEvent::Reply {
        pane,
        tag,
        line: "GAP 4, 0".into(),
        result: ok("GAP 4, 0", ReplyValue::Number(999)),
    });
    // The failed run is ended by the session: the stop, by default.
    assert_eq!(
        done,
        [Effect::EndRun {
            pane,
            ending: RunEnding::Failed,
            policy: StopOnFailure::Stop
        }]
    );
    let screen = text(&mut app, 160, 40);
    assert!(screen.contains("homing"), "{screen}");
    assert!(
        screen.contains("good.txt:4: expected GAP 4, 0 == 1000, got 999"),
        "{screen}"
    );
    app.handle(AppEvent::RunEnded {
        pane,
        aftermath: RunAftermath::Stopped(RunStop {
            ending: RunEnding::Failed,
            lines: vec![
                ok("MST 0", ReplyValue::None),
                ok("STOPAPP", ReplyValue::None),
                ok("MST 0", ReplyValue::None),
            ],
            link: LinkAtStop::Up,
        }),
    });
    let screen = text(&mut app, 160, 40);
    for line in [
        "the run failed: stopping every axis:",
        "  MST 0 → ok",
        "  STOPAPP → ok",
        "stop confirmed: every stop line answered ok",
    ] {
        assert!(screen.contains(line), "{line}:\n{screen}");
    }
}

#[test]
fn a_wait_until_shows_one_line_that_follows_its_reads() {
    let mut app = connected();
    let (mut pane, mut tag, lines) = sent(&enter(&mut app, ":wait-until GAP 8, 0 == 1 timeout 1m"));
    assert_eq!(lines, ["GAP 8, 0"]);
    for read in 1..=5 {
        let effects = app.handle(AppEvent::Reply {
            pane,
            tag,
            line: "GAP 8, 0".into(),
            result: ok("GAP 8, 0", ReplyValue::Number(0)),
        });
        let [
            Effect::Wake {
                pane: p, tag: t, ..
            },
        ] = effects.as_slice()
        else {
            panic!("read {read}: {effects:?}");
        };
        let screen = text(&mut app, 120, 40);
        let shown: Vec<&str> = screen.lines().filter(|l| l.contains("GAP 8, 0")).collect();
        // The line typed, and one line of how the wait stands.
        assert_eq!(shown.len(), 2, "read {read}:\n{screen}");
        let reads = if read == 1 {
            "1 read".to_string()
        } else {
            format!("{read} reads")
        };
        assert!(
            shown[1].contains(&format!("> :wait-until GAP 8, 0 == 1: 0 ({reads})")),
            "{screen}"
        );
        assert!(
            !screen.contains("status 100"),
            "no answer rows per read:\n{screen}"
        );
        (pane, tag, _) = sent(&app.handle(AppEvent::Wake { pane: *p, tag: *t }));
    }
    let done = app.handle(AppEvent::Reply {
        pane,
        tag,
        line: "GAP 8, 0".into(),
        result: ok("GAP 8, 0", ReplyValue::Number(1)),
    });
    assert!(done.is_empty(), "{done:?}");
    let screen = text(&mut app, 120, 40);
    let shown: Vec<&str> = screen.lines().filter(|l| l.contains("GAP 8, 0")).collect();
    assert_eq!(shown.len(), 2, "{screen}");
    assert!(shown[1].contains(": 1 (6 reads)"), "{screen}");
    // Something else said: the next wait starts a line of its own.
    let (pane, tag, _) = sent(&enter(&mut app, ":wait-until GAP 8, 0 == 1 timeout 1m"));
    app.handle(AppEvent::Reply {
        pane,
        tag,
        line: "GAP 8, 0".into(),
        result: ok("GAP 8, 0", ReplyValue::Number(1)),
    });
    let screen = text(&mut app, 120, 40);
    assert_eq!(
        screen.lines().filter(|l| l.contains("(1 read)")).count(),
        1,
        "{screen}"
    );
    assert!(screen.contains(": 1 (6 reads)"), "{screen}");
}

#[test]
fn a_run_cancelled_with_esc_or_told_to_leave_the_axes_says_so_to_the_session() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("moves.txt");
    std::fs::write(&file, "MVP ABS, 0, 51200\n:wait-until GAP 8, 0 == 1\n").expect("write");
    let mut app = connected();
    let (pane, _, _) = sent(&enter(&mut app, &format!(":run {}", file.display())));
    assert_eq!(
        app.handle(key(KeyCode::Esc)),
        [Effect::EndRun {
            pane,
            ending: RunEnding::Cancelled,
            policy: StopOnFailure::Stop
        }]
    );
    // Nothing runs any more: Esc clears the line as before.
    assert!(app.handle(key(KeyCode::Esc)).is_empty());

    sent(&enter(
        &mut app,
        &format!(":run --no-stop-on-failure {}", file.display()),
    ));
    assert_eq!(
        app.handle(key(KeyCode::Esc)),
        [Effect::EndRun {
            pane,
            ending: RunEnding::Cancelled,
            policy: StopOnFailure::Leave
        }]
    );
    app.handle(AppEvent::RunEnded {
        pane,
        aftermath: RunAftermath::Left(RunEnding::Cancelled),
    });
    let screen = text(&mut app, 160, 40);
    assert!(
        screen.contains(
            "the run was cancelled: the axes were left as they are (--no-stop-on-failure)"
        ),
        "{screen}"
    );

    // A directive typed alone is a check by hand: it stops nothing.
    let (pane, tag, _) = sent(&enter(&mut app, ":expect GAP 4, 0 == 5"));
    let done = app.handle(AppEvent::Reply {
        pane,
        tag,
        line: "GAP 4, 0".into(),
        result: ok("GAP 4, 0", ReplyValue::Number(4)),
    });
    assert!(done.is_empty(), "{done:?}");
}

#[test]
fn run_refuses_a_file_that_is_not_a_regular_one_without_reading_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Were it read, its line would be sent.
    let fifo = fifo_support::Fifo::new(dir.path().join("batch.txt"), "GAP 1, 0\n");
    let mut app = connected();
    assert!(enter(&mut app, &format!(":run {}", fifo.path.display())).is_empty());
    let screen = text(&mut app, 160, 40);
    assert!(
        screen.contains("batch.txt: it is a FIFO (named pipe), not a regular file"),
        "{screen}"
    );
    drop(fifo);
    assert!(enter(&mut app, ":run /dev/zero").is_empty());
    let screen = text(&mut app, 160, 40);
    assert!(
        screen.contains("cannot read /dev/zero: it is a character device, not a regular file"),
        "{screen}"
    );
}

#[test]
fn the_emergency_stop_drops_a_running_batch_and_confirms_what_was_sent() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("moves.txt");
    std::fs::write(&file, "MVP ABS, 0, 51200\nMVP ABS, 0, 0\n").expect("write");
    let mut app = connected();
    let (pane, tag, _) = sent(&enter(&mut app, &format!(":run {}", file.display())));
    assert_eq!(app.handle(key(KeyCode::F(12))), [Effect::EmergencyStop]);
    // Had the first move's answer come after all, the batch goes no further.
    let late = app.handle(AppEvent::Reply {
        pane,
        tag,
        line: "MVP ABS, 0, 51200".into(),
        result: ok("MVP ABS, 0, 51200", ReplyValue::None),
    });
    assert!(late.is_empty(), "{late:?}");
    app.handle(AppEvent::Stopped(vec![
        ok("MST 0", ReplyValue::None),
        ok("STOPAPP", ReplyValue::None),
        ok("MST 0", ReplyValue::None),
    ]));
    let screen = text(&mut app, 100, 40);
    assert!(
        screen.contains("F12 EMERGENCY STOP: stopping every axis and any running program"),
        "{screen}"
    );
    assert!(screen.contains("the batch was stopped"), "{screen}");
    assert!(
        screen.contains("sent MST 0") && screen.contains("sent STOPAPP"),
        "{screen}"
    );
    assert!(
        screen.contains("STOP confirmed: every stop line answered ok"),
        "{screen}"
    );
    assert!(
        screen.contains("STOP: 3 sent, all ok"),
        "the status bar says so too: {screen}"
    );
}

#[test]
fn a_line_typed_without_a_connection_says_how_to_connect() {
    let mut app = console();
    assert!(enter(&mut app, "GAP 1, 0").is_empty());
    let screen = text(&mut app, 80, 24);
    assert!(
        screen.contains("not connected: `:connect --sim tmcm1110`"),
        "{screen}"
    );
}

#[test]
fn news_from_the_module_and_the_link_is_shown() {
    let mut app = connected();
    app.handle(AppEvent::Device(axterm::device::DeviceEvent::Unsolicited {
        frame: vec![2, 1, 128, 138, 0, 0, 0, 1, 12],
        description: "motor 0 reached its target (138)".into(),
    }));
    app.handle(AppEvent::Device(axterm::device::DeviceEvent::StateChanged(
        axterm::device::LinkState::Disconnected {
            reason: "/dev/ttyUSB0 unplugged".into(),
            attempts: 0,
            retry_in: Duration::from_millis(400),
        },
    )));
    let screen = text(&mut app, 100, 30);
    assert!(
        screen.contains("module: motor 0 reached its target (138)"),
        "{screen}"
    );
    assert!(
        screen.contains("link lost: /dev/ttyUSB0 unplugged; trying again in 400 ms"),
        "{screen}"
    );
}

/// A port that vanishes says so, each failed reopening rewrites one line
/// (not a line per attempt), and the reconnection is told apart from a
/// first opening.
#[test]
fn a_vanished_port_and_its_reconnection_are_shown() {
    use axterm::device::{DeviceEvent, LinkState};
    let mut app = connected();
    let state = |state| AppEvent::Device(DeviceEvent::StateChanged(state));
    app.handle(state(LinkState::Disconnected {
        reason: "/dev/ttyUSB0 at 9600 Bd: the port vanished: /dev/ttyUSB0 is gone (unplugged?)"
            .into(),
        attempts: 0,
        retry_in: Duration::from_millis(100),
    }));
    for (attempts, retry_in) in [(1, 200), (2, 400)] {
        app.handle(state(LinkState::Disconnected {
            reason: "cannot open /dev/ttyUSB0 at 9600 Bd: no such port".into(),
            attempts,
            retry_in: Duration::from_millis(retry_in),
        }));
    }
    let screen = text(&mut app, 120, 30);
    assert!(
        screen.contains("link lost: /dev/ttyUSB0 at 9600 Bd: the port vanished"),
        "{screen}"
    );
    assert!(
        screen.contains(
            "reconnect attempt 2 failed: cannot open /dev/ttyUSB0 at 9600 Bd: no such port; \
             trying again in 400 ms"
        ),
        "{screen}"
    );
    assert!(
        !screen.contains("reconnect attempt 1"),
        "rewritten: {screen}"
    );
    // The status bar, from the session's snapshot.
    app.handle(AppEvent::Snapshot(axterm::ui::pane::Snapshot {
        link: LinkState::Disconnected {
            reason: "cannot open /dev/ttyUSB0 at 9600 Bd: no such port".into(),
            attempts: 2,
            retry_in: Duration::from_millis(400),
        },
        ..snapshot(axes(&["motor 0"]))
    }));
    let screen = text(&mut app, 160, 30);
    assert!(
        screen.contains("LOST, reconnecting (attempt 2 failed): cannot open /dev/ttyUSB0"),
        "the status bar: {screen}"
    );
    app.handle(state(LinkState::Connected {
        link: "/dev/ttyUSB0 at 9600 Bd".into(),
    }));
    let screen = text(&mut app, 120, 30);
    assert!(
        screen.contains("reconnected: link /dev/ttyUSB0 at 9600 Bd open again (attempt 3)"),
        "{screen}"
    );
    assert!(
        screen.contains("reconnect attempt 2 failed"),
        "the attempts stay in the history: {screen}"
    );
}

/// Before connecting (the connect screen, a link not yet open), help and
/// completion come from the tables of the family the connect screen
/// offers first: with no recent connection, its first simulator's, TMCL.
#[test]
fn help_and_completion_work_before_connecting() {
    let mut app = console();
    assert!(app.snapshot().is_none());
    let screen = help_on_sap_4_and_mvp(&mut app);
    assert!(
        screen.contains("not connected: help from the tmcl tables"),
        "{screen}"
    );

    // Tab: mnemonics, and inside `:help`.
    type_text(&mut app, "ms");
    app.handle(key(KeyCode::Tab));
    assert!(text(&mut app, 80, 24).contains("> MST "));
    app.handle(key(KeyCode::Esc));
    type_text(&mut app, ":help SAP maxim");
    app.handle(key(KeyCode::Tab));
    let screen = text(&mut app, 120, 30);
    assert!(screen.contains("4 Maximum positioning speed"), "{screen}");
    app.handle(key(KeyCode::Esc));

    // The syntax of the command being typed shows above the prompt.
    enter(&mut app, ":echo the output ends here");
    type_text(&mut app, "MVP");
    let lines = ui_support::screen(&mut app, 120, 30);
    let prompt = lines
        .iter()
        .position(|l| l.starts_with("│> MVP "))
        .expect("the prompt");
    assert!(
        lines[prompt - 1].starts_with("│MVP ABS|REL|COORD, <motor>"),
        "{}",
        lines.join("\n")
    );
    app.handle(key(KeyCode::Esc));

    // Sending still needs a connection.
    assert!(enter(&mut app, "MST 0").is_empty());
    assert!(text(&mut app, 100, 30).contains("not connected: `:connect"));
}

/// After the link is gone, help stays with the family last connected,
/// and says it is not connected.
#[test]
fn help_after_disconnecting_comes_from_the_family_last_connected() {
    let mut app = connected();
    app.handle(AppEvent::Disconnected);
    assert!(app.snapshot().is_none());
    enter(&mut app, ":help GAP 4");
    let screen = text(&mut app, 120, 30);
    assert!(
        screen.contains("not connected: help from the tmcl tables"),
        "{screen}"
    );
    assert!(screen.contains("Maximum positioning speed"), "{screen}");
}

/// The console connected to a module of `family`.
fn connected_to(family: &str) -> App {
    let mut app = console();
    let family = axterm::families::find_family(family).expect("registered");
    app.handle(AppEvent::Snapshot(axterm::ui::pane::Snapshot {
        family,
        ..snapshot(family.console.axes().to_vec())
    }));
    app
}

/// F1 on a word that only begins a command: the commands it may be, each
/// once (the syntax hint under them repeated the first; issue 19,
/// point 9).
#[test]
fn f1_on_the_start_of_a_word_lists_each_command_once() {
    let mut app = connected_to("sixpack2");
    type_text(&mut app, "StartR");
    app.handle(key(KeyCode::F(1)));
    let screen = text(&mut app, 100, 30);
    assert_eq!(
        screen.matches("StartReferenceSearch motno").count(),
        1,
        "{screen}"
    );
    assert!(screen.contains("StartRampParallel motors"), "{screen}");
    // Typing on: the hint is back for the line as it is now.
    type_text(&mut app, "eferenceSearch 0");
    let screen = text(&mut app, 100, 30);
    assert_eq!(
        screen.matches("StartReferenceSearch motno").count(),
        2,
        "the help above and the hint under it: {screen}"
    );
}

/// Help wraps between words, on every family's console (issue 19,
/// point 9: `until of│f`).
#[test]
fn help_wraps_between_words() {
    let words = "record every line sent from here as a macro file of the module's program \
                 language, until off";
    for family in axterm::families::FAMILIES {
        for width in [60, 70, 80, 90] {
            let mut app = connected_to(family.name);
            enter(&mut app, ":help :record-macro");
            let screen = text(&mut app, width, 30);
            for word in words.split([' ', ',']).filter(|w| !w.is_empty()) {
                assert!(
                    screen.contains(word),
                    "{} at {width} columns, `{word}` cut: {screen}",
                    family.name
                );
            }
        }
    }
}

/// Issue 19 point 15: a value read from a family whose answers carry no
/// checksum is marked so under its line; a checked family's is not.
#[test]
fn a_value_read_without_a_checksum_is_marked_unchecked() {
    use axterm::families::FAMILIES;
    for family in FAMILIES {
        let mut app = console();
        let mut shot = snapshot(axes(&["motor 0"]));
        shot.family = family;
        app.handle(AppEvent::Snapshot(shot));
        // The family's identity read (a line that parses), answered by
        // hand with a value.
        let typed = family.console.identify(1).canonical;
        let (pane, tag, _) = sent(&enter(&mut app, &typed));
        app.handle(AppEvent::Reply {
            pane,
            tag,
            line: typed.clone(),
            result: ok(&typed, ReplyValue::Number(12)),
        });
        let screen = text(&mut app, 120, 24);
        assert_eq!(
            screen.contains("unchecked: no checksum"),
            !family.console.replies_checked(),
            "{}: {screen}",
            family.name
        );
    }
}
