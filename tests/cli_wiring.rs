//! `axterm wiring`: the wiring check from the command line on the CMD-4CR
//! simulator's stage (end switches at ±100000): each switch fires for its
//! own direction (exit 0); without --yes nothing moves (exit 2). With the
//! stage's limits swapped (`--input LIMITS=swapped`) on the CMD-4CR and
//! TMCM-1110 simulators, moving + trips the − switch: said, exit 1.

mod cli_support;

use cli_support::{axterm, stderr, stdout};

#[test]
fn the_check_reports_each_switch_for_its_own_direction() {
    let out = axterm(&["wiring", "--sim", "cmd4cr", "--speed", "500000", "--yes"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let said = stdout(&out);
    let lines: Vec<&str> = said.lines().collect();
    assert_eq!(
        lines[0],
        "X, moving +: the + (right) switch fired at 100000, as it should; the module stopped \
         the axis at it",
        "{said}"
    );
    assert!(
        lines[1].starts_with("X, moving -: the − (left) switch fired at -100000"),
        "{said}"
    );
    assert!(lines[2].starts_with("X: the home switch"), "{said}");
}

#[test]
fn without_yes_nothing_moves_and_a_bad_axis_is_named() {
    let out = axterm(&["wiring", "--sim", "cmd4cr"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("give --yes to go ahead (nothing was sent)"));
    let out = axterm(&["wiring", "--sim", "tmcm1110", "--axis", "3", "--yes"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--axis 3: the tmcl family has axes 0..0"));
}

#[test]
fn swapped_limits_on_the_cmd4cr_are_said_and_exit_1() {
    let out = axterm(&[
        "wiring",
        "--sim",
        "cmd4cr",
        "--input",
        "LIMITS=swapped",
        "--speed",
        "500000",
        "--yes",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let said = stdout(&out);
    let lines: Vec<&str> = said.lines().collect();
    assert!(
        lines[0].starts_with("X, moving + tripped the − (left) switch at 1")
            && lines[0].ends_with(": swapped wiring or inverted direction"),
        "{said}"
    );
    // At the + end the − limit is on: the module refuses the − jog.
    assert!(
        lines[1].starts_with("X, moving -: the module refused to move (")
            && lines[1].contains("-Limit"),
        "{said}"
    );
}

#[test]
fn swapped_limits_on_the_tmcm1110_are_said_and_exit_1() {
    let out = axterm(&[
        "wiring",
        "--sim",
        "tmcm1110",
        "--input",
        "LIMITS=swapped",
        "--speed",
        "2047",
        // 2047 reaches the + end (200000) in about 3.5 s.
        "--give-up",
        "6",
        "--yes",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let said = stdout(&out);
    let lines: Vec<&str> = said.lines().collect();
    assert!(
        // Where it fired is read on the wall clock here: any position.
        lines[0].starts_with("motor 0, moving + tripped the − (left) switch at ")
            && lines[0].ends_with(": swapped wiring or inverted direction"),
        "{said}"
    );
    assert!(lines[1].starts_with("motor 0, moving -: "), "{said}");
    assert!(lines[2].starts_with("motor 0: the home switch"), "{said}");
}

#[test]
fn a_wiring_value_that_is_neither_is_named() {
    let out = axterm(&[
        "wiring",
        "--sim",
        "cmd4cr",
        "--input",
        "LIMITS=crossed",
        "--yes",
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("LIMITS takes one of right, swapped (or 0..1), not `crossed`"),
        "{}",
        stderr(&out)
    );
}
