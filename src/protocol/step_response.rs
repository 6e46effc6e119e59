//! The figures of a servo step response, from recorded samples: rise time
//! (10–90 %), overshoot, settling time into a band, following error, the
//! command output and whether it saturated. Pure and generic: any family
//! that records commanded and actual position and its output can use it.
//!
//! Times are measured from the step's onset: the first sample whose
//! commanded position differs from the first sample's (a gain-mode step
//! jumps there, a profiled move starts its ramp there); when the
//! recording began after the command moved, from the first sample.

use std::fmt;

/// One recorded sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepSample {
    /// Seconds from the start of the recording.
    pub time: f64,
    /// Commanded (optimal) position.
    pub commanded: f64,
    /// Actual (encoder) position.
    pub actual: f64,
    /// Command output, volts.
    pub output: f64,
}

/// What the figures are judged against.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSpec {
    /// Settled: |actual − final commanded| ≤ band, in position units.
    pub band: f64,
    /// Saturated: |output| ≥ this, volts (±10 V for an analog command).
    pub output_limit: f64,
}

impl Default for StepSpec {
    fn default() -> Self {
        StepSpec {
            band: 1.0,
            output_limit: 10.0,
        }
    }
}

/// The figures of one step response.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepFigures {
    /// Actual position at the first sample.
    pub start: f64,
    /// Commanded position at the last sample.
    pub target: f64,
    /// Seconds from the start of the recording to the step's onset.
    pub onset: f64,
    /// Seconds from 10 % to 90 % of the step; `None` if 90 % was never
    /// reached.
    pub rise_time: Option<f64>,
    /// How far past the target the actual position went, % of the step
    /// (0 when it never passed it).
    pub overshoot_percent: f64,
    /// The actual position furthest along the step's direction.
    pub peak: f64,
    /// Seconds from the onset until the actual position entered the band
    /// for good; `None` if the last sample is outside it.
    pub settling_time: Option<f64>,
    /// The following error (commanded − actual) of largest magnitude.
    pub peak_following_error: f64,
    /// The following error at the last sample.
    pub final_following_error: f64,
    /// The output of largest magnitude, volts.
    pub peak_output: f64,
    /// Some sample's output reached the limit.
    pub saturated: bool,
}

/// Why no figures could be made.
#[derive(Debug, Clone, PartialEq)]
pub enum StepError {
    TooFewSamples(usize),
    /// Sample `index` holds a value that is not a finite number.
    NotFinite {
        index: usize,
    },
    /// Sample `index` is not later than the one before it.
    TimeNotIncreasing {
        index: usize,
    },
    /// The commanded position ends where the actual one started.
    NoStep,
    BadSpec(String),
}

impl fmt::Display for StepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StepError::TooFewSamples(n) => {
                write!(f, "a step response needs at least 2 samples, got {n}")
            }
            StepError::NotFinite { index } => {
                write!(f, "sample {index} holds a value that is not a number")
            }
            StepError::TimeNotIncreasing { index } => {
                write!(f, "sample {index} is not later than the sample before it")
            }
            StepError::NoStep => write!(
                f,
                "no step: the commanded position ends where the axis started"
            ),
            StepError::BadSpec(why) => f.write_str(why),
        }
    }
}

impl std::error::Error for StepError {}

