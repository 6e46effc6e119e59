//! What the console says before a line is sent (digest D9): warnings that
//! do not stop it (a microstep rate over 200 kHz, amax over 64·vstart,
//! vmin over vstart, vrefmax outside [vstart, vmax], vstart over the
//! firmware's limit, `$10` to an odd motor…), and the commands that need
//! the user's confirmation (`$24`, `$15` with AutonullCmd, `$22`, `$CC`,
//! `$40`, `$42`, the service commands).
//!
//! Some checks span commands (amax against the vstart written earlier).
//! The SIXpack 2 cannot be asked for any setting, so they use what the
//! console knows ([`Known`]) and, where it knows nothing, the factory
//! value (§6.8), saying so.

use super::catalog::{CURRENT_STEPS, CommandSpec, Confirm, FieldKind, MOTORS, flag_by_name};
use super::command::Command;
use super::frame::Request;

/// The step clock (§6.3.1: f_clk = 20 MHz).
const CLOCK_HZ: f64 = 20e6;

/// The highest microstep frequency allowed (§6.3.1 note).
const MAX_MICROSTEP_HZ: f64 = 200e3;

/// The highest step frequency of vmin at div 3 (§7.1 `$13`).
const MAX_VMIN_HZ: f64 = 250.0;

/// The least current step for proper microstepping, 19 % (§6.2.1.2,
/// index 5: digest E11).
const MIN_MICROSTEP_PERCENT: u8 = 19;

/// Factory values (§6.8) used where the console knows no written one.
mod factory {
    pub const CLKDIV: i64 = 5;
    pub const DIV: i64 = 2;
    pub const VSTART: i64 = 5;
    pub const VMAX: i64 = 511;
    pub const AMAX: i64 = 128;
}

/// Settings of one motor the console knows were written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MotorKnown {
    pub div: Option<i64>,
    pub vstart: Option<i64>,
    pub vmax: Option<i64>,
    pub amax: Option<i64>,
}

/// What the console knows of settings written before (none unless a
/// session keeps them; the unit cannot be asked).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Known {
    pub clkdiv: Option<i64>,
    pub motors: [MotorKnown; MOTORS as usize],
}

/// A setting's value for a check: as known, or the factory value and a
/// note that it is assumed.
struct Setting {
    value: i64,
    assumed: bool,
}

impl Setting {
    fn of(known: Option<i64>, factory: i64) -> Setting {
        Setting {
            value: known.unwrap_or(factory),
            assumed: known.is_none(),
        }
    }

    /// `vstart 5 (factory value, not known to be changed)`.
    fn show(&self, name: &str) -> String {
        if self.assumed {
            format!(
                "{name} {} (factory value, not known to be changed)",
                self.value
            )
        } else {
            format!("{name} {}", self.value)
        }
    }
}

impl Known {
    fn motor(&self, motor: Option<u8>) -> MotorKnown {
        motor
            .and_then(|m| self.motors.get(usize::from(m)).copied())
            .unwrap_or_default()
    }
}

/// f_µstep = 20 MHz/(clkdiv+1)·|v|/2^(14+div) (§6.3.1).
pub fn microstep_hz(clkdiv: i64, div: i64, velocity: i64) -> f64 {
    let shift = 14 + div.clamp(0, 3);
    CLOCK_HZ / (clkdiv.max(0) as f64 + 1.0) * velocity.unsigned_abs() as f64
        / f64::from(1u32 << shift)
}

fn khz(hz: f64) -> String {
    format!("{:.0} kHz", hz / 1000.0)
}

