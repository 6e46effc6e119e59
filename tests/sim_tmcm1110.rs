//! The TMCM-1110 simulator seen from the wire: bytes in, virtual time, bytes
//! out. Frames are built by hand (manual §3.1, §3.2) so these tests depend on
//! nothing but the simulator's public interface.

use std::time::Duration;

use axterm::sim::SimulatedController;
use axterm::sim::tmcm1110::{SimConfig, Tmcm1110};
use proptest::prelude::*;

fn frame(address: u8, command: u8, kind: u8, bank: u8, value: i32) -> [u8; 9] {
    let v = value.to_be_bytes();
    let mut f = [address, command, kind, bank, v[0], v[1], v[2], v[3], 0];
    f[8] = f[..8].iter().fold(0u8, |s, b| s.wrapping_add(*b));
    f
}

/// A decoded reply: (host address, module address, status, command, value).
type Answer = (u8, u8, u8, u8, i32);

fn decode(bytes: &[u8]) -> Answer {
    assert_eq!(bytes.len(), 9, "one reply expected, got {bytes:02X?}");
    let sum = bytes[..8].iter().fold(0u8, |s, b| s.wrapping_add(*b));
    assert_eq!(sum, bytes[8], "reply checksum of {bytes:02X?}");
    (
        bytes[0],
        bytes[1],
        bytes[2],
        bytes[3],
        i32::from_be_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]),
    )
}

fn talk(sim: &mut Tmcm1110, command: u8, kind: u8, bank: u8, value: i32) -> Answer {
    sim.feed(&frame(1, command, kind, bank, value));
    decode(&sim.take_output())
}

/// Status and value of a command to module 1.
fn status_value(sim: &mut Tmcm1110, command: u8, kind: u8, bank: u8, value: i32) -> (u8, i32) {
    let (_, _, status, echoed, value) = talk(sim, command, kind, bank, value);
    assert_eq!(echoed, command, "opcode echo");
    (status, value)
}

fn new_sim() -> Tmcm1110 {
    Tmcm1110::new(SimConfig::default())
}

/// Advance in 1 ms steps, at most `limit`, until the module sends something.
fn wait_for_output(sim: &mut Tmcm1110, limit: Duration) -> Vec<u8> {
    let step = Duration::from_millis(1);
    let mut waited = Duration::ZERO;
    while waited < limit {
        sim.advance(step);
        waited += step;
        let out = sim.take_output();
        if !out.is_empty() {
            return out;
        }
    }
    Vec::new()
}

#[test]
fn every_status_code_from_the_input_that_causes_it() {
    let mut sim = new_sim();
    let mut bad = frame(1, 6, 1, 0, 0);
    bad[8] ^= 0x55;
    sim.feed(&bad);
    assert_eq!(decode(&sim.take_output()).2, 1, "wrong checksum");
    assert_eq!(status_value(&mut sim, 64, 0, 0, 0).0, 2, "UF0");
    assert_eq!(status_value(&mut sim, 6, 15, 0, 0).0, 3, "GAP 15");
    assert_eq!(status_value(&mut sim, 5, 4, 0, 5000).0, 4, "SAP 4 = 5000");
    assert_eq!(status_value(&mut sim, 9, 81, 0, 2).0, 100);
    assert_eq!(status_value(&mut sim, 132, 0, 0, 0).0, 5, "download locked");
    assert_eq!(
        status_value(&mut sim, 22, 0, 0, 0).0,
        6,
        "JA in direct mode"
    );
    // §3.5.3 Table 8: COMP is a branch command too.
    assert_eq!(
        status_value(&mut sim, 20, 0, 0, 1000).0,
        6,
        "COMP in direct mode"
    );
    assert_eq!(status_value(&mut sim, 6, 1, 0, 0), (100, 0));
}

