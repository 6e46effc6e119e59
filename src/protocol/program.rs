//! Standalone programs as a family offers them: a [`ProgramTool`] that
//! checks a program's source (located errors and warnings), colours it
//! ([`SyntaxClass`]), names the variables a console can watch and the
//! lines that read and control a program in the controller, and says how
//! the text reaches the controller: as a [`TransferPlan`] (a pure state
//! machine of prepared lines and their answers: TMCL's download, verify
//! and upload), as a [`HostRun`] (the program run statement by statement
//! from the host: A-Script), or not at all over the wire
//! ([`DownloadWay::SimulatorOnly`]).
//!
//! Pure code, no I/O and no clock: `session/` drives plans and host runs
//! through one generic runner, the editor and the command line hold a
//! `&'static dyn ProgramTool` from [`super::console::FamilyConsole::program`],
//! and neither names a family.

use std::fmt;
use std::ops::Range;
use std::sync::Arc;
use std::time::Duration;

use super::console::{PreparedLine, Reading, ReplyError, ReplyValue};
use super::wire::Frame;

/// Supplies the text of files a source includes (TMCL `#include`). The
/// tools stay pure: the command line and the editor read files, tests hand
/// over a map.
pub trait SourceLoader {
    /// The text of the file at `path`; on failure, a reason a technician
    /// understands ("no such file").
    fn load(&self, path: &str) -> Result<String, LoadError>;
}

/// Why an included file was not read.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("this source cannot include files")]
    NoIncludes,
    #[error("no such file")]
    NotFound,
    /// The file is there but could not be read as text (the reader's own
    /// error inside: permission, size, not UTF-8…).
    #[error(transparent)]
    Unreadable(Box<dyn std::error::Error + Send + Sync>),
}

/// Refuses every include: for sources that must stand alone.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoIncludes;

impl SourceLoader for NoIncludes {
    fn load(&self, _path: &str) -> Result<String, LoadError> {
        Err(LoadError::NoIncludes)
    }
}

/// Files in memory, by path.
impl SourceLoader for std::collections::BTreeMap<String, String> {
    fn load(&self, path: &str) -> Result<String, LoadError> {
        self.get(path).cloned().ok_or(LoadError::NotFound)
    }
}

/// What a piece of a source line is, for its colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SyntaxClass {
    /// White space, operators, anything uncoloured.
    Plain,
    /// A command, mnemonic, keyword or directive.
    Keyword,
    /// A label, or a block's bounds (A-Script PRG/END).
    Label,
    /// A number or a constant's name.
    Number,
    Comment,
    /// A variable (A-Script `V12`).
    Variable,
    /// What the language does not know.
    Invalid,
}

/// Something wrong in a source, where it is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// 1-based.
    pub line: usize,
    /// 1-based, in characters.
    pub column: usize,
    /// The whole message, with its place as the tool writes it.
    pub text: String,
    /// What is wrong, without the place.
    pub message: String,
    /// An error (the program cannot be built); else a warning.
    pub error: bool,
    /// In the source checked (not in a file it includes).
    pub in_source: bool,
}

/// A source as its tool checked it.
#[derive(Debug, Clone, Default)]
pub struct Checked {
    /// Every error and warning, in line order (those of included files
    /// too, marked).
    pub problems: Vec<Problem>,
    /// The built program, when there is no error.
    pub program: Option<Arc<dyn CheckedProgram>>,
}

impl Checked {
    /// The errors (not the warnings), anywhere.
    pub fn errors(&self) -> impl Iterator<Item = &Problem> {
        self.problems.iter().filter(|p| p.error)
    }
}

/// How a tool says its check went ("assembles" / "checks").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Wording {
    /// "the program assembles".
    pub passes: &'static str,
    /// "does not assemble".
    pub pass: &'static str,
}

