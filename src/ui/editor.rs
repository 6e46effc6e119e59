//! The program editor: a standalone program's source with syntax colours
//! and line numbers, checked after every change so that the lines that do
//! not check are marked as they are typed; open, save, save as; and a
//! safety copy in the data directory ([`autosave`]) written shortly after
//! each change, offered again, in its own language, when the console
//! starts after a crash.
//!
//! The editor names no language: it holds the program tool of the text
//! ([`ProgramTool`], [`language`]): the first family's at start, the one a
//! file's extension names, the connected family's, or the one the language
//! key chose. The tool checks the text, colours it, says which variables
//! can be watched and which lines run, stop and read a program in the
//! controller (`control`), how the text reaches the controller
//! ([`transfer`]: a download plan, or only the in-process simulator), and
//! whether it runs from the host (`host`).
//!
//! The text is kept and edited by `ratatui-textarea`; this pane draws it
//! itself, because the colours come from the tool's syntax.

pub mod autosave;
mod control;
mod host;
pub mod language;
pub mod transfer;
pub mod watch;

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Duration;

use ratatui::Frame;
use ratatui::crossterm::event::{KeyCode, KeyEvent};
use ratatui::layout::{Position, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui_textarea::{CursorMove, TextArea};

use super::field::Field;
use super::keymap::{Action, Context};
use super::pane::{
    Input, Notice, NoticeLevel, Outcome, Pane, PaneEvent, Region, Request, View, key_label,
};
use super::text::fit;
use super::theme::Role;
use crate::protocol::program::{
    Checked, ControlKey, Problem, ProgramTool, SourceLoader, SyntaxClass, Wording, untitled,
};
use autosave::{Autosave, read_autosave, remove_autosave, utc_time, write_autosave};
pub use control::ProgramState;
use language::{default_tool, registered_tools, role_of, same};

/// How long the text must stay unchanged before the safety copy is
/// written: a burst of typing is one write, and a pause of this long
/// is the most that a crash can lose.
pub const AUTOSAVE_QUIET: Duration = Duration::from_millis(300);

use crate::files::SourceFiles;

/// Plain text, for a console that knows no program language at all.
struct PlainText;

impl ProgramTool for PlainText {
    fn name(&self) -> &'static str {
        "text"
    }

    fn controller(&self) -> &'static str {
        "controller"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &["txt"]
    }

    fn check(&self, _name: &str, _source: &str, _files: &dyn SourceLoader) -> Checked {
        Checked::default()
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
            .map(|l| vec![(0..l.len(), SyntaxClass::Plain)])
            .collect()
    }
}

/// A file name or number being typed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PromptKind {
    Open,
    SaveAs,
    /// The number of a variable to watch (or stop watching).
    Watch,
}

/// Text the console recovered from the safety copy at start.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Recovered {
    pub file: Option<PathBuf>,
    /// When the copy was written (seconds since 1970, UTC).
    pub written: u64,
    /// The language it came back in.
    pub language: &'static str,
}

/// Tags of the lines this pane sends, and of its state timer; the
/// safety-copy timers use the change count, far below these.
const TAG_CONTROL: u64 = 1 << 48;
const TAG_STATUS: u64 = (1 << 48) + 1;
const TAG_STATUS_TIMER: u64 = (1 << 48) + 2;
/// Reads of variables outside the state batch (one just added).
const TAG_VARIABLE: u64 = (1 << 48) + 3;
/// Loading the text into the simulator.
const TAG_LOAD: u64 = (1 << 48) + 4;
/// The host run's requests count up from here.
const TAG_HOST_FIRST: u64 = 1 << 49;

/// Columns of the watch panel, and the least the text keeps beside it;
/// below that the variables go to the bottom line.
const PANEL_WIDTH: u16 = 22;
/// Columns a line's annotation needs beside it to be shown at all.
const NOTE_MIN: usize = 12;
const PANEL_MIN_TEXT: u16 = 40;

/// How often the program's state is read while it runs.
pub const WATCH_PERIOD: Duration = Duration::from_millis(200);

/// How long a message stays on the bottom line: long enough to read,
/// short enough not to hide what the editor shows by itself.
pub const MESSAGE_LIFETIME: Duration = Duration::from_secs(10);

/// Tags of the message timers count up from here.
const TAG_MESSAGE: u64 = 1 << 47;

