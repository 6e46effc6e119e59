//! A run that ends with an axis still moving, in every family: it says
//! so and, unless the file says `:leave-moving`, ends as a failed run
//! does, with the stop sequence (exit 1), the axis read back at rest by a
//! second run on the same served simulator (`axterm sim KIND --pty`).

mod cli_support;
mod motion_support;
mod served_support;

use axterm::families::FAMILIES;
use cli_support::{axterm_stdin, stderr};
use motion_support::motion_of;
use served_support::Served;

fn run(served: &Served, family: &str, extra: &[&str], text: &str) -> std::process::Output {
    let mut args = vec!["run", "--port", &served.pty, "--protocol", family];
    args.extend_from_slice(extra);
    args.push("-");
    axterm_stdin(&args, text)
}

#[test]
fn a_run_that_leaves_an_axis_moving_is_stopped_unless_the_file_means_it() {
    for family in FAMILIES {
        let motion = motion_of(family);
        let kind = family.simulators.first().expect("a simulator").name;
        let served = Served::start(kind, &[]);

        let out = run(
            &served,
            family.name,
            &["--yes"],
            &format!("{}\n", motion.start),
        );
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{}: {err}", family.name);
        assert!(
            err.contains("still moves; the file does not say :leave-moving")
                && err.contains("the run failed: stopping every axis:"),
            "{}: {err}",
            family.name
        );
        let check = run(
            &served,
            family.name,
            &["--no-stop-on-failure"],
            &format!("{}\n", motion.wait_at_rest()),
        );
        assert_eq!(
            check.status.code(),
            Some(0),
            "{}: the axis still moves: {}",
            family.name,
            stderr(&check)
        );

        // A fresh controller: one after an emergency stop may refuse to
        // move until its error is cleared (CMD-4CR).
        let served = Served::start(kind, &[]);
        let out = run(
            &served,
            family.name,
            &["--yes"],
            &format!(":leave-moving\n{}\n", motion.start),
        );
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(0), "{}: {err}", family.name);
        assert!(
            err.contains("still moves, as the file means it to (:leave-moving)")
                && !err.contains("stopping every axis"),
            "{}: {err}",
            family.name
        );
        let check = run(
            &served,
            family.name,
            &["--no-stop-on-failure"],
            &format!(":expect {} == {}\n", motion.speed, motion.at_rest),
        );
        assert_eq!(
            check.status.code(),
            Some(1),
            "{}: the axis was meant to move on: {}",
            family.name,
            stderr(&check)
        );
    }
}

#[test]
fn a_run_that_only_reads_reads_nothing_more_at_its_end() {
    let served = Served::start("tmcm1110", &[]);
    let out = run(&served, "tmcl", &["--format", "json"], "GAP 3, 0\n");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stderr(&out), "");
    assert_eq!(cli_support::stdout(&out).lines().count(), 1);
}
