//! The device task's loop; the module documentation of [`super`] tells
//! what it does and why.

use std::collections::VecDeque;
use std::future::Future;
use std::sync::Arc;
use std::time::Duration;

use tokio::sync::{broadcast, mpsc, oneshot, watch};
use tokio::time::{Instant, sleep, sleep_until};

use super::poll::PollSchedule;
use super::{
    Answer, DeviceCounters, DeviceError, DeviceEvent, DeviceOptions, Direction, Expect, LinkState,
    Order, PollPlan, Priority, Reopen, Retry, Submission, TrafficKind, TrafficRecord, Transaction,
    default_timeout,
};
use crate::link::{Link, LinkInput, LinkWriter};
use crate::protocol::wire::{Frame, Framer, Verdict, WireFormat};

/// Where the task publishes what it does.
pub(super) struct Outlets {
    pub traffic: broadcast::Sender<TrafficRecord>,
    pub events: broadcast::Sender<DeviceEvent>,
    pub state: watch::Sender<LinkState>,
    pub counters: watch::Sender<DeviceCounters>,
}

/// Who gets a job's result.
enum Origin {
    Caller(oneshot::Sender<Result<Answer, DeviceError>>),
    /// Item `index` of the current poll plan.
    Plan(usize),
}

/// A transaction on its way through the task.
struct Job {
    id: u64,
    priority: Priority,
    transaction: Transaction,
    /// Attempts sent so far.
    attempts: u32,
    origin: Origin,
}

impl Job {
    /// Whether a failed attempt may be followed by another one.
    fn may_retry(&self) -> bool {
        match self.transaction.retry {
            Retry::Never => false,
            Retry::Read(further) => self.attempts <= further,
        }
    }
}

/// After a timeout, a bad answer or an answer that took several attempts:
/// replies may still come, so the line must be quiet for `quiet` (counted
/// from `since`, the last attempt's deadline, or the last byte received,
/// whichever is later) before another request.
struct Guard {
    since: Instant,
    quiet: Duration,
    /// The retry of the same read and an emergency stop wait only for the
    /// silence time, counted from here (or the last byte received).
    settled: Instant,
    /// The job whose retry needs only the silence time.
    retry_of: Option<u64>,
}

/// The open link and what the task knows of its line.
struct Line {
    name: String,
    incoming: mpsc::UnboundedReceiver<LinkInput>,
    outgoing: Box<dyn LinkWriter>,
    byte_time: Option<Duration>,
    framer: Box<dyn Framer>,
    silence: Duration,
    last_rx: Instant,
    guard: Option<Guard>,
    /// Garbage was seen at this time: wait for silence before sending.
    garbage_at: Option<Instant>,
}

impl Line {
    fn new(link: Link, wire: &dyn WireFormat) -> Line {
        Line {
            silence: wire.silence(link.byte_time),
            framer: wire.framer(),
            name: link.name,
            incoming: link.incoming,
            outgoing: link.outgoing,
            byte_time: link.byte_time,
            last_rx: Instant::now(),
            guard: None,
            garbage_at: None,
        }
    }

    fn take_bytes(&mut self, bytes: &[u8]) -> Vec<Frame> {
        self.last_rx = Instant::now();
        self.framer.push(bytes)
    }

    /// When a partial frame held back becomes garbage.
    fn partial_deadline(&self) -> Option<Instant> {
        (self.framer.pending() > 0).then(|| self.last_rx + self.silence)
    }

    /// When the line will be quiet enough to send a request of `priority`
    /// (job `id`, `None` for a poll not yet made); `None`: now.
    fn ready_at(&self, priority: Priority, id: Option<u64>) -> Option<Instant> {
        let quiet_from = |since: Instant| since.max(self.last_rx);
        let garbage = self.garbage_at.map(|at| quiet_from(at) + self.silence);
        let guard = self.guard.as_ref().map(|guard| {
            let short =
                priority == Priority::EmergencyStop || (id.is_some() && guard.retry_of == id);
            if short {
                quiet_from(guard.settled) + self.silence
            } else {
                quiet_from(guard.since) + guard.quiet.max(self.silence)
            }
        });
        [self.partial_deadline(), garbage, guard]
            .into_iter()
            .flatten()
            .max()
    }
}

