//! The CMD-4CR's settings for the console's parameter table
//! ([`ParameterSet`]), taken from the command table: one table per axis
//! (speed profile, polarity and I/O configuration, StepNLoop, MPG,
//! joystick, sync, latch, counters) and global tables (speed profile,
//! system, I/O configuration and boot states, joystick limits, standalone
//! programs). A row's number is its command-table row and index, so the
//! rows need no numbering of their own.
//!
//! STORE saves every setting of Table 2-19 at once (§2.1.7); there is no
//! command that reloads one from flash (stored values load at power-on).

use super::catalog::{Axis, COMMANDS, CommandSpec, Form, Format, Kind};
use super::command::{Cmd4crCommand, Selector, format_value, parse_thousandths};
use super::reply::{Mst, describe_pol};
use crate::protocol::parameters::{
    ParamAccess, ParamError, ParamOp, ParamRange, ParamRefusal, ParamRole, ParamRow, ParamTable,
    ParameterSet, Scope, parse_integer,
};

/// The axes a per-axis setting exists for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Axes {
    All,
    /// Joystick settings: X follows AI1, Y AI2 (§2.5.1 Table 2-23).
    XY,
}

/// The per-axis settings, in the order of the axis table.
const AXIS_ROWS: &[(&str, Axes)] = &[
    // Speed profile (§2.1.4, §2.4.1).
    ("HSPD", Axes::All),
    ("LSPD", Axes::All),
    ("ACC", Axes::All),
    ("DEC", Axes::All),
    ("SCV", Axes::All),
    ("SSPDM", Axes::All),
    // Polarity and I/O configuration (§2.1.6, §2.1.3.1.1, §2.2.5.1).
    ("POL", Axes::All),
    ("SDE", Axes::All),
    ("SDC", Axes::All),
    ("INP", Axes::All),
    ("ERC", Axes::All),
    ("ERCD", Axes::All),
    ("ERCP", Axes::All),
    ("ZCNT", Axes::All),
    // StepNLoop (§2.5.3).
    ("SL", Axes::All),
    ("SLR", Axes::All),
    ("SLT", Axes::All),
    ("SLE", Axes::All),
    ("SLA", Axes::All),
    ("SLS", Axes::All),
    // MPG (§2.5.2).
    ("MPE", Axes::All),
    ("MPM", Axes::All),
    ("MPD", Axes::All),
    ("MP", Axes::All),
    // Joystick (§2.5.1).
    ("JMAX", Axes::XY),
    ("JMIN", Axes::XY),
    ("JTOL", Axes::XY),
    ("JSPD", Axes::XY),
    ("JDEL", Axes::XY),
    // Sync output and latch (§2.1.3.2).
    ("SYNC", Axes::All),
    ("SYNP", Axes::All),
    ("SYNMAX", Axes::All),
    ("SYNMIN", Axes::All),
    ("SYNS", Axes::All),
    ("LTS", Axes::All),
    ("LTP", Axes::All),
    ("LTE", Axes::All),
    // Counters and status (§2.6).
    ("P", Axes::All),
    ("E", Axes::All),
    ("D", Axes::All),
    ("PS", Axes::All),
    ("MST", Axes::All),
];

/// A global table: its bank number, title and rows (a keyword's bare form,
/// or every number of its indexed form).
struct Bank {
    number: u8,
    title: &'static str,
    rows: &'static [(&'static str, Shape)],
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Shape {
    Bare,
    Indexed,
}

