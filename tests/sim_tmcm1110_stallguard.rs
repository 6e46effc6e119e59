//! The TMCM-1110 simulator's StallGuard2 and CoolStep (§1.1, §4, §7.2,
//! §7.3) seen from the wire, on virtual time: the load reading AP206 under
//! `LOAD=`, AP208 bit 0, the stop on stall above AP181, and CoolStep's
//! current AP180 between its limits.

use std::time::Duration;

use axterm::sim::SimulatedController;
use axterm::sim::tmcm1110::motion::SwitchLayout;
use axterm::sim::tmcm1110::{SimConfig, Tmcm1110};

const ROR: u8 = 1;
const SAP: u8 = 5;
const GAP: u8 = 6;

fn frame(command: u8, kind: u8, value: i32) -> [u8; 9] {
    let v = value.to_be_bytes();
    let mut f = [1, command, kind, 0, v[0], v[1], v[2], v[3], 0];
    f[8] = f[..8].iter().fold(0u8, |s, b| s.wrapping_add(*b));
    f
}

/// Status and value of a command to module 1, motor 0.
fn talk(sim: &mut Tmcm1110, command: u8, kind: u8, value: i32) -> (u8, i32) {
    sim.feed(&frame(command, kind, value));
    let out = sim.take_output();
    assert_eq!(out.len(), 9, "one reply expected, got {out:02X?}");
    (out[2], i32::from_be_bytes([out[4], out[5], out[6], out[7]]))
}

fn sap(sim: &mut Tmcm1110, param: u8, value: i32) {
    assert_eq!(
        talk(sim, SAP, param, value).0,
        100,
        "SAP {param}, 0, {value}"
    );
}

fn gap(sim: &mut Tmcm1110, param: u8) -> i32 {
    let (status, value) = talk(sim, GAP, param, 0);
    assert_eq!(status, 100, "GAP {param}");
    value
}

fn ror(sim: &mut Tmcm1110, velocity: i32) {
    assert_eq!(talk(sim, ROR, 0, velocity).0, 100, "ROR 0, {velocity}");
}

fn load(sim: &mut Tmcm1110, percent: u8) {
    SimulatedController::drive_input(sim, &format!("LOAD={percent}")).expect("LOAD");
}

fn wait(sim: &mut Tmcm1110, ms: u64) {
    SimulatedController::advance(sim, Duration::from_millis(ms));
}

/// The motor turning at `velocity` (AP3 shows it) with `percent` load.
fn running(velocity: i32, percent: u8) -> Tmcm1110 {
    let mut sim = Tmcm1110::new(SimConfig::default());
    load(&mut sim, percent);
    ror(&mut sim, velocity);
    // The default ramp (AP5 100, divisors 7/3) reaches 1000 in 0.66 s.
    wait(&mut sim, 2000);
    assert_eq!(gap(&mut sim, 3), velocity, "speed reached");
    sim
}

/// §3.1: a frame is address, command, type, motor/bank, value (4 bytes, MSB
/// first) and a checksum, the sum of the first 8 bytes modulo 256. Every
/// frame and checksum here is written out by hand.
#[test]
fn hand_written_frames_read_the_load() {
    let mut sim = Tmcm1110::new(SimConfig::default());
    // ROR 0, 1000: 01 01 00 00 00 00 03 E8; 1+1+3+0xE8 = 0xED, the
    // manual's own example (§3.6.1).
    let ror_1000 = [0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x03, 0xE8, 0xED];
    // GAP 206, 0: 01 06 CE 00 00 00 00 00; 1+6+0xCE = 0xD5.
    let gap_206 = [0x01, 0x06, 0xCE, 0x00, 0x00, 0x00, 0x00, 0x00, 0xD5];

    sim.set_load_percent(0);
    sim.feed(&ror_1000);
    // Reply: host 2, module 1, status 100 (0x64), command 1; the value is
    // "don't care" (§3.6.1).
    let reply = sim.take_output();
    assert_eq!(reply.len(), 9);
    assert_eq!(reply[..4], [0x02, 0x01, 0x64, 0x01]);
    SimulatedController::advance(&mut sim, Duration::from_secs(2));
    sim.feed(&gap_206);
    // Unloaded at 1000: 1000 / 2 = 500 = 0x01F4;
    // 2+1+0x64+6+1+0xF4 = 0x162 → 0x62.
    assert_eq!(
        sim.take_output(),
        [0x02, 0x01, 0x64, 0x06, 0x00, 0x00, 0x01, 0xF4, 0x62]
    );
    sim.set_load_percent(60);
    SimulatedController::advance(&mut sim, Duration::from_millis(10));
    sim.feed(&gap_206);
    // 60 % load: 500 × 0.4 = 200 = 0xC8; 2+1+0x64+6+0xC8 = 0x135 → 0x35.
    assert_eq!(
        sim.take_output(),
        [0x02, 0x01, 0x64, 0x06, 0x00, 0x00, 0x00, 0xC8, 0x35]
    );
}

