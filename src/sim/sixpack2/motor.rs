//! One motor on the firmware's 2 ms tick (digest D5, D6): its velocity
//! register and step generator (§6.3.1), the trapezoidal ramp (§7.1 $13/$14,
//! §6.3.1.1), PI control ($19, $24), rotation ($25), the stop conditions
//! ($15 StopNull/TestNull, $31) and the reference input with its debounce
//! filter ($16). The reference search is in [`super::search`].
//!
//! The velocity register counts in 1/64 units, so that "1/64 amax is
//! accumulated with 500 Hz" (§7.1 $14) is exact; the step generator uses
//! its whole part `v` as the §6.3.1 formula does: f = 20 MHz/(clkdiv + 1)
//! · v / 2^(14 + div). It is a phase accumulator, so the µsteps a tick
//! makes are exact to the clock cycle.

use std::time::Duration;

use super::choices::Choices;
use super::search::{Resume, Search};
use super::settings::{MotorSettings, flag};
use super::stage::Mechanics;

/// The firmware tick: acceleration, the PI loop, T0, debounce and the
/// packet timeout all count it (digest D0).
pub const TICK: Duration = Duration::from_millis(2);

/// The step generator's clock, f_clk of §6.3.1.
pub const CLOCK_HZ: f64 = 20e6;

/// Clock cycles in one tick.
const CLOCKS_PER_TICK: i64 = 40_000;

/// Action codes of $20/$21/$28 (§7.2).
pub mod action {
    pub const INACTIVE: u8 = 0;
    pub const RAMP: u8 = 5;
    pub const PI: u8 = 10;
    pub const ROTATION: u8 = 15;
    pub const MECHANICAL: u8 = 30;
}

/// What a motor's tick needs from the unit.
#[derive(Debug, Clone, Copy)]
pub struct Ticking<'a> {
    pub clkdiv: u8,
    pub choices: &'a Choices,
    /// The driver-enable jumper is fitted (§5.2.6): the motors turn.
    pub drivers_enabled: bool,
}

/// µstep frequency at velocity `v` (§6.3.1).
pub fn microstep_frequency(clkdiv: u8, div: u8, v: f64) -> f64 {
    CLOCK_HZ / f64::from(u32::from(clkdiv) + 1) * v
        / f64::from(1u32 << (14 + u32::from(div.min(3))))
}

/// The step generator's phase for one µstep, in clock cycles × velocity.
fn phase_per_step(clkdiv: u8, div: u8) -> i64 {
    (i64::from(clkdiv) + 1) << (14 + u32::from(div.min(3)))
}

/// µsteps one velocity unit makes in a tick.
pub fn steps_per_tick(clkdiv: u8, div: u8) -> f64 {
    CLOCKS_PER_TICK as f64 / phase_per_step(clkdiv, div) as f64
}

/// µsteps covered while the velocity register falls from `from` to `to`
/// (1/64 units) by `rate` a tick, counting each tick at its new velocity.
fn braking_distance(from: i32, to: i32, rate: i32, per_unit: f64) -> f64 {
    if from <= to {
        return 0.0;
    }
    let (from, to, rate) = (i64::from(from), i64::from(to), i64::from(rate.max(1)));
    // Ticks whose velocity is still above `to`, then one at `to`.
    let above = (from - to + rate - 1) / rate - 1;
    let sum = above * from - rate * above * (above + 1) / 2 + to;
    sum as f64 * per_unit / 64.0
}

/// What the motor is doing.
#[derive(Debug, Clone, PartialEq)]
pub enum Mode {
    Idle,
    /// A trapezoidal ramp to the target; `group` when it leads a $50
    /// interpolation.
    Ramp {
        group: Option<u32>,
    },
    /// Following the lead of a $50 interpolation.
    Follow(Follow),
    Pi,
    Rotation {
        velocity: i32,
    },
    /// Decelerating with amax, showing `action` until it stands.
    Braking {
        action: u8,
        then: AfterBraking,
    },
    Search(Search),
}

/// What a motor does once braked to a stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AfterBraking {
    Idle,
    /// Ramp to this target ($23 after a rotation, when so chosen).
    Ramp(i32),
}

