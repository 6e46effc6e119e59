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
//! Pure text in and out: the pane reads and writes the file.

use std::fmt::Write as _;

use crate::protocol::parameters::{ParamRole, ParamRow, Scope};

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

/// Read a parameter file's text. A file that is not TOML at all is an
/// error (with its line); keys and values that are not parameters are
/// problems listed beside the entries that are fine.
pub fn parse(text: &str) -> Result<ParamFile, String> {
    let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        let place = e
            .span()
            .map(|span| {
                let line = text.get(..span.start).unwrap_or("").matches('\n').count() + 1;
                format!("line {line}: ")
            })
            .unwrap_or_default();
        format!("{place}{}", e.message())
    })?;
    let mut file = ParamFile::default();
    for (key, value) in &table {
        match (key.as_str(), value) {
            ("family", toml::Value::String(name)) => file.family = Some(name.clone()),
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
    file.entries.sort_by_key(|e| (e.scope, e.number));
    Ok(file)
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
    fn broken_toml_names_the_line() {
        let error = parse("family = \"tmcl\"\n[axis.0]\n4 = = 3\n").unwrap_err();
        assert!(error.starts_with("line 3: "), "{error}");
    }
}
