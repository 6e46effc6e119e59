//! The guided wiring check of the bring-up: jog an axis toward each end of
//! its travel and see which limit switch fires, whether the module stops
//! the axis at it, and where; where the home switch is on the way. Generic
//! over the family: the jog lines are its [`JogPlan`], the switches its
//! status poll's (`AxisStatus::left_switch`, `right_switch`,
//! `home_switch`).
//!
//! [`Session::check_wiring`] moves the axis and records what it saw
//! ([`Leg`]); [`findings`] turns that into plain lines, pure, so that a
//! swapped switch or an inverted direction is judged the same way whether
//! the observations came from a machine or a test.

use std::time::Duration;

use tokio::time::Instant;

use super::{Session, SessionError};
use crate::protocol::jog::{Direction, JogPlan};

/// How often the switches are read while the axis travels.
const LOOK_EVERY: Duration = Duration::from_millis(20);

/// How long a stopped jog may take to come to rest.
const STAND_WAIT: Duration = Duration::from_secs(5);

/// How long after a switch fired the module has to stop the axis by
/// itself before the check stops it.
const MODULE_STOP_GRACE: Duration = Duration::from_millis(300);

/// Which limit switch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// The left (−) switch.
    Negative,
    /// The right (+) switch.
    Positive,
}

impl Limit {
    fn of(direction: Direction) -> Limit {
        match direction {
            Direction::Positive => Limit::Positive,
            Direction::Negative => Limit::Negative,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Limit::Negative => "the − (left) switch",
            Limit::Positive => "the + (right) switch",
        }
    }
}

/// What one leg of the check saw: a jog in `direction` until a limit
/// switch fired or `give_up` passed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Leg {
    pub direction: Direction,
    /// Where the axis was when the jog started.
    pub from: Option<i64>,
    /// The switch that fired first, and where.
    pub fired: Option<(Limit, Option<i64>)>,
    /// Switches already active before the jog started (but the one the
    /// leg before ended on: the axis starts from it).
    pub active_at_start: Vec<Limit>,
    /// The module stood the axis by itself at the switch (within
    /// [`MODULE_STOP_GRACE`]); false when the check had to stop it.
    pub stopped_by_module: bool,
    /// Where the axis came to rest.
    pub rest: Option<i64>,
    /// Positions where the home switch was seen active during the leg.
    pub home_seen: Option<(i64, i64)>,
    /// The farthest the axis went between two reads of the switches: a
    /// switch narrower than that may pass unseen.
    pub read_spacing: Option<i64>,
    /// The module refused the jog (its answer): a module that will not
    /// move toward a limit switch that is on (CMD-4CR `?Error -Limit`).
    pub refused: Option<String>,
}

/// How far from where a leg started its axis may come to rest and still
/// have stood still: an encoder's count either way, a servo dithering as
/// it holds or coasting the last count to rest after a trip. Read a few
/// milliseconds sooner or later (the MultiFlex's status of all axes in
/// one line), an unpowered servo read 58260 at the start and 58259 at
/// the end of a leg it never moved in.
pub const STANDING_DITHER: i64 = 1;

impl Leg {
    /// The axis did not move under the jog: it came to rest within
    /// [`STANDING_DITHER`] of where it started.
    pub fn stood_still(&self) -> bool {
        matches!(
            (self.from, self.rest),
            (Some(from), Some(rest)) if (rest - from).abs() <= STANDING_DITHER
        )
    }
}

