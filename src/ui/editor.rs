//! The program editor: TMCL program source with syntax colours and line
//! numbers, assembled after every change so that the lines that do not
//! assemble are marked as they are typed; open, save, save as; and a
//! safety copy in the data directory ([`autosave`]) written shortly after
//! each change, offered again when the console starts after a crash.
//!
//! The text is kept and edited by `ratatui-textarea`; this pane draws it
//! itself, because the colours come from the assembler's syntax.
//!
//! While a program runs, its registers (mode, PC, accumulator, X) are read
//! over and over, and with them the user variables chosen to be watched
//! ([`watch`]), shown in a panel beside the text.
//!
//! The text may be A-Script instead, the CMD-4CR's language ([`script`]):
//! chosen by a `.asc` file, by a CMD-4CR connection, or by the language
//! key. Then the colours and the marked lines come from the A-Script
//! lexer and checker, the run keys drive programs already in the
//! controller over the wire (`SACTRL`, `SASTAT`, `SPC`, `V`), the
//! download key loads the in-process simulator (the manual documents no
//! download to real hardware, and the editor says so), and the run-from-
//! host key runs the text statement by statement from here
//! ([`script_run`]).

pub mod autosave;

pub mod script;
mod script_run;
pub mod transfer;
pub mod watch;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

use ratatui::Frame;
use ratatui::crossterm::event::{KeyCode, KeyEvent};
use ratatui::layout::{Position, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph};
use ratatui_textarea::{CursorMove, TextArea};

use super::field::Field;
use super::keymap::{Action, Context};
use super::pane::{
    Input, Notice, NoticeLevel, Outcome, Pane, PaneEvent, Region, Request, View, key_label,
};
use super::theme::Role;
use crate::protocol::tmcl::asm::highlight::{Names, Token, highlight};
use crate::protocol::tmcl::asm::{AsmError, NoIncludes, Program, SourceLoader, assemble};
use autosave::{Autosave, read_autosave, remove_autosave, utc_time, write_autosave};
use script::{Language, Problem};
use watch::{
    MAX_WATCHED, load_watch_list, save_watch_list, variable_line, variable_of_line,
    variable_of_word,
};

/// How long the text must stay unchanged before the safety copy is
/// written: a burst of typing is one write, and a pause of this long
/// is the most that a crash can lose.
pub const AUTOSAVE_QUIET: Duration = Duration::from_millis(300);

/// The name a TMCL buffer without a file is assembled under.
const UNTITLED: &str = "untitled.tmc";

/// Reads `#include`d files from disk, relative to the including file.
struct SourceFiles;

impl SourceLoader for SourceFiles {
    fn load(&self, path: &str) -> Result<String, String> {
        std::fs::read_to_string(path).map_err(|e| e.to_string())
    }
}

/// A file name being typed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PromptKind {
    Open,
    SaveAs,
    /// The number of a user variable to watch (or stop watching).
    Watch,
    /// The same for an A-Script variable V0–V99.
    WatchScript,
}

impl PromptKind {
    fn label(self) -> &'static str {
        match self {
            PromptKind::Open => "open file: ",
            PromptKind::SaveAs => "save as: ",
            PromptKind::Watch => "watch user variable (0..255; a watched one stops): ",
            PromptKind::WatchScript => "watch variable V (0..99; a watched one stops): ",
        }
    }
}

/// Text the console recovered from the safety copy at start.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Recovered {
    pub file: Option<PathBuf>,
    /// When the copy was written (seconds since 1970, UTC).
    pub written: u64,
}

/// Tags of the lines this pane sends, and of its register timer; the
/// safety-copy timers use the change count, far below these.
const TAG_CONTROL: u64 = 1 << 48;
const TAG_WATCH: u64 = (1 << 48) + 1;
const TAG_WATCH_TIMER: u64 = (1 << 48) + 2;
/// Reads of user variables outside the register batch (one just added).
const TAG_VARIABLE: u64 = (1 << 48) + 3;
/// Loading the text into the simulator.
const TAG_LOAD: u64 = (1 << 48) + 4;
/// The host run's requests count up from here.
const TAG_HOST_FIRST: u64 = 1 << 49;

/// Columns of the watch panel, and the least the text keeps beside it;
/// below that the variables go to the bottom line.
const PANEL_WIDTH: u16 = 22;
const PANEL_MIN_TEXT: u16 = 40;

