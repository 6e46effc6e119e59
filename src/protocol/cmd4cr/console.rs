//! The CMD-4CR as the session layer sees it ([`FamilyConsole`]): command
//! text framed for a controller ID, which commands only read, what each
//! answer carries, the emergency stop, and the queries that make up the
//! status of the four axes.

use std::sync::{Arc, LazyLock};

use super::catalog::{Action, Axis, Format, Register};
use super::command::{Cmd4crCommand, Selector, parse_command};
use super::reply::{Answer, AnswerError, MST_BITS, Mst, MstBit, MstClass, answers, parse_answer};
use super::{ControllerId, DEFAULT_ID, MAX_ID, frame};
use crate::protocol::console::{
    Answering, AxisFlag, AxisInfo, AxisUpdate, Completions, Effect, FamilyConsole, MotionPhase,
    MoveMode, PreparedLine, Reading, ReplyError, ReplyValue, StatusPoll, SwitchKind,
};
use crate::protocol::parameters::ParameterSet;
use crate::protocol::wire::{Frame, ReplyRule, Verdict, WireFormat};

/// The four axes (§1.2), numbered 0–3 in the order of the PP/EP fields.
pub const AXES: &[AxisInfo] = &[
    AxisInfo {
        number: 0,
        name: "X",
    },
    AxisInfo {
        number: 1,
        name: "Y",
    },
    AxisInfo {
        number: 2,
        name: "Z",
    },
    AxisInfo {
        number: 3,
        name: "U",
    },
];

/// The standalone programs PRG0–PRG3 (§2.7.3).
pub const PROGRAMS: u8 = 4;

/// One MST bit as an axis flag, for the status line.
fn mst_flag(bit: &'static MstBit) -> AxisFlag {
    AxisFlag {
        name: bit.name,
        description: bit.description,
    }
}

/// How an answer to a CMD-4CR command is recognised: the next line that
/// is its success answer (`OK` for a write or action, the register's
/// format for a read) or an error (`?…`, which may answer anything). Any
/// other line is not this command's answer: a late `OK` of an earlier
/// write while a read waits, a garbled `fK`, noise. If nothing better
/// comes, the device task reports those bytes as a garbled answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cmd4crReplyRule {
    /// The register's format for a read; `None` for writes and actions,
    /// answered by [`super::reply::DONE`].
    pub format: Option<Format>,
}

impl ReplyRule for Cmd4crReplyRule {
    fn examine(&self, accepted: &[Frame], frame: &[u8]) -> Verdict {
        if !accepted.is_empty() {
            return Verdict::NotMine;
        }
        if answers(&String::from_utf8_lossy(frame), self.format) {
            Verdict::Complete
        } else {
            Verdict::NotMine
        }
    }
}

/// The CMD-4CR for the session layer.
#[derive(Debug, Clone, Copy, Default)]
pub struct Cmd4crConsole;

impl Cmd4crConsole {
    /// A typed command, ready for the controller at `id`.
    pub fn prepare_command(&self, command: &Cmd4crCommand, id: u8) -> PreparedLine {
        let canonical = command.to_string();
        PreparedLine {
            bytes: frame(id, &canonical),
            canonical,
            address: id,
            answering: Answering::Reply(Arc::new(Cmd4crReplyRule {
                format: command.reply_format(),
            })),
            effect: if command.is_query() {
                Effect::Reads
            } else {
                Effect::Acts
            },
        }
    }

    fn read(&self, register: Register, selector: Selector, id: u8) -> PreparedLine {
        self.prepare_command(&Cmd4crCommand::Read { register, selector }, id)
    }
}

fn malformed(line: &PreparedLine, reason: impl Into<String>) -> ReplyError {
    ReplyError::Malformed {
        line: line.canonical.clone(),
        reason: reason.into(),
    }
}

fn axis_of(selector: Selector) -> Option<usize> {
    match selector {
        Selector::Axis(axis) => Some(axis.index()),
        _ => None,
    }
}

/// The MST bits with a switch lamp of their own (the end limits, home).
const SWITCH_BITS: [u8; 3] = [4, 5, 6];

/// Whether an MST bit is one of the axis's lamps: the inputs and outputs
/// other than the switches, and the waits.
fn is_lamp(bit: &MstBit) -> bool {
    match bit.class {
        MstClass::Signal => !SWITCH_BITS.contains(&bit.bit),
        MstClass::Waiting => true,
        MstClass::Motion | MstClass::Error => false,
    }
}

