//! The A-Script standalone command set as data: Table 5-42 (§5.2) and the
//! "Standalone" rows of the availability tables in §2, one row per form
//! (`HSPD` and `HSPD[axis]` are two rows, as in the manual), each with the
//! ASCII command it corresponds to (§4.1 T4-40), and the ASCII-only names
//! with the standalone command to use instead.

use std::fmt;

/// One of the four axes (§1.0: X, Y, Z, U).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Axis {
    X,
    Y,
    Z,
    U,
}

impl Axis {
    pub const ALL: [Axis; 4] = [Axis::X, Axis::Y, Axis::Z, Axis::U];

    pub fn letter(self) -> char {
        match self {
            Axis::X => 'X',
            Axis::Y => 'Y',
            Axis::Z => 'Z',
            Axis::U => 'U',
        }
    }

    /// The axis an upper-case letter names.
    pub fn from_letter(letter: char) -> Option<Axis> {
        Axis::ALL.into_iter().find(|a| a.letter() == letter)
    }

    /// 0 for X … 3 for U.
    pub fn index(self) -> usize {
        self as usize
    }
}

impl fmt::Display for Axis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.letter())
    }
}

/// What follows a command's name to say what it acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Addressing {
    /// Nothing: `HSPD`, `ABORT`, `DI`.
    None,
    /// An axis letter: `HSPDX`, `ABORTX`, `MSTU`.
    Axis,
    /// A number in `first..=last`: `DI1`…`DI4`, `IO1`…`IO32`, `SR0`…`SR3`.
    Index { first: u8, last: u8 },
}

/// Whether a register can be read, written or both (the R/W column).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    Read,
    Write,
    ReadWrite,
}

impl Access {
    pub fn readable(self) -> bool {
        matches!(self, Access::Read | Access::ReadWrite)
    }

    pub fn writable(self) -> bool {
        matches!(self, Access::Write | Access::ReadWrite)
    }
}

/// The shape of a command's statement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A value: read as an operand (`V1=MSTX`), written with `NAME=value`.
    Register(Access),
    /// Done by naming it: `ABORT`, `ABS`, `ECLEARX`.
    Action,
    /// `WAIT[axis]`: wait until the axis has stopped.
    Wait,
    /// `DELAY=ms`.
    Delay,
    /// `JOG[axis][+/-]`.
    Jog,
    /// `HOME[axis][+/-][mode]`.
    Home,
    /// `ZMOVE[axis][+/-]`.
    ZMove,
    /// `CIR[A1][A2]P|N[C1]:[C2]`.
    Circle,
    /// `ARC[A1][A2]P|N[C1]:[C2]:[θ]`.
    Arc,
    /// `CIRTP|N[C1]:[C2]:[Z]`.
    HelixCircle,
    /// `ARCTP|N[C1]:[C2]:[θ]:[Z]`.
    HelixArc,
    /// `V[0-99]`: a program variable (the parser reads these itself).
    Variable,
}

/// The values a write accepts, inclusive.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ValueRange {
    pub min: i64,
    pub max: i64,
}

impl ValueRange {
    pub fn contains(self, value: i64) -> bool {
        (self.min..=self.max).contains(&value)
    }
}

impl fmt::Display for ValueRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}..{}", self.min, self.max)
    }
}

/// One form of a standalone command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CommandInfo {
    pub name: &'static str,
    pub addressing: Addressing,
    pub kind: Kind,
    /// What a write accepts (None: nothing is written).
    pub values: Option<ValueRange>,
    /// The ASCII command of the same meaning (T4-40), if there is one.
    pub ascii: Option<&'static str>,
    /// Where the manual describes it.
    pub section: &'static str,
    pub meaning: &'static str,
}

impl CommandInfo {
    pub fn readable(&self) -> bool {
        matches!(self.kind, Kind::Register(a) if a.readable()) || self.kind == Kind::Variable
    }

    pub fn writable(&self) -> bool {
        matches!(self.kind, Kind::Register(a) if a.writable()) || self.kind == Kind::Variable
    }

