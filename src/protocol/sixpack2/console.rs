//! The SIXpack 2 as the session layer sees it ([`FamilyConsole`]): lines
//! framed for a unit address, which commands answer (only the queries and
//! the service commands, §7), what each answer says, the emergency stop
//! the protocol lacks, and the queries that make up the status of the six
//! motors.

use crate::protocol::plausible::{PositionRead, TopSpeed};
use std::sync::{Arc, LazyLock};
use std::time::Duration;

use super::catalog::{ACTIONS, Class, MOTORS, activity};
use super::caution::{self, Known, MotorKnown};
use super::command::Command;
use super::frame::{Reply, ReplyFraming, Request, to_hex};
use super::line::{DEFAULT_ADDRESS, canonical, parse_line};
use super::reply::{ReplyFields, check_answers};
use super::wire::{IdleAnswerRule, Sixpack2ReplyRule, Sixpack2Wire};
use crate::protocol::console::{
    Answering, AxisFlag, AxisInfo, AxisUpdate, Completions, Effect, FamilyConsole, LinkChoice,
    LinkOption, PreparedLine, Reading, ReplyError, ReplyValue, StatusPoll, StatusValue, SwitchKind,
};
use crate::protocol::parameters::{ParameterSet, Scope};
use crate::protocol::program::ProgramTool;
use crate::protocol::settings::{SettingWrite, SettingsCache};
use crate::protocol::wire::{Frame, WireFormat};

/// The factory baud rate: no jumpers fitted (§5.2.3 Table 5.1, §6.1.1).
pub const FACTORY_BAUD: u32 = 19200;

/// The six motors, motno 0..5, with the manual's "Motor 1..6" (§7).
pub const AXES: &[AxisInfo] = &[
    AxisInfo {
        number: 0,
        name: "m0/Motor1",
    },
    AxisInfo {
        number: 1,
        name: "m1/Motor2",
    },
    AxisInfo {
        number: 2,
        name: "m2/Motor3",
    },
    AxisInfo {
        number: 3,
        name: "m3/Motor4",
    },
    AxisInfo {
        number: 4,
        name: "m4/Motor5",
    },
    AxisInfo {
        number: 5,
        name: "m5/Motor6",
    },
];

/// How long a `$28` with a wait mask waits for its motors to be idle:
/// a reference search that finds no switch retries without end
/// (§6.4, digest D6.2), so there is no natural bound; ten minutes covers
/// any search or move of a commissioning run, and the emergency stop,
/// Esc or Ctrl-C end the wait sooner.
pub const IDLE_WAIT: Duration = Duration::from_secs(600);

/// `GetAllActivities`, whose wait mask delays its answer (§7.2).
const ALL_ACTIVITIES: u8 = 0x28;

/// The reply framing as a link option (digest D1.4): the manual
/// describes 8-byte replies, a 9-byte form mirroring the request is
/// plausible and unconfirmed.
pub static LINK_OPTIONS: [LinkOption; 1] = [LinkOption {
    name: "framing",
    help: "how replies are read: with or without the response address in front (digest D1.4)",
    choices: &[
        LinkChoice {
            value: "auto",
            help: "either form, told apart by its first byte ($00, the console's response \
                   address, is no command that answers)",
            family: &super::FAMILY_AUTO,
        },
        LinkChoice {
            value: "cmd8",
            help: "8 bytes CMD P0..P6, as §6.2.2.3 reads a reply",
            family: &super::FAMILY_CMD8,
        },
        LinkChoice {
            value: "addr9",
            help: "9 bytes ADDR CMD P0..P6, the response address in front",
            family: &super::FAMILY_ADDR9,
        },
    ],
}];

/// What a setting or motion line reads as once sent: the unit
/// acknowledges none (§7, digest D0), so "ok" would claim what nobody
/// saw.
pub const SENT: &str = "sent";

/// Reply fields a read clears (§7.1: `$20` "stop flag … cleared after
/// read", `$43` reset flag "1 on the first read after a reset").
const CLEARED_BY_READING: &[&str] = &["stop", "reset"];

/// The `$20` stop flag: latched by the unit until read, so the session
/// keeps it (§7.2, §6.4.4).
pub const STOP_FLAG: AxisFlag = AxisFlag {
    name: "stop flag",
    description: "a stop condition occurred (switch outside testnullrange, switch missing at \
                  zero, A_In limit; §6.4.4, §7.1 $15): the position may be lost. Reading it \
                  ($20 P6) cleared it in the unit",
};

/// The motor's action as a lamp, one per activity but "inactive" (§7.2).
static ACTION_LAMPS: LazyLock<Vec<AxisFlag>> = LazyLock::new(|| {
    ACTIONS
        .iter()
        .filter(|a| a.first != 0)
        .map(|a| AxisFlag {
            name: a.name,
            description: a.meaning,
        })
        .collect()
});

/// The lamp of an action code, if it has one (inactive and codes §7.2
/// does not name have none).
fn action_lamp(code: i64) -> Vec<AxisFlag> {
    let Ok(code) = u8::try_from(code) else {
        return Vec::new();
    };
    activity(code)
        .and_then(|a| ACTION_LAMPS.iter().find(|l| l.name == a.name))
        .copied()
        .into_iter()
        .collect()
}

/// The SIXpack 2 for the session layer, with its reply framing (digest
/// D1.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Sixpack2Console {
    pub framing: ReplyFraming,
}

impl Sixpack2Console {
    /// Replies told apart as they come: the registered family.
    pub const AUTO: Sixpack2Console = Sixpack2Console {
        framing: ReplyFraming::Auto,
    };

