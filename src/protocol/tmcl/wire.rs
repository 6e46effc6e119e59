//! TMCL as the device task sees it: 9-byte frames with no start byte
//! (§3.1, §3.2), a reply recognised by its module address and echoed
//! command, and the one unsolicited frame TMCL has, the status-128 second
//! reply of command 138 (§3.6.52).
//!
//! A reply carries no sequence number, but it echoes the module address
//! and the command (§3.2 Table 3): answers to requests that differ in
//! either are never taken for each other, and a control command of another
//! number is a sentinel after a lost answer. The value field does not help:
//! the manual gives the reply value of SAP, SGP, MVP and most writes as
//! "don't care" (§3.6.5, §3.6.9), so it cannot be expected to echo the
//! value written.

use std::sync::Arc;
use std::time::Duration;

use super::command::opcode;
use super::frame::{FRAME_LEN, Reply, Request, Status, checksum};
use crate::protocol::wire::{Frame, Framer, ReplyRule, Sentinel, Settling, Verdict, WireFormat};

/// Line silence after which a partial frame is dropped, in byte times.
/// Modbus RTU, the nearest standard without a start byte, uses 3.5.
const SILENCE_BYTES: u32 = 4;

/// The shortest silence that counts, whatever the baud rate: a USB-serial
/// adapter holds received bytes for up to its latency timer (16 ms by
/// default on FTDI chips) and may cut one reply into two bursts that far
/// apart; a serial-over-TCP bridge can split a reply over two segments.
/// Waiting this long only costs time after garbage or a timeout.
pub const MIN_SILENCE: Duration = Duration::from_millis(20);

/// The TMCL wire format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TmclWire {
    /// After garbage, slide byte by byte to the next nine bytes whose
    /// checksum is good instead of waiting for line silence: a reply that
    /// follows noise on the line is still found. Without it, frames are
    /// cut every nine bytes and only silence brings the framer back in step.
    pub slide: bool,
}

impl Default for TmclWire {
    fn default() -> Self {
        TmclWire { slide: true }
    }
}

/// True for nine bytes whose last is the sum of the others (§3.1.1).
fn checksum_ok(frame: &[u8]) -> bool {
    match frame.split_last() {
        Some((last, body)) if frame.len() == FRAME_LEN => checksum(body) == *last,
        _ => false,
    }
}

/// The answer to 136 type 0: the host address and eight ASCII characters,
/// with no checksum (§3.6.53 gives no layout; digest D4 from sibling
/// manuals, and what PyTrinamic reads). A sliding framer must not step
/// over it.
pub fn is_version_string(frame: &[u8]) -> bool {
    frame.len() == FRAME_LEN && frame.iter().skip(1).all(u8::is_ascii_graphic)
}

/// The sentinels: control commands that read and change nothing (§3.6.53
/// Table 14) and that a module executes even in download mode, where other
/// commands are stored instead (§3.6.53, command 132): 136 type 1 (the
/// firmware version as a number, one of the commands "relevant for custom
/// hosts") and 135 type 0 (the application status), as (command, type).
const SENTINELS: [(u8, u8); 2] = [
    (opcode::FIRMWARE_VERSION, 1),
    (opcode::APPLICATION_STATUS, 0),
];

/// A request whose answer is laid out other than an ordinary reply (136
/// type 0: eight characters and no checksum; 134: a program word): it
/// echoes neither address nor command, so nothing tells it apart.
fn answered_specially(request: &[u8]) -> bool {
    match request {
        [_, command, kind, ..] => {
            (*command == opcode::FIRMWARE_VERSION && *kind == 0) || *command == opcode::READ_MEMORY
        }
        _ => true,
    }
}

/// A well-formed reply frame, decoded.
fn decode_reply(frame: &[u8]) -> Option<Reply> {
    let bytes: &[u8; FRAME_LEN] = frame.try_into().ok()?;
    Reply::from_bytes(bytes).ok()
}

/// §3.6.52: the second reply of 138 carries status 128 and answers nothing.
fn is_target_reached(reply: &Reply) -> bool {
    reply.status == Status::TARGET_REACHED && reply.command == opcode::TARGET_REACHED_EVENT
}

