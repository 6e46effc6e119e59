//! A single-axis motion: jog (§2.2.2), positioning (§2.2.4), homing and
//! Z-move (§2.2.5, Appendix A), with the slow-down input (§2.1.3.1.1.2),
//! on-the-fly speed and target changes (§2.4) and stops (§2.2.3).
//!
//! A run is a [`Profile`] laid from an origin in one direction, plus a goal
//! that says what happens when the profile ends. Anything that changes the
//! motion on the way re-plans from the current position and speed.

use super::axis::{AxisState, mst};
use super::homing::{Procedure, Speed, Then, Trigger, Way};
use super::profile::{self, PhaseKind, Profile, Ramps};
use super::stage::Mark;

/// Seconds of virtual time per tick.
pub(super) const TICK_SECONDS: f64 = 1e-4;

/// Where a run is heading.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Goal {
    /// A machine position to stop on.
    Target(i64),
    /// On until told otherwise (jog, homing legs).
    Endless,
    /// Stop when the profile ends.
    Halt,
}

/// What the run is for.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Purpose {
    Jog,
    /// A positioning move; the counter where it started, for `T` in INC
    /// mode ("relative to the original move start point", §2.4.2).
    Position {
        start_counter: i64,
    },
    Procedure(ProcedureRun),
    /// Braking after STOP: no completion actions.
    Stopping,
}

/// Progress through a homing procedure or Z-move.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct ProcedureRun {
    pub procedure: &'static Procedure,
    /// +1 or −1: the commanded direction.
    pub home_dir: i64,
    pub leg: usize,
    /// The leg's trigger fired and the axis brakes before the next leg.
    pub braking: bool,
    pub index_seen: u8,
    /// For HomeOff/LimitOff: the input has been on during this leg.
    pub seen_on: bool,
    /// Modes 9..12: on the way back to counter 0.
    pub returning: bool,
}

/// What a tick did to a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Outcome {
    Running,
    /// Reached its goal normally (INP wait, homing completion).
    Completed,
    /// Stopped by STOP or the slow-down stop: nothing more to do.
    Stopped,
    /// Stopped by an end limit: error latched, ERC pulse.
    LimitStop,
}

/// A single-axis motion.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Run {
    pub profile: Profile,
    pub ticks: u64,
    /// Machine position where the profile started.
    pub origin: i64,
    /// +1 or −1.
    pub dir: i64,
    pub ramps: Ramps,
    /// The speed to cruise at (HSPD, or what SSPD set).
    pub cruise: f64,
    /// The slow-down input holds the axis at LSPD.
    pub slowed: bool,
    pub goal: Goal,
    pub purpose: Purpose,
}

impl Run {
    /// A run from standstill at `position`.
    pub fn new(position: i64, dir: i64, ramps: Ramps, goal: Goal, purpose: Purpose) -> Run {
        let mut run = Run {
            profile: Profile::empty(),
            ticks: 0,
            origin: position,
            dir,
            cruise: ramps.high,
            ramps,
            slowed: false,
            goal,
            purpose,
        };
        run.plan(position, run.ramps.low, true);
        run
    }

    fn elapsed(&self) -> f64 {
        self.ticks as f64 * TICK_SECONDS
    }

    /// Current speed, pps.
    pub fn speed(&self) -> f64 {
        let t = self.elapsed();
        if self.profile.finished_at(t) {
            self.profile.final_speed()
        } else {
            self.profile.speed_at(t)
        }
    }

    pub fn phase(&self) -> Option<PhaseKind> {
        self.profile.kind_at(self.elapsed())
    }

    /// The ramps to plan with now.
    fn effective_ramps(&self) -> Ramps {
        let cruise = if self.slowed {
            self.ramps.low
        } else {
            self.cruise
        };
        self.ramps.cruising_at(cruise)
    }

