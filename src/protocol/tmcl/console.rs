//! TMCL as the session layer sees it ([`FamilyConsole`]): which lines only
//! read (and may be retried), what each reply carries, the emergency stop,
//! and the axis parameters that make up an axis's status.

use std::sync::Arc;

use super::DEFAULT_MODULE_ADDRESS;
use super::command::{Command, RfsAction, StatusQuery, VersionFormat};
use super::frame::{FRAME_LEN, Reply, Request, checksum};
use super::line::{format_command, parse_line};
use super::params::{axis_param, global_param};
use super::wire::{TmclReplyRule, TmclWire, is_version_string};
use crate::protocol::console::{
    Answering, AxisFlag, AxisInfo, AxisUpdate, Completions, Effect, FamilyConsole, LoadScale,
    PreparedLine, Reading, ReplyError, ReplyValue, StatusPoll, StatusValue, SwitchKind,
};
use crate::protocol::parameters::ParameterSet;
use crate::protocol::wire::{Frame, ReplyRule, Verdict, WireFormat};

/// The TMCM-1110 has one motor, number 0 (§1).
pub const AXES: &[AxisInfo] = &[AxisInfo {
    number: 0,
    name: "motor 0",
}];

/// AP207 "extended error flags" (§4 Table 16): cleared when read and by
/// every motion command, so whoever reads them must keep them.
pub const ERROR_FLAGS: &[(u32, AxisFlag)] = &[
    (
        1 << 0,
        AxisFlag {
            name: "stall",
            description: "StallGuard error: the motor was stopped on a stall (AP207 bit 0, §4)",
        },
    ),
    (
        1 << 1,
        AxisFlag {
            name: "deviation",
            description: "encoder deviation error: the motor was stopped (AP207 bit 1, §4, §6.3)",
        },
    ),
];

/// AP208 "TMC262 error flags" (§4 Table 16): the driver's state now.
pub const DRIVER_FLAGS: &[(u32, AxisFlag)] = &[
    (
        1 << 0,
        AxisFlag {
            name: "sg2",
            description: "StallGuard2 threshold reached (AP208 bit 0)",
        },
    ),
    (
        1 << 1,
        AxisFlag {
            name: "overtemperature",
            description: "driver shut down by overtemperature (AP208 bit 1)",
        },
    ),
    (
        1 << 2,
        AxisFlag {
            name: "temperature warning",
            description: "driver temperature pre-warning threshold exceeded (AP208 bit 2)",
        },
    ),
    (
        1 << 3,
        AxisFlag {
            name: "short A",
            description: "short to ground on coil A, driver shut down (AP208 bit 3)",
        },
    ),
    (
        1 << 4,
        AxisFlag {
            name: "short B",
            description: "short to ground on coil B, driver shut down (AP208 bit 4)",
        },
    ),
    (
        1 << 5,
        AxisFlag {
            name: "open load A",
            description: "open load on coil A (AP208 bit 5)",
        },
    ),
    (
        1 << 6,
        AxisFlag {
            name: "open load B",
            description: "open load on coil B (AP208 bit 6)",
        },
    ),
    (
        1 << 7,
        AxisFlag {
            name: "standstill",
            description: "no step pulse for 2^20 clock cycles (AP208 bit 7)",
        },
    ),
];

/// One axis parameter read for the status display.
struct StatusParam {
    number: u8,
    fast: bool,
}

/// The axis parameters polled for each axis (§4 Table 16), fast-changing
/// ones first.
const STATUS_PARAMS: &[StatusParam] = &[
    StatusParam {
        number: 1, // actual position
        fast: true,
    },
    StatusParam {
        number: 3, // actual speed
        fast: true,
    },
    StatusParam {
        number: 8, // position reached
        fast: true,
    },
    StatusParam {
        number: 4, // maximum positioning speed, the speed gauge's scale
        fast: false,
    },
    StatusParam {
        number: 0, // target position
        fast: false,
    },
    StatusParam {
        number: 11, // left limit switch
        fast: false,
    },
    StatusParam {
        number: 10, // right limit switch
        fast: false,
    },
    StatusParam {
        number: 9, // home switch
        fast: false,
    },
    StatusParam {
        number: 206, // actual load value
        fast: false,
    },
    StatusParam {
        number: 207, // extended error flags (clear on read)
        fast: false,
    },
    StatusParam {
        number: 208, // TMC262 error flags
        fast: false,
    },
];

