//! Reading a command line (manual Ch2 "MCCL Command Syntax", Ch4, Ch11):
//! `[axis]MM[parameter]` commands separated by commas, the parameter a
//! number, `@register` or `"string"`.
//!
//! The whole line is read when its CR arrives, in the number base in force
//! then (Ch13: DM and HM "cannot be in the same command string", which is
//! what reading a line at once implies). In hexadecimal mode an integer is
//! hex digits starting with a decimal digit (`0FF`); a number with a
//! decimal point stays a decimal real (hex reals are not described).
//!
//! Choices where the manual is silent (also in [`super::choices`]): case
//! does not matter (the manual's own examples are in lower case: `1sg.04`);
//! blanks and tabs around commands and parameters are skipped (its
//! examples put spaces after commas); an empty command (`1MN,,1MF`, a
//! trailing comma) is a bad format (2).

use super::commands::{self, CommandSpec};
use super::errors::Code;

/// The number base of parameters and replies (DM / HM).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Radix {
    #[default]
    Decimal,
    Hex,
}

/// A command's parameter as typed.
#[derive(Debug, Clone, PartialEq)]
pub enum Param {
    None,
    /// An integer (no decimal point or exponent, Ch11 AL).
    Int(i64),
    Real(f64),
    /// `@n`: the value of register n.
    Register(u32),
    Text(String),
}

/// One command of a line.
#[derive(Debug, Clone, PartialEq)]
pub struct Command {
    /// The axis typed before the mnemonic, if any.
    pub axis: Option<u32>,
    pub spec: &'static CommandSpec,
    pub param: Param,
    /// The command as the controller keeps it: the axis, the mnemonic in
    /// upper case and the parameter as typed, without blanks (what `TM`
    /// lists and an error report names).
    pub text: String,
}

impl Command {
    pub fn mnemonic(&self) -> &'static str {
        self.spec.mnemonic
    }

    pub fn is(&self, mnemonic: &str) -> bool {
        self.spec.mnemonic == mnemonic
    }
}

/// Why a line could not be read: the code and the command it stopped at.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LexError {
    pub code: Code,
    pub command: String,
}

/// Read every command of `line` in `radix`.
pub fn lex(line: &str, radix: Radix) -> Result<Vec<Command>, LexError> {
    let mut cursor = Cursor {
        bytes: line.as_bytes(),
        at: 0,
    };
    let mut commands = Vec::new();
    loop {
        let start = cursor.at;
        let command = read_command(&mut cursor, radix).map_err(|code| LexError {
            code,
            command: cursor.segment_from(start),
        })?;
        commands.push(command);
        cursor.skip_blanks();
        match cursor.peek() {
            None => return Ok(commands),
            Some(b',') => cursor.at += 1,
            Some(_) => {
                return Err(LexError {
                    code: Code::BAD_FORMAT,
                    command: cursor.segment_from(start),
                });
            }
        }
    }
}

struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Cursor<'_> {
    fn peek(&self) -> Option<u8> {
        self.bytes.get(self.at).copied()
    }

    fn skip_blanks(&mut self) {
        while matches!(self.peek(), Some(b' ' | b'\t')) {
            self.at += 1;
        }
    }

    fn take_while(&mut self, keep: impl Fn(u8) -> bool) -> &str {
        let start = self.at;
        while self.peek().is_some_and(&keep) {
            self.at += 1;
        }
        std::str::from_utf8(&self.bytes[start..self.at]).unwrap_or_default()
    }

    /// The command from `start` to the next comma outside quotes, trimmed:
    /// what an error names.
    fn segment_from(&self, start: usize) -> String {
        let mut end = start;
        let mut quoted = false;
        while let Some(&b) = self.bytes.get(end) {
            match b {
                b'"' => quoted = !quoted,
                b',' if !quoted => break,
                _ => {}
            }
            end += 1;
        }
        String::from_utf8_lossy(self.bytes.get(start..end).unwrap_or_default())
            .trim()
            .to_string()
    }
}

fn read_command(cursor: &mut Cursor<'_>, radix: Radix) -> Result<Command, Code> {
    cursor.skip_blanks();
    match cursor.peek() {
        None | Some(b',') => return Err(Code::BAD_FORMAT),
        // Ch4: "does not support the use of the '@' sign in front of an axis".
        Some(b'@') => return Err(Code::BAD_FORMAT),
        _ => {}
    }
    let digits = cursor.take_while(|b| b.is_ascii_digit()).to_string();
    let axis = if digits.is_empty() {
        None
    } else {
        // An axis too long for a number is no axis there is (−15 later).
        Some(digits.parse::<u32>().unwrap_or(u32::MAX))
    };
    let letters = cursor.take_while(|b| b.is_ascii_alphabetic()).to_string();
    if letters.len() < 2 {
        return Err(Code::UNRECOGNIZED);
    }
    let (mnemonic, rest) = letters.split_at(2);
    let mnemonic = mnemonic.to_ascii_uppercase();
    let spec = commands::find(&mnemonic).ok_or(Code::UNRECOGNIZED)?;
    if !rest.is_empty() {
        // A parameter starting with a letter is no number: `1MAFF` in HM
        // too, as hex must start with a digit (Ch13 HM).
        return Err(Code::BAD_FORMAT);
    }
    let (param, source) = read_param(cursor, radix)?;
    let mut text = axis.map(|a| a.to_string()).unwrap_or_default();
    text.push_str(&mnemonic);
    text.push_str(&source);
    Ok(Command {
        axis,
        spec,
        param,
        text,
    })
}

