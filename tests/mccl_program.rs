//! MCCL text files and macros through the generic program seam, against
//! the in-process MultiFlex simulator (115200 Bd wire time, tokio's paused
//! clock) and the served one: a file with `MD` lines downloads line by
//! line, its macros are read back with `TM` and only then is it verified,
//! `MC` runs what was stored; a macro changed on the way fails the
//! download at its line; `TM-1` uploads the macros as a file; the editor
//! does the same with its keys; a background task started with `GT` keeps
//! running while the console polls; the macro manager's lines delete one
//! macro and keep the others.

mod served_support;
mod ui_support;

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::families::find_family;
use axterm::families::find_kind;
use axterm::link::LinkSpec;
use axterm::protocol::console::ReplyValue;
use axterm::protocol::program::{DownloadOptions, NoIncludes, TransferJob, UploadExtent};
use axterm::session::{Cancel, PollCadence, Session, SessionOptions};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;
use axterm::ui::PaneSetup;
use axterm::ui::app::{self, App, Connector, Controller};
use axterm::ui::live::SessionController;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use served_support::Served;
use tokio::sync::mpsc;
use ui_support::console_with;

/// A homing-style file as WinControl would download it: comments, a blank
/// line, an immediate line, two macros.
const FILE: &str = "; axis 2 back and forth, and a counter\n\
                    2MN ;motor on\n\
                    \n\
                    MD10,2MR500,WS.1,MR-500,WS.1 ;there and back\n\
                    MD11,AL@100,AA5,AR100,OT\"R100 now %d; ok\\n\"\n\
                    AL0,AR100\n";

async fn session_with(faults: FaultPlan) -> Session {
    let kind = find_kind("mccl").expect("registered");
    let spec = LinkSpec::Sim {
        kind: kind.name.into(),
        sim: Arc::new(Mutex::new((kind.build)(&SimOptions::default()))),
        baud: Some(115_200),
        faults,
    };
    let family = axterm::families::family_of(kind).expect("family");
    Session::connect(spec, family, SessionOptions::default())
        .await
        .expect("the simulator link opens")
}

fn download_job(source: &str) -> TransferJob {
    let tool = find_family("mccl")
        .and_then(|f| f.console.program())
        .expect("MCCL has a program tool");
    let checked = tool.check("cycle.mccl", source, &NoIncludes);
    TransferJob::Download {
        program: checked.program.expect("the file checks"),
        options: DownloadOptions::default(),
    }
}

async fn value(session: &Session, line: &str) -> String {
    session
        .execute_line(line)
        .await
        .unwrap_or_else(|e| panic!("{line}: {e}"))
        .value
        .to_string()
}

#[tokio::test(start_paused = true)]
async fn a_macro_file_downloads_verifies_by_tm_and_mc_runs_it() {
    let session = session_with(FaultPlan::none()).await;
    let mut phases = Vec::new();
    let report = session
        .run_job(&download_job(FILE), &Cancel::new(), &mut |p| {
            phases.push((p.phase.name(), p.done))
        })
        .await
        .expect("downloaded and verified");
    assert_eq!(report.count, 4, "four lines sent, the rest comments");
    assert!(phases.contains(&("verifying", 2)), "{phases:?}");
    let told = report
        .facts
        .iter()
        .find_map(|f| f.told.as_ref())
        .map(|t| t.text.clone());
    assert_eq!(
        told.as_deref(),
        Some("4 line(s) sent, 2 macro(s) read back with TM and verified")
    );
    // What was stored runs.
    assert_eq!(value(&session, "TR100").await, "0", "AL0,AR100 ran");
    assert_eq!(value(&session, "MC11").await, "R100 now 5; ok");
    assert_eq!(value(&session, "TR100").await, "5");
    assert_eq!(value(&session, "MC10").await, "ok");
    assert_eq!(value(&session, "2TT").await, "0", "there and back");
}

#[tokio::test(start_paused = true)]
async fn a_macro_changed_on_the_way_fails_the_download_at_its_line() {
    let faults = FaultPlan::parse("corrupt-store=1").expect("parses");
    let session = session_with(faults.clone()).await;
    let failure = session
        .run_job(&download_job(FILE), &Cancel::new(), &mut |_| {})
        .await
        .expect_err("not verified");
    assert!(
        failure
            .message
            .contains("macro 10 differs: sent `2MR500,WS.1,MR-500,WS.1`"),
        "{}",
        failure.message
    );
    assert_eq!(failure.address(), Some(1), "the MD10 line, second sent");
    assert_eq!(faults.counts().corrupted_stores, 1);
}

