//! The traffic monitor inside the console: frames with time, direction,
//! bytes, meaning and round trip; pause, hidden polls, scrolling, saving to
//! a file, and the bounded ring.

mod panes_support;
mod ui_support;

use std::time::{Duration, Instant};

use axterm::device::{Direction, Priority, TrafficKind, TrafficRecord};
use axterm::families::find_family;
use axterm::protocol::tmcl::{Reply, Status, parse_line};
use axterm::ui::app::{App, AppEvent, Effect};
use axterm::ui::keymap::Keymap;
use axterm::ui::pane::{Pane, PaneEvent, View};
use axterm::ui::theme::Theme;
use axterm::ui::traffic::{REFRESH, TrafficPane};
use panes_support::draw;
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use ui_support::{key, key_with, snapshot, type_text};

fn request(line: &str, at: Instant, priority: Priority) -> TrafficRecord {
    TrafficRecord {
        at,
        direction: Direction::Sent,
        kind: TrafficKind::Request,
        bytes: parse_line(line)
            .expect("line")
            .to_request(1)
            .to_bytes()
            .to_vec(),
        priority: Some(priority),
    }
}

fn answer(command: u8, value: i32, at: Instant, priority: Priority) -> TrafficRecord {
    TrafficRecord {
        at,
        direction: Direction::Received,
        kind: TrafficKind::Answer,
        bytes: Reply {
            host_address: 2,
            module_address: 1,
            status: Status::OK,
            command,
            value,
        }
        .to_bytes()
        .to_vec(),
        priority: Some(priority),
    }
}

fn console() -> App {
    let mut app = ui_support::console();
    let family = find_family("tmcl").expect("tmcl");
    app.handle(AppEvent::Snapshot(snapshot(family.console.axes().to_vec())));
    app.focus("traffic");
    app
}

/// A poll of AP1 and its answer, then the user's SAP and its answer.
fn some_traffic(app: &mut App, t0: Instant) {
    let ms = |n| t0 + Duration::from_millis(n);
    for record in [
        request("GAP 1, 0", ms(0), Priority::Poll),
        answer(6, -500, ms(2), Priority::Poll),
        request("SAP 4, 0, 1000", ms(10), Priority::User),
        answer(5, 1000, ms(13), Priority::User),
    ] {
        app.handle(AppEvent::Traffic(record));
    }
}

fn text(app: &mut App, w: u16, h: u16) -> String {
    draw(app, w, h).0.join("\n")
}

#[test]
fn frames_show_time_direction_bytes_meaning_and_round_trip() {
    let mut app = console();
    some_traffic(&mut app, Instant::now());
    let (lines, _) = draw(&mut app, 80, 24);
    let all = lines.join("\n");
    let sent = lines
        .iter()
        .find(|l| l.contains("SAP 4, 0, 1000 to module 1"))
        .unwrap_or_else(|| panic!("{all}"));
    assert!(sent.contains("    0.010 →"), "{sent}");
    assert!(sent.contains("01 05 04 00 00 00 03 E8"), "{sent}");
    let got = lines
        .iter()
        .find(|l| l.contains("SAP from module 1"))
        .unwrap_or_else(|| panic!("{all}"));
    assert!(got.contains("    0.013 ←   3.0ms"), "{got}");
    let poll = lines
        .iter()
        .find(|l| l.contains("GAP from module 1: -500"))
        .unwrap_or_else(|| panic!("{all}"));
    assert!(poll.contains("2.0ms"), "{poll}");
    assert!(all.contains("4 frames"), "{all}");
}

#[test]
fn at_a_large_size_traffic_and_plot_share_the_side_column() {
    let mut app = console();
    some_traffic(&mut app, Instant::now());
    let all = text(&mut app, 200, 50);
    assert!(all.contains("SAP 4, 0, 1000 to module 1"), "{all}");
    assert!(all.contains("Traffic") && all.contains("Plot"), "{all}");
    assert!(all.contains("Command"), "{all}");
}

#[test]
fn pausing_freezes_the_view_and_resuming_catches_up() {
    let mut app = console();
    let t0 = Instant::now();
    some_traffic(&mut app, t0);
    app.handle(key(KeyCode::Char(' ')));
    app.handle(AppEvent::Traffic(request(
        "MVP ABS, 0, 5000",
        t0 + Duration::from_millis(20),
        Priority::User,
    )));
    let all = text(&mut app, 80, 24);
    assert!(!all.contains("MVP ABS"), "{all}");
    assert!(
        all.contains("PAUSED (+1 new)") && all.contains("Traffic (paused)"),
        "{all}"
    );
    app.handle(key(KeyCode::Char(' ')));
    let all = text(&mut app, 80, 24);
    assert!(all.contains("MVP ABS, 0, 5000"), "{all}");
    assert!(!all.contains("PAUSED"), "{all}");
}

#[test]
fn hiding_polls_hides_them_and_their_answers() {
    let mut app = console();
    some_traffic(&mut app, Instant::now());
    app.handle(key(KeyCode::Char('p')));
    let all = text(&mut app, 80, 24);
    assert!(!all.contains("GAP"), "{all}");
    assert!(all.contains("SAP 4, 0, 1000"), "{all}");
    assert!(
        all.contains("2 frames") && all.contains("polls hidden"),
        "{all}"
    );
    app.handle(key(KeyCode::Char('p')));
    assert!(text(&mut app, 80, 24).contains("GAP 1, 0 to module 1"));
}

