//! Geometry of coordinated moves (§2.3, Appendix C): where each axis of an
//! interpolation is when the path has been followed for a distance `s`.
//!
//! Choices where the manual is silent (digest §4.5, §8.3):
//! - Linear: the path length is the main axis' distance (the axis with the
//!   largest distance, C.1); the others are scaled and rounded to the
//!   nearest pulse, so all end together and exactly.
//! - Circle and arc: HSPD is the speed along the arc, in pulses per second
//!   of arc length. Angles are measured from the first axis' + direction
//!   towards the second axis' + direction (Fig. 2-23 is lost); `P`
//!   (clockwise) turns towards smaller angles. Positions are the nearest
//!   pulse to the exact circle (C.4: ±0.5 LSB).
//! - An arc whose end angle is its start angle draws the full circle.
//! - Helical: Z moves linearly over the same path fraction; the U axis is
//!   held busy but its counters do not change (C.5: "dummy operation").

use std::f64::consts::TAU;

use super::{Axis, Rotation};

/// The largest radius of a circle or arc (§2.3.2: "134,216,773 pulses";
/// digest erratum 15 suspects 2^27 − 1, but the manual's figure is kept).
pub const MAX_RADIUS: f64 = 134_216_773.0;

/// A coordinated path.
#[derive(Debug, Clone, PartialEq)]
pub enum Path {
    Linear {
        /// (axis, start, distance) of every axis in the interpolation.
        legs: Vec<(Axis, i64, i64)>,
        /// The main axis' distance.
        length: i64,
    },
    Arc(Arc),
}

/// A circle, an arc, or either with Z moving along (helical).
#[derive(Debug, Clone, PartialEq)]
pub struct Arc {
    pub axes: (Axis, Axis),
    pub centre: (f64, f64),
    pub radius: f64,
    /// Angle of the start point, radians.
    pub start: f64,
    /// Signed sweep, radians (negative = clockwise).
    pub sweep: f64,
    /// Z start and distance of a helical move.
    pub helix: Option<(i64, i64)>,
}

impl Arc {
    /// The arc from the current position `from` around `centre`: a full
    /// circle (`end_mdeg` = `None`) or up to the absolute angle `end_mdeg`
    /// (millidegrees). `None` if the radius is 0 or too large.
    pub fn new(
        axes: (Axis, Axis),
        from: (i64, i64),
        centre: (i64, i64),
        rotation: Rotation,
        end_mdeg: Option<i64>,
    ) -> Option<Arc> {
        let centre = (centre.0 as f64, centre.1 as f64);
        let dx = from.0 as f64 - centre.0;
        let dy = from.1 as f64 - centre.1;
        let radius = dx.hypot(dy);
        if radius == 0.0 || radius > MAX_RADIUS {
            return None;
        }
        let start = dy.atan2(dx);
        let sweep = match end_mdeg {
            None => TAU,
            Some(mdeg) => {
                let end = (mdeg as f64 / 1000.0).to_radians();
                let ccw = (end - start).rem_euclid(TAU);
                let angle = match rotation {
                    Rotation::CounterClockwise => ccw,
                    Rotation::Clockwise => (TAU - ccw).rem_euclid(TAU),
                };
                // Tiny sweeps are rounding of "the same angle".
                if angle * radius < 0.5 { TAU } else { angle }
            }
        };
        Some(Arc {
            axes,
            centre,
            radius,
            start,
            sweep: match rotation {
                Rotation::Clockwise => -sweep,
                Rotation::CounterClockwise => sweep,
            },
            helix: None,
        })
    }

    /// Where the two axes are after `s` pulses of arc.
    fn point(&self, s: f64) -> (i64, i64) {
        let angle = self.start + self.sweep.signum() * s / self.radius;
        (
            (self.centre.0 + self.radius * angle.cos()).round() as i64,
            (self.centre.1 + self.radius * angle.sin()).round() as i64,
        )
    }

    /// Rate of each axis for a path speed `v` at `s` (pulses per second).
    fn rates(&self, s: f64, v: f64) -> (f64, f64) {
        let angle = self.start + self.sweep.signum() * s / self.radius;
        ((v * angle.sin()).abs(), (v * angle.cos()).abs())
    }
}

impl Path {
    /// A linear interpolation from `starts` by `distances` (same order).
    pub fn linear(legs: Vec<(Axis, i64, i64)>) -> Path {
        let length = legs.iter().map(|&(_, _, d)| d.abs()).max().unwrap_or(0);
        Path::Linear { legs, length }
    }

