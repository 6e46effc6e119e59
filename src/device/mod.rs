//! The device task: the one owner of a link. It holds exactly one request
//! in flight (every bus axterm speaks is strict master/slave), picks the
//! next by priority, matches replies to the request in flight through the
//! family's [`WireFormat`], polls status when nothing else is waiting, and
//! survives timeouts, garbage and lost links.
//!
//! It knows nothing of any family beyond [`crate::protocol::wire`].

use std::fmt;
use std::sync::Arc;
use std::time::{Duration, Instant};

use tokio::sync::{broadcast, mpsc, oneshot, watch};

use crate::link::{LinkError, LinkSpec};
use crate::protocol::wire::{Frame, ReplyRule, WireFormat};

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
    /// Overrides the device's default timeout for this request.
    pub timeout: Option<Duration>,
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
    #[error("no reply within {} ms (after {attempts} attempt{})", timeout.as_millis(), if *attempts == 1 { "" } else { "s" })]
    Timeout { timeout: Duration, attempts: u32 },
    #[error("not connected: {0}")]
    Disconnected(String),
    #[error("the link was lost while waiting for the reply: {0}")]
    LinkLost(String),
    #[error("the device task has ended")]
    Closed,
}

/// The link as the console shows it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LinkState {
    Connected {
        link: String,
    },
    /// Lost or not (yet) reopened; `reason` says why, and another attempt
    /// follows after `retry_in`.
    Disconnected {
        reason: String,
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
    /// Poll at most this often; the link's speed may make it less often.
    /// Zero means as often as the link allows.
    pub every: Duration,
}

/// Receives every poll result, in the device task, in order, none lost:
/// polling can have side effects (TMCL AP207 clears the error flags it
/// reads), so the receiver latches what it must and publishes snapshots.
pub trait PollSink: Send {
    /// `index` is the item's position in [`PollPlan::items`].
    fn record(&mut self, index: usize, result: Result<&Answer, &DeviceError>);
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

/// How the device task behaves; [`DeviceOptions::for_link`] picks defaults.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceOptions {
    /// Reply timeout when a transaction gives none. `None`: derived from
    /// the link's byte time and the request's size.
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
    pub transactions: u64,
    pub polls: u64,
    pub timeouts: u64,
    pub retries: u64,
    pub stale_frames: u64,
    pub garbage_bytes: u64,
    pub reconnects: u64,
}

/// A request handed to the device task.
#[derive(Debug)]
#[allow(dead_code)] // read by the task, which lands next
struct Submission {
    priority: Priority,
    transaction: Transaction,
    reply: oneshot::Sender<Result<Answer, DeviceError>>,
}

/// Talks to the device task; cheap to clone.
#[derive(Clone)]
pub struct DeviceHandle {
    submissions: mpsc::UnboundedSender<Submission>,
    plans: mpsc::UnboundedSender<Option<PollPlan>>,
    traffic: broadcast::Sender<TrafficRecord>,
    events: broadcast::Sender<DeviceEvent>,
    state: watch::Receiver<LinkState>,
    counters: watch::Receiver<DeviceCounters>,
}

impl DeviceHandle {
    /// Queue a transaction and wait for its answer.
    pub async fn transact(
        &self,
        priority: Priority,
        transaction: Transaction,
    ) -> Result<Answer, DeviceError> {
        let (reply, answer) = oneshot::channel();
        self.submissions
            .send(Submission {
                priority,
                transaction,
                reply,
            })
            .map_err(|_| DeviceError::Closed)?;
        answer.await.unwrap_or(Err(DeviceError::Closed))
    }

    /// Replace the poll plan (`None` stops polling).
    pub fn set_poll_plan(&self, plan: Option<PollPlan>) {
        let _ = self.plans.send(plan);
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
}

/// Open `spec` and start its device task. Fails only if the first opening
/// fails; later losses are reopened with backoff.
pub async fn connect(
    spec: LinkSpec,
    wire: Arc<dyn WireFormat>,
    options: DeviceOptions,
) -> Result<DeviceHandle, LinkError> {
    let _ = (wire, options);
    let _link = spec.open().await?;
    Err(LinkError {
        link: spec.describe(),
        reason: "the device task is not built yet".into(),
    })
}
