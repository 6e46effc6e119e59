//! `axterm tune step|stallguard CONNECTION`: the tuning tools from a batch
//! file ([`crate::session::tuning`]). `step` makes a servo step the
//! controller records itself and prints the samples and figures; a step
//! whose axis trips says so, and the axis is stopped. `stallguard` sweeps
//! the motor's speed and prints the load reading at each; with `--compare`
//! a sweep saved before (`--format json`, without the load) it suggests a
//! threshold and a stop-on-stall speed. Exit 0 on a result, 1 when the
//! axis tripped or a line failed, 2 for bad input (nothing sent), 3 when
//! the link does not open.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Duration;

use clap::{Args, Subcommand, ValueEnum};

use super::connection::Target;
use super::run_end::run_tool_to_exit;
use super::{ConnectionArgs, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::protocol::console::AxisInfo;
use crate::protocol::jog::Direction;
use crate::protocol::tuning::{StepAsk, StepSpec, SweepAsk, SweepPoint};
use crate::session::tuning::{CurrentRun, StepRun, SweepRun, WatchRun, saving_line};

#[derive(Debug, Clone, Subcommand)]
pub enum TuneCommand {
    /// A servo step response, recorded by the controller at its loop rate
    /// (MCCL: PR, then DR/DO/DQ): rise time, overshoot, settling,
    /// following error, output and saturation.
    Step(StepArgs),
    /// A StallGuard2 velocity sweep (TMCL AP206 at each speed); with
    /// --compare a sweep saved without load, a suggested threshold (AP174)
    /// and stop-on-stall speed (AP181).
    Stallguard(SweepArgs),
    /// A stall test: turn the motor at --speed and say whether the module
    /// stops it on a stall (TMCL: AP207's stall flag, with stop on stall
    /// AP181 below the speed) before --give-up seconds; exit 0 when it
    /// did, 1 when not.
    StallTest(StallTestArgs),
    /// The CoolStep form (TMCL AP168-172, 180, 182, 183) with the manual's
    /// meaning of each, and a watch of the actual current (AP180) and load
    /// (AP206) over time: the current's share of the AP6 current is the
    /// energy CoolStep saves.
    Coolstep(CurrentArgs),
}

#[derive(Debug, Clone, Args)]
pub struct StallTestArgs {
    /// The axis, as the family numbers it (TMCL motor 0 is 0).
    #[arg(long)]
    pub axis: Option<u8>,
    /// The speed to turn at (negative: the other way).
    #[arg(long, allow_negative_numbers = true)]
    pub speed: i64,
    /// Seconds to wait for the stall.
    #[arg(long, default_value_t = 5)]
    pub give_up: u64,
    /// Console lines to send first, separated by `;`: the suggestion
    /// `tune stallguard --compare` printed ("SAP 174, 0, -16; SAP 181, 0,
    /// 600"), to test it.
    #[arg(long, value_name = "LINES")]
    pub apply: Option<String>,
}

#[derive(Debug, Clone, Args)]
pub struct CurrentArgs {
    /// The axis, as the family numbers it (TMCL motor 0 is 0).
    #[arg(long)]
    pub axis: Option<u8>,
    /// Settings to write first, NAME=VALUE separated by commas
    /// (AP172=2,AP170=4); checked against the form before anything is
    /// sent.
    #[arg(long, value_name = "NAME=VALUE,…")]
    pub set: Option<String>,
    /// Turn the motor at this speed while watching (negative: the other
    /// way), and stop it after; without it the watch only reads.
    #[arg(long, allow_negative_numbers = true)]
    pub run: Option<i64>,
    /// How many readings.
    #[arg(long, default_value_t = 10)]
    pub samples: u32,
    /// Milliseconds between two readings.
    #[arg(long, default_value_t = 200)]
    pub every: u64,
    #[arg(long, value_enum, default_value_t)]
    pub format: TuneFormat,
}

/// How the result is printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum TuneFormat {
    /// Figures and readings as lines to read.
    #[default]
    Text,
    /// One JSON object: the samples or readings and the figures.
    Json,
    /// The samples or readings as comma-separated values, a header first.
    Csv,
}

