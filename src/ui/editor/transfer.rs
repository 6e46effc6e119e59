//! Download, verify and upload from the editor: the pane asks the app for
//! a [`Request::Transfer`], shows its progress as a gauge above the
//! bottom line, and reads the end.
//!
//! - Download (F4) assembles the text first: a text that does not
//!   assemble is refused with its errors marked, and nothing is sent. The
//!   session stores and verifies every word
//!   ([`crate::session::program`]); a word that fails is named by its
//!   address and its source line is marked.
//! - Verify (Shift-F4) reads back as many words as the text assembles to
//!   (134, nothing stored) and compares them: the library has no
//!   verify-only entry, and an upload of exactly that many words is one.
//! - Upload (Shift-F3) reads until the first blank word and opens the
//!   disassembly as a new unsaved buffer; unsaved text is asked about
//!   first, as Open does.
//!
//! While a transfer runs the text is locked (cursor keys still move), so
//! that a failing address still maps to the line it was assembled from.
//! Esc cancels; so does the emergency stop (the session cancels the
//! transfer itself and the stop waits for the word on the wire).

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Span;
use ratatui::widgets::Gauge;
use ratatui_textarea::CursorMove;

use std::sync::Arc;

use super::EditorPane;
use crate::protocol::program::{
    CheckedProgram, DownloadOptions, Progress, TransferFailure, TransferJob, TransferReport,
    UploadExtent,
};
use crate::protocol::tmcl::asm::{PROGRAM_MEMORY_WORDS, Program};
use crate::protocol::tmcl::tool::TmclProgram;
use crate::ui::keymap::{Action, Context};
use crate::ui::pane::{Notice, Outcome, PaneEvent, Request, View, key_label};
use crate::ui::theme::Role;

/// The tag of this pane's transfers.
pub(super) const TAG_TRANSFER: u64 = (1 << 48) + 3;

/// Which of the three a transfer is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TransferKind {
    Download,
    Verify,
    Upload,
}

impl TransferKind {
    pub fn name(self) -> &'static str {
        match self {
            TransferKind::Download => "download",
            TransferKind::Verify => "verify",
            TransferKind::Upload => "upload",
        }
    }
}

/// A transfer the pane started and waits for.
#[derive(Debug, Clone)]
pub(super) struct Running {
    kind: TransferKind,
    /// What was sent or is compared with (download, verify): its address
    /// map finds the line of a failing word.
    program: Option<Program>,
    progress: Option<Progress>,
    cancelling: bool,
}

impl EditorPane {
    /// The transfer running, if any, and how far it came.
    pub fn transfer(&self) -> Option<(TransferKind, Option<Progress>)> {
        self.transfer.as_ref().map(|r| (r.kind, r.progress))
    }

    /// The source line (0-based) of the word a transfer failed at.
    pub fn failed_line(&self) -> Option<usize> {
        self.failed_line
    }

    /// Whether a transfer may start now; if not, says why.
    fn may_transfer(&mut self, view: &View) -> bool {
        if let Some(running) = &self.transfer {
            self.message = Some(Notice::warning(format!(
                "a {} is running: {} cancels it",
                running.kind.name(),
                key_label(view.keymap, Context::Editor, Action::Cancel)
            )));
            return false;
        }
        if view.session.is_none() {
            self.message = Some(Notice::error(
                "not connected: give :connect --sim tmcm1110 (or --port PATH, --tcp HOST:PORT)",
            ));
            return false;
        }
        true
    }

    /// The program as the text assembles now; `None` after saying why
    /// nothing will be sent (the errors are marked, the cursor on the
    /// first).
    fn program_to_send(&mut self, kind: TransferKind) -> Option<Program> {
        self.assemble();
        match self.program.clone() {
            Some(program) if program.words.is_empty() => {
                self.message = Some(Notice::warning(format!(
                    "nothing to {}: the program has no instructions",
                    kind.name()
                )));
                None
            }
            Some(program) => Some(program),
            None => {
                self.next_error_from_top();
                let first = self
                    .errors
                    .first()
                    .map_or_else(String::new, |e| format!(": {e}"));
                let more = self.errors.len().saturating_sub(1);
                let more = if more > 0 {
                    format!(" (and {more} more)")
                } else {
                    String::new()
                };
                self.message = Some(Notice::error(format!(
                    "does not assemble, nothing was sent{first}{more}"
                )));
                None
            }
        }
    }

