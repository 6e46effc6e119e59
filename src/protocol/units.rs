//! The line's own units (issue 20, point 3): an axis mechanics table kept
//! in the parameter file (`[mechanics.N]`), and values written with a unit
//! suffix (`MVP ABS, 0, 12.5mm`, `1MA90deg`, `HSPDX=20mm/s`) turned into
//! the raw numbers a module takes, and raw readings shown in the axis's
//! unit.
//!
//! Two halves meet here. The mechanics say how many motor steps (or
//! encoder counts) make one unit of travel: `full_steps_per_rev` ×
//! microsteps (or `counts_per_rev`) × `gear_ratio` / `travel_per_rev`.
//! A family's [`UnitLaw`] says how many motor steps one raw unit of a
//! position, speed or acceleration is under the module's current settings
//! (TMCL §6.1 with its pulse and ramp divisors, SIXpack 2 §6.3.1's step
//! frequency, CMD-4CR's pps, MCCL's user scale and rate), and where a
//! line's operands are. Pure code, no I/O: the settings come in as a
//! lookup (read from the module, written this session, or an offline
//! file's own values).

use std::collections::BTreeMap;
use std::fmt;
use std::fmt::Write as _;
use std::ops::Range;

use super::parameters::Scope;

/// What an operand or a reading measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    Position,
    Speed,
    Acceleration,
}

impl Quantity {
    /// `mm`, `mm/s`, `mm/s²` for an axis whose unit is `unit`.
    pub fn unit_text(self, unit: &str) -> String {
        match self {
            Quantity::Position => unit.to_string(),
            Quantity::Speed => format!("{unit}/s"),
            Quantity::Acceleration => format!("{unit}/s²"),
        }
    }

    fn name(self) -> &'static str {
        match self {
            Quantity::Position => "a position or distance",
            Quantity::Speed => "a speed",
            Quantity::Acceleration => "an acceleration",
        }
    }
}

/// What one motor revolution is counted in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotorRevolution {
    /// A stepper of this many full steps, each cut into microsteps.
    FullSteps(u32),
    /// An encoder (or servo) of this many counts.
    Counts(u32),
}

/// One axis's mechanics, as `[mechanics.N]` gives them.
#[derive(Debug, Clone, PartialEq)]
pub struct Mechanics {
    /// `mm`, `deg`, `rev`…: the suffix values are written with.
    pub unit: String,
    pub revolution: MotorRevolution,
    /// Microsteps per full step, where given; a module that has a setting
    /// for it is read instead ([`UnitLaw::microsteps`]).
    pub microsteps: Option<u32>,
    /// Motor revolutions per output revolution (1 when not given).
    pub gear_ratio: f64,
    /// Units of travel per output revolution.
    pub travel_per_rev: f64,
}

// Every number in a Mechanics is finite (checked when read), so equality
// is an equivalence: files holding mechanics compare as wholes.
impl Eq for Mechanics {}

impl fmt::Display for Mechanics {
    /// `200 full steps × 256 µsteps, gear 1, 5 mm a turn`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.revolution, self.microsteps) {
            (MotorRevolution::FullSteps(n), Some(m)) => write!(f, "{n} full steps × {m} µsteps")?,
            (MotorRevolution::FullSteps(n), None) => write!(f, "{n} full steps")?,
            (MotorRevolution::Counts(n), _) => write!(f, "{n} counts")?,
        }
        write!(
            f,
            ", gear {}, {} {} a turn",
            self.gear_ratio, self.travel_per_rev, self.unit
        )
    }
}

/// The mechanics of every axis that has some, by axis number.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct MechanicsTable {
    pub axes: BTreeMap<u8, Mechanics>,
}

const KEYS: &[&str] = &[
    "unit",
    "full_steps_per_rev",
    "counts_per_rev",
    "microsteps",
    "gear_ratio",
    "travel_per_rev",
];

impl MechanicsTable {
    pub fn is_empty(&self) -> bool {
        self.axes.is_empty()
    }

