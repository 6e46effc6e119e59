//! The MCCL command set of Ch3–Ch13 as data: one row per mnemonic with its
//! binary code (Ch3 quick reference), the axis it takes, its parameter and
//! range (the "MCCL command:" line of its page), what it prints, whether it
//! holds the interpreter, whether a background task may run it, and what it
//! means. The parser, the checker, the reply reader, completion, help and
//! the parameter table all read this table.
//!
//! Mnemonics are written here in ASCII: the manual prints several with
//! Cyrillic look-alike letters (`ТВ`, `ТК`, `то`, `СН`…) and `OO` as `00`
//! (digest §1); [`super::line`] maps those letters before looking a
//! mnemonic up.
//!
//! Where the manual contradicts itself the row follows the page text and
//! its examples over the syntax line, and says so in its meaning:
//! - `CA`, `CR`, `RR`: syntax "n ≥ 0", examples `1CR-20000`, `1RR-10000`
//!   (Ch7) — any sign.
//! - `BC`, `CB`: syntax "n ≥ 0", text "a negative n stops" — any n ≤ 1024.
//! - `OM`: syntax "0, 1", text explains 0–3 (PWM modes).
//! - `SE`: syntax "n ≤ 0", examples `1SE1024` — n ≥ 0.
//! - `SM`: syntax "n > 0", text "SM0 ends" — 0–135.
//! - `UA`: syntax "n > 0, ≤ 4", text "defaults to 0", up to 8 axes — 0–8.
//! - `PC`: syntax "n > 0", text "PC0 inhibits the prompt" — 0–255.
//! - `ID`: syntax "n ≤ 6", table lists 7 — 0–7.
//! - `TR`: syntax "n ≤ 255", 1000 registers (Ch4) — 0–999.
//! - `LM`: syntax "0 - 136", text "hard + soft … 128 plus desired mode" —
//!   up to 128 + 2 + 8 = 138.
//! - `SS`: range garbled, examples 5, −.1, −1000 — any.

use std::fmt;

/// The chapter a command is described in (Ch5–Ch13).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Group {
    Setup,
    Mode,
    Motion,
    Reporting,
    Io,
    Macro,
    Register,
    Sequence,
    Misc,
}

impl Group {
    pub fn chapter(self) -> u8 {
        match self {
            Group::Setup => 5,
            Group::Mode => 6,
            Group::Motion => 7,
            Group::Reporting => 8,
            Group::Io => 9,
            Group::Macro => 10,
            Group::Register => 11,
            Group::Sequence => 12,
            Group::Misc => 13,
        }
    }

    pub fn title(self) -> &'static str {
        match self {
            Group::Setup => "Setup",
            Group::Mode => "Mode",
            Group::Motion => "Motion",
            Group::Reporting => "Reporting",
            Group::Io => "I/O",
            Group::Macro => "Macro and Multi-tasking",
            Group::Register => "Register",
            Group::Sequence => "Sequence (If/Then)",
            Group::Misc => "Miscellaneous",
        }
    }
}

/// Which axis a command takes (Ch2 "MCCL Command Syntax").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AxisRule {
    /// Acts on one axis; 0 (all) is not documented for it.
    One,
    /// Acts on one axis, or on every axis with 0 (`0MA`, `AB`, `0ST`…):
    /// only where its page says so (Ch2).
    OneOrAll,
    /// May take an axis (`5ID0` per axis, `ID7` for the tasks; `UT` per
    /// interface; `RT` without one resets the controller).
    Optional,
    /// Takes none (registers, macros, I/O channels, program flow). Digits
    /// written before it only set the line's current axis (digest §20 on
    /// `1JR-3`).
    None,
}

/// One end of a range of real values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bound {
    pub value: f64,
    /// Whether `value` itself is allowed.
    pub inclusive: bool,
}

/// The values a real ("integer or real") parameter takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RealRange {
    pub min: Option<Bound>,
    pub max: Option<Bound>,
}

impl RealRange {
    pub const ANY: RealRange = RealRange {
        min: None,
        max: None,
    };
    /// `n ≥ 0`.
    pub const NON_NEGATIVE: RealRange = RealRange::at_least(0.0);
    /// `n > 0`.
    pub const POSITIVE: RealRange = RealRange {
        min: Some(Bound {
            value: 0.0,
            inclusive: false,
        }),
        max: None,
    };

    pub const fn at_least(min: f64) -> RealRange {
        RealRange {
            min: Some(Bound {
                value: min,
                inclusive: true,
            }),
            max: None,
        }
    }

    pub const fn between(min: f64, max: f64) -> RealRange {
        RealRange {
            min: Some(Bound {
                value: min,
                inclusive: true,
            }),
            max: Some(Bound {
                value: max,
                inclusive: true,
            }),
        }
    }

    pub fn contains(&self, value: f64) -> bool {
        let above = self.min.is_none_or(|b| {
            if b.inclusive {
                value >= b.value
            } else {
                value > b.value
            }
        });
        let below = self.max.is_none_or(|b| {
            if b.inclusive {
                value <= b.value
            } else {
                value < b.value
            }
        });
        above && below && value.is_finite()
    }
}

impl fmt::Display for RealRange {
    /// `≥ 0`, `> 0`, `0.000153..10`, `any`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.min, self.max) {
            (None, None) => f.write_str("any value"),
            (Some(min), None) => {
                let op = if min.inclusive { "≥" } else { ">" };
                write!(f, "{op} {}", min.value)
            }
            (None, Some(max)) => {
                let op = if max.inclusive { "≤" } else { "<" };
                write!(f, "{op} {}", max.value)
            }
            (Some(min), Some(max)) if min.inclusive && max.inclusive => {
                write!(f, "{}..{}", min.value, max.value)
            }
            (Some(min), Some(max)) => {
                let low = if min.inclusive { "≥" } else { ">" };
                let high = if max.inclusive { "≤" } else { "<" };
                write!(f, "{low} {} and {high} {}", min.value, max.value)
            }
        }
    }
}

/// What follows the mnemonic. An omitted parameter is 0 (Ch2: "If no
/// parameter value is given with the command the default value of 0 will
/// be used"); any numeric parameter may be `@n`, the contents of register
/// n (Ch4 "Controller User Registers").
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Param {
    /// Nothing (`MN`, `PM`, `VE`).
    None,
    /// An integer from `min` to `max` (a register, a macro, a channel, a
    /// code).
    Integer { min: i64, max: i64 },
    /// One of the listed integers (`IM` 0, 1, 128).
    OneOf(&'static [i64]),
    /// "integer or real" in a range (positions, speeds, gains, seconds).
    Real(RealRange),
    /// Reporting precision `p` = 0, .1 … .5: the tenths digit is the number
    /// of decimals in the reply (Ch8 introduction).
    Precision,
    /// `TS n`: a status word (0, 64, 96, 128, 160) or one of its bits 1–31
    /// (Ch8 TS).
    Status,
    /// `TRn.p`, `TR.p`: register `n` (0–999, Ch4 "Controller User
    /// Registers"; none is the accumulator) and, in the tenths digit, the
    /// reporting precision as [`Param::Precision`] (Ch4 register table).
    RegisterPrecision,
    /// A string in double quotes (`LU"STATUS"`, `OT"…"`).
    Text,
    /// An optional string (`BK`, `BK"wait"`).
    OptionalText,
    /// `HE`: 0, 1 or a mnemonic in quotes (Ch13).
    Help,
    /// Listed in the Ch3 quick reference only, without a page: what it
    /// takes is not known; an optional number is passed on unchecked.
    Undocumented,
}

/// What a command prints on the interface that issued it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Output {
    Nothing,
    /// One reply line `AA value`: the 2-digit axis (channel, register)
    /// field and the value (Ch8).
    Value,
    /// Text of any number of lines (`VE`, `ID`, `HE`, `TM`, `DE`, `OT`,
    /// `OD`).
    Text,
}

