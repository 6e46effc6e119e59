//! The SIXpack 2 as the device task sees it: fixed-length replies with no
//! delimiter, length byte or checksum, told apart by their command byte
//! (digest D1.4); a reply recognised by its echoed command and motor; and
//! the one answer that may come when nothing asked for it, the delayed
//! `$28` (§7.2: "the PACK will send the response as soon as all concerned
//! motors are inactive"; on RS-232 it may be outstanding while other
//! requests run, §6.2.1.7).

use std::time::Duration;

use super::catalog::is_replying;
use super::frame::{CONSOLE_RESPONSE_ADDRESS, PARAMS, Reply, ReplyFraming, Request};
use super::reply::{ReplyFields, check_answers};
use crate::protocol::wire::{Frame, Framer, ReplyRule, Verdict, WireFormat};

/// Bytes of a reply without its address byte (§6.2.2.3).
pub const REPLY_LEN: usize = 1 + PARAMS;

/// The `$28` command byte.
const ALL_ACTIVITIES: u8 = 0x28;

/// The transmitter switch-over delay before every reply, at the factory
/// setting (§6.1.1: 6 ms; `$40` P2-3 in 2 ms units).
pub const SWITCH_OVER: Duration = Duration::from_millis(6);

/// Line silence after which a partial reply is dropped, in byte times: a
/// unit sends each reply as one burst after its switch-over delay (§6.1.1).
const SILENCE_BYTES: u32 = 4;

/// The shortest silence that counts, whatever the baud rate: USB-serial
/// adapters and serial-over-TCP bridges may cut one burst in two that far
/// apart (as for TMCL, see `tmcl::wire::MIN_SILENCE`).
pub const MIN_SILENCE: Duration = Duration::from_millis(20);

/// The SIXpack 2 wire format with its reply framing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Sixpack2Wire {
    pub framing: ReplyFraming,
}

impl WireFormat for Sixpack2Wire {
    fn name(&self) -> &'static str {
        "sixpack2"
    }

    fn framer(&self) -> Box<dyn Framer> {
        Box::new(Sixpack2Framer::new(self.framing))
    }

    /// A `$28` answer that no request in flight claims: the delayed
    /// response of an earlier `GetAllActivities` with a wait mask.
    fn unsolicited(&self, frame: &[u8]) -> Option<String> {
        let reply = Reply::parse(frame, self.framing).ok()?;
        if reply.command != ALL_ACTIVITIES {
            return None;
        }
        let spec = super::catalog::by_code(ALL_ACTIVITIES)?;
        let fields = ReplyFields::read(spec, &reply.params)?;
        Some(format!(
            "the motors waited for ($28) are inactive: {}",
            fields.value_text()
        ))
    }

    /// The factory switch-over delay (§6.1.1; `$40` changes it).
    fn turnaround(&self) -> Duration {
        SWITCH_OVER
    }

    fn silence(&self, byte_time: Option<Duration>) -> Duration {
        byte_time
            .map(|t| t.saturating_mul(SILENCE_BYTES))
            .unwrap_or_default()
            .max(MIN_SILENCE)
    }
}

/// Cuts replies out of the byte stream: a reply starts with a command
/// that answers (§7), so bytes before one are stepped over; with an
/// address byte in front it is 9 bytes, else 8 (digest D1.4).
#[derive(Debug, Clone, Default)]
pub struct Sixpack2Framer {
    framing: ReplyFraming,
    pending: Vec<u8>,
    skipped: Vec<u8>,
}

/// What the bytes at the start of the pending input are.
enum Start {
    /// A reply of this many bytes starts here.
    Reply(usize),
    /// Too few bytes to tell yet.
    Wait,
    /// No reply starts here.
    Skip,
}

impl Sixpack2Framer {
    pub fn new(framing: ReplyFraming) -> Self {
        Sixpack2Framer {
            framing,
            ..Self::default()
        }
    }

    fn start(&self, at: &[u8]) -> Start {
        let first = at.first().copied();
        let replying_second = at.get(1).copied().map(is_replying);
        match self.framing {
            ReplyFraming::Cmd8 => match first {
                Some(b) if is_replying(b) => Start::Reply(REPLY_LEN),
                Some(_) => Start::Skip,
                None => Start::Wait,
            },
            // Any address byte, then a command that answers.
            ReplyFraming::Addr9 => match replying_second {
                Some(true) => Start::Reply(REPLY_LEN + 1),
                Some(false) => Start::Skip,
                None => Start::Wait,
            },
            // The console's response address is $00, which no command
            // that answers is: `$00 CMD` is the address form, `CMD` alone
            // the other (digest D1.4). A stray $00 after a reset (§7.4)
            // before an 8-byte reply reads the same as the address form.
            ReplyFraming::Auto => match first {
                Some(b) if is_replying(b) => Start::Reply(REPLY_LEN),
                Some(CONSOLE_RESPONSE_ADDRESS) => match replying_second {
                    Some(true) => Start::Reply(REPLY_LEN + 1),
                    Some(false) => Start::Skip,
                    None => Start::Wait,
                },
                Some(_) => Start::Skip,
                None => Start::Wait,
            },
        }
    }
}

