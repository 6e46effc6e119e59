//! The console's event loop against a fake controller: what typing sends,
//! what the screen shows when the controller's watch channels change, that
//! the emergency stop goes out at once while lines wait and that a batch
//! goes no further, and that the loop ends on a termination signal.
//! Virtual time: a loop that waits for nothing fails at once instead of
//! hanging.

mod ui_support;

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::device::{DeviceEvent, Direction, LinkState, Priority, TrafficKind, TrafficRecord};
use axterm::families::find_family;
use axterm::protocol::Family;
use axterm::protocol::console::ReplyValue;
use axterm::session::{AxisFlag, AxisInfo, AxisStatus, LineResult, PollCadence, SessionError};
use axterm::ui::app::{self, AppEvent, Connector, Controller, Pending};
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use tokio::sync::{broadcast, mpsc, oneshot, watch};
use ui_support::looped::{Rig, no_connector, press, press_with, run_console, type_line};

/// What the console asked of the fake.
#[derive(Debug)]
enum Call {
    Execute(String, oneshot::Sender<Result<LineResult, SessionError>>),
    Stop,
    Poll(Option<PollCadence>),
}

struct Fake {
    axes: Vec<AxisInfo>,
    status: watch::Sender<Vec<AxisStatus>>,
    link: watch::Sender<LinkState>,
    identity: watch::Sender<Option<String>>,
    traffic: broadcast::Sender<TrafficRecord>,
    calls: mpsc::UnboundedSender<Call>,
}

impl Fake {
    fn new(names: &[&'static str]) -> (Arc<Fake>, mpsc::UnboundedReceiver<Call>) {
        let axes: Vec<AxisInfo> = names
            .iter()
            .enumerate()
            .map(|(i, name)| AxisInfo {
                number: i as u8,
                name,
            })
            .collect();
        let (calls, rx) = mpsc::unbounded_channel();
        let fake = Fake {
            status: watch::channel(vec![AxisStatus::default(); axes.len()]).0,
            link: watch::channel(LinkState::Connected {
                link: "fake".into(),
            })
            .0,
            identity: watch::channel(None).0,
            traffic: broadcast::channel(64).0,
            axes,
            calls,
        };
        (Arc::new(fake), rx)
    }
}

fn ok(line: &str) -> Result<LineResult, SessionError> {
    Ok(LineResult {
        line: line.into(),
        request: Vec::new(),
        // A TMCL answer: status 100.
        reply: vec![2, 1, 100, 3, 0, 0, 0, 0, 106],
        status: Some(100),
        value: ReplyValue::None,
        elapsed: Duration::ZERO,
        attempts: 1,
    })
}

impl Controller for Fake {
    fn family(&self) -> &'static Family {
        find_family("tmcl").expect("tmcl")
    }
    fn address(&self) -> u8 {
        1
    }
    fn axes(&self) -> Vec<AxisInfo> {
        self.axes.clone()
    }
    fn link_name(&self) -> String {
        "fake rig".into()
    }
    fn status(&self) -> watch::Receiver<Vec<AxisStatus>> {
        self.status.subscribe()
    }
    fn link_state(&self) -> watch::Receiver<LinkState> {
        self.link.subscribe()
    }
    fn identity(&self) -> watch::Receiver<Option<String>> {
        self.identity.subscribe()
    }
    fn traffic(&self) -> Option<broadcast::Receiver<TrafficRecord>> {
        Some(self.traffic.subscribe())
    }
    fn events(&self) -> Option<broadcast::Receiver<DeviceEvent>> {
        None
    }
    fn execute(&self, line: String) -> Pending<Result<LineResult, SessionError>> {
        let calls = self.calls.clone();
        Box::pin(async move {
            let (answer, answered) = oneshot::channel();
            let _ = calls.send(Call::Execute(line.clone(), answer));
            answered.await.unwrap_or_else(|_| ok(&line))
        })
    }
    fn emergency_stop(&self) -> Pending<Vec<Result<LineResult, SessionError>>> {
        let _ = self.calls.send(Call::Stop);
        Box::pin(async { vec![ok("MST 0"), ok("STOPAPP"), ok("MST 0")] })
    }
    fn set_polling(&self, cadence: Option<PollCadence>) {
        let _ = self.calls.send(Call::Poll(cadence));
    }
    fn acknowledge_errors(&self, _axis: usize, _seen: &[AxisFlag]) {}
    fn with_address(&self, _address: u8) -> Arc<dyn Controller> {
        let (fake, _) = Fake::new(&["other"]);
        fake
    }
}

async fn next_call(calls: &mut mpsc::UnboundedReceiver<Call>) -> Call {
    tokio::time::timeout(Duration::from_secs(600), calls.recv())
        .await
        .ok()
        .flatten()
        .expect("the console asked the controller for something")
}

