//! `:record-macro FILE | off`: the lines sent from the command pane kept
//! as a program of the connected family's language; `:record FILE | off`:
//! the whole session kept as an `axterm run` file.

use std::time::Duration;

use tokio::time::Instant;

use super::*;
use crate::files::Existing;
use crate::report::LineOutcome as SheetLine;
use crate::report::{
    CheckOutcome, Checks, EmergencyStop, Ending, Expectation, Identity, LineKind, ModuleSheet,
    RunEnd, RunLine, Settings, Sheet, Tuning, Wiring,
};
use crate::run_recording::{LineOutcome, RecordingHeader, RunRecorder};
use crate::ui::pane::SheetFact;
use crate::wall_clock::CivilTime;

/// A recording of the lines sent (SQPack's "Record Macro", §5.4.6).
#[derive(Debug)]
pub(super) struct Recording {
    pub(super) path: PathBuf,
    /// The language's lines so far, written to the file after each.
    pub(super) lines: Vec<String>,
    pub(super) tool: &'static dyn ProgramTool,
}

impl CommandPane {
    /// `:record-macro FILE | off`: record every line sent from here (typed
    /// or from a batch, once sent) as the connected family's program tool
    /// writes it, into FILE, rewritten after each line so that nothing
    /// recorded is lost; `off` ends it. An existing file is not
    /// overwritten unless `--force` comes before its name.
    pub(super) fn record_command(&mut self, rest: &str, view: &View) -> Outcome {
        if rest.eq_ignore_ascii_case("off") {
            return match self.recording.take() {
                Some(recording) => {
                    self.say(
                        Role::Ok,
                        format!(
                            "recording ended: {} line(s) in {}",
                            recording.lines.len(),
                            recording.path.display()
                        ),
                    );
                    Outcome::redraw()
                }
                None => self.fail("nothing is being recorded"),
            };
        }
        let (existing, rest) = crate::files::force_option(rest);
        if rest.is_empty() {
            return self.fail(":record-macro needs a file name (or off)");
        }
        let Some(session) = view.session else {
            return self.fail(not_connected());
        };
        // The tool records if it can say the family's own identity query.
        let probe = session.family.console.identify(session.address).bytes;
        let Some(tool) = session
            .family
            .console
            .program()
            .filter(|t| t.record(&probe).is_some())
        else {
            return self.fail(format!(
                "the {} family's program language cannot record the lines sent",
                session.family.name
            ));
        };
        let path = PathBuf::from(rest);
        if let Err(e) = crate::files::start_growing(&path, b"", existing) {
            return self.fail(format!("cannot write {}: {e}", path.display()));
        }
        if let Some(before) = self.recording.take() {
            self.say(
                Role::Muted,
                format!(
                    "recording to {} ended: {} line(s)",
                    before.path.display(),
                    before.lines.len()
                ),
            );
        }
        self.say(
            Role::Accent,
            format!(
                "recording every line sent from here to {} as {} ({} off ends it)",
                path.display(),
                tool.name(),
                ":record-macro"
            ),
        );
        self.recording = Some(Recording {
            path,
            lines: Vec::new(),
            tool,
        });
        Outcome::redraw()
    }

    /// Add a line that was sent to the recording, if one goes.
    pub(super) fn record_sent(&mut self, request: &[u8]) {
        let Some(recording) = self.recording.as_mut() else {
            return;
        };
        let Some(line) = recording.tool.record(request) else {
            return;
        };
        recording.lines.push(line);
        let mut text = recording.lines.join("\n");
        text.push('\n');
        if let Err(e) = crate::files::write_atomically(&recording.path, text.as_bytes()) {
            let path = recording.path.display().to_string();
            self.recording = None;
            self.say(
                Role::Error,
                format!("recording stopped: cannot write {path}: {e}"),
            );
        }
    }
}

