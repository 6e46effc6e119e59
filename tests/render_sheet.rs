//! The commissioning sheet rendered in a real browser: runs
//! `tests/render_sheet.sh` (docs/sheet.md, "In a browser") with this
//! build's axterm. The script prints the page to PDF, takes a screenshot,
//! and asks the browser's own SVG DOM how many points each plot series
//! holds (400 a series for the MCCL example's step response).
//!
//! Without a browser on PATH the script says so and exits 77: the test
//! says it skipped, unless `AXTERM_REQUIRE_BROWSER=1` (CI installs
//! Chromium and sets it), where a missing browser fails the test.

use std::process::Command;

#[test]
fn the_sheet_renders_in_a_real_browser_with_every_point_of_its_plot() {
    let root = env!("CARGO_MANIFEST_DIR");
    let out = tempfile::tempdir().expect("a temporary folder");
    let run = Command::new("sh")
        .arg(format!("{root}/tests/render_sheet.sh"))
        .arg(out.path())
        .env("AXTERM", env!("CARGO_BIN_EXE_axterm"))
        .current_dir(root)
        .output()
        .expect("sh runs");
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    let required = std::env::var("AXTERM_REQUIRE_BROWSER").is_ok_and(|v| v == "1");
    match run.status.code() {
        Some(77) if !required => {
            println!("skipped: {said}");
        }
        Some(77) => panic!("AXTERM_REQUIRE_BROWSER=1 but no browser to render with: {said}"),
        Some(0) => assert!(
            said.contains("400 points a series in the browser's SVG DOM"),
            "the script passed without saying what it checked: {said}"
        ),
        _ => panic!("rendering the sheet failed ({}): {said}", run.status),
    }
}
