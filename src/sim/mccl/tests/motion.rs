//! Axes on virtual time: the servo's trailing, following-error trips, at
//! target, the profiles against the manual's numbers, velocity and gain
//! mode, limits, homing, steppers open and closed loop, contour, gearing.

use super::*;
use crate::sim::mccl::axis::status;

/// Milliseconds until `axis`'s trajectory is complete (polling TS as a
/// host would, every millisecond).
fn until_complete(s: &mut Session, axis: u8, limit: u64) -> u64 {
    for ms in 0..limit {
        if s.sim.status(axis).unwrap_or(0) & status::TRAJECTORY_COMPLETE != 0 {
            return ms;
        }
        s.advance_ms(1);
    }
    panic!("axis {axis} still moving after {limit} ms");
}

#[test]
fn the_manuals_half_second_ramps_on_a_servo() {
    // Ch5 SV/SA/DS: 100000 c/s, 200000 c/s²: 0.5 s to full speed and back;
    // a 100000-count move is 1.5 s.
    let mut s = Session::new();
    s.quiet(&["1SV100000,1SA200000,1DS200000,1SE0,1MN", "1MR100000"]);
    s.advance_ms(500);
    let speed = s.tell("1TV");
    assert!((speed - 100_000.0).abs() <= 400.0, "{speed} at 0.5 s");
    let ms = 500 + until_complete(&mut s, 1, 2000);
    assert!((1497..=1504).contains(&ms), "{ms} ms");
    assert_eq!(s.tell("1TO"), 100_000.0);
}

#[test]
fn the_servo_trails_at_cruise_by_its_friction_over_sg() {
    let mut s = Session::new();
    s.quiet(&["1SV100000,1SA10000000,1DS10000000,1MN", "1MR1000000"]);
    s.advance_ms(300);
    // At 100000 c/s the plant's viscous friction (400/s) and Coulomb
    // friction (5 mV) ask 4.005 V: SG 0.04 gives that at 100.1 counts.
    let error = s.tell("1TF");
    assert!((error - 100.0).abs() <= 1.0, "TF {error}");
    // A stiffer gain halves it (SG 0.08: 50 counts).
    s.quiet(&["1SG.08"]);
    s.advance_ms(50);
    let error = s.tell("1TF");
    assert!((error - 50.0).abs() <= 1.0, "TF {error}");
}

#[test]
fn a_servo_lands_within_a_count_when_its_trajectory_completes() {
    // The acceptance's `1MN`, `1MA1000`, `1WS`, `1TP`: at the default
    // deceleration the loop trails by a / (gain·SG) = 0.5 counts when the
    // trajectory completes.
    let mut s = Session::new();
    s.quiet(&["1MN", "1MA1000", "1WS"]);
    assert_eq!(s.tell("1TP"), 1000.0);
}

#[test]
fn a_following_error_beyond_se_turns_the_motor_off_and_ws_fails() {
    // Ch5 SE: "if the position error exceeds the specified value the motor
    // error status flag will be set, and the axis will be turned off".
    let mut s = Session::new();
    s.quiet(&["1SE50,1SV100000,1SA10000000,1DS10000000,1MN"]);
    assert_eq!(s.line("1MR100000,1WS"), ["?-13 1WS"]);
    let ts = s.status(1);
    assert_eq!(ts & status::MOTOR_ERROR, status::MOTOR_ERROR);
    assert_eq!(ts & status::FOLLOWING_ERROR, status::FOLLOWING_ERROR);
    assert_eq!(ts & status::MOTOR_ON, 0);
    assert_eq!(s.error("1MR10"), -13, "no motion until MN");
    s.quiet(&["1MN"]);
    assert_eq!(s.status(1) & status::MOTOR_ERROR, 0, "MN clears it");
}

#[test]
fn at_target_needs_the_deadband_for_the_delay() {
    // Ch5 DB/DT: 1DB5, 1DT0.0025 (2.5 ms), 1MR1000,1WT.
    let mut s = Session::new();
    s.quiet(&["1MN,1DB5,1DT0.0025", "1MR1000"]);
    until_complete(&mut s, 1, 1000);
    let ts = s.status(1);
    assert_eq!(ts & status::AT_TARGET, 0, "not yet within DB for DT");
    let exchange = s.exchange("1WT", 100);
    assert!(exchange.ms >= 2, "{} ms", exchange.ms);
    let position = s.tell("1TP");
    assert!((position - 1000.0).abs() <= 5.0, "{position}");
    // A deadband of 0 waits for the exact count.
    s.quiet(&["1DB0", "1MR1000,1WT"]);
    assert_eq!(s.tell("1TP"), 2000.0);
}

