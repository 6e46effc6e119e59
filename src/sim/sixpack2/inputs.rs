//! The SIXpack 2 simulator's inputs and choices as settings typed from
//! outside (`--input REF0=1`, a line on `axterm sim sixpack2`'s standard
//! input, `:sim-input REF0=1`): the table of what there is. Applying one is
//! [`super::Sixpack2::drive_input`].
//!
//! Three kinds of row:
//! - the wiring the manual names: the reference switch of each motor
//!   (`REF0..REF5`, Ref_In on the motor connector, §5.5.2.1), its stop
//!   switches on A_In (`STOPL0`, `STOPR0`: §5.5.2.2) or A_In itself
//!   (`AIN0..AIN5`), the external analog input (`AIN6`, channel 6 of $30),
//!   the supply (channel 7), the baud jumpers `JP1`/`JP2` (§5.2.3), TTLIO1
//!   as an input (§6.1.4) and the driver-enable jumper (§5.2.6). Switches
//!   are *actuated* (pressed) or not; `stage` hands them back to the
//!   carriage;
//! - the machine behind each motor (see [`super::stage`]): where the
//!   carriage is, the travel between its stops, the switch's place, width
//!   and type;
//! - the simulator's choices where the manual is silent (digest D10.3; see
//!   [`super::choices`]).
//!
//! Motors are numbered 0..5 as in the protocol ("Motor 1..6" in the
//! manual's prose).

use crate::sim::inputs::{self, InputRow, Names, Setting, SettingError, Values};

/// Which input or choice a setting drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    Reference,
    LeftStop,
    RightStop,
    Analog,
    External,
    Supply,
    Jumper,
    Ttlio1,
    DriverEnable,
    Carriage,
    Travel,
    Turn,
    RefAt,
    RefWidth,
    Opener,
    Limits,
    Addr9,
    Fill,
    Second28,
    Timeout,
    Latency,
    Clamp,
    SlowerDeceleration,
    PiTimes64,
    PiHolds,
    RotationHolds,
    RampAfterRotation,
    SlowSearch,
    MechAtVrefmax,
    OffsetMirrored,
    RefLevels,
    JumperOpen,
    LimitsNeedStopNull,
    KeepAddress,
    ResetKey,
    StrayZero,
    Firmware,
    Serial,
    Temperature,
}

const STAGE: Values = Values::OnOffOr {
    word: "stage",
    meaning: "where the simulated carriage is sets it",
};

const fn per_motor(stem: &'static str) -> Names {
    Names::Numbered {
        stem,
        first: 0,
        last: 5,
    }
}

const fn one(name: &'static [&'static str]) -> Names {
    Names::Listed(name)
}

/// The largest carriage position or distance a setting takes, in µsteps.
pub const MOST_MICROSTEPS: u32 = 2_000_000_000;

