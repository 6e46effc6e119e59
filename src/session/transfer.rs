//! The one runner of program transfers: it drives any family's
//! [`TransferPlan`] (a pure state machine of prepared lines, see
//! [`crate::protocol::program`]) over the session, at transfer priority, with
//! progress, cancellation, and the emergency stop jumping it. The command
//! line (`axterm download`, `upload`, `disasm`) and the console's editor
//! call [`Session::transfer`] (or [`Session::run_job`]), follow it through a
//! progress callback and stop it with a [`Cancel`].
//!
//! # Sharing the module while a transfer runs
//!
//! Everything goes at [`Priority::Transfer`] (a line the plan marks goes at
//! poll priority instead, after every poll already on its way): user lines
//! and the emergency stop go first. But a plan may hold the module in a
//! mode in which it misreads other lines ([`ModuleHold`]: TMCL's download
//! mode stores them as program words). While a plan holds it:
//! - polling is paused ([`Session::start_polling`] only takes note, and
//!   polling resumes when the hold ends);
//! - user lines the hold does not admit are refused before sending;
//! - the emergency stop cancels the transfer and waits for the line on the
//!   wire, after which the plan lets the module go itself (two
//!   transactions in all, for TMCL); if that failed, the stop sends the
//!   hold's release line first.
//!
//! A plan that ends while it still holds the module (its release line got
//! no answer) leaves the hold on the session: user lines stay refused
//! until that very release line, sent by the user, succeeds, or an
//! emergency stop sends it.
//!
//! # Cancellation
//!
//! [`Cancel::cancel`] stops a transfer between two lines: the plan winds
//! down (TMCL leaves download mode) and fails as cancelled. Dropping a
//! transfer's future instead still lets the module go, from a task of its
//! own.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use tokio::sync::OwnedMutexGuard;
use tokio::time::Instant;

use super::{PreparedLine, Session, SessionError};
use crate::device::{DeviceError, Priority, Retry};
use crate::protocol::console::{Answering, Effect, adapt_line, interpret_line};
use crate::protocol::program::{
    Answer, AnswerError, ModuleHold, PlanLine, PlanStep, Progress, TransferFailure, TransferJob,
    TransferPlan, TransferReport,
};

/// Stops a transfer between two lines, and aborts a line on the wire that
/// holds the module busy (an MCCL text file's `MC` or `WS`: its abort byte
/// goes at once, see [`crate::device::Hold`]). Cheap to clone; clones
/// share. One serves one transfer: once cancelled (by its owner or an
/// emergency stop) it stays cancelled.
#[derive(Debug, Clone, Default)]
pub struct Cancel(Arc<CancelState>);

#[derive(Debug, Default)]
struct CancelState {
    cancelled: AtomicBool,
    woken: tokio::sync::Notify,
}

impl Cancel {
    pub fn new() -> Cancel {
        Cancel::default()
    }

    pub fn cancel(&self) {
        self.0.cancelled.store(true, Ordering::SeqCst);
        self.0.woken.notify_waiters();
    }

    pub fn is_cancelled(&self) -> bool {
        self.0.cancelled.load(Ordering::SeqCst)
    }

    /// Resolves once it is cancelled.
    async fn cancelled(&self) {
        loop {
            let woken = self.0.woken.notified();
            if self.is_cancelled() {
                return;
            }
            woken.await;
        }
    }
}

/// The session's record of program transfers (one at a time), shared by
/// its clones.
#[derive(Debug, Default)]
pub(crate) struct TransferState {
    /// Held by a transfer while its plan holds the module, so that an
    /// emergency stop waits for the line on the wire.
    gate: Arc<tokio::sync::Mutex<()>>,
    /// The hold on the module: a running plan's, or one a plan left when
    /// it could not let the module go.
    hold: Mutex<Option<Arc<dyn ModuleHold>>>,
    /// The running transfer's cancel handle.
    current: Mutex<Option<Cancel>>,
}

