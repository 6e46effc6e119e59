//! The batch file syntax of `axterm run` and of the console's `:run`
//! (and its directives typed one at a time): one console line per line,
//! with comments and a few directives. Shared by both front ends, so it
//! lives outside `cli/`.
//!
//! ```text
//! # comment              // comment          (blank lines are ignored too)
//! SAP 4, 0, 1000         a console line, run as in `exec`
//! :expect GAP 4, 0 == 1000
//! :wait-until GAP 8, 0 == 1 timeout 30s
//! :sleep 500ms
//! :echo homing done
//! :leave-moving           the file means to leave an axis moving at its end
//! :params axis.toml --store
//! :wiring --axis 0 --speed 2047 --give-up 10
//! :tune-step --axis 1 --distance 1000 --set SG=0.05
//! :tune-stallguard --axis 0 --from 200 --to 1000 --steps 5
//! ```
//!
//! The tool directives (`:wiring`, `:tune-step`, `:tune-stallguard`) run
//! the session's tools ([`crate::session::wiring`],
//! [`crate::session::tuning`]) for a family that has them; whether it has
//! them, the axis and every value are checked with the file, before
//! anything is sent ([`tool_plan`]).
//!
//! A run that ends with an axis still moving says so and, unless the file
//! says `:leave-moving` (anywhere in it), stops it as a failed run is
//! stopped: a file that starts a motion and ends before the motion does
//! (or a recording replayed) must not leave a motor running by mistake.
//!
//! This module knows only the syntax; the console lines themselves are
//! checked by the protocol family before anything is sent.

use std::time::Duration;

use crate::protocol::Family;
use crate::protocol::console::{AxisInfo, Effect, PreparedLine};

/// Pause between the reads of `:wait-until`: quick enough to notice a move
/// ending, and leaves the line free for others in between.
pub const WAIT_INTERVAL: Duration = Duration::from_millis(20);

/// How long `:wait-until` waits when the line gives no `timeout`.
pub const DEFAULT_WAIT_TIMEOUT: Duration = Duration::from_secs(10);

/// The longest duration a file may ask for (a day): a typo such as
/// `:sleep 100000m` must not hang a batch job for months.
pub const MAX_DURATION: Duration = Duration::from_secs(24 * 60 * 60);

/// One thing a batch file asks for.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// A console line, as typed.
    Line(String),
    /// Run the line; fail unless its result equals `value`.
    Expect {
        line: String,
        value: String,
    },
    /// Run the line again and again until its result equals `value`; fail
    /// after `timeout`. The line must only read.
    WaitUntil {
        line: String,
        value: String,
        timeout: Duration,
    },
    Sleep(Duration),
    /// Print the text.
    Echo(String),
    /// The file means to leave an axis moving when it ends: the run is not
    /// stopped for that ([`LEAVE_MOVING`]). Does nothing where it stands.
    LeaveMoving,
    /// Apply a parameter file (as `axterm params apply`), with `store`
    /// storing its settings to EEPROM/flash afterwards. The path is as
    /// written; a front end resolves it (`axterm run`: beside the run
    /// file) and checks the file before anything is sent.
    ApplyParams {
        file: String,
        store: bool,
    },
    /// The guided wiring check of an axis (`axterm wiring`): the file
    /// saying it is the consent to move the axis to both ends.
    Wiring(WiringAsk),
    /// A servo step response (`axterm tune step`).
    TuneStep(TuneStepAsk),
    /// A StallGuard2 velocity sweep (`axterm tune stallguard`).
    TuneStallguard(TuneSweepAsk),
}

/// What `:wiring` asks for.
#[derive(Debug, Clone, PartialEq)]
pub struct WiringAsk {
    /// The axis as an index into the family's axes (`axterm wiring --axis`).
    pub axis: usize,
    /// The jog speed; by default the slowest but one of the family's list.
    pub speed: Option<i64>,
    /// Give up a direction after this long without a limit switch.
    pub give_up: Duration,
}

/// What `:tune-step` asks for (`axterm tune step`'s options).
#[derive(Debug, Clone, PartialEq)]
pub struct TuneStepAsk {
    /// The axis as the family numbers it; its first by default.
    pub axis: Option<u8>,
    pub distance: i64,
    pub samples: usize,
    pub set: Vec<(String, f64)>,
    /// The settling band, in counts either side of the target.
    pub band: f64,
}

/// What `:tune-stallguard` asks for (`axterm tune stallguard`'s options).
#[derive(Debug, Clone, PartialEq)]
pub struct TuneSweepAsk {
    pub axis: Option<u8>,
    pub from: i64,
    pub to: i64,
    pub steps: u32,
    pub samples: u32,
}

/// How long `:wiring` looks for a switch in each direction by default (as
/// `axterm wiring`).
pub const DEFAULT_WIRING_GIVE_UP: Duration = Duration::from_secs(30);