const BANKS: &[Bank] = &[
    Bank {
        number: 0,
        title: "Global speed profile and interpolation (§2.1.4, §2.3.1)",
        rows: &[
            ("HSPD", Shape::Bare),
            ("LSPD", Shape::Bare),
            ("ACC", Shape::Bare),
            ("DEC", Shape::Bare),
            ("EINT", Shape::Bare),
            ("MM", Shape::Bare),
        ],
    },
    Bank {
        number: 1,
        title: "System (§2.1.1, §2.1.3.1, §3.2)",
        rows: &[
            ("ID", Shape::Bare),
            ("DB", Shape::Bare),
            ("IERR", Shape::Bare),
            ("EXST", Shape::Bare),
        ],
    },
    Bank {
        number: 2,
        title: "I/O configuration, boot states and I/O now (§2.1.3, §2.1.5)",
        rows: &[
            ("DIP", Shape::Bare),
            ("DOP", Shape::Bare),
            ("IOP", Shape::Bare),
            ("IOCFG", Shape::Bare),
            ("EOBOOT", Shape::Bare),
            ("DOBOOT", Shape::Bare),
            ("IOBOOT", Shape::Bare),
            ("EO", Shape::Bare),
            ("DO", Shape::Bare),
            ("IO", Shape::Bare),
            ("DI", Shape::Bare),
            ("AI", Shape::Indexed),
            ("PWM", Shape::Indexed),
        ],
    },
    Bank {
        number: 3,
        title: "Joystick (§2.5.1)",
        rows: &[("JENA", Shape::Bare), ("JLIM", Shape::Indexed)],
    },
    Bank {
        number: 4,
        title: "Standalone programs and variables (§2.7)",
        rows: &[
            ("SLOAD", Shape::Bare),
            ("SAP", Shape::Bare),
            ("SASTAT", Shape::Indexed),
            ("SPC", Shape::Indexed),
            ("V", Shape::Indexed),
        ],
    },
];

/// Settings that decide how the controller is reached (§2.1.1.1, §3.2.1).
const LINK: &[&str] = &["ID", "DB"];

/// Values that are motion state or live I/O, not configuration: writing a
/// saved one back would move a counter or switch an output.
const STATE: &[&str] = &["P", "E", "MP", "EO", "DO", "IO", "PWM"];

/// The power-on values the manual states, by keyword; every other setting
/// has none (the speeds, ramps, POL, the boot values: the manual gives no
/// number). Where the manual says it:
/// - ID 01 "shipped from the factory" (§2.1.1.1, §3.3); DB 1, "a baud rate
///   setting of 9600 bps" by default (§3.2.1, Table 3-39 code 1).
/// - EXST=0 by default (§2.1.1.2, §2.1.3.1.3); IERR=0 by default
///   (§2.1.3.1.1.1 "Limit error", §2.1.3.1.2).
/// - SDE[axis]=0 and SDC[axis]=0 by default (§2.1.3.1.1.2).
/// - SCV[axis]=0: "By default, the Commander core uses a linear
///   acceleration profile" (§2.1.4).
/// - EINT=1: "By default, interpolation is enabled" (§2.3.1).
/// - DIP=0: the pin table gives DI1–DI4 "Negative#", which Note 4 says is
///   the terminal's initial logic (§6.1.1.2), and DIP 0 is negative logic
///   (§2.1.6.3). DOP has no such row: the pin table says DO1–DO4 are
///   "Positive" without the `#` of a logic software can change, while
///   §2.1.6.3 says DOP toggles it, so its power-on value is left unknown.
const FACTORY_DEFAULTS: &[(&str, i64)] = &[
    ("ID", 1),
    ("DB", 1),
    ("EXST", 0),
    ("IERR", 0),
    ("SDE", 0),
    ("SDC", 0),
    ("SCV", 0),
    ("EINT", 1),
    ("DIP", 0),
];

/// The manual's power-on value of a command's setting, if it gives one.
fn factory_default(spec: &CommandSpec) -> Option<i64> {
    FACTORY_DEFAULTS
        .iter()
        .find(|(keyword, _)| *keyword == spec.keyword)
        .map(|&(_, value)| value)
}

/// Per-axis settings whose 0 means "use the global one" (§2.1.4), and the
/// global table that holds it.
const GLOBAL_WHEN_ZERO: &[&str] = &["HSPD", "LSPD", "ACC", "DEC"];
const GLOBAL_PROFILE_BANK: u8 = 0;

/// A row number: the command-table row in the high bits, the index (or 0)
/// in the low seven.
fn number_of(row_index: usize, index: u8) -> u16 {
    u16::try_from(row_index).unwrap_or(u16::MAX >> 7) << 7 | u16::from(index & 0x7F)
}

fn decode(number: u16) -> Option<(&'static CommandSpec, u8)> {
    let spec = COMMANDS.get(usize::from(number >> 7))?;
    Some((spec, (number & 0x7F) as u8))
}

fn row_of(keyword: &str, form: fn(Form) -> bool) -> Option<(usize, &'static CommandSpec)> {
    COMMANDS
        .iter()
        .enumerate()
        .find(|(_, c)| c.keyword == keyword && form(c.form))
}

