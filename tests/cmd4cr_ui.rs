//! The console's panes with the CMD-4CR family, unchanged: four axes with
//! their MST bits as lamps, drawn from readings the family interprets; the
//! parameter table from the command table, a ratio printed with decimals
//! (SLR) read into the table, STORE for a stored setting.

mod ui_support;

use std::time::Duration;

use axterm::device::LinkState;
use axterm::families::find_family;
use axterm::protocol::Family;
use axterm::protocol::console::Reading;
use axterm::session::{AxisStatus, LineResult, PollCadence, SessionError};
use axterm::ui::app::{App, AppEvent, Effect};
use axterm::ui::pane::Snapshot;
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use ui_support::{console, key, key_with, screen, type_text};

fn cmd4cr() -> &'static Family {
    find_family("cmd4cr").expect("registered")
}

fn snapshot(status: Vec<AxisStatus>) -> Snapshot {
    let family = cmd4cr();
    Snapshot {
        family,
        address: 1,
        link_name: "scripted cmd4cr".into(),
        status,
        axes: family.console.axes().to_vec(),
        link: LinkState::Connected {
            link: "scripted cmd4cr".into(),
        },
        identity: Some("V126BL".into()),
        poll: Some(PollCadence::default()),
        settings: Default::default(),
        mechanics: Default::default(),
        axis: 0,
    }
}

/// The axes' status as the session builds it from these answers.
fn status_from(answers: &[(&str, &str)]) -> Vec<AxisStatus> {
    let console = cmd4cr().console;
    let mut axes = vec![AxisStatus::default(); 4];
    for (line, answer) in answers {
        let prepared = console.prepare(line, 1).expect("valid");
        let reading: Reading = console
            .interpret(&prepared, &[answer.as_bytes().to_vec()])
            .expect("a reading");
        for (axis, update) in console.status_update(&prepared, &reading) {
            axes[axis].apply(update);
        }
    }
    axes
}

#[test]
fn four_axes_with_their_mst_lamps() {
    let status = status_from(&[
        ("PP", "1500:-20000:0:42"),
        ("MSTX", "1"),
        ("PSX", "2500"),
        // Y: stopped on its + limit, the limit error latched, EMG on.
        ("MSTY", &(16 | 256 | (1 << 15)).to_string()),
        ("MSTZ", "0"),
        ("MSTU", &(1 << 19).to_string()),
        ("HSPD", "5000"),
        ("HSPDX", "0"),
    ]);
    let mut app = console();
    app.handle(AppEvent::Snapshot(snapshot(status)));
    let text = screen(&mut app, 120, 40).join("\n");
    for name in ["X ", "Y ", "Z ", "U "] {
        assert!(text.contains(name), "axis {name}:\n{text}");
    }
    assert!(text.contains("1500") && text.contains("-20000"), "{text}");
    assert!(text.contains("2500") && text.contains("5000"), "{text}");
    assert!(text.contains("ERR +limit error"), "{text}");
    // The MST inputs and waits are lamps: EMG lit on Y, the external start
    // wait on U, the rest dark.
    let row_of = |axis: &str| {
        let lines: Vec<&str> = text.lines().collect();
        let at = lines
            .iter()
            .position(|l| l.contains(&format!("│ {axis} ")) || l.contains(&format!("│▶{axis} ")))
            .unwrap_or_else(|| panic!("no card for {axis}:\n{text}"));
        lines.get(at + 2).copied().unwrap_or_default().to_string()
    };
    assert!(
        row_of("Y").contains("EMG●") && row_of("Y").contains("ALM○"),
        "{text}"
    );
    assert!(
        row_of("U").contains("wait CSTA●") && row_of("U").contains("EMG○"),
        "{text}"
    );
    assert!(!text.contains("drv "), "lamps, not a list: {text}");
    assert!(
        !text.contains(" load "),
        "no load reading on a CMD-4CR: {text}"
    );
    // At 80×24 every axis still has its row, with its lit lamps.
    let small = screen(&mut app, 80, 24).join("\n");
    assert!(small.contains("-20000") && small.contains("42"), "{small}");
    assert!(
        small.contains("EMG●") && small.contains("wait CSTA●"),
        "{small}"
    );
}

/// Answer console lines as a CMD-4CR would: reads from `values` (0 when
/// not listed), writes and actions `OK`.
fn answer(line: &str, values: &[(&str, &str)]) -> Result<LineResult, SessionError> {
    let console = cmd4cr().console;
    let prepared = console
        .prepare(line, 1)
        .map_err(|message| SessionError::Refused {
            line: line.to_string(),
            message: message.to_string(),
        })?;
    let text = match values.iter().find(|(l, _)| *l == prepared.canonical) {
        Some((_, value)) => value.to_string(),
        None if prepared.canonical.contains('=') || prepared.canonical == "STORE" => "OK".into(),
        None => "0".into(),
    };
    let reply = text.as_bytes().to_vec();
    let reading = console
        .interpret(&prepared, std::slice::from_ref(&reply))
        .map_err(|error| SessionError::Reply {
            error: Box::new(error),
            request: prepared.bytes.clone(),
            reply: reply.clone(),
            elapsed: Duration::ZERO,
        })?;
    Ok(LineResult {
        line: prepared.canonical,
        request: prepared.bytes,
        reply,
        status: reading.status,
        value: reading.value,
        elapsed: Duration::from_millis(20),
        attempts: 1,
    })
}

