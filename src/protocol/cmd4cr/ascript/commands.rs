//! The A-Script standalone command set as data: Table 5-42 (§5.2) and the
//! "Standalone" rows of the availability tables in §2, one row per form
//! (`HSPD` and `HSPD[axis]` are two rows, as in the manual), each naming
//! the ASCII command of the same meaning (§2's tables pair them). Value
//! ranges, units and what a command means come from that ASCII row of
//! [`crate::protocol::cmd4cr::catalog`], so a value A-Script accepts is one
//! the ASCII parser accepts. Which ASCII commands programs lack is derived
//! from the same pairing.

use std::fmt;

use super::super::catalog::{
    self, Access, Action, Axis, CommandSpec, Form, FormShape, Kind as AsciiKind, Register,
    action_row, motion_row, register_row, rows_of,
};
use super::super::command::{ANGLE_MAX, HOME_MODE_MAX};

/// The shape of a standalone command's statement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// A value: read as an operand (`V1=MSTX`), written with `NAME=value`
    /// (as far as the standalone R/W column allows).
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

/// The ASCII command a standalone command corresponds to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ascii {
    Register(Register),
    Action(Action),
    /// A motion command with a syntax of its own (circle, jog, …).
    Motion(AsciiKind),
    /// None: only a program has it (`WAIT`, `DELAY`).
    None,
}

impl Ascii {
    /// Whether this is the ASCII command `kind` of the catalog.
    pub fn is(self, kind: AsciiKind) -> bool {
        match self {
            Ascii::Register(r) => kind == AsciiKind::Register(r),
            Ascii::Action(a) => kind == AsciiKind::Action(a),
            Ascii::Motion(k) => kind == k,
            Ascii::None => false,
        }
    }
}

/// The values a write accepts, inclusive, and their unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ValueRange {
    pub min: i64,
    pub max: i64,
    pub unit: &'static str,
}

impl ValueRange {
    pub fn contains(self, value: i64) -> bool {
        (self.min..=self.max).contains(&value)
    }
}

impl fmt::Display for ValueRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}..{}", self.min, self.max)?;
        if !self.unit.is_empty() {
            write!(f, " {}", self.unit.trim())?;
        }
        Ok(())
    }
}

/// Signed 32-bit: the standalone variables and what they compute (§2.7.6).
pub const I32: ValueRange = ValueRange {
    min: i32::MIN as i64,
    max: i32::MAX as i64,
    unit: "",
};
/// Positions (§1.2: 28 bits).
pub const POSITION: ValueRange = ValueRange {
    min: catalog::POSITION_MIN,
    max: catalog::POSITION_MAX,
    unit: "pulses",
};
/// An arc's absolute end angle, as the ASCII parser takes it.
pub const ANGLE: ValueRange = ValueRange {
    min: 0,
    max: ANGLE_MAX,
    unit: "millidegrees",
};
/// The homing modes (Appendix A).
pub const HOME_MODE: ValueRange = ValueRange {
    min: 0,
    max: HOME_MODE_MAX as i64,
    unit: "",
};
/// DELAY: the manual gives no limit; a time is not negative and the
/// controller holds 32-bit values.
const DELAY_MS: ValueRange = ValueRange {
    min: 0,
    max: i32::MAX as i64,
    unit: "ms",
};

/// One form of a standalone command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CommandInfo {
    pub name: &'static str,
    /// Bare, an axis letter, or an index; circles and arcs are `Motion`.
    pub form: Form,
    pub shape: Shape,
    pub ascii: Ascii,
    /// Where the manual describes it.
    pub section: &'static str,
}

impl CommandInfo {
    pub fn readable(&self) -> bool {
        matches!(self.shape, Shape::Register(a) if a.reads()) || self.shape == Shape::Variable
    }

    pub fn writable(&self) -> bool {
        matches!(self.shape, Shape::Register(a) if a.writes()) || self.shape == Shape::Variable
    }

