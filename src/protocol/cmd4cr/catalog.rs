//! The ASCII command set of the CMD-4CR manual (§4.1 Table 4-40) as data:
//! one row per form of a command (`HSPD` and `HSPD[axis]` are two rows),
//! with what it reads or writes, the values it takes and their unit, what
//! it means and where the manual explains it. Ranges and units come from
//! §2 where Table 4-40 gives none (cmd4cr digest §2). The parser, the
//! completion, the help and the parameter table all read this table.
//!
//! Where the sources disagree the row follows the section that explains
//! the command, and says so in its meaning:
//! - `ZCNT[axis]` 0–15 (§2.2.5.1, "number set plus one") against Table
//!   4-40's "1 – 16".
//! - `ERCD[axis]`, `ERCP[axis]` per axis (§2.1.6.1, Table 2-19) where Table
//!   4-40 prints no axis.
//! - `SLOAD` as the §2.7.10 bit mask, and `SLOAD[0-3]` as Table 4-40's
//!   per-program form.
//! - Writes all take `=` (every example of the manual does): Table 4-40's
//!   `HSPD[value]` and `SAP[0-1]` are read as `HSPD=[value]`, `SAP=[0-1]`.

use std::sync::LazyLock;

/// The four axes, in the order the manual lists them (and PP/EP fields).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Axis {
    X,
    Y,
    Z,
    U,
}

impl Axis {
    pub const ALL: [Axis; 4] = [Axis::X, Axis::Y, Axis::Z, Axis::U];

    /// The letter the commands use.
    pub fn letter(self) -> char {
        match self {
            Axis::X => 'X',
            Axis::Y => 'Y',
            Axis::Z => 'Z',
            Axis::U => 'U',
        }
    }

    /// The axis a letter names (upper or lower case).
    pub fn from_letter(letter: char) -> Option<Axis> {
        Axis::ALL
            .into_iter()
            .find(|a| a.letter() == letter.to_ascii_uppercase())
    }

    /// 0 for X … 3 for U: the field of PP/EP, the bit of EO (Table 2-20).
    pub fn index(self) -> usize {
        self as usize
    }

    pub fn from_index(index: usize) -> Option<Axis> {
        Axis::ALL.get(index).copied()
    }
}

/// A command that sets or reads a value: its identity for whoever acts on
/// a parsed command (the simulator dispatches on it). The keyword is in
/// the table ([`CommandSpec::keyword`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Register {
    Id,
    Ver,
    Db,
    Ierr,
    Exst,
    Eint,
    Mm,
    Hspd,
    Lspd,
    Acc,
    Dec,
    Scv,
    Sspdm,
    Sspd,
    Zcnt,
    P,
    Pp,
    E,
    Ep,
    D,
    Mst,
    Ps,
    Mp,
    Pol,
    Eo,
    Eoboot,
    Sde,
    Sdc,
    Inp,
    Erc,
    Ercd,
    Ercp,
    Di,
    Dip,
    Do,
    Dop,
    Doboot,
    Io,
    Iocfg,
    Ioboot,
    Iop,
    Ai,
    Pwm,
    Lt,
    Lts,
    Ltp,
    Lte,
    Sync,
    Synp,
    Synmax,
    Synmin,
    Syns,
    Jena,
    Jmax,
    Jmin,
    Jtol,
    Jspd,
    Jdel,
    Jlim,
    Mpe,
    Mpm,
    Mpd,
    Sl,
    Slr,
    Slt,
    Sle,
    Sla,
    Sls,
    Sactrl,
    Sastat,
    Spc,
    Sload,
    Sap,
    V,
    Bstat,
}

/// A command that does something and takes no value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Action {
    Store,
    Estop,
    Abs,
    Inc,
    Stop,
    Abort,
    Clr,
    BufferOn,
    BufferOff,
    BufferStart,
    SyncOn,
    SyncOff,
    SyncWindowOn,
    SyncWindowOff,
    /// `GS[0-31]`: call a subroutine stored in flash (§2.7.4).
    CallSub,
}

/// What a command is, for the parser: a register, an action, or one of the
/// motion commands with a syntax of their own.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    Register(Register),
    Action(Action),
    /// `[axis][pos]…`: 1–4 axes with their targets (§2.2.4.2, §2.3.1).
    Move,
    /// `J[axis][+/-]` (§2.2.2).
    Jog,
    /// `H[axis][+/-][mode]` (§2.2.5, Appendix A).
    Home,
    /// `ZMOVE[axis][+/-]` (§2.2.5.1).
    ZMove,
    /// `T[axis][newtarget]`, no `=` (§2.4.2).
    NewTarget,
    /// `CIR[A1][A2]P|N[C1]:[C2]` (§2.3.2).
    Circle,
    /// `ARC[A1][A2]P|N[C1]:[C2]:[θ]` (§2.3.2.1).
    Arc,
    /// `CIRTP|N[C1]:[C2]:[Z target]` (§2.3.3).
    HelicalCircle,
    /// `ARCTP|N[C1]:[C2]:[θ]:[Z target]` (§2.3.3).
    HelicalArc,
    /// `I[X]:[Y]:[Z]:[speed]` (§2.3.4).
    BufferMove,
}

