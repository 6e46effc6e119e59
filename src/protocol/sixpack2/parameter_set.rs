//! The SIXpack 2's settings for the console's parameter table
//! ([`ParameterSet`]), as far as they can be had: every setting is
//! write-only. No command reads one back (§7, digest D0), none stores one
//! (a reset brings back the factory values of §6.8), and most commands
//! write several settings in one frame (`$14` amax and vmax). So a row
//! reads nothing, and a row writes alone only where its command carries
//! nothing else (`$10`, `$12`, `$41`, `$42`); for the others the table
//! says which command to type, instead of guessing the values it would
//! overwrite. Keeping what was written is the session's business (issue
//! 13, point 3).
//!
//! A row's number is its command code in the high byte and its field's
//! index in the low byte (`$14` vmax is `$1402`); the microstep table's
//! rows are `$1700 + entry`.

use super::catalog::{
    COMMANDS, CURRENT_STEPS, CommandSpec, Field, FieldKind, MOTORS, by_code, motor_name,
};
use super::command::{Command, format_value};
use super::frame::Request;
use super::line::parse_value;
use crate::protocol::parameters::{
    ParamAccess, ParamError, ParamOp, ParamRange, ParamRefusal, ParamRole, ParamRow, ParamTable,
    ParameterSet, Physical, Scope,
};
use crate::protocol::settings::SettingWrite;

/// A row's number: the command and the field's index in it.
pub(crate) fn number_of(code: u8, index: usize) -> u16 {
    u16::from(code) << 8 | u16::try_from(index).unwrap_or(0xFF)
}

/// The microstep table command and its 16 entries (§7.1 `$17`).
const TABLE: u8 = 0x17;
const TABLE_ENTRIES: u16 = 16;

/// `$31` sets the A_In limits of a channel: channels 0..5 are the motors',
/// shown in their tables; 6 and 7 get banks of their own.
const LIMITS: u8 = 0x31;

/// The banks of global settings.
struct Bank {
    number: u8,
    title: &'static str,
    /// Commands whose every field (but a channel) is a row.
    codes: &'static [u8],
}

const BANKS: &[Bank] = &[
    Bank {
        number: 0,
        title: "Global: clock divider, microstep table, outputs, ready output (§7.1, §7.3)",
        codes: &[0x12, TABLE, 0x32, 0x33],
    },
    Bank {
        number: 1,
        title: "Link: baud rate, switch-over delay, packet timeout, address (§7.4)",
        codes: &[0x40, 0x41, 0x42],
    },
    Bank {
        number: 6,
        title: "A_In limits of channel 6, the external input (§7.3 $31)",
        codes: &[LIMITS],
    },
    Bank {
        number: 7,
        title: "A_In limits of channel 7, the supply voltage (§7.3 $31)",
        codes: &[LIMITS],
    },
];

/// Settings that decide how the unit is reached.
const LINK: &[u8] = &[0x40, 0x42];

/// Factory values (§6.8, digest D7), by row number; rows the manual gives
/// none for are left out.
const DEFAULTS: &[(u16, i64)] = &[
    (0x1001, 128),
    (0x1101, 8),
    (0x1102, 2),
    (0x1103, 1),
    (0x1104, 0),
    (0x1105, 500),
    (0x1200, 5),
    (0x1301, 4),
    (0x1302, 5),
    (0x1303, 2),
    (0x1401, 128),
    (0x1402, 511),
    (0x1501, 6400),
    (0x1502, 0x0AA0),
    (0x1601, 100),
    (0x1602, 0x0FFF),
    (0x1603, 0),
    (0x1801, 0),
    (0x1802, 240),
    (0x1901, 8),
    (0x1902, 129),
    (0x1903, 129),
    (0x1904, 1),
    // §3.1: TTLOUT1 is high after a reset.
    (0x3200, 1),
    (0x3300, 0x3F),
    (0x3301, 0x3F),
    // §6.1.1: switch-over delay 6 ms.
    (0x4001, 3),
];

/// §6.3.2: the default table is 255·sin((i+0.5)·π/32), i = 0..15.
fn table_default(entry: u16) -> i64 {
    let angle = (f64::from(entry) + 0.5) * std::f64::consts::PI / 32.0;
    (255.0 * angle.sin()).round() as i64
}

