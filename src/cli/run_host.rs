//! The front end every program run from the host shares (`axterm
//! run-ascript`, `axterm run-macro`): the language's family is spoken
//! unless the options say otherwise, the whole file is checked first by
//! the language's [`ProgramTool::host_run`] (every problem as
//! `FILE:LINE:`, nothing sent), lines the family wants confirmed need
//! `--yes`, then the run goes, each line printed with its answer, and a
//! run that fails, is stopped with Ctrl-C or loses its link ends with the
//! emergency stop unless `--no-stop-on-failure` (see [`super::run_end`]).
//!
//! Exit codes: 0 the run ended well, 1 it failed at run time (or no
//! answer, or Ctrl-C), 2 a bad file or usage (nothing sent), 3 the
//! connection could not be opened.

use std::io::Write;

use super::connection::{Target, family_of, names_a_connection, run_to_exit};
use super::output::Format;
use super::run::read_source;
use super::run_end::{AtTheEnd, Interrupt, RunReport, run_then_end};
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::families::FAMILIES;
use crate::protocol::Family;
use crate::protocol::program::{HostNews, ProgramTool};
use crate::session::run_end::StopOnFailure;

/// One command that runs programs of one language from the host: the
/// language whose tool names it ([`ProgramTool::host_command`]).
pub struct HostCommand {
    /// Its name on the command line (`run-macro`).
    pub name: &'static str,
}

/// What the command was asked to do.
pub struct HostRunArgs<'a> {
    pub file: &'a str,
    /// The programs to start (A-Script PRG numbers); all when `None`.
    pub start: Option<&'a [u8]>,
    pub dry_run: bool,
    pub no_stop_on_failure: bool,
    /// Send the lines the family wants confirmed.
    pub yes: bool,
}

/// Whether `tool` is the one `command` runs.
fn runs(tool: &dyn ProgramTool, command: &str) -> bool {
    tool.runs_from_host() && tool.host_command() == Some(command)
}

/// The family whose program tool `command` runs from the host.
fn host_family(command: &str) -> Option<(&'static Family, &'static dyn ProgramTool)> {
    FAMILIES.iter().find_map(|family| {
        let tool = family.console.program().filter(|t| runs(*t, command))?;
        Some((family.family, tool))
    })
}

fn say(text: &str) {
    let mut out = std::io::stdout().lock();
    // A closed pipe (`| head`) is not an error of ours.
    let _ = writeln!(out, "{text}");
    let _ = out.flush();
}

pub fn run(command: &HostCommand, connection: &ConnectionArgs, args: &HostRunArgs) -> i32 {
    let name = command.name;
    let Some((host, host_tool)) = host_family(name) else {
        eprintln!("axterm {name}: no family's programs run from the host so");
        return EXIT_USAGE;
    };
    // The language's family unless told otherwise.
    let mut connection = connection.clone();
    if connection.protocol.is_none() && connection.sim.is_none() {
        connection.protocol = Some(host.name.into());
    }
    let family = match family_of(&connection) {
        Ok(family) => family,
        Err(message) => {
            eprintln!("axterm {name}: {message}");
            return EXIT_USAGE;
        }
    };
    let Some(tool) = family.console.program().filter(|t| runs(*t, name)) else {
        let sim = crate::families::simulators_of(host)
            .first()
            .map_or_else(String::new, |k| format!(" or --sim {}", k.name));
        eprintln!(
            "axterm {name}: {} is the {}'s language; this connection speaks {}: give --protocol {}{sim}",
            host_tool.name(),
            host_tool.controller(),
            family.name,
            host.name
        );
        return EXIT_USAGE;
    };
    let (file, text) = match read_source(args.file) {
        Ok(source) => source,
        Err(message) => {
            eprintln!("axterm {name}: {message}");
            return EXIT_USAGE;
        }
    };
    let program = match tool.host_run(&file, &text, args.start) {
        Some(Ok(program)) => program,
        None => {
            eprintln!(
                "axterm {name}: {} programs do not run from the host",
                tool.name()
            );
            return EXIT_USAGE;
        }
        Some(Err(problems)) => {
            for problem in problems {
                eprintln!("{problem}");
            }
            eprintln!("axterm {name}: {file}: nothing was sent");
            return EXIT_USAGE;
        }
    };
    for warning in &program.warnings {
        eprintln!("{warning}");
    }
    if !args.yes && !program.confirm.is_empty() {
        for line in &program.confirm {
            eprintln!("{line}: not sent without --yes");
        }
        eprintln!("axterm {name}: {file}: nothing was sent");
        return EXIT_USAGE;
    }
    // A dry run given a connection checks its options as a run would.
    let target = if args.dry_run && !names_a_connection(&connection) {
        None
    } else {
        match Target::resolve(&connection) {
            Ok(target) => Some(target),
            Err(message) => {
                eprintln!("axterm {name}: {message}");
                return EXIT_USAGE;
            }
        }
    };
    let target = match target {
        Some(target) if !args.dry_run => target,
        _ => {
            eprintln!(
                "axterm {name}: {file}: checks, {} would start from the host; nothing sent (dry run)",
                program.started
            );
            return EXIT_OK;
        }
    };
    let policy = StopOnFailure::from_flag(args.no_stop_on_failure);
    let command_name = name;
    run_to_exit(name, async move {
        let name = command_name;
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm {name}: {e}");
                return EXIT_CONNECTION;
            }
        };
        eprintln!(
            "axterm {name}: running {file} from the host on {}: {} (Ctrl-C stops it{})",
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
                eprintln!("axterm {name}: cannot watch for Ctrl-C: {e}");
                return EXIT_DEVICE;
            }
        };
        let mut show = |news: &HostNews| say(&news.text);
        let prefix = format!("axterm {name}: {file}: ");
        let work = async {
            let end = session.run_from_host(program.run, &mut show).await;
            eprintln!("{prefix}{end}");
            end.ok
        };
        let report = RunReport {
            prefix: &prefix,
            format: Format::Text,
            // A host run's languages cannot say they mean to leave an
            // axis moving.
            at_the_end: AtTheEnd::Nothing,
        };
        run_then_end(&session, interrupt, policy, &report, work).await
    })
}
