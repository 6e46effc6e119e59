//! Byte transports: a real serial port, a TCP bridge (ser2net style), or a
//! simulator in this process running on the clock. Every kind opens into
//! the same [`Link`]: a pair of channels, so that the device task never
//! blocks on I/O and tests can stand a scripted link in for a real one.

use std::fmt;
use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::sync::mpsc;

use crate::sim::SimulatedController;
use crate::sim::faults::FaultPlan;
use port_trouble::Opening;

pub mod port_trouble;
pub mod ports;
pub mod rfc2217;
mod serial;
pub mod sim_line;
mod sim_link;
mod tcp;

/// Serial character frame: start bit, 8 data bits, stop bit.
pub const BITS_PER_BYTE: u32 = 10;

/// The character framing a serial line is set to: data bits, parity, stop
/// bits. Every family's line is 8N1 ([`LINE_FRAMING`]); a serial port is
/// opened with it and an RFC 2217 bridge is told it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Framing {
    pub data_bits: u8,
    pub parity: rfc2217::ComParity,
    pub stop_bits: rfc2217::ComStopBits,
}

/// 8N1, no flow control: the framing of every family's serial line.
pub const LINE_FRAMING: Framing = Framing {
    data_bits: 8,
    parity: rfc2217::ComParity::None,
    stop_bits: rfc2217::ComStopBits::One,
};

/// Wire time of one byte at `baud`.
pub fn byte_time(baud: u32) -> Duration {
    Duration::from_nanos(u64::from(BITS_PER_BYTE) * 1_000_000_000 / u64::from(baud.max(1)))
}

/// What arrives from an open link.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LinkInput {
    /// Bytes, in order, split anywhere.
    Bytes(Vec<u8>),
    /// The link is gone (cable unplugged, socket closed, write failed); the
    /// text says why. Nothing more will arrive.
    Lost(String),
}

/// An open link. Dropping it closes the link and ends its threads or tasks.
pub struct Link {
    /// Human-readable name: "/dev/ttyUSB0 at 9600 Bd", "tcp 10.0.0.5:4001", "sim tmcm1110".
    pub name: String,
    /// Received bytes and the loss notice. A closed channel also means lost.
    pub incoming: mpsc::UnboundedReceiver<LinkInput>,
    /// Where bytes to send go.
    pub outgoing: Box<dyn LinkWriter>,
    /// Wire time of one byte, when the link has a baud rate (serial, or a
    /// simulator emulating one); `None` for TCP and unthrottled simulators.
    pub byte_time: Option<Duration>,
}

/// The sending half of a link. Writes are short (a frame or a line) and
/// must not stall the device task: a serial or TCP write of a few bytes
/// lands in the kernel's buffer at once, a simulator's is a channel send.
pub trait LinkWriter: Send {
    /// Write all of `bytes`, in order. An error means the link is lost.
    fn send(&mut self, bytes: &[u8]) -> io::Result<()>;
}

/// A channel as a writer: for in-process links and for tests that script
/// the other end themselves.
impl LinkWriter for mpsc::UnboundedSender<Vec<u8>> {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        mpsc::UnboundedSender::send(self, bytes.to_vec())
            .map_err(|_| io::Error::new(io::ErrorKind::BrokenPipe, "the other end is gone"))
    }
}

impl fmt::Debug for Link {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Link").field("name", &self.name).finish()
    }
}

/// A simulated controller shared between successive openings of its link,
/// so that a link lost and reopened finds the same module (a cable pulled
/// and plugged back, not a new controller).
pub type SharedSim = Arc<Mutex<Box<dyn SimulatedController>>>;

/// Where a controller is, and how to open (and reopen) the link to it.
#[derive(Clone)]
pub enum LinkSpec {
    /// A serial port (8N1, no flow control).
    Serial { path: String, baud: u32 },
    /// A serial-over-TCP bridge, `HOST:PORT`; `baud`, when known, is the
    /// serial line's rate behind the bridge. The session paces its slow
    /// polls by it; the link itself stays untimed (bytes arrive in network
    /// packets, so inter-byte silences and reply timeouts cannot be told
    /// from the baud rate).
    Tcp { address: String, baud: Option<u32> },
    /// A serial-over-TCP bridge speaking RFC 2217 (`--tcp
    /// rfc2217://HOST:PORT`): the link sets the remote port to `baud` and
    /// [`LINE_FRAMING`] before any device byte is sent. Untimed, as
    /// [`LinkSpec::Tcp`] is.
    Rfc2217 { address: String, baud: u32 },
    /// A simulator in this process, advanced on the (tokio) clock, with
    /// optional wire-time emulation and fault injection.
    Sim {
        kind: String,
        sim: SharedSim,
        baud: Option<u32>,
        faults: FaultPlan,
    },
}

/// How `--tcp` names a bridge that speaks RFC 2217.
pub const RFC2217_SCHEME: &str = "rfc2217://";

impl fmt::Debug for LinkSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.describe())
    }
}

