//! The tuning pane's current-control view (TMCL CoolStep, §7.3): the
//! family's form with the manual's meaning of the chosen setting, a speed
//! the motor turns at while it is watched, and a live plot of the current
//! the driver sets (as a share of the full current) and the load reading
//! (as a share of its full scale) over time, with the energy saved.
//!
//! The watch is a chain of jobs ([`TuneJob::CurrentStart`], then one
//! [`TuneJob::CurrentRead`] after another), each asked for when the one
//! before has answered, so a reading shows as soon as it is taken and the
//! chain ends the moment the pane stops asking; the motor is stopped by
//! the pane ([`super::TuningPane`]'s cancel), with the jog's stop lines.

use std::collections::VecDeque;
use std::time::Duration;

use ratatui::symbols::Marker;

use super::{Series, marker_symbol};
use crate::protocol::console::AxisInfo;
use crate::protocol::tuning::{CurrentControlPlan, FormField};
use crate::session::tuning::{CurrentRun, CurrentSample, saving_line};
use crate::ui::theme::Role;

/// How long between two readings of a watch (on a slow link the readings
/// themselves take longer).
pub(super) const WATCH_EVERY: Duration = Duration::from_millis(100);

/// The readings the plot keeps: a minute at [`WATCH_EVERY`].
const WINDOW: usize = 600;

/// The speed a watch turns the motor at unless another is typed: the
/// speed `axterm tune coolstep --run` is shown with in the docs.
const DEFAULT_SPEED: i64 = 1000;

/// What the view holds between draws.
pub(super) struct CurrentView {
    /// The form as last read (the start of a watch reads it too).
    pub form: Vec<(FormField, Option<i64>)>,
    /// The full current setting as read.
    pub full: Option<i64>,
    /// Values typed, written at the next start.
    pub set: Vec<(String, i64)>,
    /// The speed the motor turns at while watched; 0 watches without
    /// turning it (a move the technician starts elsewhere).
    pub speed: i64,
    /// The readings, oldest first, at most [`WINDOW`].
    pub samples: VecDeque<CurrentSample>,
    /// When the watch under way began.
    pub began: Option<tokio::time::Instant>,
    /// The (family, axis) the form was read for.
    pub read_for: Option<(&'static str, usize)>,
    /// The tag of a form read under way.
    pub form_tag: Option<u64>,
}

impl CurrentView {
    pub(super) fn new() -> CurrentView {
        CurrentView {
            form: Vec::new(),
            full: None,
            set: Vec::new(),
            speed: DEFAULT_SPEED,
            samples: VecDeque::new(),
            began: None,
            read_for: None,
            form_tag: None,
        }
    }

    /// The rows: each writable setting of the form, then the speed.
    pub(super) fn rows(&self, plan: &dyn CurrentControlPlan) -> Vec<(String, String)> {
        let mut rows: Vec<(String, String)> = plan
            .form()
            .iter()
            .filter(|f| f.writable)
            .map(|f| (f.name.to_string(), self.value_text(f.name)))
            .collect();
        rows.push(("speed".into(), self.speed.to_string()));
        rows
    }

    /// A setting as shown: the value typed for the next start, else as
    /// read.
    fn value_text(&self, name: &str) -> String {
        if let Some((_, v)) = self.set.iter().find(|(n, _)| n == name) {
            return v.to_string();
        }
        match self.form.iter().find(|(f, _)| f.name == name) {
            Some((_, Some(v))) => v.to_string(),
            Some((_, None)) => "?".into(),
            None => "-".into(),
        }
    }

    /// The typed `text` into row `name`, checked by the plan (nothing is
    /// sent until the next start).
    pub(super) fn take_value(
        &mut self,
        plan: &dyn CurrentControlPlan,
        axis: &AxisInfo,
        name: &str,
        text: &str,
    ) -> Result<String, String> {
        let value: i64 = text
            .parse()
            .map_err(|_| format!("{name}: {text:?} is not a whole number"))?;
        if name == "speed" {
            if value < 0 {
                return Err(format!(
                    "speed: {value}: 0 or more (0 watches without turning the motor)"
                ));
            }
            self.speed = value;
            return Ok(format!("the motor turns at {value} while watched"));
        }
        plan.write(axis, name, value)
            .map_err(|why| format!("{why} (nothing sent)"))?;
        self.set.retain(|(n, _)| n != name);
        self.set.push((name.to_string(), value));
        Ok(format!("{name} {value} is written at the next watch"))
    }

