//! How a controller's ASCII interface behaves on the wire, as data: the
//! manual states some of it (echo on, CR executes, prompt `>`, Escape
//! aborts, Space pauses: Ch1, Ch2, Ch13 PC) and leaves the rest open (line
//! terminators, whether the prompt follows each line or each command:
//! digest §3.2). A [`LinkProfile`] holds both, with defaults from the
//! manual and the digest, settable field by field or learned from the
//! connect probe the digest recommends ([`LinkProfile::learn`]).
//!
//! [`LinkState`] follows what lines change on the interface as they run:
//! `DM`/`HM` (the number base both ways), `PC` (the prompt), `RT` (reset).

use std::time::Duration;

use super::line::{Line, NumberBase};
use crate::protocol::console::ProbeError;

/// Whether the controller echoes what it is sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Echo {
    /// Every character comes back as typed (Ch2: "each character typed at
    /// the keyboard should be echoed to your display"), the line's CR as a
    /// line end.
    Line,
    /// Nothing comes back but replies and the prompt (`EF`, factory use).
    Off,
}

/// When the prompt comes (Ch13 PC: "when the controller completes execution
/// of a command issued to that port" reads either way, digest §3.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PromptPer {
    /// Once, when the whole line has run [I: the digest's Ch4 transcript
    /// shows no prompt between the replies of one macro call].
    Line,
    /// After every command of a compound line.
    Command,
}

/// How the controller ends its lines (not stated, digest §3.2). The
/// framer takes CR, LF and CRLF alike whichever it is; the probe reports
/// what it saw.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LineEnd {
    Cr,
    Lf,
    CrLf,
}

/// What the console knows of the interface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LinkProfile {
    pub echo: Echo,
    /// What ends a line sent: CR (Ch1: "followed by a carriage return").
    pub send_end: u8,
    /// How reply lines end, if learned.
    pub reply_end: Option<LineEnd>,
    /// The prompt character (`PC`, default `>` = 62); `None` after `PC0`.
    pub prompt: Option<u8>,
    pub prompt_per: PromptPer,
    /// How long the line must stay quiet after a prompt before the line
    /// counts as done (digest §3.3 step 3: 50–100 ms), for a device layer
    /// that can wait for quiet.
    pub quiet_guard: Duration,
    /// The longest reply line kept (VE, ID, TM listings are long; the
    /// manual gives no limit).
    pub max_reply_line: usize,
    /// Command lines longer than this draw a warning: the controller has
    /// an error 4 "Command string too long" but no stated limit.
    pub max_command_line: usize,
    /// Aborts the line running (Ch2 "Escape").
    pub abort: u8,
    /// Pauses the line running, and resumes it when sent again (Ch2
    /// "Space bar").
    pub pause: u8,
}

/// The prompt after power-up and reset (Ch13 PC: "The default prompt
/// character is '>' (ASCII 62 decimal)").
pub const DEFAULT_PROMPT: u8 = b'>';
pub const ESCAPE: u8 = 0x1B;
pub const SPACE: u8 = b' ';
pub const CR: u8 = b'\r';

impl LinkProfile {
    /// What the manual states, and the digest's recommendations where it
    /// is silent.
    pub const MANUAL: LinkProfile = LinkProfile {
        echo: Echo::Line,
        send_end: CR,
        reply_end: None,
        prompt: Some(DEFAULT_PROMPT),
        prompt_per: PromptPer::Line,
        quiet_guard: Duration::from_millis(50),
        max_reply_line: 1024,
        max_command_line: 255,
        abort: ESCAPE,
        pause: SPACE,
    };

    pub const fn with_echo(mut self, echo: Echo) -> Self {
        self.echo = echo;
        self
    }

    pub const fn with_prompt(mut self, prompt: Option<u8>) -> Self {
        self.prompt = prompt;
        self
    }

    pub const fn with_prompt_per(mut self, per: PromptPer) -> Self {
        self.prompt_per = per;
        self
    }

    pub const fn with_quiet_guard(mut self, guard: Duration) -> Self {
        self.quiet_guard = guard;
        self
    }

