//! The demo stage (`LIMITS=right|swapped`) from the port: the lines are
//! the manual's commands typed out (Ch5 LN, LM, MN; Ch7 VM, DI, SV, GO;
//! Ch8 TS, TP), the status bits those of Ch8 TS.

use super::Session;
use crate::sim::mccl::axis::status;
use crate::sim::mccl::stage::{END_STOP_AT, LIMIT_AT};

/// Run axis 1 toward + in velocity mode at 20,000 counts/s (Ch7 VM: DI0
/// is the + direction) with both hard limits on (LN3) and a limit
/// decelerating it (LM2), the motor on (MN).
fn run_plus(s: &mut Session) {
    s.quiet(&["1LN3,1LM2,1MN", "1VM,1DI0,1SV20000,1GO"]);
}

/// Time passes 10 ms at a time until TS of axis 1 has `bit`: the
/// position then.
fn until(s: &mut Session, bit: u32, limit_ms: u64) -> f64 {
    for _ in 0..limit_ms / 10 {
        s.advance_ms(10);
        s.take_prompt();
        if s.status(1) & bit != 0 {
            return s.tell("1TP");
        }
    }
    panic!("TS bit {bit:#x} not set after {limit_ms} ms");
}

#[test]
fn wired_right_the_plus_end_closes_limit_plus_and_lm2_stops_the_axis() {
    let mut s = Session::new();
    s.drive("LIMITS=right");
    run_plus(&mut s);
    let at = until(&mut s, status::LIMIT_PLUS_INPUT, 10_000);
    // Read within one 10 ms look (200 counts) of the switch.
    assert!((LIMIT_AT..LIMIT_AT + 400.0).contains(&at), "{at}");
    s.advance_ms(2_000);
    let ts = s.status(1);
    let tripped = status::HARD_LIMIT_PLUS | status::MOTOR_ERROR | status::MOTOR_ON;
    assert_eq!(ts & tripped, tripped, "LM2: tripped, still on: {ts:#x}");
    assert_eq!(ts & status::LIMIT_MINUS_INPUT, 0);
    assert_eq!(s.line("1TV"), ["01 0"], "decelerated to a stand");
    let rest = s.tell("1TP");
    assert!(
        rest > at && rest < END_STOP_AT,
        "stopped short of the stop: {rest}"
    );
}

#[test]
fn swapped_the_plus_end_closes_limit_minus_and_the_servo_runs_into_the_end_stop() {
    let mut s = Session::new();
    s.drive("LIMITS=swapped");
    run_plus(&mut s);
    let at = until(&mut s, status::LIMIT_MINUS_INPUT, 10_000);
    assert!((LIMIT_AT..LIMIT_AT + 400.0).contains(&at), "{at}");
    let ts = s.status(1);
    assert_eq!(
        ts & (status::MOTOR_ERROR | status::LIMIT_PLUS_INPUT),
        0,
        "the - switch stops only motion toward - (Ch5 LN): {ts:#x}"
    );
    // The stop holds the shaft; the loop winds up against it until the
    // following error passes SE (1024 counts by default) and turns the
    // motor off (Ch5 SE), the encoder standing at the stop.
    until(&mut s, status::FOLLOWING_ERROR, 5_000);
    let ts = s.status(1);
    assert_eq!(
        ts & (status::MOTOR_ON | status::HARD_LIMIT_PLUS),
        0,
        "{ts:#x}"
    );
    assert_eq!(s.line("1TP"), [format!("01 {END_STOP_AT}")]);
    s.advance_ms(500);
    assert_eq!(s.tell("1TP"), END_STOP_AT, "held, not blown past");
}

#[test]
fn the_stage_is_off_until_limits_is_given_and_stage_off_removes_it() {
    let mut s = Session::new();
    s.quiet(&["1MN", "1VM,1DI0,1SV20000,1GO"]);
    s.advance_ms(4_000);
    s.take_prompt();
    assert!(s.tell("1TP") > END_STOP_AT, "no end stop without a stage");
    assert_eq!(s.status(1) & status::LIMIT_PLUS_INPUT, 0, "open by default");
    s.quiet(&["1ST"]);
    s.advance_ms(2_000);
    s.drive("LIMITS=right");
    assert_eq!(
        s.tell("1TP"),
        END_STOP_AT,
        "the stage's stop holds the shaft"
    );
    s.advance_ms(10);
    assert_ne!(s.status(1) & status::LIMIT_PLUS_INPUT, 0);
    s.drive("STAGE=off");
    assert_eq!(s.status(1) & status::LIMIT_PLUS_INPUT, 0);
}

#[test]
fn a_stepper_at_the_end_stop_loses_its_steps() {
    // Axis 5, an open-loop stepper: its counter is the steps given.
    let mut s = Session::new();
    s.drive("LIMITS=right");
    s.quiet(&["5MN", "5VM,5DI0,5SV20000,5GO"]);
    s.advance_ms(4_000);
    s.take_prompt();
    let counted = s.tell("5TP");
    assert!(counted > END_STOP_AT + 1_000.0, "steps given: {counted}");
    let shaft = s.sim.axis(5).map(|a| a.shaft);
    assert_eq!(shaft, Some(END_STOP_AT), "the shaft stands at the stop");
    assert_ne!(s.status(5) & status::LIMIT_PLUS_INPUT, 0);
}
