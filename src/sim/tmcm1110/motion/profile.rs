//! Ramp profiles as exact piecewise kinematics.
//!
//! A plan is a list of [`Segment`]s, each with a closed-form position and
//! velocity (constant acceleration, or the exponential speed decay of the soft
//! ramp). The axis evaluates the current segment from its start, so virtual
//! time can be cut into steps of any size without integrating error: a move
//! ends when the formulas say it ends, to the nanosecond.
//!
//! Speeds are in microsteps per second (pps), accelerations in pps², times in
//! seconds, positions in microsteps, all as `f64`. Segments never change
//! direction in their interior (ramps through zero speed are split), so the
//! time at which a segment reaches a given position is unique.

/// How the speed evolves within a segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Shape {
    /// Constant acceleration (pps², signed).
    Linear { accel: f64 },
    /// Exponential speed decay `v = v0·e^(−rate·t)` (rate in 1/s): the soft
    /// ramp of AP138 = 1.
    Exponential { rate: f64 },
}

/// One piece of a motion plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Segment {
    /// Speed at the start (pps, signed).
    pub v0: f64,
    pub shape: Shape,
    /// Seconds; `f64::INFINITY` for the open-ended cruise or standstill that
    /// ends every plan.
    pub duration: f64,
    /// Speed at the end as planned (taken over exactly by the next segment).
    pub v_end: f64,
    /// The machine position this segment ends on exactly: the last segment of
    /// a positioning move snaps onto its target.
    pub lands_on: Option<i64>,
}

impl Segment {
    /// Standstill for ever.
    pub const HOLD: Segment = Segment {
        v0: 0.0,
        shape: Shape::Linear { accel: 0.0 },
        duration: f64::INFINITY,
        v_end: 0.0,
        lands_on: None,
    };

    /// Constant speed for ever.
    pub fn cruise_forever(v: f64) -> Segment {
        Segment {
            v0: v,
            v_end: v,
            ..Segment::HOLD
        }
    }

    pub fn is_hold(&self) -> bool {
        self.v0 == 0.0 && self.shape == (Shape::Linear { accel: 0.0 })
    }

    /// Displacement after `t` seconds (clamped to the segment).
    pub fn displacement(&self, t: f64) -> f64 {
        let t = t.clamp(0.0, self.duration);
        match self.shape {
            Shape::Linear { accel } => self.v0 * t + 0.5 * accel * t * t,
            Shape::Exponential { rate } => -self.v0 / rate * (-rate * t).exp_m1(),
        }
    }

    /// Speed after `t` seconds.
    pub fn velocity(&self, t: f64) -> f64 {
        if t >= self.duration {
            return self.v_end;
        }
        let t = t.max(0.0);
        match self.shape {
            Shape::Linear { accel } => self.v0 + accel * t,
            Shape::Exponential { rate } => self.v0 * (-rate * t).exp(),
        }
    }

    /// Acceleration after `t` seconds (pps², signed).
    pub fn acceleration(&self, t: f64) -> f64 {
        match self.shape {
            Shape::Linear { accel } => accel,
            Shape::Exponential { rate } => -rate * self.velocity(t),
        }
    }

    /// Direction of travel in the interior: +1, −1, or 0 at standstill.
    pub fn direction(&self) -> i8 {
        let probe = if self.v0 != 0.0 {
            self.v0
        } else {
            match self.shape {
                Shape::Linear { accel } => accel,
                Shape::Exponential { .. } => 0.0,
            }
        };
        if probe > 0.0 {
            1
        } else if probe < 0.0 {
            -1
        } else {
            0
        }
    }

    /// The first time (s) within the segment at which the displacement
    /// reaches `d` (which lies in the direction of travel), if it does.
    pub fn time_to_travel(&self, d: f64) -> Option<f64> {
        let s = f64::from(self.direction());
        if s == 0.0 {
            return None;
        }
        if d * s <= 0.0 {
            return Some(0.0);
        }
        let t = match self.shape {
            Shape::Linear { accel } => {
                if accel == 0.0 {
                    d / self.v0
                } else {
                    let disc = self.v0 * self.v0 + 2.0 * accel * d;
                    if disc < 0.0 {
                        return None;
                    }
                    // 2d / (v0 + s·√disc) avoids the cancellation of the
                    // textbook root when v0 is large and the step is small.
                    2.0 * d / (self.v0 + s * disc.sqrt())
                }
            }
            Shape::Exponential { rate } => {
                let u = rate * d / self.v0;
                if u >= 1.0 {
                    return None;
                }
                -(-u).ln_1p() / rate
            }
        };
        (t.is_finite() && t >= 0.0 && t <= self.duration).then_some(t)
    }

