//! MCCL command lines (Ch2 "MCCL Command Syntax", Ch4): commands
//! `[axis]MM[parameter]` separated by commas, the axis carried from command
//! to command, parameters as numbers, `@n` (register n) or `"strings"`.
//!
//! One parser for every front end and the simulator: it reads lines as the
//! manual writes them — any case (`1sg.04`, `al@100`), blanks after commas
//! (`LU"STATUS", 2RL@0`), a `;` comment after the commands (Ch4
//! "Downloading MCCL Text Files") — and maps the Cyrillic and Greek
//! look-alike letters of the PDF text (`ТР`, `то`) to ASCII outside
//! strings. The formatter writes the canonical form the controller gets:
//! upper case, no blanks, no comment. What a line means beyond its syntax
//! (ranges, placement, flow) is [`super::check`]'s.

use std::fmt;
use std::ops::Range;

use super::catalog::{self, CommandSpec};

/// How numbers are written on the interface (Ch13 DM, HM).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum NumberBase {
    /// Decimal, the default after power-up and reset.
    #[default]
    Decimal,
    /// Hexadecimal both ways after `HM` ("If a command parameter is to be
    /// entered in hexadecimal format, and the number starts with either A,
    /// B, C, D, E, or F, it must be preceded by a '0'").
    Hex,
}

/// A number as written: its literal (upper case, otherwise as typed: `.5`,
/// `0.100000`, `0FF`) and its value.
#[derive(Debug, Clone, PartialEq)]
pub struct Number {
    text: String,
    value: f64,
    integer: bool,
}

impl Number {
    /// The literal as the controller gets it.
    pub fn text(&self) -> &str {
        &self.text
    }

    pub fn value(&self) -> f64 {
        self.value
    }

    /// Whether it is written as an integer (no decimal point, no exponent:
    /// Ch11 AL "double if n has a decimal point").
    pub fn is_integer(&self) -> bool {
        self.integer
    }

    /// The value as an integer, if written as one.
    pub fn as_integer(&self) -> Option<i64> {
        self.integer.then_some(self.value as i64)
    }

    /// The literal as it is written for an interface in `base`: an
    /// integer in hexadecimal after `HM` (a leading 0 before A–F, a sign
    /// kept: Ch13 HM), anything else as it is (reals stay decimal).
    pub fn written_in(&self, base: NumberBase) -> String {
        match base {
            NumberBase::Hex if self.integer => {
                let magnitude = format!("{:X}", (self.value as i64).unsigned_abs());
                let sign = if self.value < 0.0 { "-" } else { "" };
                let lead = if magnitude.starts_with(|c: char| c.is_ascii_alphabetic()) {
                    "0"
                } else {
                    ""
                };
                format!("{sign}{lead}{magnitude}")
            }
            NumberBase::Hex | NumberBase::Decimal => self.text.clone(),
        }
    }

    /// A decimal integer literal.
    pub fn integer(value: i64) -> Number {
        Number {
            text: value.to_string(),
            value: value as f64,
            integer: true,
        }
    }

    /// A decimal literal with `decimals` digits after the point.
    pub fn real(value: f64, decimals: usize) -> Number {
        let text = format!("{value:.decimals$}");
        Number {
            value: text.parse().unwrap_or(value),
            integer: decimals == 0,
            text,
        }
    }
}

/// What follows a mnemonic.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Number(Number),
    /// `@n`: the contents of register n (Ch4 "Controller User Registers").
    Register(u32),
    /// `"…"`, without its quotes; kept as typed (`\n`, `%d` are the
    /// controller's to read).
    Text(String),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Number(n) => f.write_str(&n.text),
            Value::Register(r) => write!(f, "@{r}"),
            Value::Text(t) => write!(f, "\"{t}\""),
        }
    }
}

/// One command of a line.
#[derive(Debug, Clone)]
pub struct Command {
    /// The axis written before it, if any (a line carries it on, see
    /// [`Line::axis_of`]).
    pub axis: Option<u8>,
    pub spec: &'static CommandSpec,
    /// `None` when nothing follows the mnemonic (the controller takes 0).
    pub value: Option<Value>,
    /// Where it is in the text parsed (bytes), for messages.
    pub span: Range<usize>,
    /// Whether blanks stood around it (the manual says none, Ch2).
    pub spaced: bool,
}

impl Command {
    pub fn new(axis: Option<u8>, spec: &'static CommandSpec, value: Option<Value>) -> Command {
        Command {
            axis,
            spec,
            value,
            span: 0..0,
            spaced: false,
        }
    }

