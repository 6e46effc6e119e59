//! Reads of a family whose answers carry no checksum (SIXpack 2, CMD-4CR,
//! MCCL: `FamilyConsole::replies_checked`) are called good only when two
//! answers in a row agree (issue 19: under corruption a SIXpack 2 position
//! read printed a wild value as ok). The test plays a CMD-4CR controller
//! on a scripted link, on tokio's paused clock.

mod device_support;

use axterm::device::DeviceOptions;
use axterm::families::FAMILIES;
use axterm::session::{LineResult, READS_TO_AGREE, Session, SessionError, SessionOptions};
use device_support::device_with;

fn cmd4cr() -> &'static axterm::protocol::Family {
    FAMILIES
        .iter()
        .find(|f| f.name == "cmd4cr")
        .expect("cmd4cr is registered")
}

#[test]
fn only_a_family_with_a_checksum_claims_checked_replies() {
    for family in FAMILIES {
        // TMCL §3.1.1 has a checksum; SIXpack 2, CMD-4CR (§3.2.2) and MCCL
        // (echo and prompt, nothing over the digits) have none.
        assert_eq!(
            family.console.replies_checked(),
            family.name == "tmcl",
            "{}",
            family.name
        );
    }
}

/// `:expect PX == 112421` on a CMD-4CR: a first answer that matches is
/// read again; the value is good only if the second answer is the same.
#[tokio::test(start_paused = true)]
async fn an_unchecked_read_is_good_only_when_a_second_answer_agrees() {
    let family = cmd4cr();
    let (device, mut script) = device_with(family.console.wire(), DeviceOptions::default());
    let session = Session::new(device, family, &SessionOptions::default());
    let line = session.prepare("PX").expect("PX prepares");
    let bytes = line.bytes.clone();
    let expect = |r: &LineResult| r.value.to_string() == "112421";

    // A damaged answer that happens to read as expected, then the truth.
    let judged = {
        let (session, line) = (session.clone(), line.clone());
        tokio::spawn(async move { session.execute_confirmed(&line, expect).await })
    };
    for answer in ["112421\r", "-2080262363\r"] {
        assert_eq!(script.request().await, bytes);
        script.send(answer.as_bytes());
    }
    let (last, good) = judged.await.expect("joined").expect("answered");
    assert!(!good, "one answer is not enough");
    assert_eq!(last.value.to_string(), "-2080262363");

    // Two that agree.
    let judged = {
        let (session, line) = (session.clone(), line.clone());
        tokio::spawn(async move { session.execute_confirmed(&line, expect).await })
    };
    for _ in 0..2 {
        assert_eq!(script.request().await, bytes);
        script.send(b"112421\r");
    }
    let (_, good) = judged.await.expect("joined").expect("answered");
    assert!(good);

    // A value that is not the one expected needs no second read.
    let judged = tokio::spawn(async move { session.execute_confirmed(&line, expect).await });
    assert_eq!(script.request().await, bytes);
    script.send(b"7\r");
    let (_, good) = judged.await.expect("joined").expect("answered");
    assert!(!good);
    assert!(script.nothing_written());
}

/// `axterm params` reads a CMD-4CR value until two answers in a row agree.
#[tokio::test(start_paused = true)]
async fn a_parameter_read_without_a_checksum_is_the_value_two_reads_agree_on() {
    let family = cmd4cr();
    let (device, mut script) = device_with(family.console.wire(), DeviceOptions::default());
    let session = Session::new(device, family, &SessionOptions::default());
    let line = session.prepare("PX").expect("PX prepares");
    let read = {
        let (session, line) = (session.clone(), line.clone());
        tokio::spawn(async move { session.read_agreed(&line).await })
    };
    for answer in ["-2080262363\r", "112421\r", "112421\r"] {
        script.request().await;
        script.send(answer.as_bytes());
    }
    let result = read.await.expect("joined").expect("two agreed");
    assert_eq!(result.value.to_string(), "112421");

    let read = tokio::spawn(async move { session.read_agreed(&line).await });
    for n in 0..READS_TO_AGREE {
        script.request().await;
        script.send(format!("{n}\r").as_bytes());
    }
    let result = read.await.expect("joined");
    let Err(SessionError::Reply { error, .. }) = &result else {
        panic!("expected an unreadable answer, got {result:?}");
    };
    assert!(
        error
            .to_string()
            .contains("no two in a row agree (0, 1, 2)"),
        "{error}"
    );
    assert!(script.nothing_written());
}

