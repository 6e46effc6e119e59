//! Speed profiles of one motion (manual §2.1.4, Appendix B): start at LSPD,
//! ramp to HSPD in ACC ms, cruise, ramp down to LSPD in DEC ms and stop at
//! once. A profile is exact kinematics: a list of phases whose distance and
//! speed are closed-form functions of the time since the profile started, so
//! sampling it at any instant gives the same answer however virtual time was
//! split.
//!
//! Choices where the manual is silent (digest §4.1, §8.3):
//! - S-curve (`SCV=1`): each ramp keeps its linear duration (the manual says
//!   an S-curve "requires more power … when the time for acceleration is the
//!   same") and follows a piecewise-quadratic speed curve with twice the
//!   linear peak acceleration. It covers exactly the distance of the linear
//!   ramp, so planning is the same for both shapes.
//! - Short moves (App. B.2, Fig. B-44 lost, `EDEC` undefined): when the
//!   deceleration would start before half the distance or the cruise would
//!   start after it, both ramps use the ACC rate; if the ramps then still do
//!   not fit, the profile is a triangle peaking at L/2.
//! - ACC and DEC outside the App. B window are clamped into it ("will be
//!   automatically adjusted").

/// One row of Appendix B, Table B-46: the speed windows of the speed
/// multiplier (`SSPDM`), with the acceleration limits they imply.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SpeedWindow {
    /// `SSPDM` values selecting this window.
    pub sspdm: &'static [u8],
    /// Highest speed of the window in pps: 65,535 steps of the multiplier
    /// ("1 - 65K", "65K - 130K" … "3.2M - 6.55M").
    pub max_speed: u32,
    /// Lowest LSPD (= the multiplier), pps.
    pub min_lspd: u32,
    /// Shortest ACC/DEC, ms.
    pub min_ramp_ms: u32,
    /// δ of the longest ramp: ((HSPD − LSPD) / δ) × 1000 ms.
    pub delta: u32,
}

/// Table B-46.
pub const SPEED_WINDOWS: &[SpeedWindow] = &[
    SpeedWindow {
        sspdm: &[0, 1],
        max_speed: 65_535,
        min_lspd: 1,
        min_ramp_ms: 2,
        delta: 50,
    },
    SpeedWindow {
        sspdm: &[2],
        max_speed: 131_070,
        min_lspd: 2,
        min_ramp_ms: 1,
        delta: 100,
    },
    SpeedWindow {
        sspdm: &[3],
        max_speed: 327_675,
        min_lspd: 5,
        min_ramp_ms: 1,
        delta: 200,
    },
    SpeedWindow {
        sspdm: &[4],
        max_speed: 655_350,
        min_lspd: 10,
        min_ramp_ms: 1,
        delta: 800,
    },
    SpeedWindow {
        sspdm: &[5],
        max_speed: 1_310_700,
        min_lspd: 20,
        min_ramp_ms: 1,
        delta: 1500,
    },
    SpeedWindow {
        sspdm: &[6],
        max_speed: 3_276_750,
        min_lspd: 50,
        min_ramp_ms: 1,
        delta: 3800,
    },
    SpeedWindow {
        sspdm: &[7],
        max_speed: 6_553_500,
        min_lspd: 100,
        min_ramp_ms: 1,
        delta: 7500,
    },
];

/// The highest pulse rate of the core (§1.2: 6.55 Mpps).
pub const MAX_SPEED: u32 = 6_553_500;

/// The window a high speed falls in (the last one for anything faster).
pub fn window_for_speed(hspd: u32) -> &'static SpeedWindow {
    SPEED_WINDOWS
        .iter()
        .find(|w| hspd <= w.max_speed)
        .unwrap_or(&SPEED_WINDOWS[SPEED_WINDOWS.len() - 1])
}

/// The window `SSPDM` selects, if the value names one.
pub fn window_for_sspdm(sspdm: u8) -> Option<&'static SpeedWindow> {
    SPEED_WINDOWS.iter().find(|w| w.sspdm.contains(&sspdm))
}

/// Ramp shape (`SCV[axis]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Shape {
    /// Trapezoidal, the default (§2.1.4).
    #[default]
    Linear,
    /// S-curve.
    SCurve,
}

