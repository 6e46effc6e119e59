//! Faults injected between a simulator and its link, for tests of
//! everything above: replies dropped or corrupted, garbage on the line,
//! late replies, a cable pulled after a while.

/// Which faults to inject, and how often. Probabilities are 0.0..=1.0 and
/// apply per reply (per chunk of output the simulator produces).
#[derive(Debug, Clone, Default, PartialEq)]
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
    /// Seed of the fault generator, so that a failing run can be replayed.
    pub seed: u64,
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
    }
}
