//! The CMD-4CR simulator seen from the wire: `@01…\r` in, virtual time,
//! `…\r` out. Frames are written by hand (§3.2.2); the sequences are the
//! manual's §4.3 examples with the corrections the digest lists (axis
//! letters restored in §4.3.4, §4.3.7 and §4.3.8, `EX=0` in §4.3.3), and
//! the assertions are the positions and states the manual implies.

use std::time::Duration;

use axterm::protocol::cmd4cr::Axis;
use axterm::sim::SimulatedController;
use axterm::sim::cmd4cr::{Cmd4cr, SimConfig};

fn sim() -> Cmd4cr {
    Cmd4cr::new(SimConfig::default())
}

/// The setup §4.3.2, §4.3.5 and §4.3.6 each begin with: global speeds,
/// X and Y enabled, absolute mode.
const GLOBAL_SETUP: [&str; 6] = ["LSPD=500", "HSPD=5000", "ACC=200", "DEC=200", "EO=3", "ABS"];

/// Send `text` to controller 01 and return its one reply line.
fn send(sim: &mut Cmd4cr, text: &str) -> String {
    sim.feed(format!("@01{text}\r").as_bytes());
    let out = sim.take_output();
    let line = String::from_utf8(out).expect("ASCII");
    let Some(reply) = line.strip_suffix('\r') else {
        panic!("{text}: no reply ending in CR, got {line:?}");
    };
    assert!(!reply.contains('\r'), "{text}: one reply, got {line:?}");
    reply.to_string()
}

fn ok(sim: &mut Cmd4cr, lines: &[&str]) {
    for line in lines {
        assert_eq!(send(sim, line), "OK", "{line}");
    }
}

fn number(sim: &mut Cmd4cr, text: &str) -> i64 {
    let reply = send(sim, text);
    reply
        .parse()
        .unwrap_or_else(|_| panic!("{text}: {reply} is no number"))
}

fn seconds(s: f64) -> Duration {
    Duration::from_secs_f64(s)
}

/// Advance in 10 ms steps until MST of `axis` shows no motion and the
/// axis takes commands again, at most `limit`; as a host polling MST does.
fn wait_stopped(sim: &mut Cmd4cr, axis: char, limit: Duration) {
    let step = Duration::from_millis(10);
    let mut waited = Duration::ZERO;
    loop {
        let mst = number(sim, &format!("MST{axis}"));
        if mst & 7 == 0 && mst & (1 << 18 | 1 << 19) == 0 {
            return;
        }
        assert!(
            waited < limit,
            "{axis} still moving after {limit:?} (MST {mst})"
        );
        sim.advance(step);
        waited += step;
    }
}

#[test]
fn the_three_documented_replies() {
    // §3.2.2: @01POLX → 7 (the default POL), @01DI → 8 with DI4 on,
    // @01STORE → OK.
    let mut sim = sim();
    assert!(sim.set_digital_input(4, true));
    let vectors: serde_json::Value =
        serde_json::from_str(include_str!("data/cmd4cr-vectors.json")).expect("vectors");
    let mut checked = 0;
    for entry in vectors.as_array().expect("array") {
        let (Some(send_text), Some(reply)) = (entry["send"].as_str(), entry["reply"].as_str())
        else {
            continue;
        };
        sim.feed(format!("{send_text}\r").as_bytes());
        assert_eq!(
            sim.take_output(),
            format!("{reply}\r").into_bytes(),
            "{send_text}"
        );
        checked += 1;
    }
    assert_eq!(checked, 3);
}

#[test]
fn every_command_vector_of_the_manual_is_answered() {
    // Every §4.3 and inline vector (as corrected): a value for a read,
    // OK or a §4.2 error for the rest, never silence or an unknown command.
    let mut sim = sim();
    let vectors: serde_json::Value =
        serde_json::from_str(include_str!("data/cmd4cr-vectors.json")).expect("vectors");
    for entry in vectors.as_array().expect("array") {
        let text = entry["likely_intended"]
            .as_str()
            .or_else(|| entry["send"].as_str());
        let Some(text) = text else { continue };
        sim.feed(format!("{text}\r").as_bytes());
        let reply = String::from_utf8(sim.take_output()).expect("ASCII");
        assert!(reply.ends_with('\r'), "{text}: {reply:?}");
        assert!(!reply.starts_with("?Unknown"), "{text}: {reply:?}");
        sim.advance(Duration::from_millis(100));
    }
}

