//! Unit tests of the simulator, driven through whole frames.

use std::time::Duration;

use super::*;
use crate::protocol::tmcl::{Reply, Request, Status};

fn sim() -> Tmcm1110 {
    Tmcm1110::new(SimConfig::default())
}

fn frame_to(address: u8, command: u8, kind: u8, motor_bank: u8, value: i32) -> [u8; 9] {
    Request {
        address,
        command,
        kind,
        motor_bank,
        value,
    }
    .to_bytes()
}

/// Send one command to address 1 and return everything the module sent.
fn send(sim: &mut Tmcm1110, command: u8, kind: u8, motor_bank: u8, value: i32) -> Vec<u8> {
    sim.feed(&frame_to(1, command, kind, motor_bank, value));
    sim.take_output()
}

/// Send one command and decode the single reply it must get.
fn ask(sim: &mut Tmcm1110, command: u8, kind: u8, motor_bank: u8, value: i32) -> Reply {
    let out = send(sim, command, kind, motor_bank, value);
    let bytes: [u8; 9] = out
        .as_slice()
        .try_into()
        .unwrap_or_else(|_| panic!("expected one 9-byte reply, got {out:02X?}"));
    Reply::from_bytes(&bytes).expect("reply checksum")
}

/// Send one command that must succeed and return its reply value.
fn ok(sim: &mut Tmcm1110, command: u8, kind: u8, motor_bank: u8, value: i32) -> i32 {
    let reply = ask(sim, command, kind, motor_bank, value);
    assert_eq!(
        reply.status,
        Status::OK,
        "command {command} type {kind} bank {motor_bank} value {value}"
    );
    assert_eq!(reply.command, command, "opcode echo");
    reply.value
}

fn status(sim: &mut Tmcm1110, command: u8, kind: u8, motor_bank: u8, value: i32) -> u8 {
    let reply = ask(sim, command, kind, motor_bank, value);
    assert_eq!(reply.command, command, "opcode echo");
    if !reply.status.is_success() {
        assert_eq!(reply.value, 0, "error replies carry value 0");
    }
    reply.status.0
}

fn hex(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).expect("hex byte"))
        .collect()
}

/// Advance in 1 ms steps until something is sent; bounded so a broken
/// simulator fails instead of hanging. Holds with an instant or ramped axis.
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

/// Let the axis run for `duration` and collect what the module sent.
fn run_for(sim: &mut Tmcm1110, duration: Duration) -> Vec<u8> {
    let mut out = Vec::new();
    let step = Duration::from_millis(10);
    let mut waited = Duration::ZERO;
    while waited < duration {
        sim.advance(step);
        waited += step;
        out.extend(sim.take_output());
    }
    out
}

const LONG: Duration = Duration::from_secs(600);

// ---- status codes ----------------------------------------------------

#[test]
fn wrong_checksum_answers_1_with_the_opcode() {
    let mut sim = sim();
    let mut frame = frame_to(1, 6, 1, 0, 0);
    frame[8] = frame[8].wrapping_add(1);
    sim.feed(&frame);
    assert_eq!(sim.take_output(), hex("02 01 01 06 00 00 00 00 0A"));
}

#[test]
fn the_misprinted_rsap_frame_of_3_6_8_gets_a_checksum_error() {
    let mut sim = sim();
    sim.feed(&hex("01 08 06 00 00 00 00 00 0A"));
    let out = sim.take_output();
    assert_eq!(out.get(2), Some(&1));
}

#[test]
fn unknown_opcodes_and_user_functions_answer_2() {
    let mut sim = sim();
    for opcode in [0, 16, 29, 47, 64, 67, 71, 100, 139, 254] {
        assert_eq!(status(&mut sim, opcode, 0, 0, 0), 2, "opcode {opcode}");
    }
}

#[test]
fn wrong_type_codes_answer_3() {
    let mut sim = sim();
    let cases: &[(u8, u8, u8, i32)] = &[
        (4, 3, 0, 0),    // MVP type 3
        (13, 3, 0, 0),   // RFS type 3
        (19, 10, 0, 0),  // CALC op 10
        (33, 11, 0, 0),  // CALCX op 11
        (45, 10, 0, 0),  // CALCV has no SWAP
        (36, 6, 0, 0),   // CLE flag 6
        (25, 4, 0, 0),   // EI of a non-interrupt
        (37, 255, 0, 0), // VECT 255
        (6, 14, 0, 0),   // GAP of a parameter the module lacks
        (5, 255, 0, 0),  // SAP 255
        (10, 1, 0, 0),   // GGP bank 0 parameter 1
        (10, 131, 0, 0), // GGP 131
        (10, 4, 3, 0),   // GGP bank 3 parameter 4
        (14, 8, 2, 1),   // SIO port 8
        (14, 1, 0, 1),   // SIO bank 0 is only port 0
        (15, 7, 0, 0),   // GIO port 7 bank 0
        (15, 1, 1, 0),   // GIO analog port 1
        (15, 8, 2, 0),   // GIO output port 8
        (30, 21, 0, 0),  // SCO 21
        (31, 21, 0, 0),  // GCO 21
        (129, 2, 0, 0),  // run application type 2
        (135, 4, 0, 0),  // application status type 4
        (136, 2, 0, 0),  // firmware version type 2
        (138, 2, 0, 1),  // 138 type 2
    ];
    for &(command, kind, bank, value) in cases {
        assert_eq!(
            status(&mut sim, command, kind, bank, value),
            3,
            "command {command} type {kind} bank {bank}"
        );
    }
}

#[test]
fn invalid_values_answer_4() {
    let mut sim = sim();
    let cases: &[(u8, u8, u8, i32)] = &[
        (1, 0, 1, 100),    // ROR motor 1
        (2, 0, 0, 2048),   // ROL beyond 2047
        (1, 0, 0, -2048),  // ROR beyond -2047
        (3, 0, 2, 0),      // MST motor 2
        (4, 0, 1, 0),      // MVP motor 1
        (4, 2, 0, 21),     // MVP COORD 21
        (4, 2, 0, -1),     // MVP COORD -1
        (5, 4, 0, 0),      // SAP 4 below 1
        (5, 4, 0, 2048),   // SAP 4 above 2047
        (5, 140, 0, 9),    // microstep resolution 9
        (6, 1, 1, 0),      // GAP motor 1
        (9, 66, 0, 0),     // SGP serial address 0
        (9, 65, 0, 9),     // SGP baud rate 9
        (9, 0, 1, 0),      // SGP bank 1
        (10, 0, 4, 0),     // GGP bank 4
        (14, 0, 2, 2),     // SIO output 2
        (14, 255, 2, 256), // SIO bit vector 256
        (14, 0, 0, 64),    // pull-up mask 64
        (14, 0, 1, 0),     // SIO bank 1
        (15, 0, 3, 0),     // GIO bank 3
        (30, 1, 1, 0),     // SCO motor 1
        (32, 1, 255, 0),   // CCO has no EEPROM form
        (37, 0, 0, 2048),  // VECT beyond program memory
        (40, 0, 1, 256),   // CALCVV var2 256
        (129, 1, 0, 2048), // run from 2048
        (132, 0, 0, -1),   // download from -1
        (134, 0, 0, 2048), // read 2048
        (137, 0, 0, 1),    // factory reset without the key
        (138, 1, 0, 2),    // 138 mask of motor 1
        (255, 0, 0, 4321), // reset without the key
    ];
    for &(command, kind, bank, value) in cases {
        assert_eq!(
            status(&mut sim, command, kind, bank, value),
            4,
            "command {command} type {kind} bank {bank} value {value}"
        );
    }
}