/// A tool directive resolved against a family: its plan, the axis (its
/// index and info) and what the plan was asked, all checked.
pub enum ToolPlan {
    Wiring {
        plan: &'static dyn crate::protocol::jog::JogPlan,
        index: usize,
        axis: AxisInfo,
        speed: i64,
        give_up: Duration,
    },
    Step {
        plan: &'static dyn crate::protocol::tuning::StepResponsePlan,
        index: usize,
        axis: AxisInfo,
        ask: crate::protocol::tuning::StepAsk,
        spec: crate::protocol::tuning::StepSpec,
    },
    Sweep {
        plan: &'static dyn crate::protocol::tuning::StallSweepPlan,
        index: usize,
        axis: AxisInfo,
        ask: crate::protocol::tuning::SweepAsk,
    },
}

/// The axis the family numbers `number` (its first when `None`), and its
/// index.
fn axis_numbered(family: &Family, number: Option<u8>) -> Result<(usize, AxisInfo), String> {
    let axes = family.console.axes();
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
            family.name,
            axes.iter()
                .map(|a| a.number.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )
    })
}

/// The tool `action` asks for, checked for `family` (the family has it,
/// the axis exists, the plan takes every value); `None` for an action
/// that is no tool directive. Nothing is sent.
pub fn tool_plan(action: &Action, family: &Family) -> Option<Result<ToolPlan, String>> {
    use crate::protocol::tuning::{StepAsk, StepSpec, SweepAsk};
    let plan = match action {
        Action::Wiring(ask) => (|| {
            let plan = family
                .console
                .jog()
                .ok_or_else(|| format!(":wiring: the {} family has no jog", family.name))?;
            let axes = family.console.axes();
            let axis = axes.get(ask.axis).copied().ok_or_else(|| {
                format!(
                    ":wiring --axis {}: the {} family has axes 0..{}",
                    ask.axis,
                    family.name,
                    axes.len().saturating_sub(1)
                )
            })?;
            let speed = ask
                .speed
                .unwrap_or_else(|| plan.speeds().get(1).copied().unwrap_or(1));
            plan.run(&axis, crate::protocol::jog::Direction::Positive, speed)
                .map_err(|why| format!(":wiring --speed {speed}: {why}"))?;
            Ok(ToolPlan::Wiring {
                plan,
                index: ask.axis,
                axis,
                speed,
                give_up: ask.give_up,
            })
        })(),
        Action::TuneStep(ask) => (|| {
            let plan = family.console.step_response().ok_or_else(|| {
                format!(
                    ":tune-step: the {} family has no servo step-response test (MCCL has)",
                    family.name
                )
            })?;
            let (index, axis) =
                axis_numbered(family, ask.axis).map_err(|why| format!(":tune-step {why}"))?;
            let step = StepAsk {
                distance: ask.distance,
                samples: ask.samples,
                set: ask.set.clone(),
            };
            plan.script(&axis, &step)
                .map_err(|why| format!(":tune-step: {why}"))?;
            Ok(ToolPlan::Step {
                plan,
                index,
                axis,
                ask: step,
                spec: StepSpec {
                    band: ask.band,
                    ..StepSpec::default()
                },
            })
        })(),
        Action::TuneStallguard(ask) => (|| {
            let plan = family.console.stall_sweep().ok_or_else(|| {
                format!(
                    ":tune-stallguard: the {} family has no StallGuard2 sweep (TMCL has)",
                    family.name
                )
            })?;
            let (index, axis) =
                axis_numbered(family, ask.axis).map_err(|why| format!(":tune-stallguard {why}"))?;
            let sweep = SweepAsk {
                from: ask.from,
                to: ask.to,
                steps: ask.steps,
                samples: ask.samples,
            };
            plan.script(&axis, &sweep)
                .map_err(|why| format!(":tune-stallguard: {why}"))?;
            Ok(ToolPlan::Sweep {
                plan,
                index,
                axis,
                ask: sweep,
            })
        })(),
        _ => return None,
    };
    Some(plan)
}

/// The directive by which a file says it means to leave an axis moving at
/// its end.
pub const LEAVE_MOVING: &str = ":leave-moving";

/// Whether `steps` say [`LEAVE_MOVING`].
pub fn leaves_moving<'a>(mut steps: impl Iterator<Item = &'a Action>) -> bool {
    steps.any(|action| *action == Action::LeaveMoving)
}

/// An action and the file line it came from (1-based).
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub line_number: usize,
    pub action: Action,
}

/// A step with its console line (if it has one) checked and encoded.
#[derive(Debug, Clone)]
pub struct CheckedStep {
    pub step: Step,
    pub line: Option<PreparedLine>,
}

