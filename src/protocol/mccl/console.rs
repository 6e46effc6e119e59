//! The MCCL controller as the session layer sees it ([`FamilyConsole`]):
//! a line parsed, checked and sent with its CR; its answer recognised by
//! the echo and the prompt and read against the line; the emergency stop;
//! the status of each axis from `TP`, `TV`, `TS`, `TT` and `TF`.
//!
//! Lines are written and checked as the manual writes them, in decimal;
//! what the interface is set to ([`MclContext`]: the profile the connect
//! probe learned, `DM`/`HM`, `PC`, `EN`/`EF`) is the session's per-link
//! state ([`LinkContexts`]): each line is encoded for it when sent (after
//! `HM` its integers in hexadecimal, so that a line, a file and the
//! parameter table mean the same in either mode) and its answer read in
//! it. Lines that may run for long are marked [`LongRunning`] (Escape
//! aborts, Space pauses).

use std::any::Any;
use std::sync::{Arc, LazyLock};

use super::catalog::{Blocks, Output};
use super::check::{CheckContext, Diagnostic, Severity, check_line};
use super::line::{Line, NumberBase, ParseErrors, parse_line};
use super::machine::{AxisKind, DEFAULT_MACHINE, Machine};
use super::parameter_set::MclParameters;
use super::profile::{Echo, LinkProfile, LinkState, PromptPer};
use super::reply::{AnswerRule, Printed, Reply, Report, read_reply, runs_straight};
use super::status::{BitClass, PRIMARY, StatusBit, StatusSelector, StatusWord, StatusWordKind};
use super::tool::MacroStore;
use super::wire::MclWire;
use crate::protocol::console::{
    Answering, AxisFlag, AxisInfo, AxisUpdate, Completions, Effect, FamilyConsole, LinkContext,
    LinkContexts, LongRunning, PreparedLine, ProbeError, Reading, ReplyError, ReplyValue,
    RunningPrograms, StatusPoll, StatusValue, SwitchKind,
};
use crate::protocol::line_error::{FamilyLineError, LineError, Mistake};
use crate::protocol::parameters::ParameterSet;
use crate::protocol::program::ProgramStore;
use crate::protocol::wire::{Frame, WireFormat};

/// The ASCII interface is point to point: there is no bus address, and the
/// console calls the controller 0.
pub const ADDRESS: u8 = 0;

/// The most axes one status line reads. Each exchange leaves the answer
/// direction idle for the byte the echo trails the request by and the
/// host's turn, so one line for the whole round comes nearer the wire's
/// rate (`bench/mccl_refresh.py`, five axes at 9600 Bd: 92 % with a line
/// per axis, 94 % with two lines, 96 % with one). The manual gives no
/// longest line (Ch14 error 4 "Command string to long" has no number);
/// six axes' `aTP,TV,TS` are 59 characters, within the 60 of its own
/// `MD1,1SV50000,1SA100000,1DS100000,1LM2,1LN3,1VM,1DI0,1GO,MJ10` (Ch7
/// IA).
/// More axes are shared evenly over the fewest lines. A line of five
/// axes answers in about 150 ms at 9600 Bd: a user's line waits for at
/// most that poll on the wire, a stop does not (Escape cuts it short,
/// [`FamilyConsole::cut_short`]).
pub const STATUS_LINE_AXES: usize = 6;

/// How the emergency stop stops the axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopMotion {
    /// `0AB`: "serves as an emergency stop", abrupt, PID and amplifier stay
    /// on (Ch7 AB).
    Abort,
    /// `0ST`: decelerate at DS (Ch7 ST).
    Decelerate,
}

/// The console for one kind of MultiFlex setup.
#[derive(Debug, Clone, Copy)]
pub struct MclConsole {
    pub profile: LinkProfile,
    pub machine: Machine,
    pub stop: StopMotion,
    /// Background task IDs the emergency stop ends with `ET`. Task IDs are
    /// whatever `GT` put in the accumulator (Ch4; their values are not
    /// stated), so it ends each of these; an ID no task has is answered
    /// −20 and read as "not running".
    pub tasks: &'static [i64],
    /// The settings table, for the same machine.
    pub parameters: &'static MclParameters,
}

/// The settings of the default machine.
pub static DEFAULT_PARAMETERS: MclParameters = MclParameters {
    machine: DEFAULT_MACHINE,
};

/// Task IDs 1–21: as many as the controller runs tasks (Ch4: "The maximum
/// number of background tasks is 21"), numbered from 1 [?].
const FIRST_TASK_IDS: &[i64] = &[
    1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21,
];

impl MclConsole {
    /// The manual's interface, the examples' machine (axes 1–4 servo, 5
    /// stepper), an abort as the emergency stop.
    pub const DEFAULT: MclConsole = MclConsole {
        profile: LinkProfile::MANUAL,
        machine: DEFAULT_MACHINE,
        stop: StopMotion::Abort,
        tasks: FIRST_TASK_IDS,
        parameters: &DEFAULT_PARAMETERS,
    };