#[test]
fn jog_and_stop_4_3_1() {
    let mut sim = sim();
    ok(
        &mut sim,
        &[
            "LSPDX=500",
            "HSPDX=5000",
            "ACCX=200",
            "DECX=200",
            "EO1=1",
            "JX-",
        ],
    );
    assert_eq!(send(&mut sim, "EO"), "1");
    sim.advance(seconds(0.1));
    assert_eq!(number(&mut sim, "MSTX"), 1, "accelerating");
    sim.advance(seconds(0.9));
    // 550 pulses of ramp, then 0.8 s at 5000 pps.
    assert_eq!(number(&mut sim, "PX"), -4550);
    assert_eq!(number(&mut sim, "PSX"), 5000);
    assert_eq!(number(&mut sim, "MSTX"), 4, "constant speed");
    assert_eq!(send(&mut sim, "JX+"), "?Error Moving");
    ok(&mut sim, &["STOPX"]);
    sim.advance(seconds(0.1));
    assert_eq!(number(&mut sim, "MSTX"), 2, "decelerating");
    sim.advance(seconds(0.2));
    assert_eq!(number(&mut sim, "PX"), -5100);
    assert_eq!(number(&mut sim, "MSTX"), 0);
    assert_eq!(number(&mut sim, "PSX"), 0);
}

#[test]
fn position_move_4_3_2() {
    let mut sim = sim();
    // The global speeds of §4.3.2, §4.3.5 and §4.3.6.
    ok(&mut sim, &GLOBAL_SETUP);
    ok(&mut sim, &["X-20000"]);
    sim.advance(seconds(0.05));
    ok(&mut sim, &["Y15000"]);
    sim.advance(seconds(1.0));
    assert_eq!(number(&mut sim, "MSTX") & 7, 4);
    assert_eq!(number(&mut sim, "MSTY") & 7, 4);
    assert_eq!(number(&mut sim, "MM"), 0);
    // X: 0.4 s of ramps and 3.78 s at 5000 pps.
    sim.advance(seconds(3.1));
    assert_ne!(number(&mut sim, "MSTX") & 7, 0);
    sim.advance(seconds(0.1));
    assert_eq!(send(&mut sim, "PP"), "-20000:15000:0:0");
    assert_eq!(send(&mut sim, "EP"), "-20000:15000:0:0");
    assert_eq!(number(&mut sim, "MSTX"), 0);
}

#[test]
fn counters_4_3_3() {
    let mut sim = sim();
    ok(&mut sim, &["X3000"]);
    sim.advance(seconds(0.5));
    // While the axis moves the counters are not cleared.
    assert_ne!(number(&mut sim, "MSTX"), 0);
    assert_eq!(send(&mut sim, "PX=0"), "?Error Moving");
    // Poll PX, EX, MSTX as the example's timer does; clear when MSTX is 0.
    let mut cleared = false;
    for _ in 0..1000 {
        let p = number(&mut sim, "PX");
        let e = number(&mut sim, "EX");
        assert_eq!(p, e, "the encoder follows the pulses");
        if number(&mut sim, "MSTX") == 0 {
            assert_eq!(p, 3000);
            ok(&mut sim, &["PX=0", "EX=0"]);
            cleared = true;
            break;
        }
        sim.advance(seconds(0.05));
    }
    assert!(cleared);
    assert_eq!(send(&mut sim, "PX"), "0");
    assert_eq!(send(&mut sim, "EX"), "0");
    assert_eq!(send(&mut sim, "DX"), "0", "no StepNLoop, no deviation");
}

#[test]
fn homing_4_3_4() {
    let mut sim = sim();
    ok(
        &mut sim,
        &[
            "LSPDY=500",
            "HSPDY=5000",
            "ACCY=200",
            "DECY=200",
            "EO2=1",
            "PY=1234",
        ],
    );
    // As printed the command has no axis (erratum): not a command.
    assert_eq!(send(&mut sim, "H-1"), "?Unknown Command: H-1");
    ok(&mut sim, &["HY-1"]);
    sim.advance(seconds(0.1));
    assert_ne!(number(&mut sim, "MSTY") & 7, 0);
    wait_stopped(&mut sim, 'Y', seconds(10.0));
    // Mode 1 ends on the home switch with the counter zeroed there.
    assert_eq!(number(&mut sim, "PY"), 0);
    assert_eq!(number(&mut sim, "EY"), 0);
    assert_eq!(number(&mut sim, "MSTY"), 64, "home input on, no error");
    // The zero is where the switch is: a move away and back ends on it.
    ok(&mut sim, &["Y5000"]);
    wait_stopped(&mut sim, 'Y', seconds(5.0));
    ok(&mut sim, &["Y0"]);
    wait_stopped(&mut sim, 'Y', seconds(5.0));
    assert_eq!(number(&mut sim, "MSTY"), 64);
}

