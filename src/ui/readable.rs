//! Numbers at a rate a technician can read.
//!
//! The status is polled 20 times a second, and a moving axis changes its
//! position digits at every poll: the last three of them blur, and each
//! change cost the terminal a frame (bench/console_cost.py: 1.5 KB/s for
//! one axis). Nobody reads digits that change more than a few times a
//! second; digital indicators refresh theirs 2 to 5 times a second for
//! that reason. [`ReadableRate`] holds what a pane shows and lets numbers
//! through at most every [`READABLE_PERIOD`] (5 a second, as fast as the
//! slow status items are polled: load, switches); whatever else changes (a
//! lamp, an error, the motion state) goes through at once, and with it
//! the numbers of that moment. A change after a quiet spell shows at
//! once; changes within the period are coalesced and the last of them is
//! shown when the period is over (the pane asks to be woken for it), so
//! nothing is lost, only delayed by at most the period.

use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::session::AxisStatus;

/// At most this often the numbers a pane shows change: 5 times a second.
pub const READABLE_PERIOD: Duration = Duration::from_millis(200);

/// How what a pane would show now differs from what it shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Difference {
    None,
    /// Numbers only: they wait for their turn.
    Numbers,
    /// Something else (a lamp, a flag, another module): shown at once.
    State,
}

/// What [`ReadableRate::offer`] did with a new value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Offer {
    /// Nothing changed that is shown.
    Same,
    /// The value is shown now.
    Shown,
    /// Held: show it (or whatever is newer) after this long.
    Later(Duration),
}

/// What a pane shows of a value that changes faster than it can be read.
#[derive(Debug, Clone)]
pub struct ReadableRate<T> {
    shown: Option<T>,
    /// When numbers last changed on the screen.
    since: Option<Instant>,
    period: Duration,
}

impl<T: Clone> Default for ReadableRate<T> {
    fn default() -> Self {
        ReadableRate::new(READABLE_PERIOD)
    }
}

impl<T: Clone> ReadableRate<T> {
    pub fn new(period: Duration) -> ReadableRate<T> {
        ReadableRate {
            shown: None,
            since: None,
            period,
        }
    }

    /// What is shown (`None` before the first offer).
    pub fn shown(&self) -> Option<&T> {
        self.shown.as_ref()
    }

    /// Forget what is shown: the next offer is shown at once.
    pub fn reset(&mut self) {
        self.shown = None;
        self.since = None;
    }

    /// The value now is `live` (at `now`); `difference` says how it
    /// differs from what is shown.
    pub fn offer(
        &mut self,
        live: &T,
        now: Instant,
        difference: impl FnOnce(&T, &T) -> Difference,
    ) -> Offer {
        let kind = match &self.shown {
            None => Difference::State,
            Some(shown) => difference(shown, live),
        };
        match kind {
            Difference::None => Offer::Same,
            Difference::State => {
                self.show(live, now);
                Offer::Shown
            }
            Difference::Numbers => {
                let waited = self.since.map(|since| now.saturating_duration_since(since));
                match waited {
                    Some(waited) if waited < self.period => Offer::Later(self.period - waited),
                    _ => {
                        self.show(live, now);
                        Offer::Shown
                    }
                }
            }
        }
    }

    /// The wake-up asked for by [`Offer::Later`] came: its period is
    /// over (a timer never fires early), show `live`.
    pub fn catch_up(&mut self, live: &T, now: Instant) {
        self.show(live, now);
    }

    fn show(&mut self, live: &T, now: Instant) {
        self.shown = Some(live.clone());
        self.since = Some(now);
    }
}

/// Where a pane's "now" comes from: the wall clock, or a test's hand.
#[derive(Clone)]
pub struct PaneClock(pub Arc<dyn Fn() -> Instant + Send + Sync>);

impl PaneClock {
    pub fn now(&self) -> Instant {
        (self.0)()
    }
}

impl Default for PaneClock {
    fn default() -> Self {
        PaneClock(Arc::new(Instant::now))
    }
}

impl std::fmt::Debug for PaneClock {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("PaneClock")
    }
}