    /// Lay a new profile from `position` at speed `v` towards the goal.
    pub fn plan(&mut self, position: i64, v: f64, fresh: bool) {
        let ramps = self.effective_ramps();
        self.origin = position;
        self.ticks = 0;
        self.profile = match self.goal {
            Goal::Endless => {
                let speed = match &self.purpose {
                    Purpose::Procedure(p) if !self.slowed => {
                        match p.procedure.legs.get(p.leg).map(|l| l.speed) {
                            Some(Speed::Low) => self.ramps.low,
                            _ => ramps.high,
                        }
                    }
                    _ => ramps.high,
                };
                profile::velocity(v, speed, &ramps)
            }
            Goal::Halt => profile::stop(v, &ramps),
            Goal::Target(target) => {
                let remaining = target - position;
                if remaining == 0 {
                    Profile::empty()
                } else if remaining.signum() == self.dir || v <= ramps.low {
                    let moving_on = remaining.signum() == self.dir;
                    self.dir = remaining.signum();
                    let v0 = if moving_on { v } else { ramps.low };
                    profile::positioning(v0, remaining.abs() as f64, &ramps, fresh)
                } else {
                    // Heading away from the target: brake, then come back.
                    profile::stop(v, &ramps)
                }
            }
        };
    }

    /// The carriage moved by `delta` under the run (lost steps): the rest
    /// of the run follows from there.
    pub fn shift(&mut self, delta: i64) {
        self.origin += delta;
        if let Goal::Target(target) = &mut self.goal {
            *target += delta;
        }
    }

    /// STOP: brake to LSPD and end.
    pub fn stop(&mut self, position: i64) {
        let v = self.speed();
        self.goal = Goal::Halt;
        self.purpose = Purpose::Stopping;
        self.plan(position, v, false);
    }

    /// SSPD: cruise at `speed` from now on (§2.4.1).
    pub fn change_speed(&mut self, position: i64, speed: f64) {
        let v = self.speed();
        self.cruise = speed;
        self.plan(position, v, false);
    }

    /// T: head for a new machine target (§2.4.2).
    pub fn change_target(&mut self, position: i64, target: i64) {
        let v = self.speed();
        self.goal = Goal::Target(target);
        self.plan(position, v, false);
    }

    /// Whether SSPD and T may act now: a jog or positioning move not in
    /// its final deceleration ("while operating at HSPD (not
    /// decelerating)", §2.4.1, §2.4.2).
    pub fn accepts_override(&self, target_change: bool) -> bool {
        let decelerating = self.phase() == Some(PhaseKind::Decelerating);
        match self.purpose {
            Purpose::Jog => !target_change && !decelerating,
            Purpose::Position { .. } => !decelerating,
            Purpose::Procedure(_) | Purpose::Stopping => false,
        }
    }

    /// One tick: move the axis and react to what it passes.
    pub fn tick(&mut self, axis: &mut AxisState, ignore_errors: bool) -> Outcome {
        let old = axis.position;
        self.ticks += 1;
        let t = self.elapsed();
        let finished = self.profile.finished_at(t);
        let travelled = if finished {
            self.profile.length().round()
        } else {
            (self.profile.distance_at(t) + 1e-9).floor()
        };
        let sent = self.origin + self.dir * travelled as i64;
        // A slipping motor goes that much less far; the rest of the run
        // follows from where it is.
        let missed = axis.slip_tick(old, sent);
        self.shift(-missed);
        let new = sent - missed;
        // An end stop holds the carriage; the pulses past it are lost as
        // missed ones are: P counts them, the carriage and encoder don't.
        let held = axis.stage.within_stops(new);
        let lost = new - held;
        axis.counter_offset -= lost;
        self.shift(-lost);
        let new = held;
        axis.position = new;
        for (at, mark) in marks(axis, old, new) {
            match self.on_mark(axis, at, mark, ignore_errors) {
                Reaction::Continue => {}
                Reaction::StopAt(outcome) => {
                    axis.position = at;
                    axis.levels = axis.levels_at(at);
                    return outcome;
                }
                Reaction::NextLegFrom => {
                    axis.position = at;
                    axis.levels = axis.levels_at(at);
                    return self.next_leg(axis);
                }
            }
        }
        // A mark may have re-planned: ask the profile now in force.
        if self.profile.finished_at(self.elapsed()) {
            return self.profile_ended(axis);
        }
        Outcome::Running
    }

