//! What the simulator does where the manual is silent (digest D10.3): each
//! choice has a default, a line in the help, and a setting that changes it
//! (`--input ADDR9=1`, a line on the standard input of `axterm sim`,
//! `:sim-input`; see [`super::inputs`]).

use std::time::Duration;

use super::settings::OutOfRange;

/// Whether a reply carries the response address in front of its command
/// byte (digest D1.4: the manual's reading is 8 bytes, `CMD P0..P6`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReplyFraming {
    /// `CMD P0..P6`, as §6.2.2.3's pseudocode reads it.
    Cmd8,
    /// `RESPADDR CMD P0..P6`, mirroring the request and the CAN ID.
    Addr9,
}

/// What a second $28 does while one is waiting (not described, D4 $28).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Second28 {
    /// Each is answered when its own masked motors are idle.
    EachOwn,
    /// The newer one replaces the waiting one, which is never answered.
    Replace,
    /// The newer one is dropped while one waits.
    Ignore,
}

/// The simulator's choices.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Choices {
    pub framing: ReplyFraming,
    /// The bytes of a reply the manual gives no meaning (the rest of a
    /// $21, $28 P6, …).
    pub fill: u8,
    pub second_28: Second28,
    /// The packet timeout after a reset, in 2 ms units (0: none).
    pub packet_timeout: u16,
    /// From a frame's last byte to its command acting.
    pub latency: Duration,
    pub out_of_range: OutOfRange,
    /// How much more slowly a ramp decelerates than it accelerates ("decelerates
    /// more slowly", §6.3.1.1), per mille: the deceleration is
    /// amax·(1000 − this)/1000. Stops ($26 overshoot, StopSoft, $2A) use amax.
    pub slower_deceleration: u16,
    /// The PI P term is 64·Δ/propdiv (§7.1) rather than Δ/propdiv (the
    /// defaults' comment, E14).
    pub pi_times_64: bool,
    /// PI control stays active (action 10) at its target rather than ending
    /// (action 0) there.
    pub pi_holds: bool,
    /// A rotation brought to velocity 0 stays action 15 rather than 0.
    pub rotation_holds: bool,
    /// $23 during a rotation stops it and then drives to the target (§6.6.3)
    /// rather than only stopping it (§7.2; E20).
    pub ramp_after_rotation: bool,
    /// The search velocity without FastRef (§6.4.8 "a fixed velocity of 1"),
    /// at div 3 as the slow approach; 0: the approach velocity vmin.
    pub slow_search_velocity: u16,
    /// The mechanical reference drives at vrefmax rather than as a ramp
    /// (vstart, vmax, amax).
    pub mech_ref_at_vrefmax: bool,
    /// A positive nulloffset moves zero into the switch on either side
    /// (mirrored for NullLeft = 0) rather than giving the switch point the
    /// coordinate +nulloffset whatever the side.
    pub offset_mirrored: bool,
    /// $30 shows the reference inputs' electrical levels rather than
    /// inverted ("The reference inputs are inverted", §7.3).
    pub ref_bits_are_levels: bool,
    /// The $30 jumper bits are 1 for an open jumper rather than a fitted one.
    pub jumper_bits_open: bool,
    /// The $31 limits act only with StopNull set.
    pub limits_need_stop_null: bool,
    /// A $42 address survives $CC (else the rotary switches are read again).
    pub address_kept: bool,
    /// The $CC P0 that resets; `None`: any.
    pub reset_key: Option<u8>,
    /// $CC is followed by one $00 byte ("usually", §7.4).
    pub stray_zero: bool,
    /// $43: firmware revision (the manual's example: 148 = V1.4.8), serial
    /// number, temperature in °C.
    pub firmware: u8,
    pub serial: u16,
    pub temperature: u8,
}

impl Default for Choices {
    fn default() -> Self {
        Choices {
            framing: ReplyFraming::Cmd8,
            fill: 0,
            second_28: Second28::EachOwn,
            packet_timeout: 25,
            latency: Duration::ZERO,
            out_of_range: OutOfRange::Clamp,
            slower_deceleration: 500,
            pi_times_64: true,
            pi_holds: false,
            rotation_holds: false,
            ramp_after_rotation: false,
            slow_search_velocity: 1,
            mech_ref_at_vrefmax: false,
            offset_mirrored: true,
            ref_bits_are_levels: false,
            jumper_bits_open: false,
            limits_need_stop_null: false,
            address_kept: false,
            reset_key: None,
            stray_zero: true,
            firmware: 148,
            serial: 1,
            temperature: 30,
        }
    }
}