#[test]
fn gap_gio_gco_and_calc_reply_values() {
    let mut sim = new_sim();
    assert_eq!(status_value(&mut sim, 5, 1, 0, -1234), (100, 0));
    assert_eq!(status_value(&mut sim, 6, 1, 0, 0), (100, -1234));
    assert_eq!(status_value(&mut sim, 14, 3, 2, 1), (100, 0));
    assert_eq!(status_value(&mut sim, 15, 3, 2, 0), (100, 1));
    assert_eq!(status_value(&mut sim, 30, 4, 0, 99), (100, 0));
    assert_eq!(status_value(&mut sim, 31, 4, 0, 0), (100, 99));
    assert_eq!(status_value(&mut sim, 32, 5, 0, 0), (100, -1234));
    assert_eq!(status_value(&mut sim, 19, 2, 0, -5000), (100, -5000));
    assert_eq!(status_value(&mut sim, 13, 2, 0, 0), (100, 0));
}

#[test]
fn target_reached_second_reply_after_a_move() {
    let mut sim = new_sim();
    sim.feed(&[0x01, 0x8A, 0x01, 0x00, 0x00, 0x00, 0x00, 0x01, 0x8D]);
    assert_eq!(
        sim.take_output(),
        [0x02, 0x01, 0x64, 0x8A, 0x00, 0x00, 0x00, 0x01, 0xF2]
    );
    assert_eq!(status_value(&mut sim, 4, 0, 0, 3200).0, 100);
    let out = wait_for_output(&mut sim, Duration::from_secs(600));
    assert_eq!(out, [0x02, 0x01, 0x80, 0x8A, 0x00, 0x00, 0x00, 0x01, 0x0E]);
    assert_eq!(status_value(&mut sim, 6, 1, 0, 0), (100, 3200));
}

#[test]
fn only_this_modules_address_is_answered() {
    let mut sim = new_sim();
    for address in [0, 2, 255] {
        sim.feed(&frame(address, 6, 1, 0, 0));
    }
    assert!(sim.take_output().is_empty());
    sim.feed(&frame(1, 6, 1, 0, 0));
    let (host, module, ..) = decode(&sim.take_output());
    assert_eq!((host, module), (2, 1));
}

#[test]
fn suppressed_replies_except_reads() {
    let mut sim = new_sim();
    sim.feed(&frame(1, 9, 255, 0, 1));
    sim.feed(&frame(1, 5, 4, 0, 321));
    sim.feed(&frame(1, 14, 0, 2, 1));
    assert!(sim.take_output().is_empty());
    assert_eq!(status_value(&mut sim, 6, 4, 0, 0), (100, 321));
    assert_eq!(status_value(&mut sim, 15, 0, 2, 0), (100, 1));
    assert_eq!(status_value(&mut sim, 10, 255, 0, 0), (100, 1));
}

#[test]
fn eeprom_survives_a_reset_and_a_new_simulator() {
    let dir = tempfile::tempdir().expect("temp dir");
    let config = SimConfig {
        eeprom_file: Some(dir.path().join("stepRocker.json")),
        ..SimConfig::default()
    };
    let mut sim = Tmcm1110::new(config.clone());
    assert_eq!(status_value(&mut sim, 5, 5, 0, 777).0, 100);
    assert_eq!(status_value(&mut sim, 7, 5, 0, 0).0, 100); // STAP 5
    assert_eq!(status_value(&mut sim, 9, 7, 2, 4242).0, 100);
    assert_eq!(status_value(&mut sim, 11, 7, 2, 0).0, 100); // STGP 7
    assert_eq!(status_value(&mut sim, 5, 5, 0, 1).0, 100);
    assert_eq!(status_value(&mut sim, 255, 0, 0, 1234).0, 100);
    assert_eq!(status_value(&mut sim, 6, 5, 0, 0), (100, 777));
    drop(sim);

    let mut sim = Tmcm1110::new(config);
    assert!(sim.eeprom_problem().is_none());
    assert_eq!(status_value(&mut sim, 6, 5, 0, 0), (100, 777));
    assert_eq!(status_value(&mut sim, 10, 7, 2, 0), (100, 4242));
}

