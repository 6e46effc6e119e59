//! Plots over time of any polled value of any axis (position, target,
//! speed, load, following error: what the session's [`AxisStatus`]
//! carries) and of any axis parameter the technician picks from the
//! family's parameter table (`:plot add X 206`, `:plot add 0 run
//! current`): several series at once, each with its own colour and
//! marker (the mono theme tells them apart by the marker) and named in a
//! legend. Positions share the upper chart, everything else the lower
//! one, over one time window that zooms through a ladder of spans and
//! can be frozen. A parameter the status poll does not read is polled by
//! the session with the slow status items while it is plotted
//! ([`Request::Watch`]); its read line comes from the family's
//! [`crate::protocol::parameters::ParameterSet`]. `:plot csv FILE` writes
//! what was plotted: time, one column per series. The pick key opens a
//! list of the same choices over the plot (the selected axis's status
//! values, then its parameters; typing narrows it), where Enter plots
//! one or stops plotting it, through the same code as `:plot add`.
//!
//! Until the technician picks series, the plot follows the selected axis:
//! its position, target and speed.

mod picker;

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, LegendPosition, Paragraph};

use super::keymap::{Action, Context};
use super::pane::{
    Input, Notice, Outcome, Pane, PaneEvent, Region, Request, Snapshot, View, key_label,
};
use super::theme::Role;
use crate::protocol::parameters::{ParamOp, ParamRow, ParameterSet, Scope};
use crate::session::AxisStatus;
use picker::Picker;

/// The spans the window steps through when zooming.
pub const WINDOWS: &[Duration] = &[
    Duration::from_secs(1),
    Duration::from_secs(2),
    Duration::from_secs(5),
    Duration::from_secs(10),
    Duration::from_secs(20),
    Duration::from_secs(30),
    Duration::from_secs(60),
    Duration::from_secs(120),
    Duration::from_secs(300),
    Duration::from_secs(600),
];

/// The window at start and after a reset.
pub const DEFAULT_WINDOW: Duration = Duration::from_secs(20);

/// Samples kept at most per series: the longest window at a 20 Hz poll,
/// twice over.
const MAX_SAMPLES: usize = 24_000;

/// Redraws per window while the picture still moves (the newest sample
/// has not left the window yet).
const TICKS_PER_WINDOW: u32 = 100;

/// Where "now" comes from: the wall clock, or a test's hand.
pub type Clock = Arc<dyn Fn() -> Instant + Send + Sync>;

/// A value the status poll carries for every axis; which ones, the
/// family says ([`crate::protocol::console::FamilyConsole::status_values`]).
pub use crate::protocol::console::StatusValue;

/// The status values by the names `:plot add` takes.
const STATUS_VALUES: &[(&str, StatusValue)] = &[
    ("position", StatusValue::Position),
    ("target", StatusValue::Target),
    ("speed", StatusValue::Speed),
    ("load", StatusValue::Load),
    ("ferr", StatusValue::FollowingError),
];

impl StatusValue {
    fn name(self) -> &'static str {
        STATUS_VALUES
            .iter()
            .find(|(_, v)| *v == self)
            .map_or("?", |(name, _)| name)
    }

    fn of(self, status: &AxisStatus) -> Option<i64> {
        match self {
            StatusValue::Position => status.position,
            StatusValue::Target => status.target,
            StatusValue::Speed => status.speed,
            StatusValue::Load => status.load,
            StatusValue::FollowingError => status.following_error,
        }
    }

    /// Positions share the upper chart.
    fn is_position(self) -> bool {
        matches!(self, StatusValue::Position | StatusValue::Target)
    }
}

/// What a series plots.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Quantity {
    Status(StatusValue),
    /// An axis parameter, read by its line (`GAP 206, 0`).
    Parameter {
        number: u16,
        name: String,
        line: String,
    },
}

impl Quantity {
    fn label(&self) -> String {
        match self {
            Quantity::Status(value) => value.name().to_string(),
            Quantity::Parameter { number, name, .. } => format!("{number} {name}"),
        }
    }
}

/// One plotted series: an axis's quantity and its readings.
#[derive(Debug, Clone)]
struct Series {
    axis: usize,
    axis_name: String,
    quantity: Quantity,
    samples: VecDeque<(Instant, i64)>,
}

