//! The program editor's A-Script mode (CMD-4CR §5): chosen by a `.asc`
//! file, by a CMD-4CR connection or by its key; colours from the A-Script
//! token classes, the checker's errors at their lines; the download key
//! honest about what the manual leaves out, loading the in-process
//! simulator instead; run control over the wire (SACTRL, SASTAT, SPC,
//! V); and the text run from the host, which the emergency stop ends.

mod ui_support;

use std::path::Path;
use std::sync::Arc;

use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::families::find_family;
use axterm::link::LinkSpec;
use axterm::session::Session;
use axterm::ui::PaneSetup;
use axterm::ui::app::{App, AppEvent, Controller, Effect};
use axterm::ui::live::SessionController;
use axterm::ui::pane::Snapshot;
use axterm::ui::theme::Role;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{Event, KeyCode, KeyModifiers};
use ui_support::looped::{Rig, no_connector, press, press_with, run_console_on};
use ui_support::{console_with, key, key_with, screen};

const EXAMPLE_1: &str = "PRG 0                ;Program start line, program 0\n    HSPD=20000       ;Set high speed\n    EO=1\n    X1000\n    WAITX\n    V1=PX\nEND\n";

fn editor_console() -> App {
    let mut app = console_with(&PaneSetup::default());
    assert!(app.focus("editor"));
    app
}

fn paste(app: &mut App, text: &str) -> Vec<Effect> {
    app.handle(AppEvent::Terminal(Event::Paste(text.to_string())))
}

/// Open `path` with F3 and the prompt.
fn open(app: &mut App, path: &Path) {
    app.handle(key(KeyCode::F(3)));
    paste(app, &path.display().to_string());
    app.handle(key(KeyCode::Enter));
}

fn cmd4cr_snapshot() -> Snapshot {
    let family = find_family("cmd4cr").expect("cmd4cr");
    Snapshot {
        family,
        link_name: "/dev/ttyUSB0 at 9600 Bd".into(),
        axes: family.console.axes().to_vec(),
        status: vec![Default::default(); family.console.axes().len()],
        ..ui_support::snapshot(Vec::new())
    }
}

fn text(lines: &[String]) -> String {
    lines.join("\n")
}

#[test]
fn an_asc_file_is_coloured_and_checked_as_a_script() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("example.asc");
    std::fs::write(
        &path,
        "PRG 0 ;start\n    HSPD=20000\n    V200=1\n    GOSUB 4\n    IF V1<10\n    ENDIF\nEND\n",
    )
    .expect("write");
    let mut app = editor_console();
    open(&mut app, &path);
    app.handle(key(KeyCode::Esc));
    let mut terminal = Terminal::new(TestBackend::new(100, 30)).expect("backend");
    terminal.draw(|f| app.render(f)).expect("draw");
    let buffer = terminal.backend().buffer().clone();
    let rows: Vec<String> = (0..30u16)
        .map(|y| {
            (0..100u16)
                .map(|x| buffer[(x, y)].symbol().to_string())
                .collect()
        })
        .collect();
    let find = |needle: &str| -> (u16, u16) {
        for (y, row) in rows.iter().enumerate() {
            if let Some(at) = row.find(needle) {
                let x = row.get(..at).map_or(0, |b| b.chars().count());
                return (u16::try_from(x).unwrap_or(0), u16::try_from(y).unwrap_or(0));
            }
        }
        panic!("{needle} not on screen:\n{}", rows.join("\n"));
    };
    let theme = app.theme().clone();
    let fg = |role: Role| theme.style(role).fg;
    let cell = |at: (u16, u16)| Some(buffer[at].fg);
    assert_eq!(cell(find("PRG")), fg(Role::CodeLabel));
    assert_eq!(cell(find("HSPD")), fg(Role::CodeMnemonic));
    assert_eq!(cell(find("20000")), fg(Role::CodeNumber));
    assert_eq!(cell(find(";start")), fg(Role::CodeComment));
    let all = rows.join("\n");
    assert!(all.contains("Program (A-Script) — example.asc"), "{all}");
    // Line 3 is an error (Table 5-43), line 4 a warning (GOSUB to a SUB
    // the file lacks: an error only when it runs).
    let third = rows.iter().find(|r| r.contains("V200=1")).expect("line 3");
    assert!(third.contains("!  3"), "{third}");
    let fourth = rows.iter().find(|r| r.contains("GOSUB 4")).expect("line 4");
    assert!(fourth.contains("?  4"), "{fourth}");
    assert!(all.contains("1 error (Ctrl-G next)"), "{all}");
    // Ctrl-G: to the error, then the warning, each said in the bottom line.
    app.handle(key_with(KeyCode::Char('g'), KeyModifiers::CONTROL));
    let lines = screen(&mut app, 100, 30);
    assert!(
        text(&lines).contains("line 3: Var Range Error"),
        "{}",
        text(&lines)
    );
    app.handle(key_with(KeyCode::Char('g'), KeyModifiers::CONTROL));
    let lines = screen(&mut app, 100, 30);
    assert!(text(&lines).contains("line 4: warning"), "{}", text(&lines));
}