    /// The form as the manual writes it: `HSPD[axis]=value`, `DO[1-4]`,
    /// `HOME[axis][+/-][mode]`.
    pub fn syntax(&self) -> String {
        let address = match self.addressing {
            Addressing::None => String::new(),
            Addressing::Axis => "[axis]".to_string(),
            Addressing::Index { first, last } => format!("[{first}-{last}]"),
        };
        let tail = match self.kind {
            Kind::Register(Access::Write) | Kind::Delay => "=value",
            Kind::Register(Access::ReadWrite) | Kind::Variable => "[=value]",
            Kind::Register(Access::Read) | Kind::Action | Kind::Wait => "",
            Kind::Jog | Kind::ZMove => "[+/-]",
            Kind::Home => "[+/-][mode]",
            Kind::Circle => "[A1][A2]P|N[C1]:[C2]",
            Kind::Arc => "[A1][A2]P|N[C1]:[C2]:[θ]",
            Kind::HelixCircle => "P|N[C1]:[C2]:[Z]",
            Kind::HelixArc => "P|N[C1]:[C2]:[θ]:[Z]",
        };
        format!("{}{address}{tail}", self.name)
    }
}

/// Signed 32-bit: the standalone variables (§2.7.6).
pub const I32: ValueRange = ValueRange {
    min: i32::MIN as i64,
    max: i32::MAX as i64,
};
/// 28-bit positions (§1.2: −134,217,728 to +134,217,727).
pub const POSITION: ValueRange = ValueRange {
    min: -134_217_728,
    max: 134_217_727,
};
/// Speeds (§1.2: up to 6,553,500 pps).
const SPEED: ValueRange = ValueRange {
    min: 1,
    max: 6_553_500,
};
/// A per-axis speed: 0 means "use the global value" (§2.1.4).
const AXIS_SPEED: ValueRange = ValueRange {
    min: 0,
    max: 6_553_500,
};
/// Times in ms and other counts the manual gives no limit for: App. B says
/// out-of-range ACC/DEC "will be automatically adjusted", so no error.
const NON_NEGATIVE: ValueRange = ValueRange {
    min: 0,
    max: i32::MAX as i64,
};
const BIT: ValueRange = ValueRange { min: 0, max: 1 };
const NIBBLE: ValueRange = ValueRange { min: 0, max: 15 };
/// The 32 configurable I/O as one word (§2.1.3.3.1).
const WORD32: ValueRange = ValueRange {
    min: 0,
    max: u32::MAX as i64,
};

const fn row(
    name: &'static str,
    addressing: Addressing,
    kind: Kind,
    values: Option<ValueRange>,
    ascii: Option<&'static str>,
    section: &'static str,
    meaning: &'static str,
) -> CommandInfo {
    CommandInfo {
        name,
        addressing,
        kind,
        values,
        ascii,
        section,
        meaning,
    }
}

use Access::{Read as R, ReadWrite as RW, Write as W};
use Addressing::{Axis as AX, None as NO};

const fn idx(first: u8, last: u8) -> Addressing {
    Addressing::Index { first, last }
}

