//! The console's panes with the MCCL family: five axes (four servos, a
//! stepper) with their primary status words as switch lamps, lamps and
//! latched errors and the servos' following error, at 80×24 and wide; a
//! line that holds the controller busy shown with its keys (Escape aborts,
//! Space pauses), polling said to wait, the emergency stop key still
//! stopping; the parameter table of §16's read-back variables.

mod ui_support;

use std::time::{Duration, Instant};

use axterm::device::{Busy, LinkState, Priority};
use axterm::families::find_family;
use axterm::protocol::Family;
use axterm::protocol::console::Reading;
use axterm::session::{AxisStatus, LineResult, PollCadence, SessionError};
use axterm::sim::SimulatedController;
use axterm::sim::mccl::{Mccl, SimConfig};
use axterm::ui::app::{App, AppEvent, Effect};
use axterm::ui::pane::Snapshot;
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use ui_support::{console, key, key_with, screen, type_text};

fn mccl() -> &'static Family {
    find_family("mccl").expect("registered")
}

fn snapshot(status: Vec<AxisStatus>) -> Snapshot {
    let family = mccl();
    Snapshot {
        family,
        address: 0,
        link_name: "sim mccl".into(),
        status,
        axes: family.console.axes().to_vec(),
        link: LinkState::Connected {
            link: "sim mccl".into(),
        },
        identity: Some("MFX-PCI1440-3-A Motion Controller".into()),
        poll: Some(PollCadence::default()),
        axis: 0,
        settings: Default::default(),
        mechanics: Default::default(),
    }
}

/// The axes' status as the session builds it from these answers (the echo
/// and the prompt added).
fn status_from(answers: &[(&str, &[&str])]) -> Vec<AxisStatus> {
    let console = mccl().console;
    let mut axes = vec![AxisStatus::default(); console.axes().len()];
    for (line, replies) in answers {
        let prepared = console.prepare(line, 0).expect("valid");
        let mut frames = vec![line.as_bytes().to_vec()];
        frames.extend(replies.iter().map(|r| r.as_bytes().to_vec()));
        frames.push(b">".to_vec());
        let reading: Reading = console.interpret(&prepared, &frames).expect("a reading");
        for (axis, update) in console.status_update(&prepared, &reading) {
            axes[axis].apply(update);
        }
    }
    axes
}

/// Axis 1 moving (motor on, lagging 58 counts), axis 2 stopped on its
/// positive limit (hard limit + tripped, motor error: Ch8 TS's own
/// example 268436489), axis 3 at rest and homed, axis 4 not read yet, the
/// stepper at its target on its home input.
fn five_axes() -> Vec<AxisStatus> {
    status_from(&[
        ("1TP,TV,TS", &["01 52000", "01 100000", "01 2"]),
        ("1TT,TF", &["01 200000", "01 58"]),
        ("2TP,TV,TS", &["02 -500", "02 0", "02 268436489"]),
        ("2TT,TF", &["02 1000", "02 3"]),
        ("3TP,TV,TS", &["03 0", "03 0", "03 2097166"]),
        ("3TT,TF", &["03 0", "03 0"]),
        ("5TP,TV,TS", &["05 1234", "05 0", "05 16777230"]),
        ("5TT", &["05 1234"]),
    ])
}

fn connected(status: Vec<AxisStatus>) -> App {
    let mut app = console();
    app.handle(AppEvent::Snapshot(snapshot(status)));
    app
}

