//! The engine on virtual time: moves end where and when their profiles
//! say, and the §4.3 sequences leave the axes where the manual implies.

use std::time::Duration;

use super::axis::mst;
use super::stage::{Stage, Window};
use super::*;

use Axis::{U, X, Y, Z};

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// §4.3.2, §4.3.5, §4.3.6: LSPD=500, HSPD=5000, ACC=200, DEC=200.
fn example_speeds() -> Motion {
    let mut m = Motion::new();
    m.global.lspd = 500;
    m.global.hspd = 5000;
    m.global.acc = 200;
    m.global.dec = 200;
    m
}

fn moving(m: &Motion, axis: Axis) -> bool {
    m.status(axis) & 7 != 0
}

/// Advance in `step`s until `axis` stops, at most `limit`; the time taken.
fn run_until_idle(m: &mut Motion, axis: Axis, step: Duration, limit: Duration) -> Duration {
    let mut waited = Duration::ZERO;
    while m.is_busy(axis) && waited < limit {
        m.advance(step);
        waited += step;
    }
    assert!(!m.is_busy(axis), "{axis:?} still busy after {limit:?}");
    waited
}

#[test]
fn a_position_move_ends_where_and_when_the_trapezoid_says() {
    // §4.3.2: X to -20000. Ramps of 0.2 s at an average 2750 pps cover
    // 550 pulses each; the cruise covers 18900 at 5000 pps: 3.78 s.
    let mut m = example_speeds();
    m.start(Start::Position {
        targets: vec![(X, -20_000)],
    })
    .expect("move");
    m.advance(ms(100));
    assert_eq!(m.status(X) & 7, mst::ACCELERATING);
    m.advance(ms(1900));
    assert_eq!(m.status(X) & 7, mst::CONSTANT);
    assert_eq!(m.pulse_rate(X), 5000);
    m.advance(ms(2100));
    assert_eq!(m.status(X) & 7, mst::DECELERATING);
    m.advance(ms(79));
    assert!(moving(&m, X), "still moving at 4.179 s");
    assert!(m.counter(X) > -20_000);
    m.advance(ms(2));
    assert!(!m.is_busy(X), "stopped at 4.181 s");
    assert_eq!(m.counter(X), -20_000);
    assert_eq!(m.encoder(X), -20_000);
    assert_eq!(m.status(X), 0, "stopped without error (§4.3.3)");
}

#[test]
fn a_move_to_where_the_axis_stands_ends_at_once() {
    // Seen in a host run: `X0` at 0 held the axis busy for a tick while MST
    // read 0, and the next move in that instant got ?Error Moving.
    let mut m = example_speeds();
    m.start(Start::Position {
        targets: vec![(X, 0)],
    })
    .expect("X0");
    assert!(!m.is_busy(X));
    assert_eq!(m.status(X) & 7, 0);
    m.start(Start::Position {
        targets: vec![(X, 100)],
    })
    .expect("the next move is accepted in the same instant");
    assert!(moving(&m, X));
}

#[test]
fn two_single_axis_moves_run_at_the_same_time() {
    // §4.3.2: X-20000 then Y15000, both under way together.
    let mut m = example_speeds();
    m.start(Start::Position {
        targets: vec![(X, -20_000)],
    })
    .expect("X");
    m.advance(ms(50));
    m.start(Start::Position {
        targets: vec![(Y, 15_000)],
    })
    .expect("Y");
    m.advance(ms(1000));
    assert!(moving(&m, X) && moving(&m, Y));
    // A second command to a moving axis is refused (§2.2.2).
    assert_eq!(
        m.start(Start::Position {
            targets: vec![(X, 0)]
        }),
        Err(Refusal::Moving)
    );
    run_until_idle(&mut m, X, ms(10), Duration::from_secs(10));
    run_until_idle(&mut m, Y, ms(10), Duration::from_secs(10));
    assert_eq!((m.counter(X), m.counter(Y)), (-20_000, 15_000));
}

#[test]
fn per_axis_speeds_win_unless_zero() {
    let mut m = example_speeds();
    m.axis_mut(X).settings.hspd = 2000;
    m.start(Start::Jog {
        axis: X,
        direction: Direction::Plus,
    })
    .expect("jog");
    m.start(Start::Jog {
        axis: Y,
        direction: Direction::Plus,
    })
    .expect("jog");
    m.advance(ms(1000));
    assert_eq!(m.pulse_rate(X), 2000);
    assert_eq!(m.pulse_rate(Y), 5000);
}

#[test]
fn a_jog_runs_until_stop_then_decelerates_to_lspd_and_stops() {
    // §4.3.1: LSPDX=500, HSPDX=5000, ACCX=200, DECX=200, JX-, STOPX.
    let mut m = Motion::new();
    let s = &mut m.axis_mut(X).settings;
    (s.lspd, s.hspd, s.acc, s.dec) = (500, 5000, 200, 200);
    m.start(Start::Jog {
        axis: X,
        direction: Direction::Minus,
    })
    .expect("jog");
    m.advance(ms(1000));
    // 550 pulses of ramp, 0.8 s at 5000.
    assert_eq!(m.counter(X), -4550);
    assert_eq!(m.status(X) & 7, mst::CONSTANT);
    m.stop(Some(X));
    m.advance(ms(100));
    assert_eq!(m.status(X) & 7, mst::DECELERATING);
    assert_eq!(m.pulse_rate(X), 2750);
    m.advance(ms(101));
    assert!(!m.is_busy(X));
    assert_eq!(m.counter(X), -5100);
    assert_eq!(m.status(X), 0);
}

#[test]
fn abort_stops_at_once() {
    let mut m = example_speeds();
    m.start(Start::Jog {
        axis: Z,
        direction: Direction::Plus,
    })
    .expect("jog");
    m.advance(ms(500));
    let at = m.counter(Z);
    m.abort(None);
    assert!(!m.is_busy(Z));
    m.advance(ms(500));
    assert_eq!(m.counter(Z), at);
    assert_eq!(m.status(Z), 0);
}