/// The program editor pane.
pub struct EditorPane {
    text: TextArea<'static>,
    file: Option<PathBuf>,
    /// The text as last opened or saved: anything else is unsaved.
    saved: String,
    data_dir: Option<PathBuf>,
    /// Changes so far; a safety-copy timer carries the count it was set
    /// at, and writes only if no change came since.
    changes: u64,
    /// What the text is written for.
    tool: &'static dyn ProgramTool,
    /// The tool came from the file's extension, the safety copy or the
    /// language key: a connection does not change it.
    tool_fixed: bool,
    /// The tool's check of the text.
    checked: Checked,
    prompt: Option<(PromptKind, Field)>,
    message: Option<Notice>,
    /// The message's number: its timer carries it.
    message_seq: u64,
    /// When the message came and when the program's state last changed,
    /// on one count: the newer of the two is shown (state wins over an
    /// older message).
    message_at: u64,
    state_at: u64,
    clock: u64,
    recovered: Option<Recovered>,
    /// The message the check's problems made (F9, the next-error key): it
    /// speaks of the text as it was, so a change takes it away (the line
    /// under the cursor still shows its own problem).
    check_notice: Option<Notice>,
    /// F3 was pressed with unsaved changes: the next F3 opens anyway.
    open_confirmed: bool,
    /// The host-run key was pressed on a text with lines the family wants
    /// confirmed: the next press runs it.
    host_confirmed: bool,
    /// Upload (Ctrl-F4) was pressed with unsaved changes: the next uploads anyway.
    upload_confirmed: bool,
    /// The program transfer under way.
    transfer: Option<transfer::Running>,
    /// The source line (0-based) of the unit the last transfer failed at.
    failed_line: Option<usize>,
    /// The source line (0-based) the program counter is on.
    current: Option<usize>,
    /// The program in the controller as last read.
    state: ProgramState,
    /// The variables watched, per tool (its variable set's key), and
    /// their values as last read.
    variables: BTreeMap<&'static str, BTreeMap<u8, Option<i64>>>,
    /// First line and column shown, and rows shown at the last draw.
    top: usize,
    left: usize,
    rows: usize,
    /// The text running from the host.
    host: Option<super::host_run::ConsoleHostRun>,
    /// The variables of the last host run, shown until the controller's
    /// are read.
    host_values: Option<Vec<i32>>,
    /// The last tag given to a request of the host run.
    host_tag: u64,
}

impl EditorPane {
    /// An empty editor keeping its safety copy in `data_dir` (`None`: no
    /// copy). A copy left there by a console that did not get to save is
    /// loaded and offered, in its own language.
    pub fn new(data_dir: Option<PathBuf>) -> EditorPane {
        let tool = default_tool().unwrap_or(&PlainText);
        let mut pane = EditorPane {
            text: TextArea::default(),
            file: None,
            saved: String::new(),
            data_dir,
            changes: 0,
            tool,
            tool_fixed: false,
            checked: Checked::default(),
            prompt: None,
            message: None,
            message_seq: 0,
            message_at: 0,
            state_at: 0,
            clock: 0,
            recovered: None,
            check_notice: None,
            open_confirmed: false,
            host_confirmed: false,
            upload_confirmed: false,
            transfer: None,
            failed_line: None,
            current: None,
            state: ProgramState::default(),
            variables: BTreeMap::new(),
            top: 0,
            left: 0,
            rows: 1,
            host: None,
            host_values: None,
            host_tag: TAG_HOST_FIRST,
        };
        pane.load_variables();
        if let Some(copy) = pane.data_dir.as_deref().and_then(read_autosave) {
            pane.recover(copy);
        }
        pane.assemble();
        pane
    }

    /// Take the safety copy `copy` as the text, in the language it was
    /// written in (else the one its file's extension names).
    fn recover(&mut self, copy: Autosave) {
        let tools = registered_tools();
        let written_in = copy
            .language
            .as_deref()
            .and_then(|name| tools.iter().copied().find(|t| t.name() == name));
        match written_in {
            Some(tool) => {
                self.set_tool(tool);
                self.tool_fixed = true;
            }
            None => {
                if let Some(file) = copy.file.as_deref() {
                    self.tool_of_file(file);
                }
            }
        }
        self.saved = copy
            .file
            .as_deref()
            .and_then(|f| crate::files::read_text(f).ok())
            .unwrap_or_default();
        self.file = copy.file.clone();
        self.set_text(&copy.text);
        self.recovered = Some(Recovered {
            file: copy.file,
            written: copy.written,
            language: self.tool.name(),
        });
    }

    /// The whole text, lines joined with `\n`.
    pub fn text(&self) -> String {
        self.text.lines().join("\n")
    }

    pub fn lines(&self) -> &[String] {
        self.text.lines()
    }

    pub fn file(&self) -> Option<&Path> {
        self.file.as_deref()
    }

    /// Whether the text differs from the file as last opened or saved.
    pub fn modified(&self) -> bool {
        self.text() != self.saved
    }

