//! The console line syntax (digest D9):
//!
//! - A mnemonic of [`super::catalog::COMMANDS`] or one of its aliases (any
//!   case), or the command code (`$23`), then the operands in field order
//!   separated by blanks: `StartRamp 0 10000`, `SetAMaxVMax 0 200 400`.
//!   An operand may also name its field, `name=value`, in any order
//!   (`SetMotorParameters m=0 poslimit=10000 flags=NullLeft,MechRef`).
//!   Optional trailing operands (the response address of a query) may be
//!   left out.
//! - Numbers are decimal, with an optional sign; `$` or `0x` marks hex.
//! - Flags by name (`NullLeft,MechRef`, SQPack's `MT_NULLLEFT` too),
//!   `none`, or a number; motor masks as motor lists (`0,2,5`), `all`,
//!   `none`, or a hex mask (`$3F`); a bare number in a mask is a motor;
//!   currents of `$11` as an index 0..8 or a percentage (`50%`). Blanks
//!   around the commas of a list are allowed.
//! - A frame as SQPack writes it in a macro file (§5.4.6):
//!   `SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)`: nine
//!   values, always hex (`10` is 16), `$`/`0x` optional, a trailing `;` or
//!   `.` ignored; or as `raw 00 15 00 10 27 00 00 10 04` (digest D9).
//!   A frame is sent exactly as written; if it carries a documented
//!   command its values are checked like a typed one.

use super::catalog::{
    ALL_MOTORS, CURRENT_STEPS, CommandSpec, Field, FieldKind, UNDOCUMENTED, by_code, by_name,
    flag_by_name,
};
use super::command::{Command, RangeError, flag_names};
use super::frame::{REQUEST_LEN, Request};

/// Why a line was refused. Messages name the command, the operand and
/// what it takes.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LineError {
    #[error("empty line: nothing to send")]
    Empty,
    #[error(
        "`{0}` is not a SIXpack 2 command: give a mnemonic (`StartRamp 0 10000`; Tab lists \
         them) or a frame, `SendToPack($00, $23, …)`"
    )]
    UnknownCommand(String),
    #[error("{name}: {why}; send it as a frame, `SendToPack($00, ${code:02X}, …)`")]
    Undocumented {
        name: &'static str,
        code: u8,
        why: &'static str,
    },
    #[error("{command}: missing {field} (syntax: {syntax})")]
    MissingOperand {
        command: &'static str,
        field: &'static str,
        syntax: String,
    },
    #[error("{command}: unexpected extra operand `{found}` (syntax: {syntax})")]
    ExtraOperand {
        command: &'static str,
        found: String,
        syntax: String,
    },
    #[error("{command}: `{key}` names no operand (syntax: {syntax})")]
    UnknownField {
        command: &'static str,
        key: String,
        syntax: String,
    },
    #[error("{command}: {field} is given twice")]
    Twice {
        command: &'static str,
        field: &'static str,
    },
    #[error("{command}: {field} `{found}`: {reason}")]
    BadValue {
        command: &'static str,
        field: &'static str,
        found: String,
        reason: ValueError,
    },
    #[error(transparent)]
    Range(#[from] RangeError),
    #[error("{form}: {reason}")]
    Frame { form: &'static str, reason: String },
    #[error(
        "the frame is for unit {line}, but unit {session} is addressed: change the frame's first \
         byte, or address unit {line} (--address {line}, or :address {line} in the console)"
    )]
    OtherUnit { line: u8, session: u8 },
}

/// How a line was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Form {
    /// A mnemonic and operands.
    Mnemonic,
    /// Nine bytes, as `SendToPack(…)` or `raw …`.
    Frame,
}

/// A line parsed and checked: the request it sends and, where its command
/// is documented, that command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParsedLine {
    pub request: Request,
    /// The documented command the request carries, values checked;
    /// `None` for a frame whose command byte §7 does not list.
    pub command: Option<Command>,
    pub form: Form,
}

impl ParsedLine {
    /// The line as the console writes it: the mnemonic form when it gives
    /// exactly these bytes, else the frame as SQPack writes it.
    pub fn canonical(&self) -> String {
        canonical(&self.request)
    }
}

/// The console line for a request: its command with operands, or, when
/// the bytes are not exactly a documented command's (an unknown command,
/// unused bytes set), the `SendToPack(…)` form.
pub fn canonical(request: &Request) -> String {
    match Command::from_request(request) {
        Ok(Some(command)) if command.to_request(request.address) == *request => command.to_string(),
        _ => send_to_pack(request),
    }
}

