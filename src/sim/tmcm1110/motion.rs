//! The StepRocker's single axis: ramp generator (TMC429, manual §6.1),
//! limit and home switches, reference search (§7.1), encoder (§6.3) and
//! StallGuard2 load reading, stop on stall (§7.2) and CoolStep current
//! regulation (§7.3) ([`stallguard`]), on virtual time.
//!
//! Motion is planned as exact piecewise kinematics ([`profile`]): a command
//! produces a list of ramp segments, and [`Axis::advance`] walks along them,
//! stopping exactly at segment ends and at the positions where a switch input
//! changes. Time is counted in whole nanoseconds, every event is rounded up to
//! the next nanosecond (never early), and positions are evaluated from the
//! segment's start, so any split of virtual time into `advance` calls gives
//! the same motion. The StallGuard and encoder-deviation supervision samples
//! every [`TICK`] of virtual time.
//!
//! Two coordinates: the *machine* position (where the carriage is; the
//! [`SwitchLayout`] lives there) and the position *counter* AP1, which is the
//! machine position plus an offset that SAP 1 and the reference search
//! rewrite, wrapped to 32 bits.

mod defaults;
mod profile;
mod reference;
pub mod stallguard;
mod switches;
#[cfg(test)]
mod tests;

use std::collections::{BTreeMap, VecDeque};
use std::time::Duration;

use crate::protocol::tmcl::units::{
    acceleration_to_pps2, pps_to_velocity, pps2_to_acceleration, velocity_to_pps,
};
use profile::{Builder, Segment, seconds_to_ns_ceil};
use reference::{Search, Step};
use stallguard::CoolStep;

pub use defaults::{MOTION_DEFAULTS, MOTION_PARAMS, MotionDefault};
pub use reference::{
    INVERT_HOME_FLAG, MIRROR_FLAG, REFERENCE_MODES, ReferenceAbort, ReferenceMode,
    ReferenceModeInfo, ReferenceOutcome,
};
pub use switches::{AxisEvent, DEFAULT_END_SWITCH_WIDTH, Switch, SwitchLayout};

/// Sampling period of the StallGuard and encoder-deviation supervision, and
/// the tolerance the simulator promises on anything it samples. Ramps and
/// switch edges are exact to the nanosecond.
pub const TICK: Duration = Duration::from_millis(1);
const TICK_NS: u64 = 1_000_000;

/// A reference search run that travels this far (machine microsteps, about
/// 328 turns at 256 µsteps) without meeting its switch gives up.
pub const REFERENCE_SEARCH_MAX_TRAVEL: i64 = 1 << 24;

/// AP206 before the motor has turned: the unloaded reading at the default
/// positioning speed AP4 = 1000 ([`stallguard::reading`]).
pub const DEFAULT_LOAD: i32 = 500;

/// §6.3: bits 2, 3 and 4 of AP210 select encoder functions (null channel
/// zeroing, Z polarity), not the prescaler.
const ENCODER_FUNCTION_BITS: i32 = 0b1_1100;
/// §6.3: the resulting prescaler is p/512.
const ENCODER_PRESCALER_ONE: i128 = 512;

/// AP207 bits (§4 Table 16).
const STALL_ERROR: i32 = 1;
const DEVIATION_ERROR: i32 = 2;

/// Ramp modes of AP138.
const MODE_POSITION: i32 = 0;
const MODE_SOFT: i32 = 1;
const MODE_VELOCITY: i32 = 2;

/// Directions the end switches forbid.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Blocks {
    positive: bool,
    negative: bool,
    /// The carriage stands against an end stop on that side.
    positive_end: bool,
    negative_end: bool,
}

impl Blocks {
    fn contains(self, direction: i8) -> bool {
        self.switch(direction) || self.end_stop(direction)
    }

    fn switch(self, direction: i8) -> bool {
        (direction > 0 && self.positive) || (direction < 0 && self.negative)
    }

    fn end_stop(self, direction: i8) -> bool {
        (direction > 0 && self.positive_end) || (direction < 0 && self.negative_end)
    }
}

/// What the ramp generator is heading for.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Goal {
    Velocity(f64),
    Position { target: i64, vmax: f64, soft: bool },
}

/// Why a slice of virtual time ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Cause {
    Budget,
    SegmentEnd,
    Crossing(i64),
    Tick,
}

/// The simulated encoder on the motor shaft: one count per microstep of the
/// machine position, scaled by AP210 into AP209.
#[derive(Debug, Clone, Default)]
struct Encoder {
    /// AP209 when last written or rescaled.
    base: i64,
    /// Shaft counts at that moment.
    shaft_at_base: i64,
    /// Microsteps the shaft lags behind the motor (injected by tests).
    slip: i64,
}

#[derive(Debug, Clone)]
pub struct Axis {
    stored: BTreeMap<u8, i32>,
    layout: SwitchLayout,
    end_switches_reversed: bool,
    home_input_inverted: bool,

