//! Tuning StallGuard2 and CoolStep on the TMCM-1110 (§1.1, §4, §7.2, §7.3):
//! pure plans, no I/O. A session runner sends what these give and hands the
//! readings back; nothing here talks to a device.
//!
//! - [`SweepPlan`]: run the motor at a list of speeds and read the
//!   StallGuard2 load value AP206 a few times at each, then stop.
//! - [`suggest`]: from sweeps without and with load, a stop-on-stall speed
//!   AP181 and a StallGuard2 threshold AP174, with the reasoning as lines.
//! - [`COOLSTEP_FORM`]: the CoolStep parameters as a form, one line of the
//!   manual's meaning and its range each, and [`coolstep_write`] to turn an
//!   entry into a checked `SAP`.

use std::fmt;

use super::Command;

/// Highest speed ROR/ROL take (§3.6.1, §3.6.2: −2047..2047 [int]).
pub const MAX_VELOCITY: i32 = 2047;

/// AP174's range (§4: −64..+63).
pub const THRESHOLD_RANGE: (i32, i32) = (-64, 63);

/// Which way the sweep turns the motor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// ROR: the position counter increases.
    Right,
    /// ROL.
    Left,
}

/// What a sweep is asked for: speeds `from`..=`to` [int] in `steps` speeds,
/// `samples` readings of AP206 at each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SweepSpec {
    pub motor: u8,
    pub direction: Direction,
    pub from: i32,
    pub to: i32,
    pub steps: u32,
    pub samples: u32,
}

/// Why a [`SweepSpec`] gives no plan.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SweepError {
    /// A speed outside 1..=2047 [int].
    Speed { which: &'static str, value: i32 },
    /// Zero steps or zero samples.
    Zero { which: &'static str },
    /// More steps than there are whole speeds between the ends.
    TooManySteps { steps: u32, most: u32 },
    /// A single step needs `from` = `to`.
    OneStepTwoSpeeds { from: i32, to: i32 },
}

impl fmt::Display for SweepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SweepError::Speed { which, value } => write!(
                f,
                "{which} speed {value} is outside 1..{MAX_VELOCITY} [int] (the sweep's direction gives ROR or ROL, and 0 does not turn)"
            ),
            SweepError::Zero { which } => write!(f, "{which} must be at least 1"),
            SweepError::TooManySteps { steps, most } => write!(
                f,
                "{steps} steps would repeat speeds: there are only {most} whole speeds between the ends"
            ),
            SweepError::OneStepTwoSpeeds { from, to } => write!(
                f,
                "one step cannot cover {from}..{to}: give 2 or more steps, or the same speed twice"
            ),
        }
    }
}

impl std::error::Error for SweepError {}

/// One instruction of a sweep, in the order the runner carries them out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SweepInstruction {
    /// Send the command; it must be answered with success (status 100)
    /// before the next instruction.
    Send(Command),
    /// Send `poll` (GAP 3, actual speed) until [`speed_reached`] holds for
    /// its value and `speed`. AP8 does not serve here: §4 sets it when the
    /// target *position* equals the actual one, which says nothing in
    /// velocity mode.
    WaitForSpeed { poll: Command, speed: i32 },
    /// Send `read` (GAP 206) and keep its value as sample `sample` of the
    /// speed at `point`.
    Sample {
        point: usize,
        sample: u32,
        read: Command,
    },
}

/// One speed of a sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SweepPoint {
    /// The speed [int] (positive; [`SweepSpec::direction`] gives the way).
    pub velocity: i32,
    /// ROR or ROL at `velocity`.
    pub start: Command,
}

/// A StallGuard2 sweep: for each speed, ROR/ROL it, wait until AP3 shows it,
/// read AP206 `samples` times; MST at the end.
///
/// A run that fails or is cancelled must still send [`SweepPlan::stop`]:
/// the motor turns in velocity mode until told otherwise.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SweepPlan {
    pub motor: u8,
    pub samples: u32,
    pub points: Vec<SweepPoint>,
}

