//! A simulator of the Trinamic SIXpack 2 (manual rev. 1.10) on its RS-232
//! /RS-485 link: 9-byte requests `ADDR CMD P0..P6` in, 8-byte replies
//! `CMD P0..P6` out for the six commands that answer ($20 $21 $28 $30 $43
//! $44), six motors on the firmware's 2 ms tick.
//!
//! A plain state machine: bytes in ([`SimulatedController::feed`]), virtual
//! time ([`SimulatedController::advance`]), bytes out
//! ([`SimulatedController::take_output`]), a BREAK on the line
//! ([`SimulatedController::line_break`]). No clock, no sleeping, no I/O.
//! Requests are read by this module's own reading of the manual
//! ([`command`]), independently of the console's codec.
//!
//! What it does (digest D10):
//! - the link: frames must arrive whole within the packet timeout ($41,
//!   from the frame's first byte); a BREAK abandons the frame in progress;
//!   frames for another address are dropped silently, as are unknown
//!   commands and motor numbers above 5; setting commands get no reply;
//!   replies leave after the transmitter switch-over delay ($40, 6 ms), as
//!   8 bytes or, as a choice, 9 with the response address first; $CC makes
//!   it deaf for a second, then (usually) sends one $00 byte and comes up
//!   with the defaults of §6.2.1.8, the address of its rotary switches, the
//!   baud rate of its jumpers and the $43 reset flag set;
//! - $28 answers when its masked motors are idle, while other requests go
//!   on (the RS-232 exception of §6.2.1.7);
//! - motion ([`motor`]): the §6.3.1 step frequency from a phase
//!   accumulator, ramps starting at vstart and accelerating by amax/64 a
//!   tick (errata E8, E9, E10 corrected), deceleration more gentle than
//!   acceleration, overshoot and return when a target moves too late
//!   ($26, $2A), PI control, rotation, rotary axes, StopAtFullsteps, $29,
//!   $50 (the lead axis ramps, the others follow along the line);
//! - the reference search ([`search`]), switch and mechanical, with
//!   retries, NullCenter, nulloffset and the resumption of what it
//!   interrupted; the stop conditions StopNull, TestNull and the $31
//!   limits, StopSoft and StopNoRef; the latched stop flag;
//! - the machine behind each motor ([`stage`]): a carriage apart from the
//!   counter, mechanical stops where the motor stalls and loses steps, the
//!   reference switch (an opener at the left end by default) and the stop
//!   switches on A_In.
//!
//! Where the manual is silent the simulator chooses; every choice is in
//! [`choices::Choices`], listed by [`Sixpack2::help_line`] and docs/sixpack2.md,
//! and changed by a setting ([`inputs`]). It keeps nothing between runs:
//! see [`NOTHING_STORED`].

pub mod choices;
pub mod command;
pub mod inputs;
pub mod motor;
pub mod search;
pub mod settings;
pub mod stage;
pub mod wire;

#[cfg(test)]
mod tests;

use std::collections::VecDeque;
use std::ops::RangeInclusive;
use std::time::Duration;

use super::SimulatedController;
use super::inputs::{Level, SettingError};
use choices::{Choices, ReplyFraming, Second28};
use command::{Command, REQUEST_LEN};
use inputs::Input;
use motor::{Follow, Mode, Motor, TICK, Ticking, steps_per_tick};
use settings::{
    MOTORS, OutOfRange, UnitSettings, baud_divisor, fastest_vmin, flag, jumper_baud, vstart_limit,
};
use stage::{Mechanics, Stage};
use wire::{Outbox, Receiver, reply_bytes};

/// The simulator as `--sim sixpack2` names it.
pub const KIND: super::SimKind = super::SimKind {
    name: "sixpack2",
    description: "Trinamic SIXpack 2 (9-byte binary frames, 6 axes)",
    build: |options| {
        let mut config = SimConfig::default();
        if let Some(address) = options.address {
            config.rotary_address = address;
        }
        Box::new(Sixpack2::new(config))
    },
    input_names: || super::inputs::names(inputs::INPUTS),
    input_help: || super::inputs::help_lines(inputs::INPUTS),
    eeprom_refusal: Some(NOTHING_STORED),
};

/// Why `axterm sim sixpack2 --eeprom FILE` is refused.
pub const NOTHING_STORED: &str = "the SIXpack 2 keeps nothing a host sets between power-ups: \
     every setting returns to its default at a reset (§6.2.1.8, §7.4 $CC), a $40 baud rate \
     \"is not stored permanently\" (§5.2.3), the address and baud rate come from its rotary \
     switches and jumpers (§5.2.1, §5.2.3), and its EEPROM is reachable only through the \
     undocumented service commands $F6/$F7 (§7.6)";

/// How long $CC takes ("about 1 second", §7.4).
pub const RESET_TIME: Duration = Duration::from_secs(1);

/// The supply voltage at power-on (ours: 24 V, within 15..48 V).
pub const DEFAULT_SUPPLY_VOLTS: u8 = 24;

