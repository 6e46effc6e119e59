//! The device task on scripted links: the test plays a TMCL module through
//! two channels, on tokio's paused clock, so every timeout and wait below
//! is virtual and exact.

mod device_support;

use std::sync::Arc;
use std::time::Duration;

use tokio::time::{Instant, sleep, sleep_until, timeout_at};

use axterm::device::{
    DeviceError, DeviceEvent, DeviceOptions, Direction, Expect, LinkState, PollItem, PollOwner,
    PollPlan, Priority, Retry, TrafficKind, Transaction, UNTIMED_LINK_TIMEOUT, default_timeout,
    spawn,
};
use axterm::link::{LinkError, LinkWriter};
use axterm::protocol::tmcl::{Status, TmclWire};
use axterm::protocol::wire::WireFormat;
use device_support::*;

fn nine_bytes() -> Duration {
    default_timeout(at_9600(), 9)
}

fn silence() -> Duration {
    TmclWire::default().silence(at_9600())
}

/// Waited `expected` on the virtual clock. tokio's timer wheel counts whole
/// milliseconds: a deadline fires on the first tick at or after it.
#[track_caller]
fn assert_waited(elapsed: Duration, expected: Duration) {
    assert!(
        elapsed >= expected && elapsed < expected + Duration::from_millis(1),
        "waited {elapsed:?}, expected {expected:?}"
    );
}

#[tokio::test(start_paused = true)]
async fn the_reply_with_our_address_and_echo_is_the_answer_others_are_stale() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let mut traffic = device.traffic();
    let gap = request(GAP, 1, 0, 0);
    let pending = device.submit(Priority::User, transaction(&gap, Retry::Never));
    assert_eq!(script.request().await, gap.to_bytes().to_vec());
    let other_module = axterm::protocol::tmcl::Request { address: 3, ..gap };
    script.send(&ok(&other_module, 1));
    script.send(&ok(&request(SAP, 1, 0, 0), 2));
    script.send(&ok(&gap, 3));
    let answer = pending.await.expect("answered");
    assert_eq!(value_of(&answer), 3);
    assert_eq!(answer.attempts, 1);
    let records: Vec<_> = drain(&mut traffic)
        .into_iter()
        .map(|r| (r.direction, r.kind, r.priority))
        .collect();
    assert_eq!(
        records,
        [
            (Direction::Sent, TrafficKind::Request, Some(Priority::User)),
            (Direction::Received, TrafficKind::Stale, None),
            (Direction::Received, TrafficKind::Stale, None),
            (
                Direction::Received,
                TrafficKind::Answer,
                Some(Priority::User)
            ),
        ]
    );
    let counters = *device.counters().borrow();
    assert_eq!((counters.stale_frames, counters.transactions), (2, 1));
}

#[tokio::test(start_paused = true)]
async fn an_error_status_is_an_answer_too() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let sap = request(SAP, 6, 0, 300);
    let pending = device.submit(Priority::User, transaction(&sap, Retry::Never));
    script.request().await;
    script.send(&reply(&sap, Status::INVALID_VALUE, 0));
    let answer = pending.await.expect("answered");
    assert_eq!(answer.frames, [reply(&sap, Status::INVALID_VALUE, 0)]);
}

/// The sentinel the device task sends to module 1 after a GGP or GAP went
/// unanswered: 136 type 1 (firmware version as a number).
fn sentinel() -> axterm::protocol::tmcl::Request {
    request(136, 1, 0, 0)
}

#[tokio::test(start_paused = true)]
async fn a_late_reply_after_a_timeout_is_stale_never_the_next_answer() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let mut traffic = device.traffic();
    let (first, second) = (ggp(1), ggp(2));
    let result = device
        .transact(Priority::User, transaction(&first, Retry::Never))
        .await;
    assert_eq!(
        result,
        Err(DeviceError::Timeout {
            timeout: nine_bytes(),
            attempts: 1
        })
    );
    let timed_out = Instant::now();
    assert_eq!(script.request().await, first.to_bytes().to_vec());

    // Both GGP replies look alike (command 10, module 1): a sentinel of
    // another command goes first, after the line has been quiet.
    let next = device.submit(Priority::User, transaction(&second, Retry::Never));
    assert_eq!(script.request().await, sentinel().to_bytes().to_vec());
    assert_eq!(timed_out.elapsed(), silence());
    script.send(&ok(&first, 111));
    sleep(Duration::from_millis(5)).await;
    assert!(script.nothing_written(), "the sentinel is not answered yet");
    script.send(&ok(&sentinel(), 1012));
    assert_eq!(script.request().await, second.to_bytes().to_vec());
    script.send(&ok(&second, 222));
    assert_eq!(value_of(&next.await.expect("answered")), 222);

    let records: Vec<_> = drain(&mut traffic)
        .into_iter()
        .map(|r| (r.direction, r.kind, r.bytes))
        .collect();
    assert_eq!(
        records,
        [
            (
                Direction::Sent,
                TrafficKind::Request,
                first.to_bytes().to_vec()
            ),
            (
                Direction::Sent,
                TrafficKind::Request,
                sentinel().to_bytes().to_vec()
            ),
            (Direction::Received, TrafficKind::Stale, ok(&first, 111)),
            (
                Direction::Received,
                TrafficKind::Answer,
                ok(&sentinel(), 1012)
            ),
            (
                Direction::Sent,
                TrafficKind::Request,
                second.to_bytes().to_vec()
            ),
            (Direction::Received, TrafficKind::Answer, ok(&second, 222)),
        ]
    );
    let counters = *device.counters().borrow();
    assert_eq!((counters.timeouts, counters.sentinels), (1, 1));
}

