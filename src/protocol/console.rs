//! What a controller family tells the session layer: how a console line
//! becomes bytes and an expected answer, what an answer means, how to stop
//! every motor, which queries make up an axis's status, and what those
//! answers say about the axis.
//!
//! Pure code, no I/O: the session builds device transactions from these
//! descriptions, so that this module needs nothing from `device/`.

use std::any::Any;
use std::fmt;
use std::sync::Arc;
use std::time::Duration;

use super::line_error::LineError;
use super::parameters::ParameterSet;
use super::program::ProgramTool;
use super::settings::{SettingWrite, SettingsCache};
use super::wire::{Frame, ReplyRule, WireFormat};

/// How a prepared line is answered.
#[derive(Debug, Clone)]
pub enum Answering {
    /// An answer the rule recognises must come.
    Reply(Arc<dyn ReplyRule>),
    /// An answer may come or may be lost (TMCL 255 software reset,
    /// §3.6.53): no answer within the timeout is not an error.
    MaybeReply(Arc<dyn ReplyRule>),
    /// The module never answers (TMCL 137 restore factory settings).
    Nothing,
    /// The answer comes apart from the request, when the module is
    /// ready, however long that takes (SIXpack 2 `$28` with a wait mask:
    /// "as soon as all concerned motors are inactive", §7.2). Other
    /// requests go on meanwhile (on RS-232 one such answer may be
    /// outstanding, §6.2.1.7): the request is done once it is written,
    /// and its answer comes as news ([`super::wire::WireFormat::unsolicited`])
    /// that the rule recognises, waited for up to `within`.
    Later {
        rule: Arc<dyn ReplyRule>,
        within: Duration,
    },
}

/// Whether sending a line twice could hurt: only reads may be retried.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effect {
    /// Reads something and changes nothing.
    Reads,
    /// Moves, writes, stores or starts something.
    Acts,
}

/// A console line parsed, validated and encoded for one module: what is
/// sent, what comes back, and whether it may be repeated.
#[derive(Debug, Clone)]
pub struct PreparedLine {
    /// The line in the family's canonical form (`SAP 6, 0, 300`), for
    /// messages.
    pub canonical: String,
    /// The module the line is addressed to.
    pub address: u8,
    /// The bytes to send.
    pub bytes: Vec<u8>,
    pub answering: Answering,
    pub effect: Effect,
}

/// What a session knows of the programs a module runs in the background
/// (MCCL tasks, Ch4 "MCCL Multi-Tasking"), for an emergency stop that ends
/// them one by one ([`FamilyConsole::emergency_stop_knowing`]).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum RunningPrograms {
    /// Anything may run: nothing was read since connecting, or a line
    /// since may have started one.
    #[default]
    Unknown,
    /// Exactly these IDs run, as last listed and since ended or not.
    Known(Vec<i64>),
}

/// What a successful answer carries.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ReplyValue {
    /// Nothing worth showing: the console prints `ok`.
    None,
    /// A number read (a parameter, an input, a status word…).
    Number(i64),
    /// Text (a firmware version string, a program word shown as a line).
    Text(String),
}

impl ReplyValue {
    /// The number read, if the answer is one.
    pub fn number(&self) -> Option<i64> {
        match self {
            ReplyValue::Number(n) => Some(*n),
            _ => None,
        }
    }
}

impl fmt::Display for ReplyValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReplyValue::None => f.write_str("ok"),
            ReplyValue::Number(n) => write!(f, "{n}"),
            ReplyValue::Text(text) => f.write_str(text),
        }
    }
}

/// A successful answer as the family reads it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reading {
    /// The status code the answer carried, where the family has one
    /// (TMCL 100 "successfully executed").
    pub status: Option<u32>,
    pub value: ReplyValue,
}