/// A program that checked: what the editor and the command line need of
/// it, and the plans that send it.
pub trait CheckedProgram: Send + Sync + fmt::Debug {
    /// For the editor's bottom line: "assembles: 12 words".
    fn state(&self) -> String;
    /// For the build key: "assembled: 12 words, 3 labels".
    fn built(&self) -> String;
    /// Units a download stores (words); 0: nothing to send.
    fn size(&self) -> usize;
    /// The source line (1-based, in the checked source) a program unit
    /// (TMCL: the word at this address) was built from.
    fn line_of(&self, unit: usize) -> Option<usize>;
    /// The source line of a program counter as the controller reports it.
    fn line_of_counter(&self, counter: i64) -> Option<usize>;
    /// The programs the source defines, where the controller has several
    /// (A-Script's PRG numbers).
    fn programs(&self) -> Vec<u8> {
        Vec::new()
    }
    /// The program the run keys act on at source line `line` (1-based):
    /// A-Script's PRG block; `None` where the controller has one program.
    fn program_at(&self, line: usize) -> Option<u8> {
        let _ = line;
        None
    }
    /// The variable that source line `line` (1-based, text `text`) names
    /// at byte `column`, if any.
    fn variable_at(&self, line: usize, text: &str, column: usize) -> Option<u8>;
    /// Store the program in the module at `address` and verify it.
    fn download(
        &self,
        address: u8,
        options: DownloadOptions,
    ) -> Result<Box<dyn TransferPlan>, TransferFailure>;
    /// Compare the module's program with this one, storing nothing.
    fn verify(&self, address: u8) -> Result<Box<dyn TransferPlan>, TransferFailure>;
    /// The program image as text (`axterm asm`), if the tool has one.
    fn image(&self) -> Option<String> {
        None
    }
    /// The listing (addresses, words, source), if the tool has one.
    fn listing(&self) -> Option<String> {
        None
    }
}

/// How a checked program reaches the controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DownloadWay {
    /// Over the wire: [`CheckedProgram::download`] gives the plan.
    Wire,
    /// The manual documents no way over the wire (`why`); a simulator in
    /// this process can take the source
    /// ([`crate::sim::SimulatedController::load_program`]).
    SimulatorOnly {
        why: &'static str,
        /// What a real controller does instead ("a real CMD-4CR takes no
        /// download").
        real: &'static str,
    },
}

/// The variables of a program a console can watch, as data.
#[derive(Debug, Clone, Copy)]
pub struct VariableSet {
    /// Under which key the list watched is kept between runs.
    pub key: &'static str,
    /// The watch panel's heading ("user variables").
    pub heading: &'static str,
    /// Written before a variable's number ("#", "V").
    pub mark: &'static str,
    /// Asked for the number when the cursor names none.
    pub prompt: &'static str,
    /// The console line that reads variable `n`.
    pub read_line: fn(u8) -> String,
    /// The variable a line made by `read_line` reads.
    pub of_line: fn(&str) -> Option<u8>,
    /// A number typed at the prompt, or why it is none.
    pub parse: fn(&str) -> Result<u8, NoSuchVariable>,
    /// How messages name variable `n` ("user variable #5", "V5").
    pub name: fn(u8) -> String,
}

/// A number typed at a variable prompt that names no variable of the set:
/// the set's own words, its numbers, and what was typed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{set} {numbers}, not `{typed}`")]
pub struct NoSuchVariable {
    /// "user variables are numbered", "TR reads registers".
    pub set: &'static str,
    /// "0..255", "V0..V99".
    pub numbers: &'static str,
    pub typed: String,
}

/// Why a stored program could not be deleted, or the listing after a
/// deletion is not what was kept. `noun` is the store's word for one
/// program ("macro"), `list_line` the line that lists them (`TM-1`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum StoreError {
    #[error(
        "the controller has no {noun} {number} ({list_line} lists {})",
        numbers_or_none(listed)
    )]
    NoSuch {
        noun: &'static str,
        list_line: &'static str,
        number: i64,
        listed: Vec<i64>,
    },
    /// A program that must be written again after the delete would not
    /// be taken as listed.
    #[error("{noun} {number} as listed cannot be defined again ({why}): nothing was erased")]
    CannotRewrite {
        noun: &'static str,
        number: i64,
        why: String,
    },
    #[error("the controller lists {noun}s {listed:?}, {kept:?} were meant to stay")]
    OtherNumbers {
        noun: &'static str,
        listed: Vec<i64>,
        kept: Vec<i64>,
    },
    #[error("{noun} {number}: {why}")]
    OtherText {
        noun: &'static str,
        number: i64,
        why: String,
    },
}