#[tokio::test(start_paused = true)]
async fn a_reply_however_late_is_never_the_next_answer() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let (first, second, third) = (ggp(1), ggp(2), ggp(3));
    let failed = device.submit(Priority::User, transaction(&first, Retry::Never));
    // A patient read, so that the late replies come while it waits.
    let patient = Transaction {
        timeout: Some(nine_bytes() * 4),
        ..transaction(&second, Retry::Never)
    };
    let next = device.submit(Priority::User, patient);
    script.request().await;
    let first_sent = Instant::now();
    assert!(failed.await.is_err());
    // The module is busy: the sentinel waits behind the late reply and
    // times out too; the next request goes after it all the same.
    assert_eq!(script.request().await, sentinel().to_bytes().to_vec());
    assert_eq!(script.request().await, second.to_bytes().to_vec());
    // Five timeouts after the first was sent, the replies come, in order.
    sleep_until(first_sent + nine_bytes() * 5).await;
    script.send(&ok(&first, 111));
    script.send(&ok(&sentinel(), 1012));
    script.send(&ok(&second, 222));
    assert_eq!(value_of(&next.await.expect("answered")), 222);
    assert_eq!(device.counters().borrow().stale_frames, 2);

    // The same when the first reply never comes: the next GGP's answer
    // could be it, so it is not taken for the next one's.
    let lost = device.submit(Priority::User, transaction(&third, Retry::Never));
    script.request().await;
    assert!(lost.await.is_err());
    let after = device.submit(Priority::User, transaction(&second, Retry::Never));
    assert_eq!(script.request().await, sentinel().to_bytes().to_vec());
    assert_eq!(script.request().await, second.to_bytes().to_vec());
    script.send(&ok(&second, 222));
    assert_eq!(
        after.await,
        Err(DeviceError::Ambiguous {
            attempts: 1,
            answer: ok(&second, 222)
        })
    );
}

#[tokio::test(start_paused = true)]
async fn after_a_retried_answer_the_other_attempts_reply_is_stale() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let (read, next) = (ggp(1), ggp(2));
    let pending = device.submit(Priority::User, transaction(&read, Retry::Read(1)));
    let pending_next = device.submit(Priority::User, transaction(&next, Retry::Never));
    script.request().await;
    assert_eq!(
        script.request().await,
        read.to_bytes().to_vec(),
        "the retry, without a sentinel: either answer is this read's"
    );
    // One of the two replies comes (whose, nobody can tell) ...
    sleep(Duration::from_millis(10)).await;
    script.send(&ok(&read, 111));
    let answer = pending.await.expect("answered");
    assert_eq!((value_of(&answer), answer.attempts), (111, 2));
    // ... so the other may still come: a sentinel goes before the next GGP.
    assert_eq!(script.request().await, sentinel().to_bytes().to_vec());
    script.send(&ok(&read, 111));
    script.send(&ok(&sentinel(), 1012));
    assert_eq!(script.request().await, next.to_bytes().to_vec());
    script.send(&ok(&next, 222));
    assert_eq!(value_of(&pending_next.await.expect("answered")), 222);
    assert_eq!(device.counters().borrow().stale_frames, 1);
}

#[tokio::test(start_paused = true)]
async fn a_request_whose_answer_looks_different_goes_at_once() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let lost = device.submit(Priority::User, transaction(&ggp(1), Retry::Never));
    script.request().await;
    assert!(lost.await.is_err());
    let timed_out = Instant::now();
    // SAP's reply echoes command 5, never GGP's 10 (§3.2).
    let sap = request(SAP, 4, 0, 100);
    let pending = device.submit(Priority::User, transaction(&sap, Retry::Never));
    assert_eq!(script.request().await, sap.to_bytes().to_vec());
    assert_eq!(timed_out.elapsed(), silence());
    script.send(&ok(&ggp(1), 111));
    script.send(&ok(&sap, 0));
    assert!(pending.await.is_ok());
    let counters = *device.counters().borrow();
    assert_eq!((counters.sentinels, counters.stale_frames), (0, 1));
}

#[tokio::test(start_paused = true)]
async fn a_garbled_answer_is_reported_with_its_bytes() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let sap = request(SAP, 4, 0, 1000);
    let pending = device.submit(Priority::User, transaction(&sap, Retry::Never));
    script.request().await;
    let mut mangled = ok(&sap, 1000);
    mangled[4] ^= 0x10;
    script.send(&mangled);
    let error = pending.await.unwrap_err();
    assert_eq!(
        error,
        DeviceError::Garbled {
            timeout: nine_bytes(),
            attempts: 1,
            received: mangled.clone(),
        }
    );
    assert_eq!(
        error.to_string(),
        format!(
            "no readable reply within {} ms, only 02 01 64 05 10 00 03 E8 57 (after 1 attempt)",
            nine_bytes().as_millis()
        )
    );
}

