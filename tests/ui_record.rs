//! `:record FILE`: a console session on an in-process simulator, driven
//! by keys through the real loop on tokio's paused clock, written down as
//! an `axterm run` file; the file then replays with the real binary
//! against a fresh simulator (exit 0) and fails on an `:expect` against
//! one whose state differs (exit 1). For TMCL and CMD-4CR.

mod cli_support;
mod report_support;
mod ui_support;

use std::path::Path;

use cli_support::{axterm, stderr, stdout};
use std::sync::Arc;

use axterm::cli::ConnectionArgs;
use axterm::cli::connection::Target;
use axterm::ui::app::Controller;
use axterm::ui::live::{SessionController, identify_later};
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use ui_support::looped::{Rig, enter, press, press_with, run_command_console};

/// The console's controller on the in-process simulator `kind`, as
/// `axterm --sim KIND` builds it (the identity read in the background).
async fn sim_controller(kind: &str) -> Arc<dyn Controller> {
    sim_controller_with(kind, &[]).await
}

/// [`sim_controller`] with the simulator's `--input` settings.
async fn sim_controller_with(kind: &str, inputs: &[&str]) -> Arc<dyn Controller> {
    let target = Target::resolve(&ConnectionArgs {
        sim: Some(kind.into()),
        baud: Some(115_200),
        input: inputs.iter().map(|s| s.to_string()).collect(),
        ..ConnectionArgs::default()
    })
    .expect("a simulator connection");
    let session = target.open().await.expect("the simulator opens");
    identify_later(&session);
    Arc::new(SessionController::new(
        session,
        target.spec.describe(),
        target.options.clone(),
    ))
}

/// The first axis row of the axes pane.
fn first_axis_row(frame: &str) -> &str {
    frame.lines().nth(1).unwrap_or_default()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).expect("the recording")
}

/// Replay `file` with `axterm run --sim KIND [extra…]`: its exit code and
/// what it said.
fn replay(kind: &str, extra: &[&str], file: &Path) -> (Option<i32>, String) {
    let mut args = vec!["run", "--sim", kind];
    args.extend_from_slice(extra);
    let file = file.to_string_lossy().into_owned();
    args.push(&file);
    let out = axterm(&args);
    (
        out.status.code(),
        format!("{}{}", stdout(&out), stderr(&out)),
    )
}

#[tokio::test(start_paused = true)]
async fn a_tmcl_session_recorded_in_the_console_replays_with_axterm_run() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("commissioning.txt");
    let path = file.display().to_string();
    let controller = sim_controller("tmcm1110").await;
    run_command_console(controller, (120, 40), async |rig: &mut Rig| {
        rig.screens.until("(1110V112)").await;
        // What is recorded, before and after.
        enter(rig, ":record");
        rig.screens.until("nothing is being recorded").await;
        enter(rig, &format!(":record {path}"));
        rig.screens.until("recording the session to").await;
        enter(rig, "SAP 4, 0, 1500");
        enter(rig, "SAP 6, 0, 999");
        enter(rig, "MVP ABS, 0, 2000");
        // The technician waits until the axis is there.
        rig.screens
            .until_frame("the axis at 2000", |f| {
                let row = first_axis_row(f);
                row.contains(" 2000 ") && row.contains("● reached")
            })
            .await;
        enter(rig, "GAP 1, 0");
        enter(rig, "GIO 3, 0");
        enter(rig, "GAP 4, 0");
        rig.screens.until("  1500  (status 100").await;
        enter(rig, ":record");
        rig.screens
            .until("5 line(s), 1 wait(s) so far (:record off ends it)")
            .await;
        enter(rig, ":record off");
        rig.screens.until("session recording ended").await;
    })
    .await;

    let text = read(&file);
    let mut body: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with("# axterm") && !l.starts_with("# recorded: 20"))
        .collect();
    // The wait is on the reached flag, or on the position where the axis
    // was seen at rest if the flag's poll had not come round yet.
    let wait = body.get(7).copied().unwrap_or_default();
    assert!(
        [
            ":wait-until GAP 8, 0 == 1 timeout 10s",
            ":wait-until GAP 1, 0 == 2000 timeout 10s"
        ]
        .contains(&wait),
        "{text}"
    );
    body.remove(7);
    assert_eq!(
        body,
        [
            "# family: tmcl (Trinamic TMCL (TMCM-1110 StepRocker), 9-byte binary frames)",
            "# link: sim tmcm1110 at 115200 Bd, address 1",
            "# firmware: 1110V112",
            "",
            "SAP 4, 0, 1500",
            "# not sent: SAP 6, 0, 999  (SAP 6: value 999 outside 0..255 (Maximum current))",
            "MVP ABS, 0, 2000",
            ":expect GAP 1, 0 == 2000",
            ":expect GIO 3, 0 == 1",
            ":expect GAP 4, 0 == 1500",
        ],
        "{text}"
    );

    let (code, said) = replay("tmcm1110", &[], &file);
    assert_eq!(code, Some(0), "{said}");
    // IN3 pulled low: the read recorded as 1 reads 0.
    let (code, said) = replay("tmcm1110", &["--input", "IN3=0"], &file);
    assert_eq!(code, Some(1), "{said}");
    assert!(said.contains("expected GIO 3, 0 == 1, got 0"), "{said}");
}

