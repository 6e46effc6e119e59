//! The parameter table inside the console, against the TMCM-1110
//! simulator: reading a row at a time, drawing at 80×24 and large, editing
//! with validation before anything is sent, store and restore, the filter,
//! changed values highlighted, export and import with the diff shown first.

mod panes_support;
mod ui_support;

use axterm::families::find_family;
use axterm::ui::app::{App, AppEvent, Effect};
use axterm::ui::keymap::Keymap;
use axterm::ui::theme::{Role, Theme};
use axterm::ui::{PaneSetup, panes};
use panes_support::{SimModule, draw, serve, style_of};
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use ui_support::{key, key_with, snapshot, type_text};

fn tmcl_snapshot() -> axterm::ui::pane::Snapshot {
    let family = find_family("tmcl").expect("tmcl");
    snapshot(family.console.axes().to_vec())
}

fn console(keymap: &str) -> App {
    let theme = Theme::builtin("dark").expect("theme");
    let keymap = Keymap::builtin(keymap).expect("keymap");
    App::new(panes(&PaneSetup::default()), theme, keymap)
}

/// A console connected to a simulated module, the parameter pane focused
/// and every parameter read.
fn reading(keymap: &str) -> (App, SimModule, panes_support::Served) {
    let mut app = console(keymap);
    let mut module = SimModule::new();
    app.handle(AppEvent::Snapshot(tmcl_snapshot()));
    let effects = app.handle(key_with(KeyCode::Char('3'), KeyModifiers::ALT));
    assert_eq!(app.focused(), Some("params"));
    let served = serve(&mut app, &mut module, effects);
    (app, module, served)
}

fn press(app: &mut App, module: &mut SimModule, code: KeyCode) -> panes_support::Served {
    let effects = app.handle(key(code));
    serve(app, module, effects)
}

fn typed(app: &mut App, module: &mut SimModule, text: &str) -> panes_support::Served {
    let effects = type_text(app, text);
    serve(app, module, effects)
}

fn filter(app: &mut App, module: &mut SimModule, text: &str) {
    press(app, module, KeyCode::Char('/'));
    // The field starts with the filter in force.
    typed_clear(app);
    typed(app, module, text);
    press(app, module, KeyCode::Enter);
}

fn screen_text(app: &mut App, w: u16, h: u16) -> String {
    draw(app, w, h).0.join("\n")
}

#[test]
fn focusing_reads_every_parameter_one_row_at_a_time() {
    let (_app, module, served) = reading("default");
    assert_eq!(served.most_at_once, 1, "one line at a time");
    assert_eq!(served.lines.first().map(String::as_str), Some("GAP 0, 0"));
    assert!(served.lines.contains(&"GAP 154, 0".to_string()));
    assert!(served.lines.contains(&"GGP 66, 0".to_string()));
    assert!(served.lines.contains(&"GGP 255, 2".to_string()));
    assert!(served.lines.contains(&"GGP 44, 3".to_string()));
    // Nothing is read twice, nothing written.
    let mut sorted = served.lines.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), served.lines.len());
    assert!(
        module
            .lines
            .iter()
            .all(|l| l.starts_with("GAP") || l.starts_with("GGP"))
    );
}

#[test]
fn the_table_at_80x24_shows_values_units_and_real_speeds() {
    let (mut app, mut module, _) = reading("default");
    filter(&mut app, &mut module, "speed");
    let (lines, _) = draw(&mut app, 80, 24);
    let text = lines.join("\n");
    assert!(
        text.contains("3 PARAMETERS") || text.contains("3 Parameters"),
        "{text}"
    );
    assert!(text.contains("No Name"), "{text}");
    assert!(text.contains("── Axis parameters: motor 0 ──"), "{text}");
    let row = lines
        .iter()
        .find(|l| l.contains("Maximum positioning speed"))
        .unwrap_or_else(|| panic!("no AP4 row:\n{text}"));
    // The simulator's AP4 with its pulse divisor, in pps (§6.1.1).
    let value = module_value(&mut module, "GAP 4, 0");
    assert!(row.contains(&value), "{row}");
    assert!(row.contains("int (vel)") && row.contains("pps"), "{row}");
    assert!(row.contains("RWE"), "{row}");
    assert!(text.contains("filter \"speed\""), "{text}");
    // The selected row's range and the keys in the footer.
    assert!(text.contains("Enter edit"), "{text}");
}