/// A follower of a $50 interpolation: it keeps its share of the lead's
/// progress along the line.
#[derive(Debug, Clone, PartialEq)]
pub struct Follow {
    pub group: u32,
    pub lead: usize,
    /// Its own distance, and the lead's, from where they started.
    pub delta: i64,
    pub lead_delta: i64,
    /// The lead's odometer at the start, and how far this one has gone.
    pub lead_start: i64,
    pub moved: i64,
    /// Its velocity register per unit of the lead's.
    pub scale: f64,
}

/// Why a stop condition fired (§7.1 $15, §7.3 $31; digest D6.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopCause {
    /// StopNull: the switch active outside ±testnullrange, driving towards it.
    SwitchOutsideRange,
    /// TestNull: at rest at zero, the switch inactive.
    SwitchMissingAtZero,
    /// $31: A_In below MinLeft moving left.
    LeftLimit,
    /// $31: A_In above MaxRight moving right.
    RightLimit,
}

/// One motor: its settings, motion and machine.
#[derive(Debug, Clone)]
pub struct Motor {
    pub settings: MotorSettings,
    pub mechanics: Mechanics,
    pub(super) mode: Mode,
    /// The position counter, posact.
    pub(super) position: i32,
    /// Every µstep counted, signed, never wrapped: progress for $50 and
    /// the reference search.
    pub(super) odometer: i64,
    pub(super) target: i32,
    /// The velocity register in 1/64 units.
    pub(super) v64: i32,
    /// The predivider in use: the motor's div, or 3 at the slow search
    /// velocities (§7.1 $13).
    pub(super) div_in_use: u8,
    phase: i64,
    stop_flag: bool,
    integral: i32,
    /// Ticks at rest (T0, TestNull).
    rest_ticks: u32,
    test_null_checked: bool,
    /// The reference input's samples, newest in bit 0, and the switch as
    /// the firmware sees it (debounced with FilterSwitch).
    debounce: u16,
    pub(super) switch: bool,
    /// Which of I0..I3 drives the coils now.
    current_field: usize,
}

impl Motor {
    pub fn new(mechanics: Mechanics) -> Motor {
        let settings = MotorSettings::default();
        Motor {
            div_in_use: settings.div,
            settings,
            mechanics,
            mode: Mode::Idle,
            position: 0,
            odometer: 0,
            target: 0,
            v64: 0,
            phase: 0,
            stop_flag: false,
            integral: 0,
            rest_ticks: 0,
            test_null_checked: false,
            debounce: 0,
            switch: false,
            current_field: 1,
        }
    }

    /// A reset: settings to their defaults, the counter to 0, at rest; the
    /// machine (and where its carriage is) stays.
    pub fn reset(&mut self) {
        let mechanics = self.mechanics.clone();
        *self = Motor::new(mechanics);
        self.sense();
    }

    // ---- what the host reads ------------------------------------------

    pub fn position(&self) -> i32 {
        self.position
    }

    /// vact, −511..511 (at the predivider in use).
    pub fn velocity(&self) -> i32 {
        self.v64 / 64
    }

    pub fn action(&self) -> u8 {
        match &self.mode {
            Mode::Idle => action::INACTIVE,
            Mode::Ramp { .. } | Mode::Follow(_) => action::RAMP,
            Mode::Pi => action::PI,
            Mode::Rotation { .. } => action::ROTATION,
            Mode::Braking { action, .. } => *action,
            Mode::Search(search) => search.action(),
        }
    }

    pub fn is_idle(&self) -> bool {
        self.mode == Mode::Idle
    }

    pub fn is_searching(&self) -> bool {
        matches!(self.mode, Mode::Search(_))
    }

    pub fn mode(&self) -> &Mode {
        &self.mode
    }

    /// The latched stop flag; reading it with $20 clears it (§7.2).
    pub fn take_stop_flag(&mut self) -> bool {
        std::mem::take(&mut self.stop_flag)
    }

    pub fn stop_flag(&self) -> bool {
        self.stop_flag
    }

    /// The reference switch as the firmware sees it.
    pub fn switch_active(&self) -> bool {
        self.switch
    }

    /// The coil current in per cent of the peak current now (§6.7).
    pub fn current_percent(&self) -> u8 {
        let index = self.settings.current_index[self.current_field];
        super::settings::CURRENT_PERCENT
            .get(usize::from(index))
            .copied()
            .unwrap_or(0)
    }

    // ---- commands ------------------------------------------------------