    /// The tool the text is written for.
    pub fn tool(&self) -> &'static dyn ProgramTool {
        self.tool
    }

    /// The tool's check of the text.
    pub fn checked(&self) -> &Checked {
        &self.checked
    }

    /// Lines (1-based) of this buffer that do not check.
    pub fn error_lines(&self) -> Vec<usize> {
        let mut lines: Vec<usize> = self
            .problems()
            .iter()
            .filter(|p| p.error)
            .map(|p| p.line)
            .collect();
        lines.dedup();
        lines
    }

    /// Lines (1-based) with a warning and no error.
    pub fn warning_lines(&self) -> Vec<usize> {
        let errors = self.error_lines();
        let mut lines: Vec<usize> = self
            .problems()
            .iter()
            .filter(|p| !p.error && !errors.contains(&p.line))
            .map(|p| p.line)
            .collect();
        lines.dedup();
        lines
    }

    /// What the tool finds wrong in this buffer (not in files it
    /// includes), in line order.
    pub fn problems(&self) -> Vec<Problem> {
        self.checked
            .problems
            .iter()
            .filter(|p| p.in_source)
            .cloned()
            .collect()
    }

    /// The first error anywhere (an included file's too), for a message.
    fn first_error(&self) -> Option<String> {
        self.checked.errors().next().map(|p| p.text.clone())
    }

    fn error_count(&self) -> usize {
        self.checked.errors().count()
    }

    /// Whether the text checks.
    fn runs(&self) -> bool {
        self.checked.program.is_some()
    }

    fn wording(&self) -> Wording {
        self.tool.wording()
    }

    /// The cursor: line and column, 0-based.
    pub fn cursor(&self) -> (usize, usize) {
        let c = self.text.cursor();
        (c.0, c.1)
    }

    pub fn recovered(&self) -> Option<&Recovered> {
        self.recovered.as_ref()
    }

    /// The message shown at the bottom, if any.
    pub fn message(&self) -> Option<&Notice> {
        self.message.as_ref()
    }

    /// Mark the source line (0-based) the program counter is on, or none.
    pub fn set_current_line(&mut self, line: Option<usize>) {
        self.current = line;
    }

    pub fn current_line(&self) -> Option<usize> {
        self.current
    }

    /// The program in the controller as last read.
    pub fn program_state(&self) -> &ProgramState {
        &self.state
    }

    /// The name the text is checked under: its file, or `untitled.EXT`
    /// after the tool's first extension.
    pub fn source_name(&self) -> String {
        self.file
            .as_ref()
            .map_or_else(|| untitled(self.tool), |f| f.display().to_string())
    }

    fn set_text(&mut self, text: &str) {
        let lines: Vec<String> = text.split('\n').map(str::to_string).collect();
        self.text = TextArea::new(lines);
        self.top = 0;
        self.left = 0;
    }

    /// Check the text again.
    fn assemble(&mut self) {
        self.checked = self
            .tool
            .check(&self.source_name(), &self.text(), &SourceFiles);
    }

    /// After a change to the text: check again, and ask for a timer for
    /// the safety copy. Recovered text that is edited is the user's now:
    /// Esc no longer throws it away.
    fn changed(&mut self) -> Outcome {
        self.changes += 1;
        self.open_confirmed = false;
        self.host_confirmed = false;
        self.upload_confirmed = false;
        self.failed_line = None;
        self.recovered = None;
        if self.message.is_some() && self.message == self.check_notice.take() {
            self.message = None;
        }
        self.assemble();
        if self.data_dir.is_none() {
            return Outcome::redraw();
        }
        Outcome::request(Request::WakeAfter {
            after: AUTOSAVE_QUIET,
            tag: self.changes,
        })
    }

    /// Write the safety copy now (or remove it when nothing is unsaved).
    pub fn write_safety_copy(&mut self) {
        let Some(dir) = self.data_dir.clone() else {
            return;
        };
        let result = if self.modified() {
            let copy = Autosave::now(self.file.clone(), self.text()).in_language(self.tool.name());
            write_autosave(&dir, &copy)
        } else {
            remove_autosave(&dir)
        };
        if let Err(e) = result {
            self.message = Some(Notice::error(e));
        }
    }

    /// Open `path` in place of the text.
    pub fn open_file(&mut self, path: &Path) -> Result<(), String> {
        let text = crate::files::read_text(path)
            .map_err(|e| format!("cannot open {}: {e}", path.display()))?;
        self.file = Some(path.to_path_buf());
        self.saved = text.clone();
        self.set_text(&text);
        self.recovered = None;
        self.current = None;
        self.tool_of_file(path);
        self.assemble();
        self.write_safety_copy();
        self.message = Some(Notice::info(format!(
            "opened {} ({} lines)",
            path.display(),
            self.text.lines().len()
        )));
        Ok(())
    }

    /// Save the text to `path` (atomically), which becomes its file.
    /// Save as, typed in the prompt: another file that exists is refused
    /// unless `--force` comes before its name, the rule of every file axterm
    /// writes on request (issue 19, point 5); the editor's own file is
    /// saved over, as any editor does.
    fn save_as_typed(&mut self, typed: &str) -> Result<(), String> {
        let (force, name) = match typed.strip_prefix("--force") {
            Some(rest) if rest.starts_with(char::is_whitespace) => (true, rest.trim()),
            _ => (false, typed),
        };
        let path = PathBuf::from(name);
        if !force && self.file.as_deref() != Some(path.as_path()) {
            crate::files::check_destination(&path, crate::files::Existing::Refuse)
                .map_err(|e| format!("cannot save as {}: {e}", path.display()))?;
        }
        self.save_to(&path)
    }

    pub fn save_to(&mut self, path: &Path) -> Result<(), String> {
        let text = self.text();
        crate::files::write_atomically(path, text.as_bytes())
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        self.file = Some(path.to_path_buf());
        self.saved = text;
        self.recovered = None;
        self.tool_of_file(path);
        self.assemble();
        self.write_safety_copy();
        self.message = Some(Notice::info(format!(
            "saved {} ({} lines)",
            path.display(),
            self.text.lines().len()
        )));
        Ok(())
    }

    /// Forget the recovered text: back to the file as it is on disk (or
    /// an empty buffer), and the safety copy removed. Only the copy as it
    /// was recovered: once edited, the text is the user's and stays.
    /// Its language goes back to the file's, else the connected
    /// family's, else the one a fresh start has: the copy's was the
    /// copy's alone.
    fn discard_recovered(&mut self, view: &View) {
        let Some(recovered) = self.recovered.take() else {
            return;
        };
        let text = recovered
            .file
            .as_deref()
            .and_then(|f| crate::files::read_text(f).ok())
            .unwrap_or_default();
        self.saved = text.clone();
        self.set_text(&text);
        self.tool_fixed = recovered
            .file
            .as_deref()
            .is_some_and(|f| language::tool_of_file(&[self.tool], f).is_some());
        if !self.tool_fixed && !self.follow_family(view) {
            let connected = view.session.and_then(|s| s.family.console.program());
            if connected.is_none()
                && let Some(tool) = default_tool()
            {
                self.set_tool(tool);
            }
        }
        self.assemble();
        self.write_safety_copy();
        self.message = Some(Notice::info("recovered text discarded"));
    }

    /// Move the cursor to the next line that does not check, after the
    /// cursor (round to the first); warnings count.
    fn next_error(&mut self) {
        let here = self.cursor().0 + 1;
        let mine = self.problems();
        let next = mine
            .iter()
            .find(|p| p.line > here)
            .or_else(|| mine.first())
            .cloned();
        match next {
            Some(p) => {
                let row = u16::try_from(p.line.saturating_sub(1)).unwrap_or(u16::MAX);
                let col = u16::try_from(p.column.saturating_sub(1)).unwrap_or(u16::MAX);
                self.text.move_cursor(CursorMove::Jump(row, col));
                self.message = Some(if p.error {
                    Notice::error(p.text)
                } else {
                    Notice::warning(p.text)
                });
                self.check_notice = self.message.clone();
            }
            None => {
                self.message = Some(match self.first_error() {
                    Some(e) => Notice::error(e),
                    None => {
                        Notice::info(format!("no errors: the program {}", self.wording().passes))
                    }
                })
            }
        }
    }

    fn prompt_input(&mut self, key: &KeyEvent, view: &View) -> Outcome {
        let Some((kind, field)) = self.prompt.as_mut() else {
            return Outcome::Ignored;
        };
        match view.keymap.action_for(Context::Command, key) {
            Some(Action::Cancel) => {
                self.prompt = None;
                return Outcome::redraw();
            }
            Some(Action::Submit) => {
                let kind = *kind;
                let name = field.text().trim().to_string();
                self.prompt = None;
                if name.is_empty() {
                    return Outcome::redraw();
                }
                let result = match kind {
                    PromptKind::Watch => return self.watch_typed(&name, view),
                    PromptKind::Open => self.open_file(&PathBuf::from(&name)),
                    PromptKind::SaveAs => self.save_as_typed(&name),
                };
                if let Err(e) = result {
                    self.message = Some(Notice::error(e));
                }
                return Outcome::redraw();
            }
            _ => {}
        }
        if field.edit(key) {
            Outcome::redraw()
        } else {
            Outcome::Ignored
        }
    }

    /// The prompt's label.
    fn prompt_label(&self, kind: PromptKind) -> &'static str {
        match kind {
            PromptKind::Open => "open file: ",
            PromptKind::SaveAs => "save as: ",
            PromptKind::Watch => self.tool.variables().map_or("watch: ", |set| set.prompt),
        }
    }

    fn action(&mut self, action: Action, view: &View) -> Outcome {
        let free = matches!(
            action,
            Action::Cancel
                | Action::EditorNextError
                | Action::EditorDownload
                | Action::EditorVerify
                | Action::EditorUpload
        );
        if !free && self.transfer.is_some() {
            self.locked(view);
            return Outcome::redraw();
        }
        match action {
            Action::EditorLanguage => return self.switch_language(view),
            Action::EditorSave => match self.file.clone() {
                Some(path) => {
                    if let Err(e) = self.save_to(&path) {
                        self.message = Some(Notice::error(e));
                    }
                }
                None => self.prompt = Some((PromptKind::SaveAs, Field::default())),
            },
            Action::EditorSaveAs => {
                let name = self.file.as_ref().map(|f| f.display().to_string());
                self.prompt = Some((PromptKind::SaveAs, Field::new(name.unwrap_or_default())));
            }
            Action::EditorOpen => {
                if self.modified() && !self.open_confirmed {
                    self.open_confirmed = true;
                    self.message = Some(Notice::warning(format!(
                        "unsaved changes: {} saves them; {} again opens another file anyway",
                        key_label(view.keymap, Context::Editor, Action::EditorSave),
                        key_label(view.keymap, Context::Editor, Action::EditorOpen),
                    )));
                } else {
                    self.open_confirmed = false;
                    self.prompt = Some((PromptKind::Open, Field::default()));
                }
            }
            Action::EditorAssemble => {
                self.assemble();
                match self.checked.program.as_ref().map(|p| p.built()) {
                    Some(built) => self.message = Some(Notice::info(built)),
                    None => {
                        self.text.move_cursor(CursorMove::Jump(0, 0));
                        self.next_error_from_top();
                    }
                }
            }
            Action::EditorNextError => self.next_error(),
            Action::EditorHostRun => return self.start_host_run(view),
            Action::Cancel => {
                if let Some(outcome) = self.cancel_host_run() {
                    return outcome;
                }
                if let Some(outcome) = self.cancel_transfer() {
                    return outcome;
                }
                if self.recovered.is_some() {
                    self.discard_recovered(view);
                } else if self.message.take().is_none() {
                    return Outcome::Ignored;
                }
            }
            Action::EditorRun => return self.control(ControlKey::Run, view),
            Action::EditorStop => return self.control(ControlKey::Stop, view),
            Action::EditorStep => return self.control(ControlKey::Step, view),
            Action::EditorReset => return self.control(ControlKey::Reset, view),
            Action::EditorWatch => return self.watch_key(view),
            Action::EditorDownload => return self.start_download(view),
            Action::EditorVerify => return self.start_verify(view),
            Action::EditorUpload => return self.start_upload(view),
            _ => return Outcome::Ignored,
        }
        Outcome::redraw()
    }

    /// The first error of this buffer, the cursor on it.
    fn next_error_from_top(&mut self) {
        if let Some(first) = self.problems().into_iter().find(|p| p.error) {
            let row = u16::try_from(first.line.saturating_sub(1)).unwrap_or(u16::MAX);
            let col = u16::try_from(first.column.saturating_sub(1)).unwrap_or(u16::MAX);
            self.text.move_cursor(CursorMove::Jump(row, col));
        }
        let more = self.error_count().saturating_sub(1);
        self.message = self.first_error().map(|e| {
            Notice::error(if more > 0 {
                format!("{e} (and {more} more)")
            } else {
                e
            })
        });
        self.check_notice = self.message.clone();
    }

    /// Say that the text waits for the transfer.
    fn locked(&mut self, view: &View) {
        if let Some((kind, _)) = self.transfer() {
            self.message = Some(Notice::warning(format!(
                "the text is locked while the {} runs: {} cancels it",
                kind.name(),
                key_label(view.keymap, Context::Editor, Action::Cancel)
            )));
        }
    }

    fn edit(&mut self, key: &KeyEvent, view: &View) -> Outcome {
        let moves = matches!(
            key.code,
            KeyCode::Up
                | KeyCode::Down
                | KeyCode::Left
                | KeyCode::Right
                | KeyCode::Home
                | KeyCode::End
                | KeyCode::PageUp
                | KeyCode::PageDown
        );
        if self.transfer.is_some() && !moves && !matches!(key.code, KeyCode::F(_) | KeyCode::Esc) {
            self.locked(view);
            return Outcome::redraw();
        }
        let page = self.rows.max(1);
        let (row, col) = self.cursor();
        let jump = |row: usize, col: usize| {
            CursorMove::Jump(
                u16::try_from(row).unwrap_or(u16::MAX),
                u16::try_from(col).unwrap_or(u16::MAX),
            )
        };
        match key.code {
            KeyCode::PageUp => {
                self.text.move_cursor(jump(row.saturating_sub(page), col));
                return Outcome::redraw();
            }
            KeyCode::PageDown => {
                self.text.move_cursor(jump(row.saturating_add(page), col));
                return Outcome::redraw();
            }
            // Function keys the keymap does not bind here belong to nobody.
            KeyCode::F(_) | KeyCode::Esc => return Outcome::Ignored,
            _ => {}
        }
        let before = self.text.lines().to_vec();
        self.text.input(ratatui_textarea::Input::from(*key));
        if self.text.lines() != before.as_slice() {
            self.changed()
        } else {
            Outcome::redraw()
        }
    }

    /// The next tick of the count that orders messages and state.
    fn tick(&mut self) -> u64 {
        self.clock += 1;
        self.clock
    }

    /// The program's state as shown changed: it wins over older messages.
    pub(super) fn state_changed(&mut self) {
        self.state_at = self.tick();
    }

    /// After an input or an event: a new message gets its time and a
    /// timer that puts it away.
    fn after(&mut self, before: Option<Notice>, outcome: Outcome) -> Outcome {
        if self.message == before || self.message.is_none() {
            return outcome;
        }
        self.message_at = self.tick();
        self.message_seq += 1;
        let timer = Request::WakeAfter {
            after: MESSAGE_LIFETIME,
            tag: TAG_MESSAGE + self.message_seq,
        };
        match outcome {
            Outcome::Ignored => Outcome::Handled(vec![timer]),
            Outcome::Handled(mut requests) => {
                requests.push(timer);
                Outcome::Handled(requests)
            }
        }
    }

    /// The message, unless the program's state changed since it came.
    fn shown_message(&self) -> Option<&Notice> {
        let state_shown = self
            .tool
            .control()
            .and_then(|control| self.state.describe(control))
            .is_some();
        let older = state_shown && self.state_at > self.message_at;
        self.message.as_ref().filter(|_| !older)
    }

    /// The bottom line: the prompt, a message, or what the tool says of
    /// the line under the cursor.
    fn bottom_line(&self, view: &View, width: u16) -> Line<'static> {
        let theme = view.theme;
        if let Some((kind, field)) = &self.prompt {
            return Line::from(vec![
                Span::styled(self.prompt_label(*kind), theme.style(Role::Prompt)),
                Span::raw(field.text().to_string()),
            ]);
        }
        if let Some(message) = self.shown_message() {
            let role = match message.level {
                NoticeLevel::Info => Role::Ok,
                NoticeLevel::Warning => Role::Warning,
                NoticeLevel::Error => Role::Error,
            };
            return Line::from(Span::styled(message.text.clone(), theme.style(role)));
        }
        let here = self.cursor().0 + 1;
        if let Some(p) = self.problems().into_iter().find(|p| p.line == here) {
            let role = if p.error { Role::Error } else { Role::Warning };
            return Line::from(Span::styled(p.text, theme.style(role)));
        }
        if let Some(host) = &self.host {
            return Line::from(Span::styled(
                format!(
                    "{}: {} stops it",
                    host.describe(),
                    key_label(view.keymap, Context::Editor, Action::Cancel)
                ),
                theme.style(Role::Warning),
            ));
        }
        let file = match &self.file {
            Some(f) => f.display().to_string(),
            None => "untitled".to_string(),
        };
        let changed = if self.modified() { " [modified]" } else { "" };
        let state = match &self.checked.program {
            Some(program) => program.state(),
            None => {
                let n = self.error_count();
                format!(
                    "{n} error{} ({} next)",
                    if n == 1 { "" } else { "s" },
                    key_label(view.keymap, Context::Editor, Action::EditorNextError)
                )
            }
        };
        let role = if self.runs() {
            Role::Muted
        } else {
            Role::Error
        };
        let mut spans = vec![
            Span::styled(format!("{file}{changed} — "), theme.style(Role::Muted)),
            Span::styled(state, theme.style(role)),
        ];
        if let Some(state) = self
            .tool
            .control()
            .and_then(|control| self.state.describe(control))
        {
            spans.push(Span::styled(
                format!(" │ {state}"),
                theme.style(Role::Accent),
            ));
        }
        // No room for the watch panel: the variables here.
        if !self.panel_shown(width)
            && let Some(values) = self.variables_inline()
        {
            spans.push(Span::styled(
                format!(" │ {values}"),
                theme.style(Role::Accent),
            ));
        }
        Line::from(spans)
    }

    /// The banner of recovered text: its keys first, so that they are
    /// seen at 80 columns whatever the file's name.
    fn recovery_line(&self, recovered: &Recovered, view: &View, width: u16) -> Line<'static> {
        let file = Autosave {
            file: recovered.file.clone(),
            written: recovered.written,
            text: String::new(),
            language: None,
        }
        .file_label();
        let save = key_label(view.keymap, Context::Editor, Action::EditorSave);
        let discard = key_label(view.keymap, Context::Editor, Action::Cancel);
        let text = format!(
            "{save} to save, or discard with {discard}: recovered unsaved text of {file} from {} ({})",
            utc_time(recovered.written),
            recovered.language
        );
        Line::from(Span::styled(
            fit(&text, usize::from(width)),
            view.theme.style(Role::Warning),
        ))
    }

    /// The pane's title: the file, and the language unless it is the
    /// first family's.
    fn title_text(&self) -> String {
        let name = self.file.as_ref().and_then(|f| f.file_name()).map_or_else(
            || "untitled".to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        let changed = if self.modified() { "*" } else { "" };
        if default_tool().is_some_and(|d| same(d, self.tool)) {
            format!("Program — {name}{changed}")
        } else {
            format!("Program ({}) — {name}{changed}", self.tool.name())
        }
    }
}

