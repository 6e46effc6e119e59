//! The TMCM-1110 simulator's inputs as settings typed from outside
//! (`--input IN3=1`, a line on `axterm sim tmcm1110`'s standard input,
//! `:sim-input IN3=1`): the table of what there is, and the reading of a
//! setting against it. Applying one is [`super::Tmcm1110::drive_input`].
//!
//! The digital inputs are GIO bank 0's ports 1..6 (§3.6.15), typed as
//! `IN1..IN6` after the port number a program reads (`GIO 3, 0` is `IN3`)
//! or by the line's name in the manual's table (`PWMD2`); `open` leaves a
//! line unconnected, to its pull-up (§3.6.14). AIN0 is the ADC value,
//! 0..65535: the manual's "16 bit result in the range of 0...65535"
//! (§3.6.15, bank 1), not a 12-bit 0..4095. LOAD is the mechanical load on
//! the simulated motor, 0..100 % of the torque it has at the AP6 run
//! current: the StallGuard2 reading AP206 falls with it and reaches 0 at
//! 100 % (§1.1, §7.2; the law is in [`super::motion::stallguard`]).

use super::io::IO_LINES;
use crate::sim::inputs::{self, InputRow, Names, Setting, SettingError, Values};

/// A digital input's values: on, off, or open to its pull-up (§3.6.14).
const PULLED_UP: Values = Values::OnOffOr {
    word: "open",
    meaning: "nothing connected",
};

/// Which input a setting drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// GIO bank-0 port n.
    Port,
    /// The same lines by name (PWMD0 …).
    Line,
    /// AIN0's ADC value.
    Analog,
    /// The motor's load, percent of its torque at the AP6 current.
    Load,
    /// How the simulated stage's end switches are wired to the left and right limit inputs.
    Limits,
}

/// Every input a setting can drive.
pub const INPUTS: &[InputRow<Input>] = &[
    InputRow {
        input: Input::Port,
        names: Names::Numbered {
            stem: "IN",
            first: 1,
            last: 6,
        },
        values: PULLED_UP,
        what: "digital input read by GIO n, 0 (§3.6.15); open: its pull-up decides (§3.6.14)",
    },
    InputRow {
        input: Input::Line,
        names: Names::Listed(&["PWMD0", "PWMD1", "PWMD2", "PWMU0", "PWMU1", "PWMU2"]),
        values: PULLED_UP,
        what: "the same inputs by their line names (PWMD0 = IN1 … PWMU2 = IN6, §3.6.15)",
    },
    InputRow {
        input: Input::Analog,
        names: Names::Listed(&["AIN0"]),
        values: Values::Number {
            max: 65535,
            unit: "ADC counts",
        },
        what: "analog input AIN0, GIO 0, 1 (§3.6.15); GIO 0, 0 reads 1 from 32768",
    },
    InputRow {
        input: Input::Load,
        names: Names::Listed(&["LOAD"]),
        values: Values::Number {
            max: 100,
            unit: "% of the torque at the AP6 current",
        },
        what: "the motor's load: StallGuard2 (AP206) falls linearly with it, 0 at 100 % (a stall; §1.1, §7.2)",
    },
    InputRow {
        input: Input::Limits,
        names: Names::Listed(&["LIMITS"]),
        values: inputs::LIMITS_WIRING,
        what: "the stage's end switches wired right, or swapped: the + end closes the left limit input (AP11), \
               the − end the right one (AP10); each still stops only its own direction (AP12/AP13)",
    },
];

/// Read a setting (`IN3=open`) against [`INPUTS`].
pub fn parse(text: &str) -> Result<Setting<Input>, SettingError> {
    inputs::parse(INPUTS, text)
}

