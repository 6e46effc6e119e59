//! Download, verify, cancel and upload from the editor through the real
//! console loop and the session, against the in-process TMCM-1110
//! simulator with 9600 baud wire time, on tokio's paused clock: what the
//! screen shows, and what the module holds afterwards.

mod ui_support;

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::families::find_kind;
use axterm::link::LinkSpec;
use axterm::protocol::program::{DownloadOptions, UploadExtent};
use axterm::protocol::tmcl::asm::parse_image;
use axterm::protocol::tmcl::asm::{NoIncludes, ProgramWord, assemble};
use axterm::protocol::tmcl::plan::{DownloadPlan, UploadPlan};
use axterm::session::Cancel;
use axterm::session::{Session, SessionOptions};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;
use axterm::ui::PaneSetup;
use axterm::ui::app::{self, App, Connector, Controller};
use axterm::ui::live::SessionController;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use tokio::sync::mpsc;
use ui_support::console_with;

const WIDTH: u16 = 80;
const HEIGHT: u16 = 24;

async fn session_with(faults: FaultPlan) -> Session {
    let kind = find_kind("tmcm1110").expect("registered");
    let spec = LinkSpec::Sim {
        kind: kind.name.into(),
        sim: Arc::new(Mutex::new((kind.build)(&SimOptions::default()))),
        baud: Some(9600),
        faults,
    };
    let family = axterm::families::family_of(kind).expect("family");
    Session::connect(spec, family, SessionOptions::default())
        .await
        .expect("the simulator link opens")
}

/// `n` words: moves, STOP last; word N on line N+1.
fn program_text(n: usize) -> String {
    let mut text: String = (0..n - 1)
        .map(|i| format!("MVP ABS, 0, {}\n", i * 10))
        .collect();
    text.push_str("STOP");
    text
}

fn words(name: &str, text: &str) -> Vec<ProgramWord> {
    match assemble(name, text, &NoIncludes) {
        Ok(p) => p.words,
        Err(e) => panic!("{e:?}"),
    }
}

async fn read_program(session: &Session) -> Vec<ProgramWord> {
    let plan = UploadPlan::new(session.address(), UploadExtent::UntilBlank);
    let report = session
        .transfer(Box::new(plan), &Cancel::new(), &mut |_| {})
        .await
        .expect("upload");
    let image = report.program.and_then(|p| p.image).unwrap_or_default();
    parse_image(&image).unwrap_or_else(|e| panic!("{e:?}"))
}

/// The console loop's keyboard and what it draws.
struct Rig {
    keys: mpsc::UnboundedSender<Event>,
    drawn: mpsc::UnboundedReceiver<String>,
    last: String,
}

impl Rig {
    fn press(&self, code: KeyCode, modifiers: KeyModifiers) {
        let _ = self.keys.send(Event::Key(KeyEvent::new(code, modifiers)));
    }

    fn paste(&self, text: &str) {
        let _ = self.keys.send(Event::Paste(text.to_string()));
    }

    /// Wait for a frame showing `needle` (virtual time: a loop that
    /// waits for nothing more gives up at once).
    async fn until(&mut self, needle: &str) -> String {
        self.until_frame(needle, |frame| frame.contains(needle))
            .await
    }

    /// Wait for a frame `ready` says yes to; `what` names it if none comes.
    async fn until_frame(&mut self, what: &str, ready: impl Fn(&str) -> bool) -> String {
        let wait = async {
            while let Some(frame) = self.drawn.recv().await {
                let found = ready(&frame);
                self.last = frame;
                if found {
                    return true;
                }
            }
            false
        };
        let found = tokio::time::timeout(Duration::from_secs(600), wait).await;
        assert!(
            matches!(found, Ok(true)),
            "never showed {what:?}; last frame:\n{}",
            self.last
        );
        self.last.clone()
    }
}

