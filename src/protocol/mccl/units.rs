//! MCCL's unit law: the MultiFlex has user units of its own (Ch5): `US`
//! encoder counts (steps) per user unit and `UR` seconds per user time
//! unit, so a position is US counts, a speed US/UR counts per second and
//! an acceleration US/UR² counts per second² (digest §14, derived from the
//! definitions). With the power-up defaults (US 1, UR 1) the raw values
//! are counts. The values typed are reals: a converted one keeps its
//! fraction.

use super::parameter_set::user_setting_row;
use crate::protocol::parameters::Scope;
use crate::protocol::units::{Operand, Quantity, UnitError, UnitLaw, UnitRefusal, ValueOf};

/// Commands whose parameter is an axis's position, speed or acceleration
/// (Ch5 setup, Ch7 motion).
const COMMANDS: &[(&str, Quantity)] = &[
    ("MA", Quantity::Position),
    ("MR", Quantity::Position),
    ("DH", Quantity::Position),
    ("SV", Quantity::Speed),
    ("MV", Quantity::Speed),
    ("SA", Quantity::Acceleration),
    ("DS", Quantity::Acceleration),
];

#[derive(Debug, Clone, Copy, Default)]
pub struct MclUnits;

impl UnitLaw for MclUnits {
    fn inputs(&self, axis: u8) -> Vec<(Scope, u16)> {
        ["US", "UR", "UO", "UZ"]
            .iter()
            .filter_map(|c| user_setting_row(c))
            .map(|(number, _)| (Scope::Axis(axis), number))
            .collect()
    }

    fn steps_per_raw(
        &self,
        axis: u8,
        quantity: Quantity,
        value_of: &ValueOf,
    ) -> Result<f64, UnitError> {
        let read = |command: &str| -> Result<f64, UnitError> {
            let (number, scale) = user_setting_row(command).ok_or_else(|| {
                UnitError::new(UnitRefusal::NotConvertible, format!("no setting {command}"))
            })?;
            let value = value_of(Scope::Axis(axis), number).ok_or_else(|| {
                UnitError::new(
                    UnitRefusal::NeedsReading,
                    format!("needs the user scaling {command} of axis {axis}, not known"),
                )
            })?;
            let value = value as f64 / scale;
            if value > 0.0 {
                Ok(value)
            } else {
                Err(UnitError::new(
                    UnitRefusal::NotConvertible,
                    format!("axis {axis}'s {command} is {value}: no conversion (Ch5)"),
                ))
            }
        };
        let scale = read("US")?;
        Ok(match quantity {
            Quantity::Position => {
                // The manual gives no mapping of the user offset and zero
                // (digest §14 [?]): a position is converted only without them.
                for command in ["UO", "UZ"] {
                    let set = user_setting_row(command)
                        .and_then(|(number, _)| value_of(Scope::Axis(axis), number))
                        .filter(|v| *v != 0);
                    if set.is_some() {
                        return Err(UnitError::new(
                            UnitRefusal::NotConvertible,
                            format!(
                                "axis {axis} has a user {} ({command}) set, and the manual gives \
                                 no mapping of it (Ch5): give the position raw",
                                if command == "UO" { "offset" } else { "zero" }
                            ),
                        ));
                    }
                }
                scale
            }
            Quantity::Speed => scale / read("UR")?,
            Quantity::Acceleration => scale / read("UR")?.powi(2),
        })
    }

