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
}

/// Axis parameters whose values the motion model owns (others are plain
/// storage in the module).
pub const MOTION_PARAMS: &[u8] = &[
    0, 1, 2, 3, 4, 5, 8, 9, 10, 11, 12, 13, 130, 135, 138, 140, 149, 153, 154, 193, 194, 195, 196,
    197,
];

#[derive(Debug, Clone, Default)]
pub struct Axis {
    params: std::collections::BTreeMap<u8, i32>,
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

    pub fn switch(&self, _which: Switch) -> bool {
        false
    }

    pub fn advance(&mut self, _dt: Duration, events: &mut Vec<AxisEvent>) {
        if self.param(138) == 0 && self.param(1) != self.param(0) {
            self.params.insert(1, self.param(0));
            self.params.insert(8, 1);
            events.push(AxisEvent::TargetReached);
        }
    }
}
