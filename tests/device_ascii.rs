//! The device task serves a line-oriented ASCII family through the same
//! interface as TMCL, unchanged: CMD-4CR's one reply line, and MCCL's echo,
//! reply lines and prompt.

mod device_support;

use std::sync::Arc;
use std::time::Duration;

use tokio::time::Instant;

use axterm::device::{
    DeviceError, DeviceHandle, DeviceOptions, Expect, Priority, Retry, TrafficKind, Transaction,
};
use axterm::protocol::ascii::{AsciiWire, EchoThenPrompt, MCCL_PROMPT, NextLine, line_bytes};
use axterm::protocol::wire::WireFormat;
use device_support::*;

fn cmd4cr_line(line: &str) -> Transaction {
    Transaction {
        bytes: line_bytes(line),
        expect: Expect::Reply(Arc::new(NextLine)),
        retry: Retry::Read(1),
        timeout: None,
        hold: None,
        cut_short: None,
    }
}

fn mccl_line(line: &str) -> Transaction {
    let bytes = line_bytes(line);
    Transaction {
        expect: Expect::Reply(Arc::new(EchoThenPrompt::new(&bytes, MCCL_PROMPT))),
        bytes,
        retry: Retry::Never,
        timeout: None,
        hold: None,
        cut_short: None,
    }
}

fn frames(answer: &axterm::device::Answer) -> Vec<String> {
    answer
        .frames
        .iter()
        .map(|f| String::from_utf8_lossy(f).into_owned())
        .collect()
}

fn cmd4cr() -> (DeviceHandle, Script) {
    device_with(Arc::new(AsciiWire::cmd4cr()), DeviceOptions::default())
}

fn mccl() -> (DeviceHandle, Script) {
    device_with(Arc::new(AsciiWire::mccl()), DeviceOptions::default())
}

#[tokio::test(start_paused = true)]
async fn cmd4cr_the_next_line_is_the_answer() {
    let (device, mut script) = cmd4cr();
    let pending = device.submit(Priority::User, cmd4cr_line("@01POLX"));
    assert_eq!(script.request().await, b"@01POLX\r".to_vec());
    script.send(b"7\r");
    assert_eq!(frames(&pending.await.expect("answered")), ["7"]);

    // Split anywhere, ended by CRLF.
    let pending = device.submit(Priority::User, cmd4cr_line("@01STORE"));
    script.request().await;
    script.send(b"O");
    script.send(b"K\r\n");
    assert_eq!(frames(&pending.await.expect("answered")), ["OK"]);
}

#[tokio::test(start_paused = true)]
async fn cmd4cr_noise_without_terminator_is_dropped_and_bounded() {
    let (device, mut script) = cmd4cr();
    let mut traffic = device.traffic();
    script.send(&[b'#'; 200]);
    let noise = Instant::now();
    let pending = device.submit(Priority::User, cmd4cr_line("@01DI"));
    script.request().await;
    assert!(
        noise.elapsed() >= AsciiWire::cmd4cr().silence(at_9600()),
        "the line is quiet first"
    );
    script.send(b"8\r");
    assert_eq!(frames(&pending.await.expect("answered")), ["8"]);
    let garbage: usize = drain(&mut traffic)
        .iter()
        .filter(|r| r.kind == TrafficKind::Garbage)
        .map(|r| r.bytes.len())
        .sum();
    assert_eq!(garbage, 200);
}

#[tokio::test(start_paused = true)]
async fn cmd4cr_a_read_is_retried_after_a_timeout() {
    let (device, mut script) = cmd4cr();
    let pending = device.submit(Priority::User, cmd4cr_line("@01PX"));
    script.request().await;
    assert_eq!(script.request().await, b"@01PX\r".to_vec());
    script.send(b"-1200\r");
    let answer = pending.await.expect("answered");
    assert_eq!(
        (frames(&answer), answer.attempts),
        (vec!["-1200".into()], 2)
    );
}

#[tokio::test(start_paused = true)]
async fn mccl_echo_reply_lines_then_a_prompt_without_terminator() {
    let (device, mut script) = mccl();
    let pending = device.submit(Priority::User, mccl_line("1TP"));
    assert_eq!(script.request().await, b"1TP\r".to_vec());
    script.send(b"1TP\r\n");
    script.send(b"01 997\r\n");
    script.send(b">");
    assert_eq!(
        frames(&pending.await.expect("answered")),
        ["1TP", "01 997", ">"]
    );

    // No reply lines: echo and prompt in one chunk.
    let pending = device.submit(Priority::User, mccl_line("1MR100"));
    script.request().await;
    script.send(b"1MR100\r\n>");
    assert_eq!(frames(&pending.await.expect("answered")), ["1MR100", ">"]);
}

#[tokio::test(start_paused = true)]
async fn mccl_an_earlier_commands_late_answer_is_never_this_ones() {
    let (device, mut script) = mccl();
    let mut traffic = device.traffic();
    let result = device.transact(Priority::User, mccl_line("1TP")).await;
    assert!(matches!(
        result,
        Err(DeviceError::Timeout { attempts: 1, .. })
    ));
    script.request().await;

    let pending = device.submit(Priority::User, mccl_line("1TV"));
    // The late answer of 1TP straddles the new request.
    script.send(b"1TP\r\n01 997\r\n");
    assert_eq!(script.request().await, b"1TV\r".to_vec());
    script.send(b">");
    script.send(b"1TV\r\n01 0.5\r\n>");
    assert_eq!(
        frames(&pending.await.expect("answered")),
        ["1TV", "01 0.5", ">"]
    );
    let stale: Vec<_> = drain(&mut traffic)
        .into_iter()
        .filter(|r| r.kind == TrafficKind::Stale)
        .map(|r| String::from_utf8_lossy(&r.bytes).into_owned())
        .collect();
    assert_eq!(stale, ["1TP", "01 997", ">"]);
}