/// `SendToPack($00, $23, $00, …)`: a request as SQPack's macro files write
/// it (§5.5.3).
pub fn send_to_pack(request: &Request) -> String {
    let values: Vec<String> = request
        .to_bytes()
        .iter()
        .map(|b| format!("${b:02X}"))
        .collect();
    format!("SendToPack({})", values.join(", "))
}

/// The unit address a mnemonic line is sent to when none is given: the
/// factory setting of the rotary switches (§5.2.1, §6.1.1).
pub const DEFAULT_ADDRESS: u8 = 0;

/// Parse and check a console line. A mnemonic line is framed for
/// `address` (the factory address 0 when `None`); a frame keeps its own
/// address byte, which must be `address` when one is given.
pub fn parse_line(text: &str, address: Option<u8>) -> Result<ParsedLine, LineError> {
    let text = text.trim();
    let Some(first) = text.split_whitespace().next() else {
        return Err(LineError::Empty);
    };
    let head = text.split(['(', ' ', '\t']).next().unwrap_or_default();
    if head.eq_ignore_ascii_case("SendToPack") {
        let bytes = parse_send_to_pack(text)?;
        return frame_line(bytes, address);
    }
    if first.eq_ignore_ascii_case("raw") {
        let bytes = parse_raw(text.get(first.len()..).unwrap_or_default())?;
        return frame_line(bytes, address);
    }
    let spec = find_spec(first)?;
    let rest = text.get(first.len()..).unwrap_or_default();
    let command = parse_operands(spec, rest)?;
    Ok(ParsedLine {
        request: command.to_request(address.unwrap_or(DEFAULT_ADDRESS)),
        command: Some(command),
        form: Form::Mnemonic,
    })
}

/// The command a line's first word names: a mnemonic, an alias, or a
/// command code.
fn find_spec(word: &str) -> Result<&'static CommandSpec, LineError> {
    if let Some(spec) = by_name(word) {
        return Ok(spec);
    }
    if let Some(undocumented) = UNDOCUMENTED
        .iter()
        .find(|u| u.name.eq_ignore_ascii_case(word))
    {
        return Err(LineError::Undocumented {
            name: undocumented.name,
            code: undocumented.code,
            why: undocumented.why,
        });
    }
    let code = hex_digits(word).and_then(|digits| u8::from_str_radix(digits, 16).ok());
    if let Some(code) = code {
        if let Some(spec) = by_code(code) {
            return Ok(spec);
        }
        if let Some(undocumented) = UNDOCUMENTED.iter().find(|u| u.code == code) {
            return Err(LineError::Undocumented {
                name: undocumented.name,
                code,
                why: undocumented.why,
            });
        }
    }
    Err(LineError::UnknownCommand(word.to_string()))
}

/// The digits of `$1F` or `0x1F`.
fn hex_digits(text: &str) -> Option<&str> {
    text.strip_prefix('$')
        .or_else(|| text.strip_prefix("0x"))
        .or_else(|| text.strip_prefix("0X"))
        .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_hexdigit()))
}

/// The operands after the mnemonic, blank-separated; blanks around the
/// commas of a list join it into one operand (`0, 2, 5`).
pub fn operand_words(text: &str) -> Vec<String> {
    let mut words: Vec<String> = Vec::new();
    let mut join_next = false;
    for word in text.split_whitespace() {
        match words.last_mut() {
            Some(last) if join_next || word.starts_with(',') => last.push_str(word),
            _ => words.push(word.to_string()),
        }
        join_next = word.ends_with(',');
    }
    words
}

