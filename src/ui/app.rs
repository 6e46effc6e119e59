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

use std::future::Future;
use std::io::Write;
use std::path::Path;
use std::pin::Pin;
use std::sync::Arc;
use std::time::{Duration, Instant};

use ratatui::Frame;
use ratatui::crossterm::event::{Event as TermEvent, KeyEvent, KeyEventKind};
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph};
use tokio::sync::{broadcast, mpsc, oneshot, watch};
use tokio::task::JoinHandle;

use super::keymap::{Action, Context, Keymap, load_keymap};
use super::pane::{
    Input, Notice, Outcome, Pane, PaneEvent, Region, Request, Snapshot, TransferDone, TransferJob,
    View, key_label,
};
use super::theme::{Role, Theme, load_theme};
use crate::device::{DeviceEvent, Direction, LinkState, Priority, TrafficKind, TrafficRecord};
use crate::protocol::Family;
use crate::session::program::{Cancel, Progress, TransferError};
use crate::session::run_end::{LinkAtStop, RunAftermath, RunEnding, RunStop, StopOnFailure};
use crate::session::{AxisFlag, AxisInfo, AxisStatus, LineResult, PollCadence, SessionError};

/// How long the loop lets traffic gather before it hands it to the panes:
/// status polling alone sends a hundred or more frames a second, and
/// waking the loop for each cost more than everything else an idle
/// console does. The first frame after a quiet spell is handed on at once;
/// the traffic monitor redraws no more often than this anyway
/// ([`super::traffic::REFRESH`]).
pub const TRAFFIC_BATCH: Duration = super::traffic::REFRESH;

/// How long traffic may gather while the traffic monitor is not on screen
/// (it keeps recording behind its tab): the pause doubles from
/// [`TRAFFIC_BATCH`] up to this while frames keep coming.
pub const TRAFFIC_BATCH_HIDDEN: Duration = Duration::from_secs(1);

/// Records a pause may let gather at the rate last seen: a quarter of the
/// device's traffic stream ([`crate::device::TRAFFIC_CAPACITY`]), so that
/// a fast transfer shortens the pause before the stream overflows.
pub const TRAFFIC_HEADROOM: usize = crate::device::TRAFFIC_CAPACITY / 4;

/// The pane that shows traffic (see [`App::is_on_screen`]).
const TRAFFIC_PANE: &str = "traffic";

/// The pause after a batch of `taken` records gathered over `seen`:
/// [`TRAFFIC_BATCH`] after a quiet spell (`fresh`), else twice the last
/// one, at most `longest`, and never so long that [`TRAFFIC_HEADROOM`]
/// records would come at the rate just seen.
pub fn traffic_pause(
    fresh: bool,
    last: Duration,
    longest: Duration,
    taken: usize,
    seen: Duration,
) -> Duration {
    let pause = if fresh {
        TRAFFIC_BATCH
    } else {
        last.saturating_mul(2)
    }
    .min(longest);
    let Ok(taken) = u32::try_from(taken) else {
        return Duration::from_millis(1);
    };
    if taken == 0 {
        return pause;
    }
    let headroom = u32::try_from(TRAFFIC_HEADROOM).unwrap_or(u32::MAX);
    let safe = seen.saturating_mul(headroom) / taken;
    pause.min(safe).max(Duration::from_millis(1))
}

/// Below this many rows (or columns) for the panes, every pane is a tab of
/// one region.
pub const TILE_MIN_HEIGHT: u16 = 16;
pub const TILE_MIN_WIDTH: u16 = 40;
/// From this width the side panes get a column of their own.
pub const SIDE_MIN_WIDTH: u16 = 160;
/// Rows the main region keeps at least when the top region is tall.
const MAIN_MIN_HEIGHT: u16 = 10;

/// Something that happened, for [`App::handle`].
#[derive(Debug)]
pub enum AppEvent {
    Terminal(TermEvent),
    /// A watch channel of the session changed: take this copy.
    Snapshot(Snapshot),
    /// A connection was just opened (at start or by `:connect`): its
    /// first snapshot.
    Connected(Snapshot),
    /// No controller any more (or not yet).
    Disconnected,
    Traffic(TrafficRecord),
    Device(DeviceEvent),
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
        result: Result<TransferDone, TransferError>,
    },
    /// A pane's program was loaded into the simulator (or not).
    ProgramLoaded {
        pane: usize,
        tag: u64,
        result: Result<String, String>,
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
    /// Stop everything: abort the lines still waiting to be sent, then the
    /// session's emergency stop, ahead of anything queued.
    EmergencyStop,
    /// End a pane's run ([`Controller::end_run`]); what was done back as
    /// [`AppEvent::RunEnded`].
    EndRun {
        pane: usize,
        ending: RunEnding,
        policy: StopOnFailure,
    },
    Poll(Option<PollCadence>),
    SetAddress(u8),
    /// Forget these latched error flags of an axis.
    ClearErrors {
        axis: usize,
        seen: Vec<AxisFlag>,
    },
    Log(Option<std::path::PathBuf>),
    Connect(Vec<String>),
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
    Quit,
}