#[tokio::test(start_paused = true)]
async fn the_second_reply_of_138_is_an_event_never_an_answer() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let mut events = device.events();
    let mut traffic = device.traffic();
    let arm = request(TARGET_EVENT, 0, 0, 1);
    let pending = device.submit(Priority::User, transaction(&arm, Retry::Never));
    script.request().await;
    // The status-128 reply of an earlier move arrives first: news, and not
    // the answer to this 138 although it echoes 138.
    script.send(&target_reached());
    script.send(&ok(&arm, 1));
    let answer = pending.await.expect("answered");
    assert_eq!(answer.frames, [ok(&arm, 1)]);
    let event = events.recv().await.expect("an event");
    assert_eq!(
        event,
        DeviceEvent::Unsolicited {
            frame: target_reached(),
            description: "target position reached (138) on module 1, motor mask 1".into(),
        }
    );

    // While nothing is in flight.
    script.send(&target_reached());
    assert!(matches!(
        events.recv().await,
        Ok(DeviceEvent::Unsolicited { .. })
    ));
    // While a GAP is in flight, just before its reply.
    let gap = request(GAP, 1, 0, 0);
    let pending = device.submit(Priority::User, transaction(&gap, Retry::Never));
    script.request().await;
    let mut both = target_reached();
    both.extend(ok(&gap, 2000));
    script.send(&both);
    assert_eq!(value_of(&pending.await.expect("answered")), 2000);
    assert!(matches!(
        events.recv().await,
        Ok(DeviceEvent::Unsolicited { .. })
    ));
    let unsolicited = drain(&mut traffic)
        .iter()
        .filter(|r| r.kind == TrafficKind::Unsolicited)
        .count();
    assert_eq!(unsolicited, 3);
    let counters = *device.counters().borrow();
    assert_eq!((counters.unsolicited, counters.stale_frames), (3, 0));
}

fn plan(
    polls: &[axterm::protocol::tmcl::Request],
    every: Duration,
    sink: &RecordingSink,
) -> PollPlan {
    PollPlan {
        items: polls
            .iter()
            .map(|r| PollItem {
                transaction: transaction(r, Retry::Read(1)),
                every,
                urgent: false,
            })
            .collect(),
        sink: Box::new(sink.clone()),
    }
}

#[tokio::test(start_paused = true)]
async fn a_user_command_waits_behind_at_most_one_poll() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let sink = RecordingSink::default();
    let polls: Vec<_> = (0..3).map(ggp).collect();
    device.set_poll_plan(Some(plan(&polls, Duration::ZERO, &sink)));
    assert_eq!(script.request().await, polls[0].to_bytes().to_vec());

    let (user, transfer) = (request(GAP, 1, 0, 0), request(SAP, 4, 0, 10));
    let pending_transfer = device.submit(Priority::Transfer, transaction(&transfer, Retry::Never));
    let pending_user = device.submit(Priority::User, transaction(&user, Retry::Never));
    script.send(&ok(&polls[0], 0));
    assert_eq!(script.request().await, user.to_bytes().to_vec());
    script.send(&ok(&user, 5));
    assert_eq!(script.request().await, transfer.to_bytes().to_vec());
    script.send(&ok(&transfer, 10));
    assert_eq!(value_of(&pending_user.await.expect("user")), 5);
    assert!(pending_transfer.await.is_ok());
    // Polling goes on where it left off.
    assert_eq!(script.request().await, polls[1].to_bytes().to_vec());
    assert_eq!(sink.results(), [(0, Ok(vec![ok(&polls[0], 0)]))]);
}

#[tokio::test(start_paused = true)]
async fn an_emergency_stop_waits_only_for_the_request_on_the_wire() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let on_wire = request(SAP, 4, 0, 1000);
    let first = device.submit(Priority::User, transaction(&on_wire, Retry::Never));
    assert_eq!(script.request().await, on_wire.to_bytes().to_vec());

    let (user, transfer, stop) = (
        request(MVP, 0, 0, 5000),
        request(SAP, 5, 0, 100),
        request(MST, 0, 0, 0),
    );
    let pending_transfer = device.submit(Priority::Transfer, transaction(&transfer, Retry::Never));
    let pending_user = device.submit(Priority::User, transaction(&user, Retry::Never));
    let pending_stop = device.submit(Priority::EmergencyStop, transaction(&stop, Retry::Never));
    sleep(nine_bytes() / 2).await;
    assert!(
        script.nothing_written(),
        "the transaction on the wire is not interrupted"
    );
    script.send(&ok(&on_wire, 0));
    for expected in [&stop, &user, &transfer] {
        assert_eq!(script.request().await, expected.to_bytes().to_vec());
        script.send(&ok(expected, 0));
    }
    for pending in [first, pending_stop, pending_user, pending_transfer] {
        assert!(pending.await.is_ok());
    }
}

#[tokio::test(start_paused = true)]
async fn after_a_timeout_an_emergency_stop_waits_only_for_silence() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let mut traffic = device.traffic();
    let lost = request(SAP, 4, 0, 1000);
    let (user, stop) = (request(SAP, 5, 0, 10), request(MST, 0, 0, 0));
    let failed = device.submit(Priority::User, transaction(&lost, Retry::Never));
    script.request().await;
    let pending_user = device.submit(Priority::User, transaction(&user, Retry::Never));
    let pending_stop = device.submit(Priority::EmergencyStop, transaction(&stop, Retry::Never));
    assert!(failed.await.is_err());
    let timed_out = Instant::now();
    // MST's reply cannot be SAP's: nothing to settle.
    assert_eq!(script.request().await, stop.to_bytes().to_vec());
    assert_eq!(timed_out.elapsed(), silence());
    script.send(&ok(&stop, 0));
    assert!(pending_stop.await.is_ok());
    // The stop does not settle the line for what follows: another SAP
    // waits for a sentinel.
    assert_eq!(script.request().await, sentinel().to_bytes().to_vec());
    script.send(&ok(&sentinel(), 1012));
    assert_eq!(script.request().await, user.to_bytes().to_vec());
    script.send(&ok(&user, 0));
    assert!(pending_user.await.is_ok());
    let priorities: Vec<_> = drain(&mut traffic)
        .into_iter()
        .filter(|r| r.direction == Direction::Sent)
        .map(|r| r.priority)
        .collect();
    assert_eq!(
        priorities,
        [
            Some(Priority::User),
            Some(Priority::EmergencyStop),
            Some(Priority::User),
            Some(Priority::User)
        ]
    );
}

