//! The axis on virtual time: ramp timing against the §6.1 formulas, switches,
//! reference search modes of §7.1, encoder and StallGuard stops.

use super::*;
use crate::protocol::tmcl::units::{acceleration_to_pps2, velocity_to_pps};
use proptest::prelude::*;

const TICK_S: f64 = 0.001;

/// Advance in `step`s until `done` holds; returns how many steps it took.
fn run_until(
    axis: &mut Axis,
    step: Duration,
    max_steps: u64,
    events: &mut Vec<AxisEvent>,
    done: impl Fn(&Axis) -> bool,
) -> u64 {
    let mut n = 0;
    while !done(axis) {
        assert!(n < max_steps, "condition not met after {n} steps");
        axis.advance(step, events);
        n += 1;
    }
    n
}

fn count(events: &[AxisEvent], event: AxisEvent) -> usize {
    events.iter().filter(|e| **e == event).count()
}

/// Put the carriage at machine position `at` (counter = machine), at rest.
fn place(axis: &mut Axis, at: i64) {
    axis.anchor = at;
    axis.anchor_frac = 0.0;
    axis.steps = at;
    axis.counter_offset = 0;
    axis.plan = VecDeque::from([Segment::HOLD]);
    axis.segment_ns = 0;
    axis.stored.insert(0, at as i32);
    axis.stored.insert(138, MODE_POSITION);
    axis.last_switches = axis.switch_states();
    axis.plan_blocks = axis.blocks();
}

fn quiet_layout() -> SwitchLayout {
    SwitchLayout::default()
}

/// An axis on a machine without switches.
fn quiet_axis() -> Axis {
    let mut axis = Axis::new();
    *axis.layout_mut() = quiet_layout();
    let mut events = Vec::new();
    axis.advance(Duration::ZERO, &mut events);
    axis
}

// ----- ramp timing -----

/// Moves the axis with the given parameters and checks that AP8 rises in the
/// tick that contains the formula's arrival time, never earlier, with AP1 on
/// the target and the speed never above AP4.
fn check_move_time(distance: i32, ap4: i32, ap5: i32, ramp_div: i32, pulse_div: i32) {
    check_move_time_on(quiet_axis(), distance, ap4, ap5, ramp_div, pulse_div);
}

fn check_move_time_on(
    mut axis: Axis,
    distance: i32,
    ap4: i32,
    ap5: i32,
    ramp_div: i32,
    pulse_div: i32,
) {
    axis.set_param(4, ap4);
    axis.set_param(5, ap5);
    axis.set_param(153, ramp_div);
    axis.set_param(154, pulse_div);
    let v = velocity_to_pps(ap4, pulse_div as u8);
    let a = acceleration_to_pps2(ap5, ramp_div as u8, pulse_div as u8);
    let d = f64::from(distance).abs();
    let expected = if d >= v * v / a {
        v / a + d / v
    } else {
        2.0 * (d / a).sqrt()
    };
    axis.move_to(distance);
    let mut events = Vec::new();
    let mut ticks = 0u64;
    while axis.param(8) == 0 {
        let position = axis.param(1);
        assert!(
            if distance > 0 {
                position < distance
            } else {
                position > distance
            },
            "at {position} before arrival"
        );
        assert!(axis.param(3).abs() <= ap4, "speed {} > AP4", axis.param(3));
        assert!(!events.contains(&AxisEvent::TargetReached));
        axis.advance(TICK, &mut events);
        ticks += 1;
        assert!(ticks < 1_000_000);
    }
    let arrival = ticks as f64 * TICK_S;
    assert!(
        arrival >= expected && arrival < expected + TICK_S,
        "arrived after {arrival} s, formula {expected} s"
    );
    assert_eq!(axis.param(1), distance);
    assert_eq!(axis.param(3), 0);
    assert_eq!(count(&events, AxisEvent::TargetReached), 1);
    assert!(!events.iter().any(|e| matches!(e, AxisEvent::LimitStop(_))));
    assert!(!axis.is_moving());
}

#[test]
fn default_one_turn_move_is_a_trapezoid_of_about_2_3_seconds() {
    let v = velocity_to_pps(1000, 3);
    let a = acceleration_to_pps2(100, 7, 3);
    let t = v / a + 51200.0 / v;
    assert!(t > 2.0 && t < 3.0, "{t}");
    // On the default machine, leaving the home switch on the way.
    check_move_time_on(Axis::new(), 51200, 1000, 100, 7, 3);
}

#[test]
fn trapezoid_times_match_the_formula_for_other_settings() {
    check_move_time(51200, 1500, 300, 7, 3);
    check_move_time(-51200, 800, 40, 8, 4);
    check_move_time(1_000_000, 2047, 2047, 5, 2);
}

#[test]
fn triangle_times_match_two_root_d_over_a() {
    // vmax²/a = 62469²/4657 ≈ 838000 µsteps > 51200: never reaches AP4.
    check_move_time(51200, 2047, 10, 7, 3);
    check_move_time(-3, 1000, 100, 7, 3);
    check_move_time(1, 1000, 100, 7, 3);
}

#[test]
fn tiny_and_uneven_time_steps_give_the_exact_arrival() {
    let setup = || {
        let mut axis = quiet_axis();
        axis.set_param(4, 2047);
        axis.set_param(5, 2000);
        axis.move_to(1000);
        axis
    };
    let a = acceleration_to_pps2(2000, 7, 3);
    let expected = 2.0 * (1000.0 / a).sqrt();
    let expected_ns = (expected * 1e9).ceil() as u64;

    // 1 µs steps.
    let mut axis = setup();
    let mut events = Vec::new();
    let n = run_until(
        &mut axis,
        Duration::from_micros(1),
        200_000,
        &mut events,
        |a| a.param(8) == 1,
    );
    assert!(n * 1000 >= expected_ns && n * 1000 < expected_ns + 1000);

    // Uneven steps arrive at the same nanosecond.
    let mut uneven = setup();
    let pattern = [7u64, 333, 1, 90_001, 12];
    let mut i = 0;
    while uneven.param(8) == 0 {
        uneven.advance(
            Duration::from_nanos(pattern[i % pattern.len()]),
            &mut events,
        );
        i += 1;
    }
    let arrived = uneven.elapsed().as_nanos() as u64;
    let last = pattern[(i - 1) % pattern.len()];
    assert!(arrived >= expected_ns && arrived - last < expected_ns);

    // One big step ends in the same state.
    let mut big = setup();
    big.advance(Duration::from_secs(5), &mut events);
    assert_eq!((big.param(1), big.param(8)), (1000, 1));
}