/// The speed settings of one motion, resolved and clamped (App. B), as
/// rates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ramps {
    /// LSPD, pps: where motion starts and where it stops.
    pub low: f64,
    /// HSPD, pps.
    pub high: f64,
    /// pps per second while accelerating (infinite: no ramp).
    pub accel: f64,
    /// pps per second while decelerating.
    pub decel: f64,
    pub shape: Shape,
}

impl Ramps {
    /// Settings as the commands give them: speeds in pps, ramp times in ms.
    pub fn new(lspd: u32, hspd: u32, acc_ms: u32, dec_ms: u32, shape: Shape) -> Ramps {
        let high = hspd.clamp(1, MAX_SPEED);
        let window = window_for_speed(high);
        let low = lspd.clamp(window.min_lspd, MAX_SPEED).min(high);
        let longest = u64::from(high - low) * 1000 / u64::from(window.delta);
        let clamp = |ms: u32| -> f64 {
            let min = u64::from(window.min_ramp_ms);
            u64::from(ms).clamp(min, longest.max(min)) as f64 / 1000.0
        };
        let span = f64::from(high - low);
        let rate = |seconds: f64| {
            if span == 0.0 {
                f64::INFINITY
            } else {
                span / seconds
            }
        };
        Ramps {
            low: f64::from(low),
            high: f64::from(high),
            accel: rate(clamp(acc_ms)),
            decel: rate(clamp(dec_ms)),
            shape,
        }
    }

    /// The same ramps cruising at `speed` instead of HSPD (SD slow-down,
    /// on-the-fly speed change, constant-speed moves).
    pub fn cruising_at(self, speed: f64) -> Ramps {
        Ramps {
            high: speed.max(self.low),
            ..self
        }
    }
}

/// What an axis is doing during a phase (MST bits 0..2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PhaseKind {
    Accelerating,
    Decelerating,
    Constant,
}

/// A ramp or a cruise: speed from `v0` to `v1` in `duration` seconds
/// (infinite only for a cruise, the last phase of a jog).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Phase {
    v0: f64,
    v1: f64,
    duration: f64,
}

impl Phase {
    fn kind(&self) -> PhaseKind {
        if self.v1 > self.v0 {
            PhaseKind::Accelerating
        } else if self.v1 < self.v0 {
            PhaseKind::Decelerating
        } else {
            PhaseKind::Constant
        }
    }

    fn length(&self) -> f64 {
        if self.duration.is_infinite() {
            f64::INFINITY
        } else {
            (self.v0 + self.v1) / 2.0 * self.duration
        }
    }

    fn distance(&self, t: f64, shape: Shape) -> f64 {
        let dv = self.v1 - self.v0;
        if dv == 0.0 {
            return self.v0 * t;
        }
        let u = t / self.duration;
        self.v0 * t
            + match shape {
                Shape::Linear => dv * t * u / 2.0,
                Shape::SCurve => dv * self.duration * s_curve_area(u),
            }
    }

    fn speed(&self, t: f64, shape: Shape) -> f64 {
        let dv = self.v1 - self.v0;
        if dv == 0.0 {
            return self.v0;
        }
        let u = t / self.duration;
        self.v0
            + dv * match shape {
                Shape::Linear => u,
                Shape::SCurve => s_curve(u),
            }
    }
}

/// Normalised S-curve speed: 0 → 1 over u = 0 → 1, slope 0 at both ends,
/// slope 2 in the middle.
fn s_curve(u: f64) -> f64 {
    if u < 0.5 {
        2.0 * u * u
    } else {
        let w = 1.0 - u;
        1.0 - 2.0 * w * w
    }
}

/// ∫₀ᵘ s_curve: 1/2 at u = 1, the area of the linear ramp.
fn s_curve_area(u: f64) -> f64 {
    if u < 0.5 {
        2.0 * u * u * u / 3.0
    } else {
        let w = 1.0 - u;
        1.0 / 12.0 + (u - 0.5) + 2.0 / 3.0 * (w * w * w - 0.125)
    }
}

