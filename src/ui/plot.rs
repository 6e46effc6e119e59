//! Plots of the selected axis over time: position (with its target) and
//! speed, from the session's status snapshots, in two charts sharing one
//! time window. The window zooms in and out through a ladder of spans and
//! can be frozen. Each signal has its own marker as well as its colour,
//! so the mono theme tells them apart too.

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Paragraph};

use super::keymap::{Action, Context};
use super::pane::{Input, Outcome, Pane, PaneEvent, Region, Request, View, key_label};
use super::theme::Role;

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

/// Samples kept at most: the longest window at a 20 Hz poll, twice over.
const MAX_SAMPLES: usize = 24_000;

/// Redraws per window while the picture still moves (the newest sample
/// has not left the window yet).
const TICKS_PER_WINDOW: u32 = 100;

/// Where "now" comes from: the wall clock, or a test's hand.
pub type Clock = Arc<dyn Fn() -> Instant + Send + Sync>;

/// One reading of the axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Sample {
    at: Instant,
    position: Option<i64>,
    target: Option<i64>,
    speed: Option<i64>,
}

/// One line of a chart: its name, points, marker and colour.
struct Signal<'a> {
    name: &'a str,
    points: &'a [(f64, f64)],
    marker: Marker,
    role: Role,
}

/// A chart's value range and the labels of its ends.
type Bounds = ([f64; 2], [String; 2]);