/// What follows the keyword of a register or action.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Form {
    /// Nothing: `HSPD`, `STORE`, `PP`.
    Bare,
    /// An axis letter: `HSPDX`, `STOPY`, `MSTU`.
    Axis,
    /// A number from `first` to `last`: `DI3`, `V12`, `SACTRL0`.
    Index { first: u8, last: u8 },
    /// The syntax of a motion command ([`Kind`] says which).
    Motion,
}

/// What the host may do with a command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Read only (`MSTX`).
    Read,
    /// Write only, with `=value` (`SSPDX=70000`, `SACTRL0=1`).
    Write,
    /// Read (bare) and write (`=value`).
    ReadWrite,
    /// Does something, no value (`STOP`, `CLRX`, `X1000`).
    Action,
}

impl Access {
    pub fn reads(self) -> bool {
        matches!(self, Access::Read | Access::ReadWrite)
    }

    pub fn writes(self) -> bool {
        matches!(self, Access::Write | Access::ReadWrite)
    }

    /// `R`, `W`, `R/W`, `W` (an action is a write, as Table 4-40 marks it).
    pub fn label(self) -> &'static str {
        match self {
            Access::Read => "R",
            Access::Write | Access::Action => "W",
            Access::ReadWrite => "R/W",
        }
    }
}

/// How a value is written on the wire and read back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// A signed decimal integer.
    Integer,
    /// A two-digit decimal (`ID=02`, §2.1.1.1).
    TwoDigits,
    /// A decimal with up to three places, held in thousandths (SLR,
    /// 0.001–999.999, §2.5.3).
    Thousandths,
    /// `:`-separated integers, one per named field (PP, EP, BSTAT).
    Fields(&'static [&'static str]),
    /// Text shown as it comes (VER: the format is not given, §2.1.1.1).
    Text,
}

/// The values a register takes or gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Values {
    /// Inclusive bounds, in the unit below (thousandths for SLR).
    pub min: i64,
    pub max: i64,
    pub unit: &'static str,
    pub format: Format,
}

impl Values {
    pub fn contains(&self, value: i64) -> bool {
        (self.min..=self.max).contains(&value)
    }
}

/// One row of Table 4-40 (one form of a command).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CommandSpec {
    /// The word the command starts with (`HSPD`, `MST`, `CIR`); empty for
    /// the move command, which starts with an axis letter.
    pub keyword: &'static str,
    /// How the manual writes the command.
    pub syntax: &'static str,
    pub kind: Kind,
    pub form: Form,
    pub access: Access,
    /// The value written or read; `None` for actions and motion commands.
    pub values: Option<Values>,
    /// What it does, in the manual's words.
    pub meaning: &'static str,
    /// Where the manual explains it.
    pub section: &'static str,
    /// Saved to flash by STORE (§2.1.7 Table 2-19).
    pub stored: bool,
}

impl CommandSpec {
    /// The syntax and meaning on one line, for help.
    pub fn summary(&self) -> String {
        format!("{}  {}  {}", self.syntax, self.access.label(), self.meaning)
    }
}

/// §1.2: the position range, 28 bits.
pub const POSITION_MIN: i64 = -134_217_728;
pub const POSITION_MAX: i64 = 134_217_727;

/// §1.2: speed steps 1–65,535 times 0.1–100, up to 6,553,500 pps.
pub const SPEED_MAX: i64 = 6_553_500;

/// Appendix B Table B-46: the longest ramp any speed window allows,
/// ((HSPD − LSPD) / δ) × 1000 ms at its largest (325K pps, LSPD 5, δ 200).
/// The controller adjusts a value outside the window of the set speeds.
pub const RAMP_MAX_MS: i64 = 1_624_975;

const I32_MIN: i64 = i32::MIN as i64;
const I32_MAX: i64 = i32::MAX as i64;
const U32_MAX: i64 = u32::MAX as i64;

const fn int(min: i64, max: i64, unit: &'static str) -> Option<Values> {
    Some(Values {
        min,
        max,
        unit,
        format: Format::Integer,
    })
}

const fn flag() -> Option<Values> {
    int(0, 1, "")
}

const POSITION: Option<Values> = int(POSITION_MIN, POSITION_MAX, "pulses");
const AXIS_FIELDS: &[&str] = &["X", "Y", "Z", "U"];

const fn fields(names: &'static [&'static str], unit: &'static str) -> Option<Values> {
    Some(Values {
        min: I32_MIN,
        max: I32_MAX,
        unit,
        format: Format::Fields(names),
    })
}