    /// $23: a ramp to `target`; nothing while the motor is active, but a
    /// rotation is stopped (§7.2).
    pub fn start_ramp(&mut self, target: i32, choices: &Choices) {
        match self.mode {
            Mode::Idle => {
                self.target = self.ramp_target(target);
                if self.target != self.position || self.v64 != 0 {
                    self.mode = Mode::Ramp { group: None };
                }
            }
            Mode::Rotation { .. } => {
                let then = if choices.ramp_after_rotation {
                    AfterBraking::Ramp(self.ramp_target(target))
                } else {
                    AfterBraking::Idle
                };
                self.mode = Mode::Braking {
                    action: action::ROTATION,
                    then,
                };
            }
            _ => {}
        }
    }

    /// $29: a ramp to the target set before, if the motor is idle.
    pub fn start_stored_ramp(&mut self) {
        if self.mode == Mode::Idle && self.target != self.position {
            self.mode = Mode::Ramp { group: None };
        }
    }

    /// $24: PI control on `target`, at once from any mode but a search.
    pub fn start_pi(&mut self, target: i32) {
        if self.is_searching() {
            return;
        }
        if self.mode != Mode::Pi {
            self.integral = 0;
        }
        self.target = self.wrap(i64::from(target));
        self.mode = Mode::Pi;
    }

    /// $25: rotate at `velocity`, at once from any mode but a search.
    pub fn rotate(&mut self, velocity: i32) {
        if self.is_searching() {
            return;
        }
        self.mode = Mode::Rotation { velocity };
    }

    /// $26: a new target, the mode unchanged (§7.2).
    pub fn set_target(&mut self, target: i32) {
        self.target = match self.mode {
            Mode::Pi => self.wrap(i64::from(target)),
            _ => self.ramp_target(target),
        };
    }

    pub fn target(&self) -> i32 {
        self.target
    }

    /// $27: the counter only; the carriage does not move.
    pub fn set_position(&mut self, position: i32) {
        self.position = self.wrap(i64::from(position));
        self.test_null_checked = false;
    }

    /// $2A: target = position; motors faster than vstart overshoot and
    /// come back (§7.2). A rotation or a follower turns into such a ramp;
    /// a search is left alone.
    pub fn stop_here(&mut self) {
        match self.mode {
            Mode::Ramp { .. } => self.target = self.ramp_target(self.position),
            Mode::Pi => self.target = self.position,
            Mode::Rotation { .. } | Mode::Follow(_) => {
                self.target = self.ramp_target(self.position);
                self.mode = Mode::Ramp { group: None };
            }
            Mode::Idle | Mode::Braking { .. } | Mode::Search(_) => {}
        }
    }

    /// $22 or AutonullCmd: a reference search, remembering what to resume.
    pub fn start_search(&mut self) {
        let resume = match self.mode {
            Mode::Search(_) => return,
            Mode::Ramp { .. } => Resume::Ramp(self.target),
            Mode::Pi => Resume::Pi(self.target),
            Mode::Rotation { velocity } => Resume::Rotation(velocity),
            Mode::Idle | Mode::Follow(_) | Mode::Braking { .. } => Resume::Position(self.position),
        };
        let mechanical = self.settings.has(flag::MECH_REF);
        self.mode = Mode::Search(Search::new(mechanical, resume));
    }

    /// $2B: the search ends; the motor brakes to a stop, unreferenced.
    pub fn abort_search(&mut self) {
        if let Mode::Search(search) = &self.mode {
            self.mode = Mode::Braking {
                action: search.action(),
                then: AfterBraking::Idle,
            };
        }
    }

    /// Start leading a $50 interpolation to the target set before.
    pub fn lead(&mut self, group: u32) {
        self.mode = Mode::Ramp { group: Some(group) };
    }

    /// Start following one.
    pub fn follow(&mut self, follow: Follow) {
        self.mode = Mode::Follow(follow);
    }

    /// $CC: everything stops where it is.
    pub fn halt(&mut self) {
        self.v64 = 0;
        self.phase = 0;
        self.mode = Mode::Idle;
    }

    // ---- positions -----------------------------------------------------

    fn rotary(&self) -> bool {
        self.settings.has(flag::ROTARY) && self.settings.poslimit > 0
    }

