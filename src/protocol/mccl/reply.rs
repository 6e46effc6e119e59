//! What the controller sends back for a line (digest §3.3): the echo of the
//! line, the output of its reporting commands, then the prompt. An error is
//! `?` and a code (Ch2: "the controller will echo a question mark
//! character, followed by an error code"; codes in Ch14), possibly with
//! the offending command. A Tell reply is `AA value`: the 2-digit axis
//! (channel, register) field, blanks, the value, with as many decimals as
//! the precision parameter asked for (Ch8); after `HM` values are
//! hexadecimal (status words as 8 lower-case digits, Ch13).
//!
//! [`AnswerRule`] tells the device layer when the answer is complete;
//! [`read_reply`] reads a complete answer against the line sent.

use std::fmt;

use super::catalog::{Blocks, Output, Param};
use super::line::{Command, Line, NumberBase};
use super::profile::{Echo, LinkProfile, LinkState, PromptPer};
use super::status::StatusSelector;
use crate::protocol::wire::{Frame, ReplyRule, Verdict};

/// One row of the Ch14 error table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ErrorCode {
    pub code: i32,
    pub meaning: &'static str,
}

/// Ch14 "Controller Error Codes" (−11 and −12 are not listed).
#[rustfmt::skip]
pub const ERROR_CODES: &[ErrorCode] = &[
    ErrorCode { code: 0, meaning: "No error" },
    ErrorCode { code: 1, meaning: "Unrecognized command" },
    ErrorCode { code: 2, meaning: "Bad command format" },
    ErrorCode { code: 3, meaning: "I/O error" },
    ErrorCode { code: 4, meaning: "Command string too long" },
    ErrorCode { code: -1, meaning: "Command Parameter Error" },
    ErrorCode { code: -2, meaning: "Command Code Invalid" },
    ErrorCode { code: -3, meaning: "Negative Repeat Count" },
    ErrorCode { code: -4, meaning: "Macro Define Command Not First" },
    ErrorCode { code: -5, meaning: "Macro Number Out of Range" },
    ErrorCode { code: -6, meaning: "Macro Doesn't Exist" },
    ErrorCode { code: -7, meaning: "Command Canceled by User" },
    ErrorCode { code: -8, meaning: "Contour Path Command Not First" },
    ErrorCode { code: -9, meaning: "Contour Path Command Parameter Invalid" },
    ErrorCode { code: -10, meaning: "Contour Path Command Doesn't Specify an AXIS" },
    ErrorCode { code: -13, meaning: "Axis error (over travel error, max. following error exceeded)" },
    ErrorCode { code: -14, meaning: "No axis specified" },
    ErrorCode { code: -15, meaning: "Axis not assigned" },
    ErrorCode { code: -16, meaning: "Axis already assigned" },
    ErrorCode { code: -17, meaning: "Axis duplicate assigned" },
    ErrorCode { code: -18, meaning: "Insufficient memory" },
    ErrorCode { code: -19, meaning: "Unrecognized variable name" },
    ErrorCode { code: -20, meaning: "Invalid background task ID" },
    ErrorCode { code: -21, meaning: "Command not supported" },
];

/// The Ch14 meaning of `code`.
pub fn error_meaning(code: i32) -> Option<&'static str> {
    ERROR_CODES
        .iter()
        .find(|e| e.code == code)
        .map(|e| e.meaning)
}

/// An error reply: `?` and a code, maybe followed by the offending command
/// (Ch14: "Many error code reports will not only include the error code
/// but also the offending command"; the example figure is lost, so any
/// text after the code is kept as it came).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ErrorReply {
    pub code: i32,
    /// What followed the code, trimmed (the offending command, if shown).
    pub detail: String,
}

impl ErrorReply {
    /// Read a line starting with `?` (blanks allowed before the code).
    pub fn parse(line: &str) -> Option<ErrorReply> {
        let rest = line.trim().strip_prefix('?')?.trim_start();
        let sign = usize::from(rest.starts_with(['-', '+']));
        let digits = rest[sign..].bytes().take_while(u8::is_ascii_digit).count();
        if digits == 0 {
            return None;
        }
        let code = rest[..sign + digits].parse().ok()?;
        Some(ErrorReply {
            code,
            detail: rest[sign + digits..].trim().to_string(),
        })
    }

    pub fn meaning(&self) -> &'static str {
        error_meaning(self.code).unwrap_or("a code Ch14 does not list")
    }

    /// The reply as a technician reads it back: `?-6 MC10`.
    pub fn text(&self) -> String {
        if self.detail.is_empty() {
            format!("?{}", self.code)
        } else {
            format!("?{} {}", self.code, self.detail)
        }
    }
}