/// A register row.
#[allow(clippy::too_many_arguments)]
const fn reg(
    keyword: &'static str,
    syntax: &'static str,
    register: Register,
    form: Form,
    access: Access,
    values: Option<Values>,
    meaning: &'static str,
    section: &'static str,
    stored: bool,
) -> CommandSpec {
    CommandSpec {
        keyword,
        syntax,
        kind: Kind::Register(register),
        form,
        access,
        values,
        meaning,
        section,
        stored,
    }
}

/// An action row.
const fn act(
    keyword: &'static str,
    syntax: &'static str,
    action: Action,
    form: Form,
    meaning: &'static str,
    section: &'static str,
) -> CommandSpec {
    CommandSpec {
        keyword,
        syntax,
        kind: Kind::Action(action),
        form,
        access: Access::Action,
        values: None,
        meaning,
        section,
        stored: false,
    }
}

/// A motion command row.
const fn motion(
    keyword: &'static str,
    syntax: &'static str,
    kind: Kind,
    meaning: &'static str,
    section: &'static str,
) -> CommandSpec {
    CommandSpec {
        keyword,
        syntax,
        kind,
        form: Form::Motion,
        access: Access::Action,
        values: None,
        meaning,
        section,
        stored: false,
    }
}

use Access::{Read as R, ReadWrite as RW, Write as W};
use Form::{Axis as A, Bare as B};