    pub fn mnemonic(&self) -> &'static str {
        self.spec.mnemonic
    }

    /// The number it takes: the value written, or 0 when none is (Ch2).
    /// `None` for a register or a string.
    pub fn number(&self) -> Option<f64> {
        match &self.value {
            None => Some(0.0),
            Some(Value::Number(n)) => Some(n.value),
            Some(_) => None,
        }
    }

    /// The string it carries, if any.
    pub fn text(&self) -> Option<&str> {
        match &self.value {
            Some(Value::Text(t)) => Some(t),
            _ => None,
        }
    }
}

impl PartialEq for Command {
    /// Commands are equal when they read the same; where they stood in a
    /// text does not matter.
    fn eq(&self, other: &Self) -> bool {
        self.axis == other.axis
            && self.spec.mnemonic == other.spec.mnemonic
            && self.value == other.value
    }
}

impl fmt::Display for Command {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(axis) = self.axis {
            write!(f, "{axis}")?;
        }
        f.write_str(self.spec.mnemonic)?;
        if let Some(value) = &self.value {
            write!(f, "{value}")?;
        }
        Ok(())
    }
}

/// Which axis a command acts on, after the line's carrying rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisRef {
    /// Written before it.
    Given(u8),
    /// Written before an earlier command of the line (Ch2: "the axis that a
    /// command acts on is assumed to be the last one specified in the
    /// command string").
    Carried(u8),
    /// None written yet on the line: the default axis (`UA`, 0 = all at
    /// power-up; Ch2 "Whenever a new command string is entered, the axis is
    /// assumed to be 0 (all) until one is specified", Ch5 UA).
    Default,
}

impl AxisRef {
    /// The axis number, if the line names one.
    pub fn number(self) -> Option<u8> {
        match self {
            AxisRef::Given(n) | AxisRef::Carried(n) => Some(n),
            AxisRef::Default => None,
        }
    }
}

/// A command line: what is sent before one CR.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Line {
    pub commands: Vec<Command>,
}

impl Line {
    pub fn new(commands: Vec<Command>) -> Line {
        Line { commands }
    }

    /// The axis command `index` acts on.
    pub fn axis_of(&self, index: usize) -> AxisRef {
        let Some(command) = self.commands.get(index) else {
            return AxisRef::Default;
        };
        if let Some(axis) = command.axis {
            return AxisRef::Given(axis);
        }
        self.commands[..index]
            .iter()
            .rev()
            .find_map(|c| c.axis)
            .map_or(AxisRef::Default, AxisRef::Carried)
    }

    /// Whether any command is `mnemonic`.
    pub fn contains(&self, mnemonic: &str) -> bool {
        self.commands.iter().any(|c| c.mnemonic() == mnemonic)
    }

    /// Whether the line defines a macro (`MDn` first): the rest is stored,
    /// not run (Ch10 MD).
    pub fn defines_macro(&self) -> bool {
        self.commands.first().is_some_and(|c| c.mnemonic() == "MD")
    }

    /// Whether the line is a background task (`GT0` first: "the commands
    /// following the Generate Task command will be executed as a background
    /// task", Ch4, Ch10 GT).
    pub fn is_task(&self) -> bool {
        self.commands
            .first()
            .is_some_and(|c| c.mnemonic() == "GT" && c.number() == Some(0.0))
    }
}

impl Line {
    /// The canonical text as it is written for an interface in `base`:
    /// the same as [`Line`]'s `Display` in decimal, integers in
    /// hexadecimal after `HM` (axes and registers stay as they are).
    pub fn written_in(&self, base: NumberBase) -> String {
        let mut text = String::new();
        for (index, command) in self.commands.iter().enumerate() {
            if index > 0 {
                text.push(',');
            }
            if let Some(axis) = command.axis {
                text.push_str(&axis.to_string());
            }
            text.push_str(command.spec.mnemonic);
            match &command.value {
                Some(Value::Number(n)) => text.push_str(&n.written_in(base)),
                Some(other) => text.push_str(&other.to_string()),
                None => {}
            }
        }
        text
    }
}

impl fmt::Display for Line {
    /// The canonical text: commands joined by commas, no blanks.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (index, command) in self.commands.iter().enumerate() {
            if index > 0 {
                f.write_str(",")?;
            }
            write!(f, "{command}")?;
        }
        Ok(())
    }
}

