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

pub mod axis;
mod group;
pub mod homing;
pub mod path;
pub mod profile;
mod run;
pub mod stage;
pub mod sync;

#[cfg(test)]
mod tests;

use std::collections::VecDeque;
use std::time::Duration;

use axis::{Axis, mst};
use group::{Group, GroupOutcome};
use path::{Arc, Path, Turn};
use profile::{PhaseKind, Ramps, Shape};
use run::{Goal, Outcome, ProcedureRun, Purpose, Run};
use stage::Stage;

pub use group::{BUFFER_SIZE, BufferStatus, BufferedMove};

/// The engine's time step.
pub const TICK: Duration = Duration::from_micros(100);

/// One of the four axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum AxisName {
    X,
    Y,
    Z,
    U,
}

impl AxisName {
    pub const ALL: [AxisName; 4] = [AxisName::X, AxisName::Y, AxisName::Z, AxisName::U];

    pub fn index(self) -> usize {
        self as usize
    }

    pub fn letter(self) -> char {
        match self {
            AxisName::X => 'X',
            AxisName::Y => 'Y',
            AxisName::Z => 'Z',
            AxisName::U => 'U',
        }
    }

    pub fn from_letter(letter: char) -> Option<AxisName> {
        AxisName::ALL.into_iter().find(|a| a.letter() == letter)
    }

    /// Axis number n (0..3), as DIn/DOn/EOn pair with axes (T2-3, T2-6).
    pub fn from_index(index: usize) -> Option<AxisName> {
        AxisName::ALL.get(index).copied()
    }
}

/// `+` or `-`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    Plus,
    Minus,
}

impl Direction {
    pub fn sign(self) -> i64 {
        match self {
            Direction::Plus => 1,
            Direction::Minus => -1,
        }
    }

    fn of(delta: i64) -> Option<Direction> {
        match delta.signum() {
            1 => Some(Direction::Plus),
            -1 => Some(Direction::Minus),
            _ => None,
        }
    }
}

