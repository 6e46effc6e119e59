//! The simulator's reading of the MCCL command set (manual Ch3 quick
//! reference and the command pages of Ch5–Ch13) as data: which axis a
//! command takes, which axis kinds it applies to, what parameter, whether
//! it reports (refused in background tasks, Ch4 "MCCL Multi-Tasking"),
//! and a line for `HE"mm"`. What each command does is in the `exec_*`
//! modules; this table is what the interpreter checks before.
//!
//! Kept here and not shared with `protocol/mccl` on purpose: the
//! simulator and the host codec are two readings of the manual that test
//! each other.

/// The manual's command groups (Ch3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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

/// The axis a command takes (Ch2 "MCCL Command Syntax").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisUse {
    /// None: an axis given is only remembered for the commands after it
    /// (`1CG,TR0`, `1TM-1`).
    None,
    /// One axis; none (axis 0) is −14.
    One,
    /// One axis, or 0 for every axis where the command's page says so
    /// (MA, MN, MF, AB, ST, LP, LT, MP, WS, GO, RT).
    OneOrAll,
}

/// The axis kinds a command applies to ("applies to" lines), a bit set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Applies(u8);

impl Applies {
    const SERVO_BIT: u8 = 1;
    const OPEN_BIT: u8 = 2;
    const CLOSED_BIT: u8 = 4;
    /// Analog Command Axis and Pulse Command Axis.
    pub const ANY: Applies = Applies(7);
    /// Analog Command Axis only.
    pub const SERVO: Applies = Applies(Self::SERVO_BIT);
    /// Pulse Command Axis, open or closed loop.
    pub const PULSE: Applies = Applies(Self::OPEN_BIT | Self::CLOSED_BIT);
    /// Analog Command Axis and closed-loop Pulse Command Axis.
    pub const CLOSED_LOOP: Applies = Applies(Self::SERVO_BIT | Self::CLOSED_BIT);
    /// Open-loop Pulse Command Axis only.
    pub const OPEN_LOOP: Applies = Applies(Self::OPEN_BIT);

    pub fn servo(self) -> bool {
        self.0 & Self::SERVO_BIT != 0
    }
    pub fn open_loop(self) -> bool {
        self.0 & Self::OPEN_BIT != 0
    }
    pub fn closed_loop(self) -> bool {
        self.0 & Self::CLOSED_BIT != 0
    }
}

/// What may follow the mnemonic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParamKind {
    /// Nothing (one given is ignored).
    None,
    /// A number, integer or real, within `min..=max`.
    Real { min: f64, max: f64 },
    /// An integer within `min..=max` (a real register given with `@n` is
    /// rounded, Ch4 "Controller User Registers"; a real typed is −1).
    Int { min: i64, max: i64 },
    /// A quoted string.
    Text,
    /// A quoted string or nothing (BK).
    OptionalText,
    /// 0, 1 or a quoted mnemonic (HE).
    HelpTopic,
    /// Reporting precision p: 0 or .1 … .5 (Ch8 introduction).
    Precision,
    /// `TRn.p`: a register 0–999 and, in the tenths digit, a reporting
    /// precision as [`ParamKind::Precision`] (Ch4 register table).
    RegisterPrecision,
}

/// One command of the table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CommandSpec {
    pub mnemonic: &'static str,
    pub group: Group,
    pub axis: AxisUse,
    pub applies: Applies,
    pub param: ParamKind,
    /// A reporting command: refused in a background task (Ch4).
    pub reports: bool,
    /// `false`: listed by the manual but not simulated (−21).
    pub simulated: bool,
    /// What it does, for `HE"mm"`.
    pub summary: &'static str,
}

const ANYWHERE: f64 = f64::INFINITY;

const fn real(min: f64, max: f64) -> ParamKind {
    ParamKind::Real { min, max }
}

const fn int(min: i64, max: i64) -> ParamKind {
    ParamKind::Int { min, max }
}

