//! The device task against the in-process TMCM-1110 simulator with random
//! faults injected on its link (dropped, corrupted, delayed replies,
//! garbage, a cable pulled every few hundred requests), over thousands of
//! transactions on tokio's paused clock:
//!
//! - no reply is ever delivered to the wrong request: user variables of
//!   bank 2 are set to distinct values first, then read back at random,
//!   several at once at mixed priorities, with a poll plan running;
//! - nothing panics;
//! - every injected fault shows up as an error or a retry, and every error
//!   or retry comes from a fault (compared with the injector's counters;
//!   a reply that never comes may cost two);
//! - no write reaches the simulator twice (a wrapping simulator counts the
//!   frames it is fed).

mod device_support;

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use proptest::prelude::*;

use axterm::device::{
    Answer, DeviceError, DeviceHandle, DeviceOptions, LinkState, PollItem, PollPlan, PollSink,
    Priority, Retry, TrafficRecord, Transaction, connect, default_timeout,
};
use axterm::link::{LinkSpec, SharedSim, byte_time};
use axterm::protocol::tmcl::{FRAME_LEN, FrameAssembler, Reply, Request, Status, TmclWire};
use axterm::sim::SimulatedController;
use axterm::sim::faults::FaultPlan;
use axterm::sim::tmcm1110::{SimConfig, Tmcm1110};
use device_support::{GGP, SAP, SGP, request};

const BAUD: u32 = 115_200;

/// Counts every frame the simulator is fed, by its bytes.
struct Counting {
    inner: Tmcm1110,
    fed: Arc<Mutex<HashMap<[u8; FRAME_LEN], u32>>>,
    assembler: FrameAssembler,
    quiet: Duration,
}

impl SimulatedController for Counting {
    fn feed(&mut self, bytes: &[u8]) {
        self.quiet = Duration::ZERO;
        let mut fed = self.fed.lock().expect("counts");
        for frame in self.assembler.push(bytes) {
            *fed.entry(frame).or_default() += 1;
        }
        drop(fed);
        self.inner.feed(bytes);
    }

    fn advance(&mut self, dt: Duration) {
        // The host never sends garbage; this only keeps the count in step
        // should a frame be cut short with the link.
        self.quiet += dt;
        if self.quiet >= Duration::from_millis(5) {
            self.assembler.resync();
        }
        self.inner.advance(dt);
    }

    fn take_output(&mut self) -> Vec<u8> {
        self.inner.take_output()
    }

    fn help(&self) -> String {
        self.inner.help()
    }
}

/// What a poll sink got: item, and the answer's frames and attempts or the error.
type PollResult = Result<(Vec<Vec<u8>>, u32), DeviceError>;

#[derive(Clone, Default)]
struct Sink(Arc<Mutex<Vec<PollResult>>>);

impl PollSink for Sink {
    fn record(&mut self, _index: usize, result: Result<&Answer, &DeviceError>) {
        let result = result
            .map(|a| (a.frames.clone(), a.attempts))
            .map_err(Clone::clone);
        self.0.lock().expect("sink").push(result);
    }
}

fn tmcl(request: &Request, retry: Retry) -> Transaction {
    device_support::transaction(request, retry)
}

/// The value of an answer, which must be a good reply with status OK.
fn value(frames: &[Vec<u8>]) -> i32 {
    let frame: [u8; FRAME_LEN] = frames
        .first()
        .and_then(|f| f.as_slice().try_into().ok())
        .expect("a 9-byte answer");
    let reply = Reply::from_bytes(&frame).expect("an answer has a good checksum");
    assert_eq!(reply.status, Status::OK, "answer {reply:?}");
    reply.value
}

/// Submit until the request has been sent: a request that failed because
/// the link was down was never sent, so sending it after the reconnection
/// is its first sending.
async fn until_sent(
    device: &DeviceHandle,
    priority: Priority,
    transaction: Transaction,
) -> Result<Answer, DeviceError> {
    loop {
        match device.transact(priority, transaction.clone()).await {
            Err(DeviceError::Disconnected(_)) => {
                let mut state = device.state();
                state
                    .wait_for(|s| matches!(s, LinkState::Connected { .. }))
                    .await
                    .expect("the task runs");
            }
            other => return other,
        }
    }
}

/// A tiny deterministic generator for the test's own choices.
struct Choices(u64);

impl Choices {
    fn below(&mut self, n: u64) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 33) % n.max(1)
    }
}

/// Tally of how transactions ended, for the comparison with the faults.
#[derive(Debug, Default)]
struct Tally {
    timeouts: u64,
    lost: u64,
    answered_after_retry: u64,
}

impl Tally {
    fn note(&mut self, result: &Result<u32, DeviceError>) {
        match result {
            Ok(attempts) if *attempts > 1 => self.answered_after_retry += 1,
            Ok(_) => {}
            Err(
                DeviceError::Timeout { .. }
                | DeviceError::Garbled { .. }
                | DeviceError::Ambiguous { .. },
            ) => self.timeouts += 1,
            Err(DeviceError::LinkLost(_)) => self.lost += 1,
            // A poll waiting for its retry when the link went: never sent
            // again (its failed attempt is counted as a retry).
            Err(DeviceError::Disconnected(_)) => {}
            Err(other) => panic!("unexpected error: {other}"),
        }
    }
}

