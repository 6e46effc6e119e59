//! Contour mode (manual Ch6 CM, Ch7 CP, CA, CR, RR, CD, VV, VA, VD, SN, NS,
//! GO, TX): axes in a group move together along lines and arcs, driven by
//! the controlling axis.
//!
//! `aCPn` must be the first command of its line or macro, and the rest of
//! it is the path command: MA/MR/GH give the end of each axis (each with
//! its own axis number, −10 without), CA/CR the arc centre, RR the radius,
//! VV the vector velocity stored with the move, CD (user-defined moves,
//! last) the distance along the path from its start. A move runs at once,
//! or waits in the buffer for GO while synchronisation is on (SN).
//!
//! Choices: each move speeds up at VA and slows down at VD to a stop at
//! its end (moves are not blended); GO1 (cubic spline) runs the buffer as
//! lines; the ending angles EA/ER are not simulated; a limit trip of any
//! axis of a moving group stops the whole group at once (or turns it off,
//! LM 0).

use std::collections::{BTreeMap, VecDeque};
use std::f64::consts::TAU;

use super::Mccl;
use super::axis::Mode;
use super::axis::profile::{Phase, Rates, trapezoid_step};
use super::errors::Code;
use super::interpreter::{Flow, Interpreter};
use super::lexer::Command;

/// The contour buffer holds 128 moves (Ch7 SN, for cubic splines).
pub const BUFFER: usize = 128;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Path {
    Linear,
    Arc {
        /// The two axes of the arc, first = x.
        axes: (u8, u8),
        centre: (f64, f64),
        radius: f64,
        start_angle: f64,
        /// Signed sweep, radians (negative = clockwise).
        sweep: f64,
    },
}

/// One move of a contour path, in counts.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    pub path: Path,
    /// Each axis' end.
    pub ends: Vec<(u8, f64)>,
    pub length: f64,
    /// VV at the time, counts per second of the controlling axis.
    pub velocity: f64,
    /// TX counts 1 for a line or user move, 2 for an arc (Ch8 TX).
    pub counts: u32,
}

#[derive(Debug, Clone, PartialEq)]
struct Running {
    segment: Segment,
    starts: Vec<(u8, f64)>,
    travelled: f64,
    speed: f64,
}

/// One contour group, named by its controlling axis.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Group {
    pub sync: bool,
    /// GO given: run the buffer.
    pub going: bool,
    pub queue: VecDeque<Segment>,
    running: Option<Running>,
    /// CD values are from the path's start (Ch7 CD example).
    pub distance: f64,
}

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Contours {
    groups: BTreeMap<u8, Group>,
}

impl Contours {
    pub fn group(&self, controller: u8) -> Option<&Group> {
        self.groups.get(&controller)
    }
}

impl Mccl {
    /// CM n: axis `n` joins the group of controlling axis `controller`.
    pub(super) fn contour_mode(&mut self, n: u8, controller: i64) -> Result<Flow, Code> {
        let controller = u8::try_from(controller).map_err(|_| Code::PARAMETER)?;
        if self.axis(controller).is_none() {
            return Err(Code::AXIS_NOT_ASSIGNED);
        }
        let axis = self.axis_mut(n).ok_or(Code::AXIS_NOT_ASSIGNED)?;
        if matches!(axis.mode, Mode::Contour(c) if c != controller) {
            return Err(Code::AXIS_ALREADY_ASSIGNED);
        }
        axis.mode = Mode::Contour(controller);
        axis.running = false;
        axis.plan = None;
        axis.slave = None;
        axis.target = axis.optimal;
        if n == controller {
            axis.contour_count = 0;
            self.contours.groups.insert(controller, Group::default());
        } else {
            self.contours.groups.entry(controller).or_default();
        }
        Ok(Flow::Next)
    }