#[tokio::test(start_paused = true)]
async fn a_cmd4cr_session_recorded_in_the_console_replays_with_axterm_run() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("commissioning.txt");
    let path = file.display().to_string();
    let controller = sim_controller("cmd4cr").await;
    run_command_console(controller, (120, 40), async |rig: &mut Rig| {
        rig.screens.until("#1 (").await;
        enter(rig, &format!(":record {path}"));
        rig.screens.until("recording the session to").await;
        enter(rig, "EO=15");
        enter(rig, "X1000");
        rig.screens
            .until_frame("axis X at 1000", |f| {
                let row = first_axis_row(f);
                row.contains(" 1000 ") && row.contains("● reached")
            })
            .await;
        enter(rig, "PX");
        enter(rig, "DI");
        rig.screens.until("sent @01DI\\r  got 0").await;
        enter(rig, ":record off");
        rig.screens.until("session recording ended").await;
    })
    .await;

    let text = read(&file);
    assert!(text.contains("# family: cmd4cr ("), "{text}");
    assert!(!text.contains("# firmware: not read"), "{text}");
    let steps: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty())
        .collect();
    assert_eq!(steps.len(), 5, "{text}");
    assert_eq!(&steps[..2], ["EO=15", "X1000"], "{text}");
    assert!(steps[2].starts_with(":wait-until MSTX == "), "{text}");
    assert_eq!(
        &steps[3..],
        [":expect PX == 1000", ":expect DI == 0"],
        "{text}"
    );

    let (code, said) = replay("cmd4cr", &[], &file);
    assert_eq!(code, Some(0), "{said}");
    let (code, said) = replay("cmd4cr", &["--input", "DI4=1"], &file);
    assert_eq!(code, Some(1), "{said}");
    assert!(said.contains("expected DI == 0, got 8"), "{said}");
}