#[test]
fn read_only_writes_answer_3_by_default_and_4_if_configured() {
    let mut sim = sim();
    assert_eq!(status(&mut sim, 5, 3, 0, 0), 3); // SAP 3: actual speed
    assert_eq!(status(&mut sim, 9, 128, 0, 0), 3); // SGP 128: application status
    let mut strict = Tmcm1110::new(SimConfig {
        read_only_write: ReadOnlyWrite::InvalidValue,
        ..SimConfig::default()
    });
    assert_eq!(status(&mut strict, 5, 3, 0, 0), 4);
    assert_eq!(status(&mut strict, 9, 130, 0, 0), 4);
    assert_eq!(status(&mut strict, 34, 8, 0, 0), 4); // AAP 8
}

#[test]
fn storing_a_parameter_without_e_answers_3() {
    let mut sim = sim();
    assert_eq!(status(&mut sim, 7, 7, 0, 0), 3); // STAP 7 (standby current: RW)
    assert_eq!(status(&mut sim, 8, 140, 0, 0), 3); // RSAP 140
    assert_eq!(status(&mut sim, 7, 99, 0, 0), 3); // STAP of no parameter
    assert_eq!(status(&mut sim, 11, 56, 2, 0), 3); // STGP 56: RAM-only variable
    assert_eq!(status(&mut sim, 11, 66, 0, 0), 3); // STGP 66: auto-stored, not E
    assert_eq!(status(&mut sim, 12, 0, 3, 0), 3); // RSGP bank 3
    assert_eq!(status(&mut sim, 11, 0, 1, 0), 4); // STGP bank 1
    assert_eq!(status(&mut sim, 7, 4, 1, 0), 4); // STAP motor 1
}

#[test]
fn program_flow_commands_answer_6_and_do_nothing() {
    let mut sim = sim();
    for opcode in [20, 21, 22, 23, 24, 27, 28, 48, 49, 80] {
        assert_eq!(status(&mut sim, opcode, 0, 0, 5), 6, "opcode {opcode}");
    }
    assert_eq!(sim.view().program_counter, 0);
    // A wrong condition code is still a wrong type.
    assert_eq!(status(&mut sim, 21, 12, 0, 0), 3);
}

#[test]
fn code_protection_locks_download_and_read_back() {
    let mut sim = sim();
    ok(&mut sim, 9, 81, 0, 2);
    assert_eq!(status(&mut sim, 132, 0, 0, 0), 5);
    assert!(!sim.view().download_mode);
    assert_eq!(send(&mut sim, 134, 0, 0, 0).len(), 9); // read-back allowed
    ok(&mut sim, 9, 81, 0, 1);
    assert_eq!(status(&mut sim, 134, 0, 0, 0), 6);
    assert_eq!(status(&mut sim, 132, 0, 0, 0), 100);
}

#[test]
fn lifting_read_back_protection_erases_the_program() {
    let mut sim = sim();
    download(&mut sim, 0, &[(1, 0, 0, 100)]);
    ok(&mut sim, 9, 81, 0, 3);
    ok(&mut sim, 9, 81, 0, 2); // protection against overwriting stays
    assert_eq!(sim.program_word(0), Some([0; 7]));
}

#[test]
fn protection_changes_that_keep_read_back_keep_the_program() {
    let mut sim = sim();
    download(&mut sim, 0, &[(1, 0, 0, 100)]);
    ok(&mut sim, 9, 81, 0, 1);
    ok(&mut sim, 9, 81, 0, 3);
    assert_eq!(sim.program_word(0), Some([1, 0, 0, 0, 0, 0, 100]));
}

// ---- replies of the manual's examples ----------------------------------

#[test]
fn gio_analog_example_of_3_6_15() {
    let mut sim = sim();
    sim.set_analog_input(302);
    sim.feed(&hex("01 0F 00 01 00 00 00 00 11"));
    assert_eq!(sim.take_output(), hex("02 01 64 0F 00 00 01 2E A5"));
}

#[test]
fn calc_echoes_its_operand_as_in_3_6_16() {
    let mut sim = sim();
    sim.feed(&hex("01 13 02 00 FF FF EC 78 78"));
    assert_eq!(sim.take_output(), hex("02 01 64 13 FF FF EC 78 DC"));
}

#[test]
fn calcv_family_replies_match_3_6_36_to_3_6_41() {
    let mut sim = sim();
    let cases = [
        ("01 28 01 41 00 00 00 2A 95", "02 01 64 28 00 00 00 00 8F"),
        ("01 29 01 1B 00 00 00 00 46", "02 01 64 29 00 00 00 00 90"),
        ("01 2A 01 1B 00 00 00 00 47", "02 01 64 2A 00 00 00 00 91"),
        ("01 2B 01 1B 00 00 00 00 48", "02 01 64 2B 00 00 00 00 92"),
        ("01 2C 01 1B 00 00 00 00 49", "02 01 64 2C 00 00 00 00 93"),
        ("01 2D 01 1B 00 00 13 88 E5", "02 01 64 2D 00 00 13 88 2F"),
    ];
    for (command, reply) in cases {
        sim.feed(&hex(command));
        assert_eq!(sim.take_output(), hex(reply), "command {command}");
    }
}

#[test]
fn example_command_frames_of_the_manual_are_accepted() {
    // Direct-mode examples with correct checksums from §3.6 (the vectors file).
    let mut sim = sim();
    for command in [
        "01 01 00 00 00 00 03 E8 ED", // ROR 0, 1000
        "01 02 00 00 00 00 03 E8 EE", // ROL 0, 1000
        "01 03 00 00 00 00 00 00 04", // MST 0
        "01 04 00 00 00 01 5F 90 F5", // MVP ABS, 0, 90000
        "01 04 01 00 FF FF D8 F0 CC", // MVP REL, 0, -10000
        "01 04 02 00 00 00 00 08 0F", // MVP COORD, 0, 8
        "01 05 04 00 00 00 03 E8 F5", // SAP 4, 0, 1000
        "01 06 01 00 00 00 00 00 08", // GAP 1, 0
        "01 07 06 00 00 00 00 00 0E", // STAP 6, 0 (storable as §3.6.7 stores it)
        "01 0B 2A 02 00 00 00 00 38", // STGP 42, 2
        "01 0C 2A 02 00 00 00 00 39", // RSGP 42, 2
        "01 0D 00 00 00 00 00 00 0E", // RFS START, 0
        "01 0E 00 02 00 00 00 01 12", // SIO 0, 2, 1
        "01 1E 01 00 00 00 03 E8 0B", // SCO 1, 0, 1000
        "01 1F 01 00 00 00 00 00 21", // GCO 1, 0
        "01 27 01 00 00 00 00 00 29", // ACO 1, 0
        "01 21 02 00 00 00 00 00 24", // CALCX MUL
        "01 22 00 00 00 00 00 00 23", // AAP 0, 0
        "01 23 2A 02 00 00 00 00 50", // AGP 42, 2
        "01 24 01 00 00 00 00 00 26", // CLE ETO
        "01 19 FF 00 00 00 00 00 19", // EI 255
        "01 1A FF 00 00 00 00 00 1A", // DI 255
        "01 25 00 00 00 00 00 32 58", // VECT 0, 50
        "01 26 00 00 00 00 00 00 27", // RETI
        "01 2E 00 00 00 00 00 00 2F", // MVPA ABS, 0
        "01 32 00 00 00 00 00 00 33", // ROLA 0
        "01 33 00 00 00 00 00 00 34", // RORA 0
        "01 37 00 00 00 00 00 03 3B", // SIV 3
        "01 38 00 00 00 00 00 00 39", // GIV
        "01 39 00 00 00 00 00 00 3A", // AIV
    ] {
        sim.feed(&hex(command));
        let out = sim.take_output();
        assert_eq!(out.get(2), Some(&100), "{command} got {out:02X?}");
        assert_eq!(out.get(3), hex(command).get(1), "{command}: opcode echo");
    }
}