fn default_of(number: u16) -> Option<i64> {
    if number >> 8 == u16::from(TABLE) {
        return Some(table_default(number & 0xFF));
    }
    DEFAULTS.iter().find(|(n, _)| *n == number).map(|(_, v)| *v)
}

const WRITE_ONLY: ParamAccess = ParamAccess {
    read: false,
    write: true,
    store: false,
    auto_stored: false,
};

fn range_of(field: &Field) -> ParamRange {
    match field.kind {
        FieldKind::OneOf(values) => ParamRange::OneOf(values),
        _ => {
            let (min, max) = field.bounds();
            ParamRange::Span { min, max }
        }
    }
}

fn row(scope: Scope, spec: &CommandSpec, index: usize, field: &'static Field) -> ParamRow {
    let number = number_of(spec.code, index);
    ParamRow {
        scope,
        number,
        name: field.name.to_string(),
        unit: field.unit,
        range: range_of(field),
        access: WRITE_ONLY,
        role: if LINK.contains(&spec.code) {
            ParamRole::Link
        } else {
            ParamRole::Setting
        },
        default: default_of(number),
        description: field.meaning,
    }
}

/// The rows of `spec` but its motor or channel.
fn rows_of(scope: Scope, spec: &'static CommandSpec) -> Vec<ParamRow> {
    if spec.code == TABLE {
        let Some(entry) = spec.fields.get(1) else {
            return Vec::new();
        };
        return (0..TABLE_ENTRIES)
            .map(|i| ParamRow {
                name: format!("table[{i}]"),
                number: u16::from(TABLE) << 8 | i,
                default: Some(table_default(i)),
                description: "microstep table entry: coil current at this step of a quarter sine \
                              (§6.3.2)",
                ..row(scope, spec, 1, entry)
            })
            .collect();
    }
    spec.fields
        .iter()
        .enumerate()
        .filter(|(_, f)| !matches!(f.kind, FieldKind::Motor | FieldKind::Channel))
        .map(|(i, f)| row(scope, spec, i, f))
        .collect()
}

/// The command and field of a row.
fn field_of(row: &ParamRow) -> Option<(&'static CommandSpec, usize)> {
    let spec = by_code(u8::try_from(row.number >> 8).ok()?)?;
    let index = if spec.code == TABLE {
        1
    } else {
        usize::from(row.number & 0xFF)
    };
    spec.fields.get(index)?;
    Some((spec, index))
}

/// The motor or channel a row's scope gives its command.
fn selector(row: &ParamRow) -> i64 {
    match row.scope {
        Scope::Axis(n) | Scope::Bank(n) => i64::from(n),
    }
}

/// The scope of the table rows a setting command writes, for the motor
/// or channel it carries; `None` when the command writes no row.
fn scope_of(spec: &CommandSpec, selector: Option<i64>) -> Option<Scope> {
    if let Some(bank) = BANKS
        .iter()
        .find(|b| b.codes.contains(&spec.code) && spec.code != LIMITS)
    {
        return Some(Scope::Bank(bank.number));
    }
    if spec.class != super::catalog::Class::Setting {
        return None;
    }
    let n = u8::try_from(selector?).ok()?;
    match spec.code {
        LIMITS if n >= MOTORS => Some(Scope::Bank(n)),
        _ if n < MOTORS => Some(Scope::Axis(n)),
        _ => None,
    }
}

