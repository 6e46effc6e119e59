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
