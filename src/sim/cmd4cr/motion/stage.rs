//! The simulated machine behind one axis: where its end limits, home and
//! slow-down switches sit, where the encoder's Z index pulses come, and
//! how many encoder counts a motor pulse makes. Positions are *machine*
//! positions in motor pulses (where the carriage is); the counters `P` and
//! `E` are offsets from it that `P[axis]=`, `E[axis]=` and homing rewrite.
//!
//! Input levels here are *logical* (on = active): the core's input logic
//! (`POL`, whose bit meanings are lost with T2-17) is kept as a raw word and
//! does not change what the simulated switches report.

/// An inclusive range of machine positions where an input is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Window {
    pub low: i64,
    pub high: i64,
}

impl Window {
    pub const fn new(low: i64, high: i64) -> Window {
        Window { low, high }
    }

    pub fn contains(&self, position: i64) -> bool {
        self.low <= position && position <= self.high
    }

    /// Where the input changes on the way from `from` to `to` (monotonic),
    /// with the level it changes to.
    fn edges(&self, from: i64, to: i64, out: &mut Vec<(i64, bool)>) {
        if to > from {
            if from < self.low && self.low <= to {
                out.push((self.low, true));
            }
            if from <= self.high && self.high < to {
                out.push((self.high.saturating_add(1), false));
            }
        } else if to < from {
            if to <= self.high && self.high < from {
                out.push((self.high, true));
            }
            if to < self.low && self.low <= from {
                out.push((self.low.saturating_sub(1), false));
            }
        }
    }
}

/// The encoder's index pulse: on at every machine position `phase + k·period`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ZIndex {
    pub period: i64,
    pub phase: i64,
}

/// A switch or index the carriage passes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    PlusLimit(bool),
    MinusLimit(bool),
    Home(bool),
    Slowdown(bool),
    /// A Z index pulse.
    Index,
}

/// The mechanics of one axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Stage {
    /// The + end limit is on from here upwards.
    pub plus_limit: Option<i64>,
    /// The − end limit is on from here downwards.
    pub minus_limit: Option<i64>,
    pub home: Option<Window>,
    /// Slow-down (SD) cams.
    pub slowdown: Vec<Window>,
    pub z_index: Option<ZIndex>,
    /// Encoder counts per motor pulse (1 on a stepper whose encoder matches
    /// its pulses, as homing modes 9..12 require, App. A.13).
    pub encoder_ratio: f64,
    /// The end limits are wired to each other's input: the carriage at
    /// the + end turns the −limit input on, at the − end the +limit one.
    pub limits_swapped: bool,
    /// Mechanical end stops (lowest, highest machine position): the
    /// carriage goes no further; the motor's further pulses are lost (a
    /// stall), as a missed step is.
    pub end_stops: Option<(i64, i64)>,
}

/// Where the demo stage's end limits close, in pulses from the power-up
/// position: 100,000 pulses, 20 s of travel at the §4.3 examples' 5,000 pps.
pub const DEMO_LIMIT: i64 = 100_000;
/// The demo stage's mechanical end stops: 10,000 pulses beyond each end
/// limit, where a carriage that no limit stops (disabled, or wired to the
/// other input) comes to a stand.
pub const DEMO_END_STOP: i64 = DEMO_LIMIT + 10_000;
/// The demo stage's home switch: 1,000 pulses wide, its edge 1,000 pulses on
/// the − side of the power-up position, so that the §4.3.4 example (`HY-1`,
/// homing towards −) finds it without starting on it.
pub const DEMO_HOME: Window = Window::new(-2_000, -1_000);
/// One Z index pulse per 1,000 pulses (a 1000-line encoder on a motor of
/// 1000 pulses a rotation), 250 pulses past each thousand so that it never
/// coincides with an edge of the home switch.
pub const DEMO_Z_INDEX: ZIndex = ZIndex {
    period: 1_000,
    phase: 250,
};

impl Stage {
    /// A linear stage with end limits at ±[`DEMO_LIMIT`], a home switch at
    /// [`DEMO_HOME`], no slow-down cams, a Z index every 1,000 pulses and an
    /// encoder counting one per pulse: what every axis of a new simulator
    /// has.
    pub fn demo() -> Stage {
        Stage {
            plus_limit: Some(DEMO_LIMIT),
            minus_limit: Some(-DEMO_LIMIT),
            home: Some(DEMO_HOME),
            slowdown: Vec::new(),
            z_index: Some(DEMO_Z_INDEX),
            encoder_ratio: 1.0,
            limits_swapped: false,
            end_stops: Some((-DEMO_END_STOP, DEMO_END_STOP)),
        }
    }

    /// A bare axis: no switches, no index, an encoder of one count a pulse.
    pub fn bare() -> Stage {
        Stage {
            plus_limit: None,
            minus_limit: None,
            home: None,
            slowdown: Vec::new(),
            z_index: None,
            encoder_ratio: 1.0,
            limits_swapped: false,
            end_stops: None,
        }
    }

    /// The +limit input at `position` (the switch at the − end when the
    /// limits are swapped).
    pub fn plus_limit_at(&self, position: i64) -> bool {
        if self.limits_swapped {
            self.minus_end_at(position)
        } else {
            self.plus_end_at(position)
        }
    }

    /// The −limit input at `position`.
    pub fn minus_limit_at(&self, position: i64) -> bool {
        if self.limits_swapped {
            self.plus_end_at(position)
        } else {
            self.minus_end_at(position)
        }
    }