#[test]
fn advance_by_zero_changes_nothing() {
    let mut axis = Axis::new();
    axis.rotate(500);
    let mut events = Vec::new();
    axis.advance(Duration::from_millis(100), &mut events);
    let before = (axis.param(1), axis.param(3), axis.elapsed());
    axis.advance(Duration::ZERO, &mut events);
    assert_eq!(before, (axis.param(1), axis.param(3), axis.elapsed()));
}

// ----- velocity mode -----

#[test]
fn ror_ramps_up_with_ap5_and_mst_ramps_down() {
    let mut axis = quiet_axis();
    let v = velocity_to_pps(1000, 3);
    let a = acceleration_to_pps2(100, 7, 3);
    let ramp_ticks = (v / a / TICK_S).ceil() as u64;
    let mut events = Vec::new();
    axis.rotate(1000);
    assert_eq!(axis.param(138), 2);
    assert_eq!(axis.param(2), 1000);
    assert_eq!(axis.param(135), 100);
    let mut last = 0;
    for _ in 0..ramp_ticks / 2 {
        axis.advance(TICK, &mut events);
        assert!(axis.param(3) >= last);
        last = axis.param(3);
    }
    assert!((last - 500).abs() <= 2, "{last}");
    axis.advance(TICK * (ramp_ticks - ramp_ticks / 2) as u32, &mut events);
    assert_eq!(axis.param(3), 1000);
    assert_eq!(axis.param(135), 0);
    axis.stop();
    assert_eq!(axis.param(135), -100);
    axis.advance(TICK * (ramp_ticks - 1) as u32, &mut events);
    assert!(axis.is_moving() && axis.param(3) > 0);
    axis.advance(TICK, &mut events);
    assert!(!axis.is_moving());
    assert_eq!(axis.param(3), 0);
    assert!(events.is_empty(), "{events:?}");
}

#[test]
fn rol_runs_negative_and_a_reversal_passes_through_zero() {
    let mut axis = quiet_axis();
    let mut events = Vec::new();
    axis.rotate(-800);
    axis.advance(Duration::from_secs(2), &mut events);
    assert_eq!(axis.param(3), -800);
    assert!(axis.param(1) < 0);
    axis.rotate(800);
    let mut speeds = Vec::new();
    for _ in 0..2000 {
        axis.advance(TICK, &mut events);
        speeds.push(axis.param(3));
    }
    assert_eq!(axis.param(3), 800);
    // Continuous: no step larger than AP5·tick (1.5 [int] here).
    for pair in speeds.windows(2) {
        assert!((pair[1] - pair[0]).abs() <= 2, "{pair:?}");
    }
}

#[test]
fn velocity_mode_is_not_limited_by_ap4() {
    let mut axis = quiet_axis();
    axis.set_param(4, 100);
    axis.rotate(2000);
    let mut events = Vec::new();
    axis.advance(Duration::from_secs(3), &mut events);
    assert_eq!(axis.param(3), 2000);
}

// ----- position mode details -----

#[test]
fn mvp_during_a_move_retargets_smoothly() {
    let mut axis = quiet_axis();
    let mut events = Vec::new();
    axis.move_to(51200);
    axis.advance(Duration::from_secs(1), &mut events);
    let here = axis.param(1);
    assert!(here > 20_000 && here < 25_000, "{here}");
    // Behind us: brake (overshooting), come back.
    axis.move_to(20_000);
    let mut max_position = here;
    run_until(&mut axis, TICK, 20_000, &mut events, |a| a.param(8) == 1);
    let mut last = axis.param(3);
    assert_eq!(axis.param(1), 20_000);
    assert_eq!(count(&events, AxisEvent::TargetReached), 1);
    // Farther away: no stop on the way.
    axis.move_to(0);
    axis.advance(Duration::from_millis(500), &mut events);
    axis.move_to(-100_000);
    let mut min_speed = i32::MAX;
    let mut speeds = vec![axis.param(3)];
    while axis.param(8) == 0 {
        axis.advance(TICK, &mut events);
        speeds.push(axis.param(3));
        max_position = max_position.max(axis.param(1));
        if axis.param(8) == 0 {
            min_speed = min_speed.min(axis.param(3).abs());
        }
        last = axis.param(3);
    }
    assert!(min_speed > 0, "stopped on the way");
    for pair in speeds.windows(2) {
        assert!((pair[1] - pair[0]).abs() <= 2, "{pair:?}");
    }
    assert_eq!(axis.param(1), -100_000);
    assert_eq!(count(&events, AxisEvent::TargetReached), 2);
    assert_eq!(last, 0);
}

#[test]
fn retarget_that_overshoots_keeps_speed_continuous() {
    let mut axis = quiet_axis();
    let mut events = Vec::new();
    axis.move_to(51200);
    axis.advance(Duration::from_secs(1), &mut events);
    let before = axis.velocity_pps();
    axis.move_to(20_000);
    assert_eq!(axis.velocity_pps(), before);
    let mut speeds = vec![axis.param(3)];
    let mut furthest = 0;
    while axis.param(8) == 0 {
        axis.advance(TICK, &mut events);
        speeds.push(axis.param(3));
        furthest = furthest.max(axis.param(1));
    }
    assert!(
        furthest > 25_000,
        "braked with AP5, so it overshot: {furthest}"
    );
    for pair in speeds.windows(2) {
        assert!((pair[1] - pair[0]).abs() <= 2, "{pair:?}");
    }
}

#[test]
fn ror_interrupts_a_positioning_move() {
    let mut axis = quiet_axis();
    let mut events = Vec::new();
    axis.move_to(51200);
    axis.advance(Duration::from_millis(300), &mut events);
    axis.rotate(-500);
    assert_eq!(axis.param(138), 2);
    assert_eq!(axis.param(8), 0);
    axis.advance(Duration::from_secs(3), &mut events);
    assert_eq!(axis.param(3), -500);
    assert!(!events.contains(&AxisEvent::TargetReached));
}

