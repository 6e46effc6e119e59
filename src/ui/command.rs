//! The command pane: the direct-mode console. A line editor with history
//! (kept per protocol family in the data directory), tab completion and
//! inline help from the family's catalogue (F1 on a word, `:help TOPIC`),
//! console commands starting with `:`, and the output: each line sent,
//! its decoded answer and status meaning, errors in plain words, the
//! bytes on the wire.

mod assist;
mod busy;
mod confirm;
mod editing;
mod hints;
mod history;
mod record;
mod runs;
mod store;

use std::collections::HashMap;
use std::path::PathBuf;

use ratatui::Frame;
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers, MouseEventKind};
use ratatui::layout::{Position, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use super::batch::{Batch, BatchStep, run_options};
use super::host_run::{ConsoleHostRun, HostUpdate};
use super::keymap::{Action, Context};
use super::pane::{
    Input, NoticeLevel, Outcome, Pane, PaneEvent, Region, Request, Snapshot, View, key_label,
};
use super::text::fit;
use super::theme::Role;
use crate::device::{Busy, DeviceEvent, LinkState};
use crate::families::{FAMILIES, find_family};
use crate::protocol::Family;
use crate::protocol::console::{Candidate, Completions, PreparedLine};
use crate::protocol::program::{HostStart, ProgramTool};
use crate::protocol::units::{MechanicsTable, has_units};
use crate::session::run_end::{AtTheEnd, RunAftermath, RunEnding, StopOnFailure};
use crate::session::{LineResult, SessionError};
use confirm::{Confirming, Deferred};
use history::History;
use record::{Recording, SessionRecording};
use runs::is_host_command;

/// Lines of output kept; older ones scroll away for good.
const OUTPUT_LIMIT: usize = 5000;
/// Rows of completion candidates shown at most.
const CANDIDATE_ROWS: usize = 3;
const PROMPT: &str = "> ";
/// Rows a page key scrolls.
const PAGE: usize = 10;

/// The console commands, for `:help` and completion.
pub const CONSOLE_COMMANDS: &[(&str, &str)] = &[
    (
        ":help [TOPIC]",
        "help on a command (`:help SAP`), a parameter (`:help SAP 4`, `:help baud`) or this list",
    ),
    (
        ":poll RATE",
        "poll status RATE times a second (0 or off: stop polling)",
    ),
    (":axis N", "work with axis N (its number or name)"),
    (":address N", "send to the module at address N"),
    (
        ":module [N]",
        "send to module N of the axes pane's list; alone: list the modules",
    ),
    (
        ":link-add CONNECTION",
        "open one more link beside those open (as :connect)",
    ),
    (
        ":traffic LINK | all",
        "show only link LINK's frames in the traffic monitor, or all",
    ),
    (
        ":clear [N]",
        "forget the latched error flags of axis N (default: the selected axis)",
    ),
    (":stop", "emergency stop, like its key"),
    (
        ":programs [delete N]",
        "list what the controller stores besides the editor's program (MCCL: its macros, by TM-1), or delete one (MCCL: RM erases them all, the others are defined again and compared)",
    ),
    (
        ":tasks [stop ID]",
        "list the programs the controller runs in the background (MCCL: ID7), or stop one (ET)",
    ),
    (
        ":log [--force] [FILE | off]",
        "log every link's frames, UTC-stamped, to FILE (none: axterm-YYYYMMDD-HHMMSS.log here; an existing FILE only with --force, which replaces it)",
    ),
    (
        ":plot add AXIS VALUE | remove AXIS VALUE | clear | csv [--force] FILE",
        "plot a status value (position, speed, load…) or a parameter by name or number; export what was plotted (in the plot pane its pick key, a by default, lists them)",
    ),
    (":theme NAME", "switch colours"),
    (":keymap NAME", "switch key bindings"),
    (
        ":connect CONNECTION",
        "connect: --sim KIND | --port PATH [--baud N] | --tcp HOST:PORT, with --protocol, --address",
    ),
    (
        ":run [--no-stop-on-failure] FILE",
        "run a batch file as `axterm run` does (checked whole first; a failed or cancelled run stops every axis unless told not to)",
    ),
    (
        ":run-ascript [--no-stop-on-failure] FILE [N…]",
        "run a CMD-4CR A-Script program from the host (checked whole first; N: only these PRG blocks; stops every axis if it fails or is cancelled unless told not to)",
    ),
    (
        ":run-macro [--no-stop-on-failure] FILE",
        "play a SIXpack 2 SQPack macro file from the host (checked whole first; frames the family wants confirmed are asked about once; stops every axis if it fails or is cancelled unless told not to)",
    ),
    (
        ":record [[--force] FILE | off]",
        "record each line sent and its answer as an `axterm run` file (reads as :expect, waits as :wait-until, the emergency stop as the stop lines it sent; an existing FILE only with --force); meanwhile :report [--force] FILE writes its commissioning sheet so far (JSON for FILE.json)",
    ),
    (
        ":report [--force] FILE",
        "write the commissioning sheet of the :record so far (JSON for FILE.json): its lines and checks, the bring-up pane's wiring checks, the tuning pane's runs with their plots, and the module's settings against the factory defaults, read first (reading the settings…; a failed read still writes the sheet, saying so); an existing FILE only with --force",
    ),
    (
        ":record-macro [--force] FILE | off",
        "record every line sent from here as a macro file of the module's program language (SIXpack 2: SendToPack lines, §5.4.6), until off; an existing FILE only with --force",
    ),
    (
        ":expect LINE == VALUE",
        "run LINE, fail unless its result is VALUE",
    ),
    (
        ":wait-until LINE == VALUE [timeout D]",
        "read LINE again until it gives VALUE",
    ),
    (
        ":sim-input SETTING",
        "drive an input of the simulator (--sim) as if wired: IO5=1, DI4=1, AI1=1650, EMG=1, ALMX=1 (`:help :sim-input` lists them)",
    ),
    (
        ":mechanics [FILE | off]",
        "take the axes' mechanics ([mechanics.N] of a parameter file): values may then be typed in an axis's unit (MVP ABS, 0, 12.5mm) and the axes pane's units key shows them; without FILE: list those in force",
    ),
    (":sleep D", "wait (500ms, 2s, 1m)"),
    (":echo TEXT", "show TEXT"),
    (
        ":leave-moving",
        "in a batch file: it means to leave an axis moving at its end (without it, `axterm run` stops an axis still moving at the end, exit 1)",
    ),
    (":quit", "leave the console"),
];

/// One row of output.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Output {
    role: Role,
    text: String,
}

