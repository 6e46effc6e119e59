//! How `axterm run` and `axterm run-ascript` end a run: the run's work
//! goes until it ends or Ctrl-C (SIGINT), SIGTERM or SIGHUP comes (each
//! ends it alike), a run file that completed is checked for an axis it
//! leaves moving ([`AtTheEnd`]), then the session decides
//! what becomes of the axes ([`Session::end_run`]: the stop sequence after
//! a run that failed or was cancelled, unless `--no-stop-on-failure`) and
//! its report is printed on standard error. A second Ctrl-C while the
//! stop waits for a lost link gives up waiting, and says so.

use std::future::Future;
use std::pin::Pin;

use serde_json::Value;

use super::connection::{Target, run_to_exit};
use super::output::{Format, json_outcome};
use super::{EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK};
use crate::session::Session;
pub use crate::session::run_end::AtTheEnd;
use crate::session::run_end::{RunAftermath, RunEnding, StopOnFailure};

/// Ctrl-C (SIGINT), SIGTERM (a service manager, `kill`) and SIGHUP (the
/// SSH session or terminal dropped), watched from when it is made: the
/// default action of each (the process ends at once, the axes going on as
/// they were told) is replaced, so the run can be ended properly. All
/// three end a run the same way: as cancelled, with the stop sequence.
pub struct Interrupt {
    #[cfg(unix)]
    signals: [(Signal, tokio::signal::unix::Signal); 3],
}

/// Which signal ended a run, for its report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Signal {
    Interrupt,
    Terminate,
    HangUp,
}

impl Signal {
    /// How the report names it: `Ctrl-C`, `SIGTERM`, `SIGHUP`.
    pub fn name(self) -> &'static str {
        match self {
            Signal::Interrupt => "Ctrl-C",
            Signal::Terminate => "SIGTERM",
            Signal::HangUp => "SIGHUP",
        }
    }
}

impl Interrupt {
    pub fn watch() -> std::io::Result<Interrupt> {
        #[cfg(unix)]
        {
            use tokio::signal::unix::{SignalKind, signal};
            Ok(Interrupt {
                signals: [
                    (Signal::Interrupt, signal(SignalKind::interrupt())?),
                    (Signal::Terminate, signal(SignalKind::terminate())?),
                    (Signal::HangUp, signal(SignalKind::hangup())?),
                ],
            })
        }
        #[cfg(not(unix))]
        {
            Ok(Interrupt {})
        }
    }

    /// The next Ctrl-C, SIGTERM or SIGHUP: which one came.
    pub async fn received(&mut self) -> Signal {
        #[cfg(unix)]
        {
            let [(a, first), (b, second), (c, third)] = &mut self.signals;
            tokio::select! {
                _ = first.recv() => *a,
                _ = second.recv() => *b,
                _ = third.recv() => *c,
            }
        }
        #[cfg(not(unix))]
        {
            let _ = tokio::signal::ctrl_c().await;
            Signal::Interrupt
        }
    }
}

/// Where and how a run's end is reported.
pub struct RunReport<'a> {
    /// `axterm run: FILE: `, before each line of the report that is not a
    /// stop line.
    pub prefix: &'a str,
    /// With [`Format::Json`] each stop line is also printed on standard
    /// output as the JSON object of its outcome, with `"stop": true`.
    pub format: Format,
    /// What a run that completed checks of the axes.
    pub at_the_end: AtTheEnd,
}

/// A run that completed under `check`: whether it ends as completed, or as
/// failed because it leaves an axis moving that the file did not mean to
/// leave so (said on standard error either way).
async fn completed_run_checked(session: &Session, check: AtTheEnd, prefix: &str) -> RunEnding {
    let found = session.check_run_end(check).await;
    if let Some(said) = &found.said {
        eprintln!("{prefix}{said}");
    }
    found.ending
}

/// Run `work` (true when every step succeeded) to its end or to a Ctrl-C,
/// then end the run under `policy` and print what was done. The exit code:
/// 0 for a run that completed, 1 otherwise.
pub async fn run_then_end(
    session: &Session,
    mut interrupt: Interrupt,
    policy: StopOnFailure,
    report: &RunReport<'_>,
    work: impl Future<Output = bool>,
) -> i32 {
    match run_then_end_on(session, &mut interrupt, policy, report, work).await {
        RunEnding::Completed => EXIT_OK,
        RunEnding::Failed | RunEnding::Cancelled => EXIT_DEVICE,
    }
}

/// [`run_then_end`] with an interrupt watched across several runs (one
/// module of a bus after another: a Ctrl-C ends the one running, which
/// ends as cancelled, and the caller stops there); how the run ended.
pub async fn run_then_end_on(
    session: &Session,
    interrupt: &mut Interrupt,
    policy: StopOnFailure,
    report: &RunReport<'_>,
    work: impl Future<Output = bool>,
) -> RunEnding {
    run_then_end_with(session, interrupt, policy, report, work)
        .await
        .0
}

