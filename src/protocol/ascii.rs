//! Line-oriented ASCII wire formats, as the device task sees them: the host
//! sends a line ended by CR, the controller answers in lines. Two answer
//! shapes cover the ASCII families:
//!
//! - [`NextLine`]: the next line is the whole answer (Nippon Pulse CMD-4CR:
//!   `@01POLX\r` → `7\r`, cmd4cr digest §1.3).
//! - [`EchoThenPrompt`]: the controller echoes the command line, prints
//!   zero or more reply lines, and sends its prompt character when done
//!   (PMC MCCL: echo on by default, prompt `>` set by `PCn`, mccl digest
//!   "Echo", "Prompt"). The prompt comes without a line terminator, so the
//!   framer cuts it on its own ([`AsciiWire::prompt`]).
//!
//! Pure code, no I/O.

use std::time::Duration;

use crate::protocol::wire::{Frame, Framer, ReplyRule, Verdict, WireFormat};

const CR: u8 = b'\r';
const LF: u8 = b'\n';

/// Line silence after which a partial line is dropped, in byte times.
const SILENCE_BYTES: u32 = 4;

/// A line-oriented ASCII wire format.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AsciiWire {
    /// Short name for logs.
    pub name: &'static str,
    /// Longest line kept; the rest of a longer line, up to its terminator,
    /// is garbage (noise without a terminator must not grow forever).
    pub max_line: usize,
    /// A character that ends an answer on its own, without a terminator,
    /// when it starts a line (MCCL's prompt, `>` by default).
    pub prompt: Option<u8>,
    /// The shortest line silence that drops a partial line, whatever the
    /// baud rate.
    pub min_silence: Duration,
    /// A line still unterminated when the line falls silent is a frame,
    /// not garbage: the controller ends its answers with a character that
    /// ends no line and that it may be told to change (MCCL `PCn`, Ch13),
    /// so that only silence tells it from the start of a line.
    pub silence_ends_line: bool,
}

/// Line silence floor of the ASCII formats: controllers print long
/// answers (MCCL `HE`, `ID`) in bursts, and a partial line may be the
/// start of one.
pub const ASCII_MIN_SILENCE: Duration = Duration::from_millis(50);

/// The CMD-4CR line: 63 bytes is the longest command or reply its USB
/// interface carries (cmd4cr digest, HID buffers "must be 63 bytes").
pub const CMD4CR_MAX_LINE: usize = 63;

/// MCCL's default prompt character (`PC62`, mccl digest "Prompt").
pub const MCCL_PROMPT: u8 = b'>';

impl AsciiWire {
    /// Nippon Pulse CMD-4CR: one reply line per command, no prompt.
    pub fn cmd4cr() -> Self {
        AsciiWire {
            name: "cmd4cr",
            max_line: CMD4CR_MAX_LINE,
            prompt: None,
            min_silence: ASCII_MIN_SILENCE,
            silence_ends_line: false,
        }
    }

    /// PMC MCCL: echo, reply lines, then the prompt `>`. The manual gives
    /// no maximum line length; help and identification texts stay well
    /// under 256 characters a line.
    pub fn mccl() -> Self {
        AsciiWire {
            name: "mccl",
            max_line: 256,
            prompt: Some(MCCL_PROMPT),
            min_silence: ASCII_MIN_SILENCE,
            silence_ends_line: true,
        }
    }
}

impl WireFormat for AsciiWire {
    fn name(&self) -> &'static str {
        self.name
    }

    fn framer(&self) -> Box<dyn Framer> {
        let framer = LineFramer::new(self.max_line, self.prompt);
        Box::new(if self.silence_ends_line {
            framer.ending_lines_on_silence()
        } else {
            framer
        })
    }

    /// Neither family sends anything unasked in direct mode.
    fn unsolicited(&self, _frame: &[u8]) -> Option<String> {
        None
    }

    fn silence(&self, byte_time: Option<Duration>) -> Duration {
        byte_time
            .map(|t| t.saturating_mul(SILENCE_BYTES))
            .unwrap_or_default()
            .max(self.min_silence)
    }
}

