//! What the setup commands of Ch5 set on one axis, with the defaults the
//! simulator chose where the manual gives none (listed in
//! [`crate::sim::mccl::choices`]), and the user units of Ch5 US/UR/UO/UZ.

use super::profile::Shape;

/// The kind of axis (Ch2 "Analog Command Axis" / "Pulse Command Axis").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisKind {
    /// A servo: ±10 V command output, encoder feedback, PID.
    Servo,
    /// A stepper: step pulses; open loop unless `IM1` closes it.
    Stepper,
}

/// The loop rate of a servo, the pulse range of a stepper (HS/MS/LS).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Speed {
    Low,
    Medium,
    High,
}

impl Speed {
    /// The pulse rates a stepper can give in this range (Ch5 HS/MS/LS).
    pub fn pulse_range(self) -> (f64, f64) {
        match self {
            Speed::Low => (0.1, 78_000.0),
            Speed::Medium => (500.0, 650_000.0),
            Speed::High => (500.0, 5_000_000.0),
        }
    }
}

/// Encoder counts (steps) per user unit, seconds per user time unit, and
/// the two offsets (Ch5 US, UR, UO, UZ). A position n in user units is
/// (n + UO + UZ) × US counts: UO is the distance from home to the machine
/// zero and UZ the part zero, both in user units; the manual gives no
/// formula, so this one is the simulator's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Units {
    pub scale: f64,
    pub rate: f64,
    pub offset: f64,
    pub zero: f64,
}

impl Default for Units {
    fn default() -> Self {
        Units {
            scale: 1.0,
            rate: 1.0,
            offset: 0.0,
            zero: 0.0,
        }
    }
}

impl Units {
    pub fn to_counts(&self, user: f64) -> f64 {
        (user + self.offset + self.zero) * self.scale
    }

    pub fn to_user(&self, counts: f64) -> f64 {
        counts / self.scale - self.offset - self.zero
    }

    /// A distance (no offsets) in counts.
    pub fn distance_to_counts(&self, user: f64) -> f64 {
        user * self.scale
    }

    pub fn distance_to_user(&self, counts: f64) -> f64 {
        counts / self.scale
    }

    /// A speed in user units per user time unit, in counts per second.
    pub fn speed_to_counts(&self, user: f64) -> f64 {
        user * self.scale / self.rate
    }

    pub fn speed_to_user(&self, counts: f64) -> f64 {
        counts * self.rate / self.scale
    }

    /// An acceleration in user units per user time unit², in counts/s².
    pub fn acceleration_to_counts(&self, user: f64) -> f64 {
        user * self.scale / (self.rate * self.rate)
    }
}

/// The setup values of one axis, in user units as given.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    pub velocity: f64,
    pub acceleration: f64,
    pub deceleration: f64,
    pub minimum_velocity: f64,
    pub velocity_override: f64,
    pub profile: Shape,
    /// DI1: velocity mode runs negative.
    pub negative: bool,
    pub proportional_gain: f64,
    pub derivative_gain: f64,
    pub integral_gain: f64,
    pub integration_limit: f64,
    pub integral_option: u8,
    pub derivative_period: i64,
    pub velocity_gain: f64,
    pub acceleration_gain: f64,
    pub deceleration_gain: f64,
    pub output_deadband: f64,
    pub output_offset: f64,
    /// SQ: output limit (position/velocity mode) or output (torque mode).
    pub torque: f64,
    pub reverse_phase: bool,
    pub output_mode: u8,
    pub output_constant: f64,
    /// SE, in user units; 0 = off.
    pub following_limit: f64,
    pub deadband: f64,
    /// DT, seconds.
    pub target_delay: f64,
    pub high_limit: f64,
    pub low_limit: f64,
    /// LN/LF mask: 1 hard +, 2 hard −, 4 soft high, 8 soft low.
    pub limits: u8,
    /// LM: hard mode + soft mode × 4 + 128 inverts the hard inputs.
    pub limit_mode: u8,
    /// FN on.
    pub fault_check: bool,
    /// EE.
    pub encoder_check: u8,
    /// ES: steps per encoder count (closed-loop steppers).
    pub steps_per_count: f64,
    /// IM: 0 open loop, 1 closed loop, 128 open loop with PID changes.
    pub input_mode: u8,
    pub speed: Speed,
    pub full_current: bool,
    pub backlash: f64,
    pub backlash_on: bool,
    pub slave_ratio: f64,
    pub vector_velocity: f64,
    pub vector_acceleration: f64,
    pub vector_deceleration: f64,
    /// Units asked for by US/UR/UO/UZ; [`super::Axis::units`] are the ones
    /// in force (applied at MN, or at once while the motor is off).
    pub units: Units,
}