#[test]
fn lowering_ap4_during_a_move_slows_down_to_it() {
    let mut axis = quiet_axis();
    let mut events = Vec::new();
    axis.move_to(150_000);
    axis.advance(Duration::from_secs(1), &mut events);
    assert_eq!(axis.param(3), 1000);
    axis.set_param(4, 500);
    axis.advance(Duration::from_secs(1), &mut events);
    assert_eq!(axis.param(3), 500);
    run_until(&mut axis, TICK, 100_000, &mut events, |a| a.param(8) == 1);
    assert_eq!(axis.param(1), 150_000);
}

#[test]
fn mvp_beyond_2_pow_31_goes_the_short_way_round() {
    for (start, target, travel) in [
        (i32::MAX - 1000, i32::MIN + 1000, 2001i64),
        (i32::MIN + 1000, i32::MAX - 1000, -2001),
    ] {
        let mut axis = quiet_axis();
        axis.set_param(1, start);
        assert_eq!(axis.param(1), start);
        let mut events = Vec::new();
        axis.move_to(target);
        let mut machine = Vec::new();
        while axis.param(8) == 0 {
            axis.advance(TICK, &mut events);
            machine.push(axis.machine_position());
        }
        assert_eq!(axis.param(1), target);
        assert_eq!(axis.machine_position(), travel);
        assert!(
            machine
                .iter()
                .all(|m| m.signum() == travel.signum() || *m == 0)
        );
    }
}

#[test]
fn writing_ap1_at_standstill_sets_the_counter_without_moving() {
    let mut axis = Axis::new();
    let mut events = Vec::new();
    axis.set_param(1, 777);
    assert_eq!((axis.param(1), axis.param(0), axis.param(8)), (777, 777, 1));
    axis.advance(Duration::from_secs(1), &mut events);
    assert_eq!(axis.machine_position(), 0);
    assert_eq!(axis.param(1), 777);
    assert!(events.is_empty());
    axis.move_to(1777);
    run_until(&mut axis, TICK, 10_000, &mut events, |a| a.param(8) == 1);
    assert_eq!(axis.machine_position(), 1000);
}

/// §4 Table 16: AP8 is "always set when target position and actual position
/// are equal", whatever the ramp mode; only an arriving move raises the
/// TargetReached event.
#[test]
fn ap8_is_set_whenever_the_counter_equals_ap0() {
    let mut axis = quiet_axis();
    let mut events = Vec::new();
    // ROR 0 with AP0 = AP1: velocity mode, still on the target.
    axis.rotate(0);
    assert_eq!((axis.param(138), axis.param(0), axis.param(1)), (2, 0, 0));
    assert_eq!(axis.param(8), 1);
    // Rotating away clears it.
    axis.rotate(300);
    axis.advance(Duration::from_millis(500), &mut events);
    assert!(axis.param(1) > 0);
    assert_eq!(axis.param(8), 0);
    // Rotating back through AP0 sets it for as long as the counter is there.
    axis.rotate(-300);
    run_until(
        &mut axis,
        Duration::from_micros(10),
        1_000_000,
        &mut events,
        |a| a.param(1) <= 0,
    );
    assert_eq!(axis.param(1), 0);
    assert_eq!(axis.param(8), 1);
    assert!(axis.is_moving());
    axis.advance(Duration::from_millis(10), &mut events);
    assert!(axis.param(1) < 0);
    assert_eq!(axis.param(8), 0);
    assert!(!events.contains(&AxisEvent::TargetReached));
}

#[test]
fn mvp_to_where_the_motor_is_reports_arrival_at_once() {
    let mut axis = Axis::new();
    let mut events = Vec::new();
    axis.move_to(0);
    axis.advance(Duration::ZERO, &mut events);
    assert_eq!(events, vec![AxisEvent::TargetReached]);
}

#[test]
fn sap_0_moves_without_clearing_ap207_and_mvp_clears_it() {
    let mut axis = quiet_axis();
    axis.stored.insert(207, 3);
    axis.set_param(0, 1000);
    assert_eq!(axis.param(207), 3);
    let mut events = Vec::new();
    run_until(&mut axis, TICK, 10_000, &mut events, |a| a.param(8) == 1);
    assert_eq!(axis.param(1), 1000);
    assert_eq!(count(&events, AxisEvent::TargetReached), 1);
    axis.move_to(0);
    assert_eq!(axis.param(207), 0);
    axis.stored.insert(207, 1);
    axis.rotate(1);
    assert_eq!(axis.param(207), 0);
    axis.stored.insert(207, 1);
    axis.stop();
    assert_eq!(axis.param(207), 0);
    axis.stored.insert(207, 1);
    axis.start_reference_search();
    assert_eq!(axis.param(207), 0);
}

#[test]
fn soft_mode_lands_exactly_and_ap130_shortens_the_tail() {
    let run = |ap130: i32| {
        let mut axis = quiet_axis();
        axis.set_param(130, ap130);
        axis.set_param(0, 51200);
        axis.set_param(138, 1);
        let mut events = Vec::new();
        let mut speeds = Vec::new();
        let ticks = run_until(&mut axis, TICK, 100_000, &mut events, |a| a.param(8) == 1);
        while speeds.len() < 3 {
            speeds.push(axis.param(3));
        }
        assert_eq!(axis.param(1), 51200);
        assert_eq!(axis.param(138), 1);
        assert_eq!(count(&events, AxisEvent::TargetReached), 1);
        ticks
    };
    let v = velocity_to_pps(1000, 3);
    let a = acceleration_to_pps2(100, 7, 3);
    let trapezoid_ticks = ((v / a + 51200.0 / v) / TICK_S).ceil() as u64;
    let slow = run(1);
    let quick = run(100);
    assert!(slow > trapezoid_ticks, "{slow} vs {trapezoid_ticks}");
    assert!(quick < slow, "{quick} vs {slow}");
}

#[test]
fn soft_mode_speed_decays_without_exceeding_ap4() {
    let mut axis = quiet_axis();
    axis.set_param(0, 51200);
    axis.set_param(138, 1);
    let mut events = Vec::new();
    let mut peak_seen = false;
    let mut last = 0;
    while axis.param(8) == 0 {
        axis.advance(TICK, &mut events);
        let speed = axis.param(3);
        assert!(speed <= 1000);
        if speed == 1000 {
            peak_seen = true;
        }
        if peak_seen && axis.param(135) < 0 {
            assert!(speed <= last);
        }
        last = speed;
    }
    assert!(peak_seen);
}

