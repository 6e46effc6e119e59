//! TMCL programs as the family's [`ProgramTool`]: the assembler's check
//! and colours, the user variables a console watches (global parameter
//! bank 2, §5.3), the program's registers and run control (§3.6.53, §5.1),
//! and the transfer plans of [`super::plan`].

use std::ops::Range;
use std::sync::Arc;

use super::asm::highlight::{Names, Token, highlight};
use super::asm::{
    AsmError, Program, ProgramWord, assemble, disassemble, format_image, listing, parse_image,
};
use super::command::opcode;
use super::plan::{DownloadPlan, UploadPlan, VerifyPlan};
use crate::protocol::program::{
    Checked, CheckedProgram, Control, ControlKey, DownloadOptions, NoIncludes, Problem,
    ProgramControl, ProgramTool, SourceLoader, StateRead, StateSlot, SyntaxClass, TransferFailure,
    TransferPlan, UploadExtent, VariableSet, Wording,
};

/// The bank of the user variables (§5.3).
const USER_BANK: u8 = 2;

/// The name a line is assembled under when it stands alone.
const UNTITLED: &str = "untitled.tmc";

/// TMCL programs (the family's [`crate::protocol::console::FamilyConsole::program`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct TmclTool;

/// The console line reading user variable `n` (GGP, §3.6.10).
pub fn variable_line(n: u8) -> String {
    format!("GGP {n}, {USER_BANK}")
}

/// The variable a line made by [`variable_line`] reads.
pub fn variable_of_line(line: &str) -> Option<u8> {
    line.strip_prefix("GGP ")?.strip_suffix(", 2")?.parse().ok()
}

/// The user variable an instruction names, if it is one of the global
/// parameter commands on bank 2: SGP, GGP, STGP, RSGP (§3.6.9–3.6.12) and
/// AGP (§3.6.30); their type byte is the variable's number.
pub fn variable_of_word(word: &ProgramWord) -> Option<u8> {
    let global = matches!(
        word.opcode,
        opcode::SGP | opcode::GGP | opcode::STGP | opcode::RSGP | opcode::AGP
    );
    (global && word.motor_bank == USER_BANK).then_some(word.kind)
}

/// The user variables (§5.3) as a console watches them.
pub static USER_VARIABLES: VariableSet = VariableSet {
    key: "user_variables",
    heading: "user variables",
    mark: "#",
    prompt: "watch user variable (0..255; a watched one stops): ",
    read_line: variable_line,
    of_line: variable_of_line,
    parse: |text| {
        text.parse::<u8>()
            .map_err(|_| crate::protocol::program::NoSuchVariable {
                set: "user variables are numbered",
                numbers: "0..255",
                typed: text.to_string(),
            })
    },
    name: |n| format!("user variable #{n}"),
};

/// The program's run control and registers: the application status and
/// the program counter as global parameters GP128 and GP130 (§5.1 Table
/// 18), the accumulator and X with command 135 types 2 and 3 (§3.6.53).
/// Command 135 types 0 and 1 would give the mode and the PC too, but
/// packed with a wait flag in a layout Table 14 does not give.
#[derive(Debug, Clone, Copy, Default)]
pub struct TmclControl;

impl ProgramControl for TmclControl {
    fn control(&self, key: ControlKey, _target: u8, _mode: Option<i64>) -> Control {
        let (line, watch) = match key {
            ControlKey::Run => ("RUNAPP", true),
            ControlKey::Stop => ("STOPAPP", false),
            ControlKey::Step => ("STEPAPP", false),
            ControlKey::Reset => ("RESETAPP", false),
        };
        Control {
            line: line.to_string(),
            watch,
            verb: None,
        }
    }

    fn state_reads(&self, _target: u8) -> Vec<StateRead> {
        [
            ("GGP 128, 0", StateSlot::Mode),
            ("GGP 130, 0", StateSlot::Counter),
            ("APPSTATUS ACCU", StateSlot::Register("ACC")),
            ("APPSTATUS X", StateSlot::Register("X")),
        ]
        .into_iter()
        .map(|(line, slot)| StateRead {
            line: line.to_string(),
            slot,
        })
        .collect()
    }