impl SweepPlan {
    /// Check `spec` and lay out its speeds: `steps` speeds from `from` to
    /// `to` (either may be the higher), evenly spaced and rounded to whole
    /// [int], both ends included.
    pub fn new(spec: &SweepSpec) -> Result<Self, SweepError> {
        for (which, value) in [("from", spec.from), ("to", spec.to)] {
            if !(1..=MAX_VELOCITY).contains(&value) {
                return Err(SweepError::Speed { which, value });
            }
        }
        if spec.steps == 0 {
            return Err(SweepError::Zero { which: "steps" });
        }
        if spec.samples == 0 {
            return Err(SweepError::Zero { which: "samples" });
        }
        let span = spec.to - spec.from;
        let most = span.unsigned_abs() + 1;
        if spec.steps == 1 && span != 0 {
            return Err(SweepError::OneStepTwoSpeeds {
                from: spec.from,
                to: spec.to,
            });
        }
        if spec.steps > most && span != 0 {
            return Err(SweepError::TooManySteps {
                steps: spec.steps,
                most,
            });
        }
        let count = if span == 0 { 1 } else { spec.steps };
        let points = (0..count)
            .map(|i| {
                let velocity = if count == 1 {
                    spec.from
                } else {
                    let t = f64::from(i) / f64::from(count - 1);
                    spec.from + (f64::from(span) * t).round() as i32
                };
                let start = match spec.direction {
                    Direction::Right => Command::Ror {
                        motor: spec.motor,
                        velocity,
                    },
                    Direction::Left => Command::Rol {
                        motor: spec.motor,
                        velocity,
                    },
                };
                SweepPoint { velocity, start }
            })
            .collect();
        Ok(SweepPlan {
            motor: spec.motor,
            samples: spec.samples,
            points,
        })
    }

    /// The speeds, in sweep order.
    pub fn velocities(&self) -> Vec<i32> {
        self.points.iter().map(|p| p.velocity).collect()
    }

    /// MST: what ends the sweep, and what a failed or cancelled run sends.
    pub fn stop(&self) -> Command {
        Command::Mst { motor: self.motor }
    }

    /// Every instruction of the sweep in order, ending with MST.
    pub fn instructions(&self) -> Vec<SweepInstruction> {
        let poll = Command::Gap {
            param: 3,
            motor: self.motor,
        };
        let read = Command::Gap {
            param: 206,
            motor: self.motor,
        };
        let mut out = Vec::new();
        for (point, p) in self.points.iter().enumerate() {
            out.push(SweepInstruction::Send(p.start));
            out.push(SweepInstruction::WaitForSpeed {
                poll,
                speed: p.velocity,
            });
            out.extend((0..self.samples).map(|sample| SweepInstruction::Sample {
                point,
                sample,
                read,
            }));
        }
        out.push(SweepInstruction::Send(self.stop()));
        out
    }
}

/// AP3 (actual speed, signed by direction) shows the sweep's speed.
pub fn speed_reached(actual: i32, speed: i32) -> bool {
    actual.unsigned_abs() == speed.unsigned_abs()
}

/// The readings of AP206 at one speed, without and with the load.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SpeedReadings {
    pub velocity: i32,
    pub unloaded: Vec<i32>,
    pub loaded: Vec<i32>,
}

/// What [`suggest`] proposes; `None` where the readings allow nothing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Suggestion {
    /// AP181, stop on stall: the lowest speed [int] of the working range.
    pub stop_on_stall_speed: Option<i32>,
    /// AP174, StallGuard2 threshold.
    pub threshold: Option<i32>,
    /// Why, one line each, for the user to read.
    pub reasons: Vec<String>,
}

impl Suggestion {
    /// The SAPs that apply the suggestion (AP174 first, so the stop on stall
    /// is armed with the new threshold).
    pub fn commands(&self, motor: u8) -> Vec<Command> {
        let mut out = Vec::new();
        if let (Some(threshold), Some(speed)) = (self.threshold, self.stop_on_stall_speed) {
            out.push(Command::Sap {
                param: 174,
                motor,
                value: threshold,
            });
            out.push(Command::Sap {
                param: 181,
                motor,
                value: speed,
            });
        }
        out
    }
}