/// Table 4-40, completed from §2 (digest §2), in the manual's order.
#[rustfmt::skip]
pub const COMMANDS: &[CommandSpec] = &[
    act("ABORT", "ABORT", Action::Abort, B, "Immediately stops all motion for all axes", "2.2.3"),
    act("ABORT", "ABORT[axis]", Action::Abort, A, "Immediately stops motion in [axis]; an interpolation it belongs to stops whole", "2.2.3"),
    act("ABS", "ABS", Action::Abs, B, "Turns on absolute position coordinate mode", "2.2.4.1"),
    reg("ACC", "ACC=[value]", Register::Acc, B, RW, int(1, RAMP_MAX_MS, "ms"), "Global acceleration time; used by coordinated moves and by axes whose own is 0", "2.1.4", false),
    reg("ACC", "ACC[axis]=[value]", Register::Acc, A, RW, int(0, RAMP_MAX_MS, "ms"), "[axis] acceleration time; 0 = use the global ACC", "2.1.4", false),
    reg("AI", "AI[1-2]", Register::Ai, Form::Index { first: 1, last: 2 }, R, int(0, 3300, "mV"), "Analog input [ch] in millivolts (10-bit)", "2.1.3.3.2", false),
    motion("ARC", "ARC[A1][A2]P|N[C1]:[C2]:[θ]", Kind::Arc, "Arc interpolation on axes [A1],[A2] around the absolute centre [C1],[C2], CW (P) or CCW (N), to the absolute angle θ in millidegrees", "2.3.2.1"),
    motion("ARCT", "ARCTP|N[C1]:[C2]:[θ]:[target]", Kind::HelicalArc, "XY arc around [C1],[C2], CW (P) or CCW (N), to θ (millidegrees) with Z linear to the absolute [target]; uses U internally", "2.3.3"),
    act("BF", "BF", Action::BufferOff, B, "Disable buffered move", "2.3.4"),
    act("BO", "BO", Action::BufferOn, B, "Enable buffered move", "2.3.4"),
    act("BSTART", "BSTART", Action::BufferStart, B, "Start processing the buffer (buffer must be enabled)", "2.3.4"),
    reg("BSTAT", "BSTAT", Register::Bstat, B, R, fields(&["enabled", "start", "end", "available"], ""), "Status of the buffer: [enabled]:[start]:[end]:[available registers]", "2.3.4", false),
    motion("CIR", "CIR[A1][A2]P|N[C1]:[C2]", Kind::Circle, "Full circle on axes [A1],[A2] around the absolute centre [C1],[C2], CW (P) or CCW (N)", "2.3.2"),
    motion("CIRT", "CIRTP|N[C1]:[C2]:[target]", Kind::HelicalCircle, "Full XY circle around [C1],[C2], CW (P) or CCW (N), with Z linear to the absolute [target]; uses U internally", "2.3.3"),
    act("CLR", "CLR[axis]", Action::Clr, A, "Clears the limit, alarm, EMG, slowdown-stop and StepNLoop error flags of [axis]", "2.6.2.3"),
    reg("D", "D[axis]", Register::D, A, R, int(I32_MIN, I32_MAX, "encoder counts"), "StepNLoop deviation of [axis] (target − actual); 0 with StepNLoop off", "2.6.1.3", false),
    reg("DB", "DB=[value]", Register::Db, B, RW, int(1, 5, ""), "Baud rate code: 1 9600, 2 19200, 3 38400, 4 57600, 5 115200; active after STORE and a power cycle", "3.2.1", true),
    reg("DEC", "DEC=[value]", Register::Dec, B, RW, int(1, RAMP_MAX_MS, "ms"), "Global deceleration time; used by coordinated moves and by axes whose own is 0", "2.1.4", false),
    reg("DEC", "DEC[axis]=[value]", Register::Dec, A, RW, int(0, RAMP_MAX_MS, "ms"), "[axis] deceleration time; 0 = use the global DEC", "2.1.4", false),
    reg("DI", "DI", Register::Di, B, R, int(0, 15, ""), "The 4 high-speed digital inputs, DI1 = bit 0", "2.1.3.2.1", false),
    reg("DI", "DI[1-4]", Register::Di, Form::Index { first: 1, last: 4 }, R, flag(), "One high-speed digital input (1-based: DI1 = bit 0)", "2.1.3.2.1", false),
    reg("DIP", "DIP=[pol]", Register::Dip, B, RW, flag(), "Digital input polarity: 0 negative, 1 positive logic", "2.1.6.3", true),
    reg("DO", "DO=[value]", Register::Do, B, RW, int(0, 15, ""), "The 4 high-speed digital outputs, DO1 = bit 0; an output in sync use cannot be set", "2.1.3.2.2", false),
    reg("DO", "DO[1-4]=[value]", Register::Do, Form::Index { first: 1, last: 4 }, RW, flag(), "One high-speed digital output (1-based: DO1 = bit 0)", "2.1.3.2.2", false),
    reg("DOBOOT", "DOBOOT=[value]", Register::Doboot, B, RW, int(0, 15, ""), "DO state at power-on", "2.1.5", true),
    reg("DOP", "DOP=[pol]", Register::Dop, B, RW, flag(), "Digital output polarity: 0 negative, 1 positive logic", "2.1.6.3", true),
    reg("E", "E[axis]=[value]", Register::E, A, RW, POSITION, "Encoder counter of [axis]", "2.6.1.2", false),
    reg("EINT", "EINT=[value]", Register::Eint, B, RW, flag(), "1 (default): multi-axis position commands are linearly interpolated; 0: the axes move independently", "2.3.1", true),
    reg("EO", "EO=[value]", Register::Eo, B, RW, int(0, 15, ""), "Enable outputs of the 4 axes, X = bit 0", "2.2.1", false),
    reg("EO", "EO[1-4]=[value]", Register::Eo, Form::Index { first: 1, last: 4 }, RW, flag(), "One enable output (1-based: EO1 = X)", "2.2.1", false),
    reg("EOBOOT", "EOBOOT=[value]", Register::Eoboot, B, RW, int(0, 15, ""), "EO state at power-on", "2.1.5", true),
    reg("EP", "EP", Register::Ep, B, R, fields(AXIS_FIELDS, "encoder counts"), "Encoder counters of all 4 axes: [X]:[Y]:[Z]:[U]", "2.6.1.2", false),
    reg("ERC", "ERC[axis]=[value]", Register::Erc, A, RW, int(0, 3, ""), "ERC (deflection counter clear) output: bit 0 on error stop, bit 1 on homing complete", "2.1.6.1", true),
    reg("ERCD", "ERCD[axis]=[value]", Register::Ercd, A, RW, int(0, 3, ""), "ERC delay: 0 0 µs, 1 12 µs, 2 1.6 ms, 3 104 ms (per axis as §2.1.6.1 and Table 2-19 say; Table 4-40 prints no axis)", "2.1.6.1", true),
    reg("ERCP", "ERCP[axis]=[value]", Register::Ercp, A, RW, int(0, 6, ""), "ERC pulse width: 0 12 µs, 1 102 µs, 2 409 µs, 3 1.6 ms, 4 13 ms, 5 52 ms, 6 104 ms (per axis as §2.1.6.1 says)", "2.1.6.1", true),
    act("ESTOP", "ESTOP", Action::Estop, B, "Emergency stop of all axes, the same as /CEMG", "2.1.3.1.2"),
    reg("EXST", "EXST=[value]", Register::Exst, B, RW, flag(), "External start: 1 = motion commands wait for /CSTA low (up to 3 queued)", "2.1.1.2", true),
    act("GS", "GS[0-31]", Action::CallSub, Form::Index { first: 0, last: 31 }, "Call the subroutine [sub] stored in flash", "2.7.4"),
    motion("H", "H[axis][+/-][mode]", Kind::Home, "Home [axis] in the + or − direction with homing mode 0–12 (Appendix A)", "2.2.5"),
    reg("HSPD", "HSPD=[value]", Register::Hspd, B, RW, int(1, SPEED_MAX, "pps"), "Global high speed; used by coordinated moves and by axes whose own is 0", "2.1.4", false),
    reg("HSPD", "HSPD[axis]=[value]", Register::Hspd, A, RW, int(0, SPEED_MAX, "pps"), "[axis] high speed; 0 = use the global HSPD", "2.1.4", false),
    motion("I", "I[X]:[Y]:[Z]:[speed]", Kind::BufferMove, "Write an XYZ interpolated move with its own speed to the buffer (buffer mode only)", "2.3.4"),
    reg("ID", "ID=[value]", Register::Id, B, RW, Some(Values { min: 0, max: 99, unit: "", format: Format::TwoDigits }), "The controller's ID, 00–99; active after STORE and a power cycle", "2.1.1.1", true),
    reg("IERR", "IERR=[value]", Register::Ierr, B, RW, flag(), "1 = limit, alarm and EMG stops latch no error (the axis still stops)", "2.1.3.1.1.1", true),
    act("INC", "INC", Action::Inc, B, "Turns on incremental coordinate mode", "2.2.4.1"),
    reg("INP", "INP[axis]=[value]", Register::Inp, A, RW, flag(), "1 = a move of [axis] completes only when the INP input says in position", "2.1.6.2", true),
    reg("IO", "IO=[value]", Register::Io, B, RW, int(0, U32_MAX, ""), "The 32 configurable I/O, IO1 = bit 0", "2.1.3.3.1", false),
    reg("IO", "IO[1-32]=[value]", Register::Io, Form::Index { first: 1, last: 32 }, RW, flag(), "One configurable I/O (1-based: IO1 = bit 0)", "2.1.3.3.1", false),
    reg("IOBOOT", "IOBOOT=[value]", Register::Ioboot, B, RW, int(0, U32_MAX, ""), "State of the output-configured I/O at power-on", "2.1.5", true),
    reg("IOCFG", "IOCFG=[value]", Register::Iocfg, B, RW, int(0, U32_MAX, ""), "I/O direction: bit = 1 output, 0 input", "2.1.3.3.1", true),
    reg("IOP", "IOP=[value]", Register::Iop, B, RW, int(0, 3, ""), "Configurable I/O logic: bit 0 inputs, bit 1 outputs (0 active low, 1 active high)", "2.1.3.3.1", true),
    motion("J", "J[axis][+/-]", Kind::Jog, "Jog [axis] in the + or − direction until STOP, ABORT or a limit", "2.2.2"),
    reg("JDEL", "JDEL[axis]=[value]", Register::Jdel, A, RW, int(0, I32_MAX, ""), "Largest speed change under joystick control (unit not stated)", "2.5.1.2", true),
    reg("JENA", "JENA=[value]", Register::Jena, B, RW, int(0, 3, ""), "Joystick control: bit 0 X, bit 1 Y; enabling it turns StepNLoop off", "2.5.1", true),
    reg("JLIM", "JLIM[1-8]=[value]", Register::Jlim, Form::Index { first: 1, last: 8 }, RW, POSITION, "Joystick soft limits: 1 X neg outer, 2 X neg inner, 3 X pos inner, 4 X pos outer, 5–8 the same for Y", "2.5.1.3", true),
    reg("JMAX", "JMAX[axis]=[value]", Register::Jmax, A, RW, int(0, 3300, "mV"), "Joystick input voltage of full + speed", "2.5.1.1", true),
    reg("JMIN", "JMIN[axis]=[value]", Register::Jmin, A, RW, int(0, 3300, "mV"), "Joystick input voltage of full − speed", "2.5.1.1", true),
    reg("JSPD", "JSPD[axis]=[value]", Register::Jspd, A, RW, int(0, SPEED_MAX, "pps"), "Joystick speed at JMAX/JMIN (unit not stated; pulses/s assumed)", "2.5.1.2", true),
    reg("JTOL", "JTOL[axis]=[value]", Register::Jtol, A, RW, int(0, 3300, "mV"), "Joystick dead band ± around the mid voltage", "2.5.1.1", true),
    reg("LSPD", "LSPD=[value]", Register::Lspd, B, RW, int(1, SPEED_MAX, "pps"), "Global low (start/stop) speed; used by coordinated moves and by axes whose own is 0", "2.1.4", false),
    reg("LSPD", "LSPD[axis]=[value]", Register::Lspd, A, RW, int(0, SPEED_MAX, "pps"), "[axis] low speed; 0 = use the global LSPD", "2.1.4", false),
    reg("LT", "LT[axis]=[value]", Register::Lt, A, W, flag(), "Latch of [axis] on its input (X DI1 … U DI4): 1 on, 0 off", "2.1.3.2.1", false),
    reg("LTE", "LTE[axis]", Register::Lte, A, R, POSITION, "Encoder position latched (invalid with StepNLoop on)", "2.1.3.2.1", false),
    reg("LTP", "LTP[axis]", Register::Ltp, A, R, POSITION, "Pulse position latched (invalid with StepNLoop on)", "2.1.3.2.1", false),
    reg("LTS", "LTS[axis]", Register::Lts, A, R, int(0, 2, ""), "Latch status: 0 off, 1 waiting for the trigger, 2 triggered", "2.1.3.2.1", false),
    reg("MM", "MM", Register::Mm, B, R, flag(), "Move mode: 0 absolute, 1 incremental", "2.2.4.1", false),
    reg("MP", "MP[axis]=[value]", Register::Mp, A, RW, POSITION, "MPG counter of [axis], after gearing", "2.5.2.2", false),
    reg("MPD", "MPD[axis]=[value]", Register::Mpd, A, RW, int(1, 2048, ""), "MPG divider numerator over 2048 (2048 = off)", "2.5.2.2", true),
    reg("MPE", "MPE[axis]=[value]", Register::Mpe, A, RW, flag(), "1 = [axis] follows its MPG input", "2.5.2", true),
    reg("MPM", "MPM[axis]=[value]", Register::Mpm, A, RW, int(1, 32, ""), "MPG multiplier (1 = off)", "2.5.2.2", true),
    reg("MST", "MST[axis]", Register::Mst, A, R, int(0, (1 << 20) - 1, ""), "Motor status word of [axis] (Table 2-28: motion, inputs, latched errors)", "2.6.2.1", false),
    reg("P", "P[axis]=[value]", Register::P, A, RW, POSITION, "Command pulse counter of [axis] (with StepNLoop on: the real-time target, in encoder counts)", "2.6.1.1", false),
    reg("POL", "POL[axis]=[pol]", Register::Pol, A, RW, int(0, (1 << 17) - 1, ""), "Polarity and input modes of [axis], a 17-bit word (Table 2-17 is lost from the manual: see the field names)", "2.1.6.3", true),
    reg("PP", "PP", Register::Pp, B, R, fields(AXIS_FIELDS, "pulses"), "Pulse counters of all 4 axes: [X]:[Y]:[Z]:[U]", "2.6.1.1", false),
    reg("PS", "PS[axis]", Register::Ps, A, R, int(I32_MIN, I32_MAX, "pps"), "Current pulse rate of [axis] (encoder counts/s for a single-axis move with StepNLoop on)", "2.6.2.2", false),
    reg("PWM", "PWM[1-2]=[value]", Register::Pwm, Form::Index { first: 1, last: 2 }, RW, int(1, 99, "%"), "PWM duty at 500 Hz: PWM1 % of the time low, PWM2 % of the time high", "2.1.3.3.3", false),
    reg("SACTRL", "SACTRL[0-3]=[0-3]", Register::Sactrl, Form::Index { first: 0, last: 3 }, W, int(0, 3, ""), "Control standalone program [prgNo]: 0 stop, 1 start, 2 pause, 3 continue", "2.7.8", false),
    reg("SAP", "SAP=[0-1]", Register::Sap, B, RW, flag(), "Where SUB 31 returns to: 0 the last executed line, 1 the first line of the program", "2.7.5", true),
    reg("SASTAT", "SASTAT[0-3]", Register::Sastat, Form::Index { first: 0, last: 3 }, R, int(0, 4, ""), "Status of standalone program: 0 idle, 1 running, 2 paused, 3 N/A, 4 error", "2.7.9", false),
    reg("SCV", "SCV[axis]=[0,1]", Register::Scv, A, RW, flag(), "1 = S-curve acceleration for [axis], 0 = trapezoidal", "2.1.4", false),
    reg("SDC", "SDC[axis]=[value]", Register::Sdc, A, RW, flag(), "Slowdown input action: 0 decelerate only, 1 decelerate and stop", "2.1.3.1.1.2", true),
    reg("SDE", "SDE[axis]=[value]", Register::Sde, A, RW, int(0, 3, ""), "Slowdown input: bit 0 enable, bit 1 latch", "2.1.3.1.1.2", true),
    reg("SL", "SL[axis]=[value]", Register::Sl, A, RW, flag(), "1 = StepNLoop closed-loop verification on [axis]", "2.5.3", true),
    reg("SLA", "SLA[axis]=[value]", Register::Sla, A, RW, int(0, I32_MAX, ""), "StepNLoop: most correction attempts", "2.5.3", true),
    reg("SLE", "SLE[axis]=[value]", Register::Sle, A, RW, int(0, I32_MAX, "encoder counts"), "StepNLoop error range (stall threshold)", "2.5.3", true),
    reg("SLOAD", "SLOAD=[value]", Register::Sload, B, RW, int(0, 15, ""), "Programs run at power-on: bit n = program n", "2.7.10", true),
    reg("SLOAD", "SLOAD[0-3]=[value]", Register::Sload, Form::Index { first: 0, last: 3 }, RW, flag(), "Run program [prg#] at power-on (Table 4-40's per-program form)", "2.7.10", true),
    reg("SLR", "SLR[axis]=[value]", Register::Slr, A, RW, Some(Values { min: 1, max: 999_999, unit: "", format: Format::Thousandths }), "StepNLoop ratio, motor pulses per encoder count, 0.001–999.999", "2.5.3", true),
    reg("SLS", "SLS[axis]", Register::Sls, A, R, int(0, 13, ""), "StepNLoop status (Table 27): 0 idle … 8–10 errors cleared by CLR, 12 N/A", "2.5.3", false),
    reg("SLT", "SLT[axis]=[value]", Register::Slt, A, RW, int(0, I32_MAX, "encoder counts"), "StepNLoop tolerance", "2.5.3", true),
    reg("SPC", "SPC[0-3]", Register::Spc, Form::Index { first: 0, last: 3 }, R, int(0, 1799, ""), "Program counter of standalone program [prg#], in compiled lines", "2.7.9", false),
    reg("SSPD", "SSPD[axis]=[value]", Register::Sspd, A, W, int(1, SPEED_MAX, "pps"), "On-the-fly speed change of [axis]; buffer and S-curve must be off", "2.4.1", false),
    reg("SSPDM", "SSPDM[axis]=[value]", Register::Sspdm, A, RW, int(0, 7, ""), "On-the-fly speed window of [axis] (Appendix B Table B-46)", "2.4.1", false),
    act("STOP", "STOP", Action::Stop, B, "Ramps every moving axis down to low speed and stops", "2.2.3"),
    act("STOP", "STOP[axis]", Action::Stop, A, "Ramps [axis] down to low speed and stops; an interpolation it belongs to stops whole", "2.2.3"),
    act("STORE", "STORE", Action::Store, B, "Saves the Table 2-19 settings to flash", "2.1.7"),
    reg("SYNC", "SYNC[axis]=[value]", Register::Sync, A, RW, int(I32_MIN, I32_MAX, ""), "Sync output condition and source (encoding not documented; shown raw)", "2.1.3.2.2", false),
    act("SYNF", "SYNF[axis]", Action::SyncOff, A, "Disables the sync output and the sync window of [axis]", "2.1.3.2.2"),
    reg("SYNMAX", "SYNMAX[axis]=[value]", Register::Synmax, A, RW, POSITION, "Upper bound of the sync pulse window", "2.1.3.2.2", false),
    reg("SYNMIN", "SYNMIN[axis]=[value]", Register::Synmin, A, RW, POSITION, "Lower bound of the sync pulse window", "2.1.3.2.2", false),
    act("SYNO", "SYNO[axis]", Action::SyncOn, A, "Enables the sync output of [axis] (X DO1 … U DO4)", "2.1.3.2.2"),
    reg("SYNP", "SYNP[axis]=[value]", Register::Synp, A, RW, POSITION, "Sync position, or the distance between pulses in continuous mode", "2.1.3.2.2", false),
    reg("SYNS", "SYNS[axis]", Register::Syns, A, R, int(0, 2, ""), "Sync status: 0 disabled, 1 waiting, 2 condition met", "2.1.3.2.2", false),
    act("SYNWF", "SYNWF[axis]", Action::SyncWindowOff, A, "Disables the sync window of [axis]; sync keeps running", "2.1.3.2.2"),
    act("SYNWO", "SYNWO[axis]", Action::SyncWindowOn, A, "Enables the sync window of [axis] (continuous mode)", "2.1.3.2.2"),
    motion("T", "T[axis][newtarget]", Kind::NewTarget, "On-the-fly target change of an individual position move of [axis]", "2.4.2"),
    reg("V", "V[0-99]=[value]", Register::V, Form::Index { first: 0, last: 99 }, RW, int(I32_MIN, I32_MAX, ""), "Standalone variable (32-bit signed)", "2.7.6", true),
    reg("VER", "VER", Register::Ver, B, R, Some(Values { min: 0, max: 0, unit: "", format: Format::Text }), "Firmware version", "2.1.1.1", false),
    motion("", "[axis][targetpos]…", Kind::Move, "Move 1–4 axes to their targets (X1000, X1000Y2000); several axes are linearly interpolated when EINT=1", "2.2.4.2"),
    reg("ZCNT", "ZCNT[axis]=[value]", Register::Zcnt, A, RW, int(0, 15, ""), "Z-index pulses for ZMOVE and homing: the move stops at pulse n+1 (§2.2.5.1: 0–15; Table 4-40 says 1–16)", "2.2.5.1", true),
    motion("ZMOVE", "ZMOVE[axis][+/-]", Kind::ZMove, "Move [axis] at HSPD in the + or − direction until ZCNT+1 Z-index pulses", "2.2.5.1"),
];

