//! A fleet of several links: `params diff|apply`, `exec` and `run` given
//! `--port A --port B` (or `--sim K --sim K`) work on every module of
//! every link in turn, name each module with its link (`L1 module 0`),
//! end with one table that has a link column, and fail (exit 1) when any
//! module of any link failed, a link that cannot be opened included. A
//! MultiFlex (MCCL) line is such a fleet: one board per link, no module
//! address. Boards are served by the real binary (`axterm sim mccl
//! --pty`) so that what one process wrote is read by the next; what an
//! apply wrote is checked with a plain single-link `exec`, not with the
//! code under test.

mod cli_support;
mod served_support;

use cli_support::{axterm, stderr, stdout};
use served_support::Served;

/// [axis.1] 0 is SV, the velocity of axis 1 (raw: thousandths); the
/// simulated board starts at 100000 units/s.
const MCCL_FILE: &str = "family = \"mccl\"\n[axis.1]\n0 = 50000000\n";
/// The read of axis 1's velocity the parameter table uses (digest §16),
/// written out here.
const MCCL_READ_SV1: &str = "LU\"PGMVEL\",1RD@0,TR0";

fn file_with(dir: &tempfile::TempDir, text: &str) -> String {
    let path = dir.path().join("line.toml");
    std::fs::write(&path, text).expect("write the file");
    path.display().to_string()
}

/// The table at the end of a fleet's output, header first.
fn table(said: &str) -> Vec<&str> {
    said.lines()
        .skip_while(|l| !l.starts_with("link  module  firmware"))
        .collect()
}

/// The row of link `label` in the table.
fn row<'a>(table: &[&'a str], label: &str) -> &'a str {
    table
        .iter()
        .find(|r| r.split_whitespace().next() == Some(label))
        .copied()
        .unwrap_or("")
}

/// What a single-link exec on `pty` reads for `line`.
fn read_board(pty: &str, line: &str) -> String {
    let out = axterm(&["exec", "--port", pty, "--protocol", "mccl", line]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    stdout(&out).trim().to_string()
}

#[test]
fn a_line_of_two_mccl_boards_is_applied_verified_and_then_diffs_clean() {
    let boards = [Served::start("mccl", &[]), Served::start("mccl", &[])];
    let dir = tempfile::tempdir().expect("temp dir");
    let file = file_with(&dir, MCCL_FILE);
    let params = |command: &str| {
        axterm(&[
            "params",
            command,
            "--protocol",
            "mccl",
            "--port",
            &boards[0].pty,
            "--port",
            &boards[1].pty,
            &file,
        ])
    };
    let out = params("diff");
    assert_eq!(
        out.status.code(),
        Some(1),
        "both differ before: {}",
        stdout(&out)
    );
    assert!(
        stdout(&out).contains("0 of 2 module(s) ok"),
        "{}",
        stdout(&out)
    );

    let out = params("apply");
    let said = stdout(&out);
    assert_eq!(out.status.code(), Some(0), "{said}{}", stderr(&out));
    for label in ["L1", "L2"] {
        assert!(
            said.contains(&format!("{label} module 0: 1SV50000")) && said.contains("verified"),
            "{label}'s write said with its link: {said}"
        );
    }
    let rows = table(&said);
    assert_eq!(
        rows.len(),
        6,
        "header, two rows, two links named, total: {said}"
    );
    for label in ["L1", "L2"] {
        let columns: Vec<&str> = row(&rows, label).split_whitespace().collect();
        // link, module, firmware (words), written, verified, differs, failed, ok
        let n = columns.len();
        assert_eq!(columns[1], "0", "{said}");
        assert_eq!(columns[n - 5..], ["1", "1", "0", "0", "ok"], "{said}");
    }
    assert_eq!(rows[3], format!("L1: --port {}", boards[0].pty));
    assert_eq!(rows[4], format!("L2: --port {}", boards[1].pty));
    assert_eq!(rows[5], "2 of 2 module(s) ok");
    for board in &boards {
        assert_eq!(read_board(&board.pty, MCCL_READ_SV1), "50000.000000");
    }

    let out = params("diff");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}{}",
        stdout(&out),
        stderr(&out)
    );
    assert!(
        stdout(&out).contains("2 of 2 module(s) ok"),
        "{}",
        stdout(&out)
    );
}