#[test]
fn an_s_curve_move_takes_the_same_time_and_ends_on_target() {
    let mut m = example_speeds();
    m.axis_mut(X).settings.s_curve = true;
    m.start(Start::Position {
        targets: vec![(X, 20_000)],
    })
    .expect("move");
    m.advance(ms(4179));
    assert!(moving(&m, X));
    m.advance(ms(2));
    assert_eq!(m.counter(X), 20_000);
    assert!(!m.is_busy(X));
}

#[test]
fn a_short_move_is_a_triangle() {
    let mut m = example_speeds();
    m.start(Start::Position {
        targets: vec![(X, 400)],
    })
    .expect("move");
    m.advance(ms(50));
    assert_eq!(m.status(X) & 7, mst::ACCELERATING);
    let t = run_until_idle(
        &mut m,
        X,
        Duration::from_micros(100),
        Duration::from_secs(1),
    );
    assert_eq!(m.counter(X), 400);
    // Peak sqrt(500² + 22500·400) ≈ 3041 pps; each ramp ≈ 0.113 s.
    // (After the 50 ms already waited.)
    assert!(t > ms(170) && t < ms(182), "{t:?}");
}

#[test]
fn incremental_moves_are_relative() {
    let mut m = example_speeds();
    m.global.incremental = true;
    for _ in 0..2 {
        m.start(Start::Position {
            targets: vec![(X, 1000)],
        })
        .expect("move");
        run_until_idle(&mut m, X, ms(10), Duration::from_secs(5));
    }
    assert_eq!(m.counter(X), 2000);
}

#[test]
fn linear_interpolation_moves_both_axes_on_one_line_and_ends_together() {
    // §4.3.5: EINT=1, X-20000Y15000: X is the main axis at 5000 pps.
    let mut m = example_speeds();
    m.start(Start::Position {
        targets: vec![(X, -20_000), (Y, 15_000)],
    })
    .expect("interpolation");
    m.advance(ms(2000));
    let (x, y) = (m.counter(X), m.counter(Y));
    assert!((y * 4 + x * 3).abs() <= 4, "on the line: ({x}, {y})");
    assert_eq!(m.pulse_rate(X), 5000);
    assert_eq!(m.pulse_rate(Y), 3750);
    m.advance(ms(2179));
    assert!(m.is_busy(X) && m.is_busy(Y));
    m.advance(ms(2));
    assert!(!m.is_busy(X) && !m.is_busy(Y));
    assert_eq!((m.counter(X), m.counter(Y)), (-20_000, 15_000));
}

#[test]
fn without_eint_the_axes_move_on_their_own() {
    let mut m = example_speeds();
    m.global.interpolate = false;
    m.start(Start::Position {
        targets: vec![(X, -20_000), (Y, 15_000)],
    })
    .expect("move");
    m.advance(ms(2000));
    assert_eq!(m.pulse_rate(X), 5000);
    assert_eq!(m.pulse_rate(Y), 5000);
    run_until_idle(&mut m, Y, ms(1), Duration::from_secs(10));
    assert!(m.is_busy(X), "Y arrives first");
    run_until_idle(&mut m, X, ms(1), Duration::from_secs(10));
    assert_eq!((m.counter(X), m.counter(Y)), (-20_000, 15_000));
}

#[test]
fn stopping_one_axis_of_an_interpolation_stops_them_all() {
    let mut m = example_speeds();
    m.start(Start::Position {
        targets: vec![(X, 20_000), (Y, 20_000)],
    })
    .expect("move");
    m.advance(ms(1000));
    m.abort(Some(Y));
    assert!(!m.is_busy(X) && !m.is_busy(Y));
    assert_eq!(m.counter(X), m.counter(Y));
}

#[test]
fn a_clockwise_circle_around_1000_0_comes_back_to_the_start() {
    // §4.3.6: CIRXYP1000:0 from (0, 0).
    let mut m = example_speeds();
    m.start(Start::Arc {
        axes: (X, Y),
        rotation: Rotation::Clockwise,
        centre: (1000, 0),
        end_mdeg: None,
        helix_z: None,
    })
    .expect("circle");
    let (mut max_x, mut max_y, mut min_y) = (0, 0, 0);
    let mut steps = 0;
    while m.is_busy(X) && steps < 10_000 {
        m.advance(ms(1));
        steps += 1;
        let (x, y) = (m.counter(X), m.counter(Y));
        let r = (((x - 1000) * (x - 1000) + y * y) as f64).sqrt();
        assert!((r - 1000.0).abs() <= 1.0, "off the circle at ({x}, {y})");
        max_x = max_x.max(x);
        max_y = max_y.max(y);
        min_y = min_y.min(y);
        if x < 500 && steps < 100 {
            // Clockwise from 180°: Y goes up first.
            assert!(y >= 0, "({x}, {y})");
        }
    }
    assert!(!m.is_busy(X));
    assert_eq!((m.counter(X), m.counter(Y)), (0, 0));
    assert_eq!((max_x, max_y, min_y), (2000, 1000, -1000));
}

#[test]
fn arcs_end_at_their_absolute_angle() {
    // ARCXYP0:0:90000 and ARCXYN0:0:90000 from (1000, 0), §2.3.2.1.
    for (rotation, midway_y_sign) in [(Rotation::Clockwise, -1), (Rotation::CounterClockwise, 1)] {
        let mut m = example_speeds();
        m.set_counter(X, 1000);
        m.start(Start::Arc {
            axes: (X, Y),
            rotation,
            centre: (0, 0),
            end_mdeg: Some(90_000),
            helix_z: None,
        })
        .expect("arc");
        m.advance(ms(100));
        assert_eq!(m.counter(Y).signum(), midway_y_sign, "{rotation:?}");
        run_until_idle(&mut m, X, ms(1), Duration::from_secs(10));
        assert_eq!((m.counter(X), m.counter(Y)), (0, 1000), "{rotation:?}");
    }
}