impl Series {
    fn new(axis: usize, axis_name: &str, quantity: Quantity) -> Series {
        Series {
            axis,
            axis_name: axis_name.to_string(),
            quantity,
            samples: VecDeque::new(),
        }
    }

    fn name(&self) -> String {
        format!("{} {}", self.axis_name, self.quantity.label())
    }

    fn reading(&self, status: &AxisStatus) -> Option<i64> {
        match &self.quantity {
            Quantity::Status(value) => value.of(status),
            Quantity::Parameter { line, .. } => status
                .watched
                .iter()
                .find(|w| &w.line == line)
                .and_then(|w| w.value),
        }
    }

    fn in_upper_chart(&self) -> bool {
        matches!(self.quantity, Quantity::Status(v) if v.is_position())
    }
}

/// Colours and markers in turn: the n-th series takes the n-th of each.
const LOOKS: &[(Role, Marker, &str)] = &[
    (Role::Plot1, Marker::Braille, "⠒"),
    (Role::Plot3, Marker::Dot, "•"),
    (Role::Plot2, Marker::Block, "█"),
    (Role::Plot4, Marker::Bar, "▄"),
    (Role::Plot1, Marker::HalfBlock, "▀"),
];

/// A chart's value range and the labels of its ends.
type Bounds = ([f64; 2], [String; 2]);

/// The plot pane.
pub struct PlotPane {
    clock: Clock,
    series: Vec<Series>,
    /// The technician picked the series (`:plot add`, `:plot clear`);
    /// until then they follow the selected axis.
    picked: bool,
    window: Duration,
    /// The moment the view froze at.
    paused: Option<Instant>,
    /// The module plotted: another one (or another link) starts over.
    following: Option<(String, u8, usize)>,
    /// A redraw is asked for already.
    ticking: bool,
    next_tag: u64,
    /// What the last `:plot` command did, for the head line.
    note: Option<String>,
    /// The list of what can be plotted, while open.
    picker: Option<Picker>,
}

impl Default for PlotPane {
    fn default() -> Self {
        PlotPane::new()
    }
}

impl PlotPane {
    pub fn new() -> PlotPane {
        PlotPane::with_clock(Arc::new(Instant::now))
    }

    pub fn with_clock(clock: Clock) -> PlotPane {
        PlotPane {
            clock,
            series: Vec::new(),
            picked: false,
            window: DEFAULT_WINDOW,
            paused: None,
            following: None,
            ticking: false,
            next_tag: 1,
            note: None,
            picker: None,
        }
    }

    /// The time span shown.
    pub fn window(&self) -> Duration {
        self.window
    }

    pub fn is_paused(&self) -> bool {
        self.paused.is_some()
    }

