//! What the device task tests share: a scripted link (the test plays the
//! controller through two channels), TMCL requests and replies, a poll
//! sink that records what it gets.

// Each test file uses its own part of this.
#![allow(dead_code)]

use std::collections::VecDeque;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::sync::{broadcast, mpsc};
use tokio::time::Instant;

use axterm::device::{
    Answer, DeviceError, DeviceHandle, DeviceOptions, Expect, PollSink, Reopen, Retry,
    TrafficRecord, Transaction, never_reopen, spawn,
};
use axterm::link::{Link, LinkError, LinkInput, byte_time};
use axterm::protocol::tmcl::{Reply, Request, Status, TmclReplyRule, TmclWire};
use axterm::protocol::wire::WireFormat;

/// The controller's end of a scripted link.
pub struct Script {
    /// Bytes (or the loss) the device task will receive.
    pub to_host: mpsc::UnboundedSender<LinkInput>,
    /// Bytes the device task wrote.
    pub from_host: mpsc::UnboundedReceiver<Vec<u8>>,
}

impl Script {
    /// The next chunk the device task writes. Fails rather than hangs
    /// when virtual time runs on without one.
    pub async fn request(&mut self) -> Vec<u8> {
        tokio::time::timeout(Duration::from_secs(3600), self.from_host.recv())
            .await
            .expect("a request within an hour of virtual time")
            .expect("the device task wrote")
    }

    pub fn send(&self, bytes: &[u8]) {
        self.to_host
            .send(LinkInput::Bytes(bytes.to_vec()))
            .expect("the device task listens");
    }

    pub fn lose(&self, reason: &str) {
        let _ = self.to_host.send(LinkInput::Lost(reason.into()));
    }

    /// Nothing was written (so far).
    pub fn nothing_written(&mut self) -> bool {
        self.from_host.try_recv().is_err()
    }
}

/// A link whose other end the test plays.
pub fn scripted(name: &str, byte_time: Option<Duration>) -> (Link, Script) {
    let (to_host, incoming) = mpsc::unbounded_channel();
    let (outgoing, from_host) = mpsc::unbounded_channel::<Vec<u8>>();
    let link = Link {
        name: name.into(),
        incoming,
        outgoing: Box::new(outgoing),
        byte_time,
    };
    (link, Script { to_host, from_host })
}

pub fn at_9600() -> Option<Duration> {
    Some(byte_time(9600))
}

/// A TMCL device task on a scripted 9600 Bd link that cannot be reopened.
pub fn tmcl_device(options: DeviceOptions) -> (DeviceHandle, Script) {
    device_with(Arc::new(TmclWire::default()), options)
}

pub fn device_with(wire: Arc<dyn WireFormat>, options: DeviceOptions) -> (DeviceHandle, Script) {
    let (link, script) = scripted("scripted", at_9600());
    let handle = spawn(
        link,
        never_reopen("scripted", "a scripted link cannot be reopened"),
        wire,
        options,
    );
    (handle, script)
}

/// Links handed out one by one by a [`Reopen`], with the (virtual) time of
/// each attempt; an attempt finding none fails.
#[derive(Clone, Default)]
pub struct Spares {
    pub links: Arc<Mutex<VecDeque<Result<Link, LinkError>>>>,
    pub attempts: Arc<Mutex<Vec<Instant>>>,
}

impl Spares {
    pub fn push(&self, link: Result<Link, LinkError>) {
        self.links.lock().expect("spares").push_back(link);
    }

    pub fn attempts(&self) -> Vec<Instant> {
        self.attempts.lock().expect("attempts").clone()
    }

    pub fn reopen(&self) -> Reopen {
        let spares = self.clone();
        Box::new(move || {
            spares
                .attempts
                .lock()
                .expect("attempts")
                .push(Instant::now());
            let next = spares.links.lock().expect("spares").pop_front();
            Box::pin(async move {
                next.unwrap_or_else(|| Err(LinkError::new("scripted", "no spare link")))
            })
        })
    }
}

pub fn request(command: u8, kind: u8, motor_bank: u8, value: i32) -> Request {
    Request {
        address: 1,
        command,
        kind,
        motor_bank,
        value,
    }
}

pub const MVP: u8 = 4;
pub const SAP: u8 = 5;
pub const GAP: u8 = 6;
pub const SGP: u8 = 9;
pub const GGP: u8 = 10;
pub const MST: u8 = 3;
pub const TARGET_EVENT: u8 = 138;

/// GGP of user variable `n` (bank 2): each reads a different value.
pub fn ggp(n: u8) -> Request {
    request(GGP, n, 2, 0)
}

pub fn transaction(request: &Request, retry: Retry) -> Transaction {
    Transaction {
        bytes: request.to_bytes().to_vec(),
        expect: Expect::Reply(Arc::new(TmclReplyRule::for_request(request))),
        retry,
        timeout: None,
        hold: None,
        cut_short: None,
    }
}

/// The module's reply to `request`.
pub fn reply(request: &Request, status: Status, value: i32) -> Vec<u8> {
    Reply {
        host_address: 2,
        module_address: request.address,
        status,
        command: request.command,
        value,
    }
    .to_bytes()
    .to_vec()
}

pub fn ok(request: &Request, value: i32) -> Vec<u8> {
    reply(request, Status::OK, value)
}

/// 138's second reply (§3.6.52).
pub fn target_reached() -> Vec<u8> {
    Reply {
        host_address: 2,
        module_address: 1,
        status: Status::TARGET_REACHED,
        command: TARGET_EVENT,
        value: 1,
    }
    .to_bytes()
    .to_vec()
}

/// The value of a TMCL answer.
pub fn value_of(answer: &Answer) -> i32 {
    let frame: [u8; 9] = answer
        .frames
        .first()
        .and_then(|f| f.as_slice().try_into().ok())
        .expect("one 9-byte frame");
    Reply::from_bytes(&frame).expect("good checksum").value
}

/// Every traffic record received so far.
pub fn drain(traffic: &mut broadcast::Receiver<TrafficRecord>) -> Vec<TrafficRecord> {
    let mut records = Vec::new();
    while let Ok(record) = traffic.try_recv() {
        records.push(record);
    }
    records
}

/// One poll result as the sink saw it: item index and the value or error.
pub type Recorded = (usize, Result<Vec<Vec<u8>>, DeviceError>);

/// A poll sink that keeps every result.
#[derive(Clone, Default)]
pub struct RecordingSink(pub Arc<Mutex<Vec<Recorded>>>);

impl RecordingSink {
    pub fn results(&self) -> Vec<Recorded> {
        self.0.lock().expect("sink").clone()
    }
}

impl PollSink for RecordingSink {
    fn record(&mut self, index: usize, result: Result<&Answer, &DeviceError>) {
        let result = result.map(|a| a.frames.clone()).map_err(Clone::clone);
        self.0.lock().expect("sink").push((index, result));
    }
}

/// A device that never stops talking: from now on, 25 bytes of noise each
/// millisecond of virtual time (25 KB/s) come from the scripted link,
/// until the task is dropped or the device task has gone. The noise is
/// 0xFF bytes: no TMCL frame (eight of them sum to F8, not FF).
pub fn nonstop_noise(script: &Script) -> tokio::task::JoinHandle<()> {
    let to_host = script.to_host.clone();
    tokio::spawn(async move {
        while to_host.send(LinkInput::Bytes(vec![0xFF; 25])).is_ok() {
            tokio::time::sleep(Duration::from_millis(1)).await;
        }
    })
}
