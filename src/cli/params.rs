//! `axterm params export|diff|apply CONNECTION FILE`: a module's settings
//! as the parameter file the console's parameter pane exports, compares
//! and imports ([`crate::protocol::parameter_file`]), through the same
//! code ([`crate::session::params`]).
//!
//! The file is read and checked against the family's tables before the
//! link is opened: a file that does not parse, names another family or
//! holds a value outside its range (or no parameter of the module) sends
//! nothing (exit 2). `diff` and `apply` take `--addresses`/`--all` and
//! several links, the file checked against each link's family
//! ([`super::fleet`]).

use std::path::PathBuf;

use clap::{Args, Subcommand};
use serde_json::{Value, json};

use super::connection::{Target, run_to_exit};
use super::fleet::{self, FleetArgs, FleetLink, FleetModule, Identity, ModuleRow, Walk};
use super::output::Format;
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::files::Existing;
use crate::protocol::parameter_file::{self, Exported};
use crate::protocol::parameters::{ParamRow, ParameterSet};
use crate::protocol::units::MechanicsTable;
use crate::session::params::{
    self as shared, ApplyOptions, ApplyReport, Difference, ModuleValue, ValueOutcome,
};

#[derive(Debug, Clone, Subcommand)]
pub enum ParamsCommand {
    /// Read every setting of the module into FILE (- for standard output).
    ///
    /// Settings the module cannot read back (every SIXpack 2 setting) are
    /// known only from what this session wrote: a new session wrote none,
    /// so they are commented out, and said so. Exit codes: 0 every
    /// readable setting read, 1 a read failed or timed out (the file is
    /// written with those commented out), 3 no connection.
    Export(ExportArgs),
    /// Compare the module's settings with FILE; print what differs.
    ///
    /// Link settings (baud rate, bus address) are shown when they differ
    /// but do not count. Exit codes: 0 nothing differs, 1 something
    /// differs, cannot be read, or cannot be read back at all (SIXpack 2
    /// settings this session did not write are not known), 2 a bad file
    /// or usage (nothing sent), 3 no connection. Several modules
    /// (--addresses, --all) or links (--port A --port B): a table at the
    /// end, exit 0 only when every module of every link matches.
    Diff(DiffArgs),
    /// Write FILE's settings that differ, then read each back.
    ///
    /// Only values that differ are written; each written value is read
    /// back where the family can (verified, or it differs). Link settings
    /// are never written. With --store the file's settings are stored to
    /// EEPROM/flash afterwards (TMCL STAP/STGP, CMD-4CR STORE); the
    /// families that store nothing refuse --store. Exit codes: 0 every
    /// value written and verified (or nothing to do), 1 a write, read
    /// back or store failed or a value reads back otherwise, 2 a bad file
    /// or usage (nothing sent), 3 no connection. Several modules
    /// (--addresses, --all) or links (--port A --port B, a line of
    /// MultiFlex boards): each in turn, a table at the end, exit 0 only
    /// when every module of every link succeeded.
    Apply(ApplyArgs),
}

#[derive(Debug, Clone, Args)]
pub struct ExportArgs {
    /// The parameter file to write (- for standard output).
    pub file: String,
    /// Replace FILE if it exists (without it an existing file is refused,
    /// exit 2, before the module is asked anything).
    #[arg(long)]
    pub force: bool,
    /// text: a summary line; json: one object with what was and was not
    /// read.
    #[arg(long, value_enum, default_value_t)]
    pub format: Format,
}

#[derive(Debug, Clone, Args)]
pub struct DiffArgs {
    /// The parameter file (TOML, as exported).
    pub file: PathBuf,
    #[command(flatten)]
    pub fleet: FleetArgs,
    /// text: a line per difference; json: one object per module.
    #[arg(long, value_enum, default_value_t)]
    pub format: Format,
}

#[derive(Debug, Clone, Args)]
pub struct ApplyArgs {
    /// The parameter file (TOML, as exported).
    pub file: PathBuf,
    /// Store the file's settings to EEPROM/flash after writing them.
    #[arg(long)]
    pub store: bool,
    /// Read and compare, print the lines that would be sent; write
    /// nothing.
    #[arg(long)]
    pub dry_run: bool,
    #[command(flatten)]
    pub fleet: FleetArgs,
    /// text: a line per value written; json: one object per module.
    #[arg(long, value_enum, default_value_t)]
    pub format: Format,
}