    fn context(&self) -> CheckContext<'_> {
        CheckContext {
            machine: &self.machine,
            profile: &self.profile,
        }
    }

    /// The interface after power-up, as this console's profile says.
    pub fn power_up(&self) -> MclContext {
        MclContext {
            profile: self.profile,
            state: LinkState::new(&self.profile),
        }
    }

    /// The MCCL state in `context` (the power-up one if it is another
    /// family's, which a session never hands over).
    fn mccl_context(&self, context: &dyn LinkContext) -> MclContext {
        context
            .as_any()
            .downcast_ref::<MclContext>()
            .copied()
            .unwrap_or_else(|| self.power_up())
    }

    /// A parsed line, ready to send to an interface after power-up.
    pub fn prepare_line(&self, line: &Line) -> PreparedLine {
        self.prepare_line_in(line, &self.power_up())
    }

    /// A parsed line, ready to send to an interface in `context`: its
    /// canonical text stays decimal (what it means), its bytes are written
    /// in the interface's number base, and its answer is waited for with
    /// the interface's echo and prompt.
    pub fn prepare_line_in(&self, line: &Line, context: &MclContext) -> PreparedLine {
        let canonical = line.to_string();
        let sent = line.written_in(context.state.base);
        let mut bytes = sent.clone().into_bytes();
        bytes.push(context.profile.send_end);
        let rule = AnswerRule::new(line, &sent, &context.profile, &context.state);
        PreparedLine {
            canonical,
            address: ADDRESS,
            bytes,
            answering: Answering::Reply(Arc::new(rule)),
            // Only a line that reads and ends at once may be sent again: a
            // repeating Tell (`1TP,RP`) still runs after a timeout.
            effect: if line
                .commands
                .iter()
                .all(|c| c.spec.only_reads() && c.spec.blocks == Blocks::No)
            {
                Effect::Reads
            } else {
                Effect::Acts
            },
        }
    }

    /// Parse and check `text`, and refuse what this console cannot follow.
    pub fn parse_checked(&self, text: &str) -> Result<Line, Refused> {
        let line = parse_line(text, NumberBase::Decimal).map_err(Refused::Parse)?;
        let errors: Vec<Diagnostic> = check_line(&line, &self.context())
            .into_iter()
            .filter(|d| d.severity == Severity::Error)
            .collect();
        if !errors.is_empty() {
            return Err(Refused::Checks(errors));
        }
        self.refusal(&line).map_or(Ok(line), Err)
    }

    /// Commands the console cannot follow.
    fn refusal(&self, line: &Line) -> Option<Refused> {
        // A macro or a task holds them without running them here.
        if line.defines_macro() || line.is_task() {
            return None;
        }
        line.commands
            .iter()
            .find(|c| c.mnemonic() == "BK" && c.text().is_some())
            .map(|command| Refused::SingleStep {
                command: command.to_string(),
            })
    }

    /// The index into [`MclConsole::axes`] of axis `number`.
    fn axis_index(&self, number: u8) -> Option<usize> {
        self.machine.axes.iter().position(|a| a.number == number)
    }

    /// The line sent, parsed again from its canonical (decimal) text (it
    /// parsed when it was prepared).
    fn line_of(&self, prepared: &PreparedLine) -> Option<Line> {
        parse_line(&prepared.canonical, NumberBase::Decimal).ok()
    }

    /// What the answer to `prepared` means on an interface in `context`.
    fn read_answer(
        &self,
        prepared: &PreparedLine,
        frames: &[Frame],
        context: &MclContext,
    ) -> Result<Reading, ReplyError> {
        let parsed = self
            .line_of(prepared)
            .ok_or_else(|| malformed(prepared, "the line sent does not parse"))?;
        let sent = String::from_utf8_lossy(&prepared.bytes);
        let sent = sent.trim_end_matches(char::from(context.profile.send_end));
        let reply = read_reply(&parsed, sent, &context.state, &context.profile, frames)
            .map_err(|problem| malformed(prepared, problem.to_string()))?;
        if let Some(error) = &reply.error {
            // Ending a task that is not running leaves it not running: the
            // emergency stop ends every task ID it may have (ET, Ch10).
            if let [command] = parsed.commands.as_slice()
                && command.mnemonic() == "ET"
                && error.code == -20
            {
                return Ok(Reading {
                    status: None,
                    value: ReplyValue::Text(format!(
                        "no background task {}: nothing to end ({})",
                        command
                            .value
                            .as_ref()
                            .map_or("0".into(), ToString::to_string),
                        error.text()
                    )),
                });
            }
            return Err(ReplyError::Refused {
                module: "the controller".into(),
                line: prepared.canonical.clone(),
                reply: error.text(),
                meaning: format!("{}, Ch14", error.meaning()),
            });
        }
        Ok(Reading {
            status: None,
            value: value_of(&parsed, &reply),
        })
    }
}

/// What the console knows of one MCCL interface: the profile the connect
/// probe learned (echo, prompt, prompts per line or per command, line
/// ends) and what lines have set since (`DM`/`HM`, `PC`, `EN`/`EF`, reset
/// by `RT`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MclContext {
    pub profile: LinkProfile,
    pub state: LinkState,
}

impl LinkContext for MclContext {
    fn as_any(&self) -> &dyn Any {
        self
    }

    fn summary(&self) -> Option<String> {
        let mut said = Vec::new();
        if self.state.base == NumberBase::Hex {
            said.push("hex (HM)".to_string());
        }
        match self.state.prompt {
            Some(b'>') => {}
            Some(p) => said.push(format!("prompt `{}`", char::from(p))),
            None => said.push("no prompt (PC0)".into()),
        }
        if self.state.echo == Echo::Off {
            said.push("echo off".into());
        }
        if self.profile.prompt_per == PromptPer::Command {
            said.push("prompt per command".into());
        }
        (!said.is_empty()).then(|| said.join(", "))
    }
}

impl LinkContexts for MclConsole {
    fn initial(&self) -> Arc<dyn LinkContext> {
        Arc::new(self.power_up())
    }

    /// `NO`, then `NO,NO,NO` (digest §3.3 step 5): the echo, the prompt,
    /// whether it comes once per line or after every command, the line
    /// ends.
    fn probe(&self) -> Vec<Vec<u8>> {
        [&b"NO"[..], b"NO,NO,NO"]
            .iter()
            .map(|line| {
                let mut bytes = line.to_vec();
                bytes.push(self.profile.send_end);
                bytes
            })
            .collect()
    }

    fn learn(
        &self,
        context: &dyn LinkContext,
        answers: &[Vec<u8>],
    ) -> Result<Arc<dyn LinkContext>, ProbeError> {
        let before = self.mccl_context(context);
        let [single, triple] = answers else {
            return Err(ProbeError::AnswerCount {
                got: answers.len(),
                wanted: 2,
            });
        };
        let learned = LinkProfile::learn(single, triple)?;
        let profile = LinkProfile {
            echo: learned.echo,
            reply_end: learned.reply_end,
            prompt: learned.prompt,
            prompt_per: learned.prompt_per,
            ..before.profile
        };
        Ok(Arc::new(MclContext {
            profile,
            state: LinkState {
                prompt: profile.prompt,
                echo: profile.echo,
                ..before.state
            },
        }))
    }

    fn adapt(&self, line: &PreparedLine, context: &dyn LinkContext) -> PreparedLine {
        match self.line_of(line) {
            Some(parsed) => PreparedLine {
                address: line.address,
                ..self.prepare_line_in(&parsed, &self.mccl_context(context))
            },
            None => line.clone(),
        }
    }

    fn interpret_in(
        &self,
        line: &PreparedLine,
        frames: &[Frame],
        context: &dyn LinkContext,
    ) -> Result<Reading, ReplyError> {
        self.read_answer(line, frames, &self.mccl_context(context))
    }

    fn after(
        &self,
        line: &PreparedLine,
        context: &dyn LinkContext,
    ) -> Option<Arc<dyn LinkContext>> {
        let before = self.mccl_context(context);
        let parsed = self.line_of(line)?;
        let mut state = before.state;
        state.after(&parsed, &before.profile);
        (state != before.state)
            .then(|| Arc::new(MclContext { state, ..before }) as Arc<dyn LinkContext>)
    }
}