/// Why a line does not parse.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ParseErrorKind {
    /// Nothing but blanks or a comment.
    Empty,
    /// Nothing between two commas, or after the last.
    EmptyCommand,
    /// `@` before the axis ("The controller does not support the use of the
    /// '@' sign in front of an axis number", Ch4).
    IndirectAxis,
    AxisTooLarge,
    /// No two-letter mnemonic where one belongs.
    NoMnemonic {
        suggestion: Option<String>,
    },
    UnknownMnemonic {
        mnemonic: String,
        suggestion: Option<String>,
    },
    /// A blank inside a command (Ch2: "with no intervening spaces").
    Blank,
    UnterminatedString,
    /// Something after a string's closing quote.
    AfterString,
    /// A string where the command takes a number, or the other way round.
    BadNumber {
        base: NumberBase,
        suggestion: Option<String>,
    },
    BadRegister,
    /// A character the controller cannot take (the interface is ASCII).
    NotAscii(char),
}

/// A line that does not parse: where, which command, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParseError {
    /// Bytes of the text parsed.
    pub span: Range<usize>,
    /// The index of the command (0-based, as JP counts), if it is in one.
    pub command: Option<usize>,
    /// The command's text as written.
    pub text: String,
    pub kind: ParseErrorKind,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let text = &self.text;
        let suggest = |f: &mut fmt::Formatter<'_>, s: &Option<String>| match s {
            Some(s) => write!(f, " — did you mean `{s}`?"),
            None => Ok(()),
        };
        match &self.kind {
            ParseErrorKind::Empty => f.write_str(
                "nothing to send (an empty line would repeat the controller's last line, Ch2)",
            ),
            ParseErrorKind::EmptyCommand => match self.command {
                Some(index) => write!(
                    f,
                    "command {} is empty (two commas, or one at the end)",
                    index + 1
                ),
                None => f.write_str("empty command"),
            },
            ParseErrorKind::IndirectAxis => write!(
                f,
                "`{text}`: an axis cannot be a register (@n): the controller does not support \
                 '@' in front of an axis number (Ch4)"
            ),
            ParseErrorKind::AxisTooLarge => {
                write!(f, "`{text}`: the axis number is too large (axes are 1–8)")
            }
            ParseErrorKind::NoMnemonic { suggestion } => {
                write!(f, "`{text}`: no two-letter command")?;
                suggest(f, suggestion)
            }
            ParseErrorKind::UnknownMnemonic {
                mnemonic,
                suggestion,
            } => {
                write!(f, "`{text}`: {mnemonic} is not an MCCL command")?;
                suggest(f, suggestion)
            }
            ParseErrorKind::Blank => write!(
                f,
                "`{text}`: no blanks inside a command (Ch2: \"with no intervening spaces\")"
            ),
            ParseErrorKind::UnterminatedString => {
                write!(f, "`{text}`: the string has no closing \"")
            }
            ParseErrorKind::AfterString => {
                write!(f, "`{text}`: nothing may follow the string's closing \"")
            }
            ParseErrorKind::BadNumber { base, suggestion } => {
                match base {
                    NumberBase::Decimal => write!(
                        f,
                        "`{text}`: the parameter is not a number ([-]digits[.digits], @n or \"text\")"
                    )?,
                    NumberBase::Hex => write!(
                        f,
                        "`{text}`: the parameter is not a hexadecimal integer (hex mode: a \
                         leading 0 before A–F, no decimal point)"
                    )?,
                }
                suggest(f, suggestion)
            }
            ParseErrorKind::BadRegister => {
                write!(f, "`{text}`: @ must be followed by a register number")
            }
            ParseErrorKind::NotAscii(c) => write!(
                f,
                "`{text}`: '{c}' is not an ASCII character (the controller's interface is ASCII)"
            ),
        }
    }
}

/// Parse errors of a line, at least one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParseErrors(pub Vec<ParseError>);

impl fmt::Display for ParseErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let texts: Vec<String> = self.0.iter().map(ToString::to_string).collect();
        f.write_str(&texts.join("; "))
    }
}

impl std::error::Error for ParseErrors {}

impl crate::protocol::line_error::FamilyLineError for ParseErrors {
    fn mistake(&self) -> crate::protocol::line_error::Mistake {
        use crate::protocol::line_error::Mistake;
        if self.0.iter().all(|e| e.kind == ParseErrorKind::Empty) {
            Mistake::Empty
        } else if self
            .0
            .iter()
            .any(|e| e.kind == ParseErrorKind::AxisTooLarge)
        {
            Mistake::Range
        } else {
            Mistake::Syntax
        }
    }
}

