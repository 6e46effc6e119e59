//! A module's settings against a parameter file
//! ([`crate::protocol::parameter_file`]): read them all, compare them with
//! a file, write what differs and read every written value back, store
//! them. One implementation for the console's parameter pane (which sends
//! its lines one at a time between the user's, through the same
//! [`reading`], [`compare`] and [`plan_writes`]) and `axterm params` (which
//! awaits them here, [`read_values`], [`apply`]).
//!
//! What a module cannot be asked for (every SIXpack 2 setting, §7) is
//! taken from what this session wrote ([`crate::protocol::settings`]);
//! never written, it is [`ModuleValue::Unknown`], which is never "the
//! same" as a file's value.

use std::collections::HashMap;

use super::{LineResult, Session, SessionError};
use crate::protocol::console::ReplyValue;
use crate::protocol::parameters::{ParamOp, ParamRole, ParamRow, ParameterSet, Scope};
use crate::protocol::settings::{KnownSetting, SettingsCache};

/// A parameter: its table and number.
pub type ParamKey = (Scope, u16);

/// What is known of one parameter's value in the module.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ModuleValue {
    Value(i64),
    /// The module refused to read it, or the answer made no sense.
    Unreadable(String),
    /// No answer came (timeout, link lost).
    NoAnswer(String),
    /// The module cannot be asked and the session wrote no value known
    /// now (never written, or reset since).
    Unknown(String),
}

impl ModuleValue {
    /// The value, if there is one.
    pub fn value(&self) -> Option<i64> {
        match self {
            ModuleValue::Value(v) => Some(*v),
            _ => None,
        }
    }

    /// Why there is no value, if there is none.
    pub fn why_not(&self) -> Option<&str> {
        match self {
            ModuleValue::Value(_) => None,
            ModuleValue::Unreadable(why)
            | ModuleValue::NoAnswer(why)
            | ModuleValue::Unknown(why) => Some(why),
        }
    }
}

impl std::fmt::Display for ModuleValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ModuleValue::Value(v) => write!(f, "{v}"),
            ModuleValue::Unreadable(why) => write!(f, "unreadable ({why})"),
            ModuleValue::NoAnswer(why) => write!(f, "no answer ({why})"),
            ModuleValue::Unknown(why) => write!(f, "unknown ({why})"),
        }
    }
}

/// The value a read of `row` answered. A value the family prints with
/// decimals (CMD-4CR SLR, 1.5) comes as text: its own parser makes it the
/// raw number the table holds. `axis_value` gives other parameters of the
/// axis for that parser.
pub fn reading(
    parameters: &dyn ParameterSet,
    row: &ParamRow,
    result: &Result<LineResult, SessionError>,
    axis_value: &dyn Fn(u16) -> Option<i64>,
) -> ModuleValue {
    match result {
        Ok(r) => {
            let number = match &r.value {
                ReplyValue::Number(v) => Some(*v),
                ReplyValue::Text(text) => parameters.parse_value(row, text, axis_value).ok(),
                ReplyValue::None => None,
            };
            match number {
                Some(v) => ModuleValue::Value(v),
                None => ModuleValue::Unreadable(format!("answer {} is not a number", r.value)),
            }
        }
        Err(SessionError::Device { error, .. }) => ModuleValue::NoAnswer(error.to_string()),
        Err(other) => ModuleValue::Unreadable(other.to_string()),
    }
}

/// What the session knows of a row the module cannot read back, from
/// what it wrote ([`ParameterSet::remembers_writes`]).
pub fn remembered(known: &SettingsCache, row: &ParamRow) -> ModuleValue {
    match known.get(row.scope, row.number) {
        Some(KnownSetting::Written(v)) => ModuleValue::Value(*v),
        Some(KnownSetting::Stale { was, why }) => {
            ModuleValue::Unknown(format!("unknown since {why}; {was} was written before"))
        }
        None => ModuleValue::Unknown(match known.forgotten() {
            Some(why) => format!("not written since {why}"),
            None => "not written this session".to_string(),
        }),
    }
}