// ---- parameters ---------------------------------------------------------

#[test]
fn axis_parameters_read_back_what_was_written() {
    let mut sim = sim();
    ok(&mut sim, 5, 4, 0, 1000); // motion model's parameter
    assert_eq!(ok(&mut sim, 6, 4, 0, 0), 1000);
    ok(&mut sim, 5, 6, 0, 200); // stored by the module
    assert_eq!(ok(&mut sim, 6, 6, 0, 0), 200);
    ok(&mut sim, 5, 174, 0, -64);
    assert_eq!(ok(&mut sim, 6, 174, 0, 0), -64);
}

#[test]
fn module_parameters_start_at_their_defaults() {
    let mut sim = sim();
    assert_eq!(ok(&mut sim, 6, 167, 0, 0), 5);
    assert_eq!(ok(&mut sim, 10, 76, 0, 0), 2);
    assert_eq!(ok(&mut sim, 10, 66, 0, 0), 1);
    assert_eq!(ok(&mut sim, 10, 78, 0, 0), 7); // §6.2 default
    assert_eq!(ok(&mut sim, 6, 214, 0, 0), 200); // §4 default 2 s
}

#[test]
fn gap_207_reads_then_clears_the_error_flags() {
    let mut sim = sim();
    sim.axis.set_param(207, 2);
    let before = sim.axis.param(207);
    assert_eq!(ok(&mut sim, 6, 207, 0, 0), before);
    assert_eq!(ok(&mut sim, 6, 207, 0, 0), 0);
}

#[test]
fn global_parameters_of_banks_2_and_3() {
    let mut sim = sim();
    ok(&mut sim, 9, 255, 2, -123);
    assert_eq!(ok(&mut sim, 10, 255, 2, 0), -123);
    ok(&mut sim, 9, 0, 3, -1); // timer period 4294967295 ms as its bit pattern
    assert_eq!(ok(&mut sim, 10, 0, 3, 0), -1);
    ok(&mut sim, 9, 44, 3, 3);
    assert_eq!(ok(&mut sim, 10, 44, 3, 0), 3);
    assert_eq!(status(&mut sim, 9, 44, 3, 4), 4);
}

#[test]
fn read_only_globals_report_the_application_state() {
    let mut sim = sim();
    assert_eq!(ok(&mut sim, 10, 128, 0, 0), 0);
    ok(&mut sim, 129, 1, 0, 17);
    assert_eq!(ok(&mut sim, 10, 128, 0, 0), 1);
    assert_eq!(ok(&mut sim, 10, 130, 0, 0), 17);
    assert_eq!(ok(&mut sim, 10, 129, 0, 0), 0);
    ok(&mut sim, 128, 0, 0, 0);
    assert_eq!(ok(&mut sim, 10, 128, 0, 0), 0);
    ok(&mut sim, 130, 0, 0, 0);
    assert_eq!(ok(&mut sim, 10, 128, 0, 0), 2);
    ok(&mut sim, 131, 0, 0, 0);
    assert_eq!(ok(&mut sim, 10, 128, 0, 0), 3);
    assert_eq!(ok(&mut sim, 10, 130, 0, 0), 0);
}

#[test]
fn tick_timer_counts_virtual_milliseconds_and_can_be_set() {
    let mut sim = sim();
    sim.advance(Duration::from_millis(1500));
    assert_eq!(ok(&mut sim, 10, 132, 0, 0), 1500);
    ok(&mut sim, 9, 132, 0, 10);
    sim.advance(Duration::from_micros(5500));
    assert_eq!(ok(&mut sim, 10, 132, 0, 0), 15);
}

#[test]
fn random_numbers_are_deterministic_and_seedable() {
    let mut a = sim();
    let mut b = sim();
    let first: Vec<i32> = (0..3).map(|_| ok(&mut a, 10, 133, 0, 0)).collect();
    let second: Vec<i32> = (0..3).map(|_| ok(&mut b, 10, 133, 0, 0)).collect();
    assert_eq!(first, second);
    assert!(first.iter().all(|&r| r >= 0));
    assert_ne!(first[0], first[1]);
    ok(&mut a, 9, 133, 0, 99);
    ok(&mut b, 9, 133, 0, 99);
    assert_eq!(ok(&mut a, 10, 133, 0, 0), ok(&mut b, 10, 133, 0, 0));
}

#[test]
fn end_switch_polarity_is_passed_to_the_axis() {
    let mut sim = sim();
    assert_eq!(ok(&mut sim, 9, 79, 0, 1), 0);
    assert_eq!(ok(&mut sim, 10, 79, 0, 0), 1);
}

// ---- motion ---------------------------------------------------------------

#[test]
fn ror_and_rol_set_velocity_mode_with_signed_speed() {
    let mut sim = sim();
    ok(&mut sim, 1, 0, 0, 500);
    assert_eq!(ok(&mut sim, 6, 2, 0, 0), 500);
    assert_eq!(ok(&mut sim, 6, 138, 0, 0), 2);
    ok(&mut sim, 2, 0, 0, 300);
    assert_eq!(ok(&mut sim, 6, 2, 0, 0), -300);
    ok(&mut sim, 3, 0, 0, 0);
    assert_eq!(ok(&mut sim, 6, 2, 0, 0), 0);
}

#[test]
fn mvp_abs_rel_and_coord_set_the_target() {
    let mut sim = sim();
    ok(&mut sim, 4, 0, 0, 1000);
    assert_eq!(ok(&mut sim, 6, 0, 0, 0), 1000);
    assert_eq!(ok(&mut sim, 6, 138, 0, 0), 0);
    run_for(&mut sim, Duration::from_secs(60));
    let actual = ok(&mut sim, 6, 1, 0, 0);
    ok(&mut sim, 4, 1, 0, -300);
    assert_eq!(ok(&mut sim, 6, 0, 0, 0), actual - 300);
    ok(&mut sim, 30, 5, 0, -4444);
    ok(&mut sim, 4, 2, 0, 5);
    assert_eq!(ok(&mut sim, 6, 0, 0, 0), -4444);
}

#[test]
fn mvp_rel_wraps_around_32_bits() {
    let mut sim = sim();
    ok(&mut sim, 5, 1, 0, i32::MAX - 10);
    ok(&mut sim, 4, 1, 0, 20);
    assert_eq!(ok(&mut sim, 6, 0, 0, 0), i32::MIN + 9);
}

#[test]
fn mvpa_rora_rola_take_the_accumulator() {
    let mut sim = sim();
    ok(&mut sim, 19, 9, 0, 700); // CALC LOAD 700
    ok(&mut sim, 51, 0, 0, 0); // RORA
    assert_eq!(ok(&mut sim, 6, 2, 0, 0), 700);
    ok(&mut sim, 50, 0, 0, 0); // ROLA
    assert_eq!(ok(&mut sim, 6, 2, 0, 0), -700);
    ok(&mut sim, 46, 0, 0, 0); // MVPA ABS
    assert_eq!(ok(&mut sim, 6, 0, 0, 0), 700);
    ok(&mut sim, 19, 9, 0, 5000);
    assert_eq!(status(&mut sim, 51, 0, 0, 0), 4); // RORA beyond 2047
}