/// A planned speed profile.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    phases: Vec<Phase>,
    shape: Shape,
}

impl Profile {
    /// No motion at all.
    pub fn empty() -> Profile {
        Profile {
            phases: Vec::new(),
            shape: Shape::Linear,
        }
    }

    /// Constant speed for `distance` (buffered moves: "each move has its own
    /// constant speed", §2.3.4).
    pub fn constant(speed: f64, distance: f64) -> Profile {
        let mut profile = Profile::empty();
        if speed > 0.0 && distance > 0.0 {
            profile.push(speed, speed, distance / speed);
        }
        profile
    }

    fn push(&mut self, v0: f64, v1: f64, duration: f64) {
        if (duration > 0.0 && duration.is_finite()) || duration == f64::INFINITY {
            self.phases.push(Phase { v0, v1, duration });
        }
    }

    /// Total time, seconds (infinite for a jog).
    pub fn duration(&self) -> f64 {
        self.phases.iter().map(|p| p.duration).sum()
    }

    /// Total distance (infinite for a jog).
    pub fn length(&self) -> f64 {
        self.phases.iter().map(Phase::length).sum()
    }

    /// The phase at `t` and the time into it; `None` once finished.
    fn locate(&self, t: f64) -> Option<(&Phase, f64, f64)> {
        let mut start = 0.0;
        let mut covered = 0.0;
        for phase in &self.phases {
            if t < start + phase.duration {
                return Some((phase, t - start, covered));
            }
            start += phase.duration;
            covered += phase.length();
        }
        None
    }

    /// Distance covered `t` seconds after the start.
    pub fn distance_at(&self, t: f64) -> f64 {
        match self.locate(t) {
            Some((phase, into, covered)) => covered + phase.distance(into, self.shape),
            None => self.length(),
        }
    }

    /// Speed `t` seconds after the start (0 once finished).
    pub fn speed_at(&self, t: f64) -> f64 {
        self.locate(t)
            .map_or(0.0, |(phase, into, _)| phase.speed(into, self.shape))
    }

    /// What the motion is doing at `t`; `None` once finished.
    pub fn kind_at(&self, t: f64) -> Option<PhaseKind> {
        self.locate(t).map(|(phase, _, _)| phase.kind())
    }

    /// Whether the profile has ended by `t`.
    pub fn finished_at(&self, t: f64) -> bool {
        self.locate(t).is_none()
    }

    /// The speed the profile ends at (its last phase's end speed).
    pub fn final_speed(&self) -> f64 {
        self.phases.last().map_or(0.0, |p| p.v1)
    }
}

/// Ramp from `v0` to `v1` with the rates of `ramps`; (duration, distance).
fn ramp(v0: f64, v1: f64, ramps: &Ramps, decel_rate: f64) -> (f64, f64) {
    let rate = if v1 >= v0 { ramps.accel } else { decel_rate };
    if rate.is_infinite() || v0 == v1 {
        return (0.0, 0.0);
    }
    let duration = (v1 - v0).abs() / rate;
    (duration, (v0 + v1) / 2.0 * duration)
}

