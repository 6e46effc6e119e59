use super::*;

#[test]
fn a_name_of_two_forms_gives_its_first_when_short_of_room() {
    assert_eq!(short_name("m0/Motor1", 4), "m0");
    assert_eq!(short_name("m0/Motor1", 9), "m0/Motor1");
    assert_eq!(short_name("motor 0", 4), "moto");
    assert_eq!(short_name("X", 4), "X");
}

#[test]
fn the_ramp_follows_the_speed() {
    assert_eq!(Ramp::from_speeds(None, None, None), Ramp::Unknown);
    assert_eq!(
        Ramp::from_speeds(Some(5), Some(0), Some(100)),
        Ramp::Standing
    );
    assert_eq!(
        Ramp::from_speeds(Some(5), Some(50), Some(100)),
        Ramp::Accelerating
    );
    assert_eq!(
        Ramp::from_speeds(Some(-5), Some(-50), Some(100)),
        Ramp::Accelerating
    );
    assert_eq!(
        Ramp::from_speeds(Some(100), Some(100), Some(100)),
        Ramp::Cruising
    );
    assert_eq!(
        Ramp::from_speeds(Some(60), Some(60), Some(100)),
        Ramp::Constant
    );
    assert_eq!(
        Ramp::from_speeds(Some(60), Some(20), Some(100)),
        Ramp::Decelerating
    );
}

#[test]
fn a_phase_the_module_reports_wins_over_the_speed_trend() {
    use MotionPhase::*;
    assert_eq!(
        Ramp::from_phase(Standing, Some(5), Some(100)),
        Ramp::Standing
    );
    assert_eq!(
        Ramp::from_phase(Accelerating, Some(100), Some(100)),
        Ramp::Accelerating
    );
    assert_eq!(
        Ramp::from_phase(Decelerating, None, None),
        Ramp::Decelerating
    );
    assert_eq!(
        Ramp::from_phase(Constant, Some(-100), Some(100)),
        Ramp::Cruising
    );
    assert_eq!(
        Ramp::from_phase(Constant, Some(60), Some(100)),
        Ramp::Constant
    );
    assert_eq!(Ramp::from_phase(Constant, None, Some(100)), Ramp::Constant);
    let pane = AxesPane::new();
    let status = AxisStatus {
        speed: Some(10),
        max_speed: Some(100),
        phase: Some(Decelerating),
        ..AxisStatus::default()
    };
    assert_eq!(
        pane.ramp(0, &status),
        Ramp::Decelerating,
        "speed rose from nothing"
    );
}

#[test]
fn a_speed_read_again_while_ramping_keeps_the_trend_until_it_is_steady() {
    let mut pane = AxesPane::new();
    let family = crate::families::find_family("tmcl").expect("tmcl");
    let mut snapshot = Snapshot {
        family,
        address: 1,
        link_name: "sim".into(),
        axes: family.console.axes().to_vec(),
        status: vec![AxisStatus::default()],
        link: LinkState::Closed,
        identity: None,
        poll: None,
        settings: Default::default(),
        mechanics: Default::default(),
        axis: 0,
    };
    let mut step = |speed: i64, pane: &mut AxesPane| {
        snapshot.status[0].speed = Some(speed);
        snapshot.status[0].max_speed = Some(1000);
        pane.remember(&snapshot);
        pane.ramp(0, &snapshot.status[0])
    };
    assert_eq!(step(100, &mut pane), Ramp::Accelerating);
    // The position was read: same speed, still accelerating.
    assert_eq!(step(100, &mut pane), Ramp::Accelerating);
    assert_eq!(step(300, &mut pane), Ramp::Accelerating);
    assert_eq!(step(1000, &mut pane), Ramp::Accelerating);
    assert_eq!(step(1000, &mut pane), Ramp::Cruising);
    assert_eq!(step(600, &mut pane), Ramp::Decelerating);
    for _ in 0..STEADY_SNAPSHOTS - 1 {
        assert_eq!(step(600, &mut pane), Ramp::Decelerating);
    }
    assert_eq!(step(600, &mut pane), Ramp::Constant);
    assert_eq!(step(0, &mut pane), Ramp::Standing);
}

#[test]
fn gauges_fill_to_their_fraction_and_mark_the_target() {
    let theme = Theme::builtin("dark").expect("built-in theme");
    let text = |spans: Vec<Span>| {
        spans
            .iter()
            .map(|s| s.content.to_string())
            .collect::<String>()
    };
    assert_eq!(text(gauge(&theme, Some(0.5), None, 10)), "█████░░░░░");
    assert_eq!(text(gauge(&theme, Some(0.0), Some(1.0), 5)), "░░░░┃");
    assert_eq!(text(gauge(&theme, None, None, 3)), "···");
    assert_eq!(fraction(5, 0, 10), 0.5);
    assert_eq!(fraction(5, 5, 5), 0.0);
    assert_eq!(fraction(i64::MIN, i64::MIN, i64::MAX), 0.0);
}

