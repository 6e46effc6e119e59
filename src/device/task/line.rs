//! The open link as the task sees it: its framer, what it heard, and the
//! attempts whose answers may still come, with the settling that keeps a
//! late answer from being taken for the next request's.

use super::*;

/// An attempt whose answer has not come (it timed out, or got only bytes
/// that made no answer) and may still come: until it does, or the line is
/// settled, or [`LATE_ANSWER_TIMEOUTS`] timeouts after its deadline, a
/// frame its rule accepts is taken for its late answer, never for the
/// answer to a request sent after it.
pub(super) struct Unanswered {
    /// The job it was an attempt of (a sentinel's own id for a sentinel).
    pub(super) job: u64,
    pub(super) request: Vec<u8>,
    pub(super) rule: Arc<dyn ReplyRule>,
    pub(super) deadline: Instant,
    pub(super) timeout: Duration,
}

impl Unanswered {
    pub(super) fn forget_at(&self) -> Instant {
        self.deadline + self.timeout.saturating_mul(LATE_ANSWER_TIMEOUTS)
    }
}

/// What has to happen before the next request may go.
pub(super) enum Settle {
    /// Nothing: no answer that may still come could be taken for its.
    Go,
    /// Send this sentinel first.
    Sentinel(Sentinel),
    /// Wait until then (the line quiet for one timeout after the last
    /// deadline), then forget the unanswered requests.
    QuietUntil(Instant),
    /// Wait until then (the oldest unanswered attempt is no longer looked
    /// for), then settle again ([`Settling::AwaitSentinel`]).
    Until(Instant),
}

/// The open link and what the task knows of its line.
pub(super) struct Line {
    pub(super) name: String,
    pub(super) incoming: mpsc::UnboundedReceiver<LinkInput>,
    pub(super) outgoing: Box<dyn LinkWriter>,
    pub(super) byte_time: Option<Duration>,
    pub(super) framer: Box<dyn Framer>,
    pub(super) silence: Duration,
    pub(super) last_rx: Instant,
    /// Since when bytes have come without the line falling silent between
    /// them (meaningful while `last_rx` is recent).
    pub(super) talking_since: Instant,
    /// Garbage was seen at this time: wait for silence before sending.
    pub(super) garbage_at: Option<Instant>,
    /// The last attempt failed at this time: wait for silence before
    /// sending (a late answer may be on its way).
    pub(super) failed_at: Option<Instant>,
    /// Attempts whose answers may still come, oldest first.
    pub(super) unanswered: VecDeque<Unanswered>,
    /// A sentinel went since the last request: the next request goes
    /// without another, whatever became of it.
    pub(super) sentinel_sent: bool,
    /// What came while no request was on the wire, since the last one was
    /// written: shown when a request could not go for it.
    pub(super) heard: Heard,
}

/// Bytes that came while no request was on the wire: how many, and the
/// first [`Heard::KEPT`] of them.
#[derive(Default)]
pub(super) struct Heard {
    pub(super) count: u64,
    pub(super) first: Vec<u8>,
}

impl Heard {
    /// Enough to recognise what kept the line busy, short enough for one
    /// error line.
    const KEPT: usize = 32;

    pub(super) fn add(&mut self, bytes: &[u8]) {
        self.count = self
            .count
            .saturating_add(u64::try_from(bytes.len()).unwrap_or(u64::MAX));
        let room = Self::KEPT.saturating_sub(self.first.len());
        self.first.extend(bytes.iter().take(room));
    }
}

impl Line {
    pub(super) fn new(link: Link, wire: &dyn WireFormat) -> Line {
        Line {
            silence: wire.silence(link.byte_time),
            framer: wire.framer(),
            name: link.name,
            incoming: link.incoming,
            outgoing: link.outgoing,
            byte_time: link.byte_time,
            last_rx: Instant::now(),
            talking_since: Instant::now(),
            garbage_at: None,
            failed_at: None,
            unanswered: VecDeque::new(),
            sentinel_sent: false,
            heard: Heard::default(),
        }
    }

