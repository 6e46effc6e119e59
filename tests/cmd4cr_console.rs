//! The CMD-4CR through the session on the real simulator (in process, with
//! the wire time of 9600 Bd, the factory rate), on tokio's paused clock:
//! the poll plan of four axes on a 9600-baud line (the slow items kept to
//! their share, a user's line behind at most the poll on the wire, the
//! refresh rate measured), and clearing latched errors with `CLR[axis]`
//! so that the next poll does not bring them back.

mod session_support;

use std::time::Duration;

use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::device::{Direction, Priority, TrafficRecord};
use axterm::families::find_family;
use axterm::protocol::console::{MotionPhase, MoveMode};
use axterm::session::{
    AxisMotion, PollCadence, SLOW_SHARE_DIVISOR, Session, SessionError, slow_period,
};
use session_support::{GIVE_UP_AFTER, wait_for};
use tokio::sync::broadcast;

async fn session(kind: &str, baud: u32) -> Session {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some(kind.into()),
        baud: Some(baud),
        ..ConnectionArgs::default()
    })
    .expect("a simulator connection");
    target.open().await.expect("the simulator opens")
}

async fn run(session: &Session, line: &str) {
    if let Err(e) = session.execute_line(line).await {
        panic!("{line}: {e}");
    }
}

/// Every record of the traffic stream until `until` (virtual time).
async fn record_traffic(
    traffic: &mut broadcast::Receiver<TrafficRecord>,
    until: tokio::time::Instant,
) -> Vec<TrafficRecord> {
    let mut records = Vec::new();
    while let Ok(Ok(record)) = tokio::time::timeout_at(until, traffic.recv()).await {
        records.push(record);
    }
    records
}

/// The command text of a request frame (`@01MSTX\r` → `MSTX`).
fn command(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes.get(3..).unwrap_or_default())
        .trim_end()
        .to_string()
}

#[tokio::test(start_paused = true)]
async fn four_axes_are_polled_within_a_9600_baud_line() {
    let session = session("cmd4cr", 9600).await;
    let mut traffic = session.device().traffic();
    session.start_polling(PollCadence::default());
    let axes = wait_for(&session, |axes| {
        axes.iter().all(|a| {
            a.position.is_some()
                && a.speed.is_some()
                && a.max_speed.is_some()
                && a.refresh.is_some()
        })
    })
    .await;
    // Standing, and no move sent: stopped, with no target to have reached
    // (MST's motion complete is no "reached", §2.2.4).
    assert!(
        axes.iter().all(|a| a.motion() == AxisMotion::Stopped),
        "{axes:?}"
    );

    // Ten seconds of polling: what each item got of the line.
    let records = record_traffic(
        &mut traffic,
        tokio::time::Instant::now() + Duration::from_secs(10),
    )
    .await;
    // Bytes both ways, and requests, per command.
    let mut by_command: std::collections::BTreeMap<String, usize> = Default::default();
    let mut sent: std::collections::BTreeMap<String, usize> = Default::default();
    let mut last_request = String::new();
    for record in &records {
        assert_eq!(record.priority.unwrap_or(Priority::Poll), Priority::Poll);
        if record.direction == Direction::Sent {
            last_request = command(&record.bytes);
            *sent.entry(last_request.clone()).or_default() += 1;
        }
        *by_command.entry(last_request.clone()).or_default() += record.bytes.len();
    }
    let total: usize = by_command.values().sum();
    let slow: usize = by_command
        .iter()
        .filter(|(c, _)| c.starts_with("HSPD"))
        .map(|(_, bytes)| bytes)
        .sum();
    // The slow items (HSPD, HSPDX..U) keep to their share of the line.
    assert!(
        slow * SLOW_SHARE_DIVISOR as usize <= total,
        "HSPD polls took {slow} of {total} bytes: {by_command:?}"
    );
    assert!(
        slow > 0,
        "the maximum speeds are still read: {by_command:?}"
    );
    // The fast items share the rest: no per-axis position read (PP reads
    // all four), each MST and PS about as often as PP.
    let times = |command: &str| sent.get(command).copied().unwrap_or(0);
    let pp = times("PP");
    for axis in ["X", "Y", "Z", "U"] {
        for command in [format!("MST{axis}"), format!("PS{axis}")] {
            assert!(
                times(&command).abs_diff(pp) <= 1,
                "{command}, PP {pp}: {sent:?}"
            );
        }
        assert_eq!(times(&format!("P{axis}")), 0);
    }

    // The refresh rate shown is what came: never more than the wire
    // allows for one round of the fast items (bytes × 10 bits / 9600).
    let round_bytes = "@01PP\r0:0:0:0\r".len() + 4 * "@01MSTX\r0\r".len() + 4 * "@01PSX\r0\r".len();
    let wire_limit = 9600.0 / (10.0 * round_bytes as f64);
    let refresh = session.status().borrow()[0]
        .refresh
        .expect("measured")
        .per_second();
    assert!(
        refresh > 0.0 && refresh <= wire_limit,
        "{refresh} of {wire_limit}"
    );
    assert!(
        (pp as f64 / 10.0 - refresh).abs() <= 0.5,
        "{refresh}/s shown, {pp} rounds in 10 s"
    );
}

