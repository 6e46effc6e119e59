//! The device task: the one owner of a link. It holds exactly one request
//! in flight (every bus axterm speaks is strict master/slave), picks the
//! next by priority, matches replies to the request in flight through the
//! family's [`WireFormat`], polls status when nothing else is waiting, and
//! survives timeouts, garbage and lost links.
//!
//! It knows nothing of any family beyond [`crate::protocol::wire`].
//!
//! # The loop
//!
//! One tokio task per link ([`spawn`], [`connect`]) owns the link's two
//! channels. While connected it goes round one loop:
//!
//! 1. Take every order waiting (requests go into one queue per
//!    [`Priority`]; requests that arrive while a transaction is on the wire
//!    are queued the same way) and, when no poll of the current plan is
//!    pending, the newest [`PollPlan`].
//! 2. Process the input already received: complete frames answer nothing
//!    now, so each is the late answer to an unanswered attempt (see below),
//!    unsolicited news ([`WireFormat::unsolicited`], published as
//!    [`DeviceEvent::Unsolicited`]) or stale (logged, counted, never
//!    delivered). A partial frame is dropped as garbage once the line has
//!    been quiet for [`WireFormat::silence`].
//! 3. Pick the next job: the head of the highest non-empty queue
//!    (emergency stop, user, transfer, poll); only when every queue is empty,
//!    the most overdue item of the poll plan. If the line must settle first
//!    (see below), wait, still taking orders, so that an emergency stop that
//!    arrives meanwhile goes first. A line's deadline is absolute: bytes
//!    that keep coming without the line ever falling silent (a device that
//!    never stops talking) hold a job back no longer than its timeout for
//!    each attempt it may have, counted from when it first headed the
//!    queues (or the talk began, if later). Then it fails unsent
//!    ([`DeviceError::NeverQuiet`]) or, after an attempt, with what that
//!    attempt got; an emergency stop goes all the same.
//! 4. Send it (one attempt) and wait for its answer: each frame received
//!    is first offered to the unanswered attempts, oldest first, then put
//!    to the request's [`ReplyRule`]; frames nobody claims are unsolicited
//!    or stale as in step 2. The attempt ends when the rule says the answer
//!    is complete, at the timeout, when a read got only bytes that made no
//!    answer and the line fell silent (a garbled answer), or when the link
//!    is lost. [`Expect::Nothing`] ends as soon as the bytes are written.
//! 5. A read ([`Retry::Read`]) that timed out or got a garbled answer goes
//!    back to the head of its queue for another attempt; anything else
//!    finishes: the caller gets its [`Answer`] or [`DeviceError`] (a
//!    [`DeviceError::Garbled`] carries the bytes that came), a poll's result
//!    goes to the plan's [`PollSink`]. A [`Retry::Never`] request is written
//!    once, whatever happens.
//!
//! # Late answers
//!
//! No family axterm speaks numbers its requests: an answer that comes
//! after its request timed out looks like the next request's. The rule is
//! that a read never returns a value that was not the answer to that read,
//! and a write is ok only on its own success answer. Three things keep it:
//!
//! - Every attempt that ended without an answer stays *unanswered* until
//!   its answer comes, the line is settled, or [`LATE_ANSWER_TIMEOUTS`]
//!   timeouts after its deadline. A module answers in order, so a frame
//!   that an unanswered attempt's rule accepts is taken for the late answer
//!   of the oldest such attempt, never for the answer to a request sent
//!   after it, even when that request's rule accepts it too: such a
//!   request fails with [`DeviceError::Ambiguous`] rather than take it
//!   (its earlier attempts excepted: any of them answers a read as well).
//! - A request whose answer could be taken for an unanswered attempt's
//!   (unless the family's [`WireFormat::answers_apart`] says it could not:
//!   then it goes at once) waits until the line has been quiet for the
//!   silence time, then for a *sentinel* ([`WireFormat::settling`]): a
//!   harmless read of the family's choosing whose answer no unanswered
//!   attempt can have. Once its answer is in, every earlier answer has
//!   come or never will, and the line is settled; whatever came before it
//!   is logged as stale. A sentinel that gets no answer joins the
//!   unanswered, and the request goes after it all the same (at most one
//!   sentinel between two requests); its answer is judged in order as
//!   above.
//! - A family without sentinels
//!   ([`Settling::QuietTime`](crate::protocol::wire::Settling::QuietTime),
//!   the default, and what a family answers when the unanswered requests
//!   went to another module than the next one) is served as before: the
//!   request waits until the line has been quiet for one timeout after the
//!   last deadline, and the unanswered attempts are then forgotten. A
//!   reply later than that (about two timeouts after its request) is the
//!   hole such a family's frames leave open.
//!
//! Two sendings skip all this: the retry of the same read (any answer to an
//! earlier attempt answers it just as well) waits only for the silence
//! time, and so does an emergency stop, which sends a sentinel first only
//! when the family has one, and never waits for the quiet time.
//!
//! # Held lines
//!
//! Some controllers run a line for as long as it takes (a wait for motion,
//! a repeat, a macro call) and take nothing meanwhile but an abort or a
//! pause byte. Such a transaction comes with a [`Hold`]: it has no reply
//! timeout of its own and ends on its answer. While it is on the wire the
//! task publishes it as [`Busy`] ([`DeviceHandle::busy`]); polling waits
//! (the plan is kept); [`DeviceHandle::abort_line`] and
//! [`DeviceHandle::pause_line`] write the hold's abort or pause bytes at
//! once, outside the one-request-in-flight rule. After an abort the line
//! gets its ordinary reply timeout as a grace for the answer to the abort
//! (the controller's error and prompt); without one it fails with
//! [`DeviceError::AbortUnanswered`]. An emergency stop that arrives while a
//! line is held aborts it first, waits for it to end (its answer or the
//! grace), then goes before everything queued; so does a shutdown.
//!
//! A read whose answer takes long on the wire may say how to cut it short
//! ([`Transaction::cut_short`]): an emergency stop that arrives while it is
//! answered writes those bytes at once and goes as soon as the cut answer
//! is in (or the read's timeout from the cut), so that a stop waits for a
//! few bytes, not for a long status line. The read fails with
//! [`DeviceError::CutShort`]; polling reads it again next round.
//!
//! # Answers that end in quiet
//!
//! A family's rule may say a frame completes the answer *unless more comes*
//! ([`Verdict::CompleteIfQuiet`](crate::protocol::wire::Verdict)): an error
//! that may or may not be followed by a prompt, prompts whose number is not
//! known. The answer is then complete once the line has been quiet for
//! [`WireFormat::quiet_guard`]; a frame that comes before is put to the rule
//! with the rest. [`Expect::UntilQuiet`] takes every byte that comes, raw,
//! until the line has been quiet that long: a connect probe that learns how
//! the controller answers.
//!
//! When the link is lost (a [`LinkInput::Lost`](crate::link::LinkInput),
//! its channel closing, a failed write) the request on the wire fails with
//! [`DeviceError::LinkLost`] (it may or may not have been carried out), every
//! queued one with [`DeviceError::Disconnected`] (never sent), and so does
//! every request submitted until the link is back: nothing is kept to be
//! sent later. The task reopens the link after `reconnect_initial`, doubling
//! the wait after each failure up to `reconnect_max`, and polling resumes
//! with the plan it had.

