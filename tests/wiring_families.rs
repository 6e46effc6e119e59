//! The wiring check (`Session::check_wiring`) against each family's
//! simulator on tokio's paused clock, with the stage's limit switches
//! wired right and swapped (`LIMITS=swapped`, the same setting on every
//! simulator): right, each switch fires for its own direction and the
//! module stops the axis at it; swapped, moving + trips the − switch at
//! the + end, which the module does not stop on (each family stops only
//! on the switch of the direction of travel), and the findings say
//! "swapped wiring or inverted direction".

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::families::find_family;
use axterm::link::{LinkSpec, SharedSim};
use axterm::session::wiring::{Leg, Limit, findings, wired_right};
use axterm::session::{Session, SessionOptions};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;

/// Per family: its name, a jog speed, the lines that make its axis 0
/// ready to move with its limits acting, and where its + end switch
/// closes (machine position = counter at power-up).
struct Case {
    family: &'static str,
    speed: i64,
    ready: &'static [&'static str],
    plus_end: i64,
}

const CASES: &[Case] = &[
    Case {
        family: "tmcl",
        speed: 2047,
        ready: &[],
        plus_end: 200_000,
    },
    Case {
        family: "cmd4cr",
        speed: 10_000,
        ready: &["EO=1"],
        plus_end: 100_000,
    },
    // MCCL (Ch5): limits + and − on (LN3), decelerate at a limit (LM2),
    // the servo's loop on (MN); the stage's + limit at 50,000 counts.
    Case {
        family: "mccl",
        speed: 20_000,
        ready: &["1LM2,1LN3,1MN"],
        plus_end: 50_000,
    },
    // SIXpack 2 (§7.1 $15, §7.3 $31): a stop only stops (StopNoRef, no
    // reference search after it), the demo's reference switch is an
    // opener (NullPositive, §5.5.2); A_In below 100 is the left stop
    // switch, above 900 the right one. The demo stage's right end switch
    // closes 100 µsteps before its stop, 199,900 µsteps from the left
    // stop, with the carriage 480 µsteps from it at power-up.
    Case {
        family: "sixpack2",
        speed: 100,
        ready: &[
            "SetMotorParameters 0 6400 StopNoRef,NullPositive",
            "SetStopSwitchLimits 0 100 900",
        ],
        plus_end: 199_420,
    },
];

async fn open(case: &Case, wiring: &str) -> Session {
    let family = find_family(case.family).expect("registered");
    let kind = axterm::families::simulators_of(family)
        .first()
        .expect("a simulator");
    let sim: SharedSim = Arc::new(Mutex::new((kind.build)(&SimOptions::default())));
    sim.lock()
        .unwrap_or_else(|e| e.into_inner())
        .drive_input(&format!("LIMITS={wiring}"))
        .unwrap_or_else(|e| panic!("{}: LIMITS={wiring}: {e}", case.family));
    let spec = LinkSpec::Sim {
        kind: kind.name.into(),
        sim,
        baud: Some(115_200),
        faults: FaultPlan::none(),
    };
    let session = Session::connect(spec, family, SessionOptions::default())
        .await
        .expect("the link opens");
    for line in case.ready {
        session.execute_line(line).await.expect("ready");
    }
    session
}

async fn check(case: &Case, wiring: &str) -> (Vec<Leg>, Vec<String>) {
    let session = open(case, wiring).await;
    let plan = session.family().console.jog().expect("a jog plan");
    let legs = session
        .check_wiring(plan, 0, case.speed, Duration::from_secs(60))
        .await
        .expect("the check runs");
    let said = findings(session.axes()[0].name, &legs);
    (legs, said)
}

/// Within one read of the switches (the jog's travel between two
/// polls) of `at`.
fn near(position: Option<i64>, at: i64, leg: &Leg) -> bool {
    let spacing = leg.read_spacing.unwrap_or(0).max(1);
    position.is_some_and(|p| (p - at).abs() <= spacing)
}

#[tokio::test(start_paused = true)]
async fn wired_right_each_switch_fires_for_its_own_direction_and_stops_the_axis() {
    for case in CASES {
        let (legs, said) = check(case, "right").await;
        assert!(wired_right(&legs), "{}: {said:#?}", case.family);
        let (limit, at) = legs[0].fired.expect("the + leg fired");
        assert_eq!(limit, Limit::Positive, "{}", case.family);
        assert!(
            near(at, case.plus_end, &legs[0]),
            "{}: {said:#?}",
            case.family
        );
        assert_eq!(legs[1].fired.map(|f| f.0), Some(Limit::Negative));
        assert!(
            said[0].contains("the + (right) switch fired at")
                && said[0].ends_with("as it should; the module stopped the axis at it"),
            "{}: {said:#?}",
            case.family
        );
        assert!(
            said[1].contains("moving -: the − (left) switch fired at"),
            "{}: {said:#?}",
            case.family
        );
    }
}

#[tokio::test(start_paused = true)]
async fn swapped_moving_plus_trips_the_minus_switch_which_does_not_stop_the_axis() {
    for case in CASES {
        let (legs, said) = check(case, "swapped").await;
        assert!(!wired_right(&legs), "{}: {said:#?}", case.family);
        let (limit, at) = legs[0].fired.expect("the + leg fired");
        assert_eq!(limit, Limit::Negative, "{}: {said:#?}", case.family);
        // It fired where the + end is, and the module ran on past it:
        // the − switch stops only motion toward −.
        assert!(
            near(at, case.plus_end, &legs[0]),
            "{}: {said:#?}",
            case.family
        );
        assert!(!legs[0].stopped_by_module, "{}: {said:#?}", case.family);
        assert!(
            legs[0].rest.is_some_and(|rest| rest > case.plus_end),
            "{}: {said:#?}",
            case.family
        );
        assert!(
            said[0].starts_with(&format!(
                "{}, moving + tripped the − (left) switch at ",
                legs_axis(case)
            )) && said[0].ends_with(": swapped wiring or inverted direction"),
            "{}: {said:#?}",
            case.family
        );
    }
}

#[tokio::test(start_paused = true)]
async fn swapped_the_minus_leg_meets_a_switch_too() {
    // The + leg ran on past the + end's switch (wired to the − input); the
    // − leg meets it again on the way back, or runs on to the − end's, or
    // (standing on it) the module refuses the − jog, or (a servo that
    // wound up against the end stop until its following error tripped)
    // the axis does not move and that is said: never "no limit switch
    // fired".
    for case in CASES {
        let (legs, said) = check(case, "swapped").await;
        let stuck = legs[1].stood_still();
        assert!(
            legs[1].fired.is_some() || legs[1].refused.is_some() || stuck,
            "{}: {said:#?}",
            case.family
        );
        assert!(
            !said[1].contains("no limit switch fired"),
            "{}: {said:#?}",
            case.family
        );
    }
}

fn legs_axis(case: &Case) -> &'static str {
    find_family(case.family).expect("registered").console.axes()[0].name
}
