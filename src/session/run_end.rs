//! What becomes of the axes when a run ends badly: a batch file (`axterm
//! run`, the console's `:run`) or an A-Script program run from the host
//! (`axterm run-ascript`, `:run-ascript`, the editor's host run) that
//! fails, is cancelled (Ctrl-C, Esc) or loses its link while an axis
//! moves. A run that stops half-way must not leave a motor running: by
//! default every front end ends such a run with [`Session::end_run`], which
//! sends the family's stop-everything sequence (the one of the console's
//! emergency-stop key, [`Session::emergency_stop_lines`], at emergency-stop
//! priority) and reports what came back for each stop line. Those who want
//! the axes left as they are say [`NO_STOP_FLAG`] ([`StopOnFailure::Leave`]).
//!
//! A lost link: the device task reopens it by itself with backoff (see
//! [`crate::device`]), failing every request meanwhile. So the stop waits
//! for the link to come back, at most [`LINK_RETURN_WAIT`] from the end of
//! the run, and is sent then; a stop line that could not be sent is
//! reported as not sent, never as done.
//!
//! This is the one place this is decided and done; the front ends only
//! say how their run ended and print [`RunAftermath::report`].

use std::fmt;
use std::future::Future;
use std::time::Duration;

use tokio::time::Instant;

use super::{LineResult, Session, SessionError};
use crate::device::{DeviceError, LinkState};
use crate::script::LEAVE_MOVING;

/// The option that leaves the axes as they are after a run that did not
/// complete (`axterm run`, `axterm run-ascript`, `:run`, `:run-ascript`).
pub const NO_STOP_FLAG: &str = "--no-stop-on-failure";

/// How long the stop after a run waits for a lost link to come back: the
/// device task tries to reopen it after 0.1, 0.2, 0.4 … s (at most 5 s
/// apart), so a cable plugged back or a bridge restarted within a few
/// seconds gets the stop; longer than that, the run's front end would be
/// holding on to a link nobody may bring back.
pub const LINK_RETURN_WAIT: Duration = Duration::from_secs(10);

/// How a run ended, as far as the axes go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunEnding {
    /// Every step done (every program reached its END).
    Completed,
    /// A step failed: a line refused or unanswered, an `:expect` that did
    /// not match, a `:wait-until` that timed out, a program that stopped in
    /// the error state, the link lost.
    Failed,
    /// The user ended it: Ctrl-C, Esc.
    Cancelled,
}

impl RunEnding {
    /// `Completed` when `ok`, else `Failed`.
    pub fn from_success(ok: bool) -> RunEnding {
        if ok {
            RunEnding::Completed
        } else {
            RunEnding::Failed
        }
    }

    fn says(self) -> &'static str {
        match self {
            RunEnding::Completed => "the run completed",
            RunEnding::Failed => "the run failed",
            RunEnding::Cancelled => "the run was cancelled",
        }
    }
}

/// Whether a run that does not complete stops the axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StopOnFailure {
    /// Send the stop-everything sequence (the default).
    #[default]
    Stop,
    /// Leave the axes as they are ([`NO_STOP_FLAG`]).
    Leave,
}

impl StopOnFailure {
    /// The policy of a front end given [`NO_STOP_FLAG`] (`true`) or not.
    pub fn from_flag(no_stop_on_failure: bool) -> StopOnFailure {
        if no_stop_on_failure {
            StopOnFailure::Leave
        } else {
            StopOnFailure::Stop
        }
    }

    /// Whether a run that ended so stops the axes.
    pub fn stops_after(self, ending: RunEnding) -> bool {
        self == StopOnFailure::Stop && ending != RunEnding::Completed
    }
}

/// What a run that completed checks of the axes at its end: a replayed
/// recording or a run file whose last move is still going must not end
/// "completed" with an axis turning behind it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AtTheEnd {
    /// Nothing: the run moved nothing, or its language has no way to say
    /// it means to leave an axis moving.
    #[default]
    Nothing,
    /// Whether an axis still moves: if one does, the run says so and ends
    /// as a failed one (the stop sequence, unless `--no-stop-on-failure`).
    StopIfMoving,
    /// Whether an axis still moves: if one does, the run says so, and that
    /// the file means it ([`LEAVE_MOVING`]).
    SayIfMoving,
}

