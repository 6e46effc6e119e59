//! The CMD-4CR simulator running the manual's standalone programs (§5.4,
//! as corrected in the digest), controlled over the wire exactly as §2.7
//! documents: SACTRL, SASTAT, SPC, SLOAD, V0–V99 and GS.

mod ascript_support;

use std::time::Duration;

use ascript_support::example;
use axterm::sim::SimulatedController;
use axterm::sim::cmd4cr::{Cmd4cr, SimConfig};

fn sim() -> Cmd4cr {
    Cmd4cr::new(SimConfig::default())
}

fn send(sim: &mut Cmd4cr, text: &str) -> String {
    sim.feed(format!("@01{text}\r").as_bytes());
    let line = String::from_utf8(sim.take_output()).expect("ASCII");
    line.strip_suffix('\r')
        .unwrap_or_else(|| panic!("{text}: {line:?}"))
        .to_string()
}

fn number(sim: &mut Cmd4cr, text: &str) -> i64 {
    let reply = send(sim, text);
    reply
        .parse()
        .unwrap_or_else(|_| panic!("{text}: {reply} is no number"))
}

fn ok(sim: &mut Cmd4cr, text: &str) {
    assert_eq!(send(sim, text), "OK", "{text}");
}

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

#[test]
fn example_1_moves_x_out_and_back() {
    let mut sim = sim();
    sim.load_program(&example("5.4.1")).expect("compiles");
    assert_eq!(number(&mut sim, "SASTAT0"), 0, "loaded, idle");
    assert_eq!(number(&mut sim, "SASTAT1"), 3, "no PRG 1");
    // The sync output of X turns on if X reaches exactly 1000 (§2.1.3.2.2).
    for line in ["SYNCX=1", "SYNPX=1000", "SYNOX", "SACTRL0=1"] {
        ok(&mut sim, line);
    }
    assert_eq!(number(&mut sim, "SASTAT0"), 1);
    let mut steps_seen = Vec::new();
    for _ in 0..300 {
        sim.advance(ms(10));
        steps_seen.push(number(&mut sim, "SPC0"));
        if number(&mut sim, "SASTAT0") == 0 {
            break;
        }
    }
    assert_eq!(number(&mut sim, "SASTAT0"), 0, "ran to END");
    assert_eq!(number(&mut sim, "SYNSX"), 2, "X reached 1000");
    assert_eq!(number(&mut sim, "PX"), 0);
    // The program's settings are the controller's (HSPD=20000 ...).
    assert_eq!(number(&mut sim, "HSPD"), 20_000);
    assert_eq!(number(&mut sim, "EO"), 1);
    assert!(steps_seen.windows(2).all(|w| w[0] <= w[1]), "SPC advances");
}

#[test]
fn example_6_steps_x_each_time_di1_is_pressed() {
    let mut sim = sim();
    sim.load_program(&example("5.4.6")).expect("compiles");
    ok(&mut sim, "SACTRL0=1");
    sim.advance(ms(100));
    assert_eq!(number(&mut sim, "PX"), 0);
    for press in 0..3i64 {
        sim.set_digital_input(1, true);
        sim.advance(ms(1500));
        sim.set_digital_input(1, false);
        sim.advance(ms(100));
        // SUB 1 moves to V1 then adds 1000: 0, 1000, 2000.
        assert_eq!(number(&mut sim, "PX"), press * 1000);
        assert_eq!(number(&mut sim, "V1"), (press + 1) * 1000);
    }
    assert_eq!(number(&mut sim, "SASTAT0"), 1, "forever loop");
    ok(&mut sim, "SACTRL0=2");
    assert_eq!(number(&mut sim, "SASTAT0"), 2);
    let pc = number(&mut sim, "SPC0");
    sim.advance(ms(100));
    assert_eq!(number(&mut sim, "SPC0"), pc, "paused");
    ok(&mut sim, "SACTRL0=3");
    assert_eq!(number(&mut sim, "SASTAT0"), 1);
    ok(&mut sim, "SACTRL0=0");
    assert_eq!(number(&mut sim, "SASTAT0"), 0);
}

#[test]
fn example_7_recovers_from_a_limit_in_sub_31() {
    let mut sim = sim();
    // The + end limit closes at 5000: X6000 (DI3) runs into it.
    sim.motion_mut()
        .axis_mut(axterm::protocol::cmd4cr::Axis::X)
        .stage
        .plus_limit = Some(5000);
    sim.load_program(&example("5.4.7")).expect("compiles");
    ok(&mut sim, "SACTRL2=1");
    sim.set_digital_input(3, true);
    sim.advance(ms(200));
    assert_eq!(number(&mut sim, "DO1"), 1, "DO1 on while X moves");
    sim.advance(ms(1500));
    // Stopped on the limit; the next X6000 is refused (?Error +Limit),
    // SUB 31 clears the error, sends X to 0 and turns DO2 on.
    assert_eq!(number(&mut sim, "DO2"), 1);
    sim.set_digital_input(3, false);
    sim.advance(ms(2000));
    assert_eq!(number(&mut sim, "PX"), 0);
    assert_eq!(number(&mut sim, "MSTX") & 0x700, 0, "error cleared");
    assert_eq!(number(&mut sim, "DO1"), 0, "idle again");
    assert_eq!(number(&mut sim, "SASTAT2"), 1, "still running");
}