impl fmt::Display for ErrorReply {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "error {} ({}, Ch14)", self.text(), self.meaning())
    }
}

/// A value a Tell command reported.
#[derive(Debug, Clone, PartialEq)]
pub enum Quantity {
    Integer(i64),
    /// Printed with decimals (`121.025`).
    Real {
        value: f64,
        text: String,
    },
}

impl Quantity {
    pub fn as_f64(&self) -> f64 {
        match self {
            Quantity::Integer(n) => *n as f64,
            Quantity::Real { value, .. } => *value,
        }
    }

    /// The value rounded to an integer.
    pub fn rounded(&self) -> i64 {
        match self {
            Quantity::Integer(n) => *n,
            Quantity::Real { value, .. } => value.round() as i64,
        }
    }

    /// Decimals printed (0 for an integer).
    pub fn decimals(&self) -> usize {
        match self {
            Quantity::Integer(_) => 0,
            Quantity::Real { text, .. } => text.split_once('.').map_or(0, |(_, f)| f.len()),
        }
    }
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Quantity::Integer(n) => write!(f, "{n}"),
            Quantity::Real { text, .. } => f.write_str(text),
        }
    }
}

/// One Tell reply line.
#[derive(Debug, Clone, PartialEq)]
pub struct Told {
    /// The 2-digit field before the value (axis, channel, register), when
    /// printed: the Ch8 introduction shows bare values (`123`), every
    /// other example the field (`01 121.025`).
    pub field: Option<u8>,
    pub value: Quantity,
}

/// Read a Tell reply line in `base`.
pub fn parse_told(line: &str, base: NumberBase) -> Result<Told, String> {
    let line = line.trim();
    let (field, value) = match line.split_once([' ', '\t']) {
        Some((field, value)) => {
            let digits = field.len() == 2 && field.bytes().all(|b| b.is_ascii_digit());
            if !digits {
                return Err(format!(
                    "`{line}`: a reply is a 2-digit field, blanks and a value"
                ));
            }
            (field.parse::<u8>().ok(), value.trim())
        }
        None => (None, line),
    };
    let value = parse_quantity(value, base).ok_or_else(|| match base {
        NumberBase::Decimal => format!("`{line}`: `{value}` is not a decimal number"),
        NumberBase::Hex => format!(
            "`{line}`: `{value}` is not a hexadecimal number of at most 8 digits (hex mode)"
        ),
    })?;
    Ok(Told { field, value })
}

fn parse_quantity(text: &str, base: NumberBase) -> Option<Quantity> {
    let (negative, digits) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text),
    };
    match base {
        NumberBase::Decimal => {
            let (whole, fraction) = match digits.split_once('.') {
                Some((w, f)) => (w, Some(f)),
                None => (digits, None),
            };
            let all_digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
            match fraction {
                None if all_digits(whole) => text.parse().ok().map(Quantity::Integer),
                Some(f) if all_digits(f) && (whole.is_empty() || all_digits(whole)) => {
                    let value: f64 = text.parse().ok()?;
                    value.is_finite().then(|| Quantity::Real {
                        value,
                        text: text.to_string(),
                    })
                }
                _ => None,
            }
        }
        // A value printed with decimals stays decimal in hex mode (hex
        // reals are not described, Ch13 HM).
        NumberBase::Hex if digits.contains('.') => parse_quantity(text, NumberBase::Decimal),
        NumberBase::Hex => {
            if digits.is_empty()
                || digits.len() > 8
                || !digits.bytes().all(|b| b.is_ascii_hexdigit())
            {
                return None;
            }
            // The 32-bit word as the controller holds it: a negative
            // position comes back as `fffffc18`.
            let word = i64::from(u32::from_str_radix(digits, 16).ok()? as i32);
            Some(Quantity::Integer(if negative { -word } else { word }))
        }
    }
}

/// What one reporting command of the line printed.
#[derive(Debug, Clone, PartialEq)]
pub enum Printed {
    Value(Told),
    Text(Vec<String>),
}

/// The output of one reporting command.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// The command's index on the line; `None` where the line repeats,
    /// jumps or calls macros, so that which command printed a line cannot
    /// be told.
    pub command: Option<usize>,
    pub printed: Printed,
}

/// A complete answer to a line.
#[derive(Debug, Clone, PartialEq)]
pub struct Reply {
    /// Reply lines, echo and prompts taken out.
    pub lines: Vec<String>,
    pub prompts: usize,
    pub error: Option<ErrorReply>,
    pub reports: Vec<Report>,
}

