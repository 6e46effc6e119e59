//! A serial port (8N1, no flow control) as a [`Link`].
//!
//! On unix the runtime's own poller (epoll) wakes a reader task, which
//! reads the non-blocking fd directly: measured over a pty, its round trip
//! is within a few per cent of a bare blocking write/read loop, while a
//! reader thread forwarding into the channel adds a thread wake-up each
//! time (see the report on the link branch). Elsewhere a thread does
//! blocking reads with a short timeout.
//!
//! The writer writes straight to a clone of the port: a frame lands in the
//! driver's buffer at once, so the device task is not held up.
//!
//! Losses: a USB adapter unplugged, or the master side of a pseudo-terminal
//! closed, hangs the tty up. Reads then return 0 bytes (raw mode waits for
//! at least one byte, so 0 is never "nothing yet"), poll reports POLLHUP
//! and writes fail with EIO. Any of these reports [`LinkInput::Lost`] once.
//!
//! [`LinkInput::Lost`]: super::LinkInput::Lost

use std::io::{self, Read, Write};
use std::path::Path;
use std::time::{Duration, Instant};

use serialport::{DataBits, FlowControl, Parity, SerialPort, StopBits};

use super::port_trouble::{self, Opening};
use super::rfc2217::{ComParity, ComStopBits};
use super::{Inbox, LINE_FRAMING, Link, LinkError, LinkWriter, byte_time, io_reason};

/// How long one write may wait for room in the driver's buffer. With no
/// flow control the UART drains at the baud rate, so only a stuck driver
/// takes this long; the write then fails and the link counts as lost.
const WRITE_TIMEOUT: Duration = Duration::from_secs(2);

/// How long the reader thread's blocking read waits before checking
/// whether the link was dropped (non-unix only).
#[cfg_attr(unix, allow(dead_code))]
const READ_POLL: Duration = Duration::from_millis(20);

/// Why the link is gone when a read returned 0 bytes or poll said POLLHUP.
const HUNG_UP: &str = "the port was hung up (unplugged?)";

/// Why the link is gone after a hang-up: the port vanished when its
/// device node went with it (a USB adapter pulled, a pty's master
/// closed), else [`HUNG_UP`]. The kernel hangs the tty up a moment
/// before it removes the node, so a node still there is not proof the
/// port stays: the first reopening then says what became of it.
fn hung_up(path: Option<&str>) -> String {
    match path {
        Some(path) if !Path::new(path).exists() => {
            format!("the port vanished: {path} is gone (unplugged?)")
        }
        _ => HUNG_UP.to_string(),
    }
}

pub(super) async fn open(
    path: &str,
    baud: u32,
    name: String,
    opening: Opening,
) -> Result<Link, LinkError> {
    let fail = |reason: String| LinkError::new(name.clone(), reason);
    let builder = serialport::new(path, baud)
        .data_bits(data_bits(LINE_FRAMING.data_bits))
        .parity(parity(LINE_FRAMING.parity))
        .stop_bits(stop_bits(LINE_FRAMING.stop_bits))
        .flow_control(FlowControl::None)
        .timeout(WRITE_TIMEOUT);
    let node = path.to_string();
    // A failure is explained where it happened, off the runtime too: the
    // explanation looks at the device, the accounts and /proc.
    let opened = tokio::task::spawn_blocking(move || {
        builder
            .open_native()
            .map_err(|e| port_trouble::explain(&node, &e, opening))
    })
    .await
    .map_err(|e| fail(format!("the opening task failed: {e}")))?;
    let port = opened.map_err(|(reason, advice)| LinkError {
        link: name.clone(),
        reason,
        advice,
    })?;
    let writer = port.try_clone_native().map_err(|e| {
        fail(format!(
            "cannot share the port between reader and writer: {e}"
        ))
    })?;
    let (inbox, incoming) = Inbox::new();
    #[cfg(unix)]
    spawn_reader(port, inbox.clone(), path.to_string()).map_err(|e| fail(io_reason(&e)))?;
    #[cfg(not(unix))]
    spawn_thread_reader(port, inbox.clone(), &name, Some(path.to_string()))
        .map_err(|e| fail(io_reason(&e)))?;
    Ok(Link {
        name,
        incoming,
        outgoing: Box::new(SerialWriter {
            port: writer,
            inbox,
            path: path.to_string(),
        }),
        byte_time: Some(byte_time(baud)),
    })
}

