//! What a pane is to the console: a title, a home region on the screen, a
//! way to draw itself from a [`View`] (theme, keymap, the session's
//! snapshots) and a way to react to input and to news.
//!
//! Panes never talk to the session directly: they return [`Request`]s in
//! an [`Outcome`], the app carries them out and answers with
//! [`PaneEvent`]s (a reply to a line a pane sent comes back to that pane
//! only, under the tag it chose). So a pane is plain state and can be
//! tested without a terminal or a device.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use ratatui::Frame;
use ratatui::crossterm::event::{KeyEvent, MouseEvent};
use ratatui::layout::Rect;

use super::keymap::{Action, Context, Keymap};
use super::theme::Theme;
use crate::device::{Busy, DeviceEvent, LinkState, TrafficRecord};
use crate::protocol::Family;
use crate::protocol::program::{Progress, TransferFailure, TransferJob, TransferReport};
use crate::protocol::settings::SettingsCache;
use crate::session::run_end::{RunAftermath, RunEnding, StopOnFailure};
use crate::session::{AxisInfo, AxisStatus, LineResult, PollCadence, SessionError};

/// Where a pane lives when the screen is large enough to show several at
/// once. When it is not (80×24), every pane becomes a tab of one region.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Region {
    /// Full width across the top, as high as the pane asks
    /// ([`Pane::height_hint`]): the axis status.
    Top,
    /// Below the top region, on the left (the whole width when the screen
    /// is not wide enough for two columns): the command console.
    Main,
    /// Below the top region, on the right when the screen is wide;
    /// otherwise these panes are tabs of [`Region::Main`].
    Side,
}

/// What the console knows of the connected controller, copied from the
/// session's watch channels whenever one of them changes.
#[derive(Clone)]
pub struct Snapshot {
    pub family: &'static Family,
    /// The module address lines are sent to.
    pub address: u8,
    /// The link as the user named it ("sim tmcm1110", "/dev/ttyUSB0").
    pub link_name: String,
    /// The module's axes, in the order of `status`.
    pub axes: Vec<AxisInfo>,
    pub status: Vec<AxisStatus>,
    pub link: LinkState,
    /// The module's identity (firmware string), once read.
    pub identity: Option<String>,
    /// How often status is polled; `None` when polling is off.
    pub poll: Option<PollCadence>,
    /// The settings written this session, for a module that cannot be
    /// asked for them (empty when it keeps none).
    pub settings: Arc<SettingsCache>,
    /// The axes' mechanics in force (`--mechanics`, `:mechanics`): values
    /// typed and shown in an axis's own units.
    pub mechanics: Arc<crate::protocol::units::MechanicsTable>,
    /// The axis the user works with (`:axis N`): index into `axes`.
    pub axis: usize,
}

impl std::fmt::Debug for Snapshot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Snapshot")
            .field("family", &self.family.name)
            .field("address", &self.address)
            .field("link_name", &self.link_name)
            .field("axes", &self.axes)
            .field("status", &self.status)
            .field("link", &self.link)
            .field("identity", &self.identity)
            .field("poll", &self.poll)
            .field("settings", &self.settings)
            .field("mechanics", &self.mechanics)
            .field("axis", &self.axis)
            .finish()
    }
}

impl Snapshot {
    /// The selected axis's number and name, if the module has axes.
    pub fn selected_axis(&self) -> Option<&AxisInfo> {
        self.axes.get(self.axis)
    }
}

/// One module of the console's list: the link it is on (numbered from 0
/// in the order the links were opened) and what it shows.
#[derive(Debug, Clone)]
pub struct ModuleEntry {
    pub link: usize,
    pub snapshot: Snapshot,
}