/// Why an answer is not what the line sent calls for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ReplyProblem {
    /// The first line is not the echo of the line sent.
    NoEcho { got: String },
    /// The answer ended without a prompt (and without an error).
    NoPrompt,
    /// Fewer reply lines than the line's reporting commands print.
    Missing { command: String },
    /// More lines than its reporting commands print.
    Unexpected { line: String },
    /// A reply line that is not a value of its command.
    BadValue { command: String, reason: String },
    /// Blanks where the answer has none: around the echo, before the
    /// prompt, a line of them (a corrupted line end).
    Damaged { got: String },
}

impl fmt::Display for ReplyProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReplyProblem::NoEcho { got } => {
                write!(
                    f,
                    "the answer starts `{got}`, not with the echo of the line"
                )
            }
            ReplyProblem::NoPrompt => f.write_str("the answer has no prompt at its end"),
            ReplyProblem::Missing { command } => write!(f, "no reply line for {command}"),
            ReplyProblem::Unexpected { line } => {
                write!(f, "`{line}` answers no reporting command of the line")
            }
            ReplyProblem::BadValue { command, reason } => write!(f, "{command}: {reason}"),
            ReplyProblem::Damaged { got } => write!(
                f,
                "`{got}` is neither the exact echo, a reply line nor the prompt alone: unreadable"
            ),
        }
    }
}

/// Whether the commands of `line` run once each, in order, so that reply
/// lines belong to its reporting commands in turn: no repeat, jump,
/// condition, break or macro call, and nothing stored or handed to a task.
pub fn runs_straight(line: &Line) -> bool {
    !line.defines_macro()
        && !line.is_task()
        && line.commands.iter().all(|c| {
            matches!(c.spec.blocks, Blocks::No | Blocks::Waits)
                && !matches!(
                    c.mnemonic(),
                    "BK" | "DF" | "DN" | "IB" | "IC" | "IE" | "IF" | "IG" | "IN" | "IS" | "IU"
                )
        })
}

/// The decimals a precision parameter asks for (Ch8: "the tenths digit
/// will be interpreted as the number of decimal digits"), if it is written
/// out.
pub fn precision_of(command: &Command) -> Option<usize> {
    let n = command.number()?;
    match command.spec.param {
        Param::Precision => Some(((n * 10.0).floor() as i64).clamp(0, 9) as usize),
        // `TRn.p` (Ch4): the register prints as it is (a real with six
        // decimals) unless a precision is asked for.
        Param::RegisterPrecision => {
            let tenths = (n.fract() * 10.0).round() as i64;
            (tenths > 0).then(|| tenths.clamp(0, 9) as usize)
        }
        _ => None,
    }
}

/// Read a value line as the output of `command`, checking its decimals
/// against the precision asked for and a status bit for 0 or 1.
fn read_value(command: &Command, line: &str, base: NumberBase) -> Result<Told, ReplyProblem> {
    let bad = |reason: String| ReplyProblem::BadValue {
        command: command.to_string(),
        reason,
    };
    let told = parse_told(line, base).map_err(bad)?;
    if base == NumberBase::Decimal
        && let Some(decimals) = precision_of(command)
        && told.value.decimals() != decimals
    {
        return Err(bad(format!(
            "`{}` has {} decimals, the precision asks for {decimals}",
            line.trim(),
            told.value.decimals()
        )));
    }
    if command.mnemonic() == "TS"
        && let Some(StatusSelector::Bit(..)) = command
            .number()
            .and_then(|n| StatusSelector::from_parameter(n as i64))
        && !matches!(told.value, Quantity::Integer(0 | 1))
    {
        return Err(bad(format!("`{}`: a status bit reads 1 or 0", line.trim())));
    }
    Ok(told)
}

