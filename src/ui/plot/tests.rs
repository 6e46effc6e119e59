use std::sync::Mutex;

use super::*;
use crate::device::LinkState;
use crate::ui::keymap::Keymap;
use crate::ui::theme::Theme;

fn snapshot_of(family: &'static crate::protocol::Family) -> Snapshot {
    Snapshot {
        family,
        address: 1,
        link_name: "sim".into(),
        axes: family.console.axes().to_vec(),
        status: vec![AxisStatus::default(); family.console.axes().len()],
        link: LinkState::Closed,
        identity: None,
        poll: None,
        settings: Default::default(),
        mechanics: Default::default(),
        axis: 0,
    }
}

/// The picker and `:plot add` offer the status values the family
/// reads and no others: MCCL reads no load (issue 19, point 9).
#[test]
fn only_the_status_values_a_family_reads_are_offered() {
    for family in crate::families::FAMILIES {
        let session = snapshot_of(family);
        let read = family.console.status_values();
        let offered: Vec<StatusValue> = plottable(&session, 0)
            .into_iter()
            .filter_map(|q| match q {
                Quantity::Status(v) => Some(v),
                Quantity::Parameter { .. } => None,
            })
            .collect();
        assert_eq!(offered, read, "{}", family.name);
        let first = session.axes.first().map_or(0, |a| a.number);
        for (name, value) in STATUS_VALUES {
            let added = find_quantity(&session, &format!("{first} {name}"));
            if read.contains(value) {
                assert!(added.is_ok(), "{}: {added:?}", family.name);
            } else {
                let error = added.expect_err(name);
                assert!(error.contains(&format!("report no {name}")), "{error}");
            }
        }
    }
    let mccl = crate::families::find_family("mccl").expect("mccl");
    assert!(!mccl.console.status_values().contains(&StatusValue::Load));
    let tmcl = crate::families::find_family("tmcl").expect("tmcl");
    assert!(tmcl.console.status_values().contains(&StatusValue::Load));
}

/// A plot pane on a hand-moved clock over a TMCL snapshot.
struct Bench {
    plot: PlotPane,
    now: Arc<Mutex<Instant>>,
    start: Instant,
    snapshot: Snapshot,
    theme: Theme,
    keymap: Keymap,
}

impl Bench {
    fn new() -> Bench {
        let start = Instant::now();
        let now = Arc::new(Mutex::new(start));
        let hand = now.clone();
        let family = crate::families::find_family("tmcl").expect("tmcl");
        Bench {
            plot: PlotPane::with_clock(Arc::new(move || {
                *hand.lock().unwrap_or_else(|e| e.into_inner())
            })),
            now,
            start,
            snapshot: Snapshot {
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
            },
            theme: Theme::builtin("dark").expect("theme"),
            keymap: Keymap::builtin("default").expect("keymap"),
        }
    }

    fn at(&mut self, ms: u64) {
        *self.now.lock().unwrap_or_else(|e| e.into_inner()) =
            self.start + Duration::from_millis(ms);
    }

    fn event(&mut self, event: PaneEvent) -> Vec<Request> {
        let view = View {
            theme: &self.theme,
            keymap: &self.keymap,
            session: Some(&self.snapshot),
            modules: &[],
            module: 0,
            focused: false,
            shown: true,
        };
        match self.plot.on_event(&event, &view) {
            Outcome::Handled(requests) => requests,
            Outcome::Ignored => Vec::new(),
        }
    }

    fn command(&mut self, args: &str) -> Vec<Request> {
        self.event(PaneEvent::Plot(args.into()))
    }

    /// The status changed at `ms`.
    fn reading(&mut self, ms: u64, change: impl FnOnce(&mut AxisStatus)) {
        self.at(ms);
        change(&mut self.snapshot.status[0]);
        self.event(PaneEvent::Snapshot);
    }

    fn screen(&mut self, width: u16, height: u16) -> String {
        let mut terminal =
            ratatui::Terminal::new(ratatui::backend::TestBackend::new(width, height))
                .expect("terminal");
        let view = View {
            theme: &self.theme,
            keymap: &self.keymap,
            session: Some(&self.snapshot),
            modules: &[],
            module: 0,
            focused: false,
            shown: true,
        };
        let plot = &mut self.plot;
        terminal
            .draw(|frame| plot.render(frame, frame.area(), &view))
            .expect("draw");
        let buffer = terminal.backend().buffer();
        (0..height)
            .map(|y| {
                (0..width)
                    .map(|x| buffer[(x, y)].symbol().to_string())
                    .collect::<String>()
            })
            .collect::<Vec<_>>()
            .join("\n")
    }
}

#[test]
fn the_window_steps_through_the_ladder_and_stops_at_its_ends() {
    let mut plot = PlotPane::new();
    assert_eq!(plot.window(), DEFAULT_WINDOW);
    plot.zoom(Action::PlotZoomIn);
    assert_eq!(plot.window(), Duration::from_secs(10));
    for _ in 0..20 {
        plot.zoom(Action::PlotZoomIn);
    }
    assert_eq!(plot.window(), Duration::from_secs(1));
    for _ in 0..20 {
        plot.zoom(Action::PlotZoomOut);
    }
    assert_eq!(plot.window(), Duration::from_secs(600));
    plot.zoom(Action::PlotZoomReset);
    assert_eq!(plot.window(), DEFAULT_WINDOW);
}