    /// A position as the counter holds it: a rotary axis in [0, poslimit)
    /// with NullLeft, else in (−poslimit, 0] (§7.2 $23; E17); a linear one
    /// wraps at 32 bits.
    pub(super) fn wrap(&self, position: i64) -> i32 {
        if !self.rotary() {
            return position as i32;
        }
        let limit = i64::from(self.settings.poslimit);
        let low = position.rem_euclid(limit);
        let wrapped = if self.settings.has(flag::NULL_LEFT) || low == 0 {
            low
        } else {
            low - limit
        };
        wrapped as i32
    }

    /// A ramp's end: in range, and on the nearest full step with
    /// StopAtFullsteps (a tie goes on in the direction of travel).
    fn ramp_target(&self, target: i32) -> i32 {
        let target = self.wrap(i64::from(target));
        if !self.settings.has(flag::STOP_AT_FULLSTEPS) {
            return target;
        }
        let t = i64::from(target);
        let rest = t.rem_euclid(16);
        let rounded = match rest {
            0..8 => t - rest,
            8 if t < i64::from(self.position) => t - rest,
            _ => t + 16 - rest,
        };
        self.wrap(rounded)
    }

    /// µsteps from here to `target`: the shorter way round on a rotary
    /// axis with WayOptimization.
    pub(super) fn remaining_to(&self, target: i32) -> i64 {
        let difference = i64::from(target) - i64::from(self.position);
        if self.rotary() && self.settings.has(flag::WAY_OPTIMIZATION) {
            let limit = i64::from(self.settings.poslimit);
            let ahead = difference.rem_euclid(limit);
            if ahead > limit / 2 {
                ahead - limit
            } else {
                ahead
            }
        } else {
            difference
        }
    }

    // ---- velocity and steps ------------------------------------------

    /// vstart in 1/64 units (no higher than vmax).
    pub(super) fn start_velocity(&self) -> i32 {
        let s = &self.settings;
        i32::from(s.vstart.max(1).min(s.vmax.max(1))) * 64
    }

    pub(super) fn amax(&self) -> i32 {
        i32::from(self.settings.amax.max(1))
    }

    /// Bring the velocity register towards `goal` by `rate` a tick; at or
    /// below vstart a stepper starts, stops and turns at once.
    pub(super) fn approach(&mut self, goal: i32, rate: i32) {
        let floor = self.start_velocity();
        let v = self.v64;
        if v == goal {
            return;
        }
        let (direction, wanted) = (v.signum(), goal.signum());
        if v == 0 {
            // A start jumps to vstart and accelerates from there.
            let start = floor.min(goal.abs());
            let first = if goal.abs() > floor {
                (floor + rate).min(goal.abs())
            } else {
                start
            };
            self.v64 = wanted * first;
        } else if direction == wanted && v.abs() < goal.abs() {
            self.v64 = direction * (v.abs() + rate).min(goal.abs());
        } else if direction == wanted {
            let slower = v.abs() - rate;
            self.v64 = direction
                * if slower <= goal.abs().max(floor) {
                    goal.abs()
                } else {
                    slower
                };
        } else {
            let slower = v.abs() - rate;
            self.v64 = if slower <= floor {
                wanted * floor.min(goal.abs())
            } else {
                direction * slower
            };
        }
    }

    /// Switch the predivider; only at rest (the step generator's phase
    /// means nothing at another one).
    pub(super) fn use_div(&mut self, div: u8) {
        if self.v64 == 0 {
            self.div_in_use = div.min(3);
            self.phase = 0;
        }
    }

    /// The µsteps this tick makes at the velocity register's whole part
    /// (not yet counted: see [`Motor::advance_by`]).
    pub(super) fn step(&mut self, clkdiv: u8) -> i64 {
        let per_step = phase_per_step(clkdiv, self.div_in_use);
        self.phase += i64::from(self.v64 / 64) * CLOCKS_PER_TICK;
        let whole = self.phase / per_step;
        self.phase -= whole * per_step;
        whole
    }

    /// Count `steps` and turn the motor by them: the carriage follows
    /// unless a stop holds it (or the drivers are off).
    pub(super) fn advance_by(&mut self, steps: i64, t: &Ticking) {
        if steps == 0 {
            return;
        }
        self.position = self.wrap(i64::from(self.position) + steps);
        self.odometer += steps;
        if t.drivers_enabled {
            self.mechanics.drive(steps);
        }
    }