    /// Whether `mark` is the end limit ahead turning on.
    fn limit_ahead(&self, mark: Mark) -> bool {
        matches!(
            (mark, self.dir > 0),
            (Mark::PlusLimit(true), true) | (Mark::MinusLimit(true), false)
        )
    }

    fn on_mark(
        &mut self,
        axis: &mut AxisState,
        at: i64,
        mark: Mark,
        ignore_errors: bool,
    ) -> Reaction {
        if self.limit_ahead(mark) {
            if !ignore_errors {
                axis.errors |= if self.dir > 0 {
                    mst::PLUS_LIMIT_ERROR
                } else {
                    mst::MINUS_LIMIT_ERROR
                };
            }
            if self.current_trigger() == Some(Trigger::Limit) {
                return self.fire(axis, at);
            }
            return Reaction::StopAt(Outcome::LimitStop);
        }
        if let Mark::Slowdown(on) = mark
            && axis.slowdown_enabled()
        {
            if on {
                if axis.settings.sdc == 1 {
                    // SDC=1: decelerate and stop, flag bit 17.
                    axis.errors |= mst::SLOWDOWN_STOP;
                    self.stop(axis.position);
                } else if !self.slowed {
                    self.slowed = true;
                    let v = self.speed();
                    self.plan(axis.position, v, false);
                }
            } else if self.slowed && !axis.slowdown_latched() {
                self.slowed = false;
                let v = self.speed();
                self.plan(axis.position, v, false);
            }
            return Reaction::Continue;
        }
        let Some(trigger) = self.current_trigger() else {
            return Reaction::Continue;
        };
        let Purpose::Procedure(p) = &mut self.purpose else {
            return Reaction::Continue;
        };
        let behind_limit_off = matches!(
            (mark, self.dir > 0),
            (Mark::MinusLimit(false), true) | (Mark::PlusLimit(false), false)
        );
        let fires = match (trigger, mark) {
            (Trigger::HomeOn, Mark::Home(true)) => true,
            (Trigger::HomeOff, Mark::Home(true)) => {
                p.seen_on = true;
                false
            }
            (Trigger::HomeOff, Mark::Home(false)) => p.seen_on,
            (Trigger::LimitOff, _) => behind_limit_off,
            (Trigger::Index, Mark::Index) => {
                p.index_seen = p.index_seen.saturating_add(1);
                p.index_seen > axis.settings.zcnt
            }
            _ => false,
        };
        if fires {
            self.fire(axis, at)
        } else {
            Reaction::Continue
        }
    }

    /// The trigger of the current homing leg, if one is awaited.
    fn current_trigger(&self) -> Option<Trigger> {
        match &self.purpose {
            Purpose::Procedure(p) if !p.braking && !p.returning => {
                p.procedure.legs.get(p.leg).map(|l| l.until)
            }
            _ => None,
        }
    }

    /// The current leg's trigger fired at `at`.
    fn fire(&mut self, axis: &mut AxisState, at: i64) -> Reaction {
        let Purpose::Procedure(p) = &mut self.purpose else {
            return Reaction::Continue;
        };
        let Some(leg) = p.procedure.legs.get(p.leg).copied() else {
            return Reaction::Continue;
        };
        if leg.zero {
            axis.zero_at(at);
        }
        match leg.then {
            Then::Stop => Reaction::NextLegFrom,
            Then::Decelerate => {
                p.braking = true;
                self.goal = Goal::Halt;
                let v = self.speed();
                self.plan(axis.position, v, false);
                Reaction::Continue
            }
            Then::SlowDown | Then::Pass => {
                p.leg += 1;
                p.index_seen = 0;
                if leg.then == Then::SlowDown {
                    let v = self.speed();
                    self.plan(axis.position, v, false);
                }
                Reaction::Continue
            }
        }
    }