use std::fmt;
use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;
use std::time::{Duration, Instant};

use tokio::sync::{broadcast, mpsc, oneshot, watch};

use crate::link::{Link, LinkError, LinkSpec};
use crate::protocol::wire::{Frame, ReplyRule, WireFormat};

mod poll;
mod task;

/// Who is asking, in the order the device task serves them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Priority {
    /// Waits only for the transaction already on the wire, then goes
    /// before everything queued.
    EmergencyStop,
    /// A line the user typed (console, exec, run).
    User,
    /// Program download/upload.
    Transfer,
    /// Status polling; only when nothing else waits.
    Poll,
}

/// What to expect back for a request.
#[derive(Debug, Clone)]
pub enum Expect {
    /// Nothing: the command is never acknowledged (SIXpack setting
    /// commands). Done once the bytes are on the wire.
    Nothing,
    /// An answer recognised by this rule.
    Reply(Arc<dyn ReplyRule>),
    /// Every byte that comes until the line has been quiet for the
    /// family's [`WireFormat::quiet_guard`], raw and unframed, as the one
    /// frame of the answer (a connect probe learning the controller's echo,
    /// prompt and line ends). No byte at all before the timeout is a
    /// [`DeviceError::Timeout`].
    UntilQuiet,
}

/// Whether a request may be sent again after a timeout or a bad reply.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Retry {
    /// Never: it moves or writes something, and doing it twice could hurt.
    Never,
    /// It only reads: up to this many further attempts.
    Read(u32),
}

