//! The plot pane inside the console, on a clock moved by hand: position
//! and speed drawn from status snapshots, the window zoomed, frozen, the
//! signals told apart by marker in the mono theme, and redraw wake-ups
//! only while the picture moves.

mod panes_support;
mod ui_support;

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use axterm::families::find_family;
use axterm::ui::app::{App, AppEvent, Effect};
use axterm::ui::axes::AxesPane;
use axterm::ui::keymap::Keymap;
use axterm::ui::pane::{Pane, Snapshot};
use axterm::ui::plot::PlotPane;
use axterm::ui::theme::Theme;
use panes_support::draw;
use ratatui::crossterm::event::KeyCode;
use ui_support::{key, moving_status, snapshot};

/// A clock the test moves.
#[derive(Clone)]
struct Hand(Arc<Mutex<Instant>>);

impl Hand {
    fn new() -> Hand {
        Hand(Arc::new(Mutex::new(Instant::now())))
    }
    fn advance(&self, by: Duration) {
        let mut now = self.0.lock().expect("clock");
        *now += by;
    }
    fn clock(&self) -> axterm::ui::plot::Clock {
        let hand = Arc::clone(&self.0);
        Arc::new(move || *hand.lock().expect("clock"))
    }
}

fn console(theme: &str, hand: &Hand) -> App {
    let panes: Vec<Box<dyn Pane>> = vec![
        Box::new(AxesPane::new()),
        Box::new(PlotPane::with_clock(hand.clock())),
    ];
    let theme = Theme::builtin(theme).expect("theme");
    let keymap = Keymap::builtin("default").expect("keymap");
    let mut app = App::new(panes, theme, keymap);
    app.focus("plot");
    app
}

fn at(position: i64, speed: i64) -> Snapshot {
    let family = find_family("tmcl").expect("tmcl");
    let mut s = snapshot(family.console.axes().to_vec());
    s.status = vec![moving_status(position, 4000, speed, 1000)];
    s
}

/// The plot pane's index in this console (after the axes pane).
const PLOT_PANE: usize = 1;

/// A move from 0 to 4000 over four seconds, sampled every half second.
fn a_move(app: &mut App, hand: &Hand) -> Vec<Effect> {
    let mut effects = Vec::new();
    for step in 0..=8 {
        effects.extend(app.handle(AppEvent::Snapshot(at(
            step * 500,
            if step < 8 { 1000 } else { 0 },
        ))));
        hand.advance(Duration::from_millis(500));
    }
    effects
}

fn text(app: &mut App, w: u16, h: u16) -> String {
    draw(app, w, h).0.join("\n")
}

#[test]
fn position_and_speed_are_drawn_at_80x24_and_large() {
    let hand = Hand::new();
    let mut app = console("dark", &hand);
    a_move(&mut app, &hand);
    for (w, h) in [(80, 24), (200, 50)] {
        let all = text(&mut app, w, h);
        assert!(all.contains("position (raw)"), "{all}");
        assert!(all.contains("speed"), "{all}");
        assert!(all.contains("-20 s") && all.contains("now"), "{all}");
        assert!(all.contains("last 20 s"), "{all}");
        // The y axis spans the move.
        assert!(all.contains("4200") || all.contains("4199"), "{all}");
        // Something was plotted.
        assert!(
            all.chars().any(|c| ('\u{2801}'..='\u{28FF}').contains(&c)),
            "{all}"
        );
    }
}

#[test]
fn the_window_zooms_in_out_and_resets() {
    let hand = Hand::new();
    let mut app = console("dark", &hand);
    a_move(&mut app, &hand);
    app.handle(key(KeyCode::Char('+')));
    let all = text(&mut app, 80, 24);
    assert!(all.contains("last 10 s") && all.contains("-10 s"), "{all}");
    app.handle(key(KeyCode::Char('-')));
    app.handle(key(KeyCode::Char('-')));
    let all = text(&mut app, 80, 24);
    assert!(all.contains("last 30 s") && all.contains("-30 s"), "{all}");
    app.handle(key(KeyCode::Char('0')));
    assert!(text(&mut app, 80, 24).contains("last 20 s"));
}

#[test]
fn freezing_holds_the_picture_while_samples_go_on() {
    let hand = Hand::new();
    let mut app = console("dark", &hand);
    a_move(&mut app, &hand);
    app.handle(key(KeyCode::Char(' ')));
    hand.advance(Duration::from_secs(1));
    app.handle(AppEvent::Snapshot(at(90_000, 2000)));
    let all = text(&mut app, 80, 24);
    assert!(
        all.contains("FROZEN") && all.contains("Plot (frozen)"),
        "{all}"
    );
    assert!(!all.contains("94"), "the new sample is not shown: {all}");
    app.handle(key(KeyCode::Char(' ')));
    let all = text(&mut app, 80, 24);
    assert!(!all.contains("FROZEN"), "{all}");
    assert!(
        all.contains("94"),
        "the y axis now reaches the new value: {all}"
    );
}