    fn plus_end_at(&self, position: i64) -> bool {
        self.plus_limit.is_some_and(|l| position >= l)
    }

    fn minus_end_at(&self, position: i64) -> bool {
        self.minus_limit.is_some_and(|l| position <= l)
    }

    /// Where the carriage heading for `position` ends up: there, or at the
    /// end stop in the way.
    pub fn within_stops(&self, position: i64) -> i64 {
        match self.end_stops {
            Some((low, high)) => position.clamp(low, high),
            None => position,
        }
    }

    pub fn home_at(&self, position: i64) -> bool {
        self.home.is_some_and(|w| w.contains(position))
    }

    pub fn slowdown_at(&self, position: i64) -> bool {
        self.slowdown.iter().any(|w| w.contains(position))
    }

    pub fn index_at(&self, position: i64) -> bool {
        self.z_index
            .is_some_and(|z| z.period > 0 && (position - z.phase).rem_euclid(z.period) == 0)
    }

    /// Encoder counts at a machine position (before the `E` offset).
    pub fn encoder_at(&self, position: i64) -> i64 {
        if self.encoder_ratio == 1.0 {
            position
        } else {
            (position as f64 * self.encoder_ratio).round() as i64
        }
    }

    /// Every switch edge and index pulse between `from` (excluded) and `to`
    /// (included), in the order the carriage meets them, with the machine
    /// position where it happens.
    pub fn marks(&self, from: i64, to: i64) -> Vec<(i64, Mark)> {
        let mut marks = Vec::new();
        if from == to {
            return marks;
        }
        let mut edges = Vec::new();
        type Edge = fn(bool) -> Mark;
        let (plus_end, minus_end): (Edge, Edge) = if self.limits_swapped {
            (Mark::MinusLimit, Mark::PlusLimit)
        } else {
            (Mark::PlusLimit, Mark::MinusLimit)
        };
        if let Some(l) = self.plus_limit {
            Window::new(l, i64::MAX).edges(from, to, &mut edges);
            marks.extend(edges.drain(..).map(|(p, on)| (p, plus_end(on))));
        }
        if let Some(l) = self.minus_limit {
            Window::new(i64::MIN, l).edges(from, to, &mut edges);
            marks.extend(edges.drain(..).map(|(p, on)| (p, minus_end(on))));
        }
        if let Some(w) = self.home {
            w.edges(from, to, &mut edges);
            marks.extend(edges.drain(..).map(|(p, on)| (p, Mark::Home(on))));
        }
        for w in &self.slowdown {
            w.edges(from, to, &mut edges);
            marks.extend(edges.drain(..).map(|(p, on)| (p, Mark::Slowdown(on))));
        }
        if let Some(z) = self.z_index.filter(|z| z.period > 0) {
            // Index positions in (from, to] or [to, from), at most a few
            // dozen per step: homing counts at most 16.
            let (low, high) = if to > from {
                (from + 1, to)
            } else {
                (to, from - 1)
            };
            let first = low + (z.phase - low).rem_euclid(z.period);
            let mut p = first;
            let mut n = 0;
            while p <= high && n < 64 {
                marks.push((p, Mark::Index));
                p += z.period;
                n += 1;
            }
        }
        if to > from {
            marks.sort_by_key(|&(p, _)| p);
        } else {
            marks.sort_by_key(|&(p, _)| std::cmp::Reverse(p));
        }
        marks
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marks_come_in_travel_order_with_their_positions() {
        let stage = Stage::demo();
        let marks = stage.marks(0, -2_600);
        assert_eq!(
            marks,
            vec![
                (-750, Mark::Index),
                (-1_000, Mark::Home(true)),
                (-1_750, Mark::Index),
                (-2_001, Mark::Home(false)),
            ]
        );
        let back = stage.marks(-2_600, -900);
        assert_eq!(
            back,
            vec![
                (-2_000, Mark::Home(true)),
                (-1_750, Mark::Index),
                (-999, Mark::Home(false)),
            ]
        );
    }

    #[test]
    fn limits_close_at_their_switching_points() {
        let stage = Stage::demo();
        assert_eq!(
            stage.marks(99_990, 100_010),
            vec![(100_000, Mark::PlusLimit(true))]
        );
        assert!(stage.plus_limit_at(100_000));
        assert!(!stage.plus_limit_at(99_999));
        assert_eq!(
            stage.marks(-100_005, -99_000),
            vec![(-99_999, Mark::MinusLimit(false)), (-99_750, Mark::Index)]
        );
    }

    #[test]
    fn swapped_limits_turn_on_the_other_input_at_each_end() {
        let mut stage = Stage::demo();
        stage.limits_swapped = true;
        assert!(stage.minus_limit_at(100_000) && !stage.plus_limit_at(100_000));
        assert!(stage.plus_limit_at(-100_000) && !stage.minus_limit_at(-100_000));
        assert_eq!(
            stage.marks(99_990, 100_010),
            vec![(100_000, Mark::MinusLimit(true))]
        );
        assert_eq!(stage.within_stops(200_000), DEMO_END_STOP);
        assert_eq!(stage.within_stops(-200_000), -DEMO_END_STOP);
        assert_eq!(Stage::bare().within_stops(200_000), 200_000);
    }

    #[test]
    fn index_and_encoder() {
        let mut stage = Stage::demo();
        assert!(stage.index_at(250));
        assert!(stage.index_at(-750));
        assert!(!stage.index_at(0));
        stage.encoder_ratio = 4.0;
        assert_eq!(stage.encoder_at(-25), -100);
    }
}