fn parse_operands(spec: &'static CommandSpec, text: &str) -> Result<Command, LineError> {
    let fields = spec.fields;
    let mut values: Vec<Option<i64>> = vec![None; fields.len()];
    let mut next = 0;
    for word in operand_words(text) {
        let (index, value_text) = match word.split_once('=') {
            Some((key, value)) => {
                let (index, _) = spec.field(key).ok_or_else(|| LineError::UnknownField {
                    command: spec.mnemonic,
                    key: key.to_string(),
                    syntax: spec.syntax(),
                })?;
                (index, value.to_string())
            }
            None => {
                while values.get(next).is_some_and(Option::is_some) {
                    next += 1;
                }
                if next >= fields.len() {
                    return Err(LineError::ExtraOperand {
                        command: spec.mnemonic,
                        found: word,
                        syntax: spec.syntax(),
                    });
                }
                next += 1;
                (next - 1, word)
            }
        };
        let field = &fields[index];
        if values[index].is_some() {
            return Err(LineError::Twice {
                command: spec.mnemonic,
                field: field.name,
            });
        }
        let value = parse_value(field, &value_text).map_err(|reason| LineError::BadValue {
            command: spec.mnemonic,
            field: field.name,
            found: value_text.clone(),
            reason,
        })?;
        values[index] = Some(value);
    }
    let values = fields
        .iter()
        .zip(values)
        .map(|(field, value)| {
            value
                .or(field.default)
                .ok_or_else(|| LineError::MissingOperand {
                    command: spec.mnemonic,
                    field: field.name,
                    syntax: spec.syntax(),
                })
        })
        .collect::<Result<Vec<i64>, LineError>>()?;
    Ok(Command::new(spec, values)?)
}

/// Why a value typed for a field is not one.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ValueError {
    #[error("too large")]
    TooLarge,
    #[error("not a number (decimal, or hex as $1F or 0x1F)")]
    NotANumber,
    /// A current step given in % that §7.1's table does not have.
    #[error("no such step: 100%, 75%, 50%, 38%, 25%, 19%, 13%, 9% or 0%")]
    NoSuchStep,
    #[error("a mask is a list of motors 0..5 (0,2,5), all, none, or hex ($3F)")]
    NotAMask,
    #[error("motor {item} is outside 0..5 (a mask lists motors: 0,2,5; or hex $3F)")]
    NoSuchMotor { item: String },
    #[error("`{item}` is no flag: {}", flag_names())]
    NoSuchFlag { item: String },
    #[error("`{value}` is not a hex byte ($00..$FF; frame values are always hex)")]
    NotAHexByte { value: String },
}

/// A decimal number with an optional sign, or hex after `$` or `0x`.
pub fn parse_number(text: &str) -> Result<i64, ValueError> {
    let (negative, digits) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let magnitude = if let Some(hex) = hex_digits(digits) {
        i64::from_str_radix(hex, 16).map_err(|_| ValueError::TooLarge)?
    } else if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) {
        digits.parse::<i64>().map_err(|_| ValueError::TooLarge)?
    } else {
        return Err(ValueError::NotANumber);
    };
    Ok(if negative { -magnitude } else { magnitude })
}

/// A value typed for `field`. Range checks come after, for all fields
/// alike ([`Command::new`]).
pub fn parse_value(field: &Field, text: &str) -> Result<i64, ValueError> {
    match field.kind {
        FieldKind::MotorMask => parse_mask(text),
        FieldKind::Flags(_) => parse_flags(text),
        FieldKind::CurrentIndex => match text.strip_suffix('%') {
            Some(percent) => {
                let percent = parse_number(percent)?;
                CURRENT_STEPS
                    .iter()
                    .find(|s| i64::from(s.percent) == percent)
                    .map(|s| i64::from(s.index))
                    .ok_or(ValueError::NoSuchStep)
            }
            None => parse_number(text),
        },
        _ => parse_number(text),
    }
}

/// A motor list (`0,2,5`), `all`, `none`, or a hex mask (`$3F`).
pub fn parse_mask(text: &str) -> Result<i64, ValueError> {
    if text.eq_ignore_ascii_case("all") {
        return Ok(ALL_MOTORS);
    }
    if text.eq_ignore_ascii_case("none") {
        return Ok(0);
    }
    if let Some(digits) = hex_digits(text) {
        return i64::from_str_radix(digits, 16).map_err(|_| ValueError::TooLarge);
    }
    let mut mask = 0;
    for item in text.split(',') {
        if item.is_empty() || !item.bytes().all(|b| b.is_ascii_digit()) {
            return Err(ValueError::NotAMask);
        }
        match item.parse::<u8>() {
            Ok(motor) if motor < 6 => mask |= 1 << motor,
            _ => {
                return Err(ValueError::NoSuchMotor {
                    item: item.to_string(),
                });
            }
        }
    }
    Ok(mask)
}

