//! Tab completion and inline help for CMD-4CR command text, read from the
//! command table ([`super::catalog`]) and the §4.2 and MST/POL tables
//! ([`super::reply`]): nothing here restates the manual.

use super::catalog::{
    Axis, COMMANDS, CommandSpec, Form, Format, Kind, keywords_longest_first, rows_of,
};
use super::reply::{ERRORS, MST_BITS, POL_FIELDS};
use crate::protocol::console::{Candidate, Completions};

/// An indexed command with more numbers than this is offered by its
/// keyword until its number is being typed (`V` has 100).
const MAX_EXPANDED: usize = 8;

/// The text being typed, upper case without blanks, and where it starts.
fn typed(line: &str, cursor: usize) -> Option<(usize, String)> {
    let before = line.get(..cursor)?;
    let start = before.len() - before.trim_start().len();
    let text: String = before
        .chars()
        .filter(|c| !c.is_whitespace())
        .map(|c| c.to_ascii_uppercase())
        .collect();
    Some((start, text))
}

/// The completions of one row for what is typed.
fn row_candidates(row: &'static CommandSpec, prefix: &str, out: &mut Vec<Candidate>) {
    let note = format!("{} {}", row.syntax, row.meaning);
    let mut push = |text: String| {
        if text.starts_with(prefix) && !out.iter().any(|c| c.text == text) {
            out.push(Candidate {
                text,
                note: note.clone(),
            });
        }
    };
    let keyword = row.keyword;
    let typed_past_keyword = !keyword.is_empty() && prefix.starts_with(keyword);
    match row.form {
        Form::Bare => push(keyword.to_string()),
        Form::Axis if typed_past_keyword => {
            for axis in Axis::ALL {
                push(format!("{keyword}{}", axis.letter()));
            }
        }
        Form::Index { first, last }
            if typed_past_keyword
                && (usize::from(last - first) < MAX_EXPANDED || prefix.len() > keyword.len()) =>
        {
            for n in first..=last {
                push(format!("{keyword}{n}"));
            }
        }
        Form::Motion if keyword.is_empty() => {
            // The move command starts with an axis letter.
            if prefix.len() <= 1 {
                for axis in Axis::ALL {
                    push(axis.letter().to_string());
                }
            }
        }
        _ => push(keyword.to_string()),
    }
}

/// Candidates for the command being typed up to `cursor`: keywords, then,
/// once a keyword is typed, its axis letters or numbers.
pub fn complete(line: &str, cursor: usize) -> Completions {
    let Some((start, prefix)) = typed(line, cursor) else {
        return Completions::default();
    };
    // After `=` comes a value: nothing to offer.
    if prefix.contains('=') {
        return Completions::default();
    }
    let mut candidates = Vec::new();
    for row in COMMANDS {
        row_candidates(row, &prefix, &mut candidates);
    }
    Completions {
        start,
        end: cursor,
        candidates,
        separator: "",
    }
}

/// The keyword `text` starts with, and whether it is a move (`X100`).
fn keyword_of(text: &str) -> Option<&'static str> {
    let mut chars = text.chars();
    let is_move = chars.next().and_then(Axis::from_letter).is_some()
        && chars
            .next()
            .is_none_or(|c| c.is_ascii_digit() || c == '-' || c == '+');
    if is_move {
        return Some("");
    }
    keywords_longest_first()
        .iter()
        .copied()
        .find(|k| text.starts_with(k))
}

fn values_line(row: &CommandSpec) -> String {
    let mut parts = Vec::new();
    if let Some(values) = row.values {
        match values.format {
            Format::Integer | Format::TwoDigits => {
                let unit = if values.unit.is_empty() {
                    String::new()
                } else {
                    format!(" {}", values.unit)
                };
                parts.push(format!("{}..{}{unit}", values.min, values.max));
            }
            Format::Thousandths => parts.push("0.001..999.999".into()),
            Format::Fields(names) => parts.push(format!("reply {}", names.join(":"))),
            Format::Text => parts.push("reply: text".into()),
        }
    }
    if let Form::Index { first, last } = row.form {
        parts.push(format!("numbered {first}..{last}"));
    }
    if row.stored {
        parts.push("kept in flash by STORE".into());
    }
    parts.push(format!("§{}", row.section));
    format!("  {}", parts.join(" · "))
}