fn role(spec: &CommandSpec) -> ParamRole {
    if LINK.contains(&spec.keyword) {
        ParamRole::Link
    } else if !spec.access.writes() || STATE.contains(&spec.keyword) {
        ParamRole::State
    } else {
        ParamRole::Setting
    }
}

fn param_row(scope: Scope, row_index: usize, index: u8, name: String) -> Option<ParamRow> {
    let spec = COMMANDS.get(row_index)?;
    let values = spec.values?;
    Some(ParamRow {
        scope,
        number: number_of(row_index, index),
        name,
        unit: match values.format {
            // Shown as the ratio itself (`value_text`), not in thousandths.
            Format::Thousandths => "pulses/count",
            _ => values.unit,
        },
        range: ParamRange::Span {
            min: values.min,
            max: values.max,
        },
        access: ParamAccess {
            read: spec.access.reads(),
            write: spec.access.writes(),
            store: spec.stored,
            auto_stored: false,
        },
        role: role(spec),
        default: factory_default(spec),
        description: spec.meaning,
    })
}

/// `HSPDX`, `AI2`, `HSPD`: how the console writes the command of a row.
fn name(spec: &CommandSpec, selector: Selector) -> String {
    match selector {
        Selector::All => spec.keyword.to_string(),
        Selector::Axis(axis) => format!("{}{}", spec.keyword, axis.letter()),
        Selector::Index(n) => format!("{}{n}", spec.keyword),
    }
}

/// The command a row reads and writes, for the scope it is shown in.
fn selector_of(row: &ParamRow, spec: &CommandSpec, index: u8) -> Option<Selector> {
    match (spec.form, row.scope) {
        (Form::Axis, Scope::Axis(axis)) => Axis::from_index(usize::from(axis)).map(Selector::Axis),
        (Form::Bare, Scope::Bank(_)) => Some(Selector::All),
        (Form::Index { first, last }, Scope::Bank(_)) if (first..=last).contains(&index) => {
            Some(Selector::Index(index))
        }
        _ => None,
    }
}

/// Whether a row's value is a decimal held in thousandths (SLR).
fn is_thousandths(row: &ParamRow) -> bool {
    decode(row.number)
        .and_then(|(spec, _)| spec.values)
        .is_some_and(|v| v.format == Format::Thousandths)
}

/// The CMD-4CR's parameters for the console.
#[derive(Debug, Clone, Copy, Default)]
pub struct Cmd4crParameters;

impl ParameterSet for Cmd4crParameters {
    fn tables(&self, axis: u8) -> Vec<ParamTable> {
        let mut tables = Vec::new();
        if let Some(letter) = Axis::from_index(usize::from(axis)) {
            let rows = AXIS_ROWS
                .iter()
                .filter(|(_, axes)| *axes == Axes::All || matches!(letter, Axis::X | Axis::Y))
                .filter_map(|(keyword, _)| row_of(keyword, |f| f == Form::Axis))
                .filter_map(|(i, spec)| {
                    param_row(Scope::Axis(axis), i, 0, name(spec, Selector::Axis(letter)))
                })
                .collect();
            tables.push(ParamTable {
                scope: Scope::Axis(axis),
                title: format!("Axis {}", letter.letter()),
                rows,
            });
        }
        for bank in BANKS {
            let scope = Scope::Bank(bank.number);
            let mut rows = Vec::new();
            for &(keyword, shape) in bank.rows {
                let found = match shape {
                    Shape::Bare => row_of(keyword, |f| f == Form::Bare),
                    Shape::Indexed => row_of(keyword, |f| matches!(f, Form::Index { .. })),
                };
                let Some((i, spec)) = found else { continue };
                match spec.form {
                    Form::Index { first, last } => rows
                        .extend((first..=last).filter_map(|n| {
                            param_row(scope, i, n, name(spec, Selector::Index(n)))
                        })),
                    _ => rows.extend(param_row(scope, i, 0, name(spec, Selector::All))),
                }
            }
            tables.push(ParamTable {
                scope,
                title: bank.title.to_string(),
                rows,
            });
        }
        tables
    }