/// The rows a request writes, with their values: what the unit holds
/// once it took the frame (it answers none, §7). A `$10` for an odd
/// motor is ignored by the unit (§7.1) and writes nothing; one for an
/// even motor sets the peak current of the pair.
pub fn written_by(request: &Request) -> Vec<SettingWrite> {
    let Ok(Some(command)) = Command::from_request(request) else {
        return Vec::new();
    };
    let spec = command.spec;
    let selector = spec
        .fields
        .iter()
        .zip(&command.values)
        .find(|(f, _)| matches!(f.kind, FieldKind::Motor | FieldKind::Channel))
        .map(|(_, v)| *v);
    let Some(scope) = scope_of(spec, selector) else {
        return Vec::new();
    };
    let value = |name: &str| command.value(name).unwrap_or(0);
    if spec.code == TABLE {
        let start = value("index");
        return (0..4)
            .filter_map(|i| {
                let number = u16::from(TABLE) << 8 | u16::try_from(start + i).ok()?;
                Some(SettingWrite {
                    scope,
                    number,
                    value: value(&format!("e{i}")),
                })
            })
            .collect();
    }
    let mut writes: Vec<SettingWrite> = spec
        .fields
        .iter()
        .zip(&command.values)
        .enumerate()
        .filter(|(_, (f, _))| !matches!(f.kind, FieldKind::Motor | FieldKind::Channel))
        .map(|(i, (_, v))| SettingWrite {
            scope,
            number: number_of(spec.code, i),
            value: *v,
        })
        .collect();
    if spec.code == 0x10 {
        match scope {
            Scope::Axis(m) if m % 2 == 1 => return Vec::new(),
            Scope::Axis(m) => {
                let pair: Vec<SettingWrite> = writes
                    .iter()
                    .map(|w| SettingWrite {
                        scope: Scope::Axis(m + 1),
                        ..*w
                    })
                    .collect();
                writes.extend(pair);
            }
            Scope::Bank(_) => {}
        }
    }
    writes
}

/// The SIXpack 2's write-only settings for the console.
#[derive(Debug, Clone, Copy, Default)]
pub struct Sixpack2Parameters;

impl ParameterSet for Sixpack2Parameters {
    fn tables(&self, axis: u8) -> Vec<ParamTable> {
        let mut tables = Vec::new();
        if axis < MOTORS {
            let scope = Scope::Axis(axis);
            let rows = COMMANDS
                .iter()
                .filter(|c| {
                    c.class == super::catalog::Class::Setting
                        && c.fields.first().is_some_and(|f| {
                            f.kind == FieldKind::Motor
                                || (c.code == LIMITS && f.kind == FieldKind::Channel)
                        })
                })
                .flat_map(|c| rows_of(scope, c))
                .collect();
            tables.push(ParamTable {
                scope,
                title: format!(
                    "{}: written only, never read back (§7)",
                    motor_name(i64::from(axis))
                ),
                rows,
            });
        }
        for bank in BANKS {
            let scope = Scope::Bank(bank.number);
            let rows = bank
                .codes
                .iter()
                .filter_map(|&code| by_code(code))
                .flat_map(|c| rows_of(scope, c))
                .collect();
            tables.push(ParamTable {
                scope,
                title: bank.title.to_string(),
                rows,
            });
        }
        tables
    }

    fn line(&self, row: &ParamRow, op: ParamOp) -> Result<String, ParamError> {
        self.line_with(row, op, &|_, _| None)
    }

    /// Every row is write-only: what is known of it is what the session
    /// wrote ([`written_by`]).
    fn remembers_writes(&self) -> bool {
        true
    }

