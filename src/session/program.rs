//! The device side of the TMCL program toolchain: download a program image
//! and verify every word by reading it back, read a program back (upload).
//! UI-free: the command line (`axterm download`, `upload`, `disasm`) and
//! the console's editor pane call [`Session::download_program`] and
//! [`Session::upload_program`], follow them through a progress callback
//! and stop them with a [`Cancel`].
//!
//! # A download (§3.6.53, digest D10.2)
//!
//! 1. Every word is checked first ([`transfer::check_image`]): nothing is
//!    sent for an image with a control command or an empty word in it.
//! 2. Status polling is paused and user lines that the module would store
//!    are refused (see below); GP128 (application status) is read at poll
//!    priority, so that it goes only after every poll already on its way:
//!    none can reach the module in download mode and be stored as a word.
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
//! # Sharing the module while a download runs
//!
//! Everything goes at [`Priority::Transfer`]: user lines and the emergency
//! stop go first. But in download mode the module stores whatever is not a
//! control command instead of executing it, so while it is in download mode
//! (the session marks itself so until 133 is answered):
//! - polling is paused ([`Session::start_polling`] only takes note, and
//!   polling resumes when download mode is left);
//! - user lines other than 133–136 are refused before sending;
//! - the emergency stop cancels the transfer and waits for the word on the
//!   wire, after which the download leaves download mode itself (two
//!   transactions in all); if that failed, the stop sends 133 first. Its
//!   MST is never stored as a program word: a stop that waits two
//!   transactions is the price of one that stops at all.
//!
//! Anything that slipped through anyway (a line racing the start of a
//! download on another thread) is caught by the verification.
//!
//! # Cancellation
//!
//! [`Cancel::cancel`] stops a transfer between two words: a download leaves
//! download mode and fails with [`TransferError::Cancelled`] (its words are
//! partly stored, not verified). Dropping a download's future instead still
//! leaves download mode, from a task of its own.
//!
//! # An upload
//!
//! The module does not know how long its program is. [`UploadExtent`]
//! says where to stop: at the first blank word (all zeros, as the simulator
//! erases; or all 0xFF, as erased EEPROM reads on most parts), after a
//! given number of words, or at the end of memory with trailing blank
//! words dropped.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use tokio::sync::OwnedMutexGuard;
use tokio::time::Instant;

use super::{PreparedLine, ReplyValue, Session, SessionError};
use crate::device::{DeviceError, Expect, Priority, Retry, Transaction};
use crate::protocol::tmcl::asm::{PROGRAM_MEMORY_WORDS, ProgramWord};
use crate::protocol::tmcl::command::opcode;
use crate::protocol::tmcl::transfer::{
    self, ApplicationState, ReadBackProblem, StoreProblem, TRANSACTION_BYTES, Unstorable, commands,
    show_word,
};
use crate::protocol::tmcl::{TmclConsole, TmclReplyRule};

/// Stops a transfer between two words. Cheap to clone; clones share. One
/// serves one transfer: once cancelled (by its owner or an emergency
/// stop) it stays cancelled.
#[derive(Debug, Clone, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    pub fn new() -> Cancel {
        Cancel::default()
    }

    pub fn cancel(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }
}

/// What a transfer is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Download: storing words (132…133).
    Storing,
    /// Download: reading every word back (134).
    Verifying,
    /// Upload: reading the program (134).
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

/// How far a transfer has come: after each word, and at the start of each
/// phase (`done` 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progress {
    pub phase: Phase,
    /// Words done in this phase.
    pub done: usize,
    /// Words this phase will take; `None` when an upload reads until the
    /// first blank word.
    pub total: Option<usize>,
}

/// What to do after a verified download.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DownloadOptions {
    /// Start the program (129 type 0: from address 0 after the reset).
    pub run: bool,
    /// Set GP77 so that the module starts the program at power-up.
    pub autostart: bool,
}

