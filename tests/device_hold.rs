//! Held lines, answers that end in quiet and raw probes, on scripted links
//! with tokio's paused clock: the test plays a controller that echoes a
//! line, runs it for as long as it takes and ends it with a prompt (the
//! shape of an MCCL `RP` or `WS` line), and takes an abort or a pause byte
//! meanwhile. Every wait below is virtual and exact.

mod device_support;

use std::sync::Arc;
use std::time::Duration;

use tokio::time::{Instant, sleep};

use axterm::device::{
    DeviceError, DeviceHandle, DeviceOptions, Expect, Hold, PollItem, PollPlan, Priority, Retry,
    TrafficKind, Transaction, default_timeout,
};
use axterm::protocol::ascii::{AsciiWire, EchoThenPrompt, MCCL_PROMPT, line_bytes};
use axterm::protocol::wire::{Frame, ReplyRule, Verdict, WireFormat};
use device_support::*;

const ESCAPE: u8 = 0x1B;

fn device() -> (DeviceHandle, Script) {
    device_with(Arc::new(AsciiWire::mccl()), DeviceOptions::default())
}

/// A line answered by its echo and the prompt.
fn line(text: &str) -> Transaction {
    let bytes = line_bytes(text);
    Transaction::new(
        bytes.clone(),
        Expect::Reply(Arc::new(EchoThenPrompt::new(&bytes, MCCL_PROMPT))),
        Retry::Never,
    )
}

/// The same line held: Escape aborts it, Space pauses it.
fn held(text: &str) -> Transaction {
    Transaction {
        hold: Some(Hold {
            abort: vec![ESCAPE],
            pause: Some(vec![b' ']),
        }),
        ..line(text)
    }
}

fn frames(answer: &axterm::device::Answer) -> Vec<String> {
    answer
        .frames
        .iter()
        .map(|f| String::from_utf8_lossy(f).into_owned())
        .collect()
}

/// The ordinary timeout of a line this long on the scripted 9600 Bd link.
fn ordinary(text: &str) -> Duration {
    default_timeout(at_9600(), line_bytes(text).len())
}

/// Waited `expected` on the virtual clock (its timer wheel counts whole
/// milliseconds: a deadline fires on the first tick at or after it).
#[track_caller]
fn assert_waited(elapsed: Duration, expected: Duration) {
    assert!(
        elapsed >= expected && elapsed < expected + Duration::from_millis(1),
        "waited {elapsed:?}, expected {expected:?}"
    );
}

const CYCLE: &str = "2MR1000,WS0.5,MR-1000,WS0.5,RP6";

/// The emergency stop `0AB` goes next and is answered, then `1MR500`,
/// queued before it.
async fn the_stop_then_the_line_queued(
    script: &mut Script,
    stop: impl std::future::Future<Output = Result<axterm::device::Answer, DeviceError>>,
    queued: impl std::future::Future<Output = Result<axterm::device::Answer, DeviceError>>,
) {
    assert_eq!(script.request().await, line_bytes("0AB"));
    script.send(b"0AB\r\n>");
    stop.await.expect("stopped");
    assert_eq!(script.request().await, line_bytes("1MR500"));
    script.send(b"1MR500\r\n>");
    queued.await.expect("sent after");
}

#[tokio::test(start_paused = true)]
async fn a_held_line_has_no_timeout_and_ends_on_its_answer() {
    let (device, mut script) = device();
    let busy = device.busy();
    assert_eq!(*busy.borrow(), None);
    let pending = device.submit(Priority::User, held(CYCLE));
    assert_eq!(script.request().await, line_bytes(CYCLE));
    script.send(format!("{CYCLE}\r\n").as_bytes());
    // An hour of motion, far beyond any reply timeout.
    sleep(Duration::from_secs(3600)).await;
    let shown = busy.borrow().clone().expect("busy while held");
    assert_eq!(shown.bytes, line_bytes(CYCLE));
    assert_eq!(shown.priority, Priority::User);
    assert!(!shown.paused && !shown.aborting && shown.pausable);
    script.send(b">");
    let answer = pending.await.expect("answered");
    assert_eq!(frames(&answer), [CYCLE, ">"]);
    assert!(answer.elapsed >= Duration::from_secs(3600));
    assert_eq!(*busy.borrow(), None, "not busy once answered");
    assert_eq!(device.counters().borrow().timeouts, 0);
}

