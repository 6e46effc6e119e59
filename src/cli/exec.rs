//! `axterm exec CONNECTION LINE...`: run console lines in order, one
//! result line each. Every line is parsed and validated before anything is
//! sent, and a line the family wants confirmed needs `--yes`; the first
//! line that fails stops the rest.

use clap::Args;

use super::confirm::{after_line, cautions};
use super::connection::run_to_exit;
use super::fleet::{self, FleetArgs, FleetLink, FleetModule, Identity, ModuleRow, Modules, Walk};
use super::output::{Format, json_outcome, print_outcome, unchecked_note};
use super::run_end::{AtTheEnd, Interrupt, RunReport, exit_or_stop_on_signal};
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::protocol::Family;
use crate::protocol::console::PreparedLine;
use crate::protocol::settings::SettingsCache;
use crate::protocol::units::{MechanicsTable, check_line, has_units};
use crate::session::Session;
use std::path::Path;

#[derive(Debug, Clone, Args)]
pub struct ExecArgs {
    /// Console lines, e.g. 'SAP 4, 0, 1000' 'GAP 4, 0'.
    #[arg(required = true)]
    pub lines: Vec<String>,
    /// text: the value (or ok) per line; json: one object per line.
    #[arg(long, value_enum, default_value_t)]
    pub format: Format,
    /// Send lines the family wants confirmed (a reset, a baud or address
    /// change, a motion that starts at once); without it they are refused
    /// and nothing is sent.
    #[arg(long)]
    pub yes: bool,
    #[command(flatten)]
    pub fleet: FleetArgs,
}

pub fn run(connection: &ConnectionArgs, args: &ExecArgs, mechanics: Option<&Path>) -> i32 {
    let links = match FleetLink::resolve_all(connection, &args.fleet) {
        Ok(links) => links,
        Err(message) => {
            eprintln!("axterm exec: {message}");
            return EXIT_USAGE;
        }
    };
    let mechanics = match super::mechanics::load(mechanics) {
        Ok(m) => m.map(|m| m.table).unwrap_or_default(),
        Err(message) => {
            eprintln!("axterm exec: {message}");
            return EXIT_USAGE;
        }
    };
    let one_module = !FleetLink::several(&links);
    let mut refused = false;
    let mut prepared = Vec::new();
    // The family's warnings once a family; every line checked for every
    // link and every address listed.
    let mut cautioned: Vec<&'static Family> = Vec::new();
    for link in &links {
        let on = link.name.as_ref().map_or(String::new(), |n| {
            format!("{} ({}): ", n.label, n.connection)
        });
        let family = link.target.family;
        let first_of_family = !cautioned.iter().any(|f| std::ptr::eq(*f, family));
        cautioned.push(family);
        let (lines, ok) = check_lines(
            &on,
            family,
            link.target.address,
            args,
            first_of_family,
            one_module.then_some(&mechanics),
        );
        refused |= !ok;
        if prepared.is_empty() {
            prepared = lines;
        }
        if let Modules::List(addresses) = &link.modules {
            for &address in addresses {
                refused |= !other_address_takes_lines(
                    &on,
                    family,
                    link.target.address,
                    address,
                    &args.lines,
                );
            }
        }
    }
    if refused {
        eprintln!("axterm exec: nothing was sent");
        return EXIT_USAGE;
    }
    let format = args.format;
    let yes = args.yes;
    if FleetLink::several(&links) {
        let lines = args.lines.clone();
        let stop_on_failure = args.fleet.stop_on_failure;
        return run_to_exit("exec", async move {
            let mut walk = Walk::new(&links, "exec", stop_on_failure);
            loop {
                let module = match walk.next().await {
                    Ok(Some(module)) => module,
                    Ok(None) => break,
                    Err(e) => {
                        eprintln!("axterm exec: {e}");
                        return EXIT_CONNECTION;
                    }
                };
                let row = exec_on_module(&module, &lines, format).await;
                walk.record(&module, row);
            }
            fleet::finish(&walk.rows(), &["lines", "failed"], format)
        });
    }
    let Some(target) = links.into_iter().next().map(|link| link.target) else {
        return EXIT_USAGE;
    };
    run_to_exit("exec", async move {
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm exec: {e}");
                return EXIT_CONNECTION;
            }
        };
        // A Ctrl-C, SIGTERM or SIGHUP while the lines go (a line that runs
        // long, MCCL `WA`) stops the axes before the process ends.
        let interrupt = match Interrupt::watch() {
            Ok(interrupt) => interrupt,
            Err(e) => {
                eprintln!("axterm exec: cannot watch for Ctrl-C: {e}");
                return EXIT_DEVICE;
            }
        };
        // Values in an axis's unit: converted with the module's settings,
        // read now, before any line is sent; one that does not convert or
        // validate sends nothing.
        let prepared = match convert_lines(&session, prepared, &mechanics, yes).await {
            Ok(prepared) => prepared,
            Err(()) => {
                eprintln!("axterm exec: nothing was sent");
                return EXIT_USAGE;
            }
        };
        let work = async {
            for (index, (line, prepared)) in prepared.iter().enumerate() {
                let outcome = session.execute(prepared).await;
                let context = format!("axterm exec: line {}: ", index + 1);
                print_outcome(format, target.family, line, &context, &outcome);
                if outcome.is_err() {
                    return EXIT_DEVICE;
                }
            }
            EXIT_OK
        };
        let report = RunReport {
            prefix: "axterm exec: ",
            format,
            at_the_end: AtTheEnd::Nothing,
        };
        exit_or_stop_on_signal(&session, interrupt, &report, work).await
    })
}

