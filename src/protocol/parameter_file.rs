//! Parameter files: a module's settings as TOML, one section per table
//! (`[axis.0]`, `[bank.2]`), parameter numbers as keys, raw values as the
//! module reads and writes them, each with its name in a comment.
//!
//! ```toml
//! family = "tmcl"
//!
//! [axis.0]
//! 4 = 1000  # Maximum positioning speed
//! ```
//!
//! Pure text in and out: the console's parameter pane and `axterm params`
//! read and write the file; what a file's entries mean to a family's
//! tables ([`check`]) and which settings an export holds
//! ([`setting_rows`]) are decided here, once for both.

use std::collections::HashMap;
use std::fmt::Write as _;

use crate::protocol::parameters::{ParamRole, ParamRow, ParameterSet, Scope};
use crate::protocol::units::MechanicsTable;

/// One value of a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Entry {
    pub scope: Scope,
    pub number: u16,
    pub value: i64,
}

/// A file as read: its values in table order, and what could not be
/// taken from it.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ParamFile {
    /// The family it says it was written for.
    pub family: Option<String>,
    pub entries: Vec<Entry>,
    /// Keys and values that are not parameters ("bank.9", "x = 1").
    pub problems: Vec<String>,
    /// The axes' mechanics (`[mechanics.N]`), carried beside the
    /// settings: the line's own units (issue 20).
    pub mechanics: MechanicsTable,
}

/// One row as exported: its value, or why there is none.
pub struct Exported<'a> {
    pub row: &'a ParamRow,
    pub value: Result<i64, String>,
}

/// The text of a parameter file. `header` lines become comments at the
/// top (what module, which link).
pub fn render(family: &str, header: &[String], rows: &[Exported]) -> String {
    let mut out = String::new();
    // Header lines name the link and the firmware the module reported:
    // a line break in either must not end the comment.
    for line in header {
        let _ = writeln!(out, "# {}", line.replace(['\n', '\r'], " "));
    }
    out.push_str(
        "# Raw values, as the module reads and writes them. Importing this file\n\
         # shows the differences first and writes nothing until asked.\n",
    );
    let _ = writeln!(out, "family = {}", quoted(family));
    let mut section = None;
    for exported in rows {
        let row = exported.row;
        if section != Some(row.scope) {
            section = Some(row.scope);
            let _ = writeln!(out, "\n[{}]", row.scope.key());
        }
        let note = match row.role {
            ParamRole::Link => " (link setting: an import shows it but does not write it)",
            _ => "",
        };
        let name = row.name.replace(['\n', '\r'], " ");
        match &exported.value {
            Ok(value) => {
                let _ = writeln!(out, "{} = {value}  # {name}{note}", row.number);
            }
            Err(why) => {
                let why = why.replace(['\n', '\r'], " ");
                let _ = writeln!(out, "# {} not read: {why}  # {name}", row.number);
            }
        }
    }
    out
}

fn quoted(text: &str) -> String {
    toml::Value::String(text.to_string()).to_string()
}

/// A parameter file that is not TOML at all: where (1-based line, when
/// the TOML reader knows it) and what the reader said.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}{message}", line.map_or(String::new(), |l| format!("line {l}: ")))]
pub struct NotToml {
    pub line: Option<usize>,
    pub message: String,
}

/// Read a parameter file's text. A file that is not TOML at all is an
/// error (with its line); keys and values that are not parameters are
/// problems listed beside the entries that are fine.
pub fn parse(text: &str) -> Result<ParamFile, NotToml> {
    let table: toml::Table = text.parse().map_err(|e: toml::de::Error| NotToml {
        line: e
            .span()
            .map(|span| text.get(..span.start).unwrap_or("").matches('\n').count() + 1),
        message: e.message().to_string(),
    })?;
    let mut file = ParamFile::default();
    for (key, value) in &table {
        match (key.as_str(), value) {
            ("family", toml::Value::String(name)) => file.family = Some(name.clone()),
            ("mechanics", value) => {
                let (mechanics, problems) = MechanicsTable::from_toml(value);
                file.mechanics = mechanics;
                file.problems.extend(problems);
            }
            ("axis" | "bank", toml::Value::Table(groups)) => {
                for (index, params) in groups {
                    let scope = index.parse::<u8>().ok().map(|n| match key.as_str() {
                        "axis" => Scope::Axis(n),
                        _ => Scope::Bank(n),
                    });
                    let (Some(scope), toml::Value::Table(params)) = (scope, params) else {
                        file.problems
                            .push(format!("[{key}.{index}] is not a table of parameters"));
                        continue;
                    };
                    read_section(scope, params, &mut file);
                }
            }
            _ => file.problems.push(format!(
                "`{key}` is neither a family nor a table of parameters"
            )),
        }
    }
    file.problems.extend(headers_with_nothing_under(text));
    file.entries.sort_by_key(|e| (e.scope, e.number));
    Ok(file)
}