const NUMBER: ParamKind = real(-ANYWHERE, ANYWHERE);
const NON_NEGATIVE: ParamKind = real(0.0, ANYWHERE);
const CHANNEL: ParamKind = int(1, 64);
const REGISTER: ParamKind = int(0, 999);
/// Macro numbers are checked by the macro commands themselves (−5).
const MACRO: ParamKind = ANY_INT;
const POINT: ParamKind = int(0, 255);
const BIT: ParamKind = int(0, 31);
const ANY_INT: ParamKind = int(i32::MIN as i64, i32::MAX as i64);

const fn row(
    mnemonic: &'static str,
    group: Group,
    axis: AxisUse,
    applies: Applies,
    param: ParamKind,
    summary: &'static str,
) -> CommandSpec {
    CommandSpec {
        mnemonic,
        group,
        axis,
        applies,
        param,
        reports: false,
        simulated: true,
        summary,
    }
}

/// A setup or motion command on one axis.
const fn axis(
    mnemonic: &'static str,
    group: Group,
    applies: Applies,
    param: ParamKind,
    summary: &'static str,
) -> CommandSpec {
    row(mnemonic, group, AxisUse::One, applies, param, summary)
}

/// A command without axis.
const fn plain(
    mnemonic: &'static str,
    group: Group,
    param: ParamKind,
    summary: &'static str,
) -> CommandSpec {
    row(mnemonic, group, AxisUse::None, Applies::ANY, param, summary)
}

/// A reporting command on one axis with a precision parameter.
const fn tell(mnemonic: &'static str, applies: Applies, summary: &'static str) -> CommandSpec {
    reporting(row(
        mnemonic,
        Group::Reporting,
        AxisUse::One,
        applies,
        ParamKind::Precision,
        summary,
    ))
}

const fn reporting(spec: CommandSpec) -> CommandSpec {
    CommandSpec {
        reports: true,
        ..spec
    }
}

const fn unsimulated(spec: CommandSpec) -> CommandSpec {
    CommandSpec {
        simulated: false,
        ..spec
    }
}

use AxisUse::OneOrAll;
use Group::*;

