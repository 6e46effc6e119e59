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
//!
//! Two settings per axis disturb the motor rather than close a switch,
//! so that StepNLoop (§2.5.3) has work to do on the simulator: `MISSX=n`
//! (after "missed steps", which StepNLoop "can help overcome", §2.1.2.3) makes
//! the X motor miss n steps of the move under way, now, and is refused
//! while no move drives the axis; `SLIPX=n` makes it miss n per mille of
//! the steps of every move from then on (1000: a motor that does not turn,
//! a stall), `SLIPX=0` ends it.

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
    /// The motor of axis X, Y, Z, U misses steps of the move under way.
    Missed,
    /// The motor of axis X, Y, Z, U misses a share of every move's steps.
    Slip,
    /// How every stage's end limits are wired to L+ and L-.
    Limits,
}

/// The most steps one `MISS…` setting makes a motor miss: far more than
/// any SLE (and the demo stage's travel), far within the 28-bit counters.
pub const MOST_MISSED: u32 = 1_000_000;

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
    InputRow {
        input: Input::Missed,
        names: Names::Listed(&["MISSX", "MISSY", "MISSZ", "MISSU"]),
        values: Values::Number {
            max: MOST_MISSED,
            unit: "steps",
        },
        what: "the motor misses that many steps of the move under way, now: carriage and encoder \
               fall behind P against the direction of travel, for StepNLoop to correct or report \
               (§2.5.3); refused while the axis stands still (no move sends it pulses)",
    },
    InputRow {
        input: Input::Slip,
        names: Names::Listed(&["SLIPX", "SLIPY", "SLIPZ", "SLIPU"]),
        values: Values::Number {
            max: 1000,
            unit: "per mille",
        },
        what: "from now on the motor misses that share of the steps of every move \
               (1000: it does not turn, a stall); 0 ends it",
    },
    InputRow {
        input: Input::Limits,
        names: Names::Listed(&["LIMITS"]),
        values: inputs::LIMITS_WIRING,
        what: "every stage's end limits wired right, or swapped: the + end turns L- on, the - end \
               L+; each still stops only its own direction (§2.1.3.1.1)",
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
                     SDX|SDY|SDZ|SDU=0|1|stage, MISSX|MISSY|MISSZ|MISSU=<steps 0..1000000>, \
                     SLIPX|SLIPY|SLIPZ|SLIPU=<per mille 0..1000>, LIMITS=right|swapped"
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
        assert_eq!(names.len(), 4 + 32 + 2 + 1 + 1 + 4 * 7 + 1);
        assert_eq!(names.first().map(String::as_str), Some("DI1"));
        assert!(names.iter().any(|n| n == "IO19"));
        assert!(names.iter().any(|n| n == "MISSU"));
        assert!(names.iter().any(|n| n == "SLIPZ"));
        assert_eq!(inputs::help_lines(INPUTS).len(), INPUTS.len());
    }

    // ---- applied to the simulator, read back over the wire ------------

    use crate::protocol::cmd4cr::Axis;
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

    /// LIMITS=swapped: at the stage's + end the -limit input comes on
    /// (MST bit 5, §2.1.3.1.1), which stops only motion toward -: the jog
    /// runs on into the end stop, where the carriage stalls while the
    /// pulse counter counts on; a jog toward - is then refused.
    #[test]
    fn swapped_limits_turn_on_l_minus_at_the_plus_end_and_a_plus_jog_runs_on() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        assert_eq!(
            drive(&mut sim, "LIMITS=swapped"),
            "LIMITS swapped: on every axis the + end turns L- on, the - end L+"
        );
        for line in ["EO=15", "HSPD=50000", "JX+"] {
            assert_eq!(ask(&mut sim, line), "OK", "{line}");
        }
        sim.advance(std::time::Duration::from_secs(3));
        let mst: u32 = ask(&mut sim, "MSTX").parse().expect("a number");
        assert_eq!(mst & (16 | 32), 32, "-limit input on, +limit off: {mst}");
        assert_ne!(ask(&mut sim, "PSX"), "0", "still pulsing");
        let encoder: i64 = ask(&mut sim, "EX").parse().expect("a number");
        assert_eq!(
            encoder,
            crate::sim::cmd4cr::motion::stage::DEMO_END_STOP,
            "held at the end stop"
        );
        let counter: i64 = ask(&mut sim, "PX").parse().expect("a number");
        assert!(counter > encoder, "P counts the lost pulses: {counter}");
        assert_eq!(ask(&mut sim, "STOPX"), "OK");
        sim.advance(std::time::Duration::from_secs(1));
        assert_eq!(ask(&mut sim, "JX-"), "?Error -Limit");
        assert_eq!(
            drive(&mut sim, "LIMITS=right"),
            "LIMITS right: on every axis the + end turns L+ on, the - end L-"
        );
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

    // ---- missed steps and slip, seen by StepNLoop (§2.5.3) -------------

    fn number(sim: &mut Cmd4cr, text: &str) -> i64 {
        let reply = ask(sim, text);
        reply
            .parse()
            .unwrap_or_else(|_| panic!("{text}: {reply} is no number"))
    }

    /// Advance in 10 ms steps until `axis` stands still and its loop is
    /// idle or in error (at most 30 s); every SLS seen on the way.
    fn settle(sim: &mut Cmd4cr, axis: char) -> Vec<i64> {
        let mut seen = Vec::new();
        for _ in 0..3000 {
            let sls = number(sim, &format!("SLS{axis}"));
            if seen.last() != Some(&sls) {
                seen.push(sls);
            }
            let mst = number(sim, &format!("MST{axis}"));
            if mst & 7 == 0 && matches!(sls, 0 | 8 | 9 | 10 | 12) {
                return seen;
            }
            sim.advance(std::time::Duration::from_millis(10));
        }
        panic!("{axis} still moving, SLS seen {seen:?}");
    }

    fn ms(n: u64) -> std::time::Duration {
        std::time::Duration::from_millis(n)
    }

    #[test]
    fn missed_steps_during_a_move_are_corrected_by_step_n_loop() {
        // SLT 10 < 30 <= SLE 1000: out of position, a correction (T2-26).
        let mut sim = Cmd4cr::new(SimConfig::default());
        for line in ["SLX=1", "SLTX=10", "SLEX=1000", "X5000"] {
            assert_eq!(ask(&mut sim, line), "OK", "{line}");
        }
        sim.advance(ms(500));
        assert_eq!(
            drive(&mut sim, "MISSX=30"),
            "MISSX 30: the X motor, moving +, missed 30 steps: \
             carriage and encoder are 30 pulses behind the pulse counter"
        );
        assert_eq!(number(&mut sim, "DX"), 30, "target - encoder");
        let seen = settle(&mut sim, 'X');
        assert!(seen.contains(&2), "a correction (SLS 2) ran: {seen:?}");
        assert_eq!(number(&mut sim, "SLSX"), 0);
        // P reads the target in encoder counts; the encoder reached it.
        assert_eq!(number(&mut sim, "EX"), 5000);
        assert_eq!(number(&mut sim, "PX"), 5000);
        assert_eq!(number(&mut sim, "DX"), 0);
        // The pulses sent: 5000 and the 30 the correction added.
        assert_eq!(sim.motion().counter(Axis::X), 5030);
    }

    #[test]
    fn steps_missed_moving_minus_leave_the_encoder_on_the_plus_side() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        for line in ["SLY=1", "Y-3000"] {
            assert_eq!(ask(&mut sim, line), "OK", "{line}");
        }
        sim.advance(ms(500));
        let said = drive(&mut sim, "MISSY=40");
        assert!(said.contains("moving -, missed 40 steps"), "{said}");
        assert_eq!(number(&mut sim, "DY"), -40, "the encoder lags at +40");
        let seen = settle(&mut sim, 'Y');
        assert!(seen.contains(&2), "{seen:?}");
        assert_eq!(number(&mut sim, "EY"), -3000);
    }

    #[test]
    fn a_large_loss_while_moving_is_a_stall_until_clr() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        for line in ["SLX=1", "SLEX=100", "HSPDX=2000", "JX+"] {
            assert_eq!(ask(&mut sim, line), "OK", "{line}");
        }
        assert_eq!(number(&mut sim, "SLSX"), 5, "jogging");
        sim.advance(ms(500));
        drive(&mut sim, "MISSX=150");
        sim.advance(ms(1));
        assert_eq!(number(&mut sim, "SLSX"), 10, "stall error");
        assert_eq!(number(&mut sim, "MSTX") & 7, 0, "the motor stopped");
        assert_eq!(number(&mut sim, "MSTX") & 0x1_0700, 0, "not an MST error");
        assert_eq!(ask(&mut sim, "JX+"), "?Error SNL");
        assert_eq!(ask(&mut sim, "X0"), "?Error SNL");
        assert_eq!(ask(&mut sim, "CLRX"), "OK");
        assert_eq!(number(&mut sim, "SLSX"), 0);
        assert_eq!(ask(&mut sim, "JX-"), "OK");
    }

    #[test]
    fn with_step_n_loop_off_p_and_e_part_by_the_missed_steps() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        assert_eq!(ask(&mut sim, "X1000"), "OK");
        sim.advance(ms(300));
        drive(&mut sim, "MISSX=30");
        settle(&mut sim, 'X');
        assert_eq!(number(&mut sim, "PX"), 1000);
        assert_eq!(number(&mut sim, "EX"), 970);
        assert_eq!(number(&mut sim, "SLSX"), 12, "N/A: nothing corrects it");
        // Back to 0: 20 more missed on the way, now short on the + side.
        assert_eq!(ask(&mut sim, "X0"), "OK");
        sim.advance(ms(300));
        drive(&mut sim, "MISSX=20");
        settle(&mut sim, 'X');
        assert_eq!(number(&mut sim, "PX"), 0);
        assert_eq!(number(&mut sim, "EX"), -10);
    }

    #[test]
    fn an_interpolated_axis_misses_steps_in_the_way_its_path_moves_it() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        assert_eq!(ask(&mut sim, "X2000Y-1000"), "OK");
        sim.advance(ms(300));
        let said = drive(&mut sim, "MISSY=25");
        assert!(said.contains("moving -"), "{said}");
        settle(&mut sim, 'X');
        assert_eq!(ask(&mut sim, "PP"), "2000:-1000:0:0");
        assert_eq!(ask(&mut sim, "EP"), "2000:-975:0:0");
    }

    #[test]
    fn missed_steps_at_rest_or_out_of_range_are_refused() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        let refused = SimulatedController::drive_input(&mut sim, "MISSX=30").expect_err("at rest");
        assert_eq!(
            refused,
            "MISSX cannot be driven: no move drives X now, and a motor misses steps only while \
             a move sends it pulses: start one (X1000, JX+, HX+0, an interpolation) and set \
             MISSX while it runs"
        );
        assert_eq!(ask(&mut sim, "EX"), "0", "nothing moved");
        assert_eq!(drive(&mut sim, "MISSX=0"), "MISSX 0: no steps missed");
        let e = SimulatedController::drive_input(&mut sim, "MISSX=1000001").expect_err("too many");
        assert_eq!(
            e,
            "MISSX takes a whole number of steps, 0..1000000, not `1000001`"
        );
        let e = SimulatedController::drive_input(&mut sim, "SLIPZ=1001").expect_err("over 1000");
        assert_eq!(
            e,
            "SLIPZ takes a whole number of per mille, 0..1000, not `1001`"
        );
        let e = SimulatedController::drive_input(&mut sim, "MISSX=-5").expect_err("negative");
        assert!(e.contains("not `-5`"), "{e}");
    }

    #[test]
    fn a_slipping_motor_runs_out_of_correction_attempts() {
        // Half of every step missed: 1000 -> 500 short -> 250 -> 125 -> 63:
        // after SLA 3 corrections still out of tolerance, SLS 9 (T2-26).
        let mut sim = Cmd4cr::new(SimConfig::default());
        assert_eq!(
            drive(&mut sim, "SLIPX=500"),
            "SLIPX 500: the X motor misses 500 of every 1000 steps while it moves"
        );
        for line in ["SLX=1", "SLTX=10", "SLEX=1000", "SLAX=3", "X1000"] {
            assert_eq!(ask(&mut sim, line), "OK", "{line}");
        }
        let seen = settle(&mut sim, 'X');
        assert!(seen.contains(&2), "{seen:?}");
        assert_eq!(number(&mut sim, "SLSX"), 9, "attempt error");
        let e = number(&mut sim, "EX");
        assert!((1000 - 63..1000 - 10).contains(&e), "short of 1000: {e}");
        assert_eq!(ask(&mut sim, "X0"), "?Error SNL");
        assert_eq!(ask(&mut sim, "CLRX"), "OK");
        assert_eq!(
            drive(&mut sim, "SLIPX=0"),
            "SLIPX 0: the X motor makes every step"
        );
        assert_eq!(ask(&mut sim, "X0"), "OK");
        settle(&mut sim, 'X');
        assert_eq!(number(&mut sim, "EX"), 0);
        assert_eq!(number(&mut sim, "SLSX"), 0);
    }

    #[test]
    fn a_motor_that_does_not_turn_stalls_and_slip_parts_p_and_e() {
        let mut sim = Cmd4cr::new(SimConfig::default());
        drive(&mut sim, "SLIPY=1000");
        for line in ["SLY=1", "SLEY=200", "JY+"] {
            assert_eq!(ask(&mut sim, line), "OK", "{line}");
        }
        let seen = settle(&mut sim, 'Y');
        assert_eq!(seen.last(), Some(&10), "stall: {seen:?}");
        assert_eq!(number(&mut sim, "EY"), 0, "the encoder never moved");
        // SL off: a tenth of the steps missed on the way.
        drive(&mut sim, "SLIPZ=100");
        assert_eq!(ask(&mut sim, "Z2000"), "OK");
        settle(&mut sim, 'Z');
        assert_eq!(number(&mut sim, "PZ"), 2000);
        assert_eq!(number(&mut sim, "EZ"), 1800);
    }

    #[test]
    fn a_slipping_motor_meets_each_switch_and_index_once() {
        // ZMOVE with ZCNT 1 stops on the second index pulse (every 1000
        // pulses from 250 on the demo stage) wherever the counter is.
        let mut sim = Cmd4cr::new(SimConfig::default());
        drive(&mut sim, "SLIPX=500");
        for line in ["ZCNTX=1", "ZMOVEX+"] {
            assert_eq!(ask(&mut sim, line), "OK", "{line}");
        }
        for _ in 0..3000 {
            if number(&mut sim, "MSTX") & 7 == 0 {
                break;
            }
            sim.advance(ms(10));
        }
        assert_eq!(number(&mut sim, "MSTX") & 7, 0, "stopped");
        assert_eq!(number(&mut sim, "EX"), 1250, "on the second index");
        let p = number(&mut sim, "PX");
        assert!((2499..=2501).contains(&p), "twice the pulses: {p}");
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