/// One request for the device task.
#[derive(Debug, Clone)]
pub struct Transaction {
    /// Bytes to send.
    pub bytes: Vec<u8>,
    pub expect: Expect,
    pub retry: Retry,
    /// Overrides the device's default timeout for this request. A held
    /// request ([`Transaction::hold`]) has none unless given here; after an
    /// abort it is the grace for the abort's answer.
    pub timeout: Option<Duration>,
    /// The request may keep the controller busy for as long as it runs,
    /// taking nothing meanwhile but these bytes (MCCL `RP`, `WS`, `MC`:
    /// Escape aborts, Space pauses, Ch2). See the module documentation.
    pub hold: Option<Hold>,
    /// Bytes that cut this request's answer short while the controller is
    /// giving it, for a read whose answer takes long on the wire (MCCL: a
    /// status line of every axis, about 150 ms at 9600 Bd; Escape aborts
    /// the line, Ch2). An emergency stop that comes meanwhile writes them
    /// and goes once the cut answer is in, instead of after the whole
    /// answer. Only for reads: the request fails with
    /// [`DeviceError::CutShort`], nothing of its answer is taken.
    pub cut_short: Option<Vec<u8>>,
}

impl Transaction {
    /// A request with the device's usual timeout, not held.
    pub fn new(bytes: Vec<u8>, expect: Expect, retry: Retry) -> Transaction {
        Transaction {
            bytes,
            expect,
            retry,
            timeout: None,
            hold: None,
            cut_short: None,
        }
    }
}

/// What a held request takes while it runs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Hold {
    /// Ends it at once (MCCL: Escape).
    pub abort: Vec<u8>,
    /// Pauses it; sent again, resumes it (MCCL: Space).
    pub pause: Option<Vec<u8>>,
}

/// A held request on the wire, as [`DeviceHandle::busy`] publishes it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Busy {
    /// When it was written.
    pub since: Instant,
    /// The request as sent.
    pub bytes: Vec<u8>,
    pub priority: Priority,
    /// Its pause bytes were sent (an odd number of times).
    pub paused: bool,
    /// Its abort bytes were sent: the answer to the abort is awaited.
    pub aborting: bool,
    /// Whether it can be paused.
    pub pausable: bool,
}

/// A completed transaction.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Answer {
    /// The frames that make up the answer (empty for [`Expect::Nothing`]).
    pub frames: Vec<Frame>,
    /// From the last attempt's first byte written to its answer complete.
    pub elapsed: Duration,
    /// 1 when the first attempt succeeded.
    pub attempts: u32,
}

/// Why a transaction failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DeviceError {
    #[error("no reply within {} ms (after {})", timeout.as_millis(), attempts_text(*attempts))]
    Timeout { timeout: Duration, attempts: u32 },
    /// Bytes came, but none made this request's answer (a corrupted
    /// reply, noise, a line that is not its success answer or an error),
    /// and no answer came before the timeout.
    #[error("no readable reply within {} ms, only {} (after {})", timeout.as_millis(), hex(received), attempts_text(*attempts))]
    Garbled {
        timeout: Duration,
        attempts: u32,
        /// The bytes that answered nothing in the last attempt that
        /// received any.
        received: Vec<u8>,
    },
    /// What came could be this request's answer, but also the late answer
    /// to an earlier request whose answer went missing: a bus without
    /// transaction ids cannot tell which, so it is not taken for this one's.
    #[error("a reply came ({}), but it may be the late reply to an earlier request, so it is not taken for this one's (after {})", hex(answer), attempts_text(*attempts))]
    Ambiguous { attempts: u32, answer: Vec<u8> },
    /// A held line was aborted (its abort bytes were written) and no answer
    /// came within the grace: the controller may still be running it.
    #[error("aborted ({} sent), but no answer came within {} ms: the controller may still be busy", hex(abort), grace.as_millis())]
    AbortUnanswered { grace: Duration, abort: Vec<u8> },
    /// The request was not sent: bytes kept coming past its line's
    /// deadline, and a request written over a device that is talking
    /// could collide with it on the bus or be lost in what it says.
    #[error("not sent: the line did not fall quiet within {} ms ({heard} bytes came, beginning {})", waited.as_millis(), hex(first))]
    NeverQuiet {
        waited: Duration,
        /// How many bytes came since the last request was written.
        heard: u64,
        /// The first of them.
        first: Vec<u8>,
    },
    /// Its answer was cut short ([`Transaction::cut_short`]) for an
    /// emergency stop: what came of it is not taken.
    #[error("cut short ({} sent) for an emergency stop", hex(by))]
    CutShort { by: Vec<u8> },
    #[error("not connected: {0}")]
    Disconnected(String),
    #[error("the link was lost while waiting for the reply: {0}")]
    LinkLost(String),
    #[error("the device task has ended")]
    Closed,
}

