//! A whole source: blocks matched (PRG…END, SUB…ENDSUB, IF…ENDIF,
//! WHILE…ENDWHILE), every error of every line collected, and the program
//! compiled into steps with resolved jump targets, which an interpreter
//! runs one at a time.
//!
//! Why steps and not the statements themselves: an ELSEIF means two things
//! (end of the branch before it, test of its own condition), and §2.7.7
//! says the controller compiles each source line into 1–4 "assembly"
//! lines, which is what its SPC counts (§2.7.9). Our steps are that
//! compiled form: IF, ELSE, WHILE, ENDWHILE and every action one step,
//! ELSEIF two, PRG, SUB and ENDIF none. An executor can report the step
//! index as its SPC.

use super::ast::{Action, Comparison, Condition, Operand, Statement};
use super::errors::{CompileError, Diagnostic, ErrorCode, Warning};
use super::lexer::Keyword;
use super::parser::{LineError, parse_line};

/// Program numbers: PRG 0–3 (§2.7.8: four programs at once).
pub const PROGRAMS: usize = 4;
/// Subroutine numbers: SUB 0–31 (§2.7.4).
pub const SUBROUTINES: usize = 32;
/// The subroutine run when an error occurs (§2.7.5).
pub const ERROR_HANDLER: u8 = 31;

/// A statement and the line it is on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SourceStatement {
    /// 1-based.
    pub line: usize,
    pub statement: Statement,
}

/// One step of a compiled program.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Step {
    /// The source line it comes from (1-based).
    pub line: usize,
    pub op: Op,
}

/// What a step does. Jump targets are step indexes in [`Program::steps`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Op {
    /// Carry out the action, go on with the next step.
    Action(Action),
    /// IF, ELSEIF, WHILE: when the condition does not hold, continue at
    /// `to`; when it does, with the next step.
    JumpUnless { condition: Condition, to: usize },
    /// The end of a taken IF branch (at its ELSEIF or ELSE), ENDWHILE back
    /// to its WHILE.
    Jump { to: usize },
    /// GOSUB: run subroutine `sub`, then the next step. The subroutine may
    /// be missing ([`Program::subroutine`] is None; the controller reports
    /// an error, §2.7.4); a warning says so before any run.
    Call { sub: u8 },
    /// ENDSUB: back to the step after the GOSUB.
    Return,
    /// END: the program has finished.
    End,
}

/// Where a program or subroutine starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Entry {
    /// The PRG or SUB line (1-based).
    pub line: usize,
    /// Its first step.
    pub start: usize,
}

/// A source that compiled.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Program {
    /// Every statement, in source order.
    pub statements: Vec<SourceStatement>,
    /// The compiled program: every block's steps, in source order.
    pub steps: Vec<Step>,
    /// PRG 0–3, where defined.
    pub programs: [Option<Entry>; PROGRAMS],
    /// SUB 0–31, where defined.
    pub subroutines: [Option<Entry>; SUBROUTINES],
    pub warnings: Vec<Warning>,
}

impl Program {
    /// Where PRG `n` starts.
    pub fn program(&self, n: u8) -> Option<Entry> {
        self.programs.get(usize::from(n)).copied().flatten()
    }

    /// Where SUB `n` starts.
    pub fn subroutine(&self, n: u8) -> Option<Entry> {
        self.subroutines.get(usize::from(n)).copied().flatten()
    }

    /// SUB 31, run when an error occurs (§2.7.5); without it a program
    /// stops in the error state.
    pub fn error_handler(&self) -> Option<Entry> {
        self.subroutine(ERROR_HANDLER)
    }

    pub fn step(&self, index: usize) -> Option<&Step> {
        self.steps.get(index)
    }

    /// The program numbers defined, in order.
    pub fn program_numbers(&self) -> impl Iterator<Item = u8> + '_ {
        (0u8..)
            .zip(&self.programs)
            .filter_map(|(n, e)| e.map(|_| n))
    }
}

/// Compile `source`: the program, or every error in it (sorted by line),
/// each with Table 5-43's code.
pub fn compile(source: &str) -> Result<Program, Vec<CompileError>> {
    let build = Build::run(source);
    if build.errors.is_empty() {
        Ok(build.program)
    } else {
        Err(build.errors)
    }
}

