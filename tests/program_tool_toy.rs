//! The program seam, as a new family would use it: a toy third family,
//! written here in the test crate and not in `src/`, offers a toy program
//! tool. Its source is checked with located errors, coloured, and
//! downloaded with verification and cancelled through the session's
//! generic runner and the editor pane, exactly as TMCL's programs are;
//! nothing in `src/` knows the toy exists.
//!
//! The toy controller speaks ASCII lines (`LINE\r`, answered `OK\r`, a
//! number, `STORED\r` or `ERR …\r`). `LOAD` puts it in a load mode in which
//! every line but `READ n` and `DONE` is stored as a program line instead
//! of being executed (as TMCL's download mode stores words): the toy plan
//! holds the module while it loads.

mod ui_support;

use std::ops::Range;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::link::LinkSpec;
use axterm::protocol::Family;
use axterm::protocol::console::{
    Answering, AxisInfo, AxisUpdate, Effect, FamilyConsole, PreparedLine, Reading, ReplyError,
    ReplyValue, StatusPoll,
};
use axterm::protocol::line_error::{FamilyLineError, LineError, Mistake};
use axterm::protocol::program::{
    Answer, AnswerError, Checked, CheckedProgram, DownloadOptions, FailureKind, ModuleHold, Phase,
    PlanLine, PlanStep, Problem, ProgramTool, Progress, SourceLoader, SyntaxClass, TransferFailure,
    TransferPlan, TransferReport,
};
use axterm::protocol::wire::{Frame, Framer, ReplyRule, Verdict, WireFormat};
use axterm::session::{Cancel, Session, SessionOptions};
use axterm::sim::SimulatedController;
use axterm::sim::faults::FaultPlan;
use axterm::ui::PaneSetup;
use axterm::ui::app::{self, App, AppEvent, Connector, Controller};
use axterm::ui::live::SessionController;
use axterm::ui::pane::Snapshot;
use axterm::ui::theme::Role;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use tokio::sync::mpsc;

/// The toy's one refusal.
#[derive(Debug, thiserror::Error)]
#[error("an empty line")]
struct EmptyLine;

impl FamilyLineError for EmptyLine {
    fn mistake(&self) -> Mistake {
        Mistake::Empty
    }
}
use ui_support::{console_with, screen};

// ---------------------------------------------------------------- the wire

/// Cuts the stream at carriage returns.
#[derive(Default)]
struct LineFramer {
    partial: Vec<u8>,
}

impl Framer for LineFramer {
    fn push(&mut self, bytes: &[u8]) -> Vec<Frame> {
        let mut frames = Vec::new();
        for &byte in bytes {
            if byte == b'\r' {
                frames.push(std::mem::take(&mut self.partial));
            } else {
                self.partial.push(byte);
            }
        }
        frames
    }

    fn pending(&self) -> usize {
        self.partial.len()
    }

    fn discard_pending(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.partial)
    }
}

/// Every line answers the line in flight.
#[derive(Debug)]
struct AnyLine;

impl ReplyRule for AnyLine {
    fn examine(&self, _accepted: &[Frame], _frame: &[u8]) -> Verdict {
        Verdict::Complete
    }
}

struct ToyWire;

impl WireFormat for ToyWire {
    fn name(&self) -> &'static str {
        "toy"
    }

    fn framer(&self) -> Box<dyn Framer> {
        Box::new(LineFramer::default())
    }

    fn unsolicited(&self, _frame: &[u8]) -> Option<String> {
        None
    }

    fn silence(&self, _byte_time: Option<Duration>) -> Duration {
        Duration::from_millis(50)
    }
}

// ------------------------------------------------------------- the family

const AXES: &[AxisInfo] = &[AxisInfo {
    number: 0,
    name: "axis",
}];

fn toy_line(text: &str, address: u8) -> PreparedLine {
    let reads = text.starts_with("READ") || text == "ID";
    PreparedLine {
        canonical: text.to_string(),
        address,
        bytes: format!("{text}\r").into_bytes(),
        answering: Answering::Reply(Arc::new(AnyLine)),
        effect: if reads { Effect::Reads } else { Effect::Acts },
    }
}

