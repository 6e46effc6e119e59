//! The texts the controller prints: VE (manual Ch8; the PCI text is the
//! manual's MFX-PCI1440 example), ID0–ID7 (Ch8; only a stepper's ID0
//! survives in the manual, as a screenshot without its layout: one item a
//! line here, and the other pages in its style), and HE (Ch13; its
//! output is lost: the mnemonics ten a line, the variable names, one
//! command's line from the command table).

use super::Model;
use super::axis::status::{self, StatusWord, Surroundings};
use super::axis::{Axis, Mode};
use super::commands::{COMMANDS, CommandSpec};
use super::io;
use super::registers::VARIABLES;

/// VE (Ch8): the manual's text for the PCI; an ETH in the same words.
pub fn version(model: Model) -> &'static [&'static str] {
    match model {
        Model::Pci => &[
            "MFX-PCI1440-3-A Motion Controller",
            "Hardware: 16384K Private RAM, 512K Flash Memory",
            "System Firmware Ver. PM1 Rev. 4.5a",
            "Copyright (c) 2002-2006 Precision MicroControl Corporation",
            "All rights reserved.",
        ],
        Model::Eth => &[
            "MFX-ETH1000-4-A Motion Controller (axterm simulator)",
            "Hardware: 16384K Private RAM, 512K Flash Memory",
            "System Firmware Ver. PM1 Rev. 4.5a",
            "Copyright (c) 2002-2006 Precision MicroControl Corporation",
            "All rights reserved.",
        ],
    }
}

/// One phrase per state, as the ID0 screenshot words them.
fn phrase(on: bool, yes: &str, no: &str) -> String {
    if on { yes.to_string() } else { no.to_string() }
}

/// ID0: the primary status in words.
pub fn primary(axis: &Axis, around: &Surroundings) -> Vec<String> {
    let word = axis.status_word(StatusWord::Primary, around);
    let bit = |b: u32| word & b != 0;
    let s = &axis.settings;
    let stepper = !axis.is_servo();
    let (looking, found, input) = if axis.is_open_loop_stepper() {
        ("Looking For Home", "Home Found", "Home Input")
    } else {
        ("Looking For Index", "Index Found", "Index Input")
    };
    let mut lines = vec![
        if stepper {
            "STEPPER STATUS:"
        } else {
            "SERVO STATUS:"
        }
        .to_string(),
        phrase(bit(status::MOTOR_ERROR), "Motor Error", "No Motor Error"),
        phrase(bit(status::MOTOR_ON), "Motor On", "Motor Off"),
        phrase(bit(status::AT_TARGET), "At Target", "Not At Target"),
        phrase(
            bit(status::TRAJECTORY_COMPLETE),
            "Trajectory Complete",
            "Trajectory Not Complete",
        ),
        phrase(
            bit(status::DIRECTION),
            "Direction = Negative",
            "Direction = Positive",
        ),
        phrase(
            bit(status::BREAKPOINT),
            "Breakpoint Reached",
            "Breakpoint Not Reached",
        ),
        phrase(
            bit(status::FOLLOWING_ERROR),
            "Max. Following Error Exceeded",
            "Max. Following Error Not Exceeded",
        ),
        if bit(status::AMP_FAULT) {
            "Amplifier Fault Tripped".to_string()
        } else {
            phrase(
                s.fault_check,
                "Amplifier Fault Enabled",
                "Amplifier Fault Disabled",
            )
        },
    ];
    let limits = [
        (status::HARD_LIMIT_PLUS, 1, "Hard Motion Limit Positive"),
        (status::HARD_LIMIT_MINUS, 2, "Hard Motion Limit Negative"),
        (status::SOFT_LIMIT_HIGH, 4, "Soft Motion Limit High"),
        (status::SOFT_LIMIT_LOW, 8, "Soft Motion Limit Low"),
    ];
    for (tripped, enabled, name) in limits {
        let state = if bit(tripped) {
            "Tripped"
        } else if s.limits & enabled != 0 {
            "Enabled"
        } else {
            "Disabled"
        };
        lines.push(format!("{name} {state}"));
    }
    lines.extend([
        phrase(bit(status::LOOKING), looking, &format!("Not {looking}")),
        phrase(
            bit(status::FOUND),
            found,
            &found.replace("Found", "Not Found"),
        ),
        phrase(bit(status::HOMED), "Motor Is Homed", "Motor Is Not Homed"),
        format!("{input} = {}", u8::from(bit(status::INDEX_INPUT))),
    ]);
    if axis.is_servo() {
        lines.push(format!(
            "Coarse Home Input = {}",
            u8::from(bit(status::COARSE_HOME_INPUT))
        ));
    } else {
        lines.push(format!(
            "Auxiliary Encoder Index = {}",
            u8::from(bit(status::AUX_INDEX_INPUT))
        ));
    }
    lines.extend([
        format!(
            "Amplifier Fault Input = {}",
            u8::from(bit(status::FAULT_INPUT))
        ),
        format!(
            "Limit Positive Input = {}",
            u8::from(bit(status::LIMIT_PLUS_INPUT))
        ),
        format!(
            "Limit Negative Input = {}",
            u8::from(bit(status::LIMIT_MINUS_INPUT))
        ),
    ]);
    lines
}