#[tokio::test(start_paused = true)]
async fn mccl_an_answer_cut_short_times_out() {
    let (device, mut script) = mccl();
    let pending = device.submit(
        Priority::User,
        Transaction {
            timeout: Some(Duration::from_millis(300)),
            ..mccl_line("1WS")
        },
    );
    script.request().await;
    script.send(b"1WS\r\n");
    assert_eq!(
        pending.await,
        Err(DeviceError::Timeout {
            timeout: Duration::from_millis(300),
            attempts: 1
        })
    );
}

/// A CMD-4CR line as the console prepares it: its own reply rule (the
/// success answer or an error) and the CMD-4CR wire with its sentinels.
fn cmd4cr_prepared(line: &str) -> Transaction {
    use axterm::protocol::console::{Answering, FamilyConsole};
    let prepared = axterm::protocol::cmd4cr::Cmd4crConsole
        .prepare(line, 1)
        .expect("a valid line");
    let Answering::Reply(rule) = prepared.answering else {
        panic!("{line} is answered")
    };
    Transaction {
        bytes: prepared.bytes,
        expect: Expect::Reply(rule),
        retry: Retry::Never,
        timeout: None,
        hold: None,
        cut_short: None,
    }
}

fn cmd4cr_console_wire() -> (DeviceHandle, Script) {
    device_with(
        Arc::new(axterm::protocol::cmd4cr::Cmd4crWire::default()),
        DeviceOptions::default(),
    )
}

#[tokio::test(start_paused = true)]
async fn cmd4cr_a_garbled_ok_is_never_success() {
    let (device, mut script) = cmd4cr_console_wire();
    let pending = device.submit(Priority::User, cmd4cr_prepared("STOPX"));
    assert_eq!(script.request().await, b"@01STOPX\r".to_vec());
    // `OK` with its first byte flipped (the issue's `corrupt=1,seed=1`).
    script.send(b"\x97K\r");
    let error = pending.await.unwrap_err();
    assert!(
        matches!(&error, DeviceError::Garbled { received, .. } if received == b"\x97K"),
        "{error:?}"
    );
}

#[tokio::test(start_paused = true)]
async fn cmd4cr_a_late_ok_is_never_a_later_writes_answer() {
    let (device, mut script) = cmd4cr_console_wire();
    let mut traffic = device.traffic();
    let jog = device
        .transact(Priority::User, cmd4cr_prepared("JX+"))
        .await;
    assert!(matches!(jog, Err(DeviceError::Timeout { .. })), "{jog:?}");
    script.request().await;
    // Every write is answered `OK`: before STOPX, a read whose answer has
    // a form no write's has settles the line.
    let stop = device.submit(Priority::User, cmd4cr_prepared("STOPX"));
    assert_eq!(script.request().await, b"@01PP\r".to_vec());
    script.send(b"OK\r");
    script.send(b"0:0:0:0\r");
    assert_eq!(script.request().await, b"@01STOPX\r".to_vec());
    script.send(b"?Error Moving\r");
    let refused = stop.await.expect("an answer");
    assert_eq!(frames(&refused), ["?Error Moving"], "the stop's own answer");
    let stale: Vec<_> = drain(&mut traffic)
        .into_iter()
        .filter(|r| r.kind == TrafficKind::Stale)
        .map(|r| r.bytes)
        .collect();
    assert_eq!(stale, [b"OK".to_vec()]);

    // With a four-field read unanswered, the sentinel is a one-number read.
    let positions = device.transact(Priority::User, cmd4cr_prepared("PP")).await;
    assert!(positions.is_err());
    script.request().await;
    let read = device.submit(Priority::User, cmd4cr_prepared("MSTX"));
    assert_eq!(script.request().await, b"@01PX\r".to_vec());
    script.send(b"12:0:0:0\r");
    script.send(b"12\r");
    assert_eq!(script.request().await, b"@01MSTX\r".to_vec());
    script.send(b"0\r");
    assert_eq!(frames(&read.await.expect("answered")), ["0"]);
}

#[tokio::test(start_paused = true)]
async fn without_sentinels_a_stop_goes_at_once_and_the_rest_wait_for_quiet() {
    let (device, mut script) = mccl();
    let lost = device.transact(Priority::User, mccl_line("1TP")).await;
    assert!(lost.is_err());
    let timed_out = Instant::now();
    script.request().await;
    let user = device.submit(Priority::User, mccl_line("1TV"));
    let stop = device.submit(Priority::EmergencyStop, mccl_line("1ST"));
    assert_eq!(script.request().await, b"1ST\r".to_vec());
    let silence = AsciiWire::mccl().silence(at_9600());
    assert_eq!(
        timed_out.elapsed(),
        silence,
        "the stop waits for silence only"
    );
    script.send(b"1ST\r\n>");
    assert!(stop.await.is_ok());
    assert_eq!(script.request().await, b"1TV\r".to_vec());
    let timeout = axterm::device::default_timeout(at_9600(), 4);
    assert!(
        timed_out.elapsed() >= timeout,
        "the next line waits for the quiet time after the lost answer"
    );
    script.send(b"1TV\r\n01 0.5\r\n>");
    assert_eq!(
        frames(&user.await.expect("answered")),
        ["1TV", "01 0.5", ">"]
    );
}
