use super::*;
use crate::ui::keymap::Keymap;
use crate::ui::theme::Theme;

/// The default theme and keys, for the pane's views.
struct Looks {
    theme: Theme,
    keymap: Keymap,
}

impl Default for Looks {
    fn default() -> Looks {
        Looks {
            theme: Theme::builtin("dark").expect("theme"),
            keymap: Keymap::builtin("default").expect("keymap"),
        }
    }
}

impl Looks {
    /// The pane's view of `session` alone, shown, `focused` or not.
    fn view<'a>(&'a self, session: Option<&'a Snapshot>, focused: bool) -> View<'a> {
        View {
            theme: &self.theme,
            keymap: &self.keymap,
            session,
            modules: &[],
            module: 0,
            focused,
            shown: true,
        }
    }
}

fn snapshot() -> Snapshot {
    let family = find_family("tmcl").expect("tmcl");
    Snapshot {
        family,
        address: 1,
        link_name: "sim".into(),
        axes: family.console.axes().to_vec(),
        status: Vec::new(),
        link: LinkState::Closed,
        identity: None,
        poll: None,
        settings: Default::default(),
        mechanics: Default::default(),
        axis: 0,
    }
}

fn cmd4cr_snapshot() -> Snapshot {
    let family = find_family("cmd4cr").expect("cmd4cr");
    Snapshot {
        family,
        axes: family.console.axes().to_vec(),
        ..snapshot()
    }
}

#[test]
fn help_offline_follows_the_connect_screen_only_while_nothing_is_connected() {
    let looks = Looks::default();
    let connected = snapshot();
    let view = |session| looks.view(session, false);
    let mut pane = CommandPane::new(None);
    // No recent connection: the connect screen's first simulator's.
    assert_eq!(pane.offline_family, Some("tmcl"));
    pane.on_event(&PaneEvent::FamilyChosen("other"), &view(None));
    assert_eq!(pane.offline_family, Some("other"));
    // A family with no tables here: TMCL's help rather than none.
    assert_eq!(pane.family(&view(None)).map(|f| f.name), Some("tmcl"));
    // Connected: the module's family, whatever the connect screen shows.
    pane.on_event(&PaneEvent::Snapshot, &view(Some(&connected)));
    pane.on_event(&PaneEvent::FamilyChosen("other"), &view(Some(&connected)));
    assert_eq!(pane.offline_family, Some("tmcl"));
    assert_eq!(
        pane.family(&view(Some(&connected))).map(|f| f.name),
        Some("tmcl")
    );
}

#[test]
fn run_ascript_wants_a_cmd4cr_module_and_a_file_and_parses_prg_numbers() {
    let looks = Looks::default();
    let tmcl = snapshot();
    let cmd4cr = cmd4cr_snapshot();
    let view = |session| looks.view(session, true);
    let mut pane = CommandPane::new(None);
    let last = |pane: &CommandPane| pane.output_lines().last().unwrap_or("").to_string();
    pane.console_command(":run-ascript p.asc", &view(None));
    assert!(last(&pane).starts_with("not connected"), "{}", last(&pane));
    pane.console_command(":run-ascript p.asc", &view(Some(&tmcl)));
    assert!(
        last(&pane).contains("this module speaks tmcl"),
        "{}",
        last(&pane)
    );
    pane.console_command(":run-ascript", &view(Some(&cmd4cr)));
    assert!(last(&pane).contains("needs a file name"), "{}", last(&pane));
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("two programs.asc");
    std::fs::write(&file, "PRG 0\n    DO1=1\nEND\nPRG 2\n    DO2=1\nEND\n").expect("write");
    let outcome = pane.console_command(
        &format!(":run-ascript {} 2", file.display()),
        &view(Some(&cmd4cr)),
    );
    assert!(
        pane.output_lines()
            .any(|l| l.contains("from the host: PRG 2 (Esc stops it")),
        "{:?}",
        pane.output_lines().collect::<Vec<_>>()
    );
    let Outcome::Handled(requests) = outcome else {
        panic!("started");
    };
    assert!(
        matches!(requests.as_slice(), [Request::Send { lines, .. }] if lines == &["DO2=1".to_string()]),
        "{requests:?}"
    );
    assert!(pane.activity().is_some_and(|a| a.ends_with("PRG 2 line 5")));
    // One at a time; a batch waits too.
    pane.console_command(":run-ascript other.asc", &view(Some(&cmd4cr)));
    assert!(
        last(&pane).contains("a host run is going"),
        "{}",
        last(&pane)
    );
    pane.console_command(":sleep 1s", &view(Some(&cmd4cr)));
    assert!(
        last(&pane).contains("a host run is going"),
        "{}",
        last(&pane)
    );
}

