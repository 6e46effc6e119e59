//! The console's `:run` and `:run-ascript` that fail or are cancelled with
//! Esc, through the real loop and a session on an in-process simulator, on
//! tokio's paused clock: the run ends with the stop sequence, each stop
//! line shown with its answer, and the axis comes to rest short of its
//! target.

mod motion_support;
mod ui_support;

use std::sync::Arc;
use std::time::Duration;

use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::session::{ReplyValue, Session, SessionOptions};
use axterm::ui::app::Controller;
use axterm::ui::live::SessionController;
use motion_support::motion_of;
use ratatui::crossterm::event::KeyCode;
use ui_support::looped::{Rig, enter, no_connector, press, run_command_console, run_console_on};

async fn session(kind: &str) -> Session {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some(kind.into()),
        baud: Some(115_200),
        ..ConnectionArgs::default()
    })
    .expect("resolves");
    target.open().await.expect("the simulator link opens")
}

/// The console at 120×40 on `session`, the command pane focused, until
/// `driver` is done (then F10).
async fn run_console(session: &Session, driver: impl AsyncFnOnce(&mut Rig)) {
    let controller: Arc<dyn Controller> = Arc::new(SessionController::new(
        session.clone(),
        "sim".into(),
        SessionOptions::default(),
    ));
    run_command_console(controller, (120, 40), driver).await;
}

async fn number(session: &Session, line: &str) -> i64 {
    match session.execute_line(line).await.map(|r| r.value) {
        Ok(ReplyValue::Number(n)) => n,
        other => panic!("{line}: {other:?}"),
    }
}