    fn operands(&self, line: &str) -> Vec<Operand> {
        // `1MA10mm,WS0.5,MR-2mm`: the axis given last in the line goes on
        // (Ch2: "the axis … is assumed to be the last one specified").
        let mut found = Vec::new();
        let mut axis: Option<u8> = None;
        let mut start = 0;
        for part in line.split(',') {
            let span_start = start;
            start += part.len() + 1;
            let lead = part.len() - part.trim_start().len();
            let text = part.trim();
            let digits = text.bytes().take_while(u8::is_ascii_digit).count();
            if digits > 0 {
                axis = text[..digits].parse().ok();
            }
            let rest = &text[digits..];
            let Some(mnemonic) = rest.get(..2) else {
                continue;
            };
            let Some(&(_, quantity)) = COMMANDS
                .iter()
                .find(|(m, _)| m.eq_ignore_ascii_case(mnemonic))
            else {
                continue;
            };
            let Some(axis) = axis.filter(|a| *a > 0) else {
                continue;
            };
            let value_start = span_start + lead + digits + 2;
            found.push(Operand {
                span: value_start..span_start + lead + text.len(),
                axis,
                quantity,
            });
        }
        found
    }

    fn raw_text(&self, raw: f64) -> String {
        // Ch2: a real has a decimal point; five decimals at most are
        // kept (digest §11), trailing zeros dropped.
        let text = format!("{raw:.5}");
        let text = text.trim_end_matches('0').trim_end_matches('.');
        if text == "-0" {
            "0".into()
        } else {
            text.into()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::units::{MechanicsTable, convert_line};

    fn user(us: f64, ur: f64) -> impl Fn(Scope, u16) -> Option<i64> {
        move |_, number| {
            let (us_row, scale) = user_setting_row("US").expect("US");
            let (ur_row, _) = user_setting_row("UR").expect("UR");
            if number == us_row {
                Some((us * scale) as i64)
            } else if number == ur_row {
                Some((ur * scale) as i64)
            } else {
                None
            }
        }
    }

    fn mechanics() -> MechanicsTable {
        // A servo of 2000 lines (8000 counts) on a rotary axis 1.
        let value: toml::Table = "[mechanics.1]\nunit = \"deg\"\ncounts_per_rev = 8000\n\
                                   travel_per_rev = 360\n"
            .parse()
            .expect("toml");
        MechanicsTable::from_toml(&value["mechanics"]).0
    }

    #[test]
    fn counts_at_the_default_scaling_and_user_units_when_set() {
        let m = mechanics();
        let c = convert_line(Some(&MclUnits), "1MA90deg", &m, &user(1.0, 1.0)).expect("converts");
        assert_eq!(c.line, "1MA2000");
        // Ch5 `3US1000` = 1000 counts per inch: here 8000 counts per turn
        // (US 8000): the user unit is a turn; `UR60` is per minute.
        let c = convert_line(
            Some(&MclUnits),
            "1MA90deg,SV360deg/s,WS0.5,MR-45deg",
            &m,
            &user(8000.0, 60.0),
        )
        .expect("converts");
        assert_eq!(c.line, "1MA0.25,SV60,WS0.5,MR-0.125");
        let offset = |scope: Scope, number: u16| {
            let (uo, _) = user_setting_row("UO").expect("UO");
            if number == uo {
                Some(10_000)
            } else {
                user(1.0, 1.0)(scope, number)
            }
        };
        let err = convert_line(Some(&MclUnits), "1MA90deg", &m, &offset).unwrap_err();
        assert!(err.message.contains("user offset (UO)"), "{err}");
        // A real with an exponent is no unit value (Ch2).
        let c = convert_line(Some(&MclUnits), "1MA1.5E3,SV2e2", &m, &|_, _| None).expect("plain");
        assert!(!c.changed());
        let err = convert_line(Some(&MclUnits), "2MA1deg", &m, &user(1.0, 1.0)).unwrap_err();
        assert!(err.message.contains("axis 2 has no mechanics"), "{err}");
        let err = convert_line(Some(&MclUnits), "1SA1deg/s", &m, &|_, _| None).unwrap_err();
        assert!(err.message.contains("takes an acceleration"), "{err}");
        let err = convert_line(Some(&MclUnits), "1SA1deg/s2", &m, &|_, _| None).unwrap_err();
        assert!(err.message.contains("user scaling US of axis 1"), "{err}");
    }
}
