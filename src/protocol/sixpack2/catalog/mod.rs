//! The SIXpack 2 instruction set (§7, table §8) as data: one row per
//! command with its mnemonic and the other names the manual uses, the
//! fields of its request in frame order (offset in P0..P6, width,
//! signedness, range, masks and flags by name), the fields of its reply,
//! and whether the console must ask before sending it (digest D9). The
//! parser, the formatter, the reply decoder, completion, help, the traffic
//! monitor and the parameter table all read these tables; nothing else
//! restates the manual.
//!
//! Where the manual disagrees with itself the row follows §7 and says so
//! (digest D11): `$31` is SetStopSwitchLimits although §6.5.1 says `$30`
//! (E18); StopNoRef is P6 bit 5 although §7.1 once says bit 6 (E13); the
//! last field of `$19` is intinpclip although §7.1 labels it intclip
//! again (E14); `$24` is StartPIControl, never SetTargetPosition (§6.6's
//! misnomer, E15), so that a pasted "SetTargetPosition" means `$26`.

/// How a field's value is written when the console shows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Radix {
    Decimal,
    /// Bit masks and magic codes read better in hex (`$0FFF`).
    Hex,
}

/// What a field holds and which values it takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldKind {
    /// A motor number, motno 0..5 ("Motor 1..6" in the manual's prose, §7).
    Motor,
    /// An input channel 0..7: 0..5 the motors' A_In, 6 the external input,
    /// 7 the supply voltage (§7.3).
    Channel,
    /// Where a query's answer goes (§6.2.2.3). Its use on RS-232/485 is
    /// never explained (digest D1.4); the console sends 0.
    ResponseAddress,
    /// A number from `min` to `max`; the field's width and `signed` decide
    /// the bytes.
    Number { min: i64, max: i64, signed: bool },
    /// One of the listed values (`$17` start index 0, 4, 8, 12).
    OneOf(&'static [i64]),
    /// Bit n = motor n (bits 6–7 name no motor, digest D2).
    MotorMask,
    /// A word of named flag bits (`$15` motor type).
    Flags(&'static [FlagBit]),
    /// A current-control index 0..8, also written as its percentage (`$11`,
    /// [`CURRENT_STEPS`]).
    CurrentIndex,
    /// Bit 0 of a byte: 0 or 1.
    Bit,
    /// An action code ([`ACTIONS`]); replies only.
    Action,
    /// `$30` reply P4: the reference inputs of motors 0..5 in bits 0..5,
    /// jumper JP1 in bit 6 and JP2 in bit 7 (§7.3, §5.2.3); replies only.
    InputsAndJumpers,
}

/// One field of a request or a reply.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field {
    /// The manual's name, also the key of `name=value` operands.
    pub name: &'static str,
    /// Index of its first byte in P0..P6.
    pub offset: usize,
    /// Bytes, least significant first (§7).
    pub width: usize,
    pub kind: FieldKind,
    pub radix: Radix,
    /// The value sent when the operand is left out; `None`: it must be
    /// given.
    pub default: Option<i64>,
    /// Unit of the raw value, empty for plain numbers and codes.
    pub unit: &'static str,
    pub meaning: &'static str,
}

impl Field {
    /// The least and the greatest value the field takes.
    pub fn bounds(&self) -> (i64, i64) {
        match self.kind {
            FieldKind::Motor => (0, i64::from(MOTORS) - 1),
            FieldKind::Channel => (0, 7),
            FieldKind::ResponseAddress => (0, 255),
            FieldKind::Number { min, max, .. } => (min, max),
            FieldKind::OneOf(values) => (
                values.iter().copied().min().unwrap_or(0),
                values.iter().copied().max().unwrap_or(0),
            ),
            FieldKind::MotorMask => (0, ALL_MOTORS),
            FieldKind::Flags(_) => (0, (1i64 << (8 * self.width)) - 1),
            FieldKind::CurrentIndex => (0, 8),
            FieldKind::Bit => (0, 1),
            FieldKind::Action | FieldKind::InputsAndJumpers => (0, 255),
        }
    }

    /// Whether the field accepts `value`.
    pub fn accepts(&self, value: i64) -> bool {
        match self.kind {
            FieldKind::OneOf(values) => values.contains(&value),
            _ => {
                let (min, max) = self.bounds();
                (min..=max).contains(&value)
            }
        }
    }

    /// Whether the bytes are read as two's complement.
    pub fn signed(&self) -> bool {
        matches!(self.kind, FieldKind::Number { signed: true, .. })
    }

    /// `P1-4`, `P0`: where the field lies in the frame, as §7 writes it.
    pub fn bytes_label(&self) -> String {
        if self.width == 1 {
            format!("P{}", self.offset)
        } else {
            format!("P{}-{}", self.offset, self.offset + self.width - 1)
        }
    }
}

/// One named bit of a flag word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FlagBit {
    /// Bit of the word (P5 bit n is bit n, P6 bit n is bit 8+n).
    pub bit: u8,
    /// The name in §7.1.
    pub name: &'static str,
    /// SQPack's name (§5.5.3), where the manual gives one.
    pub sqpack: Option<&'static str>,
    pub meaning: &'static str,
}

impl FlagBit {
    pub fn mask(&self) -> i64 {
        1 << self.bit
    }

    /// `P5.4`: the byte and bit as §7.1 names them.
    pub fn place(&self) -> String {
        format!("P{}.{}", 5 + self.bit / 8, self.bit % 8)
    }
}

