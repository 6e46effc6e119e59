//! Unit conversions of manual §6.1: TMC429 internal velocity and
//! acceleration units ↔ microsteps per second (pps), pps², full steps, rps
//! and rpm.

/// The TMC429 motion controller clock in the §6.1 formulas (16·10⁶).
pub const CLOCK_HZ: f64 = 16.0e6;

/// Largest magnitude of an internal velocity or acceleration value (§6.1.1).
pub const MAX_INTERNAL: i32 = 2047;

/// §6.1.1 equation (1): internal velocity → microsteps per second.
/// `pulse_div` is axis parameter 154 (0..13).
pub fn velocity_to_pps(velocity_int: i32, pulse_div: u8) -> f64 {
    CLOCK_HZ * f64::from(velocity_int) / (pow2(i32::from(pulse_div)) * 2048.0 * 32.0)
}

/// Inverse of [`velocity_to_pps`], rounded to the nearest internal unit and
/// clamped to ±2047.
pub fn pps_to_velocity(pps: f64, pulse_div: u8) -> i32 {
    let raw = pps * pow2(i32::from(pulse_div)) * 2048.0 * 32.0 / CLOCK_HZ;
    clamp_internal(raw)
}

/// §6.1.2 equation (3): internal acceleration → microsteps per second².
/// `ramp_div` is axis parameter 153, `pulse_div` axis parameter 154.
pub fn acceleration_to_pps2(accel_int: i32, ramp_div: u8, pulse_div: u8) -> f64 {
    CLOCK_HZ * CLOCK_HZ * f64::from(accel_int)
        / pow2(i32::from(ramp_div) + i32::from(pulse_div) + 29)
}

/// Inverse of [`acceleration_to_pps2`], rounded and clamped to ±2047.
pub fn pps2_to_acceleration(pps2: f64, ramp_div: u8, pulse_div: u8) -> i32 {
    let raw = pps2 * pow2(i32::from(ramp_div) + i32::from(pulse_div) + 29) / (CLOCK_HZ * CLOCK_HZ);
    clamp_internal(raw)
}

/// §6.1.3: the acceleration values usable for positioning ramps (MVP) with
/// the given divisors, as (lower, upper) internal units. Velocity mode is not
/// limited by this window. The lower limit may be a fraction (e.g. 0.25)
/// when the ramp divisor is below the pulse divisor.
pub fn positioning_acceleration_window(ramp_div: u8, pulse_div: u8) -> (f64, f64) {
    let diff = i32::from(ramp_div) - i32::from(pulse_div);
    let lower = pow2(diff - 1);
    let upper = (pow2(diff + 12) - 1.0).min(f64::from(MAX_INTERNAL));
    (lower, upper)
}

/// §6.1.1 equation (2): microstep frequency → full-step frequency, with
/// axis parameter 140 (microstep resolution exponent, 0..8).
pub fn pps_to_fullsteps(pps: f64, microstep_resolution: u8) -> f64 {
    pps / pow2(i32::from(microstep_resolution))
}

/// §6.1.4: microsteps per second → revolutions per second, for a motor of
/// `fullsteps_per_rev` full steps (200 for most 1.8° motors).
pub fn pps_to_rps(pps: f64, fullsteps_per_rev: u32, microstep_resolution: u8) -> f64 {
    pps / (f64::from(fullsteps_per_rev) * pow2(i32::from(microstep_resolution)))
}

/// §6.1.4: microsteps per second → revolutions per minute.
pub fn pps_to_rpm(pps: f64, fullsteps_per_rev: u32, microstep_resolution: u8) -> f64 {
    pps_to_rps(pps, fullsteps_per_rev, microstep_resolution) * 60.0
}

/// §6.1.4 inverse: revolutions per minute → microsteps per second.
pub fn rpm_to_pps(rpm: f64, fullsteps_per_rev: u32, microstep_resolution: u8) -> f64 {
    rpm / 60.0 * f64::from(fullsteps_per_rev) * pow2(i32::from(microstep_resolution))
}

/// Axis parameters the §6.1 conversions read (§4 Table 16).
const MICROSTEP_RESOLUTION: u16 = 140;
const RAMP_DIVISOR: u16 = 153;
const PULSE_DIVISOR: u16 = 154;