#[test]
fn rfs_status_reads_0_when_no_search_runs() {
    let mut sim = sim();
    assert_eq!(ok(&mut sim, 13, 2, 0, 0), 0);
    ok(&mut sim, 13, 1, 0, 0);
    assert_eq!(
        ok(&mut sim, 13, 2, 0, 0),
        i32::from(sim.axis.reference_search_active())
    );
}

#[test]
fn heartbeat_stops_the_motor_after_silence() {
    let mut sim = sim();
    ok(&mut sim, 9, 68, 0, 100);
    ok(&mut sim, 1, 0, 0, 500);
    sim.advance(Duration::from_millis(99));
    assert_eq!(sim.axis.param(2), 500);
    sim.advance(Duration::from_millis(2));
    assert_eq!(sim.axis.param(2), 0);
    // A command re-arms it.
    ok(&mut sim, 1, 0, 0, 400);
    sim.advance(Duration::from_millis(50));
    ok(&mut sim, 6, 1, 0, 0);
    sim.advance(Duration::from_millis(99));
    assert_eq!(sim.axis.param(2), 400);
    sim.advance(Duration::from_millis(1));
    assert_eq!(sim.axis.param(2), 0);
}

#[test]
fn heartbeat_off_never_stops_the_motor() {
    let mut sim = sim();
    ok(&mut sim, 1, 0, 0, 500);
    sim.advance(Duration::from_secs(3600));
    assert_eq!(sim.axis.param(2), 500);
}

// ---- command 138 -----------------------------------------------------------

#[test]
fn target_reached_example_of_3_6_52() {
    let mut sim = sim();
    sim.feed(&hex("01 8A 01 00 00 00 00 01 8D"));
    assert_eq!(sim.take_output(), hex("02 01 64 8A 00 00 00 01 F2"));
    ok(&mut sim, 4, 0, 0, 5000);
    assert_eq!(
        wait_for_output(&mut sim, LONG),
        hex("02 01 80 8A 00 00 00 01 0E")
    );
}

#[test]
fn target_reached_type_0_reports_the_next_move_only() {
    let mut sim = sim();
    assert_eq!(ok(&mut sim, 138, 0, 0, 1), 1);
    ok(&mut sim, 4, 0, 0, 800);
    assert_eq!(wait_for_output(&mut sim, LONG).get(2), Some(&128));
    ok(&mut sim, 4, 0, 0, -800);
    assert!(run_for(&mut sim, Duration::from_secs(120)).is_empty());
    assert_eq!(ok(&mut sim, 6, 1, 0, 0), -800);
}

#[test]
fn target_reached_type_1_reports_every_move() {
    let mut sim = sim();
    ok(&mut sim, 138, 1, 0, 1);
    for target in [300, -200, 900] {
        ok(&mut sim, 4, 0, 0, target);
        let out = wait_for_output(&mut sim, LONG);
        assert_eq!(out.len(), 9, "move to {target}");
        assert_eq!(out.get(2), Some(&128));
        assert_eq!(ok(&mut sim, 6, 1, 0, 0), target);
    }
}

#[test]
fn an_interrupted_move_is_not_reported() {
    for stop in [(3, 0), (1, 0), (2, 0)] {
        let mut sim = sim();
        ok(&mut sim, 138, 1, 0, 1);
        ok(&mut sim, 4, 0, 0, 100_000);
        ok(&mut sim, stop.0, stop.1, 0, 0); // MST / ROR 0 / ROL 0
        assert!(
            run_for(&mut sim, Duration::from_secs(60)).is_empty(),
            "after opcode {}",
            stop.0
        );
    }
}

#[test]
fn a_reference_search_abandons_the_reported_move() {
    let mut sim = sim();
    ok(&mut sim, 138, 1, 0, 1);
    ok(&mut sim, 4, 0, 0, 100_000);
    ok(&mut sim, 13, 0, 0, 0); // RFS START
    assert!(run_for(&mut sim, Duration::from_secs(60)).is_empty());
}

#[test]
fn a_type_0_request_is_used_up_by_an_abandoned_move() {
    let mut sim = sim();
    ok(&mut sim, 138, 0, 0, 1);
    ok(&mut sim, 4, 0, 0, 100_000);
    ok(&mut sim, 3, 0, 0, 0); // MST
    ok(&mut sim, 4, 0, 0, 500);
    assert!(run_for(&mut sim, Duration::from_secs(60)).is_empty());
}

#[test]
fn sap_0_alone_is_not_reported() {
    let mut sim = sim();
    ok(&mut sim, 138, 1, 0, 1);
    ok(&mut sim, 5, 0, 0, 400);
    assert!(run_for(&mut sim, Duration::from_secs(60)).is_empty());
}

#[test]
fn a_move_to_where_the_motor_is_is_reported_at_once() {
    let mut sim = sim();
    ok(&mut sim, 138, 1, 0, 1);
    ok(&mut sim, 4, 0, 0, 0);
    sim.advance(Duration::ZERO);
    assert_eq!(sim.take_output(), hex("02 01 80 8A 00 00 00 01 0E"));
    assert!(run_for(&mut sim, Duration::from_secs(1)).is_empty());
}

#[test]
fn reset_cancels_the_target_reached_request() {
    let mut sim = sim();
    ok(&mut sim, 138, 1, 0, 1);
    ok(&mut sim, 255, 0, 0, 1234);
    ok(&mut sim, 4, 0, 0, 100);
    assert!(run_for(&mut sim, Duration::from_secs(60)).is_empty());
    assert_eq!(sim.view().target_reached_request, TargetReachedRequest::Off);
}

// ---- addressing and suppression -------------------------------------------

#[test]
fn frames_for_other_addresses_are_ignored() {
    let mut sim = sim();
    sim.feed(&frame_to(2, 6, 1, 0, 0));
    let mut bad = frame_to(3, 6, 1, 0, 0);
    bad[8] ^= 0xFF;
    sim.feed(&bad);
    assert!(sim.take_output().is_empty());
}

#[test]
fn secondary_address_answers_with_the_address_used() {
    let mut sim = sim();
    ok(&mut sim, 9, 87, 0, 9);
    sim.feed(&frame_to(9, 6, 1, 0, 0));
    let out = sim.take_output();
    assert_eq!(out.get(..3), Some(&[2, 9, 100][..]));
    ok(&mut sim, 9, 87, 0, 0);
    sim.feed(&frame_to(9, 6, 1, 0, 0));
    assert!(sim.take_output().is_empty());
}

#[test]
fn a_new_module_address_takes_effect_for_the_next_command() {
    let mut sim = sim();
    sim.feed(&frame_to(1, 9, 66, 0, 5));
    assert_eq!(sim.take_output().get(1), Some(&1));
    assert_eq!(sim.address(), 5);
    sim.feed(&frame_to(1, 6, 1, 0, 0));
    assert!(sim.take_output().is_empty());
    sim.feed(&frame_to(5, 6, 1, 0, 0));
    assert_eq!(sim.take_output().get(..3), Some(&[2, 5, 100][..]));
}

#[test]
fn replies_carry_the_host_address() {
    let mut sim = sim();
    let out = send(&mut sim, 9, 76, 0, 0x33);
    assert_eq!(out.first(), Some(&0x33));
    assert_eq!(send(&mut sim, 6, 1, 0, 0).first(), Some(&0x33));
}