/// `:report FILE`: the sheet of the session recording so far, HTML or
/// JSON (checked against the schema); refused without a recording, and
/// an existing file kept without --force.
#[tokio::test(start_paused = true)]
async fn report_writes_the_sheet_of_the_session_recording_so_far() {
    let dir = tempfile::tempdir().expect("temp dir");
    let recording = dir.path().join("commissioning.txt").display().to_string();
    let html = dir.path().join("sheet.html");
    let json = dir.path().join("sheet.json");
    std::fs::write(&json, "yesterday's").expect("write");
    let (html_path, json_path) = (html.display().to_string(), json.display().to_string());
    let controller = sim_controller("tmcm1110").await;
    run_command_console(controller, (160, 40), async |rig: &mut Rig| {
        rig.screens.until("(1110V112)").await;
        enter(rig, &format!(":report {html_path}"));
        rig.screens
            .until(":report writes the sheet of the session recording: start one with :record")
            .await;
        enter(rig, &format!(":record {recording}"));
        rig.screens.until("recording the session to").await;
        enter(rig, "SAP 4, 0, 1500");
        enter(rig, "SAP 6, 0, 999");
        enter(rig, "GAP 4, 0");
        rig.screens.until("  1500  (status 100").await;
        enter(rig, &format!(":report {html_path}"));
        rig.screens
            .until("the sheet of the session so far is in")
            .await;
        enter(rig, &format!(":report {json_path}"));
        rig.screens.until("give --force to replace it").await;
        enter(rig, &format!(":report --force {json_path}"));
        rig.screens.until("sheet.json: All 2 checks passed").await;
    })
    .await;

    let page = scraper::Html::parse_document(&read(&html));
    let select = |css: &str| report_support::select_text(&page, css);
    let headline = &select("#verdict .headline")[0];
    // The read recorded as `:expect` and the session's end.
    assert!(headline.contains("All 2 checks passed"), "{headline}");
    assert!(select("#module-1 .identity")[0].contains("1110V112"));
    let checks = select("#module-1 .expectations tbody tr");
    assert_eq!(checks.len(), 1, "{checks:?}");
    assert!(
        checks[0].contains("GAP 4, 0") && checks[0].contains("1500"),
        "{checks:?}"
    );
    let lines = select("#module-1 .lines tbody tr");
    assert_eq!(lines.len(), 3, "{lines:?}");
    // Numbered as the answers came: the refused line at once, before the
    // answer to the one sent ahead of it.
    assert!(
        lines
            .iter()
            .any(|l| l.contains("# not sent: SAP 6, 0, 999") && l.contains("outside 0..255")),
        "{lines:?}"
    );
    let value: serde_json::Value = serde_json::from_str(&read(&json)).expect("JSON");
    let problems = report_support::validate(&report_support::schema(), &value);
    assert!(problems.is_empty(), "{problems:#?}");
    assert_eq!(value["modules"][0]["identity"]["family"], "tmcl");
    assert_eq!(value["verdict"]["passed"], true);
}