/// Who sent a line, so its answer goes to the right place.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Origin {
    Typed,
    Batch,
    /// A line of `:programs` or `:tasks` ([`store`]).
    Store,
}

/// A list of completions being offered.
#[derive(Debug, Clone)]
struct Completing {
    /// Where the completed word starts in the line.
    start: usize,
    /// Bytes of the line the current choice takes.
    len: usize,
    candidates: Vec<Candidate>,
    /// The candidate shown in the line (Tab cycles), if any yet.
    chosen: Option<usize>,
    /// The line as completion left it: any edit ends the cycle.
    line: String,
}

/// The console line editor and its output.
#[derive(Debug)]
pub struct CommandPane {
    input: String,
    /// Byte offset of the cursor in `input`, on a character boundary.
    cursor: usize,
    output: Vec<Output>,
    /// Rows scrolled back from the newest output.
    scroll: usize,
    completing: Option<Completing>,
    /// A one-line remark under the output (no completion, a syntax hint).
    hint: Option<Output>,
    /// The input F1 last explained: the syntax hint would only repeat the
    /// first line of the help shown just above it.
    explained: Option<String>,
    history: History,
    history_dir: Option<PathBuf>,
    /// The family whose history is loaded.
    family: Option<&'static str>,
    /// Whose tables help and completion use while nothing is connected:
    /// the family last connected, or the one being chosen on the connect
    /// screen since (at start: the connect screen's first choice).
    /// (Its name: [`Family`] is not `Debug`.)
    offline_family: Option<&'static str>,
    next_tag: u64,
    /// A `:report` whose settings are being read ([`record::PendingReport`]).
    report_pending: Option<record::PendingReport>,
    sent: HashMap<u64, Origin>,
    batch: Option<Batch>,
    /// The tag of the batch's current wake-up.
    batch_wake: Option<u64>,
    /// An A-Script program running from the host (`:run-ascript`).
    host: Option<ConsoleHostRun>,
    /// What becomes of the axes if the `:run` or `:run-ascript` going fails
    /// or is cancelled; `None` for directives typed alone.
    run_policy: Option<StopOnFailure>,
    /// The last output row is a state [`CommandPane::say_live`] replaces.
    live: bool,
    /// What waits for the user's yes: a line, batch or host run with
    /// lines the family wants confirmed.
    confirming: Option<Confirming>,
    /// `:record-macro FILE`: the lines sent from here, as a program.
    recording: Option<Recording>,
    /// `:record FILE`: the session as an `axterm run` file.
    session_recording: Option<SessionRecording>,
    /// The line the controller is busy with, if any (see [`busy`]).
    busy: Option<Busy>,
    /// The family the busy line is shown for (its name).
    busy_family: Option<&'static str>,
    /// The `:programs` or `:tasks` job under way.
    store_job: Option<store::StoreJob>,
    /// Reopenings of a lost link that have failed so far; `None` while
    /// the link is up. Tells a reconnection from a first opening.
    reconnecting: Option<u32>,
}

impl Default for CommandPane {
    fn default() -> CommandPane {
        CommandPane::new(None)
    }
}

