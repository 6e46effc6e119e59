//! What a host sets on a SIXpack 2 (§7.1, §7.3, §7.4), the values after a
//! reset (§6.2.1.8 = §6.8; digest D7), and how a received value is fitted
//! into its §7 range.
//!
//! Nothing here can be read back over the wire: the manual has no getters
//! for $10–$19 or $31–$42 (digest D0). The simulator keeps them to act on.

use std::ops::RangeInclusive;

/// Motors 0..5 ("Motor 1..6" in the manual's prose).
pub const MOTORS: usize = 6;

/// The bits of the $15 motor-type word: P5 is the low byte, P6 the high
/// one (§7.1; "modifier-bits 12 & 13" are P6 bits 4 and 5, which places
/// StopNoRef at P6 bit 5, not the bit 6 its own line names: erratum E13).
pub mod flag {
    pub const PI_MODE: u16 = 1 << 0;
    pub const ROTARY: u16 = 1 << 1;
    pub const AUTONULL_CMD: u16 = 1 << 2;
    pub const TEST_NULL: u16 = 1 << 3;
    pub const NULL_LEFT: u16 = 1 << 4;
    pub const NULL_CENTER: u16 = 1 << 5;
    pub const STOP_NULL: u16 = 1 << 6;
    pub const FILTER_SWITCH: u16 = 1 << 7;
    pub const WAY_OPTIMIZATION: u16 = 1 << 8;
    pub const FAST_REF: u16 = 1 << 9;
    pub const MECH_REF: u16 = 1 << 10;
    pub const DELAY_TEST_NULL: u16 = 1 << 11;
    pub const STOP_SOFT: u16 = 1 << 12;
    pub const STOP_NO_REF: u16 = 1 << 13;
    pub const NULL_POSITIVE: u16 = 1 << 14;
    pub const STOP_AT_FULLSTEPS: u16 = 1 << 15;
}

/// The motor-type word after a reset: DelayTestNull | NullCenter |
/// FilterSwitch | FastRef ("Delayedtesto | NullCenter | Filterswitch |
/// FastRef", §6.2.1.8; erratum E25), $0AA0.
pub const DEFAULT_FLAGS: u16 =
    flag::DELAY_TEST_NULL | flag::NULL_CENTER | flag::FILTER_SWITCH | flag::FAST_REF;

/// The microstep table after a reset: 255·sin((i + 0.5)·π/32), a quarter
/// sine period over one full step (§7.1 $17), rounded to nearest.
pub const SINE_TABLE: [u8; 16] = [
    13, 37, 62, 86, 109, 131, 152, 171, 189, 205, 219, 231, 240, 247, 252, 255,
];

/// Coil current in per cent of the peak current by current index (§7.1
/// $11: "0=100%, 75, 50, 38, 25, 19, [13, 9,] 0%"; 0-based as the §6.7
/// example shows, erratum E11).
pub const CURRENT_PERCENT: [u8; 9] = [100, 75, 50, 38, 25, 19, 13, 9, 0];

/// The §7 setting commands of one motor.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MotorSettings {
    /// $11 I0..I3: power-down, stopped, constant velocity, accelerating.
    pub current_index: [u8; 4],
    /// $11 T0 in 2 ms ticks: power-down delay, and the DelayTestNull
    /// settle time (§6.4.6).
    pub t0: u16,
    /// $13: slow reference approach velocity (always at div 3; 0 = the
    /// fastest allowed), start/stop velocity, predivider.
    pub vmin: u16,
    pub vstart: u16,
    pub div: u8,
    /// $14: acceleration (amax/64 velocity units per 2 ms) and top speed.
    pub amax: u16,
    pub vmax: u16,
    /// $15: µsteps per revolution (rotary) or the travel (linear), and the
    /// motor-type word ([`flag`]).
    pub poslimit: u32,
    pub flags: u16,
    /// $16: fast search velocity, debounce mask, stop after the search.
    pub vrefmax: u16,
    pub debounce_mask: u16,
    pub stop_after_search: bool,
    /// $18: distance between the zero point and the switch, and the zone
    /// around zero where the switch is not checked.
    pub null_offset: i32,
    pub test_null_range: u16,
    /// $19.
    pub propdiv: u8,
    pub intdiv: u16,
    pub intclip: u16,
    pub intinpclip: u8,
    /// $31 for this motor's A_In: 0 = no left stop, ≥ 1023 = no right stop.
    pub min_left: u16,
    pub max_right: u16,
}