#[test]
fn a_helical_move_takes_z_along_and_holds_u() {
    let mut m = example_speeds();
    m.set_counter(X, 1000);
    m.start(Start::Arc {
        axes: (X, Y),
        rotation: Rotation::CounterClockwise,
        centre: (0, 0),
        end_mdeg: None,
        helix_z: Some(3000),
    })
    .expect("helix");
    m.advance(ms(10));
    assert!(m.is_busy(U), "U is the hidden axis (C.5)");
    assert_eq!(
        m.start(Start::Jog {
            axis: U,
            direction: Direction::Plus
        }),
        Err(Refusal::Moving)
    );
    run_until_idle(&mut m, X, ms(1), Duration::from_secs(10));
    assert_eq!((m.counter(X), m.counter(Y), m.counter(Z)), (1000, 0, 3000));
    assert_eq!(m.counter(U), 0);
    assert!(!m.is_busy(U));
}

#[test]
fn the_result_does_not_depend_on_how_time_is_split() {
    let run = |step: Duration| {
        let mut m = example_speeds();
        m.start(Start::Position {
            targets: vec![(X, 12_345), (Y, -6_789)],
        })
        .expect("move");
        m.start(Start::Jog {
            axis: Z,
            direction: Direction::Minus,
        })
        .expect("jog");
        let mut trace = Vec::new();
        let mut t = Duration::ZERO;
        while t < ms(3000) {
            m.advance(step);
            t += step;
            if t.as_micros().is_multiple_of(250_000) {
                trace.push((m.counter(X), m.counter(Y), m.counter(Z)));
            }
        }
        trace
    };
    assert_eq!(run(ms(250)), run(Duration::from_micros(250)));
    assert_eq!(run(ms(250)), run(Duration::from_micros(50)));
}

#[test]
fn homing_mode_1_negative_ends_on_the_home_edge_at_zero() {
    // §4.3.4: LSPDY=500, HSPDY=5000, ACCY=200, DECY=200, HY-1.
    let mut m = Motion::new();
    let s = &mut m.axis_mut(Y).settings;
    (s.lspd, s.hspd, s.acc, s.dec) = (500, 5000, 200, 200);
    m.set_counter(Y, 777);
    m.start(Start::Home {
        axis: Y,
        direction: Direction::Minus,
        mode: 1,
    })
    .expect("home");
    run_until_idle(&mut m, Y, ms(5), Duration::from_secs(20));
    assert_eq!(m.counter(Y), 0);
    assert_eq!(m.encoder(Y), 0);
    assert_eq!(m.axis(Y).machine_position(), stage::DEMO_HOME.high);
    assert_eq!(m.status(Y), mst::HOME_INPUT, "on the switch, no error");
}

#[test]
fn every_homing_mode_zeroes_the_counter_where_the_appendix_says() {
    // (mode, direction, machine position of the zero, ends at zero).
    let home = stage::DEMO_HOME;
    let cases: &[(u8, Direction, i64, bool)] = &[
        (0, Direction::Minus, home.high, false),
        (1, Direction::Minus, home.high, true),
        // Index pulses at 250 + k·1000: the first past the home edge.
        (2, Direction::Minus, -1750, true),
        (3, Direction::Minus, -1750, false),
        // Reverse from the braking point (about -1550) to -750.
        (4, Direction::Minus, -750, true),
        (5, Direction::Minus, -750, false),
        (6, Direction::Minus, -stage::DEMO_LIMIT + 1, true),
        (7, Direction::Minus, -99_750, true),
        (8, Direction::Minus, -99_750, false),
        (9, Direction::Minus, home.high, true),
        (10, Direction::Minus, -1750, true),
        (11, Direction::Minus, -750, true),
        (12, Direction::Minus, -99_750, true),
        (6, Direction::Plus, stage::DEMO_LIMIT - 1, true),
        (1, Direction::Plus, -2000, true),
    ];
    for &(mode, direction, zero_at, ends_at_zero) in cases {
        let mut m = example_speeds();
        if direction == Direction::Plus && mode == 1 {
            m.axis_mut(X).stage.home = Some(Window::new(-2000, -1000));
            m.set_counter(X, 0);
            // Start below the switch to home upwards onto it.
            m.start(Start::Position {
                targets: vec![(X, -3000)],
            })
            .expect("move below");
            run_until_idle(&mut m, X, ms(10), Duration::from_secs(5));
        }
        m.axis_mut(X).settings.erc = 2;
        m.start(Start::Home {
            axis: X,
            direction,
            mode,
        })
        .unwrap_or_else(|e| panic!("mode {mode}: {e}"));
        run_until_idle(&mut m, X, ms(5), Duration::from_secs(60));
        let machine = m.axis(X).machine_position();
        assert_eq!(
            machine - m.counter(X),
            zero_at,
            "mode {mode} {direction:?}: zero at machine {} (ended at {machine})",
            machine - m.counter(X)
        );
        if ends_at_zero {
            assert_eq!(m.counter(X), 0, "mode {mode} {direction:?} ends on zero");
        } else {
            assert_ne!(m.counter(X), 0, "mode {mode} stops after braking");
            // Braking in the direction of the zeroing leg.
            let last = homing::procedure(mode)
                .and_then(|p| p.legs.last())
                .expect("legs");
            let way = if last.way == homing::Way::Reverse {
                -1
            } else {
                1
            };
            assert_eq!(m.counter(X).signum(), sign(direction) * way, "mode {mode}");
        }
        assert_eq!(
            m.status(X) & mst::BLOCKING_ERRORS,
            0,
            "mode {mode}: no error left (ERC bit 1 clears the limit flag)"
        );
    }
}

#[test]
fn homing_started_on_the_switch_runs_to_the_limit() {
    // A.2 operation 2: home is edge-triggered.
    let mut m = example_speeds();
    m.axis_mut(X).stage.home = Some(Window::new(-500, 500));
    m.start(Start::Home {
        axis: X,
        direction: Direction::Minus,
        mode: 1,
    })
    .expect("home");
    run_until_idle(&mut m, X, ms(10), Duration::from_secs(60));
    assert_eq!(m.axis(X).machine_position(), -stage::DEMO_LIMIT);
    assert_eq!(
        m.status(X) & (mst::MINUS_LIMIT_ERROR | mst::MINUS_LIMIT_INPUT),
        mst::MINUS_LIMIT_ERROR | mst::MINUS_LIMIT_INPUT
    );
}

