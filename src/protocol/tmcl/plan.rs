//! The TMCL program transfers as plans ([`TransferPlan`]): download a
//! program image and verify every word by reading it back, compare the
//! module's program with an image, read a program back (upload). Pure
//! state machines: the session's runner sends the lines they give at
//! transfer priority and hands them the answers.
//!
//! # A download (§3.6.53, digest D10.2)
//!
//! 1. Every word is checked first ([`transfer::check_image`]): nothing is
//!    sent for an image with a control command or an empty word in it.
//! 2. The plan holds the module from the start ([`DownloadHold`]): polling
//!    is paused and user lines that the module would store are refused;
//!    GP128 (application status) is read at poll priority, so that it goes
//!    only after every poll already on its way: none can reach the module
//!    in download mode and be stored as a word.
//! 3. 131 "reset application": a running program is stopped (the report
//!    says it was running), its program counter, stack, A, X and flags
//!    cleared, so that the new program starts at 0 (129 type 0, or GP77
//!    autostart) instead of at the old one's program counter. Decision: a
//!    download stops a running program rather than refusing; downloading
//!    is asking to replace it, and what a module does with a program that
//!    runs while its memory is rewritten is not documented.
//! 4. 132 with start address 0, every word in address order, each answer
//!    checked for status 101 "loaded into EEPROM" (100 would mean it was
//!    executed), 133. Words are never sent twice: a word without an answer
//!    fails the download.
//! 5. Verification: every word is read back with 134 and compared; the
//!    first difference fails the download with its address. The word after
//!    the program is read too: an older, longer program leaves its tail
//!    there (the manual has no erase command), and the report says so,
//!    because an upload reads until the first empty word.
//! 6. `autostart`: `SGP 77, 0, 1` (GP77 is stored by SGP itself, access
//!    RWA, §5.1, §8.7), read back with GGP 77. `run`: 129 type 0.
//!
//! A download is done only when verified: every failure, cancellation
//! included, is an error, and the report exists only for a verified one.
//!
//! # While the module is in download mode
//!
//! It stores whatever is not a control command instead of executing it,
//! so the hold refuses user lines other than 133–136, and an emergency
//! stop waits for the word on the wire, after which the plan leaves
//! download mode itself (two transactions in all); if that failed, the
//! stop sends 133 first. Its MST is never stored as a program word.
//! Anything that slipped through anyway (a line racing the start of a
//! download on another thread) is caught by the verification.
//!
//! # Cancellation
//!
//! [`TransferPlan::cancel`] stops a transfer between two words: a download
//! leaves download mode and fails as cancelled (its words are partly
//! stored, not verified).
//!
//! # An upload
//!
//! The module does not know how long its program is. [`UploadExtent`]
//! says where to stop: at the first blank word (all zeros, as the simulator
//! erases; or all 0xFF, as erased EEPROM reads on most parts), after a
//! given number of words, or at the end of memory with trailing blank
//! words dropped.

use std::sync::Arc;

use super::TmclConsole;
use super::asm::{PROGRAM_MEMORY_WORDS, ProgramWord, disassemble, format_image};
use super::command::{Command, opcode};
use super::line::format_command;
use super::transfer::{
    self, ApplicationState, ReadBackProblem, StoreProblem, Unstorable, commands, show_word,
};
use super::wire::TmclReplyRule;
use crate::protocol::console::{Answering, Effect, PreparedLine, ReplyValue};
use crate::protocol::program::{
    Answer, AnswerError, DownloadOptions, Fact, FactValue, FailureKind, ModuleHold, Phase,
    PlanLine, PlanStep, Progress, ReadProgram, Told, TransferFailure, TransferPlan, TransferReport,
    UploadExtent,
};

/// Why a TMCL transfer failed, in the words of its messages.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TransferError {
    #[error("{0}; nothing was sent")]
    Unstorable(Unstorable),
    /// A control step failed: reading the application status, reset,
    /// entering or leaving download mode, autostart, run.
    #[error("cannot {step}: {error}{hint}")]
    Step {
        step: &'static str,
        /// What the session said of the line.
        error: String,
        /// What the status means here (a protection setting), or empty.
        hint: String,
    },
    #[error(
        "module {module} did not store word {address}, {word}: {problem}; \
         the download stopped there"
    )]
    NotStored {
        module: u8,
        address: usize,
        word: String,
        problem: StoreProblem,
    },
    #[error(
        "module {module} did not answer word {address}, {word}: {error}; the download \
         stopped there (the word may or may not be stored)"
    )]
    StoreUnanswered {
        module: u8,
        address: usize,
        word: String,
        error: String,
    },
    #[error("cannot read word {address} from module {module}: {problem}")]
    ReadBack {
        module: u8,
        address: usize,
        problem: ReadBackProblem,
    },
    #[error("cannot read word {address}: module {module} did not answer: {error}")]
    ReadUnanswered {
        module: u8,
        address: usize,
        error: String,
    },
    #[error("word {address} differs: wrote {}, read {}", show_word(*.wrote), show_word(*.read))]
    Mismatch {
        address: usize,
        wrote: ProgramWord,
        read: ProgramWord,
    },
    /// Verify: the module's word against the source's.
    #[error(
        "word {address} differs: module {module} holds {}, the source has {}",
        format_command(&.held.command()),
        format_command(&.expected.command())
    )]
    Differs {
        module: u8,
        address: usize,
        held: ProgramWord,
        /// The source's word.
        expected: ProgramWord,
    },
    #[error("{}", cancelled(*.phase, *.done, *.total))]
    Cancelled {
        phase: Phase,
        done: usize,
        total: Option<usize>,
    },
    #[error(
        "{cause}; leaving download mode failed too ({exit}): the module may still store what \
         it is sent instead of executing it: send ENDDOWNLOAD"
    )]
    Stranded {
        cause: Box<TransferError>,
        exit: String,
    },
}

