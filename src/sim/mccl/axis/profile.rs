//! The trajectory generator's profiles (manual Ch7 PT, PS, PP), in counts
//! and seconds, stepped at 1 kHz.
//!
//! - Trapezoidal (PT): constant acceleration SA up to SV, constant
//!   deceleration DS; worked out afresh every tick from where the optimal
//!   position is, so a new target, speed or acceleration takes effect at
//!   once, as PT allows. `1SV100000,1SA200000,1DS200000` takes 0.5 s to
//!   reach and to leave full speed (the manual's own numbers, Ch5 DS).
//! - S-curve (PS, "sinusoidal acceleration") and parabolic (PP,
//!   "triangular acceleration, parabolic velocity"): the manual gives no
//!   equations, so the simulator plans these moves whole when they start,
//!   with the peak acceleration equal to SA (DS when slowing):
//!   S-curve a(t) = SA·sin(πt/T); parabolic a(t) = SA·(1 − t/T), the
//!   stepper-friendly ramp that is strongest at low speed, mirrored in
//!   time when slowing down. A move given a new target while it runs
//!   goes on as a trapezoid (PS/PP moves must not change, Ch7).

use std::f64::consts::PI;

/// The three velocity profiles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Shape {
    #[default]
    Trapezoid,
    SCurve,
    Parabolic,
}

impl Shape {
    /// Ramp time per unit of speed change at unit acceleration.
    fn time_factor(self) -> f64 {
        match self {
            Shape::Trapezoid => 1.0,
            Shape::SCurve => PI / 2.0,
            Shape::Parabolic => 2.0,
        }
    }

    /// Ramp distance over (speed change × ramp time).
    fn distance_factor(self) -> f64 {
        match self {
            Shape::Trapezoid | Shape::SCurve => 0.5,
            Shape::Parabolic => 2.0 / 3.0,
        }
    }

    /// Distance covered while speeding up from 0 to `v` at peak `a`.
    fn ramp_distance(self, v: f64, a: f64) -> f64 {
        self.distance_factor() * v * self.ramp_time(v, a)
    }

    fn ramp_time(self, v: f64, a: f64) -> f64 {
        if a <= 0.0 {
            return 0.0;
        }
        self.time_factor() * v / a
    }

    /// Distance and speed `t` into a ramp of duration `ramp` from 0 to `v`.
    fn ramp_at(self, v: f64, ramp: f64, t: f64) -> (f64, f64) {
        if ramp <= 0.0 {
            return (0.0, v);
        }
        let t = t.clamp(0.0, ramp);
        match self {
            Shape::Trapezoid => {
                let a = v / ramp;
                (a * t * t / 2.0, a * t)
            }
            Shape::SCurve => {
                let w = PI / ramp;
                (
                    v / 2.0 * (t - (w * t).sin() / w),
                    v / 2.0 * (1.0 - (w * t).cos()),
                )
            }
            Shape::Parabolic => {
                let a = 2.0 * v / ramp;
                (
                    a * (t * t / 2.0 - t * t * t / (6.0 * ramp)),
                    a * (t - t * t / (2.0 * ramp)),
                )
            }
        }
    }
}

/// The speeds and rates a move runs at, in counts and seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rates {
    pub velocity: f64,
    pub acceleration: f64,
    pub deceleration: f64,
    /// Start/stop speed of a stepper (MV), 0 for a servo.
    pub minimum: f64,
}

/// Where a ramp is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Phase {
    #[default]
    Idle,
    Accelerating,
    Cruising,
    Decelerating,
}

