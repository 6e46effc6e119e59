//! The axis status pane drawn by the whole console with ratatui's
//! TestBackend, from hand-made snapshots: one TMCM-1110 motor, a 4-axis
//! X/Y/Z/U machine and a 6-axis one, at 80×24 and at a large size.

mod panes_support;
mod ui_support;

use axterm::ui::app::{AppEvent, Effect};
use panes_support::{SimModule, serve};
use ratatui::crossterm::event::KeyCode;
use ui_support::{axes, console, key, moving_status, screen, show, snapshot};

#[test]
fn one_axis_at_80x24_shows_position_target_speed_switches_and_load() {
    let mut app = console();
    let mut s = snapshot(axes(&["motor 0"]));
    s.status[0] = moving_status(12_800, 51_200, 1_024, 2_047);
    s.status[0].left_switch = Some(true);
    app.handle(axterm::ui::app::AppEvent::Snapshot(s));
    let lines = screen(&mut app, 80, 24);
    let text = lines.join("\n");
    // The axes sit on top of the command pane, which keeps most rows.
    assert!(
        lines[0].contains("Axes — sim tmcm1110 #1 connected, poll 20 Hz"),
        "{text}"
    );
    assert!(
        lines[1].contains("▶motor 0") && lines[1].contains("pos       12800"),
        "{text}"
    );
    assert!(
        lines[1].contains("tgt       51200") && lines[1].contains("○ moving"),
        "{text}"
    );
    assert!(
        lines[2].contains("spd        1024") && lines[2].contains("max        2047"),
        "{text}"
    );
    assert!(lines[2].contains("accelerating"), "{text}");
    assert!(
        lines[3].contains("L● R○ H○") && lines[3].contains("load"),
        "{text}"
    );
    assert!(lines[3].contains("no errors"), "{text}");
    assert!(lines[5].contains("Command"), "{text}");
    assert!(lines[23].starts_with(" F12 STOP "), "{text}");
}

#[test]
fn an_axis_stopped_short_of_its_target_says_so_not_moving_at_80x24() {
    let mut app = console();
    let mut s = snapshot(axes(&["motor 0"]));
    s.status[0] = moving_status(104_195, 200_000, 1_500, 1_500);
    show(&mut app, s.clone());
    let lines = screen(&mut app, 80, 24);
    assert!(lines[1].contains("○ moving"), "{}", lines[1]);
    // The emergency stop (or Space): the speed falls to 0, the target
    // stays where it was, the module's reached flag stays clear.
    s.status[0].speed = Some(0);
    show(&mut app, s.clone());
    let lines = screen(&mut app, 80, 24);
    let text = lines.join("\n");
    assert!(
        lines[1].contains("tgt      200000 ○ stopped short"),
        "{text}"
    );
    assert!(!lines[1].contains("moving"), "{text}");
    // The whole label fits inside the border.
    assert!(lines[1].ends_with("stopped short│"), "{text}");
    assert!(lines[2].contains("standing"), "{text}");
    // A new move: moving again; there: reached.
    s.status[0].speed = Some(300);
    show(&mut app, s.clone());
    assert!(screen(&mut app, 80, 24)[1].contains("○ moving"));
    s.status[0].speed = Some(0);
    s.status[0].position = Some(200_000);
    s.status[0].reached = Some(true);
    show(&mut app, s);
    assert!(screen(&mut app, 80, 24)[1].contains("● reached"));
}

#[test]
fn the_position_gauge_fills_toward_the_target_and_marks_it() {
    let mut app = console();
    let mut s = snapshot(axes(&["motor 0"]));
    s.status[0] = moving_status(0, 51_200, 0, 2_047);
    show(&mut app, s.clone());
    let before = screen(&mut app, 100, 30)[1].clone();
    s.status[0].position = Some(25_600);
    show(&mut app, s.clone());
    let half = screen(&mut app, 100, 30)[1].clone();
    let filled = |line: &str| line.chars().filter(|&c| c == '█').count();
    assert_eq!(filled(&before), 0, "{before}");
    assert!(filled(&half) > 0, "{half}");
    assert!(half.contains('┃'), "the target is marked: {half}");
    s.status[0].position = Some(51_200);
    s.status[0].reached = Some(true);
    s.status[0].speed = Some(0);
    show(&mut app, s);
    let lines = screen(&mut app, 100, 30);
    assert!(filled(&lines[1]) > filled(&half), "{}", lines[1]);
    assert!(lines[1].contains("● reached"), "{}", lines[1]);
    assert!(lines[2].contains("standing"), "{}", lines[2]);
}

