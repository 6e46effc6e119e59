//! The CMD-4CR's motion engine: four axes X, Y, Z, U with their speed
//! profiles, jog, positioning, homing, interpolation, the move buffer,
//! on-the-fly changes, stops, safety inputs, counters and status, on
//! virtual time. A typed interface, no text: the wire layer turns commands
//! into calls of [`Motion`] and [`Refusal`]s into `?…` replies.
//!
//! Time advances in ticks of [`TICK`] (100 µs); every motion is exact
//! kinematics sampled at tick boundaries, and leftover time is carried to
//! the next call, so any split of virtual time gives the same motion.
//! Switch edges and index pulses are found at their exact pulse within a
//! tick, so a limit stop or a homing zero lands on the switch's position.
//!
//! Choices where the manual is silent (also in the simulator's help):
//! - Checks before a motion command, in this order: axis busy →
//!   `?Error Moving`; /CEMG low → `?Error ESTOP` (and EMG error flag,
//!   §2.1.3.1.2); ALM on → `?Error Alarm`; end limit on in the direction of
//!   travel → `?Error ±Limit`; a latched error (MST bits 8, 9, 10, 16) →
//!   `?Error Moving` (T4-41: "may be in error state"). A multi-axis command
//!   starts nothing unless every axis passes.
//! - End limits and ALM stop at once (the manual leaves "immediately, or
//!   decelerates and stops" open; Appendix A always stops at once).
//! - Circles and arcs do not check the end limits before starting (their
//!   direction changes along the way); the limits still stop them.
//! - `ESTOP` and /CEMG stop an axis under joystick control as they stop
//!   any motion, with the EMG flag if it moved (§2.1.3.1.2); it then stays
//!   still until CLR and until the stick is back in its dead band, so that
//!   an emergency stop does not end by itself while the stick is held out.
//! - StepNLoop with every kind of motion: see [`step_n_loop`].
//! - Missed steps ([`Motion::miss_steps`], [`Motion::set_slip`]): the pulse
//!   counter keeps every pulse sent, the carriage (and so the encoder)
//!   falls behind against the direction the move drives the axis, and the
//!   rest of the move goes on from where the carriage is. A slipping motor
//!   misses its share of each tick's steps (fractions carried to the next
//!   tick) on single-axis runs and interpolations alike: the carriage moves
//!   that much less, and the switches it passes are the ones it reaches.
//!   Not under the joystick or MPG, which move the axis outside the
//!   engine's moves.

pub mod axis;
mod buffering;
mod group;
pub mod homing;
mod overrides;
pub mod path;
pub mod profile;
mod run;
pub mod stage;
mod starting;
pub mod step_n_loop;
mod stopping;
pub mod sync;
mod ticking;

#[cfg(test)]
mod tests;

use std::collections::VecDeque;
use std::time::Duration;

use crate::protocol::cmd4cr::ErrorCode;
use axis::{AxisState, mst};
use group::{Group, GroupOutcome};
use path::{Arc, Path};
use profile::{PhaseKind, Ramps, Shape};
use run::{Goal, Outcome, ProcedureRun, Purpose, Run};
use stage::Stage;
use step_n_loop::{Verdict, status as sls};

pub use group::{BUFFER_SIZE, BufferStatus, BufferedMove};

/// The engine's time step.
pub const TICK: Duration = Duration::from_micros(100);

pub use crate::protocol::cmd4cr::{Axis, Direction, Rotation};

/// +1 or −1.
pub fn sign(direction: Direction) -> i64 {
    match direction {
        Direction::Plus => 1,
        Direction::Minus => -1,
    }
}

fn direction_of(delta: i64) -> Option<Direction> {
    match delta.signum() {
        1 => Some(Direction::Plus),
        -1 => Some(Direction::Minus),
        _ => None,
    }
}

/// Why a motion command is not processed: the `?…` replies of T4-41 that
/// the motion engine gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    Moving,
    Alarm,
    PlusLimit,
    MinusLimit,
    Estop,
    StepNLoop,
    BufferFull,
    BufferDisabled,
    BufferEnabled,
    SpeedWindow,
    OverrideFailed,
}

impl Refusal {
    /// The reply of Table 4-41.
    pub fn code(self) -> ErrorCode {
        match self {
            Refusal::Moving => ErrorCode::ErrorMoving,
            Refusal::Alarm => ErrorCode::ErrorAlarm,
            Refusal::PlusLimit => ErrorCode::ErrorPlusLimit,
            Refusal::MinusLimit => ErrorCode::ErrorMinusLimit,
            Refusal::Estop => ErrorCode::ErrorEstop,
            Refusal::StepNLoop => ErrorCode::ErrorSnl,
            Refusal::BufferFull => ErrorCode::BufferFull,
            Refusal::BufferDisabled => ErrorCode::BufferDisabled,
            Refusal::BufferEnabled => ErrorCode::BufferEnabled,
            Refusal::SpeedWindow => ErrorCode::SspdError,
            Refusal::OverrideFailed => ErrorCode::OverrideFailed,
        }
    }
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.code().info().reply)
    }
}

