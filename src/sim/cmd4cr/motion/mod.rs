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
mod group;
pub mod homing;
pub mod path;
pub mod profile;
mod run;
pub mod stage;
pub mod step_n_loop;
pub mod sync;

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

    /// A motion command: started, or queued while EXST=1.
    pub fn start(&mut self, start: Start) -> Result<(), Refusal> {
        self.check(&start)?;
        if self.global.external_start {
            if self.start_queue.len() >= EXTERNAL_START_QUEUE {
                return Err(Refusal::Moving);
            }
            self.start_queue.push_back(start);
            self.mark_waiting();
            return Ok(());
        }
        self.begin(start)
    }

    /// The conditions every motion command needs (see the module notes).
    fn check(&mut self, start: &Start) -> Result<(), Refusal> {
        let moves = self.directions(start);
        for &(axis, _) in &moves {
            if self.is_busy(axis)
                || self
                    .start_queue
                    .iter()
                    .any(|s| start_axes(s).contains(&axis))
            {
                return Err(Refusal::Moving);
            }
        }
        if self.emg_input {
            if !self.global.ignore_errors {
                for &(axis, _) in &moves {
                    self.axes[axis.index()].errors |= mst::EMG_ERROR;
                }
            }
            return Err(Refusal::Estop);
        }
        for &(axis, direction) in &moves {
            let a = self.axis(axis);
            if a.inputs.alarm {
                return Err(Refusal::Alarm);
            }
            match direction {
                Some(Direction::Plus) if a.limit_on(Direction::Plus) => {
                    return Err(Refusal::PlusLimit);
                }
                Some(Direction::Minus) if a.limit_on(Direction::Minus) => {
                    return Err(Refusal::MinusLimit);
                }
                _ => {}
            }
        }
        for &(axis, _) in &moves {
            let a = self.axis(axis);
            if a.step_n_loop.enabled && a.loop_state.in_error() {
                return Err(Refusal::StepNLoop);
            }
        }
        for &(axis, _) in &moves {
            let a = self.axis(axis);
            if a.errors & mst::BLOCKING_ERRORS != 0 || a.manual_control {
                return Err(Refusal::Moving);
            }
        }
        Ok(())
    }

    /// The axes a command moves, with the direction where it is known.
    fn directions(&self, start: &Start) -> Vec<(Axis, Option<Direction>)> {
        match start {
            Start::Jog { axis, direction }
            | Start::Home {
                axis, direction, ..
            }
            | Start::ZMove { axis, direction } => vec![(*axis, Some(*direction))],
            Start::Position { targets } => targets
                .iter()
                .map(|&(axis, value)| (axis, direction_of(self.distance(axis, value))))
                .collect(),
            Start::Arc { axes, helix_z, .. } => {
                let mut v = vec![(axes.0, None), (axes.1, None)];
                if let Some(z) = helix_z {
                    let to = self.counter_value(Axis::Z, *z);
                    v.push((Axis::Z, direction_of(to - self.counter(Axis::Z))));
                    v.push((Axis::U, None));
                }
                v
            }
        }
    }

    /// Pulses from where the axis is to `value` under ABS/INC; with
    /// StepNLoop on, `value` is an encoder position (§2.5.3).
    fn distance(&self, axis: Axis, value: i64) -> i64 {
        let a = self.axis(axis);
        if a.step_n_loop.enabled {
            let target = self.loop_goal(axis, value);
            let pulses = (target - a.encoder()) as f64 * a.step_n_loop.pulses_per_count();
            return pulses.round() as i64;
        }
        if self.global.incremental {
            value
        } else {
            value - self.counter(axis)
        }
    }

    /// The encoder target of `value` under ABS/INC (StepNLoop on).
    fn loop_goal(&self, axis: Axis, value: i64) -> i64 {
        if self.global.incremental {
            self.axis(axis).loop_target() + value
        } else {
            value
        }
    }

    /// The pulse counter value an absolute position means: the value
    /// itself, or with StepNLoop on an encoder position (§2.5.3: "this
    /// applies to individual as well as interpolated moves"), reached from
    /// where the encoder is at SLR pulses a count.
    fn counter_value(&self, axis: Axis, value: i64) -> i64 {
        let a = self.axis(axis);
        if !a.step_n_loop.enabled {
            return value;
        }
        let pulses = (value.saturating_sub(a.encoder())) as f64 * a.step_n_loop.pulses_per_count();
        // `as` saturates: an absurd value gives an absurd, harmless radius.
        a.counter().saturating_add(pulses.round() as i64)
    }

    /// The encoder position a StepNLoop axis should reach when it stands
    /// at machine position `end`.
    fn loop_goal_at(&self, axis: Axis, end: i64) -> i64 {
        let a = self.axis(axis);
        let counts = (end - a.position) as f64 / a.step_n_loop.pulses_per_count();
        a.encoder() + counts.round() as i64
    }

    /// Note `code` in SLS of those of `axes` whose loop follows a motion.
    fn loop_note(&mut self, axes: &[Axis], code: u8) {
        for &axis in axes {
            let a = &mut self.axes[axis.index()];
            if a.step_n_loop.enabled && a.loop_state.start.is_some() && !a.loop_state.in_error() {
                a.loop_state.status = code;
            }
        }
    }

    /// A StepNLoop axis stopped by an end limit: SLS 11 (Table 27).
    fn loop_limit_error(&mut self, axes: &[Axis]) {
        for &axis in axes {
            let a = &mut self.axes[axis.index()];
            let at_limit = a.limit_on(Direction::Plus) || a.limit_on(Direction::Minus);
            if a.step_n_loop.enabled && at_limit && !a.loop_state.in_error() {
                a.loop_state.status = sls::LIMIT_ERROR;
            }
        }
    }

    /// A commanded motion of `axis` starts: the loop follows it.
    fn loop_starts(&mut self, axis: Axis, code: u8, goal: Option<i64>) {
        let a = &mut self.axes[axis.index()];
        if !a.step_n_loop.enabled {
            return;
        }
        let origin = a.loop_target();
        a.loop_state = step_n_loop::LoopState {
            status: code,
            target: goal.unwrap_or(origin),
            origin,
            start: Some((a.counter(), a.encoder())),
            tries: 0,
        };
    }

    /// `SL[axis]=on`: the loop starts from where the encoder is.
    pub fn enable_step_n_loop(&mut self, axis: Axis, on: bool) {
        let a = &mut self.axes[axis.index()];
        if on && !a.step_n_loop.enabled {
            a.loop_state = step_n_loop::LoopState {
                target: a.encoder(),
                ..step_n_loop::LoopState::default()
            };
        }
        a.step_n_loop.enabled = on;
    }

    /// `SLS[axis]` (Table 27).
    pub fn loop_status(&self, axis: Axis) -> u8 {
        let a = self.axis(axis);
        if a.step_n_loop.enabled {
            a.loop_state.status
        } else {
            sls::NOT_ENABLED
        }
    }

    /// `P[axis]` as read: the pulse counter, or with StepNLoop on the
    /// real-time target in encoder counts (§2.6.1.1).
    pub fn position_reading(&self, axis: Axis) -> i64 {
        let a = self.axis(axis);
        if a.step_n_loop.enabled {
            a.loop_target()
        } else {
            a.counter()
        }
    }

    /// The motor misses `pulses` steps (a stall the encoder sees): the
    /// carriage lags the pulse counter by that much (+ leaves it short of
    /// a + move). For tests and demos of StepNLoop.
    pub fn lose_steps(&mut self, axis: Axis, pulses: i64) {
        self.axes[axis.index()].miss(pulses);
        let pulses = pulses.clamp(-(1 << 27), 1 << 27);
        // The pulses still to come start from where the carriage is now.
        match &mut self.activity[axis.index()] {
            Activity::Run(run) => run.shift(-pulses),
            Activity::Group(id) => {
                let id = *id;
                if let Some((_, group)) = self.groups.iter_mut().find(|(g, _)| *g == id) {
                    group.path.shift(axis, -pulses);
                }
            }
            Activity::Idle | Activity::WaitInp => {}
        }
    }

    /// Which way a move of the engine drives `axis` now: a single-axis run
    /// (positioning, jog, homing, correction, braking) its direction, an
    /// interpolation the way its path takes the axis at this point. `None`
    /// if no move sends it pulses (at rest, waiting for INP, U held by a
    /// helical move, an axis with no distance in its interpolation, the
    /// joystick or MPG, which are no moves of the engine).
    pub fn heading(&self, axis: Axis) -> Option<Direction> {
        match &self.activity[axis.index()] {
            Activity::Run(run) => direction_of(run.dir),
            Activity::Group(id) => self
                .groups
                .iter()
                .find(|(g, _)| g == id)
                .and_then(|(_, g)| direction_of(g.path.heading(axis, g.covered))),
            Activity::Idle | Activity::WaitInp => None,
        }
    }

    /// The motor of `axis` misses `pulses` steps of the move under way:
    /// the carriage (and the encoder) falls behind the pulse counter by
    /// that many, against the way the move drives it. The direction it
    /// was moving, or `None` (and nothing done) if no move drives it now
    /// ([`Motion::heading`]).
    pub fn miss_steps(&mut self, axis: Axis, pulses: u32) -> Option<Direction> {
        let direction = self.heading(axis)?;
        self.lose_steps(axis, sign(direction) * i64::from(pulses));
        Some(direction)
    }

    /// From now on the motor of `axis` misses `per_mille` of the steps of
    /// every move (0 none, 1000 all: it does not turn).
    pub fn set_slip(&mut self, axis: Axis, per_mille: u16) {
        let a = self.axis_mut(axis);
        a.inputs.slip = per_mille.min(1000);
        a.slip_carry = 0;
    }

    /// Start a checked command now.
    fn begin(&mut self, start: Start) -> Result<(), Refusal> {
        match start {
            Start::Jog { axis, direction } => {
                let ramps = self.axis_ramps(axis);
                let position = self.axis(axis).position;
                let run = Run::new(
                    position,
                    sign(direction),
                    ramps,
                    Goal::Endless,
                    Purpose::Jog,
                );
                self.loop_starts(axis, sls::JOGGING, None);
                self.launch(axis, run);
            }
            Start::Position { targets } => {
                let legs: Vec<(Axis, i64, i64)> = targets
                    .iter()
                    .map(|&(axis, value)| {
                        (axis, self.axis(axis).position, self.distance(axis, value))
                    })
                    .collect();
                let goals: Vec<(Axis, i64)> = targets
                    .iter()
                    .map(|&(axis, value)| (axis, self.loop_goal(axis, value)))
                    .collect();
                for (axis, goal) in goals {
                    self.loop_starts(axis, sls::MOVING, Some(goal));
                }
                if legs.len() >= 2 && self.global.interpolate {
                    let lead = legs
                        .iter()
                        .max_by_key(|&&(_, _, d)| d.abs())
                        .map_or(Axis::X, |&(a, _, _)| a);
                    let ramps = self.global_ramps(lead);
                    self.launch_group(Group::new(Path::linear(legs), ramps, None));
                } else {
                    for (axis, from, distance) in legs {
                        let ramps = self.axis_ramps(axis);
                        let purpose = Purpose::Position {
                            start_counter: self.counter(axis),
                        };
                        let dir = if distance < 0 { -1 } else { 1 };
                        let run =
                            Run::new(from, dir, ramps, Goal::Target(from + distance), purpose);
                        if distance == 0 {
                            // Already there: the move ends as it starts, so the
                            // axis is never seen busy with MST reading 0.
                            self.finish(axis, Some(&run), true);
                        } else {
                            self.launch(axis, run);
                        }
                    }
                }
            }
            Start::Home {
                axis,
                direction,
                mode,
            } => {
                let Some(procedure) = homing::procedure(mode) else {
                    return Err(Refusal::Moving);
                };
                self.launch_procedure(axis, direction, procedure);
            }
            Start::ZMove { axis, direction } => {
                self.launch_procedure(axis, direction, &homing::Z_MOVE);
            }
            Start::Arc {
                axes,
                rotation,
                centre,
                end_mdeg,
                helix_z,
            } => {
                let group = self.arc_group(axes, rotation, centre, end_mdeg, helix_z, None)?;
                for (axis, end) in group.path.positions(group.path.length()) {
                    let goal = self.loop_goal_at(axis, end);
                    self.loop_starts(axis, sls::MOVING, Some(goal));
                }
                self.launch_group(group);
            }
        }
        Ok(())
    }

    fn launch_procedure(
        &mut self,
        axis: Axis,
        direction: Direction,
        procedure: &'static homing::Procedure,
    ) {
        let ramps = self.axis_ramps(axis);
        let position = self.axis(axis).position;
        let purpose = Purpose::Procedure(ProcedureRun {
            procedure,
            home_dir: sign(direction),
            leg: 0,
            braking: false,
            index_seen: 0,
            seen_on: false,
            returning: false,
        });
        let run = Run::new(position, sign(direction), ramps, Goal::Endless, purpose);
        // Table 27: ZMOVE is Z-homing, modes on an end limit limit homing.
        let code = if procedure.mode == homing::Z_MOVE.mode {
            sls::Z_HOMING
        } else if procedure.uses_limit {
            sls::LIMIT_HOMING
        } else {
            sls::HOMING
        };
        self.loop_starts(axis, code, None);
        self.launch(axis, run);
    }

    fn arc_group(
        &self,
        axes: (Axis, Axis),
        rotation: Rotation,
        centre: (i64, i64),
        end_mdeg: Option<i64>,
        helix_z: Option<i64>,
        buffered_speed: Option<f64>,
    ) -> Result<Group, Refusal> {
        // With StepNLoop on, the centre and Z are encoder positions: the
        // circle is laid in pulses from where the encoder is.
        let centre = (
            self.counter_value(axes.0, centre.0),
            self.counter_value(axes.1, centre.1),
        );
        let helix_z = helix_z.map(|z| self.counter_value(Axis::Z, z));
        let from = (self.counter(axes.0), self.counter(axes.1));
        // Counters and machine positions differ by an offset: lay the
        // circle in counter space, move in machine space.
        let offsets = (
            self.axis(axes.0).counter_offset,
            self.axis(axes.1).counter_offset,
        );
        let Some(mut arc) = Arc::new(axes, from, centre, rotation, end_mdeg) else {
            // Radius 0 or beyond the largest: "could not be processed".
            return Err(Refusal::Moving);
        };
        arc.centre.0 += offsets.0 as f64;
        arc.centre.1 += offsets.1 as f64;
        let mut helpers = Vec::new();
        if let Some(z) = helix_z {
            let zaxis = self.axis(Axis::Z);
            arc.helix = Some((zaxis.position, z - zaxis.counter()));
            helpers.push(Axis::U);
        }
        let ramps = self.global_ramps(axes.0);
        let mut group = Group::new(Path::Arc(arc), ramps, buffered_speed);
        group.helpers = helpers;
        Ok(group)
    }

    fn launch(&mut self, axis: Axis, mut run: Run) {
        let a = &mut self.axes[axis.index()];
        a.levels = a.levels_at(a.position);
        a.waiting_for_inp = false;
        if a.slowdown_enabled() && a.levels.slowdown {
            // Started on the slow-down cam: run at LSPD (A.1 operation 2).
            run.slowed = true;
            let low = run.ramps.low;
            run.plan(a.position, low, true);
        }
        a.rate = run.speed();
        a.phase = run.phase();
        self.activity[axis.index()] = Activity::Run(Box::new(run));
    }

    fn launch_group(&mut self, group: Group) -> u64 {
        let id = self.next_group;
        self.next_group += 1;
        let (phase, rates) = (group.phase(), group.rates());
        for axis in group.members() {
            let a = &mut self.axes[axis.index()];
            a.levels = a.levels_at(a.position);
            a.waiting_for_inp = false;
            a.phase = phase;
            a.rate = rates
                .iter()
                .find(|(m, _)| *m == axis)
                .map_or(0.0, |&(_, r)| r);
            self.activity[axis.index()] = Activity::Group(id);
        }
        self.groups.push((id, group));
        id
    }

    /// `STOP` (`None`) or `STOP[axis]`: decelerate to LSPD and stop; every
    /// axis of an interpolation stops with it (§2.2.3).
    pub fn stop(&mut self, name: Option<Axis>) {
        let axes: Vec<Axis> = name.map_or_else(|| Axis::ALL.to_vec(), |a| vec![a]);
        for axis in axes {
            let holders = self.holders(axis);
            self.loop_note(&holders, sls::STOPPING);
            let position = self.axes[axis.index()].position;
            match &mut self.activity[axis.index()] {
                Activity::Run(run) => run.stop(position),
                Activity::Group(id) => {
                    let id = *id;
                    if Some(id) == self.buffer_group {
                        self.buffer.started = false;
                    }
                    if let Some((_, group)) = self.groups.iter_mut().find(|(g, _)| *g == id)
                        && !group.halting
                    {
                        group.stop();
                    }
                }
                Activity::WaitInp | Activity::Idle => {}
            }
        }
        if name.is_none() {
            self.start_queue.clear();
            self.clear_waiting();
        }
    }

    /// `ABORT` (`None`) or `ABORT[axis]`: stop at once (§2.2.3).
    pub fn abort(&mut self, name: Option<Axis>) {
        let axes: Vec<Axis> = name.map_or_else(|| Axis::ALL.to_vec(), |a| vec![a]);
        for axis in axes {
            // The stop is at once: SLS 4 shows until the next tick.
            let holders = self.holders(axis);
            self.loop_note(&holders, sls::ABORTING);
            self.halt(axis);
        }
        if name.is_none() {
            self.start_queue.clear();
            self.clear_waiting();
        }
    }

    fn clear_waiting(&mut self) {
        for a in &mut self.axes {
            a.waiting_for_start = false;
        }
    }

    /// Stop `axis` (and its interpolation) at once; the axes that were in
    /// motion.
    fn halt(&mut self, axis: Axis) -> Vec<Axis> {
        let members = self.holders(axis);
        if let Activity::Group(id) = self.activity[axis.index()] {
            if Some(id) == self.buffer_group {
                self.buffer.started = false;
                self.buffer_group = None;
            }
            self.groups.retain(|(g, _)| *g != id);
        }
        for &m in &members {
            self.settle(m);
        }
        members
    }

    /// The axes the motion of `axis` holds: itself, or its interpolation.
    fn holders(&self, axis: Axis) -> Vec<Axis> {
        match &self.activity[axis.index()] {
            Activity::Idle => Vec::new(),
            Activity::Run(_) | Activity::WaitInp => vec![axis],
            Activity::Group(id) => self
                .groups
                .iter()
                .find(|(g, _)| g == id)
                .map(|(_, g)| g.members())
                .unwrap_or_default(),
        }
    }

    /// The axis stands still and is free.
    fn settle(&mut self, axis: Axis) {
        self.activity[axis.index()] = Activity::Idle;
        let a = &mut self.axes[axis.index()];
        a.rate = 0.0;
        a.phase = None;
        a.waiting_for_inp = false;
        if a.loop_state.start.is_some() {
            // The target is where the pulses stopped; a move that completes
            // takes its goal back (finish).
            a.loop_state.target = a.loop_target();
            let state = &mut a.loop_state;
            state.start = None;
            // ABORT's code lasts until the next tick (end_aborts).
            if !state.in_error() && state.status != sls::ABORTING {
                state.status = sls::IDLE;
            }
        }
    }

    /// A positioning move of a StepNLoop axis ended: in position, a
    /// correction move, or an error (Table 2-26). True if a correction
    /// started.
    fn verify_position(&mut self, axis: Axis) -> bool {
        let a = &mut self.axes[axis.index()];
        if !a.step_n_loop.enabled {
            return false;
        }
        let delta = a.loop_state.target - a.encoder();
        match step_n_loop::verdict(&a.step_n_loop, delta, a.loop_state.tries) {
            Verdict::InPosition => false,
            Verdict::RangeError => {
                a.loop_state.status = sls::RANGE_ERROR;
                false
            }
            Verdict::AttemptError => {
                a.loop_state.status = sls::ATTEMPT_ERROR;
                false
            }
            Verdict::Correct => {
                let tries = a.loop_state.tries + 1;
                let pulses = (delta as f64 * a.step_n_loop.pulses_per_count()).round() as i64;
                a.loop_state.status = sls::CORRECTING;
                a.loop_state.tries = tries;
                a.loop_state.start = Some((a.counter(), a.encoder()));
                let from = a.position;
                let purpose = Purpose::Position {
                    start_counter: a.counter(),
                };
                let ramps = self.axis_ramps(axis);
                let dir = if pulses < 0 { -1 } else { 1 };
                let run = Run::new(from, dir, ramps, Goal::Target(from + pulses), purpose);
                self.launch(axis, run);
                true
            }
        }
    }

    /// Stall detection: a StepNLoop axis in motion whose encoder is further
    /// than SLE from the real-time target stops (Table 2-26, SLS 10).
    fn watch_loops(&mut self) {
        for axis in Axis::ALL {
            let a = &self.axes[axis.index()];
            if !a.step_n_loop.enabled || a.loop_state.start.is_none() || !self.is_busy(axis) {
                continue;
            }
            if a.deviation().abs() > a.step_n_loop.error_range {
                self.halt(axis);
                self.axes[axis.index()].loop_state.status = sls::STALL_ERROR;
            }
        }
    }

    /// `ESTOP` or /CEMG going low: every axis stops at once; those that were
    /// moving get the EMG error flag unless IERR=1 (§2.1.3.1.2).
    pub fn emergency_stop(&mut self) {
        self.buffer.started = false;
        self.start_queue.clear();
        self.clear_waiting();
        for axis in Axis::ALL {
            let moving = matches!(
                self.activity[axis.index()],
                Activity::Run(_) | Activity::Group(_)
            );
            let mut stopped = self.halt(axis);
            // An axis under joystick control stops too (it is no Run): it
            // stays still until the stick is back in its dead band.
            let a = &mut self.axes[axis.index()];
            let joystick = a.manual_control && !moving && (a.rate != 0.0 || a.phase.is_some());
            if joystick {
                a.rate = 0.0;
                a.phase = None;
                a.joystick_held = true;
                stopped.push(axis);
            }
            if (moving || joystick) && !self.global.ignore_errors {
                for m in stopped {
                    self.axes[m.index()].errors |= mst::EMG_ERROR;
                    if self.axes[m.index()].settings.erc & 1 != 0 {
                        self.axes[m.index()].pulse_erc();
                    }
                }
            }
        }
    }

    /// `SSPD[axis]=speed` (§2.4.1).
    pub fn change_speed(&mut self, name: Axis, speed: u32) -> Result<(), Refusal> {
        if self.buffer.enabled {
            return Err(Refusal::BufferEnabled);
        }
        let a = self.axis(name);
        let window = profile::window_for_sspdm(a.settings.sspdm).ok_or(Refusal::SpeedWindow)?;
        // With StepNLoop on a single-axis speed is in encoder counts/s; the
        // window is in pulses/s (App. B note: EPS = PPS / ratio).
        let pps = if a.step_n_loop.enabled {
            (f64::from(speed) * a.step_n_loop.pulses_per_count()).round()
        } else {
            f64::from(speed)
        };
        if a.settings.s_curve
            || pps < f64::from(window.min_lspd)
            || pps > f64::from(window.max_speed)
        {
            return Err(Refusal::SpeedWindow);
        }
        let position = a.position;
        match &mut self.activity[name.index()] {
            Activity::Run(run) if run.accepts_override(false) => {
                run.change_speed(position, pps);
                Ok(())
            }
            _ => Err(Refusal::OverrideFailed),
        }
    }

    /// `T[axis]target` (§2.4.2): ABS absolute, INC from the move's start;
    /// with StepNLoop on, in encoder counts like any target (§2.5.3).
    pub fn change_target(&mut self, name: Axis, target: i64) -> Result<(), Refusal> {
        let incremental = self.global.incremental;
        let a = &mut self.axes[name.index()];
        let position = a.position;
        match &mut self.activity[name.index()] {
            Activity::Run(run) if run.accepts_override(true) => {
                let Purpose::Position { start_counter } = run.purpose else {
                    return Err(Refusal::OverrideFailed);
                };
                let machine = if a.step_n_loop.enabled && a.loop_state.start.is_some() {
                    let goal = if incremental {
                        a.loop_state.origin.saturating_add(target)
                    } else {
                        target
                    };
                    let counts = goal.saturating_sub(a.loop_target()) as f64;
                    a.loop_state.target = goal;
                    position
                        .saturating_add((counts * a.step_n_loop.pulses_per_count()).round() as i64)
                } else {
                    let counter = if incremental {
                        start_counter + target
                    } else {
                        target
                    };
                    a.machine_for_counter(counter)
                };
                run.change_target(position, machine);
                Ok(())
            }
            _ => Err(Refusal::OverrideFailed),
        }
    }

    // ---- the buffer ---------------------------------------------------

    /// `BO` / `BF`. Turning it off stops feeding and drops what is queued;
    /// the move in progress ends normally.
    pub fn set_buffer(&mut self, on: bool) {
        self.buffer.enabled = on;
        if !on {
            self.buffer.started = false;
            self.buffer.queue.clear();
            self.buffer.head = 0;
        }
    }

    pub fn buffer_status(&self) -> BufferStatus {
        self.buffer.status()
    }

    /// `I…`, or a circle or arc while buffer mode is on.
    pub fn buffer_push(&mut self, mut entry: BufferedMove) -> Result<(), Refusal> {
        if !self.buffer.enabled {
            return Err(Refusal::BufferDisabled);
        }
        if self.buffer.queue.len() >= BUFFER_SIZE {
            return Err(Refusal::BufferFull);
        }
        if let BufferedMove::Linear { target, .. } = &mut entry
            && self.global.incremental
        {
            // Relative to where the previous queued move ends.
            let base = self.buffer_end_point();
            for (t, b) in target.iter_mut().zip(base) {
                *t += b;
            }
        }
        self.buffer.queue.push_back(entry);
        Ok(())
    }

    /// The X, Y, Z counters where the queued moves leave the axes (linear
    /// moves only; a queued arc leaves them where it started).
    fn buffer_end_point(&self) -> [i64; 3] {
        let mut point = [
            self.counter(Axis::X),
            self.counter(Axis::Y),
            self.counter(Axis::Z),
        ];
        for entry in &self.buffer.queue {
            if let BufferedMove::Linear { target, .. } = entry {
                point = *target;
            }
        }
        point
    }

    /// `BSTART`.
    pub fn buffer_start(&mut self) -> Result<(), Refusal> {
        if !self.buffer.enabled {
            return Err(Refusal::BufferDisabled);
        }
        if self.buffer_step_n_loop() {
            return Err(Refusal::StepNLoop);
        }
        if self.buffer_group.is_none() {
            for axis in [Axis::X, Axis::Y, Axis::Z] {
                if self.is_busy(axis) || self.axis(axis).errors & mst::BLOCKING_ERRORS != 0 {
                    return Err(Refusal::Moving);
                }
            }
            if self.emg_input {
                return Err(Refusal::Estop);
            }
        }
        self.buffer.started = true;
        self.feed_buffer();
        Ok(())
    }

    /// "The buffered move operation cannot be used while StepNLoop is
    /// enabled" (§2.3.4) on an axis the buffer drives.
    fn buffer_step_n_loop(&self) -> bool {
        [Axis::X, Axis::Y, Axis::Z]
            .iter()
            .any(|&a| self.axis(a).step_n_loop.enabled)
    }

    /// Start the next buffered move if the buffer runs and nothing it fed
    /// is moving.
    fn feed_buffer(&mut self) {
        if self.buffer_step_n_loop() {
            // SL turned on while the buffer ran: it stops feeding.
            self.buffer.started = false;
        }
        while self.buffer.started && self.buffer_group.is_none() {
            let Some(entry) = self.buffer.pop() else {
                return;
            };
            let group = match entry {
                BufferedMove::Linear { target, speed } => {
                    let legs = [Axis::X, Axis::Y, Axis::Z]
                        .into_iter()
                        .zip(target)
                        .map(|(axis, t)| (axis, self.axis(axis).position, t - self.counter(axis)))
                        .collect();
                    Ok(Group::new(
                        Path::linear(legs),
                        self.global_ramps(Axis::X),
                        Some(f64::from(speed.max(1))),
                    ))
                }
                BufferedMove::Arc {
                    axes,
                    rotation,
                    centre,
                    end_mdeg,
                    helix_z,
                    speed,
                } => self.arc_group(
                    axes,
                    rotation,
                    centre,
                    end_mdeg,
                    helix_z,
                    Some(f64::from(speed.max(1))),
                ),
            };
            match group {
                Ok(group) if group.path.length() > 0.0 => {
                    let busy = group.members().iter().any(|&a| self.is_busy(a));
                    if busy {
                        self.buffer.started = false;
                        return;
                    }
                    self.buffer_group = Some(self.launch_group(group));
                }
                // Nothing to do for this one (already there, or no circle).
                _ => {}
            }
        }
    }

    // ---- time ---------------------------------------------------------

    /// Let `dt` of virtual time pass.
    pub fn advance(&mut self, dt: Duration) {
        self.pending += dt;
        if self.pending >= TICK {
            self.end_aborts();
        }
        while self.pending >= TICK {
            self.pending -= TICK;
            if self.idle() {
                // Nothing moves and no output pulse runs: whole ticks
                // change nothing.
                self.pending =
                    Duration::from_nanos((self.pending.as_nanos() % TICK.as_nanos()) as u64);
                break;
            }
            self.tick();
        }
    }

    /// An aborted StepNLoop axis is idle from the tick after ABORT.
    fn end_aborts(&mut self) {
        for (i, a) in self.axes.iter_mut().enumerate() {
            if a.loop_state.status == sls::ABORTING && self.activity[i] == Activity::Idle {
                a.loop_state.status = sls::IDLE;
            }
        }
    }

    fn idle(&self) -> bool {
        self.activity.iter().all(|a| *a == Activity::Idle)
            && self.axes.iter().all(|a| a.erc.is_none())
            && self.groups.is_empty()
    }

    fn tick(&mut self) {
        let ierr = self.global.ignore_errors;
        // Pulses started during this tick last at least until the next one.
        for axis in &mut self.axes {
            axis.run_erc(TICK);
        }
        // ALM stops a moving axis at once (§2.1.2.2).
        for axis in Axis::ALL {
            let moving = matches!(
                self.activity[axis.index()],
                Activity::Run(_) | Activity::Group(_)
            );
            if moving && self.axes[axis.index()].inputs.alarm {
                let stopped = self.halt(axis);
                let a = &mut self.axes[axis.index()];
                if !ierr {
                    a.errors |= mst::ALARM_ERROR;
                }
                self.error_stop(&stopped);
            }
        }
        let counters_before: [(i64, i64); 4] =
            std::array::from_fn(|i| (self.axes[i].counter(), self.axes[i].encoder()));
        for axis in Axis::ALL {
            let i = axis.index();
            if !matches!(self.activity[i], Activity::Run(_)) {
                continue;
            }
            let Activity::Run(mut run) = std::mem::replace(&mut self.activity[i], Activity::Idle)
            else {
                continue;
            };
            let outcome = run.tick(&mut self.axes[i], ierr);
            let a = &mut self.axes[i];
            match outcome {
                Outcome::Running => {
                    a.rate = run.speed();
                    a.phase = run.phase();
                    self.activity[i] = Activity::Run(run);
                }
                Outcome::Completed => {
                    let targeted = matches!(run.purpose, Purpose::Position { .. });
                    self.finish(axis, Some(&run), targeted);
                }
                Outcome::Stopped => self.settle(axis),
                Outcome::LimitStop => {
                    self.settle(axis);
                    self.loop_limit_error(&[axis]);
                    self.error_stop(&[axis]);
                }
            }
        }
        let mut index = 0;
        while index < self.groups.len() {
            let (id, group) = &mut self.groups[index];
            let id = *id;
            let outcome = group.tick(&mut self.axes, ierr);
            match outcome {
                GroupOutcome::Running => {
                    let phase = group.phase();
                    let rates = group.rates();
                    for member in group.members() {
                        let a = &mut self.axes[member.index()];
                        a.phase = phase;
                        a.rate = rates
                            .iter()
                            .find(|(m, _)| *m == member)
                            .map_or(0.0, |&(_, r)| r);
                    }
                    index += 1;
                }
                other => {
                    let (_, group) = self.groups.remove(index);
                    let members = group.members();
                    let buffered = self.buffer_group == Some(id);
                    if buffered {
                        self.buffer_group = None;
                    }
                    match other {
                        GroupOutcome::Completed => {
                            // Every StepNLoop member is verified on its own.
                            for &m in &members {
                                self.finish(m, None, !group.buffered);
                            }
                            if buffered {
                                self.feed_buffer();
                            }
                        }
                        GroupOutcome::LimitStop => {
                            if buffered {
                                self.buffer.started = false;
                            }
                            for &m in &members {
                                self.settle(m);
                            }
                            self.loop_limit_error(&members);
                            self.error_stop(&members);
                        }
                        _ => {
                            for &m in &members {
                                self.settle(m);
                            }
                        }
                    }
                }
            }
        }
        for (i, axis) in self.axes.iter_mut().enumerate() {
            if axis.waiting_for_inp && axis.inputs.in_position {
                axis.waiting_for_inp = false;
                self.activity[i] = Activity::Idle;
            }
            let (p0, e0) = counters_before[i];
            let (from, to) = if axis.sync.uses_encoder() {
                (e0, axis.encoder())
            } else {
                (p0, axis.counter())
            };
            axis.sync.compare(from, to);
        }
        self.watch_loops();
    }

    /// An error stop of these axes: ERC pulse where ERC bit 0 asks for it
    /// (T2-13).
    fn error_stop(&mut self, axes: &[Axis]) {
        for &axis in axes {
            let a = &mut self.axes[axis.index()];
            if a.settings.erc & 1 != 0 {
                a.pulse_erc();
            }
        }
    }

    /// A motion ended normally: position verification of a `targeted`
    /// move, homing completion actions, then wait for INP if asked
    /// (§2.1.6.2).
    fn finish(&mut self, axis: Axis, run: Option<&Run>, targeted: bool) {
        let state = self.axes[axis.index()].loop_state;
        self.settle(axis);
        // Only a move the loop followed from its start is verified.
        let followed = state.start.is_some()
            && matches!(state.status, sls::MOVING | sls::CORRECTING)
            && self.axes[axis.index()].step_n_loop.enabled;
        if targeted && followed {
            // The goal, not where the pulses rounded to.
            self.axes[axis.index()].loop_state.target = state.target;
            if self.verify_position(axis) {
                return;
            }
        }
        let a = &mut self.axes[axis.index()];
        if let Some(Purpose::Procedure(p)) = run.map(|r| &r.purpose)
            && p.procedure.mode != homing::Z_MOVE.mode
            && a.settings.erc & 2 != 0
        {
            a.pulse_erc();
            if p.procedure.uses_limit {
                // A.7 note: ERC clears the limit flag in the homing direction.
                a.errors &= !if p.home_dir > 0 {
                    mst::PLUS_LIMIT_ERROR
                } else {
                    mst::MINUS_LIMIT_ERROR
                };
            }
        }
        if a.settings.inp && !a.inputs.in_position {
            a.waiting_for_inp = true;
            self.activity[axis.index()] = Activity::WaitInp;
        }
    }

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
