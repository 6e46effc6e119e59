//! An MCCL session over the device task, the test playing the controller on
//! a scripted 9600 Bd link with bytes written out by hand (echo, `01 value`
//! lines, `>`), on tokio's paused clock: a line that waits for motion is
//! held busy for as long as it runs, Escape aborts it and Space pauses it,
//! the emergency stop aborts it first; polling reads every axis's status;
//! the emergency stop aborts every axis and ends every task; the connect
//! probe learns the interface and `HM`, `PC` change how lines go.

mod device_support;
mod session_support;

use std::time::Duration;

use axterm::device::{DeviceError, DeviceOptions};
use axterm::families::find_family;
use axterm::session::{PollCadence, Session, SessionError, SessionOptions};
use device_support::{Script, device_with};
use session_support::wait_for;
use tokio::time::sleep;

fn session() -> (Session, Script) {
    let family = find_family("mccl").expect("the mccl family");
    let (device, script) = device_with(family.console.wire(), DeviceOptions::default());
    let session = Session::new(device, family, &SessionOptions::default());
    (session, script)
}

/// The controller's answer to `line`: its echo, `replies`, the prompt.
fn answer(line: &str, replies: &[&str]) -> Vec<u8> {
    let mut text = format!("{line}\r\n");
    for reply in replies {
        text.push_str(reply);
        text.push_str("\r\n");
    }
    text.push('>');
    text.into_bytes()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes)
        .trim_end_matches('\r')
        .to_string()
}

/// The Tells of a status line, each with the axis the line carried to it
/// (Ch2: "the axis that a command acts on is assumed to be the last one
/// specified in the command string"): `1TP,TV,2TP` → 1 TP, 1 TV, 2 TP.
fn tells(request: &str) -> Vec<(String, String)> {
    let mut axis = String::new();
    request
        .split(',')
        .map(|command| {
            let digits = command.bytes().take_while(u8::is_ascii_digit).count();
            if digits > 0 {
                axis = command[..digits].to_string();
            }
            (axis.clone(), command[digits..].to_string())
        })
        .collect()
}

const CYCLE: &str = "2MR1000,WS0.5,MR-1000,WS0.5,RP6";

fn start(
    session: &Session,
    line: &'static str,
) -> tokio::task::JoinHandle<Result<axterm::session::LineResult, SessionError>> {
    let session = session.clone();
    tokio::spawn(async move { session.execute_line(line).await })
}

#[tokio::test(start_paused = true)]
async fn a_line_that_waits_for_motion_is_held_busy_while_it_runs() {
    let (session, mut script) = session();
    let busy = session.busy();
    let run = start(&session, CYCLE);
    assert_eq!(text(&script.request().await), CYCLE);
    // Seven cycles of a second each, and then some: no timeout at all.
    script.send(format!("{CYCLE}\r\n").as_bytes());
    sleep(Duration::from_secs(700)).await;
    let shown = busy.borrow().clone().expect("busy");
    assert_eq!(shown.bytes, format!("{CYCLE}\r").into_bytes());
    script.send(b">");
    let result = run.await.expect("joined").expect("the line completed");
    assert_eq!(result.value.to_string(), "ok");
    assert_eq!(*busy.borrow(), None);

    // A plain line gets the link's usual timeout.
    let tell = tokio::spawn({
        let session = session.clone();
        async move { session.execute_line("1TP").await }
    });
    assert_eq!(text(&script.request().await), "1TP");
    script.send(b"1TP\r\n");
    let error = tell.await.expect("joined").expect_err("no answer");
    assert!(
        matches!(
            error,
            SessionError::Device {
                error: DeviceError::Timeout { .. },
                ..
            }
        ),
        "{error}"
    );
}

#[tokio::test(start_paused = true)]
async fn escape_aborts_the_busy_line_with_its_error_and_space_pauses_it() {
    let (session, mut script) = session();
    let run = start(&session, CYCLE);
    script.request().await;
    script.send(format!("{CYCLE}\r\n").as_bytes());
    assert_eq!(session.pause_line().await, Some(true));
    assert_eq!(script.request().await, b" ");
    assert_eq!(session.pause_line().await, Some(false));
    assert_eq!(script.request().await, b" ");
    assert!(session.abort_line().await);
    assert_eq!(script.request().await, [0x1B]);
    // The controller's answer to Escape: -7 and the command it was on.
    script.send(b"?-7 WS0.5\r\n>");
    let error = run.await.expect("joined").expect_err("aborted");
    assert_eq!(
        error.to_string(),
        "the controller refused 2MR1000,WS0.5,MR-1000,WS0.5,RP6: ?-7 WS0.5 (Command Canceled \
         by User, Ch14)"
    );
    assert!(!session.abort_line().await, "nothing held any more");
}

