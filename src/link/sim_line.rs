//! A simulated controller at the far end of an emulated serial line: the
//! wire's byte time both ways (when a baud rate is given) and the faults
//! of a [`FaultPlan`] between the controller and the host.
//!
//! Pure code on a caller-supplied clock (time since the line opened), so
//! that the in-process link (tokio's clock, paused in tests) and the served
//! simulator (the wall clock) share one implementation.

use std::collections::VecDeque;
use std::time::Duration;

use crate::link::byte_time;
use crate::sim::SimulatedController;
use crate::sim::faults::{FaultInjector, FaultPlan, Passage};

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

    /// The bytes that arrive together at the next arrival time, if that is
    /// no later than `now`.
    fn take_next_group(&mut self, now: Duration) -> Option<(Duration, Vec<u8>)> {
        let at = self.next_due().filter(|due| *due <= now)?;
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
    /// goes either way until [`SimLine::reconnect`].
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
    /// How far the controller has been advanced.
    sim_time: Duration,
    to_controller: Wire,
    /// Replies held back by a delay fault, with their release time, in
    /// order: a late reply holds up those behind it, as on a real wire.
    held: VecDeque<(Duration, Vec<u8>)>,
    to_host: Wire,
    cut: Option<String>,
}

impl SimLine {
    /// A line at `baud` (none: bytes pass at once) with `faults`, opened at
    /// time zero.
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
            cut: None,
        }
    }

    /// The host wrote `bytes` at `now`.
    pub fn host_wrote(&mut self, now: Duration, bytes: &[u8]) {
        if self.cut.is_none() {
            self.to_controller.push(now, bytes);
        }
    }

    /// The earliest time something is due on the line (a byte arriving
    /// either way, a held reply released); `None` when it is idle. The
    /// controller may still speak on its own (motion finishing), so callers
    /// also run the line periodically.
    pub fn next_due(&self) -> Option<Duration> {
        if self.cut.is_some() {
            return None;
        }
        [
            self.to_controller.next_due(),
            self.held.front().map(|(at, _)| *at),
            self.to_host.next_due(),
        ]
        .into_iter()
        .flatten()
        .min()
    }

    /// Everything up to `now`: bytes reach the controller at their arrival
    /// times (it is advanced to each one first, so its clock follows the
    /// wire exactly), replies pass the injector and go on the wire back.
    pub fn run(&mut self, sim: &mut dyn SimulatedController, now: Duration) -> LineOutput {
        if !self.armed {
            sim.arm_faults(&self.faults);
            self.armed = true;
        }
        if let Some(reason) = &self.cut {
            return LineOutput {
                to_host: Vec::new(),
                cut: Some(reason.clone()),
            };
        }
        loop {
            let bytes_at = self.to_controller.next_due().filter(|t| *t <= now);
            let held_at = self.held.front().map(|(t, _)| *t).filter(|t| *t <= now);
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
            let Some((at, group)) = self.to_controller.take_next_group(now) else {
                break;
            };
            self.advance_to(sim, at);
            if self.injector.to_controller(&group) == Passage::Cut {
                return self.cut_now();
            }
            sim.feed(&group);
            self.collect(sim, at);
        }
        self.advance_to(sim, now);
        self.collect(sim, now);
        LineOutput {
            to_host: self.to_host.take_due(now),
            cut: None,
        }
    }

    /// A new connection on the same line (a served simulator's next
    /// client): bytes in flight are lost, the fault count starts afresh,
    /// the controller's own faults are armed again.
    pub fn reconnect(&mut self) {
        self.armed = false;
        self.to_controller.clear();
        self.to_host.clear();
        self.held.clear();
        self.cut = None;
        self.injector.reconnect();
    }

    fn cut_now(&mut self) -> LineOutput {
        let requests = self.injector.requests();
        let reason = format!(
            "link cut after {requests} request{} (injected fault)",
            if requests == 1 { "" } else { "s" }
        );
        self.to_controller.clear();
        self.to_host.clear();
        self.held.clear();
        self.cut = Some(reason.clone());
        LineOutput {
            to_host: Vec::new(),
            cut: Some(reason),
        }
    }

    fn advance_to(&mut self, sim: &mut dyn SimulatedController, at: Duration) {
        if at > self.sim_time {
            sim.advance(at - self.sim_time);
            self.sim_time = at;
        }
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
        // Bytes reach the controller one by one, each a byte time after the last.
        let just_before = each - Duration::from_nanos(1);
        assert_eq!(line.run(&mut sim, just_before).to_host, b"");
        assert!(sim.fed.is_empty());
        let out = line.run(&mut sim, 3 * each);
        let fed: Vec<_> = sim.fed.iter().map(|(t, b)| (*t, b.clone())).collect();
        assert_eq!(
            fed,
            vec![
                (each, b"a".to_vec()),
                (2 * each, b"b".to_vec()),
                (3 * each, b"c".to_vec())
            ]
        );
        // Each echoed byte starts back as it is fed and takes a byte time.
        assert_eq!(out.to_host, b"ab");
        assert_eq!(line.next_due(), Some(4 * each));
        assert_eq!(
            line.run(&mut sim, 4 * each - Duration::from_nanos(1))
                .to_host,
            b""
        );
        assert_eq!(line.run(&mut sim, 4 * each).to_host, b"c");
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

    /// Counts how often it was armed and with what.
    #[derive(Default)]
    struct Armed(Vec<Option<u64>>);

    impl SimulatedController for Armed {
        fn feed(&mut self, _: &[u8]) {}
        fn advance(&mut self, _: Duration) {}
        fn take_output(&mut self) -> Vec<u8> {
            Vec::new()
        }
        fn help(&self) -> String {
            "armed".into()
        }
        fn arm_faults(&mut self, plan: &FaultPlan) {
            self.0.push(plan.corrupt_store);
        }
    }

    #[test]
    fn the_controller_is_armed_once_per_connection() {
        let mut sim = Armed::default();
        let plan = FaultPlan::parse("corrupt-store=4").expect("parses");
        let mut line = SimLine::new(None, &plan);
        line.run(&mut sim, Duration::ZERO);
        line.run(&mut sim, MS);
        assert_eq!(sim.0, [Some(4)]);
        line.reconnect();
        line.run(&mut sim, 2 * MS);
        assert_eq!(sim.0, [Some(4), Some(4)]);
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