/// Every standalone command form: Table 5-42 plus `LT`, `LTS`, `LTP`,
/// `LTE` (§2.1.3.2.1), `MPGE` (§2.1.3.1.4) and `PWM` (§2.1.3.3.3), which
/// only the §2 availability tables list. Where T5-42's R/W column
/// contradicts its own description (digest erratum 19), the description
/// wins: `SYNSTAT` "Returns the status" is read-only, `JOYDEL` "Returns"
/// and matches the read/write `JDEL`.
#[rustfmt::skip]
pub const COMMANDS: &[CommandInfo] = &[
    row("ABORT", NO, Kind::Action, None, Some("ABORT"), "2.2.3", "immediately stop all axes"),
    row("ABORT", AX, Kind::Action, None, Some("ABORT"), "2.2.3", "immediately stop the axis"),
    row("ABS", NO, Kind::Action, None, Some("ABS"), "2.2.4.1", "absolute position mode"),
    row("ACC", NO, Kind::Register(RW), Some(NON_NEGATIVE), Some("ACC"), "2.1.4", "global acceleration time in ms"),
    row("ACC", AX, Kind::Register(RW), Some(NON_NEGATIVE), Some("ACC"), "2.1.4", "axis acceleration time in ms (0: the global one)"),
    row("AI", idx(1, 2), Kind::Register(R), None, Some("AI"), "2.1.3.3.2", "analog input in mV"),
    row("ARC", NO, Kind::Arc, None, Some("ARC"), "2.3.2.1", "arc interpolation to an absolute angle in millidegrees (P: CW, N: CCW)"),
    row("ARCT", NO, Kind::HelixArc, None, Some("ARCT"), "2.3.3", "XY arc with Z linear interpolation (uses U)"),
    row("BUFOFF", NO, Kind::Action, None, Some("BF"), "2.3.4", "disable buffered moves"),
    row("BUFON", NO, Kind::Action, None, Some("BO"), "2.3.4", "enable buffered moves"),
    row("CIR", NO, Kind::Circle, None, Some("CIR"), "2.3.2", "full-circle interpolation (P: CW, N: CCW)"),
    row("CIRT", NO, Kind::HelixCircle, None, Some("CIRT"), "2.3.3", "XY circle with Z linear interpolation (uses U)"),
    row("DEC", NO, Kind::Register(RW), Some(NON_NEGATIVE), Some("DEC"), "2.1.4", "global deceleration time in ms"),
    row("DEC", AX, Kind::Register(RW), Some(NON_NEGATIVE), Some("DEC"), "2.1.4", "axis deceleration time in ms (0: the global one)"),
    row("DELAY", NO, Kind::Delay, Some(NON_NEGATIVE), None, "5.2", "wait this many ms"),
    row("DI", NO, Kind::Register(R), None, Some("DI"), "2.1.3.2.1", "the 4 high-speed digital inputs (DI1 = bit 0)"),
    row("DI", idx(1, 4), Kind::Register(R), None, Some("DI"), "2.1.3.2.1", "one high-speed digital input"),
    row("DO", NO, Kind::Register(RW), Some(NIBBLE), Some("DO"), "2.1.3.2.2", "the 4 digital outputs (DO1 = bit 0)"),
    row("DO", idx(1, 4), Kind::Register(RW), Some(BIT), Some("DO"), "2.1.3.2.2", "one digital output"),
    row("E", AX, Kind::Register(RW), Some(POSITION), Some("E"), "2.6.1.2", "encoder counter"),
    row("ECLEAR", AX, Kind::Action, None, Some("CLR"), "2.6.2.3", "clear the axis's error flags"),
    row("EINT", NO, Kind::Register(RW), Some(BIT), Some("EINT"), "2.3.1", "1: multi-axis moves are interpolated"),
    row("EO", NO, Kind::Register(RW), Some(NIBBLE), Some("EO"), "2.2.1", "the 4 enable outputs (X = bit 0)"),
    row("EO", idx(1, 4), Kind::Register(RW), Some(BIT), Some("EO"), "2.2.1", "one enable output"),
    row("HOME", AX, Kind::Home, None, Some("H"), "2.2.5", "home in the + or - direction with a mode 0-12 (Appendix A)"),
    row("HSPD", NO, Kind::Register(RW), Some(SPEED), Some("HSPD"), "2.1.4", "global high speed in pps"),
    row("HSPD", AX, Kind::Register(RW), Some(AXIS_SPEED), Some("HSPD"), "2.1.4", "axis high speed in pps (0: the global one)"),
    row("INC", NO, Kind::Action, None, Some("INC"), "2.2.4.1", "incremental position mode"),
    row("IO", NO, Kind::Register(RW), Some(WORD32), Some("IO"), "2.1.3.3.1", "the 32 configurable I/O (IO1 = bit 0)"),
    row("IO", idx(1, 32), Kind::Register(RW), Some(BIT), Some("IO"), "2.1.3.3.1", "one configurable I/O"),
    row("ISTART", NO, Kind::Action, None, Some("BSTART"), "2.3.4", "start processing the move buffer"),
    row("JOG", AX, Kind::Jog, None, Some("J"), "2.2.2", "jog in the + or - direction at HSPD"),
    row("JOYDEL", AX, Kind::Register(RW), Some(NON_NEGATIVE), Some("JDEL"), "2.5.1.2", "joystick maximum speed change"),
    row("JOYENA", NO, Kind::Register(RW), Some(ValueRange { min: 0, max: 3 }), Some("JENA"), "2.5.1", "joystick enable (bit 0: X, bit 1: Y)"),
    row("JOYHS", AX, Kind::Register(RW), Some(NON_NEGATIVE), Some("JSPD"), "2.5.1.2", "joystick maximum speed"),
    row("LSPD", NO, Kind::Register(RW), Some(SPEED), Some("LSPD"), "2.1.4", "global low speed in pps"),
    row("LSPD", AX, Kind::Register(RW), Some(AXIS_SPEED), Some("LSPD"), "2.1.4", "axis low speed in pps (0: the global one)"),
    row("LT", AX, Kind::Register(W), Some(BIT), Some("LT"), "2.1.3.2.1", "position latch enable"),
    row("LTE", AX, Kind::Register(R), None, Some("LTE"), "2.1.3.2.1", "latched encoder position"),
    row("LTP", AX, Kind::Register(R), None, Some("LTP"), "2.1.3.2.1", "latched pulse position"),
    row("LTS", AX, Kind::Register(R), None, Some("LTS"), "2.1.3.2.1", "latch status (0 off, 1 waiting, 2 latched)"),
    row("MPGE", AX, Kind::Register(RW), Some(BIT), Some("MPE"), "2.1.3.1.4", "manual pulse generator enable"),
    row("MST", AX, Kind::Register(R), None, Some("MST"), "2.6.2.1", "motor status bits"),
    row("P", AX, Kind::Register(RW), Some(POSITION), Some("P"), "2.6.1.1", "pulse (position) counter"),
    row("PS", AX, Kind::Register(R), None, Some("PS"), "2.6.2.2", "current pulse speed"),
    row("PWM", idx(1, 2), Kind::Register(RW), Some(ValueRange { min: 1, max: 99 }), Some("PWM"), "2.1.3.3.3", "PWM duty cycle in %"),
    row("SL", AX, Kind::Register(RW), Some(BIT), Some("SL"), "2.5.3", "StepNLoop enable"),
    row("SLS", AX, Kind::Register(R), None, Some("SLS"), "2.5.3", "StepNLoop status"),
    row("SR", idx(0, 3), Kind::Register(W), Some(ValueRange { min: 0, max: 3 }), Some("SACTRL"), "2.7.8", "control program n: 0 stop, 1 start, 2 pause, 3 continue"),
    row("SSPD", AX, Kind::Register(W), Some(SPEED), Some("SSPD"), "2.4.1", "on-the-fly speed change"),
    row("SSPDM", AX, Kind::Register(W), Some(ValueRange { min: 0, max: 7 }), Some("SSPDM"), "2.4.1", "on-the-fly speed window (Appendix B)"),
    row("STOP", NO, Kind::Action, None, Some("STOP"), "2.2.3", "ramp down and stop all axes"),
    row("STOP", AX, Kind::Action, None, Some("STOP"), "2.2.3", "ramp down and stop the axis"),
    row("STORE", NO, Kind::Action, None, Some("STORE"), "2.1.7", "save the parameters to flash"),
    row("SYNCFG", AX, Kind::Register(RW), Some(I32), Some("SYNC"), "2.1.3.2.2", "sync output condition and source"),
    row("SYNOFF", AX, Kind::Action, None, Some("SYNF"), "2.1.3.2.2", "disable the sync output and window"),
    row("SYNON", AX, Kind::Action, None, Some("SYNO"), "2.1.3.2.2", "enable the sync output"),
    row("SYNPOS", AX, Kind::Register(RW), Some(I32), Some("SYNP"), "2.1.3.2.2", "sync position or interval"),
    row("SYNSTAT", AX, Kind::Register(R), None, Some("SYNS"), "2.1.3.2.2", "sync status (0 off, 1 waiting, 2 met)"),
    row("V", idx(0, 99), Kind::Variable, Some(I32), Some("V"), "2.7.6", "program variable, 32-bit signed"),
    row("WAIT", AX, Kind::Wait, None, None, "5.2", "wait until the axis's motion is complete"),
    row("ZMOVE", AX, Kind::ZMove, None, Some("ZMOVE"), "2.2.5.1", "move until ZCNT Z-index pulses in the + or - direction"),
];