impl TransferState {
    fn hold(&self) -> Option<Arc<dyn ModuleHold>> {
        self.hold.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    fn set_hold(&self, hold: Option<Arc<dyn ModuleHold>>) {
        *self.hold.lock().unwrap_or_else(|e| e.into_inner()) = hold;
    }

    /// Whether the module is held (polling waits).
    pub(crate) fn held(&self) -> bool {
        self.hold().is_some()
    }

    /// Why a user line must not be sent now.
    pub(crate) fn refusal(&self, line: &PreparedLine) -> Option<String> {
        self.hold().and_then(|hold| hold.refusal(line))
    }

    fn register(&self, cancel: &Cancel) -> Result<(), TransferFailure> {
        let mut current = self.current.lock().unwrap_or_else(|e| e.into_inner());
        if current.is_some() {
            return Err(TransferFailure::busy());
        }
        *current = Some(cancel.clone());
        Ok(())
    }

    fn unregister(&self) {
        *self.current.lock().unwrap_or_else(|e| e.into_inner()) = None;
    }
}

/// Clears the session's running transfer when the transfer ends, however.
struct Registration<'s>(&'s TransferState);

impl Drop for Registration<'_> {
    fn drop(&mut self) {
        self.0.unregister();
    }
}

/// What an emergency stop found of a transfer: hold it until the stop
/// lines are sent, so that no transfer takes the module meanwhile.
pub(crate) struct Halted {
    _gate: Option<OwnedMutexGuard<()>>,
    release: Option<PreparedLine>,
    session: Session,
}

impl Halted {
    /// The line to send before the stop lines: the hold's release, when
    /// the module may still be held.
    pub(crate) fn release(&self) -> Option<&PreparedLine> {
        self.release.as_ref()
    }

    /// The module was let go.
    pub(crate) fn released(&self) {
        self.session.transfer.set_hold(None);
        resume_polling(&self.session);
    }
}

/// Cancel any transfer and, if the module is held, wait for the line on
/// the wire (the plan then lets the module go itself).
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
    if !state.held() {
        return Halted {
            _gate: None,
            release: None,
            session: session.clone(),
        };
    }
    let gate = Arc::clone(&state.gate).lock_owned().await;
    Halted {
        _gate: Some(gate),
        release: state.hold().and_then(|hold| hold.release()),
        session: session.clone(),
    }
}

/// After a user line succeeded: the hold's own release line, sent by the
/// user, ends a hold a failed plan left behind (TMCL: ENDDOWNLOAD).
pub(crate) fn after_user_line(session: &Session, line: &PreparedLine) {
    let state = &session.transfer;
    let releases = state
        .hold()
        .and_then(|hold| hold.release())
        .is_some_and(|release| release.bytes == line.bytes);
    if releases && let Ok(_gate) = state.gate.try_lock() {
        state.set_hold(None);
        resume_polling(session);
    }
}

fn resume_polling(session: &Session) {
    if let Some(cadence) = session.poll_cadence() {
        session.apply_poll_plan(cadence);
    }
}

/// A plan's hold on the module, as the runner keeps it: holds the gate;
/// if dropped before [`Holding::end`] or [`Holding::leave`], a task of its
/// own lets the module go.
struct Holding {
    session: Session,
    gate: Option<OwnedMutexGuard<()>>,
}

impl Holding {
    async fn begin(session: &Session, hold: Arc<dyn ModuleHold>) -> Holding {
        let gate = Arc::clone(&session.transfer.gate).lock_owned().await;
        session.transfer.set_hold(Some(hold));
        session.pause_polling();
        Holding {
            session: session.clone(),
            gate: Some(gate),
        }
    }

    /// The plan's hold changed (TMCL: 132 was sent).
    fn update(&self, hold: Arc<dyn ModuleHold>) {
        self.session.transfer.set_hold(Some(hold));
    }

    /// The plan let the module go: polling resumes.
    fn end(mut self) {
        self.session.transfer.set_hold(None);
        resume_polling(&self.session);
        self.gate = None;
    }

