//! `:run-ascript` in the console, through the real loop and a session on
//! the in-process CMD-4CR simulator, on tokio's paused clock: the run is
//! shown as running from the host (output, hint, status bar), and the
//! emergency-stop key ends it at once — after the stop lines nothing more
//! of the program goes on the wire.

mod ui_support;

use std::sync::Arc;
use std::time::Duration;

use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::device::{Direction, Priority, TrafficKind, TrafficRecord};
use axterm::session::{Session, SessionOptions};
use axterm::ui::app::Controller;
use axterm::ui::live::SessionController;
use ratatui::crossterm::event::KeyCode;
use tokio::sync::broadcast;
use ui_support::looped::{Rig, enter, press, run_command_console};

async fn session() -> Session {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some("cmd4cr".into()),
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
        "sim cmd4cr".into(),
        SessionOptions::default(),
    ));
    run_command_console(controller, (120, 40), driver).await;
}

fn sent(record: &TrafficRecord) -> Option<(Priority, String)> {
    if record.direction != Direction::Sent || record.kind != TrafficKind::Request {
        return None;
    }
    Some((
        record.priority?,
        String::from_utf8_lossy(&record.bytes).trim().to_string(),
    ))
}

/// Every request sent so far.
fn drain(traffic: &mut broadcast::Receiver<TrafficRecord>) -> Vec<(Priority, String)> {
    let mut all = Vec::new();
    loop {
        match traffic.try_recv() {
            Ok(record) => all.extend(sent(&record)),
            Err(broadcast::error::TryRecvError::Lagged(n)) => {
                panic!("{n} traffic records were missed: the test cannot tell what was sent")
            }
            Err(_) => return all,
        }
    }
}

const FOREVER: &str = "PRG 0\n    EO=1\n    HSPD=2000\n    WHILE 1=1\n        X5000\n        WAITX\n        X0\n        WAITX\n    ENDWHILE\nEND\n";

#[tokio::test(start_paused = true)]
async fn the_emergency_stop_ends_a_host_run_and_nothing_of_it_follows_the_stop_lines() {
    let session = session().await;
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("forever.asc");
    // The host run waits in a DELAY when the key comes (its wake-up timer
    // is not a line the stop drops): the run itself must end.
    std::fs::write(
        &file,
        "PRG 0\n    EO=1\n    HSPD=2000\n    WHILE 1=1\n        X5000\n        DELAY=200\n        X0\n        DELAY=200\n    ENDWHILE\nEND\n",
    )
    .expect("write");
    let file = file.display().to_string();
    let mut all: Vec<(Priority, String)> = Vec::new();
    run_console(&session, async |rig: &mut Rig| {
        enter(rig, &format!(":run-ascript {file}"));
        let frame = rig.screens.until("host: PRG 0 line 5: X5000 → ok").await;
        assert!(
            frame.contains(&format!(
                "running {file} from the host: PRG 0 (Esc stops it"
            )),
            "{frame}"
        );
        // The status bar says so whatever pane is shown.
        let status = frame.lines().last().unwrap_or_default();
        assert!(
            status.contains(&format!("running {file} from the host: PRG 0 line")),
            "{status}"
        );
        // Everything sent from here on; the stop lines too.
        let mut traffic = session.device().traffic();
        press(rig, KeyCode::F(12));
        let frame = rig.screens.until("STOP confirmed").await;
        assert!(
            frame.contains(&format!("the host run of {file} was stopped")),
            "{frame}"
        );
        assert!(
            !frame
                .lines()
                .last()
                .unwrap_or_default()
                .contains("from the host"),
            "{frame}"
        );
        // Let the console poll a while: the host run would have gone on
        // reading MSTX and sending moves.
        all = drain(&mut traffic);
        let stopped_at = all.len();
        loop {
            let polls_after = all
                .iter()
                .skip(stopped_at)
                .filter(|(p, _)| *p == Priority::Poll)
                .count();
            if polls_after >= 100 {
                break;
            }
            match traffic.recv().await {
                Ok(record) => all.extend(sent(&record)),
                Err(broadcast::error::RecvError::Lagged(n)) => {
                    panic!("{n} traffic records were missed: the test cannot tell what was sent")
                }
                Err(broadcast::error::RecvError::Closed) => break,
            }
        }
    })
    .await;
    let last_stop = all
        .iter()
        .rposition(|(p, _)| *p == Priority::EmergencyStop)
        .expect("stop lines were sent");
    let after_stop: Vec<(Priority, String)> = all.iter().skip(last_stop + 1).cloned().collect();
    let stops: Vec<&str> = all
        .iter()
        .filter(|(p, _)| *p == Priority::EmergencyStop)
        .map(|(_, l)| l.as_str())
        .collect();
    assert_eq!(
        stops,
        [
            "@01ESTOP",
            "@01SACTRL0=0",
            "@01SACTRL1=0",
            "@01SACTRL2=0",
            "@01SACTRL3=0",
            "@01ESTOP"
        ]
    );
    assert!(after_stop.len() >= 100, "{after_stop:?}");
    let users_after: Vec<&(Priority, String)> = after_stop
        .iter()
        .filter(|(p, _)| *p != Priority::Poll)
        .collect();
    assert!(
        users_after.is_empty(),
        "sent after the stop: {users_after:?}"
    );
    // And X stands: ESTOP stopped it, nothing moved it again.
    let px = session
        .execute_line("PX")
        .await
        .expect("PX")
        .value
        .to_string();
    tokio::time::sleep(Duration::from_secs(2)).await;
    let later = session
        .execute_line("PX")
        .await
        .expect("PX")
        .value
        .to_string();
    assert_eq!(px, later);
}

