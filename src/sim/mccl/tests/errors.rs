//! Every error code of Ch14 from the input that causes it (the causes are
//! the simulator's reading: see `choices`).

use super::*;
use crate::sim::mccl::errors::CODES;

/// A session with axes 1 and 2 on, in one contour group.
fn contour_session() -> Session {
    let mut s = Session::new();
    s.quiet(&["1MN,2MN,3MN", "1CM1,2CM1"]);
    s
}

#[test]
fn every_code_of_chapter_14_has_its_input() {
    let mut s = contour_session();
    let cases: &[(&str, i32)] = &[
        ("1XX5", 1),
        ("1M", 1),
        ("1MA1.2.3", 2),
        ("LU5", 2),
        ("1DI2", -1),
        ("PC256", -1),
        ("LP1.5", -1),
        ("AR1000", -1),
        ("5SG.1", -2),
        ("1FE0", -2),
        ("5FI0", -2),
        ("RP-1", -3),
        ("3MN,MD5,NO", -4),
        ("MD1000,NO", -5),
        ("MC-1", -5),
        ("MC10", -6),
        ("3MN,1CP1,1MA10", -8),
        ("1CA100", -8),
        ("3CP1,3MA100", -9),
        ("1CP1,1CA100,1MA100", -9),
        ("1CP1,MA100", -10),
        ("TP", -14),
        ("MR100", -14),
        ("6MN", -15),
        ("9TP", -15),
        ("2CM3", -16),
        ("1CP1,1MA5,1MA6", -17),
        ("3SM3", -17),
        ("LU\"NOSUCH\"", -19),
        ("ET99", -20),
        ("1EI9", -21),
    ];
    for &(line, code) in cases {
        assert_eq!(s.error(line), code, "{line}");
    }
    // 3: a byte that is no text.
    assert_eq!(s.typed("1T\u{2}P\r"), "1T\u{2}P\r\n?3 1T\u{2}P\r\n>");
    // 4: too long.
    assert!(
        s.typed(&format!("{}\r", "NO,".repeat(300)))
            .ends_with("?4\r\n>")
    );
    // -7: Escape.
    s.typed("WA5\r");
    assert_eq!(s.typed("\x1b"), "?-7 WA5\r\n>");
    // -13: a move on an axis that tripped.
    s.quiet(&["3SE10,3SV100000,3MR100000"]);
    s.advance_ms(100);
    assert_eq!(s.error("3MR100"), -13);
    // -18: a macro over 255 bytes.
    let long = vec!["1WS.5"; 26].join(",");
    assert_eq!(s.error(&format!("MD7,{long}")), -18);
    // -21: a reporting command in a background task ends it.
    s.quiet(&["GT0,1TP"]);
    s.advance_ms(5);
    assert_eq!(s.sim.task_count(), 0);
    // Every code of the table was met (0 is no error; 3, 4, -7, -13,
    // -18 above).
    let met: Vec<i32> = cases
        .iter()
        .map(|c| c.1)
        .chain([3, 4, -7, -13, -18])
        .collect();
    for (code, meaning) in CODES {
        assert!(
            code.0 == 0 || met.contains(&code.0),
            "{} {meaning} not produced",
            code.0
        );
    }
}

#[test]
fn an_error_stops_the_rest_of_the_line_and_te_tells_it() {
    let mut s = Session::new();
    assert_eq!(s.line("AL1,AR100,MC10,AL2,AR100"), ["?-6 MC10"]);
    assert_eq!(s.line("TR100"), ["01 1"], "nothing after the error ran");
    // A line that cannot be read runs not at all.
    assert_eq!(s.line("AL3,AR100,1XX"), ["?1 1XX"]);
    assert_eq!(s.line("TR100"), ["01 1"]);
    assert_eq!(s.one("TE"), "1");
    assert_eq!(s.line("MC10"), ["?-6 MC10"]);
    assert_eq!(s.one("TE"), "-6");
}

#[test]
fn the_ch14_example_mc10_after_rm_is_minus_6() {
    // Ch14: RM, then a line turning three motors on and calling MC10: -6.
    let mut s = Session::new();
    s.quiet(&["MD10,NO", "RM"]);
    assert_eq!(s.line("1MN,2MN,3MN,MC10"), ["?-6 MC10"]);
    assert_eq!(s.status(3) & 2, 2, "the motors before it came on");
}

#[test]
fn a_real_register_where_an_integer_is_due_is_rounded() {
    // Ch4: "If a floating point indirect parameter is used for a command
    // that does not support floating point parameters (e.g. CN, LM, PC,...),
    // the register contents will be rounded".
    let mut s = Session::new();
    s.quiet(&["AL33.6,AR100", "CN@100"]);
    assert!(s.sim.io().is_on(34));
    assert_eq!(s.error("CN33.6"), -1, "typed, a real is a parameter error");
}
