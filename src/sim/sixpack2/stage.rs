//! The machine behind one motor (digest D10.1, "world model"): where the
//! carriage is, apart from the position counter, so that a stall at a
//! mechanical stop loses steps ("The actual motor position is not known
//! after power on", §2.2); where the reference switch sits and how it is
//! wired; the end switches on A_In.
//!
//! Carriage positions are µsteps from the left mechanical stop. Inputs can
//! be forced from outside ([`super::inputs`]); forced or not, a switch here
//! is *actuated* or not (pressed by the carriage): what level that puts on
//! the pin depends on the switch type, and what the firmware makes of the
//! level on NullPositive.

/// The layout of one axis.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Stage {
    /// Distance between the mechanical stops: the carriage stays within
    /// 0..=travel. 0: no stops.
    pub travel: u32,
    /// A rotary axis: the switch comes round every `turn` µsteps, and there
    /// are no stops or end switches. 0: linear.
    pub turn: u32,
    /// The reference switch is actuated over `ref_at .. ref_at + ref_width`
    /// (carriage positions). Width 0: no switch.
    pub ref_at: u32,
    pub ref_width: u32,
    /// A normally-closed switch to GND (an "opener", recommended in §5.5.2.1):
    /// the pin is low until the switch is actuated. Else a closer: low while
    /// actuated.
    pub opener: bool,
    /// The end switches on A_In (§5.5.2.2) are actuated within this many
    /// µsteps of each stop. 0: none.
    pub end_zone: u32,
    /// Where the carriage stands at power-on.
    pub start: u32,
    /// The A_In end switches are wired the wrong way round: the one at
    /// the left stop pulls A_In up (what the firmware takes for the right
    /// end), the one at the right stop down.
    pub limits_swapped: bool,
}

/// The demo stage's travel between its stops: 200000 µsteps, 12500 full
/// steps (62.5 turns of a 200-step motor).
pub const DEMO_TRAVEL: u32 = 200_000;
/// Its reference switch: an opener actuated over the first 400 µsteps from
/// the left stop, the combined end/reference switch of §5.5.2.3 (every
/// §5.5.3 example has its reference on the left).
pub const DEMO_REF_WIDTH: u32 = 400;
/// Its A_In end switches: actuated within 100 µsteps of either stop.
pub const DEMO_END_ZONE: u32 = 100;
/// Where its carriage stands at power-on: 80 µsteps off the switch, so
/// that a search at the slow velocity of §6.4.8 finds it in seconds.
pub const DEMO_START: u32 = 480;

/// A_In with no end switch actuated, with the left one, with the right one
/// (an end-switch divider: left pulls the input down, right up).
pub const AIN_FREE: u16 = 512;
pub const AIN_LEFT_END: u16 = 0;
pub const AIN_RIGHT_END: u16 = 1023;

impl Default for Stage {
    fn default() -> Self {
        Stage {
            travel: DEMO_TRAVEL,
            turn: 0,
            ref_at: 0,
            ref_width: DEMO_REF_WIDTH,
            opener: true,
            end_zone: DEMO_END_ZONE,
            start: DEMO_START,
            limits_swapped: false,
        }
    }
}

/// Inputs forced from outside; `None` leaves them to the carriage.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Forced {
    pub reference: Option<bool>,
    pub left_end: Option<bool>,
    pub right_end: Option<bool>,
    pub analog: Option<u16>,
}

/// One axis' machine and where its carriage is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mechanics {
    pub stage: Stage,
    pub forced: Forced,
    carriage: i64,
}

impl Mechanics {
    pub fn new(stage: Stage) -> Mechanics {
        let carriage = i64::from(stage.start);
        let mut mechanics = Mechanics {
            stage,
            forced: Forced::default(),
            carriage,
        };
        mechanics.place(carriage);
        mechanics
    }

    /// Where the carriage is, µsteps from the left stop.
    pub fn carriage(&self) -> i64 {
        self.carriage
    }

    /// Put the carriage somewhere by hand (kept between the stops); where
    /// it ended up.
    pub fn place(&mut self, at: i64) -> i64 {
        self.carriage = self.within_stops(at);
        self.carriage
    }

    /// The motor turned `steps` µsteps: the carriage follows up to a stop,
    /// where the rest are lost (the motor stalls). How many it followed.
    pub fn drive(&mut self, steps: i64) -> i64 {
        let before = self.carriage;
        self.carriage = self.within_stops(before.saturating_add(steps));
        self.carriage - before
    }

    fn within_stops(&self, at: i64) -> i64 {
        if self.stage.turn == 0 && self.stage.travel > 0 {
            at.clamp(0, i64::from(self.stage.travel))
        } else {
            at
        }
    }