#[derive(Debug, Clone, Args)]
pub struct StepArgs {
    /// The axis, as the family numbers it (MCCL axis 1 is 1).
    #[arg(long)]
    pub axis: Option<u8>,
    /// The step, in position counts (negative: the other way).
    #[arg(long, allow_negative_numbers = true)]
    pub distance: i64,
    /// Samples the controller records (MCCL: 1..1024).
    #[arg(long, default_value_t = 400)]
    pub samples: usize,
    /// Gains to set first, NAME=VALUE separated by commas (SG=0.05,SD=0.3);
    /// they stay set after the test.
    #[arg(long, value_name = "NAME=VALUE,…")]
    pub set: Option<String>,
    /// The settling band, in counts either side of the target.
    #[arg(long, default_value_t = 2.0)]
    pub band: f64,
    #[arg(long, value_enum, default_value_t)]
    pub format: TuneFormat,
}

#[derive(Debug, Clone, Args)]
pub struct SweepArgs {
    /// The axis, as the family numbers it (TMCL motor 0 is 0).
    #[arg(long)]
    pub axis: Option<u8>,
    /// The first speed, in the family's velocity unit (negative turns the
    /// other way).
    #[arg(long, allow_negative_numbers = true)]
    pub from: i64,
    /// The last speed.
    #[arg(long, allow_negative_numbers = true)]
    pub to: i64,
    /// How many speeds, both ends included.
    #[arg(long, default_value_t = 5)]
    pub steps: u32,
    /// Readings taken at each speed.
    #[arg(long, default_value_t = 4)]
    pub samples: u32,
    /// A sweep of the same speeds saved before without the load (this
    /// command's --format json): suggest a threshold and a stop-on-stall
    /// speed from the two.
    #[arg(long, value_name = "FILE")]
    pub compare: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t)]
    pub format: TuneFormat,
}

pub fn run(connection: &ConnectionArgs, command: &TuneCommand) -> i32 {
    match command {
        TuneCommand::Step(args) => run_step(connection, args),
        TuneCommand::Stallguard(args) => run_sweep(connection, args),
        TuneCommand::Coolstep(args) => run_current(connection, args),
        TuneCommand::StallTest(args) => run_stall_test(connection, args),
    }
}

