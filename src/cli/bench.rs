//! `axterm bench CONNECTION [--requests N]`: how fast the link and the
//! device task are, measured on the same link in one run:
//!
//! 1. the floor: a bare blocking write/read loop with no device task (a
//!    serial port opened with serialport, a std TcpStream, or the
//!    simulator called directly);
//! 2. the device task's round trip for a user read (p50/p99);
//! 3. status polling with nothing else waiting (polls per second);
//! 4. a user read's round trip while polling saturates the link (p50/p99),
//!    each read arriving at a different moment of the poll in flight.
//!
//! The request is the family's first fast status query (TMCL `GAP 1, 0`),
//! the kind a poll repeats most; its first of any kind if none is fast.
//!
//! A request that gets no answer (a timeout, a garbled answer, on a lossy
//! line) is a fault: counted beside the figures of its measurement, which
//! go on with the next request. Only a measurement that got no answer at
//! all ends the run (exit 1).
//!
//! Where the link has a baud rate, the wire time of one transaction (its
//! request and answer bytes) is the ceiling the figures are held against:
//! polling's share of that rate, and the device task's fastest round trip,
//! which a faithful line never beats.

use std::io::{ErrorKind, Read, Write};
use std::net::TcpStream;
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::Args;
use serde_json::{Value, json};
use tokio::sync::mpsc;

use super::connection::{Target, run_to_exit};
use super::output::Format;
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::device::{
    Answer, DeviceError, Expect, PollItem, PollPlan, PollSink, Retry, Transaction, default_timeout,
};
use crate::link::{LinkSpec, SharedSim};
use crate::protocol::console::{Answering, PreparedLine};
use crate::protocol::wire::{Framer, ReplyRule, Verdict, WireFormat};
use crate::session::Session;

#[derive(Debug, Clone, Args)]
pub struct BenchArgs {
    /// Requests per measurement.
    #[arg(long, default_value_t = 500)]
    pub requests: usize,
    /// text: a table; json: one object.
    #[arg(long, value_enum, default_value_t)]
    pub format: Format,
}

/// Round trips of one measurement.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Figures {
    /// Each answered request's round trip.
    pub samples: Vec<Duration>,
    /// From the first request to the last answer.
    pub total: Duration,
    /// Requests that got no answer (timed out, garbled, refused).
    pub faults: usize,
}

impl Figures {
    /// The `q`-quantile (0.0..=1.0) by nearest rank.
    pub fn quantile(&self, q: f64) -> Option<Duration> {
        let mut sorted = self.samples.clone();
        sorted.sort();
        let last = sorted.len().checked_sub(1)?;
        let rank = ((q.clamp(0.0, 1.0) * sorted.len() as f64).ceil() as usize).clamp(1, last + 1);
        sorted.get(rank - 1).copied()
    }

    /// Completed requests per second over the whole run.
    pub fn per_second(&self, count: usize) -> Option<f64> {
        let seconds = self.total.as_secs_f64();
        (seconds > 0.0).then(|| count as f64 / seconds)
    }
}

/// One transaction on a wire with a baud rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WireTime {
    /// Request and answer bytes.
    pub bytes: usize,
    pub byte_time: Duration,
    /// How long the module waits before it answers
    /// ([`WireFormat::turnaround`]).
    pub turnaround: Duration,
}

impl WireTime {
    /// The bytes' time on the wire and the module's wait before it
    /// answers: no round trip can be shorter.
    pub fn round_trip(&self) -> Duration {
        self.byte_time
            .saturating_mul(u32::try_from(self.bytes).unwrap_or(u32::MAX))
            .saturating_add(self.turnaround)
    }

    /// Transactions per second the wire carries, back to back.
    pub fn per_second(&self) -> Option<f64> {
        let seconds = self.round_trip().as_secs_f64();
        (seconds > 0.0).then(|| 1.0 / seconds)
    }
}

/// Every measurement of a run.
#[derive(Debug, Clone, Default)]
pub struct Report {
    pub link: String,
    pub line: String,
    pub requests: usize,
    pub bare: Option<Figures>,
    pub bare_note: String,
    pub device: Figures,
    pub polls: Figures,
    pub user_while_polling: Figures,
    /// The wire time of one transaction, when the link has a baud rate.
    pub wire: Option<WireTime>,
}

