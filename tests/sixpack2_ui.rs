//! The SIXpack 2 in the console's panes, with hand-made snapshots and the
//! family's own line preparation standing in for a session: the parameter
//! table shows what was written this session and what is unknown since a
//! reset, writes a setting together with the ones its frame carries,
//! exports and imports through the settings cache.

mod ui_support;

use std::sync::Arc;

use axterm::families::find_family;
use axterm::protocol::console::ReplyValue;
use axterm::protocol::settings::SettingsCache;
use axterm::session::{LineResult, SessionError};
use axterm::ui::app::{App, AppEvent, Effect};
use axterm::ui::pane::Snapshot;
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use std::time::Duration;
use ui_support::{console, key, key_with, screen, snapshot, type_text};

fn sixpack2_snapshot(settings: SettingsCache) -> Snapshot {
    let family = find_family("sixpack2").expect("sixpack2");
    Snapshot {
        family,
        address: 0,
        link_name: "sim sixpack2".into(),
        settings: Arc::new(settings),
        mechanics: Default::default(),
        ..snapshot(family.console.axes().to_vec())
    }
}

/// A console on a SIXpack 2 whose session knows `settings`.
fn connected(settings: SettingsCache) -> App {
    let mut app = console();
    app.handle(AppEvent::Snapshot(sixpack2_snapshot(settings)));
    app
}

/// What the session would record for `lines`, sent in order.
fn written(lines: &[&str]) -> SettingsCache {
    let console = find_family("sixpack2").expect("sixpack2").console;
    let mut cache = SettingsCache::default();
    for line in lines {
        let prepared = console.prepare(line, 0).expect("valid");
        cache.record(&console.settings_written(&prepared));
    }
    cache
}

/// Answer every line the console sends as a SIXpack 2 session does (a
/// setting is `sent`), and return them.
fn serve(app: &mut App, effects: Vec<Effect>) -> Vec<String> {
    let console = find_family("sixpack2").expect("sixpack2").console;
    let mut sent = Vec::new();
    let mut queue = effects;
    while !queue.is_empty() {
        let mut next = Vec::new();
        for effect in queue {
            if let Some((pane, tag, lines)) = effect.sends() {
                for line in lines {
                    let result = console
                        .prepare(&line, 0)
                        .map(|p| LineResult {
                            line: p.canonical.clone(),
                            request: p.bytes.clone(),
                            reply: Vec::new(),
                            status: None,
                            value: ReplyValue::Text("sent".into()),
                            elapsed: Duration::from_millis(5),
                            attempts: 1,
                        })
                        .map_err(|message| SessionError::Refused {
                            line: line.clone(),
                            message: message.to_string(),
                        });
                    sent.push(line.clone());
                    next.extend(app.handle(AppEvent::Reply {
                        pane,
                        tag,
                        line,
                        result,
                    }));
                }
            }
        }
        queue = next;
    }
    sent
}

fn params(app: &mut App) -> Vec<String> {
    let effects = app.handle(key_with(KeyCode::Char('3'), KeyModifiers::ALT));
    assert_eq!(app.focused(), Some("params"));
    serve(app, effects)
}

fn filter(app: &mut App, text: &str) {
    app.handle(key(KeyCode::Char('/')));
    type_text(app, text);
    app.handle(key(KeyCode::Enter));
}

fn row<'a>(lines: &'a [String], name: &str) -> &'a str {
    lines
        .iter()
        .find(|l| l.contains(&format!(" {name} ")))
        .unwrap_or_else(|| panic!("no row {name}:\n{}", lines.join("\n")))
}

