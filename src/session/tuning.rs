//! The runner of the tuning tools: it sends a family's tuning plan
//! ([`crate::protocol::tuning`]) line by line, each on its own success, and
//! reads the answers back into samples, figures and readings. Generic over
//! the family; it never says ok for what did not happen: a test whose axis
//! tripped says so, and a test that fails or is cancelled sends the plan's
//! stop lines so that no axis is left moving.

use std::time::Duration;

use tokio::time::Instant;

use super::{Session, SessionError};
use crate::protocol::console::{AxisFlag, ReplyValue};
use crate::protocol::jog::{Direction, JogPlan};
use crate::protocol::tuning::{
    CurrentControlPlan, FormField, StallSweepPlan, StepAsk, StepFigures, StepResponsePlan,
    StepSample, StepSpec, SweepAction, SweepAsk, SweepPoint, TuneError, step_figures,
};

/// How long a sweep waits for the motor to reach one of its speeds.
const SPEED_WAIT: Duration = Duration::from_secs(20);

/// How long a run waits for a motor to come to rest after a sweep.
pub const STAND_WAIT: Duration = Duration::from_secs(10);

/// How often the speed is read while waiting for it.
const SPEED_LOOK_EVERY: Duration = Duration::from_millis(20);

/// Why a tuning run ended without a result.
#[derive(Debug, thiserror::Error)]
pub enum TuningError {
    /// The plan refused what it was asked (nothing was sent).
    #[error("{0}")]
    Plan(#[from] TuneError),
    /// A line failed.
    #[error("{0}")]
    Line(#[from] SessionError),
    /// The family has no such tool for this axis.
    #[error("{0}")]
    Unavailable(String),
    /// The motor did not reach a sweep's speed.
    #[error("the motor did not reach {speed} within {seconds} s (it reads {last:?})")]
    SpeedNotReached {
        speed: i64,
        seconds: u64,
        last: Option<i64>,
    },
}

/// What a step-response test gave.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRun {
    /// The gains as read after the test's setup, by name.
    pub gains: Vec<(&'static str, Option<f64>)>,
    pub samples: Vec<StepSample>,
    /// `None` when the samples hold no step to judge (a trip at once).
    pub figures: Option<StepFigures>,
    /// Why no figures, if none.
    pub figures_missing: Option<String>,
    /// Error flags the axis showed after the step (a following error,
    /// an amplifier fault): the test tripped, and the axis was stopped.
    pub tripped: Vec<AxisFlag>,
    pub sample_period: f64,
}

/// What a stall test saw.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StallOutcome {
    /// How long after the start the module stopped the motor on a stall;
    /// `None`: no stall was detected before the test gave up.
    pub detected_after: Option<Duration>,
    /// The fastest the motor was read turning.
    pub fastest: Option<i64>,
}

/// What a sweep gave.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepRun {
    pub points: Vec<SweepPoint>,
    /// The threshold in force during the sweep, as read.
    pub threshold: Option<i64>,
}

/// One reading of a current-control watch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurrentSample {
    /// Seconds since the watch began.
    pub time: f64,
    pub speed: Option<i64>,
    pub current: Option<i64>,
    pub load: Option<i64>,
    /// The current as a share of the full current.
    pub share: Option<f64>,
}

/// What a current-control watch gave: the form as read, and the readings.
#[derive(Debug, Clone, PartialEq)]
pub struct CurrentRun {
    pub form: Vec<(FormField, Option<i64>)>,
    pub full: Option<i64>,
    pub samples: Vec<CurrentSample>,
}

/// The energy a load-adaptive current saves, in words: `mean` is the
/// current's mean share of the full current `full` (as read).
pub fn saving_line(mean: f64, full: Option<i64>) -> String {
    format!(
        "mean current {:.0} % of the full current ({}): CoolStep saved {:.0} % of the current",
        mean * 100.0,
        full.map_or_else(|| "unread".to_string(), |f| f.to_string()),
        (1.0 - mean).max(0.0) * 100.0
    )
}

impl CurrentRun {
    /// The mean share of the full current over the samples that have one.
    pub fn mean_share(&self) -> Option<f64> {
        let shares: Vec<f64> = self.samples.iter().filter_map(|s| s.share).collect();
        (!shares.is_empty()).then(|| shares.iter().sum::<f64>() / shares.len() as f64)
    }
}