/// Plain lines of what the legs show, one each, for the axis `axis`:
/// which switch fired for which direction, and what that means.
pub fn findings(axis: &str, legs: &[Leg]) -> Vec<String> {
    let mut lines = Vec::new();
    let at = |p: Option<i64>| p.map_or_else(|| "an unread position".to_string(), |p| p.to_string());
    for leg in legs {
        let going = format!("{axis}, moving {}", leg.direction.sign());
        for limit in &leg.active_at_start {
            lines.push(format!(
                "{going}: {} was already active before the jog (at its end already, or a \
                 normally-closed switch read with the wrong polarity)",
                limit.name()
            ));
        }
        if let Some(why) = &leg.refused {
            lines.push(format!(
                "{going}: the module refused to move ({why}): is a switch of this direction on \
                 where it should not be?"
            ));
            continue;
        }
        match leg.fired {
            // Nothing moved: no switch could fire, and "check the switch"
            // would send the technician to the wrong place.
            None if leg.stood_still() => lines.push(format!(
                "{going}: the axis did not move (it stood at {}): is its motor on, or did a \
                 trip (following error, a latched stop) hold it?",
                at(leg.from)
            )),
            None => lines.push(format!(
                "{going}: no limit switch fired before the check gave up (from {} to {}): \
                 check the switch and its wiring",
                at(leg.from),
                at(leg.rest)
            )),
            Some((limit, position)) if limit == Limit::of(leg.direction) => {
                let stop = if leg.stopped_by_module {
                    "the module stopped the axis at it"
                } else {
                    "the module did NOT stop the axis (the check stopped it): is the switch \
                     enabled as a limit?"
                };
                lines.push(format!(
                    "{going}: {} fired at {}, as it should; {stop}",
                    limit.name(),
                    at(position)
                ));
            }
            Some((limit, position)) => lines.push(format!(
                "{going} tripped {} at {}: swapped wiring or inverted direction",
                limit.name(),
                at(position)
            )),
        }
    }
    let home = legs
        .iter()
        .filter_map(|leg| leg.home_seen)
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)));
    lines.push(match home {
        Some((low, high)) => format!(
            "{axis}: the home switch was seen active between {low} and {high} (read while \
             moving: its edges are only as exact as the reads)"
        ),
        None => match legs.iter().filter_map(|leg| leg.read_spacing).max() {
            Some(spacing) => format!(
                "{axis}: the home switch was not seen active (the switches were read up to \
                 {spacing} apart: a narrower switch can pass unseen; jog slower to look again)"
            ),
            None => format!("{axis}: the home switch was not seen active"),
        },
    });
    lines
}

/// Whether the findings found nothing wrong: each leg's own switch fired
/// and the module stopped the axis at it.
pub fn wired_right(legs: &[Leg]) -> bool {
    legs.iter().all(|leg| {
        leg.active_at_start.is_empty()
            && leg.refused.is_none()
            && leg.stopped_by_module
            && leg
                .fired
                .is_some_and(|(limit, _)| limit == Limit::of(leg.direction))
    })
}

/// The findings of each faulty leg (without the home switch's line, said
/// of the whole check): what a commissioning sheet's verdict names. Empty
/// when [`wired_right`].
pub fn faults(axis: &str, legs: &[Leg]) -> Vec<String> {
    legs.iter()
        .filter(|leg| !wired_right(std::slice::from_ref(leg)))
        .flat_map(|leg| {
            let mut lines = findings(axis, std::slice::from_ref(leg));
            lines.pop();
            lines
        })
        .collect()
}

impl Session {
    /// Jog axis `axis` (index into [`Session::axes`]) with `plan` at
    /// `speed` toward + until a limit switch fires, then toward −; each
    /// leg gives up after `give_up`. The axis is stopped at the end of
    /// each leg whatever happened; an error stops it too.
    pub async fn check_wiring(
        &self,
        plan: &dyn JogPlan,
        axis: usize,
        speed: i64,
        give_up: Duration,
    ) -> Result<Vec<Leg>, SessionError> {
        let mut legs: Vec<Leg> = Vec::new();
        for direction in [Direction::Positive, Direction::Negative] {
            let left_on = legs
                .last()
                .and_then(|leg| leg.fired.map(|(limit, _)| limit));
            let leg = self
                .wiring_leg(plan, axis, direction, speed, give_up, left_on)
                .await;
            let stopped = self.stop_jog(plan, axis).await;
            legs.push(leg?);
            stopped?;
        }
        Ok(legs)
    }