#[test]
fn the_table_shows_what_was_written_this_session_and_what_is_unknown() {
    let mut app = connected(written(&["SetAMaxVMax 0 100 300"]));
    assert!(params(&mut app).is_empty(), "nothing can be read back");
    filter(&mut app, "max");
    let lines = screen(&mut app, 80, 24);
    assert!(row(&lines, "vmax").contains("300"), "{}", lines.join("\n"));
    assert!(row(&lines, "amax").contains("100"));
    assert!(
        row(&lines, "vrefmax").contains("not written"),
        "{}",
        lines.join("\n")
    );
    // The selected row (amax, the first) says where its value comes from.
    let all = lines.join("\n");
    assert!(
        all.contains("written this session, never read back"),
        "{all}"
    );

    // A reset: what was written is no longer known.
    let mut after = written(&["SetAMaxVMax 0 100 300"]);
    after.forget("HardwareReset was sent (§7.4)");
    app.handle(AppEvent::Snapshot(sixpack2_snapshot(after)));
    let lines = screen(&mut app, 140, 30);
    assert!(
        row(&lines, "vmax").contains("since reset"),
        "{}",
        lines.join("\n")
    );
    let all = lines.join("\n");
    assert!(
        all.contains("unknown since HardwareReset was sent (§7.4); 100 was written before"),
        "{all}"
    );
}

#[test]
fn a_setting_is_written_with_the_others_its_frame_carries_as_known() {
    let mut app = connected(written(&["SetAMaxVMax 0 100 300"]));
    params(&mut app);
    filter(&mut app, "vmax");
    // vmax: Enter edits, the field starts with the value known.
    app.handle(key(KeyCode::Enter));
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
    let effects = type_text(&mut app, "400");
    assert!(serve(&mut app, effects).is_empty());
    let effects = app.handle(key(KeyCode::Enter));
    assert_eq!(serve(&mut app, effects), ["SetAMaxVMax 0 100 400"]);
    let all = screen(&mut app, 100, 30).join("\n");
    assert!(all.contains("SetAMaxVMax 0 100 400: sent"), "{all}");

    // Without amax known, the table says what to type.
    let mut app = connected(SettingsCache::default());
    params(&mut app);
    filter(&mut app, "vmax");
    app.handle(key(KeyCode::Enter));
    type_text(&mut app, "400");
    let effects = app.handle(key(KeyCode::Enter));
    assert!(serve(&mut app, effects).is_empty(), "nothing sent");
    let all = screen(&mut app, 140, 30).join("\n");
    assert!(
        all.contains("vmax is written together with amax by SetAMaxVMax ($14)"),
        "{all}"
    );
    // The line to type and what became of the value are readable to
    // their end, wide or narrow: the message wraps, it is not cut.
    for width in [80, 200] {
        // The left pane's text, its lines joined: what is between the
        // first two borders of each screen line.
        let left: Vec<String> = screen(&mut app, width, 30)
            .iter()
            .filter_map(|line| line.split('│').nth(1).map(str::to_string))
            .collect();
        let all = left.join(" ");
        let all = all.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(
            all.contains("so type `SetAMaxVMax 0 AMAX 400` in the command pane: nothing sent"),
            "at {width} columns: {all}"
        );
    }
}

