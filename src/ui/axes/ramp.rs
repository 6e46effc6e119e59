//! The ramp state of an axis, read from how its speed changes.

use super::*;

/// What the axis is doing, read from how its speed changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ramp {
    Unknown,
    Standing,
    Accelerating,
    /// Moving at the maximum (positioning) speed.
    Cruising,
    /// Moving at a constant speed below the maximum (velocity mode).
    Constant,
    Decelerating,
    /// Not moving, the motion not over: waiting for an input.
    Waiting,
}

impl Ramp {
    pub fn label(self) -> &'static str {
        match self {
            Ramp::Unknown => "—",
            Ramp::Standing => "standing",
            Ramp::Accelerating => "accelerating",
            Ramp::Cruising => "at max speed",
            Ramp::Constant => "constant speed",
            Ramp::Decelerating => "decelerating",
            Ramp::Waiting => "waiting",
        }
    }

    /// At most six characters, for one-row-per-axis tables.
    pub fn short_label(self) -> &'static str {
        match self {
            Ramp::Unknown => "—",
            Ramp::Standing => "stand",
            Ramp::Accelerating => "accel",
            Ramp::Cruising => "cruise",
            Ramp::Constant => "const",
            Ramp::Decelerating => "decel",
            Ramp::Waiting => "wait",
        }
    }

    /// The ramp state a module reports; a constant speed is the maximum
    /// one when the speed read equals it.
    pub fn from_phase(phase: MotionPhase, speed: Option<i64>, max: Option<i64>) -> Ramp {
        match phase {
            MotionPhase::Standing => Ramp::Standing,
            MotionPhase::Accelerating => Ramp::Accelerating,
            MotionPhase::Decelerating => Ramp::Decelerating,
            MotionPhase::Waiting => Ramp::Waiting,
            MotionPhase::Constant => match (speed, max) {
                (Some(s), Some(m)) if s.unsigned_abs() == m.unsigned_abs() => Ramp::Cruising,
                _ => Ramp::Constant,
            },
        }
    }

    /// The ramp state after `previous` speed became `speed`.
    pub fn from_speeds(previous: Option<i64>, speed: Option<i64>, max: Option<i64>) -> Ramp {
        let Some(speed) = speed else {
            return Ramp::Unknown;
        };
        let now = speed.unsigned_abs();
        if now == 0 {
            return Ramp::Standing;
        }
        let before = previous.map_or(0, i64::unsigned_abs);
        match now.cmp(&before) {
            std::cmp::Ordering::Greater => Ramp::Accelerating,
            std::cmp::Ordering::Less => Ramp::Decelerating,
            std::cmp::Ordering::Equal if max.is_some_and(|m| m.unsigned_abs() == now) => {
                Ramp::Cruising
            }
            std::cmp::Ordering::Equal => Ramp::Constant,
        }
    }
}
