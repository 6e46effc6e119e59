//! One axis on its own, tick by tick: the servo loop, the following-error
//! trip, motor on and off, abort, the stepper's steps and stall.

use super::settings::AxisKind;
use super::tick::Trip;
use super::*;

const DT: f64 = 0.001;

fn tick(axis: &mut Axis, n: usize) -> Option<Trip> {
    let mut trip = None;
    for _ in 0..n {
        let from = axis.position();
        axis.trajectory_tick(DT);
        axis.drive_tick(DT);
        trip = trip.or(axis.check_tick(DT, from, AxisInputs::default()).trip);
    }
    trip
}

fn servo() -> Axis {
    let mut axis = Axis::new(1, AxisKind::Servo);
    axis.motor_on();
    axis
}

#[test]
fn the_servo_shaft_closes_on_a_step_under_its_pid() {
    let mut axis = servo();
    axis.settings.following_limit = 0.0;
    axis.mode = Mode::Gain;
    axis.record.start_recording(8);
    axis.move_to(20.0);
    tick(&mut axis, 1);
    // Four loop samples at 4 kHz (HS); the first drives SG × 20 = 0.8 V.
    assert_eq!(axis.record.samples.len(), 4);
    assert!((axis.record.samples[0].output - 0.8).abs() < 1e-12);
    assert!(axis.shaft > 0.0 && axis.shaft < 20.0, "{}", axis.shaft);
    tick(&mut axis, 100);
    assert_eq!(axis.position(), 20.0);
    assert_eq!(axis.following_error(), 0.0);
}

#[test]
fn a_following_error_over_se_trips_and_turns_off() {
    let mut axis = servo();
    axis.settings.following_limit = 100.0;
    axis.mode = Mode::Gain;
    axis.move_to(1000.0);
    assert_eq!(tick(&mut axis, 1), Some(Trip::FollowingError));
    assert!(!axis.motor_on);
    assert!(axis.has_motor_error());
    assert_eq!(
        axis.latched & status::FOLLOWING_ERROR,
        status::FOLLOWING_ERROR
    );
    // Off, the shaft stays; a move only sets the target (Ch7 MA).
    let here = axis.shaft;
    axis.move_to(5000.0);
    tick(&mut axis, 10);
    assert_eq!(axis.shaft, here);
    assert_eq!(axis.target, 5000.0);
    assert!(axis.trajectory_complete(), "no trajectory while off");
    assert!(!axis.at_target());
    // MN: target and optimal take the position; the errors clear.
    axis.motor_on();
    assert_eq!(axis.target, axis.position());
    assert!(!axis.has_motor_error());
}

#[test]
fn abort_stops_where_the_motor_is() {
    let mut axis = servo();
    axis.move_to(100_000.0);
    tick(&mut axis, 200);
    axis.abort();
    assert_eq!(axis.target, axis.position());
    assert_eq!(axis.velocity, 0.0);
    tick(&mut axis, 50);
    assert!(axis.trajectory_complete());
}

#[test]
fn a_stepper_steps_and_a_stalled_one_does_not_turn() {
    let mut axis = Axis::new(5, AxisKind::Stepper);
    axis.motor_on();
    axis.move_to(500.0);
    tick(&mut axis, 1000);
    assert_eq!((axis.position(), axis.shaft), (500.0, 500.0));
    assert!(axis.at_target());
    axis.stalled = true;
    axis.move_to(800.0);
    tick(&mut axis, 1000);
    assert_eq!(axis.position(), 800.0, "open loop counts its steps");
    assert_eq!(axis.shaft, 500.0, "the shaft did not turn");
}

#[test]
fn dh_redefines_every_position_without_moving() {
    let mut axis = servo();
    axis.move_to(300.0);
    tick(&mut axis, 500);
    let shaft = axis.shaft;
    axis.redefine(-300.0);
    assert_eq!(axis.position(), 0.0);
    assert_eq!(axis.target, 0.0);
    assert_eq!(axis.index_phase, INDEX_PHASE - 300.0, "the marks move too");
    tick(&mut axis, 10);
    assert!((axis.shaft - (shaft - 300.0)).abs() < 1e-9);
}

#[test]
fn at_target_with_no_delay_still_needs_the_deadband() {
    let mut axis = servo();
    axis.settings.target_delay = 0.0;
    axis.settings.following_limit = 0.0;
    axis.mode = Mode::Gain;
    axis.move_to(1000.0);
    tick(&mut axis, 1);
    assert!(!axis.at_target(), "far from the target");
    tick(&mut axis, 100);
    assert!(axis.at_target());
}
