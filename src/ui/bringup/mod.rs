//! The bring-up pane: jog the selected axis by hand and watch its
//! switches, the first hour on a new axis. Generic over the family: what
//! lines move, run and stop an axis is the family's
//! [`crate::protocol::jog::JogPlan`]; the switch lamps are the status poll's.
//!
//! # The deadman
//!
//! A continuous jog runs only while the key's repeats keep coming.
//! Terminals send no key release (certainly not over SSH), so the pane
//! never waits for one: every repeat renews a [`DEADMAN`] window and a
//! timer checks it; when a window passes with no repeat, the stop goes
//! (within [`DEADMAN`] plus the timer's lateness of the last repeat). A
//! single press does not run the axis: before a terminal starts repeating
//! a held key it waits (typically 250-660 ms), so a run starts only when a
//! second press of the same key comes within [`ARM_WINDOW`]; a tap is
//! taken as nothing (the step keys move by a step). The jog also stops
//! when the pane loses the keyboard (another pane, the terminal's focus),
//! when the axis changes, on Esc or Space, and when the link is lost (then
//! through the session, which sends the stop when the link comes back);
//! F12 stops everything as everywhere.
//!
//! The stop of a run whose start lines are still on their way waits for
//! their answers, so it cannot overtake them.
//!
//! # Inputs and outputs
//!
//! Below the jog, the module's inputs and outputs as its family lists
//! them ([`crate::protocol::io::IoPlan`]): the selected axis's switches,
//! the module's switches and inputs as lamps, analog inputs in volts where
//! the manual gives the scale, and the outputs. While the pane has the
//! keyboard their read lines ride on the status poll
//! ([`Request::Watch`]): switches and digital inputs watched fast, as
//! urgent polls that go before the status of every axis, so a change
//! shows within 200 ms at 9600 Bd; analog values and outputs with the
//! slow items. An output is chosen with its keys and
//! switched with Enter after a y/n question (an output can move
//! machinery); its read line then goes at once and says what it reads.
//!
//! # The wiring check
//!
//! A key (`w`) asks y/n, then runs the session's wiring check on the
//! selected axis ([`crate::session::Session::check_wiring`], the same as
//! `axterm wiring`) at the jog speed shown: it jogs toward + until a limit
//! switch fires, then toward −, and its findings stand in the pane, a
//! plain line each. While it runs the jog keys are refused; Esc or Space
//! ends it and sends the axis's stop lines, as does losing the keyboard
//! or choosing another axis; F12 stops everything as everywhere.

mod draw;
mod outputs;
mod wiring;

use draw::*;
use std::time::Duration;

use ratatui::Frame;
use ratatui::crossterm::event::KeyEvent;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use tokio::time::Instant;

use super::keymap::{Action, Context};
use super::pane::{Input, Outcome, Pane, PaneEvent, Region, Request, View, key_label};
use super::text::{fit, wrap};
use super::theme::Role;
use crate::device::LinkState;
use crate::protocol::console::AxisInfo;
use crate::protocol::io::{IoKind, IoPlan, IoPoint};
use crate::protocol::jog::{Direction, JogPlan, STEP_DISTANCES};
use crate::session::run_end::{RunEnding, StopOnFailure};
use crate::session::{AxisMotion, AxisStatus};
use crate::ui::pane::Snapshot;

/// How long a continuous jog goes on after the last key repeat: terminals
/// repeat a held key 11-33 times a second, so a window of 200 ms rides
/// over a late repeat or more, and leaves 100 ms for the stop to reach
/// the wire within 300 ms of the last repeat: at 9600 Bd it may wait for
/// a status line's request to finish going out and for the cut answer
/// (MCCL: up to about 85 ms, `tests/ui_bringup.rs`).
pub const DEADMAN: Duration = Duration::from_millis(200);

/// How soon after a first press a second press of the same key starts a
/// run: longer than the usual delay before a terminal repeats a held key.
pub const ARM_WINDOW: Duration = Duration::from_millis(800);