/// A file's value that is not the module's.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Difference {
    pub row: ParamRow,
    pub module: ModuleValue,
    pub file: i64,
}

/// A file's settings against the module's values.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Comparison {
    /// Parameters whose value in the module is not the file's (or is not
    /// known), in the file's order.
    pub differences: Vec<Difference>,
    /// Those found equal, with their value.
    pub same: Vec<(ParamRow, i64)>,
}

impl Comparison {
    /// The differences that count: settings, not link settings (a baud
    /// rate or bus address differs from module to module by design; they
    /// are shown, never written).
    pub fn settings_differing(&self) -> impl Iterator<Item = &Difference> {
        self.differences
            .iter()
            .filter(|d| d.row.role != ParamRole::Link)
    }
}

/// Compare checked entries with the module's values (`module` gives what
/// is known of a row).
pub fn compare(
    entries: &[(ParamRow, i64)],
    module: &dyn Fn(&ParamRow) -> ModuleValue,
) -> Comparison {
    let mut comparison = Comparison::default();
    for (row, file) in entries {
        let value = module(row);
        if value == ModuleValue::Value(*file) {
            comparison.same.push((row.clone(), *file));
        } else {
            comparison.differences.push(Difference {
                row: row.clone(),
                module: value,
                file: *file,
            });
        }
    }
    comparison
}

/// One line of a write plan, and the values it writes: a family that
/// writes several settings in one line (SIXpack 2 `$14`) writes them all
/// with the first difference that needs the line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlannedWrite {
    pub line: String,
    /// The differences it settles: their row, the file's value and the
    /// module's before.
    pub values: Vec<Difference>,
}

/// What applying a file writes.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct WritePlan {
    pub writes: Vec<PlannedWrite>,
    /// Link settings that differ: shown, left to the user (writing them
    /// would cut the connection they are made over).
    pub link_left: Vec<Difference>,
    /// Differences the family has no line for, and why.
    pub refused: Vec<(Difference, String)>,
}

/// The lines writing every setting of `comparison` that differs. A
/// parameter written together with others in one line takes their values
/// from the file first (its differences and its equal values), then from
/// `known` (what the session knows of the module).
pub fn plan_writes(
    parameters: &dyn ParameterSet,
    comparison: &Comparison,
    known: &dyn Fn(Scope, u16) -> Option<i64>,
) -> WritePlan {
    let file: HashMap<ParamKey, i64> = comparison
        .differences
        .iter()
        .map(|d| ((d.row.scope, d.row.number), d.file))
        .chain(
            comparison
                .same
                .iter()
                .map(|(row, v)| ((row.scope, row.number), *v)),
        )
        .collect();
    let with_file = |scope: Scope, number: u16| {
        file.get(&(scope, number))
            .copied()
            .or_else(|| known(scope, number))
    };
    let mut plan = WritePlan::default();
    for d in &comparison.differences {
        if d.row.role == ParamRole::Link {
            plan.link_left.push(d.clone());
            continue;
        }
        if d.row.role != ParamRole::Setting {
            continue;
        }
        match parameters.line_with(&d.row, ParamOp::Write(d.file), &with_file) {
            Ok(line) => match plan.writes.iter_mut().find(|w| w.line == line) {
                Some(write) => write.values.push(d.clone()),
                None => plan.writes.push(PlannedWrite {
                    line,
                    values: vec![d.clone()],
                }),
            },
            Err(why) => plan.refused.push((d.clone(), why.into())),
        }
    }
    plan
}

/// The lines storing `rows` to the module's EEPROM or flash, each once (a
/// CMD-4CR `STORE` keeps every setting at once), and the rows that have
/// none with why (no EEPROM copy); rows every write stores (TMCL access
/// `A`) need none.
pub fn plan_store(
    parameters: &dyn ParameterSet,
    rows: &[ParamRow],
) -> (Vec<String>, Vec<(ParamRow, String)>) {
    let mut lines: Vec<String> = Vec::new();
    let mut without = Vec::new();
    for row in rows {
        if row.access.auto_stored {
            // Every write went to EEPROM already.
            continue;
        }
        match parameters.line(row, ParamOp::Store) {
            Ok(line) if !lines.contains(&line) => lines.push(line),
            Ok(_) => {}
            Err(why) => without.push((row.clone(), why.into())),
        }
    }
    (lines, without)
}

