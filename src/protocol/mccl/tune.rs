//! A servo step-response test on a MultiFlex axis, as MCCL lines (pure: no
//! I/O). The runner sends, in order and each on its own success:
//!
//! 1. [`StepTest::setup_lines`]: the gains (Ch5 SG, SD, FR, SI, IL, VG, AG,
//!    DG), the loop rate (Ch5 HS/MS/LS), the following error limit (Ch5
//!    SE), the mode (Ch6 GM: no profile, a true step; or PM with SV, SA,
//!    DS), and the motor on (Ch7 MN);
//! 2. [`StepTest::step_line`]: arm the recording (Ch7 PR n), a short lead
//!    so the first samples show the axis standing, the move (Ch7 MR d), as
//!    the manual's own `3PR10,3MA5000,3WS.1`;
//! 3. [`StepTest::wait_line`]: wait (Ch10 WA) until the n samples are
//!    taken, n × the sample period of HS/MS/LS and the lead;
//! 4. [`StepTest::readback_lines`]: `aDRi,aDOi,aDQi` for every sample
//!    (Ch8 DR actual position, DO optimal position, DQ command output),
//!    a few samples a line;
//!
//! and reads the reply lines with [`parse_readback`] into samples for
//! [`crate::protocol::step_response::step_figures`].
//!
//! Around it: [`read_gains_line`] / [`parse_gains`] read the axis' own
//! gains first (the Tell commands of Ch8: TG, TD, TI, TL, TK), and
//! [`StepTest::restore_lines`] puts them back with position mode (Ch6 PM);
//! [`StepTest::stop_line`] (Ch7 MF, motor off) is for a run that fails or
//! is cancelled, so that no axis is left moving.
//!
//! The sample period is the loop's: 0.25 ms after HS (4 kHz), 0.5 ms after
//! MS (2 kHz), 1 ms after LS (1 kHz) (Ch5 HS/MS/LS; FR's default period of
//! 0.00025 s is one HS sample).

use crate::protocol::mccl::line::NumberBase;
use crate::protocol::mccl::reply::parse_told;
use crate::protocol::step_response::StepSample;

/// The most samples PR records (Ch7 PR: n ≤ 1024).
pub const MOST_SAMPLES: usize = 1024;

/// Samples read back per line (3 commands each, well inside a line).
pub const SAMPLES_PER_LINE: usize = 8;

/// Seconds recorded before the move, so the response starts standing.
pub const LEAD_SECONDS: f64 = 0.002;

/// The servo loop rate (Ch5 HS, MS, LS).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LoopRate {
    /// HS: 4 kHz.
    High,
    /// MS: 2 kHz.
    Medium,
    /// LS: 1 kHz.
    Low,
}

impl LoopRate {
    pub fn hz(self) -> f64 {
        match self {
            LoopRate::High => 4000.0,
            LoopRate::Medium => 2000.0,
            LoopRate::Low => 1000.0,
        }
    }

    /// Seconds between loop samples (and PR samples).
    pub fn sample_period(self) -> f64 {
        1.0 / self.hz()
    }

    pub fn mnemonic(self) -> &'static str {
        match self {
            LoopRate::High => "HS",
            LoopRate::Medium => "MS",
            LoopRate::Low => "LS",
        }
    }
}

/// The gains to set; `None` leaves the axis' own.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Gains {
    /// SG, V/count (0.000153 … 10).
    pub proportional: Option<f64>,
    /// SD (≥ 0).
    pub derivative: Option<f64>,
    /// FR: the derivative period is (n + 1) samples.
    pub derivative_period: Option<u32>,
    /// SI (≥ 0).
    pub integral: Option<f64>,
    /// IL, counts × samples (≥ 0; SI does nothing while it is 0).
    pub integration_limit: Option<f64>,
    /// VG, V per count/s.
    pub velocity_feed_forward: Option<f64>,
    /// AG, V per count/s².
    pub acceleration_feed_forward: Option<f64>,
    /// DG, V per count/s².
    pub deceleration_feed_forward: Option<f64>,
}

/// How the step is made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepKind {
    /// Gain mode (Ch6 GM): "no velocity profile": the optimal position
    /// jumps to the target, a true step.
    Gain,
    /// Position mode with a trapezoid at this velocity (counts/s) and
    /// acceleration = deceleration (counts/s²).
    Profiled { velocity: f64, acceleration: f64 },
}

/// One step-response test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepTest {
    pub axis: u8,
    pub gains: Gains,
    pub rate: LoopRate,
    /// The step, counts (MR).
    pub distance: i64,
    /// PR n (1 … 1024).
    pub samples: usize,
    /// SE, counts; `None` leaves the axis' own; 0 turns the check off.
    pub following_limit: Option<f64>,
    pub kind: StepKind,
}