#[tokio::test(start_paused = true)]
async fn the_emergency_stop_aborts_a_busy_line_first() {
    let (session, mut script) = session();
    let run = start(&session, CYCLE);
    script.request().await;
    script.send(format!("{CYCLE}\r\n").as_bytes());
    sleep(Duration::from_secs(3)).await;
    let stop = tokio::spawn({
        let session = session.clone();
        async move { session.emergency_stop_lines().await }
    });
    assert_eq!(script.request().await, [0x1B], "Escape first");
    script.send(b"?-7 WS0.5\r\n>");
    assert!(run.await.expect("joined").is_err());
    assert_eq!(text(&script.request().await), "0AB");
    script.send(&answer("0AB", &[]));
    for n in 1..=21 {
        let request = text(&script.request().await);
        assert_eq!(request, format!("ET{n}"));
        script.send(&answer(&request, &["?-20"]));
    }
    let results = stop.await.expect("joined");
    assert!(results.iter().all(Result::is_ok));
}

#[tokio::test(start_paused = true)]
async fn the_connect_probe_learns_the_interface() {
    let (session, mut script) = session();
    let learn = tokio::spawn({
        let session = session.clone();
        async move { session.learn_link().await }
    });
    assert_eq!(script.request().await, b"NO\r");
    script.send(b"NO\r\n#");
    assert_eq!(script.request().await, b"NO,NO,NO\r");
    script.send(b"NO,NO,NO\r\n#");
    assert_eq!(learn.await.expect("joined"), Some(Ok(())));
    let summary = session
        .link_context()
        .borrow()
        .as_ref()
        .and_then(|c| c.summary());
    assert_eq!(summary.as_deref(), Some("prompt `#`"));
    // The prompt learned ends the next answer.
    let tell = start(&session, "1TP");
    script.request().await;
    script.send(b"1TP\r\n01 5\r\n#");
    assert_eq!(
        tell.await.expect("joined").expect("read").value.to_string(),
        "5"
    );
}

#[tokio::test(start_paused = true)]
async fn hm_pauses_polling_and_it_resumes_written_in_hex() {
    let (session, mut script) = session();
    session.start_polling(PollCadence::default());
    // Answer the first round of polls in decimal.
    for _ in 0..10 {
        let request = text(&script.request().await);
        let replies: Vec<String> = tells(&request)
            .into_iter()
            .map(|(axis, tell)| match tell.as_str() {
                "TV" | "TF" => format!("0{axis} 0"),
                "TS" => format!("0{axis} 14"),
                _ => format!("0{axis} 5"),
            })
            .collect();
        let replies: Vec<&str> = replies.iter().map(String::as_str).collect();
        script.send(&answer(&request, &replies));
    }
    let hm = start(&session, "HM");
    // Whatever poll was on the wire is answered; then HM, and no poll
    // until its answer.
    let mut request = text(&script.request().await);
    while request != "HM" {
        let replies: Vec<String> = tells(&request)
            .into_iter()
            .map(|(axis, _)| format!("0{axis} 0"))
            .collect();
        let replies: Vec<&str> = replies.iter().map(String::as_str).collect();
        script.send(&answer(&request, &replies));
        request = text(&script.request().await);
    }
    // Within HM's reply timeout (about 190 ms at 9600 Bd).
    sleep(Duration::from_millis(150)).await;
    assert!(script.nothing_written(), "no poll while HM is on its way");
    script.send(&answer("HM", &[]));
    hm.await.expect("joined").expect("HM");
    // The very first poll after it is read in hex: -1000 is fffffc18.
    let request = text(&script.request().await);
    assert!(request.starts_with("1TP,TV,TS,2TP,TV,TS"), "{request}");
    let replies: Vec<String> = tells(&request)
        .into_iter()
        .map(|(axis, tell)| match (axis.as_str(), tell.as_str()) {
            ("1", "TP") => "01 fffffc18".to_string(),
            ("1", "TV") => "01 00000064".to_string(),
            (_, "TS") => format!("0{axis} 0000000e"),
            _ => format!("0{axis} 00000000"),
        })
        .collect();
    let replies: Vec<&str> = replies.iter().map(String::as_str).collect();
    script.send(&answer(&request, &replies));
    let axes = wait_for(&session, |axes| axes[0].position == Some(-1000)).await;
    assert_eq!(axes[0].speed, Some(100));
}

