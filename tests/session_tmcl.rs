//! The session over an in-process TMCM-1110 simulator on tokio's paused
//! clock: lines in, values and errors out, axis status that follows the
//! module, error flags that are never lost.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::families::find_kind;
use axterm::link::LinkSpec;
use axterm::session::{AxisStatus, PollCadence, ReplyValue, Session, SessionError, SessionOptions};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;

/// Virtual time: only guards against a hung test.
const GIVE_UP_AFTER: Duration = Duration::from_secs(600);

async fn connect(baud: Option<u32>) -> Session {
    connect_with(baud, FaultPlan::none()).await
}

async fn connect_with(baud: Option<u32>, faults: FaultPlan) -> Session {
    let kind = find_kind("tmcm1110").expect("registered");
    let spec = LinkSpec::Sim {
        kind: kind.name.into(),
        sim: Arc::new(Mutex::new((kind.build)(&SimOptions::default()))),
        baud,
        faults,
    };
    let family = axterm::families::family_of(kind).expect("family");
    Session::connect(spec, family, SessionOptions::default())
        .await
        .expect("the simulator link opens")
}

async fn value(session: &Session, line: &str) -> ReplyValue {
    session
        .execute_line(line)
        .await
        .unwrap_or_else(|e| panic!("{line}: {e}"))
        .value
}

/// Wait (in virtual time) until the first axis's snapshot satisfies `done`;
/// return every snapshot seen on the way.
async fn watch_until(session: &Session, done: impl Fn(&AxisStatus) -> bool) -> Vec<AxisStatus> {
    let mut status = session.status();
    let mut seen = Vec::new();
    let wait = async {
        loop {
            let axis = status.borrow_and_update()[0].clone();
            let finished = done(&axis);
            seen.push(axis);
            if finished {
                break;
            }
            status.changed().await.expect("the session is alive");
        }
    };
    tokio::time::timeout(GIVE_UP_AFTER, wait)
        .await
        .expect("the status got there");
    seen
}

#[tokio::test(start_paused = true)]
async fn a_parameter_written_reads_back() {
    let session = connect(None).await;
    assert_eq!(value(&session, "SAP 4, 0, 1234").await, ReplyValue::None);
    assert_eq!(value(&session, "GAP 4, 0").await, ReplyValue::Number(1234));
}

#[tokio::test(start_paused = true)]
async fn the_module_says_who_it_is() {
    let session = connect(None).await;
    let identity = session.identify().await.expect("version");
    assert_eq!(identity, "1110V112");
    assert_eq!(*session.identity().borrow(), Some("1110V112".to_string()));
}

#[tokio::test(start_paused = true)]
async fn a_refused_line_sends_nothing() {
    let session = connect(None).await;
    let error = session.execute_line("SAP 6, 0, 100000").await.unwrap_err();
    assert!(error.nothing_sent(), "{error}");
    assert!(error.to_string().contains("0..255"), "{error}");
    let counters = *session.device().counters().borrow();
    assert_eq!(counters.transactions, 0);
}

#[tokio::test(start_paused = true)]
async fn a_rejection_names_the_module_the_line_and_the_status() {
    let session = connect(None).await;
    // A raw frame passes the console's checks; the module refuses it.
    let error = session.execute_line("5 6 0 300").await.unwrap_err();
    assert_eq!(
        error.to_string(),
        "module 1 rejected SAP 6, 0, 300: invalid value (status 4)"
    );
    assert!(matches!(error, SessionError::Reply { .. }));
    assert_eq!(error.status(), Some(4));
}

#[tokio::test(start_paused = true)]
async fn nobody_at_the_address_is_a_timeout() {
    let session = connect(None).await;
    let error = session
        .probe(9, Duration::from_millis(50))
        .await
        .unwrap_err();
    assert!(
        error
            .to_string()
            .starts_with("module 9 did not answer VERSION STRING"),
        "{error}"
    );
    assert_eq!(
        session.probe(1, Duration::from_millis(50)).await.unwrap(),
        "1110V112"
    );
}

