//! A queued request: who gets its result, how often it may be tried,
//! and what its failure says.

use super::*;

/// Who gets a job's result.
pub(super) enum Origin {
    Caller(oneshot::Sender<Result<Answer, DeviceError>>),
    /// An item of a poll plan.
    Plan(PollKey),
}

/// A transaction on its way through the task.
pub(super) struct Job {
    pub(super) id: u64,
    pub(super) priority: Priority,
    pub(super) transaction: Transaction,
    /// Attempts sent so far.
    pub(super) attempts: u32,
    pub(super) origin: Origin,
    /// The bytes that answered nothing (garbage, frames no request
    /// claimed) in the last attempt that received any: a garbled answer,
    /// if it came at all.
    pub(super) garbled: Vec<u8>,
    /// The frames its rule accepted but that could be the late answer to
    /// an earlier request (so they were taken for that one's), in the last
    /// attempt that received any.
    pub(super) ambiguous: Vec<u8>,
    /// Since when it has headed the queues (see [`Task::overdue`]).
    pub(super) waiting: Option<Instant>,
}

impl Job {
    pub(super) fn new(
        id: u64,
        priority: Priority,
        transaction: Transaction,
        origin: Origin,
    ) -> Job {
        Job {
            id,
            priority,
            transaction,
            attempts: 0,
            origin,
            garbled: Vec::new(),
            ambiguous: Vec::new(),
            waiting: None,
        }
    }

    /// How many attempts it may have in all.
    pub(super) fn allowed_attempts(&self) -> u32 {
        match self.transaction.retry {
            Retry::Never => 1,
            Retry::Read(further) => further.saturating_add(1),
        }
    }

    /// Whether a failed attempt may be followed by another one.
    pub(super) fn may_retry(&self) -> bool {
        match self.transaction.retry {
            Retry::Never => false,
            Retry::Read(further) => self.attempts <= further,
        }
    }

    /// Why its last attempt failed, all attempts considered.
    pub(super) fn failure(&self, timeout: Duration) -> DeviceError {
        let attempts = self.attempts;
        if !self.ambiguous.is_empty() {
            DeviceError::Ambiguous {
                attempts,
                answer: self.ambiguous.clone(),
            }
        } else if !self.garbled.is_empty() {
            DeviceError::Garbled {
                timeout,
                attempts,
                received: self.garbled.clone(),
            }
        } else {
            DeviceError::Timeout { timeout, attempts }
        }
    }
}