#[tokio::test(start_paused = true)]
async fn an_emergency_stop_after_a_lost_stop_settles_with_a_sentinel_first() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let stop = request(MST, 0, 0, 0);
    let failed = device.submit(Priority::EmergencyStop, transaction(&stop, Retry::Never));
    script.request().await;
    assert!(failed.await.is_err());
    let timed_out = Instant::now();
    let again = device.submit(Priority::EmergencyStop, transaction(&stop, Retry::Never));
    assert_eq!(script.request().await, sentinel().to_bytes().to_vec());
    assert_eq!(timed_out.elapsed(), silence());
    // The first stop's late answer, then the sentinel's: the second stop's
    // answer will be its own.
    script.send(&ok(&stop, 0));
    script.send(&ok(&sentinel(), 1012));
    assert_eq!(script.request().await, stop.to_bytes().to_vec());
    script.send(&ok(&stop, 0));
    assert!(again.await.is_ok());
}

#[tokio::test(start_paused = true)]
async fn a_read_is_sent_again_after_a_timeout() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let gap = request(GAP, 1, 0, 0);
    let pending = device.submit(Priority::User, transaction(&gap, Retry::Read(2)));
    let bytes = gap.to_bytes().to_vec();
    assert_eq!(script.request().await, bytes);
    let sent = Instant::now();
    assert_eq!(script.request().await, bytes);
    assert_waited(sent.elapsed(), nine_bytes() + silence());
    script.send(&ok(&gap, 7));
    let answer = pending.await.expect("answered");
    assert_eq!((value_of(&answer), answer.attempts), (7, 2));
    let counters = *device.counters().borrow();
    assert_eq!(
        (counters.timeouts, counters.retries, counters.transactions),
        (1, 1, 1)
    );
}

#[tokio::test(start_paused = true)]
async fn a_read_gives_up_after_its_retries() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let gap = request(GAP, 1, 0, 0);
    let result = device
        .transact(Priority::User, transaction(&gap, Retry::Read(2)))
        .await;
    assert_eq!(
        result,
        Err(DeviceError::Timeout {
            timeout: nine_bytes(),
            attempts: 3
        })
    );
    for _ in 0..3 {
        assert_eq!(script.request().await, gap.to_bytes().to_vec());
    }
    assert!(script.nothing_written());
    let counters = *device.counters().borrow();
    assert_eq!((counters.timeouts, counters.retries), (3, 2));
}

/// Noise that never stops must not hold a line back past its deadline
/// (fault soak: a device writing random bytes kept `1TP` waiting for 40 s
/// and more): a read that could not go for it fails once its timeout has
/// passed for each attempt it may have, not sent, with the noise shown.
#[tokio::test(start_paused = true)]
async fn nonstop_noise_fails_an_unsent_read_at_its_deadline() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let noise = nonstop_noise(&script);
    sleep(Duration::from_millis(3)).await;
    let gap = request(GAP, 1, 0, 0);
    let asked = Instant::now();
    let pending = device.transact(Priority::User, transaction(&gap, Retry::Read(2)));
    let result = timeout_at(asked + nine_bytes() * 4, pending)
        .await
        .expect("ended by the line's deadline");
    assert_waited(asked.elapsed(), nine_bytes() * 3);
    let Err(DeviceError::NeverQuiet {
        waited,
        heard,
        first,
    }) = result
    else {
        panic!("expected not sent for the noise, got {result:?}");
    };
    assert_waited(waited, nine_bytes() * 3);
    assert!(heard > 25, "{heard} bytes heard");
    assert_eq!(first, [0xFF; 32]);
    assert!(script.nothing_written());
    noise.abort();
}

/// Noise that starts after a read was sent: its attempt times out at its
/// own deadline, and the retry, which waits for a quiet line, is given up
/// at the line's deadline with the noise of the attempt shown.
#[tokio::test(start_paused = true)]
async fn nonstop_noise_after_a_read_went_fails_it_at_the_lines_deadline() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let gap = request(GAP, 1, 0, 0);
    let pending = device.submit(Priority::User, transaction(&gap, Retry::Read(2)));
    assert_eq!(script.request().await, gap.to_bytes().to_vec());
    let sent = Instant::now();
    let noise = nonstop_noise(&script);
    let result = timeout_at(sent + nine_bytes() * 4, pending)
        .await
        .expect("ended by the line's deadline");
    assert_waited(sent.elapsed(), nine_bytes() * 3);
    let Err(DeviceError::Garbled {
        attempts, received, ..
    }) = result
    else {
        panic!("expected a garbled answer, got {result:?}");
    };
    assert_eq!(attempts, 1);
    assert!(received.iter().all(|b| *b == 0xFF) && !received.is_empty());
    assert!(script.nothing_written(), "no retry went into the noise");
    noise.abort();
}