#[test]
fn gp255_suppresses_replies_except_gap_ggp_gio() {
    let mut sim = sim();
    assert!(send(&mut sim, 9, 255, 0, 1).is_empty());
    assert!(send(&mut sim, 5, 4, 0, 100).is_empty());
    assert!(send(&mut sim, 16, 0, 0, 0).is_empty()); // errors too
    assert_eq!(ok(&mut sim, 6, 4, 0, 0), 100);
    assert_eq!(ok(&mut sim, 10, 255, 0, 0), 1);
    assert_eq!(ok(&mut sim, 15, 0, 1, 0), 0);
    assert_eq!(status(&mut sim, 6, 14, 0, 0), 3);
    assert!(sim.view().replies_suppressed);
    // The reply follows the setting in force after the command.
    assert_eq!(ok(&mut sim, 9, 255, 0, 0), 0);
    assert_eq!(ok(&mut sim, 5, 4, 0, 100), 0);
}

#[test]
fn gp255_does_not_suppress_the_target_reached_message() {
    let mut sim = sim();
    ok(&mut sim, 138, 1, 0, 1);
    send(&mut sim, 9, 255, 0, 1);
    assert!(send(&mut sim, 4, 0, 0, 900).is_empty());
    assert_eq!(wait_for_output(&mut sim, LONG).get(2), Some(&128));
}

// ---- framing -----------------------------------------------------------------

#[test]
fn split_frames_are_assembled() {
    let mut sim = sim();
    let frame = frame_to(1, 6, 1, 0, 0);
    for byte in frame {
        sim.feed(&[byte]);
        sim.advance(Duration::from_millis(1));
    }
    assert_eq!(sim.take_output().len(), 9);
}

#[test]
fn silence_drops_a_partial_frame() {
    let mut sim = sim();
    sim.feed(&[0x01, 0x06, 0x01]);
    sim.advance(DEFAULT_FRAME_GAP);
    sim.feed(&frame_to(1, 6, 1, 0, 0));
    assert_eq!(sim.take_output().get(2), Some(&100));
}

#[test]
fn a_shorter_pause_keeps_the_partial_frame() {
    let mut sim = sim();
    let frame = frame_to(1, 6, 1, 0, 0);
    sim.feed(&frame[..4]);
    sim.advance(DEFAULT_FRAME_GAP - Duration::from_millis(1));
    sim.feed(&frame[4..]);
    assert_eq!(sim.take_output().get(2), Some(&100));
}

#[test]
fn frame_gap_is_configurable() {
    let mut sim = Tmcm1110::new(SimConfig {
        frame_gap: Duration::from_millis(100),
        ..SimConfig::default()
    });
    let frame = frame_to(1, 6, 1, 0, 0);
    sim.feed(&frame[..4]);
    sim.advance(Duration::from_millis(50));
    sim.feed(&frame[4..]);
    assert_eq!(sim.take_output().get(2), Some(&100));
}

// ---- I/O ---------------------------------------------------------------------

#[test]
fn outputs_are_set_one_by_one_or_as_a_vector() {
    let mut sim = sim();
    ok(&mut sim, 14, 0, 2, 1);
    assert_eq!(ok(&mut sim, 15, 0, 2, 0), 1);
    ok(&mut sim, 14, 255, 2, 0b1010_0101);
    assert_eq!(sim.view().outputs, 0b1010_0101);
    assert_eq!(ok(&mut sim, 15, 7, 2, 0), 1);
    assert_eq!(ok(&mut sim, 15, 6, 2, 0), 0);
    ok(&mut sim, 19, 9, 0, 0x13C); // A = 0x13C
    ok(&mut sim, 14, 255, 2, -1);
    assert_eq!(sim.view().outputs, 0x3C);
}

#[test]
fn inputs_follow_levels_pull_ups_and_direction() {
    let mut sim = sim();
    // GP78 = 7: PWMU0..2 are outputs, PWMD0..2 inputs; pull-ups on.
    assert_eq!(ok(&mut sim, 15, 1, 0, 0), 1); // PWMD0 open, pulled up
    sim.set_input(1, Some(false)).expect("port 1");
    assert_eq!(ok(&mut sim, 15, 1, 0, 0), 0);
    ok(&mut sim, 14, 0, 0, 0); // pull-ups off
    assert_eq!(ok(&mut sim, 15, 2, 0, 0), 0); // PWMD1 open, no pull-up
    assert_eq!(sim.view().pull_ups, 0);
    // PWMU0 (GIO 4) is an output: reads its latch (SIO 2).
    ok(&mut sim, 14, 2, 2, 1);
    assert_eq!(ok(&mut sim, 15, 4, 0, 0), 1);
    ok(&mut sim, 9, 78, 0, 0); // all inputs
    sim.set_input(4, Some(false)).expect("port 4");
    assert_eq!(ok(&mut sim, 15, 4, 0, 0), 0);
    sim.set_input(6, Some(true)).expect("port 6");
    sim.set_analog_input(40000);
    // bit 0 AIN0 (high), bit 6 PWMU2 (driven high), others low or open.
    assert_eq!(ok(&mut sim, 15, 255, 0, 0), 0b100_0001);
}

#[test]
fn only_real_input_ports_can_be_driven() {
    let mut sim = sim();
    assert_eq!(sim.set_input(0, Some(true)), Err(InputError::NoSuchPort(0)));
    assert_eq!(sim.set_input(7, Some(true)), Err(InputError::NoSuchPort(7)));
    let message = InputError::NoSuchPort(7).to_string();
    assert!(message.contains("1..6"), "{message}");
}

// ---- coordinates ---------------------------------------------------------------

#[test]
fn coordinates_set_get_capture() {
    let mut sim = sim();
    ok(&mut sim, 30, 20, 0, 777);
    assert_eq!(ok(&mut sim, 31, 20, 0, 0), 777);
    ok(&mut sim, 5, 1, 0, 4242); // actual position
    assert_eq!(ok(&mut sim, 32, 3, 0, 0), 4242);
    assert_eq!(ok(&mut sim, 31, 3, 0, 0), 4242);
    ok(&mut sim, 19, 9, 0, -9); // A = -9
    ok(&mut sim, 39, 0, 0, 0); // ACO 0
    assert_eq!(ok(&mut sim, 31, 0, 0, 0), -9);
}

#[test]
fn coordinates_are_ram_only_unless_copied_or_gp84() {
    let mut sim = sim();
    ok(&mut sim, 30, 1, 0, 1000);
    ok(&mut sim, 30, 2, 0, 2000);
    ok(&mut sim, 30, 1, 255, 0); // copy coordinate 1 to EEPROM
    reset(&mut sim);
    assert_eq!(ok(&mut sim, 31, 1, 0, 0), 0);
    ok(&mut sim, 31, 0, 255, 0); // copy all back from EEPROM
    assert_eq!(ok(&mut sim, 31, 1, 0, 0), 1000);
    assert_eq!(ok(&mut sim, 31, 2, 0, 0), 0);
    ok(&mut sim, 30, 2, 0, 2000);
    ok(&mut sim, 30, 0, 255, 0); // copy all to EEPROM
    ok(&mut sim, 30, 2, 0, 5);
    ok(&mut sim, 31, 2, 255, 0);
    assert_eq!(ok(&mut sim, 31, 2, 0, 0), 2000);

    ok(&mut sim, 9, 84, 0, 1);
    ok(&mut sim, 30, 7, 0, 70);
    ok(&mut sim, 30, 0, 0, 99); // coordinate 0 is never stored
    reset(&mut sim);
    assert_eq!(ok(&mut sim, 31, 7, 0, 0), 70);
    assert_eq!(ok(&mut sim, 31, 1, 0, 0), 1000);
    assert_eq!(ok(&mut sim, 31, 0, 0, 0), 0);
}

