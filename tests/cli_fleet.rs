//! `exec` and `run` on several modules (`--addresses`): each module's
//! results said with it, a row for every module asked for (one that does
//! not answer too), a run's stop sequence sent to the module whose run
//! failed, and `--stop-on-failure`.

mod cli_support;

use cli_support::{axterm, stderr, stdout};

#[test]
fn exec_on_several_modules_says_which_answered_what() {
    // One simulated module at address 1: 2 does not answer.
    let out = axterm(&[
        "exec",
        "--sim",
        "tmcm1110",
        "--addresses",
        "1,2",
        "SAP 4, 0, 321",
        "GAP 4, 0",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let said = stdout(&out);
    let lines: Vec<&str> = said.lines().collect();
    assert_eq!(lines[0], "module 1: ok", "{said}");
    assert_eq!(lines[1], "module 1: 321", "{said}");
    assert!(lines[2].starts_with("module  firmware"), "{said}");
    assert!(
        lines[3].contains("1110V112") && lines[3].ends_with("ok"),
        "{said}"
    );
    assert!(
        lines[4].contains("FAILED  module 2 does not answer"),
        "{said}"
    );
    assert!(stderr(&out).contains("module 2 does not answer"));

    let out = axterm(&[
        "exec",
        "--sim",
        "tmcm1110",
        "--addresses",
        "1",
        "GAP 4, 0",
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let said = stdout(&out);
    let first: serde_json::Value =
        serde_json::from_str(said.lines().next().unwrap_or("")).expect("a line's object");
    assert_eq!(first["module"], 1);
    assert_eq!(first["value"], 1000);
    let table: serde_json::Value =
        serde_json::from_str(said.lines().last().unwrap_or("")).expect("the table");
    assert_eq!(table["ok"], true);
    // A read is a line done, not a write.
    assert_eq!(table["modules"][0]["lines"], 1);
    assert_eq!(table["modules"][0]["failed"], 0);
    assert!(table["modules"][0].get("written").is_none(), "{table}");
}

#[test]
fn without_addresses_exec_prints_as_before() {
    let out = axterm(&["exec", "--sim", "tmcm1110", "SAP 4, 0, 321", "GAP 4, 0"]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(stdout(&out), "ok\n321\n");
}

#[test]
fn a_run_that_fails_on_one_module_stops_that_module_and_goes_on() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("r.txt");
    std::fs::write(&file, "ROR 0, 500\n:expect GAP 4, 0 == 1\n").expect("write");
    let file = file.display().to_string();
    let out = axterm(&["run", "--sim", "tmcm1110", "--addresses", "1,2", &file]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(err.contains("module 1: "), "{err}");
    assert!(err.contains("expected GAP 4, 0 == 1, got 1000"), "{err}");
    // The stop sequence of the emergency-stop key, at module 1.
    assert!(
        err.contains("axterm run: module 1: ") && err.contains("stopping every axis"),
        "{err}"
    );
    assert!(err.contains("  MST 0 → ok"), "{err}");
    let said = stdout(&out);
    assert!(said.contains("module 1: ok"), "{said}");
    let table: Vec<&str> = said
        .lines()
        .skip_while(|l| !l.starts_with("module  firmware"))
        .collect();
    assert_eq!(table.len(), 4, "module 2 tried too: {said}");
    assert!(table[1].contains("FAILED"), "{said}");
    assert!(table[2].contains("module 2 does not answer"), "{said}");

    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        "--addresses",
        "1,2",
        "--stop-on-failure",
        &file,
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stdout(&out).contains("not tried: --stop-on-failure after module 1 failed"),
        "{}",
        stdout(&out)
    );
}

#[test]
fn a_line_bad_for_any_listed_module_sends_nothing() {
    let out = axterm(&[
        "exec",
        "--port",
        "/nonexistent/tty",
        "--addresses",
        "1-3",
        "SAP 6, 0, 100000",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("nothing was sent"),
        "{}",
        stderr(&out)
    );
    let out = axterm(&[
        "exec",
        "--port",
        "/nonexistent/tty",
        "--protocol",
        "mccl",
        "--all",
        "VE",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("the mccl family has no module address"),
        "{}",
        stderr(&out)
    );
}

/// Issue 19 point 15: a value read on several modules of a family whose
/// answers carry no checksum says so on stderr, as on one module; stdout
/// keeps the bare value.
#[test]
fn values_read_without_a_checksum_on_several_modules_say_so() {
    let out = axterm(&["exec", "--sim", "cmd4cr", "--addresses", "1", "PX"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out).lines().next(), Some("module 1: 0"));
    assert!(
        stderr(&out)
            .contains("axterm exec: module 1: PX: unchecked (the reply carries no checksum)"),
        "{}",
        stderr(&out)
    );

    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("r.txt");
    std::fs::write(&file, "PX\n").expect("write");
    let file = file.display().to_string();
    let out = axterm(&["run", "--sim", "cmd4cr", "--addresses", "1", &file]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out).lines().next(), Some("module 1: 0"));
    assert!(
        stderr(&out).contains("PX: unchecked (the reply carries no checksum)"),
        "{}",
        stderr(&out)
    );
}