/// `:record FILE`: the session written down as an `axterm run` file
/// ([`crate::run_recording`]), appended to the file piece by piece.
#[derive(Debug)]
pub(super) struct SessionRecording {
    pub(super) path: PathBuf,
    recorder: RunRecorder,
    /// When it began, on the console's clock (virtual in tests).
    began: Instant,
    /// The module recorded: its link (index in the console's list of
    /// links) and address. A run file replays on one module, so a line
    /// sent to another is no part of it.
    module: (usize, u8),
    /// The facts of the recording for `:report`'s sheet.
    facts: SheetFacts,
}

/// A sheet asked for with `:report`, written when the settings read that
/// it started ends (the facts as they were when it was asked for).
#[derive(Debug)]
pub(super) struct PendingReport {
    pub(super) tag: u64,
    path: PathBuf,
    existing: Existing,
    sheet: Sheet,
}

/// What a session recording saw, as the commissioning sheet shows it
/// (`:report FILE`): each line sent with its answer, numbered in the
/// order sent; each read the recording wrote as `:expect` as a check that
/// passed with the value it read; the emergency stops; the wiring checks
/// and tuning runs of the other panes ([`SheetFact`]).
#[derive(Debug)]
struct SheetFacts {
    header: RecordingHeader,
    started: std::time::SystemTime,
    lines: Vec<RunLine>,
    expectations: Vec<Expectation>,
    emergency_stop: Option<EmergencyStop>,
    wiring: Option<Wiring>,
    tuning: Option<Tuning>,
}

impl SheetFacts {
    fn new(header: RecordingHeader) -> SheetFacts {
        SheetFacts {
            header,
            started: std::time::SystemTime::now(),
            lines: Vec::new(),
            expectations: Vec::new(),
            emergency_stop: None,
            wiring: None,
            tuning: None,
        }
    }

    /// A line of a tool (a directive, as `axterm run` would have it):
    /// its answer, and whether it went well.
    fn tool_line(&mut self, text: &str, kind: LineKind, answer: String, outcome: SheetLine) {
        self.lines.push(RunLine {
            number: self.lines.len() + 1,
            text: text.to_string(),
            kind,
            answer: Some(answer),
            outcome,
        });
    }

    /// What a pane's tool did: as `axterm run` records its `:wiring`,
    /// `:tune-step` or `:tune-stallguard` line. What the recording file
    /// says of it (a comment: the tool's moves were not sent from the
    /// command pane, so a replay does not make them).
    fn fact(&mut self, fact: &SheetFact) -> String {
        match fact {
            SheetFact::Wiring {
                line,
                findings,
                faults,
            } => {
                let right = faults.is_empty();
                let said = if right {
                    "wired right".to_string()
                } else {
                    format!("{} fault(s): see the wiring check", faults.len())
                };
                // Several checks together: wired right only if each was.
                let wiring = self.wiring.get_or_insert_with(|| Wiring {
                    findings: Vec::new(),
                    wired_right: true,
                    faults: Vec::new(),
                });
                wiring.findings.extend(findings.iter().cloned());
                wiring.faults.extend(faults.iter().cloned());
                wiring.wired_right &= right;
                self.tool_line(
                    line,
                    LineKind::Directive,
                    said.clone(),
                    SheetLine::of(right),
                );
                format!("# {line}: {said}\n")
            }
            SheetFact::Tuning {
                line,
                said,
                ok,
                figures,
                plots,
            } => {
                let tuning = self.tuning.get_or_insert_with(Tuning::default);
                tuning.figures.extend(figures.iter().cloned());
                tuning.plots.extend(plots.iter().cloned());
                self.tool_line(line, LineKind::Directive, said.clone(), SheetLine::of(*ok));
                format!("# {line}: {said}\n")
            }
            SheetFact::Unfinished { line, why, failed } => {
                if *failed {
                    self.tool_line(line, LineKind::Directive, why.clone(), SheetLine::Failed);
                } else {
                    // Stopped by the user: shown, but neither a pass nor
                    // a failure.
                    self.tool_line(
                        &format!("# stopped: {line}"),
                        LineKind::Comment,
                        why.clone(),
                        SheetLine::Nothing,
                    );
                }
                format!("# {line}: {why}\n")
            }
        }
    }