/// The TMCM-1110's unit law for the axis's own units: positions are
/// microsteps (§4 AP1), speeds and accelerations internal units of §6.1
/// under the axis's divisors, and the microsteps per full step are AP140
/// (2^n, §4; §6.1.4).
use crate::protocol::units::{UnitError, UnitRefusal};

#[derive(Debug, Clone, Copy, Default)]
pub struct TmclUnits;

fn setting(
    value_of: &crate::protocol::units::ValueOf,
    axis: u8,
    number: u16,
    name: &str,
    max: i64,
) -> Result<u8, UnitError> {
    let value =
        value_of(crate::protocol::parameters::Scope::Axis(axis), number).ok_or_else(|| {
            UnitError::new(
                UnitRefusal::NeedsReading,
                format!("needs the {name} (AP{number}) of motor {axis}, not known"),
            )
        })?;
    u8::try_from(value)
        .ok()
        .filter(|v| i64::from(*v) <= max)
        .ok_or_else(|| {
            UnitError::new(
                UnitRefusal::OutOfRange,
                format!("the {name} (AP{number}) reads {value}, outside 0..{max}"),
            )
        })
}

impl crate::protocol::units::UnitLaw for TmclUnits {
    fn inputs(&self, axis: u8) -> Vec<(crate::protocol::parameters::Scope, u16)> {
        let scope = crate::protocol::parameters::Scope::Axis(axis);
        [MICROSTEP_RESOLUTION, RAMP_DIVISOR, PULSE_DIVISOR]
            .map(|n| (scope, n))
            .to_vec()
    }

    fn steps_per_raw(
        &self,
        axis: u8,
        quantity: crate::protocol::units::Quantity,
        value_of: &crate::protocol::units::ValueOf,
    ) -> Result<f64, UnitError> {
        use crate::protocol::units::Quantity;
        Ok(match quantity {
            Quantity::Position => 1.0,
            Quantity::Speed => {
                let pulse = setting(value_of, axis, PULSE_DIVISOR, "pulse divisor", 13)?;
                velocity_to_pps(1, pulse)
            }
            Quantity::Acceleration => {
                let pulse = setting(value_of, axis, PULSE_DIVISOR, "pulse divisor", 13)?;
                let ramp = setting(value_of, axis, RAMP_DIVISOR, "ramp divisor", 13)?;
                acceleration_to_pps2(1, ramp, pulse)
            }
        })
    }

    fn microsteps(
        &self,
        axis: u8,
        value_of: &crate::protocol::units::ValueOf,
    ) -> Option<Result<u32, UnitError>> {
        let scope = crate::protocol::parameters::Scope::Axis(axis);
        // Not read (an offline file without it): the mechanics say.
        value_of(scope, MICROSTEP_RESOLUTION)?;
        Some(
            setting(
                value_of,
                axis,
                MICROSTEP_RESOLUTION,
                "microstep resolution",
                8,
            )
            .map(|n| 1u32 << n),
        )
    }

    fn row_quantity(
        &self,
        row: &crate::protocol::parameters::ParamRow,
    ) -> Option<crate::protocol::units::Quantity> {
        use super::params::{Unit, axis_param};
        use crate::protocol::units::Quantity;
        if !matches!(row.scope, crate::protocol::parameters::Scope::Axis(_)) {
            return None;
        }
        match axis_param(u8::try_from(row.number).ok()?)?.unit {
            Unit::Microsteps => Some(Quantity::Position),
            Unit::VelocityInternal => Some(Quantity::Speed),
            Unit::AccelerationInternal => Some(Quantity::Acceleration),
            _ => None,
        }
    }

