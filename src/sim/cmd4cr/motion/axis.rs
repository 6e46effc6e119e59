//! One axis of the core: its settings (§2.1.4, §2.1.6), the simulated
//! inputs wired to it, its counters (§2.6.1), latched error flags and the
//! status word `MST` (§2.6.2.1, T2-28).

use std::time::Duration;

use super::profile::{PhaseKind, Shape};
use super::stage::Stage;
use super::step_n_loop::{LoopState, StepNLoop};
use super::sync::{Latch, Sync};
use super::{Axis, Direction};

/// MST bits (T2-28).
pub mod mst {
    pub const ACCELERATING: u32 = 1 << 0;
    pub const DECELERATING: u32 = 1 << 1;
    pub const CONSTANT: u32 = 1 << 2;
    pub const ALARM_INPUT: u32 = 1 << 3;
    pub const PLUS_LIMIT_INPUT: u32 = 1 << 4;
    pub const MINUS_LIMIT_INPUT: u32 = 1 << 5;
    pub const HOME_INPUT: u32 = 1 << 6;
    pub const SLOWDOWN_INPUT: u32 = 1 << 7;
    pub const PLUS_LIMIT_ERROR: u32 = 1 << 8;
    pub const MINUS_LIMIT_ERROR: u32 = 1 << 9;
    pub const ALARM_ERROR: u32 = 1 << 10;
    pub const INP_INPUT: u32 = 1 << 11;
    pub const ERC_OUTPUT: u32 = 1 << 12;
    pub const INDEX_INPUT: u32 = 1 << 13;
    pub const EXTERNAL_START_INPUT: u32 = 1 << 14;
    pub const EMG_INPUT: u32 = 1 << 15;
    pub const EMG_ERROR: u32 = 1 << 16;
    pub const SLOWDOWN_STOP: u32 = 1 << 17;
    pub const WAITING_FOR_INP: u32 = 1 << 18;
    pub const WAITING_FOR_START: u32 = 1 << 19;

    /// Errors that must be cleared with CLR before the next operation
    /// (footnote 6).
    pub const BLOCKING_ERRORS: u32 = PLUS_LIMIT_ERROR | MINUS_LIMIT_ERROR | ALARM_ERROR | EMG_ERROR;
    /// Every flag CLR clears (§2.6.2.3, footnote 7).
    pub const CLEARED_BY_CLR: u32 = BLOCKING_ERRORS | SLOWDOWN_STOP;
}

/// Speed and signal settings of one axis, as the commands set them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AxisSettings {
    /// `HSPD[axis]`, pps; 0 = use the global value (§2.1.4).
    pub hspd: u32,
    /// `LSPD[axis]`, pps; 0 = global.
    pub lspd: u32,
    /// `ACC[axis]`, ms; 0 = global.
    pub acc: u32,
    /// `DEC[axis]`, ms; 0 = global.
    pub dec: u32,
    /// `SCV[axis]`.
    pub s_curve: bool,
    /// `SSPDM[axis]`, the speed window for `SSPD` (App. B).
    pub sspdm: u8,
    /// `POL[axis]`, kept raw (T2-17 is lost).
    pub polarity: u32,
    /// `SDE[axis]`: b0 enable, b1 latch.
    pub sde: u8,
    /// `SDC[axis]`: 0 decelerate only, 1 decelerate and stop.
    pub sdc: u8,
    /// `INP[axis]`: completion waits for the INP input.
    pub inp: bool,
    /// `ERC[axis]`: b0 on an error stop, b1 when homing completes.
    pub erc: u8,
    /// `ERCD[axis]` code (T2-14).
    pub ercd: u8,
    /// `ERCP[axis]` code (T2-15).
    pub ercp: u8,
    /// `ZCNT[axis]`: index pulses to wait for, minus one (0..15).
    pub zcnt: u8,
}

/// The factory `POL` word: the manual's one example reply, `@01POLX` →
/// `7` (§3.2.2), taken as every axis' power-on value.
pub const DEFAULT_POLARITY: u32 = 7;

impl Default for AxisSettings {
    fn default() -> Self {
        AxisSettings {
            hspd: 0,
            lspd: 0,
            acc: 0,
            dec: 0,
            s_curve: false,
            sspdm: 0,
            polarity: DEFAULT_POLARITY,
            sde: 0,
            sdc: 0,
            inp: false,
            erc: 0,
            ercd: 0,
            ercp: 0,
            zcnt: 0,
        }
    }
}