impl CommandPane {
    /// A console whose history is kept in `history_dir` (none: not kept).
    pub fn new(history_dir: Option<PathBuf>) -> CommandPane {
        let offline_family = super::connect::initial_family(history_dir.as_deref()).map(|f| f.name);
        CommandPane {
            input: String::new(),
            cursor: 0,
            output: Vec::new(),
            scroll: 0,
            completing: None,
            hint: None,
            explained: None,
            history: History::default(),
            history_dir,
            family: None,
            offline_family,
            next_tag: 0,
            report_pending: None,
            sent: HashMap::new(),
            batch: None,
            batch_wake: None,
            host: None,
            run_policy: None,
            live: false,
            confirming: None,
            recording: None,
            session_recording: None,
            busy: None,
            busy_family: None,
            store_job: None,
            reconnecting: None,
        }
    }

    /// The text typed so far.
    pub fn input(&self) -> &str {
        &self.input
    }

    /// Every output row, oldest first.
    pub fn output_lines(&self) -> impl Iterator<Item = &str> {
        self.output.iter().map(|o| o.text.as_str())
    }

    /// Show a one-line state that replaces the previous one while nothing
    /// else was said in between (a `:wait-until`'s reads).
    fn say_live(&mut self, role: Role, text: String) {
        match self.output.last_mut() {
            Some(last) if self.live => {
                *last = Output { role, text };
                self.scroll = 0;
            }
            _ => self.say(role, text),
        }
        self.live = true;
    }

    fn say(&mut self, role: Role, text: impl Into<String>) {
        self.live = false;
        let text = text.into();
        for line in text.lines() {
            self.output.push(Output {
                role,
                text: line.to_string(),
            });
        }
        if self.output.len() > OUTPUT_LIMIT {
            self.output.drain(..self.output.len() - OUTPUT_LIMIT);
        }
        self.scroll = 0;
    }

    fn tag(&mut self, origin: Origin) -> u64 {
        self.next_tag += 1;
        self.sent.insert(self.next_tag, origin);
        if matches!(origin, Origin::Typed | Origin::Batch) {
            self.session_record_before_line(self.next_tag);
        }
        self.next_tag
    }