impl AtTheEnd {
    /// For a file of `steps`: whether it may move an axis (a line that
    /// acts) and whether it says it means to leave one moving.
    pub fn of_script(steps: &[crate::script::CheckedStep]) -> AtTheEnd {
        use crate::protocol::console::Effect;
        use crate::script::{Action, leaves_moving};
        // The tool directives move the axis (the wiring check's jogs, a
        // step, a sweep's speeds).
        let acts = steps.iter().any(|s| {
            (matches!(s.step.action, Action::Line(_))
                && s.line.as_ref().is_some_and(|l| l.effect == Effect::Acts))
                || matches!(
                    s.step.action,
                    Action::Wiring(_) | Action::TuneStep(_) | Action::TuneStallguard(_)
                )
        });
        if !acts {
            AtTheEnd::Nothing
        } else if leaves_moving(steps.iter().map(|s| &s.step.action)) {
            AtTheEnd::SayIfMoving
        } else {
            AtTheEnd::StopIfMoving
        }
    }
}

/// What the check at the end of a run that completed found
/// ([`Session::check_run_end`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EndCheck {
    /// Completed, or failed for an axis left moving that the file did not
    /// mean to leave so.
    pub ending: RunEnding,
    /// What to tell the user, if anything: the axes still moving, or that
    /// they could not be read.
    pub said: Option<String>,
    /// Whether `said` is a problem (an axis left moving unmeant, or the
    /// axes unreadable) rather than what the file meant.
    pub alarming: bool,
}

impl EndCheck {
    /// Nothing checked or nothing found: the run stays completed.
    pub fn completed() -> EndCheck {
        EndCheck {
            ending: RunEnding::Completed,
            said: None,
            alarming: false,
        }
    }

    /// What `moving` (the axes that still move, or why they could not be
    /// read) comes to under `check`. Axes that cannot be read leave the
    /// run completed, said so: nothing is known to move.
    pub fn judge(check: AtTheEnd, moving: Result<Vec<&str>, String>) -> EndCheck {
        let moving = match moving {
            _ if check == AtTheEnd::Nothing => return EndCheck::completed(),
            Ok(moving) if moving.is_empty() => return EndCheck::completed(),
            Ok(moving) => moving,
            Err(why) => {
                return EndCheck {
                    ending: RunEnding::Completed,
                    said: Some(format!(
                        "cannot tell whether an axis still moves at the end of the run: {why}"
                    )),
                    alarming: true,
                };
            }
        };
        let axes = moving.join(", ");
        let (noun, verb) = if moving.len() == 1 {
            ("axis", "moves")
        } else {
            ("axes", "move")
        };
        if check == AtTheEnd::SayIfMoving {
            EndCheck {
                ending: RunEnding::Completed,
                said: Some(format!(
                    "the run ended and {noun} {axes} still {verb}, as the file means it to \
                     ({LEAVE_MOVING})"
                )),
                alarming: false,
            }
        } else {
            EndCheck {
                ending: RunEnding::Failed,
                said: Some(format!(
                    "the run ended and {noun} {axes} still {verb}; the file does not say \
                     {LEAVE_MOVING}, so the run ends as a failed one"
                )),
                alarming: true,
            }
        }
    }
}

/// The link when the stop after a run was due.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LinkAtStop {
    /// Up: the stop went at once.
    Up,
    /// Down when the run ended, back after `waited`: the stop went then.
    CameBack { waited: Duration },
    /// Down for all of `waited` (or closed): the stop lines say they were
    /// not sent.
    StayedDown { waited: Duration, reason: String },
}

/// The stop sent after a run that did not complete.
#[derive(Debug, Clone)]
pub struct RunStop {
    pub ending: RunEnding,
    /// What came back for each line of the stop sequence, in order (of the
    /// last attempt, when the link was lost in between).
    pub lines: Vec<Result<LineResult, SessionError>>,
    pub link: LinkAtStop,
}

impl RunStop {
    /// Every stop line answered with success.
    pub fn confirmed(&self) -> bool {
        !self.lines.is_empty()
            && self
                .lines
                .iter()
                .all(|l| l.as_ref().is_ok_and(|r| !r.reply.is_empty()))
    }

    /// Stop lines that went out but that the module never answers (a
    /// SIXpack 2 acknowledges no command, §7): sent, and no more is known.
    pub fn unacknowledged(&self) -> usize {
        self.lines
            .iter()
            .filter(|l| l.as_ref().is_ok_and(|r| r.reply.is_empty()))
            .count()
    }
}