    /// A row written together with others in one frame takes their
    /// values from `known` (what was written this session, or an
    /// imported file's); without all of them the table says which
    /// command to type.
    fn line_with(
        &self,
        row: &ParamRow,
        op: ParamOp,
        known: &dyn Fn(Scope, u16) -> Option<i64>,
    ) -> Result<String, ParamError> {
        let (spec, index) = field_of(row).ok_or_else(|| not_a_setting(row))?;
        let field = &spec.fields[index];
        let value = match op {
            ParamOp::Read => {
                return Err(ParamError::new(
                    ParamRefusal::NotReadable,
                    format!(
                        "the SIXpack 2 cannot read {} back: no command reads a setting (§7)",
                        row.name
                    ),
                ));
            }
            ParamOp::Store | ParamOp::Restore => {
                return Err(ParamError::new(
                    ParamRefusal::NotStorable,
                    "the SIXpack 2 has no command that stores or reloads a setting: a reset \
                     brings back the factory values (§6.8, §7.4)",
                ));
            }
            ParamOp::Write(value) => value,
        };
        if !field.accepts(value) {
            return Err(ParamError::new(
                ParamRefusal::OutOfRange,
                format!(
                    "{} takes {}, not {value}",
                    row.name,
                    super::command::allowed(field)
                ),
            ));
        }
        let selected: Vec<usize> = spec
            .fields
            .iter()
            .enumerate()
            .filter(|(_, f)| matches!(f.kind, FieldKind::Motor | FieldKind::Channel))
            .map(|(i, _)| i)
            .collect();
        // The other values the frame carries: a field's default, else
        // what is known of its row.
        let mut values: Vec<Option<i64>> = spec.fields.iter().map(|f| f.default).collect();
        for &i in &selected {
            values[i] = Some(selector(row));
        }
        if spec.code == TABLE {
            let entry = i64::from(row.number & 0xFF);
            let start = entry - entry % 4;
            values[0] = Some(start);
            for i in 0..4 {
                let number = u16::from(TABLE) << 8 | u16::try_from(start + i).unwrap_or(0);
                values[1 + usize::try_from(i).unwrap_or(0)] = if start + i == entry {
                    Some(value)
                } else {
                    known(row.scope, number)
                };
            }
        } else {
            values[index] = Some(value);
            for (i, slot) in values.iter_mut().enumerate() {
                if slot.is_none() {
                    *slot = known(row.scope, number_of(spec.code, i));
                }
            }
        }
        let others: Vec<&str> = spec
            .fields
            .iter()
            .zip(&values)
            .filter(|(_, v)| v.is_none())
            .map(|(f, _)| f.name)
            .collect();
        if spec.code == 0x10 && selector(row) % 2 == 1 {
            let even = selector(row) - 1;
            return Err(ParamError::new(
                ParamRefusal::NotDone,
                format!(
                    "the peak current of motors {even} and {} is set on motor {even} (§7.1)",
                    even + 1
                ),
            ));
        }
        if !others.is_empty() {
            let mut example = spec.mnemonic.to_string();
            for (f, v) in spec.fields.iter().zip(&values) {
                match v {
                    Some(v) => example.push_str(&format!(" {}", format_value(f, *v))),
                    None => example.push_str(&format!(" {}", f.name.to_ascii_uppercase())),
                }
            }
            let together = if spec.code == TABLE {
                "the other entries of its group of four".to_string()
            } else {
                others.join(", ")
            };
            return Err(ParamError::new(
                ParamRefusal::NotDone,
                format!(
                    "{} is written together with {together} by {} (${:02X}); the unit cannot \
                     read them back, so type `{example}` in the command pane",
                    row.name, spec.mnemonic, spec.code
                ),
            ));
        }
        let values: Vec<i64> = values.into_iter().map(|v| v.unwrap_or(0)).collect();
        let command = Command::new(spec, values)
            .map_err(|e| ParamError::new(ParamRefusal::OutOfRange, e.to_string()))?;
        Ok(command.to_string())
    }

    /// Times in 2 ms units as ms, current steps as percentages.
    fn physical(
        &self,
        row: &ParamRow,
        value: i64,
        unit: crate::protocol::parameters::SpeedUnit,
        axis_value: &dyn Fn(u16) -> Option<i64>,
    ) -> Option<Physical> {
        let _ = (unit, axis_value);
        let (spec, index) = field_of(row)?;
        let field = &spec.fields[index];
        match field.kind {
            FieldKind::CurrentIndex => CURRENT_STEPS
                .iter()
                .find(|s| i64::from(s.index) == value)
                .map(|s| Physical {
                    value: f64::from(s.percent),
                    unit: "% of peak",
                }),
            _ if field.unit == "2 ms" => Some(Physical {
                value: 2.0 * value as f64,
                unit: "ms",
            }),
            _ => None,
        }
    }

