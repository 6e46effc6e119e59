//! The CMD-4CR as the device task sees it: the ASCII line format of
//! [`AsciiWire::cmd4cr`] (`@01PX␍` → `7␍`, §3.2.2), and how a late answer
//! is told from the next one.
//!
//! An answer carries neither the controller's ID nor the command it
//! answers, and an error line (`?…`, §4.2) may answer any command: no two
//! requests' answers are told apart by their look ([`WireFormat::answers_apart`]
//! keeps its default). What tells them apart is the answer's form: `OK`
//! answers a write or action only, a bare number an integer read only,
//! four `:`-separated numbers PP, EP or BSTAT only (cmd4cr digest §1.4). A
//! read whose answer has a form no unanswered request's answer can have is
//! a sentinel: `PP` (every axis's position, §2.6.1.1), or `PX` (X's
//! position) when a four-field answer is among those that may still come.

use std::sync::Arc;
use std::time::Duration;

use super::catalog::{Format, Register};
use super::command::{Cmd4crCommand, Selector, parse_command};
use super::reply::succeeds;
use super::{Axis, frame, parse_request};
use crate::protocol::ascii::AsciiWire;
use crate::protocol::wire::{Frame, Framer, ReplyRule, Sentinel, Settling, Verdict, WireFormat};

/// The CMD-4CR wire format.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cmd4crWire {
    lines: AsciiWire,
}

impl Default for Cmd4crWire {
    fn default() -> Self {
        Cmd4crWire {
            lines: AsciiWire::cmd4cr(),
        }
    }
}

/// Which success answers a sentinel's form could be confused with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Form {
    /// `OK`: writes and actions.
    Done,
    /// One number (integers, two digits, thousandths).
    Number,
    /// `:`-separated numbers.
    Fields,
    /// Anything at all (VER's text, a frame that does not parse).
    Any,
}

/// The form of the success answer to a request as sent.
fn answer_form(request: &[u8]) -> Form {
    let Ok(request) = parse_request(request) else {
        return Form::Any;
    };
    let Ok(command) = parse_command(&request.text) else {
        return Form::Any;
    };
    match command.reply_format() {
        None => Form::Done,
        Some(Format::Integer | Format::TwoDigits | Format::Thousandths) => Form::Number,
        Some(Format::Fields(_)) => Form::Fields,
        Some(Format::Text) => Form::Any,
    }
}

/// The sentinels, each with the form of its answer, in order of choice.
fn sentinels() -> [(Cmd4crCommand, Form); 2] {
    [
        (
            Cmd4crCommand::Read {
                register: Register::Pp,
                selector: Selector::All,
            },
            Form::Fields,
        ),
        (
            Cmd4crCommand::Read {
                register: Register::P,
                selector: Selector::Axis(Axis::X),
            },
            Form::Number,
        ),
    ]
}

/// A sentinel's answer: its success answer only. An error line could be
/// any earlier request's, so it is not the sentinel's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SentinelRule {
    pub format: Format,
}

impl ReplyRule for SentinelRule {
    fn examine(&self, accepted: &[Frame], frame: &[u8]) -> Verdict {
        if accepted.is_empty() && succeeds(&String::from_utf8_lossy(frame), Some(self.format)) {
            Verdict::Complete
        } else {
            Verdict::NotMine
        }
    }
}