#[test]
fn s_curve_and_parabolic_moves_arrive_and_say_so() {
    let mut s = Session::new();
    s.quiet(&["1SE0,1MN,1PS"]);
    assert_eq!(s.line("1TS109"), ["01 1"], "profile word bit 13: S-curve");
    s.quiet(&["1MR100000"]);
    let curve = until_complete(&mut s, 1, 5000);
    s.quiet(&["1PP"]);
    assert_eq!(s.line("1TS110"), ["01 1"], "profile word bit 14: parabolic");
    s.quiet(&["1MR-100000"]);
    let parabola = until_complete(&mut s, 1, 5000);
    assert_eq!(s.tell("1TO"), 0.0);
    // Longer ramps at the same peak acceleration than the trapezoid's 1.5 s:
    // S-curve 2 × 0.785 s + 0.215 s at speed; parabolic 2 × 0.866 s, never
    // at full speed.
    assert!((1783..=1789).contains(&curve), "{curve}");
    assert!((1730..=1736).contains(&parabola), "{parabola}");
}

#[test]
fn velocity_mode_runs_at_sv_until_st() {
    // Ch6 VM: 1VM,2VM,1DI0,2DI1,0GO,0ST.
    let mut s = Session::new();
    s.quiet(&[
        "1MN,2MN,1SE0,2SE0",
        "1VM,2VM",
        "1DI0",
        "2DI1",
        "1SV20000,2SV20000",
        "0GO",
    ]);
    s.advance_ms(500);
    assert_eq!(s.tell("1TV"), 20_000.0);
    assert_eq!(s.tell("2TV"), -20_000.0);
    assert_eq!(s.status(2) & status::DIRECTION, status::DIRECTION);
    let exchange = s.exchange("0ST,0WS", 1000);
    // 20000 c/s at DS 200000: 0.1 s.
    assert!((99..=102).contains(&exchange.ms), "{} ms", exchange.ms);
    assert_eq!(s.tell("1TV"), 0.0);
}

#[test]
fn gain_mode_jumps_the_optimal_position() {
    let mut s = Session::new();
    s.quiet(&["1SE0,1MN,1GM", "1MR1000"]);
    assert_eq!(s.line("1TS128"), ["01 4"], "trajectory mode: gain");
    s.advance_ms(1);
    assert_eq!(s.tell("1TO"), 1000.0);
    s.advance_ms(100);
    assert_eq!(s.tell("1TP"), 1000.0);
}

#[test]
fn the_ts_example_a_hard_limit_tripped() {
    // Ch8 TS: 01 268436489 = limit + input active, hard limit + tripped,
    // trajectory complete, motor error.
    let mut s = Session::new();
    s.quiet(&["1LN1,1LM0,1MN"]);
    s.drive("LIM+1=1");
    s.quiet(&["1MR1000"]);
    s.advance_ms(2);
    assert_eq!(s.line("1TS0"), ["01 268436489"]);
    assert_eq!(s.line("HM,1TS"), ["01 10000409"]);
}

#[test]
fn limits_trip_only_toward_them_and_as_lm_says() {
    let mut s = Session::new();
    s.drive("LIM-2=1");
    // LM2: decelerate and stop under PID; LN2: the - limit.
    s.quiet(&["2SE0,2MN,2LM2,2LN2", "2MR1000,2WS0.1"]);
    assert_eq!(
        s.tell("2TP"),
        1000.0,
        "away from the active - limit: no trip"
    );
    s.quiet(&["2MR-100000"]);
    s.advance_ms(5);
    let ts = s.status(2);
    assert_eq!(ts & status::HARD_LIMIT_MINUS, status::HARD_LIMIT_MINUS);
    assert_eq!(ts & status::MOTOR_ON, status::MOTOR_ON, "LM2 keeps it on");
    // CL23: the normally-closed switch reads active when open (Ch9 CL).
    s.quiet(&["2MN", "CL23"]);
    assert_eq!(s.status(2) & status::LIMIT_MINUS_INPUT, 0);
    s.quiet(&["2MR-10,2WS"]);
    assert_eq!(s.status(2) & status::MOTOR_ERROR, 0);
    // LM + 128 inverts the hard limit input (Ch5 LM 1LM130).
    s.quiet(&["CH23", "2LM130"]);
    assert_eq!(s.status(2) & status::LIMIT_MINUS_INPUT, 0);
}

