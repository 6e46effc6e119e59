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

/// `$15` P5/P6, the motor type word (§7.1; bit places confirmed by the
/// §5.5.3 examples, digest D4). Default `$0AA0` (§6.8).
pub const MOTOR_FLAGS: &[FlagBit] = &[
    FlagBit {
        bit: 0,
        name: "PIMode",
        sqpack: None,
        meaning: "1 = PI controller, 0 = trapezoidal ramp",
    },
    FlagBit {
        bit: 1,
        name: "Rotary",
        sqpack: Some("MT_ROTARY"),
        meaning: "rotary axis: positions wrap modulo poslimit (§6.6.6)",
    },
    FlagBit {
        bit: 2,
        name: "AutonullCmd",
        sqpack: None,
        meaning: "starts a reference search, the same action as $22: writing it homes the motor",
    },
    FlagBit {
        bit: 3,
        name: "TestNull",
        sqpack: Some("MT_TESTNULL"),
        meaning: "stop flag (and a reference search unless StopNoRef) when the motor rests at \
                  zero but the switch stays inactive (§6.4.4)",
    },
    FlagBit {
        bit: 4,
        name: "NullLeft",
        sqpack: Some("MT_NULLLEFT"),
        meaning: "1 = zero point left of the driving range (positions >= 0), 0 = right \
                  (positions <= 0)",
    },
    FlagBit {
        bit: 5,
        name: "NullCenter",
        sqpack: None,
        meaning: "zero point at the centre of the switch's active zone (rotary axes)",
    },
    FlagBit {
        bit: 6,
        name: "StopNull",
        sqpack: Some("MT_STOPNULL"),
        meaning: "stop (and stop flag) when the switch is active outside ±testnullrange or an \
                  A_In limit ($31) is passed (§6.5.2)",
    },
    FlagBit {
        bit: 7,
        name: "FilterSwitch",
        sqpack: None,
        meaning: "debounce the reference input with the $16 mask (2-30 ms)",
    },
    FlagBit {
        bit: 8,
        name: "WayOptimization",
        sqpack: Some("MT_OPTIMIZEWAY"),
        meaning: "rotary axis: take the shorter way round",
    },
    FlagBit {
        bit: 9,
        name: "FastRef",
        sqpack: Some("MT_FASTREF"),
        meaning: "search the switch at vrefmax ($16); needs a correct poslimit (§6.4.8)",
    },
    FlagBit {
        bit: 10,
        name: "MechRef",
        sqpack: Some("MT_MECHREF"),
        meaning: "mechanical reference: drive 5/4·poslimit against the stop (linear axes, §5.5.1)",
    },
    FlagBit {
        bit: 11,
        name: "DelayTestNull",
        sqpack: Some("MT_DELAYTESTNULL"),
        meaning: "delay the zero-point check by T0 ($11, §6.4.6)",
    },
    FlagBit {
        bit: 12,
        name: "StopSoft",
        sqpack: None,
        meaning: "on a stop condition decelerate with amax instead of stopping abruptly",
    },
    FlagBit {
        bit: 13,
        name: "StopNoRef",
        sqpack: None,
        meaning: "on a stop condition just stop: no automatic reference search (P6 bit 5, \
                  digest E13)",
    },
    FlagBit {
        bit: 14,
        name: "NullPositive",
        sqpack: Some("MT_NULLPOSITIVE"),
        meaning: "1 = reference switch active high (a normally closed switch to GND, §5.5.2.3)",
    },
    FlagBit {
        bit: 15,
        name: "StopAtFullsteps",
        sqpack: None,
        meaning: "ramps stop only at the nearest full-step position",
    },
];

/// The flag called `name` (§7.1 name or SQPack's `MT_…`, any case).
pub fn flag_by_name(name: &str) -> Option<&'static FlagBit> {
    MOTOR_FLAGS.iter().find(|f| {
        f.name.eq_ignore_ascii_case(name) || f.sqpack.is_some_and(|s| s.eq_ignore_ascii_case(name))
    })
}

/// One step of the `$11` current control: index and percentage of the
/// peak current (§7.1; 0-based as the §6.7 example counts, digest E11).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CurrentStep {
    pub index: u8,
    pub percent: u8,
}

pub const CURRENT_STEPS: &[CurrentStep] = &[
    CurrentStep {
        index: 0,
        percent: 100,
    },
    CurrentStep {
        index: 1,
        percent: 75,
    },
    CurrentStep {
        index: 2,
        percent: 50,
    },
    CurrentStep {
        index: 3,
        percent: 38,
    },
    CurrentStep {
        index: 4,
        percent: 25,
    },
    CurrentStep {
        index: 5,
        percent: 19,
    },
    CurrentStep {
        index: 6,
        percent: 13,
    },
    CurrentStep {
        index: 7,
        percent: 9,
    },
    CurrentStep {
        index: 8,
        percent: 0,
    },
];

/// What a motor is doing, as `$20`, `$21` and `$28` report it (§7.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Activity {
    pub first: u8,
    pub last: u8,
    /// A word without blanks, for reply values (`action=ramp`).
    pub token: &'static str,
    /// How the console shows it.
    pub name: &'static str,
    pub meaning: &'static str,
}

