//! `axterm sim KIND --pty | --tcp ADDR`: serve a simulated controller to
//! other programs in real time, on a new pseudo-terminal or a TCP socket.
//!
//! The simulator itself runs on virtual time; this loop feeds it the bytes
//! that arrive, advances it by the wall-clock time that passed, and writes
//! back whatever it answered, through the same emulated line as the
//! in-process link ([`SimLine`]: the wire's byte time at `--baud`, and the
//! faults of `--fault`). Each wake-up is a real one here, so the line hands
//! the client its bytes a FIFO load at a time ([`UART_FIFO`]), each when its
//! last byte is due, rather than a write per byte: a TMCL transaction at
//! 115200 Bd wakes this loop four times (the request, a final approach,
//! 8 reply bytes, the last one) instead of twenty.

use std::io::{self, BufRead, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use crate::link::sim_line::{Handover, LineOutput, SimLine, UART_FIFO};
use crate::sim::SimulatedController;
use crate::sim::faults::FaultPlan;

/// How long one wait for input may block while nothing is due soon: the
/// granularity of the simulator's real-time clock (it may speak on its own,
/// as when a move ends), and how quickly a stop request is noticed.
const POLL_INTERVAL: Duration = Duration::from_millis(1);

/// A timed wait overshoots more the longer the processor idled (deeper idle
/// states; a virtual machine's halt): measured on the development machine,
/// 17 µs after an 87 µs wait, 37 µs after a 1.5 ms one (p50). So a wait for
/// bytes due ends this much short of them, and a second, short wait lands
/// on the instant: one wake-up more, and 13 µs off the p50 round trip.
const FINAL_WAIT: Duration = Duration::from_micros(100);

/// How finely the simulator's clock is stepped when it catches up with the
/// wall clock: an answer it makes on its own clock (after a switch-over
/// delay, at its next tick) goes on the wire within this of its time, not
/// at the next wake-up of this loop (up to [`POLL_INTERVAL`] later:
/// measured at 19200 Bd on a SIXpack 2, 0.85 ms on the p50 round trip of
/// 14.85 ms on the wire). Under a byte time at 115200 Bd.
const STAMP_STEP: Duration = Duration::from_micros(50);

/// Where to serve.
#[derive(Debug, Clone)]
pub enum Endpoint {
    Pty,
    Tcp(SocketAddr),
}

/// The line between the simulator and its client.
#[derive(Debug, Clone, Default)]
pub struct LineOptions {
    /// Emulate the wire's byte time at this baud rate, both ways.
    pub baud: Option<u32>,
    pub faults: FaultPlan,
}

/// Parse the `--tcp` value of `axterm sim`: `HOST:PORT`, or a bare port
/// meaning loopback.
pub fn parse_listen_address(text: &str) -> Result<SocketAddr, String> {
    if let Ok(port) = text.parse::<u16>() {
        return Ok(SocketAddr::from(([127, 0, 0, 1], port)));
    }
    use std::net::ToSocketAddrs;
    text.to_socket_addrs()
        .map_err(|e| format!("cannot listen on '{text}': {e}"))?
        .next()
        .ok_or_else(|| format!("cannot listen on '{text}': no address"))
}

/// The line on the standard input of `axterm sim` that puts a BREAK on
/// the line (any case).
pub const LINE_BREAK: &str = "BREAK";

/// How long the settings reader waits before trying again to read a
/// terminal it may not read now (the server runs in the background).
const BACKGROUND_RETRY: Duration = Duration::from_millis(250);

/// Read input settings (`IO5=1`), a line each, from `input` on a thread
/// of their own: the served loop applies them as they come
/// ([`SimulatedController::drive_input`]). Blank lines and `#` comments
/// are skipped; bytes that are no UTF-8 are kept as U+FFFD (the setting
/// is then refused by name, and reading goes on). At the end of `input`,
/// or when it cannot be read (no standard input open), the reader ends
/// and nothing more comes; the server goes on. A terminal that may not be
/// read now (EIO: the server is a background job, see
/// [`read_settings_from_stdin`]) is tried again later.
pub fn read_settings<R: Read + Send + 'static>(input: R) -> mpsc::Receiver<String> {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let mut reader = io::BufReader::new(input);
        let mut bytes = Vec::new();
        loop {
            bytes.clear();
            match reader.read_until(b'\n', &mut bytes) {
                Ok(0) => break,
                Ok(_) => {}
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) if is_background_read(&e) => {
                    std::thread::sleep(BACKGROUND_RETRY);
                    continue;
                }
                Err(_) => break,
            }
            let line = String::from_utf8_lossy(&bytes);
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            if tx.send(line.to_string()).is_err() {
                break;
            }
        }
    });
    rx
}