    /// The family whose tables help and completion come from: the
    /// connected module's, else [`CommandPane::offline_family`], else
    /// the first family's (TMCL).
    fn family(&self, view: &View) -> Option<&'static Family> {
        view.session
            .map(|s| s.family)
            .or_else(|| self.offline_family.and_then(find_family))
            .or_else(|| FAMILIES.first().map(|f| f.family))
    }

    /// Said before help given with nothing connected, so that it is clear
    /// whose tables it comes from.
    fn offline_note(&mut self, view: &View) {
        if view.session.is_none()
            && let Some(family) = self.family(view)
        {
            self.say(
                Role::Muted,
                format!(
                    "not connected: help from the {} tables ({})",
                    family.name, family.description
                ),
            );
        }
    }

    fn load_history(&mut self, family: &'static Family) {
        if self.family != Some(family.name) {
            self.history = History::load(self.history_dir.as_deref(), family.name);
            self.family = Some(family.name);
        }
    }

    fn set_input(&mut self, text: String) {
        self.cursor = text.len();
        self.input = text;
    }

    /// Enter: run the line.
    fn submit(&mut self, view: &View) -> Outcome {
        let line = std::mem::take(&mut self.input);
        self.cursor = 0;
        self.hint = None;
        let trimmed = line.trim().to_string();
        if trimmed.is_empty() {
            return Outcome::redraw();
        }
        if let Err(message) = self.history.push(&trimmed) {
            self.say(Role::Warning, message);
        }
        self.say(Role::Prompt, format!("{PROMPT}{trimmed}"));
        if trimmed.starts_with(':') {
            return self.console_command(&trimmed, view);
        }
        let Some(session) = view.session else {
            self.say(Role::Error, not_connected());
            return Outcome::redraw();
        };
        // A line that does not parse is sent all the same: the session
        // refuses it with its message, as for any front end.
        if let Ok(prepared) = session.family.console.prepare(&trimmed, session.address) {
            self.say_warnings(session, &prepared);
            if let Some(why) = session.family.console.confirmation(&prepared) {
                return self.ask(Deferred::Line(trimmed), vec![why]);
            }
        }
        self.send_typed(trimmed)
    }

    /// `:module N` picks where lines go; `:module` alone lists the modules.
    fn module_command(&mut self, rest: &str, view: &View) -> Outcome {
        if view.modules.is_empty() {
            return self.fail(not_connected());
        }
        if rest.is_empty() {
            for (index, entry) in view.modules.iter().enumerate() {
                let s = &entry.snapshot;
                let mark = if index == view.module { "▶" } else { " " };
                self.say(
                    Role::Normal,
                    format!(
                        "{mark}{} link {} {} #{} {}",
                        index + 1,
                        entry.link + 1,
                        s.link_name,
                        s.address,
                        s.family.name
                    ),
                );
            }
            return Outcome::redraw();
        }
        match rest.parse::<usize>() {
            Ok(n) if (1..=view.modules.len()).contains(&n) => {
                let s = view.modules.get(n - 1).map(|e| &e.snapshot);
                if let Some(s) = s {
                    self.say(
                        Role::Muted,
                        format!("lines go to module {n}: {} #{}", s.link_name, s.address),
                    );
                }
                Outcome::request(Request::SelectModule(n - 1))
            }
            _ => self.fail(format!(
                ":module needs a module number 1..{} (`:module` lists them), not `{rest}`",
                view.modules.len()
            )),
        }
    }

    fn send_typed(&mut self, line: String) -> Outcome {
        let tag = self.tag(Origin::Typed);
        Outcome::request(Request::Send {
            lines: vec![line],
            tag,
        })
    }

    fn console_command(&mut self, line: &str, view: &View) -> Outcome {
        let body = line.trim_start_matches(':');
        let (name, rest) = match body.split_once(char::is_whitespace) {
            Some((name, rest)) => (name.to_ascii_lowercase(), rest.trim()),
            None => (body.to_ascii_lowercase(), ""),
        };
        let session = view.session;
        let request = match name.as_str() {
            "help" | "h" => {
                self.help_topic(rest, view);
                return Outcome::redraw();
            }
            "quit" | "q" | "exit" => Request::Quit,
            "stop" => Request::EmergencyStop,
            "poll" => match parse_rate(rest) {
                Some(rate) => Request::Poll(rate),
                None => {
                    return self.fail(format!(
                        ":poll needs a rate in Hz (e.g. `:poll 20`; 0 or off stops), not `{rest}`"
                    ));
                }
            },
            "axis" => match session.map(|s| find_axis(s, rest)) {
                None => return self.fail(not_connected()),
                Some(Ok(index)) => Request::SelectAxis(index),
                Some(Err(message)) => return self.fail(message),
            },
            "clear" => {
                let Some(session) = session else {
                    return self.fail(not_connected());
                };
                let axis = if rest.is_empty() {
                    Ok(session.axis)
                } else {
                    find_axis(session, rest)
                };
                match axis {
                    Ok(axis) => {
                        let name = session.axes.get(axis).map_or("", |a| a.name);
                        self.say(Role::Muted, format!("error flags of {name} cleared"));
                        Request::ClearErrors(axis)
                    }
                    Err(message) => return self.fail(message),
                }
            }
            "address" => {
                // The connected family's addresses (CMD-4CR IDs are two
                // digits, 0..99), else any byte.
                let range = session.map_or(0..=255, |s| s.family.console.addresses());
                match rest.parse::<u8>() {
                    Ok(address) if range.contains(&address) => Request::SetAddress(address),
                    _ => {
                        return self.fail(format!(
                            ":address needs a module address {}..{}, not `{rest}`",
                            range.start(),
                            range.end()
                        ));
                    }
                }
            }
            "log" => match crate::files::force_option(rest) {
                // tio's habit: a name of the time, in the current directory.
                (existing, "") => Request::Log(Some((
                    PathBuf::from(
                        crate::wall_clock::CivilTime::of(std::time::SystemTime::now())
                            .log_file_name(),
                    ),
                    existing,
                ))),
                (_, "off") => Request::Log(None),
                (existing, file) => Request::Log(Some((PathBuf::from(file), existing))),
            },
            "theme" if !rest.is_empty() => Request::Theme(rest.to_string()),
            "keymap" if !rest.is_empty() => Request::Keymap(rest.to_string()),
            "theme" | "keymap" => return self.fail(format!(":{name} needs a name")),
            "module" => return self.module_command(rest, view),
            "traffic" => match rest {
                "" | "all" => Request::TrafficLink(None),
                n => match n.parse::<usize>() {
                    Ok(n) if n >= 1 => Request::TrafficLink(Some(n - 1)),
                    _ => {
                        return self.fail(format!(
                            ":traffic needs a link number (1 is the first link opened) or `all`, not `{n}`"
                        ));
                    }
                },
            },
            "link-add" => {
                if rest.is_empty() {
                    return self.fail(
                        ":link-add needs a connection: --sim cmd4cr, --port PATH or --tcp HOST:PORT",
                    );
                }
                Request::AddLink(rest.split_whitespace().map(str::to_string).collect())
            }
            "connect" => {
                if rest.is_empty() {
                    return self.fail(
                        ":connect needs a connection: --sim tmcm1110, --port PATH or --tcp HOST:PORT",
                    );
                }
                Request::Connect(rest.split_whitespace().map(str::to_string).collect())
            }
            "run" => {
                let (policy, rest) = run_options(rest);
                if rest.is_empty() {
                    return self.fail(":run needs a file name");
                }
                return match crate::files::read_text(rest) {
                    Ok(text) => {
                        self.with_run_policy(policy, |pane| pane.start_batch(rest, &text, view))
                    }
                    Err(e) => self.fail(format!("cannot read {rest}: {e}")),
                };
            }
            "record-macro" => return self.record_command(rest, view),
            "record" => return self.session_record_command(rest, view),
            "report" => return self.report_command(rest, view),
            "plot" => Request::Plot(rest.to_string()),
            command if is_host_command(command) => {
                let (policy, rest) = run_options(rest);
                return self
                    .with_run_policy(policy, |pane| pane.start_host_run(command, rest, view));
            }
            "mechanics" => match rest {
                "" => {
                    let Some(session) = session else {
                        return self.fail(not_connected());
                    };
                    if session.mechanics.is_empty() {
                        self.say(
                            Role::Muted,
                            "no mechanics in force: raw values only (:mechanics FILE)",
                        );
                    }
                    for (axis, m) in &session.mechanics.axes {
                        self.say(Role::Normal, format!("axis {axis}: {} ({m})", m.unit));
                    }
                    return Outcome::redraw();
                }
                "off" => Request::Mechanics(MechanicsTable::default()),
                file => {
                    let read = crate::files::read_text(file)
                        .map_err(|e| e.to_string())
                        .and_then(|text| MechanicsTable::parse_file(&text).map_err(String::from));
                    match read {
                        Ok((table, _)) => Request::Mechanics(table),
                        Err(message) => return self.fail(format!(":mechanics {file}: {message}")),
                    }
                }
            },
            "sim-input" => {
                if session.is_none() {
                    return self.fail(not_connected());
                }
                if rest.is_empty() {
                    return self.fail(
                        ":sim-input needs a setting NAME=VALUE, e.g. IO5=1 (`:help :sim-input` lists the inputs)",
                    );
                }
                Request::DriveSimInput(rest.to_string())
            }
            "expect" | "wait-until" | "sleep" | "echo" => {
                return self.start_batch(&format!(":{name}"), line, view);
            }
            "programs" | "tasks" => {
                let started = store::store_of(session.map(|s| s.family))
                    .and_then(|store| store::start(store, &name, rest));
                return match started {
                    Ok((job, lines)) => {
                        self.store_job = Some(job);
                        let tag = self.tag(Origin::Store);
                        Outcome::request(Request::Send { lines, tag })
                    }
                    Err(message) => self.fail(message),
                };
            }
            _ => {
                return self.fail(format!(
                    "unknown console command `:{name}` (`:help` lists them)"
                ));
            }
        };
        Outcome::request(request)
    }

    /// An answer to a line of `:programs` or `:tasks`.
    fn store_reply(
        &mut self,
        tag: u64,
        result: &Result<LineResult, SessionError>,
        family: Option<&'static Family>,
    ) -> Outcome {
        let (Ok(store), Some(job)) = (store::store_of(family), self.store_job.take()) else {
            self.sent.remove(&tag);
            return Outcome::Ignored;
        };
        // The lines that change the controller are shown with their answers.
        if matches!(job, store::StoreJob::Deleting { .. }) {
            if let Ok(r) = result {
                self.say(Role::Normal, format!("{PROMPT}{}", r.line));
            }
            self.show_reply(family, result);
        }
        let (steps, next) = store::on_reply(store, job, result);
        let goes_on = matches!(next, Some(store::StoreJob::Deleting { .. }));
        self.store_job = next;
        if !goes_on {
            // Its lines are all answered (or the rest were not sent).
            self.sent.remove(&tag);
        }
        let mut requests = Vec::new();
        for step in steps {
            match step {
                store::StoreStep::Say(role, text) => self.say(role, text),
                store::StoreStep::Send(lines) => {
                    let tag = self.tag(Origin::Store);
                    requests.push(Request::Send { lines, tag });
                }
            }
        }
        Outcome::Handled(requests)
    }

    fn fail(&mut self, message: impl Into<String>) -> Outcome {
        self.say(Role::Error, message);
        Outcome::redraw()
    }

    fn show_reply(
        &mut self,
        family: Option<&'static Family>,
        result: &Result<LineResult, SessionError>,
    ) {
        match result {
            Ok(result) => {
                let meaning = match (result.status, family) {
                    (Some(status), Some(f)) => match f.console.status_meaning(status) {
                        Some(meaning) => format!("  (status {status}: {meaning})"),
                        None => format!("  (status {status})"),
                    },
                    (Some(status), None) => format!("  (status {status})"),
                    (None, _) => String::new(),
                };
                self.say(Role::Ok, format!("  {}{meaning}", result.value));
                if let Some(f) = family {
                    let mut wire = format!("  sent {}", (f.show_bytes)(&result.request));
                    if !result.reply.is_empty() {
                        wire.push_str(&format!("  got {}", (f.show_bytes)(&result.reply)));
                    }
                    if result.attempts > 1 {
                        wire.push_str(&format!("  ({} attempts)", result.attempts));
                    }
                    if crate::session::read_unchecked(f.console, result) {
                        wire.push_str("  unchecked: no checksum");
                    }
                    self.say(Role::Muted, wire);
                }
            }
            Err(error) => {
                let prefix = match error {
                    SessionError::Refused { .. } => "not sent: ",
                    SessionError::Reply { .. } => "error: ",
                    SessionError::Device { .. } => "no answer: ",
                };
                self.say(Role::Error, format!("  {prefix}{error}"));
                if let (Some(f), Some(request)) = (family, error.request()) {
                    let mut wire = format!("  sent {}", (f.show_bytes)(request));
                    if let Some(reply) = error.reply() {
                        wire.push_str(&format!("  got {}", (f.show_bytes)(reply)));
                    }
                    self.say(Role::Muted, wire);
                }
            }
        }
    }
}