// ---- calculations ------------------------------------------------------------

#[test]
fn calculations_act_on_a_x_and_variables() {
    let mut sim = sim();
    ok(&mut sim, 19, 9, 0, 6); // A = 6
    ok(&mut sim, 33, 9, 0, 0); // X = A
    ok(&mut sim, 19, 2, 0, 7); // A = 42
    assert_eq!(sim.host_registers.accumulator, 42);
    assert_eq!(sim.host_registers.x, 6);
    ok(&mut sim, 33, 10, 0, 0); // swap
    assert_eq!(sim.host_registers.accumulator, 6);
    ok(&mut sim, 33, 8, 0, 0); // X = !X
    assert_eq!(sim.host_registers.x, !42);
    ok(&mut sim, 19, 8, 0, 0); // A = !A
    assert_eq!(sim.host_registers.accumulator, !6);

    ok(&mut sim, 9, 10, 2, 100);
    ok(&mut sim, 9, 11, 2, 30);
    ok(&mut sim, 40, 1, 10, 11); // v10 -= v11
    assert_eq!(ok(&mut sim, 10, 10, 2, 0), 70);
    ok(&mut sim, 40, 10, 10, 11); // swap
    assert_eq!(ok(&mut sim, 10, 10, 2, 0), 30);
    assert_eq!(ok(&mut sim, 10, 11, 2, 0), 70);
    ok(&mut sim, 45, 0, 11, 5); // v11 += 5
    assert_eq!(ok(&mut sim, 10, 11, 2, 0), 75);
    ok(&mut sim, 45, 8, 11, 123); // v11 = !v11
    assert_eq!(ok(&mut sim, 10, 11, 2, 0), !75);
    ok(&mut sim, 19, 9, 0, 3);
    ok(&mut sim, 41, 9, 12, 0); // v12 = A
    assert_eq!(ok(&mut sim, 10, 12, 2, 0), 3);
    ok(&mut sim, 42, 2, 11, 0); // A *= v11
    assert_eq!(sim.host_registers.accumulator, 3 * !75);
    ok(&mut sim, 44, 9, 12, 0); // X = v12
    assert_eq!(sim.host_registers.x, 3);
    ok(&mut sim, 43, 0, 12, 0); // v12 += X
    assert_eq!(ok(&mut sim, 10, 12, 2, 0), 6);
    ok(&mut sim, 42, 11, 11, 0); // A COMP v11
    assert_eq!(
        sim.host_registers.flags.comparison,
        Some(std::cmp::Ordering::Less) // A = 3 * !75 < v11 = !75
    );
}

/// §3.5.3 Table 8 puts COMP with the branch commands, and §8.6 lets direct
/// mode run beside a program without disturbing it: a COMP from the host
/// must not rewrite the flags the program's next JC tests.
#[test]
fn direct_mode_comp_answers_6_and_keeps_the_flags() {
    let mut sim = sim();
    ok(&mut sim, 19, 9, 0, 3); // A = 3
    ok(&mut sim, 45, 11, 0, 5); // v0 COMP 5: v0 = 0 is less
    let flags = sim.host_registers.flags;
    assert_eq!(flags.comparison, Some(std::cmp::Ordering::Less));
    // COMP 3 would make A equal and set the zero flag.
    assert_eq!(status(&mut sim, 20, 0, 0, 3), 6);
    assert_eq!(sim.host_registers.flags, flags);
    assert_eq!(sim.host_registers.accumulator, 3, "A untouched");
}

#[test]
fn indexed_variables_use_x_and_ignore_bad_indices() {
    let mut sim = sim();
    ok(&mut sim, 19, 9, 0, 12);
    ok(&mut sim, 33, 9, 0, 0); // X = 12
    ok(&mut sim, 55, 0, 0, 99); // SIV 99
    assert_eq!(ok(&mut sim, 10, 12, 2, 0), 99);
    assert_eq!(ok(&mut sim, 56, 0, 0, 0), 99); // GIV answers var[X]
    assert_eq!(sim.host_registers.accumulator, 12); // ... and leaves A alone
    ok(&mut sim, 57, 0, 0, 0); // AIV
    assert_eq!(ok(&mut sim, 10, 12, 2, 0), 12);
    ok(&mut sim, 19, 9, 0, 256);
    ok(&mut sim, 33, 9, 0, 0); // X = 256: outside 0..255
    ok(&mut sim, 55, 0, 0, 5);
    assert_eq!(ok(&mut sim, 56, 0, 0, 0), 0);
}

#[test]
fn interrupt_setup_is_recorded() {
    let mut sim = sim();
    ok(&mut sim, 37, 3, 0, 40); // VECT 3, 40
    ok(&mut sim, 25, 3, 0, 0); // EI 3
    ok(&mut sim, 25, 255, 0, 0); // EI 255
    assert_eq!(sim.app.interrupts.vectors.get(&3), Some(&40));
    assert!(sim.app.interrupts.enabled.contains(&3));
    assert!(sim.app.interrupts.globally_enabled);
    ok(&mut sim, 26, 3, 0, 0);
    ok(&mut sim, 26, 255, 0, 0);
    assert!(!sim.app.interrupts.enabled.contains(&3));
    assert!(!sim.app.interrupts.globally_enabled);
}

#[test]
fn cle_clears_error_flags() {
    let mut sim = sim();
    sim.app.errors.timeout = true;
    sim.app.errors.deviation = true;
    ok(&mut sim, 36, 1, 0, 0);
    assert!(!sim.app.errors.timeout);
    assert!(sim.app.errors.deviation);
    ok(&mut sim, 36, 0, 0, 0);
    assert!(!sim.app.errors.deviation);
}

// ---- download and program memory -----------------------------------------------

/// Download `commands` from `start` and check the replies.
fn download(sim: &mut Tmcm1110, start: i32, commands: &[(u8, u8, u8, i32)]) {
    ok(sim, 132, 0, 0, start);
    for (i, &(command, kind, bank, value)) in commands.iter().enumerate() {
        let reply = ask(sim, command, kind, bank, value);
        assert_eq!(reply.status, Status::LOADED);
        assert_eq!(reply.command, command);
        assert_eq!(reply.value, start + i as i32, "stored address");
    }
    ok(sim, 133, 0, 0, 0);
}

#[test]
fn download_stores_instead_of_executing() {
    let mut sim = sim();
    ok(&mut sim, 132, 0, 0, 10);
    assert!(sim.view().download_mode);
    assert_eq!(ask(&mut sim, 1, 0, 0, 500).status, Status::LOADED); // ROR stored
    assert_eq!(ask(&mut sim, 10, 129, 0, 0).status, Status::LOADED); // even GGP
    assert_eq!(ask(&mut sim, 22, 0, 0, 10).status, Status::LOADED); // JA stored
    assert_eq!(status(&mut sim, 70, 0, 0, 0), 2); // UF6 is not a command
    assert_eq!(ok(&mut sim, 135, 0, 0, 0) & 0xFFFF, 13);
    ok(&mut sim, 133, 0, 0, 0);
    assert!(!sim.view().download_mode);
    assert_eq!(sim.axis.param(2), 0, "ROR was not executed");
    assert_eq!(sim.program_word(10), Some([1, 0, 0, 0, 0, 0x01, 0xF4]));
    assert_eq!(sim.program_word(12), Some([22, 0, 0, 0, 0, 0, 10]));
}