/// `mechanics`: the file `--mechanics` names, the mechanics in force: an
/// export writes them beside the settings, a diff or apply compares the
/// file's with them.
pub fn run(
    connection: &ConnectionArgs,
    command: &ParamsCommand,
    mechanics: Option<&std::path::Path>,
) -> i32 {
    match command {
        ParamsCommand::Export(args) => export(connection, args, mechanics),
        ParamsCommand::Diff(args) => compare_or_apply(
            connection,
            &args.file,
            &args.fleet,
            None,
            args.format,
            mechanics,
        ),
        ParamsCommand::Apply(args) => compare_or_apply(
            connection,
            &args.file,
            &args.fleet,
            Some(ApplyOptions {
                store: args.store,
                dry_run: args.dry_run,
            }),
            args.format,
            mechanics,
        ),
    }
}

/// The connection, its family's parameters and its axis numbers; a usage
/// error otherwise.
fn resolve(
    connection: &ConnectionArgs,
) -> Result<(Target, &'static dyn ParameterSet, Vec<u8>), String> {
    let target = Target::resolve(connection)?;
    let (parameters, axes) = parameters_of(&target)?;
    Ok((target, parameters, axes))
}

/// The family's parameters and its axis numbers.
fn parameters_of(target: &Target) -> Result<(&'static dyn ParameterSet, Vec<u8>), String> {
    let parameters = target
        .family
        .console
        .parameters()
        .ok_or_else(|| format!("the {} family has no parameter tables", target.family.name))?;
    let axes = target
        .family
        .console
        .axes()
        .iter()
        .map(|a| a.number)
        .collect();
    Ok((parameters, axes))
}

fn export(
    connection: &ConnectionArgs,
    args: &ExportArgs,
    mechanics: Option<&std::path::Path>,
) -> i32 {
    let (target, parameters, axes) = match resolve(connection) {
        Ok(resolved) => resolved,
        Err(message) => {
            eprintln!("axterm params export: {message}");
            return EXIT_USAGE;
        }
    };
    // The mechanics in force go into the file beside the settings, so
    // that the file carries the line's units across to another line.
    let mechanics = match super::mechanics::load(mechanics) {
        Ok(m) => m.map(|m| m.table).unwrap_or_default(),
        Err(message) => {
            eprintln!("axterm params export: {message}");
            return EXIT_USAGE;
        }
    };
    if let Some(axis) = mechanics.axes.keys().find(|a| !axes.contains(a)) {
        eprintln!(
            "axterm params export: the mechanics give axis {axis}, which this module does not have"
        );
        return EXIT_USAGE;
    }
    let (file, format) = (args.file.clone(), args.format);
    let existing = Existing::from_force(args.force);
    // A file that cannot be written is known before the module is asked.
    if file != "-"
        && let Err(e) = crate::files::check_destination(&file, existing)
    {
        eprintln!("axterm params export: cannot write {file}: {e}");
        eprintln!("axterm params export: nothing was sent");
        return EXIT_USAGE;
    }
    run_to_exit("params export", async move {
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm params export: {e}");
                return EXIT_CONNECTION;
            }
        };
        let identity = Identity::ask(&session).await;
        if let Identity::Silent(why) = &identity {
            eprintln!("axterm params export: {why}: nothing exported");
            return EXIT_DEVICE;
        }
        let rows = parameter_file::setting_rows(parameters, &axes);
        let values = shared::read_values(&session, parameters, &rows).await;
        let exported: Vec<Exported> = rows
            .iter()
            .map(|row| Exported {
                row,
                value: match values.get(&(row.scope, row.number)) {
                    Some(ModuleValue::Value(v)) => Ok(*v),
                    Some(other) => Err(other.why_not().unwrap_or("not read").to_string()),
                    None => Err("not read".into()),
                },
            })
            .collect();
        let mut header = vec![format!(
            "axterm parameter file: module {} on {}",
            session.address(),
            target.spec.describe()
        )];
        if let Identity::Firmware(firmware) = &identity {
            header.push(format!("firmware {firmware}"));
        }
        let mut text = parameter_file::render(target.family.name, &header, &exported);
        text.push_str(&mechanics.render());
        let written = if file == "-" {
            print!("{text}");
            Ok(())
        } else {
            crate::files::save(&file, text.as_bytes(), existing)
        };
        if let Err(e) = written {
            eprintln!("axterm params export: cannot write {file}: {e}");
            return if e.is_usage() {
                EXIT_USAGE
            } else {
                EXIT_DEVICE
            };
        }
        // Not read: the module did not answer or refused (a failure);
        // unknown: it cannot be asked and this session wrote none.
        let failed: Vec<&Exported> = exported
            .iter()
            .filter(|e| {
                matches!(
                    values.get(&(e.row.scope, e.row.number)),
                    Some(ModuleValue::NoAnswer(_) | ModuleValue::Unreadable(_)) | None
                )
            })
            .collect();
        let unknown = exported.iter().filter(|e| e.value.is_err()).count() - failed.len();
        let read = exported.len() - failed.len() - unknown;
        match format {
            Format::Json => {
                let not_read: Vec<Value> = failed
                    .iter()
                    .map(|e| {
                        json!({
                            "scope": e.row.scope.key(),
                            "number": e.row.number,
                            "name": e.row.name,
                            "why": e.value.as_ref().err(),
                        })
                    })
                    .collect();
                println!(
                    "{}",
                    json!({
                        "file": file,
                        "module": session.address(),
                        "firmware": identity.shown(),
                        "exported": read,
                        "unknown": unknown,
                        "not_read": not_read,
                        "ok": failed.is_empty(),
                    })
                );
            }
            Format::Text => {
                let to = if file == "-" {
                    "standard output"
                } else {
                    &file
                };
                let settings = if read == 1 { "setting" } else { "settings" };
                eprintln!("axterm params export: exported {read} {settings} to {to}");
            }
        }
        if unknown > 0 {
            let settings = if unknown == 1 { "setting" } else { "settings" };
            eprintln!(
                "axterm params export: {unknown} {settings} cannot be read back from the module \
                 and were not written by this session: commented out, not exported"
            );
        }
        for e in &failed {
            eprintln!(
                "axterm params export: [{}] {} {}: not read: {}",
                e.row.scope.key(),
                e.row.number,
                e.row.name,
                e.value.as_ref().err().map_or("", String::as_str)
            );
        }
        if failed.is_empty() {
            EXIT_OK
        } else {
            EXIT_DEVICE
        }
    })
}

