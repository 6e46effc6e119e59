//! The TMCM-1110's inputs, outputs and switches (TMCL firmware manual
//! §3.6.14-§3.6.15 GIO/SIO, §4 axis parameters 9-11, §6.2 Table 21).
//! The general inputs are read in one line, `GIO 255, 0` (bank 0, all
//! inputs): the manual does not give its bit order; bit n is taken as
//! port n (AIN0 bit 0, PWMD0 bit 1 … PWMU2 bit 6), as `GIO n, 0` numbers
//! them. The manual gives no volt scale for AIN0 (a "16 bit result"
//! 0..65535): it is shown in counts. PWMU0..2 are outputs by default
//! (global parameter 78 = 7, §6.2), read as inputs only where GP 78 says.

use crate::protocol::io::{IoKind, IoPlan, IoPoint, ReadRule, input, output};

pub struct TmclIo;

impl IoPlan for TmclIo {
    fn points(&self) -> &'static [IoPoint] {
        POINTS
    }
}

const SWITCH: IoKind = IoKind::Switch;
const DIGITAL: IoKind = IoKind::DigitalInput;

const POINTS: &[IoPoint] = &[
    input(
        "left limit",
        SWITCH,
        Some(0),
        "GAP 11, 0",
        ReadRule::Value,
        true,
        "left limit switch state, axis parameter 11 (§4)",
    ),
    input(
        "right limit",
        SWITCH,
        Some(0),
        "GAP 10, 0",
        ReadRule::Value,
        true,
        "right limit switch state, axis parameter 10 (§4)",
    ),
    input(
        "home",
        SWITCH,
        Some(0),
        "GAP 9, 0",
        ReadRule::Value,
        true,
        "home switch state, axis parameter 9 (§4)",
    ),
    input(
        "AIN0",
        DIGITAL,
        None,
        "GIO 255, 0",
        ReadRule::Bit(0),
        true,
        "AIN0 read as digital, GIO 0, 0 (§3.6.15)",
    ),
    input(
        "PWMD0",
        DIGITAL,
        None,
        "GIO 255, 0",
        ReadRule::Bit(1),
        true,
        "general input, GIO 1, 0 (§3.6.15)",
    ),
    input(
        "PWMD1",
        DIGITAL,
        None,
        "GIO 255, 0",
        ReadRule::Bit(2),
        true,
        "general input, GIO 2, 0 (§3.6.15)",
    ),
    input(
        "PWMD2",
        DIGITAL,
        None,
        "GIO 255, 0",
        ReadRule::Bit(3),
        true,
        "general input, GIO 3, 0 (§3.6.15)",
    ),
    input(
        "PWMU0",
        DIGITAL,
        None,
        "GIO 255, 0",
        ReadRule::Bit(4),
        true,
        "general input, GIO 4, 0 (§3.6.15)",
    ),
    input(
        "PWMU1",
        DIGITAL,
        None,
        "GIO 255, 0",
        ReadRule::Bit(5),
        true,
        "general input, GIO 5, 0 (§3.6.15)",
    ),
    input(
        "PWMU2",
        DIGITAL,
        None,
        "GIO 255, 0",
        ReadRule::Bit(6),
        true,
        "general input, GIO 6, 0 (§3.6.15)",
    ),
    input(
        "AIN0",
        IoKind::AnalogInput { volts: None },
        None,
        "GIO 0, 1",
        ReadRule::Value,
        false,
        "analog input, 0..65535 (§3.6.15 bank 1; no volt scale given)",
    ),
    output(
        "OUT0",
        Some("GIO 0, 2"),
        ReadRule::Value,
        ["SIO 0, 2, 0", "SIO 0, 2, 1"],
        "OpenDrain1 (OUT0 in §3.5.6.4), SIO 0, 2 (§3.6.14)",
    ),
    output(
        "OUT1",
        Some("GIO 1, 2"),
        ReadRule::Value,
        ["SIO 1, 2, 0", "SIO 1, 2, 1"],
        "OpenDrain2, SIO 1, 2 (§3.6.14)",
    ),
    output(
        "PWMU0",
        Some("GIO 2, 2"),
        ReadRule::Value,
        ["SIO 2, 2, 0", "SIO 2, 2, 1"],
        "SIO 2, 2; an output where global parameter 78 says (§6.2)",
    ),
    output(
        "PWMU1",
        Some("GIO 3, 2"),
        ReadRule::Value,
        ["SIO 3, 2, 0", "SIO 3, 2, 1"],
        "SIO 3, 2; an output where global parameter 78 says (§6.2)",
    ),
    output(
        "PWMU2",
        Some("GIO 4, 2"),
        ReadRule::Value,
        ["SIO 4, 2, 0", "SIO 4, 2, 1"],
        "SIO 4, 2; an output where global parameter 78 says (§6.2)",
    ),
    output(
        "PWMD0",
        Some("GIO 5, 2"),
        ReadRule::Value,
        ["SIO 5, 2, 0", "SIO 5, 2, 1"],
        "SIO 5, 2; an output where global parameter 78 says (§6.2)",
    ),
    output(
        "PWMD1",
        Some("GIO 6, 2"),
        ReadRule::Value,
        ["SIO 6, 2, 0", "SIO 6, 2, 1"],
        "SIO 6, 2; an output where global parameter 78 says (§6.2)",
    ),
    output(
        "PWMD2",
        Some("GIO 7, 2"),
        ReadRule::Value,
        ["SIO 7, 2, 0", "SIO 7, 2, 1"],
        "SIO 7, 2; an output where global parameter 78 says (§6.2)",
    ),
];
