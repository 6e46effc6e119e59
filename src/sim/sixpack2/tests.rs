//! The simulator seen from the wire: frames written out by hand from the
//! manual (§6.2, §7: `ADDR CMD P0..P6`, LSB first), virtual time, replies
//! read byte by byte (`CMD P0..P6`). Motion is checked against the manual's
//! own numbers (§6.3.1, §6.2.1.8, §6.3.1.1), not against the simulator's
//! formulas.

use std::time::Duration;

use super::*;

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

fn sim() -> Sixpack2 {
    Sixpack2::new(SimConfig::default())
}

/// Nine bytes from their hex.
fn frame(hex: &str) -> Vec<u8> {
    let bytes: Vec<u8> = hex
        .split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).unwrap_or_else(|_| panic!("{b} is no hex byte")))
        .collect();
    assert_eq!(bytes.len(), 9, "{hex}");
    bytes
}

/// Send a frame that gets no answer, and check it gets none.
fn tell(sim: &mut Sixpack2, hex: &str) {
    sim.feed(&frame(hex));
    sim.advance(ms(20));
    assert_eq!(sim.take_output(), Vec::<u8>::new(), "{hex} answered");
}

/// Send a query and wait out the 6 ms switch-over delay: its reply.
fn ask(sim: &mut Sixpack2, hex: &str) -> Vec<u8> {
    sim.feed(&frame(hex));
    sim.advance(ms(6));
    sim.take_output()
}

/// $20 for `motor`: (position, action, stop flag).
fn position(sim: &mut Sixpack2, motor: u8) -> (i32, u8, u8) {
    let reply = ask(sim, &format!("00 20 {motor:02X} 00 00 00 00 00 00"));
    assert_eq!(reply.len(), 8, "{reply:02X?}");
    assert_eq!((reply[0], reply[1]), (0x20, motor), "{reply:02X?}");
    let pos = i32::from_le_bytes([reply[2], reply[3], reply[4], reply[5]]);
    (pos, reply[6], reply[7])
}

/// $21 for `motor`: (velocity, action).
fn velocity(sim: &mut Sixpack2, motor: u8) -> (i16, u8) {
    let reply = ask(sim, &format!("00 21 {motor:02X} 00 00 00 00 00 00"));
    assert_eq!(reply.len(), 8, "{reply:02X?}");
    assert_eq!((reply[0], reply[1]), (0x21, motor), "{reply:02X?}");
    (i16::from_le_bytes([reply[2], reply[3]]), reply[4])
}

/// Advance a tick at a time until motor `motor` is idle; the ticks taken.
fn ticks_until_idle(sim: &mut Sixpack2, motor: usize, limit: u32) -> u32 {
    for n in 0..limit {
        if sim.motor(motor).is_some_and(Motor::is_idle) {
            return n;
        }
        sim.advance(TICK);
    }
    panic!("motor {motor} still active after {limit} ticks");
}

fn carriage(sim: &Sixpack2, motor: usize) -> i64 {
    sim.motor(motor).map_or(0, |m| m.mechanics.carriage())
}

// ---- the link ---------------------------------------------------------

#[test]
fn a_reply_leaves_after_the_switch_over_delay_as_eight_bytes() {
    // §6.1.1: "pre-set to 6ms"; §6.2.2.3: cmd, motno, pos ×4, action, stop.
    let mut sim = sim();
    sim.feed(&frame("00 20 03 00 00 00 00 00 00"));
    sim.advance(ms(5));
    assert!(sim.take_output().is_empty(), "not before 6 ms");
    sim.advance(ms(1));
    assert_eq!(sim.take_output(), [0x20, 3, 0, 0, 0, 0, 0, 0]);
    // $40: divisor 65 (19200 Bd), switch-over 1 (2 ms).
    tell(&mut sim, "00 40 41 00 01 00 00 00 00");
    sim.feed(&frame("00 21 00 00 00 00 00 00 00"));
    sim.advance(ms(2));
    assert_eq!(sim.take_output(), [0x21, 0, 0, 0, 0, 0, 0, 0]);
}

#[test]
fn setting_commands_are_never_answered() {
    let mut sim = sim();
    for hex in [
        "00 10 00 80 00 00 00 00 00",
        "00 11 00 08 02 01 00 F4 01",
        "00 12 05 00 00 00 00 00 00",
        "00 13 02 05 00 64 00 02 00",
        "00 14 03 C8 00 90 01 00 00",
        "00 15 00 10 27 00 00 A0 0A",
        "00 16 00 64 00 FF 0F 00 00",
        "00 17 00 0D 25 3E 56 00 00",
        "00 18 00 00 00 00 00 F0 00",
        "00 19 00 08 81 00 81 00 01",
        "00 26 00 00 00 00 00 00 00",
        "00 27 00 00 00 00 00 00 00",
        "00 31 00 00 00 FF 03 00 00",
        "00 32 01 00 00 00 00 00 00",
        "00 33 3F 3F 00 00 00 00 00",
        "00 41 19 00 00 00 00 00 00",
    ] {
        tell(&mut sim, hex);
    }
}

#[test]
fn exactly_the_commands_with_a_response_table_answer() {
    // §7: $20 $21 $28 $30 $43 $44 have a "response"; the service commands
    // are not simulated and $CC answers with its stray byte (below).
    let mut sim = sim();
    for info in command::COMMANDS {
        if info.code == 0xCC || info.code >= 0xF2 {
            continue;
        }
        sim.feed(&[0, info.code, 0, 0, 0, 0, 0, 0, 0]);
        sim.advance(ms(20));
        let reply = sim.take_output();
        assert_eq!(
            !reply.is_empty(),
            info.replies,
            "{:02X} {}",
            info.code,
            info.name
        );
        if info.replies {
            assert_eq!((reply.len(), reply[0]), (8, info.code), "{reply:02X?}");
        }
    }
}

#[test]
fn a_frame_for_another_address_is_not_answered() {
    let mut sim = sim();
    tell(&mut sim, "01 43 00 00 00 00 00 00 00");
    tell(&mut sim, "FF 43 00 00 00 00 00 00 00");
    assert_eq!(ask(&mut sim, "00 43 00 00 00 00 00 00 00")[0], 0x43);
    // $42: address 5 at once.
    tell(&mut sim, "00 42 05 00 00 00 00 00 00");
    tell(&mut sim, "00 43 00 00 00 00 00 00 00");
    assert_eq!(ask(&mut sim, "05 43 00 00 00 00 00 00 00")[0], 0x43);
}

#[test]
fn unknown_commands_and_motor_six_are_dropped_silently() {
    let mut sim = sim();
    tell(&mut sim, "00 1A 00 00 00 00 00 00 00");
    tell(&mut sim, "00 20 06 00 00 00 00 00 00");
    tell(&mut sim, "00 F4 00 00 00 00 00 00 00");
    tell(&mut sim, "00 23 06 10 27 00 00 00 00");
    assert_eq!(position(&mut sim, 5), (0, 0, 0));
}

#[test]
fn a_partial_frame_is_dropped_after_the_packet_timeout() {
    // Ours: 25 × 2 ms after a reset. Four bytes of a $43, then silence.
    let mut sim = sim();
    sim.feed(&frame("00 43 00 00 00 00 00 00 00")[..4]);
    sim.advance(ms(49));
    assert_eq!(sim.dropped_frames(), 0);
    sim.advance(ms(1));
    assert_eq!(sim.dropped_frames(), 1);
    // The next whole frame stands on its own: one reply, to it.
    assert_eq!(ask(&mut sim, "00 20 01 00 00 00 00 00 00")[..2], [0x20, 1]);

    // $41 = 5 (10 ms): now 10 ms is too late.
    tell(&mut sim, "00 41 05 00 00 00 00 00 00");
    sim.feed(&frame("00 20 04 00 00 00 00 00 00")[..8]);
    sim.advance(ms(10));
    sim.feed(&[0]);
    assert_eq!(sim.dropped_frames(), 2, "eight bytes dropped, one pending");
    sim.feed(&frame("00 20 02 00 00 00 00 00 00")[1..]);
    sim.advance(ms(6));
    assert_eq!(
        sim.take_output(),
        [0x20, 2, 0, 0, 0, 0, 0, 0],
        "the stray 00 began a frame the next eight completed"
    );
}