#[tokio::test(start_paused = true)]
async fn an_error_stops_the_download_and_nothing_after_it_is_sent() {
    let session = session_with(FaultPlan::none()).await;
    // MC99 is not defined: ?-6, and AL7,AR101 never runs.
    let failure = session
        .run_job(
            &download_job("AL1,AR101\nMC99\nAL7,AR101\n"),
            &Cancel::new(),
            &mut |_| {},
        )
        .await
        .expect_err("stopped");
    assert!(
        failure
            .message
            .starts_with("line 2 `MC99`: the controller refused MC99: ?-6"),
        "{}",
        failure.message
    );
    assert_eq!(value(&session, "TR101").await, "1");
}

#[tokio::test(start_paused = true)]
async fn tm_1_uploads_the_macros_as_a_file_that_defines_them_again() {
    let session = session_with(FaultPlan::none()).await;
    session
        .run_job(&download_job(FILE), &Cancel::new(), &mut |_| {})
        .await
        .expect("downloaded");
    let report = session
        .run_job(
            &TransferJob::Upload(UploadExtent::All),
            &Cancel::new(),
            &mut |_| {},
        )
        .await
        .expect("uploaded");
    let source = report.program.expect("a program").source;
    assert_eq!(
        source,
        "; the controller's macros, read with TM-1\n\
         MD10,2MR500,WS.1,MR-500,WS.1\n\
         MD11,AL@100,AA5,AR100,OT\"R100 now %d; ok\\n\"\n"
    );
    // Sent back, it verifies.
    session
        .run_job(&download_job(&source), &Cancel::new(), &mut |_| {})
        .await
        .expect("the upload downloads and verifies");
}

#[tokio::test(start_paused = true)]
async fn a_background_task_keeps_running_while_the_console_polls() {
    let session = session_with(FaultPlan::none()).await;
    for line in ["1MN", "AL0,AR100"] {
        value(&session, line).await;
    }
    // A task that moves axis 1 back and forth for ever, counting its
    // cycles in R100 (a global register, Ch4).
    let task = "GT0,1MR2000,1WS,1MR-2000,1WS,AL@100,AA1,AR100,RP";
    assert_eq!(value(&session, task).await, "ok", "GT0 answers at once");
    session.start_polling(PollCadence::default());
    let mut positions = Vec::new();
    let mut status = session.status();
    let start = tokio::time::Instant::now();
    while start.elapsed() < Duration::from_secs(5) {
        tokio::time::timeout(Duration::from_secs(1), status.changed())
            .await
            .expect("polling goes on")
            .expect("the session is alive");
        if let Some(p) = status.borrow_and_update()[0].position {
            positions.push(p);
        }
    }
    let cycles: i64 = value(&session, "TR100").await.parse().expect("a count");
    assert!(cycles >= 2, "the task ran on: {cycles} cycles");
    let low = positions.iter().min().copied().unwrap_or_default();
    let high = positions.iter().max().copied().unwrap_or_default();
    assert!(
        low < 500 && high > 1500,
        "polled as it moved: {low}..{high}"
    );
    let refresh = status.borrow()[0].refresh.expect("a refresh rate");
    assert!(refresh.per_second() > 1.0, "{refresh}");
    // The task is listed and stopped by the macro manager's lines.
    let store = find_family("mccl")
        .and_then(|f| f.console.program())
        .and_then(|t| t.store())
        .expect("a store");
    let listed = session
        .execute_line(&store.running_line().expect("ID7"))
        .await
        .expect("listed");
    let ids = store.running(&listed.value);
    assert_eq!(ids, [1]);
    value(&session, &store.stop_line(ids[0])).await;
    let after: i64 = value(&session, "TR100").await.parse().expect("a count");
    tokio::time::sleep(Duration::from_secs(3)).await;
    assert_eq!(value(&session, "TR100").await, after.to_string(), "stopped");
    let listed = session.execute_line("ID7").await.expect("listed");
    assert!(store.running(&listed.value).is_empty());
}

#[tokio::test(start_paused = true)]
async fn the_macro_manager_deletes_one_macro_and_keeps_the_others() {
    let session = session_with(FaultPlan::none()).await;
    session
        .run_job(&download_job(FILE), &Cancel::new(), &mut |_| {})
        .await
        .expect("downloaded");
    let store = find_family("mccl")
        .and_then(|f| f.console.program())
        .and_then(|t| t.store())
        .expect("a store");
    let listing = session
        .execute_line(&store.list_line())
        .await
        .expect("TM-1");
    let macros = store.stored(&listing.value);
    assert_eq!(
        macros.iter().map(|m| m.number).collect::<Vec<_>>(),
        [10, 11]
    );
    let deletion = store.delete(&macros, 10).expect("deletes");
    for line in &deletion.lines {
        value(&session, line).await;
    }
    let after = session.execute_line("TM-1").await.expect("TM-1");
    assert_eq!(
        store.compare(&deletion.kept, &store.stored(&after.value)),
        Ok(())
    );
    assert!(session.execute_line("MC10").await.is_err(), "deleted");
    assert_eq!(value(&session, "MC11").await, "R100 now 5; ok", "kept");
    assert!(matches!(after.value, ReplyValue::Text(ref t) if !t.contains("MC10")));
}