#[test]
fn linear_interpolation_4_3_5() {
    let mut sim = sim();
    // The global speeds of §4.3.2, §4.3.5 and §4.3.6.
    ok(&mut sim, &GLOBAL_SETUP);
    ok(&mut sim, &["EINT=1", "X-20000Y15000"]);
    for step in 0..8 {
        sim.advance(seconds(0.5));
        let (x, y) = (number(&mut sim, "PX"), number(&mut sim, "PY"));
        // On the line from (0, 0) to (-20000, 15000): 3x + 4y = 0.
        assert!((3 * x + 4 * y).abs() <= 4, "({x}, {y}) off the line");
        if step == 3 {
            assert_eq!(number(&mut sim, "PSX"), 5000, "X is the main axis");
            assert_eq!(number(&mut sim, "PSY"), 3750);
        }
    }
    sim.advance(seconds(0.2));
    assert_eq!(send(&mut sim, "PP"), "-20000:15000:0:0");
    assert_eq!(number(&mut sim, "MSTX"), 0);
    assert_eq!(number(&mut sim, "MSTY"), 0);
}

#[test]
fn circular_interpolation_4_3_6() {
    let mut sim = sim();
    // The global speeds of §4.3.2, §4.3.5 and §4.3.6.
    ok(&mut sim, &GLOBAL_SETUP);
    ok(&mut sim, &["EINT=1", "CIRXYP1000:0"]);
    let mut points = Vec::new();
    for _ in 0..300 {
        sim.advance(seconds(0.01));
        let (x, y) = (number(&mut sim, "PX"), number(&mut sim, "PY"));
        let r = (((x - 1000).pow(2) + y.pow(2)) as f64).sqrt();
        assert!((r - 1000.0).abs() <= 1.0, "({x}, {y}) off the circle");
        points.push((x, y));
    }
    // Clockwise from (0, 0) around (1000, 0): up through (1000, 1000),
    // over to (2000, 0), down through (1000, -1000).
    let first_top = points.iter().position(|&(_, y)| y == 1000).expect("top");
    let right = points.iter().position(|&(x, _)| x == 2000).expect("right");
    let bottom = points
        .iter()
        .position(|&(_, y)| y == -1000)
        .expect("bottom");
    assert!(first_top < right && right < bottom);
    wait_stopped(&mut sim, 'X', seconds(5.0));
    assert_eq!(send(&mut sim, "PP"), "0:0:0:0");
}

#[test]
fn on_the_fly_speed_change_4_3_7() {
    let mut sim = sim();
    ok(
        &mut sim,
        &["LSPDX=1000", "HSPDX=50000", "ACCX=100", "DECX=100", "JX-"],
    );
    sim.advance(seconds(0.5));
    assert_eq!(number(&mut sim, "PSX"), 50_000);
    // As printed: no axis letters (erratum).
    assert!(send(&mut sim, "SSPDM=2").starts_with("?Unknown Command"));
    assert!(send(&mut sim, "SSPD=70000").starts_with("?Unknown Command"));
    // 70,000 pps is outside the default window 0 (up to 65,535 pps).
    assert_eq!(send(&mut sim, "SSPDX=70000"), "?SSPD Error");
    ok(&mut sim, &["SSPDMX=2", "SSPDX=70000"]);
    sim.advance(seconds(0.01));
    assert_eq!(
        number(&mut sim, "MSTX") & 7,
        1,
        "accelerating to the new speed"
    );
    sim.advance(seconds(0.5));
    assert_eq!(number(&mut sim, "PSX"), 70_000);
    assert_eq!(number(&mut sim, "MSTX") & 7, 4);
    ok(&mut sim, &["STOPX"]);
    wait_stopped(&mut sim, 'X', seconds(1.0));
}

#[test]
fn sync_output_4_3_8() {
    let mut sim = sim();
    ok(
        &mut sim,
        &["LSPDX=100", "HSPDX=1000", "SYNCX=1", "SYNPX=5000"],
    );
    // As printed SYNO has no axis (erratum).
    assert!(send(&mut sim, "SYNO").starts_with("?Unknown Command"));
    ok(&mut sim, &["SYNOX"]);
    assert_eq!(number(&mut sim, "SYNSX"), 1, "waiting for the condition");
    ok(&mut sim, &["X5000"]);
    sim.advance(seconds(3.0));
    assert_eq!(number(&mut sim, "DO1"), 0);
    wait_stopped(&mut sim, 'X', seconds(10.0));
    assert_eq!(number(&mut sim, "PX"), 5000);
    assert_eq!(number(&mut sim, "DO1"), 1, "DO1/SYNCx on at 5000");
    assert_eq!(number(&mut sim, "SYNSX"), 2);
    // The output is the sync's until SYNF; then the DO latch again.
    ok(&mut sim, &["DO1=0"]);
    assert_eq!(number(&mut sim, "DO"), 1);
    ok(&mut sim, &["SYNFX"]);
    assert_eq!(number(&mut sim, "DO"), 0);
    assert_eq!(number(&mut sim, "SYNSX"), 0);
}