    async fn wiring_leg(
        &self,
        plan: &dyn JogPlan,
        axis: usize,
        direction: Direction,
        speed: i64,
        give_up: Duration,
        left_on: Option<Limit>,
    ) -> Result<Leg, SessionError> {
        let info = *self.axes().get(axis).ok_or_else(|| SessionError::Refused {
            line: String::new(),
            message: format!("the module has no axis {axis}"),
        })?;
        let before = self.read_status_polls(false).await?;
        let status = before.get(axis).cloned().unwrap_or_default();
        let mut leg = Leg {
            direction,
            from: status.position,
            fired: None,
            active_at_start: [
                (Limit::Negative, status.left_switch),
                (Limit::Positive, status.right_switch),
            ]
            .into_iter()
            .filter(|(limit, on)| *on == Some(true) && Some(*limit) != left_on)
            .map(|(limit, _)| limit)
            .collect(),
            stopped_by_module: false,
            rest: None,
            home_seen: None,
            read_spacing: None,
            refused: None,
        };
        // The switch the last leg fired, while it stays active from the
        // start: the axis rests on it, so it is no finding of this leg.
        // Once read inactive, the axis has left it, and meeting it again
        // (an axis that ran on past a switch wired to the other input) is.
        let mut still_on = left_on.filter(|limit| match limit {
            Limit::Negative => status.left_switch == Some(true),
            Limit::Positive => status.right_switch == Some(true),
        });
        let mut last_position = status.position;
        let lines = plan
            .run(&info, direction, speed)
            .map_err(|message| SessionError::Refused {
                line: String::new(),
                message: message.to_string(),
            })?;
        for line in &lines {
            match self.execute_line(line).await {
                Ok(_) => {}
                // The module's own no: a finding, not a failure of the check.
                Err(SessionError::Reply { error, .. }) => {
                    leg.refused = Some(error.to_string());
                    leg.rest = last_position;
                    return Ok(leg);
                }
                Err(other) => return Err(other),
            }
        }
        let started = Instant::now();
        loop {
            tokio::time::sleep(LOOK_EVERY).await;
            let now = self.read_status_polls(false).await?;
            let status = now.get(axis).cloned().unwrap_or_default();
            if let (Some(before), Some(at)) = (last_position, status.position) {
                let moved = (at - before).abs();
                leg.read_spacing = Some(leg.read_spacing.map_or(moved, |s| s.max(moved)));
            }
            last_position = status.position;
            if status.home_switch == Some(true)
                && let Some(p) = status.position
            {
                leg.home_seen = Some(match leg.home_seen {
                    Some((low, high)) => (low.min(p), high.max(p)),
                    None => (p, p),
                });
            }
            let switches = [
                (Limit::Negative, status.left_switch),
                (Limit::Positive, status.right_switch),
            ];
            if still_on.is_some_and(|held| switches.contains(&(held, Some(false)))) {
                still_on = None;
            }
            let fired = switches.into_iter().find(|(limit, on)| {
                *on == Some(true)
                    && !leg.active_at_start.contains(limit)
                    && Some(*limit) != still_on
            });
            if let Some((limit, _)) = fired {
                leg.fired = Some((limit, status.position));
                break;
            }
            if started.elapsed() >= give_up {
                leg.rest = status.position;
                return Ok(leg);
            }
        }
        // Does the module stand the axis by itself at the switch?
        let fired_at = Instant::now();
        loop {
            let now = self.read_status_polls(false).await?;
            let status = now.get(axis).cloned().unwrap_or_default();
            let standing = status.speed == Some(0);
            if standing {
                leg.stopped_by_module = true;
                leg.rest = status.position;
                return Ok(leg);
            }
            if fired_at.elapsed() >= MODULE_STOP_GRACE {
                leg.rest = status.position;
                return Ok(leg);
            }
            tokio::time::sleep(LOOK_EVERY).await;
        }
    }