#[test]
fn soft_limits_stop_moves_beyond_them() {
    // Ch5 HL/LL: 1LM10, 1HL100000, 1LL-100000, 1LN0 — LM 10: decelerate.
    let mut s = Session::new();
    s.quiet(&["1SE0,1MN,1LM10,1HL1000,1LL-1000,1LN0"]);
    assert_eq!(
        s.line("1MR5000,1WS"),
        ["?-13 1WS"],
        "the wait sees the trip"
    );
    s.advance_ms(500);
    let ts = s.status(1);
    assert_eq!(ts & status::SOFT_LIMIT_HIGH, status::SOFT_LIMIT_HIGH);
    let stop = s.tell("1TP");
    assert!(
        stop > 1000.0 && stop < 5000.0,
        "stopped past the limit: {stop}"
    );
    s.quiet(&["1MN", "1MA0,1WS"]);
    assert_eq!(s.status(1) & status::MOTOR_ERROR, 0, "back out after MN");
}

#[test]
fn homing_on_the_index_with_ia_wi_mn() {
    // Ch7 IA: arm, move over the index, WI, MN: the index becomes 1000.
    let mut s = Session::new();
    s.quiet(&["1SE0,1MN,1VM,1SV2000,1DI0,1GO", "1IA1000"]);
    assert_eq!(s.line("1TS17"), ["01 1"], "looking for the index");
    s.advance_ms(400);
    assert_eq!(s.line("1TS18"), ["01 1"], "found");
    s.quiet(&["1WI,1ST,1WS.01"]);
    assert_eq!(s.line("1TS17"), ["01 0"], "WI ends the looking");
    let before = s.tell("1TP");
    s.quiet(&["1MN"]);
    let after = s.tell("1TP");
    // The index mark is at 500 counts: it is now 1000.
    assert_eq!(after - before, 500.0);
    assert_eq!(s.line("1TS21"), ["01 1"], "homed");
    assert_eq!(s.tell("1TZ"), 1000.0, "where the index was seen, redefined");
}

#[test]
fn find_index_blocks_until_it_is_captured() {
    let mut s = Session::new();
    s.quiet(&["1SE0,1MN,1VM,1SV1000,1GO"]);
    let exchange = s.exchange("1FI0", 2000);
    // From 0 at 1000 c/s the mark at 500 passes after about 0.5 s.
    assert!((500..560).contains(&exchange.ms), "{} ms", exchange.ms);
    s.quiet(&["1ST,1WS", "1PM,1MN,1GH,1WS"]);
    let home = s.tell("1TP");
    assert!(home.abs() <= 5.0, "GH returns to the index: {home}");
}

#[test]
fn a_stepper_homes_on_its_home_edge_with_fe() {
    // Ch7 FE: the open-loop stepper's home sensor edge.
    let mut s = Session::new();
    s.quiet(&["5MN,5VM,5SV1000,5DI1,5GO"]);
    s.typed("5FE0\r");
    s.advance_ms(300);
    assert!(s.sim.busy(), "FE stalls the interpreter until captured");
    s.drive("HOME5=1");
    s.advance_ms(2);
    assert!(!s.sim.busy());
    s.take_prompt();
    s.quiet(&["5ST,5WS,5MF,5MN,5PM"]);
    let position = s.tell("5TP");
    // 2 ms past the edge and DS 100000 from 1000 steps/s: a few steps.
    assert!(
        (-10.0..=-2.0).contains(&position),
        "{position} past the edge"
    );
    assert_eq!(s.line("5TS21"), ["05 1"]);
}

#[test]
fn a_stepper_counts_steps_and_a_stalled_closed_loop_trips() {
    let mut s = Session::new();
    s.quiet(&["5MN", "5MR2000,5WS"]);
    assert_eq!(s.tell("5TP"), 2000.0);
    assert_eq!(s.error("5TF"), -2, "no following error open loop");
    s.drive("STALL5=1");
    s.quiet(&["5MR1000,5WS"]);
    assert_eq!(s.tell("5TP"), 3000.0, "open loop: the steps, not the shaft");
    // Closed loop (Ch5 ES example): 25.6 steps per count.
    s.quiet(&["5MF", "5ES25.6", "5IM1", "5SE50", "5MF,5MN"]);
    assert_eq!(s.tell("5TP"), 78.0, "2000 steps of shaft = 78 counts");
    assert_eq!(s.line("5MR200,5WS"), ["?-13 5WS"]);
    assert_eq!(
        s.status(5) & status::FOLLOWING_ERROR,
        status::FOLLOWING_ERROR
    );
}