#[test]
fn the_timeout_counts_from_a_frames_first_byte() {
    // §6.1.1: the word "has to be completely transmitted during" the timeout.
    let mut sim = sim();
    tell(&mut sim, "00 41 05 00 00 00 00 00 00");
    for byte in frame("00 20 00 00 00 00 00 00 00") {
        sim.feed(&[byte]);
        sim.advance(ms(2)); // 18 ms for nine bytes, each within 10 ms of the last
    }
    sim.advance(ms(10));
    assert!(sim.take_output().is_empty());
    assert!(sim.dropped_frames() >= 1);
}

#[test]
fn a_break_abandons_the_frame_in_progress() {
    // §6.1.1: "aborted and not interpreted, when a break-code is received".
    let mut sim = sim();
    sim.feed(&frame("00 23 00 10 27 00 00 00 00")[..5]);
    sim.line_break();
    sim.feed(&frame("00 43 00 00 00 00 00 00 00"));
    sim.advance(ms(6));
    let reply = sim.take_output();
    assert_eq!(reply[0], 0x43, "{reply:02X?}");
    assert_eq!(sim.dropped_frames(), 1);
    assert_eq!(position(&mut sim, 0), (0, 0, 0), "the ramp never started");
}

#[test]
fn addr9_puts_the_response_address_before_the_command() {
    let mut sim = sim();
    sim.drive_input("ADDR9=1").expect("a choice");
    assert_eq!(
        ask(&mut sim, "00 20 00 7E 00 00 00 00 00"),
        [0x7E, 0x20, 0, 0, 0, 0, 0, 0, 0]
    );
    assert_eq!(
        ask(&mut sim, "00 43 3C 00 00 00 00 00 00")[..2],
        [0x3C, 0x43]
    );
    assert_eq!(
        ask(&mut sim, "00 28 11 00 00 00 00 00 00")[..2],
        [0x11, 0x28]
    );
}

#[test]
fn unit_information_shows_the_reset_flag_once() {
    // §7.4 $43: "during first read out 1, afterwards 0".
    let mut sim = sim();
    assert_eq!(
        ask(&mut sim, "00 43 00 00 00 00 00 00 00"),
        [0x43, 148, 1, 30, 1, 0, 0, 0]
    );
    assert_eq!(ask(&mut sim, "00 43 00 00 00 00 00 00 00")[2], 0);
}

#[test]
fn a_hardware_reset_is_deaf_for_a_second_then_sends_a_stray_zero() {
    // §7.4 $CC: "about 1 second", "a 0-byte during execution"; defaults back.
    let mut sim = sim();
    tell(&mut sim, "00 42 09 00 00 00 00 00 00");
    assert_eq!(ask(&mut sim, "09 43 00 00 00 00 00 00 00")[2], 1);
    assert_eq!(ask(&mut sim, "09 43 00 00 00 00 00 00 00")[2], 0);
    tell(&mut sim, "09 23 00 10 27 00 00 00 00");
    sim.feed(&frame("09 CC 00 00 00 00 00 00 00"));
    sim.advance(ms(500));
    assert!(sim.is_resetting());
    sim.feed(&frame("00 43 00 00 00 00 00 00 00"));
    sim.advance(ms(499));
    assert!(sim.take_output().is_empty(), "deaf while resetting");
    sim.advance(ms(1));
    assert_eq!(sim.take_output(), [0x00], "the stray $00 of §3.1");
    // The address is the rotary switches' again, the flag set, motion gone.
    tell(&mut sim, "09 43 00 00 00 00 00 00 00");
    assert_eq!(ask(&mut sim, "00 43 00 00 00 00 00 00 00")[2], 1);
    let (pos, action, _) = position(&mut sim, 0);
    assert_eq!((pos, action), (0, 0));
    assert!(
        carriage(&sim, 0) > 480,
        "the carriage stays where the reset found it"
    );
}

#[test]
fn a_reset_key_and_no_stray_zero_are_choices() {
    let mut sim = sim();
    sim.drive_input("RESETKEY=165").expect("a choice");
    sim.drive_input("STRAY00=0").expect("a choice");
    tell(&mut sim, "00 CC 00 00 00 00 00 00 00");
    assert!(!sim.is_resetting());
    sim.feed(&frame("00 CC A5 00 00 00 00 00 00"));
    sim.advance(ms(1100));
    assert!(!sim.is_resetting());
    assert!(sim.take_output().is_empty());
}

#[test]
fn a_command_acts_after_the_chosen_latency() {
    let mut sim = sim();
    // Ours by default: a $20 right after a $23 already shows the ramp.
    sim.feed(&frame("00 23 00 10 27 00 00 00 00"));
    assert_eq!(position(&mut sim, 0).1, 5);
    let mut sim = self::sim();
    sim.drive_input("LATENCY=4").expect("a choice");
    sim.feed(&frame("00 23 00 10 27 00 00 00 00"));
    sim.feed(&frame("00 20 00 00 00 00 00 00 00"));
    sim.advance(ms(3));
    assert_eq!(sim.motor(0).map(Motor::action), Some(0));
    sim.advance(ms(1));
    assert_eq!(sim.motor(0).map(Motor::action), Some(5));
    sim.advance(ms(10));
    let reply = sim.take_output();
    assert_eq!(reply[6], 5, "$20 acted after $23: {reply:02X?}");
}

// ---- motion -------------------------------------------------------------

#[test]
fn a_start_ramp_shows_action_5_then_0_at_its_target() {
    // The frame for `StartRamp 0 10000`.
    let mut sim = sim();
    tell(&mut sim, "00 23 00 10 27 00 00 00 00");
    let (pos, action, stop) = position(&mut sim, 0);
    assert!(pos > 0 && pos < 10000, "{pos}");
    assert_eq!((action, stop), (5, 0));
    sim.advance(Duration::from_secs(2));
    assert_eq!(position(&mut sim, 0), (10000, 0, 0));
    assert_eq!(carriage(&sim, 0), 480 + 10000);
}

#[test]
fn the_step_frequency_is_the_formula_of_section_6_3_1() {
    // §6.2.1.8: vstart 5 "starting with 254 Hz"; rotation at 5 starts there.
    let mut sim = sim();
    tell(&mut sim, "00 25 00 05 00 00 00 00 00");
    sim.advance(Duration::from_secs(1) - ms(20));
    assert_eq!(sim.motor(0).map(Motor::position), Some(254), "254 Hz");
    // "clkdiv=5; div=2; // 26 kHz microstep-frequency" at vmax 511: a
    // second at full speed makes 25 990 µsteps (25.99 kHz).
    tell(&mut sim, "00 25 00 FF 01 00 00 00 00");
    sim.advance(Duration::from_secs(1));
    assert_eq!(velocity(&mut sim, 0), (511, 15));
    let before = sim.motor(0).map_or(0, Motor::position);
    sim.advance(Duration::from_secs(1));
    let made = sim.motor(0).map_or(0, Motor::position) - before;
    assert!((25_990..=25_991).contains(&made), "{made}");
    // vrefmax 100 "5086 Hz": a second at 100 makes 5086.
    tell(&mut sim, "00 25 00 64 00 00 00 00 00");
    sim.advance(Duration::from_secs(1));
    let before = sim.motor(0).map_or(0, Motor::position);
    sim.advance(Duration::from_secs(1));
    let made = sim.motor(0).map_or(0, Motor::position) - before;
    assert!((5086..=5087).contains(&made), "{made}");
}