#[test]
fn general_purpose_io_4_3_9() {
    let mut sim = sim();
    // The example's loop: read IO5, copy it to IO19.
    for level in [false, true, true, false] {
        assert!(sim.set_io_input(5, level));
        let input = number(&mut sim, "IO5");
        assert_eq!(input, i64::from(level));
        ok(&mut sim, &[&format!("IO19={input}")]);
        assert_eq!(number(&mut sim, "IO19"), input);
        let expected = (i64::from(level) << 4) | (input << 18);
        assert_eq!(number(&mut sim, "IO"), expected);
    }
    // An input cannot be driven from the host.
    ok(&mut sim, &["IO5=1"]);
    assert_eq!(number(&mut sim, "IO5"), 0);
    ok(&mut sim, &["IOCFG=0"]);
    ok(&mut sim, &["IO19=1"]);
    assert_eq!(number(&mut sim, "IO19"), 0, "IO19 is an input now");
}

#[test]
fn every_error_reply_for_its_cause() {
    let mut sim = sim();
    assert_eq!(send(&mut sim, "FOO"), "?Unknown Command: FOO");
    assert_eq!(send(&mut sim, "DI5"), "?Invalid Index");
    assert_eq!(send(&mut sim, "GS5"), "?Sub not Initialized");
    // Buffer.
    assert_eq!(send(&mut sim, "I1:2:3:100"), "?Buffer Disabled");
    assert_eq!(send(&mut sim, "BSTART"), "?Buffer Disabled");
    ok(&mut sim, &["BO"]);
    for _ in 0..100 {
        ok(&mut sim, &["I0:0:0:100"]);
    }
    assert_eq!(send(&mut sim, "BSTAT"), "1:0:0:0");
    assert_eq!(send(&mut sim, "I0:0:0:100"), "?Buffer Full");
    ok(&mut sim, &["JU+"]);
    sim.advance(seconds(0.5));
    assert_eq!(send(&mut sim, "SSPDU=2000"), "?Buffer Enabled");
    ok(&mut sim, &["BF", "STOPU"]);
    wait_stopped(&mut sim, 'U', seconds(2.0));
    // SSPD and T.
    assert_eq!(
        send(&mut sim, "SSPDX=2000"),
        "?Override Failed",
        "X is idle"
    );
    ok(&mut sim, &["JX+"]);
    sim.advance(seconds(0.5));
    assert_eq!(send(&mut sim, "TX100"), "?Override Failed", "not for a jog");
    assert_eq!(send(&mut sim, "SSPDMX=3"), "OK");
    assert_eq!(send(&mut sim, "SSPDX=2"), "?SSPD Error", "below window 3");
    ok(&mut sim, &["SCVX=1"]);
    assert_eq!(send(&mut sim, "SSPDX=2000"), "?SSPD Error", "S-curve on");
    // Moving.
    assert_eq!(send(&mut sim, "X5"), "?Error Moving");
    ok(&mut sim, &["ABORTX"]);
    // Limits.
    let x = Axis::X;
    sim.motion_mut().axis_mut(x).inputs.plus_limit = Some(true);
    assert_eq!(send(&mut sim, "JX+"), "?Error +Limit");
    sim.motion_mut().axis_mut(x).inputs.plus_limit = None;
    sim.motion_mut().axis_mut(x).inputs.minus_limit = Some(true);
    assert_eq!(send(&mut sim, "X-100"), "?Error -Limit");
    sim.motion_mut().axis_mut(x).inputs.minus_limit = None;
    // Alarm.
    sim.motion_mut().set_alarm(x, true);
    assert_eq!(send(&mut sim, "HX+0"), "?Error Alarm");
    sim.motion_mut().set_alarm(x, false);
    // Emergency stop input.
    sim.set_emergency_input(true);
    assert_eq!(send(&mut sim, "ZMOVEX+"), "?Error ESTOP");
    assert_eq!(number(&mut sim, "MSTX"), (1 << 15) | (1 << 16));
    sim.set_emergency_input(false);
    // The EMG error stays until CLR.
    assert_eq!(send(&mut sim, "JX+"), "?Error Moving");
    ok(&mut sim, &["CLRX", "JX+"]);
}

#[test]
fn a_program_in_the_error_state_refuses_control() {
    let mut sim = sim();
    assert_eq!(number(&mut sim, "SASTAT0"), 3, "no program: N/A");
    // A division by zero with no SUB 31: the program stops in error.
    sim.load_program("PRG 2\n    V1=V2/V3\nEND\n")
        .expect("compiles");
    assert_eq!(number(&mut sim, "SASTAT2"), 0);
    ok(&mut sim, &["SACTRL2=1"]);
    sim.advance(Duration::from_millis(1));
    assert_eq!(number(&mut sim, "SASTAT2"), 4);
    assert_eq!(send(&mut sim, "SACTRL2=1"), "?Program Error");
    ok(&mut sim, &["SACTRL2=0"]);
    assert_eq!(number(&mut sim, "SASTAT2"), 0);
}