/// TMCL for the session layer.
#[derive(Debug, Clone, Copy, Default)]
pub struct TmclConsole;

impl TmclConsole {
    /// A typed command, ready for the module at `address`.
    pub fn prepare_command(&self, command: &Command, address: u8) -> PreparedLine {
        let request = command.to_request(address);
        // A raw frame that is exactly a typed command is judged as that
        // command: `6 1 0 0` reads like `GAP 1, 0`.
        let typed = Command::from_request(&request);
        let rule = reply_rule(&request, &typed);
        let answering = match typed {
            // §3.6.53: "this command does not send back a reply".
            Command::FactoryReset => Answering::Nothing,
            // §3.6.53: the reply "might not always get through".
            Command::SoftwareReset => Answering::MaybeReply(rule),
            // §5.1 GP255: once replies are suppressed this one may not come.
            Command::Sgp {
                param: 255,
                bank: 0,
                value,
            } if value != 0 => Answering::MaybeReply(rule),
            _ => Answering::Reply(rule),
        };
        PreparedLine {
            canonical: format_command(&typed),
            address,
            bytes: request.to_bytes().to_vec(),
            answering,
            effect: if only_reads(&typed) {
                Effect::Reads
            } else {
                Effect::Acts
            },
        }
    }
}

/// How the answer to `request` is recognised. 136 type 0 and 134 answer
/// in layouts of their own (§3.6.53, digest D4); everything else with an
/// ordinary reply.
fn reply_rule(request: &Request, typed: &Command) -> Arc<dyn ReplyRule> {
    match typed {
        Command::FirmwareVersion {
            format: VersionFormat::String,
        }
        | Command::ReadMemory { .. } => Arc::new(SpecialReplyRule {
            request: *request,
            ordinary: TmclReplyRule::for_request(request),
        }),
        _ => Arc::new(TmclReplyRule::for_request(request)),
    }
}

/// The answer to 136 type 0 (the host address and eight ASCII characters,
/// no checksum) or 134 (the host address, a 7-byte program word and a
/// checksum), or an ordinary reply refusing either.
#[derive(Debug)]
struct SpecialReplyRule {
    request: Request,
    ordinary: TmclReplyRule,
}

impl ReplyRule for SpecialReplyRule {
    fn examine(&self, accepted: &[Frame], frame: &[u8]) -> Verdict {
        if !accepted.is_empty() {
            return Verdict::NotMine;
        }
        if self.ordinary.examine(accepted, frame) == Verdict::Complete {
            return Verdict::Complete;
        }
        let Ok(frame) = <&[u8; FRAME_LEN]>::try_from(frame) else {
            return Verdict::NotMine;
        };
        let answers = if self.request.command == super::command::opcode::FIRMWARE_VERSION {
            is_version_string(frame)
        } else {
            checksum(frame.get(..8).unwrap_or_default()) == frame[8]
        };
        if answers {
            Verdict::Complete
        } else {
            Verdict::NotMine
        }
    }
}

/// Commands that read and change nothing, so that a lost reply may be
/// asked for again. GCO with motor 255 copies EEPROM to RAM (§3.6.25) and
/// is a write.
fn only_reads(command: &Command) -> bool {
    match command {
        Command::Gap { .. }
        | Command::Ggp { .. }
        | Command::Gio { .. }
        | Command::ApplicationStatus { .. }
        | Command::FirmwareVersion { .. }
        | Command::ReadMemory { .. } => true,
        Command::Gco { motor, .. } => *motor != 255,
        Command::Rfs { action, .. } => *action == RfsAction::Status,
        _ => false,
    }
}

/// The request a prepared line carries.
fn request_of(line: &PreparedLine) -> Option<Request> {
    let bytes: &[u8; FRAME_LEN] = line.bytes.as_slice().try_into().ok()?;
    Some(Request::from_bytes_unchecked(bytes))
}

fn malformed(line: &PreparedLine, reason: impl Into<String>) -> ReplyError {
    ReplyError::Malformed {
        line: line.canonical.clone(),
        reason: reason.into(),
    }
}