impl WireFormat for Cmd4crWire {
    fn name(&self) -> &'static str {
        self.lines.name()
    }

    fn framer(&self) -> Box<dyn Framer> {
        self.lines.framer()
    }

    fn unsolicited(&self, frame: &[u8]) -> Option<String> {
        self.lines.unsolicited(frame)
    }

    fn silence(&self, byte_time: Option<Duration>) -> Duration {
        self.lines.silence(byte_time)
    }

    fn settling(&self, next: &[u8], unanswered: &[&[u8]]) -> Settling {
        // A sentinel speaks for its own controller only (answers carry no
        // ID: on a bus, another controller's late answer is not ordered
        // with this one's).
        let Ok(target) = parse_request(next) else {
            return Settling::QuietTime;
        };
        let same_controller = unanswered
            .iter()
            .all(|request| parse_request(request).is_ok_and(|r| r.id == target.id));
        if !same_controller {
            return Settling::QuietTime;
        }
        let forms: Vec<Form> = unanswered.iter().map(|r| answer_form(r)).collect();
        sentinels()
            .into_iter()
            .find(|(_, form)| !forms.iter().any(|f| f == form || *f == Form::Any))
            .and_then(|(command, _)| {
                let format = command.reply_format()?;
                Some(Settling::Sentinel(Sentinel {
                    bytes: frame(target.id, &command.to_string()),
                    rule: Arc::new(SentinelRule { format }),
                }))
            })
            // Answers are bare values that cannot be told apart: wait
            // for a sentinel rather than match in order.
            .unwrap_or(Settling::AwaitSentinel)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sentinel_of(next: &str, unanswered: &[&str]) -> Option<(String, Arc<dyn ReplyRule>)> {
        let unanswered: Vec<Vec<u8>> = unanswered.iter().map(|l| l.as_bytes().to_vec()).collect();
        let views: Vec<&[u8]> = unanswered.iter().map(Vec::as_slice).collect();
        match Cmd4crWire::default().settling(next.as_bytes(), &views) {
            Settling::Sentinel(s) => Some((String::from_utf8_lossy(&s.bytes).into_owned(), s.rule)),
            Settling::AwaitSentinel => None,
            Settling::InOrder => panic!("bare values are never matched in order"),
            Settling::QuietTime => panic!("a single controller always has sentinels"),
        }
    }

    #[test]
    fn pp_settles_unless_a_four_field_answer_may_still_come() {
        let (bytes, rule) = sentinel_of("@01PX\r", &["@01MSTX\r", "@01JX+\r"]).expect("a sentinel");
        assert_eq!(bytes, "@01PP\r");
        assert_eq!(rule.examine(&[], b"1:2:3:4"), Verdict::Complete);
        for not_its in [&b"12"[..], b"OK", b"?Error Moving", b"1:2"] {
            assert_eq!(rule.examine(&[], not_its), Verdict::NotMine);
        }
        let (bytes, rule) = sentinel_of("@07PX\r", &["@07PP\r"]).expect("a sentinel");
        assert_eq!(bytes, "@07PX\r");
        assert_eq!(rule.examine(&[], b"-12"), Verdict::Complete);
        assert_eq!(rule.examine(&[], b"1:2:3:4"), Verdict::NotMine);
        assert_eq!(rule.examine(&[], b"?Program Error"), Verdict::NotMine);
    }

    #[test]
    fn without_a_sentinel_of_another_form_the_next_request_waits_for_one() {
        assert!(sentinel_of("@01PX\r", &["@01PP\r", "@01PX\r"]).is_none());
        assert!(
            sentinel_of("@01PX\r", &["@01VER\r"]).is_none(),
            "VER's text could look like anything"
        );
        assert!(sentinel_of("@01PX\r", &["@01SLRX\r", "@01EP\r"]).is_none());
    }

    #[test]
    fn another_controllers_late_answer_is_left_to_the_quiet_time() {
        let unanswered: [&[u8]; 1] = [b"@02PX\r"];
        assert!(matches!(
            Cmd4crWire::default().settling(b"@01PX\r", &unanswered),
            Settling::QuietTime
        ));
        let garbled: [&[u8]; 1] = [b"PX\r"];
        assert!(matches!(
            Cmd4crWire::default().settling(b"@01PX\r", &garbled),
            Settling::QuietTime
        ));
    }

    #[test]
    fn no_two_requests_are_told_apart_by_their_answers_alone() {
        // `?Error Moving` may answer either.
        assert!(!Cmd4crWire::default().answers_apart(b"@01JX+\r", b"@01PX\r"));
    }
}