    pub(super) fn take_bytes(&mut self, bytes: &[u8]) -> Vec<Frame> {
        self.received_now();
        self.framer.push(bytes)
    }

    /// Bytes came just now: a new stretch of talk if the line had been
    /// silent since the last ones.
    pub(super) fn received_now(&mut self) {
        let now = Instant::now();
        if now.saturating_duration_since(self.last_rx) > self.silence {
            self.talking_since = now;
        }
        self.last_rx = now;
    }

    /// When a partial frame held back becomes garbage.
    pub(super) fn partial_deadline(&self) -> Option<Instant> {
        (self.framer.pending() > 0).then(|| self.last_rx + self.silence)
    }

    /// The oldest unanswered attempt whose answer `frame` could be: a
    /// module answers in order, so the earliest possible owner is the one
    /// to take it for (a frame that could answer both an earlier request
    /// and the one in flight is never taken for the one in flight's).
    pub(super) fn late_owner(&self, frame: &[u8]) -> Option<usize> {
        self.unanswered
            .iter()
            .position(|u| u.rule.examine(&[], frame) != Verdict::NotMine)
    }

    pub(super) fn forget_expired(&mut self, now: Instant) {
        self.unanswered.retain(|u| u.forget_at() > now);
    }

    /// What has to happen before a request of `priority` (job `id`, `None`
    /// for a poll not yet made) with these `bytes` and `expect` may go.
    pub(super) fn settle(
        &self,
        wire: &dyn WireFormat,
        priority: Priority,
        id: Option<u64>,
        bytes: &[u8],
        expect: &Expect,
    ) -> Settle {
        if matches!(expect, Expect::Nothing | Expect::UntilQuiet) {
            return Settle::Go;
        }
        // Earlier attempts of the same read answer it just as well.
        let confusable = self
            .unanswered
            .iter()
            .any(|u| Some(u.job) != id && !wire.answers_apart(&u.request, bytes));
        if !confusable || self.sentinel_sent {
            return Settle::Go;
        }
        let unanswered: Vec<&[u8]> = self
            .unanswered
            .iter()
            .map(|u| u.request.as_slice())
            .collect();
        match wire.settling(bytes, &unanswered) {
            Settling::Sentinel(sentinel) => Settle::Sentinel(sentinel),
            Settling::InOrder => Settle::Go,
            Settling::AwaitSentinel if priority == Priority::EmergencyStop => Settle::Go,
            Settling::AwaitSentinel => Settle::Until(
                self.unanswered
                    .iter()
                    .map(Unanswered::forget_at)
                    .min()
                    .unwrap_or(self.last_rx),
            ),
            // An emergency stop does not wait: its answer is judged in
            // order like any other, and the unanswered stay in view.
            Settling::QuietTime if priority == Priority::EmergencyStop => Settle::Go,
            Settling::QuietTime => {
                let last = self.unanswered.iter().map(|u| u.deadline).max();
                let quiet = self
                    .unanswered
                    .iter()
                    .map(|u| u.timeout)
                    .max()
                    .unwrap_or_default()
                    .max(self.silence);
                Settle::QuietUntil(last.unwrap_or(self.last_rx).max(self.last_rx) + quiet)
            }
        }
    }

    /// When the line will be quiet enough to send, given what settling
    /// asks for; `None`: now.
    pub(super) fn ready_at(&self, settle: &Settle) -> Option<Instant> {
        let quiet_from = |since: Instant| since.max(self.last_rx);
        let garbage = self.garbage_at.map(|at| quiet_from(at) + self.silence);
        let failed = self.failed_at.map(|at| quiet_from(at) + self.silence);
        let settling = match settle {
            Settle::QuietUntil(at) | Settle::Until(at) => Some(*at),
            Settle::Go | Settle::Sentinel(_) => None,
        };
        [self.partial_deadline(), garbage, failed, settling]
            .into_iter()
            .flatten()
            .max()
    }
}