/// Read the answer `frames` to `line` (sent as `sent`, without its CR) on an
/// interface in `state` with `profile`.
pub fn read_reply(
    line: &Line,
    sent: &str,
    state: &LinkState,
    profile: &LinkProfile,
    frames: &[Frame],
) -> Result<Reply, ReplyProblem> {
    let mut texts = frames
        .iter()
        .map(|f| String::from_utf8_lossy(f).into_owned());
    let mut lines = Vec::new();
    let mut prompts = 0;
    // Ch2: the controller echoes each character as it was typed, so the
    // echo is the line exactly, and the prompt is one character: blanks
    // around either are damage (a corrupted line end), never success,
    // unless the line prints text of its own (`OT" "` prints blanks).
    let prints_text =
        !runs_straight(line) || line.commands.iter().any(|c| c.spec.output == Output::Text);
    let damaged = |got: &str| ReplyProblem::Damaged {
        got: got.to_string(),
    };
    if state.echo == Echo::Line {
        let first = texts.next().unwrap_or_default();
        let Some(rest) = first.strip_prefix(sent) else {
            return Err(ReplyProblem::NoEcho { got: first });
        };
        // An answer may follow the echo on its line (`1XX?1`).
        if !rest.is_empty() {
            if rest.trim().is_empty() {
                return Err(damaged(&first));
            }
            lines.push(rest.trim().to_string());
        }
    }
    let prompt_char = state.prompt_after(line, profile);
    let prompt = prompt_char.map(|p| vec![p]);
    for text in texts {
        if prompt.as_deref() == Some(text.as_bytes()) {
            prompts += 1;
            continue;
        }
        // A line left without its end runs into the prompt (`OT"x"`
        // prints `x>`).
        let glued = match prompt_char.map(char::from) {
            Some(p) if text.ends_with(p) => {
                prompts += 1;
                text[..text.len() - p.len_utf8()].to_string()
            }
            _ => text.clone(),
        };
        if glued.trim().is_empty() {
            if !prints_text {
                return Err(damaged(&text));
            }
            continue;
        }
        lines.push(glued.trim().to_string());
    }
    let error_at = lines.iter().position(|l| ErrorReply::parse(l).is_some());
    let error = error_at.and_then(|at| {
        let mut error = ErrorReply::parse(&lines[at])?;
        // Lines after the code belong to the error (the offending command).
        let more: Vec<&str> = lines[at + 1..].iter().map(String::as_str).collect();
        if !more.is_empty() {
            let joined = [error.detail.as_str()]
                .into_iter()
                .chain(more)
                .filter(|s| !s.is_empty())
                .collect::<Vec<_>>()
                .join(" ");
            error.detail = joined;
        }
        Some(error)
    });
    let output = &lines[..error_at.unwrap_or(lines.len())];
    if error.is_none() && prompt_char.is_some() && prompts == 0 {
        return Err(ReplyProblem::NoPrompt);
    }
    let reports = if runs_straight(line) {
        assign(line, state, output, error.is_some())?
    } else {
        output
            .iter()
            .map(|l| Report {
                command: None,
                printed: match parse_told(l, state.base) {
                    Ok(told) => Printed::Value(told),
                    Err(_) => Printed::Text(vec![l.clone()]),
                },
            })
            .collect()
    };
    Ok(Reply {
        lines,
        prompts,
        error,
        reports,
    })
}

/// Give each reporting command of a straight line its lines: one for a
/// value, the rest for text. After an error the line stopped somewhere, so
/// missing lines are no fault then.
fn assign(
    line: &Line,
    state: &LinkState,
    output: &[String],
    stopped: bool,
) -> Result<Vec<Report>, ReplyProblem> {
    let printing: Vec<(usize, &Command)> = line
        .commands
        .iter()
        .enumerate()
        .filter(|(_, c)| c.spec.output != Output::Nothing)
        .collect();
    let values = printing
        .iter()
        .filter(|(_, c)| c.spec.output == Output::Value)
        .count();
    let texts = printing.len() - values;
    let text_lines = output.len().saturating_sub(values);
    let mut rest = output;
    let mut reports = Vec::new();
    let mut first_text = true;
    for (index, command) in printing {
        let base = state.output_base(line, index);
        match command.spec.output {
            Output::Value => {
                let Some((first, tail)) = rest.split_first() else {
                    if stopped {
                        break;
                    }
                    return Err(ReplyProblem::Missing {
                        command: command.to_string(),
                    });
                };
                rest = tail;
                reports.push(Report {
                    command: Some(index),
                    printed: Printed::Value(read_value(command, first, base)?),
                });
            }
            Output::Text | Output::Nothing => {
                // With several texts on one line, where one ends is not
                // known: the first takes them all.
                let take = if first_text {
                    text_lines.min(rest.len())
                } else {
                    0
                };
                first_text = false;
                let (text, tail) = rest.split_at(take);
                rest = tail;
                reports.push(Report {
                    command: if texts == 1 { Some(index) } else { None },
                    printed: Printed::Text(text.to_vec()),
                });
            }
        }
    }
    if let Some(extra) = rest.first() {
        return Err(ReplyProblem::Unexpected {
            line: extra.clone(),
        });
    }
    Ok(reports)
}

/// How the device layer tells the answer to a line from what comes before
/// and after it: the echo of the line first (anything before it is late
/// output of something earlier), then reply lines, complete at the prompt
/// (the last one expected where prompts come per command). After an error
/// the line has stopped, and a prompt may or may not follow (digest §3.3
/// step 4): the error completes it unless more comes before the line is
/// quiet. Without a prompt (`PC0`), or where prompts come per command and
/// the line repeats or jumps so that their number is not known, quiet
/// ends it too.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AnswerRule {
    /// The line as sent, without its CR; `None` when echo is off.
    pub echo: Option<Vec<u8>>,
    /// `None` after `PC0`: the device's quiet guard ends the answer then.
    pub prompt: Option<u8>,
    /// Prompts that complete the answer; `None` when their number is not
    /// known.
    pub prompts: Option<usize>,
}