/// A real as MCCL takes it: decimal, no exponent.
fn real(x: f64) -> String {
    format!("{x}")
}

fn at_least(name: &str, mnemonic: &str, value: Option<f64>, low: f64) -> Result<(), String> {
    match value {
        Some(v) if !v.is_finite() || v < low => Err(format!(
            "{name} ({mnemonic}) must be a number ≥ {low}, not {v}"
        )),
        _ => Ok(()),
    }
}

fn finite(name: &str, mnemonic: &str, value: Option<f64>) -> Result<(), String> {
    match value {
        Some(v) if !v.is_finite() => Err(format!("{name} ({mnemonic}) must be a number, not {v}")),
        _ => Ok(()),
    }
}

/// `aSGn,aSDn,…` for the gains given, in Ch5's order; empty if none.
fn gains_commands(a: u8, g: &Gains) -> String {
    [
        ("SG", g.proportional),
        ("SD", g.derivative),
        ("FR", g.derivative_period.map(f64::from)),
        ("SI", g.integral),
        ("IL", g.integration_limit),
        ("VG", g.velocity_feed_forward),
        ("AG", g.acceleration_feed_forward),
        ("DG", g.deceleration_feed_forward),
    ]
    .iter()
    .filter_map(|(m, v)| v.map(|v| format!("{a}{m}{}", real(v))))
    .collect::<Vec<_>>()
    .join(",")
}

impl StepTest {
    /// Every value within what the manual allows (Ch5, Ch7), and the step
    /// possible: a gain-mode step beyond SE would trip at once.
    pub fn validate(&self) -> Result<(), String> {
        if self.axis == 0 {
            return Err("the axis must be 1 or more (0 would mean every axis)".into());
        }
        let g = &self.gains;
        if let Some(sg) = g.proportional
            && !(sg.is_finite() && (0.000153..=10.0).contains(&sg))
        {
            return Err(format!(
                "the proportional gain (SG) must be within 0.000153 … 10 V/count, not {sg}"
            ));
        }
        at_least("the derivative gain", "SD", g.derivative, 0.0)?;
        at_least("the integral gain", "SI", g.integral, 0.0)?;
        at_least("the integration limit", "IL", g.integration_limit, 0.0)?;
        finite("the velocity feed-forward", "VG", g.velocity_feed_forward)?;
        finite(
            "the acceleration feed-forward",
            "AG",
            g.acceleration_feed_forward,
        )?;
        finite(
            "the deceleration feed-forward",
            "DG",
            g.deceleration_feed_forward,
        )?;
        at_least("the following error limit", "SE", self.following_limit, 0.0)?;
        if self.distance == 0 {
            return Err("the step must be a distance other than 0 counts".into());
        }
        if i32::try_from(self.distance).is_err() {
            return Err(format!(
                "the step of {} counts is beyond the 32-bit position range",
                self.distance
            ));
        }
        if !(1..=MOST_SAMPLES).contains(&self.samples) {
            return Err(format!(
                "the recording must be 1 … {MOST_SAMPLES} samples (PR), not {}",
                self.samples
            ));
        }
        match self.kind {
            StepKind::Gain => {
                if let Some(limit) = self.following_limit
                    && limit > 0.0
                    && self.distance.unsigned_abs() as f64 > limit
                {
                    return Err(format!(
                        "a gain-mode step of {} counts is beyond the following error limit \
                         (SE {limit}): the axis would trip at once",
                        self.distance
                    ));
                }
            }
            StepKind::Profiled {
                velocity,
                acceleration,
            } => {
                if !(velocity.is_finite() && velocity > 0.0) {
                    return Err(format!(
                        "the step's velocity (SV) must be a number > 0 counts/s, not {velocity}"
                    ));
                }
                if !(acceleration.is_finite() && acceleration > 0.0) {
                    return Err(format!(
                        "the step's acceleration (SA, DS) must be a number > 0 counts/s², \
                         not {acceleration}"
                    ));
                }
            }
        }
        Ok(())
    }

    /// Gains, loop rate, SE, mode, motor on: one line each.
    pub fn setup_lines(&self) -> Result<Vec<String>, String> {
        self.validate()?;
        let a = self.axis;
        let gains = gains_commands(a, &self.gains);
        let mut lines = Vec::new();
        if !gains.is_empty() {
            lines.push(gains);
        }
        lines.push(format!("{a}{}", self.rate.mnemonic()));
        if let Some(limit) = self.following_limit {
            lines.push(format!("{a}SE{}", real(limit)));
        }
        lines.push(match self.kind {
            StepKind::Gain => format!("{a}GM"),
            StepKind::Profiled {
                velocity,
                acceleration,
            } => format!(
                "{a}PM,{a}SV{},{a}SA{},{a}DS{}",
                real(velocity),
                real(acceleration),
                real(acceleration)
            ),
        });
        lines.push(format!("{a}MN"));
        Ok(lines)
    }