/// Cuts a byte stream into lines ended by CR, LF or CRLF (terminators not
/// kept; empty lines carry nothing and are dropped), plus a prompt
/// character at the start of a line as a frame of its own.
#[derive(Debug, Clone)]
pub struct LineFramer {
    line: Vec<u8>,
    max_line: usize,
    prompt: Option<u8>,
    /// The previous byte was CR: an LF now is the rest of a CRLF.
    after_cr: bool,
    /// The line outgrew `max_line`: skip to its terminator.
    overlong: bool,
    skipped: Vec<u8>,
    /// A partial line that the line's silence ends is a frame.
    silence_ends_line: bool,
}

impl LineFramer {
    pub fn new(max_line: usize, prompt: Option<u8>) -> Self {
        LineFramer {
            line: Vec::new(),
            max_line: max_line.max(1),
            prompt,
            after_cr: false,
            overlong: false,
            skipped: Vec::new(),
            silence_ends_line: false,
        }
    }

    /// The same framer, taking a line still unterminated when the line
    /// falls silent as a frame ([`Framer::complete_on_silence`]).
    pub fn ending_lines_on_silence(mut self) -> Self {
        self.silence_ends_line = true;
        self
    }
}

impl Framer for LineFramer {
    fn push(&mut self, bytes: &[u8]) -> Vec<Frame> {
        let mut frames = Vec::new();
        for &byte in bytes {
            let after_cr = std::mem::replace(&mut self.after_cr, byte == CR);
            if byte == CR || byte == LF {
                if byte == LF && after_cr {
                    continue;
                }
                if self.overlong {
                    self.overlong = false;
                    self.skipped.push(byte);
                } else if !self.line.is_empty() {
                    frames.push(std::mem::take(&mut self.line));
                }
            } else if self.overlong {
                self.skipped.push(byte);
            } else if self.line.is_empty() && Some(byte) == self.prompt {
                frames.push(vec![byte]);
            } else if self.line.len() >= self.max_line {
                self.overlong = true;
                self.skipped.append(&mut self.line);
                self.skipped.push(byte);
            } else {
                self.line.push(byte);
            }
        }
        frames
    }

    fn pending(&self) -> usize {
        // An overlong line still being skipped holds nothing back, but it
        // is unfinished: counting it keeps line silence able to end it.
        self.line.len().max(usize::from(self.overlong))
    }

    fn discard_pending(&mut self) -> Vec<u8> {
        // After silence the next byte starts a new line, even if the
        // dropped one had outgrown the limit.
        self.overlong = false;
        self.after_cr = false;
        std::mem::take(&mut self.line)
    }

    fn take_skipped(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.skipped)
    }

    fn complete_on_silence(&mut self) -> Option<Frame> {
        if !self.silence_ends_line || self.overlong || self.line.is_empty() {
            return None;
        }
        self.after_cr = false;
        Some(std::mem::take(&mut self.line))
    }
}

/// `line` without its terminators and surrounding blanks.
fn trimmed(line: &[u8]) -> &[u8] {
    line.trim_ascii()
}

/// The answer is the next line, whatever it says (an error is a line
/// starting with `?`, which is for the session to read). The CMD-4CR
/// console uses a stricter form of it,
/// [`crate::protocol::cmd4cr::console::Cmd4crReplyRule`], which also
/// passes over a line that cannot answer the command (a late `OK` while a
/// read waits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct NextLine;

impl ReplyRule for NextLine {
    fn examine(&self, accepted: &[Frame], _frame: &[u8]) -> Verdict {
        if accepted.is_empty() {
            Verdict::Complete
        } else {
            Verdict::NotMine
        }
    }
}

/// The echo of the command line, then any reply lines, then the prompt
/// (MCCL). A prompt or line before the echo belongs to something earlier
/// (a late answer) and is not this request's.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EchoThenPrompt {
    /// The command line as sent, without terminators; `None` when the
    /// controller does not echo.
    pub echo: Option<Vec<u8>>,
    pub prompt: u8,
}

impl EchoThenPrompt {
    /// For a command line as sent (its CR, if any, is not part of the echo).
    pub fn new(sent: &[u8], prompt: u8) -> Self {
        EchoThenPrompt {
            echo: Some(trimmed(sent).to_vec()),
            prompt,
        }
    }

    /// For a controller with echo turned off: lines, then the prompt.
    pub fn without_echo(prompt: u8) -> Self {
        EchoThenPrompt { echo: None, prompt }
    }
}