    /// Machine position where the current segment started (whole + fraction).
    anchor: i64,
    anchor_frac: f64,
    /// The plan; the front is the current segment, the back is open-ended.
    plan: VecDeque<Segment>,
    /// Time spent in the current segment.
    segment_ns: u64,
    /// Machine microstep counter: moves by whole steps once the continuous
    /// position is a full step away, so it equals an integer target exactly
    /// when the motor arrives there from either side.
    steps: i64,
    /// AP1 = steps + counter_offset (wrapped to 32 bits).
    counter_offset: i64,
    clock_ns: u64,
    /// The end-switch blocks the plan was made with.
    plan_blocks: Blocks,

    /// `LOAD=`: percent of the torque at the AP6 current, 0..100.
    load_percent: u8,
    /// AP206 at standstill: the last measurement while the motor turned.
    held_reading: i32,
    /// The speed [int] `held_reading` was taken at (0 at standstill).
    held_speed: i32,
    /// CoolStep's current scale (AP180 while CoolStep regulates).
    coolstep_scale: i32,
    /// Consecutive readings at or above CoolStep's upper threshold.
    coolstep_above: u32,
    encoder: Encoder,

    pending: Vec<AxisEvent>,
    last_switches: [bool; 3],
    /// Direction in which a limit switch has stopped the motor (LimitStop is
    /// reported once per stop).
    limit_stopped: Option<i8>,
    /// An MVP (or SAP 0) whose arrival hasn't been reported yet.
    reached_pending: bool,
    search: Option<Search>,
    /// The search run (index, reversed) the present plan belongs to.
    search_planned: Option<(usize, bool)>,
    outcome: Option<ReferenceOutcome>,
}

impl Default for Axis {
    fn default() -> Self {
        Self::new()
    }
}

impl Axis {
    pub fn new() -> Self {
        let stored = MOTION_DEFAULTS
            .iter()
            .map(|d| (d.number, d.value))
            .collect();
        let mut axis = Axis {
            stored,
            layout: SwitchLayout::DEMO_STAGE,
            end_switches_reversed: false,
            home_input_inverted: false,
            anchor: 0,
            anchor_frac: 0.0,
            plan: VecDeque::from([Segment::HOLD]),
            segment_ns: 0,
            steps: 0,
            counter_offset: 0,
            clock_ns: 0,
            plan_blocks: Blocks::default(),
            load_percent: 0,
            held_reading: DEFAULT_LOAD,
            held_speed: 0,
            coolstep_scale: stallguard::current_scale(128),
            coolstep_above: 0,
            encoder: Encoder::default(),
            pending: Vec::new(),
            last_switches: [false; 3],
            limit_stopped: None,
            reached_pending: false,
            search: None,
            search_planned: None,
            outcome: None,
        };
        axis.last_switches = axis.switch_states();
        axis.plan_blocks = axis.blocks();
        axis
    }

    pub fn owns_param(number: u8) -> bool {
        MOTION_PARAMS.contains(&number)
    }

    pub fn param(&self, number: u8) -> i32 {
        match number {
            1 => self.actual_position(),
            3 => pps_to_velocity(self.velocity_pps(), self.pulse_div()),
            // §4 Table 16: "always set when target position and actual
            // position are equal", in any mode, like the TMC429's flag.
            8 => i32::from(self.actual_position() == self.stored(0)),
            9 => i32::from(self.switch(Switch::Home)),
            10 => i32::from(self.switch(Switch::Right)),
            11 => i32::from(self.switch(Switch::Left)),
            135 => {
                let accel = self.segment().acceleration(self.segment_seconds());
                pps2_to_acceleration(accel, self.ramp_div(), self.pulse_div())
            }
            138 if self.search.is_some() => {
                if self.search.as_ref().and_then(Search::step) == Some(Step::GoToReference) {
                    MODE_POSITION
                } else {
                    MODE_VELOCITY
                }
            }
            180 => self.current_scale(),
            206 => self.load_reading(),
            // §4 AP208 bit 0: "StallGuard2 status (1: threshold reached)";
            // measured only while the motor turns. The other bits (driver
            // temperature, shorts, open load, standstill) are not simulated.
            208 => i32::from(self.is_moving() && self.load_reading() == 0),
            209 => self.encoder_count() as i32,
            _ => self.stored(number),
        }
    }

    /// Writes a parameter the module has already validated. Writes to the
    /// read-only values (AP3, 8..11, 135, 180, 196, 197, 206..208) are
    /// ignored.
    pub fn set_param(&mut self, number: u8, value: i32) {
        match number {
            // SAP 0 moves like MVP ABS (position mode, §4 "target position")
            // but is no motion command, so AP207 stays.
            0 => {
                self.interrupt_search();
                self.stored.insert(0, value);
                self.stored.insert(138, MODE_POSITION);
                self.reached_pending = true;
                self.replan();
            }
            1 => self.set_actual_position(value),
            2 => {
                self.stored.insert(2, value);
                if self.search.is_none() && self.mode() == MODE_VELOCITY {
                    self.replan();
                }
            }
            4 | 5 | 130 | 153 | 154 => {
                self.stored.insert(number, value);
                self.replan();
            }
            138 => {
                if !(MODE_POSITION..=MODE_VELOCITY).contains(&value) {
                    return;
                }
                self.interrupt_search();
                self.stored.insert(138, value);
                if value != MODE_VELOCITY {
                    self.reached_pending = true;
                }
                self.replan();
            }
            // Switch settings take effect at the next advance, where edges
            // and limit stops are reported.
            6 | 12 | 13 | 140 | 149 | 168..=174 | 181 | 182 | 183 | 193 | 212 => {
                self.stored.insert(number, value);
            }
            194 | 195 => {
                self.stored.insert(number, value);
                if self.search.is_some() {
                    if value == 0 {
                        self.abort_search(ReferenceAbort::ZeroSpeed);
                        self.halt();
                    } else {
                        self.replan();
                    }
                }
            }
            209 => {
                self.encoder.base = i64::from(value);
                self.encoder.shaft_at_base = self.shaft();
            }
            210 => {
                self.encoder.base = self.encoder_count();
                self.encoder.shaft_at_base = self.shaft();
                self.stored.insert(210, value);
            }
            _ => {}
        }
    }