#[test]
fn a_clean_text_says_what_it_holds() {
    let mut app = editor_console();
    app.handle(key_with(KeyCode::Char('l'), KeyModifiers::CONTROL));
    app.handle(key(KeyCode::Esc));
    paste(&mut app, "PRG 1\nEND\nSUB 31\nENDSUB\n");
    let lines = screen(&mut app, 100, 30);
    assert!(
        text(&lines).contains("untitled [modified] — A-Script checks: PRG 1; SUB 31"),
        "{}",
        text(&lines)
    );
    // F9 checks and says the same.
    app.handle(key(KeyCode::F(9)));
    let lines = screen(&mut app, 100, 30);
    assert!(
        text(&lines).contains("checks: PRG 1; SUB 31"),
        "{}",
        text(&lines)
    );
}

#[test]
fn the_language_follows_a_cmd4cr_connection_unless_the_file_or_the_key_chose() {
    let mut app = editor_console();
    paste(&mut app, "PRG 0\nEND\n");
    assert!(text(&screen(&mut app, 100, 30)).contains("Program — untitled*"));
    app.handle(AppEvent::Connected(cmd4cr_snapshot()));
    let all = text(&screen(&mut app, 100, 30));
    assert!(all.contains("Program (A-Script) — untitled*"), "{all}");
    assert!(all.contains("A-Script checks: PRG 0"), "{all}");
    // The key switches (through every language there is, back to TMCL),
    // and then a connection no longer does.
    let mut all = String::new();
    for _ in 0..axterm::ui::editor::language::registered_tools().len() {
        app.handle(key_with(KeyCode::Char('l'), KeyModifiers::CONTROL));
        all = text(&screen(&mut app, 100, 30));
        if all.contains("the text is TMCL now") {
            break;
        }
    }
    assert!(all.contains("the text is TMCL now"), "{all}");
    assert!(all.contains("Program — untitled*"), "{all}");
    app.handle(AppEvent::Connected(cmd4cr_snapshot()));
    assert!(text(&screen(&mut app, 100, 30)).contains("Program — untitled*"));
    // A .tmc file is TMCL whatever is connected.
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("p.tmc");
    std::fs::write(&path, "STOP\n").expect("write");
    let mut app = editor_console();
    open(&mut app, &path);
    app.handle(AppEvent::Connected(cmd4cr_snapshot()));
    assert!(text(&screen(&mut app, 100, 30)).contains("Program — p.tmc"));
}

#[test]
fn the_download_key_says_what_the_manual_leaves_out_and_loads_a_simulator() {
    let mut app = editor_console();
    app.handle(key_with(KeyCode::Char('l'), KeyModifiers::CONTROL));
    paste(&mut app, EXAMPLE_1);
    // Not connected.
    app.handle(key(KeyCode::F(4)));
    let all = text(&screen(&mut app, 159, 30));
    assert!(
        all.contains("documents no program download over the wire (§2.7.7, §5.1.5)"),
        "{all}"
    );
    // Connected: the loop is asked to load it; a real controller refuses.
    app.handle(AppEvent::Connected(cmd4cr_snapshot()));
    let effects = app.handle(key(KeyCode::F(4)));
    let Some(Effect::LoadProgram { pane, tag, source }) = effects
        .iter()
        .find(|e| matches!(e, Effect::LoadProgram { .. }))
        .cloned()
    else {
        panic!("no load asked for: {effects:?}");
    };
    assert_eq!(source.trim_end(), EXAMPLE_1.trim_end());
    app.handle(AppEvent::ProgramLoaded {
        pane,
        tag,
        result: Err("/dev/ttyUSB0 at 9600 Bd is no simulator in this process".into()),
    });
    let all = text(&screen(&mut app, 159, 30));
    assert!(
        all.contains("(§2.7.7, §5.1.5): Ctrl-F5 runs this text from the host"),
        "{all}"
    );
    // A text that does not check is not loaded.
    paste(&mut app, "    V200=1\n");
    let effects = app.handle(key(KeyCode::F(4)));
    assert!(
        !effects
            .iter()
            .any(|e| matches!(e, Effect::LoadProgram { .. })),
        "{effects:?}"
    );
    assert!(text(&screen(&mut app, 160, 30)).contains("does not check, nothing loaded"));
}