#[tokio::test(start_paused = true)]
async fn a_held_line_given_a_timeout_keeps_it() {
    let (device, mut script) = device();
    let pending = device.submit(
        Priority::User,
        Transaction {
            timeout: Some(Duration::from_secs(2)),
            ..held(CYCLE)
        },
    );
    script.request().await;
    let start = Instant::now();
    let error = pending.await.expect_err("no answer");
    assert!(matches!(error, DeviceError::Timeout { .. }), "{error}");
    assert_eq!(start.elapsed(), Duration::from_secs(2));
}

#[tokio::test(start_paused = true)]
async fn an_abort_is_written_at_once_and_its_answer_ends_the_line() {
    let (device, mut script) = device();
    let mut traffic = device.traffic();
    let busy = device.busy();
    let pending = device.submit(Priority::User, held(CYCLE));
    script.request().await;
    script.send(format!("{CYCLE}\r\n").as_bytes());
    sleep(Duration::from_secs(5)).await;
    assert!(device.abort_line().await, "a line was held");
    assert_eq!(script.request().await, [ESCAPE]);
    assert!(busy.borrow().as_ref().is_some_and(|b| b.aborting));
    script.send(b"?-7 WS0.5\r\n>");
    let answer = pending.await.expect("the abort's answer");
    assert_eq!(frames(&answer), [CYCLE, "?-7 WS0.5", ">"]);
    assert_eq!(device.counters().borrow().aborts, 1);
    let sent: Vec<Vec<u8>> = drain(&mut traffic)
        .into_iter()
        .filter(|r| r.kind == TrafficKind::Request)
        .map(|r| r.bytes)
        .collect();
    assert_eq!(sent, [line_bytes(CYCLE), vec![ESCAPE]]);
}

#[tokio::test(start_paused = true)]
async fn an_abort_without_an_answer_fails_after_the_grace() {
    let (device, mut script) = device();
    let pending = device.submit(Priority::User, held(CYCLE));
    script.request().await;
    assert!(device.abort_line().await);
    let aborted = Instant::now();
    script.request().await;
    let error = pending.await.expect_err("no answer to the abort");
    assert_waited(aborted.elapsed(), ordinary(CYCLE));
    assert_eq!(
        error,
        DeviceError::AbortUnanswered {
            grace: ordinary(CYCLE),
            abort: vec![ESCAPE]
        }
    );
    assert!(error.to_string().contains("1B sent"), "{error}");
    assert_eq!(*device.busy().borrow(), None);
    // A second abort while the first is awaited writes nothing more.
    let pending = device.submit(Priority::User, held(CYCLE));
    script.request().await;
    assert!(device.abort_line().await);
    assert!(device.abort_line().await);
    assert_eq!(script.request().await, [ESCAPE]);
    script.send(format!("{CYCLE}\r\n?-7\r\n>").as_bytes());
    pending.await.expect("answered");
    assert!(script.nothing_written());
}

#[tokio::test(start_paused = true)]
async fn space_pauses_and_resumes_a_held_line() {
    let (device, mut script) = device();
    let busy = device.busy();
    let pending = device.submit(Priority::User, held(CYCLE));
    script.request().await;
    assert_eq!(device.pause_line().await, Some(true));
    assert_eq!(script.request().await, b" ");
    assert!(busy.borrow().as_ref().is_some_and(|b| b.paused));
    assert_eq!(device.pause_line().await, Some(false));
    assert_eq!(script.request().await, b" ");
    assert!(busy.borrow().as_ref().is_some_and(|b| !b.paused));
    // A line without a pause byte cannot be paused.
    script.send(format!("{CYCLE}\r\n>").as_bytes());
    pending.await.expect("answered");
    let pending = device.submit(
        Priority::User,
        Transaction {
            hold: Some(Hold {
                abort: vec![ESCAPE],
                pause: None,
            }),
            ..line("1WS")
        },
    );
    script.request().await;
    assert_eq!(device.pause_line().await, None);
    assert!(busy.borrow().as_ref().is_some_and(|b| !b.pausable));
    script.send(b"1WS\r\n>");
    pending.await.expect("answered");
    assert!(script.nothing_written());
}