fn module_value(module: &mut SimModule, line: &str) -> String {
    module.answer(line).expect("answer").value.to_string()
}

#[test]
fn the_table_at_a_large_size_has_range_and_description_columns() {
    let (mut app, _module, _) = reading("default");
    // Wide enough that the parameter column, beside traffic and plot, has
    // room for every column.
    let (lines, _) = draw(&mut app, 250, 60);
    let text = lines.join("\n");
    assert!(
        text.contains("Range") && text.contains("Description"),
        "{text}"
    );
    let row = lines
        .iter()
        .find(|l| l.contains("Target position"))
        .expect("AP0 row");
    assert!(row.contains("-2147483648..2147483647"), "{row}");
    assert!(row.contains("The desired target position"), "{row}");
    // More rows than at 80×24: the whole axis table down to AP175.
    assert!(text.contains("175 Slope control high side"), "{text}");
}

#[test]
fn rpm_replace_pps_when_units_are_toggled() {
    let (mut app, mut module, _) = reading("default");
    filter(&mut app, &mut module, "maximum positioning");
    assert!(screen_text(&mut app, 80, 24).contains(" pps"));
    press(&mut app, &mut module, KeyCode::Char('u'));
    let text = screen_text(&mut app, 80, 24);
    assert!(
        text.contains(" rpm") && text.contains("real: rpm"),
        "{text}"
    );
}

#[test]
fn an_out_of_range_value_is_refused_before_anything_is_sent() {
    let (mut app, mut module, _) = reading("default");
    filter(&mut app, &mut module, "maximum positioning");
    press(&mut app, &mut module, KeyCode::Enter);
    // The editor starts with the value read; replace it.
    typed_clear(&mut app);
    let sent = {
        let mut effects = type_text(&mut app, "5000");
        effects.extend(app.handle(key(KeyCode::Enter)));
        effects
    };
    assert!(!sent.iter().any(|e| e.sends().is_some()), "{sent:?}");
    let text = screen_text(&mut app, 80, 24);
    assert!(
        text.contains("takes 1..2047, not 5000: nothing sent"),
        "{text}"
    );
    // Not a number either.
    typed_clear(&mut app);
    let effects = type_text(&mut app, "fast");
    assert!(effects.is_empty());
    assert!(app.handle(key(KeyCode::Enter)).is_empty());
    assert!(screen_text(&mut app, 80, 24).contains("`fast` is not a number"));
    // Esc leaves the editor; nothing was sent at all.
    app.handle(key(KeyCode::Esc));
    assert!(!module.lines.iter().any(|l| l.starts_with("SAP")));
}

fn typed_clear(app: &mut App) {
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
    app.handle(key(KeyCode::End));
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
}

#[test]
fn a_write_is_sent_read_back_and_highlighted_as_changed() {
    let (mut app, mut module, _) = reading("default");
    filter(&mut app, &mut module, "maximum positioning");
    press(&mut app, &mut module, KeyCode::Enter);
    typed_clear(&mut app);
    typed(&mut app, &mut module, "1234");
    let served = press(&mut app, &mut module, KeyCode::Enter);
    assert_eq!(served.lines, ["SAP 4, 0, 1234", "GAP 4, 0"]);
    assert_eq!(module_value(&mut module, "GAP 4, 0"), "1234");
    // Move the selection off the row so that the highlight is not the
    // selection's.
    filter(&mut app, &mut module, "speed");
    let (lines, buffer) = draw(&mut app, 80, 24);
    let theme = Theme::builtin("dark").expect("theme");
    let changed = style_of(&lines, &buffer, "Maximum positioning speed", "1234").expect("row");
    assert_eq!(changed.fg, theme.style(Role::Changed).fg, "{lines:#?}");
    assert!(
        lines.iter().any(|l| l.contains("SAP 4, 0, 1234: ok")),
        "{lines:#?}"
    );
    // An unchanged value is not highlighted.
    let (row, value) = lines
        .iter()
        .find(|l| l.contains("Minimum speed"))
        .map(|l| {
            (
                l.clone(),
                l.split_whitespace().rev().nth(3).unwrap_or("").to_string(),
            )
        })
        .expect("AP130 row");
    let plain = style_of(&lines, &buffer, &row, &value).expect("cell");
    assert_ne!(plain.fg, theme.style(Role::Changed).fg, "{row}");
}