fn micros(d: Option<Duration>) -> Value {
    d.map_or(Value::Null, |d| json!(d.as_secs_f64() * 1e6))
}

fn figures_json(f: &Figures) -> Value {
    json!({
        "p50_us": micros(f.quantile(0.5)),
        "p99_us": micros(f.quantile(0.99)),
        "min_us": micros(f.quantile(0.0)),
        "per_second": f.per_second(f.samples.len()),
        "count": f.samples.len(),
        "faults": f.faults,
    })
}

impl Report {
    /// Polling's rate as a share (0..1) of what the wire carries.
    pub fn polling_share_of_wire(&self) -> Option<f64> {
        let wire = self.wire?.per_second()?;
        Some(self.polls.per_second(self.polls.samples.len())? / wire)
    }

    /// Requests of every measurement that got no answer.
    pub fn faults(&self) -> usize {
        let bare = self.bare.as_ref().map_or(0, |f| f.faults);
        bare + self.device.faults + self.polls.faults + self.user_while_polling.faults
    }

    /// A user read's p99 while polling, in bare p99s.
    pub fn user_p99_over_bare(&self) -> Option<f64> {
        let bare = self.bare.as_ref()?.quantile(0.99)?.as_secs_f64();
        let user = self.user_while_polling.quantile(0.99)?.as_secs_f64();
        (bare > 0.0).then(|| user / bare)
    }

    pub fn to_json(&self) -> Value {
        json!({
            "link": self.link,
            "line": self.line,
            "requests": self.requests,
            "wire": self.wire.map(|w| json!({
                "bytes": w.bytes,
                "turnaround_us": micros(Some(w.turnaround)),
                "round_trip_us": micros(Some(w.round_trip())),
                "per_second": w.per_second(),
            })),
            "bare": self.bare.as_ref().map(figures_json),
            "bare_note": self.bare_note,
            "device": figures_json(&self.device),
            "polling": {
                "per_second": self.polls.per_second(self.polls.samples.len()),
                "share_of_wire": self.polling_share_of_wire(),
                "count": self.polls.samples.len(),
                "faults": self.polls.faults,
            },
            "user_while_polling": figures_json(&self.user_while_polling),
            "user_p99_over_bare_p99": self.user_p99_over_bare(),
            "faults": self.faults(),
        })
    }

    pub fn to_table(&self) -> String {
        let show = |d: Option<Duration>| {
            d.map_or_else(
                || "-".to_string(),
                |d| format!("{:.1} µs", d.as_secs_f64() * 1e6),
            )
        };
        let rate = |r: Option<f64>| r.map_or_else(|| "-".to_string(), |r| format!("{r:.0}"));
        let row = |name: &str, f: &Figures, quantiles: bool| {
            let (p50, p99) = if quantiles {
                (show(f.quantile(0.5)), show(f.quantile(0.99)))
            } else {
                ("-".into(), "-".into())
            };
            format!(
                "{name:<34}{p50:>12}{p99:>12}{:>12}{:>8}\n",
                rate(f.per_second(f.samples.len())),
                f.faults
            )
        };
        let mut out = format!(
            "axterm bench: {}, {} × {}\n{:<34}{:>12}{:>12}{:>12}{:>8}\n",
            self.link, self.requests, self.line, "", "p50", "p99", "per second", "faults"
        );
        if let Some(wire) = self.wire {
            let name = if wire.turnaround.is_zero() {
                format!("wire time alone ({} bytes)", wire.bytes)
            } else {
                format!(
                    "wire time alone ({} bytes + {} ms)",
                    wire.bytes,
                    wire.turnaround.as_millis()
                )
            };
            let time = show(Some(wire.round_trip()));
            out.push_str(&format!(
                "{name:<34}{time:>12}{time:>12}{:>12}{:>8}\n",
                rate(wire.per_second()),
                "-"
            ));
        }
        match &self.bare {
            Some(f) => out.push_str(&row("bare write/read loop", f, true)),
            None => out.push_str(&format!("{:<34}{:>12}\n", "bare write/read loop", "-")),
        }
        out.push_str(&row("device task round trip", &self.device, true));
        out.push_str(&row("status polling (saturating)", &self.polls, false));
        out.push_str(&row(
            "user read while polling",
            &self.user_while_polling,
            true,
        ));
        out.push_str(&format!("bare loop: {}\n", self.bare_note));
        let mut against = Vec::new();
        if let Some(share) = self.polling_share_of_wire() {
            against.push(format!(
                "polling at {:.1}% of the wire's rate",
                share * 100.0
            ));
        }
        // The device task always goes over the link; the bare loop of an
        // in-process simulator does not.
        if let (Some(wire), Some(fastest)) = (self.wire, self.device.quantile(0.0)) {
            against.push(format!(
                "fastest round trip {} (the wire's {})",
                show(Some(fastest)),
                show(Some(wire.round_trip()))
            ));
        }
        if let Some(times) = self.user_p99_over_bare() {
            against.push(format!(
                "user read p99 while polling {times:.2} × the bare p99"
            ));
        }
        if !against.is_empty() {
            out.push_str(&against.join("; "));
            out.push('\n');
        }
        let faults = self.faults();
        if faults > 0 {
            out.push_str(&format!(
                "{faults} request{} got no answer (timed out or garbled): counted as faults, \
                 left out of the figures\n",
                if faults == 1 { "" } else { "s" }
            ));
        }
        out
    }
}