#[tokio::test(start_paused = true)]
async fn abort_and_pause_write_nothing_when_no_line_is_held() {
    let (device, mut script) = device();
    assert!(!device.abort_line().await);
    assert_eq!(device.pause_line().await, None);
    // Nor while a line that is not held is on the wire.
    let pending = device.submit(Priority::User, line("1TP"));
    script.request().await;
    assert!(!device.abort_line().await);
    assert_eq!(device.pause_line().await, None);
    script.send(b"1TP\r\n01 5\r\n>");
    pending.await.expect("answered");
    assert!(script.nothing_written());
    assert_eq!(*device.busy().borrow(), None);
}

#[tokio::test(start_paused = true)]
async fn an_emergency_stop_aborts_the_held_line_then_goes_first() {
    let (device, mut script) = device();
    let running = device.submit(Priority::User, held(CYCLE));
    script.request().await;
    script.send(format!("{CYCLE}\r\n").as_bytes());
    let queued = device.submit(Priority::User, line("1MR500"));
    sleep(Duration::from_secs(3)).await;
    let stop = device.submit(Priority::EmergencyStop, line("0AB"));
    // Escape at once, outside the one-request-in-flight rule.
    assert_eq!(script.request().await, [ESCAPE]);
    script.send(b"?-7 WS0.5\r\n>");
    let aborted = running.await.expect("the abort's answer");
    assert_eq!(frames(&aborted)[1], "?-7 WS0.5");
    // Then the stop, before the line queued earlier.
    the_stop_then_the_line_queued(&mut script, stop, queued).await;
}

#[tokio::test(start_paused = true)]
async fn an_emergency_stop_goes_after_the_grace_when_the_abort_is_not_answered() {
    let (device, mut script) = device();
    let running = device.submit(Priority::User, held(CYCLE));
    script.request().await;
    let stop = device.submit(Priority::EmergencyStop, line("0AB"));
    assert_eq!(script.request().await, [ESCAPE]);
    let escaped = Instant::now();
    assert!(matches!(
        running.await,
        Err(DeviceError::AbortUnanswered { .. })
    ));
    assert_eq!(script.request().await, line_bytes("0AB"));
    assert!(escaped.elapsed() >= ordinary(CYCLE));
    script.send(b"0AB\r\n>");
    stop.await.expect("stopped");
}

#[tokio::test(start_paused = true)]
async fn polling_waits_while_a_line_is_held_and_resumes_with_its_plan() {
    let (device, mut script) = device();
    let sink = RecordingSink::default();
    device.set_poll_plan(Some(PollPlan {
        items: vec![PollItem {
            transaction: line("1TP"),
            every: Duration::from_millis(50),
            urgent: false,
        }],
        sink: Box::new(sink.clone()),
    }));
    assert_eq!(script.request().await, line_bytes("1TP"));
    script.send(b"1TP\r\n01 0\r\n>");
    let pending = device.submit(Priority::User, held(CYCLE));
    assert_eq!(script.request().await, line_bytes(CYCLE));
    sleep(Duration::from_secs(10)).await;
    assert!(script.nothing_written(), "no poll while held");
    assert_eq!(sink.results().len(), 1);
    script.send(format!("{CYCLE}\r\n>").as_bytes());
    pending.await.expect("answered");
    assert_eq!(script.request().await, line_bytes("1TP"), "polling goes on");
    script.send(b"1TP\r\n01 0\r\n>");
    sleep(Duration::from_millis(1)).await;
    assert_eq!(sink.results().len(), 2);
}

/// A status line of every axis (MCCL: about 150 ms of answer at 9600 Bd)
/// that Escape may cut short.
const STATUS: &str = "1TP,TV,TS,2TP,TV,TS,3TP,TV,TS";

fn status_poll() -> PollPlan {
    PollPlan {
        items: vec![PollItem {
            transaction: Transaction {
                cut_short: Some(vec![ESCAPE]),
                ..line(STATUS)
            },
            every: Duration::from_millis(50),
            urgent: false,
        }],
        sink: Box::new(RecordingSink::default()),
    }
}

