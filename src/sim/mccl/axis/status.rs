//! The five status words of an axis (manual Ch8 TS), bit by bit.

use super::profile::{Phase, Shape};
use super::settings::Speed;
use super::{Axis, AxisInputs, Mode};

// ---- primary status (TS0, LU"STATUS") ----
pub const MOTOR_ERROR: u32 = 1 << 0;
pub const MOTOR_ON: u32 = 1 << 1;
pub const AT_TARGET: u32 = 1 << 2;
pub const TRAJECTORY_COMPLETE: u32 = 1 << 3;
pub const DIRECTION: u32 = 1 << 4;
pub const CAPTURED: u32 = 1 << 5;
pub const BREAKPOINT: u32 = 1 << 6;
pub const FOLLOWING_ERROR: u32 = 1 << 8;
pub const AMP_FAULT: u32 = 1 << 9;
pub const HARD_LIMIT_PLUS: u32 = 1 << 10;
pub const HARD_LIMIT_MINUS: u32 = 1 << 11;
pub const SOFT_LIMIT_HIGH: u32 = 1 << 12;
pub const SOFT_LIMIT_LOW: u32 = 1 << 13;
pub const ENCODER_FAULT: u32 = 1 << 14;
/// Looking for index (FI, IA, WI) or edge (FE, EL, WE).
pub const LOOKING: u32 = 1 << 17;
/// Index (closed loop) or edge (open-loop stepper) found.
pub const FOUND: u32 = 1 << 18;
pub const LOOKING_AUX: u32 = 1 << 19;
pub const AUX_FOUND: u32 = 1 << 20;
pub const HOMED: u32 = 1 << 21;
pub const INDEX_INPUT: u32 = 1 << 24;
pub const COARSE_HOME_INPUT: u32 = 1 << 25;
pub const AUX_INDEX_INPUT: u32 = 1 << 26;
pub const FAULT_INPUT: u32 = 1 << 27;
pub const LIMIT_PLUS_INPUT: u32 = 1 << 28;
pub const LIMIT_MINUS_INPUT: u32 = 1 << 29;

/// What MN clears: the motor error and the tripped flags, bits 8–14
/// (Ch5 LN, SE, FN, EE: "until the motor is turned back on").
pub const CLEARED_BY_MOTOR_ON: u32 = MOTOR_ERROR | 0x7F00;

/// The word asked for by `TS n` (0, 64, 96, 128, 160) and the bit a query
/// 1–31 above it reads; `None` for the unused range 32–63.
pub fn word_of(n: i64) -> Option<(StatusWord, Option<u32>)> {
    let (word, base) = match n {
        0..=31 => (StatusWord::Primary, 0),
        64..=95 => (StatusWord::Auxiliary, 64),
        96..=127 => (StatusWord::Profile, 96),
        128..=159 => (StatusWord::TrajectoryMode, 128),
        160..=191 => (StatusWord::EncoderFault, 160),
        _ => return None,
    };
    let bit = u32::try_from(n - base).ok().filter(|&b| b > 0);
    Some((word, bit))
}

/// The five words of Ch8 TS.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StatusWord {
    Primary,
    Auxiliary,
    Profile,
    TrajectoryMode,
    EncoderFault,
}

/// Things outside the axis its words show.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Surroundings {
    pub inputs: AxisInputs,
    /// Synchronisation on (SN) in the axis' contour group.
    pub sync_on: bool,
    /// A synchronised move is waiting for GO.
    pub sync_ready: bool,
}

impl Axis {
    pub fn status_word(&self, word: StatusWord, around: &Surroundings) -> u32 {
        match word {
            StatusWord::Primary => self.primary_status(&around.inputs),
            StatusWord::Auxiliary => self.auxiliary_status(around),
            StatusWord::Profile => self.profile_status(),
            StatusWord::TrajectoryMode => self.trajectory_mode_status(),
            StatusWord::EncoderFault => self.encoder_fault_status(),
        }
    }

    /// Primary status (n = 0).
    pub fn primary_status(&self, inputs: &AxisInputs) -> u32 {
        let mut word = self.latched;
        let set = |word: &mut u32, bit: u32, on: bool| {
            if on {
                *word |= bit;
            }
        };
        set(&mut word, MOTOR_ON, self.motor_on);
        set(&mut word, AT_TARGET, self.at_target());
        set(&mut word, TRAJECTORY_COMPLETE, self.trajectory_complete());
        set(&mut word, DIRECTION, self.negative);
        let index_now = if self.is_open_loop_stepper() {
            inputs.home
        } else {
            self.on_index_mark()
        };
        set(&mut word, INDEX_INPUT, index_now || self.index_latched);
        set(&mut word, COARSE_HOME_INPUT, self.is_servo() && inputs.home);
        set(
            &mut word,
            AUX_INDEX_INPUT,
            !self.is_servo() && self.on_mark(self.shaft.round()),
        );
        set(&mut word, FAULT_INPUT, inputs.fault);
        set(&mut word, LIMIT_PLUS_INPUT, inputs.limit_plus);
        set(&mut word, LIMIT_MINUS_INPUT, inputs.limit_minus);
        word
    }

