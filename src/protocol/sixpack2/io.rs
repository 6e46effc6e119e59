//! The SIXpack 2's inputs, outputs and switches (manual §7.3 $30-$32,
//! §5.2.3, §5.5.2, §6.1.4). One `GetInputValues 7` answers the supply
//! voltage with all six reference inputs, the jumpers JP1/JP2 and TTLIO1;
//! a motor's stop switches sit on its analog A_In (`GetInputValues n`,
//! 0..1023 ratiometric to 5 V), which the $31 limits (`SetStopSwitchLimits`,
//! set only: no getter) compare. The reference bits are inverted (§7.3):
//! the lamp shows the bit as read. `SetOutputs` ($32) writes every output
//! at once and nothing reads TTLOUT1 back.

use super::line::parse_mask;
use crate::protocol::io::{IoKind, IoPlan, IoPoint, ReadRule, VoltScale, input, output};

pub struct Sixpack2Io;

impl IoPlan for Sixpack2Io {
    fn points(&self) -> &'static [IoPoint] {
        POINTS
    }

    fn output_note(&self) -> &'static str {
        "SetOutputs writes both: TTLOUT1's line makes TTLIO1 an input, TTLIO1's sets TTLOUT1 high"
    }

    /// `refs` is a motor list (`all`, `none`, `0,2`).
    fn field(&self, text: &str, name: &str) -> Option<i64> {
        let value = text
            .split_whitespace()
            .filter_map(|word| word.split_once('='))
            .find(|(n, _)| *n == name)
            .map(|(_, v)| v)?;
        if name == "refs" {
            parse_mask(value).ok()
        } else {
            value.parse().ok()
        }
    }
}

const SWITCH: IoKind = IoKind::Switch;
const DIGITAL: IoKind = IoKind::DigitalInput;
/// §7.3: channels 0..5 ratiometric to +5 V (10 bits).
const RATIOMETRIC_5V: IoKind = IoKind::AnalogInput {
    volts: Some(VoltScale {
        zero: 0,
        volts_per_count: 5.0 / 1023.0,
    }),
};
/// §7.3: channel 7, 1 V ≈ 22 counts (saturates at 1023 ≈ 46.5 V).
const SUPPLY: IoKind = IoKind::AnalogInput {
    volts: Some(VoltScale {
        zero: 0,
        volts_per_count: 1.0 / 22.0,
    }),
};