/// Every form of the command called `name`.
pub fn forms(name: &str) -> impl Iterator<Item = &'static CommandInfo> + '_ {
    COMMANDS.iter().filter(move |c| c.name == name)
}

/// Whether `name` is a standalone command (in some form).
pub fn is_command(name: &str) -> bool {
    forms(name).next().is_some()
}

/// The form of `name` addressed this way (`Axis`, `None`, or any `Index`).
pub fn form(name: &str, addressing: AddressKind) -> Option<&'static CommandInfo> {
    forms(name).find(|c| addressing.matches(c.addressing))
}

/// How a command was addressed in source, before ranges are checked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AddressKind {
    None,
    Axis,
    Index,
}

impl AddressKind {
    fn matches(self, addressing: Addressing) -> bool {
        matches!(
            (self, addressing),
            (AddressKind::None, Addressing::None)
                | (AddressKind::Axis, Addressing::Axis)
                | (AddressKind::Index, Addressing::Index { .. })
        )
    }
}

/// An ASCII command that standalone programs do not have (§2 availability
/// tables: blank or "_" in the Standalone row), and what to write instead.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AsciiOnly {
    pub name: &'static str,
    /// Whether the ASCII command takes an axis letter (`CLRX`).
    pub axis: bool,
    pub instead: Option<&'static str>,
}

