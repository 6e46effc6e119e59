//! The TMCM-1110's parameter tables for the console's parameter table
//! ([`ParameterSet`]): rows from §4 Table 16 and §5 Tables 18–20, lines
//! GAP/SAP/STAP/RSAP and GGP/SGP/STGP/RSGP, and the §6.1 conversions of
//! velocities and accelerations.

use super::command::Command;
use super::console::AXES;
use super::line::format_command;
use super::params::{AXIS_PARAMS, Access, Bank, ParamInfo, Unit, ValueRange, axis_param};
use super::units::{acceleration_to_pps2, pps_to_rpm, rpm_to_pps, velocity_to_pps};
use crate::protocol::parameters::{
    ParamAccess, ParamError, ParamOp, ParamRange, ParamRefusal, ParamRole, ParamRow, ParamTable,
    ParameterSet, Physical, Scope, SpeedUnit, StatusQuantity, parse_integer,
};

/// The global banks, in the order the manual gives them (§5).
const BANKS: &[(Bank, &str)] = &[
    (Bank::Module, "Bank 0: module configuration"),
    (Bank::UserVariables, "Bank 2: user variables"),
    (Bank::Interrupts, "Bank 3: interrupt configuration"),
];

/// Axis parameters that are motion state, not configuration: writing a
/// saved AP0 or AP2 back would start the motor (§4 Table 16: the target
/// position in position mode, the target speed in velocity mode), AP1 and
/// AP209 would move the position and encoder references, and AP138 (ramp
/// mode) is what the last ROR, ROL, MST or MVP left.
const AXIS_STATE: &[u16] = &[0, 1, 2, 138, 209];

/// Global parameters of bank 0 that are run-time state: the tick timer and
/// the random number (§5.1 Table 18), and GP255, which with 1 silences the
/// replies this console waits for.
const BANK0_STATE: &[u16] = &[132, 133, 255];

/// Bank-0 parameters that decide how the module is reached (§5.1 Table
/// 18): writing one from a file would cut the link the console uses.
const BANK0_LINK: &[u16] = &[65, 66, 69, 70, 71, 76, 83, 87];

/// Parameters the §6.1 conversions need (§4 Table 16).
const MICROSTEP_RESOLUTION: u16 = 140;
const RAMP_DIVISOR: u16 = 153;
const PULSE_DIVISOR: u16 = 154;

/// What the axis status conversions need: the status has positions
/// (microsteps, §4 AP0/AP1) and speeds (internal units, AP3/AP4), no
/// accelerations, so the ramp divisor is not among them.
const STATUS_INPUTS: &[u16] = &[MICROSTEP_RESOLUTION, PULSE_DIVISOR];

/// §6.1.4 gives rps and rpm for "a 200 fullsteps motor", the common 1.8°
/// stepper; the module has no parameter for it, so rpm assume it.
pub const FULLSTEPS_PER_REV: u32 = 200;

/// TMCL parameters for the console.
#[derive(Debug, Clone, Copy, Default)]
pub struct TmclParameters;

fn access(access: Access) -> ParamAccess {
    ParamAccess {
        read: access.read,
        write: access.write,
        store: access.eeprom,
        auto_stored: access.auto_stored,
    }
}

fn range(range: ValueRange) -> ParamRange {
    match range {
        ValueRange::Span { min, max } => ParamRange::Span { min, max },
        ValueRange::OneOf(values) => ParamRange::OneOf(values),
    }
}

/// A row of a manual table covering several numbers (user variables
/// #0..#55) names each one: "User variable #7".
fn single_name(info: &ParamInfo, number: u8) -> String {
    if info.numbers.start() == info.numbers.end() {
        return info.name.to_string();
    }
    let base = info.name.split(" #").next().unwrap_or(info.name);
    let base = base
        .strip_suffix("variables")
        .map_or_else(|| base.to_string(), |stem| format!("{stem}variable"));
    format!("{base} #{number}")
}