impl Framer for Sixpack2Framer {
    fn push(&mut self, bytes: &[u8]) -> Vec<Frame> {
        self.pending.extend_from_slice(bytes);
        let mut frames = Vec::new();
        let mut at = 0;
        loop {
            let rest = self.pending.get(at..).unwrap_or_default();
            match self.start(rest) {
                Start::Reply(len) => match rest.get(..len) {
                    Some(frame) => {
                        frames.push(frame.to_vec());
                        at += len;
                    }
                    None => break,
                },
                Start::Skip => {
                    self.skipped.extend_from_slice(&rest[..1]);
                    at += 1;
                }
                Start::Wait => break,
            }
        }
        self.pending.drain(..at);
        frames
    }

    fn pending(&self) -> usize {
        self.pending.len()
    }

    fn discard_pending(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.pending)
    }

    fn take_skipped(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.skipped)
    }
}

/// The answer to one query: a single reply with the request's command,
/// echoing its motor or channel, and its response address where the
/// framing has an address byte. Anything else is another request's late
/// answer (an unsolicited `$28`, a poll that timed out) and not this one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sixpack2ReplyRule {
    pub request: Request,
    pub framing: ReplyFraming,
}

impl ReplyRule for Sixpack2ReplyRule {
    fn examine(&self, accepted: &[Frame], frame: &[u8]) -> Verdict {
        if !accepted.is_empty() {
            return Verdict::NotMine;
        }
        match Reply::parse(frame, self.framing) {
            Ok(reply) if check_answers(&self.request, &reply).is_ok() => Verdict::Complete,
            _ => Verdict::NotMine,
        }
    }
}

/// The delayed answer to a `$28` with a wait mask: the `$28` reply for
/// this request whose masked motors are all inactive (§7.2: it is sent
/// "as soon as all concerned motors are inactive"). An immediate `$28`
/// answer to another request, with a masked motor still active, is not
/// taken for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IdleAnswerRule {
    pub request: Request,
    pub framing: ReplyFraming,
}

impl IdleAnswerRule {
    /// The motors the request waits for (P1, bit n = motor n).
    fn mask(&self) -> u8 {
        self.request.params[1]
    }
}