fn cancelled(phase: Phase, done: usize, total: Option<usize>) -> String {
    let of = total.map_or(String::new(), |t| format!(" of {t}"));
    match phase {
        Phase::Storing => format!(
            "cancelled after storing {done}{of} words: download mode was left, the program \
             in the module is incomplete"
        ),
        Phase::Verifying => format!(
            "cancelled after verifying {done}{of} words: the program was stored but is not \
             verified"
        ),
        Phase::Reading => format!("cancelled after reading {done}{of} words"),
    }
}

impl TransferError {
    /// The program address the failure is about, if any.
    pub fn address(&self) -> Option<usize> {
        match self {
            TransferError::Unstorable(u) => Some(u.address),
            TransferError::NotStored { address, .. }
            | TransferError::StoreUnanswered { address, .. }
            | TransferError::ReadBack { address, .. }
            | TransferError::ReadUnanswered { address, .. }
            | TransferError::Mismatch { address, .. }
            | TransferError::Differs { address, .. } => Some(*address),
            TransferError::Stranded { cause, .. } => cause.address(),
            _ => None,
        }
    }
}

impl From<TransferError> for TransferFailure {
    fn from(error: TransferError) -> TransferFailure {
        let kind = match &error {
            TransferError::Unstorable(_) => FailureKind::Refused,
            TransferError::Cancelled { phase, done, total } => FailureKind::Cancelled(Progress {
                phase: *phase,
                done: *done,
                total: *total,
            }),
            _ => FailureKind::Failed,
        };
        // The console's line says what a cancelled download left behind.
        let said = match &error {
            TransferError::Cancelled {
                phase: Phase::Storing,
                done,
                total,
            } => {
                let of = total.map_or_else(String::new, |t| format!(" of {t}"));
                Some(format!(
                    "cancelled: the module left download mode; the program in it is \
                     incomplete ({done}{of} words stored)"
                ))
            }
            _ => None,
        };
        TransferFailure {
            kind,
            message: error.to_string(),
            said,
            at: error.address(),
        }
    }
}

/// Download mode as a hold on the module (see the module documentation).
#[derive(Debug, Clone)]
pub struct DownloadHold {
    module: u8,
    /// 132 was sent: 133 is needed to leave.
    entered: bool,
}

impl ModuleHold for DownloadHold {
    /// 133 (leave download mode) and the reads 134–136 are executed in
    /// download mode (§3.6.53); everything else would be stored.
    fn refusal(&self, line: &PreparedLine) -> Option<String> {
        let command = line.bytes.get(1).copied();
        let allowed = [
            opcode::EXIT_DOWNLOAD,
            opcode::READ_MEMORY,
            opcode::APPLICATION_STATUS,
            opcode::FIRMWARE_VERSION,
        ];
        if command.is_some_and(|c| allowed.contains(&c)) {
            return None;
        }
        Some(format!(
            "module {} is in download mode for a program download: it would store {} instead \
             of executing it; wait for the download or cancel it (ENDDOWNLOAD leaves download \
             mode)",
            line.address, line.canonical
        ))
    }

    fn release(&self) -> Option<PreparedLine> {
        self.entered
            .then(|| TmclConsole.prepare_command(&commands::exit_download(), self.module))
    }
}

/// What a control line is for, and how its failure reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Control {
    ReadState,
    Reset,
    Enter,
    Leave,
    SetAutostart,
    ReadAutostart,
    Run,
}

impl Control {
    fn step(self) -> &'static str {
        match self {
            Control::ReadState => "read the application status (GP128)",
            Control::Reset => "reset the application (131)",
            Control::Enter => "enter download mode (132)",
            Control::Leave => "leave download mode (133)",
            Control::SetAutostart => "switch autostart on (SGP 77, 0, 1)",
            Control::ReadAutostart => "read autostart back (GGP 77, 0)",
            Control::Run => "start the program (129)",
        }
    }

    fn command(self) -> Command {
        match self {
            Control::ReadState => commands::application_state(),
            Control::Reset => commands::reset_application(),
            Control::Enter => commands::enter_download(0),
            Control::Leave => commands::exit_download(),
            Control::SetAutostart => commands::set_autostart(true),
            Control::ReadAutostart => commands::autostart(),
            Control::Run => commands::run_application(),
        }
    }
}