#[test]
fn in_the_mono_theme_the_target_has_its_own_marker() {
    let hand = Hand::new();
    let mut app = console("mono", &hand);
    a_move(&mut app, &hand);
    let all = text(&mut app, 100, 30);
    assert!(all.contains('•'), "target drawn with dots: {all}");
    assert!(
        all.chars().any(|c| ('\u{2801}'..='\u{28FF}').contains(&c)),
        "position in braille: {all}"
    );
    assert!(all.contains("• motor 0 target"), "legend: {all}");
}

#[test]
fn redraws_are_asked_for_only_while_the_picture_moves() {
    let hand = Hand::new();
    let mut app = console("dark", &hand);
    let effects = a_move(&mut app, &hand);
    let wakes: Vec<(usize, u64)> = effects
        .iter()
        .filter_map(|e| match e {
            // The plot pane's (the axes pane asks too, for its digits).
            Effect::Wake { pane, tag, after } if *pane == PLOT_PANE => {
                assert_eq!(*after, Duration::from_millis(200));
                Some((*pane, *tag))
            }
            _ => None,
        })
        .collect();
    // One wake-up pending at a time, however many samples came.
    assert_eq!(wakes.len(), 1, "{effects:?}");
    let (pane, tag) = wakes[0];
    // Within the window the next wake-up follows.
    let next = app.handle(AppEvent::Wake { pane, tag });
    let Some(Effect::Wake { tag, .. }) = next
        .iter()
        .find(|e| matches!(e, Effect::Wake { pane, .. } if *pane == PLOT_PANE))
        .cloned()
    else {
        panic!("{next:?}")
    };
    // Once the last change has left the window the picture stands still.
    hand.advance(Duration::from_secs(30));
    let last = app.handle(AppEvent::Wake { pane, tag });
    assert!(last.is_empty(), "{last:?}");
    // The same values again are no new sample and ask for nothing.
    let again = app.handle(AppEvent::Snapshot(at(4000, 0)));
    assert!(
        !again
            .iter()
            .any(|e| matches!(e, Effect::Wake { pane, .. } if *pane == PLOT_PANE)),
        "{again:?}"
    );
}

#[test]
fn another_axis_or_link_starts_the_plot_over() {
    let hand = Hand::new();
    let mut app = console("dark", &hand);
    a_move(&mut app, &hand);
    let mut other = at(7, 0);
    other.status[0].target = Some(7);
    other.link_name = "/dev/ttyUSB0".into();
    app.handle(AppEvent::Snapshot(other));
    let all = text(&mut app, 80, 24);
    // Only the new link's position 7 (±1) is on the axis.
    assert!(
        !all.contains("4200") && all.contains(" 8│position (raw)"),
        "{all}"
    );
}

/// Type `text` into the focused pane.
fn typed(app: &mut App, text: &str) -> Vec<Effect> {
    text.chars()
        .flat_map(|c| app.handle(key(KeyCode::Char(c))))
        .collect()
}

/// The screen row holding `needle`.
fn row_with<'a>(screen: &'a str, needle: &str) -> &'a str {
    screen
        .lines()
        .find(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("no {needle}:\n{screen}"))
}

#[test]
fn the_picker_lists_status_values_then_parameters_and_typing_narrows_it_at_80x24() {
    let hand = Hand::new();
    let mut app = console("dark", &hand);
    a_move(&mut app, &hand);
    // The head line names the key.
    assert!(text(&mut app, 80, 24).contains("a pick"));
    app.handle(key(KeyCode::Char('a')));
    let all = text(&mut app, 80, 24);
    assert!(all.contains("motor 0: what to plot"), "{all}");
    assert!(all.contains("Enter plot/unplot · Esc close"), "{all}");
    // Status values first, the followed ones marked plotted; the
    // cursor on the first.
    let position = all.find("position (status)").expect("position");
    let first_parameter = all.find("   0 Target position").expect("{all}");
    assert!(position < first_parameter, "{all}");
    assert!(
        row_with(&all, "position (status)").contains("› [x]"),
        "{all}"
    );
    assert!(row_with(&all, "load (status)").contains("[ ]"), "{all}");

    typed(&mut app, "load");
    let all = text(&mut app, 80, 24);
    assert!(all.contains("filter: load"), "{all}");
    assert!(all.contains("load (status)"), "{all}");
    assert!(all.contains(" 206 Actual load value"), "{all}");
    assert!(!all.contains("position (status)"), "{all}");
    assert!(!all.contains("Target position"), "{all}");

    // By number: 206 alone.
    for _ in 0..4 {
        app.handle(key(KeyCode::Backspace));
    }
    typed(&mut app, "206");
    let all = text(&mut app, 80, 24);
    assert!(
        row_with(&all, "206 Actual load value").contains("› [ ]"),
        "{all}"
    );
    assert!(!all.contains("(status)"), "{all}");
    typed(&mut app, "9");
    assert!(text(&mut app, 80, 24).contains("nothing matches `2069`"));

    // Esc closes: the plot is back.
    app.handle(key(KeyCode::Esc));
    let all = text(&mut app, 80, 24);
    assert!(
        !all.contains("what to plot") && all.contains("position (raw)"),
        "{all}"
    );
}