#[tokio::test(start_paused = true)]
async fn a_typed_line_waits_for_at_most_the_poll_on_the_wire() {
    let session = session("cmd4cr", 9600).await;
    let mut traffic = session.device().traffic();
    session.start_polling(PollCadence {
        fast: Duration::ZERO,
        slow: Duration::ZERO,
    });
    wait_for(&session, |axes| axes.iter().all(|a| a.refresh.is_some())).await;
    for line in ["PX", "HSPDY=2000", "MSTZ", "VER"] {
        // Whatever was sent before now is behind us.
        while traffic.try_recv().is_ok() {}
        run(&session, line).await;
        let mut polls_sent = 0;
        loop {
            let record = traffic.try_recv().expect("the line went out");
            if record.direction != Direction::Sent {
                continue;
            }
            if record.priority == Some(Priority::User) {
                assert_eq!(command(&record.bytes), line);
                break;
            }
            polls_sent += 1;
        }
        // The poll on the wire when the line came was sent before it was
        // typed: not one poll went out between the two.
        assert_eq!(polls_sent, 0, "{line}");
    }
    // HSPDY=2000 is the gauge's scale at once.
    assert_eq!(session.status().borrow()[1].max_speed, Some(2000));
}

#[test]
fn the_slow_items_take_a_fortieth_of_a_slow_line_and_their_cadence_on_a_fast_one() {
    let family = find_family("cmd4cr").expect("registered");
    let polls = family.console.status_queries(1);
    let wire = family.console.wire();
    let cadence = PollCadence::default();
    let at = |baud| {
        slow_period(
            cadence,
            Some(axterm::link::byte_time(baud)),
            wire.as_ref(),
            &polls,
        )
    };
    // MM, HSPD, HSPDX..U: 50 request bytes, counted twice: 100 × 1.04 ms
    // × 40.
    assert_eq!(at(9600), axterm::link::byte_time(9600) * 100 * 40);
    assert!(at(115_200) > cadence.slow);
    assert_eq!(at(921_600), cadence.slow);
    assert_eq!(
        slow_period(cadence, None, wire.as_ref(), &polls),
        cadence.slow,
        "TCP: as asked"
    );
}

#[test]
fn a_slow_items_share_counts_an_echo_and_a_turnaround() {
    let byte = axterm::link::byte_time(9600);
    let cadence = PollCadence {
        fast: Duration::ZERO,
        slow: Duration::ZERO,
    };
    let slow_of = |kind: &str| {
        let family = find_family(kind).expect("registered");
        let polls = family.console.status_queries(1);
        let period = slow_period(cadence, Some(byte), family.console.wire().as_ref(), &polls);
        let slow: Vec<Vec<u8>> = polls
            .into_iter()
            .filter(|p| !p.fast)
            .map(|p| p.line.bytes)
            .collect();
        (period, slow)
    };
    // MultiFlex, echo on (Ch2), one line for every axis: each `aTT,TF`
    // of it comes back as its echo (7 with the comma), `0a 0` CR LF twice
    // (12), and the line's CR as CR LF and the prompt: about three times
    // the bytes sent, not twice.
    let (period, slow) = slow_of("mccl");
    assert_eq!(slow, [b"1TT,TF,2TT,TF,3TT,TF,4TT,TF,5TT\r".to_vec()]);
    let bytes: u32 = slow.iter().map(|l| 3 * l.len() as u32).sum();
    assert_eq!(period, byte * bytes * SLOW_SHARE_DIVISOR);
    // SIXpack 2: one `$30` per motor channel, each 9 bytes out, 8 back,
    // after the 6 ms switch-over delay (§6.1.1); counted as 18 bytes and
    // the delay.
    let (period, slow) = slow_of("sixpack2");
    assert_eq!(slow.len(), 6);
    assert_eq!(
        period,
        (byte * 18 + Duration::from_millis(6)) * 6 * SLOW_SHARE_DIVISOR
    );
}

