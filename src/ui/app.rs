//! The console's state and its event loop.
//!
//! [`App`] is plain state: it takes [`AppEvent`]s (keys, snapshot changes,
//! replies), hands them to the panes, and collects what the panes ask for
//! as [`Effect`]s for the loop to carry out. It draws with [`App::render`]
//! into any ratatui backend, so tests drive it with `TestBackend` and no
//! terminal.
//!
//! [`run`] is the loop: it sleeps until something happens (a key, a watch
//! channel of the session changing, traffic, a reply, a signal) and draws
//! only when the state changed, so an idle console costs nothing.

mod controller;
mod layout;
mod runner;
mod traffic_log;

pub use controller::{
    Connector, Controller, Pending, TuneJob, TuneOutcome, WiringFindings, no_simulator_to_drive,
};
pub use layout::{SIDE_MIN_WIDTH, TILE_MIN_HEIGHT, TILE_MIN_WIDTH};
pub use runner::{
    TRAFFIC_BATCH, TRAFFIC_BATCH_HIDDEN, TRAFFIC_HEADROOM, join_all, run, run_links, traffic_pause,
    worth_showing,
};
pub use traffic_log::log_line;

use std::time::Duration;

use ratatui::crossterm::event::{Event as TermEvent, KeyEvent, KeyEventKind};
use ratatui::layout::Rect;

use super::keymap::{Action, Context, Keymap, load_keymap};
use super::pane::{Input, ModuleEntry, Notice, Outcome, Pane, PaneEvent, Request, Snapshot, View};
use super::theme::{Theme, load_theme};
use crate::device::{Busy, DeviceEvent, TrafficRecord};
use crate::protocol::program::{Progress, TransferFailure, TransferJob, TransferReport};
use crate::session::run_end::{AtTheEnd, RunAftermath, RunEnding, StopOnFailure};
use crate::session::{AxisFlag, LineResult, PollCadence, SessionError};

/// How long a message stays in the status bar ("STOP: 3 sent, all ok"):
/// long enough to read, then the state it pushed aside is seen again.
pub const STATUS_MESSAGE_LIFETIME: Duration = Duration::from_secs(10);

/// Something that happened, for [`App::handle`].
#[derive(Debug)]
pub enum AppEvent {
    Terminal(TermEvent),
    /// A watch channel of the session changed: take this copy.
    Snapshot(Snapshot),
    /// A connection was just opened (at start or by `:connect`): its
    /// first snapshot. It replaces every module the console had.
    Connected(Snapshot),
    /// Module `index` of the list (on link `link`) changed, or joined the
    /// list (`index` one past its end): take this copy. For the selected
    /// module this is [`AppEvent::Snapshot`].
    Module {
        index: usize,
        link: usize,
        snapshot: Snapshot,
    },
    /// No controller any more (or not yet).
    Disconnected,
    Traffic(TrafficRecord),
    /// A frame on link `link` ([`ModuleEntry::link`]).
    LinkTraffic {
        link: usize,
        record: TrafficRecord,
    },
    Device(DeviceEvent),
    /// The controller is busy with a line that runs until its answer, or
    /// no longer.
    Busy(Option<Busy>),
    /// The answer to one line a pane sent.
    Reply {
        pane: usize,
        tag: u64,
        line: String,
        result: Result<LineResult, SessionError>,
    },
    /// The stop lines were sent; what came back for each.
    Stopped(Vec<Result<LineResult, SessionError>>),
    /// A pane's run was ended ([`Effect::EndRun`]): what was done.
    RunEnded {
        pane: usize,
        aftermath: RunAftermath,
    },
    Wake {
        pane: usize,
        tag: u64,
    },
    Notice(Notice),
    /// How far a pane's program transfer has come.
    TransferProgress {
        pane: usize,
        tag: u64,
        progress: Progress,
    },
    /// A pane's program transfer ended.
    Transferred {
        pane: usize,
        tag: u64,
        result: Result<TransferReport, TransferFailure>,
    },
    /// A status bar message has been up long enough (see
    /// [`Effect::Expire`]).
    Expired(u64),
    /// A pane's program was loaded into the simulator (or not).
    ProgramLoaded {
        pane: usize,
        tag: u64,
        result: Result<String, String>,
    },
    /// A pane's wiring check ended.
    WiringChecked {
        pane: usize,
        tag: u64,
        result: Result<WiringFindings, String>,
    },
    /// A pane's tuning job ended.
    Tuned {
        pane: usize,
        tag: u64,
        result: Result<TuneOutcome, String>,
    },
    /// A pane's settings read ([`Effect::ReadSettings`]) ended.
    SettingsRead {
        pane: usize,
        tag: u64,
        result: Result<crate::report::Settings, String>,
    },
    /// SIGTERM, SIGHUP: leave now.
    Terminate,
}

