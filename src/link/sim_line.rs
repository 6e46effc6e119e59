//! A simulated controller at the far end of an emulated serial line: the
//! wire's byte time both ways (when a baud rate is given) and the faults
//! of a [`FaultPlan`] between the controller and the host.
//!
//! Pure code on a caller-supplied clock (time since the line opened), so
//! that the in-process link (tokio's clock, paused in tests) and the served
//! simulator (the wall clock) share one implementation.
//!
//! Two things keep a real-time caller from waking once per byte (at
//! 115200 Bd a byte lasts 87 µs, no longer than a wake-up on a busy
//! machine) without any byte arriving before its time:
//!
//! - the controller's input is known up to the last byte on the wire, and
//!   whatever the host writes later arrives after it, so the controller is
//!   run that far at once, each byte fed at its own arrival time on the
//!   controller's clock; its answers are stamped with the times they were
//!   made and go on the wire back from then;
//! - with [`Handover::Fifo`] the host is handed back-to-back bytes a FIFO
//!   load at a time, each when its last byte has arrived, as from a UART's
//!   receive FIFO (a real one hands over the rest of a run only after a few
//!   byte times of silence; this one at once).

use std::collections::VecDeque;
use std::time::Duration;

use crate::link::byte_time;
use crate::sim::SimulatedController;
use crate::sim::faults::{FaultInjector, FaultPlan, Passage};

/// The FIFO load of the served simulator's line: a 16550A UART raises its
/// receive interrupt at 8 bytes, the trigger level Linux's 8250 driver
/// sets. A 9-byte TMCL reply then reaches the host as 8 bytes and, one
/// byte time later, the last one: that last wake-up of the host follows a
/// short idle, and is quicker than one after a whole transaction's idle
/// (measured at 115200 Bd on the development machine, a virtual one: 7 µs
/// off the p50 round trip against whole replies).
pub const UART_FIFO: usize = 8;

/// How bytes that have crossed the wire are handed to the host.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Handover {
    /// Each byte the moment it has arrived: the host sees frames split
    /// anywhere. A wake-up per byte costs nothing on tokio's paused clock.
    EachByte,
    /// A run of back-to-back bytes at once, when its last byte has arrived,
    /// at most this many bytes at a time (at least one).
    Fifo(usize),
}

/// One direction of the wire: bytes queued with the time each one has
/// fully arrived at the far end.
#[derive(Debug)]
struct Wire {
    byte_time: Option<Duration>,
    /// When the last byte queued finishes; the next one starts no earlier.
    free_at: Duration,
    bytes: VecDeque<(Duration, u8)>,
}

impl Wire {
    fn new(byte_time: Option<Duration>) -> Wire {
        Wire {
            byte_time,
            free_at: Duration::ZERO,
            bytes: VecDeque::new(),
        }
    }

    /// Put `bytes` on the wire at `at`; without a baud rate they arrive at once.
    fn push(&mut self, at: Duration, bytes: &[u8]) {
        for &byte in bytes {
            let arrives = match self.byte_time {
                Some(each) => self.free_at.max(at) + each,
                None => at,
            };
            self.free_at = arrives;
            self.bytes.push_back((arrives, byte));
        }
    }

    fn next_due(&self) -> Option<Duration> {
        self.bytes.front().map(|(due, _)| *due)
    }

    fn last_due(&self) -> Option<Duration> {
        self.bytes.back().map(|(due, _)| *due)
    }

    /// Every byte that has arrived by `now`.
    fn take_due(&mut self, now: Duration) -> Vec<u8> {
        let mut out = Vec::new();
        while let Some((due, byte)) = self.bytes.front().copied() {
            if due > now {
                break;
            }
            out.push(byte);
            self.bytes.pop_front();
        }
        out
    }

    /// When the first FIFO load can be handed over, and how many bytes it
    /// holds: the run of back-to-back bytes at the front (each following
    /// the one before with no idle time between), at most `fifo` of them.
    fn fifo_load(&self, fifo: usize) -> Option<(Duration, usize)> {
        let back_to_back = self.byte_time.unwrap_or(Duration::ZERO);
        let mut due = self.next_due()?;
        let mut count = 0;
        for &(arrives, _) in self.bytes.iter().take(fifo.max(1)) {
            if count > 0 && arrives > due + back_to_back {
                break;
            }
            due = arrives;
            count += 1;
        }
        Some((due, count))
    }