/// Everything a pane may read while drawing or reacting.
#[derive(Clone, Copy)]
pub struct View<'a> {
    pub theme: &'a Theme,
    pub keymap: &'a Keymap,
    /// `None` when no controller is connected (the connect screen shows).
    /// With several modules: the selected one, which lines go to.
    pub session: Option<&'a Snapshot>,
    /// Every module of every link, grouped by link; empty or one entry
    /// for a console on one module.
    pub modules: &'a [ModuleEntry],
    /// The selected module: index into `modules`.
    pub module: usize,
    /// Whether this pane has the keyboard.
    pub focused: bool,
    /// Whether this pane was on the screen at the last draw (not behind a
    /// tab). A hidden pane's redraws are not drawn, so it may skip the
    /// wake-ups that only serve to refresh its picture.
    pub shown: bool,
}

/// Input for the pane that has the focus.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Input {
    Key(KeyEvent),
    Mouse(MouseEvent),
    Paste(String),
}

/// News for every pane (or, for [`PaneEvent::Reply`] and
/// [`PaneEvent::Wake`], for the pane that asked).
#[derive(Debug, Clone)]
pub enum PaneEvent {
    /// The snapshot changed (status, link, identity, axis, poll rate).
    Snapshot,
    /// A frame went out or came in.
    Traffic(TrafficRecord),
    /// Module `.0` of [`View::modules`], not the selected one, changed
    /// (its status polled anew, its link's state…).
    ModuleChanged(usize),
    /// A frame on link `link` (numbered as [`ModuleEntry::link`]), of a
    /// console on several links; [`PaneEvent::Traffic`] is link 0's.
    LinkTraffic { link: usize, record: TrafficRecord },
    /// Show only this link's traffic (`None`: every link's).
    TrafficLink(Option<usize>),
    /// Unsolicited news from the device task.
    Device(DeviceEvent),
    /// The answer to one line of a [`Request::Send`].
    Reply {
        tag: u64,
        /// The line as sent (before the session made it canonical).
        line: String,
        result: Result<LineResult, SessionError>,
    },
    /// A [`Request::WakeAfter`] came due.
    Wake { tag: u64 },
    /// A connection was just opened (after [`PaneEvent::Snapshot`] with
    /// its first snapshot). `args` are its connection options when a pane
    /// asked for it ([`Request::Connect`]); `None` for the one given on
    /// the command line.
    Connected { args: Option<Vec<String>> },
    /// This pane was just given the keyboard (for the pane concerned
    /// only): a pane that reads from the module when first looked at
    /// starts here.
    Focused,
    /// This pane had the keyboard and lost it (another pane took it, or
    /// the terminal lost the focus): a pane that moves an axis while a key
    /// is held stops it here.
    Unfocused,
    /// The emergency stop key was pressed: lines still waiting to be sent
    /// were dropped (their replies will never come) and the stop is on its
    /// way. Forget anything queued, stop running scripts.
    Stopping,
    /// The emergency stop was sent: each stop line and what came back.
    EmergencyStop(Vec<Result<LineResult, SessionError>>),
    /// The controller is busy with a line that runs until its answer (a
    /// wait, a repeat, a macro: Escape aborts it, Space pauses it), or no
    /// longer (`None`). Polling waits meanwhile.
    Busy(Option<Busy>),
    /// What the session did about the axes after this pane's
    /// [`Request::EndRun`].
    RunEnded(RunAftermath),
    /// A message from the console itself (the answer to `:poll 10`, a
    /// theme that failed to load…), shown by the command pane.
    Notice(Notice),
    /// How far the [`Request::Transfer`] under `tag` has come (for the
    /// pane that asked; not after every word, but at every phase, every
    /// percent and the last word).
    TransferProgress { tag: u64, progress: Progress },
    /// The [`Request::Transfer`] under `tag` ended.
    Transferred {
        tag: u64,
        result: Result<TransferReport, TransferFailure>,
    },
    /// The connect screen's choice now connects with this protocol family
    /// ([`Request::ChooseFamily`]).
    FamilyChosen(&'static str),
    /// `:plot ARGS` ([`Request::Plot`]).
    Plot(String),
    /// The [`Request::LoadProgram`] under `tag` was done: what the
    /// simulator holds now, or why it holds nothing new.
    ProgramLoaded {
        tag: u64,
        result: Result<String, String>,
    },
    /// The [`Request::CheckWiring`] under `tag` ended: what it found, or
    /// why it could not run to its end.
    WiringChecked {
        tag: u64,
        result: Result<super::app::WiringFindings, String>,
    },
    /// The [`Request::Tune`] under `tag` ended: what it gave, or why not.
    Tuned {
        tag: u64,
        result: Result<super::app::TuneOutcome, String>,
    },
    /// A tool of a pane did something the commissioning sheet shows
    /// ([`Request::SheetFact`]): for the command pane's session recording.
    SheetFact(SheetFact),
    /// The [`Request::ReadSettings`] under `tag` ended: the module's
    /// settings against the factory defaults, or why they were not read.
    SettingsRead {
        tag: u64,
        result: Result<crate::report::Settings, String>,
    },
}

/// What a pane's tool did, as the commissioning sheet of a session
/// recording shows it (`:record`, `:report`): the same facts `axterm run`
/// puts on the sheet for its `:wiring`, `:tune-step` and
/// `:tune-stallguard` lines. Generic: each tool says what it did in words.
#[derive(Debug, Clone, PartialEq)]
pub enum SheetFact {
    /// The wiring check ran to its end: its findings, the faulty ones
    /// among them (none when wired right).
    Wiring {
        /// What was done, as the sheet's line shows it (`:wiring …`).
        line: String,
        findings: Vec<String>,
        faults: Vec<String>,
    },
    /// A tuning tool ran to its end: its figure lines and plots; `ok`
    /// false when it tripped (`said` says so).
    Tuning {
        line: String,
        said: String,
        ok: bool,
        figures: Vec<String>,
        plots: Vec<crate::report::Plot>,
    },
    /// A tool did not run to its end: it failed (`failed`, a failed check
    /// on the sheet) or was stopped by the user (shown, not counted).
    Unfinished {
        line: String,
        why: String,
        failed: bool,
    },
}

/// A console message and how it should look.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Notice {
    pub level: NoticeLevel,
    pub text: String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoticeLevel {
    Info,
    Warning,
    Error,
}

impl Notice {
    pub fn info(text: impl Into<String>) -> Notice {
        Notice {
            level: NoticeLevel::Info,
            text: text.into(),
        }
    }