/// What the loop must do for the app.
#[derive(Debug, Clone, PartialEq)]
pub enum Effect {
    /// Send lines in order for a pane; each answer back as
    /// [`AppEvent::Reply`].
    Send {
        pane: usize,
        tag: u64,
        lines: Vec<String>,
    },
    /// Send lines that stop motion for a pane, each ahead of everything
    /// queued ([`Controller::execute_stop`]); each answer back as
    /// [`AppEvent::Reply`].
    SendStop {
        pane: usize,
        tag: u64,
        lines: Vec<String>,
    },
    /// Read a line for a pane until two answers agree
    /// ([`Controller::read_agreed`]); the answer back as [`AppEvent::Reply`].
    ReadAgreed {
        pane: usize,
        tag: u64,
        line: String,
    },
    /// Stop everything: abort the lines still waiting to be sent, then the
    /// session's emergency stop, ahead of anything queued.
    EmergencyStop,
    /// Abort the line the controller is busy with.
    AbortLine,
    /// Pause or resume the line the controller is busy with.
    PauseLine,
    /// End a pane's run ([`Controller::end_run`]); what was done back as
    /// [`AppEvent::RunEnded`].
    EndRun {
        pane: usize,
        ending: RunEnding,
        policy: StopOnFailure,
    },
    /// Check the axes after a pane's run completed
    /// ([`Controller::check_run_end`]), then end it as its check says.
    CheckRunEnd {
        pane: usize,
        check: AtTheEnd,
        policy: StopOnFailure,
    },
    Poll(Option<PollCadence>),
    SetAddress(u8),
    /// Forget these latched error flags of an axis.
    ClearErrors {
        axis: usize,
        seen: Vec<AxisFlag>,
    },
    Log(Option<(std::path::PathBuf, crate::files::Existing)>),
    Connect(Vec<String>),
    /// Open one more link beside those open ([`Request::AddLink`]).
    AddLink(Vec<String>),
    Wake {
        pane: usize,
        tag: u64,
        after: Duration,
    },
    /// Run a program transfer for a pane; progress and the end come back
    /// as [`AppEvent::TransferProgress`] and [`AppEvent::Transferred`].
    Transfer {
        pane: usize,
        tag: u64,
        job: TransferJob,
    },
    /// Cancel the running transfer (between two words).
    CancelTransfer,
    /// Load program source into the connected simulator for a pane; the
    /// answer back as [`AppEvent::ProgramLoaded`].
    LoadProgram {
        pane: usize,
        tag: u64,
        source: String,
    },
    /// Drive an input of the connected simulator; the answer back as an
    /// [`AppEvent::Notice`].
    DriveSimInput(String),
    /// Run the wiring check for a pane; the findings back as
    /// [`AppEvent::WiringChecked`].
    CheckWiring {
        pane: usize,
        tag: u64,
        axis: usize,
        speed: i64,
    },
    /// End the running wiring check where it is.
    CancelWiring,
    /// Run a tuning job for a pane; what it gave back as
    /// [`AppEvent::Tuned`].
    Tune {
        pane: usize,
        tag: u64,
        job: TuneJob,
    },
    /// End the running tuning job where it is.
    CancelTune,
    /// Read the settings with a factory default for a pane; them back as
    /// [`AppEvent::SettingsRead`].
    ReadSettings {
        pane: usize,
        tag: u64,
        sent: Vec<String>,
    },
    /// Take these mechanics as those in force, on every module.
    Mechanics(crate::protocol::units::MechanicsTable),
    /// Poll a read line with the status, or no longer
    /// ([`Request::Watch`]); a refusal back as an [`AppEvent::Notice`].
    Watch {
        axis: usize,
        line: String,
        on: bool,
        fast: bool,
    },
    /// Answer with [`AppEvent::Expired`] after this long: the status bar
    /// message `id` ages out.
    Expire {
        id: u64,
        after: Duration,
    },
    Quit,
}

