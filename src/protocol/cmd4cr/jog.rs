//! Jogging a CMD-4CR axis: the axis's high speed `HSPD[axis]` (which the
//! jog writes), an absolute move `ABS` + `X[p]` to the step's target
//! (§2.2.4, §2.3.1: the step leaves the module in absolute mode), `J[axis]+`
//! / `J[axis]-` to run (§2.2.2), `STOP[axis]` to ramp down and stop
//! (§2.2.3). Speeds in pps, up to §1.2's 6.55 Mpps; positions are 28-bit
//! (§1.2: −134,217,728 to +134,217,727).

use crate::protocol::console::AxisInfo;
use crate::protocol::jog::{Direction, JogError, JogPlan, speed_within, target_within};

/// §1.2's speed range, pps.
const SPEEDS: std::ops::RangeInclusive<i64> = 1..=6_553_500;
/// §1.2's position range.
const POSITIONS: std::ops::RangeInclusive<i64> = -134_217_728..=134_217_727;

pub struct Cmd4crJog;

impl JogPlan for Cmd4crJog {
    fn step(
        &self,
        axis: &AxisInfo,
        standing_at: i64,
        distance: i64,
        speed: i64,
    ) -> Result<Vec<String>, JogError> {
        let speed = speed_within(speed, SPEEDS)?;
        let target = target_within(standing_at, distance, POSITIONS)?;
        let a = axis.name;
        Ok(vec![
            format!("HSPD{a}={speed}"),
            "ABS".to_string(),
            format!("{a}{target}"),
        ])
    }

    fn run(
        &self,
        axis: &AxisInfo,
        direction: Direction,
        speed: i64,
    ) -> Result<Vec<String>, JogError> {
        let speed = speed_within(speed, SPEEDS)?;
        let a = axis.name;
        Ok(vec![
            format!("HSPD{a}={speed}"),
            format!("J{a}{}", direction.sign()),
        ])
    }

    fn stop(&self, axis: &AxisInfo) -> Vec<String> {
        vec![format!("STOP{}", axis.name)]
    }

    /// A limit stop is a latched error flag until cleared: `CLR[axis]`
    /// (§2.6.2.3: "Clears limit, alarm, EMG, SD-stop and StepNLoop error
    /// flags"); until then a move answers `?Error Moving`.
    fn clear_limit_stop(&self, axis: &AxisInfo) -> Vec<String> {
        vec![format!("CLR{}", axis.name)]
    }

    fn speeds(&self) -> &'static [i64] {
        &[100, 500, 1_000, 5_000, 10_000, 50_000]
    }

    fn speed_unit(&self) -> &'static str {
        "pps"
    }

    fn side_effects(&self) -> &'static str {
        "a jog writes its speed to HSPD of the axis; a step sets ABS mode"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const Y: AxisInfo = AxisInfo {
        number: 1,
        name: "Y",
    };

    #[test]
    fn lines_are_the_manuals_commands() {
        assert_eq!(
            Cmd4crJog.step(&Y, 500, 1000, 2000).expect("a step"),
            ["HSPDY=2000", "ABS", "Y1500"]
        );
        assert_eq!(
            Cmd4crJog.run(&Y, Direction::Negative, 800).expect("a run"),
            ["HSPDY=800", "JY-"]
        );
        assert_eq!(Cmd4crJog.stop(&Y), ["STOPY"]);
        assert!(Cmd4crJog.step(&Y, 134_217_727, 1, 100).is_err());
    }
}