/// The axis `number` of the family (its first by default), and its index.
fn axis_of(target: &Target, number: Option<u8>) -> Result<(usize, AxisInfo), String> {
    let axes = target.family.console.axes();
    let found = match number {
        None => axes.first().map(|a| (0, *a)),
        Some(n) => axes
            .iter()
            .enumerate()
            .find(|(_, a)| a.number == n)
            .map(|(i, a)| (i, *a)),
    };
    found.ok_or_else(|| {
        format!(
            "--axis {}: the {} family's axes are {}",
            number.map_or_else(|| "?".to_string(), |n| n.to_string()),
            target.family.name,
            axes.iter()
                .map(|a| a.number.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )
    })
}

pub use crate::protocol::tuning::parse_settings;

fn run_step(connection: &ConnectionArgs, args: &StepArgs) -> i32 {
    let target = match Target::resolve(connection) {
        Ok(target) => target,
        Err(message) => {
            eprintln!("axterm tune step: {message}");
            return EXIT_USAGE;
        }
    };
    let Some(plan) = target.family.console.step_response() else {
        eprintln!(
            "axterm tune step: the {} family has no servo step-response test (MCCL has)",
            target.family.name
        );
        return EXIT_USAGE;
    };
    let (index, axis) = match axis_of(&target, args.axis) {
        Ok(found) => found,
        Err(message) => {
            eprintln!("axterm tune step: {message}");
            return EXIT_USAGE;
        }
    };
    let set = match args.set.as_deref().map(parse_settings).transpose() {
        Ok(set) => set.unwrap_or_default(),
        Err(message) => {
            eprintln!("axterm tune step: {message}");
            return EXIT_USAGE;
        }
    };
    if !(args.band.is_finite() && args.band > 0.0) {
        eprintln!(
            "axterm tune step: --band {}: a band is a number of counts > 0",
            args.band
        );
        return EXIT_USAGE;
    }
    let ask = StepAsk {
        distance: args.distance,
        samples: args.samples,
        set,
    };
    // Everything the plan refuses is refused before the link opens.
    if let Err(why) = plan.script(&axis, &ask) {
        eprintln!("axterm tune step: {why} (nothing was sent)");
        return EXIT_USAGE;
    }
    let spec = StepSpec {
        band: args.band,
        ..StepSpec::default()
    };
    let format = args.format;
    run_tool_to_exit(
        "tune step",
        target,
        Box::new(move |session| {
            Box::pin(async move {
                match session.step_response(plan, index, &ask, &spec).await {
                    Ok(run) => {
                        print!("{}", show_step(&axis, &run, format));
                        if run.tripped.is_empty() {
                            EXIT_OK
                        } else {
                            EXIT_DEVICE
                        }
                    }
                    Err(error) => {
                        eprintln!("axterm tune step: {error}");
                        EXIT_DEVICE
                    }
                }
            })
        }),
    )
}

fn number(value: Option<f64>) -> serde_json::Value {
    value.map_or(serde_json::Value::Null, serde_json::Value::from)
}

/// A step test's result in `format`.
pub fn show_step(axis: &AxisInfo, run: &StepRun, format: TuneFormat) -> String {
    let mut out = String::new();
    match format {
        TuneFormat::Csv => {
            out.push_str("time_s,commanded,actual,following_error,output_v\n");
            for s in &run.samples {
                let _ = writeln!(
                    out,
                    "{},{},{},{},{}",
                    s.time,
                    s.commanded,
                    s.actual,
                    s.commanded - s.actual,
                    s.output
                );
            }
        }
        TuneFormat::Json => {
            let figures = run.figures.as_ref().map(|f| {
                serde_json::json!({
                    "target": f.target,
                    "rise_time_s": number(f.rise_time),
                    "overshoot_percent": f.overshoot_percent,
                    "settling_time_s": number(f.settling_time),
                    "peak_following_error": f.peak_following_error,
                    "final_following_error": f.final_following_error,
                    "peak_output_v": f.peak_output,
                    "saturated": f.saturated,
                })
            });
            let object = serde_json::json!({
                "axis": axis.number,
                "sample_period_s": run.sample_period,
                "gains": run
                    .gains
                    .iter()
                    .map(|(name, value)| ((*name).to_string(), number(*value)))
                    .collect::<serde_json::Map<_, _>>(),
                "samples": run
                    .samples
                    .iter()
                    .map(|s| serde_json::json!({
                        "time_s": s.time,
                        "commanded": s.commanded,
                        "actual": s.actual,
                        "output_v": s.output,
                    }))
                    .collect::<Vec<_>>(),
                "figures": figures,
                "figures_missing": run.figures_missing,
                "tripped": run.tripped.iter().map(|f| f.name).collect::<Vec<_>>(),
                "ok": run.tripped.is_empty(),
            });
            let _ = writeln!(out, "{object}");
        }
        TuneFormat::Text => {
            for line in step_lines(axis, run) {
                let _ = writeln!(out, "{line}");
            }
        }
    }
    out
}

pub use crate::session::tuning::{step_lines, step_plot, sweep_lines, sweep_plot};

fn run_sweep(connection: &ConnectionArgs, args: &SweepArgs) -> i32 {
    let target = match Target::resolve(connection) {
        Ok(target) => target,
        Err(message) => {
            eprintln!("axterm tune stallguard: {message}");
            return EXIT_USAGE;
        }
    };
    let Some(plan) = target.family.console.stall_sweep() else {
        eprintln!(
            "axterm tune stallguard: the {} family has no StallGuard2 sweep (TMCL has)",
            target.family.name
        );
        return EXIT_USAGE;
    };
    let (index, axis) = match axis_of(&target, args.axis) {
        Ok(found) => found,
        Err(message) => {
            eprintln!("axterm tune stallguard: {message}");
            return EXIT_USAGE;
        }
    };
    let ask = SweepAsk {
        from: args.from,
        to: args.to,
        steps: args.steps,
        samples: args.samples,
    };
    if let Err(why) = plan.script(&axis, &ask) {
        eprintln!("axterm tune stallguard: {why} (nothing was sent)");
        return EXIT_USAGE;
    }
    let free = match &args.compare {
        None => None,
        Some(path) => match read_sweep(path) {
            Ok(points) => Some(points),
            Err(message) => {
                eprintln!(
                    "axterm tune stallguard: --compare {}: {message}",
                    path.display()
                );
                return EXIT_USAGE;
            }
        },
    };
    let format = args.format;
    run_tool_to_exit(
        "tune stallguard",
        target,
        Box::new(move |session| {
            Box::pin(async move {
                match session.stall_sweep(plan, index, &ask).await {
                    Ok(run) => {
                        let suggestion = free.as_ref().map(|free| {
                            plan.suggest(&axis, free, &run.points, run.threshold.unwrap_or(0))
                        });
                        print!(
                            "{}",
                            show_sweep(plan.reading(), &run, suggestion.as_ref(), format)
                        );
                        EXIT_OK
                    }
                    Err(error) => {
                        eprintln!("axterm tune stallguard: {error}");
                        EXIT_DEVICE
                    }
                }
            })
        }),
    )
}

fn run_stall_test(connection: &ConnectionArgs, args: &StallTestArgs) -> i32 {
    let target = match Target::resolve(connection) {
        Ok(target) => target,
        Err(message) => {
            eprintln!("axterm tune stall-test: {message}");
            return EXIT_USAGE;
        }
    };
    let Some(plan) = target.family.console.stall_sweep() else {
        eprintln!(
            "axterm tune stall-test: the {} family has no stall detection (TMCL has)",
            target.family.name
        );
        return EXIT_USAGE;
    };
    let (index, axis) = match axis_of(&target, args.axis) {
        Ok(found) => found,
        Err(message) => {
            eprintln!("axterm tune stall-test: {message}");
            return EXIT_USAGE;
        }
    };
    let ask = SweepAsk {
        from: args.speed,
        to: args.speed,
        steps: 1,
        samples: 1,
    };
    if let Err(why) = plan.script(&axis, &ask) {
        eprintln!("axterm tune stall-test: {why} (nothing was sent)");
        return EXIT_USAGE;
    }
    let apply: Vec<String> = args
        .apply
        .as_deref()
        .unwrap_or_default()
        .split(';')
        .map(str::trim)
        .filter(|line| !line.is_empty())
        .map(str::to_string)
        .collect();
    let console = target.family.console;
    for line in &apply {
        if let Err(why) = console.prepare(line, target.address) {
            eprintln!("axterm tune stall-test: --apply {line}: {why} (nothing was sent)");
            return EXIT_USAGE;
        }
    }
    let (speed, give_up) = (args.speed, Duration::from_secs(args.give_up));
    run_tool_to_exit(
        "tune stall-test",
        target,
        Box::new(move |session| {
            Box::pin(async move {
                for line in &apply {
                    if let Err(error) = session.execute_line(line).await {
                        eprintln!("axterm tune stall-test: {line}: {error}");
                        return EXIT_DEVICE;
                    }
                }
                match session.stall_test(plan, index, speed, give_up).await {
                    Ok(outcome) => {
                        let fastest = outcome
                            .fastest
                            .map_or_else(|| "unread".to_string(), |f| f.to_string());
                        match outcome.detected_after {
                            Some(after) => {
                                println!(
                                    "{}: stall detected: the module stopped the motor {:.2} s after \
                                 the start (fastest read {fastest})",
                                    axis.name,
                                    after.as_secs_f64()
                                );
                                EXIT_OK
                            }
                            None => {
                                println!(
                                    "{}: NO stall detected within {} s at {speed} (fastest read \
                                 {fastest}): is stop on stall set below this speed, and the \
                                 threshold sensitive enough?",
                                    axis.name,
                                    give_up.as_secs()
                                );
                                EXIT_DEVICE
                            }
                        }
                    }
                    Err(error) => {
                        eprintln!("axterm tune stall-test: {error}");
                        EXIT_DEVICE
                    }
                }
            })
        }),
    )
}

fn run_current(connection: &ConnectionArgs, args: &CurrentArgs) -> i32 {
    let target = match Target::resolve(connection) {
        Ok(target) => target,
        Err(message) => {
            eprintln!("axterm tune coolstep: {message}");
            return EXIT_USAGE;
        }
    };
    let Some(plan) = target.family.console.current_control() else {
        eprintln!(
            "axterm tune coolstep: the {} family has no CoolStep current control (TMCL has)",
            target.family.name
        );
        return EXIT_USAGE;
    };
    let (index, axis) = match axis_of(&target, args.axis) {
        Ok(found) => found,
        Err(message) => {
            eprintln!("axterm tune coolstep: {message}");
            return EXIT_USAGE;
        }
    };
    let set = match args.set.as_deref().map(parse_settings).transpose() {
        Ok(set) => set.unwrap_or_default(),
        Err(message) => {
            eprintln!("axterm tune coolstep: {message}");
            return EXIT_USAGE;
        }
    };
    let mut whole = Vec::new();
    for (name, value) in set {
        if value.fract() != 0.0 {
            eprintln!(
                "axterm tune coolstep: --set {name}={value}: a whole number (nothing was sent)"
            );
            return EXIT_USAGE;
        }
        if let Err(why) = plan.write(&axis, &name, value as i64) {
            eprintln!("axterm tune coolstep: --set {name}: {why} (nothing was sent)");
            return EXIT_USAGE;
        }
        whole.push((name, value as i64));
    }
    let jog = target.family.console.jog();
    let run = match (args.run, jog) {
        (None, _) => None,
        (Some(_), None) => {
            eprintln!(
                "axterm tune coolstep: --run: the {} family has no jog",
                target.family.name
            );
            return EXIT_USAGE;
        }
        (Some(speed), Some(jog)) => {
            let direction = if speed < 0 {
                Direction::Negative
            } else {
                Direction::Positive
            };
            if let Err(why) = jog.run(&axis, direction, speed.abs()) {
                eprintln!("axterm tune coolstep: --run {speed}: {why} (nothing was sent)");
                return EXIT_USAGE;
            }
            Some((jog, direction, speed.abs()))
        }
    };
    if args.samples == 0 {
        eprintln!("axterm tune coolstep: --samples 0: a watch takes one reading or more");
        return EXIT_USAGE;
    }
    let (samples, every, format) = (args.samples, Duration::from_millis(args.every), args.format);
    run_tool_to_exit(
        "tune coolstep",
        target,
        Box::new(move |session| {
            Box::pin(async move {
                let run = run.map(|(jog, direction, speed)| WatchRun {
                    jog,
                    direction,
                    speed,
                });
                match session
                    .watch_current(plan, index, &whole, run, samples, every)
                    .await
                {
                    Ok(run) => {
                        print!("{}", show_current(&run, format));
                        EXIT_OK
                    }
                    Err(error) => {
                        eprintln!("axterm tune coolstep: {error}");
                        EXIT_DEVICE
                    }
                }
            })
        }),
    )
}

/// A current watch in `format`.
pub fn show_current(run: &CurrentRun, format: TuneFormat) -> String {
    let mut out = String::new();
    let shown = |v: Option<i64>| v.map_or_else(|| "-".to_string(), |v| v.to_string());
    let percent =
        |v: Option<f64>| v.map_or_else(|| "-".to_string(), |v| format!("{:.0}", v * 100.0));
    match format {
        TuneFormat::Csv => {
            out.push_str("time_s,speed,current,load,share_percent\n");
            for s in &run.samples {
                let _ = writeln!(
                    out,
                    "{:.3},{},{},{},{}",
                    s.time,
                    shown(s.speed),
                    shown(s.current),
                    shown(s.load),
                    percent(s.share)
                );
            }
        }
        TuneFormat::Json => {
            let object = serde_json::json!({
                "form": run.form.iter().map(|(f, v)| serde_json::json!({
                    "name": f.name,
                    "title": f.title,
                    "meaning": f.meaning,
                    "value": v,
                    "range": [f.min, f.max],
                    "writable": f.writable,
                })).collect::<Vec<_>>(),
                "full": run.full,
                "samples": run.samples.iter().map(|s| serde_json::json!({
                    "time_s": s.time,
                    "speed": s.speed,
                    "current": s.current,
                    "load": s.load,
                    "share": s.share,
                })).collect::<Vec<_>>(),
                "mean_share": run.mean_share(),
            });
            let _ = writeln!(out, "{object}");
        }
        TuneFormat::Text => {
            for (field, value) in &run.form {
                let _ = writeln!(
                    out,
                    "{:<6} {:>5}  {} ({}..{}{}): {}",
                    field.name,
                    shown(*value),
                    field.title,
                    field.min,
                    field.max,
                    if field.writable { "" } else { ", read only" },
                    field.meaning
                );
            }
            for s in &run.samples {
                let _ = writeln!(
                    out,
                    "{:>7.3} s: speed {}, current {}, load {}, {} % of the full current",
                    s.time,
                    shown(s.speed),
                    shown(s.current),
                    shown(s.load),
                    percent(s.share)
                );
            }
            if let Some(mean) = run.mean_share() {
                let _ = writeln!(out, "{}", saving_line(mean, run.full));
            }
        }
    }
    out
}

/// The points of a sweep saved with `--format json`.
fn read_sweep(path: &std::path::Path) -> Result<Vec<SweepPoint>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    if text.trim().is_empty() {
        return Err("the file is empty: it holds no sweep".into());
    }
    let value: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("not a sweep saved as JSON: {e}"))?;
    let points: Vec<SweepPoint> = serde_json::from_value(value["points"].clone())
        .map_err(|e| format!("no \"points\" of a sweep: {e}"))?;
    if points.is_empty() || points.iter().any(|p| p.readings.is_empty()) {
        return Err("the sweep holds no readings".into());
    }
    Ok(points)
}

