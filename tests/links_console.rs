//! Several links in one console: the console's own loop on two in-process
//! simulators (TMCM-1110 and CMD-4CR, 9600 Bd wire time each, on tokio's
//! paused clock), drawing into a `TestBackend`. The axes pane groups the
//! modules by link and scrolls at 80×24; `:module N` sends lines to that
//! module's link only; the emergency-stop key queues every link's stop
//! lines before any link answers one.

mod ui_support;

use std::sync::Arc;

use axterm::device::{Direction, Priority, TrafficKind, TrafficRecord};
use axterm::ui::app::Controller;
use ratatui::crossterm::event::KeyCode;
use tokio::sync::broadcast;
use ui_support::looped::{Rig, no_connector, press, run_links_on, type_line};
use ui_support::{console_with, sim_controller};

/// The console with the command pane focused.
fn console() -> axterm::ui::app::App {
    let mut app = console_with(&axterm::ui::PaneSetup::default());
    app.focus("command");
    app
}

/// Both simulators, each on a link of its own.
async fn two_links() -> (Arc<dyn Controller>, Arc<dyn Controller>) {
    (
        sim_controller("tmcm1110", 9600).await,
        sim_controller("cmd4cr", 9600).await,
    )
}

/// Every record waiting in `traffic` (records missed by lagging skipped).
fn drain(traffic: &mut broadcast::Receiver<TrafficRecord>) -> Vec<TrafficRecord> {
    let mut records = Vec::new();
    loop {
        match traffic.try_recv() {
            Ok(record) => records.push(record),
            Err(broadcast::error::TryRecvError::Lagged(_)) => {}
            Err(_) => return records,
        }
    }
}

fn user_requests(records: &[TrafficRecord]) -> Vec<String> {
    records
        .iter()
        .filter(|r| r.direction == Direction::Sent && r.kind == TrafficKind::Request)
        .filter(|r| r.priority == Some(Priority::User))
        .map(|r| String::from_utf8_lossy(&r.bytes).into_owned())
        .collect()
}

/// The rows of the frame's axes pane (between its top border and the
/// first border below it).
fn axes_rows(frame: &str) -> Vec<&str> {
    frame
        .lines()
        .skip(1)
        .take_while(|l| !l.starts_with('└'))
        .collect()
}