/// What kind of command a row is: decides whether it may be repeated and
/// how it is answered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Class {
    /// Changes a setting; never acknowledged, never read back (§7, D0).
    Setting,
    /// Starts, changes or stops a motion; never acknowledged.
    Motion,
    /// Reads something and answers (§7: `$20 $21 $28 $30 $43 $44`).
    Query,
    /// Changes how the unit is reached or resets it; never acknowledged.
    Unit,
    /// Flash and EEPROM service functions (§7.6): "not intended for the
    /// user".
    Service,
}

/// When the console must ask before sending a command (digest D9).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Confirm {
    Never,
    /// Always, for this reason.
    Always(&'static str),
    /// When the named flag of the command's flag word is set.
    WhenFlag {
        flag: &'static str,
        why: &'static str,
    },
}

/// One command of §7.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CommandSpec {
    pub code: u8,
    /// The console's name for it, built from the manual's own (digest D3).
    pub mnemonic: &'static str,
    /// Other names the manual or SQPack use for it, accepted as synonyms.
    pub aliases: &'static [&'static str],
    /// The §7 heading.
    pub heading: &'static str,
    pub section: &'static str,
    pub class: Class,
    /// The request's fields after the command byte, in frame order.
    pub fields: &'static [Field],
    /// The reply's fields after the echoed command byte, if it answers.
    pub reply: Option<&'static [Field]>,
    pub confirm: Confirm,
    /// What a technician should know, from the manual.
    pub note: &'static str,
}

impl CommandSpec {
    /// `StartRamp motno target`: the mnemonic and its operands in order,
    /// optional ones in brackets.
    pub fn syntax(&self) -> String {
        let mut text = self.mnemonic.to_string();
        for field in self.fields {
            if field.default.is_some() {
                text.push_str(&format!(" [{}]", field.name));
            } else {
                text.push_str(&format!(" {}", field.name));
            }
        }
        text
    }

    /// The field called `name` (case-insensitive; `m` is motno, as in
    /// digest D9's `m=0`).
    pub fn field(&self, name: &str) -> Option<(usize, &'static Field)> {
        self.fields.iter().enumerate().find(|(_, f)| {
            f.name.eq_ignore_ascii_case(name)
                || (name.eq_ignore_ascii_case("m") && f.kind == FieldKind::Motor)
        })
    }

    /// Whether the command answers.
    pub fn answers(&self) -> bool {
        self.reply.is_some()
    }

    /// The request field of the response address, if any.
    pub fn response_field(&self) -> Option<&'static Field> {
        self.fields
            .iter()
            .find(|f| f.kind == FieldKind::ResponseAddress)
    }
}

/// The SIXpack 2 drives six motors, motno 0..5 (§7).
pub const MOTORS: u8 = 6;

/// The mask of all six motors.
pub const ALL_MOTORS: i64 = 0x3F;

const fn field(
    name: &'static str,
    offset: usize,
    width: usize,
    kind: FieldKind,
    meaning: &'static str,
) -> Field {
    Field {
        name,
        offset,
        width,
        kind,
        radix: Radix::Decimal,
        default: None,
        unit: "",
        meaning,
    }
}

const fn with_unit(field: Field, unit: &'static str) -> Field {
    Field { unit, ..field }
}

const fn hex(field: Field) -> Field {
    Field {
        radix: Radix::Hex,
        ..field
    }
}

const fn optional(field: Field, default: i64) -> Field {
    Field {
        default: Some(default),
        ..field
    }
}

const fn unsigned(min: i64, max: i64) -> FieldKind {
    FieldKind::Number {
        min,
        max,
        signed: false,
    }
}

const fn signed(min: i64, max: i64) -> FieldKind {
    FieldKind::Number {
        min,
        max,
        signed: true,
    }
}

const MOTNO: Field = field(
    "motno",
    0,
    1,
    FieldKind::Motor,
    "motor number 0..5 (Motor 1..6)",
);

/// The response address as the last operand: 0 unless given.
const fn response_at(offset: usize) -> Field {
    optional(
        field(
            "resp",
            offset,
            1,
            FieldKind::ResponseAddress,
            "response address (§6.2.2.3; the console sends 0)",
        ),
        0,
    )
}

/// The response address in front of required operands: it must be given.
const RESPONSE_REQUIRED: Field = field(
    "resp",
    0,
    1,
    FieldKind::ResponseAddress,
    "response address (§6.2.2.3)",
);

const I32: FieldKind = signed(i32::MIN as i64, i32::MAX as i64);

/// A velocity in the unit of §6.3.1 (f_µstep = 20 MHz/(clkdiv+1)·v/2^(14+div)).
const VELOCITY_UNIT: &str = "v";

mod commands;
mod flags;

pub use commands::{COMMANDS, UNDOCUMENTED, Undocumented};
pub use flags::{
    ACTIONS, Activity, CURRENT_STEPS, CurrentStep, MOTOR_FLAGS, action_from_token, action_token,
    activity, flag_by_name,
};

/// The command with this code.
pub fn by_code(code: u8) -> Option<&'static CommandSpec> {
    COMMANDS.iter().find(|c| c.code == code)
}

/// The command called `name`: its mnemonic or an alias, any case.
pub fn by_name(name: &str) -> Option<&'static CommandSpec> {
    COMMANDS.iter().find(|c| {
        c.mnemonic.eq_ignore_ascii_case(name)
            || c.aliases.iter().any(|a| a.eq_ignore_ascii_case(name))
    })
}

/// Whether a reply can start with this command byte (§7: only the
/// queries and the service commands answer).
pub fn is_replying(code: u8) -> bool {
    by_code(code).is_some_and(CommandSpec::answers)
}

/// `motor 2 (Motor 3)`: a motor as the console names it (digest D9).
pub fn motor_name(motno: i64) -> String {
    format!("motor {motno} (Motor {})", motno + 1)
}

#[cfg(test)]
mod tests;
