//! A console whose panes sit behind tabs asks for no refreshes: the traffic
//! monitor and the plot keep recording, and ask to be woken to redraw only
//! while they are on screen.

mod ui_support;

use std::time::Instant;

use axterm::device::{Direction, Priority, TrafficKind, TrafficRecord};
use axterm::ui::app::{AppEvent, Effect};
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use ui_support::{axes, console, key_with, moving_status, screen, snapshot};

fn poll_record() -> TrafficRecord {
    TrafficRecord {
        at: Instant::now(),
        direction: Direction::Sent,
        kind: TrafficKind::Request,
        bytes: vec![1, 6, 1, 0, 0, 0, 0, 0, 8],
        priority: Some(Priority::Poll),
    }
}

/// The axes pane (second of `ui::panes`): it asks to be woken to draw
/// numbers held back for a readable rate, shown or not behind a tab.
const AXES_PANE: usize = 1;

/// Wake-ups asked for, other than the axes pane's.
fn wakes(effects: &[Effect]) -> usize {
    effects
        .iter()
        .filter(|e| matches!(e, Effect::Wake { pane, .. } if *pane != AXES_PANE))
        .count()
}

#[test]
fn hidden_traffic_and_plot_panes_ask_for_no_wake_ups() {
    let mut app = console();
    let mut s = snapshot(axes(&["motor 0"]));
    // 100x30: the command pane in front, traffic and plot behind tabs.
    screen(&mut app, 100, 30);
    assert_eq!(wakes(&app.handle(AppEvent::Snapshot(s.clone()))), 0);
    assert_eq!(wakes(&app.handle(AppEvent::Traffic(poll_record()))), 0);
    s.status[0] = moving_status(100, 5000, 500, 1000);
    assert_eq!(wakes(&app.handle(AppEvent::Snapshot(s.clone()))), 0);

    // Brought to the front, they refresh as frames and samples come.
    for (pane, event) in [
        ('4', AppEvent::Traffic(poll_record())),
        ('5', {
            s.status[0].position = Some(200);
            AppEvent::Snapshot(s.clone())
        }),
    ] {
        app.handle(key_with(KeyCode::Char(pane), KeyModifiers::ALT));
        screen(&mut app, 100, 30);
        assert_eq!(wakes(&app.handle(event)), 1, "pane {pane}");
    }
}