/// [`read_settings`] from standard input. A background job reading its
/// terminal (`axterm sim cmd4cr --pty &` in an interactive shell) would be
/// stopped whole by SIGTTIN; with that signal ignored the read fails with
/// EIO instead, and is tried again until the job is brought to the
/// foreground.
pub fn read_settings_from_stdin() -> mpsc::Receiver<String> {
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to SIG_IGN touches no memory
    // of ours; nothing else in this process handles SIGTTIN.
    unsafe {
        libc::signal(libc::SIGTTIN, libc::SIG_IGN);
    }
    read_settings(io::stdin())
}

fn is_background_read(e: &io::Error) -> bool {
    #[cfg(unix)]
    {
        e.raw_os_error() == Some(libc::EIO)
    }
    #[cfg(not(unix))]
    {
        let _ = e;
        false
    }
}

/// Serve `sim` until `stop` is set. `announce` receives the endpoint's
/// name (the pty path or the bound socket address) once it is ready.
/// Input settings from `settings` are applied between two exchanges, each
/// answered with a line on standard error.
///
/// A `disconnect-after` fault hangs a pseudo-terminal up (the client sees
/// its port vanish, as when a USB adapter is pulled) and ends serving; on
/// TCP it closes the client's connection, and the next client starts a
/// fresh count.
pub fn serve(
    sim: Box<dyn SimulatedController>,
    endpoint: &Endpoint,
    line: &LineOptions,
    settings: mpsc::Receiver<String>,
    stop: Arc<AtomicBool>,
    announce: &mut dyn FnMut(&str),
) -> io::Result<()> {
    if line.baud.is_some() {
        precise_timers();
    }
    let mut clock = SimClock::new(sim, line).driven_by(settings);
    match endpoint {
        Endpoint::Pty => serve_pty(&mut clock, &stop, announce),
        Endpoint::Tcp(addr) => serve_tcp(&mut clock, *addr, &stop, announce),
    }
}

/// A simulator behind its emulated line, on the wall clock.
struct SimClock {
    sim: Box<dyn SimulatedController>,
    line: SimLine,
    epoch: Instant,
    /// Input settings typed while serving.
    settings: Option<mpsc::Receiver<String>>,
}

impl SimClock {
    fn new(sim: Box<dyn SimulatedController>, options: &LineOptions) -> Self {
        SimClock {
            sim,
            line: SimLine::new(options.baud, &options.faults)
                .handing_over(Handover::Fifo(UART_FIFO))
                .stamping_every(STAMP_STEP),
            epoch: Instant::now(),
            settings: None,
        }
    }

    fn driven_by(mut self, settings: mpsc::Receiver<String>) -> Self {
        self.settings = Some(settings);
        self
    }

    /// Apply the settings typed since the last exchange, each answered on
    /// standard error: the simulator has just caught up with the wall
    /// clock, so they act now. A line [`LINE_BREAK`] is no setting but a
    /// BREAK on the line ([`SimulatedController::line_break`]), after the
    /// bytes the client has written so far: a pseudo-terminal or a socket
    /// cannot carry one.
    fn drive_inputs(&mut self) {
        let Some(settings) = &self.settings else {
            return;
        };
        for setting in settings.try_iter() {
            if setting.eq_ignore_ascii_case(LINE_BREAK) {
                self.sim.line_break();
                eprintln!("axterm sim: a BREAK on the line");
                continue;
            }
            match self.sim.drive_input(&setting) {
                Ok(said) => eprintln!("axterm sim: {said}"),
                Err(message) => eprintln!("axterm sim: {message}"),
            }
        }
    }

    /// How long the next wait for input may last.
    fn wait(&self) -> Duration {
        let now = self.epoch.elapsed();
        wait_for(self.line.next_due().map(|due| due.saturating_sub(now)))
    }

    /// Put received bytes on the line, let the simulator catch up with the
    /// wall clock, and return what reached the client (and whether the
    /// line was cut after it).
    fn exchange(&mut self, input: &[u8]) -> LineOutput {
        let now = self.epoch.elapsed();
        if !input.is_empty() {
            self.line.host_wrote(now, input);
        }
        let out = self.line.run(self.sim.as_mut(), now);
        self.drive_inputs();
        out
    }

    /// A new client on the same line.
    fn reconnect(&mut self) {
        self.line.reconnect();
    }
}

