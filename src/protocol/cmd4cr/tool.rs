//! A-Script (CMD-4CR §2.7, §5) as the family's [`ProgramTool`]: the
//! checker's Table 5-43 errors and warnings with their lines, colours from
//! the lexer's token classes, the variables `V0`–`V99`, the run control of
//! programs already in the controller, which is all the manual documents
//! over the wire (`SACTRL[n]` T2-33, `SASTAT[n]` T2-34, `SPC[n]`), and the
//! run from the host ([`super::host`]).
//!
//! Downloading is not among it: §2.7.7 and §5.1.5 send the user to NPA's
//! Windows utility and its Software Manual, which this manual does not
//! contain. [`NO_DOWNLOAD`] says so wherever a download would be; a
//! simulator in this process takes the source instead
//! ([`DownloadWay::SimulatorOnly`]).

use std::ops::Range;
use std::sync::Arc;

use super::ascript::{self, Diagnostic, Program, Statement, TokenClass, VARIABLES};
use super::host::start_host_run;
use crate::protocol::program::{
    Checked, CheckedProgram, Control, ControlKey, CounterMap, DownloadOptions, DownloadWay,
    HostStart, Problem, ProgramControl, ProgramTool, SourceLoader, StateRead, StateSlot,
    SyntaxClass, TransferFailure, TransferPlan, VariableSet,
};

/// Said where a download would be: what the manual leaves out.
pub const NO_DOWNLOAD: &str =
    "the CMD-4CR manual documents no program download over the wire (§2.7.7, §5.1.5)";

/// A-Script programs (the family's
/// [`crate::protocol::console::FamilyConsole::program`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct AScriptTool;

/// The line that reads variable `n`.
pub fn variable_line(n: u8) -> String {
    format!("V{n}")
}

/// The variable a `V[n]` line reads.
pub fn variable_of_line(line: &str) -> Option<u8> {
    line.strip_prefix('V')?.parse().ok()
}

/// A-Script's variables V0–V99 as a console watches them.
pub static VARIABLE_SET: VariableSet = VariableSet {
    key: "ascript_variables",
    heading: "variables",
    mark: "V",
    prompt: "watch variable V (0..99; a watched one stops): ",
    read_line: variable_line,
    of_line: variable_of_line,
    parse: |text| match text.trim_start_matches(['V', 'v']).parse::<u8>() {
        Ok(n) if usize::from(n) < VARIABLES => Ok(n),
        _ => Err(crate::protocol::program::NoSuchVariable {
            set: "A-Script variables are",
            numbers: "V0..V99",
            typed: text.to_string(),
        }),
    },
    name: |n| format!("V{n}"),
};

/// `SACTRL[n]=code` (T2-33: 0 stop, 1 start, 2 pause, 3 continue).
pub fn control_line(n: u8, code: u8) -> String {
    format!("SACTRL{n}={code}")
}

/// The run control of the programs in the controller: `SACTRL[n]`, read
/// back with `SASTAT[n]` and `SPC[n]` (§2.7.8–§2.7.9).
#[derive(Debug, Clone, Copy, Default)]
pub struct AScriptControl;

impl ProgramControl for AScriptControl {
    fn control(&self, key: ControlKey, target: u8, mode: Option<i64>) -> Control {
        let (code, verb) = match key {
            ControlKey::Run => (1, "start"),
            ControlKey::Stop | ControlKey::Reset => (0, "stop"),
            // §5.1 documents no single step: the step key pauses and
            // continues instead (T2-33 codes 2 and 3).
            ControlKey::Step if mode == Some(2) => (3, "continue"),
            ControlKey::Step => (2, "pause"),
        };
        Control {
            line: control_line(target, code),
            watch: code == 1 || code == 3,
            verb: Some(verb),
        }
    }

    fn state_reads(&self, target: u8) -> Vec<StateRead> {
        vec![
            StateRead {
                line: format!("SASTAT{target}"),
                slot: StateSlot::Mode,
            },
            StateRead {
                line: format!("SPC{target}"),
                slot: StateSlot::Counter,
            },
        ]
    }

    /// `SASTAT` values (T2-34).
    fn mode_name(&self, mode: i64) -> &'static str {
        match mode {
            0 => "idle",
            1 => "running",
            2 => "paused",
            3 => "N/A",
            4 => "error",
            _ => "?",
        }
    }

    /// Running or paused: read again.
    fn keeps_running(&self, mode: i64) -> bool {
        matches!(mode, 1 | 2)
    }

    fn counter_name(&self) -> &'static str {
        "SPC"
    }

    fn program_name(&self, target: u8) -> Option<String> {
        Some(format!("PRG {target}"))
    }

    /// `SPC` counts the controller's compiled lines, which map to no
    /// source line the manual gives (digest §2.11): only a text this
    /// console loaded into the simulator (the same compiler) maps.
    fn counter_map(&self) -> CounterMap {
        CounterMap::WhenLoadedHere
    }

    fn marks_where_stopped(&self) -> bool {
        false
    }
}