/// Run the console on `session` with the editor focused until `driver`
/// quits it.
async fn run_console(session: &Session, driver: impl AsyncFnOnce(&mut Rig)) {
    let controller: Arc<dyn Controller> = Arc::new(SessionController::new(
        session.clone(),
        "sim tmcm1110".into(),
        SessionOptions::default(),
    ));
    let connector: Connector = Box::new(|_| Box::pin(async { Err("not in this test".into()) }));
    let mut app: App = console_with(&PaneSetup::default());
    app.focus("editor");
    let (keys, input) = mpsc::unbounded_channel();
    let (drawn_tx, drawn) = mpsc::unbounded_channel();
    let mut terminal = Terminal::new(TestBackend::new(WIDTH, HEIGHT)).expect("test backend");
    let mut draw = move |app: &mut App| -> std::io::Result<()> {
        let Ok(_) = terminal.draw(|f| app.render(f));
        let buffer = terminal.backend().buffer();
        let text: Vec<String> = (0..HEIGHT)
            .map(|y| {
                (0..WIDTH)
                    .map(|x| buffer[(x, y)].symbol().to_string())
                    .collect()
            })
            .collect();
        let _ = drawn_tx.send(text.join("\n"));
        Ok(())
    };
    let mut rig = Rig {
        keys,
        drawn,
        last: String::new(),
    };
    let looping = app::run(
        &mut app,
        Some(controller),
        connector,
        input,
        None,
        &mut draw,
    );
    let driving = async {
        driver(&mut rig).await;
        rig.press(KeyCode::F(10), KeyModifiers::NONE);
    };
    let (result, ()) = tokio::join!(looping, driving);
    result.expect("the loop ends cleanly");
}

fn line_with<'a>(frame: &'a str, text: &str) -> &'a str {
    frame
        .lines()
        .find(|l| l.contains(text))
        .unwrap_or_else(|| panic!("no line with {text:?} in\n{frame}"))
}

#[tokio::test(start_paused = true)]
async fn f4_shows_storing_then_verifying_and_the_module_holds_the_program() {
    let session = session_with(FaultPlan::none()).await;
    let text = program_text(12);
    run_console(&session, async |rig: &mut Rig| {
        rig.paste(&text);
        rig.until(" 12 STOP").await;
        rig.press(KeyCode::F(4), KeyModifiers::NONE);
        let storing = rig
            .until("download: storing 6/12 words — Esc cancels")
            .await;
        assert!(
            line_with(&storing, "storing 6/12").contains('█'),
            "{storing}"
        );
        rig.until("download: verifying 6/12 words").await;
        let done = rig.until("downloaded and verified 12 words").await;
        assert!(!done.contains("verifying"), "the bar is gone:\n{done}");
    })
    .await;
    assert_eq!(read_program(&session).await, words("untitled.tmc", &text));
}

#[tokio::test(start_paused = true)]
async fn a_corrupted_store_is_reported_at_its_address_and_its_line_marked() {
    let faults = FaultPlan::parse("corrupt-store=5").expect("parses");
    let session = session_with(faults.clone()).await;
    run_console(&session, async |rig: &mut Rig| {
        rig.paste(&program_text(12));
        rig.until(" 12 STOP").await;
        rig.press(KeyCode::F(4), KeyModifiers::NONE);
        let frame = rig
            .until("download failed at source line 5: word 4 differs: wrote MVP ABS, 0, 40")
            .await;
        assert!(
            line_with(&frame, "MVP ABS, 0, 40 ").contains("✗  5"),
            "{frame}"
        );
        assert!(
            !line_with(&frame, "MVP ABS, 0, 30").contains('✗'),
            "{frame}"
        );
    })
    .await;
    assert_eq!(faults.counts().corrupted_stores, 1);
}

