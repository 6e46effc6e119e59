//! `axterm exec CONNECTION LINE...`: run console lines in order, one
//! result line each. Every line is parsed and validated before anything is
//! sent, and a line the family wants confirmed needs `--yes`; the first
//! line that fails stops the rest.

use clap::Args;

use super::confirm::{after_line, cautions};
use super::connection::{Target, run_to_exit};
use super::fleet::{self, FleetArgs, Identity, ModuleRow, Modules};
use super::output::{Format, json_outcome, print_outcome};
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::protocol::Family;
use crate::protocol::settings::SettingsCache;
use crate::session::Session;

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

pub fn run(connection: &ConnectionArgs, args: &ExecArgs) -> i32 {
    let target = match Target::resolve(connection) {
        Ok(target) => target,
        Err(message) => {
            eprintln!("axterm exec: {message}");
            return EXIT_USAGE;
        }
    };
    let modules = match Modules::from_args(&args.fleet, target.family) {
        Ok(modules) => modules,
        Err(message) => {
            eprintln!("axterm exec: {message}");
            return EXIT_USAGE;
        }
    };
    let console = target.family.console;
    let mut prepared = Vec::new();
    let mut refused = false;
    let mut known = SettingsCache::default();
    for (index, line) in args.lines.iter().enumerate() {
        match console.prepare(line, target.address) {
            Ok(p) => {
                let at = format!("axterm exec: line {} `{}`: ", index + 1, line.trim());
                let said = cautions(console, &p, &known, args.yes);
                after_line(console, &p, &mut known);
                for warning in &said.warnings {
                    eprintln!("{at}{warning}");
                }
                if let Some(refusal) = said.refusal {
                    eprintln!("{at}{refusal}");
                    refused = true;
                }
                prepared.push((line.clone(), p));
            }
            Err(message) => {
                eprintln!(
                    "axterm exec: line {} `{}`: {message}",
                    index + 1,
                    line.trim()
                );
                refused = true;
            }
        }
    }
    if let Modules::List(addresses) = &modules {
        for &address in addresses {
            for (index, line) in args.lines.iter().enumerate() {
                if let (Ok(_), Err(message)) = (
                    console.prepare(line, target.address),
                    console.prepare(line, address),
                ) {
                    eprintln!(
                        "axterm exec: module {address}: line {} `{}`: {message}",
                        index + 1,
                        line.trim()
                    );
                    refused = true;
                }
            }
        }
    }
    if refused {
        eprintln!("axterm exec: nothing was sent");
        return EXIT_USAGE;
    }
    let format = args.format;
    if modules.several() {
        let lines = args.lines.clone();
        let stop_on_failure = args.fleet.stop_on_failure;
        return run_to_exit("exec", async move {
            let session = match target.open().await {
                Ok(session) => session,
                Err(e) => {
                    eprintln!("axterm exec: {e}");
                    return EXIT_CONNECTION;
                }
            };
            let sessions = fleet::sessions(&session, &modules, &target.spec, "exec").await;
            let lines = &lines;
            let rows = fleet::each_module(&sessions, stop_on_failure, move |module| async move {
                exec_on_module(&module, target.family, lines, format).await
            })
            .await;
            fleet::finish(&rows, &["lines", "failed"], format)
        });
    }
    run_to_exit("exec", async move {
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm exec: {e}");
                return EXIT_CONNECTION;
            }
        };
        for (index, (line, prepared)) in prepared.iter().enumerate() {
            let outcome = session.execute(prepared).await;
            let context = format!("axterm exec: line {}: ", index + 1);
            print_outcome(format, target.family, line, &context, &outcome);
            if outcome.is_err() {
                return EXIT_DEVICE;
            }
        }
        EXIT_OK
    })
}

/// The lines on one module of several: each result prefixed with the
/// module (text) or carrying it (JSON); the first line that fails ends
/// this module's lines, not the others'.
async fn exec_on_module(
    session: &Session,
    family: &'static Family,
    lines: &[String],
    format: Format,
) -> ModuleRow {
    let address = session.address();
    let identity = Identity::ask(session).await;
    let mut row = ModuleRow {
        address,
        firmware: identity.shown(),
        ..ModuleRow::default()
    };
    if let Identity::Silent(why) = identity {
        eprintln!("axterm exec: {why}");
        row.failed = 1;
        row.note = why;
        return row;
    }
    for (index, line) in lines.iter().enumerate() {
        // Checked for every address before anything was sent.
        let outcome = match family.console.prepare(line, address) {
            Ok(prepared) => session.execute(&prepared).await,
            Err(message) => Err(crate::session::SessionError::Refused {
                line: line.clone(),
                message,
            }),
        };
        match format {
            Format::Text => {
                if let Ok(result) = &outcome {
                    println!("module {address}: {}", result.value);
                }
            }
            Format::Json => {
                let mut object = json_outcome(family, line, &outcome);
                object["module"] = serde_json::json!(address);
                println!("{object}");
            }
        }
        match outcome {
            Ok(_) => row.written += 1,
            Err(error) => {
                eprintln!("axterm exec: module {address}: line {}: {error}", index + 1);
                row.failed = 1;
                row.note = format!("line {} failed", index + 1);
                return row;
            }
        }
    }
    row.ok = true;
    row
}