    /// PM/VM on a contour axis: it leaves the group; the controlling axis
    /// leaving ends the group's path.
    pub(super) fn leave_contour(&mut self, n: u8) {
        if let Some(Mode::Contour(controller)) = self.axis(n).map(|a| a.mode) {
            if controller == n {
                self.contours.groups.remove(&n);
            }
            if let Some(axis) = self.axis_mut(n) {
                axis.phase = Phase::Idle;
                axis.velocity = 0.0;
                axis.target = axis.optimal;
            }
        }
    }

    /// The contour group axis `n` controls, if it does.
    fn controlled_group(&mut self, n: u8) -> Option<&mut Group> {
        match self.axis(n)?.mode {
            Mode::Contour(c) if c == n => self.contours.groups.get_mut(&n),
            _ => None,
        }
    }

    /// SN / NS on the controlling axis.
    pub(super) fn set_sync(&mut self, n: u8, on: bool) -> Result<Flow, Code> {
        let group = self.controlled_group(n).ok_or(Code::CONTOUR_PARAMETER)?;
        group.sync = on;
        if !on {
            group.going = false;
        }
        Ok(Flow::Next)
    }

    /// GO on a controlling axis: run the buffer.
    pub(super) fn contour_go(&mut self, n: u8) -> bool {
        match self.controlled_group(n) {
            Some(group) => {
                group.going = true;
                true
            }
            None => false,
        }
    }

    /// `aCPn,…`: the path command made of the rest of the sequence.
    pub(super) fn contour_path(
        &mut self,
        interp: &Interpreter,
        n: u8,
        kind: i64,
    ) -> Result<Flow, Code> {
        let Some(frame) = interp.frames.last() else {
            return Ok(Flow::Next);
        };
        if self.controlled_group(n).is_none() {
            return Err(Code::CONTOUR_PARAMETER);
        }
        let program = frame.program.clone();
        let members = &program.commands[frame.pc + 1..];
        let segment = self.segment(n, kind, members)?;
        let group = self.controlled_group(n).ok_or(Code::CONTOUR_PARAMETER)?;
        if group.queue.len() >= BUFFER {
            return Err(Code::NO_MEMORY);
        }
        group.queue.push_back(segment);
        // The path command is the whole sequence.
        Ok(Flow::EndFrame)
    }