#[tokio::test(start_paused = true)]
async fn polling_reads_position_velocity_status_target_and_following_error() {
    let (session, mut script) = session();
    session.start_polling(PollCadence::default());
    let status = async {
        loop {
            let request = text(&script.request().await);
            let replies: Vec<String> = tells(&request)
                .into_iter()
                .map(|(axis, tell)| match (axis.as_str(), tell.as_str()) {
                    // Axis 2: moving, hard limit + tripped and its input on.
                    ("2", "TP") => "02 -500".to_string(),
                    ("2", "TV") => "02 1200".to_string(),
                    ("2", "TS") => "02 268436489".to_string(),
                    (_, "TP" | "TV") => format!("0{axis} 0"),
                    (_, "TS") => format!("0{axis} 14"),
                    // Axis 5, a stepper, has no TF.
                    ("5", "TT") => "05 0".to_string(),
                    (_, "TT") => format!("0{axis} 1000"),
                    (_, "TF") => format!("0{axis} 3"),
                    (_, other) => panic!("unexpected poll {other} in {request}"),
                })
                .collect();
            let replies: Vec<&str> = replies.iter().map(String::as_str).collect();
            script.send(&answer(&request, &replies));
        }
    };
    let axes = tokio::select! {
        axes = wait_for(&session, |axes| {
            axes.len() == 5
                && axes[1].position == Some(-500)
                && axes[1].following_error == Some(3)
                && axes[0].reached == Some(true)
                && axes[4].target == Some(0)
        }) => axes,
        _ = status => unreachable!("the script answers for ever"),
    };
    let moving = &axes[1];
    assert_eq!(moving.speed, Some(1200));
    assert_eq!(moving.target, Some(1000));
    assert_eq!(moving.right_switch, Some(true));
    assert_eq!(moving.reached, Some(false));
    let errors: Vec<&str> = moving.errors.iter().map(|f| f.name).collect();
    assert_eq!(errors, ["motor error", "hard limit +"]);
    // Axis 1: motor on, at target, trajectory complete (14 = bits 1–3).
    let lamps: Vec<&str> = axes[0]
        .driver_flags
        .as_deref()
        .unwrap_or_default()
        .iter()
        .map(|f| f.name)
        .collect();
    assert_eq!(lamps, ["motor"]);
    assert_eq!(
        axes[4].following_error, None,
        "an open-loop stepper has none"
    );
}

#[tokio::test(start_paused = true)]
async fn the_emergency_stop_aborts_every_axis_then_ends_every_task() {
    let (session, mut script) = session();
    let stop = tokio::spawn({
        let session = session.clone();
        async move { session.emergency_stop_lines().await }
    });
    let mut sent = Vec::new();
    for _ in 0..22 {
        let request = text(&script.request().await);
        // Task 3 is running; no other ID is a task's.
        let replies: &[&str] = match request.as_str() {
            "0AB" | "ET3" => &[],
            _ => &["?-20"],
        };
        script.send(&answer(&request, replies));
        sent.push(request);
    }
    let results = stop.await.expect("joined");
    assert_eq!(sent[0], "0AB");
    assert_eq!(sent[1..4], ["ET1", "ET2", "ET3"]);
    assert_eq!(sent.last().map(String::as_str), Some("ET21"));
    let values: Vec<String> = results
        .iter()
        .map(|r| {
            r.as_ref()
                .map(|r| r.value.to_string())
                .unwrap_or_else(|e| e.to_string())
        })
        .collect();
    assert_eq!(values[0], "ok");
    assert_eq!(values[3], "ok", "task 3 ended");
    assert!(
        values[1].starts_with("no background task 1: nothing to end (?-20)"),
        "{}",
        values[1]
    );
    assert!(results.iter().all(Result::is_ok));
}