/// Counts per volt on $30 channel 7 (§7.3).
pub const COUNTS_PER_VOLT: u16 = 22;

/// How the simulated unit is built.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SimConfig {
    /// The address of its rotary switches (CANHI/CANLO, §5.2.1; factory 0).
    pub rotary_address: u8,
    /// The baud jumpers JP1, JP2 fitted (Table 5.1; none: 19200 Bd).
    pub jumpers: [bool; 2],
    pub choices: Choices,
    /// The machine behind each motor.
    pub stages: [Stage; MOTORS],
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            rotary_address: 0,
            jumpers: [false; 2],
            choices: Choices::default(),
            stages: std::array::from_fn(|_| Stage::default()),
        }
    }
}

/// A $28 waiting for its motors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct ActivityRequest {
    respond_to: u8,
    mask: u8,
    asked: Duration,
}

/// The simulated unit.
pub struct Sixpack2 {
    config: SimConfig,
    /// Virtual time since power-on.
    now: Duration,
    next_tick: Duration,
    receiver: Receiver,
    /// Frames received, waiting for the chosen latency.
    received: VecDeque<(Duration, [u8; REQUEST_LEN])>,
    outbox: Outbox,
    output: Vec<u8>,
    activity_requests: Vec<ActivityRequest>,
    unit: UnitSettings,
    /// $31 limits of channels 6 and 7: kept, acting on no motor.
    spare_limits: [(u16, u16); 2],
    address: u8,
    reset_flag: bool,
    resetting_until: Option<Duration>,
    motors: [Motor; MOTORS],
    interpolations: u32,
    ttlio1_input: bool,
    external_analog: u16,
    supply_volts: u8,
    drivers_enabled: bool,
}

impl Sixpack2 {
    pub fn new(config: SimConfig) -> Sixpack2 {
        let motors = std::array::from_fn(|i| Motor::new(Mechanics::new(config.stages[i].clone())));
        let mut sim = Sixpack2 {
            now: Duration::ZERO,
            next_tick: TICK,
            receiver: Receiver::default(),
            received: VecDeque::new(),
            outbox: Outbox::default(),
            output: Vec::new(),
            activity_requests: Vec::new(),
            unit: UnitSettings::after_reset(0, 0),
            spare_limits: [(0, 1023); 2],
            address: config.rotary_address,
            reset_flag: true,
            resetting_until: None,
            motors,
            interpolations: 0,
            ttlio1_input: false,
            external_analog: 0,
            supply_volts: DEFAULT_SUPPLY_VOLTS,
            drivers_enabled: true,
            config,
        };
        sim.power_up(false);
        sim
    }

    /// The address it answers to now.
    pub fn address(&self) -> u8 {
        self.address
    }

    pub fn motor(&self, motor: usize) -> Option<&Motor> {
        self.motors.get(motor)
    }

    pub fn motor_mut(&mut self, motor: usize) -> Option<&mut Motor> {
        self.motors.get_mut(motor)
    }

    pub fn unit(&self) -> &UnitSettings {
        &self.unit
    }

    pub fn choices(&self) -> &Choices {
        &self.config.choices
    }

    pub fn choices_mut(&mut self) -> &mut Choices {
        &mut self.config.choices
    }

    /// Partial frames dropped so far (packet timeout, BREAK).
    pub fn dropped_frames(&self) -> u64 {
        self.receiver.dropped()
    }

    /// $CC is under way: nothing is heard.
    pub fn is_resetting(&self) -> bool {
        self.resetting_until.is_some()
    }

    /// The ready output is active (low): a motor of the $33 active mask
    /// moves, or one of its search mask searches (§6.1.3).
    pub fn ready_output_active(&self) -> bool {
        self.motors.iter().enumerate().any(|(i, m)| {
            let bit = 1u8 << i;
            (self.unit.ready_active_mask & bit != 0 && m.velocity() != 0)
                || (self.unit.ready_search_mask & bit != 0 && m.is_searching())
        })
    }

    /// TTLOUT1's level: the ready output (high = ready) when $32 makes it
    /// one, else as set.
    pub fn ttlout1(&self) -> bool {
        if self.unit.ttlout1_ready {
            !self.ready_output_active()
        } else {
            self.unit.ttlout1
        }
    }

    /// The seven-segment display: the number of active motors, and its
    /// decimal point while any searches for its reference (§2.3; E28).
    pub fn display(&self) -> (usize, bool) {
        let active = self.motors.iter().filter(|m| !m.is_idle()).count();
        let searching = self.motors.iter().any(Motor::is_searching);
        (active, searching)
    }

