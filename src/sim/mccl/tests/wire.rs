//! The port: echo, prompt, repeat, Escape and Space, the wire settings.

use super::*;
use crate::sim::mccl::link::DEFAULT_PROMPT;

#[test]
fn a_move_and_a_tell_as_the_acceptance_sends_them() {
    // Ch2: 1MN, 1MA1000, 1WS, 1TP; a servo lands within its deadband (DB 5).
    let mut s = Session::new();
    assert_eq!(s.typed("1MN\r"), "1MN\r\n>");
    assert_eq!(s.typed("1MA1000\r"), "1MA1000\r\n>");
    assert_eq!(
        s.typed("1WS\r"),
        "1WS\r\n",
        "WS blocks until the trajectory is complete"
    );
    let rest = s.advance_ms(300);
    assert_eq!(rest, ">");
    let reply = s.typed("1TP\r");
    let value: f64 = reply
        .strip_prefix("1TP\r\n01 ")
        .and_then(|r| r.strip_suffix("\r\n>"))
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{reply:?}"));
    assert!((value - 1000.0).abs() <= 5.0, "{value}");
    s.advance_ms(100);
    assert_eq!(s.one("1TP"), "01 1000", "settled on the target");
}

#[test]
fn a_bare_cr_repeats_the_last_line_until_another_key() {
    // Ch2: "All command strings are retained by the controller until some
    // character other than an Enter key is pressed."
    let mut s = Session::new();
    s.quiet(&["AL5"]);
    assert_eq!(s.line("AA1,TR0"), ["01 6"]);
    assert_eq!(s.typed_through("\r"), "\r\n01 7\r\n>");
    assert_eq!(s.typed_through("\r"), "\r\n01 8\r\n>");
    assert_eq!(
        s.typed("x\x08\r"),
        "x\x08 \x08\r\n>",
        "a key, erased: nothing to repeat"
    );
}

#[test]
fn pc_sets_the_prompt_and_pc0_drops_it() {
    let mut s = Session::new();
    assert_eq!(s.typed("PC42\r"), "PC42\r\n*");
    assert_eq!(s.typed("PC0\r"), "PC0\r\n");
    assert_eq!(s.typed("PC62\r"), "PC62\r\n>");
    assert_eq!(DEFAULT_PROMPT, b'>');
}

#[test]
fn while_a_line_runs_only_escape_and_space_count() {
    let mut s = Session::new();
    assert_eq!(s.typed("WA0.1,AL5\r"), "WA0.1,AL5\r\n");
    assert_eq!(s.typed("AL9,AR200\r"), "", "ignored, not echoed");
    assert_eq!(s.advance_ms(100), ">");
    assert_eq!(
        s.line("TR0,TR200"),
        ["01 5", "01 0"],
        "the typed-ahead line never ran"
    );
}

#[test]
fn space_pauses_and_resumes() {
    let mut s = Session::new();
    assert_eq!(s.typed("AL0,AR100\r"), "AL0,AR100\r\n>");
    s.typed("AL@100,AA1,AR100,WA0.01,RP\r");
    s.advance_ms(50);
    assert_eq!(s.typed(" "), "", "paused");
    let at_pause = s.sim.registers.get(100);
    s.advance_ms(200);
    assert_eq!(
        s.sim.registers.get(100),
        at_pause,
        "no command runs while paused"
    );
    s.typed(" ");
    s.advance_ms(50);
    assert_ne!(s.sim.registers.get(100), at_pause, "runs again");
    assert_eq!(s.typed("\x1b"), "?-7 WA0.01\r\n>");
}

#[test]
fn escape_aborts_the_repeat_cycle_with_minus_7() {
    // Ch2: 2MR1000,WS0.5,MR-1000,WS0.5,RP6 ... Escape aborts (Ch14 -7
    // "Command Canceled by User"); the report names the command it was on.
    let mut s = Session::new();
    s.quiet(&["2MN"]);
    s.typed("2MR1000,WS0.5,MR-1000,WS0.5,RP6\r");
    s.advance_ms(200);
    assert_eq!(s.typed("\x1b"), "?-7 WS0.5\r\n>");
    assert!(!s.sim.busy());
    assert_eq!(s.one("TE"), "-7");
}

#[test]
fn rp6_runs_the_cycle_seven_times() {
    let mut s = Session::new();
    s.quiet(&["2MN"]);
    s.typed("2MR1000,WS0.5,MR-1000,WS0.5,RP6\r");
    let (mut cycles, mut was_out) = (0, false);
    let mut ms = 0;
    while s.sim.busy() {
        s.advance_ms(1);
        ms += 1;
        let target = s.sim.axis(2).map(|a| a.target).unwrap_or_default();
        if target == 1000.0 && !was_out {
            cycles += 1;
        }
        was_out = target == 1000.0;
        assert!(ms < 20_000);
    }
    assert_eq!(cycles, 7);
    // Each cycle: two 1000-count moves (0.14 s each at SA 200000) and two
    // 0.5 s waits.
    assert!((8_500..9_500).contains(&ms), "{ms} ms");
    assert_eq!(s.sim.take_output(), b"");
}

