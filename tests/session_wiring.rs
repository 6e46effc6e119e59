//! The wiring check (`Session::check_wiring`) against each family's
//! simulator, on tokio's paused clock: on the TMCM-1110 and CMD-4CR stages
//! (end switches at their travel's ends) each switch fires for its own
//! direction; an MCCL axis whose − limit input closes while it moves +
//! is reported as swapped wiring, as a real miswired axis would be.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::families::find_family;
use axterm::link::{LinkSpec, SharedSim};
use axterm::protocol::jog::Direction;
use axterm::session::wiring::{Limit, findings, wired_right};
use axterm::session::{Session, SessionOptions};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;

async fn open(family: &str) -> (Session, SharedSim) {
    let family = find_family(family).expect("registered");
    let kind = axterm::families::simulators_of(family)
        .first()
        .expect("a simulator");
    let sim: SharedSim = Arc::new(Mutex::new((kind.build)(&SimOptions::default())));
    let spec = LinkSpec::Sim {
        kind: kind.name.into(),
        sim: Arc::clone(&sim),
        baud: Some(115_200),
        faults: FaultPlan::none(),
    };
    let session = Session::connect(spec, family, SessionOptions::default())
        .await
        .expect("the link opens");
    (session, sim)
}

#[tokio::test(start_paused = true)]
async fn on_a_stage_each_limit_switch_fires_for_its_own_direction() {
    for (family, speed) in [("tmcl", 2047), ("cmd4cr", 10_000)] {
        let (session, _sim) = open(family).await;
        for line in ["EO=1"].iter().filter(|_| family == "cmd4cr") {
            session.execute_line(line).await.expect("ready");
        }
        let plan = session.family().console.jog().expect("a jog plan");
        let legs = session
            .check_wiring(plan, 0, speed, Duration::from_secs(60))
            .await
            .expect("the check runs");
        let said = findings(session.axes()[0].name, &legs);
        assert!(wired_right(&legs), "{family}: {said:#?}");
        assert_eq!(legs[0].fired.map(|f| f.0), Some(Limit::Positive));
        assert_eq!(legs[1].fired.map(|f| f.0), Some(Limit::Negative));
        assert!(
            said.last()
                .is_some_and(|l| l.contains("the home switch was seen active between")),
            "{family}: {said:#?}"
        );
    }
}

#[tokio::test(start_paused = true)]
async fn a_minus_switch_closing_while_moving_plus_is_swapped_wiring() {
    let (session, sim) = open("mccl").await;
    session.execute_line("1MN").await.expect("motor on");
    let plan = session.family().console.jog().expect("a jog plan");
    // The − limit of axis 1 closes a moment after the + jog starts, as it
    // would on an axis whose switches are wired the wrong way round.
    let drive = tokio::spawn(async move {
        tokio::time::sleep(Duration::from_millis(300)).await;
        sim.lock()
            .unwrap_or_else(|e| e.into_inner())
            .drive_input("LIM-1=1")
            .expect("a simulator input");
    });
    let legs = session
        .check_wiring(plan, 0, 10_000, Duration::from_secs(5))
        .await
        .expect("the check runs");
    drive.await.expect("driven");
    assert_eq!(legs[0].direction, Direction::Positive);
    assert_eq!(legs[0].fired.map(|f| f.0), Some(Limit::Negative));
    let said = findings("servo 1", &legs);
    assert!(
        said[0].starts_with("servo 1, moving + tripped the − (left) switch at ")
            && said[0].ends_with(": swapped wiring or inverted direction"),
        "{said:#?}"
    );
    assert!(!wired_right(&legs));
}
