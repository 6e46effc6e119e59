//! Faults injected between a simulator and its link, for tests of
//! everything above: replies dropped or corrupted, garbage on the line,
//! late replies, a cable pulled after a while, a program word stored wrong.
//!
//! A [`FaultPlan`] says what to inject (parsed from the `--fault` spec
//! `drop=P,corrupt=P,garbage=P,delay=P:MS,disconnect-after=N,corrupt-store=N,seed=N`); a
//! [`FaultInjector`] applies it to the traffic of one connection, drawing
//! from its own seeded generator so that a failing run can be replayed. Every
//! fault injected is counted in the plan's [`FaultRecord`], so a test can
//! check that each one showed up above as an error or a retry.
//!
//! Faults inside the controller (`corrupt-store`: a stored program word
//! with one bit flipped while the reply says all is well) are not the
//! line's to make: the line hands the plan to the controller when it opens
//! ([`crate::sim::SimulatedController::arm_faults`]), and the controller
//! counts what it injected in the same record.
//!
//! Pure code: no clock, no I/O. The caller holds delayed replies back.

use std::fmt;
use std::str::FromStr;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// Which faults to inject, and how often. Probabilities are 0.0..=1.0 and
/// apply per reply (per chunk of output the simulator produces).
#[derive(Debug, Clone, Default)]
pub struct FaultPlan {
    /// A reply is lost.
    pub drop: f64,
    /// One byte of a reply is flipped.
    pub corrupt: f64,
    /// Random bytes appear on the line before a reply.
    pub garbage: f64,
    /// A reply is held back by `delay_ms` (probability, milliseconds).
    pub delay: f64,
    pub delay_ms: u64,
    /// The link drops after this many requests (frames fed to the simulator).
    pub disconnect_after: Option<u64>,
    /// The controller stores the N-th program word downloaded (counting
    /// from 1, per connection) with one bit flipped, and answers as if it
    /// had stored it intact: only reading the word back shows it.
    pub corrupt_store: Option<u64>,
    /// Seed of the fault generator, so that a failing run can be replayed.
    pub seed: u64,
    /// What was injected under this plan, shared by its clones and by
    /// every link opened with it.
    pub record: FaultRecord,
}

/// Plans are equal when they inject the same faults; the record of what
/// they injected so far does not count.
impl PartialEq for FaultPlan {
    fn eq(&self, other: &Self) -> bool {
        self.drop == other.drop
            && self.corrupt == other.corrupt
            && self.garbage == other.garbage
            && self.delay == other.delay
            && self.delay_ms == other.delay_ms
            && self.disconnect_after == other.disconnect_after
            && self.corrupt_store == other.corrupt_store
            && self.seed == other.seed
    }
}

impl FaultPlan {
    /// No faults at all.
    pub fn none() -> FaultPlan {
        FaultPlan::default()
    }

    /// True when nothing is injected.
    pub fn is_none(&self) -> bool {
        self.drop == 0.0
            && self.corrupt == 0.0
            && self.garbage == 0.0
            && self.delay == 0.0
            && self.disconnect_after.is_none()
            && self.corrupt_store.is_none()
    }

    /// Parse a `--fault` spec: comma-separated `drop=P`, `corrupt=P`,
    /// `garbage=P`, `delay=P:MS`, `disconnect-after=N`, `corrupt-store=N`,
    /// `seed=N`, each at most once. An empty spec injects nothing.
    pub fn parse(spec: &str) -> Result<FaultPlan, FaultSpecError> {
        let mut plan = FaultPlan::none();
        let mut seen: Vec<String> = Vec::new();
        for item in spec.split(',').map(str::trim).filter(|i| !i.is_empty()) {
            let bad = |reason: String| FaultSpecError {
                item: item.to_string(),
                reason,
            };
            let Some((name, value)) = item.split_once('=') else {
                return Err(bad(format!("expected NAME=VALUE ({})", FAULT_NAMES)));
            };
            let (name, value) = (name.trim(), value.trim());
            let name = name.to_ascii_lowercase();
            if seen.contains(&name) {
                return Err(bad(format!("'{name}' is given twice")));
            }
            match name.as_str() {
                "drop" => plan.drop = probability(value).map_err(bad)?,
                "corrupt" => plan.corrupt = probability(value).map_err(bad)?,
                "garbage" => plan.garbage = probability(value).map_err(bad)?,
                "delay" => {
                    let Some((p, ms)) = value.split_once(':') else {
                        return Err(bad(
                            "give the delay as P:MS, e.g. delay=0.1:50 (probability, milliseconds)"
                                .into(),
                        ));
                    };
                    plan.delay = probability(p.trim()).map_err(bad)?;
                    plan.delay_ms = count(ms.trim(), "milliseconds").map_err(bad)?;
                }
                "disconnect-after" => {
                    plan.disconnect_after = Some(count(value, "a number of requests").map_err(bad)?)
                }
                "corrupt-store" => {
                    let n = count(value, "a word count from 1").map_err(bad)?;
                    if n == 0 {
                        return Err(bad(
                            "words are counted from 1: corrupt-store=1 is the first word stored"
                                .into(),
                        ));
                    }
                    plan.corrupt_store = Some(n);
                }
                "seed" => plan.seed = count(value, "a seed (0 or more)").map_err(bad)?,
                _ => {
                    return Err(bad(format!(
                        "unknown fault '{name}' (known: {FAULT_NAMES})"
                    )));
                }
            }
            seen.push(name);
        }
        Ok(plan)
    }

