//! A watched line (a parameter plotted in the console) is polled with the
//! status as a slow item until it is no longer watched: seen in the
//! traffic of an in-process TMCM-1110 on tokio's paused clock.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::device::{Direction, TrafficKind, TrafficRecord};
use axterm::families::find_kind;
use axterm::link::LinkSpec;
use axterm::session::{PollCadence, Session, SessionOptions, WatchedValue};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;
use tokio::sync::broadcast;

/// Virtual time: only guards against a hung test.
const GIVE_UP_AFTER: Duration = Duration::from_secs(600);

/// `GAP 6, 0` to module 1, written out from TMCL §4 (Table 7): address,
/// instruction 6, type 6 (run current), motor 0, value 0, checksum
/// 1 + 6 + 6 = 13.
const GAP_6: [u8; 9] = [0x01, 0x06, 0x06, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0D];

async fn connect() -> Session {
    let kind = find_kind("tmcm1110").expect("registered");
    let spec = LinkSpec::Sim {
        kind: kind.name.into(),
        sim: Arc::new(Mutex::new((kind.build)(&SimOptions::default()))),
        baud: None,
        faults: FaultPlan::none(),
    };
    let family = axterm::families::family_of(kind).expect("family");
    Session::connect(spec, family, SessionOptions::default())
        .await
        .expect("the simulator link opens")
}

/// The next `count` requests sent.
async fn requests(traffic: &mut broadcast::Receiver<TrafficRecord>, count: usize) -> Vec<Vec<u8>> {
    let mut sent = Vec::new();
    let wait = async {
        while sent.len() < count {
            match traffic.recv().await {
                Ok(r) if r.direction == Direction::Sent && r.kind == TrafficKind::Request => {
                    sent.push(r.bytes)
                }
                Ok(_) | Err(broadcast::error::RecvError::Lagged(_)) => {}
                Err(broadcast::error::RecvError::Closed) => panic!("the device task ended"),
            }
        }
    };
    tokio::time::timeout(GIVE_UP_AFTER, wait)
        .await
        .expect("requests went out");
    sent
}

#[tokio::test(start_paused = true)]
async fn a_watched_parameter_is_polled_until_it_is_no_longer_watched() {
    let session = connect().await;
    session
        .execute_line("SAP 6, 0, 200")
        .await
        .expect("run current set");
    let mut traffic = session.device().traffic();
    session.start_polling(PollCadence::default());
    // Two seconds of status polls (about a hundred a second): no GAP 6.
    assert!(!requests(&mut traffic, 200).await.contains(&GAP_6.to_vec()));

    session.watch(0, "GAP 6, 0").expect("a read of axis 0");
    let polled = requests(&mut traffic, 200).await;
    let reads = polled.iter().filter(|r| **r == GAP_6).count();
    // As often as the slow items (5 Hz against the positions' 20 Hz).
    assert!(reads >= 4, "GAP 6 read {reads} times in 200 polls");
    let mut status = session.status();
    let answered = async {
        loop {
            if status.borrow_and_update()[0].watched
                == [WatchedValue {
                    line: "GAP 6, 0".into(),
                    value: Some(200),
                    reply: Some(axterm::protocol::console::ReplyValue::Number(200)),
                }]
            {
                break;
            }
            status.changed().await.expect("the session is alive");
        }
    };
    tokio::time::timeout(GIVE_UP_AFTER, answered)
        .await
        .expect("the value came");

    session.unwatch(0, "GAP 6, 0");
    assert!(session.status().borrow()[0].watched.is_empty());
    // The read already on the wire may still come; after it, none.
    requests(&mut traffic, 12).await;
    assert!(!requests(&mut traffic, 200).await.contains(&GAP_6.to_vec()));
}

#[test]
fn only_reads_of_an_axis_are_watched() {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .start_paused(true)
        .build()
        .expect("runtime");
    runtime.block_on(async {
        let session = connect().await;
        let moving = session
            .watch(0, "ROR 0, 300")
            .expect_err("a motion is no read");
        assert!(moving.to_string().contains("only a read"), "{moving}");
        let nonsense = session.watch(0, "GAP banana").expect_err("does not parse");
        assert!(nonsense.nothing_sent());
        assert!(session.watch(7, "GAP 6, 0").is_err(), "no axis 7");
    });
}

/// `GAP 11, 0` (left limit switch) to module 1: 1 + 6 + 11 = 18.
const GAP_11: [u8; 9] = [0x01, 0x06, 0x0B, 0x00, 0x00, 0x00, 0x00, 0x00, 0x12];

/// A switch watched fast (the bring-up pane's lamps) that the status
/// reads anyway as a slow item is not read twice: that item goes with the
/// fast ones, as often as the position, and its answer is the watch's.
#[tokio::test(start_paused = true)]
async fn a_fast_watch_of_a_status_line_shares_it_at_the_fast_rate() {
    let session = connect().await;
    let mut traffic = session.device().traffic();
    session.start_polling(PollCadence::default());
    let before = requests(&mut traffic, 300).await;
    let slow = before.iter().filter(|r| **r == GAP_11).count();
    session
        .watch_at(0, "GAP 11, 0", true)
        .expect("a read of axis 0");
    requests(&mut traffic, 12).await;
    let after = requests(&mut traffic, 300).await;
    let fast = after.iter().filter(|r| **r == GAP_11).count();
    let positions = after.iter().filter(|r| r[1] == 6 && r[2] == 1).count();
    assert!(fast > slow, "GAP 11 read {fast} times, {slow} before");
    assert!(
        fast + 1 >= positions,
        "GAP 11 read {fast} times, the position {positions}"
    );
    let mut status = session.status();
    let answered = async {
        loop {
            if status.borrow_and_update()[0]
                .watched
                .iter()
                .any(|w| w.line == "GAP 11, 0" && w.value == Some(0))
            {
                break;
            }
            status.changed().await.expect("the session is alive");
        }
    };
    tokio::time::timeout(GIVE_UP_AFTER, answered)
        .await
        .expect("the shared reading came");
}