/// The ASCII letter a Cyrillic or Greek look-alike stands for in the
/// manual's text (`ТВ` = TB, `ТК` = TK, `то` = TO, `СН` = CH, `ТΧ` = TX;
/// digest §1), or the character itself.
pub fn ascii_lookalike(c: char) -> char {
    match c {
        // Cyrillic capitals.
        'А' => 'A',
        'В' => 'B',
        'С' => 'C',
        'Е' => 'E',
        'Н' => 'H',
        'І' => 'I',
        'Ј' => 'J',
        'К' => 'K',
        'М' => 'M',
        'О' => 'O',
        'Р' => 'P',
        'Ѕ' => 'S',
        'Т' => 'T',
        'Х' => 'X',
        'У' => 'Y',
        // Cyrillic small letters that print like Latin ones or small caps.
        'а' => 'a',
        'в' => 'b',
        'с' => 'c',
        'е' => 'e',
        'н' => 'h',
        'і' => 'i',
        'ј' => 'j',
        'к' => 'k',
        'м' => 'm',
        'о' => 'o',
        'р' => 'p',
        'ѕ' => 's',
        'т' => 't',
        'х' => 'x',
        'у' => 'y',
        // Greek capitals.
        'Α' => 'A',
        'Β' => 'B',
        'Ε' => 'E',
        'Ζ' => 'Z',
        'Η' => 'H',
        'Ι' => 'I',
        'Κ' => 'K',
        'Μ' => 'M',
        'Ν' => 'N',
        'Ο' => 'O',
        'Ρ' => 'P',
        'Τ' => 'T',
        'Υ' => 'Y',
        'Χ' => 'X',
        'ο' => 'o',
        other => other,
    }
}

/// The text with look-alike letters mapped outside strings, and for each
/// byte of it the byte of `text` it came from.
fn normalise(text: &str) -> (String, Vec<usize>) {
    let mut out = String::with_capacity(text.len());
    let mut origin = Vec::with_capacity(text.len() + 1);
    let mut in_string = false;
    for (at, c) in text.char_indices() {
        let c = if in_string { c } else { ascii_lookalike(c) };
        if c == '"' {
            in_string = !in_string;
        }
        let before = out.len();
        out.push(c);
        origin.extend(std::iter::repeat_n(at, out.len() - before));
    }
    origin.push(text.len());
    (out, origin)
}

/// Where `;` starts a comment: outside strings (a `;` in `OT"…"` is text,
/// digest §16).
pub fn comment_start(text: &str) -> Option<usize> {
    let mut in_string = false;
    for (at, c) in text.char_indices() {
        match c {
            '"' => in_string = !in_string,
            ';' if !in_string => return Some(at),
            _ => {}
        }
    }
    None
}

/// Byte ranges of the commands of `body` (split at commas outside strings).
fn split_commands(body: &str) -> Vec<Range<usize>> {
    let mut ranges = Vec::new();
    let mut start = 0;
    let mut in_string = false;
    for (at, c) in body.char_indices() {
        match c {
            '"' => in_string = !in_string,
            ',' if !in_string => {
                ranges.push(start..at);
                start = at + 1;
            }
            _ => {}
        }
    }
    ranges.push(start..body.len());
    ranges
}

fn is_blank(c: char) -> bool {
    c == ' ' || c == '\t'
}

/// Parse a line as the controller reads it in `base`. Every command that
/// does not parse is reported, in order.
pub fn parse_line(text: &str, base: NumberBase) -> Result<Line, ParseErrors> {
    let (norm, origin) = normalise(text);
    let body = match comment_start(&norm) {
        Some(at) => &norm[..at],
        None => &norm[..],
    };
    // Blanks before the first command and before a comment are no blanks
    // between commands.
    let lead = body.len() - body.trim_start_matches(is_blank).len();
    let body = body.trim_end_matches(is_blank);
    let original = |range: &Range<usize>| -> Range<usize> {
        let start = origin.get(range.start).copied().unwrap_or(text.len());
        let end = origin.get(range.end).copied().unwrap_or(text.len());
        start..end
    };
    if body.trim_matches(is_blank).is_empty() {
        return Err(ParseErrors(vec![ParseError {
            span: 0..text.len(),
            command: None,
            text: text.trim().to_string(),
            kind: ParseErrorKind::Empty,
        }]));
    }
    let mut commands = Vec::new();
    let mut errors = Vec::new();
    for (index, range) in split_commands(&body[lead..]).into_iter().enumerate() {
        let range = range.start + lead..range.end + lead;
        let raw = &body[range.clone()];
        let trimmed = raw.trim_matches(is_blank);
        let blanks = raw.len() - raw.trim_start_matches(is_blank).len();
        let range = range.start + blanks..range.start + blanks + trimmed.len();
        let span = original(&range);
        match parse_command(trimmed, base) {
            Ok((axis, spec, value)) => commands.push(Command {
                axis,
                spec,
                value,
                span,
                spaced: trimmed.len() != raw.len(),
            }),
            Err(kind) => errors.push(ParseError {
                span,
                command: Some(index),
                text: trimmed.to_string(),
                kind,
            }),
        }
    }
    if errors.is_empty() {
        Ok(Line { commands })
    } else {
        Err(ParseErrors(errors))
    }
}