fn row_help(row: &CommandSpec) -> Vec<String> {
    vec![
        format!("{} ({}): {}", row.syntax, row.access.label(), row.meaning),
        values_line(row),
    ]
}

/// How well `rest` (what follows the keyword) fits the row's form: 2 it
/// is in that form, 1 it may become it (nothing typed after the keyword
/// yet), 0 it is not (`HOME` is not `H` and an axis: it is a topic).
fn fit(row: &CommandSpec, rest: &str) -> u8 {
    let mut chars = rest.chars();
    let first = chars.next();
    let second = chars.next();
    let is_axis = |c: Option<char>| c.is_some_and(|c| Axis::from_letter(c).is_some());
    let is_number = |c: Option<char>| c.is_some_and(|c| c.is_ascii_digit() || c == '-' || c == '+');
    let exact = match (row.form, row.kind) {
        (Form::Bare, _) => first.is_none(),
        (Form::Axis, _) => is_axis(first) && second.is_none(),
        (Form::Index { .. }, _) => first.is_some_and(|c| c.is_ascii_digit()),
        (Form::Motion, Kind::Jog | Kind::ZMove | Kind::Home) => {
            is_axis(first) && (second.is_none() || matches!(second, Some('+' | '-')))
        }
        (Form::Motion, Kind::NewTarget) => {
            is_axis(first) && (second.is_none() || is_number(second))
        }
        (Form::Motion, Kind::Circle | Kind::Arc) => is_axis(first),
        (Form::Motion, Kind::HelicalCircle | Kind::HelicalArc) => matches!(first, Some('P' | 'N')),
        (Form::Motion, Kind::BufferMove) => is_number(first),
        (Form::Motion, _) => true,
    };
    match (exact, first) {
        (true, _) => 2,
        (false, None) => 1,
        (false, Some(_)) => 0,
    }
}

/// Help on a topic: `errors` (Table 4-41), `mst` (Table 2-28), `pol`
/// (the POL fields), or words of a meaning (`:help speed`).
fn topic(text: &str) -> Vec<String> {
    match text.to_ascii_lowercase().as_str() {
        "errors" | "error" | "?" => ERRORS
            .iter()
            .map(|e| format!("{} — {}", e.reply, e.meaning))
            .collect(),
        _ => {
            let words = text.to_ascii_lowercase();
            COMMANDS
                .iter()
                .filter(|row| {
                    row.meaning.to_ascii_lowercase().contains(&words)
                        || row.syntax.to_ascii_lowercase().contains(&words)
                })
                .map(|row| format!("{} ({}): {}", row.syntax, row.access.label(), row.meaning))
                .collect()
        }
    }
}

