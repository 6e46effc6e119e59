//! Download, verify and upload from the editor: the pane asks the app for
//! a [`Request::Transfer`] of a [`TransferJob`], shows its progress as a
//! gauge above the bottom line, and reads the end. The plan is the text's
//! tool's ([`crate::protocol::program`]); the session's runner drives it.
//!
//! - Download (F4) checks the text first: a text that does not check is
//!   refused with its errors marked, and nothing is sent. A unit that
//!   fails is named by its address and its source line is marked.
//! - Verify (Shift-F4) compares the module's program with the text,
//!   storing nothing.
//! - Upload (Ctrl-F4) reads the program back and opens its source as a
//!   new unsaved buffer; unsaved text is asked about first, as Open does.
//! - Where the tool documents no download over the wire
//!   ([`DownloadWay::SimulatorOnly`]: A-Script), F4 loads the text into
//!   the simulator in this process and says what a real controller does
//!   instead.
//!
//! While a transfer runs the text is locked (cursor keys still move), so
//! that a failing address still maps to the line it was built from. Esc
//! cancels; so does the emergency stop (the session cancels the transfer
//! itself and the stop waits for the line on the wire).

use std::sync::Arc;

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Span;
use ratatui::widgets::Gauge;
use ratatui_textarea::CursorMove;

use super::{EditorPane, TAG_LOAD};
use crate::protocol::program::{
    CheckedProgram, DownloadOptions, DownloadWay, Progress, TransferFailure, TransferJob,
    TransferReport, UploadExtent,
};
use crate::ui::keymap::{Action, Context};
use crate::ui::pane::{Notice, Outcome, PaneEvent, Request, View, key_label};
use crate::ui::theme::Role;

/// The tag of this pane's transfers.
pub(super) const TAG_TRANSFER: u64 = (1 << 48) + 3;

/// How many units a progress bar without a total stands for.
const UNKNOWN_TOTAL: usize = 2048;

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
    /// What was sent or is compared with (download, verify): its map finds
    /// the line of a failing unit.
    program: Option<Arc<dyn CheckedProgram>>,
    progress: Option<Progress>,
    cancelling: bool,
}

impl EditorPane {
    /// The transfer running, if any, and how far it came.
    pub fn transfer(&self) -> Option<(TransferKind, Option<Progress>)> {
        self.transfer.as_ref().map(|r| (r.kind, r.progress))
    }

