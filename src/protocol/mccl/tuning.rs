//! The MultiFlex servo step response as the tuning tools take it
//! ([`crate::protocol::tuning::StepResponsePlan`]): the lines and the
//! read-back parser of [`super::tune`].
//!
//! The step is a gain-mode step (Ch6 GM: "no velocity profile", the
//! optimal position jumps to the target), recorded by PR at the loop rate;
//! the loop rate is HS (4 kHz, the rate of FR's default period) unless
//! `--set LOOP=2000` (MS) or `LOOP=1000` (LS) asks for another; `SE`
//! sets the following error limit the step may trip. Gains set
//! stay set; the axis goes back to position mode (PM) after the test, or
//! off (MF) if the test fails or is cancelled.

use std::time::Duration;

use super::line::NumberBase;
use super::tune::{self, Gains, LoopRate, StepKind, StepTest};
use crate::protocol::console::AxisInfo;
use crate::protocol::tuning::{
    StepAsk, StepResponsePlan, StepSample, StepScript, TuneError, TuningField,
};

pub struct McclStepResponse;

/// The gains of Ch5, in its order, and the loop rate.
const GAINS: &[TuningField] = &[
    TuningField {
        name: "SG",
        meaning: "proportional gain, V per count of following error (Ch5 SG)",
    },
    TuningField {
        name: "SD",
        meaning: "derivative gain: damps oscillation (Ch5 SD)",
    },
    TuningField {
        name: "FR",
        meaning: "derivative sampling period, n+1 loop samples (Ch5 FR)",
    },
    TuningField {
        name: "SI",
        meaning: "integral gain: removes a steady error (Ch5 SI)",
    },
    TuningField {
        name: "IL",
        meaning: "integration limit; SI does nothing while it is 0 (Ch5 IL)",
    },
    TuningField {
        name: "VG",
        meaning: "velocity feed-forward, V per count/s (Ch5 VG)",
    },
    TuningField {
        name: "AG",
        meaning: "acceleration feed-forward (Ch5 AG)",
    },
    TuningField {
        name: "DG",
        meaning: "deceleration feed-forward (Ch5 DG)",
    },
    TuningField {
        name: "SE",
        meaning: "following error limit, counts; beyond it the axis trips, motor off (Ch5 SE)",
    },
    TuningField {
        name: "LOOP",
        meaning: "loop rate, Hz: 4000 (HS), 2000 (MS), 1000 (LS) (Ch5 HS/MS/LS)",
    },
];

/// The amplifier's range (Ch5: a ±10 V analog command).
const OUTPUT_LIMIT: f64 = 10.0;

/// `ask` as a [`StepTest`] for `axis`.
fn test_of(axis: &AxisInfo, ask: &StepAsk) -> Result<StepTest, TuneError> {
    let mut gains = Gains::default();
    let mut rate = LoopRate::High;
    let mut following_limit = None;
    for (name, value) in &ask.set {
        let value = *value;
        match name.to_ascii_uppercase().as_str() {
            "SG" => gains.proportional = Some(value),
            "SD" => gains.derivative = Some(value),
            "FR" => {
                if !(value >= 0.0 && value.fract() == 0.0 && value <= f64::from(u32::MAX)) {
                    return Err(TuneError::Refused(format!(
                        "FR (the derivative period) is a whole number of samples ≥ 0, not {value}"
                    )));
                }
                gains.derivative_period = Some(value as u32);
            }
            "SI" => gains.integral = Some(value),
            "IL" => gains.integration_limit = Some(value),
            "VG" => gains.velocity_feed_forward = Some(value),
            "AG" => gains.acceleration_feed_forward = Some(value),
            "DG" => gains.deceleration_feed_forward = Some(value),
            "SE" => following_limit = Some(value),
            "LOOP" => {
                rate = match value {
                    4000.0 => LoopRate::High,
                    2000.0 => LoopRate::Medium,
                    1000.0 => LoopRate::Low,
                    _ => {
                        return Err(TuneError::Refused(format!(
                            "LOOP is the loop rate in Hz, 4000 (HS), 2000 (MS) or 1000 (LS), \
                             not {value}"
                        )));
                    }
                }
            }
            _ => {
                return Err(TuneError::UnknownGain {
                    name: name.clone(),
                    known: GAINS.iter().map(|g| g.name).collect::<Vec<_>>().join(", "),
                });
            }
        }
    }
    let test = StepTest {
        axis: axis.number,
        gains,
        rate,
        distance: ask.distance,
        samples: ask.samples,
        following_limit,
        kind: StepKind::Gain,
    };
    test.validate().map_err(TuneError::Refused)?;
    Ok(test)
}

/// Each value of a line's answer: a line of several Tells answers with
/// their values in order, space-separated.
fn values(answers: &[String]) -> Vec<String> {
    answers
        .iter()
        .flat_map(|a| a.split_whitespace().map(str::to_string))
        .collect()
}