#[test]
fn export_and_import_work_on_the_settings_written() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("pack.toml");
    let mut app = connected(written(&["SetAMaxVMax 0 100 300", "SetClockDivider 3"]));
    params(&mut app);
    app.handle(key(KeyCode::Char('e')));
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
    type_text(&mut app, &path.display().to_string());
    let effects = app.handle(key(KeyCode::Enter));
    assert!(serve(&mut app, effects).is_empty(), "nothing to read");
    let text = std::fs::read_to_string(&path).expect("exported");
    assert!(text.contains("family = \"sixpack2\""), "{text}");
    assert!(text.contains("[axis.0]\n"), "{text}");
    assert!(text.contains("\n5121 = 100  # amax\n"), "{text}");
    assert!(text.contains("\n5122 = 300  # vmax\n"), "{text}");
    assert!(text.contains("\n4608 = 3  # clkdiv\n"), "{text}");
    assert!(
        text.contains("# 5122 not read: not written this session  # vmax"),
        "other motors' vmax is not known: {text}"
    );

    // After a reset nothing is known: importing the file writes it all
    // again, each frame once with the values of the file.
    let mut after = written(&["SetAMaxVMax 0 100 300", "SetClockDivider 3"]);
    after.forget("HardwareReset was sent (§7.4)");
    app.handle(AppEvent::Snapshot(sixpack2_snapshot(after)));
    app.handle(key(KeyCode::Char('i')));
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
    type_text(&mut app, &path.display().to_string());
    let effects = app.handle(key(KeyCode::Enter));
    assert!(serve(&mut app, effects).is_empty());
    let all = screen(&mut app, 120, 30).join("\n");
    assert!(all.contains("3 differ"), "{all}");
    assert!(all.contains("unknown → file"), "{all}");
    let effects = app.handle(key(KeyCode::Char('w')));
    let sent = serve(&mut app, effects);
    assert_eq!(sent, ["SetAMaxVMax 0 100 300", "SetClockDivider 3"]);
    let all = screen(&mut app, 120, 30).join("\n");
    assert!(all.contains("wrote 2 values"), "{all}");
}

/// The lines of `effects` sent.
fn sends(effects: &[Effect]) -> Vec<String> {
    effects
        .iter()
        .filter_map(|e| e.sends().map(|(_, _, lines)| lines))
        .flatten()
        .collect()
}

fn typed_line(app: &mut App, line: &str) -> Vec<Effect> {
    type_text(app, line);
    app.handle(key(KeyCode::Enter))
}

#[test]
fn a_line_to_confirm_asks_first_and_is_sent_only_on_yes() {
    let mut app = connected(SettingsCache::default());
    assert_eq!(app.focused(), Some("command"));
    let effects = typed_line(&mut app, "HardwareReset");
    assert!(sends(&effects).is_empty(), "nothing sent before the answer");
    let all = screen(&mut app, 100, 30).join("\n");
    assert!(all.contains("every setting is replaced"), "{all}");
    assert!(
        all.contains("send HardwareReset? y sends, n or Esc does not"),
        "{all}"
    );
    // Other keys do not answer it.
    assert!(sends(&type_text(&mut app, "x")).is_empty());
    assert!(sends(&app.handle(key(KeyCode::Char('n')))).is_empty());
    let all = screen(&mut app, 100, 30).join("\n");
    assert!(all.contains("not sent: HardwareReset"), "{all}");
    assert!(!all.contains("y sends"), "{all}");

    typed_line(&mut app, "StartReferenceSearch 2");
    assert_eq!(
        sends(&app.handle(key(KeyCode::Char('y')))),
        ["StartReferenceSearch 2"]
    );
    // A line that needs none goes at once.
    assert_eq!(
        sends(&typed_line(&mut app, "StartRamp 0 100")),
        ["StartRamp 0 100"]
    );
}

#[test]
fn warnings_are_shown_with_the_line_and_know_what_was_written() {
    let mut app = connected(SettingsCache::default());
    let effects = typed_line(&mut app, "SetAMaxVMax 0 500 400");
    assert_eq!(
        sends(&effects),
        ["SetAMaxVMax 0 500 400"],
        "sent all the same"
    );
    let all = screen(&mut app, 150, 30).join("\n");
    assert!(
        all.contains(
            "warning: amax 500 is over 64·vstart = 320 with vstart 5 (factory value, not known \
             to be changed)"
        ),
        "{all}"
    );
    let mut app = connected(written(&["SetVMinVStart 0 4 8 2"]));
    typed_line(&mut app, "SetAMaxVMax 0 500 400");
    let all = screen(&mut app, 150, 30).join("\n");
    assert!(!all.contains("warning"), "vstart 8 was written: {all}");
}