type Recent = Arc<Mutex<std::collections::VecDeque<TrafficRecord>>>;

/// The last traffic records, for a failure message.
fn keep_recent_traffic(device: &DeviceHandle) -> Recent {
    let recent: Recent = Arc::default();
    let mut traffic = device.traffic();
    let keep = Arc::clone(&recent);
    tokio::spawn(async move {
        while let Ok(record) = traffic.recv().await {
            let mut recent = keep.lock().expect("recent");
            if recent.len() == 40 {
                recent.pop_front();
            }
            recent.push_back(record);
        }
    });
    recent
}

fn show(recent: &Recent) -> String {
    let recent = recent.lock().expect("recent");
    let start = recent.front().map(|r| r.at);
    recent
        .iter()
        .map(|r| {
            let at = start.map(|s| r.at - s).unwrap_or_default();
            format!(
                "{:>10.3?} {:?} {:?} {:?} {:02X?}",
                at, r.direction, r.kind, r.priority, r.bytes
            )
        })
        .collect::<Vec<_>>()
        .join("\n")
}

const VARIABLES: u8 = 32;
const BATCHES: usize = 120;

async fn run_case(plan: FaultPlan, seed: u64) {
    let fed = Arc::new(Mutex::new(HashMap::new()));
    let sim: SharedSim = Arc::new(Mutex::new(Box::new(Counting {
        inner: Tmcm1110::new(SimConfig::default()),
        fed: Arc::clone(&fed),
        assembler: FrameAssembler::new(),
        quiet: Duration::ZERO,
    })));
    let spec = LinkSpec::Sim {
        kind: "tmcm1110".into(),
        sim,
        baud: Some(BAUD),
        faults: plan.clone(),
    };
    let options = DeviceOptions {
        reconnect_initial: Duration::from_millis(10),
        reconnect_max: Duration::from_millis(40),
        ..DeviceOptions::default()
    };
    let device = connect(spec, Arc::new(TmclWire::default()), options)
        .await
        .expect("a simulator link opens");
    let recent = keep_recent_traffic(&device);
    let mut tally = Tally::default();
    let mut writes: Vec<(Vec<u8>, bool)> = Vec::new();

    // Distinct non-zero values; a variable whose write failed holds either
    // its value or 0.
    let values: Vec<i32> = (0..i32::from(VARIABLES))
        .map(|n| (n + 1) * 1_000_003 + (seed % 1000) as i32)
        .collect();
    let mut allowed: Vec<Vec<i32>> = Vec::new();
    for (n, value) in (0..VARIABLES).zip(&values) {
        let sgp = request(SGP, n, 2, *value);
        let result = until_sent(&device, Priority::User, tmcl(&sgp, Retry::Never)).await;
        tally.note(&result.as_ref().map(|a| a.attempts).map_err(Clone::clone));
        writes.push((sgp.to_bytes().to_vec(), result.is_ok()));
        allowed.push(if result.is_ok() {
            vec![*value]
        } else {
            vec![*value, 0]
        });
    }

    let sink = Sink::default();
    device.set_poll_plan(Some(PollPlan {
        items: vec![PollItem {
            transaction: tmcl(&request(GGP, 0, 2, 0), Retry::Read(1)),
            every: Duration::from_millis(20),
            urgent: false,
        }],
        sink: Box::new(sink.clone()),
    }));

    let mut choices = Choices(seed);
    let mut speed = 1;
    for _ in 0..BATCHES {
        // A few requests at once, at mixed priorities.
        let mut batch = Vec::new();
        for _ in 0..=choices.below(3) {
            let priority =
                [Priority::User, Priority::Transfer, Priority::Poll][choices.below(3) as usize];
            if choices.below(5) == 0 {
                // A write: AP4 (maximum speed) to a value never sent before.
                // Some go as emergency stops, which jump the quiet time after
                // a timeout (a stop must not wait): a late reply echoing the
                // same command could then be taken for the stop's, so stops
                // here are writes whose answers are not compared.
                speed += 1;
                let sap = request(SAP, 4, 0, speed);
                let priority = if choices.below(3) == 0 {
                    Priority::EmergencyStop
                } else {
                    priority
                };
                batch.push((None, sap, device.submit(priority, tmcl(&sap, Retry::Never))));
            } else {
                let n = choices.below(u64::from(VARIABLES)) as u8;
                let ggp = request(GGP, n, 2, 0);
                batch.push((
                    Some(n),
                    ggp,
                    device.submit(priority, tmcl(&ggp, Retry::Read(2))),
                ));
            }
        }
        for (variable, sent, pending) in batch {
            let mut result = pending.await;
            if let Err(DeviceError::Disconnected(_)) = result {
                let transaction = tmcl(
                    &sent,
                    if variable.is_some() {
                        Retry::Read(2)
                    } else {
                        Retry::Never
                    },
                );
                result = until_sent(&device, Priority::User, transaction).await;
            }
            tally.note(&result.as_ref().map(|a| a.attempts).map_err(Clone::clone));
            match variable {
                Some(n) => {
                    if let Ok(answer) = &result {
                        let got = value(&answer.frames);
                        let allowed = &mut allowed[usize::from(n)];
                        assert!(
                            allowed.contains(&got),
                            "GGP {n}, 2 answered {got}, expected one of {allowed:?}; traffic:\n{}",
                            show(&recent)
                        );
                        *allowed = vec![got];
                    }
                }
                None => writes.push((sent.to_bytes().to_vec(), result.is_ok())),
            }
        }
    }
    device.set_poll_plan(None);
    let last = tmcl(&request(GGP, 0, 2, 0), Retry::Read(9));
    let result = until_sent(&device, Priority::User, last).await;
    tally.note(&result.as_ref().map(|a| a.attempts).map_err(Clone::clone));
    // Let the last cut, if any (that request may have been the one), be
    // reopened.
    let mut counters = device.counters();
    counters
        .wait_for(|c| c.reconnects >= plan.counts().disconnects)
        .await
        .expect("the task runs");

    for polled in sink.0.lock().expect("sink").iter() {
        tally.note(
            &polled
                .as_ref()
                .map(|(_, attempts)| *attempts)
                .map_err(Clone::clone),
        );
        if let Ok((frames, _)) = polled {
            let got = value(frames);
            assert!(allowed[0].contains(&got), "poll of GGP 0, 2 answered {got}");
        }
    }

    // No write reached the simulator twice; every answered one reached it.
    // (A copy: the simulator may still be fed the last bytes in flight.)
    let fed = fed.lock().expect("counts").clone();
    for (bytes, answered) in &writes {
        let frame: [u8; FRAME_LEN] = bytes.as_slice().try_into().expect("9 bytes");
        let times = fed.get(&frame).copied().unwrap_or(0);
        assert!(
            times <= 1,
            "write {bytes:02X?} reached the simulator {times} times"
        );
        if *answered {
            assert_eq!(times, 1, "answered write {bytes:02X?}");
        }
    }

    // Faults against what the device task made of them. A failed attempt is
    // a retry or a final timeout; each request answered after a retry may
    // hide one fault on the reply of an attempt it no longer needed.
    let faults = plan.counts();
    let counters = *device.counters().borrow();
    // Sentinels' attempts included.
    let failed_attempts = counters.timeouts + counters.garbled_answers;
    let reply_faults = faults.dropped + faults.corrupted + faults.delayed;
    let report = format!("{faults}; {counters:?}; {tally:?}");
    assert!(
        reply_faults <= failed_attempts + tally.answered_after_retry,
        "a fault went unnoticed: {report}"
    );
    // A reply that never comes (dropped, or garbled past reading) leaves its
    // attempt unanswered: the next frame that could be its answer is taken
    // for that late answer, never for a later request's, so each such
    // fault may cost one more failed attempt (a sentinel's, whose answer
    // went the same way, or the next request's).
    let never_answered = faults.dropped + faults.corrupted;
    assert!(
        failed_attempts <= reply_faults + never_answered + faults.garbage,
        "an error or retry without a fault: {report}"
    );
    // A cut may come while a sentinel is on the wire, which fails no
    // request: the next one finds the link down and is never sent.
    assert!(tally.lost <= faults.disconnects, "{report}");
    assert_eq!(counters.reconnects, faults.disconnects, "{report}");
    if faults.garbage > 0 {
        assert!(counters.garbage_bytes > 0, "{report}");
    }
    device.shutdown().await;
}