/// [`run_then_end_on`], also giving what was done about the axes (for the
/// commissioning sheet): `None` when a second signal gave up the stop.
pub async fn run_then_end_with(
    session: &Session,
    interrupt: &mut Interrupt,
    policy: StopOnFailure,
    report: &RunReport<'_>,
    work: impl Future<Output = bool>,
) -> (RunEnding, Option<RunAftermath>) {
    let ending = tokio::select! {
        ok = work => RunEnding::from_success(ok),
        signal = interrupt.received() => {
            // The work is dropped here: its line in flight is answered,
            // nothing more of it is sent.
            eprintln!("{}stopped by {}", report.prefix, signal.name());
            RunEnding::Cancelled
        }
    };
    // A run that completed may still leave an axis moving.
    let ending = match ending {
        RunEnding::Completed => tokio::select! {
            ending = completed_run_checked(session, report.at_the_end, report.prefix) => ending,
            signal = interrupt.received() => {
                eprintln!("{}stopped by {}", report.prefix, signal.name());
                RunEnding::Cancelled
            }
        },
        other => other,
    };
    if ending == RunEnding::Completed {
        return (ending, Some(RunAftermath::Completed));
    }
    let aftermath = tokio::select! {
        aftermath = session.end_run(ending, policy) => aftermath,
        signal = interrupt.received() => {
            eprintln!(
                "{}{} again: gave up sending the stop; the axes may still move",
                report.prefix,
                signal.name()
            );
            return (RunEnding::Cancelled, None);
        }
    };
    print_aftermath(session, report, &aftermath);
    (ending, Some(aftermath))
}

/// The work of a one-axis tool (`axterm wiring`, `axterm tune …`) on an
/// open session, to its exit code.
pub type SessionWork =
    Box<dyn for<'s> FnOnce(&'s Session) -> Pin<Box<dyn Future<Output = i32> + Send + 's>> + Send>;

/// Open `target`'s link (exit 3 when it does not open) and run `work` on
/// its session to an exit code; Ctrl-C, SIGTERM and SIGHUP stop the axes as
/// for `exec` ([`exit_or_stop_on_signal`]). `command` names the
/// subcommand in messages (`tune step`).
pub fn run_tool_to_exit(command: &'static str, target: Target, work: SessionWork) -> i32 {
    run_to_exit(command, async move {
        let prefix = format!("axterm {command}: ");
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("{prefix}{e}");
                return EXIT_CONNECTION;
            }
        };
        let interrupt = match Interrupt::watch() {
            Ok(interrupt) => interrupt,
            Err(e) => {
                eprintln!("{prefix}cannot watch for Ctrl-C: {e}");
                return EXIT_DEVICE;
            }
        };
        let report = RunReport {
            prefix: &prefix,
            format: Format::Text,
            at_the_end: AtTheEnd::Nothing,
        };
        exit_or_stop_on_signal(&session, interrupt, &report, work(&session)).await
    })
}

/// `work` (one-shot lines, `axterm exec`: its exit code) to its end, or to
/// a Ctrl-C, SIGTERM or SIGHUP: then nothing more of it is sent and the
/// stop sequence goes out, as at the end of a cancelled run (exit 1). A
/// line that fails does not stop the axes here: the lines were asked for
/// one by one, and the exit code says which failed.
pub async fn exit_or_stop_on_signal(
    session: &Session,
    mut interrupt: Interrupt,
    report: &RunReport<'_>,
    work: impl Future<Output = i32>,
) -> i32 {
    let signal = tokio::select! {
        code = work => return code,
        signal = interrupt.received() => signal,
    };
    // The work is dropped here: its line in flight is answered (or
    // aborted by the stop), nothing more of it is sent.
    eprintln!("{}stopped by {}", report.prefix, signal.name());
    let aftermath = tokio::select! {
        aftermath = session.end_run(RunEnding::Cancelled, StopOnFailure::Stop) => aftermath,
        signal = interrupt.received() => {
            eprintln!(
                "{}{} again: gave up sending the stop; the axes may still move",
                report.prefix,
                signal.name()
            );
            return EXIT_DEVICE;
        }
    };
    print_aftermath(session, report, &aftermath);
    EXIT_DEVICE
}

fn print_aftermath(session: &Session, report: &RunReport<'_>, aftermath: &RunAftermath) {
    for line in aftermath.report() {
        if line.starts_with(' ') {
            eprintln!("{line}");
        } else {
            eprintln!("{}{line}", report.prefix);
        }
    }
    if report.format == Format::Json
        && let RunAftermath::Stopped(stop) = aftermath
    {
        for result in &stop.lines {
            let line = match result {
                Ok(r) => r.line.as_str(),
                Err(e) => e.line(),
            };
            let mut object = json_outcome(session.family(), line, result);
            if let Value::Object(map) = &mut object {
                map.insert("stop".into(), Value::Bool(true));
            }
            println!("{object}");
        }
    }
}
