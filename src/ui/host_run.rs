//! A program run from the host inside the console (`:run-ascript FILE` in
//! the command pane, the run-from-host key in the editor): the family's
//! [`HostRun`] state machine driven through a pane's requests. Each line it
//! sends is a [`Request::Send`], each wait a [`Request::WakeAfter`], under
//! a tag of the pane's; what happens comes back as lines to show. Dropping
//! it ends the run: the emergency stop (which drops every line still
//! waiting) and Esc do just that, so nothing more of the program is sent
//! after them.

use tokio::time::Instant;

use super::pane::{PaneEvent, Request};
use super::theme::Role;
use crate::protocol::program::{
    HostEnd, HostRun, HostStart, HostStep, PlaceState, RunningPlace, Tone,
};
use crate::session::transfer::answer_of;

/// What a step of the run came to, for the pane.
#[derive(Debug, Default)]
pub struct HostUpdate {
    /// Lines to show, with their colour.
    pub said: Vec<(Role, String)>,
    pub requests: Vec<Request>,
    /// The run is over: how it ended.
    pub ended: Option<HostEnd>,
}

/// A host run under way in a pane.
#[derive(Debug)]
pub struct ConsoleHostRun {
    run: Box<dyn HostRun>,
    name: String,
    /// When it began: the run's clock.
    began: Instant,
    /// The tag of the answer or wake-up it waits for.
    awaiting: Option<u64>,
}

impl ConsoleHostRun {
    /// Start the run `start`. `last_tag` is the pane's tag counter: each
    /// request takes the next.
    pub fn start(start: HostStart, last_tag: &mut u64) -> (ConsoleHostRun, HostUpdate) {
        let mut run = ConsoleHostRun {
            run: start.run,
            name: start.name,
            began: Instant::now(),
            awaiting: None,
        };
        let step = run.run.start(std::time::Duration::ZERO);
        let update = run.carry_out(step, last_tag);
        (run, update)
    }

    /// The file run.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Where each program of the file is.
    pub fn places(&self) -> Vec<RunningPlace> {
        self.run.places()
    }

    /// The variables as the host holds them.
    pub fn variables(&self) -> &[i32] {
        self.run.variables()
    }

    /// Whether `tag` is the answer or wake-up the run waits for.
    pub fn awaits(&self, tag: u64) -> bool {
        self.awaiting == Some(tag)
    }

    /// The answer or wake-up it waits for; `None` for any other event.
    pub fn on_event(&mut self, event: &PaneEvent, last_tag: &mut u64) -> Option<HostUpdate> {
        let now = self.began.elapsed();
        let step = match event {
            PaneEvent::Reply {
                tag: got,
                line,
                result,
            } if self.awaits(*got) => self.run.on_answer(&answer_of(line, result), now),
            PaneEvent::Wake { tag: got } if self.awaits(*got) => self.run.on_wake(now),
            _ => return None,
        };
        self.awaiting = None;
        Some(self.carry_out(step, last_tag))
    }

    /// "running FILE from the host: PRG 1 line 7, PRG 3 line 20", for a
    /// status line.
    pub fn describe(&self) -> String {
        let at: Vec<String> = self
            .run
            .places()
            .iter()
            .filter(|t| t.state == PlaceState::Running || t.state == PlaceState::Paused)
            .map(|t| {
                let paused = if t.state == PlaceState::Paused {
                    " (paused)"
                } else {
                    ""
                };
                format!("{} line {}{paused}", self.run.place_name(t.program), t.line)
            })
            .collect();
        format!("running {} from the host: {}", self.name, at.join(", "))
    }

    fn carry_out(&mut self, step: HostStep, last_tag: &mut u64) -> HostUpdate {
        let mut update = HostUpdate {
            said: self
                .run
                .take_news()
                .into_iter()
                .map(|news| (role_of(news.tone), format!("host: {}", news.text)))
                .collect(),
            ..HostUpdate::default()
        };
        match step {
            HostStep::Send(line) => {
                *last_tag += 1;
                let tag = *last_tag;
                self.awaiting = Some(tag);
                update.requests.push(Request::Send {
                    lines: vec![line],
                    tag,
                });
            }
            HostStep::Wake(after) => {
                *last_tag += 1;
                let tag = *last_tag;
                self.awaiting = Some(tag);
                update.requests.push(Request::WakeAfter { after, tag });
            }
            HostStep::Finished(end) => {
                let role = if end.ok { Role::Ok } else { Role::Error };
                update
                    .said
                    .push((role, format!("host run of {}: {end}", self.name)));
                update.ended = Some(end);
            }
        }
        update
    }
}

/// How news of a run is coloured.
fn role_of(tone: Tone) -> Role {
    match tone {
        Tone::Headline => Role::Accent,
        Tone::Plain => Role::Normal,
        Tone::Minor => Role::Muted,
        Tone::Warning => Role::Warning,
        Tone::Error => Role::Error,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::cmd4cr::host::start_host_run;
    use crate::protocol::console::ReplyValue;
    use crate::session::LineResult;
    use std::time::Duration;

    fn ok(line: &str) -> PaneEvent {
        PaneEvent::Reply {
            tag: 0,
            line: line.into(),
            result: Ok(LineResult {
                line: line.into(),
                request: Vec::new(),
                reply: Vec::new(),
                status: None,
                value: ReplyValue::Number(0),
                elapsed: Duration::ZERO,
                attempts: 1,
            }),
        }
    }

    fn with_tag(event: PaneEvent, tag: u64) -> PaneEvent {
        match event {
            PaneEvent::Reply { line, result, .. } => PaneEvent::Reply { tag, line, result },
            other => other,
        }
    }

    #[test]
    fn requests_carry_fresh_tags_and_only_their_answers_move_the_run_on() {
        let program =
            start_host_run("p.asc", "PRG 0\n    DO1=1\n    DELAY=5\nEND\n", None).expect("ok");
        let mut tag = 10;
        let (mut run, update) = ConsoleHostRun::start(program, &mut tag);
        assert_eq!(
            update.requests,
            [Request::Send {
                lines: vec!["DO1=1".into()],
                tag: 11
            }]
        );
        assert_eq!(
            update.said,
            [(Role::Accent, "host: PRG 0 started from the host".into())]
        );
        assert!(
            run.describe().ends_with("from the host: PRG 0 line 2"),
            "{}",
            run.describe()
        );
        // Someone else's answer.
        assert!(run.on_event(&with_tag(ok("DO1=1"), 3), &mut tag).is_none());
        let update = run
            .on_event(&with_tag(ok("DO1=1"), 11), &mut tag)
            .expect("ours");
        assert_eq!(
            update.said,
            [(Role::Normal, "host: PRG 0 line 2: DO1=1 → 0".into())]
        );
        assert!(matches!(
            update.requests.as_slice(),
            [Request::WakeAfter { tag: 12, .. }]
        ));
        assert!(run.awaits(12) && !run.awaits(11));
    }
}