    /// How many of each fault were injected so far under this plan.
    pub fn counts(&self) -> FaultCounts {
        self.record.counts()
    }
}

impl FromStr for FaultPlan {
    type Err = FaultSpecError;
    fn from_str(spec: &str) -> Result<FaultPlan, FaultSpecError> {
        FaultPlan::parse(spec)
    }
}

/// Shows the plan as a spec that parses back to it.
impl fmt::Display for FaultPlan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut items = Vec::new();
        if self.drop > 0.0 {
            items.push(format!("drop={}", self.drop));
        }
        if self.corrupt > 0.0 {
            items.push(format!("corrupt={}", self.corrupt));
        }
        if self.garbage > 0.0 {
            items.push(format!("garbage={}", self.garbage));
        }
        if self.delay > 0.0 {
            items.push(format!("delay={}:{}", self.delay, self.delay_ms));
        }
        if let Some(n) = self.disconnect_after {
            items.push(format!("disconnect-after={n}"));
        }
        if let Some(n) = self.corrupt_store {
            items.push(format!("corrupt-store={n}"));
        }
        if !items.is_empty() || self.seed != 0 {
            items.push(format!("seed={}", self.seed));
        }
        write!(f, "{}", items.join(","))
    }
}

const FAULT_NAMES: &str =
    "drop=P, corrupt=P, garbage=P, delay=P:MS, disconnect-after=N, corrupt-store=N, seed=N";

fn probability(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(p) if (0.0..=1.0).contains(&p) => Ok(p),
        _ => Err(format!("'{text}' is not a probability between 0 and 1")),
    }
}

fn count(text: &str, what: &str) -> Result<u64, String> {
    text.parse::<u64>()
        .map_err(|_| format!("'{text}' is not {what}"))
}

/// A `--fault` spec that does not parse.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("bad fault '{item}': {reason}")]
pub struct FaultSpecError {
    /// The offending item of the spec, as given.
    pub item: String,
    pub reason: String,
}

/// How many faults of each kind were injected, and what they were applied to.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FaultCounts {
    /// Requests that reached the simulator.
    pub requests: u64,
    /// Replies (chunks of output) the simulator produced.
    pub replies: u64,
    pub dropped: u64,
    pub corrupted: u64,
    /// Replies with garbage put before them.
    pub garbage: u64,
    pub delayed: u64,
    /// Links cut by `disconnect-after`.
    pub disconnects: u64,
    /// Program words stored wrong by `corrupt-store`.
    pub corrupted_stores: u64,
}

impl FaultCounts {
    /// Faults of every kind together.
    pub fn injected(&self) -> u64 {
        self.dropped
            + self.corrupted
            + self.garbage
            + self.delayed
            + self.disconnects
            + self.corrupted_stores
    }
}

impl fmt::Display for FaultCounts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} requests, {} replies: {} dropped, {} corrupted, {} with garbage, {} delayed, {} disconnects, {} program words stored corrupted",
            self.requests,
            self.replies,
            self.dropped,
            self.corrupted,
            self.garbage,
            self.delayed,
            self.disconnects,
            self.corrupted_stores
        )
    }
}

/// Counts shared by every clone of a plan, so that what the injectors of
/// successive links did can be read where the plan was made.
#[derive(Debug, Clone, Default)]
pub struct FaultRecord(Arc<Mutex<FaultCounts>>);

