//! A file with nothing in it is an error, never a success: a download of
//! an empty program, a parameter file with no settings (or cut off after a
//! section header) and a run file with no line all exit 2, say what the
//! file lacks, and send nothing, on every family's simulator.

mod cli_support;

use std::path::Path;
use std::process::Output;

use axterm::families::FAMILIES;
use cli_support::{axterm, stderr, stdout};

/// Each family's first simulator (`tmcm1110`, `sixpack2`, …).
fn simulators() -> Vec<&'static str> {
    families().into_iter().map(|(_, kind)| kind).collect()
}

/// Each family's name and its first simulator.
fn families() -> Vec<(&'static str, &'static str)> {
    FAMILIES
        .iter()
        .filter_map(|family| Some((family.name, family.simulators.first()?.name)))
        .collect()
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    path.to_string_lossy().into_owned()
}

fn assert_refused(out: &Output, what: &str, expected: &str) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{what}: {err}");
    assert!(
        err.contains(expected),
        "{what}: `{expected}` not in:\n{err}"
    );
    assert!(err.contains("nothing was sent"), "{what}: {err}");
}

#[test]
fn an_empty_program_is_not_downloaded_in_any_family() {
    let dir = tempfile::tempdir().expect("temp dir");
    let empty = write(dir.path(), "empty.txt", "");
    let blank = write(dir.path(), "blank.txt", "\n\n   \n");
    for kind in simulators() {
        for file in [&empty, &blank] {
            let out = axterm(&["download", "--sim", kind, file]);
            let what = format!("download --sim {kind} {file}");
            // TMCL and MCCL refuse the empty program, SIXpack 2 and
            // CMD-4CR take no download at all: none says it was done.
            assert_eq!(out.status.code(), Some(2), "{what}: {}", stderr(&out));
            assert!(
                !stdout(&out).contains("verified"),
                "{what}: {}",
                stdout(&out)
            );
        }
    }
    let out = axterm(&["download", "--sim", "tmcm1110", &empty]);
    assert_refused(
        &out,
        "tmcl",
        "empty.txt: the program holds nothing to download",
    );
    let out = axterm(&["download", "--sim", "mccl", &blank]);
    assert_refused(
        &out,
        "mccl",
        "blank.txt: the program holds nothing to download",
    );
}

#[test]
fn a_parameter_file_without_settings_is_refused_by_diff_and_apply() {
    let dir = tempfile::tempdir().expect("temp dir");
    let empty = write(dir.path(), "empty.toml", "");
    for (family, kind) in families() {
        let only_family = write(
            dir.path(),
            &format!("{kind}-family.toml"),
            &format!("family = \"{family}\"\n"),
        );
        for command in ["diff", "apply"] {
            for file in [&empty, &only_family] {
                let out = axterm(&["params", command, "--sim", kind, file]);
                assert_refused(
                    &out,
                    &format!("params {command} --sim {kind} {file}"),
                    "holds no settings",
                );
                assert!(!stdout(&out).contains("0 differ"), "{}", stdout(&out));
            }
        }
    }
}

#[test]
fn a_parameter_file_cut_after_a_section_header_is_not_identical() {
    let dir = tempfile::tempdir().expect("temp dir");
    for kind in simulators() {
        let whole = dir.path().join(format!("{kind}.toml"));
        let whole = whole.to_string_lossy().into_owned();
        let out = axterm(&["params", "export", "--sim", kind, &whole]);
        assert_eq!(out.status.code(), Some(0), "{kind}: {}", stderr(&out));
        let text = std::fs::read_to_string(&whole).expect("exported");
        // Cut right after the last section's header line.
        let header = text.rfind("\n[").expect("a section") + 1;
        let end = header + text[header..].find('\n').expect("header line") + 1;
        let cut = write(dir.path(), &format!("{kind}-cut.toml"), &text[..end]);
        for command in ["diff", "apply"] {
            let out = axterm(&["params", command, "--sim", kind, &cut]);
            assert_refused(
                &out,
                &format!("params {command} --sim {kind} (cut)"),
                "has no settings under it (is the file cut short?)",
            );
        }
        // Cut cleanly after its first setting: it cannot be told from a
        // shorter file, but what it leaves out is said.
        let Some(first) = text
            .lines()
            .position(|line| line.starts_with(|c: char| c.is_ascii_digit()))
        else {
            continue; // SIXpack 2: no setting is known to a new session.
        };
        let kept: Vec<&str> = text.lines().take(first + 1).collect();
        let short = write(
            dir.path(),
            &format!("{kind}-short.toml"),
            &(kept.join("\n") + "\n"),
        );
        let out = axterm(&["params", "diff", "--sim", kind, &short]);
        assert_eq!(out.status.code(), Some(0), "{kind}: {}", stderr(&out));
        assert!(
            stderr(&out).contains(" gives 1 of the module's "),
            "{kind}: {}",
            stderr(&out)
        );
    }
}

#[test]
fn an_empty_run_file_is_refused_by_every_runner() {
    let dir = tempfile::tempdir().expect("temp dir");
    let empty = write(dir.path(), "empty.txt", "");
    let comments = write(
        dir.path(),
        "comments.txt",
        "# nothing yet\n\n// still nothing\n",
    );
    for kind in simulators() {
        for file in [&empty, &comments] {
            let out = axterm(&["run", "--sim", kind, file]);
            assert_refused(&out, &format!("run --sim {kind} {file}"), "no line to run");
            let out = axterm(&["run", "--dry-run", "--sim", kind, file]);
            assert_refused(&out, &format!("run --dry-run {kind}"), "no line to run");
        }
    }
    let blank = write(dir.path(), "blank.txt", "\n  \n");
    for file in [&empty, &blank] {
        let out = axterm(&["run-macro", "--sim", "sixpack2", file]);
        assert_refused(&out, "run-macro", "nothing to play");
        let out = axterm(&["run-ascript", "--sim", "cmd4cr", file]);
        assert_refused(&out, "run-ascript", "nothing to run");
    }
}