    fn begin(&mut self, kind: TransferKind, program: Option<Program>, job: TransferJob) -> Outcome {
        self.failed_line = None;
        self.message = None;
        self.transfer = Some(Running {
            kind,
            program,
            progress: None,
            cancelling: false,
        });
        Outcome::request(Request::Transfer {
            job,
            tag: TAG_TRANSFER,
        })
    }

    pub(super) fn start_download(&mut self, view: &View) -> Outcome {
        if !self.may_transfer(view) {
            return Outcome::redraw();
        }
        let Some(program) = self.program_to_send(TransferKind::Download) else {
            return Outcome::redraw();
        };
        let job = TransferJob::Download {
            program: Arc::new(TmclProgram(program.clone())) as Arc<dyn CheckedProgram>,
            options: DownloadOptions::default(),
        };
        self.begin(TransferKind::Download, Some(program), job)
    }

    pub(super) fn start_verify(&mut self, view: &View) -> Outcome {
        if !self.may_transfer(view) {
            return Outcome::redraw();
        }
        let Some(program) = self.program_to_send(TransferKind::Verify) else {
            return Outcome::redraw();
        };
        let job = TransferJob::Verify {
            program: Arc::new(TmclProgram(program.clone())) as Arc<dyn CheckedProgram>,
        };
        self.begin(TransferKind::Verify, Some(program), job)
    }

    pub(super) fn start_upload(&mut self, view: &View) -> Outcome {
        if !self.may_transfer(view) {
            return Outcome::redraw();
        }
        if self.modified() && !self.upload_confirmed {
            self.upload_confirmed = true;
            self.message = Some(Notice::warning(format!(
                "unsaved changes: {} saves them; {} again uploads over them anyway",
                key_label(view.keymap, Context::Editor, Action::EditorSave),
                key_label(view.keymap, Context::Editor, Action::EditorUpload),
            )));
            return Outcome::redraw();
        }
        self.upload_confirmed = false;
        let job = TransferJob::Upload(UploadExtent::UntilBlank);
        self.begin(TransferKind::Upload, None, job)
    }

    /// Esc while a transfer runs: cancel it (once).
    pub(super) fn cancel_transfer(&mut self) -> Option<Outcome> {
        let running = self.transfer.as_mut()?;
        if running.cancelling {
            return Some(Outcome::redraw());
        }
        running.cancelling = true;
        Some(Outcome::request(Request::CancelTransfer))
    }

    /// Progress, the end, or the emergency stop; `None`: not about a
    /// transfer of this pane.
    pub(super) fn transfer_event(&mut self, event: &PaneEvent) -> Option<Outcome> {
        match event {
            PaneEvent::TransferProgress { tag, progress } if *tag == TAG_TRANSFER => {
                let running = self.transfer.as_mut()?;
                running.progress = Some(*progress);
                Some(Outcome::redraw())
            }
            PaneEvent::Transferred { tag, result } if *tag == TAG_TRANSFER => {
                let running = self.transfer.take()?;
                Some(self.finished(running, result))
            }
            // The session cancels the transfer for the stop; its end still
            // comes.
            PaneEvent::Stopping => {
                // The stop ends the program too (see `on_event`).
                self.watching = false;
                let running = self.transfer.as_mut()?;
                running.cancelling = true;
                Some(Outcome::redraw())
            }
            _ => None,
        }
    }