    /// What the connect probe shows (digest §3.3 step 5): `single` is what
    /// came back for `NO` + CR, `triple` for `NO,NO,NO` + CR, each up to
    /// the line falling quiet. The echo is there if the answer starts with
    /// the line sent; the prompt is the last byte of the answer that is not
    /// a line end; the prompt comes per command if `triple` holds three of
    /// them.
    pub fn learn(single: &[u8], triple: &[u8]) -> Result<LinkProfile, ProbeError> {
        let shown = |b: &[u8]| String::from_utf8_lossy(b).escape_debug().to_string();
        let prompt_of = |answer: &[u8]| -> Option<u8> {
            answer
                .iter()
                .rev()
                .copied()
                .find(|&b| b != b'\r' && b != b'\n')
                .filter(|b| !b.is_ascii_alphanumeric())
        };
        let prompt = prompt_of(single).ok_or_else(|| ProbeError::Unexpected {
            request: "NO",
            answered: format!(
                "was answered `{}`: no prompt character at its end",
                shown(single)
            ),
        })?;
        if prompt_of(triple) != Some(prompt) {
            return Err(ProbeError::Unexpected {
                request: "NO,NO,NO",
                answered: format!(
                    "was answered `{}`: it does not end with the prompt `{}` of `NO`",
                    shown(triple),
                    char::from(prompt)
                ),
            });
        }
        let echo = if single.starts_with(b"NO") {
            Echo::Line
        } else {
            Echo::Off
        };
        let prompts = triple.iter().filter(|&&b| b == prompt).count();
        let prompt_per = match prompts {
            1 => PromptPer::Line,
            3 => PromptPer::Command,
            n => {
                return Err(ProbeError::Unexpected {
                    request: "NO,NO,NO",
                    answered: format!(
                        "brought {n} prompts: neither one per line nor one per command"
                    ),
                });
            }
        };
        let reply_end = if single.windows(2).any(|w| w == b"\r\n") {
            Some(LineEnd::CrLf)
        } else if single.contains(&b'\r') {
            Some(LineEnd::Cr)
        } else if single.contains(&b'\n') {
            Some(LineEnd::Lf)
        } else {
            None
        };
        Ok(LinkProfile {
            echo,
            reply_end,
            prompt: Some(prompt),
            prompt_per,
            ..LinkProfile::MANUAL
        })
    }
}

impl Default for LinkProfile {
    fn default() -> Self {
        LinkProfile::MANUAL
    }
}

/// What the interface is set to as lines run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LinkState {
    pub base: NumberBase,
    pub prompt: Option<u8>,
    pub echo: Echo,
}

impl LinkState {
    /// After power-up or reset: decimal, the profile's prompt and echo.
    pub fn new(profile: &LinkProfile) -> LinkState {
        LinkState {
            base: NumberBase::Decimal,
            prompt: profile.prompt,
            echo: profile.echo,
        }
    }

    /// The state after `line` ran without error. `DM`/`HM` switch the base
    /// for the lines after (the parameters of the line itself are read in
    /// the base it started in: "must be executed by the controller before
    /// commands can be issued with … formatted parameters", Ch13); `PCn`
    /// sets the prompt; `EN`/`EF` turn the echo on and off (their
    /// parameter is not documented, Ch13); a whole-controller `RT`
    /// restores the base and the prompt [I: "default conditions … will be
    /// restored"; the echo is the port's, as the simulator keeps it]. A
    /// macro definition runs nothing.
    pub fn after(&mut self, line: &Line, profile: &LinkProfile) {
        if line.defines_macro() || line.is_task() {
            return;
        }
        for (index, command) in line.commands.iter().enumerate() {
            match command.mnemonic() {
                "DM" => self.base = NumberBase::Decimal,
                "HM" => self.base = NumberBase::Hex,
                "PC" => {
                    if let Some(n) = command.number() {
                        self.prompt = u8::try_from(n as i64).ok().filter(|&c| c != 0);
                    }
                }
                "EN" => self.echo = Echo::Line,
                "EF" => self.echo = Echo::Off,
                "RT" if line.axis_of(index).number().is_none_or(|a| a == 0) => {
                    *self = LinkState {
                        echo: self.echo,
                        ..LinkState::new(profile)
                    };
                }
                _ => {}
            }
        }
    }

