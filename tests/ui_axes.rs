//! The axis status pane drawn by the whole console with ratatui's
//! TestBackend, from hand-made snapshots: one TMCM-1110 motor, a 4-axis
//! X/Y/Z/U machine and a 6-axis one, at 80×24 and at a large size.

mod ui_support;

use ratatui::crossterm::event::KeyCode;
use ui_support::{axes, console, key, moving_status, screen, snapshot};

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
fn the_position_gauge_fills_toward_the_target_and_marks_it() {
    let mut app = console();
    let mut s = snapshot(axes(&["motor 0"]));
    s.status[0] = moving_status(0, 51_200, 0, 2_047);
    app.handle(axterm::ui::app::AppEvent::Snapshot(s.clone()));
    let before = screen(&mut app, 100, 30)[1].clone();
    s.status[0].position = Some(25_600);
    app.handle(axterm::ui::app::AppEvent::Snapshot(s.clone()));
    let half = screen(&mut app, 100, 30)[1].clone();
    let filled = |line: &str| line.chars().filter(|&c| c == '█').count();
    assert_eq!(filled(&before), 0, "{before}");
    assert!(filled(&half) > 0, "{half}");
    assert!(half.contains('┃'), "the target is marked: {half}");
    s.status[0].position = Some(51_200);
    s.status[0].reached = Some(true);
    s.status[0].speed = Some(0);
    app.handle(axterm::ui::app::AppEvent::Snapshot(s));
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