#[test]
fn a_batch_with_lines_to_confirm_asks_once_before_it_starts() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("homing.txt");
    std::fs::write(
        &file,
        "SetMotorParameters 0 10000 NullLeft,MechRef\nStartReferenceSearch 0\n",
    )
    .expect("write");
    let mut app = connected(SettingsCache::default());
    let effects = typed_line(&mut app, &format!(":run {}", file.display()));
    assert!(sends(&effects).is_empty());
    let all = screen(&mut app, 200, 30).join("\n");
    assert!(
        all.contains(&format!(
            "{}:2: `StartReferenceSearch 0`: it stops the motor",
            file.display()
        )),
        "{all}"
    );
    assert!(all.contains(&format!("run {}?", file.display())), "{all}");
    let effects = app.handle(key(KeyCode::Char('y')));
    assert_eq!(
        sends(&effects),
        ["SetMotorParameters 0 10000 NullLeft,MechRef"],
        "the batch starts"
    );
}

#[test]
fn the_lines_sent_are_recorded_as_a_macro_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("session.sqm");
    let mut app = connected(SettingsCache::default());
    typed_line(&mut app, &format!(":record-macro {}", file.display()));
    let effects = typed_line(&mut app, "StartRamp 0 10000");
    serve(&mut app, effects);
    let effects = typed_line(&mut app, "GetPositionAndActivity 0");
    serve(&mut app, effects);
    // A line refused is not sent and not recorded.
    let effects = typed_line(&mut app, "StartRamp 7 1");
    serve(&mut app, effects);
    assert_eq!(
        std::fs::read_to_string(&file).expect("recorded"),
        "SendToPack($00, $23, $00, $10, $27, $00, $00, $00, $00)\n\
         SendToPack($00, $20, $00, $00, $00, $00, $00, $00, $00)\n"
    );
    typed_line(&mut app, ":record-macro off");
    let all = screen(&mut app, 100, 30).join("\n");
    assert!(all.contains("recording ended: 2 line(s)"), "{all}");
    let effects = typed_line(&mut app, "StartRamp 0 0");
    serve(&mut app, effects);
    assert_eq!(
        std::fs::read_to_string(&file)
            .expect("kept")
            .lines()
            .count(),
        2,
        "nothing after off"
    );
    // An existing file is never overwritten.
    typed_line(&mut app, &format!(":record-macro {}", file.display()));
    let all = screen(&mut app, 140, 30).join("\n");
    assert!(all.contains("exists: give --force to replace it"), "{all}");
}

#[test]
fn a_macro_is_played_from_the_console_after_its_frames_are_confirmed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("home.sqm");
    std::fs::write(
        &file,
        "SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)\n\
         SendToPack($00, $22, $00, $00, $00, $00, $00, $00, $00)\n",
    )
    .expect("write");
    let mut app = connected(SettingsCache::default());
    let effects = typed_line(&mut app, &format!(":run-macro {}", file.display()));
    assert!(sends(&effects).is_empty());
    let all = screen(&mut app, 150, 30).join("\n");
    assert!(
        all.contains(&format!(
            "{}:2: `StartReferenceSearch 0`: it stops the motor",
            file.display()
        )),
        "{all}"
    );
    let effects = app.handle(key(KeyCode::Char('y')));
    assert_eq!(
        sends(&effects),
        ["SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)"]
    );
    let all = screen(&mut app, 150, 30).join("\n");
    assert!(
        all.contains("from the host: a playback of 2 frames"),
        "{all}"
    );
    // A-Script is another family's.
    let mut app = connected(SettingsCache::default());
    typed_line(&mut app, ":run-ascript p.asc");
    let all = screen(&mut app, 150, 30).join("\n");
    assert!(
        all.contains(
            ":run-ascript runs A-Script (cmd4cr) from the host; this module speaks sixpack2"
        ),
        "{all}"
    );
}

