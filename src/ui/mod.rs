//! The terminal console (TUI): panes drawn with ratatui from the session's
//! snapshots, keys through the keymap, colours through the theme.
//!
//! - [`theme`] gives every part of the screen a style, [`keymap`] turns key
//!   presses into actions, per pane; [`config`] finds the user's own files
//!   and reports what is wrong with them.
//! - [`pane`]: the [`pane::Pane`] trait and what panes see ([`View`](pane::View),
//!   [`Snapshot`](pane::Snapshot)) and ask for ([`Request`](pane::Request)).
//! - [`app`]: the [`App`](app::App) (focus, layout, status bar, dispatch) and
//!   the event loop that redraws only when something changed.
//! - [`terminal`]: raw mode and the alternate screen, always restored;
//!   [`live`]: the console on a real terminal and a real session.
//! - One file per pane: [`command`] (the console line editor, with
//!   [`batch`] for `:run`), [`axes`] (axis status gauges and lamps),
//!   [`params`] (the parameter table, export and import), [`traffic`]
//!   (every frame), [`plot`] (position and speed over time), [`connect`]
//!   (the connect screen), [`editor`] (programs, in the language of the
//!   family's program tool); [`field`] is the one-line text field they
//!   share, [`text`] how they cut text to a width.
//!
//! # Adding a pane
//!
//! 1. Write `src/ui/NAME.rs` with a type implementing [`pane::Pane`]: a
//!    `name()` (what `Request::Focus` names), its keymap `context()`
//!    (`Context::Parameters`, `Traffic`, `Plot`…: look your keys up with
//!    `view.keymap.action_for(self.context(), key)`), a `title()`, its
//!    home [`pane::Region`] (`Top`, `Main` or `Side`), `render()` into the
//!    area inside the border the app draws, and `handle_input()` for keys
//!    while it has the focus (return `Outcome::Ignored` for keys it does
//!    not use, so Tab and the global keys reach the app). Override
//!    `on_event()` to follow traffic, replies to the lines it sent
//!    ([`pane::Request::Send`] with a tag of its choosing), timers
//!    ([`pane::Request::WakeAfter`]) or snapshot changes; return
//!    `Outcome::Ignored` when nothing it shows changed, so an idle console
//!    is not redrawn, and skip refresh timers while `view.shown` is false
//!    (behind a tab). Colours only through `view.theme.style(Role::…)`.
//! 2. Add `pub mod NAME;` below and one line to [`panes`] (which gets a
//!    [`PaneSetup`] for anything a pane is built with).
//!
//! That is all: the app lays the panes out (the `Top` pane above the
//! others, as high as it asks but leaving the rest at least 10 rows; the
//! `Main` and `Side` panes share the rest as tabs, until from 160 columns
//! `Side` panes get a column of their own; on a very small screen every
//! pane is a tab), moves the focus (the keymap's next/previous pane keys
//! when the pane ignores them, Alt-1…9, a click with `--mouse`), and
//! keeps the emergency stop and quit keys ahead of every pane. A
//! connect screen is a pane too: it sees `view.session == None` and asks
//! for [`pane::Request::Connect`]. Test a pane alone with ratatui's
//! `TestBackend` and a [`pane::Snapshot`] built by hand, or inside an
//! [`app::App`] (see `tests/ui_support/`).

pub mod app;
pub mod axes;
pub mod batch;
pub mod bringup;
pub mod command;
pub mod config;
pub mod connect;
pub mod diff_backend;
pub mod editor;
pub mod field;
pub mod host_run;
pub mod key_delivery;
pub mod keymap;
pub mod live;
pub mod pane;
pub mod params;
pub mod plot;
pub mod readable;
pub mod terminal;
pub mod text;
pub mod theme;
pub mod traffic;
pub mod tuning;

use std::path::PathBuf;

use pane::Pane;

/// What the panes are built with.
#[derive(Debug, Clone, Default)]
pub struct PaneSetup {
    /// Where the command history (one file per protocol family) and the
    /// recent connections are kept; `None` keeps none.
    pub history_dir: Option<PathBuf>,
}

/// Every pane of the console, in tab order (Alt-1 is the first).
pub fn panes(setup: &PaneSetup) -> Vec<Box<dyn Pane>> {
    vec![
        Box::new(command::CommandPane::new(setup.history_dir.clone())),
        Box::new(axes::AxesPane::new()),
        Box::new(params::ParamsPane::new()),
        Box::new(traffic::TrafficPane::new()),
        Box::new(plot::PlotPane::new()),
        Box::new(connect::ConnectPane::new(
            setup.history_dir.as_deref(),
            crate::link::ports::listed_ports,
        )),
        Box::new(editor::EditorPane::new(setup.history_dir.clone())),
        Box::new(bringup::BringUpPane::new()),
        Box::new(tuning::TuningPane::new()),
    ]
}