impl Pane for CommandPane {
    fn name(&self) -> &'static str {
        "command"
    }

    fn context(&self) -> Context {
        Context::Command
    }

    fn title(&self, view: &View) -> String {
        // With several modules, the one lines go to.
        match (view.modules.len() > 1, view.session) {
            (true, Some(s)) => format!(
                "Command → module {} ({} #{})",
                view.module + 1,
                s.link_name,
                s.address
            ),
            _ => "Command".into(),
        }
    }

    fn region(&self) -> Region {
        Region::Main
    }

    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        if area.height == 0 || area.width == 0 {
            return;
        }
        if let Some(session) = view.session {
            self.load_history(session.family);
        }
        let theme = view.theme;
        let width = usize::from(area.width);
        let mut hint = self.hint_rows(view, width);
        let max_hint = usize::from(area.height.saturating_sub(2));
        hint.truncate(max_hint);
        let output_rows = usize::from(area.height).saturating_sub(1 + hint.len());
        let rows = self.wrapped(width);
        let max_scroll = rows.len().saturating_sub(output_rows);
        self.scroll = self.scroll.min(max_scroll);
        let end = rows.len() - self.scroll;
        let start = end.saturating_sub(output_rows);
        let mut lines: Vec<Line> = rows
            .get(start..end)
            .unwrap_or_default()
            .iter()
            .map(|(role, text)| Line::styled(text.clone(), theme.style(*role)))
            .collect();
        // Output sits right above the prompt, as in a shell.
        let blank = output_rows.saturating_sub(lines.len());
        let mut all: Vec<Line> = vec![Line::raw(""); blank];
        all.append(&mut lines);
        all.extend(hint);
        // The prompt, scrolled sideways to keep the cursor in view.
        let before: Vec<char> = self
            .input
            .get(..self.cursor)
            .unwrap_or("")
            .chars()
            .collect();
        let room = width.saturating_sub(PROMPT.len() + 1).max(1);
        let skip = before.len().saturating_sub(room);
        let shown: String = self.input.chars().skip(skip).take(room + 1).collect();
        all.push(Line::from(vec![
            Span::styled(PROMPT, theme.style(Role::Prompt)),
            Span::styled(shown, theme.style(Role::Normal)),
        ]));
        let prompt_row = area.y + (all.len() as u16).saturating_sub(1).min(area.height - 1);
        frame.render_widget(Paragraph::new(all), area);
        if view.focused {
            let column = (PROMPT.len() + before.len() - skip).min(width.saturating_sub(1));
            frame.set_cursor_position(Position::new(area.x + column as u16, prompt_row));
        }
    }

    fn handle_input(&mut self, input: &Input, view: &View) -> Outcome {
        match input {
            Input::Key(key) => self.edit_key(key, view),
            Input::Paste(text) => {
                let mut lines = text.lines();
                let first = lines.next().unwrap_or("");
                self.input.insert_str(self.cursor, first);
                self.cursor += first.len();
                if lines.next().is_some() {
                    self.hint = Some(Output {
                        role: Role::Warning,
                        text: "only the first pasted line was taken: use :run FILE for several"
                            .into(),
                    });
                }
                Outcome::redraw()
            }
            Input::Mouse(mouse) => match mouse.kind {
                MouseEventKind::ScrollUp => {
                    self.scroll = self.scroll.saturating_add(3);
                    Outcome::redraw()
                }
                MouseEventKind::ScrollDown => {
                    self.scroll = self.scroll.saturating_sub(3);
                    Outcome::redraw()
                }
                _ => Outcome::Ignored,
            },
        }
    }

    fn activity(&self) -> Option<String> {
        self.host
            .as_ref()
            .map(ConsoleHostRun::describe)
            .or_else(|| {
                self.busy
                    .as_ref()
                    .map(|busy| busy::activity(busy, self.busy_family.and_then(find_family)))
            })
    }

    fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        let family = view.session.map(|s| s.family);
        if let Some(host) = self.host.as_mut()
            && let Some(update) = host.on_event(event, &mut self.next_tag)
        {
            return self.host_update(update);
        }
        match event {
            PaneEvent::Reply { tag, result, .. } if self.sent.get(tag) == Some(&Origin::Store) => {
                self.store_reply(*tag, result, family)
            }
            PaneEvent::Reply { tag, line, result } => {
                let Some(origin) = self.sent.remove(tag) else {
                    return Outcome::Ignored;
                };
                let progress = match (origin, self.batch.as_mut()) {
                    (Origin::Batch, Some(batch)) => batch.wait_progress(result),
                    _ => None,
                };
                // The reads of a `:wait-until` are not worth recording.
                if progress.is_none()
                    && let Ok(sent) = result
                {
                    self.record_sent(&sent.request);
                }
                if progress.is_none() {
                    self.session_record_answer(*tag, line, result, view);
                }
                if let Some(progress) = progress {
                    self.say_live(Role::Normal, format!("{PROMPT}{progress}"));
                } else {
                    if origin == Origin::Batch
                        && let Ok(r) = result
                    {
                        self.say(Role::Normal, format!("{PROMPT}{}", r.line));
                    }
                    // A line in an axis's unit: the raw line it became.
                    if let (Ok(r), Some(f)) = (result, family)
                        && has_units(f.console.units(), line)
                    {
                        self.say(Role::Muted, format!("  in raw: {}", r.line));
                    }
                    self.show_reply(family, result);
                }
                if origin == Origin::Batch {
                    let steps = match self.batch.as_mut() {
                        Some(batch) => batch.on_reply(result),
                        None => return Outcome::redraw(),
                    };
                    return self.batch_steps(steps, view);
                }
                Outcome::redraw()
            }
            PaneEvent::Wake { tag } if self.batch_wake == Some(*tag) => {
                self.batch_wake = None;
                let steps = self.batch.as_mut().map(Batch::on_wake).unwrap_or_default();
                self.batch_steps(steps, view)
            }
            PaneEvent::Busy(busy) => {
                self.busy = busy.clone();
                self.busy_family = family.map(|f| f.name);
                Outcome::redraw()
            }
            PaneEvent::Stopping => {
                if let Some(confirming) = self.confirming.take() {
                    let what = match confirming.then {
                        Deferred::Line(line) => line,
                        Deferred::Batch { batch, .. } => batch.name().to_string(),
                        Deferred::Host { file, .. } => file,
                    };
                    self.say(Role::Warning, format!("  not sent: {what}"));
                }
                self.store_job = None;
                self.session_record_stopping();
                // The stop ended a `:report`'s settings read too: its
                // sheet is written now, saying so.
                if let Some(tag) = self.report_pending.as_ref().map(|p| p.tag) {
                    let ended = Err("the emergency stop ended the read".to_string());
                    let _ = self.report_settings_read(tag, &ended);
                }
                let dropped = self.sent.len();
                self.sent.clear();
                self.batch_wake = None;
                let batch = self.batch.take().is_some();
                let host = self.stop_host_run();
                // The emergency stop ends the run and does the stopping.
                self.run_policy = None;
                let key = key_label(view.keymap, Context::Global, Action::EmergencyStop);
                self.say(
                    Role::Emergency,
                    format!("{key} EMERGENCY STOP: stopping every axis and any running program"),
                );
                if dropped > 0 || batch {
                    self.say(
                        Role::Warning,
                        format!(
                            "  {dropped} line(s) waiting for their turn or answer were dropped{}",
                            if batch { "; the batch was stopped" } else { "" }
                        ),
                    );
                }
                if let Some(name) = host {
                    self.say(
                        Role::Warning,
                        format!("  the host run of {name} was stopped: nothing more of it is sent"),
                    );
                }
                Outcome::redraw()
            }
            PaneEvent::SheetFact(fact) => self.session_record_fact(fact, view),
            PaneEvent::SettingsRead { tag, result } => self.report_settings_read(*tag, result),
            PaneEvent::EmergencyStop(results) => {
                self.session_record_stop_lines(results);
                for result in results {
                    match result {
                        Ok(r) => {
                            let line = r.line.clone();
                            self.say(Role::Emergency, format!("  sent {line}"));
                        }
                        Err(e) => self.say(Role::Error, format!("  stop line failed: {e}")),
                    }
                    self.show_reply(family, result);
                }
                let ok = results.iter().all(Result::is_ok);
                // A line the module never answers (SIXpack 2, §7) went out,
                // and that is all anyone can say of it.
                let unanswered = results
                    .iter()
                    .filter(|r| r.as_ref().is_ok_and(|r| r.reply.is_empty()))
                    .count();
                if ok && !results.is_empty() && unanswered == 0 {
                    self.say(Role::Ok, "STOP confirmed: every stop line answered ok");
                } else if ok && !results.is_empty() {
                    self.say(
                        Role::Warning,
                        format!(
                            "STOP sent: all {} stop lines went out, {unanswered} of them never \
                             acknowledged by the module: watch the axes stop",
                            results.len()
                        ),
                    );
                } else if results.is_empty() {
                    self.say(Role::Error, "STOP: nothing was sent (not connected)");
                } else {
                    self.say(Role::Error, "STOP: some stop lines failed; check the axes");
                }
                Outcome::redraw()
            }
            PaneEvent::RunEnded(aftermath) => {
                let overall = match aftermath {
                    RunAftermath::Left(_) => Role::Warning,
                    _ if aftermath.settled() => Role::Ok,
                    _ => Role::Error,
                };
                for line in aftermath.report() {
                    // A stop line with its answer, or one that failed.
                    let role = match line.strip_prefix("  ") {
                        Some(stop) if stop.contains(" → ") => Role::Emergency,
                        Some(_) => Role::Error,
                        None => overall,
                    };
                    self.say(role, line);
                }
                Outcome::redraw()
            }
            PaneEvent::Notice(notice) => {
                let role = match notice.level {
                    NoticeLevel::Info => Role::Accent,
                    NoticeLevel::Warning => Role::Warning,
                    NoticeLevel::Error => Role::Error,
                };
                self.say(role, notice.text.clone());
                Outcome::redraw()
            }
            PaneEvent::Snapshot => {
                self.session_record_status(view);
                if let Some(session) = view.session {
                    self.load_history(session.family);
                    self.offline_family = Some(session.family.name);
                }
                Outcome::Ignored
            }
            // Help follows the connect screen only while nothing is
            // connected: browsing its list does not change the module
            // the console talks to.
            PaneEvent::FamilyChosen(name) if view.session.is_none() => {
                self.offline_family = Some(name);
                Outcome::Ignored
            }
            PaneEvent::Device(DeviceEvent::Unsolicited { description, .. }) => {
                self.say(Role::Accent, format!("module: {description}"));
                Outcome::redraw()
            }
            PaneEvent::Device(DeviceEvent::StateChanged(state)) => {
                match state {
                    LinkState::Connected { link } => match self.reconnecting.take() {
                        Some(failed) => self.say(
                            Role::Ok,
                            format!(
                                "reconnected: link {link} open again (attempt {})",
                                failed.saturating_add(1)
                            ),
                        ),
                        None => self.say(Role::Ok, format!("link {link} open")),
                    },
                    LinkState::Disconnected {
                        reason,
                        attempts: 0,
                        retry_in,
                    } => {
                        self.reconnecting = Some(0);
                        self.say(
                            Role::Error,
                            format!(
                                "link lost: {reason}; trying again in {} ms",
                                retry_in.as_millis()
                            ),
                        );
                    }
                    LinkState::Disconnected {
                        reason,
                        attempts,
                        retry_in,
                    } => {
                        self.reconnecting = Some(*attempts);
                        // One line for every attempt, rewritten in place:
                        // a port gone for an hour is not a screen of lines.
                        self.say_live(
                            Role::Error,
                            format!(
                                "reconnect attempt {attempts} failed: {reason}; trying again in {} ms",
                                retry_in.as_millis()
                            ),
                        );
                    }
                    LinkState::Closed => {
                        self.reconnecting = None;
                        self.say(Role::Warning, "link closed");
                    }
                }
                Outcome::redraw()
            }
            _ => Outcome::Ignored,
        }
    }
}

