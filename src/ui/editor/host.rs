//! Running the text from the host, where its tool offers that (A-Script):
//! the lines programs are at marked `▶`, their variables shown as the host
//! holds them, Esc and the emergency stop end it ([`ConsoleHostRun`]).

use super::EditorPane;
use crate::protocol::program::PlaceState;
use crate::session::run_end::{RunEnding, StopOnFailure};
use crate::ui::host_run::{ConsoleHostRun, HostUpdate};
use crate::ui::keymap::{Action, Context};
use crate::ui::pane::{Notice, Outcome, PaneEvent, Request, View, key_label};
use crate::ui::theme::Role;

impl EditorPane {
    /// The lines (0-based) programs running from the host are at.
    pub(super) fn running_lines(&self) -> Vec<usize> {
        self.host.as_ref().map_or_else(Vec::new, |host| {
            host.places()
                .iter()
                .filter(|t| t.state == PlaceState::Running || t.state == PlaceState::Paused)
                .map(|t| t.line.saturating_sub(1))
                .collect()
        })
    }

    /// Start running the text from the host.
    pub(super) fn start_host_run(&mut self, view: &View) -> Outcome {
        if !self.tool.runs_from_host() {
            let offered: Vec<String> = super::language::registered_tools()
                .into_iter()
                .filter(|t| t.runs_from_host())
                .map(|t| format!("{} ({})", t.name(), t.controller()))
                .collect();
            self.message = Some(Notice::warning(format!(
                "running from the host is for {}; this text is {}: {} switches",
                offered.join(", "),
                self.tool.name(),
                key_label(view.keymap, Context::Editor, Action::EditorLanguage)
            )));
            return Outcome::redraw();
        }
        if self.host.is_some() {
            self.message = Some(Notice::warning(format!(
                "the text runs from the host already: {} stops it",
                key_label(view.keymap, Context::Editor, Action::Cancel)
            )));
            return Outcome::redraw();
        }
        if view.session.is_none() {
            self.message = Some(Notice::error(self.not_connected()));
            return Outcome::redraw();
        }
        if let Some(wrong) = self.other_family(view) {
            self.message = Some(wrong);
            return Outcome::redraw();
        }
        self.assemble();
        let start = match self.tool.host_run(&self.source_name(), &self.text(), None) {
            Some(Ok(start)) => start,
            Some(Err(problems)) => {
                self.next_error_from_top();
                let more = problems.len().saturating_sub(1);
                let first = problems.into_iter().next().unwrap_or_default();
                self.message = Some(Notice::error(if more > 0 {
                    format!("nothing was sent: {first} (and {more} more)")
                } else {
                    format!("nothing was sent: {first}")
                }));
                return Outcome::redraw();
            }
            None => return Outcome::Ignored,
        };
        // Lines the family wants confirmed (an SQPack frame that homes or
        // resets): said first, sent on the key's second press.
        if let Some(first) = start.confirm.first().filter(|_| !self.host_confirmed) {
            self.host_confirmed = true;
            let more = start.confirm.len() - 1;
            // The key first, so that it shows however long the rest.
            self.message = Some(Notice::warning(format!(
                "{} again sends it: {first}{}",
                key_label(view.keymap, Context::Editor, Action::EditorHostRun),
                if more > 0 {
                    format!(" (and {more} more line(s) to confirm)")
                } else {
                    String::new()
                }
            )));
            return Outcome::redraw();
        }
        self.host_confirmed = false;
        let (run, update) = ConsoleHostRun::start(start, &mut self.host_tag);
        self.host = Some(run);
        self.host_update(update)
    }

    /// What the host run said: the last line as the message; its requests.
    fn host_update(&mut self, update: HostUpdate) -> Outcome {
        if let Some((role, text)) = update.said.last() {
            self.message = Some(match role {
                Role::Error => Notice::error(text.clone()),
                Role::Warning => Notice::warning(text.clone()),
                _ => Notice::info(text.clone()),
            });
        }
        let mut requests = update.requests;
        if let Some(end) = update.ended {
            self.end_host_run();
            // A program that failed may have left an axis moving.
            if !end.ok {
                requests.push(Request::EndRun {
                    ending: RunEnding::Failed,
                    policy: StopOnFailure::Stop,
                });
            }
        }
        Outcome::Handled(requests)
    }

    /// Let the host run go; its variables stay shown until the
    /// controller's are read.
    pub(super) fn end_host_run(&mut self) -> Option<ConsoleHostRun> {
        let host = self.host.take()?;
        self.host_values = Some(host.variables().to_vec());
        Some(host)
    }

    /// Esc during a host run: nothing more of it is sent, and the axes
    /// are stopped.
    pub(super) fn cancel_host_run(&mut self) -> Option<Outcome> {
        let host = self.end_host_run()?;
        self.message = Some(Notice::warning(format!(
            "host run of {} stopped: nothing more of it is sent; stopping every axis",
            host.name(),
        )));
        Some(Outcome::request(Request::EndRun {
            ending: RunEnding::Cancelled,
            policy: StopOnFailure::Stop,
        }))
    }

    /// What the session did about the axes after a host run ended.
    pub(super) fn run_ended(&mut self, event: &PaneEvent, view: &View) -> Option<Outcome> {
        let PaneEvent::RunEnded(aftermath) = event else {
            return None;
        };
        let summary = aftermath.summary();
        self.message = Some(if aftermath.settled() {
            Notice::info(summary)
        } else {
            Notice::error(format!(
                "{summary}: check the axes ({} stops everything)",
                key_label(view.keymap, Context::Global, Action::EmergencyStop)
            ))
        });
        Some(Outcome::redraw())
    }

    /// The emergency stop ends the host run.
    pub(super) fn stopping_host_run(&mut self) -> bool {
        match self.end_host_run() {
            Some(host) => {
                self.message = Some(Notice::warning(format!(
                    "the emergency stop ended the host run of {}: nothing more of it is sent",
                    host.name()
                )));
                true
            }
            None => false,
        }
    }

    /// The answer or wake-up the host run waits for; `None` for the others.
    pub(super) fn host_event(&mut self, event: &PaneEvent) -> Option<Outcome> {
        let host = self.host.as_mut()?;
        let update = host.on_event(event, &mut self.host_tag)?;
        Some(self.host_update(update))
    }
}