/// An emergency stop is not given up for noise: past its deadline it goes
/// all the same.
#[tokio::test(start_paused = true)]
async fn an_emergency_stop_goes_through_nonstop_noise_at_its_deadline() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let noise = nonstop_noise(&script);
    sleep(Duration::from_millis(3)).await;
    let mst = request(MST, 0, 0, 0);
    let asked = Instant::now();
    let pending = device.submit(Priority::EmergencyStop, transaction(&mst, Retry::Never));
    let written = timeout_at(asked + nine_bytes() * 2, script.request())
        .await
        .expect("sent by its deadline");
    assert_eq!(written, mst.to_bytes().to_vec());
    assert_waited(asked.elapsed(), nine_bytes());
    noise.abort();
    script.send(&ok(&mst, 0));
    pending.await.expect("answered");
}

#[tokio::test(start_paused = true)]
async fn a_write_is_never_sent_twice() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let sap = request(SAP, 4, 0, 1000);
    let pending = device.submit(Priority::User, transaction(&sap, Retry::Never));
    script.request().await;
    // A mangled answer: a bad answer for a read, but a write waits on
    // until its timeout and is not sent again.
    let mut mangled = ok(&sap, 1000);
    mangled[5] ^= 0x40;
    script.send(&mangled);
    assert_eq!(
        pending.await,
        Err(DeviceError::Garbled {
            timeout: nine_bytes(),
            attempts: 1,
            received: mangled,
        })
    );
    sleep(Duration::from_secs(10)).await;
    assert!(script.nothing_written());
    let counters = *device.counters().borrow();
    assert_eq!((counters.retries, counters.garbage_bytes), (0, 9));
}

#[tokio::test(start_paused = true)]
async fn timeouts_come_from_the_transaction_the_options_or_the_link() {
    let options = DeviceOptions {
        timeout: Some(Duration::from_secs(1)),
        ..DeviceOptions::default()
    };
    let (device, _script) = tmcl_device(options);
    let gap = request(GAP, 1, 0, 0);
    let started = Instant::now();
    let result = device
        .transact(Priority::User, transaction(&gap, Retry::Never))
        .await;
    let one_second = Duration::from_secs(1);
    assert_eq!(
        result,
        Err(DeviceError::Timeout {
            timeout: one_second,
            attempts: 1
        })
    );
    assert_eq!(started.elapsed(), one_second);

    let short = Transaction {
        timeout: Some(Duration::from_millis(50)),
        ..transaction(&gap, Retry::Never)
    };
    let result = device.transact(Priority::User, short).await;
    assert!(
        matches!(result, Err(DeviceError::Timeout { timeout, .. }) if timeout == Duration::from_millis(50))
    );

    let (link, _script) = scripted("tcp", None);
    let untimed = spawn(
        link,
        axterm::device::never_reopen("tcp", "scripted"),
        Arc::new(TmclWire::default()),
        DeviceOptions::default(),
    );
    let result = untimed
        .transact(Priority::User, transaction(&gap, Retry::Never))
        .await;
    assert!(
        matches!(result, Err(DeviceError::Timeout { timeout, .. }) if timeout == UNTIMED_LINK_TIMEOUT)
    );
}

#[tokio::test(start_paused = true)]
async fn garbage_before_a_reply_is_skipped() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let mut traffic = device.traffic();
    let gap = request(GAP, 1, 0, 0);
    let pending = device.submit(Priority::User, transaction(&gap, Retry::Never));
    script.request().await;
    let mut noisy = vec![0xAA, 0x55, 0x01];
    noisy.extend(ok(&gap, 42));
    script.send(&noisy);
    assert_eq!(value_of(&pending.await.expect("answered")), 42);
    let garbage: Vec<_> = drain(&mut traffic)
        .into_iter()
        .filter(|r| r.kind == TrafficKind::Garbage)
        .map(|r| r.bytes)
        .collect();
    assert_eq!(garbage, [vec![0xAA, 0x55, 0x01]]);
    assert_eq!(device.counters().borrow().garbage_bytes, 3);
}

#[tokio::test(start_paused = true)]
async fn without_sliding_the_framer_resyncs_on_silence_and_the_read_is_retried() {
    let (device, mut script) = device_with(
        Arc::new(TmclWire { slide: false }),
        DeviceOptions::default(),
    );
    let mut traffic = device.traffic();
    let gap = request(GAP, 1, 0, 0);
    let pending = device.submit(Priority::User, transaction(&gap, Retry::Read(1)));
    script.request().await;
    let mut noisy = vec![0xAA, 0x55];
    noisy.extend(ok(&gap, 42));
    script.send(&noisy);
    let received = Instant::now();
    // Out of step: nine bytes that are no answer, two held back until the
    // line has been quiet, then the read goes again.
    assert_eq!(script.request().await, gap.to_bytes().to_vec());
    assert_eq!(received.elapsed(), silence());
    script.send(&ok(&gap, 42));
    let answer = pending.await.expect("answered");
    assert_eq!((value_of(&answer), answer.attempts), (42, 2));
    let kinds: Vec<_> = drain(&mut traffic).into_iter().map(|r| r.kind).collect();
    assert_eq!(
        kinds,
        [
            TrafficKind::Request,
            TrafficKind::Stale,
            TrafficKind::Garbage,
            TrafficKind::Request,
            TrafficKind::Answer,
        ]
    );
    let counters = *device.counters().borrow();
    assert_eq!((counters.timeouts, counters.retries), (0, 1));
}