    /// The axis stands still after a leg: start the next one, return to
    /// zero, or finish.
    fn next_leg(&mut self, axis: &mut AxisState) -> Outcome {
        let Purpose::Procedure(p) = &mut self.purpose else {
            return Outcome::Completed;
        };
        p.leg += 1;
        p.braking = false;
        p.index_seen = 0;
        if let Some(leg) = p.procedure.legs.get(p.leg).copied() {
            self.dir = p.home_dir
                * match leg.way {
                    Way::Forward => 1,
                    Way::Reverse => -1,
                };
            let levels = axis.levels_at(axis.position);
            p.seen_on = match leg.until {
                Trigger::HomeOff => levels.home,
                _ => false,
            };
            self.goal = Goal::Endless;
            let low = self.ramps.low;
            self.plan(axis.position, low, true);
            return Outcome::Running;
        }
        if p.procedure.return_to_zero && !p.returning {
            p.returning = true;
            self.goal = Goal::Target(axis.machine_for_counter(0));
            let low = self.ramps.low;
            self.plan(axis.position, low, true);
            if self.profile.length() == 0.0 {
                return Outcome::Completed;
            }
            return Outcome::Running;
        }
        Outcome::Completed
    }

    fn profile_ended(&mut self, axis: &mut AxisState) -> Outcome {
        match self.goal {
            Goal::Endless => Outcome::Running,
            Goal::Halt => match &self.purpose {
                Purpose::Procedure(p) if p.braking => self.next_leg(axis),
                Purpose::Stopping => Outcome::Stopped,
                _ => Outcome::Completed,
            },
            Goal::Target(target) => {
                if axis.position == target {
                    match &self.purpose {
                        Purpose::Procedure(_) => self.next_leg(axis),
                        _ => Outcome::Completed,
                    }
                } else {
                    // Overshot (stop profile): come back at LSPD.
                    let v = self.speed();
                    self.plan(axis.position, v, false);
                    Outcome::Running
                }
            }
        }
    }
}

/// What a passed mark does to the run.
enum Reaction {
    Continue,
    /// Stop on the mark's position.
    StopAt(Outcome),
    /// Stop on the mark's position and go on with the next homing leg.
    NextLegFrom,
}

/// The marks an axis passes from `old` to `new`: switch edges of its stage
/// (unless forced from outside) and changes of forced inputs, in order.
pub(super) fn marks(axis: &mut AxisState, old: i64, new: i64) -> Vec<(i64, Mark)> {
    let before = axis.levels;
    let now_at_old = axis.levels_at(old);
    let mut out = Vec::new();
    // Forced inputs changed since the last tick: they act where the axis was.
    let forced = [
        (
            axis.inputs.plus_limit.is_some(),
            before.plus_limit,
            now_at_old.plus_limit,
            Mark::PlusLimit as fn(bool) -> Mark,
        ),
        (
            axis.inputs.minus_limit.is_some(),
            before.minus_limit,
            now_at_old.minus_limit,
            Mark::MinusLimit,
        ),
        (
            axis.inputs.home.is_some(),
            before.home,
            now_at_old.home,
            Mark::Home,
        ),
        (
            axis.inputs.slowdown.is_some(),
            before.slowdown,
            now_at_old.slowdown,
            Mark::Slowdown,
        ),
    ];
    for (is_forced, was, is, mark) in forced {
        if is_forced && was != is {
            out.push((old, mark(is)));
        }
    }
    for (at, mark) in axis.stage.marks(old, new) {
        let is_forced = match mark {
            Mark::PlusLimit(_) => axis.inputs.plus_limit.is_some(),
            Mark::MinusLimit(_) => axis.inputs.minus_limit.is_some(),
            Mark::Home(_) => axis.inputs.home.is_some(),
            Mark::Slowdown(_) => axis.inputs.slowdown.is_some(),
            Mark::Index => false,
        };
        if !is_forced {
            out.push((at, mark));
        }
    }
    axis.levels = axis.levels_at(new);
    out
}