/// How long to wait for input when the line has something due `left` from
/// now (`None`: nothing on its way). Never past the instant it is due, so
/// that nothing reaches the client late for want of a wake-up; while it is
/// more than two [`POLL_INTERVAL`]s away, the clock ticks at that interval.
fn wait_for(left: Option<Duration>) -> Duration {
    match left {
        Some(left) if left > 2 * POLL_INTERVAL => POLL_INTERVAL,
        Some(left) if left > FINAL_WAIT => left - FINAL_WAIT,
        Some(left) => left,
        None => POLL_INTERVAL,
    }
}

/// An emulated byte lasts 87 µs at 115200 Bd, less than Linux's default
/// 50 µs timer slack added to every timed wait: ask for none on this
/// thread, so that the emulated wire keeps its rate.
fn precise_timers() {
    #[cfg(target_os = "linux")]
    // SAFETY: PR_SET_TIMERSLACK only changes this thread's timer slack; the
    // call takes plain integers and touches no memory of ours.
    unsafe {
        libc::prctl(libc::PR_SET_TIMERSLACK, 1 as libc::c_ulong);
    }
}

fn serve_pty(
    clock: &mut SimClock,
    stop: &AtomicBool,
    announce: &mut dyn FnMut(&str),
) -> io::Result<()> {
    let (mut master, slave) = serialport::TTYPort::pair().map_err(io::Error::other)?;
    let path = serialport::SerialPort::name(&slave)
        .ok_or_else(|| io::Error::other("the pseudo-terminal has no name"))?;
    announce(&path);
    // The slave end stays open here for as long as we serve, so that a client
    // closing its own handle does not hang up the master (reads would fail
    // with EIO until someone opened the path again).
    let keep_open = slave;
    let mut settings = line_settings(&keep_open);
    let mut buf = [0u8; 512];
    while !stop.load(Ordering::Relaxed) {
        // A pseudo-terminal carries the termios its client sets (a serial
        // port opened at a baud rate, ser2net told one over RFC 2217):
        // say so when it changes, as a real module's line would notice.
        // Not an "axterm sim: " answer: those answer typed settings.
        let now = line_settings(&keep_open);
        if now != settings {
            if let Some(text) = &now {
                eprintln!("{LINE_NOTICE}{text}");
            }
            settings = now;
        }
        serialport::SerialPort::set_timeout(&mut master, clock.wait()).map_err(io::Error::other)?;
        let received = match master.read(&mut buf) {
            Ok(n) => n,
            Err(e) if is_idle(&e) => 0,
            Err(e) => return Err(e),
        };
        let out = clock.exchange(buf.get(..received).unwrap_or_default());
        if !out.to_host.is_empty() {
            master.write_all(&out.to_host)?;
        }
        if let Some(reason) = out.cut {
            // Closing both ends hangs the client's side up.
            drop(keep_open);
            drop(master);
            eprintln!("axterm sim: {reason}: the pseudo-terminal is gone");
            return Ok(());
        }
    }
    Ok(())
}

/// How `axterm sim --pty` notes on stderr that its client changed the
/// pseudo-terminal's line settings, followed by them ("19200 Bd 8N1").
pub const LINE_NOTICE: &str = "axterm sim line: the client set it to ";

/// The line settings on a pseudo-terminal, as "19200 Bd 8N1".
fn line_settings(tty: &serialport::TTYPort) -> Option<String> {
    use serialport::{DataBits, Parity, SerialPort, StopBits};
    let baud = tty.baud_rate().ok()?;
    let bits = match tty.data_bits().ok()? {
        DataBits::Five => 5,
        DataBits::Six => 6,
        DataBits::Seven => 7,
        DataBits::Eight => 8,
    };
    let parity = match tty.parity().ok()? {
        Parity::None => 'N',
        Parity::Odd => 'O',
        Parity::Even => 'E',
    };
    let stop = match tty.stop_bits().ok()? {
        StopBits::One => 1,
        StopBits::Two => 2,
    };
    Some(format!("{baud} Bd {bits}{parity}{stop}"))
}