    /// Line `line` came out so (`recorded`: what the recording wrote of it).
    fn answered(&mut self, line: &str, outcome: LineOutcome, recorded: &str) {
        let number = self.lines.len() + 1;
        let (kind, text, answer, done) = match outcome {
            LineOutcome::Answered(value) => (
                LineKind::ConsoleLine,
                line.to_string(),
                value,
                crate::report::LineOutcome::Ok,
            ),
            LineOutcome::Failed(error) => (
                LineKind::ConsoleLine,
                line.to_string(),
                error,
                crate::report::LineOutcome::Failed,
            ),
            // Refused before anything was sent: the recording keeps it as
            // a comment, and so does the sheet.
            LineOutcome::NotSent(error) => (
                LineKind::Comment,
                format!("# not sent: {line}"),
                error,
                crate::report::LineOutcome::Nothing,
            ),
        };
        if let LineOutcome::Answered(value) = outcome
            && recorded.lines().any(|l| l.starts_with(":expect "))
        {
            self.expectations.push(Expectation {
                number,
                directive: "expect".into(),
                line: line.to_string(),
                expected: value.to_string(),
                actual: Some(value.to_string()),
                outcome: CheckOutcome::Pass,
            });
        }
        self.lines.push(RunLine {
            number,
            text,
            kind,
            answer: Some(answer.to_string()),
            outcome: done,
        });
    }

    /// The sheet of the session so far, by `operator`.
    fn sheet(&self, run_file: &str, operator: String, firmware: Option<&str>) -> Sheet {
        let header = &self.header;
        let identity = Identity {
            family: header.family.clone(),
            link: header.link.clone(),
            address: header.address,
            firmware: firmware
                .or(header.firmware.as_deref())
                .map_or_else(|| "(not read)".to_string(), str::to_string),
        };
        let checks = Checks {
            lines: self.lines.clone(),
            expectations: self.expectations.clone(),
            wiring: self.wiring.clone(),
            emergency_stop: self.emergency_stop.clone(),
            run_end: RunEnd {
                ending: Ending::Completed,
                summary: "the console session so far (:report)".into(),
                stopped_axes: Vec::new(),
            },
        };
        Sheet {
            run_file: run_file.to_string(),
            operator,
            axterm_version: env!("CARGO_PKG_VERSION").to_string(),
            started_utc: CivilTime::of(self.started).stamp(),
            ended_utc: CivilTime::of(std::time::SystemTime::now()).stamp(),
            modules: vec![ModuleSheet {
                identity,
                settings: Settings::default(),
                checks,
                tuning: self.tuning.clone(),
            }],
        }
    }
}

/// The selected module as (link, address), the key a recording keeps.
fn selected_module(view: &View) -> Option<(usize, u8)> {
    let session = view.session?;
    let link = view.modules.get(view.module).map_or(0, |entry| entry.link);
    Some((link, session.address))
}

impl SessionRecording {
    fn now(&self) -> Duration {
        Instant::now().saturating_duration_since(self.began)
    }
}