/// A verified download.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DownloadReport {
    pub module: u8,
    /// Words stored and verified, from address 0.
    pub words: usize,
    /// The program's state before the download if it was executing (it
    /// was stopped by 131).
    pub stopped: Option<ApplicationState>,
    /// Memory after the program, from this address, still holds words of
    /// an earlier program.
    pub leftover_from: Option<usize>,
    /// GP77 is now 1.
    pub autostart: bool,
    /// The program was started.
    pub started: bool,
    pub elapsed: Duration,
    /// Request/reply pairs exchanged.
    pub transactions: u64,
}

impl DownloadReport {
    /// The wire time of every transaction made at `byte_time` per byte: no
    /// download over that line can be faster.
    pub fn wire_time(&self, byte_time: Duration) -> Duration {
        wire_time(self.transactions, byte_time)
    }

    /// The download's speed as a fraction of the wire's limit.
    pub fn wire_share(&self, byte_time: Duration) -> f64 {
        share(self.wire_time(byte_time), self.elapsed)
    }
}

/// Where an upload stops (the module does not know its program's length).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UploadExtent {
    /// At the first blank word (or the end of memory).
    #[default]
    UntilBlank,
    /// After this many words (at most the memory's size).
    Words(usize),
    /// The whole memory, trailing blank words dropped.
    All,
}

/// A program read back.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UploadReport {
    pub module: u8,
    /// From address 0.
    pub words: Vec<ProgramWord>,
    pub elapsed: Duration,
    pub transactions: u64,
}

/// Why a transfer failed. A download that fails is never verified.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TransferError {
    #[error("{family} modules keep no program that axterm can transfer")]
    Unsupported { family: &'static str },
    #[error("another program transfer is running on this connection")]
    Busy,
    #[error("{0}; nothing was sent")]
    Unstorable(Unstorable),
    /// A control step failed: reading the application status, reset,
    /// entering or leaving download mode, autostart, run.
    #[error("cannot {step}: {error}{hint}")]
    Step {
        step: &'static str,
        error: Box<SessionError>,
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
        error: DeviceError,
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
        error: DeviceError,
    },
    #[error("word {address} differs: wrote {}, read {}", show_word(*.wrote), show_word(*.read))]
    Mismatch {
        address: usize,
        wrote: ProgramWord,
        read: ProgramWord,
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
        exit: Box<SessionError>,
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
    /// True when nothing was sent (the image was refused).
    pub fn nothing_sent(&self) -> bool {
        matches!(
            self,
            TransferError::Unsupported { .. } | TransferError::Busy | TransferError::Unstorable(_)
        )
    }

    /// The program address the failure is about, if any.
    pub fn address(&self) -> Option<usize> {
        match self {
            TransferError::Unstorable(u) => Some(u.address),
            TransferError::NotStored { address, .. }
            | TransferError::StoreUnanswered { address, .. }
            | TransferError::ReadBack { address, .. }
            | TransferError::ReadUnanswered { address, .. }
            | TransferError::Mismatch { address, .. } => Some(*address),
            TransferError::Stranded { cause, .. } => cause.address(),
            _ => None,
        }
    }
}

/// The session's record of program transfers (one at a time), shared by
/// its clones.
#[derive(Debug, Default)]
pub(crate) struct TransferState {
    /// Held by a download while the module is in download mode, so that
    /// an emergency stop waits for the word on the wire.
    gate: Arc<tokio::sync::Mutex<()>>,
    /// The module is, or may be, in download mode because of a download.
    downloading: AtomicBool,
    /// The running transfer's cancel handle.
    current: Mutex<Option<Cancel>>,
}

impl TransferState {
    pub(crate) fn downloading(&self) -> bool {
        self.downloading.load(Ordering::SeqCst)
    }

    /// Why a user line must not be sent now: in download mode the module
    /// would store it. 133 (leave download mode) and the reads 134–136
    /// are executed (§3.6.53).
    pub(crate) fn refusal(&self, line: &PreparedLine) -> Option<String> {
        if !self.downloading() {
            return None;
        }
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

    fn register(&self, cancel: &Cancel) -> Result<(), TransferError> {
        let mut current = self.current.lock().unwrap_or_else(|e| e.into_inner());
        if current.is_some() {
            return Err(TransferError::Busy);
        }
        *current = Some(cancel.clone());
        Ok(())
    }

    fn unregister(&self) {
        *self.current.lock().unwrap_or_else(|e| e.into_inner()) = None;
    }
}

/// What an emergency stop found of a transfer: hold it until the stop
/// lines are sent, so that no download starts meanwhile.
pub(crate) struct Halted {
    _gate: Option<OwnedMutexGuard<()>>,
    leave: Option<PreparedLine>,
    state: Arc<TransferState>,
    session: Session,
}

impl Halted {
    /// The line to send before the stop lines: 133, when the module may
    /// still be in download mode.
    pub(crate) fn leave_download(&self) -> Option<&PreparedLine> {
        self.leave.as_ref()
    }

    /// The module left download mode.
    pub(crate) fn left_download(&self) {
        self.state.downloading.store(false, Ordering::SeqCst);
        resume_polling(&self.session);
    }
}

/// Cancel any transfer and, if the module is in download mode, wait for
/// the word on the wire (the download then leaves download mode itself).
pub(crate) async fn halt_transfer(session: &Session) -> Halted {
    let state = Arc::clone(&session.transfer);
    if let Some(cancel) = state
        .current
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .as_ref()
    {
        cancel.cancel();
    }
    if !state.downloading() {
        return Halted {
            _gate: None,
            leave: None,
            state,
            session: session.clone(),
        };
    }
    let gate = Arc::clone(&state.gate).lock_owned().await;
    let leave = state
        .downloading()
        .then(|| TmclConsole.prepare_command(&commands::exit_download(), session.address));
    Halted {
        _gate: Some(gate),
        leave,
        state,
        session: session.clone(),
    }
}

/// After a user line succeeded: a user's ENDDOWNLOAD ends download mode
/// left behind by a failed download.
pub(crate) fn after_user_line(session: &Session, line: &PreparedLine) {
    let state = &session.transfer;
    if state.downloading()
        && line.bytes.get(1) == Some(&opcode::EXIT_DOWNLOAD)
        && let Ok(_gate) = state.gate.try_lock()
    {
        state.downloading.store(false, Ordering::SeqCst);
        resume_polling(session);
    }
}

fn resume_polling(session: &Session) {
    if let Some(cadence) = session.poll_cadence() {
        session.apply_poll_plan(cadence);
    }
}

fn wire_time(transactions: u64, byte_time: Duration) -> Duration {
    let bytes = transactions.saturating_mul(TRANSACTION_BYTES);
    byte_time.saturating_mul(u32::try_from(bytes).unwrap_or(u32::MAX))
}

fn share(wire: Duration, elapsed: Duration) -> f64 {
    if elapsed.is_zero() {
        return 1.0;
    }
    wire.as_secs_f64() / elapsed.as_secs_f64()
}

/// Clears the session's running transfer when the transfer ends, however.
struct Registration<'s>(&'s TransferState);

impl Drop for Registration<'_> {
    fn drop(&mut self) {
        self.0.unregister();
    }
}