/// Whether a command may hold the foreground interpreter for long, so that
/// the line it is on does not finish at once (Ch2: "While the controller is
/// executing commands, it will ignore all alphanumeric keys").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Blocks {
    No,
    /// Waits for time, motion, a position, an input or a capture; Escape
    /// aborts it (Ch12 WA/WF/WN/WP/WR, Ch7 FE/FI).
    Waits,
    /// Runs a macro in the foreground until it ends (Ch4: "the host will
    /// not be able to communicate with the controller until the macro has
    /// terminated").
    RunsMacro,
    /// Repeats or jumps: the line may run for ever (`RP` without a count,
    /// a backward `JR`).
    Loops,
    /// `BK"text"`: prints the text and single-steps, waiting for a key
    /// (Ch10 BK).
    Steps,
}

/// Why a command deserves care before it is sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Caution {
    /// "reserved for factory use only" (DW, EN, EF, WB…WD).
    FactoryOnly,
    /// `EI`: "should only be issued by the MCAPI … issuing it via WinControl
    /// will cause a malfunction" (Ch5).
    McapiOnly,
    /// `RT` resets an axis or the whole controller.
    Resets,
}

/// One MCCL command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommandSpec {
    /// Two upper-case ASCII letters.
    pub mnemonic: &'static str,
    /// Binary command code from the Ch3 tables; `None` where none is
    /// printed (ID, NP, FM, FT, ME, OT, EE, PK, DE, HE: digest §19 #2).
    pub code: Option<u16>,
    /// The name the Ch3 table gives it.
    pub name: &'static str,
    pub group: Group,
    pub axis: AxisRule,
    pub param: Param,
    pub output: Output,
    pub blocks: Blocks,
    /// Whether a background task may run it: not the reporting commands
    /// (Ch4 "MCCL Multi-Tasking": "With the exception of reporting
    /// commands…").
    pub in_task: bool,
    pub caution: Option<Caution>,
    /// The kinds of axis or function it applies to, as its page says.
    pub applies: &'static str,
    /// One line from its page.
    pub meaning: &'static str,
}

impl CommandSpec {
    /// The section of the manual (`Ch7 MA`).
    pub fn section(&self) -> String {
        format!("Ch{} {}", self.group.chapter(), self.mnemonic)
    }

    /// The syntax as the manual writes it: `aMAn`, `TCx`, `LU"s"`, `aTPp`.
    pub fn syntax(&self) -> String {
        let axis = match self.axis {
            AxisRule::One | AxisRule::OneOrAll => "a",
            AxisRule::Optional => "[a]",
            AxisRule::None => "",
        };
        let param = match self.param {
            Param::None => "",
            Param::Precision => "p",
            Param::RegisterPrecision => "n.p",
            Param::Text => "\"s\"",
            Param::OptionalText => "[\"s\"]",
            Param::Help => "n|\"mm\"",
            Param::Undocumented => "[n]",
            Param::Integer { .. } | Param::OneOf(_) | Param::Real(_) | Param::Status => "n",
        };
        format!("{axis}{}{param}", self.mnemonic)
    }

    /// Whether it only reads (nothing in the controller changes): the Tell
    /// and display commands. `CG`/`GC` load the accumulator and do not.
    pub fn only_reads(&self) -> bool {
        self.output != Output::Nothing && !matches!(self.mnemonic, "OT" | "OD" | "BK")
    }

    /// The values of its parameter, for help: `0..255`, `≥ 0`, `"s"`.
    pub fn values(&self) -> String {
        match self.param {
            Param::None => "no parameter".into(),
            Param::Integer { min, max } => format!("integer {min}..{max}"),
            Param::OneOf(values) => {
                let list: Vec<String> = values.iter().map(i64::to_string).collect();
                format!("one of {}", list.join(", "))
            }
            Param::Real(range) => format!("integer or real, {range}"),
            Param::Precision => "precision 0, .1 … .5 (decimals in the reply)".into(),
            Param::RegisterPrecision => {
                "register 0..999 and precision .1 … .5 (decimals in the reply): 5.2, .3".into()
            }
            Param::Status => {
                "0 primary word, 1–31 its bits; 64/96/128/160 aux, profile, trajectory, \
                 encoder-fault words, +1–31 their bits"
                    .into()
            }
            Param::Text => "a string in double quotes".into(),
            Param::OptionalText => "nothing, or a string in double quotes".into(),
            Param::Help => "0 (mnemonics), 1 (variable names) or \"mm\" (a command)".into(),
            Param::Undocumented => "not described in the manual".into(),
        }
    }
}

/// A row of the table: one argument per column.
#[allow(clippy::too_many_arguments)]
const fn spec(
    mnemonic: &'static str,
    code: Option<u16>,
    group: Group,
    name: &'static str,
    axis: AxisRule,
    param: Param,
    applies: &'static str,
    meaning: &'static str,
) -> CommandSpec {
    CommandSpec {
        mnemonic,
        code,
        name,
        group,
        axis,
        param,
        output: Output::Nothing,
        blocks: Blocks::No,
        in_task: true,
        caution: None,
        applies,
        meaning,
    }
}

impl CommandSpec {
    const fn reports(mut self, output: Output) -> Self {
        self.output = output;
        // Ch4: reporting commands cannot run in a background task.
        self.in_task = false;
        self
    }

    const fn blocking(mut self, blocks: Blocks) -> Self {
        self.blocks = blocks;
        self
    }

    const fn caution(mut self, caution: Caution) -> Self {
        self.caution = Some(caution);
        self
    }
}

use AxisRule::{None as NoAxis, One, OneOrAll, Optional};
use Group::*;

const ANY: Param = Param::Real(RealRange::ANY);
const NON_NEGATIVE: Param = Param::Real(RealRange::NON_NEGATIVE);
const POSITIVE: Param = Param::Real(RealRange::POSITIVE);
const NONE: Param = Param::None;
const fn int(min: i64, max: i64) -> Param {
    Param::Integer { min, max }
}
/// A macro number (MD/MC/MJ/GT "n ≥ 0, < 1000").
const MACRO: Param = int(0, 999);
/// A user register (R0–R999, Ch4 "Controller User Registers").
const REGISTER: Param = int(0, 999);
/// A digital I/O channel (Ch9: 1–16 TTL in, 17–32 opto in, 33–48 TTL out,
/// 49–64 open-collector out).
const CHANNEL: Param = int(1, 64);
/// A point of the point memory (LP/LT/MP 0–255).
const POINT: Param = int(0, 255);
/// A sample of the record buffer (DA/DO/DQ/DR "p ≥ 0, < 1024").
const SAMPLE: Param = int(0, 1023);
const I32_MAX: i64 = i32::MAX as i64;
const I32_MIN: i64 = i32::MIN as i64;
const ANY_INT: Param = int(I32_MIN, I32_MAX);

const SERVO_STEPPER: &str = "servo, stepper";
const CLOSED_LOOP: &str = "servo, closed-loop stepper";
const SERVO: &str = "servo";
const STEPPER: &str = "stepper";
const OPEN_STEPPER: &str = "open-loop stepper";
const FLOW: &str = "program flow";
const REGISTERS: &str = "registers";
const IO: &str = "digital I/O";
const OTHER: &str = "other";
const UNDESCRIBED: &str = "Ch3 quick reference only: no description in the manual";