    /// Power-on, or the end of $CC: the defaults of §6.2.1.8, the counters
    /// at 0, the address from the rotary switches (unless chosen kept after
    /// $CC), the baud rate from the jumpers, the reset flag set. Where the
    /// carriages are stays as it was.
    fn power_up(&mut self, after_reset_command: bool) {
        let [jp1, jp2] = self.config.jumpers;
        self.unit = UnitSettings::after_reset(
            baud_divisor(jumper_baud(jp1, jp2)),
            self.config.choices.packet_timeout,
        );
        self.spare_limits = [(0, 1023); 2];
        for motor in &mut self.motors {
            motor.reset();
        }
        if !(after_reset_command && self.config.choices.address_kept) {
            self.address = self.config.rotary_address;
        }
        self.reset_flag = true;
        self.receiver.clear();
        self.received.clear();
        self.outbox.clear();
        self.activity_requests.clear();
    }

    fn packet_timeout(&self) -> Option<Duration> {
        (self.unit.packet_timeout > 0).then(|| TICK * u32::from(self.unit.packet_timeout))
    }

    fn switch_over(&self) -> Duration {
        TICK * u32::from(self.unit.switch_over)
    }

    // ---- the line ------------------------------------------------------

    fn receive(&mut self, byte: u8) {
        if self.is_resetting() {
            return;
        }
        let timeout = self.packet_timeout();
        if let Some(frame) = self.receiver.byte(byte, self.now, timeout) {
            let latency = self.config.choices.latency;
            if latency.is_zero() {
                self.execute(frame);
            } else {
                self.received.push_back((self.now + latency, frame));
            }
        }
    }

    fn execute(&mut self, frame: [u8; REQUEST_LEN]) {
        if frame[0] != self.address || self.is_resetting() {
            return;
        }
        if let Ok(command) = Command::read(&frame) {
            self.apply(command);
        }
    }

    fn reply(&mut self, code: u8, respond_to: u8, fields: [u8; 7]) {
        let bytes = reply_bytes(self.config.choices.framing, respond_to, code, fields);
        let due = self.now + self.switch_over();
        self.outbox.push(due, bytes);
    }

    /// The earliest thing due after `now`.
    fn next_event(&self) -> Duration {
        [
            Some(self.next_tick),
            self.resetting_until,
            self.receiver.deadline(self.packet_timeout()),
            self.received.front().map(|(due, _)| *due),
            self.outbox.next_due(),
        ]
        .into_iter()
        .flatten()
        .min()
        .unwrap_or(self.next_tick)
    }

    /// Everything due at `now`, in order.
    fn run_due(&mut self) {
        if self.resetting_until.is_some_and(|until| until <= self.now) {
            self.resetting_until = None;
            self.power_up(true);
            if self.config.choices.stray_zero {
                self.output.push(0);
            }
        }
        let timeout = self.packet_timeout();
        self.receiver.expire(self.now, timeout);
        while let Some((due, frame)) = self.received.front().copied() {
            if due > self.now {
                break;
            }
            self.received.pop_front();
            self.execute(frame);
        }
        if self.next_tick <= self.now {
            self.tick();
            self.next_tick += TICK;
        }
        self.outbox.release(self.now, &mut self.output);
    }

    // ---- the tick ------------------------------------------------------

    fn tick(&mut self) {
        let Sixpack2 {
            config,
            unit,
            motors,
            drivers_enabled,
            ..
        } = self;
        let t = Ticking {
            clkdiv: unit.clkdiv,
            choices: &config.choices,
            drivers_enabled: *drivers_enabled,
        };
        for motor in motors.iter_mut() {
            if !matches!(motor.mode(), Mode::Follow(_)) {
                motor.tick(&t);
            }
        }
        for i in 0..MOTORS {
            let Mode::Follow(follow) = motors[i].mode() else {
                continue;
            };
            let (group, lead) = (follow.group, follow.lead);
            let Some(leader) = motors.get(lead) else {
                continue;
            };
            let leading = *leader.mode() == Mode::Ramp { group: Some(group) };
            let (odometer, v64) = (leader.odometer, leader.v64);
            motors[i].follow_lead(odometer, v64, leading, &t);
        }
        for motor in motors.iter_mut() {
            motor.sense();
            if motor.check_stops(&t).is_some() {
                motor.stop_condition(&t);
            }
        }
        self.answer_activity_requests();
    }

    fn all_idle(&self, mask: u8) -> bool {
        self.motors
            .iter()
            .enumerate()
            .all(|(i, m)| mask & (1 << i) == 0 || m.is_idle())
    }

    fn activities(&self) -> [u8; 7] {
        let mut fields = [self.config.choices.fill; 7];
        for (slot, motor) in fields.iter_mut().zip(&self.motors) {
            *slot = motor.action();
        }
        fields
    }

    /// $28s whose motors are now idle: answered, no sooner than the
    /// switch-over delay after they were asked.
    fn answer_activity_requests(&mut self) {
        let (ready, waiting): (Vec<_>, Vec<_>) = std::mem::take(&mut self.activity_requests)
            .into_iter()
            .partition(|r| self.all_idle(r.mask));
        self.activity_requests = waiting;
        for request in ready {
            let bytes = reply_bytes(
                self.config.choices.framing,
                request.respond_to,
                0x28,
                self.activities(),
            );
            let due = self.now.max(request.asked + self.switch_over());
            self.outbox.push(due, bytes);
        }
    }