impl AnswerRule {
    /// The rule for `line`, sent as `sent`, on an interface with `profile`
    /// in `state`.
    pub fn new(line: &Line, sent: &str, profile: &LinkProfile, state: &LinkState) -> AnswerRule {
        let prompts = match profile.prompt_per {
            PromptPer::Line => Some(1),
            PromptPer::Command if runs_straight(line) => Some(line.commands.len().max(1)),
            PromptPer::Command => None,
        };
        AnswerRule {
            echo: (state.echo == Echo::Line).then(|| sent.as_bytes().to_vec()),
            prompt: state.prompt_after(line, profile),
            prompts,
        }
    }

    fn is_prompt(&self, frame: &[u8]) -> bool {
        self.prompt.is_some_and(|p| frame == [p])
    }

    /// The echo with an error after it on its line (`1XX?1`).
    fn echo_with_error(&self, frame: &[u8]) -> bool {
        self.echo.as_ref().is_some_and(|echo| {
            frame
                .trim_ascii()
                .strip_prefix(echo.as_slice())
                .is_some_and(is_error)
        })
    }
}

fn is_error(frame: &[u8]) -> bool {
    frame.trim_ascii_start().first() == Some(&b'?')
}

impl ReplyRule for AnswerRule {
    fn examine(&self, accepted: &[Frame], frame: &[u8]) -> Verdict {
        if accepted.is_empty()
            && let Some(echo) = &self.echo
        {
            return match frame.trim_ascii().strip_prefix(echo.as_slice()) {
                Some([]) => Verdict::Continue,
                Some(rest) if is_error(rest) => Verdict::CompleteIfQuiet,
                // Another line's echo that starts like this one.
                _ => Verdict::NotMine,
            };
        }
        let errored = accepted
            .iter()
            .enumerate()
            .any(|(i, f)| is_error(f) || (i == 0 && self.echo_with_error(f)));
        if self.is_prompt(frame) {
            if errored {
                return Verdict::Complete;
            }
            let seen = accepted.iter().filter(|f| self.is_prompt(f)).count();
            return match self.prompts {
                Some(n) if seen + 1 >= n => Verdict::Complete,
                Some(_) => Verdict::Continue,
                None => Verdict::CompleteIfQuiet,
            };
        }
        let prompt_glued = self
            .prompt
            .is_some_and(|p| frame.len() > 1 && frame.last() == Some(&p));
        if errored || is_error(frame) || self.prompt.is_none() || prompt_glued {
            Verdict::CompleteIfQuiet
        } else {
            Verdict::Continue
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::mccl::line::parse_line;

    fn line(text: &str) -> Line {
        parse_line(text, NumberBase::Decimal).expect(text)
    }

    fn frames(list: &[&str]) -> Vec<Frame> {
        list.iter().map(|s| s.as_bytes().to_vec()).collect()
    }

    fn reply(text: &str, answer: &[&str]) -> Result<Reply, ReplyProblem> {
        let profile = LinkProfile::MANUAL;
        let l = line(text);
        read_reply(
            &l,
            &l.to_string(),
            &LinkState::new(&profile),
            &profile,
            &frames(answer),
        )
    }

    fn values(reply: &Reply) -> Vec<String> {
        reply
            .reports
            .iter()
            .map(|r| match &r.printed {
                Printed::Value(t) => t.value.to_string(),
                Printed::Text(lines) => lines.join("|"),
            })
            .collect()
    }

    #[test]
    fn errors_read_with_their_ch14_meaning() {
        let e = ErrorReply::parse("?-6").expect("error");
        assert_eq!((e.code, e.meaning()), (-6, "Macro Doesn't Exist"));
        assert_eq!(e.to_string(), "error ?-6 (Macro Doesn't Exist, Ch14)");
        let e = ErrorReply::parse("? 1 1XX").expect("error");
        assert_eq!((e.code, e.detail.as_str()), (1, "1XX"));
        assert_eq!(e.text(), "?1 1XX");
        assert_eq!(
            ErrorReply::parse("?-12").map(|e| e.meaning()),
            Some("a code Ch14 does not list")
        );
        assert_eq!(ErrorReply::parse("01 5"), None);
        assert_eq!(ErrorReply::parse("?"), None);
        assert_eq!(ErrorReply::parse("?x"), None);
    }

    #[test]
    fn tell_replies_carry_a_field_and_a_value() {
        let t = parse_told("01 121.025", NumberBase::Decimal).expect("value");
        assert_eq!(t.field, Some(1));
        assert_eq!(t.value.to_string(), "121.025");
        assert_eq!(t.value.decimals(), 3);
        let t = parse_told("01\t25", NumberBase::Decimal).expect("tab");
        assert_eq!(t.value, Quantity::Integer(25));
        assert_eq!(
            parse_told("123", NumberBase::Decimal).map(|t| t.field),
            Ok(None)
        );
        assert_eq!(
            parse_told("01 0000000a", NumberBase::Hex).map(|t| t.value),
            Ok(Quantity::Integer(10))
        );
        assert!(
            parse_told("01 100000409", NumberBase::Hex).is_err(),
            "9 hex digits"
        );
        assert_eq!(
            parse_told("01 fffffc18", NumberBase::Hex).map(|t| t.value),
            Ok(Quantity::Integer(-1000)),
            "the 32-bit word"
        );
        assert_eq!(
            parse_told("01 121.025", NumberBase::Hex).map(|t| t.value.to_string()),
            Ok("121.025".into()),
            "reals stay decimal"
        );
        assert!(parse_told("01 0000000a", NumberBase::Decimal).is_err());
        assert!(parse_told("1 5", NumberBase::Decimal).is_err());
        assert!(parse_told("01 5x", NumberBase::Decimal).is_err());
        assert!(parse_told("01 1.", NumberBase::Decimal).is_err());
    }

    #[test]
    fn a_compound_reads_one_line_per_tell_command() {
        let r = reply("1TP,TV,TS", &["1TP,TV,TS", "01 1000", "01 0", "01 10", ">"]).expect("reply");
        assert_eq!(values(&r), ["1000", "0", "10"]);
        assert_eq!(r.reports[2].command, Some(2));
        assert_eq!(r.prompts, 1);
        // Nothing printed by a line that reports nothing.
        let r = reply("1MR1000", &["1MR1000", ">"]).expect("reply");
        assert!(r.reports.is_empty() && r.error.is_none());
    }

    /// Fault soak: `4SV140381` answered `4SV140381`, ` >` (a line end
    /// corrupted to a blank before the prompt) was taken for success.
    /// Ch2: the echo is the line as typed and the prompt one character.
    #[test]
    fn only_the_exact_echo_and_prompt_are_success() {
        assert!(reply("4SV140381", &["4SV140381", ">"]).is_ok());
        for damaged in [
            &["4SV140381", " >"][..],
            &["4SV140381 ", ">"],
            &[" 4SV140381", ">"],
            &["4SV140381", " ", ">"],
            &["4SV140381", "\t>"],
        ] {
            assert!(
                matches!(
                    reply("4SV140381", damaged),
                    Err(ReplyProblem::Damaged { .. } | ReplyProblem::NoEcho { .. })
                ),
                "{damaged:?}: {:?}",
                reply("4SV140381", damaged)
            );
        }
        let told = reply("1TP", &["1TP", "01 997", " >"]);
        assert!(
            matches!(told, Err(ReplyProblem::Damaged { .. })),
            "{told:?}"
        );
        // Text output may be blanks of its own (`OT` prints what it is
        // given), and runs into the prompt without its line end.
        assert!(reply("OT\"  \"", &["OT\"  \"", "  >"]).is_ok());
    }

    #[test]
    fn text_output_takes_the_lines_left() {
        let r = reply(
            "VE",
            &[
                "VE",
                "MFX-PCI1440-3-A Motion Controller",
                "Hardware: 16384K",
                ">",
            ],
        )
        .expect("reply");
        assert_eq!(
            values(&r),
            ["MFX-PCI1440-3-A Motion Controller|Hardware: 16384K"]
        );
        let r = reply("1TP,VE,2TP", &["1TP,VE,2TP", "01 5", "a", "b", "02 6", ">"]).expect("reply");
        assert_eq!(values(&r), ["5", "a|b", "6"]);
    }

    #[test]
    fn what_the_line_does_not_print_is_malformed() {
        assert_eq!(
            reply("1TP", &["1TP", ">"]),
            Err(ReplyProblem::Missing {
                command: "1TP".into()
            })
        );
        assert_eq!(
            reply("1MN", &["1MN", "01 5", ">"]),
            Err(ReplyProblem::Unexpected {
                line: "01 5".into()
            })
        );
        assert_eq!(
            reply("1TP", &["2TP", "01 5", ">"]),
            Err(ReplyProblem::NoEcho { got: "2TP".into() })
        );
        assert_eq!(reply("1TP", &["1TP", "01 5"]), Err(ReplyProblem::NoPrompt));
        // The precision asked for is the number of decimals.
        assert!(matches!(
            reply("1TP.3", &["1TP.3", "01 121.02", ">"]),
            Err(ReplyProblem::BadValue { .. })
        ));
        assert!(matches!(
            reply("1TS3", &["1TS3", "01 8", ">"]),
            Err(ReplyProblem::BadValue { .. })
        ));
    }

    #[test]
    fn an_error_stops_the_line_with_or_without_a_prompt() {
        let r = reply("1TP,MC10,2TP", &["1TP,MC10,2TP", "01 5", "?-6", ">"]).expect("reply");
        assert_eq!(r.error.as_ref().map(|e| e.code), Some(-6));
        assert_eq!(values(&r), ["5"]);
        let r = reply("MC10", &["MC10?-6"]).expect("error after the echo");
        assert_eq!(r.error.map(|e| e.code), Some(-6));
        let r = reply("MC10", &["MC10", "?-6", "MC10"]).expect("offending command after");
        assert_eq!(r.error.map(|e| e.detail), Some("MC10".into()));
    }

    #[test]
    fn repeating_lines_report_without_knowing_which_command_printed() {
        let r = reply(
            "1TP,WA0.1,RP2",
            &["1TP,WA0.1,RP2", "01 1", "01 2", "01 3", ">"],
        )
        .expect("reply");
        assert_eq!(values(&r), ["1", "2", "3"]);
        assert!(r.reports.iter().all(|r| r.command.is_none()));
    }

    #[test]
    fn hex_mode_switches_the_replies_after_hm() {
        let profile = LinkProfile::MANUAL;
        let mut state = LinkState::new(&profile);
        state.after(&line("HM"), &profile);
        let l = line("1TS");
        let r = read_reply(
            &l,
            "1TS",
            &state,
            &profile,
            &frames(&["1TS", "01 0000000a", ">"]),
        )
        .expect("hex");
        assert_eq!(values(&r), ["10"]);
        let r = read_reply(
            &l,
            "1TS",
            &state,
            &profile,
            &frames(&["1TS", "01 100000409", ">"]),
        );
        assert!(
            matches!(r, Err(ReplyProblem::BadValue { .. })),
            "the 9-digit misprint"
        );
    }

    #[test]
    fn the_answer_rule_waits_for_echo_then_prompt() {
        let profile = LinkProfile::MANUAL;
        let state = LinkState::new(&profile);
        let l = line("1TP");
        let rule = AnswerRule::new(&l, "1TP", &profile, &state);
        assert_eq!(rule.examine(&[], b">"), Verdict::NotMine, "stale prompt");
        assert_eq!(rule.examine(&[], b"01 5"), Verdict::NotMine, "stale output");
        assert_eq!(rule.examine(&[], b"1TP"), Verdict::Continue);
        assert_eq!(
            rule.examine(&[], b"1TP,TV"),
            Verdict::NotMine,
            "another line"
        );
        assert_eq!(rule.examine(&[], b"1TP?-1"), Verdict::CompleteIfQuiet);
        let echo = frames(&["1TP"]);
        assert_eq!(rule.examine(&echo, b"01 5"), Verdict::Continue);
        assert_eq!(rule.examine(&echo, b">"), Verdict::Complete);
        // An error: its prompt may follow, or not.
        assert_eq!(rule.examine(&echo, b"?-13"), Verdict::CompleteIfQuiet);
        let errored = frames(&["1TP", "?-13"]);
        assert_eq!(rule.examine(&errored, b"1TP"), Verdict::CompleteIfQuiet);
        assert_eq!(rule.examine(&errored, b">"), Verdict::Complete);
        assert_eq!(rule.examine(&frames(&["1TP?-1"]), b">"), Verdict::Complete);
        // Text run into the prompt.
        assert_eq!(rule.examine(&echo, b"x>"), Verdict::CompleteIfQuiet);
        // Per command: the third prompt of a three-command line.
        let per = profile.with_prompt_per(PromptPer::Command);
        let l = line("1MN,1MR5,1TP");
        let rule = AnswerRule::new(&l, "1MN,1MR5,1TP", &per, &state);
        let so_far = frames(&["1MN,1MR5,1TP", ">", ">", "01 5"]);
        assert_eq!(rule.examine(&so_far[..2], b">"), Verdict::Continue);
        assert_eq!(rule.examine(&so_far, b">"), Verdict::Complete);
        // Per command, repeating: how many is not known, quiet tells.
        let l = line("1TP,RP2");
        let rule = AnswerRule::new(&l, "1TP,RP2", &per, &state);
        assert_eq!(
            rule.examine(&frames(&["1TP,RP2", "01 5"]), b">"),
            Verdict::CompleteIfQuiet
        );
        // Without echo, the prompt ends it.
        let silent = LinkState {
            echo: Echo::Off,
            ..state
        };
        let rule = AnswerRule::new(&line("1TP"), "1TP", &profile, &silent);
        assert_eq!(rule.examine(&[], b"01 5"), Verdict::Continue);
        assert_eq!(rule.examine(&frames(&["01 5"]), b">"), Verdict::Complete);
        // Without a prompt (PC0), quiet does.
        let no_prompt = LinkState {
            prompt: None,
            ..state
        };
        let rule = AnswerRule::new(&line("1TP"), "1TP", &profile, &no_prompt);
        assert_eq!(rule.examine(&[], b"1TP"), Verdict::Continue);
        assert_eq!(
            rule.examine(&frames(&["1TP"]), b"01 5"),
            Verdict::CompleteIfQuiet
        );
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        fn frame() -> impl Strategy<Value = Frame> {
            prop_oneof![
                Just(b">".to_vec()),
                "[0-9]{2} -?[0-9]{1,6}(\\.[0-9]{1,5})?".prop_map(String::into_bytes),
                "\\?-?[0-9]{1,3}.{0,6}".prop_map(String::into_bytes),
                proptest::collection::vec(any::<u8>(), 0..20),
            ]
        }

        proptest! {
            #[test]
            fn reading_any_answer_never_panics(
                text in "[0-9]?[A-Za-z]{2}[0-9.@-]{0,4}(,[0-9]?[A-Za-z]{2}[0-9.-]{0,4}){0,3}",
                frames in proptest::collection::vec(frame(), 0..8),
                echo in any::<bool>(),
                hex in any::<bool>(),
            ) {
                let Ok(line) = parse_line(&text, NumberBase::Decimal) else {
                    return Ok(());
                };
                let sent = line.to_string();
                let profile = LinkProfile::MANUAL.with_echo(if echo { Echo::Line } else { Echo::Off });
                let mut state = LinkState::new(&profile);
                state.echo = profile.echo;
                if hex {
                    state.base = NumberBase::Hex;
                }
                let mut all = vec![sent.clone().into_bytes()];
                all.extend(frames.iter().cloned());
                let _ = read_reply(&line, &sent, &state, &profile, &all);
                let rule = AnswerRule::new(&line, &sent, &profile, &state);
                for at in 0..all.len() {
                    let _ = rule.examine(&all[..at], &all[at]);
                }
            }

            #[test]
            fn reply_lines_never_panic(line in "\\PC{0,40}") {
                let _ = ErrorReply::parse(&line);
                for base in [NumberBase::Decimal, NumberBase::Hex] {
                    let _ = parse_told(&line, base);
                }
            }

            #[test]
            fn tell_values_read_back_as_printed(
                axis in 1u8..9,
                values in proptest::collection::vec((-9_999_999i64..9_999_999, 0usize..6), 1..5),
            ) {
                // `aTPp,TPp,…` printed with p decimals each, as Ch8 shows.
                let commands: Vec<String> = values
                    .iter()
                    .enumerate()
                    .map(|(i, (_, p))| {
                        let axis = if i == 0 { axis.to_string() } else { String::new() };
                        if *p == 0 { format!("{axis}TP") } else { format!("{axis}TP.{p}") }
                    })
                    .collect();
                let text = commands.join(",");
                let line = parse_line(&text, NumberBase::Decimal).expect("a Tell line");
                let printed: Vec<String> = values
                    .iter()
                    .map(|(n, p)| {
                        if *p == 0 {
                            n.to_string()
                        } else {
                            format!("{:.p$}", *n as f64 / 1000.0, p = *p)
                        }
                    })
                    .collect();
                let mut frames = vec![text.clone().into_bytes()];
                frames.extend(printed.iter().map(|v| format!("{axis:02} {v}").into_bytes()));
                frames.push(b">".to_vec());
                let profile = LinkProfile::MANUAL;
                let reply = read_reply(&line, &text, &LinkState::new(&profile), &profile, &frames)
                    .expect("read");
                let got: Vec<String> = reply
                    .reports
                    .iter()
                    .map(|r| match &r.printed {
                        Printed::Value(told) => {
                            prop_assert_eq!(told.field, Some(axis));
                            Ok(told.value.to_string())
                        }
                        Printed::Text(_) => Ok(String::new()),
                    })
                    .collect::<Result<_, _>>()?;
                prop_assert_eq!(got, printed);
            }
        }
    }
}