    /// Samples kept, over all series.
    pub fn len(&self) -> usize {
        self.series.iter().map(|s| s.samples.len()).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The names of the series plotted, in legend order.
    pub fn series_names(&self) -> Vec<String> {
        self.series.iter().map(Series::name).collect()
    }

    fn zoom(&mut self, action: Action) {
        let at = WINDOWS
            .iter()
            .position(|w| *w >= self.window)
            .unwrap_or(WINDOWS.len() - 1);
        self.window = match action {
            Action::PlotZoomIn => WINDOWS[at.saturating_sub(1)],
            Action::PlotZoomOut => WINDOWS[(at + 1).min(WINDOWS.len() - 1)],
            _ => DEFAULT_WINDOW,
        };
    }

    /// The selected axis's position, target and speed, while nothing is
    /// picked.
    fn follow_selected(&mut self, session: &Snapshot) {
        let Some(axis) = session.selected_axis() else {
            return;
        };
        let wanted = [
            StatusValue::Position,
            StatusValue::Target,
            StatusValue::Speed,
        ];
        let same = self.series.len() == wanted.len()
            && self
                .series
                .iter()
                .zip(wanted)
                .all(|(s, v)| s.axis == session.axis && s.quantity == Quantity::Status(v));
        if !same {
            self.series = wanted
                .into_iter()
                .map(|v| Series::new(session.axis, axis.name, Quantity::Status(v)))
                .collect();
        }
    }

    /// Take each series's value from the snapshot; true if one changed.
    fn sample(&mut self, view: &View) -> bool {
        let Some(session) = view.session else {
            return false;
        };
        let module = (session.link_name.clone(), session.address, 0);
        if self.following.as_ref() != Some(&module) {
            // Another module: its series are not these.
            if self.following.is_some() {
                self.series.clear();
                self.picked = false;
                self.picker = None;
            }
            self.following = Some(module);
        }
        if !self.picked {
            self.follow_selected(session);
        }
        let at = (self.clock)();
        let oldest = at.checked_sub(*WINDOWS.last().unwrap_or(&DEFAULT_WINDOW));
        let mut changed = false;
        for series in &mut self.series {
            let Some(value) = session
                .status
                .get(series.axis)
                .and_then(|s| series.reading(s))
            else {
                continue;
            };
            if series.samples.back().is_some_and(|&(_, v)| v == value) {
                continue;
            }
            series.samples.push_back((at, value));
            changed = true;
            while series.samples.len() > MAX_SAMPLES
                || series
                    .samples
                    .front()
                    .zip(oldest)
                    .is_some_and(|(&(t, _), oldest)| t < oldest)
            {
                series.samples.pop_front();
            }
        }
        changed
    }

    /// While the newest sample is inside the window the picture moves
    /// with time: ask to be woken to redraw it.
    fn tick(&mut self) -> Outcome {
        let now = (self.clock)();
        let newest = self
            .series
            .iter()
            .filter_map(|s| s.samples.back().map(|&(t, _)| t))
            .max();
        let moving = self.paused.is_none()
            && newest.is_some_and(|t| now.saturating_duration_since(t) <= self.window);
        if !moving || self.ticking {
            return Outcome::redraw();
        }
        self.ticking = true;
        let tag = self.next_tag;
        self.next_tag += 1;
        let after = (self.window / TICKS_PER_WINDOW).max(Duration::from_millis(50));
        Outcome::request(Request::WakeAfter { after, tag })
    }

    /// Points of one series in the window: seconds before `now`
    /// (negative) and the value, held until the next sample and up to
    /// `now`.
    fn points(&self, now: Instant, samples: &VecDeque<(Instant, i64)>) -> Vec<(f64, f64)> {
        let start = now.checked_sub(self.window);
        let x = |at: Instant| {
            if at >= now {
                0.0
            } else {
                -now.duration_since(at).as_secs_f64()
            }
        };
        let mut points = Vec::new();
        let mut held: Option<i64> = None;
        for &(at, v) in samples {
            if at > now {
                break;
            }
            if start.is_some_and(|s| at < s) {
                held = Some(v);
                continue;
            }
            if let Some(h) = held.take() {
                // The value that was there when the window begins.
                points.push((-self.window.as_secs_f64(), h as f64));
            }
            if let Some(&(_, last)) = points.last() {
                // A step, not a slope: the value held until it changed.
                points.push((x(at), last));
            }
            points.push((x(at), v as f64));
        }
        if let Some(h) = held {
            points.push((-self.window.as_secs_f64(), h as f64));
        }
        if let Some(&(_, last)) = points.last() {
            points.push((0.0, last));
        }
        points
    }

    /// The value range of some point sets, with a margin, and its labels.
    fn bounds(signals: &[Vec<(f64, f64)>]) -> Bounds {
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        for points in signals {
            for &(_, y) in points {
                low = low.min(y);
                high = high.max(y);
            }
        }
        if !low.is_finite() || !high.is_finite() {
            (low, high) = (0.0, 1.0);
        }
        let margin = ((high - low) * 0.05).max(1.0);
        let (low, high) = (low - margin, high + margin);
        ([low, high], [format!("{low:.0}"), format!("{high:.0}")])
    }

    /// The chart of series `members` (indices into `self.series`);
    /// `label_width` pads the value labels so that the time axes of the
    /// two charts line up.
    fn chart<'a>(
        &self,
        members: &[usize],
        points: &'a [Vec<(f64, f64)>],
        view: &View,
        label_width: usize,
        show_time: bool,
    ) -> Chart<'a> {
        let theme = view.theme;
        let window = self.window.as_secs_f64();
        let x_labels: Vec<Span> = if show_time {
            vec![
                Span::raw(format!("-{}", span_label(self.window))),
                Span::raw(format!("-{}", span_label(self.window / 2))),
                Span::raw("now"),
            ]
        } else {
            Vec::new()
        };
        let mine: Vec<Vec<(f64, f64)>> = members
            .iter()
            .filter_map(|&i| points.get(i).cloned())
            .collect();
        let (bounds, labels) = Self::bounds(&mine);
        // Named after what it holds: `position (raw)`, `speed (raw)`.
        let labels_of: Vec<String> = members
            .iter()
            .filter_map(|&i| self.series.get(i))
            .map(|s| match &s.quantity {
                Quantity::Status(v) if v.is_position() => "position".to_string(),
                other => other.label(),
            })
            .collect();
        let unit = self
            .chart_unit(members, view)
            .unwrap_or_else(|| "raw".to_string());
        let title = match labels_of.first() {
            Some(first) if labels_of.iter().all(|l| l == first) => format!("{first} ({unit})"),
            _ => unit,
        };
        let y_labels: Vec<Span> = labels
            .iter()
            .map(|l| Span::raw(format!("{l:>label_width$}")))
            .collect();
        let sets = members
            .iter()
            .filter_map(|&i| Some((i, self.series.get(i)?, points.get(i)?)))
            .map(|(i, series, points)| {
                let (role, marker, glyph) = LOOKS[i % LOOKS.len()];
                Dataset::default()
                    .name(format!("{glyph} {}", series.name()))
                    .marker(marker)
                    .graph_type(GraphType::Line)
                    .style(theme.style(role))
                    .data(points)
            })
            .collect();
        Chart::new(sets)
            .style(theme.style(Role::Normal))
            .x_axis(
                Axis::default()
                    .bounds([-window, 0.0])
                    .labels(x_labels)
                    .style(theme.style(Role::PlotAxes)),
            )
            .y_axis(
                Axis::default()
                    .title(Span::styled(title, theme.style(Role::Title)))
                    .bounds(bounds)
                    .labels(y_labels)
                    .style(theme.style(Role::PlotAxes)),
            )
            .legend_position(Some(LegendPosition::TopLeft))
            .hidden_legend_constraints((Constraint::Ratio(2, 3), Constraint::Ratio(2, 3)))
    }

    /// `:plot ARGS`: what to ask for, said in the head line and in the
    /// command pane.
    pub fn command(&mut self, args: &str, view: &View) -> Outcome {
        let result = self.apply(args, view);
        self.report(result)
    }

    /// Say what a `:plot` command or the picker did, in the head line and
    /// in the command pane, and pass on its requests.
    fn report(&mut self, result: Result<(String, Vec<Request>), String>) -> Outcome {
        let notice = match &result {
            Ok((said, _)) => Notice::info(said.clone()),
            Err(message) => Notice::error(message.clone()),
        };
        self.note = Some(match &result {
            Ok((said, _)) => said.clone(),
            Err(message) => message.clone(),
        });
        let mut requests = vec![Request::Say(notice)];
        if let Ok((_, more)) = result {
            requests.extend(more);
        }
        Outcome::Handled(requests)
    }

    fn apply(&mut self, args: &str, view: &View) -> Result<(String, Vec<Request>), String> {
        let args = args.trim();
        let (verb, rest) = args
            .split_once(char::is_whitespace)
            .map_or((args, ""), |(v, r)| (v, r.trim()));
        const USAGE: &str = ":plot add AXIS VALUE, :plot remove AXIS VALUE, :plot clear or :plot csv [--force] FILE";
        match verb {
            "add" | "remove" => {
                let session = view.session.ok_or("not connected: nothing to plot")?;
                let (axis, quantity) = find_quantity(session, rest)?;
                if verb == "add" {
                    self.add(session, axis, quantity)
                } else {
                    self.remove(session, axis, quantity)
                }
            }
            "clear" => {
                let requests = self.unwatch_all();
                self.series.clear();
                self.picked = true;
                Ok(("plot cleared".into(), requests))
            }
            "csv" if !crate::files::force_option(rest).1.is_empty() => {
                let (existing, rest) = crate::files::force_option(rest);
                let text = self.csv();
                let rows = text.lines().count().saturating_sub(1);
                crate::files::save(rest, text.as_bytes(), existing)
                    .map_err(|e| format!("cannot write {rest}: {e}"))?;
                Ok((
                    format!(
                        "{rows} rows of {} series written to {rest}",
                        self.series.len()
                    ),
                    Vec::new(),
                ))
            }
            "csv" => Err(":plot csv needs a file name".into()),
            "" => Err(USAGE.to_string()),
            other => Err(format!("no `:plot {other}`: {USAGE}")),
        }
    }

    /// Plot `quantity` of `axis` (its parameter polled meanwhile): what
    /// `:plot add` and the picker do.
    fn add(
        &mut self,
        session: &Snapshot,
        axis: usize,
        quantity: Quantity,
    ) -> Result<(String, Vec<Request>), String> {
        let axis_name = session.axes.get(axis).map_or("?", |a| a.name);
        let name = format!("{axis_name} {}", quantity.label());
        if !self.picked {
            self.series.clear();
            self.picked = true;
        }
        if self.plots(axis, &quantity) {
            return Ok((format!("{name} is plotted already"), Vec::new()));
        }
        let requests = watch(axis, &quantity, true);
        self.series.push(Series::new(axis, axis_name, quantity));
        Ok((format!("plotting {name}"), requests))
    }

    /// Stop plotting `quantity` of `axis`: what `:plot remove` and the
    /// picker do.
    fn remove(
        &mut self,
        session: &Snapshot,
        axis: usize,
        quantity: Quantity,
    ) -> Result<(String, Vec<Request>), String> {
        let axis_name = session.axes.get(axis).map_or("?", |a| a.name);
        let name = format!("{axis_name} {}", quantity.label());
        let at = self
            .series
            .iter()
            .position(|s| s.axis == axis && s.quantity == quantity)
            .ok_or_else(|| format!("{name} is not plotted"))?;
        self.picked = true;
        self.series.remove(at);
        Ok((
            format!("{name} no longer plotted"),
            watch(axis, &quantity, false),
        ))
    }

    /// Whether `quantity` of `axis` is plotted.
    fn plots(&self, axis: usize, quantity: &Quantity) -> bool {
        self.series
            .iter()
            .any(|s| s.axis == axis && &s.quantity == quantity)
    }

    /// A status series in its axis's own unit, where mechanics are in
    /// force and the family's law converts it with what is known without
    /// reading (positions: microsteps from the mechanics; SIXpack 2 speeds:
    /// the settings written): the factor from raw and the unit (`mm/s`).
    fn axis_unit_of(&self, series: &Series, view: &View) -> Option<(f64, String)> {
        let session = view.session?;
        let quantity = match series.quantity {
            Quantity::Status(StatusValue::Position | StatusValue::Target) => {
                crate::protocol::units::Quantity::Position
            }
            Quantity::Status(StatusValue::Speed) => crate::protocol::units::Quantity::Speed,
            _ => return None,
        };
        let law = session.family.console.units()?;
        let axis = session.axes.get(series.axis)?.number;
        let mechanics = session.mechanics.get(axis)?;
        let value_of = |scope: Scope, number: u16| session.settings.value(scope, number);
        let factor =
            crate::protocol::units::to_units(law, mechanics, axis, quantity, 1.0, &value_of)
                .ok()?;
        Some((factor, quantity.unit_text(&mechanics.unit)))
    }

    /// The unit every series of a chart shows in, when all can be in the
    /// same axis unit (else the chart stays raw).
    fn chart_unit(&self, members: &[usize], view: &View) -> Option<String> {
        let units: Vec<Option<(f64, String)>> = members
            .iter()
            .filter_map(|&i| self.series.get(i))
            .map(|s| self.axis_unit_of(s, view))
            .collect();
        let first = units.first()?.as_ref()?.1.clone();
        units
            .iter()
            .all(|u| u.as_ref().is_some_and(|(_, unit)| *unit == first))
            .then_some(first)
    }

    /// The charts of the series in `body` (under the head line).
    fn draw_charts(&self, frame: &mut Frame, body: Rect, view: &View, now: Instant) {
        if body.height < 4 || self.series.is_empty() {
            return;
        }
        let (upper, lower): (Vec<usize>, Vec<usize>) =
            (0..self.series.len()).partition(|&i| self.series[i].in_upper_chart());
        // A chart whose series all have their axis's unit is drawn in it.
        let in_units = [self.chart_unit(&upper, view), self.chart_unit(&lower, view)];
        let points: Vec<Vec<(f64, f64)>> = self
            .series
            .iter()
            .map(|s| {
                let chart = usize::from(!s.in_upper_chart());
                let factor = in_units[chart]
                    .as_ref()
                    .and_then(|_| self.axis_unit_of(s, view))
                    .map_or(1.0, |(factor, _)| factor);
                self.points(now, &s.samples)
                    .into_iter()
                    .map(|(t, y)| (t, y * factor))
                    .collect()
            })
            .collect();
        let label_width = [&upper, &lower]
            .iter()
            .filter(|m| !m.is_empty())
            .flat_map(|m| {
                let mine: Vec<Vec<(f64, f64)>> =
                    m.iter().filter_map(|&i| points.get(i).cloned()).collect();
                Self::bounds(&mine).1
            })
            .map(|l| l.len())
            .max()
            .unwrap_or(1);
        match (upper.is_empty(), lower.is_empty()) {
            (false, false) => {
                let [top, bottom] =
                    Layout::vertical([Constraint::Percentage(55), Constraint::Percentage(45)])
                        .areas(body);
                frame.render_widget(self.chart(&upper, &points, view, label_width, false), top);
                frame.render_widget(self.chart(&lower, &points, view, label_width, true), bottom);
            }
            (false, true) => {
                frame.render_widget(self.chart(&upper, &points, view, label_width, true), body)
            }
            _ => frame.render_widget(self.chart(&lower, &points, view, label_width, true), body),
        }
    }

    /// A key or paste while the picker is open: Enter plots the chosen
    /// value or stops plotting it, Esc closes, the rest moves or filters.
    fn picker_input(&mut self, input: &Input, view: &View) -> Outcome {
        let Some(picker) = self.picker.as_mut() else {
            return Outcome::Ignored;
        };
        let key = match input {
            Input::Key(key) => key,
            Input::Paste(text) => {
                picker.paste(text);
                return Outcome::redraw();
            }
            Input::Mouse(_) => return Outcome::Ignored,
        };
        let action = view.keymap.action_for(Context::Command, key);
        match action {
            Some(Action::Cancel) => {
                self.picker = None;
                Outcome::redraw()
            }
            Some(Action::Submit) => {
                let (axis, chosen) = (picker.axis, picker.chosen());
                let Some(quantity) = chosen else {
                    return Outcome::Ignored;
                };
                let Some(session) = view.session else {
                    return self.report(Err("not connected: nothing to plot".into()));
                };
                let result = if self.plots(axis, &quantity) {
                    self.remove(session, axis, quantity)
                } else {
                    self.add(session, axis, quantity)
                };
                self.report(result)
            }
            _ if picker.key(action, key) => Outcome::redraw(),
            _ => Outcome::Ignored,
        }
    }

    /// Stop polling every plotted parameter.
    fn unwatch_all(&self) -> Vec<Request> {
        self.series
            .iter()
            .flat_map(|s| watch(s.axis, &s.quantity, false))
            .collect()
    }

    /// What was plotted as CSV: seconds since the first sample, then one
    /// column per series with the value it held at that moment (empty
    /// before its first reading); a row for every moment a value changed.
    pub fn csv(&self) -> String {
        let mut text = String::from("time_s");
        for series in &self.series {
            text.push(',');
            text.push_str(&csv_field(&series.name()));
        }
        text.push('\n');
        let mut moments: Vec<Instant> = self
            .series
            .iter()
            .flat_map(|s| s.samples.iter().map(|&(t, _)| t))
            .collect();
        moments.sort();
        moments.dedup();
        let Some(&first) = moments.first() else {
            return text;
        };
        let mut next = vec![0usize; self.series.len()];
        let mut held: Vec<Option<i64>> = vec![None; self.series.len()];
        for at in moments {
            for (n, series) in self.series.iter().enumerate() {
                while let Some(&(t, v)) = series.samples.get(next[n]) {
                    if t > at {
                        break;
                    }
                    held[n] = Some(v);
                    next[n] += 1;
                }
            }
            text.push_str(&format!("{:.3}", at.duration_since(first).as_secs_f64()));
            for value in &held {
                text.push(',');
                if let Some(v) = value {
                    text.push_str(&v.to_string());
                }
            }
            text.push('\n');
        }
        text
    }
}