/// How the axes' status now differs from the status shown: the values
/// that count as numbers (positions, speeds, load, following error, the
/// refresh rate) wait; a lamp, a flag, the motion state or another set of
/// axes does not.
pub fn status_difference(shown: &[AxisStatus], live: &[AxisStatus]) -> Difference {
    if shown == live {
        return Difference::None;
    }
    let without_numbers = |s: &AxisStatus| AxisStatus {
        position: None,
        target: None,
        speed: None,
        max_speed: None,
        own_max_speed: None,
        global_max_speed: None,
        load: None,
        following_error: None,
        refresh: None,
        // The position a session recording keeps as rest evidence is a
        // number too (it changes at every poll while the axis moves);
        // whether the axis is at rest shows in `motion()` below.
        rest_reads: s
            .rest_reads
            .iter()
            .map(|r| match r.sign {
                crate::session::RestSign::Position => crate::session::RestRead {
                    at_rest: None,
                    ..r.clone()
                },
                _ => r.clone(),
            })
            .collect(),
        watched: s
            .watched
            .iter()
            .map(|w| crate::session::WatchedValue {
                value: None,
                reply: None,
                ..w.clone()
            })
            .collect(),
        ..s.clone()
    };
    // What the axis does (moving, stopped short, at its target) is read
    // from its numbers too, and is no number: it goes through at once.
    let numbers_only = shown.len() == live.len()
        && shown
            .iter()
            .zip(live)
            .all(|(a, b)| without_numbers(a) == without_numbers(b) && a.motion() == b.motion());
    if numbers_only {
        Difference::Numbers
    } else {
        Difference::State
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_position_kept_as_rest_evidence_is_a_number() {
        use crate::session::{RestRead, RestSign};
        let status = |position: i64, at_rest: Option<&str>| AxisStatus {
            position: Some(position),
            target: Some(0),
            rest_reads: vec![
                RestRead {
                    line: "GAP 1, 0".into(),
                    sign: RestSign::Position,
                    at_rest: Some(position.to_string()),
                },
                RestRead {
                    line: "GAP 3, 0".into(),
                    sign: RestSign::Speed,
                    at_rest: at_rest.map(str::to_string),
                },
            ],
            ..AxisStatus::default()
        };
        assert_eq!(
            status_difference(&[status(100, None)], &[status(200, None)]),
            Difference::Numbers
        );
        // The speed's evidence changing is no number.
        assert_eq!(
            status_difference(&[status(100, None)], &[status(100, Some("0"))]),
            Difference::State
        );
    }

    /// Values are (state, number).
    fn difference(shown: &(u8, i64), live: &(u8, i64)) -> Difference {
        if shown.0 != live.0 {
            Difference::State
        } else if shown.1 != live.1 {
            Difference::Numbers
        } else {
            Difference::None
        }
    }

    #[test]
    fn numbers_within_the_period_are_coalesced_and_the_last_is_shown_after_it() {
        let t0 = Instant::now();
        let ms = |n: u64| t0 + Duration::from_millis(n);
        let mut rate = ReadableRate::new(Duration::from_millis(200));
        assert_eq!(rate.offer(&(0, 1), ms(0), difference), Offer::Shown);
        // A change after a quiet spell shows at once.
        assert_eq!(rate.offer(&(0, 2), ms(500), difference), Offer::Shown);
        // The next ones within the period wait, the wake-up coming due
        // at the period's end whichever of them asked.
        assert_eq!(
            rate.offer(&(0, 3), ms(550), difference),
            Offer::Later(Duration::from_millis(150))
        );
        assert_eq!(
            rate.offer(&(0, 4), ms(600), difference),
            Offer::Later(Duration::from_millis(100))
        );
        assert_eq!(rate.shown(), Some(&(0, 2)));
        // At the period's end the newest value is shown: 3 never was.
        assert_eq!(rate.offer(&(0, 4), ms(700), difference), Offer::Shown);
        assert_eq!(rate.shown(), Some(&(0, 4)));
        assert_eq!(rate.offer(&(0, 4), ms(710), difference), Offer::Same);
    }

    #[test]
    fn anything_but_numbers_is_shown_at_once_with_the_numbers_of_that_moment() {
        let t0 = Instant::now();
        let ms = |n: u64| t0 + Duration::from_millis(n);
        let mut rate = ReadableRate::new(Duration::from_millis(200));
        rate.offer(&(0, 1), ms(0), difference);
        assert!(matches!(
            rate.offer(&(0, 2), ms(20), difference),
            Offer::Later(_)
        ));
        assert_eq!(rate.offer(&(1, 3), ms(40), difference), Offer::Shown);
        assert_eq!(rate.shown(), Some(&(1, 3)));
        rate.reset();
        assert_eq!(rate.offer(&(1, 4), ms(41), difference), Offer::Shown);
    }

    #[test]
    fn positions_and_speeds_are_numbers_lamps_and_flags_are_not() {
        let one = std::slice::from_ref;
        let moving = AxisStatus {
            position: Some(100),
            speed: Some(300),
            left_switch: Some(false),
            ..AxisStatus::default()
        };
        let on = AxisStatus {
            position: Some(180),
            load: Some(20),
            ..moving.clone()
        };
        assert_eq!(
            status_difference(one(&moving), one(&moving)),
            Difference::None
        );
        assert_eq!(
            status_difference(one(&moving), one(&on)),
            Difference::Numbers
        );
        let switch = AxisStatus {
            left_switch: Some(true),
            ..on.clone()
        };
        assert_eq!(
            status_difference(one(&moving), one(&switch)),
            Difference::State
        );
        assert_eq!(
            status_difference(one(&moving), &[moving.clone(), on]),
            Difference::State
        );
        // The speed falling to 0: the axis stopped, which shows at once.
        let stopped = AxisStatus {
            speed: Some(0),
            ..moving.clone()
        };
        assert_eq!(
            status_difference(one(&moving), one(&stopped)),
            Difference::State
        );
    }
}
