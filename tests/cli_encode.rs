//! `axterm encode` as a script sees it: stdout, stderr and the exit code.

mod cli_support;

use cli_support::{axterm, stderr, stdout};

#[test]
fn a_line_becomes_uppercase_hex_bytes() {
    let out = axterm(&["encode", "tmcl", "ROR 0, 500"]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(stdout(&out), "01 01 00 00 00 00 01 F4 F7\n");
}

#[test]
fn the_address_option_sets_byte_zero() {
    let out = axterm(&["encode", "tmcl", "--address", "3", "GAP 1, 0"]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(stdout(&out), "03 06 01 00 00 00 00 00 0A\n");
}

#[test]
fn an_invalid_value_names_the_range_and_prints_nothing() {
    let out = axterm(&["encode", "tmcl", "SAP 6, 0, 300"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
    let err = stderr(&out);
    assert!(err.contains("300") && err.contains("0..255"), "{err}");
}

#[test]
fn an_unknown_mnemonic_is_named() {
    let out = axterm(&["encode", "tmcl", "MOVE 0, 10"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
    assert!(stderr(&out).contains("MOVE"), "{}", stderr(&out));
}

#[test]
fn an_unknown_family_lists_the_known_ones() {
    let out = axterm(&["encode", "modbus", "GAP 1, 0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("tmcl"), "{}", stderr(&out));
}

/// The mechanics: 200 full steps of 256 microsteps, 5 mm a turn.
const MM_AXIS: &str = "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\nmicrosteps = 256\n\
                       travel_per_rev = 5\n";

fn mechanics_file(text: &str) -> tempfile::NamedTempFile {
    let file = tempfile::NamedTempFile::new().expect("temp file");
    std::fs::write(file.path(), text).expect("written");
    file
}

#[test]
fn a_distance_in_the_axis_unit_becomes_its_microsteps() {
    let m = mechanics_file(MM_AXIS);
    let path = m.path().to_str().expect("utf-8");
    let out = axterm(&["encode", "tmcl", "--mechanics", path, "MVP ABS, 0, 10mm"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // 10 mm × 200 × 256 / 5 = 102400 = 0x00019000.
    assert_eq!(stdout(&out), "01 04 00 00 00 01 90 00 96\n");
    assert_eq!(
        stderr(&out),
        "axterm encode: 10mm → 102400: MVP ABS, 0, 102400\n"
    );
    let raw = axterm(&["encode", "tmcl", "MVP ABS, 0, 102400"]);
    assert_eq!(stdout(&raw), stdout(&out));
}

#[test]
fn a_converted_value_out_of_the_command_range_is_refused() {
    let m = mechanics_file(&format!("{MM_AXIS}\n[axis.0]\n154 = 3\n"));
    let path = m.path().to_str().expect("utf-8");
    let out = axterm(&[
        "encode",
        "tmcl",
        "--mechanics",
        path,
        "MVP ABS, 0, 300000mm",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
    let err = stderr(&out);
    assert!(
        err.contains("300000mm → 3072000000") && err.contains("outside"),
        "{err}"
    );
    // A speed converts with the file's pulse divisor (§6.1.1: 1678 at 3).
    let out = axterm(&["encode", "tmcl", "--mechanics", path, "SAP 4, 0, 5mm/s"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).contains("5mm/s → 1678"), "{}", stderr(&out));
    let out = axterm(&["encode", "tmcl", "--mechanics", path, "SAP 4, 0, 5000mm/s"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("outside 1..2047"), "{}", stderr(&out));
}

#[test]
fn a_unit_without_mechanics_or_settings_is_refused_naming_what_is_missing() {
    let out = axterm(&["encode", "tmcl", "MVP ABS, 0, 10mm"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("no mechanics are loaded"),
        "{}",
        stderr(&out)
    );
    let m = mechanics_file(MM_AXIS);
    let path = m.path().to_str().expect("utf-8");
    let out = axterm(&["encode", "tmcl", "--mechanics", path, "ROR 0, 5mm/s"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("pulse divisor (AP154)"),
        "{}",
        stderr(&out)
    );
    let out = axterm(&["encode", "tmcl", "--mechanics", path, "MVP ABS, 1, 10mm"]);
    assert_eq!(out.status.code(), Some(2));
    let bad = mechanics_file("[mechanics.0]\nunit = \"mm\"\n");
    let path = bad.path().to_str().expect("utf-8");
    let out = axterm(&["encode", "tmcl", "--mechanics", path, "MVP ABS, 0, 1mm"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("[mechanics.0] needs"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn every_family_takes_values_in_the_axis_unit() {
    let m = mechanics_file(
        "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\nmicrosteps = 10\ntravel_per_rev = 5\n\
         [mechanics.1]\nunit = \"deg\"\ncounts_per_rev = 8000\ntravel_per_rev = 360\n\
         [axis.1]\n9 = 10000\n12 = 10000\n",
    );
    let path = m.path().to_str().expect("utf-8");
    let out = axterm(&["encode", "cmd4cr", "--mechanics", path, "HSPDX=20mm/s"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "@01HSPDX=8000\\r\n");
    // MCCL user scaling US 1, UR 1 (rows 9 and 12, held in 1/10000).
    let out = axterm(&["encode", "mccl", "--mechanics", path, "1MA90deg"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "1MA2000\\r\n");
    let out = axterm(&["encode", "sixpack2", "--mechanics", path, "StartRamp 0 1mm"]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "the SIXpack 2's 16 µsteps are not 10"
    );
    assert!(
        stderr(&out).contains("the module is set to 16"),
        "{}",
        stderr(&out)
    );
}