#[test]
fn axterm_download_and_upload_take_the_family() {
    let served = Served::start("mccl", &["--baud", "115200"]);
    let dir = tempfile::tempdir().expect("a temporary directory");
    let file = dir.path().join("cycle.mfx1");
    std::fs::write(&file, FILE).expect("write");
    let axterm = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_axterm"))
            .args(args)
            .output()
            .expect("axterm runs")
    };
    let port = [
        "--port",
        served.pty.as_str(),
        "--protocol",
        "mccl",
        "--baud",
        "115200",
    ];
    let mut args = vec!["download"];
    args.extend(port);
    args.push(file.to_str().expect("a path"));
    let out = axterm(&args);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("4 line(s) sent, 2 macro(s) read back with TM and verified"),
        "{stdout}"
    );
    let uploaded = dir.path().join("up.mccl");
    let mut args = vec!["upload"];
    args.extend(port);
    args.extend(["-o", uploaded.to_str().expect("a path")]);
    let out = axterm(&args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&uploaded).expect("written");
    assert!(text.contains("MD10,2MR500,WS.1,MR-500,WS.1\n"), "{text}");
    // A file that does not check sends nothing.
    std::fs::write(&file, "1MR1000,N0\n").expect("write");
    let mut args = vec!["download"];
    args.extend(port);
    args.push(file.to_str().expect("a path"));
    let out = axterm(&args);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("1:9: error: `N0`"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

// ------------------------------------------------------------- the editor

const WIDTH: u16 = 100;
const HEIGHT: u16 = 30;

struct Rig {
    keys: mpsc::UnboundedSender<Event>,
    drawn: mpsc::UnboundedReceiver<String>,
    last: String,
}

impl Rig {
    fn press(&self, code: KeyCode, modifiers: KeyModifiers) {
        let _ = self.keys.send(Event::Key(KeyEvent::new(code, modifiers)));
    }

    async fn until(&mut self, needle: &str) -> String {
        let wait = async {
            while let Some(frame) = self.drawn.recv().await {
                let found = frame.contains(needle);
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
            "never showed {needle:?}; last frame:\n{}",
            self.last
        );
        self.last.clone()
    }
}

async fn run_console(session: &Session, driver: impl AsyncFnOnce(&mut Rig)) {
    let controller: Arc<dyn Controller> = Arc::new(SessionController::new(
        session.clone(),
        "sim mccl".into(),
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

#[tokio::test(start_paused = true)]
async fn the_editor_checks_downloads_and_uploads_mccl() {
    let session = session_with(FaultPlan::none()).await;
    run_console(&session, async |rig: &mut Rig| {
        // A connected MultiFlex makes the editor's language MCCL.
        let _ = rig.keys.send(Event::Paste(FILE.to_string()));
        rig.until("MD11,AL@100").await;
        rig.until("checks: 4 line(s) to send, 2 macro(s)").await;
        rig.press(KeyCode::F(4), KeyModifiers::NONE);
        rig.until("downloaded and verified 4 lines").await;
        // Unsaved text is asked about first; again uploads over it.
        rig.press(KeyCode::F(4), KeyModifiers::CONTROL);
        rig.until("Ctrl-F4 again uploads over them").await;
        rig.press(KeyCode::F(4), KeyModifiers::CONTROL);
        rig.until("uploaded 2 lines from module 0 into a new unsaved buffer")
            .await;
        let frame = rig.until("read with TM-1").await;
        assert!(frame.contains("MD10,2MR500,WS.1,MR-500,WS.1"), "{frame}");
    })
    .await;
    assert_eq!(value(&session, "MC11").await, "R100 now 5; ok");
}

#[tokio::test(start_paused = true)]
async fn cancelling_a_download_aborts_a_line_that_holds_the_controller() {
    let session = session_with(FaultPlan::none()).await;
    // The second line repeats for ever: it holds the controller until
    // Escape.
    let job = download_job("2MN\n2MR1000,WS.1,MR-1000,WS.1,RP\nAL5,AR100\n");
    let cancel = Cancel::new();
    let download = tokio::spawn({
        let session = session.clone();
        let cancel = cancel.clone();
        async move { session.run_job(&job, &cancel, &mut |_| {}).await }
    });
    let mut busy = session.busy();
    busy.wait_for(|b| b.is_some()).await.expect("held");
    tokio::time::sleep(Duration::from_secs(5)).await;
    cancel.cancel();
    let failure = tokio::time::timeout(Duration::from_secs(600), download)
        .await
        .expect("the held line was aborted")
        .expect("joined")
        .expect_err("cancelled or aborted");
    assert!(
        failure.message.contains("?-7") || failure.cancelled().is_some(),
        "{}",
        failure.message
    );
    assert!(busy.borrow().is_none(), "the controller is free again");
    assert_eq!(value(&session, "TR100").await, "0", "AL5,AR100 never sent");
}