/// The parameter and its source text.
fn read_param(cursor: &mut Cursor<'_>, radix: Radix) -> Result<(Param, String), Code> {
    cursor.skip_blanks();
    match cursor.peek() {
        None | Some(b',') => Ok((Param::None, String::new())),
        Some(b'"') => {
            cursor.at += 1;
            let text = cursor.take_while(|b| b != b'"').to_string();
            if cursor.peek() != Some(b'"') {
                return Err(Code::BAD_FORMAT);
            }
            cursor.at += 1;
            let source = format!("\"{text}\"");
            Ok((Param::Text(text), source))
        }
        Some(b'@') => {
            cursor.at += 1;
            let digits = cursor.take_while(|b| b.is_ascii_digit()).to_string();
            if digits.is_empty() {
                return Err(Code::BAD_FORMAT);
            }
            let register = digits.parse::<u32>().unwrap_or(u32::MAX);
            Ok((Param::Register(register), format!("@{digits}")))
        }
        Some(b) if b.is_ascii_digit() || matches!(b, b'-' | b'+' | b'.') => {
            let token = cursor
                .take_while(|b| b.is_ascii_alphanumeric() || matches!(b, b'-' | b'+' | b'.'))
                .to_string();
            let value = number(&token, radix).ok_or(Code::BAD_FORMAT)?;
            Ok((value, token))
        }
        Some(_) => Err(Code::BAD_FORMAT),
    }
}

/// A number as typed: `-12`, `.5`, `1e3`, or in hex mode `0FF`, `-10`.
pub fn number(token: &str, radix: Radix) -> Option<Param> {
    if radix == Radix::Hex && !token.contains('.') {
        return hex_integer(token);
    }
    let (sign, body) = split_sign(token);
    let (mantissa, exponent) = match body.find(['e', 'E']) {
        Some(i) => (&body[..i], Some(&body[i + 1..])),
        None => (body, None),
    };
    let (whole, fraction) = match mantissa.split_once('.') {
        Some((whole, fraction)) => (whole, Some(fraction)),
        None => (mantissa, None),
    };
    let digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
    let has_digits = !whole.is_empty() || fraction.is_some_and(|f| !f.is_empty());
    if !has_digits || !digits(whole) || !fraction.is_none_or(digits) {
        return None;
    }
    if let Some(exponent) = exponent {
        let (_, exp_digits) = split_sign(exponent);
        if exp_digits.is_empty() || !digits(exp_digits) {
            return None;
        }
    }
    if fraction.is_none() && exponent.is_none() {
        let magnitude = whole.parse::<i64>().ok()?;
        return Some(Param::Int(sign * magnitude));
    }
    let value = body.parse::<f64>().ok().filter(|v| v.is_finite())?;
    Some(Param::Real(sign as f64 * value))
}

fn split_sign(token: &str) -> (i64, &str) {
    match token.as_bytes().first() {
        Some(b'-') => (-1, &token[1..]),
        Some(b'+') => (1, &token[1..]),
        _ => (1, token),
    }
}