/// Why an answer is not a success.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReplyError {
    /// The module understood the request and refused it.
    #[error("{module} rejected {line}: {meaning} (status {status})")]
    Rejected {
        /// "module 1".
        module: String,
        /// The canonical line that was sent.
        line: String,
        status: u32,
        /// The manual's meaning of the status code.
        meaning: String,
    },
    /// The module understood the request and refused it with an error
    /// reply of its own words, no status code (CMD-4CR `?Error Moving`,
    /// §4.2).
    #[error("{module} refused {line}: {reply} ({meaning})")]
    Refused {
        /// "controller 01".
        module: String,
        /// The canonical line that was sent.
        line: String,
        /// The reply as it came.
        reply: String,
        /// The manual's meaning of the reply.
        meaning: String,
    },
    /// The answer does not make sense for the request.
    #[error("unreadable answer to {line}: {reason}")]
    Malformed { line: String, reason: String },
}

impl ReplyError {
    /// The status code of a rejection.
    pub fn status(&self) -> Option<u32> {
        match self {
            ReplyError::Rejected { status, .. } => Some(*status),
            ReplyError::Refused { .. } | ReplyError::Malformed { .. } => None,
        }
    }
}

/// One axis of a module as the console names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AxisInfo {
    /// The number the protocol uses (TMCL motor 0).
    pub number: u8,
    /// How the console shows it.
    pub name: &'static str,
}

/// A named condition of an axis (an error flag, a driver warning).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct AxisFlag {
    /// Short name for a status line ("stall").
    pub name: &'static str,
    /// What it means, with the manual section.
    pub description: &'static str,
}

/// Which end or reference switch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SwitchKind {
    Left,
    Right,
    Home,
}

/// What an axis is doing, as a module that reports it says (CMD-4CR MST
/// bits 0–2, §2.6.2.1); a family that does not has its ramp read from
/// how the speed changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionPhase {
    Standing,
    Accelerating,
    /// Moving at a constant speed.
    Constant,
    Decelerating,
    /// Not moving, and the motion not over: the module waits for an input
    /// before the move starts or completes (CMD-4CR MST bits 18, 19:
    /// in-position, external start).
    Waiting,
}

/// How a module takes the target of a move line, where it has a mode for
/// it that applies to later lines (CMD-4CR `ABS`/`INC`, read back by `MM`,
/// §2.2.4.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MoveMode {
    /// The operand is the target.
    Absolute,
    /// The operand is a step from where the axis stands.
    Incremental,
}

/// What one status answer says about an axis.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AxisUpdate {
    Position(i64),
    Target(i64),
    /// A move line sent gives the axis this target operand, meant as the
    /// axis's move mode says ([`AxisUpdate::MoveMode`]): the target
    /// itself, or a step from the position last read. For a module with
    /// no target register, whose target only the line sent tells; while
    /// the mode (or, for a step, the position) is not known, so is not
    /// the target.
    MoveTarget(i64),
    /// The axis's move mode as read or set (`None`: a reading that names
    /// no mode the manual gives).
    MoveMode(Option<MoveMode>),
    /// A line made the target unknown: a motion with no target the
    /// console can tell (a jog, a homing, a target changed in flight), or
    /// the position counter written.
    TargetUnknown,
    Speed(i64),
    /// The fastest the axis moves when positioning (TMCL AP4), for a speed
    /// gauge: the axis's own setting.
    MaxSpeed(i64),
    /// The module-wide maximum speed, which applies to an axis whose own
    /// reads 0 (CMD-4CR: a per-axis HSPD of 0 means the global HSPD,
    /// §2.1.4).
    GlobalMaxSpeed(i64),
    /// The axis stands at its target.
    Reached(bool),
    /// What the axis is doing, where the module says.
    Phase(MotionPhase),
    /// A switch is active (true) or not.
    Switch(SwitchKind, bool),
    /// Motor load reading (TMCL: StallGuard2 value, 0 = highest load).
    Load(i64),
    /// Commanded minus actual position of a closed-loop axis (MCCL `TF`,
    /// Ch8).
    FollowingError(i64),
    /// Error flags that were set; reading them may have cleared them in the
    /// module (TMCL AP207), so the session latches them.
    Errors(Vec<AxisFlag>),
    /// Conditions the driver reports now (not latched).
    DriverFlags(Vec<AxisFlag>),
}