    fn operands(&self, line: &str) -> Vec<crate::protocol::units::Operand> {
        use super::params::{Unit, axis_param, axis_param_by_name};
        use crate::protocol::units::{Operand, Quantity, split_operands};
        let (Some(head), operands) = split_operands(line) else {
            return Vec::new();
        };
        let motor = |index: usize| -> Option<u8> {
            operands.get(index).and_then(|(_, t)| t.parse::<u8>().ok())
        };
        let at = |index: usize, axis: u8, quantity| {
            operands.get(index).map(|(span, _)| Operand {
                span: span.clone(),
                axis,
                quantity,
            })
        };
        let found = match head.to_ascii_uppercase().as_str() {
            // §3.6.4: MVP ABS|REL, motor, position (COORD takes a
            // coordinate number, not a position).
            "MVP" => match operands.first().map(|(_, t)| t.to_ascii_uppercase()) {
                Some(t) if matches!(t.as_str(), "ABS" | "REL" | "0" | "1") => {
                    motor(1).and_then(|m| at(2, m, Quantity::Position))
                }
                _ => None,
            },
            // §3.6.1, §3.6.2: ROR/ROL motor, velocity [int].
            "ROR" | "ROL" => motor(0).and_then(|m| at(1, m, Quantity::Speed)),
            // §3.6.5: SAP param, motor, value, in the parameter's unit.
            "SAP" => {
                let info = operands.first().and_then(|(_, t)| {
                    t.parse::<u8>()
                        .ok()
                        .and_then(axis_param)
                        .or_else(|| axis_param_by_name(t))
                });
                let quantity = info.and_then(|i| match i.unit {
                    Unit::Microsteps => Some(Quantity::Position),
                    Unit::VelocityInternal => Some(Quantity::Speed),
                    Unit::AccelerationInternal => Some(Quantity::Acceleration),
                    _ => None,
                });
                quantity.and_then(|q| motor(1).and_then(|m| at(2, m, q)))
            }
            _ => None,
        };
        found.into_iter().collect()
    }
}

fn pow2(exponent: i32) -> f64 {
    2f64.powi(exponent)
}

