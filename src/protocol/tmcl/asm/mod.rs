//! The TMCL program toolchain: an assembler for the TMCL-IDE's source
//! syntax (the "TMCL creator", digest D10), a disassembler back to source,
//! the program image file and the assembler listing. Pure: include files
//! come through a [`SourceLoader`].
//!
//! Source syntax, as the manual's examples write it (§2.4, §3.5.6.4,
//! §3.6.x, §8):
//!
//! - one instruction per line, in the console-line syntax of
//!   [`super::line`] (mnemonics, symbolic operands `ABS`, `ZE`, `TICKS`…,
//!   decimal and `0x`/`$` hex numbers, raw frames as four numbers);
//! - `//` comments;
//! - `Label:` alone on a line or before an instruction: the address of the
//!   next instruction (one instruction = one program word, D10);
//! - `Name = value` constants, usable wherever a number is: decimal
//!   −2147483648..4294967295 (timer periods, §5.4), hex `0x0`..`0xFFFFFFFF`
//!   (a 32-bit pattern, like a hex literal), or an earlier constant;
//! - `#include File`, relative to the including file.
//!
//! Labels and constants are case-sensitive (the manual always writes them
//! the same way); mnemonics and symbolic operands are not. Where an operand
//! takes symbols (`MVP ABS…`, `JC GE…`), a symbol wins over a constant of
//! the same name.
//!
//! Assembly is two passes: the first reads every line (following includes)
//! and gives labels their addresses and constants their values; the second
//! parses each instruction with [`parse_syntax`] and checks it with
//! [`validate`] (the direct-mode tables) and [`check_program_command`]
//! (jump targets inside program memory, no control commands). Every error
//! is collected, with its file, line and column.

mod disasm;
pub mod highlight;
mod image;
mod listing;
mod source;
mod statement;

use std::collections::BTreeMap;
use std::fmt;

pub use disasm::{disassemble, label_name};
pub use image::{ImageError, ImageErrorKind, format_image, parse_image};
pub use listing::listing;
pub use source::{NoIncludes, SourceLoader, include_path};

use super::catalog::{self, OperandKind, Usage};
use super::command::Command;
use super::frame::Request;
use super::line::{LineError, SymbolResolver, is_symbol_name, parse_constant, parse_syntax};
use super::validate::validate;
use statement::{Spanned, Statement, classify, empty_operand_column, tokens};

/// Program memory size in words. The manual does not state it; a public
/// Trinamic TMCL interpreter header for another product uses 2048 (digest
/// D10.2), and its stack depth and coordinate count match this manual.
pub const PROGRAM_MEMORY_WORDS: usize = 2048;

/// How deep `#include`s may nest: far beyond any real program, and a stop
/// for a loader that invents ever new paths.
pub const MAX_INCLUDE_DEPTH: usize = 16;

/// One program memory cell: a TMCL command as stored by download mode
/// (§3.6.53), the 9-byte frame without address and checksum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ProgramWord {
    pub opcode: u8,
    pub kind: u8,
    pub motor_bank: u8,
    pub value: i32,
}

impl ProgramWord {
    /// Bytes per word: instruction, type, motor/bank, value MSB first.
    pub const LEN: usize = 7;

    pub fn to_bytes(self) -> [u8; Self::LEN] {
        let [v3, v2, v1, v0] = self.value.to_be_bytes();
        [self.opcode, self.kind, self.motor_bank, v3, v2, v1, v0]
    }

    pub fn from_bytes(bytes: [u8; Self::LEN]) -> Self {
        let [opcode, kind, motor_bank, v3, v2, v1, v0] = bytes;
        ProgramWord {
            opcode,
            kind,
            motor_bank,
            value: i32::from_be_bytes([v3, v2, v1, v0]),
        }
    }

    /// An erased cell: all zeros (opcode 0 is not a TMCL command).
    pub fn is_empty(self) -> bool {
        self == ProgramWord::default()
    }

    /// The typed command this word holds ([`Command::Raw`] if none).
    pub fn command(self) -> Command {
        Command::from_request(&Request {
            address: 0,
            command: self.opcode,
            kind: self.kind,
            motor_bank: self.motor_bank,
            value: self.value,
        })
    }
}