#[test]
fn a_ramp_accelerates_by_amax_over_64_every_2_ms() {
    // §7.1 $14: "1/64 amax is accumulated with 500Hz"; the defaults give
    // 128/64 = 2 a tick (not the 8 of §6.2.1.8's comment, E8), from vstart
    // 5: v = 5 + 2·t/2 ms (E9), 511 after 253 ticks (0.506 s).
    let mut sim = sim();
    sim.feed(&frame("00 23 00 40 0D 03 00 00 00")); // to 200000
    let v = |sim: &Sixpack2| sim.motor(0).map_or(0, Motor::velocity);
    assert_eq!(v(&sim), 0);
    sim.advance(TICK);
    assert_eq!(v(&sim), 7, "vstart, then the first 2");
    sim.advance(TICK * 9);
    assert_eq!(v(&sim), 25);
    sim.advance(TICK * 242);
    assert_eq!(v(&sim), 509);
    sim.advance(TICK);
    assert_eq!(v(&sim), 511, "at 0.506 s");
    sim.advance(TICK * 10);
    assert_eq!(v(&sim), 511);
}

#[test]
fn the_worked_example_of_section_6_3_1_1() {
    // ClockDivider 5, Div 2, VStart 16, VMax 128, AMax 5; 0 → 116666.
    // Derived in the digest (D5.2): 814 Hz at the start, 6510 Hz at vmax,
    // the acceleration 1434 ticks (2.87 s) over about 10 500 µsteps; the
    // deceleration slower than that ("decelerates more slowly").
    let mut sim = sim();
    tell(&mut sim, "00 12 05 00 00 00 00 00 00");
    tell(&mut sim, "00 13 00 04 00 10 00 02 00");
    tell(&mut sim, "00 14 00 05 00 80 00 00 00");
    sim.feed(&frame("00 23 00 BA C7 01 00 00 00"));
    sim.advance(TICK);
    let m = |sim: &Sixpack2| {
        sim.motor(0)
            .map_or((0, 0), |m| (m.velocity(), m.position()))
    };
    assert_eq!(m(&sim).0, 16, "16 × 50.86 Hz = 814 Hz");
    let mut ticks = 1;
    while m(&sim).0 < 128 {
        sim.advance(TICK);
        ticks += 1;
        assert!(ticks < 2000, "never at vmax");
    }
    assert!((1433..=1435).contains(&ticks), "{ticks} ticks to vmax");
    let (_, accelerated) = m(&sim);
    assert!((10_400..=10_600).contains(&accelerated), "{accelerated}");
    // Cruise, then the deceleration back to vstart.
    while m(&sim).0 == 128 {
        sim.advance(TICK);
    }
    let mut decelerating = 0;
    while m(&sim).0 > 16 {
        sim.advance(TICK);
        decelerating += 1;
    }
    assert!(decelerating > ticks, "{decelerating} ticks slowing down");
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(position(&mut sim, 0), (116_666, 0, 0));
}

#[test]
fn stop_motors_overshoots_and_comes_back() {
    // §7.2 $2A: "motors driving beyond vstart will overshoot and return".
    let mut sim = sim();
    tell(&mut sim, "00 23 00 40 0D 03 00 00 00");
    sim.advance(ms(600));
    sim.feed(&frame("00 2A 01 00 00 00 00 00 00"));
    let stop_at = sim.motor(0).map_or(0, Motor::position);
    let mut furthest = stop_at;
    for _ in 0..1000 {
        sim.advance(TICK);
        furthest = furthest.max(sim.motor(0).map_or(0, Motor::position));
    }
    assert!(furthest > stop_at + 1000, "{furthest} past {stop_at}");
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(position(&mut sim, 0), (stop_at, 0, 0));
}

#[test]
fn a_late_new_target_overshoots_and_drives_back() {
    // §7.2 $26: "the peak will decelerate with amax instantly and continue
    // driving a reverse ramp on its own".
    let mut sim = sim();
    tell(&mut sim, "00 23 00 40 0D 03 00 00 00");
    sim.advance(ms(800));
    let here = sim.motor(0).map_or(0, Motor::position);
    assert!(here > 12_000, "{here}");
    tell(&mut sim, "00 26 00 10 27 00 00 00 00"); // 10000, behind it
    assert_eq!(position(&mut sim, 0).1, 5, "the mode is unchanged");
    ticks_until_idle(&mut sim, 0, 10_000);
    assert_eq!(position(&mut sim, 0), (10_000, 0, 0));
}

#[test]
fn a_start_ramp_while_active_does_nothing() {
    // §7.2 $23: "does not influence the motor, if the motor is still active".
    let mut sim = sim();
    tell(&mut sim, "00 23 00 10 27 00 00 00 00");
    tell(&mut sim, "00 23 00 64 00 00 00 00 00");
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(position(&mut sim, 0).0, 10_000);
    // $26 then $23 with the same target: the on-the-fly way.
    tell(&mut sim, "00 26 00 20 4E 00 00 00 00");
    tell(&mut sim, "00 23 00 20 4E 00 00 00 00");
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(position(&mut sim, 0).0, 20_000);
}

#[test]
fn a_start_ramp_during_a_rotation_only_stops_it() {
    // §7.2 (E20: §6.6.3 says it then drives to the target: ROTRAMP=1).
    let mut sim = sim();
    tell(&mut sim, "00 25 00 C8 00 00 00 00 00");
    sim.advance(ms(500));
    tell(&mut sim, "00 23 00 00 00 00 00 00 00");
    ticks_until_idle(&mut sim, 0, 5000);
    let (pos, action, _) = position(&mut sim, 0);
    assert!(pos > 1000, "{pos}");
    assert_eq!(action, 0);

    let mut sim = self::sim();
    sim.drive_input("ROTRAMP=1").expect("a choice");
    tell(&mut sim, "00 25 00 C8 00 00 00 00 00");
    sim.advance(ms(500));
    tell(&mut sim, "00 23 00 00 00 00 00 00 00");
    ticks_until_idle(&mut sim, 0, 10_000);
    assert_eq!(position(&mut sim, 0), (0, 0, 0));
}

#[test]
fn a_rotation_changes_speed_with_amax_and_ends_at_zero() {
    // §6.6.2: accelerated "with the maximum acceleration AMax"; velocity 0
    // stops it (ours: then action 0; ROTHOLD=1 keeps 15).
    let mut sim = sim();
    tell(&mut sim, "00 25 00 9C FF 00 00 00 00"); // -100
    sim.advance(ms(200));
    assert_eq!(velocity(&mut sim, 0), (-100, 15));
    sim.feed(&frame("00 25 00 00 00 00 00 00 00"));
    let ticks = ticks_until_idle(&mut sim, 0, 1000);
    assert_eq!(ticks, 48, "100 → 6 by 2 a tick, then 0 below vstart");
    assert_eq!(velocity(&mut sim, 0), (0, 0));
    assert!(position(&mut sim, 0).0 < -1000);

    sim.drive_input("ROTHOLD=1").expect("a choice");
    tell(&mut sim, "00 25 00 0A 00 00 00 00 00");
    tell(&mut sim, "00 25 00 00 00 00 00 00 00");
    assert_eq!(velocity(&mut sim, 0), (0, 15));
}

#[test]
fn a_velocity_beyond_511_is_clamped_or_drops_the_frame() {
    let mut sim = sim();
    tell(&mut sim, "00 25 00 58 02 00 00 00 00"); // 600
    sim.advance(Duration::from_secs(1));
    assert_eq!(velocity(&mut sim, 0), (511, 15));
    let mut sim = self::sim();
    sim.drive_input("CLAMP=0").expect("a choice");
    tell(&mut sim, "00 25 00 58 02 00 00 00 00");
    assert_eq!(velocity(&mut sim, 0), (0, 0));
}