/// Every lamp an axis has, in MST bit order.
static LAMPS: LazyLock<Vec<AxisFlag>> = LazyLock::new(|| {
    MST_BITS
        .iter()
        .filter(|b| is_lamp(b))
        .map(mst_flag)
        .collect()
});

/// Bits 0–2 as the phase of the motion (Table 2-28); none set: waiting
/// while bit 18 or 19 says the move waits for INP or /CSTA (its target
/// not yet reached, or the move not yet started), else standing.
fn phase(mst: Mst) -> MotionPhase {
    if mst.is_set(0) {
        MotionPhase::Accelerating
    } else if mst.is_set(1) {
        MotionPhase::Decelerating
    } else if mst.is_set(2) {
        MotionPhase::Constant
    } else if mst.is_set(18) || mst.is_set(19) {
        MotionPhase::Waiting
    } else {
        MotionPhase::Standing
    }
}

/// The MST word as updates of its axis: switches, motion phase, latched
/// errors, and the other inputs and waits as lamps. Not whether the axis
/// reached its target: MST says the motion is complete after a STOP, an
/// ESTOP or a limit as after the target (§2.2.4: the move ends early
/// then), and the CMD-4CR has no target register; the target comes from
/// the move line sent ([`move_updates`]).
fn mst_updates(axis: usize, value: i64) -> Vec<(usize, AxisUpdate)> {
    let mst = Mst::from_value(value);
    let flags = |class: MstClass| -> Vec<AxisFlag> {
        MST_BITS
            .iter()
            .filter(|b| b.class == class && mst.is_set(b.bit))
            .map(mst_flag)
            .collect()
    };
    let lamps: Vec<AxisFlag> = MST_BITS
        .iter()
        .filter(|b| is_lamp(b) && mst.is_set(b.bit))
        .map(mst_flag)
        .collect();
    vec![
        (
            axis,
            AxisUpdate::Switch(SwitchKind::Right, mst.plus_limit()),
        ),
        (
            axis,
            AxisUpdate::Switch(SwitchKind::Left, mst.minus_limit()),
        ),
        (axis, AxisUpdate::Switch(SwitchKind::Home, mst.home())),
        (axis, AxisUpdate::Phase(phase(mst))),
        (axis, AxisUpdate::Errors(flags(MstClass::Error))),
        (axis, AxisUpdate::DriverFlags(lamps)),
    ]
}

/// The move mode the `MM` reading `value` names (Table 2-22).
fn move_mode(value: i64) -> Option<MoveMode> {
    match value {
        0 => Some(MoveMode::Absolute),
        1 => Some(MoveMode::Incremental),
        _ => None,
    }
}

/// The mode for all four axes: `ABS`/`INC` and `MM` are global (§2.2.4.1).
fn mode_updates(mode: Option<MoveMode>) -> Vec<(usize, AxisUpdate)> {
    (0..AXES.len())
        .map(|axis| (axis, AxisUpdate::MoveMode(mode)))
        .collect()
}

fn target_unknown(axes: impl IntoIterator<Item = Axis>) -> Vec<(usize, AxisUpdate)> {
    axes.into_iter()
        .map(|axis| (axis.index(), AxisUpdate::TargetUnknown))
        .collect()
}

/// What a motion line accepted says of its axes' targets. The CMD-4CR has
/// no target register: `X50000` is the only word of where the axis goes,
/// its operand absolute or a step as the move mode is (§2.2.4.1). Every
/// other motion leaves no target the console can tell: a jog or a Z-move
/// has none, a homing ends where its trigger was, a target changed in
/// flight is a step from the move's start in INC (§2.4.2), a circle or an
/// arc ends where the geometry says (§2.3.2, §2.3.3), a buffered move runs
/// later (§2.3.4).
fn move_updates(command: &Cmd4crCommand) -> Vec<(usize, AxisUpdate)> {
    match *command {
        Cmd4crCommand::Move { targets } => targets
            .iter()
            .enumerate()
            .filter_map(|(axis, target)| target.map(|t| (axis, AxisUpdate::MoveTarget(t))))
            .collect(),
        Cmd4crCommand::Jog { axis, .. }
        | Cmd4crCommand::Home { axis, .. }
        | Cmd4crCommand::ZMove { axis, .. }
        | Cmd4crCommand::NewTarget { axis, .. } => target_unknown([axis]),
        Cmd4crCommand::Circle { axes, .. } | Cmd4crCommand::Arc { axes, .. } => {
            target_unknown(axes)
        }
        Cmd4crCommand::HelicalCircle { .. }
        | Cmd4crCommand::HelicalArc { .. }
        | Cmd4crCommand::BufferMove { .. } => target_unknown([Axis::X, Axis::Y, Axis::Z]),
        _ => Vec::new(),
    }
}

