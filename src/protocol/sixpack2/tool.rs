//! SQPack macro files as the family's [`ProgramTool`] (digest D8): the
//! check of [`super::macros`] with its located errors, colours, each
//! frame shown decoded beside its line, recording (the console's lines
//! as `SendToPack` calls) and playback from the host ([`MacroRun`]).
//!
//! The SIXpack 2 stores no program: a macro is only ever played from the
//! host. How SQPack paces a playback is not documented [?]. Nothing but
//! the queries answers (§7), so a frame that is not answered is followed,
//! before the next, by its wire time at the slowest rate the jumpers give
//! (9600 Bd, §5.2.3) and the 2 ms the digest suggests between frames
//! (D1.3): the host cannot see when its bytes have left the port. A
//! query's answer is waited for and shown (its switch-over delay is in
//! it); a `$28` with a wait mask waits for its motors (§7.2); after `$CC`
//! the unit is deaf for about a second (§7.4).

use std::ops::Range;
use std::sync::Arc;
use std::time::Duration;

use super::frame::Request;
use super::macros::{self, EXTENSIONS, MacroCheck, MacroFrame, MacroLine};
use crate::protocol::program::{
    Answer, Checked, CheckedProgram, DownloadOptions, HostEnd, HostNews, HostRun, HostStart,
    HostStep, PlaceState, Problem, ProgramTool, RunningPlace, SourceLoader, SyntaxClass, Tone,
    TransferFailure, TransferPlan,
};

/// The wait after a frame the unit does not answer: 9 bytes at 9600 Bd
/// (10 bits each, 9.4 ms) and 2 ms between frames (digest D1.3), rounded
/// up.
pub const FRAME_PACE: Duration = Duration::from_millis(12);

/// The wait after `$CC`: the reset takes "about 1 second" (§7.4).
pub const RESET_PACE: Duration = Duration::from_millis(1200);

/// Why a macro is never downloaded.
pub const NO_STORE: &str = "the SIXpack 2 stores no program (§7 has no such command): a macro \
                            is played from the host";

/// SQPack macro files (the family's
/// [`crate::protocol::console::FamilyConsole::program`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct MacroTool;

fn problem_of(p: &macros::MacroProblem) -> Problem {
    Problem {
        line: p.line,
        column: p.column,
        text: p.to_string(),
        message: if p.error {
            p.message.clone()
        } else {
            format!("warning: {}", p.message)
        },
        error: p.error,
        in_source: true,
    }
}

/// The colours of one line.
fn classes(text: &str) -> Vec<(Range<usize>, SyntaxClass)> {
    let whole = 0..text.len();
    match macros::read_line(text) {
        MacroLine::Blank => Vec::new(),
        MacroLine::Comment => vec![(whole, SyntaxClass::Comment)],
        MacroLine::Other => vec![(whole, SyntaxClass::Invalid)],
        MacroLine::Bad { .. } | MacroLine::Frame { .. } => {
            let mut pieces = Vec::new();
            let start = text.len() - text.trim_start().len();
            let call = start + "SendToPack".len().min(text.len() - start);
            pieces.push((0..start, SyntaxClass::Plain));
            pieces.push((start..call, SyntaxClass::Keyword));
            let mut at = call;
            for (i, c) in text[call..].char_indices() {
                let here = call + i;
                if c.is_ascii_hexdigit() || c == '$' || c == 'x' || c == 'X' {
                    continue;
                }
                if here > at {
                    pieces.push((at..here, SyntaxClass::Number));
                }
                pieces.push((here..here + c.len_utf8(), SyntaxClass::Plain));
                at = here + c.len_utf8();
            }
            if text.len() > at {
                pieces.push((at..text.len(), SyntaxClass::Number));
            }
            pieces.retain(|(range, _)| !range.is_empty());
            pieces
        }
    }
}