/// An ordinary reply refusing `request`, as opposed to a special-format
/// answer (136 type 0, 134) whose bytes merely look like one.
fn refusal(request: &Request, frame: &[u8; FRAME_LEN]) -> Option<Reply> {
    let reply = Reply::from_bytes(frame).ok()?;
    (reply.module_address == request.address
        && reply.command == request.command
        && !reply.status.is_success())
    .then_some(reply)
}

fn rejected(line: &PreparedLine, reply: &Reply) -> ReplyError {
    ReplyError::Rejected {
        module: format!("module {}", reply.module_address),
        line: line.canonical.clone(),
        status: u32::from(reply.status.0),
        meaning: reply.status.meaning().to_string(),
    }
}

/// §3.6.53 / digest D4 (from sibling manuals): 136 type 0 answers with
/// the host address and eight ASCII characters, no checksum.
fn version_string(frame: &[u8; FRAME_LEN]) -> String {
    frame
        .get(1..)
        .unwrap_or_default()
        .iter()
        .map(|&b| {
            if b.is_ascii_graphic() || b == b' ' {
                char::from(b)
            } else {
                '?'
            }
        })
        .collect::<String>()
        .trim()
        .to_string()
}

/// 134 answers with the host address, the stored 7-byte command and a
/// checksum (the simulator's layout; the manual gives none, digest D4).
fn program_word(line: &PreparedLine, frame: &[u8; FRAME_LEN]) -> Result<String, ReplyError> {
    let sum = checksum(frame.get(..8).unwrap_or_default());
    if frame[8] != sum {
        return Err(malformed(
            line,
            format!(
                "wrong checksum: frame carries {:#04x}, its bytes sum to {sum:#04x}",
                frame[8]
            ),
        ));
    }
    let word = Request {
        address: 0,
        command: frame[1],
        kind: frame[2],
        motor_bank: frame[3],
        value: i32::from_be_bytes([frame[4], frame[5], frame[6], frame[7]]),
    };
    Ok(format_command(&Command::from_request(&word)))
}

/// The value a successful reply to `command` carries, if it carries one.
pub(super) fn reply_value(command: &Command, raw: i32) -> ReplyValue {
    match *command {
        Command::Gap { param, .. } => ReplyValue::Number(
            axis_param(param).map_or(i64::from(raw), |info| info.value_from_wire(raw)),
        ),
        Command::Ggp { param, bank } => ReplyValue::Number(
            global_param(bank, param).map_or(i64::from(raw), |info| info.value_from_wire(raw)),
        ),
        Command::ApplicationStatus { query } => match packed_status_meaning(query) {
            Some(packed) => ReplyValue::Text(format!(
                "{raw} (0x{raw:08X}: {packed}, packed in one word in a layout §3.6.53 does \
                 not give; GGP 128 reads the mode, GGP 130 the program counter)"
            )),
            None => ReplyValue::Number(i64::from(raw)),
        },
        Command::Gio { .. }
        | Command::FirmwareVersion { .. }
        | Command::Rfs {
            action: RfsAction::Status,
            ..
        } => ReplyValue::Number(i64::from(raw)),
        Command::Gco { motor, .. } if motor != 255 => ReplyValue::Number(i64::from(raw)),
        _ => ReplyValue::None,
    }
}

/// What command 135's packed types hold (§3.6.53 Table 14); `None` for
/// the plain registers (accumulator, X).
fn packed_status_meaning(query: StatusQuery) -> Option<&'static str> {
    match query {
        StatusQuery::Mode => Some("mode, wait flag and memory pointer"),
        StatusQuery::ProgramCounter => Some("mode, wait flag and program counter"),
        StatusQuery::Accumulator | StatusQuery::XRegister => None,
    }
}

fn flags_in(table: &[(u32, AxisFlag)], bits: i64) -> Vec<AxisFlag> {
    table
        .iter()
        .filter(|(bit, _)| bits & i64::from(*bit) != 0)
        .map(|(_, flag)| *flag)
        .collect()
}

