//! The bring-up pane (Alt-8) through the real loop and a session on each
//! family's in-process simulator, on tokio's paused clock: a held jog key
//! runs the axis and its stop goes out within 300 ms of the last repeat; a
//! tap moves nothing; leaving the pane stops the jog at once (before the
//! deadman would); a step moves exactly its distance.

mod motion_support;
mod ui_support;

use std::sync::Arc;
use std::time::Duration;

use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::device::{Direction, TrafficRecord};
use axterm::families::FAMILIES;
use axterm::protocol::jog::Direction as JogDirection;
use axterm::script::result_matches;
use axterm::session::{ReplyValue, Session, SessionOptions};
use axterm::ui::app::Controller;
use axterm::ui::bringup::DEADMAN;
use axterm::ui::live::SessionController;
use motion_support::motion_of;
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use tokio::sync::broadcast;
use tokio::time::Instant;
use ui_support::looped::{Rig, no_connector, press, press_with, run_console_on};

/// How often a terminal repeats a held key (30 a second).
const REPEAT: Duration = Duration::from_millis(33);

async fn session(kind: &str) -> Session {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some(kind.into()),
        baud: Some(9600),
        ..ConnectionArgs::default()
    })
    .expect("resolves");
    target.open().await.expect("the simulator link opens")
}