/// Poll a plotted parameter while it is plotted (a status value is
/// polled anyway).
fn watch(axis: usize, quantity: &Quantity, on: bool) -> Vec<Request> {
    match quantity {
        Quantity::Parameter { line, .. } => vec![Request::Watch {
            axis,
            line: line.clone(),
            on,
            fast: false,
        }],
        Quantity::Status(_) => Vec::new(),
    }
}

/// A CSV field, quoted when it holds a comma or a quote.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// `AXIS VALUE` of `:plot add`: the axis (number or name) and a status
/// value's name or an axis parameter of the family's table (number or
/// name, with its read line).
fn find_quantity(session: &Snapshot, text: &str) -> Result<(usize, Quantity), String> {
    let (axis_text, value) = text
        .split_once(char::is_whitespace)
        .map(|(a, v)| (a, v.trim()))
        .ok_or("which axis and value? e.g. `:plot add 0 load` or `:plot add 0 206`")?;
    let axis = session
        .axes
        .iter()
        .position(|a| axis_text.parse::<u8>().is_ok_and(|n| n == a.number))
        .or_else(|| {
            session
                .axes
                .iter()
                .position(|a| a.name.eq_ignore_ascii_case(axis_text))
        })
        .ok_or_else(|| format!("no axis `{axis_text}` on this module"))?;
    if let Some((name, v)) = STATUS_VALUES
        .iter()
        .find(|(name, _)| name.eq_ignore_ascii_case(value))
    {
        if !session.family.console.status_values().contains(v) {
            return Err(format!(
                "{} modules report no {name}: plot one of {}",
                session.family.name,
                status_names(session)
            ));
        }
        return Ok((axis, Quantity::Status(*v)));
    }
    let (params, rows) = axis_parameters(session, axis)?;
    let row = rows
        .iter()
        .find(|r| {
            value.parse::<u16>().is_ok_and(|n| n == r.number) || r.name.eq_ignore_ascii_case(value)
        })
        .ok_or_else(|| {
            format!(
                "`{value}` is none of {} nor a parameter of {}",
                status_names(session),
                session.axes.get(axis).map_or("?", |a| a.name)
            )
        })?;
    Ok((axis, parameter_quantity(params, row)?))
}

