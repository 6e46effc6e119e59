//! The facts of a commissioning run, as the sheet shows them: plain data
//! gathered by the front end that ran the lines (`axterm run`), with no
//! I/O of its own. The verdict is computed here from the checks, so the
//! page and the JSON can never disagree with what was found.

use serde::Serialize;

/// Everything the technician hands over after a run: who ran what, when,
/// and one section per module the run went to.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sheet {
    /// The run file as it was named (`<stdin>` for standard input).
    pub run_file: String,
    /// Who ran it (`--operator`, else the login name).
    pub operator: String,
    /// The axterm version that made the sheet.
    pub axterm_version: String,
    /// When the run started and ended, ISO 8601 in UTC.
    pub started_utc: String,
    pub ended_utc: String,
    pub modules: Vec<ModuleSheet>,
}

/// One module's part of the sheet.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModuleSheet {
    pub identity: Identity,
    pub settings: Settings,
    pub checks: Checks,
    /// Tuning results; `None` until the tuning tools fill it.
    pub tuning: Option<Tuning>,
}

/// Which module this is.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identity {
    /// The protocol family's name (`tmcl`, `cmd4cr`, …).
    pub family: String,
    /// The link as given (`--sim tmcm1110`, `--port /dev/ttyUSB0`).
    pub link: String,
    pub address: u8,
    /// The module's answer to the family's firmware query, or why there is
    /// none (in words).
    pub firmware: String,
}

/// The module's settings when the run ended.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Settings {
    /// The parameter file applied during the run, if any (its name).
    pub parameter_file: Option<String>,
    /// Each setting with a factory default in the family's tables.
    pub rows: Vec<SettingRow>,
    /// Whether the settings were stored to EEPROM/flash during the run.
    pub eeprom_stored: bool,
    /// When the settings were read, or why they were not (the console's
    /// `:report` reads them when it is given); `None` for a run's sheet,
    /// whose settings are read after the run.
    pub read: Option<String>,
}

/// One setting against the family's factory default.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SettingRow {
    /// Where it lives: `axis 0`, `bank 0`.
    pub scope: String,
    pub number: u16,
    pub name: String,
    /// The value read from the module, or `None` with `note` saying why.
    pub value: Option<i64>,
    pub note: Option<String>,
    pub factory_default: Option<i64>,
    /// The raw value's unit (`counts/s`, `V`); empty for plain numbers,
    /// flags and codes.
    pub unit: String,
    /// The value and the default as the family writes them where that is
    /// not the raw number (MCCL's reals: `10.00000` for the raw 1000000);
    /// what the page shows.
    pub value_text: Option<String>,
    pub default_text: Option<String>,
}

impl SettingRow {
    /// Whether the module's value is known and differs from the default.
    pub fn differs(&self) -> bool {
        matches!((self.value, self.factory_default), (Some(v), Some(d)) if v != d)
    }
}

/// What happened during the run, line by line.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Checks {
    /// Every line of the run file that is not blank, in order.
    pub lines: Vec<RunLine>,
    /// Every `:expect` and `:wait-until`, in order.
    pub expectations: Vec<Expectation>,
    /// The wiring check's findings, if the run did one.
    pub wiring: Option<Wiring>,
    /// The stop-everything sequence, if the run ended with it.
    pub emergency_stop: Option<EmergencyStop>,
    pub run_end: RunEnd,
}

/// One line of the run file and what came of it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunLine {
    /// The line's number in the file (1-based).
    pub number: usize,
    pub text: String,
    pub kind: LineKind,
    /// The module's answer (or the error), for a line that was sent.
    pub answer: Option<String>,
    pub outcome: LineOutcome,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum LineKind {
    Comment,
    ConsoleLine,
    Directive,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum LineOutcome {
    /// Sent (or done) and answered as hoped.
    Ok,
    Failed,
    /// The run ended before the line.
    NotRun,
    /// A comment: nothing to do.
    Nothing,
}

impl LineOutcome {
    /// Ok when it went as hoped, else failed.
    pub fn of(ok: bool) -> LineOutcome {
        if ok {
            LineOutcome::Ok
        } else {
            LineOutcome::Failed
        }
    }
}

/// An `:expect` or `:wait-until`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Expectation {
    pub number: usize,
    /// `expect` or `wait-until`.
    pub directive: String,
    pub line: String,
    pub expected: String,
    /// The last value read, or the error; `None` when it never ran.
    pub actual: Option<String>,
    pub outcome: CheckOutcome,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CheckOutcome {
    Pass,
    Fail,
    NotRun,
}

/// The wiring check's findings, one plain line each.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Wiring {
    pub findings: Vec<String>,
    /// Each switch fired for its own direction and stopped the axis.
    pub wired_right: bool,
    /// The findings that are faults (empty when wired right): what the
    /// verdict names.
    pub faults: Vec<String>,
}

/// The stop-everything sequence at the end of a run that did not complete.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EmergencyStop {
    /// Why it was sent.
    pub reason: String,
    /// Each stop line with its answer.
    pub lines: Vec<String>,
}