    /// Every FIFO load whose last byte has arrived by `now`.
    fn take_fifo(&mut self, now: Duration, fifo: usize) -> Vec<u8> {
        let mut out = Vec::new();
        while let Some((due, count)) = self.fifo_load(fifo) {
            if due > now {
                break;
            }
            out.extend(self.bytes.drain(..count).map(|(_, byte)| byte));
        }
        out
    }

    /// The bytes that arrive together at the next arrival time, if that is
    /// no later than `until`.
    fn take_next_group(&mut self, until: Duration) -> Option<(Duration, Vec<u8>)> {
        let at = self.next_due().filter(|due| *due <= until)?;
        let mut group = Vec::new();
        while let Some((due, byte)) = self.bytes.front().copied() {
            if due != at {
                break;
            }
            group.push(byte);
            self.bytes.pop_front();
        }
        Some((at, group))
    }

    fn clear(&mut self) {
        self.bytes.clear();
    }
}

/// What the line did up to a given time.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct LineOutput {
    /// Bytes that reached the host.
    pub to_host: Vec<u8>,
    /// The line was cut (a `disconnect-after` fault): why. Nothing more
    /// goes either way until [`SimLine::reconnect`]; `to_host` holds what
    /// arrived before the cut.
    pub cut: Option<String>,
}

/// The emulated line. The controller itself is passed to each call, so
/// the caller decides how it is shared.
#[derive(Debug)]
pub struct SimLine {
    injector: FaultInjector,
    /// The plan, for the faults the controller injects itself.
    faults: FaultPlan,
    /// Those have been handed to the controller for this connection.
    armed: bool,
    /// How far the controller has been advanced: ahead of the caller's
    /// clock while it works through bytes still on the wire.
    sim_time: Duration,
    to_controller: Wire,
    /// Replies held back by a delay fault, with their release time, in
    /// order: a late reply holds up those behind it, as on a real wire.
    held: VecDeque<(Duration, Vec<u8>)>,
    to_host: Wire,
    handover: Handover,
    /// Advance the controller this far at a time while catching up with
    /// the caller's clock, taking what it said after each step (`None`:
    /// all at once).
    stamp_step: Option<Duration>,
    /// A request cut the line (`disconnect-after`) when it would have
    /// arrived: then, and why. The host learns of it at that time.
    cut_at: Option<(Duration, String)>,
    cut: Option<String>,
}

impl SimLine {
    /// A line at `baud` (none: bytes pass at once) with `faults`, opened at
    /// time zero, handing the host each byte as it arrives.
    pub fn new(baud: Option<u32>, faults: &FaultPlan) -> SimLine {
        let each = baud.map(byte_time);
        SimLine {
            injector: FaultInjector::new(faults),
            faults: faults.clone(),
            armed: false,
            sim_time: Duration::ZERO,
            to_controller: Wire::new(each),
            held: VecDeque::new(),
            to_host: Wire::new(each),
            handover: Handover::EachByte,
            stamp_step: None,
            cut_at: None,
            cut: None,
        }
    }

    /// The same line, handing bytes to the host as `handover` says.
    pub fn handing_over(mut self, handover: Handover) -> SimLine {
        self.handover = handover;
        self
    }

    /// The same line, advancing the controller at most `step` at a time
    /// when it catches up with the caller's clock, so that an answer the
    /// controller makes on its own clock (the SIXpack 2's after its 6 ms
    /// switch-over delay, §6.1.1; a MultiFlex's at its next millisecond
    /// tick) is stamped within `step` of when it was made, not with the
    /// time the caller next looked: a real-time caller looks only every
    /// millisecond or so, and the answer went on the wire that much late.
    pub fn stamping_every(mut self, step: Duration) -> SimLine {
        self.stamp_step = (!step.is_zero()).then_some(step);
        self
    }

