//! MCCL text files as a program tool (Ch4 "Downloading MCCL Text Files",
//! "Building MCCL Macro Sequences"): the lines WinControl's File–Open sends
//! — `;` comments stripped outside strings, blank lines skipped — checked
//! whole against the §17 rules with located errors and warnings, coloured,
//! and sent one line at a time ([`super::plan`]); the macros they define
//! read back with `TM` and compared; the controller's macros uploaded with
//! `TM-1` as a file that defines them again. The macro manager
//! ([`MacroStore`]) lists the macros, deletes one the only way MCCL can
//! (`RM` erases them all, the others defined again), and lists and ends
//! background tasks (`ID7`, `ET`).
//!
//! Registers are the variables a console can watch (`TRn`, n ≤ 255 as
//! Ch8 TR prints it).

use crate::protocol::program::{NoSuchVariable, StoreError};
use std::collections::{BTreeMap, BTreeSet};
use std::ops::Range;
use std::sync::Arc;

use super::catalog;
use super::check::{CheckContext, Severity, check_file};
use super::console::MclConsole;
use super::line::{Line, NumberBase, Value, ascii_lookalike, comment_start, parse_line};
use super::plan::{MacroVerify, TextDownload, Upload};
use crate::protocol::console::ReplyValue;
use crate::protocol::program::{
    Checked, CheckedProgram, Deletion, DownloadOptions, Problem, ProgramStore, ProgramTool,
    SourceLoader, StoredProgram, SyntaxClass, TransferFailure, TransferPlan, UploadExtent,
    VariableSet,
};

/// The console the tool prepares its lines with.
const CONSOLE: MclConsole = MclConsole::DEFAULT;

/// MCCL text files and macros.
#[derive(Debug, Clone, Copy, Default)]
pub struct MclTool;

/// Registers as the watch panel shows them (`TRn`: Ch8 TR, n ≤ 255).
pub static REGISTERS: VariableSet = VariableSet {
    key: "mccl_registers",
    heading: "registers",
    mark: "R",
    prompt: "watch register (0..255; a watched one stops): ",
    read_line: |n| format!("TR{n}"),
    of_line: |line| line.trim().strip_prefix("TR").and_then(|n| n.parse().ok()),
    parse: |text| {
        text.trim().parse::<u8>().map_err(|_| NoSuchVariable {
            set: "TR reads registers",
            numbers: "0..255",
            typed: text.to_string(),
        })
    },
    name: |n| format!("register R{n}"),
};

/// One line a download sends, where it was in the file.
#[derive(Debug, Clone)]
pub struct FileLine {
    /// 1-based line of the source.
    pub number: usize,
    pub line: Line,
}

impl FileLine {
    /// The macro the line defines (`MDn` first), if it does.
    pub fn defines(&self) -> Option<i64> {
        self.line
            .defines_macro()
            .then(|| self.line.commands[0].number().map(|n| n as i64))
            .flatten()
    }
}

/// A text file that checked: the lines to send, in order.
#[derive(Debug)]
pub struct MclProgram {
    pub lines: Vec<FileLine>,
}

impl MclProgram {
    /// The macros the file defines, each with the index of the line that
    /// defines it last (a later definition replaces an earlier one).
    pub fn macros(&self) -> Vec<(i64, usize)> {
        let mut last: BTreeMap<i64, usize> = BTreeMap::new();
        for (index, line) in self.lines.iter().enumerate() {
            if let Some(n) = line.defines() {
                last.insert(n, index);
            }
        }
        last.into_iter().collect()
    }

    /// Stored bytes of the macros defined (the checker's estimate).
    fn macro_bytes(&self) -> usize {
        self.lines
            .iter()
            .filter(|l| l.defines().is_some())
            .flat_map(|l| l.line.commands[1..].iter())
            .map(super::check::stored_bytes)
            .sum()
    }
}

