//! Stored TMCL programs on the TMCM-1110 simulator, seen from the wire: the
//! programs are downloaded as frames (132, the commands, 133) and run with
//! 129/130, as the TMCL-IDE does (manual §3.6.53). Frames are built by hand
//! (§3.1), so nothing but the simulator's public interface is involved.

use std::time::Duration;

use axterm::sim::SimulatedController;
use axterm::sim::tmcm1110::motion::SwitchLayout;
use axterm::sim::tmcm1110::{SimConfig, Tmcm1110};

/// One command: instruction, type, motor/bank, value.
type Line = (u8, u8, u8, i32);

fn frame(command: u8, kind: u8, bank: u8, value: i32) -> [u8; 9] {
    let v = value.to_be_bytes();
    let mut f = [1, command, kind, bank, v[0], v[1], v[2], v[3], 0];
    f[8] = f[..8].iter().fold(0u8, |s, b| s.wrapping_add(*b));
    f
}

/// Send one command to module 1; its (status, value).
fn talk(sim: &mut Tmcm1110, (command, kind, bank, value): Line) -> (u8, i32) {
    sim.feed(&frame(command, kind, bank, value));
    let out = sim.take_output();
    assert_eq!(out.len(), 9, "one reply to {command}, got {out:02X?}");
    let sum = out[..8].iter().fold(0u8, |s, b| s.wrapping_add(*b));
    assert_eq!(sum, out[8], "reply checksum");
    assert_eq!(out[3], command, "opcode echo");
    (out[2], i32::from_be_bytes([out[4], out[5], out[6], out[7]]))
}

/// A command that must succeed; its reply value.
fn ok(sim: &mut Tmcm1110, line: Line) -> i32 {
    let (status, value) = talk(sim, line);
    assert_eq!(status, 100, "{line:?}");
    value
}

/// 132, every command (each answered 101), 133 (§3.6.53).
fn download(sim: &mut Tmcm1110, program: &[Line]) {
    ok(sim, (132, 0, 0, 0));
    for (address, &line) in program.iter().enumerate() {
        assert_eq!(talk(sim, line), (101, address as i32), "storing {line:?}");
    }
    ok(sim, (133, 0, 0, 0));
}

fn gap(sim: &mut Tmcm1110, param: u8) -> i32 {
    ok(sim, (6, param, 0, 0))
}

fn ggp(sim: &mut Tmcm1110, param: u8, bank: u8) -> i32 {
    ok(sim, (10, param, bank, 0))
}

fn output(sim: &mut Tmcm1110, port: u8) -> i32 {
    ok(sim, (15, port, 2, 0))
}

fn quiet_sim() -> Tmcm1110 {
    let mut sim = Tmcm1110::new(SimConfig::default());
    *sim.switch_layout_mut() = SwitchLayout::default();
    sim
}

fn secs(n: u64) -> Duration {
    Duration::from_secs(n)
}

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// Advance a second at a time until the target position (AP0) is
/// `target`; the seconds it took.
fn seconds_until_target(sim: &mut Tmcm1110, target: i32, limit: u64) -> u64 {
    for second in 1..=limit {
        sim.advance(secs(1));
        if gap(sim, 0) == target {
            return second;
        }
    }
    panic!("target still {} after {limit} s", gap(sim, 0));
}

/// §2.4: rotate left for 5 s, right for 5 s, then move between ±512000 for
/// ever. The motion is watched from the host while the program runs.
#[test]
fn the_example_program_of_2_4_moves_the_motor_back_and_forth() {
    let mut sim = quiet_sim();
    download(
        &mut sim,
        &[
            (2, 0, 0, 1000),     // ROL 0, 1000
            (27, 0, 0, 500),     // WAIT TICKS, 0, 500
            (3, 0, 0, 0),        // MST 0
            (1, 0, 0, 100),      // ROR 0, 100
            (27, 0, 0, 500),     // WAIT TICKS, 0, 500
            (3, 0, 0, 0),        // MST 0
            (5, 4, 0, 100),      // SAP 4, 0, 100
            (5, 5, 0, 100),      // SAP 5, 0, 100
            (4, 0, 0, 512_000),  // Loop: MVP ABS, 0, 512000
            (27, 1, 0, 0),       // WAIT POS, 0, 0
            (4, 0, 0, -512_000), // MVP ABS, 0, -512000
            (27, 1, 0, 0),       // WAIT POS, 0, 0
            (22, 0, 0, 8),       // JA Loop
        ],
    );
    ok(&mut sim, (129, 0, 0, 0));

    sim.advance(secs(2));
    assert_eq!(gap(&mut sim, 3), -1000, "rotating left at full speed");
    let left = gap(&mut sim, 1);
    assert!(left < -30_000, "{left}");
    sim.advance(secs(5));
    assert_eq!(gap(&mut sim, 3), 100, "rotating right after 5 s");
    let turning_point = gap(&mut sim, 1);
    sim.advance(secs(2));
    assert!(gap(&mut sim, 1) > turning_point);

    sim.advance(secs(2));
    assert_eq!(gap(&mut sim, 0), 512_000, "the loop's first MVP");
    assert_eq!(gap(&mut sim, 4), 100, "SAP 4 executed");
    // About 650000 µsteps at 100 [int] = 3052 µsteps/s: some 213 s. The
    // program's next MVP follows the arrival within milliseconds, so the
    // motor is seen within a second's travel of 512000, heading back.
    let out = seconds_until_target(&mut sim, -512_000, 300);
    assert!((200..240).contains(&out), "arrived after {out} s");
    assert!((508_900..512_000).contains(&gap(&mut sim, 1)));
    assert_eq!(gap(&mut sim, 3), -100);
    let back = seconds_until_target(&mut sim, 512_000, 400);
    assert!((320..350).contains(&back), "returned after {back} s");
    assert!((-512_000..-508_900).contains(&gap(&mut sim, 1)), "JA Loop");
    assert_eq!(ggp(&mut sim, 128, 0), 1, "still running");
}

