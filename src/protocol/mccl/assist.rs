//! Completion and inline help for MCCL lines, read from the command table
//! ([`super::catalog`]), the status words ([`super::status`]) and the
//! Ch14 error table: nothing here restates the manual.

use super::catalog::{AxisRule, Blocks, COMMANDS, CommandSpec, Output, VARIABLES, allowed_in_task};
use super::line::ascii_lookalike;
use super::reply::ERROR_CODES;
use super::status::StatusWordKind;
use crate::protocol::console::{Candidate, Completions};

/// Where the command under the cursor starts (after the last comma outside
/// a string), and whether the cursor is inside a string.
fn command_start(before: &str) -> (usize, bool) {
    let mut start = 0;
    let mut in_string = false;
    for (at, c) in before.char_indices() {
        match c {
            '"' => in_string = !in_string,
            ',' if !in_string => start = at + 1,
            _ => {}
        }
    }
    (start, in_string)
}

/// The mnemonic a command text starts with, after its axis digits.
fn mnemonic_of(command: &str) -> Option<(usize, String)> {
    let trimmed = command.trim_start();
    let lead = command.len() - trimmed.len();
    let digits = trimmed.bytes().take_while(u8::is_ascii_digit).count();
    let rest = &trimmed[digits..];
    let letters: String = rest
        .chars()
        .map(ascii_lookalike)
        .take_while(char::is_ascii_alphabetic)
        .map(|c| c.to_ascii_uppercase())
        .collect();
    Some((lead + digits, letters))
}

/// Candidates for the word at `cursor`: mnemonics while one is typed,
/// motor-table names inside `LU"…"`.
pub fn complete(line: &str, cursor: usize) -> Completions {
    let Some(before) = line.get(..cursor) else {
        return Completions::default();
    };
    let (start, in_string) = command_start(before);
    let command = &before[start..];
    let Some((offset, typed)) = mnemonic_of(command) else {
        return Completions::default();
    };
    if in_string {
        // Inside a string: only LU's has names to offer.
        let Some(quote) = command.find('"') else {
            return Completions::default();
        };
        if typed != "LU" {
            return Completions::default();
        }
        let name_start = start + quote + 1;
        let prefix = before[name_start..].to_ascii_uppercase();
        let candidates = VARIABLES
            .iter()
            .filter(|(name, _)| name.starts_with(&prefix))
            .map(|(name, read)| Candidate {
                text: name.to_string(),
                note: format!("motor table, read with {read}"),
            })
            .collect();
        return Completions {
            start: name_start,
            end: cursor,
            candidates,
            separator: "\"",
        };
    }
    let after_letters = &command[offset..];
    let letters_typed = after_letters.chars().count();
    if typed.len() > 2 || letters_typed != typed.len() {
        // Past the mnemonic: a parameter is being typed.
        return Completions::default();
    }
    let mut candidates: Vec<Candidate> = COMMANDS
        .iter()
        .filter(|c| c.mnemonic.starts_with(&typed))
        .map(|c| Candidate {
            text: c.mnemonic.to_string(),
            note: format!("{} {}", c.syntax(), c.name),
        })
        .collect();
    candidates.sort_by(|a, b| a.text.cmp(&b.text));
    Completions {
        start: start + offset,
        end: cursor,
        candidates,
        separator: "",
    }
}

fn command_help(spec: &CommandSpec) -> Vec<String> {
    let mut lines = vec![format!(
        "{} {} ({}): {}",
        spec.syntax(),
        spec.name,
        spec.section(),
        spec.meaning
    )];
    let axis = match spec.axis {
        AxisRule::One => "one axis",
        AxisRule::OneOrAll => "one axis, or 0 for all",
        AxisRule::Optional => "an axis or none",
        AxisRule::None => "no axis",
    };
    let mut facts = vec![spec.values(), axis.to_string(), spec.applies.to_string()];
    match spec.output {
        Output::Value => facts.push("replies `AA value`".into()),
        Output::Text => facts.push("replies with text".into()),
        Output::Nothing => {}
    }
    match spec.blocks {
        Blocks::No => {}
        Blocks::Waits => facts.push("waits (Escape aborts)".into()),
        Blocks::RunsMacro => facts.push("runs a macro in the foreground (Escape aborts)".into()),
        Blocks::Loops => facts.push("may repeat for ever (Escape aborts)".into()),
        Blocks::Steps => facts.push("single-steps".into()),
    }
    if !allowed_in_task(spec) {
        facts.push("not in a background task".into());
    }
    if let Some(code) = spec.code {
        facts.push(format!("code {code:X}h"));
    }
    lines.push(format!("  {}", facts.join(" · ")));
    if spec.mnemonic == "TS" {
        for kind in StatusWordKind::ALL {
            lines.push(format!("  TS{}: {}", kind.selector(), kind.title()));
            lines.extend(
                kind.bits()
                    .iter()
                    .map(|b| format!("    bit {:>2}: {}", b.bit, b.meaning)),
            );
        }
    }
    if spec.mnemonic == "LU" {
        let names: Vec<&str> = VARIABLES.iter().map(|(n, _)| *n).collect();
        lines.push(format!("  names: {}", names.join(" ")));
    }
    lines
}