    /// ROR (positive) / ROL (negative): velocity mode at `velocity` [int].
    /// Not limited by AP4, which is the maximum *positioning* speed.
    pub fn rotate(&mut self, velocity: i32) {
        self.interrupt_search();
        self.clear_error_flags();
        self.stored.insert(2, velocity);
        self.stored.insert(138, MODE_VELOCITY);
        self.reached_pending = false;
        self.replan();
    }

    /// MST: decelerate to standstill.
    pub fn stop(&mut self) {
        self.rotate(0);
    }

    /// MVP: position mode towards `target`. If the target is more than
    /// 2^31 − 1 away, the motor goes the short way round through the 32-bit
    /// wrap of the counter (§3.6.4 note).
    pub fn move_to(&mut self, target: i32) {
        self.interrupt_search();
        self.clear_error_flags();
        self.stored.insert(0, target);
        self.stored.insert(138, MODE_POSITION);
        self.reached_pending = true;
        self.replan();
    }

    /// RFS START with the mode in AP193 (§7.1). An undefined mode or a zero
    /// speed ends the search at once ([`Axis::reference_search_outcome`]).
    pub fn start_reference_search(&mut self) {
        self.clear_error_flags();
        self.search = None;
        self.search_planned = None;
        self.outcome = None;
        let mode_value = self.stored(193);
        let Some(mode) = ReferenceMode::decode(mode_value) else {
            self.end_search(ReferenceOutcome::Aborted(ReferenceAbort::InvalidMode(
                mode_value,
            )));
            return;
        };
        if self.stored(194) == 0 || self.stored(195) == 0 {
            self.end_search(ReferenceOutcome::Aborted(ReferenceAbort::ZeroSpeed));
            return;
        }
        self.reached_pending = false;
        self.limit_stopped = None;
        self.search = Some(Search::new(mode, self.steps));
        self.drive_search();
    }

    /// RFS STOP: the search ends, the motor decelerates with AP5 and the
    /// counter is left as it is.
    pub fn stop_reference_search(&mut self) {
        if self.search.is_some() {
            self.abort_search(ReferenceAbort::Stopped);
            self.stored.insert(2, 0);
            self.stored.insert(138, MODE_VELOCITY);
            self.replan();
        }
    }

    pub fn reference_search_active(&self) -> bool {
        self.search.is_some()
    }

    /// How the last reference search ended (`None` while one runs or before
    /// the first).
    pub fn reference_search_outcome(&self) -> Option<ReferenceOutcome> {
        self.outcome
    }

    /// Logical state of a switch input (AP9..AP11): the end switches after
    /// GP79 polarity, the home switch as wired.
    pub fn switch(&self, which: Switch) -> bool {
        let physical = self.physical(which);
        match which {
            Switch::Left | Switch::Right => physical != self.end_switches_reversed,
            Switch::Home => physical != self.home_input_inverted,
        }
    }

    /// GP79: end switch polarity reversed.
    pub fn set_end_switch_polarity_reversed(&mut self, reversed: bool) {
        self.end_switches_reversed = reversed;
    }

    /// The simulated machine's home switch is wired inverted (normally
    /// closed): its input is active outside the home window. Reference modes
    /// 5..8 + 128 are made for such a machine.
    pub fn set_home_input_inverted(&mut self, inverted: bool) {
        self.home_input_inverted = inverted;
    }

    /// The simulated machine's end switches are wired the wrong way round
    /// (true): the carriage at the + end closes the left limit input (AP11) and
    /// at the − end the right one; the module stops on each input as
    /// always (§4 AP12/AP13: the right switch stops positive motion).
    pub fn set_limits_swapped(&mut self, swapped: bool) {
        self.layout.limits_swapped = swapped;
        self.settle();
    }

    /// The simulated machine's switch positions.
    pub fn layout(&self) -> &SwitchLayout {
        &self.layout
    }

    /// The simulated machine's switch positions, to move them.
    pub fn layout_mut(&mut self) -> &mut SwitchLayout {
        &mut self.layout
    }

    /// True while the motor turns or a ramp is in progress.
    pub fn is_moving(&self) -> bool {
        !self.segment().is_hold()
    }

    /// AP207 is cleared when read and by every motion command (§4 Table 16);
    /// the module calls this after answering a GAP 207.
    pub fn clear_error_flags(&mut self) {
        self.stored.insert(207, 0);
    }

