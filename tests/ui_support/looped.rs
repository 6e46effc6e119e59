//! The console's real event loop ([`app::run`]) drawing into a
//! `TestBackend`, driven by keys, on tokio's paused clock: for tests of a
//! console on a fake controller or on a real session.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use axterm::ui::app::{self, App, AppEvent, Connector, Controller};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use tokio::sync::mpsc;

/// Every frame the loop drew, as text.
pub struct Screens {
    pub frames: Arc<Mutex<Vec<String>>>,
    drawn: mpsc::UnboundedReceiver<String>,
}

impl Screens {
    /// Wait for a frame containing `needle` (virtual time: gives up at
    /// once if nothing else can happen).
    pub async fn until(&mut self, needle: &str) -> String {
        self.until_frame(needle, |frame| frame.contains(needle))
            .await
    }

    /// Wait for a frame `ready` says yes to; `what` names it if none comes.
    pub async fn until_frame(&mut self, what: &str, ready: impl Fn(&str) -> bool) -> String {
        let found = tokio::time::timeout(Duration::from_secs(600), async {
            while let Some(frame) = self.drawn.recv().await {
                if ready(&frame) {
                    return Some(frame);
                }
            }
            None
        })
        .await;
        match found {
            Ok(Some(frame)) => frame,
            _ => {
                let last = self.frames.lock().map(|f| f.last().cloned()).ok().flatten();
                panic!(
                    "never showed {what:?}; last frame:\n{}",
                    last.unwrap_or_default()
                )
            }
        }
    }
}

/// The loop, its keyboard, extra events, and what it draws.
pub struct Rig {
    pub keys: mpsc::UnboundedSender<Event>,
    pub extra: mpsc::UnboundedSender<AppEvent>,
    pub screens: Screens,
}

/// The default console at 100×30 on `controller` until `driver` ends it.
pub async fn run_console(
    controller: Option<Arc<dyn Controller>>,
    connector: Connector,
    driver: impl AsyncFnOnce(Rig),
) {
    run_console_on(super::console(), (100, 30), controller, connector, driver).await;
}

/// `app` at `size` (columns, rows) on `controller` until `driver` ends
/// it (F10, or [`AppEvent::Terminate`] through `extra`).
pub async fn run_console_on(
    app: App,
    size: (u16, u16),
    controller: Option<Arc<dyn Controller>>,
    connector: Connector,
    driver: impl AsyncFnOnce(Rig),
) {
    let links = controller.map(|c| vec![vec![c]]).unwrap_or_default();
    run_links_on(app, size, links, connector, driver).await;
}

/// `app` at `size` on several links, each with its modules
/// ([`app::run_links`]), until `driver` ends it.
pub async fn run_links_on(
    mut app: App,
    (width, height): (u16, u16),
    links: Vec<Vec<Arc<dyn Controller>>>,
    connector: Connector,
    driver: impl AsyncFnOnce(Rig),
) {
    let (keys, input) = mpsc::unbounded_channel();
    let (extra, extra_rx) = mpsc::unbounded_channel();
    let (drawn_tx, drawn) = mpsc::unbounded_channel();
    let frames = Arc::new(Mutex::new(Vec::new()));
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("test backend");
    let recorded = Arc::clone(&frames);
    let mut draw = move |app: &mut App| -> std::io::Result<()> {
        let Ok(_) = terminal.draw(|f| app.render(f));
        let buffer = terminal.backend().buffer();
        let text: Vec<String> = (0..height)
            .map(|y| {
                (0..width)
                    .map(|x| buffer[(x, y)].symbol().to_string())
                    .collect()
            })
            .collect();
        let text = text.join("\n");
        if let Ok(mut frames) = recorded.lock() {
            frames.push(text.clone());
        }
        let _ = drawn_tx.send(text);
        Ok(())
    };
    let rig = Rig {
        keys,
        extra,
        screens: Screens { frames, drawn },
    };
    let looping = app::run_links(&mut app, links, connector, input, Some(extra_rx), &mut draw);
    let (result, ()) = tokio::join!(looping, driver(rig));
    result.expect("the loop ends cleanly");
}

/// The default console at `size` (columns, rows) on `controller`, the
/// command pane focused, until `driver` is done (then F10).
pub async fn run_command_console(
    controller: Arc<dyn Controller>,
    size: (u16, u16),
    driver: impl AsyncFnOnce(&mut Rig),
) {
    let mut app = super::console_with(&axterm::ui::PaneSetup::default());
    app.focus("command");
    run_console_on(
        app,
        size,
        Some(controller),
        no_connector(),
        async |mut rig: Rig| {
            driver(&mut rig).await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
}

/// Paste `line` into the focused pane and press Enter.
pub fn enter(rig: &Rig, line: &str) {
    let _ = rig.keys.send(Event::Paste(line.to_string()));
    press(rig, KeyCode::Enter);
}

/// A connector for tests that open no connections.
pub fn no_connector() -> Connector {
    Box::new(|_args| Box::pin(async { Err("no connections in this test".to_string()) }))
}

pub fn press(rig: &Rig, code: KeyCode) {
    press_with(rig, code, KeyModifiers::NONE);
}

pub fn press_with(rig: &Rig, code: KeyCode, modifiers: KeyModifiers) {
    let _ = rig.keys.send(Event::Key(KeyEvent::new(code, modifiers)));
}

/// Type `line` and press Enter.
pub fn type_line(rig: &Rig, line: &str) {
    for c in line.chars() {
        press(rig, KeyCode::Char(c));
    }
    press(rig, KeyCode::Enter);
}