// ----- switches -----

fn stage_with_right_limit_at(right: i64) -> Axis {
    let mut axis = Axis::new();
    *axis.layout_mut() = SwitchLayout {
        left_limit: Some(-right),
        right_limit: Some(right),
        end_switch_width: DEFAULT_END_SWITCH_WIDTH,
        home: None,
        ..SwitchLayout::default()
    };
    let mut events = Vec::new();
    axis.advance(Duration::ZERO, &mut events);
    axis
}

#[test]
fn right_limit_hard_stops_exactly_on_the_switch() {
    let mut axis = stage_with_right_limit_at(20_000);
    let mut events = Vec::new();
    axis.rotate(1000);
    let v = velocity_to_pps(1000, 3);
    let a = acceleration_to_pps2(100, 7, 3);
    let expected = v / a + (20_000.0 - v * v / (2.0 * a)) / v;
    let ticks = run_until(&mut axis, TICK, 10_000, &mut events, |a| {
        a.switch(Switch::Right)
    });
    let t = ticks as f64 * TICK_S;
    assert!(t >= expected && t < expected + TICK_S, "{t} vs {expected}");
    assert_eq!(axis.param(1), 20_000);
    assert_eq!(axis.param(3), 0);
    assert_eq!(axis.param(10), 1);
    assert_eq!(
        events,
        vec![
            AxisEvent::SwitchChanged {
                switch: Switch::Right,
                active: true
            },
            AxisEvent::LimitStop(Switch::Right)
        ]
    );
    // Pushing on doesn't move it, and reports no further stop.
    events.clear();
    axis.rotate(1000);
    axis.advance(Duration::from_secs(1), &mut events);
    assert_eq!(axis.param(1), 20_000);
    assert!(events.is_empty(), "{events:?}");
    // Away from the switch is free.
    axis.rotate(-1000);
    axis.advance(Duration::from_secs(1), &mut events);
    assert!(axis.param(1) < 20_000);
    assert_eq!(
        events,
        vec![AxisEvent::SwitchChanged {
            switch: Switch::Right,
            active: false
        }]
    );
}

#[test]
fn left_limit_stops_negative_motion() {
    let mut axis = stage_with_right_limit_at(20_000);
    let mut events = Vec::new();
    axis.rotate(-700);
    run_until(&mut axis, TICK, 10_000, &mut events, |a| !a.is_moving());
    assert_eq!(axis.param(1), -20_000);
    assert_eq!(axis.param(11), 1);
    assert!(events.contains(&AxisEvent::LimitStop(Switch::Left)));
}

#[test]
fn soft_stop_flag_brakes_with_ap5_past_the_switch() {
    let mut axis = stage_with_right_limit_at(20_000);
    axis.set_param(149, 1);
    let mut events = Vec::new();
    axis.rotate(1000);
    run_until(&mut axis, TICK, 10_000, &mut events, |a| {
        a.switch(Switch::Right)
    });
    assert!(axis.is_moving());
    run_until(&mut axis, TICK, 10_000, &mut events, |a| !a.is_moving());
    let v = velocity_to_pps(1000, 3);
    let a = acceleration_to_pps2(100, 7, 3);
    let expected = 20_000.0 + v * v / (2.0 * a);
    assert!((f64::from(axis.param(1)) - expected).abs() <= 1.0);
    assert_eq!(count(&events, AxisEvent::LimitStop(Switch::Right)), 1);
}

#[test]
fn disabled_limit_switch_is_ignored() {
    let mut axis = stage_with_right_limit_at(20_000);
    axis.set_param(12, 1);
    let mut events = Vec::new();
    axis.rotate(1000);
    run_until(&mut axis, TICK, 10_000, &mut events, |a| {
        a.switch(Switch::Right)
    });
    axis.advance(Duration::from_millis(500), &mut events);
    assert!(axis.param(1) > 30_000);
    assert_eq!(axis.param(10), 1, "still on the switch");
    assert_eq!(axis.param(3), 1000);
    assert_eq!(count(&events, AxisEvent::LimitStop(Switch::Right)), 0);
    // Enabling it again while inside stops the motor.
    axis.set_param(12, 0);
    axis.advance(TICK, &mut events);
    assert_eq!(axis.param(3), 0);
    assert_eq!(count(&events, AxisEvent::LimitStop(Switch::Right)), 1);
}

#[test]
fn a_carriage_pushed_past_a_disabled_switch_leaves_its_cam() {
    let mut axis = stage_with_right_limit_at(20_000);
    axis.layout_mut().end_switch_width = 5_000;
    axis.set_param(12, 1);
    let mut events = Vec::new();
    axis.rotate(300);
    run_until(
        &mut axis,
        Duration::from_micros(100),
        1_000_000,
        &mut events,
        |a| a.machine_position() > 20_000 && !a.switch(Switch::Right),
    );
    assert_eq!(
        axis.machine_position(),
        25_001,
        "open one µstep past the width"
    );
    assert_eq!(
        events,
        vec![
            AxisEvent::SwitchChanged {
                switch: Switch::Right,
                active: true
            },
            AxisEvent::SwitchChanged {
                switch: Switch::Right,
                active: false
            }
        ]
    );
    // Back in from beyond, the switch closes at its far edge.
    events.clear();
    axis.rotate(-300);
    run_until(
        &mut axis,
        Duration::from_micros(100),
        1_000_000,
        &mut events,
        |a| a.switch(Switch::Right),
    );
    assert_eq!(axis.machine_position(), 25_000);
    assert!(
        axis.is_moving(),
        "a right switch doesn't stop negative motion"
    );
}

#[test]
fn positioning_into_a_limit_stops_without_reaching() {
    let mut axis = stage_with_right_limit_at(20_000);
    let mut events = Vec::new();
    axis.move_to(50_000);
    axis.advance(Duration::from_secs(5), &mut events);
    assert_eq!(axis.param(1), 20_000);
    assert_eq!(axis.param(8), 0);
    assert!(!events.contains(&AxisEvent::TargetReached));
    assert!(events.contains(&AxisEvent::LimitStop(Switch::Right)));
    axis.move_to(0);
    run_until(&mut axis, TICK, 10_000, &mut events, |a| a.param(8) == 1);
    assert_eq!(count(&events, AxisEvent::TargetReached), 1);
}