    /// The plan ended still holding the module: the hold stays on the
    /// session (user lines refused, polling paused) until its release line
    /// gets through.
    fn leave(mut self) {
        self.gate = None;
    }
}

impl Drop for Holding {
    fn drop(&mut self) {
        let Some(gate) = self.gate.take() else {
            return;
        };
        let session = self.session.clone();
        let Ok(runtime) = tokio::runtime::Handle::try_current() else {
            // No runtime to send the release with: the hold stays, so user
            // lines are refused and an emergency stop sends it.
            return;
        };
        runtime.spawn(async move {
            let _gate = gate;
            let release = session.transfer.hold().and_then(|hold| hold.release());
            let released = match release {
                Some(line) => {
                    let line = PlanLine::new(line);
                    session.exchange(&line).await.0.result.is_ok()
                }
                None => true,
            };
            if released {
                session.transfer.set_hold(None);
                resume_polling(&session);
            }
        });
    }
}

impl Session {
    /// Drive `plan` until it is done or fails: each line at transfer
    /// priority, its answer back to the plan. `progress` hears of every
    /// step forward; `cancel` stops it between two lines (so does the
    /// emergency stop). One transfer at a time per connection.
    pub async fn transfer(
        &self,
        mut plan: Box<dyn TransferPlan>,
        cancel: &Cancel,
        progress: &mut (dyn FnMut(Progress) + Send),
    ) -> Result<TransferReport, TransferFailure> {
        self.transfer.register(cancel)?;
        let _registration = Registration(&self.transfer);
        let started = Instant::now();
        let mut holding: Option<Holding> = None;
        let mut shown: Option<Progress> = None;
        let mut transactions = 0u64;
        let mut wire_bytes = 0u64;
        loop {
            if let Some(now) = plan.progress()
                && shown != Some(now)
            {
                shown = Some(now);
                progress(now);
            }
            if cancel.is_cancelled() {
                plan.cancel();
            }
            let step = plan.next();
            match (plan.hold(), holding.as_ref()) {
                (Some(hold), None) => holding = Some(Holding::begin(self, hold).await),
                (Some(hold), Some(held)) => held.update(hold),
                (None, Some(_)) => {
                    if let Some(held) = holding.take() {
                        held.end();
                    }
                }
                (None, None) => {}
            }
            let end = match step {
                PlanStep::Send(line) => {
                    let (answer, bytes) = self.exchange_until_cancelled(&line, cancel).await;
                    transactions += 1;
                    wire_bytes += bytes;
                    plan.answer(answer);
                    continue;
                }
                PlanStep::Done(mut report) => {
                    report.elapsed = started.elapsed();
                    report.transactions = transactions;
                    report.wire_bytes = wire_bytes;
                    Ok(report)
                }
                PlanStep::Failed(failure) => Err(failure),
            };
            if let Some(held) = holding.take() {
                held.leave();
            }
            return end;
        }
    }

    /// Run a transfer the console or the command line asked for: the
    /// plan comes from the program (download, verify) or from the family's
    /// program tool (upload).
    pub async fn run_job(
        &self,
        job: &TransferJob,
        cancel: &Cancel,
        progress: &mut (dyn FnMut(Progress) + Send),
    ) -> Result<TransferReport, TransferFailure> {
        let plan = self.plan(job)?;
        self.transfer(plan, cancel, progress).await
    }

    /// The plan of `job` for this session's module (nothing sent).
    pub fn plan(&self, job: &TransferJob) -> Result<Box<dyn TransferPlan>, TransferFailure> {
        match job {
            TransferJob::Download { program, options } => {
                crate::protocol::program::download_plan(program.as_ref(), self.address, *options)
            }
            TransferJob::Verify { program } => program.verify(self.address),
            TransferJob::Upload(extent) => match self.family.console.program() {
                Some(tool) => tool.upload(self.address, *extent),
                None => Err(TransferFailure::refused(format!(
                    "{} modules keep no program that axterm can transfer",
                    self.family.name
                ))),
            },
        }
    }