const fn ascii_only(name: &'static str, axis: bool, instead: Option<&'static str>) -> AsciiOnly {
    AsciiOnly {
        name,
        axis,
        instead,
    }
}

/// ASCII commands with no standalone form. Where the standalone set has
/// its own name for the same thing, `instead` names it.
#[rustfmt::skip]
pub const ASCII_ONLY: &[AsciiOnly] = &[
    ascii_only("BF", false, Some("BUFOFF")),
    ascii_only("BO", false, Some("BUFON")),
    ascii_only("BSTART", false, Some("ISTART")),
    ascii_only("BSTAT", false, None),
    ascii_only("CLR", true, Some("ECLEAR[axis]")),
    ascii_only("D", true, None),
    ascii_only("DB", false, None),
    ascii_only("DIP", false, None),
    ascii_only("DOBOOT", false, None),
    ascii_only("DOP", false, None),
    ascii_only("EOBOOT", false, None),
    ascii_only("EP", false, None),
    ascii_only("ERC", true, None),
    ascii_only("ERCD", true, None),
    ascii_only("ERCP", true, None),
    ascii_only("ESTOP", false, Some("ABORT (ESTOP is ASCII-only)")),
    ascii_only("EXST", false, None),
    ascii_only("GS", false, Some("GOSUB n")),
    ascii_only("H", true, Some("HOME[axis][+/-][mode]")),
    ascii_only("I", false, Some("BUFON, then X[pos]Y[pos]Z[pos] moves")),
    ascii_only("ID", false, None),
    ascii_only("IERR", false, None),
    ascii_only("INP", true, None),
    ascii_only("IOBOOT", false, None),
    ascii_only("IOCFG", false, None),
    ascii_only("IOP", false, None),
    ascii_only("J", true, Some("JOG[axis][+/-]")),
    ascii_only("JDEL", true, Some("JOYDEL[axis]")),
    ascii_only("JENA", false, Some("JOYENA")),
    ascii_only("JLIM", false, None),
    ascii_only("JMAX", true, None),
    ascii_only("JMIN", true, None),
    ascii_only("JSPD", true, Some("JOYHS[axis]")),
    ascii_only("JTOL", true, None),
    ascii_only("MM", false, None),
    ascii_only("MP", true, None),
    ascii_only("MPD", true, None),
    ascii_only("MPE", true, Some("MPGE[axis]")),
    ascii_only("MPM", true, None),
    ascii_only("POL", true, None),
    ascii_only("PP", false, None),
    ascii_only("SACTRL", false, Some("SR[0-3]")),
    ascii_only("SAP", false, None),
    ascii_only("SASTAT", false, None),
    ascii_only("SCV", true, None),
    ascii_only("SDC", true, None),
    ascii_only("SDE", true, None),
    ascii_only("SLA", true, None),
    ascii_only("SLE", true, None),
    ascii_only("SLOAD", false, None),
    ascii_only("SLR", true, None),
    ascii_only("SLT", true, None),
    ascii_only("SPC", false, None),
    ascii_only("SYNC", true, Some("SYNCFG[axis]")),
    ascii_only("SYNF", true, Some("SYNOFF[axis]")),
    ascii_only("SYNMAX", true, None),
    ascii_only("SYNMIN", true, None),
    ascii_only("SYNO", true, Some("SYNON[axis]")),
    ascii_only("SYNP", true, Some("SYNPOS[axis]")),
    ascii_only("SYNS", true, Some("SYNSTAT[axis]")),
    ascii_only("SYNWF", true, None),
    ascii_only("SYNWO", true, None),
    ascii_only("T", true, None),
    ascii_only("VER", false, None),
    ascii_only("ZCNT", true, None),
];

