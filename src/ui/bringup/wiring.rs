//! The guided wiring check from the pane: asked, run on the session,
//! cancelled, and its findings shown.

use super::*;
use crate::ui::pane::SheetFact;

impl BringUpPane {
    /// `w`: ask before the wiring check moves the axis.
    pub(super) fn ask_wiring(&mut self, view: &View) -> Outcome {
        let (Some(plan), Some(session)) = (Self::plan(view), view.session) else {
            return self.not_connected();
        };
        if !matches!(self.jog, Jog::Idle | Jog::Armed { .. }) {
            self.say(Role::Error, "a jog is going: stop it first");
            return Outcome::redraw();
        }
        let Some(axis) = session.selected_axis() else {
            self.say(Role::Error, "this module has no axes");
            return Outcome::redraw();
        };
        if let Some(why) = Self::not_ready(plan, axis, session) {
            self.say(Role::Error, format!("wiring check not run: {why}"));
            return Outcome::redraw();
        }
        self.jog = Jog::Idle;
        self.wiring_confirm = true;
        self.say(
            Role::Warning,
            format!(
                "wiring check: jog {} toward + and then − until a limit switch fires? it moves \
                 the axis to both ends: y/n",
                axis.name
            ),
        );
        Outcome::redraw()
    }

    /// The y: the check goes, at the jog speed shown.
    pub(super) fn start_wiring(&mut self, view: &View) -> Outcome {
        let (Some(plan), Some(session)) = (Self::plan(view), view.session) else {
            return self.not_connected();
        };
        let Some(axis) = session.selected_axis().copied() else {
            return Outcome::Ignored;
        };
        let tag = self.tag();
        let speed = self.speed(plan);
        self.wiring = Some((tag, plan.stop(&axis)));
        // As a run file would say it, and where it was done.
        self.wiring_line = format!(
            ":wiring --axis {} --speed {speed} (the bring-up pane's check of {})",
            session.axis, axis.name
        );
        self.jog_axis = Some(session.axis);
        self.findings.clear();
        self.say(
            Role::Accent,
            format!(
                "wiring check on {}: jogging to its ends (Esc stops)",
                axis.name
            ),
        );
        Outcome::request(Request::CheckWiring {
            axis: session.axis,
            speed,
            tag,
        })
    }

    /// A key while the check runs: Esc or Space ends it, another axis
    /// ends it; the jog and step keys are refused.
    pub(super) fn key_while_checking(&mut self, key: &KeyEvent, view: &View) -> Outcome {
        let Some(action) = view.keymap.action_for(Context::BringUp, key) else {
            return Outcome::Ignored;
        };
        match action {
            Action::Cancel | Action::AxisStop => self.cancel_wiring("stopped by key"),
            Action::SelectPrevious | Action::SelectNext => {
                self.cancel_wiring("another axis chosen")
            }
            Action::JogPositive
            | Action::JogNegative
            | Action::StepPositive
            | Action::StepNegative
            | Action::WiringCheck
            | Action::OutputToggle => {
                self.say(
                    Role::Error,
                    "the wiring check is running: Esc stops it (nothing sent)",
                );
                Outcome::redraw()
            }
            _ => Outcome::Ignored,
        }
    }

    /// End the running check where it is and stop its axis.
    pub(super) fn cancel_wiring(&mut self, why: &str) -> Outcome {
        let Some((_, stop)) = self.wiring.take() else {
            return Outcome::Ignored;
        };
        let mut requests = vec![
            Request::CancelWiring,
            // Shown on a session recording's sheet, not counted: the user
            // stopped it.
            Request::SheetFact(SheetFact::Unfinished {
                line: self.wiring_line.clone(),
                why: format!("stopped before its end ({why})"),
                failed: false,
            }),
        ];
        if !stop.is_empty() {
            let left = stop.len();
            let (tag, send) = self.send_stop_lines(stop);
            self.jog = Jog::Stopping { tag, left };
            requests.push(send);
        }
        self.say(
            Role::Warning,
            format!("wiring check ended, stopping ({why})"),
        );
        Outcome::Handled(requests)
    }

    /// The check's end: its findings, or why it could not finish.
    pub(super) fn wiring_checked(
        &mut self,
        tag: u64,
        result: &Result<crate::ui::app::WiringFindings, String>,
    ) -> Outcome {
        if self.wiring.as_ref().is_none_or(|(t, _)| *t != tag) {
            return Outcome::Ignored;
        }
        self.wiring = None;
        let line = self.wiring_line.clone();
        let fact = match result {
            Ok(found) => SheetFact::Wiring {
                line,
                findings: found.lines.clone(),
                faults: found.faults.clone(),
            },
            Err(why) => SheetFact::Unfinished {
                line,
                why: why.clone(),
                failed: true,
            },
        };
        match result {
            Ok(found) => {
                self.findings = found
                    .lines
                    .iter()
                    .map(|line| (Role::Normal, line.clone()))
                    .collect();
                if found.wired_right {
                    self.say(
                        Role::Ok,
                        "wiring check: each limit switch fired for its own direction and stopped \
                         the axis",
                    );
                } else {
                    self.say(Role::Error, "wiring check: something is wrong, see below");
                }
            }
            Err(why) => self.say(Role::Error, format!("wiring check failed: {why}")),
        }
        Outcome::request(Request::SheetFact(fact))
    }
}