impl ProgramTool for MacroTool {
    fn name(&self) -> &'static str {
        "SQPack macro"
    }

    fn controller(&self) -> &'static str {
        "SIXpack 2"
    }

    fn extensions(&self) -> &'static [&'static str] {
        EXTENSIONS
    }

    fn unit(&self) -> &'static str {
        "frame"
    }

    fn check(&self, _name: &str, source: &str, _files: &dyn SourceLoader) -> Checked {
        let checked = macros::check(source);
        let program = (checked.errors().next().is_none())
            .then(|| Arc::new(MacroProgram(checked.frames.clone())) as Arc<dyn CheckedProgram>);
        Checked {
            problems: checked.problems.iter().map(problem_of).collect(),
            program,
        }
    }

    fn highlight(
        &self,
        lines: &[String],
        shown: Range<usize>,
    ) -> Vec<Vec<(Range<usize>, SyntaxClass)>> {
        lines
            .get(shown)
            .unwrap_or_default()
            .iter()
            .map(|l| classes(l))
            .collect()
    }

    /// Each frame as the command it is.
    fn annotations(&self, lines: &[String], shown: Range<usize>) -> Vec<Option<String>> {
        lines
            .get(shown)
            .unwrap_or_default()
            .iter()
            .map(|l| macros::decode_line(l))
            .collect()
    }

    fn record(&self, bytes: &[u8]) -> Option<String> {
        macros::record_line(bytes)
    }

    fn runs_from_host(&self) -> bool {
        true
    }

    fn host_command(&self) -> Option<&'static str> {
        Some("run-macro")
    }

    fn host_run(
        &self,
        name: &str,
        source: &str,
        start: Option<&[u8]>,
    ) -> Option<Result<HostStart, Vec<String>>> {
        let _ = start;
        Some(start_playback(name, &macros::check(source)))
    }
}

/// Check a macro for playback: its errors as `NAME:LINE:COLUMN: …`, or
/// the run with its warnings and the frames to confirm.
pub fn start_playback(name: &str, checked: &MacroCheck) -> Result<HostStart, Vec<String>> {
    let placed = |p: &macros::MacroProblem| format!("{name}:{p}");
    let errors: Vec<String> = checked.errors().map(placed).collect();
    if !errors.is_empty() {
        return Err(errors);
    }
    // An empty playback would end "0 frames sent" as if it had done
    // something: refused as every empty run file is.
    if checked.frames.is_empty() {
        return Err(vec![format!(
            "{name}: no SendToPack line: nothing to play (the file is empty, or holds only \
             comments and blank lines)"
        )]);
    }
    let confirm = checked
        .frames
        .iter()
        .filter_map(|f| {
            let why = f.confirm.as_ref()?;
            Some(format!(
                "{name}:{}: `{}`: {why}",
                f.line,
                macros::line_of(&f.request)
            ))
        })
        .collect();
    let frames = checked.frames.len();
    Ok(HostStart {
        run: Box::new(MacroRun::new(name, checked.frames.clone())),
        name: name.to_string(),
        warnings: checked
            .problems
            .iter()
            .filter(|p| !p.error)
            .map(placed)
            .collect(),
        started: format!(
            "a playback of {frames} frame{}",
            if frames == 1 { "" } else { "s" }
        ),
        confirm,
    })
}

/// A checked macro: its frames.
#[derive(Debug, Clone)]
pub struct MacroProgram(pub Vec<MacroFrame>);

impl CheckedProgram for MacroProgram {
    fn state(&self) -> String {
        format!("SQPack macro, {} frame(s)", self.0.len())
    }

    fn built(&self) -> String {
        format!("{} frame(s)", self.0.len())
    }

    fn size(&self) -> usize {
        self.0.len()
    }

    fn line_of(&self, unit: usize) -> Option<usize> {
        self.0.get(unit).map(|f| f.line)
    }

    fn line_of_counter(&self, counter: i64) -> Option<usize> {
        self.line_of(usize::try_from(counter).ok()?)
    }

    fn variable_at(&self, _line: usize, _text: &str, _column: usize) -> Option<u8> {
        None
    }

    fn download(
        &self,
        _address: u8,
        _options: DownloadOptions,
    ) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Err(TransferFailure::refused(NO_STORE))
    }

    fn verify(&self, _address: u8) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Err(TransferFailure::refused(format!(
            "{NO_STORE}, nor read back"
        )))
    }
}

/// A macro played from the host, frame after frame (see the module
/// documentation for the pacing).
#[derive(Debug)]
pub struct MacroRun {
    name: String,
    frames: Vec<MacroFrame>,
    next: usize,
    sent: usize,
    answered: usize,
    news: Vec<HostNews>,
    state: PlaceState,
}

impl MacroRun {
    pub fn new(name: &str, frames: Vec<MacroFrame>) -> MacroRun {
        MacroRun {
            name: name.to_string(),
            frames,
            next: 0,
            sent: 0,
            answered: 0,
            news: Vec::new(),
            state: PlaceState::Running,
        }
    }