struct ToyConsole;

impl FamilyConsole for ToyConsole {
    fn wire(&self) -> Arc<dyn WireFormat> {
        Arc::new(ToyWire)
    }

    fn default_address(&self) -> u8 {
        1
    }

    fn axes(&self) -> &'static [AxisInfo] {
        AXES
    }

    fn prepare(&self, line: &str, address: u8) -> Result<PreparedLine, LineError> {
        let line = line.trim().to_ascii_uppercase();
        if line.is_empty() {
            return Err(EmptyLine.into());
        }
        Ok(toy_line(&line, address))
    }

    fn interpret(&self, line: &PreparedLine, frames: &[Frame]) -> Result<Reading, ReplyError> {
        let text = frames
            .last()
            .map(|f| String::from_utf8_lossy(f).into_owned())
            .unwrap_or_default();
        if let Some(why) = text.strip_prefix("ERR ") {
            return Err(ReplyError::Refused {
                module: "toy 1".into(),
                line: line.canonical.clone(),
                reply: text.clone(),
                meaning: why.to_string(),
            });
        }
        let value = match text.parse::<i64>() {
            Ok(n) => ReplyValue::Number(n),
            Err(_) if text == "OK" => ReplyValue::None,
            Err(_) => ReplyValue::Text(text),
        };
        Ok(Reading {
            status: None,
            value,
        })
    }

    fn emergency_stop(&self, address: u8) -> Vec<PreparedLine> {
        vec![toy_line("HALT", address)]
    }

    fn identify(&self, address: u8) -> PreparedLine {
        toy_line("ID", address)
    }

    fn status_queries(&self, _address: u8) -> Vec<StatusPoll> {
        Vec::new()
    }

    fn status_update(&self, _line: &PreparedLine, _reading: &Reading) -> Vec<(usize, AxisUpdate)> {
        Vec::new()
    }

    fn program(&self) -> Option<&'static dyn ProgramTool> {
        Some(&ToyTool)
    }
}

/// The third family, registered here: one entry.
static TOY: Family = Family {
    name: "toy",
    description: "a toy controller of this test",
    encode_line: |line, _| Ok(format!("{line}\r").into_bytes()),
    show_bytes: |bytes| String::from_utf8_lossy(bytes).into_owned(),
    console: &ToyConsole,
};

// ------------------------------------------------------- the program tool

/// Toy programs: `MOVE n` and `WAIT` lines, `#` comments.
struct ToyTool;

/// A checked toy program: each statement and its source line.
#[derive(Debug)]
struct ToyProgram {
    statements: Vec<(usize, String)>,
}

fn check_line(number: usize, line: &str) -> Result<Option<String>, Problem> {
    let code = line.split('#').next().unwrap_or("").trim();
    if code.is_empty() {
        return Ok(None);
    }
    let problem = |column: usize, message: String| Problem {
        line: number,
        column,
        text: format!("line {number}: {message}"),
        message,
        error: true,
        in_source: true,
    };
    let start = line.len() - line.trim_start().len() + 1;
    let mut words = code.split_whitespace();
    match (words.next(), words.next(), words.next()) {
        (Some("WAIT"), None, None) => Ok(Some("WAIT".into())),
        (Some("MOVE"), Some(n), None) if n.parse::<i32>().is_ok() => Ok(Some(format!("MOVE {n}"))),
        (Some("MOVE"), _, _) => Err(problem(start + 5, "MOVE takes one number".into())),
        (Some(word), _, _) => Err(problem(start, format!("`{word}` is no toy statement"))),
        (None, _, _) => Ok(None),
    }
}

