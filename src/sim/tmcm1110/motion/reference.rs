//! The built-in reference search (manual §7.1, Table 24, AP193–AP197) as
//! data: which switches each mode looks for, in which direction, and the
//! program of slow calibration runs that pins the switching points down.

use std::fmt;

use super::Switch;

/// One row of §7.1 Table 24 (the unmodified modes 1..8).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReferenceModeInfo {
    pub mode: u8,
    /// Modes 2 and 3: the end switch searched (and calibrated) first, and the
    /// direction towards it; AP196 becomes the distance from its switching
    /// point to the reference (§7.1.2, §7.1.3).
    pub first: Option<(Switch, i8)>,
    /// The switch that becomes the zero point, and the search direction.
    pub zero: Switch,
    pub direction: i8,
    /// Modes 5/6: reverse once when the end switch ahead is reached.
    pub reverse_at_limit: bool,
    /// Modes 3, 4, 7, 8: cross the zero switch, find both its edges and
    /// take its middle (§7.1.3, §7.1.4, §7.1.7, §7.1.8).
    pub middle: bool,
    /// Table 24's wording.
    pub description: &'static str,
}

/// §7.1 Table 24. Direction convention: right = positive (ROR), left =
/// negative (ROL). Modes 7/8 follow §7.1.7/§7.1.8 and Table 24 (7 =
/// negative); §4 Table 16 has them the other way round.
pub const REFERENCE_MODES: &[ReferenceModeInfo] = &[
    ReferenceModeInfo {
        mode: 1,
        first: None,
        zero: Switch::Left,
        direction: -1,
        reverse_at_limit: false,
        middle: false,
        description: "search left stop switch only",
    },
    ReferenceModeInfo {
        mode: 2,
        first: Some((Switch::Right, 1)),
        zero: Switch::Left,
        direction: -1,
        reverse_at_limit: false,
        middle: false,
        description: "search right stop switch, then search left stop switch",
    },
    ReferenceModeInfo {
        mode: 3,
        first: Some((Switch::Right, 1)),
        zero: Switch::Left,
        direction: -1,
        reverse_at_limit: false,
        middle: true,
        description: "search right stop switch, then search left stop switch from both sides",
    },
    ReferenceModeInfo {
        mode: 4,
        first: None,
        zero: Switch::Left,
        direction: -1,
        reverse_at_limit: false,
        middle: true,
        description: "search left stop switch from both sides",
    },
    ReferenceModeInfo {
        mode: 5,
        first: None,
        zero: Switch::Home,
        direction: -1,
        reverse_at_limit: true,
        middle: false,
        description: "search home switch in negative direction, reverse the direction when left stop switch reached",
    },
    ReferenceModeInfo {
        mode: 6,
        first: None,
        zero: Switch::Home,
        direction: 1,
        reverse_at_limit: true,
        middle: false,
        description: "search home switch in positive direction, reverse the direction when right stop switch reached",
    },
    ReferenceModeInfo {
        mode: 7,
        first: None,
        zero: Switch::Home,
        direction: -1,
        reverse_at_limit: false,
        middle: true,
        description: "search home switch in negative direction, ignore end switches",
    },
    ReferenceModeInfo {
        mode: 8,
        first: None,
        zero: Switch::Home,
        direction: 1,
        reverse_at_limit: false,
        middle: true,
        description: "search home switch in positive direction, ignore end switches",
    },
];

/// §4 AP193: "Add 64 to a mode for searching the right instead of the left
/// reference switch (can be used with mode 1..4)".
pub const MIRROR_FLAG: i32 = 64;
/// §4 AP193: "Add 128 to a mode value for inverting the home switch (can be
/// used with mode 5..8)".
pub const INVERT_HOME_FLAG: i32 = 128;

/// A decoded AP193 value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReferenceMode {
    pub info: ReferenceModeInfo,
    /// +64: left and right swapped (modes 1..4).
    pub mirrored: bool,
    /// +128: home input polarity inverted for the search (modes 5..8).
    pub home_inverted: bool,
}

impl ReferenceMode {
    /// Decodes AP193; `None` for values the manual doesn't define (0, 9..63,
    /// +64 on modes 5..8, +128 on modes 1..4, …).
    pub fn decode(value: i32) -> Option<ReferenceMode> {
        let mirrored = value & MIRROR_FLAG != 0;
        let home_inverted = value & INVERT_HOME_FLAG != 0;
        let base = value & !(MIRROR_FLAG | INVERT_HOME_FLAG);
        let info = *REFERENCE_MODES
            .iter()
            .find(|row| i32::from(row.mode) == base)?;
        let limit_mode = info.zero != Switch::Home;
        if (mirrored && !limit_mode) || (home_inverted && limit_mode) {
            return None;
        }
        Some(ReferenceMode {
            info,
            mirrored,
            home_inverted,
        })
    }

    fn orient(&self, (switch, direction): (Switch, i8)) -> (Switch, i8) {
        if self.mirrored {
            (mirror(switch), -direction)
        } else {
            (switch, direction)
        }
    }