/// The console on a link to each simulator of `kinds` at `size`: the
/// first frame with every link polled, and the frame after the last
/// module's axis U was selected.
async fn grouped_at(kinds: &[&str], size: (u16, u16)) -> (String, String) {
    let mut links = Vec::new();
    for kind in kinds {
        links.push(vec![sim_controller(kind, 9600).await]);
    }
    let mut frames = (String::new(), String::new());
    let shown = &mut frames;
    run_links_on(
        console(),
        size,
        links,
        no_connector(),
        async |mut rig: Rig| {
            shown.0 = rig
                .screens
                .until_frame("the first two links polled", |f| {
                    f.contains("link 1 sim tmcm1110 at 9600 Bd · connected · poll 20 Hz → ")
                        && f.contains("link 2 sim cmd4cr at 9600 Bd · connected · poll 20 Hz → ")
                })
                .await;
            // The last axis of the last module: the list scrolls to it.
            type_line(&rig, &format!(":module {}", kinds.len()));
            type_line(&rig, ":axis U");
            shown.1 = rig
                .screens
                .until_frame("U selected", |f| f.contains(" ▶U "))
                .await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
    frames
}

#[tokio::test(start_paused = true)]
async fn a_wide_screen_lists_every_module_grouped_by_link() {
    let (first, _) = grouped_at(&["tmcm1110", "cmd4cr"], (120, 40)).await;
    let rows = axes_rows(&first);
    let text: Vec<String> = rows
        .iter()
        .map(|r| r.trim_matches('│').trim_end().to_string())
        .collect();
    assert!(
        text[0].starts_with("link 1 sim tmcm1110 at 9600 Bd · connected"),
        "{first}"
    );
    assert!(text[1].starts_with("▶module 1 tmcl #1"), "{first}");
    // Positions in their fixed-width column.
    assert!(
        text[2].starts_with(" ▶motor 0 ") && text[2].contains(" 0→0 "),
        "{first}"
    );
    assert!(
        text[3].starts_with("link 2 sim cmd4cr at 9600 Bd · connected"),
        "{first}"
    );
    assert!(text[4].starts_with(" module 2 cmd4cr #1"), "{first}");
    for (row, axis) in text[5..9].iter().zip(["X", "Y", "Z", "U"]) {
        assert!(row.starts_with(&format!("  {axis} ")), "{row}\n{first}");
    }
    assert!(
        first.contains("Axes — 2 modules on 2 links, module 1 selected"),
        "{first}"
    );
    assert!(
        first.contains("module 1/2 sim tmcm1110 at 9600 Bd #1 connected"),
        "the status bar names the module lines go to:\n{first}"
    );
}

#[tokio::test(start_paused = true)]
async fn at_80x24_the_list_scrolls_to_the_selected_module_and_axis() {
    // Two links fit: a heading each, a module line each, five axes.
    let (first, _) = grouped_at(&["tmcm1110", "cmd4cr"], (80, 24)).await;
    let rows = axes_rows(&first);
    assert_eq!(rows.len(), 9, "{first}");
    assert!(rows[0].contains("link 1 sim tmcm1110"), "{first}");
    assert!(
        rows[8].trim_start_matches('│').starts_with("  U "),
        "{first}"
    );
    // Three do not: the list scrolls to keep the selected axis in view.
    let (first, selected) = grouped_at(&["tmcm1110", "cmd4cr", "cmd4cr"], (80, 24)).await;
    let rows = axes_rows(&first);
    assert!(rows[0].contains("link 1 sim tmcm1110"), "{first}");
    let rows = axes_rows(&selected);
    let last = rows.last().expect("rows");
    assert!(
        last.trim_start_matches('│').starts_with(" ▶U "),
        "the selected axis is in view:\n{selected}"
    );
    assert!(
        !selected.contains("link 1 sim tmcm1110 ·"),
        "scrolled past the first link:\n{selected}"
    );
    assert!(
        selected.contains("Command → module 3 (sim cmd4cr at 9600 Bd #1)"),
        "{selected}"
    );
    assert!(selected.contains("module 3/3 sim cmd4cr"), "{selected}");
}

#[tokio::test(start_paused = true)]
async fn a_line_typed_after_module_2_goes_to_the_second_link_only() {
    let (tmcl, cmd4cr) = two_links().await;
    let mut tmcl_traffic = tmcl.traffic().expect("traffic");
    let mut cmd4cr_traffic = cmd4cr.traffic().expect("traffic");
    run_links_on(
        console(),
        (100, 30),
        vec![vec![tmcl], vec![cmd4cr]],
        no_connector(),
        async |mut rig: Rig| {
            rig.screens.until("module 2 cmd4cr #1").await;
            type_line(&rig, "GAP 1, 0");
            rig.screens.until("got 02 01 64 06").await;
            type_line(&rig, ":module 2");
            rig.screens
                .until("lines go to module 2: sim cmd4cr at 9600 Bd #1")
                .await;
            type_line(&rig, "PX");
            rig.screens.until("sent @01PX\\r  got 0").await;
            type_line(&rig, ":module 1");
            type_line(&rig, ":module 3");
            rig.screens
                .until(":module needs a module number 1..2 (`:module` lists them), not `3`")
                .await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
    let tmcl_lines = user_requests(&drain(&mut tmcl_traffic));
    let cmd4cr_lines = user_requests(&drain(&mut cmd4cr_traffic));
    assert_eq!(cmd4cr_lines, ["@01PX\r"], "{tmcl_lines:?}");
    assert_eq!(tmcl_lines.len(), 1, "GAP 1, 0 only: {tmcl_lines:?}");
}

#[tokio::test(start_paused = true)]
async fn the_stop_key_queues_every_links_stop_before_any_link_answers_one() {
    let (tmcl, cmd4cr) = two_links().await;
    let mut tmcl_traffic = tmcl.traffic().expect("traffic");
    let mut cmd4cr_traffic = cmd4cr.traffic().expect("traffic");
    run_links_on(
        console(),
        (100, 30),
        vec![vec![tmcl], vec![cmd4cr]],
        no_connector(),
        async |mut rig: Rig| {
            rig.screens.until("module 2 cmd4cr #1").await;
            // No poll on either wire when the key comes: a line answered
            // on each link after polling is off.
            type_line(&rig, ":poll 0");
            type_line(&rig, "ROR 0, 500");
            rig.screens.until("got 02 01 64 01").await;
            type_line(&rig, ":module 2");
            type_line(&rig, "JX+");
            rig.screens.until("sent @01JX+\\r  got OK").await;
            press(&rig, KeyCode::F(12));
            rig.screens.until("STOP: 9 sent, all ok").await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
    let stops = |records: Vec<TrafficRecord>| {
        let stop: Vec<TrafficRecord> = records
            .into_iter()
            .filter(|r| r.priority == Some(Priority::EmergencyStop))
            .collect();
        let sent = stop
            .iter()
            .find(|r| r.direction == Direction::Sent)
            .map(|r| r.at)
            .expect("a stop line sent");
        let answered = stop
            .iter()
            .find(|r| r.direction == Direction::Received)
            .map(|r| r.at)
            .expect("a stop line answered");
        (stop, sent, answered)
    };
    let (tmcl_stop, tmcl_sent, tmcl_answered) = stops(drain(&mut tmcl_traffic));
    let (cmd4cr_stop, cmd4cr_sent, cmd4cr_answered) = stops(drain(&mut cmd4cr_traffic));
    // Each link's first stop line went out before the other link had an
    // answer to its own: neither waited for the other.
    assert!(
        tmcl_sent < cmd4cr_answered,
        "{tmcl_stop:?}\n{cmd4cr_stop:?}"
    );
    assert!(
        cmd4cr_sent < tmcl_answered,
        "{tmcl_stop:?}\n{cmd4cr_stop:?}"
    );
    // TMCL: MST 0, STOPAPP, MST 0; CMD-4CR: ESTOP, SACTRL0..3=0, ESTOP.
    let sent = |stop: &[TrafficRecord]| {
        stop.iter()
            .filter(|r| r.direction == Direction::Sent)
            .count()
    };
    assert_eq!((sent(&tmcl_stop), sent(&cmd4cr_stop)), (3, 6));
}

#[tokio::test(start_paused = true)]
async fn the_traffic_monitor_names_each_frames_link_and_filters_by_link() {
    let (tmcl, cmd4cr) = two_links().await;
    run_links_on(
        console(),
        (100, 30),
        vec![vec![tmcl], vec![cmd4cr]],
        no_connector(),
        async |mut rig: Rig| {
            rig.screens.until("module 2 cmd4cr #1").await;
            // Every link's polls, each row with its link, each put into
            // words by its own family.
            ui_support::looped::press_with(
                &rig,
                KeyCode::Char('4'),
                ratatui::crossterm::event::KeyModifiers::ALT,
            );
            let both = rig
                .screens
                .until_frame("both links' frames", |f| {
                    f.contains(" L1 → ") && f.contains(" L2 → ") && f.contains("f link")
                })
                .await;
            assert!(both.contains("GAP"), "TMCL words on link 1:\n{both}");
            assert!(both.contains("@01"), "CMD-4CR bytes on link 2:\n{both}");
            // The filter key: link 1 only, then link 2 only, then all.
            press(&rig, KeyCode::Char('f'));
            let first = rig.screens.until("link 1 only").await;
            assert!(!first.contains(" L2 "), "{first}");
            press(&rig, KeyCode::Char('f'));
            let second = rig
                .screens
                .until_frame("link 2 only", |f| {
                    f.contains("link 2 only") && f.contains(" L2 ")
                })
                .await;
            assert!(!second.contains(" L1 "), "{second}");
            press(&rig, KeyCode::Char('f'));
            rig.screens
                .until_frame("every link again", |f| {
                    !f.contains(" only ·") && f.contains(" L1 ") && f.contains(" L2 ")
                })
                .await;
            // And from the command pane.
            ui_support::looped::press_with(
                &rig,
                KeyCode::Char('1'),
                ratatui::crossterm::event::KeyModifiers::ALT,
            );
            type_line(&rig, ":traffic 2");
            ui_support::looped::press_with(
                &rig,
                KeyCode::Char('4'),
                ratatui::crossterm::event::KeyModifiers::ALT,
            );
            let chosen = rig.screens.until("link 2 only").await;
            assert!(!chosen.contains(" L1 "), "{chosen}");
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
}

#[tokio::test(start_paused = true)]
async fn the_connect_screen_adds_a_link_beside_the_one_open() {
    let tmcl = sim_controller("tmcm1110", 9600).await;
    // Opens the simulator the connect screen asks for (`--sim KIND ...`).
    let connector: axterm::ui::app::Connector = Box::new(|args: Vec<String>| {
        Box::pin(async move {
            let kind = args
                .iter()
                .position(|a| a == "--sim")
                .and_then(|at| args.get(at + 1))
                .cloned()
                .ok_or_else(|| format!("no --sim in {args:?}"))?;
            Ok(sim_controller(&kind, 9600).await)
        })
    });
    run_links_on(
        console(),
        (100, 30),
        vec![vec![tmcl]],
        connector,
        async |mut rig: Rig| {
            rig.screens.until("poll 20 Hz → ").await;
            ui_support::looped::press_with(
                &rig,
                KeyCode::Char('6'),
                ratatui::crossterm::event::KeyModifiers::ALT,
            );
            rig.screens.until("Enter connect · + add a link").await;
            // Down to the CMD-4CR simulator, then +.
            for _ in 0..10 {
                press(&rig, KeyCode::Down);
            }
            for _ in 0..10 {
                press(&rig, KeyCode::Up);
            }
            press(&rig, KeyCode::Down);
            let chosen = rig.screens.until("▶ sim cmd4cr").await;
            assert!(chosen.contains("▶ sim cmd4cr"), "{chosen}");
            press(&rig, KeyCode::Char('+'));
            let added = rig
                .screens
                .until_frame("the second link listed", |f| {
                    f.contains("link 2 sim cmd4cr at 9600 Bd") && f.contains("link added")
                })
                .await;
            assert!(added.contains("link 1 sim tmcm1110 at 9600 Bd"), "{added}");
            assert!(
                added.contains("module 1/2 sim tmcm1110"),
                "still module 1:\n{added}"
            );
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
}

/// The four modules of a simulated TMCM-1110 bus (`--sim tmcm1110
/// --address 1-4`, 9600 Bd), as the console opens them: the first
/// module's controller and the others on its link.
async fn tmcl_bus() -> Vec<Arc<dyn Controller>> {
    use axterm::cli::ConnectionArgs;
    use axterm::cli::connection::Target;
    let target = Target::resolve_modules(&ConnectionArgs {
        sim: Some("tmcm1110".into()),
        baud: Some(9600),
        address: Some("1-4".parse().expect("a list")),
        ..ConnectionArgs::default()
    })
    .expect("a simulated bus");
    let session = target.open().await.expect("the bus opens");
    let first: Arc<dyn Controller> = Arc::new(
        axterm::ui::live::SessionController::new(
            session,
            target.spec.describe(),
            target.options.clone(),
        )
        .with_other_modules(target.addresses[1..].to_vec()),
    );
    std::iter::once(Arc::clone(&first))
        .chain(first.other_modules())
        .collect()
}

/// The position shown in module `module`'s motor row.
fn bus_position(frame: &str, module: usize) -> Option<i64> {
    let mut lines = frame.lines();
    lines.find(|l| l.contains(&format!("module {module} tmcl #{module}")))?;
    let row = lines.next()?;
    let words: Vec<&str> = row.split_whitespace().collect();
    let at = words.iter().position(|w| *w == "0")?;
    words.get(at + 1)?.split('→').next()?.parse().ok()
}

#[tokio::test(start_paused = true)]
async fn four_modules_of_one_simulated_bus_are_each_polled_listed_and_stopped() {
    let bus = tmcl_bus().await;
    assert_eq!(bus.len(), 4);
    let mut traffic = bus[0].traffic().expect("traffic");
    run_links_on(
        console(),
        (100, 30),
        vec![bus],
        no_connector(),
        async |mut rig: Rig| {
            let first = rig
                .screens
                .until_frame("every module polled", |f| {
                    (1..=4).all(|m| bus_position(f, m) == Some(0))
                })
                .await;
            assert!(first.contains("link 1 sim tmcm1110 at 9600 Bd"), "{first}");
            assert!(
                first.contains("Axes — 4 modules on one link, module 1 selected"),
                "{first}"
            );
            // Module 3 alone turns, and its polls go on showing it.
            type_line(&rig, ":module 3");
            type_line(&rig, "ROR 0, 500");
            let moving = rig
                .screens
                .until_frame("module 3 turning", |f| {
                    bus_position(f, 3).is_some_and(|p| p > 1000)
                })
                .await;
            for module in [1, 2, 4] {
                assert_eq!(bus_position(&moving, module), Some(0), "{moving}");
            }
            // The lines went to address 3: the TMCL frame starts with it.
            assert!(moving.contains("sent 03 01 00 00 00 00 01 F4"), "{moving}");
            press(&rig, KeyCode::F(12));
            // MST 0, STOPAPP, MST 0 to each of the four modules.
            rig.screens.until("STOP: 12 sent, all ok").await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
    // Every module was polled on the one link, at its own address.
    let polled: std::collections::BTreeSet<u8> = drain(&mut traffic)
        .iter()
        .filter(|r| r.direction == Direction::Sent && r.priority == Some(Priority::Poll))
        .filter_map(|r| r.bytes.first().copied())
        .collect();
    assert_eq!(polled, [1, 2, 3, 4].into_iter().collect());
}

#[tokio::test(start_paused = true)]
async fn a_session_recording_ends_when_another_module_is_selected() {
    // A run file replays on one module: a line typed to another must not
    // join it as if it were the recorded module's.
    let (tmcl, cmd4cr) = two_links().await;
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("session.txt");
    let record = format!(":record {}", file.display());
    run_links_on(
        console(),
        (160, 30),
        vec![vec![tmcl], vec![cmd4cr]],
        no_connector(),
        async |mut rig: Rig| {
            rig.screens.until("module 2 cmd4cr #1").await;
            type_line(&rig, &record);
            rig.screens.until("recording the session to").await;
            type_line(&rig, "GAP 1, 0");
            rig.screens.until("got 02 01 64 06").await;
            type_line(&rig, ":module 2");
            rig.screens
                .until("session recording ended: another module was selected")
                .await;
            type_line(&rig, "PX");
            rig.screens.until("sent @01PX\\r  got 0").await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
    let recorded = std::fs::read_to_string(&file).expect("the recording");
    assert!(recorded.contains("GAP 1, 0"), "{recorded}");
    assert!(
        recorded.contains("# recording ended here: another module was selected\n"),
        "{recorded}"
    );
    assert!(!recorded.contains("PX"), "{recorded}");
}

#[tokio::test(start_paused = true)]
async fn the_log_takes_every_links_frames_each_named_by_its_link() {
    let (tmcl, cmd4cr) = two_links().await;
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("line.log");
    let log = format!(":log {}", file.display());
    run_links_on(
        console(),
        (160, 30),
        vec![vec![tmcl], vec![cmd4cr]],
        no_connector(),
        async |mut rig: Rig| {
            rig.screens.until("module 2 cmd4cr #1").await;
            type_line(&rig, ":poll off");
            type_line(&rig, &log);
            rig.screens.until("logging every frame to").await;
            type_line(&rig, "GAP 1, 0");
            rig.screens.until("got 02 01 64 06").await;
            type_line(&rig, ":module 2");
            type_line(&rig, "PX");
            rig.screens.until("sent @01PX\\r  got 0").await;
            type_line(&rig, ":log off");
            rig.screens.until("closed: ").await;
            press(&rig, KeyCode::F(10));
        },
    )
    .await;
    let log = std::fs::read_to_string(&file).expect("the log");
    let user: Vec<&str> = log
        .lines()
        .filter(|line| line.contains(" request     user "))
        .collect();
    assert_eq!(user.len(), 2, "{log}");
    assert!(
        user[0].contains(" ms L1 -> request     user     01 06 01 00"),
        "{log}"
    );
    assert!(user[1].contains(" ms L2 -> request     user     "), "{log}");
    assert!(user[1].contains("@01PX"), "{log}");
}
