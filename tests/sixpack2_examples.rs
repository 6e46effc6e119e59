//! Every file of `examples/sixpack2/` (the SIXpack 2 manual's §5.5.3
//! reference-search configurations as `axterm run` files) runs clean
//! against the simulator the real binary serves (`axterm sim sixpack2
//! --pty`), each on a simulator of its own fresh from power-on: every
//! `:expect` holds. The files wait for the search with a `$28` whose
//! answer comes once the motor is idle, never for a time.

mod served_support;

use std::path::{Path, PathBuf};
use std::process::Command;

use served_support::Served;

fn examples() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sixpack2");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("examples/sixpack2")
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.extension().is_some_and(|e| e == "txt"))
        .collect();
    files.sort();
    files
}

fn run_served(file: &Path, yes: bool) -> std::process::Output {
    let served = Served::start("sixpack2", &[]);
    let mut command = Command::new(env!("CARGO_BIN_EXE_axterm"));
    command.args(["run", "--port", &served.pty, "--protocol", "sixpack2"]);
    if yes {
        command.arg("--yes");
    }
    command.arg(file).output().expect("run axterm run")
}

#[test]
fn every_example_runs_clean_against_the_served_simulator() {
    let runs: Vec<_> = examples()
        .into_iter()
        .map(|file| {
            std::thread::spawn(move || {
                let out = run_served(&file, true);
                (file, out)
            })
        })
        .collect();
    let mut failures = Vec::new();
    for run in runs {
        let (file, out) = run.join().expect("a run thread");
        if out.status.code() != Some(0) {
            failures.push(format!(
                "{}: exit {:?}\n{}{}",
                file.display(),
                out.status.code(),
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_reference_search_is_sent_only_with_yes() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sixpack2");
    let file = dir.join("5.5.3.2-mechanical-reference.txt");
    let out = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["run", "--sim", "sixpack2"])
        .arg(&file)
        .output()
        .expect("run axterm run");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(":8: `StartReferenceSearch 0`: not sent without --yes"),
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn there_is_a_file_for_every_configuration_of_5_5_3() {
    let names: Vec<String> = examples()
        .iter()
        .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    for section in 2..=4 {
        let prefix = format!("5.5.3.{section}-");
        assert!(
            names.iter().any(|n| n.starts_with(&prefix)),
            "§5.5.3.{section} missing: {names:?}"
        );
    }
}