fn fault_plan() -> impl Strategy<Value = FaultPlan> {
    // A delay longer than the timeout (so that it is a fault the task must
    // see) and shorter than two, so that the counts above hold (a reply
    // later than that holds up the sentinels and requests behind it, each
    // a failed attempt; tests/session_soak.rs goes to five timeouts).
    let timeout = default_timeout(Some(byte_time(BAUD)), FRAME_LEN);
    let delay_ms = u64::try_from((timeout * 3 / 2).as_millis()).unwrap_or(u64::MAX);
    (
        0.0..0.12f64,
        0.0..0.12f64,
        0.0..0.12f64,
        0.0..0.12f64,
        proptest::option::of(60u64..300),
        any::<u64>(),
    )
        .prop_map(
            move |(drop, corrupt, garbage, delay, disconnect_after, seed)| FaultPlan {
                drop,
                corrupt,
                garbage,
                delay,
                delay_ms,
                disconnect_after,
                seed,
                ..FaultPlan::default()
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 16, ..ProptestConfig::default() })]

    #[test]
    fn faults_never_put_a_reply_on_the_wrong_request(plan in fault_plan(), seed: u64) {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .start_paused(true)
            .build()
            .expect("a runtime");
        runtime.block_on(async {
            // Virtual time: only stops a runaway case.
            tokio::time::timeout(Duration::from_secs(24 * 3600), run_case(plan, seed))
                .await
                .expect("the case finishes");
        });
    }
}