#[test]
fn four_named_axes_get_a_card_each_at_80x24_and_side_by_side_when_wide() {
    let mut app = console();
    let mut s = snapshot(axes(&["X", "Y", "Z", "U"]));
    for (i, status) in s.status.iter_mut().enumerate() {
        *status = moving_status(1000 * (i as i64 + 1), 5000, 0, 1000);
    }
    s.status[2].errors = vec![axterm::session::AxisFlag {
        name: "stall",
        description: "test",
    }];
    app.handle(axterm::ui::app::AppEvent::Snapshot(s));
    // 80×24: the pane gets at most 11 rows inside, too few for 4 cards
    // of 3 rows: one row per axis, and the command pane gets the rest.
    let lines = screen(&mut app, 80, 24);
    let text = lines.join("\n");
    for (row, name, position) in [
        (1, "X", "1000"),
        (2, "Y", "2000"),
        (3, "Z", "3000"),
        (4, "U", "4000"),
    ] {
        assert!(
            lines[row].contains(name) && lines[row].contains(position),
            "{text}"
        );
    }
    assert!(lines[3].contains("ERR stall"), "{text}");
    assert!(lines[1].starts_with("│▶X"), "{text}");
    // 200×50: two cards side by side, two rows of cards.
    let lines = screen(&mut app, 200, 50);
    let text = lines.join("\n");
    assert!(
        lines[1].contains("▶X") && lines[1].contains(" Y "),
        "{text}"
    );
    assert!(
        lines[4].contains(" Z ") && lines[4].contains(" U "),
        "{text}"
    );
    assert!(
        lines[6].contains("ERR stall") && lines[6].contains("F8 clears"),
        "{text}"
    );
    assert!(
        lines[7].starts_with("└"),
        "the pane ends after two rows of cards: {text}"
    );
}

#[test]
fn six_axes_fit_at_80x24_and_in_three_columns_when_wide() {
    let mut app = console();
    let names = ["X", "Y", "Z", "A", "B", "C"];
    let mut s = snapshot(axes(&names));
    for (i, status) in s.status.iter_mut().enumerate() {
        *status = moving_status(-100 * i as i64, 0, 0, 500);
    }
    app.handle(axterm::ui::app::AppEvent::Snapshot(s));
    let lines = screen(&mut app, 80, 24);
    let text = lines.join("\n");
    for (row, name) in names.iter().enumerate() {
        assert!(
            lines[row + 1].contains(&format!(" {name} "))
                || lines[row + 1].contains(&format!("▶{name} ")),
            "{text}"
        );
    }
    assert!(lines[6].contains("-500"), "{text}");
    // One row each; the command pane gets the rest.
    assert!(lines[8].contains("Command"), "{text}");
    let lines = screen(&mut app, 260, 60);
    let text = lines.join("\n");
    assert!(
        lines[1].contains("▶X") && lines[1].contains(" Y ") && lines[1].contains(" Z "),
        "{text}"
    );
    assert!(
        lines[4].contains(" A ") && lines[4].contains(" B ") && lines[4].contains(" C "),
        "{text}"
    );
}

#[test]
fn keys_in_the_axis_pane_select_an_axis_and_clear_its_errors() {
    let mut app = console();
    let mut s = snapshot(axes(&["X", "Y", "Z", "U"]));
    s.axes[1].number = 0; // TMCL, the family of these fakes, knows motor 0 only
    s.status[1].errors = vec![axterm::session::AxisFlag {
        name: "stall",
        description: "test",
    }];
    app.handle(axterm::ui::app::AppEvent::Snapshot(s));
    app.focus("axes");
    app.handle(key(KeyCode::Down));
    assert_eq!(app.snapshot().map(|s| s.axis), Some(1));
    let lines = screen(&mut app, 80, 24);
    assert!(lines[2].starts_with("│▶Y"), "{}", lines[2]);
    let effects = app.handle(key(KeyCode::F(8)));
    assert_eq!(
        effects,
        [axterm::ui::app::Effect::ClearErrors {
            axis: 1,
            seen: vec![axterm::session::AxisFlag {
                name: "stall",
                description: "test"
            }]
        }]
    );
    // Space stops the selected axis with the family's stop line.
    let effects = app.handle(key(KeyCode::Char(' ')));
    assert!(
        matches!(&effects[..], [axterm::ui::app::Effect::Send { lines, .. }] if lines == &["MST 0"]),
        "{effects:?}"
    );
}

