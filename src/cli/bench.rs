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
//! The request is the family's first status query (TMCL `GAP 1, 0`).

use std::io::{Read, Write};
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
    Answer, DeviceError, Expect, PollItem, PollPlan, PollSink, Retry, Transaction,
};
use crate::link::{LinkSpec, SharedSim};
use crate::protocol::console::{Answering, PreparedLine};
use crate::protocol::wire::{Framer, ReplyRule, Verdict, WireFormat};
use crate::session::Session;

/// How long the bare loop waits for one answer before giving up.
const BARE_TIMEOUT: Duration = Duration::from_secs(2);

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
    /// Each request's round trip.
    pub samples: Vec<Duration>,
    /// From the first request to the last answer.
    pub total: Duration,
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
}

fn micros(d: Option<Duration>) -> Value {
    d.map_or(Value::Null, |d| json!(d.as_secs_f64() * 1e6))
}

fn figures_json(f: &Figures) -> Value {
    json!({
        "p50_us": micros(f.quantile(0.5)),
        "p99_us": micros(f.quantile(0.99)),
        "per_second": f.per_second(f.samples.len()),
        "count": f.samples.len(),
    })
}

impl Report {
    pub fn to_json(&self) -> Value {
        json!({
            "link": self.link,
            "line": self.line,
            "requests": self.requests,
            "bare": self.bare.as_ref().map(figures_json),
            "bare_note": self.bare_note,
            "device": figures_json(&self.device),
            "polling": { "per_second": self.polls.per_second(self.polls.samples.len()) },
            "user_while_polling": figures_json(&self.user_while_polling),
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
                "{name:<34}{p50:>12}{p99:>12}{:>12}\n",
                rate(f.per_second(f.samples.len()))
            )
        };
        let mut out = format!(
            "axterm bench: {}, {} × {}\n{:<34}{:>12}{:>12}{:>12}\n",
            self.link, self.requests, self.line, "", "p50", "p99", "per second"
        );
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
    let Some(line) = console
        .status_queries(target.address)
        .into_iter()
        .next()
        .map(|q| q.line)
    else {
        eprintln!(
            "axterm bench: the {} family has no status query to time",
            target.family.name
        );
        return EXIT_USAGE;
    };
    // The floor first: a serial port can have only one owner at a time.
    let wire = console.wire();
    let (bare, bare_note) = match bare_loop(&target.spec, wire.as_ref(), &line, args.requests) {
        Ok((figures, note)) => (Some(figures), note),
        Err(BareError::Open(message)) => {
            eprintln!("axterm bench: {message}");
            return EXIT_CONNECTION;
        }
        Err(BareError::Exchange(message)) => (None, message),
    };
    let (requests, format) = (args.requests, args.format);
    run_to_exit("bench", async move {
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm bench: {e}");
                return EXIT_CONNECTION;
            }
        };
        let report = match measure(&session, &line, requests).await {
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
async fn measure(
    session: &Session,
    line: &PreparedLine,
    requests: usize,
) -> Result<Report, String> {
    let timed = |session: &Session| {
        let session = session.clone();
        let line = line.clone();
        async move {
            let mut figures = Figures::default();
            let start = Instant::now();
            for _ in 0..requests {
                let sent = Instant::now();
                session.execute(&line).await.map_err(|e| e.to_string())?;
                figures.samples.push(sent.elapsed());
            }
            figures.total = start.elapsed();
            Ok::<Figures, String>(figures)
        }
    };
    let device = timed(session).await?;

    // Polling with every item due at once, as often as the link allows.
    let (done_tx, mut done) = mpsc::unbounded_channel();
    let expect = match &line.answering {
        Answering::Reply(rule) | Answering::MaybeReply(rule) => Expect::Reply(Arc::clone(rule)),
        Answering::Nothing => Expect::Nothing,
    };
    let item = PollItem {
        transaction: Transaction {
            bytes: line.bytes.clone(),
            expect,
            retry: Retry::Never,
            timeout: None,
        },
        every: Duration::ZERO,
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
    while polls.samples.len() < requests {
        match done.recv().await {
            Some(Ok(sample)) => polls.samples.push(sample),
            Some(Err(error)) => {
                session.device().set_poll_plan(None);
                return Err(format!("a status poll failed: {error}"));
            }
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
            if let Err(e) = session.execute(line).await {
                session.device().set_poll_plan(None);
                return Err(e.to_string());
            }
            figures.samples.push(sent.elapsed());
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
        ..Report::default()
    })
}

/// The i-th of an evenly spread sequence in 0..1 (the golden-ratio
/// sequence): where in a poll the i-th user read arrives.
fn arrival_fraction(i: usize) -> f64 {
    const GOLDEN: f64 = 0.618_033_988_749_894_9;
    (i as f64 * GOLDEN).fract()
}

/// Reports each poll's completion to the bench.
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

enum BareError {
    /// The link could not be opened at all.
    Open(String),
    /// Opened, but the loop did not complete.
    Exchange(String),
}

/// Measurement 1: request and answer with no device task in between.
fn bare_loop(
    spec: &LinkSpec,
    wire: &dyn WireFormat,
    line: &PreparedLine,
    requests: usize,
) -> Result<(Figures, String), BareError> {
    let rule = match &line.answering {
        Answering::Reply(rule) | Answering::MaybeReply(rule) => Arc::clone(rule),
        Answering::Nothing => {
            return Err(BareError::Exchange(
                "the timed line expects no answer".into(),
            ));
        }
    };
    match spec {
        LinkSpec::Serial { path, baud } => {
            let mut port = serialport::new(path, *baud)
                .timeout(BARE_TIMEOUT)
                .open()
                .map_err(|e| BareError::Open(format!("cannot open {}: {e}", spec.describe())))?;
            let figures = blocking_loop(&mut port, wire, rule.as_ref(), &line.bytes, requests)
                .map_err(BareError::Exchange)?;
            Ok((figures, "serialport".into()))
        }
        LinkSpec::Tcp { address } => {
            let mut stream = TcpStream::connect(address)
                .map_err(|e| BareError::Open(format!("cannot open {}: {e}", spec.describe())))?;
            let _ = stream.set_nodelay(true);
            let _ = stream.set_read_timeout(Some(BARE_TIMEOUT));
            let figures = blocking_loop(&mut stream, wire, rule.as_ref(), &line.bytes, requests)
                .map_err(BareError::Exchange)?;
            Ok((figures, "TcpStream".into()))
        }
        LinkSpec::Sim { sim, .. } => {
            let figures = sim_loop(sim, wire, rule.as_ref(), &line.bytes, requests)
                .map_err(BareError::Exchange)?;
            Ok((figures, "simulator called directly, no wire time".into()))
        }
    }
}

/// Write a request, read until the rule accepts an answer, repeat.
fn blocking_loop<S: Read + Write>(
    stream: &mut S,
    wire: &dyn WireFormat,
    rule: &dyn ReplyRule,
    request: &[u8],
    requests: usize,
) -> Result<Figures, String> {
    let mut framer = wire.framer();
    let mut figures = Figures::default();
    let mut buffer = [0u8; 256];
    let start = Instant::now();
    for _ in 0..requests {
        let sent = Instant::now();
        stream
            .write_all(request)
            .map_err(|e| format!("write failed: {e}"))?;
        let mut accepted = Vec::new();
        'answer: loop {
            let n = stream
                .read(&mut buffer)
                .map_err(|e| format!("no answer: {e}"))?;
            if n == 0 {
                return Err("the other end closed the link".into());
            }
            for frame in framer.push(buffer.get(..n).unwrap_or_default()) {
                match rule.examine(&accepted, &frame) {
                    Verdict::Complete => break 'answer,
                    Verdict::Continue => accepted.push(frame),
                    Verdict::NotMine => {}
                }
            }
        }
        figures.samples.push(sent.elapsed());
    }
    figures.total = start.elapsed();
    Ok(figures)
}

/// The simulator fed and read directly, no link, no clock.
fn sim_loop(
    sim: &SharedSim,
    wire: &dyn WireFormat,
    rule: &dyn ReplyRule,
    request: &[u8],
    requests: usize,
) -> Result<Figures, String> {
    let mut framer: Box<dyn Framer> = wire.framer();
    let mut figures = Figures::default();
    let mut sim = sim
        .lock()
        .map_err(|_| "the simulator is broken".to_string())?;
    let start = Instant::now();
    for _ in 0..requests {
        let sent = Instant::now();
        sim.feed(request);
        let output = sim.take_output();
        let complete = framer
            .push(&output)
            .iter()
            .any(|frame| rule.examine(&[], frame) == Verdict::Complete);
        if !complete {
            return Err("the simulator did not answer".into());
        }
        figures.samples.push(sent.elapsed());
    }
    figures.total = start.elapsed();
    Ok(figures)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figures(micros: &[u64]) -> Figures {
        Figures {
            samples: micros.iter().map(|&m| Duration::from_micros(m)).collect(),
            total: Duration::from_secs(1),
        }
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