    /// Read the commands of a path command into a move.
    fn segment(&mut self, controller: u8, kind: i64, members: &[Command]) -> Result<Segment, Code> {
        let allowed: &[&str] = match kind {
            0 => &["CD", "GH", "MA", "MR", "VV"],
            1 => &["GH", "MA", "MR", "VV"],
            _ => &["CA", "CR", "GH", "MA", "MR", "VV", "RR", "EA", "ER"],
        };
        let mut ends: Vec<(u8, f64)> = Vec::new();
        let mut centres: Vec<(u8, f64)> = Vec::new();
        let mut radius = None;
        let mut distance = None;
        let mut velocity = self
            .axis(controller)
            .map_or(0.0, |a| a.settings.vector_velocity);
        for (i, command) in members.iter().enumerate() {
            let mnemonic = command.mnemonic();
            if !allowed.contains(&mnemonic) {
                return Err(Code::CONTOUR_PARAMETER);
            }
            if !command.spec.simulated {
                return Err(Code::NOT_SUPPORTED);
            }
            let value = match &command.param {
                super::lexer::Param::Int(n) => *n as f64,
                super::lexer::Param::Real(x) => *x,
                super::lexer::Param::None => 0.0,
                _ => return Err(Code::CONTOUR_PARAMETER),
            };
            match mnemonic {
                "VV" => {
                    velocity = value;
                    if let Some(a) = self.axis_mut(controller) {
                        a.settings.vector_velocity = value;
                    }
                    continue;
                }
                "CD" => {
                    if i + 1 != members.len() {
                        return Err(Code::CONTOUR_PARAMETER);
                    }
                    distance = Some(value);
                    continue;
                }
                "RR" => {
                    radius = Some(value);
                    continue;
                }
                _ => {}
            }
            let n = command
                .axis
                .and_then(|a| u8::try_from(a).ok())
                .filter(|&a| a > 0)
                .ok_or(Code::CONTOUR_NO_AXIS)?;
            let axis = self.axis(n).ok_or(Code::AXIS_NOT_ASSIGNED)?;
            if axis.mode != Mode::Contour(controller) {
                return Err(Code::CONTOUR_PARAMETER);
            }
            let start = self.path_end(controller, n);
            let u = axis.units;
            let (list, point) = match mnemonic {
                "MA" => (&mut ends, u.to_counts(value)),
                "MR" => (&mut ends, start + u.distance_to_counts(value)),
                "GH" => (&mut ends, axis.home_position),
                "CA" => (&mut centres, u.to_counts(value)),
                _ => (&mut centres, start + u.distance_to_counts(value)),
            };
            if list.iter().any(|(a, _)| *a == n) {
                return Err(Code::AXIS_DUPLICATE);
            }
            list.push((n, point));
        }
        if ends.is_empty() {
            return Err(Code::CONTOUR_PARAMETER);
        }
        let starts: Vec<(u8, f64)> = ends
            .iter()
            .map(|&(a, _)| (a, self.path_end(controller, a)))
            .collect();
        let controller_units = self.axis(controller).map(|a| a.units).unwrap_or_default();
        let velocity = controller_units.speed_to_counts(velocity);
        let (path, length, counts) = match kind {
            0 | 1 => {
                let straight = starts
                    .iter()
                    .zip(&ends)
                    .map(|(s, e)| (e.1 - s.1).powi(2))
                    .sum::<f64>()
                    .sqrt();
                let length = match (kind, distance) {
                    (0, Some(cd)) => {
                        let cd = controller_units.distance_to_counts(cd);
                        let previous = self
                            .contours
                            .groups
                            .get(&controller)
                            .map_or(0.0, |g| g.distance);
                        if cd <= previous {
                            return Err(Code::CONTOUR_PARAMETER);
                        }
                        if let Some(g) = self.contours.groups.get_mut(&controller) {
                            g.distance = cd;
                        }
                        cd - previous
                    }
                    (0, None) => return Err(Code::CONTOUR_PARAMETER),
                    _ => straight,
                };
                (Path::Linear, length, 1)
            }
            _ => {
                let clockwise = kind == 2;
                let path = arc(&starts, &ends, &centres, radius, clockwise)?;
                let Path::Arc { radius, sweep, .. } = path else {
                    return Err(Code::CONTOUR_PARAMETER);
                };
                (path, radius * sweep.abs(), 2)
            }
        };
        Ok(Segment {
            path,
            ends,
            length,
            velocity,
            counts,
        })
    }

    /// Where axis `n` will be when the group's moves so far are done.
    fn path_end(&self, controller: u8, n: u8) -> f64 {
        let queued = self.contours.groups.get(&controller).and_then(|g| {
            g.queue
                .iter()
                .rev()
                .chain(g.running.iter().map(|r| &r.segment))
                .find_map(|s| s.ends.iter().find(|(a, _)| *a == n).map(|(_, e)| *e))
        });
        queued.unwrap_or_else(|| self.axis(n).map_or(0.0, |a| a.target))
    }

    /// One tick of every group's path.
    pub(super) fn contour_tick(&mut self, dt: f64) {
        let controllers: Vec<u8> = self.contours.groups.keys().copied().collect();
        for controller in controllers {
            self.group_tick(controller, dt);
        }
    }