fn malformed(line: &PreparedLine, reason: impl Into<String>) -> ReplyError {
    ReplyError::Malformed {
        line: line.canonical.clone(),
        reason: reason.into(),
    }
}

/// Whether `line` reads a motor-table variable (`LU"…"`, a read at `@0`,
/// `TR0`): its value is a real whatever digits it is printed with, so it is
/// given as text for the parameter table to scale.
fn reads_variable(line: &Line) -> bool {
    line.contains("LU") && line.commands.last().is_some_and(|c| c.mnemonic() == "TR")
}

/// What a reply shows: a single integer as a number, anything else as text
/// (values with decimals as printed; several values separated by blanks;
/// text lines by line ends, VE's on one line for the title).
fn value_of(line: &Line, reply: &Reply) -> ReplyValue {
    let text_of = |report: &Report| -> String {
        match &report.printed {
            Printed::Value(told) => told.value.to_string(),
            Printed::Text(lines) => {
                let is_version = report
                    .command
                    .and_then(|i| line.commands.get(i))
                    .is_some_and(|c| c.mnemonic() == "VE");
                lines.join(if is_version { " · " } else { "\n" })
            }
        }
    };
    match reply.reports.as_slice() {
        [] => ReplyValue::None,
        [
            Report {
                printed: Printed::Value(told),
                ..
            },
        ] if !reads_variable(line) => match told.value {
            super::reply::Quantity::Integer(n) => ReplyValue::Number(n),
            _ => ReplyValue::Text(told.value.to_string()),
        },
        reports => {
            let any_text = reports
                .iter()
                .any(|r| matches!(r.printed, Printed::Text(_)));
            let parts: Vec<String> = reports.iter().map(text_of).collect();
            ReplyValue::Text(parts.join(if any_text { "\n" } else { " " }))
        }
    }
}

/// The lamp of TS bit 1, "motor on" (Ch8).
pub const MOTOR_ON_LAMP: &str = "motor";

/// Primary status bits shown as lamps, with names short enough for an
/// axis card (Ch8 TS): the states that are not a switch lamp (the limit
/// inputs; the home input: a servo's coarse home, a stepper's home), the
/// reached lamp or an error flag of their own. The auxiliary encoder bits
/// (19, 20, 26) are left to `TS`.
const LAMP_BITS: &[(u8, &str)] = &[
    (1, MOTOR_ON_LAMP),
    (21, "homed"),
    (17, "seek"),
    (18, "found"),
    (5, "capt"),
    (6, "brkpt"),
    (27, "fault"),
];

fn flag(bit: &'static StatusBit) -> AxisFlag {
    AxisFlag {
        name: bit.name,
        description: bit.meaning,
    }
}

/// The lamp of primary bit `bit`.
fn lamp_of(bit: &'static StatusBit) -> Option<AxisFlag> {
    LAMP_BITS
        .iter()
        .find(|(b, _)| *b == bit.bit)
        .map(|(_, name)| AxisFlag {
            name,
            description: bit.meaning,
        })
}

static LAMPS: LazyLock<Vec<AxisFlag>> = LazyLock::new(|| {
    LAMP_BITS
        .iter()
        .filter_map(|(bit, _)| PRIMARY.iter().find(|b| b.bit == *bit))
        .filter_map(lamp_of)
        .collect()
});

/// The primary status word of an axis as updates: its limit and home
/// inputs as switches (home: the coarse home input of a servo, the home
/// input of a stepper, Ch8 TS bits 24/25), at target as reached, the
/// latched faults as errors, the rest as lamps.
fn primary_updates(axis: usize, kind: Option<AxisKind>, value: u32) -> Vec<(usize, AxisUpdate)> {
    let word = StatusWord::new(StatusWordKind::Primary, value);
    let home_bit = match kind {
        Some(AxisKind::Servo) => 25,
        _ => 24,
    };
    let errors: Vec<AxisFlag> = word
        .set_bits()
        .filter(|b| b.class == BitClass::Error)
        .map(flag)
        .collect();
    let lamps: Vec<AxisFlag> = word.set_bits().filter_map(lamp_of).collect();
    vec![
        (axis, AxisUpdate::Switch(SwitchKind::Right, word.is_set(28))),
        (axis, AxisUpdate::Switch(SwitchKind::Left, word.is_set(29))),
        (
            axis,
            AxisUpdate::Switch(SwitchKind::Home, word.is_set(home_bit)),
        ),
        (axis, AxisUpdate::Reached(word.is_set(2))),
        (axis, AxisUpdate::Errors(errors)),
        (axis, AxisUpdate::DriverFlags(lamps)),
    ]
}

