//! `axterm run-ascript CONNECTION FILE`: an A-Script program (CMD-4CR §5)
//! run from the host, for real hardware, whose program memory the manual
//! gives no way to load over the wire (§2.7.7, §5.1.5). The whole file is
//! checked first — Table 5-43's compile errors and the statements with no
//! ASCII equivalent, each as `FILE:LINE:` — and nothing is sent if any is
//! found. Then every statement that acts goes out as its ASCII command,
//! printed with its answer; variables, control flow and waits stay here
//! (see [`crate::protocol::cmd4cr::host`]). A run that fails, is stopped
//! with Ctrl-C or loses its link ends with the emergency stop (ESTOP, the
//! four programs stopped, ESTOP) unless `--no-stop-on-failure` (see
//! [`super::run_end`]).
//!
//! Exit codes as `axterm run`: 0 every program ran to its END, 1 a program
//! failed at run time (or no answer came, or Ctrl-C), 2 a bad file or
//! usage (nothing sent), 3 the connection could not be opened.

use std::io::Write;

use clap::Args;

use super::connection::{Target, family_of, names_a_connection, run_to_exit};
use super::output::Format;
use super::run::read_source;
use super::run_end::{Interrupt, RunReport, run_then_end};
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::protocol::program::{HostNews, ProgramTool};
use crate::protocol::{FAMILIES, Family};
use crate::session::run_end::StopOnFailure;

#[derive(Debug, Clone, Args)]
pub struct RunAscriptArgs {
    /// The A-Script source, or - for standard input.
    pub file: String,
    /// Start only this PRG block (0-3; again for more). Default: every PRG
    /// block of the file, as the manual's multi-thread examples run; one
    /// not started still runs when another starts it with SR[n]=1.
    #[arg(long = "prg", value_name = "N", value_parser = clap::value_parser!(u8).range(0..=3))]
    pub prg: Vec<u8>,
    /// Check the file only: send nothing (no connection needed; the
    /// options of one given are checked too, nothing is opened).
    #[arg(long)]
    pub dry_run: bool,
    /// When a program fails, the run is stopped (Ctrl-C) or loses its
    /// link, leave the axes as they are. By default the emergency stop is
    /// sent then (ESTOP, the four programs stopped, ESTOP), waiting up to
    /// 10 s for a lost link to come back.
    #[arg(long)]
    pub no_stop_on_failure: bool,
}

/// The family whose programs `run-ascript` runs from the host (A-Script,
/// the CMD-4CR's), and its program tool: the one it speaks when the
/// options name none.
fn host_family() -> Option<(&'static Family, &'static dyn ProgramTool)> {
    FAMILIES.iter().find_map(|family| {
        let tool = family.console.program().filter(|t| t.runs_from_host())?;
        Some((family, tool))
    })
}

fn say(text: &str) {
    let mut out = std::io::stdout().lock();
    // A closed pipe (`| head`) is not an error of ours.
    let _ = writeln!(out, "{text}");
    let _ = out.flush();
}

pub fn run(connection: &ConnectionArgs, args: &RunAscriptArgs) -> i32 {
    let Some((host, host_tool)) = host_family() else {
        eprintln!("axterm run-ascript: no family's programs run from the host");
        return EXIT_USAGE;
    };
    // A-Script is the CMD-4CR's: speak it unless told otherwise.
    let mut connection = connection.clone();
    if connection.protocol.is_none() && connection.sim.is_none() {
        connection.protocol = Some(host.name.into());
    }
    let family = match family_of(&connection) {
        Ok(family) => family,
        Err(message) => {
            eprintln!("axterm run-ascript: {message}");
            return EXIT_USAGE;
        }
    };
    let Some(tool) = family.console.program().filter(|t| t.runs_from_host()) else {
        let sim = host
            .simulators
            .first()
            .map_or_else(String::new, |k| format!(" or --sim {}", k.name));
        eprintln!(
            "axterm run-ascript: {} is the {}'s language; this connection speaks {}: give --protocol {}{sim}",
            host_tool.name(),
            host_tool.controller(),
            family.name,
            host.name
        );
        return EXIT_USAGE;
    };
    let (name, text) = match read_source(&args.file) {
        Ok(source) => source,
        Err(message) => {
            eprintln!("axterm run-ascript: {message}");
            return EXIT_USAGE;
        }
    };
    let start = (!args.prg.is_empty()).then_some(args.prg.as_slice());
    let program = match tool.host_run(&name, &text, start) {
        Some(Ok(program)) => program,
        None => {
            eprintln!(
                "axterm run-ascript: {} programs do not run from the host",
                tool.name()
            );
            return EXIT_USAGE;
        }
        Some(Err(problems)) => {
            for problem in problems {
                eprintln!("{problem}");
            }
            eprintln!("axterm run-ascript: {name}: nothing was sent");
            return EXIT_USAGE;
        }
    };
    for warning in &program.warnings {
        eprintln!("{warning}");
    }
    // A dry run given a connection checks its options as a run would.
    let target = if args.dry_run && !names_a_connection(&connection) {
        None
    } else {
        match Target::resolve(&connection) {
            Ok(target) => Some(target),
            Err(message) => {
                eprintln!("axterm run-ascript: {message}");
                return EXIT_USAGE;
            }
        }
    };
    let target = match target {
        Some(target) if !args.dry_run => target,
        _ => {
            eprintln!(
                "axterm run-ascript: {name}: checks, {} would start from the host; nothing sent (dry run)",
                program.started
            );
            return EXIT_OK;
        }
    };
    let policy = StopOnFailure::from_flag(args.no_stop_on_failure);
    run_to_exit("run-ascript", async move {
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm run-ascript: {e}");
                return EXIT_CONNECTION;
            }
        };
        eprintln!(
            "axterm run-ascript: running {name} from the host on {}: {} (Ctrl-C stops it{})",
            target.spec.describe(),
            program.started,
            match policy {
                StopOnFailure::Stop => " and sends the emergency stop",
                StopOnFailure::Leave => "; the axes are left as they are",
            }
        );
        // Watched from before the first line goes, so that a Ctrl-C as soon
        // as the run is announced is not lost.
        let interrupt = match Interrupt::watch() {
            Ok(interrupt) => interrupt,
            Err(e) => {
                eprintln!("axterm run-ascript: cannot watch for Ctrl-C: {e}");
                return EXIT_DEVICE;
            }
        };
        let mut show = |news: &HostNews| say(&news.text);
        let prefix = format!("axterm run-ascript: {name}: ");
        let work = async {
            let end = session.run_from_host(program.run, &mut show).await;
            eprintln!("{prefix}{end}");
            end.ok
        };
        let report = RunReport {
            prefix: &prefix,
            format: Format::Text,
        };
        run_then_end(&session, interrupt, policy, &report, work).await
    })
}
