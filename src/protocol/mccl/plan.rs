//! How an MCCL text file reaches the controller and comes back, as plans
//! the session's generic runner drives ([`TransferPlan`]).
//!
//! - [`TextDownload`]: what WinControl's File–Open does (Ch4): each line
//!   (comments stripped, blank lines skipped) sent on its own and its
//!   answer waited for (a line that runs for long is held like a typed
//!   one), stopping at the first `?` error; then each macro the file
//!   defines read back with `TMn` and compared with what was sent. Only
//!   then is it verified.
//! - [`MacroVerify`]: the read-back alone.
//! - [`Upload`]: `TM-1`, every macro turned back into the `MDn,…` line
//!   that defines it.
//!
//! The controller is not put in any mode (unlike TMCL's download mode):
//! polling and user lines go on between two lines.

use super::console::MclConsole;
use super::line::{Line, NumberBase, parse_line};
use super::tool::{MclProgram, listed_macro, listed_macros, same_commands};
use crate::protocol::console::{PreparedLine, ReplyValue};
use crate::protocol::program::{
    Answer, Fact, FactValue, FailureKind, Phase, PlanLine, PlanStep, Progress, ReadProgram, Told,
    TransferFailure, TransferPlan, TransferReport,
};

const CONSOLE: MclConsole = MclConsole::DEFAULT;

/// A line of the file, prepared.
#[derive(Debug, Clone)]
struct Sending {
    /// 1-based source line.
    number: usize,
    prepared: PreparedLine,
}

/// A macro to read back: its number, the body sent, the index of its
/// line among those sent.
#[derive(Debug, Clone)]
struct Defined {
    number: i64,
    body: Line,
    unit: usize,
}

/// Prepare a console line a plan makes itself (`TMn`, `TM-1`).
fn prepared(text: &str) -> Result<PreparedLine, TransferFailure> {
    let line = parse_line(text, NumberBase::Decimal)
        .map_err(|e| TransferFailure::refused(format!("`{text}`: {e}")))?;
    Ok(CONSOLE.prepare_line(&line))
}

fn macros_of(program: &MclProgram) -> Vec<Defined> {
    program
        .macros()
        .into_iter()
        .filter_map(|(number, unit)| {
            let line = &program.lines.get(unit)?.line;
            Some(Defined {
                number,
                body: Line::new(line.commands[1..].to_vec()),
                unit,
            })
        })
        .collect()
}

/// Where a plan stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stage {
    /// Sending line n.
    Send(usize),
    /// Reading macro n (of the list) back.
    Verify(usize),
    Over,
}

/// Reads macros back and compares them (the second half of a download,
/// or a verify alone).
#[derive(Debug)]
struct ReadBack {
    macros: Vec<Defined>,
}

impl ReadBack {
    fn line(&self, index: usize) -> Option<PlanStep> {
        let defined = self.macros.get(index)?;
        prepared(&format!("TM{}", defined.number))
            .ok()
            .map(|line| PlanStep::Send(PlanLine::new(line)))
    }

    /// Whether the answer to `TMn` lists macro `index` as sent.
    fn check(&self, index: usize, answer: &Answer) -> Result<(), TransferFailure> {
        let Some(defined) = self.macros.get(index) else {
            return Ok(());
        };
        let n = defined.number;
        let listed = match &answer.result {
            Ok(reading) => match &reading.value {
                ReplyValue::Text(text) => text.clone(),
                other => other.to_string(),
            },
            Err(_) => {
                let why = answer.error_text().unwrap_or_default();
                return Err(TransferFailure::failed(
                    format!("macro {n} could not be read back: {why}"),
                    Some(defined.unit),
                ));
            }
        };
        let body = listed
            .lines()
            .filter_map(listed_macro)
            .find(|(number, _)| *number == n)
            .map(|(_, body)| body.to_string());
        let Some(body) = body else {
            return Err(TransferFailure::failed(
                format!("TM{n} does not list macro {n}: `{listed}`"),
                Some(defined.unit),
            ));
        };
        same_commands(&defined.body, &body).map_err(|why| {
            TransferFailure::failed(
                format!(
                    "macro {n} differs: sent `{}`, the controller lists `{body}` ({why})",
                    defined.body
                ),
                Some(defined.unit),
            )
        })
    }
}

/// The cancelled failure at `progress`.
fn cancelled(progress: Progress, what: &str) -> TransferFailure {
    TransferFailure {
        kind: FailureKind::Cancelled(progress),
        message: format!("cancelled after {} {what}", progress.done),
        said: None,
        at: None,
    }
}