/// The register a command at byte `column` of `text` names (`@n`, `ARn`,
/// `RAn`, `TRn`), if it is one of 0..255.
fn register_at(text: &str, column: usize) -> Option<u8> {
    let line = parse_line(text, NumberBase::Decimal).ok()?;
    let command = line
        .commands
        .iter()
        .find(|c| c.span.contains(&column) || c.span.end == column)?;
    let register = match (&command.value, command.mnemonic()) {
        (Some(Value::Register(r)), _) => i64::from(*r),
        (_, "AR" | "RA" | "TR") => command.number()? as i64,
        _ => return None,
    };
    u8::try_from(register).ok()
}

impl CheckedProgram for MclProgram {
    fn state(&self) -> String {
        let macros = self.macros().len();
        format!(
            "checks: {} line(s) to send, {macros} macro(s){}",
            self.lines.len(),
            if macros > 0 {
                format!(" (about {} bytes)", self.macro_bytes())
            } else {
                String::new()
            }
        )
    }

    fn built(&self) -> String {
        self.state()
    }

    fn size(&self) -> usize {
        self.lines.len()
    }

    fn line_of(&self, unit: usize) -> Option<usize> {
        self.lines.get(unit).map(|l| l.number)
    }

    fn line_of_counter(&self, _counter: i64) -> Option<usize> {
        None
    }

    fn variable_at(&self, _line: usize, text: &str, column: usize) -> Option<u8> {
        register_at(text, column)
    }

    fn download(
        &self,
        address: u8,
        _options: DownloadOptions,
    ) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Ok(Box::new(TextDownload::new(address, self)?))
    }

    fn verify(&self, address: u8) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Ok(Box::new(MacroVerify::new(address, self)?))
    }

    fn listing(&self) -> Option<String> {
        let mut text = String::new();
        for line in &self.lines {
            text.push_str(&format!("{:>5}  {}\n", line.number, line.line));
        }
        Some(text)
    }
}

/// The 1-based column of byte `at` of `text`.
fn column_of(text: &str, at: usize) -> usize {
    text.get(..at.min(text.len()))
        .map_or(at, |before| before.chars().count())
        + 1
}

impl ProgramTool for MclTool {
    fn name(&self) -> &'static str {
        "MCCL"
    }

    fn controller(&self) -> &'static str {
        "MultiFlex"
    }

    /// `init.mfx1` is the manual's own text file (Ch4 Figure 7).
    fn extensions(&self) -> &'static [&'static str] {
        &["mccl", "mfx", "mfx1"]
    }

    fn unit(&self) -> &'static str {
        "line"
    }

    fn check(&self, _name: &str, source: &str, _files: &dyn SourceLoader) -> Checked {
        let context = CheckContext {
            machine: &CONSOLE.machine,
            profile: &CONSOLE.profile,
        };
        let texts: Vec<&str> = source.split('\n').collect();
        let mut problems: Vec<Problem> = check_file(source, &context, &BTreeSet::new())
            .into_iter()
            .filter(|(_, d)| d.severity != Severity::Note)
            .map(|(number, d)| {
                let text = texts.get(number - 1).copied().unwrap_or_default();
                let column = column_of(text, d.span.start);
                let error = d.severity == Severity::Error;
                Problem {
                    line: number,
                    column,
                    text: format!(
                        "{number}:{column}: {}: {}",
                        if error { "error" } else { "warning" },
                        d.message
                    ),
                    message: d.message,
                    error,
                    in_source: true,
                }
            })
            .collect();
        let mut lines = Vec::new();
        for (index, raw) in texts.iter().enumerate() {
            let body = &raw[..comment_start(raw).unwrap_or(raw.len())];
            if body.trim().is_empty() {
                continue;
            }
            if let Ok(line) = parse_line(raw, NumberBase::Decimal) {
                // What the console cannot send (BK"text" single-steps).
                if let Err(message) = CONSOLE.parse_checked(raw)
                    && !problems.iter().any(|p| p.line == index + 1 && p.error)
                {
                    problems.push(Problem {
                        line: index + 1,
                        column: 1,
                        text: format!("{}:1: error: {message}", index + 1),
                        message: message.to_string(),
                        error: true,
                        in_source: true,
                    });
                }
                lines.push(FileLine {
                    number: index + 1,
                    line,
                });
            }
        }
        // A macro defined again keeps its old bytes until RM (Ch4).
        let mut defined: BTreeMap<i64, usize> = BTreeMap::new();
        for line in &lines {
            if let Some(n) = line.defines()
                && let Some(first) = defined.insert(n, line.number)
            {
                let message = format!(
                    "macro {n} is defined again (first on line {first}): the controller keeps \
                     the old one's bytes until RM (Ch4)"
                );
                problems.push(Problem {
                    line: line.number,
                    column: 1,
                    text: format!("{}:1: warning: {message}", line.number),
                    message,
                    error: false,
                    in_source: true,
                });
            }
        }
        problems.sort_by_key(|p| (p.line, p.column));
        let program = (!problems.iter().any(|p| p.error))
            .then(|| Arc::new(MclProgram { lines }) as Arc<dyn CheckedProgram>);
        Checked { problems, program }
    }

    fn highlight(
        &self,
        lines: &[String],
        shown: Range<usize>,
    ) -> Vec<Vec<(Range<usize>, SyntaxClass)>> {
        lines
            .get(shown)
            .unwrap_or_default()
            .iter()
            .map(|line| highlight_line(line))
            .collect()
    }

    fn variable_on_line(&self, text: &str, column: usize) -> Option<u8> {
        register_at(text, column)
    }

    fn variables(&self) -> Option<&'static VariableSet> {
        Some(&REGISTERS)
    }

    fn upload(
        &self,
        address: u8,
        _extent: UploadExtent,
    ) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Ok(Box::new(Upload::new(address)?))
    }

    fn store(&self) -> Option<&'static dyn ProgramStore> {
        Some(&MacroStore)
    }
}