#[tokio::test(start_paused = true)]
async fn a_partial_frame_is_dropped_once_the_line_is_quiet() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let mut traffic = device.traffic();
    script.send(&[0x02, 0x01, 0x64]);
    let noise = Instant::now();
    let gap = request(GAP, 1, 0, 0);
    let pending = device.submit(Priority::User, transaction(&gap, Retry::Never));
    assert_eq!(script.request().await, gap.to_bytes().to_vec());
    assert_eq!(
        noise.elapsed(),
        silence(),
        "the request waits for the line to be quiet"
    );
    script.send(&ok(&gap, 1));
    assert_eq!(value_of(&pending.await.expect("answered")), 1);
    let records = drain(&mut traffic);
    assert_eq!(records[0].kind, TrafficKind::Garbage);
    assert_eq!(records[0].bytes, [0x02, 0x01, 0x64]);
    assert_eq!(records[1].kind, TrafficKind::Request);
}

#[tokio::test(start_paused = true)]
async fn a_command_without_reply_is_done_once_written() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let setting = Transaction {
        bytes: b"anything".to_vec(),
        expect: Expect::Nothing,
        retry: Retry::Never,
        timeout: None,
        hold: None,
        cut_short: None,
    };
    let started = Instant::now();
    let answer = device
        .transact(Priority::User, setting)
        .await
        .expect("written");
    assert_eq!(started.elapsed(), Duration::ZERO);
    assert!(answer.frames.is_empty());
    assert_eq!(script.request().await, b"anything".to_vec());
}

#[tokio::test(start_paused = true)]
async fn polls_go_most_overdue_first_no_more_often_than_asked_and_all_reach_the_sink() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let sink = RecordingSink::default();
    let (fast, slow) = (ggp(0), ggp(1));
    device.set_poll_plan(Some(PollPlan {
        items: vec![
            PollItem {
                transaction: transaction(&fast, Retry::Read(1)),
                every: Duration::from_millis(100),
                urgent: false,
            },
            PollItem {
                transaction: transaction(&slow, Retry::Read(1)),
                every: Duration::from_millis(300),
                urgent: false,
            },
        ],
        sink: Box::new(sink.clone()),
    }));
    let start = Instant::now();
    let end = start + Duration::from_secs(1);
    let mut sent: Vec<(usize, Duration)> = Vec::new();
    let mut value = 0;
    while let Ok(bytes) = timeout_at(end, script.request()).await {
        let index = usize::from(bytes[2]);
        sent.push((index, start.elapsed()));
        value += 1;
        script.send(&ok(&ggp(bytes[2]), value));
    }
    device.set_poll_plan(None);
    for item in [0, 1] {
        let times: Vec<_> = sent
            .iter()
            .filter(|(i, _)| *i == item)
            .map(|(_, t)| *t)
            .collect();
        let every = [100, 300][item];
        for pair in times.windows(2) {
            assert!(pair[1] - pair[0] >= Duration::from_millis(every));
        }
        assert_eq!(times.len(), [10, 4][item], "item {item} at {times:?}");
    }
    // Every answer reached the sink, in order.
    let results = sink.results();
    assert_eq!(results.len(), sent.len());
    for (n, ((index, result), (sent_index, _))) in results.iter().zip(&sent).enumerate() {
        assert_eq!(index, sent_index);
        let frames = result.as_ref().expect("answered");
        assert_eq!(frames, &vec![ok(&ggp(*index as u8), n as i32 + 1)]);
    }
}

#[tokio::test(start_paused = true)]
async fn polls_take_turns_as_fast_as_the_link_allows() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let sink = RecordingSink::default();
    let polls: Vec<_> = (0..3).map(ggp).collect();
    device.set_poll_plan(Some(plan(&polls, Duration::ZERO, &sink)));
    let mut order = Vec::new();
    for _ in 0..7 {
        let bytes = script.request().await;
        order.push(bytes[2]);
        script.send(&ok(&ggp(bytes[2]), 0));
    }
    assert_eq!(order, [0, 1, 2, 0, 1, 2, 0]);
}

#[tokio::test(start_paused = true)]
async fn a_failed_poll_is_retried_then_reported_to_the_sink() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let sink = RecordingSink::default();
    let poll = ggp(0);
    device.set_poll_plan(Some(plan(
        std::slice::from_ref(&poll),
        Duration::from_secs(1),
        &sink,
    )));
    // Neither attempt answered.
    script.request().await;
    script.request().await;
    // Replacing the plan waits for the failed poll's result.
    device.set_poll_plan(None);
    sleep(Duration::from_secs(5)).await;
    assert!(script.nothing_written());
    assert_eq!(
        sink.results(),
        [(
            0,
            Err(DeviceError::Timeout {
                timeout: nine_bytes(),
                attempts: 2
            })
        )]
    );
    let counters = *device.counters().borrow();
    assert_eq!((counters.polls, counters.transactions), (1, 1));
}