#[tokio::test(start_paused = true)]
async fn an_emergency_stop_cuts_a_long_status_read_short_and_goes_on_its_answer() {
    let (device, mut script) = device();
    let sink = RecordingSink::default();
    device.set_poll_plan(Some(PollPlan {
        sink: Box::new(sink.clone()),
        ..status_poll()
    }));
    assert_eq!(script.request().await, line_bytes(STATUS));
    script.send(format!("{STATUS}\r\n01 100\r\n01 0\r\n").as_bytes());
    let queued = device.submit(Priority::User, line("1MR500"));
    let stop = device.submit(Priority::EmergencyStop, line("0AB"));
    // Escape at once, not after the rest of the answer.
    assert_eq!(script.request().await, [ESCAPE]);
    assert!(
        script.nothing_written(),
        "the stop waits for the cut answer"
    );
    script.send(b"?-7 1TS\r\n>");
    the_stop_then_the_line_queued(&mut script, stop, queued).await;
    // The cut read is no reading: nothing of it reaches the status.
    let results = sink.results();
    assert_eq!(results.len(), 1, "{results:?}");
    assert!(
        matches!(&results[0].1, Err(DeviceError::CutShort { by }) if by == &[ESCAPE]),
        "{results:?}"
    );
    assert_eq!(device.counters().borrow().aborts, 1);
    assert_eq!(*device.busy().borrow(), None, "a poll is never shown busy");
}

#[tokio::test(start_paused = true)]
async fn only_an_emergency_stop_cuts_a_status_read_short() {
    let (device, mut script) = device();
    device.set_poll_plan(Some(status_poll()));
    assert_eq!(script.request().await, line_bytes(STATUS));
    script.send(format!("{STATUS}\r\n01 100\r\n").as_bytes());
    // A user line waits for the whole answer; the user's abort key is for
    // held lines only.
    let queued = device.submit(Priority::User, line("1MR500"));
    assert!(!device.abort_line().await);
    sleep(Duration::from_millis(5)).await;
    assert!(script.nothing_written());
    script.send(b"01 0\r\n01 0\r\n>");
    assert_eq!(script.request().await, line_bytes("1MR500"));
    script.send(b"1MR500\r\n>");
    queued.await.expect("sent after the whole answer");
    assert_eq!(device.counters().borrow().aborts, 0);
}

#[tokio::test(start_paused = true)]
async fn a_cut_read_whose_answer_never_comes_holds_the_stop_only_for_its_timeout() {
    let (device, mut script) = device();
    device.set_poll_plan(Some(status_poll()));
    assert_eq!(script.request().await, line_bytes(STATUS));
    let stop = device.submit(Priority::EmergencyStop, line("0AB"));
    assert_eq!(script.request().await, [ESCAPE]);
    let escaped = Instant::now();
    assert_eq!(script.request().await, line_bytes("0AB"));
    // The read's timeout from the cut, then the line's silence: no more.
    let silence = AsciiWire::mccl().silence(at_9600());
    assert_waited(escaped.elapsed(), ordinary(STATUS) + silence);
    script.send(b"0AB\r\n>");
    stop.await.expect("stopped");
}

#[tokio::test(start_paused = true)]
async fn a_shutdown_aborts_a_held_line() {
    let (device, mut script) = device();
    let running = device.submit(Priority::User, held(CYCLE));
    script.request().await;
    let closed = device.shutdown();
    assert_eq!(script.request().await, [ESCAPE]);
    script.send(format!("{CYCLE}\r\n?-7\r\n>").as_bytes());
    running.await.expect("the abort's answer");
    closed.await;
}

/// The echo, then lines; an error line completes the answer unless a
/// prompt follows; the prompt completes it.
#[derive(Debug)]
struct ErrorThenMaybePrompt(Vec<u8>);

impl ReplyRule for ErrorThenMaybePrompt {
    fn examine(&self, accepted: &[Frame], frame: &[u8]) -> Verdict {
        if accepted.is_empty() {
            return if frame == self.0.as_slice() {
                Verdict::Continue
            } else {
                Verdict::NotMine
            };
        }
        let after_error = accepted.iter().any(|f| f.starts_with(b"?"));
        match frame {
            b">" => Verdict::Complete,
            f if f.starts_with(b"?") => Verdict::CompleteIfQuiet,
            _ if after_error => Verdict::NotMine,
            _ => Verdict::Continue,
        }
    }
}

fn with_error_rule(text: &str) -> Transaction {
    Transaction::new(
        line_bytes(text),
        Expect::Reply(Arc::new(ErrorThenMaybePrompt(text.as_bytes().to_vec()))),
        Retry::Never,
    )
}

fn quiet_guard() -> Duration {
    AsciiWire::mccl().quiet_guard(at_9600())
}