/// Flag names joined by commas, `none`, or numbers (ORed with the names).
pub fn parse_flags(text: &str) -> Result<i64, ValueError> {
    if text.eq_ignore_ascii_case("none") {
        return Ok(0);
    }
    let mut word = 0;
    for item in text.split(',') {
        if let Some(flag) = flag_by_name(item) {
            word |= flag.mask();
        } else if let Ok(number) = parse_number(item) {
            word |= number;
        } else {
            return Err(ValueError::NoSuchFlag {
                item: item.to_string(),
            });
        }
    }
    Ok(word)
}

fn parse_send_to_pack(text: &str) -> Result<[u8; REQUEST_LEN], LineError> {
    let error = |reason: String| LineError::Frame {
        form: "SendToPack",
        reason,
    };
    let after = text
        .get("SendToPack".len()..)
        .unwrap_or_default()
        .trim_start();
    let inner = after
        .strip_prefix('(')
        .ok_or_else(|| error("expected `(` after SendToPack".into()))?;
    let inner = inner.trim_end();
    let inner = inner.strip_suffix(['.', ';']).unwrap_or(inner).trim_end();
    let inner = inner
        .strip_suffix(')')
        .ok_or_else(|| error("expected `)` at the end".into()))?;
    let values: Vec<&str> = inner.split(',').map(str::trim).collect();
    frame_bytes(&values).map_err(error)
}

fn parse_raw(text: &str) -> Result<[u8; REQUEST_LEN], LineError> {
    let values: Vec<&str> = text
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|v| !v.is_empty())
        .collect();
    frame_bytes(&values).map_err(|reason| LineError::Frame {
        form: "raw",
        reason,
    })
}

/// Nine hex values (`$`/`0x` optional, one or two digits, any case).
fn frame_bytes(values: &[&str]) -> Result<[u8; REQUEST_LEN], String> {
    if values.len() != REQUEST_LEN {
        return Err(format!(
            "a frame has 9 values (adr, cmd, p0..p6), this one {}",
            values.len()
        ));
    }
    let mut bytes = [0; REQUEST_LEN];
    for (slot, value) in bytes.iter_mut().zip(values) {
        *slot = hex_byte(value).map_err(|e| e.to_string())?;
    }
    Ok(bytes)
}

/// One value of a frame: a hex byte, `$`/`0x` optional, one or two
/// digits, any case; bare numbers are hex too (§5.4.6: "The parameters
/// are hexadecimal").
pub fn hex_byte(value: &str) -> Result<u8, ValueError> {
    let digits = value
        .strip_prefix('$')
        .or_else(|| value.strip_prefix("0x"))
        .or_else(|| value.strip_prefix("0X"))
        .unwrap_or(value);
    let ok = (1..=2).contains(&digits.len()) && digits.bytes().all(|b| b.is_ascii_hexdigit());
    ok.then(|| u8::from_str_radix(digits, 16).ok())
        .flatten()
        .ok_or_else(|| ValueError::NotAHexByte {
            value: value.to_string(),
        })
}

fn frame_line(bytes: [u8; REQUEST_LEN], address: Option<u8>) -> Result<ParsedLine, LineError> {
    let request = Request::from_bytes(&bytes).ok_or_else(|| LineError::Frame {
        form: "frame",
        reason: "not 9 bytes".into(),
    })?;
    if let Some(session) = address
        && session != request.address
    {
        return Err(LineError::OtherUnit {
            line: request.address,
            session,
        });
    }
    let command = Command::from_request(&request)?;
    Ok(ParsedLine {
        request,
        command,
        form: Form::Frame,
    })
}