/// The value a control line's answer carries, or the step's error.
fn control_value(control: Control, answer: &Answer) -> Result<ReplyValue, TransferError> {
    match &answer.result {
        Ok(reading) => Ok(reading.value.clone()),
        Err(error) => {
            let status = match error {
                AnswerError::Reply(reply) => reply.status(),
                _ => None,
            };
            let hint = match (control, status) {
                (Control::Enter, Some(5)) => {
                    "; GP81 code protection 2 or 3 forbids overwriting the program (§5.1)".into()
                }
                _ => String::new(),
            };
            Err(TransferError::Step {
                step: control.step(),
                error: answer.error_text().unwrap_or_default(),
                hint,
            })
        }
    }
}

/// Where a download stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stage {
    ReadState,
    Reset,
    Enter,
    /// Storing the word at this address.
    Store(usize),
    Leave,
    /// Reading the word at this address back.
    Verify(usize),
    /// The word after the program.
    After,
    SetAutostart,
    ReadAutostart,
    Run,
    Over,
}

/// A download: store every word in download mode, verify every word,
/// then autostart and run as asked (see the module documentation).
#[derive(Debug)]
pub struct DownloadPlan {
    module: u8,
    words: Vec<ProgramWord>,
    options: DownloadOptions,
    stage: Stage,
    /// The module is held in (or on its way into) download mode.
    hold: Option<DownloadHold>,
    cancelled: bool,
    progress: Option<Progress>,
    /// The program's state before the download, if it was executing.
    stopped: Option<ApplicationState>,
    leftover_from: Option<usize>,
    /// Why the download failed while in download mode: reported once
    /// download mode is left.
    cause: Option<TransferError>,
    /// The end.
    end: Option<Result<TransferReport, TransferError>>,
}

impl DownloadPlan {
    /// A download of `words` to the module at `module`; refused (nothing
    /// sent) when a word cannot be stored.
    pub fn new(
        words: &[ProgramWord],
        module: u8,
        options: DownloadOptions,
    ) -> Result<DownloadPlan, TransferFailure> {
        transfer::check_image(words)
            .map_err(|u| TransferFailure::from(TransferError::Unstorable(u)))?;
        Ok(DownloadPlan {
            module,
            words: words.to_vec(),
            options,
            stage: Stage::ReadState,
            hold: Some(DownloadHold {
                module,
                entered: false,
            }),
            cancelled: false,
            progress: None,
            stopped: None,
            leftover_from: None,
            cause: None,
            end: None,
        })
    }

    fn total(&self) -> Option<usize> {
        Some(self.words.len())
    }

    fn control(&self, control: Control) -> PlanStep {
        let line = TmclConsole.prepare_command(&control.command(), self.module);
        PlanStep::Send(PlanLine {
            line,
            after_polls: control == Control::ReadState,
        })
    }

    /// The download failed at `error`: out of download mode first, if in.
    fn fail(&mut self, error: TransferError) {
        match &self.hold {
            Some(hold) if hold.entered => {
                self.cause = Some(error);
                self.stage = Stage::Leave;
            }
            _ => {
                self.hold = None;
                self.finish(Err(error));
            }
        }
    }

    fn finish(&mut self, end: Result<TransferReport, TransferError>) {
        self.stage = Stage::Over;
        self.end = Some(end);
    }

    fn cancel_error(&self, phase: Phase, done: usize) -> TransferError {
        TransferError::Cancelled {
            phase,
            done,
            total: self.total(),
        }
    }

    fn report(&self) -> TransferReport {
        let mut report = TransferReport::new(self.module, self.words.len());
        let module = self.module;
        report.facts = vec![
            Fact {
                key: "stopped_program",
                value: self
                    .stopped
                    .map_or(FactValue::Absent, |s| FactValue::Text(s.to_string())),
                said: self.stopped.map(|state| {
                    format!("; the program on module {module} was {state}: stopped and reset first")
                }),
                told: self.stopped.map(|state| Told {
                    text: format!(
                        "the program on the module was {state}: stopped and reset it (131) first"
                    ),
                    note: false,
                }),
            },
            Fact {
                key: "leftover_from",
                value: self
                    .leftover_from
                    .map_or(FactValue::Absent, |f| FactValue::Number(f as u64)),
                said: self.leftover_from.map(|from| {
                    format!(
                        "; words from {from} on still hold an earlier program (an upload shows \
                         them)"
                    )
                }),
                told: self.leftover_from.map(|from| Told {
                    text: format!(
                        "memory from word {from} on still holds words of an earlier program \
                         (there is no erase command); `axterm upload` reads until the first \
                         blank word and shows them unless given --words {from}"
                    ),
                    note: true,
                }),
            },
            Fact {
                key: "autostart",
                value: FactValue::Flag(self.options.autostart),
                said: None,
                told: self.options.autostart.then(|| Told {
                    text: "autostart on: the module starts the program at power-up (GP77 = 1)"
                        .into(),
                    note: false,
                }),
            },
            Fact {
                key: "started",
                value: FactValue::Flag(self.options.run),
                said: None,
                told: self.options.run.then(|| Told {
                    text: "started the program (129)".into(),
                    note: false,
                }),
            },
        ];
        report
    }