    /// The runs the search makes, in order, ending with the move onto the
    /// reference point.
    pub(super) fn program(&self) -> Vec<Step> {
        let mut steps = Vec::new();
        if let Some(first) = self.info.first {
            let (switch, dir) = self.orient(first);
            steps.push(Step::Seek { switch, dir });
            calibrate(&mut steps, switch, dir);
        }
        let (switch, dir) = self.orient((self.info.zero, self.info.direction));
        steps.push(Step::Seek { switch, dir });
        calibrate(&mut steps, switch, dir);
        if self.info.middle {
            // Through the switch and back in at its far edge.
            steps.push(Step::Leave { switch, dir });
            steps.push(Step::Enter { switch, dir: -dir });
        }
        steps.push(Step::GoToReference);
        steps
    }

    /// The reference point and, for modes 2/3, the AP196 distance, from the
    /// switching points the program recorded (in its order).
    pub(super) fn reference(&self, marks: &[i64]) -> Option<(i64, Option<i64>)> {
        let (first, zero_marks) = if self.info.first.is_some() {
            let [out, back_in, rest @ ..] = marks else {
                return None;
            };
            (Some(centre(*out, *back_in)), rest)
        } else {
            (None, marks)
        };
        let zero = if self.info.middle {
            let [a_out, a_in, b_out, b_in] = zero_marks else {
                return None;
            };
            centre(centre(*a_out, *a_in), centre(*b_out, *b_in))
        } else {
            let [out, back_in] = zero_marks else {
                return None;
            };
            centre(*out, *back_in)
        };
        // §7.1.3: mode 3's AP196 is "the distance between the right end
        // switch and the middle of the left end switch".
        let distance = first.map(|f| f.saturating_sub(zero).saturating_abs());
        Some((zero, distance))
    }
}

/// §7.1 notes: "After hitting the reference switch, the motor slowly moves
/// until the switch is released. Finally the switch is re-entered in the
/// other direction, setting the reference point to the center of the two
/// switching points."
fn calibrate(steps: &mut Vec<Step>, switch: Switch, dir: i8) {
    steps.push(Step::Leave { switch, dir: -dir });
    steps.push(Step::Enter { switch, dir });
}

fn mirror(switch: Switch) -> Switch {
    match switch {
        Switch::Left => Switch::Right,
        Switch::Right => Switch::Left,
        Switch::Home => Switch::Home,
    }
}

/// Middle of two switching points, rounded towards negative.
fn centre(a: i64, b: i64) -> i64 {
    let sum = i128::from(a) + i128::from(b);
    sum.div_euclid(2) as i64
}

/// One run of the search.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Step {
    /// At the search speed (AP194) towards `dir` until `switch` is active.
    Seek { switch: Switch, dir: i8 },
    /// At the switch speed (AP195) towards `dir` until `switch` releases;
    /// records the last active position.
    Leave { switch: Switch, dir: i8 },
    /// At the switch speed towards `dir` until `switch` is active again;
    /// records the first active position.
    Enter { switch: Switch, dir: i8 },
    /// Position move at the switch speed onto the reference point.
    GoToReference,
}

/// How a reference search ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReferenceOutcome {
    /// The counter was set to 0 at the reference; AP197 holds its old value.
    Found { last_reference_position: i32 },
    /// The search gave up; the counter is unchanged.
    Aborted(ReferenceAbort),
}

/// Why a reference search ended without a reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReferenceAbort {
    /// RFS STOP.
    Stopped,
    /// Another motion command (ROR/ROL/MST/MVP, SAP 0/2/138) took over.
    Interrupted,
    /// AP193 holds a value Table 24 doesn't define.
    InvalidMode(i32),
    /// AP194 or AP195 is 0: the search would never move.
    ZeroSpeed,
    /// Modes 5/6: both end switches reached without finding home.
    HomeNotBetweenLimits,
    /// One run travelled the search's maximum distance without its switch.
    TravelExceeded,
    /// StallGuard stopped the motor (AP181).
    Stall,
    /// The encoder deviation stop fired (AP212).
    Deviation,
}

impl fmt::Display for ReferenceAbort {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReferenceAbort::Stopped => f.write_str("reference search stopped by RFS STOP"),
            ReferenceAbort::Interrupted => {
                f.write_str("reference search interrupted by another motion command")
            }
            ReferenceAbort::InvalidMode(mode) => write!(
                f,
                "reference search mode {mode} (AP193) is not one of 1..8, 65..68, 133..136"
            ),
            ReferenceAbort::ZeroSpeed => {
                f.write_str("reference search speed AP194 or switch speed AP195 is 0")
            }
            ReferenceAbort::HomeNotBetweenLimits => {
                f.write_str("home switch not found between the two end switches")
            }
            ReferenceAbort::TravelExceeded => write!(
                f,
                "switch not found within {} microsteps of travel",
                super::REFERENCE_SEARCH_MAX_TRAVEL
            ),
            ReferenceAbort::Stall => f.write_str("reference search ended by a stall stop"),
            ReferenceAbort::Deviation => {
                f.write_str("reference search ended by an encoder deviation stop")
            }
        }
    }
}

