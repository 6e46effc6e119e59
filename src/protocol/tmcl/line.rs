//! The console line syntax: the manual's mnemonic syntax (`MVP ABS, 0,
//! 1000`, `SAP 4, 0, 1000`, `JC ZE, 10`), console names for the commands
//! without a mnemonic (`RUNAPP`, `VERSION`, `TARGETEVENT`…, see
//! [`super::catalog`]), and raw frames as four numbers
//! (`<command> <type> <motor/bank> <value>`).
//!
//! - Case-insensitive; operands separated by commas, spaces, or both.
//! - Numbers: decimal with optional sign, hex as `0x1F` or `$1F`. Hex gives
//!   the 32-bit pattern in a value field (`0xFFFFFFFF` = −1) and a plain
//!   number in a byte field (`0xFF` = 255). Decimal values must fit in a
//!   signed 32-bit value, except SAP/SGP values of a parameter read as
//!   unsigned 32-bit (bank-3 timer periods, §5.4 Table 20): those are
//!   written and printed as the user sees them, 0..4294967295.
//! - `//` starts a comment (the manual's comment syntax).
//! - Symbolic operands where the manual uses them (`ABS`, `ZE`, `TICKS`,
//!   `ADD`…), or their numbers.
//! - Names in any numeric operand go through an optional [`SymbolResolver`]
//!   (labels and constants of the assembler). Without one, a label is an
//!   error that asks for a number.
//!
//! [`parse_line`] checks the line against the TMCM-1110 too
//! ([`super::validate`]); [`parse_syntax`] checks the syntax only.

use std::fmt;

use super::catalog::{self, CodeSet, CommandInfo, Field, Operand, OperandKind, Presence};
use super::command::Command;
use super::frame::Request;
use super::params::ParamInfo;
use super::validate::validate;

/// Supplies the values of labels and constants (`Name = value`).
pub trait SymbolResolver {
    /// The value of `name` as written (case is the resolver's business),
    /// or `None` if it is unknown.
    fn resolve(&self, name: &str) -> Option<i64>;

    /// Whether `name` was defined by a hex number: then, like a hex
    /// literal, it gives the 32-bit pattern in a value field
    /// (`Minus1 = 0xFFFFFFFF` is −1 there). Plain numbers by default.
    fn is_bit_pattern(&self, _name: &str) -> bool {
        false
    }
}

impl<F: Fn(&str) -> Option<i64>> SymbolResolver for F {
    fn resolve(&self, name: &str) -> Option<i64> {
        self(name)
    }
}

/// Why a line was refused. Messages name the command, the bad operand and
/// what is allowed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LineError {
    #[error("empty line: nothing to send")]
    Empty,
    #[error(
        "`{0}` is not a TMCL command: give a mnemonic (`GAP 1, 0`), a control command \
         (`VERSION`) or a raw frame as four numbers (`<command> <type> <motor/bank> <value>`)"
    )]
    UnknownCommand(String),
    #[error("{command}: empty operand between commas (syntax: {syntax})")]
    EmptyOperand {
        command: String,
        syntax: &'static str,
    },
    #[error("{command}: missing <{operand}> (syntax: {syntax})")]
    MissingOperand {
        command: String,
        operand: &'static str,
        syntax: &'static str,
    },
    #[error("{command}: unexpected extra operand `{found}` (syntax: {syntax})")]
    ExtraOperand {
        command: String,
        found: String,
        syntax: &'static str,
    },
    #[error("{command}: <{operand}> `{found}` is not a number")]
    NotANumber {
        command: String,
        operand: &'static str,
        found: String,
    },
    #[error(
        "{command}: label `{label}` needs a number here: a direct-mode line has no labels, \
         give the program address"
    )]
    LabelNeedsNumber { command: String, label: String },
    #[error("{command}: unknown symbol `{name}` for <{operand}>")]
    UnknownSymbol {
        command: String,
        operand: &'static str,
        name: String,
    },
    #[error("{context}: {operand} {value} outside {allowed}{}", note_suffix(.note))]
    OutOfRange {
        context: String,
        operand: String,
        value: String,
        allowed: String,
        note: Option<String>,
    },
    #[error("{context}: {operand} {value} is not one of {allowed}{}", note_suffix(.note))]
    NotOneOf {
        context: String,
        operand: String,
        value: String,
        allowed: String,
        note: Option<String>,
    },
    #[error("{context}: motor {motor} does not exist: the TMCM-1110 has one axis, motor 0")]
    NoSuchMotor { context: String, motor: u8 },
    #[error("{context}: the TMCM-1110 has no {table} {number}")]
    UnknownParameter {
        context: String,
        table: String,
        number: u8,
    },
    #[error("{context}: {name} is read-only")]
    ReadOnly { context: String, name: &'static str },
    #[error("{context}: {name} cannot be read")]
    WriteOnly { context: String, name: &'static str },
    #[error(
        "{context}: {name} cannot be stored in EEPROM (access {access}; only parameters marked E can)"
    )]
    NotStorable {
        context: String,
        name: &'static str,
        access: String,
    },
    #[error("{context}: {reason}")]
    NotAllowed { context: String, reason: String },
}