/// Every command of Ch5–Ch13 and the Ch3 quick reference, by chapter.
#[rustfmt::skip]
pub const COMMANDS: &[CommandSpec] = &[
    // Ch5 Setup.
    spec("AG", Some(0xE2), Setup, "set Acceleration feed-forward Gain", One, ANY, SERVO,
        "output += gain × commanded acceleration, only while accelerating; typically negative"),
    spec("AH", Some(0xEA), Setup, "Auxiliary encoder define Home", One, ANY, STEPPER,
        "set the auxiliary encoder position to n"),
    spec("BD", Some(0xD0), Setup, "Backlash compensation Distance", One, ANY, SERVO,
        "backlash distance (half the take-up), used while BN is on"),
    spec("DB", Some(0x76), Setup, "set position DeadBand", One, NON_NEGATIVE, SERVO,
        "position deadband for At Target (status bit 2)"),
    spec("DG", Some(0xE3), Setup, "set Deceleration feed-forward Gain", One, ANY, SERVO,
        "output += gain × commanded deceleration, only while decelerating"),
    spec("DH", Some(0x23), Setup, "Define Home", One, ANY, SERVO_STEPPER,
        "define the current position as n"),
    spec("DI", Some(0x24), Setup, "Direction", One, int(0, 1), SERVO_STEPPER,
        "velocity-mode direction: 0 positive, 1 negative"),
    spec("DS", Some(0x75), Setup, "Deceleration Set", One, POSITIVE, SERVO_STEPPER,
        "deceleration, counts (steps) per second²"),
    spec("DT", Some(0xC5), Setup, "Delay at Target", One, NON_NEGATIVE, SERVO,
        "seconds inside the deadband before At Target is set"),
    spec("EE", None, Setup, "Encoder fail detection", One, int(0, 2), SERVO_STEPPER,
        "encoder fault detection: 0 off, 1 on, 2 auxiliary (not supported); after MN a fault \
         sets status bit 14 (syntax line mangled \"n = 1 - 8\", table 0–2)"),
    spec("EI", Some(0x7C), Setup, "Enable Interrupts", One, int(0, 0xFFFF_FFFF), SERVO_STEPPER,
        "host-interrupt mask over the primary status bits: MCAPI only, \"issuing it via \
         WinControl will cause a malfunction\"")
        .caution(Caution::McapiOnly),
    spec("ES", Some(0xE5), Setup, "Encoder counts / Steps Scale", One, NON_NEGATIVE,
        "closed-loop stepper", "steps per encoder count (default 1); set before closed-loop motion"),
    spec("FC", Some(0x40), Setup, "Full Current", One, NONE, STEPPER,
        "full/half-current output low (full current)"),
    spec("FF", Some(0x33), Setup, "amplifier Fault input ofF", One, NONE, SERVO_STEPPER,
        "disable amplifier/driver fault input checking"),
    spec("FL", Some(0x151), Setup, "IIR Filter Load coefficients", Optional, Param::Undocumented,
        SERVO, UNDESCRIBED),
    spec("FN", Some(0x32), Setup, "amplifier Fault input oN", One, NONE, SERVO_STEPPER,
        "enable fault checking: an active input turns the motor off and sets status bit 9 until MN"),
    spec("FR", Some(0x27), Setup, "set derivative sampling period", One, int(0, I32_MAX), SERVO,
        "derivative sampling period = (n + 1) × servo sample period (integer; default 0)"),
    spec("HC", Some(0x41), Setup, "Half Current", One, NONE, STEPPER,
        "full/half-current output high (half current)"),
    spec("HL", Some(0xD3), Setup, "set motion High Limit", One, ANY, SERVO_STEPPER,
        "high soft limit (enabled by LN)"),
    spec("HS", Some(0xE8), Setup, "set High Speed", One, NONE, SERVO_STEPPER,
        "servo loop 4 kHz; stepper range 500 p/s – 5 Mp/s"),
    spec("IL", Some(0x28), Setup, "set Integration Limit", One, NON_NEGATIVE, CLOSED_LOOP,
        "integration limit (counts × PID period)"),
    spec("IO", Some(0x205), Setup, "Integral option", One, int(0, 2), CLOSED_LOOP,
        "integral term: 0 always on, 1 frozen during motion, 2 zeroed at motion start"),
    spec("LA", Some(0x330), Setup, "Load commutation phase A", Optional, Param::Undocumented,
        SERVO, UNDESCRIBED),
    spec("LB", Some(0x331), Setup, "load commutation phase B", Optional, Param::Undocumented,
        SERVO, UNDESCRIBED),
    spec("LD", Some(0x333), Setup, "Load commutation Divisor", Optional, Param::Undocumented,
        SERVO, UNDESCRIBED),
    spec("LE", Some(0x332), Setup, "Load commutation encoder prescale", Optional,
        Param::Undocumented, SERVO, UNDESCRIBED),
    spec("LF", Some(0x36), Setup, "motion Limits ofF", One, int(0, 15), SERVO_STEPPER,
        "disable limits, coded as LN (Ch3 gives LF and LS the same code 36h)"),
    spec("LL", Some(0xD2), Setup, "set motion Low Limit", One, ANY, SERVO_STEPPER,
        "low soft limit (enabled by LN)"),
    spec("LM", Some(0x34), Setup, "Limit Mode", One, int(0, 138), SERVO_STEPPER,
        "limit reaction: hard 0 off/1 abrupt/2 decelerate + soft 0/4 abrupt/8 decelerate \
         + 128 invert the hard-limit inputs (syntax prints 0–136; 128 + 2 + 8 is 138)"),
    spec("LN", Some(0x35), Setup, "motion Limits oN", One, int(0, 15), SERVO_STEPPER,
        "enable limits: 0 all four, else 1 hard +, 2 hard −, 4 soft high, 8 soft low"),
    spec("LR", Some(0x334), Setup, "Load commutation repeat count", Optional,
        Param::Undocumented, SERVO, UNDESCRIBED),
    spec("LS", Some(0x36), Setup, "set Low Speed", One, NONE, SERVO_STEPPER,
        "servo loop 1 kHz; stepper range 0.1 – 78,000 p/s"),
    spec("MS", Some(0xE7), Setup, "set Medium Speed", One, NONE, SERVO_STEPPER,
        "servo loop 2 kHz; stepper range 500 – 650,000 p/s"),
    spec("MV", Some(0xC4), Setup, "set Minimum Velocity", One, NON_NEGATIVE, STEPPER,
        "start/stop velocity, steps/s (typically 1–10 % of SV)"),
    spec("NF", Some(0x150), Setup, "No IIR Filter", Optional, Param::Undocumented, SERVO,
        UNDESCRIBED),
    // The syntax line says "n > 0, <= 10" but the text "between 0 and 10",
    // and 0 is what a controller holds until OB is given (OUTDBAND reads 0):
    // 0 turns the deadband off, so it is taken.
    spec("OB", Some(0xC3), Setup, "set the Output deadBand", One,
        Param::Real(RealRange::between(0.0, 10.0)),
        SERVO, "output deadband, volts (0 off, ≤ 10): output magnitude increased by n"),
    spec("OM", Some(0xD8), Setup, "set Output Mode", One, int(0, 3), SERVO_STEPPER,
        "servo 0 ±10 V, 1 0–10 V, 2 bipolar PWM, 3 unipolar PWM; stepper 0 pulse+direction, \
         1 CW/CCW (syntax line says 0, 1)"),
    spec("OO", Some(0xCB), Setup, "set the Output Offset", One,
        Param::Real(RealRange::between(-10.0, 10.0)), SERVO,
        "output offset, volts (software zero pot)"),
    spec("PH", Some(0x73), Setup, "set servo output PHase", One, int(0, 1), CLOSED_LOOP,
        "output phasing: 0 standard, 1 reverse"),
    spec("PK", None, Setup, "PWM frequency", NoAxis, int(0, I32_MAX), "PWM servo",
        "PWM frequency = n × 610 Hz, default 32 (the printed range −10…+10 contradicts the \
         default: not checked)"),
    spec("SA", Some(0x2B), Setup, "Set Acceleration", One, NON_NEGATIVE, SERVO_STEPPER,
        "maximum acceleration, counts (steps) per second²"),
    spec("SD", Some(0x2C), Setup, "Set Derivative gain", One, NON_NEGATIVE, CLOSED_LOOP,
        "derivative gain"),
    spec("SE", Some(0x19), Setup, "Stop on Error", One, NON_NEGATIVE, CLOSED_LOOP,
        "maximum following error; exceeded: motor error, motor off until MN; 0 disables \
         (syntax line prints n ≤ 0, the examples are positive)"),
    spec("SG", Some(0x2D), Setup, "Set prop. Gain of motor", One,
        Param::Real(RealRange::between(0.000153, 10.0)), CLOSED_LOOP,
        "proportional gain, volts per count"),
    spec("SI", Some(0x2E), Setup, "Set Integral gain", One, NON_NEGATIVE, CLOSED_LOOP,
        "integral gain (no effect unless IL ≠ 0)"),
    spec("SQ", Some(0x74), Setup, "Set TorQue", One, Param::Real(RealRange::between(-10.0, 10.0)),
        SERVO, "position/velocity mode: output limit 0…10 V; torque mode: output −10…10 V"),
    spec("SS", Some(0x1D), Setup, "Set Slave ratio", One, ANY, SERVO_STEPPER,
        "slave ratio used by SM (range garbled; examples 5, −.1, −1000)"),
    spec("SV", Some(0x2F), Setup, "Set Velocity", One, NON_NEGATIVE, SERVO_STEPPER,
        "maximum velocity, counts (steps) per second"),
    spec("UA", Some(0x9C), Setup, "Use as default Axis", NoAxis, int(0, 8), SERVO_STEPPER,
        "default axis for commands written without one (0 at power-up; syntax prints > 0, ≤ 4)"),
    spec("UK", Some(0xD7), Setup, "set User output constant", One, NON_NEGATIVE, SERVO,
        "units of AG/DG/VG, OB, OO (default 1.0)"),
    spec("UO", Some(0xB3), Setup, "set User Offset", One, ANY, SERVO_STEPPER,
        "user offset: home to machine zero, user units (takes effect at the next MN)"),
    spec("UP", Some(0x9D), Setup, "Use Physical axis", Optional, Param::Undocumented,
        SERVO_STEPPER, UNDESCRIBED),
    spec("UR", Some(0xB1), Setup, "set User Rate conversion", One, NON_NEGATIVE, SERVO_STEPPER,
        "seconds per user time unit of SV/SA/DS (60 = per minute)"),
    spec("US", Some(0xAF), Setup, "set User Scale", One, ANY, SERVO_STEPPER,
        "encoder counts (steps) per user unit (default 1.0)"),
    spec("UT", Some(0xB2), Setup, "set User Time conversion", Optional, NON_NEGATIVE,
        SERVO_STEPPER, "seconds per dwell unit of WA/WS/WT, per task and interface"),
    spec("UZ", Some(0xB0), Setup, "set User Zero", One, ANY, SERVO_STEPPER,
        "user (part) zero, used with UO"),
    spec("VA", Some(0xAD), Setup, "set Vector Acceleration", One, NON_NEGATIVE, SERVO_STEPPER,
        "contour vector acceleration (controlling axis)"),
    spec("VD", Some(0xAE), Setup, "set Vector Deceleration", One, NON_NEGATIVE, SERVO_STEPPER,
        "contour vector deceleration (controlling axis)"),
    spec("VG", Some(0x77), Setup, "set Velocity Gain", One, ANY, SERVO,
        "velocity feed-forward, volts per count/s; typically negative"),
    spec("VO", Some(0xE0), Setup, "set Velocity Override", One, NON_NEGATIVE, SERVO_STEPPER,
        "velocity override factor (default 1)"),
    spec("VV", Some(0xAC), Setup, "set Vector Velocity", One, NON_NEGATIVE, SERVO_STEPPER,
        "contour vector velocity, stored with each CP move"),
    spec("YF", Some(0x14F), Setup, "Yes IIR Filter", Optional, Param::Undocumented, SERVO,
        UNDESCRIBED),
    spec("ZF", Some(0x153), Setup, "Zero IIR Filter coefficients", Optional,
        Param::Undocumented, SERVO, UNDESCRIBED),
    // Ch6 Mode.
    spec("CM", Some(0x1B), Mode, "enable Contour Mode", One, int(1, 8), SERVO_STEPPER,
        "contour mode; n = the controlling axis (lowest of the group)"),
    spec("GM", Some(0x08), Mode, "enable Gain Mode", One, NONE, SERVO,
        "moves without a velocity profile, PID only (tuning)"),
    spec("IM", Some(0x72), Mode, "Input Mode", One, Param::OneOf(&[0, 1, 128]), STEPPER,
        "0 open loop, 1 closed loop, 128 allow changing pulse-axis PID parameters"),
    spec("PM", Some(0x17), Mode, "enable Position Mode", One, NONE, SERVO_STEPPER,
        "position mode (the mode at power-up and reset)"),
    spec("QM", Some(0x09), Mode, "enable TorQue mode", One, NONE, SERVO,
        "torque mode: output = SQ volts"),
    spec("SM", Some(0x1A), Mode, "enable Master/Slave mode", One, int(0, 135), SERVO_STEPPER,
        "slave the axis to master n at the SS ratio; SM0 ends (syntax prints n > 0)"),
    spec("VM", Some(0x18), Mode, "enable Velocity Mode", One, NONE, SERVO_STEPPER,
        "velocity mode: GO starts in the DI direction at SV"),
    // Ch7 Motion.
    spec("AB", Some(0x0A), Motion, "ABort", OneOrAll, NONE, SERVO_STEPPER,
        "emergency stop: stops abruptly, PID and amplifier stay on, target := position; \
         0 = all axes"),
    spec("AF", Some(0xEB), Motion, "Auxiliary encoder arm/Find index", One, ANY, STEPPER,
        "arm auxiliary-encoder index capture; its position at the index := n"),
    spec("BC", Some(0x144), Motion, "Begin position Compare", One, int(I32_MIN, 1024),
        SERVO_STEPPER,
        "position compare: n > 0 positions from LC memory, 0 fixed interval (NC), n < 0 stops"),
    spec("BF", Some(0xCF), Motion, "Backlash compensation oFf", One, NONE, SERVO,
        "backlash compensation off"),
    spec("BN", Some(0xCE), Motion, "Backlash compensation oN", One, NONE, SERVO,
        "backlash compensation on"),
    spec("CA", Some(0xB4), Motion, "arc Center Absolute", One, ANY, SERVO_STEPPER,
        "arc centre, absolute, inside a CP2/CP3 compound (syntax ≥ 0; centres may be negative)"),
    spec("CB", Some(0x148), Motion, "position Capture Begin", One, int(I32_MIN, 1024),
        SERVO_STEPPER, "capture n positions on the capture input (n < 0 stops); bit 5 when done"),
    spec("CD", Some(0xC1), Motion, "Contour Distance", One, NON_NEGATIVE, SERVO_STEPPER,
        "contour distance of a CP0 compound (its last command)"),
    spec("CP", Some(0xC0), Motion, "Contour Path", One, int(0, 3), SERVO_STEPPER,
        "start a contour compound: 0 user-defined, 1 linear, 2 CW arc, 3 CCW arc"),
    spec("CR", Some(0xB5), Motion, "arc Center Relative", One, ANY, SERVO_STEPPER,
        "arc centre relative to the target before the arc (syntax ≥ 0; example 1CR-20000)"),
    spec("EA", Some(0xBB), Motion, "arc Ending Angle absolute", One, NON_NEGATIVE,
        SERVO_STEPPER, "arc ending angle, absolute"),
    spec("EL", Some(0xE4), Motion, "home Edge Latch", One, NON_NEGATIVE, OPEN_STEPPER,
        "arm home-sensor capture (bit 18 when captured); WE + MN define it as n"),
    spec("ER", Some(0xBC), Motion, "arc Ending angle Relative", One, NON_NEGATIVE,
        SERVO_STEPPER, "arc ending angle, relative"),
    spec("FE", Some(0x0B), Motion, "Find Edge", One, ANY, OPEN_STEPPER,
        "wait for the home sensor capture (stalls the interpreter until then or Escape); MN \
         then sets its position to n")
        .blocking(Blocks::Waits),
    spec("FI", Some(0x0C), Motion, "Find Index", One, ANY, CLOSED_LOOP,
        "wait for the encoder index capture (stalls the interpreter until then or Escape); MN \
         then sets its position to n")
        .blocking(Blocks::Waits),
    spec("GH", Some(0x0D), Motion, "Go Home", One, NONE, SERVO_STEPPER,
        "move to 0, the home of the last DH, IA+WI, EL+WE, FI or FE"),
    spec("GO", Some(0x0E), Motion, "GO", OneOrAll, int(0, 1), SERVO_STEPPER,
        "start velocity-mode motion; contour mode: start the buffered path (0 linear, 1 cubic \
         spline)"),
    spec("HO", Some(0x0F), Motion, "HOme", Optional, NONE, SERVO_STEPPER,
        "run macro a (1HO runs macro 1); without an axis macro 9")
        .blocking(Blocks::RunsMacro),
    spec("IA", Some(0x5D), Motion, "Index Arm", One, ANY, CLOSED_LOOP,
        "arm index capture (bit 18 when captured); WI + MN define it as n"),
    spec("LC", Some(0x142), Motion, "Load Compare positions", One, ANY, SERVO_STEPPER,
        "load a compare position"),
    spec("LP", Some(0x70), Motion, "Learn Position", OneOrAll, POINT, SERVO_STEPPER,
        "store the actual position in point n (0 = every axis)"),
    spec("LT", Some(0x71), Motion, "Learn Target", OneOrAll, POINT, SERVO_STEPPER,
        "store the target position in point n (works with the motor off)"),
    spec("MA", Some(0x10), Motion, "Move Absolute", OneOrAll, ANY, SERVO_STEPPER,
        "move to position n; with the motor off only the target changes"),
    spec("MF", Some(0x11), Motion, "Motor ofF", OneOrAll, NONE, SERVO_STEPPER,
        "motor off: output null, PID off, amplifier/driver disabled"),
    spec("MN", Some(0x13), Motion, "Motor oN", OneOrAll, NONE, SERVO_STEPPER,
        "motor on: target := position if it was off; clears the latched error bits"),
    spec("MP", Some(0x14), Motion, "Move to Point", OneOrAll, POINT, SERVO_STEPPER,
        "move to stored point n (0 = every axis)"),
    spec("MR", Some(0x15), Motion, "Move Relative", One, ANY, SERVO_STEPPER,
        "move by n from the target (Ch3 misnames it \"Move to Point\")"),
    spec("NC", Some(0x143), Motion, "Next Compare", One, ANY, SERVO_STEPPER,
        "compare increment for BC0"),
    spec("NS", Some(0xAB), Motion, "No Synchronization", One, NONE, SERVO_STEPPER,
        "synchronization off (controlling axis)"),
    spec("OC", Some(0x140), Motion, "Output mode for Compare", One,
        Param::OneOf(&[0, 1, 2, 3, 128, 129, 130, 131]), SERVO_STEPPER,
        "compare output: 0 off, 1 static, 2 toggle, 3 one-shot; + 128 inverts it"),
    spec("OP", Some(0x141), Motion, "Output Period", One, POSITIVE, SERVO_STEPPER,
        "one-shot period, seconds"),
    spec("PP", Some(0xED), Motion, "Profile Parabolic", One, NONE, SERVO_STEPPER,
        "parabolic velocity profile (triangular acceleration)"),
    spec("PR", Some(0xD4), Motion, "Record motion data", One, int(0, 1024), SERVO_STEPPER,
        "record n samples (actual, optimal, DAC, aux encoder)"),
    spec("PS", Some(0xEE), Motion, "Profile S-curve", One, NONE, SERVO_STEPPER,
        "S-curve profile (sinusoidal acceleration)"),
    spec("PT", Some(0xEF), Motion, "Profile Trapezoidal", One, NONE, SERVO_STEPPER,
        "trapezoidal profile (constant acceleration)"),
    spec("RR", Some(0xB6), Motion, "aRc Radius", One, ANY, SERVO_STEPPER,
        "arc radius: positive < 180°, negative > 180° (syntax prints ≥ 0)"),
    spec("SN", Some(0xAA), Motion, "Synchronization oN", One, NONE, SERVO_STEPPER,
        "synchronization on: CP moves are buffered until GO"),
    spec("ST", Some(0x16), Motion, "STop", OneOrAll, NONE, SERVO_STEPPER,
        "stop, decelerating at DS; 0 = all axes"),
    // Ch8 Reporting.
    spec("AT", Some(0xE9), Reporting, "Auxiliary encoder Tell position", One, Param::Precision,
        STEPPER, "report the auxiliary encoder position")
        .reports(Output::Value),
    spec("AZ", Some(0xEC), Reporting, "Auxiliary encoder tell index", One, Param::Precision,
        STEPPER, "report the auxiliary encoder index position")
        .reports(Output::Value),
    spec("CG", Some(0x149), Reporting, "Capture Get count", One, NONE, SERVO_STEPPER,
        "load the accumulator with the number of captured positions (then TR0)"),
    spec("DA", Some(0xDB), Reporting, "Display recorded aux. encoder position", One, SAMPLE,
        STEPPER, "report recorded auxiliary encoder sample n")
        .reports(Output::Value),
    spec("DE", None, Reporting, "Display mEmory", NoAxis, int(0, 65535), OTHER,
        "dump 256 bytes of memory from n (syntax printed \"DAn\")")
        .reports(Output::Text),
    spec("DO", Some(0xD6), Reporting, "Display recorded optimal position", One, SAMPLE,
        SERVO_STEPPER, "report recorded optimal position sample n")
        .reports(Output::Value),
    spec("DQ", Some(0xBD), Reporting, "Display recorded DAC output", One, SAMPLE, SERVO,
        "report recorded DAC output sample n")
        .reports(Output::Value),
    spec("DR", Some(0xD5), Reporting, "Display recorded actual position", One, SAMPLE,
        SERVO_STEPPER, "report recorded (or captured) actual position n")
        .reports(Output::Value),
    spec("GC", Some(0x145), Reporting, "Get the position compare count", One, NONE,
        SERVO_STEPPER, "load the accumulator with the number of compare events (then TR0)"),
    spec("ID", None, Reporting, "Information Display", Optional, int(0, 7), SERVO_STEPPER,
        "formatted text: 0 primary status, 1 aux status, 2 motor table, 3 internal table, \
         4 gains, 5 encoder faults, 6 I/O assignment, 7 background task IDs")
        .reports(Output::Text),
    spec("TA", Some(0x49), Reporting, "Tell Analog to digital converter", NoAxis, int(1, 8),
        "A/D option", "report A/D channel x, 0…65536 over the input range")
        .reports(Output::Value),
    spec("TB", Some(0x5B), Reporting, "Tell Breakpoint position", One, Param::Precision,
        SERVO_STEPPER, "report the breakpoint position (IP, IR, WP, WR)")
        .reports(Output::Value),
    spec("TC", Some(0x4A), Reporting, "Tell Channel", NoAxis, int(0, 32), IO,
        "report input channel x as 1/0; TC0 all 32 inputs as one value")
        .reports(Output::Value),
    spec("TD", Some(0x4B), Reporting, "Tell Derivative gain", One, Param::Precision,
        CLOSED_LOOP, "report the derivative gain")
        .reports(Output::Value),
    spec("TE", Some(0x4C), Reporting, "Tell command interface Error", NoAxis, NONE, OTHER,
        "report the last command-interpreter error code (Ch14)")
        .reports(Output::Value),
    spec("TF", Some(0x4D), Reporting, "Tell Following error", One, Param::Precision,
        CLOSED_LOOP, "report the following error (optimal − actual)")
        .reports(Output::Value),
    spec("TG", Some(0x4E), Reporting, "Tell proportional Gain", One, Param::Precision,
        CLOSED_LOOP, "report the proportional gain")
        .reports(Output::Value),
    spec("TI", Some(0x4F), Reporting, "Tell Integral gain", One, Param::Precision, CLOSED_LOOP,
        "report the integral gain")
        .reports(Output::Value),
    spec("TK", Some(0x5C), Reporting, "Tell velocity gain", One, Param::Precision, CLOSED_LOOP,
        "report the velocity gain (VG)")
        .reports(Output::Value),
    spec("TL", Some(0x50), Reporting, "Tell integration Limit", One, Param::Precision,
        CLOSED_LOOP, "report the integration limit")
        .reports(Output::Value),
    spec("TM", Some(0x51), Reporting, "Tell stored Macros", NoAxis, int(-1, 999), FLOW,
        "list macro n (−1 = all), one line per macro starting MC<n>,")
        .reports(Output::Text),
    spec("TO", Some(0x59), Reporting, "Tell Optimal", One, Param::Precision, SERVO_STEPPER,
        "report the optimal (desired) position")
        .reports(Output::Value),
    spec("TP", Some(0x52), Reporting, "Tell Position", One, Param::Precision, SERVO_STEPPER,
        "report the actual position (servo encoder, stepper step count)")
        .reports(Output::Value),
    spec("TQ", Some(0xD1), Reporting, "Tell torQue", One, Param::Precision, SERVO,
        "report the SQ setting")
        .reports(Output::Value),
    spec("TR", Some(0x57), Reporting, "Tell Register n", NoAxis, Param::RegisterPrecision,
        REGISTERS,
        "report register n (0 = the accumulator; syntax prints n ≤ 255), .p decimals (Ch4 TRn.p)")
        .reports(Output::Value),
    spec("TS", Some(0x53), Reporting, "Tell Status", One, Param::Status, SERVO_STEPPER,
        "report a status word or bit (Ch8 TS)")
        .reports(Output::Value),
    spec("TT", Some(0x54), Reporting, "Tell Target", One, Param::Precision, SERVO_STEPPER,
        "report the target position")
        .reports(Output::Value),
    spec("TV", Some(0x55), Reporting, "Tell Velocity", One, Param::Precision, SERVO_STEPPER,
        "report the commanded velocity, in user units")
        .reports(Output::Value),
    spec("TX", Some(0x58), Reporting, "Tell contouring count", One, NONE, SERVO_STEPPER,
        "report the contour count (controlling axis)")
        .reports(Output::Value),
    spec("TZ", Some(0x5A), Reporting, "Tell index position", One, Param::Precision, CLOSED_LOOP,
        "report the index position")
        .reports(Output::Value),
    spec("VE", Some(0x56), Reporting, "tell VErsion", NoAxis, NONE, OTHER,
        "report the firmware version and memory")
        .reports(Output::Text),
    // Ch9 I/O.
    spec("CF", Some(0x1F), Io, "Channel ofF", NoAxis, CHANNEL, IO, "turn output x off"),
    spec("CH", Some(0x42), Io, "Channel High true logic", NoAxis, int(0, 64), IO,
        "channel x high-true (default); 0 = all"),
    spec("CL", Some(0x43), Io, "Channel Low true logic", NoAxis, int(0, 64), IO,
        "channel x low-true (`CL17` for a normally closed limit); 0 = all"),
    spec("CN", Some(0x21), Io, "Channel oN", NoAxis, CHANNEL, IO, "turn output x on"),
    spec("GA", Some(0xF8), Io, "Get Analog value", NoAxis, int(1, 8), "A/D option",
        "load the accumulator with A/D channel x"),
    spec("OA", Some(0xF9), Io, "Output Analog value", NoAxis, int(1, 8), "analog output",
        "analog output channel x := the accumulator (Ch3/Ch4 tables only)"),
    spec("WF", Some(0x67), Io, "Wait for channel ofF", NoAxis, CHANNEL, IO,
        "wait until channel x is off (Escape aborts)")
        .blocking(Blocks::Waits),
    spec("WN", Some(0x68), Io, "Wait for channel oN", NoAxis, CHANNEL, IO,
        "wait until channel x is on (Escape aborts)")
        .blocking(Blocks::Waits),
    // Ch10 Macro and multi-tasking.
    spec("BK", Some(0x79), Macro, "BreaK", NoAxis, Param::OptionalText, FLOW,
        "skip the rest of the line or macro (ends a task); BK\"text\" prints text and single-steps"),
    spec("ET", Some(0xFB), Macro, "Escape Task", NoAxis, ANY_INT, FLOW,
        "end the background task with ID n (the ID GT put in the accumulator)"),
    spec("GT", Some(0xFA), Macro, "Generate Task", NoAxis, MACRO, FLOW,
        "run macro n as a background task (ID into the accumulator); GT0 first on a line: the \
         rest of the line"),
    spec("MC", Some(0x02), Macro, "Macro Call", NoAxis, MACRO, FLOW,
        "call macro n (returns when it ends)")
        .blocking(Blocks::RunsMacro),
    spec("MD", Some(0x03), Macro, "Macro Definition", NoAxis, MACRO, FLOW,
        "define macro n as the rest of the line (first command only)"),
    spec("MJ", Some(0x05), Macro, "Macro Jump", NoAxis, MACRO, FLOW,
        "jump to macro n (no return)")
        .blocking(Blocks::RunsMacro),
    spec("NO", Some(0x78), Macro, "No Operation", NoAxis, NONE, FLOW,
        "does nothing (filler in sequences, short delay)"),
    spec("NP", None, Macro, "New Priority", NoAxis, int(11, 255), FLOW,
        "priority of the issuing task: 11 highest … 255 lowest, default 100"),
    spec("RM", Some(0x04), Macro, "Reset Macros", NoAxis, NONE, FLOW,
        "erase all macros (the only way to free macro memory)"),
    // Ch11 Register.
    spec("AA", Some(0x85), Register, "Accumulator Add", NoAxis, ANY, REGISTERS, "ACC += n"),
    spec("AC", Some(0x8C), Register, "Accumulator Complement", NoAxis, NONE, REGISTERS,
        "ACC := bitwise NOT ACC"),
    spec("AD", Some(0x88), Register, "Accumulator Divide", NoAxis, ANY, REGISTERS,
        "ACC /= n (no operation if n = 0)"),
    spec("AE", Some(0x8F), Register, "Accumulator logical Exclusive or", NoAxis, ANY, REGISTERS,
        "ACC ^= n"),
    spec("AL", Some(0x82), Register, "Accumulator Load", NoAxis, ANY, REGISTERS,
        "ACC := n (double if n has a decimal point, else 32-bit integer)"),
    spec("AM", Some(0x87), Register, "Accumulator Multiply", NoAxis, ANY, REGISTERS, "ACC *= n"),
    spec("AN", Some(0x8D), Register, "Accumulator logical aNd", NoAxis, ANY, REGISTERS,
        "ACC &= n"),
    spec("AO", Some(0x83), Register, "Accumulator logical Or", NoAxis, ANY, REGISTERS,
        "ACC |= n (Ch3 gives AO and RA the same code 83h)"),
    spec("AR", Some(0x84), Register, "copy Accumulator to Register", NoAxis, REGISTER,
        REGISTERS, "register n := ACC"),
    spec("AS", Some(0x86), Register, "Accumulator Subtract", NoAxis, ANY, REGISTERS, "ACC -= n"),
    spec("AV", Some(0x8B), Register, "Accumulator eValuate", NoAxis, int(0, 25), REGISTERS,
        "unary operation n on ACC (2 change sign … 9 sqrt, 10 sin … 25 double to integer)"),
    spec("AX", Some(0xE1), Register, "get Aux. indeX position", One, NONE, STEPPER,
        "ACC := auxiliary encoder position at the last captured index"),
    spec("GF", Some(0x152), Register, "Get IIR Filter coefficients", Optional,
        Param::Undocumented, SERVO, UNDESCRIBED),
    spec("GU", Some(0x89), Register, "Get the default axis", NoAxis, NONE, REGISTERS,
        "ACC := the default axis (UA)"),
    spec("GX", Some(0xF7), Register, "Get auXiliary encoder position", One, NONE, STEPPER,
        "ACC := auxiliary encoder position"),
    spec("LU", Some(0x81), Register, "Look Up motor table variable", NoAxis, Param::Text,
        REGISTERS, "ACC := address of motor-table variable \"name\" (Ch4 table; −19 if unknown)"),
    spec("RA", Some(0x83), Register, "copy Register to Accumulator", NoAxis, REGISTER, REGISTERS,
        "ACC := register n"),
    spec("RB", Some(0x96), Register, "Read Byte into accumulator", Optional, ANY, REGISTERS,
        "ACC := byte at address n (axis: of that axis's motor table)"),
    spec("RD", Some(0x93), Register, "Read Double into accumulator", Optional, ANY, REGISTERS,
        "ACC := 64-bit real at address n"),
    spec("RL", Some(0x98), Register, "Read Long into accumulator", Optional, ANY, REGISTERS,
        "ACC := 32-bit integer at address n"),
    spec("RV", Some(0x92), Register, "Read float into accumulator", Optional, ANY, REGISTERS,
        "ACC := 32-bit real at address n"),
    spec("RW", Some(0x97), Register, "Read Word into accumulator", Optional, ANY, REGISTERS,
        "ACC := 16-bit integer at address n"),
    spec("SL", Some(0x90), Register, "Shift Left accumulator", NoAxis, int(1, 31), REGISTERS,
        "ACC <<= n"),
    spec("SR", Some(0x91), Register, "Shift Right accumulator", NoAxis, int(1, 31), REGISTERS,
        "ACC >>= n (zero fill)"),
    spec("WB", Some(0x99), Register, "Write accumulator Byte", NoAxis, ANY, REGISTERS,
        "store the low byte of ACC at address n")
        .caution(Caution::FactoryOnly),
    spec("WD", Some(0x95), Register, "Write accumulator Double", NoAxis, ANY, REGISTERS,
        "store ACC as a 64-bit real at address n")
        .caution(Caution::FactoryOnly),
    spec("WL", Some(0x9B), Register, "Write accumulator Long", NoAxis, ANY, REGISTERS,
        "store ACC as a 32-bit integer at address n")
        .caution(Caution::FactoryOnly),
    spec("WV", Some(0x94), Register, "Write accumulator float", NoAxis, ANY, REGISTERS,
        "store ACC as a 32-bit real at address n")
        .caution(Caution::FactoryOnly),
    spec("WW", Some(0x9A), Register, "Write accumulator Word", NoAxis, ANY, REGISTERS,
        "store the low 16 bits of ACC at address n")
        .caution(Caution::FactoryOnly),
    // Ch12 Sequence.
    spec("DF", Some(0x6B), Sequence, "Do if channel ofF", NoAxis, CHANNEL, FLOW,
        "channel x off: continue; else skip the rest of the line or macro"),
    spec("DN", Some(0x6A), Sequence, "Do if channel oN", NoAxis, CHANNEL, FLOW,
        "channel x on: continue; else skip the rest of the line or macro"),
    spec("IB", Some(0xA5), Sequence, "If Below do next command", NoAxis, ANY, FLOW,
        "ACC < n: next command; else skip two"),
    spec("IC", Some(0xA1), Sequence, "If Clear, do next command", NoAxis, int(0, 31), FLOW,
        "ACC bit n clear: next command; else skip two"),
    spec("IE", Some(0xA2), Sequence, "If Equals do next command", NoAxis, ANY, FLOW,
        "ACC = n: next command; else skip two"),
    spec("IF", Some(0x6D), Sequence, "If channel ofF do next command", NoAxis, CHANNEL, FLOW,
        "channel x off: next command; else skip two"),
    spec("IG", Some(0xA4), Sequence, "If accumulator is Greater do next", NoAxis, ANY, FLOW,
        "ACC > n: next command; else skip two"),
    spec("IN", Some(0x6C), Sequence, "If channel oN do next command", NoAxis, CHANNEL, FLOW,
        "channel x on: next command; else skip two"),
    spec("IP", Some(0x60), Sequence, "Interrupt on absolute Position", One, ANY, SERVO_STEPPER,
        "breakpoint at position n: status bit 6 when reached (no wait)"),
    spec("IR", Some(0x61), Sequence, "Interrupt on Relative position", One, ANY, SERVO_STEPPER,
        "breakpoint at n from the last target: status bit 6 when reached (no wait)"),
    spec("IS", Some(0xA0), Sequence, "If bit Set do next command", NoAxis, int(0, 31), FLOW,
        "ACC bit n set: next command; else skip two"),
    spec("IU", Some(0xA3), Sequence, "If Unequal do next command", NoAxis, ANY, FLOW,
        "ACC ≠ n: next command; else skip two"),
    spec("JP", Some(0x06), Sequence, "JumP to command absolute", NoAxis, int(0, I32_MAX), FLOW,
        "jump to command n of the line or macro (0-based)")
        .blocking(Blocks::Loops),
    spec("JR", Some(0x07), Sequence, "Jump to command Relative", NoAxis, ANY_INT, FLOW,
        "jump n commands from this one (JR0 = itself)")
        .blocking(Blocks::Loops),
    spec("RP", Some(0x64), Sequence, "RePeat", NoAxis, int(0, I32_MAX), FLOW,
        "run the commands before it n + 1 times; 0 or none: for ever (Escape stops)")
        .blocking(Blocks::Loops),
    spec("WA", Some(0x65), Sequence, "WAit (time)", NoAxis, NON_NEGATIVE, FLOW,
        "wait n seconds (× UT; Escape aborts)")
        .blocking(Blocks::Waits),
    spec("WE", Some(0x66), Sequence, "Wait for Edge", One, NONE, OPEN_STEPPER,
        "after EL and bit 18: keep the edge position for the following MN")
        .blocking(Blocks::Waits),
    spec("WI", Some(0x5E), Sequence, "Wait for Index", One, NON_NEGATIVE, CLOSED_LOOP,
        "after IA and bit 18: keep the index position n for the following MN")
        .blocking(Blocks::Waits),
    spec("WP", Some(0x62), Sequence, "Wait for absolute Position", One, ANY, SERVO_STEPPER,
        "wait until the axis reaches position n; sets bit 6 (Escape aborts)")
        .blocking(Blocks::Waits),
    spec("WR", Some(0x63), Sequence, "Wait for Relative position", One, ANY, SERVO_STEPPER,
        "wait until n from the last target; sets bit 6 (Escape aborts)")
        .blocking(Blocks::Waits),
    spec("WS", Some(0x69), Sequence, "Wait for Stop", OneOrAll, NON_NEGATIVE, SERVO_STEPPER,
        "wait for trajectory complete (bit 3; 0 = all axes), then n seconds")
        .blocking(Blocks::Waits),
    spec("WT", Some(0xC6), Sequence, "Wait for Target", One, NON_NEGATIVE, SERVO_STEPPER,
        "wait for At Target (bit 2), plus a dwell of n")
        .blocking(Blocks::Waits),
    // Ch13 Miscellaneous.
    spec("DM", Some(0x3C), Misc, "Decimal Mode", NoAxis, NONE, OTHER,
        "numbers in decimal both ways (the default; not on a line with HM)"),
    spec("DW", Some(0xFD), Misc, "Disable Watchdog", NoAxis, NONE, OTHER,
        "disable the processor watchdog (syntax printed \"DM\")")
        .caution(Caution::FactoryOnly),
    spec("EF", Some(0x25), Misc, "Echo ofF", NoAxis, int(0, 3), OTHER,
        "echo off (n undocumented)")
        .caution(Caution::FactoryOnly),
    spec("EN", Some(0x26), Misc, "Echo oN", NoAxis, int(0, 3), OTHER,
        "echo on (n undocumented)")
        .caution(Caution::FactoryOnly),
    spec("FD", Some(0xCC), Misc, "Format text with Doubles", NoAxis, Param::Text, OTHER,
        "format text with ACC as a double into memory; ACC := its address"),
    spec("FM", None, Misc, "Free memory", NoAxis, int(1, 65536), OTHER,
        "free scratch memory at address n (from ME)"),
    spec("FT", None, Misc, "Format Text with Integers", NoAxis, Param::Text, OTHER,
        "format text with ACC as an integer into memory; ACC := its address"),
    spec("HE", None, Misc, "HElp", NoAxis, Param::Help, OTHER,
        "help: 0 the mnemonics, 1 the data-table variable names, \"mm\" a command")
        .reports(Output::Text),
    spec("HM", Some(0x3D), Misc, "Hexadecimal Mode", NoAxis, NONE, OTHER,
        "numbers in hexadecimal both ways (not on a line with DM)"),
    spec("ME", None, Misc, "MEmory allocate", NoAxis, int(1, 65536), OTHER,
        "allocate n bytes of scratch memory; ACC := its address (0 if none)"),
    spec("OD", Some(0xC3), Misc, "Output text with Doubles", NoAxis, Param::Text, OTHER,
        "print text with ACC as a double (%f); \\n line feed, \\r carriage return")
        .reports(Output::Text),
    spec("OT", None, Misc, "Output Text with integers", NoAxis, Param::Text, OTHER,
        "print text with ACC as an integer (%d); \\n line feed, \\r carriage return")
        .reports(Output::Text),
    spec("PC", Some(0x80), Misc, "set Prompt Character", NoAxis, int(0, 255), OTHER,
        "prompt character sent when a line completes (ASCII code; 0 none; default 62 `>`)"),
    spec("RT", Some(0x2A), Misc, "ReseT system", Optional, NONE, "servo, stepper, I/O",
        "reset axis a to its defaults, motor off; without an axis (or 0) the whole controller")
        .caution(Caution::Resets),
];