impl Default for MotorSettings {
    /// §6.2.1.8 (digest D7). The $31 limits are "not given": 0 and 1023,
    /// both off (a literal 0 for MaxRight would stop every move to the
    /// right, E31).
    fn default() -> Self {
        MotorSettings {
            current_index: [8, 2, 1, 0],
            t0: 500,
            vmin: 4,
            vstart: 5,
            div: 2,
            amax: 128,
            vmax: 511,
            poslimit: 400 * 16,
            flags: DEFAULT_FLAGS,
            vrefmax: 100,
            debounce_mask: 0x0FFF,
            stop_after_search: false,
            null_offset: 0,
            test_null_range: 15 * 16,
            propdiv: 8,
            intdiv: 129,
            intclip: 129,
            intinpclip: 1,
            min_left: 0,
            max_right: 1023,
        }
    }
}

impl MotorSettings {
    pub fn has(&self, bit: u16) -> bool {
        self.flags & bit != 0
    }

    /// The search direction, towards the zero side: descending with
    /// NullLeft, ascending without ("zero is the largest number", §7.1 $15).
    pub fn search_direction(&self) -> i32 {
        if self.has(flag::NULL_LEFT) { -1 } else { 1 }
    }
}

/// Settings that belong to the unit rather than a motor.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnitSettings {
    /// $12, global to all motors.
    pub clkdiv: u8,
    /// $10 peak current of the pairs 0+1, 2+3, 4+5.
    pub peak_current: [u8; 3],
    /// $17.
    pub microstep_table: [u8; 16],
    /// $32: TTLOUT1 level, TTLIO1 as input, TTLIO1 output level, TTLOUT1
    /// as the ready output.
    pub ttlout1: bool,
    pub ttlio1_input: bool,
    pub ttlio1_level: bool,
    pub ttlout1_ready: bool,
    /// $33: motors whose motion, and whose reference search, make the
    /// ready output active.
    pub ready_active_mask: u8,
    pub ready_search_mask: u8,
    /// $40: baud divisor (20 MHz / (16·baud)) and transmitter switch-over
    /// delay in 2 ms units.
    pub baud_divisor: u16,
    pub switch_over: u16,
    /// $41 in 2 ms units; 0: a partial frame is never dropped.
    pub packet_timeout: u16,
    /// $44 (CAN only): response address and bytes per forwarded packet.
    pub can_forward_address: u8,
    pub can_forward_bytes: u8,
}

impl UnitSettings {
    /// After a reset: §6.2.1.8, TTLOUT1 high (§3.1), the switch-over delay
    /// 6 ms (§6.1.1), "all other values 0"; the baud divisor from the
    /// jumpers and the packet timeout as the simulator chose.
    pub fn after_reset(baud_divisor: u16, packet_timeout: u16) -> UnitSettings {
        UnitSettings {
            clkdiv: 5,
            peak_current: [128; 3],
            microstep_table: SINE_TABLE,
            ttlout1: true,
            ttlio1_input: false,
            ttlio1_level: false,
            ttlout1_ready: false,
            ready_active_mask: 0x3F,
            ready_search_mask: 0x3F,
            baud_divisor,
            switch_over: 3,
            packet_timeout,
            can_forward_address: 0,
            can_forward_bytes: 0,
        }
    }
}

/// The baud rate the jumpers select (Table 5.1: JP1 + JP2 9600, JP2 57600,
/// JP1 38400, none 19200).
pub fn jumper_baud(jp1: bool, jp2: bool) -> u32 {
    match (jp1, jp2) {
        (true, true) => 9600,
        (false, true) => 57600,
        (true, false) => 38400,
        (false, false) => 19200,
    }
}

/// The $40 divisor of a baud rate: 20 MHz / (16·baud), rounded (§7.4).
pub fn baud_divisor(baud: u32) -> u16 {
    let exact = 20_000_000.0 / (16.0 * f64::from(baud.max(1)));
    u16::try_from(exact.round() as u64).unwrap_or(u16::MAX)
}