/// `diff` (`apply` is `None`) or `apply`: the file checked whole first
/// (against every link's family), then the work on each module of each
/// link.
fn compare_or_apply(
    connection: &ConnectionArgs,
    path: &std::path::Path,
    fleet_args: &FleetArgs,
    apply: Option<ApplyOptions>,
    format: Format,
    mechanics: Option<&std::path::Path>,
) -> i32 {
    let command = if apply.is_some() {
        "params apply"
    } else {
        "params diff"
    };
    let in_force = match super::mechanics::load(mechanics) {
        Ok(m) => m.map(|m| m.table),
        Err(message) => {
            eprintln!("axterm {command}: {message}");
            return EXIT_USAGE;
        }
    };
    let checked = FleetLink::resolve_all(connection, fleet_args).and_then(|links| {
        let mut checked = Vec::new();
        for link in &links {
            let named = |message: String| match &link.name {
                Some(name) => format!("{} ({}): {message}", name.label, name.connection),
                None => message,
            };
            let (parameters, axes) = parameters_of(&link.target).map_err(named)?;
            if let Some(options) = apply
                && options.store
            {
                refuse_store_without_place(parameters, &axes).map_err(named)?;
            }
            let (entries, carried) =
                read_file(path, link.target.family.name, parameters, &axes).map_err(named)?;
            if checked.is_empty()
                && let Some(note) = mechanics_note(path, &carried, in_force.as_ref())
            {
                eprintln!("axterm {command}: {note}");
            }
            // A file cut between two whole lines reads as a shorter file:
            // what it leaves out is said, so that "the same" is not taken
            // for the whole module.
            let settings = parameter_file::setting_rows(parameters, &axes).len();
            if entries.len() < settings {
                eprintln!(
                    "axterm {command}: {}",
                    named(format!(
                        "{} gives {} of the module's {settings} settings: the others are not \
                         compared",
                        path.display(),
                        entries.len()
                    ))
                );
            }
            checked.push((parameters, entries));
        }
        Ok((links, checked))
    });
    let (links, checked) = match checked {
        Ok(checked) => checked,
        Err(message) => {
            eprintln!("axterm {command}: {message}");
            eprintln!("axterm {command}: nothing was sent");
            return EXIT_USAGE;
        }
    };
    let stop_on_failure = fleet_args.stop_on_failure;
    run_to_exit(command, async move {
        let several = FleetLink::several(&links);
        let mut walk = Walk::new(&links, command, stop_on_failure);
        loop {
            let module = match walk.next().await {
                Ok(Some(module)) => module,
                Ok(None) => break,
                Err(e) => {
                    eprintln!("axterm {command}: {e}");
                    return EXIT_CONNECTION;
                }
            };
            let (parameters, entries) = &checked[module.link_index];
            let row = one_module(&module, *parameters, entries, apply, format, several).await;
            if !several && !row.note.is_empty() && !row.ok {
                eprintln!("axterm {command}: {}", row.note);
            }
            walk.record(&module, row);
        }
        let rows = walk.rows();
        if several {
            let columns: &[&str] = &["written", "verified", "differs", "failed"];
            return fleet::finish(&rows, columns, format);
        }
        match rows.first() {
            Some(row) if row.ok => EXIT_OK,
            _ => EXIT_DEVICE,
        }
    })
}