/// Where the continuous jog is.
#[derive(Debug, Clone, PartialEq)]
enum Jog {
    Idle,
    /// One press seen; a second within [`ARM_WINDOW`] starts the run.
    Armed {
        direction: Direction,
        at: Instant,
    },
    /// The run's lines are on their way (`left` of them unanswered).
    Starting {
        direction: Direction,
        tag: u64,
        left: usize,
        last_key: Instant,
        /// The stop was asked for meanwhile: it goes once they are
        /// answered.
        stop_asked: bool,
    },
    Running {
        direction: Direction,
        last_key: Instant,
    },
    /// The stop's lines are on their way.
    Stopping {
        tag: u64,
        left: usize,
    },
}

/// The bring-up pane.
pub struct BringUpPane {
    jog: Jog,
    /// The axis the jog started on: a change of axis stops it.
    jog_axis: Option<usize>,
    /// The lines that stop the jog going, made when it started (for its
    /// axis, whatever is selected by the time it stops).
    jog_stop: Vec<String>,
    step_index: usize,
    speed_index: usize,
    next_tag: u64,
    /// The deadman timer's tag; a wake under another tag is stale.
    deadman_tag: Option<u64>,
    /// The tags of steps on their way.
    steps: Vec<u64>,
    /// What was last sent, shown so nothing moves unseen.
    sent: Vec<String>,
    message: Option<(Role, String)>,
    /// The read lines of inputs and outputs polled for the pane now:
    /// (axis, line, fast).
    io_watched: Vec<(usize, String, bool)>,
    /// The chosen output: an index among the plan's outputs.
    output: usize,
    /// An output switch asked for and not yet confirmed: the point's
    /// index in the plan and the state asked.
    confirm: Option<(usize, bool)>,
    /// The output switch on its way: its tag, the point, the state, and
    /// how many of its lines are unanswered.
    switching: Option<(u64, usize, bool, usize)>,
    /// Outputs as this pane last set them (point index, state), for
    /// those the module cannot read back.
    set_states: Vec<(usize, bool)>,
    /// Outputs as last read back (point index, state).
    read_states: Vec<(usize, i64)>,
    /// The outputs' read lines sent once on taking the keyboard (they
    /// change only when switched: polling them would hold up the lamps),
    /// under this tag; `None` until sent.
    outputs_read: Option<u64>,
    /// The wiring check was asked for and awaits its y/n.
    wiring_confirm: bool,
    /// The wiring check running: its tag and the stop lines of its axis.
    wiring: Option<(u64, Vec<String>)>,
    /// The last wiring check as a commissioning sheet names it
    /// (`:wiring --axis 0 --speed 5000 (…)`).
    wiring_line: String,
    /// What the last wiring check found, a line each.
    findings: Vec<(Role, String)>,
}

impl Default for BringUpPane {
    fn default() -> Self {
        BringUpPane::new()
    }
}

impl BringUpPane {
    pub fn new() -> BringUpPane {
        BringUpPane {
            jog: Jog::Idle,
            jog_axis: None,
            jog_stop: Vec::new(),
            step_index: 3,
            speed_index: 1,
            next_tag: 1,
            deadman_tag: None,
            steps: Vec::new(),
            sent: Vec::new(),
            message: None,
            io_watched: Vec::new(),
            output: 0,
            confirm: None,
            switching: None,
            set_states: Vec::new(),
            read_states: Vec::new(),
            outputs_read: None,
            wiring_confirm: false,
            wiring: None,
            wiring_line: String::new(),
            findings: Vec::new(),
        }
    }