fn data_bits(bits: u8) -> DataBits {
    match bits {
        5 => DataBits::Five,
        6 => DataBits::Six,
        7 => DataBits::Seven,
        _ => DataBits::Eight,
    }
}

/// serialport has no mark or space parity.
fn parity(parity: ComParity) -> Parity {
    match parity {
        ComParity::Odd => Parity::Odd,
        ComParity::Even => Parity::Even,
        ComParity::None | ComParity::Mark | ComParity::Space => Parity::None,
    }
}

/// serialport has no 1.5 stop bits.
fn stop_bits(stop: ComStopBits) -> StopBits {
    match stop {
        ComStopBits::One | ComStopBits::OneAndHalf => StopBits::One,
        ComStopBits::Two => StopBits::Two,
    }
}

/// What a failed read means for the link.
fn read_loss(e: &io::Error, path: Option<&str>) -> String {
    match e.kind() {
        io::ErrorKind::BrokenPipe => hung_up(path),
        _ => format!("read failed: {}", io_reason(e)),
    }
}

#[cfg(unix)]
fn spawn_reader(port: serialport::TTYPort, inbox: Inbox, path: String) -> io::Result<()> {
    use std::os::fd::AsRawFd;
    use tokio::io::Interest;
    use tokio::io::unix::AsyncFd;

    // The writer's clone shares this open file, so its writes become
    // non-blocking too; `SerialWriter` waits for room itself.
    set_nonblocking(port.as_raw_fd())?;
    // SAFETY: the TTYPort owns its fd, keeps it open until it is dropped
    // (with the AsyncFd) and never swaps it for another.
    let fd = unsafe { AsyncFd::register_with_interest(port, Interest::READABLE) }?;
    tokio::spawn(async move {
        let mut buf = [0u8; 4096];
        loop {
            let ready = tokio::select! {
                _ = inbox.closed() => return,
                ready = fd.readable() => ready,
            };
            let mut guard = match ready {
                Ok(guard) => guard,
                Err(e) => return inbox.lost(read_loss(&e, Some(&path))),
            };
            match read_fd(guard.get_inner().as_raw_fd(), &mut buf) {
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => guard.clear_ready(),
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Ok(0) => {
                    drop(guard);
                    // Close our end before saying so, so that a reopening
                    // finds the port free.
                    drop(fd);
                    return inbox.lost(hung_up(Some(&path)));
                }
                Err(e) => {
                    drop(guard);
                    drop(fd);
                    return inbox.lost(read_loss(&e, Some(&path)));
                }
                Ok(n) => {
                    // A short read emptied the driver's buffer: wait for
                    // the next edge rather than read again for nothing.
                    if n < buf.len() {
                        guard.clear_ready();
                    }
                    if !inbox.bytes(buf.get(..n).unwrap_or_default()) {
                        return;
                    }
                }
            }
        }
    });
    Ok(())
}

#[cfg(unix)]
fn set_nonblocking(fd: std::os::fd::RawFd) -> io::Result<()> {
    // SAFETY: fcntl on an open fd we own; no memory is passed.
    let flags = unsafe { libc::fcntl(fd, libc::F_GETFL) };
    if flags < 0 {
        return Err(io::Error::last_os_error());
    }
    // SAFETY: as above.
    if unsafe { libc::fcntl(fd, libc::F_SETFL, flags | libc::O_NONBLOCK) } < 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(())
}

#[cfg(unix)]
fn read_fd(fd: std::os::fd::RawFd, buf: &mut [u8]) -> io::Result<usize> {
    // SAFETY: `buf` is valid for writes of its length for the whole call.
    let n = unsafe { libc::read(fd, buf.as_mut_ptr().cast(), buf.len()) };
    usize::try_from(n).map_err(|_| io::Error::last_os_error())
}