/// Every error and warning in `source`, by line: what an editor marks.
pub fn check(source: &str) -> Vec<Diagnostic> {
    let build = Build::run(source);
    let mut all: Vec<Diagnostic> = build
        .errors
        .into_iter()
        .map(Diagnostic::Error)
        .chain(build.program.warnings.into_iter().map(Diagnostic::Warning))
        .collect();
    all.sort_by_key(|d| (d.line(), d.column()));
    all
}

/// The block being read.
#[derive(Debug, Clone, Copy)]
struct Block {
    /// PRG when true, SUB when false.
    program: bool,
    /// None when the header's number was wrong.
    number: Option<u8>,
    line: usize,
    column: usize,
}

impl Block {
    fn header(&self) -> String {
        let word = if self.program { "PRG" } else { "SUB" };
        match self.number {
            Some(n) => format!("{word} {n}"),
            None => word.to_string(),
        }
    }
}

/// An IF or WHILE waiting for its closer.
#[derive(Debug, Clone)]
struct Open {
    kind: OpenKind,
    line: usize,
    column: usize,
    /// False when the line itself had an error: that error is reported,
    /// not a missing closer as well.
    parsed: bool,
}

#[derive(Debug, Clone)]
enum OpenKind {
    If {
        /// The JumpUnless to send to the next branch.
        pending: Option<usize>,
        /// The Jumps at the ends of branches, to send past ENDIF.
        exits: Vec<usize>,
        /// The line of its ELSE.
        else_line: Option<usize>,
    },
    While {
        /// Its JumpUnless.
        start: usize,
    },
}

impl Open {
    fn is_if(&self) -> bool {
        matches!(self.kind, OpenKind::If { .. })
    }

    fn missing(&self, closer_place: &str) -> CompileError {
        let (code, opener, closer) = match self.kind {
            OpenKind::If { .. } => (ErrorCode::MissingEndif, "IF", "ENDIF"),
            OpenKind::While { .. } => (ErrorCode::MissingEndwhile, "WHILE", "ENDWHILE"),
        };
        CompileError {
            line: self.line,
            column: self.column,
            code,
            detail: format!(
                "the {opener} on line {} has no {closer} before {closer_place}",
                self.line
            ),
        }
    }
}

/// A condition standing in for one that did not parse (the program is
/// not returned then; the structure still has to be followed).
const NO_CONDITION: Condition = Condition {
    left: Operand::Number(0),
    op: Comparison::Equal,
    right: Operand::Number(0),
};

struct Build {
    program: Program,
    errors: Vec<CompileError>,
    block: Option<Block>,
    open: Vec<Open>,
    /// GOSUBs, to warn about missing subroutines at the end.
    calls: Vec<(usize, usize, u8)>,
}

impl Build {
    fn run(source: &str) -> Build {
        let mut build = Build {
            program: Program::default(),
            errors: Vec::new(),
            block: None,
            open: Vec::new(),
            calls: Vec::new(),
        };
        let mut last_line = 0;
        for (index, text) in source.lines().enumerate() {
            let line = index + 1;
            last_line = line;
            let Some(parsed) = parse_line(text) else {
                continue;
            };
            let column = parsed.column;
            match parsed.statement {
                Ok(statement) => {
                    build.structure(line, column, &statement, true);
                    build
                        .program
                        .statements
                        .push(SourceStatement { line, statement });
                }
                Err(error) => {
                    build.error(line, error);
                    if let Some(keyword) = parsed.keyword {
                        build.keyword_structure(line, column, keyword);
                    }
                }
            }
        }
        build.close_block(&format!("the end of the source (line {last_line})"));
        build.warn_missing_subroutines();
        build.errors.sort_by_key(|e| (e.line, e.column));
        build
    }

    fn error(&mut self, line: usize, error: LineError) {
        self.errors.push(CompileError {
            line,
            column: error.column,
            code: error.code,
            detail: error.detail,
        });
    }

    fn push_error(&mut self, line: usize, column: usize, code: ErrorCode, detail: String) {
        self.errors.push(CompileError {
            line,
            column,
            code,
            detail,
        });
    }

    fn emit(&mut self, line: usize, op: Op) -> usize {
        self.program.steps.push(Step { line, op });
        self.program.steps.len() - 1
    }

    /// Point the jump at step `at` to `to`.
    fn patch(&mut self, at: usize, target: usize) {
        if let Some(Step {
            op: Op::JumpUnless { to, .. } | Op::Jump { to },
            ..
        }) = self.program.steps.get_mut(at)
        {
            *to = target;
        }
    }

