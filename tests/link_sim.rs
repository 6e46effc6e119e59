//! The in-process simulator link on tokio's paused clock: replies, wire
//! time at a baud rate, injected faults and reopening after a loss, all
//! asserted on virtual time, which is deterministic.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::link::{Link, LinkInput, LinkSpec, SharedSim, byte_time};
use axterm::protocol::tmcl::{FRAME_LEN, Reply, Request, Status};
use axterm::sim::faults::FaultPlan;
use axterm::sim::{SimOptions, SimulatedController};
use tokio::time::Instant;

const GAP: u8 = 6;
const SAP: u8 = 5;
const MVP: u8 = 4;
const TARGET_EVENT: u8 = 138;

fn steprocker() -> SharedSim {
    let kind = axterm::families::find_kind("tmcm1110").expect("registered");
    Arc::new(Mutex::new((kind.build)(&SimOptions::default())))
}

fn spec(sim: &SharedSim, baud: Option<u32>, faults: &str) -> LinkSpec {
    LinkSpec::Sim {
        kind: "tmcm1110".into(),
        sim: Arc::clone(sim),
        baud,
        faults: FaultPlan::parse(faults).expect("a good fault spec"),
    }
}

fn request(command: u8, kind: u8, value: i32) -> [u8; FRAME_LEN] {
    Request {
        address: 1,
        command,
        kind,
        motor_bank: 0,
        value,
    }
    .to_bytes()
}

/// The next `n` bytes, with the virtual time the last of them arrived.
async fn receive(link: &mut Link, n: usize) -> (Vec<u8>, Instant) {
    let mut got = Vec::new();
    while got.len() < n {
        match link.incoming.recv().await {
            Some(LinkInput::Bytes(bytes)) => got.extend(bytes),
            other => panic!("expected bytes, got {other:?} after {got:02X?}"),
        }
    }
    (got, Instant::now())
}

async fn transact(link: &mut Link, frame: [u8; FRAME_LEN]) -> [u8; FRAME_LEN] {
    link.outgoing.send(&frame).expect("send");
    let (bytes, _) = receive(link, FRAME_LEN).await;
    bytes.try_into().expect("exactly one frame")
}

async fn reply_to(link: &mut Link, frame: [u8; FRAME_LEN]) -> Reply {
    Reply::from_bytes(&transact(link, frame).await).expect("a good checksum")
}

#[tokio::test(start_paused = true)]
async fn a_request_gets_the_simulators_reply_at_once_without_a_baud_rate() {
    let sim = steprocker();
    let mut link = spec(&sim, None, "").open().await.expect("opens");
    assert_eq!(link.name, "sim tmcm1110");
    assert_eq!(link.byte_time, None);
    let start = Instant::now();
    let reply = reply_to(&mut link, request(SAP, 4, 1000)).await;
    assert_eq!((reply.status, reply.command), (Status::OK, SAP));
    assert_eq!(start.elapsed(), Duration::ZERO);
    let reply = reply_to(&mut link, request(GAP, 4, 0)).await;
    assert_eq!(reply.value, 1000);
}

#[tokio::test(start_paused = true)]
async fn at_9600_baud_a_frame_takes_its_wire_time_each_way() {
    let sim = steprocker();
    let mut link = spec(&sim, Some(9600), "").open().await.expect("opens");
    assert_eq!(link.name, "sim tmcm1110 at 9600 Bd");
    assert_eq!(link.byte_time, Some(byte_time(9600)));
    let one_way = 9 * byte_time(9600); // 9.375 ms
    let start = Instant::now();
    link.outgoing.send(&request(GAP, 1, 0)).expect("send");

    // The request is on the wire for 9.375 ms, so nothing can come back
    // before then, and the first reply byte takes another byte time.
    let first = link.incoming.recv().await;
    let first_at = start.elapsed();
    assert!(first_at >= Duration::from_micros(9_400), "{first_at:?}");
    let Some(LinkInput::Bytes(mut bytes)) = first else {
        panic!("expected bytes, got {first:?}");
    };
    assert!(
        bytes.len() < FRAME_LEN,
        "the reply trickles in: {bytes:02X?}"
    );
    let (rest, done) = receive(&mut link, FRAME_LEN - bytes.len()).await;
    bytes.extend(rest);
    let elapsed = done - start;
    assert!(elapsed >= 2 * one_way, "{elapsed:?}");
    // Timers fire on whole milliseconds, so a little later than the wire.
    assert!(
        elapsed <= 2 * one_way + Duration::from_millis(2),
        "{elapsed:?}"
    );
    let frame: [u8; FRAME_LEN] = bytes.try_into().expect("one frame");
    let reply = Reply::from_bytes(&frame).expect("good checksum");
    assert_eq!((reply.status, reply.command), (Status::OK, GAP));
}

/// Echoes what it is fed and remembers when, on its own clock.
#[derive(Default)]
struct Echo {
    clock: Duration,
    fed_at: Arc<Mutex<Vec<Duration>>>,
    output: Vec<u8>,
}

impl SimulatedController for Echo {
    fn feed(&mut self, bytes: &[u8]) {
        if let Ok(mut fed) = self.fed_at.lock() {
            fed.extend(bytes.iter().map(|_| self.clock));
        }
        self.output.extend_from_slice(bytes);
    }
    fn advance(&mut self, dt: Duration) {
        self.clock += dt;
    }
    fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.output)
    }
    fn help(&self) -> String {
        "echo".into()
    }
}