/// A sweep's result in `format`.
pub fn show_sweep(
    reading: &str,
    run: &SweepRun,
    suggestion: Option<&crate::protocol::tuning::SweepSuggestion>,
    format: TuneFormat,
) -> String {
    let mut out = String::new();
    match format {
        TuneFormat::Csv => {
            out.push_str("speed,mean,readings\n");
            for p in &run.points {
                let readings: Vec<String> = p.readings.iter().map(i64::to_string).collect();
                let _ = writeln!(
                    out,
                    "{},{},{}",
                    p.speed,
                    p.mean().map_or_else(String::new, |m| m.to_string()),
                    readings.join(" ")
                );
            }
        }
        TuneFormat::Json => {
            let object = serde_json::json!({
                "reading": reading,
                "threshold": run.threshold,
                "points": run
                    .points
                    .iter()
                    .map(|p| serde_json::json!({
                        "speed": p.speed,
                        "readings": p.readings,
                        "mean": p.mean(),
                    }))
                    .collect::<Vec<_>>(),
                "suggestion": suggestion.map(|s| serde_json::json!({
                    "reasons": s.reasons,
                    "lines": s.lines,
                })),
            });
            let _ = writeln!(out, "{object}");
        }
        TuneFormat::Text => {
            for line in sweep_lines(reading, run) {
                let _ = writeln!(out, "{line}");
            }
            if let Some(s) = suggestion {
                for reason in &s.reasons {
                    let _ = writeln!(out, "{reason}");
                }
                if s.lines.is_empty() {
                    let _ = writeln!(out, "no suggestion to set");
                } else {
                    let _ = writeln!(out, "to set it: {}", s.lines.join("; "));
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_read_as_names_and_numbers_and_bad_ones_are_named() {
        assert_eq!(
            parse_settings("SG=0.05, SD=0.3,").unwrap(),
            [("SG".to_string(), 0.05), ("SD".to_string(), 0.3)]
        );
        let error = |text| parse_settings(text).unwrap_err().to_string();
        assert!(error("SG").contains("NAME=VALUE"));
        assert!(error("SG=fast").contains("fast is not a number"));
        assert!(error("SG=inf").contains("inf"));
    }
}