/// Read `rows` from the module one by one (reads are retried as every
/// read is); a row it cannot read back is what the session wrote.
pub async fn read_values(
    session: &Session,
    parameters: &dyn ParameterSet,
    rows: &[ParamRow],
) -> HashMap<ParamKey, ModuleValue> {
    let mut values: HashMap<ParamKey, ModuleValue> = HashMap::new();
    for row in rows {
        let value = read_one(session, parameters, row, &values).await;
        values.insert((row.scope, row.number), value);
    }
    values
}

async fn read_one(
    session: &Session,
    parameters: &dyn ParameterSet,
    row: &ParamRow,
    values: &HashMap<ParamKey, ModuleValue>,
) -> ModuleValue {
    if !row.access.read {
        if parameters.remembers_writes() {
            return remembered(&session.settings().borrow(), row);
        }
        return ModuleValue::Unknown("write-only".into());
    }
    let line = match parameters.line(row, ParamOp::Read) {
        Ok(line) => line,
        Err(why) => return ModuleValue::Unreadable(why.into()),
    };
    // A family without a checksum: a value is the one two reads agree on.
    let result = match session.prepare(&line) {
        Ok(prepared) => session.read_agreed(&prepared).await,
        Err(error) => Err(error),
    };
    let scope = row.scope;
    let axis_value = |number: u16| values.get(&(scope, number)).and_then(ModuleValue::value);
    reading(parameters, row, &result, &axis_value)
}

/// How applying a file went for one value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ValueOutcome {
    /// Written and read back as written.
    Verified,
    /// Written, but read back as another value.
    ReadBackDiffers(i64),
    /// Written (the module acknowledged it, or acknowledges no write) but
    /// it cannot be read back: the family reads no such value.
    Unverifiable,
    /// Not written (dry run).
    Planned,
    /// The write, or the read after it, failed: why.
    Failed(String),
}

/// One value of an apply.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AppliedValue {
    pub difference: Difference,
    pub line: String,
    pub outcome: ValueOutcome,
}

/// What became of a store line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StoreOutcome {
    pub line: String,
    pub result: Result<(), String>,
}

/// What applying a file did to one module.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ApplyReport {
    pub comparison: Comparison,
    pub values: Vec<AppliedValue>,
    pub link_left: Vec<Difference>,
    /// Differences with no line to write them, and why (failures).
    pub refused: Vec<(Difference, String)>,
    pub stored: Vec<StoreOutcome>,
    /// Rows of the file with no store line, and why (notes).
    pub not_storable: Vec<(ParamRow, String)>,
}

impl ApplyReport {
    /// Values written (whatever came of the read back).
    pub fn written(&self) -> usize {
        self.values
            .iter()
            .filter(|v| {
                matches!(
                    v.outcome,
                    ValueOutcome::Verified
                        | ValueOutcome::ReadBackDiffers(_)
                        | ValueOutcome::Unverifiable
                )
            })
            .count()
    }

    pub fn verified(&self) -> usize {
        self.count(|o| *o == ValueOutcome::Verified)
    }

    pub fn unverifiable(&self) -> usize {
        self.count(|o| *o == ValueOutcome::Unverifiable)
    }

    /// Values read back as another value than written.
    pub fn differs(&self) -> usize {
        self.count(|o| matches!(o, ValueOutcome::ReadBackDiffers(_)))
    }

    /// Writes, read backs and stores that failed, and differences with no
    /// line.
    pub fn failed(&self) -> usize {
        self.count(|o| matches!(o, ValueOutcome::Failed(_)))
            + self.refused.len()
            + self.stored.iter().filter(|s| s.result.is_err()).count()
    }