#[test]
fn an_armed_store_fault_corrupts_one_word_and_replies_as_usual() {
    let mut sim = sim();
    let plan = crate::sim::faults::FaultPlan::parse("corrupt-store=2").expect("parses");
    crate::sim::SimulatedController::arm_faults(&mut sim, &plan);
    // `download` checks each reply: status 101 and the address, as usual.
    download(
        &mut sim,
        5,
        &[(4, 0, 0, 1000), (4, 0, 0, 2000), (4, 0, 0, 3000)],
    );
    assert_eq!(sim.program_word(5), Some([4, 0, 0, 0, 0, 0x03, 0xE8]));
    assert_eq!(
        sim.program_word(6),
        Some([4, 0, 0, 0, 0, 0x07, 0xD1]),
        "bit 0 flipped"
    );
    assert_eq!(sim.program_word(7), Some([4, 0, 0, 0, 0, 0x0B, 0xB8]));
    assert_eq!(plan.counts().corrupted_stores, 1);
    // Once only, until armed again.
    download(&mut sim, 0, &[(4, 0, 0, 1000), (4, 0, 0, 2000)]);
    assert_eq!(sim.program_word(1), Some([4, 0, 0, 0, 0, 0x07, 0xD0]));
    crate::sim::SimulatedController::arm_faults(&mut sim, &crate::sim::faults::FaultPlan::none());
    download(&mut sim, 0, &[(4, 0, 0, 1000), (4, 0, 0, 2000)]);
    assert_eq!(sim.program_word(1), Some([4, 0, 0, 0, 0, 0x07, 0xD0]));
    assert_eq!(plan.counts().corrupted_stores, 1);
}

#[test]
fn program_memory_reads_back_in_the_special_layout() {
    let mut sim = sim();
    download(&mut sim, 0, &[(4, 1, 0, -10000), (9, 77, 0, 1)]);
    // host, opcode, type, motor, value MSB..LSB, checksum
    assert_eq!(
        send(&mut sim, 134, 0, 0, 0),
        hex("02 04 01 00 FF FF D8 F0 CD")
    );
    assert_eq!(
        send(&mut sim, 134, 0, 0, 1),
        hex("02 09 4D 00 00 00 00 01 59")
    );
    assert_eq!(
        send(&mut sim, 134, 0, 0, 2047),
        hex("02 00 00 00 00 00 00 00 02")
    );
}

#[test]
fn application_status_layout() {
    let mut sim = sim();
    download(&mut sim, 5, &[(3, 0, 0, 0), (3, 0, 0, 0)]);
    assert_eq!(ok(&mut sim, 135, 0, 0, 0), 7); // stopped, not waiting, pointer 7
    ok(&mut sim, 129, 1, 0, 300);
    assert_eq!(ok(&mut sim, 135, 1, 0, 0), (1 << 24) | 300);
    assert_eq!(ok(&mut sim, 135, 0, 0, 0), (1 << 24) | 7);
    sim.app.wait = Some(program::Wait {
        condition: crate::protocol::tmcl::WaitCondition::Ticks,
        deadline: None,
    });
    assert_eq!(ok(&mut sim, 135, 1, 0, 0), (1 << 24) | (1 << 16) | 300);
}

#[test]
fn entering_download_mode_stops_a_running_program() {
    let mut sim = sim();
    ok(&mut sim, 129, 0, 0, 0);
    ok(&mut sim, 132, 0, 0, 0);
    assert_eq!(sim.view().application_status, ApplicationStatus::Stopped);
    // Control commands still work in download mode.
    assert_eq!(ok(&mut sim, 136, 1, 0, 0), FIRMWARE_VERSION_NUMBER);
}

#[test]
fn program_memory_ends_at_2047() {
    let mut sim = sim();
    ok(&mut sim, 132, 0, 0, 2047);
    assert_eq!(ask(&mut sim, 3, 0, 0, 0).status, Status::LOADED);
    assert_eq!(status(&mut sim, 3, 0, 0, 0), 4);
}

// ---- firmware version ---------------------------------------------------------

#[test]
fn firmware_version_string_and_number() {
    let mut sim = sim();
    let out = send(&mut sim, 136, 0, 0, 0);
    assert_eq!(out.first(), Some(&2));
    assert_eq!(out.get(1..), Some(&b"1110V112"[..]));
    assert_eq!(ok(&mut sim, 136, 1, 0, 0), 0x0456_010C);
}

// ---- EEPROM, reset, factory reset --------------------------------------------------

fn reset(sim: &mut Tmcm1110) {
    assert_eq!(ok(sim, 255, 0, 0, 1234), 0);
}

#[test]
fn stap_rsap_and_reset_restore_axis_parameters() {
    let mut sim = sim();
    ok(&mut sim, 5, 214, 0, 50);
    ok(&mut sim, 7, 214, 0, 0); // STAP
    ok(&mut sim, 5, 214, 0, 60);
    ok(&mut sim, 8, 214, 0, 0); // RSAP
    assert_eq!(ok(&mut sim, 6, 214, 0, 0), 50);
    ok(&mut sim, 5, 4, 0, 1500);
    ok(&mut sim, 7, 4, 0, 0);
    ok(&mut sim, 5, 4, 0, 100);
    ok(&mut sim, 5, 6, 0, 77); // not storable: lost on reset
    reset(&mut sim);
    assert_eq!(ok(&mut sim, 6, 4, 0, 0), 1500);
    assert_eq!(ok(&mut sim, 6, 214, 0, 0), 50);
    assert_eq!(ok(&mut sim, 6, 6, 0, 0), 128);
}

#[test]
fn software_reset_replies_then_restarts() {
    let mut sim = sim();
    ok(&mut sim, 5, 1, 0, 5555);
    ok(&mut sim, 14, 0, 2, 1);
    send(&mut sim, 9, 255, 0, 1);
    sim.advance(Duration::from_secs(2));
    // Suppression is on: the reset's reply is suppressed too.
    assert!(send(&mut sim, 255, 0, 0, 1234).is_empty());
    let view = sim.view();
    assert!(!view.replies_suppressed);
    assert_eq!(view.actual_position, 0);
    assert_eq!(view.outputs, 0);
    assert_eq!(view.uptime, Duration::ZERO);
    assert_eq!(ok(&mut sim, 255, 0, 0, 1234), 0);
}

#[test]
fn frames_after_a_reset_in_the_same_chunk_are_lost() {
    let mut sim = sim();
    let mut bytes = frame_to(1, 255, 0, 0, 1234).to_vec();
    bytes.extend(frame_to(1, 6, 1, 0, 0));
    sim.feed(&bytes);
    assert_eq!(sim.take_output().len(), 9);
}

#[test]
fn bank0_settings_are_written_through_and_survive_a_reset() {
    let mut sim = sim();
    ok(&mut sim, 9, 75, 0, 15);
    ok(&mut sim, 9, 77, 0, 1); // autostart
    reset(&mut sim);
    assert_eq!(ok(&mut sim, 10, 75, 0, 0), 15);
    assert_eq!(sim.view().application_status, ApplicationStatus::Running);
}