#[tokio::test(start_paused = true)]
async fn losing_the_link_fails_everything_and_it_is_reopened_with_backoff() {
    let spares = Spares::default();
    let (link, mut script) = scripted("first", at_9600());
    let (second, mut script2) = scripted("second", at_9600());
    // Its advice is for a first opening: the state keeps one line.
    spares.push(Err(LinkError {
        advice: vec!["plug it back in".into()],
        ..LinkError::new("second", "still unplugged")
    }));
    spares.push(Ok(second));
    let options = DeviceOptions {
        reconnect_initial: Duration::from_millis(100),
        reconnect_max: Duration::from_secs(1),
        ..DeviceOptions::default()
    };
    let device = spawn(
        link,
        spares.reopen(),
        Arc::new(TmclWire::default()),
        options,
    );
    let mut events = device.events();
    let sap = request(SAP, 4, 0, 1000);
    let in_flight = device.submit(Priority::User, transaction(&sap, Retry::Never));
    let queued = device.submit(Priority::User, transaction(&ggp(0), Retry::Read(3)));
    script.request().await;
    script.lose("cable pulled");
    assert_eq!(
        in_flight.await,
        Err(DeviceError::LinkLost("first: cable pulled".into()))
    );
    assert_eq!(
        queued.await,
        Err(DeviceError::Disconnected("first: cable pulled".into()))
    );
    let lost = Instant::now();
    assert_eq!(
        *device.state().borrow(),
        LinkState::Disconnected {
            reason: "first: cable pulled".into(),
            attempts: 0,
            retry_in: Duration::from_millis(100),
        }
    );
    // Nothing is kept to be sent later.
    let result = device
        .transact(Priority::User, transaction(&ggp(0), Retry::Never))
        .await;
    assert!(matches!(result, Err(DeviceError::Disconnected(_))));
    assert_eq!(lost.elapsed(), Duration::ZERO, "fails at once");

    let sink = RecordingSink::default();
    let poll = ggp(5);
    device.set_poll_plan(Some(plan(
        std::slice::from_ref(&poll),
        Duration::ZERO,
        &sink,
    )));
    let mut state = device.state();
    state
        .wait_for(|s| matches!(s, LinkState::Connected { .. }))
        .await
        .expect("reconnected");
    assert_eq!(
        spares.attempts(),
        [
            lost + Duration::from_millis(100),
            lost + Duration::from_millis(300)
        ]
    );
    let mut changes = Vec::new();
    while let Ok(DeviceEvent::StateChanged(state)) = events.try_recv() {
        changes.push(state);
    }
    assert_eq!(
        changes,
        [
            LinkState::Disconnected {
                reason: "first: cable pulled".into(),
                attempts: 0,
                retry_in: Duration::from_millis(100),
            },
            LinkState::Disconnected {
                reason: "cannot open second: still unplugged".into(),
                attempts: 1,
                retry_in: Duration::from_millis(200),
            },
            LinkState::Connected {
                link: "second".into()
            },
        ]
    );
    // Polling resumes on the new link; the lost write was not sent again.
    assert_eq!(script2.request().await, poll.to_bytes().to_vec());
    script2.send(&ok(&poll, 9));
    device.set_poll_plan(None);
    let result = device
        .transact(Priority::User, transaction(&ggp(1), Retry::Never))
        .await;
    assert!(result.is_err(), "script2 does not answer");
    assert_eq!(sink.results(), [(0, Ok(vec![ok(&poll, 9)]))]);
    assert_eq!(device.counters().borrow().reconnects, 1);
}

#[tokio::test(start_paused = true)]
async fn backoff_doubles_up_to_its_limit() {
    let spares = Spares::default();
    let (link, script) = scripted("first", at_9600());
    let options = DeviceOptions {
        reconnect_initial: Duration::from_millis(100),
        reconnect_max: Duration::from_millis(350),
        ..DeviceOptions::default()
    };
    let device = spawn(
        link,
        spares.reopen(),
        Arc::new(TmclWire::default()),
        options,
    );
    let start = Instant::now();
    drop(script);
    sleep(Duration::from_millis(2000)).await;
    let waits: Vec<_> = spares.attempts().windows(2).map(|w| w[1] - w[0]).collect();
    let first = spares.attempts()[0] - start;
    assert_eq!(
        first,
        Duration::from_millis(100),
        "a closed channel is a loss"
    );
    assert_eq!(waits[..4], [200, 350, 350, 350].map(Duration::from_millis));
    assert!(matches!(
        *device.state().borrow(),
        LinkState::Disconnected { retry_in, .. } if retry_in == Duration::from_millis(350)
    ));
}

struct BrokenWriter;

impl LinkWriter for BrokenWriter {
    fn send(&mut self, _bytes: &[u8]) -> std::io::Result<()> {
        Err(std::io::Error::other("device unplugged"))
    }
}

#[tokio::test(start_paused = true)]
async fn a_failed_write_is_a_lost_link() {
    let (mut link, _script) = scripted("usb", at_9600());
    link.outgoing = Box::new(BrokenWriter);
    let device = spawn(
        link,
        axterm::device::never_reopen("usb", "gone"),
        Arc::new(TmclWire::default()),
        DeviceOptions::default(),
    );
    let result = device
        .transact(Priority::User, transaction(&ggp(0), Retry::Read(3)))
        .await;
    assert_eq!(
        result,
        Err(DeviceError::LinkLost(
            "usb: writing failed: device unplugged".into()
        ))
    );
    assert!(matches!(
        *device.state().borrow(),
        LinkState::Disconnected { .. }
    ));
}

#[tokio::test(start_paused = true)]
async fn shutdown_lets_the_request_on_the_wire_finish_and_fails_the_rest() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let sap = request(SAP, 4, 0, 1000);
    let on_wire = device.submit(Priority::User, transaction(&sap, Retry::Never));
    let queued = device.submit(Priority::User, transaction(&ggp(0), Retry::Never));
    script.request().await;
    let stopped = device.shutdown();
    script.send(&ok(&sap, 0));
    assert!(on_wire.await.is_ok());
    assert_eq!(queued.await, Err(DeviceError::Closed));
    stopped.await;
    assert_eq!(*device.state().borrow(), LinkState::Closed);
    let result = device
        .transact(Priority::User, transaction(&ggp(0), Retry::Never))
        .await;
    assert_eq!(result, Err(DeviceError::Closed));
    assert!(
        script.from_host.recv().await.is_none(),
        "the link is closed"
    );
}

