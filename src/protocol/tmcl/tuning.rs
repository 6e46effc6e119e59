//! The TMCM-1110's StallGuard2 sweep as the tuning tools take it
//! ([`crate::protocol::tuning::StallSweepPlan`]): the plan and the
//! suggestion rule of [`super::tune`], written as console lines.

use super::tune::{
    self, Direction, SpeedReadings, SuggestRules, SweepInstruction, SweepPlan, SweepSpec,
};
use crate::protocol::console::AxisInfo;
use crate::protocol::tuning::{
    CurrentControlPlan, CurrentWatch, FormField, StallSweepPlan, SweepAction, SweepAsk, SweepPoint,
    SweepScript, SweepSuggestion, TuneError, TuningField,
};

pub struct TmclStallSweep;

/// The settings that bear on the StallGuard2 reading (§4, §7.2).
const FIELDS: &[TuningField] = &[
    TuningField {
        name: "AP6",
        meaning: "absolute max current, 0..255: the reading is taken at this current (§4)",
    },
    TuningField {
        name: "AP173",
        meaning: "StallGuard2 filter: 1 = one reading per four full steps, smoother (§4)",
    },
    TuningField {
        name: "AP174",
        meaning: "StallGuard2 threshold, -64..63: lower is more sensitive (§4, §7.2)",
    },
    TuningField {
        name: "AP181",
        meaning: "stop on stall above this speed; 0 = off; no detection below it (§4, §7.2)",
    },
    TuningField {
        name: "AP206",
        meaning: "actual load value, 0..1023: falls with load, 0 at stall (§4, §7.2)",
    },
];

fn to_i32(which: &str, value: i64) -> Result<i32, TuneError> {
    i32::try_from(value).map_err(|_| {
        TuneError::Refused(format!(
            "a sweep speed {which} of {value} is outside 1..{}",
            tune::MAX_VELOCITY
        ))
    })
}

impl StallSweepPlan for TmclStallSweep {
    fn reading(&self) -> &'static str {
        "AP206, the StallGuard2 load value (0..1023, 0 = stall)"
    }

    fn fields(&self) -> &'static [TuningField] {
        FIELDS
    }

    fn read_threshold(&self, axis: &AxisInfo) -> String {
        format!("GAP 174, {}", axis.number)
    }

    /// Positive speeds turn right (ROR), negative ones left (ROL).
    fn script(&self, axis: &AxisInfo, ask: &SweepAsk) -> Result<SweepScript, TuneError> {
        let direction = match (ask.from.signum(), ask.to.signum()) {
            (1, 1) => Direction::Right,
            (-1, -1) => Direction::Left,
            _ => {
                return Err(TuneError::Refused(format!(
                    "a sweep from {} to {} crosses or touches 0: give two speeds of one sign \
                     (negative turns left)",
                    ask.from, ask.to
                )));
            }
        };
        let spec = SweepSpec {
            motor: axis.number,
            direction,
            from: to_i32("from", ask.from.abs())?,
            to: to_i32("to", ask.to.abs())?,
            steps: ask.steps,
            samples: ask.samples,
        };
        let plan = SweepPlan::new(&spec).map_err(|e| TuneError::Refused(e.to_string()))?;
        let sign = if direction == Direction::Left { -1 } else { 1 };
        let actions = plan
            .instructions()
            .into_iter()
            // The stop is the script's own, sent however the sweep ends.
            .filter(|i| *i != SweepInstruction::Send(plan.stop()))
            .map(|instruction| match instruction {
                SweepInstruction::Send(command) => SweepAction::Send(command.to_string()),
                SweepInstruction::WaitForSpeed { poll, speed } => SweepAction::WaitForSpeed {
                    read: poll.to_string(),
                    speed: i64::from(sign * speed),
                },
                SweepInstruction::Sample { point, read, .. } => SweepAction::Sample {
                    point,
                    read: read.to_string(),
                },
            })
            .collect();
        Ok(SweepScript {
            speeds: plan
                .velocities()
                .into_iter()
                .map(|v| i64::from(sign * v))
                .collect(),
            actions,
            stop: vec![plan.stop().to_string()],
        })
    }

    /// AP207 bit 0 (§4): "the motor was stopped on a stall".
    fn stall_flag(&self) -> &'static str {
        "stall"
    }

    fn speed_reached(&self, actual: i64, speed: i64) -> bool {
        match (i32::try_from(actual), i32::try_from(speed)) {
            (Ok(actual), Ok(speed)) => tune::speed_reached(actual, speed),
            _ => false,
        }
    }

    fn suggest(
        &self,
        axis: &AxisInfo,
        free: &[SweepPoint],
        loaded: &[SweepPoint],
        threshold_during: i64,
    ) -> SweepSuggestion {
        let narrow = |values: &[i64]| -> Vec<i32> {
            values
                .iter()
                .map(|&v| v.clamp(0, i64::from(i32::MAX)) as i32)
                .collect()
        };
        let readings: Vec<SpeedReadings> = free
            .iter()
            .filter_map(|f| {
                let l = loaded.iter().find(|l| l.speed == f.speed)?;
                Some(SpeedReadings {
                    velocity: i32::try_from(f.speed.abs()).ok()?,
                    unloaded: narrow(&f.readings),
                    loaded: narrow(&l.readings),
                })
            })
            .collect();
        if readings.is_empty() {
            return SweepSuggestion {
                reasons: vec![
                    "the two sweeps share no speed: run them with the same --from, --to and \
                     --steps"
                        .to_string(),
                ],
                lines: Vec::new(),
            };
        }
        let rules = SuggestRules {
            threshold_during_sweep: threshold_during.clamp(
                i64::from(tune::THRESHOLD_RANGE.0),
                i64::from(tune::THRESHOLD_RANGE.1),
            ) as i32,
            ..SuggestRules::default()
        };
        let suggestion = tune::suggest(&readings, &rules);
        SweepSuggestion {
            reasons: suggestion.reasons.clone(),
            lines: suggestion
                .commands(axis.number)
                .iter()
                .map(ToString::to_string)
                .collect(),
        }
    }
}