    fn send_next(&mut self) -> HostStep {
        match self.frames.get(self.next) {
            Some(frame) => {
                HostStep::Send(macros::record_line(&frame.request.to_bytes()).unwrap_or_default())
            }
            None => {
                self.state = PlaceState::Idle;
                HostStep::Finished(HostEnd {
                    ok: true,
                    summary: format!("{} frame(s) sent, {} answered", self.sent, self.answered),
                })
            }
        }
    }

    fn pace(request: &Request) -> Duration {
        if request.command == 0xCC {
            RESET_PACE
        } else {
            FRAME_PACE
        }
    }
}

impl HostRun for MacroRun {
    fn start(&mut self, _now: Duration) -> HostStep {
        self.send_next()
    }

    fn on_answer(&mut self, answer: &Answer, _now: Duration) -> HostStep {
        let Some(frame) = self.frames.get(self.next) else {
            return self.send_next();
        };
        let (line, request) = (frame.line, frame.request);
        let at = format!("{}:{line}", self.name);
        match &answer.result {
            Ok(reading) => {
                let answered = answer.frames.iter().any(|f| !f.is_empty());
                self.sent += 1;
                self.answered += usize::from(answered);
                self.news.push(HostNews {
                    tone: Tone::Plain,
                    text: format!("{at}: {} → {}", answer.line, reading.value),
                });
                self.next += 1;
                if answered || self.next >= self.frames.len() {
                    self.send_next()
                } else {
                    HostStep::Wake(Self::pace(&request))
                }
            }
            Err(_) => {
                let why = answer.error_text().unwrap_or_default();
                self.state = PlaceState::Error;
                self.news.push(HostNews {
                    tone: Tone::Error,
                    text: format!("{at}: {why}"),
                });
                HostStep::Finished(HostEnd {
                    ok: false,
                    summary: format!("stopped at line {line} after {} frame(s): {why}", self.sent),
                })
            }
        }
    }

    fn on_wake(&mut self, _now: Duration) -> HostStep {
        self.send_next()
    }

    fn take_news(&mut self) -> Vec<HostNews> {
        std::mem::take(&mut self.news)
    }

    fn places(&self) -> Vec<RunningPlace> {
        let line = self
            .frames
            .get(self.next)
            .or(self.frames.last())
            .map_or(1, |f| f.line);
        vec![RunningPlace {
            program: 0,
            state: self.state,
            line,
        }]
    }

    fn variables(&self) -> &[i32] {
        &[]
    }