/// Section headers with nothing under them, not even a comment: an
/// export writes every row of a section under its header (its value, or
/// why it was not read), so a bare header is where a file was cut off.
/// A file cut between two whole lines of settings cannot be told from a
/// shorter file and is not guessed at.
fn headers_with_nothing_under(text: &str) -> Vec<String> {
    let mut bare = Vec::new();
    let mut open: Option<(usize, &str)> = None;
    for (index, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        if let Some((number, header)) = open.take()
            && line.starts_with('[')
        {
            bare.push((number, header));
        }
        if line.starts_with('[') {
            open = Some((index + 1, line));
        }
    }
    bare.extend(open);
    bare.into_iter()
        .map(|(number, header)| {
            format!("line {number}: {header} has no settings under it (is the file cut short?)")
        })
        .collect()
}

fn read_section(scope: Scope, params: &toml::Table, file: &mut ParamFile) {
    for (number, value) in params {
        let Ok(number) = number.parse::<u16>() else {
            file.problems.push(format!(
                "[{}] `{number}` is not a parameter number",
                scope.key()
            ));
            continue;
        };
        let toml::Value::Integer(value) = value else {
            file.problems.push(format!(
                "[{}] {number} = {value} is not a whole number",
                scope.key()
            ));
            continue;
        };
        file.entries.push(Entry {
            scope,
            number,
            value: *value,
        });
    }
}

/// Every setting of every axis and bank, for export and comparison: the
/// rows the module reads back, and where the family knows them from what
/// was written ([`ParameterSet::remembers_writes`]), the write-only ones;
/// never motion state or read-only rows. `axes` are the module's axis
/// numbers; the banks are taken once.
pub fn setting_rows(parameters: &dyn ParameterSet, axes: &[u8]) -> Vec<ParamRow> {
    let known = parameters.remembers_writes();
    let mut rows = Vec::new();
    let mut banks_done = false;
    for &axis in axes {
        for table in parameters.tables(axis) {
            let bank = matches!(table.scope, Scope::Bank(_));
            if bank && banks_done {
                continue;
            }
            rows.extend(table.rows.into_iter().filter(|r| {
                (r.access.read || known) && r.access.write && r.role != ParamRole::State
            }));
        }
        banks_done = true;
    }
    rows
}

/// A file's entries as the family's tables take them.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct CheckedFile {
    /// The settings it gives, with their rows, in table order.
    pub entries: Vec<(ParamRow, i64)>,
    /// What was not taken from it, and why (the file's own problems
    /// first): each names the parameter.
    pub problems: Vec<String>,
    /// The axes' mechanics it carries, of axes the module has: not
    /// written to the module (they are the console's), carried for the
    /// line's own units.
    pub mechanics: MechanicsTable,
}

/// Why a file is not for this module: it names another family.
pub fn family_mismatch(file: &ParamFile, family: &str) -> Option<String> {
    let named = file.family.as_deref()?;
    (!named.eq_ignore_ascii_case(family))
        .then(|| format!("it holds {named} parameters; this module speaks {family}"))
}