#[test]
fn values_are_held_as_steps_up_to_now() {
    let start = Instant::now();
    let mut plot = PlotPane::new();
    plot.window = Duration::from_secs(10);
    let samples: VecDeque<(Instant, i64)> = [(0, 5), (2, 7), (4, 9)]
        .into_iter()
        .map(|(s, v)| (start + Duration::from_secs(s), v))
        .collect();
    let now = start + Duration::from_secs(12);
    // The first sample fell out of the window: its value starts it.
    assert_eq!(
        plot.points(now, &samples),
        [
            (-10.0, 5.0),
            (-10.0, 5.0),
            (-10.0, 7.0),
            (-8.0, 7.0),
            (-8.0, 9.0),
            (0.0, 9.0)
        ]
    );
    assert!(plot.points(now, &VecDeque::new()).is_empty());
}

#[test]
fn until_series_are_picked_the_selected_axis_is_followed() {
    let mut bench = Bench::new();
    bench.reading(0, |s| s.position = Some(5));
    let axis = bench.snapshot.axes[0].name;
    assert_eq!(
        bench.plot.series_names(),
        [
            format!("{axis} position"),
            format!("{axis} target"),
            format!("{axis} speed")
        ]
    );
}

#[test]
fn several_series_are_drawn_with_a_legend() {
    let mut bench = Bench::new();
    let axis = bench.snapshot.axes[0].name;
    for value in ["position", "speed", "load", "6"] {
        bench.command(&format!("add 0 {value}"));
    }
    for (n, ms) in [0u64, 500, 1000, 1500].into_iter().enumerate() {
        let n = n as i64;
        bench.reading(ms, |s| {
            s.position = Some(1000 * n);
            s.speed = Some(300);
            s.load = Some(100 + n);
            s.watched = vec![crate::session::WatchedValue {
                line: "GAP 6, 0".into(),
                value: Some(128),
                reply: Some(crate::protocol::console::ReplyValue::Number(128)),
            }];
        });
    }
    let screen = bench.screen(120, 30);
    for name in bench.plot.series_names() {
        assert!(screen.contains(&name), "no {name} in the legend:\n{screen}");
    }
    assert_eq!(
        bench.plot.series_names()[3],
        format!("{axis} 6 Maximum current")
    );
    // Each series has its own marker in the legend.
    for glyph in ["⠒ ", "• ", "█ ", "▄ "] {
        assert!(screen.contains(glyph), "no marker {glyph}:\n{screen}");
    }
}

#[test]
fn a_parameter_series_is_polled_while_plotted() {
    let mut bench = Bench::new();
    let said = bench.command("add 0 206");
    assert!(
        said.contains(&Request::Watch {
            axis: 0,
            line: "GAP 206, 0".into(),
            on: true,
            fast: false
        }),
        "{said:?}"
    );
    let said = bench.command("remove 0 206");
    assert!(said.contains(&Request::Watch {
        axis: 0,
        line: "GAP 206, 0".into(),
        on: false,
        fast: false
    }));
    bench.command("add 0 206");
    let said = bench.command("clear");
    assert!(said.contains(&Request::Watch {
        axis: 0,
        line: "GAP 206, 0".into(),
        on: false,
        fast: false
    }));
    assert!(bench.plot.series_names().is_empty());
}

#[test]
fn what_cannot_be_plotted_is_said() {
    let mut bench = Bench::new();
    for (args, expected) in [
        ("add 9 position", "no axis `9`"),
        ("add 0 banana", "`banana` is none of position"),
        ("add 0", "which axis and value?"),
        ("csv", "needs a file name"),
        ("frobnicate", "no `:plot frobnicate`"),
    ] {
        let said = bench.command(args);
        let Some(Request::Say(notice)) = said.first() else {
            panic!("{args}: {said:?}");
        };
        assert!(notice.text.contains(expected), "{args}: {}", notice.text);
    }
}

#[test]
fn the_csv_holds_every_moment_a_value_changed_one_column_per_series() {
    let mut bench = Bench::new();
    let axis = bench.snapshot.axes[0].name;
    bench.command("add 0 position");
    bench.command("add 0 load");
    bench.reading(0, |s| s.position = Some(0));
    bench.reading(250, |s| {
        s.position = Some(100);
        s.load = Some(7);
    });
    bench.reading(500, |s| s.load = Some(9));
    bench.reading(1250, |s| s.position = Some(-20));
    let dir = tempfile::tempdir().expect("dir");
    let file = dir.path().join("plot.csv");
    bench.command(&format!("csv {}", file.display()));
    let written = std::fs::read_to_string(&file).expect("written");
    assert_eq!(
        written,
        format!(
            "time_s,{axis} position,{axis} load\n\
             0.000,0,\n\
             0.250,100,7\n\
             0.500,100,9\n\
             1.250,-20,9\n"
        )
    );
}