#[tokio::test(start_paused = true)]
async fn bytes_reach_the_simulator_one_byte_time_apart() {
    let echo = Echo::default();
    let fed_at = Arc::clone(&echo.fed_at);
    let sim: SharedSim = Arc::new(Mutex::new(Box::new(echo)));
    let mut link = spec(&sim, Some(9600), "").open().await.expect("opens");
    link.outgoing.send(&[0u8; 9]).expect("send");
    receive(&mut link, 9).await;
    let each = byte_time(9600);
    let expected: Vec<Duration> = (1..=9).map(|i| i * each).collect();
    assert_eq!(*fed_at.lock().expect("lock"), expected);
}

#[tokio::test(start_paused = true)]
async fn the_simulator_speaks_on_its_own_as_virtual_time_passes() {
    let sim = steprocker();
    let mut link = spec(&sim, None, "").open().await.expect("opens");
    let reply = reply_to(&mut link, request(TARGET_EVENT, 0, 1)).await;
    assert_eq!(reply.status, Status::OK);
    let start = Instant::now();
    let reply = reply_to(&mut link, request(MVP, 0, 2000)).await;
    assert_eq!((reply.status, reply.command), (Status::OK, MVP));
    // §3.6.52: the second reply of 138 comes when the target is reached.
    let (bytes, _) = receive(&mut link, FRAME_LEN).await;
    assert!(start.elapsed() > Duration::ZERO, "the move takes time");
    let frame: [u8; FRAME_LEN] = bytes.try_into().expect("one frame");
    let reached = Reply::from_bytes(&frame).expect("good checksum");
    assert_eq!(
        (reached.status, reached.command),
        (Status::TARGET_REACHED, TARGET_EVENT)
    );
    let reply = reply_to(&mut link, request(GAP, 1, 0)).await;
    assert_eq!(reply.value, 2000, "actual position");
}

#[tokio::test(start_paused = true)]
async fn a_dropped_reply_never_arrives_and_is_counted() {
    let sim = steprocker();
    let spec = spec(&sim, None, "drop=1");
    let mut link = spec.open().await.expect("opens");
    link.outgoing.send(&request(GAP, 1, 0)).expect("send");
    let waited = tokio::time::timeout(Duration::from_secs(1), link.incoming.recv()).await;
    assert!(waited.is_err(), "nothing arrives: {waited:?}");
    let LinkSpec::Sim { faults, .. } = &spec else {
        unreachable!("a sim spec")
    };
    let counts = faults.counts();
    assert_eq!((counts.requests, counts.dropped), (1, 1));
}

#[tokio::test(start_paused = true)]
async fn a_corrupted_reply_fails_its_checksum() {
    let sim = steprocker();
    let mut link = spec(&sim, None, "corrupt=1,seed=5")
        .open()
        .await
        .expect("opens");
    for _ in 0..20 {
        let frame = transact(&mut link, request(GAP, 1, 0)).await;
        assert!(Reply::from_bytes(&frame).is_err(), "{frame:02X?}");
    }
}

#[tokio::test(start_paused = true)]
async fn garbage_comes_before_the_reply() {
    let sim = steprocker();
    let mut link = spec(&sim, None, "garbage=1").open().await.expect("opens");
    link.outgoing.send(&request(GAP, 1, 0)).expect("send");
    let Some(LinkInput::Bytes(bytes)) = link.incoming.recv().await else {
        panic!("expected bytes");
    };
    assert!(bytes.len() > FRAME_LEN, "{bytes:02X?}");
    let tail: [u8; FRAME_LEN] = bytes
        .get(bytes.len() - FRAME_LEN..)
        .and_then(|t| t.try_into().ok())
        .expect("a frame at the end");
    assert_eq!(Reply::from_bytes(&tail).expect("intact").command, GAP);
}

#[tokio::test(start_paused = true)]
async fn a_delayed_reply_arrives_late_by_the_given_time() {
    let sim = steprocker();
    let mut link = spec(&sim, None, "delay=1:50").open().await.expect("opens");
    let start = Instant::now();
    reply_to(&mut link, request(GAP, 1, 0)).await;
    assert_eq!(start.elapsed(), Duration::from_millis(50));
}

#[tokio::test(start_paused = true)]
async fn a_cut_link_reopens_onto_the_same_module() {
    let sim = steprocker();
    let spec = spec(&sim, None, "disconnect-after=1");
    let mut link = spec.open().await.expect("opens");
    let reply = reply_to(&mut link, request(SAP, 4, 1234)).await;
    assert_eq!(reply.status, Status::OK);

    link.outgoing.send(&request(GAP, 4, 0)).expect("send");
    assert_eq!(
        link.incoming.recv().await,
        Some(LinkInput::Lost(
            "link cut after 1 request (injected fault)".into()
        ))
    );
    assert!(link.outgoing.send(&request(GAP, 4, 0)).is_err());
    assert_eq!(Arc::strong_count(&sim), 2, "the lost link let go of it");

    let mut again = spec.open().await.expect("reopens");
    let reply = reply_to(&mut again, request(GAP, 4, 0)).await;
    assert_eq!(reply.value, 1234, "the same module, state kept");
}

#[tokio::test(start_paused = true)]
async fn dropping_the_link_ends_its_task() {
    let sim = steprocker();
    let spec = spec(&sim, None, "");
    let link = spec.open().await.expect("opens");
    tokio::task::yield_now().await;
    assert_eq!(Arc::strong_count(&sim), 3, "test, spec and the link's task");
    drop(link);
    for _ in 0..100 {
        if Arc::strong_count(&sim) == 2 {
            break;
        }
        tokio::task::yield_now().await;
    }
    assert_eq!(
        Arc::strong_count(&sim),
        2,
        "the task let go of the simulator"
    );
}