#[test]
fn a_z_move_stops_on_the_zcnt_plus_one_th_index() {
    let mut m = example_speeds();
    m.axis_mut(X).settings.zcnt = 2;
    m.start(Start::ZMove {
        axis: X,
        direction: Direction::Plus,
    })
    .expect("zmove");
    run_until_idle(&mut m, X, ms(5), Duration::from_secs(10));
    // Index pulses at 250, 1250, 2250: the third.
    assert_eq!(m.counter(X), 2250);
    assert_ne!(m.status(X) & mst::INDEX_INPUT, 0);
}

#[test]
fn an_end_limit_stops_at_once_and_latches_until_clr() {
    let mut m = example_speeds();
    m.start(Start::Jog {
        axis: X,
        direction: Direction::Plus,
    })
    .expect("jog");
    run_until_idle(&mut m, X, ms(10), Duration::from_secs(30));
    assert_eq!(m.counter(X), stage::DEMO_LIMIT);
    assert_eq!(m.status(X), mst::PLUS_LIMIT_INPUT | mst::PLUS_LIMIT_ERROR);
    let jog = |d| Start::Jog {
        axis: X,
        direction: d,
    };
    assert_eq!(m.start(jog(Direction::Plus)), Err(Refusal::PlusLimit));
    assert_eq!(m.start(jog(Direction::Minus)), Err(Refusal::Moving));
    m.clear_errors(X);
    assert_eq!(m.status(X), mst::PLUS_LIMIT_INPUT);
    m.start(jog(Direction::Minus)).expect("away from the limit");
    m.advance(ms(100));
    assert_eq!(m.status(X) & mst::PLUS_LIMIT_INPUT, 0);
}

#[test]
fn with_ierr_a_limit_still_stops_but_latches_nothing() {
    let mut m = example_speeds();
    m.axis_mut(X).stage = Stage::bare();
    m.global.ignore_errors = true;
    m.axis_mut(X).inputs.minus_limit = Some(false);
    m.start(Start::Jog {
        axis: X,
        direction: Direction::Minus,
    })
    .expect("jog");
    m.advance(ms(300));
    m.axis_mut(X).inputs.minus_limit = Some(true);
    m.advance(ms(1));
    assert!(!m.is_busy(X));
    assert_eq!(m.status(X), mst::MINUS_LIMIT_INPUT);
}

#[test]
fn the_emergency_stop_flags_only_the_axes_that_moved() {
    let mut m = example_speeds();
    m.start(Start::Jog {
        axis: X,
        direction: Direction::Plus,
    })
    .expect("jog");
    m.advance(ms(300));
    m.emergency_stop();
    assert!(!m.is_busy(X));
    assert_eq!(m.status(X), mst::EMG_ERROR);
    assert_eq!(m.status(Y), 0);
    // /CEMG held low: nothing starts, and the axis that tried is flagged.
    m.set_emergency_input(true);
    assert_eq!(
        m.start(Start::Jog {
            axis: Y,
            direction: Direction::Plus
        }),
        Err(Refusal::Estop)
    );
    assert_eq!(m.status(Y), mst::EMG_INPUT | mst::EMG_ERROR);
    m.set_emergency_input(false);
    m.clear_errors(Y);
    m.start(Start::Jog {
        axis: Y,
        direction: Direction::Plus,
    })
    .expect("free again");
}

#[test]
fn an_alarm_stops_the_axis_and_refuses_moves() {
    let mut m = example_speeds();
    m.axis_mut(X).settings.erc = 1;
    m.start(Start::Jog {
        axis: X,
        direction: Direction::Plus,
    })
    .expect("jog");
    m.advance(ms(300));
    m.set_alarm(X, true);
    m.advance(Duration::from_micros(100));
    assert!(!m.is_busy(X));
    assert_eq!(
        m.status(X),
        mst::ALARM_INPUT | mst::ALARM_ERROR | mst::ERC_OUTPUT
    );
    // ERCP 0 = 12 µs: gone after a tick.
    m.advance(Duration::from_micros(100));
    assert_eq!(m.status(X) & mst::ERC_OUTPUT, 0);
    let jog = Start::Jog {
        axis: X,
        direction: Direction::Plus,
    };
    assert_eq!(m.start(jog.clone()), Err(Refusal::Alarm));
    m.set_alarm(X, false);
    assert_eq!(m.start(jog.clone()), Err(Refusal::Moving));
    m.clear_errors(X);
    m.start(jog).expect("cleared");
}

#[test]
fn on_the_fly_speed_change_needs_the_window() {
    // §4.3.7 (axis letters restored): LSPDX=1000, HSPDX=50000, JX-,
    // SSPDMX=2, SSPDX=70000.
    let mut m = Motion::new();
    let s = &mut m.axis_mut(X).settings;
    (s.lspd, s.hspd, s.acc, s.dec) = (1000, 50_000, 100, 100);
    m.axis_mut(X).stage = Stage::bare();
    m.start(Start::Jog {
        axis: X,
        direction: Direction::Minus,
    })
    .expect("jog");
    m.advance(ms(500));
    assert_eq!(m.pulse_rate(X), 50_000);
    assert_eq!(m.change_speed(X, 70_000), Err(Refusal::SpeedWindow));
    m.axis_mut(X).settings.sspdm = 2;
    m.change_speed(X, 70_000).expect("SSPD");
    m.advance(ms(10));
    assert_eq!(m.status(X) & 7, mst::ACCELERATING);
    m.advance(ms(500));
    assert_eq!(m.pulse_rate(X), 70_000);
    m.change_speed(X, 20_000).expect("slower");
    m.advance(ms(500));
    assert_eq!(m.pulse_rate(X), 20_000);
    // Refused while braking, with S-curve, and in buffer mode.
    m.stop(Some(X));
    m.advance(ms(5));
    assert_eq!(m.change_speed(X, 30_000), Err(Refusal::OverrideFailed));
    m.axis_mut(X).settings.s_curve = true;
    assert_eq!(m.change_speed(X, 30_000), Err(Refusal::SpeedWindow));
    m.set_buffer(true);
    assert_eq!(m.change_speed(X, 30_000), Err(Refusal::BufferEnabled));
}