/// A positioning move of `distance` pulses, starting at speed `v0`, cruising
/// at `ramps.high` and stopping from `ramps.low`. `fresh` applies the short
/// move rule of App. B.2 (a move started from standstill).
///
/// If the axis is too fast to stop within `distance`, the result is the stop
/// profile, longer than `distance`: the caller must come back (§2.4.2: "it
/// will reverse direction").
pub fn positioning(v0: f64, distance: f64, ramps: &Ramps, fresh: bool) -> Profile {
    let mut profile = Profile {
        phases: Vec::new(),
        shape: ramps.shape,
    };
    if distance <= 0.0 {
        return profile;
    }
    let low = ramps.low;
    let cruise = ramps.high.max(low);
    let v0 = v0.max(low);
    let mut decel = ramps.decel;
    let (mut t1, mut d1) = ramp(v0, cruise, ramps, decel);
    let (mut t2, mut d2) = ramp(cruise, low, ramps, decel);
    if fresh && (distance - d2 < distance / 2.0 || d1 > distance / 2.0) {
        // App. B.2: the ACC value is used for both ramps.
        decel = ramps.accel;
        (t1, d1) = ramp(v0, cruise, ramps, decel);
        (t2, d2) = ramp(cruise, low, ramps, decel);
    }
    if d1 + d2 <= distance {
        profile.push(v0, cruise, t1);
        profile.push(cruise, cruise, (distance - d1 - d2) / cruise);
        profile.push(cruise, low, t2);
        return profile;
    }
    let stop_distance = if decel.is_infinite() {
        0.0
    } else {
        (v0 * v0 - low * low) / (2.0 * decel)
    };
    if stop_distance > distance {
        return stop(v0, ramps);
    }
    // A triangle: the highest speed from which the axis still stops in time.
    let (a, d) = (ramps.accel, decel);
    let peak = if a.is_infinite() || d.is_infinite() {
        v0
    } else {
        ((distance + v0 * v0 / (2.0 * a) + low * low / (2.0 * d))
            / (1.0 / (2.0 * a) + 1.0 / (2.0 * d)))
            .sqrt()
            .max(v0)
    };
    let (t1, d1) = ramp(v0, peak, ramps, d);
    let (t2, d2) = ramp(peak, low, ramps, d);
    profile.push(v0, peak, t1);
    let rest = distance - d1 - d2;
    if rest > 0.0 {
        // Rounding, or ramps too steep to have a duration.
        profile.push(peak, peak, rest / peak);
    }
    profile.push(peak, low, t2);
    profile
}

/// Ramp from `v0` to `speed` and run on at it (jog, §2.2.2).
pub fn velocity(v0: f64, speed: f64, ramps: &Ramps) -> Profile {
    let mut profile = Profile {
        phases: Vec::new(),
        shape: ramps.shape,
    };
    let speed = speed.max(ramps.low);
    let v0 = v0.max(ramps.low);
    let (t, _) = ramp(v0, speed, ramps, ramps.decel);
    profile.push(v0, speed, t);
    profile.push(speed, speed, f64::INFINITY);
    profile
}

/// Decelerate from `v0` to LSPD, then stop at once (`STOP`, §2.2.3).
pub fn stop(v0: f64, ramps: &Ramps) -> Profile {
    let mut profile = Profile {
        phases: Vec::new(),
        shape: ramps.shape,
    };
    if v0 > ramps.low {
        let (t, _) = ramp(v0, ramps.low, ramps, ramps.decel);
        profile.push(v0, ramps.low, t);
    }
    profile
}

