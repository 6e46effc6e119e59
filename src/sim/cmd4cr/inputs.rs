//! The CMD-4CR simulator's inputs as settings typed from outside
//! (`--input IO5=1`, a line on `axterm sim cmd4cr`'s standard input,
//! `:sim-input IO5=1`): the table of what there is, and the reading of a
//! setting against it. Applying one is [`super::Cmd4cr::drive_input`].
//!
//! Names are the manual's: DI1..DI4 (§2.1.3.2, read with `DI`), IO1..IO32
//! (§2.1.3.3, `IO`), AI1..AI2 (§2.5.1, `AI1`), /CEMG (§2.1.3.1.2) and
//! /CSTA (§2.1.1.2) without their slash and C, ALM of each axis (§2.1.2.2,
//! MST bit 3), and the switches of each axis after §2.1.3.1.1's signal
//! names L+, L-, H (as HOME) and SD: `L+X`, `L-X`, `HOMEX`, `SDX`. Levels
//! are logical, as the simulator's wiring is: `EMG=1` is /CEMG low, the
//! emergency on. The switches come from where the simulated carriage
//! stands (see the sim's help) until a setting forces one on or off;
//! `=stage` gives it back to the carriage.

use crate::sim::inputs::{self, InputRow, Names, Setting, SettingError, Values};

/// Which input a setting drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// High-speed input DIn.
    Digital,
    /// Configurable I/O IOn, as an input.
    Io,
    /// Analog input AIn, mV.
    Analog,
    /// /CEMG.
    Emergency,
    /// /CSTA.
    Start,
    /// ALM of axis X, Y, Z, U.
    Alarm,
    /// The switches of axis X, Y, Z, U, forced or left to the stage.
    PlusLimit,
    MinusLimit,
    Home,
    Slowdown,
}

/// A switch's values: forced on or off, or left to the demo stage.
const SWITCH: Values = Values::OnOffOr {
    word: "stage",
    meaning: "where the simulated carriage is sets it",
};

/// Every input a setting can drive.
pub const INPUTS: &[InputRow<Input>] = &[
    InputRow {
        input: Input::Digital,
        names: Names::Numbered {
            stem: "DI",
            first: 1,
            last: 4,
        },
        values: Values::OnOff,
        what: "high-speed input (DI word bit n-1); a rising edge triggers the armed latch of axis n (T2-3)",
    },
    InputRow {
        input: Input::Io,
        names: Names::Numbered {
            stem: "IO",
            first: 1,
            last: 32,
        },
        values: Values::OnOff,
        what: "configurable I/O that IOCFG makes an input (IO1..IO16 at power-on); one set as output is refused",
    },
    InputRow {
        input: Input::Analog,
        names: Names::Numbered {
            stem: "AI",
            first: 1,
            last: 2,
        },
        values: Values::Number {
            max: 3300,
            unit: "mV",
        },
        what: "analog input (joystick: AI1 moves X, AI2 moves Y, §2.5.1)",
    },
    InputRow {
        input: Input::Emergency,
        names: Names::Listed(&["EMG"]),
        values: Values::OnOff,
        what: "/CEMG low: every axis stops at once and none may start (§2.1.3.1.2)",
    },
    InputRow {
        input: Input::Start,
        names: Names::Listed(&["STA"]),
        values: Values::OnOff,
        what: "/CSTA low: going low starts a move waiting for it under EXST=1 (§2.1.1.2)",
    },
    InputRow {
        input: Input::Alarm,
        names: Names::Listed(&["ALMX", "ALMY", "ALMZ", "ALMU"]),
        values: Values::OnOff,
        what: "ALM of the axis' driver: stops the axis, refuses moves (§2.1.2.2)",
    },
    InputRow {
        input: Input::PlusLimit,
        names: Names::Listed(&["L+X", "L+Y", "L+Z", "L+U"]),
        values: SWITCH,
        what: "+limit switch: stops motion in the + direction (§2.1.3.1.1, MST bit 4)",
    },
    InputRow {
        input: Input::MinusLimit,
        names: Names::Listed(&["L-X", "L-Y", "L-Z", "L-U"]),
        values: SWITCH,
        what: "-limit switch: stops motion in the - direction (§2.1.3.1.1, MST bit 5)",
    },
    InputRow {
        input: Input::Home,
        names: Names::Listed(&["HOMEX", "HOMEY", "HOMEZ", "HOMEU"]),
        values: SWITCH,
        what: "home switch H, for the homing modes (§2.2.5, MST bit 6)",
    },
    InputRow {
        input: Input::Slowdown,
        names: Names::Listed(&["SDX", "SDY", "SDZ", "SDU"]),
        values: SWITCH,
        what: "slow-down switch SD (MST bit 7)",
    },
];

