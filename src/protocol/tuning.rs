//! The tuning tools (the tuning pane, `axterm tune`) as a family's pure
//! plans: a servo step response the controller records itself (MCCL
//! chapter 5's PR with DR/DO/DQ), and a StallGuard2 velocity sweep (TMCL
//! §7.2's AP206 reading). A family that has such a tool gives it as console
//! lines, as typed (so they are checked, sent and shown as any typed line),
//! and reads their answers back; the session's runner
//! (`crate::session::tuning`) decides when, and never knows which family it
//! drives.

use std::time::Duration;

use super::console::AxisInfo;
pub use super::step_response::{StepFigures, StepSample, StepSpec, step_figures};

/// Why a tuning plan gives no lines, or its answers no result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TuneError {
    /// A value the test was asked for that the family or the test cannot
    /// take (the manual's range, a step beyond the following error limit).
    #[error("{0}")]
    Refused(String),
    /// `--set NAME=…` names no gain of the family.
    #[error("{name} is not a gain of this axis: the gains are {known}")]
    UnknownGain { name: String, known: String },
    /// An answer that does not read as the plan expects.
    #[error("the answer to {line} does not read: {reason}")]
    Answer { line: String, reason: String },
}

/// One setting a tuning tool shows and lets the technician change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TuningField {
    /// The family's own name (`SG`, `SD`, `AP174`).
    pub name: &'static str,
    /// What it does, from the manual, with the section.
    pub meaning: &'static str,
}

/// A `--set` item that is not `NAME=NUMBER`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SettingError {
    #[error("--set {item}: write NAME=VALUE (SG=0.05)")]
    NotNameValue { item: String },
    #[error("--set {item}: {value} is not a number")]
    NotANumber { item: String, value: String },
}

impl From<SettingError> for String {
    fn from(error: SettingError) -> String {
        error.to_string()
    }
}

/// `SG=0.05,SD=0.3` as names and values (`--set` of a step test).
pub fn parse_settings(text: &str) -> Result<Vec<(String, f64)>, SettingError> {
    text.split(',')
        .map(str::trim)
        .filter(|item| !item.is_empty())
        .map(|item| {
            let (name, value) = item
                .split_once('=')
                .ok_or_else(|| SettingError::NotNameValue {
                    item: item.to_string(),
                })?;
            let number: f64 = value
                .trim()
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .ok_or_else(|| SettingError::NotANumber {
                    item: item.to_string(),
                    value: value.trim().to_string(),
                })?;
            Ok((name.trim().to_string(), number))
        })
        .collect()
}

/// What a step-response test is asked for.
#[derive(Debug, Clone, PartialEq)]
pub struct StepAsk {
    /// The step, in position counts.
    pub distance: i64,
    /// How many samples the controller records.
    pub samples: usize,
    /// Gains to set before the step, by [`TuningField::name`]; they stay
    /// set after the test (tuning is changing them).
    pub set: Vec<(String, f64)>,
}

/// A step-response test as console lines, in the order the runner sends
/// them, each on its own success.
#[derive(Debug, Clone, PartialEq)]
pub struct StepScript {
    /// Gains, loop rate, mode, motor on.
    pub setup: Vec<String>,
    /// Arm the recording and make the step.
    pub step: Vec<String>,
    /// How long the recording takes after the step lines are answered.
    pub recording: Duration,
    /// Read the samples back.
    pub readback: Vec<String>,
    /// Back to the axis's normal mode (the gains set stay).
    pub restore: Vec<String>,
    /// What a failed, tripped or cancelled test sends: no axis is left
    /// moving.
    pub stop: Vec<String>,
    /// Seconds between two samples (the loop rate's).
    pub sample_period: f64,
    /// The amplifier's output limit, volts: saturation is judged on it.
    pub output_limit: f64,
}

/// A family's servo step-response test.
pub trait StepResponsePlan: Sync {
    /// The gains the pane shows and `--set` takes, in the manual's order.
    fn gains(&self) -> &'static [TuningField];

    /// The lines that read the axis's gains.
    fn read_gains(&self, axis: &AxisInfo) -> Vec<String>;

    /// The gains as the answers of [`StepResponsePlan::read_gains`] read
    /// (each line's answer text, in order), in [`StepResponsePlan::gains`]
    /// order; `None` for a gain the module does not tell.
    fn parse_gains(&self, answers: &[String]) -> Result<Vec<Option<f64>>, TuneError>;

    /// The test's lines for `axis`.
    fn script(&self, axis: &AxisInfo, ask: &StepAsk) -> Result<StepScript, TuneError>;

    /// The samples, from the answers to `script`'s read-back lines (each
    /// line's answer text, in order).
    fn samples(
        &self,
        script: &StepScript,
        ask: &StepAsk,
        answers: &[String],
    ) -> Result<Vec<StepSample>, TuneError>;
}