fn numbers_or_none(numbers: &[i64]) -> String {
    if numbers.is_empty() {
        "none".to_string()
    } else {
        numbers
            .iter()
            .map(i64::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// What a program's state is read into.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StateSlot {
    /// Running, stopped… (TMCL GP128, A-Script SASTAT).
    Mode,
    /// The program counter (TMCL GP130, A-Script SPC).
    Counter,
    /// Another register, by its name ("ACC").
    Register(&'static str),
}

/// One line that reads part of a program's state.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StateRead {
    pub line: String,
    pub slot: StateSlot,
}

/// A control key of the editor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ControlKey {
    Run,
    Stop,
    Step,
    Reset,
}

/// What a control key sends.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Control {
    pub line: String,
    /// Keep reading the program's state while it runs.
    pub watch: bool,
    /// What it does to the program, for a message ("start"), where the
    /// tool says.
    pub verb: Option<&'static str>,
}

/// Where a program counter's source line can be known.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CounterMap {
    /// Always: the counter is an address of the built image.
    Always,
    /// Only for a text this console loaded into the simulator (the
    /// controller's compiled lines map to no documented source line).
    WhenLoadedHere,
}

/// Run control of a program in the controller and what is read back
/// while it runs.
pub trait ProgramControl: Send + Sync {
    /// The line a control key sends to program `target`, given its mode
    /// as last read.
    fn control(&self, key: ControlKey, target: u8, mode: Option<i64>) -> Control;
    /// The lines that read program `target`'s state.
    fn state_reads(&self, target: u8) -> Vec<StateRead>;
    /// A mode's name ("running").
    fn mode_name(&self, mode: i64) -> &'static str;
    /// Whether a program in `mode` is still worth reading again.
    fn keeps_running(&self, mode: i64) -> bool;
    /// What the counter is called ("PC").
    fn counter_name(&self) -> &'static str;
    /// How messages name program `target` (`PRG 0`), where the controller
    /// has several.
    fn program_name(&self, target: u8) -> Option<String> {
        let _ = target;
        None
    }
    fn counter_map(&self) -> CounterMap {
        CounterMap::Always
    }
    /// Whether the line the program stopped at stays marked.
    fn marks_where_stopped(&self) -> bool {
        true
    }
}