    /// Step at the velocity register, counting and turning.
    pub(super) fn run(&mut self, t: &Ticking) -> i64 {
        let steps = self.step(t.clkdiv);
        self.advance_by(steps, t);
        steps
    }

    pub(super) fn stand(&mut self) {
        self.v64 = 0;
        self.phase = 0;
    }

    /// One tick of a trapezoidal ramp `remaining` µsteps from its end:
    /// start at vstart, accelerate by amax/64 a tick up to vmax, decelerate
    /// in time (more gently than it accelerates, §6.3.1.1; with amax when
    /// that is too late) to vstart, and creep to the end. A ramp that
    /// cannot stop in time, or whose end moved behind it ($26, $2A),
    /// brakes with amax and comes back (§7.2 $26). True on arrival.
    pub(super) fn ramp_tick(&mut self, remaining: i64, t: &Ticking) -> bool {
        let floor = self.start_velocity();
        let top = i32::from(self.settings.vmax.clamp(1, 511)) * 64;
        let amax = self.amax();
        let slower = i64::from(t.choices.slower_deceleration.min(999));
        let gentle = ((i64::from(amax) * (1000 - slower)) / 1000).max(1) as i32;
        let per_unit = steps_per_tick(t.clkdiv, self.div_in_use);
        let direction = remaining.signum() as i32;
        if self.v64 == 0 {
            if remaining == 0 {
                return true;
            }
            // A start jumps to vstart (the ramp's t = 0); this tick then
            // accelerates from there like any other.
            self.v64 = direction * floor;
        }
        let moving = self.v64.signum();
        let speed = self.v64.abs();
        if moving != direction {
            let slower = speed - amax;
            self.v64 = if slower > floor {
                moving * slower
            } else {
                direction * floor
            };
        } else {
            let left = remaining.abs() as f64;
            let fits = |x: i32| {
                left - f64::from(x / 64) * per_unit >= braking_distance(x, floor, gentle, per_unit)
            };
            let faster = if speed > top {
                (speed - amax).max(top)
            } else {
                (speed + amax).min(top)
            };
            let easing = (speed - gentle).max(floor);
            let next = if fits(faster) {
                faster
            } else if speed <= top && fits(speed) {
                speed
            } else if fits(easing) {
                easing
            } else {
                (speed - amax).max(floor)
            };
            self.v64 = direction * next.max(floor);
        }
        if self.v64 == 0 {
            self.stand();
            return true;
        }
        let steps = self.step(t.clkdiv);
        let lands = direction != 0
            && self.v64.signum() == direction
            && self.v64.abs() <= floor
            && steps.signum() == i64::from(direction)
            && steps.abs() >= remaining.abs();
        if lands {
            self.advance_by(remaining, t);
            self.stand();
            return true;
        }
        self.advance_by(steps, t);
        false
    }

    /// One tick of PI control (§7.1 $19): P = 64·Δ/propdiv (or Δ/propdiv),
    /// the integral of Δ clipped to ±intinpclip a tick and to ±intclip in
    /// all, over intdiv; the output limited to ±vmax (our choice: the
    /// manual gives no limits). True when it ends at its target.
    fn pi_tick(&mut self, t: &Ticking) -> bool {
        let s = &self.settings;
        let difference = self.remaining_to(self.target);
        let gain = if t.choices.pi_times_64 { 64 } else { 1 };
        let proportional = difference.saturating_mul(gain) / i64::from(s.propdiv.max(1));
        let step_in = i64::from(s.intinpclip);
        let clip = i64::from(s.intclip);
        let integral =
            (i64::from(self.integral) + difference.clamp(-step_in, step_in)).clamp(-clip, clip);
        self.integral = integral as i32;
        let top = i64::from(s.vmax.clamp(1, 511));
        let output = (proportional + integral / i64::from(s.intdiv.max(1))).clamp(-top, top);
        self.v64 = output as i32 * 64;
        if difference == 0 && output == 0 && !t.choices.pi_holds {
            self.stand();
            self.integral = 0;
            return true;
        }
        self.run(t);
        false
    }

