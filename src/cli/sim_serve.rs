//! `axterm sim KIND --pty | --tcp ADDR`: serve a simulated controller to
//! other programs in real time, on a new pseudo-terminal or a TCP socket.
//!
//! The simulator itself runs on virtual time; this loop feeds it the bytes
//! that arrive, advances it by the wall-clock time that passed, and writes
//! back whatever it answered.

use std::io::{self, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::sim::SimulatedController;

/// How long one wait for input may block: the granularity of the
/// simulator's real-time clock, and how quickly a stop request is noticed.
const POLL_INTERVAL: Duration = Duration::from_millis(1);

/// Where to serve.
#[derive(Debug, Clone)]
pub enum Endpoint {
    Pty,
    Tcp(SocketAddr),
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

/// Serve `sim` until `stop` is set. `announce` receives the endpoint's
/// name (the pty path or the bound socket address) once it is ready.
pub fn serve(
    sim: Box<dyn SimulatedController>,
    endpoint: &Endpoint,
    stop: Arc<AtomicBool>,
    announce: &mut dyn FnMut(&str),
) -> io::Result<()> {
    let mut clock = SimClock::new(sim);
    match endpoint {
        Endpoint::Pty => serve_pty(&mut clock, &stop, announce),
        Endpoint::Tcp(addr) => serve_tcp(&mut clock, *addr, &stop, announce),
    }
}

/// A simulator paired with the wall clock.
struct SimClock {
    sim: Box<dyn SimulatedController>,
    last: Instant,
}

impl SimClock {
    fn new(sim: Box<dyn SimulatedController>) -> Self {
        SimClock {
            sim,
            last: Instant::now(),
        }
    }

    /// Let the simulator catch up with the wall clock.
    fn tick(&mut self) {
        let now = Instant::now();
        self.sim.advance(now - self.last);
        self.last = now;
    }

    /// Feed received bytes at the current time and return what it says.
    fn exchange(&mut self, input: &[u8]) -> Vec<u8> {
        self.tick();
        if !input.is_empty() {
            self.sim.feed(input);
        }
        self.sim.take_output()
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
    serialport::SerialPort::set_timeout(&mut master, POLL_INTERVAL).map_err(io::Error::other)?;
    announce(&path);
    // The slave end stays open here for as long as we serve, so that a client
    // closing its own handle does not hang up the master (reads would fail
    // with EIO until someone opened the path again).
    let _keep_open = slave;
    let mut buf = [0u8; 512];
    while !stop.load(Ordering::Relaxed) {
        let received = match master.read(&mut buf) {
            Ok(n) => n,
            Err(e) if is_idle(&e) => 0,
            Err(e) => return Err(e),
        };
        let output = clock.exchange(&buf[..received]);
        if !output.is_empty() {
            master.write_all(&output)?;
        }
    }
    Ok(())
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
            Ok((stream, _)) => serve_tcp_client(clock, stream, stop)?,
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                clock.exchange(&[]);
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
    stream.set_read_timeout(Some(POLL_INTERVAL))?;
    let mut buf = [0u8; 512];
    while !stop.load(Ordering::Relaxed) {
        let received = match stream.read(&mut buf) {
            Ok(0) => return Ok(()),
            Ok(n) => n,
            Err(e) if is_idle(&e) => 0,
            Err(e) if is_hangup(&e) => return Ok(()),
            Err(e) => return Err(e),
        };
        let output = clock.exchange(&buf[..received]);
        if output.is_empty() {
            continue;
        }
        match stream.write_all(&output) {
            Ok(()) => {}
            Err(e) if is_hangup(&e) => return Ok(()),
            Err(e) => return Err(e),
        }
    }
    Ok(())
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