fn note_suffix(note: &Option<String>) -> String {
    match note {
        Some(n) => format!(" ({n})"),
        None => String::new(),
    }
}

/// Parse a console line and check it against the TMCM-1110 (motor 0,
/// parameter numbers and ranges, banks, ports…). Labels are refused.
pub fn parse_line(line: &str) -> Result<Command, LineError> {
    let command = parse_syntax(line, None)?;
    validate(&command)?;
    Ok(command)
}

/// As [`parse_line`], with labels and constants from `symbols`.
pub fn parse_line_with(line: &str, symbols: &dyn SymbolResolver) -> Result<Command, LineError> {
    let command = parse_syntax(line, Some(symbols))?;
    validate(&command)?;
    Ok(command)
}

/// Parse a console line without checking it against a module: only the
/// syntax, the symbolic codes and the byte/32-bit ranges of the frame.
/// A raw frame (four numbers) always comes back as [`Command::Raw`].
pub fn parse_syntax(
    line: &str,
    symbols: Option<&dyn SymbolResolver>,
) -> Result<Command, LineError> {
    let code = match line.find("//") {
        Some(i) => line.get(..i).unwrap_or(line),
        None => line,
    };
    let Some(tokens) = split_tokens(code) else {
        let first = code.split([',', ' ', '\t']).find(|w| !w.is_empty());
        let (command, syntax) = match first.and_then(catalog::find_command) {
            Some(info) => (info.name.to_string(), info.syntax),
            None => (first.unwrap_or("").to_uppercase(), RAW_SYNTAX),
        };
        return Err(LineError::EmptyOperand { command, syntax });
    };
    let Some((&head, operands)) = tokens.split_first() else {
        return Err(LineError::Empty);
    };
    let parser = OperandParser { symbols };
    if starts_like_number(head) {
        return parser.raw(&tokens);
    }
    let info =
        catalog::find_command(head).ok_or_else(|| LineError::UnknownCommand(head.to_string()))?;
    parser.mnemonic(info, operands)
}

/// Parse a number as in a value operand: decimal (−2147483648..2147483647)
/// or a `0x`/`$` hex 32-bit pattern. For the assembler's `Name = value`.
pub fn parse_number(token: &str) -> Option<i32> {
    match number_literal(token)? {
        Literal { value, hex: true } => u32::try_from(value).ok().map(|v| v as i32),
        Literal { value, hex: false } => i32::try_from(value).ok(),
    }
}

/// The value of an assembler constant (`Name = value`), as written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConstantValue {
    pub value: i64,
    /// Written in hex: a 32-bit pattern (see [`SymbolResolver::is_bit_pattern`]).
    pub hex: bool,
}

/// Parse the value of an assembler constant. Wider than [`parse_number`]:
/// a constant may stand for a value the user sees above `i32::MAX` (bank-3
/// timer periods 0..4294967295, §5.4 Table 20), so decimals go from
/// −2147483648 to 4294967295 and hex from `0x0` to `0xFFFFFFFF`. Each
/// operand then checks the value as it would the literal.
pub fn parse_constant(token: &str) -> Option<ConstantValue> {
    let Literal { value, hex } = number_literal(token)?;
    let fits = if hex {
        (0..=i64::from(u32::MAX)).contains(&value)
    } else {
        (i64::from(i32::MIN)..=i64::from(u32::MAX)).contains(&value)
    };
    fits.then_some(ConstantValue { value, hex })
}

