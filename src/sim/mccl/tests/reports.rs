//! The manual's worked replies (mccl-vectors.json, Ch8 and Ch13), each
//! after the setup that gives the state the manual describes, and the
//! text commands (VE, ID, HE, TM).

use super::*;
use crate::sim::mccl::axis::settings::AxisKind;

const VECTORS: &str = include_str!("../../../../tests/data/mccl-vectors.json");

/// The reply the manual prints for `send` in a section ending `section`.
fn manual_reply(section: &str, send: &str) -> String {
    let vectors: serde_json::Value = serde_json::from_str(VECTORS).expect("vectors");
    vectors
        .as_array()
        .expect("an array")
        .iter()
        .find(|v| {
            v["send"].as_str() == Some(send)
                && v["section"].as_str().is_some_and(|s| s.ends_with(section))
        })
        .and_then(|v| v["reply"].as_str())
        .unwrap_or_else(|| panic!("no vector {section} {send}"))
        .to_string()
}

/// The manual's examples that read axes 1 and 2 as steppers (AT, AZ).
fn stepper_machine() -> Session {
    let mut config = SimConfig::pci();
    config.axes = vec![AxisKind::Stepper, AxisKind::Stepper, AxisKind::Servo];
    Session::with(config)
}

#[test]
fn tell_replies_as_the_manual_prints_them() {
    // (section, the line sent, the setup before it, a different line sent
    // where the manual misprints it).
    let cases: &[(&str, &str, &[&str], Option<&str>)] = &[
        ("TB", "2TB.2", &["2IP21.68"], None),
        ("TD", "1SD.4", &["1SD.0032"], Some("1TD.4")),
        ("TG", "1TG.5", &["1SG.00032"], None),
        ("TL", "1TL.1", &["1IL5"], None),
        ("TQ", "1TQ.1", &[], None),
        ("TR", "TR0", &["AL15"], None),
        (
            "TO",
            "1TO.3",
            &["1US1000,1SV100,1SA200,1DS200,1MN,1MA121.025,1WS0.2"],
            None,
        ),
        (
            "TP",
            "1TP.3",
            &["1US1000,1SV100,1SA200,1DS200,1MN,1MA121.025,1WS0.2"],
            None,
        ),
        (
            "TT",
            "1TT.3",
            &["1US1000,1SV100,1SA200,1DS200,1MN,1MA121.025,1WS0.2"],
            None,
        ),
        ("TV", "1TV.2", &["1MN,1VM,1SV10,1GO,WA0.1"], None),
        ("TE", "TE", &["5SG.1"], None),
        (
            "GC",
            "1GC,TR0",
            &["1SE0,1MN,1LC0,1NC10,1BC0,1MA245,1WS"],
            None,
        ),
        (
            "TZ",
            "1TZ.3",
            &["1SE0,1US10,1DH1940.2,1MN,1IA0,1MR100,1WS"],
            None,
        ),
    ];
    for &(section, send, setup, sent) in cases {
        let mut s = Session::new();
        for line in setup {
            let lines = s.line(line);
            assert!(
                lines.iter().all(|l| !l.starts_with('?')) || send == "TE",
                "{line}: {lines:?}"
            );
        }
        let reply = s.line(sent.unwrap_or(send)).join("\n");
        assert_eq!(reply, manual_reply(section, send), "{section} {send}");
    }
}

#[test]
fn the_precision_example_with_bare_values() {
    // Ch8: position 123.4567 → 123, 123, 123.4, 123.456 (printed without
    // the axis field there: the TELLAXIS setting).
    let mut s = Session::new();
    s.drive("TELLAXIS=0");
    // SV/SA/DS are in user units too: 100000 counts/s, 200000 counts/s²,
    // what the simulated motor can follow (the defaults would be 10⁹).
    s.quiet(&["1US10000,1SV10,1SA20,1DS20,1SE0,1MN,1MA123.4567,1WS0.2"]);
    for send in ["1TP", "1TP0", "1TP.1", "1TP.3"] {
        assert_eq!(
            s.one(send),
            manual_reply("precision parameter p", send),
            "{send}"
        );
    }
}

#[test]
fn aux_encoder_tells_on_the_manuals_stepper_axes() {
    let mut s = stepper_machine();
    s.quiet(&["1AH9.762"]);
    assert_eq!(s.one("1AT.3"), manual_reply("AT", "1AT.3"));
    // AF arms the aux index: found on the mark, there it reads 21.7.
    s.quiet(&["2MN,2AF21.7,2MR1000,2WS"]);
    assert_eq!(s.line("2TS20"), ["02 1"], "aux index found");
    assert_eq!(s.one("2AZ.1"), manual_reply("AZ", "2AZ.1"));
}

