//! `axterm bench` runs against the simulator and prints every figure. Its
//! numbers are measurements, never asserted.

mod cli_support;

use cli_support::axterm;

#[test]
fn bench_prints_a_row_per_measurement() {
    let out = axterm(&["bench", "--sim", "tmcm1110", "--requests", "20"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for row in [
        "bare write/read loop",
        "device task round trip",
        "status polling (saturating)",
        "user read while polling",
    ] {
        let line = text
            .lines()
            .find(|l| l.starts_with(row))
            .unwrap_or_else(|| panic!("no row {row}: {text}"));
        assert!(
            line.split_whitespace()
                .last()
                .is_some_and(|rate| rate.parse::<f64>().is_ok()),
            "{line}"
        );
    }
}

#[test]
fn bench_json_carries_every_figure() {
    let out = axterm(&[
        "bench",
        "--sim",
        "tmcm1110",
        "--requests",
        "20",
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(report["requests"], 20);
    assert_eq!(report["line"], "GAP 1, 0");
    for part in ["bare", "device", "user_while_polling"] {
        assert_eq!(report[part]["count"], 20, "{report}");
        assert!(report[part]["p50_us"].is_number(), "{report}");
        assert!(report[part]["p99_us"].is_number(), "{report}");
    }
    assert!(report["polling"]["per_second"].is_number(), "{report}");
}

#[test]
fn at_a_baud_rate_the_figures_are_held_against_the_wire() {
    let out = axterm(&[
        "bench",
        "--sim",
        "tmcm1110",
        "--baud",
        "115200",
        "--requests",
        "5",
        "--format",
        "json",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    // GAP and its answer: 9 bytes each way.
    assert_eq!(report["wire"]["bytes"], 18, "{report}");
    assert!(report["wire"]["per_second"].is_number(), "{report}");
    assert!(report["polling"]["share_of_wire"].is_number(), "{report}");
    assert!(report["user_p99_over_bare_p99"].is_number(), "{report}");
    assert!(report["bare"]["min_us"].is_number(), "{report}");
}

#[test]
fn the_wire_counts_every_byte_that_crossed_it() {
    // CMD-4CR: `@01PP` and `0:0:0:0`, each with its carriage return, which
    // the answer's frame leaves out.
    let out = axterm(&[
        "bench",
        "--sim",
        "cmd4cr",
        "--baud",
        "115200",
        "--requests",
        "3",
        "--format",
        "json",
    ]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(report["line"], "PP", "{report}");
    assert_eq!(report["wire"]["bytes"], 14, "{report}");
}

#[test]
fn without_a_baud_rate_there_is_no_wire_figure() {
    let out = axterm(&[
        "bench",
        "--sim",
        "tmcm1110",
        "--requests",
        "5",
        "--format",
        "json",
    ]);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert!(report["wire"].is_null(), "{report}");
    assert!(report["polling"]["share_of_wire"].is_null(), "{report}");
}

#[test]
fn zero_requests_is_a_usage_error() {
    let out = axterm(&["bench", "--sim", "tmcm1110", "--requests", "0"]);
    assert_eq!(out.status.code(), Some(2));
}