    /// The encoder sits on an index mark.
    pub fn on_index_mark(&self) -> bool {
        self.on_mark(self.position())
    }

    fn on_mark(&self, position: f64) -> bool {
        self.index_period > 0.0
            && (position - self.index_phase).rem_euclid(self.index_period) == 0.0
    }

    /// Auxiliary status (n = 64).
    pub fn auxiliary_status(&self, around: &Surroundings) -> u32 {
        let s = &self.settings;
        let bits = [
            (0, s.limits & 1 != 0),
            (1, s.limits & 2 != 0),
            (2, s.hard_limit_action() == 1),
            (3, s.hard_limit_action() == 2),
            (4, s.limits & 4 != 0),
            (5, s.limits & 8 != 0),
            (6, s.soft_limit_action() == 1),
            (7, s.soft_limit_action() == 2),
            (8, s.hard_limits_inverted()),
            (9, s.hard_limits_inverted()),
            (10, s.fault_check),
            (11, s.reverse_phase),
            (12, s.backlash_on),
            (13, s.backlash_on && !self.negative),
            (14, s.backlash_on && self.negative),
            (16, s.speed == Speed::Low),
            (17, s.speed == Speed::Medium),
            (18, s.speed == Speed::High),
            (20, self.compare.active.is_some()),
            (21, self.record.capturing.is_some()),
            (22, around.sync_on),
            (23, around.sync_ready),
            (27, !self.is_servo() && s.full_current),
            (28, !self.is_servo() && s.input_mode == 128),
        ];
        bits.iter()
            .filter(|(_, on)| *on)
            .fold(0, |word, (bit, _)| word | 1 << bit)
    }

    /// Profile generator status (n = 96).
    pub fn profile_status(&self) -> u32 {
        let desired_negative = self.target < self.optimal;
        let bits = [
            (0, self.trajectory_complete()),
            (1, self.negative),
            (2, desired_negative),
            (3, self.phase == Phase::Accelerating),
            (5, self.stopping || self.phase == Phase::Decelerating),
            (12, self.settings.profile == Shape::Trapezoid),
            (13, self.settings.profile == Shape::SCurve),
            (14, self.settings.profile == Shape::Parabolic),
        ];
        bits.iter()
            .filter(|(_, on)| *on)
            .fold(0, |word, (bit, _)| word | 1 << bit)
    }

    /// Trajectory mode status (n = 128).
    pub fn trajectory_mode_status(&self) -> u32 {
        let mode_bit = match self.mode {
            Mode::Position => 0,
            Mode::Velocity => 1,
            Mode::Gain => 2,
            Mode::Torque => 3,
            Mode::Contour(_) => 4,
        };
        let mut word = 1 << mode_bit;
        if self.slave.is_some() {
            word |= 1 << 16;
        }
        word
    }

    /// Encoder fault status (n = 160): a fault shows on all of A, B, Z.
    pub fn encoder_fault_status(&self) -> u32 {
        let mut word = 0;
        if self.encoder_fault && self.is_closed_loop() {
            word |= 0b1111;
        }
        if self.settings.encoder_check == 1 {
            word |= 1 << 12;
        }
        word
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ts_parameters_name_a_word_and_a_bit() {
        assert_eq!(word_of(0), Some((StatusWord::Primary, None)));
        assert_eq!(word_of(3), Some((StatusWord::Primary, Some(3))));
        assert_eq!(word_of(64), Some((StatusWord::Auxiliary, None)));
        assert_eq!(word_of(97), Some((StatusWord::Profile, Some(1))));
        assert_eq!(word_of(128), Some((StatusWord::TrajectoryMode, None)));
        assert_eq!(word_of(191), Some((StatusWord::EncoderFault, Some(31))));
        assert_eq!(word_of(32), None);
        assert_eq!(word_of(63), None);
        assert_eq!(word_of(192), None);
    }

    #[test]
    fn the_manuals_status_example_decodes_to_its_bits() {
        // Ch8 TS: 268436489 = bits 28, 10, 3, 0.
        assert_eq!(
            LIMIT_PLUS_INPUT | HARD_LIMIT_PLUS | TRAJECTORY_COMPLETE | MOTOR_ERROR,
            268_436_489
        );
        // Ch13 DM/HM: 10 = trajectory complete + motor on.
        assert_eq!(TRAJECTORY_COMPLETE | MOTOR_ON, 10);
    }
}