impl FamilyConsole for MclConsole {
    /// TP, TT, TV and TF (Ch8); MCCL has no load reading.
    fn status_values(&self) -> &'static [StatusValue] {
        &[
            StatusValue::Position,
            StatusValue::Target,
            StatusValue::Speed,
            StatusValue::FollowingError,
        ]
    }

    fn wire(&self) -> Arc<dyn WireFormat> {
        Arc::new(MclWire::new(&self.profile))
    }

    fn default_address(&self) -> u8 {
        ADDRESS
    }

    fn addresses(&self) -> std::ops::RangeInclusive<u8> {
        ADDRESS..=ADDRESS
    }

    fn axes(&self) -> &'static [AxisInfo] {
        self.machine.axes
    }

    fn prepare(&self, line: &str, address: u8) -> Result<PreparedLine, LineError> {
        if address != ADDRESS {
            return Err(Refused::BusAddress(address).into());
        }
        let line = self.parse_checked(line)?;
        Ok(self.prepare_line(&line))
    }

    fn long_running(&self, line: &PreparedLine) -> Option<LongRunning> {
        let parsed = self.line_of(line)?;
        let blocks = !parsed.defines_macro()
            && !parsed.is_task()
            && parsed.commands.iter().any(|c| c.spec.blocks != Blocks::No);
        blocks.then(|| LongRunning {
            abort: vec![self.profile.abort],
            pause: Some(vec![self.profile.pause]),
        })
    }

    /// Escape aborts the line the controller is running (Ch2): a status
    /// line of every axis takes about 150 ms at 9600 Bd, which a stop must
    /// not wait for. A Tell line has nothing to undo.
    fn cut_short(&self, line: &PreparedLine) -> Option<Vec<u8>> {
        let _ = line;
        Some(vec![self.profile.abort])
    }

    fn link_contexts(&self) -> Option<&dyn LinkContexts> {
        Some(self)
    }

    fn interpret(&self, line: &PreparedLine, frames: &[Frame]) -> Result<Reading, ReplyError> {
        self.read_answer(line, frames, &self.power_up())
    }

    fn emergency_stop(&self, address: u8) -> Vec<PreparedLine> {
        self.emergency_stop_knowing(address, &RunningPrograms::Unknown)
    }

    fn emergency_stop_knowing(&self, _address: u8, running: &RunningPrograms) -> Vec<PreparedLine> {
        // Escape first aborts a line running in the foreground: that is the
        // device layer's, through the abort byte of the line's
        // `long_running`. Then every axis, then every task that could
        // start motion again: those known to run, every ID a task may have
        // when that cannot be known.
        let stop = match self.stop {
            StopMotion::Abort => "0AB",
            StopMotion::Decelerate => "0ST",
        };
        let tasks: &[i64] = match running {
            RunningPrograms::Known(ids) => ids,
            RunningPrograms::Unknown => self.tasks,
        };
        std::iter::once(stop.to_string())
            .chain(tasks.iter().map(|id| format!("ET{id}")))
            .filter_map(|text| parse_line(&text, NumberBase::Decimal).ok())
            .map(|line| self.prepare_line(&line))
            .collect()
    }

    /// `ID7` lists the tasks that run (Ch4); `ETn` answered ends task n;
    /// `GT` starts one whose ID only the accumulator holds, and a macro
    /// called (`MC`, `MJ`) or a reset (`RT`: the power-up macro) may start
    /// one: after those, what runs is not known until `ID7` is read again.
    fn running_after(
        &self,
        line: &PreparedLine,
        answer: Option<&ReplyValue>,
        known: RunningPrograms,
    ) -> RunningPrograms {
        let Some(parsed) = self.line_of(line) else {
            return known;
        };
        if parsed.defines_macro() {
            return known;
        }
        let lists = |c: &super::line::Command| c.mnemonic() == "ID" && c.number() == Some(7.0);
        if let (Some(answer), [only]) = (answer, parsed.commands.as_slice())
            && lists(only)
        {
            return RunningPrograms::Known(MacroStore.running(answer));
        }
        let may_start = ["GT", "MC", "MJ", "RT"];
        if parsed
            .commands
            .iter()
            .any(|c| may_start.contains(&c.mnemonic()))
        {
            return RunningPrograms::Unknown;
        }
        match known {
            RunningPrograms::Known(mut ids) if answer.is_some() => {
                for command in parsed.commands.iter().filter(|c| c.mnemonic() == "ET") {
                    if let Some(id) = command.number() {
                        ids.retain(|&running| running as f64 != id);
                    }
                }
                RunningPrograms::Known(ids)
            }
            other => other,
        }
    }

    fn identify(&self, _address: u8) -> PreparedLine {
        // VE: "Reports the revision level of the firmware … and the amount
        // of memory" (Ch8).
        let line = parse_line("VE", NumberBase::Decimal).unwrap_or_default();
        self.prepare_line(&line)
    }

    fn status_queries(&self, _address: u8) -> Vec<StatusPoll> {
        // For each axis what moves (position, velocity, status word) fast,
        // the target and, on a closed-loop axis, the following error slow
        // (digest §16); one reply line each, the axis carried (Ch8 `AA
        // value`). Several axes go on one line (see `STATUS_LINE_AXES`).
        let mut polls = Vec::new();
        let axes: Vec<(usize, u8, bool)> = self
            .machine
            .axes
            .iter()
            .enumerate()
            .map(|(index, axis)| {
                let closed = self
                    .machine
                    .kind(axis.number)
                    .is_some_and(AxisKind::closed_loop);
                (index, axis.number, closed)
            })
            .collect();
        let lines = axes.len().div_ceil(STATUS_LINE_AXES).max(1);
        let per_line = axes.len().div_ceil(lines).max(1);
        let tells = |&(_, number, closed): &(usize, u8, bool), fast: bool| match (fast, closed) {
            (true, _) => format!("{number}TP,TV,TS"),
            (false, true) => format!("{number}TT,TF"),
            (false, false) => format!("{number}TT"),
        };
        for fast in [true, false] {
            for group in axes.chunks(per_line) {
                let text: Vec<String> = group.iter().map(|axis| tells(axis, fast)).collect();
                if let Ok(line) = parse_line(&text.join(","), NumberBase::Decimal) {
                    polls.push(StatusPoll {
                        axis: group[0].0,
                        line: self.prepare_line(&line),
                        fast,
                    });
                }
            }
        }
        polls
    }

    fn status_update(&self, line: &PreparedLine, reading: &Reading) -> Vec<(usize, AxisUpdate)> {
        let Some(parsed) = self.line_of(line) else {
            return Vec::new();
        };
        // Values come back in the order of the line's value commands (see
        // `value_of`); a line with text, jumps or repeats says nothing
        // reliable about an axis.
        let tells: Vec<usize> = (0..parsed.commands.len())
            .filter(|&i| parsed.commands[i].spec.output != Output::Nothing)
            .collect();
        let all_values = tells
            .iter()
            .all(|&i| parsed.commands[i].spec.output == Output::Value);
        if !runs_straight(&parsed) || !all_values || reads_variable(&parsed) {
            return Vec::new();
        }
        let values: Vec<String> = match &reading.value {
            ReplyValue::Number(n) => vec![n.to_string()],
            ReplyValue::Text(text) => text.split(' ').map(str::to_string).collect(),
            ReplyValue::None => Vec::new(),
        };
        if values.len() != tells.len() {
            return Vec::new();
        }
        let mut updates = Vec::new();
        for (&index, text) in tells.iter().zip(&values) {
            let command = &parsed.commands[index];
            let Some(axis_number) = parsed.axis_of(index).number() else {
                continue;
            };
            let Some(axis) = self.axis_index(axis_number) else {
                continue;
            };
            let Ok(value) = text.parse::<f64>() else {
                continue;
            };
            let rounded = value.round() as i64;
            match command.mnemonic() {
                "TP" => updates.push((axis, AxisUpdate::Position(rounded))),
                "TT" => updates.push((axis, AxisUpdate::Target(rounded))),
                "TV" => updates.push((axis, AxisUpdate::Speed(rounded))),
                "TF" => updates.push((axis, AxisUpdate::FollowingError(rounded))),
                "TS" => {
                    let selector = command
                        .number()
                        .and_then(|n| StatusSelector::from_parameter(n as i64));
                    if selector == Some(StatusSelector::Word(StatusWordKind::Primary))
                        && let Ok(word) = u32::try_from(rounded)
                    {
                        let kind = self.machine.kind(axis_number);
                        updates.extend(primary_updates(axis, kind, word));
                    }
                }
                _ => {}
            }
        }
        updates
    }

    fn complete(&self, line: &str, cursor: usize) -> Completions {
        super::assist::complete(line, cursor)
    }

    fn help(&self, line: &str, cursor: usize) -> Vec<String> {
        super::assist::help(line, cursor)
    }

    fn stop_axis_line(&self, axis: u8) -> Option<String> {
        self.machine.has(axis).then(|| format!("{axis}ST"))
    }

    /// None: the latched fault bits clear only with `MN` (Ch7 MN, Ch8 TS),
    /// which also turns the motor on, so clearing them is left to the user.
    fn clear_errors_line(&self, _axis: u8) -> Option<String> {
        None
    }

    fn lamps(&self) -> &'static [AxisFlag] {
        &LAMPS
    }

    fn units(&self) -> Option<&'static dyn crate::protocol::units::UnitLaw> {
        Some(&super::units::MclUnits)
    }

    fn parameters(&self) -> Option<&'static dyn ParameterSet> {
        Some(self.parameters)
    }

    fn jog(&self) -> Option<&'static dyn crate::protocol::jog::JogPlan> {
        Some(&super::jog::McclJog)
    }

    fn io(&self) -> Option<&'static dyn crate::protocol::io::IoPlan> {
        Some(&super::io::McclIo)
    }

    fn step_response(&self) -> Option<&'static dyn crate::protocol::tuning::StepResponsePlan> {
        Some(&super::tuning::McclStepResponse)
    }

    fn program(&self) -> Option<&'static dyn crate::protocol::program::ProgramTool> {
        Some(&super::tool::MclTool)
    }

    fn describe_request(&self, bytes: &[u8]) -> Option<String> {
        Some(super::traffic::describe_request(bytes))
    }

    fn describe_reply(&self, bytes: &[u8], request: Option<&[u8]>) -> Option<String> {
        Some(super::traffic::describe_reply(
            bytes,
            request,
            &self.profile,
        ))
    }
}