/// Every line with its values in an axis's unit converted on `session`'s
/// module (the conversion said on stderr) and prepared; `Err` when one
/// did not convert, validate or may not be sent without `--yes` (each
/// said).
async fn convert_lines(
    session: &Session,
    lines: Vec<(String, Option<PreparedLine>)>,
    mechanics: &MechanicsTable,
    yes: bool,
) -> Result<Vec<(String, PreparedLine)>, ()> {
    let console = session.family().console;
    let mut ready = Vec::new();
    let mut ok = true;
    // What the lines before write, for a family whose settings are known
    // from what was written (they are not sent yet).
    let mut known = session.settings().borrow().clone();
    for (index, (line, prepared)) in lines.into_iter().enumerate() {
        if let Some(prepared) = prepared {
            after_line(console, &prepared, &mut known);
            ready.push((line, prepared));
            continue;
        }
        let at = format!("axterm exec: line {} `{}`: ", index + 1, line.trim());
        let converted = match session.convert_units(&line, mechanics, &known).await {
            Ok(converted) => converted,
            Err(message) => {
                eprintln!("{at}{message}");
                ok = false;
                continue;
            }
        };
        let notes = converted.notes.join(", ");
        match console.prepare(&converted.line, session.address()) {
            Ok(prepared) => {
                eprintln!("{at}{notes}: {}", prepared.canonical);
                let said = cautions(console, &prepared, &known, yes);
                for warning in &said.warnings {
                    eprintln!("{at}{warning}");
                }
                if let Some(refusal) = said.refusal {
                    eprintln!("{at}{refusal}");
                    ok = false;
                }
                after_line(console, &prepared, &mut known);
                ready.push((line, prepared));
            }
            Err(message) => {
                eprintln!("{at}{notes}, which the line does not take: {message}");
                ok = false;
            }
        }
    }
    if ok { Ok(ready) } else { Err(()) }
}