/// The console line of `action` on the axis numbered `axis` (`STOPZ`).
fn axis_action(action: Action, axis: u8) -> Option<String> {
    let axis = Axis::from_index(usize::from(axis))?;
    Some(
        Cmd4crCommand::Action {
            action,
            selector: Selector::Axis(axis),
        }
        .to_string(),
    )
}

/// An axis's own high speed, or (no axis) the global one for all four
/// (§2.1.4).
fn max_speed_updates(axis: Option<usize>, speed: i64) -> Vec<(usize, AxisUpdate)> {
    match axis {
        Some(axis) => vec![(axis, AxisUpdate::MaxSpeed(speed))],
        None => (0..AXES.len())
            .map(|axis| (axis, AxisUpdate::GlobalMaxSpeed(speed)))
            .collect(),
    }
}

/// The value of one `:`-separated field per axis (PP, EP).
fn per_axis(text: &str) -> Option<Vec<i64>> {
    match parse_answer(text, Some(Format::Fields(&["X", "Y", "Z", "U"]))) {
        Ok(Answer::Fields(values, _)) => Some(values),
        _ => None,
    }
}

impl FamilyConsole for Cmd4crConsole {
    fn wire(&self) -> Arc<dyn WireFormat> {
        Arc::new(super::Cmd4crWire::default())
    }

    fn default_address(&self) -> u8 {
        DEFAULT_ID
    }

    /// IDs 00–99 (§2.1.1.1); a frame carries two digits.
    fn addresses(&self) -> std::ops::RangeInclusive<u8> {
        0..=MAX_ID
    }