/// The card of `axis` (its three rows, from its name to the next card)
/// on a wide screen, where cards sit side by side.
fn card(text: &str, axis: &str) -> String {
    let lines: Vec<Vec<char>> = text.lines().map(|l| l.chars().collect()).collect();
    let name: Vec<char> = format!("{axis:<8} pos").chars().collect();
    let (row, column) = lines
        .iter()
        .enumerate()
        .find_map(|(row, line)| {
            line.windows(name.len())
                .position(|w| w == name.as_slice())
                .map(|column| (row, column))
        })
        .unwrap_or_else(|| panic!("no card for {axis}:\n{text}"));
    // The next card on the row starts where the next `  pos ` does.
    let end = lines[row][column + name.len()..]
        .windows(5)
        .position(|w| w.iter().collect::<String>() == "  pos")
        .map_or(lines[row].len(), |at| column + name.len() + at - 8);
    lines[row..row + 3]
        .iter()
        .map(|l| l[column..end.min(l.len())].iter().collect::<String>())
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn five_axes_wide_with_lamps_errors_and_following_error() {
    let mut app = connected(five_axes());
    let text = screen(&mut app, 200, 50).join("\n");
    let servo1 = card(&text, "servo 1");
    assert!(
        servo1.contains("52000") && servo1.contains("200000"),
        "{servo1}"
    );
    assert!(servo1.contains("○ moving"), "{servo1}");
    assert!(servo1.contains("ferr 58"), "the following error: {servo1}");
    assert!(
        servo1.contains("motor●") && servo1.contains("homed○"),
        "{servo1}"
    );
    assert!(servo1.contains("no errors"), "{servo1}");
    let servo2 = card(&text, "servo 2");
    assert!(
        servo2.contains("R●") && servo2.contains("L○"),
        "+ limit input: {servo2}"
    );
    assert!(servo2.contains("motor○"), "the motor went off: {servo2}");
    assert!(
        servo2.contains("ERR motor error, hard limit +"),
        "latched: {servo2}"
    );
    let servo3 = card(&text, "servo 3");
    assert!(
        servo3.contains("● reached") && servo3.contains("homed●"),
        "{servo3}"
    );
    let step5 = card(&text, "step 5");
    assert!(
        step5.contains("H●"),
        "a stepper's home input, bit 24: {step5}"
    );
    assert!(
        !step5.contains("ferr"),
        "an open-loop stepper has none: {step5}"
    );
    assert!(text.contains("poll 20 Hz"), "{text}");
}

#[test]
fn five_axes_at_80_by_24_one_row_each() {
    let mut app = connected(five_axes());
    let rows = screen(&mut app, 80, 24);
    let row = |name: &str| {
        rows.iter()
            .find(|r| r.starts_with('│') && r.contains(name))
            .cloned()
            .unwrap_or_else(|| panic!("no row for {name}:\n{}", rows.join("\n")))
    };
    let servo1 = row("servo 1");
    assert!(
        servo1.contains("52000→200000") && servo1.contains("fe58"),
        "{servo1}"
    );
    assert!(servo1.contains("motor●"), "{servo1}");
    let servo2 = row("servo 2");
    assert!(
        servo2.contains("-500→1000") && servo2.contains("R●"),
        "{servo2}"
    );
    assert!(servo2.contains("ERR motor error"), "{servo2}");
    assert!(row("servo 4").contains("—→—"), "not read yet");
    let step5 = row("step 5");
    assert!(
        step5.contains("1234→1234") && step5.contains("H●"),
        "{step5}"
    );
    // Every axis has its row, none cut off.
    for name in ["servo 1", "servo 2", "servo 3", "servo 4", "step 5"] {
        let axis_rows = rows
            .iter()
            .filter(|r| r.starts_with('│') && r.contains(name));
        assert_eq!(axis_rows.count(), 1, "{name}");
    }
}

fn busy(paused: bool, aborting: bool) -> Busy {
    Busy {
        since: Instant::now(),
        bytes: b"2MR1000,WS0.5,MR-1000,WS0.5,RP6\r".to_vec(),
        priority: Priority::User,
        paused,
        aborting,
        pausable: true,
    }
}

#[test]
fn a_busy_line_shows_its_keys_and_polling_waits() {
    let mut app = connected(five_axes());
    app.handle(AppEvent::Busy(Some(busy(false, false))));
    let text = screen(&mut app, 120, 40).join("\n");
    assert!(
        text.contains("busy 2MR1000,WS0.5,MR-1000,WS0.5,RP6: Esc aborts, Space pauses"),
        "{text}"
    );
    assert!(text.contains("poll suspended: controller busy"), "{text}");
    assert!(
        !text.contains("poll 20 Hz"),
        "no rate while nothing is polled: {text}"
    );
    assert!(text.contains("BUSY 2MR1000"), "the status bar: {text}");
    // Space pauses, the cancel key aborts.
    assert!(
        app.handle(key(KeyCode::Char(' ')))
            .contains(&Effect::PauseLine)
    );
    app.handle(AppEvent::Busy(Some(busy(true, false))));
    let text = screen(&mut app, 120, 40).join("\n");
    assert!(
        text.contains("paused 2MR1000") && text.contains("Space resumes"),
        "{text}"
    );
    assert!(app.handle(key(KeyCode::Esc)).contains(&Effect::AbortLine));
    app.handle(AppEvent::Busy(Some(busy(false, true))));
    let text = screen(&mut app, 120, 40).join("\n");
    assert!(text.contains("aborting 2MR1000"), "{text}");
    // A line being typed takes its blanks.
    let effects = type_text(&mut app, "1T P");
    assert!(!effects.contains(&Effect::PauseLine));
    // The emergency stop key works over a busy line.
    assert!(
        app.handle(key(KeyCode::F(12)))
            .contains(&Effect::EmergencyStop),
        "F12"
    );
    // Not busy: the rate again, and Esc only clears the line.
    app.handle(AppEvent::Busy(None));
    let text = screen(&mut app, 120, 40).join("\n");
    assert!(
        text.contains("poll 20 Hz") && !text.contains("busy 2MR"),
        "{text}"
    );
    assert!(!app.handle(key(KeyCode::Esc)).contains(&Effect::AbortLine));
}

/// Answer `line` as the simulated MultiFlex does: fed its bytes, run on
/// virtual time until its prompt, the answer cut and read as the session
/// reads it.
fn simulated(sim: &mut Mccl, line: &str) -> Result<LineResult, SessionError> {
    let console = mccl().console;
    let prepared = console
        .prepare(line, 0)
        .map_err(|error| SessionError::Refused {
            line: line.to_string(),
            message: error.to_string(),
        })?;
    sim.feed(&prepared.bytes);
    let mut output = Vec::new();
    for _ in 0..10_000 {
        sim.advance(Duration::from_millis(1));
        output.extend(sim.take_output());
        if output.ends_with(b">") {
            break;
        }
    }
    let frames = console.wire().framer().push(&output);
    let reading = console
        .interpret(&prepared, &frames)
        .map_err(|e| SessionError::Reply {
            error: Box::new(e),
            request: prepared.bytes.clone(),
            reply: output.clone(),
            elapsed: Duration::ZERO,
        })?;
    Ok(LineResult {
        line: prepared.canonical,
        request: prepared.bytes,
        reply: output,
        status: reading.status,
        value: reading.value,
        elapsed: Duration::ZERO,
        attempts: 1,
    })
}

/// Carry out the sends among `effects` against the simulator, the replies
/// back to the app, until nothing more is sent.
fn serve(app: &mut App, sim: &mut Mccl, mut effects: Vec<Effect>) -> Vec<String> {
    let mut sent = Vec::new();
    for _ in 0..200 {
        let Some((pane, tag, lines)) = effects.iter().find_map(Effect::sends) else {
            return sent;
        };
        effects.clear();
        for line in lines {
            let result = simulated(sim, &line);
            sent.push(line.clone());
            effects.extend(app.handle(AppEvent::Reply {
                pane,
                tag,
                line,
                result,
            }));
        }
    }
    panic!("the pane keeps sending: {sent:?}");
}

#[test]
fn the_parameter_table_reads_the_motor_table_and_sets_with_the_set_command() {
    let mut sim = Mccl::new(SimConfig::pci());
    let mut app = connected(five_axes());
    let focus = app.handle(key_with(KeyCode::Char('3'), KeyModifiers::ALT));
    let reads = serve(&mut app, &mut sim, focus);
    // §16: settings without a Tell command are read from the motor table.
    assert!(
        reads.contains(&"LU\"PGMVEL\",1RD@0,TR0".to_string()),
        "{reads:?}"
    );
    let text = screen(&mut app, 160, 48).join("\n");
    let row = |name: &str| {
        text.lines()
            .find(|l| l.contains(name))
            .unwrap_or_else(|| panic!("no {name} row:\n{text}"))
            .to_string()
    };
    assert!(
        row("SV velocity").contains("100000"),
        "{}",
        row("SV velocity")
    );
    assert!(
        row("SG proportional gain").contains("0.04"),
        "{}",
        row("SG proportional gain")
    );
    // Enter edits the row under the cursor: its set command goes.
    let mut effects = app.handle(key(KeyCode::Enter));
    // The editor starts with the value read; replace it.
    effects.extend(app.handle(key(KeyCode::End)));
    effects.extend(app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL)));
    for c in "150000".chars() {
        effects.extend(app.handle(key(KeyCode::Char(c))));
    }
    effects.extend(app.handle(key(KeyCode::Enter)));
    let sent = serve(&mut app, &mut sim, effects);
    assert_eq!(
        sent,
        ["1SV150000.000", "LU\"PGMVEL\",1RD@0,TR0"],
        "set, then read back"
    );
    let text = screen(&mut app, 160, 48).join("\n");
    let sv = text
        .lines()
        .find(|l| l.contains("SV velocity"))
        .unwrap_or_default();
    assert!(
        sv.contains("150000"),
        "read back after the write: {sv}\n{text}"
    );
}