#[test]
fn user_variables_are_restored_unless_gp85() {
    let mut sim = sim();
    ok(&mut sim, 9, 0, 2, 77);
    ok(&mut sim, 9, 55, 2, 55);
    ok(&mut sim, 9, 60, 2, 60);
    ok(&mut sim, 11, 0, 2, 0);
    ok(&mut sim, 11, 55, 2, 0);
    ok(&mut sim, 9, 0, 2, 1);
    ok(&mut sim, 12, 0, 2, 0); // RSGP
    assert_eq!(ok(&mut sim, 10, 0, 2, 0), 77);
    reset(&mut sim);
    assert_eq!(ok(&mut sim, 10, 0, 2, 0), 77);
    assert_eq!(ok(&mut sim, 10, 55, 2, 0), 55);
    assert_eq!(ok(&mut sim, 10, 60, 2, 0), 0);
    ok(&mut sim, 9, 85, 0, 1);
    reset(&mut sim);
    assert_eq!(ok(&mut sim, 10, 0, 2, 0), 0);
}

#[test]
fn factory_reset_sends_nothing_and_restores_defaults() {
    let mut sim = sim();
    ok(&mut sim, 9, 76, 0, 9);
    ok(&mut sim, 5, 214, 0, 10);
    ok(&mut sim, 7, 214, 0, 0);
    download(&mut sim, 0, &[(1, 0, 0, 1)]);
    assert!(send(&mut sim, 137, 0, 0, 1234).is_empty());
    assert_eq!(ok(&mut sim, 10, 76, 0, 0), 2);
    assert_eq!(ok(&mut sim, 6, 214, 0, 0), 200);
    assert_eq!(sim.program_word(0), Some([0; 7]));
}

#[test]
fn the_run_current_is_stored_and_restored_as_the_manuals_examples_do() {
    // §3.6.7 and §3.6.8 store and restore AP6 (Table 16 prints RW): the
    // frames as the manual prints them, RSAP's checksum corrected
    // (01+08+06 = 0F; the manual prints another, digest D11).
    let mut sim = sim();
    ok(&mut sim, 5, 6, 0, 200); // SAP 6, 0, 200
    sim.feed(&hex("01 07 06 00 00 00 00 00 0E")); // STAP 6, 0
    assert_eq!(sim.take_output(), hex("02 01 64 07 00 00 00 00 6E"));
    ok(&mut sim, 5, 6, 0, 100); // SAP 6, 0, 100
    sim.feed(&hex("01 08 06 00 00 00 00 00 0F")); // RSAP 6, 0
    assert_eq!(sim.take_output(), hex("02 01 64 08 00 00 00 00 6F"));
    assert_eq!(ok(&mut sim, 6, 6, 0, 0), 200); // GAP 6, 0
    // Across a power cycle too (§3.6.8: restored at power-up).
    let dir = tempfile::tempdir().expect("temp dir");
    let config = SimConfig {
        eeprom_file: Some(dir.path().join("eeprom.json")),
        ..SimConfig::default()
    };
    {
        let mut sim = Tmcm1110::new(config.clone());
        ok(&mut sim, 5, 6, 0, 64);
        ok(&mut sim, 7, 6, 0, 0);
        ok(&mut sim, 5, 6, 0, 255);
    }
    let mut sim = Tmcm1110::new(config);
    assert_eq!(ok(&mut sim, 6, 6, 0, 0), 64);
}

#[test]
fn eeprom_file_carries_settings_to_a_new_simulator() {
    let dir = tempfile::tempdir().expect("temp dir");
    let config = SimConfig {
        eeprom_file: Some(dir.path().join("eeprom.json")),
        ..SimConfig::default()
    };
    {
        let mut sim = Tmcm1110::new(config.clone());
        ok(&mut sim, 5, 4, 0, 1234);
        ok(&mut sim, 7, 4, 0, 0);
        ok(&mut sim, 9, 66, 0, 3);
        sim.feed(&frame_to(3, 9, 20, 2, -5));
        sim.feed(&frame_to(3, 11, 20, 2, 0));
        sim.feed(&frame_to(3, 132, 0, 0, 0));
        sim.feed(&frame_to(3, 2, 0, 0, 99));
        sim.feed(&frame_to(3, 133, 0, 0, 0));
        assert_eq!(sim.take_output().len(), 5 * 9);
        assert!(sim.eeprom_problem().is_none());
    }
    let mut sim = Tmcm1110::new(config);
    assert!(sim.eeprom_problem().is_none());
    assert_eq!(sim.address(), 3);
    let gap = |sim: &mut Tmcm1110, command, kind, bank| {
        sim.feed(&frame_to(3, command, kind, bank, 0));
        let out = sim.take_output();
        let bytes: [u8; 9] = out.as_slice().try_into().expect("one reply");
        Reply::from_bytes(&bytes).expect("checksum").value
    };
    assert_eq!(gap(&mut sim, 6, 4, 0), 1234);
    assert_eq!(gap(&mut sim, 10, 20, 2), -5);
    assert_eq!(sim.program_word(0), Some([2, 0, 0, 0, 0, 0, 99]));
}

#[test]
fn a_corrupt_eeprom_file_is_reported_and_factory_settings_used() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("eeprom.json");
    std::fs::write(&path, b"\x00\xFFnot json").expect("write");
    let mut sim = Tmcm1110::new(SimConfig {
        eeprom_file: Some(path),
        ..SimConfig::default()
    });
    let problem = sim
        .eeprom_problem()
        .map(|p| p.to_string())
        .unwrap_or_default();
    assert!(problem.contains("eeprom.json"), "{problem}");
    assert_eq!(ok(&mut sim, 10, 76, 0, 0), 2);
}

#[test]
fn an_unfinished_download_is_written_when_the_simulator_goes_away() {
    let dir = tempfile::tempdir().expect("temp dir");
    let config = SimConfig {
        eeprom_file: Some(dir.path().join("eeprom.json")),
        ..SimConfig::default()
    };
    {
        let mut sim = Tmcm1110::new(config.clone());
        ok(&mut sim, 132, 0, 0, 0);
        ask(&mut sim, 28, 0, 0, 0); // STOP stored at 0
    }
    let sim = Tmcm1110::new(config);
    assert_eq!(sim.program_word(0), Some([28, 0, 0, 0, 0, 0, 0]));
}

#[test]
fn flush_eeprom_writes_pending_changes() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("eeprom.json");
    let mut sim = Tmcm1110::new(SimConfig {
        eeprom_file: Some(path.clone()),
        ..SimConfig::default()
    });
    ok(&mut sim, 132, 0, 0, 0);
    ask(&mut sim, 28, 0, 0, 0);
    assert!(!path.exists());
    sim.flush_eeprom();
    assert!(path.exists());
}

#[test]
fn download_writes_the_file_once_at_the_end() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("eeprom.json");
    let mut sim = Tmcm1110::new(SimConfig {
        eeprom_file: Some(path.clone()),
        ..SimConfig::default()
    });
    ok(&mut sim, 132, 0, 0, 0);
    ask(&mut sim, 3, 0, 0, 0);
    assert!(!path.exists(), "written during the download");
    ok(&mut sim, 133, 0, 0, 0);
    assert!(path.exists());
}

// ---- help ---------------------------------------------------------------------

#[test]
fn help_line_lists_the_simulator_defaults() {
    let sim = sim();
    let line = sim.help_line();
    assert!(!line.contains('\n'));
    for needle in [
        "1110V112",
        "2048",
        "AP167 5",
        "GP76 2",
        "10 ms",
        "answer 3",
        "AP4 1000",
        "AP153 7",
        "left limit at -200000",
        "end switches actuated for 51200 beyond that",
        "home switch over -1000..1000",
        "50 µs per program command",
    ] {
        assert!(line.contains(needle), "{needle} missing from {line}");
    }
}
