//! Issue 15's acceptance for parameter files on a bus: four simulated
//! modules of one family served on one pseudo-terminal (`axterm sim KIND
//! --pty --address 1-4`), module 3 deaf (`--fault 3:drop=1`); `params
//! apply --addresses 1-4` writes and verifies the good modules, reports
//! module 3 and goes on; `params diff` afterwards finds nothing on the
//! good modules. Checked module by module with `axterm exec`, not with the
//! code under test.

mod cli_support;
mod served_support;

use cli_support::{axterm, stderr, stdout};
use served_support::Served;

fn file_with(dir: &tempfile::TempDir, text: &str) -> String {
    let path = dir.path().join("fleet.toml");
    std::fs::write(&path, text).expect("write the file");
    path.display().to_string()
}

/// The table at the end of a fleet's output: its rows, header first.
fn table(said: &str) -> Vec<String> {
    said.lines()
        .skip_while(|l| !l.starts_with("module  firmware"))
        .map(String::from)
        .collect()
}

/// The row of `module` in the table.
fn row(table: &[String], module: u8) -> &str {
    table
        .iter()
        .find(|r| r.split_whitespace().next() == Some(&module.to_string()))
        .map_or("", String::as_str)
}

/// Columns: module, firmware, written, verified, differs, failed, result
/// (ok or FAILED), then the note's words. The firmware column may hold
/// spaces (a SIXpack 2 answers its $43 with several fields), so the
/// numbers are cut where the header's "written" column begins.
fn counts(rows: &[String], row: &str) -> Vec<String> {
    let header = rows.first().map_or("", String::as_str);
    let numbers_at = header
        .find("written")
        .map_or(0, |at| (at + "written".len()).saturating_sub(10));
    // Counted in characters: a cut firmware column ends in "…".
    let front: String = row.chars().take(numbers_at).collect();
    let back: String = row.chars().skip(numbers_at).collect();
    let mut columns: Vec<String> = front.split_whitespace().take(1).map(String::from).collect();
    columns.push("firmware".into());
    columns.extend(back.split_whitespace().map(String::from));
    columns
}

struct Case {
    kind: &'static str,
    protocol: &'static str,
    file: &'static str,
    /// Values written per good module.
    written: usize,
    /// A read on one module after the apply, and what it must say.
    check: Option<(&'static str, &'static str)>,
}

fn apply_on_a_bus_with_one_deaf_module(case: &Case) {
    let served = Served::start(case.kind, &["--address", "1-4", "--fault", "3:drop=1"]);
    let dir = tempfile::tempdir().expect("temp dir");
    let file = file_with(&dir, case.file);
    let connection = ["--port", served.pty.as_str(), "--protocol", case.protocol];
    let mut args = vec!["params", "apply"];
    args.extend(connection);
    args.extend(["--addresses", "1-4", file.as_str()]);
    let out = axterm(&args);
    let said = stdout(&out);
    assert_eq!(out.status.code(), Some(1), "{said}{}", stderr(&out));
    let rows = table(&said);
    assert_eq!(rows.len(), 6, "a row for each of the four: {said}");
    for good in [1, 2, 4] {
        let columns = counts(&rows, row(&rows, good));
        assert_eq!(columns[6], "ok", "{said}");
        assert_eq!(columns[2], case.written.to_string(), "written: {said}");
        assert_eq!(columns[5], "0", "failed: {said}");
        assert!(said.contains(&format!("module {good}: ")), "{said}");
    }
    assert!(
        row(&rows, 3).contains("FAILED  module 3 does not answer"),
        "{said}"
    );
    assert_eq!(rows[5], "3 of 4 module(s) ok");

    if let Some((line, value)) = case.check {
        for module in ["1", "2", "4"] {
            let out = axterm(&[
                "exec",
                "--port",
                &served.pty,
                "--protocol",
                case.protocol,
                "--address",
                module,
                line,
            ]);
            assert_eq!(
                stdout(&out).trim(),
                value,
                "module {module}: {}",
                stderr(&out)
            );
        }
    }
}