/// What was done about the axes at the end of a run.
#[derive(Debug, Clone)]
pub enum RunAftermath {
    /// The run completed: nothing to do.
    Completed,
    /// The run did not complete and the axes were left as they are
    /// ([`StopOnFailure::Leave`]).
    Left(RunEnding),
    /// The run did not complete: the stop sequence was sent.
    Stopped(RunStop),
}

impl RunAftermath {
    /// What a run that ended so comes to under `policy`: nothing after a
    /// completed run, the axes left when the policy says so, else the stop
    /// that `stop` sends. Every front end's end of a run goes through
    /// here ([`Session::end_run`], the console's controllers).
    pub async fn of<F>(
        ending: RunEnding,
        policy: StopOnFailure,
        stop: impl FnOnce() -> F,
    ) -> RunAftermath
    where
        F: Future<Output = RunStop>,
    {
        if ending == RunEnding::Completed {
            RunAftermath::Completed
        } else if !policy.stops_after(ending) {
            RunAftermath::Left(ending)
        } else {
            RunAftermath::Stopped(stop().await)
        }
    }

    /// Whether nothing is left in doubt: the run completed, or every stop
    /// line answered with success. (Leaving the axes by choice is not.)
    pub fn settled(&self) -> bool {
        match self {
            RunAftermath::Completed => true,
            RunAftermath::Left(_) => false,
            RunAftermath::Stopped(stop) => stop.confirmed(),
        }
    }

    /// What to tell the user, a line each: what was done and why, each
    /// stop line with its answer (or why it has none), and whether the
    /// stop is confirmed. Empty for a completed run.
    pub fn report(&self) -> Vec<String> {
        match self {
            RunAftermath::Completed => Vec::new(),
            RunAftermath::Left(ending) => vec![format!(
                "{}: the axes were left as they are ({NO_STOP_FLAG})",
                ending.says()
            )],
            RunAftermath::Stopped(stop) => {
                let mut lines = vec![match &stop.link {
                    LinkAtStop::Up => format!("{}: stopping every axis:", stop.ending.says()),
                    LinkAtStop::CameBack { waited } => format!(
                        "{}: the link was down; it came back after {}, stopping every axis:",
                        stop.ending.says(),
                        show(*waited)
                    ),
                    LinkAtStop::StayedDown { waited, reason } => format!(
                        "{}: the link is down ({reason}) and did not come back within {}: \
                         the stop could not be sent; the axes may still move:",
                        stop.ending.says(),
                        show(*waited)
                    ),
                }];
                lines.extend(stop.lines.iter().map(|l| format!("  {}", StopLine(l))));
                let failed = stop.lines.iter().filter(|l| l.is_err()).count();
                let unacknowledged = stop.unacknowledged();
                lines.push(if stop.confirmed() {
                    "stop confirmed: every stop line answered ok".to_string()
                } else if failed == 0 && unacknowledged > 0 {
                    format!(
                        "stop sent: every stop line went out, {unacknowledged} of them never \
                         acknowledged by the module: check the axes"
                    )
                } else if stop.lines.is_empty() {
                    "STOP NOT SENT: the family has no stop lines; check the axes".to_string()
                } else {
                    format!(
                        "STOP NOT CONFIRMED: {failed} of {} stop lines failed; check the axes",
                        stop.lines.len()
                    )
                });
                lines
            }
        }
    }

    /// One line for a status bar or a message: what was done.
    pub fn summary(&self) -> String {
        match self {
            RunAftermath::Completed => RunEnding::Completed.says().to_string(),
            RunAftermath::Left(ending) => {
                format!("{}: axes left as they are ({NO_STOP_FLAG})", ending.says())
            }
            RunAftermath::Stopped(stop) => {
                let failed = stop.lines.iter().filter(|l| l.is_err()).count();
                if stop.confirmed() {
                    format!(
                        "{}: STOP sent, {} lines ok",
                        stop.ending.says(),
                        stop.lines.len()
                    )
                } else if failed == 0 && !stop.lines.is_empty() {
                    format!(
                        "{}: STOP sent, {} lines out, {} unacknowledged",
                        stop.ending.says(),
                        stop.lines.len(),
                        stop.unacknowledged()
                    )
                } else {
                    format!(
                        "{}: STOP NOT CONFIRMED ({failed} of {} lines failed)",
                        stop.ending.says(),
                        stop.lines.len()
                    )
                }
            }
        }
    }
}