    /// The load on the simulated motor (`LOAD=`), in percent of the torque
    /// the motor has at the AP6 run current; 100 and more stall it at that
    /// current (clamped to 100).
    pub fn set_load_percent(&mut self, percent: u8) {
        self.load_percent = percent.min(100);
    }

    /// The load set by [`Axis::set_load_percent`].
    pub fn load_percent(&self) -> u8 {
        self.load_percent
    }

    /// AP180: the current scale (0..31, (n + 1)/32 of the module maximum) the
    /// driver runs the motor with now. While the motor turns: AP183's scale
    /// at or below the AP182 speed (when AP182 > 0), else CoolStep's when
    /// AP172 turns it on, else AP6's. At standstill AP6's (the standby
    /// current AP7 is not simulated).
    pub fn current_scale(&self) -> i32 {
        let run = stallguard::current_scale(self.stored(6));
        if !self.is_moving() {
            return run;
        }
        if self.below_coolstep_speed() {
            return stallguard::current_scale(self.stored(183));
        }
        let coolstep = self.coolstep();
        if coolstep.enabled() {
            self.coolstep_scale
                .clamp(coolstep.min_scale, coolstep.max_scale)
        } else {
            run
        }
    }

    /// AP206: the StallGuard2 reading ([`stallguard::reading`]) now, or,
    /// at standstill, the last one taken at the last run's top speed (after
    /// a stall stop 0; before the first motion [`DEFAULT_LOAD`]).
    pub fn load_reading(&self) -> i32 {
        if !self.is_moving() {
            return self.held_reading;
        }
        let fraction = stallguard::torque_fraction(
            self.load_percent,
            stallguard::current_scale(self.stored(6)),
            self.current_scale(),
        );
        stallguard::reading(self.param(3), fraction, self.stored(174))
    }

    /// §4 AP182: "Above this speed CoolStep becomes enabled"; below it the
    /// slow run current AP183 applies. AP182 = 0: no slow range.
    fn below_coolstep_speed(&self) -> bool {
        let threshold = self.stored(182);
        threshold > 0 && self.param(3).abs() <= threshold
    }

    fn coolstep(&self) -> CoolStep {
        CoolStep::from_params(
            self.stored(6),
            self.stored(168),
            self.stored(169),
            self.stored(170),
            self.stored(171),
            self.stored(172),
        )
    }

    /// One StallGuard2 measurement (every [`TICK`] while the motor turns
    /// and something uses it), fed to CoolStep when it regulates.
    fn measure(&mut self) -> i32 {
        let reading = self.load_reading();
        let coolstep = self.coolstep();
        if coolstep.enabled() && !self.below_coolstep_speed() {
            (self.coolstep_scale, self.coolstep_above) =
                coolstep.regulate(self.coolstep_scale, self.coolstep_above, reading);
        } else {
            // Off or in the slow range: CoolStep starts again from AP6's
            // current when it takes over.
            self.coolstep_scale = coolstep.max_scale;
            self.coolstep_above = 0;
        }
        reading
    }

    /// The shaft (and with it the encoder) falls `microsteps` behind the
    /// motor, as when steps are lost; negative values make it run ahead.
    pub fn inject_slip(&mut self, microsteps: i64) {
        self.encoder.slip = self.encoder.slip.saturating_add(microsteps);
    }

    /// Where the carriage is in machine microsteps (the frame of the
    /// [`SwitchLayout`]), independent of the counter offset.
    pub fn machine_position(&self) -> i64 {
        self.steps
    }

    /// Actual speed in microsteps per second (AP3 before rounding to [int]).
    pub fn velocity_pps(&self) -> f64 {
        self.segment().velocity(self.segment_seconds())
    }

    /// Virtual time this axis has lived through.
    pub fn elapsed(&self) -> Duration {
        Duration::from_nanos(self.clock_ns)
    }

    pub fn advance(&mut self, dt: Duration, events: &mut Vec<AxisEvent>) {
        let mut remaining = u64::try_from(dt.as_nanos()).unwrap_or(u64::MAX);
        let mut idle_slices = 0u32;
        self.settle();
        loop {
            let (mut slice, mut cause) = self.next_slice(remaining);
            // Every zero-length slice consumes a discrete event, so this
            // only guards against a numerical surprise looping for ever.
            if slice == 0 && cause != Cause::Budget {
                idle_slices += 1;
                if idle_slices > 1000 {
                    slice = remaining.min(1);
                    cause = Cause::Budget;
                }
            } else {
                idle_slices = 0;
            }
            self.pass_time(slice);
            remaining -= slice;
            if self.is_moving() {
                // AP206 at standstill is the last reading taken at the
                // run's top speed so far (a stall's 0 included), not one
                // of the ramp down, which falls to 0 with the speed.
                let speed = self.param(3).abs();
                if speed >= self.held_speed {
                    self.held_speed = speed;
                    self.held_reading = self.load_reading();
                }
            } else {
                self.held_speed = 0;
                // At standstill the driver runs on AP6; CoolStep starts
                // from there when the motor turns again.
                self.coolstep_scale = self.coolstep().max_scale;
                self.coolstep_above = 0;
            }
            match cause {
                Cause::Budget => {
                    if remaining == 0 {
                        self.settle();
                        break;
                    }
                }
                Cause::SegmentEnd => self.finish_segment(),
                Cause::Crossing(position) => self.reach(position),
                Cause::Tick => self.supervise(),
            }
            self.settle();
        }
        events.append(&mut self.pending);
    }