    pub fn get(&self, axis: u8) -> Option<&Mechanics> {
        self.axes.get(&axis)
    }

    /// The `mechanics` table of a parameter file (`[mechanics.0]` …): the
    /// axes that are well formed, and a problem naming each key that is
    /// not (that axis is left out).
    pub fn from_toml(value: &toml::Value) -> (MechanicsTable, Vec<String>) {
        let mut table = MechanicsTable::default();
        let mut problems = Vec::new();
        let toml::Value::Table(groups) = value else {
            problems.push("`mechanics` is not a table of axes ([mechanics.0] …)".into());
            return (table, problems);
        };
        for (index, entry) in groups {
            let Ok(axis) = index.parse::<u8>() else {
                problems.push(format!(
                    "[mechanics.{index}]: `{index}` is not an axis number"
                ));
                continue;
            };
            let toml::Value::Table(keys) = entry else {
                problems.push(format!("[mechanics.{index}] is not a table of mechanics"));
                continue;
            };
            match Mechanics::from_keys(keys) {
                Ok(mechanics) => {
                    table.axes.insert(axis, mechanics);
                }
                Err(why) => problems.push(format!("[mechanics.{axis}] {why}")),
            }
        }
        (table, problems)
    }

    /// The table's text, `[mechanics.N]` sections, for a parameter file.
    pub fn render(&self) -> String {
        let mut out = String::new();
        for (axis, m) in &self.axes {
            let _ = writeln!(out, "\n[mechanics.{axis}]");
            let _ = writeln!(out, "unit = {}", toml::Value::String(m.unit.clone()));
            match m.revolution {
                MotorRevolution::FullSteps(n) => {
                    let _ = writeln!(out, "full_steps_per_rev = {n}");
                }
                MotorRevolution::Counts(n) => {
                    let _ = writeln!(out, "counts_per_rev = {n}");
                }
            }
            if let Some(n) = m.microsteps {
                let _ = writeln!(out, "microsteps = {n}");
            }
            let _ = writeln!(out, "gear_ratio = {}", toml::Value::Float(m.gear_ratio));
            let _ = writeln!(
                out,
                "travel_per_rev = {}  # {} per output revolution",
                toml::Value::Float(m.travel_per_rev),
                m.unit
            );
        }
        out
    }

    /// Read a mechanics file (a parameter file, or one holding only
    /// `[mechanics.N]` sections): the table, and the values of the
    /// file's `[axis.N]` and `[bank.N]` sections (what an offline
    /// conversion takes as the module's settings). Every problem of the
    /// mechanics is an error.
    pub fn parse_file(
        text: &str,
    ) -> Result<(MechanicsTable, Vec<super::parameter_file::Entry>), UnitError> {
        let file = super::parameter_file::parse(text)
            .map_err(|e| UnitError::new(UnitRefusal::BadMechanics, e.to_string()))?;
        let mechanics_problems: Vec<&String> = file
            .problems
            .iter()
            .filter(|p| p.starts_with("[mechanics") || p.starts_with("`mechanics`"))
            .collect();
        if !mechanics_problems.is_empty() {
            return Err(UnitError::new(
                UnitRefusal::BadMechanics,
                mechanics_problems
                    .iter()
                    .map(|p| p.as_str())
                    .collect::<Vec<_>>()
                    .join("; "),
            ));
        }
        if file.mechanics.is_empty() {
            return Err(UnitError::new(
                UnitRefusal::NoMechanics,
                "it has no [mechanics.N] section",
            ));
        }
        Ok((file.mechanics, file.entries))
    }
}

fn positive_integer(keys: &toml::Table, key: &str) -> Result<Option<u32>, String> {
    match keys.get(key) {
        None => Ok(None),
        Some(toml::Value::Integer(n)) if *n > 0 => u32::try_from(*n)
            .map(Some)
            .map_err(|_| format!("{key} = {n} is too large")),
        Some(other) => Err(format!("{key} = {other} is not a whole number above 0")),
    }
}