#[tokio::test(start_paused = true)]
async fn esc_cancels_a_download_and_the_module_leaves_download_mode() {
    let session = session_with(FaultPlan::none()).await;
    run_console(&session, async |rig: &mut Rig| {
        rig.paste(&program_text(40));
        rig.until(" 40 STOP").await;
        rig.press(KeyCode::F(4), KeyModifiers::NONE);
        rig.until("download: storing 3/40 words").await;
        rig.press(KeyCode::Esc, KeyModifiers::NONE);
        let frame = rig.until("cancelled: the module left download mode").await;
        assert!(!frame.contains("download: storing"), "{frame}");
    })
    .await;
    // Download mode was left: a line that would be stored is executed.
    session
        .execute_line("SAP 4, 0, 1000")
        .await
        .expect("executed, not refused or stored");
    let stored = read_program(&session).await;
    assert!(
        !stored.is_empty() && stored.len() < 40,
        "partly stored: {}",
        stored.len()
    );
}

#[tokio::test(start_paused = true)]
async fn the_emergency_stop_cancels_a_download_from_the_editor() {
    let session = session_with(FaultPlan::none()).await;
    run_console(&session, async |rig: &mut Rig| {
        rig.paste(&program_text(40));
        rig.until(" 40 STOP").await;
        rig.press(KeyCode::F(4), KeyModifiers::NONE);
        rig.until("download: storing 3/40 words").await;
        rig.press(KeyCode::F(12), KeyModifiers::NONE);
        let frame = rig.until("cancelled: the module left download mode").await;
        assert!(!frame.contains("download: storing"), "{frame}");
        rig.until("STOP: ").await;
    })
    .await;
    session
        .execute_line("SAP 4, 0, 1000")
        .await
        .expect("download mode was left");
}

#[tokio::test(start_paused = true)]
async fn verify_compares_without_storing_and_upload_opens_what_the_module_holds() {
    let session = session_with(FaultPlan::none()).await;
    let text = program_text(12);
    let image = words("test.tmc", &text);
    let plan =
        DownloadPlan::new(&image, session.address(), DownloadOptions::default()).expect("storable");
    session
        .transfer(Box::new(plan), &Cancel::new(), &mut |_| {})
        .await
        .expect("downloaded");
    let dir = tempfile::tempdir().expect("temp dir");
    let saved = dir.path().join("uploaded.tmc");
    run_console(&session, async |rig: &mut Rig| {
        // The same program verifies.
        rig.paste(&text);
        rig.until(" 12 STOP").await;
        rig.press(KeyCode::F(4), KeyModifiers::SHIFT);
        rig.until("verified: module 1 holds these 12 words").await;
        // Line 3 changed: word 2 differs, nothing is stored.
        for _ in 0..9 {
            rig.press(KeyCode::Up, KeyModifiers::NONE);
        }
        rig.press(KeyCode::End, KeyModifiers::NONE);
        rig.paste("5");
        rig.until("MVP ABS, 0, 205").await;
        rig.press(KeyCode::F(4), KeyModifiers::SHIFT);
        let frame = rig
            .until("verify failed at source line 3: word 2 differs: module 1 holds MVP ABS, 0, 20,")
            .await;
        assert!(
            line_with(&frame, "MVP ABS, 0, 205").contains("✗  3"),
            "{frame}"
        );
        // Upload over the unsaved text: asked first.
        rig.press(KeyCode::F(4), KeyModifiers::CONTROL);
        rig.until("Ctrl-F4 again uploads over them").await;
        rig.press(KeyCode::F(4), KeyModifiers::CONTROL);
        let frame = rig
            .until("uploaded 12 words from module 1 into a new unsaved buffer")
            .await;
        assert!(!frame.contains("MVP ABS, 0, 205"), "{frame}");
        // Saved to a file, to read what the buffer holds.
        rig.press(KeyCode::F(2), KeyModifiers::NONE);
        rig.until("save as:").await;
        rig.paste(&saved.display().to_string());
        rig.press(KeyCode::Enter, KeyModifiers::NONE);
        rig.until("saved ").await;
    })
    .await;
    let source = std::fs::read_to_string(&saved).expect("the uploaded buffer, saved");
    assert_eq!(words("uploaded.tmc", &source), image);
    assert_eq!(read_program(&session).await, image, "verify stored nothing");
}

