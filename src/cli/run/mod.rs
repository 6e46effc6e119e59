//! `axterm run CONNECTION FILE` (or `-` for standard input): a batch file
//! of console lines and directives (syntax in [`super::script`]). The whole
//! file is parsed and every console line validated before anything is
//! sent; a bad line anywhere sends nothing and lists every bad line as
//! `FILE:LINE: message`. A run that fails, is cancelled (Ctrl-C) or loses
//! its link ends with the stop-everything sequence unless
//! `--no-stop-on-failure` (see [`super::run_end`]). A line the family
//! wants confirmed is refused when `--yes` is not given.

mod several_links;

use several_links::{FleetRun, run_on_links, said_cautions};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use clap::Args;
use serde_json::json;

use super::confirm::{after_line, cautions};
use super::connection::{Target, family_of, names_a_connection, run_to_exit};
use super::fleet::{self, FleetArgs, FleetLink, FleetModule, Identity, ModuleRow, Modules, Walk};
use super::output::{CheckOutcome, Format, json_check, print_outcome};
use super::run_end::{AtTheEnd, Interrupt, RunReport, run_then_end_with};
use super::run_sheet::{ModuleRecord, ReportArgs, SheetRequest};
use super::script::{self, Action, CheckedStep, WAIT_INTERVAL, check_script, result_matches};
use super::{ConnectionArgs, EXIT_CONNECTION, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::protocol::parameters::ParamRow;
use crate::protocol::settings::SettingsCache;
use crate::protocol::units::{MechanicsTable, check_line};
use crate::session::params::ApplyOptions;
use std::collections::HashMap;
use std::path::Path;

use crate::protocol::Family;
use crate::protocol::console::PreparedLine;
use crate::session::run_end::{RunEnding, StopOnFailure};
use crate::session::wiring::findings;
use crate::session::{LineResult, Session, SessionError};

#[derive(Debug, Clone, Args)]
pub struct RunArgs {
    /// The batch file, or - for standard input.
    pub file: String,
    /// Go on after a failed line or :expect (the exit code still says 1).
    #[arg(long)]
    pub keep_going: bool,
    /// Check the file only: parse and validate every line, send nothing
    /// (no connection needed; the options of one given are checked too,
    /// nothing is opened).
    #[arg(long)]
    pub dry_run: bool,
    /// text: the value (or ok) per console line; json: one object per
    /// console line and one per `:expect` and `:wait-until` (expected,
    /// actual, ok).
    #[arg(long, value_enum, default_value_t)]
    pub format: Format,
    /// When the run fails, is cancelled (Ctrl-C) or loses its link, leave
    /// the axes as they are. By default the family's stop-everything
    /// sequence is sent then (the console's emergency stop), waiting up to
    /// 10 s for a lost link to come back, and each stop line's answer is
    /// printed.
    #[arg(long)]
    pub no_stop_on_failure: bool,
    /// Send lines the family wants confirmed (a reset, a baud or address
    /// change, a motion that starts at once); without it the file is
    /// refused and nothing is sent.
    #[arg(long)]
    pub yes: bool,
    /// With --addresses or --all the file runs on each module in turn,
    /// each run ending as a single one does (the stop sequence at that
    /// module after a failure, unless --no-stop-on-failure); the next
    /// module is tried all the same unless --stop-on-failure.
    #[command(flatten)]
    pub fleet: FleetArgs,
    #[command(flatten)]
    pub sheet: ReportArgs,
}

/// The file's name as messages give it (`<stdin>` for `-`) and its text.
pub(super) fn read_source(file: &str) -> Result<(String, String), String> {
    if file == "-" {
        let text = crate::files::read_stdin_text()
            .map_err(|e| format!("cannot read standard input: {e}"))?;
        Ok(("<stdin>".into(), text))
    } else {
        let text = crate::files::read_text(file).map_err(|e| format!("cannot read {file}: {e}"))?;
        Ok((file.to_string(), text))
    }
}

pub fn run(connection: &ConnectionArgs, args: &RunArgs, mechanics: Option<&Path>) -> i32 {
    // A dry run needs only the family; a real run needs a connection. A
    // dry run given a connection checks its options as a real run would
    // (address, --program, --input), though nothing is opened.
    if !connection.more_links.is_empty() {
        return run_on_links(connection, args);
    }
    let resolved = if args.dry_run && !names_a_connection(connection) {
        family_of(connection).map(|family| {
            let address = connection
                .first_address()
                .unwrap_or_else(|| family.console.default_address());
            (family, address, None)
        })
    } else {
        Target::resolve(connection).map(|t| (t.family, t.address, (!args.dry_run).then_some(t)))
    };
    let (family, address, target) = match resolved {
        Ok(resolved) => resolved,
        Err(message) => {
            eprintln!("axterm run: {message}");
            return EXIT_USAGE;
        }
    };
    let sheet = match sheet_request(args) {
        Ok(sheet) => sheet,
        Err(code) => return code,
    };
    let link = super::links::describe_link(connection);
    let (name, text) = match read_source(&args.file) {
        Ok(source) => source,
        Err(message) => {
            eprintln!("axterm run: {message}");
            return EXIT_USAGE;
        }
    };
    let modules = match Modules::from_args(&args.fleet, family) {
        Ok(modules) => modules,
        Err(message) => {
            eprintln!("axterm run: {message}");
            return EXIT_USAGE;
        }
    };
    // Values in an axis's unit: checked against the mechanics now,
    // converted with the module's settings once connected (a dry run:
    // with the mechanics file's own), before the file is checked.
    let law = family.console.units();
    let unit_lines = script::unit_lines(&text, law);
    let mut text = text;
    if !unit_lines.is_empty() {
        let mechanics = match super::mechanics::load(mechanics) {
            Ok(m) => m.unwrap_or_default(),
            Err(message) => {
                eprintln!("axterm run: {message}");
                return EXIT_USAGE;
            }
        };
        let mut ok = true;
        for (number, line) in &unit_lines {
            let problem = if modules.several() {
                Some(
                    "values in an axis's unit are converted on one module at a time: give \
                      them raw to several"
                        .to_string(),
                )
            } else {
                check_line(law, line, &mechanics.table)
                    .err()
                    .map(String::from)
            };
            if let Some(problem) = problem {
                eprintln!("{name}:{number}: {problem}");
                ok = false;
            }
        }
        if !ok {
            eprintln!("axterm run: {name}: nothing was sent");
            return EXIT_USAGE;
        }
        match target {
            Some(target) => {
                let run = UnitRun {
                    name,
                    text,
                    sheet,
                    link,
                    unit_lines,
                    mechanics: mechanics.table,
                    yes: args.yes,
                    format: args.format,
                    keep_going: args.keep_going,
                    policy: StopOnFailure::from_flag(args.no_stop_on_failure),
                };
                return run_to_exit("run", run.run(target));
            }
            None => {
                let mut replaced = HashMap::new();
                for (number, line) in unit_lines {
                    match mechanics.convert_offline(law, &line) {
                        Ok(converted) => {
                            eprintln!(
                                "{name}:{number}: {}: {}",
                                converted.notes.join(", "),
                                converted.line
                            );
                            replaced.insert(number, (line, converted.line));
                        }
                        Err(problem) => {
                            eprintln!("{name}:{number}: {problem}");
                            ok = false;
                        }
                    }
                }
                if !ok {
                    eprintln!("axterm run: {name}: nothing was sent");
                    return EXIT_USAGE;
                }
                text = script::with_lines_replaced(&text, &replaced);
            }
        }
    }
    // Every module's lines are checked before anything is sent.
    if let Modules::List(addresses) = &modules
        && !checks_at("", &name, &text, family, addresses)
    {
        eprintln!("axterm run: {name}: nothing was sent");
        return EXIT_USAGE;
    }
    let checked = match check_script(&name, &text, family, address) {
        Ok(checked) => checked,
        Err(problems) => {
            for problem in problems {
                eprintln!("{problem}");
            }
            eprintln!("axterm run: {name}: nothing was sent");
            return EXIT_USAGE;
        }
    };
    if !said_cautions(&name, family, &checked, args.yes) {
        eprintln!("axterm run: {name}: nothing was sent");
        return EXIT_USAGE;
    }
    let Some(target) = target else {
        let lines = checked.iter().filter(|c| c.line.is_some()).count();
        eprintln!("axterm run: {name}: {lines} console lines valid, nothing sent (dry run)");
        return EXIT_OK;
    };
    let (format, keep_going) = (args.format, args.keep_going);
    let policy = StopOnFailure::from_flag(args.no_stop_on_failure);
    if modules.several() {
        let fleet_run = FleetRun {
            name,
            text,
            format,
            keep_going,
            policy,
            stop_on_failure: args.fleet.stop_on_failure,
            sheet: sheet.map(|request| (request, Mutex::new(Vec::new()))),
            link,
        };
        let links = vec![FleetLink {
            name: None,
            target,
            modules,
        }];
        return run_to_exit("run", async move { fleet_run.run(&links).await });
    }
    run_to_exit("run", async move {
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm run: {e}");
                return EXIT_CONNECTION;
            }
        };
        let run = CheckedRun {
            name: &name,
            text: &text,
            checked: &checked,
            format,
            keep_going,
            policy,
            sheet: sheet.as_ref(),
            link: &link,
        };
        run.run(&session).await
    })
}