/// The number an answer carries, if it is one.
fn number_read(
    result: &Result<crate::session::LineResult, crate::session::SessionError>,
) -> Option<i64> {
    result.as_ref().ok()?.value.number()
}

/// One line of source as styled cells, `left` characters scrolled off,
/// at most `width` shown.
fn styled_line(
    line: &str,
    pieces: &[(Range<usize>, SyntaxClass)],
    view: &View,
    base: Style,
    left: usize,
    width: usize,
) -> Vec<Span<'static>> {
    let theme = view.theme;
    let mut spans: Vec<Span<'static>> = Vec::new();
    let mut skipped = 0;
    let mut shown = 0;
    for (range, class) in pieces {
        let style = role_of(*class).map_or(base, |r| base.patch(theme.style(r)));
        let mut piece = String::new();
        for c in line.get(range.clone()).unwrap_or("").chars() {
            if skipped < left {
                skipped += 1;
                continue;
            }
            if shown >= width {
                break;
            }
            piece.push(if c.is_control() { ' ' } else { c });
            shown += 1;
        }
        if !piece.is_empty() {
            spans.push(Span::styled(piece, style));
        }
    }
    spans
}

impl Pane for EditorPane {
    fn name(&self) -> &'static str {
        "editor"
    }

    fn context(&self) -> Context {
        Context::Editor
    }

    fn title(&self, _view: &View) -> String {
        self.title_text()
    }

    fn region(&self) -> Region {
        Region::Main
    }

    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        if area.height == 0 || area.width == 0 {
            return;
        }
        let theme = view.theme;
        let mut y = area.y;
        let mut rows = usize::from(area.height);
        if let Some(recovered) = &self.recovered
            && rows > 2
        {
            let line = self.recovery_line(recovered, view, area.width);
            frame.render_widget(Paragraph::new(line), Rect::new(area.x, y, area.width, 1));
            y += 1;
            rows -= 1;
        }
        // The bottom line.
        rows = rows.saturating_sub(1);
        let bottom_y = y + u16::try_from(rows).unwrap_or(0);
        frame.render_widget(
            Paragraph::new(self.bottom_line(view, area.width)),
            Rect::new(area.x, bottom_y, area.width, 1),
        );
        // The progress of a transfer, above the bottom line.
        if self.transfer.is_some() && rows > 1 {
            rows -= 1;
            let gauge_y = y + u16::try_from(rows).unwrap_or(0);
            self.render_transfer(frame, Rect::new(area.x, gauge_y, area.width, 1), view);
        }
        self.rows = rows.max(1);
        let (row, col) = self.cursor();
        if row < self.top {
            self.top = row;
        } else if rows > 0 && row >= self.top + rows {
            self.top = row + 1 - rows;
        }
        let lines = self.text.lines();
        let digits = lines.len().to_string().len().max(3);
        let gutter = digits + 2;
        // The watch panel takes the right of the text rows.
        let panel = self.panel_shown(area.width);
        let text_cols = if panel {
            area.width - PANEL_WIDTH
        } else {
            area.width
        };
        let text_width = usize::from(text_cols).saturating_sub(gutter);
        if col < self.left {
            self.left = col;
        } else if text_width > 0 && col >= self.left + text_width {
            self.left = col + 1 - text_width;
        }
        let error_lines = self.error_lines();
        let warning_lines = self.warning_lines();
        let running = self.running_lines();
        let end = (self.top + rows).min(lines.len());
        let classes = self.tool.highlight(lines, self.top..end);
        // What the tool says of a line in words, beside it where there is
        // room (an SQPack frame's command).
        let notes = self.tool.annotations(lines, self.top..end);
        let mut shown = Vec::with_capacity(rows);
        for (((index, line), pieces), note) in lines
            .iter()
            .enumerate()
            .skip(self.top)
            .take(rows)
            .zip(classes.iter())
            .zip(notes.iter().chain(std::iter::repeat(&None)))
        {
            let is_error = error_lines.contains(&(index + 1));
            let is_current = self.current == Some(index) || running.contains(&index);
            let (marker, gutter_role) = if is_current {
                ("▶", Role::CodeCurrent)
            } else if self.failed_line == Some(index) {
                ("✗", Role::CodeError)
            } else if is_error {
                ("!", Role::CodeError)
            } else if warning_lines.contains(&(index + 1)) {
                ("?", Role::Warning)
            } else {
                (" ", Role::CodeGutter)
            };
            let base = if is_current {
                theme.style(Role::CodeCurrent)
            } else {
                Style::default()
            };
            let mut spans = vec![Span::styled(
                format!("{marker}{:>digits$} ", index + 1),
                theme.style(gutter_role),
            )];
            spans.extend(styled_line(line, pieces, view, base, self.left, text_width));
            let used = line.chars().count().saturating_sub(self.left);
            let room = text_width.saturating_sub(used + 4);
            if let Some(note) = note.as_deref().filter(|_| room >= NOTE_MIN) {
                spans.push(Span::styled(
                    format!("  » {}", fit(note, room)),
                    theme.style(Role::Muted),
                ));
            }
            let mut styled = Line::from(spans);
            if is_current {
                styled = styled.style(base);
            }
            shown.push(styled);
        }
        let height = u16::try_from(rows).unwrap_or(u16::MAX);
        let text_area = Rect::new(area.x, y, text_cols, height);
        frame.render_widget(Paragraph::new(shown), text_area);
        if panel {
            let panel_area = Rect::new(area.x + text_cols, y, PANEL_WIDTH, height);
            self.render_panel(frame, panel_area, view);
        }
        if view.focused {
            match &self.prompt {
                Some((kind, field)) => {
                    let x = self.prompt_label(*kind).chars().count() + field.cursor_column();
                    let x = area.x + u16::try_from(x).unwrap_or(0).min(area.width - 1);
                    frame.set_cursor_position(Position::new(x, bottom_y));
                }
                None if rows > 0 => {
                    let x = gutter + col.saturating_sub(self.left);
                    let x = area.x + u16::try_from(x).unwrap_or(0).min(text_cols - 1);
                    let y = y + u16::try_from(row - self.top).unwrap_or(0);
                    frame.set_cursor_position(Position::new(x, y));
                }
                None => {}
            }
        }
    }

    fn handle_input(&mut self, input: &Input, view: &View) -> Outcome {
        let before = self.message.clone();
        let outcome = self.input(input, view);
        self.after(before, outcome)
    }

    fn activity(&self) -> Option<String> {
        self.host
            .as_ref()
            .map(|h| format!("editor: {}", h.describe()))
    }

    fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        let before = self.message.clone();
        let outcome = self.event(event, view);
        self.after(before, outcome)
    }
}