impl StepResponsePlan for McclStepResponse {
    fn gains(&self) -> &'static [TuningField] {
        GAINS
    }

    fn read_gains(&self, axis: &AxisInfo) -> Vec<String> {
        vec![tune::read_gains_line(axis.number)]
    }

    fn parse_gains(&self, answers: &[String]) -> Result<Vec<Option<f64>>, TuneError> {
        let line = tune::read_gains_line(0);
        let gains = tune::parse_gains(&values(answers), NumberBase::Decimal).map_err(|reason| {
            TuneError::Answer {
                line: line.clone(),
                reason,
            }
        })?;
        // FR, AG, DG and the loop rate have no Tell command (Ch8).
        Ok(vec![
            gains.proportional,
            gains.derivative,
            None,
            gains.integral,
            gains.integration_limit,
            gains.velocity_feed_forward,
            None,
            None,
            None,
            None,
        ])
    }

    fn script(&self, axis: &AxisInfo, ask: &StepAsk) -> Result<StepScript, TuneError> {
        let test = test_of(axis, ask)?;
        Ok(StepScript {
            setup: test.setup_lines().map_err(TuneError::Refused)?,
            step: vec![test.step_line()],
            // The lead before the step is inside the recording.
            recording: Duration::from_secs_f64(test.recording_seconds()) + Duration::from_millis(1),
            readback: test.readback_lines(),
            restore: test.restore_lines(&Gains::default()),
            stop: vec![test.stop_line()],
            sample_period: test.rate.sample_period(),
            output_limit: OUTPUT_LIMIT,
        })
    }

    fn samples(
        &self,
        _script: &StepScript,
        ask: &StepAsk,
        answers: &[String],
    ) -> Result<Vec<StepSample>, TuneError> {
        let test = test_of(
            &AxisInfo {
                number: 1,
                name: "",
            },
            ask,
        )?;
        test.parse_readback(&values(answers), NumberBase::Decimal)
            .map_err(|reason| TuneError::Answer {
                line: "the read-back (DR, DO, DQ)".into(),
                reason,
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::console::FamilyConsole;
    use crate::protocol::mccl::MclConsole;

    const AXIS: AxisInfo = AxisInfo {
        number: 2,
        name: "axis 2",
    };

    fn ask(set: &[(&str, f64)]) -> StepAsk {
        StepAsk {
            distance: 100,
            samples: 16,
            set: set.iter().map(|(n, v)| (n.to_string(), *v)).collect(),
        }
    }

    #[test]
    fn the_script_is_lines_the_console_takes() {
        let script = McclStepResponse
            .script(&AXIS, &ask(&[("SG", 0.05), ("sd", 0.3), ("LOOP", 2000.0)]))
            .expect("a script");
        assert_eq!(script.setup[0], "2SG0.05,2SD0.3");
        assert!(script.setup.contains(&"2MS".to_string()), "{script:?}");
        assert_eq!(script.sample_period, 0.0005);
        assert_eq!(script.readback.len(), 2);
        assert_eq!(script.restore, ["2PM"]);
        assert_eq!(script.stop, ["2MF"]);
        let console = MclConsole::DEFAULT;
        let address = console.default_address();
        for line in script
            .setup
            .iter()
            .chain(&script.step)
            .chain(&script.readback)
            .chain(&script.restore)
            .chain(&script.stop)
            .chain(&McclStepResponse.read_gains(&AXIS))
        {
            assert!(console.prepare(line, address).is_ok(), "{line}");
        }
    }

    #[test]
    fn an_unknown_gain_or_rate_is_named() {
        let error = McclStepResponse
            .script(&AXIS, &ask(&[("KP", 1.0)]))
            .unwrap_err();
        assert!(error.to_string().starts_with("KP is not a gain"), "{error}");
        let error = McclStepResponse
            .script(&AXIS, &ask(&[("LOOP", 3000.0)]))
            .unwrap_err();
        assert!(error.to_string().contains("not 3000"), "{error}");
        let error = McclStepResponse
            .script(&AXIS, &ask(&[("SG", 11.0)]))
            .unwrap_err();
        assert!(error.to_string().contains("SG"), "{error}");
    }

    #[test]
    fn gains_read_in_field_order_and_samples_from_space_separated_answers() {
        let gains = McclStepResponse
            .parse_gains(&["0.04000 0.20000 0.00000 0.00000 0.00000".to_string()])
            .expect("gains");
        assert_eq!(gains[0], Some(0.04));
        assert_eq!(gains[1], Some(0.2));
        assert_eq!(gains[2], None);
        assert_eq!(gains.len(), GAINS.len());
        let one = StepAsk {
            samples: 2,
            ..ask(&[])
        };
        let script = McclStepResponse.script(&AXIS, &one).expect("a script");
        let samples = McclStepResponse
            .samples(&script, &one, &["0 0 1.5 3 10 2.25".to_string()])
            .expect("samples");
        assert_eq!(samples.len(), 2);
        assert_eq!(samples[1].actual, 3.0);
        assert_eq!(samples[1].commanded, 10.0);
        assert_eq!(samples[1].output, 2.25);
        assert_eq!(samples[1].time, 0.00025);
    }
}