impl From<Command> for ProgramWord {
    fn from(command: Command) -> Self {
        let (opcode, kind, motor_bank, value) = command.fields();
        ProgramWord {
            opcode,
            kind,
            motor_bank,
            value,
        }
    }
}

/// Where an instruction came from, for listings and the debugger.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SourceLine {
    pub address: u16,
    pub file: String,
    /// 1-based.
    pub line: usize,
    /// The instruction as written, from its first character to the end of
    /// the line (labels before it left out, its comment kept).
    pub text: String,
}

/// An assembled program.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Program {
    /// The name the main source was assembled under.
    pub source_name: String,
    /// The image, from address 0.
    pub words: Vec<ProgramWord>,
    /// Labels and their addresses: the IDE's symbol file (§8.6), which a
    /// host needs to start a routine with command 129 type 1.
    pub symbols: BTreeMap<String, u16>,
    /// Constants and their values as written.
    pub constants: BTreeMap<String, i64>,
    /// One entry per word, in address order.
    pub lines: Vec<SourceLine>,
}

/// A place in a source file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    pub file: String,
    pub line: usize,
    pub column: usize,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file, self.line, self.column)
    }
}

/// One thing wrong with a program, where it is.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{file}:{line}:{column}: {kind}")]
pub struct AsmError {
    pub file: String,
    /// 1-based.
    pub line: usize,
    /// 1-based, in characters.
    pub column: usize,
    pub kind: AsmErrorKind,
}

impl AsmError {
    fn at(location: Location, kind: AsmErrorKind) -> Self {
        AsmError {
            file: location.file,
            line: location.line,
            column: location.column,
            kind,
        }
    }

    /// What is wrong, without the place.
    pub fn message(&self) -> String {
        self.kind.to_string()
    }
}

const CONSTANT_VALUES: &str =
    "a decimal -2147483648..4294967295, a hex 0x0..0xFFFFFFFF or an earlier constant";

/// What is wrong. Messages say what was found and what was expected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AsmErrorKind {
    #[error(
        "`{found}` is not a TMCL command: expected a mnemonic (MVP, SAP, JA…), a label \
         `Name:`, a constant `Name = value` or `#include File`{}",
        if *.looks_like_label { format!(" (a label needs a colon: `{found}:`)") } else { String::new() }
    )]
    UnknownMnemonic {
        found: String,
        looks_like_label: bool,
    },
    /// An operand the console-line parser or the module's tables refuse.
    #[error("{0}")]
    Operand(Box<LineError>),
    #[error("{command}: undefined label `{name}`{}", did_you_mean(.suggestion))]
    UndefinedLabel {
        command: String,
        name: String,
        suggestion: Option<String>,
    },
    #[error(
        "{command}: <{operand}> `{name}` is not a number or a defined constant or label{}",
        did_you_mean(.suggestion)
    )]
    UndefinedSymbol {
        command: String,
        operand: String,
        name: String,
        suggestion: Option<String>,
    },
    #[error("duplicate label `{name}`: already defined at {first}")]
    DuplicateLabel { name: String, first: Location },
    #[error("`{name}` is already a {} (at {first}): give this {} another name",
        if *.first_is_label { "label" } else { "constant" },
        if *.first_is_label { "constant" } else { "label" })]
    NameTaken {
        name: String,
        first_is_label: bool,
        first: Location,
    },
    #[error("constant `{name}` = {value} contradicts its definition = {previous} at {first}")]
    ConstantRedefined {
        name: String,
        value: i64,
        previous: i64,
        first: Location,
    },
    #[error("constant `{name}` needs a value after `=`: {CONSTANT_VALUES}")]
    MissingConstantValue { name: String },
    #[error("constant `{name}`: `{found}` is not {CONSTANT_VALUES}")]
    BadConstantValue { name: String, found: String },
    #[error(
        "{command} is a direct-mode control command (§3.6.53): the module executes it \
         during a download instead of storing it, so a program cannot hold it"
    )]
    NotStorable { command: String },
    #[error("{command}: address {address} outside program memory 0..{}", PROGRAM_MEMORY_WORDS - 1)]
    AddressOutsideMemory { command: String, address: i64 },
    #[error("program memory is full: it holds {PROGRAM_MEMORY_WORDS} instructions")]
    ProgramTooLong,
    #[error("#include needs a file name: `#include File.inc`")]
    IncludeWithoutName,
    #[error("unknown directive `{found}`: the only directive is `#include File`")]
    UnknownDirective { found: String },
    #[error("cannot include `{path}`: {reason}")]
    IncludeFailed { path: String, reason: String },
    #[error("include cycle: {}", .chain.join(" -> "))]
    IncludeCycle { chain: Vec<String> },
    #[error("includes nested deeper than {MAX_INCLUDE_DEPTH} files")]
    IncludeTooDeep,
}

