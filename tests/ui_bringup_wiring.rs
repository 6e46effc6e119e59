//! The wiring check from the bring-up pane (Alt-8), through the real loop
//! and a session on the CMD-4CR simulator, on tokio's paused clock: `w`
//! asks y/n and moves nothing without the y; with it the session's check
//! runs and its findings stand in the pane, at 80×24 and at 160×48 (right
//! wiring and `LIMITS=swapped`); Esc during the check ends it and sends
//! the axis's stop, and the axis stays standing.

mod ui_support;

use std::sync::Arc;
use std::time::Duration;

use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::device::{Direction, TrafficRecord};
use axterm::session::{Session, SessionOptions};
use axterm::ui::app::Controller;
use axterm::ui::live::SessionController;
use ratatui::crossterm::event::KeyCode;
use tokio::sync::broadcast;
use ui_support::looped::{Rig, no_connector, press, run_console_on};

async fn session(inputs: &[&str]) -> Session {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some("cmd4cr".into()),
        baud: Some(9600),
        input: inputs.iter().map(|s| s.to_string()).collect(),
        ..ConnectionArgs::default()
    })
    .expect("resolves");
    let session = target.open().await.expect("the simulator link opens");
    session.execute_line("EO=1").await.expect("motor enabled");
    session
}

/// The console at `size` on `session`, the bring-up pane focused, until
/// `driver` is done (then F10).
async fn run_bringup(session: &Session, size: (u16, u16), driver: impl AsyncFnOnce(&mut Rig)) {
    let controller: Arc<dyn Controller> = Arc::new(SessionController::new(
        session.clone(),
        "sim".into(),
        SessionOptions::default(),
    ));
    let mut app = ui_support::console_with(&axterm::ui::PaneSetup::default());
    app.focus("bringup");
    run_console_on(
        app,
        size,
        Some(controller),
        no_connector(),
        async |mut rig: Rig| {
            driver(&mut rig).await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
}

/// Jog at the fastest of the family's speeds (50,000 pps: the stage's
/// ends, 100,000 pulses out, in about 2 s), then `w` and `y`.
async fn start_check(rig: &mut Rig) {
    rig.screens.until("standing by").await;
    for _ in 0..5 {
        press(rig, KeyCode::Char('f'));
    }
    rig.screens.until("speed 50000 pps").await;
    press(rig, KeyCode::Char('w'));
    rig.screens.until("y/n").await;
    press(rig, KeyCode::Char('y'));
}

#[tokio::test(start_paused = true)]
async fn at_80x24_the_findings_of_a_right_wiring_stand_in_the_pane() {
    let session = session(&[]).await;
    run_bringup(&session, (80, 24), async |rig: &mut Rig| {
        start_check(rig).await;
        let screen = rig.screens.until("wiring check: each limit switch").await;
        // Wrapped to the pane's width, each finding whole.
        let flat = screen.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(
            flat.contains("X, moving +: the + (right) switch fired at"),
            "{screen}"
        );
        assert!(flat.contains("as it should;"), "{screen}");
        assert!(
            screen.contains("X, moving -: the − (left) switch fired at"),
            "{screen}"
        );
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn at_160x48_swapped_limits_are_said_as_swapped_wiring() {
    let session = session(&["LIMITS=swapped"]).await;
    run_bringup(&session, (160, 48), async |rig: &mut Rig| {
        start_check(rig).await;
        let screen = rig.screens.until("wiring check: something is wrong").await;
        // The pane is the left half: the finding wraps at its edge.
        assert!(
            screen.contains("X, moving + tripped the − (left) switch at 1")
                && screen.contains(": swapped wiring or inverted"),
            "{screen}"
        );
        assert!(
            screen.contains("X, moving -: the module refused to move"),
            "{screen}"
        );
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn without_the_y_nothing_moves() {
    let session = session(&[]).await;
    let mut traffic = session.device().traffic();
    run_bringup(&session, (100, 30), async |rig: &mut Rig| {
        rig.screens.until("standing by").await;
        press(rig, KeyCode::Char('w'));
        rig.screens.until("y/n").await;
        press(rig, KeyCode::Char('n'));
        rig.screens
            .until("wiring check not run: nothing moved")
            .await;
    })
    .await;
    while let Ok(record) = traffic.try_recv() {
        assert!(
            !(record.direction == Direction::Sent && record.bytes.starts_with(b"@01JX")),
            "a jog went out: {record:?}"
        );
    }
}

/// Wait for `bytes` to go out on the link.
async fn until_sent(traffic: &mut broadcast::Receiver<TrafficRecord>, bytes: &[u8]) {
    loop {
        match traffic.recv().await {
            Ok(record) if record.direction == Direction::Sent && record.bytes == bytes => return,
            Ok(_) | Err(broadcast::error::RecvError::Lagged(_)) => {}
            Err(broadcast::error::RecvError::Closed) => panic!("the link closed"),
        }
    }
}

#[tokio::test(start_paused = true)]
async fn esc_during_the_check_stops_the_axis_and_it_stays_standing() {
    let session = session(&[]).await;
    let mut traffic = session.device().traffic();
    let plan = session.family().console.jog().expect("a jog plan");
    let stop_line = plan.stop(&session.axes()[0]);
    let stop = session
        .prepare(stop_line.last().expect("a stop line"))
        .expect("prepares")
        .bytes;
    let probe = session.clone();
    run_bringup(&session, (100, 30), async |rig: &mut Rig| {
        start_check(rig).await;
        rig.screens.until("WIRING CHECK").await;
        until_sent(&mut traffic, b"@01JX+\r").await;
        tokio::time::sleep(Duration::from_millis(300)).await;
        press(rig, KeyCode::Esc);
        until_sent(&mut traffic, &stop).await;
        rig.screens.until("jog stopped").await;
        // The check's task ended: no − leg follows, the axis stands.
        tokio::time::sleep(Duration::from_secs(2)).await;
        let first = probe
            .execute_line("PX")
            .await
            .expect("PX")
            .value
            .to_string();
        // Longer than the check's 30 s give-up: a check left running
        // would start its − leg by now.
        tokio::time::sleep(Duration::from_secs(40)).await;
        let later = probe
            .execute_line("PX")
            .await
            .expect("PX")
            .value
            .to_string();
        assert_eq!(first, later, "still standing");
        assert_eq!(
            probe
                .execute_line("PSX")
                .await
                .expect("PSX")
                .value
                .to_string(),
            "0"
        );
    })
    .await;
    while let Ok(record) = traffic.try_recv() {
        assert!(
            !(record.direction == Direction::Sent && record.bytes == b"@01JX-\r"),
            "the − leg went out after Esc"
        );
    }
}