    /// The structure a line with a parse error still has (so that
    /// `IF V1==1` still needs its ENDIF).
    fn keyword_structure(&mut self, line: usize, column: usize, keyword: Keyword) {
        let statement = match keyword {
            Keyword::Prg | Keyword::Sub => {
                self.open_block(line, column, keyword == Keyword::Prg, None);
                return;
            }
            Keyword::If => Statement::If(NO_CONDITION),
            Keyword::ElseIf => Statement::ElseIf(NO_CONDITION),
            Keyword::While => Statement::While(NO_CONDITION),
            // Closers and GOSUB take nothing after them: their errors
            // leave the structure as it was.
            _ => return,
        };
        self.structure(line, column, &statement, false);
    }

    /// Follow the block structure of `statement`, compiling its steps.
    /// `parsed` is false for the stand-in of a line that had an error.
    fn structure(&mut self, line: usize, column: usize, statement: &Statement, parsed: bool) {
        match statement {
            Statement::Prg(n) => self.open_block(line, column, true, Some(*n)),
            Statement::Sub(n) => self.open_block(line, column, false, Some(*n)),
            Statement::End => self.end_block(line, column, true),
            Statement::EndSub => self.end_block(line, column, false),
            _ if self.block.is_none() => self.push_error(
                line,
                column,
                ErrorCode::Error,
                format!(
                    "`{statement}` is outside any PRG … END or SUB … ENDSUB block (§2.7.1: code is written between PRG and END)"
                ),
            ),
            Statement::If(condition) => {
                let at = self.emit(
                    line,
                    Op::JumpUnless {
                        condition: *condition,
                        to: usize::MAX,
                    },
                );
                self.open.push(Open {
                    kind: OpenKind::If {
                        pending: Some(at),
                        exits: Vec::new(),
                        else_line: None,
                    },
                    line,
                    column,
                    parsed,
                });
            }
            Statement::ElseIf(condition) => self.branch(line, column, Some(*condition)),
            Statement::Else => self.branch(line, column, None),
            Statement::EndIf => self.end_if(line, column),
            Statement::While(condition) => {
                let start = self.emit(
                    line,
                    Op::JumpUnless {
                        condition: *condition,
                        to: usize::MAX,
                    },
                );
                self.open.push(Open {
                    kind: OpenKind::While { start },
                    line,
                    column,
                    parsed,
                });
            }
            Statement::EndWhile => self.end_while(line, column),
            Statement::Gosub(sub) => {
                self.calls.push((line, column, *sub));
                self.emit(line, Op::Call { sub: *sub });
            }
            Statement::Action(action) => {
                self.emit(line, Op::Action(action.clone()));
            }
        }
    }

    fn open_block(&mut self, line: usize, column: usize, program: bool, number: Option<u8>) {
        let header = if program { "PRG" } else { "SUB" };
        self.close_block(&format!("{header} on line {line}"));
        if let Some(n) = number {
            let start = self.program.steps.len();
            let entries: &mut [Option<Entry>] = if program {
                &mut self.program.programs
            } else {
                &mut self.program.subroutines
            };
            match entries.get_mut(usize::from(n)) {
                Some(Some(first)) => {
                    let first = first.line;
                    self.push_error(
                        line,
                        column,
                        ErrorCode::Error,
                        format!("{header} {n} is already defined on line {first}"),
                    );
                }
                Some(slot) => *slot = Some(Entry { line, start }),
                None => {}
            }
        }
        self.block = Some(Block {
            program,
            number,
            line,
            column,
        });
    }

    /// End the block being read at a line that is not its closer: every
    /// IF and WHILE in it, and the block itself, are missing their closer.
    fn close_block(&mut self, place: &str) {
        self.close_open(0, place);
        if let Some(block) = self.block.take() {
            let (code, closer) = if block.program {
                (ErrorCode::MissingEnd, "END")
            } else {
                (ErrorCode::ErrorEndsub, "ENDSUB")
            };
            // A header whose number was wrong has its error already.
            if block.number.is_some() {
                self.push_error(
                    block.line,
                    block.column,
                    code,
                    format!(
                        "{} on line {} has no {closer} before {place}",
                        block.header(),
                        block.line
                    ),
                );
            }
        }
    }

    /// Report the IFs and WHILEs above stack depth `depth` as missing
    /// their closer before `place`, and drop them.
    fn close_open(&mut self, depth: usize, place: &str) {
        let unclosed = self.open.split_off(depth.min(self.open.len()));
        for open in unclosed.iter().rev().filter(|o| o.parsed) {
            self.errors.push(open.missing(place));
        }
    }