pub fn run(connection: &ConnectionArgs, args: &BenchArgs) -> i32 {
    let target = match Target::resolve(connection) {
        Ok(target) => target,
        Err(message) => {
            eprintln!("axterm bench: {message}");
            return EXIT_USAGE;
        }
    };
    if args.requests == 0 {
        eprintln!("axterm bench: --requests must be at least 1");
        return EXIT_USAGE;
    }
    let console = target.family.console;
    let queries = console.status_queries(target.address);
    let Some(line) = queries
        .iter()
        .find(|q| q.fast)
        .or_else(|| queries.first())
        .map(|q| q.line.clone())
    else {
        eprintln!(
            "axterm bench: the {} family has no status query to time",
            target.family.name
        );
        return EXIT_USAGE;
    };
    // The floor first: a serial port can have only one owner at a time.
    let wire = console.wire();
    // As long as the device task would wait for an answer.
    let answer_timeout = target
        .options
        .device
        .timeout
        .unwrap_or_else(|| default_timeout(target.spec.byte_time(), line.bytes.len()));
    let (bare, bare_note, wire_bytes) = match bare_loop(
        &target.spec,
        wire.as_ref(),
        &line,
        args.requests,
        answer_timeout,
    ) {
        Ok((bare, note)) => (Some(bare.figures), note, Some(bare.bytes)),
        Err(BareError::Open(message)) => {
            eprintln!("axterm bench: {message}");
            return EXIT_CONNECTION;
        }
        Err(BareError::Exchange(message)) => (None, message, None),
    };
    let byte_time = target.spec.byte_time();
    let (requests, format) = (args.requests, args.format);
    run_to_exit("bench", async move {
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm bench: {e}");
                return EXIT_CONNECTION;
            }
        };
        let turnaround = target.family.console.wire().turnaround();
        let measured = measure(&session, &line, requests, byte_time, wire_bytes, turnaround);
        let report = match measured.await {
            Ok(mut report) => {
                report.bare = bare;
                report.bare_note = bare_note;
                report.link = target.spec.describe();
                report
            }
            Err(message) => {
                eprintln!("axterm bench: {message}");
                return EXIT_DEVICE;
            }
        };
        match format {
            Format::Text => print!("{}", report.to_table()),
            Format::Json => println!("{}", report.to_json()),
        }
        EXIT_OK
    })
}