impl CommandPane {
    /// `:record [FILE | off]`: write every line sent from here (typed, or
    /// of a `:run` batch) with its answer to FILE as an `axterm run` file:
    /// reads as `:expect`, the waits the technician made for a move as
    /// `:wait-until` on the status poll that showed the axis at rest,
    /// failed lines as comments. Each piece is appended and synced as it
    /// comes, so a crash loses nothing recorded. Alone: what is recorded.
    pub(super) fn session_record_command(&mut self, rest: &str, view: &View) -> Outcome {
        if rest.is_empty() {
            let said = match &self.session_recording {
                Some(r) => {
                    let (lines, waits) = r.recorder.counts();
                    format!(
                        "recording the session to {}: {lines} line(s), {waits} wait(s) so far (:record off ends it)",
                        r.path.display()
                    )
                }
                None => "nothing is being recorded (:record FILE starts)".to_string(),
            };
            self.say(Role::Accent, said);
            return Outcome::redraw();
        }
        if rest.eq_ignore_ascii_case("off") {
            if let Some(r) = self.session_recording.as_mut() {
                let text = r.recorder.finish();
                self.session_record_write(&text);
            }
            return match self.session_recording.take() {
                Some(r) => {
                    let (lines, waits) = r.recorder.counts();
                    self.say(
                        Role::Ok,
                        format!(
                            "session recording ended: {lines} line(s), {waits} wait(s) in {} (replay: axterm run CONNECTION {})",
                            r.path.display(),
                            r.path.display()
                        ),
                    );
                    Outcome::redraw()
                }
                None => self.fail("nothing is being recorded"),
            };
        }
        let Some(session) = view.session else {
            return self.fail(not_connected());
        };
        let (existing, rest) = crate::files::force_option(rest);
        if rest.is_empty() {
            return self.fail(":record needs a file name (or off)");
        }
        let path = PathBuf::from(rest);
        let header = RecordingHeader {
            family: session.family.name.to_string(),
            family_description: session.family.description.to_string(),
            link: session.link_name.clone(),
            address: session.address,
            firmware: session.identity.clone(),
            started: CivilTime::of(std::time::SystemTime::now()).date_time(),
        };
        if let Err(e) = crate::files::start_growing(&path, header.text().as_bytes(), existing) {
            return self.fail(format!("cannot write {}: {e}", path.display()));
        }
        if let Some(before) = self.session_recording.take() {
            self.say(
                Role::Muted,
                format!("session recording to {} ended", before.path.display()),
            );
        }
        self.say(
            Role::Accent,
            format!(
                "recording the session to {} as an axterm run file (:record off ends it)",
                path.display()
            ),
        );
        let mut recording = SessionRecording {
            path,
            recorder: RunRecorder::new(),
            began: Instant::now(),
            module: selected_module(view).unwrap_or((0, session.address)),
            facts: SheetFacts::new(header),
        };
        recording.recorder.observe(&session.status, Duration::ZERO);
        self.session_recording = Some(recording);
        Outcome::redraw()
    }

    /// A status snapshot came: the recording watches the axes, or ends
    /// when another module was selected.
    pub(super) fn session_record_status(&mut self, view: &View) {
        if !self.session_record_still_on(view) {
            return;
        }
        if let (Some(r), Some(session)) = (self.session_recording.as_mut(), view.session) {
            let now = r.now();
            r.recorder.observe(&session.status, now);
        }
    }

    /// Whether the recording (if any) goes on: it ends, saying why, once
    /// the selected module is not the one recorded, as the lines typed
    /// from then on go elsewhere.
    fn session_record_still_on(&mut self, view: &View) -> bool {
        let Some(r) = self.session_recording.as_ref() else {
            return false;
        };
        if selected_module(view) == Some(r.module) {
            return true;
        }
        let text = "# recording ended here: another module was selected\n".to_string();
        self.session_record_write(&text);
        if let Some(r) = self.session_recording.take() {
            let (lines, waits) = r.recorder.counts();
            self.say(
                Role::Warning,
                format!(
                    "session recording ended: another module was selected, and a recording replays on one module ({lines} line(s), {waits} wait(s) in {})",
                    r.path.display()
                ),
            );
        }
        false
    }

    /// A line is about to be sent: the waits made before it.
    pub(super) fn session_record_before_line(&mut self, tag: u64) {
        let Some(r) = self.session_recording.as_mut() else {
            return;
        };
        let now = r.now();
        let text = r.recorder.before_line(tag, now);
        self.session_record_write(&text);
    }