impl FamilyConsole for TmclConsole {
    /// AP0 target, AP1 position, AP3 speed and AP206 load, as polled.
    fn status_values(&self) -> &'static [StatusValue] {
        &[
            StatusValue::Position,
            StatusValue::Target,
            StatusValue::Speed,
            StatusValue::Load,
        ]
    }

    fn wire(&self) -> Arc<dyn WireFormat> {
        Arc::new(TmclWire::default())
    }

    /// §3.1.1: every reply carries an 8-bit checksum, and one that does
    /// not add up is never an answer.
    fn replies_checked(&self) -> bool {
        true
    }

    fn complete(&self, line: &str, cursor: usize) -> Completions {
        super::assist::complete(line, cursor)
    }

    fn help(&self, line: &str, cursor: usize) -> Vec<String> {
        super::assist::help(line, cursor)
    }

    fn stop_axis_line(&self, axis: u8) -> Option<String> {
        AXES.iter()
            .any(|a| a.number == axis)
            .then(|| format_command(&Command::Mst { motor: axis }))
    }

    fn load_scale(&self) -> Option<LoadScale> {
        // AP206, StallGuard2 load reading 0..1023: 0 is the highest load
        // (§4 Table 16).
        let full_scale = axis_param(206).map_or(1023, |p| match p.range {
            super::params::ValueRange::Span { max, .. } => max,
            super::params::ValueRange::OneOf(_) => 1023,
        });
        Some(LoadScale {
            full_scale,
            zero_is_highest: true,
        })
    }

    fn status_meaning(&self, status: u32) -> Option<String> {
        let status = u8::try_from(status).ok()?;
        Some(super::frame::Status(status).meaning().to_string())
    }

    fn units(&self) -> Option<&'static dyn crate::protocol::units::UnitLaw> {
        Some(&super::units::TmclUnits)
    }

    fn parameters(&self) -> Option<&'static dyn ParameterSet> {
        Some(&super::parameter_set::TmclParameters)
    }

    fn jog(&self) -> Option<&'static dyn crate::protocol::jog::JogPlan> {
        Some(&super::jog::TmclJog)
    }

    fn io(&self) -> Option<&'static dyn crate::protocol::io::IoPlan> {
        Some(&super::io::TmclIo)
    }

    fn stall_sweep(&self) -> Option<&'static dyn crate::protocol::tuning::StallSweepPlan> {
        Some(&super::tuning::TmclStallSweep)
    }

    fn current_control(&self) -> Option<&'static dyn crate::protocol::tuning::CurrentControlPlan> {
        Some(&super::tuning::TmclCoolStep)
    }

    fn program(&self) -> Option<&'static dyn crate::protocol::program::ProgramTool> {
        Some(&super::tool::TmclTool)
    }

    fn describe_request(&self, bytes: &[u8]) -> Option<String> {
        Some(super::traffic::describe_request(bytes))
    }

    fn describe_reply(&self, bytes: &[u8], request: Option<&[u8]>) -> Option<String> {
        Some(super::traffic::describe_reply(bytes, request))
    }

    fn default_address(&self) -> u8 {
        DEFAULT_MODULE_ADDRESS
    }

    /// GP66, the serial address, is 1..255 (§5.1 Table 18).
    fn addresses(&self) -> std::ops::RangeInclusive<u8> {
        1..=255
    }

    fn axes(&self) -> &'static [AxisInfo] {
        AXES
    }

    fn prepare(
        &self,
        line: &str,
        address: u8,
    ) -> Result<PreparedLine, crate::protocol::line_error::LineError> {
        let command = parse_line(line)?;
        Ok(self.prepare_command(&command, address))
    }

    fn interpret(&self, line: &PreparedLine, frames: &[Frame]) -> Result<Reading, ReplyError> {
        let no_answer = Reading {
            status: None,
            value: ReplyValue::None,
        };
        let Some(last) = frames.last() else {
            return match line.answering {
                Answering::Reply(_) | Answering::Later { .. } => Err(malformed(line, "no reply")),
                Answering::MaybeReply(_) | Answering::Nothing => Ok(no_answer),
            };
        };
        let request = request_of(line).ok_or_else(|| malformed(line, "not a TMCL request"))?;
        let frame: &[u8; FRAME_LEN] = last.as_slice().try_into().map_err(|_| {
            malformed(
                line,
                format!(
                    "a reply has {FRAME_LEN} bytes, this one {}: {}",
                    last.len(),
                    super::to_hex(last)
                ),
            )
        })?;
        let command = Command::from_request(&request);
        let special = matches!(
            command,
            Command::FirmwareVersion {
                format: VersionFormat::String
            } | Command::ReadMemory { .. }
        );
        if special {
            if let Some(reply) = refusal(&request, frame) {
                return Err(rejected(line, &reply));
            }
            let text = match command {
                Command::ReadMemory { .. } => program_word(line, frame)?,
                _ => version_string(frame),
            };
            return Ok(Reading {
                status: None,
                value: ReplyValue::Text(text),
            });
        }
        let reply = Reply::from_bytes(frame)
            .map_err(|e| malformed(line, format!("{}: {e}", super::to_hex(frame))))?;
        if !reply.status.is_success() {
            return Err(rejected(line, &reply));
        }
        Ok(Reading {
            status: Some(u32::from(reply.status.0)),
            value: reply_value(&command, reply.value),
        })
    }

    fn emergency_stop(&self, address: u8) -> Vec<PreparedLine> {
        // MST every motor at once; then stop a standalone program, which
        // could otherwise start the motor again (§3.5: direct-mode commands
        // run beside it); then MST again in case it did meanwhile.
        let stops = AXES
            .iter()
            .map(|axis| self.prepare_command(&Command::Mst { motor: axis.number }, address));
        let mut lines: Vec<PreparedLine> = stops.clone().collect();
        lines.push(self.prepare_command(&Command::StopApplication, address));
        lines.extend(stops);
        lines
    }

    fn identify(&self, address: u8) -> PreparedLine {
        self.prepare_command(
            &Command::FirmwareVersion {
                format: VersionFormat::String,
            },
            address,
        )
    }

    fn status_queries(&self, address: u8) -> Vec<StatusPoll> {
        AXES.iter()
            .enumerate()
            .flat_map(|(index, axis)| {
                STATUS_PARAMS.iter().map(move |param| StatusPoll {
                    axis: index,
                    line: self.prepare_command(
                        &Command::Gap {
                            param: param.number,
                            motor: axis.number,
                        },
                        address,
                    ),
                    fast: param.fast,
                })
            })
            .collect()
    }

    fn status_update(&self, line: &PreparedLine, reading: &Reading) -> Vec<(usize, AxisUpdate)> {
        status_update(line, reading).into_iter().collect()
    }
}