    /// The source line (0-based) of the unit a transfer failed at.
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
            self.message = Some(Notice::error(self.not_connected()));
            return false;
        }
        if let Some(wrong) = self.other_family(view) {
            self.message = Some(wrong);
            return false;
        }
        true
    }

    /// The program as the text checks now; `None` after saying why
    /// nothing will be sent (the errors are marked, the cursor on the
    /// first).
    fn program_to_send(&mut self, kind: TransferKind) -> Option<Arc<dyn CheckedProgram>> {
        self.assemble();
        match self.checked.program.clone() {
            Some(program) if program.size() == 0 => {
                self.message = Some(Notice::warning(format!(
                    "nothing to {}: the program has no instructions",
                    kind.name()
                )));
                None
            }
            Some(program) => Some(program),
            None => {
                self.next_error_from_top();
                let errors: Vec<String> = self.checked.errors().map(|p| p.text.clone()).collect();
                let first = errors
                    .first()
                    .map_or_else(String::new, |e| format!(": {e}"));
                let more = errors.len().saturating_sub(1);
                let more = if more > 0 {
                    format!(" (and {more} more)")
                } else {
                    String::new()
                };
                self.message = Some(Notice::error(format!(
                    "does not {}, nothing was sent{first}{more}",
                    self.tool.wording().pass
                )));
                None
            }
        }
    }

    fn begin(
        &mut self,
        kind: TransferKind,
        program: Option<Arc<dyn CheckedProgram>>,
        job: TransferJob,
    ) -> Outcome {
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
        if let DownloadWay::SimulatorOnly { why, .. } = self.tool.download_way() {
            return self.load_into_simulator(why, view);
        }
        if !self.may_transfer(view) {
            return Outcome::redraw();
        }
        let Some(program) = self.program_to_send(TransferKind::Download) else {
            return Outcome::redraw();
        };
        let job = TransferJob::Download {
            program: Arc::clone(&program),
            options: DownloadOptions::default(),
        };
        self.begin(TransferKind::Download, Some(program), job)
    }

    pub(super) fn start_verify(&mut self, view: &View) -> Outcome {
        if let DownloadWay::SimulatorOnly { why, .. } = self.tool.download_way() {
            return self.no_read_back(why, view);
        }
        if !self.may_transfer(view) {
            return Outcome::redraw();
        }
        let Some(program) = self.program_to_send(TransferKind::Verify) else {
            return Outcome::redraw();
        };
        let job = TransferJob::Verify {
            program: Arc::clone(&program),
        };
        self.begin(TransferKind::Verify, Some(program), job)
    }

    pub(super) fn start_upload(&mut self, view: &View) -> Outcome {
        if let DownloadWay::SimulatorOnly { why, .. } = self.tool.download_way() {
            return self.no_read_back(why, view);
        }
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

    /// Verify or upload where the manual documents no read-back either.
    fn no_read_back(&mut self, why: &str, view: &View) -> Outcome {
        let host = if self.tool.runs_from_host() {
            format!(
                ": {} runs this text from the host",
                key_label(view.keymap, Context::Editor, Action::EditorHostRun)
            )
        } else {
            String::new()
        };
        self.message = Some(Notice::warning(format!("{why}, nor a read-back{host}")));
        Outcome::redraw()
    }

    /// The download key where the manual documents no download: the
    /// simulator in this process takes the text; a controller cannot, and
    /// the editor says what can be done instead.
    fn load_into_simulator(&mut self, why: &str, view: &View) -> Outcome {
        let host = key_label(view.keymap, Context::Editor, Action::EditorHostRun);
        if view.session.is_none() {
            let sim = super::language::simulator_of(self.tool)
                .unwrap_or_else(|| "an in-process simulator".to_string());
            self.message = Some(Notice::warning(format!(
                "not connected; {why}. With {sim} this key loads the simulator; {host} runs the text from the host"
            )));
            return Outcome::redraw();
        }
        if let Some(wrong) = self.other_family(view) {
            self.message = Some(wrong);
            return Outcome::redraw();
        }
        self.assemble();
        if self.checked.program.is_none() {
            self.next_error_from_top();
            if let Some(message) = self.message.take() {
                self.message = Some(Notice::error(format!(
                    "does not {}, nothing loaded: {}",
                    self.tool.wording().pass,
                    message.text
                )));
            }
            return Outcome::redraw();
        }
        // As an empty download is refused: loaded, it would read as a
        // program in the simulator.
        if self.checked.program.as_ref().is_some_and(|p| p.size() == 0) {
            self.message = Some(Notice::error(
                "nothing loaded: the text holds no program (it is empty, or only blank lines)",
            ));
            return Outcome::redraw();
        }
        self.message = Some(Notice::info("loading the text into the simulator…"));
        Outcome::request(Request::LoadProgram {
            source: self.text(),
            tag: TAG_LOAD,
        })
    }

    /// What the simulator said to the text loaded into it.
    fn loaded(&mut self, result: &Result<String, String>, view: &View) {
        let DownloadWay::SimulatorOnly { why, real } = self.tool.download_way() else {
            return;
        };
        let host = key_label(view.keymap, Context::Editor, Action::EditorHostRun);
        let run = key_label(view.keymap, Context::Editor, Action::EditorRun);
        let stop = key_label(view.keymap, Context::Editor, Action::EditorStop);
        self.message = Some(match result {
            Ok(said) => {
                self.state.loaded = Some(self.text());
                let target = self
                    .checked
                    .program
                    .as_ref()
                    .and_then(|p| p.program_at(self.cursor().0 + 1))
                    .unwrap_or(0);
                let start = self.tool.control().map(|control| {
                    let line = control
                        .control(crate::protocol::program::ControlKey::Run, target, None)
                        .line;
                    let name = control
                        .program_name(target)
                        .unwrap_or_else(|| "the program".into());
                    format!("{run} starts {name} ({line}); ")
                });
                Notice::info(format!(
                    "{said}: {}{real}, {host} runs from the host",
                    start.unwrap_or_default()
                ))
            }
            // A real controller (or a served simulator): `why` says only
            // that it is no simulator here.
            Err(_) => Notice::warning(format!(
                "{why}: {host} runs this text from the host, {run}/{stop} start/stop a program already in it"
            )),
        });
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

    /// The emergency stop: the session cancels the transfer; its end still
    /// comes.
    pub(super) fn stopping_transfer(&mut self) -> bool {
        match self.transfer.as_mut() {
            Some(running) => {
                running.cancelling = true;
                true
            }
            None => false,
        }
    }

    /// Progress, the end, a load; `None`: not about a transfer of this
    /// pane.
    pub(super) fn transfer_event(&mut self, event: &PaneEvent, view: &View) -> Option<Outcome> {
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
            PaneEvent::ProgramLoaded { tag, result } if *tag == TAG_LOAD => {
                self.loaded(result, view);
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
        let unit = self.tool.unit();
        match (running.kind, result) {
            (TransferKind::Download, Ok(report)) => {
                let mut text = format!(
                    "downloaded and verified {} {unit}{}",
                    report.count,
                    if report.count == 1 { "" } else { "s" }
                );
                for said in report.facts.iter().filter_map(|f| f.said.as_ref()) {
                    text.push_str(said);
                }
                self.message = Some(Notice::info(text));
            }
            (TransferKind::Verify, Ok(report)) => {
                self.message = Some(Notice::info(format!(
                    "verified: module {} holds these {} {unit}s",
                    report.module, report.count
                )));
            }
            (TransferKind::Upload, Ok(report)) => return self.open_upload(report),
            (kind, Err(error)) => self.failed(kind, running.program.as_deref(), error),
        }
        Outcome::redraw()
    }

    fn failed(
        &mut self,
        kind: TransferKind,
        program: Option<&dyn CheckedProgram>,
        error: &TransferFailure,
    ) {
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

    /// Mark the source line that unit `address` was built from and put the
    /// cursor on it; the line (0-based), if it is in this buffer.
    fn mark_address(
        &mut self,
        program: Option<&dyn CheckedProgram>,
        address: usize,
    ) -> Option<usize> {
        let line = program?.line_of(address)?.checked_sub(1)?;
        self.failed_line = Some(line);
        let row = u16::try_from(line).unwrap_or(u16::MAX);
        self.text.move_cursor(CursorMove::Jump(row, 0));
        Some(line)
    }

    /// Upload: the source read back as a new buffer without a file.
    fn open_upload(&mut self, report: &TransferReport) -> Outcome {
        let text = report
            .program
            .as_ref()
            .map_or_else(String::new, |p| p.source.clone());
        if report.count == 0 {
            self.message = Some(Notice::warning(format!(
                "module {} holds no program ({} 0 is blank); the text is unchanged",
                report.module,
                self.tool.unit()
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
            "uploaded {} {}s from module {} into a new unsaved buffer",
            report.count,
            self.tool.unit(),
            report.module
        )));
        outcome
    }

    /// The gauge row while a transfer runs.
    pub(super) fn render_transfer(&self, frame: &mut Frame, area: Rect, view: &View) {
        let Some(running) = &self.transfer else {
            return;
        };
        let theme = view.theme;
        let unit = self.tool.unit();
        let (ratio, what) = match running.progress {
            None => (0.0, "starting".to_string()),
            Some(p) => match p.total {
                Some(total) => (
                    fraction(p.done, total),
                    format!("{} {}/{total} {unit}s", p.phase.name(), p.done),
                ),
                None => (
                    fraction(p.done, UNKNOWN_TOTAL),
                    format!(
                        "{} {} {unit}s (until a blank {unit})",
                        p.phase.name(),
                        p.done
                    ),
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