    /// [`Session::exchange`], aborting the line if the transfer is
    /// cancelled while it holds the module busy (its answer, the abort's
    /// error, then ends it).
    async fn exchange_until_cancelled(&self, step: &PlanLine, cancel: &Cancel) -> (Answer, u64) {
        let context = self.current_context();
        let bytes = adapt_line(self.family.console, &step.line, context.as_deref()).bytes;
        let device = self.device.clone();
        // Once cancelled and this very line is held on the wire, its abort
        // goes; a line answered at once is never held, and nothing is sent.
        let abort = async move {
            cancel.cancelled().await;
            let mut busy = device.busy();
            if busy
                .wait_for(|b| b.as_ref().is_some_and(|b| b.bytes == bytes))
                .await
                .is_ok()
            {
                device.abort_line().await;
            }
            std::future::pending::<std::convert::Infallible>().await
        };
        tokio::select! {
            done = self.exchange(step) => done,
            never = abort => match never {},
        }
    }

    /// Send one line of a plan and read what came back; with the bytes
    /// that crossed the wire both ways. The line is adapted to the
    /// family's per-link state and held if it may run for long, as a
    /// user's line is.
    async fn exchange(&self, step: &PlanLine) -> (Answer, u64) {
        let console = self.family.console;
        let context = self.current_context();
        let line = &adapt_line(console, &step.line, context.as_deref());
        let priority = if step.after_polls {
            Priority::Poll
        } else {
            Priority::Transfer
        };
        let retry = match (&line.answering, line.effect) {
            // An answer that may be lost is never asked for twice.
            (Answering::MaybeReply(_), _) => Retry::Never,
            (_, Effect::Reads) => Retry::Read(self.read_retries),
            (_, Effect::Acts) => Retry::Never,
        };
        let transaction = self.transaction(line, retry, None);
        let sent = line.bytes.len() as u64;
        let frames = match self.device.transact(priority, transaction).await {
            Ok(answer) => answer.frames,
            Err(DeviceError::Timeout { .. })
                if matches!(line.answering, Answering::MaybeReply(_)) =>
            {
                Vec::new()
            }
            Err(error) => {
                let answer = Answer {
                    line: line.canonical.clone(),
                    frames: Vec::new(),
                    result: Err(AnswerError::Lost {
                        address: line.address,
                        reason: error.to_string(),
                    }),
                };
                return (answer, sent);
            }
        };
        let received: u64 = frames.iter().map(|f| f.len() as u64).sum();
        let result =
            interpret_line(console, line, &frames, context.as_deref()).map_err(AnswerError::Reply);
        if result.is_ok()
            && let (Some(contexts), Some(context)) = (console.link_contexts(), &context)
            && let Some(changed) = contexts.after(line, context.as_ref())
        {
            self.context.send_replace(Some(changed));
        }
        let answer = Answer {
            line: line.canonical.clone(),
            frames,
            result,
        };
        (answer, sent + received)
    }
}

/// A session error as the answer a plan or a host run reads.
pub fn answer_of(line: &str, result: &Result<super::LineResult, SessionError>) -> Answer {
    match result {
        Ok(r) => Answer {
            line: r.line.clone(),
            frames: vec![r.reply.clone()],
            result: Ok(crate::protocol::console::Reading {
                status: r.status,
                value: r.value.clone(),
            }),
        },
        Err(SessionError::Refused { message, .. }) => Answer {
            line: line.to_string(),
            frames: Vec::new(),
            result: Err(AnswerError::Refused(message.clone())),
        },
        Err(SessionError::Reply { error, reply, .. }) => Answer {
            line: line.to_string(),
            frames: vec![reply.clone()],
            result: Err(AnswerError::Reply(error.as_ref().clone())),
        },
        Err(SessionError::Device {
            line: canonical,
            address,
            error,
            ..
        }) => Answer {
            line: canonical.clone(),
            frames: Vec::new(),
            result: Err(AnswerError::Lost {
                address: *address,
                reason: error.to_string(),
            }),
        },
    }
}
