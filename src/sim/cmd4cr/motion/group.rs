//! Coordinated motion (§2.3, Appendix C): several axes following one path
//! with one speed profile, and the 100-register move buffer (§2.3.4).
//!
//! Interpolated moves use the global speed settings (§2.1.4); the profile
//! runs along the path length ([`super::path`]). An error stop of any
//! member stops them all, and the slow-down input of any member slows or
//! stops them all (C.6).
//!
//! Choices where the manual is silent (digest §4.6, §8.3):
//! - A buffered move runs at its own constant speed without ramps ("each
//!   move has its own constant speed"), so consecutive moves join
//!   seamlessly; `I` gives the main-axis speed, a buffered circle or arc
//!   takes the global HSPD at the time it was queued.
//! - `BSTAT` start and end are ring indices (0..99) of the oldest queued
//!   move and of the register the next one goes into.

use std::collections::VecDeque;

use super::axis::{AxisState, mst};
use super::path::Path;
use super::profile::{self, PhaseKind, Profile, Ramps};
use super::run::{TICK_SECONDS, marks};
use super::stage::Mark;
use super::{Axis, Rotation};

/// Buffer registers (§2.3.4).
pub const BUFFER_SIZE: usize = 100;

/// A move waiting in the buffer.
#[derive(Debug, Clone, PartialEq)]
pub enum BufferedMove {
    /// `I x:y:z:speed`: the X, Y, Z targets (absolute or incremental as
    /// `MM` said when queued, resolved then) and the main-axis speed.
    Linear { target: [i64; 3], speed: u32 },
    /// `CIR…`/`ARC…` (and the helical forms), at `speed` along the arc.
    Arc {
        axes: (Axis, Axis),
        rotation: Rotation,
        centre: (i64, i64),
        end_mdeg: Option<i64>,
        helix_z: Option<i64>,
        speed: u32,
    },
}

/// The move buffer.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Buffer {
    pub enabled: bool,
    /// `BSTART` was sent: feed moves as the previous one ends.
    pub started: bool,
    pub(super) queue: VecDeque<BufferedMove>,
    /// Ring index of the oldest queued move.
    pub(super) head: usize,
}

/// `BSTAT`: enabled, start, end, available (§2.3.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BufferStatus {
    pub enabled: bool,
    pub start: usize,
    pub end: usize,
    pub available: usize,
}

impl Buffer {
    pub fn status(&self) -> BufferStatus {
        BufferStatus {
            enabled: self.enabled,
            start: self.head,
            end: (self.head + self.queue.len()) % BUFFER_SIZE,
            available: BUFFER_SIZE - self.queue.len(),
        }
    }

    pub(super) fn pop(&mut self) -> Option<BufferedMove> {
        let next = self.queue.pop_front()?;
        self.head = (self.head + 1) % BUFFER_SIZE;
        Some(next)
    }
}

/// What a tick did to a group.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum GroupOutcome {
    Running,
    Completed,
    Stopped,
    /// A member hit an end limit: all stop at once.
    LimitStop,
}

/// An interpolation under way.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Group {
    pub path: Path,
    pub profile: Profile,
    pub ticks: u64,
    /// Path distance covered when the profile started.
    pub base: f64,
    /// Path distance covered now.
    pub covered: f64,
    pub ramps: Ramps,
    pub cruise: f64,
    pub slowed: bool,
    pub halting: bool,
    /// Fed from the buffer: constant speed.
    pub buffered: bool,
    /// Axes held busy without moving (U during helical moves, C.5).
    pub helpers: Vec<Axis>,
}

impl Group {
    /// A group starting from standstill with ramps, or at constant `speed`
    /// for a buffered move.
    pub fn new(path: Path, ramps: Ramps, buffered_speed: Option<f64>) -> Group {
        let length = path.length();
        let (profile, buffered) = match buffered_speed {
            Some(speed) => (Profile::constant(speed, length), true),
            None => (profile::positioning(ramps.low, length, &ramps, true), false),
        };
        Group {
            path,
            profile,
            ticks: 0,
            base: 0.0,
            covered: 0.0,
            cruise: ramps.high,
            ramps,
            slowed: false,
            halting: false,
            buffered,
            helpers: Vec::new(),
        }
    }