    fn store_place(&self) -> &'static str {
        "nowhere: the SIXpack 2 stores no setting"
    }

    /// A motor mask as its list of motors (`0,2`): typed back as a bare
    /// number, `5`, it would read as motor 5, not motors 0 and 2.
    fn value_text(&self, row: &ParamRow, value: i64) -> String {
        match field_of(row).map(|(spec, index)| &spec.fields[index]) {
            Some(field) if field.kind == FieldKind::MotorMask => format_value(field, value),
            _ => value.to_string(),
        }
    }

    /// Flags and masks by name; the debounce mask as its delay.
    fn value_note(
        &self,
        row: &ParamRow,
        value: i64,
        value_of: &dyn Fn(Scope, u16) -> Option<i64>,
    ) -> Option<String> {
        let _ = value_of;
        let (spec, index) = field_of(row)?;
        let field = &spec.fields[index];
        match field.kind {
            FieldKind::Flags(_) | FieldKind::MotorMask => Some(format_value(field, value)),
            _ if spec.code == 0x16 && field.name == "debounce" => {
                let ones = (value + 1).trailing_zeros();
                (value > 0 && value & (value + 1) == 0)
                    .then(|| format!("{} ms", 2 * (i64::from(ones) - 1)))
            }
            _ => None,
        }
    }

    fn parse_value(
        &self,
        row: &ParamRow,
        text: &str,
        axis_value: &dyn Fn(u16) -> Option<i64>,
    ) -> Result<i64, ParamError> {
        let _ = axis_value;
        let (spec, index) = field_of(row).ok_or_else(|| not_a_setting(row))?;
        // A flag, mask or current-step name that is not one is as wrong
        // as a number that is not a number: the field's text is refused.
        parse_value(&spec.fields[index], text.trim())
            .map_err(|why| ParamError::new(ParamRefusal::NotANumber, why.to_string()))
    }
}

