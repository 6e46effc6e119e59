//! Which axes a controller has and of what kind. A MultiFlex has up to 8
//! axes, each an analog (servo) or a pulse (stepper) command axis, the
//! stepper open or closed loop (Ch2, digest §2); which ones depends on the
//! model, so it is data. The default is the machine the manual's examples
//! use: axes 1–4 servos, axis 5 a stepper (`5MF`, `5HS`, `5ES25.6`…).

use crate::protocol::console::AxisInfo;

/// The most axes a MultiFlex drives (`CM n ≤ 8`; compare outputs for
/// axes 1–4 and 5–8, Ch9).
pub const MAX_AXES: u8 = 8;

/// What drives an axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AxisKind {
    /// Analog command axis (±10 V or PWM), closed loop on its encoder.
    Servo,
    /// Pulse command axis without feedback (the default: `IM0`).
    OpenLoopStepper,
    /// Pulse command axis with encoder feedback (`IM1` + `ES`).
    ClosedLoopStepper,
}

impl AxisKind {
    /// Whether it has a following error (servo, closed-loop stepper: Ch8
    /// TF, SE).
    pub fn closed_loop(self) -> bool {
        !matches!(self, AxisKind::OpenLoopStepper)
    }

    pub fn name(self) -> &'static str {
        match self {
            AxisKind::Servo => "servo",
            AxisKind::OpenLoopStepper => "stepper",
            AxisKind::ClosedLoopStepper => "closed-loop stepper",
        }
    }
}

/// The axes of one controller, numbered from 1 as MCCL numbers them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Machine {
    /// Kind of axis 1, 2, ….
    pub kinds: &'static [AxisKind],
    /// How the console shows them (`number` is the MCCL axis number).
    pub axes: &'static [AxisInfo],
}

impl Machine {
    /// The kind of axis `number` (1-based), if the machine has it.
    pub fn kind(&self, number: u8) -> Option<AxisKind> {
        let index = usize::from(number).checked_sub(1)?;
        self.kinds.get(index).copied()
    }

    pub fn has(&self, number: u8) -> bool {
        self.kind(number).is_some()
    }

    /// `1–5` for messages.
    pub fn span(&self) -> String {
        match self.kinds.len() {
            0 => "none".into(),
            1 => "1".into(),
            n => format!("1–{n}"),
        }
    }
}

/// Axes 1–4 servos, axis 5 a stepper (digest §2).
pub const DEFAULT_MACHINE: Machine = Machine {
    kinds: &[
        AxisKind::Servo,
        AxisKind::Servo,
        AxisKind::Servo,
        AxisKind::Servo,
        AxisKind::OpenLoopStepper,
    ],
    axes: &[
        AxisInfo {
            number: 1,
            name: "servo 1",
        },
        AxisInfo {
            number: 2,
            name: "servo 2",
        },
        AxisInfo {
            number: 3,
            name: "servo 3",
        },
        AxisInfo {
            number: 4,
            name: "servo 4",
        },
        AxisInfo {
            number: 5,
            name: "step 5",
        },
    ],
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_machine_is_four_servos_and_a_stepper() {
        let m = DEFAULT_MACHINE;
        assert_eq!(m.kind(1), Some(AxisKind::Servo));
        assert_eq!(m.kind(5), Some(AxisKind::OpenLoopStepper));
        assert_eq!(m.kind(0), None);
        assert_eq!(m.kind(6), None);
        assert_eq!(m.span(), "1–5");
        assert_eq!(m.kinds.len(), m.axes.len());
        assert!(m.axes.iter().zip(1..).all(|(a, n)| a.number == n));
        assert!(!AxisKind::OpenLoopStepper.closed_loop() && AxisKind::Servo.closed_loop());
    }
}