    /// The row of the ASCII table for the same command in the same form:
    /// its values, unit and meaning.
    pub fn ascii_row(&self) -> Option<&'static CommandSpec> {
        let shape = match self.form {
            Form::Bare => FormShape::Bare,
            Form::Axis => FormShape::Axis,
            Form::Index { .. } => FormShape::Index,
            Form::Motion => FormShape::Bare,
        };
        match self.ascii {
            Ascii::Register(register) => register_row(register, shape),
            Ascii::Action(action) => action_row(action, shape),
            Ascii::Motion(kind) => motion_row(kind),
            Ascii::None => None,
        }
    }

    /// What a write accepts: the ASCII row's range (DELAY's own).
    pub fn values(&self) -> Option<ValueRange> {
        if self.shape == Shape::Delay {
            return Some(DELAY_MS);
        }
        let values = self.ascii_row()?.values?;
        Some(ValueRange {
            min: values.min,
            max: values.max,
            unit: values.unit,
        })
    }

    /// What it does (the ASCII table's words, or ours for WAIT and DELAY).
    pub fn meaning(&self) -> &'static str {
        match (self.shape, self.ascii_row()) {
            (Shape::Wait, _) => "Waits until the motion of [axis] is complete",
            (Shape::Delay, _) => "Waits this many milliseconds",
            (_, Some(row)) => row.meaning,
            (_, None) => "",
        }
    }

    /// The form as the manual writes it: `HSPD[axis]=value`, `DO[1-4]`,
    /// `HOME[axis][+/-][mode]`.
    pub fn syntax(&self) -> String {
        let address = match self.form {
            Form::Bare | Form::Motion => String::new(),
            Form::Axis => "[axis]".to_string(),
            Form::Index { first, last } => format!("[{first}-{last}]"),
        };
        let tail = match self.shape {
            Shape::Register(Access::Write) | Shape::Delay => "=value",
            Shape::Register(Access::ReadWrite) | Shape::Variable => "[=value]",
            Shape::Register(_) | Shape::Action | Shape::Wait => "",
            Shape::Jog | Shape::ZMove => "[+/-]",
            Shape::Home => "[+/-][mode]",
            Shape::Circle => "[A1][A2]P|N[C1]:[C2]",
            Shape::Arc => "[A1][A2]P|N[C1]:[C2]:[θ]",
            Shape::HelixCircle => "P|N[C1]:[C2]:[Z]",
            Shape::HelixArc => "P|N[C1]:[C2]:[θ]:[Z]",
        };
        format!("{}{address}{tail}", self.name)
    }
}

const fn row(
    name: &'static str,
    form: Form,
    shape: Shape,
    ascii: Ascii,
    section: &'static str,
) -> CommandInfo {
    CommandInfo {
        name,
        form,
        shape,
        ascii,
        section,
    }
}

use Access::{Read as R, ReadWrite as RW, Write as W};
use Form::{Axis as AX, Bare as NO, Motion as MO};

const fn idx(first: u8, last: u8) -> Form {
    Form::Index { first, last }
}

const fn reg(register: Register) -> Ascii {
    Ascii::Register(register)
}

const fn act(action: Action) -> Ascii {
    Ascii::Action(action)
}

