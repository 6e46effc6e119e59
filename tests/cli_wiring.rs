//! `axterm wiring`: the wiring check from the command line on the CMD-4CR
//! simulator's stage (end switches at ±100000): each switch fires for its
//! own direction (exit 0); without --yes nothing moves (exit 2).

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