fn clamp_internal(raw: f64) -> i32 {
    let limit = f64::from(MAX_INTERNAL);
    raw.round().clamp(-limit, limit) as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tolerance: f64) -> bool {
        (a - b).abs() <= tolerance
    }

    #[test]
    fn velocity_example_of_6_1_1() {
        // "a velocity value of 1678 and a pulse divisor of 3 … approximately 51208.5pps"
        let pps = velocity_to_pps(1678, 3);
        assert!(close(pps, 51208.5, 0.1), "{pps}");
        assert_eq!(pps_to_velocity(pps, 3), 1678);
        assert_eq!(pps_to_velocity(51200.0, 3), 1678);
    }

    #[test]
    fn acceleration_example_of_6_1_2() {
        // "an acceleration value of 100 … ramp divisor of 7 … pulse divisor of 3
        // … approximately 46566pps²"
        let pps2 = acceleration_to_pps2(100, 7, 3);
        assert!(close(pps2, 46566.0, 1.0), "{pps2}");
        assert_eq!(pps2_to_acceleration(pps2, 7, 3), 100);
    }

    #[test]
    fn rpm_example_of_6_1_4() {
        // "a 200 fullsteps motor and a microstep setting of 256 … 51200pps will
        // result in 1rps (60rpm)"
        assert!(close(pps_to_rps(51200.0, 200, 8), 1.0, 1e-12));
        assert!(close(pps_to_rpm(51200.0, 200, 8), 60.0, 1e-9));
        assert!(close(rpm_to_pps(60.0, 200, 8), 51200.0, 1e-9));
        assert!(close(pps_to_fullsteps(51200.0, 8), 200.0, 1e-12));
    }

    #[test]
    fn acceleration_window_of_6_1_3() {
        // rd = pd: 2^-1 .. 2^12 − 1 = 4095, capped at 2047.
        assert_eq!(positioning_acceleration_window(3, 3), (0.5, 2047.0));
        // rd − pd = 4: 8 .. capped.
        assert_eq!(positioning_acceleration_window(7, 3), (8.0, 2047.0));
        // rd − pd = −3: 1/16 .. 511.
        assert_eq!(positioning_acceleration_window(0, 3), (0.0625, 511.0));
    }

    fn divisors(scope: crate::protocol::parameters::Scope, n: u16) -> Option<i64> {
        assert_eq!(scope, crate::protocol::parameters::Scope::Axis(0));
        match n {
            PULSE_DIVISOR => Some(3),
            RAMP_DIVISOR => Some(7),
            MICROSTEP_RESOLUTION => Some(8),
            _ => None,
        }
    }

    fn mechanics(text: &str) -> crate::protocol::units::MechanicsTable {
        let value: toml::Table = text.parse().expect("toml");
        let (table, problems) =
            crate::protocol::units::MechanicsTable::from_toml(&value["mechanics"]);
        assert!(problems.is_empty(), "{problems:?}");
        table
    }

    /// One motor revolution per unit: a unit is 200 × 256 = 51200 µsteps.
    const ONE_REV_PER_UNIT: &str = "[mechanics.0]\nunit = \"rev\"\nfull_steps_per_rev = 200\n\
        travel_per_rev = 1\n";

    #[test]
    fn the_law_gives_the_manual_numbers_of_6_1() {
        use crate::protocol::units::{Quantity, UnitLaw, to_units};
        let m = mechanics(ONE_REV_PER_UNIT);
        let m = m.get(0).expect("axis 0");
        // §6.1.1: 1678 [int] at pulse divisor 3 is about 51208.5 pps,
        // §6.1.4: 51200 pps of a 200-step motor at 256 µsteps is 1 rps.
        let rps = to_units(&TmclUnits, m, 0, Quantity::Speed, 1678.0, &divisors).expect("known");
        assert!(close(rps * 51200.0, 51208.5, 0.1), "{rps}");
        // §6.1.2: 100 [int] at ramp divisor 7, pulse divisor 3 ≈ 46566 pps².
        let per_s2 =
            to_units(&TmclUnits, m, 0, Quantity::Acceleration, 100.0, &divisors).expect("known");
        assert!(close(per_s2 * 51200.0, 46566.0, 1.0), "{per_s2}");
        assert_eq!(TmclUnits.microsteps(0, &divisors), Some(Ok(256)));
    }

    #[test]
    fn unit_values_of_a_line_become_raw_numbers() {
        use crate::protocol::units::convert_line;
        let m = mechanics(
            "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\nmicrosteps = 256\n\
             travel_per_rev = 5\n",
        );
        let none = |_: crate::protocol::parameters::Scope, _: u16| None;
        // The example: 10 mm at 5 mm a turn of 200 × 256 µsteps.
        let c = convert_line(Some(&TmclUnits), "MVP ABS, 0, 10mm", &m, &none).expect("converts");
        assert_eq!(c.line, "MVP ABS, 0, 102400");
        assert_eq!(c.notes, ["10mm → 102400"]);
        // A speed needs the pulse divisor: 51208.5 pps is 1678 [int] (§6.1.1).
        let err = convert_line(Some(&TmclUnits), "SAP 4, 0, 20mm/s", &m, &none).unwrap_err();
        assert!(err.message.contains("pulse divisor (AP154)"), "{err}");
        let mm_s = 51208.5 / 10240.0;
        let c = convert_line(
            Some(&TmclUnits),
            &format!("SAP 4, 0, {mm_s}mm/s"),
            &m,
            &divisors,
        )
        .expect("converts");
        assert_eq!(c.line, "SAP 4, 0, 1678");
        // §6.1.2: 46566 pps² is 100 [int] at divisors 7 and 3.
        let c = convert_line(
            Some(&TmclUnits),
            &format!("SAP 5, 0, {}mm/s2", 46566.0 / 10240.0),
            &m,
            &divisors,
        )
        .expect("converts");
        assert_eq!(c.line, "SAP 5, 0, 100");
        // A speed where a position goes, another unit, no mechanics.
        let err = convert_line(Some(&TmclUnits), "MVP REL, 0, 2mm/s", &m, &none).unwrap_err();
        assert!(err.message.contains("takes a position"), "{err}");
        let err = convert_line(Some(&TmclUnits), "MVP REL, 0, 2deg", &m, &none).unwrap_err();
        assert!(err.message.contains("axis 0 is in mm"), "{err}");
        let empty = crate::protocol::units::MechanicsTable::default();
        let err = convert_line(Some(&TmclUnits), "ROL 0, 2mm/s", &empty, &none).unwrap_err();
        assert!(err.message.contains("no mechanics"), "{err}");
        // Plain lines pass as they are.
        let c = convert_line(Some(&TmclUnits), "MVP ABS, 0, 1000", &empty, &none).expect("plain");
        assert!(!c.changed());
    }

    #[test]
    fn inverse_conversions_clamp_to_the_internal_range() {
        assert_eq!(pps_to_velocity(1.0e9, 0), 2047);
        assert_eq!(pps_to_velocity(-1.0e9, 0), -2047);
        assert_eq!(pps2_to_acceleration(1.0e12, 0, 0), 2047);
    }
}