/// Every standalone command form: Table 5-42 plus `LT`, `LTS`, `LTP`,
/// `LTE` (§2.1.3.2.1), `MPGE` (§2.1.3.1.4) and `PWM` (§2.1.3.3.3), which
/// only the §2 availability tables list. The access is the standalone one
/// (T5-42's R/W column: `SSPDM` is write-only there); where that column
/// contradicts its own description (digest erratum 19) the description
/// wins: `SYNSTAT` "Returns the status" is read-only, `JOYDEL` "Returns"
/// and pairs with the read/write `JDEL`.
#[rustfmt::skip]
pub const COMMANDS: &[CommandInfo] = &[
    row("ABORT", NO, Shape::Action, act(Action::Abort), "2.2.3"),
    row("ABORT", AX, Shape::Action, act(Action::Abort), "2.2.3"),
    row("ABS", NO, Shape::Action, act(Action::Abs), "2.2.4.1"),
    row("ACC", NO, Shape::Register(RW), reg(Register::Acc), "2.1.4"),
    row("ACC", AX, Shape::Register(RW), reg(Register::Acc), "2.1.4"),
    row("AI", idx(1, 2), Shape::Register(R), reg(Register::Ai), "2.1.3.3.2"),
    row("ARC", MO, Shape::Arc, Ascii::Motion(AsciiKind::Arc), "2.3.2.1"),
    row("ARCT", MO, Shape::HelixArc, Ascii::Motion(AsciiKind::HelicalArc), "2.3.3"),
    row("BUFOFF", NO, Shape::Action, act(Action::BufferOff), "2.3.4"),
    row("BUFON", NO, Shape::Action, act(Action::BufferOn), "2.3.4"),
    row("CIR", MO, Shape::Circle, Ascii::Motion(AsciiKind::Circle), "2.3.2"),
    row("CIRT", MO, Shape::HelixCircle, Ascii::Motion(AsciiKind::HelicalCircle), "2.3.3"),
    row("DEC", NO, Shape::Register(RW), reg(Register::Dec), "2.1.4"),
    row("DEC", AX, Shape::Register(RW), reg(Register::Dec), "2.1.4"),
    row("DELAY", NO, Shape::Delay, Ascii::None, "5.2"),
    row("DI", NO, Shape::Register(R), reg(Register::Di), "2.1.3.2.1"),
    row("DI", idx(1, 4), Shape::Register(R), reg(Register::Di), "2.1.3.2.1"),
    row("DO", NO, Shape::Register(RW), reg(Register::Do), "2.1.3.2.2"),
    row("DO", idx(1, 4), Shape::Register(RW), reg(Register::Do), "2.1.3.2.2"),
    row("E", AX, Shape::Register(RW), reg(Register::E), "2.6.1.2"),
    row("ECLEAR", AX, Shape::Action, act(Action::Clr), "2.6.2.3"),
    row("EINT", NO, Shape::Register(RW), reg(Register::Eint), "2.3.1"),
    row("EO", NO, Shape::Register(RW), reg(Register::Eo), "2.2.1"),
    row("EO", idx(1, 4), Shape::Register(RW), reg(Register::Eo), "2.2.1"),
    row("HOME", AX, Shape::Home, Ascii::Motion(AsciiKind::Home), "2.2.5"),
    row("HSPD", NO, Shape::Register(RW), reg(Register::Hspd), "2.1.4"),
    row("HSPD", AX, Shape::Register(RW), reg(Register::Hspd), "2.1.4"),
    row("INC", NO, Shape::Action, act(Action::Inc), "2.2.4.1"),
    row("IO", NO, Shape::Register(RW), reg(Register::Io), "2.1.3.3.1"),
    row("IO", idx(1, 32), Shape::Register(RW), reg(Register::Io), "2.1.3.3.1"),
    row("ISTART", NO, Shape::Action, act(Action::BufferStart), "2.3.4"),
    row("JOG", AX, Shape::Jog, Ascii::Motion(AsciiKind::Jog), "2.2.2"),
    row("JOYDEL", AX, Shape::Register(RW), reg(Register::Jdel), "2.5.1.2"),
    row("JOYENA", NO, Shape::Register(RW), reg(Register::Jena), "2.5.1"),
    row("JOYHS", AX, Shape::Register(RW), reg(Register::Jspd), "2.5.1.2"),
    row("LSPD", NO, Shape::Register(RW), reg(Register::Lspd), "2.1.4"),
    row("LSPD", AX, Shape::Register(RW), reg(Register::Lspd), "2.1.4"),
    row("LT", AX, Shape::Register(W), reg(Register::Lt), "2.1.3.2.1"),
    row("LTE", AX, Shape::Register(R), reg(Register::Lte), "2.1.3.2.1"),
    row("LTP", AX, Shape::Register(R), reg(Register::Ltp), "2.1.3.2.1"),
    row("LTS", AX, Shape::Register(R), reg(Register::Lts), "2.1.3.2.1"),
    row("MPGE", AX, Shape::Register(RW), reg(Register::Mpe), "2.1.3.1.4"),
    row("MST", AX, Shape::Register(R), reg(Register::Mst), "2.6.2.1"),
    row("P", AX, Shape::Register(RW), reg(Register::P), "2.6.1.1"),
    row("PS", AX, Shape::Register(R), reg(Register::Ps), "2.6.2.2"),
    row("PWM", idx(1, 2), Shape::Register(RW), reg(Register::Pwm), "2.1.3.3.3"),
    row("SL", AX, Shape::Register(RW), reg(Register::Sl), "2.5.3"),
    row("SLS", AX, Shape::Register(R), reg(Register::Sls), "2.5.3"),
    row("SR", idx(0, 3), Shape::Register(W), reg(Register::Sactrl), "2.7.8"),
    row("SSPD", AX, Shape::Register(W), reg(Register::Sspd), "2.4.1"),
    row("SSPDM", AX, Shape::Register(W), reg(Register::Sspdm), "2.4.1"),
    row("STOP", NO, Shape::Action, act(Action::Stop), "2.2.3"),
    row("STOP", AX, Shape::Action, act(Action::Stop), "2.2.3"),
    row("STORE", NO, Shape::Action, act(Action::Store), "2.1.7"),
    row("SYNCFG", AX, Shape::Register(RW), reg(Register::Sync), "2.1.3.2.2"),
    row("SYNOFF", AX, Shape::Action, act(Action::SyncOff), "2.1.3.2.2"),
    row("SYNON", AX, Shape::Action, act(Action::SyncOn), "2.1.3.2.2"),
    row("SYNPOS", AX, Shape::Register(RW), reg(Register::Synp), "2.1.3.2.2"),
    row("SYNSTAT", AX, Shape::Register(R), reg(Register::Syns), "2.1.3.2.2"),
    row("V", idx(0, 99), Shape::Variable, reg(Register::V), "2.7.6"),
    row("WAIT", AX, Shape::Wait, Ascii::None, "5.2"),
    row("ZMOVE", AX, Shape::ZMove, Ascii::Motion(AsciiKind::ZMove), "2.2.5.1"),
];