#[test]
fn single_step_advances_the_pc_one_command() {
    let mut sim = quiet_sim();
    download(
        &mut sim,
        &[
            (5, 4, 0, 500),  // SAP 4, 0, 500
            (4, 0, 0, 1000), // MVP ABS, 0, 1000
            (22, 0, 0, 0),   // JA 0
        ],
    );
    for (pc, ap4, ap0) in [(1, 500, 0), (2, 500, 1000), (0, 500, 1000)] {
        ok(&mut sim, (130, 0, 0, 0));
        sim.advance(ms(1));
        assert_eq!(ggp(&mut sim, 130, 0), pc);
        assert_eq!(ok(&mut sim, (135, 1, 0, 0)), pc, "135 type 1: stopped, PC");
        assert_eq!((gap(&mut sim, 4), gap(&mut sim, 0)), (ap4, ap0));
    }
}

/// §3.5.6.4: the main loop toggles output 3 every 500 ms with WAITs, the
/// timer 0 interrupt toggles OUT0 (port 0) every 1000 ms.
#[test]
fn the_timer_interrupt_example_of_3_5_6_4_toggles_both_outputs() {
    let mut sim = quiet_sim();
    download(
        &mut sim,
        &[
            (37, 0, 0, 9),   // VECT 0, Timer0Irq
            (9, 0, 3, 1000), // SGP 0, 3, 1000
            (25, 0, 0, 0),   // EI 0
            (25, 255, 0, 0), // EI 255
            (14, 3, 2, 1),   // Loop: SIO 3, 2, 1
            (27, 0, 0, 50),  // WAIT TICKS, 0, 50
            (14, 3, 2, 0),   // SIO 3, 2, 0
            (27, 0, 0, 50),  // WAIT TICKS, 0, 50
            (22, 0, 0, 4),   // JA Loop
            (15, 0, 2, 0),   // Timer0Irq: GIO 0, 2
            (21, 1, 0, 13),  // JC NZ, Out0Off
            (14, 0, 2, 1),   // SIO 0, 2, 1
            (38, 0, 0, 0),   // RETI
            (14, 0, 2, 0),   // Out0Off: SIO 0, 2, 0
            (38, 0, 0, 0),   // RETI
        ],
    );
    ok(&mut sim, (129, 0, 0, 0));
    let mut seen = Vec::new();
    let mut at = 0;
    for sample in [300, 700, 1200, 1700, 2200, 2700, 3200] {
        sim.advance(ms(sample - at));
        at = sample;
        seen.push((output(&mut sim, 0), output(&mut sim, 3)));
    }
    assert_eq!(
        seen,
        [(0, 1), (0, 0), (1, 1), (1, 0), (0, 1), (0, 0), (1, 1)]
    );
}