/// `:report` after the bring-up pane's wiring check and the tuning pane's
/// step test on a MultiFlex servo: the sheet holds the check's findings,
/// the step's figures and plot, and the module's settings against the
/// factory defaults, read when `:report` was given.
#[tokio::test(start_paused = true)]
async fn report_carries_the_panes_wiring_check_step_test_and_settings() {
    let dir = tempfile::tempdir().expect("temp dir");
    let recording = dir.path().join("commissioning.txt");
    let html = dir.path().join("sheet.html");
    let json = dir.path().join("sheet.json");
    let (html_path, json_path) = (html.display().to_string(), json.display().to_string());
    // Every axis on the simulator's demo stage: limits at ±50,000 counts.
    let controller = sim_controller_with("mccl", &["LIMITS=right"]).await;
    run_command_console(controller, (160, 48), async |rig: &mut Rig| {
        enter(rig, &format!(":record {}", recording.display()));
        rig.screens.until("recording the session to").await;
        // Servo 1's limits on, decelerating at them, its loop on (Ch5 LN,
        // LM, MN), as the wiring check wants them.
        enter(rig, "1LM2,1LN3,1MN");
        rig.screens.until("1LM2,1LN3,1MN  ").await;
        press_with(rig, KeyCode::Char('8'), KeyModifiers::ALT);
        rig.screens.until("standing by").await;
        // 10,000 counts/s: the stage's + limit, 50,000 counts out, in 5 s.
        for _ in 0..2 {
            press(rig, KeyCode::Char('f'));
        }
        rig.screens.until("speed 10000 counts/s").await;
        press(rig, KeyCode::Char('w'));
        rig.screens.until("y/n").await;
        press(rig, KeyCode::Char('y'));
        rig.screens.until("wiring check: each limit switch").await;
        press_with(rig, KeyCode::Char('9'), KeyModifiers::ALT);
        rig.screens.until("SG 0.04").await;
        press(rig, KeyCode::Char('r'));
        rig.screens.until("it moves the axis: y/n").await;
        press(rig, KeyCode::Char('y'));
        rig.screens.until("step done").await;
        press_with(rig, KeyCode::Char('1'), KeyModifiers::ALT);
        enter(rig, &format!(":report {html_path}"));
        rig.screens
            .until("reading the settings for the sheet")
            .await;
        rig.screens.until("sheet.html: All 2 checks passed").await;
        enter(rig, &format!(":report {json_path}"));
        rig.screens.until("sheet.json: All 2 checks passed").await;
    })
    .await;

    let page = scraper::Html::parse_document(&read(&html));
    let select = |css: &str| report_support::select_text(&page, css);
    // The wiring check and the session's end.
    let headline = &select("#verdict .headline")[0];
    assert!(
        headline.contains("✓ PASS") && headline.contains("All 2 checks passed"),
        "{headline}"
    );
    let wiring = &select("#module-1 .wiring")[0];
    assert!(
        wiring.contains("Wiring check ✓ PASS")
            && wiring.contains("servo 1, moving +: the + (right) switch fired at")
            && wiring.contains("servo 1, moving -: the − (left) switch fired at"),
        "{wiring}"
    );
    let tuning = &select("#module-1 .tuning")[0];
    assert!(
        tuning.contains("servo 1: 400 samples every 0.25 ms; gains SG 0.04")
            && tuning.contains("rise time (10-90 %): ")
            && tuning.contains("Step response, servo 1"),
        "{tuning}"
    );
    for name in ["commanded", "actual"] {
        let css = format!("#module-1 .tuning svg g.series[data-name=\"{name}\"] .point");
        assert_eq!(select(&css).len(), 400, "{name}");
    }
    let lines = select("#module-1 .lines tbody tr");
    assert!(
        lines.iter().any(|l| l.contains(":wiring --axis 0 --speed")
            && l.contains("the bring-up pane's check of servo 1")
            && l.contains("wired right")),
        "{lines:?}"
    );
    assert!(
        lines.iter().any(
            |l| l.contains(":tune-step --axis 1 --distance 1000 --samples 400")
                && l.contains("400 samples")
        ),
        "{lines:?}"
    );
    // The settings, read when :report was given: nothing changed from
    // the factory's (SQ 10 V, Ch5 SQ), every axis's rows.
    let settings = &select("#module-1 .settings")[0];
    assert!(
        settings.contains("Settings readfrom the module when the sheet was asked for (:report)"),
        "{settings}"
    );
    let rows = select("#module-1 .settings-table tbody tr");
    // Its cells run together: value, default, unit.
    assert!(
        rows.iter().any(
            |r| r.contains("axis 1") && r.contains("SQ output limit (torque)10.0000010.00000V")
        ),
        "{rows:?}"
    );
    assert!(rows.iter().any(|r| r.contains("axis 5")), "{rows:?}");
    assert!(select("#module-1 .settings-table tr.differs").is_empty());
    // The JSON: the same facts, valid against the schema.
    let value: serde_json::Value = serde_json::from_str(&read(&json)).expect("JSON");
    let problems = report_support::validate(&report_support::schema(), &value);
    assert!(problems.is_empty(), "{problems:#?}");
    let module = &value["modules"][0];
    assert_eq!(module["checks"]["wiring"]["wired_right"], true);
    assert_eq!(module["tuning"]["plots"][0]["series"][1]["name"], "actual");
    assert!(
        module["settings"]["rows"]
            .as_array()
            .is_some_and(|r| !r.is_empty())
    );
    // The recording file says what the panes did, as comments: a replay
    // does not repeat their moves.
    let file = read(&recording);
    assert!(
        file.contains("# :wiring --axis 0 --speed")
            && file.contains("(the bring-up pane's check of servo 1): wired right"),
        "{file}"
    );
    assert!(
        file.contains("# :tune-step --axis 1 --distance 1000"),
        "{file}"
    );
}