pub struct TmclCoolStep;

/// `AP172` and the like, for the form's names.
const AP_NAMES: [&str; 256] = ap_names();

const fn ap_names() -> [&'static str; 256] {
    // Only the form's parameters need a name; the rest stay empty.
    let mut names = [""; 256];
    names[6] = "AP6";
    names[168] = "AP168";
    names[169] = "AP169";
    names[170] = "AP170";
    names[171] = "AP171";
    names[172] = "AP172";
    names[180] = "AP180";
    names[182] = "AP182";
    names[183] = "AP183";
    names
}

/// The AP number `name` (`AP172`, `ap172`, `172`) names.
fn parameter_number(name: &str) -> Option<u8> {
    let digits = name
        .strip_prefix("AP")
        .or_else(|| name.strip_prefix("ap"))
        .unwrap_or(name);
    digits.parse().ok()
}

impl CurrentControlPlan for TmclCoolStep {
    fn form(&self) -> Vec<FormField> {
        tune::COOLSTEP_FORM
            .iter()
            .map(|f| FormField {
                name: AP_NAMES[usize::from(f.number)],
                title: f.name,
                meaning: f.meaning,
                min: i64::from(f.min),
                max: i64::from(f.max),
                writable: f.writable,
            })
            .collect()
    }

    fn read(&self, axis: &AxisInfo, field: &FormField) -> String {
        let number = parameter_number(field.name).unwrap_or_default();
        format!("GAP {number}, {}", axis.number)
    }

    fn write(&self, axis: &AxisInfo, name: &str, value: i64) -> Result<String, TuneError> {
        let number = parameter_number(name).ok_or_else(|| TuneError::UnknownGain {
            name: name.to_string(),
            known: self
                .form()
                .iter()
                .map(|f| f.name)
                .collect::<Vec<_>>()
                .join(", "),
        })?;
        let value = i32::try_from(value)
            .map_err(|_| TuneError::Refused(format!("AP{number}: {value} is out of range")))?;
        tune::coolstep_write(number, axis.number, value)
            .map(|command| command.to_string())
            .map_err(|e| TuneError::Refused(e.to_string()))
    }

    fn watch(&self, axis: &AxisInfo) -> CurrentWatch {
        let m = axis.number;
        CurrentWatch {
            current: format!("GAP 180, {m}"),
            load: format!("GAP 206, {m}"),
            speed: format!("GAP 3, {m}"),
            full: format!("GAP 6, {m}"),
            // §4 axis parameters, AP206 "Actual load value": 0..1023.
            load_full: 1023,
        }
    }

