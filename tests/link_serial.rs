//! The serial link over a real pseudo-terminal: the test holds the master
//! side (standing in for the adapter and the module behind it), the link
//! opens the slave path as it would open /dev/ttyUSB0.
//!
//! What the two sides of a Linux pty do when the other goes away:
//! - slave (the link's side) when the master closes: hung up for good,
//!   like an unplugged USB adapter. Reads return 0 bytes, poll says
//!   POLLHUP, writes fail with EIO, and the /dev/pts node disappears.
//! - master when no slave fd is open: reads fail with EIO (poll says
//!   POLLHUP), but only until someone opens the slave path again; that is
//!   why the served simulator keeps its own slave fd open.

use std::io::{Read, Write};
use std::time::Duration;

use axterm::link::{Link, LinkInput, LinkSpec, byte_time};
use serialport::{SerialPort, TTYPort};

/// Only guards against a hung test; a healthy exchange takes microseconds.
const GIVE_UP_AFTER: Duration = Duration::from_secs(10);

/// A pty whose master the test keeps; the pair's own slave handle is closed
/// so that the link's is the only one.
fn pty() -> (TTYPort, String) {
    let (mut master, slave) = TTYPort::pair().expect("a pseudo-terminal");
    let path = slave.name().expect("the slave has a path");
    master.set_timeout(GIVE_UP_AFTER).expect("timeout");
    drop(slave);
    (master, path)
}

async fn read_exactly(link: &mut Link, n: usize) -> Vec<u8> {
    let mut got = Vec::new();
    while got.len() < n {
        match tokio::time::timeout(GIVE_UP_AFTER, link.incoming.recv()).await {
            Ok(Some(LinkInput::Bytes(bytes))) => got.extend(bytes),
            other => panic!("expected bytes, got {other:?} after {got:?}"),
        }
    }
    got
}

async fn next_input(link: &mut Link) -> Option<LinkInput> {
    tokio::time::timeout(GIVE_UP_AFTER, link.incoming.recv())
        .await
        .expect("the link reports within the guard time")
}

#[tokio::test]
async fn bytes_pass_both_ways() {
    let (mut master, path) = pty();
    let spec = LinkSpec::Serial {
        path: path.clone(),
        baud: 9600,
    };
    let mut link = spec.open().await.expect("opens");
    assert_eq!(link.name, format!("{path} at 9600 Bd"));
    assert_eq!(link.byte_time, Some(byte_time(9600)));

    master.write_all(b"from the module").expect("write");
    assert_eq!(read_exactly(&mut link, 15).await, b"from the module");

    link.outgoing.send(b"to the module").expect("send");
    let mut buf = [0u8; 13];
    master.read_exact(&mut buf).expect("read");
    assert_eq!(&buf, b"to the module");
}

#[tokio::test]
async fn closing_the_far_end_is_a_loss_reported_once() {
    let (master, path) = pty();
    let mut link = LinkSpec::Serial {
        path: path.clone(),
        baud: 115_200,
    }
    .open()
    .await
    .expect("opens");
    // Closing the master removes the slave's node before close() returns;
    // the reader (on this test's one thread) only looks after that.
    drop(master);
    assert_eq!(
        next_input(&mut link).await,
        Some(LinkInput::Lost(format!(
            "the port vanished: {path} is gone (unplugged?)"
        )))
    );
    assert!(link.outgoing.send(b"x").is_err(), "writes fail too");
    assert!(
        link.incoming.try_recv().is_err(),
        "one loss notice, nothing after it"
    );
}

#[tokio::test]
async fn dropping_the_link_closes_the_port() {
    let (mut master, path) = pty();
    let link = LinkSpec::Serial { path, baud: 9600 }
        .open()
        .await
        .expect("opens");
    drop(link);
    // The master's read fails (POLLHUP) once no slave fd is open any more,
    // and waits (up to the guard time) while one still is.
    let read = tokio::task::spawn_blocking(move || master.read(&mut [0u8; 1]))
        .await
        .expect("joins");
    let error = read.expect_err("no slave left open");
    assert_eq!(error.kind(), std::io::ErrorKind::BrokenPipe, "{error}");
}

#[tokio::test]
async fn a_missing_port_is_named_in_the_error() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("ttyUSB9").to_string_lossy().into_owned();
    let error = LinkSpec::Serial {
        path: path.clone(),
        baud: 9600,
    }
    .open()
    .await
    .expect_err("no such port");
    assert_eq!(
        error.headline(),
        format!("cannot open {path} at 9600 Bd: no such port (not plugged in? a wrong name?)")
    );
    // Then the ports there are (none in a container, some on a PC).
    assert!(
        error.advice.first().is_some_and(|line| {
            line.starts_with("no serial port is here at all")
                || line == &format!("{path} is not among the serial ports here (`axterm ports`):")
        }),
        "{error}"
    );
    assert!(
        error
            .to_string()
            .starts_with(&format!("{}\n  ", error.headline())),
        "the advice follows, indented: {error}"
    );
}