#[test]
fn load_lowers_the_reading_at_the_same_speed_and_speed_raises_it() {
    let unloaded = gap(&mut running(1000, 0), 206);
    let loaded = gap(&mut running(1000, 60), 206);
    assert!(loaded < unloaded, "{loaded} vs {unloaded}");
    assert_eq!((unloaded, loaded), (500, 200), "linear in load");
    assert_eq!(gap(&mut running(1000, 30), 206), 350, "halfway");
    assert_eq!(gap(&mut running(500, 60), 206), 100, "slower reads lower");
}

#[test]
fn a_stalled_motor_reads_0_and_sets_the_stallguard_flag() {
    let mut sim = running(1000, 100);
    assert_eq!(gap(&mut sim, 206), 0);
    assert_eq!(gap(&mut sim, 208) & 1, 1, "AP208 bit 0: threshold reached");
    // AP181 = 0: no stop on stall, the motor is still driven.
    assert_eq!(gap(&mut sim, 3), 1000);
    // Unloaded, no flag.
    let mut free = running(1000, 0);
    assert_eq!(gap(&mut free, 208) & 1, 0);
}

#[test]
fn the_flag_rises_when_the_reading_falls_below_the_ap174_threshold() {
    // 60 % at 1000 reads 200 unshifted; AP174 moves the readout by 16 a
    // step: −12 leaves 8 (above the threshold), −13 reaches 0.
    let mut sim = running(1000, 60);
    sap(&mut sim, 174, -12);
    wait(&mut sim, 5);
    assert_eq!((gap(&mut sim, 206), gap(&mut sim, 208) & 1), (8, 0));
    sap(&mut sim, 174, -13);
    wait(&mut sim, 5);
    assert_eq!((gap(&mut sim, 206), gap(&mut sim, 208) & 1), (0, 1));
    // Lower is more sensitive: the same threshold flags nothing unloaded.
    load(&mut sim, 0);
    wait(&mut sim, 5);
    assert_eq!((gap(&mut sim, 206), gap(&mut sim, 208) & 1), (292, 0));
}

#[test]
fn a_stall_stops_the_motor_above_ap181_only() {
    // Below the AP181 speed: a stall reads 0 but the motor is not stopped.
    let mut sim = Tmcm1110::new(SimConfig::default());
    sap(&mut sim, 181, 800);
    load(&mut sim, 100);
    ror(&mut sim, 500);
    wait(&mut sim, 2000);
    assert_eq!(gap(&mut sim, 3), 500);
    assert_eq!(gap(&mut sim, 207), 0, "no StallGuard error");

    // Above it the motor stops, AP207 bit 0 says why.
    ror(&mut sim, 1000);
    wait(&mut sim, 2000);
    assert_eq!(gap(&mut sim, 3), 0);
    assert_eq!(gap(&mut sim, 207) & 1, 1);
    // At standstill AP206 keeps the last reading; no measurement, no flag.
    assert_eq!((gap(&mut sim, 206), gap(&mut sim, 208) & 1), (0, 0));

    // Above AP181 without a stall it turns on.
    let mut free = Tmcm1110::new(SimConfig::default());
    sap(&mut free, 181, 800);
    load(&mut free, 90);
    ror(&mut free, 1000);
    wait(&mut free, 2000);
    assert_eq!((gap(&mut free, 3), gap(&mut free, 206)), (1000, 50));
    assert_eq!(gap(&mut free, 207), 0);
}