    /// After verification: autostart, run, or done.
    fn after_verify(&mut self) {
        if self.options.autostart {
            self.stage = Stage::SetAutostart;
        } else {
            self.start_or_finish();
        }
    }

    fn start_or_finish(&mut self) {
        if !self.options.run {
            let report = self.report();
            self.finish(Ok(report));
            return;
        }
        if self.cancelled {
            let len = self.words.len();
            let error = self.cancel_error(Phase::Verifying, len);
            self.finish(Err(error));
            return;
        }
        self.stage = Stage::Run;
    }

    fn verify_next(&mut self, address: usize) {
        if address < self.words.len() {
            self.stage = Stage::Verify(address);
        } else if self.words.len() >= PROGRAM_MEMORY_WORDS {
            self.after_verify();
        } else {
            self.stage = Stage::After;
        }
    }
}

fn store_line(module: u8, word: ProgramWord) -> PreparedLine {
    let request = transfer::store_request(module, word);
    PreparedLine {
        canonical: format_command(&word.command()),
        address: module,
        bytes: request.to_bytes().to_vec(),
        answering: Answering::Reply(Arc::new(TmclReplyRule::for_request(&request))),
        effect: Effect::Acts,
    }
}

fn read_line(module: u8, address: usize) -> PreparedLine {
    let at = u16::try_from(address).unwrap_or(u16::MAX);
    TmclConsole.prepare_command(&commands::read_memory(at), module)
}

/// The word a 134 answer holds, or why not.
fn read_word(module: u8, address: usize, answer: &Answer) -> Result<ProgramWord, TransferError> {
    if let Err(AnswerError::Lost { reason, .. }) = &answer.result {
        return Err(TransferError::ReadUnanswered {
            module,
            address,
            error: reason.clone(),
        });
    }
    transfer::read_back(module, answer.last_frame()).map_err(|problem| TransferError::ReadBack {
        module,
        address,
        problem,
    })
}

impl TransferPlan for DownloadPlan {
    fn next(&mut self) -> PlanStep {
        if let Some(end) = self.end.take() {
            return match end {
                Ok(report) => PlanStep::Done(report),
                Err(error) => PlanStep::Failed(error.into()),
            };
        }
        match self.stage {
            Stage::ReadState => self.control(Control::ReadState),
            Stage::Reset => self.control(Control::Reset),
            Stage::Enter => {
                // 133 is needed from the moment 132 may have arrived.
                if let Some(hold) = self.hold.as_mut() {
                    hold.entered = true;
                }
                self.control(Control::Enter)
            }
            Stage::Store(address) => {
                if self.cancelled {
                    let error = self.cancel_error(Phase::Storing, address);
                    self.fail(error);
                    return self.next();
                }
                match self.words.get(address) {
                    Some(word) => PlanStep::Send(PlanLine::new(store_line(self.module, *word))),
                    None => {
                        self.stage = Stage::Leave;
                        self.next()
                    }
                }
            }
            Stage::Leave => self.control(Control::Leave),
            Stage::Verify(address) => {
                if self.cancelled {
                    let error = self.cancel_error(Phase::Verifying, address);
                    self.finish(Err(error));
                    return self.next();
                }
                PlanStep::Send(PlanLine::new(read_line(self.module, address)))
            }
            Stage::After => PlanStep::Send(PlanLine::new(read_line(self.module, self.words.len()))),
            Stage::SetAutostart => self.control(Control::SetAutostart),
            Stage::ReadAutostart => self.control(Control::ReadAutostart),
            Stage::Run => self.control(Control::Run),
            // An end already taken: nothing more.
            Stage::Over => PlanStep::Failed(TransferFailure::failed("the download is over", None)),
        }
    }