impl AxisSettings {
    pub fn shape(&self) -> Shape {
        if self.s_curve {
            Shape::SCurve
        } else {
            Shape::Linear
        }
    }
}

/// ERCD delay codes (T2-14).
pub const ERC_DELAYS: &[Duration] = &[
    Duration::ZERO,
    Duration::from_micros(12),
    Duration::from_micros(1600),
    Duration::from_millis(104),
];

/// ERCP width codes (T2-15).
pub const ERC_WIDTHS: &[Duration] = &[
    Duration::from_micros(12),
    Duration::from_micros(102),
    Duration::from_micros(409),
    Duration::from_micros(1600),
    Duration::from_millis(13),
    Duration::from_millis(52),
    Duration::from_millis(104),
];

/// Inputs of the axis that are not a switch of the [`Stage`], and switch
/// levels forced from outside (tests, demos). `None` leaves a switch to the
/// stage.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AxisInputs {
    /// ALM from the servo driver.
    pub alarm: bool,
    /// INP from the servo driver; on unless told otherwise, so that
    /// `INP[axis]=1` does not hold every move forever. The simulated drive's
    /// INP line counts as connected only while `INP[axis]=1`, so an axis at
    /// rest reads MST 0 as §4.3.3 expects.
    pub in_position: bool,
    pub plus_limit: Option<bool>,
    pub minus_limit: Option<bool>,
    pub home: Option<bool>,
    pub slowdown: Option<bool>,
    /// Per mille of the steps sent that the motor misses while it moves (a
    /// motor short of torque; 1000 = it does not turn at all). 0 normally.
    pub slip: u16,
}

impl Default for AxisInputs {
    fn default() -> Self {
        AxisInputs {
            alarm: false,
            in_position: true,
            plus_limit: None,
            minus_limit: None,
            home: None,
            slowdown: None,
            slip: 0,
        }
    }
}

/// Logical switch levels at one moment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Levels {
    pub plus_limit: bool,
    pub minus_limit: bool,
    pub home: bool,
    pub slowdown: bool,
    pub index: bool,
}

/// An ERC output pulse under way.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct ErcPulse {
    pub delay: Duration,
    pub width: Duration,
}

/// One axis.
#[derive(Debug, Clone)]
pub struct AxisState {
    pub name: Axis,
    pub settings: AxisSettings,
    pub stage: Stage,
    pub inputs: AxisInputs,
    /// Where the carriage is, in pulses (the stage's coordinates).
    pub(super) position: i64,
    /// `P` = position − counter_offset.
    pub(super) counter_offset: i64,
    /// `E` = encoder(position) − encoder_offset.
    pub(super) encoder_offset: i64,
    /// Latched MST error bits (8, 9, 10, 16, 17).
    pub(super) errors: u32,
    /// Current pulse rate, pps.
    pub(super) rate: f64,
    pub(super) phase: Option<PhaseKind>,
    pub(super) waiting_for_inp: bool,
    pub(super) waiting_for_start: bool,
    pub(super) erc: Option<ErcPulse>,
    /// Switch levels at the end of the last tick.
    pub(super) levels: Levels,
    pub latch: Latch,
    pub sync: Sync,
    /// The axis follows its MPG input or the joystick: motion commands are
    /// refused (§2.2.2 "operating conditions").
    pub manual_control: bool,
    /// An emergency stop caught the axis under joystick control: it stays
    /// still until the stick is back in its dead band.
    pub(super) joystick_held: bool,
    /// `SL`, `SLR`, `SLT`, `SLE`, `SLA`.
    pub step_n_loop: StepNLoop,
    pub(super) loop_state: LoopState,
    /// Thousandths of a missed step not yet whole (see [`AxisInputs::slip`]).
    pub(super) slip_carry: u64,
}

/// The 28-bit position range (§1.2): counters wrap within it.
pub fn wrap28(value: i64) -> i64 {
    const SPAN: i64 = 1 << 28;
    (value + (1 << 27)).rem_euclid(SPAN) - (1 << 27)
}