    fn finished(
        &mut self,
        running: Running,
        result: &Result<TransferReport, TransferFailure>,
    ) -> Outcome {
        match (running.kind, result) {
            (TransferKind::Download, Ok(report)) => {
                self.message = Some(Notice::info(downloaded(report)));
            }
            (TransferKind::Verify, Ok(report)) => {
                self.message = Some(Notice::info(format!(
                    "verified: module {} holds these {} words",
                    report.module, report.count
                )));
            }
            (TransferKind::Upload, Ok(report)) => return self.open_upload(report),
            (kind, Err(error)) => self.failed(kind, running.program.as_ref(), error),
        }
        Outcome::redraw()
    }

    fn failed(&mut self, kind: TransferKind, program: Option<&Program>, error: &TransferFailure) {
        if error.cancelled().is_some() {
            self.message = Some(Notice::warning(error.console_text()));
            return;
        }
        let line = error
            .address()
            .and_then(|address| self.mark_address(program, address));
        let at = line.map_or_else(String::new, |l| format!(" at source line {}", l + 1));
        self.message = Some(Notice::error(format!(
            "{} failed{at}: {error}",
            kind.name()
        )));
    }

    /// Mark the source line that `address` was assembled from and put the
    /// cursor on it; the line (0-based), if it is in this buffer.
    fn mark_address(&mut self, program: Option<&Program>, address: usize) -> Option<usize> {
        let name = self.source_name();
        let line = program?
            .lines
            .iter()
            .find(|l| usize::from(l.address) == address && l.file == name)?
            .line
            .checked_sub(1)?;
        self.failed_line = Some(line);
        let row = u16::try_from(line).unwrap_or(u16::MAX);
        self.text.move_cursor(CursorMove::Jump(row, 0));
        Some(line)
    }

    /// Upload: the disassembly as a new buffer without a file.
    fn open_upload(&mut self, report: &TransferReport) -> Outcome {
        let text = report
            .program
            .as_ref()
            .map_or_else(String::new, |p| p.source.clone());
        if report.count == 0 {
            self.message = Some(Notice::warning(format!(
                "module {} holds no program (word 0 is blank); the text is unchanged",
                report.module
            )));
            return Outcome::redraw();
        }
        self.file = None;
        self.saved = String::new();
        self.set_text(text.strip_suffix('\n').unwrap_or(&text));
        self.recovered = None;
        self.current = None;
        let outcome = self.changed();
        self.message = Some(Notice::info(format!(
            "uploaded {} words from module {} into a new unsaved buffer",
            report.count, report.module
        )));
        outcome
    }

    /// The gauge row while a transfer runs.
    pub(super) fn render_transfer(&self, frame: &mut Frame, area: Rect, view: &View) {
        let Some(running) = &self.transfer else {
            return;
        };
        let theme = view.theme;
        let (ratio, what) = match running.progress {
            None => (0.0, "starting".to_string()),
            Some(p) => match p.total {
                Some(total) => (
                    fraction(p.done, total),
                    format!("{} {}/{total} words", p.phase.name(), p.done),
                ),
                None => (
                    fraction(p.done, PROGRAM_MEMORY_WORDS),
                    format!("{} {} words (until a blank word)", p.phase.name(), p.done),
                ),
            },
        };
        let after = if running.cancelling {
            "cancelling…".to_string()
        } else {
            format!(
                "{} cancels",
                key_label(view.keymap, Context::Editor, Action::Cancel)
            )
        };
        let label = format!("{}: {what} — {after}", running.kind.name());
        let gauge = Gauge::default()
            .ratio(ratio)
            .use_unicode(true)
            .label(Span::raw(label))
            .gauge_style(
                theme
                    .style(Role::GaugeFill)
                    .patch(theme.style(Role::GaugeEmpty)),
            );
        frame.render_widget(gauge, area);
    }
}

fn fraction(done: usize, total: usize) -> f64 {
    if total == 0 {
        return 1.0;
    }
    (done as f64 / total as f64).clamp(0.0, 1.0)
}

fn downloaded(report: &TransferReport) -> String {
    let mut text = format!(
        "downloaded and verified {} word{}",
        report.count,
        if report.count == 1 { "" } else { "s" }
    );
    for said in report.facts.iter().filter_map(|f| f.said.as_ref()) {
        text.push_str(said);
    }
    text
}