/// How the readings were taken and how far apart they must be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SuggestRules {
    /// AP174 during both sweeps (the readout is relative to it).
    pub threshold_during_sweep: i32,
    /// Least distance, in AP206 counts, between the highest loaded and the
    /// lowest unloaded reading for a speed to count as separable.
    pub min_separation: i32,
    /// AP206 counts one step of AP174 moves the readout by. The manual does
    /// not give this; [`DEFAULT_COUNTS_PER_THRESHOLD_STEP`] is the
    /// simulator's, so on a real motor check the suggestion with a second
    /// sweep at the suggested AP174.
    pub counts_per_threshold_step: i32,
}

/// The simulator's readout shift per AP174 step
/// (`sim::tmcm1110::motion::stallguard::THRESHOLD_STEP`).
pub const DEFAULT_COUNTS_PER_THRESHOLD_STEP: i32 = 16;

/// A distance of 64 counts (1/16 of the 0..1023 range) between loaded and
/// unloaded readings: our choice, well above the sample-to-sample spread.
pub const DEFAULT_MIN_SEPARATION: i32 = 64;

impl Default for SuggestRules {
    fn default() -> Self {
        SuggestRules {
            threshold_during_sweep: 0,
            min_separation: DEFAULT_MIN_SEPARATION,
            counts_per_threshold_step: DEFAULT_COUNTS_PER_THRESHOLD_STEP,
        }
    }
}