/// Every mnemonic of Ch3 plus the ones only Ch4–Ch13 give (EE, PK, DE, HE,
/// ID, NP, FM, FT, ME, OT), in the manual's group order.
#[rustfmt::skip]
pub const COMMANDS: &[CommandSpec] = &[
    // ---- Setup (Ch5) ----
    axis("AG", Setup, Applies::SERVO, NUMBER, "set Acceleration feed-forward Gain"),
    axis("AH", Setup, Applies::PULSE, NUMBER, "Auxiliary encoder define Home"),
    axis("BD", Setup, Applies::SERVO, NUMBER, "Backlash compensation Distance"),
    axis("DB", Setup, Applies::SERVO, NON_NEGATIVE, "set position DeadBand"),
    axis("DG", Setup, Applies::SERVO, NUMBER, "set Deceleration feed-forward Gain"),
    axis("DH", Setup, Applies::ANY, NUMBER, "Define Home (current position = n)"),
    axis("DI", Setup, Applies::ANY, int(0, 1), "Direction for velocity mode (0 +, 1 -)"),
    axis("DS", Setup, Applies::ANY, real(0.0, ANYWHERE), "Deceleration Set"),
    axis("DT", Setup, Applies::SERVO, NON_NEGATIVE, "Delay at Target (s)"),
    axis("EE", Setup, Applies::ANY, int(0, 2), "Encoder fail Enable (0 off, 1 on, 2 aux)"),
    unsimulated(axis("EI", Setup, Applies::ANY, int(0, u32::MAX as i64), "Enable host Interrupts (MCAPI only)")),
    axis("ES", Setup, Applies::PULSE, NON_NEGATIVE, "Encoder counts / Steps Scale (steps per count)"),
    axis("FC", Setup, Applies::PULSE, ParamKind::None, "Full Current"),
    axis("FF", Setup, Applies::ANY, ParamKind::None, "amplifier Fault input ofF"),
    unsimulated(axis("FL", Setup, Applies::SERVO, NUMBER, "IIR Filter Load coefficients")),
    axis("FN", Setup, Applies::ANY, ParamKind::None, "amplifier Fault input oN"),
    axis("FR", Setup, Applies::SERVO, int(0, i32::MAX as i64), "set derivative sampling period ((n+1) x sample)"),
    axis("HC", Setup, Applies::PULSE, ParamKind::None, "Half Current"),
    axis("HL", Setup, Applies::ANY, NUMBER, "set motion High soft Limit"),
    axis("HS", Setup, Applies::ANY, ParamKind::None, "set High Speed (servo 4 kHz)"),
    axis("IL", Setup, Applies::CLOSED_LOOP, NON_NEGATIVE, "set Integration Limit"),
    axis("IO", Setup, Applies::CLOSED_LOOP, int(0, 2), "Integral Option"),
    unsimulated(axis("LA", Setup, Applies::SERVO, NUMBER, "Load commutation phase A")),
    unsimulated(axis("LB", Setup, Applies::SERVO, NUMBER, "Load commutation phase B")),
    unsimulated(axis("LD", Setup, Applies::SERVO, NUMBER, "Load commutation Divisor")),
    unsimulated(axis("LE", Setup, Applies::SERVO, NUMBER, "Load commutation encoder prescale")),
    axis("LF", Setup, Applies::ANY, int(0, 15), "motion Limits ofF"),
    axis("LL", Setup, Applies::ANY, NUMBER, "set motion Low soft Limit"),
    axis("LM", Setup, Applies::ANY, int(0, 136), "Limit Mode"),
    axis("LN", Setup, Applies::ANY, int(0, 15), "motion Limits oN"),
    unsimulated(axis("LR", Setup, Applies::SERVO, NUMBER, "Load commutation Repeat count")),
    axis("LS", Setup, Applies::ANY, ParamKind::None, "set Low Speed (servo 1 kHz)"),
    axis("MS", Setup, Applies::ANY, ParamKind::None, "set Medium Speed (servo 2 kHz)"),
    // MV "will have no effect on servos": taken, ignored.
    axis("MV", Setup, Applies::ANY, NON_NEGATIVE, "set Minimum Velocity (steppers)"),
    unsimulated(axis("NF", Setup, Applies::SERVO, ParamKind::None, "No IIR Filter")),
    axis("OB", Setup, Applies::ANY, real(0.0, 10.0), "set the Output deadBand (V)"),
    axis("OM", Setup, Applies::ANY, int(0, 3), "set Output Mode"),
    axis("OO", Setup, Applies::SERVO, real(-10.0, 10.0), "set the Output Offset (V)"),
    axis("PH", Setup, Applies::CLOSED_LOOP, int(0, 1), "set servo output PHase"),
    plain("PK", Setup, int(1, 255), "Pwm time Konstant (n x 610 Hz)"),
    axis("SA", Setup, Applies::ANY, NON_NEGATIVE, "Set Acceleration"),
    axis("SD", Setup, Applies::CLOSED_LOOP, NON_NEGATIVE, "Set Derivative gain"),
    axis("SE", Setup, Applies::CLOSED_LOOP, NON_NEGATIVE, "Stop on following Error (0 off)"),
    axis("SG", Setup, Applies::CLOSED_LOOP, real(0.000153, 10.0), "Set proportional Gain (V/count)"),
    axis("SI", Setup, Applies::CLOSED_LOOP, NON_NEGATIVE, "Set Integral gain"),
    axis("SQ", Setup, Applies::SERVO, real(-10.0, 10.0), "Set torQue (output limit / torque mode volts)"),
    axis("SS", Setup, Applies::ANY, NUMBER, "Set Slave ratio"),
    axis("SV", Setup, Applies::ANY, NON_NEGATIVE, "Set Velocity"),
    plain("UA", Setup, int(0, 8), "Use Axis as default"),
    axis("UK", Setup, Applies::SERVO, NON_NEGATIVE, "set User output Konstant"),
    axis("UO", Setup, Applies::ANY, NUMBER, "set User Offset"),
    unsimulated(axis("UP", Setup, Applies::ANY, NUMBER, "Use Physical axis")),
    axis("UR", Setup, Applies::ANY, real(f64::MIN_POSITIVE, ANYWHERE), "set User Rate conversion (s per time unit)"),
    axis("US", Setup, Applies::ANY, real(f64::MIN_POSITIVE, ANYWHERE), "set User Scale (counts per user unit)"),
    plain("UT", Setup, NON_NEGATIVE, "set User Time conversion (s per dwell unit)"),
    axis("UZ", Setup, Applies::ANY, NUMBER, "set User Zero"),
    axis("VA", Setup, Applies::ANY, NON_NEGATIVE, "set Vector Acceleration"),
    axis("VD", Setup, Applies::ANY, NON_NEGATIVE, "set Vector Deceleration"),
    axis("VG", Setup, Applies::SERVO, NUMBER, "set Velocity feed-forward Gain"),
    axis("VO", Setup, Applies::ANY, NON_NEGATIVE, "set Velocity Override"),
    axis("VV", Setup, Applies::ANY, NON_NEGATIVE, "set Vector Velocity"),
    unsimulated(axis("YF", Setup, Applies::SERVO, ParamKind::None, "Yes IIR Filter")),
    unsimulated(axis("ZF", Setup, Applies::SERVO, ParamKind::None, "Zero IIR Filter coefficients")),
    // ---- Mode (Ch6) ----
    axis("CM", Mode, Applies::ANY, int(1, 8), "enable Contour Mode (n = controlling axis)"),
    axis("GM", Mode, Applies::SERVO, ParamKind::None, "enable Gain Mode (no velocity profile)"),
    axis("IM", Mode, Applies::PULSE, int(0, 128), "Input Mode (0 open, 1 closed loop, 128 PID changes)"),
    axis("PM", Mode, Applies::ANY, ParamKind::None, "enable Position Mode"),
    axis("QM", Mode, Applies::SERVO, ParamKind::None, "enable torQue Mode"),
    axis("SM", Mode, Applies::ANY, int(0, 135), "Set Master/slave mode (n = master, 0 ends)"),
    axis("VM", Mode, Applies::ANY, ParamKind::None, "enable Velocity Mode"),
    // ---- Motion (Ch7) ----
    row("AB", Motion, OneOrAll, Applies::ANY, ParamKind::None, "ABort (stop at once)"),
    axis("AF", Motion, Applies::PULSE, NUMBER, "Auxiliary encoder Find index"),
    axis("BC", Motion, Applies::ANY, int(i32::MIN as i64, 1024), "Begin position Compare"),
    axis("BF", Motion, Applies::SERVO, ParamKind::None, "Backlash compensation oFf"),
    axis("BN", Motion, Applies::SERVO, ParamKind::None, "Backlash compensation oN"),
    axis("CA", Motion, Applies::ANY, NUMBER, "arc Center Absolute"),
    axis("CB", Motion, Applies::ANY, int(i32::MIN as i64, 1024), "position Capture Begin"),
    axis("CD", Motion, Applies::ANY, NON_NEGATIVE, "Contour Distance"),
    axis("CP", Motion, Applies::ANY, int(0, 3), "Contour Path (0 user, 1 linear, 2 CW, 3 CCW)"),
    axis("CR", Motion, Applies::ANY, NUMBER, "arc Center Relative"),
    unsimulated(axis("EA", Motion, Applies::ANY, NUMBER, "arc Ending Angle absolute")),
    axis("EL", Motion, Applies::OPEN_LOOP, NUMBER, "home Edge Latch (arm)"),
    unsimulated(axis("ER", Motion, Applies::ANY, NUMBER, "arc Ending angle Relative")),
    axis("FE", Motion, Applies::OPEN_LOOP, NUMBER, "Find Edge (blocks until captured)"),
    axis("FI", Motion, Applies::CLOSED_LOOP, NUMBER, "Find Index (blocks until captured)"),
    axis("GH", Motion, Applies::ANY, ParamKind::None, "Go Home"),
    row("GO", Motion, OneOrAll, Applies::ANY, int(0, 1), "GO (velocity or contour motion)"),
    row("HO", Motion, AxisUse::None, Applies::ANY, ParamKind::None, "HOme (run macro a; 9 without axis)"),
    axis("IA", Motion, Applies::CLOSED_LOOP, NUMBER, "Index Arm"),
    axis("LC", Motion, Applies::ANY, NUMBER, "Load Compare position"),
    row("LP", Motion, OneOrAll, Applies::ANY, POINT, "Learn Position"),
    row("LT", Motion, OneOrAll, Applies::ANY, POINT, "Learn Target"),
    row("MA", Motion, OneOrAll, Applies::ANY, NUMBER, "Move Absolute"),
    row("MF", Motion, OneOrAll, Applies::ANY, ParamKind::None, "Motor ofF"),
    row("MN", Motion, OneOrAll, Applies::ANY, ParamKind::None, "Motor oN"),
    row("MP", Motion, OneOrAll, Applies::ANY, POINT, "Move to Point"),
    axis("MR", Motion, Applies::ANY, NUMBER, "Move Relative (to the target)"),
    axis("NC", Motion, Applies::ANY, NUMBER, "Next Compare increment"),
    axis("NS", Motion, Applies::ANY, ParamKind::None, "No Synchronization"),
    axis("OC", Motion, Applies::ANY, int(0, 131), "Output mode for Compare"),
    axis("OP", Motion, Applies::ANY, real(f64::MIN_POSITIVE, ANYWHERE), "Output Period (s)"),
    axis("PP", Motion, Applies::ANY, ParamKind::None, "Profile Parabolic"),
    axis("PR", Motion, Applies::ANY, int(0, 1024), "Record motion data"),
    axis("PS", Motion, Applies::ANY, ParamKind::None, "Profile S-curve"),
    axis("PT", Motion, Applies::ANY, ParamKind::None, "Profile Trapezoidal"),
    axis("RR", Motion, Applies::ANY, NUMBER, "aRc Radius"),
    axis("SN", Motion, Applies::ANY, ParamKind::None, "Synchronization oN"),
    row("ST", Motion, OneOrAll, Applies::ANY, ParamKind::None, "STop (decelerate)"),
    // ---- Reporting (Ch8) ----
    tell("AT", Applies::PULSE, "Auxiliary encoder Tell position"),
    tell("AZ", Applies::PULSE, "Auxiliary encoder tell index"),
    axis("CG", Reporting, Applies::ANY, ParamKind::None, "Capture Get count (to ACC)"),
    reporting(axis("DA", Reporting, Applies::PULSE, int(0, 1023), "Display recorded Aux. encoder position")),
    reporting(plain("DE", Reporting, int(0, 65535), "Display mEmory (256 bytes)")),
    reporting(axis("DO", Reporting, Applies::ANY, int(0, 1023), "Display recorded Optimal position")),
    reporting(axis("DQ", Reporting, Applies::SERVO, int(0, 1023), "Display recorded DAC output")),
    reporting(axis("DR", Reporting, Applies::ANY, int(0, 1023), "Display Recorded actual position")),
    axis("GC", Reporting, Applies::ANY, ParamKind::None, "Get Compare count (to ACC)"),
    reporting(row("ID", Reporting, AxisUse::None, Applies::ANY, int(0, 7), "Information Display")),
    reporting(plain("TA", Reporting, int(1, 8), "Tell Analog input")),
    tell("TB", Applies::ANY, "Tell Breakpoint position"),
    reporting(plain("TC", Reporting, int(0, 64), "Tell digital Channel (0 = inputs 1-32)")),
    tell("TD", Applies::CLOSED_LOOP, "Tell Derivative gain"),
    reporting(plain("TE", Reporting, ParamKind::None, "Tell command interpreter Error")),
    tell("TF", Applies::CLOSED_LOOP, "Tell Following error"),
    tell("TG", Applies::CLOSED_LOOP, "Tell proportional Gain"),
    tell("TI", Applies::CLOSED_LOOP, "Tell Integral gain"),
    tell("TK", Applies::CLOSED_LOOP, "Tell velocity gain"),
    tell("TL", Applies::CLOSED_LOOP, "Tell integration Limit"),
    reporting(plain("TM", Macro, MACRO, "Tell Macros (-1 = all)")),
    tell("TO", Applies::ANY, "Tell Optimal position"),
    tell("TP", Applies::ANY, "Tell Position"),
    tell("TQ", Applies::SERVO, "Tell torQue setting"),
    reporting(plain("TR", Register, ParamKind::RegisterPrecision, "Tell Register n")),
    reporting(axis("TS", Reporting, Applies::ANY, int(0, 191), "Tell Status word or bit")),
    tell("TT", Applies::ANY, "Tell Target"),
    tell("TV", Applies::ANY, "Tell Velocity"),
    reporting(axis("TX", Reporting, Applies::ANY, ParamKind::None, "Tell contouring count")),
    tell("TZ", Applies::CLOSED_LOOP, "Tell index position"),
    reporting(plain("VE", Reporting, ParamKind::None, "tell VErsion")),
    // ---- I/O (Ch9) ----
    plain("CF", Io, CHANNEL, "Channel ofF"),
    plain("CH", Io, int(0, 64), "Channel High true logic (0 = all)"),
    plain("CL", Io, int(0, 64), "Channel Low true logic (0 = all)"),
    plain("CN", Io, CHANNEL, "Channel oN"),
    plain("GA", Register, int(1, 8), "Get Analog (to ACC)"),
    plain("OA", Register, int(1, 8), "Output Analog (ACC)"),
    plain("WF", Sequence, CHANNEL, "Wait for channel ofF"),
    plain("WN", Sequence, CHANNEL, "Wait for channel oN"),
    // ---- Macro and multi-tasking (Ch10) ----
    plain("BK", Macro, ParamKind::OptionalText, "BreaK (skip the rest; \"text\" single-steps)"),
    plain("ET", Macro, ANY_INT, "Escape (end) Task n"),
    plain("GT", Macro, MACRO, "Generate Task (run macro n in the background)"),
    plain("MC", Macro, MACRO, "Macro Call"),
    plain("MD", Macro, MACRO, "Macro Define"),
    plain("MJ", Macro, MACRO, "Macro Jump"),
    plain("NO", Macro, ParamKind::None, "No Operation"),
    plain("NP", Macro, int(11, 255), "New Priority of this task"),
    plain("RM", Macro, ParamKind::None, "Reset (erase) all Macros"),
    // ---- Register (Ch11) ----
    plain("AA", Register, NUMBER, "Accumulator Add"),
    plain("AC", Register, ParamKind::None, "Accumulator Complement"),
    plain("AD", Register, NUMBER, "Accumulator Divide"),
    plain("AE", Register, NUMBER, "Accumulator Exclusive or"),
    plain("AL", Register, NUMBER, "Accumulator Load"),
    plain("AM", Register, NUMBER, "Accumulator Multiply"),
    plain("AN", Register, NUMBER, "Accumulator aNd"),
    plain("AO", Register, NUMBER, "Accumulator Or"),
    plain("AR", Register, REGISTER, "copy Accumulator to Register n"),
    plain("AS", Register, NUMBER, "Accumulator Subtract"),
    plain("AV", Register, int(1, 25), "Accumulator eValuate"),
    axis("AX", Register, Applies::PULSE, ParamKind::None, "get Aux. indeX position (to ACC)"),
    unsimulated(plain("GF", Register, NUMBER, "Get IIR Filter coefficients")),
    plain("GU", Register, ParamKind::None, "Get the default axis (to ACC)"),
    axis("GX", Register, Applies::PULSE, ParamKind::None, "Get auXiliary encoder position (to ACC)"),
    plain("LU", Register, ParamKind::Text, "Look Up motor table variable"),
    plain("RA", Register, REGISTER, "copy Register n to Accumulator"),
    row("RB", Register, AxisUse::None, Applies::ANY, ANY_INT, "Read Byte into accumulator"),
    row("RD", Register, AxisUse::None, Applies::ANY, ANY_INT, "Read Double into accumulator"),
    row("RL", Register, AxisUse::None, Applies::ANY, ANY_INT, "Read Long into accumulator"),
    row("RV", Register, AxisUse::None, Applies::ANY, ANY_INT, "Read float into accumulator"),
    row("RW", Register, AxisUse::None, Applies::ANY, ANY_INT, "Read Word into accumulator"),
    plain("SL", Register, int(1, 31), "Shift Left accumulator"),
    plain("SR", Register, int(1, 31), "Shift Right accumulator"),
    plain("WB", Register, ANY_INT, "Write accumulator Byte to n"),
    plain("WD", Register, ANY_INT, "Write accumulator Double to n"),
    plain("WL", Register, ANY_INT, "Write accumulator Long to n"),
    plain("WV", Register, ANY_INT, "Write accumulator float to n"),
    plain("WW", Register, ANY_INT, "Write accumulator Word to n"),
    // ---- Sequence (Ch12) ----
    plain("DF", Sequence, CHANNEL, "Do if channel ofF (else skip the rest)"),
    plain("DN", Sequence, CHANNEL, "Do if channel oN (else skip the rest)"),
    plain("IB", Sequence, NUMBER, "If accumulator Below n do next, else skip 2"),
    plain("IC", Sequence, BIT, "If accumulator bit Clear do next, else skip 2"),
    plain("IE", Sequence, NUMBER, "If accumulator Equals n do next, else skip 2"),
    plain("IF", Sequence, CHANNEL, "If channel ofF do next, else skip 2"),
    plain("IG", Sequence, NUMBER, "If accumulator Greater do next, else skip 2"),
    plain("IN", Sequence, CHANNEL, "If channel oN do next, else skip 2"),
    axis("IP", Sequence, Applies::ANY, NUMBER, "Interrupt (breakpoint) on absolute Position"),
    axis("IR", Sequence, Applies::ANY, NUMBER, "Interrupt (breakpoint) on Relative position"),
    plain("IS", Sequence, BIT, "If accumulator bit Set do next, else skip 2"),
    plain("IU", Sequence, NUMBER, "If accumulator Unequal do next, else skip 2"),
    plain("JP", Sequence, ANY_INT, "JumP to command n (0-based)"),
    plain("JR", Sequence, ANY_INT, "Jump Relative n commands"),
    plain("RP", Sequence, int(i32::MIN as i64, i32::MAX as i64), "RePeat (n more times; 0 forever)"),
    plain("WA", Sequence, NON_NEGATIVE, "WAit n (x UT) seconds"),
    axis("WE", Sequence, Applies::OPEN_LOOP, ParamKind::None, "Wait for Edge"),
    axis("WI", Sequence, Applies::CLOSED_LOOP, NON_NEGATIVE, "Wait for Index"),
    axis("WP", Sequence, Applies::ANY, NUMBER, "Wait for absolute Position"),
    axis("WR", Sequence, Applies::ANY, NUMBER, "Wait for Relative position"),
    row("WS", Sequence, OneOrAll, Applies::ANY, NON_NEGATIVE, "Wait for Stop (trajectory complete) + n s"),
    axis("WT", Sequence, Applies::ANY, NON_NEGATIVE, "Wait for Target + n s"),
    // ---- Miscellaneous (Ch13) ----
    plain("DM", Misc, ParamKind::None, "Decimal Mode"),
    plain("DW", Misc, ParamKind::None, "Disable Watchdog (factory use)"),
    plain("EF", Misc, int(0, 3), "Echo ofF (factory use)"),
    plain("EN", Misc, int(0, 3), "Echo oN (factory use)"),
    plain("FD", Misc, ParamKind::Text, "Format text with Double into memory"),
    plain("FM", Misc, int(1, 65536), "Free Memory"),
    plain("FT", Misc, ParamKind::Text, "Format Text with integer into memory"),
    reporting(plain("HE", Misc, ParamKind::HelpTopic, "HElp (0 mnemonics, 1 variables, \"mm\")")),
    plain("HM", Misc, ParamKind::None, "Hexadecimal Mode"),
    plain("ME", Misc, int(1, 65536), "MEmory allocate"),
    plain("OD", Misc, ParamKind::Text, "Output text with Double (%f)"),
    plain("OT", Misc, ParamKind::Text, "Output Text with integer (%d)"),
    plain("PC", Misc, int(0, 255), "set Prompt Character (0 none)"),
    row("RT", Misc, OneOrAll, Applies::ANY, ParamKind::None, "ReseT (axis, or 0/none = controller)"),
];