/// `--store` where the family stores nothing (MCCL, SIXpack 2): refused
/// with the family's reason before anything is sent.
pub(super) fn refuse_store_without_place(
    parameters: &dyn ParameterSet,
    axes: &[u8],
) -> Result<(), String> {
    let rows = parameter_file::setting_rows(parameters, axes);
    let (lines, without) = shared::plan_store(parameters, &rows);
    match (lines.is_empty(), without.first()) {
        (true, Some((_, why))) => Err(format!("--store: {why}")),
        _ => Ok(()),
    }
}

/// Read, parse and check the file: every problem is an error naming the
/// parameter (nothing is sent then).
pub(super) fn read_file(
    path: &std::path::Path,
    family: &str,
    parameters: &dyn ParameterSet,
    axes: &[u8],
) -> Result<(Vec<(ParamRow, i64)>, MechanicsTable), String> {
    let shown = path.display();
    let text = crate::files::read_text(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
    let parsed = parameter_file::parse(&text)
        .map_err(|e| format!("{shown} is not a parameter file: {e}"))?;
    if let Some(why) = parameter_file::family_mismatch(&parsed, family) {
        return Err(format!("{shown}: {why}"));
    }
    let checked = parameter_file::check(parsed, parameters, axes);
    if !checked.problems.is_empty() {
        let list: Vec<String> = checked
            .problems
            .iter()
            .map(|p| format!("{shown}: {}", p.trim_end_matches(", left alone")))
            .collect();
        return Err(list.join("\n"));
    }
    Ok((checked.entries, checked.mechanics))
}

/// What a diff or apply says of the mechanics a file carries: they are
/// the console's, not the module's, so nothing is written; compared with
/// the mechanics in force (`--mechanics`) where there are some.
fn mechanics_note(
    path: &std::path::Path,
    carried: &MechanicsTable,
    in_force: Option<&MechanicsTable>,
) -> Option<String> {
    let shown = path.display();
    if carried.is_empty() {
        return None;
    }
    let axes: Vec<String> = carried.axes.keys().map(u8::to_string).collect();
    let axes = axes.join(", ");
    Some(match in_force {
        None => format!(
            "{shown} carries the mechanics of axis {axes}: not written to the module (give the \
             file to --mechanics, or :mechanics in the console, to use them)"
        ),
        Some(in_force) if in_force == carried => {
            format!("{shown}: mechanics of axis {axes} as in force")
        }
        Some(in_force) => {
            let differing: Vec<String> = carried
                .axes
                .iter()
                .filter(|(axis, m)| in_force.get(**axis) != Some(*m))
                .map(|(axis, m)| match in_force.get(*axis) {
                    Some(now) => format!("[mechanics.{axis}] {m} in the file, {now} in force"),
                    None => format!("[mechanics.{axis}] {m} in the file, none in force"),
                })
                .collect();
            format!(
                "{shown}: mechanics differ from those in force (not written to the module): {}",
                if differing.is_empty() {
                    "the file leaves out axes in force".to_string()
                } else {
                    differing.join("; ")
                }
            )
        }
    })
}

/// The label of a parameter in messages: `[axis.0] 4 Maximum positioning
/// speed`.
fn label(row: &ParamRow) -> String {
    format!("[{}] {} {}", row.scope.key(), row.number, row.name)
}

/// Diff or apply on one module; its row of the table, with its lines
/// printed as they come (prefixed with the module when there are
/// several).
async fn one_module(
    module: &FleetModule,
    parameters: &dyn ParameterSet,
    entries: &[(ParamRow, i64)],
    apply: Option<ApplyOptions>,
    format: Format,
    several: bool,
) -> ModuleRow {
    let session = &module.session;
    let address = session.address();
    let identity = Identity::ask(session).await;
    let mut row = module.row(identity.shown());
    if let Identity::Silent(why) = &identity {
        row.failed = 1;
        row.note = why.clone();
        if format == Format::Json && !several {
            println!(
                "{}",
                json!({ "module": address, "ok": false, "error": why })
            );
        }
        return row;
    }
    let prefix = if several {
        format!("{}: ", module.who())
    } else {
        String::new()
    };
    let report = match apply {
        Some(options) => shared::apply(session, parameters, entries, options).await,
        None => {
            let rows: Vec<ParamRow> = entries.iter().map(|(r, _)| r.clone()).collect();
            let values = shared::read_values(session, parameters, &rows).await;
            let module = |r: &ParamRow| {
                values
                    .get(&(r.scope, r.number))
                    .cloned()
                    .unwrap_or_else(|| ModuleValue::NoAnswer("not read".into()))
            };
            ApplyReport {
                comparison: shared::compare(entries, &module),
                ..ApplyReport::default()
            }
        }
    };
    let dry_run = apply.is_some_and(|o| o.dry_run);
    match apply {
        None => fill_diff_row(&mut row, &report),
        Some(_) => fill_apply_row(&mut row, &report, dry_run),
    }
    match format {
        Format::Text => print_text(
            &prefix,
            &module.who(),
            &report,
            apply.is_some(),
            dry_run,
            &row,
        ),
        Format::Json => println!("{}", json_report(&row, &report, apply.is_some(), dry_run)),
    }
    row
}

/// A difference the module could not be asked about (no answer, refused).
fn unread(d: &Difference) -> bool {
    matches!(
        d.module,
        ModuleValue::NoAnswer(_) | ModuleValue::Unreadable(_)
    )
}

fn fill_diff_row(row: &mut ModuleRow, report: &ApplyReport) {
    let counted: Vec<&Difference> = report.comparison.settings_differing().collect();
    row.failed = counted.iter().filter(|d| unread(d)).count();
    row.differs = counted.len() - row.failed;
    let unknown = counted
        .iter()
        .filter(|d| matches!(d.module, ModuleValue::Unknown(_)))
        .count();
    if unknown > 0 {
        row.note = format!("{unknown} cannot be read back: not known");
    }
    row.ok = counted.is_empty();
}

fn fill_apply_row(row: &mut ModuleRow, report: &ApplyReport, dry_run: bool) {
    row.written = report.written();
    row.verified = report.verified();
    row.differs = report.differs();
    row.failed = report.failed();
    let mut notes = Vec::new();
    if dry_run {
        notes.push(format!("dry run: {} to write", report.values.len()));
    }
    let unverifiable = report.unverifiable();
    if unverifiable > 0 {
        notes.push(format!("{unverifiable} written, cannot be read back"));
    }
    if let Some((_, why)) = report.not_storable.first() {
        notes.push(format!(
            "{} not kept by a store (e.g. {why})",
            report.not_storable.len()
        ));
    }
    if !report.link_left.is_empty() {
        notes.push(format!(
            "{} link setting(s) differ, not written",
            report.link_left.len()
        ));
    }
    row.note = notes.join("; ");
    row.ok = report.succeeded();
}

fn outcome_text(outcome: &ValueOutcome) -> String {
    match outcome {
        ValueOutcome::Verified => "verified".into(),
        ValueOutcome::ReadBackDiffers(v) => format!("DIFFERS: reads back {v}"),
        ValueOutcome::Unverifiable => "written, cannot be read back".into(),
        ValueOutcome::Planned => "not sent (dry run)".into(),
        ValueOutcome::Failed(why) => format!("FAILED: {why}"),
    }
}

fn outcome_name(outcome: &ValueOutcome) -> &'static str {
    match outcome {
        ValueOutcome::Verified => "verified",
        ValueOutcome::ReadBackDiffers(_) => "differs",
        ValueOutcome::Unverifiable => "unverifiable",
        ValueOutcome::Planned => "planned",
        ValueOutcome::Failed(_) => "failed",
    }
}

