//! The console's emergency stop goes ahead of everything queued: with a
//! move on the wire, more lines and status polls waiting behind it, the
//! stop lines are the next requests the device task sends, and the lines
//! the console dropped are never sent after them. Through the console's
//! own controller, on the in-process TMCM-1110 simulator with 9600 baud
//! wire time, on virtual time.

mod ui_support;

use std::time::Duration;

use axterm::device::{Direction, Priority, TrafficKind, TrafficRecord};
use axterm::session::PollCadence;
use tokio::sync::broadcast;
use ui_support::sim_controller;

/// The next request sent (answers and the rest skipped).
async fn next_request(traffic: &mut broadcast::Receiver<TrafficRecord>) -> TrafficRecord {
    let wait = async {
        loop {
            match traffic.recv().await {
                Ok(r) if r.direction == Direction::Sent && r.kind == TrafficKind::Request => {
                    return r;
                }
                Ok(_) => {}
                Err(e) => panic!("traffic stream: {e}"),
            }
        }
    };
    tokio::time::timeout(Duration::from_secs(60), wait)
        .await
        .expect("a request was sent")
}

#[tokio::test(start_paused = true)]
async fn the_stop_lines_go_before_queued_lines_and_polls() {
    let controller = sim_controller("tmcm1110", 9600).await;
    let mut traffic = controller.traffic().expect("a traffic stream");
    controller.set_polling(Some(PollCadence {
        fast: Duration::from_millis(10),
        slow: Duration::from_millis(10),
    }));
    // Polls are flowing.
    let first = next_request(&mut traffic).await;
    assert_eq!(first.priority, Some(Priority::Poll));

    // Three moves queued behind whatever is on the wire.
    let mut moves = Vec::new();
    for line in ["MVP ABS, 0, 51200", "MVP ABS, 0, 0", "MVP ABS, 0, 51200"] {
        moves.push(tokio::spawn(controller.execute(line.to_string())));
    }
    // Wait until the first move is on the wire: the others and the polls
    // now wait in the queues.
    loop {
        let request = next_request(&mut traffic).await;
        if request.priority == Some(Priority::User) {
            break;
        }
    }
    // As the console does: drop the lines still waiting, then stop.
    for job in &moves {
        job.abort();
    }
    let stop = tokio::spawn(controller.emergency_stop());

    let mut after = Vec::new();
    for _ in 0..3 {
        after.push(next_request(&mut traffic).await);
    }
    let priorities: Vec<_> = after.iter().map(|r| r.priority).collect();
    assert_eq!(priorities, [Some(Priority::EmergencyStop); 3], "{after:?}");
    let stop_lines: Vec<&[u8]> = after.iter().map(|r| r.bytes.as_slice()).collect();
    assert_eq!(
        stop_lines,
        [
            &[0x01, 0x03, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04][..], // MST 0
            &[0x01, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x81][..], // STOPAPP
            &[0x01, 0x03, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04][..], // MST 0
        ]
    );
    let results = stop.await.expect("the stop task");
    assert_eq!(results.len(), 3);
    for result in &results {
        let result = result.as_ref().expect("every stop line answered");
        assert_eq!(result.status, Some(100));
    }
    // Polling goes on; the moves that were waiting never go out.
    for _ in 0..20 {
        let request = next_request(&mut traffic).await;
        assert_eq!(request.priority, Some(Priority::Poll), "{request:?}");
    }
}

#[tokio::test(start_paused = true)]
async fn after_the_emergency_stop_the_axis_lamp_says_stopped_short_not_moving() {
    use ratatui::crossterm::event::KeyCode;
    use ui_support::looped::{enter, press, run_command_console};
    let controller = sim_controller("tmcm1110", 115_200).await;
    run_command_console(controller, (80, 24), async |rig| {
        enter(rig, "SAP 4, 0, 1500");
        enter(rig, "MVP ABS, 0, 512000000");
        rig.screens
            .until_frame("the axis moving at full speed", |f| {
                f.contains("○ moving") && f.contains("at max speed")
            })
            .await;
        press(rig, KeyCode::F(12));
        let frame = rig
            .screens
            .until_frame("the axis standing after the stop", |f| {
                f.contains("standing") && f.contains("STOP confirmed")
            })
            .await;
        let lamp_row = frame.lines().nth(1).unwrap_or_default();
        assert!(lamp_row.contains("○ stopped short"), "{frame}");
        assert!(!lamp_row.contains("moving"), "{frame}");
    })
    .await;
}