    fn count(&self, wanted: impl Fn(&ValueOutcome) -> bool) -> usize {
        self.values.iter().filter(|v| wanted(&v.outcome)).count()
    }

    /// Whether the module now holds the file: nothing failed, nothing
    /// read back otherwise.
    pub fn succeeded(&self) -> bool {
        self.failed() == 0 && self.differs() == 0
    }
}

/// What `apply` is asked to do beyond writing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ApplyOptions {
    /// Store the file's settings to EEPROM/flash after writing.
    pub store: bool,
    /// Read and plan only: no write, no store.
    pub dry_run: bool,
}

/// Compare `entries` (checked against the family's tables) with the
/// module, write what differs, read every written value back where the
/// module can, and with `store` store the file's settings.
pub async fn apply(
    session: &Session,
    parameters: &dyn ParameterSet,
    entries: &[(ParamRow, i64)],
    options: ApplyOptions,
) -> ApplyReport {
    let rows: Vec<ParamRow> = entries.iter().map(|(row, _)| row.clone()).collect();
    let values = read_values(session, parameters, &rows).await;
    let module = |row: &ParamRow| {
        values
            .get(&(row.scope, row.number))
            .cloned()
            .unwrap_or_else(|| ModuleValue::NoAnswer("not read".into()))
    };
    let comparison = compare(entries, &module);
    let known = |scope: Scope, number: u16| {
        values
            .get(&(scope, number))
            .and_then(ModuleValue::value)
            .or_else(|| session.settings().borrow().value(scope, number))
    };
    let plan = plan_writes(parameters, &comparison, &known);
    let mut report = ApplyReport {
        link_left: plan.link_left,
        refused: plan.refused,
        ..ApplyReport::default()
    };
    for write in plan.writes {
        let outcomes = if options.dry_run {
            vec![ValueOutcome::Planned; write.values.len()]
        } else {
            write_and_verify(session, parameters, &write).await
        };
        for (difference, outcome) in write.values.into_iter().zip(outcomes) {
            report.values.push(AppliedValue {
                difference,
                line: write.line.clone(),
                outcome,
            });
        }
    }
    if options.store && !options.dry_run {
        let (lines, without) = plan_store(parameters, &rows);
        report.not_storable = without;
        for line in lines {
            let result = session
                .execute_line(&line)
                .await
                .map(|_| ())
                .map_err(|e| e.to_string());
            report.stored.push(StoreOutcome { line, result });
        }
    }
    report.comparison = comparison;
    report
}