/// The device-task measurements (2–4).
/// `wire_bytes`: a transaction's bytes as the bare loop counted them.
async fn measure(
    session: &Session,
    line: &PreparedLine,
    requests: usize,
    byte_time: Option<Duration>,
    wire_bytes: Option<usize>,
    turnaround: Duration,
) -> Result<Report, String> {
    let mut device = Figures::default();
    let mut transaction_bytes = 0;
    let mut last_fault = String::new();
    let start = Instant::now();
    for _ in 0..requests {
        let sent = Instant::now();
        match session.execute(line).await {
            Ok(result) => {
                device.samples.push(sent.elapsed());
                transaction_bytes = wire_bytes_of(&result.request, &result.reply);
            }
            Err(error) => {
                device.faults += 1;
                last_fault = error.to_string();
            }
        }
    }
    device.total = start.elapsed();
    if device.samples.is_empty() {
        return Err(format!(
            "no request was answered ({} faults; the last: {last_fault})",
            device.faults
        ));
    }
    // The answer's frames may leave out a terminator that was on the wire:
    // the bare loop's count is the better one.
    let wire = byte_time.map(|byte_time| WireTime {
        bytes: wire_bytes.unwrap_or(transaction_bytes),
        byte_time,
        turnaround,
    });

    // Polling with every item due at once, as often as the link allows.
    let (done_tx, mut done) = mpsc::unbounded_channel();
    let expect = match &line.answering {
        Answering::Reply(rule) | Answering::MaybeReply(rule) => Expect::Reply(Arc::clone(rule)),
        Answering::Nothing | Answering::Later { .. } => Expect::Nothing,
    };
    let item = PollItem {
        transaction: Transaction {
            bytes: line.bytes.clone(),
            expect,
            retry: Retry::Never,
            timeout: None,
            hold: None,
            cut_short: None,
        },
        every: Duration::ZERO,
        urgent: false,
    };
    session.device().set_poll_plan(Some(PollPlan {
        items: vec![item],
        sink: Box::new(TimingSink {
            done: done_tx,
            last: Instant::now(),
        }),
    }));
    let mut polls = Figures::default();
    let start = Instant::now();
    while polls.samples.len() + polls.faults < requests {
        match done.recv().await {
            Some(Ok(sample)) => polls.samples.push(sample),
            Some(Err(_)) => polls.faults += 1,
            None => return Err("the device task ended".into()),
        }
    }
    polls.total = start.elapsed();
    // Polling goes on: a user read now waits for at most the poll in flight.
    // A technician's command arrives at any moment of a poll, not right
    // after one has started (as a read issued the instant the previous one
    // returned would), so each read starts after a spread of fractions of
    // a round trip.
    let round_trip = device.quantile(0.5).unwrap_or_default();
    let user_while_polling = {
        let mut figures = Figures::default();
        let start = Instant::now();
        for i in 0..requests {
            let offset = round_trip.mul_f64(arrival_fraction(i));
            let _ = tokio::task::spawn_blocking(move || std::thread::sleep(offset)).await;
            let sent = Instant::now();
            match session.execute(line).await {
                Ok(_) => figures.samples.push(sent.elapsed()),
                Err(_) => figures.faults += 1,
            }
        }
        figures.total = start.elapsed();
        figures
    };
    session.device().set_poll_plan(None);
    Ok(Report {
        line: line.canonical.clone(),
        requests,
        device,
        polls,
        user_while_polling,
        wire,
        ..Report::default()
    })
}

/// The i-th of an evenly spread sequence in 0..1 (the golden-ratio
/// sequence): where in a poll the i-th user read arrives.
fn arrival_fraction(i: usize) -> f64 {
    const GOLDEN: f64 = 0.618_033_988_749_894_9;
    (i as f64 * GOLDEN).fract()
}

/// Reports each poll's completion to the bench: the time since the one
/// before, or the fault.
struct TimingSink {
    done: mpsc::UnboundedSender<Result<Duration, DeviceError>>,
    last: Instant,
}

impl PollSink for TimingSink {
    fn record(&mut self, _index: usize, result: Result<&Answer, &DeviceError>) {
        let now = Instant::now();
        let sample = now - self.last;
        self.last = now;
        let _ = self.done.send(result.map(|_| sample).map_err(Clone::clone));
    }
}

/// What the bare loop measured.
struct Bare {
    figures: Figures,
    /// One transaction's bytes as they crossed the link, request and
    /// answer; where the answer starts with the echo of the request (MCCL:
    /// every character echoed as it arrives, on a full-duplex line), the
    /// request travels under its echo, and only the answer and one byte
    /// more are counted.
    bytes: usize,
}

/// A transaction's bytes on the wire: `request` and `answer` one after the
/// other, or, when `answer` starts with the echo of `request` (without
/// its line end), the answer and the one byte the echo trails the request
/// by (full duplex).
fn wire_bytes_of(request: &[u8], answer: &[u8]) -> usize {
    let line = request.trim_ascii_end();
    if !line.is_empty() && answer.starts_with(line) {
        answer.len() + 1
    } else {
        request.len() + answer.len()
    }
}

enum BareError {
    /// The link could not be opened at all.
    Open(String),
    /// Opened, but the loop did not complete.
    Exchange(String),
}