#[test]
fn pi_control_drives_to_its_target_at_once() {
    // §7.2 $24: PI "immediately, even if the motor is inactive"; §7.1 $19:
    // P = 64·difference/propdiv, so 1000 µsteps off asks far above vmax.
    let mut sim = sim();
    tell(&mut sim, "00 24 00 E8 03 00 00 00 00");
    assert_eq!(sim.motor(0).map(Motor::action), Some(10));
    sim.advance(TICK);
    assert_eq!(sim.motor(0).map(Motor::velocity), Some(511));
    ticks_until_idle(&mut sim, 0, 2000);
    assert_eq!(position(&mut sim, 0), (1000, 0, 0));
    // A new target while it runs takes effect at once.
    tell(&mut sim, "00 19 00 10 81 00 81 00 01"); // propdiv 16
    sim.drive_input("PIHOLD=1").expect("a choice");
    tell(&mut sim, "00 24 00 D0 07 00 00 00 00");
    tell(&mut sim, "00 24 00 18 FC FF FF 00 00"); // -1000
    sim.advance(Duration::from_secs(1));
    assert_eq!(position(&mut sim, 0), (-1000, 10, 0), "held at its target");
}

#[test]
fn parallel_ramps_start_together_and_end_apart() {
    // §6.6.4: same settings, motor 1 the longer way: both start at once,
    // motor 2 ends earlier.
    let mut sim = sim();
    tell(&mut sim, "00 26 00 20 4E 00 00 00 00"); // 20000
    tell(&mut sim, "00 26 01 10 27 00 00 00 00"); // 10000
    tell(&mut sim, "00 26 02 10 27 00 00 00 00"); // not in the mask
    sim.feed(&frame("00 29 03 00 00 00 00 00 00"));
    let actions: Vec<u8> = (0..3)
        .filter_map(|i| sim.motor(i).map(Motor::action))
        .collect();
    assert_eq!(actions, [5, 5, 0]);
    let second = ticks_until_idle(&mut sim, 1, 5000);
    assert!(!sim.motor(0).is_some_and(Motor::is_idle));
    let first = second + ticks_until_idle(&mut sim, 0, 5000);
    assert!(first > second);
    assert_eq!(position(&mut sim, 0).0, 20_000);
    assert_eq!(position(&mut sim, 1).0, 10_000);
    assert_eq!(position(&mut sim, 2).0, 0);
}

#[test]
fn interpolated_axes_arrive_together_on_a_line() {
    // §6.2.2.4 / §6.6.5: axis 1 to 10000, axis 2 to 2000, with $26 then $50.
    let mut sim = sim();
    tell(&mut sim, "00 26 00 10 27 00 00 00 00");
    tell(&mut sim, "00 26 01 D0 07 00 00 00 00");
    sim.feed(&frame("00 50 03 00 00 00 00 00 00"));
    let mut ticks = 0;
    while !sim.motor(0).is_some_and(Motor::is_idle) {
        sim.advance(TICK);
        ticks += 1;
        let (a, b) = (
            sim.motor(0).map_or(0, Motor::position),
            sim.motor(1).map_or(0, Motor::position),
        );
        assert!((i64::from(a) - 5 * i64::from(b)).abs() <= 5, "{a} vs {b}");
        if ticks % 50 == 0 && a < 10_000 {
            assert_eq!(sim.motor(1).map(Motor::action), Some(5));
            let (va, vb) = (
                sim.motor(0).map_or(0, Motor::velocity),
                sim.motor(1).map_or(0, Motor::velocity),
            );
            assert_eq!(va / 5, vb, "proportionally reduced velocity");
        }
        assert!(ticks < 5000);
    }
    assert!(sim.motor(1).is_some_and(Motor::is_idle), "arrived together");
    assert_eq!(position(&mut sim, 0).0, 10_000);
    assert_eq!(position(&mut sim, 1).0, 2000);
}

#[test]
fn stop_at_fullsteps_ends_ramps_on_a_full_step() {
    let mut sim = sim();
    tell(&mut sim, "00 15 00 00 19 00 00 A0 8A"); // default word + StopAtFullsteps
    tell(&mut sim, "00 23 00 17 27 00 00 00 00"); // 10007
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(position(&mut sim, 0).0, 10_000);
    tell(&mut sim, "00 23 00 19 27 00 00 00 00"); // 10009
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(position(&mut sim, 0).0, 10_016);
}

#[test]
fn a_rotary_axis_wraps_its_counter() {
    // §7.2 $23: null-left rotary positions are 0 <= position < poslimit.
    let mut sim = sim();
    tell(&mut sim, "00 15 00 00 19 00 00 12 00"); // 6400, Rotary + NullLeft
    tell(&mut sim, "00 25 00 FF 01 00 00 00 00");
    for _ in 0..200 {
        sim.advance(ms(10));
        let pos = sim.motor(0).map_or(-1, Motor::position);
        assert!((0..6400).contains(&pos), "{pos}");
    }
    // Without NullLeft: -poslimit < position <= 0.
    let mut sim = self::sim();
    tell(&mut sim, "00 15 00 00 19 00 00 02 00");
    tell(&mut sim, "00 25 00 FF 01 00 00 00 00");
    for _ in 0..200 {
        sim.advance(ms(10));
        let pos = sim.motor(0).map_or(1, Motor::position);
        assert!((-6399..=0).contains(&pos), "{pos}");
    }
}

#[test]
fn way_optimization_takes_the_shorter_way_round() {
    let mut sim = sim();
    sim.drive_input("TURN0=6400")
        .expect("a rotary machine, no stops");
    tell(&mut sim, "00 15 00 00 19 00 00 12 01"); // Rotary, NullLeft, WayOptimization
    tell(&mut sim, "00 23 00 40 06 00 00 00 00"); // 1600
    ticks_until_idle(&mut sim, 0, 5000);
    let before = carriage(&sim, 0);
    tell(&mut sim, "00 23 00 80 16 00 00 00 00"); // 5760: 2240 back through 0
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(position(&mut sim, 0).0, 5760);
    assert_eq!(carriage(&sim, 0), before - 2240);
}

#[test]
fn a_stall_at_a_mechanical_stop_loses_steps() {
    // §2.2: the position is not known after power on; a stop holds the
    // carriage while the counter counts on.
    let mut sim = sim();
    tell(&mut sim, "00 23 00 30 F8 FF FF 00 00"); // -2000
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(position(&mut sim, 0).0, -2000);
    assert_eq!(carriage(&sim, 0), 0, "held at the left stop");
    tell(&mut sim, "00 23 00 00 00 00 00 00 00");
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(carriage(&sim, 0), 2000, "1520 steps lost");
}

#[test]
fn without_the_driver_enable_jumper_the_counter_runs_alone() {
    let mut sim = sim();
    sim.drive_input("ENABLE=0").expect("an input");
    tell(&mut sim, "00 23 00 E8 03 00 00 00 00");
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(position(&mut sim, 0).0, 1000);
    assert_eq!(carriage(&sim, 0), 480);
}

// ---- $28 --------------------------------------------------------------------

#[test]
fn get_all_activities_answers_at_once_without_a_mask() {
    let mut sim = sim();
    tell(&mut sim, "00 25 02 0A 00 00 00 00 00");
    assert_eq!(
        ask(&mut sim, "00 28 00 00 00 00 00 00 00"),
        [0x28, 0, 0, 15, 0, 0, 0, 0]
    );
}