/// Whether `token` can name a label or constant: a letter or `_`, then
/// letters, digits, `_` or `.`.
pub fn is_symbol_name(token: &str) -> bool {
    is_symbol(token)
}

/// The canonical console line of a command: `parse_syntax(format_command(c))
/// == c` for every command. Raw commands print as four numbers.
pub fn format_command(command: &Command) -> String {
    let (code, kind, motor_bank, value) = command.fields();
    let info = if command.is_raw() {
        None
    } else {
        catalog::command_by_opcode(code)
    };
    let Some(info) = info else {
        return format!("{code} {kind} {motor_bank} {value}");
    };
    let mut parts = Vec::new();
    for operand in info.operands {
        let field = match (operand.field, operand.kind) {
            (Field::Type, _) => i64::from(kind),
            (Field::MotorBank, _) => i64::from(motor_bank),
            // As the user sees it: timer periods unsigned (§5.4).
            (Field::Value, OperandKind::ParamValue(table)) => table
                .param(kind, motor_bank)
                .map_or(i64::from(value), |info| info.value_from_wire(value)),
            (Field::Value, _) => i64::from(value),
        };
        match (operand.presence, operand.kind) {
            (_, OperandKind::Zero) => continue,
            (Presence::SetsType(code), _) if kind != code => continue,
            _ => {}
        }
        let symbol = match operand.kind {
            OperandKind::Code(set) => u8::try_from(field).ok().and_then(|c| set.keyword_of(c)),
            _ => None,
        };
        parts.push(symbol.map_or_else(|| field.to_string(), str::to_string));
    }
    if parts.is_empty() {
        info.name.to_string()
    } else {
        format!("{} {}", info.name, parts.join(", "))
    }
}

impl fmt::Display for Command {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&format_command(self))
    }
}

const RAW_SYNTAX: &str = "<command> <type> <motor/bank> <value>";
const RAW_CONTEXT: &str = "raw frame";

const RAW_OPERANDS: [Operand; 4] = [
    raw_operand("command", Field::Type),
    raw_operand("type", Field::Type),
    raw_operand("motor/bank", Field::MotorBank),
    Operand {
        name: "value",
        field: Field::Value,
        kind: OperandKind::Number,
        presence: Presence::Required,
    },
];

const fn raw_operand(name: &'static str, field: Field) -> Operand {
    Operand {
        name,
        field,
        kind: OperandKind::Byte,
        presence: Presence::Required,
    }
}

/// Split on commas and white space. `None` when a comma has no operand on
/// one side (`SAP 4,,0`, a trailing or leading comma).
fn split_tokens(text: &str) -> Option<Vec<&str>> {
    let mut tokens = Vec::new();
    let mut start = None;
    // A comma was seen since the last token: another comma is an empty operand.
    let mut comma_pending = false;
    for (i, ch) in text.char_indices() {
        let separator = ch == ',' || ch.is_whitespace();
        if separator {
            if let Some(s) = start.take() {
                tokens.push(text.get(s..i)?);
            }
            if ch == ',' {
                if comma_pending || tokens.is_empty() {
                    return None;
                }
                comma_pending = true;
            }
        } else if start.is_none() {
            start = Some(i);
            comma_pending = false;
        }
    }
    match start {
        Some(s) => tokens.push(text.get(s..)?),
        None if comma_pending => return None,
        None => {}
    }
    Some(tokens)
}

/// A number as written: its value (saturated far outside any field) and
/// whether it was hex.
struct Literal {
    value: i64,
    hex: bool,
}

fn starts_like_number(token: &str) -> bool {
    token
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_digit() || c == '-' || c == '+' || c == '$')
}