fn print_text(
    prefix: &str,
    who: &str,
    report: &ApplyReport,
    applying: bool,
    dry_run: bool,
    row: &ModuleRow,
) {
    let comparison = &report.comparison;
    if applying {
        for value in &report.values {
            let d = &value.difference;
            println!(
                "{prefix}{}  {}: {} -> {}  {}",
                value.line,
                label(&d.row),
                d.module,
                d.file,
                outcome_text(&value.outcome)
            );
        }
        for (d, why) in &report.refused {
            println!(
                "{prefix}{}: {} -> {}  FAILED: {why}",
                label(&d.row),
                d.module,
                d.file
            );
        }
        for stored in &report.stored {
            match &stored.result {
                Ok(()) => println!("{prefix}{}  stored", stored.line),
                Err(why) => println!("{prefix}{}  FAILED: {why}", stored.line),
            }
        }
    } else {
        for d in &comparison.differences {
            let link = if d.row.role == crate::protocol::parameters::ParamRole::Link {
                "  (link setting: does not count)"
            } else {
                ""
            };
            println!(
                "{prefix}{}: module {}, file {}{link}",
                label(&d.row),
                d.module,
                d.file
            );
        }
    }
    if applying {
        for d in &report.link_left {
            println!(
                "{prefix}{}: module {}, file {}  link setting: not written",
                label(&d.row),
                d.module,
                d.file
            );
        }
    }
    let same = comparison.same.len();
    let summary = if !applying {
        format!(
            "{} differ, {} failed to read, {same} the same",
            row.differs, row.failed
        )
    } else if dry_run {
        format!(
            "{} to write (dry run: nothing sent), {same} already the same",
            report.values.len()
        )
    } else {
        format!(
            "wrote {}, verified {}, {} differ after writing, {} failed, {same} already the same{}",
            row.written,
            row.verified,
            row.differs,
            row.failed,
            if report.stored.is_empty() {
                String::new()
            } else {
                format!(", {} store line(s) sent", report.stored.len())
            }
        )
    };
    let note = if row.note.is_empty() {
        String::new()
    } else {
        format!(" ({})", row.note)
    };
    println!("{who} ({}): {summary}{note}", row.firmware);
}

