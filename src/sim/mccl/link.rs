//! The ASCII command port (manual Ch2, Ch13 PC, Ch14): echo of what is
//! typed, the line being typed with backspace editing, the prompt when a
//! line completes, error reports, and what goes back on the wire.
//!
//! The manual leaves the wire form open (digest §3.2), so the simulator's
//! choices are settings ([`LinkProfile`], changeable from outside with the
//! `ECHO`, `EOL`, `PROMPTS`, `ERRORS`, `TELLAXIS` inputs):
//! - echo on, every byte typed echoed as it arrives; the CR that ends a
//!   line is echoed as the line terminator;
//! - every line of output ends with the terminator, CR LF by default;
//! - the prompt (`>`, `PCn`) follows a line's completion (or, as a
//!   setting, each command of it), after an error report too; it ends no
//!   line, so the next typed line follows it (`>mc10` in Ch4's transcript);
//! - an error is `?code` and the offending command (`?-6 MC10`, Ch14
//!   "Many error code reports ... include ... the offending command"), or
//!   `?code` alone as a setting;
//! - a Tell reply is `AA value`, the axis field two digits (Ch8), or the
//!   bare value (the Ch8 introduction's `123`) as a setting.

use super::errors::Code;
use super::lexer::Radix;

/// ASCII Escape: abort (Ch2).
pub const ESCAPE: u8 = 0x1B;
/// Space pauses and resumes a running line (Ch2); in single-step mode it
/// runs the next command (Ch4).
pub const SPACE: u8 = b' ';
/// The key that turns single stepping on while a line runs. The manual's
/// "<ctrl> ." lost its key in conversion; Ctrl-T (0x14) is the simulator's.
pub const STEP_KEY: u8 = 0x14;
pub const BACKSPACE: u8 = 0x08;
pub const DELETE: u8 = 0x7F;
/// The longest line kept (error 4 "Command string too long" beyond it;
/// the manual gives no number).
pub const MAX_LINE: usize = 512;
/// The default prompt, `>` (Ch13 PC).
pub const DEFAULT_PROMPT: u8 = b'>';
/// Output bytes not yet on the wire above which a reporting command waits
/// (the simulated port's transmit buffer). The manual gives no buffer; a
/// small one keeps a line of many Tells running while its answer goes
/// out, so that Escape can still cut it short (Ch2): at 9600 Bd the last
/// 24 bytes take 25 ms.
pub const TRANSMIT_BUFFER: f64 = 24.0;
/// The rate the simulated port sends at, bytes per second, until the line
/// it is connected by says its own: 115200 Bd.
pub const DEFAULT_OUTPUT_RATE: f64 = 11_520.0;

/// What ends a line of output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Eol {
    Cr,
    Lf,
    CrLf,
}

impl Eol {
    pub fn bytes(self) -> &'static [u8] {
        match self {
            Eol::Cr => b"\r",
            Eol::Lf => b"\n",
            Eol::CrLf => b"\r\n",
        }
    }
}

/// When the prompt is sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PromptGranularity {
    /// Once the whole line has completed.
    Line,
    /// After every command of the line ("when the controller completes
    /// execution of a command", Ch13 PC, read the other way).
    Command,
}

/// What an error report holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorText {
    /// `?-6`
    Code,
    /// `?-6 MC10`
    CodeAndCommand,
}

/// The wire form of the port, where the manual is silent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkProfile {
    pub echo: bool,
    pub eol: Eol,
    pub prompts: PromptGranularity,
    pub errors: ErrorText,
    /// Tell replies start with the two-digit axis field.
    pub tell_axis: bool,
    /// Bytes per second the port sends.
    pub output_rate: f64,
}

impl Default for LinkProfile {
    fn default() -> Self {
        LinkProfile {
            echo: true,
            eol: Eol::CrLf,
            prompts: PromptGranularity::Line,
            errors: ErrorText::CodeAndCommand,
            tell_axis: true,
            output_rate: DEFAULT_OUTPUT_RATE,
        }
    }
}

/// What the foreground interpreter of the port is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Activity {
    /// Taking a line.
    #[default]
    Typing,
    /// Running a line.
    Running,
    /// Running, paused by Space.
    Paused,
    /// Single stepping: one command per Space.
    Stepping,
}

/// What a byte typed at the port asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Keyed {
    Nothing,
    /// A line to run (the typed one, or the last one again on a bare CR).
    Line(Vec<u8>),
    /// A bare CR with no line retained: just the prompt.
    EmptyLine,
    /// The typed line was longer than [`MAX_LINE`].
    TooLong(Vec<u8>),
    Abort,
    Pause,
    Resume,
    StartStepping,
    StepOnce,
    EndStepping,
}