#[test]
fn reversed_end_switch_polarity_inverts_the_inputs() {
    let mut axis = stage_with_right_limit_at(20_000);
    let mut events = Vec::new();
    axis.set_end_switch_polarity_reversed(true);
    assert_eq!((axis.param(10), axis.param(11)), (1, 1));
    axis.advance(Duration::ZERO, &mut events);
    assert_eq!(events.len(), 2);
    axis.rotate(1000);
    axis.advance(Duration::from_secs(1), &mut events);
    assert_eq!(axis.param(1), 0, "both directions blocked");
}

#[test]
fn home_switch_edges_are_reported_where_the_window_ends() {
    let mut axis = Axis::new();
    assert_eq!(axis.param(9), 1);
    assert_eq!(axis.layout().home_span(), Some((-1_000, 1_000)));
    let mut events = Vec::new();
    axis.rotate(100);
    run_until(
        &mut axis,
        Duration::from_micros(100),
        100_000,
        &mut events,
        |a| !a.switch(Switch::Home),
    );
    assert_eq!(axis.param(1), 1001);
    assert_eq!(
        events,
        vec![AxisEvent::SwitchChanged {
            switch: Switch::Home,
            active: false
        }]
    );
    axis.set_home_input_inverted(true);
    assert_eq!(axis.param(9), 1);
}

#[test]
fn moving_a_switch_under_the_carriage_is_reported() {
    let mut axis = Axis::new();
    let mut events = Vec::new();
    axis.layout_mut().home = None;
    axis.advance(Duration::ZERO, &mut events);
    assert_eq!(
        events,
        vec![AxisEvent::SwitchChanged {
            switch: Switch::Home,
            active: false
        }]
    );
}

// ----- reference search -----

struct SearchResult {
    axis: Axis,
    events: Vec<AxisEvent>,
}

fn search_from(mode: i32, start: i64, layout: SwitchLayout, inverted_home: bool) -> SearchResult {
    let mut axis = Axis::new();
    *axis.layout_mut() = layout;
    axis.set_home_input_inverted(inverted_home);
    place(&mut axis, start);
    axis.set_param(193, mode);
    axis.start_reference_search();
    let mut events = Vec::new();
    let mut n = 0;
    while axis.reference_search_active() {
        assert!(axis.param(3).abs() <= 1000);
        axis.advance(Duration::from_millis(50), &mut events);
        n += 1;
        assert!(n < 100_000, "search mode {mode} never ended");
    }
    SearchResult { axis, events }
}

/// The search ended at machine position `reference` with the counter 0
/// there, AP197 = the old counter value, and one done event.
fn assert_found(result: &SearchResult, reference: i64) {
    let axis = &result.axis;
    assert_eq!(
        axis.reference_search_outcome(),
        Some(ReferenceOutcome::Found {
            last_reference_position: reference as i32
        })
    );
    assert_eq!(axis.machine_position(), reference);
    assert_eq!(axis.param(1), 0);
    assert_eq!(axis.param(197), reference as i32);
    assert_eq!(axis.param(0), 0);
    assert_eq!(axis.param(8), 1);
    assert!(!axis.is_moving());
    assert_eq!(count(&result.events, AxisEvent::ReferenceSearchDone), 1);
    assert!(
        !result
            .events
            .iter()
            .any(|e| matches!(e, AxisEvent::LimitStop(_)))
    );
}

#[test]
fn mode_1_finds_the_left_switch_and_65_the_right() {
    let r = search_from(1, 50_000, SwitchLayout::DEMO_STAGE, false);
    assert_found(&r, -200_000);
    assert_eq!(r.axis.param(196), 0);
    let r = search_from(65, -50_000, SwitchLayout::DEMO_STAGE, false);
    assert_found(&r, 200_000);
}

/// §7.1.4: mode 4 searches the left switch "from both sides so that the
/// middle of the switch will be found and used as the zero point".
#[test]
fn mode_4_zeroes_on_the_middle_of_the_left_switch_and_68_of_the_right() {
    let middle = DEFAULT_END_SWITCH_WIDTH / 2;
    let r = search_from(4, 50_000, SwitchLayout::DEMO_STAGE, false);
    assert_found(&r, -200_000 - middle);
    assert_eq!(r.axis.param(196), 0);
    // It crossed the switch: out at the far edge and back in.
    let left_edges: Vec<bool> = r
        .events
        .iter()
        .filter_map(|e| match e {
            AxisEvent::SwitchChanged {
                switch: Switch::Left,
                active,
            } => Some(*active),
            _ => None,
        })
        .collect();
    assert_eq!(left_edges, [true, false, true, false, true]);
    assert_eq!(r.axis.param(11), 1, "standing on the switch");
    let r = search_from(68, -50_000, SwitchLayout::DEMO_STAGE, false);
    assert_found(&r, 200_000 + middle);
    // Starting on the switch finds the same middle.
    let r = search_from(4, -240_000, SwitchLayout::DEMO_STAGE, false);
    assert_found(&r, -200_000 - middle);
    let narrow = SwitchLayout {
        end_switch_width: 1_001,
        ..SwitchLayout::DEMO_STAGE
    };
    // Edges at −200000 and −201001: the middle rounds towards negative.
    assert_found(&search_from(4, 0, narrow, false), -200_501);
}

#[test]
fn search_starting_on_the_switch_still_finds_its_edge() {
    let r = search_from(
        1,
        -200_000 - DEFAULT_END_SWITCH_WIDTH,
        SwitchLayout::DEMO_STAGE,
        false,
    );
    assert_found(&r, -200_000);
}

#[test]
fn limit_disables_do_not_influence_the_search() {
    let mut axis = Axis::new();
    place(&mut axis, 10_000);
    axis.set_param(13, 1);
    axis.set_param(193, 1);
    axis.start_reference_search();
    let mut events = Vec::new();
    run_until(
        &mut axis,
        Duration::from_millis(50),
        10_000,
        &mut events,
        |a| !a.reference_search_active(),
    );
    assert_eq!(axis.machine_position(), -200_000);
    assert_eq!(axis.param(1), 0);
}