/// WinControl's File–Open, then the macros read back.
#[derive(Debug)]
pub struct TextDownload {
    address: u8,
    lines: Vec<Sending>,
    read_back: ReadBack,
    stage: Stage,
    cancelled: bool,
    end: Option<Result<TransferReport, TransferFailure>>,
    progress: Progress,
}

impl TextDownload {
    pub fn new(address: u8, program: &MclProgram) -> Result<TextDownload, TransferFailure> {
        let lines = program
            .lines
            .iter()
            .map(|l| Sending {
                number: l.number,
                prepared: CONSOLE.prepare_line(&l.line),
            })
            .collect::<Vec<_>>();
        if lines.is_empty() {
            return Err(TransferFailure::refused(
                "the file has no line to send (only comments and blank lines)",
            ));
        }
        Ok(TextDownload {
            address,
            progress: Progress {
                phase: Phase::Storing,
                done: 0,
                total: Some(lines.len()),
            },
            lines,
            read_back: ReadBack {
                macros: macros_of(program),
            },
            stage: Stage::Send(0),
            cancelled: false,
            end: None,
        })
    }

    fn finish(&mut self, end: Result<TransferReport, TransferFailure>) {
        self.stage = Stage::Over;
        self.end = Some(end);
    }

    fn report(&self) -> TransferReport {
        let macros = self.read_back.macros.len() as u64;
        let mut report = TransferReport::new(self.address, self.lines.len());
        report.facts.push(Fact {
            key: "macros_verified",
            value: FactValue::Number(macros),
            said: (macros > 0).then(|| format!("; {macros} macro(s) verified by TM")),
            told: Some(Told {
                text: format!(
                    "{} line(s) sent, {macros} macro(s) read back with TM and verified",
                    self.lines.len()
                ),
                note: false,
            }),
        });
        report
    }

    fn verify_or_finish(&mut self) {
        if self.read_back.macros.is_empty() {
            let report = self.report();
            self.finish(Ok(report));
        } else {
            self.stage = Stage::Verify(0);
            self.progress = Progress {
                phase: Phase::Verifying,
                done: 0,
                total: Some(self.read_back.macros.len()),
            };
        }
    }
}

impl TransferPlan for TextDownload {
    fn next(&mut self) -> PlanStep {
        if let Some(end) = self.end.take() {
            return match end {
                Ok(report) => PlanStep::Done(report),
                Err(failure) => PlanStep::Failed(failure),
            };
        }
        if self.cancelled {
            let what = match self.stage {
                Stage::Send(_) => "line(s) sent",
                _ => "macro(s) verified",
            };
            self.stage = Stage::Over;
            return PlanStep::Failed(cancelled(self.progress, what));
        }
        match self.stage {
            Stage::Send(n) => match self.lines.get(n) {
                Some(line) => PlanStep::Send(PlanLine::new(line.prepared.clone())),
                None => PlanStep::Failed(TransferFailure::failed("no line to send", None)),
            },
            Stage::Verify(k) => self.read_back.line(k).unwrap_or_else(|| {
                PlanStep::Failed(TransferFailure::failed("no macro to read back", None))
            }),
            Stage::Over => PlanStep::Failed(TransferFailure::failed("the download is over", None)),
        }
    }

    fn answer(&mut self, answer: Answer) {
        match self.stage {
            Stage::Send(n) => {
                if let Some(why) = answer.error_text() {
                    // WinControl's download stops at the first `?` (the
                    // lines after may need this one).
                    let line = self.lines.get(n);
                    let failure = TransferFailure::failed(
                        format!(
                            "line {} `{}`: {why}; nothing after it was sent",
                            line.map_or(0, |l| l.number),
                            line.map_or("", |l| l.prepared.canonical.as_str())
                        ),
                        Some(n),
                    );
                    self.finish(Err(failure));
                    return;
                }
                self.progress.done = n + 1;
                if n + 1 < self.lines.len() {
                    self.stage = Stage::Send(n + 1);
                } else {
                    self.verify_or_finish();
                }
            }
            Stage::Verify(k) => {
                if let Err(failure) = self.read_back.check(k, &answer) {
                    self.finish(Err(failure));
                    return;
                }
                self.progress.done = k + 1;
                if k + 1 < self.read_back.macros.len() {
                    self.stage = Stage::Verify(k + 1);
                } else {
                    let report = self.report();
                    self.finish(Ok(report));
                }
            }
            Stage::Over => {}
        }
    }

    fn cancel(&mut self) {
        self.cancelled = true;
    }

    fn progress(&self) -> Option<Progress> {
        Some(self.progress)
    }
}

