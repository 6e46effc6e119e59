//! What the console knows of one connected controller: its axes and their
//! status snapshots, its identity, the connection state. Built from a
//! family's protocol knowledge ([`crate::protocol::console`]) on top of the
//! device task.
//!
//! Every front end goes through [`Session::execute_line`]: the line is
//! parsed and validated by the family first (nothing is sent if that
//! fails), sent at user priority (reads may be retried, anything that moves
//! or writes never), and the answer read back as a value or an error that
//! names the line and the module's status.
//!
//! A line the family says may run for long ([`FamilyConsole::long_running`])
//! is sent held: no reply timeout, the module busy ([`Session::busy`]) until
//! its answer, its abort and pause bytes sent on request
//! ([`Session::abort_line`], [`Session::pause_line`]) and before an
//! emergency stop.
//!
//! Where the family keeps a per-link state ([`LinkContexts`]: MCCL's number
//! base, prompt and echo), the session holds the current one: learned from
//! the family's probe at connect, every line (typed, polled, stopping,
//! transferring) adapted to it when sent and its answer read in it, and
//! replaced by what a successful line leaves behind. Polling pauses while a
//! line that changes it is on its way, and resumes adapted to the new one.

mod cadence;
mod host_run;
mod later;
pub mod params;
pub mod run_end;
pub mod settings;
pub mod sheet;
mod status;
pub mod transfer;
pub mod tuning;
mod units;
pub mod wiring;

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::sync::watch;

pub use crate::protocol::console::{AxisFlag, AxisInfo, PreparedLine, ReplyError, ReplyValue};
pub use cadence::{
    LAMP_PERIOD, PollCadence, SLOW_SHARE_DIVISOR, URGENT_SHARE_MOST, slow_period, urgent_period,
};
pub use status::{AxisMotion, AxisStatus, RefreshRate, RestRead, RestSign, WatchedValue};
pub use transfer::Cancel;

use crate::device::{
    self, Busy, DeviceError, DeviceHandle, DeviceOptions, Expect, Hold, LinkState, PollItem,
    PollOwner, PollPlan, Priority, Retry, Transaction,
};
use crate::link::{LinkError, LinkSpec};
use crate::protocol::Family;
use crate::protocol::console::{
    Answering, Effect, FamilyConsole, LinkContext, LinkContexts, RunningPrograms, StatusPoll,
    adapt_line, interpret_line,
};
use crate::protocol::plausible::{self, PositionRead, Sighting};
use status::{StatusBoard, StatusSink};

/// Further attempts for a read whose reply was lost or garbled.
pub const DEFAULT_READ_RETRIES: u32 = 2;

/// The most reads [`Session::read_agreed`] makes of a value whose answers
/// carry no check, looking for two in a row that agree.
pub const READS_TO_AGREE: usize = 3;

/// How a session talks to its controller.
#[derive(Debug, Clone)]
pub struct SessionOptions {
    /// Module address; the family's default when `None`.
    pub address: Option<u8>,
    /// Further attempts for reads (never for anything else).
    pub read_retries: u32,
    pub device: DeviceOptions,
}

impl Default for SessionOptions {
    fn default() -> Self {
        SessionOptions {
            address: None,
            read_retries: DEFAULT_READ_RETRIES,
            device: DeviceOptions::default(),
        }
    }
}

/// What came back for one line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LineResult {
    /// The line as the family writes it (`SAP 4, 0, 1234`).
    pub line: String,
    /// The bytes sent.
    pub request: Vec<u8>,
    /// The answer's bytes, every frame in order (empty if none came).
    pub reply: Vec<u8>,
    /// The status code the answer carried, where the family has one.
    pub status: Option<u32>,
    pub value: ReplyValue,
    /// From the last attempt's first byte written to its answer.
    pub elapsed: Duration,
    pub attempts: u32,
}

/// Why a line did not succeed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SessionError {
    /// Refused before anything was sent: it does not parse, or the family
    /// says the module would not accept it.
    #[error("{message}")]
    Refused { line: String, message: String },
    /// The module answered with an error status, or with an answer that
    /// makes no sense for the request.
    #[error("{error}")]
    Reply {
        error: Box<ReplyError>,
        request: Vec<u8>,
        reply: Vec<u8>,
        elapsed: Duration,
    },
    /// No answer: timeout, link lost, device task ended.
    #[error("module {address} did not answer {line}: {error}")]
    Device {
        line: String,
        address: u8,
        request: Vec<u8>,
        error: DeviceError,
    },
}

impl SessionError {
    /// True when nothing was sent (a usage error, not a device error).
    pub fn nothing_sent(&self) -> bool {
        matches!(self, SessionError::Refused { .. })
    }

    /// The line as the family writes it (`MST 0`).
    pub fn line(&self) -> &str {
        match self {
            SessionError::Refused { line, .. } | SessionError::Device { line, .. } => line,
            SessionError::Reply { error, .. } => match error.as_ref() {
                ReplyError::Rejected { line, .. }
                | ReplyError::Refused { line, .. }
                | ReplyError::Malformed { line, .. } => line,
            },
        }
    }