#[test]
fn mode_2_zeroes_on_the_left_switch_and_measures_the_distance() {
    let r = search_from(2, 0, SwitchLayout::DEMO_STAGE, false);
    assert_found(&r, -200_000);
    assert_eq!(r.axis.param(196), 400_000);
    let r = search_from(66, 0, SwitchLayout::DEMO_STAGE, false);
    assert_found(&r, 200_000);
    assert_eq!(r.axis.param(196), 400_000);
    let asymmetric = SwitchLayout {
        left_limit: Some(-12_345),
        right_limit: Some(67_890),
        end_switch_width: 1_000,
        home: None,
        ..SwitchLayout::default()
    };
    let r = search_from(2, 0, asymmetric, false);
    assert_found(&r, -12_345);
    assert_eq!(r.axis.param(196), 67_890 + 12_345);
}

/// §7.1.3: mode 3 zeroes on "the middle of the left end switch", and AP196
/// is "the distance between the right end switch and the middle of the left
/// end switch".
#[test]
fn mode_3_zeroes_on_the_middle_of_the_left_switch_and_measures_from_the_right() {
    let middle = DEFAULT_END_SWITCH_WIDTH / 2;
    let r = search_from(3, 0, SwitchLayout::DEMO_STAGE, false);
    assert_found(&r, -200_000 - middle);
    assert_eq!(i64::from(r.axis.param(196)), 400_000 + middle);
    // Mirrored: the left switch first, the middle of the right one is zero.
    let r = search_from(67, 0, SwitchLayout::DEMO_STAGE, false);
    assert_found(&r, 200_000 + middle);
    assert_eq!(i64::from(r.axis.param(196)), 400_000 + middle);
    let asymmetric = SwitchLayout {
        left_limit: Some(-12_345),
        right_limit: Some(67_890),
        end_switch_width: 1_000,
        home: None,
        ..SwitchLayout::default()
    };
    let r = search_from(3, 0, asymmetric, false);
    assert_found(&r, -12_845);
    assert_eq!(r.axis.param(196), 67_890 + 12_845);
}

#[test]
fn mode_5_finds_the_upper_edge_of_home_from_either_side() {
    for start in [50_000, -50_000, 0] {
        let r = search_from(5, start, SwitchLayout::DEMO_STAGE, false);
        assert_found(&r, 1_000);
    }
    // From below it first reverses at the left switch.
    let r = search_from(5, -50_000, SwitchLayout::DEMO_STAGE, false);
    assert!(r.events.contains(&AxisEvent::SwitchChanged {
        switch: Switch::Left,
        active: true
    }));
}

#[test]
fn mode_6_finds_the_lower_edge_of_home_from_either_side() {
    for start in [50_000, -50_000, 0] {
        let r = search_from(6, start, SwitchLayout::DEMO_STAGE, false);
        assert_found(&r, -1_000);
    }
    let r = search_from(6, 50_000, SwitchLayout::DEMO_STAGE, false);
    assert!(r.events.contains(&AxisEvent::SwitchChanged {
        switch: Switch::Right,
        active: true
    }));
}

#[test]
fn mode_5_without_a_home_switch_gives_up_at_the_second_limit() {
    let layout = SwitchLayout {
        home: None,
        ..SwitchLayout::DEMO_STAGE
    };
    let r = search_from(5, 0, layout, false);
    assert_eq!(
        r.axis.reference_search_outcome(),
        Some(ReferenceOutcome::Aborted(
            ReferenceAbort::HomeNotBetweenLimits
        ))
    );
    assert_eq!(r.axis.machine_position(), 200_000);
    assert_eq!(r.axis.param(1), 200_000, "counter untouched");
    assert!(!r.axis.is_moving());
    assert_eq!(count(&r.events, AxisEvent::ReferenceSearchDone), 1);
}

#[test]
fn modes_7_and_8_find_the_middle_of_home_searching_negative_and_positive() {
    let layout = SwitchLayout {
        home: Some((3_000, 7_000)),
        ..SwitchLayout::DEMO_STAGE
    };
    // §7.1.7: mode 7 searches in negative direction, 8 in positive.
    assert_found(&search_from(7, 50_000, layout.clone(), false), 5_000);
    assert_found(&search_from(8, 0, layout.clone(), false), 5_000);
    assert_found(&search_from(8, 5_500, layout.clone(), false), 5_000);
    // The other way they run off, through the end switch they ignore, and
    // give up after the maximum travel.
    for (mode, start, direction) in [(7, 0, -1), (8, 50_000, 1)] {
        let r = search_from(mode, start, layout.clone(), false);
        assert_eq!(
            r.axis.reference_search_outcome(),
            Some(ReferenceOutcome::Aborted(ReferenceAbort::TravelExceeded))
        );
        assert_eq!(
            r.axis.machine_position(),
            start + direction * REFERENCE_SEARCH_MAX_TRAVEL
        );
    }
}

#[test]
fn plus_128_finds_an_inverted_home_input_like_the_plain_modes() {
    for (mode, expected) in [(5, 1_000), (6, -1_000), (7, 0), (8, 0)] {
        let start = if mode == 8 { -50_000 } else { 50_000 };
        let plain = search_from(mode, start, SwitchLayout::DEMO_STAGE, false);
        assert_found(&plain, expected);
        let inverted = search_from(mode + 128, start, SwitchLayout::DEMO_STAGE, true);
        assert_found(&inverted, expected);
    }
    // On a normally wired input +128 takes the window for the gap and
    // references on the first position outside it.
    let r = search_from(133, 0, SwitchLayout::DEMO_STAGE, false);
    assert_found(&r, -1_001);
}

#[test]
fn ap197_holds_the_counter_value_not_the_machine_position() {
    let mut axis = Axis::new();
    place(&mut axis, 10_000);
    axis.set_param(1, 123_456);
    axis.set_param(193, 1);
    axis.start_reference_search();
    let mut events = Vec::new();
    run_until(
        &mut axis,
        Duration::from_millis(50),
        10_000,
        &mut events,
        |a| !a.reference_search_active(),
    );
    assert_eq!(axis.param(197), 123_456 - 210_000);
    assert_eq!(axis.param(1), 0);
}