#[test]
fn the_emergency_stop_flags_only_moving_axes() {
    let mut sim = sim();
    ok(&mut sim, &["JX+", "JZ-"]);
    sim.advance(seconds(0.5));
    ok(&mut sim, &["ESTOP"]);
    assert_eq!(number(&mut sim, "MSTX"), 1 << 16);
    assert_eq!(number(&mut sim, "MSTZ"), 1 << 16);
    assert_eq!(number(&mut sim, "MSTY"), 0);
    let x = number(&mut sim, "PX");
    sim.advance(seconds(0.5));
    assert_eq!(number(&mut sim, "PX"), x, "stopped at once");
    ok(&mut sim, &["IERR=1", "CLRX", "JX+", "ESTOP"]);
    assert_eq!(number(&mut sim, "MSTX"), 0, "IERR=1 latches nothing");
}

#[test]
fn buffered_moves_over_the_wire() {
    let mut sim = sim();
    ok(
        &mut sim,
        &[
            "BO",
            "I1000:0:0:2000",
            "I1000:1000:0:1000",
            "CIRXYN1000:500",
        ],
    );
    assert_eq!(send(&mut sim, "BSTAT"), "1:0:3:97");
    sim.advance(seconds(1.0));
    assert_eq!(send(&mut sim, "PP"), "0:0:0:0", "waits for BSTART");
    ok(&mut sim, &["BSTART"]);
    sim.advance(seconds(0.25));
    assert_eq!(number(&mut sim, "PSX"), 2000, "its own constant speed");
    sim.advance(seconds(0.5));
    assert_eq!(
        number(&mut sim, "PSY"),
        1000,
        "the next one, without a stop"
    );
    wait_stopped(&mut sim, 'X', seconds(10.0));
    assert_eq!(
        send(&mut sim, "PP"),
        "1000:1000:0:0",
        "the circle ends where it began"
    );
    assert_eq!(send(&mut sim, "BSTAT"), "1:3:3:100");
    ok(&mut sim, &["BF"]);
    assert_eq!(send(&mut sim, "BSTAT"), "0:0:0:100");
}

#[test]
fn helical_and_arc_moves_over_the_wire() {
    let mut sim = sim();
    ok(&mut sim, &["HSPD=5000", "PX=1000", "ARCXYN0:0:90000"]);
    wait_stopped(&mut sim, 'X', seconds(5.0));
    assert_eq!(send(&mut sim, "PP"), "0:1000:0:0");
    ok(&mut sim, &["CIRTP0:0:-500"]);
    sim.advance(seconds(0.1));
    assert_eq!(
        send(&mut sim, "JU+"),
        "?Error Moving",
        "U is used internally"
    );
    wait_stopped(&mut sim, 'X', seconds(5.0));
    assert_eq!(send(&mut sim, "PP"), "0:1000:-500:0");
}

#[test]
fn target_change_over_the_wire() {
    let mut sim = sim();
    ok(&mut sim, &["HSPD=5000", "X20000"]);
    sim.advance(seconds(1.0));
    ok(&mut sim, &["TX3000"]);
    wait_stopped(&mut sim, 'X', seconds(10.0));
    assert_eq!(number(&mut sim, "PX"), 3000);
}

#[test]
fn external_start_over_the_wire() {
    let mut sim = sim();
    ok(&mut sim, &["EXST=1", "X100", "Y200"]);
    sim.advance(seconds(1.0));
    assert_eq!(send(&mut sim, "PP"), "0:0:0:0");
    assert_eq!(number(&mut sim, "MSTX"), 1 << 19);
    sim.set_start_input(true);
    sim.set_start_input(false);
    sim.advance(seconds(1.0));
    assert_eq!(send(&mut sim, "PP"), "100:0:0:0", "one move per /CSTA edge");
    sim.set_start_input(true);
    sim.advance(seconds(1.0));
    assert_eq!(send(&mut sim, "PP"), "100:200:0:0");
}

#[test]
fn reads_of_settings_echo_what_was_written() {
    let mut sim = sim();
    for (write, read, value) in [
        ("ACCZ=123", "ACCZ", "123"),
        ("ZCNTU=15", "ZCNTU", "15"),
        ("DB=5", "DB", "5"),
        ("ERCDY=3", "ERCDY", "3"),
        ("PWM2=99", "PWM2", "99"),
        ("SYNCZ=-1", "SYNCZ", "-1"),
        ("JENA=0", "JENA", "0"),
        ("SLRX=0.001", "SLRX", "0.001"),
        ("SAP=1", "SAP", "1"),
        ("IERR=1", "IERR", "1"),
    ] {
        ok(&mut sim, &[write]);
        assert_eq!(send(&mut sim, read), value, "{read}");
    }
    assert_eq!(send(&mut sim, "VER"), "V126BL");
    assert_eq!(send(&mut sim, "SLSX"), "12", "StepNLoop off: N/A");
    assert_eq!(send(&mut sim, "AI1"), "0");
    assert!(sim.set_analog_input(1, 1650));
    assert_eq!(send(&mut sim, "AI1"), "1650");
}

