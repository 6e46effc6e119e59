//! What the device task needs to know of a family's wire format, and no
//! more: how to cut the incoming byte stream into frames, and whether a
//! frame answers the request in flight, means something on its own (an
//! unsolicited event such as TMCL 138's second reply, §3.6.52) or is stale.
//!
//! Neither TMCL nor the ASCII families carry a transaction id, so an answer
//! that comes after its request timed out looks like the next request's.
//! A family tells the device task what it has to tell answers apart: which
//! requests' answers can never be taken for each other
//! ([`WireFormat::answers_apart`]), and a harmless request whose answer
//! nothing else can give, sent to settle the line after an answer went
//! missing ([`WireFormat::settling`], [`Sentinel`]). Both are optional; a
//! family that offers neither is served as before: after a timeout the
//! line must be quiet for a while, and an answer later than that is the
//! hole its frames leave open.
//!
//! Pure code, no I/O: each family implements these next to its codec, and
//! the device task (`device/`) serves every family through them unchanged.

use std::fmt;
use std::sync::Arc;
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
    /// The partial frame held back, taken as a frame of its own because
    /// the line has fallen silent after it: a line the controller leaves
    /// unterminated (a prompt character it was told to change, MCCL
    /// `PCn`). `None` (the default): a partial frame is garbage, dropped
    /// with [`Framer::discard_pending`].
    fn complete_on_silence(&mut self) -> Option<Frame> {
        None
    }
}

/// How a request's answer is recognised, judged one frame at a time.
pub trait ReplyRule: Send + Sync + fmt::Debug {
    /// `accepted` holds the frames of this answer accepted so far (empty for
    /// the first); `frame` is the next frame received while the request is
    /// in flight. Also asked, with `accepted` empty, whether a frame could
    /// be the late answer to a request that timed out: a rule that accepts
    /// only what its own request's answer can look like (the success
    /// answer, or an error the module names) is what lets a late answer be
    /// told from the next one.
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
    /// It completes the answer unless more belongs to it: the answer is
    /// complete once the line has been quiet for
    /// [`WireFormat::quiet_guard`] (an error that a prompt may or may not
    /// follow; prompts whose number is not known; a controller told to
    /// send no prompt). A frame that comes before is put to the rule with
    /// the others; one it says is not its own ends the answer before it.
    CompleteIfQuiet,
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

    /// How long a module waits after a request before it answers (the
    /// SIXpack 2's transmitter switch-over delay, 6 ms at the factory
    /// setting, §6.1.1): part of every exchange's time on the line beside
    /// its bytes, for measurements held against the wire's rate. Zero by
    /// default.
    fn turnaround(&self) -> Duration {
        Duration::ZERO
    }

    /// Bytes an exchange of `request` puts on the busier direction of the
    /// line, for sharing out the line's time between poll items: the
    /// request and an answer as long again by default (TMCL: 9 and 9; a
    /// CMD-4CR read like `@01HSPDX` is answered with fewer). Counted with
    /// [`WireFormat::turnaround`] beside it.
    fn exchange_bytes(&self, request: &[u8]) -> usize {
        request.len().saturating_mul(2)
    }

    /// How long the line must stay quiet after a frame that completes an
    /// answer only if nothing more comes ([`Verdict::CompleteIfQuiet`]), and
    /// after the last byte of an [`Expect::UntilQuiet`](crate::device::Expect)
    /// answer. The line silence by default.
    fn quiet_guard(&self, byte_time: Option<Duration>) -> Duration {
        self.silence(byte_time)
    }

    /// Whether no answer to `earlier` can ever be taken for an answer to
    /// `next`, nor the other way round, judged from the two requests as
    /// sent (TMCL: they go to different modules or are different commands,
    /// and the reply echoes both, §3.2). Then `next` may go while an answer
    /// to `earlier` may still come. The default, `false`, is always safe.
    fn answers_apart(&self, earlier: &[u8], next: &[u8]) -> bool {
        let _ = (earlier, next);
        false
    }

    /// How to make sure that no late answer to the requests in
    /// `unanswered` (as sent, oldest first: they timed out or got no answer
    /// that could be read, and their answers may still come) is taken for
    /// the answer to `next`. The default, [`Settling::QuietTime`], is what
    /// a family without a sentinel can do; a family with sentinels answers
    /// it too when an unanswered request went to another module than
    /// `next` (a module answers in order, but two modules' answers are not
    /// ordered with each other, so a sentinel speaks for its own module
    /// only).
    fn settling(&self, next: &[u8], unanswered: &[&[u8]]) -> Settling {
        let _ = (next, unanswered);
        Settling::QuietTime
    }
}

/// What the device task does before sending a request while answers to
/// earlier ones may still come (and cannot be told from its answer).
#[derive(Debug, Clone)]
pub enum Settling {
    /// Nothing tells a late answer from the next one: wait until the line
    /// has been quiet for one reply timeout after the last request's
    /// deadline, then take it that no answer comes later than that.
    QuietTime,
    /// Send this sentinel first. Its answer cannot be any unanswered
    /// request's, and a module answers in order: once it is in, every
    /// earlier answer has come or never will.
    Sentinel(Sentinel),
    /// The family has sentinels, but none whose answer can be told from
    /// every unanswered request's just now (a sentinel is among them):
    /// send the request; the answers that come are matched to the
    /// requests in the order they were sent, and one that could be an
    /// earlier request's is never taken for this one's.
    InOrder,
    /// The family has sentinels, but every one could be taken for an
    /// unanswered request's answer (their own answers lost, or an answer
    /// any frame could be): wait until the oldest of those is no longer
    /// looked for ([`crate::device::LATE_ANSWER_TIMEOUTS`]), then settle
    /// again. Matching in order instead would be a guess where answers
    /// cannot be told apart: a dropped answer leaves the next one taken
    /// for the oldest request it could answer.
    AwaitSentinel,
}

/// A request that reads and changes nothing, whose answer marks a point in
/// the stream of answers (see [`Settling::Sentinel`]).
#[derive(Debug, Clone)]
pub struct Sentinel {
    /// The bytes to send.
    pub bytes: Vec<u8>,
    /// Accepts its answer, and nothing an unanswered request could still
    /// get back (an error reply included).
    pub rule: Arc<dyn ReplyRule>,
}