    /// 8-byte replies `CMD P0..P6` only, as §6.2.2.3 reads them.
    pub const CMD8: Sixpack2Console = Sixpack2Console {
        framing: ReplyFraming::Cmd8,
    };

    /// 9-byte replies with the response address in front only.
    pub const ADDR9: Sixpack2Console = Sixpack2Console {
        framing: ReplyFraming::Addr9,
    };

    /// A request, ready to send: answered only if its command answers; a
    /// `$28` with a wait mask answers when its motors are idle, as news,
    /// while other requests go on (§7.2, §6.2.1.7).
    pub fn prepare_request(&self, request: Request) -> PreparedLine {
        let command = Command::from_request(&request).ok().flatten();
        let answers = command.as_ref().is_some_and(|c| c.spec.answers());
        let waits = command
            .as_ref()
            .is_some_and(|c| c.spec.code == ALL_ACTIVITIES && c.value("wait") != Some(0));
        PreparedLine {
            canonical: canonical(&request),
            address: request.address,
            bytes: request.to_bytes().to_vec(),
            answering: if waits {
                Answering::Later {
                    rule: Arc::new(IdleAnswerRule {
                        request,
                        framing: self.framing,
                    }),
                    within: IDLE_WAIT,
                }
            } else if answers {
                Answering::Reply(Arc::new(Sixpack2ReplyRule {
                    request,
                    framing: self.framing,
                }))
            } else {
                Answering::Nothing
            },
            effect: if command.as_ref().is_some_and(only_reads) {
                Effect::Reads
            } else {
                Effect::Acts
            },
        }
    }

    /// A typed command for the unit at `address`.
    pub fn prepare_command(&self, command: &Command, address: u8) -> PreparedLine {
        self.prepare_request(command.to_request(address))
    }

    fn line(&self, mnemonic: &str, values: &[i64], address: u8) -> Option<PreparedLine> {
        let spec = super::catalog::by_name(mnemonic)?;
        let command = Command::new(spec, values.to_vec()).ok()?;
        Some(self.prepare_command(&command, address))
    }
}

/// Queries that may be asked again after a lost answer. Not a `$28` with
/// a wait mask: what a second one does while the first is pending is not
/// known (digest D4), and on RS-485 its answer may collide. Not `$44`: it
/// also sets the RS-232 forwarding (§7.4). `$20` and `$43` clear a flag
/// by being read (the stop flag, the reset flag), so a retry after a lost
/// answer may find it cleared; they still count as reads, as TMCL's
/// AP207 does, so that `:wait-until` may poll them.
fn only_reads(command: &Command) -> bool {
    match command.spec.code {
        0x28 => command.value("wait") == Some(0),
        0x44 => false,
        _ => command.spec.class == Class::Query,
    }
}

/// What the cautions know of earlier settings, from the session's cache
/// (the rows of [`super::parameter_set`]: `$12` clkdiv, `$13` div and
/// vstart, `$14` amax and vmax).
pub(super) fn known_of(cache: &SettingsCache) -> Known {
    let mut known = Known {
        clkdiv: cache.value(Scope::Bank(0), 0x1200),
        ..Known::default()
    };
    for (m, motor) in known.motors.iter_mut().enumerate() {
        let scope = Scope::Axis(u8::try_from(m).unwrap_or(0));
        *motor = MotorKnown {
            div: cache.value(scope, 0x1303),
            vstart: cache.value(scope, 0x1302),
            amax: cache.value(scope, 0x1401),
            vmax: cache.value(scope, 0x1402),
        };
    }
    known
}

/// Whether motor `axis`'s NullPositive flag (`$15` flags bit 14) is known
/// to be set by what the session wrote.
fn null_positive(known: &SettingsCache, axis: usize) -> bool {
    let Some(flags) = super::catalog::by_code(0x15)
        .and_then(|spec| spec.fields.iter().position(|f| f.name == "flags"))
        .and_then(|index| u16::try_from(index).ok())
    else {
        return false;
    };
    let scope = Scope::Axis(u8::try_from(axis).unwrap_or(u8::MAX));
    known
        .value(scope, 0x1500 | flags)
        .is_some_and(|value| value & (1 << NULL_POSITIVE_BIT) != 0)
}

/// The stop switches of a motor from a `$30` of its channel: "voltage
/// levels below a defined level are interpreted as the left and above an
/// other level as right end switch", the levels being `$31`'s MinLeft
/// (0 = no function) and MaxRight (≥ 1023 = no function) (§5.5.2.2,
/// §7.3). `$31` cannot be read back, so only limits this session wrote
/// count; a switch without a known limit is not reported.
fn stop_switches(
    line: &PreparedLine,
    reading: &Reading,
    known: &SettingsCache,
) -> Vec<(usize, AxisUpdate)> {
    let Some(command) = request_of(line).and_then(|r| Command::from_request(&r).ok().flatten())
    else {
        return Vec::new();
    };
    if command.spec.code != 0x30 {
        return Vec::new();
    }
    let ReplyValue::Text(text) = &reading.value else {
        return Vec::new();
    };
    let Some(values) = ReplyFields::parse_value(command.spec, text) else {
        return Vec::new();
    };
    let get = |name: &str| values.iter().find(|(n, _)| *n == name).map(|(_, v)| *v);
    // The channel is the request's; the reply's text leaves it out.
    let (Some(channel), Some(analog)) = (command.value("channel"), get("analog")) else {
        return Vec::new();
    };
    let Some(axis) = usize::try_from(channel).ok().filter(|&a| a < AXES.len()) else {
        return Vec::new();
    };
    let Some(limits) = super::catalog::by_code(0x31) else {
        return Vec::new();
    };
    let field = |name: &str| {
        limits
            .fields
            .iter()
            .position(|f| f.name == name)
            .and_then(|i| u16::try_from(i).ok())
            .map(|i| 0x3100 | i)
    };
    let scope = Scope::Axis(u8::try_from(axis).unwrap_or(u8::MAX));
    let limit = |name: &str| field(name).and_then(|number| known.value(scope, number));
    let mut updates = Vec::new();
    if let Some(min_left) = limit("minleft") {
        updates.push((
            axis,
            AxisUpdate::Switch(SwitchKind::Left, min_left > 0 && analog < min_left),
        ));
    }
    if let Some(max_right) = limit("maxright") {
        updates.push((
            axis,
            AxisUpdate::Switch(SwitchKind::Right, max_right < 1023 && analog > max_right),
        ));
    }
    updates
}

