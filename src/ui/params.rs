//! The parameter table: every axis parameter of the selected axis and
//! every global parameter by bank, from the family's tables
//! ([`ParameterSet`]), with the value read from the module, its unit and
//! real-world equivalent, range and access.
//!
//! Values are read one row at a time through the session (each read is
//! sent when the previous one is answered, so typed commands and status
//! polls get their turn and the screen never waits): when the pane first
//! gets the keyboard, on refresh, and before an export or a comparison.
//! A value is edited in place and checked (range, access) before it is
//! sent; a write is read back. Values that differ from what was first
//! read this session are highlighted. The whole configuration exports to
//! a TOML file ([`parameter_file`]); importing one shows the differences before
//! anything is written. What is read, compared and written is decided in
//! [`crate::session::params`], shared with `axterm params`; the pane only
//! sends its lines one at a time so that the screen never waits.

mod draw;

use std::collections::{HashMap, VecDeque};
use std::path::PathBuf;
use std::sync::Arc;

use ratatui::Frame;
use ratatui::crossterm::event::{KeyEvent, MouseEventKind};
use ratatui::layout::{Position, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use super::field::Field;
use super::keymap::{Action, Context};
use super::pane::{Input, Outcome, Pane, PaneEvent, Region, Request, Snapshot, View, key_label};
use super::text::fit;
use super::theme::Role;
use crate::files::Existing;
use crate::protocol::parameter_file::{self, Exported, ParamFile};
use crate::protocol::parameters::{ParamOp, ParamRow, ParamTable, ParameterSet, Scope, SpeedUnit};
use crate::protocol::settings::SettingsCache;
use crate::session::params::{self as shared, Comparison, ModuleValue as Cell, plan_writes};
use crate::session::{LineResult, SessionError};

/// The file name offered for exports and imports.
pub const DEFAULT_FILE: &str = "axterm-params.toml";

/// Rows a page key moves when the pane has not been drawn yet.
const DEFAULT_PAGE: usize = 10;

/// A parameter: its table and number.
type Key = (Scope, u16);

/// Why a line is sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Purpose {
    /// Reading values (a table, an export, a comparison).
    Read,
    /// Reading a value back after a write or restore.
    ReadBack,
    /// What the user asked for: a write, store or restore.
    User,
    /// A write of an imported file's value.
    Import,
}

/// One line waiting to be sent, for one parameter.
#[derive(Debug, Clone)]
struct Job {
    row: ParamRow,
    op: ParamOp,
    line: String,
    purpose: Purpose,
}

/// What the text field is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FileUse {
    Export,
    Import,
    Compare,
}

/// What the keys do right now.
#[derive(Debug, Clone)]
enum Mode {
    Browse,
    Filter(Field),
    Edit {
        row: ParamRow,
        field: Field,
    },
    File {
        purpose: FileUse,
        field: Field,
    },
    /// The module against a file.
    Diff(Diff),
}

/// A file compared with the module.
#[derive(Debug, Clone)]
struct Diff {
    path: PathBuf,
    /// Whether `w` writes the file's values (import) or this only shows
    /// the differences.
    import: bool,
    /// The differences, and the entries found equal (their values go
    /// into lines that write them together with a difference).
    comparison: Comparison,
    /// What was not taken from the file, and why.
    problems: Vec<String>,
    scroll: usize,
}

/// A comparison waiting for its reads.
#[derive(Debug, Clone)]
struct Comparing {
    path: PathBuf,
    import: bool,
    entries: Vec<(ParamRow, i64)>,
    problems: Vec<String>,
}

/// Reads and writes in progress, for the status line.
#[derive(Debug, Clone, Copy, Default)]
struct Progress {
    done: usize,
    total: usize,
}

/// Which connection the values belong to.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Connection {
    family: &'static str,
    link: String,
    address: u8,
}

/// A line of the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Item {
    Header(usize),
    Row(usize, usize),
}