/// What a family offers for its standalone programs. One per family that
/// has programs, from [`super::console::FamilyConsole::program`].
pub trait ProgramTool: Send + Sync {
    /// The language's name ("TMCL", "A-Script").
    fn name(&self) -> &'static str;
    /// The controllers that run it, as messages name them ("CMD-4CR").
    fn controller(&self) -> &'static str;
    /// File extensions, lower case without the dot; the first names an
    /// untitled buffer.
    fn extensions(&self) -> &'static [&'static str];
    /// How the check's outcome reads.
    fn wording(&self) -> Wording {
        Wording {
            passes: "checks",
            pass: "check",
        }
    }
    /// What one unit of a stored program is called ("word").
    fn unit(&self) -> &'static str {
        "word"
    }
    /// Check the source `source` called `name`, reading what it includes
    /// through `files`.
    fn check(&self, name: &str, source: &str, files: &dyn SourceLoader) -> Checked;
    /// The classes of each line in `shown` of `lines` (the whole text:
    /// a label declared anywhere colours its uses), byte ranges covering
    /// each line.
    fn highlight(
        &self,
        lines: &[String],
        shown: Range<usize>,
    ) -> Vec<Vec<(Range<usize>, SyntaxClass)>>;
    /// What each line in `shown` of `lines` says in words, for an editor
    /// to show beside it (SQPack macros: the command a frame of nine hex
    /// bytes is), `None` for a line with nothing to add. None by default.
    fn annotations(&self, lines: &[String], shown: Range<usize>) -> Vec<Option<String>> {
        lines
            .get(shown)
            .unwrap_or_default()
            .iter()
            .map(|_| None)
            .collect()
    }

    /// The program line that sends the request `bytes` again, for a
    /// console that records what it sends as a program (SQPack's "Record
    /// Macro", §5.4.6); `None` when the language cannot say it.
    fn record(&self, bytes: &[u8]) -> Option<String> {
        let _ = bytes;
        None
    }

    /// The variable line `text` names at byte `column`, read from the line
    /// alone (when the whole does not check).
    fn variable_on_line(&self, text: &str, column: usize) -> Option<u8> {
        let _ = (text, column);
        None
    }
    /// The variables a console can watch, if any.
    fn variables(&self) -> Option<&'static VariableSet> {
        None
    }
    /// Run control of a program in the controller, if the family has it.
    fn control(&self) -> Option<&'static dyn ProgramControl> {
        None
    }
    /// How a checked program reaches the controller.
    fn download_way(&self) -> DownloadWay {
        DownloadWay::Wire
    }
    /// Read the program of the module at `address` back.
    fn upload(
        &self,
        address: u8,
        extent: UploadExtent,
    ) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        let _ = (address, extent);
        Err(TransferFailure::refused(format!(
            "{} programs cannot be read back from the controller",
            self.name()
        )))
    }
    /// A program image file (`axterm asm -o`) as a program to download.
    fn load_image(
        &self,
        name: &str,
        text: &str,
    ) -> Option<Result<Arc<dyn CheckedProgram>, Vec<String>>> {
        let _ = (name, text);
        None
    }
    /// The source of the program image file `name`, if the tool has
    /// images; its problems as `NAME:LINE: …`.
    fn disassemble(&self, name: &str, image: &str) -> Option<Result<String, Vec<String>>> {
        let _ = (name, image);
        None
    }
    /// What the controller keeps besides the program in the editor and
    /// runs in the background, for a console to list, delete and stop
    /// (MCCL macros and tasks); `None` if nothing.
    fn store(&self) -> Option<&'static dyn ProgramStore> {
        None
    }
    /// Whether programs of this language run from the host
    /// ([`ProgramTool::host_run`]).
    fn runs_from_host(&self) -> bool {
        false
    }

    /// The command that runs programs of this language from the host
    /// (`run-ascript`: `axterm run-ascript` and the console's
    /// `:run-ascript`), if they run from the host.
    fn host_command(&self) -> Option<&'static str> {
        None
    }
    /// Check `source` for a run from the host and start it, the programs
    /// `start` (all when `None`); `None` when the language has no host
    /// run. Every problem is listed as `NAME:LINE: …`; nothing may be sent
    /// when there is one.
    fn host_run(
        &self,
        name: &str,
        source: &str,
        start: Option<&[u8]>,
    ) -> Option<Result<HostStart, Vec<String>>> {
        let _ = (name, source, start);
        None
    }
}

impl fmt::Debug for dyn ProgramTool {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "ProgramTool({})", self.name())
    }
}

/// A program stored in the controller, as it lists it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StoredProgram {
    pub number: i64,
    /// Its text as the controller lists it.
    pub text: String,
}

/// How a stored program is deleted where the controller cannot delete
/// one alone (MCCL: `RM` erases every macro, Ch10).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Deletion {
    /// What the user must know before it is done.
    pub warning: String,
    /// The console lines that do it, in order.
    pub lines: Vec<String>,
    /// What the listing must show afterwards.
    pub kept: Vec<StoredProgram>,
}

/// The programs a controller keeps besides the one in the editor (MCCL
/// macros, Ch10) and those it runs in the background (MCCL tasks): the
/// console lines that list, delete and stop them and how their answers
/// read. Pure: a console sends the lines and hands the answers back.
pub trait ProgramStore: Send + Sync {
    /// What one stored program is called ("macro").
    fn stored_noun(&self) -> &'static str;
    /// The line that lists every stored program (MCCL `TM-1`).
    fn list_line(&self) -> String;
    /// The stored programs in the answer to [`ProgramStore::list_line`].
    fn stored(&self, listing: &ReplyValue) -> Vec<StoredProgram>;
    /// How to delete stored program `number` out of `listing` and keep
    /// the others; why not, if it cannot be.
    fn delete(&self, listing: &[StoredProgram], number: i64) -> Result<Deletion, StoreError>;
    /// Whether `listing` (read after a [`Deletion`]) holds exactly what it
    /// kept; what differs if not.
    fn compare(&self, kept: &[StoredProgram], listing: &[StoredProgram]) -> Result<(), StoreError>;
    /// What one running program is called ("background task").
    fn running_noun(&self) -> &'static str;
    /// The line that lists the programs running in the background (MCCL
    /// `ID7`), if the controller has one.
    fn running_line(&self) -> Option<String>;
    /// Their IDs in its answer.
    fn running(&self, answer: &ReplyValue) -> Vec<i64>;
    /// The line that stops running program `id` (MCCL `ETn`).
    fn stop_line(&self, id: i64) -> String;
}