#[test]
fn writing_a_typed_speed_in_pps_converts_it() {
    let (mut app, mut module, _) = reading("default");
    filter(&mut app, &mut module, "maximum positioning");
    // Pulse divisor 3 (set here) and §6.1.1: 51208.5 pps is 1678.
    module.answer("SAP 154, 0, 3").expect("pulse divisor");
    press(&mut app, &mut module, KeyCode::F(5));
    filter(&mut app, &mut module, "pulse divisor");
    press(&mut app, &mut module, KeyCode::F(5));
    filter(&mut app, &mut module, "maximum positioning");
    press(&mut app, &mut module, KeyCode::Enter);
    typed_clear(&mut app);
    typed(&mut app, &mut module, "51208.5 pps");
    let served = press(&mut app, &mut module, KeyCode::Enter);
    assert_eq!(
        served.lines.first().map(String::as_str),
        Some("SAP 4, 0, 1678")
    );
}

#[test]
fn store_and_restore_send_their_lines_and_refuse_what_cannot_be_stored() {
    let (mut app, mut module, _) = reading("default");
    filter(&mut app, &mut module, "maximum positioning");
    let served = press(&mut app, &mut module, KeyCode::Char('s'));
    assert_eq!(served.lines, ["STAP 4, 0"]);
    assert!(screen_text(&mut app, 80, 24).contains("STAP 4, 0: stored in EEPROM"));
    let served = press(&mut app, &mut module, KeyCode::Char('r'));
    assert_eq!(served.lines, ["RSAP 4, 0", "GAP 4, 0"]);
    // The run current is stored, as the manual's STAP example stores it.
    filter(&mut app, &mut module, "maximum current");
    let served = press(&mut app, &mut module, KeyCode::Char('s'));
    assert_eq!(served.lines, ["STAP 6, 0"]);
    assert!(screen_text(&mut app, 80, 24).contains("STAP 6, 0: stored in EEPROM"));
    // AP7 has no EEPROM copy (§4 Table 16: RW): nothing is sent.
    filter(&mut app, &mut module, "standby current");
    let served = press(&mut app, &mut module, KeyCode::Char('s'));
    assert!(served.lines.is_empty());
    assert!(screen_text(&mut app, 80, 24).contains("no EEPROM copy"));
    // User variables of bank 2 go through STGP/RSGP.
    filter(&mut app, &mut module, "user variable #5");
    let served = press(&mut app, &mut module, KeyCode::Char('s'));
    assert_eq!(served.lines, ["STGP 5, 2"]);
    let served = press(&mut app, &mut module, KeyCode::Char('r'));
    assert_eq!(served.lines, ["RSGP 5, 2", "GGP 5, 2"]);
}

#[test]
fn the_filter_keeps_matching_rows_and_esc_clears_it() {
    let (mut app, mut module, _) = reading("default");
    filter(&mut app, &mut module, "divisor");
    let text = screen_text(&mut app, 80, 24);
    assert!(
        text.contains("Ramp divisor") && text.contains("Pulse divisor"),
        "{text}"
    );
    assert!(!text.contains("Maximum current"), "{text}");
    assert!(text.contains("2 parameters"), "{text}");
    // A number finds its row (and names with it).
    filter(&mut app, &mut module, "206");
    let text = screen_text(&mut app, 80, 24);
    assert!(text.contains("2 parameters"), "{text}");
    assert!(
        text.contains(" 206 Actual load value") && text.contains("User variable #206"),
        "{text}"
    );
    press(&mut app, &mut module, KeyCode::Esc);
    let text = screen_text(&mut app, 80, 24);
    assert!(!text.contains("filter \""), "{text}");
    assert!(text.contains("Target position"), "{text}");
}

#[test]
fn typing_a_filter_in_the_vim_keymap_does_not_quit() {
    let (mut app, mut module, _) = reading("vim");
    press(&mut app, &mut module, KeyCode::Char('/'));
    let effects = type_text(&mut app, "sq");
    assert!(!effects.contains(&Effect::Quit), "{effects:?}");
    assert!(!app.should_quit());
    assert!(screen_text(&mut app, 80, 24).contains("filter: sq"));
}