#[test]
fn the_pane_title_names_the_link_the_module_and_the_poll_rate() {
    let mut app = console();
    let mut s = snapshot(axes(&["motor 0"]));
    s.identity = Some("1110V1.12".into());
    s.poll = None;
    app.handle(axterm::ui::app::AppEvent::Snapshot(s));
    let lines = screen(&mut app, 80, 24);
    assert!(
        lines[0].contains("Axes — sim tmcm1110 #1 (1110V1.12) connected, poll off"),
        "{}",
        lines[0]
    );
}

#[test]
fn unknown_values_show_as_dashes_not_zeros() {
    let mut app = console();
    app.handle(axterm::ui::app::AppEvent::Snapshot(snapshot(axes(&[
        "motor 0",
    ]))));
    let lines = screen(&mut app, 100, 30);
    assert!(lines[1].contains("pos           —"), "{}", lines[1]);
    assert!(lines[1].contains("reached?"), "{}", lines[1]);
}

/// The lines sent by a batch of effects.
fn sent_lines(effects: &[Effect]) -> Vec<String> {
    effects
        .iter()
        .flat_map(|e| match e {
            Effect::Send { lines, .. } => lines.clone(),
            _ => Vec::new(),
        })
        .collect()
}

/// The units key (u) goes raw → pps → rpm → raw; each time it leaves raw
/// units the microstep resolution (AP140) and the pulse divisor (AP154)
/// are read from the module (here the simulator), so a resolution changed
/// meanwhile is taken into account.
#[test]
fn the_units_key_shows_steps_and_pps_then_turns_and_rpm_with_the_modules_settings() {
    let mut module = SimModule::new();
    for line in ["SAP 140, 0, 8", "SAP 154, 0, 3"] {
        module.answer(line).expect("the simulator takes it");
    }
    let mut app = console();
    let mut s = snapshot(axes(&["motor 0"]));
    // §6.1.1: 1678 is about 51208.5 pps with pulse divisor 3; §6.1.4:
    // at 256 microsteps a 200-step motor turns once per 51200.
    s.status[0] = moving_status(12_800, 51_200, 1_678, 1_678);
    app.handle(AppEvent::Snapshot(s));
    app.focus("axes");
    let lines = screen(&mut app, 100, 30);
    assert!(
        lines[0].contains("poll 20 Hz · u units: raw"),
        "{}",
        lines[0]
    );
    assert!(lines[2].contains("spd        1678"), "{}", lines[2]);

    let effects = app.handle(key(KeyCode::Char('u')));
    assert_eq!(sent_lines(&effects), ["GAP 140, 0", "GAP 154, 0"]);
    serve(&mut app, &mut module, effects);
    let lines = screen(&mut app, 100, 30);
    let all = lines.join("\n");
    assert!(lines[0].contains("u units: pps"), "{all}");
    assert!(
        lines[1].contains("pos 12800 µsteps") && lines[1].contains("tgt 51200 µsteps"),
        "{all}"
    );
    assert_eq!(lines[2].matches(" 51208 pps ").count(), 2, "{all}");

    // 64 microsteps a full step now: a quarter as many to a turn.
    module
        .answer("SAP 140, 0, 6")
        .expect("the simulator takes it");
    let effects = app.handle(key(KeyCode::Char('u')));
    assert_eq!(sent_lines(&effects), ["GAP 140, 0", "GAP 154, 0"]);
    serve(&mut app, &mut module, effects);
    let lines = screen(&mut app, 100, 30);
    let all = lines.join("\n");
    assert!(lines[0].contains("u units: rpm"), "{all}");
    assert!(
        lines[1].contains(" 1 rev ") && lines[1].contains(" 4 rev "),
        "{all}"
    );
    assert_eq!(lines[2].matches(" 240.0 rpm ").count(), 2, "{all}");

    let effects = app.handle(key(KeyCode::Char('u')));
    assert!(sent_lines(&effects).is_empty(), "{effects:?}");
    let lines = screen(&mut app, 100, 30);
    assert!(lines[0].contains("u units: raw"), "{}", lines[0]);
    assert!(lines[1].contains("pos       12800"), "{}", lines[1]);
}