    /// Whole nanoseconds until the segment is over, rounded up so that an
    /// event never fires before its exact time; `u64::MAX` when open-ended.
    pub fn duration_ns(&self) -> u64 {
        seconds_to_ns_ceil(self.duration)
    }
}

/// Seconds → nanoseconds, rounded up, saturating (infinite → `u64::MAX`).
pub(super) fn seconds_to_ns_ceil(seconds: f64) -> u64 {
    let ns = (seconds * 1e9).ceil();
    if ns.is_nan() || ns <= 0.0 {
        0
    } else if ns >= u64::MAX as f64 {
        u64::MAX
    } else {
        ns as u64
    }
}

/// Builds a plan segment by segment, keeping track of the speed reached and
/// the distance covered so far (relative to the plan's start).
#[derive(Debug, Clone)]
pub(super) struct Builder {
    segments: Vec<Segment>,
    v: f64,
    moved: f64,
}

/// Iteration cap of the planners' loops (each iteration removes one cause of
/// re-planning; three or four are ever needed).
const MAX_PLANNER_STEPS: usize = 8;

impl Builder {
    pub fn new(v: f64) -> Self {
        Builder {
            segments: Vec::new(),
            v,
            moved: 0.0,
        }
    }

    pub fn velocity(&self) -> f64 {
        self.v
    }

    pub fn len(&self) -> usize {
        self.segments.len()
    }

    fn push(&mut self, segment: Segment) {
        let usable = segment.duration > 0.0 && segment.duration.is_finite();
        if !usable {
            // Zero-length pieces change nothing but the speed bookkeeping.
            self.v = segment.v_end;
            return;
        }
        self.moved += segment.displacement(segment.duration);
        self.v = segment.v_end;
        self.segments.push(segment);
    }

    /// Ramp linearly to `target` with `accel` (> 0), split at zero speed.
    pub fn ramp_to(&mut self, target: f64, accel: f64) {
        if self.v * target < 0.0 {
            self.ramp_to(0.0, accel);
        }
        let dv = target - self.v;
        if dv == 0.0 {
            return;
        }
        self.push(Segment {
            v0: self.v,
            shape: Shape::Linear {
                accel: accel.copysign(dv),
            },
            duration: dv.abs() / accel,
            v_end: target,
            lands_on: None,
        });
    }

    /// Keep the present speed for `duration` seconds.
    pub fn cruise(&mut self, duration: f64) {
        self.push(Segment {
            v0: self.v,
            shape: Shape::Linear { accel: 0.0 },
            duration,
            v_end: self.v,
            lands_on: None,
        });
    }

    /// Exponential decay of the speed down to `target` (same sign, smaller).
    fn decay_to(&mut self, target: f64, rate: f64) {
        if target == 0.0 || self.v == 0.0 || target.abs() >= self.v.abs() {
            return;
        }
        self.push(Segment {
            v0: self.v,
            shape: Shape::Exponential { rate },
            duration: (self.v / target).ln() / rate,
            v_end: target,
            lands_on: None,
        });
    }

    /// Change the speed at once (the TMC429 starts and ends soft ramps at
    /// its minimum speed).
    fn jump_to(&mut self, v: f64) {
        self.v = v;
    }

    /// Velocity mode (AP138 = 2): ramp to `target` and keep it.
    pub fn velocity_mode(&mut self, target: f64, accel: f64) {
        self.ramp_to(target, accel);
    }

