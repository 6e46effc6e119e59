//! The end of a run that did not complete ([`Session::end_run`]), over the
//! in-process TMCM-1110 simulator on tokio's paused clock: the stop
//! sequence goes out and the axis comes to speed 0 short of its target;
//! told to leave the axes, nothing is sent; a link lost mid-motion gets
//! the stop once it is back, and one that stays away is reported with every
//! stop line as not sent.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::device::{
    self, DeviceOptions, Direction, Priority, TrafficKind, TrafficRecord, never_reopen,
};
use axterm::families::find_family;
use axterm::families::find_kind;
use axterm::link::LinkSpec;
use axterm::session::run_end::{
    LINK_RETURN_WAIT, LinkAtStop, RunAftermath, RunEnding, StopOnFailure,
};
use axterm::session::{ReplyValue, Session, SessionOptions};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;
use tokio::sync::broadcast;

/// The TMCL stop sequence (`TmclConsole::emergency_stop`): every motor,
/// the standalone program, every motor again.
const STOP_LINES: [&str; 3] = ["MST 0", "STOPAPP", "MST 0"];

fn spec(faults: FaultPlan) -> LinkSpec {
    let kind = find_kind("tmcm1110").expect("registered");
    LinkSpec::Sim {
        kind: kind.name.into(),
        sim: Arc::new(Mutex::new((kind.build)(&SimOptions::default()))),
        baud: Some(9600),
        faults,
    }
}

async fn connect(faults: FaultPlan) -> Session {
    Session::connect(
        spec(faults),
        find_family("tmcl").expect("tmcl"),
        SessionOptions::default(),
    )
    .await
    .expect("the simulator link opens")
}

async fn number(session: &Session, line: &str) -> i64 {
    match session.execute_line(line).await {
        Ok(result) => match result.value {
            ReplyValue::Number(n) => n,
            other => panic!("{line}: {other}"),
        },
        Err(e) => panic!("{line}: {e}"),
    }
}