/// Parse a whole script and validate every console line in it for
/// `family` at `address`, before anything is sent. Every problem is listed
/// as `NAME:LINE: message`, in line order.
pub fn check_script(
    name: &str,
    text: &str,
    family: &Family,
    address: u8,
) -> Result<Vec<CheckedStep>, Vec<String>> {
    let mut checked = Vec::new();
    let mut problems = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        let line_number = index + 1;
        let action = match parse_script_line(raw) {
            Ok(Some(action)) => action,
            Ok(None) => continue,
            Err(message) => {
                problems.push(format!("{name}:{line_number}: {message}"));
                continue;
            }
        };
        let (line, must_only_read) = match &action {
            Action::Line(line) | Action::Expect { line, .. } => (Some(line), false),
            Action::WaitUntil { line, .. } => (Some(line), true),
            Action::Sleep(_)
            | Action::Echo(_)
            | Action::LeaveMoving
            | Action::ApplyParams { .. }
            | Action::Wiring(_)
            | Action::TuneStep(_)
            | Action::TuneStallguard(_) => (None, false),
        };
        if let Some(Err(message)) = tool_plan(&action, family) {
            problems.push(format!("{name}:{line_number}: {message}"));
        }
        let prepared = match line.map(|l| family.console.prepare(l, address)) {
            None => None,
            Some(Ok(prepared)) => {
                if must_only_read && prepared.effect != Effect::Reads {
                    problems.push(format!(
                        "{name}:{line_number}: :wait-until sends `{}` again and again: give \
                         a line that only reads (GAP, GGP, GIO…)",
                        prepared.canonical
                    ));
                }
                Some(prepared)
            }
            Some(Err(message)) => {
                problems.push(format!("{name}:{line_number}: {message}"));
                None
            }
        };
        checked.push(CheckedStep {
            step: Step {
                line_number,
                action,
            },
            line: prepared,
        });
    }
    // A file with nothing to do is refused as every front end's empty
    // file is (download, params, run-macro, run-ascript): ending "ok"
    // after doing nothing would hide a wrong or cut-off file.
    if checked.is_empty() && problems.is_empty() {
        problems.push(format!(
            "{name}: no line to run (the file is empty, or holds only comments and blank lines)"
        ));
    }
    if problems.is_empty() {
        Ok(checked)
    } else {
        Err(problems)
    }
}

/// A line of the file that cannot be understood.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScriptError {
    pub line_number: usize,
    pub message: String,
}

/// Parse a whole file. Every bad line is reported, not just the first.
pub fn parse_script(text: &str) -> Result<Vec<Step>, Vec<ScriptError>> {
    let mut steps = Vec::new();
    let mut errors = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        let line_number = index + 1;
        match parse_script_line(raw) {
            Ok(Some(action)) => steps.push(Step {
                line_number,
                action,
            }),
            Ok(None) => {}
            Err(message) => errors.push(ScriptError {
                line_number,
                message,
            }),
        }
    }
    if errors.is_empty() {
        Ok(steps)
    } else {
        Err(errors)
    }
}

/// One line of a file: `None` for blank lines and comments.
/// The console lines of a script that give a value in an axis's unit
/// (`MVP ABS, 0, 10mm`), by line number (from 1): what must be converted
/// with the module's settings before the script is checked.
pub fn unit_lines(
    text: &str,
    law: Option<&dyn crate::protocol::units::UnitLaw>,
) -> Vec<(usize, String)> {
    text.lines()
        .enumerate()
        .filter_map(|(index, raw)| match parse_script_line(raw) {
            Ok(Some(
                Action::Line(line) | Action::Expect { line, .. } | Action::WaitUntil { line, .. },
            )) if crate::protocol::units::has_units(law, &line) => Some((index + 1, line)),
            _ => None,
        })
        .collect()
}

/// Every console line of a script by line number (from 1).
pub fn console_lines(text: &str) -> Vec<(usize, String)> {
    text.lines()
        .enumerate()
        .filter_map(|(index, raw)| match parse_script_line(raw) {
            Ok(Some(
                Action::Line(line) | Action::Expect { line, .. } | Action::WaitUntil { line, .. },
            )) => Some((index + 1, line)),
            _ => None,
        })
        .collect()
}

/// `text` with the console line of each numbered line replaced (its
/// directive and the rest of the line kept): a script's unit lines
/// converted, line numbers unchanged for messages.
pub fn with_lines_replaced(
    text: &str,
    replaced: &std::collections::HashMap<usize, (String, String)>,
) -> String {
    let mut out = String::new();
    for (index, raw) in text.lines().enumerate() {
        match replaced.get(&(index + 1)) {
            Some((from, to)) => out.push_str(&raw.replacen(from.as_str(), to, 1)),
            None => out.push_str(raw),
        }
        out.push('\n');
    }
    out
}

