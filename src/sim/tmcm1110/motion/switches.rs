//! The stage's switches: which inputs there are, what a switch event is,
//! and where on the travel each switch is (the layout `LIMITS=` and the
//! demo stage set).

/// Which switch input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Switch {
    Left,
    Right,
    Home,
}

/// Something the axis did that the module must react to (138 reply,
/// interrupts, WAIT conditions).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisEvent {
    /// Position mode: a move (MVP, SAP 0/138) arrived on its target and
    /// stands there.
    TargetReached,
    /// A limit switch stopped the motor.
    LimitStop(Switch),
    /// A reference search finished.
    ReferenceSearchDone,
    /// StallGuard stop (AP181/AP174): AP207 bit 0 set, interrupt 15.
    StallStop,
    /// Encoder deviation stop (AP212): AP207 bit 1 set, interrupt 21.
    DeviationStop,
    /// A switch input changed its logical level (interrupts 27/28, WAIT REFSW/LIMSW).
    SwitchChanged { switch: Switch, active: bool },
}

/// How far each end switch of a new [`SwitchLayout`] stays actuated beyond
/// its switching point, in microsteps: one motor turn at 256 µsteps. Long
/// enough that a soft stop (AP149 = 1) from the fastest speed (2047, pulse
/// divisor 3) with the default acceleration (≈ 41900 µsteps of braking)
/// still ends on the switch, short enough that reference modes 3 and 4
/// cross the switch in seconds at the default switch speed. A soft stop
/// braking longer than the width carries the carriage past the cam: the
/// switch opens again and, no longer held, the motor heads for its goal as
/// after leaving any switch (a real machine would hit its end stop there).
pub const DEFAULT_END_SWITCH_WIDTH: i64 = 51_200;

/// Where the simulated machine's switches sit, in microsteps of the
/// machine position (which is the position counter until SAP 1 or a
/// reference search rewrites the counter; the switches don't move then).
/// Tests and the simulator's options move them.
///
/// An end switch is a lever under a cam: it closes at its switching point
/// and stays closed for `end_switch_width` microsteps further out; beyond
/// that the carriage has passed the cam and the switch is open again. A
/// moving motor is stopped where the switch closes, so the carriage only
/// gets further out with the switch disabled (AP12/AP13 = 1), during a soft
/// stop's braking (AP149 = 1), or in a reference search, which crosses the
/// switch to find its middle (modes 3 and 4, §7.1.3/§7.1.4).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SwitchLayout {
    /// Switching point of the left end switch: active from here down to
    /// `left_limit − end_switch_width`.
    pub left_limit: Option<i64>,
    /// Switching point of the right end switch: active from here up to
    /// `right_limit + end_switch_width`.
    pub right_limit: Option<i64>,
    /// Actuated length of each end switch beyond its switching point
    /// (negative counts as 0: active on the switching point only).
    pub end_switch_width: i64,
    /// Home switch is active inside this window (inclusive).
    pub home: Option<(i64, i64)>,
    /// Mechanical end stops (lowest, highest machine position): the
    /// carriage goes no further whatever the switches say. The simulator
    /// stands the motor there at once, without a limit-stop event (a real
    /// stepper would stall against the stop and lose steps).
    pub end_stops: Option<(i64, i64)>,
    /// The end switches are wired to each other's input: the + end closes
    /// the left limit input (AP11), the − end the right one.
    pub limits_swapped: bool,
}

impl Default for SwitchLayout {
    /// A machine without switches (end switches of the default width once
    /// placed).
    fn default() -> Self {
        SwitchLayout {
            left_limit: None,
            right_limit: None,
            end_switch_width: DEFAULT_END_SWITCH_WIDTH,
            home: None,
            end_stops: None,
            limits_swapped: false,
        }
    }
}

impl SwitchLayout {
    /// The simulated machine a new [`Axis`] starts with: a linear stage with
    /// end switches closing at ±200000 µsteps (≈ ±3.9 turns at 256 µsteps)
    /// and actuated for [`DEFAULT_END_SWITCH_WIDTH`] beyond, and a home
    /// switch over −1000..1000, so the carriage starts on home; its end
    /// stops one switch width beyond each switch's far end (±302400), so
    /// that a carriage whose switch does not stop it (disabled, or wired
    /// to the other input) does not run off forever.
    pub const DEMO_STAGE: SwitchLayout = SwitchLayout {
        left_limit: Some(-200_000),
        right_limit: Some(200_000),
        end_switch_width: DEFAULT_END_SWITCH_WIDTH,
        home: Some((-1_000, 1_000)),
        end_stops: Some((
            -200_000 - 2 * DEFAULT_END_SWITCH_WIDTH,
            200_000 + 2 * DEFAULT_END_SWITCH_WIDTH,
        )),
        limits_swapped: false,
    };

    /// The machine positions (lowest, highest) where the left end switch is
    /// actuated.
    pub fn left_switch_span(&self) -> Option<(i64, i64)> {
        self.left_limit
            .map(|edge| (edge.saturating_sub(self.width()), edge))
    }

    /// The machine positions (lowest, highest) where the right end switch is
    /// actuated.
    pub fn right_switch_span(&self) -> Option<(i64, i64)> {
        self.right_limit
            .map(|edge| (edge, edge.saturating_add(self.width())))
    }

    /// The machine positions (lowest, highest) where the home switch is
    /// actuated.
    pub fn home_span(&self) -> Option<(i64, i64)> {
        self.home.map(|(a, b)| (a.min(b), a.max(b)))
    }

    pub(super) fn width(&self) -> i64 {
        self.end_switch_width.max(0)
    }

    pub(super) fn span(&self, which: Switch) -> Option<(i64, i64)> {
        match which {
            Switch::Left => self.left_switch_span(),
            Switch::Right => self.right_switch_span(),
            Switch::Home => self.home_span(),
        }
    }
}
