//! The simulator seen from its port on virtual time: lines typed as a
//! terminal would, time advanced a millisecond at a time, replies read
//! back. The numbers checked are the manual's own where it has them.

mod errors;
mod examples;
mod flow;
mod macros;
mod motion;
mod props;
mod reports;
mod servo;
mod stage;
mod tasks;
mod wire;

use std::time::Duration;

use super::{Mccl, SimConfig};
use crate::sim::SimulatedController;

pub const MS: Duration = Duration::from_millis(1);

/// A simulator and what it sent.
pub struct Session {
    pub sim: Mccl,
}

/// What a line brought back.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Exchange {
    /// The lines after the echo, without terminators or the prompt.
    pub lines: Vec<String>,
    /// Milliseconds it ran.
    pub ms: u64,
}

impl Session {
    pub fn new() -> Session {
        Session::with(SimConfig::pci())
    }

    pub fn with(config: SimConfig) -> Session {
        Session {
            sim: Mccl::new(config),
        }
    }

    /// Send bytes, return what came back at once.
    pub fn typed(&mut self, bytes: &str) -> String {
        self.sim.feed(bytes.as_bytes());
        String::from_utf8_lossy(&self.sim.take_output()).into_owned()
    }

    /// Send bytes and let time pass until the line they end has completed
    /// (a Tell waits for room in the port's transmit buffer): all that
    /// came back.
    pub fn typed_through(&mut self, bytes: &str) -> String {
        let mut out = self.typed(bytes);
        for _ in 0..1000 {
            if !self.sim.busy() {
                return out;
            }
            out.push_str(&self.advance_ms(1));
        }
        panic!("{bytes:?}: still running after a second: {out:?}");
    }

    pub fn advance_ms(&mut self, ms: u64) -> String {
        let mut out = Vec::new();
        for _ in 0..ms {
            self.sim.advance(MS);
            out.extend(self.sim.take_output());
        }
        String::from_utf8_lossy(&out).into_owned()
    }

    /// Type `line` + CR and let time pass until the line has completed (at
    /// most `limit_ms`): the reply lines.
    pub fn exchange(&mut self, line: &str, limit_ms: u64) -> Exchange {
        let mut out = self.typed(&format!("{line}\r"));
        let mut ms = 0;
        while self.sim.busy() {
            assert!(
                ms < limit_ms,
                "{line}: still running after {limit_ms} ms: {out:?}"
            );
            out.push_str(&self.advance_ms(1));
            ms += 1;
        }
        let Some(body) = out.strip_suffix('>') else {
            panic!("{line}: no prompt at the end of {out:?}");
        };
        let echo = format!("{line}\r\n");
        let Some(replies) = body.strip_prefix(&echo) else {
            panic!("{line}: no echo at the start of {out:?}");
        };
        let lines = replies
            .split_terminator("\r\n")
            .map(str::to_string)
            .collect();
        Exchange { lines, ms }
    }

    /// The reply lines of `line`, run for at most a minute.
    pub fn line(&mut self, line: &str) -> Vec<String> {
        self.exchange(line, 60_000).lines
    }

    /// Lines that must answer nothing but the prompt.
    pub fn quiet(&mut self, lines: &[&str]) {
        for line in lines {
            assert_eq!(self.line(line), Vec::<String>::new(), "{line}");
        }
    }

    /// The one reply line of `line`.
    pub fn one(&mut self, line: &str) -> String {
        let lines = self.line(line);
        assert_eq!(lines.len(), 1, "{line}: {lines:?}");
        lines[0].clone()
    }

    /// The value of a Tell reply `AA value`.
    pub fn tell(&mut self, line: &str) -> f64 {
        let reply = self.one(line);
        let value = reply.split_whitespace().nth(1).unwrap_or_default();
        value
            .parse()
            .unwrap_or_else(|_| panic!("{line}: no value in {reply:?}"))
    }

    /// TS of axis n as a number.
    pub fn status(&mut self, axis: u8) -> u32 {
        self.tell(&format!("{axis}TS")) as u32
    }

    /// The error code a line reports (`?code ...`).
    pub fn error(&mut self, line: &str) -> i32 {
        let reply = self.one(line);
        let code = reply
            .strip_prefix('?')
            .and_then(|r| r.split_whitespace().next())
            .unwrap_or_else(|| panic!("{line}: no error in {reply:?}"));
        code.parse().unwrap_or_else(|_| panic!("{line}: {reply:?}"))
    }

    /// The prompt that ends a line which completed while time passed.
    pub fn take_prompt(&mut self) {
        let out = String::from_utf8_lossy(&self.sim.take_output()).into_owned();
        assert!(out.is_empty() || out.ends_with('>'), "{out:?}");
    }

    /// A setting driven from outside.
    pub fn drive(&mut self, setting: &str) {
        if let Err(e) = self.sim.drive_input(setting) {
            panic!("{setting}: {e}");
        }
    }
}