#[test]
fn coolstep_raises_the_current_under_load_and_lowers_it_unloaded_within_limits() {
    let mut sim = Tmcm1110::new(SimConfig::default());
    // AP6 128 = current scale 16; SEIMIN 0: at least 8. Lower threshold
    // 32 × 2 = 64, upper 64 + 32 × (3 + 1) = 192; up 1, down every reading.
    assert_eq!(gap(&mut sim, 6), 128);
    for (param, value) in [(168, 0), (169, 3), (170, 3), (171, 0), (172, 2)] {
        sap(&mut sim, param, value);
    }
    assert_eq!(gap(&mut sim, 180), 16, "at standstill: the AP6 current");
    ror(&mut sim, 1000);
    wait(&mut sim, 2000);
    // Unloaded: 500 is above the upper threshold, the current falls to the
    // minimum and stays there.
    assert_eq!(gap(&mut sim, 180), 8);
    assert_eq!(gap(&mut sim, 206), 500);

    // 60 % of the AP6 torque is 113 % of the torque at scale 8: a stall,
    // reading 0, below the lower threshold: the current rises, until at 11
    // (60 % × 17/12 = 85 %, reading 75) it sits between the thresholds.
    load(&mut sim, 60);
    let mut seen = Vec::new();
    for _ in 0..50 {
        wait(&mut sim, 1);
        seen.push(gap(&mut sim, 180));
    }
    assert!(seen.windows(2).all(|w| w[0] <= w[1]), "rising: {seen:?}");
    assert_eq!(*seen.last().unwrap(), 11, "{seen:?}");
    assert_eq!(gap(&mut sim, 206), 75);

    // More load than the AP6 current carries: the current rises to AP6's
    // and no further.
    load(&mut sim, 100);
    wait(&mut sim, 100);
    assert_eq!((gap(&mut sim, 180), gap(&mut sim, 206)), (16, 0));

    // Unloaded again: back down to the minimum.
    load(&mut sim, 0);
    wait(&mut sim, 100);
    assert_eq!(gap(&mut sim, 180), 8);

    // SEIMIN 1: a quarter.
    sap(&mut sim, 168, 1);
    wait(&mut sim, 100);
    assert_eq!(gap(&mut sim, 180), 4);

    // AP172 = 0 turns CoolStep off: the AP6 current.
    sap(&mut sim, 172, 0);
    wait(&mut sim, 5);
    assert_eq!(gap(&mut sim, 180), 16);
}

#[test]
fn below_the_coolstep_speed_the_slow_run_current_applies() {
    let mut sim = Tmcm1110::new(SimConfig::default());
    sap(&mut sim, 172, 2);
    sap(&mut sim, 182, 1500);
    sap(&mut sim, 183, 64);
    ror(&mut sim, 1000);
    wait(&mut sim, 2000);
    assert_eq!(gap(&mut sim, 180), 8, "AP183 64 = scale 8");
    // 40 % of the AP6 torque at half the current: 40 % × 17/9 = 76 %.
    load(&mut sim, 40);
    wait(&mut sim, 5);
    assert_eq!(gap(&mut sim, 206), 122);
    // AP180 is a status value.
    assert_eq!(talk(&mut sim, SAP, 180, 3).0, 3, "read-only: status 3");
}

#[test]
fn load_settings_are_checked() {
    let mut sim = Tmcm1110::new(SimConfig::default());
    let said = SimulatedController::drive_input(&mut sim, "LOAD=100").unwrap();
    assert_eq!(
        said,
        "LOAD 100 % of the torque at the AP6 current: the motor stalls"
    );
    let e = SimulatedController::drive_input(&mut sim, "LOAD=101").unwrap_err();
    assert!(e.starts_with("LOAD takes a whole number of"), "{e}");
    assert!(
        sim.help()
            .contains("LOAD=<% of the torque at the AP6 current 0..100>")
    );
    assert!(
        sim.help()
            .contains("StallGuard2 AP206 = |AP3|/2 × (1 − load) + 16 × AP174")
    );
}

#[test]
fn a_threshold_below_zero_stops_the_motor_before_it_stalls() {
    // 60 % load reads 0.2 × |AP3|, never 0 on the way to 1000: AP174 0 and
    // AP181 500 let it turn.
    let mut sim = Tmcm1110::new(SimConfig::default());
    sap(&mut sim, 181, 500);
    load(&mut sim, 60);
    ror(&mut sim, 1000);
    wait(&mut sim, 2000);
    assert_eq!(gap(&mut sim, 3), 1000);
    // AP174 −13 takes 208 off: 0 at every speed up to 1000, and the stop on
    // stall acts on that reading.
    sap(&mut sim, 174, -13);
    wait(&mut sim, 5);
    assert_eq!(gap(&mut sim, 3), 0, "stopped");
    assert_eq!(gap(&mut sim, 207) & 1, 1);
}