    fn answer(&mut self, answer: Answer) {
        let module = self.module;
        match self.stage {
            Stage::ReadState => match control_value(Control::ReadState, &answer) {
                Ok(value) => {
                    let state = match value {
                        ReplyValue::Number(n) => ApplicationState::from_gp128(n),
                        _ => ApplicationState::Unknown(-1),
                    };
                    self.stopped = state.is_active().then_some(state);
                    self.stage = Stage::Reset;
                    if self.cancelled {
                        let error = self.cancel_error(Phase::Storing, 0);
                        self.fail(error);
                    }
                }
                Err(error) => self.fail(error),
            },
            Stage::Reset => match control_value(Control::Reset, &answer) {
                Ok(_) => {
                    self.stage = Stage::Enter;
                    if self.cancelled {
                        let error = self.cancel_error(Phase::Storing, 0);
                        self.fail(error);
                    }
                }
                Err(error) => self.fail(error),
            },
            Stage::Enter => match control_value(Control::Enter, &answer) {
                Ok(_) => {
                    self.progress = Some(Progress {
                        phase: Phase::Storing,
                        done: 0,
                        total: self.total(),
                    });
                    self.stage = Stage::Store(0);
                }
                Err(error) => self.fail(error),
            },
            Stage::Store(address) => {
                let word = self.words.get(address).copied().unwrap_or_default();
                let stored = match &answer.result {
                    Err(AnswerError::Lost { reason, .. }) => Err(TransferError::StoreUnanswered {
                        module,
                        address,
                        word: show_word(word),
                        error: reason.clone(),
                    }),
                    _ => transfer::judge_store(answer.last_frame()).map_err(|problem| {
                        TransferError::NotStored {
                            module,
                            address,
                            word: show_word(word),
                            problem,
                        }
                    }),
                };
                match stored {
                    Ok(()) => {
                        self.progress = Some(Progress {
                            phase: Phase::Storing,
                            done: address + 1,
                            total: self.total(),
                        });
                        self.stage = Stage::Store(address + 1);
                    }
                    Err(error) => self.fail(error),
                }
            }
            Stage::Leave => {
                let left = control_value(Control::Leave, &answer);
                let cause = self.cause.take();
                match (cause, left) {
                    (None, Ok(_)) => {
                        self.hold = None;
                        self.progress = Some(Progress {
                            phase: Phase::Verifying,
                            done: 0,
                            total: self.total(),
                        });
                        self.verify_next(0);
                    }
                    (Some(cause), Ok(_)) => {
                        self.hold = None;
                        self.finish(Err(cause));
                    }
                    // Still (maybe) in download mode: the hold stays.
                    (None, Err(_)) => self.finish(Err(TransferError::Step {
                        step: Control::Leave.step(),
                        error: answer.error_text().unwrap_or_default(),
                        hint: "; the module may still store what it is sent instead of \
                               executing it: send ENDDOWNLOAD"
                            .into(),
                    })),
                    (Some(cause), Err(_)) => self.finish(Err(TransferError::Stranded {
                        cause: Box::new(cause),
                        exit: answer.error_text().unwrap_or_default(),
                    })),
                }
            }
            Stage::Verify(address) => match read_word(module, address, &answer) {
                Ok(read) => {
                    let wrote = self.words.get(address).copied().unwrap_or_default();
                    if read != wrote {
                        self.finish(Err(TransferError::Mismatch {
                            address,
                            wrote,
                            read,
                        }));
                        return;
                    }
                    self.progress = Some(Progress {
                        phase: Phase::Verifying,
                        done: address + 1,
                        total: self.total(),
                    });
                    self.verify_next(address + 1);
                }
                Err(error) => self.finish(Err(error)),
            },
            Stage::After => match read_word(module, self.words.len(), &answer) {
                Ok(next) => {
                    self.leftover_from = (!transfer::is_blank(next)).then_some(self.words.len());
                    self.after_verify();
                }
                Err(error) => self.finish(Err(error)),
            },
            Stage::SetAutostart => match control_value(Control::SetAutostart, &answer) {
                Ok(_) => self.stage = Stage::ReadAutostart,
                Err(error) => self.finish(Err(error)),
            },
            Stage::ReadAutostart => match control_value(Control::ReadAutostart, &answer) {
                Ok(ReplyValue::Number(1)) => self.start_or_finish(),
                Ok(value) => self.finish(Err(TransferError::Step {
                    step: "switch autostart on",
                    error: format!("GP77 reads back {value} after SGP 77, 0, 1"),
                    hint: String::new(),
                })),
                Err(error) => self.finish(Err(error)),
            },
            Stage::Run => match control_value(Control::Run, &answer) {
                Ok(_) => {
                    let report = self.report();
                    self.finish(Ok(report));
                }
                Err(error) => self.finish(Err(error)),
            },
            Stage::Over => {}
        }
    }

    fn cancel(&mut self) {
        if self.cancelled {
            return;
        }
        self.cancelled = true;
        // Before 132 was sent: nothing to leave, the download ends at once.
        if matches!(self.stage, Stage::ReadState | Stage::Reset | Stage::Enter)
            && self.hold.as_ref().is_some_and(|h| !h.entered)
        {
            let error = self.cancel_error(Phase::Storing, 0);
            self.fail(error);
        }
    }

    fn progress(&self) -> Option<Progress> {
        self.progress
    }

    fn hold(&self) -> Option<Arc<dyn ModuleHold>> {
        self.hold
            .clone()
            .map(|hold| Arc::new(hold) as Arc<dyn ModuleHold>)
    }
}

/// Read the module's words and compare them with a program's, storing
/// nothing: the first difference fails it with its address.
#[derive(Debug)]
pub struct VerifyPlan {
    module: u8,
    words: Vec<ProgramWord>,
    next: usize,
    cancelled: bool,
    progress: Progress,
    end: Option<Result<TransferReport, TransferError>>,
}