/// ID1: the auxiliary status, one line per named bit.
pub fn auxiliary(axis: &Axis, around: &Surroundings) -> Vec<String> {
    const NAMES: &[(u32, &str)] = &[
        (0, "Hard Motion Limit Positive Enabled"),
        (1, "Hard Motion Limit Negative Enabled"),
        (2, "Hard Motion Limit Mode Abrupt"),
        (3, "Hard Motion Limit Mode Smooth"),
        (4, "Soft Motion Limit High Enabled"),
        (5, "Soft Motion Limit Low Enabled"),
        (6, "Soft Motion Limit Mode Abrupt"),
        (7, "Soft Motion Limit Mode Smooth"),
        (8, "Positive Limit Invert"),
        (9, "Negative Limit Invert"),
        (10, "Amplifier / Driver Fault Enabled"),
        (11, "Phasing Reverse"),
        (12, "Backlash Compensation On"),
        (16, "Low Speed"),
        (17, "Medium Speed"),
        (18, "High Speed"),
        (20, "Waiting For Primary Compare"),
        (21, "Waiting For Primary Capture"),
        (22, "Synchronization On"),
        (23, "Ready for Synchronized move"),
        (27, "Full Current"),
        (28, "Open Loop Enable PID changes"),
    ];
    let word = axis.status_word(StatusWord::Auxiliary, around);
    let mut lines = vec!["AUXILIARY STATUS:".to_string()];
    lines.extend(
        NAMES
            .iter()
            .map(|(bit, name)| format!("{name} = {}", (word >> bit) & 1)),
    );
    lines
}

/// ID2: the motor table in user units.
pub fn motor_table(axis: &Axis) -> Vec<String> {
    let s = &axis.settings;
    let u = &axis.units;
    let mode = match axis.mode {
        Mode::Position => "Position".to_string(),
        Mode::Velocity => "Velocity".to_string(),
        Mode::Gain => "Gain".to_string(),
        Mode::Torque => "Torque".to_string(),
        Mode::Contour(c) => format!("Contour (axis {c})"),
    };
    vec![
        format!("MOTOR TABLE, AXIS {}:", axis.number),
        format!("Mode = {mode}"),
        format!("Position = {:.3}", u.to_user(axis.position())),
        format!("Optimal = {:.3}", u.to_user(axis.optimal)),
        format!("Target = {:.3}", u.to_user(axis.target)),
        format!("Velocity = {:.3}", s.velocity),
        format!("Acceleration = {:.3}", s.acceleration),
        format!("Deceleration = {:.3}", s.deceleration),
        format!("Minimum Velocity = {:.3}", s.minimum_velocity),
        format!("Velocity Override = {:.3}", s.velocity_override),
        format!("Max. Following Error = {:.3}", s.following_limit),
        format!("Deadband = {:.3}", s.deadband),
        format!("Delay At Target = {:.4}", s.target_delay),
        format!("High Limit = {:.3}", s.high_limit),
        format!("Low Limit = {:.3}", s.low_limit),
        format!("User Scale = {:.3}", s.units.scale),
        format!("User Rate = {:.3}", s.units.rate),
        format!("User Offset = {:.3}", s.units.offset),
        format!("User Zero = {:.3}", s.units.zero),
    ]
}