/// Parse one command (no blanks around it) in `base`.
pub fn parse_command(
    text: &str,
    base: NumberBase,
) -> Result<(Option<u8>, &'static CommandSpec, Option<Value>), ParseErrorKind> {
    parse_command_plain(text, base).map_err(|kind| match kind {
        ParseErrorKind::NoMnemonic { .. } => ParseErrorKind::NoMnemonic {
            suggestion: suggest(text, base),
        },
        ParseErrorKind::UnknownMnemonic { mnemonic, .. } => ParseErrorKind::UnknownMnemonic {
            mnemonic,
            suggestion: suggest(text, base),
        },
        ParseErrorKind::BadNumber { base, .. } => ParseErrorKind::BadNumber {
            base,
            suggestion: suggest(text, base),
        },
        other => other,
    })
}

fn parse_command_plain(
    text: &str,
    base: NumberBase,
) -> Result<(Option<u8>, &'static CommandSpec, Option<Value>), ParseErrorKind> {
    if text.is_empty() {
        return Err(ParseErrorKind::EmptyCommand);
    }
    // Outside a string: a letter the controller cannot take (inside one it
    // is reported when the string is read).
    let before_string = &text[..text.find('"').unwrap_or(text.len())];
    if let Some(c) = before_string.chars().find(|c| !c.is_ascii()) {
        return Err(ParseErrorKind::NotAscii(c));
    }
    if text.starts_with('@') {
        return Err(ParseErrorKind::IndirectAxis);
    }
    let digits = text.bytes().take_while(u8::is_ascii_digit).count();
    let axis = if digits == 0 {
        None
    } else {
        Some(
            text[..digits]
                .parse::<u8>()
                .map_err(|_| ParseErrorKind::AxisTooLarge)?,
        )
    };
    let rest = &text[digits..];
    let letters: String = rest.chars().take(2).collect();
    if letters.chars().count() < 2 || !letters.chars().all(|c| c.is_ascii_alphabetic()) {
        if rest[..rest.find('"').unwrap_or(rest.len())].contains(is_blank) {
            return Err(ParseErrorKind::Blank);
        }
        return Err(ParseErrorKind::NoMnemonic { suggestion: None });
    }
    let mnemonic = letters.to_ascii_uppercase();
    let spec = catalog::find(&mnemonic).ok_or(ParseErrorKind::UnknownMnemonic {
        mnemonic,
        suggestion: None,
    })?;
    let param = &rest[2..];
    let value = parse_value(param, base)?;
    Ok((axis, spec, value))
}

/// The parameter text after a mnemonic.
fn parse_value(text: &str, base: NumberBase) -> Result<Option<Value>, ParseErrorKind> {
    if text.is_empty() {
        return Ok(None);
    }
    if let Some(inner) = text.strip_prefix('"') {
        let Some(end) = inner.find('"') else {
            return Err(ParseErrorKind::UnterminatedString);
        };
        if end + 1 != inner.len() {
            return Err(ParseErrorKind::AfterString);
        }
        let content = &inner[..end];
        if let Some(c) = content.chars().find(|c| !c.is_ascii()) {
            return Err(ParseErrorKind::NotAscii(c));
        }
        return Ok(Some(Value::Text(content.to_string())));
    }
    if text.contains(is_blank) {
        return Err(ParseErrorKind::Blank);
    }
    if let Some(register) = text.strip_prefix('@') {
        let radix = match base {
            NumberBase::Decimal => 10,
            NumberBase::Hex => 16,
        };
        if register.is_empty() || !register.chars().all(|c| c.is_digit(radix)) {
            return Err(ParseErrorKind::BadRegister);
        }
        return u32::from_str_radix(register, radix)
            .map(|r| Some(Value::Register(r)))
            .map_err(|_| ParseErrorKind::BadRegister);
    }
    // Whether the command takes a number at all is the checker's to say.
    parse_number(text, base)
        .map(|n| Some(Value::Number(n)))
        .ok_or(ParseErrorKind::BadNumber {
            base,
            suggestion: None,
        })
}