pub fn parse_script_line(raw: &str) -> Result<Option<Action>, String> {
    let line = raw.trim();
    if line.is_empty() || line.starts_with('#') || line.starts_with("//") {
        return Ok(None);
    }
    let Some(directive) = line.strip_prefix(':') else {
        return Ok(Some(Action::Line(line.to_string())));
    };
    let (name, rest) = match directive.split_once(char::is_whitespace) {
        Some((name, rest)) => (name, rest.trim()),
        None => (directive, ""),
    };
    let action = match name.to_ascii_lowercase().as_str() {
        "expect" => {
            let (line, value) = comparison(":expect", rest)?;
            Action::Expect { line, value }
        }
        "wait-until" => {
            let (line, value) = comparison(":wait-until", rest)?;
            let (value, timeout) = split_timeout(&value)?;
            Action::WaitUntil {
                line,
                value,
                timeout: timeout.unwrap_or(DEFAULT_WAIT_TIMEOUT),
            }
        }
        "sleep" => {
            if rest.is_empty() {
                return Err(":sleep needs a duration, e.g. `:sleep 500ms`".into());
            }
            Action::Sleep(parse_duration(rest)?)
        }
        "echo" => Action::Echo(rest.to_string()),
        "params" => {
            let (file, store) = match rest.strip_suffix("--store") {
                Some(file) if file.is_empty() || file.ends_with(char::is_whitespace) => {
                    (file.trim(), true)
                }
                _ => (rest, false),
            };
            if file.is_empty() {
                return Err(
                    ":params needs a parameter file, e.g. `:params axis.toml --store`".into(),
                );
            }
            Action::ApplyParams {
                file: file.to_string(),
                store,
            }
        }
        "wiring" => Action::Wiring(wiring_ask(rest)?),
        "tune-step" => Action::TuneStep(tune_step_ask(rest)?),
        "tune-stallguard" => Action::TuneStallguard(tune_sweep_ask(rest)?),
        "leave-moving" if rest.is_empty() => Action::LeaveMoving,
        "leave-moving" => return Err(format!("{LEAVE_MOVING} takes nothing after it")),
        _ => {
            return Err(format!(
                "unknown directive `:{name}` (known: :expect, :wait-until, :sleep, :echo, \
                 :params, :wiring, :tune-step, :tune-stallguard, {LEAVE_MOVING})"
            ));
        }
    };
    Ok(Some(action))
}