fn role(scope: Scope, number: u16, info: &ParamInfo) -> ParamRole {
    if !info.access.write {
        return ParamRole::State;
    }
    match scope {
        Scope::Axis(_) if AXIS_STATE.contains(&number) => ParamRole::State,
        Scope::Bank(0) if BANK0_STATE.contains(&number) => ParamRole::State,
        Scope::Bank(0) if BANK0_LINK.contains(&number) => ParamRole::Link,
        _ => ParamRole::Setting,
    }
}

fn rows(scope: Scope, table: &'static [ParamInfo]) -> Vec<ParamRow> {
    table
        .iter()
        .flat_map(|info| {
            info.numbers.clone().map(move |number| ParamRow {
                scope,
                number: u16::from(number),
                name: single_name(info, number),
                unit: info.unit.label(),
                range: range(info.range),
                access: access(info.access),
                role: role(scope, u16::from(number), info),
                default: info.default,
                description: info.description,
            })
        })
        .collect()
}

fn info_of(row: &ParamRow) -> Option<&'static ParamInfo> {
    let number = u8::try_from(row.number).ok()?;
    let table = match row.scope {
        Scope::Axis(_) => AXIS_PARAMS,
        Scope::Bank(bank) => Bank::from_number(bank)?.table(),
    };
    table.iter().find(|p| p.numbers.contains(&number))
}

/// "AP4", "GP66 (bank 0)": how the manual names a parameter.
fn label(row: &ParamRow) -> String {
    match row.scope {
        Scope::Axis(_) => format!("AP{}", row.number),
        Scope::Bank(bank) => format!("GP{} (bank {bank})", row.number),
    }
}

/// A divisor or resolution read from the module, if it is one the §6.1
/// formulas take (0..13, 0..8).
fn exponent(value: Option<i64>, max: u8) -> Option<u8> {
    u8::try_from(value?).ok().filter(|v| *v <= max)
}

/// What one internal unit of `info` is worth in pps (or pps²).
fn pps_per_unit(info: &ParamInfo, axis_value: &dyn Fn(u16) -> Option<i64>) -> Option<f64> {
    let pulse = exponent(axis_value(PULSE_DIVISOR), 13)?;
    match info.unit {
        Unit::VelocityInternal => Some(velocity_to_pps(1, pulse)),
        Unit::AccelerationInternal => {
            let ramp = exponent(axis_value(RAMP_DIVISOR), 13)?;
            Some(acceleration_to_pps2(1, ramp, pulse))
        }
        _ => None,
    }
}

impl ParameterSet for TmclParameters {
    fn tables(&self, axis: u8) -> Vec<ParamTable> {
        let name = AXES
            .iter()
            .find(|a| a.number == axis)
            .map_or_else(|| format!("motor {axis}"), |a| a.name.to_string());
        let mut tables = vec![ParamTable {
            scope: Scope::Axis(axis),
            title: format!("Axis parameters: {name}"),
            rows: rows(Scope::Axis(axis), AXIS_PARAMS),
        }];
        for (bank, title) in BANKS {
            let scope = Scope::Bank(*bank as u8);
            tables.push(ParamTable {
                scope,
                title: (*title).to_string(),
                rows: rows(scope, bank.table()),
            });
        }
        tables
    }