/// One stop line and what came of it: its answer, or whether it went out
/// at all (a line never sent must not read as one unanswered).
struct StopLine<'a>(&'a Result<LineResult, SessionError>);

impl fmt::Display for StopLine<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Ok(result) => write!(f, "{} → {}", result.line, result.value),
            Err(SessionError::Device { line, error, .. }) => match error {
                DeviceError::Disconnected(_)
                | DeviceError::Closed
                | DeviceError::NeverQuiet { .. } => {
                    write!(f, "{line}: NOT SENT ({error})")
                }
                DeviceError::LinkLost(_) => {
                    write!(
                        f,
                        "{line}: sent, the link was lost before the answer ({error})"
                    )
                }
                DeviceError::Timeout { .. } | DeviceError::AbortUnanswered { .. } => {
                    write!(f, "{line}: sent, no answer ({error})")
                }
                DeviceError::Garbled { .. }
                | DeviceError::Ambiguous { .. }
                | DeviceError::CutShort { .. } => {
                    write!(f, "{line}: sent, no readable answer ({error})")
                }
            },
            Err(SessionError::Refused { line, message }) => {
                write!(f, "{line}: NOT SENT ({message})")
            }
            Err(error @ SessionError::Reply { .. }) => write!(f, "{error}"),
        }
    }
}

/// Whether a stop line failed because the link was down (or the device
/// task gone): it never went out.
fn not_sent_for_the_link(result: &Result<LineResult, SessionError>) -> bool {
    matches!(
        result,
        Err(SessionError::Device {
            error: DeviceError::Disconnected(_) | DeviceError::Closed,
            ..
        })
    )
}

/// Why the link is not up, for the report.
fn down_because(state: &LinkState) -> String {
    match state {
        LinkState::Disconnected {
            reason,
            attempts: 0,
            ..
        } => reason.clone(),
        // The reopenings tried meanwhile, so that a port gone for good
        // is told from one that was never tried again.
        LinkState::Disconnected {
            reason, attempts, ..
        } => format!(
            "{reason}; {attempts} reconnect attempt{} failed",
            if *attempts == 1 { "" } else { "s" }
        ),
        LinkState::Closed => "the connection was closed".to_string(),
        LinkState::Connected { .. } => "it went again".to_string(),
    }
}

/// `1500 ms`, `10 s`.
fn show(duration: Duration) -> String {
    if duration.subsec_millis() == 0 && !duration.is_zero() {
        format!("{} s", duration.as_secs())
    } else {
        format!("{} ms", duration.as_millis())
    }
}

impl Session {
    /// End a run that ended so, under `policy`: nothing for a completed
    /// run or when told to leave the axes; otherwise the stop sequence,
    /// waiting up to [`LINK_RETURN_WAIT`] for a lost link to come back.
    pub async fn end_run(&self, ending: RunEnding, policy: StopOnFailure) -> RunAftermath {
        RunAftermath::of(ending, policy, || {
            self.stop_after_run(ending, LINK_RETURN_WAIT)
        })
        .await
    }

    /// Check the axes at the end of a run that completed, under `check`
    /// (every front end's `:run`/`axterm run` goes through here).
    pub async fn check_run_end(&self, check: AtTheEnd) -> EndCheck {
        if check == AtTheEnd::Nothing {
            return EndCheck::completed();
        }
        let moving = self.moving_axes().await.map_err(|e| e.to_string());
        EndCheck::judge(check, moving)
    }