#[test]
fn an_unreadable_parameter_is_shown_as_such() {
    let mut app = console("default");
    let mut module = SimModule::new();
    module.refuse.push("GAP 6, 0".into());
    app.handle(AppEvent::Snapshot(tmcl_snapshot()));
    let effects = app.handle(key_with(KeyCode::Char('3'), KeyModifiers::ALT));
    serve(&mut app, &mut module, effects);
    filter(&mut app, &mut module, "maximum current");
    let text = screen_text(&mut app, 80, 24);
    assert!(text.contains("unreadable"), "{text}");
    assert!(text.contains("invalid command"), "{text}");
}

#[test]
fn the_emergency_stop_drops_the_reads_still_waiting() {
    let mut app = console("default");
    app.handle(AppEvent::Snapshot(tmcl_snapshot()));
    let effects = app.handle(key_with(KeyCode::Char('3'), KeyModifiers::ALT));
    assert_eq!(effects.iter().filter(|e| e.sends().is_some()).count(), 1);
    let effects = app.handle(key(KeyCode::F(12)));
    assert!(effects.contains(&Effect::EmergencyStop));
    assert!(screen_text(&mut app, 80, 24).contains("parameter lines not sent"));
    // Refresh starts again from the top.
    let effects = app.handle(key(KeyCode::F(5)));
    assert!(
        effects
            .iter()
            .any(|e| e.sends().is_some_and(|(_, _, lines)| lines == ["GAP 0, 0"]))
    );
}

#[test]
fn export_then_import_shows_the_difference_and_writes_only_when_asked() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("rig.toml");
    let (mut app, mut module, _) = reading("default");
    let original = module_value(&mut module, "GAP 4, 0");
    // Export.
    press(&mut app, &mut module, KeyCode::Char('e'));
    typed_clear(&mut app);
    typed(&mut app, &mut module, &path.display().to_string());
    let served = press(&mut app, &mut module, KeyCode::Enter);
    assert!(
        served.lines.contains(&"GAP 4, 0".to_string()),
        "fresh values are read"
    );
    assert!(
        !served.lines.contains(&"GAP 1, 0".to_string()),
        "positions are not settings"
    );
    let text = std::fs::read_to_string(&path).expect("exported");
    assert!(text.contains("family = \"tmcl\""), "{text}");
    assert!(
        text.contains(&format!("4 = {original}  # Maximum positioning speed")),
        "{text}"
    );
    assert!(screen_text(&mut app, 80, 24).contains("exported"));
    // Someone changes the module.
    module.answer("SAP 4, 0, 77").expect("write");
    // Import: the difference is shown, nothing written yet.
    press(&mut app, &mut module, KeyCode::Char('i'));
    typed_clear(&mut app);
    typed(&mut app, &mut module, &path.display().to_string());
    let served = press(&mut app, &mut module, KeyCode::Enter);
    assert!(
        served
            .lines
            .iter()
            .all(|l| l.starts_with("GAP") || l.starts_with("GGP"))
    );
    let text = screen_text(&mut app, 100, 30);
    assert!(text.contains("1 differ"), "{text}");
    assert!(
        text.contains(&format!("module          77 → file {original:>11}")),
        "{text}"
    );
    // w writes the file's value and reads it back.
    let served = press(&mut app, &mut module, KeyCode::Char('w'));
    assert_eq!(
        served.lines,
        [format!("SAP 4, 0, {original}"), "GAP 4, 0".into()]
    );
    assert_eq!(module_value(&mut module, "GAP 4, 0"), original);
    assert!(screen_text(&mut app, 80, 24).contains("wrote 1 value from"));
    // Compared again: nothing differs.
    press(&mut app, &mut module, KeyCode::Char('d'));
    typed_clear(&mut app);
    typed(&mut app, &mut module, &path.display().to_string());
    press(&mut app, &mut module, KeyCode::Enter);
    let text = screen_text(&mut app, 100, 30);
    assert!(text.contains("0 differ"), "{text}");
    assert!(
        text.contains("the module holds every value of the file"),
        "{text}"
    );
}