    // ----- parameters -----

    fn stored(&self, number: u8) -> i32 {
        self.stored.get(&number).copied().unwrap_or(0)
    }

    fn mode(&self) -> i32 {
        self.stored(138)
    }

    fn pulse_div(&self) -> u8 {
        self.stored(154).clamp(0, 13) as u8
    }

    fn ramp_div(&self) -> u8 {
        self.stored(153).clamp(0, 13) as u8
    }

    /// An internal velocity value in pps.
    fn speed_pps(&self, velocity_int: i32) -> f64 {
        velocity_to_pps(velocity_int.clamp(-2047, 2047), self.pulse_div())
    }

    /// AP4 in pps (at least 1 [int], so a ramp always ends).
    fn max_speed_pps(&self) -> f64 {
        self.speed_pps(self.stored(4).clamp(1, 2047))
    }

    /// AP5 in pps² (at least 1 [int]). §6.1.3's window for positioning ramps
    /// isn't enforced: the manual doesn't say what happens outside it.
    fn accel_pps2(&self) -> f64 {
        acceleration_to_pps2(
            self.stored(5).clamp(1, 2047),
            self.ramp_div(),
            self.pulse_div(),
        )
    }

    fn actual_position(&self) -> i32 {
        self.steps.wrapping_add(self.counter_offset) as i32
    }

    /// SAP 1: rewrite the counter. The carriage doesn't move: in position
    /// modes the target moves along by the same amount, so a motor at its
    /// target stays there (AP8 stays 1) and a running move ends where it
    /// would have.
    fn set_actual_position(&mut self, value: i32) {
        let delta = value.wrapping_sub(self.actual_position());
        self.counter_offset = self.counter_offset.wrapping_add(i64::from(delta));
        if self.mode() != MODE_VELOCITY {
            let target = self.stored(0).wrapping_add(delta);
            self.stored.insert(0, target);
        }
    }

    /// The machine position of AP0, the short way round (§3.6.4 note).
    fn target_machine(&self) -> i64 {
        let offset = self.stored(0).wrapping_sub(self.actual_position());
        self.steps.saturating_add(i64::from(offset))
    }

    /// A position move has arrived: the rule for [`AxisEvent::TargetReached`]
    /// (command 138's second reply), stricter than AP8, which also reads 1
    /// when the counter merely passes AP0.
    fn arrived(&self) -> bool {
        self.search.is_none()
            && self.mode() != MODE_VELOCITY
            && !self.is_moving()
            && self.actual_position() == self.stored(0)
    }

    // ----- encoder and supervision -----

    fn shaft(&self) -> i64 {
        self.steps.saturating_sub(self.encoder.slip)
    }

    fn encoder_count(&self) -> i64 {
        let prescaler = i128::from(self.stored(210) & !ENCODER_FUNCTION_BITS);
        let counts = i128::from(self.shaft()) - i128::from(self.encoder.shaft_at_base);
        let scaled = (counts * prescaler).div_euclid(ENCODER_PRESCALER_ONE);
        let total = i128::from(self.encoder.base) + scaled;
        total.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64
    }

    fn deviation(&self) -> i64 {
        let encoder = self.encoder_count() as i32;
        i64::from(self.actual_position().wrapping_sub(encoder)).abs()
    }

    /// Sampling is needed while the motor turns with a stop on stall
    /// (AP181), a deviation stop (AP212) or CoolStep (AP172) set.
    fn supervision_armed(&self) -> bool {
        self.is_moving()
            && (self.stored(212) > 0 || self.stored(181) > 0 || self.coolstep().enabled())
    }

    /// Every [`TICK`] while armed: a StallGuard2 measurement (and CoolStep's
    /// reaction to it); §7.2 / AP181: stall stop at or above the
    /// AP181 speed when the load reading is 0; AP212: deviation stop. Both
    /// stop the motor at once, like the TMCL firmware's hard stop (velocity
    /// mode, target speed 0).
    fn supervise(&mut self) {
        if !self.is_moving() {
            return;
        }
        let reading = self.measure();
        let threshold = self.stored(181);
        let speed = self.param(3).abs();
        let stall = threshold > 0 && speed >= threshold && reading == 0;
        let max_deviation = self.stored(212);
        let deviation = max_deviation > 0 && self.deviation() > i64::from(max_deviation);
        if !stall && !deviation {
            return;
        }
        let mut flags = self.stored(207);
        if stall {
            flags |= STALL_ERROR;
            self.pending.push(AxisEvent::StallStop);
        }
        if deviation {
            flags |= DEVIATION_ERROR;
            self.pending.push(AxisEvent::DeviationStop);
        }
        self.stored.insert(207, flags);
        if self.search.is_some() {
            let reason = if stall {
                ReferenceAbort::Stall
            } else {
                ReferenceAbort::Deviation
            };
            self.abort_search(reason);
        }
        self.halt();
    }

    // ----- switches -----