impl EditorPane {
    fn input(&mut self, input: &Input, view: &View) -> Outcome {
        match input {
            Input::Key(key) => {
                if self.prompt.is_some() {
                    return self.prompt_input(key, view);
                }
                if let Some(action) = view.keymap.action_for(Context::Editor, key) {
                    return self.action(action, view);
                }
                // Help, next pane, clear errors: the app's.
                if view.keymap.action_for(Context::Global, key).is_some() {
                    return Outcome::Ignored;
                }
                self.edit(key, view)
            }
            Input::Paste(text) => {
                if let Some((_, field)) = self.prompt.as_mut() {
                    field.insert_str(text);
                    return Outcome::redraw();
                }
                if self.transfer.is_some() {
                    self.locked(view);
                    return Outcome::redraw();
                }
                if self
                    .text
                    .insert_str(text.replace("\r\n", "\n").replace('\r', "\n"))
                {
                    self.changed()
                } else {
                    Outcome::Ignored
                }
            }
            Input::Mouse(_) => Outcome::Ignored,
        }
    }

    fn event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        if let PaneEvent::Wake { tag } = event
            && *tag == TAG_MESSAGE + self.message_seq
        {
            // The message has been up long enough.
            return match self.message.take() {
                Some(_) => Outcome::redraw(),
                None => Outcome::Ignored,
            };
        }
        if let Some(outcome) = self.host_event(event) {
            return outcome;
        }
        if let Some(outcome) = self.run_ended(event, view) {
            return outcome;
        }
        if let PaneEvent::Stopping = event {
            // The stop ends the program (TMCL 128) and any run from the
            // host; the session cancels a transfer itself, and its end
            // still comes.
            self.state.watching = false;
            let transfer = self.stopping_transfer();
            let host = self.stopping_host_run();
            return if transfer || host {
                Outcome::redraw()
            } else {
                Outcome::Ignored
            };
        }
        if let Some(outcome) = self.transfer_event(event, view) {
            return outcome;
        }
        if let Some(outcome) = self.control_event(event, view) {
            return outcome;
        }
        match event {
            PaneEvent::Snapshot if self.follow_family(view) => Outcome::redraw(),
            PaneEvent::Wake { tag } if *tag == self.changes => {
                self.write_safety_copy();
                // Nothing on screen changed unless writing failed.
                if self
                    .message
                    .as_ref()
                    .is_some_and(|m| m.level == NoticeLevel::Error)
                {
                    Outcome::redraw()
                } else {
                    Outcome::Ignored
                }
            }
            _ => Outcome::Ignored,
        }
    }
}
