//! The simulated motor's StallGuard2 reading (AP206) and CoolStep current
//! regulation (AP168..172, 180, 182, 183): pure laws, no state of the axis.
//!
//! What the manual says, and what the simulator makes of it:
//!
//! - §1.1 / §7.2: "The StallGuard2 measurement value changes linearly over a
//!   wide range of load, velocity, and current settings. At maximum motor
//!   load, the value reaches zero or is near zero." The manual gives no
//!   numbers, only that the value is linear in load and falls to 0 at the
//!   maximum load. The simulator's law ([`reading`]) is therefore a choice:
//!
//!   `AP206 = clamp(round(|v| / 2 × (1 − f)) + 16 × AP174, 0, 1023)`, and 0
//!   once `f ≥ 1` (stalled),
//!
//!   where `v` is the actual speed AP3 in [int] (the unloaded reading grows
//!   with speed, as back-EMF does: |v| / 2 spans 0..1023 over 0..2047, and
//!   the default positioning speed 1000 reads 500) and `f` is the load as a
//!   fraction of the torque available at the actual current (`LOAD=` percent
//!   of the torque at the AP6 current, scaled by (CS₆ + 1) / (CS + 1) when
//!   the actual current scale CS differs, torque being taken proportional to
//!   current). So the reading is higher at higher speed, lower under more
//!   load and less current, and 0 at a stall.
//! - §4 AP174: "controls StallGuard2 threshold level for stall output and
//!   sets the optimum measurement range for readout. A lower value gives a
//!   higher sensitivity. […] A higher value makes StallGuard2 less sensitive
//!   and requires more torque to indicate a stall." The simulator reads this
//!   as an offset of the readout, [`THRESHOLD_STEP`] = 16 counts per step
//!   (the step size is our choice; ±64 steps cover the whole 0..1023): a
//!   negative AP174 makes the reading reach 0 before the motor stalls, a
//!   positive one lifts it, but a stalled motor reads 0 whatever AP174.
//!   Equivalently, the threshold is the unshifted reading `−16 × AP174`, and
//!   AP208 bit 0 ("StallGuard2 status, 1: threshold reached") is set while
//!   the motor turns and the (shifted) reading is 0.
//! - §4 AP181 / §7.3 Table 25: "Above this speed motor will stop in case
//!   StallGuard2 load value reaches zero." (the axis does this with the
//!   reading above).
//! - §4 AP168..172, 180, 182, 183 and §7.3: CoolStep, see [`CoolStep`].
//!
//! Not simulated: the filter AP173 (kept, no effect), measurement noise, and
//! the dependence on microstep resolution and pulse divisor (the law is in
//! [int] velocity units).

/// Largest StallGuard2 reading (§4 AP206: 0..1023).
pub const MAX_READING: i32 = 1023;

/// Readout counts one step of AP174 shifts the reading by (our choice).
pub const THRESHOLD_STEP: i32 = 16;

/// §7.3 Table 25, AP6: "0..255 divided by eight": the current scale CS,
/// 0..31, of a current setting 0..255 (AP6, AP183).
pub fn current_scale(setting: i32) -> i32 {
    setting.clamp(0, 255) / 8
}

/// The load as a fraction of the torque available at current scale
/// `actual_scale`, for a load of `load_percent` % of the torque at the set
/// current scale `set_scale` (torque taken proportional to (CS + 1) / 32).
pub fn torque_fraction(load_percent: u8, set_scale: i32, actual_scale: i32) -> f64 {
    let set = f64::from(set_scale.clamp(0, 31) + 1);
    let actual = f64::from(actual_scale.clamp(0, 31) + 1);
    f64::from(load_percent.min(100)) / 100.0 * set / actual
}

/// The motor stalls once the load needs all the torque there is.
pub fn stalled(fraction: f64) -> bool {
    fraction >= 1.0
}

/// The StallGuard2 reading (AP206) at actual speed `velocity` [int], load
/// `fraction` of the available torque and threshold `ap174` (module docs).
pub fn reading(velocity: i32, fraction: f64, ap174: i32) -> i32 {
    if stalled(fraction) {
        return 0;
    }
    let unloaded = f64::from(velocity.unsigned_abs().min(2047)) / 2.0;
    let raw = (unloaded * (1.0 - fraction.max(0.0))).round() as i32;
    (raw + THRESHOLD_STEP * ap174.clamp(-64, 63)).clamp(0, MAX_READING)
}

/// The CoolStep settings of §4 (AP168..172) and the current limits they
/// give, read from the axis parameters.
///
/// - AP172 "SmartEnergy hysteresis start": the lower threshold; 0 turns
///   CoolStep off. Its scale is not printed in the AP172 row; the AP170 row
///   counts in 32s, so the simulator takes lower = 32 × AP172.
/// - AP170 "SmartEnergy hysteresis": the distance to the upper threshold.
///   The manual's row prints "Hysteresis: ([AP172] + 1) * 32, Upper
///   StallGuard threshold: ([AP172] + 1) * 32", naming AP172 in both; read
///   as the distance (AP170 + 1) × 32, so upper = lower + 32 × (AP170 + 1).
/// - AP171 "current up step": 0..3 → 1, 2, 4, 8 scale steps per reading
///   below the lower threshold.
/// - AP169 "current down step": 0..3 → 32, 8, 2, 1 readings above the upper
///   threshold per decrement (of one scale step).
/// - AP168 SEIMIN: minimum 1/2 (0) or 1/4 (1) of the AP6 current scale.
/// - AP182: CoolStep works above this speed; below it the motor runs on the
///   slow run current AP183.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CoolStep {
    /// AP6 as current scale CS, 0..31: the upper limit.
    pub max_scale: i32,
    /// AP168's portion of it: the lower limit.
    pub min_scale: i32,
    /// 32 × AP172; 0: CoolStep off.
    pub lower: i32,
    /// lower + 32 × (AP170 + 1).
    pub upper: i32,
    /// Scale steps up per reading below `lower` (AP171).
    pub up_step: i32,
    /// Readings above `upper` per step down (AP169).
    pub readings_per_down_step: u32,
}