/// The macros of a file read back and compared, nothing sent but `TM`.
#[derive(Debug)]
pub struct MacroVerify {
    address: u8,
    read_back: ReadBack,
    next: usize,
    cancelled: bool,
    end: Option<Result<TransferReport, TransferFailure>>,
}

impl MacroVerify {
    pub fn new(address: u8, program: &MclProgram) -> Result<MacroVerify, TransferFailure> {
        let macros = macros_of(program);
        if macros.is_empty() {
            return Err(TransferFailure::refused(
                "the file defines no macro: there is nothing in the controller to compare (lines \
                 that are not MD ran when they were sent)",
            ));
        }
        Ok(MacroVerify {
            address,
            read_back: ReadBack { macros },
            next: 0,
            cancelled: false,
            end: None,
        })
    }

    fn progress_now(&self) -> Progress {
        Progress {
            phase: Phase::Verifying,
            done: self.next,
            total: Some(self.read_back.macros.len()),
        }
    }
}

impl TransferPlan for MacroVerify {
    fn next(&mut self) -> PlanStep {
        if let Some(end) = self.end.take() {
            return match end {
                Ok(report) => PlanStep::Done(report),
                Err(failure) => PlanStep::Failed(failure),
            };
        }
        if self.cancelled {
            return PlanStep::Failed(cancelled(self.progress_now(), "macro(s) compared"));
        }
        self.read_back.line(self.next).unwrap_or_else(|| {
            PlanStep::Failed(TransferFailure::failed("no macro to read back", None))
        })
    }

    fn answer(&mut self, answer: Answer) {
        if let Err(failure) = self.read_back.check(self.next, &answer) {
            self.end = Some(Err(failure));
            return;
        }
        self.next += 1;
        if self.next >= self.read_back.macros.len() {
            self.end = Some(Ok(TransferReport::new(self.address, self.next)));
        }
    }

    fn cancel(&mut self) {
        self.cancelled = true;
    }

    fn progress(&self) -> Option<Progress> {
        Some(self.progress_now())
    }
}

/// `TM-1`: every macro, as a file of the `MDn,…` lines that define them.
#[derive(Debug)]
pub struct Upload {
    address: u8,
    line: PreparedLine,
    asked: bool,
    cancelled: bool,
    end: Option<Result<TransferReport, TransferFailure>>,
}

impl Upload {
    pub fn new(address: u8) -> Result<Upload, TransferFailure> {
        Ok(Upload {
            address,
            line: prepared("TM-1")?,
            asked: false,
            cancelled: false,
            end: None,
        })
    }
}

/// The file that defines the macros of a `TM-1` listing again.
pub fn source_of_listing(listing: &ReplyValue) -> (String, usize) {
    let macros = listed_macros(listing);
    let mut source = String::from("; the controller's macros, read with TM-1\n");
    for stored in &macros {
        source.push_str(&format!("MD{},{}\n", stored.number, stored.text));
    }
    (source, macros.len())
}

impl TransferPlan for Upload {
    fn next(&mut self) -> PlanStep {
        if let Some(end) = self.end.take() {
            return match end {
                Ok(report) => PlanStep::Done(report),
                Err(failure) => PlanStep::Failed(failure),
            };
        }
        if self.cancelled || self.asked {
            return PlanStep::Failed(cancelled(
                Progress {
                    phase: Phase::Reading,
                    done: 0,
                    total: None,
                },
                "macros read",
            ));
        }
        self.asked = true;
        PlanStep::Send(PlanLine::new(self.line.clone()))
    }

    fn answer(&mut self, answer: Answer) {
        let end = match &answer.result {
            Ok(reading) => {
                let (source, units) = source_of_listing(&reading.value);
                let mut report = TransferReport::new(self.address, units);
                report.program = Some(ReadProgram {
                    source,
                    image: None,
                    units,
                });
                Ok(report)
            }
            Err(_) => Err(TransferFailure::failed(
                format!(
                    "TM-1 brought no listing: {}",
                    answer.error_text().unwrap_or_default()
                ),
                None,
            )),
        };
        self.end = Some(end);
    }

    fn cancel(&mut self) {
        self.cancelled = true;
    }