    /// The answer to a line sent from here (`line` as sent).
    pub(super) fn session_record_answer(
        &mut self,
        tag: u64,
        line: &str,
        result: &Result<LineResult, SessionError>,
        view: &View,
    ) {
        if !self.session_record_still_on(view) {
            return;
        }
        let Some(r) = self.session_recording.as_mut() else {
            return;
        };
        let effect = view.session.and_then(|s| {
            s.family
                .console
                .prepare(line, s.address)
                .ok()
                .map(|p| p.effect)
        });
        let (value, error);
        let outcome = match result {
            Ok(answer) => {
                value = answer.value.to_string();
                LineOutcome::Answered(&value)
            }
            Err(e) => {
                error = e.to_string();
                if e.nothing_sent() {
                    LineOutcome::NotSent(&error)
                } else {
                    LineOutcome::Failed(&error)
                }
            }
        };
        let now = r.now();
        let text = r.recorder.answered(tag, line, effect, outcome, now);
        r.facts.answered(line, outcome, &text);
        self.session_record_write(&text);
    }

    /// `:report [--force] FILE`: the commissioning sheet of the session
    /// recording so far (`:record`): its identity, each line sent with its
    /// answer, each read it recorded as `:expect` as a check, the
    /// emergency stops, the wiring checks and tuning runs of the other
    /// panes. The module's settings against the factory defaults are read
    /// now, without holding up the console ("reading the settings…"); the
    /// sheet is written when the read ends, with the facts as they were
    /// when it was asked for. HTML, or JSON for a FILE ending `.json`.
    pub(super) fn report_command(&mut self, rest: &str, view: &View) -> Outcome {
        let (existing, rest) = crate::files::force_option(rest);
        if rest.is_empty() {
            return self.fail(":report needs a file name (FILE.json writes the JSON)");
        }
        if !self.session_record_still_on(view) {
            return self.fail(
                ":report writes the sheet of the session recording: start one with :record FILE",
            );
        }
        let Some(r) = self.session_recording.as_ref() else {
            return self.fail(":report writes the sheet of the session recording");
        };
        if let Some(pending) = &self.report_pending {
            let path = pending.path.display().to_string();
            return self.fail(format!(
                "the sheet for {path} is still reading the settings: :report again when it is written"
            ));
        }
        let path = PathBuf::from(rest);
        // Refused now, before the module is asked anything.
        if let Err(e) = crate::files::check_destination(&path, existing) {
            return self.fail(format!("cannot write {}: {e}", path.display()));
        }
        let operator = std::env::var("USER")
            .ok()
            .filter(|u| !u.is_empty())
            .or_else(|| std::env::var("LOGNAME").ok().filter(|u| !u.is_empty()))
            .unwrap_or_else(|| "(not given)".into());
        let firmware = view.session.and_then(|s| s.identity.as_deref());
        let sheet = r
            .facts
            .sheet(&r.path.display().to_string(), operator, firmware);
        // The lines that succeeded, as the family writes them: whether one
        // stored the settings.
        let sent: Vec<String> = view.session.map_or_else(Vec::new, |session| {
            r.facts
                .lines
                .iter()
                .filter(|l| l.kind == LineKind::ConsoleLine && l.outcome == SheetLine::Ok)
                .filter_map(|l| {
                    let prepared = session.family.console.prepare(&l.text, session.address);
                    prepared.ok().map(|p| p.canonical)
                })
                .collect()
        });
        self.next_tag += 1;
        let tag = self.next_tag;
        self.say(
            Role::Accent,
            format!("reading the settings for the sheet in {}…", path.display()),
        );
        self.report_pending = Some(PendingReport {
            tag,
            path,
            existing,
            sheet,
        });
        Outcome::request(Request::ReadSettings { sent, tag })
    }