/// Suggest AP181 and AP174 from readings per speed with and without load.
///
/// The manual's facts: the reading falls linearly with load and reaches 0 at
/// the maximum load (§1.1, §7.2); the motor is stopped when it reaches 0,
/// and only above the AP181 speed (§4 AP181, §7.3 Table 25); a lower AP174
/// is more sensitive (§4 AP174). The rule built on them:
///
/// 1. The *working range* is the largest set of the fastest speeds, taken
///    downwards from the top, over which the highest loaded reading stays
///    at least `min_separation` below the lowest unloaded one: one
///    threshold then tells load from no load at every speed in it. Slow
///    speeds fall out first, since the reading grows with speed and the
///    two sweeps draw together there.
/// 2. AP181 = the lowest speed of the working range: below it the readings
///    can't be told apart, and there must be no stall detection.
/// 3. The threshold level is halfway between that highest loaded and that
///    lowest unloaded reading. AP174 moves the readout by
///    `counts_per_threshold_step` a step, so AP174 = its sweep value −
///    round(level / step) puts the readout's 0 (the stall output) at that
///    level: the load reads 0 and stops the motor, no load stays above 0.
///    Clamped to −64..63.
pub fn suggest(readings: &[SpeedReadings], rules: &SuggestRules) -> Suggestion {
    let mut reasons = Vec::new();
    let mut speeds: Vec<&SpeedReadings> = readings
        .iter()
        .filter(|r| !r.unloaded.is_empty() && !r.loaded.is_empty())
        .collect();
    if speeds.len() < readings.len() {
        reasons.push(format!(
            "{} speed(s) left out: a sweep without or with load has no reading there",
            readings.len() - speeds.len()
        ));
    }
    speeds.sort_by_key(|r| std::cmp::Reverse(r.velocity.unsigned_abs()));
    let none = |mut reasons: Vec<String>, why: String| {
        reasons.push(why);
        Suggestion {
            stop_on_stall_speed: None,
            threshold: None,
            reasons,
        }
    };
    if speeds.is_empty() {
        return none(
            reasons,
            "no speed has readings both without and with load".into(),
        );
    }
    // Taken downwards from the fastest speed while one level still separates.
    let mut working = 0;
    let mut highest_loaded = i32::MIN;
    let mut lowest_unloaded = i32::MAX;
    for r in &speeds {
        let loaded = highest_loaded.max(*r.loaded.iter().max().unwrap_or(&0));
        let unloaded = lowest_unloaded.min(*r.unloaded.iter().min().unwrap_or(&0));
        if unloaded - loaded < rules.min_separation {
            reasons.push(format!(
                "at {} [int] and below, loaded (up to {}) and unloaded (down to {}) readings are \
                 less than {} apart: no threshold tells them apart there",
                r.velocity.abs(),
                loaded,
                unloaded,
                rules.min_separation
            ));
            break;
        }
        highest_loaded = loaded;
        lowest_unloaded = unloaded;
        working += 1;
    }
    if working == 0 {
        return none(
            reasons,
            "even the fastest speed does not separate load from no load: try a higher load, \
             higher speeds or another current"
                .into(),
        );
    }
    let slowest = speeds[working - 1].velocity.abs();
    let fastest = speeds[0].velocity.abs();
    reasons.push(format!(
        "working range {slowest}..{fastest} [int]: unloaded readings {lowest_unloaded} and up, \
         loaded readings {highest_loaded} and down"
    ));
    reasons.push(format!(
        "AP181 = {slowest}: no stall detection below the working range, where the readings \
         cannot be separated (§4 AP181: below this speed the motor is not stopped)"
    ));
    let level = (highest_loaded + lowest_unloaded) / 2;
    let step = rules.counts_per_threshold_step.max(1);
    let shift = (f64::from(level) / f64::from(step)).round() as i32;
    let raw = rules.threshold_during_sweep - shift;
    let threshold = raw.clamp(THRESHOLD_RANGE.0, THRESHOLD_RANGE.1);
    reasons.push(format!(
        "threshold level {level}, halfway between: AP174 = {} − round({level} / {step}) = {raw}, \
         so that the load reads 0 (stall) and no load stays above 0 (§4 AP174: lower is more \
         sensitive)",
        rules.threshold_during_sweep
    ));
    if threshold != raw {
        reasons.push(format!(
            "AP174 clamped to {threshold}: the parameter takes −64..63 only, so the separation \
             is not where the level says; check with a sweep at AP174 = {threshold}"
        ));
    }
    if step != DEFAULT_COUNTS_PER_THRESHOLD_STEP {
        reasons.push(format!(
            "{step} counts per AP174 step assumed (the manual gives no figure)"
        ));
    } else {
        reasons.push(
            "16 counts per AP174 step is the simulator's figure, the manual gives none: on a \
             real motor sweep again at the suggested AP174 to check"
                .into(),
        );
    }
    Suggestion {
        stop_on_stall_speed: Some(slowest),
        threshold: Some(threshold),
        reasons,
    }
}

/// One CoolStep parameter in the form.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CoolStepField {
    pub number: u8,
    pub name: &'static str,
    /// The manual's meaning, one line.
    pub meaning: &'static str,
    pub min: i32,
    pub max: i32,
    /// False for AP180, a status value.
    pub writable: bool,
}

/// The CoolStep parameters (§4 Table 16, §7.3 Table 25), in the manual's
/// order.
pub const COOLSTEP_FORM: &[CoolStepField] = &[
    CoolStepField {
        number: 168,
        name: "SmartEnergy current minimum (SEIMIN)",
        meaning: "lowest CoolStep current: 0 = 1/2, 1 = 1/4 of the AP6 current",
        min: 0,
        max: 1,
        writable: true,
    },
    CoolStepField {
        number: 169,
        name: "SmartEnergy current down step",
        meaning: "readings above the upper threshold per current decrement: 0..3 = 32, 8, 2, 1",
        min: 0,
        max: 3,
        writable: true,
    },
    CoolStepField {
        number: 170,
        name: "SmartEnergy hysteresis",
        meaning: "distance from the lower to the upper StallGuard2 threshold (in 32s); above the upper the current falls",
        min: 0,
        max: 15,
        writable: true,
    },
    CoolStepField {
        number: 171,
        name: "SmartEnergy current up step",
        meaning: "current increment per reading below the lower threshold: 0..3 = 1, 2, 4, 8",
        min: 0,
        max: 3,
        writable: true,
    },
    CoolStepField {
        number: 172,
        name: "SmartEnergy hysteresis start",
        meaning: "the lower StallGuard2 threshold; 0 (default) turns CoolStep off",
        min: 0,
        max: 15,
        writable: true,
    },
    CoolStepField {
        number: 180,
        name: "SmartEnergy actual current",
        meaning: "the current CoolStep set now, 0..31 = 1/32..32/32, between SEIMIN's portion and the AP6 current",
        min: 0,
        max: 31,
        writable: false,
    },
    CoolStepField {
        number: 182,
        name: "SmartEnergy threshold speed",
        meaning: "above this speed [int] CoolStep becomes enabled",
        min: 0,
        max: 2047,
        writable: true,
    },
    CoolStepField {
        number: 183,
        name: "SmartEnergy slow run current",
        meaning: "motor current below the threshold speed; 255 = 100 % of the module maximum",
        min: 0,
        max: 255,
        writable: true,
    },
];