fn not_connected() -> String {
    "not connected: `:connect --sim tmcm1110` (or --port PATH, --tcp HOST:PORT)".into()
}

/// A rate in Hz: a number, or `off`.
fn parse_rate(text: &str) -> Option<f64> {
    let text = text
        .trim()
        .trim_end_matches("Hz")
        .trim_end_matches("hz")
        .trim();
    if text.eq_ignore_ascii_case("off") {
        return Some(0.0);
    }
    text.parse::<f64>()
        .ok()
        .filter(|r| r.is_finite() && *r >= 0.0)
}

/// The index of the axis named `text` (its number or its name).
fn find_axis(session: &Snapshot, text: &str) -> Result<usize, String> {
    let text = text.trim();
    let by_number = text
        .parse::<u8>()
        .ok()
        .and_then(|n| session.axes.iter().position(|a| a.number == n));
    let by_name = || {
        session
            .axes
            .iter()
            .position(|a| a.name.eq_ignore_ascii_case(text))
    };
    by_number.or_else(by_name).ok_or_else(|| {
        let known: Vec<String> = session
            .axes
            .iter()
            .map(|a| format!("{} ({})", a.number, a.name))
            .collect();
        format!("no axis `{text}`: this module has {}", known.join(", "))
    })
}

#[cfg(test)]
mod tests;