impl ProgramTool for ToyTool {
    fn name(&self) -> &'static str {
        "Toy"
    }

    fn controller(&self) -> &'static str {
        "toy controller"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &["toy"]
    }

    fn unit(&self) -> &'static str {
        "statement"
    }

    fn check(&self, _name: &str, source: &str, _files: &dyn SourceLoader) -> Checked {
        let mut problems = Vec::new();
        let mut statements = Vec::new();
        for (index, line) in source.split('\n').enumerate() {
            match check_line(index + 1, line) {
                Ok(Some(statement)) => statements.push((index + 1, statement)),
                Ok(None) => {}
                Err(problem) => problems.push(problem),
            }
        }
        let program = problems
            .is_empty()
            .then(|| Arc::new(ToyProgram { statements }) as Arc<dyn CheckedProgram>);
        Checked { problems, program }
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
            .map(|line| {
                let mut pieces = Vec::new();
                let code_end = line.find('#').unwrap_or(line.len());
                let mut at = 0;
                for word in line[..code_end].split_inclusive(' ') {
                    let end = at + word.trim_end().len();
                    let class = if word.trim().parse::<i32>().is_ok() {
                        SyntaxClass::Number
                    } else if matches!(word.trim(), "MOVE" | "WAIT") {
                        SyntaxClass::Keyword
                    } else {
                        SyntaxClass::Plain
                    };
                    pieces.push((at..end, class));
                    pieces.push((end..at + word.len(), SyntaxClass::Plain));
                    at += word.len();
                }
                pieces.push((code_end..line.len(), SyntaxClass::Comment));
                pieces.retain(|(range, _)| !range.is_empty());
                pieces
            })
            .collect()
    }
}

impl CheckedProgram for ToyProgram {
    fn state(&self) -> String {
        format!("toy: {} statements", self.statements.len())
    }

    fn built(&self) -> String {
        self.state()
    }

    fn size(&self) -> usize {
        self.statements.len()
    }

    fn line_of(&self, unit: usize) -> Option<usize> {
        self.statements.get(unit).map(|(line, _)| *line)
    }

    fn line_of_counter(&self, counter: i64) -> Option<usize> {
        self.line_of(usize::try_from(counter).ok()?)
    }

    fn variable_at(&self, _line: usize, _text: &str, _column: usize) -> Option<u8> {
        None
    }

    fn download(
        &self,
        address: u8,
        _options: DownloadOptions,
    ) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Ok(Box::new(ToyDownload::new(
            address,
            self.statements.iter().map(|(_, s)| s.clone()).collect(),
        )))
    }

    fn verify(&self, _address: u8) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        Err(TransferFailure::refused("not in this test"))
    }
}

/// Load mode: user lines other than `READ` and `DONE` would be stored.
#[derive(Debug)]
struct LoadHold {
    address: u8,
}

impl ModuleHold for LoadHold {
    fn refusal(&self, line: &PreparedLine) -> Option<String> {
        let admitted = line.canonical.starts_with("READ") || line.canonical == "DONE";
        (!admitted).then(|| {
            format!(
                "the toy is loading a program: it would store {}",
                line.canonical
            )
        })
    }

