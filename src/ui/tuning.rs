//! The tuning pane: the family's tuning tool on the selected axis. Generic
//! over the family: a servo step test where the family's console has a
//! [`crate::protocol::tuning::StepResponsePlan`], a load sweep where it
//! has a [`crate::protocol::tuning::StallSweepPlan`], neither otherwise.
//! The runs are the session's ([`crate::session::tuning`], the same as
//! `axterm tune`), carried by [`Request::Tune`].
//!
//! # Step test
//!
//! The gains as read from the axis (when the pane gets the keyboard, and
//! on the refresh key), then the step's distance and sample count: a row
//! each, chosen with Up/Down; Enter types a value into the chosen row
//! (pre-filled with the value shown: confirming it unchanged sets that
//! same value). Gains typed are the `set` of the next run. The run key
//! asks y/n (it moves the axis), then the plot shows commanded and actual
//! position over time with the run before faded behind, and the figures
//! under it (a trip as `TRIPPED: …`).
//!
//! # Sweep
//!
//! From, to and steps as rows; the run key asks y/n and the readings are
//! plotted against speed. A key keeps the last sweep as the free one (no
//! load); the next sweep (the load applied) is drawn beside it with the
//! plan's suggestion and the lines that would set it, sent only on their
//! key after a y/n question.
//!
//! # Current control
//!
//! Where the family also has a load-adaptive current control (TMCL
//! CoolStep), a key switches between its tools. The view shows the form's
//! settings and a speed as rows, the chosen setting's meaning from the
//! manual under them; the run key (after a y/n question when the motor is
//! to turn) writes what was typed, starts the motor and plots the current
//! and the load reading live until Esc (see [`current`]).
//!
//! # Stopping
//!
//! Esc during a run ends it: its task is dropped ([`Request::CancelTune`])
//! and the plan's stop lines for the axis go out (a dropped run sends
//! none of its own). Losing the keyboard or the link, or choosing another
//! axis, does the same; F12 stops everything as everywhere.

mod current;

use ratatui::Frame;
use ratatui::crossterm::event::KeyEvent;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, LegendPosition, Paragraph};

use super::app::{TuneJob, TuneOutcome};
use super::field::Field;
use super::keymap::{Action, Context};
use super::pane::{Input, Outcome, Pane, PaneEvent, Region, Request, SheetFact, View, key_label};
use super::text::{fit, wrap};
use super::theme::Role;
use crate::device::LinkState;
use crate::protocol::console::AxisInfo;
use crate::protocol::tuning::{
    CurrentControlPlan, StallSweepPlan, StepAsk, StepResponsePlan, SweepAsk, SweepPoint,
    SweepSuggestion,
};
use crate::session::tuning::{StepRun, SweepRun, step_lines, step_plot, sweep_lines, sweep_plot};
use current::{CurrentView, WATCH_EVERY};