/// The name a buffer of `tool` without a file goes by (`untitled.tmc`).
pub fn untitled(tool: &dyn ProgramTool) -> String {
    match tool.extensions().first() {
        Some(extension) => format!("untitled.{extension}"),
        None => "untitled".to_string(),
    }
}

/// Whether `path`'s extension is one of `tool`'s.
pub fn is_file_of(tool: &dyn ProgramTool, path: &std::path::Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| tool.extensions().iter().any(|x| x.eq_ignore_ascii_case(e)))
}

/// A transfer the console or the command line asks for; the session makes
/// its plan for the module it talks to.
#[derive(Debug, Clone)]
pub enum TransferJob {
    /// Store the program and verify it.
    Download {
        program: Arc<dyn CheckedProgram>,
        options: DownloadOptions,
    },
    /// Compare the module's program with this one, storing nothing.
    Verify { program: Arc<dyn CheckedProgram> },
    /// Read the module's program back.
    Upload(UploadExtent),
}

impl TransferJob {
    /// "download", "verify", "upload".
    pub fn name(&self) -> &'static str {
        match self {
            TransferJob::Download { .. } => "download",
            TransferJob::Verify { .. } => "verify",
            TransferJob::Upload(_) => "upload",
        }
    }

    /// The program sent or compared with, if any.
    pub fn program(&self) -> Option<&Arc<dyn CheckedProgram>> {
        match self {
            TransferJob::Download { program, .. } | TransferJob::Verify { program } => {
                Some(program)
            }
            TransferJob::Upload(_) => None,
        }
    }
}

/// Jobs are the same when they move the same program (the very same
/// check) the same way.
impl PartialEq for TransferJob {
    fn eq(&self, other: &TransferJob) -> bool {
        let same = |a: &Arc<dyn CheckedProgram>, b: &Arc<dyn CheckedProgram>| {
            std::ptr::addr_eq(Arc::as_ptr(a), Arc::as_ptr(b))
        };
        match (self, other) {
            (
                TransferJob::Download { program, options },
                TransferJob::Download {
                    program: p,
                    options: o,
                },
            ) => same(program, p) && options == o,
            (TransferJob::Verify { program }, TransferJob::Verify { program: p }) => {
                same(program, p)
            }
            (TransferJob::Upload(a), TransferJob::Upload(b)) => a == b,
            _ => false,
        }
    }
}

/// What came back for a line a plan or a host run sent.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Answer {
    /// The line as the family writes it.
    pub line: String,
    /// The answer's frames, in order (none if none came).
    pub frames: Vec<Frame>,
    pub result: Result<Reading, AnswerError>,
}

/// Why a line brought no success.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AnswerError {
    /// Refused before sending: the message.
    Refused(String),
    /// The module's answer is an error, or unreadable.
    Reply(ReplyError),
    /// Nothing came from module `address`: the device's reason ("no reply
    /// within 202 ms").
    Lost { address: u8, reason: String },
}

impl Answer {
    /// The error as the session says it, if the line failed.
    pub fn error_text(&self) -> Option<String> {
        match &self.result {
            Ok(_) => None,
            Err(AnswerError::Refused(message)) => Some(message.clone()),
            Err(AnswerError::Reply(error)) => Some(error.to_string()),
            Err(AnswerError::Lost { address, reason }) => Some(format!(
                "module {address} did not answer {}: {reason}",
                self.line
            )),
        }
    }

    /// The last frame, as a TMCL reply is judged.
    pub fn last_frame(&self) -> &[u8] {
        self.frames.last().map(Vec::as_slice).unwrap_or_default()
    }
}