    fn plan(view: &View) -> Option<&'static dyn JogPlan> {
        view.session.and_then(|s| s.family.console.jog())
    }

    fn tag(&mut self) -> u64 {
        let tag = self.next_tag;
        self.next_tag += 1;
        tag
    }

    fn speed(&self, plan: &dyn JogPlan) -> i64 {
        let speeds = plan.speeds();
        speeds
            .get(self.speed_index.min(speeds.len().saturating_sub(1)))
            .copied()
            .unwrap_or(1)
    }

    fn step_distance(&self) -> i64 {
        STEP_DISTANCES
            .get(self.step_index)
            .copied()
            .unwrap_or(STEP_DISTANCES[0])
    }

    fn say(&mut self, role: Role, text: impl Into<String>) {
        self.message = Some((role, text.into()));
    }

    /// Send `lines` under a fresh tag.
    fn send(&mut self, lines: Vec<String>) -> (u64, Request) {
        let tag = self.tag();
        self.sent = lines.clone();
        (tag, Request::Send { lines, tag })
    }

    /// Send a jog's stop `lines` under a fresh tag, ahead of everything
    /// queued (a status read on the wire is cut short for them where the
    /// family can).
    fn send_stop_lines(&mut self, lines: Vec<String>) -> (u64, Request) {
        let tag = self.tag();
        self.sent = lines.clone();
        (tag, Request::SendStop { lines, tag })
    }

    /// Why the selected axis would not move now, by its driver lamps as
    /// last polled (nothing is judged before they are).
    fn not_ready(plan: &dyn JogPlan, axis: &AxisInfo, session: &Snapshot) -> Option<String> {
        let lit = session.status.get(session.axis)?.driver_flags.as_deref()?;
        plan.not_ready(axis, lit)
    }

    /// A timer for the deadman window ending `after` from now.
    fn deadman_in(&mut self, after: Duration) -> Request {
        let tag = self.tag();
        self.deadman_tag = Some(tag);
        Request::WakeAfter { after, tag }
    }

    /// A jog key (pressed or repeated) in `direction`.
    fn jog_key(&mut self, direction: Direction, view: &View) -> Outcome {
        let now = Instant::now();
        match self.jog.clone() {
            Jog::Starting {
                direction: going,
                tag,
                left,
                stop_asked: false,
                ..
            } if going == direction => {
                self.jog = Jog::Starting {
                    direction,
                    tag,
                    left,
                    last_key: now,
                    stop_asked: false,
                };
                Outcome::redraw()
            }
            Jog::Running {
                direction: going, ..
            } if going == direction => {
                self.jog = Jog::Running {
                    direction,
                    last_key: now,
                };
                Outcome::redraw()
            }
            Jog::Starting { .. } | Jog::Running { .. } => {
                // The other way while running: taken as letting go.
                self.stop("the other jog key")
            }
            Jog::Stopping { .. } => Outcome::redraw(),
            Jog::Armed {
                direction: armed,
                at,
            } if armed == direction && now.duration_since(at) <= ARM_WINDOW => {
                self.start_run(direction, now, view)
            }
            Jog::Idle | Jog::Armed { .. } => {
                self.jog = Jog::Armed { direction, at: now };
                self.say(
                    Role::Muted,
                    format!(
                        "hold the key to jog {}: it runs while the key repeats",
                        direction.sign()
                    ),
                );
                Outcome::redraw()
            }
        }
    }

    fn start_run(&mut self, direction: Direction, now: Instant, view: &View) -> Outcome {
        let (Some(plan), Some(session)) = (Self::plan(view), view.session) else {
            self.jog = Jog::Idle;
            return self.not_connected();
        };
        let Some(axis) = session.selected_axis().copied() else {
            self.jog = Jog::Idle;
            self.say(Role::Error, "this module has no axes");
            return Outcome::redraw();
        };
        if let Some(why) = Self::not_ready(plan, &axis, session) {
            self.jog = Jog::Idle;
            self.say(Role::Error, format!("nothing sent: {why}"));
            return Outcome::redraw();
        }
        let lines = match plan.run(&axis, direction, self.speed(plan)) {
            Ok(lines) => lines,
            Err(why) => {
                self.jog = Jog::Idle;
                self.say(Role::Error, format!("nothing sent: {why}"));
                return Outcome::redraw();
            }
        };
        self.jog_stop = plan.stop(&axis);
        let left = lines.len();
        let (tag, send) = self.send(lines);
        self.jog = Jog::Starting {
            direction,
            tag,
            left,
            last_key: now,
            stop_asked: false,
        };
        self.jog_axis = Some(session.axis);
        self.say(
            Role::Accent,
            format!("jogging {} {}", axis.name, direction.sign()),
        );
        let wake = self.deadman_in(DEADMAN);
        Outcome::Handled(vec![send, wake])
    }

    /// Stop the continuous jog, if one runs; `why` is said.
    fn stop(&mut self, why: &str) -> Outcome {
        match self.jog.clone() {
            Jog::Starting {
                direction,
                tag,
                left,
                last_key,
                ..
            } => {
                self.jog = Jog::Starting {
                    direction,
                    tag,
                    left,
                    last_key,
                    stop_asked: true,
                };
                self.say(Role::Warning, format!("stopping ({why})"));
                Outcome::redraw()
            }
            Jog::Running { .. } => {
                self.deadman_tag = None;
                match self.stop_lines() {
                    Some(lines) => {
                        let left = lines.len();
                        let (tag, send) = self.send_stop_lines(lines);
                        self.jog = Jog::Stopping { tag, left };
                        self.say(Role::Warning, format!("stopping ({why})"));
                        Outcome::request(send)
                    }
                    None => {
                        self.jog = Jog::Idle;
                        Outcome::redraw()
                    }
                }
            }
            Jog::Armed { .. } => {
                self.jog = Jog::Idle;
                Outcome::redraw()
            }
            Jog::Idle | Jog::Stopping { .. } => Outcome::Ignored,
        }
    }

    /// The stop lines of the axis the jog runs on, kept from its start.
    fn stop_lines(&self) -> Option<Vec<String>> {
        (!self.jog_stop.is_empty()).then(|| self.jog_stop.clone())
    }

    /// Send the stop now (the run's start lines were all answered).
    fn send_stop(&mut self) -> Outcome {
        self.deadman_tag = None;
        match self.stop_lines() {
            Some(lines) => {
                let left = lines.len();
                let (tag, send) = self.send_stop_lines(lines);
                self.jog = Jog::Stopping { tag, left };
                Outcome::request(send)
            }
            None => {
                self.jog = Jog::Idle;
                Outcome::redraw()
            }
        }
    }

    fn not_connected(&mut self) -> Outcome {
        self.say(Role::Error, "not connected: nothing to jog");
        Outcome::redraw()
    }

    /// One step in `direction` from where the axis stands.
    fn step(&mut self, direction: Direction, view: &View) -> Outcome {
        let (Some(plan), Some(session)) = (Self::plan(view), view.session) else {
            return self.not_connected();
        };
        if !matches!(self.jog, Jog::Idle | Jog::Armed { .. }) {
            self.say(Role::Error, "a jog is going: stop it first");
            return Outcome::redraw();
        }
        let Some(axis) = session.selected_axis().copied() else {
            self.say(Role::Error, "this module has no axes");
            return Outcome::redraw();
        };
        let status = session
            .status
            .get(session.axis)
            .cloned()
            .unwrap_or_default();
        // A step is from where the axis stands: a position read while it
        // moves is already stale.
        let standing = matches!(
            status.motion(),
            AxisMotion::AtTarget | AxisMotion::Stopped | AxisMotion::StoppedShort
        );
        let Some(position) = status.position.filter(|_| standing) else {
            self.say(
                Role::Error,
                format!(
                    "{} must stand with its position read before a step (nothing sent)",
                    axis.name
                ),
            );
            return Outcome::redraw();
        };
        if let Some(why) = Self::not_ready(plan, &axis, session) {
            self.say(Role::Error, format!("nothing sent: {why}"));
            return Outcome::redraw();
        }
        let distance = direction.signed(self.step_distance());
        match plan.step(&axis, position, distance, self.speed(plan)) {
            Ok(lines) => {
                let (tag, send) = self.send(lines);
                self.steps.push(tag);
                self.say(
                    Role::Accent,
                    format!("step {distance} from {position} on {}", axis.name),
                );
                Outcome::request(send)
            }
            Err(why) => {
                self.say(Role::Error, format!("nothing sent: {why}"));
                Outcome::redraw()
            }
        }
    }

    /// A reply to a line of ours.
    fn answer(&mut self, tag: u64, failed: Option<String>) -> Outcome {
        if let Some(at) = self.steps.iter().position(|t| *t == tag) {
            if let Some(why) = failed {
                self.steps.remove(at);
                self.say(Role::Error, format!("step failed: {why}"));
            }
            return Outcome::redraw();
        }
        match self.jog.clone() {
            Jog::Starting {
                direction,
                tag: start,
                left,
                last_key,
                stop_asked,
            } if start == tag => {
                if let Some(why) = failed {
                    // A line of the start failed: the rest was not sent.
                    // The stop goes anyway, in case a first line started
                    // something.
                    self.say(Role::Error, format!("jog failed: {why}"));
                    return self.send_stop();
                }
                if left > 1 {
                    self.jog = Jog::Starting {
                        direction,
                        tag: start,
                        left: left - 1,
                        last_key,
                        stop_asked,
                    };
                    return Outcome::redraw();
                }
                if stop_asked {
                    return self.send_stop();
                }
                self.jog = Jog::Running {
                    direction,
                    last_key,
                };
                Outcome::redraw()
            }
            Jog::Stopping { tag: stop, left } if stop == tag => {
                if let Some(why) = failed {
                    self.jog = Jog::Idle;
                    self.say(
                        Role::Error,
                        format!("the stop failed: {why}; F12 stops every axis"),
                    );
                } else if left > 1 {
                    self.jog = Jog::Stopping {
                        tag: stop,
                        left: left - 1,
                    };
                } else {
                    self.jog = Jog::Idle;
                    self.say(Role::Ok, "jog stopped");
                }
                Outcome::redraw()
            }
            _ => Outcome::Ignored,
        }
    }

    /// The deadman timer came due.
    fn deadman(&mut self) -> Outcome {
        let last_key = match &self.jog {
            Jog::Starting { last_key, .. } | Jog::Running { last_key, .. } => *last_key,
            _ => {
                self.deadman_tag = None;
                return Outcome::Ignored;
            }
        };
        let quiet = Instant::now().saturating_duration_since(last_key);
        if quiet >= DEADMAN {
            return self.stop("the key was let go");
        }
        let wake = self.deadman_in(DEADMAN - quiet);
        Outcome::Handled(vec![wake])
    }

    /// The link went: the session stops every axis once it is back.
    fn link_lost(&mut self) -> Outcome {
        if matches!(self.jog, Jog::Idle | Jog::Armed { .. }) && self.wiring.is_none() {
            return Outcome::Ignored;
        }
        self.wiring = None;
        self.jog = Jog::Idle;
        self.deadman_tag = None;
        self.say(
            Role::Error,
            "the link was lost while jogging: every axis is stopped when it is back",
        );
        Outcome::request(Request::EndRun {
            ending: RunEnding::Cancelled,
            policy: StopOnFailure::Stop,
        })
    }

    fn key(&mut self, key: &KeyEvent, view: &View) -> Outcome {
        if self.wiring_confirm {
            self.wiring_confirm = false;
            if key.code == ratatui::crossterm::event::KeyCode::Char('y') {
                return self.start_wiring(view);
            }
            self.say(Role::Muted, "wiring check not run: nothing moved");
            return Outcome::redraw();
        }
        if self.wiring.is_some() {
            return self.key_while_checking(key, view);
        }
        if self.confirm.is_some() {
            // Only y switches; any other key answers no (and does
            // nothing else).
            let yes = key.code == ratatui::crossterm::event::KeyCode::Char('y');
            return self.confirmed(yes, view);
        }
        let Some(action) = view.keymap.action_for(Context::BringUp, key) else {
            return Outcome::Ignored;
        };
        match action {
            Action::OutputNext => self.choose_output(true, view),
            Action::OutputPrevious => self.choose_output(false, view),
            Action::OutputToggle => self.ask_output(view),
            Action::WiringCheck => self.ask_wiring(view),
            Action::JogPositive => self.jog_key(Direction::Positive, view),
            Action::JogNegative => self.jog_key(Direction::Negative, view),
            Action::StepPositive => self.step(Direction::Positive, view),
            Action::StepNegative => self.step(Direction::Negative, view),
            Action::StepLarger => {
                self.step_index = (self.step_index + 1).min(STEP_DISTANCES.len() - 1);
                Outcome::redraw()
            }
            Action::StepSmaller => {
                self.step_index = self.step_index.saturating_sub(1);
                Outcome::redraw()
            }
            Action::JogFaster => {
                let most = Self::plan(view).map_or(0, |p| p.speeds().len().saturating_sub(1));
                self.speed_index = (self.speed_index + 1).min(most);
                Outcome::redraw()
            }
            Action::JogSlower => {
                self.speed_index = self.speed_index.saturating_sub(1);
                Outcome::redraw()
            }
            Action::Cancel | Action::AxisStop => match self.stop("stopped by key") {
                Outcome::Ignored => Outcome::redraw(),
                outcome => outcome,
            },
            Action::SelectPrevious | Action::SelectNext => {
                let Some(session) = view.session else {
                    return Outcome::Ignored;
                };
                let count = session.axes.len();
                if count == 0 {
                    return Outcome::Ignored;
                }
                let axis = if action == Action::SelectNext {
                    (session.axis + 1) % count
                } else {
                    (session.axis + count - 1) % count
                };
                let mut requests = match self.stop("another axis chosen") {
                    Outcome::Handled(requests) => requests,
                    Outcome::Ignored => Vec::new(),
                };
                requests.push(Request::SelectAxis(axis));
                Outcome::Handled(requests)
            }
            _ => Outcome::Ignored,
        }
    }

    fn state_text(&self) -> &'static str {
        if self.wiring.is_some() {
            return "WIRING CHECK";
        }
        match self.jog {
            Jog::Idle => "standing by",
            Jog::Armed { .. } => "hold the key to jog",
            Jog::Starting {
                stop_asked: true, ..
            } => "stopping",
            Jog::Starting { .. } | Jog::Running { .. } => "JOGGING",
            Jog::Stopping { .. } => "stopping",
        }
    }
}