/// Warnings about a request (none stops it).
pub fn warnings(request: &Request, known: &Known) -> Vec<String> {
    let command = match Command::from_request(request) {
        Ok(Some(command)) => command,
        Ok(None) => {
            return vec![format!(
                "${:02X} is not in the instruction set (§7): its layout and any answer are \
                 unknown; it is sent as written and no answer is waited for",
                request.command
            )];
        }
        // Refused before it gets here; nothing to add.
        Err(_) => return Vec::new(),
    };
    let mut found = Vec::new();
    let stray = Command::stray_bytes(command.spec, &request.params);
    if !stray.is_empty() {
        found.push(format!(
            "{} {} unused by {} and should be $00 (§6.2)",
            stray.join(", "),
            if stray.len() == 1 { "is" } else { "are" },
            command.spec.mnemonic
        ));
    }
    let value = |name: &str| command.value(name).unwrap_or(0);
    let motor = command.motor();
    let mine = known.motor(motor);
    let clkdiv = Setting::of(known.clkdiv, factory::CLKDIV);
    let over_limit = |what: String, hz: f64, found: &mut Vec<String>| {
        if hz > MAX_MICROSTEP_HZ {
            found.push(format!(
                "{what} gives {}, over the 200 kHz microstep limit (§6.3.1)",
                khz(hz)
            ));
        }
    };
    match command.spec.code {
        0x10 if motor.is_some_and(|m| m % 2 == 1) => {
            let m = motor.unwrap_or(1);
            found.push(format!(
                "the peak current of motors {} and {m} is set on motor {} only: this frame for \
                 motor {m} is ignored (§7.1)",
                m - 1,
                m - 1
            ));
        }
        0x11 => {
            for name in ["I1", "I2", "I3"] {
                let percent = CURRENT_STEPS
                    .iter()
                    .find(|s| i64::from(s.index) == value(name))
                    .map_or(0, |s| s.percent);
                if percent < MIN_MICROSTEP_PERCENT {
                    found.push(format!(
                        "{name} {percent}% is below 19 %, the least current for proper \
                         microstepping (§6.2.1.2)"
                    ));
                }
            }
            if value("T0") % 2 == 1 {
                found.push("T0 is odd: firmware before v1.40 needs even values (§7.1)".into());
            }
        }
        0x12 => {
            for m in 0..MOTORS {
                let div = Setting::of(known.motors[usize::from(m)].div, factory::DIV);
                let vmax = Setting::of(known.motors[usize::from(m)].vmax, factory::VMAX);
                let hz = microstep_hz(value("clkdiv"), div.value, vmax.value);
                over_limit(
                    format!("{} at {} on motor {m}", vmax.show("vmax"), div.show("div")),
                    hz,
                    &mut found,
                );
            }
        }
        0x13 => {
            let (vmin, vstart, div) = (value("vmin"), value("vstart"), value("div"));
            if vmin > vstart {
                found.push(format!(
                    "vmin {vmin} is above vstart {vstart} (§7.1: vmin <= vstart)"
                ));
            }
            let limit = (512 >> (3 - div.clamp(0, 3))) - 1;
            if vstart >= limit {
                found.push(format!(
                    "vstart {vstart} at div {div} is over the firmware's limit: vstart < {limit} \
                     (§7.1)"
                ));
            }
            let vmin_hz = microstep_hz(clkdiv.value, 3, vmin);
            if vmin_hz > MAX_VMIN_HZ {
                found.push(format!(
                    "vmin {vmin} at div 3 steps at {vmin_hz:.0} Hz with {}: over the 250 Hz \
                     §7.1 allows",
                    clkdiv.show("clkdiv")
                ));
            }
            over_limit(
                format!(
                    "vstart {vstart} at div {div} with {}",
                    clkdiv.show("clkdiv")
                ),
                microstep_hz(clkdiv.value, div, vstart),
                &mut found,
            );
            let amax = Setting::of(mine.amax, factory::AMAX);
            if amax.value > 64 * vstart {
                found.push(format!(
                    "{} is over 64·vstart = {} (§7.1: 0 < amax <= 64·vstart)",
                    amax.show("amax"),
                    64 * vstart
                ));
            }
        }
        0x14 => {
            let (amax, vmax) = (value("amax"), value("vmax"));
            let vstart = Setting::of(mine.vstart, factory::VSTART);
            if amax > 64 * vstart.value {
                found.push(format!(
                    "amax {amax} is over 64·vstart = {} with {} (§7.1: 0 < amax <= 64·vstart)",
                    64 * vstart.value,
                    vstart.show("vstart")
                ));
            }
            let div = Setting::of(mine.div, factory::DIV);
            over_limit(
                format!(
                    "vmax {vmax} at {} with {}",
                    div.show("div"),
                    clkdiv.show("clkdiv")
                ),
                microstep_hz(clkdiv.value, div.value, vmax),
                &mut found,
            );
        }
        0x15 => {
            let flags = value("flags");
            let has = |name: &str| flag_by_name(name).is_some_and(|f| flags & f.mask() != 0);
            if has("MechRef") && has("Rotary") {
                found.push("MechRef is for linear axes only (§5.5.1), and Rotary is set".into());
            }
        }
        0x16 => {
            let vrefmax = value("vrefmax");
            let vstart = Setting::of(mine.vstart, factory::VSTART);
            let vmax = Setting::of(mine.vmax, factory::VMAX);
            if vrefmax < vstart.value || vrefmax > vmax.value {
                found.push(format!(
                    "vrefmax {vrefmax} is outside [vstart, vmax] with {} and {} (§7.1: 511 >= \
                     vmax >= vrefmax >= vstart)",
                    vstart.show("vstart"),
                    vmax.show("vmax")
                ));
            }
            let mask = value("debounce");
            if mask & (mask + 1) != 0 || mask == 0 {
                found.push(format!(
                    "debounce ${mask:04X} is not a run of low one-bits ($0001 = 0 ms, $0003 = \
                     2 ms … $FFFF = 30 ms, §7.1)"
                ));
            }
        }
        0x28 if value("wait") != 0 => {
            found.push(format!(
                "the answer comes only once motors {} are inactive: it is waited for while other \
                 requests go on; on RS-485 with several units keep the bus idle until it comes \
                 (§7.2)",
                super::command::format_mask(value("wait"))
            ));
        }
        0x25 => {
            let velocity = value("velocity");
            let div = Setting::of(mine.div, factory::DIV);
            over_limit(
                format!(
                    "velocity {velocity} at {} with {}",
                    div.show("div"),
                    clkdiv.show("clkdiv")
                ),
                microstep_hz(clkdiv.value, div.value, velocity),
                &mut found,
            );
        }
        _ => {}
    }
    found
}

