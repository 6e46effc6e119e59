//! The device task's loop; the module documentation of [`super`] tells
//! what it does and why.

mod job;
mod line;
mod receive;

use job::{Job, Origin};
use line::{Heard, Line, Settle, Unanswered};
use std::collections::VecDeque;
use std::future::Future;
use std::sync::Arc;
use std::time::Duration;

use tokio::sync::{broadcast, mpsc, oneshot, watch};
use tokio::time::{Instant, sleep, sleep_until};

use super::poll::{PollKey, PollPlans};
use super::{
    Answer, Busy, DeviceCounters, DeviceError, DeviceEvent, DeviceOptions, Direction, Expect, Hold,
    LATE_ANSWER_TIMEOUTS, LinkState, Order, PollOwner, PollPlan, Priority, Reopen, Retry,
    Submission, TrafficKind, TrafficRecord, Transaction, default_timeout,
};
use crate::link::{Link, LinkInput, LinkWriter};
use crate::protocol::wire::{Frame, Framer, ReplyRule, Sentinel, Settling, Verdict, WireFormat};

/// Where the task publishes what it does.
pub(super) struct Outlets {
    pub traffic: broadcast::Sender<TrafficRecord>,
    pub events: broadcast::Sender<DeviceEvent>,
    pub state: watch::Sender<LinkState>,
    pub counters: watch::Sender<DeviceCounters>,
    pub busy: watch::Sender<Option<Busy>>,
}

/// Whether a job waiting for the line has waited past its line's deadline.
enum Overdue {
    /// Not yet: it may wait until then (while the talk goes on).
    No(Option<Instant>),
    /// An emergency stop: it goes without the line falling quiet.
    SendAnyway,
    GiveUp,
}

/// What became of one attempt.
enum Attempt {
    Answered,
    TimedOut,
    /// Only bytes that made no answer came, then silence (ends a read's
    /// attempt early, so that it is asked again at once).
    Garbled,
    /// A held request was aborted and no answer came within the grace.
    AbortUnanswered,
    Lost(String),
}

/// A held request on the wire, or a read that may be cut short: what it
/// takes meanwhile and what was sent.
struct Holding {
    hold: Hold,
    /// A held request ([`Transaction::hold`]): published as busy, it takes
    /// the user's abort and pause. Else a read that only an emergency stop
    /// cuts short ([`Transaction::cut_short`]).
    held: bool,
    /// How long the answer to an abort is waited for.
    grace: Duration,
    aborted: bool,
    paused: bool,
    busy: Busy,
}

/// How far the answer of the attempt on the wire has come.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Progress {
    /// More is to come.
    Open,
    /// Complete unless more comes before the line has been quiet for the
    /// quiet guard.
    UnlessMore,
    Complete,
}

/// What one attempt received.
#[derive(Default)]
struct Received {
    /// The frames of the answer.
    accepted: Vec<Frame>,
    /// The answer came as the late answer to an earlier attempt of the
    /// same job: this attempt's own answer may still come.
    through_earlier_attempt: bool,
    /// Garbage and frames nobody claimed.
    garbled: Vec<u8>,
    /// Frames this request's rule accepted but taken for an earlier
    /// request's late answer.
    ambiguous: Vec<u8>,
    /// The rule said the answer is complete unless more comes.
    unless_more: bool,
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
    plans: mpsc::UnboundedReceiver<(PollOwner, Option<PollPlan>)>,
    plans_open: bool,
    out: Outlets,
    counters: DeviceCounters,
    queues: [VecDeque<Job>; 4],
    /// Every module's poll plan, served in turn.
    polling: PollPlans,
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
        plans: mpsc::UnboundedReceiver<(PollOwner, Option<PollPlan>)>,
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
            polling: PollPlans::default(),
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
            if let (_, Some(frame)) = self.expire_partial(&mut line, now) {
                self.unrelated(&mut line, frame);
            }
            self.drop_abandoned();
            line.forget_expired(now);