#[tokio::test(start_paused = true)]
async fn clearing_an_error_sends_clr_and_the_next_polls_do_not_bring_it_back() {
    let session = session("cmd4cr", 9600).await;
    session.start_polling(PollCadence::default());
    // X runs into its + end limit (the simulator's stage: ±100000).
    for line in ["HSPDX=400000", "ACCX=10", "X150000"] {
        run(&session, line).await;
    }
    let axes = wait_for(&session, |axes| {
        !axes[0].errors.is_empty() && axes[0].phase == Some(MotionPhase::Standing)
    })
    .await;
    let seen = axes[0].errors.clone();
    let names: Vec<&str> = seen.iter().map(|f| f.name).collect();
    assert_eq!(names, ["+limit error"]);
    // The controller refuses to move X until the error is cleared.
    let refused = session.execute_line("X0").await.unwrap_err();
    assert!(matches!(refused, SessionError::Reply { .. }), "{refused}");

    let cleared = session.clear_errors(0, &seen).await.expect("CLRX answered");
    let cleared = cleared.expect("a line was sent");
    assert_eq!(cleared.line, "CLRX");
    assert_eq!(cleared.request, b"@01CLRX\r".to_vec());
    // Two more rounds of polls: MSTX is read again, without the error.
    let polls = session.device().counters().borrow().polls;
    let mut counters = session.device().counters();
    tokio::time::timeout(GIVE_UP_AFTER, counters.wait_for(|c| c.polls >= polls + 20))
        .await
        .expect("polls go on")
        .expect("the device task is alive");
    let x = session.status().borrow()[0].clone();
    assert!(x.errors.is_empty(), "{:?}", x.errors);
    assert_eq!(x.right_switch, Some(true), "still on the limit switch");
    // And X moves again, away from the limit.
    run(&session, "X0").await;
}

#[tokio::test(start_paused = true)]
async fn a_tmcl_module_needs_no_line_to_clear_its_errors() {
    let session = session("tmcm1110", 9600).await;
    let mut traffic = session.device().traffic();
    let cleared = session.clear_errors(0, &[]).await.expect("nothing to fail");
    assert!(cleared.is_none());
    assert!(traffic.try_recv().is_err(), "nothing was sent");
}

/// Issue 19, point 8: the CMD-4CR has no target register; the target of
/// `X50000` comes from the line sent, read in the move mode (`MM`, polled
/// first, §2.2.4.1), and an emergency stop before it is a stop short of
/// it, not "reached" from MST's motion complete.
#[tokio::test(start_paused = true)]
async fn a_move_shows_its_target_and_an_emergency_stop_before_it_is_short() {
    let session = session("cmd4cr", 9600).await;
    session.start_polling(PollCadence::default());
    let axes = wait_for(&session, |axes| {
        axes[0].move_mode.is_some() && axes[0].position.is_some()
    })
    .await;
    assert_eq!(axes[0].move_mode, Some(MoveMode::Absolute), "read by MM");
    run(&session, "X50000").await;
    assert_eq!(session.status().borrow()[0].target, Some(50000));
    wait_for(&session, |axes| axes[0].motion() == AxisMotion::Moving).await;
    session
        .emergency_stop()
        .await
        .expect("the stop is answered");
    let axes = wait_for(&session, |axes| axes[0].motion() != AxisMotion::Moving).await;
    let x = &axes[0];
    assert!(x.position.is_some_and(|p| p < 50000), "{x:?}");
    assert_eq!(x.motion(), AxisMotion::StoppedShort, "{x:?}");
    // Polls go on: it stays short, whatever MST says of the motion.
    let polls = session.device().counters().borrow().polls;
    let mut counters = session.device().counters();
    tokio::time::timeout(GIVE_UP_AFTER, counters.wait_for(|c| c.polls >= polls + 20))
        .await
        .expect("polls go on")
        .expect("the device task is alive");
    assert_eq!(
        session.status().borrow()[0].motion(),
        AxisMotion::StoppedShort
    );
}

/// In INC the operand is a step from where the axis stands; a move that
/// gets there is reached.
#[tokio::test(start_paused = true)]
async fn an_incremental_move_targets_a_step_from_the_position_and_is_reached() {
    let session = session("cmd4cr", 9600).await;
    session.start_polling(PollCadence::default());
    // A step needs the position it starts from.
    wait_for(&session, |axes| axes[0].position == Some(0)).await;
    run(&session, "INC").await;
    run(&session, "X700").await;
    assert_eq!(session.status().borrow()[0].target, Some(700));
    wait_for(&session, |axes| axes[0].motion() == AxisMotion::AtTarget).await;
    run(&session, "X-200").await;
    assert_eq!(session.status().borrow()[0].target, Some(500));
    let axes = wait_for(&session, |axes| {
        axes[0].position == Some(500) && axes[0].motion() != AxisMotion::Moving
    })
    .await;
    assert_eq!(axes[0].motion(), AxisMotion::AtTarget, "{:?}", axes[0]);
}

/// Without the mode read or set, `X…` gives no target: the axis that
/// stands again has "stopped", never "reached".
#[tokio::test(start_paused = true)]
async fn without_the_move_mode_a_move_has_no_target_and_ends_stopped() {
    let session = session("cmd4cr", 9600).await;
    run(&session, "X300").await;
    assert_eq!(session.status().borrow()[0].target, None);
    let mut reads = 0;
    loop {
        run(&session, "MSTX").await;
        if session.status().borrow()[0].motion() != AxisMotion::Moving {
            break;
        }
        reads += 1;
        assert!(reads < 10_000, "X never stopped");
    }
    run(&session, "PX").await;
    let x = session.status().borrow()[0].clone();
    assert_eq!(x.position, Some(300), "{x:?}");
    assert_eq!(x.target, None);
    assert_eq!(x.motion(), AxisMotion::Stopped);
}