    /// Arm PR, wait the lead, make the step.
    pub fn step_line(&self) -> String {
        let a = self.axis;
        format!(
            "{a}PR{},WA{},{a}MR{}",
            self.samples,
            real(LEAD_SECONDS),
            self.distance
        )
    }

    /// Seconds the recording takes.
    pub fn recording_seconds(&self) -> f64 {
        self.samples as f64 * self.rate.sample_period()
    }

    /// Wait until every sample is taken (whole milliseconds, one more for
    /// the sample under way).
    pub fn wait_line(&self) -> String {
        let ms = (self.recording_seconds() * 1000.0).ceil() + 1.0;
        format!("WA{}", real(ms / 1000.0))
    }

    /// `aDRi,aDOi,aDQi` for every sample, [`SAMPLES_PER_LINE`] a line.
    pub fn readback_lines(&self) -> Vec<String> {
        let a = self.axis;
        (0..self.samples)
            .collect::<Vec<_>>()
            .chunks(SAMPLES_PER_LINE)
            .map(|chunk| {
                chunk
                    .iter()
                    .map(|i| format!("{a}DR{i},{a}DO{i},{a}DQ{i}"))
                    .collect::<Vec<_>>()
                    .join(",")
            })
            .collect()
    }

    /// Back to position mode with `previous` gains (as [`parse_gains`]
    /// read them): the gains line if any, then `aPM`. A gain of SG below
    /// the manual's 0.000153 (a 5-decimal read of a smaller one) is left
    /// out rather than sent out of range.
    pub fn restore_lines(&self, previous: &Gains) -> Vec<String> {
        let a = self.axis;
        let mut kept = *previous;
        kept.proportional = kept.proportional.filter(|&sg| sg >= 0.000153);
        let mut lines = Vec::new();
        let gains = gains_commands(a, &kept);
        if !gains.is_empty() {
            lines.push(gains);
        }
        lines.push(format!("{a}PM"));
        lines
    }

    /// Motor off (Ch7 MF): what a failed or cancelled run sends, so that no
    /// axis is left moving (a tripped axis is off already).
    pub fn stop_line(&self) -> String {
        format!("{}MF", self.axis)
    }

    /// Read the replies of [`StepTest::readback_lines`] (their reply lines,
    /// in order, prompts and echoes removed).
    pub fn parse_readback<S: AsRef<str>>(
        &self,
        replies: &[S],
        base: NumberBase,
    ) -> Result<Vec<StepSample>, String> {
        parse_readback(replies, self.samples, self.rate, base)
    }
}

/// The Tell precision used to read gains back: 5 decimals (Ch8 `p` = .5,
/// the most the manual shows).
pub const GAIN_PRECISION: &str = ".5";

/// `aTG.5,aTD.5,aTI.5,aTL.5,aTK.5`: the gains a Tell command reports (Ch8:
/// FR, AG and DG have none).
pub fn read_gains_line(axis: u8) -> String {
    ["TG", "TD", "TI", "TL", "TK"]
        .iter()
        .map(|m| format!("{axis}{m}{GAIN_PRECISION}"))
        .collect::<Vec<_>>()
        .join(",")
}

/// The five replies of [`read_gains_line`], in its order.
pub fn parse_gains<S: AsRef<str>>(replies: &[S], base: NumberBase) -> Result<Gains, String> {
    const WHAT: [&str; 5] = [
        "TG (proportional gain)",
        "TD (derivative gain)",
        "TI (integral gain)",
        "TL (integration limit)",
        "TK (velocity gain)",
    ];
    if replies.len() != WHAT.len() {
        return Err(format!(
            "reading the gains back needs 5 reply lines (TG, TD, TI, TL, TK), got {}",
            replies.len()
        ));
    }
    let mut values = [0.0; 5];
    for (k, reply) in replies.iter().enumerate() {
        values[k] = parse_told(reply.as_ref(), base)
            .map_err(|e| format!("{}: {e}", WHAT[k]))?
            .value
            .as_f64();
    }
    Ok(Gains {
        proportional: Some(values[0]),
        derivative: Some(values[1]),
        integral: Some(values[2]),
        integration_limit: Some(values[3]),
        velocity_feed_forward: Some(values[4]),
        ..Gains::default()
    })
}