    // ---- commands ------------------------------------------------------

    fn fit(&self, value: impl Into<i64>, range: RangeInclusive<i64>) -> Option<i64> {
        self.config.choices.out_of_range.fit(value.into(), range)
    }

    fn apply(&mut self, command: Command) {
        match command {
            Command::PeakCurrent { motor, value } => {
                // §7.1: the pairs 0+1, 2+3, 4+5 share it; only the values
                // for 0, 2 and 4 are valid (odd ones are ignored).
                if motor % 2 == 0 {
                    self.unit.peak_current[motor / 2] = value;
                }
            }
            Command::CurrentControl { motor, index, t0 } => {
                let fitted: Option<Vec<u8>> = index
                    .iter()
                    .map(|&i| self.fit(i, 0..=8).map(|i| i as u8))
                    .collect();
                let (Some(fitted), Some(t0)) = (fitted, self.fit(t0, 1..=65535)) else {
                    return;
                };
                let s = &mut self.motors[motor].settings;
                s.current_index.copy_from_slice(&fitted);
                s.t0 = t0 as u16;
            }
            Command::ClockDivider { clkdiv } => {
                if let Some(clkdiv) = self.fit(clkdiv, 0..=31) {
                    self.unit.clkdiv = clkdiv as u8;
                }
            }
            Command::VMinVStart {
                motor,
                vmin,
                vstart,
                div,
            } => self.set_vmin_vstart(motor, vmin, vstart, div),
            Command::AMaxVMax { motor, amax, vmax } => {
                // 0 < amax ≤ 64·vstart (§7.1 $14).
                let most = (64 * i64::from(self.motors[motor].settings.vstart)).min(32767);
                let (Some(amax), Some(vmax)) = (self.fit(amax, 1..=most), self.fit(vmax, 1..=511))
                else {
                    return;
                };
                let s = &mut self.motors[motor].settings;
                (s.amax, s.vmax) = (amax as u16, vmax as u16);
            }
            Command::MotorParameters {
                motor,
                poslimit,
                flags,
            } => {
                let Some(poslimit) = self.fit(poslimit, 0..=0x7FFF_FFFF) else {
                    return;
                };
                let m = &mut self.motors[motor];
                m.settings.poslimit = poslimit as u32;
                // AutonullCmd is a command, not a setting: it starts the
                // search "$22 starts" (§7.2).
                m.settings.flags = flags & !flag::AUTONULL_CMD;
                if flags & flag::AUTONULL_CMD != 0 {
                    m.start_search();
                }
            }
            Command::RefSearchParameters {
                motor,
                vrefmax,
                debounce_mask,
                stop_after,
            } => {
                let Some(vrefmax) = self.fit(vrefmax, 1..=511) else {
                    return;
                };
                let s = &mut self.motors[motor].settings;
                s.vrefmax = vrefmax as u16;
                s.debounce_mask = debounce_mask;
                s.stop_after_search = stop_after;
            }
            Command::MotorTable { start, entries } => {
                // The pointer is 0, 4, 8 or 12 (§7.1 $17).
                let start = match (start, self.config.choices.out_of_range) {
                    (0 | 4 | 8 | 12, _) => start,
                    (_, OutOfRange::Clamp) => start.min(12) / 4 * 4,
                    (_, OutOfRange::Ignore) => return,
                };
                let start = usize::from(start);
                self.unit.microstep_table[start..start + 4].copy_from_slice(&entries);
            }
            Command::NullPointOffset {
                motor,
                offset,
                range,
            } => {
                let s = &mut self.motors[motor].settings;
                (s.null_offset, s.test_null_range) = (offset, range);
            }
            Command::PiParameters {
                motor,
                propdiv,
                intdiv,
                intclip,
                intinpclip,
            } => {
                let (Some(propdiv), Some(intdiv), Some(intclip)) = (
                    self.fit(propdiv, 1..=255),
                    self.fit(intdiv, 1..=32767),
                    self.fit(intclip, 1..=32767),
                ) else {
                    return;
                };
                let s = &mut self.motors[motor].settings;
                s.propdiv = propdiv as u8;
                s.intdiv = intdiv as u16;
                s.intclip = intclip as u16;
                s.intinpclip = intinpclip;
            }
            Command::GetPosition { motor, respond_to } => {
                let m = &mut self.motors[motor];
                let [p0, p1, p2, p3] = m.position().to_le_bytes();
                let fields = [
                    motor as u8,
                    p0,
                    p1,
                    p2,
                    p3,
                    m.action(),
                    u8::from(m.take_stop_flag()),
                ];
                self.reply(0x20, respond_to, fields);
            }
            Command::GetVelocity { motor, respond_to } => {
                let m = &self.motors[motor];
                let [v0, v1] = (m.velocity() as i16).to_le_bytes();
                let fill = self.config.choices.fill;
                let fields = [motor as u8, v0, v1, m.action(), fill, fill, fill];
                self.reply(0x21, respond_to, fields);
            }
            Command::StartReferenceSearch { motor } => self.motors[motor].start_search(),
            Command::StartRamp { motor, target } => {
                let choices = &self.config.choices;
                self.motors[motor].start_ramp(target, choices);
            }
            Command::StartPi { motor, target } => self.motors[motor].start_pi(target),
            Command::Rotate { motor, velocity } => {
                if let Some(velocity) = self.fit(velocity, -511..=511) {
                    self.motors[motor].rotate(velocity as i32);
                }
            }
            Command::SetTarget { motor, target } => self.motors[motor].set_target(target),
            Command::SetPosition { motor, position } => self.motors[motor].set_position(position),
            Command::GetActivities {
                respond_to,
                wait_mask,
            } => self.ask_activities(respond_to, wait_mask),
            Command::StartRampParallel { mask } => {
                for (i, motor) in self.motors.iter_mut().enumerate() {
                    if mask & (1 << i) != 0 {
                        motor.start_stored_ramp();
                    }
                }
            }
            Command::StopMotors { mask } => {
                for (i, motor) in self.motors.iter_mut().enumerate() {
                    if mask & (1 << i) != 0 {
                        motor.stop_here();
                    }
                }
            }
            Command::AbortReferenceSearch { motor } => self.motors[motor].abort_search(),
            Command::GetInputs {
                channel,
                respond_to,
            } => {
                if let Some(fields) = self.inputs_of(channel) {
                    self.reply(0x30, respond_to, fields);
                }
            }
            Command::StopSwitchLimits {
                channel,
                min_left,
                max_right,
            } => match usize::from(channel) {
                motor @ 0..MOTORS => {
                    let s = &mut self.motors[motor].settings;
                    (s.min_left, s.max_right) = (min_left, max_right);
                }
                spare @ (6 | 7) => self.spare_limits[spare - 6] = (min_left, max_right),
                _ => {}
            },
            Command::Outputs {
                ttlout1,
                ttlio1_input,
                ttlio1_level,
                ttlout1_ready,
            } => {
                let u = &mut self.unit;
                u.ttlout1 = ttlout1;
                u.ttlio1_input = ttlio1_input;
                u.ttlio1_level = ttlio1_level;
                u.ttlout1_ready = ttlout1_ready;
            }
            Command::ReadyMask { active, search } => {
                self.unit.ready_active_mask = active;
                self.unit.ready_search_mask = search;
            }
            Command::BaudRate {
                divisor,
                switch_over,
            } => {
                let (Some(divisor), Some(switch_over)) = (
                    self.fit(divisor, 1..=65535),
                    self.fit(switch_over, 1..=1000),
                ) else {
                    return;
                };
                self.unit.baud_divisor = divisor as u16;
                self.unit.switch_over = switch_over as u16;
            }
            Command::PacketTimeout { timeout } => {
                if let Some(timeout) = self.fit(timeout, 2..=65535) {
                    self.unit.packet_timeout = timeout as u16;
                }
            }
            Command::UnitAddress { address } => self.address = address,
            Command::GetUnitInformation { respond_to } => {
                let c = &self.config.choices;
                let [s0, s1] = c.serial.to_le_bytes();
                let fields = [
                    c.firmware,
                    u8::from(self.reset_flag),
                    c.temperature,
                    s0,
                    s1,
                    c.fill,
                    c.fill,
                ];
                self.reset_flag = false;
                self.reply(0x43, respond_to, fields);
            }
            Command::Rs232ViaCan {
                respond_to,
                forward_to,
                bytes,
            } => {
                let Some(bytes) = self.fit(bytes, 0..=8) else {
                    return;
                };
                self.unit.can_forward_address = forward_to;
                self.unit.can_forward_bytes = bytes as u8;
                // Nothing waits to go out of RS-232; CTS (not wired here) reads 0.
                let fill = self.config.choices.fill;
                self.reply(0x44, respond_to, [0, 0, fill, fill, fill, fill, fill]);
            }
            Command::StartInterpolation { mask } => self.interpolate(mask),
            Command::HardwareReset { key } => {
                if self.config.choices.reset_key.is_none_or(|k| k == key) {
                    self.begin_reset();
                }
            }
        }
    }