/// Everything axis `axis` can plot, as `:plot add` finds it: the status
/// values the family reads, then the axis parameters of the family's
/// table that can be read (a write-only one has no reading to plot).
fn plottable(session: &Snapshot, axis: usize) -> Vec<Quantity> {
    let read = session.family.console.status_values();
    let mut all: Vec<Quantity> = STATUS_VALUES
        .iter()
        .filter(|(_, v)| read.contains(v))
        .map(|&(_, v)| Quantity::Status(v))
        .collect();
    if let Ok((params, rows)) = axis_parameters(session, axis) {
        all.extend(
            rows.iter()
                .filter_map(|row| parameter_quantity(params, row).ok()),
        );
    }
    all
}

/// The family's parameter set and the parameters of axis `axis` in it.
fn axis_parameters(
    session: &Snapshot,
    axis: usize,
) -> Result<(&'static dyn ParameterSet, Vec<ParamRow>), String> {
    let info = session.axes.get(axis).ok_or("no such axis")?;
    let params = session.family.console.parameters().ok_or_else(|| {
        format!(
            "{} has no parameter table: plot one of {}",
            session.family.name,
            status_names(session)
        )
    })?;
    let rows = params
        .tables(info.number)
        .into_iter()
        .flat_map(|t| t.rows)
        .filter(|r| r.scope == Scope::Axis(info.number))
        .collect();
    Ok((params, rows))
}

