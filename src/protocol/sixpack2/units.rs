//! The SIXpack 2's unit law (§6.3.1): positions are microsteps, 16 to a
//! full step; a velocity v is a step frequency of
//! `f = 20 MHz / (clkdiv + 1) · v / 2^(14 + div)` with the module-wide
//! ClockDivider (`$12`) and the motor's Div (`$13`); an acceleration
//! amax adds amax/64 to v every 2 ms (§7.1 `$14`, digest D5.2). The
//! module reads none of its settings back (§7): the law takes them from
//! what was written this session.

use super::catalog::{COMMANDS, FieldKind, by_name};
use super::parameter_set::number_of as row_number;
use crate::protocol::parameters::Scope;
use crate::protocol::units::{
    Operand, Quantity, UnitError, UnitLaw, UnitRefusal, ValueOf, split_operands,
};

/// §6.3.1: "f_clk is 20MHz".
pub const CLOCK_HZ: f64 = 20.0e6;
/// §6.3.1: "a fixed micro step frequency of 16 micro steps every full step".
pub const MICROSTEPS: u32 = 16;
/// §7.1 `$14`: "1/64 amax is accumulated with 500Hz".
const AMAX_DIVISOR: f64 = 64.0;
const TICKS_PER_SECOND: f64 = 500.0;

/// `$12` ClockDivider, field 0 (bank 0), and `$13` div, field 3 (per motor).
const CLOCK_DIVIDER: (u8, usize) = (0x12, 0);
const DIV: (u8, usize) = (0x13, 3);

/// §6.3.1: microsteps per second of one velocity unit.
pub fn step_frequency(clkdiv: u8, div: u8) -> f64 {
    CLOCK_HZ / (f64::from(clkdiv) + 1.0) / 2f64.powi(14 + i32::from(div))
}

#[derive(Debug, Clone, Copy, Default)]
pub struct Sixpack2Units;

/// What a field holds, by its unit in the catalogue.
fn field_quantity(field: &super::catalog::Field) -> Option<Quantity> {
    match (field.unit, field.name) {
        ("µsteps", _) => Some(Quantity::Position),
        // vmin runs at div 3 whatever the motor's div (§7.1 $13).
        ("v", name) if name != "vmin" => Some(Quantity::Speed),
        (_, "amax") => Some(Quantity::Acceleration),
        _ => None,
    }
}

fn settings(axis: u8, value_of: &ValueOf) -> Result<(u8, u8), UnitError> {
    let clkdiv = value_of(Scope::Bank(0), row_number(CLOCK_DIVIDER.0, CLOCK_DIVIDER.1))
        .ok_or_else(|| {
            UnitError::new(
                UnitRefusal::NeedsReading,
                "needs the ClockDivider ($12): not written this session (the module reads none \
                 back)",
            )
        })?;
    let div = value_of(Scope::Axis(axis), row_number(DIV.0, DIV.1)).ok_or_else(|| {
        UnitError::new(
            UnitRefusal::NeedsReading,
            format!(
                "needs the div of motor {axis} ($13 SetVMinVStart): not written this session (the \
                 module reads none back)"
            ),
        )
    })?;
    let clkdiv = u8::try_from(clkdiv)
        .ok()
        .filter(|c| *c <= 31)
        .ok_or_else(|| {
            UnitError::new(
                UnitRefusal::OutOfRange,
                format!("the ClockDivider is {clkdiv}, outside 0..31"),
            )
        })?;
    let div = u8::try_from(div).ok().filter(|d| *d <= 3).ok_or_else(|| {
        UnitError::new(
            UnitRefusal::OutOfRange,
            format!("the div of motor {axis} is {div}, outside 0..3"),
        )
    })?;
    Ok((clkdiv, div))
}

impl UnitLaw for Sixpack2Units {
    fn inputs(&self, axis: u8) -> Vec<(Scope, u16)> {
        vec![
            (Scope::Bank(0), row_number(CLOCK_DIVIDER.0, CLOCK_DIVIDER.1)),
            (Scope::Axis(axis), row_number(DIV.0, DIV.1)),
        ]
    }

    fn steps_per_raw(
        &self,
        axis: u8,
        quantity: Quantity,
        value_of: &ValueOf,
    ) -> Result<f64, UnitError> {
        Ok(match quantity {
            Quantity::Position => 1.0,
            Quantity::Speed => {
                let (clkdiv, div) = settings(axis, value_of)?;
                step_frequency(clkdiv, div)
            }
            Quantity::Acceleration => {
                let (clkdiv, div) = settings(axis, value_of)?;
                step_frequency(clkdiv, div) / AMAX_DIVISOR * TICKS_PER_SECOND
            }
        })
    }

    fn microsteps(&self, _axis: u8, _value_of: &ValueOf) -> Option<Result<u32, UnitError>> {
        Some(Ok(MICROSTEPS))
    }

    fn row_quantity(&self, row: &crate::protocol::parameters::ParamRow) -> Option<Quantity> {
        // A row is a command's field (`$14` P3-4 vmax is 0x1402).
        let Scope::Axis(_) = row.scope else {
            return None;
        };
        let spec = super::catalog::by_code(u8::try_from(row.number >> 8).ok()?)?;
        let field = spec.fields.get(usize::from(row.number & 0xFF))?;
        field_quantity(field)
    }