/// The form's field for `number`.
pub fn coolstep_field(number: u8) -> Option<&'static CoolStepField> {
    COOLSTEP_FORM.iter().find(|f| f.number == number)
}

/// Why a form entry gives no command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FormError {
    NotInForm(u8),
    ReadOnly(u8),
    OutOfRange {
        number: u8,
        value: i32,
        min: i32,
        max: i32,
    },
}

impl fmt::Display for FormError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FormError::NotInForm(n) => write!(f, "AP{n} is not a CoolStep parameter"),
            FormError::ReadOnly(n) => write!(f, "AP{n} is a status value, read only"),
            FormError::OutOfRange {
                number,
                value,
                min,
                max,
            } => write!(f, "AP{number} takes {min}..{max}, not {value}"),
        }
    }
}

impl std::error::Error for FormError {}

/// The SAP that writes `value` into CoolStep parameter `number`, checked
/// against the form first.
pub fn coolstep_write(number: u8, motor: u8, value: i32) -> Result<Command, FormError> {
    let field = coolstep_field(number).ok_or(FormError::NotInForm(number))?;
    if !field.writable {
        return Err(FormError::ReadOnly(number));
    }
    if !(field.min..=field.max).contains(&value) {
        return Err(FormError::OutOfRange {
            number,
            value,
            min: field.min,
            max: field.max,
        });
    }
    Ok(Command::Sap {
        param: number,
        motor,
        value,
    })
}