/// Every form of the command called `name`.
pub fn forms(name: &str) -> impl Iterator<Item = &'static CommandInfo> + '_ {
    COMMANDS.iter().filter(move |c| c.name == name)
}

/// Whether `name` is a standalone command (in some form).
pub fn is_command(name: &str) -> bool {
    forms(name).next().is_some()
}

/// The form of `name` of this shape (bare, axis or any index).
pub fn form(name: &str, shape: FormShape) -> Option<&'static CommandInfo> {
    forms(name).find(|c| shape.fits(c.form))
}

/// An ASCII command that standalone programs do not have (blank or "_" in
/// the Standalone row of §2's tables), and what to write instead.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AsciiOnly {
    /// The ASCII keyword.
    pub keyword: &'static str,
    /// The standalone command of the same meaning, if there is one.
    pub instead: Option<String>,
}

/// The ASCII-only command a word of source names (`CLRX`, `BO`, `POLU`),
/// if it is one: an ASCII keyword (with its axis letter, if it takes one)
/// that is not a standalone name.
pub fn ascii_only_command(word: &str) -> Option<AsciiOnly> {
    if is_command(word) || !word.chars().all(|c| c.is_ascii_uppercase()) {
        return None;
    }
    let row = rows_of(word).next().or_else(|| {
        let (name, last) = split_last_letter(word)?;
        Axis::from_letter(last)?;
        // `CLRX`, or `JX`, `HX`, `TX`: motion commands written with an axis.
        rows_of(name).find(|r| matches!(r.form, Form::Axis | Form::Motion))
    })?;
    if is_command(row.keyword) {
        // `ABSX`: a standalone name in a form it does not have.
        return None;
    }
    let instead = match row.kind {
        AsciiKind::Action(Action::CallSub) => Some("GOSUB n".to_string()),
        AsciiKind::BufferMove => Some("BUFON, then X[pos]Y[pos]Z[pos] moves".to_string()),
        kind => COMMANDS
            .iter()
            .find(|c| c.ascii.is(kind))
            .map(CommandInfo::syntax),
    };
    Some(AsciiOnly {
        keyword: row.keyword,
        instead,
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
    fn each_name_has_at_most_one_form_per_shape() {
        for c in COMMANDS {
            for shape in [FormShape::Bare, FormShape::Axis, FormShape::Index] {
                let n = forms(c.name).filter(|f| shape.fits(f.form)).count();
                assert!(n <= 1, "{} has {n} {shape:?} forms", c.name);
            }
        }
    }

    #[test]
    fn every_standalone_form_has_its_ascii_row_but_wait_and_delay() {
        for c in COMMANDS {
            match c.ascii {
                Ascii::None => assert!(matches!(c.shape, Shape::Wait | Shape::Delay), "{}", c.name),
                _ => {
                    let row = c.ascii_row();
                    assert!(row.is_some(), "{} has no ASCII row", c.syntax());
                    if let (Some(row), Form::Index { first, last }) = (row, c.form) {
                        assert_eq!(row.form, Form::Index { first, last }, "{}", c.name);
                    }
                }
            }
            if c.writable() || c.shape == Shape::Delay {
                assert!(c.values().is_some(), "{} has no value range", c.name);
            }
            assert!(!c.meaning().is_empty(), "{}", c.name);
        }
    }

    #[test]
    fn values_and_meanings_are_the_ascii_tables() {
        let hspd = form("HSPD", FormShape::Axis).and_then(CommandInfo::values);
        assert_eq!(hspd.map(|v| (v.min, v.max)), Some((0, 6_553_500)));
        assert_eq!(
            hspd.map(|v| v.to_string()).as_deref(),
            Some("0..6553500 pps")
        );
        let sr = form("SR", FormShape::Index).and_then(CommandInfo::values);
        assert_eq!(sr.map(|v| (v.min, v.max)), Some((0, 3)));
        assert!(
            form("MST", FormShape::Axis)
                .map(CommandInfo::meaning)
                .is_some_and(|m| m.contains("status"))
        );
    }

    #[test]
    fn syntax_is_written_as_the_manual_does() {
        let syntax = |name, shape| form(name, shape).map(CommandInfo::syntax);
        assert_eq!(
            syntax("HSPD", FormShape::Axis).as_deref(),
            Some("HSPD[axis][=value]")
        );
        assert_eq!(syntax("DI", FormShape::Index).as_deref(), Some("DI[1-4]"));
        assert_eq!(
            syntax("HOME", FormShape::Axis).as_deref(),
            Some("HOME[axis][+/-][mode]")
        );
        assert_eq!(
            syntax("SR", FormShape::Index).as_deref(),
            Some("SR[0-3]=value")
        );
        assert_eq!(syntax("CIR", FormShape::Bare).as_deref(), None);
    }

    #[test]
    fn ascii_only_words_name_the_standalone_command_to_use() {
        let instead = |word| ascii_only_command(word).map(|a| a.instead);
        assert_eq!(instead("CLRX"), Some(Some("ECLEAR[axis]".into())));
        assert_eq!(instead("BO"), Some(Some("BUFON".into())));
        assert_eq!(instead("SACTRL"), Some(Some("SR[0-3]=value".into())));
        assert_eq!(instead("JX"), Some(Some("JOG[axis][+/-]".into())));
        assert_eq!(instead("GS"), Some(Some("GOSUB n".into())));
        assert_eq!(instead("POLU"), Some(None));
        assert_eq!(instead("ESTOP"), Some(None));
        assert_eq!(ascii_only_command("POLU").map(|a| a.keyword), Some("POL"));
        // Not ASCII-only: standalone names, and names in forms neither set has.
        assert_eq!(ascii_only_command("HSPD"), None);
        assert_eq!(ascii_only_command("ABSX"), None);
        assert_eq!(ascii_only_command("MMX"), None);
        assert_eq!(ascii_only_command("FOO"), None);
    }
}
