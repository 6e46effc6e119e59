//! The device task over real byte transports: `axterm sim tmcm1110` served
//! on a pseudo-terminal (opened as a serial port) and on TCP, in real time.
//! Waits are for events (a reply, a state change); the time limits only
//! stop a hung test.

mod device_support;

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::time::Duration;

use tokio::sync::mpsc;
use tokio::time::timeout;

use axterm::device::{
    Answer, DeviceError, DeviceEvent, DeviceHandle, DeviceOptions, LinkState, PollItem, PollPlan,
    PollSink, Priority, Retry, connect,
};
use axterm::link::LinkSpec;
use axterm::protocol::tmcl::{FRAME_LEN, Reply, Request, Status, TmclWire};
use device_support::{GAP, MVP, SAP, TARGET_EVENT, request, transaction};

/// Only guards against a hung test; a healthy exchange takes milliseconds.
const GIVE_UP_AFTER: Duration = Duration::from_secs(10);

/// A simulator served by the real binary.
struct Served {
    child: Child,
    endpoint: String,
}

impl Served {
    fn start(args: &[&str]) -> Served {
        let mut child = Command::new(env!("CARGO_BIN_EXE_axterm"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start axterm sim");
        let stdout = child.stdout.take().expect("stdout");
        let mut first_line = String::new();
        BufReader::new(stdout)
            .read_line(&mut first_line)
            .expect("read the endpoint line");
        Served {
            child,
            endpoint: first_line.trim().to_string(),
        }
    }

    /// End it as a user would (SIGTERM) and wait for it.
    fn terminate(mut self) {
        let pid = libc::pid_t::try_from(self.child.id()).expect("pid fits pid_t");
        // SAFETY: sends a signal to our own child process; nothing is shared.
        let sent = unsafe { libc::kill(pid, libc::SIGTERM) };
        assert_eq!(sent, 0, "kill(SIGTERM) failed");
        let _ = self.child.wait();
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn reply_of(answer: &Answer) -> Reply {
    let frame: [u8; FRAME_LEN] = answer
        .frames
        .first()
        .and_then(|f| f.as_slice().try_into().ok())
        .expect("a 9-byte answer");
    Reply::from_bytes(&frame).expect("good checksum")
}

async fn ask(device: &DeviceHandle, request: Request, retry: Retry) -> Reply {
    let answer = timeout(
        GIVE_UP_AFTER,
        device.transact(Priority::User, transaction(&request, retry)),
    )
    .await
    .expect("not hung")
    .expect("answered");
    reply_of(&answer)
}

/// Poll results as values, through a channel.
struct ChannelSink(mpsc::UnboundedSender<Result<i32, DeviceError>>);

impl PollSink for ChannelSink {
    fn record(&mut self, _index: usize, result: Result<&Answer, &DeviceError>) {
        let _ = self
            .0
            .send(result.map(|a| reply_of(a).value).map_err(Clone::clone));
    }
}

fn poll_position(device: &DeviceHandle) -> mpsc::UnboundedReceiver<Result<i32, DeviceError>> {
    let (tx, rx) = mpsc::unbounded_channel();
    device.set_poll_plan(Some(PollPlan {
        items: vec![PollItem {
            transaction: transaction(&request(GAP, 1, 0, 0), Retry::Read(2)),
            every: Duration::from_millis(10),
            urgent: false,
        }],
        sink: Box::new(ChannelSink(tx)),
    }));
    rx
}

/// The next poll result that is a value.
async fn next_polled_value(polls: &mut mpsc::UnboundedReceiver<Result<i32, DeviceError>>) -> i32 {
    timeout(GIVE_UP_AFTER, async {
        loop {
            if let Ok(value) = polls.recv().await.expect("polling goes on") {
                return value;
            }
        }
    })
    .await
    .expect("a poll answered")
}

async fn wait_for_state(device: &DeviceHandle, wanted: impl Fn(&LinkState) -> bool) {
    let mut state = device.state();
    timeout(GIVE_UP_AFTER, state.wait_for(|s| wanted(s)))
        .await
        .expect("the state changes")
        .expect("the task runs");
}

/// SAP/GAP, an error status, 138 and its second reply as an event, polling:
/// the manual's sequence (§3.6.5, §3.6.6, §3.6.4, §3.6.52) through the task.
async fn run_sequence(device: &DeviceHandle) {
    let mut events = device.events();
    let reply = ask(device, request(SAP, 4, 0, 1000), Retry::Never).await;
    assert_eq!((reply.status, reply.command), (Status::OK, SAP));
    let reply = ask(device, request(GAP, 4, 0, 0), Retry::Read(2)).await;
    assert_eq!(reply.value, 1000);
    let reply = ask(device, request(SAP, 6, 0, 300), Retry::Never).await;
    assert_eq!(reply.status, Status::INVALID_VALUE, "AP6 range is 0..255");

    let reply = ask(device, request(TARGET_EVENT, 0, 0, 1), Retry::Never).await;
    assert_eq!((reply.status, reply.value), (Status::OK, 1));
    let reply = ask(device, request(MVP, 0, 0, 2000), Retry::Never).await;
    assert_eq!((reply.status, reply.command), (Status::OK, MVP));
    let event = timeout(GIVE_UP_AFTER, async {
        loop {
            if let DeviceEvent::Unsolicited { description, .. } =
                events.recv().await.expect("events")
            {
                return description;
            }
        }
    })
    .await
    .expect("the target is reached");
    assert!(
        event.starts_with("target position reached (138)"),
        "{event}"
    );

    let reply = ask(device, request(GAP, 8, 0, 0), Retry::Read(2)).await;
    assert_eq!(reply.value, 1, "position reached flag");
    let mut polls = poll_position(device);
    assert_eq!(next_polled_value(&mut polls).await, 2000);
    assert_eq!(next_polled_value(&mut polls).await, 2000);
    device.set_poll_plan(None);
}

#[tokio::test]
async fn the_device_task_drives_a_steprocker_served_on_a_pty() {
    let served = Served::start(&["sim", "tmcm1110", "--pty"]);
    let spec = LinkSpec::Serial {
        path: served.endpoint.clone(),
        baud: 9600,
    };
    let device = connect(
        spec,
        Arc::new(TmclWire::default()),
        DeviceOptions::default(),
    )
    .await
    .expect("the pty opens");
    run_sequence(&device).await;
    let counters = *device.counters().borrow();
    assert_eq!((counters.timeouts, counters.unsolicited), (0, 1));
    timeout(GIVE_UP_AFTER, device.shutdown())
        .await
        .expect("shuts down");
}

#[tokio::test]
async fn replies_behind_garbage_are_found_on_an_emulated_wire() {
    let served = Served::start(&[
        "sim",
        "tmcm1110",
        "--pty",
        "--baud",
        "115200",
        "--fault",
        "garbage=1,seed=7",
    ]);
    let spec = LinkSpec::Serial {
        path: served.endpoint.clone(),
        baud: 115_200,
    };
    let device = connect(
        spec,
        Arc::new(TmclWire::default()),
        DeviceOptions::default(),
    )
    .await
    .expect("the pty opens");
    for value in [10, 20, 30] {
        let reply = ask(&device, request(SAP, 4, 0, value), Retry::Never).await;
        assert_eq!(reply.status, Status::OK);
        let reply = ask(&device, request(GAP, 4, 0, 0), Retry::Never).await;
        assert_eq!(reply.value, value);
    }
    let counters = *device.counters().borrow();
    assert!(counters.garbage_bytes >= 6, "{counters:?}");
    assert_eq!(counters.retries, 0);
}

#[tokio::test]
async fn over_tcp_a_lost_connection_is_reopened_and_polling_resumes() {
    let served = Served::start(&["sim", "tmcm1110", "--tcp", "127.0.0.1:0"]);
    let address = served.endpoint.clone();
    let options = DeviceOptions {
        reconnect_initial: Duration::from_millis(20),
        reconnect_max: Duration::from_millis(200),
        ..DeviceOptions::default()
    };
    let device = connect(
        LinkSpec::Tcp {
            address: address.clone(),
            baud: None,
        },
        Arc::new(TmclWire::default()),
        options,
    )
    .await
    .expect("the socket connects");
    run_sequence(&device).await;

    let mut polls = poll_position(&device);
    assert_eq!(next_polled_value(&mut polls).await, 2000);
    served.terminate();
    wait_for_state(&device, |s| matches!(s, LinkState::Disconnected { .. })).await;
    // Results from before the loss.
    while polls.try_recv().is_ok() {}
    let result = device
        .transact(
            Priority::User,
            transaction(&request(GAP, 1, 0, 0), Retry::Never),
        )
        .await;
    assert!(
        matches!(result, Err(DeviceError::Disconnected(_))),
        "{result:?}"
    );

    // A new simulator on the same port: a fresh module at position 0.
    let _again = Served::start(&["sim", "tmcm1110", "--tcp", &address]);
    wait_for_state(&device, |s| matches!(s, LinkState::Connected { .. })).await;
    assert_eq!(next_polled_value(&mut polls).await, 0);
    assert!(device.counters().borrow().reconnects >= 1);
}