/// The console's parameter pane reads through its controller's
/// `read_agreed` (`Effect::ReadAgreed`): on a session, a damaged first
/// answer is not what the table shows.
#[tokio::test(start_paused = true)]
async fn the_console_reads_a_parameter_until_two_answers_agree() {
    use axterm::ui::app::Controller;
    use axterm::ui::live::SessionController;
    let family = cmd4cr();
    let (device, mut script) = device_with(family.console.wire(), DeviceOptions::default());
    let session = Session::new(device, family, &SessionOptions::default());
    let controller = SessionController::new(session, "script".into(), SessionOptions::default());
    let read = tokio::spawn(controller.read_agreed("PX".into()));
    for answer in ["-2080262363\r", "112421\r", "112421\r"] {
        script.request().await;
        script.send(answer.as_bytes());
    }
    let result = read.await.expect("joined").expect("two agreed");
    assert_eq!(result.value.to_string(), "112421");
    assert!(script.nothing_written());
}

/// The §6.2.2.3 reply to `$20` for motor 0: the command byte, the motor,
/// posact LSB first, the action, the stop flag (no address, no checksum).
fn posact_reply(position: i32, action: u8) -> Vec<u8> {
    let mut reply = vec![0x20, 0];
    reply.extend_from_slice(&position.to_le_bytes());
    reply.extend_from_slice(&[action, 0]);
    reply
}

/// Issue 19 point 15: a SIXpack 2 position that jumps further between two
/// reads than §6.3.1's step-frequency law allows at its fastest is a damaged reply, not a
/// value; the read after it is taken as it comes. A jump while a reference
/// search runs (which sets a new zero) is not judged.
#[tokio::test(start_paused = true)]
async fn a_sixpack2_position_faster_than_any_motor_goes_is_refused() {
    let family = FAMILIES
        .iter()
        .find(|f| f.name == "sixpack2")
        .expect("sixpack2 is registered");
    let (device, mut script) = device_with(family.console.wire(), DeviceOptions::default());
    let session = Session::new(device, family, &SessionOptions::default());
    let read = |session: &Session| {
        let session = session.clone();
        tokio::spawn(async move { session.execute_line("GetPositionAndActivity 0").await })
    };
    let mut answer = async |reply: Vec<u8>, session: &Session| {
        let pending = read(session);
        script.request().await;
        script.send(&reply);
        pending.await.expect("joined")
    };
    let first = answer(posact_reply(112_421, 0), &session).await;
    assert_eq!(
        first.expect("read").value.to_string(),
        "posact=112421 action=inactive stop=0"
    );
    let damaged = answer(posact_reply(-2_080_262_363, 0), &session).await;
    let Err(SessionError::Reply { error, .. }) = &damaged else {
        panic!("expected a damaged reply, got {damaged:?}");
    };
    assert!(
        error.to_string().contains("-2080262363 after 112421"),
        "{error}"
    );
    // Forgotten with it: the next reading is taken.
    let next = answer(posact_reply(112_421, 0), &session).await;
    assert!(next.is_ok(), "{next:?}");
    // A reference search (action 20) may set a new zero.
    let searching = answer(posact_reply(-5_000_000, 20), &session).await;
    assert!(searching.is_ok(), "{searching:?}");
    let zeroed = answer(posact_reply(0, 0), &session).await;
    assert!(zeroed.is_ok(), "{zeroed:?}");
}