/// The command of a mnemonic (upper-case ASCII).
pub fn find(mnemonic: &str) -> Option<&'static CommandSpec> {
    COMMANDS.iter().find(|c| c.mnemonic == mnemonic)
}

/// OT and OD print text to the interface, which a background task may do
/// (which interface gets it is not stated, digest §3.2); every other
/// command that prints is a reporting command and refused in a task.
fn task_may_print(spec: &CommandSpec) -> bool {
    matches!(spec.mnemonic, "OT" | "OD")
}

/// Whether a background task may run `spec` (Ch4 "MCCL Multi-Tasking").
pub fn allowed_in_task(spec: &CommandSpec) -> bool {
    spec.in_task || task_may_print(spec)
}

/// The motor-table variables `LU"name"` looks up, with the read command
/// that fetches each (Ch4 "Reading Data from Controller Memory"; the
/// headings of the double and float tables are displaced in the seed, so
/// which table is which follows their order and the `LU"POSITION",3RD@0`
/// example, digest §10).
pub const VARIABLES: &[(&str, &str)] = &[
    ("INTMASK", "RL"),
    ("INTPEND", "RL"),
    ("STATUS", "RL"),
    ("AUXSTAT", "RL"),
    ("CITADS", "RL"),
    ("POSCOUNT", "RL"),
    ("IDXCOUNT", "RL"),
    ("CMDCOUNT", "RL"),
    ("TGTCOUNT", "RL"),
    ("BACKLASH", "RD"),
    ("ENCSCALE", "RD"),
    ("ENCODERFLT", "RD"),
    ("MAXERROR", "RD"),
    ("POSITION", "RD"),
    ("TARGET", "RD"),
    ("OPTIMAL", "RD"),
    ("BRKPOS", "RD"),
    ("POSDBAND", "RD"),
    ("PGMACC", "RD"),
    ("PGMDEC", "RD"),
    ("MINVEL", "RD"),
    ("PGMVEL", "RD"),
    ("SCALE", "RD"),
    ("OFFSET", "RD"),
    ("OUTCONST", "RD"),
    ("RATE", "RD"),
    ("ZERO", "RD"),
    ("LOLIM", "RD"),
    ("HILIM", "RD"),
    ("TGTDELAY", "RD"),
    ("CURVEL", "RD"),
    ("VELGAIN", "RD"),
    ("KVEL", "RV"),
    ("KACC", "RV"),
    ("KDEC", "RV"),
    ("OUTDBAND", "RV"),
    ("KPOS", "RV"),
    ("KDER", "RV"),
    ("KINT", "RV"),
    ("ILIM", "RV"),
    ("MAXTRQ", "RV"),
    ("OUTOFFSET", "RV"),
    ("VELOVRD", "RV"),
    ("AXISNUM", "RW"),
    ("COEFMAX", "RW"),
    ("COEFCNT", "RW"),
    ("MASTER", "RW"),
    ("INPUTMODE", "RW"),
    ("INTEGRALOPT", "RW"),
    ("SFREQ", "RW"),
    ("WAITSTOP", "RW"),
    ("WAITTARGET", "RW"),
];