/// How a current-control watch turns the motor, if it does.
#[derive(Clone, Copy)]
pub struct WatchRun<'a> {
    pub jog: &'a dyn JogPlan,
    pub direction: Direction,
    pub speed: i64,
}

/// A step test's samples as the sheet's plot: commanded and actual
/// position over time (ms).
pub fn step_plot(axis: &crate::protocol::console::AxisInfo, run: &StepRun) -> crate::report::Plot {
    use crate::report::{Plot, Series};
    let series = |name: &str, value: fn(&crate::protocol::tuning::StepSample) -> f64| Series {
        name: name.to_string(),
        points: run
            .samples
            .iter()
            .map(|s| (s.time * 1000.0, value(s)))
            .collect(),
    };
    Plot {
        title: format!("Step response, {}", axis.name),
        x_label: "time (ms)".into(),
        y_label: "position (counts)".into(),
        series: vec![
            series("commanded", |s| s.commanded),
            series("actual", |s| s.actual),
        ],
    }
}

/// A sweep's readings as the sheet's plot: the mean reading at each
/// speed, and every reading.
pub fn sweep_plot(
    axis: &crate::protocol::console::AxisInfo,
    reading: &str,
    run: &SweepRun,
) -> crate::report::Plot {
    use crate::report::{Plot, Series};
    let as_f64 = |n: i64| n as f64;
    Plot {
        title: format!("StallGuard2 sweep, {}", axis.name),
        x_label: "speed".into(),
        y_label: reading.split(',').next().unwrap_or(reading).to_string(),
        series: vec![
            Series {
                name: "mean".into(),
                points: run
                    .points
                    .iter()
                    .filter_map(|p| Some((as_f64(p.speed), as_f64(p.mean()?))))
                    .collect(),
            },
            Series {
                name: "readings".into(),
                points: run
                    .points
                    .iter()
                    .flat_map(|p| p.readings.iter().map(|&r| (as_f64(p.speed), as_f64(r))))
                    .collect(),
            },
        ],
    }
}

/// A sweep's readings as lines: the reading and the threshold, then each
/// speed's mean and readings.
pub fn sweep_lines(reading: &str, run: &SweepRun) -> Vec<String> {
    let mut lines = vec![format!(
        "{reading}; threshold during the sweep: {}",
        run.threshold
            .map_or_else(|| "not read".to_string(), |t| t.to_string())
    )];
    for p in &run.points {
        let readings: Vec<String> = p.readings.iter().map(i64::to_string).collect();
        lines.push(format!(
            "speed {}: {} (readings {})",
            p.speed,
            p.mean().map_or_else(|| "-".to_string(), |m| m.to_string()),
            readings.join(" ")
        ));
    }
    lines
}