/// How often the registers are read while the program runs.
pub const WATCH_PERIOD: Duration = Duration::from_millis(200);

/// The lines that read the program's state: the application status and
/// the program counter as global parameters GP128 and GP130 (§5.1 Table
/// 18), the accumulator and X with command 135 types 2 and 3 (§3.6.53).
/// Command 135 types 0 and 1 would give the mode and the PC too, but packed
/// with a wait flag in a layout Table 14 does not give.
pub const WATCH_LINES: [&str; 4] = ["GGP 128, 0", "GGP 130, 0", "APPSTATUS ACCU", "APPSTATUS X"];

/// The program's state as the module last told it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Watch {
    /// 0 stopped, 1 running, 2 stepping, 3 reset (GP128, §5.1).
    pub mode: Option<i64>,
    pub pc: Option<i64>,
    pub accu: Option<i64>,
    pub x: Option<i64>,
}

impl Watch {
    fn mode_name(&self) -> &'static str {
        match self.mode {
            Some(0) => "stopped",
            Some(1) => "running",
            Some(2) => "stepping",
            Some(3) => "reset",
            Some(_) => "?",
            None => "-",
        }
    }
}

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
    program: Option<Program>,
    errors: Vec<AsmError>,
    prompt: Option<(PromptKind, Field)>,
    message: Option<Notice>,
    recovered: Option<Recovered>,
    /// F3 was pressed with unsaved changes: the next F3 opens anyway.
    open_confirmed: bool,
    /// Shift-F3 was pressed with unsaved changes: the next uploads anyway.
    upload_confirmed: bool,
    /// The program transfer under way.
    transfer: Option<transfer::Running>,
    /// The source line (0-based) of the word the last transfer failed at.
    failed_line: Option<usize>,
    /// The source line (0-based) the program counter is on.
    current: Option<usize>,
    /// The program's registers as last read from the module.
    watch: Watch,
    /// Reading the registers again and again while the program runs.
    watching: bool,
    /// The line the register batch under way ends with: its answer decides
    /// whether to read again.
    watch_last: Option<String>,
    /// The user variables watched, and their values as last read.
    variables: BTreeMap<u8, Option<i64>>,
    /// First line and column shown, and rows shown at the last draw.
    top: usize,
    left: usize,
    rows: usize,
    /// What the text is written in.
    language: Language,
    /// The language came from the file's extension or the language key:
    /// a connection does not change it.
    language_fixed: bool,
    /// The A-Script check of the text (empty in TMCL mode).
    script: script::Checked,
    /// A-Script: the controller's program state as last read.
    script_state: script_run::ProgramState,
    /// The watched variables of the other language (TMCL user variables
    /// 0..255, A-Script V0–V99), kept while this one is shown.
    other_variables: BTreeMap<u8, Option<i64>>,
    /// A-Script text running from the host.
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
    /// loaded and offered.
    pub fn new(data_dir: Option<PathBuf>) -> EditorPane {
        let mut pane = EditorPane {
            text: TextArea::default(),
            file: None,
            saved: String::new(),
            data_dir,
            changes: 0,
            program: None,
            errors: Vec::new(),
            prompt: None,
            message: None,
            recovered: None,
            open_confirmed: false,
            upload_confirmed: false,
            transfer: None,
            failed_line: None,
            current: None,
            watch: Watch::default(),
            watching: false,
            watch_last: None,
            variables: BTreeMap::new(),
            top: 0,
            left: 0,
            rows: 1,
            language: Language::Tmcl,
            language_fixed: false,
            script: script::Checked::default(),
            script_state: script_run::ProgramState::default(),
            other_variables: BTreeMap::new(),
            host: None,
            host_values: None,
            host_tag: TAG_HOST_FIRST,
        };
        if let Some(dir) = pane.data_dir.as_deref() {
            pane.variables = load_watch_list(dir)
                .into_iter()
                .map(|n| (n, None))
                .collect();
            pane.other_variables = watch::load_script_watch_list(dir)
                .into_iter()
                .map(|n| (n, None))
                .collect();
        }
        if let Some(copy) = pane.data_dir.as_deref().and_then(read_autosave) {
            if let Some(language) = copy.file.as_deref().and_then(Language::of_file) {
                pane.set_language(language);
                pane.language_fixed = true;
            }
            pane.saved = copy
                .file
                .as_deref()
                .and_then(|f| std::fs::read_to_string(f).ok())
                .unwrap_or_default();
            pane.file = copy.file.clone();
            pane.set_text(&copy.text);
            pane.recovered = Some(Recovered {
                file: copy.file,
                written: copy.written,
            });
        }
        pane.assemble();
        pane
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

    /// What the assembler found wrong, in source order.
    pub fn errors(&self) -> &[AsmError] {
        &self.errors
    }

    /// The program, when the text assembles.
    pub fn program(&self) -> Option<&Program> {
        self.program.as_ref()
    }

    /// Lines (1-based) of this buffer that do not assemble (or check).
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

    /// What the assembler (or the A-Script checker) finds wrong in this
    /// buffer, in line order.
    pub fn problems(&self) -> Vec<Problem> {
        match self.language {
            Language::Tmcl => {
                let name = self.source_name();
                self.errors
                    .iter()
                    .filter(|e| e.file == name)
                    .map(|e| Problem {
                        line: e.line,
                        column: e.column,
                        text: e.to_string(),
                        error: true,
                    })
                    .collect()
            }
            Language::AScript => self.script.diagnostics.iter().map(Problem::of).collect(),
        }
    }

    /// The first error anywhere (a TMCL `#include`d file's too), for a
    /// message.
    fn first_error(&self) -> Option<String> {
        match self.language {
            Language::Tmcl => self.errors.first().map(ToString::to_string),
            Language::AScript => self
                .script
                .diagnostics
                .iter()
                .find(|d| d.is_error())
                .map(ToString::to_string),
        }
    }

    fn error_count(&self) -> usize {
        match self.language {
            Language::Tmcl => self.errors.len(),
            Language::AScript => self
                .script
                .diagnostics
                .iter()
                .filter(|d| d.is_error())
                .count(),
        }
    }

    /// Whether the text assembles (or checks).
    fn runs(&self) -> bool {
        match self.language {
            Language::Tmcl => self.program.is_some(),
            Language::AScript => self.script.program.is_some(),
        }
    }

    /// What the text is written in.
    pub fn language(&self) -> Language {
        self.language
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

    /// The program's registers as last read.
    pub fn watched(&self) -> Watch {
        self.watch
    }

    /// The user variables watched, with their values as last read.
    pub fn watched_variables(&self) -> Vec<(u8, Option<i64>)> {
        self.variables.iter().map(|(n, v)| (*n, *v)).collect()
    }

    /// The source line (0-based) of program address `pc`, through the
    /// assembled program's address map.
    pub fn line_of_pc(&self, pc: i64) -> Option<usize> {
        let name = self.source_name();
        let program = self.program.as_ref()?;
        let line = program.lines.iter().find(|l| i64::from(l.address) == pc)?;
        (line.file == name).then(|| line.line.saturating_sub(1))
    }

    /// Ask for the registers, and the user variables watched.
    fn read_registers(&mut self) -> Request {
        let lines: Vec<String> = WATCH_LINES
            .iter()
            .map(|l| l.to_string())
            .chain(self.variables.keys().map(|n| variable_line(*n)))
            .collect();
        self.watch_last = lines.last().cloned();
        Request::Send {
            lines,
            tag: TAG_WATCH,
        }
    }

    /// Send a program control line, then read the registers.
    fn control(&mut self, line: &str, watch: bool) -> Outcome {
        self.watching = watch;
        let read = self.read_registers();
        Outcome::Handled(vec![
            Request::Send {
                lines: vec![line.to_string()],
                tag: TAG_CONTROL,
            },
            read,
        ])
    }

    fn register_reply(&mut self, line: &str, value: Option<i64>) -> Vec<Request> {
        match line {
            "GGP 128, 0" => self.watch.mode = value,
            "GGP 130, 0" => {
                self.watch.pc = value;
                self.current = value.and_then(|pc| self.line_of_pc(pc));
            }
            "APPSTATUS ACCU" => self.watch.accu = value,
            "APPSTATUS X" => self.watch.x = value,
            other => self.variable_reply(other, value),
        }
        if self.watch_last.as_deref() != Some(line) {
            return Vec::new();
        }
        // The last of the batch: again later while the program runs.
        if self.watching && self.watch.mode == Some(1) {
            vec![Request::WakeAfter {
                after: WATCH_PERIOD,
                tag: TAG_WATCH_TIMER,
            }]
        } else {
            self.watching = false;
            Vec::new()
        }
    }

    /// A watched variable's value came (`None`: it could not be read).
    fn variable_reply(&mut self, line: &str, value: Option<i64>) {
        if let Some(slot) = variable_of_line(line).and_then(|n| self.variables.get_mut(&n)) {
            *slot = value;
        }
    }

    /// The user variable the cursor's line names (GGP/SGP/STGP/RSGP/AGP
    /// n, 2), read from the assembled program, or from the line alone
    /// when the whole does not assemble.
    fn variable_at_cursor(&self) -> Option<u8> {
        let row = self.cursor().0;
        let name = self.source_name();
        if let Some(program) = &self.program {
            return program
                .lines
                .iter()
                .filter(|l| l.file == name && l.line == row + 1)
                .filter_map(|l| program.words.get(usize::from(l.address)))
                .find_map(variable_of_word);
        }
        let line = self.text.lines().get(row)?;
        let alone = assemble(UNTITLED, line, &NoIncludes).ok()?;
        alone.words.iter().find_map(variable_of_word)
    }

    /// Watch user variable `n` (A-Script: `V[n]`), or stop watching it;
    /// the list is kept in the data directory, one per language.
    fn toggle_variable(&mut self, n: u8, view: &View) -> Outcome {
        let (name, read, reads) = match self.language {
            Language::Tmcl => (
                format!("user variable #{n}"),
                variable_line(n),
                view.session.is_some(),
            ),
            Language::AScript => (
                format!("V{n}"),
                script::variable_line(n),
                view.session.is_some_and(|s| s.family.name == "cmd4cr"),
            ),
        };
        let mut requests = Vec::new();
        if self.variables.remove(&n).is_some() {
            self.message = Some(Notice::info(format!("{name} no longer watched")));
        } else if self.variables.len() >= MAX_WATCHED {
            self.message = Some(Notice::warning(format!(
                "{MAX_WATCHED} variables are watched already: stop watching one first ({} on its line)",
                key_label(view.keymap, Context::Editor, Action::EditorWatch)
            )));
            return Outcome::redraw();
        } else {
            self.variables.insert(n, None);
            self.message = Some(Notice::info(if read == name {
                format!("watching {name}")
            } else {
                format!("watching {name} ({read})")
            }));
            if reads {
                requests.push(Request::Send {
                    lines: vec![read],
                    tag: match self.language {
                        Language::Tmcl => TAG_VARIABLE,
                        Language::AScript => script_run::TAG_VARIABLE,
                    },
                });
            }
        }
        if let Some(dir) = self.data_dir.as_deref() {
            let list: Vec<u8> = self.variables.keys().copied().collect();
            let saved = match self.language {
                Language::Tmcl => save_watch_list(dir, &list),
                Language::AScript => watch::save_script_watch_list(dir, &list),
            };
            if let Err(e) = saved {
                self.message = Some(Notice::error(e));
            }
        }
        Outcome::Handled(requests)
    }

    /// Whether the watch panel has room beside the text in `width`.
    fn panel_shown(&self, width: u16) -> bool {
        !self.variables.is_empty() && width >= PANEL_MIN_TEXT + PANEL_WIDTH
    }

    /// The watch panel: each variable watched and its value.
    fn render_panel(&self, frame: &mut Frame, area: Rect, view: &View) {
        let theme = view.theme;
        let block = Block::default()
            .borders(Borders::LEFT)
            .border_style(theme.style(Role::Border));
        let inner = block.inner(area);
        frame.render_widget(block, area);
        let width = usize::from(inner.width);
        let heading = match self.language {
            Language::Tmcl => " user variables",
            Language::AScript if self.host_variables_shown() => " variables (host)",
            Language::AScript => " variables",
        };
        let mut lines = vec![Line::styled(heading, theme.style(Role::Title))];
        for (n, value) in self.shown_variables() {
            let label = match self.language {
                Language::Tmcl => format!(" #{n}"),
                Language::AScript => format!(" V{n}"),
            };
            let shown = value.map_or_else(|| "—".to_string(), |v: i64| v.to_string());
            let pad = width.saturating_sub(label.chars().count() + shown.chars().count() + 1);
            lines.push(Line::from(vec![
                Span::styled(label, theme.style(Role::Muted)),
                Span::raw(" ".repeat(pad)),
                Span::styled(shown, theme.style(Role::Accent)),
            ]));
        }
        let note = if view.session.is_none() {
            " not connected".to_string()
        } else {
            format!(
                " {}: add/remove",
                key_label(view.keymap, Context::Editor, Action::EditorWatch)
            )
        };
        lines.push(Line::styled(note, theme.style(Role::Muted)));
        frame.render_widget(Paragraph::new(lines), inner);
    }

    /// The name the text is assembled under: its file, or `untitled.tmc`
    /// (`untitled.asc`).
    pub fn source_name(&self) -> String {
        self.file.as_ref().map_or_else(
            || self.language.untitled().to_string(),
            |f| f.display().to_string(),
        )
    }

    fn set_text(&mut self, text: &str) {
        let lines: Vec<String> = text.split('\n').map(str::to_string).collect();
        self.text = TextArea::new(lines);
        self.top = 0;
        self.left = 0;
    }

    fn assemble(&mut self) {
        if self.language == Language::AScript {
            self.program = None;
            self.errors.clear();
            self.script = script::check(&self.text());
            return;
        }
        self.script = script::Checked::default();
        match assemble(&self.source_name(), &self.text(), &SourceFiles) {
            Ok(program) => {
                self.program = Some(program);
                self.errors.clear();
            }
            Err(errors) => {
                self.program = None;
                self.errors = errors;
            }
        }
    }

    /// After a change to the text: assemble again, and ask for a timer
    /// for the safety copy.
    fn changed(&mut self) -> Outcome {
        self.changes += 1;
        self.open_confirmed = false;
        self.upload_confirmed = false;
        self.failed_line = None;
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
            write_autosave(&dir, &Autosave::now(self.file.clone(), self.text()))
        } else {
            remove_autosave(&dir)
        };
        if let Err(e) = result {
            self.message = Some(Notice::error(e));
        }
    }

    /// Open `path` in place of the text.
    pub fn open_file(&mut self, path: &Path) -> Result<(), String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot open {}: {e}", path.display()))?;
        self.file = Some(path.to_path_buf());
        self.saved = text.clone();
        self.set_text(&text);
        self.recovered = None;
        self.current = None;
        self.language_of_file(path);
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
    pub fn save_to(&mut self, path: &Path) -> Result<(), String> {
        let text = self.text();
        autosave::write_atomically(path, text.as_bytes())?;
        self.file = Some(path.to_path_buf());
        self.saved = text;
        self.recovered = None;
        self.language_of_file(path);
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
    /// an empty buffer), and the safety copy removed.
    fn discard_recovered(&mut self) {
        let Some(recovered) = self.recovered.take() else {
            return;
        };
        let text = recovered
            .file
            .as_deref()
            .and_then(|f| std::fs::read_to_string(f).ok())
            .unwrap_or_default();
        self.saved = text.clone();
        self.set_text(&text);
        self.assemble();
        self.write_safety_copy();
        self.message = Some(Notice::info("recovered text discarded"));
    }

    /// Move the cursor to the next line that does not assemble (or check),
    /// after the cursor (round to the first); A-Script warnings count.
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
            }
            None => {
                self.message = Some(match self.first_error() {
                    Some(e) => Notice::error(e),
                    None => Notice::info(match self.language {
                        Language::Tmcl => "no errors: the program assembles",
                        Language::AScript => "no errors: the program checks",
                    }),
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
                if kind == PromptKind::WatchScript {
                    return match name.trim_start_matches(['V', 'v']).parse::<u8>() {
                        Ok(n) if usize::from(n) < crate::protocol::cmd4cr::ascript::VARIABLES => {
                            self.toggle_variable(n, view)
                        }
                        _ => {
                            self.message = Some(Notice::error(format!(
                                "A-Script variables are V0..V99, not `{name}`"
                            )));
                            Outcome::redraw()
                        }
                    };
                }
                if kind == PromptKind::Watch {
                    return match name.parse::<u8>() {
                        Ok(n) => self.toggle_variable(n, view),
                        Err(_) => {
                            self.message = Some(Notice::error(format!(
                                "user variables are numbered 0..255, not `{name}`"
                            )));
                            Outcome::redraw()
                        }
                    };
                }
                let path = PathBuf::from(name);
                let result = match kind {
                    PromptKind::Open => self.open_file(&path),
                    PromptKind::SaveAs => self.save_to(&path),
                    PromptKind::Watch | PromptKind::WatchScript => Ok(()),
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
        if action == Action::EditorLanguage {
            return self.switch_language(view);
        }
        if let Some(outcome) = self.script_action(action, view) {
            return outcome;
        }
        match action {
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
                match &self.program {
                    Some(p) => {
                        self.message = Some(Notice::info(format!(
                            "assembled: {} words, {} labels",
                            p.words.len(),
                            p.symbols.len()
                        )))
                    }
                    None => {
                        self.text.move_cursor(CursorMove::Jump(0, 0));
                        self.next_error_from_top();
                    }
                }
            }
            Action::EditorNextError => self.next_error(),
            Action::EditorHostRun => {
                self.message = Some(Notice::warning(format!(
                    "running from the host is for A-Script (CMD-4CR); this text is TMCL: {} switches",
                    key_label(view.keymap, Context::Editor, Action::EditorLanguage)
                )));
            }
            Action::Cancel => {
                if let Some(outcome) = self.cancel_transfer() {
                    return outcome;
                }
                if self.recovered.is_some() {
                    self.discard_recovered();
                } else if self.message.take().is_none() {
                    return Outcome::Ignored;
                }
            }
            Action::EditorRun => return self.control("RUNAPP", true),
            Action::EditorStop => return self.control("STOPAPP", false),
            Action::EditorStep => return self.control("STEPAPP", false),
            Action::EditorReset => return self.control("RESETAPP", false),
            Action::EditorWatch => match self.variable_at_cursor() {
                Some(n) => return self.toggle_variable(n, view),
                None => self.prompt = Some((PromptKind::Watch, Field::default())),
            },
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

    /// The bottom line: the prompt, a message, or what the assembler says
    /// of the line under the cursor.
    fn bottom_line(&self, view: &View, width: u16) -> Line<'static> {
        let theme = view.theme;
        if let Some((kind, field)) = &self.prompt {
            return Line::from(vec![
                Span::styled(kind.label(), theme.style(Role::Prompt)),
                Span::raw(field.text().to_string()),
            ]);
        }
        if let Some(message) = &self.message {
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
        let state = match (&self.program, &self.script.program, self.error_count()) {
            (Some(p), _, _) => format!("assembles: {} words", p.words.len()),
            (_, Some(p), _) => format!("A-Script {}", script::summary(p)),
            (None, None, n) => format!(
                "{n} error{} ({} next)",
                if n == 1 { "" } else { "s" },
                key_label(view.keymap, Context::Editor, Action::EditorNextError)
            ),
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
        if let Some(state) = self.script_state.describe() {
            spans.push(Span::styled(
                format!(" │ {state}"),
                theme.style(Role::Accent),
            ));
        }
        if self.watch != Watch::default() {
            let show = |v: Option<i64>| v.map_or_else(|| "-".to_string(), |v| v.to_string());
            spans.push(Span::styled(
                format!(
                    " │ {} PC {} ACC {} X {}",
                    self.watch.mode_name(),
                    show(self.watch.pc),
                    show(self.watch.accu),
                    show(self.watch.x)
                ),
                theme.style(Role::Accent),
            ));
        }
        // No room for the watch panel: the variables here.
        if !self.variables.is_empty() && !self.panel_shown(width) {
            let mark = match self.language {
                Language::Tmcl => "#",
                Language::AScript => "V",
            };
            let values: Vec<String> = self
                .shown_variables()
                .into_iter()
                .map(|(n, v)| {
                    format!(
                        "{mark}{n}={}",
                        v.map_or_else(|| "—".to_string(), |v| v.to_string())
                    )
                })
                .collect();
            spans.push(Span::styled(
                format!(" │ {}", values.join(" ")),
                theme.style(Role::Accent),
            ));
        }
        Line::from(spans)
    }

    fn recovery_line(&self, recovered: &Recovered, view: &View) -> Line<'static> {
        let file = Autosave {
            file: recovered.file.clone(),
            written: recovered.written,
            text: String::new(),
        }
        .file_label();
        let save = key_label(view.keymap, Context::Editor, Action::EditorSave);
        let discard = key_label(view.keymap, Context::Editor, Action::Cancel);
        Line::from(Span::styled(
            format!(
                "recovered unsaved text of {file} from {} — {save} to save, or discard with {discard}",
                utc_time(recovered.written)
            ),
            view.theme.style(Role::Warning),
        ))
    }
}

/// The number an answer carries, if it is one.
fn number_read(
    result: &Result<crate::session::LineResult, crate::session::SessionError>,
) -> Option<i64> {
    match result {
        Ok(r) => match r.value {
            crate::session::ReplyValue::Number(n) => Some(n),
            _ => None,
        },
        Err(_) => None,
    }
}

/// One line of source as styled cells, `left` characters scrolled off,
/// at most `width` shown.
fn styled_line(
    line: &str,
    language: Language,
    names: &Names,
    view: &View,
    base: Style,
    left: usize,
    width: usize,
) -> Vec<Span<'static>> {
    let theme = view.theme;
    let mut spans: Vec<Span<'static>> = Vec::new();
    let mut skipped = 0;
    let mut shown = 0;
    let pieces: Vec<(std::ops::Range<usize>, Option<Role>)> = match language {
        Language::Tmcl => highlight(line, names)
            .into_iter()
            .map(|(range, token)| {
                let role = match token {
                    Token::Plain => None,
                    Token::Mnemonic => Some(Role::CodeMnemonic),
                    Token::Label => Some(Role::CodeLabel),
                    Token::Number => Some(Role::CodeNumber),
                    Token::Comment => Some(Role::CodeComment),
                };
                (range, role)
            })
            .collect(),
        Language::AScript => crate::protocol::cmd4cr::ascript::tokens(line)
            .into_iter()
            .map(|(range, class)| (range, script::role_of(class)))
            .collect(),
    };
    for (range, role) in pieces {
        let style = role.map_or(base, |r| base.patch(theme.style(r)));
        let mut piece = String::new();
        for c in line.get(range).unwrap_or("").chars() {
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
        let name = self.file.as_ref().and_then(|f| f.file_name()).map_or_else(
            || "untitled".to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        let changed = if self.modified() { "*" } else { "" };
        match self.language {
            Language::Tmcl => format!("Program — {name}{changed}"),
            Language::AScript => format!("Program (A-Script) — {name}{changed}"),
        }
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
            let line = self.recovery_line(recovered, view);
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
        let lines = self.text.lines();
        let (row, col) = self.cursor();
        if row < self.top {
            self.top = row;
        } else if rows > 0 && row >= self.top + rows {
            self.top = row + 1 - rows;
        }
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
        let names = match self.language {
            Language::Tmcl => Names::declared(lines.iter().map(String::as_str)),
            Language::AScript => Names::default(),
        };
        let mut shown = Vec::with_capacity(rows);
        for (index, line) in lines.iter().enumerate().skip(self.top).take(rows) {
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
            spans.extend(styled_line(
                line,
                self.language,
                &names,
                view,
                base,
                self.left,
                text_width,
            ));
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
                    let x = kind.label().chars().count() + field.cursor_column();
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

    fn activity(&self) -> Option<String> {
        self.host
            .as_ref()
            .map(|h| format!("editor: {}", h.describe()))
    }

    fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        if let Some(outcome) = self.transfer_event(event) {
            return outcome;
        }
        if let Some(outcome) = self.script_event(event, view) {
            return outcome;
        }
        match event {
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
            PaneEvent::Reply { tag, line, result } if *tag == TAG_WATCH => {
                if result.is_err() {
                    self.watching = false;
                }
                Outcome::Handled(self.register_reply(line, number_read(result)))
            }
            PaneEvent::Reply {
                tag,
                line,
                result: Err(e),
            } if *tag == TAG_CONTROL => {
                self.watching = false;
                self.message = Some(Notice::error(format!("{line}: {e}")));
                Outcome::redraw()
            }
            PaneEvent::Wake { tag } if *tag == TAG_WATCH_TIMER && self.watching => {
                Outcome::request(self.read_registers())
            }
            PaneEvent::Connected { .. } if !self.variables.is_empty() => {
                // Another module: its own values, read once.
                for value in self.variables.values_mut() {
                    *value = None;
                }
                Outcome::Handled(vec![Request::Send {
                    lines: self.variables.keys().map(|n| variable_line(*n)).collect(),
                    tag: TAG_VARIABLE,
                }])
            }
            PaneEvent::Reply { tag, line, result } if *tag == TAG_VARIABLE => {
                if let Err(e) = result {
                    self.message = Some(Notice::error(format!("{line}: {e}")));
                }
                self.variable_reply(line, number_read(result));
                Outcome::redraw()
            }
            PaneEvent::Stopping | PaneEvent::EmergencyStop(_) => {
                // The stop ends the program (TMCL 128): read where it
                // stopped, once.
                self.watching = false;
                Outcome::Ignored
            }
            _ => Outcome::Ignored,
        }
    }
}