    /// The bytes sent, if any were.
    pub fn request(&self) -> Option<&[u8]> {
        match self {
            SessionError::Refused { .. } => None,
            SessionError::Reply { request, .. } | SessionError::Device { request, .. } => {
                Some(request)
            }
        }
    }

    /// The bytes of an answer that was an error.
    pub fn reply(&self) -> Option<&[u8]> {
        match self {
            SessionError::Reply { reply, .. } => Some(reply),
            _ => None,
        }
    }

    /// The status code of a rejection.
    pub fn status(&self) -> Option<u32> {
        match self {
            SessionError::Reply { error, .. } => error.status(),
            _ => None,
        }
    }
}

/// The error for a line whose answer came garbled: what the family makes
/// of the bytes that came instead (CMD-4CR: "`fK` is not OK, the answer
/// to a write or action"; TMCL: a wrong checksum), with those bytes as the
/// reply. Never a success, whatever the bytes say.
fn garbled(
    console: &dyn FamilyConsole,
    line: &PreparedLine,
    received: Vec<u8>,
    timeout: Duration,
    context: Option<&dyn LinkContext>,
) -> SessionError {
    let why = match interpret_line(console, line, std::slice::from_ref(&received), context) {
        Err(ReplyError::Malformed { reason, .. }) => reason,
        _ => "it is not an answer to this line".to_string(),
    };
    SessionError::Reply {
        error: Box::new(ReplyError::Malformed {
            line: line.canonical.clone(),
            reason: format!(
                "{why} (garbled: nothing readable came within {} ms)",
                timeout.as_millis()
            ),
        }),
        request: line.bytes.clone(),
        reply: received,
        elapsed: timeout,
    }
}

/// Between the two status reads of [`Session::moving_axes`]: a motion just
/// started shows by then (a module may read speed 0 for its first
/// moments, while it starts to accelerate).
pub const MOTION_START_GRACE: Duration = Duration::from_millis(100);

/// Whether a value `line` reads is called good only once a second read
/// agrees ([`Session::execute_confirmed`]): a read of a family whose
/// answers carry no check of their own.
pub fn confirms_reads(console: &dyn FamilyConsole, line: &PreparedLine) -> bool {
    line.effect == Effect::Reads && !console.replies_checked()
}

/// Whether `result` holds a value a reply carried (a frame that gets no
/// reply, "sent", holds none) from a family whose replies carry no check
/// ([`FamilyConsole::replies_checked`]): nothing on the wire vouches for
/// its digits, and every front end says so.
pub fn read_unchecked(console: &dyn FamilyConsole, result: &LineResult) -> bool {
    !result.reply.is_empty() && result.value != ReplyValue::None && !console.replies_checked()
}

/// One connected controller. Cheap to clone; clones share everything.
#[derive(Clone)]
pub struct Session {
    device: DeviceHandle,
    family: &'static Family,
    address: u8,
    read_retries: u32,
    board: StatusBoard,
    identity: Arc<watch::Sender<Option<String>>>,
    /// The poll cadence asked for, if polling is on (paused while a
    /// program transfer holds the module, see [`transfer`]).
    polling: Arc<Mutex<Option<PollCadence>>>,
    transfer: Arc<transfer::TransferState>,
    /// One byte's wire time on the link, when it has a known speed.
    byte_time: Option<Duration>,
    /// The settings written this session ([`settings`]).
    settings: settings::SharedSettings,
    /// The family's per-link state, where it keeps one.
    context: Arc<watch::Sender<Option<Arc<dyn LinkContext>>>>,
    /// Whose poll plan this module's is: modules on one link (a bus,
    /// [`Session::at_address`]) each poll by their own, in turn.
    poll_owner: PollOwner,
    /// Lines read with the status for someone watching them (a plotted
    /// parameter), as slow items ([`Session::watch`]).
    watches: Arc<Mutex<Vec<StatusPoll>>>,
    /// What runs in the background, as far as the lines sent and their
    /// answers tell ([`FamilyConsole::running_after`]): the emergency stop
    /// ends those ([`FamilyConsole::emergency_stop_knowing`]). Not known
    /// on connecting: the module may run what it was left running.
    running: Arc<Mutex<RunningPrograms>>,
    /// The last position read of each axis and when, where the family's
    /// answers carry no checksum: a read that jumps further than any axis
    /// goes is refused ([`crate::protocol::plausible`]). Forgotten when a
    /// line that acts is sent (it may set a position).
    positions: Arc<Mutex<HashMap<usize, SeenPosition>>>,
}

/// A position read and when its answer came.
#[derive(Debug, Clone, Copy)]
struct SeenPosition {
    read: PositionRead,
    at: tokio::time::Instant,
    round_trip: Duration,
}