/// How the run ended.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct RunEnd {
    pub ending: Ending,
    /// What was said of the end (the axes left as they were, stopped…).
    pub summary: String,
    /// The stop lines that answered ok at the end (each stops an axis or
    /// a program), empty when no stop was sent.
    pub stopped_axes: Vec<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Ending {
    Completed,
    #[default]
    Failed,
    Cancelled,
}

/// Tuning results: plots and figures. Empty until the tuning tools exist.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Tuning {
    pub plots: Vec<Plot>,
    /// Figure lines such as `rise time 12 ms`.
    pub figures: Vec<String>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Series {
    pub name: String,
    /// (x, y) points in the plot's units.
    pub points: Vec<(f64, f64)>,
}

impl Checks {
    /// Whether `line` failed and counts as a check of its own: a console
    /// line, or a directive that is neither an `:expect`/`:wait-until`
    /// (counted as such) nor a `:wiring` whose findings the wiring check
    /// holds (counted by it): a `:params` that failed, a `:tune-step`
    /// whose axis tripped.
    fn counts_failed(&self, line: &RunLine) -> bool {
        if line.outcome != LineOutcome::Failed {
            return false;
        }
        match line.kind {
            LineKind::ConsoleLine => true,
            LineKind::Directive => {
                let is_wiring = line
                    .text
                    .split_whitespace()
                    .next()
                    .is_some_and(|word| word.eq_ignore_ascii_case(":wiring"));
                let counted_as_expectation =
                    self.expectations.iter().any(|e| e.number == line.number);
                let counted_as_wiring = is_wiring && self.wiring.is_some();
                !(counted_as_expectation || counted_as_wiring)
            }
            LineKind::Comment => false,
        }
    }
}

/// The sheet's verdict, computed from the checks.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Verdict {
    pub passed: bool,
    /// Checks counted: every `:expect`/`:wait-until`, the wiring check,
    /// each failed console line or other directive (a `:params`, a
    /// `:tune-step` that tripped), and the run's end.
    pub checks: usize,
    pub failed: usize,
    /// One sentence a supervisor reads.
    pub headline: String,
    /// What failed, one item each.
    pub failures: Vec<String>,
}

impl ModuleSheet {
    /// What failed on this module, in the order of the run.
    pub fn failures(&self) -> Vec<String> {
        let checks = &self.checks;
        let mut failures = Vec::new();
        for line in &checks.lines {
            if checks.counts_failed(line) {
                failures.push(format!(
                    "line {} `{}`: {}",
                    line.number,
                    line.text,
                    line.answer.as_deref().unwrap_or("failed")
                ));
            }
        }
        for e in &checks.expectations {
            match e.outcome {
                CheckOutcome::Pass => {}
                CheckOutcome::Fail => failures.push(format!(
                    "line {} `{}` expected {}, got {}",
                    e.number,
                    e.line,
                    e.expected,
                    e.actual.as_deref().unwrap_or("nothing")
                )),
                CheckOutcome::NotRun => {
                    failures.push(format!("line {} `{}` was not run", e.number, e.line))
                }
            }
        }
        if let Some(wiring) = &checks.wiring
            && !wiring.wired_right
        {
            failures.push(if wiring.faults.is_empty() {
                "the wiring check found a fault".into()
            } else {
                format!(
                    "the wiring check found a fault: {}",
                    wiring.faults.join("; ")
                )
            });
        }
        if checks.run_end.ending != Ending::Completed {
            let said = match checks.run_end.ending {
                Ending::Cancelled => "the run was cancelled",
                _ => "the run did not complete",
            };
            failures.push(if checks.run_end.summary.is_empty() {
                said.to_string()
            } else {
                format!("{said} ({})", checks.run_end.summary)
            });
        }
        failures
    }

    /// How many checks this module counts (see [`Verdict::checks`]).
    pub fn check_count(&self) -> usize {
        let failed_lines = self
            .checks
            .lines
            .iter()
            .filter(|l| self.checks.counts_failed(l))
            .count();
        self.checks.expectations.len()
            + usize::from(self.checks.wiring.is_some())
            + failed_lines
            + 1
    }

    pub fn verdict(&self) -> Verdict {
        verdict(self.check_count(), self.failures())
    }
}

impl Sheet {
    /// The whole sheet's verdict: every module's checks together, each
    /// failure naming its module when there are several.
    pub fn verdict(&self) -> Verdict {
        let several = self.modules.len() > 1;
        let mut checks = 0;
        let mut failures = Vec::new();
        for module in &self.modules {
            checks += module.check_count();
            for failure in module.failures() {
                failures.push(if several {
                    format!(
                        "module {} on {}: {failure}",
                        module.identity.address, module.identity.link
                    )
                } else {
                    failure
                });
            }
        }
        if self.modules.is_empty() {
            failures.push("no module was run".into());
        }
        verdict(checks, failures)
    }
}

fn verdict(checks: usize, failures: Vec<String>) -> Verdict {
    let failed = failures.len().min(checks.max(failures.len()));
    let checks = checks.max(failed);
    let headline = if failures.is_empty() {
        match checks {
            1 => "The one check passed".to_string(),
            n => format!("All {n} checks passed"),
        }
    } else {
        format!(
            "{failed} of {checks} checks failed: {}",
            failures.join("; ")
        )
    };
    Verdict {
        passed: failures.is_empty(),
        checks,
        failed,
        headline,
        failures,
    }
}