    /// GP128: 0 stopped, 1 running, 2 stepping, 3 reset (§5.1).
    fn mode_name(&self, mode: i64) -> &'static str {
        match mode {
            0 => "stopped",
            1 => "running",
            2 => "stepping",
            3 => "reset",
            _ => "?",
        }
    }

    fn keeps_running(&self, mode: i64) -> bool {
        mode == 1
    }

    fn counter_name(&self) -> &'static str {
        "PC"
    }
}

fn class_of(token: Token) -> SyntaxClass {
    match token {
        Token::Plain => SyntaxClass::Plain,
        Token::Mnemonic => SyntaxClass::Keyword,
        Token::Label => SyntaxClass::Label,
        Token::Number => SyntaxClass::Number,
        Token::Comment => SyntaxClass::Comment,
    }
}

fn problem_of(error: &AsmError, name: &str) -> Problem {
    Problem {
        line: error.line,
        column: error.column,
        text: error.to_string(),
        message: error.message(),
        error: true,
        in_source: error.file == name,
    }
}

impl ProgramTool for TmclTool {
    fn name(&self) -> &'static str {
        "TMCL"
    }

    fn controller(&self) -> &'static str {
        "TMCL module"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &["tmc", "tmcl"]
    }

    fn wording(&self) -> Wording {
        Wording {
            passes: "assembles",
            pass: "assemble",
        }
    }

    fn check(&self, name: &str, source: &str, files: &dyn SourceLoader) -> Checked {
        match assemble(name, source, files) {
            Ok(program) => Checked {
                problems: Vec::new(),
                program: Some(Arc::new(TmclProgram(program))),
            },
            Err(errors) => Checked {
                problems: errors.iter().map(|e| problem_of(e, name)).collect(),
                program: None,
            },
        }
    }

    fn highlight(
        &self,
        lines: &[String],
        shown: Range<usize>,
    ) -> Vec<Vec<(Range<usize>, SyntaxClass)>> {
        let names = Names::declared(lines.iter().map(String::as_str));
        lines
            .get(shown)
            .unwrap_or_default()
            .iter()
            .map(|line| {
                highlight(line, &names)
                    .into_iter()
                    .map(|(range, token)| (range, class_of(token)))
                    .collect()
            })
            .collect()
    }

    fn variable_on_line(&self, text: &str, _column: usize) -> Option<u8> {
        let alone = assemble(UNTITLED, text, &NoIncludes).ok()?;
        alone.words.iter().find_map(variable_of_word)
    }

    fn variables(&self) -> Option<&'static VariableSet> {
        Some(&USER_VARIABLES)
    }

    fn control(&self) -> Option<&'static dyn ProgramControl> {
        Some(&TmclControl)
    }

    fn upload(
        &self,
        address: u8,
        extent: UploadExtent,
    ) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Ok(Box::new(UploadPlan::new(address, extent)))
    }

    fn load_image(
        &self,
        name: &str,
        text: &str,
    ) -> Option<Result<Arc<dyn CheckedProgram>, Vec<String>>> {
        Some(
            parse_image(text)
                .map(|words| {
                    Arc::new(TmclProgram(Program {
                        source_name: name.to_string(),
                        words,
                        ..Program::default()
                    })) as Arc<dyn CheckedProgram>
                })
                .map_err(|errors| {
                    errors
                        .iter()
                        .map(|e| format!("{name}:{}: {}", e.line, e.kind))
                        .collect()
                }),
        )
    }

    fn disassemble(&self, name: &str, image: &str) -> Option<Result<String, Vec<String>>> {
        Some(
            parse_image(image)
                .map(|words| disassemble(&words))
                .map_err(|errors| {
                    errors
                        .iter()
                        .map(|e| format!("{name}:{}: {}", e.line, e.kind))
                        .collect()
                }),
        )
    }
}

/// An assembled TMCL program.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TmclProgram(pub Program);