/// The parameter table pane.
pub struct ParamsPane {
    connection: Option<Connection>,
    /// The tables of the selected axis; rebuilt when the axis changes.
    tables: Vec<ParamTable>,
    tables_for: Option<(&'static str, u8)>,
    values: HashMap<Key, Cell>,
    /// The first value read of each parameter this session.
    first: HashMap<Key, i64>,
    queue: VecDeque<Job>,
    in_flight: Option<(u64, Job)>,
    next_tag: u64,
    progress: Progress,
    /// Index into the rows shown (headers not counted).
    selected: usize,
    /// First line of the table shown.
    offset: usize,
    page: usize,
    filter: String,
    mode: Mode,
    message: Option<(Role, String)>,
    unit: SpeedUnit,
    /// The real column shows each axis's own unit (mechanics in force)
    /// instead of pps or rpm.
    axis_units: bool,
    /// Where to write an export once its reads are done.
    export: Option<(PathBuf, Existing)>,
    comparing: Option<Comparing>,
    /// The path last used, offered next time.
    last_file: String,
    importing: Option<Importing>,
    /// The settings written this session, from the snapshot: the values
    /// of rows the module cannot read back.
    known: Arc<SettingsCache>,
    /// Whether the connected family knows write-only rows from what was
    /// written ([`ParameterSet::remembers_writes`]).
    remembers_writes: bool,
}

/// An import being written, for the message when it is done.
#[derive(Debug, Clone)]
struct Importing {
    path: PathBuf,
    written: usize,
    failed: usize,
    /// Why values could not be written (the first is said).
    problems: Vec<String>,
    /// Link settings that differ, left to the user.
    skipped: usize,
}

impl Default for ParamsPane {
    fn default() -> Self {
        ParamsPane::new()
    }
}

impl ParamsPane {
    pub fn new() -> ParamsPane {
        ParamsPane {
            connection: None,
            tables: Vec::new(),
            tables_for: None,
            values: HashMap::new(),
            first: HashMap::new(),
            queue: VecDeque::new(),
            in_flight: None,
            next_tag: 1,
            progress: Progress::default(),
            selected: 0,
            offset: 0,
            page: DEFAULT_PAGE,
            filter: String::new(),
            mode: Mode::Browse,
            message: None,
            unit: SpeedUnit::Pps,
            axis_units: false,
            export: None,
            comparing: None,
            last_file: DEFAULT_FILE.to_string(),
            importing: None,
            known: Arc::default(),
            remembers_writes: false,
        }
    }

    /// The value read for a parameter, if one was, or for one the module
    /// cannot read back, the value written this session, while known.
    pub fn value(&self, scope: Scope, number: u16) -> Option<i64> {
        match self.values.get(&(scope, number)) {
            Some(Cell::Value(v)) => Some(*v),
            _ => self.known.value(scope, number),
        }
    }

    /// What the table knows of a row: read from the module, or for a row
    /// it cannot read back (where the family remembers writes), what was
    /// written this session.
    fn cell(&self, row: &ParamRow) -> Option<Cell> {
        let key = (row.scope, row.number);
        if row.access.read || !self.remembers_writes {
            return self.values.get(&key).cloned();
        }
        Some(shared::remembered(&self.known, row))
    }

    /// Lines waiting to be sent (the one in flight included).
    pub fn pending(&self) -> usize {
        self.queue.len() + usize::from(self.in_flight.is_some())
    }

    fn set_message(&mut self, role: Role, text: impl Into<String>) {
        self.message = Some((role, text.into()));
    }

    fn parameters(view: &View) -> Option<&'static dyn ParameterSet> {
        view.session.and_then(|s| s.family.console.parameters())
    }

    /// Follow the snapshot: a new connection forgets everything, another
    /// axis brings its tables.
    fn follow(&mut self, view: &View) {
        let Some(session) = view.session else {
            // Lines not answered yet never will be.
            self.drop_work();
            return;
        };
        self.known = Arc::clone(&session.settings);
        self.remembers_writes = Self::parameters(view).is_some_and(|p| p.remembers_writes());
        let connection = Connection {
            family: session.family.name,
            link: session.link_name.clone(),
            address: session.address,
        };
        if self.connection.as_ref() != Some(&connection) {
            self.drop_work();
            self.values.clear();
            self.first.clear();
            self.message = None;
            self.mode = Mode::Browse;
            self.connection = Some(connection);
            self.tables_for = None;
        }
        let axis = session.selected_axis().map_or(0, |a| a.number);
        if self.tables_for != Some((session.family.name, axis)) {
            self.tables = Self::parameters(view).map_or_else(Vec::new, |p| p.tables(axis));
            self.tables_for = Some((session.family.name, axis));
            self.selected = 0;
            self.offset = 0;
        }
    }

    fn drop_work(&mut self) {
        self.queue.clear();
        self.in_flight = None;
        self.progress = Progress::default();
        self.export = None;
        self.comparing = None;
        self.importing = None;
    }