impl Effect {
    /// The lines this effect sends for a pane, as (pane, tag, lines):
    /// those of [`Effect::Send`] and [`Effect::SendStop`], or the one line of
    /// [`Effect::ReadAgreed`]; each is answered as an [`AppEvent::Reply`].
    pub fn sends(&self) -> Option<(usize, u64, Vec<String>)> {
        match self {
            Effect::Send { pane, tag, lines } | Effect::SendStop { pane, tag, lines } => {
                Some((*pane, *tag, lines.clone()))
            }
            Effect::ReadAgreed { pane, tag, line } => Some((*pane, *tag, vec![line.clone()])),
            _ => None,
        }
    }
}

/// The console.
pub struct App {
    panes: Vec<Box<dyn Pane>>,
    focus: usize,
    /// When each pane last had the focus: a slot shows the pane of its own
    /// that had it most recently.
    focused_at: Vec<u64>,
    focus_clock: u64,
    theme: Theme,
    keymap: Keymap,
    snapshot: Option<Snapshot>,
    /// Every module of every link, grouped by link (the selected one's
    /// newest copy is `snapshot`).
    modules: Vec<ModuleEntry>,
    /// The selected module: index into `modules`, where lines go.
    module: usize,
    /// What the last emergency stop did, for the status bar, and its
    /// number (it ages out, see [`STATUS_MESSAGE_LIFETIME`]).
    last_stop: Option<(u64, String)>,
    status_messages: u64,
    dirty: bool,
    quit: bool,
    /// Ended from outside (SIGTERM, SIGHUP, SIGINT, the terminal gone):
    /// the loop stops every axis before it lets go ([`App::terminated`]).
    terminated: bool,
    /// What the loop did on its way out, for standard error once the
    /// terminal is given back ([`App::parting_report`]).
    parting: Vec<String>,
    /// Where each shown pane was drawn last, for mouse clicks.
    drawn: Vec<(usize, Rect)>,
    /// Where the user's themes and keymaps are (`:theme`, `:keymap`).
    config_dir: Option<std::path::PathBuf>,
    /// The options of the last `Request::Connect`, told to the panes
    /// when that connection opens.
    connect_args: Option<Vec<String>>,
    /// The line the controller is busy with, if any.
    busy: Option<Busy>,
}

impl App {
    /// A console with these panes; the first has the focus.
    pub fn new(panes: Vec<Box<dyn Pane>>, theme: Theme, keymap: Keymap) -> App {
        let count = panes.len();
        let mut focused_at = vec![0; count];
        if let Some(first) = focused_at.first_mut() {
            *first = 1;
        }
        App {
            panes,
            focus: 0,
            focused_at,
            focus_clock: 1,
            theme,
            keymap,
            snapshot: None,
            modules: Vec::new(),
            module: 0,
            last_stop: None,
            status_messages: 0,
            dirty: true,
            quit: false,
            terminated: false,
            parting: Vec::new(),
            drawn: Vec::new(),
            config_dir: None,
            connect_args: None,
            busy: None,
        }
    }

    /// Look for the user's themes and keymaps in `dir`.
    pub fn set_config_dir(&mut self, dir: Option<std::path::PathBuf>) {
        self.config_dir = dir;
    }

    /// Whether something changed since the last [`App::render`].
    pub fn needs_redraw(&self) -> bool {
        self.dirty
    }

    pub fn should_quit(&self) -> bool {
        self.quit
    }

    /// Whether the console was ended from outside ([`AppEvent::Terminate`])
    /// rather than quit by the user.
    pub fn terminated(&self) -> bool {
        self.terminated
    }

    /// What the loop did on its way out (the stop sent when the console
    /// was ended from outside), a line each; empty when nothing.
    pub fn parting_report(&self) -> &[String] {
        &self.parting
    }

    /// Keep `lines` for [`App::parting_report`].
    pub(crate) fn set_parting_report(&mut self, lines: Vec<String>) {
        self.parting = lines;
    }

    pub fn snapshot(&self) -> Option<&Snapshot> {
        self.snapshot.as_ref()
    }

    /// Every module of every link, grouped by link.
    pub fn modules(&self) -> &[ModuleEntry] {
        &self.modules
    }

    /// The selected module (index into [`App::modules`]): where lines go.
    pub fn selected_module(&self) -> usize {
        self.module
    }

    /// The line the controller is busy with, if any.
    pub fn busy(&self) -> Option<&Busy> {
        self.busy.as_ref()
    }

    pub fn theme(&self) -> &Theme {
        &self.theme
    }

    pub fn set_theme(&mut self, theme: Theme) {
        self.theme = theme;
        self.dirty = true;
    }