/// Read the TMCL speed every 100 ms of virtual time until it is 0; false
/// if it still turns after 100 reads.
async fn comes_to_rest(session: &Session) -> bool {
    for _ in 0..100 {
        if number(session, "GAP 3, 0").await == 0 {
            return true;
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    false
}

fn batch(dir: &std::path::Path, wait: &str) -> String {
    let file = dir.join("move.txt");
    std::fs::write(
        &file,
        format!(
            "SAP 4, 0, 1500\nMVP ABS, 0, 512000000\n:wait-until GAP 8, 0 == 1 timeout {wait}\n"
        ),
    )
    .expect("write");
    file.display().to_string()
}

const STOP_REPORT: [&str; 4] = [
    "  MST 0 → ok",
    "  STOPAPP → ok",
    "  MST 0 → ok",
    "stop confirmed: every stop line answered ok",
];

#[tokio::test(start_paused = true)]
async fn esc_cancels_a_run_with_the_stop_sequence_and_the_axis_comes_to_rest() {
    let session = session("tmcm1110").await;
    let dir = tempfile::tempdir().expect("temp dir");
    let file = batch(dir.path(), "10m");
    run_console(&session, async |rig: &mut Rig| {
        enter(rig, &format!(":run {file}"));
        rig.screens.until("MVP ABS, 0, 512000000").await;
        // The move is under way while the batch waits for its end.
        loop {
            if number(&session, "GAP 3, 0").await > 0 {
                break;
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        press(rig, KeyCode::Esc);
        let frame = rig.screens.until("stop confirmed").await;
        assert!(frame.contains("batch stopped"), "{frame}");
        assert!(
            frame.contains("the run was cancelled: stopping every axis:"),
            "{frame}"
        );
        for line in STOP_REPORT {
            assert!(frame.contains(line), "{line}:\n{frame}");
        }
        assert!(comes_to_rest(&session).await, "the axis still turns");
        assert_eq!(number(&session, "GAP 8, 0").await, 0, "short of target");
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn a_run_whose_wait_until_fails_ends_with_the_stop_sequence() {
    let session = session("tmcm1110").await;
    let dir = tempfile::tempdir().expect("temp dir");
    let file = batch(dir.path(), "100ms");
    run_console(&session, async |rig: &mut Rig| {
        enter(rig, &format!(":run {file}"));
        let frame = rig.screens.until("stop confirmed").await;
        assert!(
            frame.contains("GAP 8, 0 did not become 1 within 100 ms"),
            "{frame}"
        );
        assert!(
            frame.contains("the run failed: stopping every axis:"),
            "{frame}"
        );
        for line in STOP_REPORT {
            assert!(frame.contains(line), "{line}:\n{frame}");
        }
        assert!(comes_to_rest(&session).await, "the axis still turns");
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn esc_ends_a_host_run_with_the_emergency_stop_and_the_axis_stands() {
    let session = session("cmd4cr").await;
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("jog.asc");
    // A jog, then a wait that never ends: only Esc ends the run.
    std::fs::write(
        &file,
        "PRG 0\n    EO=1\n    HSPD=1000\n    JOGX+\n    WHILE 1=1\n        DELAY=100\n    ENDWHILE\nEND\n",
    )
    .expect("write");
    let file = file.display().to_string();
    run_console(&session, async |rig: &mut Rig| {
        enter(rig, &format!(":run-ascript {file}"));
        rig.screens.until("JOGX+ as JX+ → ok").await;
        assert_ne!(number(&session, "MSTX").await & 0b111, 0, "jogging");
        press(rig, KeyCode::Esc);
        let frame = rig.screens.until("stop confirmed").await;
        assert!(
            frame.contains("the run was cancelled: stopping every axis:"),
            "{frame}"
        );
        assert!(frame.contains("  ESTOP → ok"), "{frame}");
        // ESTOP stops at once (§2.1.3.1.2): the axis stands.
        assert_eq!(number(&session, "MSTX").await & 0b111, 0);
    })
    .await;
}

/// Read `line` every 20 ms of virtual time until `ready` says yes to what
/// it printed; false if it never did in 500 reads.
async fn reads_until(session: &Session, line: &str, ready: impl Fn(&str) -> bool) -> bool {
    for _ in 0..500 {
        match session.execute_line(line).await {
            Ok(result) if ready(&result.value.to_string()) => return true,
            Ok(_) => {}
            Err(e) => panic!("{line}: {e}"),
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    false
}

/// SIGTERM, SIGHUP or SIGINT from outside (`AppEvent::Terminate`) ends the
/// console as Ctrl-C ends `axterm run`: every axis stopped before it lets
/// go, in every family.
#[tokio::test(start_paused = true)]
async fn a_console_ended_from_outside_stops_every_axis_in_every_family() {
    use axterm::families::FAMILIES;
    use axterm::script::result_matches;
    use axterm::ui::app::AppEvent;
    for family in FAMILIES {
        let motion = motion_of(family);
        let (start, speed, at_rest) = (motion.start, motion.speed, motion.at_rest);
        let kind = family.simulators.first().expect("a simulator").name;
        let session = session(kind).await;
        let controller: Arc<dyn Controller> = Arc::new(SessionController::new(
            session.clone(),
            "sim".into(),
            SessionOptions::default(),
        ));
        let mut app = ui_support::console_with(&axterm::ui::PaneSetup::default());
        app.focus("command");
        // Ended only by the signal: no F10 after the driver.
        run_console_on(
            app,
            (120, 40),
            Some(controller),
            no_connector(),
            async |rig: Rig| {
                enter(&rig, start);
                assert!(
                    reads_until(&session, speed, |v| !result_matches(v, at_rest)).await,
                    "{}: {start} did not start the axis",
                    family.name
                );
                let _ = rig.extra.send(AppEvent::Terminate);
            },
        )
        .await;
        assert!(
            reads_until(&session, speed, |v| result_matches(v, at_rest)).await,
            "{}: the axis still moves after the console ended",
            family.name
        );
    }
}

/// A `:run` that completes with an axis still moving (a replayed
/// recording whose last move still goes) says so and ends as a failed run:
/// the stop sequence, the axis at rest; one that says `:leave-moving` says
/// the axis moves as the file means and leaves it so. In every family, as
/// `axterm run` does.
#[tokio::test(start_paused = true)]
async fn a_console_run_that_leaves_an_axis_moving_says_so_and_stops_it_unless_meant() {
    use axterm::families::FAMILIES;
    use axterm::script::result_matches;
    for family in FAMILIES {
        let motion = motion_of(family);
        let (start, speed, at_rest) = (motion.start, motion.speed, motion.at_rest);
        let kind = family.simulators.first().expect("a simulator").name;
        let dir = tempfile::tempdir().expect("temp dir");
        let unmeant = dir.path().join("moves.txt");
        std::fs::write(&unmeant, format!("{start}\n")).expect("write");
        let meant = dir.path().join("meant.txt");
        std::fs::write(&meant, format!("{start}\n:leave-moving\n")).expect("write");

        let session = session(kind).await;
        run_console(&session, async |rig: &mut Rig| {
            enter(rig, &format!(":run {}", unmeant.display()));
            rig.screens
                .until("still moves; the file does not say :leave-moving")
                .await;
            // The stop report follows (a SIXpack 2's 18 lines scroll the
            // rest away): the axis at rest is what counts.
            assert!(
                reads_until(&session, speed, |v| result_matches(v, at_rest)).await,
                "{}: the axis still moves after the run",
                family.name
            );
        })
        .await;

        let session = self::session(kind).await;
        run_console(&session, async |rig: &mut Rig| {
            enter(rig, &format!(":run {}", meant.display()));
            let frame = rig.screens.until("as the file means it to").await;
            assert!(!frame.contains("stopping every axis"), "{frame}");
            assert!(
                reads_until(&session, speed, |v| !result_matches(v, at_rest)).await,
                "{}: the axis was stopped although the file meant it to move",
                family.name
            );
            session.emergency_stop_lines().await;
        })
        .await;
    }
}