pub const ACTIONS: &[Activity] = &[
    Activity {
        first: 0,
        last: 0,
        token: "inactive",
        name: "inactive",
        meaning: "the motor stands",
    },
    Activity {
        first: 5,
        last: 5,
        token: "ramp",
        name: "ramp",
        meaning: "trapezoidal ramp ($23, $29, $50)",
    },
    Activity {
        first: 10,
        last: 10,
        token: "PI",
        name: "PI",
        meaning: "PI controller ($24)",
    },
    Activity {
        first: 15,
        last: 15,
        token: "rotation",
        name: "rotation",
        meaning: "constant rotation ($25)",
    },
    Activity {
        first: 20,
        last: 29,
        token: "refsearch",
        name: "ref search",
        meaning: "reference switch search ($22; the manual does not say what each of 20-29 means)",
    },
    Activity {
        first: 30,
        last: 30,
        token: "mechref",
        name: "mech ref",
        meaning: "mechanical reference ($28 calls it mechanical calibration)",
    },
];

/// The activity of an action code, if the manual names it.
pub fn activity(code: u8) -> Option<&'static Activity> {
    ACTIONS.iter().find(|a| (a.first..=a.last).contains(&code))
}

/// An action code as a reply value shows it: `ramp`, `refsearch23`, or
/// the number when the manual gives it no meaning.
pub fn action_token(code: u8) -> String {
    match activity(code) {
        Some(a) if a.first != a.last => format!("{}{code}", a.token),
        Some(a) => a.token.to_string(),
        None => code.to_string(),
    }
}

/// The action code a reply value's token stands for.
pub fn action_from_token(token: &str) -> Option<u8> {
    if let Ok(code) = token.parse::<u8>() {
        return Some(code);
    }
    ACTIONS.iter().find_map(|a| {
        if a.first == a.last {
            a.token.eq_ignore_ascii_case(token).then_some(a.first)
        } else {
            let rest = token.get(a.token.len()..)?;
            let head = token.get(..a.token.len())?;
            let code = rest.parse::<u8>().ok()?;
            (head.eq_ignore_ascii_case(a.token) && (a.first..=a.last).contains(&code))
                .then_some(code)
        }
    })
}

// Reply layouts (§7). The first field of `$20`, `$21` and `$30` echoes
// the request's P0.

const POSITION_REPLY: &[Field] = &[
    MOTNO,
    with_unit(
        field("posact", 1, 4, I32, "actual position (signed long)"),
        "µsteps",
    ),
    field("action", 5, 1, FieldKind::Action, "current action"),
    field(
        "stop",
        6,
        1,
        FieldKind::Bit,
        "stop flag: a stop condition has occurred; cleared by this read",
    ),
];

const VELOCITY_REPLY: &[Field] = &[
    MOTNO,
    with_unit(
        field("vact", 1, 2, signed(-32768, 32767), "actual velocity"),
        VELOCITY_UNIT,
    ),
    field("action", 3, 1, FieldKind::Action, "current action"),
];

const ACTIVITIES_REPLY: &[Field] = &[
    field("m0", 0, 1, FieldKind::Action, "action of motor 0 (Motor 1)"),
    field("m1", 1, 1, FieldKind::Action, "action of motor 1 (Motor 2)"),
    field("m2", 2, 1, FieldKind::Action, "action of motor 2 (Motor 3)"),
    field("m3", 3, 1, FieldKind::Action, "action of motor 3 (Motor 4)"),
    field("m4", 4, 1, FieldKind::Action, "action of motor 4 (Motor 5)"),
    field("m5", 5, 1, FieldKind::Action, "action of motor 5 (Motor 6)"),
];

const INPUTS_REPLY: &[Field] = &[
    field("channel", 0, 1, FieldKind::Channel, "channel read"),
    field(
        "analog",
        1,
        2,
        unsigned(0, 65535),
        "analog value 0..1023 (channel 7: 22 counts per volt)",
    ),
    field(
        "ref",
        3,
        1,
        FieldKind::Bit,
        "the channel's reference input (inverted, §7.3)",
    ),
    field(
        "inputs",
        4,
        1,
        FieldKind::InputsAndJumpers,
        "all reference inputs (bit n = motor n) and jumpers JP1 (bit 6), JP2 (bit 7)",
    ),
    field("ttlio1", 5, 1, FieldKind::Bit, "logic state of TTLIO1"),
];

const UNIT_REPLY: &[Field] = &[
    field(
        "firmware",
        0,
        1,
        unsigned(0, 255),
        "firmware revision (148 = V1.4.8)",
    ),
    field(
        "reset",
        1,
        1,
        FieldKind::Bit,
        "reset flag: 1 on the first read after a reset, 0 afterwards",
    ),
    with_unit(
        field(
            "temperature",
            2,
            1,
            signed(-128, 127),
            "temperature of the unit (keep below 85 °C, §3.1)",
        ),
        "°C",
    ),
    field("serial", 3, 2, unsigned(0, 65535), "serial number"),
];

const CAN_RS232_REPLY: &[Field] = &[
    field(
        "txbuffer",
        0,
        1,
        unsigned(0, 255),
        "bytes in the RS-232 send buffer (0 = empty)",
    ),
    field(
        "cts",
        1,
        1,
        FieldKind::Bit,
        "state of the CTS line (inverted)",
    ),
];

const ERASE_REPLY: &[Field] = &[field("erased", 0, 1, unsigned(0, 255), "1 = erase OK")];

const CHECKSUM_REPLY: &[Field] = &[hex(field(
    "checksum",
    0,
    2,
    unsigned(0, 65535),
    "flash checksum (depends on the firmware version)",
))];

