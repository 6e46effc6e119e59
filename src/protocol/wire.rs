//! What the device task needs to know of a family's wire format, and no
//! more: how to cut the incoming byte stream into frames, and whether a
//! frame answers the request in flight, means something on its own (an
//! unsolicited event such as TMCL 138's second reply, §3.6.52) or is stale.
//!
//! Pure code, no I/O: each family implements these next to its codec, and
//! the device task (`device/`) serves every family through them unchanged.

use std::fmt;
use std::time::Duration;

/// One frame as cut from the byte stream (a 9-byte TMCL reply, one ASCII
/// line without its terminator, a prompt character…).
pub type Frame = Vec<u8>;

/// Cuts the incoming byte stream into frames. Never panics, whatever it is fed.
pub trait Framer: Send {
    /// Append received bytes; return every frame now complete, in order.
    fn push(&mut self, bytes: &[u8]) -> Vec<Frame>;
    /// Bytes of an incomplete frame held back.
    fn pending(&self) -> usize;
    /// Drop an incomplete frame (after line silence, or before a new
    /// request) and return its bytes so they can be logged as garbage.
    fn discard_pending(&mut self) -> Vec<u8>;
    /// Bytes the framer has stepped over since the last call while looking
    /// for a frame boundary (garbage before a good frame, the tail of an
    /// overlong line), so that the device task can log them as garbage
    /// instead of letting them vanish. Framers that never skip keep the
    /// default.
    fn take_skipped(&mut self) -> Vec<u8> {
        Vec::new()
    }
}

/// How a request's answer is recognised, judged one frame at a time.
pub trait ReplyRule: Send + Sync + fmt::Debug {
    /// `accepted` holds the frames of this answer accepted so far (empty for
    /// the first); `frame` is the next frame received while the request is
    /// in flight.
    fn examine(&self, accepted: &[Frame], frame: &[u8]) -> Verdict;
}

/// What a frame is to the request in flight.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// It completes the answer (the frames accepted so far plus this one).
    Complete,
    /// It belongs to the answer, and more is to come (an echo before the
    /// reply, one line of a multi-line reply…).
    Continue,
    /// Not an answer to this request: unsolicited or stale.
    NotMine,
}

/// A family's wire format as the device task sees it.
pub trait WireFormat: Send + Sync {
    /// Short name for logs ("tmcl", "ascii-cr").
    fn name(&self) -> &'static str;
    /// A fresh framer for a newly opened link.
    fn framer(&self) -> Box<dyn Framer>;
    /// A frame that answers no request but carries news (TMCL: status 128
    /// from command 138, §3.6.52): a description for the event stream.
    /// `None` means the frame is stale noise.
    fn unsolicited(&self, frame: &[u8]) -> Option<String>;
    /// How long the line must stay quiet before a partial frame is dropped
    /// and the framer starts afresh, given the wire time of one byte (none
    /// for links without a baud rate). TMCL has no start byte, so this is
    /// its only way back into step after garbage.
    fn silence(&self, byte_time: Option<Duration>) -> Duration;
}