    fn group_tick(&mut self, controller: u8, dt: f64) {
        let Some(axis) = self.axis(controller) else {
            return;
        };
        let units = axis.units;
        let s = &axis.settings;
        let acceleration = units.acceleration_to_counts(s.vector_acceleration);
        let deceleration = units.acceleration_to_counts(s.vector_deceleration);
        let override_factor = s.velocity_override;
        let Some(group) = self.contours.groups.get_mut(&controller) else {
            return;
        };
        if group.running.is_none() {
            let may_start = !group.sync || group.going;
            let Some(segment) = may_start.then(|| group.queue.pop_front()).flatten() else {
                if group.queue.is_empty() {
                    group.going = false;
                }
                return;
            };
            let starts = segment
                .ends
                .iter()
                .map(|&(a, _)| {
                    let here = self
                        .axes
                        .get(usize::from(a).saturating_sub(1))
                        .map_or(0.0, |x| x.optimal);
                    (a, here)
                })
                .collect();
            for &(a, end) in &segment.ends {
                if let Some(x) = self.axes.get_mut(usize::from(a).saturating_sub(1)) {
                    x.target = end;
                }
            }
            if let Some(group) = self.contours.groups.get_mut(&controller) {
                group.running = Some(Running {
                    segment,
                    starts,
                    travelled: 0.0,
                    speed: 0.0,
                });
            }
        }
        let Some(group) = self.contours.groups.get_mut(&controller) else {
            return;
        };
        let Some(run) = &mut group.running else {
            return;
        };
        let rates = Rates {
            velocity: run.segment.velocity * override_factor,
            acceleration,
            deceleration,
            minimum: 0.0,
        };
        let (s, v, phase) =
            trapezoid_step(run.travelled, run.speed, run.segment.length, &rates, dt);
        run.travelled = s;
        run.speed = v;
        let fraction = if run.segment.length > 0.0 {
            s / run.segment.length
        } else {
            1.0
        };
        let points: Vec<(u8, f64)> = match run.segment.path {
            Path::Linear => run
                .starts
                .iter()
                .zip(&run.segment.ends)
                .map(|(&(a, from), &(_, to))| (a, from + (to - from) * fraction))
                .collect(),
            Path::Arc {
                axes,
                centre,
                radius,
                start_angle,
                sweep,
            } => {
                let angle = start_angle + sweep * fraction;
                vec![
                    (axes.0, centre.0 + radius * angle.cos()),
                    (axes.1, centre.1 + radius * angle.sin()),
                ]
            }
        };
        let done = phase == Phase::Idle;
        let ends = run.segment.ends.clone();
        let counts = run.segment.counts;
        if done {
            group.running = None;
        }
        for (a, p) in if done { ends } else { points } {
            if let Some(x) = self.axes.get_mut(usize::from(a).saturating_sub(1)) {
                if !x.motor_on {
                    continue;
                }
                x.velocity = (p - x.optimal) / dt;
                x.optimal = p;
                x.phase = if done { Phase::Idle } else { phase };
                x.note_direction();
                if done {
                    x.velocity = 0.0;
                }
            }
        }
        if done && let Some(c) = self.axis_mut(controller) {
            c.contour_count = c.contour_count.wrapping_add(counts);
        }
    }

    /// A member of a moving group tripped: the whole group stops at once
    /// (or turns off, with LM's "motor off").
    pub(super) fn stop_group_of(&mut self, n: u8, off: bool) {
        let Some(Mode::Contour(controller)) = self.axis(n).map(|a| a.mode) else {
            return;
        };
        if let Some(group) = self.contours.groups.get_mut(&controller) {
            group.running = None;
            group.queue.clear();
            group.going = false;
        }
        for axis in &mut self.axes {
            if axis.mode == Mode::Contour(controller) {
                if off {
                    axis.motor_off();
                } else {
                    axis.abort();
                }
            }
        }
    }

    /// Synchronisation of the group of axis `n`: on, and a move waiting.
    pub(super) fn sync_state(&self, n: u8) -> (bool, bool) {
        let Some(Mode::Contour(controller)) = self.axis(n).map(|a| a.mode) else {
            return (false, false);
        };
        self.contours
            .group(controller)
            .map_or((false, false), |g| (g.sync, g.sync && !g.queue.is_empty()))
    }
}