impl AxisState {
    pub fn new(name: Axis, stage: Stage) -> AxisState {
        let mut axis = AxisState {
            name,
            settings: AxisSettings::default(),
            stage,
            inputs: AxisInputs::default(),
            position: 0,
            counter_offset: 0,
            encoder_offset: 0,
            errors: 0,
            rate: 0.0,
            phase: None,
            waiting_for_inp: false,
            waiting_for_start: false,
            erc: None,
            levels: Levels::default(),
            latch: Latch::default(),
            sync: Sync::default(),
            manual_control: false,
            joystick_held: false,
            step_n_loop: StepNLoop::default(),
            loop_state: LoopState::default(),
            slip_carry: 0,
        };
        axis.levels = axis.levels_at(0);
        axis
    }

    /// Where the carriage is (machine position, pulses).
    pub fn machine_position(&self) -> i64 {
        self.position
    }

    /// Power-on: settings, counters, flags and latches afresh; the
    /// carriage, its stage and what is wired stay as they are.
    pub(super) fn power_up(&mut self) {
        *self = AxisState {
            stage: self.stage.clone(),
            inputs: self.inputs.clone(),
            position: self.position,
            counter_offset: self.position,
            encoder_offset: self.stage.encoder_at(self.position),
            ..AxisState::new(self.name, Stage::bare())
        };
        self.levels = self.levels_at(self.position);
    }

    /// `P[axis]`: the command pulse counter.
    pub fn counter(&self) -> i64 {
        wrap28(self.position - self.counter_offset)
    }

    /// `E[axis]`: the encoder counter.
    pub fn encoder(&self) -> i64 {
        wrap28(self.stage.encoder_at(self.position) - self.encoder_offset)
    }

    /// With StepNLoop on, the real-time target in encoder counts: where the
    /// pulses sent so far should have put the encoder (§2.6.1.1).
    pub fn loop_target(&self) -> i64 {
        match self.loop_state.start {
            Some((pulses, encoder)) => {
                let moved = (self.counter() - pulses) as f64;
                encoder + (moved / self.step_n_loop.pulses_per_count()).round() as i64
            }
            None => self.loop_state.target,
        }
    }

    /// `D[axis]`: target − encoder with StepNLoop on, else 0 (§2.6.1.3).
    pub fn deviation(&self) -> i64 {
        if self.step_n_loop.enabled {
            self.loop_target() - self.encoder()
        } else {
            0
        }
    }

    pub(super) fn set_counter(&mut self, value: i64) {
        self.counter_offset = self.position - wrap28(value);
    }

    pub(super) fn set_encoder(&mut self, value: i64) {
        self.encoder_offset = self.stage.encoder_at(self.position) - wrap28(value);
    }

    /// The motor misses `pulses` steps (signed, in the carriage's
    /// coordinates: +30 leaves it 30 pulses short of a + move): the pulse
    /// counter keeps what was sent, the carriage and so the encoder fall
    /// behind. Clamped to the 28-bit range.
    pub(super) fn miss(&mut self, pulses: i64) {
        let pulses = pulses.clamp(-(1 << 27), 1 << 27);
        self.position -= pulses;
        self.counter_offset -= pulses;
        self.levels = self.levels_at(self.position);
    }

    /// One tick sends the pulses that would take the carriage from `old` to
    /// `new`; under slip the motor misses its share of them (fractions
    /// carried to the next tick). The counter keeps every pulse; the
    /// missed ones (signed as the motion) are returned, for the carriage to
    /// stop that much short.
    pub(super) fn slip_tick(&mut self, old: i64, new: i64) -> i64 {
        let moved = new - old;
        if self.inputs.slip == 0 || moved == 0 {
            return 0;
        }
        let slip = u64::from(self.inputs.slip.min(1000));
        let owed = self.slip_carry + moved.unsigned_abs().saturating_mul(slip);
        self.slip_carry = owed % 1000;
        let missed = i64::try_from(owed / 1000).unwrap_or(i64::MAX) * moved.signum();
        self.counter_offset -= missed;
        missed
    }

    /// Make the current trigger position `at` the zero of both counters.
    pub(super) fn zero_at(&mut self, at: i64) {
        self.counter_offset = at;
        self.encoder_offset = self.stage.encoder_at(at);
        if self.loop_state.start.is_some() {
            // The loop follows from the new zero.
            self.loop_state.start = Some((self.counter(), self.encoder()));
        }
    }