#[test]
fn a_linear_contour_move_and_its_count() {
    // Ch5 VV: 1CM1,2CM1, VA/VD, 1CP1,1MA10000,2MA20000,1VV25000.
    let mut s = Session::new();
    s.quiet(&[
        "1SE0,2SE0,1MN,2MN",
        "1CM1",
        "2CM1",
        "1VA50000,1VD50000",
        "1CP1,1MA10000,2MA20000,1VV25000",
    ]);
    assert_eq!(s.line("1TS128"), ["01 16"], "contour mode");
    s.advance_ms(200);
    let (x, y) = (s.tell("1TO"), s.tell("2TO"));
    assert!((y - 2.0 * x).abs() < 2.0, "on the line: {x} {y}");
    // 22361 counts at 25000 c/s with 0.5 s ramps: about 1.4 s.
    s.advance_ms(1500);
    assert_eq!((s.tell("1TO"), s.tell("2TO")), (10_000.0, 20_000.0));
    assert_eq!(s.line("1TX"), ["01 1"]);
}

#[test]
fn an_arc_keeps_its_radius_and_counts_two() {
    // Ch7 CA: 1CP2,1CA10000,2CA0,1MA20000,2MA0: 180° clockwise.
    let mut s = Session::new();
    s.quiet(&[
        "1SE0,2SE0,1MN,2MN",
        "1CM1,2CM1",
        "1VV20000,1VA100000,1VD100000",
        "1CP2,1CA10000,2CA0,1MA20000,2MA0",
    ]);
    for _ in 0..10 {
        s.advance_ms(150);
        let (x, y) = (s.tell("1TO"), s.tell("2TO"));
        let r = ((x - 10_000.0).powi(2) + y.powi(2)).sqrt();
        assert!((r - 10_000.0).abs() < 1.0, "{x} {y}");
        assert!(
            y >= -1.0,
            "clockwise from (0,0) about (10000,0) goes up: {y}"
        );
    }
    s.advance_ms(1000);
    assert_eq!(s.line("1TX"), ["01 2"]);
}

#[test]
fn synchronised_moves_wait_for_go() {
    let mut s = Session::new();
    s.quiet(&[
        "1SE0,2SE0,1MN,2MN",
        "1CM1,2CM1",
        "1SN",
        "1CP1,1MR1000,2MR1000",
        "1CP1,1MR1000",
    ]);
    s.advance_ms(100);
    assert_eq!(s.tell("1TO"), 0.0, "buffered");
    assert_eq!(s.line("1TS86"), ["01 1"], "aux bit 22: synchronisation on");
    s.quiet(&["1GO"]);
    s.advance_ms(2000);
    assert_eq!((s.tell("1TO"), s.tell("2TO")), (2000.0, 1000.0));
    assert_eq!(s.line("1TX"), ["01 2"]);
}

#[test]
fn learned_points_are_moved_to() {
    // Ch7 LP: learn two points, move back to them with 0MP.
    let mut s = Session::new();
    s.quiet(&[
        "1SE0,2SE0,1DH0,1MN,2DH0,2MN",
        "1MR250,2MR-100,0WS0.02",
        "1LP1,2LP1",
        "1MR500,2MR300,0WS0.01",
        "1LP2,2LP2",
        "1MA0,2MA0,0WS.25",
        "0MP1,0WS.25",
    ]);
    let (x, y) = (s.tell("1TP"), s.tell("2TP"));
    assert!(
        (x - 250.0).abs() <= 5.0 && (y + 100.0).abs() <= 5.0,
        "{x} {y}"
    );
    assert_eq!(s.error("3MP7"), -1, "never learned");
}

#[test]
fn a_slave_follows_its_master_at_the_ratio() {
    // Ch6 SM: 2SS5, 3SS-0.1, 2SM1,3SM1.
    let mut s = Session::new();
    s.quiet(&[
        "1SE0,2SE0,3SE0,1MN,2MN,3MN",
        "2SS5",
        "3SS-0.1",
        "2SM1,3SM1",
        "1MR1000,1WS",
    ]);
    assert_eq!(s.tell("2TO"), 5000.0);
    assert_eq!(s.tell("3TO"), -100.0);
    assert_eq!(s.line("2TS144"), ["02 1"], "trajectory word bit 16");
    s.quiet(&["2SM0,3SM0", "1MR1000,1WS"]);
    assert_eq!(s.tell("2TO"), 5000.0, "no longer geared");
}