/// Every input and choice a setting can drive.
pub const INPUTS: &[InputRow<Input>] = &[
    InputRow {
        input: Input::Reference,
        names: per_motor("REF"),
        values: STAGE,
        what: "the motor's reference switch actuated (Ref_In, §5.5.2.1; the pin's level follows its type, OPENERn)",
    },
    InputRow {
        input: Input::LeftStop,
        names: per_motor("STOPL"),
        values: STAGE,
        what: "the left stop switch on A_In actuated (§5.5.2.2): A_In reads 0",
    },
    InputRow {
        input: Input::RightStop,
        names: per_motor("STOPR"),
        values: STAGE,
        what: "the right stop switch on A_In actuated: A_In reads 1023 (free: 512)",
    },
    InputRow {
        input: Input::Analog,
        names: per_motor("AIN"),
        values: Values::NumberOr {
            max: 1023,
            unit: "counts",
            word: "stage",
            meaning: "from the stop switches",
        },
        what: "A_In of the motor connector ($30 channels 0..5, the $31 limits)",
    },
    InputRow {
        input: Input::External,
        names: one(&["AIN6"]),
        values: Values::Number {
            max: 1023,
            unit: "counts",
        },
        what: "the external analog input, pin 7 of the multifunction connector ($30 channel 6)",
    },
    InputRow {
        input: Input::Supply,
        names: one(&["SUPPLY"]),
        values: Values::Number { max: 58, unit: "V" },
        what: "the supply voltage ($30 channel 7: 22 counts a volt, at most 1023)",
    },
    InputRow {
        input: Input::Jumper,
        names: one(&["JP1", "JP2"]),
        values: Values::OnOff,
        what: "baud jumper fitted (Table 5.1; read at reset, shown by $30 at once)",
    },
    InputRow {
        input: Input::Ttlio1,
        names: one(&["TTLIO1"]),
        values: Values::OnOff,
        what: "the level on TTLIO1 while $32 makes it an input ($30 P5)",
    },
    InputRow {
        input: Input::DriverEnable,
        names: one(&["ENABLE"]),
        values: Values::OnOff,
        what: "the driver-enable jumper (§5.2.6): open (0), no motor turns while the counters run on",
    },
    InputRow {
        input: Input::Carriage,
        names: per_motor("CARRIAGE"),
        values: Values::Number {
            max: MOST_MICROSTEPS,
            unit: "µsteps from the left stop",
        },
        what: "move the carriage there by hand (the counter does not see it)",
    },
    InputRow {
        input: Input::Travel,
        names: per_motor("TRAVEL"),
        values: Values::Number {
            max: MOST_MICROSTEPS,
            unit: "µsteps",
        },
        what: "distance between the mechanical stops (0: none); a motor driving into a stop loses steps",
    },
    InputRow {
        input: Input::Turn,
        names: per_motor("TURN"),
        values: Values::Number {
            max: MOST_MICROSTEPS,
            unit: "µsteps",
        },
        what: "a rotary machine: its switch comes round every so many µsteps, no stops (0: linear)",
    },
    InputRow {
        input: Input::RefAt,
        names: per_motor("REFAT"),
        values: Values::Number {
            max: MOST_MICROSTEPS,
            unit: "µsteps from the left stop",
        },
        what: "where the reference switch's actuated zone begins",
    },
    InputRow {
        input: Input::RefWidth,
        names: per_motor("REFWIDTH"),
        values: Values::Number {
            max: MOST_MICROSTEPS,
            unit: "µsteps",
        },
        what: "how long the reference switch stays actuated (0: no switch)",
    },
    InputRow {
        input: Input::Opener,
        names: per_motor("OPENER"),
        values: Values::OnOff,
        what: "the reference switch is an opener (normally closed, §5.5.2.1: pin high while actuated; \
               needs NullPositive) rather than a closer",
    },
    InputRow {
        input: Input::Limits,
        names: one(&["LIMITS"]),
        values: inputs::LIMITS_WIRING,
        what: "every motor's A_In end switches wired right, or swapped: the switch at the left stop \
               pulls A_In up (1023, stopped by MaxRight), the right one down (0, MinLeft) (§5.5.2.2, $31)",
    },
    InputRow {
        input: Input::Addr9,
        names: one(&["ADDR9"]),
        values: Values::OnOff,
        what: "choice: replies carry the response address before the command byte (9 bytes) \
               rather than not (8 bytes, the manual's reading, D1.4)",
    },
    InputRow {
        input: Input::Fill,
        names: one(&["FILL"]),
        values: Values::Number {
            max: 255,
            unit: "byte",
        },
        what: "choice: the value of reply bytes the manual gives no meaning",
    },
    InputRow {
        input: Input::Second28,
        names: one(&["SECOND28"]),
        values: Values::Number {
            max: 2,
            unit: "rule",
        },
        what: "choice: a $28 while another waits: 0 each is answered when its own motors are idle, \
               1 it replaces the waiting one, 2 it is dropped",
    },
    InputRow {
        input: Input::Timeout,
        names: one(&["TIMEOUT"]),
        values: Values::Number {
            max: 65535,
            unit: "2 ms units",
        },
        what: "choice: the packet timeout now and after a reset (0: none; $41 sets it from the host)",
    },
    InputRow {
        input: Input::Latency,
        names: one(&["LATENCY"]),
        values: Values::Number {
            max: 1000,
            unit: "ms",
        },
        what: "choice: from a frame's last byte to its command acting",
    },
    InputRow {
        input: Input::Clamp,
        names: one(&["CLAMP"]),
        values: Values::OnOff,
        what: "choice: values outside their §7 range are clamped (1) or drop the frame (0)",
    },
    InputRow {
        input: Input::SlowerDeceleration,
        names: one(&["SLOWDECEL"]),
        values: Values::Number {
            max: 999,
            unit: "per mille",
        },
        what: "choice: ramps decelerate this much more slowly than they accelerate (§6.3.1.1)",
    },
    InputRow {
        input: Input::PiTimes64,
        names: one(&["PIX64"]),
        values: Values::OnOff,
        what: "choice: the PI P term is 64·Δ/propdiv (§7.1, 1) or Δ/propdiv (the defaults' comment, 0)",
    },
    InputRow {
        input: Input::PiHolds,
        names: one(&["PIHOLD"]),
        values: Values::OnOff,
        what: "choice: PI control stays action 10 at its target (1) or ends there (0)",
    },
    InputRow {
        input: Input::RotationHolds,
        names: one(&["ROTHOLD"]),
        values: Values::OnOff,
        what: "choice: a rotation at velocity 0 stays action 15 (1) or ends (0)",
    },
    InputRow {
        input: Input::RampAfterRotation,
        names: one(&["ROTRAMP"]),
        values: Values::OnOff,
        what: "choice: $23 during a rotation stops it and drives to the target (§6.6.3, 1) or only stops it (§7.2, 0)",
    },
    InputRow {
        input: Input::SlowSearch,
        names: one(&["SLOWREF"]),
        values: Values::Number {
            max: 511,
            unit: "velocity at div 3",
        },
        what: "choice: the search velocity without FastRef (§6.4.8: 1; 0: vmin)",
    },
    InputRow {
        input: Input::MechAtVrefmax,
        names: one(&["MECHFAST"]),
        values: Values::OnOff,
        what: "choice: the mechanical reference drives at vrefmax (1) or as a ramp (0)",
    },
    InputRow {
        input: Input::OffsetMirrored,
        names: one(&["OFFSETMIRROR"]),
        values: Values::OnOff,
        what: "choice: a positive nulloffset moves zero into the switch on either side (1) \
               or makes the switch point +nulloffset (0)",
    },
    InputRow {
        input: Input::RefLevels,
        names: one(&["REFLEVEL"]),
        values: Values::OnOff,
        what: "choice: $30 shows reference inputs as levels (1) or inverted (0, §7.3)",
    },
    InputRow {
        input: Input::JumperOpen,
        names: one(&["JPOPEN"]),
        values: Values::OnOff,
        what: "choice: $30 jumper bits are 1 for an open jumper (1) or a fitted one (0)",
    },
    InputRow {
        input: Input::LimitsNeedStopNull,
        names: one(&["LIMITSTOPNULL"]),
        values: Values::OnOff,
        what: "choice: the $31 limits act only with StopNull set (1) or always (0)",
    },
    InputRow {
        input: Input::KeepAddress,
        names: one(&["KEEPADDR"]),
        values: Values::OnOff,
        what: "choice: a $42 address survives $CC (1) or the rotary switches are read again (0)",
    },
    InputRow {
        input: Input::ResetKey,
        names: one(&["RESETKEY"]),
        values: Values::NumberOr {
            max: 255,
            unit: "P0",
            word: "any",
            meaning: "every $CC resets",
        },
        what: "choice: the $CC P0 value that resets",
    },
    InputRow {
        input: Input::StrayZero,
        names: one(&["STRAY00"]),
        values: Values::OnOff,
        what: "choice: $CC ends with one $00 byte on the line (§7.4: \"usually\")",
    },
    InputRow {
        input: Input::Firmware,
        names: one(&["FIRMWARE"]),
        values: Values::Number {
            max: 255,
            unit: "revision",
        },
        what: "choice: the $43 firmware revision (148 = V1.4.8)",
    },
    InputRow {
        input: Input::Serial,
        names: one(&["SERIAL"]),
        values: Values::Number {
            max: 65535,
            unit: "number",
        },
        what: "choice: the $43 serial number",
    },
    InputRow {
        input: Input::Temperature,
        names: one(&["TEMP"]),
        values: Values::Number {
            max: 127,
            unit: "°C",
        },
        what: "the $43 board temperature",
    },
];