            // What the next job needs first, and when it may go:
            // `Some(None)` now, `None` never.
            let next = self.next(now);
            let settle = self.settle_for(&line, &next, now);
            let wake_for_work = match next {
                Next::Queued { .. } | Next::Poll => Some(line.ready_at(&settle)),
                Next::PollAt(at) => Some(Some(at)),
                Next::Idle => None,
            }
            .map(|at| at.filter(|at| *at > now));
            let mut line_deadline = None;
            let mut send_anyway = false;
            if let Next::Queued { id, .. } = next {
                let overdue = self.overdue(&line, id, now);
                if let Some(Some(_)) = wake_for_work {
                    match overdue {
                        Overdue::No(deadline) => line_deadline = deadline,
                        Overdue::SendAnyway => send_anyway = true,
                        Overdue::GiveUp => {
                            self.give_up(&mut line, id, now);
                            continue;
                        }
                    }
                }
            }
            if matches!(wake_for_work, Some(None)) || send_anyway {
                let sent = match settle {
                    Settle::Sentinel(sentinel) => {
                        let priority = match next {
                            Next::Queued { priority, .. } => priority,
                            _ => Priority::Poll,
                        };
                        self.send_sentinel(&mut line, sentinel, priority).await
                    }
                    Settle::QuietUntil(_) => {
                        // Quiet for a timeout after the last deadline: a
                        // family without sentinels can only take it that
                        // no answer comes later than that.
                        line.unanswered.clear();
                        self.execute_next(&mut line, now).await
                    }
                    Settle::Go => self.execute_next(&mut line, now).await,
                    // The oldest unanswered is forgotten by now (the loop
                    // forgets at its top): settle again.
                    Settle::Until(_) => Ok(()),
                };
                if let Err(reason) = sent {
                    return Ended::Lost(reason);
                }
                continue;
            }
            let wake = [
                wake_for_work.flatten(),
                line.partial_deadline(),
                line_deadline,
            ]
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

    /// Whether queued job `id`, if it has to wait for the line to be
    /// ready, is past its line's deadline. Bytes that keep coming without
    /// the line ever falling silent (a device that never stops talking)
    /// hold it back no longer than its timeout for each attempt it may
    /// have, counted from when it first headed the queues or the talk
    /// began, whichever is later; retries and the waits before them
    /// included. Past it, an emergency stop goes all the same; anything
    /// else is given up. Waits the line's silence ends (settling after a
    /// lost answer, a burst of garbage) are left alone.
    fn overdue(&mut self, line: &Line, id: u64, now: Instant) -> Overdue {
        let Some(each) = self.queued(id).map(|job| {
            let transaction = &job.transaction;
            self.timeout_for(line, transaction.timeout, transaction.bytes.len())
        }) else {
            return Overdue::No(None);
        };
        let Some(job) = self
            .queues
            .iter_mut()
            .find_map(|q| q.front_mut().filter(|j| j.id == id))
        else {
            return Overdue::No(None);
        };
        let budget = each.saturating_mul(job.allowed_attempts());
        let since = *job.waiting.get_or_insert(now);
        // Held back by talk that has not stopped since it began (or since
        // the job headed the queues, if it began before).
        let talking = now.saturating_duration_since(line.last_rx) <= line.silence;
        let deadline = since.max(line.talking_since) + budget;
        if !talking {
            // Bytes that come wake the task anyway.
            Overdue::No(None)
        } else if now < deadline {
            Overdue::No(Some(deadline))
        } else if job.priority == Priority::EmergencyStop {
            Overdue::SendAnyway
        } else {
            Overdue::GiveUp
        }
    }

    /// Fail queued job `id`, held back past its line's deadline by a line
    /// that never fell quiet: with what its last attempt got if it had
    /// one, else as not sent, with what came meanwhile.
    fn give_up(&mut self, line: &mut Line, id: u64, now: Instant) {
        let Some(job) = self.queues.iter_mut().find_map(|queue| {
            let index = queue.iter().position(|job| job.id == id)?;
            queue.remove(index)
        }) else {
            return;
        };
        let since = job.waiting.unwrap_or(now);
        let error = if job.attempts > 0 {
            let timeout =
                self.timeout_for(line, job.transaction.timeout, job.transaction.bytes.len());
            job.failure(timeout)
        } else {
            DeviceError::NeverQuiet {
                waited: now.saturating_duration_since(since),
                heard: line.heard.count,
                first: line.heard.first.clone(),
            }
        };
        self.deliver(job, Err(error));
    }

