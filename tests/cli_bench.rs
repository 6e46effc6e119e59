//! `axterm bench` runs against the simulator and prints every figure. Its
//! numbers are measurements, never asserted.

mod cli_support;
mod served_support;

use cli_support::{axterm, stderr};
use served_support::Served;

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
        let mut words = line.split_whitespace().rev();
        assert!(
            words.next().is_some_and(|faults| faults == "0"),
            "no faults on the simulator: {line}"
        );
        assert!(
            words.next().is_some_and(|rate| rate.parse::<f64>().is_ok()),
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

#[test]
fn on_a_lossy_line_faults_are_counted_and_the_measuring_goes_on() {
    // A fifth of the replies lost: before, the first lost poll ended the
    // run with exit 1 and no figures.
    let served = Served::start("tmcm1110", &["--fault", "drop=0.2,seed=5"]);
    let out = axterm(&[
        "bench",
        "--port",
        &served.pty,
        "--timeout",
        "50",
        "--requests",
        "30",
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let mut faults = 0;
    for part in ["bare", "device", "polling", "user_while_polling"] {
        let count = report[part]["count"].as_u64().expect("a count");
        let lost = report[part]["faults"].as_u64().expect("a fault count");
        assert_eq!(count + lost, 30, "{part}: {report}");
        assert!(count > 0, "{part}: {report}");
        faults += lost;
    }
    assert!(faults > 0, "{report}");
    assert_eq!(report["faults"], faults, "{report}");
    assert!(report["polling"]["per_second"].is_number(), "{report}");
}

#[test]
fn a_sixpack2_is_timed_with_its_status_read_and_its_switch_over_delay() {
    // Settings are never answered (§7): the bench times the family's first
    // status query, which is, and holds it against its bytes and the 6 ms
    // the unit waits before it answers (§6.1.1).
    let served = Served::start("sixpack2", &["--baud", "19200"]);
    let out = axterm(&[
        "bench",
        "--port",
        &served.pty,
        "--protocol",
        "sixpack2",
        "--requests",
        "5",
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(report["line"], "GetPositionAndActivity 0");
    assert_eq!(report["wire"]["bytes"], 17, "{report}");
    assert_eq!(report["wire"]["turnaround_us"], 6000.0, "{report}");
    assert_eq!(report["device"]["count"], 5, "{report}");
    assert_eq!(report["faults"], 0, "{report}");
}

#[test]
fn an_mccl_answer_overlaps_its_request_on_the_wire() {
    // The status line of all five axes and its answer: the echo comes
    // back as the line is sent (full duplex), 49 characters and CR LF,
    // then fifteen one-digit Tell lines (`01 0`, 6 bytes each) and the
    // prompt: 142 bytes back and the one the echo trails the request by.
    let out = axterm(&[
        "bench",
        "--sim",
        "mccl",
        "--baud",
        "115200",
        "--requests",
        "3",
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
    assert_eq!(
        report["line"], "1TP,TV,TS,2TP,TV,TS,3TP,TV,TS,4TP,TV,TS,5TP,TV,TS",
        "{report}"
    );
    assert_eq!(report["wire"]["bytes"], 51 + 15 * 6 + 1 + 1, "{report}");
    assert!(report["polling"]["share_of_wire"].is_number(), "{report}");
}