    /// The prompt that ends `line`'s answer: the one in force once it has
    /// run (`PC35` is answered with `#`, `PC0` with none).
    pub fn prompt_after(&self, line: &Line, profile: &LinkProfile) -> Option<u8> {
        let mut after = *self;
        after.after(line, profile);
        after.prompt
    }

    /// The base the replies of command `index` of `line` come in: the
    /// line's start base, switched by a `DM`/`HM` before it on the line
    /// [? the manual shows them on lines of their own].
    pub fn output_base(&self, line: &Line, index: usize) -> NumberBase {
        line.commands[..index.min(line.commands.len())]
            .iter()
            .rev()
            .find_map(|c| match c.mnemonic() {
                "DM" => Some(NumberBase::Decimal),
                "HM" => Some(NumberBase::Hex),
                _ => None,
            })
            .unwrap_or(self.base)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::mccl::line::parse_line;

    fn line(text: &str) -> Line {
        parse_line(text, NumberBase::Decimal).expect(text)
    }

    #[test]
    fn the_manual_profile_echoes_and_prompts_per_line() {
        let p = LinkProfile::MANUAL;
        assert_eq!(p.echo, Echo::Line);
        assert_eq!(p.prompt, Some(b'>'));
        assert_eq!(p.send_end, b'\r');
        assert_eq!((p.abort, p.pause), (0x1B, b' '));
        let q = p
            .with_prompt(Some(b'#'))
            .with_prompt_per(PromptPer::Command);
        assert_eq!((q.prompt, q.prompt_per), (Some(b'#'), PromptPer::Command));
    }

    #[test]
    fn the_probe_tells_echo_prompt_and_line_ends() {
        let p = LinkProfile::learn(b"NO\r\n>", b"NO,NO,NO\r\n>").expect("learned");
        assert_eq!(p.echo, Echo::Line);
        assert_eq!(p.prompt, Some(b'>'));
        assert_eq!(p.prompt_per, PromptPer::Line);
        assert_eq!(p.reply_end, Some(LineEnd::CrLf));
        let p = LinkProfile::learn(b"\r#", b"#\r#\r#").expect("learned");
        assert_eq!(p.echo, Echo::Off);
        assert_eq!(p.prompt, Some(b'#'));
        assert_eq!(p.prompt_per, PromptPer::Command);
        assert_eq!(p.reply_end, Some(LineEnd::Cr));
        assert!(LinkProfile::learn(b"", b"").is_err());
        assert!(LinkProfile::learn(b"NO\r\n>", b"NO,NO,NO\r\n>>").is_err());
        assert!(LinkProfile::learn(b"NO\r\n>", b"NO,NO,NO\r\n").is_err());
    }

    #[test]
    fn dm_hm_pc_and_reset_change_the_state_for_later_lines() {
        let profile = LinkProfile::MANUAL;
        let mut state = LinkState::new(&profile);
        let hm = line("HM,1TS");
        // The replies after HM on its own line come in hex.
        assert_eq!(state.output_base(&hm, 0), NumberBase::Decimal);
        assert_eq!(state.output_base(&hm, 1), NumberBase::Hex);
        state.after(&hm, &profile);
        assert_eq!(state.base, NumberBase::Hex);
        state.after(&line("PC35"), &profile);
        assert_eq!(state.prompt, Some(b'#'));
        state.after(&line("PC0"), &profile);
        assert_eq!(state.prompt, None);
        state.after(&line("EF1"), &profile);
        assert_eq!(state.echo, Echo::Off);
        // An axis reset keeps the interface; a controller reset does not.
        state.after(&line("1RT"), &profile);
        assert_eq!(state.base, NumberBase::Hex);
        state.after(&line("RT"), &profile);
        assert_eq!(
            state,
            LinkState {
                echo: Echo::Off,
                ..LinkState::new(&profile)
            },
            "the echo is the port's"
        );
        state.after(&line("EN1"), &profile);
        assert_eq!(state, LinkState::new(&profile));
        // A macro definition stores HM, it does not run it.
        state.after(&line("MD5,HM"), &profile);
        assert_eq!(state.base, NumberBase::Decimal);
        state.after(&line("HM"), &profile);
        state.after(&line("DM"), &profile);
        assert_eq!(state.base, NumberBase::Decimal);
    }
}