    /// The machine position where `P` reads `counter`.
    pub(super) fn machine_for_counter(&self, counter: i64) -> i64 {
        counter + self.counter_offset
    }

    /// Switch levels with the carriage at `position`, forced inputs first.
    pub(super) fn levels_at(&self, position: i64) -> Levels {
        Levels {
            plus_limit: self
                .inputs
                .plus_limit
                .unwrap_or_else(|| self.stage.plus_limit_at(position)),
            minus_limit: self
                .inputs
                .minus_limit
                .unwrap_or_else(|| self.stage.minus_limit_at(position)),
            home: self
                .inputs
                .home
                .unwrap_or_else(|| self.stage.home_at(position)),
            slowdown: self
                .inputs
                .slowdown
                .unwrap_or_else(|| self.stage.slowdown_at(position)),
            index: self.stage.index_at(position),
        }
    }

    /// The end limit in `direction` is on now.
    pub fn limit_on(&self, direction: Direction) -> bool {
        let levels = self.levels_at(self.position);
        match direction {
            Direction::Plus => levels.plus_limit,
            Direction::Minus => levels.minus_limit,
        }
    }

    /// The slow-down input acts (SDE bit 0) and is on.
    pub(super) fn slowdown_enabled(&self) -> bool {
        self.settings.sde & 1 != 0
    }

    pub(super) fn slowdown_latched(&self) -> bool {
        self.settings.sde & 2 != 0
    }

    pub fn errors(&self) -> u32 {
        self.errors
    }

    /// Current pulse rate (`PS[axis]`), pps.
    pub fn pulse_rate(&self) -> f64 {
        self.rate
    }

    /// Start an ERC pulse with this axis' delay and width.
    pub(super) fn pulse_erc(&mut self) {
        let delay = ERC_DELAYS
            .get(usize::from(self.settings.ercd))
            .copied()
            .unwrap_or_default();
        let width = ERC_WIDTHS
            .get(usize::from(self.settings.ercp))
            .copied()
            .unwrap_or(ERC_WIDTHS[0]);
        self.erc = Some(ErcPulse { delay, width });
    }

    pub(super) fn erc_on(&self) -> bool {
        self.erc.is_some_and(|p| p.delay.is_zero())
    }

    /// Let `dt` pass on the ERC pulse.
    pub(super) fn run_erc(&mut self, dt: Duration) {
        if let Some(pulse) = &mut self.erc {
            if !pulse.delay.is_zero() {
                pulse.delay = pulse.delay.saturating_sub(dt);
            } else {
                pulse.width = pulse.width.saturating_sub(dt);
                if pulse.width.is_zero() {
                    self.erc = None;
                }
            }
        }
    }

    /// `MST[axis]` (T2-28), given the core-wide EMG and /CSTA levels.
    pub fn status(&self, emg_input: bool, start_input: bool) -> u32 {
        let levels = self.levels_at(self.position);
        let mut bits = self.errors;
        bits |= match self.phase {
            Some(PhaseKind::Accelerating) => mst::ACCELERATING,
            Some(PhaseKind::Decelerating) => mst::DECELERATING,
            Some(PhaseKind::Constant) => mst::CONSTANT,
            None => 0,
        };
        let flag = |on: bool, bit: u32| if on { bit } else { 0 };
        bits |= flag(self.inputs.alarm, mst::ALARM_INPUT);
        bits |= flag(levels.plus_limit, mst::PLUS_LIMIT_INPUT);
        bits |= flag(levels.minus_limit, mst::MINUS_LIMIT_INPUT);
        bits |= flag(levels.home, mst::HOME_INPUT);
        bits |= flag(levels.slowdown, mst::SLOWDOWN_INPUT);
        bits |= flag(self.settings.inp && self.inputs.in_position, mst::INP_INPUT);
        bits |= flag(self.erc_on(), mst::ERC_OUTPUT);
        bits |= flag(levels.index, mst::INDEX_INPUT);
        bits |= flag(start_input, mst::EXTERNAL_START_INPUT);
        bits |= flag(emg_input, mst::EMG_INPUT);
        bits |= flag(self.waiting_for_inp, mst::WAITING_FOR_INP);
        bits |= flag(self.waiting_for_start, mst::WAITING_FOR_START);
        bits
    }
}
