//! `axterm run FILE --report SHEET.html --report-json SHEET.json`: the
//! commissioning sheet of the run ([`crate::report`]). The facts are
//! gathered here as the run goes ([`ModuleRecord`]): the module's
//! identity asked before the first line, each line's answer and each
//! check's reading as they come, the run's end and stop as they were
//! reported, and the settings read after the run against the family's
//! factory defaults. The files are checked before anything is sent and
//! written when the run has ended; an existing file is replaced only with
//! `--force`.

use std::path::PathBuf;
use std::sync::Mutex;
use std::time::SystemTime;

use clap::Args;

use super::script::{Action, CheckedStep};
use crate::files::{Existing, check_destination};
use crate::report::{
    CheckOutcome, Checks, EmergencyStop, Ending, Expectation, Identity, LineKind, LineOutcome,
    ModuleSheet, Plot, RunEnd, RunLine, Settings, Sheet, Tuning, Wiring, sheet_html, sheet_json,
};
use crate::session::Session;
use crate::session::run_end::{RunAftermath, RunEnding};
use crate::wall_clock::CivilTime;

#[derive(Debug, Clone, Default, Args)]
pub struct ReportArgs {
    /// Write the commissioning sheet of the run to this file: one
    /// self-contained HTML page (verdict, identity, settings against the
    /// factory defaults, every line and check, the run's end), for A4.
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
    /// Write the sheet as JSON (schema: docs/sheet.schema.json, version 1).
    #[arg(long, value_name = "FILE")]
    pub report_json: Option<PathBuf>,
    /// Who ran it, for the sheet; by default the login name (USER,
    /// LOGNAME).
    #[arg(long, value_name = "NAME")]
    pub operator: Option<String>,
    /// Replace an existing --report or --report-json file (without it an
    /// existing file is refused, exit 2, and nothing is sent).
    #[arg(long)]
    pub force: bool,
}

/// A sheet asked for: where it goes, and the facts of the whole run.
pub struct SheetRequest {
    html: Option<PathBuf>,
    json: Option<PathBuf>,
    existing: Existing,
    operator: String,
    started: SystemTime,
}

fn now_utc(time: SystemTime) -> String {
    CivilTime::of(time).stamp()
}