/// The reader where there is no fd to poll: a thread doing blocking reads
/// with a short timeout, so that it notices a dropped link promptly.
#[cfg_attr(unix, allow(dead_code))]
fn spawn_thread_reader<P>(
    mut port: P,
    inbox: Inbox,
    name: &str,
    path: Option<String>,
) -> io::Result<()>
where
    P: SerialPort + Read + 'static,
{
    port.set_timeout(READ_POLL)?;
    std::thread::Builder::new()
        .name(format!("read {name}"))
        .spawn(move || {
            let mut buf = [0u8; 4096];
            let reason = loop {
                if inbox.is_closed() {
                    return;
                }
                match port.read(&mut buf) {
                    Ok(0) => break hung_up(path.as_deref()),
                    Ok(n) => {
                        if !inbox.bytes(buf.get(..n).unwrap_or_default()) {
                            return;
                        }
                    }
                    Err(e)
                        if matches!(
                            e.kind(),
                            io::ErrorKind::TimedOut | io::ErrorKind::Interrupted
                        ) => {}
                    Err(e) => break read_loss(&e, path.as_deref()),
                }
            };
            // Close our end before saying so, so that a reopening finds
            // the port free.
            drop(port);
            inbox.lost(reason);
        })?;
    Ok(())
}

struct SerialWriter<P> {
    port: P,
    inbox: Inbox,
    /// The port's path, to tell a vanished port from a hung-up one.
    path: String,
}

impl<P: Write + Send> LinkWriter for SerialWriter<P> {
    fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        let result = write_all(&mut self.port, bytes);
        if let Err(e) = &result {
            let reason = match e.kind() {
                io::ErrorKind::BrokenPipe => hung_up(Some(&self.path)),
                _ => format!("write failed: {}", io_reason(e)),
            };
            self.inbox.lost(reason);
        }
        result
    }
}

/// `write_all` for a port whose fd may be non-blocking: serialport's write
/// first waits (up to its timeout) until there is room, so "would block"
/// only means another writer filled the buffer in between; try again until
/// [`WRITE_TIMEOUT`] has passed.
fn write_all(port: &mut impl Write, mut bytes: &[u8]) -> io::Result<()> {
    let deadline = Instant::now() + WRITE_TIMEOUT;
    while !bytes.is_empty() {
        match port.write(bytes) {
            Ok(0) => return Err(io::ErrorKind::WriteZero.into()),
            Ok(n) => bytes = bytes.get(n..).unwrap_or_default(),
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
                ) && Instant::now() < deadline => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use crate::link::LinkInput;

    /// The thread reader is what non-unix systems use; it is tested here
    /// over a pseudo-terminal.
    #[tokio::test]
    async fn the_thread_reader_forwards_bytes_and_reports_a_hangup() {
        let (mut master, slave) = serialport::TTYPort::pair().expect("pty");
        let (inbox, mut incoming) = Inbox::new();
        // No path: whether the pty's node is gone yet when this thread
        // sees the hang-up is a race with the kernel ([`hung_up`]).
        spawn_thread_reader(slave, inbox, "pty", None).expect("reader");
        master.write_all(b"hello").expect("write");
        let mut got = Vec::new();
        while got.len() < 5 {
            match incoming.recv().await {
                Some(LinkInput::Bytes(bytes)) => got.extend(bytes),
                other => panic!("unexpected {other:?}"),
            }
        }
        assert_eq!(got, b"hello");
        drop(master);
        assert_eq!(incoming.recv().await, Some(LinkInput::Lost(HUNG_UP.into())));
        assert_eq!(incoming.recv().await, None);
    }

    #[test]
    fn a_hang_up_whose_node_is_gone_is_a_vanished_port() {
        let dir = tempfile::tempdir().expect("temp dir");
        let there = dir.path().join("ttyUSB0");
        std::fs::write(&there, "").expect("node stand-in");
        let there = there.to_string_lossy().into_owned();
        assert_eq!(hung_up(Some(&there)), HUNG_UP);
        let gone = dir.path().join("ttyUSB1").to_string_lossy().into_owned();
        assert_eq!(
            hung_up(Some(&gone)),
            format!("the port vanished: {gone} is gone (unplugged?)")
        );
        assert_eq!(hung_up(None), HUNG_UP);
    }
}