/// What a transfer is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Download: storing.
    Storing,
    /// Download or verify: reading back and comparing.
    Verifying,
    /// Upload: reading the program.
    Reading,
}

impl Phase {
    pub fn name(self) -> &'static str {
        match self {
            Phase::Storing => "storing",
            Phase::Verifying => "verifying",
            Phase::Reading => "reading",
        }
    }
}

/// How far a transfer has come: after each unit, and at the start of each
/// phase (`done` 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progress {
    pub phase: Phase,
    /// Units done in this phase.
    pub done: usize,
    /// Units this phase will take; `None` when an upload reads until the
    /// first blank unit.
    pub total: Option<usize>,
}

/// What to do after a verified download.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DownloadOptions {
    /// Start the program.
    pub run: bool,
    /// Make the module start the program at power-up.
    pub autostart: bool,
}

/// The plan that stores `program` in the module at `address`: every
/// download goes through here. A program with no unit in it (an empty
/// file, or only comments and blank lines) is refused before anything is
/// sent: storing nothing and reading nothing back would read as a
/// verified download.
pub fn download_plan(
    program: &dyn CheckedProgram,
    address: u8,
    options: DownloadOptions,
) -> Result<Box<dyn TransferPlan>, TransferFailure> {
    if program.size() == 0 {
        return Err(TransferFailure::refused(
            "the program holds nothing to download (the file is empty, or only comments and \
             blank lines)",
        ));
    }
    program.download(address, options)
}

/// Where an upload stops (a module need not know its program's length).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UploadExtent {
    /// At the first blank unit (or the end of memory).
    #[default]
    UntilBlank,
    /// After this many units (at most the memory's size).
    Units(usize),
    /// The whole memory, trailing blank units dropped.
    All,
}

/// A line a plan sends.
#[derive(Debug, Clone)]
pub struct PlanLine {
    pub line: PreparedLine,
    /// Send it at polling priority, after every poll already on its way
    /// (TMCL reads GP128 so before download mode: none can be stored).
    pub after_polls: bool,
}

impl PlanLine {
    pub fn new(line: PreparedLine) -> PlanLine {
        PlanLine {
            line,
            after_polls: false,
        }
    }
}

/// What a plan wants next.
#[derive(Debug)]
pub enum PlanStep {
    /// Send this line; [`TransferPlan::answer`] takes its answer.
    Send(PlanLine),
    /// Done: what it did (the runner fills in the time and counts).
    Done(TransferReport),
    Failed(TransferFailure),
}

/// A module held in a mode in which it misreads other lines (TMCL
/// download mode stores them as program words, §3.6.53): while a plan
/// holds it, the session refuses user lines the hold does not admit, stops
/// polling, and an emergency stop waits for the line on the wire and the
/// plan's way out, or sends [`ModuleHold::release`] first.
pub trait ModuleHold: Send + Sync + fmt::Debug {
    /// Why `line` must not be sent now; `None` if the module executes it
    /// even while held.
    fn refusal(&self, line: &PreparedLine) -> Option<String>;
    /// The line that lets the module go (TMCL 133), if it must be sent:
    /// `None` while the mode is not entered yet. A user line with these
    /// very bytes that succeeds ends the hold too.
    fn release(&self) -> Option<PreparedLine>;
}

/// How a program's text reaches the controller, or comes back: a pure
/// state machine of prepared lines and their answers. The session's
/// runner asks [`TransferPlan::next`], sends the line at transfer
/// priority, hands the answer to [`TransferPlan::answer`], and so on until
/// it is done or failed.
pub trait TransferPlan: Send {
    /// What to do next.
    fn next(&mut self) -> PlanStep;
    /// The answer to the line of the last [`PlanStep::Send`].
    fn answer(&mut self, answer: Answer);
    /// Stop at the next line: the plan winds down (TMCL leaves download
    /// mode) and then fails as cancelled.
    fn cancel(&mut self);
    /// How far it has come.
    fn progress(&self) -> Option<Progress>;
    /// The hold the plan has on the module before its next line, if any.
    fn hold(&self) -> Option<Arc<dyn ModuleHold>> {
        None
    }
}

