//! Tab completion and inline help for TMCL console lines, read from the
//! command catalogue ([`super::catalog`]) and the parameter tables
//! ([`super::params`]): nothing here restates the manual.

use super::catalog::{
    COMMANDS, CodeSet, CommandInfo, Field, Operand, OperandKind, Presence, Usage,
};
use super::catalog::{command_by_opcode, find_command};
use super::console::AXES;
use super::line::parse_number;
use super::params::{AXIS_PARAMS, BANK0_PARAMS, BANK2_PARAMS, BANK3_PARAMS, ParamInfo};
use crate::protocol::console::{Candidate, Completions};

/// The global parameter banks (§5): number, table, what they hold.
const BANKS: &[(u8, &[ParamInfo], &str)] = &[
    (0, BANK0_PARAMS, "module settings"),
    (2, BANK2_PARAMS, "user variables"),
    (3, BANK3_PARAMS, "interrupt configuration"),
];

/// Commands whose `<parameter>` is an axis parameter (§4); the other
/// commands with a `<parameter>` take a global one (§5).
const AXIS_PARAM_COMMANDS: &[&str] = &["SAP", "GAP", "STAP", "RSAP", "AAP"];

/// The words of a line as byte ranges: operands are separated by commas,
/// spaces or both; `//` starts a comment.
fn words(line: &str) -> Vec<(usize, usize)> {
    let end = line.find("//").unwrap_or(line.len());
    let mut words = Vec::new();
    let mut start = None;
    for (i, c) in line[..end].char_indices() {
        let separator = c == ',' || c.is_whitespace();
        match (separator, start) {
            (true, Some(s)) => {
                words.push((s, i));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        words.push((s, end));
    }
    words
}

/// The word at `cursor` (its range, possibly empty) and how many words
/// come before it. `None` when the cursor is inside a comment or not on a
/// character boundary.
fn word_at(line: &str, cursor: usize) -> Option<((usize, usize), usize)> {
    if cursor > line.len() || !line.is_char_boundary(cursor) {
        return None;
    }
    if line.find("//").is_some_and(|c| cursor > c) {
        return None;
    }
    let words = words(line);
    for (index, &(start, end)) in words.iter().enumerate() {
        if start <= cursor && cursor <= end {
            return Some(((start, end), index));
        }
    }
    let before = words.iter().filter(|&&(_, end)| end < cursor).count();
    Some(((cursor, cursor), before))
}

fn starts_with_ignore_case(text: &str, prefix: &str) -> bool {
    text.len() >= prefix.len()
        && text
            .get(..prefix.len())
            .is_some_and(|head| head.eq_ignore_ascii_case(prefix))
}

/// The command a line starts with: by name, or by instruction number for
/// a raw frame.
fn command_of(first: &str) -> Option<&'static CommandInfo> {
    find_command(first).or_else(|| {
        parse_number(first)
            .and_then(|n| u8::try_from(n).ok())
            .and_then(command_by_opcode)
    })
}

/// Whether a command's `<parameter>` is an axis parameter.
fn takes_axis_param(command: &CommandInfo) -> bool {
    AXIS_PARAM_COMMANDS.contains(&command.name)
}

fn is_param_operand(operand: &Operand) -> bool {
    operand.name == "parameter" && operand.field == Field::Type
}

/// Every parameter row `command` may name, as (number, row, bank).
fn param_rows(
    command: &CommandInfo,
    typing_number: bool,
) -> Vec<(u8, &'static ParamInfo, Option<u8>)> {
    let expand = |table: &'static [ParamInfo], bank: Option<u8>| {
        table.iter().flat_map(move |row| {
            // A row covering many numbers (user variables) is offered
            // once, unless its numbers are being typed.
            let numbers = if typing_number {
                row.numbers.clone()
            } else {
                *row.numbers.start()..=*row.numbers.start()
            };
            numbers.map(move |n| (n, row, bank))
        })
    };
    if takes_axis_param(command) {
        expand(AXIS_PARAMS, None).collect()
    } else {
        BANKS
            .iter()
            .flat_map(|&(bank, table, _)| expand(table, Some(bank)))
            .collect()
    }
}

/// The parameter row a line names, once its parameter and bank are given.
fn named_param(command: &CommandInfo, operands: &[&str]) -> Option<&'static ParamInfo> {
    let number = operands.first().and_then(|w| parse_number(w))?;
    let number = u8::try_from(number).ok()?;
    if takes_axis_param(command) {
        super::params::axis_param(number)
    } else {
        let bank = operands.get(1).and_then(|w| parse_number(w))?;
        super::params::global_param(u8::try_from(bank).ok()?, number)
    }
}

