//! The front ends against a served simulator whose line corrupts every
//! reply (`axterm sim KIND --pty --fault corrupt=1`): a line whose answer
//! came garbled fails, naming the line and the bytes that came, with exit
//! 1; it is never reported `ok`.

mod cli_support;
mod served_support;

use cli_support::{axterm, stderr, stdout};
use served_support::Served;

#[test]
fn cmd4cr_garbled_answers_to_writes_and_motions_are_errors_never_ok() {
    // The run of issue 11: it printed `K`, `fK`, `K` and exited 0.
    let served = Served::start("cmd4cr", &["--fault", "corrupt=1,seed=1"]);
    let out = axterm(&[
        "exec",
        "--port",
        &served.pty,
        "--protocol",
        "cmd4cr",
        "HSPDX=5000",
        "JX+",
        "STOPX",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert_eq!(stdout(&out), "", "nothing is reported done");
    let error = stderr(&out);
    assert!(
        error.starts_with("axterm exec: line 1: unreadable answer to HSPDX=5000: `"),
        "{error}"
    );
    assert!(
        error.contains("` is not OK, the answer to a write or action (garbled"),
        "{error}"
    );
    assert!(
        !error.contains("line 2"),
        "the first failure stops the rest: {error}"
    );

    let out = axterm(&[
        "exec",
        "--port",
        &served.pty,
        "--protocol",
        "cmd4cr",
        "--format",
        "json",
        "STOPX",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let json: serde_json::Value = serde_json::from_str(stdout(&out).trim()).expect("json");
    assert_eq!(json["ok"], false);
    assert_eq!(json["request"], "@01STOPX\\r");
    assert!(
        json["reply"].as_str().is_some_and(|r| !r.is_empty()),
        "{json}"
    );
}

#[test]
fn tmcl_a_corrupted_reply_is_named_with_its_bytes_not_as_silence() {
    let served = Served::start("tmcm1110", &["--fault", "corrupt=1,seed=1"]);
    let out = axterm(&["exec", "--port", &served.pty, "SAP 4, 0, 1000"]);
    assert_eq!(out.status.code(), Some(1));
    let error = stderr(&out);
    assert!(
        error.starts_with("axterm exec: line 1: unreadable answer to SAP 4, 0, 1000: 02 01 "),
        "{error}"
    );
    assert!(error.contains("wrong checksum"), "{error}");
    assert!(!error.contains("no reply"), "{error}");
}