/// A fact a finished transfer reports beside its count.
#[derive(Debug, Clone, PartialEq)]
pub struct Fact {
    /// Its key in machine-readable output ("leftover_from").
    pub key: &'static str,
    pub value: FactValue,
    /// Said in the console's one-line message ("; words from 12 on still
    /// hold an earlier program"), if worth saying there.
    pub said: Option<String>,
    /// Told on the command line, if worth telling there.
    pub told: Option<Told>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum FactValue {
    Flag(bool),
    Number(u64),
    Text(String),
    /// Nothing to say (`null`).
    Absent,
}

/// A line for the command line's report.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Told {
    pub text: String,
    /// A note (standard error) rather than the report (standard output).
    pub note: bool,
}

/// A program read from the controller.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadProgram {
    /// As source (TMCL: disassembled).
    pub source: String,
    /// As an image file, if the tool has images.
    pub image: Option<String>,
    /// Units read.
    pub units: usize,
}

/// What a finished transfer did. A download's report exists only when it
/// was verified.
#[derive(Debug, Clone, PartialEq)]
pub struct TransferReport {
    pub module: u8,
    /// Units stored and verified, compared, or read.
    pub count: usize,
    pub facts: Vec<Fact>,
    /// An upload's program.
    pub program: Option<ReadProgram>,
    /// From the first line sent to the last answer (the runner's).
    pub elapsed: Duration,
    /// Lines exchanged (the runner's).
    pub transactions: u64,
    /// Bytes both ways (the runner's).
    pub wire_bytes: u64,
}

impl TransferReport {
    pub fn new(module: u8, count: usize) -> TransferReport {
        TransferReport {
            module,
            count,
            facts: Vec::new(),
            program: None,
            elapsed: Duration::ZERO,
            transactions: 0,
            wire_bytes: 0,
        }
    }

    /// The fact under `key`.
    pub fn fact(&self, key: &str) -> Option<&FactValue> {
        self.facts.iter().find(|f| f.key == key).map(|f| &f.value)
    }

    /// The wire time of every byte exchanged at `byte_time` per byte: no
    /// transfer over that line can be faster.
    pub fn wire_time(&self, byte_time: Duration) -> Duration {
        byte_time.saturating_mul(u32::try_from(self.wire_bytes).unwrap_or(u32::MAX))
    }

    /// The transfer's speed as a share of the wire's limit.
    pub fn wire_share(&self, byte_time: Duration) -> f64 {
        if self.elapsed.is_zero() {
            return 1.0;
        }
        self.wire_time(byte_time).as_secs_f64() / self.elapsed.as_secs_f64()
    }
}

/// What kind of failure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FailureKind {
    /// Refused before anything was sent.
    Refused,
    /// Another transfer runs on this connection (nothing sent).
    Busy,
    /// Cancelled (by its owner or an emergency stop) at this point.
    Cancelled(Progress),
    /// The module refused, did not answer, or what came back differs.
    Failed,
}

/// Why a transfer failed. A download that fails is never verified.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct TransferFailure {
    pub kind: FailureKind,
    /// The whole story.
    pub message: String,
    /// How the console's one line says it, where it differs.
    pub said: Option<String>,
    /// The program unit (TMCL: address) the failure is about.
    pub at: Option<usize>,
}

impl TransferFailure {
    pub fn refused(message: impl Into<String>) -> TransferFailure {
        TransferFailure {
            kind: FailureKind::Refused,
            message: message.into(),
            said: None,
            at: None,
        }
    }

    pub fn busy() -> TransferFailure {
        TransferFailure {
            kind: FailureKind::Busy,
            message: "another program transfer is running on this connection".into(),
            said: None,
            at: None,
        }
    }

    pub fn failed(message: impl Into<String>, at: Option<usize>) -> TransferFailure {
        TransferFailure {
            kind: FailureKind::Failed,
            message: message.into(),
            said: None,
            at,
        }
    }

    /// True when nothing was sent.
    pub fn nothing_sent(&self) -> bool {
        matches!(self.kind, FailureKind::Refused | FailureKind::Busy)
    }

    /// The program unit the failure is about.
    pub fn address(&self) -> Option<usize> {
        self.at
    }