fn attempts_text(attempts: u32) -> String {
    match attempts {
        1 => "1 attempt".to_string(),
        n => format!("{n} attempts"),
    }
}

/// Bytes in hex, as a device error shows them (the family's own way is
/// for the layers above, which know it).
fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The link as the console shows it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LinkState {
    Connected {
        link: String,
    },
    /// Lost or not (yet) reopened; `reason` says why (the loss, then
    /// the last failed reopening), `attempts` how many reopenings have
    /// failed since the loss, and another attempt follows after
    /// `retry_in`.
    Disconnected {
        reason: String,
        attempts: u32,
        retry_in: Duration,
    },
    /// Shut down on request.
    Closed,
}

/// Direction of a frame on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    Sent,
    Received,
}

/// What a received (or sent) chunk of bytes was found to be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrafficKind {
    Request,
    /// (Part of) the answer to the request in flight.
    Answer,
    /// An unsolicited frame with news (see [`DeviceEvent::Unsolicited`]).
    Unsolicited,
    /// A well-formed frame nobody was waiting for (a late reply).
    Stale,
    /// Bytes that never made a frame (dropped after line silence or before
    /// a request).
    Garbage,
}

/// One entry of the traffic stream (traffic monitor, logs).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TrafficRecord {
    pub at: Instant,
    pub direction: Direction,
    pub kind: TrafficKind,
    pub bytes: Vec<u8>,
    pub priority: Option<Priority>,
}

/// News from the device task that answers no request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DeviceEvent {
    /// An unsolicited frame and what the family says it means.
    Unsolicited {
        frame: Frame,
        description: String,
    },
    StateChanged(LinkState),
}

/// One thing to poll, and how often at most.
#[derive(Debug, Clone)]
pub struct PollItem {
    pub transaction: Transaction,
    /// Poll this often at most: on a grid of this period from the plan's
    /// first poll, so a poll sent a little late does not delay the next
    /// one (see `poll.rs`); the link's speed may make it less often. Zero
    /// means as often as the link allows.
    pub every: Duration,
    /// Goes before every item not urgent whenever it is due, whoever's
    /// plan that is (a switch a technician is watching: its change must
    /// show at once, however many items a round of the others has). Its
    /// `every` is what keeps it from taking the whole line; the plan's
    /// maker sets it (`session::urgent_period`).
    pub urgent: bool,
}

/// Receives every poll result, in the device task, in order, none lost:
/// polling can have side effects (TMCL AP207 clears the error flags it
/// reads), so the receiver latches what it must and publishes snapshots.
pub trait PollSink: Send {
    /// `index` is the item's position in [`PollPlan::items`].
    fn record(&mut self, index: usize, result: Result<&Answer, &DeviceError>);
}

/// Whose poll plan: each module on a link (a [`crate::session::Session`]
/// and its clones) has its own, [`DeviceHandle::set_poll_plan_of`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PollOwner(u64);

impl PollOwner {
    /// The owner of [`DeviceHandle::set_poll_plan`]: the link's one plan
    /// for callers that poll one module.
    pub const LINK: PollOwner = PollOwner(0);

    /// An owner no other has been given.
    pub fn new() -> PollOwner {
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        PollOwner(NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed))
    }
}

impl Default for PollOwner {
    fn default() -> Self {
        PollOwner::new()
    }
}

/// What to poll. The most overdue item goes next whenever nothing of
/// higher priority waits, so on a slow link every item is polled as often
/// as the link allows, in turn.
pub struct PollPlan {
    pub items: Vec<PollItem>,
    pub sink: Box<dyn PollSink>,
}

