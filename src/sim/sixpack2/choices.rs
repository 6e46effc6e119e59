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

    /// The choices in words, for the simulator's help: each followed by
    /// the setting that changes it, in brackets.
    pub fn describe(&self) -> String {
        let pick = |b: bool, yes: &str, no: &str| if b { yes } else { no }.to_string();
        let second = match self.second_28 {
            Second28::EachOwn => {
                "a $28 while another waits: each answered when its own motors are idle"
            }
            Second28::Replace => "a $28 while another waits replaces it",
            Second28::Ignore => "a $28 while another waits is dropped",
        };
        let timeout = match self.packet_timeout {
            0 => "no packet timeout".to_string(),
            n => format!(
                "packet timeout {} ms at power-on and after $CC, counted from a frame's first byte",
                u32::from(n) * 2
            ),
        };
        let slow_search = match self.slow_search_velocity {
            0 => "without FastRef the search drives at vmin (div 3) and takes the edge it meets"
                .to_string(),
            v => format!(
                "without FastRef the search drives at velocity {v} (div 3, §6.4.8) and takes the edge it meets"
            ),
        };
        let choices: [(String, &str); 31] = [
            (self.describe_framing().to_string(), "ADDR9"),
            (format!("reply bytes without a meaning (the rest of $21, $28 P6, …) ${:02X}", self.fill), "FILL"),
            (second.to_string(), "SECOND28"),
            (timeout, "TIMEOUT"),
            ("a BREAK is a line event, not a byte: it drops the frame in progress".to_string(), "BREAK on the standard input"),
            (format!(
                "a command acts {} ms after its last byte (a $20 right after a $23 shows action 5), motion from the next 2 ms tick",
                self.latency.as_millis()
            ), "LATENCY"),
            (pick(
                self.out_of_range == OutOfRange::Clamp,
                "values outside their §7 range are clamped (vstart to its firmware limit, amax to 64·vstart, vmin to vstart and 250 Hz)",
                "a frame with a value outside its §7 range is dropped",
            ), "CLAMP"),
            ("unknown commands, motno > 5, $30/$31 channels > 7 and the service commands $F2..$F7 are dropped without a reply; $12, $13, $16 while moving act at once (a new div at the next rest)".to_string(), "-"),
            (format!(
                "ramps decelerate at amax·{}/1000 and creep at vstart to the target; stops, overshoots and speed changes use amax",
                1000 - u32::from(self.slower_deceleration.min(999))
            ), "SLOWDECEL"),
            (pick(
                self.pi_times_64,
                "PI: v = 64·Δ/propdiv + I/intdiv, limited to ±vmax, no acceleration limit",
                "PI: v = Δ/propdiv + I/intdiv, limited to ±vmax, no acceleration limit",
            ), "PIX64"),
            (pick(self.pi_holds, "PI stays action 10 at its target", "PI ends (action 0) at its target"), "PIHOLD"),
            (pick(self.rotation_holds, "a rotation at velocity 0 stays action 15", "a rotation at velocity 0 ends (action 0)"), "ROTHOLD"),
            (pick(
                self.ramp_after_rotation,
                "$23 during a rotation stops it, then drives to the target (§6.6.3)",
                "$23 during a rotation only stops it (§7.2)",
            ), "ROTRAMP"),
            ("$2A turns a rotation into a ramp back to where it was (overshoot and return) and retargets PI; $23 $24 $25 $26 $29 $2A $50 leave a reference search alone; $29 leaves an active motor alone; $50 starts nothing if a masked motor is active; $26 at rest only stores the target; $27 is taken while moving (the ramp goes on to its target)".to_string(), "-"),
            ("$50: the lead (the longest time at its own vmax) ramps with its own settings, the others keep their share of its progress, on a straight line".to_string(), "-"),
            ("StopAtFullsteps: a ramp ends on the full step (multiple of 16) nearest its target, a tie in the direction of travel; rotary axes wrap the counter every tick, targets and $27 positions into range".to_string(), "-"),
            ("search codes 20 stopping, 21 driving to the switch, 22 backing off, 23 slow approach at vmin, 24 crossing it (NullCenter), 25 driving to zero; 30 the whole mechanical reference".to_string(), "-"),
            (slow_search, "SLOWREF"),
            (pick(
                self.mech_ref_at_vrefmax,
                "the mechanical reference drives at vrefmax",
                "the mechanical reference drives as a ramp (vstart, vmax, amax)",
            ), "MECHFAST"),
            (pick(
                self.offset_mirrored,
                "a positive nulloffset puts zero that far into the switch on either side (the switch point gets +nulloffset with NullLeft, -nulloffset without); the mechanical stop likewise",
                "the switch point (or the mechanical stop) gets coordinate +nulloffset on either side",
            ), "OFFSETMIRROR"),
            ("NullCenter: zero is the middle of the two edges met at vmin; the slow approach gives up (and all starts again) past twice the back-off; retries at once, without limit; after $2B the motor brakes and stays unreferenced; after the search a motor at rest drives back to the number it started at, a ramp, rotation or PI goes on".to_string(), "-"),
            ("a stop condition stops abruptly: above vstart the carriage runs on a tick's travel (steps lost); TestNull looks once per rest at exactly position 0, after T0 (DelayTestNull) and the debounce delay; no stop condition during a search".to_string(), "-"),
            (pick(
                self.ref_bits_are_levels,
                "$30 shows the reference inputs' electrical levels",
                "$30 shows the reference inputs inverted (1 = pin low); channels 6/7 P3 = 0",
            ), "REFLEVEL"),
            (pick(self.jumper_bits_open, "$30 jumper bits 1 = open", "$30 jumper bits 1 = fitted; the jumpers set the baud rate at the next reset"), "JPOPEN"),
            (pick(
                self.limits_need_stop_null,
                "$31 limits act only with StopNull, strictly (below MinLeft, above MaxRight); off after a reset (0, 1023); channels 6/7 kept, acting on nothing",
                "$31 limits act without StopNull, strictly (below MinLeft, above MaxRight); off after a reset (0, 1023); channels 6/7 kept, acting on nothing",
            ), "LIMITSTOPNULL"),
            (pick(self.address_kept, "a $42 address survives $CC", "$42 acts at once; $CC reads the rotary switches again"), "KEEPADDR"),
            ("$40: the switch-over delay acts from the next reply; the baud divisor is kept, the line does not follow; $44 answers 0 bytes waiting, CTS 0".to_string(), "-"),
            (match self.reset_key {
                None => "$CC resets with any P0".to_string(),
                Some(key) => format!("$CC resets only with P0 = {key}"),
            }, "RESETKEY"),
            (pick(
                self.stray_zero,
                "$CC: deaf for 1 s, then one $00 byte (none at power-on)",
                "$CC: deaf for 1 s, no $00 byte",
            ), "STRAY00"),
            ("the coils get I3 while the velocity changes (decelerating too), I2 at constant velocity, I1 at rest, I0 after T0".to_string(), "-"),
            (format!("$43: firmware {}, serial {}, {} °C", self.firmware, self.serial, self.temperature), "FIRMWARE, SERIAL, TEMP"),
        ];
        choices
            .iter()
            .map(|(text, setting)| match *setting {
                "-" => text.clone(),
                setting => format!("{text} [{setting}]"),
            })
            .collect::<Vec<_>>()
            .join("; ")
    }
}
