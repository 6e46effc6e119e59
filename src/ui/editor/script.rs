//! The editor's A-Script mode (CMD-4CR §2.7, §5): which language a buffer
//! is in, its colours from the A-Script lexer's token classes, its check
//! by the A-Script checker (Table 5-43 errors and warnings, with lines),
//! and the run control of programs already in the controller, which is
//! all the manual documents over the wire: `SACTRL[n]` (T2-33),
//! `SASTAT[n]` (T2-34), `SPC[n]` and the variables `V[n]`.
//!
//! Downloading is not among it: §2.7.7 and §5.1.5 send the user to NPA's
//! Windows utility and its Software Manual, which this manual does not
//! contain. [`NO_DOWNLOAD`] says so wherever a download would be.

use std::path::Path;

use crate::protocol::cmd4cr::ascript::{self, Diagnostic, Program, Statement, TokenClass};
use crate::ui::theme::Role;

/// What the editor's text is written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Language {
    /// Trinamic TMCL assembler source (`.tmc`).
    Tmcl,
    /// Nippon Pulse CMD-4CR A-Script (`.asc`).
    AScript,
}

impl Language {
    /// The language a file's extension says (`.asc`, `.tmc`, `.tmcl`).
    pub fn of_file(path: &Path) -> Option<Language> {
        let extension = path.extension()?.to_str()?.to_ascii_lowercase();
        match extension.as_str() {
            "asc" => Some(Language::AScript),
            "tmc" | "tmcl" => Some(Language::Tmcl),
            _ => None,
        }
    }

    /// The language of a protocol family's controllers.
    pub fn of_family(family: &str) -> Language {
        if family == "cmd4cr" {
            Language::AScript
        } else {
            Language::Tmcl
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Language::Tmcl => "TMCL",
            Language::AScript => "A-Script",
        }
    }

    /// The name a buffer without a file is checked under.
    pub fn untitled(self) -> &'static str {
        match self {
            Language::Tmcl => "untitled.tmc",
            Language::AScript => "untitled.asc",
        }
    }

    pub fn other(self) -> Language {
        match self {
            Language::Tmcl => Language::AScript,
            Language::AScript => Language::Tmcl,
        }
    }
}

/// Said where a download would be: what the manual leaves out.
pub const NO_DOWNLOAD: &str =
    "the CMD-4CR manual documents no program download over the wire (§2.7.7, §5.1.5)";

/// An A-Script text as the checker sees it.
#[derive(Debug, Clone, Default)]
pub struct Checked {
    /// The compiled program, when there is no error.
    pub program: Option<Program>,
    /// Every error and warning, by line.
    pub diagnostics: Vec<Diagnostic>,
}

/// Check `text`.
pub fn check(text: &str) -> Checked {
    Checked {
        program: ascript::compile(text).ok(),
        diagnostics: ascript::check(text),
    }
}

/// What a checked text holds, for the bottom line: `checks: PRG 0, PRG 1;
/// SUB 31`.
pub fn summary(program: &Program) -> String {
    let programs: Vec<String> = program
        .program_numbers()
        .map(|n| format!("PRG {n}"))
        .collect();
    let subroutines: Vec<String> = (0u8..)
        .zip(&program.subroutines)
        .filter(|(_, s)| s.is_some())
        .map(|(n, _)| format!("SUB {n}"))
        .collect();
    let mut text = if programs.is_empty() {
        "checks: no PRG".to_string()
    } else {
        format!("checks: {}", programs.join(", "))
    };
    if !subroutines.is_empty() {
        text.push_str("; ");
        text.push_str(&subroutines.join(", "));
    }
    text
}

/// The colour of a token class (the TMCL editor's roles: blocks as its
/// labels, commands and keywords as its mnemonics).
pub fn role_of(class: TokenClass) -> Option<Role> {
    match class {
        TokenClass::Plain | TokenClass::Operator => None,
        TokenClass::Block => Some(Role::CodeLabel),
        TokenClass::Keyword | TokenClass::Command => Some(Role::CodeMnemonic),
        TokenClass::Variable => Some(Role::Accent),
        TokenClass::Number => Some(Role::CodeNumber),
        TokenClass::Comment => Some(Role::CodeComment),
        TokenClass::Invalid => Some(Role::CodeError),
    }
}

/// The PRG block source line `line` (1-based) is in; the file's first
/// PRG block when it is in none (a SUB, or outside any block).
pub fn program_at(program: &Program, line: usize) -> Option<u8> {
    let mut current = None;
    for s in &program.statements {
        if s.line > line {
            break;
        }
        match s.statement {
            Statement::Prg(n) => current = Some(n),
            Statement::End | Statement::Sub(_) => current = None,
            _ => {}
        }
    }
    current.or_else(|| {
        (0u8..)
            .zip(&program.programs)
            .filter_map(|(n, entry)| entry.map(|e| (e.line, n)))
            .min()
            .map(|(_, n)| n)
    })
}