/// The rows of a keyword (case-insensitive).
pub fn rows_of(keyword: &str) -> impl Iterator<Item = &'static CommandSpec> + '_ {
    COMMANDS
        .iter()
        .filter(move |c| !c.keyword.is_empty() && c.keyword.eq_ignore_ascii_case(keyword))
}

/// The row of a register in a form.
pub fn register_row(register: Register, form: FormShape) -> Option<&'static CommandSpec> {
    COMMANDS
        .iter()
        .find(|c| c.kind == Kind::Register(register) && form.fits(c.form))
}

/// The row of an action in a form.
pub fn action_row(action: Action, form: FormShape) -> Option<&'static CommandSpec> {
    COMMANDS
        .iter()
        .find(|c| c.kind == Kind::Action(action) && form.fits(c.form))
}

/// The row of a motion command.
pub fn motion_row(kind: Kind) -> Option<&'static CommandSpec> {
    COMMANDS.iter().find(|c| c.kind == kind)
}

/// The shape of what follows a keyword, without the bounds of an index.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FormShape {
    Bare,
    Axis,
    Index,
}

impl FormShape {
    pub fn fits(self, form: Form) -> bool {
        matches!(
            (self, form),
            (FormShape::Bare, Form::Bare)
                | (FormShape::Axis, Form::Axis)
                | (FormShape::Index, Form::Index { .. })
        )
    }
}