/// The parameter files a run file applies (`:params`), by line number,
/// each read and checked against the family's tables.
type ParamFiles = HashMap<usize, Vec<(ParamRow, i64)>>;

/// Read and check every parameter file `checked` applies, a path
/// relative to the run file's folder (standard input: the working
/// folder); every problem as `NAME:LINE: message`. Called before
/// anything of the file is sent to a module.
fn load_params(
    name: &str,
    checked: &[CheckedStep],
    family: &Family,
) -> Result<ParamFiles, Vec<String>> {
    let mut files = ParamFiles::new();
    let mut problems = Vec::new();
    let folder = match name {
        "<stdin>" => None,
        name => Path::new(name).parent(),
    };
    for item in checked {
        let Action::ApplyParams { file, store } = &item.step.action else {
            continue;
        };
        let at = format!("{name}:{}: ", item.step.line_number);
        let Some(parameters) = family.console.parameters() else {
            problems.push(format!(
                "{at}the {} family has no parameter tables",
                family.name
            ));
            continue;
        };
        let axes: Vec<u8> = family.console.axes().iter().map(|a| a.number).collect();
        if *store && let Err(why) = super::params::refuse_store_without_place(parameters, &axes) {
            problems.push(format!("{at}{why}"));
            continue;
        }
        let path = match folder {
            Some(folder) if Path::new(file).is_relative() => folder.join(file),
            _ => Path::new(file).to_path_buf(),
        };
        match super::params::read_file(&path, family.name, parameters, &axes) {
            Ok((entries, _mechanics)) => {
                files.insert(item.step.line_number, entries);
            }
            Err(message) => problems.extend(message.lines().map(|l| format!("{at}{l}"))),
        }
    }
    if problems.is_empty() {
        Ok(files)
    } else {
        Err(problems)
    }
}

