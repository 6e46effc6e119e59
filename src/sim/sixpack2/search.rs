//! The reference search ($22, or AutonullCmd in $15; §7.2, §6.2.1.5, §6.4,
//! §5.5.1; digest D6.2, D6.3) as a state machine on the motor's tick.
//!
//! Switch search: stop; drive towards the zero side (NullLeft: descending)
//! at vrefmax with FastRef until the switch is active; drive back until it
//! is inactive; approach it at vmin (always at div 3) to find its edge;
//! with NullCenter cross it at vmin to its far edge and take the middle.
//! The reference point gets the coordinate that puts zero nulloffset
//! further into the switch, and the motor drives there. Without FastRef
//! the first drive is already slow ("a fixed velocity of 1", §6.4.8) and
//! the edge it finds is taken as is. No switch within 5/4 of poslimit, or
//! none at the slow approach where the fast drive had found it: the whole
//! procedure starts again, without limit ($2B ends it). Then the motor
//! resumes what it did (a motor at rest drives back to the numeric
//! position where the search began), unless $16 says stop.
//!
//! Mechanical reference (MechRef): drive 5/4 of poslimit towards the zero
//! side, into the stopper, where the motor stalls; that is the reference.
//!
//! The action codes 20..29 are not documented; ours are [`Phase::code`].

use super::motor::{Mode, Motor, Ticking, action};
use super::settings::{fastest_vmin, flag};

/// What the motor did before the search, to resume afterwards (§7.2 $22).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Resume {
    /// At rest (or stopped by a stop condition): back to this position.
    Position(i32),
    Ramp(i32),
    Pi(i32),
    Rotation(i32),
}

/// The steps of a switch search.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Braking whatever motion there was (with amax).
    Stopping,
    /// Driving towards the switch.
    Seeking,
    /// Driving back until it is inactive again.
    BackingOff,
    /// Slowly towards it, for the exact edge.
    Approaching,
    /// NullCenter: slowly through it, for the far edge.
    Crossing,
    /// A ramp to the new zero.
    ToZero,
    /// MechRef: the drive into the stopper.
    Mechanical,
}

impl Phase {
    /// The action code $20/$21/$28 show (our mapping of 20..29).
    pub fn code(self) -> u8 {
        match self {
            Phase::Stopping => 20,
            Phase::Seeking => 21,
            Phase::BackingOff => 22,
            Phase::Approaching => 23,
            Phase::Crossing => 24,
            Phase::ToZero => 25,
            Phase::Mechanical => action::MECHANICAL,
        }
    }
}

/// A reference search under way.
#[derive(Debug, Clone, PartialEq)]
pub struct Search {
    mechanical: bool,
    phase: Phase,
    resume: Resume,
    /// µsteps driven in this phase.
    driven: i64,
    /// The odometer where the switch was met driving fast (or where the
    /// search began on it).
    found: i64,
    /// How far the slow approach may go before it gives up.
    approach_limit: i64,
    /// The odometer at the first edge (NullCenter).
    first_edge: i64,
    /// µsteps of the mechanical drive still to go.
    mechanical_left: i64,
    /// How often the whole procedure started again.
    retries: u32,
}

impl Search {
    pub fn new(mechanical: bool, resume: Resume) -> Search {
        Search {
            mechanical,
            phase: Phase::Stopping,
            resume,
            driven: 0,
            found: 0,
            approach_limit: 0,
            first_edge: 0,
            mechanical_left: 0,
            retries: 0,
        }
    }

    pub fn action(&self) -> u8 {
        if self.mechanical {
            action::MECHANICAL
        } else {
            self.phase.code()
        }
    }

    pub fn phase(&self) -> Phase {
        self.phase
    }

    pub fn retries(&self) -> u32 {
        self.retries
    }

    fn enter(&mut self, phase: Phase) {
        self.phase = phase;
        self.driven = 0;
    }

    fn retry(&mut self) {
        self.retries = self.retries.saturating_add(1);
        self.enter(Phase::Stopping);
    }
}

/// What a search tick came to.
enum Outcome {
    Going(Search),
    Done(Resume),
}