#[tokio::test(start_paused = true)]
async fn dropping_every_handle_ends_the_task() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let mut state = device.state();
    drop(device);
    state
        .wait_for(|s| *s == LinkState::Closed)
        .await
        .expect("closed");
    assert!(script.from_host.recv().await.is_none());
}

#[tokio::test(start_paused = true)]
async fn traffic_records_carry_virtual_timestamps() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let mut traffic = device.traffic();
    let gap = request(GAP, 1, 0, 0);
    let pending = device.submit(Priority::Poll, transaction(&gap, Retry::Never));
    script.request().await;
    let sent = Instant::now();
    sleep(Duration::from_millis(25)).await;
    script.send(&ok(&gap, 0));
    let answer = pending.await.expect("answered");
    assert_eq!(answer.elapsed, Duration::from_millis(25));
    let records = drain(&mut traffic);
    assert_eq!(records.len(), 2);
    assert_eq!(records[0].at, sent.into_std());
    assert_eq!(records[1].at - records[0].at, Duration::from_millis(25));
    assert_eq!(records[1].priority, Some(Priority::Poll));
    assert_eq!(records[1].bytes, ok(&gap, 0));
}

#[tokio::test(start_paused = true)]
async fn an_answer_that_never_came_is_forgotten_after_the_horizon() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    let lost = device.submit(Priority::User, transaction(&ggp(1), Retry::Never));
    script.request().await;
    assert!(lost.await.is_err());
    // The sentinel gets no answer either, and the next GGP's answer could
    // be the first one's: not taken.
    let next = device.submit(Priority::User, transaction(&ggp(3), Retry::Never));
    assert_eq!(script.request().await, sentinel().to_bytes().to_vec());
    assert_eq!(script.request().await, ggp(3).to_bytes().to_vec());
    script.send(&ok(&ggp(3), 333));
    assert!(matches!(next.await, Err(DeviceError::Ambiguous { .. })));
    // Long after, nothing is looked for any more: a GGP goes at once and
    // its answer is its own.
    sleep(nine_bytes() * (axterm::device::LATE_ANSWER_TIMEOUTS + 1)).await;
    let later = device.submit(Priority::User, transaction(&ggp(2), Retry::Never));
    assert_eq!(script.request().await, ggp(2).to_bytes().to_vec());
    script.send(&ok(&ggp(2), 222));
    assert_eq!(value_of(&later.await.expect("answered")), 222);
}

#[tokio::test(start_paused = true)]
async fn modules_on_one_link_poll_by_plans_of_their_own_in_turn() {
    let (device, mut script) = tmcl_device(DeviceOptions::default());
    // Module A polls three items, module B one; both as often as the
    // link allows. Each gets every other poll: B's one item is not
    // crowded out by A's three.
    let (a_sink, b_sink) = (RecordingSink::default(), RecordingSink::default());
    let a_polls: Vec<_> = (0..3).map(ggp).collect();
    let b_polls = vec![ggp(9)];
    let (a, b) = (PollOwner::new(), PollOwner::new());
    device.set_poll_plan_of(a, Some(plan(&a_polls, Duration::ZERO, &a_sink)));
    device.set_poll_plan_of(b, Some(plan(&b_polls, Duration::ZERO, &b_sink)));
    let mut sent = Vec::new();
    for n in 0..6 {
        let bytes = script.request().await;
        let polled = a_polls
            .iter()
            .chain(&b_polls)
            .find(|p| p.to_bytes().to_vec() == bytes)
            .expect("one of the polls");
        sent.push(polled.kind);
        script.send(&ok(polled, n));
    }
    assert_eq!(sent, [0, 9, 1, 9, 2, 9]);

    // A user line goes ahead of both plans, behind at most the poll
    // already on its way.
    let user = request(GAP, 1, 0, 0);
    let pending = device.submit(Priority::User, transaction(&user, Retry::Never));
    let mut next = script.request().await;
    if let Some(polled) = a_polls
        .iter()
        .chain(&b_polls)
        .find(|p| p.to_bytes().to_vec() == next)
    {
        sent.push(polled.kind);
        script.send(&ok(polled, 6));
        next = script.request().await;
    }
    assert_eq!(next, user.to_bytes().to_vec());
    script.send(&ok(&user, 7));
    assert_eq!(value_of(&pending.await.expect("user")), 7);

    // Each result went to the sink of the plan that polled it.
    let indices = |sink: &RecordingSink| -> Vec<usize> {
        sink.results().iter().map(|(index, _)| *index).collect()
    };
    let of_b = sent.iter().filter(|&&kind| kind == 9).count();
    assert_eq!(indices(&b_sink), vec![0; of_b]);
    assert_eq!(&indices(&a_sink)[..3], [0, 1, 2]);
    assert_eq!(a_sink.results().len(), sent.len() - of_b);

    // B stops: only A polls from now on.
    device.set_poll_plan_of(b, None);
    let mut after = Vec::new();
    for n in 0..4 {
        let bytes = script.request().await;
        let polled = a_polls
            .iter()
            .chain(&b_polls)
            .find(|p| p.to_bytes().to_vec() == bytes)
            .expect("one of the polls");
        after.push(polled.kind);
        script.send(&ok(polled, 10 + n));
    }
    // At most the one poll of B already chosen before the plan went.
    assert!(after.iter().skip(1).all(|&kind| kind != 9), "{after:?}");
}