/// The family's tool, as the pane shows it.
#[derive(Clone, Copy)]
enum Tool {
    Step(&'static dyn StepResponsePlan),
    Sweep(&'static dyn StallSweepPlan),
    Current(&'static dyn CurrentControlPlan),
    None,
}

impl Tool {
    /// What the tool is called in the title and the switch's message.
    fn label(&self) -> &'static str {
        match self {
            Tool::Step(_) => "step response",
            Tool::Sweep(_) => "load sweep",
            Tool::Current(_) => "current control",
            Tool::None => "",
        }
    }
}

/// The tools the family of the session has, in the order the switch key
/// goes through them.
fn tools(view: &View) -> Vec<Tool> {
    let Some(session) = view.session else {
        return Vec::new();
    };
    let console = session.family.console;
    let mut tools = Vec::new();
    if let Some(plan) = console.step_response() {
        tools.push(Tool::Step(plan));
    }
    if let Some(plan) = console.stall_sweep() {
        tools.push(Tool::Sweep(plan));
    }
    if let Some(plan) = console.current_control() {
        tools.push(Tool::Current(plan));
    }
    tools
}

/// What awaits a y/n answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Confirm {
    Run,
    Apply,
}

/// A run under way: its tag, the axis and the lines that stop it.
#[derive(Debug, Clone, PartialEq)]
struct Running {
    tag: u64,
    /// The module (in [`View::modules`]) and the axis it runs on.
    module: usize,
    axis: usize,
    info: AxisInfo,
    stop: Vec<String>,
    /// The run as a commissioning sheet names it (`:tune-step …`); none
    /// for a current watch, which the sheet has no section for.
    line: Option<String>,
}

/// The tuning pane.
pub struct TuningPane {
    next_tag: u64,
    /// Which of the family's [`tools`] is shown.
    tool_index: usize,
    current: CurrentView,
    selected: usize,
    /// A value being typed into the selected row.
    editing: Option<Field>,
    /// The gains as last read (or as the last run read them).
    gains: Vec<(&'static str, Option<f64>)>,
    /// Gains typed, set at the next run.
    set: Vec<(String, f64)>,
    gains_tag: Option<u64>,
    /// The (family, axis) the gains were read for.
    read_for: Option<(&'static str, usize)>,
    distance: i64,
    samples: usize,
    /// The settling band of the step's figures, counts either side.
    band: f64,
    from: i64,
    to: i64,
    steps: u32,
    /// Readings taken at each speed of a sweep.
    readings: u32,
    confirm: Option<Confirm>,
    running: Option<Running>,
    step: Option<StepRun>,
    previous: Option<StepRun>,
    sweep: Option<SweepRun>,
    free: Option<SweepRun>,
    suggestion: Option<SweepSuggestion>,
    apply_tag: Option<u64>,
    message: Option<(Role, String)>,
}

impl Default for TuningPane {
    fn default() -> Self {
        TuningPane::new()
    }
}

/// Readings taken at each speed of a sweep unless another number is
/// typed.
const SWEEP_SAMPLES: u32 = 4;

impl TuningPane {
    pub fn new() -> TuningPane {
        TuningPane {
            next_tag: 1,
            tool_index: 0,
            current: CurrentView::new(),
            selected: 0,
            editing: None,
            gains: Vec::new(),
            set: Vec::new(),
            gains_tag: None,
            read_for: None,
            distance: 1000,
            samples: 400,
            band: crate::protocol::tuning::StepSpec::default().band,
            from: 200,
            to: 1000,
            steps: 5,
            readings: SWEEP_SAMPLES,
            confirm: None,
            running: None,
            step: None,
            previous: None,
            sweep: None,
            free: None,
            suggestion: None,
            apply_tag: None,
            message: None,
        }
    }

    fn tag(&mut self) -> u64 {
        self.next_tag += 1;
        self.next_tag
    }

    fn say(&mut self, role: Role, text: impl Into<String>) {
        self.message = Some((role, text.into()));
    }

    /// The tool shown.
    fn tool(&self, view: &View) -> Tool {
        let tools = tools(view);
        match tools.len() {
            0 => Tool::None,
            n => tools[self.tool_index % n],
        }
    }

    fn axis(view: &View) -> Option<(usize, AxisInfo)> {
        let session = view.session?;
        session.selected_axis().map(|a| (session.axis, *a))
    }

    /// The rows of the tool: (name, value shown).
    fn rows(&self, tool: &Tool) -> Vec<(String, String)> {
        match tool {
            Tool::Step(plan) => {
                let mut rows: Vec<(String, String)> = plan
                    .gains()
                    .iter()
                    .map(|g| (g.name.to_string(), self.gain_text(g.name)))
                    .collect();
                rows.push(("distance".into(), self.distance.to_string()));
                rows.push(("samples".into(), self.samples.to_string()));
                rows.push(("band".into(), self.band.to_string()));
                rows
            }
            Tool::Sweep(_) => vec![
                ("from".into(), self.from.to_string()),
                ("to".into(), self.to.to_string()),
                ("steps".into(), self.steps.to_string()),
                ("readings".into(), self.readings.to_string()),
            ],
            Tool::Current(plan) => self.current.rows(*plan),
            Tool::None => Vec::new(),
        }
    }

    /// A gain as shown: the value typed for the next run, else as read.
    fn gain_text(&self, name: &str) -> String {
        if let Some((_, v)) = self.set.iter().find(|(n, _)| n == name) {
            return v.to_string();
        }
        match self.gains.iter().find(|(n, _)| *n == name) {
            Some((_, Some(v))) => v.to_string(),
            Some((_, None)) => "?".into(),
            None => "-".into(),
        }
    }

    /// Read what the tool shows of the selected axis: the gains of a
    /// step tool, the form of a current control; once per axis, or
    /// `again`.
    fn refresh(&mut self, view: &View, again: bool) -> Vec<Request> {
        if let Tool::Current(_) = self.tool(view) {
            return self.read_form(view, again);
        }
        self.read_gains(view, again)
    }

    /// Read the form of a current control (nothing is written or moved).
    fn read_form(&mut self, view: &View, again: bool) -> Vec<Request> {
        let (Some(session), Some((axis, _))) = (view.session, Self::axis(view)) else {
            return Vec::new();
        };
        let key = (session.family.name, axis);
        if self.running.is_some() || (!again && self.current.read_for == Some(key)) {
            return Vec::new();
        }
        if self.current.read_for != Some(key) {
            self.current.set.clear();
        }
        self.current.read_for = Some(key);
        let tag = self.tag();
        self.current.form_tag = Some(tag);
        vec![Request::Tune {
            job: TuneJob::CurrentStart {
                axis,
                set: Vec::new(),
                run: None,
            },
            tag,
        }]
    }

    /// Read the gains of the selected axis (a step tool only).
    fn read_gains(&mut self, view: &View, again: bool) -> Vec<Request> {
        let (Tool::Step(_), Some(session), Some((axis, _))) =
            (self.tool(view), view.session, Self::axis(view))
        else {
            return Vec::new();
        };
        let key = (session.family.name, axis);
        if self.running.is_some() || (!again && self.read_for == Some(key)) {
            return Vec::new();
        }
        if self.read_for != Some(key) {
            self.set.clear();
        }
        self.read_for = Some(key);
        let tag = self.tag();
        self.gains_tag = Some(tag);
        vec![Request::Tune {
            job: TuneJob::Gains { axis },
            tag,
        }]
    }

    fn key(&mut self, key: &KeyEvent, view: &View) -> Outcome {
        if let Some(field) = self.editing.take() {
            return self.field_key(field, key, view);
        }
        let action = view.keymap.action_for(Context::Tuning, key);
        if let Some(confirm) = self.confirm.take() {
            if matches!(action, Some(Action::EmergencyStop)) {
                return Outcome::Ignored;
            }
            let yes = matches!(key.code, ratatui::crossterm::event::KeyCode::Char('y'));
            if yes {
                return match confirm {
                    Confirm::Run => self.start(view),
                    Confirm::Apply => self.apply(),
                };
            }
            self.say(Role::Muted, "not done: nothing sent");
            return Outcome::redraw();
        }
        if self.running.is_some() {
            return match action {
                Some(Action::Cancel | Action::AxisStop) => self.cancel("stopped by key"),
                Some(Action::TuneRun | Action::ParameterEdit | Action::TuneApply) => {
                    self.say(
                        Role::Warning,
                        "a run is under way: Esc stops it (nothing sent)",
                    );
                    Outcome::redraw()
                }
                _ => Outcome::Ignored,
            };
        }
        let tool = self.tool(view);
        let rows = self.rows(&tool).len();
        match action {
            Some(Action::TuneTool) => {
                let count = tools(view).len();
                if count < 2 {
                    self.say(Role::Muted, "this family has one tuning tool");
                    return Outcome::redraw();
                }
                self.tool_index = (self.tool_index + 1) % count;
                self.selected = 0;
                let shown = self.tool(view);
                self.say(
                    Role::Muted,
                    format!(
                        "switched to the {} ({} for the next tool)",
                        shown.label(),
                        key_label(view.keymap, Context::Tuning, Action::TuneTool)
                    ),
                );
                Outcome::Handled(self.refresh(view, false))
            }
            Some(Action::SelectPrevious) if rows > 0 => {
                self.selected = self.selected.checked_sub(1).unwrap_or(rows - 1);
                Outcome::redraw()
            }
            Some(Action::SelectNext) if rows > 0 => {
                self.selected = (self.selected + 1) % rows;
                Outcome::redraw()
            }
            Some(Action::ParameterEdit) if rows > 0 => {
                let shown = self
                    .rows(&tool)
                    .get(self.selected.min(rows - 1))
                    .map(|(_, v)| v.clone())
                    .unwrap_or_default();
                let shown = if shown == "?" || shown == "-" {
                    String::new()
                } else {
                    shown
                };
                self.editing = Some(Field::new(shown));
                Outcome::redraw()
            }
            Some(Action::ParameterRefresh) => Outcome::Handled(self.refresh(view, true)),
            Some(Action::TuneRun) => self.ask_run(view, &tool),
            Some(Action::TuneKeepFree) => {
                match self.sweep.take() {
                    Some(sweep) => {
                        self.free = Some(sweep);
                        self.suggestion = None;
                        self.say(
                            Role::Ok,
                            "kept as the free sweep: apply the load and run again",
                        );
                    }
                    None => self.say(Role::Warning, "no sweep to keep yet"),
                }
                Outcome::redraw()
            }
            Some(Action::TuneApply) => {
                match &self.suggestion {
                    Some(s) if !s.lines.is_empty() => {
                        self.confirm = Some(Confirm::Apply);
                        let text = format!("send {}? y/n", s.lines.join("; "));
                        self.say(Role::Warning, text);
                    }
                    _ => self.say(Role::Warning, "no suggestion to send"),
                }
                Outcome::redraw()
            }
            _ => Outcome::Ignored,
        }
    }

    fn field_key(&mut self, mut field: Field, key: &KeyEvent, view: &View) -> Outcome {
        match view.keymap.action_for(Context::Command, key) {
            Some(Action::Cancel) => {
                self.say(Role::Muted, "not changed");
                Outcome::redraw()
            }
            Some(Action::Submit) => {
                let text = field.text().trim().to_string();
                if let Err(why) = self.take_value(&self.tool(view), &text, view) {
                    self.say(Role::Error, why);
                    self.editing = Some(field);
                }
                Outcome::redraw()
            }
            _ => {
                field.edit(key);
                self.editing = Some(field);
                Outcome::redraw()
            }
        }
    }

    /// The typed `text` into the selected row.
    fn take_value(&mut self, tool: &Tool, text: &str, view: &View) -> Result<(), String> {
        let rows = self.rows(tool);
        let Some((name, _)) = rows.get(self.selected) else {
            return Err("no row chosen".into());
        };
        if let Tool::Current(plan) = tool {
            let Some((_, info)) = Self::axis(view) else {
                return Err("no axis to tune".into());
            };
            let said = self.current.take_value(*plan, &info, name, text)?;
            self.say(Role::Changed, said);
            return Ok(());
        }
        let whole = |text: &str| {
            text.parse::<i64>()
                .map_err(|_| format!("{name}: {text:?} is not a whole number"))
        };
        match (tool, name.as_str()) {
            (Tool::Step(_), "distance") => {
                let d = whole(text)?;
                if d == 0 {
                    return Err("distance: a step of 0 counts is no step".into());
                }
                self.distance = d;
            }
            (Tool::Step(_), "samples") => {
                let n = whole(text)?;
                self.samples = usize::try_from(n)
                    .ok()
                    .filter(|&n| n >= 2)
                    .ok_or_else(|| format!("samples: {n} (at least 2)"))?;
            }
            (Tool::Step(_), "band") => {
                self.band = text
                    .parse()
                    .ok()
                    .filter(|b: &f64| b.is_finite() && *b > 0.0)
                    .ok_or_else(|| format!("band: {text:?} (counts either side, more than 0)"))?;
            }
            (Tool::Step(_), gain) => {
                let v: f64 = text
                    .parse()
                    .ok()
                    .filter(|v: &f64| v.is_finite())
                    .ok_or_else(|| format!("{gain}: {text:?} is not a number"))?;
                self.set.retain(|(n, _)| n != gain);
                self.set.push((gain.to_string(), v));
                self.say(Role::Changed, format!("{gain} {v} is set at the next run"));
                return Ok(());
            }
            (Tool::Sweep(_), "from") => self.from = whole(text)?,
            (Tool::Sweep(_), "to") => self.to = whole(text)?,
            (Tool::Sweep(_), "readings") => {
                let n = whole(text)?;
                self.readings = u32::try_from(n)
                    .ok()
                    .filter(|&n| n >= 1)
                    .ok_or_else(|| format!("readings: {n} (at least 1 at each speed)"))?;
            }
            (Tool::Sweep(_), _) => {
                let n = whole(text)?;
                self.steps = u32::try_from(n)
                    .ok()
                    .filter(|&n| n >= 1)
                    .ok_or_else(|| format!("steps: {n} (at least 1)"))?;
            }
            (Tool::Current(_) | Tool::None, _) => {
                return Err("no tuning tool for this family".into());
            }
        }
        self.message = None;
        Ok(())
    }

    fn step_ask(&self) -> StepAsk {
        StepAsk {
            distance: self.distance,
            samples: self.samples,
            set: self.set.clone(),
        }
    }

    fn sweep_ask(&self) -> SweepAsk {
        SweepAsk {
            from: self.from,
            to: self.to,
            steps: self.steps,
            samples: self.readings,
        }
    }

    /// The run key: checked by the plan first (nothing sent on a refusal),
    /// then a y/n question.
    fn ask_run(&mut self, view: &View, tool: &Tool) -> Outcome {
        let Some((axis, info)) = Self::axis(view) else {
            self.say(Role::Error, "no axis to tune");
            return Outcome::redraw();
        };
        if self.gains_tag.is_some() || self.current.form_tag.is_some() {
            // One job at a time on the link: the read ends in a moment.
            self.say(
                Role::Warning,
                "the settings are being read: run again in a moment (nothing sent)",
            );
            return Outcome::redraw();
        }
        let checked = match tool {
            Tool::Step(plan) => plan
                .script(&info, &self.step_ask())
                .map_err(|e| e.to_string())
                .map(|_| {
                    format!(
                        "step {} by {} counts, recording {} samples?",
                        info.name, self.distance, self.samples
                    )
                }),
            Tool::Sweep(plan) => plan
                .script(&info, &self.sweep_ask())
                .map_err(|e| e.to_string())
                .map(|_| {
                    format!(
                        "sweep {} from {} to {} in {} speeds?",
                        info.name, self.from, self.to, self.steps
                    )
                }),
            Tool::Current(_) => match self.current_job(view, axis, &info) {
                Ok(_) if self.current.speed == 0 => return self.start(view),
                Ok(_) => Ok(format!(
                    "watch the current of {} turning at {}?",
                    info.name, self.current.speed
                )),
                Err(why) => Err(why),
            },
            Tool::None => {
                self.say(Role::Error, "no tuning tool for this family");
                return Outcome::redraw();
            }
        };
        match checked {
            Ok(question) => {
                self.confirm = Some(Confirm::Run);
                self.say(Role::Warning, format!("{question} it moves the axis: y/n"));
            }
            Err(why) => self.say(Role::Error, format!("{why} (nothing sent)")),
        }
        Outcome::redraw()
    }

    /// The start of a current watch on `axis` and the lines that stop
    /// it: the typed settings, and the motor turning at the speed (a
    /// positive jog) unless it is 0. Checked by the plans: nothing is sent
    /// on an error.
    fn current_job(
        &self,
        view: &View,
        axis: usize,
        info: &AxisInfo,
    ) -> Result<(TuneJob, Vec<String>), String> {
        let speed = self.current.speed;
        let (run, stop) = if speed == 0 {
            (None, Vec::new())
        } else {
            let jog = view
                .session
                .and_then(|s| s.family.console.jog())
                .ok_or("this family has no jog to turn the motor with: speed 0 watches only")?;
            let direction = crate::protocol::jog::Direction::Positive;
            jog.run(info, direction, speed)
                .map_err(|e| format!("speed {speed}: {e}"))?;
            (Some((direction, speed)), jog.stop(info))
        };
        let job = TuneJob::CurrentStart {
            axis,
            set: self.current.set.clone(),
            run,
        };
        Ok((job, stop))
    }

    fn start(&mut self, view: &View) -> Outcome {
        let Some((axis, info)) = Self::axis(view) else {
            return Outcome::redraw();
        };
        let (job, stop) = match self.tool(view) {
            Tool::Step(plan) => {
                let ask = self.step_ask();
                match plan.script(&info, &ask) {
                    Ok(script) => (
                        TuneJob::Step {
                            axis,
                            ask,
                            band: self.band,
                        },
                        script.stop,
                    ),
                    Err(why) => {
                        self.say(Role::Error, format!("{why} (nothing sent)"));
                        return Outcome::redraw();
                    }
                }
            }
            Tool::Sweep(plan) => {
                let ask = self.sweep_ask();
                match plan.script(&info, &ask) {
                    Ok(script) => (TuneJob::Sweep { axis, ask }, script.stop),
                    Err(why) => {
                        self.say(Role::Error, format!("{why} (nothing sent)"));
                        return Outcome::redraw();
                    }
                }
            }
            Tool::Current(_) => match self.current_job(view, axis, &info) {
                Ok(started) => started,
                Err(why) => {
                    self.say(Role::Error, format!("{why} (nothing sent)"));
                    return Outcome::redraw();
                }
            },
            Tool::None => return Outcome::redraw(),
        };
        let tag = self.tag();
        let line = self.sheet_line(&job, &info);
        self.running = Some(Running {
            tag,
            module: view.module,
            axis,
            info,
            stop,
            line,
        });
        self.say(
            Role::Emergency,
            format!("running on {} (Esc stops it)", info.name),
        );
        Outcome::request(Request::Tune { job, tag })
    }

    /// A run as a run file would say it, and where it was done.
    fn sheet_line(&self, job: &TuneJob, info: &AxisInfo) -> Option<String> {
        Some(match job {
            TuneJob::Step { ask, band, .. } => {
                let set: Vec<String> = ask.set.iter().map(|(n, v)| format!("{n}={v}")).collect();
                format!(
                    ":tune-step --axis {} --distance {} --samples {}{} (the tuning pane's step of \
                     {}, settling band {band} counts)",
                    info.number,
                    ask.distance,
                    ask.samples,
                    if set.is_empty() {
                        String::new()
                    } else {
                        format!(" --set {}", set.join(","))
                    },
                    info.name
                )
            }
            TuneJob::Sweep { ask, .. } => format!(
                ":tune-stallguard --axis {} --from {} --to {} --steps {} --samples {} (the tuning \
                 pane's sweep of {})",
                info.number, ask.from, ask.to, ask.steps, ask.samples, info.name
            ),
            TuneJob::Gains { .. } => format!("reading the gains of {}", info.name),
            TuneJob::CurrentStart { .. } | TuneJob::CurrentRead { .. } => return None,
        })
    }

    /// End the run: drop its task and send the axis's stop lines.
    fn cancel(&mut self, why: &str) -> Outcome {
        let Some(running) = self.running.take() else {
            return Outcome::Ignored;
        };
        let mut requests = vec![Request::CancelTune];
        if let Some(line) = running.line.clone() {
            // Shown on a session recording's sheet, not counted: the user
            // stopped it.
            requests.push(Request::SheetFact(SheetFact::Unfinished {
                line,
                why: format!("stopped before its end ({why})"),
                failed: false,
            }));
        }
        if !running.stop.is_empty() {
            let tag = self.tag();
            self.say(
                Role::Warning,
                format!("run ended, stopping ({why}): {}", running.stop.join("; ")),
            );
            requests.push(Request::Send {
                lines: running.stop,
                tag,
            });
        } else {
            self.say(Role::Warning, format!("run ended ({why})"));
        }
        Outcome::Handled(requests)
    }

    fn apply(&mut self) -> Outcome {
        let Some(s) = &self.suggestion else {
            return Outcome::redraw();
        };
        let lines = s.lines.clone();
        let tag = self.tag();
        self.apply_tag = Some(tag);
        self.say(Role::Sent, format!("sending {}", lines.join("; ")));
        Outcome::request(Request::Send { lines, tag })
    }

    fn tuned(&mut self, tag: u64, result: &Result<TuneOutcome, String>, view: &View) -> Outcome {
        if self.gains_tag == Some(tag) {
            self.gains_tag = None;
            match result {
                Ok(TuneOutcome::Gains(gains)) => self.gains = gains.clone(),
                Ok(_) => {}
                Err(why) => self.say(Role::Error, format!("the gains do not read: {why}")),
            }
            return Outcome::redraw();
        }
        if self.current.form_tag == Some(tag) {
            self.current.form_tag = None;
            match result {
                Ok(TuneOutcome::CurrentStarted(run)) => self.current.took_form(run),
                Ok(_) => {}
                Err(why) => self.say(Role::Error, format!("the form does not read: {why}")),
            }
            return Outcome::redraw();
        }
        let Some(running) = self.running.as_ref().filter(|r| r.tag == tag) else {
            return Outcome::Ignored;
        };
        let axis = running.axis;
        // A current watch goes on, a reading at a time, until stopped.
        let next_read = match result {
            Ok(TuneOutcome::CurrentStarted(run)) => {
                self.current.started(run, tokio::time::Instant::now());
                self.say(
                    Role::Emergency,
                    "watching: the plot follows current and load (Esc ends it)",
                );
                Some(std::time::Duration::ZERO)
            }
            Ok(TuneOutcome::CurrentRead(sample)) => {
                self.current.push(*sample);
                Some(WATCH_EVERY)
            }
            Err(why) if matches!(self.tool(view), Tool::Current(_)) => {
                // The motor may turn: stop it as Esc would.
                let why = format!("the watch failed: {why}");
                let outcome = self.cancel(&why);
                self.say(Role::Error, why);
                return outcome;
            }
            _ => None,
        };
        if let Some(wait) = next_read {
            let tag = self.tag();
            if let Some(running) = self.running.as_mut() {
                running.tag = tag;
            }
            return Outcome::request(Request::Tune {
                job: TuneJob::CurrentRead {
                    axis,
                    full: self.current.full,
                    began: self.current.began.unwrap_or_else(tokio::time::Instant::now),
                    wait,
                },
                tag,
            });
        }
        let Some(running) = self.running.take() else {
            return Outcome::Ignored;
        };
        let fact = sheet_fact(&running, result, &self.tool(view));
        match result {
            Ok(TuneOutcome::Step(run)) => {
                self.gains = run.gains.clone();
                self.set.clear();
                if run.tripped.is_empty() {
                    self.say(Role::Ok, "step done");
                } else {
                    self.say(Role::Error, "the step TRIPPED: the axis was stopped");
                }
                self.previous = self.step.replace(run.clone());
            }
            Ok(TuneOutcome::Sweep(run)) => {
                self.suggestion = match (self.tool(view), &self.free, Self::axis(view)) {
                    (Tool::Sweep(plan), Some(free), Some((_, info))) => Some(plan.suggest(
                        &info,
                        &free.points,
                        &run.points,
                        run.threshold.unwrap_or(0),
                    )),
                    _ => None,
                };
                self.say(Role::Ok, "sweep done");
                self.sweep = Some(run.clone());
            }
            Ok(
                TuneOutcome::Gains(_)
                | TuneOutcome::CurrentStarted(_)
                | TuneOutcome::CurrentRead(_),
            ) => {}
            Err(why) => self.say(Role::Error, format!("the run failed: {why}")),
        }
        Outcome::Handled(fact.map(Request::SheetFact).into_iter().collect())
    }

    /// The step plot's series: (points, role, marker, name); the run
    /// before faded behind.
    fn step_series(&self) -> Series {
        let Some(run) = self.step.as_ref() else {
            return Vec::new();
        };
        // Counts from where each run started, so that the run before
        // lies over this one though the axis stood elsewhere then.
        let series = |run: &StepRun, actual: bool| -> Vec<(f64, f64)> {
            let start = run.samples.first().map_or(0.0, |s| s.actual);
            run.samples
                .iter()
                .map(|s| {
                    let value = if actual { s.actual } else { s.commanded };
                    (s.time * 1000.0, value - start)
                })
                .collect()
        };
        let mut all: Series = Vec::new();
        if let Some(previous) = &self.previous {
            all.push((series(previous, true), Role::Muted, Marker::Bar, "before"));
        }
        all.push((series(run, false), Role::Plot2, Marker::Dot, "commanded"));
        all.push((series(run, true), Role::Plot1, Marker::Braille, "actual"));
        all
    }

    /// The sweep plot's series: the mean reading at each speed.
    fn sweep_series(&self) -> Series {
        let means = |points: &[SweepPoint]| -> Vec<(f64, f64)> {
            points
                .iter()
                .filter_map(|p| Some((p.speed as f64, p.mean()? as f64)))
                .collect()
        };
        let mut all: Series = Vec::new();
        if let Some(free) = &self.free {
            all.push((means(&free.points), Role::Plot2, Marker::Dot, "free"));
        }
        if let Some(sweep) = &self.sweep {
            let name = if self.free.is_some() {
                "loaded"
            } else {
                "reading"
            };
            all.push((means(&sweep.points), Role::Plot1, Marker::Braille, name));
        }
        all
    }
}

type Series = Vec<(Vec<(f64, f64)>, Role, Marker, &'static str)>;

/// The character a marker draws a point with (braille: one full cell).
fn marker_symbol(marker: Marker) -> &'static str {
    match marker {
        Marker::Dot => "•",
        Marker::Block => "█",
        Marker::Bar => "▄",
        Marker::HalfBlock => "▀",
        _ => "⣿",
    }
}

/// Each series's marker and name on one line.
fn series_key(series: &Series) -> String {
    series
        .iter()
        .map(|(_, _, marker, name)| format!("{} {name}", marker_symbol(*marker)))
        .collect::<Vec<_>>()
        .join("   ")
}

/// How a chart's value axis is scaled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scale {
    /// To the values, with a margin.
    Values,
    /// From zero (or below) to the largest value.
    FromZero,
    /// 0 to 100 % (more if a value is above), over exactly the time the
    /// points span.
    Percent,
}

/// What a run that ended gave, as the commissioning sheet shows it: the
/// figure lines and plot `axterm run` puts there for its `:tune-step` and
/// `:tune-stallguard`.
fn sheet_fact(
    running: &Running,
    result: &Result<TuneOutcome, String>,
    tool: &Tool,
) -> Option<SheetFact> {
    let line = running.line.clone()?;
    let axis = &running.info;
    Some(match result {
        Ok(TuneOutcome::Step(run)) => {
            let tripped: Vec<&str> = run.tripped.iter().map(|f| f.name).collect();
            SheetFact::Tuning {
                line,
                said: if tripped.is_empty() {
                    format!("{} samples", run.samples.len())
                } else {
                    format!("tripped ({}): the axis was stopped", tripped.join(", "))
                },
                ok: tripped.is_empty(),
                figures: step_lines(axis, run),
                plots: vec![step_plot(axis, run)],
            }
        }
        Ok(TuneOutcome::Sweep(run)) => {
            let reading = match tool {
                Tool::Sweep(plan) => plan.reading(),
                _ => "reading",
            };
            SheetFact::Tuning {
                line,
                said: format!("{} speeds swept", run.points.len()),
                ok: true,
                figures: sweep_lines(reading, run),
                plots: vec![sweep_plot(axis, reading, run)],
            }
        }
        Ok(
            TuneOutcome::Gains(_) | TuneOutcome::CurrentStarted(_) | TuneOutcome::CurrentRead(_),
        ) => return None,
        Err(why) => SheetFact::Unfinished {
            line,
            why: why.clone(),
            failed: true,
        },
    })
}

/// The chart of `series`, borrowing their points.
fn series_chart<'a>(
    series: &'a Series,
    scale: Scale,
    titles: (&'a str, &'a str),
    view: &View,
) -> Chart<'a> {
    let points = || series.iter().flat_map(|(p, ..)| p.iter().copied());
    let (x, y) = bounds(points());
    let (x, y) = match scale {
        Scale::Values => (x, y),
        Scale::FromZero => (x, [y[0].min(0.0), y[1]]),
        Scale::Percent => {
            let (first, last) = points().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.0), b.max(p.0))
            });
            let top = points().fold(100.0_f64, |top, p| top.max(p.1));
            ([first, last.max(first + 1.0)], [0.0, top])
        }
    };
    let sets = series
        .iter()
        .map(|(points, role, marker, name)| {
            Dataset::default()
                .name(*name)
                .marker(*marker)
                .graph_type(GraphType::Line)
                .style(view.theme.style(*role))
                .data(points)
        })
        .collect();
    chart(sets, x, y, titles.0, titles.1, view)
}