/// Which part of the screen a pane is drawn in, after the screen size
/// decided how many parts there are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Slot {
    Top,
    Main,
    Side,
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
    /// What the last emergency stop did, for the status bar.
    last_stop: Option<String>,
    dirty: bool,
    quit: bool,
    /// Where each shown pane was drawn last, for mouse clicks.
    drawn: Vec<(usize, Rect)>,
    /// Where the user's themes and keymaps are (`:theme`, `:keymap`).
    config_dir: Option<std::path::PathBuf>,
    /// The options of the last `Request::Connect`, told to the panes
    /// when that connection opens.
    connect_args: Option<Vec<String>>,
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
            last_stop: None,
            dirty: true,
            quit: false,
            drawn: Vec::new(),
            config_dir: None,
            connect_args: None,
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

    pub fn snapshot(&self) -> Option<&Snapshot> {
        self.snapshot.as_ref()
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
                    self.snapshot = Some(snapshot);
                    self.dirty = true;
                    self.broadcast(&PaneEvent::Snapshot, &mut effects);
                }
            }
            AppEvent::Connected(snapshot) => {
                self.snapshot = Some(snapshot);
                self.dirty = true;
                self.broadcast(&PaneEvent::Snapshot, &mut effects);
                let args = self.connect_args.take();
                self.broadcast(&PaneEvent::Connected { args }, &mut effects);
            }
            AppEvent::Disconnected => {
                if self.snapshot.take().is_some() {
                    self.dirty = true;
                    self.broadcast(&PaneEvent::Snapshot, &mut effects);
                }
            }
            AppEvent::Traffic(record) => self.broadcast(&PaneEvent::Traffic(record), &mut effects),
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
                self.last_stop = Some(match (failed, results.len()) {
                    (_, 0) => "STOP not sent".to_string(),
                    (0, n) => format!("STOP: {n} sent, all ok"),
                    (failed, n) => format!("STOP: {failed} of {n} FAILED"),
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
            AppEvent::ProgramLoaded { pane, tag, result } => {
                let event = PaneEvent::ProgramLoaded { tag, result };
                self.deliver(pane, &event, &mut effects);
            }
            AppEvent::Terminate => {
                self.quit = true;
                effects.push(Effect::Quit);
            }
        }
        if self.focus != focus_before {
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
            TermEvent::FocusGained | TermEvent::FocusLost => {}
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
        self.last_stop = Some("STOP sending…".into());
        self.dirty = true;
        // The loop drops the lines of every earlier Send before it stops.
        effects.push(Effect::EmergencyStop);
        self.broadcast(&PaneEvent::Stopping, effects);
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
            Request::EmergencyStop => self.emergency_stop(effects),
            Request::EndRun { ending, policy } => effects.push(Effect::EndRun {
                pane,
                ending,
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
            Request::Quit => {
                self.quit = true;
                effects.push(Effect::Quit);
            }
        }
    }

    /// Draw the whole screen.
    pub fn render(&mut self, frame: &mut Frame) {
        self.dirty = false;
        let area = frame.area();
        // Ordinary text first; every other role patches over it.
        frame.render_widget(Block::default().style(self.theme.style(Role::Normal)), area);
        let [body, status] =
            Layout::vertical([Constraint::Min(1), Constraint::Length(1)]).areas(area);
        self.drawn.clear();
        for (slot, rect) in self.slots(body) {
            let members: Vec<usize> = (0..self.panes.len())
                .filter(|&i| self.slot_of(i, body) == slot)
                .collect();
            let Some(&shown) = members
                .iter()
                .max_by_key(|&&i| self.focused_at.get(i).copied().unwrap_or(0))
            else {
                continue;
            };
            self.render_slot(frame, rect, &members, shown);
        }
        self.render_status(frame, status);
    }

    /// The slots the screen has room for, with their areas.
    fn slots(&self, body: Rect) -> Vec<(Slot, Rect)> {
        let mode = Mode::of(body);
        if mode == Mode::Tabs {
            return vec![(Slot::Main, body)];
        }
        let has = |region: Region| self.panes.iter().any(|p| p.region() == region);
        let mut slots = Vec::new();
        let mut rest = body;
        if has(Region::Top) {
            let view = self.view(false);
            let inner_width = body.width.saturating_sub(2);
            let room = body.height.saturating_sub(MAIN_MIN_HEIGHT);
            let wanted = self
                .panes
                .iter()
                .filter(|p| p.region() == Region::Top)
                .filter_map(|p| p.height_hint(&view, inner_width, room.saturating_sub(2)))
                .max()
                .unwrap_or(body.height / 3)
                .saturating_add(2);
            let top = wanted.min(room);
            let [top_area, below] =
                Layout::vertical([Constraint::Length(top), Constraint::Min(0)]).areas(body);
            slots.push((Slot::Top, top_area));
            rest = below;
        }
        if mode == Mode::Columns && has(Region::Side) && has(Region::Main) {
            let [main, side] =
                Layout::horizontal([Constraint::Percentage(55), Constraint::Percentage(45)])
                    .areas(rest);
            slots.push((Slot::Main, main));
            slots.push((Slot::Side, side));
        } else {
            slots.push((Slot::Main, rest));
        }
        slots
    }

    fn slot_of(&self, index: usize, body: Rect) -> Slot {
        let Some(pane) = self.panes.get(index) else {
            return Slot::Main;
        };
        match (Mode::of(body), pane.region()) {
            (Mode::Tabs, _) => Slot::Main,
            (_, Region::Top) => Slot::Top,
            (Mode::Columns, Region::Side)
                if self.panes.iter().any(|p| p.region() == Region::Main) =>
            {
                Slot::Side
            }
            _ => Slot::Main,
        }
    }

    fn view(&self, focused: bool) -> View<'_> {
        View {
            theme: &self.theme,
            keymap: &self.keymap,
            session: self.snapshot.as_ref(),
            focused,
            shown: true,
        }
    }

    /// A bordered slot: its title is the shown pane's, or a tab strip when
    /// several panes share the slot.
    fn render_slot(&mut self, frame: &mut Frame, area: Rect, members: &[usize], shown: usize) {
        let focused = shown == self.focus;
        let theme = &self.theme;
        let border = theme.style(if focused {
            Role::BorderFocused
        } else {
            Role::Border
        });
        let view = View {
            theme,
            keymap: &self.keymap,
            session: self.snapshot.as_ref(),
            focused,
            shown: true,
        };
        let mut title = vec![Span::raw(" ")];
        for (n, &index) in members.iter().enumerate() {
            let Some(pane) = self.panes.get(index) else {
                continue;
            };
            if n > 0 {
                title.push(Span::styled(" │ ", border));
            }
            let text = if members.len() > 1 {
                format!("{} {}", index + 1, pane.title(&view))
            } else {
                pane.title(&view)
            };
            let style = if index == shown {
                theme.style(Role::Title)
            } else {
                theme.style(Role::Muted)
            };
            title.push(Span::styled(text, style));
        }
        title.push(Span::raw(" "));
        let block = Block::default()
            .borders(Borders::ALL)
            .border_style(border)
            .title(Line::from(title));
        let inner = block.inner(area);
        frame.render_widget(block, area);
        if let Some(pane) = self.panes.get_mut(shown) {
            pane.render(frame, inner, &view);
        }
        self.drawn.push((shown, area));
    }

    fn render_status(&self, frame: &mut Frame, area: Rect) {
        let theme = &self.theme;
        let bar = theme.style(Role::StatusBar);
        let key = theme.style(Role::StatusKey);
        let mut spans = vec![
            Span::styled(
                format!(" {} ", self.keymap.stop_hint()),
                theme.style(Role::Emergency),
            ),
            Span::styled(" ", bar),
        ];
        if let Some(stop) = &self.last_stop {
            spans.push(Span::styled(format!("{stop} │ "), bar));
        }
        for activity in self.panes.iter().filter_map(|p| p.activity()) {
            spans.push(Span::styled(activity, key));
            spans.push(Span::styled(" │ ", bar));
        }
        match &self.snapshot {
            Some(s) => {
                let state = match &s.link {
                    LinkState::Connected { .. } => "connected".to_string(),
                    LinkState::Disconnected { reason, .. } => format!("LOST: {reason}"),
                    LinkState::Closed => "closed".to_string(),
                };
                spans.push(Span::styled(
                    format!("{} #{} {state} │ ", s.link_name, s.address),
                    bar,
                ));
                spans.push(Span::styled(
                    format!("{} │ ", super::axes::poll_text(s)),
                    bar,
                ));
                if let Some(axis) = s.selected_axis().filter(|_| s.axes.len() > 1) {
                    spans.push(Span::styled(format!("axis {} │ ", axis.name), bar));
                }
            }
            None => spans.push(Span::styled("not connected │ ", bar)),
        }
        let context = self.context();
        spans.push(Span::styled(
            key_label(&self.keymap, context, Action::Quit),
            key,
        ));
        spans.push(Span::styled(" quit ", bar));
        spans.push(Span::styled(
            key_label(&self.keymap, context, Action::Help),
            key,
        ));
        spans.push(Span::styled(" help", bar));
        let line = Line::from(spans).style(bar);
        frame.render_widget(Paragraph::new(line).style(Style::default()), area);
    }
}