#[test]
fn download_and_verify_round_trip() {
    let mut sim = new_sim();
    let program: [(u8, u8, u8, i32); 4] = [
        (5, 4, 0, 1000),  // SAP 4, 0, 1000
        (4, 0, 0, 51200), // MVP ABS, 0, 51200
        (27, 1, 0, 0),    // WAIT POS, 0, 0
        (28, 0, 0, 0),    // STOP
    ];
    assert_eq!(status_value(&mut sim, 132, 0, 0, 0), (100, 0));
    for (address, &(command, kind, bank, value)) in program.iter().enumerate() {
        assert_eq!(
            status_value(&mut sim, command, kind, bank, value),
            (101, address as i32)
        );
    }
    assert_eq!(status_value(&mut sim, 133, 0, 0, 0), (100, 0));
    for (address, &(command, kind, bank, value)) in program.iter().enumerate() {
        sim.feed(&frame(1, 134, 0, 0, address as i32));
        let out = sim.take_output();
        let v = value.to_be_bytes();
        let mut expected = [2, command, kind, bank, v[0], v[1], v[2], v[3], 0];
        expected[8] = expected[..8].iter().fold(0u8, |s, b| s.wrapping_add(*b));
        assert_eq!(out, expected, "address {address}");
    }
    // 135 type 0: status stopped (byte 3), not waiting (byte 2), pointer 4.
    assert_eq!(status_value(&mut sim, 135, 0, 0, 0), (100, 4));
    // Nothing was executed.
    assert_eq!(status_value(&mut sim, 6, 4, 0, 0).0, 100);
    assert_eq!(status_value(&mut sim, 6, 0, 0, 0), (100, 0));
}

#[test]
fn factory_reset_sends_nothing() {
    let mut sim = new_sim();
    assert_eq!(status_value(&mut sim, 9, 76, 0, 7).0, 100);
    sim.feed(&frame(1, 137, 0, 0, 1234));
    assert!(sim.take_output().is_empty());
    sim.advance(Duration::from_millis(100));
    assert!(sim.take_output().is_empty());
    assert_eq!(talk(&mut sim, 10, 76, 0, 0).0, 2, "host address back to 2");
}

#[test]
fn split_and_garbage_input_resynchronises_after_silence() {
    let mut sim = new_sim();
    let request = frame(1, 6, 1, 0, 0);
    sim.feed(&request[..2]);
    sim.feed(&request[2..7]);
    sim.feed(&request[7..]);
    assert_eq!(decode(&sim.take_output()).2, 100);

    // Line noise: three stray bytes shift the frame boundaries...
    sim.feed(&[0xAA, 0x01, 0x55]);
    sim.advance(Duration::from_millis(20));
    // ...until a pause lets the module start afresh.
    sim.feed(&request);
    assert_eq!(decode(&sim.take_output()).2, 100);

    // Without the pause the frame is cut wrongly and gets no valid answer.
    sim.feed(&[0x01, 0x02]);
    sim.feed(&request);
    let out = sim.take_output();
    assert!(out.is_empty() || out.get(2) == Some(&1), "{out:02X?}");
    sim.advance(Duration::from_millis(20));
    sim.feed(&request);
    assert_eq!(decode(&sim.take_output()).2, 100);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Arbitrary bytes, split anywhere, with arbitrary pauses: no panic, and
    /// everything sent is whole 9-byte frames.
    #[test]
    fn arbitrary_bytes_never_panic(
        chunks in prop::collection::vec(
            (prop::collection::vec(any::<u8>(), 0..40), 0u64..50),
            0..40,
        )
    ) {
        let mut sim = new_sim();
        for (bytes, pause) in chunks {
            sim.feed(&bytes);
            sim.advance(Duration::from_millis(pause));
            prop_assert_eq!(sim.take_output().len() % 9, 0);
        }
    }

    /// Well-formed frames to this module with any opcode, type, bank and
    /// value: no panic, at most one reply each, a status from the manual.
    #[test]
    fn arbitrary_commands_never_panic(
        commands in prop::collection::vec(
            (any::<u8>(), any::<u8>(), any::<u8>(), any::<i32>(), 0u64..20),
            0..60,
        )
    ) {
        let mut sim = new_sim();
        for (command, kind, bank, value, pause) in commands {
            sim.feed(&frame(1, command, kind, bank, value));
            let out = sim.take_output();
            prop_assert!(out.len() <= 9, "{:02X?}", out);
            if out.len() == 9 && !matches!(command, 134 | 136) {
                let (_, _, status, echoed, _) = decode(&out);
                prop_assert!(matches!(status, 1..=6 | 100 | 101), "status {}", status);
                prop_assert_eq!(echoed, command);
            }
            sim.advance(Duration::from_millis(pause));
            prop_assert_eq!(sim.take_output().len() % 9, 0);
        }
    }
}