impl std::error::Error for Refusal {}

/// Settings of the whole core.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GlobalSettings {
    /// `HSPD`, pps.
    pub hspd: u32,
    /// `LSPD`, pps.
    pub lspd: u32,
    /// `ACC`, ms.
    pub acc: u32,
    /// `DEC`, ms.
    pub dec: u32,
    /// `EINT`: multi-axis moves are interpolated (default 1, §2.3.1).
    pub interpolate: bool,
    /// `INC` (`MM` 1) rather than `ABS`.
    pub incremental: bool,
    /// `IERR`: do not latch limit, alarm and EMG errors.
    pub ignore_errors: bool,
    /// `EXST`: motion waits for /CSTA.
    pub external_start: bool,
}

/// Power-on speeds, our choice (the manual gives none, digest §0): slow
/// enough for a first test of an unknown machine.
pub const DEFAULT_HSPD: u32 = 1000;
pub const DEFAULT_LSPD: u32 = 100;
pub const DEFAULT_ACC_MS: u32 = 300;
pub const DEFAULT_DEC_MS: u32 = 300;

impl Default for GlobalSettings {
    fn default() -> Self {
        GlobalSettings {
            hspd: DEFAULT_HSPD,
            lspd: DEFAULT_LSPD,
            acc: DEFAULT_ACC_MS,
            dec: DEFAULT_DEC_MS,
            interpolate: true,
            incremental: false,
            ignore_errors: false,
            external_start: false,
        }
    }
}

/// A motion command.
#[derive(Debug, Clone, PartialEq)]
pub enum Start {
    /// `J[axis]±`.
    Jog { axis: Axis, direction: Direction },
    /// `X…Y…Z…U…`: targets as written (ABS/INC applies when it starts).
    Position { targets: Vec<(Axis, i64)> },
    /// `H[axis]±mode`.
    Home {
        axis: Axis,
        direction: Direction,
        mode: u8,
    },
    /// `ZMOVE[axis]±`.
    ZMove { axis: Axis, direction: Direction },
    /// `CIR…`, `ARC…`, `CIRT…`, `ARCT…` (centre absolute, §2.3.2).
    Arc {
        axes: (Axis, Axis),
        rotation: Rotation,
        centre: (i64, i64),
        end_mdeg: Option<i64>,
        helix_z: Option<i64>,
    },
}

/// Motion commands that may wait for /CSTA (§2.1.1.2).
pub const EXTERNAL_START_QUEUE: usize = 3;

/// What an axis is busy with.
#[derive(Debug, Clone, PartialEq)]
enum Activity {
    Idle,
    Run(Box<Run>),
    /// Member of the interpolation with this id.
    Group(u64),
    /// Motion ended; waiting for INP (MST bit 18).
    WaitInp,
}

/// The four axes and everything they share.
#[derive(Debug, Clone)]
pub struct Motion {
    pub global: GlobalSettings,
    axes: [AxisState; 4],
    activity: [Activity; 4],
    groups: Vec<(u64, Group)>,
    next_group: u64,
    buffer: group::Buffer,
    /// Id of the group the buffer feeds now.
    buffer_group: Option<u64>,
    /// /CEMG is low (emergency stop input on).
    emg_input: bool,
    /// /CSTA is low.
    start_input: bool,
    start_queue: VecDeque<Start>,
    /// Time not yet spent in whole ticks.
    pending: Duration,
}

impl Default for Motion {
    fn default() -> Self {
        Motion::new()
    }
}

impl Motion {
    /// Four axes on the demo stage ([`Stage::demo`]), power-on settings.
    pub fn new() -> Motion {
        Motion::with_stages(std::array::from_fn(|_| Stage::demo()))
    }

    pub fn with_stages(stages: [Stage; 4]) -> Motion {
        let mut stages = stages.into_iter();
        let axes =
            Axis::ALL.map(|name| AxisState::new(name, stages.next().unwrap_or_else(Stage::bare)));
        Motion {
            global: GlobalSettings::default(),
            axes,
            activity: std::array::from_fn(|_| Activity::Idle),
            groups: Vec::new(),
            next_group: 0,
            buffer: group::Buffer::default(),
            buffer_group: None,
            emg_input: false,
            start_input: false,
            start_queue: VecDeque::new(),
            pending: Duration::ZERO,
        }
    }

    pub fn axis(&self, name: Axis) -> &AxisState {
        &self.axes[name.index()]
    }

    pub fn axis_mut(&mut self, name: Axis) -> &mut AxisState {
        &mut self.axes[name.index()]
    }