fn positive_number(keys: &toml::Table, key: &str) -> Result<Option<f64>, String> {
    let value = match keys.get(key) {
        None => return Ok(None),
        Some(toml::Value::Integer(n)) => *n as f64,
        Some(toml::Value::Float(x)) => *x,
        Some(other) => return Err(format!("{key} = {other} is not a number")),
    };
    if value.is_finite() && value > 0.0 {
        Ok(Some(value))
    } else {
        Err(format!("{key} = {value} is not a number above 0"))
    }
}

impl Mechanics {
    fn from_keys(keys: &toml::Table) -> Result<Mechanics, String> {
        if let Some(key) = keys.keys().find(|k| !KEYS.contains(&k.as_str())) {
            return Err(format!(
                "`{key}` is not a mechanics key (keys: {})",
                KEYS.join(", ")
            ));
        }
        let unit = match keys.get("unit") {
            Some(toml::Value::String(unit)) => unit.trim().to_string(),
            Some(other) => return Err(format!("unit = {other} is not a text (\"mm\")")),
            None => return Err("has no unit (unit = \"mm\", \"deg\", \"rev\"…)".into()),
        };
        if unit.is_empty() || !unit.chars().all(|c| c.is_alphabetic()) {
            return Err(format!(
                "unit = \"{unit}\": a unit is letters only (mm, deg, rev), so that `12.5{unit}` reads as one"
            ));
        }
        let full_steps = positive_integer(keys, "full_steps_per_rev")?;
        let counts = positive_integer(keys, "counts_per_rev")?;
        let revolution = match (full_steps, counts) {
            (Some(n), None) => MotorRevolution::FullSteps(n),
            (None, Some(n)) => MotorRevolution::Counts(n),
            (Some(_), Some(_)) => {
                return Err(
                    "gives both full_steps_per_rev and counts_per_rev: a stepper's full steps or an encoder's counts, one of them".into(),
                );
            }
            (None, None) => {
                return Err(
                    "needs full_steps_per_rev (a stepper) or counts_per_rev (an encoder or servo)"
                        .into(),
                );
            }
        };
        let microsteps = positive_integer(keys, "microsteps")?;
        if microsteps.is_some() && matches!(revolution, MotorRevolution::Counts(_)) {
            return Err("microsteps go with full_steps_per_rev, not counts_per_rev".into());
        }
        let travel_per_rev = positive_number(keys, "travel_per_rev")?
            .ok_or_else(|| format!("needs travel_per_rev ({unit} per output revolution)"))?;
        Ok(Mechanics {
            unit,
            revolution,
            microsteps,
            gear_ratio: positive_number(keys, "gear_ratio")?.unwrap_or(1.0),
            travel_per_rev,
        })
    }

    /// Motor steps (microsteps, or encoder counts) per unit of travel,
    /// with `module_microsteps` the module's own setting where it has
    /// one. A module setting and a mechanics value that disagree are an
    /// error: the file would be wrong for this line.
    pub fn steps_per_unit(&self, module_microsteps: Option<u32>) -> Result<f64, UnitError> {
        let per_motor_rev = match self.revolution {
            MotorRevolution::Counts(n) => f64::from(n),
            MotorRevolution::FullSteps(n) => {
                let micro = match (module_microsteps, self.microsteps) {
                    (Some(module), Some(file)) if module != file => {
                        return Err(UnitError::new(
                            UnitRefusal::BadMechanics,
                            format!(
                                "the mechanics say {file} microsteps, the module is set to \
                                 {module}: correct one of them"
                            ),
                        ));
                    }
                    (Some(m), _) | (None, Some(m)) => m,
                    (None, None) => {
                        return Err(UnitError::new(
                            UnitRefusal::BadMechanics,
                            "the microsteps are not known: give microsteps in the mechanics (the \
                             module has no setting for them)",
                        ));
                    }
                };
                f64::from(n) * f64::from(micro)
            }
        };
        Ok(per_motor_rev * self.gear_ratio / self.travel_per_rev)
    }
}

