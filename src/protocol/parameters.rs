//! Parameters as the console's parameter table sees them, whatever the
//! family: tables of rows (number, name, unit, range, access), the console
//! line that reads, writes, stores or restores one, and the real-world
//! value of a raw one where the family knows a conversion.
//!
//! A family offers this through [`super::console::FamilyConsole::parameters`];
//! the rows come from its own manual tables (TMCL: `tmcl::params`). Pure
//! code, no I/O.

use std::fmt;

/// Which table a parameter lives in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Scope {
    /// A parameter of one axis (TMCL axis parameters of motor N).
    Axis(u8),
    /// A global parameter of a bank (TMCL global parameter banks).
    Bank(u8),
}

impl Scope {
    /// The section of a parameter file (`axis.0`, `bank.2`).
    pub fn key(self) -> String {
        match self {
            Scope::Axis(n) => format!("axis.{n}"),
            Scope::Bank(n) => format!("bank.{n}"),
        }
    }
}

/// The values a parameter accepts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamRange {
    /// Every value from `min` to `max` inclusive.
    Span { min: i64, max: i64 },
    /// Only the listed values.
    OneOf(&'static [i64]),
}

impl ParamRange {
    pub fn contains(&self, value: i64) -> bool {
        match self {
            ParamRange::Span { min, max } => (*min..=*max).contains(&value),
            ParamRange::OneOf(values) => values.contains(&value),
        }
    }
}

impl fmt::Display for ParamRange {
    /// `0..255`, or the listed values separated by commas.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamRange::Span { min, max } => write!(f, "{min}..{max}"),
            ParamRange::OneOf(values) => {
                let list: Vec<String> = values.iter().map(|v| v.to_string()).collect();
                f.write_str(&list.join(", "))
            }
        }
    }
}

/// What the host may do with a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ParamAccess {
    pub read: bool,
    pub write: bool,
    /// Can be stored to and restored from the module's EEPROM.
    pub store: bool,
    /// Written through to EEPROM by every write (no store needed).
    pub auto_stored: bool,
}

impl fmt::Display for ParamAccess {
    /// `R`, `RW`, `RWE`, `RWA`, `W`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (flag, letter) in [
            (self.read, "R"),
            (self.write, "W"),
            (self.store, "E"),
            (self.auto_stored, "A"),
        ] {
            if flag {
                f.write_str(letter)?;
            }
        }
        Ok(())
    }
}

/// What a parameter is to a saved configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamRole {
    /// Part of the configuration: exported, and written back on import.
    Setting,
    /// Motion or run-time state (a target position, a counter): never
    /// exported, since writing it back would move a motor or mean nothing.
    State,
    /// Decides how the module is reached (baud rate, bus address):
    /// exported, but an import only shows a difference and leaves writing
    /// it to the user, since it would cut the connection it is made over.
    Link,
}

/// One parameter of a table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParamRow {
    pub scope: Scope,
    pub number: u16,
    pub name: String,
    /// The raw value's unit; empty for plain numbers, flags and codes.
    pub unit: &'static str,
    pub range: ParamRange,
    pub access: ParamAccess,
    pub role: ParamRole,
    /// The factory default, where the manual gives one.
    pub default: Option<i64>,
    /// One line from the manual.
    pub description: &'static str,
}

/// One table: the parameters of an axis, or of a global bank.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParamTable {
    pub scope: Scope,
    /// "Axis parameters, motor 0", "Bank 0: module configuration".
    pub title: String,
    pub rows: Vec<ParamRow>,
}

/// What to do with one parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamOp {
    Read,
    Write(i64),
    /// Copy the value in RAM to EEPROM.
    Store,
    /// Copy the value in EEPROM back to RAM.
    Restore,
}

/// A raw value in real-world units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Physical {
    pub value: f64,
    pub unit: &'static str,
}

impl fmt::Display for Physical {
    /// Four significant digits are plenty on a console; integers stay
    /// integers.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.value;
        if !v.is_finite() {
            return write!(f, "? {}", self.unit);
        }
        let magnitude = v.abs();
        let decimals = if v.fract() == 0.0 || magnitude >= 1000.0 {
            0
        } else if magnitude >= 100.0 {
            1
        } else if magnitude >= 10.0 {
            2
        } else {
            3
        };
        write!(f, "{v:.decimals$} {}", self.unit)
    }
}

