//! Shared by the console's render tests: a console with the real panes,
//! hand-made snapshots, keys, and the screen as text.
#![allow(dead_code)]

pub mod looped;

use std::sync::Arc;

use axterm::device::LinkState;
use axterm::families::find_family;
use axterm::session::{AxisInfo, AxisStatus, PollCadence};
use axterm::ui::app::{App, AppEvent};
use axterm::ui::keymap::Keymap;
use axterm::ui::pane::Snapshot;
use axterm::ui::theme::Theme;
use axterm::ui::{PaneSetup, panes};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};

pub fn console() -> App {
    console_with(&PaneSetup::default())
}

pub fn console_with(setup: &PaneSetup) -> App {
    let theme = Theme::builtin("dark").expect("built-in theme");
    let keymap = Keymap::builtin("default").expect("built-in keymap");
    App::new(panes(setup), theme, keymap)
}

/// Axes with these names, numbered from 0. The names must live for the
/// whole test run, as a family's names do.
pub fn axes(names: &[&'static str]) -> Vec<AxisInfo> {
    names
        .iter()
        .enumerate()
        .map(|(i, name)| AxisInfo {
            number: i as u8,
            name,
        })
        .collect()
}

/// A connected TMCL module with `axes`, polled at 20 Hz, nothing read yet.
pub fn snapshot(axes: Vec<AxisInfo>) -> Snapshot {
    Snapshot {
        family: find_family("tmcl").expect("tmcl"),
        address: 1,
        link_name: "sim tmcm1110".into(),
        status: vec![AxisStatus::default(); axes.len()],
        axes,
        link: LinkState::Connected {
            link: "sim tmcm1110".into(),
        },
        identity: None,
        poll: Some(PollCadence::default()),
        settings: Default::default(),
        mechanics: Default::default(),
        axis: 0,
    }
}

pub fn moving_status(position: i64, target: i64, speed: i64, max_speed: i64) -> AxisStatus {
    AxisStatus {
        position: Some(position),
        target: Some(target),
        speed: Some(speed),
        max_speed: Some(max_speed),
        own_max_speed: Some(max_speed),
        global_max_speed: None,
        reached: Some(position == target),
        left_switch: Some(false),
        right_switch: Some(false),
        home_switch: Some(false),
        load: Some(800),
        errors: Vec::new(),
        driver_flags: Some(Vec::new()),
        ..AxisStatus::default()
    }
}

pub fn key(code: KeyCode) -> AppEvent {
    AppEvent::Terminal(Event::Key(KeyEvent::new(code, KeyModifiers::NONE)))
}

pub fn key_with(code: KeyCode, modifiers: KeyModifiers) -> AppEvent {
    AppEvent::Terminal(Event::Key(KeyEvent::new(code, modifiers)))
}

/// Hand the console a snapshot, then carry out at once the wake-ups it
/// asks for, as the loop would once their time is up: numbers a pane
/// held back for a readable rate are drawn.
pub fn show(app: &mut App, snapshot: Snapshot) {
    let effects = app.handle(AppEvent::Snapshot(snapshot));
    for effect in effects {
        if let axterm::ui::app::Effect::Wake { pane, tag, .. } = effect {
            app.handle(AppEvent::Wake { pane, tag });
        }
    }
}

/// Type `text` key by key.
pub fn type_text(app: &mut App, text: &str) -> Vec<axterm::ui::app::Effect> {
    let mut effects = Vec::new();
    for c in text.chars() {
        effects.extend(app.handle(key(KeyCode::Char(c))));
    }
    effects
}

/// The screen as lines of text.
pub fn screen(app: &mut App, width: u16, height: u16) -> Vec<String> {
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

/// The console's own controller on a session with the in-process
/// simulator `kind`, its wire timed at `baud`.
pub async fn sim_controller(kind: &str, baud: u32) -> Arc<dyn axterm::ui::app::Controller> {
    use axterm::cli::ConnectionArgs;
    use axterm::cli::connection::Target;
    let target = Target::resolve(&ConnectionArgs {
        sim: Some(kind.into()),
        baud: Some(baud),
        ..ConnectionArgs::default()
    })
    .expect("a simulator connection");
    let session = target.open().await.expect("the simulator opens");
    Arc::new(axterm::ui::live::SessionController::new(
        session,
        target.spec.describe(),
        target.options.clone(),
    ))
}