    /// One tick of whatever the motor does (a follower is moved by its
    /// lead, see [`Motor::follow_lead`]).
    pub fn tick(&mut self, t: &Ticking) {
        let before = self.v64;
        if self.v64 == 0 && !self.is_searching() {
            // A $13 div change made while moving takes effect at rest.
            self.use_div(self.settings.div);
        }
        match self.mode.clone() {
            Mode::Idle | Mode::Follow(_) => {}
            Mode::Ramp { .. } => {
                let remaining = self.remaining_to(self.target);
                if self.ramp_tick(remaining, t) {
                    self.mode = Mode::Idle;
                }
            }
            Mode::Pi => {
                if self.pi_tick(t) {
                    self.mode = Mode::Idle;
                }
            }
            Mode::Rotation { velocity } => {
                let top = i32::from(self.settings.vmax.clamp(1, 511));
                self.approach(velocity.clamp(-top, top) * 64, self.amax());
                if self.v64 == 0 {
                    self.stand();
                    if !t.choices.rotation_holds {
                        self.mode = Mode::Idle;
                    }
                } else {
                    self.run(t);
                }
            }
            Mode::Braking { then, .. } => {
                self.approach(0, self.amax());
                if self.v64 == 0 {
                    self.stand();
                    self.mode = Mode::Idle;
                    if let AfterBraking::Ramp(target) = then {
                        self.target = target;
                        if target != self.position {
                            self.mode = Mode::Ramp { group: None };
                        }
                    }
                } else {
                    self.run(t);
                }
            }
            Mode::Search(_) => self.search_tick(t),
        }
        self.track_rest(before);
    }

    /// A follower's tick: its share of how far the lead has come; it stops
    /// where that puts it once the lead is no longer leading.
    pub fn follow_lead(&mut self, lead_odometer: i64, lead_v64: i32, leading: bool, t: &Ticking) {
        let before = self.v64;
        let Mode::Follow(follow) = &mut self.mode else {
            return;
        };
        let progress = (lead_odometer - follow.lead_start) as f64 / follow.lead_delta as f64;
        let wanted = (follow.delta as f64 * progress).round() as i64;
        let steps = wanted - follow.moved;
        follow.moved = wanted;
        let scale = follow.scale;
        self.advance_by(steps, t);
        if leading {
            self.v64 = (f64::from(lead_v64) * scale) as i32;
        } else {
            self.stand();
            self.mode = Mode::Idle;
        }
        self.track_rest(before);
    }

    fn track_rest(&mut self, before: i32) {
        if self.v64 == 0 && self.mode == Mode::Idle {
            self.rest_ticks = self.rest_ticks.saturating_add(1);
        } else {
            self.rest_ticks = 0;
            self.test_null_checked = false;
        }
        // §6.7: I3 while the velocity changes (decelerating too: our
        // choice), I2 at constant velocity, I1 stopped, I0 after T0.
        self.current_field = if self.v64 == 0 {
            if self.rest_ticks >= u32::from(self.settings.t0) {
                0
            } else {
                1
            }
        } else if self.v64 != before {
            3
        } else {
            2
        };
    }

    // ---- the reference input and stop conditions ---------------------

    /// Sample the reference input (NullPositive: active high) into the
    /// debounce register: with FilterSwitch the switch changes only when
    /// every sample under the $16 mask agrees ($0001: at once, $0FFF:
    /// after 12 samples, 22 ms; §6.4.7).
    pub fn sense(&mut self) {
        let level = self.mechanics.switch_level();
        let active = level == self.settings.has(flag::NULL_POSITIVE);
        self.debounce = (self.debounce << 1) | u16::from(active);
        if self.settings.has(flag::FILTER_SWITCH) {
            let mask = self.settings.debounce_mask | 1;
            if self.debounce & mask == mask {
                self.switch = true;
            } else if self.debounce & mask == 0 {
                self.switch = false;
            }
        } else {
            self.switch = active;
        }
    }

    /// The debounce filter's delay in ticks: one less than the mask's
    /// low-order ones.
    fn debounce_ticks(&self) -> u32 {
        if self.settings.has(flag::FILTER_SWITCH) {
            (self.settings.debounce_mask | 1).trailing_ones() - 1
        } else {
            0
        }
    }