#[test]
fn a_new_target_behind_the_axis_makes_it_reverse() {
    let mut m = example_speeds();
    m.start(Start::Position {
        targets: vec![(X, 10_000)],
    })
    .expect("move");
    m.advance(ms(1000));
    assert!(m.counter(X) > 3000);
    m.change_target(X, 2000).expect("T");
    run_until_idle(&mut m, X, ms(1), Duration::from_secs(10));
    assert_eq!(m.counter(X), 2000);
    // Not accepted for a jog.
    m.start(Start::Jog {
        axis: X,
        direction: Direction::Plus,
    })
    .expect("jog");
    assert_eq!(m.change_target(X, 0), Err(Refusal::OverrideFailed));
}

#[test]
fn in_inc_mode_a_new_target_counts_from_the_move_start() {
    let mut m = example_speeds();
    m.set_counter(X, 1000);
    m.global.incremental = true;
    m.start(Start::Position {
        targets: vec![(X, 5000)],
    })
    .expect("move");
    m.advance(ms(500));
    m.change_target(X, 8000).expect("T");
    run_until_idle(&mut m, X, ms(1), Duration::from_secs(10));
    assert_eq!(m.counter(X), 9000);
}

#[test]
fn the_sync_output_turns_on_at_its_position() {
    // §4.3.8: LSPDX=100, HSPDX=1000, SYNCX=1, SYNPX=5000, SYNOX, X5000.
    let mut m = Motion::new();
    let s = &mut m.axis_mut(X).settings;
    (s.lspd, s.hspd) = (100, 1000);
    let sync = &mut m.axis_mut(X).sync;
    sync.config = 1;
    sync.position = 5000;
    let counter = m.counter(X);
    m.axis_mut(X).sync.enable(counter);
    m.start(Start::Position {
        targets: vec![(X, 5000)],
    })
    .expect("move");
    m.advance(ms(4000));
    assert!(!m.axis(X).sync.output);
    run_until_idle(&mut m, X, ms(10), Duration::from_secs(10));
    assert!(m.axis(X).sync.output);
    assert_eq!(m.axis(X).sync.status, sync::SyncStatus::Met);
}

#[test]
fn the_latch_catches_the_counters_at_the_input_edge() {
    let mut m = example_speeds();
    m.axis_mut(Y).latch.enable(true);
    m.start(Start::Jog {
        axis: Y,
        direction: Direction::Plus,
    })
    .expect("jog");
    m.advance(ms(700));
    let at = m.counter(Y);
    m.latch_input(Y);
    m.advance(ms(300));
    let latch = m.axis(Y).latch;
    assert_eq!(latch.status, sync::LatchStatus::Triggered);
    assert_eq!((latch.pulse, latch.encoder), (at, at));
}

#[test]
fn buffered_moves_run_one_after_another_at_their_own_speed() {
    let mut m = example_speeds();
    assert_eq!(
        m.buffer_push(BufferedMove::Linear {
            target: [1, 2, 3],
            speed: 100
        }),
        Err(Refusal::BufferDisabled)
    );
    assert_eq!(m.buffer_start(), Err(Refusal::BufferDisabled));
    m.set_buffer(true);
    m.buffer_push(BufferedMove::Linear {
        target: [1000, 2000, 3000],
        speed: 5000,
    })
    .expect("I");
    m.buffer_push(BufferedMove::Linear {
        target: [1000, 0, 0],
        speed: 3000,
    })
    .expect("I");
    let status = m.buffer_status();
    assert_eq!(
        (status.enabled, status.start, status.end, status.available),
        (true, 0, 2, 98)
    );
    m.advance(ms(100));
    assert_eq!(m.counter(Z), 0, "nothing moves before BSTART");
    m.buffer_start().expect("BSTART");
    // First move: Z is the main axis, 3000 pulses at 5000 pps = 0.6 s.
    m.advance(ms(300));
    assert_eq!(m.pulse_rate(Z), 5000);
    assert_eq!(m.status(Z) & 7, mst::CONSTANT);
    m.advance(ms(301));
    // Both moves have left the registers for the operation register.
    let status = m.buffer_status();
    assert_eq!((status.start, status.end, status.available), (2, 2, 100));
    assert!(m.is_busy(Y), "the second move follows without a stop");
    assert_eq!(m.pulse_rate(Z), 3000);
    m.advance(ms(1000));
    assert!(!m.is_busy(X));
    assert_eq!((m.counter(X), m.counter(Y), m.counter(Z)), (1000, 0, 0));
    for _ in 0..BUFFER_SIZE {
        m.buffer_push(BufferedMove::Linear {
            target: [0, 0, 0],
            speed: 10,
        })
        .expect("room");
    }
    assert_eq!(
        m.buffer_push(BufferedMove::Linear {
            target: [0, 0, 0],
            speed: 10
        }),
        Err(Refusal::BufferFull)
    );
}

#[test]
fn external_start_holds_moves_until_csta() {
    let mut m = example_speeds();
    m.global.external_start = true;
    m.start(Start::Position {
        targets: vec![(X, 1000)],
    })
    .expect("queued");
    m.advance(ms(100));
    assert_eq!(m.counter(X), 0);
    assert_eq!(m.status(X), mst::WAITING_FOR_START);
    m.set_start_input(true);
    assert_eq!(m.status(X) & mst::WAITING_FOR_START, 0);
    m.set_start_input(false);
    run_until_idle(&mut m, X, ms(10), Duration::from_secs(5));
    assert_eq!(m.counter(X), 1000);
}