impl TmclProgram {
    /// The source line of the word at `address`, in the main source.
    fn line_at(&self, address: usize) -> Option<usize> {
        let program = &self.0;
        program
            .lines
            .iter()
            .find(|l| usize::from(l.address) == address && l.file == program.source_name)
            .map(|l| l.line)
    }
}

impl CheckedProgram for TmclProgram {
    fn state(&self) -> String {
        format!("assembles: {} words", self.0.words.len())
    }

    fn built(&self) -> String {
        format!(
            "assembled: {} words, {} labels",
            self.0.words.len(),
            self.0.symbols.len()
        )
    }

    fn size(&self) -> usize {
        self.0.words.len()
    }

    fn line_of(&self, unit: usize) -> Option<usize> {
        self.line_at(unit)
    }

    fn line_of_counter(&self, counter: i64) -> Option<usize> {
        self.line_at(usize::try_from(counter).ok()?)
    }

    /// The variable the words assembled from line `line` name.
    fn variable_at(&self, line: usize, _text: &str, _column: usize) -> Option<u8> {
        let program = &self.0;
        program
            .lines
            .iter()
            .filter(|l| l.file == program.source_name && l.line == line)
            .filter_map(|l| program.words.get(usize::from(l.address)))
            .find_map(variable_of_word)
    }

    fn download(
        &self,
        address: u8,
        options: DownloadOptions,
    ) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Ok(Box::new(DownloadPlan::new(
            &self.0.words,
            address,
            options,
        )?))
    }

    fn verify(&self, address: u8) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Ok(Box::new(VerifyPlan::new(&self.0.words, address)))
    }

    fn image(&self) -> Option<String> {
        Some(format_image(&self.0.words))
    }

    fn listing(&self) -> Option<String> {
        Some(listing(&self.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn word(line: &str) -> ProgramWord {
        let program = assemble("t.tmc", line, &NoIncludes).expect("assembles");
        program.words[0]
    }

    #[test]
    fn global_parameter_commands_on_bank_2_name_a_user_variable() {
        for line in [
            "GGP 5, 2",
            "SGP 5, 2, -1",
            "STGP 5, 2",
            "RSGP 5, 2",
            "AGP 5, 2",
        ] {
            assert_eq!(variable_of_word(&word(line)), Some(5), "{line}");
        }
        // Bank 0 is module configuration; other commands name no variable.
        assert_eq!(variable_of_word(&word("GGP 65, 0")), None);
        assert_eq!(variable_of_word(&word("GAP 5, 0")), None);
        assert_eq!(variable_of_word(&word("MVP ABS, 0, 2")), None);
    }

    #[test]
    fn the_read_line_names_its_variable() {
        assert_eq!(variable_line(42), "GGP 42, 2");
        assert_eq!(variable_of_line(&variable_line(255)), Some(255));
        assert_eq!(variable_of_line("GGP 5, 0"), None);
        assert_eq!(variable_of_line("APPSTATUS X"), None);
        assert_eq!(variable_of_line("GGP 300, 2"), None);
        assert!((USER_VARIABLES.parse)("300").is_err());
    }

    #[test]
    fn errors_of_included_files_are_marked_as_not_in_the_source() {
        let mut files = std::collections::BTreeMap::new();
        files.insert("inc.tmc".to_string(), "JA Nowhere\n".to_string());
        let checked = TmclTool.check("main.tmc", "#include inc.tmc\nSTOP\nMVP\n", &files);
        assert!(checked.program.is_none());
        let places: Vec<(usize, bool)> = checked
            .problems
            .iter()
            .map(|p| (p.line, p.in_source))
            .collect();
        assert!(places.contains(&(1, false)), "{places:?}");
        assert!(places.contains(&(3, true)), "{places:?}");
    }

    #[test]
    fn labels_declared_later_colour_earlier_uses() {
        let lines = vec!["JA Loop".to_string(), "Loop: STOP".to_string()];
        let classes = TmclTool.highlight(&lines, 0..1);
        assert_eq!(classes.len(), 1);
        assert!(
            classes[0]
                .iter()
                .any(|(r, c)| &lines[0][r.clone()] == "Loop" && *c == SyntaxClass::Label),
            "{classes:?}"
        );
    }
}