/// A number literal in `base`: decimal `[-]digits[.digits][E[-]digits]`
/// (`.5`, `-.1` and `1.` too); hexadecimal `[-]digit[hexdigits]`, at most
/// 32 bits.
pub fn parse_number(text: &str, base: NumberBase) -> Option<Number> {
    let (negative, digits) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text),
    };
    match base {
        NumberBase::Decimal => {
            let (mantissa, exponent) = match digits.find(['e', 'E']) {
                Some(at) => (&digits[..at], Some(&digits[at + 1..])),
                None => (digits, None),
            };
            let (whole, fraction) = match mantissa.split_once('.') {
                Some((w, f)) => (w, Some(f)),
                None => (mantissa, None),
            };
            let all_digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
            let has_digit = !whole.is_empty() || fraction.is_some_and(|f| !f.is_empty());
            if !has_digit || !all_digits(whole) || !fraction.is_none_or(all_digits) {
                return None;
            }
            if let Some(exponent) = exponent {
                let e = exponent.strip_prefix(['-', '+']).unwrap_or(exponent);
                if e.is_empty() || !all_digits(e) {
                    return None;
                }
            }
            let value: f64 = text.parse().ok()?;
            let integer = fraction.is_none() && exponent.is_none();
            if !value.is_finite() || (integer && value.abs() > i64::MAX as f64) {
                return None;
            }
            Some(Number {
                text: text.to_ascii_uppercase(),
                value,
                integer,
            })
        }
        // Reals stay decimal in hex mode (hex reals are not described,
        // Ch13 HM; the simulator reads them so).
        NumberBase::Hex if digits.contains('.') => parse_number(text, NumberBase::Decimal),
        NumberBase::Hex => {
            let first = digits.chars().next()?;
            if !first.is_ascii_digit() || !digits.chars().all(|c| c.is_ascii_hexdigit()) {
                return None;
            }
            let significant = digits.trim_start_matches('0');
            if significant.len() > 8 {
                return None;
            }
            let magnitude = i64::from_str_radix(digits, 16).ok()?;
            let value = if negative { -magnitude } else { magnitude };
            Some(Number {
                text: text.to_ascii_uppercase(),
                value: value as f64,
                integer: true,
            })
        }
    }
}

/// A command that parses when a glyph the PDF text confuses is read the
/// other way: `G0` → `GO`, `N0` → `NO`, `1D10` → `1DI0`, `0D"…"` → `OD"…"`,
/// `1i150.0` → `1IL50.0`, `lsg.04` → `1SG.04` (digest §17 rule 1).
pub fn suggest(text: &str, base: NumberBase) -> Option<String> {
    let mut candidates = Vec::new();
    let starts = [text.to_string(), leading_one(text)];
    for start in starts.iter().filter(|s| !s.is_empty()) {
        let digits = start.bytes().take_while(u8::is_ascii_digit).count();
        // The mnemonic may start at the axis's last digit (an `O` read as
        // `0`, an `I` or `l` as `1`), or just after the axis.
        for cut in [digits, digits.saturating_sub(1)] {
            let (axis, rest) = start.split_at(cut);
            let slot: String = rest.chars().take(2).collect();
            if slot.chars().count() < 2 {
                continue;
            }
            let tail = &rest[slot.len()..];
            for letters in letter_readings(&slot) {
                candidates.push(format!("{axis}{letters}{tail}"));
            }
        }
    }
    candidates
        .into_iter()
        .filter(|c| c != text)
        .find(|c| parse_command_plain(c, base).is_ok())
        .map(|c| upper_outside_strings(&c))
}

/// `text` in upper case except inside strings.
fn upper_outside_strings(text: &str) -> String {
    let mut in_string = false;
    text.chars()
        .map(|c| {
            if c == '"' {
                in_string = !in_string;
            }
            if in_string { c } else { c.to_ascii_uppercase() }
        })
        .collect()
}

/// `l`, `I` or `i` at the start read as the digit 1 (`lsg.04`); empty if
/// the text does not start so.
fn leading_one(text: &str) -> String {
    match text.strip_prefix(['l', 'I', 'i']) {
        Some(rest) => format!("1{rest}"),
        None => String::new(),
    }
}