#[test]
fn verify_and_upload_say_there_is_no_way_to_read_a_program_back() {
    let mut app = editor_console();
    app.handle(AppEvent::Connected(cmd4cr_snapshot()));
    app.handle(key_with(KeyCode::F(4), KeyModifiers::SHIFT));
    let all = text(&screen(&mut app, 159, 30));
    assert!(
        all.contains("nor a read-back: Ctrl-F5 runs this text from the host"),
        "{all}"
    );
}

#[test]
fn ctrl_t_watches_the_variable_on_the_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console_with(&PaneSetup {
        history_dir: Some(dir.path().to_path_buf()),
    });
    assert!(app.focus("editor"));
    app.handle(AppEvent::Connected(cmd4cr_snapshot()));
    paste(&mut app, "PRG 0\n    V12=V3+1\nEND");
    app.handle(key(KeyCode::Up));
    app.handle(key(KeyCode::Home));
    let effects = app.handle(key_with(KeyCode::Char('t'), KeyModifiers::CONTROL));
    assert!(
        effects
            .iter()
            .any(|e| matches!(e, Effect::Send { lines, .. } if lines == &["V12".to_string()])),
        "{effects:?}"
    );
    let all = text(&screen(&mut app, 100, 30));
    assert!(all.contains("watching V12"), "{all}");
    assert!(all.contains(" V12"), "{all}");
    // Kept for the next start, apart from the TMCL list.
    let kept = std::fs::read_to_string(dir.path().join("editor-watch.json")).expect("kept");
    assert!(kept.contains("\"ascript_variables\":[12]"), "{kept}");
}