/// The classes of one line: `;` comments (outside strings), strings,
/// two-letter mnemonics (the catalogue's, the PDF's look-alike letters
/// read as ASCII; anything else invalid), numbers and axes, `@n`
/// registers.
pub fn highlight_line(line: &str) -> Vec<(Range<usize>, SyntaxClass)> {
    let mut pieces: Vec<(Range<usize>, SyntaxClass)> = Vec::new();
    let comment = comment_start(line).unwrap_or(line.len());
    let chars: Vec<(usize, char)> = line[..comment].char_indices().collect();
    let end_of = |i: usize| chars.get(i).map_or(comment, |(at, _)| *at);
    let mut i = 0;
    while i < chars.len() {
        let (at, c) = chars[i];
        let start = i;
        let class = if c == '"' {
            i += 1;
            while i < chars.len() && chars[i].1 != '"' {
                i += 1;
            }
            i = (i + 1).min(chars.len());
            SyntaxClass::Label
        } else if c == '@' {
            i += 1;
            while i < chars.len() && chars[i].1.is_ascii_digit() {
                i += 1;
            }
            SyntaxClass::Variable
        } else if c.is_ascii_digit() || matches!(c, '-' | '+' | '.') {
            while i < chars.len()
                && (chars[i].1.is_ascii_digit()
                    || matches!(chars[i].1, '-' | '+' | '.' | 'e' | 'E')
                        && (chars[i].1 != 'e' && chars[i].1 != 'E' || i > start))
            {
                // An exponent only inside a number, never a mnemonic's E.
                if matches!(chars[i].1, 'e' | 'E')
                    && !chars
                        .get(i + 1)
                        .is_some_and(|(_, n)| n.is_ascii_digit() || *n == '-')
                {
                    break;
                }
                i += 1;
            }
            SyntaxClass::Number
        } else if ascii_lookalike(c).is_ascii_alphabetic() {
            let mut mnemonic = String::new();
            while i < chars.len() && ascii_lookalike(chars[i].1).is_ascii_alphabetic() {
                mnemonic.push(ascii_lookalike(chars[i].1).to_ascii_uppercase());
                i += 1;
            }
            if mnemonic.len() == 2 && catalog::find(&mnemonic).is_some() {
                SyntaxClass::Keyword
            } else {
                SyntaxClass::Invalid
            }
        } else {
            i += 1;
            SyntaxClass::Plain
        };
        let _ = at;
        let range = end_of(start)..end_of(i);
        match pieces.last_mut() {
            Some((last, last_class)) if *last_class == class && last.end == range.start => {
                last.end = range.end;
            }
            _ => pieces.push((range, class)),
        }
    }
    if comment < line.len() {
        pieces.push((comment..line.len(), SyntaxClass::Comment));
    }
    pieces.retain(|(range, _)| !range.is_empty());
    pieces
}