impl fmt::Debug for PollPlan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("PollPlan")
            .field("items", &self.items)
            .finish_non_exhaustive()
    }
}

/// How the device task behaves; the default suits every link.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceOptions {
    /// Reply timeout when a transaction gives none. `None`: derived from
    /// the link's byte time and the request's size ([`default_timeout`]).
    pub timeout: Option<Duration>,
    /// First and longest wait between attempts to reopen a lost link.
    pub reconnect_initial: Duration,
    pub reconnect_max: Duration,
}

impl Default for DeviceOptions {
    fn default() -> Self {
        DeviceOptions {
            timeout: None,
            reconnect_initial: Duration::from_millis(100),
            reconnect_max: Duration::from_secs(5),
        }
    }
}

/// Counters for benchmarks and the status line.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DeviceCounters {
    /// Transactions finished (answered or failed), polls included.
    pub transactions: u64,
    /// Of which polls of the poll plan.
    pub polls: u64,
    /// Attempts (sentinels included) that got no complete answer in time.
    pub timeouts: u64,
    /// Attempts of reads and sentinels that ended before their timeout
    /// because only bytes that made no answer came (a corrupted reply) and
    /// the line fell silent.
    pub garbled_answers: u64,
    /// Sentinels sent to settle the line after an answer went missing.
    pub sentinels: u64,
    /// Failed attempts (a timeout or a bad answer) put back for another
    /// one; a loss of the link or a shutdown may come before it is sent.
    pub retries: u64,
    /// Well-formed frames that answered nothing and meant nothing.
    pub stale_frames: u64,
    /// Bytes that never made a frame.
    pub garbage_bytes: u64,
    /// Successful reopenings of a lost link.
    pub reconnects: u64,
    /// Unsolicited frames with news (TMCL 138's second reply).
    pub unsolicited: u64,
    /// Held requests aborted and reads cut short (their abort bytes
    /// written).
    pub aborts: u64,
}

/// A request handed to the device task.
#[derive(Debug)]
struct Submission {
    priority: Priority,
    transaction: Transaction,
    reply: oneshot::Sender<Result<Answer, DeviceError>>,
}

/// What a handle asks of the device task.
#[derive(Debug)]
enum Order {
    Submit(Submission),
    /// Write the held request's abort bytes; true if there was one.
    Abort(oneshot::Sender<bool>),
    /// Write the held request's pause bytes; whether it is paused now, or
    /// `None` if no pausable request is held.
    Pause(oneshot::Sender<Option<bool>>),
    /// Finish the attempt on the wire, fail everything else, close the link.
    Shutdown,
}

/// Talks to the device task; cheap to clone. The task ends when the last
/// handle is dropped or [`DeviceHandle::shutdown`] is called.
#[derive(Clone)]
pub struct DeviceHandle {
    orders: mpsc::UnboundedSender<Order>,
    plans: mpsc::UnboundedSender<(PollOwner, Option<PollPlan>)>,
    traffic: broadcast::Sender<TrafficRecord>,
    events: broadcast::Sender<DeviceEvent>,
    state: watch::Receiver<LinkState>,
    counters: watch::Receiver<DeviceCounters>,
    busy: watch::Receiver<Option<Busy>>,
}

impl DeviceHandle {
    /// Queue a transaction and wait for its answer. While the link is down
    /// this fails at once with [`DeviceError::Disconnected`].
    pub async fn transact(
        &self,
        priority: Priority,
        transaction: Transaction,
    ) -> Result<Answer, DeviceError> {
        self.submit(priority, transaction).await
    }