#[test]
fn with_inp_a_move_completes_when_the_drive_says_so() {
    let mut m = example_speeds();
    m.axis_mut(X).settings.inp = true;
    m.axis_mut(X).inputs.in_position = false;
    m.start(Start::Position {
        targets: vec![(X, 500)],
    })
    .expect("move");
    m.advance(ms(1000));
    assert_eq!(m.counter(X), 500);
    assert!(m.is_busy(X));
    assert_eq!(m.status(X), mst::WAITING_FOR_INP);
    m.axis_mut(X).inputs.in_position = true;
    m.advance(ms(1));
    assert!(!m.is_busy(X));
    assert_eq!(m.status(X), mst::INP_INPUT);
}

#[test]
fn the_slowdown_input_slows_to_lspd_or_stops() {
    for sdc in [0u8, 1] {
        let mut m = example_speeds();
        m.axis_mut(X).stage.slowdown = vec![Window::new(3000, 4000)];
        m.axis_mut(X).settings.sde = 1;
        m.axis_mut(X).settings.sdc = sdc;
        m.start(Start::Position {
            targets: vec![(X, 30_000)],
        })
        .expect("move");
        // At 5000 pps the cam is reached after about 0.7 s.
        m.advance(ms(1000));
        if sdc == 0 {
            assert_eq!(m.pulse_rate(X), 500, "decelerated to LSPD on the cam");
            m.advance(ms(3000));
            assert_eq!(m.pulse_rate(X), 5000, "back to HSPD past it (no latch)");
            run_until_idle(&mut m, X, ms(10), Duration::from_secs(10));
            assert_eq!(m.counter(X), 30_000);
        } else {
            assert!(!m.is_busy(X), "stopped on the cam");
            assert_eq!(m.status(X), mst::SLOWDOWN_STOP | mst::SLOWDOWN_INPUT);
            // Bit 17 does not block motion (footnote 7).
            m.start(Start::Jog {
                axis: X,
                direction: Direction::Minus,
            })
            .expect("may move on");
        }
    }
}

#[test]
fn refusals_come_in_order() {
    let mut m = example_speeds();
    m.axis_mut(X).inputs.plus_limit = Some(true);
    let plus = Start::Position {
        targets: vec![(X, 10)],
    };
    assert_eq!(m.start(plus.clone()), Err(Refusal::PlusLimit));
    m.set_alarm(X, true);
    assert_eq!(m.start(plus.clone()), Err(Refusal::Alarm));
    // Multi-axis: nothing starts if one axis fails.
    let both = Start::Position {
        targets: vec![(Y, 10), (X, 10)],
    };
    assert_eq!(m.start(both), Err(Refusal::Alarm));
    assert!(!m.is_busy(Y));
}

// ---- StepNLoop beyond single-axis moves (§2.5.3, Table 2-26, Table 27) --

/// StepNLoop on `axis` of a drive making `pulses` motor pulses an encoder
/// count (SLR = pulses), SLT 5, SLE 300, SLA 3.
fn closed_loop(m: &mut Motion, axis: Axis, pulses: i64) {
    let a = m.axis_mut(axis);
    a.stage.encoder_ratio = 1.0 / pulses as f64;
    a.step_n_loop.ratio = pulses * 1000;
    a.step_n_loop.tolerance = 5;
    a.step_n_loop.error_range = 300;
    a.step_n_loop.attempts = 3;
    m.enable_step_n_loop(axis, true);
}

/// Advance 1 ms at a time until `axis` is idle, noting every SLS seen.
fn loop_codes_until_idle(m: &mut Motion, axis: Axis) -> Vec<u8> {
    let mut seen = vec![m.loop_status(axis)];
    for _ in 0..20_000 {
        if !m.is_busy(axis) {
            break;
        }
        m.advance(ms(1));
        let code = m.loop_status(axis);
        if seen.last() != Some(&code) {
            seen.push(code);
        }
    }
    assert!(!m.is_busy(axis), "{axis:?} still busy");
    seen
}

#[test]
fn an_interpolated_move_is_verified_and_corrected_per_axis() {
    // X on a 2:1 drive, Y 1:1, both closed loop: X1000 Y500 are encoder
    // positions, the main axis (X, 2000 pulses) runs at HSPD in pulses/s.
    let mut m = example_speeds();
    closed_loop(&mut m, X, 2);
    closed_loop(&mut m, Y, 1);
    m.start(Start::Position {
        targets: vec![(X, 1000), (Y, 500)],
    })
    .expect("move");
    m.advance(ms(300));
    assert_eq!(m.pulse_rate_reading(X), 5000, "any interpolation: pulse/s");
    assert_eq!(m.loop_status(X), sls::MOVING);
    // X misses 40 steps: 20 counts, beyond SLT, within SLE.
    m.lose_steps(X, 40);
    assert_eq!(m.axis(X).deviation(), 20);
    let x_codes = loop_codes_until_idle(&mut m, X);
    assert!(!m.is_busy(Y));
    assert!(
        x_codes.contains(&sls::CORRECTING),
        "X corrects on its own: {x_codes:?}"
    );
    assert_eq!((m.encoder(X), m.encoder(Y)), (1000, 500));
    assert_eq!((m.loop_status(X), m.loop_status(Y)), (sls::IDLE, sls::IDLE));
    assert_eq!(m.position_reading(X), 1000);
    assert_eq!(m.axis(X).deviation(), 0);
}

#[test]
fn each_axis_of_an_interpolation_gets_its_own_verdict() {
    // X may not correct (SLA 0): its miss is an attempt error; Y is in
    // position and stays free.
    let mut m = example_speeds();
    closed_loop(&mut m, X, 1);
    closed_loop(&mut m, Y, 1);
    m.axis_mut(X).step_n_loop.attempts = 0;
    m.start(Start::Position {
        targets: vec![(X, 2000), (Y, 1000)],
    })
    .expect("move");
    m.advance(ms(300));
    m.lose_steps(X, 50);
    run_until_idle(&mut m, X, ms(5), Duration::from_secs(10));
    assert_eq!(m.loop_status(X), sls::ATTEMPT_ERROR);
    assert_eq!(m.loop_status(Y), sls::IDLE);
    assert_eq!(m.encoder(X), 1950);
    let x_back = Start::Position {
        targets: vec![(X, 0), (Y, 0)],
    };
    assert_eq!(m.start(x_back), Err(Refusal::StepNLoop));
    m.start(Start::Position {
        targets: vec![(Y, 0)],
    })
    .expect("Y alone");
}