/// Measurement 1: request and answer with no device task in between,
/// waiting at most `answer_timeout` for an answer (then a fault).
fn bare_loop(
    spec: &LinkSpec,
    wire: &dyn WireFormat,
    line: &PreparedLine,
    requests: usize,
    answer_timeout: Duration,
) -> Result<(Bare, String), BareError> {
    let rule = match &line.answering {
        Answering::Reply(rule) | Answering::MaybeReply(rule) => Arc::clone(rule),
        Answering::Nothing | Answering::Later { .. } => {
            return Err(BareError::Exchange(
                "the timed line expects no answer of its own".into(),
            ));
        }
    };
    let answered = |bare: Bare, note: &str| (bare, note.to_string());
    match spec {
        LinkSpec::Serial { path, baud } => {
            let mut port = serialport::new(path, *baud)
                .timeout(answer_timeout)
                .open()
                .map_err(|e| BareError::Open(format!("cannot open {}: {e}", spec.describe())))?;
            blocking_loop(&mut port, wire, rule.as_ref(), &line.bytes, requests)
                .map(|bare| answered(bare, "serialport"))
                .map_err(BareError::Exchange)
        }
        LinkSpec::Tcp { address, .. } => {
            let mut stream = TcpStream::connect(address)
                .map_err(|e| BareError::Open(format!("cannot open {}: {e}", spec.describe())))?;
            let _ = stream.set_nodelay(true);
            let _ = stream.set_read_timeout(Some(answer_timeout));
            blocking_loop(&mut stream, wire, rule.as_ref(), &line.bytes, requests)
                .map(|bare| answered(bare, "TcpStream"))
                .map_err(BareError::Exchange)
        }
        // The bare loop writes and reads raw bytes; Telnet's escaping and
        // the RFC 2217 opening live in the link, so only the link is timed.
        LinkSpec::Rfc2217 { .. } => Err(BareError::Exchange(
            "no bare loop over RFC 2217 (it needs the link's Telnet handling)".into(),
        )),
        LinkSpec::Sim { sim, .. } => sim_loop(sim, wire, rule.as_ref(), &line.bytes, requests)
            .map(|bare| answered(bare, "simulator called directly, no wire time"))
            .map_err(BareError::Exchange),
    }
}

/// Write a request, read until the rule accepts an answer, repeat. A read
/// that times out (the stream's read timeout) is a fault: the request is
/// given up and the next one goes.
fn blocking_loop<S: Read + Write>(
    stream: &mut S,
    wire: &dyn WireFormat,
    rule: &dyn ReplyRule,
    request: &[u8],
    requests: usize,
) -> Result<Bare, String> {
    let mut framer = wire.framer();
    let mut figures = Figures::default();
    let mut buffer = [0u8; 256];
    let mut bytes = 0;
    let mut last_fault = String::new();
    let start = Instant::now();
    for _ in 0..requests {
        let sent = Instant::now();
        stream
            .write_all(request)
            .map_err(|e| format!("write failed: {e}"))?;
        let mut answer = Vec::new();
        let mut accepted = Vec::new();
        let answered = 'answer: loop {
            let n = match stream.read(&mut buffer) {
                Ok(0) => return Err("the other end closed the link".into()),
                Ok(n) => n,
                Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::WouldBlock) => {
                    last_fault = format!("no answer: {e}");
                    break 'answer false;
                }
                Err(e) => return Err(format!("reading failed: {e}")),
            };
            let read = buffer.get(..n).unwrap_or_default();
            answer.extend_from_slice(read);
            for frame in framer.push(read) {
                match rule.examine(&accepted, &frame) {
                    // The bare loop does not wait for a quiet guard.
                    Verdict::Complete | Verdict::CompleteIfQuiet => break 'answer true,
                    Verdict::Continue => accepted.push(frame),
                    Verdict::NotMine => {}
                }
            }
        };
        if answered {
            figures.samples.push(sent.elapsed());
            bytes = wire_bytes_of(request, &answer);
        } else {
            figures.faults += 1;
            framer.discard_pending();
        }
    }
    figures.total = start.elapsed();
    if figures.samples.is_empty() {
        return Err(last_fault);
    }
    Ok(Bare { figures, bytes })
}

/// Milliseconds of its own clock a simulator gets to answer in the bare
/// loop.
const SIM_ANSWER_TICKS: usize = 1000;

