//! `axterm run FILE --report SHEET.html --report-json SHEET.json` against
//! the simulators: the commissioning example of a family run end to end,
//! the page parsed with a real HTML parser and the JSON validated against
//! the schema; a failing check named in the verdict; hostile text from a
//! run file shown as text; an existing sheet never replaced without
//! --force (and then nothing is sent); one section per module of a bus.

mod cli_support;
mod report_support;

use std::path::Path;
use std::process::{Command, Output};

use cli_support::{axterm, stderr};
use report_support::select_text;
use scraper::{Html, Selector};
use serde_json::Value;

const TMCL_EXAMPLE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/tmcl/commission.txt");

fn text(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}

/// The sheet's page and JSON after a run, the JSON checked against the
/// schema.
fn sheet(html: &Path, json: &Path) -> (Html, Value) {
    let page = Html::parse_document(&std::fs::read_to_string(html).expect("the page"));
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(json).expect("the JSON")).expect("JSON");
    let problems = report_support::validate(&report_support::schema(), &json);
    assert!(problems.is_empty(), "{problems:#?}");
    (page, json)
}

fn run_example(extra: &[&str]) -> (Output, Html, Value) {
    run_family("tmcm1110", TMCL_EXAMPLE, extra)
}

/// A family's commissioning example run on simulator `sim` with `extra`
/// options: the output, the page and the JSON (checked against the
/// schema).
fn run_family(sim: &str, example: &str, extra: &[&str]) -> (Output, Html, Value) {
    let dir = tempfile::tempdir().expect("temp dir");
    let (html, json) = (dir.path().join("s.html"), dir.path().join("s.json"));
    let mut args = vec!["run", "--sim", sim, "--yes", example, "--report"];
    let (html_arg, json_arg) = (text(&html), text(&json));
    args.extend([html_arg.as_str(), "--report-json", json_arg.as_str()]);
    args.extend(extra);
    let out = axterm(&args);
    let (page, json) = sheet(&html, &json);
    (out, page, json)
}

