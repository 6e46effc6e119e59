//! Values in an axis's own units (issue 20, point 3) through `exec` and
//! `run` on the simulators: converted with the module's settings, said on
//! stderr before anything is sent, refused (exit 2, nothing sent) where
//! they cannot be.

mod cli_support;

use cli_support::{axterm, stderr, stdout};

fn file(text: &str) -> tempfile::NamedTempFile {
    let file = tempfile::NamedTempFile::new().expect("temp file");
    std::fs::write(file.path(), text).expect("written");
    file
}

/// 200 full steps of 256 microsteps, 5 mm a turn: 10240 µsteps a mm.
const MM_AXIS: &str = "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\nmicrosteps = 256\n\
                       travel_per_rev = 5\n";

fn path(file: &tempfile::NamedTempFile) -> &str {
    file.path().to_str().expect("utf-8")
}

#[test]
fn exec_converts_with_the_module_s_own_divisors() {
    let m = file(MM_AXIS);
    // AP0 (target position) in mm; AP4 in mm/s with the simulator's pulse
    // divisor, read first: 5 mm/s is 51200 pps, 1678 [int] at divisor 3
    // (§6.1.1).
    let out = axterm(&[
        "exec",
        "--sim",
        "tmcm1110",
        "--mechanics",
        path(&m),
        "SAP 154, 0, 3",
        "SAP 0, 0, 10mm",
        "GAP 0, 0",
        "SAP 4, 0, 5mm/s",
        "GAP 4, 0",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "ok\nok\n102400\nok\n1678\n");
    let err = stderr(&out);
    assert!(
        err.contains("line 2 `SAP 0, 0, 10mm`: 10mm → 102400: SAP 0, 0, 102400"),
        "{err}"
    );
    assert!(err.contains("5mm/s → 1678: SAP 4, 0, 1678"), "{err}");
}

#[test]
fn a_converted_value_out_of_range_sends_nothing() {
    let m = file(MM_AXIS);
    let out = axterm(&[
        "exec",
        "--sim",
        "tmcm1110",
        "--mechanics",
        path(&m),
        "SAP 4, 0, 100",
        "SAP 4, 0, 500mm/s",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "", "not even the first line went");
    let err = stderr(&out);
    assert!(
        err.contains("500mm/s → 167772") && err.contains("outside 1..2047"),
        "{err}"
    );
    assert!(err.contains("nothing was sent"), "{err}");
}

#[test]
fn a_unit_value_without_mechanics_is_refused_before_connecting() {
    let out = axterm(&["exec", "--sim", "tmcm1110", "MVP ABS, 0, 10mm"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("no mechanics are loaded"),
        "{}",
        stderr(&out)
    );
    let m = file(MM_AXIS);
    let out = axterm(&[
        "exec",
        "--sim",
        "tmcm1110",
        "--mechanics",
        path(&m),
        "ROR 0, 5deg/s",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("axis 0 is in mm"), "{}", stderr(&out));
}

#[test]
fn sixpack2_converts_with_what_the_lines_before_write() {
    // A 400-step motor: 6400 µsteps a turn (§6.2.1.8's poslimit comment).
    let m = file("[mechanics.0]\nunit = \"rev\"\nfull_steps_per_rev = 400\ntravel_per_rev = 1\n");
    let out = axterm(&[
        "exec",
        "--sim",
        "sixpack2",
        "--mechanics",
        path(&m),
        "SetClockDivider 5",
        "SetVMinVStart 0 4 5 2",
        "SetAMaxVMax 0 128 2rev/s",
        "SetTargetPosition 0 2rev",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let err = stderr(&out);
    // §6.3.1: 12800 µsteps/s at 20 MHz/6/2^16 a unit is v = 252.
    assert!(err.contains("2rev/s → 252: SetAMaxVMax 0 128 252"), "{err}");
    assert!(err.contains("2rev → 12800"), "{err}");
    // Without the settings written, the module cannot be asked for them.
    let out = axterm(&[
        "exec",
        "--sim",
        "sixpack2",
        "--mechanics",
        path(&m),
        "SetAMaxVMax 0 128 2rev/s",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("ClockDivider ($12)"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_run_file_converts_its_unit_lines_before_it_is_checked() {
    let m = file(MM_AXIS);
    let script = file("SAP 1, 0, 2.5mm\n:expect GAP 1, 0 == 25600\n");
    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        "--mechanics",
        path(&m),
        path(&script),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stderr(&out).contains(":1: 2.5mm → 25600: SAP 1, 0, 25600"),
        "{}",
        stderr(&out)
    );
    // A dry run converts with the mechanics file's own settings.
    let bad = file("SAP 4, 0, 1mm\nSAP 4, 0, 1mm/s\n");
    let out = axterm(&[
        "run",
        "--dry-run",
        "--protocol",
        "tmcl",
        "--mechanics",
        path(&m),
        path(&bad),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains(":1: `1mm` is a position or distance, and this operand takes a speed"),
        "{err}"
    );
    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        "--mechanics",
        path(&m),
        path(&bad),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
}

#[test]
fn mccl_and_cmd4cr_lines_take_units_too() {
    let m = file(
        "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\nmicrosteps = 10\ntravel_per_rev = 5\n\
         [mechanics.1]\nunit = \"deg\"\ncounts_per_rev = 8000\ntravel_per_rev = 360\n",
    );
    let out = axterm(&[
        "exec",
        "--sim",
        "cmd4cr",
        "--mechanics",
        path(&m),
        "HSPDX=20mm/s",
        "HSPDX",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        stdout(&out),
        "OK\n8000\n".replace("OK\n", &first_line(&out))
    );
    let out = axterm(&[
        "exec",
        "--sim",
        "mccl",
        "--mechanics",
        path(&m),
        "1DH90deg",
        "1TP",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).contains("90deg → 2000"), "{}", stderr(&out));
    assert!(stdout(&out).ends_with("2000\n"), "{}", stdout(&out));
}

fn first_line(out: &std::process::Output) -> String {
    stdout(out)
        .lines()
        .next()
        .map(|l| format!("{l}\n"))
        .unwrap_or_default()
}

#[test]
fn params_export_carries_the_mechanics_in_force_and_diff_compares_them() {
    let m = file(MM_AXIS);
    let dir = tempfile::tempdir().expect("temp dir");
    let exported = dir.path().join("line3.toml");
    let exported_path = exported.to_str().expect("utf-8");
    let out = axterm(&[
        "params",
        "export",
        "--sim",
        "tmcm1110",
        "--mechanics",
        path(&m),
        exported_path,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = std::fs::read_to_string(&exported).expect("written");
    assert!(
        text.contains("\n[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\n"),
        "{text}"
    );
    // The export is a mechanics file with the module's own settings: an
    // offline speed converts with its pulse divisor.
    let out = axterm(&[
        "encode",
        "tmcl",
        "--mechanics",
        exported_path,
        "SAP 4, 0, 5mm/s",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).contains("→ 1678"), "{}", stderr(&out));
    let out = axterm(&["params", "diff", "--sim", "tmcm1110", exported_path]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("carries the mechanics of axis 0: not written"),
        "{}",
        stderr(&out)
    );
    let other = file(&MM_AXIS.replace("travel_per_rev = 5", "travel_per_rev = 4"));
    let out = axterm(&[
        "params",
        "diff",
        "--sim",
        "tmcm1110",
        "--mechanics",
        path(&other),
        exported_path,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("mechanics differ from those in force"),
        "{}",
        stderr(&out)
    );
    // Mechanics of an axis the module lacks, or malformed, are refused.
    let bad = text.replace("[mechanics.0]", "[mechanics.3]");
    std::fs::write(&exported, bad).expect("written");
    let out = axterm(&["params", "apply", "--sim", "tmcm1110", exported_path]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("[mechanics.3]: this module has no axis 3"),
        "{}",
        stderr(&out)
    );
}