/// The figures of a step test as lines to read (the CLI's text, the
/// tuning pane's figures).
pub fn step_lines(axis: &crate::protocol::console::AxisInfo, run: &StepRun) -> Vec<String> {
    let mut lines = Vec::new();
    let gains: Vec<String> = run
        .gains
        .iter()
        .filter_map(|(name, value)| value.map(|v| format!("{name} {v}")))
        .collect();
    lines.push(format!(
        "{}: {} samples every {} ms; gains {}",
        axis.name,
        run.samples.len(),
        run.sample_period * 1000.0,
        if gains.is_empty() {
            "not read".to_string()
        } else {
            gains.join(", ")
        }
    ));
    if !run.tripped.is_empty() {
        lines.push(format!(
            "TRIPPED: {} — the axis was stopped",
            run.tripped
                .iter()
                .map(|f| format!("{} ({})", f.name, f.description))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    match &run.figures {
        Some(f) => {
            let ms = |t: Option<f64>| {
                t.map_or_else(|| "never".to_string(), |t| format!("{:.2} ms", t * 1000.0))
            };
            lines.push(format!("rise time (10-90 %): {}", ms(f.rise_time)));
            lines.push(format!("overshoot: {:.1} %", f.overshoot_percent));
            lines.push(format!("settling time: {}", ms(f.settling_time)));
            lines.push(format!(
                "following error: peak {:.0}, final {:.0} counts",
                f.peak_following_error, f.final_following_error
            ));
            lines.push(format!(
                "output: peak {:.2} V{}",
                f.peak_output,
                if f.saturated { ", SATURATED" } else { "" }
            ));
        }
        None => lines.push(format!(
            "no figures: {}",
            run.figures_missing
                .as_deref()
                .unwrap_or("no step in the samples")
        )),
    }
    lines
}

/// The text of a line's answer, as a plan reads it.
fn answer_text(value: &ReplyValue) -> String {
    match value {
        ReplyValue::None => String::new(),
        ReplyValue::Number(n) => n.to_string(),
        ReplyValue::Text(text) => text.clone(),
    }
}

impl Session {
    /// Send `lines` in order, each on the success of the one before; the
    /// answers' text.
    async fn send_all(&self, lines: &[String]) -> Result<Vec<String>, SessionError> {
        let mut answers = Vec::with_capacity(lines.len());
        for line in lines {
            answers.push(answer_text(&self.execute_line(line).await?.value));
        }
        Ok(answers)
    }

    /// The axis's gains as `plan` reads them.
    pub async fn read_gains(
        &self,
        plan: &dyn StepResponsePlan,
        axis: usize,
    ) -> Result<Vec<(&'static str, Option<f64>)>, TuningError> {
        let info = self.axis_info(axis)?;
        let answers = self.send_all(&plan.read_gains(&info)).await?;
        let values = plan.parse_gains(&answers)?;
        Ok(plan
            .gains()
            .iter()
            .map(|g| g.name)
            .zip(values.into_iter().chain(std::iter::repeat(None)))
            .collect())
    }

    /// A step-response test of axis `axis`: set up, step, wait while the
    /// controller records, read the samples back, restore the mode; the
    /// figures judged with `spec`. A trip seen after the step stops the
    /// axis with the plan's stop lines and is reported in the result; a
    /// failed line stops it too and is the error.
    pub async fn step_response(
        &self,
        plan: &dyn StepResponsePlan,
        axis: usize,
        ask: &StepAsk,
        spec: &StepSpec,
    ) -> Result<StepRun, TuningError> {
        let info = self.axis_info(axis)?;
        let script = plan.script(&info, ask)?;
        let run = async {
            self.send_all(&script.setup).await?;
            let gains = self.read_gains(plan, axis).await?;
            // Flags the axis showed before the step are not the step's.
            let before = self.axis_errors(axis).await?;
            self.send_all(&script.step).await?;
            tokio::time::sleep(script.recording).await;
            let answers = self.send_all(&script.readback).await?;
            let samples = plan.samples(&script, ask, &answers)?;
            let mut tripped = self.axis_errors(axis).await?;
            tripped.retain(|flag| !before.contains(flag));
            if tripped.is_empty() {
                self.send_all(&script.restore).await?;
            }
            Ok::<_, TuningError>((gains, samples, tripped))
        };
        let (gains, samples, tripped) = match run.await {
            Ok(done) => done,
            Err(error) => {
                let _ = self.send_all(&script.stop).await;
                return Err(error);
            }
        };
        if !tripped.is_empty() {
            self.send_all(&script.stop).await?;
        }
        let spec = StepSpec {
            output_limit: script.output_limit,
            ..*spec
        };
        let (figures, figures_missing) = match step_figures(&samples, &spec) {
            Ok(figures) => (Some(figures), None),
            Err(why) => (None, Some(why.to_string())),
        };
        Ok(StepRun {
            gains,
            samples,
            figures,
            figures_missing,
            tripped,
            sample_period: script.sample_period,
        })
    }

    /// A load sweep of axis `axis`: each speed in turn, wait until the
    /// motor turns at it, take the readings; the plan's stop at the end,
    /// however the sweep ends.
    pub async fn stall_sweep(
        &self,
        plan: &dyn StallSweepPlan,
        axis: usize,
        ask: &SweepAsk,
    ) -> Result<SweepRun, TuningError> {
        let info = self.axis_info(axis)?;
        let script = plan.script(&info, ask)?;
        let run = async {
            let threshold = self
                .execute_line(&plan.read_threshold(&info))
                .await?
                .value
                .number();
            let mut points: Vec<SweepPoint> = script
                .speeds
                .iter()
                .map(|&speed| SweepPoint {
                    speed,
                    readings: Vec::new(),
                })
                .collect();
            for action in &script.actions {
                match action {
                    SweepAction::Send(line) => {
                        self.execute_line(line).await?;
                    }
                    SweepAction::WaitForSpeed { read, speed } => {
                        self.wait_for_speed(plan, read, *speed).await?;
                    }
                    SweepAction::Sample { point, read } => {
                        let value = self.execute_line(read).await?.value;
                        let ReplyValue::Number(n) = value else {
                            return Err(TuningError::Plan(TuneError::Answer {
                                line: read.clone(),
                                reason: format!("{value} is not a number"),
                            }));
                        };
                        if let Some(p) = points.get_mut(*point) {
                            p.readings.push(n);
                        }
                    }
                }
            }
            Ok::<_, TuningError>(SweepRun { points, threshold })
        };
        let result = run.await;
        let stopped = self.send_all(&script.stop).await;
        let done = result?;
        stopped?;
        Ok(done)
    }

    /// Write `set` (checked against the form first: nothing is sent if
    /// one is refused), read the form, then read current, load and speed
    /// `samples` times, `every` apart; with `run`, the motor turns while
    /// it watches and is stopped after, however the watch ends.
    pub async fn watch_current(
        &self,
        plan: &dyn CurrentControlPlan,
        axis: usize,
        set: &[(String, i64)],
        run: Option<WatchRun<'_>>,
        samples: u32,
        every: Duration,
    ) -> Result<CurrentRun, TuningError> {
        let watch = async {
            let mut done = self.begin_current_watch(plan, axis, set, run).await?;
            let began = Instant::now();
            for k in 0..samples {
                if k > 0 {
                    tokio::time::sleep(every).await;
                }
                done.samples
                    .push(self.read_current(plan, axis, done.full, began).await?);
            }
            Ok::<_, TuningError>(done)
        };
        let result = watch.await;
        // A refusal of the plan comes before anything is sent.
        if let Some(run) = run.filter(|_| !matches!(result, Err(TuningError::Plan(_)))) {
            let info = self.axis_info(axis)?;
            let stopped = self.send_all(&run.jog.stop(&info)).await;
            let done = result?;
            stopped?;
            return Ok(done);
        }
        result
    }

    /// The start of a current watch, for a caller that reads the samples
    /// itself ([`Session::read_current`], the tuning pane's live plot):
    /// write `set` (checked against the form first: nothing is sent if one
    /// is refused), read the form and the full current, then start the
    /// motor with `run`. The motor is left turning: the caller stops it
    /// with `run`'s stop lines, also when this fails (a start line may
    /// have gone out). The run has no samples yet.
    pub async fn begin_current_watch(
        &self,
        plan: &dyn CurrentControlPlan,
        axis: usize,
        set: &[(String, i64)],
        run: Option<WatchRun<'_>>,
    ) -> Result<CurrentRun, TuningError> {
        let info = self.axis_info(axis)?;
        let writes = set
            .iter()
            .map(|(name, value)| plan.write(&info, name, *value))
            .collect::<Result<Vec<_>, _>>()?;
        let start = match run {
            Some(run) => run
                .jog
                .run(&info, run.direction, run.speed)
                .map_err(|e| TuneError::Refused(e.into()))?,
            None => Vec::new(),
        };
        self.send_all(&writes).await?;
        let mut form = Vec::new();
        for field in plan.form() {
            let value = self
                .execute_line(&plan.read(&info, &field))
                .await?
                .value
                .number();
            form.push((field, value));
        }
        let full = self
            .execute_line(&plan.watch(&info).full)
            .await?
            .value
            .number();
        self.send_all(&start).await?;
        Ok(CurrentRun {
            form,
            full,
            samples: Vec::new(),
        })
    }

    /// One reading of a current watch: speed, current and load of `axis`,
    /// timed from `began`, the share taken to `full` (as
    /// [`Session::begin_current_watch`] read it).
    pub async fn read_current(
        &self,
        plan: &dyn CurrentControlPlan,
        axis: usize,
        full: Option<i64>,
        began: Instant,
    ) -> Result<CurrentSample, TuningError> {
        let lines = plan.watch(&self.axis_info(axis)?);
        let speed = self.execute_line(&lines.speed).await?.value.number();
        let current = self.execute_line(&lines.current).await?.value.number();
        let load = self.execute_line(&lines.load).await?.value.number();
        Ok(CurrentSample {
            time: began.elapsed().as_secs_f64(),
            speed,
            current,
            load,
            share: current.zip(full).and_then(|(c, f)| plan.share(c, f)),
        })
    }

    /// A stall test: turn the motor at `speed` and watch, for at most
    /// `give_up`, whether the module stops it on a stall (its stall flag
    /// rises); the motor is stopped at the end either way.
    pub async fn stall_test(
        &self,
        plan: &dyn StallSweepPlan,
        axis: usize,
        speed: i64,
        give_up: Duration,
    ) -> Result<StallOutcome, TuningError> {
        let info = self.axis_info(axis)?;
        let script = plan.script(
            &info,
            &SweepAsk {
                from: speed,
                to: speed,
                steps: 1,
                samples: 1,
            },
        )?;
        let start: Vec<String> = script
            .actions
            .iter()
            .take_while(|a| matches!(a, SweepAction::Send(_)))
            .filter_map(|a| match a {
                SweepAction::Send(line) => Some(line.clone()),
                _ => None,
            })
            .collect();
        let read_speed = script.actions.iter().find_map(|a| match a {
            SweepAction::WaitForSpeed { read, .. } => Some(read.clone()),
            _ => None,
        });
        let watch = async {
            let before = self.axis_errors(axis).await?;
            self.send_all(&start).await?;
            let began = Instant::now();
            let mut fastest = None::<i64>;
            loop {
                if let Some(read) = &read_speed
                    && let ReplyValue::Number(n) = self.execute_line(read).await?.value
                {
                    fastest = Some(fastest.map_or(n.abs(), |f| f.max(n.abs())));
                }
                let now = self.axis_errors(axis).await?;
                if now
                    .iter()
                    .any(|f| f.name == plan.stall_flag() && !before.contains(f))
                {
                    return Ok::<_, TuningError>(StallOutcome {
                        detected_after: Some(began.elapsed()),
                        fastest,
                    });
                }
                if began.elapsed() >= give_up {
                    return Ok(StallOutcome {
                        detected_after: None,
                        fastest,
                    });
                }
                tokio::time::sleep(SPEED_LOOK_EVERY).await;
            }
        };
        let result = watch.await;
        let stopped = self.send_all(&script.stop).await;
        let done = result?;
        stopped?;
        Ok(done)
    }

    async fn wait_for_speed(
        &self,
        plan: &dyn StallSweepPlan,
        read: &str,
        speed: i64,
    ) -> Result<(), TuningError> {
        let asked = Instant::now();
        let mut last = None;
        loop {
            if let ReplyValue::Number(n) = self.execute_line(read).await?.value {
                if plan.speed_reached(n, speed) {
                    return Ok(());
                }
                last = Some(n);
            }
            if asked.elapsed() >= SPEED_WAIT {
                return Err(TuningError::SpeedNotReached {
                    speed,
                    seconds: SPEED_WAIT.as_secs(),
                    last,
                });
            }
            tokio::time::sleep(SPEED_LOOK_EVERY).await;
        }
    }

    /// Wait until axis `axis` stands (its status poll reads speed 0), up
    /// to `within`: after a sweep's stop a motor ramps down, and a run
    /// that goes on (or ends and checks for moving axes) must see it at
    /// rest. Whether it stands.
    pub async fn wait_standing(&self, axis: usize, within: Duration) -> Result<bool, SessionError> {
        let asked = Instant::now();
        loop {
            let status = self.read_status_polls(false).await?;
            if status.get(axis).is_some_and(|s| s.speed == Some(0)) {
                return Ok(true);
            }
            if asked.elapsed() >= within {
                return Ok(false);
            }
            tokio::time::sleep(SPEED_LOOK_EVERY).await;
        }
    }

    fn axis_info(&self, axis: usize) -> Result<crate::protocol::console::AxisInfo, TuningError> {
        self.axes().get(axis).copied().ok_or_else(|| {
            TuningError::Unavailable(format!(
                "the module has no axis {axis} (it has 0..{})",
                self.axes().len().saturating_sub(1)
            ))
        })
    }

    /// The error flags axis `axis` shows now (read afresh).
    async fn axis_errors(&self, axis: usize) -> Result<Vec<AxisFlag>, SessionError> {
        let status = self.read_status_polls(false).await?;
        Ok(status
            .get(axis)
            .map(|s| s.errors.clone())
            .unwrap_or_default())
    }
}