    /// $13: div 0..3, vstart within the firmware's limit for it, vmin ≤
    /// vstart and vmin·f(1, div 3) ≤ 250 Hz (0: the fastest allowed).
    fn set_vmin_vstart(&mut self, motor: usize, vmin: u16, vstart: u16, div: u8) {
        let Some(div) = self.fit(div, 0..=3) else {
            return;
        };
        let div = div as u8;
        let Some(vstart) = self.fit(vstart, 1..=i64::from(vstart_limit(div))) else {
            return;
        };
        let vstart = vstart as u16;
        let most = i64::from(fastest_vmin(self.unit.clkdiv, vstart));
        let vmin = if vmin == 0 {
            Some(0)
        } else {
            self.fit(vmin, 1..=most)
        };
        let Some(vmin) = vmin else {
            return;
        };
        let s = &mut self.motors[motor].settings;
        (s.vmin, s.vstart, s.div) = (vmin as u16, vstart, div);
    }

    /// $30 for `channel`: none for a channel above 7 (dropped).
    fn inputs_of(&self, channel: u8) -> Option<[u8; 7]> {
        let c = &self.config.choices;
        let reference_bit = |m: &Motor| {
            let level = m.mechanics.switch_level();
            if c.ref_bits_are_levels { level } else { !level }
        };
        let (analog, reference) = match usize::from(channel) {
            motor @ 0..MOTORS => {
                let m = &self.motors[motor];
                (m.mechanics.analog(), u8::from(reference_bit(m)))
            }
            6 => (self.external_analog, 0),
            7 => (
                (u16::from(self.supply_volts) * COUNTS_PER_VOLT).min(1023),
                0,
            ),
            _ => return None,
        };
        let mut all = 0u8;
        for (i, m) in self.motors.iter().enumerate() {
            all |= u8::from(reference_bit(m)) << i;
        }
        for (bit, fitted) in [6, 7].into_iter().zip(self.config.jumpers) {
            all |= u8::from(fitted != c.jumper_bits_open) << bit;
        }
        let ttlio1 = if self.unit.ttlio1_input {
            self.ttlio1_input
        } else {
            self.unit.ttlio1_level
        };
        let [a0, a1] = analog.to_le_bytes();
        Some([channel, a0, a1, reference, all, u8::from(ttlio1), c.fill])
    }