/// The GIO bank-0 port a digital setting drives.
pub fn port_of(setting: &Setting<Input>) -> Option<u8> {
    match setting.row.input {
        Input::Port => Some(setting.which),
        Input::Line => {
            let name = setting.name();
            IO_LINES
                .iter()
                .find(|line| line.name == name)
                .and_then(|line| line.input_port)
        }
        Input::Analog | Input::Load | Input::Limits => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::SimulatedController;
    use crate::sim::inputs::Level;
    use crate::sim::tmcm1110::{SimConfig, Tmcm1110};

    #[test]
    fn ports_and_line_names_reach_the_same_gio_port() {
        let cases = [
            ("IN1=1", 1, Level::On),
            ("PWMD0=1", 1, Level::On),
            ("in3=open", 3, Level::Released),
            ("PWMD2=0", 3, Level::Off),
            ("PWMU0=1", 4, Level::On),
            ("pwmu2=OPEN", 6, Level::Released),
            ("IN6=0", 6, Level::Off),
        ];
        for (text, port, level) in cases {
            let setting = parse(text).unwrap_or_else(|e| panic!("{text}: {e}"));
            assert_eq!(
                (port_of(&setting), setting.level),
                (Some(port), level),
                "{text}"
            );
        }
        let ain = parse("AIN0=65535").expect("the 16-bit top");
        assert_eq!((port_of(&ain), ain.level), (None, Level::Number(65535)));
    }

    #[test]
    fn what_the_module_has_not_is_refused() {
        let e = parse("IN0=1").expect_err("port 0 is AIN0").to_string();
        assert!(e.starts_with("there is no input `IN0`"), "{e}");
        assert!(
            e.ends_with(
                "IN1..IN6=0|1|open, PWMD0|PWMD1|PWMD2|PWMU0|PWMU1|PWMU2=0|1|open, \
                 AIN0=<ADC counts 0..65535>, LOAD=<% of the torque at the AP6 current 0..100>, \
                 LIMITS=right|swapped"
            ),
            "{e}"
        );
        assert!(parse("IN7=1").is_err());
        assert!(parse("OpenDrain1=1").is_err(), "an output");
        let e = parse("AIN0=65536").expect_err("17 bits").to_string();
        assert_eq!(
            e,
            "AIN0 takes a whole number of ADC counts, 0..65535, not `65536`"
        );
        assert_eq!(
            parse("IN2=high").expect_err("a word").to_string(),
            "IN2 takes 1 (on), 0 (off) or open (nothing connected), not `high`"
        );
        assert_eq!(inputs::names(INPUTS).len(), 6 + 6 + 1 + 1 + 1);
        let e = parse("LOAD=101").expect_err("over 100 %").to_string();
        assert!(e.starts_with("LOAD takes a whole number of"), "{e}");
    }

    fn gio(sim: &mut Tmcm1110, port: u8, bank: u8) -> i32 {
        let request = crate::protocol::tmcl::Request {
            address: 1,
            command: 15,
            kind: port,
            motor_bank: bank,
            value: 0,
        };
        sim.feed(&request.to_bytes());
        let out = sim.take_output();
        let bytes: [u8; 9] = out.as_slice().try_into().expect("one reply");
        crate::protocol::tmcl::Reply::from_bytes(&bytes)
            .expect("a reply")
            .value
    }

    #[test]
    fn settings_drive_what_gio_reads() {
        let mut sim = Tmcm1110::new(SimConfig::default());
        let drive = |sim: &mut Tmcm1110, text: &str| {
            SimulatedController::drive_input(sim, text).unwrap_or_else(|e| panic!("{text}: {e}"))
        };
        assert_eq!(gio(&mut sim, 3, 0), 1, "open, pull-up on");
        assert_eq!(drive(&mut sim, "IN3=0"), "IN3 (PWMD2) off");
        assert_eq!(gio(&mut sim, 3, 0), 0);
        assert_eq!(
            drive(&mut sim, "PWMD2=open"),
            "IN3 (PWMD2) open: its pull-up decides"
        );
        assert_eq!(gio(&mut sim, 3, 0), 1);
        assert_eq!(drive(&mut sim, "AIN0=302"), "AIN0 302");
        assert_eq!(gio(&mut sim, 0, 1), 302, "§3.6.15's example value");
        assert_eq!(gio(&mut sim, 0, 0), 0);
        assert!(sim.help().contains("IN1..IN6=0|1|open"), "{}", sim.help());
        // SGP 78, 0, 1 makes PWMU0 (IN4) an output: the level is kept, the
        // answer says so.
        let sgp = crate::protocol::tmcl::Request {
            address: 1,
            command: 9,
            kind: 78,
            motor_bank: 0,
            value: 1,
        };
        sim.feed(&sgp.to_bytes());
        let _ = sim.take_output();
        assert_eq!(
            drive(&mut sim, "IN4=0"),
            "IN4 (PWMU0) off; an output now (GP78 bit 0): GIO reads its latch until it is an input again"
        );
    }

    /// §3.6.2 ROR and §3.6.6 GAP frames written out by hand (address 1,
    /// command, type, motor, value MSB first, checksum = byte sum):
    /// with the limits swapped, ROR 0, 2047 carries the carriage onto the
    /// switch at the plus end, which now closes the left input (AP11); the
    /// right switch (AP10) stops positive motion (AP12), so the motor runs
    /// on until the end stop holds it.
    #[test]
    fn swapped_limits_close_the_left_input_at_the_plus_end_and_do_not_stop_the_motor() {
        let mut sim = Tmcm1110::new(SimConfig::default());
        assert_eq!(
            SimulatedController::drive_input(&mut sim, "LIMITS=swapped"),
            Ok(
                "LIMITS swapped: the + end closes the left limit input, the − end the right one"
                    .into()
            )
        );
        let ror = [0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x07, 0xFF, 0x08];
        sim.feed(&ror);
        let _ = sim.take_output();
        let gap = |sim: &mut Tmcm1110, kind: u8| {
            let sum = 0x01u8.wrapping_add(0x06).wrapping_add(kind);
            sim.feed(&[0x01, 0x06, kind, 0x00, 0x00, 0x00, 0x00, 0x00, sum]);
            let out = sim.take_output();
            let bytes: [u8; 9] = out.as_slice().try_into().expect("one reply");
            i32::from_be_bytes([bytes[4], bytes[5], bytes[6], bytes[7]])
        };
        // 2047 at pulse divisor 3 is about 62,500 µsteps/s: past the +
        // switching point (200000) in under 4 s.
        for _ in 0..40 {
            sim.advance(std::time::Duration::from_millis(100));
            if gap(&mut sim, 1) >= 200_000 {
                break;
            }
        }
        assert!(gap(&mut sim, 1) >= 200_000);
        assert_eq!(
            (gap(&mut sim, 11), gap(&mut sim, 10)),
            (1, 0),
            "AP11 left, AP10 right"
        );
        assert_ne!(
            gap(&mut sim, 3),
            0,
            "still running: only AP10 stops + motion"
        );
        // It runs on to the end stop and stands there.
        sim.advance(std::time::Duration::from_secs(10));
        assert_eq!(
            gap(&mut sim, 1),
            200_000 + 2 * super::super::motion::DEFAULT_END_SWITCH_WIDTH as i32
        );
        assert_eq!(gap(&mut sim, 3), 0);
        assert_eq!(
            SimulatedController::drive_input(&mut sim, "LIMITS=right"),
            Ok(
                "LIMITS right: the + end closes the right limit input, the − end the left one"
                    .into()
            )
        );
        assert!(
            sim.help().contains("LIMITS=right|swapped"),
            "{}",
            sim.help()
        );
    }
}