/// A macro as `TM` lists it: `MC<n>,` and its commands (the manual's
/// `MC1,1LM2,1LN3,MJ10`; its BK example has a blank after the number and
/// reals as `0.100000`, Ch4): the number and the commands' text.
pub fn listed_macro(text: &str) -> Option<(i64, &str)> {
    let rest = text
        .trim()
        .strip_prefix("MC")
        .or_else(|| text.trim().strip_prefix("mc"))?;
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    let number = rest.get(..digits)?.parse().ok()?;
    let body = rest[digits..]
        .strip_prefix([',', ' '])
        .unwrap_or(&rest[digits..]);
    Some((number, body.trim()))
}

/// Every macro of a `TM-1` (or `TMn`) answer.
pub fn listed_macros(listing: &ReplyValue) -> Vec<StoredProgram> {
    let text = match listing {
        ReplyValue::Text(text) => text.as_str(),
        _ => "",
    };
    text.lines()
        .filter_map(listed_macro)
        .map(|(number, body)| StoredProgram {
            number,
            text: body.to_string(),
        })
        .collect()
}

/// Whether the commands `listed` (as `TM` lists a macro) are the commands
/// `sent` (the body of an `MD` line): the same mnemonics on the same axes
/// (written or carried) with the same values (numbers by value, so that
/// `WS.1` is `WS0.100000`).
pub fn same_commands(sent: &Line, listed: &str) -> Result<(), String> {
    let listed = parse_line(listed, NumberBase::Decimal)
        .map_err(|e| format!("the listing does not read as MCCL: {e}"))?;
    if sent.commands.len() != listed.commands.len() {
        return Err(format!(
            "{} commands sent, {} listed",
            sent.commands.len(),
            listed.commands.len()
        ));
    }
    for (index, (a, b)) in sent.commands.iter().zip(&listed.commands).enumerate() {
        let same_value = match (&a.value, &b.value) {
            (Some(Value::Number(x)), Some(Value::Number(y))) => {
                (x.value() - y.value()).abs() <= 1e-9 * x.value().abs().max(1.0)
            }
            (None, Some(Value::Number(y))) => y.value() == 0.0,
            (Some(Value::Number(x)), None) => x.value() == 0.0,
            (x, y) => x == y,
        };
        if a.mnemonic() != b.mnemonic()
            || sent.axis_of(index).number() != listed.axis_of(index).number()
            || !same_value
        {
            return Err(format!(
                "command {} was sent `{a}`, listed `{b}`",
                index + 1
            ));
        }
    }
    Ok(())
}

/// The macro manager: `TM-1` lists, `RM` and the others defined again
/// delete one (MCCL has no single-macro delete, Ch10 RM), `ID7` lists the
/// background tasks, `ET` ends one.
#[derive(Debug, Clone, Copy, Default)]
pub struct MacroStore;

