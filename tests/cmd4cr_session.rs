//! The CMD-4CR family through the unchanged session and device task, on
//! tokio's paused clock, against a tiny scripted controller behind the
//! in-process link (the real simulator is another engineer's): the poll
//! plan fills the status of all four axes (PP gives four positions in one
//! reading), MST bits become switches, errors and lamps, a per-axis HSPD
//! of 0 falls back to the global one, and the emergency stop sends its
//! lines in order.

mod session_support;

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::families::find_family;
use axterm::link::LinkSpec;
use axterm::protocol::cmd4cr::parse_request;
use axterm::protocol::console::MotionPhase;
use axterm::session::{AxisMotion, PollCadence, ReplyValue, Session, SessionError, SessionOptions};
use axterm::sim::SimulatedController;
use axterm::sim::faults::FaultPlan;
use session_support::wait_for;

/// A controller that answers each command text from a table (`OK` for
/// anything with `=` and for actions it does not know, like the manual's
/// STORE), and logs what it received.
struct Scripted {
    id: u8,
    answers: Arc<Mutex<HashMap<String, String>>>,
    received: Arc<Mutex<Vec<String>>>,
    input: Vec<u8>,
    output: Vec<u8>,
}

impl SimulatedController for Scripted {
    fn feed(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            if byte != b'\r' {
                self.input.push(byte);
                continue;
            }
            let line = std::mem::take(&mut self.input);
            let Ok(request) = parse_request(&line) else {
                continue;
            };
            if request.id != self.id {
                continue; // Another controller's frame: silence.
            }
            self.received
                .lock()
                .expect("log")
                .push(request.text.clone());
            let answer = self
                .answers
                .lock()
                .expect("answers")
                .get(&request.text)
                .cloned()
                .unwrap_or_else(|| "OK".into());
            self.output.extend_from_slice(answer.as_bytes());
            self.output.push(b'\r');
        }
    }

    fn advance(&mut self, _dt: Duration) {}

    fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.output)
    }

    fn help(&self) -> String {
        "scripted CMD-4CR".into()
    }
}

struct Fake {
    answers: Arc<Mutex<HashMap<String, String>>>,
    received: Arc<Mutex<Vec<String>>>,
}

impl Fake {
    fn set(&self, command: &str, answer: &str) {
        self.answers
            .lock()
            .expect("answers")
            .insert(command.into(), answer.into());
    }

    fn received(&self) -> Vec<String> {
        self.received.lock().expect("log").clone()
    }
}

async fn connect(answers: &[(&str, &str)]) -> (Session, Fake) {
    let fake = Fake {
        answers: Arc::new(Mutex::new(
            answers
                .iter()
                .map(|(c, a)| (c.to_string(), a.to_string()))
                .collect(),
        )),
        received: Arc::default(),
    };
    let controller = Scripted {
        id: 1,
        answers: Arc::clone(&fake.answers),
        received: Arc::clone(&fake.received),
        input: Vec::new(),
        output: Vec::new(),
    };
    let spec = LinkSpec::Sim {
        kind: "scripted cmd4cr".into(),
        sim: Arc::new(Mutex::new(Box::new(controller))),
        baud: Some(9600),
        faults: FaultPlan::none(),
    };
    let family = find_family("cmd4cr").expect("registered");
    let session = Session::connect(spec, family, SessionOptions::default())
        .await
        .expect("the link opens");
    (session, fake)
}

const STANDING: &[(&str, &str)] = &[
    ("PP", "100:-200:300:-400"),
    ("MSTX", "0"),
    ("MSTY", "0"),
    ("MSTZ", "0"),
    ("MSTU", "0"),
    ("PSX", "0"),
    ("PSY", "0"),
    ("PSZ", "0"),
    ("PSU", "0"),
    ("HSPD", "5000"),
    ("HSPDX", "0"),
    ("HSPDY", "800"),
    ("HSPDZ", "0"),
    ("HSPDU", "0"),
    ("VER", "V126BL"),
];

#[tokio::test(start_paused = true)]
async fn polling_fills_the_status_of_all_four_axes() {
    let (session, fake) = connect(STANDING).await;
    assert_eq!(session.status().borrow().len(), 4);
    session.start_polling(PollCadence::default());
    let axes = wait_for(&session, |axes| {
        axes.iter()
            .all(|a| a.position.is_some() && a.own_max_speed.is_some())
    })
    .await;
    let positions: Vec<Option<i64>> = axes.iter().map(|a| a.position).collect();
    assert_eq!(positions, [Some(100), Some(-200), Some(300), Some(-400)]);
    // X, Z and U use the global HSPD (theirs is 0, §2.1.4); Y its own.
    let max: Vec<Option<i64>> = axes.iter().map(|a| a.max_speed).collect();
    assert_eq!(max, [Some(5000), Some(800), Some(5000), Some(5000)]);
    // Standing (MST 0), no move sent: stopped, nothing reached.
    assert!(axes.iter().all(|a| a.motion() == AxisMotion::Stopped));
    // One PP reads all positions: no per-axis position query is polled.
    let received = fake.received();
    assert!(received.contains(&"PP".to_string()));
    assert!(!received.iter().any(|r| r == "PX"));
}