/// What kind of refusal a value in an axis's unit holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnitRefusal {
    /// The number before the unit is not one, or the suffix is no unit.
    NotAUnitValue,
    /// No mechanics for the value's axis.
    NoMechanics,
    /// The mechanics are incomplete, wrong, or disagree with the module.
    BadMechanics,
    /// The axis is in another unit, or the operand takes another quantity.
    WrongUnit,
    /// A setting the conversion needs has not been read from the module.
    NeedsReading,
    /// The family does not take this quantity as a number (CMD-4CR ramps
    /// are times).
    NotConvertible,
    /// The result is no number the command can hold.
    OutOfRange,
}

/// Why a value in an axis's unit was not converted: its kind, and the
/// words for the technician (the value as typed, the axis, the setting
/// missing).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct UnitError {
    pub kind: UnitRefusal,
    pub message: String,
}

impl UnitError {
    pub fn new(kind: UnitRefusal, message: impl Into<String>) -> UnitError {
        UnitError {
            kind,
            message: message.into(),
        }
    }

    /// The same error about the value `text` (`` `12mm`: … ``).
    fn about(self, text: &str) -> UnitError {
        UnitError {
            kind: self.kind,
            message: format!("`{text}`: {}", self.message),
        }
    }
}

impl From<UnitError> for String {
    fn from(error: UnitError) -> String {
        error.message
    }
}

/// The mechanics in force, shared by every module a console works with.
pub type SharedMechanics = std::sync::Arc<std::sync::RwLock<MechanicsTable>>;

/// A value as typed with a unit suffix: `12.5mm`, `20mm/s`, `100mm/s2`.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitAmount {
    pub amount: f64,
    /// The unit without its time part (`mm`).
    pub unit: String,
    pub quantity: Quantity,
}

impl UnitAmount {
    /// `text` read as a number with a unit suffix; `None` when it has no
    /// suffix (a plain number, a symbol, a register): that operand is the
    /// family's to read.
    pub fn parse(text: &str) -> Option<Result<UnitAmount, UnitError>> {
        let text = text.trim();
        let number_end = text
            .char_indices()
            .find(|&(i, c)| !(c.is_ascii_digit() || c == '.' || ((c == '-' || c == '+') && i == 0)))
            .map_or(text.len(), |(i, _)| i);
        let (number, suffix) = text.split_at(number_end);
        // An exponent (MCCL reals, `1.5E3`, Ch2) is part of the number.
        let exponent = suffix
            .strip_prefix(['e', 'E'])
            .map(|rest| rest.strip_prefix(['+', '-']).unwrap_or(rest))
            .is_some_and(|digits| !digits.is_empty() && digits.chars().all(|c| c.is_ascii_digit()));
        if exponent
            || !number.chars().any(|c| c.is_ascii_digit())
            || !suffix.chars().next().is_some_and(char::is_alphabetic)
            || suffix.starts_with(['x', 'X']) && number == "0"
        {
            return None;
        }
        let amount: f64 = match number.parse() {
            Ok(amount) => amount,
            Err(_) => {
                return Some(Err(UnitError::new(
                    UnitRefusal::NotAUnitValue,
                    format!("`{text}`: `{number}` is not a number"),
                )));
            }
        };
        let (unit, per) = match suffix.split_once('/') {
            Some((unit, per)) => (unit, Some(per)),
            None => (suffix, None),
        };
        let quantity = match per {
            None => Quantity::Position,
            Some("s") => Quantity::Speed,
            Some("s2" | "s²" | "s^2") => Quantity::Acceleration,
            Some(other) => {
                return Some(Err(UnitError::new(
                    UnitRefusal::NotAUnitValue,
                    format!(
                        "`{text}`: per `{other}` is no time axterm knows: give {unit}/s or {unit}/s²"
                    ),
                )));
            }
        };
        if !unit.chars().all(char::is_alphabetic) {
            return Some(Err(UnitError::new(
                UnitRefusal::NotAUnitValue,
                format!("`{text}`: `{unit}` is not a unit"),
            )));
        }
        Some(Ok(UnitAmount {
            amount,
            unit: unit.to_string(),
            quantity,
        }))
    }
}