/// A StallGuard2 sweep in the tuning pane (TMCL) during a recording: on
/// the sheet as `axterm run` puts its `:tune-stallguard`, its readings
/// plotted; a sweep the user stops is shown and not counted.
#[tokio::test(start_paused = true)]
async fn report_carries_a_stallguard_sweep_of_the_tuning_pane() {
    let dir = tempfile::tempdir().expect("temp dir");
    let recording = dir.path().join("sweep.txt");
    let html = dir.path().join("sheet.html");
    let html_path = html.display().to_string();
    let controller = sim_controller("tmcm1110").await;
    run_command_console(controller, (160, 48), async |rig: &mut Rig| {
        enter(rig, &format!(":record {}", recording.display()));
        rig.screens.until("recording the session to").await;
        // The power down delay set and stored (TMCL STAP): the sheet says
        // the settings were stored, and flags it against its default.
        enter(rig, "SAP 214, 0, 100");
        enter(rig, "STAP 214, 0");
        rig.screens.until("STAP 214, 0  ").await;
        press_with(rig, KeyCode::Char('9'), KeyModifiers::ALT);
        rig.screens.until("from 200").await;
        // One stopped with Esc, then one to its end.
        press(rig, KeyCode::Char('r'));
        rig.screens.until("it moves the axis: y/n").await;
        press(rig, KeyCode::Char('y'));
        rig.screens.until("Esc stops it").await;
        press(rig, KeyCode::Esc);
        rig.screens.until("run ended, stopping").await;
        press(rig, KeyCode::Char('r'));
        rig.screens.until("it moves the axis: y/n").await;
        press(rig, KeyCode::Char('y'));
        rig.screens.until("sweep done").await;
        press_with(rig, KeyCode::Char('1'), KeyModifiers::ALT);
        enter(rig, &format!(":report {html_path}"));
        // The session's end the one check: the sweep counts only if it fails.
        rig.screens.until("sheet.html: The one check passed").await;
    })
    .await;

    let page = scraper::Html::parse_document(&read(&html));
    let select = |css: &str| report_support::select_text(&page, css);
    let settings = &select("#module-1 .settings")[0];
    assert!(settings.contains("Stored to EEPROMyes"), "{settings}");
    let differs = select("#module-1 .settings-table tr.differs");
    assert!(
        differs.len() == 1 && differs[0].contains("Power down delay100200"),
        "{differs:?}"
    );
    let tuning = &select("#module-1 .tuning")[0];
    assert!(
        tuning.contains("threshold during the sweep")
            && tuning.contains("speed 200: ")
            && tuning.contains("StallGuard2 sweep, motor 0"),
        "{tuning}"
    );
    // A mean a speed, four readings a speed: 5 speeds.
    let points = |name: &str| {
        select(&format!(
            "#module-1 .tuning svg g.series[data-name=\"{name}\"] .point"
        ))
        .len()
    };
    assert_eq!((points("mean"), points("readings")), (5, 20));
    let lines = select("#module-1 .lines tbody tr");
    assert!(
        lines.iter().any(|l| l.contains(
            ":tune-stallguard --axis 0 --from 200 --to 1000 --steps 5 --samples 4 (the tuning \
             pane's sweep of motor 0)"
        ) && l.contains("5 speeds swept")),
        "{lines:?}"
    );
    assert!(
        lines
            .iter()
            .any(|l| l.contains("# stopped: :tune-stallguard") && l.contains("stopped by key")),
        "{lines:?}"
    );
}