/// A value the status poll reads for every axis of a family: what the
/// plot offers to follow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StatusValue {
    Position,
    Target,
    Speed,
    Load,
    FollowingError,
}

/// How a line that may keep the module busy for long is dealt with while it
/// runs (MCCL `RP`, `WS`, `MC`, `FI`: the controller takes nothing but an
/// abort and a pause byte until the line's prompt, Ch2). The session sends
/// it held: no reply timeout, the module shown busy, the abort and pause
/// bytes sent when the user asks (and the abort before an emergency stop).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LongRunning {
    /// Sent while the line runs, aborts it (MCCL: Escape).
    pub abort: Vec<u8>,
    /// Sent while the line runs, pauses it; sent again, resumes it (MCCL:
    /// Space).
    pub pause: Option<Vec<u8>>,
}

/// What a family keeps of one link between lines where its lines change
/// how later lines are written or read (MCCL: `DM`/`HM` the number base
/// both ways, `PC` the prompt, `EN`/`EF` the echo, Ch13; the interface as
/// the connect probe found it). An immutable snapshot: a line that changes
/// it makes a new one ([`LinkContexts::after`]). The session keeps the
/// current one; only the family looks inside.
pub trait LinkContext: Send + Sync + fmt::Debug {
    /// For the family to look inside.
    fn as_any(&self) -> &dyn Any;
    /// What differs from the module's power-up state, for the console to
    /// show ("hex numbers, prompt `#`"); `None` when nothing does.
    fn summary(&self) -> Option<String> {
        None
    }
}

/// Why the connect probe's answers did not show the link's state: the
/// session then keeps the state it had.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ProbeError {
    #[error("nothing to learn ({context})")]
    NothingToLearn { context: String },
    #[error("the probe brought {got} answers, not {wanted}")]
    AnswerCount { got: usize, wanted: usize },
    /// A probe request's answer is not what any state of the link gives.
    #[error("`{request}` {answered}")]
    Unexpected {
        request: &'static str,
        /// What came back and why it does not fit (`was answered `…`: no
        /// prompt character at its end`).
        answered: String,
    },
}

/// A family whose lines read and change a state kept per link
/// ([`LinkContext`]). Lines are prepared as if the module were in its
/// power-up state ([`FamilyConsole::prepare`]: a line means the same
/// whatever the state); the session makes each one fit the current state
/// when it sends it ([`LinkContexts::adapt`]), reads its answer in that
/// state, and takes the state the line leaves behind.
pub trait LinkContexts: Send + Sync {
    /// The state before the connect probe: the module's power-up state as
    /// the family's defaults describe it.
    fn initial(&self) -> Arc<dyn LinkContext>;
    /// Requests sent raw at connect, each answered by every byte that comes
    /// until the line is quiet (MCCL `NO` and `NO,NO,NO`, digest §3.3: the
    /// echo, the prompt and whether it comes per line or per command).
    /// None by default.
    fn probe(&self) -> Vec<Vec<u8>> {
        Vec::new()
    }
    /// The state the probe's answers (in order) show, from `context`; an
    /// error says what did not fit, and the session keeps `context`.
    fn learn(
        &self,
        context: &dyn LinkContext,
        answers: &[Vec<u8>],
    ) -> Result<Arc<dyn LinkContext>, ProbeError> {
        let _ = answers;
        Err(ProbeError::NothingToLearn {
            context: format!("{context:?}"),
        })
    }
    /// `line` (prepared for the power-up state, or adapted before: the
    /// result is the same) as it must be sent in `context`: its bytes and
    /// the answer it waits for.
    fn adapt(&self, line: &PreparedLine, context: &dyn LinkContext) -> PreparedLine;
    /// What the answer to `line`, sent adapted to `context`, means.
    fn interpret_in(
        &self,
        line: &PreparedLine,
        frames: &[Frame],
        context: &dyn LinkContext,
    ) -> Result<Reading, ReplyError>;
    /// The state after `line` ran without error in `context`; `None` when
    /// it changes nothing.
    fn after(&self, line: &PreparedLine, context: &dyn LinkContext)
    -> Option<Arc<dyn LinkContext>>;
}