/// The sheet asked for, if any; the exit code when it cannot be (a file
/// that cannot be written, a dry run: nothing is sent).
fn sheet_request(args: &RunArgs) -> Result<Option<SheetRequest>, i32> {
    let sheet = SheetRequest::from_args(&args.sheet).map_err(|message| {
        eprintln!("axterm run: {message}");
        eprintln!("axterm run: nothing was sent");
        EXIT_USAGE
    })?;
    if args.dry_run && sheet.is_some() {
        eprintln!("axterm run: a dry run sends nothing and has no sheet: drop --report");
        return Err(EXIT_USAGE);
    }
    Ok(sheet)
}

/// A sheet's files written, or the exit code made 1 when they could not
/// be (said on standard error).
fn sheet_written(
    sheet: &SheetRequest,
    name: &str,
    modules: Vec<crate::report::ModuleSheet>,
    code: i32,
) -> i32 {
    match sheet.write(name, modules) {
        Ok(()) => code,
        Err(message) => {
            eprintln!("axterm run: {message}");
            if code == EXIT_OK { EXIT_DEVICE } else { code }
        }
    }
}

/// The checked file on one module's session, ended as a run is.
struct CheckedRun<'a> {
    name: &'a str,
    text: &'a str,
    checked: &'a [CheckedStep],
    format: Format,
    keep_going: bool,
    policy: StopOnFailure,
    sheet: Option<&'a SheetRequest>,
    link: &'a str,
}