/// Which real-world unit a conversion should give where there is a choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SpeedUnit {
    /// Microsteps per second (and per second² for accelerations).
    #[default]
    Pps,
    /// Revolutions per minute.
    Rpm,
}

/// A reading of the axis status that a family may show in real-world
/// units (the axis pane's units key).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StatusQuantity {
    /// The actual or the target position.
    Position,
    /// The actual speed, or the maximum positioning speed.
    Speed,
}

/// What kind of refusal a parameter line or an edited value holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamRefusal {
    /// The row is not a parameter of the family.
    NotAParameter,
    /// A write to a parameter the module only reads out.
    ReadOnly,
    /// A read of a parameter the module only takes.
    NotReadable,
    /// A value outside the parameter's range.
    OutOfRange,
    /// A store or restore of a parameter that has no non-volatile copy.
    NotStorable,
    /// Text that is not a number.
    NotANumber,
    /// A unit the parameter is not in.
    WrongUnit,
    /// A conversion that needs another parameter read from the module first.
    NeedsReading,
    /// An operation the family does not do on this row (an MCCL setting
    /// outside an axis, a write the family cannot make on its own).
    NotDone,
}

/// Why a parameter line or an edited value was refused: its kind, and the
/// family's words for the technician (naming the parameter, its range or
/// its access, as the manual gives them).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct ParamError {
    pub kind: ParamRefusal,
    pub message: String,
}

impl ParamError {
    pub fn new(kind: ParamRefusal, message: impl Into<String>) -> ParamError {
        ParamError {
            kind,
            message: message.into(),
        }
    }
}

impl From<ParamError> for String {
    fn from(error: ParamError) -> String {
        error.message
    }
}

/// A family's parameters, for the parameter table.
pub trait ParameterSet: Send + Sync {
    /// The tables for the axis numbered `axis`: its axis parameters first,
    /// then every global bank.
    fn tables(&self, axis: u8) -> Vec<ParamTable>;

    /// The console line doing `op` on `row`, or why there is none (the
    /// parameter cannot be stored, the value is out of range).
    fn line(&self, row: &ParamRow, op: ParamOp) -> Result<String, ParamError>;

    /// [`ParameterSet::line`] for a family that writes several
    /// parameters in one line (SIXpack 2 `$14`: amax and vmax): the others
    /// take their values from `known` (what was written this session, an
    /// imported file's values). By default the same as `line`.
    fn line_with(
        &self,
        row: &ParamRow,
        op: ParamOp,
        known: &dyn Fn(Scope, u16) -> Option<i64>,
    ) -> Result<String, ParamError> {
        let _ = known;
        self.line(row, op)
    }

    /// Whether the rows the module cannot read back are known from what
    /// the session wrote ([`crate::protocol::settings::SettingsCache`]):
    /// then the table shows, exports and compares them from it. `false`
    /// by default (such rows are actions, shown as write-only).
    fn remembers_writes(&self) -> bool {
        false
    }

    /// `value` of `row` in real-world units, if the family converts it;
    /// `axis_value` gives other parameters of the same axis (divisors,
    /// resolution) as read from the module, `None` where not read yet.
    fn physical(
        &self,
        row: &ParamRow,
        value: i64,
        unit: SpeedUnit,
        axis_value: &dyn Fn(u16) -> Option<i64>,
    ) -> Option<Physical> {
        let _ = (row, value, unit, axis_value);
        None
    }