/// `line` as it must be sent in `context`, where the family keeps one.
pub fn adapt_line(
    console: &dyn FamilyConsole,
    line: &PreparedLine,
    context: Option<&dyn LinkContext>,
) -> PreparedLine {
    match (console.link_contexts(), context) {
        (Some(contexts), Some(context)) => contexts.adapt(line, context),
        _ => line.clone(),
    }
}

/// The answer to `line` read in `context`, where the family keeps one.
pub fn interpret_line(
    console: &dyn FamilyConsole,
    line: &PreparedLine,
    frames: &[Frame],
    context: Option<&dyn LinkContext>,
) -> Result<Reading, ReplyError> {
    match (console.link_contexts(), context) {
        (Some(contexts), Some(context)) => contexts.interpret_in(line, frames, context),
        _ => console.interpret(line, frames),
    }
}

/// A line that reads part of an axis's status.
#[derive(Debug, Clone)]
pub struct StatusPoll {
    /// Index into [`FamilyConsole::axes`].
    pub axis: usize,
    pub line: PreparedLine,
    /// Whether it changes fast (position, speed) and is worth reading more
    /// often than the rest.
    pub fast: bool,
}

/// How a family's load reading ([`AxisUpdate::Load`]) reads on a gauge.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoadScale {
    /// The reading at one end of the scale (the other end is 0).
    pub full_scale: i64,
    /// Whether 0 means the highest load (TMCL StallGuard2, AP206).
    pub zero_is_highest: bool,
}

/// One way to finish the word under the cursor of a console line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Candidate {
    /// What replaces the word (`MVP`, `ABS`, `4`).
    pub text: String,
    /// What it is, for the list shown to the user
    /// ("Maximum positioning speed").
    pub note: String,
}

/// What completing the word under the cursor offers.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Completions {
    /// Byte offsets of the word a candidate replaces (`start..end`; equal
    /// when the cursor is between words).
    pub start: usize,
    pub end: usize,
    pub candidates: Vec<Candidate>,
    /// What follows a chosen candidate when the line goes on: a space
    /// after a mnemonic, `, ` between operands, nothing after the last.
    pub separator: &'static str,
}

/// A choice about reading a family's link that its manual leaves open
/// (SIXpack 2: whether a reply carries the response address in front,
/// digest D1.4), made on the command line (`--link-option framing=cmd8`)
/// or the connect screen.
#[derive(Debug)]
pub struct LinkOption {
    /// `framing`.
    pub name: &'static str,
    /// What it decides, for help.
    pub help: &'static str,
    /// What it may be; the first is the default.
    pub choices: &'static [LinkChoice],
}

/// One value of a [`LinkOption`] and the family as it makes it.
pub struct LinkChoice {
    /// `cmd8`.
    pub value: &'static str,
    /// What it means, for help.
    pub help: &'static str,
    /// The family with this choice made (its console reads the link so).
    pub family: &'static super::Family,
}

impl fmt::Debug for LinkChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LinkChoice")
            .field("value", &self.value)
            .field("help", &self.help)
            .finish_non_exhaustive()
    }
}

/// What the session layer needs of a controller family. One implementation
/// per family, registered in [`crate::families::FAMILIES`].
pub trait FamilyConsole: Send + Sync {
    /// The wire format the device task cuts frames and matches answers with.
    fn wire(&self) -> Arc<dyn WireFormat>;

    /// The module address when the user gives none.
    fn default_address(&self) -> u8;

    /// The serial baud rate when the user gives none: the family's
    /// factory setting (TMCL GP65 = 9600 Bd, §5.1; the default).
    fn default_baud(&self) -> u32 {
        9600
    }