    /// The settings read for a `:report` ended: the sheet is written,
    /// with them, or saying why they were not read.
    pub(super) fn report_settings_read(
        &mut self,
        tag: u64,
        result: &Result<Settings, String>,
    ) -> Outcome {
        let Some(pending) = self.report_pending.take_if(|p| p.tag == tag) else {
            return Outcome::Ignored;
        };
        let PendingReport {
            path,
            existing,
            mut sheet,
            ..
        } = pending;
        let when = CivilTime::of(std::time::SystemTime::now()).stamp();
        let settings = match result {
            Ok(settings) => Settings {
                read: Some(format!(
                    "from the module when the sheet was asked for (:report), at {when}"
                )),
                ..settings.clone()
            },
            Err(why) => {
                self.say(
                    Role::Warning,
                    format!("the settings were not read ({why}): the sheet says so"),
                );
                Settings {
                    read: Some(format!("not read ({why})")),
                    ..Settings::default()
                }
            }
        };
        if let Some(module) = sheet.modules.first_mut() {
            module.settings = settings;
        }
        let is_json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        let bytes = if is_json {
            match serde_json::to_string_pretty(&crate::report::sheet_json(&sheet)) {
                Ok(mut text) => {
                    text.push('\n');
                    text.into_bytes()
                }
                Err(e) => return self.fail(format!("cannot write {}: {e}", path.display())),
            }
        } else {
            crate::report::sheet_html(&sheet).into_bytes()
        };
        if let Err(e) = crate::files::save(&path, &bytes, existing) {
            return self.fail(format!("cannot write {}: {e}", path.display()));
        }
        let verdict = sheet.verdict();
        self.say(
            if verdict.passed {
                Role::Ok
            } else {
                Role::Warning
            },
            format!(
                "the sheet of the session so far is in {}: {}",
                path.display(),
                verdict.headline
            ),
        );
        Outcome::redraw()
    }

    /// A pane's tool did something the sheet shows: into the recording's
    /// facts (and a comment into its file), when it was done on the
    /// module recorded.
    pub(super) fn session_record_fact(&mut self, fact: &SheetFact, view: &View) -> Outcome {
        if !self.session_record_still_on(view) {
            return Outcome::Ignored;
        }
        let Some(r) = self.session_recording.as_mut() else {
            return Outcome::Ignored;
        };
        let text = r.facts.fact(fact);
        self.session_record_write(&text);
        Outcome::Ignored
    }

    /// The emergency stop: lines waiting were dropped; the stop lines
    /// come with [`CommandPane::session_record_stop_lines`].
    pub(super) fn session_record_stopping(&mut self) {
        let Some(r) = self.session_recording.as_mut() else {
            return;
        };
        let text = r.recorder.forget_unanswered();
        self.session_record_write(&text);
    }

    /// What the emergency stop sent: recorded as the stop lines they are,
    /// so that a replay stops the axes where the technician did.
    pub(super) fn session_record_stop_lines(
        &mut self,
        results: &[Result<LineResult, SessionError>],
    ) {
        let Some(r) = self.session_recording.as_mut() else {
            return;
        };
        let values: Vec<(String, String, bool)> = results
            .iter()
            .map(|result| match result {
                Ok(answer) => (answer.line.clone(), answer.value.to_string(), true),
                Err(e) => (e.line().to_string(), e.to_string(), false),
            })
            .collect();
        let lines: Vec<(&str, LineOutcome)> = values
            .iter()
            .zip(results)
            .map(|((line, value, ok), result)| {
                let outcome = match result {
                    _ if *ok => LineOutcome::Answered(value),
                    Err(e) if e.nothing_sent() => LineOutcome::NotSent(value),
                    _ => LineOutcome::Failed(value),
                };
                (line.as_str(), outcome)
            })
            .collect();
        let now = r.now();
        let text = r.recorder.emergency_stop(&lines, now);
        let stop = r.facts.emergency_stop.get_or_insert_with(|| EmergencyStop {
            reason: "the emergency stop was pressed".into(),
            lines: Vec::new(),
        });
        stop.lines.extend(values.iter().map(|(line, value, ok)| {
            format!("{line}: {value}{}", if *ok { "" } else { " (FAILED)" })
        }));
        self.session_record_write(&text);
    }