impl Choices {
    /// The reply framing in words.
    pub fn describe_framing(&self) -> &'static str {
        match self.framing {
            ReplyFraming::Cmd8 => {
                "replies are 8 bytes CMD P0..P6 (ADDR9=1: response address first)"
            }
            ReplyFraming::Addr9 => "replies are 9 bytes RESPADDR CMD P0..P6 (ADDR9=0: 8 bytes)",
        }
    }

    /// The choices in words, for the simulator's help.
    pub fn describe(&self) -> String {
        let yes_no = |b: bool, yes: &str, no: &str| if b { yes } else { no }.to_string();
        let framing = self.describe_framing();
        let second = match self.second_28 {
            Second28::EachOwn => "each waiting $28 is answered when its own motors are idle",
            Second28::Replace => "a second $28 replaces the waiting one",
            Second28::Ignore => "a second $28 is dropped while one waits",
        };
        let timeout = if self.packet_timeout == 0 {
            "no packet timeout after a reset".to_string()
        } else {
            format!(
                "packet timeout {} ms after a reset, from a frame's first byte",
                u32::from(self.packet_timeout) * 2
            )
        };
        let slow_search = if self.slow_search_velocity == 0 {
            "without FastRef the search drives at vmin (div 3)".to_string()
        } else {
            format!(
                "without FastRef the search drives at velocity {} (div 3) and takes the switch edge at once",
                self.slow_search_velocity
            )
        };
        [
            framing.to_string(),
            format!("unspecified reply bytes ${:02X}", self.fill),
            second.to_string(),
            timeout,
            format!(
                "a command acts {} ms after its last byte, motion from the next 2 ms tick",
                self.latency.as_millis()
            ),
            yes_no(
                self.out_of_range == OutOfRange::Clamp,
                "values outside their §7 range are clamped (vstart to its firmware limit, amax to 64·vstart)",
                "frames with values outside their §7 range are dropped",
            ),
            "unknown commands, motno > 5 and the service commands $F2..$F7 are dropped without a reply"
                .to_string(),
            format!(
                "ramps decelerate at amax·{}/1000, stops and overshoots at amax",
                1000 - u32::from(self.slower_deceleration.min(999))
            ),
            yes_no(
                self.pi_times_64,
                "PI: v = 64·Δ/propdiv + I/intdiv, limited to ±vmax, no acceleration limit",
                "PI: v = Δ/propdiv + I/intdiv, limited to ±vmax, no acceleration limit",
            ),
            yes_no(
                self.pi_holds,
                "PI stays action 10 at its target",
                "PI ends (action 0) at its target",
            ),
            yes_no(
                self.rotation_holds,
                "a rotation at velocity 0 stays action 15",
                "a rotation at velocity 0 ends (action 0)",
            ),
            yes_no(
                self.ramp_after_rotation,
                "$23 during a rotation stops it, then drives to the target",
                "$23 during a rotation only stops it",
            ),
            "$2A stops a rotation or PI like a ramp (overshoot and return); $23, $24, $25, $26, $29, $2A, $50 leave a reference search alone"
                .to_string(),
            "$50: the lead axis (longest time at its vmax) ramps, the others follow its progress on the line".to_string(),
            "StopAtFullsteps: a ramp ends on the nearest full step (multiple of 16) to its target".to_string(),
            "rotary axes wrap the counter every tick, and targets and $27 positions into range".to_string(),
            "search codes: 20 stopping, 21 driving to the switch, 22 backing off, 23 slow approach, 24 crossing (NullCenter), 25 driving to zero; 30 mechanical".to_string(),
            slow_search,
            yes_no(
                self.mech_ref_at_vrefmax,
                "the mechanical reference drives at vrefmax",
                "the mechanical reference drives as a ramp (vstart, vmax, amax)",
            ),
            yes_no(
                self.offset_mirrored,
                "a positive nulloffset moves zero into the switch on either side",
                "the switch point gets coordinate +nulloffset on either side",
            ),
            "NullCenter: zero is the middle of the two edges found at vmin; retries at once, without limit; after $2B the motor stops where it is, unreferenced".to_string(),
            yes_no(
                self.ref_bits_are_levels,
                "$30 shows the reference inputs' electrical levels",
                "$30 shows the reference inputs inverted (1 = input pulled low)",
            ),
            yes_no(
                self.jumper_bits_open,
                "$30 jumper bits 1 = open",
                "$30 jumper bits 1 = fitted",
            ),
            yes_no(
                self.limits_need_stop_null,
                "$31 limits act only with StopNull, checked strictly (below MinLeft, above MaxRight), not during a search",
                "$31 limits act without StopNull, checked strictly (below MinLeft, above MaxRight), not during a search",
            ),
            yes_no(
                self.address_kept,
                "a $42 address survives $CC",
                "$CC reads the address from the rotary switches again",
            ),
            "$40 changes the switch-over delay at once; its baud divisor is kept, the line does not follow"
                .to_string(),
            match self.reset_key {
                None => "$CC resets with any P0".to_string(),
                Some(key) => format!("$CC resets only with P0 = {key}"),
            },
            yes_no(
                self.stray_zero,
                "$CC: deaf for 1 s, then one $00 byte",
                "$CC: deaf for 1 s, no $00 byte",
            ),
            format!(
                "$43: firmware {}, serial {}, {} °C",
                self.firmware, self.serial, self.temperature
            ),
        ]
        .join("; ")
    }
}