/// The module is in download mode (or 132 is on its way): holds the gate;
/// if dropped before [`DownloadMode::leave`], a task of its own leaves
/// download mode.
struct DownloadMode {
    session: Session,
    gate: Option<OwnedMutexGuard<()>>,
    /// 132 was sent: 133 is needed to leave.
    entered: bool,
}

impl DownloadMode {
    async fn begin(session: &Session) -> DownloadMode {
        let gate = Arc::clone(&session.transfer.gate).lock_owned().await;
        session.transfer.downloading.store(true, Ordering::SeqCst);
        session.pause_polling();
        DownloadMode {
            session: session.clone(),
            gate: Some(gate),
            entered: false,
        }
    }

    /// Leave download mode (133 if 132 was sent) and resume polling. On
    /// failure the session stays marked as downloading: user lines stay
    /// refused until an ENDDOWNLOAD or an emergency stop gets through.
    async fn leave(mut self, count: &mut u64) -> Result<(), SessionError> {
        let result = if self.entered {
            *count += 1;
            exit_download(&self.session).await
        } else {
            Ok(())
        };
        if result.is_ok() {
            self.session
                .transfer
                .downloading
                .store(false, Ordering::SeqCst);
            resume_polling(&self.session);
        }
        self.entered = false;
        self.gate = None;
        result
    }
}

