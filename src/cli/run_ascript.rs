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

use clap::Args;

use super::ConnectionArgs;
use super::run_host::{HostCommand, HostRunArgs};

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

/// The language `run-ascript` runs.
pub const COMMAND: HostCommand = HostCommand {
    name: "run-ascript",
};

pub fn run(connection: &ConnectionArgs, args: &RunAscriptArgs) -> i32 {
    let start = (!args.prg.is_empty()).then_some(args.prg.as_slice());
    super::run_host::run(
        &COMMAND,
        connection,
        &HostRunArgs {
            file: &args.file,
            start,
            dry_run: args.dry_run,
            no_stop_on_failure: args.no_stop_on_failure,
            yes: false,
        },
    )
}