#[tokio::test]
async fn a_port_in_use_is_refused_plainly() {
    let (_master, path) = pty();
    let spec = LinkSpec::Serial { path, baud: 9600 };
    let _first = spec.open().await.expect("opens");
    // Refused even as root: TIOCEXCL does not bind root, but serialport
    // also takes an exclusive flock, which does.
    let error = spec.open().await.expect_err("already open");
    assert_eq!(
        error.reason, "the port is in use by another program",
        "{error}"
    );
    // The holder is this very process (the first link), found in /proc.
    let comm = std::fs::read_to_string("/proc/self/comm").expect("own comm");
    let held_by = format!("held by {} (pid {})", comm.trim(), std::process::id());
    assert!(error.advice.contains(&held_by), "{error}");
}

/// The link states the device task tells, up to the first that `last`
/// accepts.
async fn changes_until(
    events: &mut tokio::sync::broadcast::Receiver<axterm::device::DeviceEvent>,
    last: impl Fn(&axterm::device::LinkState) -> bool,
) -> Vec<axterm::device::LinkState> {
    let mut changes = Vec::new();
    loop {
        let event = tokio::time::timeout(GIVE_UP_AFTER, events.recv())
            .await
            .expect("news within the guard time")
            .expect("the task runs");
        if let axterm::device::DeviceEvent::StateChanged(change) = event {
            let done = last(&change);
            changes.push(change);
            if done {
                return changes;
            }
        }
    }
}

/// A port that vanishes (its by-id link removed and its tty hung up, as
/// when a USB adapter is pulled) says so; the device task's reopenings
/// fail, each counted, until the port is back under the same name.
#[tokio::test]
async fn a_vanished_port_is_said_so_and_reopened_when_it_returns() {
    use axterm::device::{DeviceOptions, LinkState, connect};
    use axterm::protocol::tmcl::TmclWire;
    use std::os::unix::fs::symlink;
    use std::sync::Arc;

    let dir = tempfile::tempdir().expect("temp dir");
    let stable = dir.path().join("usb-Trinamic_StepRocker-if00");
    let name = stable.to_string_lossy().into_owned();
    let (master, first) = pty();
    symlink(&first, &stable).expect("by-id link");
    let options = DeviceOptions {
        reconnect_initial: Duration::from_millis(5),
        reconnect_max: Duration::from_millis(20),
        ..DeviceOptions::default()
    };
    let spec = LinkSpec::Serial {
        path: name.clone(),
        baud: 9600,
    };
    let device = connect(spec, Arc::new(TmclWire::default()), options)
        .await
        .expect("opens");
    let mut events = device.events();

    // Unplugged: udev removes the link, the kernel hangs the tty up.
    std::fs::remove_file(&stable).expect("unlink");
    drop(master);
    let mut changes = changes_until(&mut events, |s| {
        matches!(s, LinkState::Disconnected { attempts: 2, .. })
    })
    .await;

    // Plugged back in: a new tty under the same stable name.
    let (_master, second) = pty();
    symlink(&second, &stable).expect("by-id link again");
    changes.extend(changes_until(&mut events, |s| matches!(s, LinkState::Connected { .. })).await);

    let link = format!("{name} at 9600 Bd");
    assert_eq!(
        changes.first(),
        Some(&LinkState::Disconnected {
            reason: format!("{link}: the port vanished: {name} is gone (unplugged?)"),
            attempts: 0,
            retry_in: Duration::from_millis(5),
        }),
        "{changes:#?}"
    );
    let failures: Vec<&LinkState> = changes[1..changes.len() - 1].iter().collect();
    assert!(failures.len() >= 2, "{changes:#?}");
    for (n, failure) in failures.iter().enumerate() {
        let LinkState::Disconnected {
            reason, attempts, ..
        } = failure
        else {
            panic!("not a failed attempt: {failure:?}");
        };
        assert_eq!(
            usize::try_from(*attempts).ok(),
            Some(n + 1),
            "counted in order"
        );
        assert_eq!(
            reason,
            &format!("cannot open {link}: the port vanished: {name} is not there (unplugged?)"),
            "one line, without the port list"
        );
    }
    assert_eq!(changes.last(), Some(&LinkState::Connected { link }));
    assert_eq!(device.counters().borrow().reconnects, 1);
}