fn number_literal(token: &str) -> Option<Literal> {
    let hex_digits = token
        .strip_prefix("0x")
        .or_else(|| token.strip_prefix("0X"))
        .or_else(|| token.strip_prefix('$'));
    if let Some(digits) = hex_digits {
        if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_hexdigit()) {
            return None;
        }
        let significant = digits.trim_start_matches('0');
        let value = if significant.len() > 15 {
            i64::MAX
        } else {
            i64::from_str_radix(significant, 16).unwrap_or(0)
        };
        return Some(Literal { value, hex: true });
    }
    let (negative, digits) = match token.strip_prefix('-') {
        Some(d) => (true, d),
        None => (false, token.strip_prefix('+').unwrap_or(token)),
    };
    if digits.is_empty() || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    let magnitude = digits.parse::<i64>().unwrap_or(i64::MAX);
    let value = if negative { -magnitude } else { magnitude };
    Some(Literal { value, hex: false })
}

fn is_symbol(token: &str) -> bool {
    let mut chars = token.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.')
}

struct OperandParser<'a> {
    symbols: Option<&'a dyn SymbolResolver>,
}

impl OperandParser<'_> {
    fn raw(&self, tokens: &[&str]) -> Result<Command, LineError> {
        let mut fields = [0i64; 4];
        for (i, operand) in RAW_OPERANDS.iter().enumerate() {
            let token = tokens.get(i).ok_or(LineError::MissingOperand {
                command: RAW_CONTEXT.to_string(),
                operand: operand.name,
                syntax: RAW_SYNTAX,
            })?;
            fields[i] = self.value(RAW_CONTEXT, operand, token, None)?;
        }
        if let Some(extra) = tokens.get(RAW_OPERANDS.len()) {
            return Err(LineError::ExtraOperand {
                command: RAW_CONTEXT.to_string(),
                found: extra.to_string(),
                syntax: RAW_SYNTAX,
            });
        }
        let [command, kind, motor_bank, value] = fields;
        Ok(Command::Raw {
            command: byte(command),
            kind: byte(kind),
            motor_bank: byte(motor_bank),
            value: word(value),
        })
    }

    fn mnemonic(&self, info: &CommandInfo, tokens: &[&str]) -> Result<Command, LineError> {
        let mut kind: u8 = 0;
        let mut motor_bank: u8 = 0;
        let mut value: i32 = info.fixed_value;
        // Each operand with its token, or its default; `None` for an
        // optional operand left out that has no default.
        let mut given = Vec::with_capacity(info.operands.len());
        let mut remaining = tokens.iter();
        for operand in info.operands {
            let source = match remaining.next() {
                Some(token) => Some(Given::Token(token)),
                None => match operand.presence {
                    Presence::Required => {
                        return Err(LineError::MissingOperand {
                            command: info.name.to_string(),
                            operand: operand.name,
                            syntax: info.syntax,
                        });
                    }
                    Presence::Default(d) => Some(Given::Default(d)),
                    Presence::SetsType(_) => None,
                },
            };
            given.push((operand, source));
        }
        // The value field last: how a SAP/SGP value is read depends on the
        // parameter the type and motor/bank fields name.
        let (bytes, words): (Vec<_>, Vec<_>) = given
            .into_iter()
            .partition(|(operand, _)| operand.field != Field::Value);
        for (operand, source) in bytes.into_iter().chain(words) {
            let Some(source) = source else { continue };
            let param = match operand.kind {
                OperandKind::ParamValue(table) => table
                    .param(kind, motor_bank)
                    .map(|info| TargetParam { number: kind, info }),
                _ => None,
            };
            let v = match source {
                Given::Token(token) => self.value(info.name, operand, token, param)?,
                Given::Default(d) => d,
            };
            if let Presence::SetsType(code) = operand.presence {
                kind = code;
            }
            match operand.field {
                Field::Type => kind = byte(v),
                Field::MotorBank => motor_bank = byte(v),
                Field::Value => value = word(v),
            }
        }
        if let Some(extra) = remaining.next() {
            return Err(LineError::ExtraOperand {
                command: info.name.to_string(),
                found: extra.to_string(),
                syntax: info.syntax,
            });
        }
        let command = Command::from_request(&Request {
            address: 0,
            command: info.opcode,
            kind,
            motor_bank,
            value,
        });
        if command.is_raw() {
            // The catalogue and the typed commands disagree: a bug, but a
            // line must never panic.
            return Err(LineError::NotAllowed {
                context: info.name.to_string(),
                reason: "these operands do not form a valid command".to_string(),
            });
        }
        Ok(command)
    }

    /// One operand's number, checked against what its kind accepts. Byte
    /// operands come back in 0..=255, value operands in i32 range (the
    /// frame's value field; a timer period's bits, see [`TargetParam`]).
    fn value(
        &self,
        command: &str,
        operand: &Operand,
        token: &str,
        param: Option<TargetParam>,
    ) -> Result<i64, LineError> {
        if let OperandKind::Code(set) = operand.kind
            && let Some(code) = set.code_of(token)
        {
            return Ok(i64::from(code));
        }
        let not_a_code = |set: CodeSet| LineError::NotOneOf {
            context: command.to_string(),
            operand: operand.name.to_string(),
            value: token.to_string(),
            allowed: set.describe(),
            note: None,
        };
        let (value, hex) = match (number_literal(token), operand.kind) {
            (Some(Literal { value, hex }), _) => (value, hex),
            // A word that is not one of the symbols: name them, unless a
            // constant of that name exists.
            (None, OperandKind::Code(set)) => {
                let constant = self.symbols.and_then(|s| s.resolve(token));
                (constant.ok_or_else(|| not_a_code(set))?, false)
            }
            (None, _) => {
                let value = self.symbol(command, operand, token)?;
                let hex = self.symbols.is_some_and(|s| s.is_bit_pattern(token));
                (value, hex)
            }
        };
        let out_of_range = |allowed: String, note: Option<String>| LineError::OutOfRange {
            context: command.to_string(),
            operand: operand.name.to_string(),
            value: token.to_string(),
            allowed,
            note,
        };
        match operand.kind {
            OperandKind::Byte => {
                if (0..=255).contains(&value) {
                    Ok(value)
                } else {
                    Err(out_of_range("0..255".to_string(), None))
                }
            }
            OperandKind::Number | OperandKind::Label | OperandKind::ParamValue(_) => {
                if hex {
                    u32::try_from(value)
                        .map(|v| i64::from(v as i32))
                        .map_err(|_| out_of_range("0x0..0xFFFFFFFF".to_string(), None))
                } else if let Some(TargetParam { number, info }) =
                    param.filter(|p| reads_unsigned(p.info))
                {
                    info.wire_value(value)
                        .map(i64::from)
                        .ok_or_else(|| LineError::OutOfRange {
                            context: format!("{command} {number}"),
                            operand: operand.name.to_string(),
                            value: token.to_string(),
                            allowed: info.range.to_string(),
                            note: Some(info.name.to_string()),
                        })
                } else if i32::try_from(value).is_ok() {
                    Ok(value)
                } else {
                    Err(out_of_range(
                        format!("{}..{}", i32::MIN, i32::MAX),
                        Some("give a larger 32-bit pattern in hex, e.g. 0xFFFFFFFF".to_string()),
                    ))
                }
            }
            OperandKind::Code(set) => match u8::try_from(value) {
                Ok(code) if set.keyword_of(code).is_some() => Ok(value),
                _ => Err(not_a_code(set)),
            },
            OperandKind::Zero => {
                if value == 0 {
                    Ok(0)
                } else {
                    Err(out_of_range("0".to_string(), None))
                }
            }
        }
    }

    fn symbol(&self, command: &str, operand: &Operand, token: &str) -> Result<i64, LineError> {
        let is_label = operand.kind == OperandKind::Label;
        if !is_symbol(token) {
            return Err(LineError::NotANumber {
                command: command.to_string(),
                operand: operand.name,
                found: token.to_string(),
            });
        }
        match self.symbols {
            Some(symbols) => symbols
                .resolve(token)
                .ok_or_else(|| LineError::UnknownSymbol {
                    command: command.to_string(),
                    operand: operand.name,
                    name: token.to_string(),
                }),
            None if is_label => Err(LineError::LabelNeedsNumber {
                command: command.to_string(),
                label: token.to_string(),
            }),
            None => Err(LineError::NotANumber {
                command: command.to_string(),
                operand: operand.name,
                found: token.to_string(),
            }),
        }
    }
}