impl Drop for DownloadMode {
    fn drop(&mut self) {
        let Some(gate) = self.gate.take() else {
            return;
        };
        let session = self.session.clone();
        let entered = self.entered;
        let Ok(runtime) = tokio::runtime::Handle::try_current() else {
            // No runtime to send 133 with: the session stays marked, so
            // user lines are refused and an emergency stop sends 133.
            return;
        };
        runtime.spawn(async move {
            let _gate = gate;
            if !entered || exit_download(&session).await.is_ok() {
                session.transfer.downloading.store(false, Ordering::SeqCst);
                resume_polling(&session);
            }
        });
    }
}

async fn exit_download(session: &Session) -> Result<(), SessionError> {
    let line = TmclConsole.prepare_command(&commands::exit_download(), session.address);
    session
        .send(Priority::Transfer, &line, Retry::Never, None)
        .await
        .map(|_| ())
}

/// One transfer's bookkeeping.
struct Run<'a> {
    session: &'a Session,
    cancel: &'a Cancel,
    progress: &'a mut (dyn FnMut(Progress) + Send),
    transactions: u64,
}

impl Run<'_> {
    fn module(&self) -> u8 {
        self.session.address
    }

    fn report(&mut self, phase: Phase, done: usize, total: Option<usize>) {
        (self.progress)(Progress { phase, done, total });
    }

    /// A control line at transfer priority (or `priority`).
    async fn control(
        &mut self,
        step: &'static str,
        command: &crate::protocol::tmcl::Command,
        priority: Priority,
    ) -> Result<ReplyValue, TransferError> {
        let line = TmclConsole.prepare_command(command, self.module());
        let retry = match line.effect {
            crate::protocol::console::Effect::Reads => Retry::Read(self.session.read_retries),
            crate::protocol::console::Effect::Acts => Retry::Never,
        };
        self.transactions += 1;
        let result = self.session.send(priority, &line, retry, None).await;
        result.map(|r| r.value).map_err(|error| {
            let hint = match (command, error.status()) {
                (crate::protocol::tmcl::Command::EnterDownload { .. }, Some(5)) => {
                    "; GP81 code protection 2 or 3 forbids overwriting the program (§5.1)".into()
                }
                _ => String::new(),
            };
            TransferError::Step {
                step,
                error: Box::new(error),
                hint,
            }
        })
    }

    /// Store one word (download mode): never sent twice.
    async fn store(&mut self, address: usize, word: ProgramWord) -> Result<(), TransferError> {
        let module = self.module();
        let request = transfer::store_request(module, word);
        let transaction = Transaction {
            bytes: request.to_bytes().to_vec(),
            expect: Expect::Reply(Arc::new(TmclReplyRule::for_request(&request))),
            retry: Retry::Never,
            timeout: None,
        };
        self.transactions += 1;
        let answer = self
            .session
            .device
            .transact(Priority::Transfer, transaction)
            .await
            .map_err(|error| TransferError::StoreUnanswered {
                module,
                address,
                word: show_word(word),
                error,
            })?;
        let frame = answer.frames.last().map(Vec::as_slice).unwrap_or_default();
        transfer::judge_store(frame).map_err(|problem| TransferError::NotStored {
            module,
            address,
            word: show_word(word),
            problem,
        })
    }

    /// Read one word back (134); reads may be retried.
    async fn read(&mut self, address: usize) -> Result<ProgramWord, TransferError> {
        let module = self.module();
        let at = u16::try_from(address).unwrap_or(u16::MAX);
        let line = TmclConsole.prepare_command(&commands::read_memory(at), module);
        let transaction =
            self.session
                .transaction(&line, Retry::Read(self.session.read_retries), None);
        self.transactions += 1;
        let answer = self
            .session
            .device
            .transact(Priority::Transfer, transaction)
            .await
            .map_err(|error| TransferError::ReadUnanswered {
                module,
                address,
                error,
            })?;
        let frame = answer.frames.last().map(Vec::as_slice).unwrap_or_default();
        transfer::read_back(module, frame).map_err(|problem| TransferError::ReadBack {
            module,
            address,
            problem,
        })
    }

    fn check_cancel(
        &self,
        phase: Phase,
        done: usize,
        total: Option<usize>,
    ) -> Result<(), TransferError> {
        if self.cancel.is_cancelled() {
            return Err(TransferError::Cancelled { phase, done, total });
        }
        Ok(())
    }

    /// Steps 2–4 of the module documentation, inside download mode.
    async fn store_all(
        &mut self,
        mode: &mut DownloadMode,
        words: &[ProgramWord],
    ) -> Result<Option<ApplicationState>, TransferError> {
        let total = Some(words.len());
        // At poll priority: it goes once every poll already on its way has
        // been answered, and the poll plan is gone by then.
        let state = self
            .control(
                "read the application status (GP128)",
                &commands::application_state(),
                Priority::Poll,
            )
            .await?;
        let state = match state {
            ReplyValue::Number(n) => ApplicationState::from_gp128(n),
            _ => ApplicationState::Unknown(-1),
        };
        self.check_cancel(Phase::Storing, 0, total)?;
        self.control(
            "reset the application (131)",
            &commands::reset_application(),
            Priority::Transfer,
        )
        .await?;
        self.check_cancel(Phase::Storing, 0, total)?;
        mode.entered = true;
        self.control(
            "enter download mode (132)",
            &commands::enter_download(0),
            Priority::Transfer,
        )
        .await?;
        self.report(Phase::Storing, 0, total);
        for (address, word) in words.iter().enumerate() {
            self.check_cancel(Phase::Storing, address, total)?;
            self.store(address, *word).await?;
            self.report(Phase::Storing, address + 1, total);
        }
        Ok(state.is_active().then_some(state))
    }

    /// Step 5: every word read back and compared; the word after the
    /// program looked at.
    async fn verify(&mut self, words: &[ProgramWord]) -> Result<Option<usize>, TransferError> {
        let total = Some(words.len());
        self.report(Phase::Verifying, 0, total);
        for (address, wrote) in words.iter().enumerate() {
            self.check_cancel(Phase::Verifying, address, total)?;
            let read = self.read(address).await?;
            if read != *wrote {
                return Err(TransferError::Mismatch {
                    address,
                    wrote: *wrote,
                    read,
                });
            }
            self.report(Phase::Verifying, address + 1, total);
        }
        let after = words.len();
        if after >= PROGRAM_MEMORY_WORDS {
            return Ok(None);
        }
        let next = self.read(after).await?;
        Ok((!transfer::is_blank(next)).then_some(after))
    }
}