/// Why a motion command is not processed: the `?…` replies of T4-41 that
/// the motion engine gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum Refusal {
    #[error("?Error Moving")]
    Moving,
    #[error("?Error Alarm")]
    Alarm,
    #[error("?Error +Limit")]
    PlusLimit,
    #[error("?Error -Limit")]
    MinusLimit,
    #[error("?Error ESTOP")]
    Estop,
    #[error("?Error SNL")]
    StepNLoop,
    #[error("?Buffer Full")]
    BufferFull,
    #[error("?Buffer Disabled")]
    BufferDisabled,
    #[error("?Buffer Enabled")]
    BufferEnabled,
    #[error("?SSPD Error")]
    SpeedWindow,
    #[error("?Override Failed")]
    OverrideFailed,
}

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
    Jog {
        axis: AxisName,
        direction: Direction,
    },
    /// `X…Y…Z…U…`: targets as written (ABS/INC applies when it starts).
    Position { targets: Vec<(AxisName, i64)> },
    /// `H[axis]±mode`.
    Home {
        axis: AxisName,
        direction: Direction,
        mode: u8,
    },
    /// `ZMOVE[axis]±`.
    ZMove {
        axis: AxisName,
        direction: Direction,
    },
    /// `CIR…`, `ARC…`, `CIRT…`, `ARCT…` (centre absolute, §2.3.2).
    Arc {
        axes: (AxisName, AxisName),
        turn: Turn,
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
    axes: [Axis; 4],
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
            AxisName::ALL.map(|name| Axis::new(name, stages.next().unwrap_or_else(Stage::bare)));
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

    pub fn axis(&self, name: AxisName) -> &Axis {
        &self.axes[name.index()]
    }

    pub fn axis_mut(&mut self, name: AxisName) -> &mut Axis {
        &mut self.axes[name.index()]
    }

    /// Whether the axis is busy (moving, in an interpolation, waiting for
    /// INP or held by a helical move).
    pub fn is_busy(&self, name: AxisName) -> bool {
        self.activity[name.index()] != Activity::Idle
    }

    /// Any axis busy, or a move waiting for /CSTA.
    pub fn any_busy(&self) -> bool {
        AxisName::ALL.iter().any(|&a| self.is_busy(a)) || !self.start_queue.is_empty()
    }

    /// `MST[axis]`.
    pub fn status(&self, name: AxisName) -> u32 {
        self.axis(name).status(self.emg_input, self.start_input)
    }

    /// `PS[axis]`, pps.
    pub fn pulse_rate(&self, name: AxisName) -> i64 {
        self.axis(name).rate.round() as i64
    }

    /// `P[axis]`.
    pub fn counter(&self, name: AxisName) -> i64 {
        self.axis(name).counter()
    }

    /// `E[axis]`.
    pub fn encoder(&self, name: AxisName) -> i64 {
        self.axis(name).encoder()
    }

    /// `P[axis]=v`.
    pub fn set_counter(&mut self, name: AxisName, value: i64) {
        self.axis_mut(name).set_counter(value);
    }

    /// `E[axis]=v`.
    pub fn set_encoder(&mut self, name: AxisName, value: i64) {
        self.axis_mut(name).set_encoder(value);
    }

    /// `CLR[axis]`: clear the latched flags (§2.6.2.3).
    pub fn clear_errors(&mut self, name: AxisName) {
        self.axis_mut(name).errors &= !mst::CLEARED_BY_CLR;
    }

    // ---- speed settings ----------------------------------------------

    /// The ramps of a single-axis move: per-axis values unless 0 (§2.1.4).
    fn axis_ramps(&self, name: AxisName) -> Ramps {
        let s = &self.axis(name).settings;
        let g = &self.global;
        let or = |own: u32, global: u32| if own == 0 { global } else { own };
        Ramps::new(
            or(s.lspd, g.lspd),
            or(s.hspd, g.hspd),
            or(s.acc, g.acc),
            or(s.dec, g.dec),
            s.shape(),
        )
    }

    /// The ramps of a coordinated move: always the global values (§2.1.4);
    /// S-curve if the first axis has it.
    fn global_ramps(&self, lead: AxisName) -> Ramps {
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
    pub fn set_alarm(&mut self, name: AxisName, on: bool) {
        self.axis_mut(name).inputs.alarm = on;
    }

    /// The position latch input of `name` rose (DIn, T2-3).
    pub fn latch_input(&mut self, name: AxisName) {
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
            if self.axis(axis).errors & mst::BLOCKING_ERRORS != 0 {
                return Err(Refusal::Moving);
            }
        }
        Ok(())
    }

    /// The axes a command moves, with the direction where it is known.
    fn directions(&self, start: &Start) -> Vec<(AxisName, Option<Direction>)> {
        match start {
            Start::Jog { axis, direction }
            | Start::Home {
                axis, direction, ..
            }
            | Start::ZMove { axis, direction } => vec![(*axis, Some(*direction))],
            Start::Position { targets } => targets
                .iter()
                .map(|&(axis, value)| (axis, Direction::of(self.distance(axis, value))))
                .collect(),
            Start::Arc { axes, helix_z, .. } => {
                let mut v = vec![(axes.0, None), (axes.1, None)];
                if let Some(z) = helix_z {
                    v.push((AxisName::Z, Direction::of(z - self.counter(AxisName::Z))));
                    v.push((AxisName::U, None));
                }
                v
            }
        }
    }

    /// Pulses from the current counter to `value` under ABS/INC.
    fn distance(&self, axis: AxisName, value: i64) -> i64 {
        if self.global.incremental {
            value
        } else {
            value - self.counter(axis)
        }
    }

    /// Start a checked command now.
    fn begin(&mut self, start: Start) -> Result<(), Refusal> {
        match start {
            Start::Jog { axis, direction } => {
                let ramps = self.axis_ramps(axis);
                let position = self.axis(axis).position;
                let run = Run::new(
                    position,
                    direction.sign(),
                    ramps,
                    Goal::Endless,
                    Purpose::Jog,
                );
                self.launch(axis, run);
            }
            Start::Position { targets } => {
                let legs: Vec<(AxisName, i64, i64)> = targets
                    .iter()
                    .map(|&(axis, value)| {
                        (axis, self.axis(axis).position, self.distance(axis, value))
                    })
                    .collect();
                if legs.len() >= 2 && self.global.interpolate {
                    let lead = legs
                        .iter()
                        .max_by_key(|&&(_, _, d)| d.abs())
                        .map_or(AxisName::X, |&(a, _, _)| a);
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
                        self.launch(axis, run);
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
                turn,
                centre,
                end_mdeg,
                helix_z,
            } => {
                let group = self.arc_group(axes, turn, centre, end_mdeg, helix_z, None)?;
                self.launch_group(group);
            }
        }
        Ok(())
    }

    fn launch_procedure(
        &mut self,
        axis: AxisName,
        direction: Direction,
        procedure: &'static homing::Procedure,
    ) {
        let ramps = self.axis_ramps(axis);
        let position = self.axis(axis).position;
        let purpose = Purpose::Procedure(ProcedureRun {
            procedure,
            home_dir: direction.sign(),
            leg: 0,
            braking: false,
            index_seen: 0,
            seen_on: false,
            returning: false,
        });
        let run = Run::new(position, direction.sign(), ramps, Goal::Endless, purpose);
        self.launch(axis, run);
    }

    fn arc_group(
        &self,
        axes: (AxisName, AxisName),
        turn: Turn,
        centre: (i64, i64),
        end_mdeg: Option<i64>,
        helix_z: Option<i64>,
        buffered_speed: Option<f64>,
    ) -> Result<Group, Refusal> {
        let from = (self.counter(axes.0), self.counter(axes.1));
        // Counters and machine positions differ by an offset: lay the
        // circle in counter space, move in machine space.
        let offsets = (
            self.axis(axes.0).counter_offset,
            self.axis(axes.1).counter_offset,
        );
        let Some(mut arc) = Arc::new(axes, from, centre, turn, end_mdeg) else {
            // Radius 0 or beyond the largest: "could not be processed".
            return Err(Refusal::Moving);
        };
        arc.centre.0 += offsets.0 as f64;
        arc.centre.1 += offsets.1 as f64;
        let mut helpers = Vec::new();
        if let Some(z) = helix_z {
            let zaxis = self.axis(AxisName::Z);
            arc.helix = Some((zaxis.position, z - zaxis.counter()));
            helpers.push(AxisName::U);
        }
        let ramps = self.global_ramps(axes.0);
        let mut group = Group::new(Path::Arc(arc), ramps, buffered_speed);
        group.helpers = helpers;
        Ok(group)
    }

    fn launch(&mut self, axis: AxisName, mut run: Run) {
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
        for axis in group.members() {
            let a = &mut self.axes[axis.index()];
            a.levels = a.levels_at(a.position);
            a.waiting_for_inp = false;
            self.activity[axis.index()] = Activity::Group(id);
        }
        self.groups.push((id, group));
        id
    }

    /// `STOP` (`None`) or `STOP[axis]`: decelerate to LSPD and stop; every
    /// axis of an interpolation stops with it (§2.2.3).
    pub fn stop(&mut self, name: Option<AxisName>) {
        let axes: Vec<AxisName> = name.map_or_else(|| AxisName::ALL.to_vec(), |a| vec![a]);
        for axis in axes {
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
    pub fn abort(&mut self, name: Option<AxisName>) {
        let axes: Vec<AxisName> = name.map_or_else(|| AxisName::ALL.to_vec(), |a| vec![a]);
        for axis in axes {
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
    fn halt(&mut self, axis: AxisName) -> Vec<AxisName> {
        let members = match &self.activity[axis.index()] {
            Activity::Idle => return Vec::new(),
            Activity::Run(_) | Activity::WaitInp => vec![axis],
            Activity::Group(id) => {
                let id = *id;
                if Some(id) == self.buffer_group {
                    self.buffer.started = false;
                    self.buffer_group = None;
                }
                let members = self
                    .groups
                    .iter()
                    .find(|(g, _)| *g == id)
                    .map(|(_, g)| g.members())
                    .unwrap_or_default();
                self.groups.retain(|(g, _)| *g != id);
                members
            }
        };
        for &m in &members {
            self.settle(m);
        }
        members
    }

    /// The axis stands still and is free.
    fn settle(&mut self, axis: AxisName) {
        self.activity[axis.index()] = Activity::Idle;
        let a = &mut self.axes[axis.index()];
        a.rate = 0.0;
        a.phase = None;
        a.waiting_for_inp = false;
    }

    /// `ESTOP` or /CEMG going low: every axis stops at once; those that were
    /// moving get the EMG error flag unless IERR=1 (§2.1.3.1.2).
    pub fn emergency_stop(&mut self) {
        self.buffer.started = false;
        self.start_queue.clear();
        self.clear_waiting();
        for axis in AxisName::ALL {
            let moving = matches!(
                self.activity[axis.index()],
                Activity::Run(_) | Activity::Group(_)
            );
            let stopped = self.halt(axis);
            if moving && !self.global.ignore_errors {
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
    pub fn change_speed(&mut self, name: AxisName, speed: u32) -> Result<(), Refusal> {
        if self.buffer.enabled {
            return Err(Refusal::BufferEnabled);
        }
        let a = self.axis(name);
        let window = profile::window_for_sspdm(a.settings.sspdm).ok_or(Refusal::SpeedWindow)?;
        if a.settings.s_curve || speed < window.min_lspd || speed > window.max_speed {
            return Err(Refusal::SpeedWindow);
        }
        let position = a.position;
        match &mut self.activity[name.index()] {
            Activity::Run(run) if run.accepts_override(false) => {
                run.change_speed(position, f64::from(speed));
                Ok(())
            }
            _ => Err(Refusal::OverrideFailed),
        }
    }

    /// `T[axis]target` (§2.4.2): ABS absolute, INC from the move's start.
    pub fn change_target(&mut self, name: AxisName, target: i64) -> Result<(), Refusal> {
        let incremental = self.global.incremental;
        let a = &self.axes[name.index()];
        let position = a.position;
        match &mut self.activity[name.index()] {
            Activity::Run(run) if run.accepts_override(true) => {
                let Purpose::Position { start_counter } = run.purpose else {
                    return Err(Refusal::OverrideFailed);
                };
                let counter = if incremental {
                    start_counter + target
                } else {
                    target
                };
                let machine = a.machine_for_counter(counter);
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
            self.counter(AxisName::X),
            self.counter(AxisName::Y),
            self.counter(AxisName::Z),
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
        if self.buffer_group.is_none() {
            for axis in [AxisName::X, AxisName::Y, AxisName::Z] {
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

    /// Start the next buffered move if the buffer runs and nothing it fed
    /// is moving.
    fn feed_buffer(&mut self) {
        while self.buffer.started && self.buffer_group.is_none() {
            let Some(entry) = self.buffer.pop() else {
                return;
            };
            let group = match entry {
                BufferedMove::Linear { target, speed } => {
                    let legs = [AxisName::X, AxisName::Y, AxisName::Z]
                        .into_iter()
                        .zip(target)
                        .map(|(axis, t)| (axis, self.axis(axis).position, t - self.counter(axis)))
                        .collect();
                    Ok(Group::new(
                        Path::linear(legs),
                        self.global_ramps(AxisName::X),
                        Some(f64::from(speed.max(1))),
                    ))
                }
                BufferedMove::Arc {
                    axes,
                    turn,
                    centre,
                    end_mdeg,
                    helix_z,
                    speed,
                } => self.arc_group(
                    axes,
                    turn,
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
        for axis in AxisName::ALL {
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
        for axis in AxisName::ALL {
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
                    self.finish(axis, Some(&run));
                }
                Outcome::Stopped => self.settle(axis),
                Outcome::LimitStop => {
                    self.settle(axis);
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
                            for &m in &members {
                                self.finish(m, None);
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
    }

    /// An error stop of these axes: ERC pulse where ERC bit 0 asks for it
    /// (T2-13).
    fn error_stop(&mut self, axes: &[AxisName]) {
        for &axis in axes {
            let a = &mut self.axes[axis.index()];
            if a.settings.erc & 1 != 0 {
                a.pulse_erc();
            }
        }
    }

    /// A motion ended normally: homing completion actions, then wait for
    /// INP if asked (§2.1.6.2).
    fn finish(&mut self, axis: AxisName, run: Option<&Run>) {
        self.settle(axis);
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
    pub fn phase(&self, name: AxisName) -> Option<PhaseKind> {
        self.axis(name).phase
    }

    /// The ramps a single-axis move of `name` would use now.
    pub fn ramps_of(&self, name: AxisName) -> Ramps {
        self.axis_ramps(name)
    }

    /// The shape of `name`'s ramps.
    pub fn shape_of(&self, name: AxisName) -> Shape {
        self.axis(name).settings.shape()
    }
}

/// The axes a command holds.
fn start_axes(start: &Start) -> Vec<AxisName> {
    match start {
        Start::Jog { axis, .. } | Start::Home { axis, .. } | Start::ZMove { axis, .. } => {
            vec![*axis]
        }
        Start::Position { targets } => targets.iter().map(|&(a, _)| a).collect(),
        Start::Arc { axes, helix_z, .. } => {
            let mut v = vec![axes.0, axes.1];
            if helix_z.is_some() {
                v.extend([AxisName::Z, AxisName::U]);
            }
            v
        }
    }
}
