//! The tuning pane (Alt-9): the family's tuning tool through the console.
//! On the app alone: a gain confirmed unchanged is set at the next run
//! with that same value; Esc during a run drops it and sends the axis's
//! stop. Through the real loop and a session on the in-process
//! simulators, on tokio's paused clock: a finished MCCL step shows its
//! plot and figures at 80×24 and 160×48; a TMCL sweep kept as the free
//! one and a sweep under load show both curves and the suggestion; Esc
//! during a step sends the stop and the axis stands; F12 during a sweep
//! stops the motor.

mod ui_support;

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::device::{Direction, TrafficRecord};
use axterm::families::find_family;
use axterm::link::{LinkSpec, SharedSim};
use axterm::session::{ReplyValue, Session, SessionOptions};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;
use axterm::ui::app::{AppEvent, Controller, Effect, TuneJob, TuneOutcome};
use axterm::ui::live::SessionController;
use ratatui::crossterm::event::KeyCode;
use tokio::sync::broadcast;
use ui_support::looped::{Rig, no_connector, press, run_console_on};
use ui_support::{axes, key, snapshot};

/// An MCCL module's snapshot with one axis, the tuning pane focused; the
/// gains read as `SG 0.04, SD 0.2`. The pane's index and the app.
fn mccl_app() -> (axterm::ui::app::App, usize) {
    let mut app = ui_support::console_with(&axterm::ui::PaneSetup::default());
    let mut shot = snapshot(vec![axterm::session::AxisInfo {
        number: 1,
        name: "axis 1",
    }]);
    shot.family = find_family("mccl").expect("mccl");
    app.handle(AppEvent::Snapshot(shot));
    let effects = app.handle(ui_support::key_with(
        KeyCode::Char('9'),
        ratatui::crossterm::event::KeyModifiers::ALT,
    ));
    let Some((pane, tag)) = effects.iter().find_map(|e| match e {
        Effect::Tune {
            pane,
            tag,
            job: TuneJob::Gains { axis: 0 },
        } => Some((*pane, *tag)),
        _ => None,
    }) else {
        panic!("the gains were not read on opening: {effects:?}");
    };
    let plan = find_family("mccl")
        .unwrap()
        .console
        .step_response()
        .unwrap();
    let gains = plan
        .gains()
        .iter()
        .map(|g| {
            let value = match g.name {
                "SG" => Some(0.04),
                "SD" => Some(0.2),
                _ => None,
            };
            (g.name, value)
        })
        .collect();
    app.handle(AppEvent::Tuned {
        pane,
        tag,
        result: Ok(TuneOutcome::Gains(gains)),
    });
    (app, pane)
}

fn the_step(effects: &[Effect]) -> Option<(u64, axterm::protocol::tuning::StepAsk)> {
    effects.iter().find_map(|e| match e {
        Effect::Tune {
            tag,
            job: TuneJob::Step { ask, .. },
            ..
        } => Some((*tag, ask.clone())),
        _ => None,
    })
}

#[test]
fn a_gain_confirmed_unchanged_is_set_at_the_next_run_with_that_value() {
    let (mut app, _) = mccl_app();
    let shown = ui_support::screen(&mut app, 80, 24).join("\n");
    assert!(shown.contains("SG 0.04"), "{shown}");
    // SG is the first row: Enter opens it pre-filled, Enter confirms.
    app.handle(key(KeyCode::Enter));
    let editing = ui_support::screen(&mut app, 80, 24).join("\n");
    assert!(editing.contains("SG=0.04_"), "{editing}");
    app.handle(key(KeyCode::Enter));
    // Without a y nothing runs.
    app.handle(key(KeyCode::Char('r')));
    assert!(the_step(&app.handle(key(KeyCode::Char('n')))).is_none());
    app.handle(key(KeyCode::Char('r')));
    let effects = app.handle(key(KeyCode::Char('y')));
    let (_, ask) = the_step(&effects).expect("the step runs on y");
    assert_eq!(ask.set, vec![("SG".to_string(), 0.04)]);
    assert_eq!((ask.distance, ask.samples), (1000, 400));
}