#[test]
fn enter_in_the_picker_plots_a_parameter_with_its_poll_and_enter_again_stops_it() {
    let hand = Hand::new();
    let mut app = console("mono", &hand);
    a_move(&mut app, &hand);
    app.handle(key(KeyCode::Char('a')));
    typed(&mut app, "actual load");
    let added = app.handle(key(KeyCode::Enter));
    // Polled as `:plot add 0 206` has it polled.
    assert!(
        added.contains(&Effect::Watch {
            axis: 0,
            line: "GAP 206, 0".into(),
            on: true,
            fast: false
        }),
        "{added:?}"
    );
    let all = text(&mut app, 80, 24);
    assert!(all.contains("› [x]  206 Actual load value"), "{all}");
    assert!(
        all.contains("plotting motor 0 206 Actual load value"),
        "{all}"
    );

    let removed = app.handle(key(KeyCode::Enter));
    assert!(
        removed.contains(&Effect::Watch {
            axis: 0,
            line: "GAP 206, 0".into(),
            on: false,
            fast: false
        }),
        "{removed:?}"
    );
    let all = text(&mut app, 80, 24);
    assert!(
        row_with(&all, "206 Actual load value").contains("› [ ]"),
        "{all}"
    );

    // Added again, the picker closed: the legend names it.
    app.handle(key(KeyCode::Enter));
    app.handle(key(KeyCode::Esc));
    let mut load = at(4000, 0);
    load.status[0].watched = vec![axterm::session::WatchedValue {
        line: "GAP 206, 0".into(),
        value: Some(512),
        reply: Some(axterm::protocol::console::ReplyValue::Number(512)),
    }];
    app.handle(AppEvent::Snapshot(load));
    let all = text(&mut app, 80, 24);
    assert!(all.contains("motor 0 206 Actual load value"), "{all}");
}

#[test]
fn letters_typed_in_the_picker_filter_and_quit_nothing_in_the_vim_keymap() {
    let hand = Hand::new();
    let panes: Vec<Box<dyn Pane>> = vec![
        Box::new(AxesPane::new()),
        Box::new(PlotPane::with_clock(hand.clock())),
    ];
    let theme = Theme::builtin("dark").expect("theme");
    let keymap = Keymap::builtin("vim").expect("keymap");
    let mut app = App::new(panes, theme, keymap);
    app.focus("plot");
    a_move(&mut app, &hand);
    app.handle(key(KeyCode::Char('a')));
    let effects = typed(&mut app, "quick");
    assert!(!effects.contains(&Effect::Quit), "{effects:?}");
    assert!(text(&mut app, 80, 24).contains("filter: quick"));
    // Closed, q quits again.
    app.handle(key(KeyCode::Esc));
    assert!(app.handle(key(KeyCode::Char('q'))).contains(&Effect::Quit));
}

/// With mechanics in force a position chart is drawn in the axis's unit
/// (TMCL positions are microsteps, §4 AP1: 10240 a mm with these
/// mechanics); speeds, which need the pulse divisor the plot does not
/// read, stay raw.
#[test]
fn with_mechanics_positions_are_plotted_in_the_axis_unit() {
    let hand = Hand::new();
    let mut app = console("dark", &hand);
    let (mechanics, _) = axterm::protocol::units::MechanicsTable::parse_file(
        "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\nmicrosteps = 256\n\
         travel_per_rev = 5\n",
    )
    .expect("mechanics");
    let mechanics = Arc::new(mechanics);
    for step in 0..=8 {
        let mut s = at(step * 12_800, 1000);
        s.mechanics = Arc::clone(&mechanics);
        app.handle(AppEvent::Snapshot(s));
        hand.advance(Duration::from_millis(500));
    }
    let all = text(&mut app, 120, 40);
    assert!(all.contains("position (mm)"), "{all}");
    assert!(all.contains("speed (raw)"), "{all}");
    // 0 to 102400 µsteps is 0 to 10 mm: the axis spans about 11, not 107520.
    assert!(all.contains("11│") && !all.contains("107520"), "{all}");
}