    fn line(&self, row: &ParamRow, op: ParamOp) -> Result<String, ParamError> {
        let not_a_parameter = || {
            ParamError::new(
                ParamRefusal::NotAParameter,
                format!("{} is not a CMD-4CR parameter", row.name),
            )
        };
        let (spec, index) = decode(row.number).ok_or_else(not_a_parameter)?;
        let Kind::Register(register) = spec.kind else {
            return Err(not_a_parameter());
        };
        let selector = selector_of(row, spec, index).ok_or_else(not_a_parameter)?;
        let command = name(spec, selector);
        match op {
            ParamOp::Read if spec.access.reads() => {
                Ok(Cmd4crCommand::Read { register, selector }.to_string())
            }
            ParamOp::Read => Err(ParamError::new(
                ParamRefusal::NotReadable,
                format!("{command} cannot be read ({})", spec.syntax),
            )),
            ParamOp::Write(value) if spec.access.writes() => {
                let values = spec.values.ok_or_else(not_a_parameter)?;
                if !values.contains(value) {
                    return Err(ParamError::new(
                        ParamRefusal::OutOfRange,
                        format!(
                            "{command} takes {}..{}, not {}",
                            format_value(values.min, values.format),
                            format_value(values.max, values.format),
                            format_value(value, values.format)
                        ),
                    ));
                }
                Ok(Cmd4crCommand::Write {
                    register,
                    selector,
                    value,
                }
                .to_string())
            }
            ParamOp::Write(_) => Err(ParamError::new(
                ParamRefusal::ReadOnly,
                format!("{command} is read-only ({})", spec.syntax),
            )),
            ParamOp::Store if spec.stored => Ok("STORE".into()),
            ParamOp::Store => Err(ParamError::new(
                ParamRefusal::NotStorable,
                format!(
                    "{command} is not kept in flash: STORE saves only the settings of Table 2-19 \
                     (§2.1.7)"
                ),
            )),
            ParamOp::Restore => Err(ParamError::new(
                ParamRefusal::NotDone,
                format!(
                    "the CMD-4CR has no command reloading {command} from flash: stored values load \
                     at power-on (§2.1.7)"
                ),
            )),
        }
    }

    /// SLR as the ratio it is (`1.500`, what `parse_value` reads back as
    /// 1500 thousandths), the rest as plain numbers.
    fn value_text(&self, row: &ParamRow, value: i64) -> String {
        if !is_thousandths(row) {
            return value.to_string();
        }
        let sign = if value < 0 { "-" } else { "" };
        let magnitude = value.unsigned_abs();
        format!("{sign}{}.{:03}", magnitude / 1000, magnitude % 1000)
    }

    /// SLR's range as ratios (`0.001..999.999`).
    fn range_text(&self, row: &ParamRow) -> String {
        match row.range {
            ParamRange::Span { min, max } if is_thousandths(row) => {
                format!(
                    "{}..{}",
                    self.value_text(row, min),
                    self.value_text(row, max)
                )
            }
            range => range.to_string(),
        }
    }