/// Values show in their unit, whole at any width: the soft limits were
/// cut to `-214748364…`, the velocity shown in thousandths.
#[test]
fn parameter_values_show_in_their_unit_and_no_number_is_cut() {
    let mut sim = Mccl::new(SimConfig::pci());
    let mut app = connected(five_axes());
    let focus = app.handle(key_with(KeyCode::Char('3'), KeyModifiers::ALT));
    serve(&mut app, &mut sim, focus);
    for (width, height) in [(80, 24), (120, 40), (200, 50)] {
        for (filter, shown) in [
            ("SV velocity", "100000.000 counts/s"),
            ("HL high", "2147483647.000 counts"),
            ("LL low", "-2147483648.000 counts"),
        ] {
            app.handle(key(KeyCode::Char('/')));
            for _ in 0..40 {
                app.handle(key(KeyCode::Backspace));
            }
            type_text(&mut app, filter);
            app.handle(key(KeyCode::Enter));
            let text = screen(&mut app, width, height).join("\n");
            let row = text
                .lines()
                .find(|l| l.contains(filter) && !l.contains("filter"))
                .unwrap_or_else(|| panic!("no {filter} row:\n{text}"));
            let words: Vec<&str> = row.split_whitespace().collect();
            assert!(
                words.join(" ").contains(shown),
                "{width}x{height}: {row}\n{text}"
            );
        }
    }
}