    /// Send the stop-everything sequence after a run that did not
    /// complete. While the link is down the stop waits for it to come
    /// back, at most `reach` in all. The link may also have gone with the
    /// run's last line before the device task has said so: a stop whose
    /// lines could not be sent waits for news of the link and is sent
    /// again whole (a stop line twice does no harm; a stop line never sent
    /// does). What could not be sent is reported as such.
    pub async fn stop_after_run(&self, ending: RunEnding, reach: Duration) -> RunStop {
        let started = Instant::now();
        let deadline = started + reach;
        let mut state = self.link_state();
        let mut waited = false;
        loop {
            let down = matches!(*state.borrow_and_update(), LinkState::Disconnected { .. });
            if down {
                waited = true;
                // Up or not by the deadline, the stop is tried: if the
                // link is still down its lines fail at once, each saying so.
                let _ = tokio::time::timeout_at(
                    deadline,
                    state.wait_for(|s| !matches!(s, LinkState::Disconnected { .. })),
                )
                .await;
            }
            let lines = self.emergency_stop_lines().await;
            if !lines.iter().any(not_sent_for_the_link) {
                let link = if waited {
                    LinkAtStop::CameBack {
                        waited: started.elapsed(),
                    }
                } else {
                    LinkAtStop::Up
                };
                return RunStop {
                    ending,
                    lines,
                    link,
                };
            }
            waited = true;
            // News of the link before the next attempt; none comes from a
            // device task that has ended.
            let news = Instant::now() < deadline
                && matches!(
                    tokio::time::timeout_at(deadline, state.changed()).await,
                    Ok(Ok(()))
                );
            if !news {
                let reason = down_because(&state.borrow());
                return RunStop {
                    ending,
                    lines,
                    link: LinkAtStop::StayedDown {
                        waited: started.elapsed(),
                        reason,
                    },
                };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::console::ReplyValue;

    #[test]
    fn the_end_check_fails_a_run_only_for_an_axis_left_moving_unmeant() {
        let moving = || Ok(vec!["0"]);
        assert_eq!(
            EndCheck::judge(AtTheEnd::Nothing, moving()),
            EndCheck::completed()
        );
        assert_eq!(
            EndCheck::judge(AtTheEnd::StopIfMoving, Ok(Vec::new())),
            EndCheck::completed()
        );
        let unmeant = EndCheck::judge(AtTheEnd::StopIfMoving, moving());
        assert_eq!(unmeant.ending, RunEnding::Failed);
        assert!(unmeant.alarming);
        let meant = EndCheck::judge(AtTheEnd::SayIfMoving, moving());
        assert_eq!(meant.ending, RunEnding::Completed);
        assert!(meant.said.is_some_and(|s| s.contains(LEAVE_MOVING)));
        // Axes that cannot be read: nothing known to move, but said.
        let unread = EndCheck::judge(AtTheEnd::StopIfMoving, Err("timeout".into()));
        assert_eq!(unread.ending, RunEnding::Completed);
        assert!(unread.said.is_some_and(|s| s.contains("timeout")));
    }

    #[test]
    fn a_link_still_down_counts_the_reconnect_attempts() {
        let down = |attempts| LinkState::Disconnected {
            reason: "cannot open /dev/ttyUSB0 at 9600 Bd: no such port".into(),
            attempts,
            retry_in: Duration::from_secs(5),
        };
        assert_eq!(
            down_because(&down(0)),
            "cannot open /dev/ttyUSB0 at 9600 Bd: no such port"
        );
        assert_eq!(
            down_because(&down(1)),
            "cannot open /dev/ttyUSB0 at 9600 Bd: no such port; 1 reconnect attempt failed"
        );
        assert_eq!(
            down_because(&down(7)),
            "cannot open /dev/ttyUSB0 at 9600 Bd: no such port; 7 reconnect attempts failed"
        );
    }

    fn ok(line: &str) -> Result<LineResult, SessionError> {
        Ok(LineResult {
            line: line.into(),
            request: Vec::new(),
            reply: vec![2, 1, 100],
            status: Some(100),
            value: ReplyValue::None,
            elapsed: Duration::ZERO,
            attempts: 1,
        })
    }

    /// A line the module never answers, sent.
    fn sent(line: &str) -> Result<LineResult, SessionError> {
        Ok(LineResult {
            line: line.into(),
            request: vec![0, 0x25],
            reply: Vec::new(),
            status: None,
            value: ReplyValue::Text("sent".into()),
            elapsed: Duration::ZERO,
            attempts: 1,
        })
    }

    #[test]
    fn a_stop_the_module_never_answers_is_sent_not_confirmed() {
        let stop = RunAftermath::Stopped(RunStop {
            ending: RunEnding::Failed,
            lines: vec![sent("ConstantRotation 0 0"), sent("AbortReferenceSearch 0")],
            link: LinkAtStop::Up,
        });
        assert!(!stop.settled(), "nobody saw the axes stop");
        let report = stop.report();
        assert_eq!(report[1], "  ConstantRotation 0 0 → sent");
        assert_eq!(
            report[3],
            "stop sent: every stop line went out, 2 of them never acknowledged by the module: \
             check the axes"
        );
        assert!(
            stop.summary()
                .ends_with("STOP sent, 2 lines out, 2 unacknowledged")
        );
    }

    fn device(line: &str, error: DeviceError) -> Result<LineResult, SessionError> {
        Err(SessionError::Device {
            line: line.into(),
            address: 1,
            request: Vec::new(),
            error,
        })
    }

    #[test]
    fn only_a_run_that_did_not_complete_stops_and_only_by_default() {
        use RunEnding::*;
        assert_eq!(StopOnFailure::default(), StopOnFailure::Stop);
        for (policy, ending, stops) in [
            (StopOnFailure::Stop, Completed, false),
            (StopOnFailure::Stop, Failed, true),
            (StopOnFailure::Stop, Cancelled, true),
            (StopOnFailure::Leave, Completed, false),
            (StopOnFailure::Leave, Failed, false),
            (StopOnFailure::Leave, Cancelled, false),
        ] {
            assert_eq!(policy.stops_after(ending), stops, "{policy:?} {ending:?}");
        }
        assert_eq!(StopOnFailure::from_flag(true), StopOnFailure::Leave);
        assert_eq!(StopOnFailure::from_flag(false), StopOnFailure::Stop);
        assert_eq!(RunEnding::from_success(true), Completed);
        assert_eq!(RunEnding::from_success(false), Failed);
    }

    #[test]
    fn the_report_says_what_was_sent_what_was_not_and_what_got_no_answer() {
        let stop = RunAftermath::Stopped(RunStop {
            ending: RunEnding::Failed,
            lines: vec![
                ok("MST 0"),
                device(
                    "STOPAPP",
                    DeviceError::Timeout {
                        timeout: Duration::from_millis(202),
                        attempts: 1,
                    },
                ),
                device("MST 0", DeviceError::Disconnected("unplugged".into())),
            ],
            link: LinkAtStop::Up,
        });
        assert_eq!(
            stop.report(),
            [
                "the run failed: stopping every axis:",
                "  MST 0 → ok",
                "  STOPAPP: sent, no answer (no reply within 202 ms (after 1 attempt))",
                "  MST 0: NOT SENT (not connected: unplugged)",
                "STOP NOT CONFIRMED: 2 of 3 stop lines failed; check the axes",
            ]
        );
        assert!(!stop.settled());
        assert_eq!(
            stop.summary(),
            "the run failed: STOP NOT CONFIRMED (2 of 3 lines failed)"
        );
    }

    #[test]
    fn the_report_of_a_stop_after_a_lost_link_says_how_long_it_waited() {
        let back = RunAftermath::Stopped(RunStop {
            ending: RunEnding::Cancelled,
            lines: vec![ok("ESTOP")],
            link: LinkAtStop::CameBack {
                waited: Duration::from_millis(1500),
            },
        });
        assert_eq!(
            back.report(),
            [
                "the run was cancelled: the link was down; it came back after 1500 ms, stopping every axis:",
                "  ESTOP → ok",
                "stop confirmed: every stop line answered ok",
            ]
        );
        assert!(back.settled());
        let gone = RunAftermath::Stopped(RunStop {
            ending: RunEnding::Failed,
            lines: vec![device("ESTOP", DeviceError::Disconnected("gone".into()))],
            link: LinkAtStop::StayedDown {
                waited: Duration::from_secs(10),
                reason: "gone".into(),
            },
        });
        let report = gone.report();
        assert!(
            report[0].contains("did not come back within 10 s")
                && report[0].contains("the axes may still move"),
            "{report:?}"
        );
        assert_eq!(report[1], "  ESTOP: NOT SENT (not connected: gone)");
    }

    #[test]
    fn leaving_the_axes_says_so_and_a_completed_run_says_nothing() {
        let left = RunAftermath::Left(RunEnding::Cancelled);
        assert_eq!(
            left.report(),
            ["the run was cancelled: the axes were left as they are (--no-stop-on-failure)"]
        );
        assert!(!left.settled());
        assert!(RunAftermath::Completed.report().is_empty());
        assert!(RunAftermath::Completed.settled());
    }
}
