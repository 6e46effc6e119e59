//! Device-side fuzzing on a real pseudo-terminal, with real timing: for
//! every family in `families::FAMILIES`, a fake device on the pty's master
//! side answers the console's lines with what the family's corpus offers,
//! bent, cut into chunks with pauses of its own choosing, and between
//! them talks noise, sometimes nonstop at about 25 KB/s (fault soak, issue
//! 19: a device that never stopped talking kept a line waiting forever).
//! The console side is the real thing: the serial link on the pty's slave
//! path, the device task, a session. Every line must end (answered,
//! refused, timed out, garbled or not sent) and nothing may panic.
//!
//! Each case costs real time (a line's timeout for each attempt), so it
//! runs fewer cases than the other targets: `AXTERM_FUZZ_CASES / 150`,
//! 4 to 5000 per family (10 by default). `fuzz/run 100000 device` runs it
//! longer; `AXTERM_FUZZ_SEED` picks another run.

mod fuzz_support;

use std::io::{Read, Write};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread;
use std::time::Duration;

use axterm::device::DeviceOptions;
use axterm::families::FAMILIES;
use axterm::link::LinkSpec;
use axterm::protocol::console::{Answering, PreparedLine};
use axterm::session::{Session, SessionOptions};
use fuzz_support::{FamilyCorpus, Rng, bend_bytes, cases, chunks, noise_bytes, seed};
use serialport::{SerialPort, TTYPort};

/// The reply timeout the console is given: short, so that a case is short.
const TIMEOUT: Duration = Duration::from_millis(30);

/// Only guards against a line that never ends (the fault this target is
/// for); a line ends within its timeout for each of its attempts, and a
/// few silences, far below it.
const GIVE_UP_AFTER: Duration = Duration::from_secs(20);

/// How the fake device talks between its answers in one case.
#[derive(Debug, Clone, Copy)]
enum Talk {
    /// Nothing but its answers.
    Quiet,
    /// A burst of noise now and then.
    Bursts,
    /// Noise without a pause, ~25 bytes each millisecond.
    Nonstop,
}

/// The fake device: until `stop`, reads what the console writes and, for
/// each request, maybe answers with one of `answers` (bent or whole, in
/// chunks with pauses), talking as `talk` says in between.
fn fake_device(
    mut master: TTYPort,
    mut rng: Rng,
    answers: Vec<Vec<u8>>,
    talk: Talk,
    stop: Arc<AtomicBool>,
) {
    let mut buffer = [0u8; 256];
    while !stop.load(Ordering::Relaxed) {
        let heard = master.read(&mut buffer).unwrap_or(0);
        if heard > 0 && rng.chance(70) {
            let mut answer = rng.pick(&answers).cloned().unwrap_or_default();
            if rng.chance(40) {
                answer = bend_bytes(&mut rng, &answer);
            }
            // Line ends for the families that cut lines; noise to the
            // framers of the others.
            if rng.chance(60) {
                answer.extend_from_slice(b"\r\n");
            }
            for piece in chunks(&mut rng, &answer) {
                let _ = master.write_all(&piece);
                if rng.chance(10) {
                    thread::sleep(Duration::from_millis(rng.below(5) as u64));
                }
            }
        }
        let noise = match talk {
            Talk::Quiet => Vec::new(),
            Talk::Bursts if rng.chance(5) => noise_bytes(&mut rng, 64),
            Talk::Bursts => Vec::new(),
            Talk::Nonstop => (0..25).map(|_| rng.byte()).collect(),
        };
        let _ = master.write_all(&noise);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_talking_device_never_holds_a_line_forever() {
    let per_family = (cases() / 150).clamp(4, 5000);
    let mut rng = Rng::new(seed() ^ 0xDE71_CE00);
    for family in FAMILIES {
        let corpus = FamilyCorpus::build(family);
        let mut answers: Vec<Vec<u8>> = corpus.answers.iter().flatten().cloned().collect();
        answers.extend(corpus.frames.iter().take(64).cloned());
        // Lines that wait for the device by design have no reply deadline
        // to keep: a SIXpack 2 `$28` with a wait mask waits for its motors
        // to be idle (§7.2, up to its IDLE_WAIT), an MCCL line that runs
        // long is held until its prompt or an abort (Ch2). The emergency
        // stop, Esc and Ctrl-C end those; they are not this target's.
        let lines: Vec<(String, PreparedLine)> = corpus
            .lines
            .iter()
            .filter(|(_, prepared)| {
                !matches!(prepared.answering, Answering::Later { .. })
                    && family.console.long_running(prepared).is_none()
            })
            .cloned()
            .collect();
        let mut ended = 0;
        for case in 0..per_family {
            let Some((line, _)) = rng.pick(&lines).cloned() else {
                break;
            };
            let talk = [Talk::Quiet, Talk::Bursts, Talk::Nonstop][rng.below(3)];
            let (mut master, slave) = TTYPort::pair().expect("a pseudo-terminal");
            let path = slave.name().expect("the slave has a path");
            drop(slave);
            master
                .set_timeout(Duration::from_millis(1))
                .expect("a read timeout");
            let stop = Arc::new(AtomicBool::new(false));
            let device = {
                let (rng, answers, stop) =
                    (Rng::new(rng.next_u64()), answers.clone(), Arc::clone(&stop));
                thread::spawn(move || fake_device(master, rng, answers, talk, stop))
            };
            let options = SessionOptions {
                address: Some(corpus.address),
                read_retries: 1,
                device: DeviceOptions {
                    timeout: Some(TIMEOUT),
                    ..DeviceOptions::default()
                },
            };
            let spec = LinkSpec::Serial {
                path,
                baud: 115_200,
            };
            let outcome = tokio::time::timeout(GIVE_UP_AFTER, async {
                let session = Session::connect(spec, family, options).await?;
                let _ = session.execute_line(&line).await;
                session.device().shutdown().await;
                Ok::<_, axterm::link::LinkError>(())
            })
            .await;
            stop.store(true, Ordering::Relaxed);
            device.join().expect("the fake device ends");
            match outcome {
                Ok(Ok(())) => ended += 1,
                Ok(Err(error)) => panic!("{}: the pty did not open: {error}", family.name),
                Err(_) => panic!(
                    "{} case {case}: `{line}` with a device talking {talk:?} did not end \
                     within {GIVE_UP_AFTER:?}",
                    family.name
                ),
            }
        }
        eprintln!(
            "fuzz device {}: {ended} lines on a talking pty, all ended",
            family.name
        );
        assert_eq!(ended, per_family, "{}", family.name);
    }
}