/// The read command of a motor-table variable, if the table lists it.
pub fn variable(name: &str) -> Option<&'static str> {
    VARIABLES
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))
        .map(|(_, read)| *read)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn every_mnemonic_is_two_ascii_capitals_and_listed_once() {
        let mut seen = HashSet::new();
        for command in COMMANDS {
            assert_eq!(command.mnemonic.len(), 2, "{}", command.mnemonic);
            assert!(
                command.mnemonic.bytes().all(|b| b.is_ascii_uppercase()),
                "{}",
                command.mnemonic
            );
            assert!(seen.insert(command.mnemonic), "{} twice", command.mnemonic);
            assert!(!command.meaning.is_empty());
        }
        // Ch3 lists about 200 operations; every one of its mnemonics is here.
        assert!(COMMANDS.len() > 190, "{}", COMMANDS.len());
    }

    #[test]
    fn the_quick_reference_codes_are_kept_with_their_misprints_noted() {
        assert_eq!(find("MA").map(|c| c.code), Some(Some(0x10)));
        assert_eq!(find("IO").map(|c| c.code), Some(Some(0x205)));
        // Ch3 prints LF = LS = 36h and AO = RA = 83h (digest §19 #2).
        assert_eq!(
            find("LF").and_then(|c| c.code),
            find("LS").and_then(|c| c.code)
        );
        assert_eq!(
            find("AO").and_then(|c| c.code),
            find("RA").and_then(|c| c.code)
        );
        assert_eq!(find("OT").map(|c| c.code), Some(None));
        assert!(find("MR").is_some_and(|c| c.meaning.contains("Move to Point")));
    }

    #[test]
    fn reporting_commands_print_and_stay_out_of_tasks() {
        for mnemonic in ["TP", "TS", "TR", "VE", "TM", "ID", "HE"] {
            let command = find(mnemonic).expect(mnemonic);
            assert_ne!(command.output, Output::Nothing, "{mnemonic}");
            assert!(!allowed_in_task(command), "{mnemonic}");
            assert!(command.only_reads(), "{mnemonic}");
        }
        for mnemonic in ["OT", "OD"] {
            assert!(allowed_in_task(find(mnemonic).expect(mnemonic)));
            assert!(!find(mnemonic).expect(mnemonic).only_reads());
        }
        // CG and GC only load the accumulator (then TR0 prints it).
        assert_eq!(find("CG").map(|c| c.output), Some(Output::Nothing));
    }

    #[test]
    fn waits_calls_and_repeats_block() {
        for mnemonic in ["WS", "WA", "WT", "WP", "WR", "WN", "WF", "FI", "FE"] {
            assert_eq!(
                find(mnemonic).map(|c| c.blocks),
                Some(Blocks::Waits),
                "{mnemonic}"
            );
        }
        for mnemonic in ["MC", "MJ", "HO"] {
            assert_eq!(find(mnemonic).map(|c| c.blocks), Some(Blocks::RunsMacro));
        }
        assert_eq!(find("RP").map(|c| c.blocks), Some(Blocks::Loops));
        assert_eq!(
            find("GT").map(|c| c.blocks),
            Some(Blocks::No),
            "a task runs beside"
        );
    }

    #[test]
    fn syntax_and_ranges_read_as_the_manual_writes_them() {
        let syntax = |m: &str| find(m).map(|c| c.syntax()).unwrap_or_default();
        assert_eq!(syntax("MA"), "aMAn");
        assert_eq!(syntax("TP"), "aTPp");
        assert_eq!(syntax("TC"), "TCn");
        assert_eq!(syntax("LU"), "LU\"s\"");
        assert_eq!(syntax("ID"), "[a]IDn");
        assert_eq!(
            find("SG").map(|c| c.values()).unwrap_or_default(),
            "integer or real, 0.000153..10"
        );
        assert_eq!(
            find("DS").map(|c| c.values()).unwrap_or_default(),
            "integer or real, > 0"
        );
        assert!(RealRange::POSITIVE.contains(0.5) && !RealRange::POSITIVE.contains(0.0));
        assert!(!RealRange::ANY.contains(f64::NAN));
    }

    #[test]
    fn motor_table_variables_name_their_read_command() {
        assert_eq!(variable("STATUS"), Some("RL"));
        assert_eq!(variable("position"), Some("RD"));
        assert_eq!(variable("KPOS"), Some("RV"));
        assert_eq!(variable("SFREQ"), Some("RW"));
        assert_eq!(variable("NOSUCH"), None);
    }
}