#[test]
fn a_diff_only_shows_and_problems_in_the_file_are_listed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("odd.toml");
    std::fs::write(
        &path,
        "family = \"tmcl\"\n[axis.0]\n4 = 5\n6 = 999\n1 = 0\n200 = 1\n250 = 3\n[bank.0]\n66 = 9\n",
    )
    .expect("write file");
    let (mut app, mut module, _) = reading("default");
    press(&mut app, &mut module, KeyCode::Char('d'));
    typed_clear(&mut app);
    typed(&mut app, &mut module, &path.display().to_string());
    press(&mut app, &mut module, KeyCode::Enter);
    let text = screen_text(&mut app, 120, 40);
    assert!(text.contains("Compare"), "{text}");
    assert!(text.contains("999 is outside 0..255"), "{text}");
    assert!(text.contains("Actual position: not a setting"), "{text}");
    assert!(text.contains("[axis.0] 250: no such parameter"), "{text}");
    assert!(text.contains("(link setting: not written)"), "{text}");
    // w does nothing in a diff; Esc closes it.
    let served = press(&mut app, &mut module, KeyCode::Char('w'));
    assert!(served.lines.is_empty());
    press(&mut app, &mut module, KeyCode::Esc);
    assert!(screen_text(&mut app, 80, 24).contains("No Name"));
}

#[test]
fn a_file_for_another_family_or_not_toml_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let other = dir.path().join("other.toml");
    std::fs::write(&other, "family = \"mccl\"\n").expect("write");
    let broken = dir.path().join("broken.toml");
    std::fs::write(&broken, "[axis.0\n").expect("write");
    let (mut app, mut module, _) = reading("default");
    for (path, says) in [
        (other, "holds mccl parameters"),
        (broken, "is not a parameter file: line 1"),
        (dir.path().join("missing.toml"), "cannot read"),
    ] {
        press(&mut app, &mut module, KeyCode::Char('i'));
        typed_clear(&mut app);
        typed(&mut app, &mut module, &path.display().to_string());
        let served = press(&mut app, &mut module, KeyCode::Enter);
        assert!(served.lines.is_empty());
        let text = screen_text(&mut app, 120, 30);
        assert!(text.contains(says), "{says}: {text}");
    }
}

#[test]
fn not_connected_the_pane_says_so() {
    let mut app = console("default");
    app.focus("params");
    let text = screen_text(&mut app, 80, 24);
    assert!(text.contains("not connected"), "{text}");
    assert!(app.handle(key(KeyCode::F(5))).is_empty());
}

/// The table's reads ask for a value two answers agree on (the session
/// reads once where the family has a checksum); its writes are plain sends.
#[test]
fn the_table_reads_values_two_answers_agree_on_and_writes_plainly() {
    let mut app = console("default");
    app.handle(AppEvent::Snapshot(tmcl_snapshot()));
    let effects = app.handle(key_with(KeyCode::Char('3'), KeyModifiers::ALT));
    assert!(
        effects
            .iter()
            .any(|e| matches!(e, Effect::ReadAgreed { line, .. } if line == "GAP 0, 0")),
        "{effects:?}"
    );
    assert!(
        !effects.iter().any(|e| matches!(e, Effect::Send { .. })),
        "{effects:?}"
    );
}

/// With mechanics in force the units key goes on from rpm to the axes'
/// own units: the maximum positioning speed in mm/s by §6.1.1 with the
/// pulse divisor read in the table.
#[test]
fn with_mechanics_the_real_column_shows_the_axis_own_units() {
    let mut app = console("default");
    let mut module = SimModule::new();
    for line in ["SAP 140, 0, 8", "SAP 154, 0, 3", "SAP 4, 0, 1678"] {
        module.answer(line).expect("the simulator takes it");
    }
    let mut s = tmcl_snapshot();
    let (mechanics, _) = axterm::protocol::units::MechanicsTable::parse_file(
        "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\ntravel_per_rev = 5\n",
    )
    .expect("mechanics");
    s.mechanics = std::sync::Arc::new(mechanics);
    app.handle(AppEvent::Snapshot(s));
    let effects = app.handle(key_with(KeyCode::Char('3'), KeyModifiers::ALT));
    serve(&mut app, &mut module, effects);
    filter(&mut app, &mut module, "maximum positioning");
    press(&mut app, &mut module, KeyCode::Char('u'));
    press(&mut app, &mut module, KeyCode::Char('u'));
    let text = screen_text(&mut app, 100, 30);
    // 1678 [int] at divisor 3 ≈ 51208.5 pps; 10240 µsteps a mm.
    assert!(
        text.contains("5.001 mm/s") && text.contains("real: axis units"),
        "{text}"
    );
    press(&mut app, &mut module, KeyCode::Char('u'));
    assert!(screen_text(&mut app, 100, 30).contains("real: pps"));
}
