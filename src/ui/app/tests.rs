use super::*;
use crate::device::LinkState;
use crate::session::AxisStatus;
use crate::ui::pane::Region;
use ratatui::Frame;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use ratatui::crossterm::event::{KeyCode, KeyEventState, KeyModifiers};
use ratatui::widgets::Paragraph;
use tokio::sync::mpsc;

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
    let family = crate::families::find_family("tmcl").expect("tmcl");
    Snapshot {
        family,
        address: 1,
        link_name: "sim tmcm1110".into(),
        axes: family.console.axes().to_vec(),
        status: vec![AxisStatus::default()],
        link: LinkState::Connected { link: "sim".into() },
        identity: None,
        poll: Some(PollCadence::default()),
        settings: Default::default(),
        mechanics: Default::default(),
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

/// The stop's answers as the session gives them: `n` lines, all ok.
fn stopped(n: usize) -> AppEvent {
    let ok = || {
        Ok(LineResult {
            line: "MST 0".into(),
            request: Vec::new(),
            reply: vec![2, 1, 100],
            status: Some(100),
            value: crate::session::ReplyValue::None,
            elapsed: Duration::ZERO,
            attempts: 1,
        })
    };
    AppEvent::Stopped((0..n).map(|_| ok()).collect())
}

#[test]
fn a_stop_message_ages_out_and_the_quit_and_help_keys_never_fall_off() {
    let mut app = three();
    let mut long = snapshot();
    long.link_name = "/dev/serial/by-id/usb-FTDI_FT232R_USB_UART_A50285BI-if00-port0".into();
    app.handle(AppEvent::Snapshot(long));
    let effects = app.handle(stopped(3));
    let status = screen(&mut app, 80, 24).pop().unwrap_or_default();
    assert!(status.starts_with(" F12 STOP "), "{status}");
    assert!(status.contains("STOP: 3 sent, all ok"), "{status}");
    assert!(status.trim_end().ends_with("F10 quit F1 help"), "{status}");
    // The loop comes back after the lifetime: the message is gone and
    // the link's state shows again.
    let id = effects
        .iter()
        .find_map(|e| match e {
            Effect::Expire { id, after } => {
                assert_eq!(*after, STATUS_MESSAGE_LIFETIME);
                Some(*id)
            }
            _ => None,
        })
        .expect("the message asks to age out");
    app.handle(AppEvent::Expired(id));
    assert!(app.needs_redraw());
    let status = screen(&mut app, 80, 24).pop().unwrap_or_default();
    assert!(!status.contains("STOP: 3"), "{status}");
    assert!(status.contains("/dev/serial/by-id/"), "{status}");
    assert!(status.trim_end().ends_with("F10 quit F1 help"), "{status}");
    // An older message's timer does not take a newer one away.
    app.handle(stopped(2));
    app.handle(AppEvent::Expired(id));
    let status = screen(&mut app, 80, 24).pop().unwrap_or_default();
    assert!(status.contains("STOP: 2 sent, all ok"), "{status}");
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
    use crate::protocol::program::Phase;
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
