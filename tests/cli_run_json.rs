//! The JSON of a run holds every check: each `:expect` and `:wait-until`,
//! passing or failing, is an object with its line, the value expected, the
//! value read and `ok`, on every family's simulator; and a fleet's table
//! counts the lines done, never calling a read a write.

mod cli_support;

use axterm::families::FAMILIES;
use cli_support::{axterm, stderr, stdout};
use serde_json::Value;

/// A family's simulator, a line that sets a value, the line that reads it
/// back, the value it reads, and a value it does not read.
struct ReadBack {
    family: &'static str,
    sim: &'static str,
    set: &'static str,
    read: &'static str,
    value: &'static str,
    other: &'static str,
}

const READ_BACKS: &[ReadBack] = &[
    ReadBack {
        family: "tmcl",
        sim: "tmcm1110",
        set: "SAP 4, 0, 1000",
        read: "GAP 4, 0",
        value: "1000",
        other: "7",
    },
    ReadBack {
        family: "cmd4cr",
        sim: "cmd4cr",
        set: "POLX=5",
        read: "POLX",
        value: "5",
        other: "7",
    },
    ReadBack {
        family: "sixpack2",
        sim: "sixpack2",
        set: "# nothing to set: an axis at rest after power-on",
        read: "GetPositionAndActivity 0",
        value: "action=inactive",
        other: "action=ramp",
    },
    ReadBack {
        family: "mccl",
        sim: "mccl",
        set: "# nothing to set: the position after power-on",
        read: "1TP",
        value: "0",
        other: "7",
    },
];

fn objects(out: &std::process::Output) -> Vec<Value> {
    stdout(out)
        .lines()
        .map(|line| serde_json::from_str(line).expect("one JSON object a line"))
        .collect()
}

#[test]
fn every_expect_and_wait_until_is_an_object_in_every_family() {
    for family in FAMILIES {
        assert!(
            READ_BACKS.iter().any(|r| r.family == family.name),
            "no read-back line for {}",
            family.name
        );
    }
    let dir = tempfile::tempdir().expect("temp dir");
    for case in READ_BACKS {
        let (read, value, other) = (case.read, case.value, case.other);
        let file = dir.path().join(format!("{}.txt", case.sim));
        std::fs::write(
            &file,
            format!(
                "{}\n:expect {read} == {value}\n:wait-until {read} == {value} timeout 10s\n\
                 :expect {read} == {other}\n",
                case.set
            ),
        )
        .expect("write");
        let file = file.to_string_lossy().into_owned();
        let out = axterm(&[
            "run",
            "--sim",
            case.sim,
            "--format",
            "json",
            "--keep-going",
            "--no-stop-on-failure",
            &file,
        ]);
        let sim = case.sim;
        assert_eq!(out.status.code(), Some(1), "{sim}: {}", stderr(&out));
        let checks: Vec<Value> = objects(&out)
            .into_iter()
            .filter(|o| o.get("directive").is_some())
            .collect();
        assert_eq!(checks.len(), 3, "{sim}: {}", stdout(&out));
        let expected = [
            ("expect", 2, value, true),
            ("wait-until", 3, value, true),
            ("expect", 4, other, false),
        ];
        for (check, (directive, line_number, wanted, ok)) in checks.iter().zip(expected) {
            assert_eq!(check["directive"], directive, "{sim}: {check}");
            assert_eq!(check["line"], read, "{sim}: {check}");
            assert_eq!(check["line_number"], line_number, "{sim}: {check}");
            assert_eq!(check["expected"], wanted, "{sim}: {check}");
            assert_eq!(check["ok"], ok, "{sim}: {check}");
            let actual = match &check["actual"] {
                Value::String(text) => text.clone(),
                other => other.to_string(),
            };
            assert!(actual.contains(value), "{sim}: {check}");
        }
    }
}

#[test]
fn a_fleet_run_marks_each_check_with_its_module() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("r.txt");
    std::fs::write(&file, ":expect GAP 4, 0 == 1000\n").expect("write");
    let file = file.to_string_lossy().into_owned();
    let out = axterm(&[
        "run",
        "--sim",
        "tmcm1110",
        "--addresses",
        "1",
        "--format",
        "json",
        &file,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let said = objects(&out);
    let check = said
        .iter()
        .find(|o| o.get("directive").is_some())
        .expect("the check's object");
    assert_eq!(check["module"], 1, "{check}");
    assert_eq!(check["actual"], 1000, "{check}");
    assert_eq!(check["ok"], true, "{check}");
    let table = said.last().expect("the table");
    assert_eq!(table["modules"][0]["lines"], 1, "{table}");
    assert!(table["modules"][0].get("written").is_none(), "{table}");
}

#[test]
fn a_fleet_exec_counts_a_read_as_a_line_not_a_write() {
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
    let said = objects(&out);
    let table = said.last().expect("the table");
    assert_eq!(table["modules"][0]["lines"], 1, "{table}");
    assert_eq!(table["modules"][0]["failed"], 0, "{table}");
    assert!(table["modules"][0].get("written").is_none(), "{table}");
}