/// What becomes of a value outside its §7 range (the manual does not say,
/// digest D10.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutOfRange {
    /// Brought to the nearest end of the range.
    Clamp,
    /// The whole frame is dropped; the setting keeps its value.
    Ignore,
}

impl OutOfRange {
    /// `value` in `range`, or what this policy makes of it (`None`: drop
    /// the frame).
    pub fn fit(self, value: i64, range: RangeInclusive<i64>) -> Option<i64> {
        if range.contains(&value) {
            return Some(value);
        }
        match self {
            OutOfRange::Clamp => Some(value.clamp(*range.start(), *range.end())),
            OutOfRange::Ignore => None,
        }
    }
}

/// The firmware's limit on vstart for a predivider: `0 < vstart < (512 >>
/// (3 − div)) − 1` (§7.1 $13), so the largest allowed is 61, 125, 253, 509.
/// (The manual's own example says "< 256" for div 2; E7: the formula wins.)
pub fn vstart_limit(div: u8) -> u16 {
    (512u16 >> (3 - div.min(3))) - 2
}

/// vmin = 0 "lets the firmware pick the fastest allowed value" (§7.1
/// $13): the largest vmin with vmin·f(1, div 3) ≤ 250 Hz, and at most
/// vstart.
pub fn fastest_vmin(clkdiv: u8, vstart: u16) -> u16 {
    // f(1, div 3) = 20 MHz / (clkdiv + 1) / 2^17.
    let most = 250.0 * f64::from(u32::from(clkdiv) + 1) * f64::from(1u32 << 17) / 20e6;
    let most = most.floor().max(1.0) as u16;
    most.min(vstart.max(1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_word_is_the_manuals_0aa0() {
        // §6.2.1.8, and the bytes P5 = $A0, P6 = $0A (digest D7).
        assert_eq!(DEFAULT_FLAGS, 0x0AA0);
        assert_eq!(DEFAULT_FLAGS as u8, 0xA0);
        assert_eq!((DEFAULT_FLAGS >> 8) as u8, 0x0A);
    }

    #[test]
    fn the_sine_table_is_the_formula_of_section_7_1() {
        for (i, &entry) in SINE_TABLE.iter().enumerate() {
            let exact = 255.0 * ((i as f64 + 0.5) / 32.0 * std::f64::consts::PI).sin();
            assert_eq!(f64::from(entry), exact.round(), "entry {i}");
        }
    }

    #[test]
    fn the_vstart_limit_follows_the_formula() {
        // 0 < vstart < (512 shr (3 - div)) - 1.
        assert_eq!(
            [0, 1, 2, 3].map(vstart_limit),
            [62, 126, 254, 510],
            "div 2: below 255 (E7)"
        );
    }

    #[test]
    fn the_jumpers_pick_the_rates_of_table_5_1() {
        assert_eq!(jumper_baud(false, false), 19200);
        assert_eq!(jumper_baud(true, true), 9600);
        assert_eq!(jumper_baud(false, true), 57600);
        assert_eq!(jumper_baud(true, false), 38400);
        // 20 MHz / (16 · 19200) = 65.1.
        assert_eq!(baud_divisor(19200), 65);
        assert_eq!(baud_divisor(9600), 130);
    }

    #[test]
    fn the_fastest_vmin_keeps_below_250_hz() {
        // f(1, div 3) at clkdiv 5 is 25.43 Hz: 9 · 25.43 = 229 Hz, 10 would be 254.
        assert_eq!(fastest_vmin(5, 511), 9);
        assert_eq!(fastest_vmin(5, 5), 5, "and at most vstart");
    }

    #[test]
    fn values_outside_their_range_are_clamped_or_dropped() {
        assert_eq!(OutOfRange::Clamp.fit(40, 0..=31), Some(31));
        assert_eq!(OutOfRange::Ignore.fit(40, 0..=31), None);
        assert_eq!(OutOfRange::Ignore.fit(31, 0..=31), Some(31));
        assert_eq!(OutOfRange::Clamp.fit(0, 1..=511), Some(1));
    }
}