impl FaultRecord {
    pub fn counts(&self) -> FaultCounts {
        // A poisoned lock still holds valid counters.
        *self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// A controller stored a program word corrupted (`corrupt-store`).
    pub fn note_corrupted_store(&self) {
        self.update(|c| c.corrupted_stores += 1);
    }

    fn update(&self, change: impl FnOnce(&mut FaultCounts)) {
        change(&mut self.0.lock().unwrap_or_else(|e| e.into_inner()));
    }
}

/// What becomes of host bytes on their way to the simulator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Passage {
    /// Feed them to the simulator.
    Deliver,
    /// The link is cut (`disconnect-after`): nothing more goes either way.
    Cut,
}

/// A reply on its way to the host, after the injector had its say.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Delivery {
    /// What goes on the line (garbage first, if any, then the reply,
    /// possibly corrupted).
    pub bytes: Vec<u8>,
    /// How long to hold it back (zero: send it now).
    pub delay: Duration,
}

/// Most garbage bytes put before one reply.
pub const MAX_GARBAGE: u64 = 8;

/// Applies a [`FaultPlan`] to the traffic of one connection.
///
/// A request is a burst of host bytes: the first byte after the simulator
/// said something (or after the connection opened) starts the next one.
/// On a strict master/slave bus every request is answered before the next,
/// so this counts requests without knowing the family's framing; a request
/// the simulator ignores (another module's address) merges with the next.
#[derive(Debug)]
pub struct FaultInjector {
    plan: FaultPlan,
    rng: SplitMix64,
    requests: u64,
    /// The simulator answered since the last request began.
    answered: bool,
    cut: bool,
}

impl FaultInjector {
    pub fn new(plan: &FaultPlan) -> FaultInjector {
        FaultInjector {
            plan: plan.clone(),
            rng: SplitMix64(plan.seed),
            requests: 0,
            answered: true,
            cut: false,
        }
    }

    /// A new connection on the same line (a client reconnecting to a
    /// served simulator): the request count starts afresh, the generator
    /// runs on.
    pub fn reconnect(&mut self) {
        self.requests = 0;
        self.answered = true;
        self.cut = false;
    }

    /// Requests seen on this connection so far.
    pub fn requests(&self) -> u64 {
        self.requests
    }

    /// Host bytes about to be fed to the simulator.
    pub fn to_controller(&mut self, bytes: &[u8]) -> Passage {
        if self.cut {
            return Passage::Cut;
        }
        if bytes.is_empty() {
            return Passage::Deliver;
        }
        if self.answered {
            if self
                .plan
                .disconnect_after
                .is_some_and(|limit| self.requests >= limit)
            {
                self.cut = true;
                self.plan.record.update(|c| c.disconnects += 1);
                return Passage::Cut;
            }
            self.answered = false;
            self.requests += 1;
            self.plan.record.update(|c| c.requests += 1);
        }
        Passage::Deliver
    }

    /// A reply from the simulator on its way to the host; `None` when it is
    /// dropped. One draw per fault kind, always in the same order, so a
    /// seed replays the same faults.
    pub fn to_host(&mut self, mut reply: Vec<u8>) -> Option<Delivery> {
        if reply.is_empty() || self.cut {
            return None;
        }
        self.answered = true;
        let drop = self.rng.chance(self.plan.drop);
        let corrupt = self.rng.chance(self.plan.corrupt);
        let garbage = self.rng.chance(self.plan.garbage);
        let delay = self.rng.chance(self.plan.delay);
        self.plan.record.update(|c| c.replies += 1);
        if drop {
            self.plan.record.update(|c| c.dropped += 1);
            return None;
        }
        if corrupt {
            let index = self.rng.below(reply.len() as u64) as usize;
            // XOR with a non-zero mask always changes the byte, so a
            // checksum over the frame always catches it.
            let mask = (self.rng.below(255) + 1) as u8;
            if let Some(byte) = reply.get_mut(index) {
                *byte ^= mask;
            }
            self.plan.record.update(|c| c.corrupted += 1);
        }
        let mut bytes = Vec::with_capacity(reply.len() + MAX_GARBAGE as usize);
        if garbage {
            let len = self.rng.below(MAX_GARBAGE) + 1;
            bytes.extend((0..len).map(|_| self.rng.next() as u8));
            self.plan.record.update(|c| c.garbage += 1);
        }
        bytes.extend_from_slice(&reply);
        let delay = if delay {
            self.plan.record.update(|c| c.delayed += 1);
            Duration::from_millis(self.plan.delay_ms)
        } else {
            Duration::ZERO
        };
        Some(Delivery { bytes, delay })
    }
}