/// The arc from the starts to the ends of two axes, about the centre given
/// (CA/CR) or worked out from RR (positive: the short way, negative: the
/// long way round).
fn arc(
    starts: &[(u8, f64)],
    ends: &[(u8, f64)],
    centres: &[(u8, f64)],
    radius: Option<f64>,
    clockwise: bool,
) -> Result<Path, Code> {
    if ends.len() != 2 {
        return Err(Code::CONTOUR_PARAMETER);
    }
    let (x, y) = (ends[0].0, ends[1].0);
    let (sx, sy) = (starts[0].1, starts[1].1);
    let (ex, ey) = (ends[0].1, ends[1].1);
    let centre = if let Some(rr) = radius {
        let r = rr.abs();
        let (mx, my) = ((sx + ex) / 2.0, (sy + ey) / 2.0);
        let (dx, dy) = (ex - sx, ey - sy);
        let chord = (dx * dx + dy * dy).sqrt();
        if chord == 0.0 || chord > 2.0 * r + 1e-9 {
            return Err(Code::CONTOUR_PARAMETER);
        }
        let h = (r * r - chord * chord / 4.0).max(0.0).sqrt();
        // The centre on the side that makes the sweep short for RR > 0.
        let (nx, ny) = (-dy / chord, dx / chord);
        let side = if clockwise == (rr > 0.0) { -1.0 } else { 1.0 };
        (mx + side * h * nx, my + side * h * ny)
    } else {
        let find = |a: u8| centres.iter().find(|(c, _)| *c == a).map(|(_, v)| *v);
        match (find(x), find(y)) {
            (Some(cx), Some(cy)) if centres.len() == 2 => (cx, cy),
            _ => return Err(Code::CONTOUR_PARAMETER),
        }
    };
    let r = ((sx - centre.0).powi(2) + (sy - centre.1).powi(2)).sqrt();
    let r_end = ((ex - centre.0).powi(2) + (ey - centre.1).powi(2)).sqrt();
    if r == 0.0 || (r - r_end).abs() > (1e-3 * r).max(1.0) {
        return Err(Code::CONTOUR_PARAMETER);
    }
    let start_angle = (sy - centre.1).atan2(sx - centre.0);
    let end_angle = (ey - centre.1).atan2(ex - centre.0);
    let mut sweep = end_angle - start_angle;
    if clockwise {
        while sweep >= 0.0 {
            sweep -= TAU;
        }
    } else {
        while sweep <= 0.0 {
            sweep += TAU;
        }
    }
    Ok(Path::Arc {
        axes: (x, y),
        centre,
        radius: r,
        start_angle,
        sweep,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn the_manuals_half_circle() {
        // Ch7 CA: 1CP2,1CA10000,2CA0,1MA20000,2MA0 from (0, 0): 180° clockwise.
        let path = arc(
            &[(1, 0.0), (2, 0.0)],
            &[(1, 20_000.0), (2, 0.0)],
            &[(1, 10_000.0), (2, 0.0)],
            None,
            true,
        )
        .expect("an arc");
        let Path::Arc { radius, sweep, .. } = path else {
            panic!("not an arc");
        };
        assert_eq!(radius, 10_000.0);
        assert!((sweep + PI).abs() < 1e-9, "{sweep}");
    }

    #[test]
    fn a_radius_gives_the_short_or_long_way() {
        // Ch7 RR: 1CP2,1MR10000,2MR10000,1RR10000 is 90°; -10000 is 270°.
        for (rr, expected) in [(10_000.0, PI / 2.0), (-10_000.0, 3.0 * PI / 2.0)] {
            let path = arc(
                &[(1, 0.0), (2, 0.0)],
                &[(1, 10_000.0), (2, 10_000.0)],
                &[],
                Some(rr),
                true,
            )
            .expect("an arc");
            let Path::Arc { sweep, .. } = path else {
                panic!("not an arc");
            };
            assert!((sweep.abs() - expected).abs() < 1e-9, "RR{rr}: {sweep}");
        }
        assert!(
            arc(
                &[(1, 0.0), (2, 0.0)],
                &[(1, 30_000.0), (2, 0.0)],
                &[],
                Some(10_000.0),
                true
            )
            .is_err(),
            "the chord is longer than the diameter"
        );
    }
}