/// Every keyword once, longest first: the order the parser tries them in,
/// so that `EXST` wins over `E` + axis and `SSPDM` over `SSPD`
/// (digest §9).
pub fn keywords_longest_first() -> &'static [&'static str] {
    // Sorted once: every poll's answer is read through the parser.
    static KEYWORDS: LazyLock<Vec<&'static str>> = LazyLock::new(|| {
        let mut keywords: Vec<&'static str> = COMMANDS
            .iter()
            .map(|c| c.keyword)
            .filter(|k| !k.is_empty())
            .collect();
        keywords.sort_by(|a, b| b.len().cmp(&a.len()).then(a.cmp(b)));
        keywords.dedup();
        keywords
    });
    &KEYWORDS
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn every_row_is_distinct_and_well_formed() {
        let mut seen = HashSet::new();
        for row in COMMANDS {
            let shape = match row.form {
                Form::Bare => "bare",
                Form::Axis => "axis",
                Form::Index { first, last } => {
                    assert!(first <= last, "{}", row.syntax);
                    "index"
                }
                Form::Motion => "motion",
            };
            assert!(
                seen.insert((row.keyword, shape)),
                "two {shape} rows for {}",
                row.keyword
            );
            assert!(
                row.keyword.chars().all(|c| c.is_ascii_uppercase()),
                "{}",
                row.keyword
            );
            assert!(row.syntax.starts_with(row.keyword), "{}", row.syntax);
            match (row.kind, row.access) {
                (Kind::Register(_), Access::Action) => panic!("{}: a register acts", row.syntax),
                (Kind::Register(_), _) => {
                    let values = row.values.expect("a register has values");
                    assert!(values.min <= values.max, "{}", row.syntax);
                }
                (_, access) => {
                    assert_eq!(access, Access::Action, "{}", row.syntax);
                    assert!(row.values.is_none(), "{}", row.syntax);
                }
            }
            assert_eq!(
                row.form == Form::Motion,
                !matches!(row.kind, Kind::Register(_) | Kind::Action(_))
            );
            assert!(!row.meaning.is_empty() && !row.section.is_empty());
        }
    }

    #[test]
    fn keywords_are_tried_longest_first() {
        let keywords = keywords_longest_first();
        let position = |k: &str| keywords.iter().position(|x| *x == k).expect(k);
        for (long, short) in [
            ("EXST", "E"),
            ("EOBOOT", "EO"),
            ("SSPDM", "SSPD"),
            ("CIRT", "CIR"),
            ("ARCT", "ARC"),
            ("SLOAD", "SL"),
            ("ZMOVE", "ZCNT"),
            ("HSPD", "H"),
        ] {
            assert!(position(long) < position(short), "{long} before {short}");
        }
        assert_eq!(
            keywords.len(),
            keywords.iter().collect::<HashSet<_>>().len()
        );
    }

    #[test]
    fn stored_rows_are_the_table_2_19_set() {
        // §2.1.7 Table 2-19, as the keywords of the rows STORE saves.
        let mut table: Vec<&str> = vec![
            "DB", "DIP", "DOBOOT", "DOP", "EINT", "EOBOOT", "ERC", "ERCD", "ERCP", "EXST", "ID",
            "IERR", "INP", "IOBOOT", "IOCFG", "IOP", "JDEL", "JENA", "JLIM", "JMAX", "JMIN",
            "JSPD", "JTOL", "MPD", "MPE", "MPM", "POL", "SAP", "SDC", "SDE", "SL", "SLA", "SLE",
            "SLOAD", "SLR", "SLT", "V", "ZCNT",
        ];
        table.sort_unstable();
        let mut stored: Vec<&str> = COMMANDS
            .iter()
            .filter(|c| c.stored)
            .map(|c| c.keyword)
            .collect();
        stored.sort_unstable();
        stored.dedup();
        assert_eq!(stored, table);
    }

    #[test]
    fn axes_know_their_letters_and_bits() {
        for (i, axis) in Axis::ALL.into_iter().enumerate() {
            assert_eq!(axis.index(), i);
            assert_eq!(Axis::from_letter(axis.letter()), Some(axis));
            assert_eq!(Axis::from_index(i), Some(axis));
        }
        assert_eq!(Axis::from_letter('u'), Some(Axis::U));
        assert_eq!(Axis::from_letter('W'), None);
        assert_eq!(Axis::from_index(4), None);
    }
}