const FLASH_DATA_REPLY: &[Field] = &[
    hex(field("d0", 0, 1, unsigned(0, 255), "data byte 0")),
    hex(field("d1", 1, 1, unsigned(0, 255), "data byte 1")),
    hex(field("d2", 2, 1, unsigned(0, 255), "data byte 2")),
    hex(field("d3", 3, 1, unsigned(0, 255), "data byte 3")),
    hex(field("d4", 4, 1, unsigned(0, 255), "data byte 4")),
    hex(field("d5", 5, 1, unsigned(0, 255), "data byte 5")),
    hex(field("d6", 6, 1, unsigned(0, 255), "data byte 6")),
];

const WRITTEN_REPLY: &[Field] = &[field(
    "written",
    0,
    1,
    unsigned(0, 255),
    "1 = writing successful",
)];

/// `$F7`: §7.6 copies the `$F6` table ("1=writing successful"); where the
/// value read goes is unknown (digest E22), so every byte is shown.
const EEPROM_READ_REPLY: &[Field] = &[
    hex(field(
        "p0",
        0,
        1,
        unsigned(0, 255),
        "P0 (\"1=writing successful\", sic)",
    )),
    hex(field("p1", 1, 1, unsigned(0, 255), "P1 (layout unknown)")),
    hex(field("p2", 2, 1, unsigned(0, 255), "P2 (layout unknown)")),
    hex(field("p3", 3, 1, unsigned(0, 255), "P3 (layout unknown)")),
    hex(field("p4", 4, 1, unsigned(0, 255), "P4 (layout unknown)")),
    hex(field("p5", 5, 1, unsigned(0, 255), "P5 (layout unknown)")),
    hex(field("p6", 6, 1, unsigned(0, 255), "P6 (layout unknown)")),
];

const SERVICE: Confirm = Confirm::Always(
    "a service function, not intended for the user: used improperly it can damage the unit \
     permanently (§7.6)",
);

const TARGET: Field = with_unit(
    field("target", 1, 4, I32, "target position (signed long)"),
    "µsteps",
);

const EEPROM_FIELDS: &[Field] = &[
    RESPONSE_REQUIRED,
    hex(field(
        "magic",
        1,
        2,
        unsigned(0, 65535),
        "magic code 2 (not documented)",
    )),
    hex(field("address", 3, 2, unsigned(0, 65535), "EEPROM address")),
    hex(field("value", 5, 2, unsigned(0, 65535), "value")),
];