/// Read a setting (`REF0=1`) against [`INPUTS`].
pub fn parse(text: &str) -> Result<Setting<Input>, SettingError> {
    inputs::parse(INPUTS, text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::inputs::Level;

    fn read(text: &str) -> (Input, u8, Level) {
        let s = parse(text).unwrap_or_else(|e| panic!("{text}: {e}"));
        (s.row.input, s.which, s.level)
    }

    #[test]
    fn the_wiring_is_read_by_motor_number() {
        assert_eq!(read("REF0=1"), (Input::Reference, 0, Level::On));
        assert_eq!(read("ref5=stage"), (Input::Reference, 5, Level::Released));
        assert_eq!(read("STOPR2=0"), (Input::RightStop, 2, Level::Off));
        assert_eq!(read("AIN3=700"), (Input::Analog, 3, Level::Number(700)));
        assert_eq!(read("AIN6=700"), (Input::External, 0, Level::Number(700)));
        assert_eq!(read("JP2=1"), (Input::Jumper, 1, Level::On));
        assert_eq!(read("ADDR9=1"), (Input::Addr9, 0, Level::On));
        assert_eq!(read("RESETKEY=any"), (Input::ResetKey, 0, Level::Released));
    }

    #[test]
    fn motor_six_and_values_outside_are_refused() {
        for text in ["REF6=1", "CARRIAGE6=0", "AIN7=1"] {
            let e = parse(text).expect_err(text).to_string();
            assert!(e.starts_with("there is no input"), "{e}");
        }
        let e = parse("AIN0=1024").expect_err("above 1023").to_string();
        assert_eq!(
            e,
            "AIN0 takes a whole number of counts, 0..1023, or stage (from the stop switches), not `1024`"
        );
        assert!(parse("SECOND28=3").is_err());
    }
}
