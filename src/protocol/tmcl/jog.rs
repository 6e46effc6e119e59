//! Jogging a TMCM-1110 axis: `MVP REL` at the maximum positioning speed
//! (axis parameter 4, which the step writes), `ROR`/`ROL` at a velocity,
//! `MST` to stop (TMCL firmware manual §4.2-§4.5; velocities 0..2047 on
//! the TMCM-1110, axis parameter 4's range).

use crate::protocol::console::AxisInfo;
use crate::protocol::jog::{Direction, JogError, JogPlan, speed_within, target_within};

/// The TMCM-1110's velocity range (axis parameters 2 and 4).
const SPEEDS: std::ops::RangeInclusive<i64> = 1..=2047;

pub struct TmclJog;

impl JogPlan for TmclJog {
    fn step(
        &self,
        axis: &AxisInfo,
        _standing_at: i64,
        distance: i64,
        speed: i64,
    ) -> Result<Vec<String>, JogError> {
        let speed = speed_within(speed, SPEEDS)?;
        // MVP REL takes a 32-bit offset (§4.4).
        let distance = target_within(0, distance, i64::from(i32::MIN)..=i64::from(i32::MAX))?;
        let m = axis.number;
        Ok(vec![
            format!("SAP 4, {m}, {speed}"),
            format!("MVP REL, {m}, {distance}"),
        ])
    }

    fn run(
        &self,
        axis: &AxisInfo,
        direction: Direction,
        speed: i64,
    ) -> Result<Vec<String>, JogError> {
        let speed = speed_within(speed, SPEEDS)?;
        let command = match direction {
            Direction::Positive => "ROR",
            Direction::Negative => "ROL",
        };
        Ok(vec![format!("{command} {}, {speed}", axis.number)])
    }

    fn stop(&self, axis: &AxisInfo) -> Vec<String> {
        vec![format!("MST {}", axis.number)]
    }

    fn speeds(&self) -> &'static [i64] {
        &[25, 100, 250, 500, 1000, 2047]
    }

    fn speed_unit(&self) -> &'static str {
        "velocity units"
    }

    fn side_effects(&self) -> &'static str {
        "a step writes its speed to axis parameter 4 (SAP 4)"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MOTOR_0: AxisInfo = AxisInfo {
        number: 0,
        name: "motor 0",
    };

    #[test]
    fn lines_are_the_manuals_commands() {
        assert_eq!(
            TmclJog.step(&MOTOR_0, 0, -500, 300).expect("a step"),
            ["SAP 4, 0, 300", "MVP REL, 0, -500"]
        );
        assert_eq!(
            TmclJog
                .run(&MOTOR_0, Direction::Negative, 100)
                .expect("a run"),
            ["ROL 0, 100"]
        );
        assert_eq!(TmclJog.stop(&MOTOR_0), ["MST 0"]);
        assert!(TmclJog.run(&MOTOR_0, Direction::Positive, 2048).is_err());
    }
}