/// The figures of `samples` (in time order) against `spec`.
pub fn step_figures(samples: &[StepSample], spec: &StepSpec) -> Result<StepFigures, StepError> {
    if !(spec.band.is_finite() && spec.band >= 0.0) {
        return Err(StepError::BadSpec(format!(
            "the settling band must be a number ≥ 0, not {}",
            spec.band
        )));
    }
    if !(spec.output_limit.is_finite() && spec.output_limit > 0.0) {
        return Err(StepError::BadSpec(format!(
            "the output limit must be a number > 0, not {}",
            spec.output_limit
        )));
    }
    if samples.len() < 2 {
        return Err(StepError::TooFewSamples(samples.len()));
    }
    for (index, s) in samples.iter().enumerate() {
        let finite = [s.time, s.commanded, s.actual, s.output]
            .iter()
            .all(|v| v.is_finite());
        if !finite {
            return Err(StepError::NotFinite { index });
        }
        if index > 0 && s.time <= samples[index - 1].time {
            return Err(StepError::TimeNotIncreasing { index });
        }
    }
    let first = samples[0];
    let last = samples[samples.len() - 1];
    let start = first.actual;
    let target = last.commanded;
    let step = target - start;
    if step == 0.0 {
        return Err(StepError::NoStep);
    }
    let onset = samples
        .iter()
        .find(|s| s.commanded != first.commanded)
        .map_or(first.time, |s| s.time);
    // Progress along the step: 0 at the start, 1 on the target.
    let progress = |s: &StepSample| (s.actual - start) / step;
    let crossing = |level: f64| -> Option<f64> {
        let mut before: Option<&StepSample> = None;
        for s in samples {
            if progress(s) >= level {
                return Some(match before {
                    Some(b) if progress(b) < level => {
                        let (pb, ps) = (progress(b), progress(s));
                        b.time + (s.time - b.time) * (level - pb) / (ps - pb)
                    }
                    _ => s.time,
                });
            }
            before = Some(s);
        }
        None
    };
    let rise_time = match (crossing(0.1), crossing(0.9)) {
        (Some(t10), Some(t90)) => Some(t90 - t10),
        _ => None,
    };
    let furthest = samples
        .iter()
        .max_by(|a, b| progress(a).total_cmp(&progress(b)))
        .unwrap_or(&first);
    let overshoot_percent = (progress(furthest) - 1.0).max(0.0) * 100.0;
    let settling_time = if (last.actual - target).abs() > spec.band {
        None
    } else {
        let entered = samples
            .iter()
            .rposition(|s| (s.actual - target).abs() > spec.band)
            .map_or(first.time, |i| samples[i + 1].time);
        Some((entered - onset).max(0.0))
    };
    let largest = |values: &mut dyn Iterator<Item = f64>| {
        values.fold(0.0f64, |m, v| if v.abs() > m.abs() { v } else { m })
    };
    let peak_following_error = largest(&mut samples.iter().map(|s| s.commanded - s.actual));
    let peak_output = largest(&mut samples.iter().map(|s| s.output));
    Ok(StepFigures {
        start,
        target,
        onset,
        rise_time,
        overshoot_percent,
        peak: furthest.actual,
        settling_time,
        peak_following_error,
        final_following_error: last.commanded - last.actual,
        peak_output,
        saturated: samples
            .iter()
            .any(|s| s.output.abs() >= spec.output_limit - 1e-9),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A step from 0 to `to` at t = 1 ms, sampled every ms, the actual
    /// position given per sample.
    fn curve(to: f64, actual: &[f64], output: &[f64]) -> Vec<StepSample> {
        actual
            .iter()
            .enumerate()
            .map(|(i, &a)| StepSample {
                time: i as f64 * 0.001,
                commanded: if i == 0 { 0.0 } else { to },
                actual: a,
                output: output.get(i).copied().unwrap_or(0.0),
            })
            .collect()
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    #[test]
    fn a_ringing_step_gives_its_rise_overshoot_and_settling() {
        let samples = curve(
            100.0,
            &[
                0.0, 0.0, 20.0, 60.0, 100.0, 130.0, 110.0, 95.0, 102.0, 100.0,
            ],
            &[0.0, 4.0, 10.0, 3.0, -1.0, -3.0, -1.0, 0.5, 0.0, 0.0],
        );
        let f = step_figures(&samples, &StepSpec::default()).expect("figures");
        // 10 at 1.5 ms (between 0 and 20), 90 at 3.75 ms (between 60 and
        // 100): 2.25 ms.
        assert!(close(f.rise_time.expect("rise"), 0.00225), "{f:?}");
        assert!(close(f.overshoot_percent, 30.0));
        assert_eq!(f.peak, 130.0);
        // Within ±1 from 9 ms (102 is outside): 9 ms − onset 1 ms.
        assert!(close(f.settling_time.expect("settled"), 0.008), "{f:?}");
        assert!(close(f.onset, 0.001));
        assert_eq!(f.peak_following_error, 100.0);
        assert_eq!(f.final_following_error, 0.0);
        assert_eq!(f.peak_output, 10.0);
        assert!(f.saturated);
        // Within ±2 from 8 ms.
        let wide = StepSpec {
            band: 2.0,
            ..StepSpec::default()
        };
        let f = step_figures(&samples, &wide).expect("figures");
        assert!(close(f.settling_time.expect("settled"), 0.007));
    }

    #[test]
    fn a_sluggish_step_never_rises_nor_settles() {
        let samples = curve(100.0, &[0.0, 0.0, 5.0, 30.0, 60.0, 80.0], &[0.0, -2.0]);
        let f = step_figures(&samples, &StepSpec::default()).expect("figures");
        assert_eq!(f.rise_time, None);
        assert_eq!(f.settling_time, None);
        assert_eq!(f.overshoot_percent, 0.0);
        assert_eq!(f.final_following_error, 20.0);
        assert_eq!(f.peak_output, -2.0);
        assert!(!f.saturated, "2 V of 10");
    }

    #[test]
    fn a_negative_step_measures_along_its_direction() {
        let samples = curve(-50.0, &[0.0, 0.0, -30.0, -55.0, -50.0], &[]);
        let f = step_figures(&samples, &StepSpec::default()).expect("figures");
        assert!(close(f.overshoot_percent, 10.0));
        assert_eq!(f.peak, -55.0);
        assert!(f.rise_time.is_some());
        assert!(close(f.settling_time.expect("settled"), 0.003));
    }

    #[test]
    fn a_lower_output_limit_counts_as_saturation() {
        let samples = curve(10.0, &[0.0, 5.0, 10.0], &[0.0, 2.5, 0.0]);
        let spec = StepSpec {
            output_limit: 2.5,
            ..StepSpec::default()
        };
        assert!(step_figures(&samples, &spec).expect("figures").saturated);
    }

    #[test]
    fn bad_input_is_named() {
        let spec = StepSpec::default();
        assert_eq!(step_figures(&[], &spec), Err(StepError::TooFewSamples(0)));
        let flat = curve(0.0, &[0.0, 0.0, 0.0], &[]);
        assert_eq!(step_figures(&flat, &spec), Err(StepError::NoStep));
        let mut bad = curve(10.0, &[0.0, 5.0, 10.0], &[]);
        bad[1].actual = f64::NAN;
        assert_eq!(
            step_figures(&bad, &spec),
            Err(StepError::NotFinite { index: 1 })
        );
        let mut backwards = curve(10.0, &[0.0, 5.0, 10.0], &[]);
        backwards[2].time = 0.0;
        let err = step_figures(&backwards, &spec).expect_err("time");
        assert_eq!(err, StepError::TimeNotIncreasing { index: 2 });
        assert!(err.to_string().contains("sample 2"));
        let negative = StepSpec { band: -1.0, ..spec };
        let err = step_figures(&curve(10.0, &[0.0, 10.0], &[]), &negative).expect_err("band");
        assert!(err.to_string().contains("settling band"), "{err}");
    }
}