    /// Whether the axis is busy (moving, in an interpolation, waiting for
    /// INP or held by a helical move).
    pub fn is_busy(&self, name: Axis) -> bool {
        self.activity[name.index()] != Activity::Idle
    }

    /// Any axis busy, or a move waiting for /CSTA.
    pub fn any_busy(&self) -> bool {
        Axis::ALL.iter().any(|&a| self.is_busy(a)) || !self.start_queue.is_empty()
    }

    /// `MST[axis]`.
    pub fn status(&self, name: Axis) -> u32 {
        self.axis(name).status(self.emg_input, self.start_input)
    }

    /// `PS[axis]`, pps.
    pub fn pulse_rate(&self, name: Axis) -> i64 {
        self.axis(name).rate.round() as i64
    }

    /// `PS[axis]` as read (T2-29): encoder counts/s for a single-axis move
    /// with StepNLoop on, pulses/s otherwise.
    pub fn pulse_rate_reading(&self, name: Axis) -> i64 {
        let a = self.axis(name);
        match self.activity[name.index()] {
            Activity::Run(_) if a.step_n_loop.enabled => {
                (a.rate / a.step_n_loop.pulses_per_count()).round() as i64
            }
            _ => self.pulse_rate(name),
        }
    }

    /// `P[axis]`.
    pub fn counter(&self, name: Axis) -> i64 {
        self.axis(name).counter()
    }

    /// `E[axis]`.
    pub fn encoder(&self, name: Axis) -> i64 {
        self.axis(name).encoder()
    }

    /// `P[axis]=v`.
    pub fn set_counter(&mut self, name: Axis, value: i64) {
        self.axis_mut(name).set_counter(value);
    }

    /// `E[axis]=v`.
    pub fn set_encoder(&mut self, name: Axis, value: i64) {
        self.axis_mut(name).set_encoder(value);
    }

    /// `CLR[axis]`: clear the latched flags (§2.6.2.3).
    pub fn clear_errors(&mut self, name: Axis) {
        let a = self.axis_mut(name);
        a.errors &= !mst::CLEARED_BY_CLR;
        // CLR clears the StepNLoop errors too (Table 27).
        if a.loop_state.in_error() || a.loop_state.status == sls::LIMIT_ERROR {
            a.loop_state.status = sls::IDLE;
        }
    }

    /// Whether the axis stands still without a latched error (§4.3.3: the
    /// counters "can be cleared only when the axis is normally stopped").
    pub fn stopped_normally(&self, name: Axis) -> bool {
        !self.is_busy(name) && self.axis(name).errors & mst::BLOCKING_ERRORS == 0
    }

    /// Move an idle axis by `delta` pulses at once (MPG following,
    /// §2.5.2), stopping on an end limit in the way; the pulses moved.
    pub fn nudge(&mut self, name: Axis, delta: i64) -> i64 {
        if self.is_busy(name) || delta == 0 || self.emg_input {
            return 0;
        }
        let a = &mut self.axes[name.index()];
        let old = a.position;
        let direction = if delta > 0 {
            Direction::Plus
        } else {
            Direction::Minus
        };
        if a.limit_on(direction) {
            return 0;
        }
        let mut new = old.saturating_add(delta.clamp(-(1 << 31), 1 << 31));
        for (at, mark) in run::marks(a, old, new) {
            let ahead = match mark {
                stage::Mark::PlusLimit(true) => delta > 0,
                stage::Mark::MinusLimit(true) => delta < 0,
                _ => false,
            };
            if ahead {
                new = at;
                break;
            }
        }
        a.position = new;
        a.levels = a.levels_at(new);
        new - old
    }

    /// One tick of joystick control of an idle axis (§2.5.1): move by
    /// `pulses` at `velocity` pps (signed), unless an end limit in that
    /// direction is on or the emergency stop input is; MST and PS show the
    /// motion.
    pub fn joystick_move(&mut self, name: Axis, pulses: i64, velocity: f64) {
        if self.is_busy(name) {
            return;
        }
        let a = &mut self.axes[name.index()];
        if a.joystick_held && velocity == 0.0 {
            // The stick is back in its dead band: it may drive again.
            a.joystick_held = false;
        }
        let blocked = self.emg_input
            || a.joystick_held
            // "The error status is clear" (§2.5.1 operating conditions).
            || a.errors & mst::EMG_ERROR != 0
            || (velocity > 0.0 && self.axis(name).limit_on(Direction::Plus))
            || (velocity < 0.0 && self.axis(name).limit_on(Direction::Minus));
        let velocity = if blocked { 0.0 } else { velocity };
        let moved = if blocked { 0 } else { self.nudge(name, pulses) };
        let a = &mut self.axes[name.index()];
        let speed = velocity.abs();
        a.phase = if speed == 0.0 && moved == 0 {
            None
        } else if speed > a.rate {
            Some(PhaseKind::Accelerating)
        } else if speed < a.rate {
            Some(PhaseKind::Decelerating)
        } else {
            Some(PhaseKind::Constant)
        };
        a.rate = speed;
    }