/// ID3: the internal motor table (raw counters).
pub fn internal_table(axis: &Axis) -> Vec<String> {
    vec![
        format!("INTERNAL MOTOR TABLE, AXIS {}:", axis.number),
        format!("Position Count = {}", axis.position()),
        format!("Optimal Count = {}", axis.optimal.round()),
        format!("Target Count = {}", axis.target.round()),
        format!("Index Count = {}", axis.index_position.round()),
        format!("Step Count = {}", axis.steps.round()),
        format!("Contour Count = {}", axis.contour_count),
    ]
}

/// ID4: the filter gains and the command output.
pub fn filter(axis: &Axis) -> Vec<String> {
    let s = &axis.settings;
    vec![
        format!("FILTER GAINS, AXIS {}:", axis.number),
        format!("Proportional Gain = {:.6}", s.proportional_gain),
        format!("Derivative Gain = {:.6}", s.derivative_gain),
        format!("Integral Gain = {:.6}", s.integral_gain),
        format!("Integration Limit = {:.6}", s.integration_limit),
        format!("Derivative Period = {}", s.derivative_period),
        format!("Velocity Gain = {:.6}", s.velocity_gain),
        format!("Acceleration Gain = {:.6}", s.acceleration_gain),
        format!("Deceleration Gain = {:.6}", s.deceleration_gain),
        format!("Torque Limit = {:.3}", s.torque),
        format!("Command Output = {:.3}", axis.output_voltage()),
    ]
}

/// ID5: encoder fault inputs and enables.
pub fn encoder_faults(axis: &Axis) -> Vec<String> {
    let word = axis.encoder_fault_status();
    vec![
        format!("ENCODER FAULT, AXIS {}:", axis.number),
        format!("Primary Encoder Fault = {}", word & 1),
        format!("Phase A Fault = {}", (word >> 1) & 1),
        format!("Phase B Fault = {}", (word >> 2) & 1),
        format!("Phase Z Fault = {}", (word >> 3) & 1),
        format!("Primary Encoder Fault Enabled = {}", (word >> 12) & 1),
    ]
}

/// ID6: the I/O channels of the axis (Ch9 Table 1).
pub fn io_assignment(axis: &Axis) -> Vec<String> {
    let Some(c) = io::channels_of(axis.number) else {
        return vec![format!("AXIS {} I/O: none", axis.number)];
    };
    let home = if axis.is_servo() {
        "Coarse Home"
    } else {
        "Home"
    };
    vec![
        format!("AXIS {} I/O ASSIGNMENT:", axis.number),
        format!("{home} (inp) {}", c.home),
        format!("Plus Limit (inp) {}", c.limit_plus),
        format!("Minus Limit (inp) {}", c.limit_minus),
        format!("Amp Fault (inp) {}", c.fault),
        format!("Capture (inp) {}", c.capture),
        format!("Compare (out) {}", c.compare),
    ]
}

/// ID7: the active background tasks.
pub fn tasks(ids: &[i32]) -> Vec<String> {
    let mut lines = vec![format!("ACTIVE BACKGROUND TASKS: {}", ids.len())];
    lines.extend(ids.iter().map(|id| format!("Task ID {id}")));
    lines
}

/// HE0: every mnemonic, ten a line.
pub fn mnemonics() -> Vec<String> {
    let names: Vec<&str> = COMMANDS.iter().map(|c| c.mnemonic).collect();
    names.chunks(10).map(|chunk| chunk.join(" ")).collect()
}

/// HE1: the motor-table variable names, eight a line.
pub fn variables() -> Vec<String> {
    let names: Vec<&str> = VARIABLES.iter().map(|v| v.name).collect();
    names.chunks(8).map(|chunk| chunk.join(" ")).collect()
}

/// HE"mm": the command's line.
pub fn describe(spec: &CommandSpec) -> String {
    let simulated = if spec.simulated {
        ""
    } else {
        " (not simulated)"
    };
    format!("{} - {}{simulated}", spec.mnemonic, spec.summary)
}