/// One operand of a line that may be given in the axis's units.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Operand {
    /// Where it is in the line (byte offsets).
    pub span: Range<usize>,
    /// The axis it is meant for.
    pub axis: u8,
    /// What it measures in the family's raw terms.
    pub quantity: Quantity,
}

/// A family's settings as the conversion takes them: a row of its
/// parameter set (by table and number), `None` where not known.
pub type ValueOf<'a> = dyn Fn(Scope, u16) -> Option<i64> + 'a;

/// How a family's raw numbers relate to motor steps, from its manual.
pub trait UnitLaw: Send + Sync {
    /// The settings (rows of the family's parameter set) the law converts
    /// with for `axis`: what the console reads (or takes from what was
    /// written) before it converts.
    fn inputs(&self, axis: u8) -> Vec<(Scope, u16)>;

    /// Motor steps (or encoder counts, per the mechanics) in one raw unit
    /// of `quantity` on `axis` (a position unit, a speed unit per second,
    /// an acceleration unit per second²); an error names the setting that
    /// is missing.
    fn steps_per_raw(
        &self,
        axis: u8,
        quantity: Quantity,
        value_of: &ValueOf,
    ) -> Result<f64, UnitError>;

    /// The module's microsteps per full step where it has a setting for
    /// them (`None`: it has none, the mechanics give them).
    fn microsteps(&self, axis: u8, value_of: &ValueOf) -> Option<Result<u32, UnitError>> {
        let _ = (axis, value_of);
        None
    }

    /// The operands of `line` that take a position, speed or acceleration
    /// of an axis: where they are, which axis, what they measure. A line
    /// the family cannot read here has none (its parser says why).
    fn operands(&self, line: &str) -> Vec<Operand>;

    /// What a parameter row holds, where it is an axis's position, speed
    /// or acceleration in the law's raw terms: the parameter table shows
    /// it in the axis's unit. None by default.
    fn row_quantity(&self, row: &super::parameters::ParamRow) -> Option<Quantity> {
        let _ = row;
        None
    }

    /// A converted raw value as the line is written: a whole number by
    /// default (rounded).
    fn raw_text(&self, raw: f64) -> String {
        format!("{}", raw.round() as i64)
    }
}

/// A line with its unit values turned raw.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Converted {
    /// The line as the family reads it.
    pub line: String,
    /// One note per value: `10mm → 102400`.
    pub notes: Vec<String>,
}

impl Converted {
    /// Whether anything was converted.
    pub fn changed(&self) -> bool {
        !self.notes.is_empty()
    }
}

/// Whether `line` gives any value with a unit suffix.
pub fn has_units(law: Option<&dyn UnitLaw>, line: &str) -> bool {
    suffixed(law, line).next().is_some()
}

fn suffixed<'a>(
    law: Option<&dyn UnitLaw>,
    line: &'a str,
) -> impl Iterator<Item = (Operand, &'a str)> + 'a {
    let operands = law.map(|l| l.operands(line)).unwrap_or_default();
    operands.into_iter().filter_map(move |op| {
        let text = line.get(op.span.clone())?;
        UnitAmount::parse(text).map(|_| (op, text))
    })
}

/// The axes whose settings `line`'s unit values need: what to read
/// before [`convert_line`].
pub fn axes_needed(law: &dyn UnitLaw, line: &str) -> Vec<u8> {
    let mut axes: Vec<u8> = suffixed(Some(law), line).map(|(op, _)| op.axis).collect();
    axes.sort_unstable();
    axes.dedup();
    axes
}

/// One unit value of a line, checked against its axis's mechanics.
struct Found<'a> {
    operand: Operand,
    text: &'a str,
    amount: UnitAmount,
    mechanics: &'a Mechanics,
}