/// Help from the tables for the command `line` holds, or for a topic. The
/// first line is the syntax of the form being typed.
pub fn help(line: &str, cursor: usize) -> Vec<String> {
    let _ = cursor;
    let text = line.trim();
    if text.is_empty() {
        return Vec::new();
    }
    let compact: String = text
        .chars()
        .filter(|c| !c.is_whitespace())
        .map(|c| c.to_ascii_uppercase())
        .collect();
    let head = compact.split('=').next().unwrap_or_default();
    let Some(keyword) = keyword_of(head) else {
        return topic(text);
    };
    let rest = head.get(keyword.len()..).unwrap_or_default();
    let mut rows: Vec<&'static CommandSpec> = if keyword.is_empty() {
        COMMANDS.iter().filter(|r| r.kind == Kind::Move).collect()
    } else {
        rows_of(keyword).collect()
    };
    if rows.iter().all(|row| fit(row, rest) == 0) {
        return topic(text);
    }
    // The form being typed first: its syntax is the hint under the line.
    rows.sort_by_key(|row| std::cmp::Reverse(fit(row, rest)));
    let mut lines: Vec<String> = rows.iter().flat_map(|row| row_help(row)).collect();
    match keyword {
        "MST" => lines.extend(
            MST_BITS
                .iter()
                .map(|b| format!("  bit {:>2}: {}", b.bit, b.description)),
        ),
        "POL" => {
            lines.push(
                "  Table 2-17 is lost: the fields are known, not what their values mean".into(),
            );
            lines.extend(
                POL_FIELDS
                    .iter()
                    .map(|f| format!("  {}: {} (§{})", f.bits(), f.name, f.section)),
            );
        }
        _ => {}
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(line: &str) -> Vec<String> {
        complete(line, line.len())
            .candidates
            .into_iter()
            .map(|c| c.text)
            .collect()
    }

    #[test]
    fn keywords_complete_then_their_axes_and_numbers() {
        assert_eq!(texts("HSP"), ["HSPD"]);
        assert_eq!(texts("HSPD"), ["HSPD", "HSPDX", "HSPDY", "HSPDZ", "HSPDU"]);
        assert_eq!(texts("hspdu"), ["HSPDU"]);
        assert_eq!(
            texts("SACTRL"),
            ["SACTRL0", "SACTRL1", "SACTRL2", "SACTRL3"]
        );
        assert_eq!(
            texts("V"),
            ["V", "VER"],
            "100 variables are not listed at once"
        );
        assert_eq!(
            texts("V9"),
            [
                "V9", "V90", "V91", "V92", "V93", "V94", "V95", "V96", "V97", "V98", "V99"
            ]
        );
        assert!(texts("ST").iter().any(|t| t == "STORE"));
        assert!(texts("HSPDX=").is_empty());
        let all = texts("");
        assert!(all.len() > 80, "every keyword: {}", all.len());
        let c = complete("  hs", 4);
        assert_eq!((c.start, c.end), (2, 4));
        assert!(c.candidates.iter().all(|c| !c.note.is_empty()));
    }

    #[test]
    fn help_starts_with_the_form_being_typed() {
        let help = help("HSPDX=5000", 0);
        assert!(help[0].starts_with("HSPD[axis]=[value] (R/W)"), "{help:?}");
        assert!(
            help[1].contains("0..6553500 pps") && help[1].contains("§2.1.4"),
            "{help:?}"
        );
        let bare = super::help("HSPD", 0);
        assert!(bare[0].starts_with("HSPD=[value]"), "{bare:?}");
        assert!(super::help("X1000", 0)[0].starts_with("[axis][targetpos]"));
        assert!(super::help("CIRXYP1:1", 0)[0].starts_with("CIR[A1][A2]"));
        assert!(
            super::help("POLX", 0)
                .iter()
                .any(|l| l.contains("bits 15-16: MPG input mode"))
        );
        assert!(
            super::help("MSTX", 0)
                .iter()
                .any(|l| l.contains("bit 16: EMG error"))
        );
        assert!(super::help("SLRY", 0)[1].contains("kept in flash by STORE"));
        assert!(super::help("", 0).is_empty());
    }

    #[test]
    fn topics_and_words_of_meanings() {
        let errors = help("errors", 0);
        assert_eq!(errors.len(), ERRORS.len());
        assert!(errors[1].starts_with("?Error Moving"));
        let found = help("joystick", 0);
        assert!(found.iter().any(|l| l.starts_with("JENA")), "{found:?}");
        assert!(help("nothing like this", 0).is_empty());
        // Typing a keyword: the rows it may become.
        assert!(
            help("HSP", 0)[0].starts_with("HSPD"),
            "{:?}",
            help("HSP", 0)
        );
        assert!(help("home", 0).iter().any(|l| l.starts_with("H[axis]")));
    }
}