/// The value the editor's watch panel shows for user variable `n`.
fn watched_value(frame: &str, n: u8) -> Option<i64> {
    let label = format!(" #{n} ");
    let line = frame
        .lines()
        .find(|l| l.contains(&label) && !l.contains("user variables"))?;
    let panel = line.rsplit_once(&label)?.1;
    panel.trim_end_matches('│').trim().parse().ok()
}

/// A program counting in user variable 5: watched from the editor while
/// it runs on the simulator, the panel shows the count going up.
#[tokio::test(start_paused = true)]
async fn a_watched_user_variable_counts_up_beside_the_running_program() {
    let session = session_with(FaultPlan::none()).await;
    let text = "Count = 5\n\
                SGP Count, 2, 0\n\
                Loop: GGP Count, 2\n\
                CALC ADD, 1\n\
                AGP Count, 2\n\
                WAIT TICKS, 0, 20 // 200 ms\n\
                JA Loop";
    run_console(&session, async |rig: &mut Rig| {
        rig.paste(text);
        rig.until("  7 JA Loop").await;
        rig.press(KeyCode::F(4), KeyModifiers::NONE);
        rig.until("downloaded and verified 6 words").await;
        // Line 3 (`Loop: GGP Count, 2`), then the watch key.
        for _ in 0..4 {
            rig.press(KeyCode::Up, KeyModifiers::NONE);
        }
        rig.press(KeyCode::Char('t'), KeyModifiers::CONTROL);
        let frame = rig.until("watching user variable #5").await;
        assert!(frame.contains("user variables"), "{frame}");
        // Esc puts the message away: the registers show in its place.
        rig.press(KeyCode::Esc, KeyModifiers::NONE);
        rig.press(KeyCode::F(5), KeyModifiers::NONE);
        let frame = rig
            .until_frame("the count at 3 or more", |f| {
                watched_value(f, 5).is_some_and(|v| v >= 3)
            })
            .await;
        let seen = watched_value(&frame, 5).unwrap_or_default();
        let frame = rig
            .until_frame("the count going on up", |f| {
                watched_value(f, 5).is_some_and(|v| v >= seen + 2)
            })
            .await;
        assert!(frame.contains("running PC"), "{frame}");
    })
    .await;
    // The module agrees: it counted on.
    let counted = session.execute_line("GGP 5, 2").await.expect("read");
    match counted.value {
        axterm::session::ReplyValue::Number(n) => assert!(n >= 5, "{n}"),
        other => panic!("{other:?}"),
    }
}

/// F4, F5, then F12: the stop ends the program (TMCL 128), and the
/// editor reads its state again instead of leaving `running` up until
/// Shift-F5 (issue 19, point 6).
#[tokio::test(start_paused = true)]
async fn after_the_emergency_stop_the_editor_shows_the_program_stopped() {
    let session = session_with(FaultPlan::none()).await;
    let text = "Loop: WAIT TICKS, 0, 20 // 200 ms\n\
                JA Loop";
    run_console(&session, async |rig: &mut Rig| {
        rig.paste(text);
        rig.until("  2 JA Loop").await;
        rig.press(KeyCode::F(4), KeyModifiers::NONE);
        rig.until("downloaded and verified 2 words").await;
        rig.press(KeyCode::Esc, KeyModifiers::NONE);
        rig.press(KeyCode::F(5), KeyModifiers::NONE);
        rig.until("running PC").await;
        rig.press(KeyCode::F(12), KeyModifiers::NONE);
        let frame = rig.until("stopped PC").await;
        assert!(!frame.contains("running PC"), "{frame}");
    })
    .await;
    let mode = session.execute_line("GGP 128, 0").await.expect("read");
    assert_eq!(mode.value.to_string(), "0", "the module agrees: stopped");
}