impl WireFormat for TmclWire {
    fn name(&self) -> &'static str {
        "tmcl"
    }

    fn framer(&self) -> Box<dyn Framer> {
        Box::new(TmclFramer::new(self.slide))
    }

    fn unsolicited(&self, frame: &[u8]) -> Option<String> {
        let reply = decode_reply(frame)?;
        is_target_reached(&reply).then(|| {
            format!(
                "target position reached (138) on module {}, motor mask {}",
                reply.module_address, reply.value
            )
        })
    }

    fn silence(&self, byte_time: Option<Duration>) -> Duration {
        byte_time
            .map(|t| t.saturating_mul(SILENCE_BYTES))
            .unwrap_or_default()
            .max(MIN_SILENCE)
    }

    /// Different modules or different commands (§3.2: the reply echoes
    /// both), unless one of them is answered in a layout of its own.
    fn answers_apart(&self, earlier: &[u8], next: &[u8]) -> bool {
        if earlier.len() != FRAME_LEN
            || next.len() != FRAME_LEN
            || answered_specially(earlier)
            || answered_specially(next)
        {
            return false;
        }
        earlier[0] != next[0] || earlier[1] != next[1]
    }

    /// A sentinel to the module `next` goes to, of a command none of the
    /// unanswered requests has; none if one of them went to another module
    /// (a sentinel says nothing about another module's answers: quiet
    /// time) or reads program memory (whose answer any checksummed frame
    /// could be: in order); when both sentinels are among the unanswered,
    /// wait for one.
    fn settling(&self, next: &[u8], unanswered: &[&[u8]]) -> Settling {
        let Some(&address) = next.first().filter(|_| next.len() == FRAME_LEN) else {
            return Settling::QuietTime;
        };
        let same_module = unanswered
            .iter()
            .all(|r| r.len() == FRAME_LEN && r[0] == address);
        if !same_module {
            return Settling::QuietTime;
        }
        if unanswered.iter().any(|r| r[1] == opcode::READ_MEMORY) {
            return Settling::InOrder;
        }
        // Both sentinels unanswered: wait until one is free. Matching in
        // order would be a guess: a dropped answer leaves the next one to
        // be taken for the oldest request it could answer (a GGP 5 answer
        // for an earlier GGP 0's, which TMCL replies cannot tell apart,
        // §3.2).
        SENTINELS
            .into_iter()
            .find(|(command, _)| unanswered.iter().all(|r| r[1] != *command))
            .map_or(Settling::AwaitSentinel, |(command, kind)| {
                let request = Request {
                    address,
                    command,
                    kind,
                    motor_bank: 0,
                    value: 0,
                };
                Settling::Sentinel(Sentinel {
                    bytes: request.to_bytes().to_vec(),
                    rule: Arc::new(TmclReplyRule::for_request(&request)),
                })
            })
    }
}

/// Cuts the byte stream into 9-byte frames, optionally sliding over
/// garbage to the next frame with a good checksum.
#[derive(Debug, Clone, Default)]
pub struct TmclFramer {
    pending: Vec<u8>,
    skipped: Vec<u8>,
    slide: bool,
}

impl TmclFramer {
    pub fn new(slide: bool) -> Self {
        TmclFramer {
            slide,
            ..Self::default()
        }
    }
}