/// How the screen is shared out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// One pane at a time, as tabs (80×24).
    Tabs,
    /// The top region over the main region.
    Rows,
    /// The top region over main and side columns.
    Columns,
}

impl Mode {
    fn of(body: Rect) -> Mode {
        if body.width < TILE_MIN_WIDTH || body.height < TILE_MIN_HEIGHT {
            Mode::Tabs
        } else if body.width < SIDE_MIN_WIDTH {
            Mode::Rows
        } else {
            Mode::Columns
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

/// A future the loop can spawn.
pub type Pending<T> = Pin<Box<dyn Future<Output = T> + Send>>;

/// The controller as the console drives it: a [`crate::session::Session`],
/// or a fake in tests.
pub trait Controller: Send + Sync {
    fn family(&self) -> &'static Family;
    fn address(&self) -> u8;
    fn axes(&self) -> Vec<AxisInfo>;
    /// The link as the user named it.
    fn link_name(&self) -> String;
    fn status(&self) -> watch::Receiver<Vec<AxisStatus>>;
    fn link_state(&self) -> watch::Receiver<LinkState>;
    fn identity(&self) -> watch::Receiver<Option<String>>;
    fn traffic(&self) -> Option<broadcast::Receiver<TrafficRecord>>;
    fn events(&self) -> Option<broadcast::Receiver<DeviceEvent>>;
    /// Send one line at user priority.
    fn execute(&self, line: String) -> Pending<Result<LineResult, SessionError>>;
    /// Every stop line, ahead of everything queued; what came back for each.
    fn emergency_stop(&self) -> Pending<Vec<Result<LineResult, SessionError>>>;
    /// End a run that ended so under `policy`
    /// ([`crate::session::Session::end_run`]). By default: the stop lines
    /// of [`Controller::emergency_stop`] when the policy says so, without
    /// waiting for a lost link.
    fn end_run(&self, ending: RunEnding, policy: StopOnFailure) -> Pending<RunAftermath> {
        let stop = policy.stops_after(ending).then(|| self.emergency_stop());
        Box::pin(RunAftermath::of(ending, policy, move || async move {
            RunStop {
                ending,
                lines: match stop {
                    Some(stop) => stop.await,
                    None => Vec::new(),
                },
                link: LinkAtStop::Up,
            }
        }))
    }
    fn set_polling(&self, cadence: Option<PollCadence>);
    fn acknowledge_errors(&self, axis: usize, seen: &[AxisFlag]);
    /// Clear the error flags of `axis` in the module where its family
    /// needs a line for that (CMD-4CR `CLRX`), then forget those the user
    /// has seen; what the clear line brought back, if one was sent. By
    /// default only forgets them.
    fn clear_errors(
        &self,
        axis: usize,
        seen: Vec<AxisFlag>,
    ) -> Pending<Result<Option<LineResult>, SessionError>> {
        self.acknowledge_errors(axis, &seen);
        Box::pin(async { Ok(None) })
    }
    /// The same link, sending to another module address.
    fn with_address(&self, address: u8) -> Arc<dyn Controller>;
    /// Run a program transfer, telling `progress` how far it came;
    /// `cancel` stops it between two words (so does the emergency stop).
    /// Controllers without program memory refuse.
    fn transfer(
        &self,
        job: TransferJob,
        cancel: Cancel,
        progress: Box<dyn FnMut(Progress) + Send>,
    ) -> Pending<Result<TransferDone, TransferError>> {
        let _ = (job, cancel, progress);
        let family = self.family().name;
        Box::pin(async move { Err(TransferError::Unsupported { family }) })
    }
    /// Load program source into the simulator behind the link, as its
    /// vendor's tool would write it into the controller: what it holds
    /// now, or why not. Only a simulator in this process can; a real
    /// controller (or a served simulator) refuses.
    fn load_program(&self, source: &str) -> Result<String, String> {
        let _ = source;
        Err(format!(
            "{} is no simulator in this process: there is no program memory to load into",
            self.link_name()
        ))
    }
    /// Drive an input of the simulator behind the link by a setting
    /// (`IO5=1`, [`crate::sim::SimulatedController::drive_input`]): what
    /// now holds, or why not. Only a simulator in this process can; a
    /// real controller (or a served simulator) refuses.
    fn drive_sim_input(&self, setting: &str) -> Result<String, String> {
        let _ = setting;
        Err(no_simulator_to_drive(&self.link_name()))
    }
}

/// Why `:sim-input` does nothing on `link`.
pub fn no_simulator_to_drive(link: &str) -> String {
    format!(
        "{link} is no simulator in this process: there is no input to drive \
         (a real controller's inputs are wired; a served `axterm sim` reads settings on its standard input)"
    )
}

/// Opens a connection for `:connect` (and the connect screen).
pub type Connector =
    Box<dyn Fn(Vec<String>) -> Pending<Result<Arc<dyn Controller>, String>> + Send>;

/// One connected controller as the loop watches it.
struct Connection {
    controller: Arc<dyn Controller>,
    status: watch::Receiver<Vec<AxisStatus>>,
    link: watch::Receiver<LinkState>,
    identity: watch::Receiver<Option<String>>,
    traffic: Option<broadcast::Receiver<TrafficRecord>>,
    /// Traffic is taken in batches: after a batch, none is taken before
    /// this (see [`TRAFFIC_BATCH`]); `None`: the next record wakes the
    /// loop.
    traffic_after: Option<tokio::time::Instant>,
    /// The last pause, and when traffic was last taken.
    traffic_pause: Duration,
    traffic_taken: tokio::time::Instant,
    events: Option<broadcast::Receiver<DeviceEvent>>,
    poll: Option<PollCadence>,
}

impl Connection {
    fn new(controller: Arc<dyn Controller>, poll: Option<PollCadence>) -> Connection {
        controller.set_polling(poll);
        Connection {
            status: controller.status(),
            link: controller.link_state(),
            identity: controller.identity(),
            traffic: controller.traffic(),
            traffic_after: None,
            traffic_pause: TRAFFIC_BATCH,
            traffic_taken: tokio::time::Instant::now(),
            events: controller.events(),
            controller,
            poll,
        }
    }

    fn snapshot(&mut self, axis: usize) -> Snapshot {
        let c = &self.controller;
        let axes = c.axes();
        Snapshot {
            family: c.family(),
            address: c.address(),
            link_name: c.link_name(),
            axis: axis.min(axes.len().saturating_sub(1)),
            axes,
            status: self.status.borrow_and_update().clone(),
            link: self.link.borrow_and_update().clone(),
            identity: self.identity.borrow_and_update().clone(),
            poll: self.poll,
        }
    }
}

/// Something the loop waits for, besides the app's own messages.
enum Wakeup {
    Input(Option<TermEvent>),
    Changed,
    ChannelGone,
    Traffic(Result<TrafficRecord, broadcast::error::RecvError>),
    /// The pause after a batch of traffic is over.
    TrafficDue,
    Device(Result<DeviceEvent, broadcast::error::RecvError>),
    Internal(Option<AppEvent>),
    Connected(Result<Arc<dyn Controller>, String>),
}

/// A log of every frame to a file (`:log FILE`), written by a task of its
/// own from the device's traffic stream.
struct TrafficLog {
    stop: oneshot::Sender<()>,
}

impl TrafficLog {
    /// Start logging `connection`'s traffic to `path`; the task reports
    /// when it ends.
    fn start(
        path: &Path,
        connection: &Connection,
        internal: &mpsc::UnboundedSender<AppEvent>,
    ) -> Result<TrafficLog, String> {
        let Some(mut traffic) = connection.controller.traffic() else {
            return Err("this connection has no traffic to log".into());
        };
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(|e| format!("cannot log to {}: {e}", path.display()))?;
        let out = std::io::LineWriter::new(file);
        let family = connection.controller.family();
        let name = path.display().to_string();
        let (stop, mut stopped) = oneshot::channel();
        let report = internal.clone();
        tokio::spawn(async move {
            let mut log = LogWriter {
                out,
                family,
                start: None,
                frames: 0,
                failure: None,
            };
            loop {
                tokio::select! {
                    _ = &mut stopped => {
                        // Everything sent before the stop is written.
                        while let Ok(record) = traffic.try_recv() {
                            log.write(&record);
                        }
                        break;
                    }
                    record = traffic.recv() => match record {
                        Ok(record) => log.write(&record),
                        Err(broadcast::error::RecvError::Lagged(n)) => {
                            log.failure
                                .get_or_insert(format!("{n} frames were missed (the disk was too slow)"));
                        }
                        Err(broadcast::error::RecvError::Closed) => break,
                    },
                }
            }
            let frames = log.frames;
            let notice = match log.failure {
                None => Notice::info(format!("log {name} closed: {frames} frames")),
                Some(e) => Notice::error(format!("log {name} closed after {frames} frames: {e}")),
            };
            let _ = report.send(AppEvent::Notice(notice));
        });
        Ok(TrafficLog { stop })
    }

    fn stop(self) {
        let _ = self.stop.send(());
    }
}

struct LogWriter {
    out: std::io::LineWriter<std::fs::File>,
    family: &'static Family,
    start: Option<Instant>,
    frames: u64,
    /// The first write that failed; later frames are counted, not written.
    failure: Option<String>,
}

impl LogWriter {
    fn write(&mut self, record: &TrafficRecord) {
        let start = *self.start.get_or_insert(record.at);
        self.frames += 1;
        if self.failure.is_none()
            && let Err(e) = writeln!(self.out, "{}", log_line(self.family, start, record))
        {
            self.failure = Some(e.to_string());
        }
    }
}

/// One logged frame: milliseconds since the log began, direction, what it
/// was, who asked, the bytes as the family shows them.
pub fn log_line(family: &Family, start: Instant, record: &TrafficRecord) -> String {
    let at = record.at.saturating_duration_since(start).as_secs_f64() * 1000.0;
    let direction = match record.direction {
        Direction::Sent => "->",
        Direction::Received => "<-",
    };
    let kind = match record.kind {
        TrafficKind::Request => "request",
        TrafficKind::Answer => "answer",
        TrafficKind::Unsolicited => "unsolicited",
        TrafficKind::Stale => "stale",
        TrafficKind::Garbage => "garbage",
    };
    let by = match record.priority {
        Some(Priority::EmergencyStop) => "stop",
        Some(Priority::User) => "user",
        Some(Priority::Transfer) => "transfer",
        Some(Priority::Poll) => "poll",
        None => "-",
    };
    format!(
        "{at:>12.3} ms {direction} {kind:<11} {by:<8} {}",
        (family.show_bytes)(&record.bytes)
    )
}

/// The loop's side of the console: the connection and everything in
/// flight for the app.
struct Runner {
    connection: Option<Connection>,
    internal: mpsc::UnboundedSender<AppEvent>,
    /// Tasks sending lines, which the emergency stop aborts.
    sending: Vec<JoinHandle<()>>,
    connecting: Option<Pending<Result<Arc<dyn Controller>, String>>>,
    connector: Connector,
    log: Option<TrafficLog>,
    /// The cancel handle of the last transfer started (one at a time:
    /// the session refuses a second). Not aborted by the emergency stop:
    /// the session cancels it, and its end is still reported.
    transfer: Option<Cancel>,
}

/// Drives an [`App`] until it quits: `input` carries terminal events,
/// `extra` anything else (signals, start-up notices), `draw` paints the
/// app (it is called only when something changed). The session's watch
/// channels and event stream, the replies and the timers wake the loop,
/// and traffic at most once per [`TRAFFIC_BATCH`]; nothing else does.
pub async fn run(
    app: &mut App,
    controller: Option<Arc<dyn Controller>>,
    connector: Connector,
    mut input: mpsc::UnboundedReceiver<TermEvent>,
    extra: Option<mpsc::UnboundedReceiver<AppEvent>>,
    draw: &mut (dyn FnMut(&mut App) -> std::io::Result<()> + Send),
) -> std::io::Result<()> {
    let (internal, mut internal_rx) = mpsc::unbounded_channel::<AppEvent>();
    if let Some(mut extra) = extra {
        let tx = internal.clone();
        tokio::spawn(async move {
            while let Some(event) = extra.recv().await {
                if tx.send(event).is_err() {
                    break;
                }
            }
        });
    }
    let mut runner = Runner {
        connection: controller.map(|c| Connection::new(c, Some(PollCadence::default()))),
        internal,
        sending: Vec::new(),
        connecting: None,
        connector,
        log: None,
        transfer: None,
    };
    if let Some(c) = runner.connection.as_mut() {
        let snapshot = c.snapshot(0);
        runner.handle(app, AppEvent::Connected(snapshot));
    }
    loop {
        if app.should_quit() {
            break;
        }
        if app.needs_redraw() {
            draw(app)?;
        }
        let traffic_shown = app.is_on_screen(TRAFFIC_PANE);
        let wakeup = runner
            .wait(&mut input, &mut internal_rx, traffic_shown)
            .await;
        let traffic = matches!(wakeup, Wakeup::Traffic(Ok(_)) | Wakeup::TrafficDue);
        if let Some(event) = runner.event(app, wakeup) {
            runner.handle(app, event);
        }
        if traffic {
            runner.take_traffic(app, traffic_shown);
        }
    }
    if let Some(log) = runner.log.take() {
        log.stop();
    }
    if let Some(c) = runner.connection {
        c.controller.set_polling(None);
    }
    for job in runner.sending {
        job.abort();
    }
    // A download leaves download mode before it ends.
    if let Some(cancel) = runner.transfer {
        cancel.cancel();
    }
    Ok(())
}

impl Runner {
    async fn wait(
        &mut self,
        input: &mut mpsc::UnboundedReceiver<TermEvent>,
        internal: &mut mpsc::UnboundedReceiver<AppEvent>,
        traffic_shown: bool,
    ) -> Wakeup {
        let connecting = &mut self.connecting;
        let connect = async {
            match connecting.as_mut() {
                Some(pending) => pending.await,
                None => std::future::pending().await,
            }
        };
        let Some(c) = self.connection.as_mut() else {
            return tokio::select! {
                event = input.recv() => Wakeup::Input(event),
                event = internal.recv() => Wakeup::Internal(event),
                result = connect => Wakeup::Connected(result),
            };
        };
        // The traffic monitor brought to the front waits no longer than
        // its refresh for the frames that gathered behind its tab.
        let traffic_after = c.traffic_after.map(|at| {
            if traffic_shown {
                at.min(c.traffic_taken + TRAFFIC_BATCH)
            } else {
                at
            }
        });
        let traffic = async {
            match (c.traffic.as_mut(), traffic_after) {
                (Some(_), Some(at)) => {
                    tokio::time::sleep_until(at).await;
                    Wakeup::TrafficDue
                }
                (Some(rx), None) => Wakeup::Traffic(rx.recv().await),
                (None, _) => std::future::pending().await,
            }
        };
        let events = async {
            match c.events.as_mut() {
                Some(rx) => rx.recv().await,
                None => std::future::pending().await,
            }
        };
        let gone = |changed: Result<(), watch::error::RecvError>| match changed {
            Ok(()) => Wakeup::Changed,
            Err(_) => Wakeup::ChannelGone,
        };
        tokio::select! {
            event = input.recv() => Wakeup::Input(event),
            event = internal.recv() => Wakeup::Internal(event),
            result = connect => Wakeup::Connected(result),
            changed = c.status.changed() => gone(changed),
            changed = c.link.changed() => gone(changed),
            changed = c.identity.changed() => gone(changed),
            wakeup = traffic => wakeup,
            event = events => Wakeup::Device(event),
        }
    }

    /// What a wake-up means for the app, if anything.
    fn event(&mut self, app: &App, wakeup: Wakeup) -> Option<AppEvent> {
        Some(match wakeup {
            Wakeup::Input(Some(event)) => AppEvent::Terminal(event),
            Wakeup::Input(None) => AppEvent::Terminate,
            Wakeup::Changed => {
                let axis = app.snapshot().map_or(0, |s| s.axis);
                AppEvent::Snapshot(self.connection.as_mut()?.snapshot(axis))
            }
            Wakeup::ChannelGone => {
                self.disconnect();
                AppEvent::Disconnected
            }
            Wakeup::Traffic(Ok(record)) => AppEvent::Traffic(record),
            Wakeup::TrafficDue => return None,
            Wakeup::Device(Ok(event)) => AppEvent::Device(event),
            Wakeup::Traffic(Err(broadcast::error::RecvError::Closed))
            | Wakeup::Device(Err(broadcast::error::RecvError::Closed)) => {
                if let Some(c) = self.connection.as_mut() {
                    c.traffic = None;
                    c.events = None;
                }
                return None;
            }
            // A pane that could not keep up misses some traffic; the next
            // record comes.
            Wakeup::Traffic(Err(_)) | Wakeup::Device(Err(_)) => return None,
            Wakeup::Internal(event) => event?,
            Wakeup::Connected(result) => {
                self.connecting = None;
                match result {
                    Ok(controller) => {
                        let poll = self
                            .connection
                            .as_ref()
                            .map_or(Some(PollCadence::default()), |c| c.poll);
                        self.disconnect();
                        let mut c = Connection::new(controller, poll);
                        let snapshot = c.snapshot(0);
                        self.connection = Some(c);
                        AppEvent::Connected(snapshot)
                    }
                    Err(message) => AppEvent::Notice(Notice::error(message)),
                }
            }
        })
    }

    /// Hand the panes every traffic record waiting, and pause before
    /// taking more if there were any ([`traffic_pause`]; otherwise the
    /// next record wakes the loop at once).
    fn take_traffic(&mut self, app: &mut App, traffic_shown: bool) {
        let Some(c) = self.connection.as_mut() else {
            return;
        };
        let woken_by_a_record = c.traffic_after.is_none();
        let mut records = Vec::new();
        let mut closed = false;
        if let Some(rx) = c.traffic.as_mut() {
            loop {
                match rx.try_recv() {
                    Ok(record) => records.push(record),
                    // Missed by a pane that could not keep up; read on.
                    Err(broadcast::error::TryRecvError::Lagged(_)) => {}
                    Err(broadcast::error::TryRecvError::Empty) => break,
                    Err(broadcast::error::TryRecvError::Closed) => {
                        closed = true;
                        break;
                    }
                }
            }
        }
        let now = tokio::time::Instant::now();
        c.traffic_after = if woken_by_a_record || !records.is_empty() {
            let longest = if traffic_shown {
                TRAFFIC_BATCH
            } else {
                TRAFFIC_BATCH_HIDDEN
            };
            c.traffic_pause = traffic_pause(
                woken_by_a_record,
                c.traffic_pause,
                longest,
                records.len(),
                now.saturating_duration_since(c.traffic_taken),
            );
            Some(now + c.traffic_pause)
        } else {
            None
        };
        c.traffic_taken = now;
        if closed {
            c.traffic = None;
            c.traffic_after = None;
        }
        for record in records {
            self.handle(app, AppEvent::Traffic(record));
        }
    }

    /// Let go of the connection: no polling, no log.
    fn disconnect(&mut self) {
        if let Some(log) = self.log.take() {
            log.stop();
        }
        if let Some(old) = self.connection.take() {
            old.controller.set_polling(None);
        }
    }

    /// Hand an event to the app and carry out what it asks for; events
    /// that come of it are handled in turn.
    fn handle(&mut self, app: &mut App, event: AppEvent) {
        self.sending.retain(|job| !job.is_finished());
        let mut queue = vec![event];
        while let Some(event) = queue.pop() {
            for effect in app.handle(event) {
                self.carry_out(effect, app, &mut queue);
            }
        }
    }

    fn carry_out(&mut self, effect: Effect, app: &App, queue: &mut Vec<AppEvent>) {
        let not_connected = || {
            AppEvent::Notice(Notice::error(
                "not connected: give :connect --sim tmcm1110 (or --port PATH, --tcp HOST:PORT)",
            ))
        };
        match effect {
            Effect::Send { pane, tag, lines } => {
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                let controller = Arc::clone(&c.controller);
                let tx = self.internal.clone();
                self.sending.push(tokio::spawn(async move {
                    for line in lines {
                        let result = controller.execute(line.clone()).await;
                        let failed = result.is_err();
                        let reply = AppEvent::Reply {
                            pane,
                            tag,
                            line,
                            result,
                        };
                        if tx.send(reply).is_err() || failed {
                            break;
                        }
                    }
                }));
            }
            Effect::EmergencyStop => {
                // Lines still waiting to be sent must not go after the stop.
                for job in self.sending.drain(..) {
                    job.abort();
                }
                let Some(c) = self.connection.as_ref() else {
                    queue.push(AppEvent::Stopped(Vec::new()));
                    return;
                };
                let stop = c.controller.emergency_stop();
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    let results = stop.await;
                    let _ = tx.send(AppEvent::Stopped(results));
                });
            }
            Effect::EndRun {
                pane,
                ending,
                policy,
            } => {
                // Unlike the stop key, lines already queued are kept: they
                // are other panes' and answered after the stop, which goes
                // first at emergency-stop priority.
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                let end = c.controller.end_run(ending, policy);
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    let aftermath = end.await;
                    let _ = tx.send(AppEvent::RunEnded { pane, aftermath });
                });
            }
            Effect::Poll(cadence) => {
                if let Some(c) = self.connection.as_mut() {
                    c.poll = cadence;
                    c.controller.set_polling(cadence);
                    let axis = app.snapshot().map_or(0, |s| s.axis);
                    queue.push(AppEvent::Snapshot(c.snapshot(axis)));
                } else {
                    queue.push(not_connected());
                }
            }
            Effect::SetAddress(address) => {
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                let poll = c.poll;
                let controller = c.controller.with_address(address);
                self.disconnect();
                let mut fresh = Connection::new(controller, poll);
                let axis = app.snapshot().map_or(0, |s| s.axis);
                queue.push(AppEvent::Snapshot(fresh.snapshot(axis)));
                self.connection = Some(fresh);
            }
            Effect::ClearErrors { axis, seen } => {
                let Some(c) = self.connection.as_ref() else {
                    return;
                };
                let name = app
                    .snapshot()
                    .and_then(|s| s.axes.get(axis))
                    .map_or_else(|| format!("axis {axis}"), |a| a.name.to_string());
                let clearing = c.controller.clear_errors(axis, seen);
                let tx = self.internal.clone();
                // Among the lines the emergency stop drops if still waiting.
                self.sending.push(tokio::spawn(async move {
                    let notice = match clearing.await {
                        Ok(None) => return,
                        Ok(Some(result)) => Notice::info(format!(
                            "{}: {}, the error flags of {name} are cleared in the controller",
                            result.line, result.value
                        )),
                        Err(e) => Notice::error(format!(
                            "the error flags of {name} stay: clearing them failed: {e}"
                        )),
                    };
                    let _ = tx.send(AppEvent::Notice(notice));
                }));
            }
            Effect::Log(path) => {
                if let Some(log) = self.log.take() {
                    log.stop();
                }
                let Some(path) = path else {
                    return;
                };
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                match TrafficLog::start(&path, c, &self.internal) {
                    Ok(log) => {
                        self.log = Some(log);
                        queue.push(AppEvent::Notice(Notice::info(format!(
                            "logging every frame to {}",
                            path.display()
                        ))));
                    }
                    Err(message) => queue.push(AppEvent::Notice(Notice::error(message))),
                }
            }
            Effect::Connect(args) => {
                self.connecting = Some((self.connector)(args));
            }
            Effect::Wake { pane, tag, after } => {
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    tokio::time::sleep(after).await;
                    let _ = tx.send(AppEvent::Wake { pane, tag });
                });
            }
            Effect::Transfer { pane, tag, job } => {
                let Some(c) = self.connection.as_ref() else {
                    queue.push(AppEvent::Transferred {
                        pane,
                        tag,
                        result: Err(not_connected_transfer()),
                    });
                    return;
                };
                let cancel = Cancel::new();
                self.transfer = Some(cancel.clone());
                let tx = self.internal.clone();
                let mut last: Option<Progress> = None;
                let progress = Box::new(move |progress: Progress| {
                    if worth_showing(last.as_ref(), &progress) {
                        last = Some(progress);
                        let _ = tx.send(AppEvent::TransferProgress {
                            pane,
                            tag,
                            progress,
                        });
                    }
                });
                let running = c.controller.transfer(job, cancel, progress);
                let tx = self.internal.clone();
                tokio::spawn(async move {
                    let result = running.await;
                    let _ = tx.send(AppEvent::Transferred { pane, tag, result });
                });
            }
            Effect::CancelTransfer => {
                if let Some(cancel) = self.transfer.as_ref() {
                    cancel.cancel();
                }
            }
            Effect::LoadProgram { pane, tag, source } => {
                let result = match self.connection.as_ref() {
                    Some(c) => c.controller.load_program(&source),
                    None => Err("not connected: nothing to load into".to_string()),
                };
                queue.push(AppEvent::ProgramLoaded { pane, tag, result });
            }
            Effect::DriveSimInput(setting) => {
                let Some(c) = self.connection.as_ref() else {
                    queue.push(not_connected());
                    return;
                };
                let notice = match c.controller.drive_sim_input(&setting) {
                    Ok(said) => Notice::info(format!("simulator input: {said}")),
                    Err(message) => Notice::error(format!(":sim-input {setting}: {message}")),
                };
                queue.push(AppEvent::Notice(notice));
            }
            Effect::Quit => {}
        }
    }
}