impl ReplyRule for IdleAnswerRule {
    fn examine(&self, accepted: &[Frame], frame: &[u8]) -> Verdict {
        let answer = Sixpack2ReplyRule {
            request: self.request,
            framing: self.framing,
        };
        if answer.examine(accepted, frame) != Verdict::Complete {
            return Verdict::NotMine;
        }
        let Ok(reply) = Reply::parse(frame, self.framing) else {
            return Verdict::NotMine;
        };
        // P0..P5: the action of motors 0..5.
        let idle = (0..6).all(|m| self.mask() & (1 << m) == 0 || reply.params[m] == 0);
        if idle {
            Verdict::Complete
        } else {
            Verdict::NotMine
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn position(motor: u8, pos: i32) -> Vec<u8> {
        let mut frame = vec![0x20, motor];
        frame.extend_from_slice(&pos.to_le_bytes());
        frame.extend_from_slice(&[5, 0]);
        frame
    }

    fn activities() -> Vec<u8> {
        vec![0x28, 0, 5, 0, 0, 0, 0, 0]
    }

    fn query(command: u8, p0: u8) -> Request {
        Request {
            address: 0,
            command,
            params: [p0, 0, 0, 0, 0, 0, 0],
        }
    }

    #[test]
    fn eight_byte_replies_are_cut_by_their_command_byte() {
        let mut framer = Sixpack2Framer::new(ReplyFraming::Cmd8);
        let reply = position(1, 10_000);
        let mut input = vec![0x00, 0xAA];
        input.extend_from_slice(&reply[..5]);
        assert!(framer.push(&input).is_empty());
        assert_eq!(framer.take_skipped(), [0x00, 0xAA]);
        assert_eq!(framer.pending(), 5);
        let mut rest = reply[5..].to_vec();
        rest.extend_from_slice(&activities());
        assert_eq!(framer.push(&rest), [reply, activities()]);
        assert_eq!(framer.pending(), 0);
    }

    #[test]
    fn nine_byte_replies_carry_an_address_first() {
        let mut framer = Sixpack2Framer::new(ReplyFraming::Addr9);
        let mut reply = vec![0x07];
        reply.extend_from_slice(&position(0, -5));
        let mut input = vec![0x55];
        input.extend_from_slice(&reply);
        assert_eq!(framer.push(&input), [reply]);
        assert_eq!(framer.take_skipped(), [0x55]);
        // One byte could still be an address.
        assert!(framer.push(&[0x01]).is_empty());
        assert_eq!(framer.pending(), 1);
        assert_eq!(framer.discard_pending(), [0x01]);
    }

    #[test]
    fn auto_takes_either_form() {
        let mut framer = Sixpack2Framer::new(ReplyFraming::Auto);
        let short = position(2, 1);
        let mut long = vec![0x00];
        long.extend_from_slice(&position(3, 2));
        let mut input = short.clone();
        input.extend_from_slice(&long);
        input.push(0x00);
        assert_eq!(framer.push(&input), [short, long]);
        assert_eq!(framer.pending(), 1, "a $00 may start an address form");
        // A reply of another unit's address form: its address is skipped
        // and the 8 bytes after it read as the reply itself.
        let mut framer = Sixpack2Framer::new(ReplyFraming::Auto);
        let mut other = vec![0x05];
        other.extend_from_slice(&activities());
        assert_eq!(framer.push(&other), [activities()]);
        assert_eq!(framer.take_skipped(), [0x05]);
    }

    #[test]
    fn a_reply_must_answer_the_query_in_flight() {
        let rule = Sixpack2ReplyRule {
            request: query(0x20, 1),
            framing: ReplyFraming::Auto,
        };
        assert_eq!(rule.examine(&[], &position(1, 7)), Verdict::Complete);
        assert_eq!(
            rule.examine(&[], &position(2, 7)),
            Verdict::NotMine,
            "another motor"
        );
        assert_eq!(
            rule.examine(&[], &activities()),
            Verdict::NotMine,
            "a late $28"
        );
        let mut addressed = vec![0x00];
        addressed.extend_from_slice(&position(1, 7));
        assert_eq!(rule.examine(&[], &addressed), Verdict::Complete);
        assert_eq!(
            rule.examine(&[position(1, 7)], &position(1, 7)),
            Verdict::NotMine,
            "one frame is the whole answer"
        );
        let strict = Sixpack2ReplyRule {
            request: query(0x20, 1),
            framing: ReplyFraming::Cmd8,
        };
        assert_eq!(strict.examine(&[], &addressed), Verdict::NotMine);
    }

    #[test]
    fn a_late_28_is_news() {
        let wire = Sixpack2Wire::default();
        assert_eq!(
            wire.unsolicited(&activities()).as_deref(),
            Some(
                "the motors waited for ($28) are inactive: m0=inactive m1=ramp m2=inactive \
                 m3=inactive m4=inactive m5=inactive"
            )
        );
        assert_eq!(
            wire.unsolicited(&position(0, 0)),
            None,
            "a stale $20 is noise"
        );
        assert_eq!(wire.unsolicited(&[0x28, 0, 0]), None);
    }

    #[test]
    fn a_waited_28_is_taken_only_once_its_motors_are_idle() {
        let request = Request {
            address: 0,
            command: 0x28,
            params: [0, 0b0000_0011, 0, 0, 0, 0, 0],
        };
        let rule = IdleAnswerRule {
            request,
            framing: ReplyFraming::Auto,
        };
        // Motor 1 still ramps: an immediate answer to another $28.
        assert_eq!(rule.examine(&[], &activities()), Verdict::NotMine);
        let idle = vec![0x28, 0, 0, 15, 0, 0, 0, 0];
        assert_eq!(
            rule.examine(&[], &idle),
            Verdict::Complete,
            "motor 2 rotates, but it is not waited for"
        );
        assert_eq!(rule.examine(&[], &position(0, 0)), Verdict::NotMine);
    }

    #[test]
    fn silence_is_four_byte_times_but_never_below_the_floor() {
        let wire = Sixpack2Wire::default();
        assert_eq!(wire.silence(None), MIN_SILENCE);
        assert_eq!(
            wire.silence(Some(Duration::from_millis(10))),
            Duration::from_millis(40)
        );
    }
}