/// Why a request needs the user's confirmation before it is sent, if it
/// does (digest D9).
pub fn confirmation(request: &Request) -> Option<String> {
    let Ok(Some(command)) = Command::from_request(request) else {
        return None;
    };
    match command.spec.confirm {
        Confirm::Never => None,
        Confirm::Always(why) => Some(why.to_string()),
        Confirm::WhenFlag { flag, why } => {
            let bit = flag_by_name(flag)?;
            let word = flag_word(&command)?;
            (word & bit.mask() != 0).then(|| why.to_string())
        }
    }
}

/// The value of the command's flag word, if it has one.
fn flag_word(command: &Command) -> Option<i64> {
    command
        .spec
        .fields
        .iter()
        .zip(&command.values)
        .find(|(f, _)| matches!(f.kind, FieldKind::Flags(_)))
        .map(|(_, v)| *v)
}

/// Every command that may need confirmation, for help.
pub fn confirmed_commands() -> impl Iterator<Item = &'static CommandSpec> {
    super::catalog::COMMANDS
        .iter()
        .filter(|c| c.confirm != Confirm::Never)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::sixpack2::line::parse_line;

    fn warn(line: &str) -> Vec<String> {
        warn_known(line, &Known::default())
    }

    fn warn_known(line: &str, known: &Known) -> Vec<String> {
        let parsed = parse_line(line, None).unwrap_or_else(|e| panic!("{line}: {e}"));
        warnings(&parsed.request, known)
    }

    fn confirm(line: &str) -> Option<String> {
        let parsed = parse_line(line, None).unwrap_or_else(|e| panic!("{line}: {e}"));
        confirmation(&parsed.request)
    }

    #[test]
    fn the_step_frequency_law_of_6_3_1() {
        // Digest D5.1's table.
        assert_eq!(format!("{:.2}", microstep_hz(5, 2, 1)), "50.86");
        assert_eq!(format!("{:.0}", microstep_hz(5, 2, 511)), "25991");
        assert_eq!(format!("{:.1}", microstep_hz(5, 3, 4)), "101.7");
        assert_eq!(format!("{:.0}", microstep_hz(0, 0, 511)), "623779");
        assert_eq!(format!("{:.2}", microstep_hz(31, 3, 1)), "4.77");
    }

    #[test]
    fn sound_settings_say_nothing() {
        for line in [
            "StartRamp 0 10000",
            "SetVMinVStart 2 5 100 2",
            "SetAMaxVMax 3 200 400",
            "SetRefSearchParameters 0 100 $0FFF 0",
            "SetCurrentControl 0 0% 50% 75% 100% 500",
            "SetPeakCurrent 2 200",
            "SetClockDivider 5",
            "ConstantRotation 0 -511",
            "SetMotorParameters 0 10000 NullLeft,MechRef",
        ] {
            assert_eq!(warn(line), Vec::<String>::new(), "{line}");
        }
    }

    #[test]
    fn d9_warnings() {
        let w = warn("SetVMinVStart 0 20 10 2");
        assert!(
            w.iter().any(|m| m.contains("vmin 20 is above vstart 10")),
            "{w:?}"
        );
        assert!(w.iter().any(|m| m.contains("over the 250 Hz")), "{w:?}");
        let w = warn("SetVMinVStart 0 4 255 2");
        assert!(w.iter().any(|m| m.contains("vstart < 255")), "{w:?}");
        assert!(
            warn("SetVMinVStart 0 4 254 2").is_empty(),
            "E7: 254 is safe"
        );
        let w = warn("SetVMinVStart 0 4 1 2");
        assert!(
            w.iter().any(|m| m.contains("amax 128 (factory value")),
            "{w:?}"
        );
        // §5.6.2.1's misprinted bytes: vmin 10 at clkdiv 5 is 254 Hz.
        let w = warn("SendToPack($00, $13, $02, $0A, $00, $0A, $00, $02, $00)");
        assert!(w.iter().any(|m| m.contains("254 Hz")), "{w:?}");

        let w = warn("SetAMaxVMax 0 500 400");
        assert_eq!(
            w,
            [
                "amax 500 is over 64·vstart = 320 with vstart 5 (factory value, not known to be \
              changed) (§7.1: 0 < amax <= 64·vstart)"
            ]
        );
        let mut known = Known::default();
        known.motors[0].vstart = Some(8);
        assert!(warn_known("SetAMaxVMax 0 500 400", &known).is_empty());
        known.clkdiv = Some(0);
        known.motors[0].div = Some(0);
        let w = warn_known("SetAMaxVMax 0 500 400", &known);
        assert!(w[0].contains("488 kHz, over the 200 kHz"), "{w:?}");
        let w = warn_known("ConstantRotation 0 200", &known);
        assert!(
            w[0].starts_with("velocity 200 at div 0 with clkdiv 0 gives 244 kHz"),
            "{w:?}"
        );
        let w = warn("SetClockDivider 0");
        assert!(w.is_empty(), "div 2 (factory) stays under 200 kHz: {w:?}");
        let mut at_div_0 = Known::default();
        at_div_0.motors[4].div = Some(0);
        let w = warn_known("SetClockDivider 1", &at_div_0);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("on motor 4"), "{w:?}");

        let w = warn("SetRefSearchParameters 0 3 $0FFF 0");
        assert!(
            w[0].starts_with("vrefmax 3 is outside [vstart, vmax]"),
            "{w:?}"
        );
        let w = warn("SetRefSearchParameters 0 100 $0F0F 0");
        assert!(w[0].contains("$0F0F is not a run"), "{w:?}");

        let w = warn("SetPeakCurrent 3 100");
        assert_eq!(
            w,
            [
                "the peak current of motors 2 and 3 is set on motor 2 only: this frame for motor 3 \
              is ignored (§7.1)"
            ]
        );
        let w = warn("SetCurrentControl 0 0% 13% 75% 100% 501");
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(w[0].starts_with("I1 13% is below 19 %"));
        assert!(w[1].starts_with("T0 is odd"));
        assert!(warn("GetAllActivities").is_empty());
        let w = warn("GetAllActivities 0 1,2");
        assert!(
            w[0].starts_with("the answer comes only once motors 1,2 are inactive"),
            "{w:?}"
        );
        let w = warn("SetMotorParameters 0 6400 Rotary,MechRef");
        assert!(w[0].contains("linear axes only"), "{w:?}");
    }

    #[test]
    fn frames_beyond_the_manual_are_flagged() {
        let w = warn("SendToPack($00, $1A, $00, $20, $00, $00, $00, $00, $00)");
        assert!(
            w[0].starts_with("$1A is not in the instruction set"),
            "{w:?}"
        );
        let w = warn("raw 00 23 00 10 27 00 00 01 02");
        assert_eq!(
            w,
            ["P5, P6 are unused by StartRamp and should be $00 (§6.2)"]
        );
    }

    #[test]
    fn d9_confirmations() {
        for line in [
            "StartPIControl 0 100",
            "StartReferenceSearch 0",
            "HardwareReset",
            "SetBaudRate 65 3",
            "SetUnitAddress 3",
            "FlashChecksum",
            "EepromRead 0 0 0 0",
            "SetMotorParameters 0 10000 AutonullCmd",
            "SendToPack($00, $22, $00, $00, $00, $00, $00, $00, $00)",
        ] {
            assert!(confirm(line).is_some(), "{line}");
        }
        for line in [
            "StartRamp 0 1",
            "SetMotorParameters 0 10000 NullLeft,MechRef",
            "SetPacketTimeout 100",
            "GetUnitInformation",
            "SendToPack($00, $1A, $00, $20, $00, $00, $00, $00, $00)",
        ] {
            assert_eq!(confirm(line), None, "{line}");
        }
        assert!(
            confirm("SetMotorParameters 0 1 AutonullCmd")
                .is_some_and(|w| w.contains("starts a reference search"))
        );
        let listed: Vec<u8> = confirmed_commands().map(|c| c.code).collect();
        assert_eq!(
            listed,
            [
                0x15, 0x22, 0x24, 0x40, 0x42, 0xCC, 0xF2, 0xF3, 0xF4, 0xF5, 0xF6, 0xF7
            ]
        );
    }
}
