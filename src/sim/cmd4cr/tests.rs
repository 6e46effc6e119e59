//! The controller around the engine: framing, IDs, flash and power cycle,
//! inputs from outside.

use std::time::Duration;

use super::*;

fn sim() -> Cmd4cr {
    Cmd4cr::new(SimConfig::default())
}

fn send_to(sim: &mut Cmd4cr, id: &str, text: &str) -> Option<String> {
    sim.feed(format!("@{id}{text}\r").as_bytes());
    let out = String::from_utf8(sim.take_output()).expect("ASCII reply");
    if out.is_empty() {
        return None;
    }
    Some(out.strip_suffix('\r').expect("ends in CR").to_string())
}

fn send(sim: &mut Cmd4cr, text: &str) -> String {
    send_to(sim, "01", text).unwrap_or_else(|| panic!("no reply to {text}"))
}

#[test]
fn a_frame_may_arrive_in_pieces_after_noise() {
    let mut sim = sim();
    sim.feed(b"\xff\x00garbage");
    sim.feed(b"@0");
    sim.feed(b"1PO");
    assert!(sim.take_output().is_empty());
    sim.feed(b"LX\r\n");
    assert_eq!(sim.take_output(), b"7\r");
    // A new `@` abandons a frame left without its CR.
    sim.feed(b"@01HSPD=9@01MM\r");
    assert_eq!(sim.take_output(), b"0\r");
    assert_eq!(send(&mut sim, "HSPD"), "1000");
}

#[test]
fn only_its_own_id_is_answered_and_00_is_no_broadcast() {
    let mut sim = sim();
    assert_eq!(send_to(&mut sim, "02", "PX"), None);
    assert_eq!(send_to(&mut sim, "00", "PX"), None);
    assert_eq!(send_to(&mut sim, "1", "PX"), None, "one digit is no ID");
    assert_eq!(send_to(&mut sim, "01", "PX"), Some("0".into()));
    let mut zero = Cmd4cr::new(SimConfig {
        id: Some(0),
        ..SimConfig::default()
    });
    assert_eq!(send_to(&mut zero, "00", "ID"), Some("01".into()));
    assert_eq!(send_to(&mut zero, "01", "ID"), None);
}

#[test]
fn a_line_without_cr_does_not_grow_forever() {
    let mut sim = sim();
    let mut long = b"@01".to_vec();
    long.extend(std::iter::repeat_n(b'X', 10 * MAX_LINE));
    sim.feed(&long);
    assert!(sim.line.len() <= MAX_LINE);
    sim.feed(b"\r@01MM\r");
    assert_eq!(sim.take_output(), b"0\r");
}

#[test]
fn id_and_boot_values_act_after_store_and_a_power_cycle() {
    let mut sim = sim();
    assert_eq!(send(&mut sim, "ID=02"), "OK");
    assert_eq!(send(&mut sim, "ID"), "02");
    assert_eq!(send(&mut sim, "EOBOOT=5"), "OK");
    assert_eq!(send(&mut sim, "EO"), "0");
    assert_eq!(send(&mut sim, "HSPD=2345"), "OK");
    assert_eq!(send(&mut sim, "STORE"), "OK");
    sim.power_cycle();
    assert_eq!(send_to(&mut sim, "01", "ID"), None);
    assert_eq!(send_to(&mut sim, "02", "EO"), Some("5".into()));
    // HSPD is not in Table 2-19: back to its power-on value.
    assert_eq!(send_to(&mut sim, "02", "HSPD"), Some("1000".into()));
}

#[test]
fn a_power_cycle_without_store_forgets() {
    let mut sim = sim();
    send(&mut sim, "POLY=3");
    send(&mut sim, "V7=-12");
    sim.power_cycle();
    assert_eq!(send(&mut sim, "POLY"), "7");
    assert_eq!(send(&mut sim, "V7"), "0");
}

#[test]
fn the_flash_file_keeps_table_2_19_between_runs() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("flash.json");
    let config = || SimConfig {
        flash_file: Some(path.clone()),
        ..SimConfig::default()
    };
    let mut first = Cmd4cr::new(config());
    for line in [
        "POLX=5",
        "V99=-2147483648",
        "SLRZ=2.5",
        "SLOAD=9",
        "JLIM3=777",
    ] {
        assert_eq!(send(&mut first, line), "OK", "{line}");
    }
    assert_eq!(send(&mut first, "STORE"), "OK");
    drop(first);
    let mut second = Cmd4cr::new(config());
    assert!(second.flash_problem().is_none());
    assert_eq!(send(&mut second, "POLX"), "5");
    assert_eq!(send(&mut second, "V99"), "-2147483648");
    assert_eq!(send(&mut second, "SLRZ"), "2.5");
    assert_eq!(send(&mut second, "SLOAD"), "9");
    assert_eq!(send(&mut second, "SLOAD3"), "1");
    assert_eq!(send(&mut second, "JLIM3"), "777");
    let text = std::fs::read_to_string(&path).expect("file");
    assert!(text.contains("\"POLX\": 5"), "{text}");
}

#[test]
fn the_mpg_moves_the_axis_through_its_gearing() {
    // §2.5.2.2: MPM 5, MPD 512: 100 counts in, 125 out.
    let mut sim = sim();
    for line in ["MPMX=5", "MPDX=512", "MPEX=1"] {
        assert_eq!(send(&mut sim, line), "OK");
    }
    sim.turn_mpg(Axis::X, 100);
    assert_eq!(send(&mut sim, "MPX"), "125");
    assert_eq!(send(&mut sim, "PX"), "125");
    sim.turn_mpg(Axis::X, 1);
    sim.turn_mpg(Axis::X, 1);
    assert_eq!(send(&mut sim, "MPX"), "127", "fractions carry over");
    // Under MPG control the axis takes no motion command.
    assert_eq!(send(&mut sim, "JX+"), "?Error Moving");
    send(&mut sim, "MPEX=0");
    sim.turn_mpg(Axis::X, 100);
    assert_eq!(send(&mut sim, "PX"), "127");
    assert_eq!(send(&mut sim, "JX+"), "OK");
}

#[test]
fn the_latch_takes_its_input_edge() {
    let mut sim = sim();
    send(&mut sim, "LTY=1");
    assert_eq!(send(&mut sim, "LTSY"), "1");
    send(&mut sim, "JY+");
    sim.advance(Duration::from_millis(2000));
    let at: i64 = send(&mut sim, "PY").parse().expect("number");
    assert!(sim.set_digital_input(2, true));
    sim.advance(Duration::from_millis(500));
    assert_eq!(send(&mut sim, "LTSY"), "2");
    assert_eq!(send(&mut sim, "LTPY"), at.to_string());
    assert_eq!(send(&mut sim, "LTEY"), at.to_string());
    assert!(!sim.set_digital_input(5, true));
}

#[test]
fn help_names_the_choices() {
    let help = sim().help();
    for word in [
        "HSPD 1000",
        "POL 7",
        "IOCFG 0xFFFF0000",
        "00 is no broadcast",
        "\"OK\"",
    ] {
        assert!(help.contains(word), "{word}: {help}");
    }
}