/// Prepare every line for `family` at `address`, saying each problem
/// (after `on`, the link when there are several) and, when `cautions`,
/// the family's warnings; the lines, and whether all may be sent. A line
/// with values in an axis's unit is checked against `mechanics` (`None`:
/// several modules, where such lines are refused) and left unprepared:
/// it is converted once the module's settings are read.
fn check_lines(
    on: &str,
    family: &Family,
    address: u8,
    args: &ExecArgs,
    cautions_said: bool,
    mechanics: Option<&MechanicsTable>,
) -> (Vec<(String, Option<PreparedLine>)>, bool) {
    let console = family.console;
    let mut prepared = Vec::new();
    let mut ok = true;
    let mut known = SettingsCache::default();
    for (index, line) in args.lines.iter().enumerate() {
        let at = format!("axterm exec: {on}line {} `{}`: ", index + 1, line.trim());
        if has_units(console.units(), line) {
            let checked = match mechanics {
                Some(mechanics) => {
                    check_line(console.units(), line, mechanics).map_err(String::from)
                }
                None => Err(
                    "values in an axis's unit are converted on one module at a time: give \
                     them raw to several"
                        .to_string(),
                ),
            };
            if let Err(message) = checked {
                eprintln!("{at}{message}");
                ok = false;
            }
            prepared.push((line.clone(), None));
            continue;
        }
        match console.prepare(line, address) {
            Ok(p) => {
                let said = cautions(console, &p, &known, args.yes);
                after_line(console, &p, &mut known);
                if cautions_said {
                    for warning in &said.warnings {
                        eprintln!("{at}{warning}");
                    }
                }
                if let Some(refusal) = said.refusal {
                    eprintln!("{at}{refusal}");
                    ok = false;
                }
                prepared.push((line.clone(), Some(p)));
            }
            Err(message) => {
                eprintln!("{at}{message}");
                ok = false;
            }
        }
    }
    (prepared, ok)
}

/// Whether every line that prepares at `first` prepares at `address` too
/// (a listed module); each that does not is said.
fn other_address_takes_lines(
    on: &str,
    family: &Family,
    first: u8,
    address: u8,
    lines: &[String],
) -> bool {
    let console = family.console;
    let mut ok = true;
    for (index, line) in lines.iter().enumerate() {
        if let (Ok(_), Err(message)) =
            (console.prepare(line, first), console.prepare(line, address))
        {
            eprintln!(
                "axterm exec: {on}module {address}: line {} `{}`: {message}",
                index + 1,
                line.trim()
            );
            ok = false;
        }
    }
    ok
}

/// The lines on one module of several: each result prefixed with the
/// module (and its link, with several) in text, or carrying them in JSON;
/// the first line that fails ends this module's lines, not the others'.
async fn exec_on_module(module: &FleetModule, lines: &[String], format: Format) -> ModuleRow {
    let session = &module.session;
    let family = session.family();
    let address = module.address();
    let who = module.who();
    let identity = Identity::ask(session).await;
    let mut row = module.row(identity.shown());
    if let Identity::Silent(why) = identity {
        let on = module
            .link
            .as_ref()
            .map_or(String::new(), |l| format!("{}: ", l.label));
        eprintln!("axterm exec: {on}{why}");
        row.failed = 1;
        row.note = why;
        return row;
    }
    for (index, line) in lines.iter().enumerate() {
        // Checked for every address before anything was sent.
        let outcome = match family.console.prepare(line, address) {
            Ok(prepared) => session.execute(&prepared).await,
            Err(error) => Err(crate::session::SessionError::Refused {
                line: line.clone(),
                message: error.to_string(),
            }),
        };
        match format {
            Format::Text => {
                if let Ok(result) = &outcome {
                    println!("{who}: {}", result.value);
                    if let Some(note) = unchecked_note(family, line, result) {
                        eprintln!("axterm exec: {who}: {note}");
                    }
                }
            }
            Format::Json => {
                let mut object = json_outcome(family, line, &outcome);
                module.mark(&mut object);
                println!("{object}");
            }
        }
        match outcome {
            Ok(_) => row.written += 1,
            Err(error) => {
                eprintln!("axterm exec: {who}: line {}: {error}", index + 1);
                row.failed = 1;
                row.note = format!("line {} failed", index + 1);
                return row;
            }
        }
    }
    row.ok = true;
    row
}
