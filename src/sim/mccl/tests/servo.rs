//! The servo loop on virtual time, driven by the step-response plan of
//! [`crate::protocol::mccl::tune`] and judged by
//! [`crate::protocol::step_response`]: three gain sets give figures in the
//! order control theory expects, the integral removes a friction error,
//! PR records at the HS/MS/LS rate (Ch5, Ch7).

use super::*;
use crate::protocol::mccl::NumberBase;
use crate::protocol::mccl::tune::{Gains, LoopRate, StepKind, StepTest};
use crate::protocol::step_response::{StepFigures, StepSpec, step_figures};
use crate::sim::mccl::axis::status;

/// A 20-count gain-mode step on axis 1, 100 ms recorded at 4 kHz, SE 40.
fn step(proportional: f64, derivative: f64) -> StepTest {
    StepTest {
        axis: 1,
        gains: Gains {
            proportional: Some(proportional),
            derivative: Some(derivative),
            derivative_period: Some(0),
            ..Gains::default()
        },
        rate: LoopRate::High,
        distance: 20,
        samples: 400,
        following_limit: Some(40.0),
        kind: StepKind::Gain,
    }
}

/// Run the plan's lines on the simulator; the figures, and the status word
/// after.
fn run(s: &mut Session, test: &StepTest) -> (StepFigures, u32) {
    for line in test.setup_lines().expect("a valid test") {
        s.quiet(&[line.as_str()]);
    }
    s.quiet(&[test.step_line().as_str(), test.wait_line().as_str()]);
    let mut replies = Vec::new();
    for line in test.readback_lines() {
        replies.extend(s.line(&line));
    }
    let samples = test
        .parse_readback(&replies, NumberBase::Decimal)
        .expect("samples");
    let figures = step_figures(&samples, &StepSpec::default()).expect("figures");
    (figures, s.status(1))
}

#[test]
fn three_gain_sets_damp_ring_and_trip_in_that_order() {
    // The manual's example gains (Ch5 SG: 1sg.04, 1sd.2): well damped.
    let (damped, ts) = run(&mut Session::new(), &step(0.04, 0.2));
    assert_eq!(ts & status::MOTOR_ERROR, 0);
    let damped_settling = damped.settling_time.expect("the damped step settles");
    // (Encoder counts are whole: 2 counts over is 10 %.)
    assert!(damped.overshoot_percent < 11.0, "{damped:?}");
    assert!(!damped.saturated, "0.8 V + a derivative kick of 4 V");
    // No derivative (Ch5 SD: it "has the effect of dampening
    // oscillations"): it rings, overshooting more and settling later.
    let (ringing, ts) = run(&mut Session::new(), &step(0.04, 0.0));
    assert_eq!(ts & status::MOTOR_ERROR, 0);
    assert!(
        ringing.overshoot_percent > damped.overshoot_percent + 20.0,
        "{ringing:?} vs {damped:?}"
    );
    let ringing_settling = ringing.settling_time.expect("it settles in the end");
    assert!(ringing_settling > damped_settling, "{ringing:?}");
    // Far too much proportional gain: the loop oscillates at the
    // amplifier's limits until the following error passes SE 40, and the
    // axis trips as Ch5 SE says: motor error, motor off.
    let mut s = Session::new();
    let (unstable, ts) = run(&mut s, &step(5.0, 0.2));
    assert!(unstable.saturated, "{unstable:?}");
    assert!(unstable.peak_following_error.abs() > 40.0, "{unstable:?}");
    assert_eq!(ts & status::MOTOR_ERROR, status::MOTOR_ERROR);
    assert_eq!(ts & status::FOLLOWING_ERROR, status::FOLLOWING_ERROR);
    assert_eq!(ts & status::MOTOR_ON, 0);
    // Stopped: it stays where it tripped, and the output is 0 V.
    let here = s.tell("1TP");
    s.advance_ms(50);
    assert_eq!(s.tell("1TP"), here);
    assert_eq!(s.line("1DQ399"), ["01 0.000"]);
}

#[test]
fn the_integral_removes_the_error_friction_leaves() {
    // Coulomb friction worth 0.2 V: SG 0.01 alone stops up to 20 counts
    // short, where it can no longer push through.
    let stuck = |s: &mut Session| {
        if let Some(axis) = s.sim.axis_mut(1) {
            axis.servo.plant.coulomb = 0.2 * axis.servo.plant.gain;
        }
    };
    let proportional = StepTest {
        distance: 100,
        samples: 1024,
        following_limit: Some(1024.0),
        ..step(0.01, 0.2)
    };
    let mut s = Session::new();
    stuck(&mut s);
    let (alone, _) = run(&mut s, &proportional);
    assert!(alone.final_following_error.abs() >= 2.0, "{alone:?}");
    assert_eq!(alone.settling_time, None, "outside ±1 count");
    // Ch5 SI with its IL (nothing without IL): the sum of the error
    // pushes it home.
    let integral = StepTest {
        gains: Gains {
            // At most 0.001 × 300 = 0.3 V: enough for the 0.2 V.
            integral: Some(0.001),
            integration_limit: Some(300.0),
            ..proportional.gains
        },
        ..proportional
    };
    let mut s = Session::new();
    stuck(&mut s);
    let (with, _) = run(&mut s, &integral);
    assert!(with.final_following_error.abs() <= 1.0, "{with:?}");
    assert!(with.settling_time.is_some(), "{with:?}");
    // Without IL the integral gain does nothing.
    let no_limit = StepTest {
        gains: Gains {
            integration_limit: Some(0.0),
            ..integral.gains
        },
        ..integral
    };
    let mut s = Session::new();
    stuck(&mut s);
    let (limitless, _) = run(&mut s, &no_limit);
    assert_eq!(limitless.final_following_error, alone.final_following_error);
}

#[test]
fn pr_records_at_the_loop_rate_of_hs_ms_ls() {
    // 25 ms of recording are 100 samples at 4 kHz, 50 at 2 kHz, 25 at 1 kHz.
    for (rate, taken) in [("HS", 100), ("MS", 50), ("LS", 25)] {
        let mut s = Session::new();
        s.quiet(&[&format!("1{rate},1MN"), "1PR1024"]);
        s.advance_ms(25);
        let samples = s.sim.axis(1).map_or(0, |a| a.record.samples.len());
        assert_eq!(samples, taken, "{rate}");
    }
    // PR n takes n and no more; DR beyond them is refused.
    let mut s = Session::new();
    s.quiet(&["1MN", "1PR100"]);
    s.advance_ms(100);
    assert_eq!(s.sim.axis(1).map(|a| a.record.samples.len()), Some(100));
    assert_eq!(s.error("1DR100"), -1);
    // At cruise (100000 counts/s) successive optimal positions are one
    // sample apart: 25 counts at HS, 100 at LS.
    for (rate, apart) in [("HS", 25.0), ("LS", 100.0)] {
        let mut s = Session::new();
        s.quiet(&[
            &format!("1{rate},1SE0,1SA10000000,1DS10000000,1MN"),
            "1MR1000000",
        ]);
        s.advance_ms(100);
        s.quiet(&["1PR3"]);
        s.advance_ms(5);
        let first = s.tell("1DO0");
        let second = s.tell("1DO1");
        assert_eq!(second - first, apart, "{rate}");
    }
}
