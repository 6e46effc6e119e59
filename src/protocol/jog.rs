//! How a family's axis is jogged by hand (the console's bring-up pane): a
//! step of a given distance, a run in one direction until told to stop,
//! and the stop. Each family gives the console lines it would type for
//! them (so they are checked, sent and shown as any typed line), from its
//! manual; the pane decides when (its deadman, its keys), never how.

use super::console::{AxisFlag, AxisInfo};

/// Which way a jog goes, in the axis's own count direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Counts up.
    Positive,
    /// Counts down.
    Negative,
}

impl Direction {
    /// `+` or `-`.
    pub fn sign(self) -> &'static str {
        match self {
            Direction::Positive => "+",
            Direction::Negative => "-",
        }
    }

    /// `distance` with this direction's sign.
    pub fn signed(self, distance: i64) -> i64 {
        match self {
            Direction::Positive => distance.abs(),
            Direction::Negative => -distance.abs(),
        }
    }
}

/// A family's way of jogging one axis: console lines, as typed.
pub trait JogPlan: Sync {
    /// The lines that move `axis` by `distance` (position counts, signed)
    /// from `standing_at` (its position, read while it stands) at `speed`
    /// (the family's speed unit); why not, for a speed or a target the
    /// family cannot take.
    fn step(
        &self,
        axis: &AxisInfo,
        standing_at: i64,
        distance: i64,
        speed: i64,
    ) -> Result<Vec<String>, JogError>;

    /// The lines that turn `axis` on in `direction` at `speed` until
    /// [`JogPlan::stop`].
    fn run(
        &self,
        axis: &AxisInfo,
        direction: Direction,
        speed: i64,
    ) -> Result<Vec<String>, JogError>;

    /// The lines that stop `axis` (with its deceleration).
    fn stop(&self, axis: &AxisInfo) -> Vec<String>;

    /// The lines that let `axis` move again after a limit switch stopped
    /// it, where the module latches that stop as an error; none by
    /// default.
    fn clear_limit_stop(&self, axis: &AxisInfo) -> Vec<String> {
        let _ = axis;
        Vec::new()
    }

    /// Why `axis` would not move now, judged from the driver lamps its
    /// status last lit (`lit`), and what makes it ready: a jog the module
    /// takes without an error but that turns nothing (a servo whose
    /// motor is off). `None` (the default): nothing known stands in the
    /// way.
    fn not_ready(&self, axis: &AxisInfo, lit: &[AxisFlag]) -> Option<String> {
        let _ = (axis, lit);
        None
    }

    /// The speeds offered, slowest first, in [`JogPlan::speed_unit`].
    fn speeds(&self) -> &'static [i64];

    /// The unit of a speed ("pps", "counts/s", "velocity units").
    fn speed_unit(&self) -> &'static str;

    /// What a jog writes besides moving, said on the pane so that nothing
    /// is changed unseen (a speed setting a step writes).
    fn side_effects(&self) -> &'static str;
}

/// The step distances the pane offers, in position counts.
pub const STEP_DISTANCES: &[i64] = &[1, 10, 100, 1_000, 10_000, 100_000];

/// Why a jog was not planned: a speed or a target the family cannot take.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum JogError {
    #[error("a jog speed of {speed} is outside {}..{}", range.start(), range.end())]
    Speed {
        speed: i64,
        range: std::ops::RangeInclusive<i64>,
    },
    #[error(
        "a step of {distance} from {from} ends at {target}, outside {}..{}",
        range.start(),
        range.end()
    )]
    Target {
        from: i64,
        distance: i64,
        target: i64,
        range: std::ops::RangeInclusive<i64>,
    },
}

impl From<JogError> for String {
    fn from(error: JogError) -> String {
        error.to_string()
    }
}

/// `speed` if it lies in `range`, else why not.
pub fn speed_within(speed: i64, range: std::ops::RangeInclusive<i64>) -> Result<i64, JogError> {
    if range.contains(&speed) {
        Ok(speed)
    } else {
        Err(JogError::Speed { speed, range })
    }
}

/// `from + distance` if it stays in `range` (a target register's width).
pub fn target_within(
    from: i64,
    distance: i64,
    range: std::ops::RangeInclusive<i64>,
) -> Result<i64, JogError> {
    let target = from.saturating_add(distance);
    if range.contains(&target) {
        Ok(target)
    } else {
        Err(JogError::Target {
            from,
            distance,
            target,
            range,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::FAMILIES;

    /// Every family can be jogged, and every line of its plan is one its
    /// own console takes (parses and validates) for every axis.
    #[test]
    fn every_familys_jog_lines_are_lines_its_console_takes() {
        for family in FAMILIES {
            let console = family.console;
            let plan = console
                .jog()
                .unwrap_or_else(|| panic!("{} has no jog plan", family.name));
            let address = console.default_address();
            let speed = plan.speeds()[0];
            for axis in console.axes() {
                let mut lines = plan.step(axis, 1000, -100, speed).expect("a step");
                lines.extend(plan.run(axis, Direction::Positive, speed).expect("a run"));
                lines.extend(plan.run(axis, Direction::Negative, speed).expect("a run"));
                lines.extend(plan.stop(axis));
                lines.extend(plan.clear_limit_stop(axis));
                for line in lines {
                    assert!(
                        console.prepare(&line, address).is_ok(),
                        "{}: {line}: {:?}",
                        family.name,
                        console.prepare(&line, address).err()
                    );
                }
            }
            for speed in plan.speeds() {
                assert!(
                    plan.run(&console.axes()[0], Direction::Positive, *speed)
                        .is_ok()
                );
            }
        }
    }
}