/// A parameter as a series: its read line from the family's set.
fn parameter_quantity(params: &dyn ParameterSet, row: &ParamRow) -> Result<Quantity, String> {
    let line = params
        .line(row, ParamOp::Read)
        .map_err(|e| format!("cannot read {}: {e}", row.name))?;
    Ok(Quantity::Parameter {
        number: row.number,
        name: row.name.clone(),
        line,
    })
}

/// The names of the status values `session`'s family reads.
fn status_names(session: &Snapshot) -> String {
    let read = session.family.console.status_values();
    STATUS_VALUES
        .iter()
        .filter(|(_, v)| read.contains(v))
        .map(|(name, _)| *name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// "20 s", "2 min", "500 ms".
fn span_label(span: Duration) -> String {
    let s = span.as_secs_f64();
    if s >= 120.0 {
        format!("{:.0} min", s / 60.0)
    } else if s >= 1.0 {
        format!("{s:.0} s")
    } else {
        format!("{:.0} ms", s * 1000.0)
    }
}

impl Pane for PlotPane {
    fn name(&self) -> &'static str {
        "plot"
    }

    /// While the picker is open keys are looked up as on the command
    /// line, so that letters are filter text (the vim keymap's `q` does
    /// not quit in the middle of a filter).
    fn context(&self) -> Context {
        if self.picker.is_some() {
            Context::Command
        } else {
            Context::Plot
        }
    }

    fn title(&self, _view: &View) -> String {
        if self.paused.is_some() {
            "Plot (frozen)".into()
        } else {
            "Plot".into()
        }
    }

    fn region(&self) -> Region {
        Region::Side
    }

    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        if area.height == 0 || area.width == 0 {
            return;
        }
        let theme = view.theme;
        let now = self.paused.unwrap_or_else(|| (self.clock)());
        let key = |action| key_label(view.keymap, Context::Plot, action);
        let mut status = format!(
            "last {}{} · {} pick · {} {} in/out · {} reset · {} freeze · :plot add AXIS VALUE",
            span_label(self.window),
            if self.paused.is_some() {
                " · FROZEN"
            } else {
                ""
            },
            key(Action::PlotPick),
            key(Action::PlotZoomIn),
            key(Action::PlotZoomOut),
            key(Action::PlotZoomReset),
            key(Action::PlotPause),
        );
        if let Some(note) = &self.note {
            status = format!("{note} · {status}");
        }
        match view.session {
            None => status = "not connected".into(),
            Some(session) if self.series.is_empty() => {
                status = format!(
                    "nothing plotted: {} picks, or :plot add AXIS VALUE ({})",
                    key(Action::PlotPick),
                    status_names(session)
                );
            }
            Some(_) => {}
        }
        let [head, body] =
            Layout::vertical([Constraint::Length(1), Constraint::Min(0)]).areas(area);
        frame.render_widget(
            Paragraph::new(Line::styled(status, theme.style(Role::Muted))),
            head,
        );
        self.draw_charts(frame, body, view, now);
        if let Some(mut picker) = self.picker.take() {
            // Over the charts, the head line with its keys left visible.
            let axis = picker.axis;
            picker.render(frame, body, view, |q| self.plots(axis, q));
            self.picker = Some(picker);
        }
    }

    fn handle_input(&mut self, input: &Input, view: &View) -> Outcome {
        if self.picker.is_some() {
            return self.picker_input(input, view);
        }
        let Input::Key(key) = input else {
            return Outcome::Ignored;
        };
        match view.keymap.action_for(Context::Plot, key) {
            Some(action @ (Action::PlotZoomIn | Action::PlotZoomOut | Action::PlotZoomReset)) => {
                self.zoom(action);
                self.tick()
            }
            Some(Action::PlotPause) => {
                self.paused = match self.paused {
                    Some(_) => None,
                    None => Some((self.clock)()),
                };
                self.tick()
            }
            Some(Action::PlotPick) => {
                let Some(session) = view.session else {
                    return self.report(Err("not connected: nothing to plot".into()));
                };
                let axis = session.axis;
                let axis_name = session.axes.get(axis).map_or("?", |a| a.name);
                self.picker = Some(Picker::new(axis, axis_name, plottable(session, axis)));
                Outcome::redraw()
            }
            _ => Outcome::Ignored,
        }
    }
    fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        match event {
            // Sampled always; behind a tab nothing asks for refreshes.
            PaneEvent::Snapshot => {
                if self.sample(view) && self.paused.is_none() && view.shown {
                    self.tick()
                } else {
                    Outcome::Ignored
                }
            }
            PaneEvent::Wake { .. } => {
                self.ticking = false;
                if view.shown {
                    self.tick()
                } else {
                    Outcome::Ignored
                }
            }
            PaneEvent::Plot(args) => self.command(args, view),
            _ => Outcome::Ignored,
        }
    }
}

#[cfg(test)]
mod tests;