fn param_note(row: &ParamInfo, bank: Option<u8>) -> String {
    match bank {
        Some(bank) => format!("{} (bank {bank})", row.name),
        None => row.name.to_string(),
    }
}

/// Completions of the word at `cursor`.
pub fn complete(line: &str, cursor: usize) -> Completions {
    let Some(((start, end), index)) = word_at(line, cursor) else {
        return Completions::default();
    };
    let prefix = line.get(start..cursor).unwrap_or("");
    let all = words(line);
    let word = |i: usize| all.get(i).and_then(|&(s, e)| line.get(s..e)).unwrap_or("");
    let mut completions = Completions {
        start,
        end,
        candidates: Vec::new(),
        separator: "",
    };
    if index == 0 {
        completions.candidates = COMMANDS
            .iter()
            .filter(|c| starts_with_ignore_case(c.name, prefix))
            .map(|c| Candidate {
                text: c.name.to_string(),
                note: c.summary.to_string(),
            })
            .collect();
        let has_operands = |text: &str| find_command(text).is_some_and(|c| !c.operands.is_empty());
        if completions.candidates.len() == 1
            && completions
                .candidates
                .first()
                .is_some_and(|c| has_operands(&c.text))
        {
            completions.separator = " ";
        }
        return completions;
    }
    let Some(command) = command_of(word(0)) else {
        return completions;
    };
    let Some(operand) = command.operands.get(index - 1) else {
        return completions;
    };
    if index < command.operands.len() {
        completions.separator = ", ";
    }
    let operands: Vec<&str> = (1..index).map(word).collect();
    completions.candidates = match operand.kind {
        OperandKind::Code(set) => code_candidates(set, prefix),
        _ if is_param_operand(operand) => param_rows(command, !prefix.is_empty())
            .into_iter()
            .filter(|(number, row, _)| {
                if prefix.is_empty() || prefix.starts_with(|c: char| c.is_ascii_digit()) {
                    number.to_string().starts_with(prefix)
                } else {
                    row.name
                        .to_ascii_lowercase()
                        .contains(&prefix.to_ascii_lowercase())
                }
            })
            .map(|(number, row, bank)| Candidate {
                text: number.to_string(),
                note: param_note(row, bank),
            })
            .collect(),
        _ if operand.name == "motor" => AXES
            .iter()
            .filter(|axis| axis.number.to_string().starts_with(prefix))
            .map(|axis| Candidate {
                text: axis.number.to_string(),
                note: axis.name.to_string(),
            })
            .collect(),
        _ if operand.name == "bank" => {
            let number = operands.first().and_then(|w| parse_number(w));
            BANKS
                .iter()
                .filter(|(bank, table, _)| {
                    bank.to_string().starts_with(prefix)
                        && number.is_none_or(|n| {
                            table.iter().any(|row| row.numbers.contains(&(n as u8)))
                                && (0..=255).contains(&n)
                        })
                })
                .map(|(bank, table, what)| {
                    let row = number.and_then(|n| {
                        table
                            .iter()
                            .find(|row| u8::try_from(n).is_ok_and(|n| row.numbers.contains(&n)))
                    });
                    Candidate {
                        text: bank.to_string(),
                        note: row.map_or_else(|| what.to_string(), |row| row.name.to_string()),
                    }
                })
                .collect()
        }
        OperandKind::ParamValue(_) => match named_param(command, &operands) {
            Some(ParamInfo {
                range: super::params::ValueRange::OneOf(values),
                name,
                ..
            }) => values
                .iter()
                .map(|v| v.to_string())
                .filter(|v| v.starts_with(prefix))
                .map(|text| Candidate {
                    text,
                    note: name.to_string(),
                })
                .collect(),
            _ => Vec::new(),
        },
        _ => Vec::new(),
    };
    completions
}

fn code_candidates(set: CodeSet, prefix: &str) -> Vec<Candidate> {
    set.entries()
        .into_iter()
        .filter(|(keyword, code)| {
            starts_with_ignore_case(keyword, prefix) || code.to_string() == prefix
        })
        .map(|(keyword, code)| Candidate {
            text: keyword.to_string(),
            note: format!("{code}"),
        })
        .collect()
}