#[test]
fn the_tmcl_commissioning_example_hands_over_a_passing_sheet() {
    let (out, page, json) = run_example(&["--operator", "Ada Lovelace"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let headline = &select_text(&page, "#verdict .headline")[0];
    assert!(headline.contains("✓ PASS"), "{headline}");
    // Seven :expect/:wait-until lines, the wiring check and the run's end.
    assert!(headline.contains("All 9 checks passed"), "{headline}");
    // Where each switch was seen is a read taken while the axis moves, in
    // real time here: under load it can lag the switch by a few steps
    // (-199987 for -200000), so only the finding itself is checked (the
    // exact ends on tokio's paused clock: tests/wiring_families.rs).
    let wiring = &select_text(&page, "#module-1 .wiring")[0];
    let stopped = "as it should; the module stopped the axis at it";
    let leg = |start: &str| {
        wiring
            .lines()
            .any(|l| l.starts_with(start) && l.ends_with(stopped))
    };
    assert!(
        wiring.contains("Wiring check ✓ PASS")
            && leg("motor 0, moving +: the + (right) switch fired at ")
            && leg("motor 0, moving -: the − (left) switch fired at -"),
        "{wiring}"
    );
    let run = &select_text(&page, "#run")[0];
    assert!(
        run.contains("Ada Lovelace") && run.contains("commission.txt"),
        "{run}"
    );
    let identity = &select_text(&page, "#module-1 .identity")[0];
    // The simulator's answer to TMCL 136 (firmware version string).
    assert!(identity.contains("1110V112"), "{identity}");
    assert!(identity.contains("--sim tmcm1110"), "{identity}");
    let settings = &select_text(&page, "#module-1 .settings")[0];
    assert!(
        settings.contains("Parameter file appliedaxis.toml"),
        "{settings}"
    );
    assert!(settings.contains("Stored to EEPROMyes"), "{settings}");
    // Power down delay (axis parameter 214) set to 100 against its
    // factory default 200: the only setting flagged.
    let differs = select_text(&page, "#module-1 .settings-table tr.differs");
    assert_eq!(differs.len(), 1, "{differs:?}");
    assert!(differs[0].contains("Power down delay") && differs[0].contains("100"));
    let checks = select_text(&page, "#module-1 .expectations tbody tr");
    assert_eq!(checks.len(), 7, "{checks:?}");
    assert!(checks.iter().all(|c| c.contains("✓ PASS")), "{checks:?}");
    let lines = select_text(&page, "#module-1 .lines tbody tr");
    assert!(
        lines.iter().any(|l| l.contains(":params axis.toml --store")
            && l.contains("2 written, 2 verified")
            && l.contains("✓ ok")),
        "{lines:?}"
    );
    let end = &select_text(&page, "#module-1 .run-end")[0];
    assert!(
        end.contains("completed") && end.contains("No emergency stop"),
        "{end}"
    );
    assert_eq!(json["verdict"]["passed"], true);
    assert_eq!(json["operator"], "Ada Lovelace");
    assert_eq!(json["modules"][0]["identity"]["firmware"], "1110V112");
}

#[test]
fn a_check_that_fails_is_named_in_the_verdict_with_the_emergency_stop() {
    // The enable input IN1 held low: the file's `:expect GIO 1, 0 == 1`
    // (line 14) fails, and the run ends with the stop sequence.
    let (out, page, json) = run_example(&["--input", "IN1=0"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let headline = &select_text(&page, "#verdict .headline")[0];
    assert!(headline.contains("✗ FAIL"), "{headline}");
    assert!(
        headline.contains("line 14 `GIO 1, 0` expected 1, got 0"),
        "{headline}"
    );
    let failed = select_text(&page, "#module-1 .expectations tr.fail");
    assert!(failed[0].contains("GIO 1, 0") && failed[0].contains("✗ FAIL"));
    // The homing checks after it never ran, and say so.
    assert!(failed.iter().filter(|f| f.contains("NOT RUN")).count() == 2);
    let stop = &select_text(&page, "#module-1 .emergency-stop")[0];
    assert!(
        stop.contains("EMERGENCY STOP") && stop.contains("MST 0"),
        "{stop}"
    );
    assert_eq!(json["verdict"]["passed"], false);
    assert_eq!(json["modules"][0]["checks"]["run_end"]["ending"], "failed");
}

#[test]
fn a_hostile_comment_shows_as_text() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("hostile.txt");
    std::fs::write(
        &file,
        "# <script>alert(1)</script> & co\n:echo <b>bold</b> & \"quoted\"\nGAP 4, 0\n",
    )
    .expect("write");
    let (html, json) = (dir.path().join("s.html"), dir.path().join("s.json"));
    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        &text(&file),
        "--report",
        &text(&html),
        "--report-json",
        &text(&json),
        "--operator",
        "<i>root</i>",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let (page, _) = sheet(&html, &json);
    for element in ["script", "b", "i"] {
        let selector = Selector::parse(element).expect("selector");
        assert!(
            page.select(&selector).next().is_none(),
            "a <{element}> got in"
        );
    }
    let lines = select_text(&page, "#module-1 .lines");
    assert!(
        lines[0].contains("# <script>alert(1)</script> & co"),
        "{lines:?}"
    );
    assert!(lines[0].contains("<b>bold</b> & \"quoted\""), "{lines:?}");
    assert!(select_text(&page, "#run")[0].contains("<i>root</i>"));
}

#[test]
fn an_existing_sheet_is_refused_without_force_and_nothing_is_sent() {
    let dir = tempfile::tempdir().expect("temp dir");
    let html = dir.path().join("s.html");
    std::fs::write(&html, "the sheet of yesterday").expect("write");
    // A run file that would fail if it were sent: nothing may be.
    let file = dir.path().join("f.txt");
    std::fs::write(&file, ":expect GAP 4, 0 == 12345\n").expect("write");
    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        &text(&file),
        "--report",
        &text(&html),
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("give --force to replace it"),
        "{}",
        stderr(&out)
    );
    assert!(
        stderr(&out).contains("nothing was sent"),
        "{}",
        stderr(&out)
    );
    assert!(!stderr(&out).contains("12345"), "{}", stderr(&out));
    assert_eq!(
        std::fs::read_to_string(&html).expect("read"),
        "the sheet of yesterday"
    );
    let json = dir.path().join("s.json");
    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        &text(&file),
        "--report",
        &text(&html),
        "--report-json",
        &text(&json),
        "--force",
    ]);
    // The check fails (the run says 1) and the sheet is replaced.
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let (page, _) = sheet(&html, &json);
    assert!(select_text(&page, "#verdict .headline")[0].contains("expected 12345"));
}