/// Send one write, then read back each value it wrote.
async fn write_and_verify(
    session: &Session,
    parameters: &dyn ParameterSet,
    write: &PlannedWrite,
) -> Vec<ValueOutcome> {
    if let Err(e) = session.execute_line(&write.line).await {
        let why = if e.nothing_sent() {
            format!("{e} (nothing sent)")
        } else {
            e.to_string()
        };
        return vec![ValueOutcome::Failed(why); write.values.len()];
    }
    let mut outcomes = Vec::new();
    for d in &write.values {
        if !d.row.access.read {
            outcomes.push(ValueOutcome::Unverifiable);
            continue;
        }
        let read = read_one(session, parameters, &d.row, &HashMap::new()).await;
        outcomes.push(match read {
            ModuleValue::Value(v) if v == d.file => ValueOutcome::Verified,
            ModuleValue::Value(v) => ValueOutcome::ReadBackDiffers(v),
            other => ValueOutcome::Failed(format!(
                "written, but not read back: {}",
                other.why_not().unwrap_or("")
            )),
        });
    }
    outcomes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::parameters::{ParamAccess, ParamRange};
    use crate::protocol::parameters::{ParamError, ParamRefusal};

    fn row(number: u16, role: ParamRole, read: bool) -> ParamRow {
        ParamRow {
            scope: Scope::Axis(0),
            number,
            name: format!("p{number}"),
            unit: "",
            range: ParamRange::Span { min: 0, max: 100 },
            access: ParamAccess {
                read,
                write: true,
                store: false,
                auto_stored: false,
            },
            role,
            default: None,
            description: "",
        }
    }

    /// Writes `Pn=v`, or `P1,2=a,b` when the row is 1 or 2 (a line
    /// carrying two settings).
    struct Pair;

    impl ParameterSet for Pair {
        fn tables(&self, _axis: u8) -> Vec<crate::protocol::parameters::ParamTable> {
            Vec::new()
        }

        fn line(&self, row: &ParamRow, op: ParamOp) -> Result<String, ParamError> {
            self.line_with(row, op, &|_, _| None)
        }

        fn line_with(
            &self,
            row: &ParamRow,
            op: ParamOp,
            known: &dyn Fn(Scope, u16) -> Option<i64>,
        ) -> Result<String, ParamError> {
            let ParamOp::Write(v) = op else {
                return Err(ParamError::new(ParamRefusal::NotReadable, "only writes"));
            };
            if row.number == 9 {
                return Err(ParamError::new(ParamRefusal::NotDone, "p9 has no line"));
            }
            if row.number <= 2 {
                let a = if row.number == 1 {
                    Some(v)
                } else {
                    known(row.scope, 1)
                };
                let b = if row.number == 2 {
                    Some(v)
                } else {
                    known(row.scope, 2)
                };
                let (Some(a), Some(b)) = (a, b) else {
                    return Err(ParamError::new(ParamRefusal::NotDone, "needs both"));
                };
                return Ok(format!("P1,2={a},{b}"));
            }
            Ok(format!("P{}={v}", row.number))
        }
    }

    #[test]
    fn only_what_differs_is_written_and_link_settings_are_left() {
        let entries = vec![
            (row(3, ParamRole::Setting, true), 5),
            (row(4, ParamRole::Setting, true), 6),
            (row(5, ParamRole::Link, true), 7),
            (row(9, ParamRole::Setting, true), 1),
        ];
        let module = |r: &ParamRow| match r.number {
            3 => ModuleValue::Value(5),
            _ => ModuleValue::Value(0),
        };
        let comparison = compare(&entries, &module);
        assert_eq!(comparison.same.len(), 1);
        assert_eq!(comparison.differences.len(), 3);
        assert_eq!(comparison.settings_differing().count(), 2);
        let plan = plan_writes(&Pair, &comparison, &|_, _| None);
        let lines: Vec<&str> = plan.writes.iter().map(|w| w.line.as_str()).collect();
        assert_eq!(lines, ["P4=6"]);
        assert_eq!(plan.link_left.len(), 1);
        assert_eq!(plan.refused.len(), 1);
        assert_eq!(plan.refused[0].1, "p9 has no line");
    }

    #[test]
    fn settings_written_together_take_the_files_values_in_one_line() {
        let entries = vec![
            (row(1, ParamRole::Setting, false), 10),
            (row(2, ParamRole::Setting, false), 20),
        ];
        let unknown = |_: &ParamRow| ModuleValue::Unknown("not written this session".into());
        let comparison = compare(&entries, &unknown);
        assert_eq!(comparison.differences.len(), 2, "unknown is never the same");
        let plan = plan_writes(&Pair, &comparison, &|_, _| None);
        assert_eq!(plan.writes.len(), 1);
        assert_eq!(plan.writes[0].line, "P1,2=10,20");
        assert_eq!(plan.writes[0].values.len(), 2);
    }

    #[test]
    fn a_stale_setting_says_why_it_is_unknown() {
        let mut cache = SettingsCache::default();
        let r = row(1, ParamRole::Setting, false);
        assert_eq!(
            remembered(&cache, &r),
            ModuleValue::Unknown("not written this session".into())
        );
        cache.record(&[crate::protocol::settings::SettingWrite {
            scope: Scope::Axis(0),
            number: 1,
            value: 42,
        }]);
        assert_eq!(remembered(&cache, &r), ModuleValue::Value(42));
        cache.forget("a reset");
        assert!(matches!(remembered(&cache, &r), ModuleValue::Unknown(why) if why.contains("42")));
    }
}