fn class_of(class: TokenClass) -> SyntaxClass {
    match class {
        TokenClass::Plain | TokenClass::Operator => SyntaxClass::Plain,
        TokenClass::Block => SyntaxClass::Label,
        TokenClass::Keyword | TokenClass::Command => SyntaxClass::Keyword,
        TokenClass::Variable => SyntaxClass::Variable,
        TokenClass::Number => SyntaxClass::Number,
        TokenClass::Comment => SyntaxClass::Comment,
        TokenClass::Invalid => SyntaxClass::Invalid,
    }
}

fn problem_of(diagnostic: &Diagnostic) -> Problem {
    Problem {
        line: diagnostic.line(),
        column: diagnostic.column(),
        text: diagnostic.to_string(),
        message: match diagnostic {
            Diagnostic::Error(e) => format!("{}: {}", e.code, e.detail),
            Diagnostic::Warning(w) => format!("warning: {}", w.message),
        },
        error: diagnostic.is_error(),
        in_source: true,
    }
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

impl ProgramTool for AScriptTool {
    fn name(&self) -> &'static str {
        "A-Script"
    }

    fn controller(&self) -> &'static str {
        "CMD-4CR"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &["asc"]
    }

    fn unit(&self) -> &'static str {
        "statement"
    }

    fn check(&self, _name: &str, source: &str, _files: &dyn SourceLoader) -> Checked {
        Checked {
            problems: ascript::check(source).iter().map(problem_of).collect(),
            program: ascript::compile(source)
                .ok()
                .map(|p| Arc::new(AScriptProgram(p)) as Arc<dyn CheckedProgram>),
        }
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
            .map(|line| {
                ascript::tokens(line)
                    .into_iter()
                    .map(|(range, class)| (range, class_of(class)))
                    .collect()
            })
            .collect()
    }

    fn variable_on_line(&self, text: &str, column: usize) -> Option<u8> {
        variable_at(text, column)
    }

    fn variables(&self) -> Option<&'static VariableSet> {
        Some(&VARIABLE_SET)
    }

    fn control(&self) -> Option<&'static dyn ProgramControl> {
        Some(&AScriptControl)
    }

    fn download_way(&self) -> DownloadWay {
        DownloadWay::SimulatorOnly {
            why: NO_DOWNLOAD,
            real: "a real CMD-4CR takes no download",
        }
    }

    fn runs_from_host(&self) -> bool {
        true
    }

    fn host_command(&self) -> Option<&'static str> {
        Some("run-ascript")
    }

    fn host_run(
        &self,
        name: &str,
        source: &str,
        start: Option<&[u8]>,
    ) -> Option<Result<HostStart, Vec<String>>> {
        Some(start_host_run(name, source, start))
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

/// A compiled A-Script text.
#[derive(Debug, Clone)]
pub struct AScriptProgram(pub Program);

impl CheckedProgram for AScriptProgram {
    fn state(&self) -> String {
        format!("A-Script {}", summary(&self.0))
    }

    fn built(&self) -> String {
        summary(&self.0)
    }

    fn size(&self) -> usize {
        self.0.statements.len()
    }

    fn line_of(&self, unit: usize) -> Option<usize> {
        self.0.step(unit).map(|step| step.line)
    }

    fn line_of_counter(&self, counter: i64) -> Option<usize> {
        self.line_of(usize::try_from(counter).ok()?)
    }

    fn programs(&self) -> Vec<u8> {
        self.0.program_numbers().collect()
    }

    fn program_at(&self, line: usize) -> Option<u8> {
        program_at(&self.0, line)
    }

    fn variable_at(&self, _line: usize, text: &str, column: usize) -> Option<u8> {
        variable_at(text, column)
    }

    fn download(
        &self,
        _address: u8,
        _options: DownloadOptions,
    ) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Err(TransferFailure::refused(NO_DOWNLOAD))
    }

    fn verify(&self, _address: u8) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Err(TransferFailure::refused(format!(
            "{NO_DOWNLOAD}, nor a read-back"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::program::NoIncludes;

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
        assert_eq!((VARIABLE_SET.parse)("v12"), Ok(12));
        assert!((VARIABLE_SET.parse)("V100").is_err());
    }

    #[test]
    fn errors_and_warnings_come_with_their_lines() {
        let checked = AScriptTool.check(
            "p.asc",
            "PRG 0\n    V200=1\n    GOSUB 4\nEND\n",
            &NoIncludes,
        );
        assert!(checked.program.is_none());
        let lines: Vec<(usize, bool)> =
            checked.problems.iter().map(|d| (d.line, d.error)).collect();
        assert_eq!(lines, [(2, true), (3, false)]);
        assert_eq!(class_of(TokenClass::Invalid), SyntaxClass::Invalid);
    }

    #[test]
    fn the_step_key_pauses_and_continues() {
        let pause = AScriptControl.control(ControlKey::Step, 1, Some(1));
        assert_eq!((pause.line.as_str(), pause.watch), ("SACTRL1=2", false));
        let resume = AScriptControl.control(ControlKey::Step, 1, Some(2));
        assert_eq!((resume.line.as_str(), resume.watch), ("SACTRL1=3", true));
        assert_eq!(
            AScriptControl.control(ControlKey::Reset, 0, None).line,
            "SACTRL0=0"
        );
    }
}