/// Servo defaults (the manual's own example values where it has them:
/// SV 100000, SA/DS 200000 from Ch5 DS; SG .04, SD .2 from Ch5 SG; SE 1024
/// from Ch5 SE; DB 5 from Ch5 DB; the 4 kHz loop from FR's default period
/// of 0.00025 s).
pub const SERVO_VELOCITY: f64 = 100_000.0;
pub const SERVO_ACCELERATION: f64 = 200_000.0;
pub const DEFAULT_GAIN: f64 = 0.04;
pub const DEFAULT_DERIVATIVE_GAIN: f64 = 0.2;
pub const DEFAULT_FOLLOWING_LIMIT: f64 = 1024.0;
pub const DEFAULT_DEADBAND: f64 = 5.0;
pub const DEFAULT_TARGET_DELAY: f64 = 0.01;
/// Stepper defaults: 10000 steps/s, 100000 steps/s², MV 1 % of SV (Ch5
/// MV: "typically between 1% and 10%"), the low pulse range.
pub const STEPPER_VELOCITY: f64 = 10_000.0;
pub const STEPPER_ACCELERATION: f64 = 100_000.0;
pub const STEPPER_MINIMUM_VELOCITY: f64 = 100.0;

impl Settings {
    pub fn factory(kind: AxisKind) -> Settings {
        let (velocity, acceleration, minimum_velocity, speed) = match kind {
            AxisKind::Servo => (SERVO_VELOCITY, SERVO_ACCELERATION, 0.0, Speed::High),
            AxisKind::Stepper => (
                STEPPER_VELOCITY,
                STEPPER_ACCELERATION,
                STEPPER_MINIMUM_VELOCITY,
                Speed::Low,
            ),
        };
        Settings {
            velocity,
            acceleration,
            deceleration: acceleration,
            minimum_velocity,
            velocity_override: 1.0,
            profile: Shape::Trapezoid,
            negative: false,
            proportional_gain: DEFAULT_GAIN,
            derivative_gain: DEFAULT_DERIVATIVE_GAIN,
            integral_gain: 0.0,
            integration_limit: 0.0,
            integral_option: 0,
            derivative_period: 0,
            velocity_gain: 0.0,
            acceleration_gain: 0.0,
            deceleration_gain: 0.0,
            output_deadband: 0.0,
            output_offset: 0.0,
            torque: 10.0,
            reverse_phase: false,
            output_mode: 0,
            output_constant: 1.0,
            following_limit: DEFAULT_FOLLOWING_LIMIT,
            deadband: DEFAULT_DEADBAND,
            target_delay: DEFAULT_TARGET_DELAY,
            high_limit: f64::from(i32::MAX),
            low_limit: f64::from(i32::MIN),
            limits: 0,
            limit_mode: 0,
            fault_check: false,
            encoder_check: 0,
            steps_per_count: 1.0,
            input_mode: 0,
            speed,
            full_current: false,
            backlash: 0.0,
            backlash_on: false,
            slave_ratio: 1.0,
            vector_velocity: velocity,
            vector_acceleration: acceleration,
            vector_deceleration: acceleration,
            units: Units::default(),
        }
    }

    /// LM's reaction to a hard limit (0 off, 1 abrupt, 2 decelerate).
    pub fn hard_limit_action(&self) -> u8 {
        self.limit_mode & 3
    }

    pub fn soft_limit_action(&self) -> u8 {
        (self.limit_mode >> 2) & 3
    }

    /// LM + 128: the hard-limit inputs are active low.
    pub fn hard_limits_inverted(&self) -> bool {
        self.limit_mode & 128 != 0
    }
}

/// LM takes a hard mode 0–2 plus a soft mode 0, 4 or 8, plus 128 (Ch5 LM).
pub fn limit_mode_is_valid(n: i64) -> bool {
    (0..=255).contains(&n) && n & 3 != 3 && (n >> 2) & 3 != 3 && n & 0x70 == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_convert_both_ways() {
        // Ch5 US: 1000 counts per inch; UO 12.25, UZ 1.25 (Ch5 UZ example).
        let units = Units {
            scale: 1000.0,
            rate: 60.0,
            offset: 12.25,
            zero: 1.25,
        };
        assert_eq!(units.to_counts(2.5), 16_000.0);
        assert_eq!(units.to_user(16_000.0), 2.5);
        assert_eq!(units.speed_to_counts(60.0), 1000.0, "60 in/min = 1000 c/s");
        assert_eq!(units.acceleration_to_counts(3600.0), 1000.0);
        assert_eq!(units.speed_to_user(1000.0), 60.0);
    }

    #[test]
    fn limit_modes_are_the_sums_the_manual_allows() {
        for n in [0, 1, 2, 4, 8, 10, 128, 130, 136] {
            assert!(limit_mode_is_valid(n), "{n}");
        }
        for n in [3, 12, 16, 64, 131, 140, -1] {
            assert!(!limit_mode_is_valid(n), "{n}");
        }
    }
}