    /// AP180 is a current scale 0..31 (n+1)/32 of the driver's range; AP6
    /// 0..255 sets the scale the driver runs at, AP6 / 8 (§4 AP6, §7.3
    /// Table 25: the CoolStep current lies between SEIMIN's portion and
    /// the AP6 current).
    fn share(&self, current: i64, full: i64) -> Option<f64> {
        if !(0..=31).contains(&current) || !(0..=255).contains(&full) {
            return None;
        }
        Some((current + 1) as f64 / (full / 8 + 1) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::console::FamilyConsole;
    use crate::protocol::tmcl::TmclConsole;

    const MOTOR: AxisInfo = AxisInfo {
        number: 0,
        name: "motor 0",
    };

    fn ask(from: i64, to: i64) -> SweepAsk {
        SweepAsk {
            from,
            to,
            steps: 3,
            samples: 2,
        }
    }

    #[test]
    fn a_sweep_is_lines_the_console_takes_ending_without_its_stop() {
        let script = TmclStallSweep
            .script(&MOTOR, &ask(100, 300))
            .expect("a plan");
        assert_eq!(script.speeds, [100, 200, 300]);
        assert_eq!(script.stop, ["MST 0"]);
        assert_eq!(
            script.actions[..4],
            [
                SweepAction::Send("ROR 0, 100".into()),
                SweepAction::WaitForSpeed {
                    read: "GAP 3, 0".into(),
                    speed: 100
                },
                SweepAction::Sample {
                    point: 0,
                    read: "GAP 206, 0".into()
                },
                SweepAction::Sample {
                    point: 0,
                    read: "GAP 206, 0".into()
                },
            ]
        );
        let mut lines: Vec<String> = script
            .actions
            .iter()
            .map(|a| match a {
                SweepAction::Send(l)
                | SweepAction::WaitForSpeed { read: l, .. }
                | SweepAction::Sample { read: l, .. } => l.clone(),
            })
            .collect();
        assert!(!lines.contains(&"MST 0".to_string()));
        lines.extend(script.stop);
        for line in lines {
            assert!(TmclConsole.prepare(&line, 1).is_ok(), "{line}");
        }
    }

    #[test]
    fn negative_speeds_turn_left_and_a_sweep_through_0_is_refused() {
        let script = TmclStallSweep
            .script(&MOTOR, &ask(-100, -300))
            .expect("a plan");
        assert_eq!(script.actions[0], SweepAction::Send("ROL 0, 100".into()));
        assert_eq!(script.speeds, [-100, -200, -300]);
        assert!(matches!(
            script.actions[1],
            SweepAction::WaitForSpeed { speed: -100, .. }
        ));
        let refused = TmclStallSweep.script(&MOTOR, &ask(-100, 300)).unwrap_err();
        assert!(
            refused.to_string().contains("crosses or touches 0"),
            "{refused}"
        );
        let refused = TmclStallSweep.script(&MOTOR, &ask(100, 3000)).unwrap_err();
        assert!(refused.to_string().contains("3000"), "{refused}");
    }

    #[test]
    fn the_stall_flag_is_one_the_console_raises() {
        let names: Vec<&str> = crate::protocol::tmcl::console::ERROR_FLAGS
            .iter()
            .map(|(_, f)| f.name)
            .collect();
        assert!(names.contains(&TmclStallSweep.stall_flag()), "{names:?}");
    }

    #[test]
    fn the_coolstep_form_reads_and_writes_checked_lines() {
        let form = TmclCoolStep.form();
        assert_eq!(form.len(), tune::COOLSTEP_FORM.len());
        assert_eq!(form[4].name, "AP172");
        assert_eq!(TmclCoolStep.read(&MOTOR, &form[4]), "GAP 172, 0");
        assert_eq!(
            TmclCoolStep.write(&MOTOR, "AP172", 2).unwrap(),
            "SAP 172, 0, 2"
        );
        assert_eq!(
            TmclCoolStep.write(&MOTOR, "172", 2).unwrap(),
            "SAP 172, 0, 2"
        );
        let refused = TmclCoolStep.write(&MOTOR, "AP180", 3).unwrap_err();
        assert!(refused.to_string().contains("read only"), "{refused}");
        let refused = TmclCoolStep.write(&MOTOR, "AP172", 16).unwrap_err();
        assert!(refused.to_string().contains("0..15"), "{refused}");
        let refused = TmclCoolStep.write(&MOTOR, "AP4", 1).unwrap_err();
        assert!(
            refused.to_string().contains("not a CoolStep parameter"),
            "{refused}"
        );
        // The full scale at AP6 255 is 32/32; half of it is 16/32.
        assert_eq!(TmclCoolStep.share(31, 255), Some(1.0));
        assert_eq!(TmclCoolStep.share(15, 255), Some(0.5));
        assert_eq!(TmclCoolStep.share(7, 128), Some(8.0 / 17.0));
        assert_eq!(TmclCoolStep.share(32, 255), None);
    }

    #[test]
    fn the_suggestion_is_the_tune_rules_as_sap_lines() {
        let free: Vec<SweepPoint> = [(100, 50), (200, 100), (300, 150)]
            .iter()
            .map(|&(speed, r)| SweepPoint {
                speed,
                readings: vec![r, r],
            })
            .collect();
        let loaded: Vec<SweepPoint> = free
            .iter()
            .map(|p| SweepPoint {
                speed: p.speed,
                readings: p.readings.iter().map(|r| r * 2 / 5).collect(),
            })
            .collect();
        let said = TmclStallSweep.suggest(&MOTOR, &free, &loaded, 0);
        assert_eq!(said.lines.len(), 2, "{said:?}");
        assert!(said.lines[0].starts_with("SAP 174, 0, "), "{said:?}");
        assert!(said.lines[1].starts_with("SAP 181, 0, "), "{said:?}");
        assert!(!said.reasons.is_empty());
        let none = TmclStallSweep.suggest(&MOTOR, &free, &[], 0);
        assert!(none.lines.is_empty());
        assert!(none.reasons[0].contains("share no speed"));
    }
}