    /// Queue a transaction now and return the future of its answer:
    /// transactions submitted one after the other from one place are queued
    /// in that order, however their futures are awaited.
    pub fn submit(
        &self,
        priority: Priority,
        transaction: Transaction,
    ) -> impl Future<Output = Result<Answer, DeviceError>> + Send + 'static {
        let (reply, answer) = oneshot::channel();
        let queued = self
            .orders
            .send(Order::Submit(Submission {
                priority,
                transaction,
                reply,
            }))
            .is_ok();
        async move {
            if !queued {
                return Err(DeviceError::Closed);
            }
            answer.await.unwrap_or(Err(DeviceError::Closed))
        }
    }

    /// Replace the poll plan (`None` stops polling). It takes effect once
    /// no poll of the current plan is on the wire or waiting for a retry,
    /// so that every poll's result reaches the sink of the plan that made it.
    pub fn set_poll_plan(&self, plan: Option<PollPlan>) {
        self.set_poll_plan_of(PollOwner::LINK, plan);
    }

    /// Replace `owner`'s poll plan (`None`: it polls no more), beside the
    /// plans of other owners: each module of a bus polls by a plan of its
    /// own, and the task takes the owners in turn (see `poll.rs`). As
    /// [`DeviceHandle::set_poll_plan`], it takes effect between polls.
    pub fn set_poll_plan_of(&self, owner: PollOwner, plan: Option<PollPlan>) {
        let _ = self.plans.send((owner, plan));
    }

    /// Every frame in and out, from now on.
    pub fn traffic(&self) -> broadcast::Receiver<TrafficRecord> {
        self.traffic.subscribe()
    }

    /// Unsolicited frames and link state changes, from now on.
    pub fn events(&self) -> broadcast::Receiver<DeviceEvent> {
        self.events.subscribe()
    }

    pub fn state(&self) -> watch::Receiver<LinkState> {
        self.state.clone()
    }

    pub fn counters(&self) -> watch::Receiver<DeviceCounters> {
        self.counters.clone()
    }

    /// The held request on the wire, if any (see the module documentation).
    pub fn busy(&self) -> watch::Receiver<Option<Busy>> {
        self.busy.clone()
    }

    /// Abort the held request on the wire: its abort bytes are written at
    /// once. Resolves to whether one was held (nothing is written if not).
    pub fn abort_line(&self) -> impl Future<Output = bool> + Send + 'static {
        let (reply, done) = oneshot::channel();
        let sent = self.orders.send(Order::Abort(reply)).is_ok();
        async move { sent && done.await.unwrap_or(false) }
    }

    /// Pause the held request on the wire, or resume it if paused: its
    /// pause bytes are written at once. Resolves to whether it is paused
    /// now; `None` if no request that can be paused is held.
    pub fn pause_line(&self) -> impl Future<Output = Option<bool>> + Send + 'static {
        let (reply, done) = oneshot::channel();
        let sent = self.orders.send(Order::Pause(reply)).is_ok();
        async move {
            if !sent {
                return None;
            }
            done.await.ok().flatten()
        }
    }

    /// Let the attempt on the wire finish, fail every other request with
    /// [`DeviceError::Closed`], close the link. The order is given at once;
    /// the future returned ends with the task (state [`LinkState::Closed`]).
    pub fn shutdown(&self) -> impl Future<Output = ()> + Send + 'static {
        let _ = self.orders.send(Order::Shutdown);
        let mut state = self.state.clone();
        async move {
            // An error means the task is gone already.
            let _ = state.wait_for(|s| *s == LinkState::Closed).await;
        }
    }
}

/// The future of one attempt to (re)open a link.
pub type OpenFuture = Pin<Box<dyn Future<Output = Result<Link, LinkError>> + Send>>;

/// How the device task reopens its link after a loss: called once per
/// attempt. [`connect`] makes one from the [`LinkSpec`]; tests hand in
/// links of their own.
pub type Reopen = Box<dyn FnMut() -> OpenFuture + Send>;

/// A [`Reopen`] for a link that cannot be opened again: every attempt fails
/// with `reason`.
pub fn never_reopen(link: impl Into<String>, reason: impl Into<String>) -> Reopen {
    let error = LinkError::new(link, reason);
    Box::new(move || {
        let error = error.clone();
        Box::pin(async move { Err(error) })
    })
}

/// Open `spec` and start its device task. Fails only if the first opening
/// fails; later losses are reopened with backoff.
pub async fn connect(
    spec: LinkSpec,
    wire: Arc<dyn WireFormat>,
    options: DeviceOptions,
) -> Result<DeviceHandle, LinkError> {
    let link = spec.open().await?;
    let reopen: Reopen = Box::new(move || {
        let spec = spec.clone();
        Box::pin(async move { spec.reopen().await })
    });
    Ok(spawn(link, reopen, wire, options))
}