/// What a reading says about the one motor, if it reads status.
fn status_update(line: &PreparedLine, reading: &Reading) -> Option<(usize, AxisUpdate)> {
    let request = request_of(line)?;
    let Command::Gap { param, motor } = Command::from_request(&request) else {
        return None;
    };
    let axis = AXES.iter().position(|a| a.number == motor)?;
    let ReplyValue::Number(value) = reading.value else {
        return None;
    };
    let update = match param {
        0 => AxisUpdate::Target(value),
        1 => AxisUpdate::Position(value),
        3 => AxisUpdate::Speed(value),
        4 => AxisUpdate::MaxSpeed(value),
        8 => AxisUpdate::Reached(value != 0),
        9 => AxisUpdate::Switch(SwitchKind::Home, value != 0),
        10 => AxisUpdate::Switch(SwitchKind::Right, value != 0),
        11 => AxisUpdate::Switch(SwitchKind::Left, value != 0),
        206 => AxisUpdate::Load(value),
        207 => AxisUpdate::Errors(flags_in(ERROR_FLAGS, value)),
        208 => AxisUpdate::DriverFlags(flags_in(DRIVER_FLAGS, value)),
        _ => return None,
    };
    Some((axis, update))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::tmcl::Status;

    fn reply(status: u8, command: u8, value: i32) -> Frame {
        Reply {
            host_address: 2,
            module_address: 1,
            status: Status(status),
            command,
            value,
        }
        .to_bytes()
        .to_vec()
    }

    fn prepare(line: &str) -> PreparedLine {
        TmclConsole.prepare(line, 1).expect("valid line")
    }

    #[test]
    fn reads_may_be_retried_and_everything_else_not() {
        for line in [
            "GAP 1, 0",
            "GGP 66, 0",
            "GIO 0, 1",
            "GCO 3, 0",
            "RFS STATUS, 0",
            "APPSTATUS",
            "VERSION",
            "READMEM 0",
            "6 1 0 0",
        ] {
            assert_eq!(prepare(line).effect, Effect::Reads, "{line}");
        }
        for line in [
            "SAP 4, 0, 100",
            "MVP ABS, 0, 100",
            "GCO 3, 255",
            "RFS START, 0",
            "STAP 4, 0",
            "RUNAPP",
            "5 4 0 100",
        ] {
            assert_eq!(prepare(line).effect, Effect::Acts, "{line}");
        }
    }

    #[test]
    fn factory_reset_expects_nothing_and_reset_maybe_a_reply() {
        assert!(matches!(
            prepare("FACTORYRESET").answering,
            Answering::Nothing
        ));
        assert!(matches!(
            prepare("RESET").answering,
            Answering::MaybeReply(_)
        ));
        assert!(matches!(
            prepare("SGP 255, 0, 1").answering,
            Answering::MaybeReply(_)
        ));
        assert!(matches!(prepare("GAP 1, 0").answering, Answering::Reply(_)));
    }

    /// `APPSTATUS MODE` answers a packed word: a bare `5` says nothing
    /// (issue 19, point 8); the registers stay numbers.
    #[test]
    fn the_packed_application_status_says_what_it_holds() {
        let line = prepare("APPSTATUS MODE");
        let reading = TmclConsole
            .interpret(&line, &[reply(100, 135, 5)])
            .expect("a reading");
        let shown = reading.value.to_string();
        assert!(
            shown.starts_with("5 (0x00000005: mode, wait flag and memory pointer"),
            "{shown}"
        );
        assert!(shown.contains("GGP 128"), "{shown}");
        let line = prepare("APPSTATUS ACCU");
        let reading = TmclConsole
            .interpret(&line, &[reply(100, 135, 7)])
            .expect("a reading");
        assert_eq!(reading.value, ReplyValue::Number(7));
    }

    #[test]
    fn a_raw_frame_is_named_by_the_command_it_carries() {
        assert_eq!(prepare("5 6 0 300").canonical, "SAP 6, 0, 300");
        assert_eq!(prepare("200 1 2 3").canonical, "200 1 2 3");
    }

    #[test]
    fn a_refused_line_names_the_range() {
        let message = TmclConsole
            .prepare("SAP 6, 0, 100000", 1)
            .unwrap_err()
            .to_string();
        assert!(message.contains("0..255"), "{message}");
    }

    #[test]
    fn reads_carry_their_value_and_writes_say_ok() {
        let gap = prepare("GAP 4, 0");
        let reading = TmclConsole.interpret(&gap, &[reply(100, 6, 1234)]).unwrap();
        assert_eq!(reading.value, ReplyValue::Number(1234));
        assert_eq!(reading.status, Some(100));
        let sap = prepare("SAP 4, 0, 1234");
        let reading = TmclConsole.interpret(&sap, &[reply(100, 5, 1234)]).unwrap();
        assert_eq!(reading.value, ReplyValue::None);
        assert_eq!(reading.value.to_string(), "ok");
    }

    #[test]
    fn timer_periods_read_back_unsigned() {
        let ggp = prepare("GGP 0, 3");
        let reading = TmclConsole.interpret(&ggp, &[reply(100, 10, -1)]).unwrap();
        assert_eq!(reading.value, ReplyValue::Number(4_294_967_295));
    }

    #[test]
    fn error_statuses_become_rejections_with_the_manuals_meaning() {
        let sap = prepare("SAP 6, 0, 200");
        let error = TmclConsole.interpret(&sap, &[reply(4, 5, 0)]).unwrap_err();
        assert_eq!(
            error.to_string(),
            "module 1 rejected SAP 6, 0, 200: invalid value (status 4)"
        );
        assert_eq!(error.status(), Some(4));
    }

    #[test]
    fn a_reply_with_a_bad_checksum_is_malformed() {
        let gap = prepare("GAP 1, 0");
        let mut frame = reply(100, 6, 5);
        frame[8] ^= 0xFF;
        let error = TmclConsole.interpret(&gap, &[frame]).unwrap_err();
        assert!(matches!(error, ReplyError::Malformed { .. }), "{error}");
        assert_eq!(
            error.to_string(),
            "unreadable answer to GAP 1, 0: 02 01 64 06 00 00 00 05 8D: wrong checksum: \
             frame carries 0x8d, its bytes sum to 0x72"
        );
        assert_eq!(
            TmclConsole
                .interpret(&gap, &[vec![1, 2, 3]])
                .unwrap_err()
                .to_string(),
            "unreadable answer to GAP 1, 0: a reply has 9 bytes, this one 3: 01 02 03"
        );
    }

    #[test]
    fn the_version_string_is_text() {
        let version = prepare("VERSION");
        let mut frame = vec![2];
        frame.extend_from_slice(b"1110V112");
        let reading = TmclConsole.interpret(&version, &[frame]).unwrap();
        assert_eq!(reading.value, ReplyValue::Text("1110V112".into()));
        let refused = TmclConsole
            .interpret(&version, &[reply(6, 136, 0)])
            .unwrap_err();
        assert_eq!(refused.status(), Some(6));
    }

    #[test]
    fn special_answers_are_recognised_and_ordinary_ones_too() {
        let Answering::Reply(version) = prepare("VERSION").answering else {
            panic!("VERSION expects a reply")
        };
        let mut text = vec![2];
        text.extend_from_slice(b"1110V112");
        assert_eq!(version.examine(&[], &text), Verdict::Complete);
        assert_eq!(version.examine(&[], &reply(2, 136, 0)), Verdict::Complete);
        assert_eq!(version.examine(&[], &reply(100, 6, 0)), Verdict::NotMine);
        let Answering::Reply(memory) = prepare("READMEM 0").answering else {
            panic!("READMEM expects a reply")
        };
        let mut word = vec![2, 4, 0, 0, 0, 0, 0, 5];
        word.push(checksum(&word));
        assert_eq!(memory.examine(&[], &word), Verdict::Complete);
        word[8] ^= 1;
        assert_eq!(memory.examine(&[], &word), Verdict::NotMine);
        let Answering::Reply(gap) = prepare("GAP 1, 0").answering else {
            panic!("GAP expects a reply")
        };
        assert_eq!(gap.examine(&[], &text), Verdict::NotMine);
        assert_eq!(gap.examine(&[], &reply(100, 6, 0)), Verdict::Complete);
    }

    #[test]
    fn a_program_word_reads_as_a_line() {
        let read = prepare("READMEM 3");
        let mut frame = vec![2, 4, 0, 0, 0, 0, 0x03, 0xE8];
        frame.push(checksum(&frame));
        let reading = TmclConsole.interpret(&read, &[frame]).unwrap();
        assert_eq!(reading.value, ReplyValue::Text("MVP ABS, 0, 1000".into()));
    }

    #[test]
    fn no_reply_is_fine_only_where_none_may_come() {
        assert!(TmclConsole.interpret(&prepare("RESET"), &[]).is_ok());
        assert!(TmclConsole.interpret(&prepare("FACTORYRESET"), &[]).is_ok());
        assert!(TmclConsole.interpret(&prepare("GAP 1, 0"), &[]).is_err());
    }

    #[test]
    fn emergency_stop_stops_the_motor_and_the_program() {
        let lines: Vec<String> = TmclConsole
            .emergency_stop(1)
            .into_iter()
            .map(|l| l.canonical)
            .collect();
        assert_eq!(lines, ["MST 0", "STOPAPP", "MST 0"]);
    }

    #[test]
    fn error_flag_reads_name_their_flags() {
        let gap = prepare("GAP 207, 0");
        let reading = TmclConsole.interpret(&gap, &[reply(100, 6, 3)]).unwrap();
        let [(axis, update)] = TmclConsole
            .status_update(&gap, &reading)
            .try_into()
            .expect("one update");
        assert_eq!(axis, 0);
        let AxisUpdate::Errors(flags) = update else {
            panic!("{update:?}")
        };
        let names: Vec<_> = flags.iter().map(|f| f.name).collect();
        assert_eq!(names, ["stall", "deviation"]);
        // A write says nothing about the status.
        let sap = prepare("SAP 4, 0, 10");
        let reading = TmclConsole.interpret(&sap, &[reply(100, 5, 0)]).unwrap();
        assert!(TmclConsole.status_update(&sap, &reading).is_empty());
    }

    #[test]
    fn every_axis_gets_every_status_query() {
        let queries = TmclConsole.status_queries(1);
        assert_eq!(queries.len(), STATUS_PARAMS.len() * AXES.len());
        assert!(queries.iter().all(|q| q.line.effect == Effect::Reads));
        assert!(queries.iter().any(|q| q.line.canonical == "GAP 207, 0"));
    }
}