#[test]
fn rfs_stop_aborts_and_decelerates() {
    let mut axis = Axis::new();
    place(&mut axis, 50_000);
    axis.start_reference_search();
    assert!(axis.reference_search_active());
    let mut events = Vec::new();
    axis.advance(Duration::from_secs(1), &mut events);
    assert_eq!(axis.param(3), -1000);
    axis.stop_reference_search();
    assert!(!axis.reference_search_active());
    assert_eq!(
        axis.reference_search_outcome(),
        Some(ReferenceOutcome::Aborted(ReferenceAbort::Stopped))
    );
    assert!(axis.is_moving());
    axis.advance(Duration::from_secs(1), &mut events);
    assert!(!axis.is_moving());
    assert_eq!(axis.param(1) as i64, axis.machine_position());
    assert_eq!(count(&events, AxisEvent::ReferenceSearchDone), 1);
}

#[test]
fn a_motion_command_interrupts_the_search() {
    let mut axis = Axis::new();
    axis.start_reference_search();
    axis.rotate(300);
    assert!(!axis.reference_search_active());
    assert_eq!(
        axis.reference_search_outcome(),
        Some(ReferenceOutcome::Aborted(ReferenceAbort::Interrupted))
    );
}

#[test]
fn undefined_mode_or_zero_speed_ends_the_search_at_once() {
    let mut axis = Axis::new();
    let mut events = Vec::new();
    axis.set_param(193, 9);
    axis.start_reference_search();
    assert!(!axis.reference_search_active());
    assert_eq!(
        axis.reference_search_outcome(),
        Some(ReferenceOutcome::Aborted(ReferenceAbort::InvalidMode(9)))
    );
    axis.set_param(193, 1);
    axis.set_param(195, 0);
    axis.start_reference_search();
    assert_eq!(
        axis.reference_search_outcome(),
        Some(ReferenceOutcome::Aborted(ReferenceAbort::ZeroSpeed))
    );
    axis.advance(Duration::ZERO, &mut events);
    assert_eq!(count(&events, AxisEvent::ReferenceSearchDone), 2);
}

#[test]
fn search_without_its_switch_gives_up_after_the_maximum_travel() {
    let layout = SwitchLayout {
        left_limit: None,
        ..SwitchLayout::DEMO_STAGE
    };
    let r = search_from(1, 0, layout, false);
    assert_eq!(
        r.axis.reference_search_outcome(),
        Some(ReferenceOutcome::Aborted(ReferenceAbort::TravelExceeded))
    );
    assert_eq!(r.axis.machine_position(), -REFERENCE_SEARCH_MAX_TRAVEL);
    assert_eq!(r.axis.param(3), 0);
}

#[test]
fn rfs_status_mode_reads_as_velocity_mode_while_searching() {
    let mut axis = Axis::new();
    place(&mut axis, 50_000);
    axis.start_reference_search();
    assert_eq!(axis.param(138), 2);
    let mut events = Vec::new();
    axis.advance(Duration::from_millis(10), &mut events);
    assert_eq!(axis.param(138), 2);
    assert_eq!(axis.param(8), 0, "left AP0 behind");
}

// ----- encoder and StallGuard -----

#[test]
fn encoder_follows_the_motor_through_the_prescaler() {
    let mut axis = quiet_axis();
    let mut events = Vec::new();
    axis.move_to(1000);
    axis.advance(Duration::from_secs(1), &mut events);
    assert_eq!(axis.param(209), 1000);
    axis.set_param(210, 1024);
    axis.move_to(2000);
    axis.advance(Duration::from_secs(1), &mut events);
    assert_eq!(axis.param(209), 3000);
    // Bits 2..4 select encoder functions, not the prescaler (§6.3).
    axis.set_param(210, 64 | 4 | 8 | 16);
    axis.move_to(2800);
    axis.advance(Duration::from_secs(1), &mut events);
    assert_eq!(axis.param(209), 3100);
    axis.set_param(209, -5);
    assert_eq!(axis.param(209), -5);
    axis.inject_slip(8 * 10);
    assert_eq!(axis.param(209), -15);
}

#[test]
fn encoder_deviation_stops_the_motor_within_a_tick() {
    let mut axis = quiet_axis();
    axis.set_param(212, 100);
    let mut events = Vec::new();
    axis.rotate(500);
    axis.advance(Duration::from_millis(500), &mut events);
    assert!(axis.is_moving());
    assert!(events.is_empty());
    axis.inject_slip(101);
    axis.advance(TICK, &mut events);
    assert_eq!(events, vec![AxisEvent::DeviationStop]);
    assert_eq!(axis.param(207), 2);
    assert_eq!(axis.param(3), 0);
    assert_eq!(axis.param(138), 2);
    assert_eq!(axis.param(2), 0);
    assert!(!axis.is_moving());
    axis.clear_error_flags();
    assert_eq!(axis.param(207), 0);
    // Within the allowance nothing happens.
    let mut calm = quiet_axis();
    calm.set_param(212, 100);
    calm.rotate(500);
    calm.inject_slip(100);
    calm.advance(Duration::from_secs(1), &mut events);
    assert!(calm.is_moving());
}

#[test]
fn stall_stops_once_the_speed_reaches_ap181() {
    let mut axis = quiet_axis();
    axis.set_param(181, 500);
    axis.set_load_percent(100);
    let mut events = Vec::new();
    axis.rotate(1000);
    let ticks = run_until(&mut axis, TICK, 10_000, &mut events, |a| !a.is_moving());
    assert_eq!(events, vec![AxisEvent::StallStop]);
    assert_eq!(axis.param(207), 1);
    // AP3 reaches 500 (rounded) at 499.5/1000 of the ramp time.
    let v = velocity_to_pps(1000, 3);
    let a = acceleration_to_pps2(100, 7, 3);
    let reach = 0.4995 * v / a;
    let t = ticks as f64 * TICK_S;
    assert!(t >= reach && t < reach + TICK_S, "{t} vs {reach}");

    // A loaded motor or AP181 = 0 doesn't stall.
    for (threshold, load) in [(500, 99), (0, 100)] {
        let mut axis = quiet_axis();
        axis.set_param(181, threshold);
        axis.set_load_percent(load);
        axis.rotate(1000);
        let mut events = Vec::new();
        axis.advance(Duration::from_secs(2), &mut events);
        assert!(events.is_empty() && axis.param(3) == 1000);
    }
}