/// What became of one attempt.
enum Attempt {
    Answered,
    TimedOut,
    /// Garbage ended in silence and nothing was accepted: the answer came
    /// mangled, if at all.
    BadAnswer,
    Lost(String),
}

/// Why serving a link ended.
enum Ended {
    Lost(String),
    Closed,
}

/// What to do next.
enum Next {
    /// The head of a queue.
    Queued {
        priority: Priority,
        id: u64,
    },
    /// A poll of the plan is due now.
    Poll,
    /// The next poll falls due then.
    PollAt(Instant),
    Idle,
}

/// Queues in the order they are served.
fn queue_index(priority: Priority) -> usize {
    match priority {
        Priority::EmergencyStop => 0,
        Priority::User => 1,
        Priority::Transfer => 2,
        Priority::Poll => 3,
    }
}

/// The shortest wait between attempts to reopen a link, so that a zero
/// `reconnect_initial` cannot spin.
const MIN_RECONNECT_WAIT: Duration = Duration::from_millis(1);

pub(super) struct Task {
    wire: Arc<dyn WireFormat>,
    options: DeviceOptions,
    reopen: Reopen,
    orders: mpsc::UnboundedReceiver<Order>,
    orders_open: bool,
    plans: mpsc::UnboundedReceiver<Option<PollPlan>>,
    plans_open: bool,
    out: Outlets,
    counters: DeviceCounters,
    queues: [VecDeque<Job>; 4],
    schedule: Option<PollSchedule>,
    next_id: u64,
    /// Shut down once the attempt on the wire is done.
    closing: bool,
}

impl Task {
    pub(super) fn new(
        wire: Arc<dyn WireFormat>,
        options: DeviceOptions,
        reopen: Reopen,
        orders: mpsc::UnboundedReceiver<Order>,
        plans: mpsc::UnboundedReceiver<Option<PollPlan>>,
        out: Outlets,
    ) -> Task {
        Task {
            wire,
            options,
            reopen,
            orders,
            orders_open: true,
            plans,
            plans_open: true,
            out,
            counters: DeviceCounters::default(),
            queues: Default::default(),
            schedule: None,
            next_id: 0,
            closing: false,
        }
    }

    pub(super) async fn run(mut self, link: Link) {
        let mut next = Some(link);
        while let Some(link) = next.take() {
            match self.serve(link).await {
                Ended::Closed => break,
                Ended::Lost(reason) => {
                    self.reject_queued(|| DeviceError::Disconnected(reason.clone()));
                    next = self.reconnect(reason).await;
                }
            }
        }
        self.close();
    }

    /// Serve one open link until it is lost or the task shuts down.
    async fn serve(&mut self, link: Link) -> Ended {
        let mut line = Line::new(link, self.wire.as_ref());
        self.set_state(LinkState::Connected {
            link: line.name.clone(),
        });
        loop {
            self.take_orders();
            if self.closing {
                return Ended::Closed;
            }
            self.take_plans();
            if let Err(reason) = self.absorb(&mut line) {
                return Ended::Lost(reason);
            }
            let now = Instant::now();
            self.expire_partial(&mut line, now);
            self.drop_abandoned();

            // When the next job may go: `Some(None)` now, `None` never.
            let wake_for_work = match self.next(now) {
                Next::Queued { priority, id } => Some(line.ready_at(priority, Some(id))),
                Next::Poll => Some(line.ready_at(Priority::Poll, None)),
                Next::PollAt(at) => Some(Some(at)),
                Next::Idle => None,
            }
            .map(|at| at.filter(|at| *at > now));
            if let Some(None) = wake_for_work
                && let Some(job) = self.take_job(now)
            {
                if let Err(reason) = self.execute(&mut line, job).await {
                    return Ended::Lost(reason);
                }
                continue;
            }
            let wake = [wake_for_work.flatten(), line.partial_deadline()]
                .into_iter()
                .flatten()
                .min();
            let take_plan = self.plans_open && !self.plan_job_pending();
            tokio::select! {
                biased;
                input = line.incoming.recv() => {
                    if let Err(reason) = self.receive_idle(&mut line, input) {
                        return Ended::Lost(reason);
                    }
                }
                order = self.orders.recv(), if self.orders_open => self.order(order),
                plan = self.plans.recv(), if take_plan => self.plan(plan),
                () = sleep_until(wake.unwrap_or(now)), if wake.is_some() => {}
            }
        }
    }