    /// Check the stop conditions after this tick's motion; the one that
    /// fired, if any.
    pub fn check_stops(&mut self, t: &Ticking) -> Option<StopCause> {
        let s = &self.settings;
        let moving = matches!(
            self.mode,
            Mode::Ramp { .. } | Mode::Pi | Mode::Rotation { .. } | Mode::Follow(_)
        );
        let direction = self.v64.signum();
        if moving && direction != 0 {
            if s.has(flag::STOP_NULL)
                && self.switch
                && i64::from(self.position).abs() > i64::from(s.test_null_range)
                && direction == s.search_direction()
            {
                return Some(StopCause::SwitchOutsideRange);
            }
            if !t.choices.limits_need_stop_null || s.has(flag::STOP_NULL) {
                let analog = self.mechanics.analog();
                if direction < 0 && s.min_left > 0 && analog < s.min_left {
                    return Some(StopCause::LeftLimit);
                }
                if direction > 0 && s.max_right < 1023 && analog > s.max_right {
                    return Some(StopCause::RightLimit);
                }
            }
            return None;
        }
        let at_rest_at_zero = self.mode == Mode::Idle && self.v64 == 0 && self.position == 0;
        if s.has(flag::TEST_NULL) && at_rest_at_zero && !self.test_null_checked {
            let settle = if s.has(flag::DELAY_TEST_NULL) {
                u32::from(s.t0)
            } else {
                0
            };
            if self.rest_ticks >= settle + self.debounce_ticks() {
                self.test_null_checked = true;
                if !self.switch {
                    return Some(StopCause::SwitchMissingAtZero);
                }
            }
        }
        None
    }

    /// A stop condition: stop abruptly (a rotor faster than vstart carries
    /// the carriage on for about a tick's travel: steps lost) or, with
    /// StopSoft, decelerate with amax; latch the stop flag; and unless
    /// StopNoRef start a reference search (AutonullCmd, §6.4.4).
    pub fn stop_condition(&mut self, t: &Ticking) {
        self.stop_flag = true;
        let s = &self.settings;
        if self.v64 != 0 {
            if s.has(flag::STOP_SOFT) {
                self.mode = Mode::Braking {
                    action: self.action(),
                    then: AfterBraking::Idle,
                };
            } else {
                if self.v64.abs() > self.start_velocity() && t.drivers_enabled {
                    let per_unit = steps_per_tick(t.clkdiv, self.div_in_use);
                    let run_on = (f64::from(self.v64 / 64) * per_unit).round() as i64;
                    self.mechanics.drive(run_on);
                }
                self.stand();
                self.mode = Mode::Idle;
            }
        } else {
            self.mode = Mode::Idle;
        }
        if !self.settings.has(flag::STOP_NO_REF) {
            self.start_search();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_step_frequencies_of_section_6_3_1() {
        // Digest D5.1, from the §6.3.1 formula and §6.2.1.8's comments.
        let hz = |clkdiv, div, v| microstep_frequency(clkdiv, div, v);
        assert!((hz(5, 2, 1.0) - 50.86).abs() < 0.005);
        assert!((hz(5, 2, 5.0) - 254.3).abs() < 0.05, "254 Hz");
        assert!((hz(5, 2, 511.0) - 25_990.0).abs() < 1.0, "26 kHz");
        assert!((hz(5, 3, 4.0) - 101.7).abs() < 0.05, "102 Hz");
        assert!((hz(5, 2, 100.0) - 5086.0).abs() < 0.5, "5086 Hz");
        assert!((hz(31, 3, 1.0) - 4.77).abs() < 0.005, "slowest");
        assert!(hz(0, 0, 511.0) > 600_000.0, "over the 200 kHz limit");
        // §2.3 "full step frequencies from 0.3 Hz 12.5 kHz": a sixteenth of
        // the µstep frequency (E10: §6.3.1.1 says times 16), from the
        // slowest setting to the 200 kHz limit.
        assert!((hz(31, 3, 1.0) / 16.0 - 0.3).abs() < 0.01);
        assert_eq!(200_000.0 / 16.0, 12_500.0);
    }

    #[test]
    fn the_braking_distance_counts_each_tick_at_its_velocity() {
        // From 10 to 4 units by 2 a tick: 8, 6, 4 (then 4 again, creeping).
        let d = braking_distance(10 * 64, 4 * 64, 2 * 64, 1.0);
        assert!((d - 18.0).abs() < 1e-9, "{d}");
        assert_eq!(braking_distance(4 * 64, 4 * 64, 1, 1.0), 0.0);
        // Not a whole number of steps: 10 → 5 by 2: 8, 6, 5.
        let d = braking_distance(10 * 64, 5 * 64, 2 * 64, 1.0);
        assert!((d - 19.0).abs() < 1e-9, "{d}");
    }
}
