//! Reads of a family whose answers carry no checksum (SIXpack 2, CMD-4CR,
//! MCCL: `FamilyConsole::replies_checked`) are called good only when two
//! answers in a row agree (issue 19: under corruption a SIXpack 2 position
//! read printed a wild value as ok). The test plays a CMD-4CR controller
//! on a scripted link, on tokio's paused clock.

mod device_support;

use axterm::device::DeviceOptions;
use axterm::protocol::FAMILIES;
use axterm::session::{READS_TO_AGREE, Session, SessionError, SessionOptions};
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

#[tokio::test(start_paused = true)]
async fn an_unchecked_read_is_good_only_when_two_answers_agree() {
    let family = cmd4cr();
    let (device, mut script) = device_with(family.console.wire(), DeviceOptions::default());
    let session = Session::new(device, family, &SessionOptions::default());
    let line = session.prepare("PX").expect("PX prepares");
    let bytes = line.bytes.clone();
    let pending = tokio::spawn(async move { session.execute_agreed(&line).await });
    // A damaged value, then two that agree.
    for answer in ["-2080262363\r", "112421\r", "112421\r"] {
        assert_eq!(script.request().await, bytes);
        script.send(answer.as_bytes());
    }
    let result = pending.await.expect("joined").expect("two reads agreed");
    assert_eq!(result.value.to_string(), "112421");
    assert!(script.nothing_written(), "no read after two agreed");
}

#[tokio::test(start_paused = true)]
async fn unchecked_reads_that_never_agree_are_unreadable() {
    let family = cmd4cr();
    let (device, mut script) = device_with(family.console.wire(), DeviceOptions::default());
    let session = Session::new(device, family, &SessionOptions::default());
    let line = session.prepare("PX").expect("PX prepares");
    let pending = tokio::spawn(async move { session.execute_agreed(&line).await });
    for n in 0..READS_TO_AGREE {
        script.request().await;
        script.send(format!("{n}\r").as_bytes());
    }
    let result = pending.await.expect("joined");
    let Err(SessionError::Reply { error, .. }) = &result else {
        panic!("expected an unreadable answer, got {result:?}");
    };
    let message = error.to_string();
    assert!(
        message.contains("no two in a row agree (0, 1, 2, 3)"),
        "{message}"
    );
    assert!(script.nothing_written());
}