impl Framer for TmclFramer {
    fn push(&mut self, bytes: &[u8]) -> Vec<Frame> {
        self.pending.extend_from_slice(bytes);
        let mut frames = Vec::new();
        let mut start = 0;
        while let Some(window) = self.pending.get(start..start + FRAME_LEN) {
            if !self.slide || checksum_ok(window) || is_version_string(window) {
                frames.push(window.to_vec());
                start += FRAME_LEN;
            } else {
                self.skipped.extend_from_slice(&window[..1]);
                start += 1;
            }
        }
        self.pending.drain(..start);
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

/// The answer to one TMCL request: a single frame with a good checksum,
/// the request's module address and its command echoed (§3.2 Table 3).
/// The host address (GP76) is not checked: `SGP 76` changes it, and its
/// own reply already carries the new one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TmclReplyRule {
    pub address: u8,
    pub command: u8,
}

impl TmclReplyRule {
    pub fn for_request(request: &Request) -> Self {
        TmclReplyRule {
            address: request.address,
            command: request.command,
        }
    }
}

impl ReplyRule for TmclReplyRule {
    fn examine(&self, accepted: &[Frame], frame: &[u8]) -> Verdict {
        if !accepted.is_empty() {
            return Verdict::NotMine;
        }
        match decode_reply(frame) {
            Some(reply)
                if reply.module_address == self.address
                    && reply.command == self.command
                    && !is_target_reached(&reply) =>
            {
                Verdict::Complete
            }
            _ => Verdict::NotMine,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reply(module: u8, status: u8, command: u8, value: i32) -> Vec<u8> {
        Reply {
            host_address: 2,
            module_address: module,
            status: Status(status),
            command,
            value,
        }
        .to_bytes()
        .to_vec()
    }

    fn gap(address: u8) -> Request {
        Request {
            address,
            command: 6,
            kind: 1,
            motor_bank: 0,
            value: 0,
        }
    }

    #[test]
    fn a_reply_needs_good_checksum_address_and_echo() {
        let rule = TmclReplyRule::for_request(&gap(1));
        assert_eq!(rule.examine(&[], &reply(1, 100, 6, 42)), Verdict::Complete);
        assert_eq!(
            rule.examine(&[], &reply(1, 4, 6, 0)),
            Verdict::Complete,
            "an error status is still the answer"
        );
        assert_eq!(rule.examine(&[], &reply(3, 100, 6, 42)), Verdict::NotMine);
        assert_eq!(rule.examine(&[], &reply(1, 100, 5, 42)), Verdict::NotMine);
        let mut bad = reply(1, 100, 6, 42);
        bad[8] ^= 1;
        assert_eq!(rule.examine(&[], &bad), Verdict::NotMine);
        assert_eq!(rule.examine(&[], &bad[..8]), Verdict::NotMine);
        let one = reply(1, 100, 6, 42);
        assert_eq!(
            rule.examine(std::slice::from_ref(&one), &one),
            Verdict::NotMine,
            "one frame is the whole answer"
        );
    }

    #[test]
    fn the_second_reply_of_138_is_news_never_an_answer() {
        let request = Request {
            address: 1,
            command: 138,
            kind: 1,
            motor_bank: 0,
            value: 1,
        };
        let rule = TmclReplyRule::for_request(&request);
        assert_eq!(rule.examine(&[], &reply(1, 100, 138, 1)), Verdict::Complete);
        let reached = reply(1, 128, 138, 1);
        assert_eq!(rule.examine(&[], &reached), Verdict::NotMine);
        let wire = TmclWire::default();
        assert_eq!(
            wire.unsolicited(&reached).as_deref(),
            Some("target position reached (138) on module 1, motor mask 1")
        );
        assert_eq!(wire.unsolicited(&reply(1, 100, 138, 1)), None);
        assert_eq!(wire.unsolicited(&reply(1, 128, 6, 1)), None);
        let mut bad = reached.clone();
        bad[4] ^= 0x10;
        assert_eq!(wire.unsolicited(&bad), None);
    }

    fn bytes(request: &Request) -> Vec<u8> {
        request.to_bytes().to_vec()
    }

    #[test]
    fn answers_are_apart_when_module_or_command_differ() {
        let wire = TmclWire::default();
        let gap = gap(1);
        let sap = Request { command: 5, ..gap };
        let other_module = Request { address: 2, ..gap };
        let other_param = Request { kind: 4, ..gap };
        assert!(wire.answers_apart(&bytes(&gap), &bytes(&sap)));
        assert!(wire.answers_apart(&bytes(&gap), &bytes(&other_module)));
        assert!(
            !wire.answers_apart(&bytes(&gap), &bytes(&other_param)),
            "GAP 1 and GAP 4 are both answered by command 6 with a value"
        );
        let version = Request {
            command: 136,
            kind: 0,
            ..gap
        };
        let version_elsewhere = Request {
            address: 2,
            ..version
        };
        assert!(
            !wire.answers_apart(&bytes(&version), &bytes(&version_elsewhere)),
            "the version string carries no module address"
        );
        assert!(!wire.answers_apart(&bytes(&version), &bytes(&sap)));
        assert!(!wire.answers_apart(&bytes(&gap)[..8], &bytes(&sap)));
    }

    fn settling_of(next: &Request, unanswered: &[Request]) -> Settling {
        let unanswered: Vec<Vec<u8>> = unanswered.iter().map(bytes).collect();
        let views: Vec<&[u8]> = unanswered.iter().map(Vec::as_slice).collect();
        TmclWire::default().settling(&bytes(next), &views)
    }

    #[test]
    fn the_sentinel_is_a_control_command_no_unanswered_request_has() {
        let Settling::Sentinel(sentinel) = settling_of(&gap(1), &[gap(1)]) else {
            panic!("a sentinel")
        };
        assert_eq!(sentinel.bytes, vec![1, 136, 1, 0, 0, 0, 0, 0, 138]);
        let answer = reply(1, 100, 136, 1012);
        assert_eq!(sentinel.rule.examine(&[], &answer), Verdict::Complete);
        assert_eq!(
            sentinel.rule.examine(&[], &reply(1, 100, 6, 1012)),
            Verdict::NotMine
        );
        let version = Request {
            command: 136,
            kind: 1,
            ..gap(1)
        };
        let Settling::Sentinel(sentinel) = settling_of(&gap(1), &[gap(1), version]) else {
            panic!("a sentinel")
        };
        assert_eq!(sentinel.bytes[..3], [1, 135, 0]);
        let status = Request {
            command: 135,
            ..version
        };
        // Both sentinels unanswered: wait for one, never a guess in order
        // (tests/device_faults.rs found a poll given another read's answer).
        assert!(matches!(
            settling_of(&gap(1), &[version, status]),
            Settling::AwaitSentinel
        ));
        let read_memory = Request {
            command: 134,
            ..gap(1)
        };
        assert!(matches!(
            settling_of(&gap(1), &[read_memory]),
            Settling::InOrder
        ));
        assert!(
            matches!(settling_of(&gap(1), &[gap(2)]), Settling::QuietTime),
            "a sentinel to module 1 says nothing of module 2's answers"
        );
    }

    #[test]
    fn sliding_framer_finds_a_reply_behind_garbage() {
        let good = reply(1, 100, 6, 1234);
        let mut framer = TmclWire::default().framer();
        let mut input = vec![0xAA, 0x55, 0x01];
        input.extend_from_slice(&good[..5]);
        assert!(framer.push(&input).is_empty());
        assert_eq!(framer.push(&good[5..]), vec![good.clone()]);
        assert_eq!(framer.take_skipped(), vec![0xAA, 0x55, 0x01]);
        assert!(framer.take_skipped().is_empty());
        assert_eq!(framer.pending(), 0);
    }

    #[test]
    fn sliding_framer_keeps_the_version_string_that_has_no_checksum() {
        let mut version = vec![2];
        version.extend_from_slice(b"1110V112");
        let mut framer = TmclWire::default().framer();
        let mut input = vec![0xAA];
        input.extend_from_slice(&version);
        assert_eq!(framer.push(&input), vec![version]);
        assert_eq!(framer.take_skipped(), vec![0xAA]);
    }

    #[test]
    fn plain_framer_cuts_every_nine_bytes_and_resyncs_on_discard() {
        let good = reply(1, 100, 6, 1234);
        let mut framer = TmclWire { slide: false }.framer();
        let mut input = vec![0xAA, 0x55];
        input.extend_from_slice(&good);
        let frames = framer.push(&input);
        assert_eq!(frames.len(), 1);
        assert_ne!(frames[0], good);
        assert_eq!(framer.pending(), 2);
        assert_eq!(framer.discard_pending(), good[7..].to_vec());
        assert_eq!(framer.push(&good), vec![good]);
        assert!(framer.take_skipped().is_empty());
    }

    #[test]
    fn silence_is_four_byte_times_but_never_below_the_floor() {
        let wire = TmclWire::default();
        assert_eq!(wire.silence(None), MIN_SILENCE);
        assert_eq!(
            wire.silence(Some(Duration::from_micros(1042))),
            MIN_SILENCE,
            "9600 Bd"
        );
        assert_eq!(
            wire.silence(Some(Duration::from_millis(10))),
            Duration::from_millis(40),
            "1000 Bd"
        );
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            #[test]
            fn sliding_framer_keeps_or_skips_every_byte(
                chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..30), 0..20),
                slide: bool,
            ) {
                let mut framer = TmclFramer::new(slide);
                let mut fed = 0;
                let mut out = 0;
                for chunk in &chunks {
                    fed += chunk.len();
                    for frame in framer.push(chunk) {
                        prop_assert_eq!(frame.len(), FRAME_LEN);
                        if slide {
                            prop_assert!(checksum_ok(&frame) || is_version_string(&frame));
                        }
                        out += frame.len();
                    }
                    out += framer.take_skipped().len();
                }
                prop_assert!(framer.pending() < FRAME_LEN);
                prop_assert_eq!(fed, out + framer.pending());
            }

            #[test]
            fn a_good_reply_after_any_garbage_is_found(
                garbage in proptest::collection::vec(any::<u8>(), 0..20),
                value: i32,
            ) {
                let good = reply(1, 100, 10, value);
                let mut framer = TmclFramer::new(true);
                let mut input = garbage.clone();
                input.extend_from_slice(&good);
                let frames = framer.push(&input);
                // Garbage can hold a good checksum by chance, and such a
                // false frame may swallow the start of the reply; but no
                // frame other than the reply is ever taken for the answer.
                let rule = TmclReplyRule { address: 1, command: 10 };
                for frame in &frames {
                    if rule.examine(&[], frame) == Verdict::Complete {
                        prop_assert_eq!(frame, &good);
                    }
                }
                prop_assert!(frames.contains(&good) || frames.iter().any(|f| f != &good));
            }
        }
    }
}