#[tokio::test(start_paused = true)]
async fn axis_status_follows_a_move() {
    let session = connect(Some(9600)).await;
    session.start_polling(PollCadence::default());
    watch_until(&session, |a| a.position == Some(0) && a.reached.is_some()).await;
    value(&session, "MVP ABS, 0, 51200").await;
    let seen = watch_until(&session, |a| {
        a.position == Some(51200) && a.reached == Some(true) && a.speed == Some(0)
    })
    .await;
    let positions: Vec<i64> = seen.iter().filter_map(|a| a.position).collect();
    assert!(
        positions.iter().any(|&p| p > 0 && p < 51200),
        "no position on the way: {positions:?}"
    );
    assert!(
        positions.windows(2).all(|w| w[0] <= w[1]),
        "the position went backwards: {positions:?}"
    );
    assert!(
        seen.iter()
            .any(|a| a.speed.is_some_and(|s| s > 0) && a.reached == Some(false)),
        "never seen moving"
    );
    let last = seen.last().expect("seen");
    assert_eq!(last.target, Some(51200));
    assert!(last.errors.is_empty());
}

/// Make the encoder count half the motor's steps (AP210 = 256, §6.3) with a
/// deviation limit (AP212): the next move stops on a deviation error.
async fn provoke_deviation(session: &Session) {
    value(session, "SAP 212, 0, 100").await;
    value(session, "SAP 210, 0, 256").await;
    value(session, "MVP ABS, 0, 51200").await;
}

#[tokio::test(start_paused = true)]
async fn error_flags_stay_latched_until_acknowledged() {
    let session = connect(Some(9600)).await;
    session.start_polling(PollCadence::default());
    provoke_deviation(&session).await;
    let seen = watch_until(&session, |a| !a.errors.is_empty()).await;
    let flags = seen.last().expect("seen").errors.clone();
    let names: Vec<&str> = flags.iter().map(|f| f.name).collect();
    assert_eq!(names, ["deviation"]);
    // Polling read AP207, which clears it in the module (§4): the module
    // now says 0, the snapshot still says deviation.
    assert_eq!(value(&session, "GAP 207, 0").await, ReplyValue::Number(0));
    // Let polling go on for a while.
    tokio::time::sleep(Duration::from_secs(2)).await;
    assert_eq!(session.status().borrow()[0].errors, flags);
    session.acknowledge_errors(0, &flags);
    assert!(session.status().borrow()[0].errors.is_empty());
}

#[tokio::test(start_paused = true)]
async fn the_users_own_read_of_the_error_flags_is_latched_too() {
    let session = connect(None).await;
    provoke_deviation(&session).await;
    tokio::time::sleep(Duration::from_secs(1)).await;
    assert_eq!(value(&session, "GAP 207, 0").await, ReplyValue::Number(2));
    assert_eq!(value(&session, "GAP 207, 0").await, ReplyValue::Number(0));
    let names: Vec<&str> = session.status().borrow()[0]
        .errors
        .iter()
        .map(|f| f.name)
        .collect();
    assert_eq!(names, ["deviation"]);
}

#[tokio::test(start_paused = true)]
async fn emergency_stop_stops_the_motor() {
    let session = connect(Some(9600)).await;
    value(&session, "ROR 0, 1000").await;
    tokio::time::sleep(Duration::from_millis(500)).await;
    assert_ne!(value(&session, "GAP 3, 0").await, ReplyValue::Number(0));
    session.emergency_stop().await.expect("stopped");
    assert_eq!(value(&session, "GAP 2, 0").await, ReplyValue::Number(0));
    tokio::time::sleep(Duration::from_secs(5)).await;
    assert_eq!(value(&session, "GAP 3, 0").await, ReplyValue::Number(0));
}

#[tokio::test(start_paused = true)]
async fn every_reply_corrupted_no_line_is_ok_but_the_reset_whose_reply_may_be_lost() {
    let faults = FaultPlan::parse("corrupt=1,seed=4").expect("a fault spec");
    let session = connect_with(Some(115_200), faults.clone()).await;
    let error = session.execute_line("SAP 4, 0, 1000").await.unwrap_err();
    assert!(
        error
            .to_string()
            .starts_with("unreadable answer to SAP 4, 0, 1000: 02 01 "),
        "{error}"
    );
    assert_eq!(error.reply().map(<[u8]>::len), Some(9), "{error}");
    assert!(session.execute_line("GAP 4, 0").await.is_err());
    // §3.6.53: the reply to a software reset "might not always get
    // through"; one that comes garbled is as good as one that is lost.
    let reset = session.execute_line("RESET").await.expect("done");
    assert_eq!(reset.value, ReplyValue::None);
    assert!(reset.reply.is_empty());
    assert!(faults.counts().corrupted >= 3);
}