#[test]
fn distance_and_samples_are_typed_and_a_bad_value_is_named_and_kept_out() {
    let (mut app, _) = mccl_app();
    let rows = find_family("mccl")
        .unwrap()
        .console
        .step_response()
        .unwrap()
        .gains()
        .len();
    for _ in 0..rows {
        app.handle(key(KeyCode::Down));
    }
    app.handle(key(KeyCode::Enter));
    for _ in 0..4 {
        app.handle(key(KeyCode::Backspace));
    }
    ui_support::type_text(&mut app, "abc");
    app.handle(key(KeyCode::Enter));
    let said = ui_support::screen(&mut app, 80, 24).join("\n");
    assert!(said.contains("\"abc\" is not a whole number"), "{said}");
    for _ in 0..3 {
        app.handle(key(KeyCode::Backspace));
    }
    ui_support::type_text(&mut app, "-250");
    app.handle(key(KeyCode::Enter));
    // The settling band, two rows below: a band of 0 is none.
    app.handle(key(KeyCode::Down));
    app.handle(key(KeyCode::Down));
    app.handle(key(KeyCode::Enter));
    app.handle(key(KeyCode::Backspace));
    ui_support::type_text(&mut app, "0");
    app.handle(key(KeyCode::Enter));
    let said = ui_support::screen(&mut app, 80, 24).join("\n");
    assert!(said.contains("band: \"0\" (counts either side"), "{said}");
    app.handle(key(KeyCode::Backspace));
    ui_support::type_text(&mut app, "2.5");
    app.handle(key(KeyCode::Enter));
    app.handle(key(KeyCode::Char('r')));
    let effects = app.handle(key(KeyCode::Char('y')));
    let (_, ask) = the_step(&effects).expect("runs");
    assert_eq!(ask.distance, -250);
    assert!(ask.set.is_empty(), "{:?}", ask.set);
    assert!(
        effects.iter().any(|e| matches!(
            e,
            Effect::Tune {
                job: TuneJob::Step { band, .. },
                ..
            } if *band == 2.5
        )),
        "{effects:?}"
    );
}

#[test]
fn a_sweep_takes_the_readings_per_speed_typed() {
    let mut app = ui_support::console_with(&axterm::ui::PaneSetup::default());
    app.handle(AppEvent::Snapshot(snapshot(axes(&["motor 0"]))));
    app.focus("tuning");
    for _ in 0..3 {
        app.handle(key(KeyCode::Down));
    }
    app.handle(key(KeyCode::Enter));
    app.handle(key(KeyCode::Backspace));
    ui_support::type_text(&mut app, "9");
    app.handle(key(KeyCode::Enter));
    app.handle(key(KeyCode::Char('r')));
    let effects = app.handle(key(KeyCode::Char('y')));
    let asked = effects.iter().find_map(|e| match e {
        Effect::Tune {
            job: TuneJob::Sweep { ask, .. },
            ..
        } => Some(*ask),
        _ => None,
    });
    assert_eq!(asked.map(|a| a.samples), Some(9), "{effects:?}");
}

#[test]
fn esc_during_a_run_drops_it_and_sends_the_axis_stop() {
    let (mut app, _) = mccl_app();
    app.handle(key(KeyCode::Char('r')));
    the_step(&app.handle(key(KeyCode::Char('y')))).expect("runs");
    let effects = app.handle(key(KeyCode::Esc));
    assert!(effects.contains(&Effect::CancelTune), "{effects:?}");
    let sent: Vec<Vec<String>> = effects
        .iter()
        .filter_map(Effect::sends)
        .map(|(_, _, l)| l)
        .collect();
    assert_eq!(sent, vec![vec!["1MF".to_string()]]);
}