    fn line(&self, row: &ParamRow, op: ParamOp) -> Result<String, ParamError> {
        let not_a_parameter = || {
            ParamError::new(
                ParamRefusal::NotAParameter,
                format!("{} is not a parameter", label(row)),
            )
        };
        let info = info_of(row).ok_or_else(not_a_parameter)?;
        let param = u8::try_from(row.number).map_err(|_| not_a_parameter())?;
        let name = label(row);
        let value = |v: i64| {
            info.wire_value(v).ok_or_else(|| {
                ParamError::new(
                    ParamRefusal::OutOfRange,
                    format!("{name} takes {}, not {v}", info.range),
                )
            })
        };
        let storable = || {
            if info.access.auto_stored {
                Err(ParamError::new(
                    ParamRefusal::NotStorable,
                    format!(
                        "{name} is written to EEPROM by every write (access {})",
                        info.access
                    ),
                ))
            } else if !info.access.eeprom {
                Err(ParamError::new(
                    ParamRefusal::NotStorable,
                    format!("{name} has no EEPROM copy (access {})", info.access),
                ))
            } else {
                Ok(())
            }
        };
        if let ParamOp::Write(_) = op
            && !info.access.write
        {
            return Err(ParamError::new(
                ParamRefusal::ReadOnly,
                format!("{name} is read-only (access {})", info.access),
            ));
        }
        if op == ParamOp::Read && !info.access.read {
            return Err(ParamError::new(
                ParamRefusal::NotReadable,
                format!("{name} cannot be read (access {})", info.access),
            ));
        }
        let command = match (row.scope, op) {
            (Scope::Axis(motor), ParamOp::Read) => Command::Gap { param, motor },
            (Scope::Axis(motor), ParamOp::Write(v)) => Command::Sap {
                param,
                motor,
                value: value(v)?,
            },
            (Scope::Axis(motor), ParamOp::Store) => {
                storable()?;
                Command::Stap { param, motor }
            }
            (Scope::Axis(motor), ParamOp::Restore) => {
                storable()?;
                Command::Rsap { param, motor }
            }
            (Scope::Bank(bank), ParamOp::Read) => Command::Ggp { param, bank },
            (Scope::Bank(bank), ParamOp::Write(v)) => Command::Sgp {
                param,
                bank,
                value: value(v)?,
            },
            (Scope::Bank(bank), ParamOp::Store) => {
                storable()?;
                Command::Stgp { param, bank }
            }
            (Scope::Bank(bank), ParamOp::Restore) => {
                storable()?;
                Command::Rsgp { param, bank }
            }
        };
        Ok(format_command(&command))
    }

    fn physical(
        &self,
        row: &ParamRow,
        value: i64,
        unit: SpeedUnit,
        axis_value: &dyn Fn(u16) -> Option<i64>,
    ) -> Option<Physical> {
        if !matches!(row.scope, Scope::Axis(_)) {
            return None;
        }
        let info = axis_param(u8::try_from(row.number).ok()?)?;
        let pps = pps_per_unit(info, axis_value)? * value as f64;
        let accel = info.unit == Unit::AccelerationInternal;
        match unit {
            SpeedUnit::Pps => Some(Physical {
                value: pps,
                unit: if accel { "pps²" } else { "pps" },
            }),
            SpeedUnit::Rpm => {
                let resolution = exponent(axis_value(MICROSTEP_RESOLUTION), 8)?;
                Some(Physical {
                    value: pps_to_rpm(pps, FULLSTEPS_PER_REV, resolution),
                    unit: if accel { "rpm/s" } else { "rpm" },
                })
            }
        }
    }

