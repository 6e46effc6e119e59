//! Jogging a SIXpack 2 motor: `StartRamp` to a target at the motor's own
//! vmax ($23, §7.2: the step changes no setting), `ConstantRotation` at a
//! velocity −511..511 and `ConstantRotation m 0` to decelerate and stop
//! ($25, §7.2).

use crate::protocol::console::AxisInfo;
use crate::protocol::jog::{Direction, JogError, JogPlan, speed_within, target_within};

/// $25's velocity range (§7.2).
const SPEEDS: std::ops::RangeInclusive<i64> = 1..=511;

pub struct Sixpack2Jog;

impl JogPlan for Sixpack2Jog {
    fn step(
        &self,
        axis: &AxisInfo,
        standing_at: i64,
        distance: i64,
        _speed: i64,
    ) -> Result<Vec<String>, JogError> {
        // $23's target is a signed long (§7.2).
        let target = target_within(
            standing_at,
            distance,
            i64::from(i32::MIN)..=i64::from(i32::MAX),
        )?;
        Ok(vec![format!("StartRamp {} {target}", axis.number)])
    }

    fn run(
        &self,
        axis: &AxisInfo,
        direction: Direction,
        speed: i64,
    ) -> Result<Vec<String>, JogError> {
        let speed = direction.signed(speed_within(speed, SPEEDS)?);
        Ok(vec![format!("ConstantRotation {} {speed}", axis.number)])
    }

    fn stop(&self, axis: &AxisInfo) -> Vec<String> {
        vec![format!("ConstantRotation {} 0", axis.number)]
    }

    fn speeds(&self) -> &'static [i64] {
        &[10, 25, 50, 100, 250, 511]
    }

    fn speed_unit(&self) -> &'static str {
        "velocity units"
    }

    fn side_effects(&self) -> &'static str {
        "a step ramps at the motor's own vmax ($14), not the jog speed"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const M2: AxisInfo = AxisInfo {
        number: 2,
        name: "m2/Motor3",
    };

    #[test]
    fn lines_are_the_manuals_commands() {
        assert_eq!(
            Sixpack2Jog.step(&M2, 1000, -300, 50).expect("a step"),
            ["StartRamp 2 700"]
        );
        assert_eq!(
            Sixpack2Jog
                .run(&M2, Direction::Negative, 100)
                .expect("a run"),
            ["ConstantRotation 2 -100"]
        );
        assert_eq!(Sixpack2Jog.stop(&M2), ["ConstantRotation 2 0"]);
        assert!(Sixpack2Jog.run(&M2, Direction::Positive, 512).is_err());
        assert!(Sixpack2Jog.step(&M2, i64::from(i32::MAX), 1, 50).is_err());
    }
}