#[tokio::test(start_paused = true)]
async fn a_host_run_shows_each_command_and_how_it_ended_and_esc_stops_one() {
    let session = session().await;
    let dir = tempfile::tempdir().expect("temp dir");
    let short = dir.path().join("short.asc");
    std::fs::write(
        &short,
        "PRG 0\n    HSPD=50000\n    X300\n    WAITX\n    V1=PX\n    DO1=1\nEND\n",
    )
    .expect("write");
    let short = short.display().to_string();
    let forever = dir.path().join("forever.asc");
    std::fs::write(&forever, FOREVER).expect("write");
    let forever = forever.display().to_string();
    let bad = dir.path().join("bad.asc");
    std::fs::write(&bad, "PRG 0\n    V200=1\nEND\n").expect("write");
    let bad = bad.display().to_string();
    run_console(&session, async |rig: &mut Rig| {
        enter(rig, &format!(":run-ascript {bad}"));
        let frame = rig.screens.until(&format!("{bad}: nothing was sent")).await;
        assert!(
            frame.contains(&format!("{bad}:2: Var Range Error")),
            "{frame}"
        );

        enter(rig, &format!(":run-ascript {short}"));
        let frame = rig
            .screens
            .until(&format!(
                "host run of {short}: every program ran to its END"
            ))
            .await;
        for line in [
            "host: PRG 0 started from the host",
            "host: PRG 0 line 2: HSPD=50000 → ok",
            "host: PRG 0 line 3: X300 → ok",
            "host: PRG 0 line 6: DO1=1 → ok",
            "host: PRG 0 reached END (line 7)",
        ] {
            assert!(frame.contains(line), "{line}:\n{frame}");
        }

        enter(rig, &format!(":run-ascript {forever}"));
        rig.screens.until("host: PRG 0 line 5: X5000 → ok").await;
        press(rig, KeyCode::Esc);
        let frame = rig
            .screens
            .until(&format!(
                "host run of {forever} stopped: nothing more of it is sent"
            ))
            .await;
        assert!(
            !frame
                .lines()
                .last()
                .unwrap_or_default()
                .contains("from the host"),
            "{frame}"
        );
    })
    .await;
    assert_eq!(
        session
            .execute_line("DO1")
            .await
            .expect("DO1")
            .value
            .to_string(),
        "1"
    );
}