/// The port.
#[derive(Debug, Clone)]
pub struct Link {
    pub profile: LinkProfile,
    /// PC: the prompt byte, 0 for none.
    pub prompt: u8,
    pub radix: Radix,
    /// TE: the last interpreter error.
    pub last_error: Code,
    pub activity: Activity,
    line: Vec<u8>,
    overflow: bool,
    /// The last line, run again by a bare CR until any other key.
    retained: Option<Vec<u8>>,
    output: Vec<u8>,
    /// Bytes written but not yet sent at the port's rate.
    backlog: f64,
}

impl Link {
    pub fn new(profile: LinkProfile) -> Link {
        Link {
            profile,
            prompt: DEFAULT_PROMPT,
            radix: Radix::Decimal,
            last_error: Code::NONE,
            activity: Activity::Typing,
            line: Vec::new(),
            overflow: false,
            retained: None,
            output: Vec::new(),
            backlog: 0.0,
        }
    }

    /// RT: the port's own settings back to power-up (the profile, being
    /// the simulator's, stays).
    pub fn reset(&mut self) {
        self.prompt = DEFAULT_PROMPT;
        self.radix = Radix::Decimal;
        self.last_error = Code::NONE;
        self.retained = None;
    }

    pub fn running(&self) -> bool {
        self.activity != Activity::Typing
    }

    /// One byte from the host.
    pub fn key(&mut self, byte: u8) -> Keyed {
        match self.activity {
            Activity::Typing => self.type_byte(byte),
            // "it will ignore all alphanumeric keys" (Ch2).
            Activity::Running => match byte {
                ESCAPE => Keyed::Abort,
                SPACE => {
                    self.activity = Activity::Paused;
                    Keyed::Pause
                }
                STEP_KEY => {
                    self.activity = Activity::Stepping;
                    Keyed::StartStepping
                }
                _ => Keyed::Nothing,
            },
            Activity::Paused => match byte {
                ESCAPE => Keyed::Abort,
                SPACE => {
                    self.activity = Activity::Running;
                    Keyed::Resume
                }
                _ => Keyed::Nothing,
            },
            Activity::Stepping => match byte {
                ESCAPE => Keyed::Abort,
                SPACE => Keyed::StepOnce,
                b'\r' => {
                    self.activity = Activity::Running;
                    Keyed::EndStepping
                }
                _ => Keyed::Nothing,
            },
        }
    }

    fn type_byte(&mut self, byte: u8) -> Keyed {
        match byte {
            b'\r' => {
                self.newline();
                let line = std::mem::take(&mut self.line);
                if std::mem::take(&mut self.overflow) {
                    self.retained = Some(line.clone());
                    return Keyed::TooLong(line);
                }
                if line.is_empty() {
                    return match self.retained.clone() {
                        Some(last) => Keyed::Line(last),
                        None => Keyed::EmptyLine,
                    };
                }
                self.retained = Some(line.clone());
                Keyed::Line(line)
            }
            // LF is ignored (a host may end lines with CR LF).
            b'\n' => Keyed::Nothing,
            BACKSPACE | DELETE => {
                self.retained = None;
                if self.line.pop().is_some() && self.profile.echo {
                    self.write(b"\x08 \x08");
                }
                Keyed::Nothing
            }
            ESCAPE => {
                // The simulator's choice: Escape while typing drops the line.
                self.retained = None;
                self.line.clear();
                self.overflow = false;
                Keyed::Nothing
            }
            _ => {
                self.retained = None;
                if self.line.len() >= MAX_LINE {
                    self.overflow = true;
                    return Keyed::Nothing;
                }
                self.line.push(byte);
                if self.profile.echo {
                    self.write(&[byte]);
                }
                Keyed::Nothing
            }
        }
    }

    // ---- output ------------------------------------------------------

    pub fn write(&mut self, bytes: &[u8]) {
        self.output.extend_from_slice(bytes);
        self.backlog += bytes.len() as f64;
    }

    /// A line of output and its terminator.
    pub fn line(&mut self, text: &str) {
        self.write(text.as_bytes());
        self.newline();
    }

    pub fn newline(&mut self) {
        let eol = self.profile.eol.bytes();
        self.write(eol);
    }

    pub fn send_prompt(&mut self) {
        if self.prompt != 0 {
            let prompt = self.prompt;
            self.write(&[prompt]);
        }
    }

    /// `?code command` (or `?code`), the error kept for TE.
    pub fn error(&mut self, code: Code, command: &str) {
        self.last_error = code;
        let text = match self.profile.errors {
            ErrorText::CodeAndCommand if !command.is_empty() => format!("?{code} {command}"),
            _ => format!("?{code}"),
        };
        self.line(&text);
    }