/// Carry out the console's sends until it asks for nothing more; returns
/// the lines sent.
fn serve(app: &mut App, effects: Vec<Effect>, values: &[(&str, &str)]) -> Vec<String> {
    let mut sent = Vec::new();
    let mut queue = effects;
    while !queue.is_empty() {
        assert!(sent.len() < 10_000, "the console never stops sending");
        let mut next = Vec::new();
        for effect in queue {
            if let Some((pane, tag, lines)) = effect.sends() {
                for line in lines {
                    sent.push(line.clone());
                    let result = answer(&line, values);
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

const VALUES: &[(&str, &str)] = &[("SLRX", "1.5"), ("HSPDX", "4000"), ("POLX", "7")];

fn parameter_table() -> (App, Vec<String>) {
    let mut app = console();
    app.handle(AppEvent::Snapshot(snapshot(vec![AxisStatus::default(); 4])));
    let effects = app.handle(key_with(KeyCode::Char('3'), KeyModifiers::ALT));
    assert_eq!(app.focused(), Some("params"));
    let sent = serve(&mut app, effects, VALUES);
    (app, sent)
}

fn filter(app: &mut App, text: &str) {
    app.handle(key(KeyCode::Char('/')));
    for _ in 0..40 {
        app.handle(key(KeyCode::Backspace));
    }
    type_text(app, text);
    app.handle(key(KeyCode::Enter));
}

#[test]
fn the_parameter_table_reads_every_setting_of_the_axis_and_the_globals() {
    let (mut app, sent) = parameter_table();
    for line in [
        "HSPDX", "POLX", "SLRX", "JMAXX", "HSPD", "ID", "DB", "IOCFG", "JLIM8", "V99",
    ] {
        assert!(sent.contains(&line.to_string()), "{line} read: {sent:?}");
    }
    assert!(sent.iter().all(|l| !l.contains('=')), "nothing written");
    filter(&mut app, "SLRX");
    let text = screen(&mut app, 120, 40).join("\n");
    let row = text
        .lines()
        .find(|l| l.contains("SLRX") && !l.contains("filter"))
        .unwrap_or_else(|| panic!("no SLRX row:\n{text}"));
    // The ratio in its unit, as an edit starts from it: not thousandths.
    assert!(
        row.contains(" 1.500 pulses/count") && !row.contains("1500"),
        "{row}"
    );
    assert!(!text.contains("unreadable"), "{text}");
}

#[test]
fn storing_a_setting_sends_store() {
    let (mut app, _) = parameter_table();
    filter(&mut app, "POLX");
    let effects = app.handle(key(KeyCode::Char('s')));
    assert_eq!(serve(&mut app, effects, VALUES), ["STORE"]);
    // HSPD is not in the flash set (Table 2-19): nothing is sent.
    filter(&mut app, "HSPDX");
    let effects = app.handle(key(KeyCode::Char('s')));
    assert!(serve(&mut app, effects, VALUES).is_empty());
    let text = screen(&mut app, 120, 40).join("\n");
    assert!(text.contains("Table 2-19"), "{text}");
}

fn enter(app: &mut App, line: &str) -> Vec<Effect> {
    let mut effects = type_text(app, line);
    effects.extend(app.handle(key(KeyCode::Enter)));
    effects
}

#[test]
fn address_takes_the_ids_a_controller_can_have() {
    let mut app = console();
    app.handle(AppEvent::Snapshot(snapshot(vec![AxisStatus::default(); 4])));
    app.focus("command");
    assert_eq!(enter(&mut app, ":address 99"), [Effect::SetAddress(99)]);
    // A frame carries two digits: `@100…` would reach controller 10.
    assert!(enter(&mut app, ":address 100").is_empty());
    let text = screen(&mut app, 100, 30).join("\n");
    assert!(text.contains("module address 0..99, not `100`"), "{text}");
}

/// Issue 19, point 8, through the console's real loop on the simulator:
/// after `X50000` the X row shows its target, and F12 before it leaves
/// the lamp at "stopped short", not "reached".
#[tokio::test(start_paused = true)]
async fn a_move_shows_its_target_and_f12_before_it_stops_short() {
    use ui_support::looped::{Rig, enter, press, run_command_console};
    let first_row = |frame: &str| frame.lines().nth(1).unwrap_or_default().to_string();
    let controller = ui_support::sim_controller("cmd4cr", 115_200).await;
    run_command_console(controller, (120, 40), async |rig: &mut Rig| {
        rig.screens.until("connected").await;
        enter(rig, "X50000");
        rig.screens
            .until_frame("X moving to 50000", |f| {
                let row = first_row(f);
                row.contains("50000") && row.contains("○ moving")
            })
            .await;
        press(rig, KeyCode::F(12));
        let frame = rig
            .screens
            .until_frame("X stopped", |f| !first_row(f).contains("moving"))
            .await;
        let row = first_row(&frame);
        assert!(
            row.contains("○ stopped short") && row.contains("50000"),
            "{frame}"
        );
        assert!(!row.contains("reached"), "{frame}");
    })
    .await;
}