#[test]
fn get_all_activities_waits_for_its_masked_motors() {
    // §7.2 $28: "as soon as all concerned motors are inactive"; other
    // requests go on meanwhile (§6.2.1.7).
    let mut sim = sim();
    tell(&mut sim, "00 23 00 10 27 00 00 00 00");
    tell(&mut sim, "00 25 01 0A 00 00 00 00 00"); // not in the mask
    sim.feed(&frame("00 28 00 01 00 00 00 00 00"));
    sim.advance(ms(6));
    assert!(sim.take_output().is_empty());
    let (_, action, _) = position(&mut sim, 0);
    assert_eq!(action, 5, "$20 answered while $28 waits");
    let mut waited = Duration::ZERO;
    let reply = loop {
        sim.advance(TICK);
        waited += TICK;
        let out = sim.take_output();
        if !out.is_empty() {
            break out;
        }
        assert!(waited < Duration::from_secs(3));
    };
    assert_eq!(reply, [0x28, 0, 15, 0, 0, 0, 0, 0]);
    assert_eq!(position(&mut sim, 0), (10_000, 0, 0));
}

#[test]
fn a_second_activity_request_follows_the_chosen_rule() {
    let start = |rule: &str| {
        let mut sim = sim();
        sim.drive_input(rule).expect("a choice");
        tell(&mut sim, "00 23 00 10 27 00 00 00 00");
        tell(&mut sim, "00 23 01 20 4E 00 00 00 00");
        sim.feed(&frame("00 28 00 02 00 00 00 00 00")); // waits for motor 1
        sim
    };
    let replies = |sim: &mut Sixpack2| {
        let mut all = Vec::new();
        for _ in 0..2000 {
            sim.advance(TICK);
            all.extend(sim.take_output());
        }
        all
    };
    // 0: each in its own time: motor 0's first, then motor 1's.
    let mut sim = start("SECOND28=0");
    sim.feed(&frame("00 28 00 01 00 00 00 00 00"));
    let all = replies(&mut sim);
    assert_eq!(all.len(), 16);
    assert_eq!(all[..8], [0x28, 0, 5, 0, 0, 0, 0, 0]);
    assert_eq!(all[8..], [0x28, 0, 0, 0, 0, 0, 0, 0]);
    // 1: the newer replaces the waiting one.
    let mut sim = start("SECOND28=1");
    sim.feed(&frame("00 28 00 01 00 00 00 00 00"));
    assert_eq!(replies(&mut sim), [0x28, 0, 5, 0, 0, 0, 0, 0]);
    // 2: the newer is dropped.
    let mut sim = start("SECOND28=2");
    sim.feed(&frame("00 28 00 01 00 00 00 00 00"));
    assert_eq!(replies(&mut sim), [0x28, 0, 0, 0, 0, 0, 0, 0]);
}

// ---- reference search ---------------------------------------------------------

/// Track the action codes motor 0 shows until it is idle.
fn actions_until_idle(sim: &mut Sixpack2, limit: u32) -> Vec<u8> {
    let mut seen = Vec::new();
    for _ in 0..limit {
        let action = sim.motor(0).map_or(0, Motor::action);
        if seen.last() != Some(&action) {
            seen.push(action);
        }
        if action == 0 && seen.len() > 1 {
            return seen;
        }
        sim.advance(TICK);
    }
    panic!("still searching: {seen:?}");
}

#[test]
fn the_mechanical_reference_of_section_5_5_3_2() {
    // Poslimit 10000, NullLeft, MechRef: 12500 µsteps into the left stop.
    let mut sim = sim();
    tell(&mut sim, "00 15 00 10 27 00 00 10 04");
    tell(&mut sim, "00 22 00 00 00 00 00 00 00");
    assert_eq!(position(&mut sim, 0).1, 30, "mechanical reference");
    let seen = actions_until_idle(&mut sim, 20_000);
    assert_eq!(seen, [30, 0]);
    // At the stopper, now position 0; back at the numeric start (0): there.
    assert_eq!(position(&mut sim, 0), (0, 0, 0));
    assert_eq!(carriage(&sim, 0), 0);
    tell(&mut sim, "00 23 00 E8 03 00 00 00 00");
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(
        carriage(&sim, 0),
        1000,
        "the counter and the carriage agree now"
    );
}

#[test]
fn the_switch_search_of_section_5_5_3_3() {
    // NullLeft + NullPositive (an opener), Poslimit 33333 (the stated value:
    // the printed bytes are 500000, erratum E2), no FastRef: the slow drive
    // takes the switch edge (§6.4.8).
    let mut sim = sim();
    tell(&mut sim, "00 15 00 35 82 00 00 10 40");
    sim.feed(&frame("00 22 00 00 00 00 00 00 00"));
    let seen = actions_until_idle(&mut sim, 50_000);
    assert_eq!(seen, [20, 21, 25, 0]);
    assert_eq!(position(&mut sim, 0), (0, 0, 0));
    assert_eq!(carriage(&sim, 0), 399, "the switch's edge");
    // $30 shows it: bit 0 of channel 0 and of AllInputs (inverted: the
    // opener is open, the pin high, the bit 0).
    let reply = ask(&mut sim, "00 30 00 00 00 00 00 00 00");
    assert_eq!(reply, [0x30, 0, 0x00, 0x02, 0, 0b0011_1110, 0, 0]);
}

#[test]
fn a_fast_search_finds_the_middle_of_the_switch() {
    // The default word (FastRef, FilterSwitch, NullCenter, DelayTestNull)
    // with NullLeft and NullPositive for the demo's opener on the left.
    // The switch away from the stop, so that it has a far edge.
    let mut sim = sim();
    tell(&mut sim, "00 15 00 00 19 00 00 F0 4A");
    sim.drive_input("REFAT0=1000").expect("an input");
    sim.drive_input("CARRIAGE0=5000").expect("an input");
    sim.feed(&frame("00 22 00 00 00 00 00 00 00"));
    let seen = actions_until_idle(&mut sim, 50_000);
    assert_eq!(seen, [20, 21, 22, 23, 24, 25, 0]);
    let middle = carriage(&sim, 0);
    assert!((1190..=1210).contains(&middle), "{middle}");
    assert_eq!(position(&mut sim, 0), (0, 0, 0));
}

#[test]
fn the_slow_approach_runs_at_vmin_with_div_3() {
    // §6.2.1.8: "vmin=4 … // 102 Hz", with div 3 whatever the motor's
    // (§7.1 $13): 4 × 25.43 Hz = 101.7 µsteps a second.
    let mut sim = sim();
    tell(&mut sim, "00 15 00 00 19 00 00 90 42"); // FilterSwitch, NullLeft, FastRef, NullPositive
    sim.drive_input("CARRIAGE0=3000").expect("an input");
    sim.feed(&frame("00 22 00 00 00 00 00 00 00"));
    let phase = |sim: &Sixpack2| sim.motor(0).map_or(0, Motor::action);
    for _ in 0..20_000 {
        if phase(&sim) == 23 && sim.motor(0).is_some_and(|m| m.velocity() == -4) {
            break;
        }
        sim.advance(TICK);
    }
    assert_eq!(
        velocity(&mut sim, 0),
        (-4, 23),
        "towards the switch on the left"
    );
    let before = sim.motor(0).map_or(0, Motor::position);
    sim.advance(Duration::from_secs(1));
    assert_eq!(phase(&sim), 23, "still approaching");
    let made = sim.motor(0).map_or(0, Motor::position) - before;
    assert!((-102..=-101).contains(&made), "{made} µsteps in a second");
}