/// Ch13 HM: hex digits, the first a decimal digit; a 32-bit word, so
/// `0FFFFFFFF` is −1.
fn hex_integer(token: &str) -> Option<Param> {
    let (sign, body) = split_sign(token);
    if !body.as_bytes().first()?.is_ascii_digit() || !body.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let magnitude = u64::from_str_radix(body, 16).ok()?;
    let word = u32::try_from(magnitude).ok()?;
    Some(Param::Int(sign * i64::from(word as i32)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn read(line: &str) -> Vec<(Option<u32>, &'static str, Param, String)> {
        lex(line, Radix::Decimal)
            .unwrap_or_else(|e| panic!("{line}: {e:?}"))
            .into_iter()
            .map(|c| (c.axis, c.spec.mnemonic, c.param, c.text))
            .collect()
    }

    fn error(line: &str, radix: Radix) -> (i32, String) {
        let e = lex(line, radix).expect_err(line);
        (e.code.0, e.command)
    }

    #[test]
    fn the_manuals_compound_line_reads_as_five_commands() {
        // Ch2: the axis is given once; WS0.5 is a real, RP6 an integer.
        let commands = read("2MR1000,WS0.5,MR-1000,WS0.5,RP6");
        assert_eq!(
            commands,
            [
                (Some(2), "MR", Param::Int(1000), "2MR1000".into()),
                (None, "WS", Param::Real(0.5), "WS0.5".into()),
                (None, "MR", Param::Int(-1000), "MR-1000".into()),
                (None, "WS", Param::Real(0.5), "WS0.5".into()),
                (None, "RP", Param::Int(6), "RP6".into()),
            ]
        );
    }

    #[test]
    fn lower_case_spaces_strings_and_registers_as_the_manual_writes_them() {
        assert_eq!(
            read("1sg.04"),
            [(Some(1), "SG", Param::Real(0.04), "1SG.04".into())]
        );
        assert_eq!(
            read("LU\"STATUS\", 2RL@0"),
            [
                (
                    None,
                    "LU",
                    Param::Text("STATUS".into()),
                    "LU\"STATUS\"".into()
                ),
                (Some(2), "RL", Param::Register(0), "2RL@0".into()),
            ]
        );
        assert_eq!(
            read("MD100, IN4, MJ101, NO, 1JR-3").len(),
            5,
            "Ch4's multitasking example"
        );
        assert_eq!(
            read("OT\"a, b\"")[0].2,
            Param::Text("a, b".into()),
            "a comma inside a string"
        );
        assert_eq!(read("3SS-.1")[0].2, Param::Real(-0.1));
        assert_eq!(read("AL1e3")[0].2, Param::Real(1000.0));
        assert_eq!(read("1TP")[0].2, Param::None);
    }

    #[test]
    fn hex_mode_reads_integers_in_hex_and_reals_in_decimal() {
        let commands = lex("1MA0FF,TM-1,AL0FFFFFFFF,1WS.5", Radix::Hex).expect("reads");
        let params: Vec<_> = commands.into_iter().map(|c| c.param).collect();
        assert_eq!(
            params,
            [
                Param::Int(255),
                Param::Int(-1),
                Param::Int(-1),
                Param::Real(0.5)
            ]
        );
        // Ch13: a hex number starting with A-F must be preceded by 0.
        assert_eq!(error("1MAFF", Radix::Hex), (2, "1MAFF".into()));
        assert_eq!(error("1MA0FFFFFFFFF", Radix::Hex).0, 2, "over 32 bits");
    }

    #[test]
    fn unknown_mnemonics_are_1_and_bad_parameters_2() {
        assert_eq!(error("1XX5", Radix::Decimal), (1, "1XX5".into()));
        assert_eq!(error("1M", Radix::Decimal), (1, "1M".into()));
        assert_eq!(error("1MN,12", Radix::Decimal), (1, "12".into()));
        assert_eq!(error("1MA1.2.3", Radix::Decimal), (2, "1MA1.2.3".into()));
        assert_eq!(error("1MAx", Radix::Decimal).0, 2);
        assert_eq!(error("1MA--5", Radix::Decimal).0, 2);
        assert_eq!(error("OT\"open", Radix::Decimal), (2, "OT\"open".into()));
        assert_eq!(error("1MA@", Radix::Decimal).0, 2);
        assert_eq!(error("@1MA5", Radix::Decimal).0, 2, "@ before the axis");
        assert_eq!(error("1MN,,1MF", Radix::Decimal), (2, "".into()));
        assert_eq!(error("1MN,", Radix::Decimal).0, 2);
        assert_eq!(error("1MA1000 5", Radix::Decimal).0, 2);
        assert_eq!(error("1MA1e", Radix::Decimal).0, 2);
        assert_eq!(error("ALinf", Radix::Decimal).0, 2);
    }

    proptest! {
        #[test]
        fn no_line_panics_the_lexer(line in "[ -~]{0,40}") {
            let _ = lex(&line, Radix::Decimal);
            let _ = lex(&line, Radix::Hex);
        }

        #[test]
        fn canonical_text_reads_back_to_the_same_commands(
            axis in proptest::option::of(0u32..9),
            mnemonic in proptest::sample::select(vec!["MA", "MR", "WS", "AL", "TP", "OT", "RP"]),
            param in prop_oneof![
                Just(String::new()),
                (-100_000i64..100_000).prop_map(|n| n.to_string()),
                (-1000.0f64..1000.0).prop_map(|x| format!("{x:.3}")),
                (0u32..1000).prop_map(|r| format!("@{r}")),
                "[a-z ,%]{0,8}".prop_map(|s| format!("\"{s}\"")),
            ],
        ) {
            let line = format!("{}{}{}", axis.map(|a| a.to_string()).unwrap_or_default(), mnemonic.to_lowercase(), param);
            let first = lex(&line, Radix::Decimal).expect("reads");
            let text: Vec<_> = first.iter().map(|c| c.text.clone()).collect();
            let again = lex(&text.join(","), Radix::Decimal).expect("reads again");
            prop_assert_eq!(first, again);
        }
    }
}