const POINTS: &[IoPoint] = &[
    input(
        "reference",
        SWITCH,
        Some(0),
        "GetInputValues 7",
        ReadRule::FieldBit("refs", 0),
        true,
        "reference input of motor 0, $30 P4 bit 0, inverted (§7.3)",
    ),
    input(
        "A_In (stop switches)",
        RATIOMETRIC_5V,
        Some(0),
        "GetInputValues 0",
        ReadRule::Field("analog"),
        true,
        "motor 0's A_In, where its stop switches are wired; $31 limits (§5.5.2.2, §7.3)",
    ),
    input(
        "reference",
        SWITCH,
        Some(1),
        "GetInputValues 7",
        ReadRule::FieldBit("refs", 1),
        true,
        "reference input of motor 1, $30 P4 bit 1, inverted (§7.3)",
    ),
    input(
        "A_In (stop switches)",
        RATIOMETRIC_5V,
        Some(1),
        "GetInputValues 1",
        ReadRule::Field("analog"),
        true,
        "motor 1's A_In, where its stop switches are wired; $31 limits (§5.5.2.2, §7.3)",
    ),
    input(
        "reference",
        SWITCH,
        Some(2),
        "GetInputValues 7",
        ReadRule::FieldBit("refs", 2),
        true,
        "reference input of motor 2, $30 P4 bit 2, inverted (§7.3)",
    ),
    input(
        "A_In (stop switches)",
        RATIOMETRIC_5V,
        Some(2),
        "GetInputValues 2",
        ReadRule::Field("analog"),
        true,
        "motor 2's A_In, where its stop switches are wired; $31 limits (§5.5.2.2, §7.3)",
    ),
    input(
        "reference",
        SWITCH,
        Some(3),
        "GetInputValues 7",
        ReadRule::FieldBit("refs", 3),
        true,
        "reference input of motor 3, $30 P4 bit 3, inverted (§7.3)",
    ),
    input(
        "A_In (stop switches)",
        RATIOMETRIC_5V,
        Some(3),
        "GetInputValues 3",
        ReadRule::Field("analog"),
        true,
        "motor 3's A_In, where its stop switches are wired; $31 limits (§5.5.2.2, §7.3)",
    ),
    input(
        "reference",
        SWITCH,
        Some(4),
        "GetInputValues 7",
        ReadRule::FieldBit("refs", 4),
        true,
        "reference input of motor 4, $30 P4 bit 4, inverted (§7.3)",
    ),
    input(
        "A_In (stop switches)",
        RATIOMETRIC_5V,
        Some(4),
        "GetInputValues 4",
        ReadRule::Field("analog"),
        true,
        "motor 4's A_In, where its stop switches are wired; $31 limits (§5.5.2.2, §7.3)",
    ),
    input(
        "reference",
        SWITCH,
        Some(5),
        "GetInputValues 7",
        ReadRule::FieldBit("refs", 5),
        true,
        "reference input of motor 5, $30 P4 bit 5, inverted (§7.3)",
    ),
    input(
        "A_In (stop switches)",
        RATIOMETRIC_5V,
        Some(5),
        "GetInputValues 5",
        ReadRule::Field("analog"),
        true,
        "motor 5's A_In, where its stop switches are wired; $31 limits (§5.5.2.2, §7.3)",
    ),
    input(
        "JP1",
        DIGITAL,
        None,
        "GetInputValues 7",
        ReadRule::Field("jp1"),
        true,
        "jumper JP1, $30 P4 bit 6 (§5.2.3)",
    ),
    input(
        "JP2",
        DIGITAL,
        None,
        "GetInputValues 7",
        ReadRule::Field("jp2"),
        true,
        "jumper JP2, $30 P4 bit 7 (§5.2.3)",
    ),
    input(
        "TTLIO1",
        DIGITAL,
        None,
        "GetInputValues 7",
        ReadRule::Field("ttlio1"),
        true,
        "TTLIO1's level, $30 P5 bit 0 (§6.1.4)",
    ),
    input(
        "external",
        IoKind::AnalogInput { volts: None },
        None,
        "GetInputValues 6",
        ReadRule::Field("analog"),
        false,
        "external analog input, pin 7 of the multifunction connector, $30 channel 6 (scale not given)",
    ),
    input(
        "supply",
        SUPPLY,
        None,
        "GetInputValues 7",
        ReadRule::Field("analog"),
        false,
        "supply voltage, $30 channel 7, 22 counts a volt (§7.3)",
    ),
    output(
        "TTLOUT1",
        None,
        ReadRule::Value,
        ["SetOutputs 0 1 0 0", "SetOutputs 1 1 0 0"],
        "TTLOUT1 level (1 = READY), $32 P0; TTLIO1 left an input (§7.3)",
    ),
    output(
        "TTLIO1",
        Some("GetInputValues 7"),
        ReadRule::Field("ttlio1"),
        ["SetOutputs 1 0 0 0", "SetOutputs 1 0 1 0"],
        "TTLIO1 as an output, $32 P1/P2; TTLOUT1 high (§7.3, §6.1.4)",
    ),
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::console::ReplyValue;

    /// `$30`'s answer as the console prints it: the reference inputs are
    /// a motor list.
    #[test]
    fn the_reference_inputs_come_out_of_the_motor_list() {
        let reply = ReplyValue::Text("analog=528 ref=0 refs=0,2 jp1=1 jp2=0 ttlio1=1".into());
        let state = |name: &str, axis: Option<usize>| {
            let point = POINTS
                .iter()
                .find(|p| p.name == name && p.axis == axis)
                .expect("a point");
            Sixpack2Io.state(point, &reply)
        };
        assert_eq!(state("reference", Some(0)), Some(1));
        assert_eq!(state("reference", Some(1)), Some(0));
        assert_eq!(state("reference", Some(2)), Some(1));
        assert_eq!(state("JP1", None), Some(1));
        assert_eq!(state("TTLIO1", None), Some(1));
        let all = ReplyValue::Text("analog=0 ref=1 refs=all jp1=0 jp2=0 ttlio1=0".into());
        let reference_5 = POINTS
            .iter()
            .find(|p| p.name == "reference" && p.axis == Some(5))
            .expect("motor 5's");
        assert_eq!(Sixpack2Io.state(reference_5, &all), Some(1));
    }
}