/// Start the device task on a link that is already open; `reopen` opens it
/// again after a loss. Must be called within a tokio runtime.
pub fn spawn(
    link: Link,
    reopen: Reopen,
    wire: Arc<dyn WireFormat>,
    options: DeviceOptions,
) -> DeviceHandle {
    let (orders_tx, orders) = mpsc::unbounded_channel();
    let (plans_tx, plans) = mpsc::unbounded_channel();
    let (traffic, _) = broadcast::channel(TRAFFIC_CAPACITY);
    let (events, _) = broadcast::channel(EVENTS_CAPACITY);
    let (state_tx, state) = watch::channel(LinkState::Connected {
        link: link.name.clone(),
    });
    let (counters_tx, counters) = watch::channel(DeviceCounters::default());
    let (busy_tx, busy) = watch::channel(None);
    let outlets = task::Outlets {
        traffic: traffic.clone(),
        events: events.clone(),
        state: state_tx,
        counters: counters_tx,
        busy: busy_tx,
    };
    let task = task::Task::new(wire, options, reopen, orders, plans, outlets);
    tokio::spawn(task.run(link));
    DeviceHandle {
        orders: orders_tx,
        plans: plans_tx,
        traffic,
        events,
        state,
        counters,
        busy,
    }
}

/// Records the traffic stream holds for a slow subscriber before it lags.
pub const TRAFFIC_CAPACITY: usize = 4096;
const EVENTS_CAPACITY: usize = 256;

/// Reply bytes the default timeout leaves wire time for: more than any TMCL
/// (9) or CMD-4CR (63) reply, a few MCCL lines.
pub const REPLY_ALLOWANCE_BYTES: u32 = 64;

/// Time the controller and the adapters add on top of wire time: command
/// processing (an EEPROM write takes milliseconds), a USB-serial adapter's
/// latency timer in each direction (16 ms by default on FTDI chips), an
/// RS-485 turnaround.
pub const PROCESSING_MARGIN: Duration = Duration::from_millis(50);

/// How long an answer that went missing is still looked for, in reply
/// timeouts after its deadline: until then a frame that could be it is
/// taken for it (and never for a later request's answer), unless a
/// sentinel's answer has shown that it will not come. An answer later
/// than that is the hole a bus without transaction ids leaves open.
pub const LATE_ANSWER_TIMEOUTS: u32 = 10;

/// Timeout on links without a baud rate (TCP, unthrottled simulators): a
/// serial-over-TCP bridge may sit in front of a slow serial line we know
/// nothing about.
pub const UNTIMED_LINK_TIMEOUT: Duration = Duration::from_millis(500);

/// The reply timeout of a request of `request_len` bytes when neither the
/// transaction nor the options give one: twice the wire time of the
/// request and [`REPLY_ALLOWANCE_BYTES`] of reply, plus
/// [`PROCESSING_MARGIN`]; [`UNTIMED_LINK_TIMEOUT`] without a byte time.
/// At 9600 Bd a TMCL request gets 2 × 73 × 1.04 ms + 50 ms ≈ 202 ms; at
/// 115200 Bd ≈ 63 ms.
pub fn default_timeout(byte_time: Option<Duration>, request_len: usize) -> Duration {
    match byte_time {
        None => UNTIMED_LINK_TIMEOUT,
        Some(byte_time) => {
            let bytes = u32::try_from(request_len)
                .unwrap_or(u32::MAX)
                .saturating_add(REPLY_ALLOWANCE_BYTES);
            byte_time
                .saturating_mul(bytes)
                .saturating_mul(2)
                .saturating_add(PROCESSING_MARGIN)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_timeout_follows_the_byte_time() {
        assert_eq!(default_timeout(None, 9), UNTIMED_LINK_TIMEOUT);
        let at_9600 = crate::link::byte_time(9600);
        assert_eq!(
            default_timeout(Some(at_9600), 9),
            at_9600 * 146 + PROCESSING_MARGIN
        );
        assert!(
            default_timeout(Some(crate::link::byte_time(115_200)), 9) < Duration::from_millis(70)
        );
        assert!(
            default_timeout(Some(at_9600), 200) > default_timeout(Some(at_9600), 9),
            "a longer request gets longer"
        );
        assert_eq!(
            default_timeout(Some(Duration::MAX), usize::MAX),
            Duration::MAX,
            "saturates, never panics"
        );
    }

    #[test]
    fn errors_name_what_went_wrong() {
        let timeout = DeviceError::Timeout {
            timeout: Duration::from_millis(202),
            attempts: 3,
        };
        assert_eq!(
            timeout.to_string(),
            "no reply within 202 ms (after 3 attempts)"
        );
    }
}