/// The console at 159×40 on an in-process CMD-4CR simulator, the editor
/// focused, on the paused clock, until `driver` is done (then F10).
async fn on_the_simulator(driver: impl AsyncFnOnce(&mut Rig, &Session)) {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some("cmd4cr".into()),
        ..ConnectionArgs::default()
    })
    .expect("resolves");
    let session = target.open().await.expect("opens");
    let LinkSpec::Sim { sim, .. } = &target.spec else {
        panic!("a simulator link");
    };
    let controller: Arc<dyn Controller> = Arc::new(
        SessionController::new(
            session.clone(),
            target.spec.describe(),
            target.options.clone(),
        )
        .with_simulator(Arc::clone(sim)),
    );
    let mut app: App = console_with(&PaneSetup::default());
    app.focus("editor");
    run_console_on(
        app,
        (159, 40),
        Some(controller),
        no_connector(),
        async |mut rig: Rig| {
            driver(&mut rig, &session).await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
}

fn paste_into(rig: &Rig, text: &str) {
    let _ = rig.keys.send(Event::Paste(text.to_string()));
}

async fn read(session: &Session, line: &str) -> String {
    session
        .execute_line(line)
        .await
        .unwrap_or_else(|e| panic!("{line}: {e}"))
        .value
        .to_string()
}

#[tokio::test(start_paused = true)]
async fn f4_loads_the_simulator_and_f5_runs_the_program_there_watched_over_the_wire() {
    on_the_simulator(async |rig: &mut Rig, session: &Session| {
        rig.screens.until("Program (A-Script)").await;
        paste_into(rig, EXAMPLE_1);
        rig.screens.until("A-Script checks: PRG 0").await;
        press(rig, KeyCode::F(4));
        let frame = rig
            .screens
            .until("loaded into the simulator (sim cmd4cr)")
            .await;
        assert!(frame.contains("F5 starts PRG 0 (SACTRL0=1)"), "{frame}");
        assert_eq!(read(session, "SASTAT0").await, "0");
        press(rig, KeyCode::F(5));
        rig.screens
            .until("SACTRL0=1: start PRG 0 in the controller")
            .await;
        // The message gives way to the program's state.
        press(rig, KeyCode::Esc);
        let frame = rig.screens.until("PRG 0 running SPC").await;
        // The simulator has the editor's text: its SPC marks a line.
        assert!(frame.contains('▶'), "{frame}");
        rig.screens.until("PRG 0 idle SPC").await;
        assert_eq!(read(session, "PX").await, "1000");
        assert_eq!(read(session, "V1").await, "1000");
    })
    .await;
}

/// F4, F5, then F12: the stop ends the programs (SACTRL), and the editor
/// reads `SASTAT` again instead of leaving `running` up (issue 19,
/// point 6, as for TMCL).
#[tokio::test(start_paused = true)]
async fn after_the_emergency_stop_the_editor_shows_the_program_idle() {
    on_the_simulator(async |rig: &mut Rig, session: &Session| {
        rig.screens.until("Program (A-Script)").await;
        paste_into(
            rig,
            "PRG 0\n    WHILE 1=1\n        DELAY=100\n    ENDWHILE\nEND\n",
        );
        rig.screens.until("A-Script checks: PRG 0").await;
        press(rig, KeyCode::F(4));
        rig.screens
            .until("loaded into the simulator (sim cmd4cr)")
            .await;
        press(rig, KeyCode::F(5));
        rig.screens
            .until("SACTRL0=1: start PRG 0 in the controller")
            .await;
        press(rig, KeyCode::Esc);
        rig.screens.until("PRG 0 running SPC").await;
        press(rig, KeyCode::F(12));
        let frame = rig.screens.until("PRG 0 idle SPC").await;
        assert!(!frame.contains("PRG 0 running"), "{frame}");
        assert_eq!(read(session, "SASTAT0").await, "0");
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn the_text_runs_from_the_host_with_its_lines_marked_and_the_stop_key_ends_it() {
    on_the_simulator(async |rig: &mut Rig, session: &Session| {
        rig.screens.until("Program (A-Script)").await;
        paste_into(rig, EXAMPLE_1);
        rig.screens.until("A-Script checks: PRG 0").await;
        // Watch V1: the host's own value is shown while it runs.
        press(rig, KeyCode::Up);
        press(rig, KeyCode::Up);
        press_with(rig, KeyCode::Char('t'), KeyModifiers::CONTROL);
        rig.screens.until("watching V1").await;
        press_with(rig, KeyCode::F(5), KeyModifiers::CONTROL);
        let frame = rig.screens.until("running untitled.asc from the host: PRG 0 line").await;
        assert!(frame.contains("editor: running untitled.asc from the host"), "{frame}");
        assert!(frame.contains('▶'), "the line it is at is marked:\n{frame}");
        let frame = rig.screens.until("every program ran to its END").await;
        assert!(
            frame.lines().any(|l| l
                .split(" V1 ")
                .nth(1)
                .is_some_and(|rest| rest.trim_start().starts_with("1000"))),
            "{frame}"
        );
        assert_eq!(read(session, "PX").await, "1000");
        // The controller's V1 is not the host's.
        assert_eq!(read(session, "V1").await, "0");

        // Again, with a second program that never ends: F12 ends the run.
        press(rig, KeyCode::PageDown);
        press(rig, KeyCode::End);
        paste_into(rig, "PRG 1\n    WHILE 1=1\n        X0\n        DELAY=100\n        X500\n        DELAY=100\n    ENDWHILE\nEND\n");
        press_with(rig, KeyCode::F(5), KeyModifiers::CONTROL);
        rig.screens.until("X500 → ok").await;
        press(rig, KeyCode::F(12));
        let frame = rig
            .screens
            .until("the emergency stop ended the host run of untitled.asc")
            .await;
        assert!(!frame.contains("editor: running"), "{frame}");
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn esc_ends_a_host_run_from_the_editor_with_the_emergency_stop() {
    on_the_simulator(async |rig: &mut Rig, session: &Session| {
        rig.screens.until("Program (A-Script)").await;
        paste_into(
            rig,
            "PRG 0\n    EO=1\n    HSPD=1000\n    JOGX+\n    WHILE 1=1\n        DELAY=100\n    ENDWHILE\nEND\n",
        );
        rig.screens.until("A-Script checks: PRG 0").await;
        press_with(rig, KeyCode::F(5), KeyModifiers::CONTROL);
        // At the DELAY, the jog already sent.
        rig.screens
            .until("running untitled.asc from the host: PRG 0 line 6")
            .await;
        assert_ne!(read(session, "MSTX").await, "0", "jogging");
        press(rig, KeyCode::Esc);
        rig.screens
            .until("the run was cancelled: STOP sent, 6 lines ok")
            .await;
        let mst: i64 = read(session, "MSTX").await.parse().expect("a number");
        assert_eq!(mst & 0b111, 0, "MSTX {mst}: the axis stands");
    })
    .await;
}