#[test]
fn tmcl_bus_apply_writes_verifies_and_reports_the_deaf_module() {
    let case = Case {
        kind: "tmcm1110",
        protocol: "tmcl",
        file: "family = \"tmcl\"\n[axis.0]\n4 = 777\n5 = 200\n[bank.2]\n0 = 42\n",
        written: 3,
        check: Some(("GAP 4, 0", "777")),
    };
    apply_on_a_bus_with_one_deaf_module(&case);
}

#[test]
fn cmd4cr_bus_apply_writes_verifies_and_reports_the_deaf_module() {
    let case = Case {
        kind: "cmd4cr",
        protocol: "cmd4cr",
        file: "family = \"cmd4cr\"\n[axis.0]\n5120 = 3000\n[axis.1]\n5120 = 4000\n",
        written: 2,
        check: Some(("HSPDX", "3000")),
    };
    apply_on_a_bus_with_one_deaf_module(&case);
}

#[test]
fn sixpack2_bus_apply_writes_and_reports_the_deaf_module() {
    // Nothing reads back on a SIXpack 2 (§7): the writes are counted, not
    // verified; the deaf module does not answer its $43.
    let case = Case {
        kind: "sixpack2",
        protocol: "sixpack2",
        file: "family = \"sixpack2\"\n[axis.0]\n4097 = 128\n5121 = 100\n5122 = 400\n",
        written: 3,
        check: None,
    };
    apply_on_a_bus_with_one_deaf_module(&case);
}

#[test]
fn after_an_apply_diff_finds_nothing_on_the_good_modules() {
    for (kind, protocol, text) in [
        ("tmcm1110", "tmcl", "[axis.0]\n4 = 777\n[bank.2]\n0 = 42\n"),
        ("cmd4cr", "cmd4cr", "[axis.0]\n5120 = 3000\n"),
    ] {
        let served = Served::start(kind, &["--address", "1-4", "--fault", "3:drop=1"]);
        let dir = tempfile::tempdir().expect("temp dir");
        let file = file_with(&dir, text);
        let run = |command: &str, addresses: &str| {
            axterm(&[
                "params",
                command,
                "--port",
                &served.pty,
                "--protocol",
                protocol,
                "--addresses",
                addresses,
                &file,
            ])
        };
        let out = run("diff", "1,2,4");
        assert_eq!(out.status.code(), Some(1), "{kind}: differs before");
        let out = run("apply", "1-4");
        assert_eq!(out.status.code(), Some(1), "{kind}: module 3 failed");
        let out = run("diff", "1,2,4");
        let said = stdout(&out);
        assert_eq!(out.status.code(), Some(0), "{kind}: {said}{}", stderr(&out));
        assert!(
            !said.contains(": module "),
            "{kind}: no difference listed: {said}"
        );
        assert!(said.contains("3 of 3 module(s) ok"), "{said}");
        let out = run("diff", "1-4");
        assert_eq!(out.status.code(), Some(1), "module 3 is not skipped");
        assert!(stdout(&out).contains("FAILED  module 3 does not answer"));
    }
}

#[test]
fn all_scans_the_bus_and_works_on_every_module_found() {
    let served = Served::start("cmd4cr", &["--address", "1-4", "--fault", "3:drop=1"]);
    let dir = tempfile::tempdir().expect("temp dir");
    let file = file_with(&dir, "[axis.0]\n5120 = 2500\n");
    let out = axterm(&[
        "params",
        "apply",
        "--port",
        &served.pty,
        "--protocol",
        "cmd4cr",
        "--all",
        &file,
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("scan found 3 module(s): 1, 2, 4"),
        "{}",
        stderr(&out)
    );
    let last = stdout(&out).lines().last().unwrap_or("").to_string();
    let object: serde_json::Value = serde_json::from_str(&last).expect("the table");
    let modules: Vec<i64> = object["modules"]
        .as_array()
        .expect("rows")
        .iter()
        .filter_map(|m| m["module"].as_i64())
        .collect();
    assert_eq!(modules, [1, 2, 4]);
    assert_eq!(object["ok"], true);
}