    pub fn warning(text: impl Into<String>) -> Notice {
        Notice {
            level: NoticeLevel::Warning,
            text: text.into(),
        }
    }

    pub fn error(text: impl Into<String>) -> Notice {
        Notice {
            level: NoticeLevel::Error,
            text: text.into(),
        }
    }
}

/// Something a pane asks the app to do.
#[derive(Debug, Clone, PartialEq)]
pub enum Request {
    /// Send these console lines in order at user priority; each answer
    /// comes back to this pane as [`PaneEvent::Reply`] with `tag`. A line
    /// is sent only after the previous one was answered.
    Send { lines: Vec<String>, tag: u64 },
    /// Send these lines that stop motion (a jog's stop) as
    /// [`Request::Send`] does, but each ahead of everything queued, as the
    /// emergency stop goes: a status read on the wire is cut short for
    /// them where the family can.
    SendStop { lines: Vec<String>, tag: u64 },
    /// Read this line at user priority, as [`Request::Send`] does, but
    /// where the family's answers carry no check, until two answers agree
    /// ([`crate::session::Session::read_agreed`]): what a value shown as
    /// read is. The answer comes back as [`PaneEvent::Reply`] with `tag`.
    ReadAgreed { line: String, tag: u64 },
    /// Stop every axis and any standalone program, ahead of everything.
    EmergencyStop,
    /// Send lines to the module at this index of [`View::modules`] from
    /// now on (`:module N`, the picker key).
    SelectModule(usize),
    /// The traffic monitor shows only this link's frames (`None`: every
    /// link's; `:traffic LINK`).
    TrafficLink(Option<usize>),
    /// Open one more link beside those open, with these options (the
    /// options of `:connect`): its modules join the list.
    AddLink(Vec<String>),
    /// Abort the line the controller is busy with ([`PaneEvent::Busy`]).
    AbortLine,
    /// Pause the line the controller is busy with, or resume it.
    PauseLine,
    /// A run of this pane (`:run`, a host run) ended so: the session
    /// decides what becomes of the axes under `policy`
    /// ([`crate::session::Session::end_run`]); what it did comes back to
    /// this pane as [`PaneEvent::RunEnded`].
    EndRun {
        ending: RunEnding,
        policy: StopOnFailure,
    },
    /// A run of this pane (`:run`) completed: the session checks the axes
    /// under `check` ([`crate::session::Session::check_run_end`]), says
    /// what it found, and ends the run under `policy` as a failed one when
    /// an axis is left moving that the file did not mean to leave so (what
    /// it did back as [`PaneEvent::RunEnded`]).
    CheckRunEnd {
        check: crate::session::run_end::AtTheEnd,
        policy: StopOnFailure,
    },
    /// Poll status this many times a second (0: stop polling).
    Poll(f64),
    /// Work with this axis (index into [`Snapshot::axes`]).
    SelectAxis(usize),
    /// Send lines to this module address from now on.
    SetAddress(u8),
    /// Forget the latched error flags of this axis that the user has seen.
    ClearErrors(usize),
    /// Log every frame to this file, replacing one there only with
    /// `--force` (`None`: stop logging).
    Log(Option<(PathBuf, crate::files::Existing)>),
    /// Switch colours.
    Theme(String),
    /// Switch key bindings.
    Keymap(String),
    /// Connect (or reconnect) with these connection options
    /// (`--sim tmcm1110`, `--port /dev/ttyUSB0 --baud 115200`).
    Connect(Vec<String>),
    /// Take these axis mechanics as those in force (`:mechanics FILE`;
    /// an empty table: none).
    Mechanics(crate::protocol::units::MechanicsTable),
    /// Give the keyboard to the pane called this ([`Pane::name`]).
    Focus(&'static str),
    /// The protocol family (its [`Family::name`]) of the connection being
    /// chosen on the connect screen: the other panes hear of it as
    /// [`PaneEvent::FamilyChosen`] (help and completion use its tables
    /// while nothing is connected).
    ChooseFamily(&'static str),
    /// Answer with [`PaneEvent::Wake`] after this long.
    WakeAfter { after: Duration, tag: u64 },
    /// Run a program transfer (one at a time per connection): progress
    /// comes back as [`PaneEvent::TransferProgress`], the end as
    /// [`PaneEvent::Transferred`], both under `tag`.
    Transfer { job: TransferJob, tag: u64 },
    /// Stop the running transfer between two words (a download leaves
    /// download mode); its [`PaneEvent::Transferred`] still comes.
    CancelTransfer,
    /// Load program source into the connected simulator's program memory,
    /// as its vendor's tool would (only an in-process simulator can: the
    /// CMD-4CR manual gives no wire format for it). The answer comes back
    /// as [`PaneEvent::ProgramLoaded`] under `tag`.
    LoadProgram { source: String, tag: u64 },
    /// Run the wiring check on axis `axis` at jog speed `speed`
    /// ([`crate::session::Session::check_wiring`]); what it found comes
    /// back as [`PaneEvent::WiringChecked`] under `tag`. One at a time;
    /// the emergency stop ends it.
    CheckWiring { axis: usize, speed: i64, tag: u64 },
    /// End the running wiring check where it is (its moves are the
    /// pane's to stop: send the stop lines after this).
    CancelWiring,
    /// Run a tuning job ([`crate::session::tuning`]); what it gave comes
    /// back as [`PaneEvent::Tuned`] under `tag`. One at a time; the
    /// emergency stop ends it.
    Tune { job: super::app::TuneJob, tag: u64 },
    /// End the running tuning job where it is (a dropped run sends no stop
    /// lines: the pane sends the axis's stop after this).
    CancelTune,
    /// Drive an input of the connected simulator by a setting (`IO5=1`),
    /// as if wired (only an in-process simulator can); what now holds, or
    /// why not, comes back as a [`PaneEvent::Notice`].
    DriveSimInput(String),
    /// Read `line` (a read of axis `axis`) with the status polls (`on`),
    /// or no longer; its number comes in the snapshot's
    /// [`crate::session::AxisStatus::watched`]; with the fast status
    /// items when `fast` ([`crate::session::Session::watch_at`]).
    Watch {
        axis: usize,
        line: String,
        on: bool,
        fast: bool,
    },
    /// `:plot ARGS` typed in the command pane: for the plot pane, as
    /// [`PaneEvent::Plot`].
    Plot(String),
    /// Tell every pane what a tool did, for the commissioning sheet (as
    /// [`PaneEvent::SheetFact`]).
    SheetFact(SheetFact),
    /// Read the module's settings that have a factory default
    /// ([`crate::session::sheet::read_settings`]; `sent`: the canonical
    /// lines sent that succeeded, to tell whether one stored them); they
    /// come back as [`PaneEvent::SettingsRead`] under `tag`.
    ReadSettings { sent: Vec<String>, tag: u64 },
    /// Say this in the command pane (as [`PaneEvent::Notice`]).
    Say(Notice),
    /// Leave the console.
    Quit,
}

/// What a pane did with an input or an event.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Outcome {
    /// Not for this pane: the app may use the key (Tab moves the focus).
    #[default]
    Ignored,
    /// Taken; the screen is redrawn and the requests carried out in order.
    Handled(Vec<Request>),
}

impl Outcome {
    /// Taken, nothing to ask: just redraw.
    pub fn redraw() -> Outcome {
        Outcome::Handled(Vec::new())
    }