/// `count` samples from reply lines in the order DR i, DO i, DQ i for i =
/// 0, 1, …; sample i at i × the loop's sample period. Each reply is a Tell
/// line (`01 1234`, Ch8; the bare value too); DR and DO in counts, DQ in
/// volts.
pub fn parse_readback<S: AsRef<str>>(
    replies: &[S],
    count: usize,
    rate: LoopRate,
    base: NumberBase,
) -> Result<Vec<StepSample>, String> {
    if replies.len() != 3 * count {
        return Err(format!(
            "{count} samples need {} reply lines (DR, DO, DQ each), got {}",
            3 * count,
            replies.len()
        ));
    }
    const WHAT: [&str; 3] = [
        "DR (actual position)",
        "DO (optimal position)",
        "DQ (output)",
    ];
    let period = rate.sample_period();
    replies
        .chunks(3)
        .enumerate()
        .map(|(i, three)| {
            let mut values = [0.0; 3];
            for (k, reply) in three.iter().enumerate() {
                let told = parse_told(reply.as_ref(), base)
                    .map_err(|e| format!("sample {i}, {}: {e}", WHAT[k]))?;
                values[k] = told.value.as_f64();
            }
            Ok(StepSample {
                time: i as f64 * period,
                actual: values[0],
                commanded: values[1],
                output: values[2],
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn test() -> StepTest {
        StepTest {
            axis: 1,
            gains: Gains {
                // Ch5 SG's example: 1sg.04, 1sd.2, 1fr7, 1si.0065, 1il50.
                proportional: Some(0.04),
                derivative: Some(0.2),
                derivative_period: Some(7),
                integral: Some(0.0065),
                integration_limit: Some(50.0),
                // Ch5 VG, AG, DG examples.
                velocity_feed_forward: Some(-0.00009),
                acceleration_feed_forward: Some(-0.00002),
                deceleration_feed_forward: Some(-0.00002),
            },
            rate: LoopRate::High,
            distance: 20,
            samples: 20,
            following_limit: Some(1024.0),
            kind: StepKind::Gain,
        }
    }

    #[test]
    fn the_lines_are_the_manuals_commands() {
        let t = test();
        assert_eq!(
            t.setup_lines().expect("valid"),
            [
                "1SG0.04,1SD0.2,1FR7,1SI0.0065,1IL50,1VG-0.00009,1AG-0.00002,1DG-0.00002",
                "1HS",
                "1SE1024",
                "1GM",
                "1MN",
            ]
        );
        assert_eq!(t.step_line(), "1PR20,WA0.002,1MR20");
        // 20 samples at 4 kHz: 5 ms, and one more.
        assert_eq!(t.wait_line(), "WA0.006");
        let lines = t.readback_lines();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with("1DR0,1DO0,1DQ0,1DR1,1DO1,1DQ1,"));
        assert_eq!(
            lines[2],
            "1DR16,1DO16,1DQ16,1DR17,1DO17,1DQ17,1DR18,1DO18,1DQ18,1DR19,1DO19,1DQ19"
        );
        let profiled = StepTest {
            gains: Gains::default(),
            rate: LoopRate::Low,
            following_limit: None,
            kind: StepKind::Profiled {
                velocity: 100_000.0,
                acceleration: 200_000.0,
            },
            ..t
        };
        assert_eq!(
            profiled.setup_lines().expect("valid"),
            ["1LS", "1PM,1SV100000,1SA200000,1DS200000", "1MN"]
        );
    }

    #[test]
    fn the_sample_period_follows_the_loop_rate() {
        // Ch5 HS 4 kHz, MS 2 kHz, LS 1 kHz; FR7 "2 msec" = 8 HS samples.
        assert_eq!(LoopRate::High.sample_period(), 0.00025);
        assert_eq!(LoopRate::Medium.sample_period(), 0.0005);
        assert_eq!(LoopRate::Low.sample_period(), 0.001);
        assert_eq!(8.0 * LoopRate::High.sample_period(), 0.002);
        let t = StepTest {
            rate: LoopRate::Medium,
            samples: 1000,
            ..test()
        };
        assert_eq!(t.recording_seconds(), 0.5);
    }

    #[test]
    fn bad_values_are_refused_with_their_name() {
        let cases: Vec<(StepTest, &str)> = vec![
            (
                StepTest {
                    gains: Gains {
                        proportional: Some(11.0),
                        ..Gains::default()
                    },
                    ..test()
                },
                "SG",
            ),
            (
                StepTest {
                    gains: Gains {
                        derivative: Some(-0.1),
                        ..Gains::default()
                    },
                    ..test()
                },
                "SD",
            ),
            (
                StepTest {
                    gains: Gains {
                        velocity_feed_forward: Some(f64::NAN),
                        ..Gains::default()
                    },
                    ..test()
                },
                "VG",
            ),
            (
                StepTest {
                    samples: 1025,
                    ..test()
                },
                "PR",
            ),
            (
                StepTest {
                    samples: 0,
                    ..test()
                },
                "PR",
            ),
            (
                StepTest {
                    distance: 0,
                    ..test()
                },
                "other than 0",
            ),
            (
                StepTest {
                    distance: 2000,
                    ..test()
                },
                "SE 1024",
            ),
            (StepTest { axis: 0, ..test() }, "axis"),
            (
                StepTest {
                    kind: StepKind::Profiled {
                        velocity: 0.0,
                        acceleration: 1.0,
                    },
                    ..test()
                },
                "SV",
            ),
        ];
        for (t, named) in cases {
            let err = t.setup_lines().expect_err(named);
            assert!(err.contains(named), "{err} should name {named}");
        }
    }

    #[test]
    fn replies_in_the_manuals_tell_form_become_samples() {
        // Ch8: a Tell reply is the 2-digit axis and the value (`01 512`);
        // DQ prints volts.
        let replies = [
            "01 0", "01 0", "01 0.000", //
            "01 0", "01 20", "01 4.800", //
            "01 3", "01 20", "01 3.480", //
        ];
        let t = StepTest {
            samples: 3,
            ..test()
        };
        let samples = t
            .parse_readback(&replies, NumberBase::Decimal)
            .expect("samples");
        assert_eq!(samples.len(), 3);
        assert_eq!(
            samples[1],
            StepSample {
                time: 0.00025,
                commanded: 20.0,
                actual: 0.0,
                output: 4.8
            }
        );
        assert_eq!(samples[2].actual, 3.0);
        assert_eq!(samples[2].time, 0.0005);
        // Bare values (no axis field) read the same.
        let bare = ["0", "0", "0", "0", "20", "4.8", "3", "20", "3.48"];
        assert_eq!(
            t.parse_readback(&bare, NumberBase::Decimal)
                .expect("samples"),
            samples
        );
        // After HM (Ch8) integers are hex.
        let hex = [
            "01 0", "01 0", "01 0", "01 0", "01 14", "01 4.8", "01 3", "01 14", "01 3.48",
        ];
        assert_eq!(
            t.parse_readback(&hex, NumberBase::Hex).expect("samples")[1].commanded,
            20.0
        );
    }

    #[test]
    fn the_gains_are_read_back_and_restored() {
        assert_eq!(read_gains_line(2), "2TG.5,2TD.5,2TI.5,2TL.5,2TK.5");
        // Ch8's Tell form with 5 decimals, the values of Ch5's examples.
        let replies = [
            "02 0.04000",
            "02 0.20000",
            "02 0.00650",
            "02 50.00000",
            "02 -0.00009",
        ];
        let gains = parse_gains(&replies, NumberBase::Decimal).expect("gains");
        assert_eq!(gains.proportional, Some(0.04));
        assert_eq!(gains.integration_limit, Some(50.0));
        assert_eq!(gains.velocity_feed_forward, Some(-0.00009));
        assert_eq!(gains.derivative_period, None, "FR has no Tell");
        let t = StepTest { axis: 2, ..test() };
        assert_eq!(
            t.restore_lines(&gains),
            ["2SG0.04,2SD0.2,2SI0.0065,2IL50,2VG-0.00009", "2PM"]
        );
        assert_eq!(t.stop_line(), "2MF");
        let err = parse_gains(&replies[..4], NumberBase::Decimal).expect_err("short");
        assert!(err.contains("5 reply lines"), "{err}");
        let bad = ["02 0.04", "?-2 2TD", "0", "0", "0"];
        let err = parse_gains(&bad, NumberBase::Decimal).expect_err("bad");
        assert!(err.contains("TD"), "{err}");
    }

    #[test]
    fn a_bad_reply_names_its_sample_and_command() {
        let t = StepTest {
            samples: 2,
            ..test()
        };
        let short = ["01 0", "01 0", "01 0"];
        let err = t
            .parse_readback(&short, NumberBase::Decimal)
            .expect_err("count");
        assert!(err.contains("6 reply lines"), "{err}");
        let bad = ["01 0", "01 0", "01 0", "01 1", "01 20", "?-1 1DQ1"];
        let err = t
            .parse_readback(&bad, NumberBase::Decimal)
            .expect_err("bad");
        assert!(err.contains("sample 1") && err.contains("DQ"), "{err}");
    }
}