#[test]
fn prompts_per_command_as_a_setting() {
    let mut s = Session::new();
    s.drive("PROMPTS=command");
    assert_eq!(s.typed("AL1,AL2,NO\r"), "AL1,AL2,NO\r\n>>>");
    s.drive("PROMPTS=line");
    assert_eq!(s.typed("AL1,AL2,NO\r"), "AL1,AL2,NO\r\n>");
}

#[test]
fn terminators_error_text_tell_field_and_echo_are_settings() {
    let mut s = Session::new();
    s.drive("EOL=cr");
    s.drive("ERRORS=code");
    s.drive("TELLAXIS=0");
    assert_eq!(s.typed("1XX\r"), "1XX\r?1\r>");
    assert_eq!(s.typed("1TP\r"), "1TP\r0\r>");
    s.drive("ECHO=0");
    assert_eq!(s.typed("1TP\r"), "\r0\r>");
    s.typed("EN\r");
    assert_eq!(
        s.typed_through("1TP\r"),
        "1TP\r0\r>",
        "EN turns the echo back on"
    );
}

#[test]
fn hex_mode_both_ways() {
    // Ch13 DM/HM: status 10 prints as 0000000a; hex parameters need a
    // leading 0 before A-F.
    let mut s = Session::new();
    s.quiet(&["1MN"]);
    assert_eq!(s.line("DM,1TS"), ["01 10"]);
    assert_eq!(s.line("HM,1TS"), ["01 0000000a"]);
    assert_eq!(s.line("AL0FF,TR0"), ["01 000000ff"]);
    assert_eq!(s.error("ALFF"), 2);
    // The line is read in the base in force when it arrives: DM acts on
    // the lines after it.
    assert_eq!(s.line("DM,AL255,TR0"), ["01 597"]);
    assert_eq!(s.line("AL255,TR0"), ["01 255"]);
}

#[test]
fn line_noise_and_long_lines() {
    let mut s = Session::new();
    assert_eq!(s.typed("1T\u{1}P\r"), "1T\u{1}P\r\n?3 1T\u{1}P\r\n>");
    let long = "NO,".repeat(200);
    let out = s.typed(&format!("{long}\r"));
    assert!(out.ends_with("\r\n?4\r\n>"), "{out:?}");
}

/// Ch2: commands on one line separated by commas, "the axis that a
/// command acts on is assumed to be the last one specified in the command
/// string"; Ch8: a Tell prints `AA value`, the axis in two digits. The
/// console's status line for several axes, byte for byte, the echo (its
/// CR as CR LF) first and one prompt after the line.
#[test]
fn one_line_tells_several_axes_each_with_its_own_axis() {
    let mut s = Session::new();
    s.quiet(&["2DH1000", "3DH-250"]);
    assert_eq!(
        s.typed_through("1TP,TT,2TP,TT,3TP,TT\r"),
        "1TP,TT,2TP,TT,3TP,TT\r\n01 0\r\n01 0\r\n02 1000\r\n02 1000\r\n03 -250\r\n03 -250\r\n>"
    );
}

#[test]
fn escape_cuts_a_line_of_tells_short_while_its_answer_goes_out() {
    // Ch2: "Escape" aborts the command string being executed; Ch14 -7
    // "Command Canceled by User". At 9600 Bd (960 bytes/s) a status line
    // of five axes answers for about 150 ms; a Tell waits for room in the
    // port's transmit buffer, so the line is still running when Escape
    // comes 40 ms in, and what follows is the abort, not the rest.
    let mut s = Session::new();
    s.drive("OUTRATE=960");
    let line = "1TP,TV,TS,2TP,TV,TS,3TP,TV,TS,4TP,TV,TS,5TP,TV,TS";
    let mut out = s.typed(&format!("{line}\r"));
    out.push_str(&s.advance_ms(40));
    assert!(s.sim.busy(), "still answering 40 ms in: {out:?}");
    out.push_str(&s.typed("\x1b"));
    for _ in 0..200 {
        out.push_str(&s.advance_ms(1));
    }
    assert!(!s.sim.busy());
    let body = out
        .strip_prefix(&format!("{line}\r\n"))
        .unwrap_or_else(|| panic!("no echo: {out:?}"));
    let lines: Vec<&str> = body.split_terminator("\r\n").collect();
    let (last, tells) = lines.split_last().expect("lines");
    assert_eq!(*last, ">", "{out:?}");
    let (abort, tells) = tells.split_last().expect("the abort's report");
    assert!(
        abort.starts_with("?-7 ") && abort.len() > 4,
        "the abort names the command it was on: {out:?}"
    );
    assert!(tells.len() < 15, "cut short: {} of 15 Tells", tells.len());
    assert!(
        tells.iter().all(|t| t.len() > 3 && t.as_bytes()[2] == b' '),
        "each Tell a whole `AA value` line: {tells:?}"
    );
}

#[test]
fn the_port_sends_at_the_rate_of_the_line_it_is_connected_by() {
    let mut s = Session::new();
    s.sim.line_byte_time(Some(crate::link::byte_time(9600)));
    assert!((s.sim.link.profile.output_rate - 960.0).abs() < 0.01);
    // A line without a rate leaves the port's own.
    s.sim.line_byte_time(None);
    assert!((s.sim.link.profile.output_rate - 960.0).abs() < 0.01);
}