impl CheckedRun<'_> {
    async fn run(&self, session: &Session) -> i32 {
        let Self {
            name,
            checked,
            format,
            keep_going,
            policy,
            ..
        } = *self;
        let params = match load_params(name, checked, session.family()) {
            Ok(params) => params,
            Err(problems) => {
                for problem in problems {
                    eprintln!("{problem}");
                }
                eprintln!("axterm run: {name}: nothing was sent");
                return EXIT_USAGE;
            }
        };
        // Watched from before the first line goes, so that a Ctrl-C as
        // soon as the run starts still ends it properly.
        let mut interrupt = match Interrupt::watch() {
            Ok(interrupt) => interrupt,
            Err(e) => {
                eprintln!("axterm run: cannot watch for Ctrl-C: {e}");
                return EXIT_DEVICE;
            }
        };
        // The sheet's identity is asked before the first line.
        let identity = match self.sheet {
            Some(_) => Some(Identity::ask(session).await),
            None => None,
        };
        let record = self.sheet.map(|_| ModuleRecord::new(self.text, checked));
        let runner = Runner {
            session,
            name,
            format,
            module: None,
            record: record.as_ref(),
            params: &params,
        };
        // With --keep-going a failed step does not end the run; the run
        // still failed, and ends as one that did.
        let work = async {
            let mut failed = false;
            for item in checked {
                if !runner.step(item).await {
                    failed = true;
                    if !keep_going {
                        break;
                    }
                }
            }
            !failed
        };
        let prefix = format!("axterm run: {name}: ");
        let report = RunReport {
            prefix: &prefix,
            format,
            at_the_end: AtTheEnd::of_script(checked),
        };
        let (ending, aftermath) =
            run_then_end_with(session, &mut interrupt, policy, &report, work).await;
        let code = match ending {
            RunEnding::Completed => EXIT_OK,
            RunEnding::Failed | RunEnding::Cancelled => EXIT_DEVICE,
        };
        let (Some(sheet), Some(record), Some(identity)) = (self.sheet, record, identity) else {
            return code;
        };
        let module = record
            .finish(
                session,
                sheet_identity(session, self.link, &identity),
                ending,
                aftermath.as_ref(),
            )
            .await;
        sheet_written(sheet, name, vec![module], code)
    }
}

/// The sheet's identity of the module on `session`.
fn sheet_identity(session: &Session, link: &str, identity: &Identity) -> crate::report::Identity {
    crate::report::Identity {
        family: session.family().name.to_string(),
        link: link.to_string(),
        address: session.address(),
        firmware: match identity {
            Identity::Firmware(firmware) => firmware.clone(),
            Identity::Odd(why) | Identity::Silent(why) => format!("(no firmware answer: {why})"),
        },
    }
}

/// A file with values in an axis's unit on one module: connected first,
/// its unit lines converted with the module's settings (reads only), the
/// file then checked as any other; a line that does not convert or check
/// sends nothing of the file.
struct UnitRun {
    name: String,
    text: String,
    sheet: Option<SheetRequest>,
    link: String,
    unit_lines: Vec<(usize, String)>,
    mechanics: MechanicsTable,
    yes: bool,
    format: Format,
    keep_going: bool,
    policy: StopOnFailure,
}

impl UnitRun {
    async fn run(self, target: Target) -> i32 {
        let name = &self.name;
        let session = match target.open().await {
            Ok(session) => session,
            Err(e) => {
                eprintln!("axterm run: {e}");
                return EXIT_CONNECTION;
            }
        };
        let mut replaced = HashMap::new();
        let mut ok = true;
        let family = session.family();
        // What the lines before each unit line write (not sent yet), for a
        // family whose settings are known from what was written.
        let mut known = session.settings().borrow().clone();
        let mut before = 0;
        for (number, line) in &self.unit_lines {
            for (_, earlier) in script::console_lines(&self.text)
                .into_iter()
                .filter(|(n, _)| (before..*number).contains(n))
            {
                if let Ok(prepared) = family.console.prepare(&earlier, session.address()) {
                    after_line(family.console, &prepared, &mut known);
                }
            }
            before = *number + 1;
            match session.convert_units(line, &self.mechanics, &known).await {
                Ok(converted) => {
                    eprintln!(
                        "{name}:{number}: {}: {}",
                        converted.notes.join(", "),
                        converted.line
                    );
                    if let Ok(prepared) = family.console.prepare(&converted.line, session.address())
                    {
                        after_line(family.console, &prepared, &mut known);
                    }
                    replaced.insert(*number, (line.clone(), converted.line));
                }
                Err(problem) => {
                    eprintln!("{name}:{number}: {problem}");
                    ok = false;
                }
            }
        }
        if !ok {
            eprintln!("axterm run: {name}: nothing was sent");
            return EXIT_USAGE;
        }
        let text = script::with_lines_replaced(&self.text, &replaced);
        let checked = match check_script(name, &text, family, session.address()) {
            Ok(checked) => checked,
            Err(problems) => {
                for problem in problems {
                    eprintln!("{problem}");
                }
                eprintln!("axterm run: {name}: nothing was sent");
                return EXIT_USAGE;
            }
        };
        if !said_cautions(name, family, &checked, self.yes) {
            eprintln!("axterm run: {name}: nothing was sent");
            return EXIT_USAGE;
        }
        let run = CheckedRun {
            name,
            text: &text,
            checked: &checked,
            format: self.format,
            keep_going: self.keep_going,
            policy: self.policy,
            sheet: self.sheet.as_ref(),
            link: &self.link,
        };
        run.run(&session).await
    }
}

