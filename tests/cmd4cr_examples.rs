//! Every file of `examples/cmd4cr/` (the CMD-4CR manual's §4.3 worked
//! sequences as `axterm run` files) runs clean against the simulator the
//! real binary serves (`axterm sim cmd4cr --pty`), each on a simulator of
//! its own fresh from power-on: every `:expect` holds. A file whose
//! leading comments hold `# simulator: OPTIONS` gets a simulator started
//! with those options (`# simulator: --input IO5=1`, the §4.3.9 THEN
//! branch).
//!
//! The served simulator runs on the wall clock; the files wait for states
//! with `:wait-until` (reading the controller), never for a time.

mod served_support;

use std::path::{Path, PathBuf};
use std::process::Command;

use served_support::Served;

fn examples() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cmd4cr");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("examples/cmd4cr")
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.extension().is_some_and(|e| e == "txt"))
        .collect();
    files.sort();
    files
}

/// The options of the file's `# simulator:` line among its leading
/// comments, split at blanks; none without one.
fn simulator_options(file: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(file).expect("read the example");
    text.lines()
        .take_while(|line| line.starts_with('#'))
        .find_map(|line| line.strip_prefix("# simulator:"))
        .map(|options| options.split_whitespace().map(str::to_string).collect())
        .unwrap_or_default()
}

fn run_served(file: &Path, options: &[String]) -> std::process::Output {
    let options: Vec<&str> = options.iter().map(String::as_str).collect();
    let served = Served::start("cmd4cr", &options);
    Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["run", "--port", &served.pty, "--protocol", "cmd4cr"])
        .arg(file)
        .output()
        .expect("run axterm run")
}

#[test]
fn both_branches_of_4_3_9_are_shown_and_the_then_branch_needs_io5_on() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cmd4cr");
    assert!(simulator_options(&dir.join("4.3.9-io.txt")).is_empty());
    let on = dir.join("4.3.9-io-on.txt");
    assert_eq!(simulator_options(&on), ["--input", "IO5=1"]);
    // Without the input the THEN branch's first expectation fails.
    let out = run_served(&on, &[]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("expected IO5 == 1, got 0"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn there_is_a_file_for_every_worked_sequence_of_4_3() {
    let names: Vec<String> = examples()
        .iter()
        .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    for section in 1..=9 {
        let prefix = format!("4.3.{section}-");
        assert!(
            names.iter().any(|n| n.starts_with(&prefix)),
            "§4.3.{section} missing: {names:?}"
        );
    }
}

#[test]
fn every_example_runs_clean_against_the_served_simulator() {
    let runs: Vec<_> = examples()
        .into_iter()
        .map(|file| {
            std::thread::spawn(move || {
                let out = run_served(&file, &simulator_options(&file));
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
fn every_example_checks_clean_without_a_connection() {
    for file in examples() {
        let out = Command::new(env!("CARGO_BIN_EXE_axterm"))
            .args(["run", "--dry-run", "--protocol", "cmd4cr"])
            .arg(&file)
            .output()
            .expect("run axterm run --dry-run");
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}: {}",
            file.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