    /// The axis parameters [`ParameterSet::status_physical`] converts
    /// with, which the console reads from the module before it shows
    /// status in real-world units. Empty (the default) when the family
    /// converts no status reading.
    fn status_inputs(&self) -> &'static [u16] {
        &[]
    }

    /// A status reading of an axis in real-world units: with
    /// [`SpeedUnit::Pps`] in the module's own steps, with
    /// [`SpeedUnit::Rpm`] in revolutions. `axis_value` gives the
    /// [`ParameterSet::status_inputs`] of that axis as read from the
    /// module, `None` where not read yet.
    fn status_physical(
        &self,
        quantity: StatusQuantity,
        value: i64,
        unit: SpeedUnit,
        axis_value: &dyn Fn(u16) -> Option<i64>,
    ) -> Option<Physical> {
        let _ = (quantity, value, unit, axis_value);
        None
    }

    /// Where a store puts a value, for the message after it (TMCL: its
    /// EEPROM).
    fn store_place(&self) -> &'static str {
        "EEPROM"
    }

    /// What `value` of `row` means beyond its number and unit, where the
    /// family says more (CMD-4CR: a per-axis speed of 0 is the global
    /// one; the POL word field by field, raw). `value_of` gives other
    /// parameters as read from the module (by table and number), `None`
    /// where not read yet.
    fn value_note(
        &self,
        row: &ParamRow,
        value: i64,
        value_of: &dyn Fn(Scope, u16) -> Option<i64>,
    ) -> Option<String> {
        let _ = (row, value, value_of);
        None
    }

    /// `value` of `row` as the table shows it and as an edit of it
    /// starts: [`ParameterSet::parse_value`] reads this text back as
    /// `value`, so that a value confirmed unchanged writes what was read.
    /// The plain number by default; a family whose rows keep a scaled
    /// number (MCCL's reals in thousandths) gives it in its unit.
    fn value_text(&self, row: &ParamRow, value: i64) -> String {
        let _ = row;
        value.to_string()
    }

    /// The values `row` takes, in the terms of
    /// [`ParameterSet::value_text`]: its raw range by default.
    fn range_text(&self, row: &ParamRow) -> String {
        row.range.to_string()
    }

    /// A value as the user typed it for `row`: a number, or (where the
    /// family converts) a number with a real-world unit (`51200 pps`).
    fn parse_value(
        &self,
        row: &ParamRow,
        text: &str,
        axis_value: &dyn Fn(u16) -> Option<i64>,
    ) -> Result<i64, ParamError> {
        let _ = (row, axis_value);
        parse_integer(text)
    }
}

/// A decimal (`-12`) or hexadecimal (`0x1F`) integer.
pub fn parse_integer(text: &str) -> Result<i64, ParamError> {
    let text = text.trim();
    let (negative, digits) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let magnitude = match digits
        .strip_prefix("0x")
        .or_else(|| digits.strip_prefix("0X"))
    {
        Some(hex) => i64::from_str_radix(hex, 16),
        None => digits.parse::<i64>(),
    };
    match magnitude {
        Ok(m) if negative => Ok(-m),
        Ok(m) => Ok(m),
        Err(_) if text.is_empty() => {
            Err(ParamError::new(ParamRefusal::NotANumber, "no value given"))
        }
        Err(_) => Err(ParamError::new(
            ParamRefusal::NotANumber,
            format!("`{text}` is not a number"),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integers_parse_in_decimal_and_hex() {
        assert_eq!(parse_integer(" 1234 "), Ok(1234));
        assert_eq!(parse_integer("-5"), Ok(-5));
        assert_eq!(parse_integer("+7"), Ok(7));
        assert_eq!(parse_integer("0x1F"), Ok(31));
        assert!(parse_integer("").unwrap_err().message.contains("no value"));
        assert!(parse_integer("12a").unwrap_err().message.contains("`12a`"));
        assert!(parse_integer("99999999999999999999").is_err());
    }

    #[test]
    fn access_and_ranges_read_as_in_the_manuals() {
        let rwe = ParamAccess {
            read: true,
            write: true,
            store: true,
            auto_stored: false,
        };
        assert_eq!(rwe.to_string(), "RWE");
        assert_eq!(ParamRange::Span { min: 0, max: 255 }.to_string(), "0..255");
        assert_eq!(ParamRange::OneOf(&[1, 2, 65]).to_string(), "1, 2, 65");
        assert!(ParamRange::OneOf(&[1, 2, 65]).contains(65));
        assert!(!ParamRange::Span { min: 1, max: 2 }.contains(0));
    }

    #[test]
    fn physical_values_keep_a_sensible_precision() {
        let pps = |value| Physical { value, unit: "pps" }.to_string();
        assert_eq!(pps(51208.49), "51208 pps");
        assert_eq!(pps(60.0), "60 pps");
        assert_eq!(pps(15.2587), "15.26 pps");
        assert_eq!(pps(0.25), "0.250 pps");
        assert_eq!(pps(f64::NAN), "? pps");
    }

    #[test]
    fn scopes_name_their_file_sections() {
        assert_eq!(Scope::Axis(0).key(), "axis.0");
        assert_eq!(Scope::Bank(3).key(), "bank.3");
    }
}