    fn ask_activities(&mut self, respond_to: u8, mask: u8) {
        let request = ActivityRequest {
            respond_to,
            mask,
            asked: self.now,
        };
        if !self.activity_requests.is_empty() {
            match self.config.choices.second_28 {
                Second28::EachOwn => {}
                Second28::Replace => self.activity_requests.clear(),
                Second28::Ignore => return,
            }
        }
        if self.all_idle(mask) {
            let fields = self.activities();
            self.reply(0x28, respond_to, fields);
        } else {
            self.activity_requests.push(request);
        }
    }

    /// $50: the masked motors, all at rest, to their $26 targets together.
    /// The lead is the one with the longest time at its own vmax (§6.6.5;
    /// E29): it ramps with its own settings, the others keep their share
    /// of its progress, so that all arrive together on a straight line.
    /// Nothing starts if a masked motor is active.
    fn interpolate(&mut self, mask: u8) {
        let chosen: Vec<usize> = (0..MOTORS).filter(|i| mask & (1 << i) != 0).collect();
        if chosen.iter().any(|&i| !self.motors[i].is_idle()) {
            return;
        }
        let clkdiv = self.unit.clkdiv;
        let rate = |m: &Motor| {
            f64::from(m.settings.vmax.clamp(1, 511)) * steps_per_tick(clkdiv, m.settings.div)
        };
        let moves: Vec<(usize, i64, f64)> = chosen
            .iter()
            .map(|&i| {
                let m = &self.motors[i];
                let delta = m.remaining_to(m.target());
                (i, delta, delta.abs() as f64 / rate(m))
            })
            .collect();
        let Some(&(lead, lead_delta, _)) =
            moves
                .iter()
                .fold(None, |best: Option<&(usize, i64, f64)>, m| match best {
                    Some(b) if b.2 >= m.2 => Some(b),
                    _ => Some(m),
                })
        else {
            return;
        };
        if lead_delta == 0 {
            return;
        }
        self.interpolations = self.interpolations.wrapping_add(1);
        let group = self.interpolations;
        let lead_start = self.motors[lead].odometer;
        let lead_per_unit = steps_per_tick(clkdiv, self.motors[lead].settings.div);
        self.motors[lead].lead(group);
        for &(i, delta, _) in &moves {
            if i == lead || delta == 0 {
                continue;
            }
            let per_unit = steps_per_tick(clkdiv, self.motors[i].settings.div);
            let scale = delta as f64 / lead_delta as f64 * lead_per_unit / per_unit;
            self.motors[i].follow(Follow {
                group,
                lead,
                delta,
                lead_delta,
                lead_start,
                moved: 0,
                scale,
            });
        }
    }

    /// $CC: every motor stops where it is, the unit is deaf for
    /// [`RESET_TIME`], then comes up afresh.
    fn begin_reset(&mut self) {
        self.resetting_until = Some(self.now + RESET_TIME);
        self.receiver.clear();
        self.received.clear();
        self.outbox.clear();
        self.activity_requests.clear();
        for motor in &mut self.motors {
            motor.halt();
        }
    }

    // ---- inputs from outside --------------------------------------------

