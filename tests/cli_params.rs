//! `axterm params export|diff|apply` as a script sees it: the file the
//! console's parameter pane writes, compared with and applied to a module
//! over a real pseudo-terminal (`axterm sim KIND --pty`, which keeps its
//! state from one command to the next), and checked afterwards with
//! `axterm exec`, not with the code under test.

mod cli_support;
mod served_support;

use cli_support::{axterm, stderr, stdout};
use served_support::Served;

/// A file in a temporary directory.
fn file_with(dir: &tempfile::TempDir, name: &str, text: &str) -> String {
    let path = dir.path().join(name);
    std::fs::write(&path, text).expect("write the file");
    path.display().to_string()
}

fn code(out: &std::process::Output) -> Option<i32> {
    out.status.code()
}

/// `axterm exec --port PTY LINE` → its one value.
fn read_on(pty: &str, protocol: &str, line: &str) -> String {
    let out = axterm(&["exec", "--port", pty, "--protocol", protocol, line]);
    assert_eq!(code(&out), Some(0), "{line}: {}", stderr(&out));
    stdout(&out).trim().to_string()
}

#[test]
fn tmcl_export_diff_apply_and_diff_again_on_a_served_module() {
    let served = Served::start("tmcm1110", &[]);
    let dir = tempfile::tempdir().expect("temp dir");
    let exported = dir.path().join("m.toml").display().to_string();
    let out = axterm(&["params", "export", "--port", &served.pty, &exported]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let text = std::fs::read_to_string(&exported).expect("exported");
    assert!(text.contains("family = \"tmcl\""), "{text}");
    assert!(text.contains("# firmware 1110V112"), "{text}");
    assert!(
        text.contains("4 = 1000  # Maximum positioning speed"),
        "{text}"
    );

    // Nothing differs from what was just read.
    let out = axterm(&["params", "diff", "--port", &served.pty, &exported]);
    assert_eq!(code(&out), Some(0), "{}{}", stdout(&out), stderr(&out));
    assert!(stdout(&out).contains(": 0 differ, 0 failed to read"));

    let edited = text
        .replace("\n4 = 1000  #", "\n4 = 777  #")
        .replace("\n6 = 128  #", "\n6 = 100  #");
    let file = file_with(&dir, "edited.toml", &edited);
    let out = axterm(&["params", "diff", "--port", &served.pty, &file]);
    assert_eq!(code(&out), Some(1), "differences exit 1: {}", stderr(&out));
    let said = stdout(&out);
    assert!(
        said.contains("[axis.0] 4 Maximum positioning speed: module 1000, file 777"),
        "{said}"
    );
    assert!(said.contains("2 differ"), "{said}");
    assert_eq!(
        read_on(&served.pty, "tmcl", "GAP 4, 0"),
        "1000",
        "diff wrote"
    );

    let out = axterm(&["params", "apply", "--port", &served.pty, &file]);
    assert_eq!(code(&out), Some(0), "{}{}", stdout(&out), stderr(&out));
    let said = stdout(&out);
    assert!(
        said.contains("SAP 4, 0, 777  [axis.0] 4 Maximum positioning speed: 1000 -> 777  verified"),
        "{said}"
    );
    assert!(
        said.contains("wrote 2, verified 2"),
        "only what differs: {said}"
    );
    assert_eq!(read_on(&served.pty, "tmcl", "GAP 4, 0"), "777");
    assert_eq!(read_on(&served.pty, "tmcl", "GAP 6, 0"), "100");

    let out = axterm(&["params", "diff", "--port", &served.pty, &file]);
    assert_eq!(code(&out), Some(0), "{}", stdout(&out));
    let out = axterm(&["params", "apply", "--port", &served.pty, &file]);
    assert_eq!(code(&out), Some(0));
    assert!(stdout(&out).contains("wrote 0"), "{}", stdout(&out));
}

#[test]
fn a_dry_run_plans_and_writes_nothing() {
    let served = Served::start("tmcm1110", &[]);
    let dir = tempfile::tempdir().expect("temp dir");
    let file = file_with(
        &dir,
        "p.toml",
        "family = \"tmcl\"\n[axis.0]\n4 = 555\n5 = 100\n",
    );
    let out = axterm(&["params", "apply", "--port", &served.pty, &file, "--dry-run"]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let said = stdout(&out);
    assert!(said.contains("SAP 4, 0, 555"), "{said}");
    assert!(said.contains("not sent (dry run)"), "{said}");
    assert!(
        said.contains("1 to write (dry run: nothing sent), 1 already the same"),
        "{said}"
    );
    assert_eq!(read_on(&served.pty, "tmcl", "GAP 4, 0"), "1000");
}

#[test]
fn store_keeps_the_values_in_eeprom_only_when_asked() {
    let served = Served::start("tmcm1110", &[]);
    let dir = tempfile::tempdir().expect("temp dir");
    let file = file_with(&dir, "p.toml", "[axis.0]\n4 = 600\n");
    let out = axterm(&["params", "apply", "--port", &served.pty, &file]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    assert!(!stdout(&out).contains("STAP"), "{}", stdout(&out));
    // Without --store the EEPROM still has the factory value: restoring
    // it brings that back.
    let out = axterm(&["exec", "--port", &served.pty, "RSAP 4, 0", "GAP 4, 0"]);
    assert_eq!(stdout(&out), "ok\n1000\n", "{}", stderr(&out));

    let out = axterm(&["params", "apply", "--port", &served.pty, &file, "--store"]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("STAP 4, 0  stored"),
        "{}",
        stdout(&out)
    );
    let out = axterm(&[
        "exec",
        "--port",
        &served.pty,
        "SAP 4, 0, 5",
        "RSAP 4, 0",
        "GAP 4, 0",
    ]);
    assert_eq!(stdout(&out), "ok\nok\n600\n", "{}", stderr(&out));
}

#[test]
fn a_bad_file_sends_nothing_and_names_the_parameter() {
    let dir = tempfile::tempdir().expect("temp dir");
    // A port that cannot exist: had anything been sent, opening it would
    // have failed with exit 3.
    let no_port = ["--port", "/nonexistent/tty"];
    let range = file_with(&dir, "r.toml", "[axis.0]\n4 = 1000\n6 = 300\n");
    for command in ["diff", "apply"] {
        let mut args = vec!["params", command];
        args.extend(no_port);
        args.push(&range);
        let out = axterm(&args);
        assert_eq!(code(&out), Some(2), "{}", stderr(&out));
        let err = stderr(&out);
        assert!(
            err.contains("[axis.0] 6 Maximum current: 300 is outside 0..255"),
            "{err}"
        );
        assert!(err.contains("nothing was sent"), "{err}");
    }
    let other = file_with(&dir, "o.toml", "family = \"cmd4cr\"\n[axis.0]\n5120 = 1\n");
    let out = axterm(&["params", "apply", "--port", "/nonexistent/tty", &other]);
    assert_eq!(code(&out), Some(2));
    assert!(
        stderr(&out).contains("it holds cmd4cr parameters; this module speaks tmcl"),
        "{}",
        stderr(&out)
    );
    let broken = file_with(&dir, "b.toml", "[axis.0]\n4 = = 1\n");
    let out = axterm(&["params", "diff", "--port", "/nonexistent/tty", &broken]);
    assert_eq!(code(&out), Some(2));
    assert!(
        stderr(&out).contains("is not a parameter file: line 2"),
        "{}",
        stderr(&out)
    );
    let unknown = file_with(&dir, "u.toml", "[axis.0]\n1 = 5\n999 = 1\n");
    let out = axterm(&["params", "apply", "--port", "/nonexistent/tty", &unknown]);
    assert_eq!(code(&out), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains("[axis.0] 1 Actual position: not a setting"),
        "{err}"
    );
    assert!(err.contains("[axis.0] 999: no such parameter"), "{err}");
}

#[test]
fn json_gives_every_value_and_its_outcome() {
    let served = Served::start("tmcm1110", &[]);
    let dir = tempfile::tempdir().expect("temp dir");
    let file = file_with(&dir, "p.toml", "[axis.0]\n4 = 1234\n5 = 100\n");
    let out = axterm(&[
        "params",
        "apply",
        "--port",
        &served.pty,
        &file,
        "--format",
        "json",
    ]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let object: serde_json::Value =
        serde_json::from_str(stdout(&out).trim()).expect("one JSON object");
    assert_eq!(object["module"], 1);
    assert_eq!(object["firmware"], "1110V112");
    assert_eq!(object["written"], 1);
    assert_eq!(object["verified"], 1);
    assert_eq!(object["same"], 1);
    assert_eq!(object["ok"], true);
    let value = &object["values"][0];
    assert_eq!(value["scope"], "axis.0");
    assert_eq!(value["number"], 4);
    assert_eq!(value["module"], 1000);
    assert_eq!(value["file"], 1234);
    assert_eq!(value["line"], "SAP 4, 0, 1234");
    assert_eq!(value["outcome"], "verified");

    let out = axterm(&[
        "params",
        "export",
        "--port",
        &served.pty,
        "-",
        "--format",
        "json",
    ]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    let last = stdout(&out).lines().last().unwrap_or("").to_string();
    let object: serde_json::Value = serde_json::from_str(&last).expect("JSON after the file");
    assert_eq!(object["ok"], true);
    assert!(stdout(&out).contains("4 = 1234  # Maximum positioning speed"));
}

#[test]
fn cmd4cr_applies_verifies_and_stores_once() {
    let served = Served::start("cmd4cr", &[]);
    let dir = tempfile::tempdir().expect("temp dir");
    // 5120 is HSPD of X and of Y (not kept by STORE), 9216 POL (Table
    // 2-19: kept).
    let file = file_with(
        &dir,
        "c.toml",
        "family = \"cmd4cr\"\n[axis.0]\n5120 = 3000\n9216 = 5\n[axis.1]\n5120 = 4000\n",
    );
    let out = axterm(&[
        "params",
        "diff",
        "--port",
        &served.pty,
        "--protocol",
        "cmd4cr",
        &file,
    ]);
    assert_eq!(code(&out), Some(1), "{}{}", stdout(&out), stderr(&out));
    let out = axterm(&[
        "params",
        "apply",
        "--port",
        &served.pty,
        "--protocol",
        "cmd4cr",
        &file,
        "--store",
    ]);
    assert_eq!(code(&out), Some(0), "{}{}", stdout(&out), stderr(&out));
    let said = stdout(&out);
    assert!(said.contains("wrote 3, verified 3"), "{said}");
    assert_eq!(said.matches("STORE  stored").count(), 1, "{said}");
    assert!(said.contains("2 not kept by a store"), "{said}");
    assert_eq!(read_on(&served.pty, "cmd4cr", "HSPDX"), "3000");
    let out = axterm(&[
        "params",
        "diff",
        "--port",
        &served.pty,
        "--protocol",
        "cmd4cr",
        &file,
    ]);
    assert_eq!(code(&out), Some(0), "{}", stdout(&out));
}

#[test]
fn mccl_applies_and_diffs_one_board_and_has_no_store_nor_addresses() {
    let served = Served::start("mccl", &[]);
    let dir = tempfile::tempdir().expect("temp dir");
    // [axis.1] 0 is SV, the velocity of axis 1 (raw: thousandths).
    let file = file_with(
        &dir,
        "m.toml",
        "family = \"mccl\"\n[axis.1]\n0 = 50000000\n",
    );
    let connection = ["--port", served.pty.as_str(), "--protocol", "mccl"];
    let run = |extra: &[&str]| {
        let mut args: Vec<&str> = vec!["params"];
        args.extend(extra.iter().take(1));
        args.extend(connection);
        args.extend(extra.iter().skip(1));
        axterm(&args)
    };
    let out = run(&["diff", &file]);
    assert_eq!(code(&out), Some(1), "{}{}", stdout(&out), stderr(&out));
    let out = run(&["apply", &file]);
    assert_eq!(code(&out), Some(0), "{}{}", stdout(&out), stderr(&out));
    assert!(stdout(&out).contains("verified"), "{}", stdout(&out));
    let out = run(&["diff", &file]);
    assert_eq!(code(&out), Some(0), "{}{}", stdout(&out), stderr(&out));

    let out = run(&["apply", &file, "--store"]);
    assert_eq!(code(&out), Some(2));
    assert!(stderr(&out).contains("--store: MCCL keeps settings in the controller's RAM"));
    let out = run(&["apply", &file, "--addresses", "1-4"]);
    assert_eq!(code(&out), Some(2));
    assert!(
        stderr(&out).contains("the mccl family has no module address on its link"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn sixpack2_writes_what_it_cannot_read_back_and_says_so() {
    let dir = tempfile::tempdir().expect("temp dir");
    // $11 peak of motor 0, and $14 amax + vmax in one frame.
    let file = file_with(
        &dir,
        "s.toml",
        "family = \"sixpack2\"\n[axis.0]\n4097 = 128\n5121 = 100\n5122 = 400\n",
    );
    let out = axterm(&["params", "apply", "--sim", "sixpack2", &file]);
    assert_eq!(code(&out), Some(0), "{}{}", stdout(&out), stderr(&out));
    let said = stdout(&out);
    assert_eq!(said.matches("SetAMaxVMax 0 100 400").count(), 2, "{said}");
    let written = said
        .lines()
        .filter(|l| l.starts_with("Set") && l.ends_with("written, cannot be read back"));
    assert_eq!(written.count(), 3, "{said}");
    assert!(said.contains("wrote 3, verified 0"), "{said}");

    let out = axterm(&["params", "diff", "--sim", "sixpack2", &file]);
    assert_eq!(code(&out), Some(1), "unknown is not the same");
    assert!(stderr(&out).contains("3 cannot be read back: not known"));

    let out = axterm(&["params", "export", "--sim", "sixpack2", "-"]);
    assert_eq!(code(&out), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains("family = \"sixpack2\""));
    assert!(
        stderr(&out).contains("cannot be read back from the module and were not written"),
        "{}",
        stderr(&out)
    );
    let out = axterm(&["params", "apply", "--sim", "sixpack2", &file, "--store"]);
    assert_eq!(code(&out), Some(2));
    assert!(stderr(&out).contains("the SIXpack 2 has no command that stores"));
}

#[test]
fn every_module_asked_for_gets_a_row_and_stop_on_failure_says_who_was_not_tried() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = file_with(&dir, "p.toml", "[axis.0]\n4 = 900\n");
    // One simulated module at address 1: 2 and 3 do not answer.
    let out = axterm(&[
        "params",
        "apply",
        "--sim",
        "tmcm1110",
        "--addresses",
        "1-3",
        &file,
    ]);
    assert_eq!(code(&out), Some(1), "{}", stderr(&out));
    let said = stdout(&out);
    assert!(said.contains("module 1: SAP 4, 0, 900"), "{said}");
    let table: Vec<&str> = said
        .lines()
        .skip_while(|l| !l.starts_with("module  firmware"))
        .collect();
    assert_eq!(table.len(), 5, "{said}");
    assert!(
        table[1].contains("1110V112") && table[1].contains(" ok"),
        "{said}"
    );
    assert!(
        table[2].contains("FAILED  module 2 does not answer"),
        "{said}"
    );
    assert!(
        table[3].contains("FAILED  module 3 does not answer"),
        "{said}"
    );
    assert_eq!(table[4], "1 of 3 module(s) ok");

    let out = axterm(&[
        "params",
        "diff",
        "--sim",
        "tmcm1110",
        "--addresses",
        "2,1",
        "--stop-on-failure",
        "--format",
        "json",
        &file,
    ]);
    assert_eq!(code(&out), Some(1));
    let last = stdout(&out).lines().last().unwrap_or("").to_string();
    let object: serde_json::Value = serde_json::from_str(&last).expect("the table as JSON");
    assert_eq!(object["ok"], false);
    assert_eq!(object["modules"][0]["module"], 2);
    assert_eq!(object["modules"][0]["note"], "module 2 does not answer");
    assert_eq!(object["modules"][1]["module"], 1);
    assert_eq!(
        object["modules"][1]["note"],
        "not tried: --stop-on-failure after module 2 failed"
    );
}

/// What each family's simulator reports must round-trip: its own export
/// applies and compares with nothing refused and nothing differing (an
/// MCCL servo reports OB 0, which the table once refused as outside
/// `> 0`).
#[test]
fn every_family_applies_and_diffs_its_own_export_unchanged() {
    let mut round_tripped = Vec::new();
    for family in axterm::families::FAMILIES {
        for sim in family.simulators {
            let dir = tempfile::tempdir().expect("temp dir");
            let file = dir.path().join("exported.toml").display().to_string();
            let connection = ["--sim", sim.name];
            let run = |command: &str| {
                let mut args = vec!["params", command];
                args.extend(connection);
                args.push(&file);
                axterm(&args)
            };
            let out = run("export");
            assert_eq!(code(&out), Some(0), "{}: {}", sim.name, stderr(&out));
            let exported = format!("{}{}", stdout(&out), stderr(&out));
            if exported.contains("exported 0 settings") {
                // A module that reads back none of its settings (a fresh
                // SIXpack 2, §7) exports only commented rows: such a file
                // holds no settings, which apply and diff refuse as they
                // refuse an empty file, naming it, with nothing sent.
                assert!(
                    exported.contains("cannot be read back"),
                    "{}: {exported}",
                    sim.name
                );
                for command in ["apply", "diff"] {
                    let out = run(command);
                    assert_eq!(code(&out), Some(2), "{} {command}", sim.name);
                    assert!(
                        stderr(&out).contains("it holds no settings"),
                        "{} {command}: {}",
                        sim.name,
                        stderr(&out)
                    );
                }
                continue;
            }
            for command in ["apply", "diff"] {
                let out = run(command);
                let said = format!("{}{}", stdout(&out), stderr(&out));
                assert_eq!(code(&out), Some(0), "{} {command}: {said}", sim.name);
                assert!(
                    !said.contains("outside") && !said.contains("nothing was sent"),
                    "{} {command} refused part of its own file: {said}",
                    sim.name
                );
                assert!(
                    said.contains(" 0 differ") && said.contains(" 0 failed"),
                    "{} {command}: {said}",
                    sim.name
                );
            }
            let out = run("apply");
            assert!(
                stdout(&out).contains("wrote 0,"),
                "{}: nothing to write: {}",
                sim.name,
                stdout(&out)
            );
            round_tripped.push(family.name);
        }
    }
    for family in ["tmcl", "cmd4cr", "mccl"] {
        assert!(
            round_tripped.contains(&family),
            "{family}: {round_tripped:?}"
        );
    }
}
