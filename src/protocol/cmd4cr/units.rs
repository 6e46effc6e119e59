//! The CMD-4CR's unit law: positions are command pulses and speeds pulses
//! per second (pps) as they are (§2.1.4 HSPD/LSPD, §2.2.4 `X1000`, §1.2's
//! 0.1–6,553,500 pps); the driver's microsteps are the driver's, so the
//! mechanics give them. With StepNLoop on, single-axis speeds and P are in
//! encoder counts (§2.5.3): give such an axis `counts_per_rev`. ACC and
//! DEC are ramp times in ms, not accelerations: they take no unit value.

use crate::protocol::parameters::Scope;
use crate::protocol::units::{Operand, Quantity, UnitLaw, ValueOf};

/// §2: the axes X, Y, Z, U are numbered 0..3 in the console.
const AXES: &[u8] = b"XYZU";

/// Settings written `NAMEaxis=value` that take a value in an axis's
/// units (§2.1.4, §2.4.1, §2.6): their quantity.
const SETTINGS: &[(&str, Quantity)] = &[
    ("HSPD", Quantity::Speed),
    ("LSPD", Quantity::Speed),
    ("SSPD", Quantity::Speed),
    ("P", Quantity::Position),
];

#[derive(Debug, Clone, Copy, Default)]
pub struct Cmd4crUnits;

fn axis_of(letter: u8) -> Option<u8> {
    AXES.iter()
        .position(|a| a.eq_ignore_ascii_case(&letter))
        .and_then(|i| u8::try_from(i).ok())
}

/// Where a value starts: a digit, a sign or a decimal point.
fn starts_value(byte: Option<&u8>) -> bool {
    byte.is_some_and(|b| b.is_ascii_digit() || matches!(b, b'-' | b'+' | b'.'))
}

/// `X10mmY-5mm`: each axis letter's value and its span, the unit running
/// to the next axis letter that starts a value.
fn positions(text: &str, offset: usize) -> Option<Vec<Operand>> {
    let bytes = text.as_bytes();
    let mut found = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let axis = axis_of(bytes[i])?;
        if !starts_value(bytes.get(i + 1)) {
            return None;
        }
        let start = i + 1;
        let mut end = start + 1;
        while end < bytes.len()
            && !(axis_of(bytes[end]).is_some() && starts_value(bytes.get(end + 1)))
        {
            end += 1;
        }
        found.push(Operand {
            span: offset + start..offset + end,
            axis,
            quantity: Quantity::Position,
        });
        i = end;
    }
    Some(found)
}

impl UnitLaw for Cmd4crUnits {
    fn inputs(&self, _axis: u8) -> Vec<(Scope, u16)> {
        Vec::new()
    }

    fn steps_per_raw(
        &self,
        _axis: u8,
        quantity: Quantity,
        _value_of: &ValueOf,
    ) -> Result<f64, crate::protocol::units::UnitError> {
        use crate::protocol::units::{UnitError, UnitRefusal};
        match quantity {
            Quantity::Position | Quantity::Speed => Ok(1.0),
            Quantity::Acceleration => Err(UnitError::new(
                UnitRefusal::NotConvertible,
                "the CMD-4CR sets ramps as times (ACC, DEC in ms), not accelerations",
            )),
        }
    }

    fn row_quantity(&self, row: &crate::protocol::parameters::ParamRow) -> Option<Quantity> {
        // The per-axis speed rows (HSPDX, LSPDY…) hold pps as they are.
        let Scope::Axis(_) = row.scope else {
            return None;
        };
        let keyword = row.name.get(..row.name.len().checked_sub(1)?)?;
        SETTINGS
            .iter()
            .find(|(k, q)| *q == Quantity::Speed && k.eq_ignore_ascii_case(keyword))
            .map(|&(_, q)| q)
    }

    fn operands(&self, line: &str) -> Vec<Operand> {
        let trimmed = line.trim_start();
        let offset = line.len() - trimmed.len();
        let code = trimmed.trim_end();
        if let Some((name, _)) = code.split_once('=') {
            // `HSPDX=20mm/s`, `PX = 10mm`.
            let value_start = offset + name.len() + 1;
            let value = &line[value_start..offset + code.len()];
            let lead = value.len() - value.trim_start().len();
            let name = name.trim().as_bytes();
            let Some((&letter, keyword)) = name.split_last() else {
                return Vec::new();
            };
            let (Some(axis), Ok(keyword)) = (axis_of(letter), std::str::from_utf8(keyword)) else {
                return Vec::new();
            };
            return SETTINGS
                .iter()
                .find(|(k, _)| k.eq_ignore_ascii_case(keyword))
                .map(|&(_, quantity)| Operand {
                    span: value_start + lead..offset + code.len(),
                    axis,
                    quantity,
                })
                .into_iter()
                .collect();
        }
        // `TX1000`: a new target on the fly (§2.4.2).
        if let Some(rest) = code.strip_prefix(['T', 't'])
            && rest.len() > 1
            && axis_of(rest.as_bytes()[0]).is_some()
        {
            return positions(rest, offset + 1).unwrap_or_default();
        }
        positions(code, offset).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::units::{MechanicsTable, convert_line};

    fn mechanics() -> MechanicsTable {
        // A 1.8° stepper at 10 microsteps on a 5 mm lead screw (X), a
        // 4000-count encoder through a 10:1 gear on a rotary table (Y).
        let value: toml::Table = "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\n\
            microsteps = 10\ntravel_per_rev = 5\n\
            [mechanics.1]\nunit = \"deg\"\ncounts_per_rev = 4000\ngear_ratio = 10\ntravel_per_rev = 360\n"
            .parse()
            .expect("toml");
        let (m, problems) = MechanicsTable::from_toml(&value["mechanics"]);
        assert!(problems.is_empty(), "{problems:?}");
        m
    }

    fn convert(line: &str) -> Result<String, String> {
        convert_line(Some(&Cmd4crUnits), line, &mechanics(), &|_, _| None)
            .map(|c| c.line)
            .map_err(String::from)
    }

    #[test]
    fn pulses_and_pps_are_the_raw_values() {
        // §2.1.4: HSPD in pps; 20 mm/s at 400 pulses a mm.
        assert_eq!(convert("HSPDX=20mm/s"), Ok("HSPDX=8000".into()));
        assert_eq!(convert("hspdx = 20mm/s"), Ok("hspdx = 8000".into()));
        assert_eq!(convert("X12.5mm"), Ok("X5000".into()));
        assert_eq!(convert("X1mmY-90deg"), Ok("X400Y-10000".into()));
        assert_eq!(convert("TX2mm"), Ok("TX800".into()));
        assert_eq!(convert("PY=36deg"), Ok("PY=4000".into()));
        assert_eq!(convert("X1000Y-20"), Ok("X1000Y-20".into()));
        assert!(
            convert("Z1mm")
                .unwrap_err()
                .contains("axis 2 has no mechanics")
        );
        assert!(convert("HSPDX=20mm").unwrap_err().contains("takes a speed"));
    }
}