fn module_json(value: &ModuleValue) -> Value {
    match value {
        ModuleValue::Value(v) => json!(v),
        _ => Value::Null,
    }
}

fn json_report(row: &ModuleRow, report: &ApplyReport, applying: bool, dry_run: bool) -> Value {
    let mut object = row.json();
    let difference = |d: &Difference| {
        json!({
            "scope": d.row.scope.key(),
            "number": d.row.number,
            "name": d.row.name,
            "module": module_json(&d.module),
            "module_note": d.module.why_not(),
            "file": d.file,
            "link": d.row.role == crate::protocol::parameters::ParamRole::Link,
        })
    };
    object["same"] = json!(report.comparison.same.len());
    if applying {
        object["dry_run"] = json!(dry_run);
        object["values"] = report
            .values
            .iter()
            .map(|v| {
                let mut o = difference(&v.difference);
                o["line"] = json!(v.line);
                o["outcome"] = json!(outcome_name(&v.outcome));
                match &v.outcome {
                    ValueOutcome::ReadBackDiffers(read) => o["read_back"] = json!(read),
                    ValueOutcome::Failed(why) => o["error"] = json!(why),
                    _ => {}
                }
                o
            })
            .chain(report.refused.iter().map(|(d, why)| {
                let mut o = difference(d);
                o["outcome"] = json!("failed");
                o["error"] = json!(why);
                o
            }))
            .collect();
        object["link_left"] = report.link_left.iter().map(difference).collect();
        object["stored"] = report
            .stored
            .iter()
            .map(|s| json!({ "line": s.line, "ok": s.result.is_ok(), "error": s.result.as_ref().err() }))
            .collect();
    } else {
        object["differences"] = report
            .comparison
            .differences
            .iter()
            .map(difference)
            .collect();
    }
    object
}