    /// The host wrote `bytes` at `now`.
    pub fn host_wrote(&mut self, now: Duration, bytes: &[u8]) {
        if self.cut.is_none() && self.cut_at.is_none() {
            self.to_controller.push(now, bytes);
        }
    }

    /// The earliest time something is due for the host (bytes to hand
    /// over, a held reply released, the line cut); `None` when nothing is
    /// on its way. The controller may still speak on its own (motion
    /// finishing), so callers also run the line periodically.
    pub fn next_due(&self) -> Option<Duration> {
        if self.cut.is_some() {
            return None;
        }
        let to_host = match self.handover {
            Handover::EachByte => self.to_host.next_due(),
            Handover::Fifo(fifo) => self.to_host.fifo_load(fifo).map(|(due, _)| due),
        };
        [
            self.to_controller.next_due(),
            self.held.front().map(|(at, _)| *at),
            to_host,
            self.cut_at.as_ref().map(|(at, _)| *at),
        ]
        .into_iter()
        .flatten()
        .min()
    }

    /// Everything up to `now`, and the controller's side up to the last
    /// byte on the wire: bytes reach the controller at their arrival times
    /// (it is advanced to each one first, so its clock follows the wire
    /// exactly), replies pass the injector and go on the wire back.
    pub fn run(&mut self, sim: &mut dyn SimulatedController, now: Duration) -> LineOutput {
        if !self.armed {
            sim.arm_faults(&self.faults);
            sim.line_byte_time(self.to_host.byte_time);
            self.armed = true;
        }
        if let Some(reason) = &self.cut {
            return LineOutput {
                to_host: Vec::new(),
                cut: Some(reason.clone()),
            };
        }
        // Nothing the host writes from now on can reach the controller
        // before the last byte already on the wire.
        let horizon = self
            .to_controller
            .last_due()
            .map_or(now, |last| last.max(now));
        while self.cut_at.is_none() {
            let bytes_at = self.to_controller.next_due().filter(|t| *t <= horizon);
            let held_at = self.held.front().map(|(t, _)| *t).filter(|t| *t <= horizon);
            let release_first = match (bytes_at, held_at) {
                (None, None) => break,
                (None, Some(_)) => true,
                (Some(_), None) => false,
                (Some(bytes), Some(held)) => held <= bytes,
            };
            if release_first {
                self.release_held();
                continue;
            }
            let Some((at, group)) = self.to_controller.take_next_group(horizon) else {
                break;
            };
            self.advance_stamping(sim, at);
            if self.injector.to_controller(&group) == Passage::Cut {
                self.cut_at = Some((at, self.cut_reason()));
                self.to_controller.clear();
                break;
            }
            sim.feed(&group);
            self.collect(sim, at);
        }
        if let Some((at, reason)) = self.cut_at.take_if(|(at, _)| *at <= now) {
            // What arrived before the cut reaches the host; the rest is lost.
            let to_host = self.to_host.take_due(at);
            return LineOutput {
                to_host,
                cut: Some(self.cut_now(reason)),
            };
        }
        // Ahead of `now`, the controller has been heard already.
        if now > self.sim_time {
            self.advance_stamping(sim, now);
            self.collect(sim, now);
        }
        let to_host = match self.handover {
            Handover::EachByte => self.to_host.take_due(now),
            Handover::Fifo(fifo) => self.to_host.take_fifo(now, fifo),
        };
        LineOutput { to_host, cut: None }
    }

    /// A new connection on the same line (a served simulator's next
    /// client): bytes in flight are lost, the fault count starts afresh,
    /// the controller's own faults are armed again.
    pub fn reconnect(&mut self) {
        self.armed = false;
        self.to_controller.clear();
        self.to_host.clear();
        self.held.clear();
        self.cut_at = None;
        self.cut = None;
        self.injector.reconnect();
    }

    fn cut_reason(&self) -> String {
        let requests = self.injector.requests();
        format!(
            "link cut after {requests} request{} (injected fault)",
            if requests == 1 { "" } else { "s" }
        )
    }

    /// The line goes dead for `reason`: bytes in flight are lost.
    fn cut_now(&mut self, reason: String) -> String {
        self.cut_at = None;
        self.to_controller.clear();
        self.to_host.clear();
        self.held.clear();
        self.cut = Some(reason.clone());
        reason
    }