#[tokio::test(start_paused = true)]
async fn mst_bits_show_as_switches_errors_and_lamps() {
    let (session, fake) = connect(STANDING).await;
    // Y: + limit input on, + limit error latched, EMG signal on, moving
    // at constant speed.
    fake.set("MSTY", &(4 | 16 | 256 | (1 << 15)).to_string());
    fake.set("PSY", "1200");
    session.start_polling(PollCadence::default());
    let axes = wait_for(&session, |axes| !axes[1].errors.is_empty()).await;
    let y = &axes[1];
    assert_eq!(y.right_switch, Some(true));
    assert_eq!(y.left_switch, Some(false));
    assert_eq!(y.home_switch, Some(false));
    assert_eq!(y.phase, Some(MotionPhase::Constant));
    let errors: Vec<&str> = y.errors.iter().map(|f| f.name).collect();
    assert_eq!(errors, ["+limit error"]);
    let lamps: Vec<&str> = y.driver_flags.iter().flatten().map(|f| f.name).collect();
    assert_eq!(lamps, ["EMG"]);
    let axes = wait_for(&session, |axes| axes[1].speed.is_some()).await;
    assert_eq!(axes[1].speed, Some(1200));
    // Cleared on the controller: the console keeps the error until the
    // user acknowledges it.
    fake.set("MSTY", "0");
    let axes = wait_for(&session, |axes| {
        axes[1].phase == Some(MotionPhase::Standing)
    })
    .await;
    assert_eq!(axes[1].errors.len(), 1);
}

#[tokio::test(start_paused = true)]
async fn lines_answer_with_values_and_refusals() {
    let (session, fake) = connect(STANDING).await;
    fake.set("X1000", "?Error Moving");
    fake.set("SLRX", "1.5");
    assert_eq!(
        session.execute_line("hspdx=5000").await.expect("ok").value,
        ReplyValue::None
    );
    assert_eq!(
        session.execute_line("SLRX").await.expect("read").value,
        ReplyValue::Text("1.5".into())
    );
    let error = session.execute_line("X1000").await.unwrap_err();
    assert!(
        error
            .to_string()
            .contains("controller 01 refused X1000: ?Error Moving"),
        "{error}"
    );
    assert!(matches!(
        session.execute_line("DI5").await,
        Err(SessionError::Refused { .. })
    ));
    assert_eq!(session.identify().await.expect("VER"), "V126BL");
    // A user's PP read updates the status as a poll would.
    session.execute_line("PP").await.expect("read");
    let axes = session.status().borrow().clone();
    assert_eq!(axes[3].position, Some(-400));
    assert_eq!(
        fake.received(),
        ["HSPDX=5000", "SLRX", "X1000", "VER", "PP"],
        "DI5 was never sent"
    );
}

#[tokio::test(start_paused = true)]
async fn a_write_answered_other_than_ok_is_an_error_with_the_bytes() {
    let (session, fake) = connect(STANDING).await;
    // A controller that answers a write with something else (the manual
    // shows `OK` only): never taken for success.
    fake.set("HSPDX=5000", "5000");
    fake.set("JX+", "fK");
    for (line, reply) in [("HSPDX=5000", "5000"), ("JX+", "fK")] {
        let error = session.execute_line(line).await.unwrap_err();
        assert_eq!(error.reply(), Some(reply.as_bytes()), "{error}");
        assert!(
            error.to_string().starts_with(&format!(
                "unreadable answer to {line}: `{reply}` is not OK, the answer to a write or action \
                 (garbled: nothing readable came within "
            )),
            "{error}"
        );
        assert_eq!(error.request(), Some(format!("@01{line}\r").as_bytes()));
    }
    // Sent once each: a write is never sent again.
    assert_eq!(
        fake.received()
            .iter()
            .filter(|r| !STANDING.iter().any(|(c, _)| c == r) && *r != "PX")
            .collect::<Vec<_>>(),
        ["HSPDX=5000", "JX+"]
    );
}

#[tokio::test(start_paused = true)]
async fn the_emergency_stop_stops_motion_then_the_programs() {
    let (session, fake) = connect(STANDING).await;
    let results = session.emergency_stop_lines().await;
    let lines: Vec<String> = results
        .into_iter()
        .map(|r| r.expect("answered").line)
        .collect();
    let expected = [
        "ESTOP",
        "SACTRL0=0",
        "SACTRL1=0",
        "SACTRL2=0",
        "SACTRL3=0",
        "ESTOP",
    ];
    assert_eq!(lines, expected);
    assert_eq!(fake.received(), expected);
}

#[tokio::test(start_paused = true)]
async fn another_id_on_the_bus_is_addressed_by_its_own_frames() {
    let (session, fake) = connect(STANDING).await;
    let probe = session.probe(2, Duration::from_millis(200)).await;
    assert!(
        matches!(probe, Err(SessionError::Device { .. })),
        "no controller 02: {probe:?}"
    );
    assert!(fake.received().is_empty(), "controller 01 ignored @02VER");
    assert_eq!(
        session
            .probe(1, Duration::from_millis(200))
            .await
            .ok()
            .as_deref(),
        Some("V126BL")
    );
}