    /// Every address a module of this family can have: what a bus scan
    /// tries when told nothing else, and all it may try.
    fn addresses(&self) -> std::ops::RangeInclusive<u8> {
        0..=255
    }

    /// Whether the family's answers carry a check of their own (a
    /// checksum) that tells a value damaged on the wire from a good one.
    /// Without one (the default: claim it only where the manual gives
    /// it), a value is called good only when two reads agree
    /// ([`crate::session::Session::execute_confirmed`]).
    fn replies_checked(&self) -> bool {
        false
    }

    /// The position of an axis that `line`'s answer `value` gives, for
    /// judging it against the last one ([`crate::protocol::plausible`]);
    /// `None` (the default) for a line that reads no position.
    fn position_read(
        &self,
        _line: &PreparedLine,
        _value: &ReplyValue,
    ) -> Option<crate::protocol::plausible::PositionRead> {
        None
    }

    /// The fastest any axis of the family moves, from its manual, in the
    /// unit of [`FamilyConsole::position_read`] per second; `None` (the
    /// default) where the manual gives no such number.
    fn top_speed(&self) -> Option<crate::protocol::plausible::TopSpeed> {
        None
    }

    /// A second read's value as it would read had the first read not
    /// changed it: `second` with what reading clears (a latched flag)
    /// taken from `first`, so that two reads can be compared. By default
    /// reading changes nothing.
    fn as_if_unread(
        &self,
        _line: &PreparedLine,
        _first: &ReplyValue,
        second: &ReplyValue,
    ) -> ReplyValue {
        second.clone()
    }