fn not_a_setting(row: &ParamRow) -> ParamError {
    ParamError::new(
        ParamRefusal::NotAParameter,
        format!("{} is not a SIXpack 2 setting", row.name),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::parameters::SpeedUnit;

    fn find(axis: u8, scope: Scope, name: &str) -> ParamRow {
        Sixpack2Parameters
            .tables(axis)
            .into_iter()
            .find(|t| t.scope == scope)
            .and_then(|t| t.rows.into_iter().find(|r| r.name == name))
            .unwrap_or_else(|| panic!("{name} in {scope:?}"))
    }

    fn none(_: u16) -> Option<i64> {
        None
    }

    #[test]
    fn every_motor_table_holds_its_settings_write_only_with_factory_values() {
        let tables = Sixpack2Parameters.tables(2);
        assert_eq!(tables.len(), 1 + BANKS.len());
        let motor = &tables[0];
        assert!(motor.title.starts_with("motor 2 (Motor 3): written only"));
        let names: Vec<&str> = motor.rows.iter().map(|r| r.name.as_str()).collect();
        for name in [
            "peak",
            "I0",
            "T0",
            "vmin",
            "vstart",
            "div",
            "amax",
            "vmax",
            "poslimit",
            "flags",
            "vrefmax",
            "debounce",
            "nulloffset",
            "testnullrange",
            "propdiv",
            "intinpclip",
            "minleft",
            "maxright",
        ] {
            assert!(names.contains(&name), "{name} in {names:?}");
        }
        assert!(motor.rows.iter().all(|r| r.access == WRITE_ONLY));
        assert_eq!(find(2, Scope::Axis(2), "vmax").default, Some(511));
        assert_eq!(find(2, Scope::Axis(2), "flags").default, Some(0x0AA0));
        assert_eq!(
            find(2, Scope::Axis(2), "maxright").default,
            None,
            "not given (E31)"
        );
        assert_eq!(find(0, Scope::Bank(1), "address").role, ParamRole::Link);
        assert_eq!(find(0, Scope::Bank(1), "timeout").role, ParamRole::Setting);
        assert!(
            Sixpack2Parameters.tables(6).len() == BANKS.len(),
            "no motor 6"
        );
        // §6.3.2 / digest D4: the default sine table.
        let table: Vec<i64> = (0..16)
            .map(|i| {
                find(0, Scope::Bank(0), &format!("table[{i}]"))
                    .default
                    .unwrap_or(-1)
            })
            .collect();
        assert_eq!(
            table,
            [
                13, 37, 62, 86, 109, 131, 152, 171, 189, 205, 219, 231, 240, 247, 252, 255
            ]
        );
    }

    #[test]
    fn nothing_reads_or_stores_and_few_settings_write_alone() {
        let vmax = find(0, Scope::Axis(0), "vmax");
        let error = Sixpack2Parameters
            .line(&vmax, ParamOp::Read)
            .unwrap_err()
            .to_string();
        assert!(error.contains("cannot read vmax back"), "{error}");
        assert!(Sixpack2Parameters.line(&vmax, ParamOp::Store).is_err());
        let error = Sixpack2Parameters
            .line(&vmax, ParamOp::Write(400))
            .unwrap_err()
            .to_string();
        assert_eq!(
            error,
            "vmax is written together with amax by SetAMaxVMax ($14); the unit cannot read them \
             back, so type `SetAMaxVMax 0 AMAX 400` in the command pane"
        );
        let error = Sixpack2Parameters
            .line(&vmax, ParamOp::Write(600))
            .unwrap_err()
            .to_string();
        assert_eq!(error, "vmax takes 1..511, not 600");
        let peak = find(4, Scope::Axis(4), "peak");
        assert_eq!(
            Sixpack2Parameters
                .line(&peak, ParamOp::Write(200))
                .as_deref(),
            Ok("SetPeakCurrent 4 200")
        );
        let odd = find(5, Scope::Axis(5), "peak");
        let error = Sixpack2Parameters
            .line(&odd, ParamOp::Write(200))
            .unwrap_err()
            .to_string();
        assert!(error.contains("set on motor 4"), "{error}");
        let clkdiv = find(0, Scope::Bank(0), "clkdiv");
        assert_eq!(
            Sixpack2Parameters
                .line(&clkdiv, ParamOp::Write(3))
                .as_deref(),
            Ok("SetClockDivider 3")
        );
        let address = find(0, Scope::Bank(1), "address");
        assert_eq!(
            Sixpack2Parameters
                .line(&address, ParamOp::Write(9))
                .as_deref(),
            Ok("SetUnitAddress 9")
        );
        let entry = find(0, Scope::Bank(0), "table[5]");
        let error = Sixpack2Parameters
            .line(&entry, ParamOp::Write(9))
            .unwrap_err()
            .to_string();
        assert!(error.contains("`WriteMotorTable 4 E0 9 E2 E3`"), "{error}");
        let limit = find(0, Scope::Bank(7), "maxright");
        let error = Sixpack2Parameters
            .line(&limit, ParamOp::Write(900))
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("`SetStopSwitchLimits 7 MINLEFT 900`"),
            "{error}"
        );
    }

    fn writes(line: &str) -> Vec<(Scope, u16, i64)> {
        let parsed = super::super::line::parse_line(line, None).expect("valid");
        written_by(&parsed.request)
            .into_iter()
            .map(|w| (w.scope, w.number, w.value))
            .collect()
    }

    #[test]
    fn a_setting_line_writes_the_rows_of_its_fields() {
        assert_eq!(
            writes("SetAMaxVMax 2 100 300"),
            [(Scope::Axis(2), 0x1401, 100), (Scope::Axis(2), 0x1402, 300)]
        );
        assert_eq!(writes("SetClockDivider 3"), [(Scope::Bank(0), 0x1200, 3)]);
        assert_eq!(
            writes("SetPacketTimeout 25"),
            [(Scope::Bank(1), 0x4100, 25)]
        );
        assert_eq!(
            writes("WriteMotorTable 4 1 2 3 4"),
            [
                (Scope::Bank(0), 0x1704, 1),
                (Scope::Bank(0), 0x1705, 2),
                (Scope::Bank(0), 0x1706, 3),
                (Scope::Bank(0), 0x1707, 4)
            ]
        );
        assert_eq!(
            writes("SetStopSwitchLimits 7 10 900"),
            [(Scope::Bank(7), 0x3101, 10), (Scope::Bank(7), 0x3102, 900)]
        );
        assert_eq!(
            writes("SetStopSwitchLimits 1 10 900"),
            [(Scope::Axis(1), 0x3101, 10), (Scope::Axis(1), 0x3102, 900)]
        );
        // §7.1: the pair's peak current is set on the even motor only.
        assert_eq!(
            writes("SetPeakCurrent 2 200"),
            [(Scope::Axis(2), 0x1001, 200), (Scope::Axis(3), 0x1001, 200)]
        );
        assert!(writes("SetPeakCurrent 3 200").is_empty());
        assert!(writes("StartRamp 0 100").is_empty(), "a motion");
        assert!(writes("GetPositionAndActivity 0").is_empty());
        // Every row written is a row of the tables.
        for line in [
            "SetCurrentControl 0 0% 50% 75% 100% 500",
            "SetVMinVStart 5 4 5 2",
            "SetMotorParameters 1 10000 NullLeft,MechRef",
            "SetRefSearchParameters 0 100 $0FFF 0",
            "SetNullPointOffset 0 -5 240",
            "SetPIParameters 0 8 129 129 1",
            "SetOutputs 1 0 0 0",
            "SetReadyMask all all",
            "SetBaudRate 65 3",
            "SetUnitAddress 4",
        ] {
            let rows = writes(line);
            assert!(!rows.is_empty(), "{line}");
            for (scope, number, _) in rows {
                let axis = match scope {
                    Scope::Axis(n) => n,
                    Scope::Bank(_) => 0,
                };
                assert!(
                    Sixpack2Parameters
                        .tables(axis)
                        .iter()
                        .any(|t| t.scope == scope && t.rows.iter().any(|r| r.number == number)),
                    "{line}: {scope:?} {number:04X}"
                );
            }
        }
    }

    #[test]
    fn a_row_written_with_others_takes_their_known_values() {
        let vmax = find(0, Scope::Axis(0), "vmax");
        let amax_known = |scope: Scope, number: u16| {
            (scope == Scope::Axis(0) && number == 0x1401).then_some(100)
        };
        assert_eq!(
            Sixpack2Parameters
                .line_with(&vmax, ParamOp::Write(400), &amax_known)
                .as_deref(),
            Ok("SetAMaxVMax 0 100 400")
        );
        let entry = find(0, Scope::Bank(0), "table[5]");
        let error = Sixpack2Parameters
            .line_with(&entry, ParamOp::Write(9), &|_, n| {
                (n == 0x1704).then_some(1)
            })
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("with the other entries of its group of four")
                && error.contains("`WriteMotorTable 4 1 9 E2 E3`"),
            "{error}"
        );
        let all = |_: Scope, n: u16| Some(i64::from(n & 0xFF));
        assert_eq!(
            Sixpack2Parameters
                .line_with(&entry, ParamOp::Write(9), &all)
                .as_deref(),
            Ok("WriteMotorTable 4 4 9 6 7")
        );
    }

    #[test]
    fn values_read_as_a_technician_reads_them() {
        let flags = find(1, Scope::Axis(1), "flags");
        assert_eq!(
            Sixpack2Parameters
                .value_note(&flags, 0x0410, &|_, _| None)
                .as_deref(),
            Some("NullLeft,MechRef")
        );
        assert_eq!(
            Sixpack2Parameters.parse_value(&flags, "NullLeft,MechRef", &none),
            Ok(0x0410)
        );
        let debounce = find(1, Scope::Axis(1), "debounce");
        assert_eq!(
            Sixpack2Parameters
                .value_note(&debounce, 0x0FFF, &|_, _| None)
                .as_deref(),
            Some("22 ms")
        );
        assert_eq!(
            Sixpack2Parameters.value_note(&debounce, 0x0F0F, &|_, _| None),
            None
        );
        let t0 = find(1, Scope::Axis(1), "T0");
        let shown = Sixpack2Parameters.physical(&t0, 500, SpeedUnit::Pps, &none);
        assert_eq!(shown.map(|p| p.to_string()).as_deref(), Some("1000 ms"));
        let i1 = find(1, Scope::Axis(1), "I1");
        let shown = Sixpack2Parameters.physical(&i1, 2, SpeedUnit::Pps, &none);
        assert_eq!(
            shown.map(|p| p.to_string()).as_deref(),
            Some("50 % of peak")
        );
        assert_eq!(Sixpack2Parameters.parse_value(&i1, "38%", &none), Ok(3));
        let ready = find(0, Scope::Bank(0), "active");
        assert_eq!(
            Sixpack2Parameters
                .value_note(&ready, 0x3F, &|_, _| None)
                .as_deref(),
            Some("all")
        );
    }
}