/// Take a parsed file's entries against the tables of a module with
/// `axes`: an entry that is no parameter here, not a setting (read-only,
/// motion state) or outside its range is a problem naming it, and left
/// out.
pub fn check(file: ParamFile, parameters: &dyn ParameterSet, axes: &[u8]) -> CheckedFile {
    let mut problems = file.problems;
    let mut entries = Vec::new();
    let mut mechanics = file.mechanics;
    mechanics.axes.retain(|axis, _| {
        let here = axes.contains(axis);
        if !here {
            problems.push(format!(
                "[mechanics.{axis}]: this module has no axis {axis}"
            ));
        }
        here
    });
    let mut tables: HashMap<Scope, Vec<ParamRow>> = HashMap::new();
    for &axis in axes {
        for table in parameters.tables(axis) {
            tables.entry(table.scope).or_insert(table.rows);
        }
    }
    for Entry {
        scope,
        number,
        value,
    } in file.entries
    {
        let label = format!("[{}] {number}", scope.key());
        let Some(row) = tables
            .get(&scope)
            .and_then(|rows| rows.iter().find(|r| r.number == number))
        else {
            problems.push(format!("{label}: no such parameter on this module"));
            continue;
        };
        let name = &row.name;
        if !row.access.write || row.role == ParamRole::State {
            problems.push(format!("{label} {name}: not a setting, left alone"));
        } else if !row.range.contains(value) {
            problems.push(format!(
                "{label} {name}: {value} is outside {}, left alone",
                row.range
            ));
        } else {
            entries.push((row.clone(), value));
        }
    }
    if entries.is_empty() && problems.is_empty() {
        problems.push(
            "it holds no settings (an empty file, or one cut short): nothing to compare or apply"
                .to_string(),
        );
    }
    CheckedFile {
        entries,
        problems,
        mechanics,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::parameters::{ParamAccess, ParamRange};

    fn row(scope: Scope, number: u16, name: &str, role: ParamRole) -> ParamRow {
        ParamRow {
            scope,
            number,
            name: name.into(),
            unit: "",
            range: ParamRange::Span { min: 0, max: 10 },
            access: ParamAccess::default(),
            role,
            default: None,
            description: "",
        }
    }

    #[test]
    fn a_rendered_file_reads_back_as_the_same_values() {
        let speed = row(
            Scope::Axis(0),
            4,
            "Maximum positioning speed",
            ParamRole::Setting,
        );
        let baud = row(Scope::Bank(0), 65, "RS485 baud rate", ParamRole::Link);
        let var = row(Scope::Bank(2), 10, "User variable #10", ParamRole::Setting);
        let broken = row(Scope::Bank(2), 11, "User variable #11", ParamRole::Setting);
        let text = render(
            "tmcl",
            &["module 1 on sim tmcm1110".into()],
            &[
                Exported {
                    row: &speed,
                    value: Ok(1000),
                },
                Exported {
                    row: &baud,
                    value: Ok(0),
                },
                Exported {
                    row: &var,
                    value: Ok(-7),
                },
                Exported {
                    row: &broken,
                    value: Err("no answer".into()),
                },
            ],
        );
        assert!(text.starts_with("# module 1 on sim tmcm1110\n"), "{text}");
        assert!(text.contains("[axis.0]\n4 = 1000  # Maximum positioning speed\n"));
        assert!(text.contains("65 = 0  # RS485 baud rate (link setting"));
        let file = parse(&text).expect("parses");
        assert_eq!(file.family.as_deref(), Some("tmcl"));
        assert!(file.problems.is_empty(), "{:?}", file.problems);
        assert_eq!(
            file.entries,
            [
                Entry {
                    scope: Scope::Axis(0),
                    number: 4,
                    value: 1000
                },
                Entry {
                    scope: Scope::Bank(0),
                    number: 65,
                    value: 0
                },
                Entry {
                    scope: Scope::Bank(2),
                    number: 10,
                    value: -7
                },
            ]
        );
    }

    #[test]
    fn numbers_sort_as_numbers() {
        let file = parse("[axis.0]\n10 = 1\n4 = 2\n").expect("parses");
        let numbers: Vec<u16> = file.entries.iter().map(|e| e.number).collect();
        assert_eq!(numbers, [4, 10]);
    }

    #[test]
    fn what_is_not_a_parameter_is_listed_not_fatal() {
        let file = parse(
            "colour = \"red\"\n[axis.x]\n1 = 2\n[axis.0]\nspeed = 5\n6 = \"high\"\n7 = 100\n",
        )
        .expect("parses");
        assert_eq!(file.entries.len(), 1);
        assert_eq!(file.problems.len(), 4, "{:?}", file.problems);
        assert!(file.problems.iter().any(|p| p.contains("`speed`")));
        assert!(file.problems.iter().any(|p| p.contains("6 = \"high\"")));
    }

    #[test]
    fn broken_toml_keeps_its_line_as_a_number() {
        let error = parse("[axis.0]\n4 = 1\n\n5 = \n").unwrap_err();
        assert_eq!(error.line, Some(4), "{error}");
    }

    #[test]
    fn broken_toml_names_the_line() {
        let error = parse("family = \"tmcl\"\n[axis.0]\n4 = = 3\n")
            .unwrap_err()
            .to_string();
        assert!(error.starts_with("line 3: "), "{error}");
    }
}

#[cfg(test)]
mod check_tests {
    use super::*;
    use crate::protocol::tmcl::parameter_set::TmclParameters;

    #[test]
    fn a_file_without_settings_or_cut_after_a_header_is_a_problem() {
        for text in ["", "family = \"tmcl\"\n", "# a comment\n\n"] {
            let checked = check(parse(text).expect("parses"), &TmclParameters, &[0]);
            assert!(checked.entries.is_empty());
            assert_eq!(
                checked.problems,
                [
                    "it holds no settings (an empty file, or one cut short): nothing to compare or \
                  apply"
                ],
                "{text:?}"
            );
        }
        let cut = parse("family = \"tmcl\"\n[axis.0]\n4 = 1000\n\n[bank.0]\n  \n").expect("parses");
        assert_eq!(
            cut.problems,
            ["line 5: [bank.0] has no settings under it (is the file cut short?)"]
        );
        let cut = parse("[axis.0]\n[axis.1]\n4 = 1\n").expect("parses");
        assert_eq!(
            cut.problems,
            ["line 1: [axis.0] has no settings under it (is the file cut short?)"]
        );
        // A section whose values were not read (commented out, as an
        // export writes them) is whole.
        let whole =
            parse("[axis.0]\n4 = 1000\n[bank.0]\n# 0 not read: no answer  # x\n").expect("parses");
        assert!(whole.problems.is_empty(), "{:?}", whole.problems);
    }

    #[test]
    fn entries_are_checked_against_the_tables_and_name_the_parameter() {
        let file = parse(
            "family = \"tmcl\"\n[axis.0]\n4 = 1000\n6 = 300\n1 = 5\n999 = 1\n[bank.9]\n1 = 1\n",
        )
        .expect("parses");
        let checked = check(file, &TmclParameters, &[0]);
        assert_eq!(checked.entries.len(), 1, "{:?}", checked);
        assert_eq!(checked.entries[0].0.number, 4);
        assert_eq!(checked.entries[0].1, 1000);
        let problems = checked.problems.join("\n");
        assert!(
            problems.contains("[axis.0] 6 Maximum current: 300 is outside 0..255"),
            "{problems}"
        );
        assert!(
            problems.contains("[axis.0] 1 Actual position: not a setting"),
            "{problems}"
        );
        assert!(
            problems.contains("[axis.0] 999: no such parameter"),
            "{problems}"
        );
        assert!(
            problems.contains("[bank.9] 1: no such parameter"),
            "{problems}"
        );
    }

    #[test]
    fn a_file_for_another_family_names_both() {
        let file = parse("family = \"cmd4cr\"\n").expect("parses");
        let why = family_mismatch(&file, "tmcl").expect("refused");
        assert_eq!(why, "it holds cmd4cr parameters; this module speaks tmcl");
        assert_eq!(family_mismatch(&file, "CMD4CR"), None);
        assert_eq!(family_mismatch(&ParamFile::default(), "tmcl"), None);
    }

    #[test]
    fn an_export_holds_settings_only_and_the_banks_once() {
        let rows = setting_rows(&TmclParameters, &[0]);
        assert!(
            rows.iter()
                .all(|r| r.access.write && r.role != ParamRole::State)
        );
        assert!(
            rows.iter()
                .any(|r| r.scope == Scope::Axis(0) && r.number == 4)
        );
        let banks = rows
            .iter()
            .filter(|r| r.scope == Scope::Bank(2) && r.number == 0)
            .count();
        assert_eq!(banks, 1);
    }
}