    /// Position mode (AP138 = 0): the time-optimal trapezoid (or triangle)
    /// that comes to rest `distance` from the plan's start, never faster than
    /// `vmax` unless already faster (then it first slows down to `vmax`).
    /// Returns true when the plan ends on the target.
    pub fn trapezoid(&mut self, distance: f64, vmax: f64, accel: f64) -> bool {
        for _ in 0..MAX_PLANNER_STEPS {
            let d = distance - self.moved;
            let v = self.v;
            if v == 0.0 && d == 0.0 {
                return true;
            }
            let braking = v * v / (2.0 * accel);
            if v != 0.0 && (d == 0.0 || v.signum() != d.signum() || braking > d.abs()) {
                // Moving away, or too fast to stop in time: stop first (and
                // come back: the TMC429 overshoots rather than brake harder).
                self.ramp_to(0.0, accel);
                continue;
            }
            let s = d.signum();
            let (dd, w) = (d.abs(), v.abs());
            if w > vmax {
                self.ramp_to(s * vmax, accel);
                continue;
            }
            // Peak speed of the triangle through the remaining distance.
            let peak = (accel * dd + w * w / 2.0).sqrt();
            if peak <= vmax {
                self.ramp_to(s * peak, accel);
            } else {
                self.ramp_to(s * vmax, accel);
                let cruise = (distance - self.moved).abs() - vmax * vmax / (2.0 * accel);
                if cruise > 0.0 {
                    self.cruise(cruise / vmax);
                }
            }
            self.ramp_to(0.0, accel);
            return true;
        }
        false
    }

    /// Soft mode (AP138 = 1), our model of the manual's "exponential decrease
    /// of speed": accelerate linearly like position mode, then follow the
    /// curve v = k·(distance to go) with k = accel/vmax (so the deceleration
    /// starts at `accel` and dies away exponentially) down to `vmin`
    /// (AP130), and cover the last vmin/k microsteps at `vmin`.
    /// Returns true when the plan ends on the target.
    pub fn soft(&mut self, distance: f64, vmax: f64, accel: f64, vmin: f64) -> bool {
        let vmin = vmin.min(vmax);
        let k = accel / vmax;
        for _ in 0..MAX_PLANNER_STEPS {
            let d = distance - self.moved;
            let v = self.v;
            if v == 0.0 && d == 0.0 {
                return true;
            }
            if v != 0.0 && (d == 0.0 || v.signum() != d.signum()) {
                self.ramp_to(0.0, accel);
                continue;
            }
            let s = d.signum();
            let (dd, w) = (d.abs(), v.abs());
            if w > k * dd {
                // Closer than the soft curve allows.
                if w * w / (2.0 * accel) > dd {
                    self.ramp_to(0.0, accel);
                    continue;
                }
                self.approach(distance, s, w / dd, vmin);
                return true;
            }
            if w > vmax {
                self.ramp_to(s * vmax, accel);
                continue;
            }
            // Speed where the acceleration parabola meets the curve.
            let r = accel / k;
            let meet = -r + (r * r + w * w + 2.0 * accel * dd).sqrt();
            let peak = meet.min(vmax);
            if peak <= vmin {
                // A hop shorter than the curve's tail: all of it at vmin.
                self.jump_to(s * vmin);
                self.cruise(dd / vmin);
                return true;
            }
            self.ramp_to(s * peak, accel);
            if peak >= vmax {
                let cruise = (distance - self.moved).abs() - vmax / k;
                if cruise > 0.0 {
                    self.cruise(cruise / vmax);
                }
            }
            self.approach(distance, s, k, vmin);
            return true;
        }
        false
    }

    /// The exponential tail of the soft ramp and its creep at `vmin`.
    fn approach(&mut self, distance: f64, s: f64, rate: f64, vmin: f64) {
        let w = self.v.abs();
        if w > vmin {
            self.decay_to(s * vmin, rate);
        } else {
            self.jump_to(s * vmin);
        }
        let rest = (distance - self.moved).abs();
        if rest > 0.0 {
            self.cruise(rest / vmin);
        }
    }

