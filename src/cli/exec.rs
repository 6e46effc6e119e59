//! `axterm exec CONNECTION LINE...`: run console lines in order, one
//! result line each. Every line is parsed and validated before anything is
//! sent, and a line the family wants confirmed needs `--yes`; the first
//! line that fails stops the rest.

use clap::Args;

use super::confirm::{after_line, cautions};
use super::connection::{Target, run_to_exit};
use super::output::{Format, print_outcome};
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::protocol::settings::SettingsCache;

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
}

pub fn run(connection: &ConnectionArgs, args: &ExecArgs) -> i32 {
    let target = match Target::resolve(connection) {
        Ok(target) => target,
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
    if refused {
        eprintln!("axterm exec: nothing was sent");
        return EXIT_USAGE;
    }
    let format = args.format;
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