    /// Whether the carriage actuates the reference switch (or it is forced).
    pub fn switch_actuated(&self) -> bool {
        if let Some(forced) = self.forced.reference {
            return forced;
        }
        let width = i64::from(self.stage.ref_width);
        if width == 0 {
            return false;
        }
        let at = if self.stage.turn > 0 {
            self.carriage.rem_euclid(i64::from(self.stage.turn))
        } else {
            self.carriage
        };
        let low = i64::from(self.stage.ref_at);
        (low..low + width).contains(&at)
    }

    /// The level on Ref_In (true = high): the 10 k pull-up unless the
    /// switch connects the pin to GND (§5.5.2.1).
    pub fn switch_level(&self) -> bool {
        let actuated = self.switch_actuated();
        if self.stage.opener {
            actuated
        } else {
            !actuated
        }
    }

    fn end_actuated(&self, left: bool) -> bool {
        let forced = if left {
            self.forced.left_end
        } else {
            self.forced.right_end
        };
        if let Some(forced) = forced {
            return forced;
        }
        let stage = &self.stage;
        if stage.turn > 0 || stage.travel == 0 || stage.end_zone == 0 {
            return false;
        }
        let zone = i64::from(stage.end_zone);
        if left {
            self.carriage < zone
        } else {
            self.carriage > i64::from(stage.travel) - zone
        }
    }

    pub fn left_end_actuated(&self) -> bool {
        self.end_actuated(true)
    }

    pub fn right_end_actuated(&self) -> bool {
        self.end_actuated(false)
    }

    /// A_In, 0..1023: forced, else from the end switches.
    pub fn analog(&self) -> u16 {
        if let Some(value) = self.forced.analog {
            return value;
        }
        let (left, right) = if self.stage.limits_swapped {
            (AIN_RIGHT_END, AIN_LEFT_END)
        } else {
            (AIN_LEFT_END, AIN_RIGHT_END)
        };
        if self.left_end_actuated() {
            left
        } else if self.right_end_actuated() {
            right
        } else {
            AIN_FREE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stop_holds_the_carriage_and_the_rest_of_the_steps_are_lost() {
        let mut m = Mechanics::new(Stage::default());
        assert_eq!(m.carriage(), 480);
        assert_eq!(m.drive(-300), -300);
        assert_eq!(m.drive(-1000), -180, "only 180 to the left stop");
        assert_eq!(m.carriage(), 0);
        assert_eq!(m.drive(250_000), 200_000);
        assert_eq!(m.place(-5), 0);
    }

    #[test]
    fn the_demo_opener_is_high_while_actuated() {
        let mut m = Mechanics::new(Stage::default());
        assert!(!m.switch_actuated());
        assert!(!m.switch_level(), "an opener holds the pin low");
        m.place(399);
        assert!(m.switch_actuated() && m.switch_level());
        m.place(400);
        assert!(!m.switch_actuated());
        m.stage.opener = false;
        assert!(m.switch_level(), "a closer leaves the pull-up alone");
        m.forced.reference = Some(true);
        assert!(!m.switch_level());
    }

    #[test]
    fn the_end_switches_pull_a_in_down_or_up() {
        let mut m = Mechanics::new(Stage::default());
        assert_eq!(m.analog(), AIN_FREE);
        m.place(99);
        assert_eq!(m.analog(), AIN_LEFT_END);
        m.place(i64::from(DEMO_TRAVEL) - 99);
        assert_eq!(m.analog(), AIN_RIGHT_END);
        m.forced.analog = Some(700);
        assert_eq!(m.analog(), 700);
    }

    #[test]
    fn swapped_end_switches_pull_a_in_the_other_way() {
        let mut m = Mechanics::new(Stage {
            limits_swapped: true,
            ..Stage::default()
        });
        m.place(i64::from(DEMO_TRAVEL) - 99);
        assert!(m.right_end_actuated());
        assert_eq!(m.analog(), AIN_LEFT_END, "the right end reads as the left");
        m.place(99);
        assert_eq!(m.analog(), AIN_RIGHT_END);
    }

    #[test]
    fn a_rotary_stage_has_no_stops_and_its_switch_comes_round() {
        let mut m = Mechanics::new(Stage {
            turn: 6400,
            ref_at: 100,
            ref_width: 50,
            ..Stage::default()
        });
        m.place(0);
        assert_eq!(m.drive(-64_000 - 6400 + 120), -64_000 - 6400 + 120);
        assert!(m.switch_actuated(), "at -70280 ≡ 120 (mod 6400)");
        assert!(!m.left_end_actuated());
    }
}