/// The plot pane.
pub struct PlotPane {
    clock: Clock,
    samples: VecDeque<Sample>,
    window: Duration,
    /// The moment the view froze at.
    paused: Option<Instant>,
    /// The axis being plotted: another one (or another link) starts over.
    following: Option<(String, u8, usize)>,
    /// A redraw is asked for already.
    ticking: bool,
    next_tag: u64,
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
            samples: VecDeque::new(),
            window: DEFAULT_WINDOW,
            paused: None,
            following: None,
            ticking: false,
            next_tag: 1,
        }
    }

    /// The time span shown.
    pub fn window(&self) -> Duration {
        self.window
    }

    pub fn is_paused(&self) -> bool {
        self.paused.is_some()
    }

    /// Samples kept.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
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

    /// Take the selected axis's values from the snapshot; true if they
    /// changed.
    fn sample(&mut self, view: &View) -> bool {
        let Some(session) = view.session else {
            return false;
        };
        let following = (session.link_name.clone(), session.address, session.axis);
        if self.following.as_ref() != Some(&following) {
            self.samples.clear();
            self.following = Some(following);
        }
        let Some(status) = session.status.get(session.axis) else {
            return false;
        };
        let at = (self.clock)();
        let sample = Sample {
            at,
            position: status.position,
            target: status.target,
            speed: status.speed,
        };
        let same = self.samples.back().is_some_and(|last| {
            (last.position, last.target, last.speed)
                == (sample.position, sample.target, sample.speed)
        });
        if same {
            return false;
        }
        self.samples.push_back(sample);
        let oldest = at.checked_sub(*WINDOWS.last().unwrap_or(&DEFAULT_WINDOW));
        while self.samples.len() > MAX_SAMPLES
            || self
                .samples
                .front()
                .zip(oldest)
                .is_some_and(|(s, oldest)| s.at < oldest)
        {
            self.samples.pop_front();
        }
        true
    }

    /// While the newest sample is inside the window the picture moves
    /// with time: ask to be woken to redraw it.
    fn tick(&mut self) -> Outcome {
        let now = (self.clock)();
        let moving = self.paused.is_none()
            && self
                .samples
                .back()
                .is_some_and(|s| now.saturating_duration_since(s.at) <= self.window);
        if !moving || self.ticking {
            return Outcome::redraw();
        }
        self.ticking = true;
        let tag = self.next_tag;
        self.next_tag += 1;
        let after = (self.window / TICKS_PER_WINDOW).max(Duration::from_millis(50));
        Outcome::request(Request::WakeAfter { after, tag })
    }

    /// Points of one signal in the window: seconds before `now` (negative)
    /// and the value, held until the next sample and up to `now`.
    fn points(&self, now: Instant, value: impl Fn(&Sample) -> Option<i64>) -> Vec<(f64, f64)> {
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
        for sample in &self.samples {
            if sample.at > now {
                break;
            }
            let Some(v) = value(sample) else {
                continue;
            };
            let before = start.is_some_and(|s| sample.at < s);
            if before {
                held = Some(v);
                continue;
            }
            if let Some(h) = held.take() {
                // The value that was there when the window begins.
                points.push((-self.window.as_secs_f64(), h as f64));
            }
            if let Some(&(_, last)) = points.last() {
                // A step, not a slope: the value held until it changed.
                points.push((x(sample.at), last));
            }
            points.push((x(sample.at), v as f64));
        }
        if let Some(h) = held {
            points.push((-self.window.as_secs_f64(), h as f64));
        }
        if let Some(&(_, last)) = points.last() {
            points.push((0.0, last));
        }
        points
    }

    /// The value range of some signals, with a margin, and its labels.
    fn bounds(signals: &[&[(f64, f64)]]) -> Bounds {
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        for points in signals {
            for &(_, y) in points.iter() {
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

    /// One chart; `label_width` pads the value labels so that the time
    /// axes of the two charts line up.
    fn chart<'a>(
        &self,
        title: &'a str,
        signals: Vec<Signal<'a>>,
        view: &View,
        (bounds, labels): Bounds,
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
        let y_labels: Vec<Span> = labels
            .iter()
            .map(|l| Span::raw(format!("{l:>label_width$}")))
            .collect();
        let sets = signals
            .into_iter()
            .map(|signal| {
                Dataset::default()
                    .name(signal.name)
                    .marker(signal.marker)
                    .graph_type(GraphType::Line)
                    .style(theme.style(signal.role))
                    .data(signal.points)
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
            .hidden_legend_constraints((Constraint::Ratio(1, 2), Constraint::Ratio(1, 2)))
    }
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

    fn context(&self) -> Context {
        Context::Plot
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
        let axis = view
            .session
            .and_then(|s| s.selected_axis())
            .map_or("no axis", |a| a.name);
        let mut status = format!(
            "{axis} · last {}{} · {} {} in/out · {} reset · {} freeze",
            span_label(self.window),
            if self.paused.is_some() {
                " · FROZEN"
            } else {
                ""
            },
            key(Action::PlotZoomIn),
            key(Action::PlotZoomOut),
            key(Action::PlotZoomReset),
            key(Action::PlotPause),
        );
        if view.session.is_none() {
            status = "not connected".into();
        }
        let [head, body] =
            Layout::vertical([Constraint::Length(1), Constraint::Min(0)]).areas(area);
        frame.render_widget(
            Paragraph::new(Line::styled(status, theme.style(Role::Muted))),
            head,
        );
        if body.height < 4 {
            return;
        }
        let position = self.points(now, |s| s.position);
        let target = self.points(now, |s| s.target);
        let speed = self.points(now, |s| s.speed);
        let [top, bottom] =
            Layout::vertical([Constraint::Percentage(55), Constraint::Percentage(45)]).areas(body);
        let position_bounds = Self::bounds(&[&position, &target]);
        let speed_bounds = Self::bounds(&[&speed]);
        let label_width = position_bounds
            .1
            .iter()
            .chain(speed_bounds.1.iter())
            .map(String::len)
            .max()
            .unwrap_or(1);
        let position_chart = self.chart(
            "position (raw)",
            vec![
                Signal {
                    name: "position",
                    points: &position,
                    marker: Marker::Braille,
                    role: Role::Plot1,
                },
                Signal {
                    name: "target •",
                    points: &target,
                    marker: Marker::Dot,
                    role: Role::Plot3,
                },
            ],
            view,
            position_bounds,
            label_width,
            false,
        );
        frame.render_widget(position_chart, top);
        let speed_chart = self.chart(
            "speed (raw)",
            vec![Signal {
                name: "speed",
                points: &speed,
                marker: Marker::Braille,
                role: Role::Plot2,
            }],
            view,
            speed_bounds,
            label_width,
            true,
        );
        frame.render_widget(speed_chart, bottom);
    }

    fn handle_input(&mut self, input: &Input, view: &View) -> Outcome {
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
            _ => Outcome::Ignored,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_window_steps_through_the_ladder_and_stops_at_its_ends() {
        let mut plot = PlotPane::new();
        assert_eq!(plot.window(), DEFAULT_WINDOW);
        plot.zoom(Action::PlotZoomIn);
        assert_eq!(plot.window(), Duration::from_secs(10));
        for _ in 0..20 {
            plot.zoom(Action::PlotZoomIn);
        }
        assert_eq!(plot.window(), Duration::from_secs(1));
        for _ in 0..20 {
            plot.zoom(Action::PlotZoomOut);
        }
        assert_eq!(plot.window(), Duration::from_secs(600));
        plot.zoom(Action::PlotZoomReset);
        assert_eq!(plot.window(), DEFAULT_WINDOW);
    }

    #[test]
    fn values_are_held_as_steps_up_to_now() {
        let start = Instant::now();
        let mut plot = PlotPane::new();
        plot.window = Duration::from_secs(10);
        for (s, v) in [(0, 5), (2, 7), (4, 9)] {
            plot.samples.push_back(Sample {
                at: start + Duration::from_secs(s),
                position: Some(v),
                target: None,
                speed: None,
            });
        }
        let now = start + Duration::from_secs(12);
        let points = plot.points(now, |s| s.position);
        // The first sample fell out of the window: its value starts it.
        assert_eq!(
            points,
            [
                (-10.0, 5.0),
                (-10.0, 5.0),
                (-10.0, 7.0),
                (-8.0, 7.0),
                (-8.0, 9.0),
                (0.0, 9.0)
            ]
        );
        assert!(plot.points(now, |s| s.target).is_empty());
    }

    #[test]
    fn span_labels_read_naturally() {
        assert_eq!(span_label(Duration::from_secs(20)), "20 s");
        assert_eq!(span_label(Duration::from_secs(300)), "5 min");
        assert_eq!(span_label(Duration::from_millis(500)), "500 ms");
    }
}