#[test]
fn step_n_loop_moves_in_encoder_counts_and_corrects_lost_steps() {
    // §2.5.3: a 2:1 drive, two motor pulses per encoder count.
    let mut sim = sim();
    sim.motion_mut().axis_mut(Axis::X).stage.encoder_ratio = 0.5;
    assert_eq!(send(&mut sim, "SLSX"), "12", "N/A while off");
    // The calibration recipe: with SL off, +1000 pulses, SLR = 1000 / EX.
    ok(&mut sim, &["EX=0", "PX=0", "HSPDX=1000", "X1000"]);
    wait_stopped(&mut sim, 'X', seconds(5.0));
    assert_eq!(number(&mut sim, "EX"), 500);
    ok(
        &mut sim,
        &["SLRX=2", "SLTX=5", "SLEX=300", "SLAX=3", "SLX=1"],
    );
    assert_eq!(number(&mut sim, "SLSX"), 0);
    assert_eq!(number(&mut sim, "PX"), 500, "the target, in encoder counts");
    assert_eq!(number(&mut sim, "DX"), 0);
    // X1500 is an encoder position: 2000 pulses; HSPDX in counts/s.
    ok(&mut sim, &["X1500"]);
    sim.advance(seconds(0.5));
    assert_eq!(number(&mut sim, "SLSX"), 1, "moving");
    assert_eq!(number(&mut sim, "PSX"), 1000, "encoder counts/s");
    // The motor misses 40 steps: 20 counts behind, within SLE.
    sim.motion_mut().lose_steps(Axis::X, 40);
    assert_eq!(number(&mut sim, "DX"), 20);
    let mut corrected = false;
    for _ in 0..500 {
        sim.advance(seconds(0.01));
        corrected |= number(&mut sim, "SLSX") == 2;
        if number(&mut sim, "MSTX") & 7 == 0 && number(&mut sim, "SLSX") == 0 {
            break;
        }
    }
    assert!(corrected, "a correction move ran (SLS 2)");
    assert_eq!(number(&mut sim, "EX"), 1500);
    assert_eq!(number(&mut sim, "DX"), 0);
    assert_eq!(number(&mut sim, "PX"), 1500);
}

#[test]
fn a_step_n_loop_stall_stops_the_axis_and_answers_error_snl() {
    let mut sim = sim();
    ok(&mut sim, &["SLX=1", "SLEX=100", "HSPDX=2000", "JX+"]);
    assert_eq!(number(&mut sim, "SLSX"), 5, "jogging");
    sim.advance(seconds(0.5));
    sim.motion_mut().lose_steps(Axis::X, 150);
    sim.advance(seconds(0.001));
    assert_eq!(number(&mut sim, "SLSX"), 10, "stall error");
    assert_eq!(number(&mut sim, "MSTX") & 7, 0, "stopped");
    assert_eq!(number(&mut sim, "MSTX") & 0x1_0700, 0, "not an MST error");
    assert_eq!(send(&mut sim, "JX+"), "?Error SNL");
    ok(&mut sim, &["CLRX"]);
    assert_eq!(number(&mut sim, "SLSX"), 0);
    ok(&mut sim, &["JX-", "ABORTX"]);
    // No more attempts allowed: the first correction is an attempt error.
    ok(&mut sim, &["SLAX=0", "SLEX=1000", "X100"]);
    sim.advance(seconds(0.05));
    sim.motion_mut().lose_steps(Axis::X, 30);
    wait_stopped(&mut sim, 'X', seconds(5.0));
    assert_eq!(number(&mut sim, "SLSX"), 9);
    assert_eq!(send(&mut sim, "X0"), "?Error SNL");
}