fn did_you_mean(suggestion: &Option<String>) -> String {
    match suggestion {
        Some(s) => format!(" (did you mean `{s}`?)"),
        None => String::new(),
    }
}

/// Whether a program can hold `command`: not a control command (the module
/// executes those even in download mode, §3.6.53), and the address of a
/// jump, call, vector or restart inside program memory. Operand ranges are
/// [`validate`]'s business; raw frames pass unless they are control
/// commands.
pub fn check_program_command(command: &Command) -> Result<(), AsmErrorKind> {
    let (opcode, _, _, value) = command.fields();
    let Some(info) = catalog::command_by_opcode(opcode) else {
        return Ok(());
    };
    if info.usage == Usage::DirectOnly {
        let command = if command.is_raw() {
            format!("instruction {opcode} ({})", info.name)
        } else {
            info.name.to_string()
        };
        return Err(AsmErrorKind::NotStorable { command });
    }
    let takes_address = info.operands.iter().any(|o| o.kind == OperandKind::Label);
    if !command.is_raw() && takes_address && !in_memory(i64::from(value)) {
        return Err(AsmErrorKind::AddressOutsideMemory {
            command: info.name.to_string(),
            address: i64::from(value),
        });
    }
    Ok(())
}

fn in_memory(address: i64) -> bool {
    usize::try_from(address).is_ok_and(|a| a < PROGRAM_MEMORY_WORDS)
}

/// Assemble the program `source`, known as `source_name` (a path, for
/// messages and for resolving includes through `loader`). Either the whole
/// program or every error found, in source order.
pub fn assemble(
    source_name: &str,
    source: &str,
    loader: &dyn SourceLoader,
) -> Result<Program, Vec<AsmError>> {
    let mut pass = FirstPass {
        loader,
        instructions: Vec::new(),
        labels: BTreeMap::new(),
        constants: BTreeMap::new(),
        errors: Vec::new(),
        order: 0,
        full_reported: false,
    };
    let mut stack = Vec::new();
    pass.read(source_name, source, &mut stack);
    let FirstPass {
        instructions,
        labels,
        constants,
        mut errors,
        ..
    } = pass;

    let symbols = Symbols {
        labels: &labels,
        constants: &constants,
    };
    let mut words = Vec::with_capacity(instructions.len());
    let mut lines = Vec::with_capacity(instructions.len());
    for item in &instructions {
        match encode(item, &symbols) {
            Ok(word) => words.push(word),
            Err((column, kind)) => {
                let location = Location {
                    file: item.file.clone(),
                    line: item.line,
                    column,
                };
                errors.push((item.order, AsmError::at(location, kind)));
            }
        }
        lines.push(SourceLine {
            address: address_u16(item.address),
            file: item.file.clone(),
            line: item.line,
            text: item.shown.clone(),
        });
    }
    if !errors.is_empty() {
        // Stable: errors of one line stay in the order they were found.
        errors.sort_by_key(|(order, _)| *order);
        return Err(errors.into_iter().map(|(_, e)| e).collect());
    }
    Ok(Program {
        source_name: source_name.to_string(),
        words,
        symbols: labels
            .into_iter()
            .map(|(name, def)| (name, address_u16(def.address)))
            .collect(),
        constants: constants
            .into_iter()
            .map(|(name, def)| (name, def.value))
            .collect(),
        lines,
    })
}

fn address_u16(address: usize) -> u16 {
    u16::try_from(address).unwrap_or(u16::MAX)
}

/// An instruction found by the first pass.
struct Instruction {
    /// Position in reading order, for sorting errors.
    order: usize,
    file: String,
    line: usize,
    address: usize,
    /// The instruction without comment, and its column.
    code: String,
    column: usize,
    /// As written, comment included.
    shown: String,
}

struct LabelDef {
    address: usize,
    at: Location,
}