#[test]
fn example_8_one_thread_controls_the_other() {
    let mut sim = sim();
    sim.load_program(&example("5.4.8")).expect("compiles");
    for line in ["SYNCX=1", "SYNPX=1000", "SYNOX"] {
        ok(&mut sim, line);
    }
    // PRG 1 starts PRG 0 (SR0=1) while DI1 is off.
    ok(&mut sim, "SACTRL1=1");
    sim.advance(ms(50));
    assert_eq!(number(&mut sim, "SASTAT0"), 1);
    let mut positions = Vec::new();
    for _ in 0..40 {
        sim.advance(ms(50));
        positions.push(number(&mut sim, "PX"));
    }
    assert_eq!(number(&mut sim, "SYNSX"), 2, "PRG 0 moves X to 1000");
    assert!(
        positions.iter().filter(|&&p| p < 100).count() > 1,
        "and back to 0"
    );
    // DI1: ABORTX and SR0=0.
    sim.set_digital_input(1, true);
    sim.advance(ms(10));
    assert_eq!(number(&mut sim, "SASTAT0"), 0);
    let x = number(&mut sim, "PX");
    sim.advance(ms(500));
    assert_eq!(number(&mut sim, "PX"), x, "X stopped");
    assert_eq!(number(&mut sim, "MSTX") & 7, 0);
    sim.set_digital_input(1, false);
    sim.advance(ms(10));
    assert_eq!(number(&mut sim, "SASTAT0"), 1, "started again");
}

#[test]
fn every_example_program_loads() {
    for section in [
        "5.4.1", "5.4.2", "5.4.3", "5.4.4", "5.4.5", "5.4.6", "5.4.7", "5.4.8", "5.4.9", "5.4.10",
    ] {
        let mut sim = sim();
        sim.load_program(&example(section))
            .unwrap_or_else(|e| panic!("{section}: {e:?}"));
    }
}

#[test]
fn example_2_feeds_the_buffer_from_a_program() {
    let mut sim = sim();
    sim.load_program(&example("5.4.2")).expect("compiles");
    ok(&mut sim, "SACTRL1=1");
    let mut seen_buffer = false;
    // Seven moves at 100..500 pps: about 38 s.
    for _ in 0..1000 {
        sim.advance(ms(50));
        if send(&mut sim, "BSTAT").starts_with("1:") {
            seen_buffer = true;
        }
        if number(&mut sim, "SASTAT1") != 1 {
            break;
        }
    }
    assert!(seen_buffer, "BUFON turned buffer mode on");
    assert_eq!(number(&mut sim, "SASTAT1"), 0, "ran to END");
    assert!(
        send(&mut sim, "BSTAT").starts_with("0:"),
        "BUFOFF at the end"
    );
    assert_eq!(send(&mut sim, "PP"), "0:100:100:0");
}

#[test]
fn gs_calls_a_subroutine_and_variables_are_shared() {
    let mut sim = sim();
    sim.load_program("SUB 4\n    V2=V1*3\n    X500\n    WAITX\nENDSUB\n")
        .expect("compiles");
    assert_eq!(send(&mut sim, "GS3"), "?Sub not Initialized");
    ok(&mut sim, "V1=7");
    ok(&mut sim, "GS4");
    sim.advance(ms(2000));
    assert_eq!(number(&mut sim, "V2"), 21);
    assert_eq!(number(&mut sim, "PX"), 500);
}

#[test]
fn a_runtime_error_runs_sub_31_and_sap_picks_where_to_return() {
    for (sap, expected) in [(0, 1), (1, 2)] {
        let mut sim = sim();
        // The first pass divides by zero; SUB 31 fixes V3 and counts.
        sim.load_program(
            "PRG 0\n    V9=V9+1\n    V1=10/V3\n    DELAY=100000\nEND\nSUB 31\n    V3=2\n    V8=V8+1\nENDSUB\n",
        )
        .expect("compiles");
        ok(&mut sim, &format!("SAP={sap}"));
        ok(&mut sim, "SACTRL0=1");
        sim.advance(ms(10));
        assert_eq!(number(&mut sim, "SASTAT0"), 1);
        assert_eq!(number(&mut sim, "V8"), 1, "SUB 31 ran once");
        assert_eq!(number(&mut sim, "V1"), 5, "the division done after it");
        // SAP=0: back to the failing line; SAP=1: from the first line.
        assert_eq!(number(&mut sim, "V9"), expected, "SAP={sap}");
    }
}

#[test]
fn a_wait_for_an_axis_that_stops_on_an_error_is_an_error() {
    let mut sim = sim();
    sim.load_program("PRG 3\n    JOGX+\n    WAITX\n    V1=1\nEND\n")
        .expect("compiles");
    ok(&mut sim, "SACTRL3=1");
    sim.advance(ms(100));
    sim.motion_mut()
        .set_alarm(axterm::protocol::cmd4cr::Axis::X, true);
    sim.advance(ms(10));
    assert_eq!(number(&mut sim, "SASTAT3"), 4, "no SUB 31: error state");
    assert_eq!(number(&mut sim, "V1"), 0);
}

#[test]
fn programs_run_at_power_on_with_sload_and_stay_in_flash() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("flash.json");
    let config = || SimConfig {
        flash_file: Some(path.clone()),
        ..SimConfig::default()
    };
    let mut first = Cmd4cr::new(config());
    first
        .load_program("PRG 1\n    V5=V5+1\n    X300\n    WAITX\nEND\n")
        .expect("compiles");
    ok(&mut first, "SLOAD=2");
    ok(&mut first, "STORE");
    drop(first);
    let mut second = Cmd4cr::new(config());
    assert!(second.flash_problem().is_none());
    assert_eq!(number(&mut second, "SASTAT1"), 1, "started at power-on");
    second.advance(ms(2000));
    assert_eq!(number(&mut second, "SASTAT1"), 0);
    assert_eq!(number(&mut second, "PX"), 300);
    assert_eq!(number(&mut second, "V5"), 1);
}