/// Whether the file checks at each of `addresses` (every problem said).
/// `on` goes before each (the link, with several).
fn checks_at(on: &str, name: &str, text: &str, family: &'static Family, addresses: &[u8]) -> bool {
    let problems: Vec<String> = addresses
        .iter()
        .filter_map(|&a| check_script(name, text, family, a).err())
        .flatten()
        .collect();
    for problem in &problems {
        eprintln!("{on}{problem}");
    }
    problems.is_empty()
}

struct Runner<'a> {
    session: &'a Session,
    name: &'a str,
    format: Format,
    /// The module, when the file runs on several: its results say which.
    module: Option<&'a FleetModule>,
    /// The facts for the commissioning sheet, when one was asked for.
    record: Option<&'a ModuleRecord>,
    /// The parameter files the file applies, checked.
    params: &'a ParamFiles,
}

impl Runner<'_> {
    /// Run one step; false if it failed (the failure is reported).
    async fn step(&self, item: &CheckedStep) -> bool {
        let at = match self.module {
            Some(module) => format!(
                "{}: {}:{}: ",
                module.who(),
                self.name,
                item.step.line_number
            ),
            None => format!("{}:{}: ", self.name, item.step.line_number),
        };
        let family = self.session.family();
        match (&item.step.action, &item.line) {
            (Action::Line(text), Some(line)) => {
                let outcome = self.session.execute(line).await;
                match self.module {
                    None => print_outcome(self.format, family, text, &at, &outcome),
                    Some(module) => {
                        print_module_outcome(self.format, family, module, text, &at, &outcome)
                    }
                }
                if let Some(record) = self.record {
                    let (answer, canonical) = match &outcome {
                        Ok(result) => (result.value.to_string(), Some(line.canonical.as_str())),
                        Err(e) => (e.to_string(), None),
                    };
                    record.line(
                        item.step.line_number,
                        Some(answer),
                        outcome.is_ok(),
                        canonical,
                    );
                }
                outcome.is_ok()
            }
            (Action::Expect { line: text, value }, Some(line)) => {
                // A family whose answers carry no check of their own is read
                // twice before a value is called good.
                let good = |r: &LineResult| result_matches(&r.value.to_string(), value);
                let (outcome, ok) = match self.session.execute_confirmed(line, good).await {
                    Ok((result, ok)) => (Ok(result), ok),
                    Err(e) => (Err(e), false),
                };
                self.print_check(&CheckOutcome {
                    directive: "expect",
                    line: text,
                    line_number: item.step.line_number,
                    expected: value,
                    last: &outcome,
                    ok,
                });
                match &outcome {
                    Ok(result) if !ok => {
                        eprintln!(
                            "{at}expected {} == {value}, got {}",
                            result.line, result.value
                        );
                    }
                    Ok(_) => {}
                    Err(e) => eprintln!("{at}{e}"),
                }
                self.record_check(item, &outcome, ok);
                ok
            }
            (
                Action::WaitUntil {
                    line: text,
                    value,
                    timeout,
                },
                Some(line),
            ) => {
                let (last, ok) = self.wait_until(&at, line, value, *timeout).await;
                self.record_check(item, &last, ok);
                self.print_check(&CheckOutcome {
                    directive: "wait-until",
                    line: text,
                    line_number: item.step.line_number,
                    expected: value,
                    last: &last,
                    ok,
                });
                ok
            }
            (Action::Sleep(duration), _) => {
                tokio::time::sleep(*duration).await;
                if let Some(record) = self.record {
                    record.line(item.step.line_number, None, true, None);
                }
                true
            }
            (Action::Echo(text), _) => {
                if let Some(record) = self.record {
                    record.line(item.step.line_number, Some(text.clone()), true, None);
                }
                match (self.format, self.module) {
                    (Format::Text, None) => println!("{text}"),
                    (Format::Text, Some(module)) => println!("{}: {text}", module.who()),
                    (Format::Json, None) => println!("{}", json!({ "echo": text })),
                    (Format::Json, Some(module)) => {
                        let mut object = json!({ "echo": text });
                        module.mark(&mut object);
                        println!("{object}");
                    }
                }
                true
            }
            (Action::ApplyParams { file, store }, _) => {
                self.apply_params(&at, item.step.line_number, file, *store)
                    .await
            }
            // Said of the file as a whole (see `run_then_end_on`).
            (Action::LeaveMoving, _) => {
                if let Some(record) = self.record {
                    record.line(item.step.line_number, None, true, None);
                }
                true
            }
            (action @ (Action::Wiring(_) | Action::TuneStep(_) | Action::TuneStallguard(_)), _) => {
                self.tool(&at, item.step.line_number, action).await
            }
            // check_script prepares a line for every step that has one.
            (_, None) => {
                eprintln!("{at}internal error: the line was not checked");
                false
            }
        }
    }

    /// Apply the checked parameter file of line `number` as `params
    /// apply` does (only values that differ written, each read back where
    /// the family can; with `store` stored afterwards): one line saying
    /// what was done; false if anything failed or reads back otherwise.
    async fn apply_params(&self, at: &str, number: usize, file: &str, store: bool) -> bool {
        let family = self.session.family();
        let (Some(entries), Some(parameters)) =
            (self.params.get(&number), family.console.parameters())
        else {
            eprintln!("{at}internal error: the parameter file was not checked");
            return false;
        };
        let options = ApplyOptions {
            store,
            dry_run: false,
        };
        let report =
            crate::session::params::apply(self.session, parameters, entries, options).await;
        let ok = report.succeeded();
        let stored = store && ok && report.stored.iter().all(|s| s.result.is_ok());
        let mut said = format!(
            "{file}: {} written, {} verified",
            report.written(),
            report.verified()
        );
        if store {
            said += &format!(
                ", {} stored",
                report.stored.iter().filter(|s| s.result.is_ok()).count()
            );
        }
        if !ok {
            said += &format!(
                ", {} failed, {} read back otherwise",
                report.failed(),
                report.differs()
            );
            eprintln!("{at}{said}");
        }
        match (self.format, self.module) {
            (Format::Text, None) => println!("{said}"),
            (Format::Text, Some(module)) => println!("{}: {said}", module.who()),
            (Format::Json, module) => {
                let mut object = json!({ "params": file, "said": said, "ok": ok });
                if let Some(module) = module {
                    module.mark(&mut object);
                }
                println!("{object}");
            }
        }
        if let Some(record) = self.record {
            record.params_applied(number, file, said, ok, stored);
        }
        ok
    }

    /// Lines a tool printed: each as a line (text; after `module N: ` with
    /// several), or one JSON object `{"tool": …, "lines": […], "ok": …}`.
    fn say(&self, tool: &str, lines: &[String], ok: bool) {
        match (self.format, self.module) {
            (Format::Text, None) => lines.iter().for_each(|l| println!("{l}")),
            (Format::Text, Some(module)) => {
                lines.iter().for_each(|l| println!("{}: {l}", module.who()));
            }
            (Format::Json, module) => {
                let mut object = json!({ "tool": tool, "lines": lines, "ok": ok });
                if let Some(module) = module {
                    module.mark(&mut object);
                }
                println!("{object}");
            }
        }
    }

    /// A tool directive of line `number` (checked with the file): the
    /// wiring check, a step test or a sweep, its lines printed and put on
    /// the sheet. False when it failed, found a wiring fault or tripped.
    async fn tool(&self, at: &str, number: usize, action: &Action) -> bool {
        let session = self.session;
        let Some(Ok(plan)) = script::tool_plan(action, session.family()) else {
            eprintln!("{at}internal error: the directive was not checked");
            return false;
        };
        let failed = |error: String| {
            eprintln!("{at}{error}");
            if let Some(record) = self.record {
                record.line(number, Some(error), false, None);
            }
            false
        };
        match plan {
            script::ToolPlan::Wiring {
                plan,
                index,
                axis,
                speed,
                give_up,
            } => {
                let legs = match session.check_wiring(plan, index, speed, give_up).await {
                    Ok(legs) => legs,
                    Err(error) => return failed(error.to_string()),
                };
                let found = findings(axis.name, &legs);
                let faults = crate::session::wiring::faults(axis.name, &legs);
                let right = faults.is_empty();
                self.say("wiring", &found, right);
                if !right {
                    eprintln!("{at}the wiring check found a fault: {}", faults.join("; "));
                }
                if let Some(record) = self.record {
                    record.wiring(number, found, faults);
                }
                right
            }
            script::ToolPlan::Step {
                plan,
                index,
                axis,
                ask,
                spec,
            } => {
                let run = match session.step_response(plan, index, &ask, &spec).await {
                    Ok(run) => run,
                    Err(error) => return failed(error.to_string()),
                };
                let lines = super::tune::step_lines(&axis, &run);
                let ok = run.tripped.is_empty();
                self.say("tune-step", &lines, ok);
                let said = match run.tripped.iter().map(|f| f.name).collect::<Vec<_>>() {
                    tripped if tripped.is_empty() => format!("{} samples", run.samples.len()),
                    tripped => {
                        let said =
                            format!("tripped ({}): the axis was stopped", tripped.join(", "));
                        eprintln!("{at}{said}");
                        said
                    }
                };
                if let Some(record) = self.record {
                    let plot = super::tune::step_plot(&axis, &run);
                    record.tuned(number, said, ok, lines, vec![plot]);
                }
                ok
            }
            script::ToolPlan::Sweep {
                plan,
                index,
                axis,
                ask,
            } => {
                let run = match session.stall_sweep(plan, index, &ask).await {
                    Ok(run) => run,
                    Err(error) => return failed(error.to_string()),
                };
                // The sweep's stop ramps the motor down: the run goes on
                // (or ends) with it at rest.
                match session
                    .wait_standing(index, crate::session::tuning::STAND_WAIT)
                    .await
                {
                    Ok(true) => {}
                    Ok(false) => {
                        return failed(format!(
                            "{} still moves {} s after the sweep's stop",
                            axis.name,
                            crate::session::tuning::STAND_WAIT.as_secs()
                        ));
                    }
                    Err(error) => return failed(error.to_string()),
                }
                let text = super::tune::show_sweep(
                    plan.reading(),
                    &run,
                    None,
                    super::tune::TuneFormat::Text,
                );
                let lines: Vec<String> = text.lines().map(str::to_string).collect();
                self.say("tune-stallguard", &lines, true);
                if let Some(record) = self.record {
                    let plot = super::tune::sweep_plot(&axis, plan.reading(), &run);
                    let said = format!("{} speeds swept", run.points.len());
                    record.tuned(number, said, true, lines, vec![plot]);
                }
                true
            }
        }
    }

    /// A check's reading for the sheet: the value read, or the error.
    fn record_check(
        &self,
        item: &CheckedStep,
        outcome: &Result<LineResult, SessionError>,
        ok: bool,
    ) {
        if let Some(record) = self.record {
            let actual = match outcome {
                Ok(result) => result.value.to_string(),
                Err(e) => e.to_string(),
            };
            record.check(item.step.line_number, actual, ok);
        }
    }

    /// A check's object on standard output (JSON only: the text form
    /// says nothing of a check that passes, a failed one on stderr).
    fn print_check(&self, check: &CheckOutcome) {
        if self.format != Format::Json {
            return;
        }
        let mut object = json_check(check);
        if let Some(module) = self.module {
            module.mark(&mut object);
        }
        println!("{object}");
    }

    /// Read `line` until it gives `value` or `timeout` has passed: the
    /// last reading, and whether it matched (a failure is said).
    async fn wait_until(
        &self,
        at: &str,
        line: &PreparedLine,
        value: &str,
        timeout: Duration,
    ) -> (Result<LineResult, SessionError>, bool) {
        let deadline = tokio::time::Instant::now() + timeout;
        loop {
            let good = |r: &LineResult| result_matches(&r.value.to_string(), value);
            let (outcome, ok) = match self.session.execute_confirmed(line, good).await {
                Ok((result, ok)) => (Ok(result), ok),
                Err(e) => (Err(e), false),
            };
            let got = match &outcome {
                Ok(result) => result.value.to_string(),
                Err(e) => {
                    eprintln!("{at}{e}");
                    return (outcome, false);
                }
            };
            if ok {
                return (outcome, true);
            }
            if tokio::time::Instant::now() >= deadline {
                eprintln!(
                    "{at}{} did not become {value} within {} (last {got})",
                    line.canonical,
                    show_duration(timeout)
                );
                return (outcome, false);
            }
            tokio::time::sleep(WAIT_INTERVAL).await;
        }
    }
}