#[tokio::test(start_paused = true)]
async fn an_answer_complete_unless_more_comes_ends_in_quiet() {
    let (device, mut script) = device();
    let pending = device.submit(Priority::User, with_error_rule("MC10"));
    script.request().await;
    script.send(b"MC10\r\n?-6\r\n");
    let came = Instant::now();
    let answer = pending.await.expect("complete once quiet");
    assert_waited(came.elapsed(), quiet_guard());
    assert_eq!(frames(&answer), ["MC10", "?-6"]);

    // A prompt within the guard belongs to it, and ends it at once.
    let pending = device.submit(Priority::User, with_error_rule("MC11"));
    script.request().await;
    script.send(b"MC11\r\n?-6\r\n");
    sleep(quiet_guard() / 2).await;
    let prompt = Instant::now();
    script.send(b">");
    let answer = pending.await.expect("answered");
    assert_eq!(prompt.elapsed(), Duration::ZERO);
    assert_eq!(frames(&answer), ["MC11", "?-6", ">"]);

    // Bytes of a frame not yet complete keep the answer open.
    let pending = device.submit(Priority::User, with_error_rule("MC12"));
    script.request().await;
    script.send(b"MC12\r\n?-6\r\n");
    sleep(quiet_guard() * 3 / 4).await;
    script.send(b"?-");
    sleep(quiet_guard() * 3 / 4).await;
    script.send(b"7\r\n");
    let answer = pending.await.expect("answered");
    assert_eq!(frames(&answer), ["MC12", "?-6", "?-7"]);

    // A frame the rule does not take ends the answer before it.
    let mut traffic = device.traffic();
    let pending = device.submit(Priority::User, with_error_rule("MC13"));
    script.request().await;
    script.send(b"MC13\r\n?-6\r\nnoise\r\n");
    let answer = pending.await.expect("answered");
    assert_eq!(frames(&answer), ["MC13", "?-6"]);
    let stale: Vec<Vec<u8>> = drain(&mut traffic)
        .into_iter()
        .filter(|r| r.kind == TrafficKind::Stale)
        .map(|r| r.bytes)
        .collect();
    assert_eq!(stale, [b"noise".to_vec()]);
}

#[tokio::test(start_paused = true)]
async fn a_raw_probe_takes_every_byte_until_the_line_is_quiet() {
    let (device, mut script) = device();
    // A partial line from before is not part of it.
    script.send(b"stale");
    sleep(Duration::from_millis(1)).await;
    let probe = Transaction::new(b"NO\r".to_vec(), Expect::UntilQuiet, Retry::Read(1));
    let pending = device.submit(Priority::User, probe.clone());
    assert_eq!(script.request().await, b"NO\r");
    script.send(b"NO\r");
    sleep(quiet_guard() / 2).await;
    script.send(b"\n>");
    let last = Instant::now();
    let answer = pending.await.expect("answered");
    assert_eq!(answer.frames, [b"NO\r\n>".to_vec()], "raw, unframed");
    assert_waited(last.elapsed(), quiet_guard());

    // Nothing at all is a timeout, retried as a read.
    let pending = device.submit(Priority::User, probe);
    script.request().await;
    script.request().await;
    let error = pending.await.expect_err("nothing came");
    assert!(
        matches!(error, DeviceError::Timeout { attempts: 2, .. }),
        "{error}"
    );
}

#[tokio::test(start_paused = true)]
async fn a_line_left_unterminated_is_a_frame_once_the_line_is_silent() {
    // A prompt changed to `#` (MCCL PC35) ends no line and is not the
    // framer's own prompt: silence alone tells it from a line's start.
    let (device, mut script) = device();
    let bytes = line_bytes("1TP");
    let pending = device.submit(
        Priority::User,
        Transaction::new(
            bytes.clone(),
            Expect::Reply(Arc::new(EchoThenPrompt::new(&bytes, b'#'))),
            Retry::Never,
        ),
    );
    script.request().await;
    script.send(b"1TP\r\n01 5\r\n#");
    let prompt = Instant::now();
    let answer = pending.await.expect("answered at the silence");
    assert_eq!(frames(&answer), ["1TP", "01 5", "#"]);
    assert_waited(prompt.elapsed(), AsciiWire::mccl().silence(at_9600()));
    assert_eq!(device.counters().borrow().garbage_bytes, 0);
}