/// The GAPs that read the whole form.
pub fn coolstep_reads(motor: u8) -> Vec<Command> {
    COOLSTEP_FORM
        .iter()
        .map(|f| Command::Gap {
            param: f.number,
            motor,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::tmcl::params;

    /// A parameter's range in the parameter table.
    fn table_range(number: u8) -> Option<(i64, i64)> {
        match params::axis_param(number)?.range {
            params::ValueRange::Span { min, max } => Some((min, max)),
            _ => None,
        }
    }

    fn spec(from: i32, to: i32, steps: u32) -> SweepSpec {
        SweepSpec {
            motor: 0,
            direction: Direction::Right,
            from,
            to,
            steps,
            samples: 3,
        }
    }

    #[test]
    fn a_sweep_spaces_its_speeds_evenly_with_both_ends() {
        let plan = SweepPlan::new(&spec(200, 1000, 5)).unwrap();
        assert_eq!(plan.velocities(), vec![200, 400, 600, 800, 1000]);
        let down = SweepPlan::new(&spec(1000, 100, 4)).unwrap();
        assert_eq!(down.velocities(), vec![1000, 700, 400, 100]);
        let rounded = SweepPlan::new(&spec(1, 10, 4)).unwrap();
        assert_eq!(rounded.velocities(), vec![1, 4, 7, 10]);
        assert_eq!(
            SweepPlan::new(&spec(5, 5, 1)).unwrap().velocities(),
            vec![5]
        );
        assert_eq!(
            SweepPlan::new(&spec(5, 5, 3)).unwrap().velocities(),
            vec![5]
        );
        assert_eq!(
            SweepPlan::new(&spec(1, 3, 3)).unwrap().velocities(),
            vec![1, 2, 3]
        );
    }

    #[test]
    fn a_sweep_runs_waits_samples_and_stops() {
        let mut s = spec(300, 600, 2);
        s.samples = 2;
        s.motor = 0;
        let plan = SweepPlan::new(&s).unwrap();
        let gap3 = Command::Gap { param: 3, motor: 0 };
        let gap206 = Command::Gap {
            param: 206,
            motor: 0,
        };
        use SweepInstruction::*;
        assert_eq!(
            plan.instructions(),
            vec![
                Send(Command::Ror {
                    motor: 0,
                    velocity: 300
                }),
                WaitForSpeed {
                    poll: gap3,
                    speed: 300
                },
                Sample {
                    point: 0,
                    sample: 0,
                    read: gap206
                },
                Sample {
                    point: 0,
                    sample: 1,
                    read: gap206
                },
                Send(Command::Ror {
                    motor: 0,
                    velocity: 600
                }),
                WaitForSpeed {
                    poll: gap3,
                    speed: 600
                },
                Sample {
                    point: 1,
                    sample: 0,
                    read: gap206
                },
                Sample {
                    point: 1,
                    sample: 1,
                    read: gap206
                },
                Send(Command::Mst { motor: 0 }),
            ]
        );
        assert_eq!(plan.stop(), Command::Mst { motor: 0 });
        let mut left = s;
        left.direction = Direction::Left;
        assert_eq!(
            SweepPlan::new(&left).unwrap().points[0].start,
            Command::Rol {
                motor: 0,
                velocity: 300
            }
        );
        assert!(speed_reached(-300, 300), "ROL reads negative");
        assert!(speed_reached(300, 300));
        assert!(!speed_reached(299, 300));
    }

    #[test]
    fn a_bad_sweep_says_what_is_wrong() {
        let e = |s: SweepSpec| SweepPlan::new(&s).unwrap_err().to_string();
        assert_eq!(
            e(spec(0, 100, 2)),
            "from speed 0 is outside 1..2047 [int] (the sweep's direction gives ROR or ROL, and 0 does not turn)"
        );
        assert!(e(spec(100, 2048, 2)).starts_with("to speed 2048 is outside"));
        assert_eq!(e(spec(100, 200, 0)), "steps must be at least 1");
        let mut no_samples = spec(100, 200, 2);
        no_samples.samples = 0;
        assert_eq!(e(no_samples), "samples must be at least 1");
        assert_eq!(
            e(spec(100, 102, 4)),
            "4 steps would repeat speeds: there are only 3 whole speeds between the ends"
        );
        assert!(e(spec(100, 200, 1)).starts_with("one step cannot cover 100..200"));
    }

    fn at(velocity: i32, unloaded: &[i32], loaded: &[i32]) -> SpeedReadings {
        SpeedReadings {
            velocity,
            unloaded: unloaded.to_vec(),
            loaded: loaded.to_vec(),
        }
    }

    /// Readings of the simulator's law (|v|/2 unloaded, × 0.4 at 60 % load).
    fn sim_like() -> Vec<SpeedReadings> {
        [100, 200, 400, 600, 800, 1000]
            .into_iter()
            .map(|v| {
                let u = v / 2;
                let l = u * 2 / 5;
                at(v, &[u - 2, u, u + 2], &[l - 2, l, l + 2])
            })
            .collect()
    }

    #[test]
    fn the_suggestion_stops_where_load_and_no_load_part() {
        let s = suggest(&sim_like(), &SuggestRules::default());
        // Downwards from 1000: the unloaded reading falls with speed, the
        // loaded one of 1000 (up to 202) stays the highest. 600 still parts
        // (unloaded down to 298), 400 no more (unloaded down to 198).
        assert_eq!(s.stop_on_stall_speed, Some(600));
        // Level (202 + 298) / 2 = 250; 250 / 16 = 15.6 → 16; AP174 = −16.
        assert_eq!(s.threshold, Some(-16));
        assert_eq!(
            s.commands(0),
            vec![
                Command::Sap {
                    param: 174,
                    motor: 0,
                    value: -16
                },
                Command::Sap {
                    param: 181,
                    motor: 0,
                    value: 600
                },
            ]
        );
        let text = s.reasons.join("\n");
        assert!(
            text.contains("at 400 [int] and below, loaded (up to 202) and unloaded (down to 198)"),
            "{text}"
        );
        assert!(text.contains("working range 600..1000 [int]"), "{text}");
        assert!(text.contains("AP181 = 600"), "{text}");
        assert!(text.contains("AP174 = 0 − round(250 / 16) = -16"), "{text}");
        // The threshold puts the loaded readings at 0 and the unloaded above,
        // with the simulator's shift of 16 per step.
        for r in &sim_like()[3..] {
            assert!(r.loaded.iter().all(|l| l - 16 * 16 <= 0), "{r:?}");
            assert!(r.unloaded.iter().all(|u| u - 16 * 16 > 0), "{r:?}");
        }
    }

    #[test]
    fn readings_taken_at_another_threshold_are_taken_back() {
        let rules = SuggestRules {
            threshold_during_sweep: 5,
            ..SuggestRules::default()
        };
        let s = suggest(&sim_like(), &rules);
        assert_eq!(s.threshold, Some(5 - 16));
        let clamped = suggest(
            &[at(2000, &[1023], &[900])],
            &SuggestRules {
                threshold_during_sweep: -40,
                ..SuggestRules::default()
            },
        );
        assert_eq!(clamped.threshold, Some(-64));
        assert!(clamped.reasons.iter().any(|r| r.contains("clamped to -64")));
    }

    #[test]
    fn no_separation_no_suggestion() {
        let s = suggest(
            &[at(100, &[50, 52], &[40, 45]), at(200, &[100], &[60])],
            &SuggestRules::default(),
        );
        assert_eq!((s.stop_on_stall_speed, s.threshold), (None, None));
        assert!(s.commands(0).is_empty());
        assert!(
            s.reasons
                .last()
                .unwrap()
                .starts_with("even the fastest speed"),
            "{:?}",
            s.reasons
        );
        let empty = suggest(&[at(100, &[], &[1])], &SuggestRules::default());
        assert_eq!(empty.threshold, None);
        assert_eq!(
            empty.reasons,
            vec![
                "1 speed(s) left out: a sweep without or with load has no reading there",
                "no speed has readings both without and with load",
            ]
        );
    }

    #[test]
    fn the_coolstep_form_matches_the_parameter_table() {
        let numbers: Vec<u8> = COOLSTEP_FORM.iter().map(|f| f.number).collect();
        assert_eq!(numbers, vec![168, 169, 170, 171, 172, 180, 182, 183]);
        for f in COOLSTEP_FORM {
            assert_eq!(
                table_range(f.number),
                Some((i64::from(f.min), i64::from(f.max))),
                "AP{}",
                f.number
            );
            let info = params::axis_param(f.number).unwrap();
            assert_eq!(info.access.write, f.writable, "AP{}", f.number);
            assert!(!f.meaning.contains('\n'));
        }
    }

    #[test]
    fn a_form_entry_becomes_a_checked_sap() {
        assert_eq!(
            coolstep_write(172, 0, 2),
            Ok(Command::Sap {
                param: 172,
                motor: 0,
                value: 2
            })
        );
        assert_eq!(
            coolstep_write(171, 0, 4).unwrap_err().to_string(),
            "AP171 takes 0..3, not 4"
        );
        assert_eq!(
            coolstep_write(180, 0, 3).unwrap_err().to_string(),
            "AP180 is a status value, read only"
        );
        assert_eq!(
            coolstep_write(6, 0, 3).unwrap_err().to_string(),
            "AP6 is not a CoolStep parameter"
        );
        assert_eq!(coolstep_reads(0).len(), COOLSTEP_FORM.len());
        assert_eq!(
            coolstep_reads(0)[5],
            Command::Gap {
                param: 180,
                motor: 0
            }
        );
    }
}