/// Why the MultiFlex console refuses a line.
#[derive(Debug, thiserror::Error)]
pub enum Refused {
    #[error("address {0}: the MCCL interface is point to point and has no bus address")]
    BusAddress(u8),
    #[error(transparent)]
    Parse(ParseErrors),
    /// What the check of chapter 4's rules found (an axis the controller
    /// does not have, a value out of its range, …).
    #[error("{}", .0.iter().map(|d| d.message.as_str()).collect::<Vec<_>>().join("; "))]
    Checks(Vec<Diagnostic>),
    #[error(
        "`{command}`: BK\"text\" single-steps, which waits for keys this console does \
         not send (Space, Enter)"
    )]
    SingleStep { command: String },
}

impl FamilyLineError for Refused {
    fn mistake(&self) -> Mistake {
        match self {
            Refused::BusAddress(_) => Mistake::Address,
            Refused::Parse(errors) => errors.mistake(),
            Refused::Checks(_) => Mistake::Range,
            Refused::SingleStep { .. } => Mistake::NotSent,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::wire::Verdict;

    const CONSOLE: MclConsole = MclConsole::DEFAULT;

    fn prepare(line: &str) -> PreparedLine {
        CONSOLE
            .prepare(line, 0)
            .unwrap_or_else(|e| panic!("{line}: {e}"))
    }

    fn frames(list: &[&str]) -> Vec<Frame> {
        list.iter().map(|s| s.as_bytes().to_vec()).collect()
    }

    fn answer(line: &PreparedLine, replies: &[&str]) -> Result<Reading, ReplyError> {
        let mut all = vec![line.canonical.as_str()];
        all.extend_from_slice(replies);
        all.push(">");
        CONSOLE.interpret(line, &frames(&all))
    }

    fn canonicals(lines: &[PreparedLine]) -> Vec<String> {
        lines.iter().map(|l| l.canonical.clone()).collect()
    }

    /// Ch4's register table lists `TRn.p` (register n) and `TR.p` (the
    /// accumulator): a register and a reporting precision, whose decimals
    /// the reply must have.
    #[test]
    fn tr_takes_a_register_and_a_precision() {
        for line in ["TR5.3", "TR.2", "TR999.5", "TR5", "TR"] {
            assert!(CONSOLE.prepare(line, 0).is_ok(), "{line}");
        }
        for line in ["TR1000", "TR5.7", "TR5.25", "TR-1"] {
            assert!(CONSOLE.prepare(line, 0).is_err(), "{line}");
        }
        assert_eq!(
            answer(&prepare("TR5.3"), &["01 123.456"]).map(|r| r.value),
            Ok(ReplyValue::Text("123.456".into()))
        );
        assert_eq!(
            answer(&prepare("TR.1"), &["01 123.4"]).map(|r| r.value),
            Ok(ReplyValue::Text("123.4".into()))
        );
        assert!(
            answer(&prepare("TR5.2"), &["01 15"]).is_err(),
            "2 decimals asked"
        );
        assert_eq!(
            answer(&prepare("TR5"), &["01 123.456700"]).map(|r| r.value),
            Ok(ReplyValue::Text("123.456700".into())),
            "without a precision, as the register holds it"
        );
    }

    #[test]
    fn a_line_is_sent_canonical_with_a_cr() {
        let line = prepare("2mr1000, ws0.5 ;there and back");
        assert_eq!(line.canonical, "2MR1000,WS0.5");
        assert_eq!(line.bytes, b"2MR1000,WS0.5\r".to_vec());
        assert_eq!(line.effect, Effect::Acts);
        assert_eq!(prepare("1TP,TV,TS").effect, Effect::Reads);
        assert_eq!(
            prepare("1TP,RP").effect,
            Effect::Acts,
            "still running after a timeout"
        );
        assert_eq!(
            prepare("1CG,TR0").effect,
            Effect::Acts,
            "CG loads the accumulator"
        );
        assert!(
            CONSOLE
                .prepare("1TP", 1)
                .unwrap_err()
                .to_string()
                .contains("point to point")
        );
    }

    #[test]
    fn what_does_not_parse_or_check_is_refused() {
        let e = CONSOLE.prepare("", 0).unwrap_err().to_string();
        assert!(e.contains("repeat the controller's last line"), "{e}");
        let e = CONSOLE.prepare("1DS0", 0).unwrap_err().to_string();
        assert_eq!(e, "`1DS0`: DS must be > 0, not 0");
        let e = CONSOLE.prepare("1EI9", 0).unwrap_err().to_string();
        assert!(e.contains("malfunction"), "{e}");
        let e = CONSOLE.prepare("BK\"wait\"", 0).unwrap_err().to_string();
        assert!(e.contains("single-steps"), "{e}");
        // What changes the interface is followed, not refused.
        for line in ["HM", "PC35", "EF1", "EN1", "PC0"] {
            assert!(CONSOLE.prepare(line, 0).is_ok(), "{line}");
        }
        // Stored in a macro they are not run now.
        assert!(CONSOLE.prepare("MD10,1TP,BK\"wait\",RP1", 0).is_ok());
        // Warnings do not stop a line.
        assert!(CONSOLE.prepare("TP,RP999", 0).is_ok());
        assert!(CONSOLE.prepare("PC62", 0).is_ok(), "the prompt it has");
        assert!(CONSOLE.prepare("DM", 0).is_ok());
    }

    fn context(console: &MclConsole, line: &str, before: &dyn LinkContext) -> Arc<dyn LinkContext> {
        let contexts = console.link_contexts().expect("MCCL keeps a link state");
        contexts
            .after(&prepare(line), before)
            .unwrap_or_else(|| panic!("{line} changes the interface"))
    }

    #[test]
    fn after_hm_lines_are_written_and_read_in_hex() {
        let contexts = CONSOLE.link_contexts().expect("contexts");
        let power_up = contexts.initial();
        assert!(
            contexts
                .after(&prepare("1MA1000"), power_up.as_ref())
                .is_none(),
            "a move changes nothing of the interface"
        );
        let hex = context(&CONSOLE, "HM", power_up.as_ref());
        assert_eq!(hex.summary().as_deref(), Some("hex (HM)"));
        let line = contexts.adapt(&prepare("MD10,1MA1000,MR-255,WS0.5"), hex.as_ref());
        assert_eq!(line.canonical, "MD10,1MA1000,MR-255,WS0.5", "what it means");
        assert_eq!(line.bytes, b"MD0A,1MA3E8,MR-0FF,WS0.5\r".to_vec());
        // Adapting again changes nothing.
        let again = contexts.adapt(&line, hex.as_ref());
        assert_eq!(again.bytes, line.bytes);
        let tp = contexts.adapt(&prepare("1TP,TS"), hex.as_ref());
        let frames = frames(&["1TP,TS", "01 fffffc18", "01 0000000a", ">"]);
        let reading = contexts
            .interpret_in(&tp, &frames, hex.as_ref())
            .expect("hex replies");
        assert_eq!(reading.value, ReplyValue::Text("-1000 10".into()));
        assert_eq!(
            CONSOLE.status_update(&tp, &reading)[0],
            (0, AxisUpdate::Position(-1000))
        );
        // The emergency stop's task IDs in hex too.
        let stops = CONSOLE.emergency_stop(0);
        assert_eq!(
            contexts.adapt(&stops[21], hex.as_ref()).bytes,
            b"ET15\r".to_vec()
        );
        // DM, or a reset of the whole controller, go back to decimal.
        let decimal = context(&CONSOLE, "DM", hex.as_ref());
        assert_eq!(decimal.summary(), None);
        let reset = context(&CONSOLE, "RT", hex.as_ref());
        assert_eq!(reset.summary(), None);
        assert!(contexts.after(&prepare("1RT"), hex.as_ref()).is_none());
    }

    #[test]
    fn a_changed_prompt_or_echo_is_waited_for() {
        let contexts = CONSOLE.link_contexts().expect("contexts");
        let power_up = contexts.initial();
        let hash = context(&CONSOLE, "PC35", power_up.as_ref());
        assert_eq!(hash.summary().as_deref(), Some("prompt `#`"));
        let Answering::Reply(rule) = contexts.adapt(&prepare("1TP"), hash.as_ref()).answering
        else {
            panic!("a reply")
        };
        let so_far = frames(&["1TP", "01 5"]);
        assert_eq!(rule.examine(&so_far, b">"), Verdict::Continue);
        assert_eq!(rule.examine(&so_far, b"#"), Verdict::Complete);
        let none = context(&CONSOLE, "PC0", hash.as_ref());
        assert_eq!(none.summary().as_deref(), Some("no prompt (PC0)"));
        let silent = context(&CONSOLE, "EF1", power_up.as_ref());
        let line = contexts.adapt(&prepare("1TP"), silent.as_ref());
        let reading = contexts
            .interpret_in(&line, &frames(&["01 5", ">"]), silent.as_ref())
            .expect("no echo to strip");
        assert_eq!(reading.value, ReplyValue::Number(5));
        assert_eq!(silent.summary().as_deref(), Some("echo off"));
    }

    #[test]
    fn the_probe_learns_echo_prompt_and_granularity() {
        let contexts = CONSOLE.link_contexts().expect("contexts");
        assert_eq!(contexts.probe(), [b"NO\r".to_vec(), b"NO,NO,NO\r".to_vec()]);
        let power_up = contexts.initial();
        let learned = contexts
            .learn(
                power_up.as_ref(),
                &[b"NO\r\n#".to_vec(), b"NO,NO,NO\r\n###".to_vec()],
            )
            .expect("learned");
        assert_eq!(
            learned.summary().as_deref(),
            Some("prompt `#`, prompt per command")
        );
        let Answering::Reply(rule) = contexts
            .adapt(&prepare("1MN,2MN"), learned.as_ref())
            .answering
        else {
            panic!("a reply")
        };
        let so_far = frames(&["1MN,2MN", "#"]);
        assert_eq!(rule.examine(&so_far[..1], b"#"), Verdict::Continue);
        assert_eq!(rule.examine(&so_far, b"#"), Verdict::Complete);
        let e = contexts
            .learn(power_up.as_ref(), &[b"".to_vec(), b"".to_vec()])
            .unwrap_err()
            .to_string();
        assert!(e.contains("no prompt"), "{e}");
        assert!(contexts.learn(power_up.as_ref(), &[]).is_err());
    }

    #[test]
    fn the_answer_is_the_echo_the_output_and_the_prompt() {
        let Answering::Reply(rule) = prepare("1TP").answering else {
            panic!("a reply")
        };
        assert_eq!(rule.examine(&[], b">"), Verdict::NotMine);
        assert_eq!(rule.examine(&[], b"1TP"), Verdict::Continue);
        assert_eq!(
            rule.examine(&frames(&["1TP", "01 997"]), b">"),
            Verdict::Complete
        );
        let tp = prepare("1TP");
        assert_eq!(
            answer(&tp, &["01 997"]).map(|r| r.value),
            Ok(ReplyValue::Number(997))
        );
        assert_eq!(
            answer(&prepare("1TP.3"), &["01 121.025"]).map(|r| r.value),
            Ok(ReplyValue::Text("121.025".into()))
        );
        assert_eq!(
            answer(&prepare("1TP,TV,TS"), &["01 1000", "01 0", "01 10"]).map(|r| r.value),
            Ok(ReplyValue::Text("1000 0 10".into()))
        );
        assert_eq!(
            answer(&prepare("1MN"), &[]).map(|r| r.value),
            Ok(ReplyValue::None)
        );
        let version = answer(
            &prepare("VE"),
            &["MFX-PCI1440-3-A Motion Controller", "Rev. 4.5a"],
        );
        assert_eq!(
            version.map(|r| r.value),
            Ok(ReplyValue::Text(
                "MFX-PCI1440-3-A Motion Controller · Rev. 4.5a".into()
            ))
        );
        let listing = answer(&prepare("TM-1"), &["MC1,1LM2", "MC10,1VM"]);
        assert_eq!(
            listing.map(|r| r.value),
            Ok(ReplyValue::Text("MC1,1LM2\nMC10,1VM".into()))
        );
    }

    #[test]
    fn errors_are_refusals_with_their_ch14_meaning() {
        let mc = prepare("MC10");
        let error = answer(&mc, &["?-6"]).unwrap_err();
        assert_eq!(
            error.to_string(),
            "the controller refused MC10: ?-6 (Macro Doesn't Exist, Ch14)"
        );
        // Anything else than the success answer is malformed.
        let error = answer(&prepare("1TP"), &[]).unwrap_err();
        assert!(matches!(error, ReplyError::Malformed { .. }), "{error}");
        assert!(
            error.to_string().contains("no reply line for 1TP"),
            "{error}"
        );
        let error = CONSOLE
            .interpret(&prepare("1TP"), &frames(&["1TP", "01 5"]))
            .unwrap_err();
        assert!(error.to_string().contains("no prompt"), "{error}");
        let error = answer(&prepare("1MN"), &["01 5"]).unwrap_err();
        assert!(matches!(error, ReplyError::Malformed { .. }), "{error}");
        // ET of an ID no task has: nothing was running.
        let et = answer(&prepare("ET5"), &["?-20"]).expect("not running");
        assert!(
            et.value.to_string().contains("no background task 5"),
            "{}",
            et.value
        );
        assert!(answer(&prepare("ET5,NO"), &["?-20"]).is_err());
    }

    #[test]
    fn the_emergency_stop_aborts_every_axis_then_ends_every_task() {
        let lines = CONSOLE.emergency_stop(0);
        let names = canonicals(&lines);
        assert_eq!(names[0], "0AB");
        assert_eq!(names[1], "ET1");
        assert_eq!(names.last().map(String::as_str), Some("ET21"));
        assert_eq!(names.len(), 22);
        let gentle = MclConsole {
            stop: StopMotion::Decelerate,
            tasks: &[7],
            ..CONSOLE
        };
        assert_eq!(canonicals(&gentle.emergency_stop(0)), ["0ST", "ET7"]);
        assert_eq!(lines[0].bytes, b"0AB\r".to_vec());
    }

    #[test]
    fn the_stop_ends_the_tasks_known_to_run_and_every_one_when_unknown() {
        use RunningPrograms::{Known, Unknown};
        let stop =
            |running: &RunningPrograms| canonicals(&CONSOLE.emergency_stop_knowing(0, running));
        assert_eq!(stop(&Known(vec![3, 9])), ["0AB", "ET3", "ET9"]);
        assert_eq!(stop(&Known(Vec::new())), ["0AB"]);
        assert_eq!(stop(&Unknown).len(), 22);
        let after = |line: &str, answer: Option<&str>, known: RunningPrograms| {
            let value = answer.map(|a| ReplyValue::Text(a.into()));
            CONSOLE.running_after(&prepare(line), value.as_ref(), known)
        };
        let listing = "ACTIVE BACKGROUND TASKS: 2\nTask ID 3\nTask ID 9";
        assert_eq!(after("ID7", Some(listing), Unknown), Known(vec![3, 9]));
        assert_eq!(after("ID7", None, Unknown), Unknown, "not answered");
        assert_eq!(after("ET3", Some(""), Known(vec![3, 9])), Known(vec![9]));
        assert_eq!(after("ET3", None, Known(vec![3, 9])), Known(vec![3, 9]));
        for starts in ["GT100", "GT0,1MR5,1WS", "MC10", "1MR5,MJ10", "RT"] {
            assert_eq!(after(starts, None, Known(vec![])), Unknown, "{starts}");
            assert_eq!(after(starts, Some(""), Known(vec![])), Unknown, "{starts}");
        }
        // Stored, not run; and lines that start nothing.
        for line in ["MD10,GT11", "1MR1000", "1TP"] {
            assert_eq!(
                after(line, Some(""), Known(vec![4])),
                Known(vec![4]),
                "{line}"
            );
        }
    }

    #[test]
    fn long_lines_abort_with_escape_and_pause_with_space() {
        for line in [
            "2MR1000,WS0.5,MR-1000,WS0.5,RP6",
            "1TP,RP",
            "MC10",
            "1FI1000",
            "WA1",
        ] {
            let long = CONSOLE.long_running(&prepare(line)).expect(line);
            assert_eq!(long.abort, [0x1B]);
            assert_eq!(long.pause, Some(vec![b' ']));
        }
        for line in ["1MR1000", "1TP", "MD10,1MR1000,1WS,RP", "GT0,1MR5,1WS"] {
            assert_eq!(CONSOLE.long_running(&prepare(line)), None, "{line}");
        }
    }

    #[test]
    fn status_comes_from_one_tell_line_for_every_axis() {
        let polls = CONSOLE.status_queries(0);
        let names: Vec<(usize, &str, bool)> = polls
            .iter()
            .map(|p| (p.axis, p.line.canonical.as_str(), p.fast))
            .collect();
        assert_eq!(
            names,
            [
                (0, "1TP,TV,TS,2TP,TV,TS,3TP,TV,TS,4TP,TV,TS,5TP,TV,TS", true),
                // An open-loop stepper has no TF.
                (0, "1TT,TF,2TT,TF,3TT,TF,4TT,TF,5TT", false),
            ]
        );
        assert!(polls.iter().all(|p| p.line.effect == Effect::Reads));

        // Ch8: one `AA value` line a Tell, each with the axis the line
        // carried to it (Ch2: "the axis that a command acts on is assumed
        // to be the last one specified in the command string").
        let fast = &polls[0].line;
        let mut replies = vec!["01 7", "01 0", "01 0"];
        replies.extend(["02 -500", "02 1200", "02 268436489"]);
        replies.extend(["03 0", "03 0", "03 0", "04 0", "04 0", "04 0"]);
        replies.extend(["05 40", "05 0", "05 0"]);
        let reading = answer(fast, &replies).expect("read");
        let updates = CONSOLE.status_update(fast, &reading);
        assert!(updates.contains(&(0, AxisUpdate::Position(7))));
        assert!(updates.contains(&(4, AxisUpdate::Position(40))));
        let updates: Vec<AxisUpdate> = updates
            .into_iter()
            .filter(|(axis, _)| *axis == 1)
            .map(|(_, u)| u)
            .collect();
        assert!(updates.contains(&AxisUpdate::Position(-500)));
        assert!(updates.contains(&AxisUpdate::Speed(1200)));
        assert!(updates.contains(&AxisUpdate::Switch(SwitchKind::Right, true)));
        assert!(updates.contains(&AxisUpdate::Switch(SwitchKind::Left, false)));
        assert!(updates.contains(&AxisUpdate::Reached(false)));
        let errors = updates.iter().find_map(|u| match u {
            AxisUpdate::Errors(flags) => Some(flags.iter().map(|f| f.name).collect::<Vec<_>>()),
            _ => None,
        });
        assert_eq!(errors, Some(vec!["motor error", "hard limit +"]));
        // An answer short of a Tell is no reading of any axis.
        assert!(answer(fast, &replies[..14]).is_err());

        let slow = &polls[1].line;
        let reading = answer(
            slow,
            &[
                "01 1000", "01 3", "02 0", "02 0", "03 0", "03 0", "04 0", "04 0", "05 9",
            ],
        )
        .expect("read");
        let updates = CONSOLE.status_update(slow, &reading);
        assert_eq!(
            updates[..2],
            [
                (0, AxisUpdate::Target(1000)),
                (0, AxisUpdate::FollowingError(3))
            ]
        );
        assert_eq!(updates.last(), Some(&(4, AxisUpdate::Target(9))));

        // A user's own read counts; real values are rounded.
        let own = prepare("3TP.3");
        let reading = answer(&own, &["03 121.725"]).expect("read");
        assert_eq!(
            CONSOLE.status_update(&own, &reading),
            [(2, AxisUpdate::Position(122))]
        );
        // A stepper's home lamp is bit 24, a servo's coarse home bit 25.
        let stepper = prepare("5TS");
        let reading = answer(&stepper, &["05 16777216"]).expect("read");
        assert!(
            CONSOLE
                .status_update(&stepper, &reading)
                .contains(&(4, AxisUpdate::Switch(SwitchKind::Home, true)))
        );
        // A repeating line or a status bit says nothing reliable.
        let repeat = prepare("1TP,RP2");
        let reading = answer(&repeat, &["01 1", "01 2", "01 3"]).expect("read");
        assert!(CONSOLE.status_update(&repeat, &reading).is_empty());
        let bit = prepare("1TS3");
        let reading = answer(&bit, &["01 1"]).expect("read");
        assert!(CONSOLE.status_update(&bit, &reading).is_empty());
    }

    /// A jog says the motor is off from the lamps the status poll lights
    /// (Ch8 TS bit 1 "motor on"), before anything is sent.
    #[test]
    fn a_jog_knows_the_motor_is_off_from_the_status_lamps() {
        use crate::protocol::jog::JogPlan;
        let ts = prepare("1TS");
        let lamps_of = |value: &str| {
            let reading = answer(&ts, &[value]).expect("read");
            CONSOLE
                .status_update(&ts, &reading)
                .into_iter()
                .find_map(|(_, update)| match update {
                    AxisUpdate::DriverFlags(flags) => Some(flags),
                    _ => None,
                })
                .expect("driver lamps")
        };
        let axis = CONSOLE.axes()[0];
        let jog = super::super::jog::McclJog;
        let off = jog.not_ready(&axis, &lamps_of("01 0"));
        assert!(
            off.as_deref().is_some_and(|why| why.contains("1MN")),
            "{off:?}"
        );
        assert_eq!(jog.not_ready(&axis, &lamps_of("01 2")), None, "bit 1 set");
    }

    /// Past six axes the lines share them evenly: eight servos in two
    /// lines of four (39 characters each).
    #[test]
    fn more_axes_than_a_line_takes_share_the_fewest_lines_evenly() {
        const KINDS: [AxisKind; 8] = [AxisKind::Servo; 8];
        const AXES: [AxisInfo; 8] = {
            let mut axes = [AxisInfo {
                number: 1,
                name: "servo",
            }; 8];
            let mut n = 0;
            while n < 8 {
                axes[n].number = n as u8 + 1;
                n += 1;
            }
            axes
        };
        let console = MclConsole {
            machine: Machine {
                kinds: &KINDS,
                axes: &AXES,
            },
            ..MclConsole::DEFAULT
        };
        let lines: Vec<(usize, String, bool)> = console
            .status_queries(0)
            .into_iter()
            .map(|p| (p.axis, p.line.canonical, p.fast))
            .collect();
        let fast = |n: std::ops::RangeInclusive<u8>| {
            n.map(|a| format!("{a}TP,TV,TS"))
                .collect::<Vec<_>>()
                .join(",")
        };
        let slow = |n: std::ops::RangeInclusive<u8>| {
            n.map(|a| format!("{a}TT,TF")).collect::<Vec<_>>().join(",")
        };
        assert_eq!(
            lines,
            [
                (0, fast(1..=4), true),
                (4, fast(5..=8), true),
                (0, slow(1..=4), false),
                (4, slow(5..=8), false),
            ]
        );
        assert!(lines.iter().all(|(_, line, _)| line.len() <= 60));
    }
    #[test]
    fn lamps_stop_keys_and_identity() {
        let names: Vec<&str> = CONSOLE.lamps().iter().map(|f| f.name).collect();
        assert_eq!(
            names,
            ["motor", "homed", "seek", "found", "capt", "brkpt", "fault"]
        );
        let homed = CONSOLE.lamps()[1];
        assert!(homed.description.contains("homed"), "{}", homed.description);
        assert_eq!(CONSOLE.stop_axis_line(2).as_deref(), Some("2ST"));
        assert_eq!(CONSOLE.stop_axis_line(6), None);
        assert_eq!(CONSOLE.clear_errors_line(1), None);
        assert_eq!(CONSOLE.identify(0).bytes, b"VE\r".to_vec());
        assert_eq!(CONSOLE.axes().len(), 5);
        assert_eq!(CONSOLE.addresses(), 0..=0);
    }
}