    fn progress(&self) -> Option<Progress> {
        Some(Progress {
            phase: Phase::Reading,
            done: 0,
            total: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::console::Reading;
    use crate::protocol::mccl::tool::MclTool;
    use crate::protocol::program::{AnswerError, CheckedProgram, NoIncludes, ProgramTool};

    fn program(source: &str) -> std::sync::Arc<dyn CheckedProgram> {
        MclTool
            .check("t.mccl", source, &NoIncludes)
            .program
            .expect("checks")
    }

    fn ok(line: &str, value: ReplyValue) -> Answer {
        Answer {
            line: line.into(),
            frames: Vec::new(),
            result: Ok(Reading {
                status: None,
                value,
            }),
        }
    }

    fn sent(step: PlanStep) -> String {
        match step {
            PlanStep::Send(line) => line.line.canonical,
            other => panic!("not a line: {other:?}"),
        }
    }

    const FILE: &str = "; a cycle\n2MN ;motor on\nMD10,2MR500,WS.1,MR-500,WS.1\n\nMD11,AL5,AR100\n";

    #[test]
    fn lines_go_one_by_one_then_the_macros_are_read_back() {
        let mut plan = program(FILE).download(0, Default::default()).expect("plan");
        let mut lines = Vec::new();
        for _ in 0..3 {
            lines.push(sent(plan.next()));
            plan.answer(ok("", ReplyValue::None));
        }
        assert_eq!(
            lines,
            ["2MN", "MD10,2MR500,WS.1,MR-500,WS.1", "MD11,AL5,AR100"]
        );
        assert_eq!(plan.progress().map(|p| p.phase), Some(Phase::Verifying));
        assert_eq!(sent(plan.next()), "TM10");
        plan.answer(ok(
            "TM10",
            ReplyValue::Text("MC10 2MR500,2WS0.100000,2MR-500,2WS0.100000".into()),
        ));
        assert_eq!(sent(plan.next()), "TM11");
        plan.answer(ok("TM11", ReplyValue::Text("MC11,AL5,AR100".into())));
        let PlanStep::Done(report) = plan.next() else {
            panic!("verified")
        };
        assert_eq!(report.count, 3);
        assert_eq!(report.fact("macros_verified"), Some(&FactValue::Number(2)));
    }

    #[test]
    fn a_listing_that_differs_fails_the_download_at_its_line() {
        let mut plan = program(FILE).download(0, Default::default()).expect("plan");
        for _ in 0..3 {
            plan.next();
            plan.answer(ok("", ReplyValue::None));
        }
        plan.next();
        plan.answer(ok(
            "TM10",
            ReplyValue::Text("MC10,2MR500,WS0.2,MR-500,WS.1".into()),
        ));
        let PlanStep::Failed(failure) = plan.next() else {
            panic!("not verified")
        };
        assert!(
            failure.message.contains("macro 10 differs"),
            "{}",
            failure.message
        );
        assert_eq!(failure.address(), Some(1), "the MD10 line");
    }

    #[test]
    fn an_error_stops_the_download_at_its_line() {
        let mut plan = program(FILE).download(0, Default::default()).expect("plan");
        plan.next();
        plan.answer(ok("", ReplyValue::None));
        plan.next();
        plan.answer(Answer {
            line: "MD10,…".into(),
            frames: Vec::new(),
            result: Err(AnswerError::Refused("?-18".into())),
        });
        let PlanStep::Failed(failure) = plan.next() else {
            panic!("stopped")
        };
        assert!(
            failure.message.starts_with("line 3 `MD10"),
            "{}",
            failure.message
        );
        assert!(failure.message.contains("nothing after it was sent"));
        assert_eq!(failure.address(), Some(1));
    }

    #[test]
    fn cancelling_stops_between_two_lines() {
        let mut plan = program(FILE).download(0, Default::default()).expect("plan");
        plan.next();
        plan.answer(ok("", ReplyValue::None));
        plan.cancel();
        let PlanStep::Failed(failure) = plan.next() else {
            panic!("cancelled")
        };
        assert_eq!(failure.cancelled().map(|p| p.done), Some(1));
    }

    #[test]
    fn upload_turns_the_listing_into_md_lines() {
        let mut plan = MclTool.upload(0, Default::default()).expect("plan");
        assert_eq!(sent(plan.next()), "TM-1");
        plan.answer(ok(
            "TM-1",
            ReplyValue::Text("MC1,1LM2,1LN3,MJ10\nMC10,2MR500,WS0.1".into()),
        ));
        let PlanStep::Done(report) = plan.next() else {
            panic!("read")
        };
        let program = report.program.expect("a program");
        assert_eq!(
            program.source,
            "; the controller's macros, read with TM-1\nMD1,1LM2,1LN3,MJ10\nMD10,2MR500,WS0.1\n"
        );
        assert_eq!(program.units, 2);
        // What it gives back checks, and defines the same macros.
        assert!(
            MclTool
                .check("up.mccl", &program.source, &NoIncludes)
                .program
                .is_some()
        );
    }

    #[test]
    fn verify_needs_macros() {
        assert!(program("1MN\n").verify(0).is_err());
        let mut plan = program(FILE).verify(0).expect("plan");
        assert_eq!(sent(plan.next()), "TM10");
    }
}