/// Until the module answers (or when it cannot), a value that needs what
/// was not read is marked raw rather than shown in a wrong unit; a read
/// that fails is said in the title. One row per axis shows units too.
#[test]
fn values_not_yet_convertible_are_marked_raw_and_a_failed_read_is_said() {
    let mut app = console();
    let mut s = snapshot(axes(&["X", "Y", "Z", "U"]));
    for status in &mut s.status {
        *status = moving_status(100, 200, 10, 20);
    }
    app.handle(AppEvent::Snapshot(s));
    app.focus("axes");
    let effects = app.handle(key(KeyCode::Char('u')));
    let sends: Vec<(usize, u64, String)> = effects
        .iter()
        .filter_map(|e| match e {
            Effect::Send { pane, tag, lines } => Some((*pane, *tag, lines.join(";"))),
            _ => None,
        })
        .collect();
    // Two reads an axis.
    assert_eq!(sends.len(), 8, "{effects:?}");
    let lines = screen(&mut app, 80, 24);
    let all = lines.join("\n");
    // 80×24: one row per axis; positions need nothing (µsteps), speeds
    // need the pulse divisor.
    assert!(
        lines[1].contains("100 µsteps→200 µsteps") && lines[1].contains("v10 raw/20 raw"),
        "{all}"
    );
    let (pane, tag, line) = sends[1].clone();
    app.handle(AppEvent::Reply {
        pane,
        tag,
        line: line.clone(),
        result: Err(axterm::session::SessionError::Refused {
            line,
            message: "no answer in 200 ms".into(),
        }),
    });
    let lines = screen(&mut app, 80, 24);
    assert!(lines[0].contains("GAP 154, 0:"), "{}", lines[0]);
    assert!(lines[1].contains("v10 raw/20 raw"), "{}", lines[1]);
}

mod no_units {
    //! A family without unit conversions: TMCL's frames and lines, no
    //! parameter tables.
    use std::sync::Arc;

    use axterm::protocol::Family;
    use axterm::protocol::console::{
        AxisInfo, AxisUpdate, FamilyConsole, PreparedLine, Reading, ReplyError, StatusPoll,
    };
    use axterm::protocol::tmcl::TmclConsole;
    use axterm::protocol::wire::{Frame, WireFormat};

    pub struct Plain;

    impl FamilyConsole for Plain {
        fn wire(&self) -> Arc<dyn WireFormat> {
            TmclConsole.wire()
        }
        fn default_address(&self) -> u8 {
            1
        }
        fn axes(&self) -> &'static [AxisInfo] {
            TmclConsole.axes()
        }
        fn prepare(
            &self,
            line: &str,
            address: u8,
        ) -> Result<PreparedLine, axterm::protocol::line_error::LineError> {
            TmclConsole.prepare(line, address)
        }
        fn interpret(&self, line: &PreparedLine, frames: &[Frame]) -> Result<Reading, ReplyError> {
            TmclConsole.interpret(line, frames)
        }
        fn emergency_stop(&self, address: u8) -> Vec<PreparedLine> {
            TmclConsole.emergency_stop(address)
        }
        fn identify(&self, address: u8) -> PreparedLine {
            TmclConsole.identify(address)
        }
        fn status_queries(&self, address: u8) -> Vec<StatusPoll> {
            TmclConsole.status_queries(address)
        }
        fn status_update(
            &self,
            line: &PreparedLine,
            reading: &Reading,
        ) -> Vec<(usize, AxisUpdate)> {
            TmclConsole.status_update(line, reading)
        }
    }

    pub static PLAIN: Family = Family {
        name: "plain",
        description: "a family with no unit conversions",
        encode_line: |line, address| {
            TmclConsole
                .prepare(line, address.unwrap_or(1))
                .map(|p| p.bytes)
        },
        show_bytes: |_| String::new(),
        console: &Plain,
    };
}

#[test]
fn the_units_key_says_so_when_the_family_has_no_conversion() {
    let mut app = console();
    let mut s = snapshot(axes(&["motor 0"]));
    s.family = &no_units::PLAIN;
    s.status[0] = moving_status(12_800, 51_200, 1_678, 1_678);
    app.handle(AppEvent::Snapshot(s));
    app.focus("axes");
    let effects = app.handle(key(KeyCode::Char('u')));
    assert!(sent_lines(&effects).is_empty(), "{effects:?}");
    let lines = screen(&mut app, 100, 30);
    assert!(
        lines[0].contains("plain has no real-world units: raw only"),
        "{}",
        lines[0]
    );
    assert!(lines[1].contains("pos       12800"), "{}", lines[1]);
}