#[test]
fn a_family_without_a_tuning_tool_says_so() {
    let mut app = ui_support::console_with(&axterm::ui::PaneSetup::default());
    let mut shot = snapshot(axes(&["X"]));
    shot.family = find_family("cmd4cr").expect("cmd4cr");
    app.handle(AppEvent::Snapshot(shot));
    app.focus("tuning");
    let shown = ui_support::screen(&mut app, 80, 24).join("\n");
    assert!(shown.contains("no tuning tool for this family"), "{shown}");
}

async fn session(kind: &str) -> Session {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some(kind.into()),
        baud: Some(115_200),
        ..ConnectionArgs::default()
    })
    .expect("resolves");
    target.open().await.expect("the simulator link opens")
}

/// A session on `family`'s first simulator, which the test may drive.
async fn session_with_sim(family: &str) -> (Session, SharedSim) {
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

/// The console at `size` on `session`, the tuning pane focused, until
/// `driver` is done (then F10).
async fn run_tuning(
    session: &Session,
    size: (u16, u16),
    driver: impl AsyncFnOnce(&mut Rig, Arc<dyn Controller>),
) {
    run_tuning_on(session, None, size, driver).await;
}

async fn run_tuning_on(
    session: &Session,
    sim: Option<SharedSim>,
    size: (u16, u16),
    driver: impl AsyncFnOnce(&mut Rig, Arc<dyn Controller>),
) {
    let mut controller =
        SessionController::new(session.clone(), "sim".into(), SessionOptions::default());
    if let Some(sim) = sim {
        controller = controller.with_simulator(sim);
    }
    let controller: Arc<dyn Controller> = Arc::new(controller);
    let mut app = ui_support::console_with(&axterm::ui::PaneSetup::default());
    app.focus("tuning");
    let c = Arc::clone(&controller);
    run_console_on(
        app,
        size,
        Some(controller),
        no_connector(),
        async |mut rig: Rig| {
            driver(&mut rig, c).await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
}

/// Wait until a frame holding `text` goes out on the link.
async fn until_sent(traffic: &mut broadcast::Receiver<TrafficRecord>, text: &str) {
    loop {
        match traffic.recv().await {
            Ok(record)
                if record.direction == Direction::Sent
                    && String::from_utf8_lossy(&record.bytes).contains(text) =>
            {
                return;
            }
            Ok(_) | Err(broadcast::error::RecvError::Lagged(_)) => {}
            Err(broadcast::error::RecvError::Closed) => panic!("the link closed"),
        }
    }
}

/// Read `line` every 20 ms of virtual time until it reads 0.
async fn reads_zero(session: &Session, line: &str) -> bool {
    for _ in 0..500 {
        if let Ok(result) = session.execute_line(line).await
            && result.value == ReplyValue::Number(0)
        {
            return true;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    false
}

#[tokio::test(start_paused = true)]
async fn a_finished_step_shows_its_plot_and_figures_at_80x24_and_160x48() {
    for size in [(80, 24), (160, 48)] {
        let session = session("mccl").await;
        run_tuning(&session, size, async |rig: &mut Rig, _| {
            rig.screens.until("SG 0.04").await;
            press(rig, KeyCode::Char('r'));
            rig.screens.until("it moves the axis: y/n").await;
            press(rig, KeyCode::Char('y'));
            let done = rig.screens.until("overshoot").await;
            for said in [
                "step done",
                "rise time",
                "settling time",
                "following error",
                // The key names each series by its marker, at any size.
                "• commanded   ⣿ actual",
            ] {
                assert!(done.contains(said), "{size:?}: no {said:?} in\n{done}");
            }
            if size.0 < 160 {
                return;
            }
            // Wide, the legend shows; a second run draws the first
            // behind it.
            assert!(
                done.contains("commanded") && done.contains("actual"),
                "{done}"
            );
            press(rig, KeyCode::Char('r'));
            rig.screens.until("it moves the axis: y/n").await;
            press(rig, KeyCode::Char('y'));
            rig.screens
                .until_frame("the run before", |f| {
                    f.contains("▄ before") && f.contains("step done")
                })
                .await;
        })
        .await;
    }
}

#[tokio::test(start_paused = true)]
async fn esc_during_a_step_sends_the_stop_and_the_axis_stands() {
    let session = session("mccl").await;
    run_tuning(&session, (100, 30), async |rig: &mut Rig, _| {
        rig.screens.until("SG 0.04").await;
        let mut traffic = session.device().traffic();
        press(rig, KeyCode::Char('r'));
        rig.screens.until("it moves the axis: y/n").await;
        press(rig, KeyCode::Char('y'));
        until_sent(&mut traffic, "1MR1000").await;
        press(rig, KeyCode::Esc);
        until_sent(&mut traffic, "1MF").await;
        rig.screens
            .until("run ended, stopping (stopped by key)")
            .await;
        assert!(reads_zero(&session, "1TV").await, "the axis still moves");
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn two_sweeps_free_and_loaded_show_both_curves_and_the_suggestion() {
    for size in [(80, 24), (160, 48)] {
        let (session, sim) = session_with_sim("tmcl").await;
        run_tuning_on(
            &session,
            Some(sim),
            size,
            async |rig: &mut Rig, controller| {
                rig.screens.until("from 200").await;
                press(rig, KeyCode::Char('r'));
                rig.screens.until("it moves the axis: y/n").await;
                press(rig, KeyCode::Char('y'));
                rig.screens.until("sweep done").await;
                press(rig, KeyCode::Char('K'));
                rig.screens.until("kept as the free sweep").await;
                controller
                    .drive_sim_input("LOAD=60")
                    .expect("the load applies");
                press(rig, KeyCode::Char('r'));
                rig.screens.until("it moves the axis: y/n").await;
                press(rig, KeyCode::Char('y'));
                let done = rig.screens.until("to set it").await;
                assert!(done.contains("SAP 174, 0, "), "{size:?}:\n{done}");
                // Wide, both curves show under their key; at 80×24 the
                // suggestion takes the plot's room.
                if size.0 >= 160 {
                    assert!(done.contains("• free   ⣿ loaded"), "{size:?}:\n{done}");
                }
                // The suggestion goes only on its key and a y.
                let mut traffic = session.device().traffic();
                press(rig, KeyCode::Char('a'));
                rig.screens.until("y/n").await;
                press(rig, KeyCode::Char('y'));
                rig.screens.until(": done").await;
                let mut sent = Vec::new();
                while let Ok(record) = traffic.try_recv() {
                    if record.direction == Direction::Sent {
                        sent.push(record.bytes);
                    }
                }
                assert!(!sent.is_empty(), "nothing sent");
            },
        )
        .await;
    }
}

#[tokio::test(start_paused = true)]
async fn f12_during_a_sweep_stops_the_motor() {
    let session = session("tmcm1110").await;
    run_tuning(&session, (100, 30), async |rig: &mut Rig, _| {
        rig.screens.until("from 200").await;
        press(rig, KeyCode::Char('r'));
        rig.screens.until("it moves the axis: y/n").await;
        press(rig, KeyCode::Char('y'));
        rig.screens.until("running on").await;
        // Until the motor turns.
        let mut turning = false;
        for _ in 0..500 {
            if let Ok(r) = session.execute_line("GAP 3, 0").await
                && matches!(r.value, ReplyValue::Number(n) if n != 0)
            {
                turning = true;
                break;
            }
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
        assert!(turning, "the sweep never turned the motor");
        press(rig, KeyCode::F(12));
        rig.screens.until("STOP: every axis").await;
        assert!(
            reads_zero(&session, "GAP 3, 0").await,
            "the motor still turns"
        );
        // The run is over: a new one may be asked for.
        press(rig, KeyCode::Char('r'));
        rig.screens.until("it moves the axis: y/n").await;
        press(rig, KeyCode::Char('n'));
    })
    .await;
}

#[test]
fn leaving_the_pane_or_losing_the_link_during_a_run_stops_the_axis() {
    for how in ["leave", "link"] {
        let (mut app, _) = mccl_app();
        app.handle(key(KeyCode::Char('r')));
        the_step(&app.handle(key(KeyCode::Char('y')))).expect("runs");
        let effects = if how == "leave" {
            app.handle(ui_support::key_with(
                KeyCode::Char('1'),
                ratatui::crossterm::event::KeyModifiers::ALT,
            ))
        } else {
            let mut shot = snapshot(vec![axterm::session::AxisInfo {
                number: 1,
                name: "axis 1",
            }]);
            shot.family = find_family("mccl").expect("mccl");
            shot.link = axterm::device::LinkState::Disconnected {
                reason: "the cable".into(),
                attempts: 0,
                retry_in: Duration::from_millis(100),
            };
            app.handle(AppEvent::Snapshot(shot))
        };
        assert!(effects.contains(&Effect::CancelTune), "{how}: {effects:?}");
        let sent: Vec<Vec<String>> = effects
            .iter()
            .filter_map(Effect::sends)
            .map(|(_, _, l)| l)
            .collect();
        assert_eq!(sent, vec![vec!["1MF".to_string()]], "{how}");
    }
}

/// A TMCL module's snapshot with one motor, the tuning pane focused and
/// switched to the CoolStep view, whose form read (asked for on the
/// switch) answered AP172 = 3, AP6 = 128. The pane's index and the app.
fn coolstep_app() -> (axterm::ui::app::App, usize) {
    let mut app = ui_support::console_with(&axterm::ui::PaneSetup::default());
    app.handle(AppEvent::Snapshot(snapshot(axes(&["motor 0"]))));
    app.focus("tuning");
    let effects = app.handle(key(KeyCode::Char('t')));
    let Some((pane, tag)) = effects.iter().find_map(|e| match e {
        Effect::Tune {
            pane,
            tag,
            job:
                TuneJob::CurrentStart {
                    axis: 0,
                    set,
                    run: None,
                },
        } if set.is_empty() => Some((*pane, *tag)),
        _ => None,
    }) else {
        panic!("the form was not read on switching to it: {effects:?}");
    };
    let plan = find_family("tmcl")
        .unwrap()
        .console
        .current_control()
        .unwrap();
    let form = plan
        .form()
        .into_iter()
        .map(|f| {
            let value = if f.name == "AP172" { 3 } else { 0 };
            (f, Some(value))
        })
        .collect();
    app.handle(AppEvent::Tuned {
        pane,
        tag,
        result: Ok(TuneOutcome::CurrentStarted(
            axterm::session::tuning::CurrentRun {
                form,
                full: Some(128),
                samples: Vec::new(),
            },
        )),
    });
    (app, pane)
}

/// The start of a watch among `effects`: its tag, what it writes, how
/// the motor turns.
fn the_watch(effects: &[Effect]) -> Option<(u64, TuneJob)> {
    effects.iter().find_map(|e| match e {
        Effect::Tune { tag, job, .. } if matches!(job, TuneJob::CurrentStart { .. }) => {
            Some((*tag, job.clone()))
        }
        _ => None,
    })
}

#[test]
fn a_coolstep_value_confirmed_unchanged_is_written_with_that_value() {
    let (mut app, _) = coolstep_app();
    let shown = ui_support::screen(&mut app, 80, 24).join("\n");
    assert!(shown.contains("AP172 3"), "{shown}");
    // AP168..AP171 come first; AP172 is the fifth row.
    for _ in 0..4 {
        app.handle(key(KeyCode::Down));
    }
    let shown = ui_support::screen(&mut app, 80, 24).join("\n");
    assert!(
        shown.contains("turns CoolStep off"),
        "the chosen setting's meaning is shown:\n{shown}"
    );
    app.handle(key(KeyCode::Enter));
    app.handle(key(KeyCode::Enter));
    app.handle(key(KeyCode::Char('r')));
    let (_, job) = the_watch(&app.handle(key(KeyCode::Char('y')))).expect("the watch starts");
    assert_eq!(
        job,
        TuneJob::CurrentStart {
            axis: 0,
            set: vec![("AP172".to_string(), 3)],
            run: Some((axterm::protocol::jog::Direction::Positive, 1000)),
        }
    );
}

#[test]
fn a_watch_waits_for_the_form_read_under_way() {
    let mut app = ui_support::console_with(&axterm::ui::PaneSetup::default());
    app.handle(AppEvent::Snapshot(snapshot(axes(&["motor 0"]))));
    app.focus("tuning");
    app.handle(key(KeyCode::Char('t')));
    let effects = app.handle(key(KeyCode::Char('r')));
    assert!(
        !effects.iter().any(|e| matches!(e, Effect::Tune { .. })),
        "{effects:?}"
    );
    let shown = ui_support::screen(&mut app, 80, 24).join("\n");
    assert!(
        shown.contains("the settings are being read: run again in a moment"),
        "{shown}"
    );
}

#[test]
fn a_coolstep_value_outside_the_form_is_named_and_nothing_is_sent() {
    let (mut app, _) = coolstep_app();
    for _ in 0..4 {
        app.handle(key(KeyCode::Down));
    }
    app.handle(key(KeyCode::Enter));
    app.handle(key(KeyCode::Backspace));
    app.handle(key(KeyCode::Char('9')));
    app.handle(key(KeyCode::Char('9')));
    let effects = app.handle(key(KeyCode::Enter));
    assert!(the_watch(&effects).is_none(), "{effects:?}");
    let shown = ui_support::screen(&mut app, 80, 24).join("\n");
    assert!(
        shown.contains("AP172 takes 0..15, not 99"),
        "the refusal names the setting and its range:\n{shown}"
    );
}

#[test]
fn a_watch_that_fails_stops_the_motor_and_one_cancelled_sends_its_stop() {
    for how in ["failed", "esc", "other axis"] {
        let (mut app, pane) = coolstep_app();
        app.handle(key(KeyCode::Char('r')));
        let (tag, _) = the_watch(&app.handle(key(KeyCode::Char('y')))).expect("the watch starts");
        let effects = match how {
            "failed" => app.handle(AppEvent::Tuned {
                pane,
                tag,
                result: Err("no answer to GAP 206, 0".into()),
            }),
            "esc" => app.handle(key(KeyCode::Esc)),
            _ => {
                let mut shot = snapshot(axes(&["motor 0", "motor 1"]));
                shot.axis = 1;
                app.handle(AppEvent::Snapshot(shot))
            }
        };
        assert!(effects.contains(&Effect::CancelTune), "{how}: {effects:?}");
        let sent: Vec<Vec<String>> = effects
            .iter()
            .filter_map(Effect::sends)
            .map(|(_, _, l)| l)
            .collect();
        assert_eq!(sent, vec![vec!["MST 0".to_string()]], "{how}");
    }
}

#[test]
fn each_reading_asks_for_the_next_until_the_watch_ends() {
    let (mut app, pane) = coolstep_app();
    app.handle(key(KeyCode::Char('r')));
    let (tag, _) = the_watch(&app.handle(key(KeyCode::Char('y')))).expect("the watch starts");
    let plan = find_family("tmcl")
        .unwrap()
        .console
        .current_control()
        .unwrap();
    let effects = app.handle(AppEvent::Tuned {
        pane,
        tag,
        result: Ok(TuneOutcome::CurrentStarted(
            axterm::session::tuning::CurrentRun {
                form: plan.form().into_iter().map(|f| (f, Some(0))).collect(),
                full: Some(128),
                samples: Vec::new(),
            },
        )),
    });
    let next = |effects: &[Effect]| {
        effects
            .iter()
            .find_map(|e| match e {
                Effect::Tune {
                    tag,
                    job: TuneJob::CurrentRead { full, axis: 0, .. },
                    ..
                } => {
                    assert_eq!(*full, Some(128));
                    Some(*tag)
                }
                _ => None,
            })
            .expect("the next reading is asked for")
    };
    let mut tag = next(&effects);
    for (time, current, load, share) in [(0.0, 7, 900, 0.5), (0.1, 15, 400, 1.0)] {
        let effects = app.handle(AppEvent::Tuned {
            pane,
            tag,
            result: Ok(TuneOutcome::CurrentRead(
                axterm::session::tuning::CurrentSample {
                    time,
                    speed: Some(1000),
                    current: Some(current),
                    load: Some(load),
                    share: Some(share),
                },
            )),
        });
        tag = next(&effects);
    }
    let shown = ui_support::screen(&mut app, 80, 24).join("\n");
    for said in [
        "now: speed 1000, current 15 (100 %), load 400",
        "mean current 75 % of the full current (128): CoolStep saved 25 %",
        "• current, % of the full current",
        "█ load reading, % of 1023",
    ] {
        assert!(shown.contains(said), "no {said:?} in\n{shown}");
    }
    // Esc ends the chain: a late reading asks for no other.
    app.handle(key(KeyCode::Esc));
    let effects = app.handle(AppEvent::Tuned {
        pane,
        tag,
        result: Ok(TuneOutcome::CurrentRead(
            axterm::session::tuning::CurrentSample {
                time: 0.3,
                speed: Some(0),
                current: Some(7),
                load: Some(0),
                share: Some(0.5),
            },
        )),
    });
    assert!(
        !effects.iter().any(|e| matches!(e, Effect::Tune { .. })),
        "{effects:?}"
    );
}

/// The share of the full current in the newest reading shown, in %.
fn share_now(frame: &str) -> Option<u32> {
    let after = frame.split("now: ").nth(1)?;
    let open = after.find('(')?;
    let close = after[open..].find(" %)")?;
    after[open + 1..open + close].trim().parse().ok()
}

#[tokio::test(start_paused = true)]
async fn the_coolstep_watch_plots_current_and_load_live_and_esc_stops_the_motor() {
    for size in [(80, 24), (160, 48)] {
        let (session, sim) = session_with_sim("tmcl").await;
        run_tuning_on(
            &session,
            Some(sim),
            size,
            async |rig: &mut Rig, controller| {
                rig.screens.until("from 200").await;
                press(rig, KeyCode::Char('t'));
                rig.screens
                    .until_frame("the form read", |f| {
                        f.contains("AP183 ") && !f.contains("AP183 -")
                    })
                    .await;
                for _ in 0..4 {
                    press(rig, KeyCode::Down);
                }
                press(rig, KeyCode::Enter);
                press(rig, KeyCode::Backspace);
                press(rig, KeyCode::Char('2'));
                press(rig, KeyCode::Enter);
                rig.screens
                    .until("AP172 2 is written at the next watch")
                    .await;
                press(rig, KeyCode::Char('r'));
                rig.screens.until("it moves the axis: y/n").await;
                press(rig, KeyCode::Char('y'));
                // Without load CoolStep brings the current down ...
                let free = rig
                    .screens
                    .until_frame("the current lowered", |f| {
                        f.contains("CoolStep saved") && share_now(f).is_some_and(|p| p < 80)
                    })
                    .await;
                assert!(free.contains("• current"), "{size:?}: no key in\n{free}");
                let low = share_now(&free).expect("a share");
                // ... and under load it goes back up, live.
                controller
                    .drive_sim_input("LOAD=60")
                    .expect("the load applies");
                rig.screens
                    .until_frame("the current raised under load", |f| {
                        share_now(f).is_some_and(|p| p > low + 10)
                    })
                    .await;
                press(rig, KeyCode::Esc);
                rig.screens
                    .until("run ended, stopping (stopped by key): MST 0")
                    .await;
                assert!(
                    reads_zero(&session, "GAP 3, 0").await,
                    "{size:?}: the motor still turns"
                );
            },
        )
        .await;
        let ap172 = session.execute_line("GAP 172, 0").await.expect("reads");
        assert_eq!(
            ap172.value,
            ReplyValue::Number(2),
            "{size:?}: AP172 written"
        );
    }
}