    /// The lines of the table: a header for each table with rows shown,
    /// then its rows that match the filter.
    fn items(&self) -> Vec<Item> {
        let filter = self.filter.trim().to_lowercase();
        let mut items = Vec::new();
        for (t, table) in self.tables.iter().enumerate() {
            let rows: Vec<usize> = table
                .rows
                .iter()
                .enumerate()
                .filter(|(_, row)| matches(row, &filter))
                .map(|(r, _)| r)
                .collect();
            if rows.is_empty() {
                continue;
            }
            items.push(Item::Header(t));
            items.extend(rows.into_iter().map(|r| Item::Row(t, r)));
        }
        items
    }

    fn shown_rows(&self) -> Vec<(usize, usize)> {
        self.items()
            .into_iter()
            .filter_map(|item| match item {
                Item::Row(t, r) => Some((t, r)),
                Item::Header(_) => None,
            })
            .collect()
    }

    fn selected_row(&self) -> Option<&ParamRow> {
        let (t, r) = *self.shown_rows().get(self.selected)?;
        self.tables.get(t)?.rows.get(r)
    }

    /// The value of another parameter of the same axis, for conversions.
    fn axis_value(&self, scope: Scope) -> impl Fn(u16) -> Option<i64> + '_ {
        move |number| self.value(scope, number)
    }

    /// The line writing `value` to `row`: with the values of the
    /// parameters written together with it (a family that writes several
    /// in one line) from `file` (an import's values), else as known.
    fn write_line(
        &self,
        parameters: &dyn ParameterSet,
        row: &ParamRow,
        value: i64,
        file: &HashMap<Key, i64>,
    ) -> Result<String, String> {
        let known = |scope: Scope, number: u16| {
            file.get(&(scope, number))
                .copied()
                .or_else(|| self.value(scope, number))
        };
        Ok(parameters.line_with(row, ParamOp::Write(value), &known)?)
    }

    /// Queue `op` on `row`; says why not if the family has no line for it.
    fn queue_job(
        &mut self,
        parameters: &dyn ParameterSet,
        row: &ParamRow,
        op: ParamOp,
        purpose: Purpose,
    ) -> Result<(), String> {
        let line = match op {
            ParamOp::Write(value) => self.write_line(parameters, row, value, &HashMap::new())?,
            _ => parameters.line(row, op)?,
        };
        let job = Job {
            row: row.clone(),
            op,
            line,
            purpose,
        };
        if purpose == Purpose::ReadBack {
            self.queue.push_front(job);
        } else {
            self.queue.push_back(job);
        }
        self.progress.total += 1;
        Ok(())
    }

    /// Read these rows (the readable ones), skipping any already waiting.
    fn queue_reads<'a>(
        &mut self,
        parameters: &dyn ParameterSet,
        rows: impl IntoIterator<Item = &'a ParamRow>,
    ) {
        for row in rows {
            if !row.access.read {
                continue;
            }
            let key = (row.scope, row.number);
            let waiting = self
                .queue
                .iter()
                .chain(self.in_flight.as_ref().map(|(_, job)| job))
                .any(|j| j.op == ParamOp::Read && (j.row.scope, j.row.number) == key);
            if !waiting {
                let _ = self.queue_job(parameters, row, ParamOp::Read, Purpose::Read);
            }
        }
    }

    /// Send the next line if none is in flight.
    fn pump(&mut self, view: &View) -> Outcome {
        if self.in_flight.is_some() || view.session.is_none() {
            return Outcome::redraw();
        }
        let Some(job) = self.queue.pop_front() else {
            self.progress = Progress::default();
            return self.finish(view);
        };
        let tag = self.next_tag;
        self.next_tag += 1;
        // A value shown as read is one two answers agree on where the
        // family's answers carry no checksum (issue: a damaged SIXpack 2
        // answer shown as the module's value).
        let request = if job.op == ParamOp::Read {
            Request::ReadAgreed {
                line: job.line.clone(),
                tag,
            }
        } else {
            Request::Send {
                lines: vec![job.line.clone()],
                tag,
            }
        };
        self.in_flight = Some((tag, job));
        Outcome::request(request)
    }

    /// Everything asked for was answered: write a waiting export, show a
    /// waiting comparison.
    fn finish(&mut self, view: &View) -> Outcome {
        if let Some((path, existing)) = self.export.take() {
            self.write_export(&path, existing, view);
        }
        if let Some(comparing) = self.comparing.take() {
            self.show_diff(comparing);
        }
        if let Some(run) = self.importing.take() {
            let mut text = format!(
                "wrote {} from {}",
                counted(run.written, "value"),
                run.path.display()
            );
            if run.failed > 0 {
                text.push_str(&format!(", {} failed", run.failed));
                if let Some(first) = run.problems.first() {
                    text.push_str(&format!(" ({first})"));
                }
            }
            if run.skipped > 0 {
                text.push_str(&format!(
                    "; {} left for you to write",
                    counted(run.skipped, "link setting")
                ));
            }
            let role = if run.failed > 0 {
                Role::Error
            } else {
                Role::Ok
            };
            self.set_message(role, text);
        }
        Outcome::redraw()
    }

    fn answer(
        &mut self,
        tag: u64,
        result: &Result<LineResult, SessionError>,
        view: &View,
    ) -> Outcome {
        let Some((sent, job)) = self.in_flight.take() else {
            return Outcome::Ignored;
        };
        if sent != tag {
            self.in_flight = Some((sent, job));
            return Outcome::Ignored;
        }
        self.progress.done += 1;
        let key = (job.row.scope, job.row.number);
        match (job.op, result) {
            (ParamOp::Read, _) => {
                let cell = match Self::parameters(view) {
                    Some(p) => {
                        shared::reading(p, &job.row, result, &self.axis_value(job.row.scope))
                    }
                    None => Cell::Unreadable("no parameter tables".into()),
                };
                if let Cell::Value(v) = cell {
                    self.first.entry(key).or_insert(v);
                }
                self.values.insert(key, cell);
            }
            (op, Ok(r)) => {
                if job.purpose == Purpose::Import
                    && let Some(run) = self.importing.as_mut()
                {
                    run.written += 1;
                }
                let place = Self::parameters(view).map_or("EEPROM", |p| p.store_place());
                let done = match op {
                    ParamOp::Store => format!("stored in {place}"),
                    ParamOp::Restore => format!("restored from {place}"),
                    // `sent` for a module that acknowledges no write.
                    _ => r.value.to_string(),
                };
                if job.purpose == Purpose::User {
                    self.set_message(Role::Ok, format!("{}: {done}", r.line));
                }
                if matches!(op, ParamOp::Write(_) | ParamOp::Restore)
                    && let Some(parameters) = Self::parameters(view)
                {
                    let _ = self.queue_job(parameters, &job.row, ParamOp::Read, Purpose::ReadBack);
                }
            }
            (_, Err(e)) => {
                if job.purpose == Purpose::Import
                    && let Some(run) = self.importing.as_mut()
                {
                    run.failed += 1;
                }
                let nothing = if e.nothing_sent() {
                    " (nothing sent)"
                } else {
                    ""
                };
                self.set_message(Role::Error, format!("{} failed{nothing}: {e}", job.line));
            }
        }
        self.pump(view)
    }

    fn start_reading(&mut self, view: &View, all: bool) -> Outcome {
        let Some(parameters) = Self::parameters(view) else {
            return self.no_parameters(view);
        };
        let rows: Vec<ParamRow> = self
            .shown_rows()
            .into_iter()
            .filter_map(|(t, r)| self.tables.get(t)?.rows.get(r).cloned())
            .filter(|row| all || !self.values.contains_key(&(row.scope, row.number)))
            .collect();
        self.queue_reads(parameters, &rows);
        self.pump(view)
    }

    fn no_parameters(&mut self, view: &View) -> Outcome {
        match view.session {
            None => self.set_message(Role::Error, "not connected"),
            Some(s) => self.set_message(
                Role::Warning,
                format!("the {} family has no parameter tables", s.family.name),
            ),
        }
        Outcome::redraw()
    }

    /// Every setting of every axis and bank, for export and comparison.
    fn setting_rows(session: &Snapshot, parameters: &dyn ParameterSet) -> Vec<ParamRow> {
        let axes: Vec<u8> = session.axes.iter().map(|a| a.number).collect();
        parameter_file::setting_rows(parameters, &axes)
    }

    fn start_export(&mut self, path: PathBuf, existing: Existing, view: &View) -> Outcome {
        let (Some(session), Some(parameters)) = (view.session, Self::parameters(view)) else {
            return self.no_parameters(view);
        };
        // A file that cannot be written is known before the module is
        // asked (an existing one needs `--force` before its name).
        if let Err(e) = crate::files::check_destination(&path, existing) {
            self.set_message(Role::Error, format!("cannot write {}: {e}", path.display()));
            return Outcome::redraw();
        }
        let rows = Self::setting_rows(session, parameters);
        // Fresh values: what was read earlier may have been changed since
        // by a typed command or a program.
        self.queue_reads(parameters, &rows);
        self.export = Some((path.clone(), existing));
        self.set_message(
            Role::Accent,
            format!(
                "reading {} for {}…",
                counted(rows.len(), "setting"),
                path.display()
            ),
        );
        self.pump(view)
    }

    fn write_export(&mut self, path: &std::path::Path, existing: Existing, view: &View) {
        let (Some(session), Some(parameters)) = (view.session, Self::parameters(view)) else {
            return;
        };
        let rows = Self::setting_rows(session, parameters);
        let exported: Vec<Exported> = rows
            .iter()
            .map(|row| Exported {
                row,
                value: match self.cell(row) {
                    Some(Cell::Value(v)) => Ok(v),
                    Some(Cell::Unreadable(why) | Cell::NoAnswer(why) | Cell::Unknown(why)) => {
                        Err(why)
                    }
                    None => Err("not read".into()),
                },
            })
            .collect();
        let failed = exported.iter().filter(|e| e.value.is_err()).count();
        let mut header = vec![format!(
            "axterm parameter file: module {} on {}",
            session.address, session.link_name
        )];
        if let Some(identity) = &session.identity {
            header.push(format!("firmware {identity}"));
        }
        let text = parameter_file::render(session.family.name, &header, &exported);
        match crate::files::save(path, text.as_bytes(), existing) {
            Ok(()) if failed == 0 => self.set_message(
                Role::Ok,
                format!(
                    "exported {} to {}",
                    counted(exported.len(), "setting"),
                    path.display()
                ),
            ),
            Ok(()) => self.set_message(
                Role::Warning,
                format!(
                    "exported {} to {}; {failed} could not be read or are not known \
                     (commented out)",
                    counted(exported.len() - failed, "setting"),
                    path.display()
                ),
            ),
            Err(e) => {
                self.set_message(Role::Error, format!("cannot write {}: {e}", path.display()))
            }
        }
    }

    /// Read a file, check its entries against the tables, and read the
    /// module's values of those that are fine; the diff shows when they
    /// are in.
    fn start_compare(&mut self, path: PathBuf, import: bool, view: &View) -> Outcome {
        let (Some(session), Some(parameters)) = (view.session, Self::parameters(view)) else {
            return self.no_parameters(view);
        };
        let parsed = crate::files::read_text(&path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))
            .and_then(|text| {
                parameter_file::parse(&text)
                    .map_err(|e| format!("{} is not a parameter file: {e}", path.display()))
            });
        let parsed: ParamFile = match parsed {
            Ok(parsed) => parsed,
            Err(message) => {
                self.set_message(Role::Error, message);
                return Outcome::redraw();
            }
        };
        if let Some(why) = parameter_file::family_mismatch(&parsed, session.family.name) {
            self.set_message(Role::Error, format!("{}: {why}", path.display()));
            return Outcome::redraw();
        }
        let axes: Vec<u8> = session.axes.iter().map(|a| a.number).collect();
        let checked = parameter_file::check(parsed, parameters, &axes);
        let (entries, problems) = (checked.entries, checked.problems);
        let rows: Vec<ParamRow> = entries.iter().map(|(row, _)| row.clone()).collect();
        self.queue_reads(parameters, &rows);
        self.comparing = Some(Comparing {
            path: path.clone(),
            import,
            entries,
            problems,
        });
        self.set_message(
            Role::Accent,
            format!("reading the module to compare with {}…", path.display()),
        );
        self.pump(view)
    }

    fn show_diff(&mut self, comparing: Comparing) {
        let module = |row: &ParamRow| {
            self.cell(row)
                .unwrap_or_else(|| Cell::NoAnswer("not read".into()))
        };
        let comparison = shared::compare(&comparing.entries, &module);
        self.message = None;
        self.mode = Mode::Diff(Diff {
            path: comparing.path,
            import: comparing.import,
            comparison,
            problems: comparing.problems,
            scroll: 0,
        });
    }

    /// Write the file's values that differ (settings only), each read
    /// back after it is written.
    fn write_diff(&mut self, diff: Diff, view: &View) -> Outcome {
        let Some(parameters) = Self::parameters(view) else {
            return self.no_parameters(view);
        };
        let mut run = Importing {
            path: diff.path.clone(),
            written: 0,
            failed: 0,
            problems: Vec::new(),
            skipped: 0,
        };
        // A parameter written together with others in one line takes
        // their values from the file first: one line for them all.
        let known = |scope: Scope, number: u16| self.value(scope, number);
        let plan = plan_writes(parameters, &diff.comparison, &known);
        run.skipped = plan.link_left.len();
        for (_, why) in plan.refused {
            run.failed += 1;
            run.problems.push(why);
        }
        let queued = plan.writes.len();
        for write in plan.writes {
            let Some(first) = write.values.first() else {
                continue;
            };
            self.queue.push_back(Job {
                row: first.row.clone(),
                op: ParamOp::Write(first.file),
                line: write.line,
                purpose: Purpose::Import,
            });
            self.progress.total += 1;
        }
        self.set_message(
            Role::Accent,
            format!(
                "writing {} from {}…",
                counted(queued, "value"),
                diff.path.display()
            ),
        );
        self.importing = Some(run);
        self.mode = Mode::Browse;
        self.pump(view)
    }

    fn edit_submit(&mut self, row: ParamRow, field: Field, view: &View) -> Outcome {
        let Some(parameters) = Self::parameters(view) else {
            return self.no_parameters(view);
        };
        let checked = parameters
            .parse_value(&row, field.text(), &self.axis_value(row.scope))
            .map_err(String::from)
            .and_then(|value| {
                if !row.range.contains(value) {
                    return Err(format!(
                        "{} takes {}, not {}",
                        row.name,
                        parameters.range_text(&row),
                        parameters.value_text(&row, value)
                    ));
                }
                Ok((
                    value,
                    self.write_line(parameters, &row, value, &HashMap::new())?,
                ))
            });
        match checked {
            Err(why) => {
                self.set_message(Role::Error, format!("{why}: nothing sent"));
                self.mode = Mode::Edit { row, field };
                Outcome::redraw()
            }
            Ok((value, line)) => {
                self.set_message(Role::Accent, format!("{line}…"));
                self.queue.push_back(Job {
                    row,
                    op: ParamOp::Write(value),
                    line,
                    purpose: Purpose::User,
                });
                self.progress.total += 1;
                self.mode = Mode::Browse;
                self.pump(view)
            }
        }
    }

    fn user_op(&mut self, op: ParamOp, view: &View) -> Outcome {
        let Some(parameters) = Self::parameters(view) else {
            return self.no_parameters(view);
        };
        let Some(row) = self.selected_row().cloned() else {
            return Outcome::redraw();
        };
        match self.queue_job(parameters, &row, op, Purpose::User) {
            Ok(()) => self.pump(view),
            Err(why) => {
                self.set_message(Role::Error, format!("{why}: nothing sent"));
                Outcome::redraw()
            }
        }
    }

    fn begin_edit(&mut self, view: &View) -> Outcome {
        let Some(row) = self.selected_row().cloned() else {
            return Outcome::redraw();
        };
        if !row.access.write {
            self.set_message(
                Role::Warning,
                format!("{} is read-only (access {})", row.name, row.access),
            );
            return Outcome::redraw();
        }
        let Some(parameters) = Self::parameters(view) else {
            return self.no_parameters(view);
        };
        // The field starts from the value as shown, in the text the family
        // reads back as that value: Enter on it unchanged writes what was
        // read (an MCCL velocity in its unit, not its thousandths).
        let current = match self.cell(&row) {
            Some(Cell::Value(v)) => parameters.value_text(&row, v),
            _ => String::new(),
        };
        self.message = None;
        self.mode = Mode::Edit {
            row,
            field: Field::new(current),
        };
        Outcome::redraw()
    }

    fn move_selection(&mut self, action: Action) {
        let count = self.shown_rows().len();
        let last = count.saturating_sub(1);
        self.selected = match action {
            Action::SelectPrevious => self.selected.saturating_sub(1),
            Action::SelectNext => (self.selected + 1).min(last),
            Action::ScrollPageUp => self.selected.saturating_sub(self.page),
            Action::ScrollPageDown => (self.selected + self.page).min(last),
            Action::ScrollTop => 0,
            Action::ScrollBottom => last,
            _ => self.selected,
        }
        .min(last);
    }

    fn browse_key(&mut self, key: &KeyEvent, view: &View) -> Outcome {
        let Some(action) = view.keymap.action_for(Context::Parameters, key) else {
            return Outcome::Ignored;
        };
        match action {
            Action::SelectPrevious
            | Action::SelectNext
            | Action::ScrollPageUp
            | Action::ScrollPageDown
            | Action::ScrollTop
            | Action::ScrollBottom => self.move_selection(action),
            Action::ParameterEdit | Action::ParameterWrite => return self.begin_edit(view),
            Action::ParameterStore => return self.user_op(ParamOp::Store, view),
            Action::ParameterRestore => return self.user_op(ParamOp::Restore, view),
            Action::ParameterRefresh => return self.start_reading(view, true),
            Action::ParameterFilter => {
                self.mode = Mode::Filter(Field::new(self.filter.clone()));
            }
            Action::Cancel => {
                if self.message.take().is_none() {
                    self.filter.clear();
                    self.selected = 0;
                }
            }
            Action::ToggleUnits => {
                // pps → rpm → the axes' own units (with mechanics in
                // force and a family that converts) → pps…
                let axis = view
                    .session
                    .is_some_and(|s| s.family.console.units().is_some() && !s.mechanics.is_empty());
                (self.unit, self.axis_units) = match (self.unit, self.axis_units) {
                    (_, true) => (SpeedUnit::Pps, false),
                    (SpeedUnit::Pps, false) => (SpeedUnit::Rpm, false),
                    (SpeedUnit::Rpm, false) => (SpeedUnit::Pps, axis),
                };
            }
            Action::ParameterExport | Action::ParameterImport | Action::ParameterDiff => {
                let purpose = match action {
                    Action::ParameterExport => FileUse::Export,
                    Action::ParameterImport => FileUse::Import,
                    _ => FileUse::Compare,
                };
                self.mode = Mode::File {
                    purpose,
                    field: Field::new(self.last_file.clone()),
                };
            }
            _ => return Outcome::Ignored,
        }
        Outcome::redraw()
    }

    fn diff_key(&mut self, mut diff: Diff, key: &KeyEvent, view: &View) -> Outcome {
        let action = view.keymap.action_for(Context::Parameters, key);
        let lines = diff.comparison.differences.len() + diff.problems.len();
        match action {
            Some(Action::ParameterWrite) if diff.import => return self.write_diff(diff, view),
            Some(Action::Cancel) => {
                self.mode = Mode::Browse;
                return Outcome::redraw();
            }
            Some(Action::SelectNext | Action::ScrollDown) => {
                diff.scroll = (diff.scroll + 1).min(lines.saturating_sub(1));
            }
            Some(Action::SelectPrevious | Action::ScrollUp) => {
                diff.scroll = diff.scroll.saturating_sub(1);
            }
            Some(Action::ScrollPageDown) => {
                diff.scroll = (diff.scroll + self.page).min(lines.saturating_sub(1));
            }
            Some(Action::ScrollPageUp) => diff.scroll = diff.scroll.saturating_sub(self.page),
            Some(Action::ScrollTop) => diff.scroll = 0,
            Some(_) | None => {
                self.mode = Mode::Diff(diff);
                return Outcome::Ignored;
            }
        }
        self.mode = Mode::Diff(diff);
        Outcome::redraw()
    }

    /// Keys while a text field is open: submit and cancel through the
    /// command line's bindings, the rest edits.
    fn field_key(&mut self, mode: Mode, key: &KeyEvent, view: &View) -> Outcome {
        let action = view.keymap.action_for(Context::Command, key);
        match (mode, action) {
            (Mode::Edit { .. } | Mode::File { .. }, Some(Action::Cancel)) => {
                self.message = None;
                Outcome::redraw()
            }
            (Mode::Filter(_), Some(Action::Cancel)) => {
                self.filter.clear();
                self.selected = 0;
                Outcome::redraw()
            }
            (Mode::Filter(_), Some(Action::Submit)) => Outcome::redraw(),
            (Mode::Edit { row, field }, Some(Action::Submit)) => self.edit_submit(row, field, view),
            (Mode::File { purpose, field }, Some(Action::Submit)) => {
                let text = field.text().trim().to_string();
                let (existing, name) = crate::files::force_option(&text);
                if name.is_empty() {
                    self.mode = Mode::File { purpose, field };
                    self.set_message(Role::Error, "no file name given");
                    return Outcome::redraw();
                }
                self.last_file = name.to_string();
                let path = PathBuf::from(name);
                match purpose {
                    FileUse::Export => self.start_export(path, existing, view),
                    FileUse::Import => self.start_compare(path, true, view),
                    FileUse::Compare => self.start_compare(path, false, view),
                }
            }
            (mut mode, _) => {
                let field = match &mut mode {
                    Mode::Filter(field) | Mode::Edit { field, .. } | Mode::File { field, .. } => {
                        field
                    }
                    _ => {
                        self.mode = mode;
                        return Outcome::Ignored;
                    }
                };
                let edited = field.edit(key);
                if let Mode::Filter(field) = &mode {
                    self.filter = field.text().to_string();
                    self.selected = 0;
                }
                self.mode = mode;
                if edited {
                    Outcome::redraw()
                } else {
                    Outcome::Ignored
                }
            }
        }
    }
}