    /// Send one attempt of `job` and see it through. `Err` carries the
    /// reason the link was lost.
    async fn execute(&mut self, line: &mut Line, mut job: Job) -> Result<(), String> {
        job.attempts += 1;
        let bytes = job.transaction.bytes.clone();
        let timeout = job
            .transaction
            .timeout
            .or(self.options.timeout)
            .unwrap_or_else(|| default_timeout(line.byte_time, bytes.len()));
        if let Err(error) = line.outgoing.send(&bytes) {
            let reason = format!("{}: writing failed: {error}", line.name);
            self.finish(job, Err(DeviceError::LinkLost(reason.clone())));
            return Err(reason);
        }
        let started = Instant::now();
        let priority = job.priority;
        // An emergency stop jumps the guard but does not lift it: a late
        // reply may still come for whatever goes after it.
        if priority != Priority::EmergencyStop {
            line.guard = None;
        }
        line.garbage_at = None;
        self.publish(Direction::Sent, TrafficKind::Request, bytes, Some(priority));
        let rule = match &job.transaction.expect {
            Expect::Nothing => {
                let answer = Answer {
                    frames: Vec::new(),
                    elapsed: Duration::ZERO,
                    attempts: job.attempts,
                };
                self.finish(job, Ok(answer));
                return Ok(());
            }
            Expect::Reply(rule) => Arc::clone(rule),
        };
        let deadline = started + timeout;
        let may_retry = job.may_retry();
        let mut accepted: Vec<Frame> = Vec::new();
        let outcome = loop {
            let partial = line.partial_deadline();
            tokio::select! {
                biased;
                input = line.incoming.recv() => match input {
                    Some(LinkInput::Bytes(bytes)) => {
                        let frames = line.take_bytes(&bytes);
                        self.log_skipped(line);
                        let mut complete = false;
                        for frame in frames {
                            let verdict = if complete {
                                Verdict::NotMine
                            } else {
                                rule.examine(&accepted, &frame)
                            };
                            match verdict {
                                Verdict::NotMine => self.classify(frame),
                                Verdict::Continue | Verdict::Complete => {
                                    complete = verdict == Verdict::Complete;
                                    self.publish(
                                        Direction::Received,
                                        TrafficKind::Answer,
                                        frame.clone(),
                                        Some(priority),
                                    );
                                    accepted.push(frame);
                                }
                            }
                        }
                        if complete {
                            break Attempt::Answered;
                        }
                    }
                    Some(LinkInput::Lost(reason)) => break Attempt::Lost(reason),
                    None => break Attempt::Lost("the link closed".into()),
                },
                order = self.orders.recv(), if self.orders_open => self.order(order),
                () = sleep_until(deadline) => break Attempt::TimedOut,
                () = sleep_until(partial.unwrap_or(deadline)), if partial.is_some() => {
                    self.expire_partial(line, Instant::now());
                    if accepted.is_empty() && may_retry {
                        break Attempt::BadAnswer;
                    }
                }
            }
        };
        let now = Instant::now();
        // A reply to this attempt may come until one timeout after its
        // deadline: the guard lasts that long, and longer if bytes keep
        // coming.
        let since = (started + timeout).max(line.last_rx);
        // A bad answer was followed by silence already.
        let settled = match outcome {
            Attempt::BadAnswer => line.last_rx,
            _ => now,
        };
        let guard = |retry_of| Guard {
            since,
            quiet: timeout,
            settled,
            retry_of,
        };
        match outcome {
            Attempt::Answered => {
                if job.attempts > 1 {
                    // An earlier attempt may still be answered.
                    line.guard = Some(guard(None));
                }
                let answer = Answer {
                    frames: accepted,
                    elapsed: now.saturating_duration_since(started),
                    attempts: job.attempts,
                };
                self.finish(job, Ok(answer));
            }
            Attempt::TimedOut | Attempt::BadAnswer => {
                if matches!(outcome, Attempt::TimedOut) {
                    self.counters.timeouts += 1;
                    self.publish_counters();
                }
                line.guard = Some(guard(may_retry.then_some(job.id)));
                if may_retry {
                    self.counters.retries += 1;
                    self.publish_counters();
                    self.queues[queue_index(priority)].push_front(job);
                } else {
                    let attempts = job.attempts;
                    self.finish(job, Err(DeviceError::Timeout { timeout, attempts }));
                }
            }
            Attempt::Lost(reason) => {
                let reason = format!("{}: {reason}", line.name);
                self.finish(job, Err(DeviceError::LinkLost(reason.clone())));
                return Err(reason);
            }
        }
        Ok(())
    }