    fn advance_to(&mut self, sim: &mut dyn SimulatedController, at: Duration) {
        if at > self.sim_time {
            sim.advance(at - self.sim_time);
            self.sim_time = at;
        }
    }

    /// Advance the controller to `at`, by [`SimLine::stamping_every`]'s
    /// steps where one was given, taking what it said after each.
    fn advance_stamping(&mut self, sim: &mut dyn SimulatedController, at: Duration) {
        if let Some(step) = self.stamp_step {
            while self.sim_time + step < at {
                let next = self.sim_time + step;
                self.advance_to(sim, next);
                self.collect(sim, next);
            }
        }
        self.advance_to(sim, at);
    }

    /// Whatever the controller said by `at`, through the injector.
    fn collect(&mut self, sim: &mut dyn SimulatedController, at: Duration) {
        let reply = sim.take_output();
        let Some(delivery) = self.injector.to_host(reply) else {
            return;
        };
        if delivery.delay.is_zero() && self.held.is_empty() {
            self.to_host.push(at, &delivery.bytes);
        } else {
            let after_last = self.held.back().map_or(Duration::ZERO, |(t, _)| *t);
            self.held
                .push_back(((at + delivery.delay).max(after_last), delivery.bytes));
        }
    }

    fn release_held(&mut self) {
        if let Some((at, bytes)) = self.held.pop_front() {
            self.to_host.push(at, &bytes);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Echoes what it is fed, and remembers when (on its own clock).
    #[derive(Default)]
    struct Echo {
        clock: Duration,
        fed: Vec<(Duration, Vec<u8>)>,
        output: Vec<u8>,
    }

    impl SimulatedController for Echo {
        fn feed(&mut self, bytes: &[u8]) {
            self.fed.push((self.clock, bytes.to_vec()));
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

    const MS: Duration = Duration::from_millis(1);

    /// Answers what it is fed with `b"ok"` 6 ms later on its own clock, as
    /// a SIXpack 2 after its switch-over delay (§6.1.1).
    #[derive(Default)]
    struct Delayed {
        clock: Duration,
        due: Option<Duration>,
        output: Vec<u8>,
    }

    impl SimulatedController for Delayed {
        fn feed(&mut self, _bytes: &[u8]) {
            self.due = Some(self.clock + 6 * MS);
        }
        fn advance(&mut self, dt: Duration) {
            self.clock += dt;
            if self.due.is_some_and(|due| due <= self.clock) {
                self.due = None;
                self.output.extend_from_slice(b"ok");
            }
        }
        fn take_output(&mut self) -> Vec<u8> {
            std::mem::take(&mut self.output)
        }
        fn help(&self) -> String {
            "delayed".into()
        }
    }

    /// When the host has the answer, the line run every `every` of the
    /// caller's clock after the request (sent at zero, one byte).
    fn answered_at(line: SimLine, every: Duration) -> Duration {
        let mut line = line;
        let mut sim = Delayed::default();
        line.host_wrote(Duration::ZERO, b"?");
        let mut now = Duration::ZERO;
        let mut got = Vec::new();
        while got.len() < 2 {
            got.extend(line.run(&mut sim, now).to_host);
            if got.len() < 2 {
                now = (now + every).min(line.next_due().unwrap_or(now + every));
            }
        }
        now
    }

    #[test]
    fn an_answer_made_on_the_controllers_clock_leaves_on_time_when_stamped_finely() {
        let each = byte_time(9600);
        // The request's byte arrives after one byte time, the answer is
        // made 6 ms later and takes two byte times back.
        let on_time = each + 6 * MS + 2 * each;
        // Looked at every 1.3 ms, the answer was stamped at the next look
        // and left that late.
        let coarse = answered_at(SimLine::new(Some(9600), &FaultPlan::none()), 1300 * MICRO);
        assert!(coarse > on_time + 100 * MICRO, "{coarse:?}");
        let fine = answered_at(
            SimLine::new(Some(9600), &FaultPlan::none()).stamping_every(50 * MICRO),
            1300 * MICRO,
        );
        assert!(
            fine >= on_time && fine <= on_time + 50 * MICRO,
            "{fine:?} of {on_time:?}"
        );
    }

    const MICRO: Duration = Duration::from_micros(1);

    #[test]
    fn the_controller_learns_the_lines_byte_time_at_each_connection() {
        let mut sim = Opened::default();
        let mut line = SimLine::new(Some(9600), &FaultPlan::none());
        line.run(&mut sim, Duration::ZERO);
        line.run(&mut sim, MS);
        assert_eq!(sim.byte_times, [Some(byte_time(9600))], "once a connection");
        line.reconnect();
        line.run(&mut sim, 2 * MS);
        assert_eq!(sim.byte_times, [Some(byte_time(9600)); 2]);
        let mut untimed = Opened::default();
        SimLine::new(None, &FaultPlan::none()).run(&mut untimed, Duration::ZERO);
        assert_eq!(untimed.byte_times, [None]);
    }

    #[test]
    fn without_a_baud_rate_bytes_pass_at_once() {
        let mut sim = Echo::default();
        let mut line = SimLine::new(None, &FaultPlan::none());
        line.host_wrote(5 * MS, b"abc");
        assert_eq!(line.next_due(), Some(5 * MS));
        let out = line.run(&mut sim, 5 * MS);
        assert_eq!(out.to_host, b"abc");
        assert_eq!(sim.fed, vec![(5 * MS, b"abc".to_vec())]);
        assert_eq!(line.next_due(), None);
    }

    #[test]
    fn each_byte_takes_its_wire_time_both_ways() {
        let each = byte_time(9600);
        let mut sim = Echo::default();
        let mut line = SimLine::new(Some(9600), &FaultPlan::none());
        line.host_wrote(Duration::ZERO, b"abc");
        // Nothing else can reach the controller before these three bytes,
        // so it has them at once, each at its arrival time on its clock.
        assert_eq!(line.run(&mut sim, Duration::ZERO).to_host, b"");
        let fed: Vec<_> = sim.fed.iter().map(|(t, b)| (*t, b.clone())).collect();
        assert_eq!(
            fed,
            vec![
                (each, b"a".to_vec()),
                (2 * each, b"b".to_vec()),
                (3 * each, b"c".to_vec())
            ]
        );
        // Each echoed byte starts back as it is fed and takes a byte time;
        // none reaches the host a nanosecond early.
        assert_eq!(line.next_due(), Some(2 * each));
        let just_before = 2 * each - Duration::from_nanos(1);
        assert_eq!(line.run(&mut sim, just_before).to_host, b"");
        assert_eq!(line.run(&mut sim, 3 * each).to_host, b"ab");
        assert_eq!(line.next_due(), Some(4 * each));
        assert_eq!(
            line.run(&mut sim, 4 * each - Duration::from_nanos(1))
                .to_host,
            b""
        );
        assert_eq!(line.run(&mut sim, 4 * each).to_host, b"c");
        assert_eq!(line.next_due(), None);
        assert_eq!(sim.clock, 4 * each, "the controller is back on the clock");
    }

    /// Answers `reply` once it has been fed `request_len` bytes, like a
    /// binary-framed controller.
    struct Framed {
        request_len: usize,
        reply: Vec<u8>,
        received: usize,
        output: Vec<u8>,
    }

    impl Framed {
        fn tmcl() -> Framed {
            Framed {
                request_len: 9,
                reply: b"123456789".to_vec(),
                received: 0,
                output: Vec::new(),
            }
        }
    }

    impl SimulatedController for Framed {
        fn feed(&mut self, bytes: &[u8]) {
            for _ in bytes {
                self.received += 1;
                if self.received == self.request_len {
                    self.received = 0;
                    self.output.extend_from_slice(&self.reply);
                }
            }
        }
        fn advance(&mut self, _: Duration) {}
        fn take_output(&mut self) -> Vec<u8> {
            std::mem::take(&mut self.output)
        }
        fn help(&self) -> String {
            "framed".into()
        }
    }

    #[test]
    fn a_fifo_hands_the_reply_over_whole_when_its_last_byte_arrives() {
        let each = byte_time(115_200);
        let mut sim = Framed::tmcl();
        let mut line =
            SimLine::new(Some(115_200), &FaultPlan::none()).handing_over(Handover::Fifo(16));
        line.host_wrote(Duration::ZERO, b"request..");
        assert_eq!(line.run(&mut sim, Duration::ZERO).to_host, b"");
        // One wake-up for the whole reply: 9 byte times out, 9 back.
        assert_eq!(line.next_due(), Some(18 * each));
        let just_before = 18 * each - Duration::from_nanos(1);
        assert_eq!(line.run(&mut sim, just_before).to_host, b"");
        assert_eq!(line.run(&mut sim, 18 * each).to_host, b"123456789");
        assert_eq!(line.next_due(), None);
    }

    #[test]
    fn a_fifo_hands_over_at_most_its_size_at_once() {
        let each = byte_time(115_200);
        let mut sim = Framed {
            request_len: 1,
            reply: (0..20).collect(),
            received: 0,
            output: Vec::new(),
        };
        let mut line =
            SimLine::new(Some(115_200), &FaultPlan::none()).handing_over(Handover::Fifo(16));
        line.host_wrote(Duration::ZERO, b"?");
        line.run(&mut sim, Duration::ZERO);
        assert_eq!(line.next_due(), Some(17 * each));
        let first = line.run(&mut sim, 20 * each).to_host;
        assert_eq!(first, (0..16).collect::<Vec<u8>>());
        assert_eq!(line.next_due(), Some(21 * each));
        assert_eq!(line.run(&mut sim, 21 * each).to_host, [16, 17, 18, 19]);
    }

    #[test]
    fn a_fifo_hands_over_bytes_apart_on_the_wire_apart() {
        let each = byte_time(9600);
        let mut sim = Echo::default();
        let mut line =
            SimLine::new(Some(9600), &FaultPlan::none()).handing_over(Handover::Fifo(16));
        line.host_wrote(Duration::ZERO, b"a");
        line.host_wrote(10 * each, b"b");
        line.run(&mut sim, Duration::ZERO);
        // The echo of "a" is followed by idle time, so it goes on its own.
        assert_eq!(line.next_due(), Some(2 * each));
        assert_eq!(line.run(&mut sim, 2 * each).to_host, b"a");
        assert_eq!(
            line.run(&mut sim, 12 * each - Duration::from_nanos(1))
                .to_host,
            b""
        );
        assert_eq!(line.run(&mut sim, 12 * each).to_host, b"b");
    }

    /// A host that writes its next request the moment the last reply is
    /// handed over, as a polling loop does.
    fn saturate(line: &mut SimLine, sim: &mut Framed, transactions: u32) -> Duration {
        let mut now = Duration::ZERO;
        for _ in 0..transactions {
            line.host_wrote(now, b"request..");
            let mut reply = line.run(sim, now).to_host;
            while reply.len() < 9 {
                now = line.next_due().expect("a reply is on its way");
                reply.extend(line.run(sim, now).to_host);
            }
            assert_eq!(reply, b"123456789");
        }
        now
    }

    #[test]
    fn a_saturated_line_keeps_the_baud_rate_exactly() {
        // Neither faster than the wire (no byte early) nor slower (no time
        // lost between transactions): 18 byte times each, over a thousand.
        for handover in [Handover::EachByte, Handover::Fifo(UART_FIFO)] {
            let mut line = SimLine::new(Some(115_200), &FaultPlan::none()).handing_over(handover);
            let took = saturate(&mut line, &mut Framed::tmcl(), 1000);
            assert_eq!(took, 18_000 * byte_time(115_200), "{handover:?}");
        }
    }

    #[test]
    fn a_cut_reaches_the_host_when_the_request_would_have_arrived() {
        let each = byte_time(9600);
        let mut sim = Echo::default();
        let plan = FaultPlan::parse("disconnect-after=1").expect("parses");
        let mut line = SimLine::new(Some(9600), &plan);
        line.host_wrote(Duration::ZERO, b"1");
        line.host_wrote(Duration::ZERO, b"2");
        assert_eq!(line.run(&mut sim, Duration::ZERO), LineOutput::default());
        assert_eq!(sim.fed.len(), 1, "the cut request never arrives");
        assert_eq!(line.next_due(), Some(2 * each));
        let just_before = 2 * each - Duration::from_nanos(1);
        assert_eq!(line.run(&mut sim, just_before), LineOutput::default());
        // The echo of "1" arrived just as the line went dead.
        assert_eq!(
            line.run(&mut sim, 2 * each),
            LineOutput {
                to_host: b"1".to_vec(),
                cut: Some("link cut after 1 request (injected fault)".into()),
            }
        );
        assert_eq!(line.next_due(), None);
    }

    #[test]
    fn a_delayed_reply_holds_up_the_ones_behind_it() {
        let mut sim = Echo::default();
        let plan = FaultPlan::parse("delay=1:10").expect("parses");
        let mut line = SimLine::new(None, &plan);
        line.host_wrote(Duration::ZERO, b"1");
        assert_eq!(line.run(&mut sim, Duration::ZERO).to_host, b"");
        assert_eq!(line.next_due(), Some(10 * MS));
        line.host_wrote(MS, b"2");
        assert_eq!(line.run(&mut sim, 9 * MS).to_host, b"");
        assert_eq!(line.run(&mut sim, 10 * MS).to_host, b"1");
        assert_eq!(line.run(&mut sim, 11 * MS).to_host, b"2");
        assert_eq!(plan.counts().delayed, 2);
    }

    #[test]
    fn a_cut_line_stays_cut_until_reconnected() {
        let mut sim = Echo::default();
        let plan = FaultPlan::parse("disconnect-after=1").expect("parses");
        let mut line = SimLine::new(None, &plan);
        line.host_wrote(Duration::ZERO, b"1");
        assert_eq!(line.run(&mut sim, Duration::ZERO).to_host, b"1");
        line.host_wrote(MS, b"2");
        let out = line.run(&mut sim, MS);
        assert_eq!(
            out.cut.as_deref(),
            Some("link cut after 1 request (injected fault)")
        );
        assert_eq!(sim.fed.len(), 1, "the cut request never arrives");
        line.host_wrote(2 * MS, b"3");
        assert!(line.run(&mut sim, 2 * MS).cut.is_some());
        assert_eq!(line.next_due(), None);

        line.reconnect();
        line.host_wrote(3 * MS, b"4");
        assert_eq!(
            line.run(&mut sim, 3 * MS),
            LineOutput {
                to_host: b"4".to_vec(),
                cut: None
            }
        );
    }

    /// What the line told it at each connection: the faults it was armed
    /// with, the line's byte time.
    #[derive(Default)]
    struct Opened {
        armed: Vec<Option<u64>>,
        byte_times: Vec<Option<Duration>>,
    }

    impl SimulatedController for Opened {
        fn feed(&mut self, _: &[u8]) {}
        fn advance(&mut self, _: Duration) {}
        fn take_output(&mut self) -> Vec<u8> {
            Vec::new()
        }
        fn help(&self) -> String {
            "opened".into()
        }
        fn arm_faults(&mut self, plan: &FaultPlan) {
            self.armed.push(plan.corrupt_store);
        }
        fn line_byte_time(&mut self, byte_time: Option<Duration>) {
            self.byte_times.push(byte_time);
        }
    }

    #[test]
    fn the_controller_is_armed_once_per_connection() {
        let mut sim = Opened::default();
        let plan = FaultPlan::parse("corrupt-store=4").expect("parses");
        let mut line = SimLine::new(None, &plan);
        line.run(&mut sim, Duration::ZERO);
        line.run(&mut sim, MS);
        assert_eq!(sim.armed, [Some(4)]);
        line.reconnect();
        line.run(&mut sim, 2 * MS);
        assert_eq!(sim.armed, [Some(4), Some(4)]);
    }

    #[test]
    fn the_controller_keeps_time_while_the_line_is_idle() {
        let mut sim = Echo::default();
        let mut line = SimLine::new(Some(9600), &FaultPlan::none());
        line.run(&mut sim, 7 * MS);
        line.run(&mut sim, 20 * MS);
        assert_eq!(sim.clock, 20 * MS);
    }
}