fn serve_tcp(
    clock: &mut SimClock,
    addr: SocketAddr,
    stop: &AtomicBool,
    announce: &mut dyn FnMut(&str),
) -> io::Result<()> {
    let listener = TcpListener::bind(addr)?;
    listener.set_nonblocking(true)?;
    announce(&listener.local_addr()?.to_string());
    // One client at a time, as on a serial line; the simulator (and any
    // motion in progress) lives on between clients.
    while !stop.load(Ordering::Relaxed) {
        match listener.accept() {
            Ok((stream, _)) => {
                // accept(2) hands out blocking sockets on Linux but not
                // everywhere; the client loop relies on read timeouts.
                stream.set_nonblocking(false)?;
                clock.reconnect();
                serve_tcp_client(clock, stream, stop)?;
            }
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                let _ = clock.exchange(&[]);
                std::thread::sleep(POLL_INTERVAL);
            }
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

fn serve_tcp_client(
    clock: &mut SimClock,
    mut stream: TcpStream,
    stop: &AtomicBool,
) -> io::Result<()> {
    stream.set_nodelay(true)?;
    let mut buf = [0u8; 512];
    while !stop.load(Ordering::Relaxed) {
        let received = match read_within(&mut stream, &mut buf, clock.wait()) {
            Ok(0) => return Ok(()),
            Ok(n) => n,
            Err(e) if is_idle(&e) => 0,
            Err(e) if is_hangup(&e) => return Ok(()),
            Err(e) => return Err(e),
        };
        let out = clock.exchange(buf.get(..received).unwrap_or_default());
        if !out.to_host.is_empty() {
            match stream.write_all(&out.to_host) {
                Ok(()) => {}
                Err(e) if is_hangup(&e) => return Ok(()),
                Err(e) => return Err(e),
            }
        }
        if let Some(reason) = out.cut {
            eprintln!("axterm sim: {reason}: closing the connection");
            let _ = stream.shutdown(std::net::Shutdown::Both);
            return Ok(());
        }
    }
    Ok(())
}

/// Read what the client sent, waiting at most `timeout` for it; an idle
/// error when nothing came.
///
/// A socket's read timeout (SO_RCVTIMEO) counts in scheduler ticks (4 ms
/// at 250 Hz), so at 115200 Bd every wait for a byte due would end
/// milliseconds late; ppoll takes the timeout to the nanosecond.
#[cfg(target_os = "linux")]
fn read_within(stream: &mut TcpStream, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
    use std::os::fd::AsRawFd;
    if !wait_readable(stream.as_raw_fd(), timeout)? {
        return Err(io::ErrorKind::TimedOut.into());
    }
    stream.read(buf)
}

#[cfg(not(target_os = "linux"))]
fn read_within(stream: &mut TcpStream, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
    // A zero timeout means "block forever" to the socket API.
    stream.set_read_timeout(Some(timeout.max(Duration::from_micros(1))))?;
    stream.read(buf)
}

/// Wait until `fd` has something to read (data, or the other end gone) or
/// `timeout` has passed; true when it has.
#[cfg(target_os = "linux")]
fn wait_readable(fd: std::os::fd::RawFd, timeout: Duration) -> io::Result<bool> {
    let mut pollfd = libc::pollfd {
        fd,
        events: libc::POLLIN,
        revents: 0,
    };
    let timeout = libc::timespec {
        tv_sec: libc::time_t::try_from(timeout.as_secs()).unwrap_or(libc::time_t::MAX),
        // Below a billion: fits a c_long of any width.
        tv_nsec: timeout.subsec_nanos() as libc::c_long,
    };
    // SAFETY: one valid pollfd, a valid timespec, no signal mask; all live
    // for the whole call.
    let ready = unsafe { libc::ppoll(&mut pollfd, 1, &timeout, std::ptr::null()) };
    if ready < 0 {
        let e = io::Error::last_os_error();
        return if e.kind() == io::ErrorKind::Interrupted {
            Ok(false)
        } else {
            Err(e)
        };
    }
    Ok(ready > 0)
}

fn is_idle(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
    )
}

fn is_hangup(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::ConnectionReset
            | io::ErrorKind::ConnectionAborted
            | io::ErrorKind::BrokenPipe
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    const US: Duration = Duration::from_micros(1);

    #[test]
    fn a_wait_for_bytes_due_ends_short_of_them_then_on_the_instant() {
        // A reply due in 1562.5 µs (18 bytes at 115200 Bd): a long wait to
        // 100 µs before it, then a short one to the instant.
        let due = Duration::from_nanos(1_562_500);
        assert_eq!(wait_for(Some(due)), due - FINAL_WAIT);
        assert_eq!(wait_for(Some(FINAL_WAIT)), FINAL_WAIT);
        assert_eq!(wait_for(Some(37 * US)), 37 * US);
        assert_eq!(wait_for(Some(Duration::ZERO)), Duration::ZERO);
    }

    #[test]
    fn the_clock_ticks_while_nothing_is_due_soon() {
        assert_eq!(wait_for(None), POLL_INTERVAL);
        assert_eq!(wait_for(Some(Duration::from_millis(19))), POLL_INTERVAL);
        assert_eq!(
            wait_for(Some(2 * POLL_INTERVAL)),
            2 * POLL_INTERVAL - FINAL_WAIT
        );
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_socket_read_waits_for_the_client_or_the_timeout() {
        let listener = TcpListener::bind("127.0.0.1:0").expect("listens");
        let mut client =
            TcpStream::connect(listener.local_addr().expect("bound")).expect("connects");
        let (mut served, _) = listener.accept().expect("accepts");
        let mut buf = [0u8; 16];
        let idle = read_within(&mut served, &mut buf, Duration::ZERO).expect_err("nothing sent");
        assert!(is_idle(&idle), "{idle:?}");
        client.write_all(b"GAP").expect("sends");
        // Returns as soon as the bytes are there; the timeout only bounds a
        // broken test.
        let n = read_within(&mut served, &mut buf, Duration::from_secs(10)).expect("reads");
        assert_eq!(buf.get(..n), Some(&b"GAP"[..]));
        drop(client);
        let closed = read_within(&mut served, &mut buf, Duration::from_secs(10)).expect("reads");
        assert_eq!(closed, 0, "the client's close reads as the end");
    }

    #[test]
    fn settings_are_read_a_line_each_until_the_input_ends() {
        let typed =
            io::Cursor::new(b"IO5=1\n\n  # a comment\nIO\xff=1\n AI1=1650 \r\nEMG=1".to_vec());
        let read: Vec<String> = read_settings(typed).iter().collect();
        assert_eq!(read, ["IO5=1", "IO\u{fffd}=1", "AI1=1650", "EMG=1"]);
    }

    #[test]
    fn a_setting_acts_on_the_served_simulator_at_the_next_exchange() {
        let kind = crate::families::find_kind("cmd4cr").expect("registered");
        let sim = (kind.build)(&crate::sim::SimOptions::default());
        let (tx, rx) = mpsc::channel();
        let mut clock = SimClock::new(sim, &LineOptions::default()).driven_by(rx);
        assert_eq!(clock.exchange(b"@01IO5\r").to_host, b"0\r");
        tx.send("IO5=1".to_string()).expect("the clock listens");
        tx.send("IO5=7".to_string())
            .expect("a bad one is only reported");
        let _ = clock.exchange(&[]);
        assert_eq!(clock.exchange(b"@01IO5\r").to_host, b"1\r");
        drop(tx);
        // No more settings: serving goes on.
        assert_eq!(clock.exchange(b"@01IO\r").to_host, b"16\r");
    }

    /// Counts the BREAKs it sees and the bytes it is fed.
    #[derive(Default)]
    struct BreakCounter {
        breaks: std::sync::Arc<std::sync::atomic::AtomicUsize>,
        fed: Vec<u8>,
    }

    impl SimulatedController for BreakCounter {
        fn feed(&mut self, bytes: &[u8]) {
            self.fed.extend_from_slice(bytes);
        }
        fn advance(&mut self, _: Duration) {}
        fn take_output(&mut self) -> Vec<u8> {
            std::mem::take(&mut self.fed)
        }
        fn help(&self) -> String {
            "counts breaks".into()
        }
        fn line_break(&mut self) {
            self.breaks.fetch_add(1, Ordering::SeqCst);
        }
    }

    #[test]
    fn a_break_line_puts_a_break_on_the_line_after_the_bytes_so_far() {
        let breaks = Arc::new(std::sync::atomic::AtomicUsize::new(0));
        let sim = BreakCounter {
            breaks: Arc::clone(&breaks),
            fed: Vec::new(),
        };
        let (tx, rx) = mpsc::channel();
        let mut clock = SimClock::new(Box::new(sim), &LineOptions::default()).driven_by(rx);
        assert_eq!(clock.exchange(b"ab").to_host, b"ab");
        tx.send("break".to_string()).expect("the clock listens");
        tx.send("BREAK".to_string()).expect("the clock listens");
        let _ = clock.exchange(&[]);
        assert_eq!(breaks.load(Ordering::SeqCst), 2);
        // Not a setting: the controller's drive_input never sees it.
        tx.send("BREAKS".to_string()).expect("the clock listens");
        let _ = clock.exchange(&[]);
        assert_eq!(breaks.load(Ordering::SeqCst), 2);
    }

    #[test]
    fn bare_port_means_loopback() {
        assert_eq!(
            parse_listen_address("4001").unwrap(),
            "127.0.0.1:4001".parse().unwrap()
        );
        assert_eq!(
            parse_listen_address("0.0.0.0:4002").unwrap(),
            "0.0.0.0:4002".parse().unwrap()
        );
        assert!(parse_listen_address("no-such-host-name.invalid:x").is_err());
    }
}
