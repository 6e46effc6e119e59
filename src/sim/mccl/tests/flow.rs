//! Sequencing (Ch12): If/Then "next or skip two", DF/DN, JP/JR, RP, BK,
//! waits; registers and accumulator arithmetic (Ch11); the axis carried
//! from command to command (Ch2).

use super::*;

#[test]
fn a_true_condition_runs_the_next_command_and_the_ones_after() {
    // Ch12 IE: "If the contents of the accumulator equals n, command
    // execution will continue with the command following the IE command.
    // Otherwise the two commands following the IE command will be skipped."
    let mut s = Session::new();
    assert_eq!(s.line("AL1,IE1,AL10,AL20,AR100,TR100"), ["01 20"]);
    assert_eq!(s.line("AL0,IE1,AL10,AL20,AR100,TR100"), ["01 0"]);
}

#[test]
fn each_conditional_tests_what_its_page_says() {
    let mut s = Session::new();
    // Each line leaves 1 in R100 if the condition held, else 2.
    let cases = [
        ("AL5,IB6", 1),
        ("AL5,IB5", 2),
        ("AL5,IG4", 1),
        ("AL5,IG5", 2),
        ("AL5,IU4", 1),
        ("AL5,IU5", 2),
        ("AL8,IS3", 1),
        ("AL8,IS2", 2),
        ("AL8,IC2", 1),
        ("AL8,IC3", 2),
        ("AL2.5,IE2.5", 1),
        ("AL2.5,IE2", 2),
        ("NO,IN5", 2),
        ("NO,IF5", 1),
    ];
    for (test, expected) in cases {
        let line = format!("{test},JR4,NO,AL2,JR2,AL1,AR100,TR100");
        assert_eq!(s.line(&line), [format!("01 {expected}")], "{test}");
    }
    s.drive("IN5=1");
    assert_eq!(s.line("NO,IN5,JR4,NO,AL2,JR2,AL1,AR100,TR100"), ["01 1"]);
}

#[test]
fn the_manuals_jump_to_macro_pattern() {
    // Ch9 IN: IN5,MJ10,NO,MJ11 — jump to macro 10 if input 5 is on, else 11.
    let mut s = Session::new();
    s.quiet(&["MD10,AL10,AR100", "MD11,AL11,AR100"]);
    s.quiet(&["IN5,MJ10,NO,MJ11"]);
    assert_eq!(s.line("TR100"), ["01 11"]);
    s.drive("IN5=1");
    s.quiet(&["IN5,MJ10,NO,MJ11"]);
    assert_eq!(s.line("TR100"), ["01 10"]);
}

#[test]
fn df_and_dn_skip_the_rest() {
    let mut s = Session::new();
    s.quiet(&["AL1,AR100,DN2,AL2,AR100"]);
    assert_eq!(s.line("TR100"), ["01 1"], "channel 2 off: the rest skipped");
    assert_eq!(s.line("DF2,AL3,AR100,TR100"), ["01 3"]);
}

#[test]
fn jumps_count_from_zero_and_from_themselves() {
    // Ch12 JP: "IE0,JP5,NO,1MR1000,1WS,1MR2000,1WS" jumps to 1MR2000.
    let mut s = Session::new();
    assert_eq!(s.line("AL0,AR100,JP4,AL1,AR100,TR100"), ["01 0"]);
    // JR-n loops: count to 5.
    assert_eq!(
        s.line("AL0,AA1,IG4,JR3,NO,JR-4,AR101,TR101"),
        ["01 5"],
        "a loop closed by JR"
    );
    assert_eq!(s.error("JP9"), -1);
    assert_eq!(s.error("NO,JR-2"), -1);
}

#[test]
fn rp_n_runs_everything_before_it_n_plus_1_times() {
    // Ch8 DR: "AL0,AR100" then "…,AL@100,AA1,AR100,RP9" walks 10 samples.
    let mut s = Session::new();
    s.quiet(&["AL0,AR100", "AL@100,AA1,AR100,RP9"]);
    assert_eq!(s.line("TR100"), ["01 10"]);
    // Ch12 WA: 1TP,WA0.1,RP9 — ten reports a tenth of a second apart.
    let exchange = s.exchange("1TP,WA0.1,RP9", 5000);
    assert_eq!(exchange.lines, vec!["01 0".to_string(); 10]);
    assert!((1000..=1010).contains(&exchange.ms), "{} ms", exchange.ms);
}