/// The variable `V[n]` written at or nearest before `column` (0-based,
/// in bytes) of `line`, else the first on the line.
pub fn variable_at(line: &str, column: usize) -> Option<u8> {
    let variables: Vec<(usize, u8)> = ascript::tokens(line)
        .into_iter()
        .filter(|(_, class)| *class == TokenClass::Variable)
        .filter_map(|(range, _)| {
            let n = line.get(range.clone())?.get(1..)?.parse().ok()?;
            Some((range.start, n))
        })
        .collect();
    variables
        .iter()
        .rev()
        .find(|(start, _)| *start <= column)
        .or_else(|| variables.first())
        .map(|(_, n)| *n)
}

/// `SASTAT` values (T2-34).
pub fn status_name(code: i64) -> &'static str {
    match code {
        0 => "idle",
        1 => "running",
        2 => "paused",
        3 => "N/A",
        4 => "error",
        _ => "?",
    }
}

/// The lines that read program `n`'s state: `SASTAT[n]` and `SPC[n]`
/// (§2.7.9).
pub fn status_lines(n: u8) -> [String; 2] {
    [format!("SASTAT{n}"), format!("SPC{n}")]
}

/// `SACTRL[n]=code` (T2-33: 0 stop, 1 start, 2 pause, 3 continue).
pub fn control_line(n: u8, code: u8) -> String {
    format!("SACTRL{n}={code}")
}

/// The line that reads variable `n`.
pub fn variable_line(n: u8) -> String {
    format!("V{n}")
}

/// The variable a `V[n]` line reads.
pub fn variable_of_line(line: &str) -> Option<u8> {
    line.strip_prefix('V')?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extension_or_the_family_says_the_language() {
        assert_eq!(
            Language::of_file(Path::new("a/b.ASC")),
            Some(Language::AScript)
        );
        assert_eq!(Language::of_file(Path::new("b.tmc")), Some(Language::Tmcl));
        assert_eq!(Language::of_file(Path::new("b.txt")), None);
        assert_eq!(Language::of_file(Path::new("noext")), None);
        assert_eq!(Language::of_family("cmd4cr"), Language::AScript);
        assert_eq!(Language::of_family("tmcl"), Language::Tmcl);
    }

    #[test]
    fn the_program_under_the_cursor_is_its_prg_block_else_the_first() {
        let source = "PRG 2\n V1=1\nEND\nPRG 0\n V2=2\nEND\nSUB 1\n V3=3\nENDSUB\n";
        let program = ascript::compile(source).expect("compiles");
        assert_eq!(program_at(&program, 2), Some(2));
        assert_eq!(program_at(&program, 5), Some(0));
        // In SUB 1: the first PRG of the file.
        assert_eq!(program_at(&program, 8), Some(2));
        assert_eq!(summary(&program), "checks: PRG 0, PRG 2; SUB 1");
    }

    #[test]
    fn the_variable_at_the_cursor() {
        let line = "    V12=V3+V45";
        assert_eq!(variable_at(line, 0), Some(12));
        assert_eq!(variable_at(line, 9), Some(3));
        assert_eq!(variable_at(line, 14), Some(45));
        assert_eq!(variable_at("    X1000", 4), None);
        assert_eq!(variable_of_line("V7"), Some(7));
        assert_eq!(variable_of_line("SPC0"), None);
    }

    #[test]
    fn errors_and_warnings_come_with_their_lines() {
        let checked = check("PRG 0\n    V200=1\n    GOSUB 4\nEND\n");
        assert!(checked.program.is_none());
        let lines: Vec<(usize, bool)> = checked
            .diagnostics
            .iter()
            .map(|d| (d.line(), d.is_error()))
            .collect();
        assert_eq!(lines, [(2, true), (3, false)]);
        assert_eq!(role_of(TokenClass::Invalid), Some(Role::CodeError));
    }
}

/// Something wrong in the text, as the editor marks it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// 1-based.
    pub line: usize,
    /// 1-based, in characters.
    pub column: usize,
    pub text: String,
    /// An error (the text cannot run); else a warning.
    pub error: bool,
}

impl Problem {
    pub fn of(diagnostic: &Diagnostic) -> Problem {
        Problem {
            line: diagnostic.line(),
            column: diagnostic.column(),
            text: diagnostic.to_string(),
            error: diagnostic.is_error(),
        }
    }
}