    /// Drive one input or change one choice by a setting typed from outside
    /// (`REF0=1`, `AIN2=700`, `ADDR9=1`; the names in [`inputs::INPUTS`]):
    /// what now holds, or what was wrong.
    pub fn drive_input(&mut self, text: &str) -> Result<String, SettingError> {
        let setting = inputs::parse(text)?;
        let name = setting.name();
        let level = setting.level;
        let on = level == Level::On;
        let number = match level {
            Level::Number(n) => Some(n),
            _ => None,
        };
        let n = number.unwrap_or(0);
        let motor = usize::from(setting.which).min(MOTORS - 1);
        let c = &mut self.config.choices;
        let said = match setting.row.input {
            Input::Reference => {
                let m = &mut self.motors[motor];
                m.mechanics.forced.reference = level.is_on();
                match level {
                    Level::Released => format!(
                        "{name} from the stage: {}",
                        actuated(m.mechanics.switch_actuated())
                    ),
                    _ => format!("{name} {}", actuated(on)),
                }
            }
            Input::LeftStop | Input::RightStop => {
                let m = &mut self.motors[motor];
                if setting.row.input == Input::LeftStop {
                    m.mechanics.forced.left_end = level.is_on();
                } else {
                    m.mechanics.forced.right_end = level.is_on();
                }
                format!("{name} {level}: A_In{motor} reads {}", m.mechanics.analog())
            }
            Input::Analog => {
                let m = &mut self.motors[motor];
                m.mechanics.forced.analog = number.map(|n| n.min(1023) as u16);
                format!("{name} {}", m.mechanics.analog())
            }
            Input::External => {
                self.external_analog = n.min(1023) as u16;
                format!("{name} {}", self.external_analog)
            }
            Input::Supply => {
                self.supply_volts = n.min(58) as u8;
                format!(
                    "{name} {} V: channel 7 reads {}",
                    self.supply_volts,
                    (u16::from(self.supply_volts) * COUNTS_PER_VOLT).min(1023)
                )
            }
            Input::Jumper => {
                let jumper = usize::from(setting.which).min(1);
                self.config.jumpers[jumper] = on;
                let [jp1, jp2] = self.config.jumpers;
                format!(
                    "{name} {}: {} Bd from the next reset",
                    if on { "fitted" } else { "open" },
                    jumper_baud(jp1, jp2)
                )
            }
            Input::Ttlio1 => {
                self.ttlio1_input = on;
                format!("{name} {level}")
            }
            Input::DriverEnable => {
                self.drivers_enabled = on;
                if on {
                    format!("{name} fitted: the drivers turn the motors")
                } else {
                    format!("{name} open: no motor turns, the counters run on")
                }
            }
            Input::Carriage => {
                let at = self.motors[motor].mechanics.place(i64::from(n));
                format!(
                    "{name}: the carriage of motor {motor} is at {at} µsteps from the left stop"
                )
            }
            Input::Travel | Input::Turn | Input::RefAt | Input::RefWidth | Input::Opener => {
                let m = &mut self.motors[motor];
                let stage = &mut m.mechanics.stage;
                match setting.row.input {
                    Input::Travel => stage.travel = n,
                    Input::Turn => stage.turn = n,
                    Input::RefAt => stage.ref_at = n,
                    Input::RefWidth => stage.ref_width = n,
                    _ => stage.opener = on,
                }
                self.config.stages[motor] = stage.clone();
                let carriage = m.mechanics.carriage();
                m.mechanics.place(carriage);
                format!("{name} {level}: {}", describe_stage(&m.mechanics.stage))
            }
            Input::Limits => {
                let swapped = crate::sim::inputs::limits_swapped(level);
                for (m, stage) in self.motors.iter_mut().zip(self.config.stages.iter_mut()) {
                    m.mechanics.stage.limits_swapped = swapped;
                    stage.limits_swapped = swapped;
                }
                if swapped {
                    "LIMITS swapped: on every motor the switch at the left stop pulls A_In up, \
                     the right one down"
                        .into()
                } else {
                    "LIMITS right: on every motor the switch at the left stop pulls A_In down, \
                     the right one up"
                        .into()
                }
            }
            Input::Addr9 => {
                c.framing = if on {
                    ReplyFraming::Addr9
                } else {
                    ReplyFraming::Cmd8
                };
                format!("{name} {level}: {}", c.describe_framing())
            }
            Input::Fill => {
                c.fill = n as u8;
                format!("{name}: unspecified reply bytes ${:02X}", c.fill)
            }
            Input::Second28 => {
                c.second_28 = match n {
                    0 => Second28::EachOwn,
                    1 => Second28::Replace,
                    _ => Second28::Ignore,
                };
                format!("{name} {n}")
            }
            Input::Timeout => {
                c.packet_timeout = n as u16;
                self.unit.packet_timeout = c.packet_timeout;
                match n {
                    0 => format!("{name} 0: no packet timeout, now and after a reset"),
                    n => format!(
                        "{name} {n}: a packet timeout of {} ms, now and after a reset",
                        2 * n
                    ),
                }
            }
            Input::Latency => {
                c.latency = Duration::from_millis(u64::from(n));
                format!("{name} {n} ms")
            }
            Input::Clamp => {
                c.out_of_range = if on {
                    OutOfRange::Clamp
                } else {
                    OutOfRange::Ignore
                };
                format!("{name} {level}")
            }
            Input::SlowerDeceleration => {
                c.slower_deceleration = n as u16;
                format!("{name} {n}: ramps decelerate at amax·{}/1000", 1000 - n)
            }
            Input::PiTimes64 => flag_choice(&mut c.pi_times_64, on, &name),
            Input::PiHolds => flag_choice(&mut c.pi_holds, on, &name),
            Input::RotationHolds => flag_choice(&mut c.rotation_holds, on, &name),
            Input::RampAfterRotation => flag_choice(&mut c.ramp_after_rotation, on, &name),
            Input::SlowSearch => {
                c.slow_search_velocity = n as u16;
                format!("{name} {n}")
            }
            Input::MechAtVrefmax => flag_choice(&mut c.mech_ref_at_vrefmax, on, &name),
            Input::OffsetMirrored => flag_choice(&mut c.offset_mirrored, on, &name),
            Input::RefLevels => flag_choice(&mut c.ref_bits_are_levels, on, &name),
            Input::JumperOpen => flag_choice(&mut c.jumper_bits_open, on, &name),
            Input::LimitsNeedStopNull => flag_choice(&mut c.limits_need_stop_null, on, &name),
            Input::KeepAddress => flag_choice(&mut c.address_kept, on, &name),
            Input::ResetKey => {
                c.reset_key = number.map(|n| n as u8);
                match c.reset_key {
                    Some(key) => format!("{name} {key}: $CC resets only with P0 = {key}"),
                    None => format!("{name} any: every $CC resets"),
                }
            }
            Input::StrayZero => flag_choice(&mut c.stray_zero, on, &name),
            Input::Firmware => {
                c.firmware = n as u8;
                format!("{name} {n}")
            }
            Input::Serial => {
                c.serial = n as u16;
                format!("{name} {n}")
            }
            Input::Temperature => {
                c.temperature = n as u8;
                format!("{name} {n} °C")
            }
        };
        Ok(said)
    }