    fn session_record_write(&mut self, text: &str) {
        let Some(r) = self.session_recording.as_ref() else {
            return;
        };
        if text.is_empty() {
            return;
        }
        if let Err(e) = crate::files::append_synced(&r.path, text.as_bytes()) {
            let path = r.path.display().to_string();
            self.session_recording = None;
            self.say(
                Role::Error,
                format!("session recording stopped: cannot write {path}: {e}"),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn facts() -> SheetFacts {
        SheetFacts::new(RecordingHeader {
            family: "tmcl".into(),
            family_description: String::new(),
            link: "sim tmcm1110".into(),
            address: 1,
            firmware: Some("1110V112".into()),
            started: String::new(),
        })
    }

    #[test]
    fn a_read_recorded_as_expect_is_a_check_and_a_failed_line_fails_the_sheet() {
        let mut facts = facts();
        facts.answered(
            "GAP 4, 0",
            LineOutcome::Answered("1000"),
            ":expect GAP 4, 0 == 1000\n",
        );
        // A read while an axis moved is recorded as a plain line: no check.
        facts.answered("GAP 1, 0", LineOutcome::Answered("17"), "GAP 1, 0  # 17\n");
        let sheet = facts.sheet("s.txt", "Ada".into(), None);
        assert_eq!(sheet.verdict().headline, "All 2 checks passed");
        assert_eq!(sheet.modules[0].identity.firmware, "1110V112");
        facts.answered(
            "SAP 6, 0, 200",
            LineOutcome::Failed("invalid value (status 4)"),
            "# failed: SAP 6, 0, 200\n",
        );
        let verdict = facts.sheet("s.txt", "Ada".into(), None).verdict();
        assert_eq!(
            verdict.failures,
            ["line 3 `SAP 6, 0, 200`: invalid value (status 4)"]
        );
    }

    #[test]
    fn a_panes_wiring_check_and_tuning_run_are_checks_as_in_a_run() {
        let mut facts = facts();
        let line = ":wiring --axis 0 --speed 2047 (the bring-up pane's check of motor 0)";
        let said = facts.fact(&SheetFact::Wiring {
            line: line.into(),
            findings: vec!["motor 0, moving +: …".into(), "motor 0: home".into()],
            faults: Vec::new(),
        });
        assert_eq!(said, format!("# {line}: wired right\n"));
        // Stopped by the user: on the sheet, not a check.
        facts.fact(&SheetFact::Unfinished {
            line: ":tune-stallguard --axis 0 (…)".into(),
            why: "stopped before its end (stopped by key)".into(),
            failed: false,
        });
        facts.fact(&SheetFact::Tuning {
            line: ":tune-stallguard --axis 0 --from 200 (…)".into(),
            said: "5 speeds swept".into(),
            ok: true,
            figures: vec!["speed 200: 400".into()],
            plots: Vec::new(),
        });
        let sheet = facts.sheet("s.txt", "Ada".into(), None);
        // The wiring check and the session's end.
        assert_eq!(sheet.verdict().headline, "All 2 checks passed");
        let module = &sheet.modules[0];
        assert!(module.checks.wiring.as_ref().is_some_and(|w| w.wired_right));
        assert_eq!(module.tuning.as_ref().map(|t| t.figures.len()), Some(1));
        assert_eq!(module.checks.lines[1].kind, LineKind::Comment);
        // A second check that found a fault makes the wiring check fail,
        // naming it; a step that tripped fails as its own check.
        facts.fact(&SheetFact::Wiring {
            line: line.into(),
            findings: vec!["motor 0, moving + tripped the − (left) switch".into()],
            faults: vec!["motor 0, moving + tripped the − (left) switch".into()],
        });
        facts.fact(&SheetFact::Tuning {
            line: ":tune-step --axis 1 (…)".into(),
            said: "tripped (following error): the axis was stopped".into(),
            ok: false,
            figures: Vec::new(),
            plots: Vec::new(),
        });
        let verdict = facts.sheet("s.txt", "Ada".into(), None).verdict();
        assert_eq!(verdict.checks, 3, "{verdict:?}");
        assert_eq!(
            verdict.failures,
            [
                "line 5 `:tune-step --axis 1 (…)`: tripped (following error): the axis was stopped",
                "the wiring check found a fault: motor 0, moving + tripped the − (left) switch"
            ]
        );
    }
}