/// Where an operand's token came from.
enum Given<'t> {
    Token(&'t str),
    Default(i64),
}

/// The parameter a SAP/SGP value is for, when the parameter tables know it.
#[derive(Clone, Copy)]
struct TargetParam {
    number: u8,
    info: &'static ParamInfo,
}

/// Whether the parameter reads frame values as unsigned 32-bit (bank-3
/// timer periods, §5.4): then a decimal value is what the user sees,
/// 0..4294967295, and goes into the frame through
/// [`ParamInfo::wire_value`]. Asked of the parameter itself so the
/// parser, the formatter and `value_from_wire` cannot disagree.
fn reads_unsigned(info: &ParamInfo) -> bool {
    info.value_from_wire(-1) == i64::from(u32::MAX)
}

/// Operand values are range-checked before they get here.
fn byte(value: i64) -> u8 {
    u8::try_from(value).unwrap_or(0)
}

fn word(value: i64) -> i32 {
    i32::try_from(value).unwrap_or(0)
}

impl crate::protocol::line_error::FamilyLineError for LineError {
    fn mistake(&self) -> crate::protocol::line_error::Mistake {
        use crate::protocol::line_error::Mistake;
        match self {
            LineError::Empty => Mistake::Empty,
            LineError::OutOfRange { .. }
            | LineError::NotOneOf { .. }
            | LineError::NoSuchMotor { .. }
            | LineError::UnknownParameter { .. }
            | LineError::ReadOnly { .. }
            | LineError::WriteOnly { .. }
            | LineError::NotStorable { .. }
            | LineError::NotAllowed { .. } => Mistake::Range,
            _ => Mistake::Syntax,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::tmcl::command::{CalcOp, Condition, MoveMode, StatusQuery};

    fn syntax(line: &str) -> Result<Command, LineError> {
        parse_syntax(line, None)
    }

    #[test]
    fn commas_spaces_and_case_are_interchangeable() {
        let expected = Command::Mvp {
            mode: MoveMode::Abs,
            motor: 0,
            target: 1000,
        };
        for line in [
            "MVP ABS, 0, 1000",
            "mvp abs 0 1000",
            "Mvp Abs,0,1000",
            "MVP ABS ,0 ,  1000",
            "  MVP\tABS, 0, 1000  // go",
        ] {
            assert_eq!(syntax(line), Ok(expected), "{line}");
        }
    }

    #[test]
    fn symbolic_operands_also_take_their_numbers() {
        assert_eq!(syntax("MVP 1, 0, -5"), syntax("MVP REL, 0, -5"));
        assert_eq!(
            syntax("JC 4, 10"),
            Ok(Command::Jc {
                condition: Condition::Gt,
                address: 10
            })
        );
        assert!(matches!(
            syntax("MVP 3, 0, 0"),
            Err(LineError::NotOneOf { .. })
        ));
    }

    #[test]
    fn hex_gives_bit_patterns_in_values_and_plain_numbers_in_bytes() {
        assert_eq!(
            syntax("SAP $4, 0x0, 0xFFFFFFFF"),
            Ok(Command::Sap {
                param: 4,
                motor: 0,
                value: -1
            })
        );
        assert_eq!(
            syntax("GAP 0xFF, 0"),
            Ok(Command::Gap {
                param: 255,
                motor: 0
            })
        );
        assert!(matches!(
            syntax("SAP 4, 0, 0x100000000"),
            Err(LineError::OutOfRange { .. })
        ));
        assert!(matches!(
            syntax("GAP 256, 0"),
            Err(LineError::OutOfRange { .. })
        ));
        assert!(matches!(
            syntax("SAP 4, 0, 2147483648"),
            Err(LineError::OutOfRange { .. })
        ));
        assert_eq!(parse_number("$7FFFFFFF"), Some(i32::MAX));
        assert_eq!(parse_number("-2147483648"), Some(i32::MIN));
        assert_eq!(parse_number("0x"), None);
    }

    #[test]
    fn timer_period_values_are_read_as_the_user_sees_them() {
        let timer = |value| Command::Sgp {
            param: 0,
            bank: 3,
            value,
        };
        assert_eq!(syntax("SGP 0, 3, 4294967295"), Ok(timer(-1)));
        assert_eq!(format_command(&timer(-1)), "SGP 0, 3, 4294967295");
        // The same bits of a signed parameter print signed.
        let variable = Command::Sgp {
            param: 0,
            bank: 2,
            value: -1,
        };
        assert_eq!(format_command(&variable), "SGP 0, 2, -1");
        // A constant is a value as written, like a decimal.
        let constants = |name: &str| (name == "Period").then_some(3_000_000_000);
        assert_eq!(
            parse_syntax("SGP 0, 3, Period", Some(&constants)),
            Ok(timer(3_000_000_000u32 as i32))
        );
        assert!(matches!(
            parse_syntax("SGP 0, 2, Period", Some(&constants)),
            Err(LineError::OutOfRange { .. })
        ));
    }

    #[test]
    fn constants_reach_the_unsigned_timer_range() {
        let c = |value, hex| Some(ConstantValue { value, hex });
        assert_eq!(parse_constant("4294967295"), c(4_294_967_295, false));
        assert_eq!(parse_constant("-2147483648"), c(-2_147_483_648, false));
        assert_eq!(parse_constant("0xFFFFFFFF"), c(4_294_967_295, true));
        assert_eq!(parse_constant("$10"), c(16, true));
        assert_eq!(parse_constant("4294967296"), None);
        assert_eq!(parse_constant("-2147483649"), None);
        assert_eq!(parse_constant("0x100000000"), None);
        assert_eq!(parse_constant("12x"), None);
    }

    #[test]
    fn hex_constants_are_bit_patterns_like_hex_literals() {
        struct Hex;
        impl SymbolResolver for Hex {
            fn resolve(&self, name: &str) -> Option<i64> {
                (name == "AllOnes").then_some(0xFFFF_FFFF)
            }
            fn is_bit_pattern(&self, name: &str) -> bool {
                name == "AllOnes"
            }
        }
        assert_eq!(
            parse_syntax("SAP 4, 0, AllOnes", Some(&Hex)),
            parse_syntax("SAP 4, 0, 0xFFFFFFFF", None)
        );
        assert_eq!(
            parse_syntax("SGP 0, 3, AllOnes", Some(&Hex)),
            syntax("SGP 0, 3, 4294967295")
        );
        // The same number as a plain constant is too large for a signed value.
        let plain = |name: &str| (name == "AllOnes").then_some(0xFFFF_FFFF);
        assert!(matches!(
            parse_syntax("SAP 4, 0, AllOnes", Some(&plain)),
            Err(LineError::OutOfRange { .. })
        ));
    }

    #[test]
    fn calc_families_refuse_operations_they_lack() {
        let err = syntax("CALC SWAP, 1").unwrap_err();
        assert!(err.to_string().contains("LOAD (9)"), "{err}");
        assert!(syntax("CALCV SWAP, 1, 2").is_err());
        assert!(syntax("CALCX COMP").is_err());
        assert_eq!(
            syntax("CALCX swap"),
            Ok(Command::Calcx { op: CalcOp::Swap })
        );
    }

    #[test]
    fn labels_need_a_resolver() {
        let err = syntax("JA Loop").unwrap_err();
        assert_eq!(
            err,
            LineError::LabelNeedsNumber {
                command: "JA".to_string(),
                label: "Loop".to_string()
            }
        );
        assert!(err.to_string().contains("direct-mode line"));
        let labels = |name: &str| (name == "Loop").then_some(7);
        assert_eq!(
            parse_syntax("JA Loop", Some(&labels)),
            Ok(Command::Ja { address: 7 })
        );
        assert!(matches!(
            parse_syntax("JA Elsewhere", Some(&labels)),
            Err(LineError::UnknownSymbol { .. })
        ));
    }

    #[test]
    fn constants_work_in_any_numeric_operand() {
        let constants = |name: &str| match name {
            "MaxSpeed" => Some(500),
            "Motor0" => Some(0),
            _ => None,
        };
        assert_eq!(
            parse_syntax("SAP 4, Motor0, MaxSpeed", Some(&constants)),
            Ok(Command::Sap {
                param: 4,
                motor: 0,
                value: 500
            })
        );
        assert!(matches!(
            syntax("SAP 4, Motor0, 1"),
            Err(LineError::NotANumber { .. })
        ));
    }

    #[test]
    fn control_commands_have_defaults() {
        assert_eq!(
            syntax("RUNAPP"),
            Ok(Command::RunApplication { start: None })
        );
        assert_eq!(
            syntax("runapp 5"),
            Ok(Command::RunApplication { start: Some(5) })
        );
        assert_eq!(
            syntax("APPSTATUS"),
            Ok(Command::ApplicationStatus {
                query: StatusQuery::Mode
            })
        );
        assert_eq!(
            syntax("APPSTATUS X"),
            Ok(Command::ApplicationStatus {
                query: StatusQuery::XRegister
            })
        );
        assert_eq!(format_command(&Command::FactoryReset), "FACTORYRESET");
        assert_eq!(syntax("RESET").map(|c| c.to_request(1).value), Ok(1234));
    }

    #[test]
    fn raw_frames_stay_raw() {
        assert_eq!(
            syntax("1 0 0 500"),
            Ok(Command::Raw {
                command: 1,
                kind: 0,
                motor_bank: 0,
                value: 500
            })
        );
        assert_eq!(syntax("1, 0, 0, 500"), syntax("1 0 0 500"));
        assert!(matches!(
            syntax("1 0 0"),
            Err(LineError::MissingOperand { .. })
        ));
        assert!(matches!(
            syntax("1 0 0 0 0"),
            Err(LineError::ExtraOperand { .. })
        ));
        assert!(matches!(
            syntax("256 0 0 0"),
            Err(LineError::OutOfRange { .. })
        ));
    }

    #[test]
    fn malformed_lines_say_what_is_wrong() {
        assert_eq!(syntax("   // only a comment"), Err(LineError::Empty));
        assert!(matches!(
            syntax("FOO 1"),
            Err(LineError::UnknownCommand(name)) if name == "FOO"
        ));
        assert!(matches!(
            syntax("SAP 4,,0"),
            Err(LineError::EmptyOperand { command, .. }) if command == "SAP"
        ));
        assert!(matches!(
            syntax("SAP 4, 0, 1,"),
            Err(LineError::EmptyOperand { .. })
        ));
        assert!(matches!(
            syntax("SAP 4, 0, 12x"),
            Err(LineError::NotANumber {
                operand: "value",
                ..
            })
        ));
        assert!(matches!(
            syntax("SAP 4, 0, €"),
            Err(LineError::NotANumber { .. })
        ));
        assert!(matches!(
            syntax("GCO 1, 0, 5"),
            Err(LineError::OutOfRange { .. })
        ));
    }

    #[test]
    fn gco_accepts_the_manuals_three_operand_form() {
        assert_eq!(
            syntax("GCO 0, 255, 0"),
            Ok(Command::Gco {
                coordinate: 0,
                motor: 255
            })
        );
        assert_eq!(
            format_command(&Command::Gco {
                coordinate: 0,
                motor: 255
            }),
            "GCO 0, 255"
        );
    }

    #[test]
    fn formatting_is_canonical() {
        let cases = [
            ("mvp rel 0 -10000", "MVP REL, 0, -10000"),
            ("jc 5 10", "JC GE, 10"),
            ("TARGETEVENT", "TARGETEVENT ALWAYS, 1"),
            ("DOWNLOAD", "DOWNLOAD 0"),
            ("UF3", "UF3 0, 0, 0"),
            ("calcvv 1 65 42", "CALCVV SUB, 65, 42"),
        ];
        for (line, canonical) in cases {
            let command = syntax(line).unwrap();
            assert_eq!(format_command(&command), canonical);
            assert_eq!(command.to_string(), canonical);
        }
    }
}