#[test]
fn the_ready_output_and_the_display_show_activity() {
    // §6.1.3, §7.3 $32/$33, §2.3: ready active while a masked motor moves
    // or searches; the display counts active motors, its point a search.
    let mut sim = sim();
    tell(&mut sim, "00 32 01 00 00 01 00 00 00"); // TTLOUT1 = the ready output
    assert!(sim.ttlout1() && !sim.ready_output_active());
    assert_eq!(sim.display(), (0, false));
    tell(&mut sim, "00 25 01 0A 00 00 00 00 00");
    assert!(!sim.ttlout1(), "active: low");
    assert_eq!(sim.display(), (1, false));
    tell(&mut sim, "00 33 01 00 00 00 00 00 00"); // only motor 0 counts
    assert!(sim.ttlout1());
    tell(&mut sim, "00 22 02 00 00 00 00 00 00");
    assert_eq!(sim.display(), (2, true));
    tell(&mut sim, "00 33 01 04 00 00 00 00 00"); // and motor 2 searching
    assert!(!sim.ttlout1());
}

#[test]
fn the_null_offset_moves_zero_into_the_switch() {
    // §6.2.1.5: NullLeft and a positive offset: "the reference switch is
    // reliably closed at position null".
    let mut sim = sim();
    tell(&mut sim, "00 15 00 00 19 00 00 10 40");
    tell(&mut sim, "00 18 00 64 00 00 00 F0 00"); // offset 100
    tell(&mut sim, "00 22 00 00 00 00 00 00 00");
    actions_until_idle(&mut sim, 50_000);
    assert_eq!(position(&mut sim, 0).0, 0);
    assert_eq!(carriage(&sim, 0), 299, "100 further into the switch");
}

#[test]
fn a_search_resumes_the_ramp_it_interrupted() {
    // §7.2 $22: "resumes its previous operation" unless $16 P5 bit 0.
    let mut sim = sim();
    tell(&mut sim, "00 15 00 00 19 00 00 10 42"); // NullLeft, NullPositive, FastRef
    tell(&mut sim, "00 23 00 10 27 00 00 00 00");
    sim.advance(ms(300));
    tell(&mut sim, "00 22 00 00 00 00 00 00 00");
    let seen = actions_until_idle(&mut sim, 50_000);
    assert_eq!(seen.first(), Some(&20));
    assert!(seen.contains(&5), "{seen:?}");
    assert_eq!(position(&mut sim, 0).0, 10_000);
    assert_eq!(carriage(&sim, 0), 399 + 10_000);
    // Stop after the search.
    tell(&mut sim, "00 16 00 64 00 FF 0F 01 00");
    tell(&mut sim, "00 22 00 00 00 00 00 00 00");
    let seen = actions_until_idle(&mut sim, 50_000);
    assert!(!seen.contains(&5), "{seen:?}");
    assert_eq!(position(&mut sim, 0).0, 0);
}

#[test]
fn a_search_without_a_switch_starts_again_until_aborted() {
    // §7.2 $22: no switch within 125 % of the range: "the whole procedure
    // repeats"; §6.4.9: $2B aborts it.
    let mut sim = sim();
    sim.drive_input("REFWIDTH0=0").expect("an input");
    tell(&mut sim, "00 15 00 40 06 00 00 00 02"); // poslimit 1600, FastRef
    tell(&mut sim, "00 22 00 00 00 00 00 00 00");
    let mut restarts = 0;
    let mut last = 20;
    for _ in 0..5000 {
        sim.advance(TICK);
        let action = sim.motor(0).map_or(0, Motor::action);
        if action == 20 && last != 20 {
            restarts += 1;
        }
        last = action;
    }
    assert!(restarts >= 2, "{restarts}");
    tell(&mut sim, "00 2B 00 00 00 00 00 00 00");
    ticks_until_idle(&mut sim, 0, 1000);
    assert_eq!(position(&mut sim, 0).1, 0);
}

#[test]
fn stop_null_stops_and_searches_when_the_switch_is_hit_early() {
    // §5.5.3.4: combined end/reference switch left (StopNull + NullLeft +
    // NullPositive), Poslimit 500000. After the search, a move left past
    // ±testnullrange with the switch active is a stop condition: stop
    // flag, and a new search (StopNoRef clear).
    let mut sim = sim();
    tell(&mut sim, "00 15 00 20 A1 07 00 50 40");
    tell(&mut sim, "00 22 00 00 00 00 00 00 00");
    actions_until_idle(&mut sim, 50_000);
    assert_eq!(carriage(&sim, 0), 399);
    tell(&mut sim, "00 23 00 E8 03 00 00 00 00"); // 1000
    ticks_until_idle(&mut sim, 0, 5000);
    // Someone moves the carriage by hand: the counter is 600 µsteps off.
    sim.drive_input("CARRIAGE0=700").expect("an input");
    tell(&mut sim, "00 23 00 00 00 00 00 00 00");
    sim.advance(ms(400));
    let (_, action, stop) = position(&mut sim, 0);
    assert_eq!(stop, 1, "stop flag");
    assert!((20..=25).contains(&action), "searching again: {action}");
    assert_eq!(position(&mut sim, 0).2, 0, "cleared by the read");
    // Referenced again, it drives back to the number where it stopped.
    actions_until_idle(&mut sim, 50_000);
    let (pos, _, _) = position(&mut sim, 0);
    assert!((600..=700).contains(&pos), "{pos}");
    assert_eq!(
        carriage(&sim, 0),
        399 + i64::from(pos),
        "counter and carriage agree"
    );
}

#[test]
fn stop_no_ref_only_stops() {
    let mut sim = sim();
    tell(&mut sim, "00 31 00 64 00 FF 03 00 00"); // MinLeft 100
    tell(&mut sim, "00 15 00 00 19 00 00 00 20"); // StopNoRef
    tell(&mut sim, "00 23 00 18 FC FF FF 00 00"); // -1000: through the left stop switch
    sim.advance(Duration::from_secs(1));
    let (pos, action, stop) = position(&mut sim, 0);
    assert_eq!((action, stop), (0, 1));
    assert!(pos > -1000, "stopped early at {pos}");
    assert!(carriage(&sim, 0) < 100, "inside the stop switch's zone");
}

#[test]
fn the_a_in_limits_depend_on_the_direction() {
    // §7.3 $31: "checked dependent on the motor direction". Forced A_In.
    let mut sim = sim();
    tell(&mut sim, "00 15 00 00 19 00 00 00 20"); // StopNoRef
    tell(&mut sim, "00 31 00 00 00 58 02 00 00"); // MaxRight 600
    sim.drive_input("AIN0=700").expect("an input");
    tell(&mut sim, "00 23 00 18 FC FF FF 00 00"); // left: no stop
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(position(&mut sim, 0), (-1000, 0, 0));
    tell(&mut sim, "00 23 00 00 00 00 00 00 00"); // right: stops at once
    sim.advance(ms(10));
    let (pos, action, stop) = position(&mut sim, 0);
    assert_eq!((action, stop), (0, 1));
    assert!(pos < -990, "{pos}");
    // LIMITSTOPNULL=1: without StopNull the limits do nothing.
    sim.drive_input("LIMITSTOPNULL=1").expect("a choice");
    tell(&mut sim, "00 23 00 00 00 00 00 00 00");
    ticks_until_idle(&mut sim, 0, 5000);
    assert_eq!(position(&mut sim, 0), (0, 0, 0));
}