/// A line's outcome on one module of several: the value after `module N:
/// ` (text), or the JSON object with the module.
fn print_module_outcome(
    format: Format,
    family: &Family,
    module: &FleetModule,
    line: &str,
    context: &str,
    outcome: &Result<crate::session::LineResult, crate::session::SessionError>,
) {
    match format {
        Format::Text => {
            if let Ok(result) = outcome {
                println!("{}: {}", module.who(), result.value);
                if let Some(note) = super::output::unchecked_note(family, line, result) {
                    eprintln!("{context}{note}");
                }
            }
        }
        Format::Json => {
            let mut object = super::output::json_outcome(family, line, outcome);
            module.mark(&mut object);
            println!("{object}");
        }
    }
    if let Err(error) = outcome {
        eprintln!("{context}{error}");
    }
}

fn show_duration(duration: Duration) -> String {
    if duration.subsec_millis() == 0 {
        format!("{} s", duration.as_secs())
    } else {
        format!("{} ms", duration.as_millis())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::find_family;

    fn check(text: &str) -> Result<Vec<CheckedStep>, Vec<String>> {
        check_script("f.txt", text, find_family("tmcl").unwrap(), 1)
    }

    #[test]
    fn every_bad_console_line_is_listed_with_file_and_line() {
        let problems = check("GAP 1, 0\nSAP 6, 0, 100000\n:expect FOO 1 == 2\nMST 0\n")
            .err()
            .unwrap();
        assert_eq!(problems.len(), 2, "{problems:?}");
        assert!(problems[0].starts_with("f.txt:2: "), "{}", problems[0]);
        assert!(problems[0].contains("0..255"), "{}", problems[0]);
        assert!(problems[1].starts_with("f.txt:3: "), "{}", problems[1]);
    }

    #[test]
    fn syntax_errors_and_bad_console_lines_are_listed_together_in_order() {
        let problems = check("BOGUS\n:sleep forever\n").err().unwrap();
        assert_eq!(problems.len(), 2, "{problems:?}");
        assert!(
            problems[0].starts_with("f.txt:1: `BOGUS`"),
            "{}",
            problems[0]
        );
        assert!(
            problems[1].starts_with("f.txt:2: `forever`"),
            "{}",
            problems[1]
        );
    }

    #[test]
    fn wait_until_refuses_lines_that_act() {
        let problems = check(":wait-until MVP ABS, 0, 100 == ok\n").err().unwrap();
        assert!(problems[0].contains("only reads"), "{}", problems[0]);
        assert!(check(":wait-until GAP 8, 0 == 1 timeout 2s\n").is_ok());
    }

    #[test]
    fn a_valid_file_has_a_line_for_every_step_that_sends() {
        let checked =
            check("# c\nSAP 4, 0, 5\n:expect GAP 4, 0 == 5\n:echo hi\n:sleep 1s\n").unwrap();
        let sends: Vec<bool> = checked.iter().map(|c| c.line.is_some()).collect();
        assert_eq!(sends, [true, true, false, false]);
    }

    #[test]
    fn durations_show_plainly() {
        assert_eq!(show_duration(Duration::from_secs(10)), "10 s");
        assert_eq!(show_duration(Duration::from_millis(1500)), "1500 ms");
    }
}