#[test]
fn the_joystick_drives_x_from_ai1_within_its_soft_limits() {
    // §2.5.1: JMAX 3250, JMIN 10, JTOL 50: MID 1630, dead band 1580-1680.
    let mut sim = sim();
    ok(
        &mut sim,
        &[
            "JMAXX=3250",
            "JMINX=10",
            "JTOLX=50",
            "JSPDX=2000",
            "JDELX=100",
            "JLIM3=3000",
            "JLIM4=4000",
        ],
    );
    assert!(sim.set_analog_input(1, 1650));
    ok(&mut sim, &["JENA=1"]);
    sim.advance(seconds(0.5));
    assert_eq!(number(&mut sim, "PX"), 0, "inside the dead band");
    assert_eq!(
        send(&mut sim, "JX+"),
        "?Error Moving",
        "under joystick control"
    );
    sim.set_analog_input(1, 3250);
    sim.advance(seconds(0.01));
    assert_eq!(number(&mut sim, "MSTX") & 7, 1, "speeding up, JDEL per ms");
    sim.advance(seconds(0.5));
    assert_eq!(number(&mut sim, "PSX"), 2000, "full speed at JMAX");
    assert_eq!(number(&mut sim, "MSTX") & 7, 4);
    // Past the inner soft limit it slows, at the outer one it stops.
    sim.advance(seconds(2.0));
    let x = number(&mut sim, "PX");
    assert!((3000..4000).contains(&x), "slowing between the limits: {x}");
    assert!(number(&mut sim, "PSX") < 2000);
    sim.advance(seconds(2.0));
    let x = number(&mut sim, "PX");
    assert_eq!(x, 4000, "stopped at the outer limit");
    assert_eq!(number(&mut sim, "PSX"), 0);
    // Back the other way, half deflection: about half speed.
    sim.set_analog_input(1, 10 + (1580 - 10) / 2);
    sim.advance(seconds(0.5));
    let v = number(&mut sim, "PSX");
    assert!((950..=1050).contains(&v), "{v}");
    assert!(number(&mut sim, "PX") < x);
    ok(&mut sim, &["JENA=0"]);
    sim.advance(seconds(0.1));
    assert_eq!(number(&mut sim, "PSX"), 0);
    assert_eq!(number(&mut sim, "MSTX") & 7, 0);
    ok(&mut sim, &["JX+"]);
}

/// X and Y on 2:1 drives (two motor pulses an encoder count), closed loop
/// with SLT 5, SLE 300.
fn closed_loop_xy(sim: &mut Cmd4cr) {
    for axis in [Axis::X, Axis::Y] {
        sim.motion_mut().axis_mut(axis).stage.encoder_ratio = 0.5;
    }
    ok(
        sim,
        &[
            "SLRX=2", "SLRY=2", "SLTX=5", "SLTY=5", "SLEX=300", "SLEY=300", "SLX=1", "SLY=1",
        ],
    );
}

#[test]
fn step_n_loop_interpolation_over_the_wire() {
    // §2.5.3: X1000Y500 are encoder positions (2000 and 1000 pulses); the
    // speed is HSPD in pulses/s (T2-29: "ALL interpolated moves").
    let mut sim = sim();
    ok(&mut sim, &GLOBAL_SETUP);
    closed_loop_xy(&mut sim);
    ok(&mut sim, &["X1000Y500"]);
    sim.advance(seconds(0.3));
    assert_eq!(number(&mut sim, "PSX"), 5000, "pulses/s");
    assert_eq!(number(&mut sim, "SLSX"), 1);
    assert_eq!(number(&mut sim, "SLSY"), 1);
    // Y misses 30 steps: 15 counts, corrected on its own at the end.
    sim.motion_mut().lose_steps(Axis::Y, 30);
    let mut y_corrected = false;
    for _ in 0..300 {
        sim.advance(seconds(0.01));
        y_corrected |= number(&mut sim, "SLSY") == 2;
    }
    assert!(y_corrected, "Y corrected (SLS 2)");
    assert_eq!(send(&mut sim, "EP"), "1000:500:0:0");
    assert_eq!(send(&mut sim, "PP"), "1000:500:0:0", "targets, in counts");
    assert_eq!(number(&mut sim, "SLSX"), 0);
    assert_eq!(number(&mut sim, "SLSY"), 0);
    // A circle around encoder (0, 500) comes back to encoder (1000, 500).
    ok(&mut sim, &["CIRXYN0:500"]);
    assert_eq!(number(&mut sim, "SLSX"), 1);
    wait_stopped(&mut sim, 'X', seconds(10.0));
    assert_eq!(send(&mut sim, "EP"), "1000:500:0:0");
    assert_eq!(number(&mut sim, "DX"), 0);
}