/// `LIMITS=swapped`: at the right end the stop switch pulls A_In down
/// (0), which MinLeft checks only moving left (§7.3 $31, "dependent on
/// the motor direction"): the move right ends on its target; a move left
/// from there stops at once.
#[test]
fn swapped_limits_read_the_right_end_as_the_left() {
    let mut sim = sim();
    sim.drive_input("LIMITS=swapped").expect("an input");
    tell(&mut sim, "00 15 00 00 19 00 00 00 20"); // StopNoRef
    tell(&mut sim, "00 31 00 64 00 FF 03 00 00"); // MinLeft 100, MaxRight off
    tell(&mut sim, "00 23 00 3C 0B 03 00 00 00"); // 199484: into the right zone
    ticks_until_idle(&mut sim, 0, 2_000_000);
    assert_eq!(position(&mut sim, 0), (199_484, 0, 0));
    assert!(carriage(&sim, 0) > 199_900, "on the right stop switch");
    assert_eq!(ask(&mut sim, "00 30 00 00 00 00 00 00 00")[2..4], [0, 0]);
    tell(&mut sim, "00 23 00 00 00 00 00 00 00"); // left: stops at once
    sim.advance(ms(10));
    let (pos, action, stop) = position(&mut sim, 0);
    assert_eq!((action, stop), (0, 1));
    assert!(pos > 199_400, "{pos}");
}

#[test]
fn stop_soft_decelerates_instead() {
    let mut sim = sim();
    tell(&mut sim, "00 15 00 00 19 00 00 00 30"); // StopSoft + StopNoRef
    tell(&mut sim, "00 31 00 00 00 58 02 00 00");
    tell(&mut sim, "00 23 00 40 0D 03 00 00 00");
    sim.advance(ms(400));
    sim.drive_input("AIN0=700").expect("an input");
    sim.advance(TICK * 2);
    let (v, action) = velocity(&mut sim, 0);
    assert!(v > 100, "still running down: {v}");
    assert_eq!(action, 5);
    ticks_until_idle(&mut sim, 0, 1000);
    assert_eq!(position(&mut sim, 0).2, 1);
}

#[test]
fn test_null_misses_the_switch_at_zero() {
    // §6.4.4: at the zero point with the switch inactive after the settle
    // time (T0 with DelayTestNull): stop flag and a reference search.
    let mut sim = sim();
    tell(&mut sim, "00 27 00 18 FC FF FF 00 00"); // position -1000: not at zero
    tell(&mut sim, "00 11 00 08 02 01 00 0A 00"); // T0 = 10 ticks
    tell(&mut sim, "00 15 00 00 19 00 00 18 48"); // TestNull, NullLeft, DelayTestNull, NullPositive
    sim.feed(&frame("00 23 00 00 00 00 00 00 00"));
    ticks_until_idle(&mut sim, 0, 5000);
    // At 0 the carriage is at 1480, off the switch.
    sim.advance(TICK * 8);
    assert!(sim.motor(0).is_some_and(Motor::is_idle), "not before T0");
    assert!(!sim.motor(0).is_some_and(Motor::stop_flag));
    sim.advance(TICK);
    let (_, action, stop) = position(&mut sim, 0);
    assert_eq!(stop, 1);
    assert!((20..=25).contains(&action), "{action}");
}

// ---- inputs -------------------------------------------------------------------

#[test]
fn input_values_show_switches_jumpers_and_the_supply() {
    let mut sim = sim();
    sim.drive_input("JP2=1").expect("an input");
    sim.drive_input("REF3=1").expect("an input");
    sim.drive_input("AIN6=300").expect("an input");
    // Channel 3: A_In 512, the opener actuated (pin high, bit 0);
    // AllInputs: the other openers idle (pins low: bits 1), JP2 bit 7.
    assert_eq!(
        ask(&mut sim, "00 30 03 00 00 00 00 00 00"),
        [0x30, 3, 0x00, 0x02, 0, 0b1011_0111, 0, 0]
    );
    assert_eq!(
        ask(&mut sim, "00 30 06 00 00 00 00 00 00")[2..4],
        [0x2C, 0x01]
    );
    // Channel 7: 24 V × 22 = 528.
    assert_eq!(
        ask(&mut sim, "00 30 07 00 00 00 00 00 00")[2..4],
        [0x10, 0x02]
    );
    tell(&mut sim, "00 30 08 00 00 00 00 00 00");
    // TTLIO1 as an input, driven high.
    tell(&mut sim, "00 32 01 01 00 00 00 00 00");
    sim.drive_input("TTLIO1=1").expect("an input");
    assert_eq!(ask(&mut sim, "00 30 00 00 00 00 00 00 00")[6], 1);
}

#[test]
fn the_jumpers_set_the_baud_rate_at_the_next_reset() {
    let mut sim = sim();
    assert_eq!(sim.unit().baud_divisor, 65);
    sim.drive_input("JP1=1").expect("an input");
    sim.drive_input("JP2=1").expect("an input");
    assert_eq!(sim.unit().baud_divisor, 65);
    sim.feed(&frame("00 CC 00 00 00 00 00 00 00"));
    sim.advance(RESET_TIME);
    assert_eq!(sim.unit().baud_divisor, 130, "9600 Bd");
}

#[test]
fn only_the_even_motors_set_a_pairs_peak_current() {
    // §7.1 $10: "Only the values set for motor-numbers 0,2 and 4 are valid."
    let mut sim = sim();
    tell(&mut sim, "00 10 01 40 00 00 00 00 00");
    assert_eq!(sim.unit().peak_current, [128; 3]);
    tell(&mut sim, "00 10 02 40 00 00 00 00 00");
    assert_eq!(sim.unit().peak_current, [128, 64, 128]);
}

#[test]
fn the_coil_current_follows_the_motion() {
    // §6.7 with the defaults: 100 % accelerating, 75 % at constant
    // velocity, 50 % stopped, 0 % after T0 (1 s).
    let mut sim = sim();
    let percent = |sim: &Sixpack2| sim.motor(0).map_or(255, Motor::current_percent);
    tell(&mut sim, "00 25 00 64 00 00 00 00 00");
    sim.feed(&frame("00 25 00 64 00 00 00 00 00"));
    sim.advance(TICK);
    assert_eq!(percent(&sim), 100);
    sim.advance(ms(500));
    assert_eq!(percent(&sim), 75);
    tell(&mut sim, "00 25 00 00 00 00 00 00 00");
    ticks_until_idle(&mut sim, 0, 1000);
    sim.advance(TICK);
    assert_eq!(percent(&sim), 50);
    sim.advance(Duration::from_secs(1));
    assert_eq!(percent(&sim), 0);
}

#[test]
fn every_input_and_choice_is_answered_in_words() {
    let mut sim = sim();
    for name in crate::sim::inputs::names(inputs::INPUTS) {
        let said = sim
            .drive_input(&format!("{name}=1"))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(said.starts_with(&name), "{name}: {said}");
    }
    assert!(sim.help_line().contains("SIXpack 2"));
}

#[test]
fn autonull_cmd_in_the_motor_parameters_starts_a_search() {
    // §7.1 $15 P5 bit 2: "$22 and CMD $15, P5, Bit2 start the same action".
    let mut sim = sim();
    sim.feed(&frame("00 15 00 00 19 00 00 54 40")); // AutonullCmd, NullLeft, StopNull, NullPositive
    assert_eq!(sim.motor(0).map(Motor::action), Some(20));
    let flags = sim.motor(0).map_or(0, |m| m.settings.flags);
    assert_eq!(flags, 0x4050, "kept without the command bit");
    actions_until_idle(&mut sim, 50_000);
    assert_eq!(carriage(&sim, 0), 399);
}

#[test]
fn the_debounce_mask_delays_the_switch() {
    // §7.1 $16: "$0001=0ms, $0003=2ms, … $FFFF=30ms"; $0FFF is 22 ms
    // (§6.2.1.8: "Filter delay 12-1 cycles"). Samples every 2 ms.
    for (mask, samples) in [("01 00", 1), ("03 00", 2), ("FF 0F", 12), ("FF FF", 16)] {
        let mut sim = sim();
        tell(&mut sim, "00 15 00 00 19 00 00 80 40"); // FilterSwitch, NullPositive
        tell(&mut sim, &format!("00 16 00 64 00 {mask} 00 00"));
        sim.drive_input("REF0=1").expect("an input");
        sim.advance(TICK * (samples - 1));
        assert!(!sim.motor(0).is_some_and(Motor::switch_active), "{mask}");
        sim.advance(TICK);
        assert!(sim.motor(0).is_some_and(Motor::switch_active), "{mask}");
    }
}