#[test]
fn captures_on_the_capture_input_count_for_cg() {
    // Ch8 CG: 1CG,TR0 → 01 25.
    let mut s = Session::new();
    s.quiet(&["1CB25"]);
    for _ in 0..25 {
        s.drive("IN1=1");
        s.advance_ms(2);
        s.drive("IN1=0");
        s.advance_ms(2);
    }
    assert_eq!(s.line("1CG,TR0"), ["01 25"]);
    assert_eq!(s.line("1TS5"), ["01 1"], "position captured");
}

#[test]
fn interval_compare_counts_for_gc() {
    // Ch7 BC: 1OC3,1OP.01,1LC1000,1NC250,1BC0,1MA3000,1WP2100.
    let mut s = Session::new();
    s.quiet(&[
        "1SE0,1MN",
        "1OC3,1OP.01",
        "1LC1000",
        "1NC250",
        "1BC0",
        "1MA3000,1WP2100",
    ]);
    assert_eq!(s.line("1GC,TR0"), ["01 5"]);
    assert_eq!(s.line("1TS6"), ["01 1"], "breakpoint reached");
    s.quiet(&["1BC-1"]);
}

#[test]
fn recorded_samples_are_displayed() {
    // Ch8 DR: 3PR10,3MA5000,3WS.1 then 3DR@100,… ,RP9.
    let mut s = Session::new();
    s.quiet(&["3SE0,3DH0,3MN", "3PR10,3MA5000,3WS.1", "AL0,AR100"]);
    let lines = s.line("3DR@100,AL@100,AA1,AR100,RP9");
    assert_eq!(lines.len(), 10);
    assert!(lines.iter().all(|l| l.starts_with("03 ")), "{lines:?}");
    assert_eq!(s.error("3DO10"), -1, "only 10 taken");
}

#[test]
fn the_auxiliary_and_encoder_fault_words_show_the_settings() {
    let mut s = Session::new();
    // LN3: hard limits + and - enabled; LM2: hard limits decelerate;
    // FN: amp fault checked; high speed is the servo default.
    s.quiet(&["1LN3,1LM2,1FN"]);
    assert_eq!(s.tell("1TS64") as u32, 1 | 2 | 8 | 1 << 10 | 1 << 18);
    s.quiet(&["1LM132"]);
    assert_eq!(s.line("1TS72"), ["01 1"], "bit 8: positive limit inverted");
    // EE1 and an encoder fault: TS160 and a trip with motor error.
    s.quiet(&["1EE1,1SE0,1MN"]);
    assert_eq!(s.tell("1TS160") as u32, 1 << 12);
    s.drive("ENCFAULT1=1");
    s.advance_ms(2);
    assert_eq!(s.tell("1TS160") as u32, 0b1111 | 1 << 12);
    let ts = s.status(1);
    assert_eq!(ts & status::ENCODER_FAULT, status::ENCODER_FAULT);
    assert_eq!(ts & status::MOTOR_ON, 0);
}

#[test]
fn an_amplifier_fault_turns_the_motor_off_when_checked() {
    let mut s = Session::new();
    s.quiet(&["1MN"]);
    s.drive("FAULT1=1");
    s.advance_ms(2);
    assert_eq!(
        s.status(1) & status::MOTOR_ON,
        status::MOTOR_ON,
        "FF: not checked"
    );
    assert_eq!(s.status(1) & status::FAULT_INPUT, status::FAULT_INPUT);
    s.quiet(&["1FN"]);
    s.advance_ms(2);
    let ts = s.status(1);
    assert_eq!(
        ts & (status::AMP_FAULT | status::MOTOR_ON),
        status::AMP_FAULT
    );
}

#[test]
fn rt_of_an_axis_restores_its_defaults_and_turns_it_off() {
    let mut s = Session::new();
    s.quiet(&["1SV500,1SG.1,1MN,2MN", "1RT"]);
    assert_eq!(s.status(1) & status::MOTOR_ON, 0);
    assert_eq!(s.status(2) & status::MOTOR_ON, status::MOTOR_ON);
    assert_eq!(s.line("1TG.2"), ["01 0.04"]);
    s.quiet(&["AL5,AR500"]);
    assert_eq!(s.typed("PC42\r"), "PC42\r\n*");
    // RT with no axis: the controller, prompt included.
    assert_eq!(s.typed("RT\r"), "RT\r\n>");
    assert_eq!(s.line("TR500"), ["01 0"]);
}