#[test]
fn a_board_that_cannot_be_reached_is_a_failed_row_and_the_others_are_done() {
    let good = Served::start("mccl", &[]);
    // A board whose every answer is lost.
    let deaf = Served::start("mccl", &["--fault", "drop=1"]);
    let dir = tempfile::tempdir().expect("temp dir");
    let file = file_with(&dir, MCCL_FILE);
    let out = axterm(&[
        "params",
        "apply",
        "--protocol",
        "mccl",
        "--timeout",
        "200",
        "--port",
        "/nonexistent/tty",
        "--port",
        &deaf.pty,
        "--port",
        &good.pty,
        &file,
    ]);
    let said = stdout(&out);
    assert_eq!(out.status.code(), Some(1), "{said}{}", stderr(&out));
    let rows = table(&said);
    assert!(
        row(&rows, "L1").contains("FAILED  L1 cannot be opened"),
        "not skipped, not an abort: {said}"
    );
    assert!(
        stderr(&out).contains("L1 (--port /nonexistent/tty): cannot open"),
        "{}",
        stderr(&out)
    );
    assert!(
        row(&rows, "L2").contains("FAILED  module 0 does not answer"),
        "{said}"
    );
    assert!(row(&rows, "L3").ends_with("ok"), "{said}");
    assert_eq!(rows.last().copied(), Some("1 of 3 module(s) ok"), "{said}");
    assert_eq!(read_board(&good.pty, MCCL_READ_SV1), "50000.000000");

    // In JSON: a "link" on every row, the unreachable one's error kept.
    let out = axterm(&[
        "params",
        "diff",
        "--protocol",
        "mccl",
        "--port",
        "/nonexistent/tty",
        "--port",
        &good.pty,
        &file,
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let last = stdout(&out).lines().last().unwrap_or("").to_string();
    let object: serde_json::Value = serde_json::from_str(&last).expect("the table");
    let modules = object["modules"].as_array().expect("rows");
    assert_eq!(modules.len(), 2);
    assert_eq!(modules[0]["link"], "L1");
    assert_eq!(modules[0]["connection"], "--port /nonexistent/tty");
    assert_eq!(modules[0]["ok"], false);
    assert_eq!(modules[1]["link"], "L2");
    assert_eq!(modules[1]["ok"], true, "diff finds nothing after the apply");
    assert_eq!(object["ok"], false);
}

#[test]
fn stop_on_failure_leaves_the_later_links_untried_and_says_so() {
    let good = Served::start("mccl", &[]);
    let dir = tempfile::tempdir().expect("temp dir");
    let file = file_with(&dir, MCCL_FILE);
    let out = axterm(&[
        "params",
        "apply",
        "--protocol",
        "mccl",
        "--stop-on-failure",
        "--port",
        "/nonexistent/tty",
        "--port",
        &good.pty,
        &file,
    ]);
    let said = stdout(&out);
    assert_eq!(out.status.code(), Some(1), "{said}{}", stderr(&out));
    assert!(
        row(&table(&said), "L2")
            .contains("not tried: --stop-on-failure after L1 could not be opened"),
        "{said}"
    );
    assert_eq!(
        read_board(&good.pty, MCCL_READ_SV1),
        "100000.000000",
        "nothing was written to the board not tried"
    );
}

#[test]
fn exec_on_two_links_says_each_result_with_its_link_and_module() {
    let out = axterm(&[
        "exec", "--sim", "mccl", "--sim", "mccl", "1MN", "1MA1000", "1WS", "1TP",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let said = stdout(&out);
    let lines: Vec<&str> = said.lines().collect();
    assert_eq!(
        lines[..8],
        [
            "L1 module 0: ok",
            "L1 module 0: ok",
            "L1 module 0: ok",
            "L1 module 0: 1000",
            "L2 module 0: ok",
            "L2 module 0: ok",
            "L2 module 0: ok",
            "L2 module 0: 1000",
        ],
        "{said}"
    );
    assert!(lines[8].starts_with("link  module  firmware"), "{said}");
    assert_eq!(lines.last().copied(), Some("2 of 2 module(s) ok"), "{said}");

    // Each link's --address list is its modules; JSON lines carry the link.
    let out = axterm(&[
        "exec",
        "--sim",
        "tmcm1110",
        "--address",
        "1,2",
        "--sim",
        "tmcm1110",
        "--address",
        "5",
        "GAP 4, 0",
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let objects: Vec<serde_json::Value> = stdout(&out)
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON lines"))
        .collect();
    let said: Vec<(String, i64)> = objects[..3]
        .iter()
        .map(|o| {
            (
                o["link"].as_str().unwrap_or("").to_string(),
                o["module"].as_i64().unwrap_or(-1),
            )
        })
        .collect();
    assert_eq!(
        said,
        [("L1".into(), 1), ("L1".into(), 2), ("L2".into(), 5)],
        "{}",
        stdout(&out)
    );
    assert_eq!(objects[3]["ok"], true);
}

#[test]
fn a_line_bad_for_one_links_family_sends_nothing_on_any_link() {
    let out = axterm(&["exec", "--sim", "tmcm1110", "--sim", "mccl", "GAP 4, 0"]);
    assert_eq!(out.status.code(), Some(2), "{}", stdout(&out));
    assert!(stdout(&out).is_empty(), "{}", stdout(&out));
    let err = stderr(&out);
    assert!(
        err.contains("axterm exec: L2 (--sim mccl): line 1 `GAP 4, 0`"),
        "{err}"
    );
    assert!(err.contains("nothing was sent"), "{err}");

    // A command that works on one link still refuses several.
    let out = axterm(&["params", "export", "--sim", "mccl", "--sim", "mccl", "-"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("one link at a time"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_run_failing_on_two_links_ends_each_failing_module_with_the_stop_sequence() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("r.txt");
    std::fs::write(&file, "ROR 0, 500\n:expect GAP 4, 0 == 1\n").expect("write");
    let file = file.display().to_string();
    let out = axterm(&["run", "--sim", "tmcm1110", "--sim", "tmcm1110", &file]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    for label in ["L1", "L2"] {
        assert!(
            err.contains(&format!(
                "{label} module 1: {file}:2: expected GAP 4, 0 == 1, got 1000"
            )),
            "{err}"
        );
        // The stop sequence of the emergency-stop key, at that module.
        let stop = format!(
            "axterm run: {label} module 1: {file}: the run failed: stopping every axis:\n  MST 0 → ok\n"
        );
        assert!(err.contains(&stop), "{label}: {err}");
        let confirmed = format!(
            "axterm run: {label} module 1: {file}: stop confirmed: every stop line answered ok"
        );
        assert!(err.contains(&confirmed), "{label}: {err}");
    }
    let said = stdout(&out);
    assert!(
        said.contains("L1 module 1: ok") && said.contains("L2 module 1: ok"),
        "{said}"
    );
    let rows = table(&said);
    assert!(row(&rows, "L1").contains("FAILED"), "{said}");
    assert!(row(&rows, "L2").contains("FAILED"), "{said}");
    assert_eq!(rows.last().copied(), Some("0 of 2 module(s) ok"), "{said}");
}

#[test]
fn a_run_file_is_checked_for_every_link_before_any_is_opened() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("r.txt");
    std::fs::write(&file, "GAP 4, 0\n").expect("write");
    let file = file.display().to_string();
    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        "--port",
        "/nonexistent/tty",
        "--protocol",
        "mccl",
        &file,
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stdout(&out));
    assert!(stdout(&out).is_empty(), "{}", stdout(&out));
    let err = stderr(&out);
    assert!(
        err.contains(&format!("L2 (--port /nonexistent/tty): {file}:1: ")),
        "the bad line named with its link: {err}"
    );
    assert!(err.contains("nothing was sent"), "{err}");

    let out = axterm(&[
        "run",
        "--dry-run",
        "--sim",
        "tmcm1110",
        "--sim",
        "tmcm1110",
        &file,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("1 console lines valid on 2 links, nothing sent (dry run)"),
        "{}",
        stderr(&out)
    );
}