impl CoolStep {
    /// From AP6, AP168, AP169, AP170, AP171 and AP172.
    pub fn from_params(
        ap6: i32,
        ap168: i32,
        ap169: i32,
        ap170: i32,
        ap171: i32,
        ap172: i32,
    ) -> Self {
        let max_scale = current_scale(ap6);
        let min_scale = if ap168 == 1 {
            max_scale / 4
        } else {
            max_scale / 2
        };
        let lower = 32 * ap172.clamp(0, 15);
        CoolStep {
            max_scale,
            min_scale,
            lower,
            upper: lower + 32 * (ap170.clamp(0, 15) + 1),
            up_step: 1 << ap171.clamp(0, 3),
            readings_per_down_step: [32, 8, 2, 1][ap169.clamp(0, 3) as usize],
        }
    }

    /// AP172 = 0 turns CoolStep off (§4).
    pub fn enabled(&self) -> bool {
        self.lower > 0
    }

    /// One StallGuard2 measurement: the new current scale and count of
    /// consecutive readings above the upper threshold, from the present
    /// ones. Below the lower threshold the scale rises by the up step (at
    /// most to AP6's); at or above the upper threshold it falls by one every
    /// `readings_per_down_step` readings (at least to the SEIMIN portion);
    /// in between it stays.
    pub fn regulate(&self, scale: i32, above: u32, reading: i32) -> (i32, u32) {
        let scale = scale.clamp(self.min_scale, self.max_scale);
        if reading < self.lower {
            ((scale + self.up_step).min(self.max_scale), 0)
        } else if reading >= self.upper {
            let above = above + 1;
            if above >= self.readings_per_down_step {
                ((scale - 1).max(self.min_scale), 0)
            } else {
                (scale, above)
            }
        } else {
            (scale, 0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reading_falls_linearly_with_load_and_rises_with_speed() {
        assert_eq!(reading(1000, 0.0, 0), 500);
        assert_eq!(reading(-1000, 0.0, 0), 500, "either direction");
        assert_eq!(reading(1000, 0.6, 0), 200);
        assert_eq!(reading(1000, 0.3, 0), 350, "halfway: linear");
        assert_eq!(reading(2000, 0.6, 0), 400, "faster reads higher");
        assert_eq!(
            reading(2047, 0.0, 0),
            MAX_READING,
            "1023.5 rounds up, clamped"
        );
        assert_eq!(reading(1000, 1.0, 0), 0, "stalled");
        assert_eq!(reading(1000, 1.0, 63), 0, "stalled whatever AP174");
        // AP174 shifts the readout: lower is more sensitive.
        assert_eq!(reading(1000, 0.6, -10), 40);
        assert_eq!(reading(1000, 0.6, -13), 0, "reaches 0 before the stall");
        assert_eq!(reading(1000, 0.6, 2), 232);
    }

    #[test]
    fn less_current_leaves_less_torque() {
        assert_eq!(torque_fraction(60, 15, 15), 0.6);
        assert_eq!(torque_fraction(50, 15, 7), 1.0, "half the current");
        assert!(stalled(torque_fraction(50, 15, 7)));
        assert!(!stalled(torque_fraction(99, 15, 15)));
        assert_eq!(current_scale(128), 16);
        assert_eq!(current_scale(255), 31);
        assert_eq!(current_scale(7), 0, "step 0 = 0..7");
    }

    #[test]
    fn coolstep_limits_and_steps_follow_the_parameters() {
        // AP6 128 → CS 16; SEIMIN 0 → 8; AP172 2 → 64; AP170 3 → 64 + 128.
        let cs = CoolStep::from_params(128, 0, 3, 3, 1, 2);
        assert_eq!((cs.max_scale, cs.min_scale), (16, 8));
        assert_eq!((cs.lower, cs.upper), (64, 192));
        assert_eq!((cs.up_step, cs.readings_per_down_step), (2, 1));
        assert!(cs.enabled());
        assert_eq!(CoolStep::from_params(128, 1, 0, 0, 3, 2).min_scale, 4);
        assert_eq!(CoolStep::from_params(128, 1, 0, 0, 3, 2).up_step, 8);
        assert!(!CoolStep::from_params(128, 0, 0, 0, 0, 0).enabled());

        assert_eq!(cs.regulate(10, 0, 63), (12, 0), "below the lower: up");
        assert_eq!(cs.regulate(16, 0, 0), (16, 0), "not above AP6");
        assert_eq!(cs.regulate(10, 0, 100), (10, 0), "in the band: stays");
        assert_eq!(cs.regulate(10, 0, 192), (9, 0), "upper reached: down");
        assert_eq!(cs.regulate(8, 0, 500), (8, 0), "not below SEIMIN");
        // AP169 = 0: 32 readings per step down.
        let slow = CoolStep::from_params(128, 0, 0, 3, 0, 2);
        let mut state = (16, 0);
        for _ in 0..31 {
            state = slow.regulate(state.0, state.1, 500);
        }
        assert_eq!(state, (16, 31));
        assert_eq!(slow.regulate(state.0, state.1, 500), (15, 0));
    }
}
