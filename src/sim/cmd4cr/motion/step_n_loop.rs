//! StepNLoop closed-loop position verification of one axis (§2.5.3, Table
//! 2-26, Table 27): with `SL[axis]=1` position targets are in encoder
//! counts, for single-axis and interpolated moves alike ("this applies to
//! individual as well as interpolated moves"); single-axis speeds (and
//! `SSPD`) are in encoder counts/s, interpolation speeds stay in pulses/s
//! (T2-29: "ALL interpolated moves: pulse/sec"). `P` reads the real-time
//! target, `D` the deviation target − encoder, and the loop checks it:
//! - while moving (homing, jogging and interpolation included), |D| > SLE
//!   is a stall: the axis stops, SLS 10 (an interpolation stops with it,
//!   C.6);
//! - at the end of a targeted move, |D| ≤ SLT is in position; SLT < |D|
//!   ≤ SLE starts a correction move (SLS 2), at most SLA of them (then SLS
//!   9); |D| > SLE is a range error (SLS 8).
//!
//! SLS shows what the axis does (Table 27): 1 positioning, 2 correcting,
//! 3 braking after STOP, 4 ABORT, 5 jogging, 6 homing on the home switch
//! (modes 0–5, 9–11), 7 ZMOVE, 13 homing on an end limit (modes 6, 7, 8,
//! 12), 11 stopped by an end limit.
//!
//! Errors show in SLS, not MST (footnotes 4, 5); a motion command while
//! 8, 9 or 10 is set answers `?Error SNL`; CLR clears them.
//!
//! Choices where the manual is silent (also in the simulator's help):
//! - A correction move uses the axis' single-axis speeds (encoder
//!   counts/s); the attempt count starts again with every commanded move.
//! - An interpolated move (linear, circle, arc, helical) is verified per
//!   axis when it ends: each closed-loop axis gets its own verdict and, if
//!   it must, its own single-axis correction; the others are free at once.
//!   Axes with SL off in the same move are not verified.
//! - A circle's centre and a helical Z are encoder positions converted per
//!   axis at SLR pulses a count from where the encoder is; with equal SLR
//!   on both axes the circle in counts is the circle in pulses (unequal
//!   ratios draw the circle in pulses around the converted centre).
//! - `T` with SL on is an encoder target too; in INC mode it counts from
//!   what `P` read when the move began.
//! - STOP, ABORT, an end limit, ESTOP and ALM end the move without a
//!   correction: `P` then reads where the pulses stopped. SLS 3 lasts while
//!   the axis brakes; ABORT stops at once, so SLS 4 lasts until the next
//!   100 µs tick. SLS 11 stays until CLR or the next motion; it does not
//!   itself refuse moves (the MST limit flag does, unless IERR=1).
//! - The buffer does not run while SL is on for X, Y or Z (§2.3.4):
//!   `BSTART` answers `?Error SNL`, the only reply T4-41 ties to
//!   StepNLoop; SL turned on while the buffer runs stops the feed after
//!   the move under way.
//! - Latch values are "invalid" with SL on (§2.1.3.2.1): `LTP` keeps the
//!   raw pulse counter, which is not in the units `P` reads.
//! - `SL=1` on an axis under joystick control leaves SL off (§2.5.1:
//!   "automatically disabled"); the write is answered like any other.
//! - The simulated motor misses steps only when told to (the `MISS…` and
//!   `SLIP…` settings, [`super::Motion::miss_steps`]); the loop sees them
//!   as any encoder would.

/// `SLS` codes (Table 27).
pub mod status {
    pub const IDLE: u8 = 0;
    pub const MOVING: u8 = 1;
    pub const CORRECTING: u8 = 2;
    pub const STOPPING: u8 = 3;
    pub const ABORTING: u8 = 4;
    pub const JOGGING: u8 = 5;
    pub const HOMING: u8 = 6;
    pub const Z_HOMING: u8 = 7;
    pub const RANGE_ERROR: u8 = 8;
    pub const ATTEMPT_ERROR: u8 = 9;
    pub const STALL_ERROR: u8 = 10;
    pub const LIMIT_ERROR: u8 = 11;
    pub const NOT_ENABLED: u8 = 12;
    pub const LIMIT_HOMING: u8 = 13;
}

/// The settings (`SL`, `SLR`, `SLT`, `SLE`, `SLA`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StepNLoop {
    pub enabled: bool,
    /// `SLR`: motor pulses per encoder count, in thousandths.
    pub ratio: i64,
    /// `SLT`, encoder counts.
    pub tolerance: i64,
    /// `SLE`, encoder counts.
    pub error_range: i64,
    /// `SLA`.
    pub attempts: i64,
}

/// Defaults, our choice: ratio 1.000, tolerance 10 counts, error range
/// 1000 counts, 3 attempts.
impl Default for StepNLoop {
    fn default() -> Self {
        StepNLoop {
            enabled: false,
            ratio: 1000,
            tolerance: 10,
            error_range: 1000,
            attempts: 3,
        }
    }
}

impl StepNLoop {
    /// Pulses per encoder count.
    pub fn pulses_per_count(&self) -> f64 {
        self.ratio.max(1) as f64 / 1000.0
    }
}

/// What the loop is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LoopState {
    /// `SLS` while enabled.
    pub status: u8,
    /// The encoder target of the last positioning move.
    pub target: i64,
    /// Where the current positioning move started, in encoder counts (what
    /// `P` read then): `T` in INC mode counts from here (§2.4.2).
    pub origin: i64,
    /// Pulse counter and encoder when the current motion started.
    pub start: Option<(i64, i64)>,
    /// Corrections made for the current target.
    pub tries: i64,
}

impl LoopState {
    pub fn in_error(&self) -> bool {
        matches!(
            self.status,
            status::RANGE_ERROR | status::ATTEMPT_ERROR | status::STALL_ERROR
        )
    }
}

/// After a positioning move: what to do with deviation `delta`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    InPosition,
    Correct,
    RangeError,
    AttemptError,
}

pub fn verdict(settings: &StepNLoop, delta: i64, tries: i64) -> Verdict {
    let d = delta.abs();
    if d <= settings.tolerance {
        Verdict::InPosition
    } else if d > settings.error_range {
        Verdict::RangeError
    } else if tries >= settings.attempts {
        Verdict::AttemptError
    } else {
        Verdict::Correct
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_2_26() {
        let s = StepNLoop {
            enabled: true,
            tolerance: 5,
            error_range: 100,
            attempts: 2,
            ..StepNLoop::default()
        };
        assert_eq!(verdict(&s, -5, 0), Verdict::InPosition);
        assert_eq!(verdict(&s, 6, 0), Verdict::Correct);
        assert_eq!(verdict(&s, 6, 2), Verdict::AttemptError);
        assert_eq!(verdict(&s, -101, 0), Verdict::RangeError);
        assert_eq!(s.pulses_per_count(), 1.0);
    }
}