struct ConstantDef {
    value: i64,
    hex: bool,
    at: Location,
}

struct FirstPass<'l> {
    loader: &'l dyn SourceLoader,
    instructions: Vec<Instruction>,
    labels: BTreeMap<String, LabelDef>,
    constants: BTreeMap<String, ConstantDef>,
    errors: Vec<(usize, AsmError)>,
    order: usize,
    full_reported: bool,
}

impl FirstPass<'_> {
    fn error(&mut self, at: Location, kind: AsmErrorKind) {
        self.errors.push((self.order, AsmError::at(at, kind)));
    }

    /// Read one file; `stack` holds the files including it. Recursion is
    /// bounded by [`MAX_INCLUDE_DEPTH`].
    fn read(&mut self, path: &str, text: &str, stack: &mut Vec<String>) {
        stack.push(path.to_string());
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        for (index, line) in text.lines().enumerate() {
            self.order += 1;
            let number = index + 1;
            let at = |column| Location {
                file: path.to_string(),
                line: number,
                column,
            };
            match classify(line) {
                Statement::Empty => {}
                Statement::IncludeWithoutName { column } => {
                    self.error(at(column), AsmErrorKind::IncludeWithoutName);
                }
                Statement::UnknownDirective { directive } => {
                    let found = directive.text.to_string();
                    self.error(
                        at(directive.column),
                        AsmErrorKind::UnknownDirective { found },
                    );
                }
                Statement::Include { name } => self.include(path, name, at(name.column), stack),
                Statement::Constant { name, value } => {
                    self.define_constant(name, value, at(name.column), at(value.column));
                }
                Statement::Code {
                    labels,
                    instruction,
                } => {
                    for label in labels {
                        self.define_label(label.text, at(label.column));
                    }
                    if let Some(instruction) = instruction {
                        self.add_instruction(path, number, line, instruction);
                    }
                }
            }
        }
        stack.pop();
    }

    fn include(&mut self, from: &str, name: Spanned<'_>, at: Location, stack: &mut Vec<String>) {
        let path = include_path(from, name.text);
        if let Some(first) = stack.iter().position(|p| *p == path) {
            let mut chain: Vec<String> = stack.get(first..).unwrap_or_default().to_vec();
            chain.push(path);
            self.error(at, AsmErrorKind::IncludeCycle { chain });
            return;
        }
        if stack.len() >= MAX_INCLUDE_DEPTH {
            self.error(at, AsmErrorKind::IncludeTooDeep);
            return;
        }
        match self.loader.load(&path) {
            Ok(text) => self.read(&path, &text, stack),
            Err(reason) => {
                let reason = reason.to_string();
                self.error(at, AsmErrorKind::IncludeFailed { path, reason });
            }
        }
    }

    fn define_label(&mut self, name: &str, at: Location) {
        if let Some(first) = self.labels.get(name) {
            let first = first.at.clone();
            let name = name.to_string();
            self.error(at, AsmErrorKind::DuplicateLabel { name, first });
        } else if let Some(first) = self.constants.get(name) {
            let first = first.at.clone();
            let name = name.to_string();
            let kind = AsmErrorKind::NameTaken {
                name,
                first_is_label: false,
                first,
            };
            self.error(at, kind);
        } else {
            let address = self.instructions.len();
            self.labels
                .insert(name.to_string(), LabelDef { address, at });
        }
    }

    fn define_constant(
        &mut self,
        name: Spanned<'_>,
        value: Spanned<'_>,
        at: Location,
        value_at: Location,
    ) {
        let defined_name = name.text.to_string();
        if value.text.is_empty() {
            let kind = AsmErrorKind::MissingConstantValue { name: defined_name };
            self.error(value_at, kind);
            return;
        }
        let parsed = match parse_constant(value.text) {
            Some(c) => Some((c.value, c.hex)),
            None if is_symbol_name(value.text) => {
                self.constants.get(value.text).map(|c| (c.value, c.hex))
            }
            None => None,
        };
        let Some((number, hex)) = parsed else {
            let kind = AsmErrorKind::BadConstantValue {
                name: defined_name,
                found: value.text.to_string(),
            };
            self.error(value_at, kind);
            return;
        };
        if let Some(label) = self.labels.get(name.text) {
            let kind = AsmErrorKind::NameTaken {
                name: defined_name,
                first_is_label: true,
                first: label.at.clone(),
            };
            self.error(at, kind);
            return;
        }
        if let Some(previous) = self.constants.get(name.text) {
            // The same definition twice (a file included twice) is harmless.
            if previous.value != number || previous.hex != hex {
                let kind = AsmErrorKind::ConstantRedefined {
                    name: defined_name,
                    value: number,
                    previous: previous.value,
                    first: previous.at.clone(),
                };
                self.error(at, kind);
            }
            return;
        }
        self.constants.insert(
            defined_name,
            ConstantDef {
                value: number,
                hex,
                at,
            },
        );
    }

    fn add_instruction(&mut self, file: &str, line: usize, text: &str, code: Spanned<'_>) {
        let address = self.instructions.len();
        if address >= PROGRAM_MEMORY_WORDS && !self.full_reported {
            self.full_reported = true;
            let at = Location {
                file: file.to_string(),
                line,
                column: code.column,
            };
            self.error(at, AsmErrorKind::ProgramTooLong);
        }
        let shown = text
            .chars()
            .skip(code.column - 1)
            .collect::<String>()
            .trim_end()
            .to_string();
        self.instructions.push(Instruction {
            order: self.order,
            file: file.to_string(),
            line,
            address,
            code: code.text.to_string(),
            column: code.column,
            shown,
        });
    }
}