#[test]
fn a_circle_in_encoder_counts_runs_at_pulse_speed_and_is_verified() {
    // Both axes 2 pulses a count. From encoder (500, 0), ARCXYN0:0:90000
    // ends at encoder (0, 500): 1000 pulses of radius.
    let mut m = example_speeds();
    m.global.hspd = 2000;
    m.set_encoder(X, 500);
    closed_loop(&mut m, X, 2);
    closed_loop(&mut m, Y, 2);
    assert_eq!(m.position_reading(X), 500);
    m.start(Start::Arc {
        axes: (X, Y),
        rotation: Rotation::CounterClockwise,
        centre: (0, 0),
        end_mdeg: Some(90_000),
        helix_z: None,
    })
    .expect("arc");
    assert_eq!(m.loop_status(X), sls::MOVING);
    // A quarter of a 1000-pulse circle is 1571 pulses: at 45° both axes
    // run at 2000·sin 45° pulses/s, read in pulses/s.
    let mut at_45 = None;
    for _ in 0..2000 {
        m.advance(ms(1));
        // Counters from (0, 0) to (-1000, 1000) around (-1000, 0).
        if m.counter(Y) >= m.counter(X) + 1000 && at_45.is_none() {
            at_45 = Some((m.pulse_rate_reading(X), m.pulse_rate_reading(Y)));
            m.lose_steps(Y, 30);
        }
        if !m.is_busy(X) {
            break;
        }
    }
    let (vx, vy) = at_45.expect("passed 45°");
    assert!(
        (1380..=1450).contains(&vx) && (1380..=1450).contains(&vy),
        "{vx} {vy}"
    );
    let y_codes = loop_codes_until_idle(&mut m, Y);
    assert!(y_codes.contains(&sls::CORRECTING), "{y_codes:?}");
    assert_eq!((m.encoder(X), m.encoder(Y)), (0, 500));
    // Y's 30 lost pulses were sent again by the correction.
    assert_eq!((m.counter(X), m.counter(Y)), (-1000, 1030));
    assert_eq!((m.loop_status(X), m.loop_status(Y)), (sls::IDLE, sls::IDLE));
}

#[test]
fn a_helical_z_target_is_an_encoder_position() {
    let mut m = example_speeds();
    m.set_counter(X, 1000);
    closed_loop(&mut m, Z, 2);
    m.start(Start::Arc {
        axes: (X, Y),
        rotation: Rotation::CounterClockwise,
        centre: (0, 0),
        end_mdeg: None,
        helix_z: Some(-250),
    })
    .expect("helix");
    assert_eq!(m.loop_status(Z), sls::MOVING);
    run_until_idle(&mut m, X, ms(1), Duration::from_secs(10));
    assert_eq!(m.encoder(Z), -250);
    assert_eq!(m.counter(Z), -500, "2 pulses a count");
    assert_eq!(m.loop_status(Z), sls::IDLE);
}

#[test]
fn a_stall_in_a_circle_stops_the_whole_interpolation() {
    let mut m = example_speeds();
    m.set_encoder(X, 1000);
    closed_loop(&mut m, X, 1);
    closed_loop(&mut m, Y, 1);
    m.start(Start::Arc {
        axes: (X, Y),
        rotation: Rotation::Clockwise,
        centre: (0, 0),
        end_mdeg: None,
        helix_z: None,
    })
    .expect("circle");
    m.advance(ms(300));
    m.lose_steps(Y, 400);
    m.advance(ms(1));
    assert!(!m.is_busy(X) && !m.is_busy(Y), "C.6: all stop");
    assert_eq!(m.loop_status(Y), sls::STALL_ERROR);
    assert_eq!(m.loop_status(X), sls::IDLE);
    assert_eq!(
        m.start(Start::Jog {
            axis: Y,
            direction: Direction::Plus
        }),
        Err(Refusal::StepNLoop)
    );
}

#[test]
fn stop_and_abort_show_in_sls_until_the_axis_stands() {
    let mut m = example_speeds();
    closed_loop(&mut m, X, 1);
    let jog = Start::Jog {
        axis: X,
        direction: Direction::Plus,
    };
    m.start(jog.clone()).expect("jog");
    assert_eq!(m.loop_status(X), sls::JOGGING);
    m.advance(ms(500));
    m.stop(Some(X));
    assert_eq!(m.loop_status(X), sls::STOPPING);
    m.advance(ms(50));
    assert_eq!(m.loop_status(X), sls::STOPPING, "still braking");
    assert_eq!(
        loop_codes_until_idle(&mut m, X),
        vec![sls::STOPPING, sls::IDLE]
    );
    // ABORT stops at once; its code lasts until the next tick.
    m.start(Start::Position {
        targets: vec![(X, 50_000)],
    })
    .expect("move");
    m.advance(ms(500));
    m.abort(Some(X));
    assert!(!m.is_busy(X));
    assert_eq!(m.loop_status(X), sls::ABORTING);
    let stood = m.encoder(X);
    m.advance(TICK);
    assert_eq!(m.loop_status(X), sls::IDLE);
    assert_eq!(m.position_reading(X), stood, "P reads where it stopped");
    assert_eq!(m.axis(X).deviation(), 0, "no correction after ABORT");
}