    /// §2.1.7: STORE writes every setting of Table 2-19 at once.
    fn store_place(&self) -> &'static str {
        "flash, with every setting of Table 2-19"
    }

    fn value_note(
        &self,
        row: &ParamRow,
        value: i64,
        value_of: &dyn Fn(Scope, u16) -> Option<i64>,
    ) -> Option<String> {
        let (spec, _) = decode(row.number)?;
        if !matches!(row.scope, Scope::Axis(_)) {
            return None;
        }
        match spec.keyword {
            keyword if GLOBAL_WHEN_ZERO.contains(&keyword) && value == 0 => {
                let (global, _) = row_of(keyword, |f| f == Form::Bare)?;
                // Short enough for the table's column; the row's unit is
                // the global one's.
                Some(
                    match value_of(Scope::Bank(GLOBAL_PROFILE_BANK), number_of(global, 0)) {
                        Some(v) => format!("global {v}"),
                        None => format!("global {keyword}"),
                    },
                )
            }
            // Table 2-17 is lost: the fields by name, their bits raw.
            "POL" => Some(describe_pol(value)),
            "MST" => {
                let names: Vec<&str> = Mst::from_value(value).set_bits().map(|b| b.name).collect();
                Some(if names.is_empty() {
                    "stopped, no input on".into()
                } else {
                    names.join(", ")
                })
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
        if is_thousandths(row) {
            parse_thousandths(text.trim()).ok_or_else(|| {
                ParamError::new(
                    ParamRefusal::NotANumber,
                    format!("`{}` is not a number with at most 3 decimals", text.trim()),
                )
            })
        } else {
            parse_integer(text)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(axis: u8, scope: Scope) -> ParamTable {
        Cmd4crParameters
            .tables(axis)
            .into_iter()
            .find(|t| t.scope == scope)
            .expect("the table")
    }

    fn row(axis: u8, scope: Scope, name: &str) -> ParamRow {
        table(axis, scope)
            .rows
            .into_iter()
            .find(|r| r.name == name)
            .unwrap_or_else(|| panic!("{name}"))
    }

    fn line(row: &ParamRow, op: ParamOp) -> Result<String, String> {
        Cmd4crParameters.line(row, op).map_err(String::from)
    }

    #[test]
    fn every_axis_has_its_table_and_joystick_rows_only_on_x_and_y() {
        let x = table(0, Scope::Axis(0));
        assert_eq!(x.title, "Axis X");
        assert_eq!(x.rows[0].name, "HSPDX");
        assert!(x.rows.iter().any(|r| r.name == "JMAXX"));
        let z = table(2, Scope::Axis(2));
        assert!(z.rows.iter().all(|r| !r.name.starts_with("JM")));
        assert!(z.rows.iter().any(|r| r.name == "SLRZ"));
        assert_eq!(Cmd4crParameters.tables(0).len(), 1 + BANKS.len());
        assert_eq!(Cmd4crParameters.tables(9).len(), BANKS.len(), "no axis 9");
        // Every listed row exists in the command table.
        assert_eq!(x.rows.len(), AXIS_ROWS.len());
    }

    #[test]
    fn rows_read_write_and_store_through_their_commands() {
        let hspd = row(1, Scope::Axis(1), "HSPDY");
        assert_eq!(line(&hspd, ParamOp::Read).as_deref(), Ok("HSPDY"));
        assert_eq!(
            line(&hspd, ParamOp::Write(5000)).as_deref(),
            Ok("HSPDY=5000")
        );
        assert!(
            line(&hspd, ParamOp::Write(-1))
                .unwrap_err()
                .contains("0..6553500")
        );
        assert!(
            line(&hspd, ParamOp::Store)
                .unwrap_err()
                .contains("Table 2-19")
        );
        let pol = row(0, Scope::Axis(0), "POLX");
        assert_eq!(line(&pol, ParamOp::Store).as_deref(), Ok("STORE"));
        assert!(
            line(&pol, ParamOp::Restore)
                .unwrap_err()
                .contains("power-on")
        );
        assert_eq!(pol.access.to_string(), "RWE");
        let mst = row(3, Scope::Axis(3), "MSTU");
        assert_eq!(mst.role, ParamRole::State);
        assert!(
            line(&mst, ParamOp::Write(1))
                .unwrap_err()
                .contains("read-only")
        );
        let v = row(0, Scope::Bank(4), "V42");
        assert_eq!(line(&v, ParamOp::Write(-7)).as_deref(), Ok("V42=-7"));
        let ai = row(0, Scope::Bank(2), "AI2");
        assert_eq!(line(&ai, ParamOp::Read).as_deref(), Ok("AI2"));
        let id = row(0, Scope::Bank(1), "ID");
        assert_eq!(id.role, ParamRole::Link);
        assert_eq!(line(&id, ParamOp::Write(2)).as_deref(), Ok("ID=02"));
        let p = row(0, Scope::Axis(0), "PX");
        assert_eq!(p.role, ParamRole::State);
    }

    #[test]
    fn the_steps_per_count_ratio_reads_in_thousandths() {
        let slr = row(0, Scope::Axis(0), "SLRX");
        assert_eq!(slr.unit, "pulses/count");
        let none = |_: u16| None;
        assert_eq!(Cmd4crParameters.parse_value(&slr, "1.5", &none), Ok(1500));
        assert_eq!(line(&slr, ParamOp::Write(1500)).as_deref(), Ok("SLRX=1.5"));
        assert_eq!(Cmd4crParameters.value_text(&slr, 1500), "1.500");
        assert_eq!(Cmd4crParameters.value_text(&slr, -2), "-0.002");
        let hspd = row(0, Scope::Axis(0), "HSPDX");
        assert_eq!(Cmd4crParameters.value_text(&hspd, 4000), "4000");
        assert_eq!(Cmd4crParameters.parse_value(&hspd, "0x10", &none), Ok(16));
    }

    #[test]
    fn a_per_axis_speed_of_zero_names_the_global_one_and_pol_its_fields() {
        let hspd = row(0, Scope::Axis(0), "HSPDX");
        let global = row(0, Scope::Bank(0), "HSPD");
        let read = |scope: Scope, number: u16| {
            (scope == global.scope && number == global.number).then_some(5000)
        };
        let note = |row: &ParamRow, value, read: &dyn Fn(Scope, u16) -> Option<i64>| {
            Cmd4crParameters.value_note(row, value, read)
        };
        assert_eq!(note(&hspd, 0, &read).as_deref(), Some("global 5000"));
        assert_eq!(note(&hspd, 0, &|_, _| None).as_deref(), Some("global HSPD"));
        assert_eq!(note(&hspd, 800, &read), None, "its own");
        let acc = row(2, Scope::Axis(2), "ACCZ");
        assert_eq!(note(&acc, 0, &|_, _| None).as_deref(), Some("global ACC"));
        assert_eq!(
            Cmd4crParameters.store_place(),
            "flash, with every setting of Table 2-19"
        );
        assert_eq!(note(&global, 0, &read), None, "the global one itself");
        let pol = row(0, Scope::Axis(0), "POLX");
        let text = note(&pol, 7, &read).expect("fields");
        assert!(text.starts_with("POL 7: pulse/direction"), "{text}");
        assert!(text.contains("MPG input mode (bits 15-16) = 0"), "{text}");
        let mst = row(1, Scope::Axis(1), "MSTY");
        assert_eq!(note(&mst, 4 | 64, &read).as_deref(), Some("const, HOME"));
        assert_eq!(
            note(&mst, 0, &read).as_deref(),
            Some("stopped, no input on")
        );
        let sync = row(0, Scope::Axis(0), "SYNCX");
        assert_eq!(note(&sync, 1, &read), None, "shown raw");
    }

    #[test]
    fn the_power_on_values_the_manual_states_are_the_rows_defaults() {
        // Written out from the manual: ID 01 from the factory (§3.3), baud
        // code 1 = 9600 (Table 3-39), EINT=1 (§2.3.1), IERR=0
        // (§2.1.3.1.1.1), EXST=0 (§2.1.1.2), SDEX=0 and SDCX=0
        // (§2.1.3.1.1.2), linear profile: SCV 0 (§2.1.4), DI negative logic
        // (§6.1.1.2): DIP 0.
        for (scope, name, default) in [
            (Scope::Bank(1), "ID", 1),
            (Scope::Bank(1), "DB", 1),
            (Scope::Bank(0), "EINT", 1),
            (Scope::Bank(1), "IERR", 0),
            (Scope::Bank(1), "EXST", 0),
            (Scope::Axis(0), "SDEX", 0),
            (Scope::Axis(2), "SDCZ", 0),
            (Scope::Axis(3), "SCVU", 0),
            (Scope::Bank(2), "DIP", 0),
        ] {
            let axis = match scope {
                Scope::Axis(n) => n,
                Scope::Bank(_) => 0,
            };
            assert_eq!(row(axis, scope, name).default, Some(default), "{name}");
        }
        // The manual gives no number for these: no default is made up.
        for (scope, name) in [
            (Scope::Axis(0), "HSPDX"),
            (Scope::Axis(0), "POLX"),
            (Scope::Bank(0), "HSPD"),
            (Scope::Bank(2), "DOP"),
            (Scope::Bank(2), "EOBOOT"),
        ] {
            assert_eq!(row(0, scope, name).default, None, "{name}");
        }
    }

    #[test]
    fn a_row_from_elsewhere_is_refused() {
        let mut foreign = row(0, Scope::Axis(0), "HSPDX");
        foreign.number = u16::MAX;
        assert!(line(&foreign, ParamOp::Read).is_err());
        foreign.number = number_of(0, 0); // ABORT, an action
        assert!(line(&foreign, ParamOp::Read).is_err());
    }
}