#[test]
fn the_macro_manager_lists_deletes_and_stops_tasks() {
    let mut sim = Mccl::new(SimConfig::pci());
    for line in [
        "MD1,1LM2,1LN3",
        "MD10,2MR500,WS.1",
        "MD11,AL5,AR100",
        "GT0,WA100",
    ] {
        simulated(&mut sim, line).expect("stored");
    }
    let mut app = connected(five_axes());
    let typed = |app: &mut App, sim: &mut Mccl, text: &str| {
        let mut effects = type_text(app, text);
        effects.extend(app.handle(key(KeyCode::Enter)));
        serve(app, sim, effects)
    };
    assert_eq!(typed(&mut app, &mut sim, ":programs"), ["TM-1"]);
    let text = screen(&mut app, 120, 40).join("\n");
    assert!(text.contains("3 macro(s) stored"), "{text}");
    assert!(text.contains("macro 10: 2MR500,WS.1"), "{text}");
    // Deleting one: RM, the others defined again, the listing compared.
    let sent = typed(&mut app, &mut sim, ":programs delete 10");
    assert_eq!(
        sent,
        ["TM-1", "RM", "MD1,1LM2,1LN3", "MD11,AL5,AR100", "TM-1"]
    );
    let text = screen(&mut app, 120, 40).join("\n");
    assert!(text.contains("RM erases every macro"), "{text}");
    assert!(
        text.contains("macro 10 deleted; the listing holds the others as they were (1, 11)"),
        "{text}"
    );
    assert!(
        simulated(&mut sim, "MC10").is_err(),
        "gone from the controller"
    );
    let text_of = |app: &mut App| screen(app, 120, 40).join("\n");
    assert!(typed(&mut app, &mut sim, ":programs delete 7").contains(&"TM-1".to_string()));
    assert!(text_of(&mut app).contains("no macro 7 (TM-1 lists 1, 11)"));
    // Background tasks: listed, one stopped.
    assert_eq!(typed(&mut app, &mut sim, ":tasks"), ["ID7"]);
    assert!(text_of(&mut app).contains("background task IDs: 1"));
    assert_eq!(typed(&mut app, &mut sim, ":tasks stop 1"), ["ET1"]);
    assert_eq!(typed(&mut app, &mut sim, ":tasks"), ["ID7"]);
    assert!(text_of(&mut app).contains("no background task running"));
}

#[test]
fn the_editor_marks_mccl_errors_and_warnings_where_they_are() {
    let mut app = console();
    app.handle(AppEvent::Connected(snapshot(five_axes())));
    assert!(app.focus("editor"));
    app.handle(AppEvent::Terminal(ratatui::crossterm::event::Event::Paste(
        "; homing\n1MR1000,N0\nMD5,5LM2\nMD5,5LM1\n".into(),
    )));
    let text = screen(&mut app, 120, 40).join("\n");
    assert!(
        text.contains("Program (MCCL)"),
        "the connected family's: {text}"
    );
    let row = |needle: &str| {
        text.lines()
            .find(|l| l.contains(needle))
            .unwrap_or_else(|| panic!("no {needle}:\n{text}"))
            .to_string()
    };
    assert!(
        row("1MR1000,N0").contains('!'),
        "an error: {}",
        row("1MR1000,N0")
    );
    assert!(
        row("MD5,5LM1").contains('?'),
        "a warning: {}",
        row("MD5,5LM1")
    );
    assert!(!row("MD5,5LM2").contains('!'), "{}", row("MD5,5LM2"));
    // Ctrl-G goes to the error, and says what it is.
    app.handle(ui_support::key_with(
        KeyCode::Char('g'),
        KeyModifiers::CONTROL,
    ));
    let text = screen(&mut app, 120, 40).join("\n");
    assert!(text.contains("did you mean `NO`"), "{text}");
}