    /// The segments so far, the last one marked as landing on `target` when
    /// `landed` (a complete positioning plan).
    pub fn into_segments(mut self, landed_on: Option<i64>) -> Vec<Segment> {
        if let (Some(target), Some(last)) = (landed_on, self.segments.last_mut()) {
            last.v_end = 0.0;
            last.lands_on = Some(target);
        }
        self.segments
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn total_time(segments: &[Segment]) -> f64 {
        segments.iter().map(|s| s.duration).sum()
    }

    fn total_distance(segments: &[Segment]) -> f64 {
        segments.iter().map(|s| s.displacement(s.duration)).sum()
    }

    #[test]
    fn trapezoid_from_rest_takes_v_over_a_plus_d_over_v() {
        let (d, v, a) = (51200.0, 30517.578125, 46566.128730773926);
        let mut b = Builder::new(0.0);
        assert!(b.trapezoid(d, v, a));
        let segs = b.into_segments(Some(51200));
        assert_eq!(segs.len(), 3);
        assert!((total_time(&segs) - (v / a + d / v)).abs() < 1e-9);
        assert!((total_distance(&segs) - d).abs() < 1e-6);
    }

    #[test]
    fn triangle_from_rest_takes_two_root_d_over_a() {
        let (d, a) = (1000.0, 50000.0);
        let mut b = Builder::new(0.0);
        assert!(b.trapezoid(-d, 1.0e6, a));
        let segs = b.into_segments(Some(-1000));
        assert_eq!(segs.len(), 2);
        assert!((total_time(&segs) - 2.0 * (d / a).sqrt()).abs() < 1e-12);
        assert!((total_distance(&segs) + d).abs() < 1e-9);
    }

    #[test]
    fn too_fast_to_stop_overshoots_and_returns() {
        let mut b = Builder::new(1000.0);
        // braking distance 1000²/2000 = 500 > 100
        assert!(b.trapezoid(100.0, 2000.0, 1000.0));
        let segs = b.into_segments(Some(100));
        assert!(segs.iter().any(|s| s.direction() < 0));
        assert!((total_distance(&segs) - 100.0).abs() < 1e-9);
    }

    #[test]
    fn ramps_through_zero_are_split() {
        let mut b = Builder::new(-500.0);
        b.velocity_mode(500.0, 1000.0);
        let segs = b.into_segments(None);
        assert_eq!(segs.len(), 2);
        assert_eq!(segs[0].direction(), -1);
        assert_eq!(segs[1].direction(), 1);
    }

    #[test]
    fn soft_ramp_lands_and_decays() {
        let (d, vmax, a, vmin) = (51200.0, 30000.0, 45000.0, 30.0);
        let mut b = Builder::new(0.0);
        assert!(b.soft(d, vmax, a, vmin));
        let segs = b.into_segments(Some(51200));
        assert!((total_distance(&segs) - d).abs() < 1e-6);
        assert!(
            segs.iter()
                .any(|s| matches!(s.shape, Shape::Exponential { .. }))
        );
        // Slower than the trapezoid, which ends after v/a + d/v.
        assert!(total_time(&segs) > vmax / a + d / vmax);
        // Never faster than vmax, never decelerating harder than a.
        for s in &segs {
            assert!(s.v0.abs() <= vmax + 1e-9 && s.v_end.abs() <= vmax + 1e-9);
            assert!(s.acceleration(0.0).abs() <= a + 1e-6);
        }
    }

    #[test]
    fn time_to_travel_inverts_displacement() {
        let lin = Segment {
            v0: 100.0,
            shape: Shape::Linear { accel: -40.0 },
            duration: 2.5,
            v_end: 0.0,
            lands_on: None,
        };
        let t = lin.time_to_travel(90.0).unwrap();
        assert!((lin.displacement(t) - 90.0).abs() < 1e-9);
        assert_eq!(lin.time_to_travel(200.0), None);
        let exp = Segment {
            v0: -100.0,
            shape: Shape::Exponential { rate: 2.0 },
            duration: 1.0,
            v_end: -100.0 * (-2.0f64).exp(),
            lands_on: None,
        };
        let t = exp.time_to_travel(-30.0).unwrap();
        assert!((exp.displacement(t) + 30.0).abs() < 1e-9);
        assert_eq!(exp.time_to_travel(-49.0), None);
    }

    #[test]
    fn nanoseconds_round_up() {
        assert_eq!(seconds_to_ns_ceil(1.0), 1_000_000_000);
        assert_eq!(seconds_to_ns_ceil(1.0e-9 * 0.5), 1);
        assert_eq!(seconds_to_ns_ceil(f64::INFINITY), u64::MAX);
        assert_eq!(seconds_to_ns_ceil(-3.0), 0);
        assert_eq!(seconds_to_ns_ceil(f64::NAN), 0);
    }
}