    fn release(&self) -> Option<PreparedLine> {
        Some(toy_line("DONE", self.address))
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stage {
    Load,
    Store(usize),
    Done,
    Verify(usize),
    Over,
}

/// `LOAD`, every statement (each answered `STORED`), `DONE`, then every
/// statement read back with `READ n` and compared.
struct ToyDownload {
    address: u8,
    statements: Vec<String>,
    stage: Stage,
    held: bool,
    cancelled: bool,
    /// Why it failed, told once `DONE` is answered.
    cause: Option<TransferFailure>,
    end: Option<Result<TransferReport, TransferFailure>>,
    progress: Option<Progress>,
}

impl ToyDownload {
    fn new(address: u8, statements: Vec<String>) -> ToyDownload {
        ToyDownload {
            address,
            statements,
            stage: Stage::Load,
            held: true,
            cancelled: false,
            cause: None,
            end: None,
            progress: None,
        }
    }

    fn total(&self) -> Option<usize> {
        Some(self.statements.len())
    }

    fn line(&self, text: &str) -> PlanStep {
        PlanStep::Send(PlanLine::new(toy_line(text, self.address)))
    }

    fn finish(&mut self, end: Result<TransferReport, TransferFailure>) {
        self.stage = Stage::Over;
        self.end = Some(end);
    }
}

impl TransferPlan for ToyDownload {
    fn next(&mut self) -> PlanStep {
        if let Some(end) = self.end.take() {
            return match end {
                Ok(report) => PlanStep::Done(report),
                Err(failure) => PlanStep::Failed(failure),
            };
        }
        match self.stage {
            Stage::Load => self.line("LOAD"),
            Stage::Store(n) if self.cancelled => {
                self.cause = Some(TransferFailure {
                    kind: FailureKind::Cancelled(Progress {
                        phase: Phase::Storing,
                        done: n,
                        total: self.total(),
                    }),
                    message: format!("cancelled after storing {n} statements"),
                    said: None,
                    at: None,
                });
                self.stage = Stage::Done;
                self.line("DONE")
            }
            Stage::Store(n) => match self.statements.get(n) {
                // Raw: in load mode the statement is the line.
                Some(statement) => {
                    let statement = statement.clone();
                    self.line(&statement)
                }
                None => {
                    self.stage = Stage::Done;
                    self.line("DONE")
                }
            },
            Stage::Done => self.line("DONE"),
            Stage::Verify(n) => self.line(&format!("READ {n}")),
            Stage::Over => PlanStep::Failed(TransferFailure::failed("over", None)),
        }
    }

    fn answer(&mut self, answer: Answer) {
        let text = match &answer.result {
            Ok(reading) => reading.value.to_string(),
            Err(AnswerError::Lost { reason, .. }) => {
                let failure = TransferFailure::failed(format!("no answer: {reason}"), None);
                self.finish(Err(failure));
                return;
            }
            Err(_) => answer.error_text().unwrap_or_default(),
        };
        match self.stage {
            Stage::Load => self.stage = Stage::Store(0),
            Stage::Store(n) if text == "STORED" => {
                self.progress = Some(Progress {
                    phase: Phase::Storing,
                    done: n + 1,
                    total: self.total(),
                });
                self.stage = Stage::Store(n + 1);
            }
            Stage::Store(n) => {
                self.cause = Some(TransferFailure::failed(
                    format!("statement {n} was not stored: {text}"),
                    Some(n),
                ));
                self.stage = Stage::Done;
            }
            Stage::Done => {
                self.held = false;
                match self.cause.take() {
                    Some(cause) => self.finish(Err(cause)),
                    None if self.statements.is_empty() => {
                        self.finish(Ok(TransferReport::new(self.address, 0)))
                    }
                    None => {
                        self.progress = Some(Progress {
                            phase: Phase::Verifying,
                            done: 0,
                            total: self.total(),
                        });
                        self.stage = Stage::Verify(0);
                    }
                }
            }
            Stage::Verify(n) => {
                let wrote = self.statements.get(n).cloned().unwrap_or_default();
                if text != wrote {
                    self.finish(Err(TransferFailure::failed(
                        format!("statement {n} differs: wrote {wrote}, read {text}"),
                        Some(n),
                    )));
                    return;
                }
                self.progress = Some(Progress {
                    phase: Phase::Verifying,
                    done: n + 1,
                    total: self.total(),
                });
                if n + 1 < self.statements.len() {
                    self.stage = Stage::Verify(n + 1);
                } else {
                    let report = TransferReport::new(self.address, self.statements.len());
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
        self.progress
    }

    fn hold(&self) -> Option<Arc<dyn ModuleHold>> {
        self.held.then(|| {
            Arc::new(LoadHold {
                address: self.address,
            }) as Arc<dyn ModuleHold>
        })
    }
}

// ------------------------------------------------------- the toy controller

/// The controller: executes `MOVE n`, `ID`, `HALT`; `LOAD` … `DONE` stores
/// what comes between; `READ n` reads a stored line.
#[derive(Default)]
struct ToySim {
    input: Vec<u8>,
    output: Vec<u8>,
    loading: bool,
    memory: Vec<String>,
    position: i64,
}

impl ToySim {
    fn answer(&mut self, line: &str) -> String {
        if let Some(n) = line.strip_prefix("READ ") {
            return n
                .parse::<usize>()
                .ok()
                .and_then(|n| self.memory.get(n).cloned())
                .unwrap_or_else(|| "EMPTY".into());
        }
        if line == "DONE" {
            self.loading = false;
            return "OK".into();
        }
        if self.loading {
            self.memory.push(line.to_string());
            return "STORED".into();
        }
        match line {
            "ID" => "TOY 1".into(),
            "LOAD" => {
                self.loading = true;
                self.memory.clear();
                "OK".into()
            }
            "HALT" => "OK".into(),
            "POS" => self.position.to_string(),
            _ => match line.strip_prefix("MOVE ").map(str::parse::<i64>) {
                Some(Ok(n)) => {
                    self.position = n;
                    "OK".into()
                }
                _ => "ERR unknown".into(),
            },
        }
    }
}

impl SimulatedController for ToySim {
    fn feed(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            if byte == b'\r' {
                let line = String::from_utf8_lossy(&std::mem::take(&mut self.input)).into_owned();
                let answer = self.answer(line.trim());
                self.output.extend_from_slice(answer.as_bytes());
                self.output.push(b'\r');
            } else {
                self.input.push(byte);
            }
        }
    }

    fn advance(&mut self, _dt: Duration) {}

    fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.output)
    }

    fn help(&self) -> String {
        "a toy controller".into()
    }
}

async fn toy_session(baud: Option<u32>) -> Session {
    let spec = LinkSpec::Sim {
        kind: "toy".into(),
        sim: Arc::new(Mutex::new(
            Box::new(ToySim::default()) as Box<dyn SimulatedController>
        )),
        baud,
        faults: FaultPlan::none(),
    };
    Session::connect(spec, &TOY, SessionOptions::default())
        .await
        .expect("the toy link opens")
}

async fn read(session: &Session, line: &str) -> String {
    session
        .execute_line(line)
        .await
        .unwrap_or_else(|e| panic!("{line}: {e}"))
        .value
        .to_string()
}

fn program(count: usize) -> String {
    (0..count)
        .map(|i| format!("MOVE {}\n", i * 10))
        .chain(std::iter::once("WAIT # the end".to_string()))
        .collect()
}

// ------------------------------------------------------------------ tests

#[test]
fn the_toy_tool_checks_with_located_errors() {
    let checked = ToyTool.check(
        "p.toy",
        "MOVE 1\nJUMP 3\nMOVE x\n# fine\n",
        &axterm::protocol::program::NoIncludes,
    );
    assert!(checked.program.is_none());
    let places: Vec<(usize, usize)> = checked
        .problems
        .iter()
        .map(|p| (p.line, p.column))
        .collect();
    assert_eq!(places, [(2, 1), (3, 6)]);
}

#[tokio::test(start_paused = true)]
async fn the_generic_runner_downloads_and_verifies_a_toy_program_and_holds_the_module() {
    let session = toy_session(Some(9600)).await;
    let checked = ToyTool.check("p.toy", &program(6), &axterm::protocol::program::NoIncludes);
    let program = checked.program.expect("checks");
    let plan = program
        .download(session.address(), DownloadOptions::default())
        .expect("a plan");
    // While it loads, a line the toy would store is refused; a read goes.
    let (go, signal) = tokio::sync::oneshot::channel::<()>();
    let user = session.clone();
    let attempt = tokio::spawn(async move {
        let _ = signal.await;
        let stored = user.execute_line("MOVE 5").await;
        let admitted = user.execute_line("READ 0").await;
        (stored, admitted)
    });
    let mut go = Some(go);
    let mut seen: Vec<Progress> = Vec::new();
    let report = session
        .transfer(plan, &Cancel::new(), &mut |p| {
            if p.phase == Phase::Storing
                && p.done == 2
                && let Some(go) = go.take()
            {
                let _ = go.send(());
            }
            seen.push(p);
        })
        .await
        .expect("downloaded and verified");
    assert_eq!(report.count, 7);
    // LOAD, 7 statements, DONE, 7 reads.
    assert_eq!(report.transactions, 16);
    assert!(
        seen.iter()
            .any(|p| p.phase == Phase::Verifying && p.done == 7)
    );
    let (stored, admitted) = attempt.await.expect("the user task");
    let refused = stored.expect_err("refused while loading");
    assert!(refused.nothing_sent(), "{refused}");
    assert!(
        refused.to_string().contains("loading a program"),
        "{refused}"
    );
    admitted.expect("READ is admitted while loading");
    // The module holds the program and executes lines again.
    assert_eq!(read(&session, "READ 6").await, "WAIT");
    assert_eq!(read(&session, "MOVE 5").await, "ok");
    assert_eq!(read(&session, "POS").await, "5");
}

#[tokio::test(start_paused = true)]
async fn cancelling_a_toy_download_lets_the_module_go_before_failing() {
    let session = toy_session(Some(9600)).await;
    let checked = ToyTool.check(
        "p.toy",
        &program(20),
        &axterm::protocol::program::NoIncludes,
    );
    let plan = checked
        .program
        .expect("checks")
        .download(session.address(), DownloadOptions::default())
        .expect("a plan");
    let cancel = Cancel::new();
    let canceller = cancel.clone();
    let failure = session
        .transfer(plan, &cancel, &mut |p| {
            if p.phase == Phase::Storing && p.done == 3 {
                canceller.cancel();
            }
        })
        .await
        .expect_err("cancelled");
    assert_eq!(
        failure.cancelled(),
        Some(Progress {
            phase: Phase::Storing,
            done: 3,
            total: Some(21)
        })
    );
    // DONE was sent: the toy executes lines again.
    assert_eq!(read(&session, "MOVE 7").await, "ok");
    assert_eq!(
        read(&session, "READ 3").await,
        "EMPTY",
        "statement 3 never sent"
    );
}

fn toy_snapshot() -> Snapshot {
    Snapshot {
        family: &TOY,
        address: 1,
        link_name: "toy".into(),
        axes: AXES.to_vec(),
        status: vec![Default::default()],
        link: axterm::device::LinkState::Connected { link: "toy".into() },
        identity: None,
        poll: None,
        settings: Default::default(),
        mechanics: Default::default(),
        axis: 0,
    }
}

#[test]
fn the_editor_checks_and_colours_toy_source_with_the_toy_tool() {
    let mut app = console_with(&PaneSetup::default());
    app.handle(AppEvent::Snapshot(toy_snapshot()));
    assert!(app.focus("editor"));
    app.handle(AppEvent::Terminal(Event::Paste(
        "MOVE 100 # out\nJUMP 3\nWAIT".into(),
    )));
    let lines = screen(&mut app, 100, 30);
    let all = lines.join("\n");
    assert!(all.contains("Program (Toy) — untitled*"), "{all}");
    let jump = lines.iter().find(|l| l.contains("JUMP 3")).expect("line 2");
    assert!(jump.contains("!  2"), "{jump}");
    assert!(all.contains("1 error (Ctrl-G next)"), "{all}");

    let mut terminal = Terminal::new(TestBackend::new(100, 30)).expect("backend");
    terminal.draw(|f| app.render(f)).expect("draw");
    let buffer = terminal.backend().buffer().clone();
    let theme = app.theme().clone();
    let find = |text: &str| -> (u16, u16) {
        for y in 0..30u16 {
            let row: String = (0..100u16)
                .map(|x| buffer[(x, y)].symbol().to_string())
                .collect();
            if let Some(at) = row.find(text) {
                let x = row.get(..at).map_or(0, |b| b.chars().count());
                return (u16::try_from(x).unwrap_or(0), y);
            }
        }
        panic!("{text} not on screen");
    };
    let fg = |role: Role| theme.style(role).fg;
    assert_eq!(Some(buffer[find("MOVE")].fg), fg(Role::CodeMnemonic));
    assert_eq!(Some(buffer[find("100")].fg), fg(Role::CodeNumber));
    assert_eq!(Some(buffer[find("# out")].fg), fg(Role::CodeComment));
}

const WIDTH: u16 = 80;
const HEIGHT: u16 = 24;

/// The console loop's keyboard and what it draws.
struct Rig {
    keys: mpsc::UnboundedSender<Event>,
    drawn: mpsc::UnboundedReceiver<String>,
    last: String,
}

impl Rig {
    fn press(&self, code: KeyCode) {
        let _ = self
            .keys
            .send(Event::Key(KeyEvent::new(code, KeyModifiers::NONE)));
    }

    async fn until(&mut self, needle: &str) -> String {
        let wait = async {
            while let Some(frame) = self.drawn.recv().await {
                let found = frame.contains(needle);
                self.last = frame;
                if found {
                    return true;
                }
            }
            false
        };
        let found = tokio::time::timeout(Duration::from_secs(600), wait).await;
        assert!(
            matches!(found, Ok(true)),
            "never showed {needle:?}; last frame:\n{}",
            self.last
        );
        self.last.clone()
    }
}

/// The real console loop on the toy session, the editor in front.
async fn run_console(session: &Session, driver: impl AsyncFnOnce(&mut Rig)) {
    let controller: Arc<dyn Controller> = Arc::new(SessionController::new(
        session.clone(),
        "toy".into(),
        SessionOptions::default(),
    ));
    let connector: Connector = Box::new(|_| Box::pin(async { Err("not in this test".into()) }));
    let mut app: App = console_with(&PaneSetup::default());
    app.focus("editor");
    let (keys, input) = mpsc::unbounded_channel();
    let (drawn_tx, drawn) = mpsc::unbounded_channel();
    let mut terminal = Terminal::new(TestBackend::new(WIDTH, HEIGHT)).expect("test backend");
    let mut draw = move |app: &mut App| -> std::io::Result<()> {
        let Ok(_) = terminal.draw(|f| app.render(f));
        let buffer = terminal.backend().buffer();
        let text: Vec<String> = (0..HEIGHT)
            .map(|y| {
                (0..WIDTH)
                    .map(|x| buffer[(x, y)].symbol().to_string())
                    .collect()
            })
            .collect();
        let _ = drawn_tx.send(text.join("\n"));
        Ok(())
    };
    let mut rig = Rig {
        keys,
        drawn,
        last: String::new(),
    };
    let looping = app::run(
        &mut app,
        Some(controller),
        connector,
        input,
        None,
        &mut draw,
    );
    let driving = async {
        driver(&mut rig).await;
        rig.press(KeyCode::F(10));
    };
    let (result, ()) = tokio::join!(looping, driving);
    result.expect("the loop ends cleanly");
}

#[tokio::test(start_paused = true)]
async fn f4_downloads_and_verifies_a_toy_program_and_esc_cancels_one() {
    let session = toy_session(Some(9600)).await;
    run_console(&session, async |rig: &mut Rig| {
        let _ = rig.keys.send(Event::Paste(program(3)));
        rig.until("Program (Toy)").await;
        rig.press(KeyCode::F(4));
        rig.until("download: verifying").await;
        rig.until("downloaded and verified 4 statements").await;

        // A longer one, cancelled while it stores.
        let _ = rig.keys.send(Event::Paste(format!("\n{}", program(40))));
        rig.until(" 45 WAIT").await;
        rig.press(KeyCode::F(4));
        rig.until("download: storing 3/45 statements — Esc cancels")
            .await;
        rig.press(KeyCode::Esc);
        let frame = rig.until("cancelled after storing").await;
        assert!(!frame.contains("download: storing"), "{frame}");
    })
    .await;
    // The module left load mode: it executes lines again, and the first
    // program's lines were overwritten only in part.
    assert_eq!(read(&session, "MOVE 9").await, "ok");
    let first = read(&session, "READ 0").await;
    assert_eq!(first, "MOVE 0");
    assert_eq!(read(&session, "READ 44").await, "EMPTY");
}