/// NullPositive's bit in the motor flags (§7.1 `$15` P6 bit 6).
const NULL_POSITIVE_BIT: u32 = 14;

/// The request a prepared line carries.
fn request_of(line: &PreparedLine) -> Option<Request> {
    Request::from_bytes(&line.bytes)
}

fn malformed(line: &PreparedLine, reason: impl Into<String>) -> ReplyError {
    ReplyError::Malformed {
        line: line.canonical.clone(),
        reason: reason.into(),
    }
}

/// The action of a reading as the axis's lamps.
fn action_updates(axis: usize, action: Option<i64>) -> Option<(usize, AxisUpdate)> {
    action.map(|code| (axis, AxisUpdate::DriverFlags(action_lamp(code))))
}

impl FamilyConsole for Sixpack2Console {
    /// posact, the target and vact, as polled; the SIXpack 2 reports no
    /// load.
    fn status_values(&self) -> &'static [StatusValue] {
        &[
            StatusValue::Position,
            StatusValue::Target,
            StatusValue::Speed,
        ]
    }

    fn wire(&self) -> Arc<dyn WireFormat> {
        Arc::new(Sixpack2Wire {
            framing: self.framing,
        })
    }

    /// The rotary switches' factory setting (§5.2.1).
    fn default_address(&self) -> u8 {
        DEFAULT_ADDRESS
    }

    fn default_baud(&self) -> u32 {
        FACTORY_BAUD
    }

    fn link_options(&self) -> &'static [LinkOption] {
        &LINK_OPTIONS
    }

    fn axes(&self) -> &'static [AxisInfo] {
        AXES
    }

    fn prepare(
        &self,
        line: &str,
        address: u8,
    ) -> Result<PreparedLine, crate::protocol::line_error::LineError> {
        let parsed = parse_line(line, Some(address))?;
        Ok(self.prepare_request(parsed.request))
    }

    /// The D9 warnings, the cross-field ones against what was written
    /// this session (else the factory values, said so).
    fn warnings(&self, line: &PreparedLine, known: &SettingsCache) -> Vec<String> {
        request_of(line).map_or_else(Vec::new, |r| caution::warnings(&r, &known_of(known)))
    }

    fn settings_written(&self, line: &PreparedLine) -> Vec<SettingWrite> {
        request_of(line).map_or_else(Vec::new, |r| super::parameter_set::written_by(&r))
    }

    /// `$CC` resets every setting to its factory value (§7.4, §6.8); a
    /// `$43` reading the reset flag set says a reset happened since the
    /// flag was last read (a power cycle, a `$CC`, the reset button).
    fn settings_lost(&self, line: &PreparedLine, reading: &Reading) -> Option<String> {
        let request = request_of(line)?;
        match request.command {
            0xCC => Some("HardwareReset was sent (§7.4)".into()),
            0x43 => {
                let ReplyValue::Text(text) = &reading.value else {
                    return None;
                };
                let spec = super::catalog::by_code(0x43)?;
                let values = ReplyFields::parse_value(spec, text)?;
                values
                    .iter()
                    .any(|(name, v)| *name == "reset" && *v == 1)
                    .then(|| "the unit reported a reset ($43 reset flag, §7.4)".into())
            }
            _ => None,
        }
    }

    fn confirmation(&self, line: &PreparedLine) -> Option<String> {
        caution::confirmation(&request_of(line)?)
    }

    /// §7.1: reading `$20` clears its stop flag, reading `$43` its reset
    /// flag; a second read shows them as the first left them.
    fn as_if_unread(
        &self,
        _line: &PreparedLine,
        first: &ReplyValue,
        second: &ReplyValue,
    ) -> ReplyValue {
        let (ReplyValue::Text(first), ReplyValue::Text(second)) = (first, second) else {
            return second.clone();
        };
        let cleared = |word: &&str| {
            word.split_once('=')
                .is_some_and(|(name, _)| CLEARED_BY_READING.contains(&name))
        };
        let words: Vec<&str> = second
            .split_whitespace()
            .map(|word| match word.split_once('=') {
                Some((name, _)) if CLEARED_BY_READING.contains(&name) => first
                    .split_whitespace()
                    .filter(cleared)
                    .find(|w| w.split_once('=').is_some_and(|(n, _)| n == name))
                    .unwrap_or(word),
                _ => word,
            })
            .collect();
        ReplyValue::Text(words.join(" "))
    }

    fn interpret(&self, line: &PreparedLine, frames: &[Frame]) -> Result<Reading, ReplyError> {
        let Some(frame) = frames.last() else {
            return match line.answering {
                Answering::Nothing => Ok(Reading {
                    status: None,
                    value: ReplyValue::Text(SENT.into()),
                }),
                Answering::Reply(_) | Answering::MaybeReply(_) | Answering::Later { .. } => {
                    Err(malformed(line, "no reply"))
                }
            };
        };
        let request =
            request_of(line).ok_or_else(|| malformed(line, "not a 9-byte SIXpack 2 request"))?;
        let got = |reason: String| malformed(line, format!("got {}: {reason}", to_hex(frame)));
        let reply = Reply::parse(frame, self.framing).map_err(|e| got(e.to_string()))?;
        let spec = check_answers(&request, &reply).map_err(|e| got(e.to_string()))?;
        let fields = ReplyFields::read(spec, &reply.params)
            .ok_or_else(|| got(format!("{} does not answer", spec.mnemonic)))?;
        if let Some(impossible) = fields.impossible() {
            return Err(got(format!("{impossible}: a damaged reply")));
        }
        Ok(Reading {
            status: None,
            value: ReplyValue::Text(fields.value_text()),
        })
    }

    /// The protocol has no emergency-stop command (digest D9). `$25` with
    /// velocity 0 switches any motor to rotation at once, even from a ramp
    /// or PI control, and decelerates it with amax (§7.2), without the
    /// return trip a `$2A` makes. Its effect on a reference search is not
    /// stated, so `$2B` follows for every motor: the console cannot know
    /// which motor searches at the moment the key is pressed (its last
    /// poll is up to a refresh old, and AutonullCmd or a stop condition
    /// starts a search unasked, §6.4.4), and aborting a search that does
    /// not run is harmless. What a motor does after `$2B` is not stated
    /// either (it might resume its previous action, as a search that ends
    /// does), so `$25` v=0 goes to every motor once more. 18 frames, about
    /// 85 ms at 19200 Bd; the first six stop every motor not searching.
    fn emergency_stop(&self, address: u8) -> Vec<PreparedLine> {
        let motors = 0..i64::from(MOTORS);
        let stop = |m| self.line("ConstantRotation", &[m, 0], address);
        let abort = |m| self.line("AbortReferenceSearch", &[m], address);
        motors
            .clone()
            .filter_map(stop)
            .chain(motors.clone().filter_map(abort))
            .chain(motors.filter_map(stop))
            .collect()
    }

    /// `$43`: firmware revision, reset flag, temperature, serial number.
    /// Reading it clears the reset flag (§7.4), which the reading shows.
    fn identify(&self, address: u8) -> PreparedLine {
        let request = Request {
            address,
            command: 0x43,
            params: [0; 7],
        };
        self.prepare_request(request)
    }

    /// Per motor `$20` (position, action, stop flag) and `$21` (velocity,
    /// action), fast; and one `$30`, whose P4 carries the reference inputs
    /// of all six motors (§7.3), slow. At 19200 Bd an exchange is 17 bytes
    /// plus the 6 ms switch-over delay, about 15 ms, so the twelve fast
    /// queries refresh all six motors at most 5.6 times a second (5.3 to
    /// 5.5 measured against the served simulator).
    fn status_queries(&self, address: u8) -> Vec<StatusPoll> {
        let mut polls = Vec::new();
        for mnemonic in ["GetPositionAndActivity", "GetVelocityAndActivity"] {
            for (axis, info) in AXES.iter().enumerate() {
                if let Some(line) = self.line(mnemonic, &[i64::from(info.number), 0], address) {
                    polls.push(StatusPoll {
                        axis,
                        line,
                        fast: true,
                    });
                }
            }
        }
        // One `$30` per motor channel: its A_In, which against the `$31`
        // limits is the stop switches (§7.3), and every reference input.
        // Slow items: the fast round stays 12 exchanges; a slow round adds
        // six of 17 bytes (102 bytes, about 89 ms at 19200 Bd with the
        // 6 ms switch-over each) where it had one.
        for (axis, info) in AXES.iter().enumerate() {
            if let Some(line) = self.line("GetInputValues", &[i64::from(info.number), 0], address) {
                polls.push(StatusPoll {
                    axis,
                    line,
                    fast: false,
                });
            }
        }
        polls
    }

    /// `$20`'s posact; a motor in a reference search (action 20-29) or a
    /// mechanical reference (30) may be given a new zero by it.
    fn position_read(&self, line: &PreparedLine, value: &ReplyValue) -> Option<PositionRead> {
        let command = request_of(line).and_then(|r| Command::from_request(&r).ok().flatten())?;
        if command.spec.code != 0x20 {
            return None;
        }
        let axis = usize::from(command.motor()?);
        let ReplyValue::Text(text) = value else {
            return None;
        };
        let values = ReplyFields::parse_value(command.spec, text)?;
        let get = |name: &str| values.iter().find(|(n, _)| *n == name).map(|(_, v)| *v);
        let position = get("posact")?;
        let may_jump = get("action").is_some_and(|code| (20..=30).contains(&code));
        Some(PositionRead {
            axis,
            position,
            may_jump,
        })
    }

    /// §6.3.1's step-frequency law `f_µstep = 20 MHz / (clkdiv+1) · |v|
    /// / 2^(14+div)` at its most (clkdiv 0, div 0, v 511): about 624 kHz,
    /// whatever the settings. The manual's 200 kHz is a limit the user
    /// must keep, not one the module enforces; posact counts microsteps.
    fn top_speed(&self) -> Option<TopSpeed> {
        Some(TopSpeed {
            per_second: 20e6 * 511.0 / f64::from(1u32 << 14),
            source: "SIXpack 2 manual §6.3.1 at clkdiv 0, div 0, v 511",
        })
    }

    fn status_update(&self, line: &PreparedLine, reading: &Reading) -> Vec<(usize, AxisUpdate)> {
        let Some(command) = request_of(line).and_then(|r| Command::from_request(&r).ok().flatten())
        else {
            return Vec::new();
        };
        let axis = command.motor().map(usize::from);
        let code = command.spec.code;
        // Lines that set what the gauges show, taking effect at once
        // (§7.1 $14: "promptly reacts"; §7.2 $24, $26). `$23` is left
        // out: it does nothing while the motor is active (§7.2).
        match (code, axis) {
            (0x14, Some(axis)) => {
                return command
                    .value("vmax")
                    .map(|v| (axis, AxisUpdate::MaxSpeed(v)))
                    .into_iter()
                    .collect();
            }
            (0x24 | 0x26, Some(axis)) => {
                return command
                    .value("target")
                    .map(|t| (axis, AxisUpdate::Target(t)))
                    .into_iter()
                    .collect();
            }
            _ => {}
        }
        let ReplyValue::Text(text) = &reading.value else {
            return Vec::new();
        };
        let Some(values) = ReplyFields::parse_value(command.spec, text) else {
            return Vec::new();
        };
        let get = |name: &str| values.iter().find(|(n, _)| *n == name).map(|(_, v)| *v);
        let mut updates = Vec::new();
        match (code, axis) {
            (0x20, Some(axis)) => {
                updates.extend(get("posact").map(|p| (axis, AxisUpdate::Position(p))));
                updates.extend(action_updates(axis, get("action")));
                if let Some(stop) = get("stop") {
                    let flags = if stop == 1 {
                        vec![STOP_FLAG]
                    } else {
                        Vec::new()
                    };
                    updates.push((axis, AxisUpdate::Errors(flags)));
                }
            }
            (0x21, Some(axis)) => {
                updates.extend(get("vact").map(|v| (axis, AxisUpdate::Speed(v))));
                updates.extend(action_updates(axis, get("action")));
            }
            (0x28, _) => {
                for (axis, name) in ["m0", "m1", "m2", "m3", "m4", "m5"].iter().enumerate() {
                    updates.extend(action_updates(axis, get(name)));
                }
            }
            // The reference inputs of all six motors, as read: "the
            // reference inputs are inverted" (§7.3), so 1 is a switch
            // pulling its input low, the active state of the factory
            // setting NullPositive = 0 (§6.4.2).
            (0x30, _) => {
                if let Some(refs) = get("refs") {
                    for axis in 0..AXES.len() {
                        updates.push((
                            axis,
                            AxisUpdate::Switch(SwitchKind::Home, refs & (1 << axis) != 0),
                        ));
                    }
                }
            }
            _ => {}
        }
        updates
    }

    /// The `$30` bits are the reference inputs' levels inverted (§7.3);
    /// which level is the active one is the motor's NullPositive flag
    /// (§6.4.2, factory 0: low). Where the session wrote the flags this
    /// session, a set NullPositive makes a 0 bit the active state.
    fn status_update_known(
        &self,
        line: &PreparedLine,
        reading: &Reading,
        known: &SettingsCache,
    ) -> Vec<(usize, AxisUpdate)> {
        let mut updates = self.status_update(line, reading);
        for (axis, update) in &mut updates {
            if let AxisUpdate::Switch(SwitchKind::Home, active) = update
                && null_positive(known, *axis)
            {
                *active = !*active;
            }
        }
        updates.extend(stop_switches(line, reading, known));
        updates
    }

    fn complete(&self, line: &str, cursor: usize) -> Completions {
        super::assist::complete(line, cursor)
    }

    fn help(&self, line: &str, cursor: usize) -> Vec<String> {
        super::assist::help(line, cursor)
    }

    /// `ConstantRotation m 0`: decelerates the motor with amax from a
    /// ramp, a rotation or PI control alike, without the overshoot and
    /// return of `StopMotors` (§7.2).
    fn stop_axis_line(&self, axis: u8) -> Option<String> {
        (axis < MOTORS).then(|| format!("ConstantRotation {axis} 0"))
    }

    fn lamps(&self) -> &'static [AxisFlag] {
        &ACTION_LAMPS
    }

    fn units(&self) -> Option<&'static dyn crate::protocol::units::UnitLaw> {
        Some(&super::units::Sixpack2Units)
    }

    fn parameters(&self) -> Option<&'static dyn ParameterSet> {
        Some(&super::parameter_set::Sixpack2Parameters)
    }

    /// SQPack macro files, played from the host (§5.4.6, digest D8).
    fn jog(&self) -> Option<&'static dyn crate::protocol::jog::JogPlan> {
        Some(&super::jog::Sixpack2Jog)
    }

    fn io(&self) -> Option<&'static dyn crate::protocol::io::IoPlan> {
        Some(&super::io::Sixpack2Io)
    }

    fn program(&self) -> Option<&'static dyn ProgramTool> {
        Some(&super::tool::MacroTool)
    }

    fn describe_request(&self, bytes: &[u8]) -> Option<String> {
        Some(super::traffic::describe_request(bytes))
    }

    fn describe_reply(&self, bytes: &[u8], request: Option<&[u8]>) -> Option<String> {
        Some(super::traffic::describe_reply(bytes, request, self.framing))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::wire::Verdict;

    const CONSOLE: Sixpack2Console = Sixpack2Console::AUTO;

    #[test]
    fn a_second_read_shows_the_flags_the_first_cleared_as_it_left_them() {
        let pos = prepare("GetPositionAndActivity 0");
        let first = ReplyValue::Text("posact=9 action=inactive stop=1".into());
        let second = ReplyValue::Text("posact=9 action=inactive stop=0".into());
        assert_eq!(CONSOLE.as_if_unread(&pos, &first, &second), first);
        let moved = ReplyValue::Text("posact=12 action=inactive stop=0".into());
        assert_eq!(
            CONSOLE.as_if_unread(&pos, &first, &moved).to_string(),
            "posact=12 action=inactive stop=1"
        );
    }

    fn prepare(line: &str) -> PreparedLine {
        CONSOLE
            .prepare(line, 0)
            .unwrap_or_else(|e| panic!("{line}: {e}"))
    }

    fn reply(line: &PreparedLine, frame: &[u8]) -> Result<Reading, ReplyError> {
        CONSOLE.interpret(line, &[frame.to_vec()])
    }

    fn updates_of(line: &str, frame: &[u8]) -> Vec<(usize, AxisUpdate)> {
        let line = prepare(line);
        let reading = reply(&line, frame).expect("a reading");
        CONSOLE.status_update(&line, &reading)
    }

    /// §5.5.2.2, §7.3: A_In below `$31`'s MinLeft is the left stop
    /// switch, above MaxRight the right one; limits not written this
    /// session are not known (`$31` cannot be read back) and give nothing.
    #[test]
    fn a_30_of_a_motor_channel_reads_its_stop_switches_against_the_written_31() {
        let line = prepare("GetInputValues 2");
        // Channel 2, A_In 1000 ($03E8), no reference inputs.
        let reading = reply(&line, &[0x30, 2, 0xE8, 0x03, 0, 0, 0, 0]).expect("a reading");
        let switches = |known: &SettingsCache| -> Vec<(usize, AxisUpdate)> {
            CONSOLE
                .status_update_known(&line, &reading, known)
                .into_iter()
                .filter(|(_, u)| {
                    matches!(
                        u,
                        AxisUpdate::Switch(SwitchKind::Left | SwitchKind::Right, _)
                    )
                })
                .collect()
        };
        let mut known = SettingsCache::default();
        assert_eq!(switches(&known), [], "nothing written: not known");
        let written = CONSOLE.settings_written(&prepare("SetStopSwitchLimits 2 100 900"));
        known.record(&written);
        assert_eq!(
            switches(&known),
            [
                (2, AxisUpdate::Switch(SwitchKind::Left, false)),
                (2, AxisUpdate::Switch(SwitchKind::Right, true)),
            ]
        );
        // MaxRight 1023: no function (§7.3); MinLeft 0 too.
        known.record(&CONSOLE.settings_written(&prepare("SetStopSwitchLimits 2 0 1023")));
        assert_eq!(
            switches(&known),
            [
                (2, AxisUpdate::Switch(SwitchKind::Left, false)),
                (2, AxisUpdate::Switch(SwitchKind::Right, false)),
            ]
        );
        // Another motor's limits do not count for channel 2.
        let mut other = SettingsCache::default();
        other.record(&CONSOLE.settings_written(&prepare("SetStopSwitchLimits 1 100 900")));
        assert_eq!(switches(&other), []);
    }

    fn canonicals(lines: &[PreparedLine]) -> Vec<String> {
        lines.iter().map(|l| l.canonical.clone()).collect()
    }

    #[test]
    fn settings_and_motions_are_never_answered_and_read_as_sent() {
        for text in [
            "StartRamp 0 10000",
            "SetAMaxVMax 0 200 400",
            "SetMotorParameters 0 10000 NullLeft,MechRef",
            "HardwareReset",
            "SendToPack($00, $1A, $00, $20, $00, $00, $00, $00, $00)",
        ] {
            let line = prepare(text);
            assert!(matches!(line.answering, Answering::Nothing), "{text}");
            assert_eq!(line.effect, Effect::Acts, "{text}");
            let reading = CONSOLE.interpret(&line, &[]).expect("nothing to wait for");
            assert_eq!(reading.value, ReplyValue::Text("sent".into()), "{text}");
        }
    }

    #[test]
    fn only_queries_and_service_commands_answer() {
        for text in [
            "GetPositionAndActivity 0",
            "GetVelocityAndActivity 5",
            "GetAllActivities",
            "GetInputValues 7",
            "GetUnitInformation",
        ] {
            let line = prepare(text);
            assert!(matches!(line.answering, Answering::Reply(_)), "{text}");
            assert_eq!(line.effect, Effect::Reads, "{text}");
            assert!(
                CONSOLE.interpret(&line, &[]).is_err(),
                "{text}: no reply is an error"
            );
        }
        for text in [
            "FlashChecksum",
            "FlashRead",
            "EepromWrite 0 0 0 0",
            "ConfigRS232ViaCAN",
        ] {
            let line = prepare(text);
            assert!(matches!(line.answering, Answering::Reply(_)), "{text}");
            assert_eq!(
                line.effect,
                Effect::Acts,
                "{text}: a service command is never repeated"
            );
        }
        let waiting = prepare("GetAllActivities 0 0,1");
        assert!(matches!(
            waiting.answering,
            Answering::Later {
                within: IDLE_WAIT,
                ..
            }
        ));
        assert_eq!(
            waiting.effect,
            Effect::Acts,
            "a delayed $28 is never asked twice"
        );
    }

    #[test]
    fn lines_are_framed_for_the_unit_and_refused_with_the_operand_named() {
        let line = CONSOLE.prepare("StartRamp 0 10000", 5).expect("valid");
        assert_eq!(to_hex(&line.bytes), "05 23 00 10 27 00 00 00 00");
        assert_eq!(line.address, 5);
        assert_eq!(line.canonical, "StartRamp 0 10000");
        let error = CONSOLE
            .prepare("StartRamp 6 100", 0)
            .unwrap_err()
            .to_string();
        assert_eq!(error, "StartRamp: motno 6 is outside 0..5 (Motor 1..6)");
        let error = CONSOLE
            .prepare("SendToPack($03, $22, $00, $00, $00, $00, $00, $00, $00)", 0)
            .unwrap_err()
            .to_string();
        assert!(error.contains("unit 3"), "{error}");
        assert_eq!(
            prepare("SendToPack($00, $22, $00, $00, $00, $00, $00, $00, $00)").canonical,
            "StartReferenceSearch 0"
        );
    }

    #[test]
    fn replies_read_as_their_fields() {
        let pos = prepare("GetPositionAndActivity 2");
        let reading = reply(&pos, &[0x20, 2, 0x10, 0x27, 0, 0, 5, 0]).expect("answer");
        assert_eq!(
            reading.value,
            ReplyValue::Text("posact=10000 action=ramp stop=0".into())
        );
        assert_eq!(reading.status, None);
        // The address form is read as well (Auto).
        let reading = reply(&pos, &[0, 0x20, 2, 0xFF, 0xFF, 0xFF, 0xFF, 0, 1]).expect("answer");
        assert_eq!(
            reading.value,
            ReplyValue::Text("posact=-1 action=inactive stop=1".into())
        );
        let unit = prepare("GetUnitInformation");
        let reading = reply(&unit, &[0x43, 148, 1, 25, 0x39, 0x30, 0, 0]).expect("answer");
        assert_eq!(
            reading.value.to_string(),
            "firmware=148 reset=1 temperature=25 serial=12345"
        );
    }

    /// Issue 19: with no checksum (§7.1), a corrupted reply is caught only
    /// by a value no SIXpack 2 sends: an action code §7.2 does not list.
    #[test]
    fn an_action_code_the_manual_does_not_list_is_a_damaged_reply() {
        let pos = prepare("GetPositionAndActivity 2");
        let error = reply(&pos, &[0x20, 2, 0x10, 0x27, 0, 0, 7, 0]).unwrap_err();
        assert!(
            error
                .to_string()
                .contains("action 7 is no action code of §7.2"),
            "{error}"
        );
        assert!(
            reply(&pos, &[0x20, 2, 0x10, 0x27, 0, 0, 23, 0]).is_ok(),
            "a search"
        );
        let all = prepare("GetAllActivities");
        assert!(reply(&all, &[0x28, 0, 5, 10, 15, 30, 0, 0]).is_ok());
        assert!(reply(&all, &[0x28, 0, 5, 10, 15, 31, 0, 0]).is_err());
    }

    #[test]
    fn a_malformed_or_mismatched_reply_names_its_bytes() {
        let pos = prepare("GetPositionAndActivity 2");
        let error = reply(&pos, &[0x20, 3, 0, 0, 0, 0, 0, 0]).unwrap_err();
        assert_eq!(
            error.to_string(),
            "unreadable answer to GetPositionAndActivity 2: got 20 03 00 00 00 00 00 00: it is \
             for motno 3, not 2"
        );
        let error = reply(&pos, &[0x21, 2, 0, 0, 0, 0, 0, 0]).unwrap_err();
        assert!(
            error.to_string().contains("echoes command $21, not $20"),
            "{error}"
        );
        let error = reply(&pos, &[0x20, 2, 0]).unwrap_err();
        assert!(
            error.to_string().contains("got 20 02 00: 3 bytes"),
            "{error}"
        );
        let error = reply(&pos, &[0x05, 0x20, 2, 0, 0, 0, 0, 0, 0]).unwrap_err();
        assert!(error.to_string().contains("address byte $05"), "{error}");
        assert!(matches!(error, ReplyError::Malformed { .. }));
        let strict = Sixpack2Console {
            framing: ReplyFraming::Cmd8,
        };
        let line = strict
            .prepare("GetPositionAndActivity 2", 0)
            .expect("valid");
        assert!(
            strict
                .interpret(&line, &[vec![0, 0x20, 2, 0, 0, 0, 0, 0, 0]])
                .is_err()
        );
    }

    #[test]
    fn the_reply_rule_takes_only_this_querys_answer() {
        let Answering::Reply(rule) = prepare("GetVelocityAndActivity 1").answering else {
            panic!("a query expects a reply")
        };
        assert_eq!(
            rule.examine(&[], &[0x21, 1, 0, 0, 0, 0, 0, 0]),
            Verdict::Complete
        );
        assert_eq!(
            rule.examine(&[], &[0x21, 2, 0, 0, 0, 0, 0, 0]),
            Verdict::NotMine
        );
        assert_eq!(
            rule.examine(&[], &[0x28, 0, 0, 0, 0, 0, 0, 0]),
            Verdict::NotMine
        );
    }

    #[test]
    fn emergency_stop_rotates_every_motor_to_zero_aborts_searches_and_stops_again() {
        let lines = CONSOLE.emergency_stop(4);
        let names = canonicals(&lines);
        let mut expected: Vec<String> = (0..6).map(|m| format!("ConstantRotation {m} 0")).collect();
        expected.extend((0..6).map(|m| format!("AbortReferenceSearch {m}")));
        expected.extend((0..6).map(|m| format!("ConstantRotation {m} 0")));
        assert_eq!(names, expected);
        assert_eq!(to_hex(&lines[0].bytes), "04 25 00 00 00 00 00 00 00");
        assert_eq!(to_hex(&lines[6].bytes), "04 2B 00 00 00 00 00 00 00");
        assert!(
            lines
                .iter()
                .all(|l| matches!(l.answering, Answering::Nothing))
        );
        assert!(lines.iter().all(|l| CONSOLE.confirmation(l).is_none()));
    }

    #[test]
    fn status_reads_every_motor_fast_and_each_motors_inputs_slow() {
        let polls = CONSOLE.status_queries(0);
        let names: Vec<&str> = polls.iter().map(|p| p.line.canonical.as_str()).collect();
        assert_eq!(names.len(), 18);
        assert_eq!(names[0], "GetPositionAndActivity 0");
        assert_eq!(names[6], "GetVelocityAndActivity 0");
        assert_eq!(names[12], "GetInputValues 0");
        assert_eq!(names[17], "GetInputValues 5");
        let inputs: Vec<usize> = polls.iter().skip(12).map(|p| p.axis).collect();
        assert_eq!(inputs, [0, 1, 2, 3, 4, 5], "each motor's A_In");
        assert!(polls.iter().skip(12).all(|p| !p.fast), "slow items");
        assert!(polls.iter().all(|p| p.line.effect == Effect::Reads));
        assert_eq!(polls.iter().filter(|p| p.fast).count(), 12);
        let axes: Vec<usize> = polls.iter().take(6).map(|p| p.axis).collect();
        assert_eq!(axes, [0, 1, 2, 3, 4, 5]);
        // Six motors at 19200 Bd: 12 exchanges of 17 bytes (10 bits each)
        // plus the 6 ms switch-over delay.
        let exchange = 17.0 * 10.0 / 19200.0 + 0.006;
        let refreshes = 1.0 / (12.0 * exchange);
        assert!((5.0..6.0).contains(&refreshes), "{refreshes}");
    }

    #[test]
    fn position_polls_show_position_action_and_the_latched_stop_flag() {
        let updates = updates_of(
            "GetPositionAndActivity 3",
            &[0x20, 3, 0x10, 0x27, 0, 0, 23, 1],
        );
        assert_eq!(
            updates,
            [
                (3, AxisUpdate::Position(10_000)),
                (
                    3,
                    AxisUpdate::DriverFlags(vec![AxisFlag {
                        name: "ref search",
                        description: ACTIONS[4].meaning
                    }])
                ),
                (3, AxisUpdate::Errors(vec![STOP_FLAG])),
            ]
        );
        let idle = updates_of("GetPositionAndActivity 0", &[0x20, 0, 0, 0, 0, 0, 0, 0]);
        assert!(idle.contains(&(0, AxisUpdate::DriverFlags(Vec::new()))));
        assert!(idle.contains(&(0, AxisUpdate::Errors(Vec::new()))));
        let speed = updates_of(
            "GetVelocityAndActivity 1",
            &[0x21, 1, 0x01, 0xFE, 15, 0, 0, 0],
        );
        assert_eq!(speed[0], (1, AxisUpdate::Speed(-511)));
        let AxisUpdate::DriverFlags(lit) = &speed[1].1 else {
            panic!("{speed:?}")
        };
        assert_eq!(lit[0].name, "rotation");
    }

    #[test]
    fn reference_inputs_of_all_motors_come_from_one_30() {
        let updates = updates_of("GetInputValues 0", &[0x30, 0, 0, 0, 1, 0b0010_0001, 0, 0]);
        assert_eq!(updates.len(), 6);
        assert_eq!(updates[0], (0, AxisUpdate::Switch(SwitchKind::Home, true)));
        assert_eq!(updates[1], (1, AxisUpdate::Switch(SwitchKind::Home, false)));
        assert_eq!(updates[5], (5, AxisUpdate::Switch(SwitchKind::Home, true)));
        let all = updates_of("GetAllActivities", &[0x28, 0, 5, 0, 0, 30, 0, 0]);
        assert_eq!(all.len(), 6);
        let AxisUpdate::DriverFlags(lit) = &all[4].1 else {
            panic!("{all:?}")
        };
        assert_eq!(lit[0].name, "mech ref");
    }

    #[test]
    fn what_the_user_sets_shows_at_once_but_a_ramp_target_does_not() {
        let sent = |text: &str| {
            let line = prepare(text);
            let reading = CONSOLE.interpret(&line, &[]).expect("sent");
            CONSOLE.status_update(&line, &reading)
        };
        assert_eq!(
            sent("SetAMaxVMax 2 100 300"),
            [(2, AxisUpdate::MaxSpeed(300))]
        );
        assert_eq!(
            sent("SetTargetPosition 1 -50"),
            [(1, AxisUpdate::Target(-50))]
        );
        assert_eq!(sent("StartPIControl 0 7"), [(0, AxisUpdate::Target(7))]);
        assert!(
            sent("StartRamp 0 100").is_empty(),
            "ignored while the motor is active"
        );
    }

    #[test]
    fn lamps_stop_key_identity_and_cautions() {
        let names: Vec<&str> = CONSOLE.lamps().iter().map(|f| f.name).collect();
        assert_eq!(names, ["ramp", "PI", "rotation", "ref search", "mech ref"]);
        assert_eq!(
            CONSOLE.stop_axis_line(5).as_deref(),
            Some("ConstantRotation 5 0")
        );
        assert_eq!(CONSOLE.stop_axis_line(6), None);
        assert!(CONSOLE.prepare("ConstantRotation 5 0", 0).is_ok());
        assert_eq!(CONSOLE.clear_errors_line(0), None);
        let identity = CONSOLE.identify(2);
        assert_eq!(to_hex(&identity.bytes), "02 43 00 00 00 00 00 00 00");
        assert_eq!(identity.effect, Effect::Reads);
        assert_eq!(
            (CONSOLE.default_address(), CONSOLE.default_baud()),
            (0, 19200)
        );
        assert_eq!(CONSOLE.axes().len(), 6);
        assert!(CONSOLE.confirmation(&prepare("HardwareReset")).is_some());
        assert!(CONSOLE.confirmation(&prepare("StartRamp 0 1")).is_none());
        let nothing = SettingsCache::default();
        assert_eq!(
            CONSOLE
                .warnings(&prepare("SetPeakCurrent 1 10"), &nothing)
                .len(),
            1
        );
    }
}