    /// Every axis the group holds.
    pub fn members(&self) -> Vec<Axis> {
        let mut axes = self.path.axes();
        axes.extend(self.helpers.iter().copied());
        axes
    }

    fn elapsed(&self) -> f64 {
        self.ticks as f64 * TICK_SECONDS
    }

    /// Path speed now.
    pub fn speed(&self) -> f64 {
        let t = self.elapsed();
        if self.profile.finished_at(t) {
            0.0
        } else {
            self.profile.speed_at(t)
        }
    }

    pub fn phase(&self) -> Option<PhaseKind> {
        self.profile.kind_at(self.elapsed())
    }

    /// Pulse rate of each moving member.
    pub fn rates(&self) -> Vec<(Axis, f64)> {
        self.path.rates(self.covered, self.speed())
    }

    fn replan(&mut self) {
        let v = self.speed();
        self.base = self.covered;
        self.ticks = 0;
        let cruise = if self.slowed {
            self.ramps.low
        } else {
            self.cruise
        };
        let ramps = self.ramps.cruising_at(cruise);
        self.profile = if self.halting {
            profile::stop(v, &ramps)
        } else if self.buffered {
            Profile::constant(cruise, self.path.length() - self.base)
        } else {
            profile::positioning(v, self.path.length() - self.base, &ramps, false)
        };
    }

    /// STOP: brake along the path.
    pub fn stop(&mut self) {
        self.halting = true;
        self.replan();
    }

    pub fn tick(&mut self, axes: &mut [AxisState; 4], ignore_errors: bool) -> GroupOutcome {
        self.ticks += 1;
        let t = self.elapsed();
        let finished = self.profile.finished_at(t);
        let length = self.path.length();
        let mut covered = self.base
            + if finished {
                self.profile.length()
            } else {
                self.profile.distance_at(t)
            };
        let at_end = covered >= length - 1e-9 || (finished && !self.halting);
        if at_end {
            covered = length;
        }
        self.covered = covered;
        let mut limit_stop = false;
        let mut replan = false;
        for (name, new) in self.path.positions(covered) {
            let Some(axis) = axes.get_mut(name.index()) else {
                continue;
            };
            let old = axis.position;
            // A slipping motor goes that much less far; the rest of the
            // path follows from where it is.
            let missed = axis.slip_tick(old, new);
            self.path.shift(name, -missed);
            let new = new - missed;
            axis.position = new;
            let dir = (new - old).signum();
            for (at, mark) in marks(axis, old, new) {
                match mark {
                    Mark::PlusLimit(true) | Mark::MinusLimit(true)
                        if (mark == Mark::PlusLimit(true)) == (dir > 0) && dir != 0 =>
                    {
                        if !ignore_errors {
                            axis.errors |= if dir > 0 {
                                mst::PLUS_LIMIT_ERROR
                            } else {
                                mst::MINUS_LIMIT_ERROR
                            };
                        }
                        axis.position = at;
                        axis.levels = axis.levels_at(at);
                        limit_stop = true;
                        break;
                    }
                    Mark::Slowdown(on) if axis.slowdown_enabled() && !self.buffered => {
                        if on && axis.settings.sdc == 1 {
                            axis.errors |= mst::SLOWDOWN_STOP;
                            self.halting = true;
                            replan = true;
                        } else if on && !self.slowed {
                            self.slowed = true;
                            replan = true;
                        } else if !on && self.slowed && !axis.slowdown_latched() {
                            self.slowed = false;
                            replan = true;
                        }
                    }
                    _ => {}
                }
            }
        }
        if limit_stop {
            return GroupOutcome::LimitStop;
        }
        if at_end {
            return GroupOutcome::Completed;
        }
        if self.halting && finished {
            return GroupOutcome::Stopped;
        }
        if replan {
            self.replan();
        }
        GroupOutcome::Running
    }
}