#[test]
fn the_microstep_table_is_written_four_entries_at_a_time() {
    let mut sim = sim();
    tell(&mut sim, "00 17 04 FF FF FF FF 00 00");
    let table = sim.unit().microstep_table;
    assert_eq!(table[..8], [13, 37, 62, 86, 255, 255, 255, 255]);
    tell(&mut sim, "00 17 0E 01 02 03 04 00 00"); // 14: clamped to 12
    assert_eq!(sim.unit().microstep_table[12..], [1, 2, 3, 4]);
    sim.drive_input("CLAMP=0").expect("a choice");
    tell(&mut sim, "00 17 05 09 09 09 09 00 00");
    assert_eq!(sim.unit().microstep_table[4..8], [255; 4], "dropped");
}

#[test]
fn set_actual_position_moves_the_counter_not_the_carriage() {
    let mut sim = sim();
    tell(&mut sim, "00 27 00 A0 86 01 00 00 00"); // 100000
    assert_eq!(position(&mut sim, 0).0, 100_000);
    assert_eq!(carriage(&sim, 0), 480);
}

// ---- the choices, each changed by its setting -----------------------------

#[test]
fn the_reply_choices_change_the_bytes() {
    let mut sim = sim();
    for setting in [
        "FILL=170",
        "FIRMWARE=150",
        "SERIAL=4660",
        "TEMP=45",
        "REFLEVEL=1",
        "JPOPEN=1",
    ] {
        sim.drive_input(setting).expect(setting);
    }
    assert_eq!(
        ask(&mut sim, "00 43 00 00 00 00 00 00 00"),
        [0x43, 150, 1, 45, 0x34, 0x12, 0xAA, 0xAA]
    );
    assert_eq!(
        ask(&mut sim, "00 21 01 00 00 00 00 00 00"),
        [0x21, 1, 0, 0, 0, 0xAA, 0xAA, 0xAA]
    );
    // Levels: the idle openers hold their pins low (0); no jumper fitted: 1s.
    assert_eq!(
        ask(&mut sim, "00 30 00 00 00 00 00 00 00"),
        [0x30, 0, 0x00, 0x02, 0, 0b1100_0000, 0, 0xAA]
    );
    assert_eq!(
        ask(&mut sim, "00 28 00 00 00 00 00 00 00")[7],
        0xAA,
        "$28 P6"
    );
}

#[test]
fn a_kept_address_survives_a_reset() {
    let mut sim = sim();
    sim.drive_input("KEEPADDR=1").expect("a choice");
    tell(&mut sim, "00 42 07 00 00 00 00 00 00");
    sim.feed(&frame("07 CC 00 00 00 00 00 00 00"));
    sim.advance(RESET_TIME);
    assert_eq!(sim.take_output(), [0]);
    assert_eq!(ask(&mut sim, "07 43 00 00 00 00 00 00 00")[0], 0x43);
}

#[test]
fn the_stop_switches_and_outputs_show_in_the_inputs() {
    let mut sim = sim();
    sim.drive_input("STOPL1=1").expect("an input");
    assert_eq!(ask(&mut sim, "00 30 01 00 00 00 00 00 00")[2..4], [0, 0]);
    sim.drive_input("STOPL1=0").expect("an input");
    sim.drive_input("STOPR1=1").expect("an input");
    assert_eq!(
        ask(&mut sim, "00 30 01 00 00 00 00 00 00")[2..4],
        [0xFF, 0x03]
    );
    sim.drive_input("STOPR1=stage").expect("an input");
    assert_eq!(
        ask(&mut sim, "00 30 01 00 00 00 00 00 00")[2..4],
        [0x00, 0x02]
    );
    // TTLIO1 as an output set high ($32 P1 = 0, P2 = 1).
    tell(&mut sim, "00 32 00 00 01 00 00 00 00");
    assert_eq!(ask(&mut sim, "00 30 01 00 00 00 00 00 00")[6], 1);
}

#[test]
fn the_pi_gain_may_leave_out_the_64() {
    // PIX64=0: the defaults' comment "v = position-difference / 8".
    let mut sim = sim();
    sim.drive_input("PIX64=0").expect("a choice");
    sim.feed(&frame("00 24 00 E8 03 00 00 00 00"));
    sim.advance(TICK);
    assert_eq!(sim.motor(0).map(Motor::velocity), Some(125), "1000 / 8");
}

#[test]
fn the_deceleration_may_be_as_quick_as_the_acceleration() {
    let mut sim = sim();
    sim.drive_input("SLOWDECEL=0").expect("a choice");
    sim.feed(&frame("00 23 00 A0 86 01 00 00 00")); // 100000
    let v = |sim: &Sixpack2| sim.motor(0).map_or(0, Motor::velocity);
    let (mut up, mut down) = (0, 0);
    while v(&sim) < 511 {
        sim.advance(TICK);
        up += 1;
    }
    while v(&sim) == 511 {
        sim.advance(TICK);
    }
    while v(&sim) > 5 {
        sim.advance(TICK);
        down += 1;
    }
    assert!((up - 2..=up + 2).contains(&down), "{up} up, {down} down");
}

#[test]
fn the_slow_search_velocity_and_the_mechanical_speed_are_choices() {
    // SLOWREF=0: without FastRef the first drive is at vmin (4), not 1.
    let mut sim = sim();
    sim.drive_input("SLOWREF=0").expect("a choice");
    tell(&mut sim, "00 15 00 00 19 00 00 10 40");
    sim.feed(&frame("00 22 00 00 00 00 00 00 00"));
    sim.advance(TICK * 2); // a tick to stop (at rest already), one driving
    assert_eq!(velocity(&mut sim, 0), (-4, 21));
    // MECHFAST=1: the mechanical reference at vrefmax (100).
    let mut sim = self::sim();
    sim.drive_input("MECHFAST=1").expect("a choice");
    sim.drive_input("CARRIAGE0=100000").expect("an input");
    tell(&mut sim, "00 15 00 40 0D 03 00 10 04"); // poslimit 200000
    sim.feed(&frame("00 22 00 00 00 00 00 00 00"));
    sim.advance(Duration::from_secs(1));
    assert_eq!(velocity(&mut sim, 0), (-100, 30));
}

#[test]
fn the_null_offset_on_the_right_follows_the_chosen_sign() {
    // NullLeft = 0: the switch on the right, searched ascending. Ours:
    // zero 100 further into the switch (right); OFFSETMIRROR=0: the switch
    // point is +100, zero 100 left of it.
    for (mirrored, zero_at) in [("1", 199_700), ("0", 199_500)] {
        let mut sim = sim();
        sim.drive_input(&format!("OFFSETMIRROR={mirrored}"))
            .expect("a choice");
        sim.drive_input("REFAT0=199600").expect("an input");
        sim.drive_input("CARRIAGE0=199590").expect("an input");
        tell(&mut sim, "00 18 00 64 00 00 00 F0 00"); // offset 100
        tell(&mut sim, "00 16 00 64 00 FF 0F 01 00"); // stop after the search
        tell(&mut sim, "00 15 00 00 19 00 00 00 40"); // NullPositive
        sim.feed(&frame("00 22 00 00 00 00 00 00 00"));
        actions_until_idle(&mut sim, 50_000);
        assert_eq!(position(&mut sim, 0).0, 0);
        assert_eq!(carriage(&sim, 0), zero_at, "OFFSETMIRROR={mirrored}");
    }
}