    /// What goes next, given the queues and the poll plan.
    fn next(&self, now: Instant) -> Next {
        if let Some(job) = self.queues.iter().find_map(|queue| queue.front()) {
            return Next::Queued {
                priority: job.priority,
                id: job.id,
            };
        }
        match self.schedule.as_ref().and_then(|s| s.next(now)) {
            Some((_, Some(due))) if due > now => Next::PollAt(due),
            Some(_) => Next::Poll,
            None => Next::Idle,
        }
    }

    fn take_job(&mut self, now: Instant) -> Option<Job> {
        if let Some(job) = self.queues.iter_mut().find_map(VecDeque::pop_front) {
            return Some(job);
        }
        let schedule = self.schedule.as_mut()?;
        let (index, due) = schedule.next(now)?;
        if due.is_some_and(|due| due > now) {
            return None;
        }
        let transaction = schedule.sent(index, now)?.transaction.clone();
        let id = self.new_id();
        Some(Job {
            id,
            priority: Priority::Poll,
            transaction,
            attempts: 0,
            origin: Origin::Plan(index),
        })
    }

    fn new_id(&mut self) -> u64 {
        self.next_id += 1;
        self.next_id
    }

    /// A poll of the current plan waits for a retry: the plan stays until
    /// its result is recorded.
    fn plan_job_pending(&self) -> bool {
        self.queues[queue_index(Priority::Poll)]
            .iter()
            .any(|job| matches!(job.origin, Origin::Plan(_)))
    }

    fn take_orders(&mut self) {
        while self.orders_open {
            match self.orders.try_recv() {
                Ok(order) => self.order(Some(order)),
                Err(mpsc::error::TryRecvError::Empty) => break,
                Err(mpsc::error::TryRecvError::Disconnected) => self.order(None),
            }
        }
    }

    /// An order while connected; `None`: every handle is gone.
    fn order(&mut self, order: Option<Order>) {
        match order {
            Some(Order::Submit(Submission {
                priority,
                transaction,
                reply,
            })) => {
                let id = self.new_id();
                self.queues[queue_index(priority)].push_back(Job {
                    id,
                    priority,
                    transaction,
                    attempts: 0,
                    origin: Origin::Caller(reply),
                });
            }
            Some(Order::Shutdown) => self.closing = true,
            None => {
                self.orders_open = false;
                self.closing = true;
            }
        }
    }