    fn physical(&self, which: Switch) -> bool {
        let at = self.steps;
        let wired = match which {
            Switch::Left if self.layout.limits_swapped => Switch::Right,
            Switch::Right if self.layout.limits_swapped => Switch::Left,
            other => other,
        };
        self.layout
            .span(wired)
            .is_some_and(|(low, high)| (low..=high).contains(&at))
    }

    fn switch_states(&self) -> [bool; 3] {
        [
            self.switch(Switch::Left),
            self.switch(Switch::Right),
            self.switch(Switch::Home),
        ]
    }

    fn emit_switch_edges(&mut self) {
        let now = self.switch_states();
        for (i, which) in [Switch::Left, Switch::Right, Switch::Home]
            .into_iter()
            .enumerate()
        {
            if now[i] != self.last_switches[i] {
                self.pending.push(AxisEvent::SwitchChanged {
                    switch: which,
                    active: now[i],
                });
            }
        }
        self.last_switches = now;
    }

    /// Right switch stops positive motion, left stops negative (AP12/AP13 =
    /// 1 disable them); the reference search handles the switches itself
    /// (§7.1: AP12/AP13 don't influence it).
    fn blocks(&self) -> Blocks {
        let (positive_end, negative_end) =
            self.layout.end_stops.map_or((false, false), |(low, high)| {
                (self.steps >= high, self.steps <= low)
            });
        if self.search.is_some() {
            return Blocks {
                positive_end,
                negative_end,
                ..Blocks::default()
            };
        }
        Blocks {
            positive: self.switch(Switch::Right) && self.stored(12) == 0,
            negative: self.switch(Switch::Left) && self.stored(13) == 0,
            positive_end,
            negative_end,
        }
    }

    /// The next machine position, in `direction`, at which a switch input
    /// changes or the search's travel bound lies.
    fn next_threshold(&self, direction: i8) -> Option<i64> {
        if direction == 0 {
            return None;
        }
        let up = direction > 0;
        let mut candidates: Vec<i64> = Vec::with_capacity(7);
        for which in [Switch::Left, Switch::Right, Switch::Home] {
            if let Some((low, high)) = self.layout.span(which) {
                if up {
                    candidates.extend([low, high.saturating_add(1)]);
                } else {
                    candidates.extend([high, low.saturating_sub(1)]);
                }
            }
        }
        if let Some((low, high)) = self.layout.end_stops {
            candidates.push(if up { high } else { low });
        }
        if let Some(search) = &self.search {
            let bound = REFERENCE_SEARCH_MAX_TRAVEL * i64::from(direction);
            candidates.push(search.run_start.saturating_add(bound));
        }
        let at = self.steps;
        if up {
            candidates.into_iter().filter(|c| *c > at).min()
        } else {
            candidates.into_iter().filter(|c| *c < at).max()
        }
    }

    // ----- kinematics -----

    fn segment(&self) -> Segment {
        self.plan.front().copied().unwrap_or(Segment::HOLD)
    }

    fn segment_seconds(&self) -> f64 {
        self.segment_ns as f64 * 1e-9
    }

    /// Continuous machine position minus `origin`.
    fn position_from(&self, origin: i64) -> f64 {
        self.anchor.saturating_sub(origin) as f64
            + self.anchor_frac
            + self.segment().displacement(self.segment_seconds())
    }

    /// How long until the next thing happens, at most `budget` ns. Ties go
    /// to the discrete causes, so an event due exactly at the end of an
    /// `advance` is handled within it.
    fn next_slice(&self, budget: u64) -> (u64, Cause) {
        let segment = self.segment();
        let mut best = (budget, Cause::Budget);
        let mut consider = |ns: u64, cause: Cause| {
            if ns <= best.0 {
                best = (ns, cause);
            }
        };
        if self.supervision_armed() {
            consider(TICK_NS - self.clock_ns % TICK_NS, Cause::Tick);
        }
        if let Some(position) = self.next_threshold(segment.direction()) {
            let distance = position.saturating_sub(self.anchor) as f64 - self.anchor_frac;
            if let Some(t) = segment.time_to_travel(distance) {
                let at = seconds_to_ns_ceil(t);
                consider(
                    at.saturating_sub(self.segment_ns),
                    Cause::Crossing(position),
                );
            }
        }
        if segment.duration.is_finite() {
            let end = segment.duration_ns();
            consider(end.saturating_sub(self.segment_ns), Cause::SegmentEnd);
        }
        best
    }

    fn pass_time(&mut self, ns: u64) {
        if ns == 0 {
            return;
        }
        self.segment_ns = self.segment_ns.saturating_add(ns);
        self.clock_ns = self.clock_ns.saturating_add(ns);
        self.update_steps();
    }

    /// The counter moves once the continuous position is a whole step away.
    fn update_steps(&mut self) {
        let offset = self.position_from(self.steps);
        if offset >= 1.0 {
            self.steps = self.steps.saturating_add(offset.floor() as i64);
        } else if offset <= -1.0 {
            self.steps = self.steps.saturating_add(offset.ceil() as i64);
        }
    }

    /// A switch threshold was reached: make sure the counter shows it even
    /// if rounding left the continuous position a hair short.
    fn reach(&mut self, position: i64) {
        let direction = self.segment().direction();
        if direction > 0 {
            self.steps = self.steps.max(position);
        } else if direction < 0 {
            self.steps = self.steps.min(position);
        }
    }