impl Session {
    /// Download `words` to address 0, verify every word by reading it
    /// back, then set autostart and start the program as `options` say.
    /// See the module documentation for every step. `progress` hears of
    /// every word; `cancel` stops between two words.
    pub async fn download_program(
        &self,
        words: &[ProgramWord],
        options: DownloadOptions,
        cancel: &Cancel,
        progress: &mut (dyn FnMut(Progress) + Send),
    ) -> Result<DownloadReport, TransferError> {
        self.tmcl_only()?;
        transfer::check_image(words).map_err(TransferError::Unstorable)?;
        self.transfer.register(cancel)?;
        let _registration = Registration(&self.transfer);
        let started = Instant::now();
        let mut run = Run {
            session: self,
            cancel,
            progress,
            transactions: 0,
        };

        let mut mode = DownloadMode::begin(self).await;
        let stored = run.store_all(&mut mode, words).await;
        let left = mode.leave(&mut run.transactions).await;
        let stopped = match (stored, left) {
            (Ok(stopped), Ok(())) => stopped,
            (Err(cause), Ok(())) => return Err(cause),
            (Ok(_), Err(error)) => {
                return Err(TransferError::Step {
                    step: "leave download mode (133)",
                    error: Box::new(error),
                    hint: "; the module may still store what it is sent instead of executing \
                           it: send ENDDOWNLOAD"
                        .into(),
                });
            }
            (Err(cause), Err(exit)) => {
                return Err(TransferError::Stranded {
                    cause: Box::new(cause),
                    exit: Box::new(exit),
                });
            }
        };

        let leftover_from = run.verify(words).await?;
        if options.autostart {
            run.control(
                "switch autostart on (SGP 77, 0, 1)",
                &commands::set_autostart(true),
                Priority::Transfer,
            )
            .await?;
            let value = run
                .control(
                    "read autostart back (GGP 77, 0)",
                    &commands::autostart(),
                    Priority::Transfer,
                )
                .await?;
            if value != ReplyValue::Number(1) {
                return Err(TransferError::Step {
                    step: "switch autostart on",
                    error: Box::new(SessionError::Refused {
                        line: "GGP 77, 0".into(),
                        message: format!("GP77 reads back {value} after SGP 77, 0, 1"),
                    }),
                    hint: String::new(),
                });
            }
        }
        if options.run {
            run.check_cancel(Phase::Verifying, words.len(), Some(words.len()))?;
            run.control(
                "start the program (129)",
                &commands::run_application(),
                Priority::Transfer,
            )
            .await?;
        }
        Ok(DownloadReport {
            module: self.address,
            words: words.len(),
            stopped,
            leftover_from,
            autostart: options.autostart,
            started: options.run,
            elapsed: started.elapsed(),
            transactions: run.transactions,
        })
    }