#[test]
fn the_editor_shows_a_macro_file_decoded_beside_its_lines_and_marks_its_errors() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("home.sqm");
    std::fs::write(
        &path,
        "# §5.5.3.2\n\
         SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)\n\
         SendToPack($00, $22, $00)\n",
    )
    .expect("write");
    let mut app = console();
    assert!(app.focus("editor"));
    app.handle(key(KeyCode::F(3)));
    app.handle(AppEvent::Terminal(ratatui::crossterm::event::Event::Paste(
        path.display().to_string(),
    )));
    app.handle(key(KeyCode::Enter));
    app.handle(key(KeyCode::Esc));
    let lines = screen(&mut app, 140, 30);
    let all = lines.join("\n");
    assert!(all.contains("Program (SQPack macro) — home.sqm"), "{all}");
    let frame = lines
        .iter()
        .find(|l| l.contains("SendToPack($00, $15"))
        .expect("the frame's line");
    assert!(
        frame.contains("» SetMotorParameters 0 10000 NullLeft,MechRef (Motor 1)"),
        "{frame}"
    );
    let bad = lines
        .iter()
        .find(|l| l.contains("SendToPack($00, $22, $00)"))
        .expect("the bad line");
    assert!(bad.contains("!  3"), "marked as an error: {bad}");
    // F9 checks: the error with its place.
    app.handle(key(KeyCode::F(9)));
    let all = screen(&mut app, 140, 30).join("\n");
    assert!(
        all.contains("3:25: a frame has 9 values (adr, cmd, p0..p6), this one 3"),
        "{all}"
    );
}

/// The six motors as the family reads its status answers (the bytes of
/// §7.2/§7.3 written out): motor 0 ramping towards 10000, motor 1
/// rotating at -300, motor 2 searching its reference, motor 3 stopped by
/// a switch (its stop flag), 4 and 5 at rest; the reference inputs of 2
/// and 5 active.
fn six_motors() -> Vec<axterm::session::AxisStatus> {
    let console = find_family("sixpack2").expect("sixpack2").console;
    let mut status = vec![axterm::session::AxisStatus::default(); 6];
    let mut read = |line: &str, reply: &[u8]| {
        let prepared = console.prepare(line, 0).expect("valid");
        let frames: Vec<Vec<u8>> = if reply.is_empty() {
            Vec::new()
        } else {
            vec![reply.to_vec()]
        };
        let reading = console.interpret(&prepared, &frames).expect("an answer");
        for (axis, update) in console.status_update(&prepared, &reading) {
            status[axis].apply(update);
        }
    };
    let position = |m: u8, pos: i32, action: u8, stop: u8| {
        let mut reply = vec![0x20, m];
        reply.extend_from_slice(&pos.to_le_bytes());
        reply.extend_from_slice(&[action, stop]);
        reply
    };
    let velocity = |m: u8, v: i16, action: u8| {
        let mut reply = vec![0x21, m];
        reply.extend_from_slice(&v.to_le_bytes());
        reply.extend_from_slice(&[action, 0, 0, 0]);
        reply
    };
    for (m, pos, v, action, stop) in [
        (0u8, 4200, 350, 5, 0),
        (1, -123_456, -300, 15, 0),
        (2, 77, -100, 21, 0),
        (3, -241, 0, 0, 1),
        (4, 0, 0, 0, 0),
        (5, 999_999, 0, 0, 0),
    ] {
        read(
            &format!("GetPositionAndActivity {m}"),
            &position(m, pos, action, stop),
        );
        read(
            &format!("GetVelocityAndActivity {m}"),
            &velocity(m, v, action),
        );
    }
    // $30 P4: reference inputs of motors 2 and 5.
    read("GetInputValues 0", &[0x30, 0, 0, 0, 0, 0b0010_0100, 0, 0]);
    read("SetAMaxVMax 0 100 400", &[]);
    status
}

fn six_motor_console() -> App {
    let mut snapshot = sixpack2_snapshot(SettingsCache::default());
    snapshot.status = six_motors();
    let mut app = console();
    app.handle(AppEvent::Snapshot(snapshot));
    app
}