/// The ways two characters may read as a mnemonic: `0` as O, `1` as I or L.
fn letter_readings(slot: &str) -> Vec<String> {
    let choices = |c: char| -> Vec<char> {
        match c {
            '0' => vec!['O'],
            '1' => vec!['I', 'L'],
            'l' => vec!['L', 'I'],
            c if c.is_ascii_alphabetic() => vec![c.to_ascii_uppercase()],
            _ => vec![],
        }
    };
    let mut chars = slot.chars();
    let (Some(a), Some(b)) = (chars.next(), chars.next()) else {
        return Vec::new();
    };
    let mut readings = Vec::new();
    for x in choices(a) {
        for y in choices(b) {
            readings.push(format!("{x}{y}"));
        }
    }
    readings
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Line {
        parse_line(text, NumberBase::Decimal).unwrap_or_else(|e| panic!("{text}: {e}"))
    }

    fn error(text: &str) -> ParseError {
        parse_line(text, NumberBase::Decimal)
            .expect_err(text)
            .0
            .remove(0)
    }

    #[test]
    fn a_compound_line_carries_its_axis() {
        let line = parse("2MR1000,WS0.5,MR-1000,WS0.5,RP6");
        assert_eq!(line.commands.len(), 5);
        assert_eq!(line.axis_of(0), AxisRef::Given(2));
        assert_eq!(line.axis_of(1), AxisRef::Carried(2));
        assert_eq!(line.axis_of(3), AxisRef::Carried(2));
        assert_eq!(line.to_string(), "2MR1000,WS0.5,MR-1000,WS0.5,RP6");
        let line = parse("2MR1000,3MR-500,0WS0.3,2MR1000");
        assert_eq!(line.axis_of(2), AxisRef::Given(0));
        let line = parse("TP,RP999");
        assert_eq!(line.axis_of(0), AxisRef::Default);
    }

    #[test]
    fn lines_read_as_the_manual_writes_them() {
        assert_eq!(parse("1sg.04").to_string(), "1SG.04");
        assert_eq!(parse("al@100,AC,AR101").to_string(), "AL@100,AC,AR101");
        assert_eq!(
            parse("LU\"STATUS\", 2RL@0 ;status into ACC").to_string(),
            "LU\"STATUS\",2RL@0"
        );
        let spaced = parse("MD100, IN4, MJ101, NO, 1JR-3");
        assert!(spaced.commands[1].spaced && !spaced.commands[0].spaced);
        assert_eq!(spaced.to_string(), "MD100,IN4,MJ101,NO,1JR-3");
        // Strings keep their case, commas, semicolons and escapes.
        let text = parse("OT\"a, b; c %d \\n\"");
        assert_eq!(text.commands[0].text(), Some("a, b; c %d \\n"));
        assert_eq!(text.to_string(), "OT\"a, b; c %d \\n\"");
    }

    #[test]
    fn lookalike_letters_of_the_pdf_read_as_ascii() {
        // Cyrillic Т, В, К, С, Н and Greek Τ, Χ as printed in Ch3 and Ch8.
        assert_eq!(parse("1ТВ.2").to_string(), "1TB.2");
        assert_eq!(parse("1то.3").to_string(), "1TO.3");
        assert_eq!(parse("СН17").to_string(), "CH17");
        assert_eq!(parse("1ΤΧ").to_string(), "1TX");
        // Inside a string nothing is mapped, and non-ASCII is refused.
        let error = error("OT\"Тест\"");
        assert_eq!(error.kind, ParseErrorKind::NotAscii('Т'));
        // Spans point into the text as typed (Т is two bytes).
        let line = parse("1ТР,1TV");
        assert_eq!(line.commands[1].span, 6..9);
    }

    #[test]
    fn parameters_are_numbers_registers_or_strings() {
        let line = parse("1MA10.25,1WS.1,3SS-.1,AL1E3,1MR@10,LU\"POSITION\"");
        let values: Vec<Option<Value>> = line.commands.iter().map(|c| c.value.clone()).collect();
        assert_eq!(values[0], Some(Value::Number(Number::real(10.25, 2))));
        assert_eq!(line.commands[1].number(), Some(0.1));
        assert_eq!(line.commands[2].number(), Some(-0.1));
        assert_eq!(line.commands[3].number(), Some(1000.0));
        assert!(!match &values[3] {
            Some(Value::Number(n)) => n.is_integer(),
            _ => true,
        });
        assert_eq!(values[4], Some(Value::Register(10)));
        assert_eq!(values[5], Some(Value::Text("POSITION".into())));
        // No parameter: the controller takes 0 (Ch2).
        assert_eq!(parse("1MA").commands[0].number(), Some(0.0));
        assert_eq!(parse("1MA").commands[0].value, None);
    }

    #[test]
    fn hex_mode_reads_hex_integers() {
        let line = parse_line("1MR0FF,AL-10,AN0FFFFFFFF", NumberBase::Hex).expect("hex");
        assert_eq!(line.commands[0].number(), Some(255.0));
        assert_eq!(line.commands[1].number(), Some(-16.0));
        assert_eq!(line.commands[2].number(), Some(f64::from(u32::MAX)));
        assert_eq!(line.to_string(), "1MR0FF,AL-10,AN0FFFFFFFF");
        // Reals stay decimal.
        let real = parse_line("1WS1.5", NumberBase::Hex).expect("a real");
        assert_eq!(real.commands[0].number(), Some(1.5));
        // A–F first needs a leading 0; at most 32 bits.
        for bad in ["1MRFF", "AL123456789"] {
            assert!(
                matches!(
                    parse_line(bad, NumberBase::Hex).expect_err(bad).0[0].kind,
                    ParseErrorKind::BadNumber {
                        base: NumberBase::Hex,
                        ..
                    }
                ),
                "{bad}"
            );
        }
        // The same text is decimal outside hex mode.
        assert!(parse_line("1MR0FF", NumberBase::Decimal).is_err());
    }

    #[test]
    fn a_line_is_written_in_the_base_of_the_interface() {
        let line = parse("MD10,1MA1000,MR-255,WS0.5,AL@100,OT\"%d\",TM-1,AL171");
        assert_eq!(line.written_in(NumberBase::Decimal), line.to_string());
        assert_eq!(
            line.written_in(NumberBase::Hex),
            "MD0A,1MA3E8,MR-0FF,WS0.5,AL@100,OT\"%d\",TM-1,AL0AB"
        );
        // What is written in hex reads back as the same line there.
        let again = parse_line(&line.written_in(NumberBase::Hex), NumberBase::Hex).expect("hex");
        let values = |l: &Line| l.commands.iter().map(Command::number).collect::<Vec<_>>();
        assert_eq!(values(&again), values(&line));
    }

    #[test]
    fn what_does_not_parse_is_named_with_its_place() {
        let e = error("1MN,,1TP");
        assert_eq!(e.kind, ParseErrorKind::EmptyCommand);
        assert_eq!(e.command, Some(1));
        assert_eq!(
            e.to_string(),
            "command 2 is empty (two commas, or one at the end)"
        );
        let e = error("@1MR100");
        assert_eq!(e.kind, ParseErrorKind::IndirectAxis);
        let e = error("1XX100");
        assert!(e.to_string().contains("XX is not an MCCL command"), "{e}");
        assert_eq!(error("1MR 100").kind, ParseErrorKind::Blank);
        assert_eq!(error("OT\"abc").kind, ParseErrorKind::UnterminatedString);
        assert_eq!(error("OT\"abc\"x").kind, ParseErrorKind::AfterString);
        assert_eq!(error("1MR@").kind, ParseErrorKind::BadRegister);
        assert_eq!(error("300MR1").kind, ParseErrorKind::AxisTooLarge);
        assert_eq!(error("  ;only a comment").kind, ParseErrorKind::Empty);
        assert_eq!(error("").kind, ParseErrorKind::Empty);
        // Every bad command is listed.
        let all = parse_line("1XX,2MR,3YY", NumberBase::Decimal).expect_err("two");
        assert_eq!(all.0.len(), 2);
        assert_eq!(all.0[1].command, Some(2));
        assert_eq!(all.0[1].span, 8..11);
    }

    #[test]
    fn glyphs_the_pdf_confuses_get_a_suggestion() {
        for (typed, meant) in [
            ("1G0", "1GO"),
            ("N0", "NO"),
            ("5D10", "5DI0"),
            ("1D11", "1DI1"),
            ("0D\"x %f\"", "OD\"x %f\""),
            ("1i150.0", "1IL50.0"),
            ("lsg.04", "1SG.04"),
            ("20B1.5", "2OB1.5"),
        ] {
            let e = error(typed);
            assert!(
                e.to_string().contains(&format!("did you mean `{meant}`")),
                "{typed}: {e}"
            );
        }
    }

    #[test]
    fn formatting_then_parsing_gives_the_same_line() {
        for text in [
            "2MR1000,WS0.5,MR-1000,WS0.5,RP6",
            "MD10,1MR1000,1WS0.100000,1TP,BK\"wait\",RP1",
            "GT100,AR@100,1VM,1DI0,1GO",
            "1TP.3,TT.3",
        ] {
            let line = parse(text);
            assert_eq!(parse(&line.to_string()), line, "{text}");
        }
    }
}