    fn place_name(&self, _program: u8) -> String {
        "macro".into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::console::{Reading, ReplyValue};
    use crate::protocol::program::{AnswerError, NoIncludes};

    const HOMING: &str = "# §5.5.3.2\n\
        SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)\n\
        SendToPack($00, $22, $00, $00, $00, $00, $00, $00, $00)\n\
        SendToPack($00, $28, $00, $01, $00, $00, $00, $00, $00)\n\
        SendToPack($00, $CC, $00, $00, $00, $00, $00, $00, $00)\n\
        SendToPack($00, $20, $00, $00, $00, $00, $00, $00, $00)\n";

    fn sent(line: &str) -> Answer {
        Answer {
            line: line.into(),
            frames: vec![Vec::new()],
            result: Ok(Reading {
                status: None,
                value: ReplyValue::Text("sent".into()),
            }),
        }
    }

    fn answered(line: &str, value: &str) -> Answer {
        Answer {
            line: line.into(),
            frames: vec![vec![0x28, 0, 0, 0, 0, 0, 0, 0]],
            result: Ok(Reading {
                status: None,
                value: ReplyValue::Text(value.into()),
            }),
        }
    }

    #[test]
    fn playback_paces_unanswered_frames_and_reads_answers() {
        let start = MacroTool
            .host_run("home.sqm", HOMING, None)
            .expect("a host run")
            .expect("checks");
        assert_eq!(start.started, "a playback of 5 frames");
        assert_eq!(start.confirm.len(), 2, "{:?}", start.confirm);
        assert!(start.confirm[0].starts_with("home.sqm:3: `StartReferenceSearch 0`: "));
        assert!(start.confirm[1].starts_with("home.sqm:5: `HardwareReset`: "));
        let mut run = start.run;
        let first = "SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)";
        assert_eq!(run.start(Duration::ZERO), HostStep::Send(first.into()));
        assert_eq!(run.places()[0].line, 2, "the line being sent is marked");
        let step = run.on_answer(
            &sent("SetMotorParameters 0 10000 NullLeft,MechRef"),
            Duration::ZERO,
        );
        assert_eq!(step, HostStep::Wake(FRAME_PACE));
        assert!(matches!(run.on_wake(Duration::ZERO), HostStep::Send(l) if l.contains("$22")));
        assert_eq!(
            run.on_answer(&sent("StartReferenceSearch 0"), Duration::ZERO),
            HostStep::Wake(FRAME_PACE)
        );
        run.on_wake(Duration::ZERO);
        // The $28 is answered: the next frame goes at once.
        let step = run.on_answer(
            &answered("GetAllActivities 0 0", "m0=inactive"),
            Duration::ZERO,
        );
        assert!(matches!(step, HostStep::Send(l) if l.contains("$CC")));
        assert_eq!(
            run.on_answer(&sent("HardwareReset"), Duration::ZERO),
            HostStep::Wake(RESET_PACE)
        );
        run.on_wake(Duration::ZERO);
        let end = run.on_answer(
            &answered("GetPositionAndActivity 0", "posact=0"),
            Duration::ZERO,
        );
        assert_eq!(
            end,
            HostStep::Finished(HostEnd {
                ok: true,
                summary: "5 frame(s) sent, 2 answered".into()
            })
        );
        let news: Vec<String> = run.take_news().into_iter().map(|n| n.text).collect();
        assert_eq!(news.len(), 5);
        assert_eq!(news[2], "home.sqm:4: GetAllActivities 0 0 → m0=inactive");
    }

    #[test]
    fn a_failed_frame_ends_the_playback() {
        let mut run = MacroTool
            .host_run("m.sqm", HOMING, None)
            .expect("a host run")
            .expect("checks")
            .run;
        run.start(Duration::ZERO);
        let lost = Answer {
            line: "SetMotorParameters 0 10000 NullLeft,MechRef".into(),
            frames: Vec::new(),
            result: Err(AnswerError::Lost {
                address: 0,
                reason: "not connected: unplugged".into(),
            }),
        };
        let HostStep::Finished(end) = run.on_answer(&lost, Duration::ZERO) else {
            panic!("it ends")
        };
        assert!(!end.ok);
        assert!(
            end.summary
                .starts_with("stopped at line 2 after 0 frame(s)")
        );
        assert_eq!(run.places()[0].state, PlaceState::Error);
    }

    #[test]
    fn a_macro_with_errors_is_not_played_and_says_where() {
        let problems = MacroTool
            .host_run("bad.sqm", "SendToPack($00, $23, $07)\n", None)
            .expect("a host run")
            .expect_err("refused");
        assert_eq!(
            problems,
            ["bad.sqm:1:25: a frame has 9 values (adr, cmd, p0..p6), this one 3"]
        );
        let checked = MacroTool.check("bad.sqm", "SendToPack($00, $23, $07)\n", &NoIncludes);
        assert!(checked.program.is_none());
        assert_eq!(checked.problems[0].column, 25);
    }

    #[test]
    fn the_editor_gets_colours_annotations_and_no_download() {
        let lines: Vec<String> = HOMING.lines().map(str::to_string).collect();
        let notes = MacroTool.annotations(&lines, 0..3);
        assert_eq!(
            notes,
            [
                None,
                Some("SetMotorParameters 0 10000 NullLeft,MechRef (Motor 1)".into()),
                Some("StartReferenceSearch 0 (Motor 1)".into())
            ]
        );
        let colours = MacroTool.highlight(&lines, 1..2);
        assert_eq!(colours[0][0], (0..10, SyntaxClass::Keyword));
        assert!(colours[0].contains(&(11..14, SyntaxClass::Number)));
        assert_eq!(
            MacroTool.highlight(&lines, 0..1)[0],
            [(0..lines[0].len(), SyntaxClass::Comment)]
        );
        let checked = MacroTool.check("m.sqm", HOMING, &NoIncludes);
        let program = checked.program.expect("checks");
        assert_eq!(program.size(), 5);
        assert_eq!(program.line_of(1), Some(3));
        let refused = program
            .download(0, DownloadOptions::default())
            .err()
            .expect("refused");
        assert!(refused.nothing_sent());
        assert_eq!(
            MacroTool
                .record(&[0, 0x23, 0, 0x10, 0x27, 0, 0, 0, 0])
                .as_deref(),
            Some("SendToPack($00, $23, $00, $10, $27, $00, $00, $00, $00)")
        );
    }
}