/// Help for the word at `cursor`, read in its line, or for a topic.
pub fn help(line: &str, cursor: usize) -> Vec<String> {
    let all = words(line);
    let word = |i: usize| all.get(i).and_then(|&(s, e)| line.get(s..e)).unwrap_or("");
    if all.is_empty() {
        return Vec::new();
    }
    let Some(command) = command_of(word(0)) else {
        return params_named(line.trim());
    };
    let index = match word_at(line, cursor.min(line.len())) {
        Some(((start, end), index)) if start == end => index.saturating_sub(1),
        Some((_, index)) => index,
        None => 0,
    };
    let mut lines = command_help(command);
    if index == 0 {
        return lines;
    }
    let operands: Vec<&str> = (1..=index).map(word).collect();
    let Some(operand) = command.operands.get(index - 1) else {
        return lines;
    };
    if is_param_operand(operand) || matches!(operand.kind, OperandKind::ParamValue(_)) {
        let param_words = if takes_axis_param(command) {
            vec![word(1)]
        } else {
            vec![word(1), word(2)]
        };
        let rows: Vec<(u8, &'static ParamInfo, Option<u8>)> =
            match named_param(command, &param_words) {
                Some(row) => vec![(
                    parse_number(word(1))
                        .and_then(|n| u8::try_from(n).ok())
                        .unwrap_or(0),
                    row,
                    (!takes_axis_param(command))
                        .then(|| parse_number(word(2)).and_then(|n| u8::try_from(n).ok()))
                        .flatten(),
                )],
                // A global parameter without its bank yet: every bank's row of
                // that number.
                None => {
                    let number = operands.first().and_then(|w| parse_number(w));
                    param_rows(command, true)
                        .into_iter()
                        .filter(|(n, _, _)| number == Some(i32::from(*n)))
                        .collect()
                }
            };
        if !rows.is_empty() {
            lines.truncate(1);
            for (number, row, bank) in rows {
                lines.extend(param_help(number, row, bank));
            }
        }
    }
    lines
}

/// Every parameter whose name contains `text`.
fn params_named(text: &str) -> Vec<String> {
    if text.is_empty() {
        return Vec::new();
    }
    let wanted = text.to_ascii_lowercase();
    let axis = AXIS_PARAMS.iter().map(|row| (row, None));
    let global = BANKS
        .iter()
        .flat_map(|&(bank, table, _)| table.iter().map(move |row| (row, Some(bank))));
    axis.chain(global)
        .filter(|(row, _)| row.name.to_ascii_lowercase().contains(&wanted))
        .flat_map(|(row, bank)| param_help(*row.numbers.start(), row, bank))
        .collect()
}

fn command_help(command: &CommandInfo) -> Vec<String> {
    let mut lines = vec![
        format!(
            "{}   (§{}, instruction {})",
            command.syntax, command.section, command.opcode
        ),
        format!("  {}", command.summary),
    ];
    match command.usage {
        Usage::Standalone => {
            lines.push("  meant for TMCL programs; the module also runs it in direct mode".into())
        }
        Usage::UserDefined => lines.push("  customer-specific firmware extension".into()),
        Usage::DirectAndStandalone | Usage::DirectOnly => {}
    }
    for operand in command.operands {
        let accepts = match operand.kind {
            OperandKind::Byte if operand.name == "motor" => {
                let numbers: Vec<String> = AXES.iter().map(|a| a.number.to_string()).collect();
                format!("{} (the TMCM-1110's motor)", numbers.join(", "))
            }
            OperandKind::Byte if is_param_operand(operand) => {
                if takes_axis_param(command) {
                    "an axis parameter number, 0..255 (§4 Table 16; Tab lists them)".into()
                } else {
                    "a global parameter number, 0..255 (§5; Tab lists them)".into()
                }
            }
            OperandKind::Byte => "0..255".into(),
            OperandKind::Number => format!("{}..{}", i32::MIN, i32::MAX),
            OperandKind::ParamValue(_) => {
                "within the parameter's range (F1 on the parameter)".into()
            }
            OperandKind::Label => "a program address".into(),
            OperandKind::Code(set) => set.describe(),
            OperandKind::Zero => continue,
        };
        let presence = match operand.presence {
            Presence::Required => String::new(),
            Presence::Default(value) => format!(" (optional, default {value})"),
            Presence::SetsType(_) => " (optional)".into(),
        };
        lines.push(format!("  <{}>: {accepts}{presence}", operand.name));
    }
    lines
}

fn param_help(number: u8, row: &ParamInfo, bank: Option<u8>) -> Vec<String> {
    let what = match bank {
        Some(bank) => format!("global parameter {number} of bank {bank}"),
        None => format!("axis parameter {number}"),
    };
    let unit = row.unit.label();
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    let default = row
        .default
        .map(|d| format!(", default {d}"))
        .unwrap_or_default();
    vec![
        format!(
            "{what} “{}”: {}{unit}, access {}{default} ({})",
            row.name, row.range, row.access, row.section
        ),
        format!("  {}", row.description),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(c: &Completions) -> Vec<&str> {
        c.candidates.iter().map(|c| c.text.as_str()).collect()
    }

    #[test]
    fn mnemonics_complete_from_the_catalogue() {
        let c = complete("ms", 2);
        assert_eq!(texts(&c), ["MST"]);
        assert_eq!((c.start, c.end, c.separator), (0, 2, " "));
        assert_eq!(complete("mv", 2).separator, "");
        let c = complete("S", 1);
        assert!(texts(&c).contains(&"SAP") && texts(&c).contains(&"SGP"));
        assert!(texts(&c).iter().all(|t| t.starts_with('S')));
        assert!(complete("", 0).candidates.len() == COMMANDS.len());
    }

    #[test]
    fn symbolic_operands_complete_with_their_codes() {
        let c = complete("MVP a", 5);
        assert_eq!(texts(&c), ["ABS"]);
        assert_eq!(c.candidates[0].note, "0");
        assert_eq!((c.start, c.end, c.separator), (4, 5, ", "));
        let c = complete("MVP ", 4);
        assert_eq!(texts(&c), ["ABS", "REL", "COORD"]);
        assert_eq!(texts(&complete("MVP ABS, ", 9)), ["0"]);
    }

    #[test]
    fn parameters_complete_by_number_or_by_name() {
        let c = complete("SAP 14", 6);
        assert!(texts(&c).contains(&"140"), "{:?}", texts(&c));
        assert!(texts(&c).iter().all(|t| t.starts_with("14")));
        let c = complete("GAP posit", 9);
        let found: Vec<_> = c
            .candidates
            .iter()
            .map(|c| (c.text.as_str(), c.note.as_str()))
            .collect();
        assert!(found.contains(&("0", "Target position")), "{found:?}");
        assert!(found.contains(&("1", "Actual position")));
        // Global parameters name their bank.
        let c = complete("GGP baud", 8);
        assert!(
            c.candidates.iter().any(|c| c.note.contains("(bank 0)")),
            "{c:?}"
        );
        // The banks that hold the parameter already given, named by it.
        let c = complete("GGP 65, ", 8);
        let found: Vec<_> = c
            .candidates
            .iter()
            .map(|c| (c.text.as_str(), c.note.as_str()))
            .collect();
        assert_eq!(found.len(), 2, "{found:?}");
        assert_eq!(found[1], ("2", "User variables #56..#255"));
        // A row of many numbers is offered once until digits are typed.
        let c = complete("GGP ", 4);
        assert_eq!(
            c.candidates
                .iter()
                .filter(|c| c.note.starts_with("User variables #56"))
                .count(),
            1
        );
        let c = complete("GGP 1", 5);
        assert!(texts(&c).contains(&"199"));
    }

    #[test]
    fn nothing_to_complete_is_no_candidate_and_odd_cursors_are_harmless() {
        assert!(complete("NOSUCH ", 7).candidates.is_empty());
        assert!(complete("MVP ABS, 0, 5", 13).candidates.is_empty());
        assert!(complete("GAP 1, 0 // c", 13).candidates.is_empty());
        assert!(complete("é", 1).candidates.is_empty());
        assert!(complete("MVP", 99).candidates.is_empty());
    }

    #[test]
    fn help_shows_syntax_operands_and_parameter_rows() {
        let lines = help("SAP", 3);
        assert!(
            lines[0].starts_with("SAP <parameter>, <motor>, <value>"),
            "{lines:?}"
        );
        assert!(lines[0].contains("§3.6.5"));
        assert!(lines.iter().any(|l| l.contains("<motor>: 0")));
        let lines = help("MVP", 0);
        assert!(
            lines
                .iter()
                .any(|l| l.contains("<mode>: ABS (0), REL (1), COORD (2)"))
        );
        // On the parameter: its row, range and unit.
        let lines = help("SAP 4, 0, 1000", 5);
        assert!(
            lines
                .iter()
                .any(|l| l.starts_with("axis parameter 4 “Maximum positioning speed”")),
            "{lines:?}"
        );
        let lines = help("SAP 4", 5);
        assert!(
            lines
                .iter()
                .any(|l| l.contains("Maximum positioning speed"))
        );
        // A name as a topic.
        let lines = help("baud", 4);
        assert!(
            lines
                .iter()
                .any(|l| l.contains("global parameter 65 of bank 0")),
            "{lines:?}"
        );
        assert!(help("", 0).is_empty());
        assert!(help("zzzz", 4).is_empty());
    }

    proptest::proptest! {
        #[test]
        fn any_line_and_cursor_is_answered_without_panicking(line in ".{0,40}", cursor in 0usize..50) {
            let c = complete(&line, cursor);
            proptest::prop_assert!(c.start <= c.end && c.end <= line.len());
            let _ = help(&line, cursor);
        }
    }
}