/// Where each column marker of the axis pane's rows is, by screen row:
/// `→` between position and target, `/` after the speed, the `L`
/// switch lamp, and the card labels.
fn column_marks(lines: &[String]) -> Vec<Vec<(&'static str, Option<usize>)>> {
    let end = lines
        .iter()
        .position(|l| l.contains("Command"))
        .unwrap_or(lines.len());
    lines[..end]
        .iter()
        .map(|line| {
            ["→", "/", " L", " tgt ", " max ", "ferr", "spd "]
                .into_iter()
                .map(|mark| {
                    let at = line.find(mark).map(|byte| line[..byte].chars().count());
                    (mark, at)
                })
                .collect()
        })
        .collect()
}

/// A number gaining a digit moves no column, in any family's rows or
/// cards (issue 19, point 9: SIXpack 2 and MCCL rows shifted).
#[test]
fn columns_stay_put_when_a_number_gains_a_digit() {
    use axterm::protocol::console::StatusValue;
    for family in axterm::families::FAMILIES {
        let reads_ferr = family
            .console
            .status_values()
            .contains(&StatusValue::FollowingError);
        let at = |n: i64| {
            let mut s = axterm::ui::pane::Snapshot {
                family,
                ..snapshot(family.console.axes().to_vec())
            };
            for status in &mut s.status {
                *status = moving_status(n, n, n, n.abs());
                if reads_ferr {
                    // A servo trips at its maximum following error long
                    // before 5 digits.
                    status.following_error = Some(n.clamp(-9999, 9999));
                }
            }
            s
        };
        for (width, height) in [(80, 24), (120, 40), (200, 60)] {
            let mut app = console();
            ui_support::show(&mut app, at(9));
            let before = screen(&mut app, width, height);
            for n in [10, 12345, -99_999] {
                ui_support::show(&mut app, at(n));
                let after = screen(&mut app, width, height);
                assert_eq!(
                    column_marks(&before),
                    column_marks(&after),
                    "{} at {width}×{height}, 9 then {n}:\n{}\n{}",
                    family.name,
                    before.join("\n"),
                    after.join("\n")
                );
            }
        }
    }
}

/// With mechanics in force the units key goes on past rpm to the axes'
/// own units: each value beside its raw number, converted with the
/// module's settings read afresh (TMCL §6.1: positions in µsteps, speeds
/// with the pulse divisor; AP140 for the microsteps).
#[test]
fn with_mechanics_the_units_key_shows_the_axis_own_units_beside_raw() {
    let mut module = SimModule::new();
    for line in ["SAP 140, 0, 8", "SAP 154, 0, 3"] {
        module.answer(line).expect("the simulator takes it");
    }
    let mut app = console();
    let mut s = snapshot(axes(&["motor 0"]));
    let value: toml::Table = "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\n\
                              travel_per_rev = 5\n"
        .parse()
        .expect("toml");
    let (mechanics, problems) =
        axterm::protocol::units::MechanicsTable::from_toml(&value["mechanics"]);
    assert!(problems.is_empty(), "{problems:?}");
    s.mechanics = std::sync::Arc::new(mechanics);
    // 102400 µsteps at 10240 a mm: 10 mm; 1678 [int] at divisor 3 is
    // 51208.5 pps (§6.1.1), 5.0 mm/s.
    s.status[0] = moving_status(51_200, 102_400, 1_678, 1_678);
    app.handle(AppEvent::Snapshot(s));
    app.focus("axes");
    for _ in 0..3 {
        let effects = app.handle(key(KeyCode::Char('u')));
        serve(&mut app, &mut module, effects);
    }
    let lines = screen(&mut app, 120, 30);
    let all = lines.join("\n");
    assert!(lines[0].contains("u units: axis units"), "{all}");
    assert!(
        lines[1].contains("51200 = 5 mm") && lines[1].contains("102400 = 10 mm"),
        "{all}"
    );
    assert_eq!(lines[2].matches("1678 = 5.001 mm/s").count(), 2, "{all}");
    let effects = app.handle(key(KeyCode::Char('u')));
    assert!(sent_lines(&effects).is_empty(), "{effects:?}");
    assert!(screen(&mut app, 120, 30)[0].contains("u units: raw"));
}