    /// Stop a jog of axis `axis` with `plan`'s stop lines, wait (at most
    /// [`STAND_WAIT`]) for it to stand, and clear a limit stop the module
    /// latched, so that the next leg may move.
    async fn stop_jog(&self, plan: &dyn JogPlan, axis: usize) -> Result<(), SessionError> {
        let Some(info) = self.axes().get(axis) else {
            return Ok(());
        };
        for line in plan.stop(info) {
            self.execute_line(&line).await?;
        }
        // Still moving after the wait: the limit stop is cleared anyway,
        // and the next leg's jog is the module's to refuse.
        self.wait_standing(axis, STAND_WAIT).await?;
        for line in plan.clear_limit_stop(info) {
            self.execute_line(&line).await?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn leg(direction: Direction, fired: Option<Limit>, stopped: bool) -> Leg {
        Leg {
            direction,
            from: Some(0),
            fired: fired.map(|limit| (limit, Some(200_000))),
            active_at_start: Vec::new(),
            stopped_by_module: stopped,
            rest: Some(200_010),
            home_seen: None,
            read_spacing: Some(1500),
            refused: None,
        }
    }

    #[test]
    fn each_switch_against_its_own_direction_is_right() {
        let legs = [
            leg(Direction::Positive, Some(Limit::Positive), true),
            leg(Direction::Negative, Some(Limit::Negative), true),
        ];
        assert!(wired_right(&legs));
        let said = findings("motor 0", &legs);
        assert!(said[0].contains("moving +: the + (right) switch fired at 200000, as it should"));
        assert!(said[0].contains("the module stopped the axis at it"));
    }

    #[test]
    fn a_switch_against_the_direction_of_travel_is_swapped_wiring() {
        let legs = [
            leg(Direction::Positive, Some(Limit::Negative), true),
            leg(Direction::Negative, Some(Limit::Positive), true),
        ];
        assert!(!wired_right(&legs));
        let said = findings("X", &legs);
        assert_eq!(
            said[0],
            "X, moving + tripped the − (left) switch at 200000: swapped wiring or inverted \
             direction"
        );
    }

    #[test]
    fn an_axis_that_did_not_move_is_said_so_not_a_missing_switch() {
        let mut stuck = leg(Direction::Negative, None, false);
        stuck.rest = stuck.from;
        let legs = [leg(Direction::Positive, Some(Limit::Positive), true), stuck];
        let said = findings("1", &legs);
        assert!(said[1].contains("did not move (it stood at 0)"), "{said:?}");
        assert!(!said[1].contains("no limit switch fired"), "{said:?}");
        // A count of dither is standing; two are a move.
        let mut dither = legs.clone();
        dither[1].rest = dither[1].from.map(|p| p - STANDING_DITHER);
        assert!(findings("1", &dither)[1].contains("did not move (it stood at 0)"));
        dither[1].rest = dither[1].from.map(|p| p - STANDING_DITHER - 1);
        assert!(findings("1", &dither)[1].contains("no limit switch fired"));
    }

    #[test]
    fn no_switch_or_no_stop_is_said() {
        let legs = [
            leg(Direction::Positive, None, false),
            leg(Direction::Negative, Some(Limit::Negative), false),
        ];
        assert!(!wired_right(&legs));
        let said = findings("1", &legs);
        assert!(said[0].contains("no limit switch fired"), "{said:?}");
        assert!(said[1].contains("did NOT stop the axis"), "{said:?}");
        assert!(said[2].contains("read up to 1500 apart"), "{said:?}");
    }

    #[test]
    fn a_refused_jog_is_said_with_the_modules_answer() {
        let mut refused = leg(Direction::Negative, None, false);
        refused.refused = Some("?Error -Limit".into());
        let legs = [
            leg(Direction::Positive, Some(Limit::Negative), false),
            refused,
        ];
        assert!(!wired_right(&legs));
        let said = findings("X", &legs);
        assert_eq!(
            said[1],
            "X, moving -: the module refused to move (?Error -Limit): is a switch of this \
             direction on where it should not be?"
        );
    }
}