#[test]
fn the_operator_defaults_to_the_login_name() {
    let dir = tempfile::tempdir().expect("temp dir");
    let json = dir.path().join("s.json");
    let file = dir.path().join("f.txt");
    std::fs::write(&file, "GAP 4, 0\n").expect("write");
    let out = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["run", "--sim", "tmcm1110", &text(&file), "--report-json"])
        .arg(&json)
        .env("USER", "technician-7")
        .output()
        .expect("run axterm");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let value: Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("read")).expect("JSON");
    assert_eq!(value["operator"], "technician-7");
}

#[test]
fn every_module_of_a_bus_gets_its_section_and_a_silent_one_fails_the_sheet() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (html, json) = (dir.path().join("s.html"), dir.path().join("s.json"));
    let file = dir.path().join("f.txt");
    std::fs::write(&file, ":expect GAP 4, 0 == 1000\n").expect("write");
    // The simulated bus has module 1 only: module 2 does not answer.
    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        "--addresses",
        "1,2",
        &text(&file),
        "--report",
        &text(&html),
        "--report-json",
        &text(&json),
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let (page, json) = sheet(&html, &json);
    assert_eq!(select_text(&page, "section.module").len(), 2);
    assert!(select_text(&page, "#module-1 .verdict")[0].contains("✓ PASS"));
    let second = &select_text(&page, "#module-2 .verdict")[0];
    assert!(
        second.contains("✗ FAIL") && second.contains("does not answer"),
        "{second}"
    );
    assert_eq!(json["modules"][1]["identity"]["address"], 2);
    assert_eq!(json["verdict"]["passed"], false);
}

#[test]
fn the_cmd4cr_commissioning_example_passes_and_a_limit_switch_on_fails_it() {
    let example = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/cmd4cr/commission.txt"
    );
    let dir = tempfile::tempdir().expect("temp dir");
    let (html, json) = (dir.path().join("s.html"), dir.path().join("s.json"));
    let (html_arg, json_arg) = (text(&html), text(&json));
    let args = [
        "run",
        "--sim",
        "cmd4cr",
        "--yes",
        example,
        "--report",
        &html_arg,
        "--report-json",
        &json_arg,
        "--force",
    ];
    let out = axterm(&args);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let (page, value) = sheet(&html, &json);
    let headline = &select_text(&page, "#verdict .headline")[0];
    // Four :expect/:wait-until lines before homing's two, the wiring
    // check and the run's end.
    assert!(
        headline.contains("✓ PASS") && headline.contains("All 7 checks passed"),
        "{headline}"
    );
    assert_eq!(value["modules"][0]["identity"]["family"], "cmd4cr");
    assert_eq!(value["modules"][0]["checks"]["wiring"]["wired_right"], true);
    // The −limit switch of X on (MSTX bit 5, Table 2-28): the switch check
    // fails and the verdict says which line and what was read.
    let mut failing = args.to_vec();
    failing.extend(["--input", "L-X=1"]);
    let out = axterm(&failing);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let (page, _) = sheet(&html, &json);
    let headline = &select_text(&page, "#verdict .headline")[0];
    assert!(headline.contains("✗ FAIL"), "{headline}");
    assert!(headline.contains("`MSTX` expected 0, got 32"), "{headline}");
}

#[test]
fn a_parameter_file_that_does_not_check_sends_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(
        dir.path().join("bad.toml"),
        "family = \"tmcl\"\n[axis.0]\n6 = 300\n",
    )
    .expect("write");
    let file = dir.path().join("f.txt");
    // The first line would fail if it were sent: nothing may be.
    std::fs::write(&file, ":expect GAP 4, 0 == 12345\n:params bad.toml\n").expect("write");
    let json = dir.path().join("s.json");
    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        &text(&file),
        "--report-json",
        &text(&json),
    ]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("f.txt:2: ") && err.contains("bad.toml"),
        "{err}"
    );
    assert!(
        err.contains("nothing was sent") && !err.contains("12345"),
        "{err}"
    );
    assert!(!json.exists(), "a sheet of a run that never ran");
}

const CMD4CR_EXAMPLE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/examples/cmd4cr/commission.txt"
);