impl LinkSpec {
    /// How the user would name this link in a message.
    pub fn describe(&self) -> String {
        match self {
            LinkSpec::Serial { path, baud } => format!("{path} at {baud} Bd"),
            LinkSpec::Tcp {
                address,
                baud: None,
            } => format!("tcp {address}"),
            LinkSpec::Tcp {
                address,
                baud: Some(baud),
            } => format!("tcp {address} (line at {baud} Bd)"),
            LinkSpec::Rfc2217 { address, baud } => {
                format!("{RFC2217_SCHEME}{address} at {baud} Bd")
            }
            LinkSpec::Sim { kind, baud, .. } => match baud {
                Some(baud) => format!("sim {kind} at {baud} Bd"),
                None => format!("sim {kind}"),
            },
        }
    }

    /// Wire time of one byte, where the link has a baud rate.
    pub fn byte_time(&self) -> Option<Duration> {
        match self {
            LinkSpec::Serial { baud, .. } => Some(byte_time(*baud)),
            LinkSpec::Tcp { baud, .. } => baud.map(byte_time),
            LinkSpec::Rfc2217 { baud, .. } => Some(byte_time(*baud)),
            LinkSpec::Sim { baud, .. } => baud.map(byte_time),
        }
    }
}

/// Why a link could not be opened: a one-line reason, and what to do
/// about it on lines of their own (who owns the port, who holds it,
/// which ports there are). Shown whole, the advice follows the reason
/// indented; [`LinkError::headline`] is the one line for places that have
/// one (a status bar, a table cell).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}{}", self.headline(), indented(&self.advice))]
pub struct LinkError {
    /// The link, as [`LinkSpec::describe`] names it.
    pub link: String,
    pub reason: String,
    /// Lines that explain the reason and say how to fix it; may be empty.
    pub advice: Vec<String>,
}

impl LinkError {
    /// A failure with nothing to add to its reason.
    pub fn new(link: impl Into<String>, reason: impl Into<String>) -> LinkError {
        LinkError {
            link: link.into(),
            reason: reason.into(),
            advice: Vec::new(),
        }
    }

    /// `cannot open LINK: REASON`, without the advice.
    pub fn headline(&self) -> String {
        format!("cannot open {}: {}", self.link, self.reason)
    }
}

/// Each line on a line of its own, indented under the headline.
fn indented(lines: &[String]) -> String {
    lines.iter().map(|line| format!("\n  {line}")).collect()
}

impl LinkSpec {
    /// Open the link. Blocking work (opening a serial port) is kept off the
    /// async runtime; must be called within a tokio runtime, which then
    /// runs the link's reader.
    pub async fn open(&self) -> Result<Link, LinkError> {
        self.open_as(Opening::First).await
    }

    /// Open the link again after it was lost: as [`LinkSpec::open`], but
    /// a serial port that is not there has vanished.
    pub async fn reopen(&self) -> Result<Link, LinkError> {
        self.open_as(Opening::Again).await
    }

    async fn open_as(&self, opening: Opening) -> Result<Link, LinkError> {
        match self {
            LinkSpec::Serial { path, baud } => {
                serial::open(path, *baud, self.describe(), opening).await
            }
            LinkSpec::Tcp { address, .. } => tcp::open(address, None, self.describe()).await,
            LinkSpec::Rfc2217 { address, baud } => {
                tcp::open(address, Some(*baud), self.describe()).await
            }
            LinkSpec::Sim {
                sim, baud, faults, ..
            } => Ok(sim_link::open(
                Arc::clone(sim),
                *baud,
                faults.clone(),
                self.describe(),
            )),
        }
    }
}

/// The sending side of a link's `incoming` channel: bytes, and at most one
/// loss notice however many readers and writers notice the loss.
#[derive(Debug, Clone)]
struct Inbox {
    tx: mpsc::UnboundedSender<LinkInput>,
    lost: Arc<AtomicBool>,
}

impl Inbox {
    fn new() -> (Inbox, mpsc::UnboundedReceiver<LinkInput>) {
        let (tx, rx) = mpsc::unbounded_channel();
        let inbox = Inbox {
            tx,
            lost: Arc::new(AtomicBool::new(false)),
        };
        (inbox, rx)
    }

    /// Pass received bytes on; false when the link's owner is gone.
    fn bytes(&self, bytes: &[u8]) -> bool {
        if bytes.is_empty() {
            return !self.tx.is_closed();
        }
        self.tx.send(LinkInput::Bytes(bytes.to_vec())).is_ok()
    }

    /// Report the loss, unless it has been reported already.
    fn lost(&self, reason: impl Into<String>) {
        if !self.lost.swap(true, Ordering::SeqCst) {
            let _ = self.tx.send(LinkInput::Lost(reason.into()));
        }
    }

    fn is_lost(&self) -> bool {
        self.lost.load(Ordering::SeqCst)
    }

    /// Resolves when the link's owner has dropped its receiver.
    async fn closed(&self) {
        self.tx.closed().await
    }

    fn is_closed(&self) -> bool {
        self.tx.is_closed()
    }
}

/// An I/O error as a technician reads it: the OS's words, without Rust's
/// "(os error 2)" suffix.
fn io_reason(e: &io::Error) -> String {
    let text = e.to_string();
    match text.rsplit_once(" (os error ") {
        Some((words, code)) if code.ends_with(')') => words.to_string(),
        _ => text,
    }
}