    /// Queued job `id`, if it heads its queue.
    fn queued(&self, id: u64) -> Option<&Job> {
        self.queues
            .iter()
            .find_map(|queue| queue.front().filter(|job| job.id == id))
    }

    /// What has to happen before `next` goes.
    fn settle_for(&self, line: &Line, next: &Next, now: Instant) -> Settle {
        if line.unanswered.is_empty() {
            return Settle::Go;
        }
        let (priority, id, transaction) = match *next {
            Next::Queued { priority, id } => {
                let Some(job) = self.queued(id) else {
                    return Settle::Go;
                };
                (priority, Some(id), &job.transaction)
            }
            Next::Poll => {
                let Some(item) = self
                    .polling
                    .next(now)
                    .and_then(|(key, _)| self.polling.item(key))
                else {
                    return Settle::Go;
                };
                (Priority::Poll, None, &item.transaction)
            }
            Next::PollAt(_) | Next::Idle => return Settle::Go,
        };
        line.settle(
            self.wire.as_ref(),
            priority,
            id,
            &transaction.bytes,
            &transaction.expect,
        )
    }

    /// Take the next job and send it. `Err` carries the reason the link
    /// was lost.
    async fn execute_next(&mut self, line: &mut Line, now: Instant) -> Result<(), String> {
        match self.take_job(now) {
            Some(job) => self.execute(line, job).await,
            None => Ok(()),
        }
    }

    /// The reply timeout of a request of `len` bytes that gives none.
    fn timeout_for(&self, line: &Line, given: Option<Duration>, len: usize) -> Duration {
        given
            .or(self.options.timeout)
            .unwrap_or_else(|| default_timeout(line.byte_time, len))
    }

    /// Write `bytes` as a request and log it; `Err` with the reason the
    /// link was lost if writing failed.
    fn write_request(
        &mut self,
        line: &mut Line,
        bytes: &[u8],
        priority: Priority,
    ) -> Result<(), String> {
        if let Err(error) = line.outgoing.send(bytes) {
            return Err(format!("{}: writing failed: {error}", line.name));
        }
        line.garbage_at = None;
        line.failed_at = None;
        line.heard = Heard::default();
        self.publish(
            Direction::Sent,
            TrafficKind::Request,
            bytes.to_vec(),
            Some(priority),
        );
        Ok(())
    }