/// One tick of the trapezoid toward `target` from position `p` at speed
/// `v`: the new position, speed and phase. Arrives exactly.
pub fn trapezoid_step(p: f64, v: f64, target: f64, rates: &Rates, dt: f64) -> (f64, f64, Phase) {
    let s = target - p;
    if s == 0.0 && v == 0.0 {
        return (p, 0.0, Phase::Idle);
    }
    let direction = if s != 0.0 { s.signum() } else { -v.signum() };
    let a = rates.acceleration.max(1e-9);
    let d = rates.deceleration.max(1e-9);
    // Moving away from the target: brake first.
    if v * direction < 0.0 {
        let speed = (v.abs() - d * dt).max(0.0);
        let v_new = v.signum() * speed;
        return (p + v_new * dt, v_new, Phase::Decelerating);
    }
    let speed = v.abs();
    let remaining = s.abs();
    // The fastest speed this tick from which the rest can still be
    // stopped at d, with the tick's own travel counted.
    let braking = -d * dt + ((d * dt).powi(2) + 2.0 * d * remaining).sqrt();
    let cruise = rates.velocity.max(0.0);
    let wanted = if speed > cruise {
        (speed - d * dt).max(cruise)
    } else {
        (speed + a * dt).min(cruise)
    };
    let mut v_new = wanted.min(braking);
    if v_new < rates.minimum {
        v_new = rates.minimum;
    }
    if v_new <= 0.0 {
        // No speed to move at (SV 0): the move does not start.
        return (p, 0.0, Phase::Cruising);
    }
    let travel = v_new * dt;
    // The braking speed only ever nears the target; the last fraction of
    // a count (less than one tick of deceleration) is taken at once.
    if travel >= remaining - d * dt * dt {
        return (target, 0.0, Phase::Idle);
    }
    let phase = if v_new < speed - 1e-9 {
        Phase::Decelerating
    } else if v_new > speed + 1e-9 {
        Phase::Accelerating
    } else {
        Phase::Cruising
    };
    (p + direction * travel, direction * v_new, phase)
}

/// Change speed `v` toward `goal` at `acceleration` (speeding up) or
/// `deceleration` (slowing down) for one tick: velocity mode and stops.
pub fn ramp_velocity(v: f64, goal: f64, acceleration: f64, deceleration: f64, dt: f64) -> f64 {
    if v == goal {
        return v;
    }
    // Slowing down when the goal is nearer zero or on the other side.
    let slowing = goal.abs() < v.abs() || goal * v < 0.0;
    let rate = if slowing { deceleration } else { acceleration };
    let step = rate.max(0.0) * dt;
    if goal * v < 0.0 {
        // Through zero: slow to a stop first.
        let speed = (v.abs() - step).max(0.0);
        return v.signum() * speed;
    }
    if (goal - v).abs() <= step {
        goal
    } else {
        v + (goal - v).signum() * step
    }
}

/// A point-to-point move planned whole (S-curve and parabolic profiles).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plan {
    shape: Shape,
    start: f64,
    direction: f64,
    distance: f64,
    peak: f64,
    accelerating: f64,
    cruising: f64,
    decelerating: f64,
    /// Time since the move began.
    elapsed: f64,
}

impl Plan {
    /// The move from `start` (at rest) to `target`; `None` if there is no
    /// distance to go.
    pub fn new(shape: Shape, start: f64, target: f64, rates: &Rates) -> Option<Plan> {
        let distance = (target - start).abs();
        if distance == 0.0 {
            return None;
        }
        let a = rates.acceleration.max(1e-9);
        let d = rates.deceleration.max(1e-9);
        let full = rates.velocity.max(1e-9);
        let ramps = |v: f64| shape.ramp_distance(v, a) + shape.ramp_distance(v, d);
        let peak = if ramps(full) <= distance {
            full
        } else {
            // Ramp distance grows with v²: scale to fit.
            (distance / ramps(1.0)).sqrt()
        };
        let accelerating = shape.ramp_time(peak, a);
        let decelerating = shape.ramp_time(peak, d);
        let cruising = (distance - ramps(peak)).max(0.0) / peak;
        Some(Plan {
            shape,
            start,
            direction: (target - start).signum(),
            distance,
            peak,
            accelerating,
            cruising,
            decelerating,
            elapsed: 0.0,
        })
    }

    pub fn duration(&self) -> f64 {
        self.accelerating + self.cruising + self.decelerating
    }

    pub fn peak(&self) -> f64 {
        self.peak
    }