#[test]
fn saving_writes_the_frames_shown_to_a_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("frames.txt");
    let mut app = console();
    some_traffic(&mut app, Instant::now());
    app.handle(key(KeyCode::Char('p')));
    app.handle(key(KeyCode::Char('s')));
    assert!(text(&mut app, 80, 24).contains("save to: axterm-traffic.txt"));
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
    // Letters are the file name now, not keys (p would hide polls).
    type_text(&mut app, &path.display().to_string());
    app.handle(key(KeyCode::Enter));
    let saved = std::fs::read_to_string(&path).expect("saved");
    let lines: Vec<&str> = saved.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines.len(), 2, "{saved}");
    assert!(lines[0].contains("SAP 4, 0, 1000 to module 1"), "{saved}");
    assert!(lines[1].contains("3.0ms") && lines[1].contains("100 successfully executed"));
    assert!(text(&mut app, 80, 24).contains("saved 2 frame(s)"));
}

#[test]
fn a_file_that_cannot_be_written_is_reported() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut app = console();
    some_traffic(&mut app, Instant::now());
    app.handle(key(KeyCode::Char('s')));
    app.handle(key_with(KeyCode::Char('u'), KeyModifiers::CONTROL));
    type_text(
        &mut app,
        &dir.path().join("no/such/dir.txt").display().to_string(),
    );
    app.handle(key(KeyCode::Enter));
    assert!(text(&mut app, 120, 24).contains("cannot write"));
}

#[test]
fn scrolled_back_the_view_stays_put_as_frames_arrive() {
    let mut app = console();
    let t0 = Instant::now();
    for n in 0..40u64 {
        app.handle(AppEvent::Traffic(request(
            &format!("SAP 4, 0, {}", 100 + n),
            t0 + Duration::from_millis(n),
            Priority::User,
        )));
    }
    app.handle(key(KeyCode::Home));
    let all = text(&mut app, 80, 24);
    assert!(all.contains("SAP 4, 0, 100 to"), "{all}");
    app.handle(AppEvent::Traffic(request(
        "SAP 4, 0, 999",
        t0 + Duration::from_millis(50),
        Priority::User,
    )));
    let all = text(&mut app, 80, 24);
    assert!(
        all.contains("SAP 4, 0, 100 to") && !all.contains("999"),
        "{all}"
    );
    app.handle(key(KeyCode::End));
    assert!(text(&mut app, 80, 24).contains("SAP 4, 0, 999 to"));
    // Clearing empties the monitor.
    app.handle(key_with(KeyCode::Char('l'), KeyModifiers::CONTROL));
    assert!(text(&mut app, 80, 24).contains("no frames yet"));
}

#[test]
fn memory_is_a_ring_of_the_last_frames() {
    let theme = Theme::builtin("dark").expect("theme");
    let keymap = Keymap::builtin("default").expect("keymap");
    let family = find_family("tmcl").expect("tmcl");
    let session = snapshot(family.console.axes().to_vec());
    let view = View {
        theme: &theme,
        keymap: &keymap,
        session: Some(&session),
        modules: &[],
        module: 0,
        focused: true,
        shown: true,
    };
    let mut pane = TrafficPane::with_limit(100);
    let t0 = Instant::now();
    for n in 0..250 {
        let record = request("GAP 1, 0", t0 + Duration::from_millis(n), Priority::Poll);
        pane.on_event(&PaneEvent::Traffic(record), &view);
    }
    assert_eq!(pane.len(), 100);
    assert_eq!(axterm::ui::traffic::TRAFFIC_LIMIT, 10_000);
}

#[test]
fn garbage_and_late_frames_say_what_they_are() {
    let mut app = console();
    let t0 = Instant::now();
    app.handle(AppEvent::Traffic(TrafficRecord {
        at: t0,
        direction: Direction::Received,
        kind: TrafficKind::Garbage,
        bytes: vec![0xFF, 0x00, 0x13],
        priority: None,
    }));
    let mut late = answer(6, 7, t0, Priority::User);
    late.kind = TrafficKind::Stale;
    app.handle(AppEvent::Traffic(late));
    let all = text(&mut app, 100, 24);
    assert!(
        all.contains("garbage: 3 byte(s) that never made a frame"),
        "{all}"
    );
    assert!(
        all.contains("late, nobody waited: command 6 from module 1: 7"),
        "{all}"
    );
}

#[test]
fn a_flood_of_frames_is_drawn_at_most_every_refresh() {
    let mut app = console();
    let t0 = Instant::now();
    let wakes = |effects: &[Effect]| -> Vec<(usize, u64)> {
        effects
            .iter()
            .filter_map(|e| match e {
                Effect::Wake { pane, tag, after } if *after == REFRESH => Some((*pane, *tag)),
                _ => None,
            })
            .collect()
    };
    // The first frame is drawn at once, with a wake-up asked for.
    draw(&mut app, 80, 24);
    let first = app.handle(AppEvent::Traffic(request("GAP 1, 0", t0, Priority::Poll)));
    assert!(app.needs_redraw());
    let woken = wakes(&first);
    assert_eq!(woken.len(), 1, "{first:?}");
    draw(&mut app, 80, 24);
    // The next ones wait for it.
    for n in 1..50 {
        let effects = app.handle(AppEvent::Traffic(request(
            "GAP 1, 0",
            t0 + Duration::from_millis(n),
            Priority::Poll,
        )));
        assert!(wakes(&effects).is_empty());
    }
    assert!(!app.needs_redraw());
    let (pane, tag) = woken[0];
    let again = app.handle(AppEvent::Wake { pane, tag });
    assert!(app.needs_redraw());
    assert!(text(&mut app, 80, 24).contains("50 frames"));
    // Nothing new by the next wake-up: nothing to draw, no more wake-ups.
    let (pane, tag) = wakes(&again)[0];
    assert!(app.handle(AppEvent::Wake { pane, tag }).is_empty());
    assert!(!app.needs_redraw());
}
