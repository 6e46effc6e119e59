//! `axterm run-macro CONNECTION FILE`: an SQPack macro file (SIXpack 2,
//! §5.4.6) played from the host, the only way a macro ever reaches the
//! unit (it stores no program). The whole file is checked first (exactly
//! nine hex values a `SendToPack` line, documented commands' values in
//! range, each problem as `FILE:LINE:COLUMN:`), and nothing is sent if
//! one is wrong; frames the family wants confirmed (`$22`, `$CC`, …)
//! need `--yes`. Each frame is printed with its answer (`sent` for the
//! many the unit never answers, the fields of a query's), paced as
//! [`crate::protocol::sixpack2::tool`] says. A playback that fails, is
//! stopped with Ctrl-C or loses its link ends with the emergency stop
//! unless `--no-stop-on-failure` (see [`super::run_host`]).

use clap::Args;

use super::ConnectionArgs;
use super::run_host::{HostCommand, HostRunArgs};

#[derive(Debug, Clone, Args)]
pub struct RunMacroArgs {
    /// The macro file, or - for standard input.
    pub file: String,
    /// Check the file only: send nothing (no connection needed; the
    /// options of one given are checked too, nothing is opened).
    #[arg(long)]
    pub dry_run: bool,
    /// When the playback fails, is stopped (Ctrl-C) or loses its link,
    /// leave the axes as they are. By default the emergency stop is sent
    /// then, waiting up to 10 s for a lost link to come back.
    #[arg(long)]
    pub no_stop_on_failure: bool,
    /// Send the frames the family wants confirmed (a reference search,
    /// PI control, a reset, a baud or address change); without it the
    /// file is refused and nothing is sent.
    #[arg(long)]
    pub yes: bool,
}

/// The language `run-macro` plays.
pub const COMMAND: HostCommand = HostCommand { name: "run-macro" };

pub fn run(connection: &ConnectionArgs, args: &RunMacroArgs) -> i32 {
    super::run_host::run(
        &COMMAND,
        connection,
        &HostRunArgs {
            file: &args.file,
            start: None,
            dry_run: args.dry_run,
            no_stop_on_failure: args.no_stop_on_failure,
            yes: args.yes,
        },
    )
}