/// Start the move of issue 11: far away at speed 1500.
async fn start_long_move(session: &Session) {
    for line in ["SAP 4, 0, 1500", "MVP ABS, 0, 512000000"] {
        session
            .execute_line(line)
            .await
            .unwrap_or_else(|e| panic!("{line}: {e}"));
    }
    // What the run's `:wait-until GAP 8, 0 == 1 timeout 100ms` saw.
    for _ in 0..5 {
        assert_eq!(number(session, "GAP 8, 0").await, 0);
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
}

/// Read the speed until it is 0 (the module decelerates after MST), a
/// read every 100 ms of virtual time; false if it is still turning after
/// `reads` reads.
async fn comes_to_rest(session: &Session, reads: usize) -> bool {
    for _ in 0..reads {
        if number(session, "GAP 3, 0").await == 0 {
            return true;
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    false
}

/// The requests sent since `traffic` was subscribed, as hex.
fn requests(traffic: &mut broadcast::Receiver<TrafficRecord>) -> Vec<(Priority, Vec<u8>)> {
    let mut all = Vec::new();
    while let Ok(record) = traffic.try_recv() {
        if record.direction == Direction::Sent && record.kind == TrafficKind::Request {
            all.push((
                record.priority.expect("a request has a priority"),
                record.bytes,
            ));
        }
    }
    all
}

fn stop_lines(aftermath: &RunAftermath) -> Vec<String> {
    match aftermath {
        RunAftermath::Stopped(stop) => stop
            .lines
            .iter()
            .map(|l| match l {
                Ok(r) => r.line.clone(),
                Err(e) => panic!("a stop line failed: {e}"),
            })
            .collect(),
        other => panic!("no stop: {other:?}"),
    }
}

#[tokio::test(start_paused = true)]
async fn a_failed_run_ends_with_the_stop_sequence_and_the_axis_at_speed_0_short_of_its_target() {
    let session = connect(FaultPlan::none()).await;
    start_long_move(&session).await;
    assert_ne!(
        number(&session, "GAP 3, 0").await,
        0,
        "the move is under way"
    );
    let mut traffic = session.device().traffic();
    let aftermath = session
        .end_run(RunEnding::Failed, StopOnFailure::Stop)
        .await;
    assert_eq!(stop_lines(&aftermath), STOP_LINES);
    assert!(aftermath.settled(), "{:?}", aftermath.report());
    // Each stop line went at emergency-stop priority, as the console's
    // stop key sends them: MST 0 by the manual's bytes (§3.6.3).
    let sent = requests(&mut traffic);
    assert_eq!(sent.len(), 3, "{sent:?}");
    assert!(sent.iter().all(|(p, _)| *p == Priority::EmergencyStop));
    assert_eq!(sent[0].1, [0x01, 0x03, 0x00, 0x00, 0, 0, 0, 0, 0x04]);
    let report = aftermath.report();
    assert_eq!(report[0], "the run failed: stopping every axis:");
    assert_eq!(report[1], "  MST 0 → ok");
    assert_eq!(
        report.last().map(String::as_str),
        Some("stop confirmed: every stop line answered ok")
    );
    assert!(comes_to_rest(&session, 100).await, "the axis still turns");
    assert_eq!(
        number(&session, "GAP 8, 0").await,
        0,
        "stopped short of the target"
    );
}

#[tokio::test(start_paused = true)]
async fn a_cancelled_run_stops_too_and_one_told_to_leave_the_axes_sends_nothing() {
    let session = connect(FaultPlan::none()).await;
    start_long_move(&session).await;
    let mut traffic = session.device().traffic();
    let left = session
        .end_run(RunEnding::Failed, StopOnFailure::Leave)
        .await;
    assert!(matches!(left, RunAftermath::Left(RunEnding::Failed)));
    assert!(requests(&mut traffic).is_empty(), "nothing sent");
    tokio::time::sleep(Duration::from_secs(2)).await;
    assert_eq!(number(&session, "GAP 3, 0").await, 1500, "still moving");
    let completed = session
        .end_run(RunEnding::Completed, StopOnFailure::Stop)
        .await;
    assert!(matches!(completed, RunAftermath::Completed));

    let cancelled = session
        .end_run(RunEnding::Cancelled, StopOnFailure::Stop)
        .await;
    assert_eq!(stop_lines(&cancelled), STOP_LINES);
    assert!(cancelled.report()[0].starts_with("the run was cancelled: stopping"));
    assert!(comes_to_rest(&session, 100).await, "the axis still turns");
}

#[tokio::test(start_paused = true)]
async fn a_link_lost_mid_motion_gets_the_stop_once_it_is_back() {
    // The cable is pulled at the 40th request of each connection: the
    // run's reads get as far as that; after the reopening the stop and
    // the reads that follow it fit.
    let faults = FaultPlan {
        disconnect_after: Some(40),
        ..FaultPlan::none()
    };
    let session = connect(faults.clone()).await;
    start_long_move(&session).await;
    let lost = loop {
        match session.execute_line("GAP 8, 0").await {
            Ok(_) => tokio::time::sleep(Duration::from_millis(20)).await,
            Err(e) => break e,
        }
    };
    assert!(!lost.nothing_sent(), "{lost}");
    let aftermath = session
        .end_run(RunEnding::Failed, StopOnFailure::Stop)
        .await;
    let RunAftermath::Stopped(stop) = &aftermath else {
        panic!("{aftermath:?}");
    };
    assert!(
        matches!(stop.link, LinkAtStop::CameBack { waited } if waited < LINK_RETURN_WAIT),
        "{:?}",
        stop.link
    );
    assert_eq!(stop_lines(&aftermath), STOP_LINES);
    assert!(
        aftermath.report()[0].contains("the link was down; it came back after"),
        "{:?}",
        aftermath.report()
    );
    assert_eq!(faults.record.counts().disconnects, 1);
    assert!(comes_to_rest(&session, 30).await, "the axis still turns");
}

#[tokio::test(start_paused = true)]
async fn a_link_that_stays_away_is_reported_and_no_stop_line_reads_as_sent() {
    let family = find_family("tmcl").expect("tmcl");
    let faults = FaultPlan {
        disconnect_after: Some(2),
        ..FaultPlan::none()
    };
    let link = spec(faults).open().await.expect("opens");
    let device = device::spawn(
        link,
        never_reopen("sim tmcm1110", "the cable is unplugged"),
        family.console.wire(),
        DeviceOptions::default(),
    );
    let session = Session::new(device, family, &SessionOptions::default());
    for line in ["SAP 4, 0, 1500", "MVP ABS, 0, 512000000"] {
        session.execute_line(line).await.expect(line);
    }
    assert!(session.execute_line("GAP 8, 0").await.is_err(), "cut");
    let started = tokio::time::Instant::now();
    let aftermath = session
        .end_run(RunEnding::Failed, StopOnFailure::Stop)
        .await;
    assert!(
        started.elapsed() >= LINK_RETURN_WAIT,
        "waited for the link for {:?}",
        started.elapsed()
    );
    let RunAftermath::Stopped(stop) = &aftermath else {
        panic!("{aftermath:?}");
    };
    assert!(
        matches!(&stop.link, LinkAtStop::StayedDown { reason, .. } if reason.contains("unplugged")),
        "{:?}",
        stop.link
    );
    assert!(!aftermath.settled());
    let report = aftermath.report();
    assert!(report[0].contains("did not come back"), "{report:?}");
    let shown: Vec<&str> = report.iter().skip(1).take(3).map(String::as_str).collect();
    for (shown, line) in shown.iter().zip(STOP_LINES) {
        assert!(
            shown.starts_with(&format!("  {line}: NOT SENT")),
            "{shown}: {report:?}"
        );
    }
    assert!(
        report
            .last()
            .is_some_and(|l| l.starts_with("STOP NOT CONFIRMED: 3 of 3")),
        "{report:?}"
    );
}