#[tokio::test(start_paused = true)]
async fn a_typed_line_reaches_the_controller_and_its_answer_the_screen() {
    let (fake, mut calls) = Fake::new(&["motor 0"]);
    run_console(Some(fake.clone()), no_connector(), async |mut rig: Rig| {
        // Polling starts at the default rate.
        assert!(matches!(next_call(&mut calls).await, Call::Poll(Some(c)) if c == PollCadence::default()));
        rig.screens.until("poll 20 Hz").await;
        type_line(&rig, "GAP 4, 0");
        let Call::Execute(line, answer) = next_call(&mut calls).await else {
            panic!("expected the line")
        };
        assert_eq!(line, "GAP 4, 0");
        let _ = answer.send(Ok(LineResult {
            value: ReplyValue::Number(2047),
            ..ok("GAP 4, 0").expect("ok")
        }));
        rig.screens.until("  2047  (status 100").await;
        press(&rig, KeyCode::F(10));
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn the_screen_follows_the_controller_s_snapshots() {
    let (fake, _calls) = Fake::new(&["X", "Y", "Z", "U"]);
    run_console(Some(fake.clone()), no_connector(), async |mut rig: Rig| {
        rig.screens.until("fake rig #1 connected").await;
        fake.status.send_modify(|axes| {
            axes[2].position = Some(-4242);
            axes[2].errors = vec![AxisFlag {
                name: "stall",
                description: "test",
            }];
        });
        let frame = rig.screens.until("-4242").await;
        assert!(frame.contains("ERR stall"), "{frame}");
        fake.link.send_replace(LinkState::Disconnected {
            reason: "cable pulled".into(),
            attempts: 0,
            retry_in: Duration::from_secs(1),
        });
        rig.screens.until("LOST: cable pulled").await;
        let _ = rig.extra.send(AppEvent::Terminate);
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn the_stop_goes_out_at_once_while_lines_wait_and_a_batch_goes_no_further() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("moves.txt");
    std::fs::write(
        &file,
        "MVP ABS, 0, 51200\nMVP ABS, 0, 0\nMVP ABS, 0, 51200\n",
    )
    .expect("write");
    let (fake, mut calls) = Fake::new(&["motor 0"]);
    run_console(Some(fake.clone()), no_connector(), async |mut rig: Rig| {
        assert!(matches!(next_call(&mut calls).await, Call::Poll(_)));
        type_line(&rig, &format!(":run {}", file.display()));
        let Call::Execute(first, pending_answer) = next_call(&mut calls).await else {
            panic!("expected the first move")
        };
        assert_eq!(first, "MVP ABS, 0, 51200");
        // A typed line waits behind it.
        type_line(&rig, "GAP 1, 0");
        let Call::Execute(typed, _typed_answer) = next_call(&mut calls).await else {
            panic!("expected the typed line")
        };
        assert_eq!(typed, "GAP 1, 0");
        // Neither has an answer: the stop does not wait for them.
        press(&rig, KeyCode::F(12));
        assert!(matches!(next_call(&mut calls).await, Call::Stop));
        let frame = rig.screens.until("STOP confirmed").await;
        assert!(frame.contains("the batch was stopped"), "{frame}");
        // The first move's answer comes after all: nothing more is sent.
        let _ = pending_answer.send(ok("MVP ABS, 0, 51200"));
        type_line(&rig, ":echo after");
        rig.screens.until("after").await;
        assert!(calls.try_recv().is_err(), "nothing was sent after the stop");
        press(&rig, KeyCode::F(10));
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn connect_opens_a_controller_and_the_console_follows_it() {
    let (fake, _calls) = Fake::new(&["X", "Y"]);
    let offered = Arc::new(Mutex::new(Some(fake as Arc<dyn Controller>)));
    let asked = Arc::new(Mutex::new(Vec::new()));
    let asked_in = Arc::clone(&asked);
    let connector: Connector = Box::new(move |args| {
        if let Ok(mut asked) = asked_in.lock() {
            asked.push(args);
        }
        let controller = offered.lock().ok().and_then(|mut o| o.take());
        Box::pin(async move { controller.ok_or_else(|| "gone".to_string()) })
    });
    run_console(None, connector, async |mut rig: Rig| {
        rig.screens.until("not connected").await;
        type_line(&rig, ":connect --sim tmcm1110");
        let frame = rig.screens.until("fake rig #1 connected").await;
        assert!(frame.contains("▶X") && frame.contains(" Y "), "{frame}");
        type_line(&rig, ":connect --sim tmcm1110");
        rig.screens.until("gone").await;
        press(&rig, KeyCode::F(10));
    })
    .await;
    let asked = asked.lock().map(|a| a.clone()).unwrap_or_default();
    assert_eq!(asked[0], ["--sim", "tmcm1110"]);
}

// On the real clock: the log file is written by a thread of its own, and a
// paused clock would run the wait for its "closed" notice out (virtual time
// jumps ahead whenever the runtime is idle, as it is while that thread
// works), which made this test fail on a loaded machine.
#[tokio::test]
async fn log_writes_every_frame_to_a_file_until_it_is_turned_off() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("wire.log");
    let (fake, _calls) = Fake::new(&["motor 0"]);
    run_console(Some(fake.clone()), no_connector(), async |mut rig: Rig| {
        type_line(&rig, &format!(":log {}", file.display()));
        rig.screens.until("logging every frame to").await;
        let at = std::time::Instant::now();
        let record = |direction, kind, priority, bytes: &[u8], ms| TrafficRecord {
            at: at + Duration::from_millis(ms),
            direction,
            kind,
            bytes: bytes.to_vec(),
            priority,
        };
        let _ = fake.traffic.send(record(
            Direction::Sent,
            TrafficKind::Request,
            Some(Priority::User),
            &[1, 6, 1, 0, 0, 0, 0, 0, 8],
            0,
        ));
        let _ = fake.traffic.send(record(
            Direction::Received,
            TrafficKind::Answer,
            None,
            &[2, 1, 100, 6, 0, 0, 0, 0, 109],
            2,
        ));
        type_line(&rig, ":log off");
        rig.screens.until("closed: 2 frames").await;
        press(&rig, KeyCode::F(10));
    })
    .await;
    let log = std::fs::read_to_string(&file).expect("log file");
    // Each line starts with its wall-clock time, `2025-03-07T14:05:09.123Z `.
    let lines: Vec<&str> = log
        .lines()
        .map(|line| {
            let (stamp, rest) = line.split_at_checked(25).unwrap_or_default();
            assert!(
                stamp.len() == 25
                    && stamp.as_bytes().get(10) == Some(&b'T')
                    && stamp.ends_with("Z "),
                "{line}"
            );
            rest
        })
        .collect();
    assert_eq!(
        lines,
        [
            "       0.000 ms -> request     user     01 06 01 00 00 00 00 00 08",
            "       2.000 ms <- answer      -        02 01 64 06 00 00 00 00 6D",
        ]
    );
}

/// A status poll going out (GAP 1, 0).
fn poll_record() -> TrafficRecord {
    TrafficRecord {
        at: std::time::Instant::now(),
        direction: Direction::Sent,
        kind: TrafficKind::Request,
        bytes: vec![1, 6, 1, 0, 0, 0, 0, 0, 8],
        priority: Some(Priority::Poll),
    }
}

#[tokio::test(start_paused = true)]
async fn traffic_is_taken_in_batches_not_one_wake_up_per_frame() {
    let (fake, _calls) = Fake::new(&["motor 0"]);
    run_console(Some(fake.clone()), no_connector(), async |mut rig: Rig| {
        rig.screens.until("fake rig #1 connected").await;
        // The traffic monitor to the front.
        press_with(&rig, KeyCode::Char('4'), KeyModifiers::ALT);
        rig.screens.until("no frames yet").await;
        // The first frame after a quiet spell shows at once.
        let _ = fake.traffic.send(poll_record());
        rig.screens.until("1 frames").await;
        // Those that follow wait in the channel for the batch: the loop is
        // not woken for each.
        for _ in 0..4 {
            let _ = fake.traffic.send(poll_record());
        }
        for _ in 0..10 {
            tokio::task::yield_now().await;
        }
        tokio::time::advance(app::TRAFFIC_BATCH / 2).await;
        for _ in 0..10 {
            tokio::task::yield_now().await;
        }
        assert_eq!(fake.traffic.len(), 4, "not taken yet");
        // Then all at once, and none lost.
        rig.screens.until("5 frames").await;
        assert_eq!(fake.traffic.len(), 0);
        press(&rig, KeyCode::F(10));
    })
    .await;
}

#[tokio::test(start_paused = true)]
async fn behind_its_tab_the_monitor_takes_traffic_still_less_often_and_in_front_at_once() {
    let (fake, _calls) = Fake::new(&["motor 0"]);
    run_console(Some(fake.clone()), no_connector(), async |mut rig: Rig| {
        // 100x30: the command pane in front, the traffic monitor behind.
        rig.screens.until("fake rig #1 connected").await;
        // A frame every 50 ms for a second: the pauses between batches
        // grow past the monitor's refresh.
        let mut most_waiting = 0;
        for _ in 0..20 {
            let _ = fake.traffic.send(poll_record());
            for _ in 0..5 {
                tokio::task::yield_now().await;
            }
            most_waiting = most_waiting.max(fake.traffic.len());
            tokio::time::advance(Duration::from_millis(50)).await;
        }
        assert!(
            most_waiting * 50 > app::TRAFFIC_BATCH.as_millis() as usize * 2,
            "at most {most_waiting} frames waited"
        );
        // Brought to the front, it shows every frame without waiting out
        // the pause.
        press_with(&rig, KeyCode::Char('4'), KeyModifiers::ALT);
        let within = app::TRAFFIC_BATCH + Duration::from_millis(1);
        let shown = tokio::time::timeout(within, rig.screens.until("20 frames")).await;
        assert!(shown.is_ok(), "the frames waited out the pause");
        assert_eq!(fake.traffic.len(), 0);
        press(&rig, KeyCode::F(10));
    })
    .await;
}