/// Help on a topic: `errors` (Ch14), `status` (the TS words), `variables`
/// (the motor table), or words of the commands' names and meanings.
fn topic(text: &str) -> Vec<String> {
    match text.to_ascii_lowercase().as_str() {
        "errors" | "error" | "?" => ERROR_CODES
            .iter()
            .map(|e| format!("?{} — {}", e.code, e.meaning))
            .collect(),
        "status" => StatusWordKind::ALL
            .iter()
            .flat_map(|kind| {
                std::iter::once(format!("TS{}: {}", kind.selector(), kind.title())).chain(
                    kind.bits()
                        .iter()
                        .map(|b| format!("  bit {:>2}: {}", b.bit, b.meaning)),
                )
            })
            .collect(),
        "variables" | "motor table" => VARIABLES
            .iter()
            .map(|(name, read)| format!("{name} (read with {read})"))
            .collect(),
        words => COMMANDS
            .iter()
            .filter(|c| {
                c.name.to_ascii_lowercase().contains(words)
                    || c.meaning.to_ascii_lowercase().contains(words)
            })
            .map(|c| format!("{} {}: {}", c.syntax(), c.name, c.meaning))
            .collect(),
    }
}

/// Help for the command under `cursor` in `line`, or for a topic.
pub fn help(line: &str, cursor: usize) -> Vec<String> {
    let text = line.trim();
    if text.is_empty() {
        return Vec::new();
    }
    let cursor = cursor.min(line.len());
    let before = line.get(..cursor).unwrap_or(line);
    let (start, _) = command_start(before);
    let command_end = line[start..].find(',').map_or(line.len(), |at| start + at);
    let command = line.get(start..command_end).unwrap_or_default();
    let unquoted = command.trim().split('"').next().unwrap_or_default();
    if let Some((_, letters)) = mnemonic_of(command)
        && !unquoted.contains(' ')
        && letters.len() >= 2
        && let Some(spec) = COMMANDS.iter().find(|c| c.mnemonic == &letters[..2])
        && (letters.len() == 2 || command.trim().len() <= 3)
    {
        return command_help(spec);
    }
    topic(text)
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
    fn mnemonics_complete_after_the_axis_and_the_comma() {
        assert_eq!(
            texts("1M"),
            [
                "MA", "MC", "MD", "ME", "MF", "MJ", "MN", "MP", "MR", "MS", "MV"
            ]
        );
        assert_eq!(
            texts("1MR1000,W"),
            [
                "WA", "WB", "WD", "WE", "WF", "WI", "WL", "WN", "WP", "WR", "WS", "WT", "WV", "WW"
            ]
        );
        assert_eq!(texts("2mr1000,ws"), ["WS"]);
        let c = complete("1MR1000,2T", 10);
        assert_eq!((c.start, c.end), (9, 10));
        assert!(c.candidates.iter().all(|c| c.text.starts_with('T')));
        assert!(texts("1MR10").is_empty(), "a parameter");
        assert!(texts("").len() > 190);
    }

    #[test]
    fn names_complete_inside_lu() {
        assert_eq!(texts("LU\"POS"), ["POSCOUNT", "POSITION", "POSDBAND"]);
        let c = complete("LU\"STA", 6);
        assert_eq!((c.start, c.separator), (3, "\""));
        assert!(texts("OT\"POS").is_empty());
    }

    #[test]
    fn help_shows_the_command_under_the_cursor() {
        let help = help("2MR1000,WS0.5", 9);
        assert!(
            help[0].starts_with("aWSn Wait for Stop (Ch12 WS)"),
            "{help:?}"
        );
        assert!(help[1].contains("waits (Escape aborts)"), "{help:?}");
        let tp = super::help("1TP.3", 0);
        assert!(
            tp[1].contains("precision") && tp[1].contains("not in a background task"),
            "{tp:?}"
        );
        let ts = super::help("1TS", 0);
        assert!(
            ts.iter()
                .any(|l| l.contains("bit 28: Limit Positive Input Active"))
        );
        assert!(super::help("LU", 0).iter().any(|l| l.contains("PGMVEL")));
        assert!(super::help("", 0).is_empty());
    }

    #[test]
    fn topics_and_words() {
        let errors = help("errors", 0);
        assert_eq!(errors.len(), ERROR_CODES.len());
        assert!(errors.iter().any(|l| l == "?-6 — Macro Doesn't Exist"));
        assert!(help("status", 0).iter().any(|l| l.starts_with("TS160")));
        assert!(
            help("variables", 0)
                .iter()
                .any(|l| l == "KPOS (read with RV)")
        );
        assert!(help("velocity", 0).iter().any(|l| l.starts_with("aSVn")));
        assert!(help("no such words here", 0).is_empty());
    }
}