#[test]
fn another_modules_numbers_are_drawn_at_the_readable_rate_too() {
    let mut drawn = Drawn::new();
    let other = Snapshot {
        address: 2,
        ..drawn.snapshot.clone()
    };
    let mut modules = vec![
        ModuleEntry {
            link: 0,
            snapshot: drawn.snapshot.clone(),
        },
        ModuleEntry {
            link: 0,
            snapshot: other,
        },
    ];
    let theme = drawn.theme.clone();
    let keymap = drawn.keymap.clone();
    let session = drawn.snapshot.clone();
    let changed = |pane: &mut AxesPane, modules: &[ModuleEntry], event: PaneEvent| {
        let view = View {
            theme: &theme,
            keymap: &keymap,
            session: Some(&session),
            modules,
            module: 0,
            focused: false,
            shown: true,
        };
        pane.on_event(&event, &view)
    };
    let position = |pane: &AxesPane, modules: &[ModuleEntry]| {
        pane.module_status(1, &modules[1].snapshot)[0].position
    };
    // The first status of module 2 is drawn at once.
    assert_eq!(
        changed(&mut drawn.pane, &modules, PaneEvent::ModuleChanged(1)),
        Outcome::redraw()
    );
    // A position 50 ms later waits for its turn, with a wake-up.
    drawn.later(50);
    modules[1].snapshot.status[0].position = Some(10);
    let Outcome::Handled(asked) = changed(&mut drawn.pane, &modules, PaneEvent::ModuleChanged(1))
    else {
        panic!("a wake-up asked for");
    };
    let [Request::WakeAfter { after, tag }] = asked.as_slice() else {
        panic!("{asked:?}");
    };
    assert_eq!(*after, super::super::readable::READABLE_PERIOD / 4 * 3);
    assert_eq!(position(&drawn.pane, &modules), Some(0), "held back");
    // A lamp is no number: it goes through at once, numbers with it.
    modules[1].snapshot.status[0].left_switch = Some(true);
    assert_eq!(
        changed(&mut drawn.pane, &modules, PaneEvent::ModuleChanged(1)),
        Outcome::redraw()
    );
    assert_eq!(position(&drawn.pane, &modules), Some(10));
    // The wake-up draws what is newest.
    modules[1].snapshot.status[0].position = Some(20);
    assert_eq!(
        changed(&mut drawn.pane, &modules, PaneEvent::ModuleChanged(1)),
        Outcome::Ignored,
        "a wake-up is already asked for"
    );
    drawn.later(200);
    changed(&mut drawn.pane, &modules, PaneEvent::Wake { tag: *tag });
    assert_eq!(position(&drawn.pane, &modules), Some(20));
}

/// A pane on a hand-moved clock, a TMCL snapshot and a way to draw
/// it: the screen as cells.
struct Drawn {
    pane: AxesPane,
    now: std::sync::Arc<std::sync::Mutex<std::time::Instant>>,
    snapshot: Snapshot,
    theme: Theme,
    keymap: super::super::keymap::Keymap,
}

impl Drawn {
    fn new() -> Drawn {
        let now = std::sync::Arc::new(std::sync::Mutex::new(std::time::Instant::now()));
        let hand = now.clone();
        let clock = PaneClock(std::sync::Arc::new(move || {
            *hand.lock().unwrap_or_else(|e| e.into_inner())
        }));
        let family = crate::families::find_family("tmcl").expect("tmcl");
        let status = AxisStatus {
            position: Some(0),
            target: Some(51_200),
            speed: Some(0),
            max_speed: Some(1000),
            left_switch: Some(false),
            ..AxisStatus::default()
        };
        Drawn {
            pane: AxesPane::with_clock(clock),
            now,
            snapshot: Snapshot {
                family,
                address: 1,
                link_name: "sim".into(),
                axes: family.console.axes().to_vec(),
                status: vec![status],
                link: LinkState::Closed,
                identity: None,
                poll: None,
                settings: Default::default(),
                mechanics: Default::default(),
                axis: 0,
            },
            theme: Theme::builtin("dark").expect("dark"),
            keymap: super::super::keymap::Keymap::builtin("default").expect("keymap"),
        }
    }

    fn later(&mut self, ms: u64) {
        let mut now = self.now.lock().unwrap_or_else(|e| e.into_inner());
        *now += std::time::Duration::from_millis(ms);
    }

    /// The snapshot changed: what the pane asks for.
    fn snapshot_changed(&mut self) -> Vec<Request> {
        let view = View {
            theme: &self.theme,
            keymap: &self.keymap,
            session: Some(&self.snapshot),
            modules: &[],
            module: 0,
            focused: false,
            shown: true,
        };
        match self.pane.on_event(&PaneEvent::Snapshot, &view) {
            Outcome::Handled(requests) => requests,
            Outcome::Ignored => Vec::new(),
        }
    }