    fn axes(&self) -> &'static [AxisInfo] {
        AXES
    }

    fn prepare(
        &self,
        line: &str,
        address: u8,
    ) -> Result<PreparedLine, crate::protocol::line_error::LineError> {
        if address > MAX_ID {
            return Err(super::command::IdOutOfRange(address).into());
        }
        let command = parse_command(line)?;
        Ok(self.prepare_command(&command, address))
    }

    fn interpret(&self, line: &PreparedLine, frames: &[Frame]) -> Result<Reading, ReplyError> {
        let Some(last) = frames.last() else {
            return Err(malformed(line, "no reply"));
        };
        let text = String::from_utf8_lossy(last);
        let command = parse_command(&line.canonical).map_err(|e| malformed(line, e.to_string()))?;
        let value = match parse_answer(&text, command.reply_format()) {
            Ok(Answer::Done(_)) => ReplyValue::None,
            Ok(Answer::Integer(value)) => ReplyValue::Number(value),
            Ok(Answer::Thousandths(_, text) | Answer::Fields(_, text) | Answer::Text(text)) => {
                ReplyValue::Text(text)
            }
            Err(AnswerError::Refused(error)) => {
                return Err(ReplyError::Refused {
                    module: ControllerId(line.address).to_string(),
                    line: line.canonical.clone(),
                    reply: error.line(),
                    meaning: error.meaning().to_string(),
                });
            }
            Err(AnswerError::Unreadable { expected, .. }) => {
                // The bytes as they came, escaped: a garbled answer may
                // hold anything, a terminal's control sequences included.
                return Err(malformed(
                    line,
                    format!(
                        "`{}` is not {expected}",
                        super::show_bytes(last.trim_ascii())
                    ),
                ));
            }
        };
        Ok(Reading {
            status: None,
            value,
        })
    }

    fn emergency_stop(&self, address: u8) -> Vec<PreparedLine> {
        // ESTOP stops every axis at once, as the /CEMG input does
        // (§2.1.3.1.2), whatever moves it (a jog, a buffer, the joystick,
        // which STOP does not stop, §2.5.1.3). Then the four standalone
        // programs, which could start motion again (§2.7.3: they run beside
        // the ASCII commands) — an error handler (SUB 31) may answer the
        // stop with a move (§5.4.7: ECLEARX, X0). Then ESTOP again for
        // whatever started in between.
        let estop = self.prepare_command(
            &Cmd4crCommand::Action {
                action: Action::Estop,
                selector: Selector::All,
            },
            address,
        );
        let mut lines = vec![estop.clone()];
        lines.extend((0..PROGRAMS).map(|program| {
            self.prepare_command(
                &Cmd4crCommand::Write {
                    register: Register::Sactrl,
                    selector: Selector::Index(program),
                    value: 0,
                },
                address,
            )
        }));
        lines.push(estop);
        lines
    }

    fn identify(&self, address: u8) -> PreparedLine {
        // §2.1.1.1: "The current version of firmware can be found with the
        // VER command"; its format is not given, so it is shown as it
        // comes.
        self.read(Register::Ver, Selector::All, address)
    }

    fn status_queries(&self, address: u8) -> Vec<StatusPoll> {
        // No command reads MST or PS of all axes at once; PP reads all four
        // positions in one line (§2.6.1.1). HSPD is the speed gauge's
        // scale: an axis's own unless 0, else the global one (§2.1.4).
        let poll = |axis: usize, line: PreparedLine, fast: bool| StatusPoll { axis, line, fast };
        // First the move mode, which says what the target of a move line
        // sent is (§2.2.4.1): its power-on state is not in the manual and a
        // standalone program may change it (ABS/INC are program commands
        // too), so it is read, not assumed — first, so that a move typed
        // just after connecting finds it known. Slow: the ABS/INC lines
        // the console sends set it at once.
        let mut polls = vec![
            poll(0, self.read(Register::Mm, Selector::All, address), false),
            poll(0, self.read(Register::Pp, Selector::All, address), true),
        ];
        for register in [Register::Mst, Register::Ps] {
            polls.extend(Axis::ALL.into_iter().map(|axis| {
                poll(
                    axis.index(),
                    self.read(register, Selector::Axis(axis), address),
                    true,
                )
            }));
        }
        polls.push(poll(
            0,
            self.read(Register::Hspd, Selector::All, address),
            false,
        ));
        polls.extend(Axis::ALL.into_iter().map(|axis| {
            poll(
                axis.index(),
                self.read(Register::Hspd, Selector::Axis(axis), address),
                false,
            )
        }));
        polls
    }

    fn status_update(&self, line: &PreparedLine, reading: &Reading) -> Vec<(usize, AxisUpdate)> {
        let (register, selector) = match parse_command(&line.canonical) {
            Ok(Cmd4crCommand::Read { register, selector }) => (register, selector),
            // A high speed the user set is the speed gauge's new scale at
            // once: the slow poll of HSPD only has to catch what a
            // standalone program sets (any answer but `?…` is success).
            Ok(Cmd4crCommand::Write {
                register: Register::Hspd,
                selector,
                value,
            }) => return max_speed_updates(axis_of(selector), value),
            // A position counter written: the axis stands elsewhere than
            // any target it had, in other coordinates.
            Ok(Cmd4crCommand::Write {
                register: Register::P,
                selector,
                ..
            }) => {
                return match axis_of(selector) {
                    Some(axis) => vec![(axis, AxisUpdate::TargetUnknown)],
                    None => target_unknown(Axis::ALL),
                };
            }
            Ok(Cmd4crCommand::Action {
                action: Action::Abs,
                ..
            }) => return mode_updates(Some(MoveMode::Absolute)),
            Ok(Cmd4crCommand::Action {
                action: Action::Inc,
                ..
            }) => return mode_updates(Some(MoveMode::Incremental)),
            Ok(command) => return move_updates(&command),
            Err(_) => return Vec::new(),
        };
        let number = reading.value.number();
        let axis = axis_of(selector);
        match (register, axis, number) {
            (Register::Pp, None, _) => {
                let ReplyValue::Text(text) = &reading.value else {
                    return Vec::new();
                };
                per_axis(text)
                    .unwrap_or_default()
                    .into_iter()
                    .enumerate()
                    .map(|(axis, position)| (axis, AxisUpdate::Position(position)))
                    .collect()
            }
            (Register::P, Some(axis), Some(position)) => {
                vec![(axis, AxisUpdate::Position(position))]
            }
            (Register::Ps, Some(axis), Some(speed)) => vec![(axis, AxisUpdate::Speed(speed))],
            (Register::Mst, Some(axis), Some(word)) => mst_updates(axis, word),
            (Register::Hspd, axis, Some(speed)) => max_speed_updates(axis, speed),
            (Register::Mm, None, Some(mode)) => mode_updates(move_mode(mode)),
            _ => Vec::new(),
        }
    }

    fn complete(&self, line: &str, cursor: usize) -> Completions {
        super::assist::complete(line, cursor)
    }

    fn help(&self, line: &str, cursor: usize) -> Vec<String> {
        super::assist::help(line, cursor)
    }

    fn stop_axis_line(&self, axis: u8) -> Option<String> {
        axis_action(Action::Stop, axis)
    }

    /// `CLR[axis]`: the limit, alarm, EMG and slowdown-stop error bits of
    /// MST stay set until it (§2.6.2.3, Table 2-28 footnotes 6 and 7);
    /// there is no all-axes form.
    fn clear_errors_line(&self, axis: u8) -> Option<String> {
        axis_action(Action::Clr, axis)
    }

    fn lamps(&self) -> &'static [AxisFlag] {
        &LAMPS
    }

    fn units(&self) -> Option<&'static dyn crate::protocol::units::UnitLaw> {
        Some(&super::units::Cmd4crUnits)
    }

    fn parameters(&self) -> Option<&'static dyn ParameterSet> {
        Some(&super::parameter_set::Cmd4crParameters)
    }

    fn jog(&self) -> Option<&'static dyn crate::protocol::jog::JogPlan> {
        Some(&super::jog::Cmd4crJog)
    }

    fn io(&self) -> Option<&'static dyn crate::protocol::io::IoPlan> {
        Some(&super::io::Cmd4crIo)
    }

    fn program(&self) -> Option<&'static dyn crate::protocol::program::ProgramTool> {
        Some(&super::tool::AScriptTool)
    }

    fn describe_request(&self, bytes: &[u8]) -> Option<String> {
        Some(super::traffic::describe_request(bytes))
    }

    fn describe_reply(&self, bytes: &[u8], request: Option<&[u8]>) -> Option<String> {
        Some(super::traffic::describe_reply(bytes, request))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prepare(line: &str) -> PreparedLine {
        Cmd4crConsole.prepare(line, 1).expect("valid line")
    }

    fn reply(line: &PreparedLine, text: &str) -> Result<Reading, ReplyError> {
        Cmd4crConsole.interpret(line, &[text.as_bytes().to_vec()])
    }

    /// What the answer `text` to `line` says about the axes.
    fn updates_of(line: &str, text: &str) -> Vec<(usize, AxisUpdate)> {
        let line = prepare(line);
        let reading = reply(&line, text).expect("a reading");
        Cmd4crConsole.status_update(&line, &reading)
    }

    fn canonicals(lines: &[PreparedLine]) -> Vec<String> {
        lines.iter().map(|l| l.canonical.clone()).collect()
    }

    #[test]
    fn a_line_becomes_a_frame_for_the_controller_id() {
        let line = Cmd4crConsole.prepare("hspdx = 5000", 7).expect("valid");
        assert_eq!(line.canonical, "HSPDX=5000");
        assert_eq!(line.bytes, b"@07HSPDX=5000\r".to_vec());
        assert_eq!(line.address, 7);
        let error = Cmd4crConsole.prepare("PX", 100).unwrap_err().to_string();
        assert!(error.contains("00..99"), "{error}");
        let error = Cmd4crConsole.prepare("EO=16", 1).unwrap_err().to_string();
        assert!(error.contains("0..15"), "{error}");
    }

    #[test]
    fn only_pure_queries_read() {
        for line in [
            "PX", "PP", "MSTU", "DI", "DI3", "VER", "SLRX", "BSTAT", "V5",
        ] {
            assert_eq!(prepare(line).effect, Effect::Reads, "{line}");
        }
        for line in [
            "PX=0",
            "X1000",
            "JX+",
            "STOP",
            "STORE",
            "SACTRL0=1",
            "GS3",
            "CLRX",
            "HX+0",
            "BO",
        ] {
            assert_eq!(prepare(line).effect, Effect::Acts, "{line}");
        }
    }

    #[test]
    fn replies_carry_their_values() {
        assert_eq!(
            reply(&prepare("POLX"), "7").map(|r| r.value),
            Ok(ReplyValue::Number(7))
        );
        assert_eq!(
            reply(&prepare("STORE"), "OK").map(|r| r.value),
            Ok(ReplyValue::None)
        );
        assert_eq!(
            reply(&prepare("PP"), "1:-2:3:4").map(|r| r.value),
            Ok(ReplyValue::Text("1:-2:3:4".into()))
        );
        assert_eq!(
            reply(&prepare("SLRX"), "1.5").map(|r| r.value),
            Ok(ReplyValue::Text("1.5".into()))
        );
        assert_eq!(
            reply(&prepare("VER"), "V126BL").map(|r| r.value),
            Ok(ReplyValue::Text("V126BL".into()))
        );
        // A write answered other than OK: never success.
        let error = reply(&prepare("HSPDX=5000"), "fK").unwrap_err();
        assert_eq!(
            error.to_string(),
            "unreadable answer to HSPDX=5000: `fK` is not OK, the answer to a write or action"
        );
    }

    #[test]
    fn error_replies_are_refusals_with_the_manuals_meaning() {
        let error = reply(&prepare("X1000"), "?Error Moving").unwrap_err();
        assert_eq!(
            error.to_string(),
            "controller 01 refused X1000: ?Error Moving (the move command could not be \
             processed: one or more of the required axes may be in error state or in motion)"
        );
        assert_eq!(error.status(), None);
        let error = reply(&prepare("PX"), "?Unknown Command: PX").unwrap_err();
        assert!(matches!(error, ReplyError::Refused { .. }), "{error}");
        let error = reply(&prepare("PX"), "OK").unwrap_err();
        assert!(matches!(error, ReplyError::Malformed { .. }), "{error}");
        let none = Cmd4crConsole.interpret(&prepare("PX"), &[]).unwrap_err();
        assert!(none.to_string().contains("no reply"));
    }

    #[test]
    fn a_read_waits_for_a_line_that_can_answer_it() {
        let Answering::Reply(rule) = prepare("PX").answering else {
            panic!("PX expects a reply")
        };
        assert_eq!(rule.examine(&[], b"OK"), Verdict::NotMine, "stale OK");
        assert_eq!(rule.examine(&[], b"-12"), Verdict::Complete);
        assert_eq!(rule.examine(&[], b"?Error Moving"), Verdict::Complete);
        assert_eq!(rule.examine(&[b"1".to_vec()], b"2"), Verdict::NotMine);
        let Answering::Reply(rule) = prepare("PP").answering else {
            panic!("PP expects a reply")
        };
        assert_eq!(rule.examine(&[], b"7"), Verdict::NotMine);
        assert_eq!(rule.examine(&[], b"7:0:0:0"), Verdict::Complete);
        let Answering::Reply(rule) = prepare("X100").answering else {
            panic!("X100 expects a reply")
        };
        assert_eq!(rule.examine(&[], b"OK"), Verdict::Complete);
        assert_eq!(rule.examine(&[], b"?Error Moving"), Verdict::Complete);
        for garbled in [&b"fK"[..], b"K", b"O\xAA", b"12", b"0:0:0:0"] {
            assert_eq!(rule.examine(&[], garbled), Verdict::NotMine, "{garbled:?}");
        }
    }

    #[test]
    fn emergency_stop_stops_all_motion_then_the_programs() {
        assert_eq!(
            canonicals(&Cmd4crConsole.emergency_stop(1)),
            [
                "ESTOP",
                "SACTRL0=0",
                "SACTRL1=0",
                "SACTRL2=0",
                "SACTRL3=0",
                "ESTOP"
            ]
        );
        assert_eq!(
            Cmd4crConsole.emergency_stop(3)[0].bytes,
            b"@03ESTOP\r".to_vec()
        );
    }

    #[test]
    fn identity_is_the_firmware_version() {
        let line = Cmd4crConsole.identify(1);
        assert_eq!(line.bytes, b"@01VER\r".to_vec());
        assert_eq!(line.effect, Effect::Reads);
    }

    #[test]
    fn status_reads_positions_of_all_axes_in_one_line() {
        let polls = Cmd4crConsole.status_queries(1);
        let names: Vec<&str> = polls.iter().map(|p| p.line.canonical.as_str()).collect();
        assert_eq!(
            names,
            [
                "MM", "PP", "MSTX", "MSTY", "MSTZ", "MSTU", "PSX", "PSY", "PSZ", "PSU", "HSPD",
                "HSPDX", "HSPDY", "HSPDZ", "HSPDU"
            ]
        );
        assert!(polls.iter().all(|p| p.line.effect == Effect::Reads));
        assert_eq!(polls.iter().filter(|p| p.fast).count(), 9);
        let pp = &polls[1].line;
        let reading = reply(pp, "100:-200:0:5").expect("read");
        assert_eq!(
            Cmd4crConsole.status_update(pp, &reading),
            [
                (0, AxisUpdate::Position(100)),
                (1, AxisUpdate::Position(-200)),
                (2, AxisUpdate::Position(0)),
                (3, AxisUpdate::Position(5)),
            ]
        );
    }

    #[test]
    fn mst_becomes_switches_completion_errors_and_lamps() {
        let line = prepare("MSTY");
        // Decelerating, + limit on, + limit error latched, INP on.
        let reading = reply(&line, &(2 | 16 | 256 | 2048).to_string()).expect("read");
        let updates = Cmd4crConsole.status_update(&line, &reading);
        assert!(updates.iter().all(|(axis, _)| *axis == 1));
        let updates: Vec<AxisUpdate> = updates.into_iter().map(|(_, u)| u).collect();
        assert!(updates.contains(&AxisUpdate::Switch(SwitchKind::Right, true)));
        assert!(updates.contains(&AxisUpdate::Switch(SwitchKind::Left, false)));
        assert!(updates.contains(&AxisUpdate::Switch(SwitchKind::Home, false)));
        assert!(updates.contains(&AxisUpdate::Phase(MotionPhase::Decelerating)));
        let names = |wanted: fn(&AxisUpdate) -> Option<&Vec<AxisFlag>>| -> Vec<&str> {
            updates
                .iter()
                .find_map(wanted)
                .map(|flags| flags.iter().map(|f| f.name).collect())
                .unwrap_or_default()
        };
        assert_eq!(
            names(|u| match u {
                AxisUpdate::Errors(f) => Some(f),
                _ => None,
            }),
            ["+limit error"]
        );
        assert_eq!(
            names(|u| match u {
                AxisUpdate::DriverFlags(f) => Some(f),
                _ => None,
            }),
            ["INP"]
        );
        let idle = updates_of("MSTY", "0");
        assert!(idle.contains(&(1, AxisUpdate::Phase(MotionPhase::Standing))));
        // Motion complete is no target reached: a STOP, an ESTOP or a
        // limit completes a move as well (§2.2.4).
        assert!(
            !idle
                .iter()
                .any(|(_, u)| matches!(u, AxisUpdate::Reached(_))),
            "{idle:?}"
        );
        for (word, phase) in [
            (1, MotionPhase::Accelerating),
            (4, MotionPhase::Constant),
            (4 | 64, MotionPhase::Constant),
            // Pulses done, waiting for INP: not yet at the target.
            (1 << 18, MotionPhase::Waiting),
            (1 << 19, MotionPhase::Waiting),
            (2 | (1 << 18), MotionPhase::Decelerating),
        ] {
            let found = updates_of("MSTY", &word.to_string());
            assert!(found.contains(&(1, AxisUpdate::Phase(phase))), "{word}");
        }
    }

    #[test]
    fn the_lamps_are_the_inputs_and_waits_without_switch_lamps_of_their_own() {
        let names: Vec<&str> = Cmd4crConsole.lamps().iter().map(|f| f.name).collect();
        assert_eq!(
            names,
            [
                "ALM",
                "SD",
                "INP",
                "ERC",
                "EZ",
                "EXT",
                "EMG",
                "wait INP",
                "wait CSTA"
            ]
        );
        // A lit lamp is named by the driver flags of the same reading.
        let lit: Vec<&str> = updates_of("MSTX", &(8 | 64 | (1 << 18)).to_string())
            .into_iter()
            .find_map(|(_, u)| match u {
                AxisUpdate::DriverFlags(flags) => Some(flags),
                _ => None,
            })
            .unwrap_or_default()
            .iter()
            .map(|f| f.name)
            .collect();
        assert_eq!(lit, ["ALM", "wait INP"]);
    }

    #[test]
    fn speeds_and_their_scale() {
        let ps = prepare("PSZ");
        let reading = reply(&ps, "4000").expect("read");
        assert_eq!(
            Cmd4crConsole.status_update(&ps, &reading),
            [(2, AxisUpdate::Speed(4000))]
        );
        let own = prepare("HSPDU");
        let reading = reply(&own, "0").expect("read");
        assert_eq!(
            Cmd4crConsole.status_update(&own, &reading),
            [(3, AxisUpdate::MaxSpeed(0))]
        );
        let global = prepare("HSPD");
        let reading = reply(&global, "5000").expect("read");
        assert_eq!(Cmd4crConsole.status_update(&global, &reading).len(), 4);
        // A user's own read of a position counts too; a position written
        // says only that any target is unknown now (not a position: the
        // next poll reads it).
        let px = prepare("PX");
        let reading = reply(&px, "12").expect("read");
        assert_eq!(
            Cmd4crConsole.status_update(&px, &reading),
            [(0, AxisUpdate::Position(12))]
        );
        assert_eq!(updates_of("PX=0", "OK"), [(0, AxisUpdate::TargetUnknown)]);
        assert!(updates_of("LSPDX=100", "OK").is_empty());
        // A high speed written is the gauge's scale at once.
        assert_eq!(
            updates_of("HSPDY=800", "OK"),
            [(1, AxisUpdate::MaxSpeed(800))]
        );
        assert_eq!(
            updates_of("HSPD=7000", "OK")[3],
            (3, AxisUpdate::GlobalMaxSpeed(7000))
        );
    }

    #[test]
    fn a_move_line_gives_its_target_operand_and_the_mode_comes_from_abs_inc_and_mm() {
        assert_eq!(
            updates_of("X50000", "OK"),
            [(0, AxisUpdate::MoveTarget(50000))]
        );
        assert_eq!(
            updates_of("Y-20Z300", "OK"),
            [
                (1, AxisUpdate::MoveTarget(-20)),
                (2, AxisUpdate::MoveTarget(300))
            ]
        );
        let all = |mode| -> Vec<(usize, AxisUpdate)> {
            (0..4).map(|a| (a, AxisUpdate::MoveMode(mode))).collect()
        };
        assert_eq!(updates_of("ABS", "OK"), all(Some(MoveMode::Absolute)));
        assert_eq!(updates_of("INC", "OK"), all(Some(MoveMode::Incremental)));
        assert_eq!(updates_of("MM", "0"), all(Some(MoveMode::Absolute)));
        assert_eq!(updates_of("MM", "1"), all(Some(MoveMode::Incremental)));
        assert_eq!(updates_of("MM", "7"), all(None), "no mode of Table 2-22");
        // No target the console can tell after these.
        for (line, axes) in [
            ("JX+", &[0][..]),
            ("HY-1", &[1]),
            ("ZMOVEU+", &[3]),
            ("TX5000", &[0]),
            ("PZ=0", &[2]),
            ("CIRXZP1000:1000", &[0, 2]),
        ] {
            let expected: Vec<(usize, AxisUpdate)> = axes
                .iter()
                .map(|&a| (a, AxisUpdate::TargetUnknown))
                .collect();
            assert_eq!(updates_of(line, "OK"), expected, "{line}");
        }
        // A stop says nothing of the target: the axis stands short of it.
        assert!(updates_of("STOP", "OK").is_empty());
        assert!(updates_of("ESTOP", "OK").is_empty());
    }

    #[test]
    fn clearing_errors_sends_clr_for_the_axis() {
        assert_eq!(Cmd4crConsole.clear_errors_line(0).as_deref(), Some("CLRX"));
        assert_eq!(Cmd4crConsole.clear_errors_line(3).as_deref(), Some("CLRU"));
        assert_eq!(Cmd4crConsole.clear_errors_line(4), None);
        assert_eq!(prepare("CLRY").effect, Effect::Acts);
    }

    #[test]
    fn the_stop_key_stops_one_axis_with_a_ramp() {
        assert_eq!(Cmd4crConsole.stop_axis_line(2).as_deref(), Some("STOPZ"));
        assert_eq!(Cmd4crConsole.stop_axis_line(4), None);
    }
}