impl Motor {
    /// The search's range: 5/4 of poslimit (none when poslimit is 0: the
    /// search goes on until it finds the switch, §6.4.8).
    fn search_range(&self) -> Option<i64> {
        let limit = i64::from(self.settings.poslimit);
        (limit > 0).then_some(limit * 5 / 4)
    }

    /// vmin in use: 0 picks the fastest allowed (§7.1 $13).
    fn slow_velocity(&self, clkdiv: u8) -> i32 {
        let s = &self.settings;
        let vmin = if s.vmin == 0 {
            fastest_vmin(clkdiv, s.vstart)
        } else {
            s.vmin
        };
        i32::from(vmin.clamp(1, 511))
    }

    /// The first drive's velocity without FastRef (at div 3).
    fn unhurried_velocity(&self, t: &Ticking) -> i32 {
        match t.choices.slow_search_velocity {
            0 => self.slow_velocity(t.clkdiv),
            v => i32::from(v.min(511)),
        }
    }

    /// Run at `velocity` (whole units) with predivider 3, braking first
    /// from any motion at another predivider.
    fn run_slowly(&mut self, velocity: i32, t: &Ticking) -> i64 {
        if self.div_in_use != 3 {
            self.approach(0, self.amax());
            if self.v64 != 0 {
                return self.run(t);
            }
            self.use_div(3);
        }
        self.v64 = velocity * 64;
        self.run(t)
    }

    /// Run towards `velocity` (whole units, ramping with amax) at the
    /// motor's own predivider.
    fn run_fast(&mut self, velocity: i32, t: &Ticking) -> i64 {
        if self.div_in_use != self.settings.div {
            self.stand();
            self.use_div(self.settings.div);
        }
        self.approach(velocity * 64, self.amax());
        self.run(t)
    }

    /// The coordinate the reference point gets: zero lies nulloffset
    /// further into the switch (§7.1 $18), mirrored for NullLeft = 0 unless
    /// chosen otherwise (the sign convention there is not stated).
    fn reference_coordinate(&self, t: &Ticking) -> i64 {
        let offset = i64::from(self.settings.null_offset);
        if t.choices.offset_mirrored {
            -i64::from(self.settings.search_direction()) * offset
        } else {
            offset
        }
    }

    /// The reference point lies `back` µsteps behind where the motor is:
    /// set the counter from it.
    fn set_reference(&mut self, back: i64, t: &Ticking) {
        let here = self.reference_coordinate(t) + back;
        self.position = self.wrap(here);
    }

    pub(super) fn search_tick(&mut self, t: &Ticking) {
        let Mode::Search(search) = std::mem::replace(&mut self.mode, Mode::Idle) else {
            return;
        };
        match self.search_step(search, t) {
            Outcome::Going(search) => self.mode = Mode::Search(search),
            Outcome::Done(resume) => self.resume(resume),
        }
    }