    fn take_plans(&mut self) {
        if self.plan_job_pending() {
            return;
        }
        while self.plans_open {
            match self.plans.try_recv() {
                Ok(plan) => self.plan(Some(plan)),
                Err(mpsc::error::TryRecvError::Empty) => break,
                Err(mpsc::error::TryRecvError::Disconnected) => self.plan(None),
            }
        }
    }

    fn plan(&mut self, plan: Option<Option<PollPlan>>) {
        match plan {
            Some(plan) => self.schedule = plan.map(PollSchedule::new),
            None => self.plans_open = false,
        }
    }

    /// Process input that has arrived but not been read: no request is in
    /// flight, so every frame is unsolicited or stale.
    fn absorb(&mut self, line: &mut Line) -> Result<(), String> {
        loop {
            match line.incoming.try_recv() {
                Ok(input) => self.receive_idle(line, Some(input))?,
                Err(mpsc::error::TryRecvError::Empty) => return Ok(()),
                Err(mpsc::error::TryRecvError::Disconnected) => {
                    return self.receive_idle(line, None);
                }
            }
        }
    }

    fn receive_idle(&mut self, line: &mut Line, input: Option<LinkInput>) -> Result<(), String> {
        match input {
            Some(LinkInput::Bytes(bytes)) => {
                let frames = line.take_bytes(&bytes);
                self.log_skipped(line);
                for frame in frames {
                    self.classify(frame);
                }
                Ok(())
            }
            Some(LinkInput::Lost(reason)) => Err(format!("{}: {reason}", line.name)),
            None => Err(format!("{}: the link closed", line.name)),
        }
    }

    /// A frame that answers nothing: news or stale.
    fn classify(&mut self, frame: Frame) {
        match self.wire.unsolicited(&frame) {
            Some(description) => {
                self.counters.unsolicited += 1;
                self.publish(
                    Direction::Received,
                    TrafficKind::Unsolicited,
                    frame.clone(),
                    None,
                );
                let _ = self
                    .out
                    .events
                    .send(DeviceEvent::Unsolicited { frame, description });
            }
            None => {
                self.counters.stale_frames += 1;
                self.publish(Direction::Received, TrafficKind::Stale, frame, None);
            }
        }
        self.publish_counters();
    }

    /// Drop a partial frame once the line has been quiet long enough.
    fn expire_partial(&mut self, line: &mut Line, now: Instant) {
        if line.partial_deadline().is_some_and(|at| at <= now) {
            let bytes = line.framer.discard_pending();
            self.log_garbage(line, bytes);
        }
    }

    fn log_skipped(&mut self, line: &mut Line) {
        let bytes = line.framer.take_skipped();
        self.log_garbage(line, bytes);
    }

    fn log_garbage(&mut self, line: &mut Line, bytes: Vec<u8>) {
        if bytes.is_empty() {
            return;
        }
        // The garbage ended with the last byte received.
        line.garbage_at = Some(line.last_rx);
        self.counters.garbage_bytes += u64::try_from(bytes.len()).unwrap_or(u64::MAX);
        self.publish(Direction::Received, TrafficKind::Garbage, bytes, None);
        self.publish_counters();
    }

    /// Count a transaction that was sent and hand its result over.
    fn finish(&mut self, job: Job, result: Result<Answer, DeviceError>) {
        self.counters.transactions += 1;
        if matches!(job.origin, Origin::Plan(_)) {
            self.counters.polls += 1;
        }
        self.publish_counters();
        self.deliver(job, result);
    }

    fn deliver(&mut self, job: Job, result: Result<Answer, DeviceError>) {
        match job.origin {
            Origin::Caller(reply) => {
                // The caller may have given up waiting; nothing to do then.
                let _ = reply.send(result);
            }
            Origin::Plan(index) => {
                if let Some(schedule) = self.schedule.as_mut() {
                    schedule.record(index, result.as_ref());
                }
            }
        }
    }