/// A transfer asked for with no controller connected.
fn not_connected_transfer() -> TransferError {
    TransferError::Step {
        step: "start the transfer",
        error: Box::new(SessionError::Refused {
            line: String::new(),
            message: "not connected: give :connect --sim tmcm1110 (or --port PATH, --tcp \
                      HOST:PORT)"
                .into(),
        }),
        hint: String::new(),
    }
}

/// Whether a transfer's progress is worth a redraw: the start of each
/// phase, every whole percent, the last word (a download of 2048 words
/// on a fast link would otherwise redraw 4096 times). Without a total
/// (an upload until the first blank word), every 16th word.
pub fn worth_showing(last: Option<&Progress>, next: &Progress) -> bool {
    let Some(last) = last else {
        return true;
    };
    if last.phase != next.phase || next.done == 0 {
        return true;
    }
    match next.total {
        Some(total) if total > 0 => {
            next.done >= total || last.done * 100 / total != next.done * 100 / total
        }
        _ => next.done.is_multiple_of(16),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ratatui::Terminal;
    use ratatui::backend::TestBackend;
    use ratatui::crossterm::event::{KeyCode, KeyEventState, KeyModifiers};

    /// A pane that shows its name and keeps every key it is given, unless
    /// it is told to ignore keys.
    struct Probe {
        name: &'static str,
        region: Region,
        takes_keys: bool,
        keys: Vec<KeyCode>,
        /// `View::shown` at the last event.
        shown: Option<bool>,
    }

    impl Probe {
        fn boxed(name: &'static str, region: Region, takes_keys: bool) -> Box<dyn Pane> {
            Box::new(Probe {
                name,
                region,
                takes_keys,
                keys: Vec::new(),
                shown: None,
            })
        }
    }

    impl Pane for Probe {
        fn name(&self) -> &'static str {
            self.name
        }
        fn context(&self) -> Context {
            match self.name {
                "command" => Context::Command,
                "axes" => Context::Axis,
                _ => Context::Traffic,
            }
        }
        fn title(&self, _view: &View) -> String {
            self.name.to_uppercase()
        }
        fn region(&self) -> Region {
            self.region
        }
        fn height_hint(&self, _view: &View, _width: u16, _room: u16) -> Option<u16> {
            (self.region == Region::Top).then_some(3)
        }
        fn render(&mut self, frame: &mut Frame, area: Rect, _view: &View) {
            let text = format!(
                "inside {} keys {} shown at the last event {:?}",
                self.name,
                self.keys.len(),
                self.shown
            );
            frame.render_widget(Paragraph::new(text), area);
        }
        fn handle_input(&mut self, input: &Input, _view: &View) -> Outcome {
            match input {
                Input::Key(key) if self.takes_keys => {
                    self.keys.push(key.code);
                    Outcome::redraw()
                }
                _ => Outcome::Ignored,
            }
        }
        fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
            self.shown = Some(view.shown);
            match event {
                PaneEvent::Snapshot => Outcome::redraw(),
                _ => Outcome::Ignored,
            }
        }
    }

    fn key(code: KeyCode, modifiers: KeyModifiers) -> AppEvent {
        AppEvent::Terminal(TermEvent::Key(KeyEvent {
            code,
            modifiers,
            kind: KeyEventKind::Press,
            state: KeyEventState::NONE,
        }))
    }

    fn app(panes: Vec<Box<dyn Pane>>) -> App {
        let theme = Theme::builtin("dark").expect("built-in theme");
        let keymap = Keymap::builtin("default").expect("built-in keymap");
        App::new(panes, theme, keymap)
    }

    fn three() -> App {
        app(vec![
            Probe::boxed("command", Region::Main, true),
            Probe::boxed("axes", Region::Top, false),
            Probe::boxed("traffic", Region::Side, false),
        ])
    }

    fn screen(app: &mut App, width: u16, height: u16) -> Vec<String> {
        let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("test backend");
        terminal.draw(|f| app.render(f)).expect("draw");
        let buffer = terminal.backend().buffer();
        (0..height)
            .map(|y| {
                (0..width)
                    .map(|x| buffer[(x, y)].symbol().to_string())
                    .collect::<String>()
            })
            .collect()
    }

    fn snapshot() -> Snapshot {
        let family = crate::protocol::find_family("tmcl").expect("tmcl");
        Snapshot {
            family,
            address: 1,
            link_name: "sim tmcm1110".into(),
            axes: family.console.axes().to_vec(),
            status: vec![AxisStatus::default()],
            link: LinkState::Connected { link: "sim".into() },
            identity: None,
            poll: Some(PollCadence::default()),
            axis: 0,
        }
    }

    #[test]
    fn at_80x24_the_top_pane_stays_and_the_others_are_tabs() {
        let mut app = three();
        let lines = screen(&mut app, 80, 24);
        assert!(lines[0].contains(" AXES "), "{}", lines[0]);
        assert!(lines[1].contains("inside axes"));
        assert!(lines[5].contains("1 COMMAND │ 3 TRAFFIC"), "{}", lines[5]);
        assert!(lines[6].contains("inside command"));
        app.handle(key(KeyCode::Char('3'), KeyModifiers::ALT));
        let lines = screen(&mut app, 80, 24);
        assert!(lines[6].contains("inside traffic"), "{}", lines[6]);
    }

    #[test]
    fn on_a_tiny_screen_every_pane_is_a_tab() {
        let mut app = three();
        let lines = screen(&mut app, 60, 14);
        assert!(
            lines[0].contains("1 COMMAND │ 2 AXES │ 3 TRAFFIC"),
            "{}",
            lines[0]
        );
        assert!(lines[1].contains("inside command"));
        app.handle(key(KeyCode::Char('2'), KeyModifiers::ALT));
        let lines = screen(&mut app, 60, 14);
        assert!(lines[1].contains("inside axes"), "{}", lines[1]);
    }

    #[test]
    fn a_large_screen_tiles_top_main_and_side() {
        let mut app = three();
        let lines = screen(&mut app, 200, 50);
        // The axes on top (3 rows inside a border), then two columns.
        assert!(lines[0].contains(" AXES "), "{}", lines[0]);
        assert!(lines[1].contains("inside axes"));
        assert!(lines[5].contains(" COMMAND ") && lines[5].contains(" TRAFFIC "));
        assert!(lines[6].contains("inside command") && lines[6].contains("inside traffic"));
        // Between the two sizes the side pane is a tab beside the command.
        let lines = screen(&mut app, 120, 40);
        assert!(lines[5].contains("1 COMMAND │ 3 TRAFFIC"), "{}", lines[5]);
    }

    #[test]
    fn the_status_bar_always_shows_the_stop_key() {
        for (w, h) in [(80, 24), (200, 50)] {
            let mut app = three();
            let lines = screen(&mut app, w, h);
            assert!(lines[usize::from(h) - 1].starts_with(" F12 STOP "));
        }
        let mut app = three();
        app.handle(AppEvent::Snapshot(snapshot()));
        let status = screen(&mut app, 100, 30).pop().unwrap_or_default();
        assert!(status.contains("sim tmcm1110 #1 connected"), "{status}");
        assert!(status.contains("poll 20 Hz"), "{status}");
    }

    #[test]
    fn the_stop_key_goes_to_the_app_whichever_pane_has_the_focus() {
        let mut app = three();
        let f12 = || key(KeyCode::F(12), KeyModifiers::NONE);
        assert_eq!(app.handle(f12()), [Effect::EmergencyStop]);
        app.handle(key(KeyCode::Char('3'), KeyModifiers::ALT));
        assert_eq!(app.focused(), Some("traffic"));
        assert_eq!(app.handle(f12()), [Effect::EmergencyStop]);
        // The command pane takes every other key, but never this one.
        app.focus("command");
        app.handle(key(KeyCode::Char('x'), KeyModifiers::NONE));
        assert_eq!(app.handle(f12()), [Effect::EmergencyStop]);
        let lines = screen(&mut app, 80, 24);
        assert!(lines[6].contains("keys 1"), "{}", lines[6]);
        assert!(lines[23].contains("STOP sending"), "{}", lines[23]);
    }

    #[test]
    fn tab_moves_the_focus_only_when_the_pane_does_not_use_it() {
        let mut app = three();
        app.handle(key(KeyCode::Tab, KeyModifiers::NONE));
        assert_eq!(app.focused(), Some("command"));
        app.focus("axes");
        app.handle(key(KeyCode::Tab, KeyModifiers::NONE));
        assert_eq!(app.focused(), Some("traffic"));
        app.handle(key(KeyCode::Tab, KeyModifiers::NONE));
        assert_eq!(app.focused(), Some("command"));
        app.focus("axes");
        app.handle(key(KeyCode::BackTab, KeyModifiers::SHIFT));
        assert_eq!(app.focused(), Some("command"));
    }

    #[test]
    fn the_screen_is_redrawn_only_when_something_changed() {
        let mut app = three();
        screen(&mut app, 80, 24);
        assert!(!app.needs_redraw());
        app.handle(AppEvent::Snapshot(snapshot()));
        assert!(app.needs_redraw());
        screen(&mut app, 80, 24);
        // The same values again (a poll that read what was there) draw nothing.
        app.handle(AppEvent::Snapshot(snapshot()));
        assert!(!app.needs_redraw());
        let mut moved = snapshot();
        moved.status[0].position = Some(5);
        app.handle(AppEvent::Snapshot(moved));
        assert!(app.needs_redraw());
        screen(&mut app, 80, 24);
        // A key no pane and no binding uses changes nothing.
        app.focus("axes");
        screen(&mut app, 80, 24);
        app.handle(key(KeyCode::Char('z'), KeyModifiers::NONE));
        assert!(!app.needs_redraw());
    }

    #[test]
    fn a_pane_behind_a_tab_does_not_redraw_the_screen() {
        let mut app = three();
        app.handle(AppEvent::Snapshot(snapshot()));
        // 120x40: the axes on top, the command in front of the traffic tab.
        screen(&mut app, 120, 40);
        assert!(!app.needs_redraw());
        // Every probe redraws on a snapshot; only shown ones count.
        let mut moved = snapshot();
        moved.status[0].position = Some(1);
        app.handle(AppEvent::Snapshot(moved));
        assert!(app.needs_redraw());
        screen(&mut app, 120, 40);
        let traffic = 2;
        let mut effects = Vec::new();
        app.deliver(traffic, &PaneEvent::Snapshot, &mut effects);
        assert!(!app.needs_redraw(), "the traffic tab is hidden");
        app.deliver(0, &PaneEvent::Snapshot, &mut effects);
        assert!(app.needs_redraw(), "the command pane is shown");
        screen(&mut app, 120, 40);
        app.deliver(traffic, &PaneEvent::Snapshot, &mut effects);
        // Panes are told, and may skip wake-ups that only refresh.
        app.handle(AppEvent::Terminal(TermEvent::Key(KeyEvent::new(
            KeyCode::Char('3'),
            KeyModifiers::ALT,
        ))));
        let lines = screen(&mut app, 120, 40);
        assert!(
            lines[6].contains("inside traffic keys 0 shown at the last event Some(false)"),
            "{}",
            lines[6]
        );
    }

    #[test]
    fn a_click_focuses_the_pane_under_it() {
        use ratatui::crossterm::event::{MouseButton, MouseEvent, MouseEventKind};
        let click = |row| {
            AppEvent::Terminal(TermEvent::Mouse(MouseEvent {
                kind: MouseEventKind::Down(MouseButton::Left),
                column: 10,
                row,
                modifiers: KeyModifiers::NONE,
            }))
        };
        let mut app = three();
        screen(&mut app, 120, 40);
        app.handle(click(2));
        assert_eq!(app.focused(), Some("axes"));
        app.handle(click(20));
        assert_eq!(app.focused(), Some("command"));
    }

    #[test]
    fn transfer_progress_is_shown_at_each_phase_each_percent_and_the_end() {
        use crate::session::program::Phase;
        let at = |phase, done, total| Progress { phase, done, total };
        let mut shown = Vec::new();
        let mut last: Option<Progress> = None;
        let steps = (0..=300)
            .map(|n| at(Phase::Storing, n, Some(300)))
            .chain((0..=300).map(|n| at(Phase::Verifying, n, Some(300))));
        for p in steps {
            if worth_showing(last.as_ref(), &p) {
                last = Some(p);
                shown.push(p);
            }
        }
        // 0 and 100 percent of each phase and every percent between.
        assert_eq!(shown.len(), 2 * 101, "{shown:?}");
        assert_eq!(shown.first(), Some(&at(Phase::Storing, 0, Some(300))));
        assert!(shown.contains(&at(Phase::Storing, 300, Some(300))));
        assert!(shown.contains(&at(Phase::Verifying, 0, Some(300))));
        assert_eq!(shown.last(), Some(&at(Phase::Verifying, 300, Some(300))));
        // A short program: every word.
        let small = at(Phase::Storing, 1, Some(3));
        assert!(worth_showing(Some(&at(Phase::Storing, 0, Some(3))), &small));
        // Reading until a blank word: every 16th.
        let reading = |n| at(Phase::Reading, n, None);
        assert!(!worth_showing(Some(&reading(0)), &reading(15)));
        assert!(worth_showing(Some(&reading(0)), &reading(16)));
    }

    /// The console's loop runs as a task of its own (see `live`): the app,
    /// its panes and the drawing are `Send`.
    #[tokio::test(start_paused = true)]
    async fn the_loop_runs_as_a_spawned_task() {
        let mut app = three();
        let (_keys, input) = mpsc::unbounded_channel();
        let (extra, extra_rx) = mpsc::unbounded_channel();
        let connector: Connector = Box::new(|_| Box::pin(async { Err("none".to_string()) }));
        let mut terminal = Terminal::new(TestBackend::new(80, 24)).expect("backend");
        let (drawn, mut frames) = mpsc::unbounded_channel();
        let looping = tokio::spawn(async move {
            let mut draw = |app: &mut App| -> std::io::Result<()> {
                let Ok(_) = terminal.draw(|f| app.render(f));
                let _ = drawn.send(());
                Ok(())
            };
            run(&mut app, None, connector, input, Some(extra_rx), &mut draw).await
        });
        assert_eq!(frames.recv().await, Some(()), "the first frame");
        let _ = extra.send(AppEvent::Terminate);
        assert!(matches!(looping.await, Ok(Ok(()))));
    }

    #[test]
    fn traffic_pauses_grow_while_frames_come_and_shrink_when_they_pour_in() {
        let ms = Duration::from_millis;
        let longest = TRAFFIC_BATCH_HIDDEN;
        // After a quiet spell: the monitor's refresh.
        assert_eq!(
            traffic_pause(true, ms(800), longest, 1, ms(5000)),
            TRAFFIC_BATCH
        );
        // Then doubling up to the longest.
        assert_eq!(traffic_pause(false, ms(100), longest, 4, ms(100)), ms(200));
        assert_eq!(traffic_pause(false, ms(800), longest, 32, ms(800)), longest);
        assert_eq!(
            traffic_pause(false, ms(100), TRAFFIC_BATCH, 4, ms(100)),
            TRAFFIC_BATCH
        );
        // A transfer pouring frames in: short enough that the stream
        // cannot fill.
        let pause = traffic_pause(false, ms(100), longest, TRAFFIC_HEADROOM * 2, ms(100));
        assert_eq!(pause, ms(50));
        // Nonsense never panics.
        assert_eq!(
            traffic_pause(
                false,
                Duration::MAX,
                Duration::MAX,
                usize::MAX,
                Duration::MAX
            ),
            ms(1)
        );
        assert_eq!(traffic_pause(false, ms(100), longest, 0, ms(0)), ms(200));
        assert_eq!(traffic_pause(false, ms(100), longest, 9, ms(0)), ms(1));
    }

    #[test]
    fn poll_rates_become_cadences() {
        assert_eq!(cadence_for(0.0), None);
        assert_eq!(cadence_for(f64::NAN), None);
        let c = cadence_for(20.0).expect("20 Hz");
        assert_eq!(c.fast, Duration::from_millis(50));
        assert_eq!(c.slow, Duration::from_millis(200));
        assert_eq!(rate_of(c.fast), "20");
        assert_eq!(rate_of(Duration::from_millis(400)), "2.5");
    }
}