    fn finish_segment(&mut self) {
        let Some(done) = self.plan.pop_front() else {
            self.plan.push_back(Segment::HOLD);
            return;
        };
        self.segment_ns = 0;
        if self.plan.is_empty() {
            self.plan.push_back(if done.v_end == 0.0 {
                Segment::HOLD
            } else {
                Segment::cruise_forever(done.v_end)
            });
        }
        if let Some(target) = done.lands_on {
            self.anchor = target;
            self.anchor_frac = 0.0;
            self.steps = target;
        } else {
            self.set_anchor(self.anchor_frac + done.displacement(done.duration));
            self.update_steps();
        }
    }

    /// Anchor = `anchor` + `offset` (normalised to whole + fraction).
    fn set_anchor(&mut self, offset: f64) {
        let whole = offset.floor();
        self.anchor = self.anchor.saturating_add(whole as i64);
        self.anchor_frac = offset - whole;
    }

    /// Start a new plan here and now; returns the speed to continue from.
    fn reanchor(&mut self) -> f64 {
        let segment = self.segment();
        let t = self.segment_seconds();
        let v = segment.velocity(t);
        self.set_anchor(self.anchor_frac + segment.displacement(t));
        self.segment_ns = 0;
        self.plan.clear();
        v
    }

    /// Stop dead on the current microstep.
    fn hard_stop(&mut self) {
        self.reanchor();
        self.anchor = self.steps;
        self.anchor_frac = 0.0;
        self.plan.clear();
        self.plan.push_back(Segment::HOLD);
    }

    /// Hard stop and leave the axis in velocity mode with target speed 0.
    fn halt(&mut self) {
        self.stored.insert(2, 0);
        self.stored.insert(138, MODE_VELOCITY);
        self.hard_stop();
        self.replan();
    }

    fn goal(&self) -> Goal {
        if let Some(search) = &self.search {
            let fast = self.speed_pps(self.stored(194).abs());
            let slow = self.speed_pps(self.stored(195).abs());
            let dir = f64::from(search.run_direction());
            return match search.step() {
                Some(Step::Seek { .. }) => Goal::Velocity(dir * fast),
                Some(Step::Leave { .. } | Step::Enter { .. }) => Goal::Velocity(dir * slow),
                Some(Step::GoToReference) => Goal::Position {
                    target: search.reference.unwrap_or(self.steps),
                    vmax: slow,
                    soft: false,
                },
                None => Goal::Velocity(0.0),
            };
        }
        match self.mode() {
            MODE_VELOCITY => Goal::Velocity(self.speed_pps(self.stored(2))),
            mode => Goal::Position {
                target: self.target_machine(),
                vmax: self.max_speed_pps(),
                soft: mode == MODE_SOFT,
            },
        }
    }

    /// Plan the motion from the present state towards the present goal,
    /// within the end-switch blocks.
    fn replan(&mut self) {
        let v = self.reanchor();
        let blocks = self.blocks();
        let accel = self.accel_pps2();
        let mut builder = Builder::new(v);
        let heading = if v > 0.0 {
            1
        } else if v < 0.0 {
            -1
        } else {
            0
        };
        if blocks.end_stop(heading) {
            // Against a mechanical end stop: the carriage stands at once.
            builder = Builder::new(0.0);
            self.anchor = self.steps;
            self.anchor_frac = 0.0;
        } else if blocks.switch(heading) {
            // Running into an active end switch: AP149 chooses between a
            // hard stop and a deceleration ramp.
            if self.stored(149) == 1 {
                builder.ramp_to(0.0, accel);
            } else {
                builder = Builder::new(0.0);
                self.anchor = self.steps;
                self.anchor_frac = 0.0;
            }
            if self.limit_stopped != Some(heading) {
                let which = if heading > 0 {
                    Switch::Right
                } else {
                    Switch::Left
                };
                self.pending.push(AxisEvent::LimitStop(which));
                self.limit_stopped = Some(heading);
            }
        }
        let braking = builder.len();
        let mut landing = None;
        match self.goal() {
            Goal::Velocity(target) => builder.velocity_mode(target, accel),
            Goal::Position { target, vmax, soft } => {
                let distance = target.saturating_sub(self.anchor) as f64 - self.anchor_frac;
                let landed = if soft {
                    let vmin = self.speed_pps(self.stored(130).clamp(1, 2047));
                    builder.soft(distance, vmax, accel, vmin)
                } else {
                    builder.trapezoid(distance, vmax, accel)
                };
                if landed {
                    if builder.len() == 0 {
                        // Already there (to within a rounding hair).
                        self.anchor = target;
                        self.anchor_frac = 0.0;
                    }
                    landing = Some(target);
                }
            }
        }
        let v_last = builder.velocity();
        let mut segments = builder.into_segments(landing);
        let cut = segments
            .iter()
            .skip(braking)
            .position(|s| blocks.contains(s.direction()));
        let open_end = if let Some(cut) = cut {
            segments.truncate(braking + cut);
            Segment::HOLD
        } else if landing.is_some() || v_last == 0.0 {
            Segment::HOLD
        } else {
            Segment::cruise_forever(v_last)
        };
        self.plan = segments.into();
        self.plan.push_back(open_end);
        self.segment_ns = 0;
        self.plan_blocks = blocks;
    }