    pub fn keymap(&self) -> &Keymap {
        &self.keymap
    }

    pub fn set_keymap(&mut self, keymap: Keymap) {
        self.keymap = keymap;
        self.dirty = true;
    }

    /// The name of the pane with the focus.
    pub fn focused(&self) -> Option<&'static str> {
        self.panes.get(self.focus).map(|p| p.name())
    }

    /// Give the focus to the pane called `name`.
    pub fn focus(&mut self, name: &str) -> bool {
        match self.panes.iter().position(|p| p.name() == name) {
            Some(index) => {
                self.focus_index(index);
                true
            }
            None => false,
        }
    }

    fn focus_index(&mut self, index: usize) {
        if index < self.panes.len() {
            self.focus = index;
            self.focus_clock += 1;
            if let Some(at) = self.focused_at.get_mut(index) {
                *at = self.focus_clock;
            }
            self.dirty = true;
        }
    }

    /// Take in one event; returns what the loop must do.
    pub fn handle(&mut self, event: AppEvent) -> Vec<Effect> {
        let mut effects = Vec::new();
        let focus_before = self.focus;
        match event {
            AppEvent::Terminal(event) => self.terminal_event(event, &mut effects),
            AppEvent::Snapshot(snapshot) => {
                let changed = self
                    .snapshot
                    .as_ref()
                    .is_none_or(|old| !same(old, &snapshot));
                if changed {
                    match self.modules.get_mut(self.module) {
                        Some(entry) => entry.snapshot = snapshot.clone(),
                        None => self.modules.push(ModuleEntry {
                            link: 0,
                            snapshot: snapshot.clone(),
                        }),
                    }
                    self.snapshot = Some(snapshot);
                    self.dirty = true;
                    self.broadcast(&PaneEvent::Snapshot, &mut effects);
                }
            }
            AppEvent::Module {
                index,
                link,
                snapshot,
            } => self.module_changed(index, link, snapshot, &mut effects),
            AppEvent::Connected(snapshot) => {
                self.modules = vec![ModuleEntry {
                    link: 0,
                    snapshot: snapshot.clone(),
                }];
                self.module = 0;
                self.snapshot = Some(snapshot);
                self.dirty = true;
                self.broadcast(&PaneEvent::Snapshot, &mut effects);
                let args = self.connect_args.take();
                self.broadcast(&PaneEvent::Connected { args }, &mut effects);
            }
            AppEvent::Disconnected => {
                if self.busy.take().is_some() {
                    self.broadcast(&PaneEvent::Busy(None), &mut effects);
                }
                self.modules.clear();
                self.module = 0;
                if self.snapshot.take().is_some() {
                    self.dirty = true;
                    self.broadcast(&PaneEvent::Snapshot, &mut effects);
                }
            }
            AppEvent::Busy(busy) => {
                if self.busy != busy {
                    self.busy = busy.clone();
                    self.dirty = true;
                    self.broadcast(&PaneEvent::Busy(busy), &mut effects);
                }
            }
            AppEvent::Traffic(record) => self.broadcast(&PaneEvent::Traffic(record), &mut effects),
            AppEvent::LinkTraffic { link, record } => {
                self.broadcast(&PaneEvent::LinkTraffic { link, record }, &mut effects)
            }
            AppEvent::Device(event) => self.broadcast(&PaneEvent::Device(event), &mut effects),
            AppEvent::Reply {
                pane,
                tag,
                line,
                result,
            } => {
                let event = PaneEvent::Reply { tag, line, result };
                self.deliver(pane, &event, &mut effects);
            }
            AppEvent::Wake { pane, tag } => {
                self.deliver(pane, &PaneEvent::Wake { tag }, &mut effects)
            }
            AppEvent::Stopped(results) => {
                let failed = results.iter().filter(|r| r.is_err()).count();
                // Lines the module never answers went out, no more.
                let unanswered = results
                    .iter()
                    .filter(|r| r.as_ref().is_ok_and(|r| r.reply.is_empty()))
                    .count();
                let text = match (failed, results.len()) {
                    (_, 0) => "STOP not sent".to_string(),
                    (0, n) if unanswered > 0 => {
                        format!("STOP: {n} sent, {unanswered} unacknowledged")
                    }
                    (0, n) => format!("STOP: {n} sent, all ok"),
                    (failed, n) => format!("STOP: {failed} of {n} FAILED"),
                };
                let id = self.status_message(text);
                effects.push(Effect::Expire {
                    id,
                    after: STATUS_MESSAGE_LIFETIME,
                });
                self.dirty = true;
                self.broadcast(&PaneEvent::EmergencyStop(results), &mut effects);
            }
            AppEvent::RunEnded { pane, aftermath } => {
                self.deliver(pane, &PaneEvent::RunEnded(aftermath), &mut effects);
            }
            AppEvent::Notice(notice) => self.broadcast(&PaneEvent::Notice(notice), &mut effects),
            AppEvent::TransferProgress {
                pane,
                tag,
                progress,
            } => {
                let event = PaneEvent::TransferProgress { tag, progress };
                self.deliver(pane, &event, &mut effects);
            }
            AppEvent::Transferred { pane, tag, result } => {
                let event = PaneEvent::Transferred { tag, result };
                self.deliver(pane, &event, &mut effects);
            }
            AppEvent::Expired(id) => {
                if self
                    .last_stop
                    .as_ref()
                    .is_some_and(|(shown, _)| *shown == id)
                {
                    self.last_stop = None;
                    self.dirty = true;
                }
            }
            AppEvent::WiringChecked { pane, tag, result } => {
                let event = PaneEvent::WiringChecked { tag, result };
                self.deliver(pane, &event, &mut effects);
            }
            AppEvent::Tuned { pane, tag, result } => {
                let event = PaneEvent::Tuned { tag, result };
                self.deliver(pane, &event, &mut effects);
            }
            AppEvent::SettingsRead { pane, tag, result } => {
                let event = PaneEvent::SettingsRead { tag, result };
                self.deliver(pane, &event, &mut effects);
            }
            AppEvent::ProgramLoaded { pane, tag, result } => {
                let event = PaneEvent::ProgramLoaded { tag, result };
                self.deliver(pane, &event, &mut effects);
            }
            AppEvent::Terminate => {
                self.quit = true;
                self.terminated = true;
                effects.push(Effect::Quit);
            }
        }
        if self.focus != focus_before {
            self.deliver(focus_before, &PaneEvent::Unfocused, &mut effects);
            self.deliver(self.focus, &PaneEvent::Focused, &mut effects);
        }
        effects
    }

    fn terminal_event(&mut self, event: TermEvent, effects: &mut Vec<Effect>) {
        match event {
            TermEvent::Key(key) if key.kind != KeyEventKind::Release => self.key(key, effects),
            TermEvent::Key(_) => {}
            TermEvent::Mouse(mouse) => {
                use ratatui::crossterm::event::MouseEventKind;
                if let MouseEventKind::Down(_) = mouse.kind {
                    let hit = self.drawn.iter().find(|(_, r)| {
                        r.contains(ratatui::layout::Position::new(mouse.column, mouse.row))
                    });
                    if let Some(&(index, _)) = hit
                        && index != self.focus
                    {
                        self.focus_index(index);
                        return;
                    }
                }
                self.give_focused(&Input::Mouse(mouse), effects);
            }
            TermEvent::Paste(text) => {
                self.give_focused(&Input::Paste(text), effects);
            }
            TermEvent::Resize(_, _) => self.dirty = true,
            TermEvent::FocusLost => self.deliver(self.focus, &PaneEvent::Unfocused, effects),
            TermEvent::FocusGained => {}
        }
    }

    /// The keymap section of the pane with the focus.
    fn context(&self) -> Context {
        self.panes
            .get(self.focus)
            .map_or(Context::Global, |p| p.context())
    }

    fn key(&mut self, key: KeyEvent, effects: &mut Vec<Effect>) {
        let action = self.keymap.action_for(self.context(), &key);
        // The emergency stop, quit and the pane keys work whatever the
        // focus, before the pane sees the key.
        match action {
            Some(Action::EmergencyStop) => {
                self.emergency_stop(effects);
                return;
            }
            Some(Action::Quit) => {
                self.quit = true;
                effects.push(Effect::Quit);
                return;
            }
            Some(a) => {
                if let Some(n) = a.pane_number() {
                    self.focus_index(usize::from(n).saturating_sub(1));
                    return;
                }
            }
            None => {}
        }
        if self.give_focused(&Input::Key(key), effects) {
            return;
        }
        match action {
            Some(Action::NextPane) => self.cycle_focus(1),
            Some(Action::PreviousPane) => self.cycle_focus(self.panes.len().saturating_sub(1)),
            Some(Action::Help) => {
                let help = self.key_help();
                self.broadcast(&PaneEvent::Notice(Notice::info(help)), effects);
            }
            Some(Action::ClearErrors) => {
                let axis = self.snapshot.as_ref().map(|s| s.axis);
                if let Some(axis) = axis {
                    self.request(self.focus, Request::ClearErrors(axis), effects);
                }
            }
            _ => {}
        }
    }

    /// The keys of the pane with the focus, global ones first, one line.
    pub fn key_help(&self) -> String {
        let context = self.context();
        let mut parts = Vec::new();
        for binding in self.keymap.bindings() {
            if binding.context != Context::Global && binding.context != context {
                continue;
            }
            if binding.action.pane_number().is_some_and(|n| n > 1) {
                continue;
            }
            if let Some(chord) = binding.chords.first() {
                let title = match binding.action.pane_number() {
                    Some(_) => "Pane N".to_string(),
                    None => binding.action.title().to_string(),
                };
                let label = match binding.action.pane_number() {
                    Some(_) => chord.label().replace('1', "N"),
                    None => chord.label(),
                };
                parts.push(format!("{label} {title}"));
            }
        }
        format!("keys: {}", parts.join(" · "))
    }

    fn emergency_stop(&mut self, effects: &mut Vec<Effect>) {
        // In progress: state, up until the stop's answers come.
        self.status_message("STOP sending…".into());
        self.dirty = true;
        // The loop drops the lines of every earlier Send before it stops.
        effects.push(Effect::EmergencyStop);
        self.broadcast(&PaneEvent::Stopping, effects);
    }

    /// Module `index` changed or joined the list.
    fn module_changed(
        &mut self,
        index: usize,
        link: usize,
        snapshot: Snapshot,
        effects: &mut Vec<Effect>,
    ) {
        if index == self.module && self.snapshot.is_some() {
            if let Some(entry) = self.modules.get_mut(index) {
                entry.link = link;
            }
            let axis = self.snapshot.as_ref().map_or(0, |s| s.axis);
            let snapshot = Snapshot {
                axis: axis.min(snapshot.axes.len().saturating_sub(1)),
                ..snapshot
            };
            let changed = self
                .snapshot
                .as_ref()
                .is_none_or(|old| !same(old, &snapshot));
            if changed {
                if let Some(entry) = self.modules.get_mut(index) {
                    entry.snapshot = snapshot.clone();
                }
                self.snapshot = Some(snapshot);
                self.dirty = true;
                self.broadcast(&PaneEvent::Snapshot, effects);
            }
            return;
        }
        let entry = ModuleEntry { link, snapshot };
        let count = self.modules.len();
        match self.modules.get_mut(index) {
            Some(old) if old.link == entry.link && same(&old.snapshot, &entry.snapshot) => return,
            Some(old) => {
                *old = entry;
                // The panes that show it decide when it is drawn (numbers
                // at a readable rate, as the selected module's).
                self.broadcast(&PaneEvent::ModuleChanged(index), effects);
                return;
            }
            None if index == count => self.modules.push(entry),
            None => return,
        }
        if self.snapshot.is_none() {
            // The first module of a console that had none.
            self.select_module(index, effects);
        } else {
            // A module joined the list: the panes hear of it.
            self.broadcast(&PaneEvent::Snapshot, effects);
        }
        self.dirty = true;
    }

    /// Lines go to module `index` from now on; the panes follow it.
    fn select_module(&mut self, index: usize, effects: &mut Vec<Effect>) {
        let Some(entry) = self.modules.get(index) else {
            let notice = Notice::error(format!(
                "no module {}: the console has {} ({})",
                index + 1,
                self.modules.len(),
                ":module N picks one of them"
            ));
            self.broadcast(&PaneEvent::Notice(notice), effects);
            return;
        };
        let snapshot = entry.snapshot.clone();
        // The axis chosen on the module left is kept for coming back.
        if let (Some(left), Some(current)) = (self.modules.get_mut(self.module), &self.snapshot) {
            left.snapshot = current.clone();
        }
        self.module = index;
        self.snapshot = Some(snapshot);
        self.dirty = true;
        self.broadcast(&PaneEvent::Snapshot, effects);
    }

    /// The selected module as the status bar and the prompt name it:
    /// `module 2/3 sim cmd4cr #1`; `None` with one module or none.
    pub fn module_label(&self) -> Option<String> {
        if self.modules.len() < 2 {
            return None;
        }
        let s = &self.modules.get(self.module)?.snapshot;
        Some(format!(
            "module {}/{} {} #{}",
            self.module + 1,
            self.modules.len(),
            s.link_name,
            s.address
        ))
    }

    /// Show `text` in the status bar as its newest message; its number.
    fn status_message(&mut self, text: String) -> u64 {
        self.status_messages += 1;
        self.last_stop = Some((self.status_messages, text));
        self.status_messages
    }

    fn cycle_focus(&mut self, step: usize) {
        if !self.panes.is_empty() {
            self.focus_index((self.focus + step) % self.panes.len());
        }
    }

    /// Hand input to the focused pane; true if it took it.
    fn give_focused(&mut self, input: &Input, effects: &mut Vec<Effect>) -> bool {
        let index = self.focus;
        let view = View {
            theme: &self.theme,
            keymap: &self.keymap,
            session: self.snapshot.as_ref(),
            modules: &self.modules,
            module: self.module,
            focused: true,
            shown: true,
        };
        let Some(pane) = self.panes.get_mut(index) else {
            return false;
        };
        let outcome = pane.handle_input(input, &view);
        self.outcome(index, outcome, effects)
    }

    fn broadcast(&mut self, event: &PaneEvent, effects: &mut Vec<Effect>) {
        for index in 0..self.panes.len() {
            self.deliver(index, event, effects);
        }
    }

    fn deliver(&mut self, index: usize, event: &PaneEvent, effects: &mut Vec<Effect>) {
        let view = View {
            theme: &self.theme,
            keymap: &self.keymap,
            session: self.snapshot.as_ref(),
            modules: &self.modules,
            module: self.module,
            focused: index == self.focus,
            shown: self.is_shown(index),
        };
        let Some(pane) = self.panes.get_mut(index) else {
            return;
        };
        let outcome = pane.on_event(event, &view);
        self.outcome(index, outcome, effects);
    }

    /// Carry out a pane's outcome; true if it was handled.
    fn outcome(&mut self, pane: usize, outcome: Outcome, effects: &mut Vec<Effect>) -> bool {
        let Outcome::Handled(requests) = outcome else {
            return false;
        };
        // A pane behind a tab draws nothing: it is drawn afresh when it
        // comes to the front (the focus moving marks the screen dirty).
        if self.is_shown(pane) {
            self.dirty = true;
        }
        for request in requests {
            self.request(pane, request, effects);
        }
        true
    }

    /// Whether the pane called `name` was on the screen at the last draw.
    pub fn is_on_screen(&self, name: &str) -> bool {
        self.panes
            .iter()
            .position(|p| p.name() == name)
            .is_some_and(|index| self.is_shown(index))
    }

    /// Whether `pane` was on the screen at the last draw (before the
    /// first draw, every pane counts as shown).
    fn is_shown(&self, pane: usize) -> bool {
        self.drawn.is_empty() || self.drawn.iter().any(|(index, _)| *index == pane)
    }

    fn request(&mut self, pane: usize, request: Request, effects: &mut Vec<Effect>) {
        match request {
            Request::Send { lines, tag } => effects.push(Effect::Send { pane, tag, lines }),
            Request::SendStop { lines, tag } => {
                effects.push(Effect::SendStop { pane, tag, lines });
            }
            Request::ReadAgreed { line, tag } => {
                effects.push(Effect::ReadAgreed { pane, tag, line })
            }
            Request::EmergencyStop => self.emergency_stop(effects),
            Request::SelectModule(index) => self.select_module(index, effects),
            Request::AddLink(args) => effects.push(Effect::AddLink(args)),
            Request::TrafficLink(link) => self.broadcast(&PaneEvent::TrafficLink(link), effects),
            Request::AbortLine => effects.push(Effect::AbortLine),
            Request::PauseLine => effects.push(Effect::PauseLine),
            Request::EndRun { ending, policy } => effects.push(Effect::EndRun {
                pane,
                ending,
                policy,
            }),
            Request::CheckRunEnd { check, policy } => effects.push(Effect::CheckRunEnd {
                pane,
                check,
                policy,
            }),
            Request::Poll(rate) => effects.push(Effect::Poll(cadence_for(rate))),
            Request::SelectAxis(axis) => {
                if let Some(snapshot) = self.snapshot.as_mut()
                    && axis < snapshot.axes.len()
                {
                    snapshot.axis = axis;
                    self.broadcast(&PaneEvent::Snapshot, effects);
                }
            }
            Request::SetAddress(address) => effects.push(Effect::SetAddress(address)),
            Request::ClearErrors(axis) => {
                let seen = self
                    .snapshot
                    .as_ref()
                    .and_then(|s| s.status.get(axis))
                    .map(|s| s.errors.clone())
                    .unwrap_or_default();
                effects.push(Effect::ClearErrors { axis, seen });
            }
            Request::Log(path) => effects.push(Effect::Log(path)),
            Request::Theme(name) => {
                let loaded = load_theme(&name, self.config_dir.as_deref());
                let notice = match &loaded.problem {
                    Some(problem) => Notice::error(problem.to_string()),
                    None => Notice::info(format!("theme {}", loaded.value.name())),
                };
                self.set_theme(loaded.value);
                self.broadcast(&PaneEvent::Notice(notice), effects);
            }
            Request::Keymap(name) => {
                let loaded = load_keymap(&name, self.config_dir.as_deref());
                let notice = match &loaded.problem {
                    Some(problem) => Notice::error(problem.to_string()),
                    None => Notice::info(format!(
                        "keymap {}: {}",
                        loaded.value.name(),
                        loaded.value.stop_hint()
                    )),
                };
                self.set_keymap(loaded.value);
                self.broadcast(&PaneEvent::Notice(notice), effects);
            }
            Request::Connect(args) => {
                self.connect_args = Some(args.clone());
                effects.push(Effect::Connect(args));
            }
            Request::Focus(name) => {
                self.focus(name);
            }
            Request::ChooseFamily(name) => {
                self.broadcast(&PaneEvent::FamilyChosen(name), effects);
            }
            Request::WakeAfter { after, tag } => effects.push(Effect::Wake { pane, tag, after }),
            Request::Transfer { job, tag } => effects.push(Effect::Transfer { pane, tag, job }),
            Request::CancelTransfer => effects.push(Effect::CancelTransfer),
            Request::LoadProgram { source, tag } => {
                effects.push(Effect::LoadProgram { pane, tag, source })
            }
            Request::DriveSimInput(setting) => effects.push(Effect::DriveSimInput(setting)),
            Request::CheckWiring { axis, speed, tag } => effects.push(Effect::CheckWiring {
                pane,
                tag,
                axis,
                speed,
            }),
            Request::CancelWiring => effects.push(Effect::CancelWiring),
            Request::Tune { job, tag } => effects.push(Effect::Tune { pane, tag, job }),
            Request::CancelTune => effects.push(Effect::CancelTune),
            Request::Mechanics(table) => effects.push(Effect::Mechanics(table)),
            Request::Watch {
                axis,
                line,
                on,
                fast,
            } => effects.push(Effect::Watch {
                axis,
                line,
                on,
                fast,
            }),
            Request::Plot(args) => self.broadcast(&PaneEvent::Plot(args), effects),
            Request::SheetFact(fact) => self.broadcast(&PaneEvent::SheetFact(fact), effects),
            Request::ReadSettings { sent, tag } => {
                effects.push(Effect::ReadSettings { pane, tag, sent })
            }
            Request::Say(notice) => self.broadcast(&PaneEvent::Notice(notice), effects),
            Request::Quit => {
                self.quit = true;
                effects.push(Effect::Quit);
            }
        }
    }
}

/// Whether two snapshots would draw the same.
fn same(a: &Snapshot, b: &Snapshot) -> bool {
    a.address == b.address
        && a.link_name == b.link_name
        && a.axes == b.axes
        && a.status == b.status
        && a.link == b.link
        && a.identity == b.identity
        && a.poll == b.poll
        && a.settings == b.settings
        && a.mechanics == b.mechanics
        && a.axis == b.axis
        && std::ptr::eq(a.family, b.family)
}

/// Poll `rate` times a second for what moves and a quarter as often for
/// the rest (the session's default ratio); 0 or less stops polling.
pub fn cadence_for(rate: f64) -> Option<PollCadence> {
    if !rate.is_finite() || rate <= 0.0 {
        return None;
    }
    let fast = Duration::from_secs_f64(1.0 / rate.min(1000.0));
    Some(PollCadence {
        fast,
        slow: fast * 4,
    })
}

/// Times a second for a polling period, rounded for the status bar.
pub fn rate_of(period: Duration) -> String {
    let hz = 1.0 / period.as_secs_f64();
    if (hz - hz.round()).abs() < 0.05 {
        format!("{}", hz.round())
    } else {
        format!("{hz:.1}")
    }
}

#[cfg(test)]
mod tests;