/// What a StallGuard2 sweep is asked for: `steps` speeds from `from` to
/// `to` (the family's speed unit), `samples` readings at each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SweepAsk {
    pub from: i64,
    pub to: i64,
    pub steps: u32,
    pub samples: u32,
}

/// One instruction of a sweep, in order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SweepAction {
    /// Send the line; it must succeed before the next.
    Send(String),
    /// Send `read` (the actual speed) until it shows `speed`.
    WaitForSpeed { read: String, speed: i64 },
    /// Send `read` (the load reading) and keep its value for speed
    /// number `point`.
    Sample { point: usize, read: String },
}

/// A sweep as console lines.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SweepScript {
    /// The speeds, in the order they are run.
    pub speeds: Vec<i64>,
    pub actions: Vec<SweepAction>,
    /// What ends the sweep, and what a failed or cancelled one sends.
    pub stop: Vec<String>,
}

/// The readings taken at one speed.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct SweepPoint {
    pub speed: i64,
    pub readings: Vec<i64>,
}

impl SweepPoint {
    /// The mean of the readings, rounded; `None` without any.
    pub fn mean(&self) -> Option<i64> {
        let n = i64::try_from(self.readings.len()).ok().filter(|&n| n > 0)?;
        let sum: i64 = self.readings.iter().sum();
        Some((sum + n / 2).div_euclid(n))
    }
}

/// What a sweep with and a sweep without load suggest.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SweepSuggestion {
    /// The reasoning, a plain line each.
    pub reasons: Vec<String>,
    /// The lines that would set it (the technician decides whether to).
    pub lines: Vec<String>,
}

/// A family's StallGuard2-style load sweep.
pub trait StallSweepPlan: Sync {
    /// What the reading is ("AP206 StallGuard2 load value, 0 = stall").
    fn reading(&self) -> &'static str;

    /// The settings that bear on the reading, with their meaning.
    fn fields(&self) -> &'static [TuningField];

    /// The line that reads the threshold in force during a sweep (the
    /// suggestion is relative to it).
    fn read_threshold(&self, axis: &AxisInfo) -> String;

    /// The sweep's lines for `axis`.
    fn script(&self, axis: &AxisInfo, ask: &SweepAsk) -> Result<SweepScript, TuneError>;

    /// Whether an actual speed read shows the asked one.
    fn speed_reached(&self, actual: i64, speed: i64) -> bool;

    /// The name of the axis error flag the module raises when it stops
    /// the motor on a stall (`crate::protocol::console::AxisFlag::name`).
    fn stall_flag(&self) -> &'static str;

    /// A threshold and a stop-on-stall speed from a sweep without load
    /// (`free`) and one with (`loaded`), with the reasoning.
    fn suggest(
        &self,
        axis: &AxisInfo,
        free: &[SweepPoint],
        loaded: &[SweepPoint],
        threshold_during: i64,
    ) -> SweepSuggestion;
}

/// One setting of a current-control form (TMCL CoolStep).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FormField {
    /// The family's own name (`AP172`).
    pub name: &'static str,
    /// Its name in the manual.
    pub title: &'static str,
    /// What it does, from the manual.
    pub meaning: &'static str,
    pub min: i64,
    pub max: i64,
    /// False for a status value.
    pub writable: bool,
}

/// The lines a current-control watch reads each time.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CurrentWatch {
    /// The current the driver sets now.
    pub current: String,
    /// The load reading.
    pub load: String,
    /// The actual speed.
    pub speed: String,
    /// The full (maximum) current setting the ratio is taken to.
    pub full: String,
    /// The load reading's full scale (its largest value), so that a plot
    /// can show it beside the current's share.
    pub load_full: i64,
}

/// A family's load-adaptive current control (TMCL CoolStep, §7.3).
pub trait CurrentControlPlan: Sync {
    /// The form's settings, in the manual's order.
    fn form(&self) -> Vec<FormField>;

    /// The line that reads `field` of `axis`.
    fn read(&self, axis: &AxisInfo, field: &FormField) -> String;

    /// The line that writes `value` into the setting named `name`, checked
    /// against the form.
    fn write(&self, axis: &AxisInfo, name: &str, value: i64) -> Result<String, TuneError>;

    /// What a watch reads.
    fn watch(&self, axis: &AxisInfo) -> CurrentWatch;

    /// The current as a share of the full current (0..1), from the two
    /// readings of [`CurrentWatch`].
    fn share(&self, current: i64, full: i64) -> Option<f64>;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_points_mean_rounds_and_an_empty_point_has_none() {
        let point = |readings: &[i64]| SweepPoint {
            speed: 100,
            readings: readings.to_vec(),
        };
        assert_eq!(point(&[1, 2]).mean(), Some(2));
        assert_eq!(point(&[1, 1, 2]).mean(), Some(1));
        assert_eq!(point(&[]).mean(), None);
    }
}