impl crate::protocol::line_error::FamilyLineError for LineError {
    fn mistake(&self) -> crate::protocol::line_error::Mistake {
        use crate::protocol::line_error::Mistake;
        match self {
            LineError::Empty => Mistake::Empty,
            LineError::Range(_) | LineError::BadValue { .. } => Mistake::Range,
            LineError::OtherUnit { .. } => Mistake::Address,
            LineError::Undocumented { .. } => Mistake::NotSent,
            _ => Mistake::Syntax,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::sixpack2::frame::to_hex;

    fn bytes(line: &str) -> String {
        let parsed = parse_line(line, None).unwrap_or_else(|e| panic!("{line}: {e}"));
        to_hex(&parsed.request.to_bytes())
    }

    fn error(line: &str) -> String {
        parse_line(line, None)
            .err()
            .unwrap_or_else(|| panic!("{line} parsed"))
            .to_string()
    }

    #[test]
    fn mnemonics_and_operands_in_field_order() {
        assert_eq!(bytes("StartRamp 0 10000"), "00 23 00 10 27 00 00 00 00");
        assert_eq!(bytes("startramp 0 $2710"), "00 23 00 10 27 00 00 00 00");
        assert_eq!(bytes("Ramp 0 0x2710"), "00 23 00 10 27 00 00 00 00");
        assert_eq!(bytes("$23 0 10000"), "00 23 00 10 27 00 00 00 00");
        assert_eq!(bytes("StartRamp 1 -1"), "00 23 01 FF FF FF FF 00 00");
        assert_eq!(bytes("SetAMaxVMax 3 200 400"), "00 14 03 C8 00 90 01 00 00");
        assert_eq!(
            bytes("SetMotorParameters 0 10000 NullLeft,MechRef"),
            "00 15 00 10 27 00 00 10 04"
        );
        assert_eq!(
            bytes("SetMotorParameters 0 10000 MT_NULLLEFT, MT_MECHREF"),
            "00 15 00 10 27 00 00 10 04"
        );
        assert_eq!(
            bytes("SetMotorParameters m=0 poslimit=10000 flags=NullLeft,MechRef"),
            "00 15 00 10 27 00 00 10 04"
        );
        assert_eq!(
            bytes("SetMotorParameters flags=$0410 0 10000"),
            "00 15 00 10 27 00 00 10 04"
        );
        assert_eq!(bytes("StopMotors 0, 2, 5"), "00 2A 25 00 00 00 00 00 00");
        assert_eq!(bytes("StopMotors all"), "00 2A 3F 00 00 00 00 00 00");
        assert_eq!(bytes("StopMotors $3F"), "00 2A 3F 00 00 00 00 00 00");
        assert_eq!(
            bytes("GetAllActivities 0 1,3"),
            "00 28 00 0A 00 00 00 00 00"
        );
        assert_eq!(
            bytes("GetAllActivities wait=1,3"),
            "00 28 00 0A 00 00 00 00 00"
        );
        assert_eq!(
            bytes("GetPositionAndActivity 4"),
            "00 20 04 00 00 00 00 00 00"
        );
        assert_eq!(
            bytes("SetCurrentControl 0 0% 50% 75% 100% 500"),
            "00 11 00 08 02 01 00 F4 01"
        );
        assert_eq!(
            bytes("SetCurrentControl 0 8 2 1 0 500"),
            "00 11 00 08 02 01 00 F4 01"
        );
        assert_eq!(
            bytes("ConstantRotation 5 -511"),
            "00 25 05 01 FE 00 00 00 00"
        );
        assert_eq!(bytes("HardwareReset"), "00 CC 00 00 00 00 00 00 00");
    }

    #[test]
    fn a_mnemonic_line_goes_to_the_address_given() {
        let parsed = parse_line("StartRamp 0 1", Some(7)).expect("valid");
        assert_eq!(parsed.request.address, 7);
        assert_eq!(parsed.form, Form::Mnemonic);
    }

    #[test]
    fn frames_are_always_hex_and_keep_their_bytes() {
        let line = "SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04).";
        assert_eq!(bytes(line), "00 15 00 10 27 00 00 10 04");
        let parsed = parse_line(line, None).expect("valid");
        assert_eq!(parsed.form, Form::Frame);
        assert_eq!(
            parsed.canonical(),
            "SetMotorParameters 0 10000 NullLeft,MechRef"
        );
        assert_eq!(
            bytes("sendtopack ( 0, 15, 0, 10, 27, 0, 0, 10, 4 );"),
            "00 15 00 10 27 00 00 10 04",
            "bare numbers are hex"
        );
        assert_eq!(
            bytes("raw 00 22 00 00 00 00 00 00 00"),
            "00 22 00 00 00 00 00 00 00"
        );
        assert_eq!(
            bytes("raw 0x00,0x22,0,0,0,0,0,0,0"),
            "00 22 00 00 00 00 00 00 00"
        );
        // An undocumented command goes as written.
        let margin = parse_line(
            "SendToPack($00, $1A, $00, $20, $00, $00, $00, $00, $00)",
            None,
        )
        .expect("valid");
        assert_eq!(margin.command, None);
        assert_eq!(
            margin.canonical(),
            "SendToPack($00, $1A, $00, $20, $00, $00, $00, $00, $00)"
        );
        // Unused bytes set: sent as written, shown as a frame.
        let stray = parse_line("raw 00 23 00 10 27 00 00 01 00", None).expect("valid");
        assert_eq!(
            stray.canonical(),
            "SendToPack($00, $23, $00, $10, $27, $00, $00, $01, $00)"
        );
    }

    #[test]
    fn frames_with_bad_values_are_refused() {
        assert!(
            error("SendToPack($00, $15)").contains("9 values"),
            "{}",
            error("SendToPack($00, $15)")
        );
        assert!(error("SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $104)").contains("$104"));
        assert!(error("SendToPack $00, $15").contains("`(`"));
        assert!(error("SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04").contains("`)`"));
        assert_eq!(
            error("raw 00 23 06 00 00 00 00 00 00"),
            "StartRamp: motno 6 is outside 0..5 (Motor 1..6)"
        );
        let other = parse_line("raw 01 22 00 00 00 00 00 00 00", Some(0)).unwrap_err();
        assert!(other.to_string().contains("unit 1"), "{other}");
        assert!(parse_line("raw 01 22 00 00 00 00 00 00 00", Some(1)).is_ok());
    }

    #[test]
    fn a_bad_operand_is_named() {
        assert_eq!(
            error("StartRamp 6 100"),
            "StartRamp: motno 6 is outside 0..5 (Motor 1..6)"
        );
        assert_eq!(
            error("SetAMaxVMax 0 500 2000"),
            "SetAMaxVMax: vmax 2000 is outside 1..511"
        );
        assert!(error("StartRamp 0").contains("missing target"));
        assert!(error("StartRamp 0 1 2").contains("extra operand `2`"));
        assert!(error("StartRamp 0, 10000").contains("motno `0,10000`"));
        assert!(error("StartRamp 0 ten").contains("target `ten`: not a number"));
        assert!(error("StartRamp 0 99999999999").contains("outside"));
        assert!(error("StartRamp 0 9999999999999999999999").contains("too large"));
        assert!(error("StartRamp foo=1").contains("`foo` names no operand"));
        assert!(error("StartRamp 0 target=1 2").contains("extra operand"));
        assert!(error("StartRamp motno=1 motno=2").contains("given twice"));
        assert!(error("StopMotors 6").contains("motor 6 is outside 0..5"));
        assert!(error("StopMotors 63").contains("motor 63"));
        assert!(error("SetMotorParameters 0 1 NullRight").contains("`NullRight` is no flag"));
        assert!(error("SetCurrentControl 0 40% 0 0 0 1").contains("no such step"));
        assert!(error("Jog 0").contains("`Jog` is not a SIXpack 2 command"));
        assert!(error("SetMargin 0 16").contains("§6.5.3"));
        assert!(error("$1A 0").contains("SendToPack($00, $1A"));
        assert_eq!(error("   "), "empty line: nothing to send");
    }

    #[test]
    fn canonical_lines_parse_back_to_the_same_bytes() {
        for line in [
            "StartRamp 0 10000",
            "SetMotorParameters 0 10000 NullLeft,MechRef",
            "SetCurrentControl 0 0% 50% 75% 100% 500",
            "StopMotors 0,2,5",
            "GetAllActivities 0 all",
            "SetRefSearchParameters 0 100 $0FFF 0",
            "SendToPack($00, $1A, $00, $20, $00, $00, $00, $00, $00)",
        ] {
            let parsed = parse_line(line, None).expect("valid");
            let again = parse_line(&parsed.canonical(), None).expect("canonical parses");
            assert_eq!(again.request, parsed.request, "{line}");
        }
    }

    #[test]
    fn numbers_and_lists() {
        assert_eq!(parse_number("-$10"), Ok(-16));
        assert_eq!(parse_number("+7"), Ok(7));
        assert!(parse_number("$").is_err());
        assert!(parse_number("1e3").is_err());
        assert_eq!(parse_mask("none"), Ok(0));
        assert_eq!(parse_mask("5"), Ok(32));
        assert!(parse_mask("0,,1").is_err());
        assert_eq!(parse_flags("none"), Ok(0));
        assert_eq!(parse_flags("nullleft,$8000"), Ok(0x8010));
        assert_eq!(operand_words(" 0 ,1, 2  x,y "), ["0,1,2", "x,y"]);
    }
}