    fn status_inputs(&self) -> &'static [u16] {
        STATUS_INPUTS
    }

    fn status_physical(
        &self,
        quantity: StatusQuantity,
        value: i64,
        unit: SpeedUnit,
        axis_value: &dyn Fn(u16) -> Option<i64>,
    ) -> Option<Physical> {
        let resolution = || exponent(axis_value(MICROSTEP_RESOLUTION), 8);
        let raw = value as f64;
        Some(match (quantity, unit) {
            // Positions are counted in microsteps already (§4 AP1).
            (StatusQuantity::Position, SpeedUnit::Pps) => Physical {
                value: raw,
                unit: "µsteps",
            },
            // §6.1.4: a revolution is 200 full steps of 2^AP140 microsteps.
            (StatusQuantity::Position, SpeedUnit::Rpm) => Physical {
                value: raw / (f64::from(FULLSTEPS_PER_REV) * 2f64.powi(i32::from(resolution()?))),
                unit: "rev",
            },
            // §6.1.1 equation (1), with the pulse divisor AP154.
            (StatusQuantity::Speed, SpeedUnit::Pps) => Physical {
                value: velocity_to_pps(1, exponent(axis_value(PULSE_DIVISOR), 13)?) * raw,
                unit: "pps",
            },
            (StatusQuantity::Speed, SpeedUnit::Rpm) => {
                let pps = velocity_to_pps(1, exponent(axis_value(PULSE_DIVISOR), 13)?) * raw;
                Physical {
                    value: pps_to_rpm(pps, FULLSTEPS_PER_REV, resolution()?),
                    unit: "rpm",
                }
            }
        })
    }

    fn parse_value(
        &self,
        row: &ParamRow,
        text: &str,
        axis_value: &dyn Fn(u16) -> Option<i64>,
    ) -> Result<i64, ParamError> {
        let text = text.trim();
        let split = text
            .find(|c: char| c.is_ascii_alphabetic() && c != 'x' && c != 'X')
            .filter(|_| !text.starts_with("0x") && !text.starts_with("0X"));
        let Some(at) = split else {
            return parse_integer(text);
        };
        let (number, unit) = text.split_at(at);
        if number.trim().is_empty() {
            return parse_integer(text);
        }
        let unit = unit.trim().to_ascii_lowercase();
        let info = match row.scope {
            Scope::Axis(_) => u8::try_from(row.number).ok().and_then(axis_param),
            Scope::Bank(_) => None,
        };
        let Some(info) =
            info.filter(|i| matches!(i.unit, Unit::VelocityInternal | Unit::AccelerationInternal))
        else {
            return Err(ParamError::new(
                ParamRefusal::WrongUnit,
                format!("{} takes a plain number, not `{text}`", label(row)),
            ));
        };
        let accel = info.unit == Unit::AccelerationInternal;
        let wanted = if accel {
            "pps2 (or pps²) or rpm/s"
        } else {
            "pps or rpm"
        };
        let amount: f64 = number.trim().parse().map_err(|_| {
            ParamError::new(
                ParamRefusal::NotANumber,
                format!("`{}` is not a number", number.trim()),
            )
        })?;
        let pps = match (unit.as_str(), accel) {
            ("pps", false) | ("pps2" | "pps²", true) => amount,
            ("rpm", false) | ("rpm/s", true) => {
                let resolution =
                    exponent(axis_value(MICROSTEP_RESOLUTION), 8).ok_or_else(|| {
                        ParamError::new(
                            ParamRefusal::NeedsReading,
                            "rpm need the microstep resolution (AP140): read it first (refresh)",
                        )
                    })?;
                rpm_to_pps(amount, FULLSTEPS_PER_REV, resolution)
            }
            _ => {
                return Err(ParamError::new(
                    ParamRefusal::WrongUnit,
                    format!("{} is in {wanted}, not `{unit}`", label(row)),
                ));
            }
        };
        let per_unit = pps_per_unit(info, axis_value).ok_or_else(|| {
            ParamError::new(
                ParamRefusal::NeedsReading,
                if accel {
                    "converting needs the ramp and pulse divisors (AP153, AP154): read them first \
                     (refresh)"
                } else {
                    "converting needs the pulse divisor (AP154): read it first (refresh)"
                },
            )
        })?;
        let raw = (pps / per_unit).round();
        if !raw.is_finite() || raw.abs() > 1e15 {
            return Err(ParamError::new(
                ParamRefusal::OutOfRange,
                format!("{text} is far out of range"),
            ));
        }
        Ok(raw as i64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(scope: Scope, number: u16) -> ParamRow {
        let tables = TmclParameters.tables(0);
        tables
            .iter()
            .flat_map(|t| t.rows.iter())
            .find(|r| r.scope == scope && r.number == number)
            .cloned()
            .unwrap_or_else(|| panic!("{scope:?} {number}"))
    }

    fn divisors(n: u16) -> Option<i64> {
        match n {
            PULSE_DIVISOR => Some(3),
            RAMP_DIVISOR => Some(7),
            MICROSTEP_RESOLUTION => Some(8),
            _ => None,
        }
    }

    #[test]
    fn tables_cover_the_axis_and_every_bank_one_row_per_number() {
        let tables = TmclParameters.tables(0);
        let scopes: Vec<Scope> = tables.iter().map(|t| t.scope).collect();
        assert_eq!(
            scopes,
            [
                Scope::Axis(0),
                Scope::Bank(0),
                Scope::Bank(2),
                Scope::Bank(3)
            ]
        );
        assert_eq!(tables[2].rows.len(), 256);
        assert_eq!(tables[2].rows[7].name, "User variable #7");
        assert!(tables[2].rows[55].access.store);
        assert!(!tables[2].rows[56].access.store);
        let speed = row(Scope::Axis(0), 4);
        assert_eq!(speed.name, "Maximum positioning speed");
        assert_eq!(speed.range, ParamRange::Span { min: 1, max: 2047 });
        assert_eq!(speed.access.to_string(), "RWE");
        assert_eq!(speed.role, ParamRole::Setting);
    }

    #[test]
    fn motion_state_and_link_settings_are_told_apart() {
        assert_eq!(row(Scope::Axis(0), 0).role, ParamRole::State);
        assert_eq!(row(Scope::Axis(0), 3).role, ParamRole::State);
        assert_eq!(row(Scope::Axis(0), 209).role, ParamRole::State);
        assert_eq!(row(Scope::Axis(0), 4).role, ParamRole::Setting);
        assert_eq!(row(Scope::Bank(0), 66).role, ParamRole::Link);
        assert_eq!(row(Scope::Bank(0), 255).role, ParamRole::State);
        assert_eq!(row(Scope::Bank(0), 79).role, ParamRole::Setting);
    }

    #[test]
    fn lines_read_write_store_and_restore() {
        let speed = row(Scope::Axis(0), 4);
        let line = |r: &ParamRow, op| TmclParameters.line(r, op);
        assert_eq!(line(&speed, ParamOp::Read).unwrap(), "GAP 4, 0");
        assert_eq!(
            line(&speed, ParamOp::Write(1000)).unwrap(),
            "SAP 4, 0, 1000"
        );
        assert_eq!(line(&speed, ParamOp::Store).unwrap(), "STAP 4, 0");
        assert_eq!(line(&speed, ParamOp::Restore).unwrap(), "RSAP 4, 0");
        let var = row(Scope::Bank(2), 5);
        assert_eq!(line(&var, ParamOp::Read).unwrap(), "GGP 5, 2");
        assert_eq!(line(&var, ParamOp::Write(-3)).unwrap(), "SGP 5, 2, -3");
        assert_eq!(line(&var, ParamOp::Store).unwrap(), "STGP 5, 2");
        assert_eq!(line(&var, ParamOp::Restore).unwrap(), "RSGP 5, 2");
        let timer = row(Scope::Bank(3), 0);
        assert_eq!(
            line(&timer, ParamOp::Write(4_294_967_295)).unwrap(),
            "SGP 0, 3, 4294967295"
        );
    }

    #[test]
    fn impossible_operations_say_why() {
        let line = |r: &ParamRow, op| TmclParameters.line(r, op).unwrap_err().to_string();
        assert!(line(&row(Scope::Axis(0), 7), ParamOp::Store).contains("no EEPROM copy"));
        assert_eq!(
            TmclParameters.line(&row(Scope::Axis(0), 6), ParamOp::Store),
            Ok("STAP 6, 0".to_string())
        );
        assert!(line(&row(Scope::Bank(0), 65), ParamOp::Store).contains("every write"));
        assert!(line(&row(Scope::Axis(0), 3), ParamOp::Write(1)).contains("read-only"));
        assert_eq!(
            line(&row(Scope::Axis(0), 6), ParamOp::Write(300)),
            "AP6 takes 0..255, not 300"
        );
    }

    #[test]
    fn speeds_convert_with_the_modules_divisors() {
        let speed = row(Scope::Axis(0), 4);
        // §6.1.1: 1678 with pulse divisor 3 is about 51208.5 pps.
        let pps = TmclParameters
            .physical(&speed, 1678, SpeedUnit::Pps, &divisors)
            .unwrap();
        assert!((pps.value - 51208.5).abs() < 0.1, "{pps}");
        assert_eq!(pps.unit, "pps");
        // §6.1.4: 51200 pps at 256 microsteps of a 200-step motor is 60 rpm.
        let rpm = TmclParameters
            .physical(&speed, 1678, SpeedUnit::Rpm, &divisors)
            .unwrap();
        assert!((rpm.value - 60.0).abs() < 0.01, "{rpm}");
        // §6.1.2: 100 with ramp divisor 7, pulse divisor 3: about 46566 pps².
        let accel = row(Scope::Axis(0), 5);
        let pps2 = TmclParameters
            .physical(&accel, 100, SpeedUnit::Pps, &divisors)
            .unwrap();
        assert!((pps2.value - 46566.0).abs() < 1.0, "{pps2}");
        assert_eq!(pps2.unit, "pps²");
        // No divisor read yet, or a parameter with no conversion: nothing.
        assert!(
            TmclParameters
                .physical(&speed, 1678, SpeedUnit::Pps, &|_| None)
                .is_none()
        );
        assert!(
            TmclParameters
                .physical(&row(Scope::Axis(0), 6), 100, SpeedUnit::Pps, &divisors)
                .is_none()
        );
    }

    #[test]
    fn status_readings_convert_to_steps_and_revolutions() {
        let convert = |q, v, u| TmclParameters.status_physical(q, v, u, &divisors);
        // §6.1.1: 1678 with pulse divisor 3 is about 51208.5 pps; §6.1.4:
        // 51200 pps at 256 microsteps of a 200-step motor is 60 rpm.
        let pps = convert(StatusQuantity::Speed, 1678, SpeedUnit::Pps).unwrap();
        assert!((pps.value - 51208.5).abs() < 0.1, "{pps}");
        assert_eq!(pps.unit, "pps");
        let rpm = convert(StatusQuantity::Speed, -1678, SpeedUnit::Rpm).unwrap();
        assert!((rpm.value + 60.0).abs() < 0.01, "{rpm}");
        assert_eq!(rpm.unit, "rpm");
        // 51200 microsteps at 256 per full step: one turn of 200 steps.
        let turns = convert(StatusQuantity::Position, 12800, SpeedUnit::Rpm).unwrap();
        assert_eq!((turns.value, turns.unit), (0.25, "rev"));
        let steps = convert(StatusQuantity::Position, 12800, SpeedUnit::Pps).unwrap();
        assert_eq!((steps.value, steps.unit), (12800.0, "µsteps"));
        assert_eq!(TmclParameters.status_inputs(), [140, 154]);
        // Nothing read yet, or a resolution the module cannot have: no
        // conversion rather than a wrong one.
        let none = |q, u| TmclParameters.status_physical(q, 100, u, &|_| None);
        assert!(none(StatusQuantity::Speed, SpeedUnit::Pps).is_none());
        assert!(none(StatusQuantity::Position, SpeedUnit::Rpm).is_none());
        let odd = |n| (n == MICROSTEP_RESOLUTION).then_some(9);
        assert!(
            TmclParameters
                .status_physical(StatusQuantity::Position, 1, SpeedUnit::Rpm, &odd)
                .is_none()
        );
    }

    #[test]
    fn values_may_be_typed_in_real_world_units() {
        let speed = row(Scope::Axis(0), 4);
        let parse = |r: &ParamRow, text| {
            TmclParameters
                .parse_value(r, text, &divisors)
                .map_err(String::from)
        };
        assert_eq!(parse(&speed, "1678"), Ok(1678));
        assert_eq!(parse(&speed, "0x10"), Ok(16));
        assert_eq!(parse(&speed, "51208.5 pps"), Ok(1678));
        assert_eq!(parse(&speed, "60rpm"), Ok(1678));
        assert_eq!(parse(&row(Scope::Axis(0), 5), "46566 pps2"), Ok(100));
        assert!(
            parse(&speed, "5 furlongs")
                .unwrap_err()
                .contains("pps or rpm")
        );
        assert!(
            parse(&row(Scope::Axis(0), 6), "5 pps")
                .unwrap_err()
                .contains("plain number")
        );
        let unknown = TmclParameters
            .parse_value(&speed, "100 pps", &|_| None)
            .map_err(String::from);
        assert!(unknown.unwrap_err().contains("AP154"));
    }
}