/// The device's hold for a line the family says may run for long.
fn hold_of(console: &dyn FamilyConsole, line: &PreparedLine) -> Option<Hold> {
    console.long_running(line).map(|long| Hold {
        abort: long.abort,
        pause: long.pause,
    })
}

impl Session {
    /// Open `spec` and start the device task for `family`.
    pub async fn connect(
        spec: LinkSpec,
        family: &'static Family,
        options: SessionOptions,
    ) -> Result<Session, LinkError> {
        let byte_time = spec.byte_time();
        let device = device::connect(spec, family.console.wire(), options.device.clone()).await?;
        let session = Session::new(device, family, &options).with_byte_time(byte_time);
        // A probe that fails leaves the family's defaults: the lines after
        // it show what does not fit.
        let _ = session.learn_link().await;
        Ok(session)
    }

    /// A session over a device task already running.
    pub fn new(device: DeviceHandle, family: &'static Family, options: &SessionOptions) -> Session {
        let axes = family.console.axes().len();
        let (board, _) = watch::channel(vec![AxisStatus::default(); axes]);
        let (identity, _) = watch::channel(None);
        let (context, _) = watch::channel(family.console.link_contexts().map(|c| c.initial()));
        Session {
            family,
            address: options
                .address
                .unwrap_or_else(|| family.console.default_address()),
            read_retries: options.read_retries,
            board: Arc::new(board),
            identity: Arc::new(identity),
            polling: Arc::new(Mutex::new(None)),
            transfer: Arc::new(transfer::TransferState::default()),
            byte_time: None,
            settings: settings::new_cache(device.state()),
            context: Arc::new(context),
            poll_owner: PollOwner::new(),
            watches: Arc::new(Mutex::new(Vec::new())),
            running: Arc::new(Mutex::new(RunningPrograms::Unknown)),
            positions: Arc::new(Mutex::new(HashMap::new())),
            device,
        }
    }

    /// The same session on a link whose byte takes `byte_time` on the
    /// wire (`None`: unknown): the poll plan is fitted to it.
    pub fn with_byte_time(mut self, byte_time: Option<Duration>) -> Session {
        self.byte_time = byte_time;
        self
    }

    /// A session on the same link and device task for the module at
    /// `address`, with status of its own and polling off.
    pub fn at_address(&self, address: u8) -> Session {
        let options = SessionOptions {
            address: Some(address),
            read_retries: self.read_retries,
            device: DeviceOptions::default(),
        };
        Session {
            context: Arc::clone(&self.context),
            ..Session::new(self.device.clone(), self.family, &options)
                .with_byte_time(self.byte_time)
        }
    }