#[test]
fn rp_without_a_count_runs_until_escape() {
    // Ch2: 1TP,RP "The position will be displayed continuously ... until
    // stopped by the operator pressing the Escape key."
    let mut s = Session::new();
    s.typed("1TP,RP\r");
    let out = s.advance_ms(100);
    assert!(
        out.matches("01 0\r\n").count() > 100,
        "{} replies",
        out.matches('\n').count()
    );
    let abort = s.typed("\x1b");
    assert!(
        abort.ends_with("?-7 1TP\r\n>") || abort.ends_with("?-7 RP\r\n>"),
        "{abort:?}"
    );
    // The port is not flooded: at 11520 bytes/s, about 1150 bytes in 100 ms.
    assert!(out.len() < 1500, "{} bytes", out.len());
}

#[test]
fn bk_ends_the_macro_and_a_called_macro_returns() {
    // Ch7 FI's homing subroutines: MD21,…,IC25,BK,NO,JR-5 return to their
    // caller through BK.
    let mut s = Session::new();
    s.quiet(&["MD21,AL1,AR100,BK,AL2,AR100", "MD20,MC21,AL3,AR101"]);
    s.quiet(&["MC20"]);
    assert_eq!(s.line("TR100,TR101"), ["01 1", "01 3"]);
    s.quiet(&["AL7,BK,AL8,TR0"]);
}

#[test]
fn the_axis_carries_from_command_to_command_and_resets_per_line() {
    // Ch2: "the axis that a command acts on is assumed to be the last one
    // specified in the command string. Whenever a new command string is
    // entered, the axis is assumed to be 0 (all)".
    let mut s = Session::new();
    s.quiet(&["2MN,MR1000,WS,3MN,MR-500,WS"]);
    assert_eq!(s.tell("2TT"), 1000.0);
    assert_eq!(s.tell("3TT"), -500.0);
    assert_eq!(s.error("MR5"), -14, "a new line starts with no axis");
    // UA: the default axis for commands without one (Ch5 UA).
    s.quiet(&["UA2", "MR5"]);
    assert_eq!(s.tell("2TT"), 1005.0);
    // TR's field is the axis in force, here the default axis.
    assert_eq!(s.line("GU,TR0"), ["02 2"]);
    // A generic macro on the default axis (Ch5 UA example).
    s.quiet(&["MD10,MR1000", "UA3,MC10"]);
    assert_eq!(s.tell("3TT"), 500.0);
}

#[test]
fn register_arithmetic_follows_the_more_precise_type() {
    let mut s = Session::new();
    assert_eq!(s.line("AL7,AD2,TR0"), ["01 3"]);
    assert_eq!(s.line("AL7,AD2.0,TR0"), ["01 3.500000"]);
    assert_eq!(s.line("AL7.5,AA1,TR0"), ["01 8.500000"]);
    assert_eq!(s.line("AL7,AD0,TR0"), ["01 7"], "AD0 does nothing");
    assert_eq!(s.line("AL12,AN10,AO1,AE3,TR0"), ["01 10"]);
    assert_eq!(s.line("AL1,SL4,SR1,TR0"), ["01 8"]);
    assert_eq!(s.line("AL0,AC,TR0"), ["01 -1"]);
    assert_eq!(s.line("AL9,AV9,TR0"), ["01 3.000000"]);
    assert_eq!(s.line("AV22,AV25,TR0"), ["01 3"]);
    // Ch11 AA example: AL@100,AA5,AR101.
    s.quiet(&["AL40,AR100", "AL@100,AA5,AR101"]);
    assert_eq!(s.line("RA101,TR0"), ["01 45"]);
}

#[test]
fn wait_for_a_channel_and_for_a_time() {
    let mut s = Session::new();
    s.typed("WN7,AL1,AR100\r");
    s.advance_ms(50);
    assert!(s.sim.busy(), "waits for channel 7");
    s.drive("IN7=1");
    assert_eq!(s.advance_ms(2), ">");
    assert_eq!(s.line("TR100"), ["01 1"]);
    // UT changes the dwell unit (Ch5 UT).
    let exchange = s.exchange("UT0.001,WA100,UT1", 1000);
    assert!((100..=102).contains(&exchange.ms), "{} ms", exchange.ms);
}

#[test]
fn output_text_with_the_accumulator() {
    // Ch13 OT: register 200 holds the part count.
    let mut s = Session::new();
    s.quiet(&[
        "al0,ar200",
        "MD100,al@200,AA1,AR200,OT\"The part count = %d \\r\\n\"",
    ]);
    assert_eq!(
        s.line("MC100,MC100"),
        ["The part count = 1 ", "The part count = 2 "]
    );
    assert_eq!(s.line("AL2.5,OD\"%5.2f|\\r\\n\""), [" 2.50|"]);
}