/// The ASCII-only command a word of source names (`CLRX`, `BO`, `SACTRL`),
/// if it is one.
pub fn ascii_only_command(word: &str) -> Option<&'static AsciiOnly> {
    ASCII_ONLY.iter().find(|a| a.name == word).or_else(|| {
        let (name, last) = split_last_letter(word)?;
        Axis::from_letter(last)?;
        ASCII_ONLY.iter().find(|a| a.axis && a.name == name)
    })
}

/// `word` without its last letter, and that letter.
pub(crate) fn split_last_letter(word: &str) -> Option<(&str, char)> {
    let last = word.chars().next_back()?;
    Some((word.get(..word.len() - last.len_utf8())?, last))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_name_has_at_most_one_form_per_addressing() {
        for c in COMMANDS {
            for kind in [AddressKind::None, AddressKind::Axis, AddressKind::Index] {
                let n = forms(c.name).filter(|f| kind.matches(f.addressing)).count();
                assert!(n <= 1, "{} has {n} {kind:?} forms", c.name);
            }
        }
    }

    #[test]
    fn no_ascii_only_name_is_also_a_standalone_command() {
        for a in ASCII_ONLY {
            assert!(!is_command(a.name), "{}", a.name);
            if let Some(instead) = a.instead {
                let name: String = instead
                    .chars()
                    .take_while(char::is_ascii_uppercase)
                    .collect();
                assert!(
                    is_command(&name) || name == "GOSUB",
                    "{} -> {instead}",
                    a.name
                );
            }
        }
    }

    #[test]
    fn writes_have_a_range_and_reads_none_needed() {
        for c in COMMANDS {
            if c.writable() || c.kind == Kind::Delay {
                assert!(c.values.is_some(), "{} has no value range", c.name);
            }
        }
    }

    #[test]
    fn syntax_is_written_as_the_manual_does() {
        let syntax = |name, kind| form(name, kind).map(CommandInfo::syntax);
        assert_eq!(
            syntax("HSPD", AddressKind::Axis).as_deref(),
            Some("HSPD[axis][=value]")
        );
        assert_eq!(syntax("DI", AddressKind::Index).as_deref(), Some("DI[1-4]"));
        assert_eq!(
            syntax("HOME", AddressKind::Axis).as_deref(),
            Some("HOME[axis][+/-][mode]")
        );
        assert_eq!(
            syntax("SR", AddressKind::Index).as_deref(),
            Some("SR[0-3]=value")
        );
    }

    #[test]
    fn ascii_only_words_are_found_with_and_without_their_axis() {
        assert_eq!(
            ascii_only_command("CLRX").map(|a| a.instead),
            Some(Some("ECLEAR[axis]"))
        );
        assert_eq!(ascii_only_command("BO").map(|a| a.name), Some("BO"));
        assert_eq!(ascii_only_command("POLU").map(|a| a.name), Some("POL"));
        // A name that takes no axis is not found with one.
        assert!(ascii_only_command("MMX").is_none());
        assert!(ascii_only_command("HSPD").is_none());
    }
}
