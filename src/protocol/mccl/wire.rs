//! The MCCL interface as the device task sees it: lines cut at CR, LF or
//! CRLF, the prompt as a frame of its own (a changed prompt ended by the
//! line falling quiet), the quiet guard of the digest's end-of-reply
//! algorithm (§3.3 step 3), and what tells answers apart: with echo on,
//! every answer starts with the echo of its own line (Ch2), so two
//! different lines' answers cannot be taken for each other, and `NO` (no
//! operation, Ch13) settles the line after an answer went missing.

use std::sync::Arc;
use std::time::Duration;

use super::profile::{Echo, LinkProfile};
use super::reply::AnswerRule;
use crate::protocol::ascii::{ASCII_MIN_SILENCE, AsciiWire};
use crate::protocol::wire::{Framer, Sentinel, Settling, WireFormat};

/// The sentinel: a line that does nothing and answers with its echo.
const SENTINEL: &str = "NO";

/// The wire format of one MCCL interface.
#[derive(Debug, Clone)]
pub struct MclWire {
    lines: AsciiWire,
    quiet_guard: Duration,
    echo: Echo,
}

impl MclWire {
    /// For an interface with `profile` (as the console assumes it at
    /// connect: the echo it tells answers apart by, the prompt the framer
    /// cuts at once).
    pub fn new(profile: &LinkProfile) -> MclWire {
        MclWire {
            lines: AsciiWire {
                name: "mccl",
                max_line: profile.max_reply_line,
                prompt: profile.prompt,
                min_silence: ASCII_MIN_SILENCE,
                silence_ends_line: true,
            },
            quiet_guard: profile.quiet_guard,
            echo: profile.echo,
        }
    }
}

/// A line as sent, without its CR and blanks.
fn text(bytes: &[u8]) -> &[u8] {
    bytes.trim_ascii()
}

impl WireFormat for MclWire {
    fn name(&self) -> &'static str {
        "mccl"
    }

    fn framer(&self) -> Box<dyn Framer> {
        self.lines.framer()
    }

    /// Nothing comes unasked in direct mode (a background task's `OT` is
    /// shown as stale output).
    fn unsolicited(&self, _frame: &[u8]) -> Option<String> {
        None
    }

    fn silence(&self, byte_time: Option<Duration>) -> Duration {
        self.lines.silence(byte_time)
    }

    fn quiet_guard(&self, byte_time: Option<Duration>) -> Duration {
        self.quiet_guard.max(self.silence(byte_time))
    }

    /// With echo on, the answer direction carries the line's echo (its CR
    /// echoed as CR LF, Ch2) beside the answer: `1TP,TV,TS` comes back as
    /// 30 bytes (11 of echo, three `01 0` lines and the prompt), three
    /// times the line. Without echo, the default.
    fn exchange_bytes(&self, request: &[u8]) -> usize {
        match self.echo {
            Echo::Line => request.len().saturating_mul(3),
            _ => request.len().saturating_mul(2),
        }
    }

    /// With echo on, an answer starts with the echo of its own line: the
    /// answers to two different lines cannot be taken for each other.
    fn answers_apart(&self, earlier: &[u8], next: &[u8]) -> bool {
        self.echo == Echo::Line && text(earlier) != text(next)
    }

    /// `NO` first, unless it is itself among the unanswered; without echo
    /// nothing tells answers apart.
    fn settling(&self, _next: &[u8], unanswered: &[&[u8]]) -> Settling {
        if self.echo != Echo::Line {
            return Settling::QuietTime;
        }
        if unanswered.iter().any(|u| text(u) == SENTINEL.as_bytes()) {
            return Settling::InOrder;
        }
        let mut bytes = SENTINEL.as_bytes().to_vec();
        bytes.push(b'\r');
        // Its echo, then whatever prompt the interface has now: quiet ends
        // it, so that a prompt changed by `PC` ends it too.
        let rule = AnswerRule {
            echo: Some(SENTINEL.as_bytes().to_vec()),
            prompt: None,
            prompts: None,
        };
        Settling::Sentinel(Sentinel {
            bytes,
            rule: Arc::new(rule),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::wire::Verdict;

    #[test]
    fn different_lines_answer_apart_only_with_echo() {
        let wire = MclWire::new(&LinkProfile::MANUAL);
        assert!(wire.answers_apart(b"1TP\r", b"2TP\r"));
        assert!(wire.answers_apart(b"1TP\r", b"1TP,TV\r"));
        assert!(!wire.answers_apart(b"1TP\r", b"1TP\r"));
        let quiet = MclWire::new(&LinkProfile::MANUAL.with_echo(Echo::Off));
        assert!(!quiet.answers_apart(b"1TP\r", b"2TP\r"));
        assert!(matches!(
            quiet.settling(b"1TP\r", &[b"1TP\r"]),
            Settling::QuietTime
        ));
    }

    #[test]
    fn no_settles_the_line_unless_it_is_unanswered_itself() {
        let wire = MclWire::new(&LinkProfile::MANUAL);
        let Settling::Sentinel(sentinel) = wire.settling(b"1TP\r", &[b"1TP\r"]) else {
            panic!("a sentinel");
        };
        assert_eq!(sentinel.bytes, b"NO\r");
        assert_eq!(sentinel.rule.examine(&[], b"1TP"), Verdict::NotMine);
        assert_eq!(sentinel.rule.examine(&[], b"NO"), Verdict::Continue);
        let echo = vec![b"NO".to_vec()];
        assert_eq!(sentinel.rule.examine(&echo, b">"), Verdict::CompleteIfQuiet);
        assert_eq!(sentinel.rule.examine(&echo, b"#"), Verdict::CompleteIfQuiet);
        assert!(matches!(
            wire.settling(b"1TP\r", &[b"NO\r"]),
            Settling::InOrder
        ));
        assert!(wire.quiet_guard(None) >= LinkProfile::MANUAL.quiet_guard);
    }
}