/// §8.6: a host starts routines through a jump table with 129 type 1.
#[test]
fn the_jump_table_of_8_6_starts_routines_by_address() {
    let mut sim = quiet_sim();
    download(
        &mut sim,
        &[
            (22, 0, 0, 3),   // Func1: JA Func1Start
            (22, 0, 0, 8),   // Func2: JA Func2Start
            (22, 0, 0, 12),  // Func3: JA Func3Start
            (4, 0, 0, 1000), // Func1Start: MVP ABS, 0, 1000
            (27, 1, 0, 0),   // WAIT POS, 0, 0
            (4, 0, 0, 0),    // MVP ABS, 0, 0
            (27, 1, 0, 0),   // WAIT POS, 0, 0
            (28, 0, 0, 0),   // STOP
            (2, 0, 0, 500),  // Func2Start: ROL 0, 500
            (27, 0, 0, 100), // WAIT TICKS, 0, 100
            (3, 0, 0, 0),    // MST 0
            (28, 0, 0, 0),   // STOP
            (1, 0, 0, 1000), // Func3Start: ROR 0, 1000
            (27, 0, 0, 700), // WAIT TICKS, 0, 700
            (3, 0, 0, 0),    // MST 0
            (28, 0, 0, 0),   // STOP
        ],
    );
    ok(&mut sim, (129, 1, 0, 1));
    sim.advance(ms(500));
    assert_eq!(gap(&mut sim, 2), -500, "Func2 rotates left");
    sim.advance(ms(600));
    assert_eq!((ggp(&mut sim, 128, 0), ggp(&mut sim, 130, 0)), (0, 11));
    assert!(gap(&mut sim, 1) < 0);

    ok(&mut sim, (129, 1, 0, 0));
    sim.advance(secs(5));
    assert_eq!((ggp(&mut sim, 128, 0), ggp(&mut sim, 130, 0)), (0, 7));
    assert_eq!(gap(&mut sim, 1), 0, "Func1 went to 1000 and back to 0");

    ok(&mut sim, (129, 1, 0, 2));
    sim.advance(secs(8));
    assert_eq!(ggp(&mut sim, 130, 0), 15);
    assert!(gap(&mut sim, 1) > 150_000, "Func3 ran right for 7 s");
}

/// §8.4/§8.6: host and program talk through user variables while the
/// program runs; the host's GGP/SGP do not disturb it.
#[test]
fn host_and_program_talk_through_user_variables() {
    let mut sim = quiet_sim();
    download(
        &mut sim,
        &[
            (10, 10, 2, 0), // Loop: GGP 10, 2
            (20, 0, 0, 0),  // COMP 0
            (21, 2, 0, 0),  // JC EQ, Loop
            (34, 0, 0, 0),  // AAP 0, 0: move to the requested position
            (27, 1, 0, 0),  // WAIT POS, 0, 0
            (6, 1, 0, 0),   // GAP 1, 0
            (35, 11, 2, 0), // AGP 11, 2: report where it is
            (9, 10, 2, 0),  // SGP 10, 2, 0: request done
            (22, 0, 0, 0),  // JA Loop
        ],
    );
    ok(&mut sim, (129, 0, 0, 0));
    sim.advance(ms(100));
    assert_eq!(gap(&mut sim, 1), 0, "nothing requested");
    ok(&mut sim, (9, 10, 2, 5000));
    let mut waited = 0;
    while ggp(&mut sim, 10, 2) != 0 {
        assert!(waited < 100, "request not served");
        sim.advance(ms(100));
        waited += 1;
    }
    assert_eq!(ggp(&mut sim, 11, 2), 5000);
    assert_eq!(ggp(&mut sim, 128, 0), 1, "back in its loop");
}

#[test]
fn status_135_reports_pc_accumulator_and_x() {
    let mut sim = quiet_sim();
    download(
        &mut sim,
        &[
            (19, 9, 0, 1234), // CALC LOAD, 1234
            (33, 9, 0, 0),    // CALCX LOAD
            (19, 9, 0, -5),   // CALC LOAD, -5
            (27, 0, 0, 100),  // WAIT TICKS, 0, 100
            (28, 0, 0, 0),    // STOP
        ],
    );
    ok(&mut sim, (129, 0, 0, 0));
    sim.advance(ms(10));
    assert_eq!(ok(&mut sim, (135, 1, 0, 0)), (1 << 24) | (1 << 16) | 3);
    assert_eq!(ok(&mut sim, (135, 0, 0, 0)), (1 << 24) | (1 << 16) | 5);
    assert_eq!(ok(&mut sim, (135, 2, 0, 0)), -5);
    assert_eq!(ok(&mut sim, (135, 3, 0, 0)), 1234);
    // A direct-mode CALC has its own accumulator (§8.6).
    assert_eq!(ok(&mut sim, (19, 9, 0, 77)), 77);
    assert_eq!(ok(&mut sim, (135, 2, 0, 0)), -5);
    sim.advance(secs(1));
    assert_eq!(ok(&mut sim, (135, 1, 0, 0)), 4, "stopped on the STOP");
}

/// §8.7: GP77 = 1 starts the stored program at power-up (here: a software
/// reset).
#[test]
fn autostart_runs_the_program_after_a_reset() {
    let mut sim = quiet_sim();
    download(
        &mut sim,
        &[
            (45, 0, 0, 1), // CALCV ADD, 0, 1
            (22, 0, 0, 0), // JA 0
        ],
    );
    ok(&mut sim, (9, 77, 0, 1));
    ok(&mut sim, (255, 0, 0, 1234));
    sim.advance(ms(10));
    assert_eq!(ggp(&mut sim, 128, 0), 1);
    assert!(ggp(&mut sim, 0, 2) > 0, "the program counts");

    ok(&mut sim, (9, 77, 0, 0));
    ok(&mut sim, (255, 0, 0, 1234));
    sim.advance(ms(10));
    assert_eq!((ggp(&mut sim, 128, 0), ggp(&mut sim, 0, 2)), (0, 0));
}