    /// The carriage of `axis` moved by `delta` under the path (lost
    /// steps): the rest of the path follows from there.
    pub fn shift(&mut self, axis: Axis, delta: i64) {
        match self {
            Path::Linear { legs, .. } => {
                for (a, start, _) in legs.iter_mut() {
                    if *a == axis {
                        *start += delta;
                    }
                }
            }
            Path::Arc(arc) => {
                if arc.axes.0 == axis {
                    arc.centre.0 += delta as f64;
                } else if arc.axes.1 == axis {
                    arc.centre.1 += delta as f64;
                } else if let Some((start, _)) = &mut arc.helix
                    && axis == Axis::Z
                {
                    *start += delta;
                }
            }
        }
    }

    /// Path length in pulses.
    pub fn length(&self) -> f64 {
        match self {
            Path::Linear { length, .. } => *length as f64,
            Path::Arc(arc) => arc.radius * arc.sweep.abs(),
        }
    }

    /// The axes the path moves, with their positions after `s` of it; at
    /// the end (`s` ≥ length) the exact end point.
    pub fn positions(&self, s: f64) -> Vec<(Axis, i64)> {
        let s = s.clamp(0.0, self.length());
        match self {
            Path::Linear { legs, length } => {
                let done = s.floor() as i64;
                legs.iter()
                    .map(|&(axis, start, distance)| (axis, start + scale(distance, done, *length)))
                    .collect()
            }
            Path::Arc(arc) => {
                let total = self.length();
                let (a, b) = if s >= total {
                    arc.point(arc.radius * arc.sweep.abs())
                } else {
                    arc.point(s)
                };
                let mut out = vec![(arc.axes.0, a), (arc.axes.1, b)];
                if let Some((start, distance)) = arc.helix {
                    let fraction = if total > 0.0 { s / total } else { 1.0 };
                    out.push((Axis::Z, start + (distance as f64 * fraction).round() as i64));
                }
                out
            }
        }
    }

    /// The pulse rate of each axis at path speed `v` (PS, §2.6.2.2).
    pub fn rates(&self, s: f64, v: f64) -> Vec<(Axis, f64)> {
        match self {
            Path::Linear { legs, length } => legs
                .iter()
                .map(|&(axis, _, d)| {
                    let share = if *length == 0 {
                        0.0
                    } else {
                        d.abs() as f64 / *length as f64
                    };
                    (axis, v * share)
                })
                .collect(),
            Path::Arc(arc) => {
                let (a, b) = arc.rates(s, v);
                let mut out = vec![(arc.axes.0, a), (arc.axes.1, b)];
                if let Some((_, distance)) = arc.helix {
                    let total = self.length();
                    let share = if total > 0.0 {
                        distance.abs() as f64 / total
                    } else {
                        0.0
                    };
                    out.push((Axis::Z, v * share));
                }
                out
            }
        }
    }

    /// Which way `axis` travels after `s` of the path: +1, −1, or 0 if
    /// the path does not move it there (no leg of its own, a leg of 0).
    pub fn heading(&self, axis: Axis, s: f64) -> i64 {
        match self {
            Path::Linear { legs, .. } => legs
                .iter()
                .find(|&&(a, _, _)| a == axis)
                .map_or(0, |&(_, _, d)| d.signum()),
            Path::Arc(arc) => {
                // d/ds of centre + r·(cos, sin) at the angle reached.
                let turn = arc.sweep.signum();
                let angle = arc.start + turn * s / arc.radius;
                let slope = if arc.axes.0 == axis {
                    -turn * angle.sin()
                } else if arc.axes.1 == axis {
                    turn * angle.cos()
                } else {
                    return match arc.helix {
                        Some((_, distance)) if axis == Axis::Z => distance.signum(),
                        _ => 0,
                    };
                };
                if slope > 0.0 {
                    1
                } else if slope < 0.0 {
                    -1
                } else {
                    0
                }
            }
        }
    }

    /// The axes the path moves.
    pub fn axes(&self) -> Vec<Axis> {
        match self {
            Path::Linear { legs, .. } => legs.iter().map(|&(a, _, _)| a).collect(),
            Path::Arc(arc) => {
                let mut axes = vec![arc.axes.0, arc.axes.1];
                if arc.helix.is_some() {
                    axes.push(Axis::Z);
                }
                axes
            }
        }
    }
}