    fn woken(&mut self, tag: u64) -> Vec<Request> {
        let view = View {
            theme: &self.theme,
            keymap: &self.keymap,
            session: Some(&self.snapshot),
            modules: &[],
            module: 0,
            focused: false,
            shown: true,
        };
        match self.pane.on_event(&PaneEvent::Wake { tag }, &view) {
            Outcome::Handled(requests) => requests,
            Outcome::Ignored => Vec::new(),
        }
    }

    fn draw(&mut self) -> ratatui::buffer::Buffer {
        let mut terminal =
            ratatui::Terminal::new(ratatui::backend::TestBackend::new(100, 3)).expect("term");
        let view = View {
            theme: &self.theme,
            keymap: &self.keymap,
            session: Some(&self.snapshot),
            modules: &[],
            module: 0,
            focused: false,
            shown: true,
        };
        let pane = &mut self.pane;
        terminal
            .draw(|frame| pane.render(frame, frame.area(), &view))
            .expect("draw");
        terminal.backend().buffer().clone()
    }
}

/// Whether only the first row differs.
fn only_the_first_row_differs(a: &ratatui::buffer::Buffer, b: &ratatui::buffer::Buffer) -> bool {
    a.diff(b).iter().all(|(_, y, _)| *y == 0)
}

/// The columns of the cells that differ between two screens.
fn changed(before: &ratatui::buffer::Buffer, after: &ratatui::buffer::Buffer) -> Vec<u16> {
    before.diff(after).into_iter().map(|(x, _, _)| x).collect()
}

#[test]
fn a_position_moved_within_the_readable_period_and_a_gauge_cell_changes_no_cell() {
    let mut drawn = Drawn::new();
    assert!(drawn.snapshot_changed().is_empty(), "the first is shown");
    let first = drawn.draw();
    // 50 ms later (the next 20 Hz poll) the axis moved 10 of 51200
    // counts: less than a cell of the gauge, and too soon to change
    // the digits.
    drawn.later(50);
    drawn.snapshot.status[0].position = Some(10);
    let asked = drawn.snapshot_changed();
    let [Request::WakeAfter { after, tag }] = asked.as_slice() else {
        panic!("a wake-up for the held digits, not {asked:?}");
    };
    assert_eq!(*after, super::super::readable::READABLE_PERIOD / 4 * 3);
    assert_eq!(changed(&first, &drawn.draw()), [] as [u16; 0]);
    // Another poll before the wake-up asks for no second one.
    drawn.later(50);
    drawn.snapshot.status[0].position = Some(20);
    assert!(drawn.snapshot_changed().is_empty());
    assert_eq!(changed(&first, &drawn.draw()), [] as [u16; 0]);
    // At the wake-up the newest position is drawn: its digits change,
    // the gauge does not.
    drawn.later(100);
    assert!(drawn.woken(*tag).is_empty());
    let after = drawn.draw();
    let columns = changed(&first, &after);
    assert!(!columns.is_empty());
    // The position's field: right-aligned after "pos ", before the
    // gauge (11 columns wide for TMCL's numbers).
    let row: Vec<&str> = (0..100u16).map(|x| after[(x, 0)].symbol()).collect();
    let pos = row
        .windows(4)
        .position(|w| w.concat() == "pos ")
        .expect("pos label") as u16
        + 4;
    assert_eq!(
        row[usize::from(pos) + 9..usize::from(pos) + 11].concat(),
        "20"
    );
    assert!(
        columns.iter().all(|x| (pos..pos + 11).contains(x)),
        "only the position's digits changed: {columns:?}"
    );
    assert!(only_the_first_row_differs(&first, &after));
}

#[test]
fn a_lamp_is_drawn_at_once_with_the_numbers_of_that_moment() {
    let mut drawn = Drawn::new();
    drawn.snapshot_changed();
    drawn.later(10);
    drawn.snapshot.status[0].position = Some(3000);
    assert_eq!(drawn.snapshot_changed().len(), 1, "the digits wait");
    drawn.later(10);
    drawn.snapshot.status[0].left_switch = Some(true);
    drawn.snapshot.status[0].position = Some(3100);
    drawn.snapshot_changed();
    let shown = drawn.pane.drawn_status(0, &drawn.snapshot);
    assert_eq!(shown.left_switch, Some(true));
    assert_eq!(shown.position, Some(3100));
}

#[test]
fn the_position_gauge_keeps_still_while_the_digits_wait_in_velocity_mode() {
    // ROR: no target, the position runs away from everything seen, so
    // the gauge's range grows with it.
    let mut drawn = Drawn::new();
    drawn.snapshot.status[0].target = None;
    drawn.snapshot.status[0].position = Some(1000);
    drawn.snapshot_changed();
    let first = drawn.draw();
    for position in [1100, 1200, 1300] {
        drawn.later(50);
        drawn.snapshot.status[0].position = Some(position);
        drawn.snapshot_changed();
        assert_eq!(changed(&first, &drawn.draw()), [] as [u16; 0]);
    }
}