#[test]
fn swapped_limit_switches_fail_the_cmd4cr_sheet_naming_the_wiring() {
    let (out, page, json) = run_family("cmd4cr", CMD4CR_EXAMPLE, &["--input", "LIMITS=swapped"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let headline = &select_text(&page, "#verdict .headline")[0];
    assert!(
        headline.contains("✗ FAIL")
            && headline.contains(
                "the wiring check found a fault: X, moving + tripped the − (left) switch at"
            ),
        "{headline}"
    );
    let wiring = &select_text(&page, "#module-1 .wiring")[0];
    assert!(wiring.contains("Wiring check ✗ FAIL"), "{wiring}");
    // The :wiring line failed, and the homing after it never ran.
    let lines = select_text(&page, "#module-1 .lines tr.fail");
    assert!(
        lines.iter().any(|l| l.contains(":wiring --speed 500000")),
        "{lines:?}"
    );
    let faults = json["modules"][0]["checks"]["wiring"]["faults"]
        .as_array()
        .expect("faults");
    assert_eq!(faults.len(), 2, "{faults:?}");
    assert_eq!(json["verdict"]["passed"], false);
}

#[test]
fn swapped_limit_switches_fail_the_tmcl_sheet_naming_the_wiring() {
    let (out, page, _) = run_example(&["--input", "LIMITS=swapped"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let headline = &select_text(&page, "#verdict .headline")[0];
    assert!(
        headline.contains(
            "the wiring check found a fault: motor 0, moving + tripped the − (left) switch at"
        ),
        "{headline}"
    );
}

const SIXPACK2_EXAMPLE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/examples/sixpack2/commission.txt"
);

#[test]
fn the_sixpack2_commissioning_example_passes_and_a_reference_switch_on_fails_it() {
    let (out, page, json) = run_family("sixpack2", SIXPACK2_EXAMPLE, &[]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let headline = &select_text(&page, "#verdict .headline")[0];
    // Two :expect lines and the run's end.
    assert!(
        headline.contains("✓ PASS") && headline.contains("All 3 checks passed"),
        "{headline}"
    );
    assert_eq!(
        json["modules"][0]["settings"]["parameter_file"],
        "axis.toml"
    );
    let lines = select_text(&page, "#module-1 .lines tbody tr");
    assert!(
        lines
            .iter()
            .any(|l| l.contains(":params axis.toml") && l.contains("4 written, 0 verified")),
        "{lines:?}"
    );
    // Motor 0's reference switch actuated at rest: its input reads 0.
    let (out, page, _) = run_family("sixpack2", SIXPACK2_EXAMPLE, &["--input", "REF0=1"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let headline = &select_text(&page, "#verdict .headline")[0];
    assert!(
        headline.contains("✗ FAIL")
            && headline.contains("line 11 `GetInputValues 0` expected analog=512 ref=1, got")
            && headline.contains("ref=0"),
        "{headline}"
    );
}

const MCCL_EXAMPLE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/mccl/commission.txt");

#[test]
fn the_mccl_commissioning_example_passes_with_its_step_response_plotted() {
    let (out, page, json) = run_family("mccl", MCCL_EXAMPLE, &[]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let headline = &select_text(&page, "#verdict .headline")[0];
    // Six :expect/:wait-until lines and the run's end.
    assert!(
        headline.contains("✓ PASS") && headline.contains("All 7 checks passed"),
        "{headline}"
    );
    let tuning = &select_text(&page, "#module-1 .tuning")[0];
    assert!(
        tuning.contains("servo 1: 400 samples every 0.25 ms; gains SG 0.04, SD 0.3")
            && tuning.contains("rise time (10-90 %): ")
            && tuning.contains("Step response, servo 1"),
        "{tuning}"
    );
    // One plot; each series a marker per sample, as many as the JSON's.
    assert_eq!(select_text(&page, "#module-1 .tuning svg").len(), 1);
    for (index, name) in ["commanded", "actual"].into_iter().enumerate() {
        let css = format!("#module-1 .tuning svg g.series[data-name=\"{name}\"] .point");
        let points = select_text(&page, &css).len();
        let series = &json["modules"][0]["tuning"]["plots"][0]["series"][index];
        assert_eq!(series["name"], name);
        assert_eq!(points, 400);
        assert_eq!(series["points"].as_array().map(Vec::len), Some(400));
    }
    // The last commanded sample is the step's target.
    let last = json["modules"][0]["tuning"]["plots"][0]["series"][0]["points"][399][1].as_f64();
    assert_eq!(last, Some(1000.0));
}

/// The settings table's rows of module 1: (where, setting, value,
/// factory default, flagged as differing).
fn setting_rows(page: &Html) -> Vec<(String, String, String, String, bool)> {
    let rows = Selector::parse("#module-1 .settings-table tbody tr").expect("selector");
    let cell = Selector::parse("td").expect("selector");
    page.select(&rows)
        .map(|row| {
            let cells: Vec<String> = row
                .select(&cell)
                .map(|c| c.text().collect::<String>())
                .collect();
            let differs = row.value().attr("class") == Some("differs");
            (
                cells[0].clone(),
                cells[2].clone(),
                cells[3].clone(),
                cells[4].clone(),
                differs,
            )
        })
        .collect()
}

#[test]
fn the_cmd4cr_and_mccl_sheets_list_settings_against_the_manuals_defaults() {
    // CMD-4CR: the parameter file sets SCVX=1, an S-curve, where the core
    // comes with a linear profile (§2.1.4); EINT comes 1 (§2.3.1), the
    // baud code 1 = 9600 (Table 3-39).
    let cmd4cr = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/cmd4cr/commission.txt"
    );
    let (out, page, json) = run_family("cmd4cr", cmd4cr, &[]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let rows = setting_rows(&page);
    let flagged: Vec<&str> = rows.iter().filter(|r| r.4).map(|r| r.1.as_str()).collect();
    assert_eq!(flagged, ["SCVX"], "{rows:?}");
    let row = |name: &str| rows.iter().find(|r| r.1 == name).expect(name).clone();
    assert_eq!(
        row("SCVX"),
        ("axis 0".into(), "SCVX".into(), "1".into(), "0".into(), true)
    );
    assert_eq!(row("EINT").3, "1");
    assert_eq!(row("DB").3, "1");
    assert_eq!(row("SDCU").3, "0", "every axis's rows");
    let settings = &select_text(&page, "#module-1 .settings")[0];
    assert!(
        settings.contains("Parameter file appliedaxis.toml"),
        "{settings}"
    );
    assert_eq!(
        json["modules"][0]["settings"]["parameter_file"],
        "axis.toml"
    );

    // MCCL: the file limits servo 1's output to 8 V (SQ), 10.0 V by
    // default (Ch5 SQ); the stepper, axis 5, has its ES row (default 1).
    let (out, page, json) = run_family("mccl", MCCL_EXAMPLE, &[]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let rows = setting_rows(&page);
    let flagged: Vec<_> = rows.iter().filter(|r| r.4).collect();
    assert_eq!(flagged.len(), 1, "{rows:?}");
    assert_eq!(
        (flagged[0].0.as_str(), flagged[0].1.as_str()),
        ("axis 1", "SQ output limit (torque)")
    );
    // As MCCL writes the reals (in volts); the JSON keeps the raw
    // numbers (5 decimals: 8 V is 800000).
    assert_eq!(
        (flagged[0].2.as_str(), flagged[0].3.as_str()),
        ("8.00000", "10.00000")
    );
    let sq = json["modules"][0]["settings"]["rows"]
        .as_array()
        .expect("rows")
        .iter()
        .find(|r| r["differs"] == true)
        .expect("the row that differs");
    assert_eq!(sq["value"], 800_000);
    assert_eq!(sq["factory_default"], 1_000_000);
    assert_eq!(
        (&sq["value_text"], &sq["unit"]),
        (&"8.00000".into(), &"V".into())
    );
    assert!(
        rows.iter()
            .any(|r| r.0 == "axis 5" && r.1 == "ES steps per encoder count" && r.3 == "1.0000"),
        "{rows:?}"
    );
    assert!(
        rows.iter()
            .any(|r| r.0 == "axis 2" && r.1 == "VO velocity override" && !r.4),
        "{rows:?}"
    );
    let differing = json["modules"][0]["settings"]["rows"]
        .as_array()
        .expect("rows")
        .iter()
        .filter(|r| r["differs"] == true)
        .count();
    assert_eq!(differing, 1);
}

#[test]
fn a_limit_input_on_fails_the_mccl_sheet_naming_the_check() {
    let (out, page, _) = run_family("mccl", MCCL_EXAMPLE, &["--input", "LIM-1=1"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let headline = &select_text(&page, "#verdict .headline")[0];
    assert!(
        headline.contains("✗ FAIL") && headline.contains("line 11 `1TS29` expected 0, got 1"),
        "{headline}"
    );
    // The run stopped there: no tuning was done.
    let tuning = &select_text(&page, "#module-1 .tuning")[0];
    assert!(tuning.contains("No tuning was done"), "{tuning}");
}

#[test]
fn a_tool_the_family_lacks_is_refused_before_anything_is_sent() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("f.txt");
    // The first line would fail if it were sent: nothing may be.
    std::fs::write(
        &file,
        ":expect GAP 4, 0 == 12345\n:tune-step --distance 1000\n",
    )
    .expect("write");
    let json = dir.path().join("s.json");
    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        &text(&file),
        "--report-json",
        &text(&json),
    ]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("f.txt:2: :tune-step: the tmcl family has no servo step-response test"),
        "{err}"
    );
    assert!(
        err.contains("nothing was sent") && !err.contains("12345"),
        "{err}"
    );
    assert!(!json.exists(), "a sheet of a run that never ran");
}

#[test]
fn a_stallguard_sweep_puts_its_readings_on_the_sheet() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("f.txt");
    std::fs::write(&file, ":tune-stallguard --from 200 --to 1000 --steps 3\n").expect("write");
    let (html, json) = (dir.path().join("s.html"), dir.path().join("s.json"));
    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        &text(&file),
        "--report",
        &text(&html),
        "--report-json",
        &text(&json),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let (page, json) = sheet(&html, &json);
    let plot = &json["modules"][0]["tuning"]["plots"][0];
    assert_eq!(plot["x_label"], "speed");
    // Three speeds, four readings at each.
    assert_eq!(
        plot["series"][0]["points"].as_array().map(Vec::len),
        Some(3)
    );
    assert_eq!(
        plot["series"][1]["points"].as_array().map(Vec::len),
        Some(12)
    );
    let figures = &select_text(&page, "#module-1 .tuning .figures")[0];
    assert!(figures.contains("speed 200: "), "{figures}");
    assert_eq!(select_text(&page, "#module-1 .tuning svg").len(), 1);
}

#[test]
fn a_tool_directive_prints_one_json_object_with_its_lines() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("f.txt");
    std::fs::write(&file, ":tune-step --axis 1 --distance 1000\n").expect("write");
    let out = axterm(&["run", "--sim", "mccl", "--format", "json", &text(&file)]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let said = cli_support::stdout(&out);
    let objects: Vec<Value> = said
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    assert_eq!(objects.len(), 1, "{said}");
    assert_eq!(objects[0]["tool"], "tune-step");
    assert_eq!(objects[0]["ok"], true);
    let first = objects[0]["lines"][0].as_str().unwrap_or_default();
    assert!(
        first.starts_with("servo 1: 400 samples every 0.25 ms"),
        "{first}"
    );
}

#[test]
fn a_step_that_trips_fails_the_sheet_naming_its_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("f.txt");
    // Unstable gains and a tight following error limit: the step trips
    // (as in tests/cli_tune.rs), and the run stops there.
    std::fs::write(
        &file,
        ":tune-step --axis 1 --distance 20 --set SG=5,SE=40\n:echo not reached\n",
    )
    .expect("write");
    let (html, json) = (dir.path().join("s.html"), dir.path().join("s.json"));
    let out = axterm(&[
        "run",
        "--sim",
        "mccl",
        &text(&file),
        "--report",
        &text(&html),
        "--report-json",
        &text(&json),
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let (page, json) = sheet(&html, &json);
    let headline = &select_text(&page, "#verdict .headline")[0];
    assert!(
        headline.contains("✗ FAIL")
            && headline
                .contains("line 1 `:tune-step --axis 1 --distance 20 --set SG=5,SE=40`: tripped (")
            && headline.contains("the axis was stopped"),
        "{headline}"
    );
    // The plot of what it did is on the sheet all the same.
    assert_eq!(select_text(&page, "#module-1 .tuning svg").len(), 1);
    let figures = &select_text(&page, "#module-1 .tuning .figures")[0];
    assert!(figures.contains("TRIPPED: "), "{figures}");
    assert_eq!(json["verdict"]["passed"], false);
}