    fn end_block(&mut self, line: usize, column: usize, program: bool) {
        let (word, other) = if program {
            ("END", "ENDSUB")
        } else {
            ("ENDSUB", "END")
        };
        match self.block {
            None => self.push_error(
                line,
                column,
                ErrorCode::Error,
                format!("{word} without {}", if program { "PRG" } else { "SUB" }),
            ),
            Some(block) if block.program != program => self.push_error(
                line,
                column,
                ErrorCode::Error,
                format!(
                    "{word} inside {} (line {}): it ends with {other}",
                    block.header(),
                    block.line
                ),
            ),
            Some(_) => {
                self.close_open(0, &format!("{word} on line {line}"));
                self.emit(line, if program { Op::End } else { Op::Return });
                self.block = None;
            }
        }
    }

    /// The innermost open IF, closing any WHILE opened inside it (those
    /// are missing their ENDWHILE before `place`).
    fn innermost_if(&mut self, place: &str) -> Option<usize> {
        let at = self.open.iter().rposition(Open::is_if)?;
        self.close_open(at + 1, place);
        Some(at)
    }

    /// ELSEIF (with its condition) or ELSE.
    fn branch(&mut self, line: usize, column: usize, condition: Option<Condition>) {
        let word = if condition.is_some() {
            "ELSEIF"
        } else {
            "ELSE"
        };
        let Some(at) = self.innermost_if(&format!("{word} on line {line}")) else {
            self.push_error(line, column, ErrorCode::Error, format!("{word} without IF"));
            return;
        };
        let else_before = match self.open.get(at) {
            Some(Open {
                kind: OpenKind::If { else_line, .. },
                ..
            }) => *else_line,
            _ => None,
        };
        if let Some(else_line) = else_before {
            self.push_error(
                line,
                column,
                ErrorCode::Error,
                format!("{word} after the ELSE on line {else_line}: ELSE is the last branch"),
            );
            return;
        }
        let exit = self.emit(line, Op::Jump { to: usize::MAX });
        let next_branch = exit + 1;
        let pending = condition.map(|condition| {
            self.emit(
                line,
                Op::JumpUnless {
                    condition,
                    to: usize::MAX,
                },
            )
        });
        let mut patch_from = None;
        if let Some(Open {
            kind:
                OpenKind::If {
                    pending: previous,
                    exits,
                    else_line,
                },
            ..
        }) = self.open.get_mut(at)
        {
            patch_from = previous.take();
            *previous = pending;
            exits.push(exit);
            if condition.is_none() {
                *else_line = Some(line);
            }
        }
        if let Some(from) = patch_from {
            self.patch(from, next_branch);
        }
    }

    fn end_if(&mut self, line: usize, column: usize) {
        if self
            .innermost_if(&format!("ENDIF on line {line}"))
            .is_none()
        {
            self.push_error(line, column, ErrorCode::Error, "ENDIF without IF".into());
            return;
        }
        let end = self.program.steps.len();
        if let Some(Open {
            kind: OpenKind::If { pending, exits, .. },
            ..
        }) = self.open.pop()
        {
            for jump in pending.into_iter().chain(exits) {
                self.patch(jump, end);
            }
        }
    }

    fn end_while(&mut self, line: usize, column: usize) {
        let Some(at) = self
            .open
            .iter()
            .rposition(|o| matches!(o.kind, OpenKind::While { .. }))
        else {
            self.push_error(
                line,
                column,
                ErrorCode::Error,
                "ENDWHILE without WHILE".into(),
            );
            return;
        };
        self.close_open(at + 1, &format!("ENDWHILE on line {line}"));
        if let Some(Open {
            kind: OpenKind::While { start },
            ..
        }) = self.open.pop()
        {
            let back = self.emit(line, Op::Jump { to: start });
            self.patch(start, back + 1);
        }
    }

    fn warn_missing_subroutines(&mut self) {
        for &(line, column, sub) in &self.calls {
            if self.program.subroutine(sub).is_none() {
                self.program.warnings.push(Warning {
                    line,
                    column,
                    message: format!(
                        "GOSUB {sub}: there is no SUB {sub} in this source; the controller reports an error when the call runs (§2.7.4)"
                    ),
                });
            }
        }
    }
}

#[cfg(test)]
mod tests;
