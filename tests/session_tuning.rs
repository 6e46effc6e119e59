//! The tuning runner (`Session::stall_sweep`, `Session::step_response`)
//! on tokio's paused clock: a sweep that fails half-way still sends its
//! stop, so the motor it set turning stands; a step that trips stops the
//! axis and says which flags it tripped.

use std::sync::{Arc, Mutex};

use axterm::families::find_family;
use axterm::link::{LinkSpec, SharedSim};
use axterm::protocol::console::AxisInfo;
use axterm::protocol::console::ReplyValue;
use axterm::protocol::tuning::{
    StallSweepPlan, StepAsk, StepSpec, SweepAction, SweepAsk, SweepPoint, SweepScript,
    SweepSuggestion, TuneError, TuningField,
};
use axterm::session::tuning::TuningError;
use axterm::session::{Session, SessionError, SessionOptions};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;

async fn open(family: &str) -> Session {
    let family = find_family(family).expect("registered");
    let kind = axterm::families::simulators_of(family)
        .first()
        .expect("a simulator");
    let sim: SharedSim = Arc::new(Mutex::new((kind.build)(&SimOptions::default())));
    let spec = LinkSpec::Sim {
        kind: kind.name.into(),
        sim,
        baud: Some(115_200),
        faults: FaultPlan::none(),
    };
    Session::connect(spec, family, SessionOptions::default())
        .await
        .expect("the link opens")
}

/// The TMCL sweep with a line the console refuses after the motor turns.
struct BrokenHalfWay;

impl StallSweepPlan for BrokenHalfWay {
    fn reading(&self) -> &'static str {
        "AP206"
    }
    fn fields(&self) -> &'static [TuningField] {
        &[]
    }
    fn read_threshold(&self, axis: &AxisInfo) -> String {
        format!("GAP 174, {}", axis.number)
    }
    fn script(&self, axis: &AxisInfo, ask: &SweepAsk) -> Result<SweepScript, TuneError> {
        let real = find_family("tmcl").unwrap().console.stall_sweep().unwrap();
        let mut script = real.script(axis, ask)?;
        script.actions.truncate(3);
        script
            .actions
            .push(SweepAction::Send("SAP 999, 0, 1".into()));
        Ok(script)
    }
    fn speed_reached(&self, actual: i64, speed: i64) -> bool {
        actual == speed
    }
    fn stall_flag(&self) -> &'static str {
        "stall"
    }
    fn suggest(&self, _: &AxisInfo, _: &[SweepPoint], _: &[SweepPoint], _: i64) -> SweepSuggestion {
        SweepSuggestion {
            reasons: Vec::new(),
            lines: Vec::new(),
        }
    }
}

async fn speed(session: &Session) -> i64 {
    match session
        .execute_line("GAP 3, 0")
        .await
        .expect("a read")
        .value
    {
        ReplyValue::Number(n) => n,
        other => panic!("{other:?}"),
    }
}

#[tokio::test(start_paused = true)]
async fn a_sweep_that_fails_half_way_stops_the_motor_it_turned() {
    let session = open("tmcl").await;
    let ask = SweepAsk {
        from: 500,
        to: 800,
        steps: 2,
        samples: 1,
    };
    let error = session
        .stall_sweep(&BrokenHalfWay, 0, &ask)
        .await
        .expect_err("the bad line fails the sweep");
    assert!(
        matches!(error, TuningError::Line(SessionError::Refused { .. })),
        "{error:?}"
    );
    // The motor had reached 500 before the bad line; the stop went after.
    tokio::time::sleep(std::time::Duration::from_secs(2)).await;
    assert_eq!(speed(&session).await, 0);
}

#[tokio::test(start_paused = true)]
async fn a_whole_sweep_ends_standing_with_a_reading_per_sample() {
    let session = open("tmcl").await;
    let plan = session.family().console.stall_sweep().expect("TMCL sweeps");
    let ask = SweepAsk {
        from: 300,
        to: 900,
        steps: 3,
        samples: 2,
    };
    let run = session.stall_sweep(plan, 0, &ask).await.expect("a sweep");
    assert_eq!(run.threshold, Some(0));
    assert_eq!(
        run.points.iter().map(|p| p.speed).collect::<Vec<_>>(),
        [300, 600, 900]
    );
    assert!(run.points.iter().all(|p| p.readings.len() == 2));
    tokio::time::sleep(std::time::Duration::from_secs(2)).await;
    assert_eq!(speed(&session).await, 0);
}

#[tokio::test(start_paused = true)]
async fn a_step_that_trips_stops_the_axis_and_names_the_flags() {
    let session = open("mccl").await;
    let plan = session
        .family()
        .console
        .step_response()
        .expect("MCCL steps");
    let ask = StepAsk {
        distance: 20,
        samples: 200,
        set: vec![("SG".into(), 5.0), ("SE".into(), 40.0)],
    };
    let run = session
        .step_response(plan, 0, &ask, &StepSpec::default())
        .await
        .expect("the test runs");
    let names: Vec<&str> = run.tripped.iter().map(|f| f.name).collect();
    assert!(names.contains(&"following error"), "{names:?}");
    assert_eq!(run.samples.len(), 200);
    // Well damped, nothing trips and the figures are there.
    let ask = StepAsk {
        distance: 20,
        samples: 200,
        set: vec![
            ("SG".into(), 0.04),
            ("SD".into(), 0.2),
            ("SE".into(), 1024.0),
        ],
    };
    let session = open("mccl").await;
    let run = session
        .step_response(plan, 0, &ask, &StepSpec::default())
        .await
        .expect("the test runs");
    assert!(run.tripped.is_empty(), "{:?}", run.tripped);
    let figures = run.figures.expect("figures");
    assert_eq!(figures.target, 20.0);
    assert!(figures.settling_time.is_some(), "{figures:?}");
}

#[tokio::test(start_paused = true)]
async fn a_current_watch_that_turned_the_motor_stops_it_after() {
    use axterm::protocol::jog::Direction;
    use axterm::session::tuning::WatchRun;
    let session = open("tmcl").await;
    let console = session.family().console;
    let plan = console.current_control().expect("TMCL has CoolStep");
    let run = WatchRun {
        jog: console.jog().expect("a jog"),
        direction: Direction::Positive,
        speed: 800,
    };
    let watched = session
        .watch_current(
            plan,
            0,
            &[("AP172".into(), 2)],
            Some(run),
            4,
            std::time::Duration::from_millis(500),
        )
        .await
        .expect("a watch");
    assert_eq!(watched.samples.len(), 4);
    assert_eq!(watched.samples[3].speed, Some(800));
    assert!(watched.mean_share().is_some());
    tokio::time::sleep(std::time::Duration::from_secs(2)).await;
    assert_eq!(speed(&session).await, 0);
    // A setting outside the form is refused before anything moves, and
    // nothing is sent: not even the stop of a motor never started.
    let mut traffic = session.device().traffic();
    let refused = session
        .watch_current(
            plan,
            0,
            &[("AP172".into(), 99)],
            Some(run),
            1,
            Default::default(),
        )
        .await
        .expect_err("AP172 99 is out of range");
    assert!(refused.to_string().contains("0..15"), "{refused}");
    let mut sent = Vec::new();
    while let Ok(record) = traffic.try_recv() {
        if record.direction == axterm::device::Direction::Sent {
            sent.push(record.bytes);
        }
    }
    assert!(sent.is_empty(), "sent on a refusal: {sent:?}");
    assert_eq!(speed(&session).await, 0);
}