    /// One line for the user: what is simulated and the choices made where
    /// the manual is silent.
    pub fn help_line(&self) -> String {
        let [jp1, jp2] = self.config.jumpers;
        format!(
            "SIXpack 2 simulator (firmware {}): address {} (rotary switches {}), {} Bd by its jumpers \
             (the served line runs at --baud whatever they say), six motors on a 2 ms tick; \
             each motor's machine: {}; choices where the manual is silent: {}; \
             a BREAK: a line BREAK on the standard input of `axterm sim`; \
             inputs driven from outside (--input, a line on the standard input of `axterm sim`, :sim-input): {}",
            self.config.choices.firmware,
            self.address,
            self.config.rotary_address,
            jumper_baud(jp1, jp2),
            describe_stage(&self.config.stages[0]),
            self.config.choices.describe(),
            super::inputs::summary(inputs::INPUTS),
        )
    }
}

fn actuated(on: bool) -> &'static str {
    if on { "actuated" } else { "not actuated" }
}

fn flag_choice(choice: &mut bool, on: bool, name: &str) -> String {
    *choice = on;
    format!("{name} {}", if on { "on" } else { "off" })
}

/// A stage in words, for help and answers to settings.
fn describe_stage(stage: &Stage) -> String {
    let stops = match (stage.turn, stage.travel) {
        (0, 0) => "no mechanical stops".to_string(),
        (0, travel) => format!("mechanical stops {travel} µsteps apart"),
        (turn, _) => format!("rotary, its switch coming round every {turn} µsteps"),
    };
    let switch = if stage.ref_width == 0 {
        "no reference switch".to_string()
    } else {
        format!(
            "reference switch ({}) actuated from {} for {} µsteps",
            if stage.opener { "opener" } else { "closer" },
            stage.ref_at,
            stage.ref_width
        )
    };
    let ends = if stage.turn == 0 && stage.travel > 0 && stage.end_zone > 0 {
        format!(
            "stop switches on A_In within {} µsteps of each stop (A_In 0 left, 1023 right, 512 between)",
            stage.end_zone
        )
    } else {
        "A_In 512".to_string()
    };
    format!(
        "{stops}, {switch}, {ends}, carriage at {} µsteps from the left stop at power-on",
        stage.start
    )
}

impl SimulatedController for Sixpack2 {
    fn feed(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.receive(byte);
        }
    }

    fn advance(&mut self, dt: Duration) {
        let end = self.now + dt;
        loop {
            let next = self.next_event();
            if next > end {
                break;
            }
            self.now = next.max(self.now);
            self.run_due();
        }
        self.now = end;
    }

    fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.output)
    }

    fn help(&self) -> String {
        self.help_line()
    }

    fn drive_input(&mut self, setting: &str) -> Result<String, String> {
        Sixpack2::drive_input(self, setting).map_err(|e| e.to_string())
    }

    fn line_break(&mut self) {
        self.receiver.line_break();
    }
}
