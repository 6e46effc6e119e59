//! The StepRocker's single axis: ramp generator (TMC429, manual §6.1),
//! limit and home switches, reference search (§7.1). Placeholder interface;
//! the real model replaces the bodies.

use std::time::Duration;

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
    /// Position mode: the actual position reached the target (AP8 rose).
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

/// Where the simulated machine's switches sit, in microsteps of the
/// position counter. Tests and the simulator's options move them.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SwitchLayout {
    /// Left stop switch is active at and below this position.
    pub left_limit: Option<i64>,
    /// Right stop switch is active at and above this position.
    pub right_limit: Option<i64>,
    /// Home switch is active inside this window (inclusive).
    pub home: Option<(i64, i64)>,
}

/// Axis parameters whose values the motion model owns (others are plain
/// storage in the module).
pub const MOTION_PARAMS: &[u8] = &[
    0, 1, 2, 3, 4, 5, 8, 9, 10, 11, 12, 13, 130, 135, 138, 140, 149, 153, 154, 174, 181, 193, 194,
    195, 196, 197, 206, 207, 209, 210, 212,
];

#[derive(Debug, Clone, Default)]
pub struct Axis {
    params: std::collections::BTreeMap<u8, i32>,
    layout: SwitchLayout,
}

impl Axis {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn owns_param(number: u8) -> bool {
        MOTION_PARAMS.contains(&number)
    }

    pub fn param(&self, number: u8) -> i32 {
        self.params.get(&number).copied().unwrap_or(0)
    }

    pub fn set_param(&mut self, number: u8, value: i32) {
        if number == 0 {
            self.move_to(value);
        } else {
            self.params.insert(number, value);
        }
    }

    /// ROR (positive) / ROL (negative): velocity mode at `velocity` [int].
    pub fn rotate(&mut self, velocity: i32) {
        self.params.insert(2, velocity);
        self.params.insert(138, 2);
    }

    /// MST: decelerate to standstill.
    pub fn stop(&mut self) {
        self.rotate(0);
    }

    /// MVP: position mode towards `target`.
    pub fn move_to(&mut self, target: i32) {
        self.params.insert(0, target);
        self.params.insert(138, 0);
    }

    pub fn start_reference_search(&mut self) {}

    pub fn stop_reference_search(&mut self) {}

    pub fn reference_search_active(&self) -> bool {
        false
    }

    /// Logical state of a switch input (AP9..AP11), after GP79 polarity.
    pub fn switch(&self, _which: Switch) -> bool {
        false
    }

    /// GP79: end switch polarity reversed.
    pub fn set_end_switch_polarity_reversed(&mut self, _reversed: bool) {}

    /// The simulated machine's switch positions.
    pub fn layout_mut(&mut self) -> &mut SwitchLayout {
        &mut self.layout
    }

    /// True while the motor turns or a ramp is in progress.
    pub fn is_moving(&self) -> bool {
        self.param(3) != 0
    }

    /// AP207 is cleared when read and by every motion command (§4 Table 16);
    /// the module calls this after answering a GAP 207.
    pub fn clear_error_flags(&mut self) {
        self.params.insert(207, 0);
    }

    pub fn advance(&mut self, _dt: Duration, events: &mut Vec<AxisEvent>) {
        if self.param(138) == 0 && self.param(1) != self.param(0) {
            self.params.insert(1, self.param(0));
            self.params.insert(8, 1);
            events.push(AxisEvent::TargetReached);
        }
    }
}