#[test]
fn homing_kinds_have_their_own_codes() {
    // Table 27: 6 homing (home switch), 7 Z-homing (ZMOVE), 13 limit
    // homing (modes on an end limit).
    for (start, code) in [
        (
            Start::Home {
                axis: X,
                direction: Direction::Minus,
                mode: 0,
            },
            sls::HOMING,
        ),
        (
            Start::ZMove {
                axis: X,
                direction: Direction::Plus,
            },
            sls::Z_HOMING,
        ),
        (
            Start::Home {
                axis: X,
                direction: Direction::Plus,
                mode: 6,
            },
            sls::LIMIT_HOMING,
        ),
        (
            Start::Home {
                axis: X,
                direction: Direction::Plus,
                mode: 12,
            },
            sls::LIMIT_HOMING,
        ),
    ] {
        let mut m = example_speeds();
        m.global.hspd = 50_000;
        closed_loop(&mut m, X, 1);
        m.start(start.clone()).expect("homing");
        m.advance(ms(10));
        assert_eq!(m.loop_status(X), code, "{start:?}");
        let codes = loop_codes_until_idle(&mut m, X);
        assert_eq!(codes.last(), Some(&sls::IDLE), "{start:?}: {codes:?}");
        assert_eq!(m.axis(X).deviation(), 0);
    }
}

#[test]
fn an_end_limit_stop_is_sls_limit_error_until_clr() {
    let mut m = example_speeds();
    closed_loop(&mut m, X, 1);
    m.start(Start::Jog {
        axis: X,
        direction: Direction::Plus,
    })
    .expect("jog");
    run_until_idle(&mut m, X, ms(10), Duration::from_secs(30));
    assert_eq!(m.loop_status(X), sls::LIMIT_ERROR);
    // The MST limit flag refuses the next move, not StepNLoop.
    let back = Start::Jog {
        axis: X,
        direction: Direction::Minus,
    };
    assert_eq!(m.start(back.clone()), Err(Refusal::Moving));
    m.clear_errors(X);
    assert_eq!(m.loop_status(X), sls::IDLE);
    m.start(back).expect("away from the limit");
}

#[test]
fn a_new_target_with_step_n_loop_is_in_encoder_counts() {
    // 2 pulses a count: X1500, then TX800 on the way; INC counts from
    // where the move began.
    for (incremental, first, change, end) in [(false, 1500, 800, 800), (true, 1500, 300, 400)] {
        let mut m = example_speeds();
        (m.global.lspd, m.global.hspd) = (500, 1000);
        m.set_encoder(X, 100);
        closed_loop(&mut m, X, 2);
        m.global.incremental = incremental;
        let target = if incremental { first - 100 } else { first };
        m.start(Start::Position {
            targets: vec![(X, target)],
        })
        .expect("move");
        m.advance(ms(300));
        m.change_target(X, change).expect("T");
        let codes = loop_codes_until_idle(&mut m, X);
        assert!(!codes.contains(&sls::CORRECTING), "{codes:?}");
        assert_eq!(m.encoder(X), end, "INC {incremental}");
        assert_eq!(m.position_reading(X), end);
    }
}

#[test]
fn an_on_the_fly_speed_with_step_n_loop_is_in_encoder_counts() {
    let mut m = Motion::new();
    m.axis_mut(X).stage = Stage::bare();
    closed_loop(&mut m, X, 2);
    let s = &mut m.axis_mut(X).settings;
    (s.lspd, s.hspd, s.acc, s.dec, s.sspdm) = (500, 1000, 100, 100, 0);
    m.start(Start::Jog {
        axis: X,
        direction: Direction::Plus,
    })
    .expect("jog");
    m.advance(ms(500));
    assert_eq!(m.pulse_rate_reading(X), 1000);
    assert_eq!(m.pulse_rate(X), 2000);
    m.change_speed(X, 1500).expect("SSPD");
    m.advance(ms(500));
    assert_eq!(m.pulse_rate_reading(X), 1500, "encoder counts/s");
    assert_eq!(m.pulse_rate(X), 3000);
}

#[test]
fn the_buffer_does_not_run_with_step_n_loop() {
    // §2.3.4: "cannot be used while StepNLoop is enabled".
    let mut m = example_speeds();
    m.set_buffer(true);
    m.buffer_push(BufferedMove::Linear {
        target: [1000, 0, 0],
        speed: 1000,
    })
    .expect("queued");
    closed_loop(&mut m, Z, 1);
    assert_eq!(m.buffer_start(), Err(Refusal::StepNLoop));
    m.advance(ms(100));
    assert_eq!(m.counter(X), 0);
    // Turned on while the buffer runs: the next move is not fed.
    m.enable_step_n_loop(Z, false);
    m.buffer_push(BufferedMove::Linear {
        target: [2000, 0, 0],
        speed: 1000,
    })
    .expect("queued");
    m.buffer_start().expect("BSTART");
    m.advance(ms(100));
    m.enable_step_n_loop(Y, true);
    run_until_idle(&mut m, X, ms(10), Duration::from_secs(10));
    assert_eq!(m.counter(X), 1000, "the move under way ends, no more");
    assert_eq!(m.buffer_status().available, BUFFER_SIZE - 1);
}

#[test]
fn an_emergency_stop_holds_a_joystick_axis_until_the_stick_is_centred() {
    let mut m = Motion::new();
    m.axis_mut(X).manual_control = true;
    for _ in 0..10 {
        m.joystick_move(X, 1, 10_000.0);
    }
    assert_eq!(m.counter(X), 10);
    assert_eq!(m.pulse_rate(X), 10_000);
    m.emergency_stop();
    assert_eq!(m.pulse_rate(X), 0);
    assert_eq!(m.status(X), mst::EMG_ERROR, "moving: flagged");
    m.clear_errors(X);
    m.joystick_move(X, 1, 10_000.0);
    assert_eq!(m.counter(X), 10, "held while the stick is out");
    m.joystick_move(X, 0, 0.0);
    m.joystick_move(X, 1, 10_000.0);
    assert_eq!(m.counter(X), 11, "free again");
    // The EMG flag alone holds it too.
    m.emergency_stop();
    m.joystick_move(X, 0, 0.0);
    m.joystick_move(X, 1, 10_000.0);
    assert_eq!(m.counter(X), 11, "until CLR");
    m.clear_errors(X);
    m.joystick_move(X, 1, 10_000.0);
    assert_eq!(m.counter(X), 12);
}