    /// Power-on (§2.1.5): every axis stops, settings and counters start
    /// afresh; the machine (carriages, stages, wired inputs) stays as it is.
    pub fn power_up(&mut self) {
        for axis in &mut self.axes {
            axis.power_up();
        }
        self.activity = std::array::from_fn(|_| Activity::Idle);
        self.groups.clear();
        self.buffer = group::Buffer::default();
        self.buffer_group = None;
        self.start_queue.clear();
        self.global = GlobalSettings::default();
        self.pending = Duration::ZERO;
    }

    // ---- speed settings ----------------------------------------------

    /// The ramps of a single-axis move: per-axis values unless 0 (§2.1.4).
    fn axis_ramps(&self, name: Axis) -> Ramps {
        let a = self.axis(name);
        let s = &a.settings;
        let g = &self.global;
        let or = |own: u32, global: u32| if own == 0 { global } else { own };
        // With StepNLoop on, single-axis speeds are encoder counts/s (§2.5.3).
        let scale = |speed: u32| {
            if a.step_n_loop.enabled {
                (f64::from(speed) * a.step_n_loop.pulses_per_count())
                    .round()
                    .clamp(1.0, f64::from(profile::MAX_SPEED)) as u32
            } else {
                speed
            }
        };
        Ramps::new(
            scale(or(s.lspd, g.lspd)),
            scale(or(s.hspd, g.hspd)),
            or(s.acc, g.acc),
            or(s.dec, g.dec),
            s.shape(),
        )
    }

    /// The ramps of a coordinated move: always the global values (§2.1.4);
    /// S-curve if the first axis has it.
    fn global_ramps(&self, lead: Axis) -> Ramps {
        let g = &self.global;
        Ramps::new(
            g.lspd,
            g.hspd,
            g.acc,
            g.dec,
            self.axis(lead).settings.shape(),
        )
    }

    // ---- inputs from outside ------------------------------------------

    /// /CEMG low (`true`) or high: while low every axis stops and none may
    /// start (§2.1.3.1.2).
    pub fn set_emergency_input(&mut self, low: bool) {
        self.emg_input = low;
        if low {
            self.emergency_stop();
        }
    }

    pub fn emergency_input(&self) -> bool {
        self.emg_input
    }

    /// /CSTA level; a falling edge starts the oldest waiting move
    /// (§2.1.1.2).
    pub fn set_start_input(&mut self, low: bool) {
        let edge = low && !self.start_input;
        self.start_input = low;
        if edge && let Some(start) = self.start_queue.pop_front() {
            for axis in start_axes(&start) {
                self.axes[axis.index()].waiting_for_start = false;
            }
            // Checked when queued; a move that can no longer start is dropped.
            let _ = self.begin(start);
            self.mark_waiting();
        }
    }

    fn mark_waiting(&mut self) {
        for start in &self.start_queue {
            for axis in start_axes(start) {
                self.axes[axis.index()].waiting_for_start = true;
            }
        }
    }

    /// ALM of one axis; an axis in motion stops at once (§2.1.2.2).
    pub fn set_alarm(&mut self, name: Axis, on: bool) {
        self.axis_mut(name).inputs.alarm = on;
    }

    /// The position latch input of `name` rose (DIn, T2-3).
    pub fn latch_input(&mut self, name: Axis) {
        let axis = self.axis_mut(name);
        let (pulse, encoder) = (axis.counter(), axis.encoder());
        axis.latch.trigger(pulse, encoder);
    }

    // ---- motion commands ----------------------------------------------

    /// What phase an axis is in (MST bits 0..2).
    pub fn phase(&self, name: Axis) -> Option<PhaseKind> {
        self.axis(name).phase
    }

    /// The ramps a single-axis move of `name` would use now.
    pub fn ramps_of(&self, name: Axis) -> Ramps {
        self.axis_ramps(name)
    }

    /// The shape of `name`'s ramps.
    pub fn shape_of(&self, name: Axis) -> Shape {
        self.axis(name).settings.shape()
    }
}

/// The axes a command holds.
fn start_axes(start: &Start) -> Vec<Axis> {
    match start {
        Start::Jog { axis, .. } | Start::Home { axis, .. } | Start::ZMove { axis, .. } => {
            vec![*axis]
        }
        Start::Position { targets } => targets.iter().map(|&(a, _)| a).collect(),
        Start::Arc { axes, helix_z, .. } => {
            let mut v = vec![axes.0, axes.1];
            if helix_z.is_some() {
                v.extend([Axis::Z, Axis::U]);
            }
            v
        }
    }
}