    /// Forget queued jobs whose caller has stopped waiting: a console
    /// that drops the lines still queued behind an emergency stop must not
    /// see them sent after it (a move after the stop).
    fn drop_abandoned(&mut self) {
        for queue in &mut self.queues {
            queue.retain(|job| match &job.origin {
                Origin::Caller(reply) => !reply.is_closed(),
                Origin::Plan(_) => true,
            });
        }
    }

    /// Fail every queued job (never sent, or waiting for a retry).
    fn reject_queued(&mut self, error: impl Fn() -> DeviceError) {
        for index in 0..self.queues.len() {
            while let Some(job) = self.queues[index].pop_front() {
                self.deliver(job, Err(error()));
            }
        }
    }

    /// Reopen the link with backoff, failing every request meanwhile.
    /// `None`: shut down instead.
    async fn reconnect(&mut self, mut reason: String) -> Option<Link> {
        let initial = self.options.reconnect_initial.max(MIN_RECONNECT_WAIT);
        let longest = self.options.reconnect_max.max(initial);
        let mut wait = initial;
        loop {
            self.set_state(LinkState::Disconnected {
                reason: reason.clone(),
                retry_in: wait,
            });
            self.while_down(sleep(wait), &reason).await?;
            let open = (self.reopen)();
            match self.while_down(open, &reason).await? {
                Ok(link) => {
                    self.counters.reconnects += 1;
                    self.publish_counters();
                    return Some(link);
                }
                Err(error) => {
                    reason = error.to_string();
                    wait = wait.saturating_mul(2).min(longest);
                }
            }
        }
    }

    /// Wait for `future` while the link is down: requests fail at once,
    /// plans are taken. `None`: shut down instead.
    async fn while_down<F: Future>(&mut self, future: F, reason: &str) -> Option<F::Output> {
        tokio::pin!(future);
        loop {
            if self.closing {
                return None;
            }
            tokio::select! {
                biased;
                order = self.orders.recv(), if self.orders_open => match order {
                    Some(Order::Submit(submission)) => {
                        let _ = submission
                            .reply
                            .send(Err(DeviceError::Disconnected(reason.to_string())));
                    }
                    other => self.order(other),
                },
                plan = self.plans.recv(), if self.plans_open => self.plan(plan),
                output = &mut future => return Some(output),
            }
        }
    }

    /// Fail whatever is left and say so.
    fn close(&mut self) {
        self.reject_queued(|| DeviceError::Closed);
        while let Ok(order) = self.orders.try_recv() {
            if let Order::Submit(submission) = order {
                let _ = submission.reply.send(Err(DeviceError::Closed));
            }
        }
        self.set_state(LinkState::Closed);
    }

    fn set_state(&mut self, state: LinkState) {
        if *self.out.state.borrow() == state {
            return;
        }
        self.out.state.send_replace(state.clone());
        let _ = self.out.events.send(DeviceEvent::StateChanged(state));
    }

    fn publish(
        &self,
        direction: Direction,
        kind: TrafficKind,
        bytes: Vec<u8>,
        priority: Option<Priority>,
    ) {
        // Nobody listening is fine.
        let _ = self.out.traffic.send(TrafficRecord {
            at: Instant::now().into_std(),
            direction,
            kind,
            bytes,
            priority,
        });
    }

    fn publish_counters(&self) {
        self.out.counters.send_replace(self.counters);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queues_are_served_in_priority_order() {
        let all = [
            Priority::Poll,
            Priority::EmergencyStop,
            Priority::Transfer,
            Priority::User,
        ];
        for p in all {
            for q in all {
                assert_eq!(p.cmp(&q), queue_index(p).cmp(&queue_index(q)));
            }
        }
    }
}