impl ProgramStore for MacroStore {
    fn stored_noun(&self) -> &'static str {
        "macro"
    }

    fn list_line(&self) -> String {
        "TM-1".into()
    }

    fn stored(&self, listing: &ReplyValue) -> Vec<StoredProgram> {
        listed_macros(listing)
    }

    fn delete(&self, listing: &[StoredProgram], number: i64) -> Result<Deletion, StoreError> {
        if !listing.iter().any(|m| m.number == number) {
            return Err(StoreError::NoSuch {
                noun: "macro",
                list_line: "TM-1",
                number,
                listed: listing.iter().map(|m| m.number).collect(),
            });
        }
        let kept: Vec<StoredProgram> = listing
            .iter()
            .filter(|m| m.number != number)
            .cloned()
            .collect();
        let mut lines = vec!["RM".to_string()];
        for stored in &kept {
            let line = format!("MD{},{}", stored.number, stored.text);
            CONSOLE
                .parse_checked(&line)
                .map_err(|e| StoreError::CannotRewrite {
                    noun: "macro",
                    number: stored.number,
                    why: e.to_string(),
                })?;
            lines.push(line);
        }
        Ok(Deletion {
            warning: format!(
                "RM erases every macro (Ch10: there is no single-macro delete); {} other(s) are \
                 defined again from the listing{}",
                kept.len(),
                if kept.is_empty() {
                    String::new()
                } else {
                    ": a failure on the way leaves them erased".to_string()
                }
            ),
            lines,
            kept,
        })
    }

    fn compare(&self, kept: &[StoredProgram], listing: &[StoredProgram]) -> Result<(), StoreError> {
        let numbers = |list: &[StoredProgram]| list.iter().map(|m| m.number).collect::<Vec<_>>();
        if numbers(kept) != numbers(listing) {
            return Err(StoreError::OtherNumbers {
                noun: "macro",
                listed: numbers(listing),
                kept: numbers(kept),
            });
        }
        for (meant, listed) in kept.iter().zip(listing) {
            let differs = |why: String| StoreError::OtherText {
                noun: "macro",
                number: meant.number,
                why,
            };
            let sent =
                parse_line(&meant.text, NumberBase::Decimal).map_err(|e| differs(e.to_string()))?;
            same_commands(&sent, &listed.text).map_err(differs)?;
        }
        Ok(())
    }

    fn running_noun(&self) -> &'static str {
        "background task"
    }

    fn running_line(&self) -> Option<String> {
        Some("ID7".into())
    }

    /// `ID7`'s format is lost with the manual's figures: every line that
    /// names an ID (`Task ID 1`) gives its last number.
    fn running(&self, answer: &ReplyValue) -> Vec<i64> {
        let text = match answer {
            ReplyValue::Text(text) => text.clone(),
            ReplyValue::Number(n) => n.to_string(),
            ReplyValue::None => String::new(),
        };
        text.lines()
            .filter(|l| l.to_ascii_uppercase().contains("ID"))
            .filter_map(|l| {
                l.split(|c: char| !c.is_ascii_digit())
                    .rfind(|w| !w.is_empty())
                    .and_then(|w| w.parse().ok())
            })
            .collect()
    }

    fn stop_line(&self, id: i64) -> String {
        format!("ET{id}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::program::NoIncludes;

    fn check(source: &str) -> Checked {
        MclTool.check("test.mccl", source, &NoIncludes)
    }

    #[test]
    fn a_file_checks_with_located_errors_and_warnings() {
        let checked = check("; homing\nMD5,5LM2 ;limits\n  1MR1000,N0\nMD5,5LM1\n1TP,RP2,2TP\n");
        let errors: Vec<(usize, usize, &str)> = checked
            .errors()
            .map(|p| (p.line, p.column, p.message.as_str()))
            .collect();
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert_eq!((errors[0].0, errors[0].1), (3, 11), "`N0` on line 3");
        assert!(errors[0].2.contains("NO"), "{errors:?}");
        let warnings: Vec<(usize, &str)> = checked
            .problems
            .iter()
            .filter(|p| !p.error)
            .map(|p| (p.line, p.message.as_str()))
            .collect();
        assert!(
            warnings
                .iter()
                .any(|(l, m)| *l == 4 && m.contains("defined again"))
        );
        assert!(
            warnings
                .iter()
                .any(|(l, m)| *l == 5 && m.contains("what follows RP"))
        );
        assert!(checked.program.is_none());
        let good = check("; homing\nMD5,5LM2 ;limits\nMC5\n");
        let program = good.program.expect("checks");
        assert_eq!(program.size(), 2);
        assert_eq!(program.line_of(0), Some(2));
        assert!(program.state().contains("2 line(s) to send, 1 macro(s)"));
    }

    #[test]
    fn what_the_console_cannot_send_is_an_error_too() {
        let checked = check("BK\"wait\"\n");
        assert!(checked.errors().any(|p| p.message.contains("single-steps")));
    }

    #[test]
    fn colours_follow_the_syntax() {
        let line = "MD10,1MR-1.5e3,AL@100,OT\"a;b\",XX ;comment";
        let classes: Vec<(&str, SyntaxClass)> = highlight_line(line)
            .into_iter()
            .map(|(r, c)| (&line[r], c))
            .collect();
        assert!(classes.contains(&("MD", SyntaxClass::Keyword)));
        assert!(classes.contains(&("-1.5e3", SyntaxClass::Number)));
        assert!(classes.contains(&("@100", SyntaxClass::Variable)));
        assert!(
            classes.contains(&("\"a;b\"", SyntaxClass::Label)),
            "{classes:?}"
        );
        assert!(classes.contains(&("XX", SyntaxClass::Invalid)));
        assert!(classes.contains(&(";comment", SyntaxClass::Comment)));
        // A mnemonic starting with E after an axis is no exponent.
        let classes: Vec<(&str, SyntaxClass)> = highlight_line("1EE1")
            .into_iter()
            .map(|(r, c)| (&"1EE1"[r], c))
            .collect();
        assert!(
            classes.contains(&("EE", SyntaxClass::Keyword)),
            "{classes:?}"
        );
    }

    #[test]
    fn listings_compare_by_meaning() {
        assert_eq!(
            listed_macro("MC10,2MR500,WS0.1"),
            Some((10, "2MR500,WS0.1"))
        );
        assert_eq!(
            listed_macro("MC10 1MR1000,1WS0.100000"),
            Some((10, "1MR1000,1WS0.100000"))
        );
        let sent = parse_line("1MR1000,WS.1,AL@100", NumberBase::Decimal).expect("line");
        assert_eq!(same_commands(&sent, "1MR1000,1WS0.100000,AL@100"), Ok(()));
        assert!(same_commands(&sent, "1MR1000,1WS0.2,AL@100").is_err());
        assert!(same_commands(&sent, "1MR1000,2WS0.1,AL@100").is_err());
        assert!(same_commands(&sent, "1MR1000,WS.1").is_err());
    }

    #[test]
    fn a_macro_is_deleted_by_rm_and_the_others_defined_again() {
        let listing = listed_macros(&ReplyValue::Text(
            "MC1,1LM2,1LN3,MJ10\nMC10,2MR500,WS0.1\nMC11,AL5".into(),
        ));
        assert_eq!(listing.len(), 3);
        let deletion = MacroStore.delete(&listing, 10).expect("deletes");
        assert_eq!(deletion.lines, ["RM", "MD1,1LM2,1LN3,MJ10", "MD11,AL5"]);
        assert!(deletion.warning.contains("erases every macro"));
        assert_eq!(MacroStore.compare(&deletion.kept, &deletion.kept), Ok(()));
        assert!(MacroStore.compare(&deletion.kept, &listing).is_err());
        let e = MacroStore.delete(&listing, 7).unwrap_err().to_string();
        assert!(e.contains("no macro 7") && e.contains("1, 10, 11"), "{e}");
    }

    #[test]
    fn tasks_are_listed_by_id7_and_ended_by_et() {
        let answer = ReplyValue::Text("ACTIVE BACKGROUND TASKS: 2\nTask ID 1\nTask ID 3".into());
        assert_eq!(MacroStore.running(&answer), [1, 3]);
        assert_eq!(MacroStore.stop_line(3), "ET3");
        assert_eq!(MacroStore.running(&ReplyValue::None), Vec::<i64>::new());
    }

    #[test]
    fn registers_are_watched_with_tr() {
        assert_eq!((REGISTERS.read_line)(100), "TR100");
        assert_eq!((REGISTERS.of_line)("TR100"), Some(100));
        assert_eq!(register_at("AL@100,AA1,AR100", 2), Some(100));
        assert_eq!(register_at("AL@100,AA1,AR100", 14), Some(100));
        assert_eq!(register_at("1MR1000", 2), None);
    }
}