/// A search under way.
#[derive(Debug, Clone)]
pub(super) struct Search {
    pub mode: ReferenceMode,
    pub steps: Vec<Step>,
    pub index: usize,
    /// Switching points recorded by Leave/Enter runs.
    pub marks: Vec<i64>,
    /// Machine position where the present run started (travel bound).
    pub run_start: i64,
    /// Modes 5/6: the seek has turned round at the end switch.
    pub reversed: bool,
    /// The reference point, once known (machine position).
    pub reference: Option<i64>,
    /// AP196 result of modes 2/3.
    pub distance: Option<i64>,
}

impl Search {
    pub fn new(mode: ReferenceMode, start: i64) -> Search {
        Search {
            steps: mode.program(),
            mode,
            index: 0,
            marks: Vec::new(),
            run_start: start,
            reversed: false,
            reference: None,
            distance: None,
        }
    }

    pub fn step(&self) -> Option<Step> {
        self.steps.get(self.index).copied()
    }

    /// Direction of the present run (Seek turns round in modes 5/6).
    pub fn run_direction(&self) -> i8 {
        match self.step() {
            Some(Step::Seek { dir, .. }) => {
                if self.reversed {
                    -dir
                } else {
                    dir
                }
            }
            Some(Step::Leave { dir, .. } | Step::Enter { dir, .. }) => dir,
            Some(Step::GoToReference) | None => 0,
        }
    }

    pub fn next(&mut self, position: i64) {
        self.index += 1;
        self.run_start = position;
        self.reversed = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_24_has_eight_modes_with_7_negative_and_8_positive() {
        let modes: Vec<u8> = REFERENCE_MODES.iter().map(|r| r.mode).collect();
        assert_eq!(modes, vec![1, 2, 3, 4, 5, 6, 7, 8]);
        assert_eq!(REFERENCE_MODES[6].direction, -1);
        assert_eq!(REFERENCE_MODES[7].direction, 1);
    }

    #[test]
    fn decode_accepts_exactly_the_documented_values() {
        let valid: Vec<i32> = (-1..300)
            .filter(|v| ReferenceMode::decode(*v).is_some())
            .collect();
        let mut expected: Vec<i32> = (1..=8).collect();
        expected.extend(65..=68);
        expected.extend(133..=136);
        assert_eq!(valid, expected);
    }

    #[test]
    fn mirrored_mode_2_searches_left_first_and_zeroes_right() {
        let mode = ReferenceMode::decode(66).unwrap();
        let program = mode.program();
        assert_eq!(
            program.first(),
            Some(&Step::Seek {
                switch: Switch::Left,
                dir: -1
            })
        );
        assert!(program.contains(&Step::Seek {
            switch: Switch::Right,
            dir: 1
        }));
    }

    #[test]
    fn reference_is_the_centre_of_the_switching_points() {
        let m1 = ReferenceMode::decode(1).unwrap();
        assert_eq!(m1.reference(&[-10, -12]), Some((-11, None)));
        let m7 = ReferenceMode::decode(7).unwrap();
        assert_eq!(m7.reference(&[7000, 7000, 3000, 3000]), Some((5000, None)));
        let m2 = ReferenceMode::decode(2).unwrap();
        assert_eq!(
            m2.reference(&[200, 200, -100, -100]),
            Some((-100, Some(300)))
        );
        assert_eq!(m2.reference(&[1, 2]), None);
        // Rounds towards negative.
        assert_eq!(m1.reference(&[-3, -2]), Some((-3, None)));
    }

    #[test]
    fn modes_3_and_4_cross_the_zero_switch_and_take_its_middle() {
        for mode in [3, 4, 67, 68] {
            let program = ReferenceMode::decode(mode).unwrap().program();
            let zero = if mode < 64 {
                Switch::Left
            } else {
                Switch::Right
            };
            let outward = if mode < 64 { -1 } else { 1 };
            // After the calibration at the near edge: out through the far
            // edge and back in.
            assert_eq!(
                program[program.len() - 3..],
                [
                    Step::Leave {
                        switch: zero,
                        dir: outward
                    },
                    Step::Enter {
                        switch: zero,
                        dir: -outward
                    },
                    Step::GoToReference
                ],
                "mode {mode}"
            );
        }
        let m4 = ReferenceMode::decode(4).unwrap();
        assert_eq!(m4.reference(&[-100, -100, -300, -300]), Some((-200, None)));
        assert_eq!(m4.reference(&[-100, -100]), None);
        // Mode 3: the right switch's point, then the left switch's two edges;
        // AP196 runs from the right switch to the left switch's middle.
        let m3 = ReferenceMode::decode(3).unwrap();
        assert_eq!(
            m3.reference(&[500, 500, -100, -100, -300, -300]),
            Some((-200, Some(700)))
        );
        assert_eq!(m3.reference(&[500, 500, -100, -100]), None);
    }
}