impl VerifyPlan {
    pub fn new(words: &[ProgramWord], module: u8) -> VerifyPlan {
        let total = words.len().min(PROGRAM_MEMORY_WORDS);
        VerifyPlan {
            module,
            words: words.iter().take(total).copied().collect(),
            next: 0,
            cancelled: false,
            progress: Progress {
                phase: Phase::Reading,
                done: 0,
                total: Some(total),
            },
            end: None,
        }
    }
}

impl TransferPlan for VerifyPlan {
    fn next(&mut self) -> PlanStep {
        if let Some(end) = self.end.take() {
            return match end {
                Ok(report) => PlanStep::Done(report),
                Err(error) => PlanStep::Failed(error.into()),
            };
        }
        if self.cancelled {
            return PlanStep::Failed(
                TransferError::Cancelled {
                    phase: Phase::Reading,
                    done: self.next,
                    total: Some(self.words.len()),
                }
                .into(),
            );
        }
        if self.next >= self.words.len() {
            return PlanStep::Done(TransferReport::new(self.module, self.words.len()));
        }
        PlanStep::Send(PlanLine::new(read_line(self.module, self.next)))
    }

    fn answer(&mut self, answer: Answer) {
        let address = self.next;
        match read_word(self.module, address, &answer) {
            Ok(held) => {
                let expected = self.words.get(address).copied().unwrap_or_default();
                if held != expected {
                    self.end = Some(Err(TransferError::Differs {
                        module: self.module,
                        address,
                        held,
                        expected,
                    }));
                    return;
                }
                self.next += 1;
                self.progress.done = self.next;
            }
            Err(error) => self.end = Some(Err(error)),
        }
    }

    fn cancel(&mut self) {
        self.cancelled = true;
    }

    fn progress(&self) -> Option<Progress> {
        Some(self.progress)
    }
}

/// Read the module's program back with 134, as far as the extent says.
#[derive(Debug)]
pub struct UploadPlan {
    module: u8,
    extent: UploadExtent,
    limit: usize,
    words: Vec<ProgramWord>,
    cancelled: bool,
    progress: Progress,
    end: Option<Result<TransferReport, TransferError>>,
    over: bool,
}

impl UploadPlan {
    pub fn new(module: u8, extent: UploadExtent) -> UploadPlan {
        let (limit, total) = match extent {
            UploadExtent::UntilBlank => (PROGRAM_MEMORY_WORDS, None),
            UploadExtent::Units(n) => {
                let n = n.min(PROGRAM_MEMORY_WORDS);
                (n, Some(n))
            }
            UploadExtent::All => (PROGRAM_MEMORY_WORDS, Some(PROGRAM_MEMORY_WORDS)),
        };
        UploadPlan {
            module,
            extent,
            limit,
            words: Vec::new(),
            cancelled: false,
            progress: Progress {
                phase: Phase::Reading,
                done: 0,
                total,
            },
            end: None,
            over: false,
        }
    }

    fn report(&mut self) -> TransferReport {
        if self.extent == UploadExtent::All {
            while self.words.last().is_some_and(|w| transfer::is_blank(*w)) {
                self.words.pop();
            }
        }
        let mut report = TransferReport::new(self.module, self.words.len());
        report.program = Some(ReadProgram {
            source: disassemble(&self.words),
            image: Some(format_image(&self.words)),
            units: self.words.len(),
        });
        report
    }

    /// The words read so far.
    pub fn words(&self) -> &[ProgramWord] {
        &self.words
    }
}

impl TransferPlan for UploadPlan {
    fn next(&mut self) -> PlanStep {
        if let Some(end) = self.end.take() {
            return match end {
                Ok(report) => PlanStep::Done(report),
                Err(error) => PlanStep::Failed(error.into()),
            };
        }
        let address = self.words.len();
        if self.over || address >= self.limit {
            return PlanStep::Done(self.report());
        }
        if self.cancelled {
            return PlanStep::Failed(
                TransferError::Cancelled {
                    phase: Phase::Reading,
                    done: address,
                    total: self.progress.total,
                }
                .into(),
            );
        }
        PlanStep::Send(PlanLine::new(read_line(self.module, address)))
    }

    fn answer(&mut self, answer: Answer) {
        let address = self.words.len();
        match read_word(self.module, address, &answer) {
            Ok(word) => {
                if self.extent == UploadExtent::UntilBlank && transfer::is_blank(word) {
                    self.over = true;
                    return;
                }
                self.words.push(word);
                self.progress.done = address + 1;
            }
            Err(error) => self.end = Some(Err(error)),
        }
    }

    fn cancel(&mut self) {
        self.cancelled = true;
    }