    /// A Tell reply: `AA value`, or the bare value.
    pub fn tell(&mut self, field: u32, value: &str) {
        if self.profile.tell_axis {
            self.line(&format!("{field:02} {value}"));
        } else {
            self.line(value);
        }
    }

    pub fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.output)
    }

    /// Time passed: the port sends at its rate.
    pub fn drain(&mut self, seconds: f64) {
        self.backlog = (self.backlog - self.profile.output_rate * seconds).max(0.0);
    }

    /// More is waiting to be sent than the transmit buffer holds.
    pub fn congested(&self) -> bool {
        self.backlog > TRANSMIT_BUFFER
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn typed(link: &mut Link, text: &[u8]) -> Vec<Keyed> {
        text.iter()
            .map(|&b| link.key(b))
            .filter(|k| *k != Keyed::Nothing)
            .collect()
    }

    #[test]
    fn typing_echoes_and_cr_ends_the_line() {
        let mut link = Link::new(LinkProfile::default());
        assert_eq!(typed(&mut link, b"1TP\r"), [Keyed::Line(b"1TP".to_vec())]);
        assert_eq!(link.take_output(), b"1TP\r\n");
        // Ch2: a bare Enter repeats the line, until another key is pressed.
        assert_eq!(typed(&mut link, b"\r"), [Keyed::Line(b"1TP".to_vec())]);
        assert_eq!(typed(&mut link, b"x\x08\r"), [Keyed::EmptyLine]);
        assert_eq!(link.take_output(), b"\r\nx\x08 \x08\r\n");
    }

    #[test]
    fn backspace_edits_and_lf_is_ignored() {
        let mut link = Link::new(LinkProfile {
            echo: false,
            ..LinkProfile::default()
        });
        assert_eq!(
            typed(&mut link, b"1MA1x\x7f0\r\n"),
            [Keyed::Line(b"1MA10".to_vec())]
        );
        assert_eq!(link.take_output(), b"\r\n", "no echo but the terminator");
    }

    #[test]
    fn while_running_only_escape_space_and_the_step_key_count() {
        let mut link = Link::new(LinkProfile::default());
        link.activity = Activity::Running;
        assert_eq!(typed(&mut link, b"1TP\r"), []);
        assert_eq!(typed(&mut link, b" "), [Keyed::Pause]);
        assert_eq!(typed(&mut link, b"abc"), []);
        assert_eq!(typed(&mut link, b" "), [Keyed::Resume]);
        assert_eq!(typed(&mut link, b"\x14"), [Keyed::StartStepping]);
        assert_eq!(
            typed(&mut link, b" \r"),
            [Keyed::StepOnce, Keyed::EndStepping]
        );
        assert_eq!(typed(&mut link, b"\x1b"), [Keyed::Abort]);
        assert!(
            link.take_output().is_empty(),
            "nothing echoed while running"
        );
    }

    #[test]
    fn a_line_too_long_is_reported_not_cut() {
        let mut link = Link::new(LinkProfile::default());
        let long = vec![b'N'; MAX_LINE + 5];
        let _ = typed(&mut link, &long);
        assert!(matches!(link.key(b'\r'), Keyed::TooLong(l) if l.len() == MAX_LINE));
    }

    #[test]
    fn errors_and_tell_replies_follow_the_profile() {
        let mut link = Link::new(LinkProfile::default());
        link.error(Code::MACRO_MISSING, "MC10");
        link.tell(1, "1000");
        link.send_prompt();
        assert_eq!(link.take_output(), b"?-6 MC10\r\n01 1000\r\n>");
        assert_eq!(link.last_error, Code(-6));
        link.profile = LinkProfile {
            eol: Eol::Cr,
            errors: ErrorText::Code,
            tell_axis: false,
            ..LinkProfile::default()
        };
        link.prompt = 0;
        link.error(Code::UNRECOGNIZED, "1XX");
        link.tell(1, "1000");
        link.send_prompt();
        assert_eq!(link.take_output(), b"?1\r1000\r");
    }

    #[test]
    fn the_backlog_drains_at_the_output_rate() {
        let mut link = Link::new(LinkProfile::default());
        link.write(&[b'x'; 130]);
        assert!(link.congested());
        link.drain(0.01);
        assert!(!link.congested(), "115 bytes sent in 10 ms");
    }

    proptest! {
        #[test]
        fn no_bytes_panic_the_line_editor(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
            let mut link = Link::new(LinkProfile::default());
            for b in bytes {
                if let Keyed::Line(_) = link.key(b) {
                    link.activity = Activity::Running;
                }
                if b == b'!' {
                    link.activity = Activity::Typing;
                }
            }
        }
    }
}