#[test]
fn step_n_loop_codes_for_stop_abort_homing_and_limits() {
    let mut sim = sim();
    ok(&mut sim, &["HSPD=20000", "SLX=1", "JX+"]);
    sim.advance(seconds(0.5));
    ok(&mut sim, &["STOPX"]);
    assert_eq!(number(&mut sim, "SLSX"), 3, "stopping");
    wait_stopped(&mut sim, 'X', seconds(5.0));
    assert_eq!(number(&mut sim, "SLSX"), 0);
    ok(&mut sim, &["JX-"]);
    sim.advance(seconds(0.1));
    ok(&mut sim, &["ABORTX"]);
    assert_eq!(number(&mut sim, "SLSX"), 4, "aborting");
    sim.advance(seconds(0.001));
    assert_eq!(number(&mut sim, "SLSX"), 0);
    for (command, code) in [("HX-0", 6), ("ZMOVEX+", 7), ("HX+6", 13)] {
        ok(&mut sim, &[command]);
        assert_eq!(number(&mut sim, "SLSX"), code, "{command}");
        wait_stopped(&mut sim, 'X', seconds(30.0));
        assert_eq!(number(&mut sim, "SLSX"), 0, "{command} done");
    }
    // A jog into the end limit: SLS 11 beside the MST limit error (mode 6
    // left its own limit flag: A.7, cleared by ERC or CLR).
    ok(&mut sim, &["CLRX", "JX+"]);
    wait_stopped(&mut sim, 'X', seconds(30.0));
    assert_eq!(number(&mut sim, "SLSX"), 11, "limit error");
    assert_eq!(send(&mut sim, "JX-"), "?Error Moving", "the MST flag");
    ok(&mut sim, &["CLRX"]);
    assert_eq!(number(&mut sim, "SLSX"), 0);
}

#[test]
fn what_step_n_loop_cannot_be_used_with() {
    let mut sim = sim();
    closed_loop_xy(&mut sim);
    // The buffer (§2.3.4): BSTART refused, nothing moves.
    ok(&mut sim, &["BO", "I100:0:0:1000"]);
    assert_eq!(send(&mut sim, "BSTART"), "?Error SNL");
    sim.advance(seconds(0.5));
    assert_eq!(send(&mut sim, "PP"), "0:0:0:0");
    ok(&mut sim, &["BF"]);
    // Latch values are "invalid" (§2.1.3.2.1): LTP keeps the raw pulse
    // counter, not P's encoder-count target.
    ok(&mut sim, &["LTX=1", "X500"]);
    wait_stopped(&mut sim, 'X', seconds(5.0));
    assert!(sim.set_digital_input(1, true));
    assert_eq!(number(&mut sim, "PX"), 500);
    assert_eq!(number(&mut sim, "LTPX"), 1000, "pulses");
    assert_eq!(number(&mut sim, "LTEX"), 500);
    // The joystick turns StepNLoop off, and keeps it off (§2.5.1).
    ok(&mut sim, &["JENA=1"]);
    assert_eq!(number(&mut sim, "SLX"), 0);
    ok(&mut sim, &["SLX=1"]);
    assert_eq!(number(&mut sim, "SLX"), 0, "still off under the joystick");
    assert_eq!(number(&mut sim, "SLSX"), 12);
    assert_eq!(number(&mut sim, "SLY"), 1, "Y is not under the joystick");
    ok(&mut sim, &["JENA=0", "SLX=1"]);
    assert_eq!(number(&mut sim, "SLX"), 1);
}

#[test]
fn under_the_joystick_stop_is_not_processed_but_estop_is() {
    let mut sim = sim();
    ok(
        &mut sim,
        &["JMAXX=3300", "JMINX=0", "JSPDX=2000", "JDELX=100"],
    );
    assert!(sim.set_analog_input(1, 3300));
    ok(&mut sim, &["JENA=1"]);
    sim.advance(seconds(0.5));
    assert_eq!(number(&mut sim, "PSX"), 2000);
    // §2.5.1.3: "invalid status", string unknown: answered like any
    // other command, and the joystick keeps the axis.
    assert_eq!(send(&mut sim, "STOP"), "OK");
    assert_eq!(send(&mut sim, "STOPX"), "OK");
    sim.advance(seconds(0.1));
    assert_eq!(number(&mut sim, "PSX"), 2000, "STOP did not stop it");
    // ESTOP does, at once, and the axis stays still with the stick out.
    ok(&mut sim, &["ESTOP"]);
    assert_eq!(number(&mut sim, "PSX"), 0);
    assert_eq!(number(&mut sim, "MSTX"), 1 << 16, "EMG error, no motion");
    let x = number(&mut sim, "PX");
    ok(&mut sim, &["CLRX"]);
    sim.advance(seconds(0.5));
    assert_eq!(number(&mut sim, "PX"), x, "held while the stick is out");
    // Back to the dead band, then out again: it moves.
    assert!(sim.set_analog_input(1, 1650));
    sim.advance(seconds(0.5));
    assert!(sim.set_analog_input(1, 3300));
    sim.advance(seconds(0.5));
    assert!(number(&mut sim, "PX") > x);
}

#[test]
fn the_help_tells_the_step_n_loop_and_joystick_choices() {
    let help = sim().help();
    for words in [
        "corrected per axis",
        "BSTART with SL on answers ?Error SNL",
        "STOP under the joystick answers like any command",
        "\"invalid status\" reply is not given",
        "ESTOP stops it",
    ] {
        assert!(help.contains(words), "{words}: {help}");
    }
}