    pub fn request(request: Request) -> Outcome {
        Outcome::Handled(vec![request])
    }
}

/// One pane of the console. See the module documentation of [`crate::ui`]
/// for how a pane is added.
pub trait Pane: Send {
    /// A short stable name: what [`Request::Focus`] names ("command",
    /// "axes", "params").
    fn name(&self) -> &'static str;

    /// The keymap section of its own keys. The app looks keys up there
    /// (after the global ones) to move the focus when the pane ignores a
    /// key; the pane looks its own actions up with
    /// `view.keymap.action_for(self.context(), key)`.
    fn context(&self) -> Context;

    /// Shown in its border and on its tab.
    fn title(&self, view: &View) -> String;

    /// Where it goes when there is room for several panes.
    fn region(&self) -> Region;

    /// Rows it would like inside its border at this inner width, given
    /// that at most `room` rows are to be had, if it has a natural height
    /// (the axis gauges: cards when they fit, one row per axis when not);
    /// `None` takes a third of the screen.
    fn height_hint(&self, view: &View, width: u16, room: u16) -> Option<u16> {
        let _ = (view, width, room);
        None
    }

    /// Draw into `area` (inside the border the app draws). A focused pane
    /// with a text cursor sets it with `frame.set_cursor_position`.
    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View);

    /// A key, mouse or paste while this pane has the focus. The emergency
    /// stop, quit and focus-pane-N keys never get here; the other global
    /// actions (help, clear errors, next pane) come here first and go to
    /// the app if the pane ignores them.
    fn handle_input(&mut self, input: &Input, view: &View) -> Outcome;

    /// Something the pane has under way that must be seen whatever is on
    /// the screen (a program running from the host): the status bar shows
    /// it.
    fn activity(&self) -> Option<String> {
        None
    }

    /// News for every pane; return [`Outcome::Ignored`] when it changes
    /// nothing this pane shows, so that an idle screen is not redrawn.
    fn on_event(&mut self, event: &PaneEvent, view: &View) -> Outcome {
        let _ = (event, view);
        Outcome::Ignored
    }
}

/// The first key of `action` in `context` as the status bar shows it
/// ("F12"), or "(unbound)".
pub fn key_label(keymap: &Keymap, context: Context, action: Action) -> String {
    keymap
        .chords(context, action)
        .first()
        .map_or_else(|| "(unbound)".to_string(), |chord| chord.label())
}