/// The simulator fed and read directly, no link, no clock.
fn sim_loop(
    sim: &SharedSim,
    wire: &dyn WireFormat,
    rule: &dyn ReplyRule,
    request: &[u8],
    requests: usize,
) -> Result<Bare, String> {
    let mut framer: Box<dyn Framer> = wire.framer();
    let mut bytes = 0;
    let mut figures = Figures::default();
    let mut sim = sim
        .lock()
        .map_err(|_| "the simulator is broken".to_string())?;
    let start = Instant::now();
    for _ in 0..requests {
        let sent = Instant::now();
        sim.feed(request);
        let mut output = Vec::new();
        let mut accepted = Vec::new();
        // A controller that works on a clock of its own (MCCL's 1 kHz
        // tick) may answer only once it has run a moment.
        let mut complete = false;
        for _ in 0..SIM_ANSWER_TICKS {
            let came = sim.take_output();
            output.extend_from_slice(&came);
            for frame in framer.push(&came) {
                match rule.examine(&accepted, &frame) {
                    Verdict::Complete | Verdict::CompleteIfQuiet => complete = true,
                    Verdict::Continue => accepted.push(frame),
                    Verdict::NotMine => {}
                }
            }
            if complete {
                break;
            }
            sim.advance(Duration::from_millis(1));
        }
        bytes = wire_bytes_of(request, &output);
        if !complete {
            return Err("the simulator did not answer".into());
        }
        figures.samples.push(sent.elapsed());
    }
    figures.total = start.elapsed();
    Ok(Bare { figures, bytes })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figures(micros: &[u64]) -> Figures {
        Figures {
            samples: micros.iter().map(|&m| Duration::from_micros(m)).collect(),
            total: Duration::from_secs(1),
            faults: 0,
        }
    }

    #[test]
    fn an_echo_sent_back_as_the_request_arrives_overlaps_it() {
        // TMCL: the reply comes after the request.
        assert_eq!(wire_bytes_of(&[1; 9], &[2; 9]), 18);
        // MCCL: the echo of `1TP\r` comes back while it is sent.
        assert_eq!(wire_bytes_of(b"1TP\r", b"1TP\r\n01 5\r\n>"), 13);
    }

    #[test]
    fn user_reads_arrive_spread_over_a_poll() {
        let fractions: Vec<f64> = (0..1000).map(arrival_fraction).collect();
        assert!(fractions.iter().all(|f| (0.0..1.0).contains(f)));
        // Every tenth of a poll gets its share of arrivals.
        for tenth in 0..10 {
            let low = f64::from(tenth) / 10.0;
            let count = fractions
                .iter()
                .filter(|f| (low..low + 0.1).contains(*f))
                .count();
            assert!((90..=110).contains(&count), "tenth {tenth}: {count}");
        }
    }

    #[test]
    fn a_modules_wait_before_it_answers_is_wire_time_too() {
        // SIXpack 2 at 19200 Bd: 9 bytes out, 8 back, after the 6 ms
        // switch-over delay (§6.1.1).
        let wire = WireTime {
            bytes: 17,
            byte_time: crate::link::byte_time(19_200),
            turnaround: Duration::from_millis(6),
        };
        assert_eq!(
            wire.round_trip(),
            Duration::from_nanos(17 * 520_833) + Duration::from_millis(6)
        );
        let report = Report {
            wire: Some(wire),
            ..Report::default()
        };
        assert!(
            report
                .to_table()
                .contains("wire time alone (17 bytes + 6 ms)   14854.2 µs"),
            "{}",
            report.to_table()
        );
        let sixpack2 = crate::families::find_family("sixpack2").expect("registered");
        assert_eq!(
            sixpack2.console.wire().turnaround(),
            Duration::from_millis(6)
        );
    }

    #[test]
    fn figures_are_held_against_the_wire_time() {
        // TMCL at 115200 Bd: 9 bytes out, 9 back.
        let wire = WireTime {
            bytes: 18,
            byte_time: crate::link::byte_time(115_200),
            turnaround: Duration::ZERO,
        };
        assert_eq!(wire.round_trip(), Duration::from_nanos(18 * 86_805));
        let per_second = wire.per_second().expect("a rate");
        assert!((per_second - 640.0).abs() < 0.01, "{per_second}");
        let report = Report {
            link: "/dev/pts/3 at 115200 Bd".into(),
            line: "GAP 1, 0".into(),
            requests: 100,
            bare: Some(figures(&(1601..=1700).collect::<Vec<_>>())),
            device: figures(&[1650, 1590]),
            // 608 polls in a second: 95% of the wire's 640.
            polls: Figures {
                samples: vec![Duration::from_micros(1645); 608],
                total: Duration::from_secs(1),
                faults: 0,
            },
            user_while_polling: figures(&(1..=100).map(|n| n * 34).collect::<Vec<_>>()),
            wire: Some(wire),
            ..Report::default()
        };
        let share = report.polling_share_of_wire().expect("a share");
        assert!((share - 0.95).abs() < 1e-3, "{share}");
        // 3366 µs against 1699 µs.
        let times = report.user_p99_over_bare().expect("a ratio");
        assert!((times - 3366.0 / 1699.0).abs() < 1e-9, "{times}");
        let table = report.to_table();
        assert!(
            table.contains(
                "wire time alone (18 bytes)           1562.5 µs   1562.5 µs         640       -"
            ),
            "{table}"
        );
        assert!(
            table.contains(
                "status polling (saturating)                  -           -         608       0"
            ),
            "{table}"
        );
        assert!(!table.contains("no answer"), "{table}");
        assert!(
            table.contains(
                "polling at 95.0% of the wire's rate; fastest round trip 1590.0 µs \
                 (the wire's 1562.5 µs); user read p99 while polling 1.98 × the bare p99"
            ),
            "{table}"
        );
        let json = report.to_json();
        assert_eq!(json["wire"]["bytes"], 18);
        assert_eq!(json["bare"]["min_us"], 1601.0);
        assert_eq!(json["polling"]["share_of_wire"], share);
    }

    #[test]
    fn faults_stand_beside_the_figures_they_are_left_out_of() {
        let lossy = |micros: &[u64], faults| Figures {
            faults,
            ..figures(micros)
        };
        let report = Report {
            requests: 4,
            bare: Some(lossy(&[100, 100, 100], 1)),
            device: lossy(&[200, 200], 2),
            polls: lossy(&[200, 200, 200], 1),
            user_while_polling: lossy(&[300, 300, 300, 300], 0),
            ..Report::default()
        };
        assert_eq!(report.faults(), 4);
        let table = report.to_table();
        let device_row = format!(
            "{:<34}{:>12}{:>12}{:>12}{:>8}\n",
            "device task round trip", "200.0 µs", "200.0 µs", 2, 2
        );
        assert!(table.contains(&device_row), "{table}");
        assert!(
            table.ends_with(
                "4 requests got no answer (timed out or garbled): counted as faults, \
                 left out of the figures\n"
            ),
            "{table}"
        );
        let json = report.to_json();
        assert_eq!(json["faults"], 4);
        assert_eq!(json["bare"]["faults"], 1);
        assert_eq!(json["device"]["faults"], 2);
        assert_eq!(json["device"]["count"], 2);
        assert_eq!(json["polling"]["faults"], 1);
        assert_eq!(json["polling"]["count"], 3);
        assert_eq!(json["user_while_polling"]["faults"], 0);
    }

    #[test]
    fn without_a_baud_rate_there_is_no_wire_to_compare_with() {
        let report = Report {
            bare: Some(figures(&[100, 200])),
            user_while_polling: figures(&[300, 400]),
            polls: figures(&[100]),
            ..Report::default()
        };
        assert_eq!(report.polling_share_of_wire(), None);
        assert_eq!(report.user_p99_over_bare(), Some(2.0));
        let table = report.to_table();
        assert!(!table.contains("wire"), "{table}");
        assert!(table.ends_with("user read p99 while polling 2.00 × the bare p99\n"));
        assert!(report.to_json()["wire"].is_null());
    }

    #[test]
    fn quantiles_by_nearest_rank() {
        let f = figures(&(1..=100).collect::<Vec<_>>());
        assert_eq!(f.quantile(0.5), Some(Duration::from_micros(50)));
        assert_eq!(f.quantile(0.99), Some(Duration::from_micros(99)));
        assert_eq!(f.quantile(1.0), Some(Duration::from_micros(100)));
        assert_eq!(f.quantile(0.0), Some(Duration::from_micros(1)));
        assert_eq!(figures(&[7]).quantile(0.99), Some(Duration::from_micros(7)));
        assert_eq!(figures(&[]).quantile(0.5), None);
        assert_eq!(f.per_second(100), Some(100.0));
    }
}