impl SheetRequest {
    /// The request, if a sheet was asked for; a file that cannot be
    /// written is refused now, before anything is sent.
    pub fn from_args(args: &ReportArgs) -> Result<Option<SheetRequest>, String> {
        if args.report.is_none() && args.report_json.is_none() {
            if args.operator.is_some() || args.force {
                return Err("--operator and --force go with --report or --report-json".into());
            }
            return Ok(None);
        }
        if args.report.is_some() && args.report == args.report_json {
            return Err("--report and --report-json name the same file".into());
        }
        let existing = Existing::from_force(args.force);
        for path in [&args.report, &args.report_json].into_iter().flatten() {
            check_destination(path, existing)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
        let operator = args
            .operator
            .clone()
            .or_else(|| std::env::var("USER").ok().filter(|u| !u.is_empty()))
            .or_else(|| std::env::var("LOGNAME").ok().filter(|u| !u.is_empty()))
            .unwrap_or_else(|| "(not given)".into());
        Ok(Some(SheetRequest {
            html: args.report.clone(),
            json: args.report_json.clone(),
            existing,
            operator,
            started: SystemTime::now(),
        }))
    }

    /// Write the sheet of `modules`; what went wrong, if anything.
    pub fn write(&self, run_file: &str, modules: Vec<ModuleSheet>) -> Result<(), String> {
        let sheet = Sheet {
            run_file: run_file.to_string(),
            operator: self.operator.clone(),
            axterm_version: env!("CARGO_PKG_VERSION").to_string(),
            started_utc: now_utc(self.started),
            ended_utc: now_utc(SystemTime::now()),
            modules,
        };
        if let Some(path) = &self.html {
            crate::files::save(path, sheet_html(&sheet).as_bytes(), self.existing)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
        if let Some(path) = &self.json {
            let mut text = serde_json::to_string_pretty(&sheet_json(&sheet))
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
            text.push('\n');
            crate::files::save(path, text.as_bytes(), self.existing)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
        Ok(())
    }
}

/// One module's facts as its run goes. Shared by reference with the
/// steps of the run (which may be dropped at a Ctrl-C), hence the lock.
pub struct ModuleRecord {
    facts: Mutex<Checks>,
    /// The canonical form of each console line that succeeded, to find a
    /// store among them.
    sent: Mutex<Vec<String>>,
    /// The parameter file applied (the last one), and whether a
    /// parameter file's settings were stored.
    applied: Mutex<(Option<String>, bool)>,
    /// The tuning results of the run's tool directives, in order.
    tuning: Mutex<Option<Tuning>>,
}

/// How a file's line is classed on the sheet (the syntax of
/// [`crate::script`]: `#` and `//` comments, `:` directives).
fn kind_of(line: &str) -> Option<LineKind> {
    let line = line.trim();
    if line.is_empty() {
        None
    } else if line.starts_with('#') || line.starts_with("//") {
        Some(LineKind::Comment)
    } else if line.starts_with(':') {
        Some(LineKind::Directive)
    } else {
        Some(LineKind::ConsoleLine)
    }
}

impl ModuleRecord {
    /// Every line of `text` not run yet, and every check of `checked`.
    pub fn new(text: &str, checked: &[CheckedStep]) -> ModuleRecord {
        let lines = text
            .lines()
            .enumerate()
            .filter_map(|(index, line)| {
                kind_of(line).map(|kind| RunLine {
                    number: index + 1,
                    text: line.trim().to_string(),
                    kind,
                    answer: None,
                    outcome: if kind == LineKind::Comment {
                        LineOutcome::Nothing
                    } else {
                        LineOutcome::NotRun
                    },
                })
            })
            .collect();
        let expectations = checked
            .iter()
            .filter_map(|item| {
                let (directive, line, value) = match &item.step.action {
                    Action::Expect { line, value } => ("expect", line, value),
                    Action::WaitUntil { line, value, .. } => ("wait-until", line, value),
                    _ => return None,
                };
                Some(Expectation {
                    number: item.step.line_number,
                    directive: directive.into(),
                    line: line.clone(),
                    expected: value.clone(),
                    actual: None,
                    outcome: CheckOutcome::NotRun,
                })
            })
            .collect();
        ModuleRecord {
            facts: Mutex::new(Checks {
                lines,
                expectations,
                ..Checks::default()
            }),
            sent: Mutex::new(Vec::new()),
            applied: Mutex::new((None, false)),
            tuning: Mutex::new(None),
        }
    }

    /// The parameter file of line `number` was applied: what was said of
    /// it, whether it went well, whether its settings were stored.
    pub fn params_applied(&self, number: usize, file: &str, said: String, ok: bool, stored: bool) {
        self.line(number, Some(said), ok, None);
        let mut applied = self.applied.lock().unwrap_or_else(|e| e.into_inner());
        applied.0 = Some(file.to_string());
        applied.1 |= stored;
    }

    /// The wiring check of line `number` found `findings` (`faults` among
    /// them): on the sheet's wiring check, several checks of a run
    /// together (wired right only if each was).
    pub fn wiring(&self, number: usize, findings: Vec<String>, faults: Vec<String>) {
        let right = faults.is_empty();
        let said = if right {
            "wired right".to_string()
        } else {
            format!("{} fault(s): see the wiring check", faults.len())
        };
        self.with(|facts| {
            let wiring = facts.wiring.get_or_insert_with(|| Wiring {
                findings: Vec::new(),
                wired_right: true,
                faults: Vec::new(),
            });
            wiring.findings.extend(findings);
            wiring.faults.extend(faults);
            wiring.wired_right &= right;
        });
        self.line(number, Some(said), right, None);
    }

    /// The tuning tool of line `number` gave `figures` and `plots`; `ok`
    /// false when it tripped (`said` says why).
    pub fn tuned(
        &self,
        number: usize,
        said: String,
        ok: bool,
        figures: Vec<String>,
        plots: Vec<Plot>,
    ) {
        {
            let mut tuning = self.tuning.lock().unwrap_or_else(|e| e.into_inner());
            let tuning = tuning.get_or_insert_with(Tuning::default);
            tuning.figures.extend(figures);
            tuning.plots.extend(plots);
        }
        self.line(number, Some(said), ok, None);
    }

    /// The section of a module the run never reached (it did not answer,
    /// the file does not check for its address): every line not run, the
    /// run failed for `why`, no setting read.
    pub fn unreached(text: &str, identity: Identity, why: &str) -> ModuleSheet {
        let mut checks = ModuleRecord::new(text, &[])
            .facts
            .into_inner()
            .unwrap_or_else(|e| e.into_inner());
        checks.run_end = RunEnd {
            ending: Ending::Failed,
            summary: format!("nothing was sent: {why}"),
            stopped_axes: Vec::new(),
        };
        ModuleSheet {
            identity,
            settings: Settings::default(),
            checks,
            tuning: None,
        }
    }

    fn with<T>(&self, f: impl FnOnce(&mut Checks) -> T) -> T {
        let mut facts = self.facts.lock().unwrap_or_else(|e| e.into_inner());
        f(&mut facts)
    }

    /// Line `number` was done: its answer (or error) and whether it went
    /// well. `canonical` is the console line sent, if it succeeded.
    pub fn line(&self, number: usize, answer: Option<String>, ok: bool, canonical: Option<&str>) {
        self.with(|facts| {
            if let Some(line) = facts.lines.iter_mut().find(|l| l.number == number) {
                line.answer = answer;
                line.outcome = LineOutcome::of(ok);
            }
        });
        if let (true, Some(canonical)) = (ok, canonical) {
            self.sent
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(canonical.to_string());
        }
    }

    /// The check on line `number` read `actual` (or failed so).
    pub fn check(&self, number: usize, actual: String, pass: bool) {
        self.with(|facts| {
            if let Some(e) = facts.expectations.iter_mut().find(|e| e.number == number) {
                e.actual = Some(actual.clone());
                e.outcome = if pass {
                    CheckOutcome::Pass
                } else {
                    CheckOutcome::Fail
                };
            }
        });
        self.line(number, Some(actual), pass, None);
    }

    /// The module's section, once its run has ended: the identity given,
    /// the end as it came, and the settings read now.
    pub async fn finish(
        self,
        session: &Session,
        identity: Identity,
        ending: RunEnding,
        aftermath: Option<&RunAftermath>,
    ) -> ModuleSheet {
        let sent = self.sent.into_inner().unwrap_or_else(|e| e.into_inner());
        let (parameter_file, stored) = self.applied.into_inner().unwrap_or_else(|e| e.into_inner());
        let tuning = self.tuning.into_inner().unwrap_or_else(|e| e.into_inner());
        let mut checks = self.facts.into_inner().unwrap_or_else(|e| e.into_inner());
        checks.run_end = RunEnd {
            ending: match ending {
                RunEnding::Completed => Ending::Completed,
                RunEnding::Failed => Ending::Failed,
                RunEnding::Cancelled => Ending::Cancelled,
            },
            summary: aftermath.map_or_else(
                || match ending {
                    RunEnding::Completed => "the run completed".into(),
                    _ => "the run did not complete".into(),
                },
                RunAftermath::summary,
            ),
            stopped_axes: Vec::new(),
        };
        if let Some(RunAftermath::Stopped(stop)) = aftermath {
            checks.run_end.stopped_axes = stop
                .lines
                .iter()
                .filter_map(|l| l.as_ref().ok().map(|r| r.line.clone()))
                .collect();
            checks.emergency_stop = Some(EmergencyStop {
                reason: match ending {
                    RunEnding::Cancelled => "the run was cancelled".into(),
                    _ => "the run failed".into(),
                },
                lines: aftermath
                    .map(RunAftermath::report)
                    .unwrap_or_default()
                    .into_iter()
                    .skip(1)
                    .map(|l| l.trim().to_string())
                    .collect(),
            });
        }
        // After a second Ctrl-C gave up the stop the user wants out: the
        // module is not asked anything more.
        let mut settings = match aftermath {
            Some(_) => crate::session::sheet::read_settings(session, &sent).await,
            None => Settings::default(),
        };
        settings.parameter_file = parameter_file;
        settings.eeprom_stored |= stored;
        ModuleSheet {
            identity,
            settings,
            checks,
            tuning,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::find_family;
    use crate::script::check_script;

    const FILE: &str =
        "# set up\n\nSAP 4, 0, 1000\n:expect GAP 4, 0 == 1000\n// the end\n:echo done\n";

    fn record() -> ModuleRecord {
        let checked = check_script("f.txt", FILE, find_family("tmcl").unwrap(), 1).unwrap();
        ModuleRecord::new(FILE, &checked)
    }

    #[test]
    fn every_line_but_blanks_is_on_the_sheet_classed_and_not_run_until_done() {
        let record = record();
        let facts = record.facts.lock().unwrap();
        let kinds: Vec<(usize, LineKind, LineOutcome)> = facts
            .lines
            .iter()
            .map(|l| (l.number, l.kind, l.outcome))
            .collect();
        assert_eq!(
            kinds,
            [
                (1, LineKind::Comment, LineOutcome::Nothing),
                (3, LineKind::ConsoleLine, LineOutcome::NotRun),
                (4, LineKind::Directive, LineOutcome::NotRun),
                (5, LineKind::Comment, LineOutcome::Nothing),
                (6, LineKind::Directive, LineOutcome::NotRun),
            ]
        );
        assert_eq!(facts.expectations.len(), 1);
        assert_eq!(facts.expectations[0].outcome, CheckOutcome::NotRun);
    }

    #[test]
    fn a_check_marks_its_expectation_and_its_line() {
        let record = record();
        record.line(3, Some("ok".into()), true, Some("SAP 4, 0, 1000"));
        record.check(4, "999".into(), false);
        let facts = record.facts.lock().unwrap();
        assert_eq!(facts.lines[1].outcome, LineOutcome::Ok);
        assert_eq!(facts.lines[2].outcome, LineOutcome::Failed);
        assert_eq!(facts.lines[2].answer.as_deref(), Some("999"));
        let e = &facts.expectations[0];
        assert_eq!(
            (e.outcome, e.actual.as_deref()),
            (CheckOutcome::Fail, Some("999"))
        );
        assert_eq!(*record.sent.lock().unwrap(), ["SAP 4, 0, 1000"]);
    }

    #[test]
    fn a_module_never_reached_is_a_failed_section_that_says_why() {
        let identity = Identity {
            family: "tmcl".into(),
            link: "--sim tmcm1110".into(),
            address: 2,
            firmware: "(no firmware answer: module 2 does not answer)".into(),
        };
        let section = ModuleRecord::unreached(FILE, identity, "module 2 does not answer");
        let verdict = section.verdict();
        assert!(!verdict.passed);
        assert!(
            verdict.failures[0].contains("nothing was sent: module 2 does not answer"),
            "{:?}",
            verdict.failures
        );
    }

    #[test]
    fn a_sheet_needs_a_file_and_refuses_one_name_for_both() {
        let none = ReportArgs::default();
        assert!(SheetRequest::from_args(&none).unwrap().is_none());
        let orphan = ReportArgs {
            operator: Some("Ada".into()),
            ..ReportArgs::default()
        };
        assert!(SheetRequest::from_args(&orphan).is_err());
        let same = ReportArgs {
            report: Some("s".into()),
            report_json: Some("s".into()),
            ..ReportArgs::default()
        };
        let error = SheetRequest::from_args(&same).err().unwrap();
        assert!(error.contains("the same file"), "{error}");
    }
}