    /// The choices about reading the link that the family's manual
    /// leaves open ([`LinkOption`]); none by default.
    fn link_options(&self) -> &'static [LinkOption] {
        &[]
    }

    /// The axes of a module of this family.
    fn axes(&self) -> &'static [AxisInfo];

    /// Parse and validate a console line for the module at `address`. An
    /// error is the family's own, naming what is wrong; nothing may be
    /// sent then.
    fn prepare(&self, line: &str, address: u8) -> Result<PreparedLine, LineError>;

    /// Cautions about a prepared line that do not stop it being sent (a
    /// value the manual advises against, a setting that clashes with one
    /// written before, as `known` has it): shown before sending, on
    /// stderr in batch use. None by default.
    fn warnings(&self, line: &PreparedLine, known: &SettingsCache) -> Vec<String> {
        let _ = (line, known);
        Vec::new()
    }

    /// The parameters (rows of [`FamilyConsole::parameters`]) that `line`
    /// writes once sent, with their values: what the console knows of
    /// settings a module cannot be asked for ([`SettingsCache`]). None by
    /// default.
    fn settings_written(&self, line: &PreparedLine) -> Vec<SettingWrite> {
        let _ = line;
        Vec::new()
    }

    /// Why no setting written before is known any more once `line` was
    /// sent and `reading` came of it: the module was reset (SIXpack 2
    /// `$CC`, or the reset flag of `$43`, §7.4). `None` by default.
    fn settings_lost(&self, line: &PreparedLine, reading: &Reading) -> Option<String> {
        let _ = (line, reading);
        None
    }

    /// Why `line` must not be sent without the user's confirmation (it
    /// moves at once, resets the module, cuts the connection…), if it
    /// must not: the console asks, batch use needs `--yes`. `None` by
    /// default.
    fn confirmation(&self, line: &PreparedLine) -> Option<String> {
        let _ = line;
        None
    }

    /// Whether `line` may keep the module busy for long, and how to abort
    /// or pause it meanwhile. `None` (the default): it is answered within
    /// the link's usual timeout.
    fn long_running(&self, line: &PreparedLine) -> Option<LongRunning> {
        let _ = line;
        None
    }

    /// Bytes that cut the answer to `line`, a status read, short while the
    /// controller gives it, so that an emergency stop need not wait for a
    /// long answer on a slow line (the device task's
    /// `Transaction::cut_short`). `None` (the default): it is waited for.
    fn cut_short(&self, line: &PreparedLine) -> Option<Vec<u8>> {
        let _ = line;
        None
    }

    /// The family's per-link state, if its lines change how later lines
    /// are written or read (see [`LinkContexts`]); `None` (the default):
    /// every line is sent and read the same way.
    fn link_contexts(&self) -> Option<&dyn LinkContexts> {
        None
    }

    /// What the answer to `line` means. `frames` are the frames of the
    /// answer as the device task collected them (empty when none came for
    /// an [`Answering::MaybeReply`] line).
    fn interpret(&self, line: &PreparedLine, frames: &[Frame]) -> Result<Reading, ReplyError>;

    /// The lines that stop every motor of the module at `address`.
    fn emergency_stop(&self, address: u8) -> Vec<PreparedLine>;

    /// [`FamilyConsole::emergency_stop`] in the light of what the session
    /// knows runs in the background (`running`): a family whose stop ends
    /// background programs one by one ends those known to run, and all of
    /// them only when it cannot know. By default: the whole stop.
    fn emergency_stop_knowing(&self, address: u8, running: &RunningPrograms) -> Vec<PreparedLine> {
        let _ = running;
        self.emergency_stop(address)
    }

    /// What runs in the background after `line` (`answer`: its value when
    /// it was answered with success; `None` when it failed, which may
    /// still have started something), given what was `known` before. By
    /// default nothing changes: the family's stop does not depend on it.
    fn running_after(
        &self,
        line: &PreparedLine,
        answer: Option<&ReplyValue>,
        known: RunningPrograms,
    ) -> RunningPrograms {
        let _ = (line, answer);
        known
    }

    /// The line asking the module at `address` who it is; its reading is
    /// the identity (TMCL: the firmware version string, 136 type 0).
    fn identify(&self, address: u8) -> PreparedLine;

    /// The lines that make up every axis's status.
    fn status_queries(&self, address: u8) -> Vec<StatusPoll>;

    /// What a successful reading of `line` says about the axes, if `line`
    /// reads status (a poll, or the user reading an error flag register:
    /// its flags must not be lost either): each update with its axis index.
    /// One reading may speak of several axes (CMD-4CR `PP` reads all four
    /// positions, §2.6.1.1).
    fn status_update(&self, line: &PreparedLine, reading: &Reading) -> Vec<(usize, AxisUpdate)>;

    /// [`FamilyConsole::status_update`] in the light of the settings the
    /// session knows were written (`known`): a family whose readings mean
    /// different things under different settings overrides this (SIXpack
    /// 2: whether a reference input is active high or low follows its
    /// motor's NullPositive flag, §6.4.2). By default settings change
    /// nothing.
    fn status_update_known(
        &self,
        line: &PreparedLine,
        reading: &Reading,
        known: &SettingsCache,
    ) -> Vec<(usize, AxisUpdate)> {
        let _ = known;
        self.status_update(line, reading)
    }

    /// The values [`FamilyConsole::status_queries`] read for every axis
    /// (the [`AxisUpdate`]s of [`FamilyConsole::status_update`]): the plot
    /// offers these and no others. Position and speed by default.
    fn status_values(&self) -> &'static [StatusValue] {
        &[StatusValue::Position, StatusValue::Speed]
    }

    /// Candidates for the word of `line` at byte offset `cursor`: command
    /// names, symbolic operands, parameter numbers (found by number or by
    /// name), from the family's catalogue. None by default.
    fn complete(&self, line: &str, cursor: usize) -> Completions {
        let _ = (line, cursor);
        Completions::default()
    }

    /// Help from the manual's tables for the word of `line` at `cursor`,
    /// read in its line (a command: its syntax, operands and ranges; a
    /// parameter number after `SAP`: that parameter's row), or for a topic
    /// (`line` = `SAP`, `SAP 4`, a parameter name). Empty when there is
    /// none.
    fn help(&self, line: &str, cursor: usize) -> Vec<String> {
        let _ = (line, cursor);
        Vec::new()
    }

    /// The console line that stops one axis normally (TMCL `MST 0`), for
    /// a stop key in the axis pane; `None` if the family has none.
    fn stop_axis_line(&self, axis: u8) -> Option<String> {
        let _ = axis;
        None
    }

    /// The console line that clears the latched error flags of one axis in
    /// the module, sent when the user clears them (F8, `:clear`) so that
    /// the next status poll does not bring them back (CMD-4CR `CLR[axis]`:
    /// MST error bits stay set until it, §2.6.2.3). `None` when the module
    /// needs none (TMCL: reading AP207 clears its flags, §4 Table 16).
    fn clear_errors_line(&self, axis: u8) -> Option<String> {
        let _ = axis;
        None
    }

    /// The conditions of an axis shown as lamps, each lit while the
    /// driver flags ([`AxisUpdate::DriverFlags`]) name it (CMD-4CR: the
    /// input and wait bits of MST). Empty (the default): the lit ones are
    /// listed as text.
    fn lamps(&self) -> &'static [AxisFlag] {
        &[]
    }

    /// How to show the load reading on a gauge, if the family has one.
    fn load_scale(&self) -> Option<LoadScale> {
        None
    }

    /// What an answer's status code means, in the manual's words.
    fn status_meaning(&self, status: u32) -> Option<String> {
        let _ = status;
        None
    }

    /// The family's standalone programs: their language's check, colours,
    /// watch and run control, and how a program reaches the controller;
    /// `None` if the family has none.
    fn program(&self) -> Option<&'static dyn ProgramTool> {
        None
    }

    /// How the family's raw positions, speeds and accelerations relate to
    /// motor steps, from its manual, and where a line's operands are: for
    /// values given and shown in an axis's own units
    /// ([`crate::protocol::units`]). `None` (the default): raw only.
    fn units(&self) -> Option<&'static dyn super::units::UnitLaw> {
        None
    }

    /// How an axis of this family is jogged by hand (the bring-up pane);
    /// `None` if the console does not know.
    fn jog(&self) -> Option<&'static dyn crate::protocol::jog::JogPlan> {
        None
    }

    /// The module's inputs, outputs and switches, from its manual (the
    /// bring-up pane's lamps); `None` if the console does not know.
    fn io(&self) -> Option<&'static dyn crate::protocol::io::IoPlan> {
        None
    }

    /// A servo step-response test the controller records itself (the
    /// tuning pane, `axterm tune step`); `None` where the family has none.
    fn step_response(&self) -> Option<&'static dyn crate::protocol::tuning::StepResponsePlan> {
        None
    }

    /// A StallGuard2-style load sweep (the tuning pane, `axterm tune
    /// stallguard`); `None` where the family has none.
    fn stall_sweep(&self) -> Option<&'static dyn crate::protocol::tuning::StallSweepPlan> {
        None
    }

    /// A load-adaptive current control (TMCL CoolStep: the form, a watch of
    /// current and load); `None` where the family has none.
    fn current_control(&self) -> Option<&'static dyn crate::protocol::tuning::CurrentControlPlan> {
        None
    }

    /// The family's parameter tables and how to read, write, store and
    /// restore one, for the parameter table; `None` if it has none.
    fn parameters(&self) -> Option<&'static dyn ParameterSet> {
        None
    }

    /// A frame sent to the module in words, for the traffic monitor: its
    /// console line. `None`: the family has no decoder and the monitor
    /// shows the bytes only.
    fn describe_request(&self, bytes: &[u8]) -> Option<String> {
        let _ = bytes;
        None
    }

    /// A frame from the module in words: its status meaning and value,
    /// read in the light of `request`, the last frame sent, if any.
    fn describe_reply(&self, bytes: &[u8], request: Option<&[u8]>) -> Option<String> {
        let _ = (bytes, request);
        None
    }
}