#[test]
fn sim_input_completes_the_simulators_input_names() {
    let looks = Looks::default();
    let cmd4cr = cmd4cr_snapshot();
    let tmcl = snapshot();
    let view = |session| looks.view(session, true);
    let mut pane = CommandPane::new(None);
    pane.set_input(":sim-input alm".into());
    let offered = pane.completions(&view(Some(&cmd4cr)));
    let texts: Vec<&str> = offered.candidates.iter().map(|c| c.text.as_str()).collect();
    assert_eq!(texts, ["ALMX=", "ALMY=", "ALMZ=", "ALMU="]);
    assert_eq!((offered.start, offered.end), (11, 14));
    pane.set_input(":sim-input IN".into());
    let offered = pane.completions(&view(Some(&tmcl)));
    assert_eq!(offered.candidates.len(), 6, "IN1..IN6");
    // The request carries the setting as typed; the simulator reads it.
    let outcome = pane.console_command(":sim-input  io5=1 ", &view(Some(&cmd4cr)));
    assert_eq!(
        outcome,
        Outcome::request(Request::DriveSimInput("io5=1".into()))
    );
    pane.console_command(":sim-input IO5=1", &view(None));
    assert!(
        pane.output_lines()
            .last()
            .is_some_and(|l| l.starts_with("not connected")),
    );
}

#[test]
fn report_reads_the_settings_first_and_a_failed_read_still_writes_the_sheet() {
    let looks = Looks::default();
    let connected = snapshot();
    let view = looks.view(Some(&connected), true);
    let dir = tempfile::tempdir().expect("temp dir");
    let recording = dir.path().join("session.txt");
    let sheet = dir.path().join("sheet.html");
    let mut pane = CommandPane::new(None);
    let last = |pane: &CommandPane| pane.output_lines().last().unwrap_or("").to_string();
    pane.console_command(&format!(":record {}", recording.display()), &view);
    assert!(
        last(&pane).contains("recording the session"),
        "{}",
        last(&pane)
    );
    let asked = pane.console_command(&format!(":report {}", sheet.display()), &view);
    let Outcome::Handled(requests) = asked else {
        panic!("{}", last(&pane))
    };
    let [Request::ReadSettings { tag, .. }] = requests.as_slice() else {
        panic!("{requests:?}")
    };
    assert!(
        last(&pane).contains("reading the settings"),
        "{}",
        last(&pane)
    );
    // Nothing is written until the read ends, and one sheet at a time.
    assert!(!sheet.exists());
    pane.console_command(&format!(":report {}", sheet.display()), &view);
    assert!(
        last(&pane).contains("still reading the settings"),
        "{}",
        last(&pane)
    );
    // A reply under another tag is not this read's.
    let other = PaneEvent::SettingsRead {
        tag: tag + 100,
        result: Err("no".into()),
    };
    assert_eq!(pane.on_event(&other, &view), Outcome::Ignored);
    let failed = PaneEvent::SettingsRead {
        tag: *tag,
        result: Err("the link is down".into()),
    };
    pane.on_event(&failed, &view);
    let page = std::fs::read_to_string(&sheet).expect("the sheet was written");
    assert!(
        page.contains("Settings read</th><td>not read (the link is down)"),
        "{page}"
    );
    let said: Vec<&str> = pane.output_lines().collect();
    assert!(
        said.iter()
            .any(|l| l.contains("the settings were not read (the link is down)")),
        "{said:?}"
    );
    assert!(last(&pane).contains("the sheet of the session so far is in"));
}

#[test]
fn the_emergency_stop_during_a_reports_settings_read_writes_its_sheet() {
    let looks = Looks::default();
    let connected = snapshot();
    let view = looks.view(Some(&connected), true);
    let dir = tempfile::tempdir().expect("temp dir");
    let sheet = dir.path().join("sheet.json");
    let mut pane = CommandPane::new(None);
    pane.console_command(
        &format!(":record {}", dir.path().join("s.txt").display()),
        &view,
    );
    pane.console_command(&format!(":report {}", sheet.display()), &view);
    assert!(!sheet.exists());
    // The stop aborts the read's task: its answer never comes.
    pane.on_event(&PaneEvent::Stopping, &view);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&sheet).expect("written")).expect("JSON");
    assert_eq!(
        json["modules"][0]["settings"]["read"],
        "not read (the emergency stop ended the read)"
    );
    // And the next :report goes.
    pane.console_command(&format!(":report --force {}", sheet.display()), &view);
    let said: Vec<&str> = pane.output_lines().collect();
    assert!(
        said.last()
            .is_some_and(|l| l.contains("reading the settings")),
        "{said:?}"
    );
}