/// Labels and constants, for the console-line parser.
struct Symbols<'a> {
    labels: &'a BTreeMap<String, LabelDef>,
    constants: &'a BTreeMap<String, ConstantDef>,
}

impl Symbols<'_> {
    /// A defined name close to `name`: the same but for case, or one or
    /// two typing slips away (the closest, first in name order on a tie).
    fn similar(&self, name: &str) -> Option<String> {
        let names = || self.labels.keys().chain(self.constants.keys());
        if let Some(same) = names().find(|k| k.eq_ignore_ascii_case(name)) {
            return Some(same.clone());
        }
        let lower = name.to_ascii_lowercase();
        names()
            .filter_map(|k| {
                let distance = edit_distance(&k.to_ascii_lowercase(), &lower);
                (distance <= 2 && distance < name.chars().count()).then_some((distance, k))
            })
            .min_by_key(|(distance, _)| *distance)
            .map(|(_, k)| k.clone())
    }
}

impl SymbolResolver for Symbols<'_> {
    fn resolve(&self, name: &str) -> Option<i64> {
        match self.labels.get(name) {
            Some(label) => i64::try_from(label.address).ok(),
            None => self.constants.get(name).map(|c| c.value),
        }
    }

    fn is_bit_pattern(&self, name: &str) -> bool {
        !self.labels.contains_key(name) && self.constants.get(name).is_some_and(|c| c.hex)
    }
}

/// Levenshtein distance (insertions, deletions, substitutions) in
/// characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut current = Vec::with_capacity(b.len() + 1);
        current.push(i + 1);
        for (j, cb) in b.iter().enumerate() {
            let substitute = previous.get(j).copied().unwrap_or(0) + usize::from(ca != *cb);
            let delete = previous.get(j + 1).copied().unwrap_or(0) + 1;
            let insert = current.get(j).copied().unwrap_or(0) + 1;
            current.push(substitute.min(delete).min(insert));
        }
        previous = current;
    }
    previous.last().copied().unwrap_or(0)
}

/// Second pass for one instruction: the word, or the column and the error.
fn encode(item: &Instruction, symbols: &Symbols<'_>) -> Result<ProgramWord, (usize, AsmErrorKind)> {
    let instruction = Spanned {
        text: &item.code,
        column: item.column,
    };
    let command = parse_syntax(&item.code, Some(symbols))
        .map_err(|e| operand_error(e, instruction, symbols))?;
    check_program_command(&command).map_err(|kind| {
        let column = match kind {
            AsmErrorKind::AddressOutsideMemory { .. } => {
                operand_column(instruction, "address").unwrap_or(item.column)
            }
            _ => item.column,
        };
        (column, kind)
    })?;
    validate(&command).map_err(|e| operand_error(e, instruction, symbols))?;
    Ok(ProgramWord::from(command))
}