    /// React to whatever changed at this instant: switch edges, end-switch
    /// blocks, search progress, arrival.
    fn settle(&mut self) {
        self.emit_switch_edges();
        if self.search.is_some() {
            self.drive_search();
        }
        if self.search.is_none() {
            let blocks = self.blocks();
            if self.limit_stopped.is_some_and(|d| !blocks.contains(d)) {
                self.limit_stopped = None;
            }
            if blocks != self.plan_blocks {
                self.replan();
            }
        }
        if self.reached_pending && self.arrived() {
            self.reached_pending = false;
            self.pending.push(AxisEvent::TargetReached);
        }
    }

    // ----- reference search -----

    /// What the search sees of a switch: end switches after GP79, the home
    /// switch inverted again with +128.
    fn search_sees(&self, which: Switch, search: &Search) -> bool {
        let state = self.switch(which);
        if which == Switch::Home && search.mode.home_inverted {
            !state
        } else {
            state
        }
    }

    /// Advance the search's program as far as the present state allows.
    fn drive_search(&mut self) {
        // Each pass completes at most one run; a program has at most eleven.
        for _ in 0..16 {
            let Some(search) = self.search.clone() else {
                return;
            };
            let Some(step) = search.step() else {
                return;
            };
            let done = match step {
                Step::Seek { switch, .. } => {
                    if self.search_sees(switch, &search) {
                        true
                    } else if search.mode.info.reverse_at_limit {
                        // Modes 5/6: turn round once at the end switch ahead.
                        let dir = search.run_direction();
                        let ahead = if dir > 0 { Switch::Right } else { Switch::Left };
                        if self.switch(ahead) {
                            if search.reversed {
                                self.abort_search(ReferenceAbort::HomeNotBetweenLimits);
                                self.halt();
                                return;
                            }
                            self.hard_stop();
                            if let Some(s) = self.search.as_mut() {
                                s.reversed = true;
                                s.run_start = self.steps;
                            }
                            continue;
                        }
                        false
                    } else {
                        false
                    }
                }
                Step::Leave { switch, dir } => {
                    let released = !self.search_sees(switch, &search);
                    if released {
                        let last_active = self.steps.saturating_sub(i64::from(dir));
                        if let Some(s) = self.search.as_mut() {
                            s.marks.push(last_active);
                        }
                    }
                    released
                }
                Step::Enter { switch, .. } => {
                    let entered = self.search_sees(switch, &search);
                    if entered {
                        let at = self.steps;
                        if let Some(s) = self.search.as_mut() {
                            s.marks.push(at);
                        }
                    }
                    entered
                }
                Step::GoToReference => {
                    let Some((reference, distance)) = search
                        .reference
                        .map(|r| (r, search.distance))
                        .or_else(|| search.mode.reference(&search.marks))
                    else {
                        self.abort_search(ReferenceAbort::TravelExceeded);
                        self.halt();
                        return;
                    };
                    if let Some(s) = self.search.as_mut() {
                        s.reference = Some(reference);
                        s.distance = distance;
                    }
                    if !self.is_moving() && self.steps == reference && self.anchor == reference {
                        self.finish_search(reference, distance);
                        return;
                    }
                    false
                }
            };
            if done {
                self.hard_stop();
                let at = self.steps;
                if let Some(s) = self.search.as_mut() {
                    s.next(at);
                }
                continue;
            }
            if step != Step::GoToReference
                && self.steps.saturating_sub(search.run_start).abs() >= REFERENCE_SEARCH_MAX_TRAVEL
            {
                self.abort_search(ReferenceAbort::TravelExceeded);
                self.halt();
                return;
            }
            let run = (search.index, search.reversed);
            if self.search_planned != Some(run) {
                self.search_planned = Some(run);
                self.replan();
            }
            return;
        }
    }

    /// §7.1 / AP197: the counter becomes 0 at the reference, AP197 keeps the
    /// value it had there; the motor stands on the reference in position
    /// mode with target 0.
    fn finish_search(&mut self, reference: i64, distance: Option<i64>) {
        let last = self.actual_position();
        self.counter_offset = reference.wrapping_neg();
        self.stored.insert(197, last);
        if let Some(distance) = distance {
            self.stored.insert(196, distance as i32);
        }
        self.stored.insert(0, 0);
        self.stored.insert(138, MODE_POSITION);
        self.end_search(ReferenceOutcome::Found {
            last_reference_position: last,
        });
        self.replan();
    }

    fn abort_search(&mut self, reason: ReferenceAbort) {
        self.end_search(ReferenceOutcome::Aborted(reason));
    }

    fn end_search(&mut self, outcome: ReferenceOutcome) {
        self.search = None;
        self.search_planned = None;
        self.outcome = Some(outcome);
        self.pending.push(AxisEvent::ReferenceSearchDone);
    }

    /// A motion command takes over from a running search.
    fn interrupt_search(&mut self) {
        if self.search.is_some() {
            self.abort_search(ReferenceAbort::Interrupted);
        }
    }
}