    fn operands(&self, line: &str) -> Vec<Operand> {
        let (Some(head), words) = split_operands(line) else {
            return Vec::new();
        };
        let Some(spec) = by_name(head).filter(|s| COMMANDS.iter().any(|c| c.code == s.code)) else {
            return Vec::new();
        };
        // Operands in field order, or `name=value` (the parser's forms).
        let mut motor = None;
        let mut found = Vec::new();
        for (index, (span, word)) in words.iter().enumerate() {
            let (field, value_start) = match word.split_once('=') {
                Some((name, _)) => (spec.field(name).map(|(_, f)| f), name.len() + 1),
                None => (spec.fields.get(index), 0),
            };
            let Some(field) = field else { continue };
            let span = span.start + value_start..span.end;
            if field.kind == FieldKind::Motor {
                motor = line.get(span.clone()).and_then(|t| t.parse::<u8>().ok());
                continue;
            }
            let Some(quantity) = field_quantity(field) else {
                continue;
            };
            found.push((span, quantity));
        }
        let Some(axis) = motor else {
            return Vec::new();
        };
        found
            .into_iter()
            .map(|(span, quantity)| Operand {
                span,
                axis,
                quantity,
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::units::{MechanicsTable, convert_line};

    fn defaults(scope: Scope, number: u16) -> Option<i64> {
        // §6.2.1.8's default values: clkdiv=5; div=2.
        match (scope, number) {
            (Scope::Bank(0), n) if n == row_number(0x12, 0) => Some(5),
            (Scope::Axis(_), n) if n == row_number(0x13, 3) => Some(2),
            _ => None,
        }
    }

    #[test]
    fn the_parameter_rows_in_motor_steps_are_known_by_their_field() {
        use crate::protocol::parameters::ParameterSet;
        let tables = super::super::parameter_set::Sixpack2Parameters.tables(0);
        let quantity = |number: u16| {
            let row = tables
                .iter()
                .flat_map(|t| t.rows.iter())
                .find(|r| r.scope == Scope::Axis(0) && r.number == number)
                .unwrap_or_else(|| panic!("row {number:#x}"));
            Sixpack2Units.row_quantity(row)
        };
        assert_eq!(quantity(0x1402), Some(Quantity::Speed), "vmax");
        assert_eq!(quantity(0x1401), Some(Quantity::Acceleration), "amax");
        assert_eq!(quantity(0x1302), Some(Quantity::Speed), "vstart");
        assert_eq!(quantity(0x1301), None, "vmin runs at div 3");
        assert_eq!(quantity(0x1303), None, "div");
    }

    #[test]
    fn the_step_frequencies_of_the_manuals_defaults() {
        // §6.2.1.8: "clkdiv=5; div=2; // 26 kHz microstep-frequency"
        // at vmax=511, "vstart=5; // starting with 254 Hz",
        // "vrefmax=100 // … 5086 Hz", "vmin=4 // 102 Hz" (at div 3).
        assert!((step_frequency(5, 2) * 511.0 - 26_000.0).abs() < 50.0);
        assert!((step_frequency(5, 2) * 5.0 - 254.0).abs() < 0.5);
        assert!((step_frequency(5, 2) * 100.0 - 5086.0).abs() < 0.5);
        assert!((step_frequency(5, 3) * 4.0 - 102.0).abs() < 0.5);
        let per_v = Sixpack2Units
            .steps_per_raw(0, Quantity::Speed, &defaults)
            .expect("known");
        assert!((per_v - 50.86).abs() < 0.01, "{per_v}");
    }

    #[test]
    fn a_line_s_unit_values_convert_with_what_was_written() {
        let value: toml::Table = "[mechanics.1]\nunit = \"rev\"\nfull_steps_per_rev = 400\n\
                                   travel_per_rev = 1\n"
            .parse()
            .expect("toml");
        let (m, problems) = MechanicsTable::from_toml(&value["mechanics"]);
        assert!(problems.is_empty(), "{problems:?}");
        // §6.2.1.8: "poslimit=400*16; // 400 full- = 6400 microsteps/revolution".
        let c = convert_line(Some(&Sixpack2Units), "StartRamp 1 2rev", &m, &defaults)
            .expect("converts");
        assert_eq!(c.line, "StartRamp 1 12800");
        // 26 kHz at the defaults is vmax 511: 6400 µsteps a turn.
        let rps = step_frequency(5, 2) * 511.0 / 6400.0;
        let c = convert_line(
            Some(&Sixpack2Units),
            &format!("SetAMaxVMax 1 128 {rps}rev/s"),
            &m,
            &defaults,
        )
        .expect("converts");
        assert_eq!(c.line, "SetAMaxVMax 1 128 511");
        let c = convert_line(
            Some(&Sixpack2Units),
            "ConstantRotation motno=1 velocity=-1rev/s",
            &m,
            &defaults,
        )
        .expect("converts");
        assert_eq!(c.line, "ConstantRotation motno=1 velocity=-126");
        let none = |_: Scope, _: u16| None;
        let err =
            convert_line(Some(&Sixpack2Units), "ConstantRotation 1 1rev/s", &m, &none).unwrap_err();
        assert!(err.message.contains("ClockDivider ($12)"), "{err}");
    }
}