/// Every unit value of `line` with its mechanics; an error names the
/// value and what is wrong (no mechanics for its axis, another unit, a
/// speed where a position goes).
fn found<'a>(
    law: &dyn UnitLaw,
    line: &'a str,
    mechanics: &'a MechanicsTable,
) -> Result<Vec<Found<'a>>, UnitError> {
    let mut all = Vec::new();
    for (operand, text) in suffixed(Some(law), line) {
        let amount = match UnitAmount::parse(text) {
            Some(Ok(amount)) => amount,
            Some(Err(why)) => return Err(why),
            None => continue,
        };
        let axis = operand.axis;
        let Some(m) = mechanics.get(axis) else {
            return Err(UnitError::new(
                UnitRefusal::NoMechanics,
                if mechanics.is_empty() {
                    format!("`{text}`: no mechanics are loaded (--mechanics FILE, :mechanics FILE)")
                } else {
                    format!("`{text}`: axis {axis} has no mechanics ([mechanics.{axis}])")
                },
            ));
        };
        if !amount.unit.eq_ignore_ascii_case(&m.unit) {
            return Err(UnitError::new(
                UnitRefusal::WrongUnit,
                format!(
                    "`{text}`: axis {axis} is in {} ({}, {}, {})",
                    m.unit,
                    Quantity::Position.unit_text(&m.unit),
                    Quantity::Speed.unit_text(&m.unit),
                    Quantity::Acceleration.unit_text(&m.unit)
                ),
            ));
        }
        if amount.quantity != operand.quantity {
            return Err(UnitError::new(
                UnitRefusal::WrongUnit,
                format!(
                    "`{text}` is {}, and this operand takes {}: give it in {}",
                    amount.quantity.name(),
                    operand.quantity.name(),
                    operand.quantity.unit_text(&m.unit)
                ),
            ));
        }
        all.push(Found {
            operand,
            text,
            amount,
            mechanics: m,
        });
    }
    Ok(all)
}

/// Check `line`'s unit values against the mechanics without the
/// module's settings: what can be refused before anything is read.
pub fn check_line(
    law: Option<&dyn UnitLaw>,
    line: &str,
    mechanics: &MechanicsTable,
) -> Result<(), UnitError> {
    match law {
        Some(law) => found(law, line, mechanics).map(|_| ()),
        None => Ok(()),
    }
}

/// `line` with every value given in an axis's unit turned into the raw
/// number it is under the module's settings (`value_of`), with a note
/// for each; an error names the value and what is wrong (no mechanics
/// for its axis, another unit, a setting not known, a result no whole
/// number can hold). The family checks the line's ranges afterwards.
pub fn convert_line(
    law: Option<&dyn UnitLaw>,
    line: &str,
    mechanics: &MechanicsTable,
    value_of: &ValueOf,
) -> Result<Converted, UnitError> {
    let unchanged = || Converted {
        line: line.to_string(),
        notes: Vec::new(),
    };
    let Some(law) = law else {
        return Ok(unchanged());
    };
    let all = found(law, line, mechanics)?;
    if all.is_empty() {
        return Ok(unchanged());
    }
    let mut out = String::new();
    let mut notes = Vec::new();
    let mut at = 0;
    for Found {
        operand,
        text,
        amount,
        mechanics: m,
    } in all
    {
        let module_micro = law
            .microsteps(operand.axis, value_of)
            .transpose()
            .map_err(|e| e.about(text))?;
        let steps_per_unit = m.steps_per_unit(module_micro).map_err(|e| e.about(text))?;
        let per_raw = law
            .steps_per_raw(operand.axis, operand.quantity, value_of)
            .map_err(|e| e.about(text))?;
        let raw = amount.amount * steps_per_unit / per_raw;
        if !raw.is_finite() || raw.abs() >= 9.0e15 {
            return Err(UnitError::new(
                UnitRefusal::OutOfRange,
                format!("`{text}` is far out of range ({raw:e} raw)"),
            ));
        }
        let raw_text = law.raw_text(raw);
        out.push_str(line.get(at..operand.span.start).unwrap_or(""));
        out.push_str(&raw_text);
        at = operand.span.end;
        notes.push(format!("{text} → {raw_text}"));
    }
    out.push_str(line.get(at..).unwrap_or(""));
    Ok(Converted { line: out, notes })
}