/// Ramp from `v0` to `speed` and stop there (the first leg of a reversal
/// that must end exactly at LSPD, homing steps); same as [`stop`] when
/// `speed` is LSPD.
pub fn ramp_to(v0: f64, speed: f64, ramps: &Ramps) -> Profile {
    let mut profile = Profile {
        phases: Vec::new(),
        shape: ramps.shape,
    };
    let (t, _) = ramp(v0, speed, ramps, ramps.decel);
    profile.push(v0, speed, t);
    profile
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-6 * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn trapezoid_covers_the_distance_in_the_time_the_ramps_say() {
        // §4.3.2: LSPD 500, HSPD 5000, ACC = DEC = 200 ms; X to -20000.
        let ramps = Ramps::new(500, 5000, 200, 200, Shape::Linear);
        let p = positioning(500.0, 20_000.0, &ramps, true);
        // Each ramp: 0.2 s at an average 2750 pps = 550 pulses.
        let cruise = (20_000.0 - 1100.0) / 5000.0;
        assert!(close(p.duration(), 0.4 + cruise), "{}", p.duration());
        assert!(close(p.length(), 20_000.0));
        assert!(close(p.distance_at(0.2), 550.0));
        assert!(close(p.speed_at(0.1), 2750.0));
        assert_eq!(p.kind_at(0.1), Some(PhaseKind::Accelerating));
        assert_eq!(p.kind_at(1.0), Some(PhaseKind::Constant));
        assert_eq!(
            p.kind_at(p.duration() - 0.01),
            Some(PhaseKind::Decelerating)
        );
        assert!(p.finished_at(p.duration()));
    }

    #[test]
    fn a_short_move_is_a_triangle_peaking_at_half_way_with_the_acc_rate() {
        // ACC 200 ms, DEC 50 ms: the ramps need 550 + 137.5 pulses, the move
        // is 400, so App. B.2 uses ACC for both ramps.
        let ramps = Ramps::new(500, 5000, 200, 50, Shape::Linear);
        let p = positioning(500.0, 400.0, &ramps, true);
        assert!(close(p.length(), 400.0));
        let half = p.duration() / 2.0;
        assert!(close(p.distance_at(half), 200.0), "{}", p.distance_at(half));
        assert!(p.speed_at(half) < 5000.0);
        assert_eq!(p.kind_at(half * 0.9), Some(PhaseKind::Accelerating));
        assert_eq!(p.kind_at(half * 1.1), Some(PhaseKind::Decelerating));
    }

    #[test]
    fn an_s_curve_ramp_takes_the_same_time_and_distance_as_a_linear_one() {
        let linear = positioning(
            100.0,
            10_000.0,
            &Ramps::new(100, 2100, 100, 100, Shape::Linear),
            true,
        );
        let s = positioning(
            100.0,
            10_000.0,
            &Ramps::new(100, 2100, 100, 100, Shape::SCurve),
            true,
        );
        assert!(close(linear.duration(), s.duration()));
        assert!(close(linear.distance_at(0.1), s.distance_at(0.1)));
        // Slower start, faster middle: jerk limited.
        assert!(s.speed_at(0.01) < linear.speed_at(0.01));
        assert!((s.speed_at(0.05) - linear.speed_at(0.05)).abs() < 1e-6);
        assert!(s.speed_at(0.07) > linear.speed_at(0.07));
    }

    #[test]
    fn ramp_times_are_clamped_to_appendix_b() {
        // HSPD 20000, LSPD 10000: longest ramp (10000 / 50) × 1000 ms.
        let r = Ramps::new(10_000, 20_000, 500_000, 0, Shape::Linear);
        assert!(close(r.accel, 10_000.0 / 200.0));
        // Shortest ramp in the first window: 2 ms.
        assert!(close(r.decel, 10_000.0 / 0.002));
        // HSPD 900000: window 5, δ 1500, shortest 1 ms.
        let r = Ramps::new(9_000, 900_000, 1_000_000, 0, Shape::Linear);
        assert!(close(r.accel, 891_000.0 / 594.0));
        assert!(close(r.decel, 891_000.0 / 0.001));
    }

    #[test]
    fn a_jog_runs_forever_and_a_stop_ends_at_lspd() {
        let ramps = Ramps::new(500, 5000, 200, 200, Shape::Linear);
        let jog = velocity(500.0, 5000.0, &ramps);
        assert!(jog.duration().is_infinite());
        assert!(close(jog.speed_at(100.0), 5000.0));
        let stop = stop(5000.0, &ramps);
        assert!(close(stop.duration(), 0.2));
        assert!(close(stop.length(), 550.0));
        assert!(close(stop.final_speed(), 500.0));
    }

    #[test]
    fn too_close_to_stop_gives_the_stop_profile() {
        let ramps = Ramps::new(500, 5000, 200, 200, Shape::Linear);
        let p = positioning(5000.0, 100.0, &ramps, false);
        assert!(p.length() > 100.0);
        assert!(close(p.length(), 550.0));
    }

    #[test]
    fn equal_speeds_have_no_ramps() {
        let ramps = Ramps::new(1000, 1000, 200, 200, Shape::Linear);
        let p = positioning(1000.0, 500.0, &ramps, true);
        assert!(close(p.duration(), 0.5));
        assert_eq!(p.kind_at(0.1), Some(PhaseKind::Constant));
    }

    #[test]
    fn windows_follow_table_b_46() {
        assert_eq!(window_for_speed(50_000).delta, 50);
        assert_eq!(window_for_speed(70_000).sspdm, &[2]);
        assert_eq!(window_for_speed(7_000_000).delta, 7500);
        assert_eq!(window_for_sspdm(1).map(|w| w.max_speed), Some(65_535));
        assert!(window_for_sspdm(8).is_none());
    }
}