    /// Read the module's program back with 134, as far as `extent` says.
    pub async fn upload_program(
        &self,
        extent: UploadExtent,
        cancel: &Cancel,
        progress: &mut (dyn FnMut(Progress) + Send),
    ) -> Result<UploadReport, TransferError> {
        self.tmcl_only()?;
        self.transfer.register(cancel)?;
        let _registration = Registration(&self.transfer);
        let started = Instant::now();
        let mut run = Run {
            session: self,
            cancel,
            progress,
            transactions: 0,
        };
        let (limit, total) = match extent {
            UploadExtent::UntilBlank => (PROGRAM_MEMORY_WORDS, None),
            UploadExtent::Words(n) => {
                let n = n.min(PROGRAM_MEMORY_WORDS);
                (n, Some(n))
            }
            UploadExtent::All => (PROGRAM_MEMORY_WORDS, Some(PROGRAM_MEMORY_WORDS)),
        };
        run.report(Phase::Reading, 0, total);
        let mut words = Vec::new();
        for address in 0..limit {
            run.check_cancel(Phase::Reading, address, total)?;
            let word = run.read(address).await?;
            if extent == UploadExtent::UntilBlank && transfer::is_blank(word) {
                break;
            }
            words.push(word);
            run.report(Phase::Reading, address + 1, total);
        }
        if extent == UploadExtent::All {
            while words.last().is_some_and(|w| transfer::is_blank(*w)) {
                words.pop();
            }
        }
        Ok(UploadReport {
            module: self.address,
            words,
            elapsed: started.elapsed(),
            transactions: run.transactions,
        })
    }

    fn tmcl_only(&self) -> Result<(), TransferError> {
        if self.family.name == "tmcl" {
            Ok(())
        } else {
            Err(TransferError::Unsupported {
                family: self.family.name,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_wire_time_counts_request_and_reply_of_every_transaction() {
        let byte_time = crate::link::byte_time(115_200);
        // The figure: 2 × 1000 transactions × 18 bytes × 10 bits.
        let time = wire_time(2000, byte_time);
        let expected = 2000.0 * 18.0 * 10.0 / 115_200.0;
        assert!((time.as_secs_f64() - expected).abs() < 1e-3, "{time:?}");
        assert_eq!(share(Duration::from_secs(1), Duration::from_secs(2)), 0.5);
        assert_eq!(share(Duration::from_secs(1), Duration::ZERO), 1.0);
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
            wrote: ProgramWord {
                opcode: 4,
                kind: 0,
                motor_bank: 0,
                value: 1000,
            },
            read: ProgramWord {
                opcode: 4,
                kind: 0,
                motor_bank: 0,
                value: 1001,
            },
        };
        assert_eq!(
            error.to_string(),
            "word 17 differs: wrote MVP ABS, 0, 1000 (04 00 00 00 00 03 E8), read \
             MVP ABS, 0, 1001 (04 00 00 00 00 03 E9)"
        );
        assert_eq!(error.address(), Some(17));
        assert!(!error.nothing_sent());
    }
}