// ---- motion seen from the wire ------------------------------------------------

const SAP: u8 = 5;
const GAP: u8 = 6;
const MVP: u8 = 4;
const ROR: u8 = 1;
const RFS: u8 = 13;
const TARGET_EVENT: u8 = 138;

/// Advance in 1 ms ticks (the simulator's tick) until `done`, at most
/// `limit` ticks; returns the number of ticks taken.
fn ticks_until(sim: &mut Tmcm1110, limit: u32, mut done: impl FnMut(&mut Tmcm1110) -> bool) -> u32 {
    for tick in 1..=limit {
        sim.advance(Duration::from_millis(1));
        if done(sim) {
            return tick;
        }
    }
    panic!("condition not reached within {limit} ticks");
}

fn gap(sim: &mut Tmcm1110, param: u8) -> i32 {
    let (status, value) = status_value(sim, GAP, param, 0, 0);
    assert_eq!(status, 100, "GAP {param}");
    value
}

fn sap(sim: &mut Tmcm1110, param: u8, value: i32) {
    assert_eq!(
        status_value(sim, SAP, param, 0, value).0,
        100,
        "SAP {param}, 0, {value}"
    );
}

/// §6.1 formulas: speed and acceleration in microsteps/s and /s².
fn real_units(speed: i32, accel: i32, ramp_div: u32, pulse_div: u32) -> (f64, f64) {
    let v = 16.0e6 * f64::from(speed) / (2f64.powi(pulse_div as i32) * 2048.0 * 32.0);
    let a = 16.0e6f64.powi(2) * f64::from(accel) / 2f64.powi((ramp_div + pulse_div + 29) as i32);
    (v, a)
}

/// Time of a point-to-point move of `distance` µsteps: trapezoid when the
/// ramp reaches `v`, triangle otherwise.
fn ramp_time(distance: f64, v: f64, a: f64) -> f64 {
    if distance >= v * v / a {
        v / a + distance / v
    } else {
        2.0 * (distance / a).sqrt()
    }
}