    /// Send one attempt of `job` and see it through. `Err` carries the
    /// reason the link was lost.
    async fn execute(&mut self, line: &mut Line, mut job: Job) -> Result<(), String> {
        job.attempts += 1;
        let bytes = job.transaction.bytes.clone();
        let timeout = self.timeout_for(line, job.transaction.timeout, bytes.len());
        let priority = job.priority;
        if matches!(job.transaction.expect, Expect::UntilQuiet) {
            // Everything that comes is its answer, raw: nothing of before.
            let dropped = line.framer.discard_pending();
            self.log_garbage(line, &dropped);
        }
        if let Err(reason) = self.write_request(line, &bytes, priority) {
            self.finish(job, Err(DeviceError::LinkLost(reason.clone())));
            return Err(reason);
        }
        let started = Instant::now();
        line.sentinel_sent = false;
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
            Expect::UntilQuiet => return self.execute_raw(line, job, started, timeout).await,
            Expect::Reply(rule) => Arc::clone(rule),
        };
        let cut_short = job
            .transaction
            .cut_short
            .clone()
            .map(|abort| Hold { abort, pause: None });
        let held = job.transaction.hold.is_some();
        let mut holding = job
            .transaction
            .hold
            .clone()
            .or(cut_short)
            .map(|hold| Holding {
                busy: Busy {
                    since: started.into_std(),
                    bytes: bytes.clone(),
                    priority,
                    paused: false,
                    aborting: false,
                    pausable: hold.pause.is_some(),
                },
                hold,
                held,
                grace: timeout,
                aborted: false,
                paused: false,
            });
        // A held request ends on its answer, unless it was given a timeout.
        let deadline = match (held, job.transaction.timeout) {
            (true, None) => None,
            _ => Some(started + timeout),
        };
        if let Some(holding) = holding.as_ref().filter(|h| h.held) {
            self.out.busy.send_replace(Some(holding.busy.clone()));
        }
        let may_retry = job.may_retry() && !held;
        let (outcome, received) = self
            .attempt(
                line,
                job.id,
                &rule,
                priority,
                deadline,
                may_retry,
                holding.as_mut(),
            )
            .await;
        if held {
            self.out.busy.send_replace(None);
        }
        // A read cut short for a stop: nothing of it is taken, and it is not
        // asked again before the stop.
        let cut = holding
            .as_ref()
            .filter(|h| !h.held && h.aborted)
            .map(|h| h.hold.abort.clone());
        let may_retry = may_retry && cut.is_none();
        let now = Instant::now();
        // The last attempt's bytes: a reply garbled once, read whole.
        if !received.garbled.is_empty() {
            job.garbled = received.garbled.clone();
        }
        if !received.ambiguous.is_empty() {
            job.ambiguous = received.ambiguous.clone();
        }
        let unanswered = Unanswered {
            job: job.id,
            request: bytes,
            rule,
            deadline: deadline.unwrap_or(now).min(now),
            timeout,
        };
        match outcome {
            Attempt::Answered if cut.is_some() => {
                let by = cut.unwrap_or_default();
                self.finish(job, Err(DeviceError::CutShort { by }));
            }
            Attempt::Answered => {
                if received.through_earlier_attempt {
                    // An earlier attempt's answer came: this one's may
                    // still come, as late as any answer after its own
                    // deadline, not after the earlier answer's arrival
                    // (tests/device_faults.rs: a retry's late answer taken
                    // for the next read's).
                    line.unanswered.push_back(Unanswered {
                        deadline: deadline.unwrap_or(now).max(now),
                        ..unanswered
                    });
                }
                let answer = Answer {
                    frames: received.accepted,
                    elapsed: now.saturating_duration_since(started),
                    attempts: job.attempts,
                };
                self.finish(job, Ok(answer));
            }
            Attempt::TimedOut | Attempt::Garbled | Attempt::AbortUnanswered => {
                self.count_failure(&outcome);
                line.unanswered.push_back(unanswered);
                // A garbled answer was followed by silence already.
                line.failed_at = Some(match outcome {
                    Attempt::Garbled => line.last_rx,
                    _ => now,
                });
                if may_retry {
                    self.counters.retries += 1;
                    self.publish_counters();
                    self.queues[queue_index(priority)].push_front(job);
                } else {
                    self.publish_counters();
                    let error = match (&outcome, &holding) {
                        (Attempt::AbortUnanswered, Some(holding)) => DeviceError::AbortUnanswered {
                            grace: holding.grace,
                            abort: holding.hold.abort.clone(),
                        },
                        _ => job.failure(timeout),
                    };
                    self.finish(job, Err(error));
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

    /// See an [`Expect::UntilQuiet`] request through: every byte that
    /// comes, unframed, until the line has been quiet for the quiet guard.
    async fn execute_raw(
        &mut self,
        line: &mut Line,
        job: Job,
        started: Instant,
        timeout: Duration,
    ) -> Result<(), String> {
        let deadline = started + timeout;
        let guard = self.wire.quiet_guard(line.byte_time);
        let priority = job.priority;
        let mut came = Vec::new();
        let outcome = loop {
            let quiet = (!came.is_empty()).then(|| line.last_rx + guard);
            tokio::select! {
                biased;
                input = line.incoming.recv() => match input {
                    Some(LinkInput::Bytes(bytes)) => {
                        line.received_now();
                        self.publish(
                            Direction::Received,
                            TrafficKind::Answer,
                            bytes.clone(),
                            Some(priority),
                        );
                        came.extend_from_slice(&bytes);
                    }
                    Some(LinkInput::Lost(reason)) => break Attempt::Lost(reason),
                    None => break Attempt::Lost("the link closed".into()),
                },
                order = self.orders.recv(), if self.orders_open => self.order(order),
                () = sleep_until(quiet.unwrap_or(deadline)), if quiet.is_some() => {
                    break Attempt::Answered;
                }
                // A line that never falls quiet answers with what came.
                () = sleep_until(deadline) => break if came.is_empty() {
                    Attempt::TimedOut
                } else {
                    Attempt::Answered
                },
            }
        };
        let now = Instant::now();
        match outcome {
            Attempt::Answered => {
                let answer = Answer {
                    frames: vec![came],
                    elapsed: now.saturating_duration_since(started),
                    attempts: job.attempts,
                };
                self.finish(job, Ok(answer));
            }
            Attempt::Lost(reason) => {
                let reason = format!("{}: {reason}", line.name);
                self.finish(job, Err(DeviceError::LinkLost(reason.clone())));
                return Err(reason);
            }
            Attempt::TimedOut | Attempt::Garbled | Attempt::AbortUnanswered => {
                self.count_failure(&Attempt::TimedOut);
                line.failed_at = Some(now);
                if job.may_retry() {
                    self.counters.retries += 1;
                    self.publish_counters();
                    self.queues[queue_index(priority)].push_front(job);
                } else {
                    self.publish_counters();
                    let error = job.failure(timeout);
                    self.finish(job, Err(error));
                }
            }
        }
        Ok(())
    }

    /// An order while a request is on the wire. While it is held, an abort
    /// or a pause is written at once, and an emergency stop or a shutdown
    /// aborts it first. `Err` carries the reason the link was lost.
    fn order_on_wire(
        &mut self,
        line: &mut Line,
        order: Option<Order>,
        holding: Option<&mut Holding>,
        deadline: &mut Option<Instant>,
    ) -> Result<(), String> {
        let Some(holding) = holding else {
            self.order(order);
            return Ok(());
        };
        if !holding.held {
            // A read that may be cut short: only for an emergency stop.
            let stop =
                matches!(&order, Some(Order::Submit(s)) if s.priority == Priority::EmergencyStop);
            self.order(order);
            if stop {
                self.abort_held(line, holding, deadline)?;
            }
            return Ok(());
        }
        match order {
            Some(Order::Abort(reply)) => {
                self.abort_held(line, holding, deadline)?;
                let _ = reply.send(true);
            }
            Some(Order::Pause(reply)) => {
                let paused = match holding.hold.pause.clone() {
                    Some(bytes) if !holding.aborted => {
                        self.write_held(line, &bytes, holding.busy.priority)?;
                        holding.paused = !holding.paused;
                        holding.busy.paused = holding.paused;
                        self.out.busy.send_replace(Some(holding.busy.clone()));
                        Some(holding.paused)
                    }
                    _ => None,
                };
                let _ = reply.send(paused);
            }
            Some(Order::Submit(submission)) if submission.priority == Priority::EmergencyStop => {
                self.order(Some(Order::Submit(submission)));
                self.abort_held(line, holding, deadline)?;
            }
            Some(Order::Shutdown) | None => {
                self.order(order);
                self.abort_held(line, holding, deadline)?;
            }
            other => self.order(other),
        }
        Ok(())
    }

    /// Write the held request's abort bytes (once) and give its answer the
    /// grace from now.
    fn abort_held(
        &mut self,
        line: &mut Line,
        holding: &mut Holding,
        deadline: &mut Option<Instant>,
    ) -> Result<(), String> {
        if holding.aborted {
            return Ok(());
        }
        let bytes = holding.hold.abort.clone();
        self.write_held(line, &bytes, holding.busy.priority)?;
        holding.aborted = true;
        holding.busy.aborting = true;
        if holding.held {
            self.out.busy.send_replace(Some(holding.busy.clone()));
        }
        self.counters.aborts += 1;
        self.publish_counters();
        *deadline = Some(Instant::now() + holding.grace);
        Ok(())
    }

    /// Write bytes a held request takes while it runs.
    fn write_held(
        &mut self,
        line: &mut Line,
        bytes: &[u8],
        priority: Priority,
    ) -> Result<(), String> {
        if let Err(error) = line.outgoing.send(bytes) {
            return Err(format!("{}: writing failed: {error}", line.name));
        }
        self.publish(
            Direction::Sent,
            TrafficKind::Request,
            bytes.to_vec(),
            Some(priority),
        );
        Ok(())
    }

    /// Send a sentinel before the next request (see [`Settling`]): once its
    /// answer is in, no answer to an earlier request can come any more,
    /// and none is looked for. If it gets none, it joins the unanswered
    /// and the request goes after it all the same.
    async fn send_sentinel(
        &mut self,
        line: &mut Line,
        sentinel: Sentinel,
        priority: Priority,
    ) -> Result<(), String> {
        let id = self.new_id();
        let timeout = self.timeout_for(line, None, sentinel.bytes.len());
        self.write_request(line, &sentinel.bytes, priority)?;
        line.sentinel_sent = true;
        self.counters.sentinels += 1;
        self.publish_counters();
        let deadline = Instant::now() + timeout;
        let (outcome, _) = self
            .attempt(
                line,
                id,
                &sentinel.rule,
                priority,
                Some(deadline),
                true,
                None,
            )
            .await;
        match outcome {
            Attempt::Answered => line.unanswered.clear(),
            Attempt::TimedOut | Attempt::Garbled | Attempt::AbortUnanswered => {
                self.count_failure(&outcome);
                self.publish_counters();
                line.failed_at = Some(Instant::now());
                line.unanswered.push_back(Unanswered {
                    job: id,
                    request: sentinel.bytes,
                    rule: sentinel.rule,
                    deadline,
                    timeout,
                });
            }
            Attempt::Lost(reason) => return Err(format!("{}: {reason}", line.name)),
        }
        Ok(())
    }

    /// Count an attempt that ended without an answer.
    fn count_failure(&mut self, outcome: &Attempt) {
        match outcome {
            Attempt::TimedOut | Attempt::AbortUnanswered => self.counters.timeouts += 1,
            Attempt::Garbled => self.counters.garbled_answers += 1,
            Attempt::Answered | Attempt::Lost(_) => {}
        }
    }

    /// Wait for the answer to the attempt of job `id` on the wire: each
    /// frame received is either the late answer to an unanswered attempt
    /// (the oldest that could have it), or put to `rule`, or news or stale.
    /// The attempt ends when the rule says the answer is complete (or
    /// complete unless more comes, and the line stays quiet for the quiet
    /// guard), at `deadline` (none for a held request until it is
    /// aborted), when the link is lost, or (`end_early`, for reads) when
    /// only bytes that made no answer came and the line fell silent.
    #[allow(clippy::too_many_arguments)]
    async fn attempt(
        &mut self,
        line: &mut Line,
        id: u64,
        rule: &Arc<dyn ReplyRule>,
        priority: Priority,
        mut deadline: Option<Instant>,
        end_early: bool,
        mut holding: Option<&mut Holding>,
    ) -> (Attempt, Received) {
        let mut received = Received::default();
        let guard = self.wire.quiet_guard(line.byte_time);
        let outcome = loop {
            let now = Instant::now();
            let partial = line.partial_deadline();
            let garbled = (end_early
                && received.accepted.is_empty()
                && !received.garbled.is_empty()
                && partial.is_none())
            .then(|| line.last_rx + line.silence);
            let quiet = received.unless_more.then(|| line.last_rx + guard);
            let aborted = holding.as_ref().is_some_and(|h| h.aborted);
            tokio::select! {
                biased;
                input = line.incoming.recv() => match input {
                    Some(LinkInput::Bytes(bytes)) => {
                        let frames = line.take_bytes(&bytes);
                        let skipped = self.log_skipped(line);
                        received.garbled.extend(skipped);
                        let progress =
                            self.take_frames(line, id, rule, priority, frames, &mut received);
                        if progress == Progress::Complete {
                            break Attempt::Answered;
                        }
                    }
                    Some(LinkInput::Lost(reason)) => break Attempt::Lost(reason),
                    None => break Attempt::Lost("the link closed".into()),
                },
                order = self.orders.recv(), if self.orders_open => {
                    if let Err(reason) =
                        self.order_on_wire(line, order, holding.as_deref_mut(), &mut deadline)
                    {
                        break Attempt::Lost(reason);
                    }
                }
                () = sleep_until(quiet.unwrap_or(now)), if quiet.is_some() => {
                    break Attempt::Answered;
                }
                () = sleep_until(deadline.unwrap_or(now)), if deadline.is_some() => {
                    break if aborted {
                        Attempt::AbortUnanswered
                    } else {
                        Attempt::TimedOut
                    };
                }
                () = sleep_until(partial.unwrap_or(now)), if partial.is_some() => {
                    let (dropped, frame) = self.expire_partial(line, Instant::now());
                    received.garbled.extend(dropped);
                    if let Some(frame) = frame {
                        let progress =
                            self.take_frames(line, id, rule, priority, vec![frame], &mut received);
                        if progress == Progress::Complete {
                            break Attempt::Answered;
                        }
                    }
                }
                () = sleep_until(garbled.unwrap_or(now)), if garbled.is_some() => {
                    break Attempt::Garbled;
                }
            }
        };
        (outcome, received)
    }

    /// Frames received while job `id`'s attempt is on the wire: how far
    /// its answer has come.
    fn take_frames(
        &mut self,
        line: &mut Line,
        id: u64,
        rule: &Arc<dyn ReplyRule>,
        priority: Priority,
        frames: Vec<Frame>,
        received: &mut Received,
    ) -> Progress {
        let mut progress = if received.unless_more {
            Progress::UnlessMore
        } else {
            Progress::Open
        };
        for frame in frames {
            if progress == Progress::Complete {
                self.unrelated(line, frame);
                continue;
            }
            if received.accepted.is_empty()
                && let Some(index) = line.late_owner(&frame)
            {
                let owner = line.unanswered.remove(index);
                if owner.as_ref().is_some_and(|u| u.job == id) {
                    // An earlier attempt of this job: its answer is this
                    // job's answer too.
                    received.through_earlier_attempt = true;
                } else {
                    if rule.examine(&[], &frame) != Verdict::NotMine {
                        received.ambiguous.extend_from_slice(&frame);
                    }
                    self.stale(frame);
                    continue;
                }
            }
            match rule.examine(&received.accepted, &frame) {
                Verdict::NotMine if progress == Progress::UnlessMore => {
                    // The answer ended before it: it is not this answer's.
                    progress = Progress::Complete;
                    self.unrelated(line, frame);
                }
                Verdict::NotMine => {
                    if !self.news(&frame) {
                        received.garbled.extend_from_slice(&frame);
                        self.stale(frame);
                    }
                }
                verdict => {
                    progress = match verdict {
                        Verdict::Complete => Progress::Complete,
                        Verdict::CompleteIfQuiet => Progress::UnlessMore,
                        _ => Progress::Open,
                    };
                    self.publish(
                        Direction::Received,
                        TrafficKind::Answer,
                        frame.clone(),
                        Some(priority),
                    );
                    received.accepted.push(frame);
                }
            }
        }
        received.unless_more = progress == Progress::UnlessMore;
        progress
    }

    /// What goes next, given the queues and the poll plan.
    fn next(&self, now: Instant) -> Next {
        if let Some(job) = self.queues.iter().find_map(|queue| queue.front()) {
            return Next::Queued {
                priority: job.priority,
                id: job.id,
            };
        }
        match self.polling.next(now) {
            Some((_, Some(due))) if due > now => Next::PollAt(due),
            Some(_) => Next::Poll,
            None => Next::Idle,
        }
    }

    fn take_job(&mut self, now: Instant) -> Option<Job> {
        if let Some(job) = self.queues.iter_mut().find_map(VecDeque::pop_front) {
            return Some(job);
        }
        let (key, due) = self.polling.next(now)?;
        if due.is_some_and(|due| due > now) {
            return None;
        }
        let transaction = self.polling.sent(key, now)?.transaction.clone();
        let id = self.new_id();
        Some(Job::new(id, Priority::Poll, transaction, Origin::Plan(key)))
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
                self.queues[queue_index(priority)].push_back(Job::new(
                    id,
                    priority,
                    transaction,
                    Origin::Caller(reply),
                ));
            }
            Some(Order::Shutdown) => self.closing = true,
            // Nothing is held.
            Some(Order::Abort(reply)) => {
                let _ = reply.send(false);
            }
            Some(Order::Pause(reply)) => {
                let _ = reply.send(None);
            }
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

    fn plan(&mut self, plan: Option<(PollOwner, Option<PollPlan>)>) {
        match plan {
            Some((owner, plan)) => self.polling.set(owner, plan),
            None => self.plans_open = false,
        }
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
            Origin::Plan(key) => self.polling.record(key, result.as_ref()),
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
        let mut attempts = 0u32;
        loop {
            self.set_state(LinkState::Disconnected {
                reason: reason.clone(),
                attempts,
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
                    // One line: the state is shown in status bars; the
                    // advice under it was for the first opening.
                    reason = error.headline();
                    attempts = attempts.saturating_add(1);
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