impl ReplyRule for EchoThenPrompt {
    fn examine(&self, accepted: &[Frame], frame: &[u8]) -> Verdict {
        let is_prompt = frame == [self.prompt];
        match (&self.echo, accepted.is_empty()) {
            (Some(echo), true) => {
                if trimmed(frame) == echo.as_slice() {
                    Verdict::Continue
                } else {
                    Verdict::NotMine
                }
            }
            _ if is_prompt => Verdict::Complete,
            _ => Verdict::Continue,
        }
    }
}

/// Bytes as a technician reads an ASCII frame: printable characters as
/// they are, CR and LF as `\r` and `\n`, a backslash doubled, anything
/// else as `\xNN`.
pub fn show_bytes(bytes: &[u8]) -> String {
    let mut text = String::with_capacity(bytes.len());
    for &b in bytes {
        match b {
            b'\r' => text.push_str("\\r"),
            b'\n' => text.push_str("\\n"),
            b'\\' => text.push_str("\\\\"),
            b' '..=b'~' => text.push(char::from(b)),
            _ => text.push_str(&format!("\\x{b:02X}")),
        }
    }
    text
}

/// A console line as sent on an ASCII wire: the line and a CR.
pub fn line_bytes(line: &str) -> Vec<u8> {
    let mut bytes = trimmed(line.as_bytes()).to_vec();
    bytes.push(CR);
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(framer: &mut dyn Framer, input: &[u8]) -> Vec<String> {
        framer
            .push(input)
            .iter()
            .map(|f| String::from_utf8_lossy(f).into_owned())
            .collect()
    }

    #[test]
    fn silence_ends_an_unterminated_line_only_where_asked() {
        let mut plain = LineFramer::new(64, Some(b'>'));
        assert!(plain.push(b"#").is_empty());
        assert_eq!(plain.complete_on_silence(), None, "garbage by default");
        let mut mccl = LineFramer::new(64, Some(b'>')).ending_lines_on_silence();
        assert!(mccl.push(b"1TP\r\n01 5\r\n#").len() == 2);
        assert_eq!(mccl.complete_on_silence(), Some(b"#".to_vec()));
        assert_eq!(mccl.pending(), 0);
        assert_eq!(mccl.complete_on_silence(), None, "nothing held back");
        // The tail of an overlong line is not a frame.
        let mut short = LineFramer::new(2, None).ending_lines_on_silence();
        short.push(b"abcd");
        assert_eq!(short.complete_on_silence(), None);
        assert!(AsciiWire::mccl().silence_ends_line && !AsciiWire::cmd4cr().silence_ends_line);
    }

    #[test]
    fn cr_lf_and_crlf_all_end_a_line() {
        let mut framer = AsciiWire::cmd4cr().framer();
        assert_eq!(
            lines(framer.as_mut(), b"7\rOK\nA\r\nB\n\rC"),
            ["7", "OK", "A", "B"]
        );
        assert_eq!(framer.pending(), 1);
        assert_eq!(lines(framer.as_mut(), b"\r\n"), ["C"]);
        assert_eq!(framer.pending(), 0);
    }

    #[test]
    fn a_line_split_anywhere_is_joined() {
        let mut framer = AsciiWire::cmd4cr().framer();
        assert!(framer.push(b"12").is_empty());
        assert!(framer.push(b"34").is_empty());
        assert_eq!(lines(framer.as_mut(), b"\r"), ["1234"]);
        assert!(framer.push(b"\n").is_empty(), "LF of a split CRLF");
    }

    #[test]
    fn prompt_without_terminator_is_cut_at_line_start_only() {
        let mut framer = AsciiWire::mccl().framer();
        assert_eq!(lines(framer.as_mut(), b"1MR100\r\n>"), ["1MR100", ">"]);
        assert_eq!(framer.pending(), 0);
        // The echo of the next line may follow the prompt at once (">mc10").
        assert_eq!(lines(framer.as_mut(), b">mc10\r"), [">", "mc10"]);
        assert_eq!(lines(framer.as_mut(), b"a>b\r"), ["a>b"]);
        let mut cmd4cr = AsciiWire::cmd4cr().framer();
        assert!(cmd4cr.push(b">").is_empty(), "no prompt configured");
    }

    #[test]
    fn an_overlong_line_is_skipped_up_to_its_terminator() {
        let mut framer = LineFramer::new(4, None);
        assert!(framer.push(b"abcdefgh").is_empty());
        assert_eq!(
            framer.pending(),
            1,
            "nothing held past the limit, but unfinished"
        );
        assert!(framer.push(b"ij\r").is_empty());
        assert_eq!(framer.take_skipped(), b"abcdefghij\r".to_vec());
        assert_eq!(lines(&mut framer, b"ok\r"), ["ok"]);
        assert_eq!(lines(&mut framer, b"abcd\r"), ["abcd"], "exactly the limit");
    }

    #[test]
    fn discarding_after_silence_starts_a_fresh_line() {
        let mut framer = LineFramer::new(4, None);
        assert!(framer.push(b"ab").is_empty());
        assert_eq!(framer.discard_pending(), b"ab".to_vec());
        assert!(framer.push(b"abcdef").is_empty());
        framer.discard_pending();
        assert_eq!(lines(&mut framer, b"7\r"), ["7"]);
    }

    #[test]
    fn next_line_takes_one_line() {
        assert_eq!(NextLine.examine(&[], b"7"), Verdict::Complete);
        assert_eq!(NextLine.examine(&[b"7".to_vec()], b"8"), Verdict::NotMine);
    }

    #[test]
    fn echo_then_reply_lines_then_prompt() {
        let rule = EchoThenPrompt::new(b"1TP\r", b'>');
        assert_eq!(rule.examine(&[], b">"), Verdict::NotMine, "stale prompt");
        assert_eq!(rule.examine(&[], b"2TP"), Verdict::NotMine);
        assert_eq!(rule.examine(&[], b"1TP"), Verdict::Continue);
        let echo = vec![b"1TP".to_vec()];
        assert_eq!(rule.examine(&echo, b">"), Verdict::Complete);
        assert_eq!(rule.examine(&echo, b"01 997"), Verdict::Continue);
        let reply = vec![b"1TP".to_vec(), b"01 997".to_vec()];
        assert_eq!(rule.examine(&reply, b">"), Verdict::Complete);

        let quiet = EchoThenPrompt::without_echo(b'>');
        assert_eq!(quiet.examine(&[], b"?-3"), Verdict::Continue);
        assert_eq!(quiet.examine(&[b"?-3".to_vec()], b">"), Verdict::Complete);
    }

    #[test]
    fn silence_has_a_floor() {
        let wire = AsciiWire::mccl();
        assert_eq!(wire.silence(None), ASCII_MIN_SILENCE);
        assert_eq!(
            wire.silence(Some(Duration::from_millis(100))),
            Duration::from_millis(400)
        );
        assert_eq!(line_bytes(" @01POLX "), b"@01POLX\r".to_vec());
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            #[test]
            fn framer_never_panics_and_bounds_what_it_holds(
                chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..40), 0..20),
                max_line in 1usize..16,
                prompt in proptest::option::of(any::<u8>()),
            ) {
                let mut framer = LineFramer::new(max_line, prompt);
                for chunk in &chunks {
                    for frame in framer.push(chunk) {
                        prop_assert!(!frame.is_empty());
                        prop_assert!(frame.len() <= max_line);
                        prop_assert!(!frame.contains(&CR) && !frame.contains(&LF));
                    }
                    prop_assert!(framer.pending() <= max_line.max(1));
                    let _ = framer.take_skipped();
                }
            }

            #[test]
            fn lines_come_back_however_they_are_split(
                text in proptest::collection::vec("[a-zA-Z0-9 ?@.-]{1,12}", 1..8),
                cut in any::<proptest::sample::Index>(),
                ending in prop_oneof![Just("\r"), Just("\n"), Just("\r\n")],
            ) {
                let wanted: Vec<String> = text
                    .iter()
                    .map(|l| l.to_string())
                    .filter(|l| !l.is_empty())
                    .collect();
                let stream: String = text.iter().map(|l| format!("{l}{ending}")).collect();
                let bytes = stream.as_bytes();
                let at = cut.index(bytes.len() + 1);
                let mut framer = LineFramer::new(64, None);
                let mut got = lines(&mut framer, &bytes[..at]);
                got.extend(lines(&mut framer, &bytes[at..]));
                prop_assert_eq!(got, wanted);
            }
        }
    }
}