    fn progress(&self) -> Option<Progress> {
        Some(self.progress)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::console::{FamilyConsole, Reading};
    use crate::protocol::tmcl::frame::{Reply, Status};

    fn word(opcode: u8, kind: u8, motor_bank: u8, value: i32) -> ProgramWord {
        ProgramWord {
            opcode,
            kind,
            motor_bank,
            value,
        }
    }

    /// The answer a module gives to `line` with `status` and `value`.
    fn answered(line: &PreparedLine, status: u8, value: i32) -> Answer {
        let request = &line.bytes;
        let frame = Reply {
            host_address: 2,
            module_address: request[0],
            status: Status(status),
            command: request[1],
            value,
        }
        .to_bytes()
        .to_vec();
        let frames = vec![frame];
        Answer {
            line: line.canonical.clone(),
            result: TmclConsole
                .interpret(line, &frames)
                .map_err(AnswerError::Reply),
            frames,
        }
    }

    fn lost(line: &PreparedLine) -> Answer {
        Answer {
            line: line.canonical.clone(),
            frames: Vec::new(),
            result: Err(AnswerError::Lost {
                address: line.address,
                reason: "no reply within 202 ms".into(),
            }),
        }
    }

    /// A 134 answer holding `word`.
    fn holding(line: &PreparedLine, w: ProgramWord) -> Answer {
        let mut frame = vec![2];
        frame.extend_from_slice(&w.to_bytes());
        frame.push(crate::protocol::tmcl::checksum(&frame));
        let frames = vec![frame];
        Answer {
            line: line.canonical.clone(),
            result: Ok(Reading {
                status: None,
                value: ReplyValue::None,
            }),
            frames,
        }
    }

    fn sent(step: PlanStep) -> PreparedLine {
        match step {
            PlanStep::Send(line) => line.line,
            other => panic!("expected a line, got {other:?}"),
        }
    }

    #[test]
    fn a_download_reads_the_state_resets_stores_leaves_and_verifies_in_order() {
        let words = [word(4, 0, 0, 1000), word(28, 0, 0, 0)];
        let mut plan = DownloadPlan::new(&words, 1, DownloadOptions::default()).expect("storable");
        assert!(
            plan.hold().is_some_and(|h| h.release().is_none()),
            "held, not entered"
        );
        let PlanStep::Send(first) = plan.next() else {
            panic!("a line first")
        };
        assert!(first.after_polls, "GP128 goes after the polls on their way");
        assert_eq!(first.line.canonical, "GGP 128, 0");
        plan.answer(answered(&first.line, 100, 1));
        let reset = sent(plan.next());
        assert_eq!(reset.canonical, "RESETAPP");
        plan.answer(answered(&reset, 100, 0));
        let enter = sent(plan.next());
        assert_eq!(enter.canonical, "DOWNLOAD 0");
        assert!(
            plan.hold().is_some_and(|h| h.release().is_some()),
            "133 needed now"
        );
        plan.answer(answered(&enter, 100, 0));
        for w in words {
            let store = sent(plan.next());
            assert_eq!(
                store.bytes,
                transfer::store_request(1, w).to_bytes().to_vec()
            );
            plan.answer(answered(&store, 101, 0));
        }
        let leave = sent(plan.next());
        assert_eq!(leave.canonical, "ENDDOWNLOAD");
        plan.answer(answered(&leave, 100, 0));
        assert!(plan.hold().is_none(), "download mode was left");
        for (address, w) in words.iter().enumerate() {
            let read = sent(plan.next());
            assert_eq!(read.canonical, format!("READMEM {address}"));
            plan.answer(holding(&read, *w));
        }
        let after = sent(plan.next());
        assert_eq!(after.canonical, "READMEM 2");
        plan.answer(holding(&after, word(9, 0, 0, 0)));
        let PlanStep::Done(report) = plan.next() else {
            panic!("verified")
        };
        assert_eq!(report.count, 2);
        assert_eq!(
            report.fact("stopped_program"),
            Some(&FactValue::Text("running".into()))
        );
        assert_eq!(report.fact("leftover_from"), Some(&FactValue::Number(2)));
    }

    #[test]
    fn a_word_executed_instead_of_stored_fails_after_leaving_download_mode() {
        let words = [word(4, 0, 0, 1000)];
        let mut plan = DownloadPlan::new(&words, 1, DownloadOptions::default()).expect("storable");
        for status in [100, 100, 100] {
            let line = sent(plan.next());
            plan.answer(answered(&line, status, 0));
        }
        let store = sent(plan.next());
        plan.answer(answered(&store, 100, 0));
        let leave = sent(plan.next());
        assert_eq!(leave.canonical, "ENDDOWNLOAD");
        plan.answer(answered(&leave, 100, 0));
        let PlanStep::Failed(failure) = plan.next() else {
            panic!("failed")
        };
        assert_eq!(failure.address(), Some(0));
        assert!(
            failure.message.contains("executed it instead of storing"),
            "{failure}"
        );
    }

    #[test]
    fn a_lost_133_leaves_the_hold_and_says_to_send_enddownload() {
        let mut plan =
            DownloadPlan::new(&[word(28, 0, 0, 0)], 1, DownloadOptions::default()).expect("ok");
        for status in [100, 100, 100, 101] {
            let line = sent(plan.next());
            plan.answer(answered(&line, status, 0));
        }
        let leave = sent(plan.next());
        plan.answer(lost(&leave));
        assert!(plan.hold().is_some(), "still held");
        let PlanStep::Failed(failure) = plan.next() else {
            panic!("failed")
        };
        assert!(
            failure.message.starts_with(
                "cannot leave download mode (133): module 1 did not answer ENDDOWNLOAD"
            ),
            "{failure}"
        );
        assert!(failure.message.contains("send ENDDOWNLOAD"), "{failure}");
    }

    #[test]
    fn cancelling_while_storing_leaves_download_mode_then_fails_as_cancelled() {
        let words = [word(28, 0, 0, 0), word(28, 0, 0, 0), word(28, 0, 0, 0)];
        let mut plan = DownloadPlan::new(&words, 1, DownloadOptions::default()).expect("ok");
        for status in [100, 100, 100, 101] {
            let line = sent(plan.next());
            plan.answer(answered(&line, status, 0));
        }
        plan.cancel();
        let leave = sent(plan.next());
        assert_eq!(leave.canonical, "ENDDOWNLOAD");
        plan.answer(answered(&leave, 100, 0));
        let PlanStep::Failed(failure) = plan.next() else {
            panic!("cancelled")
        };
        assert_eq!(
            failure.cancelled(),
            Some(Progress {
                phase: Phase::Storing,
                done: 1,
                total: Some(3)
            })
        );
        assert!(
            failure
                .console_text()
                .starts_with("cancelled: the module left download mode"),
            "{failure:?}"
        );
        assert!(plan.hold().is_none());
    }

    #[test]
    fn cancelled_before_entering_sends_nothing_more() {
        let mut plan =
            DownloadPlan::new(&[word(28, 0, 0, 0)], 1, DownloadOptions::default()).expect("ok");
        let first = sent(plan.next());
        plan.cancel();
        plan.answer(answered(&first, 100, 0));
        assert!(matches!(plan.next(), PlanStep::Failed(f) if f.cancelled().is_some()));
        assert!(plan.hold().is_none());
    }

    #[test]
    fn the_hold_admits_only_what_the_module_executes_in_download_mode() {
        let hold = DownloadHold {
            module: 1,
            entered: true,
        };
        let line = |command: &Command| TmclConsole.prepare_command(command, 1);
        assert!(hold.refusal(&line(&commands::read_memory(0))).is_none());
        assert!(hold.refusal(&line(&commands::exit_download())).is_none());
        let refused = hold
            .refusal(&line(&Command::Mst { motor: 0 }))
            .expect("MST would be stored");
        assert!(refused.contains("download mode"), "{refused}");
        assert_eq!(
            hold.release().map(|l| l.canonical),
            Some("ENDDOWNLOAD".to_string())
        );
    }

    #[test]
    fn verify_names_the_first_word_that_differs() {
        let words = [word(4, 0, 0, 10), word(4, 0, 0, 20)];
        let mut plan = VerifyPlan::new(&words, 1);
        let first = sent(plan.next());
        plan.answer(holding(&first, words[0]));
        let second = sent(plan.next());
        plan.answer(holding(&second, word(4, 0, 0, 999)));
        let PlanStep::Failed(failure) = plan.next() else {
            panic!("differs")
        };
        assert_eq!(failure.address(), Some(1));
        assert_eq!(
            failure.message,
            "word 1 differs: module 1 holds MVP ABS, 0, 999, the source has MVP ABS, 0, 20"
        );
    }

    #[test]
    fn an_upload_stops_at_the_first_blank_word() {
        let mut plan = UploadPlan::new(1, UploadExtent::UntilBlank);
        let first = sent(plan.next());
        plan.answer(holding(&first, word(28, 0, 0, 0)));
        let second = sent(plan.next());
        plan.answer(holding(&second, ProgramWord::default()));
        let PlanStep::Done(report) = plan.next() else {
            panic!("done")
        };
        assert_eq!(report.count, 1);
        let program = report.program.expect("read");
        assert_eq!(program.source.lines().last().map(str::trim), Some("STOP"));
    }

    #[test]
    fn cancellations_say_what_state_they_leave() {
        let storing = TransferError::Cancelled {
            phase: Phase::Storing,
            done: 3,
            total: Some(10),
        };
        assert_eq!(
            storing.to_string(),
            "cancelled after storing 3 of 10 words: download mode was left, the program in \
             the module is incomplete"
        );
        let verifying = TransferError::Cancelled {
            phase: Phase::Verifying,
            done: 0,
            total: Some(10),
        };
        assert!(verifying.to_string().contains("not verified"));
    }

    #[test]
    fn a_mismatch_names_the_address_and_both_words() {
        let error = TransferError::Mismatch {
            address: 17,
            wrote: word(4, 0, 0, 1000),
            read: word(4, 0, 0, 1001),
        };
        assert_eq!(
            error.to_string(),
            "word 17 differs: wrote MVP ABS, 0, 1000 (04 00 00 00 00 03 E8), read \
             MVP ABS, 0, 1001 (04 00 00 00 00 03 E9)"
        );
        let failure = TransferFailure::from(error);
        assert_eq!(failure.address(), Some(17));
        assert!(!failure.nothing_sent());
    }
}