/// `--name value` pairs of a tool directive, each name among `known`
/// and given once.
fn options<'a>(
    directive: &str,
    rest: &'a str,
    known: &[&str],
) -> Result<Vec<(&'a str, &'a str)>, String> {
    let words: Vec<&str> = rest.split_whitespace().collect();
    let mut pairs: Vec<(&str, &str)> = Vec::new();
    for pair in words.chunks(2) {
        let name = pair.first().copied().unwrap_or_default();
        let option = name.strip_prefix("--").filter(|n| known.contains(n));
        let Some(option) = option else {
            return Err(format!(
                ":{directive}: `{name}` is not an option of it (it takes {})",
                known
                    .iter()
                    .map(|k| format!("--{k}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        };
        let Some(value) = pair.get(1) else {
            return Err(format!(":{directive}: {name} needs a value"));
        };
        if pairs.iter().any(|(n, _)| *n == option) {
            return Err(format!(":{directive}: {name} is given twice"));
        }
        pairs.push((option, value));
    }
    Ok(pairs)
}

/// The value of option `name` parsed as a `T`, if given.
fn option<T: std::str::FromStr>(
    directive: &str,
    pairs: &[(&str, &str)],
    name: &str,
    what: &str,
) -> Result<Option<T>, String> {
    pairs
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, value)| {
            value
                .parse()
                .map_err(|_| format!(":{directive} --{name} {value}: give {what}"))
        })
        .transpose()
}

fn required<T>(directive: &str, value: Option<T>, name: &str) -> Result<T, String> {
    value.ok_or_else(|| format!(":{directive} needs --{name}"))
}

/// `:wiring [--axis N] [--speed S] [--give-up SECONDS]`.
fn wiring_ask(rest: &str) -> Result<WiringAsk, String> {
    const D: &str = "wiring";
    let pairs = options(D, rest, &["axis", "speed", "give-up"])?;
    let give_up = match pairs.iter().find(|(n, _)| *n == "give-up") {
        None => DEFAULT_WIRING_GIVE_UP,
        Some((_, value)) if value.bytes().all(|b| b.is_ascii_digit()) => {
            parse_duration(&format!("{value}s"))?
        }
        Some((_, value)) => parse_duration(value)?,
    };
    if give_up.is_zero() {
        return Err(":wiring --give-up 0: give the check some time (seconds > 0)".into());
    }
    Ok(WiringAsk {
        axis: option(D, &pairs, "axis", "an axis index (0, 1, …)")?.unwrap_or(0),
        speed: option(D, &pairs, "speed", "a whole speed in the family's unit")?,
        give_up,
    })
}

/// `:tune-step --distance D [--axis N] [--samples N] [--set NAME=V,…]
/// [--band B]`.
fn tune_step_ask(rest: &str) -> Result<TuneStepAsk, String> {
    const D: &str = "tune-step";
    let pairs = options(D, rest, &["axis", "distance", "samples", "set", "band"])?;
    let band: f64 = option(D, &pairs, "band", "a number of counts > 0")?.unwrap_or(2.0);
    if !(band.is_finite() && band > 0.0) {
        return Err(format!(
            ":{D} --band {band}: a band is a number of counts > 0"
        ));
    }
    let set = match pairs.iter().find(|(n, _)| *n == "set") {
        None => Vec::new(),
        Some((_, text)) => {
            crate::protocol::tuning::parse_settings(text).map_err(|why| format!(":{D} {why}"))?
        }
    };
    Ok(TuneStepAsk {
        axis: option(D, &pairs, "axis", "an axis number")?,
        distance: required(
            D,
            option(D, &pairs, "distance", "a whole number of counts")?,
            "distance",
        )?,
        samples: option(D, &pairs, "samples", "a whole number of samples")?.unwrap_or(400),
        set,
        band,
    })
}

/// `:tune-stallguard --from S --to S [--steps N] [--samples N] [--axis N]`.
fn tune_sweep_ask(rest: &str) -> Result<TuneSweepAsk, String> {
    const D: &str = "tune-stallguard";
    let pairs = options(D, rest, &["axis", "from", "to", "steps", "samples"])?;
    let speed = "a whole speed in the family's unit";
    Ok(TuneSweepAsk {
        axis: option(D, &pairs, "axis", "an axis number")?,
        from: required(D, option(D, &pairs, "from", speed)?, "from")?,
        to: required(D, option(D, &pairs, "to", speed)?, "to")?,
        steps: option(D, &pairs, "steps", "a whole number of speeds")?.unwrap_or(5),
        samples: option(D, &pairs, "samples", "a whole number of readings")?.unwrap_or(4),
    })
}

/// `LINE == VALUE`, both non-empty.
fn comparison(directive: &str, rest: &str) -> Result<(String, String), String> {
    let usage = format!("{directive} needs `LINE == VALUE`, e.g. `{directive} GAP 8, 0 == 1`");
    let Some((line, value)) = rest.split_once("==") else {
        return Err(usage);
    };
    let (line, value) = (line.trim(), value.trim());
    if line.is_empty() || value.is_empty() {
        return Err(usage);
    }
    Ok((line.to_string(), value.to_string()))
}

/// `VALUE [timeout DURATION]`.
fn split_timeout(value: &str) -> Result<(String, Option<Duration>), String> {
    let words: Vec<&str> = value.split_whitespace().collect();
    let Some(at) = words.iter().position(|w| w.eq_ignore_ascii_case("timeout")) else {
        return Ok((value.to_string(), None));
    };
    let expected = words.get(..at).unwrap_or_default().join(" ");
    let after = words.get(at + 1..).unwrap_or_default();
    match after {
        [duration] if !expected.is_empty() => Ok((expected, Some(parse_duration(duration)?))),
        [] => Err("`timeout` needs a duration, e.g. `timeout 5s`".into()),
        _ if expected.is_empty() => Err("give the value to wait for before `timeout`".into()),
        _ => Err(format!(
            "unexpected `{}` after the timeout: give `VALUE timeout DURATION`",
            after.get(1..).unwrap_or_default().join(" ")
        )),
    }
}

/// A duration as `500ms`, `2s`, `1.5s` or `1m` (a number and a unit; no
/// negative values; at most a day).
pub fn parse_duration(text: &str) -> Result<Duration, String> {
    let text = text.trim();
    let usage = || {
        format!("`{text}` is not a duration: give a number and ms, s or m (`500ms`, `1.5s`, `1m`)")
    };
    let split = text
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .ok_or_else(usage)?;
    let (number, unit) = (
        text.get(..split).ok_or_else(usage)?,
        text.get(split..).ok_or_else(usage)?,
    );
    let nanos_per_unit: u128 = match unit.trim() {
        "ms" => 1_000_000,
        "s" => 1_000_000_000,
        "m" | "min" => 60_000_000_000,
        _ => return Err(usage()),
    };
    // Exact decimal arithmetic: 0.007 s is 7 ms, not 6.999999 ms.
    let (whole, fraction) = number.split_once('.').unwrap_or((number, ""));
    let digits_only = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
    if whole.is_empty()
        || !digits_only(whole)
        || !digits_only(fraction)
        || (number.contains('.') && fraction.is_empty())
        || whole.len() > 12
        || fraction.len() > 12
    {
        return Err(usage());
    }
    let whole: u128 = whole.parse().map_err(|_| usage())?;
    let scale = 10u128.pow(fraction.len() as u32);
    let fraction: u128 = if fraction.is_empty() {
        0
    } else {
        fraction.parse().map_err(|_| usage())?
    };
    let nanos = whole * nanos_per_unit + fraction * nanos_per_unit / scale;
    let duration = Duration::from_nanos(u64::try_from(nanos).map_err(|_| usage())?);
    if duration > MAX_DURATION {
        return Err(format!(
            "{text} is longer than the 24 hours a file may ask for"
        ));
    }
    Ok(duration)
}

/// Whether a line's result (as printed: `ok`, a number, text) equals the
/// value a file expects. Numbers compare by value, so `0x10` matches 16;
/// `ok` matches in any case; anything else must match exactly, but for a
/// result of `name=value` fields (SIXpack 2 `posact=10000 action=ramp
/// stop=0`), which an expected value of `name=value` fields matches when
/// each of them is among the result's (`action=inactive`, or
/// `posact=0x2710 stop=0`: values compare as above).
pub fn result_matches(printed: &str, expected: &str) -> bool {
    let single = match (parse_integer(printed), parse_integer(expected)) {
        (Some(a), Some(b)) => a == b,
        _ => {
            printed == expected
                || (printed.eq_ignore_ascii_case("ok") && expected.eq_ignore_ascii_case("ok"))
        }
    };
    single || fields_match(printed, expected)
}

/// `name=value` words, if the whole text is made of them.
fn fields(text: &str) -> Option<Vec<(&str, &str)>> {
    let words: Vec<(&str, &str)> = text
        .split_whitespace()
        .map(|word| word.split_once('=').filter(|(name, _)| !name.is_empty()))
        .collect::<Option<_>>()?;
    (!words.is_empty()).then_some(words)
}

/// Whether every field expected is among the printed ones, with a value
/// that matches.
fn fields_match(printed: &str, expected: &str) -> bool {
    let (Some(printed), Some(expected)) = (fields(printed), fields(expected)) else {
        return false;
    };
    expected.iter().all(|(name, value)| {
        printed
            .iter()
            .any(|(n, v)| n == name && !v.contains('=') && result_matches(v, value))
    })
}

/// A decimal or `0x`/`$` hex integer, optionally signed.
fn parse_integer(text: &str) -> Option<i128> {
    let (negative, digits) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let magnitude = if let Some(hex) = digits
        .strip_prefix("0x")
        .or_else(|| digits.strip_prefix("0X"))
        .or_else(|| digits.strip_prefix('$'))
    {
        i128::from_str_radix(hex, 16).ok()?
    } else if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) {
        digits.parse().ok()?
    } else {
        return None;
    };
    Some(if negative { -magnitude } else { magnitude })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn a_script_with_no_line_is_refused() {
        let tmcl = crate::families::find_family("tmcl").expect("tmcl");
        for text in ["", "\n  \n", "# setup\n// later\n"] {
            let problems = check_script("f.txt", text, tmcl, 1).expect_err("nothing to run");
            assert_eq!(
                problems,
                [
                    "f.txt: no line to run (the file is empty, or holds only comments and blank \
                  lines)"
                ]
            );
        }
        assert!(check_script("f.txt", ":echo hello\n", tmcl, 1).is_ok());
    }

    #[test]
    fn leave_moving_is_a_directive_of_the_whole_file() {
        assert_eq!(
            parse_script_line(":leave-moving"),
            Ok(Some(Action::LeaveMoving))
        );
        assert_eq!(
            parse_script_line(":leave-moving now"),
            Err(":leave-moving takes nothing after it".to_string())
        );
        let steps = parse_script("ROR 0, 500\n:leave-moving\n").expect("parses");
        assert!(leaves_moving(steps.iter().map(|s| &s.action)));
        let steps = parse_script("ROR 0, 500\n").expect("parses");
        assert!(!leaves_moving(steps.iter().map(|s| &s.action)));
    }

    #[test]
    fn comments_and_blank_lines_are_skipped() {
        let steps = parse_script("# setup\n\n   // more\nSAP 4, 0, 1000\n  GAP 4, 0  \n").unwrap();
        assert_eq!(
            steps,
            [
                Step {
                    line_number: 4,
                    action: Action::Line("SAP 4, 0, 1000".into())
                },
                Step {
                    line_number: 5,
                    action: Action::Line("GAP 4, 0".into())
                },
            ]
        );
    }

    #[test]
    fn params_takes_a_file_and_maybe_store() {
        let params = |file: &str, store| {
            Ok(Some(Action::ApplyParams {
                file: file.into(),
                store,
            }))
        };
        assert_eq!(
            parse_script_line(":params axis.toml"),
            params("axis.toml", false)
        );
        assert_eq!(
            parse_script_line(":params my axis.toml --store"),
            params("my axis.toml", true)
        );
        // `--store` only as a word of its own.
        assert_eq!(
            parse_script_line(":params a--store"),
            params("a--store", false)
        );
    }

    #[test]
    fn directives_parse() {
        assert_eq!(
            parse_script_line(":expect GAP 4, 0 == 1000"),
            Ok(Some(Action::Expect {
                line: "GAP 4, 0".into(),
                value: "1000".into()
            }))
        );
        assert_eq!(
            parse_script_line(":wait-until GAP 8, 0 == 1 timeout 1.5s"),
            Ok(Some(Action::WaitUntil {
                line: "GAP 8, 0".into(),
                value: "1".into(),
                timeout: Duration::from_millis(1500)
            }))
        );
        assert_eq!(
            parse_script_line(":wait-until GAP 8, 0 == 1"),
            Ok(Some(Action::WaitUntil {
                line: "GAP 8, 0".into(),
                value: "1".into(),
                timeout: DEFAULT_WAIT_TIMEOUT
            }))
        );
        assert_eq!(
            parse_script_line(":sleep 500ms"),
            Ok(Some(Action::Sleep(Duration::from_millis(500))))
        );
        assert_eq!(
            parse_script_line(":echo  homing done "),
            Ok(Some(Action::Echo("homing done".into())))
        );
        assert_eq!(
            parse_script_line(":echo"),
            Ok(Some(Action::Echo(String::new())))
        );
    }

    #[test]
    fn the_tool_directives_parse_with_their_defaults() {
        assert_eq!(
            parse_script_line(":wiring"),
            Ok(Some(Action::Wiring(WiringAsk {
                axis: 0,
                speed: None,
                give_up: DEFAULT_WIRING_GIVE_UP
            })))
        );
        assert_eq!(
            parse_script_line(":wiring --axis 1 --speed 500000 --give-up 10"),
            Ok(Some(Action::Wiring(WiringAsk {
                axis: 1,
                speed: Some(500_000),
                give_up: Duration::from_secs(10)
            })))
        );
        assert_eq!(
            parse_script_line(":tune-step --axis 1 --distance -1000 --set SG=0.05,SD=0.3"),
            Ok(Some(Action::TuneStep(TuneStepAsk {
                axis: Some(1),
                distance: -1000,
                samples: 400,
                set: vec![("SG".into(), 0.05), ("SD".into(), 0.3)],
                band: 2.0
            })))
        );
        assert_eq!(
            parse_script_line(":tune-stallguard --from 200 --to 1000 --steps 3"),
            Ok(Some(Action::TuneStallguard(TuneSweepAsk {
                axis: None,
                from: 200,
                to: 1000,
                steps: 3,
                samples: 4
            })))
        );
    }

    #[test]
    fn a_tool_the_family_lacks_or_a_value_its_plan_refuses_is_a_problem_of_the_file() {
        let tmcl = crate::families::find_family("tmcl").expect("tmcl");
        let mccl = crate::families::find_family("mccl").expect("mccl");
        let text = ":tune-step --distance 1000\n:wiring --axis 3\n:wiring --speed 0\n\
                    :tune-stallguard --from 200 --to 1000\n";
        let problems = check_script("f.txt", text, tmcl, 1).expect_err("refused");
        assert_eq!(problems.len(), 3, "{problems:?}");
        assert!(
            problems[0].starts_with("f.txt:1: :tune-step: the tmcl family has no servo"),
            "{problems:?}"
        );
        assert!(
            problems[1].starts_with("f.txt:2: :wiring --axis 3: the tmcl family has axes 0..0"),
            "{problems:?}"
        );
        assert!(
            problems[2].starts_with("f.txt:3: :wiring --speed 0: "),
            "{problems:?}"
        );
        let problems =
            check_script("f.txt", ":tune-stallguard --from 1 --to 2\n", mccl, 1).expect_err("no");
        assert!(problems[0].contains("no StallGuard2 sweep"), "{problems:?}");
        assert!(check_script("f.txt", ":tune-step --axis 1 --distance 1000\n", mccl, 1).is_ok());
        let problems = check_script(
            "f.txt",
            ":tune-step --axis 1 --distance 1000 --set XX=1\n",
            mccl,
            1,
        )
        .expect_err("no such gain");
        assert!(problems[0].contains("XX is not a gain"), "{problems:?}");
    }

    #[test]
    fn bad_directives_say_what_is_expected() {
        for (line, needle) in [
            (":expect GAP 4, 0", "LINE == VALUE"),
            (":expect == 5", "LINE == VALUE"),
            (":wait-until GAP 8, 0 == 1 timeout", "needs a duration"),
            (":wait-until GAP 8, 0 == 1 timeout 5", "not a duration"),
            (":wait-until GAP 8, 0 == timeout 5s", "value to wait for"),
            (
                ":wait-until GAP 8, 0 == 1 timeout 5s now",
                "unexpected `now`",
            ),
            (":sleep", "needs a duration"),
            (":sleep soon", "not a duration"),
            (":pause 5s", "unknown directive `:pause`"),
            (":params", "needs a parameter file"),
            (":params --store", "needs a parameter file"),
            (":wiring --axis", "--axis needs a value"),
            (":wiring --axis x", "--axis x: give an axis index"),
            (":wiring --axis 0 --axis 1", "given twice"),
            (":wiring --give-up 0", "some time"),
            (":wiring now", "`now` is not an option"),
            (":tune-step --axis 1", "needs --distance"),
            (
                ":tune-step --distance 10 --band 0",
                "a band is a number of counts > 0",
            ),
            (":tune-step --distance 10 --set SG", "NAME=VALUE"),
            (":tune-stallguard --from 1", "needs --to"),
            (
                ":tune-stallguard --from 1 --to 2 --steps -1",
                "--steps -1: give",
            ),
        ] {
            let error = parse_script_line(line).unwrap_err();
            assert!(error.contains(needle), "{line}: {error}");
        }
    }

    #[test]
    fn every_bad_line_is_reported_with_its_number() {
        let errors = parse_script("GAP 1, 0\n:sleep\n:echo fine\n:nope\n").unwrap_err();
        let numbers: Vec<usize> = errors.iter().map(|e| e.line_number).collect();
        assert_eq!(numbers, [2, 4]);
    }

    #[test]
    fn durations() {
        assert_eq!(parse_duration("500ms"), Ok(Duration::from_millis(500)));
        assert_eq!(parse_duration("2s"), Ok(Duration::from_secs(2)));
        assert_eq!(parse_duration("1.5s"), Ok(Duration::from_millis(1500)));
        assert_eq!(parse_duration("1m"), Ok(Duration::from_secs(60)));
        assert_eq!(parse_duration("0ms"), Ok(Duration::ZERO));
        for bad in [
            "", "5", "ms", "-1s", "1.s", ".5s", "1..5s", "1h", "2 s s", "1e3s", "25000m",
        ] {
            assert!(parse_duration(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn results_compare_as_numbers_or_exactly() {
        assert!(result_matches(
            "posact=10000 action=inactive stop=0",
            "action=inactive"
        ));
        assert!(result_matches(
            "posact=10000 action=inactive stop=0",
            "stop=0 posact=0x2710"
        ));
        assert!(!result_matches(
            "posact=10000 action=ramp stop=0",
            "action=inactive"
        ));
        assert!(!result_matches("posact=10000", "posact=10000 stop=0"));
        assert!(!result_matches("posact=10000", "posact"));
        assert!(!result_matches("10000", "posact=10000"));
        assert!(result_matches("16", "0x10"));
        assert!(result_matches("-5", "-5"));
        assert!(result_matches("255", "$FF"));
        assert!(result_matches("ok", "OK"));
        assert!(result_matches("1110V112", "1110V112"));
        assert!(!result_matches("1110V112", "1110v112"));
        assert!(!result_matches("0", "ok"));
        assert!(!result_matches("15", "16"));
    }

    proptest! {
        #[test]
        fn the_parser_never_panics(text in "\\PC*") {
            let _ = parse_script(&text);
        }

        #[test]
        fn directive_lines_never_panic(rest in "\\PC*", name in "(expect|wait-until|sleep|echo|x)") {
            let _ = parse_script_line(&format!(":{name} {rest}"));
        }

        #[test]
        fn durations_never_panic(text in "[0-9.]{0,30}(ms|s|m|min|x)?") {
            let _ = parse_duration(&text);
        }

        #[test]
        fn millisecond_durations_round_trip(ms in 0u64..86_400_000) {
            prop_assert_eq!(parse_duration(&format!("{ms}ms")), Ok(Duration::from_millis(ms)));
        }

        #[test]
        fn comparisons_never_panic(a in "\\PC*", b in "\\PC*") {
            let _ = result_matches(&a, &b);
        }

        #[test]
        fn a_result_of_fields_matches_any_of_its_fields(
            fields in proptest::collection::vec(("[a-z][a-z0-9]{0,6}", "-?[0-9]{1,6}|[a-z]{1,8}"), 1..6),
            pick in proptest::collection::vec(any::<bool>(), 6),
        ) {
            let printed: Vec<String> = fields.iter().map(|(n, v)| format!("{n}={v}")).collect();
            let chosen: Vec<String> = printed
                .iter()
                .zip(&pick)
                .filter(|(_, p)| **p)
                .map(|(f, _)| f.clone())
                .collect();
            prop_assume!(!chosen.is_empty());
            prop_assert!(result_matches(&printed.join(" "), &chosen.join(" ")));
        }
    }
}