fn check_move_time(speed: i32, accel: i32, ramp_div: u8, pulse_div: u8) {
    let mut sim = new_sim();
    sap(&mut sim, 153, i32::from(ramp_div));
    sap(&mut sim, 154, i32::from(pulse_div));
    sap(&mut sim, 4, speed);
    sap(&mut sim, 5, accel);
    assert_eq!(status_value(&mut sim, TARGET_EVENT, 0, 0, 1), (100, 1));
    assert_eq!(status_value(&mut sim, MVP, 0, 0, 51200).0, 100);
    assert_eq!(gap(&mut sim, 8), 0, "not reached at the start");

    let (v, a) = real_units(speed, accel, u32::from(ramp_div), u32::from(pulse_div));
    let expected_ms = ramp_time(51200.0, v, a) * 1000.0;
    let mut reply_tick = None;
    let taken = ticks_until(&mut sim, 600_000, |sim| {
        let out = sim.take_output();
        if !out.is_empty() {
            assert_eq!(decode(&out).2, 128, "the 138 second reply");
            reply_tick.get_or_insert(());
        }
        let reached = gap(sim, 8) == 1;
        if !reached {
            assert!(gap(sim, 3).abs() <= speed, "speed never above AP4");
        }
        reached
    });
    assert!(
        (f64::from(taken) - expected_ms).abs() <= 1.0,
        "reached after {taken} ms, the ramp formulas say {expected_ms:.3} ms"
    );
    assert_eq!(gap(&mut sim, 1), 51200, "lands exactly on the target");
    assert_eq!(gap(&mut sim, 3), 0);
    let late = sim.take_output();
    assert!(
        reply_tick.is_some() || !late.is_empty(),
        "138 reported the arrival"
    );
}

#[test]
fn a_trapezoid_move_to_51200_takes_the_time_of_the_ramp_formulas() {
    // Defaults' divisors (the §6.1 examples): 30518 pps, 46566 pps².
    check_move_time(1000, 100, 7, 3);
    check_move_time(2047, 1000, 9, 4);
}

#[test]
fn a_triangle_move_to_51200_takes_the_time_of_the_ramp_formulas() {
    // Too short to reach top speed: 2·√(d/a).
    check_move_time(2047, 10, 7, 3);
}

#[test]
fn the_right_limit_switch_stops_the_axis() {
    let mut sim = new_sim();
    let limit = sim
        .switch_layout_mut()
        .right_limit
        .expect("the demo stage has a right limit");
    sap(&mut sim, 5, 2047);
    assert_eq!(status_value(&mut sim, ROR, 0, 0, 2000).0, 100);
    ticks_until(&mut sim, 600_000, |sim| gap(sim, 10) == 1);
    assert_eq!(gap(&mut sim, 3), 0, "hard stop at the switch (AP149 = 0)");
    let position = i64::from(gap(&mut sim, 1));
    assert_eq!(position, limit, "stopped where the switch closes");
    sim.advance(Duration::from_secs(1));
    assert_eq!(i64::from(gap(&mut sim, 1)), limit, "and stays there");

    // Disabled (AP12 = 1), the same switch no longer stops it.
    sap(&mut sim, 12, 1);
    assert_eq!(status_value(&mut sim, ROR, 0, 0, 2000).0, 100);
    sim.advance(Duration::from_millis(500));
    assert!(i64::from(gap(&mut sim, 1)) > limit);
}

#[test]
fn reference_search_mode_1_zeroes_at_the_left_switch_and_65_at_the_right() {
    for (mode, expect_left) in [(1, true), (65, false)] {
        let mut sim = new_sim();
        let layout = sim.switch_layout_mut().clone();
        sap(&mut sim, 193, mode);
        sap(&mut sim, 194, 2000);
        sap(&mut sim, 195, 500);
        assert_eq!(status_value(&mut sim, RFS, 0, 0, 0).0, 100, "RFS START");
        assert_ne!(status_value(&mut sim, RFS, 2, 0, 0).1, 0, "active");
        ticks_until(&mut sim, 600_000, |sim| {
            status_value(sim, RFS, 2, 0, 0).1 == 0
        });
        assert_eq!(gap(&mut sim, 1), 0, "counter zeroed at the reference");
        assert_eq!(gap(&mut sim, 3), 0, "at standstill");
        // AP197 holds the old counter there: the switch's place in the
        // coordinates the module started with.
        let switch_at = if expect_left {
            layout.left_limit
        } else {
            layout.right_limit
        };
        let old_counter = i64::from(gap(&mut sim, 197));
        assert!(
            (old_counter - switch_at.expect("switch")).abs() <= 1,
            "mode {mode}: reference at {old_counter}, switch at {switch_at:?}"
        );
    }
}