/// `distance · done / length`, rounded to the nearest pulse, without
/// overflow for 28-bit positions.
fn scale(distance: i64, done: i64, length: i64) -> i64 {
    if length == 0 {
        return distance;
    }
    let product = i128::from(distance) * i128::from(done);
    let length = i128::from(length);
    let half = length / 2;
    let q = if product >= 0 {
        (product + half) / length
    } else {
        (product - half) / length
    };
    i64::try_from(q).unwrap_or(distance)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_axes_end_together_and_exactly() {
        // §4.3.5: X to -20000 and Y to 15000 from 0.
        let path = Path::linear(vec![(Axis::X, 0, -20_000), (Axis::Y, 0, 15_000)]);
        assert_eq!(path.length(), 20_000.0);
        assert_eq!(
            path.positions(10_000.0),
            vec![(Axis::X, -10_000), (Axis::Y, 7_500)]
        );
        assert_eq!(
            path.positions(20_000.0),
            vec![(Axis::X, -20_000), (Axis::Y, 15_000)]
        );
        let rates = path.rates(0.0, 5000.0);
        assert_eq!(rates, vec![(Axis::X, 5000.0), (Axis::Y, 3750.0)]);
    }

    #[test]
    fn a_clockwise_circle_comes_back_to_its_start() {
        // §4.3.6: CIRXYP1000:0 from (0, 0): radius 1000, start angle 180°.
        let arc = Arc::new(
            (Axis::X, Axis::Y),
            (0, 0),
            (1000, 0),
            Rotation::Clockwise,
            None,
        )
        .expect("arc");
        let path = Path::Arc(arc);
        assert!((path.length() - TAU * 1000.0).abs() < 1e-6);
        // A quarter clockwise from 180° is 90°: (1000, 1000).
        let quarter = path.length() / 4.0;
        assert_eq!(
            path.positions(quarter),
            vec![(Axis::X, 1000), (Axis::Y, 1000)]
        );
        assert_eq!(
            path.positions(path.length()),
            vec![(Axis::X, 0), (Axis::Y, 0)]
        );
    }

    #[test]
    fn arcs_end_at_their_absolute_angle() {
        // ARCXYP0:0:90000 vs ARCXYN0:0:90000 from 0° (1000, 0).
        let cw = Arc::new(
            (Axis::X, Axis::Y),
            (1000, 0),
            (0, 0),
            Rotation::Clockwise,
            Some(90_000),
        )
        .expect("arc");
        let ccw = Arc::new(
            (Axis::X, Axis::Y),
            (1000, 0),
            (0, 0),
            Rotation::CounterClockwise,
            Some(90_000),
        )
        .expect("arc");
        assert!((cw.sweep + 1.5 * std::f64::consts::PI).abs() < 1e-9);
        assert!((ccw.sweep - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
        for arc in [cw, ccw] {
            let path = Path::Arc(arc);
            assert_eq!(
                path.positions(path.length()),
                vec![(Axis::X, 0), (Axis::Y, 1000)]
            );
        }
    }

    #[test]
    fn degenerate_arcs_are_refused_or_full() {
        assert!(
            Arc::new(
                (Axis::X, Axis::Y),
                (5, 5),
                (5, 5),
                Rotation::Clockwise,
                None
            )
            .is_none()
        );
        let same = Arc::new(
            (Axis::X, Axis::Y),
            (1000, 0),
            (0, 0),
            Rotation::Clockwise,
            Some(0),
        )
        .expect("arc");
        assert!((same.sweep.abs() - TAU).abs() < 1e-9);
    }

    #[test]
    fn helical_z_follows_the_path_fraction() {
        let mut arc = Arc::new(
            (Axis::X, Axis::Y),
            (1000, 0),
            (0, 0),
            Rotation::CounterClockwise,
            None,
        )
        .expect("arc");
        arc.helix = Some((0, 400));
        let path = Path::Arc(arc);
        let half = path.positions(path.length() / 2.0);
        assert_eq!(half, vec![(Axis::X, -1000), (Axis::Y, 0), (Axis::Z, 200)]);
    }

    #[test]
    fn each_axis_heads_the_way_its_part_of_the_path_moves_it() {
        let linear = Path::linear(vec![(Axis::X, 0, 500), (Axis::Y, 0, -300), (Axis::Z, 0, 0)]);
        assert_eq!(linear.heading(Axis::X, 100.0), 1);
        assert_eq!(linear.heading(Axis::Y, 100.0), -1);
        assert_eq!(linear.heading(Axis::Z, 100.0), 0, "no distance");
        assert_eq!(linear.heading(Axis::U, 100.0), 0, "not in it");
        // Counter-clockwise from (1000, 0) around (0, 0): at 45° X falls
        // and Y rises, at 135° both fall; clockwise the other way round.
        for (rotation, turn) in [(Rotation::CounterClockwise, 1), (Rotation::Clockwise, -1)] {
            let mut arc =
                Arc::new((Axis::X, Axis::Y), (1000, 0), (0, 0), rotation, None).expect("arc");
            arc.helix = Some((0, -400));
            let path = Path::Arc(arc);
            let eighth = path.length() / 8.0;
            assert_eq!(path.heading(Axis::X, eighth), -1, "{rotation:?}");
            assert_eq!(path.heading(Axis::Y, eighth), turn, "{rotation:?}");
            assert_eq!(path.heading(Axis::X, 3.0 * eighth), -1, "{rotation:?}");
            assert_eq!(path.heading(Axis::Y, 3.0 * eighth), -turn, "{rotation:?}");
            assert_eq!(path.heading(Axis::Z, eighth), -1, "helical Z");
            assert_eq!(path.heading(Axis::U, eighth), 0);
        }
    }
}