/// The assembler's form of a console-line error, and the column of the
/// operand it is about.
fn operand_error(
    error: LineError,
    instruction: Spanned<'_>,
    symbols: &Symbols<'_>,
) -> (usize, AsmErrorKind) {
    let head = instruction.column;
    match error {
        LineError::UnknownCommand(found) => {
            let looks_like_label =
                is_symbol_name(instruction.text.trim()) && instruction.text.trim() == found;
            let kind = AsmErrorKind::UnknownMnemonic {
                found,
                looks_like_label,
            };
            (head, kind)
        }
        LineError::UnknownSymbol {
            command,
            operand,
            name,
        } => {
            let column = token_column(instruction, &name).unwrap_or(head);
            let suggestion = symbols.similar(&name);
            let is_label = catalog::find_command(&command).is_some_and(|info| {
                info.operands
                    .iter()
                    .any(|o| o.name == operand && o.kind == OperandKind::Label)
            });
            let kind = if is_label {
                AsmErrorKind::UndefinedLabel {
                    command,
                    name,
                    suggestion,
                }
            } else {
                AsmErrorKind::UndefinedSymbol {
                    command,
                    operand: operand.to_string(),
                    name,
                    suggestion,
                }
            };
            (column, kind)
        }
        other => {
            let column = error_column(&other, instruction).unwrap_or(head);
            (column, AsmErrorKind::Operand(Box::new(other)))
        }
    }
}

fn error_column(error: &LineError, instruction: Spanned<'_>) -> Option<usize> {
    match error {
        LineError::EmptyOperand { .. } => empty_operand_column(instruction),
        // Just past the end: where the operand should have been.
        LineError::MissingOperand { .. } => {
            Some(instruction.column + instruction.text.chars().count())
        }
        LineError::ExtraOperand { .. } => extra_operand_column(instruction),
        LineError::NotANumber { found, .. } => token_column(instruction, found),
        LineError::LabelNeedsNumber { label, .. } => token_column(instruction, label),
        LineError::UnknownSymbol { name, .. } => token_column(instruction, name),
        LineError::OutOfRange { operand, value, .. }
        | LineError::NotOneOf { operand, value, .. } => {
            operand_column(instruction, operand).or_else(|| token_column(instruction, value))
        }
        LineError::NoSuchMotor { .. } => operand_column(instruction, "motor"),
        LineError::UnknownParameter { .. }
        | LineError::ReadOnly { .. }
        | LineError::WriteOnly { .. }
        | LineError::NotStorable { .. } => operand_column(instruction, "parameter"),
        LineError::Empty | LineError::UnknownCommand(_) | LineError::NotAllowed { .. } => None,
    }
}

/// Names of the four numbers of a raw frame, as the parser reports them.
const RAW_OPERANDS: [&str; 4] = ["command", "type", "motor/bank", "value"];

/// The column of the operand called `name` (`"address"` is the label
/// operand), by its position in the instruction.
fn operand_column(instruction: Spanned<'_>, name: &str) -> Option<usize> {
    let tokens = tokens(instruction);
    let head = tokens.first()?;
    let position = match catalog::find_command(head.text) {
        Some(info) => {
            1 + info.operands.iter().position(|o| {
                o.name == name || (name == "address" && o.kind == OperandKind::Label)
            })?
        }
        None => RAW_OPERANDS.iter().position(|n| *n == name)?,
    };
    tokens.get(position).map(|t| t.column)
}

/// The column of the first operand beyond those the command takes.
fn extra_operand_column(instruction: Spanned<'_>) -> Option<usize> {
    let tokens = tokens(instruction);
    let head = tokens.first()?;
    let position = match catalog::find_command(head.text) {
        Some(info) => 1 + info.operands.len(),
        None => RAW_OPERANDS.len(),
    };
    tokens.get(position).map(|t| t.column)
}

/// The column of the operand written as `found`.
fn token_column(instruction: Spanned<'_>, found: &str) -> Option<usize> {
    let tokens = tokens(instruction);
    let skip = usize::from(
        tokens
            .first()
            .is_some_and(|t| catalog::find_command(t.text).is_some()),
    );
    tokens
        .iter()
        .skip(skip)
        .find(|t| t.text.eq_ignore_ascii_case(found))
        .map(|t| t.column)
}

#[cfg(test)]
mod tests;
