//! `axterm wiring CONNECTION --yes`: the guided wiring check of an axis
//! ([`crate::session::wiring`]): it jogs the axis toward + until a limit
//! switch fires, then toward −, and prints what it found, a plain line
//! each. Exit 0 when each switch fired for its own direction and the
//! module stopped the axis at it, 1 otherwise (or on a device error), 2
//! for bad input. Ctrl-C, SIGTERM and SIGHUP stop the axes as for `exec`.

use std::time::Duration;

use clap::Args;

use super::connection::Target;
use super::run_end::run_tool_to_exit;
use super::{ConnectionArgs, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::session::wiring::{findings, wired_right};

#[derive(Debug, Clone, Args)]
pub struct WiringArgs {
    /// The axis to check (its number as the family counts them: TMCL
    /// motor 0, CMD-4CR X=0, MCCL axis 1 is 0, SIXpack 2 motor 0).
    #[arg(long, default_value_t = 0)]
    pub axis: usize,
    /// The jog speed, in the family's speed unit (the bring-up pane's
    /// list shows it); by default the slowest but one of that list.
    #[arg(long)]
    pub speed: Option<i64>,
    /// Give up a direction after this many seconds without a limit switch.
    #[arg(long, default_value_t = 30)]
    pub give_up: u64,
    /// The check moves the axis to both ends of its travel: say so.
    #[arg(long)]
    pub yes: bool,
}

pub fn run(connection: &ConnectionArgs, args: &WiringArgs) -> i32 {
    let target = match Target::resolve(connection) {
        Ok(target) => target,
        Err(message) => {
            eprintln!("axterm wiring: {message}");
            return EXIT_USAGE;
        }
    };
    let family = target.family;
    let Some(plan) = family.console.jog() else {
        eprintln!("axterm wiring: the {} family has no jog", family.name);
        return EXIT_USAGE;
    };
    let axes = family.console.axes();
    let Some(axis) = axes.get(args.axis).copied() else {
        eprintln!(
            "axterm wiring: --axis {}: the {} family has axes 0..{}",
            args.axis,
            family.name,
            axes.len().saturating_sub(1)
        );
        return EXIT_USAGE;
    };
    let speed = args
        .speed
        .unwrap_or_else(|| plan.speeds().get(1).copied().unwrap_or(1));
    if let Err(why) = plan.run(&axis, crate::protocol::jog::Direction::Positive, speed) {
        eprintln!("axterm wiring: --speed {speed}: {why}");
        return EXIT_USAGE;
    }
    if !args.yes {
        eprintln!(
            "axterm wiring: the check runs {} to both ends of its travel, until a limit \
             switch stops it: give --yes to go ahead (nothing was sent)",
            axis.name
        );
        return EXIT_USAGE;
    }
    let index = args.axis;
    let give_up = Duration::from_secs(args.give_up);
    run_tool_to_exit(
        "wiring",
        target,
        Box::new(move |session| {
            Box::pin(async move {
                match session.check_wiring(plan, index, speed, give_up).await {
                    Ok(legs) => {
                        for line in findings(axis.name, &legs) {
                            println!("{line}");
                        }
                        if wired_right(&legs) {
                            EXIT_OK
                        } else {
                            EXIT_DEVICE
                        }
                    }
                    Err(error) => {
                        eprintln!("axterm wiring: {error}");
                        // The axis may still move: stop everything.
                        let _ = session.emergency_stop_lines().await;
                        EXIT_DEVICE
                    }
                }
            })
        }),
    )
}