#[test]
fn six_axes_fit_80x24_one_row_each() {
    let mut app = six_motor_console();
    let lines = screen(&mut app, 80, 24);
    let all = lines.join("\n");
    let rows: Vec<&String> = lines
        .iter()
        .filter(|l| {
            ["m0 ", "m1 ", "m2 ", "m3 ", "m4 ", "m5 "]
                .iter()
                .any(|m| l.contains(m))
        })
        .collect();
    assert_eq!(rows.len(), 6, "{all}");
    let row = |m: usize| rows[m].as_str();
    assert!(row(0).starts_with("│▶m0"), "{}", row(0));
    assert!(
        row(0).contains("4200") && row(0).contains("350/400") && row(0).contains("ramp●"),
        "{}",
        row(0)
    );
    assert!(
        row(1).contains("-123456") && row(1).contains("rotation●"),
        "{}",
        row(1)
    );
    assert!(
        row(2).contains("ref search●") && row(2).contains("H●"),
        "{}",
        row(2)
    );
    assert!(row(3).contains("ERR stop flag"), "{}", row(3));
    assert!(
        row(4).contains("H○") && row(4).contains("no errors"),
        "{}",
        row(4)
    );
    assert!(
        row(5).contains("999999") && row(5).contains("H●"),
        "{}",
        row(5)
    );
    // The command pane still has room below.
    assert!(all.contains("1 Command"), "{all}");
}

#[test]
fn six_axes_on_a_wide_screen_are_cards_with_every_lamp() {
    let mut app = six_motor_console();
    let lines = screen(&mut app, 200, 50);
    let all = lines.join("\n");
    for name in [
        "m0/Motor1",
        "m1/Motor2",
        "m2/Motor3",
        "m3/Motor4",
        "m4/Motor5",
        "m5/Motor6",
    ] {
        assert!(all.contains(name), "{name}: {all}");
    }
    let card = |name: &str| {
        lines
            .iter()
            .position(|l| l.contains(name))
            .unwrap_or_else(|| panic!("{name}: {all}"))
    };
    let m1 = card("m1/Motor2");
    assert!(lines[m1].contains("-123456"), "{}", lines[m1]);
    assert!(lines[m1 + 1].contains("spd") && lines[m1 + 1].contains("-300"));
    // Every action as a lamp, the one in force lit.
    assert!(
        lines[m1 + 2].contains("ramp○ PI○ rotation● ref search○ mech ref○"),
        "{}",
        lines[m1 + 2]
    );
    let m3 = card("m3/Motor4");
    assert!(lines[m3 + 2].contains("ERR stop flag"), "{}", lines[m3 + 2]);
    let m0 = card("m0/Motor1");
    assert!(lines[m0 + 1].contains("max") && lines[m0 + 1].contains("400"));
}

#[test]
fn the_editor_plays_a_macro_only_once_its_frames_to_confirm_were_said() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("home.sqm");
    std::fs::write(
        &path,
        "SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)\n\
         SendToPack($00, $22, $00, $00, $00, $00, $00, $00, $00)\n",
    )
    .expect("write");
    let mut app = connected(SettingsCache::default());
    assert!(app.focus("editor"));
    app.handle(key(KeyCode::F(3)));
    app.handle(AppEvent::Terminal(ratatui::crossterm::event::Event::Paste(
        path.display().to_string(),
    )));
    app.handle(key(KeyCode::Enter));
    let effects = app.handle(key_with(KeyCode::F(5), KeyModifiers::CONTROL));
    assert!(
        sends(&effects).is_empty(),
        "nothing sent on the first press"
    );
    let all = screen(&mut app, 150, 40).join("\n");
    assert!(
        all.contains("Ctrl-F5 again sends it: ")
            && all.contains("home.sqm:2: `StartReferenceSearch 0`: it stops"),
        "{all}"
    );
    let effects = app.handle(key_with(KeyCode::F(5), KeyModifiers::CONTROL));
    assert_eq!(
        sends(&effects),
        ["SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)"]
    );
}