    /// Position, velocity and phase `t` seconds into the move.
    pub fn at(&self, t: f64) -> (f64, f64, Phase) {
        let (ta, tc, td) = (self.accelerating, self.cruising, self.decelerating);
        let (covered, speed, phase) = if t >= self.duration() {
            (self.distance, 0.0, Phase::Idle)
        } else if t < ta {
            let (x, v) = self.shape.ramp_at(self.peak, ta, t);
            (x, v, Phase::Accelerating)
        } else if t < ta + tc {
            let (x, _) = self.shape.ramp_at(self.peak, ta, ta);
            (x + self.peak * (t - ta), self.peak, Phase::Cruising)
        } else {
            // The decelerating ramp is the speeding-up one run backwards.
            let (x, v) = self.shape.ramp_at(self.peak, td, self.duration() - t);
            (self.distance - x, v, Phase::Decelerating)
        };
        (
            self.start + self.direction * covered,
            self.direction * speed,
            phase,
        )
    }

    /// Advance by `dt`: the new position, velocity and phase.
    pub fn step(&mut self, dt: f64) -> (f64, f64, Phase) {
        self.elapsed += dt;
        self.at(self.elapsed)
    }

    pub fn finished(&self) -> bool {
        self.elapsed >= self.duration()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 0.001;

    fn rates(v: f64, a: f64, d: f64) -> Rates {
        Rates {
            velocity: v,
            acceleration: a,
            deceleration: d,
            minimum: 0.0,
        }
    }

    /// Run the trapezoid to the end: (ticks, peak speed, time it first
    /// reached full speed).
    fn run_trapezoid(distance: f64, r: &Rates) -> (usize, f64, Option<f64>) {
        let (mut p, mut v) = (0.0, 0.0);
        let mut peak: f64 = 0.0;
        let mut reached = None;
        for tick in 1..1_000_000 {
            let (np, nv, phase) = trapezoid_step(p, v, distance, r, DT);
            (p, v) = (np, nv);
            peak = peak.max(v.abs());
            if reached.is_none() && (v.abs() - r.velocity).abs() < 1e-6 {
                reached = Some(tick as f64 * DT);
            }
            if phase == Phase::Idle {
                assert_eq!(p, distance, "arrives exactly");
                return (tick, peak, reached);
            }
        }
        panic!("never arrived");
    }

    #[test]
    fn the_manuals_half_second_ramps() {
        // Ch5 DS/SA/SV: 1SV100000, 1SA200000, 1DS200000 — "accelerate to max.
        // velocity in 0.5 seconds", "decelerate to zero velocity in 0.5
        // seconds". A 100000-count move: 25000 up, 50000 at speed, 25000 down,
        // 1.5 s in all.
        let r = rates(100_000.0, 200_000.0, 200_000.0);
        let (ticks, peak, reached) = run_trapezoid(100_000.0, &r);
        assert_eq!(peak, 100_000.0);
        let reached = reached.expect("reaches full speed");
        assert!(
            (reached - 0.5).abs() <= 2.0 * DT,
            "full speed at {reached} s"
        );
        let total = ticks as f64 * DT;
        assert!((total - 1.5).abs() <= 3.0 * DT, "took {total} s");
    }

    #[test]
    fn a_short_move_is_a_triangle() {
        // 1000 counts at 200000 c/s²: peak √(2·500·200000) ≈ 14142 c/s,
        // 2·√(1000/200000) ≈ 0.141 s.
        let r = rates(100_000.0, 200_000.0, 200_000.0);
        let (ticks, peak, _) = run_trapezoid(1000.0, &r);
        assert!((peak - 14_142.0).abs() < 300.0, "peak {peak}");
        let total = ticks as f64 * DT;
        assert!((total - 0.1414).abs() <= 3.0 * DT, "took {total} s");
    }

    #[test]
    fn a_faster_decel_shortens_only_the_end() {
        let r = rates(10_000.0, 10_000.0, 40_000.0);
        let (ticks, _, _) = run_trapezoid(20_000.0, &r);
        // 1 s up (5000), 0.25 s down (1250), 13750 at speed: 2.625 s.
        let total = ticks as f64 * DT;
        assert!((total - 2.625).abs() <= 3.0 * DT, "took {total} s");
    }

    #[test]
    fn a_new_target_behind_brakes_then_returns() {
        let r = rates(10_000.0, 100_000.0, 100_000.0);
        let (mut p, mut v) = (0.0, 0.0);
        for _ in 0..100 {
            (p, v, _) = trapezoid_step(p, v, 10_000.0, &r, DT);
        }
        assert!(v > 0.0);
        let mut went_back = false;
        for _ in 0..10_000 {
            let phase;
            (p, v, phase) = trapezoid_step(p, v, 0.0, &r, DT);
            went_back |= v < 0.0;
            if phase == Phase::Idle {
                break;
            }
        }
        assert!(went_back);
        assert_eq!((p, v), (0.0, 0.0));
    }

    #[test]
    fn a_stepper_starts_and_stops_at_its_minimum_speed() {
        let r = Rates {
            minimum: 500.0,
            ..rates(10_000.0, 100_000.0, 100_000.0)
        };
        let (_, v, _) = trapezoid_step(0.0, 0.0, 10_000.0, &r, DT);
        assert_eq!(v, 500.0, "jumps to MV");
        let (p, v, phase) = trapezoid_step(9_999.7, 500.0, 10_000.0, &r, DT);
        assert_eq!((p, v, phase), (10_000.0, 0.0, Phase::Idle), "stops from MV");
    }

    #[test]
    fn planned_profiles_peak_at_sa_and_arrive_exactly() {
        let r = rates(100_000.0, 200_000.0, 200_000.0);
        for shape in [Shape::Trapezoid, Shape::SCurve, Shape::Parabolic] {
            let mut plan = Plan::new(shape, 0.0, 300_000.0, &r).expect("a move");
            let mut last_v = 0.0;
            let mut peak_a: f64 = 0.0;
            let mut ticks = 0;
            while !plan.finished() {
                let (_, v, _) = plan.step(DT);
                peak_a = peak_a.max(((v - last_v) / DT).abs());
                last_v = v;
                ticks += 1;
            }
            assert!(
                (peak_a - 200_000.0).abs() < 0.01 * 200_000.0,
                "{shape:?}: peak acceleration {peak_a}"
            );
            assert_eq!(plan.at(plan.duration()).0, 300_000.0, "{shape:?}");
            // Ramps: trapezoid 0.5 s, S-curve π/2 × 0.5 s, parabolic 1 s;
            // the rest at 100000 c/s.
            let ramp = 0.5 * shape.time_factor();
            let ramps = 2.0 * shape.distance_factor() * 100_000.0 * ramp;
            let expected = 2.0 * ramp + (300_000.0 - ramps) / 100_000.0;
            assert!(
                (ticks as f64 * DT - expected).abs() <= 2.0 * DT,
                "{shape:?}: {} s, expected {expected} s",
                ticks as f64 * DT
            );
        }
    }

    #[test]
    fn a_planned_move_is_continuous() {
        let r = rates(50_000.0, 100_000.0, 300_000.0);
        for shape in [Shape::SCurve, Shape::Parabolic] {
            let plan = Plan::new(shape, 500.0, -20_000.0, &r).expect("a move");
            let mut last = plan.at(0.0);
            let mut t = 0.0;
            while t < plan.duration() {
                t += DT / 4.0;
                let now = plan.at(t);
                assert!(
                    (now.0 - last.0).abs() <= 50_000.0 * DT / 4.0 + 1e-6,
                    "{shape:?} at {t}"
                );
                assert!(now.0 <= last.0 + 1e-9, "{shape:?} goes one way");
                last = now;
            }
            assert_eq!(last.0, -20_000.0);
        }
    }

    #[test]
    fn velocity_ramps_through_zero_at_the_deceleration() {
        let mut v = 1000.0;
        let mut ticks = 0;
        while v != -1000.0 {
            v = ramp_velocity(v, -1000.0, 10_000.0, 100_000.0, DT);
            ticks += 1;
            assert!(ticks < 1000);
        }
        // 10 ms down at DS, 100 ms up at SA.
        assert_eq!(ticks, 110);
    }
}