mod tuning {
    //! The pure tuning plans carried out against the simulator by a small
    //! driver of the test's own: sweep without and with load, suggest,
    //! apply, and the suggestion stops the loaded motor and not the free one.
    use super::*;
    use axterm::protocol::tmcl::tune::{
        Direction, SpeedReadings, SuggestRules, SweepInstruction, SweepPlan, SweepSpec,
        speed_reached, suggest,
    };
    use axterm::protocol::tmcl::{Command, Reply};

    fn send(sim: &mut Tmcm1110, command: Command) -> i32 {
        sim.feed(&command.to_request(1).to_bytes());
        let out = sim.take_output();
        let bytes: [u8; 9] = out.as_slice().try_into().expect("one reply");
        let reply = Reply::from_bytes(&bytes).expect("a reply");
        assert_eq!(reply.status.0, 100, "{command:?}");
        reply.value
    }

    /// Readings per speed of one sweep.
    fn sweep(sim: &mut Tmcm1110, plan: &SweepPlan) -> Vec<Vec<i32>> {
        let mut readings = vec![Vec::new(); plan.points.len()];
        for step in plan.instructions() {
            match step {
                SweepInstruction::Send(command) => {
                    send(sim, command);
                }
                SweepInstruction::WaitForSpeed { poll, speed } => {
                    let mut polls = 0;
                    while !speed_reached(send(sim, poll), speed) {
                        polls += 1;
                        assert!(polls < 1000, "speed {speed} not reached");
                        wait(sim, 10);
                    }
                }
                SweepInstruction::Sample { point, read, .. } => {
                    wait(sim, 5);
                    readings[point].push(send(sim, read));
                }
            }
        }
        wait(sim, 2000);
        assert_eq!(gap(sim, 3), 0, "the sweep ends with the motor stopped");
        readings
    }

    #[test]
    fn a_suggestion_from_two_sweeps_stops_the_loaded_motor_only() {
        let plan = SweepPlan::new(&SweepSpec {
            motor: 0,
            direction: Direction::Right,
            from: 200,
            to: 1200,
            steps: 6,
            samples: 3,
        })
        .unwrap();
        let mut sim = Tmcm1110::new(SimConfig::default());
        // A machine without end switches: the sweeps turn for many turns.
        *sim.switch_layout_mut() = SwitchLayout::default();
        let free = sweep(&mut sim, &plan);
        load(&mut sim, 60);
        let loaded = sweep(&mut sim, &plan);
        let readings: Vec<SpeedReadings> = plan
            .velocities()
            .into_iter()
            .zip(free.into_iter().zip(loaded))
            .map(|(velocity, (unloaded, loaded))| SpeedReadings {
                velocity,
                unloaded,
                loaded,
            })
            .collect();
        let s = suggest(&readings, &SuggestRules::default());
        let (Some(threshold), Some(speed)) = (s.threshold, s.stop_on_stall_speed) else {
            panic!("no suggestion: {:?}", s.reasons);
        };
        for command in s.commands(0) {
            send(&mut sim, command);
        }
        assert_eq!(gap(&mut sim, 174), threshold);
        assert_eq!(gap(&mut sim, 181), speed);
        // Loaded at the top speed: stopped.
        ror(&mut sim, 1200);
        wait(&mut sim, 3000);
        assert_eq!(gap(&mut sim, 3), 0, "{:?}", s.reasons);
        assert_eq!(gap(&mut sim, 207) & 1, 1);
        // Unloaded: it turns at every speed of the working range.
        load(&mut sim, 0);
        for v in plan.velocities().into_iter().filter(|v| *v >= speed) {
            ror(&mut sim, v);
            wait(&mut sim, 3000);
            assert_eq!(gap(&mut sim, 3), v, "{:?}", s.reasons);
        }
    }
}

/// After a plain stop (MST, §3.6.3: the motor ramps down) AP206 keeps the
/// reading of the run's top speed, not the ramp's last one near 0: a
/// standing motor does not look stalled.
#[test]
fn a_ramped_stop_keeps_the_top_speeds_reading() {
    const MST: u8 = 3;
    let mut sim = running(1000, 0);
    assert_eq!(gap(&mut sim, 206), 500);
    assert_eq!(talk(&mut sim, MST, 0, 0).0, 100, "MST 0");
    wait(&mut sim, 2000);
    assert_eq!(gap(&mut sim, 3), 0, "standing");
    assert_eq!(gap(&mut sim, 206), 500);
}