fn bounds(points: impl Iterator<Item = (f64, f64)>) -> ([f64; 2], [f64; 2]) {
    let mut x = [f64::INFINITY, f64::NEG_INFINITY];
    let mut y = [f64::INFINITY, f64::NEG_INFINITY];
    for (px, py) in points {
        x = [x[0].min(px), x[1].max(px)];
        y = [y[0].min(py), y[1].max(py)];
    }
    let widen = |b: [f64; 2]| {
        if !b[0].is_finite() {
            [0.0, 1.0]
        } else if b[1] <= b[0] {
            [b[0] - 1.0, b[1] + 1.0]
        } else {
            let pad = (b[1] - b[0]) * 0.05;
            [b[0] - pad, b[1] + pad]
        }
    };
    (widen(x), widen(y))
}

fn chart<'a>(
    sets: Vec<Dataset<'a>>,
    x: [f64; 2],
    y: [f64; 2],
    x_title: &'a str,
    y_title: &'a str,
    view: &View,
) -> Chart<'a> {
    let theme = view.theme;
    let label = |v: f64| Span::raw(format!("{v:.0}"));
    Chart::new(sets)
        .style(theme.style(Role::Normal))
        .x_axis(
            Axis::default()
                .title(Span::styled(x_title, theme.style(Role::Title)))
                .bounds(x)
                .labels(vec![label(x[0]), label((x[0] + x[1]) / 2.0), label(x[1])])
                .style(theme.style(Role::PlotAxes)),
        )
        .y_axis(
            Axis::default()
                .title(Span::styled(y_title, theme.style(Role::Title)))
                .bounds(y)
                .labels(vec![label(y[0]), label(y[1])])
                .style(theme.style(Role::PlotAxes)),
        )
        .legend_position(Some(LegendPosition::TopLeft))
        .hidden_legend_constraints((Constraint::Ratio(1, 1), Constraint::Ratio(1, 1)))
}