#[test]
fn a_following_error_of_512_and_twelve_contour_moves() {
    let mut s = Session::new();
    s.quiet(&["1MN"]);
    s.drive("STALL1=1");
    s.quiet(&["1MR512,1WS"]);
    assert_eq!(s.one("1TF"), manual_reply("TF", "1TF"));
    let mut s = Session::new();
    s.quiet(&["1SE0,2SE0,1MN,2MN", "1CM1,2CM1"]);
    for _ in 0..12 {
        s.quiet(&["1CP1,1MR10,2MR10"]);
    }
    s.advance_ms(2000);
    assert_eq!(s.one("1TX"), manual_reply("TX", "1TX"));
}

#[test]
fn tc_reads_a_channel_and_the_status_example_of_dm_hm() {
    let mut s = Session::new();
    s.drive("IN3=1");
    assert_eq!(s.one("TC3"), manual_reply("TC", "TC3"));
    assert_eq!(s.one("TC0"), "00 4");
    s.quiet(&["1MN"]);
    assert_eq!(
        s.one("1TS"),
        manual_reply("DM", "1TS").lines().next().unwrap_or_default()
    );
}

#[test]
fn ve_is_the_manuals_text() {
    let mut s = Session::new();
    assert_eq!(s.line("VE").join("\n"), manual_reply("VE", "VE"));
}

#[test]
fn id0_of_a_stepper_says_what_the_manuals_screenshot_does() {
    // Ch8 ID: the surviving screenshot, one item a line here.
    let mut s = Session::new();
    assert_eq!(s.line("5ID0").join(" "), manual_reply("ID", "5ID0"));
    let servo = s.line("1ID0");
    assert_eq!(servo[0], "SERVO STATUS:");
    assert!(servo.contains(&"Not Looking For Index".to_string()));
    assert_eq!(s.error("ID0"), -14, "which axis?");
    s.quiet(&["MD1,WA1", "GT1"]);
    assert_eq!(s.line("ID7"), ["ACTIVE BACKGROUND TASKS: 1", "Task ID 1"]);
    assert_eq!(s.line("2ID6")[3], "Minus Limit (inp) 23");
}

#[test]
fn help_lists_mnemonics_and_describes_one() {
    let mut s = Session::new();
    let all = s.line("HE0").join(" ");
    assert!(all.contains("MA") && all.contains("RT"), "{all}");
    assert_eq!(s.line("HE\"ma\""), ["MA - Move Absolute"]);
    assert!(s.line("HE1").join(" ").contains("POSITION"));
    assert_eq!(s.error("HE\"zz\""), -1);
}

#[test]
fn status_words_read_through_lu_and_rl() {
    // Ch4: LU"STATUS",2RL@0 loads the status word of axis 2.
    let mut s = Session::new();
    s.quiet(&["2MN"]);
    let ts = s.status(2);
    assert_eq!(s.line("LU\"STATUS\",2RL@0,TR0"), [format!("02 {ts}")]);
    assert_eq!(s.error("LU\"STATUS\",RL@0"), -14);
    s.quiet(&["2SE0,2MA500,2WS0.1"]);
    assert_eq!(s.line("LU\"POSITION\",2RD@0,TR0"), ["02 500.000000"]);
    // Scratch memory: ME, WL, RL, FM.
    assert_eq!(
        s.line("ME100,AR100,AL1234,WL@100,AL0,RL@100,TR0"),
        ["01 1234"]
    );
    s.quiet(&["FM@100"]);
    assert_eq!(s.error("FM@100"), -1, "freed already");
}

/// Ch4's register table: `TRn.p` tells register n, `TR.p` the accumulator,
/// with p as the Tell commands' precision (Ch8: the tenths digit is the
/// number of decimals). Without a precision a register prints as before.
#[test]
fn tr_takes_a_register_and_a_precision() {
    let mut s = Session::new();
    assert_eq!(s.line("AL123.4567,AR5"), Vec::<String>::new());
    assert_eq!(s.line("TR5.3"), ["01 123.456"]);
    assert_eq!(s.line("TR.1"), ["01 123.4"], "the accumulator");
    assert_eq!(s.line("TR5"), ["01 123.456700"], "a real as %f");
    assert_eq!(s.line("AL15,AR7"), Vec::<String>::new());
    assert_eq!(s.line("TR7.2"), ["01 15.00"]);
    assert_eq!(s.line("TR7"), ["01 15"]);
    assert_eq!(s.line("TR7.7"), ["?-1 TR7.7"], "precision .1 … .5");
}