    /// The chosen row's title and meaning from the manual.
    pub(super) fn meaning(&self, plan: &dyn CurrentControlPlan, name: &str) -> String {
        match plan.form().into_iter().find(|f| f.name == name) {
            Some(f) => format!(
                "{} {} ({}..{}): {}",
                f.name, f.title, f.min, f.max, f.meaning
            ),
            None => "speed: the motor turns at it while the current is watched (0: it is not \
                     turned; watch a move started elsewhere)"
                .into(),
        }
    }

    /// A watch's start answered: the form as read, the typed values
    /// written, the plot emptied for the new watch.
    pub(super) fn started(&mut self, run: &CurrentRun, began: tokio::time::Instant) {
        self.took_form(run);
        self.samples.clear();
        self.began = Some(began);
    }

    /// The form as read.
    pub(super) fn took_form(&mut self, run: &CurrentRun) {
        self.form = run.form.clone();
        self.full = run.full;
        self.set.clear();
    }

    pub(super) fn push(&mut self, sample: CurrentSample) {
        if self.samples.len() == WINDOW {
            self.samples.pop_front();
        }
        self.samples.push_back(sample);
    }

    /// The plot's series: the load under the current, each in % of its
    /// full scale over seconds.
    pub(super) fn series(&self, load_full: i64) -> Series {
        let load = self
            .samples
            .iter()
            .filter_map(|s| {
                let load = s.load? as f64 / load_full.max(1) as f64;
                Some((s.time, load * 100.0))
            })
            .collect();
        let current = self
            .samples
            .iter()
            .filter_map(|s| Some((s.time, s.share? * 100.0)))
            .collect();
        vec![
            (load, Role::Plot2, LOAD_MARKER, "load"),
            (current, Role::Plot1, CURRENT_MARKER, "current"),
        ]
    }

    /// The line under the plot that names each series by its marker, so
    /// the plot reads without colour and without a legend.
    pub(super) fn key_line(load_full: i64) -> String {
        format!(
            "{} current, % of the full current   {} load reading, % of {load_full}",
            marker_symbol(CURRENT_MARKER),
            marker_symbol(LOAD_MARKER)
        )
    }

    /// The newest reading and the energy saved over the readings shown.
    pub(super) fn figures(&self) -> Vec<String> {
        let Some(last) = self.samples.back() else {
            return Vec::new();
        };
        let shown = |v: Option<i64>| v.map_or_else(|| "-".to_string(), |v| v.to_string());
        let mut lines = vec![format!(
            "now: speed {}, current {} ({}), load {}",
            shown(last.speed),
            shown(last.current),
            last.share
                .map_or_else(|| "-".to_string(), |s| format!("{:.0} %", s * 100.0)),
            shown(last.load)
        )];
        let shares: Vec<f64> = self.samples.iter().filter_map(|s| s.share).collect();
        if !shares.is_empty() {
            let mean = shares.iter().sum::<f64>() / shares.len() as f64;
            lines.push(saving_line(mean, self.full));
        }
        lines
    }
}

/// The current's marker: a dot per cell.
const CURRENT_MARKER: Marker = Marker::Dot;
/// The load's marker: a full block per cell, unlike the current's dots.
const LOAD_MARKER: Marker = Marker::Block;

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(time: f64, load: i64, share: f64) -> CurrentSample {
        CurrentSample {
            time,
            speed: Some(1000),
            current: Some(10),
            load: Some(load),
            share: Some(share),
        }
    }

    #[test]
    fn the_window_keeps_the_newest_readings() {
        let mut view = CurrentView::new();
        for k in 0..WINDOW + 5 {
            view.push(sample(k as f64, 0, 0.5));
        }
        assert_eq!(view.samples.len(), WINDOW);
        assert_eq!(view.samples.front().map(|s| s.time), Some(5.0));
    }

    #[test]
    fn load_and_current_are_plotted_in_percent_of_their_full_scale() {
        let mut view = CurrentView::new();
        view.push(sample(0.5, 1023, 0.25));
        let series = view.series(1023);
        assert_eq!(series[0].0, vec![(0.5, 100.0)]);
        assert_eq!(series[1].0, vec![(0.5, 25.0)]);
    }

    #[test]
    fn the_energy_saved_is_the_mean_shares_complement() {
        let mut view = CurrentView::new();
        view.full = Some(128);
        view.push(sample(0.0, 500, 0.25));
        view.push(sample(0.1, 500, 0.75));
        let figures = view.figures();
        assert!(figures[0].contains("current 10 (75 %)"), "{figures:?}");
        assert!(
            figures[1].contains("50 % of the full current (128)")
                && figures[1].contains("saved 50 %"),
            "{figures:?}"
        );
    }
}