/// The console at 100×30 on `session`, the bring-up pane focused, until
/// `driver` is done (then F10).
async fn run_bringup(session: &Session, driver: impl AsyncFnOnce(&mut Rig)) {
    let controller: Arc<dyn Controller> = Arc::new(SessionController::new(
        session.clone(),
        "sim".into(),
        SessionOptions::default(),
    ));
    let mut app = ui_support::console_with(&axterm::ui::PaneSetup::default());
    app.focus("bringup");
    run_console_on(
        app,
        (100, 30),
        Some(controller),
        no_connector(),
        async |mut rig: Rig| {
            driver(&mut rig).await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
}

/// Press `code` as a held key repeats it, for `held`.
async fn hold(rig: &Rig, code: KeyCode, held: Duration) {
    let start = Instant::now();
    loop {
        press(rig, code);
        if start.elapsed() >= held {
            return;
        }
        tokio::time::sleep(REPEAT).await;
    }
}

/// Virtual time from now until `bytes` go out on the link.
async fn until_sent(traffic: &mut broadcast::Receiver<TrafficRecord>, bytes: &[u8]) -> Duration {
    let from = Instant::now();
    loop {
        match traffic.recv().await {
            Ok(record) if record.direction == Direction::Sent && record.bytes == bytes => {
                return from.elapsed();
            }
            Ok(_) | Err(broadcast::error::RecvError::Lagged(_)) => {}
            Err(broadcast::error::RecvError::Closed) => panic!("the link closed"),
        }
    }
}

/// Read `line` every 20 ms of virtual time until `ready` says yes.
async fn reads_until(session: &Session, line: &str, ready: impl Fn(&str) -> bool) -> bool {
    for _ in 0..500 {
        match session.execute_line(line).await {
            Ok(result) if ready(&result.value.to_string()) => return true,
            Ok(_) => {}
            Err(e) => panic!("{line}: {e}"),
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    false
}

/// The bytes of the family's jog stop for its first axis.
fn stop_bytes(session: &Session) -> Vec<u8> {
    let family = session.family();
    let plan = family.console.jog().expect("a jog plan");
    let stop = plan.stop(&family.console.axes()[0]);
    let line = stop.last().expect("a stop line");
    session.prepare(line).expect("the stop prepares").bytes
}

#[tokio::test(start_paused = true)]
async fn a_held_jog_key_runs_the_axis_and_letting_go_stops_it_within_300_ms() {
    for family in FAMILIES {
        let motion = motion_of(family);
        let kind = family.simulators.first().expect("a simulator").name;
        let session = session(kind).await;
        let stop = stop_bytes(&session);
        for line in motion.ready {
            session.execute_line(line).await.expect("ready");
        }
        let before = position(&session, motion.position).await;
        run_bringup(&session, async |rig: &mut Rig| {
            rig.screens.until("standing by").await;
            hold(rig, KeyCode::Right, Duration::from_millis(800)).await;
            let mut traffic = session.device().traffic();
            // The last repeat was just pressed: nothing more comes.
            let after = until_sent(&mut traffic, &stop).await;
            assert!(
                after <= Duration::from_millis(300),
                "{}: the stop went {after:?} after the last repeat",
                family.name
            );
            assert!(
                after >= DEADMAN - REPEAT,
                "{}: the stop went {after:?} after the last repeat, before the window",
                family.name
            );
            rig.screens.until("jog stopped").await;
            assert!(
                reads_until(&session, motion.speed, |v| result_matches(
                    v,
                    motion.at_rest
                ))
                .await,
                "{}: the axis still moves",
                family.name
            );
            let after = position(&session, motion.position).await;
            assert!(
                after > before,
                "{}: jogging + moved from {before} to {after}",
                family.name
            );
        })
        .await;
    }
}

/// The link lost while jogging: the jog is handed to the session, which
/// stops every axis once the link is back (Session::end_run).
#[test]
fn a_lost_link_while_jogging_ends_it_through_the_session() {
    use axterm::device::LinkState;
    use axterm::session::run_end::{RunEnding, StopOnFailure};
    use axterm::ui::app::{AppEvent, Effect};
    use ui_support::{axes, key, snapshot};
    let mut app = ui_support::console_with(&axterm::ui::PaneSetup::default());
    let mut shot = snapshot(axes(&["motor 0"]));
    app.handle(AppEvent::Snapshot(shot.clone()));
    app.focus("bringup");
    assert!(app.handle(key(KeyCode::Right)).is_empty());
    let effects = app.handle(key(KeyCode::Right));
    let Some((pane, tag, lines)) = effects.iter().find_map(Effect::sends) else {
        panic!("no run sent: {effects:?}");
    };
    assert_eq!(lines, ["ROR 0, 100"]);
    app.handle(AppEvent::Reply {
        pane,
        tag,
        line: lines[0].clone(),
        result: Ok(axterm::session::LineResult {
            line: lines[0].clone(),
            request: vec![1],
            reply: vec![2],
            status: Some(100),
            value: ReplyValue::None,
            elapsed: Duration::ZERO,
            attempts: 1,
        }),
    });
    shot.link = LinkState::Disconnected {
        reason: "the cable".into(),
        attempts: 0,
        retry_in: Duration::from_millis(100),
    };
    let effects = app.handle(AppEvent::Snapshot(shot));
    assert!(
        effects.contains(&Effect::EndRun {
            pane,
            ending: RunEnding::Cancelled,
            policy: StopOnFailure::Stop,
        }),
        "{effects:?}"
    );
}

#[tokio::test(start_paused = true)]
async fn a_tap_of_a_jog_key_moves_nothing() {
    for family in FAMILIES {
        let kind = family.simulators.first().expect("a simulator").name;
        let session = session(kind).await;
        let mut traffic = session.device().traffic();
        run_bringup(&session, async |rig: &mut Rig| {
            rig.screens.until("standing by").await;
            press(rig, KeyCode::Right);
            rig.screens.until("hold the key to jog").await;
            // Long after a second press could have come.
            tokio::time::sleep(Duration::from_secs(2)).await;
        })
        .await;
        let plan = family.console.jog().expect("a jog plan");
        let run = plan
            .run(
                &family.console.axes()[0],
                JogDirection::Positive,
                plan.speeds()[1],
            )
            .expect("a run");
        let run_bytes: Vec<Vec<u8>> = run
            .iter()
            .map(|l| session.prepare(l).expect("prepares").bytes)
            .collect();
        while let Ok(record) = traffic.try_recv() {
            assert!(
                !(record.direction == Direction::Sent && run_bytes.contains(&record.bytes)),
                "{}: a tap sent {:?}",
                family.name,
                record.bytes
            );
        }
    }
}

#[tokio::test(start_paused = true)]
async fn leaving_the_pane_stops_the_jog_at_once() {
    for family in FAMILIES {
        let motion = motion_of(family);
        let kind = family.simulators.first().expect("a simulator").name;
        let session = session(kind).await;
        let stop = stop_bytes(&session);
        for line in motion.ready {
            session.execute_line(line).await.expect("ready");
        }
        let before = position(&session, motion.position).await;
        run_bringup(&session, async |rig: &mut Rig| {
            rig.screens.until("standing by").await;
            hold(rig, KeyCode::Left, Duration::from_millis(600)).await;
            let mut traffic = session.device().traffic();
            press_with(rig, KeyCode::Char('1'), KeyModifiers::ALT);
            let after = until_sent(&mut traffic, &stop).await;
            assert!(
                after < DEADMAN - REPEAT,
                "{}: the stop went {after:?} after the pane was left: the deadman's, not the \
                 pane's",
                family.name
            );
            assert!(
                reads_until(&session, motion.speed, |v| result_matches(
                    v,
                    motion.at_rest
                ))
                .await,
                "{}: the axis still moves",
                family.name
            );
            let after = position(&session, motion.position).await;
            assert!(
                after < before,
                "{}: jogging - moved from {before} to {after}",
                family.name
            );
        })
        .await;
    }
}

async fn position(session: &Session, line: &str) -> i64 {
    match session.execute_line(line).await.map(|r| r.value) {
        Ok(ReplyValue::Number(n)) => n,
        Ok(ReplyValue::Text(text)) => text
            .split_whitespace()
            .find_map(|w| w.strip_prefix("posact="))
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{line}: no position in {text}")),
        other => panic!("{line}: {other:?}"),
    }
}

#[tokio::test(start_paused = true)]
async fn a_step_moves_exactly_its_distance() {
    for family in FAMILIES {
        let motion = motion_of(family);
        let kind = family.simulators.first().expect("a simulator").name;
        let session = session(kind).await;
        for line in motion.ready {
            session.execute_line(line).await.expect("ready");
        }
        run_bringup(&session, async |rig: &mut Rig| {
            let before = position(&session, motion.position).await;
            // The pane needs the axis standing, its position polled.
            rig.screens.until(&format!("pos {before}  speed 0 ")).await;
            press_with(rig, KeyCode::Right, KeyModifiers::SHIFT);
            rig.screens.until("step 1000 from").await;
            assert!(
                reads_until(&session, motion.position, |_| true).await,
                "{}: no position",
                family.name
            );
            let mut now = position(&session, motion.position).await;
            for _ in 0..500 {
                if now == before + 1000 {
                    break;
                }
                tokio::time::sleep(Duration::from_millis(20)).await;
                now = position(&session, motion.position).await;
            }
            assert_eq!(now, before + 1000, "{}: the step", family.name);
        })
        .await;
    }
}

/// At 80×24 every pane is a tab of one strip, eight of them now: the tab
/// shown keeps its whole title (the others give up words, then all but
/// their number), so the pane the keyboard is in is always named.
#[test]
fn at_80_columns_the_shown_tab_is_named_whole() {
    use axterm::ui::app::AppEvent;
    use ui_support::{axes, screen, snapshot};
    let mut app = ui_support::console_with(&axterm::ui::PaneSetup::default());
    app.handle(AppEvent::Snapshot(snapshot(axes(&["motor 0"]))));
    for (name, label) in [
        ("command", "1 Command"),
        ("params", "3 Parameters"),
        ("traffic", "4 Traffic"),
        ("plot", "5 Plot"),
        ("connect", "6 Connect"),
        ("editor", "7 Program — untitled"),
        ("bringup", "8 Jog — motor 0"),
    ] {
        assert!(app.focus(name), "{name}");
        let shown = screen(&mut app, 80, 24).join("\n");
        assert!(shown.contains(label), "{name}: {shown}");
    }
}

/// A MultiFlex servo takes a jog with its motor off and turns nothing
/// (Ch8 TS bit 1; MA only moves the target): the pane says so from the
/// polled lamps and sends nothing, for a held key, a step and the wiring
/// check.
#[tokio::test(start_paused = true)]
async fn a_jog_of_a_servo_whose_motor_is_off_sends_nothing_and_says_why() {
    let session = session("mccl").await;
    let mut traffic = session.device().traffic();
    run_bringup(&session, async |rig: &mut Rig| {
        rig.screens.until("standing by").await;
        // The lamps are polled: the motor lamp is known to be off.
        rig.screens.until("driver none").await;
        hold(rig, KeyCode::Right, Duration::from_millis(300)).await;
        rig.screens.until("motor is off").await;
        rig.screens.until("1MN switches it on").await;
        press_with(rig, KeyCode::Right, KeyModifiers::SHIFT);
        tokio::time::sleep(Duration::from_millis(100)).await;
        // Nor is the wiring check offered: it would jog nothing.
        press(rig, KeyCode::Char('w'));
        rig.screens.until("wiring check not run").await;
    })
    .await;
    let sent: Vec<String> = std::iter::from_fn(|| traffic.try_recv().ok())
        .filter(|r| r.direction == Direction::Sent)
        .map(|r| String::from_utf8_lossy(&r.bytes).into_owned())
        .collect();
    assert!(
        !sent
            .iter()
            .any(|s| s.contains("GO") || s.contains("MA") || s.contains("SV")),
        "{sent:?}"
    );
}