/// `n` and the noun, plural unless one (`1 parameter`, `3 settings`).
fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// Whether a row passes the filter: its name contains it, or it is its
/// number.
fn matches(row: &ParamRow, filter: &str) -> bool {
    filter.is_empty()
        || row.name.to_lowercase().contains(filter)
        || row.number.to_string() == filter
}

impl Pane for ParamsPane {
    fn name(&self) -> &'static str {
        "params"
    }

    /// While a value, filter or file name is typed, keys are looked up
    /// as on the command line, so that letters are text (the vim keymap's
    /// `q` does not quit in the middle of a filter).
    fn context(&self) -> Context {
        match self.mode {
            Mode::Filter(_) | Mode::Edit { .. } | Mode::File { .. } => Context::Command,
            Mode::Browse | Mode::Diff(_) => Context::Parameters,
        }
    }

    fn title(&self, _view: &View) -> String {
        "Parameters".into()
    }

    fn region(&self) -> Region {
        Region::Main
    }

    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        self.draw(frame, area, view);
    }

    fn handle_input(&mut self, input: &Input, view: &View) -> Outcome {
        self.follow(view);
        match input {
            Input::Key(key) => {
                let mode = std::mem::replace(&mut self.mode, Mode::Browse);
                match mode {
                    Mode::Browse => self.browse_key(key, view),
                    Mode::Diff(diff) => self.diff_key(diff, key, view),
                    typing => self.field_key(typing, key, view),
                }
            }
            Input::Paste(text) => match &mut self.mode {
                Mode::Filter(field) => {
                    field.insert_str(text);
                    self.filter = field.text().to_string();
                    Outcome::redraw()
                }
                Mode::Edit { field, .. } | Mode::File { field, .. } => {
                    field.insert_str(text.lines().next().unwrap_or(""));
                    Outcome::redraw()
                }
                _ => Outcome::Ignored,
            },
            Input::Mouse(mouse) => match mouse.kind {
                MouseEventKind::ScrollUp => {
                    self.move_selection(Action::SelectPrevious);
                    Outcome::redraw()
                }
                MouseEventKind::ScrollDown => {
                    self.move_selection(Action::SelectNext);
                    Outcome::redraw()
                }
                _ => Outcome::Ignored,
            },
        }
    }

    fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        match event {
            PaneEvent::Snapshot => {
                let before = (self.connection.clone(), self.tables_for);
                let known = Arc::clone(&self.known);
                self.follow(view);
                if before != (self.connection.clone(), self.tables_for) || known != self.known {
                    Outcome::redraw()
                } else {
                    Outcome::Ignored
                }
            }
            PaneEvent::Connected { .. } => {
                // A connection opened again may hold other values (the
                // module was reset): forget what was read.
                self.connection = None;
                self.follow(view);
                Outcome::redraw()
            }
            PaneEvent::Focused => {
                self.follow(view);
                if view.session.is_some() && !self.tables.is_empty() {
                    self.start_reading(view, false)
                } else {
                    Outcome::Ignored
                }
            }
            PaneEvent::Reply { tag, result, .. } => self.answer(*tag, result, view),
            PaneEvent::Stopping => {
                let dropped = self.pending();
                if dropped == 0 {
                    return Outcome::Ignored;
                }
                self.drop_work();
                self.set_message(
                    Role::Warning,
                    format!(
                        "emergency stop: {} not sent",
                        counted(dropped, "parameter line")
                    ),
                );
                Outcome::redraw()
            }
            _ => Outcome::Ignored,
        }
    }
}
