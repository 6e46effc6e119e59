//! Jogging a MultiFlex axis: a step is position mode `PM`, the maximum
//! velocity `SV` (which the jog writes) and a move absolute `MA` to the
//! step's target (Ch.3: MR adds to the target, which a stopped velocity
//! move may have left elsewhere); a run is velocity mode `VM`, `DI` for
//! the direction, `SV` and `GO`; `ST` stops, decelerating at DS. The
//! motor is not switched on (MN) by a jog: with the motor off MA only
//! moves the target, as the manual says.

use crate::protocol::console::{AxisFlag, AxisInfo};
use crate::protocol::jog::{Direction, JogError, JogPlan, speed_within, target_within};
use crate::protocol::mccl::console::MOTOR_ON_LAMP;

/// SV takes any velocity ≥ 0 (counts/s); the jog keeps to a 32-bit one.
const SPEEDS: std::ops::RangeInclusive<i64> = 1..=i32::MAX as i64;

pub struct McclJog;

impl JogPlan for McclJog {
    fn step(
        &self,
        axis: &AxisInfo,
        standing_at: i64,
        distance: i64,
        speed: i64,
    ) -> Result<Vec<String>, JogError> {
        let speed = speed_within(speed, SPEEDS)?;
        let target = target_within(
            standing_at,
            distance,
            i64::from(i32::MIN)..=i64::from(i32::MAX),
        )?;
        let a = axis.number;
        Ok(vec![format!("{a}PM,{a}SV{speed},{a}MA{target}")])
    }

    fn run(
        &self,
        axis: &AxisInfo,
        direction: Direction,
        speed: i64,
    ) -> Result<Vec<String>, JogError> {
        let speed = speed_within(speed, SPEEDS)?;
        let a = axis.number;
        let di = match direction {
            Direction::Positive => 0,
            Direction::Negative => 1,
        };
        Ok(vec![format!("{a}VM,{a}DI{di},{a}SV{speed},{a}GO")])
    }

    /// With the motor off (TS bit 1 clear) MA only moves the target and
    /// GO turns nothing, without an error: say so before anything is sent.
    fn not_ready(&self, axis: &AxisInfo, lit: &[AxisFlag]) -> Option<String> {
        let on = lit.iter().any(|flag| flag.name == MOTOR_ON_LAMP);
        (!on).then(|| {
            format!(
                "{}'s motor is off; {}MN switches it on (TS bit 1: a jog would turn nothing)",
                axis.name, axis.number
            )
        })
    }

    fn stop(&self, axis: &AxisInfo) -> Vec<String> {
        vec![format!("{}ST", axis.number)]
    }

    /// A limit trips the axis (a move or wait on it is error -13): `MN`
    /// clears the latched error flags and switches the motor on again.
    fn clear_limit_stop(&self, axis: &AxisInfo) -> Vec<String> {
        vec![format!("{}MN", axis.number)]
    }

    fn speeds(&self) -> &'static [i64] {
        &[100, 1_000, 5_000, 10_000, 50_000, 100_000]
    }

    fn speed_unit(&self) -> &'static str {
        "counts/s"
    }

    fn side_effects(&self) -> &'static str {
        "a jog writes its speed to SV and leaves the axis in PM or VM mode"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const AXIS_2: AxisInfo = AxisInfo {
        number: 2,
        name: "2",
    };

    #[test]
    fn lines_are_the_manuals_commands() {
        assert_eq!(
            McclJog.step(&AXIS_2, 100, 50, 2000).expect("a step"),
            ["2PM,2SV2000,2MA150"]
        );
        assert_eq!(
            McclJog
                .run(&AXIS_2, Direction::Negative, 500)
                .expect("a run"),
            ["2VM,2DI1,2SV500,2GO"]
        );
        assert_eq!(McclJog.stop(&AXIS_2), ["2ST"]);
    }
}