#[test]
fn stall_during_a_search_aborts_it() {
    let mut axis = Axis::new();
    place(&mut axis, 50_000);
    axis.set_param(181, 100);
    axis.set_load_percent(100);
    axis.start_reference_search();
    let mut events = Vec::new();
    axis.advance(Duration::from_secs(1), &mut events);
    assert!(!axis.reference_search_active());
    assert_eq!(
        axis.reference_search_outcome(),
        Some(ReferenceOutcome::Aborted(ReferenceAbort::Stall))
    );
    assert!(events.contains(&AxisEvent::StallStop));
    assert!(events.contains(&AxisEvent::ReferenceSearchDone));
}

#[test]
fn defaults_table_feeds_the_parameters() {
    let axis = Axis::new();
    for d in MOTION_DEFAULTS {
        assert!(Axis::owns_param(d.number), "AP{}", d.number);
        assert_eq!(axis.param(d.number), d.value, "AP{}", d.number);
    }
    assert_eq!(axis.param(140), 8);
    assert_eq!(axis.param(206), DEFAULT_LOAD);
}

// ----- property -----

#[derive(Debug, Clone)]
enum Op {
    Move(i32),
    Rotate(i32),
    Stop,
    SetParam(u8, i32),
    StartSearch(i32),
    StopSearch,
    Advance(u64),
    Slip(i64),
    Load(u8),
    Polarity(bool),
    Layout(Option<i64>, Option<i64>, i64, Option<(i64, i64)>),
}

fn op() -> impl Strategy<Value = Op> {
    let mode = prop::sample::select(vec![
        1, 2, 3, 4, 5, 6, 7, 8, 65, 66, 67, 68, 133, 134, 135, 136,
    ]);
    prop_oneof![
        prop_oneof![-300_000i32..300_000, any::<i32>()].prop_map(Op::Move),
        (-2047i32..=2047).prop_map(Op::Rotate),
        Just(Op::Stop),
        prop_oneof![
            (1i32..=2047).prop_map(|v| Op::SetParam(4, v)),
            (1i32..=2047).prop_map(|v| Op::SetParam(5, v)),
            (0i32..=1).prop_map(|v| Op::SetParam(12, v)),
            (0i32..=1).prop_map(|v| Op::SetParam(13, v)),
            (1i32..=2047).prop_map(|v| Op::SetParam(130, v)),
            (0i32..=2).prop_map(|v| Op::SetParam(138, v)),
            (0i32..=1).prop_map(|v| Op::SetParam(149, v)),
            (0i32..=13).prop_map(|v| Op::SetParam(153, v)),
            (0i32..=13).prop_map(|v| Op::SetParam(154, v)),
            (0i32..=2047).prop_map(|v| Op::SetParam(181, v)),
            (0i32..=2047).prop_map(|v| Op::SetParam(194, v)),
            (0i32..=2047).prop_map(|v| Op::SetParam(195, v)),
            any::<i32>().prop_map(|v| Op::SetParam(1, v)),
            any::<i32>().prop_map(|v| Op::SetParam(0, v)),
            (-2047i32..=2047).prop_map(|v| Op::SetParam(2, v)),
            any::<i32>().prop_map(|v| Op::SetParam(209, v)),
            (0i32..=65_535).prop_map(|v| Op::SetParam(210, v)),
            (0i32..=1000).prop_map(|v| Op::SetParam(212, v)),
        ],
        mode.prop_map(Op::StartSearch),
        Just(Op::StopSearch),
        prop_oneof![1u64..2_000, 1_000u64..3_000_000, 1_000_000u64..60_000_000]
            .prop_map(Op::Advance),
        (-500i64..500).prop_map(Op::Slip),
        (0u8..=100).prop_map(Op::Load),
        any::<bool>().prop_map(Op::Polarity),
        (
            prop::option::of(-400_000i64..0),
            prop::option::of(0i64..400_000),
            -10i64..100_000,
            prop::option::of((-50_000i64..50_000, 0i64..20_000))
        )
            .prop_map(|(l, r, width, h)| Op::Layout(
                l,
                r,
                width,
                h.map(|(a, w)| (a, a + w))
            )),
    ]
}

/// The fastest speed the axis may run at without a new command: AP4 in the
/// position modes, |AP2| in velocity mode, the search speeds while searching.
fn speed_limit(axis: &Axis) -> i32 {
    if axis.reference_search_active() {
        axis.param(194).max(axis.param(195))
    } else if axis.param(138) == 2 {
        axis.param(2).abs()
    } else {
        axis.param(4)
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_commands_never_panic_or_overshoot_the_speed_limit(
        ops in prop::collection::vec(op(), 1..40)
    ) {
        let mut axis = Axis::new();
        let mut events = Vec::new();
        let mut bound = speed_limit(&axis);
        for op in ops {
            match op {
                Op::Advance(us) => {
                    axis.advance(Duration::from_micros(us), &mut events);
                    let speed = axis.param(3).abs();
                    prop_assert!(speed <= bound, "speed {} above {}", speed, bound);
                    bound = speed.max(speed_limit(&axis));
                }
                other => {
                    match other {
                        Op::Move(t) => axis.move_to(t),
                        Op::Rotate(v) => axis.rotate(v),
                        Op::Stop => axis.stop(),
                        Op::SetParam(n, v) => axis.set_param(n, v),
                        Op::StartSearch(m) => {
                            axis.set_param(193, m);
                            axis.start_reference_search();
                        }
                        Op::StopSearch => axis.stop_reference_search(),
                        Op::Slip(s) => axis.inject_slip(s),
                        Op::Load(l) => axis.set_load_percent(l),
                        Op::Polarity(p) => axis.set_end_switch_polarity_reversed(p),
                        Op::Layout(l, r, width, h) => {
                            *axis.layout_mut() = SwitchLayout {
                                left_limit: l,
                                right_limit: r,
                                end_switch_width: width,
                                home: h,
                                ..SwitchLayout::default()
                            };
                        }
                        Op::Advance(_) => {}
                    }
                    bound = axis.param(3).abs().max(speed_limit(&axis));
                }
            }
            // §4 Table 16: AP8 is set exactly when AP1 = AP0.
            prop_assert_eq!(axis.param(8) == 1, axis.param(1) == axis.param(0));
            prop_assert!(axis.param(3).abs() <= 2047);
        }
    }
}