    /// Where it was cancelled, if it was.
    pub fn cancelled(&self) -> Option<Progress> {
        match self.kind {
            FailureKind::Cancelled(progress) => Some(progress),
            _ => None,
        }
    }

    /// The console's one line.
    pub fn console_text(&self) -> &str {
        self.said.as_deref().unwrap_or(&self.message)
    }
}

/// A program checked for a run from the host, and started.
#[derive(Debug)]
pub struct HostStart {
    pub run: Box<dyn HostRun>,
    /// The file's name, for messages.
    pub name: String,
    /// What compiles but is likely not meant, as `NAME:LINE: warning: …`.
    pub warnings: Vec<String>,
    /// Which programs start ("PRG 0 and PRG 2").
    pub started: String,
    /// The lines the family wants confirmed before they are sent
    /// ([`super::console::FamilyConsole::confirmation`]), as `NAME:LINE:
    /// `line`: why`: the console asks before the run starts, the command
    /// line needs `--yes`.
    pub confirm: Vec<String>,
}

/// What a host run needs done next.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum HostStep {
    /// Send this console line; [`HostRun::on_answer`] takes its answer.
    Send(String),
    /// Call [`HostRun::on_wake`] after this long.
    Wake(Duration),
    /// The run is over.
    Finished(HostEnd),
}

/// How a host run ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HostEnd {
    /// Every program ran to its end.
    pub ok: bool,
    /// How, in words.
    pub summary: String,
}

impl fmt::Display for HostEnd {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.summary)
    }
}

/// How a piece of news of a host run should stand out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tone {
    /// A program started, ended or was controlled.
    Headline,
    /// A statement sent and its answer.
    Plain,
    /// Something routine worth a glance.
    Minor,
    Warning,
    Error,
}

/// Something worth telling the user of a host run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HostNews {
    pub tone: Tone,
    pub text: String,
}

/// Where a program of a host run stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlaceState {
    Idle,
    Running,
    Paused,
    /// Stopped by a runtime error.
    Error,
}

/// A program's place in a host run, for a console that marks its line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunningPlace {
    pub program: u8,
    pub state: PlaceState,
    /// The source line (1-based) of the statement it is at.
    pub line: usize,
}

/// A program run from the host, statement by statement: a plain state
/// machine with no I/O and no clock of its own (`now` is the time since
/// the run began). Dropping it ends the run: nothing more is sent.
pub trait HostRun: Send + fmt::Debug {
    /// The first step.
    fn start(&mut self, now: Duration) -> HostStep;
    /// The answer to the last [`HostStep::Send`].
    fn on_answer(&mut self, answer: &Answer, now: Duration) -> HostStep;
    /// A [`HostStep::Wake`] came due.
    fn on_wake(&mut self, now: Duration) -> HostStep;
    /// The news since the last call, oldest first.
    fn take_news(&mut self) -> Vec<HostNews>;
    /// Every program of the source, with its state and line.
    fn places(&self) -> Vec<RunningPlace>;
    /// The variables as the host holds them.
    fn variables(&self) -> &[i32];
    /// How messages name program `program` of the run ("PRG 0").
    fn place_name(&self, program: u8) -> String {
        format!("program {program}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::FAMILIES;

    #[test]
    fn no_family_downloads_an_empty_program() {
        let mut tried = 0;
        for family in FAMILIES {
            let Some(tool) = family.console.program() else {
                continue;
            };
            if tool.download_way() != DownloadWay::Wire {
                continue;
            }
            for source in ["", "\n\n"] {
                let checked = tool.check("empty", source, &NoIncludes);
                // A tool may refuse it as a source already; one that
                // checks it must not make a download of it.
                let Some(program) = checked.program else {
                    continue;
                };
                tried += 1;
                let address = family.console.default_address();
                let Err(refused) =
                    download_plan(program.as_ref(), address, DownloadOptions::default())
                else {
                    panic!("{}: a download of nothing was planned", family.name);
                };
                assert!(refused.nothing_sent(), "{}: {refused}", family.name);
                assert!(
                    refused.to_string().contains("holds nothing to download"),
                    "{}: {refused}",
                    family.name
                );
            }
        }
        assert!(tried > 0, "no family's tool checked an empty source");
    }
}