/// A raw reading of `quantity` on `axis` in the axis's unit, where the
/// mechanics and settings allow.
pub fn to_units(
    law: &dyn UnitLaw,
    mechanics: &Mechanics,
    axis: u8,
    quantity: Quantity,
    raw: f64,
    value_of: &ValueOf,
) -> Result<f64, UnitError> {
    let module_micro = law.microsteps(axis, value_of).transpose()?;
    let steps_per_unit = mechanics.steps_per_unit(module_micro)?;
    let per_raw = law.steps_per_raw(axis, quantity, value_of)?;
    Ok(raw * per_raw / steps_per_unit)
}

/// A value in an axis's unit, as the console shows it (`12.50 mm/s`).
pub struct InUnits<'a> {
    pub value: f64,
    pub quantity: Quantity,
    pub unit: &'a str,
}

impl fmt::Display for InUnits<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        super::parameters::Physical {
            value: self.value,
            unit: "",
        }
        .fmt(f)?;
        // Physical leaves a space before its (empty) unit.
        f.write_str(&self.quantity.unit_text(self.unit))
    }
}

/// Operand spans of a line whose operands are split by commas and blanks
/// (TMCL, SIXpack 2): each operand after the mnemonic with its byte
/// range, comments (`//`) left out.
pub fn split_operands(line: &str) -> (Option<&str>, Vec<(Range<usize>, &str)>) {
    let code = match line.find("//") {
        Some(i) => line.get(..i).unwrap_or(line),
        None => line,
    };
    let mut words = Vec::new();
    let mut start = None;
    for (i, c) in code.char_indices() {
        if c == ',' || c.is_whitespace() {
            if let Some(s) = start.take() {
                words.push((s..i, &code[s..i]));
            }
        } else if start.is_none() {
            start = Some(i);
        }
    }
    if let Some(s) = start {
        words.push((s..code.len(), &code[s..]));
    }
    let mut words = words.into_iter();
    let head = words.next().map(|(_, w)| w);
    (head, words.collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> (MechanicsTable, Vec<String>) {
        let value: toml::Table = text.parse().expect("toml");
        MechanicsTable::from_toml(value.get("mechanics").expect("mechanics"))
    }

    #[test]
    fn a_mechanics_table_reads_and_renders_back() {
        let (t, problems) = table(
            "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\nmicrosteps = 256\ntravel_per_rev = 5\n\
             [mechanics.2]\nunit = \"deg\"\ncounts_per_rev = 4000\ngear_ratio = 10\ntravel_per_rev = 360.0\n",
        );
        assert!(problems.is_empty(), "{problems:?}");
        let m0 = t.get(0).expect("axis 0");
        assert_eq!(m0.revolution, MotorRevolution::FullSteps(200));
        assert_eq!(m0.gear_ratio, 1.0);
        assert_eq!(m0.steps_per_unit(None), Ok(10240.0));
        let m2 = t.get(2).expect("axis 2");
        assert_eq!(m2.steps_per_unit(None), Ok(4000.0 * 10.0 / 360.0));
        let text = format!("family = \"tmcl\"\n{}", t.render());
        let again: toml::Table = text.parse().expect("renders TOML");
        let (back, problems) = MechanicsTable::from_toml(&again["mechanics"]);
        assert!(problems.is_empty());
        assert_eq!(back, t);
    }

    #[test]
    fn bad_mechanics_are_named() {
        let (_, p) = table("[mechanics.0]\nunit = \"mm\"\ntravel_per_rev = 5\n");
        assert!(
            p[0].contains("[mechanics.0] needs full_steps_per_rev"),
            "{p:?}"
        );
        let (_, p) =
            table("[mechanics.0]\nunit = \"m m\"\nfull_steps_per_rev = 200\ntravel_per_rev = 5\n");
        assert!(p[0].contains("letters only"), "{p:?}");
        let (_, p) =
            table("[mechanics.1]\nunit = \"mm\"\nfull_steps_per_rev = 200\ntravel_per_rev = 0\n");
        assert!(
            p[0].contains("travel_per_rev = 0 is not a number above 0"),
            "{p:?}"
        );
        let (_, p) = table("[mechanics.1]\nunit = \"mm\"\nfull_steps = 200\n");
        assert!(
            p[0].contains("`full_steps` is not a mechanics key"),
            "{p:?}"
        );
        let (_, p) = table("[mechanics.x]\nunit = \"mm\"\n");
        assert!(p[0].contains("not an axis number"), "{p:?}");
    }

    #[test]
    fn microsteps_of_the_module_and_of_the_file_must_agree() {
        let (t, _) = table(
            "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\nmicrosteps = 256\ntravel_per_rev = 5\n",
        );
        let m = t.get(0).expect("axis 0");
        assert_eq!(m.steps_per_unit(Some(256)), Ok(10240.0));
        assert!(
            m.steps_per_unit(Some(16))
                .unwrap_err()
                .message
                .contains("256 microsteps, the module is set to 16")
        );
        let (t, _) =
            table("[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\ntravel_per_rev = 5\n");
        let m = t.get(0).expect("axis 0");
        assert_eq!(m.steps_per_unit(Some(16)), Ok(640.0));
        assert!(
            m.steps_per_unit(None)
                .unwrap_err()
                .message
                .contains("give microsteps")
        );
    }

    #[test]
    fn unit_amounts_read_their_quantity_from_the_suffix() {
        let read =
            |t: &str| UnitAmount::parse(t).map(|r| r.map(|a| (a.amount, a.unit, a.quantity)));
        assert_eq!(
            read("12.5mm"),
            Some(Ok((12.5, "mm".into(), Quantity::Position)))
        );
        assert_eq!(
            read("-90deg"),
            Some(Ok((-90.0, "deg".into(), Quantity::Position)))
        );
        assert_eq!(
            read("20mm/s"),
            Some(Ok((20.0, "mm/s".replace("/s", ""), Quantity::Speed)))
        );
        assert_eq!(
            read("100mm/s2"),
            Some(Ok((100.0, "mm".into(), Quantity::Acceleration)))
        );
        assert_eq!(
            read("100mm/s²"),
            Some(Ok((100.0, "mm".into(), Quantity::Acceleration)))
        );
        assert_eq!(read("1000"), None);
        assert_eq!(read("0x1F"), None);
        assert_eq!(read("ABS"), None);
        assert_eq!(read("-5"), None);
        assert_eq!(read("1.5E3"), None, "an MCCL real with an exponent");
        assert_eq!(read("2e-4"), None);
        assert!(
            read("3mm/min")
                .expect("a unit")
                .unwrap_err()
                .message
                .contains("mm/s")
        );
        assert!(
            read("1.2.3mm")
                .expect("a unit")
                .unwrap_err()
                .message
                .contains("not a number")
        );
    }

    #[test]
    fn operands_split_on_commas_and_blanks() {
        let (head, ops) = split_operands("MVP ABS, 0, 12.5mm // go");
        assert_eq!(head, Some("MVP"));
        let texts: Vec<&str> = ops.iter().map(|(_, t)| *t).collect();
        assert_eq!(texts, ["ABS", "0", "12.5mm"]);
        assert_eq!(ops[2].0, 12..18);
    }
}