    fn search_step(&mut self, mut search: Search, t: &Ticking) -> Outcome {
        let toward = self.settings.search_direction();
        let fast = self.settings.has(flag::FAST_REF);
        let range = self.search_range();
        let beyond = |driven: i64| range.is_some_and(|r| driven > r);
        match search.phase {
            Phase::Stopping => {
                self.approach(0, self.amax());
                if self.v64 != 0 {
                    self.run(t);
                    return Outcome::Going(search);
                }
                self.stand();
                self.use_div(self.settings.div);
                if search.mechanical {
                    search.mechanical_left = range.unwrap_or(0);
                    search.enter(Phase::Mechanical);
                } else if self.switch {
                    search.found = self.odometer;
                    search.enter(Phase::BackingOff);
                } else {
                    search.enter(Phase::Seeking);
                }
            }
            Phase::Seeking => {
                let steps = if fast {
                    let vrefmax = i32::from(self.settings.vrefmax.clamp(1, 511));
                    self.run_fast(toward * vrefmax, t)
                } else {
                    let velocity = self.unhurried_velocity(t);
                    self.run_slowly(toward * velocity, t)
                };
                search.driven += steps.abs();
                if self.switch && self.v64.signum() == toward {
                    if fast {
                        search.found = self.odometer;
                        search.enter(Phase::BackingOff);
                    } else {
                        return self.edge_found(search, t);
                    }
                } else if beyond(search.driven) {
                    search.retry();
                }
            }
            Phase::BackingOff => {
                let steps = if fast {
                    let vrefmax = i32::from(self.settings.vrefmax.clamp(1, 511));
                    self.run_fast(-toward * vrefmax, t)
                } else {
                    let velocity = self.unhurried_velocity(t);
                    self.run_slowly(-toward * velocity, t)
                };
                search.driven += steps.abs();
                if !self.switch && self.v64.signum() == -toward {
                    // The slow approach must meet the switch again before
                    // it passes where the fast drive met it, with as much
                    // again to spare.
                    let back = (self.odometer - search.found).abs();
                    search.approach_limit = 2 * back + 16;
                    search.enter(Phase::Approaching);
                } else if beyond(search.driven) {
                    search.retry();
                }
            }
            Phase::Approaching => {
                let vmin = self.slow_velocity(t.clkdiv);
                let steps = self.run_slowly(toward * vmin, t);
                if self.v64.signum() == toward {
                    search.driven += steps.abs();
                    if self.switch {
                        return self.edge_found(search, t);
                    }
                    if search.driven > search.approach_limit {
                        search.retry();
                    }
                } else {
                    // Still braking from backing off: the distance it
                    // covers has to be made up.
                    search.approach_limit += steps.abs();
                }
            }
            Phase::Crossing => {
                let vmin = self.slow_velocity(t.clkdiv);
                let steps = self.run_slowly(toward * vmin, t);
                search.driven += steps.abs();
                if !self.switch {
                    let middle = (search.first_edge + self.odometer) / 2;
                    let back = self.odometer - middle;
                    return self.reference_found(search, back, t);
                }
                if beyond(search.driven) {
                    search.retry();
                }
            }
            Phase::ToZero => {
                let remaining = self.remaining_to(0);
                if self.ramp_tick(remaining, t) {
                    return Outcome::Done(search.resume);
                }
            }
            Phase::Mechanical => {
                let steps = if t.choices.mech_ref_at_vrefmax {
                    let vrefmax = i32::from(self.settings.vrefmax.clamp(1, 511));
                    self.approach(toward * vrefmax * 64, self.amax());
                    // The last tick is cut short at the drive's end.
                    let mut steps = self.step(t.clkdiv);
                    if steps.abs() >= search.mechanical_left {
                        steps = i64::from(toward) * search.mechanical_left;
                        self.stand();
                    }
                    self.advance_by(steps, t);
                    steps
                } else {
                    let before = self.odometer;
                    self.ramp_tick(i64::from(toward) * search.mechanical_left, t);
                    self.odometer - before
                };
                search.mechanical_left -= steps.abs();
                if search.mechanical_left <= 0 {
                    self.stand();
                    self.set_reference(0, t);
                    return Outcome::Done(search.resume);
                }
            }
        }
        Outcome::Going(search)
    }

    fn edge_found(&mut self, mut search: Search, t: &Ticking) -> Outcome {
        if self.settings.has(flag::NULL_CENTER) {
            search.first_edge = self.odometer;
            search.enter(Phase::Crossing);
            Outcome::Going(search)
        } else {
            self.reference_found(search, 0, t)
        }
    }

    /// The reference point is `back` µsteps behind: coordinates set, slow
    /// motion stopped (below vstart, at once), on to zero.
    fn reference_found(&mut self, mut search: Search, back: i64, t: &Ticking) -> Outcome {
        self.stand();
        self.use_div(self.settings.div);
        self.set_reference(back, t);
        search.enter(Phase::ToZero);
        Outcome::Going(search)
    }

    /// After the search: stop, or take up what it interrupted (§7.2 $22,
    /// $16 P5).
    fn resume(&mut self, resume: Resume) {
        self.stand();
        self.mode = Mode::Idle;
        if self.settings.stop_after_search {
            return;
        }
        match resume {
            Resume::Position(target) | Resume::Ramp(target) => {
                self.target = self.wrap(i64::from(target));
                if self.target != self.position {
                    self.mode = Mode::Ramp { group: None };
                }
            }
            Resume::Pi(target) => self.start_pi(target),
            Resume::Rotation(velocity) => self.rotate(velocity),
        }
    }
}