/// SplitMix64 (Steele, Lea and Flood, 2014): tiny, fast, and every seed,
/// zero included, gives a good sequence.
#[derive(Debug, Clone)]
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform draw in 0.0..1.0 (53 bits).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// True with probability `p` (always for 1, never for 0).
    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// A draw in 0..n (n > 0; the tiny modulo bias does not matter here).
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n.max(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_spec_parses() {
        let plan: FaultPlan =
            "drop=0.1, corrupt=0.2,garbage=1,delay=0.5:40,disconnect-after=7,corrupt-store=3,seed=42"
                .parse()
                .expect("parses");
        assert_eq!(plan.drop, 0.1);
        assert_eq!(plan.corrupt, 0.2);
        assert_eq!(plan.garbage, 1.0);
        assert_eq!((plan.delay, plan.delay_ms), (0.5, 40));
        assert_eq!(plan.disconnect_after, Some(7));
        assert_eq!(plan.corrupt_store, Some(3));
        assert_eq!(plan.seed, 42);
        assert!(!plan.is_none());
        assert_eq!(FaultPlan::parse(&plan.to_string()), Ok(plan));
    }

    #[test]
    fn an_empty_spec_injects_nothing() {
        assert!(FaultPlan::parse("").expect("parses").is_none());
        assert!(FaultPlan::parse("seed=3").expect("parses").is_none());
        assert!(
            !FaultPlan::parse("corrupt-store=1")
                .expect("parses")
                .is_none()
        );
        assert_eq!(FaultPlan::none().to_string(), "");
    }

    #[test]
    fn bad_specs_name_the_bad_item() {
        let cases = [
            (
                "drop=1.5",
                "bad fault 'drop=1.5': '1.5' is not a probability between 0 and 1",
            ),
            (
                "drop=0.1,corrupt=x",
                "bad fault 'corrupt=x': 'x' is not a probability between 0 and 1",
            ),
            (
                "corrupt=NaN",
                "bad fault 'corrupt=NaN': 'NaN' is not a probability between 0 and 1",
            ),
            (
                "garbage=-0.1",
                "bad fault 'garbage=-0.1': '-0.1' is not a probability between 0 and 1",
            ),
            (
                "delay=0.5",
                "bad fault 'delay=0.5': give the delay as P:MS, e.g. delay=0.1:50 (probability, milliseconds)",
            ),
            (
                "delay=0.5:soon",
                "bad fault 'delay=0.5:soon': 'soon' is not milliseconds",
            ),
            (
                "disconnect-after=-1",
                "bad fault 'disconnect-after=-1': '-1' is not a number of requests",
            ),
            (
                "seed=abc",
                "bad fault 'seed=abc': 'abc' is not a seed (0 or more)",
            ),
            (
                "dorp=0.1",
                "bad fault 'dorp=0.1': unknown fault 'dorp' (known: drop=P, corrupt=P, garbage=P, delay=P:MS, disconnect-after=N, corrupt-store=N, seed=N)",
            ),
            (
                "drop",
                "bad fault 'drop': expected NAME=VALUE (drop=P, corrupt=P, garbage=P, delay=P:MS, disconnect-after=N, corrupt-store=N, seed=N)",
            ),
            (
                "corrupt-store=0",
                "bad fault 'corrupt-store=0': words are counted from 1: corrupt-store=1 is the first word stored",
            ),
            (
                "corrupt-store=x",
                "bad fault 'corrupt-store=x': 'x' is not a word count from 1",
            ),
            (
                "drop=0.1,drop=0.2",
                "bad fault 'drop=0.2': 'drop' is given twice",
            ),
        ];
        for (spec, message) in cases {
            let error = FaultPlan::parse(spec).expect_err(spec);
            assert_eq!(error.to_string(), message, "{spec}");
        }
    }

    fn run(plan: &FaultPlan, replies: usize) -> Vec<Option<Delivery>> {
        let mut injector = FaultInjector::new(plan);
        (0..replies)
            .map(|i| {
                assert_eq!(injector.to_controller(&[i as u8]), Passage::Deliver);
                injector.to_host(vec![1, 2, 3, 4, 5, 6, 7, 8, 9])
            })
            .collect()
    }

    #[test]
    fn a_seed_replays_the_same_faults() {
        let spec = "drop=0.3,corrupt=0.3,garbage=0.3,delay=0.3:20,seed=7";
        let first = run(&FaultPlan::parse(spec).expect("parses"), 200);
        let again = run(&FaultPlan::parse(spec).expect("parses"), 200);
        assert_eq!(first, again);
        let other = run(
            &FaultPlan::parse(&spec.replace("seed=7", "seed=8")).expect("parses"),
            200,
        );
        assert_ne!(first, other);
    }

    #[test]
    fn no_plan_passes_everything_untouched() {
        let plan = FaultPlan::none();
        for delivery in run(&plan, 50) {
            assert_eq!(
                delivery,
                Some(Delivery {
                    bytes: vec![1, 2, 3, 4, 5, 6, 7, 8, 9],
                    delay: Duration::ZERO
                })
            );
        }
        let counts = plan.counts();
        assert_eq!(
            (counts.requests, counts.replies, counts.injected()),
            (50, 50, 0)
        );
    }

    #[test]
    fn drop_loses_every_reply_and_counts_them() {
        let plan = FaultPlan::parse("drop=1").expect("parses");
        assert!(run(&plan, 10).iter().all(Option::is_none));
        assert_eq!(plan.counts().dropped, 10);
    }

    #[test]
    fn corrupt_flips_exactly_one_byte() {
        let plan = FaultPlan::parse("corrupt=1,seed=3").expect("parses");
        for delivery in run(&plan, 100) {
            let bytes = delivery.expect("delivered").bytes;
            assert_eq!(bytes.len(), 9);
            let changed = bytes
                .iter()
                .zip([1u8, 2, 3, 4, 5, 6, 7, 8, 9])
                .filter(|(a, b)| **a != *b)
                .count();
            assert_eq!(changed, 1, "{bytes:?}");
        }
        assert_eq!(plan.counts().corrupted, 100);
    }

    #[test]
    fn garbage_comes_before_the_intact_reply() {
        let plan = FaultPlan::parse("garbage=1").expect("parses");
        for delivery in run(&plan, 100) {
            let bytes = delivery.expect("delivered").bytes;
            let extra = bytes.len() - 9;
            assert!((1..=MAX_GARBAGE as usize).contains(&extra), "{bytes:?}");
            assert_eq!(bytes[extra..], [1, 2, 3, 4, 5, 6, 7, 8, 9]);
        }
        assert_eq!(plan.counts().garbage, 100);
    }

    #[test]
    fn delay_holds_replies_back_by_the_given_time() {
        let plan = FaultPlan::parse("delay=1:25").expect("parses");
        for delivery in run(&plan, 10) {
            assert_eq!(
                delivery.expect("delivered").delay,
                Duration::from_millis(25)
            );
        }
        assert_eq!(plan.counts().delayed, 10);
    }

    #[test]
    fn half_the_replies_are_dropped_at_one_half() {
        let plan = FaultPlan::parse("drop=0.5,seed=11").expect("parses");
        let dropped = run(&plan, 1000).iter().filter(|d| d.is_none()).count();
        assert!((400..600).contains(&dropped), "{dropped}");
    }

    #[test]
    fn the_link_is_cut_at_the_request_after_the_limit() {
        let plan = FaultPlan::parse("disconnect-after=2").expect("parses");
        let mut injector = FaultInjector::new(&plan);
        for _ in 0..2 {
            // A request split into pieces is still one request.
            assert_eq!(injector.to_controller(&[1, 2]), Passage::Deliver);
            assert_eq!(injector.to_controller(&[3]), Passage::Deliver);
            assert!(injector.to_host(vec![9]).is_some());
        }
        assert_eq!(injector.requests(), 2);
        assert_eq!(injector.to_controller(&[1]), Passage::Cut);
        assert_eq!(injector.to_controller(&[1]), Passage::Cut);
        assert_eq!(injector.to_host(vec![9]), None);
        let counts = plan.counts();
        assert_eq!((counts.requests, counts.disconnects), (2, 1));

        injector.reconnect();
        assert_eq!(injector.to_controller(&[1]), Passage::Deliver);
        assert_eq!(plan.counts().requests, 3);
    }

    #[test]
    fn clones_of_a_plan_share_one_record() {
        let plan = FaultPlan::parse("drop=1").expect("parses");
        let copy = plan.clone();
        run(&copy, 3);
        assert_eq!(plan.counts().dropped, 3);
        assert_eq!(plan, copy);
    }
}