/// Read a setting (`IO5=1`) against [`INPUTS`].
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
    fn the_manuals_inputs_are_read() {
        assert_eq!(read("DI4=1"), (Input::Digital, 4, Level::On));
        assert_eq!(read("io5=1"), (Input::Io, 5, Level::On));
        assert_eq!(read("IO32=0"), (Input::Io, 32, Level::Off));
        assert_eq!(read("AI2=3300"), (Input::Analog, 2, Level::Number(3300)));
        assert_eq!(read("EMG=1"), (Input::Emergency, 0, Level::On));
        assert_eq!(read("STA=off"), (Input::Start, 0, Level::Off));
        assert_eq!(read("ALMU=1"), (Input::Alarm, 3, Level::On));
    }

    #[test]
    fn inputs_outside_the_manuals_ranges_are_refused() {
        for text in [
            "DI0=1", "DI5=1", "IO33=1", "AI3=5", "ALMA=1", "EMGX=1", "DO1=1",
        ] {
            let e = parse(text).expect_err(text).to_string();
            assert!(e.starts_with("there is no input"), "{e}");
            assert!(
                e.ends_with(
                    "the inputs are DI1..DI4=0|1, IO1..IO32=0|1, AI1..AI2=<mV 0..3300>, \
                     EMG=0|1, STA=0|1, ALMX|ALMY|ALMZ|ALMU=0|1, L+X|L+Y|L+Z|L+U=0|1|stage, \
                     L-X|L-Y|L-Z|L-U=0|1|stage, HOMEX|HOMEY|HOMEZ|HOMEU=0|1|stage, \
                     SDX|SDY|SDZ|SDU=0|1|stage"
                ),
                "{e}"
            );
        }
        let e = parse("AI1=3301").expect_err("above 3.3 V").to_string();
        assert_eq!(e, "AI1 takes a whole number of mV, 0..3300, not `3301`");
        let e = parse("EMG=open").expect_err("no open").to_string();
        assert_eq!(e, "EMG takes 1 (on) or 0 (off), not `open`");
        let e = parse("IO5").expect_err("no value").to_string();
        assert!(e.contains("give NAME=VALUE, e.g. DI1=1"), "{e}");
    }

    #[test]
    fn every_name_is_offered_for_completion() {
        let names = inputs::names(INPUTS);
        assert_eq!(names.len(), 4 + 32 + 2 + 1 + 1 + 4 * 5);
        assert_eq!(names.first().map(String::as_str), Some("DI1"));
        assert!(names.iter().any(|n| n == "IO19"));
        assert_eq!(inputs::help_lines(INPUTS).len(), INPUTS.len());
    }

    // ---- applied to the simulator, read back over the wire ------------

    use crate::sim::SimulatedController;
    use crate::sim::cmd4cr::{Cmd4cr, SimConfig};

    fn ask(sim: &mut Cmd4cr, text: &str) -> String {
        sim.feed(format!("@01{text}\r").as_bytes());
        let out = String::from_utf8_lossy(&sim.take_output()).into_owned();
        out.trim_end_matches('\r').to_string()
    }

    fn drive(sim: &mut Cmd4cr, text: &str) -> String {
        SimulatedController::drive_input(sim, text).unwrap_or_else(|e| panic!("{text}: {e}"))
    }

    #[test]
    fn di4_on_reads_8_as_the_manual_shows() {
        // §3.2.2 example: `@01DI` answers 8, DI4 on.
        let mut sim = Cmd4cr::new(SimConfig::default());
        assert_eq!(drive(&mut sim, "DI4=1"), "DI4 on");
        assert_eq!(ask(&mut sim, "DI"), "8");
        assert_eq!(drive(&mut sim, "di4=0"), "DI4 off");
        assert_eq!(ask(&mut sim, "DI"), "0");
    }

    #[test]
    fn a_rising_di_edge_triggers_the_armed_latch() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        assert_eq!(ask(&mut sim, "LTY=1"), "OK");
        drive(&mut sim, "DI2=1");
        assert_eq!(ask(&mut sim, "LTSY"), "2", "latched");
    }

    #[test]
    fn an_io_input_reads_back_and_an_io_output_is_refused() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        assert_eq!(drive(&mut sim, "IO5=1"), "IO5 on");
        assert_eq!(ask(&mut sim, "IO5"), "1");
        assert_eq!(ask(&mut sim, "IO"), "16");
        let refused = SimulatedController::drive_input(&mut sim, "IO19=1").expect_err("output");
        assert_eq!(
            refused,
            "IO19 cannot be driven: IOCFG 0xFFFF0000 makes IO19 an output (bit 18 set); \
             the simulator drives inputs only (IOCFG with bit 18 clear makes it one)"
        );
        assert_eq!(ask(&mut sim, "IO19"), "0");
        assert_eq!(ask(&mut sim, "IOCFG=0"), "OK");
        assert_eq!(drive(&mut sim, "IO19=1"), "IO19 on");
        assert_eq!(ask(&mut sim, "IO19"), "1");
    }

    #[test]
    fn analog_inputs_read_in_millivolts() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        assert_eq!(drive(&mut sim, "AI2=1650"), "AI2 1650 mV");
        assert_eq!(ask(&mut sim, "AI2"), "1650");
        assert_eq!(ask(&mut sim, "AI1"), "0");
    }

    #[test]
    fn emg_stops_and_refuses_moves_until_it_clears() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        assert_eq!(ask(&mut sim, "EO=15"), "OK");
        assert_eq!(
            drive(&mut sim, "EMG=1"),
            "EMG on (/CEMG low: every axis stops, none may start)"
        );
        assert_eq!(ask(&mut sim, "X1000"), "?Error ESTOP");
        assert_eq!(drive(&mut sim, "EMG=0"), "EMG off (/CEMG high)");
    }

    #[test]
    fn sta_low_starts_a_move_waiting_for_it() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        for line in ["EO=15", "EXST=1", "X1000"] {
            assert_eq!(ask(&mut sim, line), "OK", "{line}");
        }
        sim.advance(std::time::Duration::from_millis(50));
        assert_eq!(ask(&mut sim, "PX"), "0", "waits for /CSTA");
        assert_eq!(drive(&mut sim, "STA=1"), "STA on (/CSTA low)");
        sim.advance(std::time::Duration::from_secs(5));
        assert_eq!(ask(&mut sim, "PX"), "1000");
        assert_eq!(drive(&mut sim, "STA=0"), "STA off (/CSTA high)");
    }

    #[test]
    fn alm_of_an_axis_refuses_its_moves() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        assert_eq!(ask(&mut sim, "EO=15"), "OK");
        assert_eq!(drive(&mut sim, "ALMY=1"), "ALMY on");
        assert_eq!(ask(&mut sim, "Y1000"), "?Error Alarm");
        assert_eq!(ask(&mut sim, "X10"), "OK", "X has no alarm");
        drive(&mut sim, "ALMY=0");
        sim.advance(std::time::Duration::from_secs(1));
        assert_eq!(ask(&mut sim, "CLRY"), "OK");
        assert_eq!(ask(&mut sim, "Y1000"), "OK");
    }

    #[test]
    fn a_forced_limit_stops_a_jog_and_stage_gives_the_switch_back() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        for line in ["EO=15", "HSPD=1000", "JX+"] {
            assert_eq!(ask(&mut sim, line), "OK", "{line}");
        }
        sim.advance(std::time::Duration::from_millis(500));
        let moving: i64 = ask(&mut sim, "PX").parse().expect("a number");
        assert!(moving > 0, "jogging: {moving}");
        assert_eq!(drive(&mut sim, "L+X=1"), "L+X on");
        sim.advance(std::time::Duration::from_millis(100));
        let stopped = ask(&mut sim, "PX");
        sim.advance(std::time::Duration::from_millis(500));
        assert_eq!(ask(&mut sim, "PX"), stopped, "stopped at the limit");
        let mst: u32 = ask(&mut sim, "MSTX").parse().expect("a number");
        assert_eq!(
            mst & (16 | 256),
            16 | 256,
            "+limit input and +limit error: {mst}"
        );
        assert_eq!(
            drive(&mut sim, "l+x=STAGE"),
            "L+X from the stage (where the carriage is)"
        );
        assert_eq!(ask(&mut sim, "CLRX"), "OK");
        let mst: u32 = ask(&mut sim, "MSTX").parse().expect("a number");
        assert_eq!(mst & 16, 0, "far from the stage's limit: {mst}");
        // HOME at rest shows in MST (bit 6) while forced on.
        drive(&mut sim, "HOMEY=1");
        let mst: u32 = ask(&mut sim, "MSTY").parse().expect("a number");
        assert_eq!(mst & 64, 64, "{mst}");
    }

    #[test]
    fn a_bad_setting_changes_nothing_and_says_why() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        let e = SimulatedController::drive_input(&mut sim, "IO5=2").expect_err("2");
        assert_eq!(e, "IO5 takes 1 (on) or 0 (off), not `2`");
        assert_eq!(ask(&mut sim, "IO"), "0");
        assert!(
            sim.help().contains("DI1..DI4=0|1, IO1..IO32=0|1"),
            "{}",
            sim.help()
        );
    }
}