    pub fn family(&self) -> &'static Family {
        self.family
    }

    /// The module address lines are sent to.
    pub fn address(&self) -> u8 {
        self.address
    }

    /// The module's axes, in the order of [`Session::status`].
    pub fn axes(&self) -> &'static [AxisInfo] {
        self.family.console.axes()
    }

    /// The device task, for traffic, events and counters.
    pub fn device(&self) -> &DeviceHandle {
        &self.device
    }

    /// The link as the console shows it.
    pub fn link_state(&self) -> watch::Receiver<LinkState> {
        self.device.state()
    }

    /// Every axis's status snapshot, updated by polling and by the replies
    /// to the user's own status reads.
    pub fn status(&self) -> watch::Receiver<Vec<AxisStatus>> {
        self.board.subscribe()
    }

    /// The held line on the wire, if any: a line that runs until its answer
    /// (the console shows it busy, with its abort and pause keys).
    pub fn busy(&self) -> watch::Receiver<Option<Busy>> {
        self.device.busy()
    }

    /// Abort the held line on the wire (MCCL: Escape): its answer (the
    /// controller's error) ends it. Whether one was held.
    pub async fn abort_line(&self) -> bool {
        self.device.abort_line().await
    }

    /// Pause the held line on the wire, or resume it (MCCL: Space): whether
    /// it is paused now; `None` when no line that can pause is held.
    pub async fn pause_line(&self) -> Option<bool> {
        self.device.pause_line().await
    }

    /// The family's per-link state, where it keeps one (see
    /// [`LinkContexts`]).
    pub fn link_context(&self) -> watch::Receiver<Option<Arc<dyn LinkContext>>> {
        self.context.subscribe()
    }

    fn current_context(&self) -> Option<Arc<dyn LinkContext>> {
        self.context.borrow().clone()
    }

    fn contexts(&self) -> Option<&'static dyn LinkContexts> {
        self.family.console.link_contexts()
    }

    /// Send the family's connect probe and keep what it shows (MCCL: the
    /// echo, the prompt and its granularity, from `NO` and `NO,NO,NO`).
    /// `None` when the family has no probe; an error says why nothing was
    /// learned (the defaults stay).
    pub async fn learn_link(&self) -> Option<Result<(), String>> {
        let contexts = self.contexts()?;
        let probe = contexts.probe();
        if probe.is_empty() {
            return None;
        }
        let mut answers = Vec::new();
        for bytes in probe {
            let transaction = Transaction::new(bytes, Expect::UntilQuiet, Retry::Never);
            match self.device.transact(Priority::User, transaction).await {
                Ok(answer) => answers.push(answer.frames.concat()),
                Err(error) => {
                    return Some(Err(format!("the connect probe got no answer: {error}")));
                }
            }
        }
        let context = self.current_context()?;
        Some(
            contexts
                .learn(context.as_ref(), &answers)
                .map(|learned| self.set_context(learned))
                .map_err(|e| e.to_string()),
        )
    }

    /// Take the per-link state a line left behind; the poll plan follows.
    fn set_context(&self, context: Arc<dyn LinkContext>) {
        self.context.send_replace(Some(context));
        self.resume_polling();
    }

    /// Apply the poll plan again if polling is on and no transfer holds
    /// the module.
    fn resume_polling(&self) {
        if let Some(cadence) = self.poll_cadence()
            && !self.transfer.held()
        {
            self.apply_poll_plan(cadence);
        }
    }

    /// The module's identity (firmware string), once [`Session::identify`]
    /// has read it.
    pub fn identity(&self) -> watch::Receiver<Option<String>> {
        self.identity.subscribe()
    }

    /// Forget the error flags of `axis` the user has seen (those shown to
    /// them); flags that arrived since stay latched.
    pub fn acknowledge_errors(&self, axis: usize, seen: &[AxisFlag]) {
        self.board.send_modify(|axes| {
            if let Some(status) = axes.get_mut(axis) {
                status.acknowledge(seen);
            }
        });
    }

    /// Clear the error flags of `axis`: in the module first, where the
    /// family has a line for it (CMD-4CR `CLRX`; TMCL needs none), then on
    /// screen, forgetting the flags the user has seen. The clear line goes
    /// at user priority, so at most the poll already on the wire comes
    /// before it; a poll after it reads the flags cleared. If the module
    /// refuses it or does not answer, the flags stay latched.
    pub async fn clear_errors(
        &self,
        axis: usize,
        seen: &[AxisFlag],
    ) -> Result<Option<LineResult>, SessionError> {
        let line = self
            .axes()
            .get(axis)
            .and_then(|a| self.family.console.clear_errors_line(a.number));
        let result = match line {
            Some(line) => Some(self.execute_line(&line).await?),
            None => None,
        };
        self.acknowledge_errors(axis, seen);
        Ok(result)
    }

    /// Parse and validate a line for this session's module. Sends nothing.
    pub fn prepare(&self, line: &str) -> Result<PreparedLine, SessionError> {
        self.family
            .console
            .prepare(line, self.address)
            .map_err(|error| SessionError::Refused {
                line: line.trim().to_string(),
                message: error.to_string(),
            })
    }

    /// Parse, validate, send at user priority and read the answer.
    pub async fn execute_line(&self, line: &str) -> Result<LineResult, SessionError> {
        let prepared = self.prepare(line)?;
        self.execute(&prepared).await
    }

    /// Parse, validate and send a line that stops motion (a jog's stop)
    /// ahead of everything queued, as the emergency stop goes: a status
    /// read on the wire is cut short for it where the family can
    /// ([`crate::protocol::FamilyConsole::cut_short`]). Sent once, never
    /// again after a timeout.
    pub async fn execute_stop_line(&self, line: &str) -> Result<LineResult, SessionError> {
        let prepared = self.prepare(line)?;
        self.execute_at(Priority::EmergencyStop, &prepared).await
    }

    /// Send a prepared line at user priority and read the answer. While a
    /// program transfer holds the module (TMCL download mode), lines it
    /// would misread are refused (nothing is sent).
    pub async fn execute(&self, line: &PreparedLine) -> Result<LineResult, SessionError> {
        self.execute_at(Priority::User, line).await
    }

    async fn execute_at(
        &self,
        priority: Priority,
        line: &PreparedLine,
    ) -> Result<LineResult, SessionError> {
        if let Some(message) = self.transfer.refusal(line) {
            return Err(SessionError::Refused {
                line: line.canonical.clone(),
                message,
            });
        }
        let retry = match (line.effect, priority) {
            (Effect::Reads, Priority::User) => Retry::Read(self.read_retries),
            _ => Retry::Never,
        };
        let result = self.send(priority, line, retry, None).await;
        if line.effect == Effect::Acts {
            self.positions
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .clear();
        }
        let result = result?;
        transfer::after_user_line(self, line);
        self.position_plausible(line, &result)?;
        Ok(result)
    }

    /// Refuse a position read that moved further since the last read of
    /// its axis than the family's fastest motion allows (only where the
    /// answers carry no checksum to tell a damaged one); remember it
    /// otherwise. A refused reading is forgotten with the last one: the
    /// next read is taken as it comes, so one wrong call cannot repeat.
    fn position_plausible(
        &self,
        line: &PreparedLine,
        result: &LineResult,
    ) -> Result<(), SessionError> {
        let console = self.family.console;
        if console.replies_checked() {
            return Ok(());
        }
        let (Some(top), Some(read)) = (
            console.top_speed(),
            console.position_read(line, &result.value),
        ) else {
            return Ok(());
        };
        let now = SeenPosition {
            read,
            at: tokio::time::Instant::now(),
            round_trip: result.elapsed,
        };
        let mut positions = self.positions.lock().unwrap_or_else(|e| e.into_inner());
        let verdict = match positions.get(&read.axis) {
            Some(last) => plausible::judge(
                &Sighting {
                    read: last.read,
                    at: Duration::ZERO,
                    round_trip: last.round_trip,
                },
                &Sighting {
                    read: now.read,
                    at: now.at.saturating_duration_since(last.at),
                    round_trip: now.round_trip,
                },
                top,
            ),
            None => Ok(()),
        };
        match verdict {
            Ok(()) => {
                positions.insert(read.axis, now);
                Ok(())
            }
            Err(reason) => {
                positions.remove(&read.axis);
                Err(SessionError::Reply {
                    error: Box::new(ReplyError::Malformed {
                        line: line.canonical.clone(),
                        reason,
                    }),
                    request: result.request.clone(),
                    reply: result.reply.clone(),
                    elapsed: result.elapsed,
                })
            }
        }
    }

    /// Send a prepared line as [`Session::execute`] does and judge its
    /// answer with `good` (what `:expect` and `:wait-until` ask of it).
    /// A read of a family whose answers carry no check of their own
    /// ([`FamilyConsole::replies_checked`]: SIXpack 2, CMD-4CR, MCCL) that
    /// looks good is read once more, and called good only if the second
    /// answer is good too (they agree on what `good` judges; the rest of a
    /// reply, a position while a search runs, may move between them; what
    /// the first read cleared is taken as it left it,
    /// [`FamilyConsole::as_if_unread`]): one damaged answer cannot pass.
    /// The result is the last answer read, and whether it is good.
    pub async fn execute_confirmed(
        &self,
        line: &PreparedLine,
        good: impl Fn(&LineResult) -> bool,
    ) -> Result<(LineResult, bool), SessionError> {
        let first = self.execute(line).await?;
        if !good(&first) || !confirms_reads(self.family.console, line) {
            let verdict = good(&first);
            return Ok((first, verdict));
        }
        let second = self.execute(line).await?;
        let as_if_unread = LineResult {
            value: (self
                .family
                .console
                .as_if_unread(line, &first.value, &second.value)),
            ..second.clone()
        };
        let verdict = good(&as_if_unread);
        Ok((second, verdict))
    }

    /// Read `line` until two answers in a row agree, if the family's
    /// answers carry no check ([`confirms_reads`]; at most
    /// [`READS_TO_AGREE`] reads), else once: what the parameter reads of
    /// `axterm params` call a value. Reads that never agree are an
    /// unreadable answer naming what came.
    pub async fn read_agreed(&self, line: &PreparedLine) -> Result<LineResult, SessionError> {
        let mut last = self.execute(line).await?;
        if !confirms_reads(self.family.console, line) {
            return Ok(last);
        }
        let mut values = vec![last.value.to_string()];
        while values.len() < READS_TO_AGREE {
            let next = self.execute(line).await?;
            let as_if_unread = self
                .family
                .console
                .as_if_unread(line, &last.value, &next.value);
            if as_if_unread == last.value {
                return Ok(next);
            }
            values.push(next.value.to_string());
            last = next;
        }
        Err(SessionError::Reply {
            error: Box::new(ReplyError::Malformed {
                line: line.canonical.clone(),
                reason: format!(
                    "{READS_TO_AGREE} reads, no two in a row agree ({}): {} answers carry no \
                     checksum to tell the good one",
                    values.join(", "),
                    self.family.name
                ),
            }),
            request: line.bytes.clone(),
            reply: last.reply,
            elapsed: last.elapsed,
        })
    }

    /// Stop every motor, ahead of everything queued. Every stop line is
    /// sent even if one fails; the first failure is returned.
    ///
    /// A program transfer is cancelled. While a transfer holds the module
    /// (TMCL download mode stores what it is sent instead of executing
    /// it), the stop waits until the transfer has let it go (the line on
    /// the wire and the release: two transactions), or sends the release
    /// first if that failed (see [`transfer`]).
    pub async fn emergency_stop(&self) -> Result<(), SessionError> {
        let results = self.emergency_stop_lines().await;
        results
            .into_iter()
            .find_map(Result::err)
            .map_or(Ok(()), Err)
    }

    /// [`Session::emergency_stop`], with what came back for each stop line
    /// in order, for a console that confirms them.
    ///
    /// Every line is queued at once, in order: sent one after the other's
    /// answer, a line waiting in the user queue would go on the wire
    /// between two stop lines (a move between `MST` and `STOPAPP`).
    ///
    /// While a transfer holds the module, the stop first waits for it to
    /// let the module go (see [`Session::emergency_stop`]), or sends the
    /// hold's release line itself as the first line.
    pub async fn emergency_stop_lines(&self) -> Vec<Result<LineResult, SessionError>> {
        let halted = transfer::halt_transfer(self).await;
        let leave = halted.release().cloned();
        let running = self.running_programs();
        let lines: Vec<PreparedLine> = leave
            .iter()
            .cloned()
            .chain(
                self.family
                    .console
                    .emergency_stop_knowing(self.address, &running),
            )
            .collect();
        let mut sends: Vec<_> = lines
            .iter()
            .map(|line| Box::pin(self.send(Priority::EmergencyStop, line, Retry::Never, None)))
            .collect();
        let mut results: Vec<Option<Result<LineResult, SessionError>>> =
            sends.iter().map(|_| None).collect();
        // Polled in order, so the first poll of each queues it in order.
        std::future::poll_fn(|cx| {
            let mut pending = false;
            for (send, result) in sends.iter_mut().zip(results.iter_mut()) {
                if result.is_none() {
                    match send.as_mut().poll(cx) {
                        std::task::Poll::Ready(r) => *result = Some(r),
                        std::task::Poll::Pending => pending = true,
                    }
                }
            }
            if pending {
                std::task::Poll::Pending
            } else {
                std::task::Poll::Ready(())
            }
        })
        .await;
        drop(sends);
        let results: Vec<_> = results.into_iter().flatten().collect();
        if leave.is_some() && results.first().is_some_and(Result::is_ok) {
            halted.released();
        }
        // Every stop line answered: every background program it ends is
        // ended (a line sent since may have started one again: it said so
        // when its answer came, after the stop's, which jumped it).
        if !results.is_empty() && results.iter().all(Result::is_ok) {
            *self.running.lock().unwrap_or_else(|e| e.into_inner()) =
                RunningPrograms::Known(Vec::new());
        }
        results
    }

    /// What runs in the background after `line`, `answer`ed or not.
    fn note_running(&self, line: &PreparedLine, answer: Option<&ReplyValue>) {
        if line.address != self.address {
            return;
        }
        let mut running = self.running.lock().unwrap_or_else(|e| e.into_inner());
        let known = std::mem::take(&mut *running);
        *running = self.family.console.running_after(line, answer, known);
    }

    /// What the session knows runs in the background
    /// ([`FamilyConsole::running_after`]).
    pub fn running_programs(&self) -> RunningPrograms {
        self.running
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// Read every axis's fast-changing status (the family's fast status
    /// polls: position, speed, motion phase) twice, [`MOTION_START_GRACE`]
    /// apart, and name the axes seen moving either time. Twice, because a module may still read speed 0 (and
    /// standing) just after a motion was started; for the end of a run
    /// that must not leave an axis moving.
    pub async fn moving_axes(&self) -> Result<Vec<&'static str>, SessionError> {
        let first = self.read_fast_status().await?;
        tokio::time::sleep(MOTION_START_GRACE).await;
        let second = self.read_fast_status().await?;
        let axes = self.axes();
        Ok(first
            .iter()
            .zip(&second)
            .enumerate()
            // Not a position that changed: a servo holding its place
            // dithers by a count or so.
            .filter(|(_, (before, now))| {
                before.motion() == AxisMotion::Moving || now.motion() == AxisMotion::Moving
            })
            .map(|(index, _)| axes.get(index).map_or("?", |a| a.name))
            .collect())
    }

    /// Send the family's fast status polls once; the status they leave.
    async fn read_fast_status(&self) -> Result<Vec<AxisStatus>, SessionError> {
        self.read_status_polls(true).await
    }

    /// Send every status poll of the family once (the switches are slow
    /// items in some), or only the fast ones; the status they leave.
    async fn read_status_polls(&self, fast_only: bool) -> Result<Vec<AxisStatus>, SessionError> {
        let polls = self.family.console.status_queries(self.address);
        for poll in polls.iter().filter(|p| p.fast || !fast_only) {
            self.send(
                Priority::User,
                &poll.line,
                Retry::Read(self.read_retries),
                None,
            )
            .await?;
        }
        Ok(self.board.borrow().clone())
    }

    /// Read the module's identity (TMCL: the firmware version string) and
    /// keep it for [`Session::identity`].
    pub async fn identify(&self) -> Result<String, SessionError> {
        let line = self.family.console.identify(self.address);
        let retry = Retry::Read(self.read_retries);
        let result = self.send(Priority::User, &line, retry, None).await?;
        let identity = result.value.to_string();
        self.identity.send_replace(Some(identity.clone()));
        Ok(identity)
    }

    /// Ask whoever answers at `address` who it is, once, waiting at most
    /// `timeout`: for scanning a bus.
    pub async fn probe(&self, address: u8, timeout: Duration) -> Result<String, SessionError> {
        let line = self.family.console.identify(address);
        let result = self
            .send(Priority::User, &line, Retry::Read(0), Some(timeout))
            .await?;
        Ok(result.value.to_string())
    }

    /// Poll every axis's status at `cadence` (replaces any earlier plan).
    /// While a transfer holds the module, polling starts once it lets go.
    pub fn start_polling(&self, cadence: PollCadence) {
        *self.polling.lock().unwrap_or_else(|e| e.into_inner()) = Some(cadence);
        if !self.transfer.held() {
            self.apply_poll_plan(cadence);
        }
    }

    pub fn stop_polling(&self) {
        *self.polling.lock().unwrap_or_else(|e| e.into_inner()) = None;
        self.pause_polling();
    }

    /// No polls until a plan is applied again; the cadence asked for is
    /// kept.
    fn pause_polling(&self) {
        self.device.set_poll_plan_of(self.poll_owner, None);
        // Nothing is refreshed any more.
        status::post_refresh(&self.board, None);
    }

    /// The poll cadence asked for, if polling is on.
    pub fn poll_cadence(&self) -> Option<PollCadence> {
        *self.polling.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Read `line` (a read of axis `axis`, as the family's parameter
    /// table writes it) with the status, as often as the slow items, until
    /// [`Session::unwatch`]: its value lands in the axis's
    /// [`AxisStatus::watched`]. A line that does not parse or only acts
    /// is refused, and nothing is polled.
    pub fn watch(&self, axis: usize, line: &str) -> Result<(), SessionError> {
        self.watch_at(axis, line, false)
    }

    /// [`Session::watch`], as an urgent poll when `fast` (a switch whose
    /// change must show at once): it goes before every other poll when
    /// due, at [`urgent_period`]. A line a status item reads already is
    /// not read twice: that item's answer is the watched line's too, and
    /// the item is urgent.
    pub fn watch_at(&self, axis: usize, line: &str, fast: bool) -> Result<(), SessionError> {
        let prepared = self.prepare(line)?;
        if prepared.effect != Effect::Reads || axis >= self.axes().len() {
            return Err(SessionError::Refused {
                line: prepared.canonical,
                message: format!(
                    "only a read of an axis of {} can be watched",
                    self.family.name
                ),
            });
        }
        {
            let mut watches = self.watches.lock().unwrap_or_else(|e| e.into_inner());
            if let Some(watch) = watches
                .iter_mut()
                .find(|w| w.axis == axis && w.line.canonical == prepared.canonical)
            {
                if watch.fast || !fast {
                    return Ok(());
                }
                watch.fast = true;
            } else {
                watches.push(StatusPoll {
                    axis,
                    line: prepared.clone(),
                    fast,
                });
            }
        }
        status::post_watched(&self.board, axis, &prepared.canonical, None);
        self.resume_polling();
        Ok(())
    }

    /// Stop reading `line` for axis `axis` ([`Session::watch`]).
    pub fn unwatch(&self, axis: usize, line: &str) {
        let canonical = self
            .prepare(line)
            .map_or_else(|_| line.trim().to_string(), |p| p.canonical);
        self.watches
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .retain(|w| !(w.axis == axis && w.line.canonical == canonical));
        status::forget_watched(&self.board, axis, &canonical);
        self.resume_polling();
    }

    fn apply_poll_plan(&self, cadence: PollCadence) {
        let console = self.family.console;
        let context = self.current_context();
        let mut polls: Vec<StatusPoll> = console
            .status_queries(self.address)
            .into_iter()
            .map(|poll| StatusPoll {
                line: adapt_line(console, &poll.line, context.as_deref()),
                ..poll
            })
            .collect();
        let status_items = polls.len();
        // Watched lines go with the slow items and share their cap on
        // the line's time; a line watched fast (a switch on the screen)
        // is urgent, and so is the status item that reads it already.
        let mut shared = Vec::new();
        let mut urgent = vec![false; status_items];
        for watch in self
            .watches
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .iter()
        {
            let watch = StatusPoll {
                line: adapt_line(console, &watch.line, context.as_deref()),
                ..watch.clone()
            };
            match polls[..status_items]
                .iter()
                .position(|p| p.line.canonical == watch.line.canonical)
            {
                Some(index) => {
                    // A switch watched fast that the status reads slowly
                    // (TMCL's AP 9-11) is read fast for everyone.
                    polls[index].fast |= watch.fast;
                    urgent[index] |= watch.fast;
                    shared.push((index, watch));
                }
                None => {
                    urgent.push(watch.fast);
                    polls.push(watch);
                }
            }
        }
        let wire = console.wire();
        let slow = slow_period(cadence, self.byte_time, wire.as_ref(), &polls);
        let lamps: Vec<&StatusPoll> = polls
            .iter()
            .zip(&urgent)
            .filter(|(_, u)| **u)
            .map(|(p, _)| p)
            .collect();
        let lamp = urgent_period(cadence, self.byte_time, wire.as_ref(), &lamps);
        let items = polls
            .iter()
            .zip(&urgent)
            .map(|(poll, &urgent)| PollItem {
                transaction: Transaction {
                    cut_short: console.cut_short(&poll.line),
                    ..self.transaction(&poll.line, Retry::Never, None)
                },
                every: match (urgent, poll.fast) {
                    (true, _) => lamp,
                    (false, true) => cadence.fast,
                    (false, false) => slow,
                },
                urgent,
            })
            .collect();
        let watched = polls.split_off(status_items);
        let sink = StatusSink::new(
            self.family,
            polls,
            Arc::clone(&self.board),
            context,
            Some(self.settings.subscribe()),
        )
        .with_watched(watched)
        .with_shared(shared);
        self.device.set_poll_plan_of(
            self.poll_owner,
            Some(PollPlan {
                items,
                sink: Box::new(sink),
            }),
        );
    }

    fn transaction(
        &self,
        line: &PreparedLine,
        retry: Retry,
        timeout: Option<Duration>,
    ) -> Transaction {
        let expect = match &line.answering {
            Answering::Reply(rule) | Answering::MaybeReply(rule) => Expect::Reply(Arc::clone(rule)),
            // Its answer is picked out of the news ([`later`]).
            Answering::Nothing | Answering::Later { .. } => Expect::Nothing,
        };
        Transaction {
            bytes: line.bytes.clone(),
            expect,
            retry,
            timeout,
            hold: hold_of(self.family.console, line),
            cut_short: None,
        }
    }

    async fn send(
        &self,
        priority: Priority,
        line: &PreparedLine,
        retry: Retry,
        timeout: Option<Duration>,
    ) -> Result<LineResult, SessionError> {
        // An answer that may be lost is never asked for twice.
        let retry = match line.answering {
            Answering::MaybeReply(_) => Retry::Never,
            _ => retry,
        };
        let console = self.family.console;
        let context = self.current_context();
        let line = &adapt_line(console, line, context.as_deref());
        // A line that changes the per-link state: no poll goes between it
        // and the plan adapted to what it leaves behind.
        let changes = match (self.contexts(), &context) {
            (Some(contexts), Some(context)) => contexts.after(line, context.as_ref()),
            _ => None,
        };
        let paused = changes.is_some() && priority != Priority::EmergencyStop;
        if paused {
            self.device.set_poll_plan_of(self.poll_owner, None);
        }
        let transaction = self.transaction(line, retry, timeout);
        // Taken as failed until answered: a line that may start a
        // background program makes it unknown from before it is sent, so
        // that an emergency stop pressed meanwhile ends every one.
        self.note_running(line, None);
        let result = self
            .send_adapted(priority, line, transaction, context.as_deref())
            .await;
        if let Ok(answer) = &result {
            self.note_running(line, Some(&answer.value));
        }
        match (&result, changes) {
            (Ok(_), Some(changed)) => self.set_context(changed),
            _ if paused => self.resume_polling(),
            _ => {}
        }
        result
    }

    /// Send a line already adapted to `context` and read its answer there.
    async fn send_adapted(
        &self,
        priority: Priority,
        line: &PreparedLine,
        transaction: Transaction,
        context: Option<&dyn LinkContext>,
    ) -> Result<LineResult, SessionError> {
        let console = self.family.console;
        let later = later::LaterAnswer::for_line(&line.answering, || self.device.events());
        let answered = match self.device.transact(priority, transaction).await {
            Ok(answer) => match later {
                Some(later) => later.wait().await.map(|(frames, elapsed)| device::Answer {
                    frames,
                    elapsed,
                    attempts: answer.attempts,
                }),
                None => Ok(answer),
            },
            Err(error) => Err(error),
        };
        let (frames, elapsed, attempts) = match answered {
            Ok(answer) => (answer.frames, answer.elapsed, answer.attempts),
            // An answer that may be lost is not needed.
            Err(
                DeviceError::Timeout { timeout, attempts }
                | DeviceError::Garbled {
                    timeout, attempts, ..
                },
            ) if matches!(line.answering, Answering::MaybeReply(_)) => {
                (Vec::new(), timeout, attempts)
            }
            Err(DeviceError::Garbled {
                timeout, received, ..
            }) => {
                return Err(garbled(console, line, received, timeout, context));
            }
            Err(error) => {
                return Err(SessionError::Device {
                    line: line.canonical.clone(),
                    address: line.address,
                    request: line.bytes.clone(),
                    error,
                });
            }
        };
        let reply: Vec<u8> = frames.concat();
        let reading = interpret_line(console, line, &frames, context).map_err(|error| {
            SessionError::Reply {
                error: Box::new(error),
                request: line.bytes.clone(),
                reply: reply.clone(),
                elapsed,
            }
        })?;
        if line.address == self.address {
            let updates = console.status_update_known(line, &reading, &self.settings.borrow());
            for (axis, update) in updates {
                status::post(&self.board, axis, update);
            }
            settings::record(&self.settings, console, line, &reading);
        }
        Ok(LineResult {
            line: line.canonical.clone(),
            request: line.bytes.clone(),
            reply,
            status: reading.status,
            value: reading.value,
            elapsed,
            attempts,
        })
    }
}