/// The command spelled `mnemonic` (two letters, upper case).
pub fn find(mnemonic: &str) -> Option<&'static CommandSpec> {
    COMMANDS.iter().find(|c| c.mnemonic == mnemonic)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mnemonic_is_two_upper_case_letters_and_unique() {
        for (i, spec) in COMMANDS.iter().enumerate() {
            assert_eq!(spec.mnemonic.len(), 2, "{}", spec.mnemonic);
            assert!(spec.mnemonic.bytes().all(|b| b.is_ascii_uppercase()));
            assert!(
                COMMANDS[i + 1..]
                    .iter()
                    .all(|c| c.mnemonic != spec.mnemonic),
                "{} twice",
                spec.mnemonic
            );
        }
    }

    #[test]
    fn the_quick_reference_of_chapter_3_is_covered() {
        // Ch3's tables, every group (OCR look-alikes normalised).
        let ch3 = "AG AH BD DB DG DH DI DS DT EI ES FC FF FL FN FR HC HL HS IL IO LA LB LD LE LF LL LM \
                   LN LR LS MS MV NF OB OM OO PH SA SD SE SG SI SQ SS SV UA UK UO UP UR US UT UZ VA \
                   VD VG VO VV YF ZF AB AF BC BF BN CA CB CD CP CR EA EL ER FE FI GH GO HO IA LC LP \
                   LT MA MF MN MP MR NC NS OC OP PP PR PS PT RR SN ST CM GM IM PM SM QM VM AT AZ CG \
                   DA DO DQ DR GC TA ID TB TC TD TE TF TG TI TK TL TM TO TP TQ TR TS TT TV TX TZ VE \
                   AA AC AD AE AL AM AN AO AR AS AV AX GA GF GU GX LU OA RA RB RD RL RV RW SL SR WB \
                   WD WL WV WW BK ET GT MC MD MJ NP RM DF DN IB IC IE IF IG IN IP IR IS IU JP JR RP \
                   WA WE WF WI WN WP WR WS WT DM DW EF EN FD FM FT HM ME NO OD OT PC RT CF CH CL CN";
        for mnemonic in ch3.split_whitespace() {
            assert!(find(mnemonic).is_some(), "{mnemonic} missing");
        }
        for extra in ["EE", "PK", "DE", "HE"] {
            assert!(find(extra).is_some(), "{extra} missing");
        }
    }

    #[test]
    fn only_the_undescribed_and_mcapi_commands_are_unsimulated() {
        let mut unsimulated: Vec<_> = COMMANDS
            .iter()
            .filter(|c| !c.simulated)
            .map(|c| c.mnemonic)
            .collect();
        unsimulated.sort_unstable();
        assert_eq!(
            unsimulated,
            [
                "EA", "EI", "ER", "FL", "GF", "LA", "LB", "LD", "LE", "LR", "NF", "UP", "YF", "ZF"
            ]
        );
    }
}