impl Pane for TuningPane {
    fn name(&self) -> &'static str {
        "tuning"
    }

    fn context(&self) -> Context {
        Context::Tuning
    }

    fn title(&self, view: &View) -> String {
        let tool = self.tool(view);
        match (tool, Self::axis(view)) {
            (Tool::None, _) | (_, None) => "Tune".to_string(),
            (_, Some((_, a))) if tools(view).len() > 1 => {
                format!("Tune — {} · {}", a.name, tool.label())
            }
            (_, Some((_, a))) => format!("Tune — {}", a.name),
        }
    }

    fn region(&self) -> Region {
        Region::Main
    }

    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        let theme = view.theme;
        let width = usize::from(area.width);
        let tool = self.tool(view);
        let mut head: Vec<Line> = Vec::new();
        if view.session.is_none() {
            head.push(Line::styled("not connected", theme.style(Role::Muted)));
            frame.render_widget(Paragraph::new(head), area);
            return;
        }
        if matches!(tool, Tool::None) {
            head.push(Line::styled(
                "no tuning tool for this family",
                theme.style(Role::Muted),
            ));
            frame.render_widget(Paragraph::new(head), area);
            return;
        }
        // The rows on one or two lines.
        let rows = self.rows(&tool);
        let mut spans = Vec::new();
        for (i, (name, value)) in rows.iter().enumerate() {
            let text = match (&self.editing, i == self.selected) {
                (Some(field), true) => format!(" {name}={}_ ", field.text()),
                _ => format!(" {name} {value} "),
            };
            let typed = match tool {
                Tool::Current(_) => self.current.set.iter().any(|(n, _)| n == name),
                _ => self.set.iter().any(|(n, _)| n == name),
            };
            let role = if i == self.selected {
                Role::Selection
            } else if typed {
                Role::Changed
            } else {
                Role::Normal
            };
            spans.push(Span::styled(text, theme.style(role)));
        }
        let mut line_spans = Vec::new();
        let mut used = 0;
        for span in spans {
            let w = span.content.chars().count();
            if used + w > width && !line_spans.is_empty() {
                head.push(Line::from(std::mem::take(&mut line_spans)));
                used = 0;
            }
            used += w;
            line_spans.push(span);
        }
        if !line_spans.is_empty() {
            head.push(Line::from(line_spans));
        }
        // The chosen setting's meaning, from the manual.
        if let (Tool::Current(plan), Some((name, _))) = (tool, rows.get(self.selected)) {
            for part in wrap(&self.current.meaning(plan, name), width) {
                head.push(Line::styled(part, theme.style(Role::Muted)));
            }
        }
        let keys = |action| key_label(view.keymap, Context::Tuning, action);
        // The switch to the family's next tool, where it has several.
        let other = if tools(view).len() > 1 {
            format!(" · {} next tool", keys(Action::TuneTool))
        } else {
            String::new()
        };
        // Each key with what it does; the sweep's list is the longest, so
        // its "choose" goes to fit 80 columns.
        let (choose, doing): (&str, &[(Action, &str)]) = match tool {
            Tool::Step(_) => (
                " choose",
                &[
                    (Action::ParameterEdit, "type a value"),
                    (Action::ParameterRefresh, "read gains"),
                    (Action::TuneRun, "run step"),
                    (Action::Cancel, "stop"),
                ],
            ),
            Tool::Current(_) => (
                " choose",
                &[
                    (Action::ParameterEdit, "type"),
                    (Action::ParameterRefresh, "read"),
                    (Action::TuneRun, "watch"),
                    (Action::Cancel, "stop"),
                ],
            ),
            _ => (
                "",
                &[
                    (Action::ParameterEdit, "type"),
                    (Action::TuneRun, "sweep"),
                    (Action::TuneKeepFree, "keep free"),
                    (Action::TuneApply, "send"),
                    (Action::Cancel, "stop"),
                ],
            ),
        };
        let hint = format!(
            "{}/{}{choose} · {}{other}",
            keys(Action::SelectPrevious),
            keys(Action::SelectNext),
            doing
                .iter()
                .map(|(action, what)| format!("{} {what}", keys(*action)))
                .collect::<Vec<_>>()
                .join(" · ")
        );
        head.push(Line::styled(fit(&hint, width), theme.style(Role::Muted)));
        if let Some((role, text)) = &self.message {
            for part in wrap(text, width) {
                head.push(Line::styled(part, theme.style(*role)));
            }
        }
        let (series, scale, titles) = match (tool, Self::axis(view)) {
            (Tool::Step(_), _) => (
                self.step_series(),
                Scale::Values,
                ("ms", "counts from the start"),
            ),
            (Tool::Current(plan), Some((_, info))) => (
                self.current.series(plan.watch(&info).load_full),
                Scale::Percent,
                ("s", "%"),
            ),
            _ => (self.sweep_series(), Scale::FromZero, ("speed", "reading")),
        };
        let plotted = series.iter().any(|(points, ..)| !points.is_empty());
        // The figures (or the sweep's suggestion) under the plot, after
        // the key that names each series by its marker (the legend has no
        // room at 80×24, and a marker reads without colour).
        let mut foot: Vec<Line> = Vec::new();
        match &tool {
            Tool::Step(_) => {
                if let (Some(run), Some((_, info))) = (&self.step, Self::axis(view)) {
                    for text in step_lines(&info, run) {
                        let role = if text.starts_with("TRIPPED") {
                            Role::Error
                        } else {
                            Role::Normal
                        };
                        for part in wrap(&text, width) {
                            foot.push(Line::styled(part, theme.style(role)));
                        }
                    }
                }
            }
            Tool::Sweep(plan) => {
                if let Some(sweep) = &self.sweep {
                    foot.push(Line::styled(
                        fit(
                            &format!(
                                "{}; threshold during the sweep: {}",
                                plan.reading(),
                                sweep
                                    .threshold
                                    .map_or_else(|| "not read".into(), |t| t.to_string())
                            ),
                            width,
                        ),
                        theme.style(Role::Muted),
                    ));
                }
                if let Some(s) = &self.suggestion {
                    for reason in &s.reasons {
                        for part in wrap(reason, width) {
                            foot.push(Line::styled(part, theme.style(Role::Normal)));
                        }
                    }
                    let lines = if s.lines.is_empty() {
                        "no suggestion to set".to_string()
                    } else {
                        format!(
                            "to set it ({}): {}",
                            keys(Action::TuneApply),
                            s.lines.join("; ")
                        )
                    };
                    for part in wrap(&lines, width) {
                        foot.push(Line::styled(part, theme.style(Role::Accent)));
                    }
                } else if self.free.is_some() {
                    foot.push(Line::styled(
                        fit("free sweep kept: run the sweep with the load", width),
                        theme.style(Role::Muted),
                    ));
                }
            }
            Tool::Current(plan) => {
                if let Some((_, info)) = Self::axis(view)
                    && !self.current.samples.is_empty()
                {
                    let key = CurrentView::key_line(plan.watch(&info).load_full);
                    foot.push(Line::styled(fit(&key, width), theme.style(Role::Muted)));
                }
                for text in self.current.figures() {
                    for part in wrap(&text, width) {
                        foot.push(Line::styled(part, theme.style(Role::Normal)));
                    }
                }
            }
            Tool::None => {}
        }
        // The plot needs four rows and its key a line under it; with four
        // rows left (an MCCL step at 80×24) the key goes at the end of the
        // line above the plot where it fits; with fewer (a long
        // suggestion) neither is drawn.
        let room = usize::from(area.height).saturating_sub(head.len() + foot.len());
        let plotted = plotted && room >= 4;
        if plotted && !matches!(tool, Tool::Current(_)) {
            if room >= 5 {
                foot.insert(
                    0,
                    Line::styled(fit(&series_key(&series), width), theme.style(Role::Muted)),
                );
            } else if let Some(above) = head.last_mut() {
                let key = format!("   {}", series_key(&series));
                if above.width() + key.chars().count() <= width {
                    above.push_span(Span::styled(key, theme.style(Role::Muted)));
                }
            }
        }
        let head_h = u16::try_from(head.len()).unwrap_or(u16::MAX);
        let foot_h = u16::try_from(foot.len()).unwrap_or(u16::MAX);
        let [top, middle, bottom] = Layout::vertical([
            Constraint::Length(head_h),
            Constraint::Min(0),
            Constraint::Length(foot_h),
        ])
        .areas(area);
        frame.render_widget(Paragraph::new(head), top);
        // At 80×24 the figures come before the plot.
        frame.render_widget(Paragraph::new(foot), bottom);
        if plotted && middle.height >= 4 {
            frame.render_widget(series_chart(&series, scale, titles, view), middle);
        }
    }

    fn handle_input(&mut self, input: &Input, view: &View) -> Outcome {
        match input {
            Input::Key(key) => self.key(key, view),
            _ => Outcome::Ignored,
        }
    }

    fn activity(&self) -> Option<String> {
        self.running.as_ref().map(|_| "TUNING RUN".to_string())
    }

    fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        match event {
            PaneEvent::Tuned { tag, result } => self.tuned(*tag, result, view),
            PaneEvent::Reply { tag, line, result } if self.apply_tag == Some(*tag) => {
                match result {
                    Ok(_) => self.say(Role::Ok, format!("{line}: done")),
                    Err(e) => {
                        self.apply_tag = None;
                        self.say(Role::Error, format!("{line}: {e}"));
                    }
                }
                Outcome::redraw()
            }
            PaneEvent::Reply {
                result: Err(e),
                line,
                ..
            } => {
                self.say(Role::Error, format!("{line}: {e}"));
                Outcome::redraw()
            }
            PaneEvent::Focused => Outcome::Handled(self.refresh(view, false)),
            PaneEvent::Unfocused => {
                self.confirm = None;
                self.editing = None;
                self.cancel("the pane lost the keyboard")
            }
            PaneEvent::Stopping => {
                self.confirm = None;
                if self.running.take().is_some() {
                    // The emergency stop ended the run's task too.
                    self.say(Role::Emergency, "STOP: every axis");
                    Outcome::redraw()
                } else {
                    Outcome::Ignored
                }
            }
            PaneEvent::Snapshot => {
                let lost = view.session.is_none_or(|s| {
                    matches!(s.link, LinkState::Disconnected { .. } | LinkState::Closed)
                });
                if lost && self.running.is_some() {
                    return self.cancel("the link was lost");
                }
                let axis = view.session.map(|s| (view.module, s.axis));
                if self
                    .running
                    .as_ref()
                    .is_some_and(|r| Some((r.module, r.axis)) != axis)
                {
                    return self.cancel("another axis was chosen");
                }
                if view.focused && !lost {
                    let requests = self.refresh(view, false);
                    if !requests.is_empty() {
                        return Outcome::Handled(requests);
                    }
                }
                Outcome::Ignored
            }
            _ => Outcome::Ignored,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::tuning::StepSample;

    /// A step run from `start` by 100 counts.
    fn run_from(start: f64) -> StepRun {
        let sample = |time: f64, commanded: f64, actual: f64| StepSample {
            time,
            commanded: start + commanded,
            actual: start + actual,
            output: 0.0,
        };
        StepRun {
            gains: Vec::new(),
            samples: vec![sample(0.0, 100.0, 0.0), sample(0.001, 100.0, 90.0)],
            figures: None,
            figures_missing: None,
            tripped: Vec::new(),
            sample_period: 0.001,
        }
    }

    #[test]
    fn the_run_before_lies_over_this_one_though_the_axis_stood_elsewhere() {
        let mut pane = TuningPane::new();
        pane.previous = Some(run_from(0.0));
        pane.step = Some(run_from(1000.0));
        let series = pane.step_series();
        let (before, actual) = (&series[0], &series[2]);
        assert_eq!((before.3, actual.3), ("before", "actual"));
        assert_eq!(before.0, actual.0);
        assert_eq!(actual.0, vec![(0.0, 0.0), (1.0, 90.0)]);
        assert_eq!(series[1].0, vec![(0.0, 100.0), (1.0, 100.0)]);
    }
}