/// Every command of §7 in the order of §8.
pub const COMMANDS: &[CommandSpec] = &[
    CommandSpec {
        code: 0x10,
        mnemonic: "SetPeakCurrent",
        aliases: &["PeakCurrent", "SetMaxCurrent"],
        heading: "Peak current",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "peak",
                    1,
                    1,
                    unsigned(0, 255),
                    "peak current = DIP-switch current · peak/256 (§7.1 \"value\")",
                ),
                "/256",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "set for motor pairs 0+1, 2+3, 4+5: only motno 0, 2 and 4 take effect (§7.1); \
               default 128",
    },
    CommandSpec {
        code: 0x11,
        mnemonic: "SetCurrentControl",
        aliases: &[],
        heading: "Current control",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            field(
                "I0",
                1,
                1,
                FieldKind::CurrentIndex,
                "power-down current, after T0 at standstill",
            ),
            field(
                "I1",
                2,
                1,
                FieldKind::CurrentIndex,
                "current when the motor stands at its target",
            ),
            field(
                "I2",
                3,
                1,
                FieldKind::CurrentIndex,
                "current at constant velocity",
            ),
            field(
                "I3",
                4,
                1,
                FieldKind::CurrentIndex,
                "current while accelerating",
            ),
            with_unit(
                field(
                    "T0",
                    5,
                    2,
                    unsigned(1, 65535),
                    "power-down delay (also the DelayTestNull settle time, §6.4.6); firmware \
                     before v1.40 needs even values",
                ),
                "2 ms",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "currents as index 0..8 or as percentages (100% 75% 50% 38% 25% 19% 13% 9% 0%); \
               defaults I0 0%, I1 50%, I2 75%, I3 100%, T0 500",
    },
    CommandSpec {
        code: 0x12,
        mnemonic: "SetClockDivider",
        aliases: &["ClockDivider"],
        heading: "Velocity setting",
        section: "7.1",
        class: Class::Setting,
        fields: &[field(
            "clkdiv",
            0,
            1,
            unsigned(0, 31),
            "clock divider of all motors: f_µstep = 20 MHz/(clkdiv+1)·v/2^(14+div)",
        )],
        reply: None,
        confirm: Confirm::Never,
        note: "global to all motors; change it only with all motors stopped; default 5",
    },
    CommandSpec {
        code: 0x13,
        mnemonic: "SetVMinVStart",
        aliases: &["StartVelocity"],
        heading: "Starting velocity",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "vmin",
                    1,
                    2,
                    unsigned(0, 511),
                    "slow velocity for locating the switch, always at div 3 (0 = fastest allowed)",
                ),
                VELOCITY_UNIT,
            ),
            with_unit(
                field(
                    "vstart",
                    3,
                    2,
                    unsigned(1, 511),
                    "start and end velocity of every ramp",
                ),
                VELOCITY_UNIT,
            ),
            field(
                "div",
                5,
                1,
                unsigned(0, 3),
                "velocity predivider of this motor",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "change it only with the motor stopped; vmin <= vstart, vstart < (512 >> \
               (3-div)) - 1; defaults vmin 4, vstart 5, div 2",
    },
    CommandSpec {
        code: 0x14,
        mnemonic: "SetAMaxVMax",
        aliases: &[],
        heading: "Velocity, Acceleration",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            field(
                "amax",
                1,
                2,
                unsigned(1, 32767),
                "acceleration: amax/64 is added to the velocity every 2 ms",
            ),
            with_unit(
                field("vmax", 3, 2, unsigned(1, 511), "maximum velocity"),
                VELOCITY_UNIT,
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "takes effect at once, even while moving; 0 < amax <= 64·vstart; defaults \
               amax 128, vmax 511",
    },
    CommandSpec {
        code: 0x15,
        mnemonic: "SetMotorParameters",
        aliases: &[],
        heading: "Motor Parameters",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "poslimit",
                    1,
                    4,
                    unsigned(0, 0x7FFF_FFFF),
                    "µsteps per revolution (rotary) or total travel (linear): the reference \
                     search drives up to 5/4 of it",
                ),
                "µsteps",
            ),
            hex(field(
                "flags",
                5,
                2,
                FieldKind::Flags(MOTOR_FLAGS),
                "motor type flags by name (NullLeft,MechRef), none, or a number",
            )),
        ],
        reply: None,
        confirm: Confirm::WhenFlag {
            flag: "AutonullCmd",
            why: "AutonullCmd starts a reference search at once (§7.1, the same action as $22)",
        },
        note: "writes the whole flag word: flags not named are cleared (factory word $0AA0 = \
               FilterSwitch,NullCenter,FastRef,DelayTestNull)",
    },
    CommandSpec {
        code: 0x16,
        mnemonic: "SetRefSearchParameters",
        aliases: &[],
        heading: "Reference Search Parameters",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "vrefmax",
                    1,
                    2,
                    unsigned(1, 511),
                    "fast reference search velocity: vstart <= vrefmax <= vmax",
                ),
                VELOCITY_UNIT,
            ),
            hex(field(
                "debounce",
                3,
                2,
                unsigned(0, 65535),
                "debounce mask of the reference input: $0001 = 0 ms, $0003 = 2 ms … $FFFF = 30 ms",
            )),
            field(
                "stopafter",
                5,
                1,
                FieldKind::Bit,
                "1 = stop after the search, 0 = resume the previous action",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "change it only with the motor stopped; defaults vrefmax 100, debounce $0FFF \
               (22 ms), stopafter 0",
    },
    CommandSpec {
        code: 0x17,
        mnemonic: "WriteMotorTable",
        aliases: &[],
        heading: "Write motor characteristics Table",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            field(
                "index",
                0,
                1,
                FieldKind::OneOf(&[0, 4, 8, 12]),
                "first of the four entries written: 0, 4, 8 or 12",
            ),
            field("e0", 1, 1, unsigned(0, 255), "table entry index+0"),
            field("e1", 2, 1, unsigned(0, 255), "table entry index+1"),
            field("e2", 3, 1, unsigned(0, 255), "table entry index+2"),
            field("e3", 4, 1, unsigned(0, 255), "table entry index+3"),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "16 entries, a quarter sine period, common to all motors; default \
               255·sin((i+0.5)·π/32); all 255 gives full steps (§6.3.2)",
    },
    CommandSpec {
        code: 0x18,
        mnemonic: "SetNullPointOffset",
        aliases: &[],
        heading: "Null Point-Offset and -Range",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "nulloffset",
                    1,
                    4,
                    I32,
                    "distance between zero point and reference switch (signed long)",
                ),
                "µsteps",
            ),
            with_unit(
                field(
                    "testnullrange",
                    5,
                    2,
                    unsigned(0, 65535),
                    "± range around zero where the switch may be active",
                ),
                "µsteps",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "defaults nulloffset 0, testnullrange 240 (§6.8)",
    },
    CommandSpec {
        code: 0x19,
        mnemonic: "SetPIParameters",
        aliases: &[],
        heading: "PI-Parameter",
        section: "7.1",
        class: Class::Setting,
        fields: &[
            MOTNO,
            field(
                "propdiv",
                1,
                1,
                unsigned(1, 255),
                "P term = 64·position difference/propdiv",
            ),
            field(
                "intdiv",
                2,
                2,
                unsigned(1, 32767),
                "divisor of the integral part",
            ),
            field(
                "intclip",
                4,
                2,
                unsigned(1, 32767),
                "clip of the position-difference integral",
            ),
            field(
                "intinpclip",
                6,
                1,
                unsigned(0, 255),
                "clip of the position difference integrated each 2 ms (§7.1 labels it \
                 intclip again, digest E14)",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "the controller runs at 500 Hz; defaults 8, 129, 129, 1",
    },
    CommandSpec {
        code: 0x20,
        mnemonic: "GetPositionAndActivity",
        aliases: &[],
        heading: "Query Position and Activity",
        section: "7.2",
        class: Class::Query,
        fields: &[MOTNO, response_at(1)],
        reply: Some(POSITION_REPLY),
        confirm: Confirm::Never,
        note: "answers posact, the action and the stop flag; reading clears the stop flag",
    },
    CommandSpec {
        code: 0x21,
        mnemonic: "GetVelocityAndActivity",
        aliases: &[],
        heading: "Query Velocity and Activity",
        section: "7.2",
        class: Class::Query,
        fields: &[MOTNO, response_at(1)],
        reply: Some(VELOCITY_REPLY),
        confirm: Confirm::Never,
        note: "answers vact (sign = direction) and the action",
    },
    CommandSpec {
        code: 0x22,
        mnemonic: "StartReferenceSearch",
        aliases: &[],
        heading: "Start search of Reference",
        section: "7.2",
        class: Class::Motion,
        fields: &[MOTNO],
        reply: None,
        confirm: Confirm::Always(
            "it stops the motor and drives it to its reference switch or mechanical stop \
             (§7.2)",
        ),
        note: "retries until found or aborted ($2B); then the position is nulloffset and the \
               previous action resumes unless $16 stopafter is 1",
    },
    CommandSpec {
        code: 0x23,
        mnemonic: "StartRamp",
        aliases: &["Ramp"],
        heading: "Start trapezoidal Ramp",
        section: "7.2",
        class: Class::Motion,
        fields: &[MOTNO, TARGET],
        reply: None,
        confirm: Confirm::Never,
        note: "does nothing while the motor is active (a rotation is only stopped); to retarget \
               a ramp send SetTargetPosition then StartRamp with the same target",
    },
    CommandSpec {
        code: 0x24,
        mnemonic: "StartPIControl",
        aliases: &[],
        heading: "Activate PI-Controller on Target Position",
        section: "7.2",
        class: Class::Motion,
        fields: &[MOTNO, TARGET],
        reply: None,
        confirm: Confirm::Always(
            "it switches the motor to PI control and drives it to the target at once, even \
             from standstill (§7.2)",
        ),
        note: "§6.6 calls it SetTargetPosition by mistake: to set a target for $29/$50 use \
               SetTargetPosition ($26)",
    },
    CommandSpec {
        code: 0x25,
        mnemonic: "ConstantRotation",
        aliases: &[],
        heading: "Start Rotation / change Rotation Velocity",
        section: "7.2",
        class: Class::Motion,
        fields: &[
            MOTNO,
            with_unit(
                field(
                    "velocity",
                    1,
                    2,
                    signed(-511, 511),
                    "rotation velocity (0 = decelerate and stop)",
                ),
                VELOCITY_UNIT,
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "takes effect at once, even while the motor is active; changes obey amax",
    },
    CommandSpec {
        code: 0x26,
        mnemonic: "SetTargetPosition",
        aliases: &[],
        heading: "Set Target Position",
        section: "7.2",
        class: Class::Motion,
        fields: &[MOTNO, TARGET],
        reply: None,
        confirm: Confirm::Never,
        note: "changes the target without changing the mode (a running ramp may overshoot and \
               come back); the target for StartRampParallel and StartInterpolation",
    },
    CommandSpec {
        code: 0x27,
        mnemonic: "SetActualPosition",
        aliases: &[],
        heading: "Set actual Position",
        section: "7.2",
        class: Class::Motion,
        fields: &[
            MOTNO,
            with_unit(
                field("position", 1, 4, I32, "new actual position (signed long)"),
                "µsteps",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "can start unintended reference searches when TestNull or StopNull are set",
    },
    CommandSpec {
        code: 0x28,
        mnemonic: "GetAllActivities",
        aliases: &[],
        heading: "Query all Motor Activities, Request delayed Response",
        section: "7.2",
        class: Class::Query,
        fields: &[
            response_at(0),
            optional(
                field(
                    "wait",
                    1,
                    1,
                    FieldKind::MotorMask,
                    "answer only once these motors are inactive (none = at once)",
                ),
                0,
            ),
        ],
        reply: Some(ACTIVITIES_REPLY),
        confirm: Confirm::Never,
        note: "answers the action of all six motors; with a wait mask the answer may come much \
               later (RS-485 with several units: keep the bus idle until it does)",
    },
    CommandSpec {
        code: 0x29,
        mnemonic: "StartRampParallel",
        aliases: &[],
        heading: "Start trapezoidal Ramp in parallel",
        section: "7.2",
        class: Class::Motion,
        fields: &[field(
            "motors",
            0,
            1,
            FieldKind::MotorMask,
            "motors to start towards their SetTargetPosition targets",
        )],
        reply: None,
        confirm: Confirm::Never,
        note: "each motor uses its own vstart/vmax/amax; meant for inactive motors",
    },
    CommandSpec {
        code: 0x2A,
        mnemonic: "StopMotors",
        aliases: &[],
        heading: "Stop Motors selectively or synchronously",
        section: "7.2",
        class: Class::Motion,
        fields: &[field(
            "motors",
            0,
            1,
            FieldKind::MotorMask,
            "motors whose target becomes their actual position",
        )],
        reply: None,
        confirm: Confirm::Never,
        note: "motors faster than vstart overshoot and ramp back to where they were: not an \
               emergency stop",
    },
    CommandSpec {
        code: 0x2B,
        mnemonic: "AbortReferenceSearch",
        aliases: &[],
        heading: "Abort reference search",
        section: "7.2",
        class: Class::Motion,
        fields: &[MOTNO],
        reply: None,
        confirm: Confirm::Never,
        note: "what the motor does afterwards is not stated",
    },
    CommandSpec {
        code: 0x30,
        mnemonic: "GetInputValues",
        aliases: &[],
        heading: "Read Motor Input Channels and additional Inputs",
        section: "7.3",
        class: Class::Query,
        fields: &[
            field(
                "channel",
                0,
                1,
                FieldKind::Channel,
                "0..5 A_In of a motor, 6 external input, 7 supply voltage",
            ),
            response_at(1),
        ],
        reply: Some(INPUTS_REPLY),
        confirm: Confirm::Never,
        note: "answers the analog value, the channel's reference input, all reference inputs \
               with the jumpers, and TTLIO1",
    },
    CommandSpec {
        code: 0x31,
        mnemonic: "SetStopSwitchLimits",
        aliases: &[],
        heading: "Setting the Limits for the Stop Function left/right",
        section: "7.3",
        class: Class::Setting,
        fields: &[
            field(
                "channel",
                0,
                1,
                FieldKind::Channel,
                "A_In channel (0..5 = motor)",
            ),
            field(
                "minleft",
                1,
                2,
                unsigned(0, 65535),
                "stop when moving left below this value (0 = off)",
            ),
            field(
                "maxright",
                3,
                2,
                unsigned(0, 65535),
                "stop when moving right above this value (>= 1023 = off)",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "§6.5.1 calls it CMD $30 by mistake; the voltage should rise to the right",
    },
    CommandSpec {
        code: 0x32,
        mnemonic: "SetOutputs",
        aliases: &[],
        heading: "Setting of additional Outputs",
        section: "7.3",
        class: Class::Setting,
        fields: &[
            field(
                "ttlout1",
                0,
                1,
                FieldKind::Bit,
                "level of TTLOUT1 (1 = READY, 0 = active)",
            ),
            field(
                "ttlio1input",
                1,
                1,
                FieldKind::Bit,
                "TTLIO1 direction (1 = input, 0 = output)",
            ),
            field(
                "ttlio1",
                2,
                1,
                FieldKind::Bit,
                "level of TTLIO1 as an output",
            ),
            field(
                "ready",
                3,
                1,
                FieldKind::Bit,
                "1 = TTLOUT1 works as the ready output",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "TTLOUT1 is high after a reset: programming it low lets the host see a power loss \
               (§3.1)",
    },
    CommandSpec {
        code: 0x33,
        mnemonic: "SetReadyMask",
        aliases: &[],
        heading: "Function of the ready Output",
        section: "7.3",
        class: Class::Setting,
        fields: &[
            field(
                "active",
                0,
                1,
                FieldKind::MotorMask,
                "ready output active while any of these motors moves",
            ),
            field(
                "searching",
                1,
                1,
                FieldKind::MotorMask,
                "ready output active while any of these motors searches its reference",
            ),
        ],
        reply: None,
        confirm: Confirm::Never,
        note: "defaults all, all",
    },
    CommandSpec {
        code: 0x40,
        mnemonic: "SetBaudRate",
        aliases: &[],
        heading: "Adjust RS 232 / RS 485 Baud rate",
        section: "7.4",
        class: Class::Unit,
        fields: &[
            field(
                "divisor",
                0,
                2,
                unsigned(1, 65535),
                "20 MHz/(16·baud): 130 = 9600, 65 = 19200, 33 = 38400, 22 = 57600",
            ),
            with_unit(
                field(
                    "delay",
                    2,
                    2,
                    unsigned(1, 1000),
                    "transmitter switch-over delay (default 3 = 6 ms)",
                ),
                "2 ms",
            ),
        ],
        reply: None,
        confirm: Confirm::Always(
            "the unit changes its baud rate and the console does not follow: reconnect at the \
             new rate (§7.4; not stored, a reset restores the jumpers' rate)",
        ),
        note: "not stored permanently; to change only the delay resend the current divisor",
    },
    CommandSpec {
        code: 0x41,
        mnemonic: "SetPacketTimeout",
        aliases: &[],
        heading: "Setting of Timeout for Abort of Packet",
        section: "7.4",
        class: Class::Unit,
        fields: &[with_unit(
            field(
                "timeout",
                0,
                2,
                unsigned(2, 65535),
                "a frame not complete within this time is dropped",
            ),
            "2 ms",
        )],
        reply: None,
        confirm: Confirm::Never,
        note: "the factory value is not given",
    },
    CommandSpec {
        code: 0x42,
        mnemonic: "SetUnitAddress",
        aliases: &[],
        heading: "Change Address of Unit",
        section: "7.4",
        class: Class::Unit,
        fields: &[field(
            "address",
            0,
            1,
            unsigned(0, 255),
            "new RS-232/RS-485 address",
        )],
        reply: None,
        confirm: Confirm::Always(
            "the unit answers only at the new address from then on and the console does not \
             follow: change :address (the rotary switches set it again at a reset)",
        ),
        note: "whether the change survives a reset is not stated",
    },
    CommandSpec {
        code: 0x43,
        mnemonic: "GetUnitInformation",
        aliases: &[],
        heading: "Read out Information about Unit",
        section: "7.4",
        class: Class::Query,
        fields: &[response_at(0)],
        reply: Some(UNIT_REPLY),
        confirm: Confirm::Never,
        note: "answers firmware revision, reset flag (cleared by this read), temperature and \
               serial number",
    },
    CommandSpec {
        code: 0x44,
        mnemonic: "ConfigRS232ViaCAN",
        aliases: &[],
        heading: "Configure /query RS 232-operating Mode via CAN",
        section: "7.4",
        class: Class::Query,
        fields: &[
            response_at(0),
            optional(
                field(
                    "forward",
                    1,
                    1,
                    unsigned(0, 255),
                    "CAN response address for bytes received on RS-232 (upper 8 ID bits)",
                ),
                0,
            ),
            optional(
                field(
                    "bytes",
                    2,
                    1,
                    unsigned(0, 8),
                    "bytes per forwarded packet, 1..8 (0 = off)",
                ),
                0,
            ),
        ],
        reply: Some(CAN_RS232_REPLY),
        confirm: Confirm::Never,
        note: "CAN mode only (§6.1.5)",
    },
    CommandSpec {
        code: 0x50,
        mnemonic: "StartInterpolation",
        aliases: &[],
        heading: "Start multi-dimensional linear Interpolation",
        section: "7.5",
        class: Class::Motion,
        fields: &[field(
            "motors",
            0,
            1,
            FieldKind::MotorMask,
            "motors moved together to their SetTargetPosition targets",
        )],
        reply: None,
        confirm: Confirm::Never,
        note: "the motors must stand; all arrive together; query every one before the next \
               command",
    },
    CommandSpec {
        code: 0xCC,
        mnemonic: "HardwareReset",
        aliases: &[],
        heading: "Complete Hardware Reset",
        section: "7.4",
        class: Class::Unit,
        fields: &[optional(
            hex(field(
                "p0",
                0,
                1,
                unsigned(0, 255),
                "\"HW-Reset\": the manual does not give the value (the console sends $00)",
            )),
            0,
        )],
        reply: None,
        confirm: Confirm::Always(
            "every setting is replaced by the factory defaults; the unit takes about 1 s and \
             usually sends one $00 byte (§7.4)",
        ),
        note: "afterwards the $43 reset flag is 1",
    },
    CommandSpec {
        code: 0xF2,
        mnemonic: "FlashEnableErase",
        aliases: &[],
        heading: "Enable erasing and writing the Flash-Memory",
        section: "7.6",
        class: Class::Service,
        fields: &[
            RESPONSE_REQUIRED,
            hex(field(
                "magic",
                1,
                4,
                unsigned(0, 0xFFFF_FFFF),
                "magic code (not documented)",
            )),
        ],
        reply: Some(ERASE_REPLY),
        confirm: SERVICE,
        note: "service function",
    },
    CommandSpec {
        code: 0xF3,
        mnemonic: "FlashProgram",
        aliases: &[],
        heading: "Program Flash Memory",
        section: "7.6",
        class: Class::Service,
        fields: &[
            hex(field("d0", 0, 1, unsigned(0, 255), "data byte 0")),
            hex(field("d1", 1, 1, unsigned(0, 255), "data byte 1")),
            hex(field("d2", 2, 1, unsigned(0, 255), "data byte 2")),
            hex(field("d3", 3, 1, unsigned(0, 255), "data byte 3")),
            hex(field("d4", 4, 1, unsigned(0, 255), "data byte 4")),
            hex(field("d5", 5, 1, unsigned(0, 255), "data byte 5")),
            hex(field("d6", 6, 1, unsigned(0, 255), "data byte 6")),
        ],
        reply: None,
        confirm: SERVICE,
        note: "service function: only after erasing, not to be interrupted",
    },
    CommandSpec {
        code: 0xF4,
        mnemonic: "FlashChecksum",
        aliases: &[],
        heading: "Query flash Memory Check-Sum and abort Programming if necessary",
        section: "7.6",
        class: Class::Service,
        fields: &[response_at(0)],
        reply: Some(CHECKSUM_REPLY),
        confirm: SERVICE,
        note: "service function: also aborts programming and resets the FlashRead pointer",
    },
    CommandSpec {
        code: 0xF5,
        mnemonic: "FlashRead",
        aliases: &[],
        heading: "Read out Flash-Memory",
        section: "7.6",
        class: Class::Service,
        fields: &[response_at(0)],
        reply: Some(FLASH_DATA_REPLY),
        confirm: SERVICE,
        note: "service function: seven bytes at an auto-incrementing pointer",
    },
    CommandSpec {
        code: 0xF6,
        mnemonic: "EepromWrite",
        aliases: &[],
        heading: "Write EEPROM",
        section: "7.6",
        class: Class::Service,
        fields: EEPROM_FIELDS,
        reply: Some(WRITTEN_REPLY),
        confirm: SERVICE,
        note: "service function",
    },
    CommandSpec {
        code: 0xF7,
        mnemonic: "EepromRead",
        aliases: &[],
        heading: "Read EEPROM",
        section: "7.6",
        class: Class::Service,
        fields: EEPROM_FIELDS,
        reply: Some(EEPROM_READ_REPLY),
        confirm: SERVICE,
        note: "service function; §7.6 documents it exactly as EepromWrite (sic), so its layout \
               is a guess",
    },
];

/// A name the manual uses for a command it gives no frame layout for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Undocumented {
    pub name: &'static str,
    pub code: u8,
    pub why: &'static str,
}

/// Commands named outside §7 whose frame is unknown: the console sends them
/// only as raw frames.
pub const UNDOCUMENTED: &[Undocumented] = &[Undocumented {
    name: "SetMargin",
    code: 0x1A,
    why: "§6.5.3 names SetMargin (CMD $1A) but §7 and §8 give no layout (digest E19)",
}];

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
mod tests {
    use super::*;

    #[test]
    fn every_command_is_listed_once_in_the_order_of_section_8() {
        let codes: Vec<u8> = COMMANDS.iter().map(|c| c.code).collect();
        assert_eq!(
            codes,
            [
                0x10, 0x11, 0x12, 0x13, 0x14, 0x15, 0x16, 0x17, 0x18, 0x19, 0x20, 0x21, 0x22, 0x23,
                0x24, 0x25, 0x26, 0x27, 0x28, 0x29, 0x2A, 0x2B, 0x30, 0x31, 0x32, 0x33, 0x40, 0x41,
                0x42, 0x43, 0x44, 0x50, 0xCC, 0xF2, 0xF3, 0xF4, 0xF5, 0xF6, 0xF7
            ]
        );
        let mut names: Vec<String> = COMMANDS
            .iter()
            .flat_map(|c| std::iter::once(c.mnemonic).chain(c.aliases.iter().copied()))
            .map(str::to_ascii_lowercase)
            .collect();
        let all = names.len();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), all, "every name is unique");
    }

    #[test]
    fn fields_fit_in_p0_to_p6_without_overlap() {
        for spec in COMMANDS {
            for layout in std::iter::once(spec.fields).chain(spec.reply) {
                let mut used = [false; 7];
                for f in layout {
                    assert!(
                        f.width >= 1 && f.offset + f.width <= 7,
                        "{} {}",
                        spec.mnemonic,
                        f.name
                    );
                    for b in &mut used[f.offset..f.offset + f.width] {
                        assert!(!*b, "{} {} overlaps", spec.mnemonic, f.name);
                        *b = true;
                    }
                    let (min, max) = f.bounds();
                    let bits = 8 * f.width as u32;
                    let (lo, hi) = if f.signed() {
                        (-(1i64 << (bits - 1)), (1i64 << (bits - 1)) - 1)
                    } else {
                        (0, (1i64 << bits) - 1)
                    };
                    assert!(
                        lo <= min && max <= hi,
                        "{} {} fits its bytes",
                        spec.mnemonic,
                        f.name
                    );
                }
            }
            // Optional operands come last, so that positions stay in field order.
            let first_optional = spec.fields.iter().position(|f| f.default.is_some());
            if let Some(first) = first_optional {
                assert!(
                    spec.fields[first..].iter().all(|f| f.default.is_some()),
                    "{}",
                    spec.mnemonic
                );
            }
        }
    }

    #[test]
    fn only_the_queries_and_service_commands_answer() {
        let replying: Vec<u8> = COMMANDS
            .iter()
            .filter(|c| c.answers())
            .map(|c| c.code)
            .collect();
        assert_eq!(
            replying,
            [
                0x20, 0x21, 0x28, 0x30, 0x43, 0x44, 0xF2, 0xF4, 0xF5, 0xF6, 0xF7
            ]
        );
        assert!(!is_replying(0x00), "no reply starts with $00 (digest D1.4)");
    }

    #[test]
    fn flag_bits_follow_section_7_1_and_the_5_5_3_examples() {
        let word = |names: &[&str]| -> i64 {
            names
                .iter()
                .map(|n| flag_by_name(n).expect("a flag").mask())
                .sum()
        };
        // §5.5.3.2: P5 = $10, P6 = $04.
        assert_eq!(word(&["MT_NULLLEFT", "MT_MECHREF"]), 0x0410);
        // §5.5.3.4: P5 = $50, P6 = $40.
        assert_eq!(word(&["NullLeft", "StopNull", "NullPositive"]), 0x4050);
        // §6.8 factory word.
        assert_eq!(
            word(&["DelayTestNull", "NullCenter", "FilterSwitch", "FastRef"]),
            0x0AA0
        );
        // E13: StopNoRef is P6 bit 5.
        assert_eq!(
            flag_by_name("stopnoref").map(FlagBit::place),
            Some("P6.5".into())
        );
        assert_eq!(MOTOR_FLAGS.len(), 16);
    }

    #[test]
    fn action_codes_read_as_words_and_back() {
        for code in [0u8, 5, 10, 15, 20, 23, 29, 30, 7, 255] {
            assert_eq!(action_from_token(&action_token(code)), Some(code), "{code}");
        }
        assert_eq!(action_token(5), "ramp");
        assert_eq!(action_token(23), "refsearch23");
        assert_eq!(action_token(31), "31");
        assert_eq!(action_from_token("refsearch31"), None);
        assert_eq!(activity(25).map(|a| a.name), Some("ref search"));
    }

    #[test]
    fn current_steps_are_the_0_based_list() {
        let percents: Vec<u8> = CURRENT_STEPS.iter().map(|s| s.percent).collect();
        assert_eq!(percents, [100, 75, 50, 38, 25, 19, 13, 9, 0]);
        // E11: 19 % is index 5.
        assert_eq!(
            CURRENT_STEPS
                .iter()
                .find(|s| s.percent == 19)
                .map(|s| s.index),
            Some(5)
        );
    }

    #[test]
    fn names_and_codes_find_their_rows() {
        assert_eq!(by_name("peakcurrent").map(|c| c.code), Some(0x10));
        assert_eq!(by_name("SetMaxCurrent").map(|c| c.code), Some(0x10));
        assert_eq!(by_name("ramp").map(|c| c.code), Some(0x23));
        assert_eq!(
            by_name("SetTargetPosition").map(|c| c.code),
            Some(0x26),
            "E15"
        );
        assert_eq!(
            by_code(0x31).map(|c| c.mnemonic),
            Some("SetStopSwitchLimits")
        );
        assert_eq!(by_code(0x1A), None);
        assert_eq!(
            by_code(0x23).map(CommandSpec::syntax).as_deref(),
            Some("StartRamp motno target")
        );
        assert_eq!(
            by_code(0x20).map(CommandSpec::syntax).as_deref(),
            Some("GetPositionAndActivity motno [resp]")
        );
        assert_eq!(motor_name(2), "motor 2 (Motor 3)");
    }
}