impl Pane for BringUpPane {
    fn name(&self) -> &'static str {
        "bringup"
    }

    fn context(&self) -> Context {
        Context::BringUp
    }

    fn title(&self, view: &View) -> String {
        match view.session.and_then(|s| s.selected_axis()) {
            Some(axis) => format!("Jog — {}", axis.name),
            None => "Jog".to_string(),
        }
    }

    fn region(&self) -> Region {
        Region::Main
    }

    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        let theme = view.theme;
        let width = usize::from(area.width);
        let mut lines: Vec<Line> = Vec::new();
        let (Some(session), Some(plan)) = (view.session, Self::plan(view)) else {
            lines.push(Line::styled(
                fit("not connected: nothing to jog", width),
                theme.style(Role::Muted),
            ));
            frame.render_widget(Paragraph::new(lines), area);
            return;
        };
        let status: AxisStatus = session
            .status
            .get(session.axis)
            .cloned()
            .unwrap_or_default();
        let axis = session.selected_axis().map_or("—", |a| a.name);
        let state_role = match self.jog {
            _ if self.wiring.is_some() => Role::Emergency,
            Jog::Starting { .. } | Jog::Running { .. } => Role::Emergency,
            _ => Role::Normal,
        };
        lines.push(Line::from(vec![
            Span::styled(format!("{axis}  "), theme.style(Role::Accent)),
            Span::styled(
                format!(
                    "pos {}  speed {}  ",
                    number(status.position),
                    number(status.speed)
                ),
                theme.style(Role::Normal),
            ),
            Span::styled(self.state_text(), theme.style(state_role)),
        ]));
        if Self::io(view).is_none() {
            let mut switches = vec![Span::styled("switches ", theme.style(Role::Muted))];
            for (name, value) in [
                ("left/−", status.left_switch),
                ("right/+", status.right_switch),
                ("home", status.home_switch),
            ] {
                let (mark, role) = lamp(value);
                switches.push(Span::styled(format!("{name} "), theme.style(Role::Normal)));
                switches.push(Span::styled(format!("{mark}  "), theme.style(role)));
            }
            lines.push(Line::from(switches));
        }
        let driver = status
            .driver_flags
            .as_ref()
            .map(|flags| {
                if flags.is_empty() {
                    "none".to_string()
                } else {
                    flags.iter().map(|f| f.name).collect::<Vec<_>>().join(" ")
                }
            })
            .unwrap_or_else(|| "—".to_string());
        lines.push(Line::styled(
            fit(&format!("driver {driver}"), width),
            theme.style(Role::Normal),
        ));
        lines.push(Line::styled(
            fit(
                &format!(
                    "step {} counts   speed {} {}",
                    self.step_distance(),
                    self.speed(plan),
                    plan.speed_unit()
                ),
                width,
            ),
            theme.style(Role::Accent),
        ));
        let keys = |action| key_label(view.keymap, Context::BringUp, action);
        lines.push(Line::styled(
            fit(
                &format!(
                    "hold {}/{} jog · {}/{} step · {}{} size · {}{} speed · {} stop · {} wiring check",
                    keys(Action::JogNegative),
                    keys(Action::JogPositive),
                    keys(Action::StepNegative),
                    keys(Action::StepPositive),
                    keys(Action::StepSmaller),
                    keys(Action::StepLarger),
                    keys(Action::JogSlower),
                    keys(Action::JogFaster),
                    keys(Action::Cancel),
                    keys(Action::WiringCheck),
                ),
                width,
            ),
            theme.style(Role::Muted),
        ));
        lines.push(Line::styled(
            fit(&format!("note: {}", plan.side_effects()), width),
            theme.style(Role::Muted),
        ));
        if !self.sent.is_empty() {
            lines.push(Line::styled(
                fit(&format!("sent: {}", self.sent.join(" · ")), width),
                theme.style(Role::Sent),
            ));
        }
        if let Some((role, text)) = &self.message {
            lines.push(Line::styled(fit(text, width), theme.style(*role)));
        }
        for (role, finding) in &self.findings {
            for part in wrap(finding, width) {
                lines.push(Line::styled(part, theme.style(*role)));
            }
        }
        if let Some(io) = Self::io(view) {
            self.io_lines(&mut lines, io, session, width, view);
        }
        // At 80×24 a long list runs past the pane's foot: the switches,
        // the question and the outputs come first, the general inputs
        // after.
        frame.render_widget(Paragraph::new(lines), area);
    }

    fn handle_input(&mut self, input: &Input, view: &View) -> Outcome {
        match input {
            Input::Key(key) => self.key(key, view),
            _ => Outcome::Ignored,
        }
    }

    fn activity(&self) -> Option<String> {
        if self.wiring.is_some() {
            return Some("WIRING CHECK".to_string());
        }
        matches!(self.jog, Jog::Starting { .. } | Jog::Running { .. })
            .then(|| "JOGGING".to_string())
    }

    fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        match event {
            PaneEvent::Reply { tag, result, .. }
                if self.switching.is_some_and(|(t, ..)| t == *tag) =>
            {
                self.output_answer(result, view)
            }
            PaneEvent::Reply { tag, line, result } if self.outputs_read == Some(*tag) => {
                self.output_read(line, result, view)
            }
            PaneEvent::Reply { tag, result, .. } => {
                self.answer(*tag, result.as_ref().err().map(|e| e.to_string()))
            }
            PaneEvent::WiringChecked { tag, result } => self.wiring_checked(*tag, result),
            PaneEvent::Focused => {
                let mut requests = self.sync_watches(view, true);
                requests.extend(self.read_outputs(view));
                Outcome::Handled(requests)
            }
            PaneEvent::Wake { tag } if self.deadman_tag == Some(*tag) => self.deadman(),
            PaneEvent::RunEnded(aftermath) => {
                let role = if aftermath.settled() {
                    Role::Ok
                } else {
                    Role::Error
                };
                self.say(role, aftermath.summary());
                Outcome::redraw()
            }
            PaneEvent::Unfocused => {
                self.confirm = None;
                self.wiring_confirm = false;
                self.outputs_read = None;
                let watches = self.sync_watches(view, false);
                let stopped = if self.wiring.is_some() {
                    self.cancel_wiring("the pane lost the keyboard")
                } else {
                    self.stop("the pane lost the keyboard")
                };
                match stopped {
                    Outcome::Handled(mut requests) => {
                        requests.extend(watches);
                        Outcome::Handled(requests)
                    }
                    Outcome::Ignored if watches.is_empty() => Outcome::Ignored,
                    Outcome::Ignored => Outcome::Handled(watches),
                }
            }
            PaneEvent::Stopping => {
                // F12: the emergency stop goes ahead of everything; our
                // lines still waiting were dropped.
                let was = !matches!(self.jog, Jog::Idle) || self.wiring.is_some();
                self.jog = Jog::Idle;
                // The emergency stop ended the check's task too.
                self.wiring = None;
                self.deadman_tag = None;
                self.steps.clear();
                if was {
                    self.say(Role::Emergency, "STOP: every axis");
                    Outcome::redraw()
                } else {
                    Outcome::Ignored
                }
            }
            PaneEvent::Snapshot => {
                // The selected axis's switches follow it; the first
                // snapshot of a session brings its plan.
                let watches = if view.focused {
                    let mut requests = self.sync_watches(view, true);
                    requests.extend(self.read_outputs(view));
                    requests
                } else {
                    Vec::new()
                };
                match self.snapshot(view) {
                    Outcome::Handled(mut requests) => {
                        requests.extend(watches);
                        Outcome::Handled(requests)
                    }
                    Outcome::Ignored if watches.is_empty() => Outcome::Ignored,
                    Outcome::Ignored => Outcome::Handled(watches),
                }
            }
            _ => Outcome::Ignored,
        }
    }
}

impl BringUpPane {
    /// A new snapshot: the jog's checks.
    fn snapshot(&mut self, view: &View) -> Outcome {
        {
            {
                let Some(session) = view.session else {
                    return self.link_lost();
                };
                if matches!(
                    session.link,
                    LinkState::Disconnected { .. } | LinkState::Closed
                ) {
                    return self.link_lost();
                }
                if self.jog_axis.is_some_and(|axis| axis != session.axis) {
                    if self.wiring.is_some() {
                        return self.cancel_wiring("another axis chosen");
                    }
                    if !matches!(self.jog, Jog::Idle | Jog::Stopping { .. }) {
                        return self.stop("another axis chosen");
                    }
                }
                // The lamps and numbers follow the poll.
                if view.shown {
                    Outcome::redraw()
                } else {
                    Outcome::Ignored
                }
            }
        }
    }
}
