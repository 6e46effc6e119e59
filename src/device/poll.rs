//! When each item of a poll plan is due.
//!
//! Each item is polled on a grid of its period, laid from the plan's first
//! poll: a poll sent a little late (the timer woke late, the items before
//! it in the burst were answered first) does not push the next one back.
//! Items of one period therefore stay together and go out as one burst,
//! one after the other's answer, after a single timer wake-up; scheduled
//! from each item's own send time they drifted apart by a round trip each,
//! and a console polling one axis woke for almost every poll on its own.
//!
//! A poll sent later than a quarter of its period lays its grid afresh
//! from its send: on a link too slow for the plan every poll is late, and
//! a grid kept there would make the items of long periods look the most
//! overdue and take turns from the fast ones.

use std::time::Duration;

use tokio::time::Instant;

use super::{Answer, DeviceError, PollItem, PollPlan};

/// A poll plan and when each of its items was last sent.
pub(super) struct PollSchedule {
    plan: PollPlan,
    /// The grid point of each item's last send (see the module docs) and
    /// the number of that send; `None`: never polled, due at once.
    last: Vec<Option<(Instant, u64)>>,
    sends: u64,
    /// The plan's first poll, where every item's grid starts.
    origin: Option<Instant>,
}

impl PollSchedule {
    pub(super) fn new(plan: PollPlan) -> Self {
        let last = vec![None; plan.items.len()];
        PollSchedule {
            plan,
            last,
            sends: 0,
            origin: None,
        }
    }

    /// When item `index` is due (never-polled items at once, others
    /// `every` after the grid point of their last send), and the number of
    /// its last send.
    fn due(&self, index: usize) -> Option<(Instant, u64)> {
        let item = self.plan.items.get(index)?;
        let (last, send) = (*self.last.get(index)?)?;
        Some((last + item.every, send))
    }

    /// The most overdue item and when it is due (`None` inside the pair:
    /// never polled, due now). Of items due at the same time the one sent
    /// longest ago goes first, so items take turns even when answers take
    /// no time at all.
    pub(super) fn next(&self) -> Option<(usize, Option<Instant>)> {
        (0..self.plan.items.len())
            .map(|index| (index, self.due(index)))
            .min_by_key(|(index, due)| (due.is_some(), *due, *index))
            .map(|(index, due)| (index, due.map(|(at, _)| at)))
    }

    /// Item `index` is being sent now.
    pub(super) fn sent(&mut self, index: usize, now: Instant) -> Option<&PollItem> {
        self.sends += 1;
        let origin = *self.origin.get_or_insert(now);
        let item = self.plan.items.get(index)?;
        let last = self.last.get_mut(index)?;
        let expected = last.map_or(origin, |(at, _)| at + item.every);
        *last = Some((grid_point(expected, item.every, now), self.sends));
        Some(item)
    }

    pub(super) fn record(&mut self, index: usize, result: Result<&Answer, &DeviceError>) {
        self.plan.sink.record(index, result);
    }
}

/// Where an item's grid lies after a send at `now` that was due at
/// `expected`: still at `expected` if the send was late by less than a
/// quarter of the period `every`, else at `now` (see the module docs).
fn grid_point(expected: Instant, every: Duration, now: Instant) -> Instant {
    match now.checked_duration_since(expected) {
        Some(late) if late < every / 4 => expected,
        _ => now,
    }
}

#[cfg(test)]
mod tests {
    use std::sync::{Arc, Mutex};

    use super::super::{Expect, PollSink, Retry, Transaction};
    use super::*;

    struct Nowhere;
    impl PollSink for Nowhere {
        fn record(&mut self, _: usize, _: Result<&Answer, &DeviceError>) {}
    }

    fn item(every_ms: u64) -> PollItem {
        PollItem {
            transaction: Transaction {
                bytes: vec![1],
                expect: Expect::Nothing,
                retry: Retry::Read(0),
                timeout: None,
            },
            every: Duration::from_millis(every_ms),
        }
    }

    fn schedule(items: Vec<PollItem>) -> PollSchedule {
        PollSchedule::new(PollPlan {
            items,
            sink: Box::new(Nowhere),
        })
    }

    #[test]
    fn items_never_polled_go_first_in_order_then_take_turns() {
        let mut s = schedule(vec![item(0), item(0), item(0)]);
        let t0 = Instant::now();
        let mut order = Vec::new();
        for _ in 0..6 {
            let (index, _) = s.next().expect("an item");
            order.push(index);
            // Answers that take no time at all.
            s.sent(index, t0);
        }
        assert_eq!(order, [0, 1, 2, 0, 1, 2]);
    }

    #[test]
    fn the_most_overdue_item_goes_next() {
        let mut s = schedule(vec![item(100), item(10)]);
        let t0 = Instant::now();
        s.sent(0, t0);
        s.sent(1, t0);
        assert_eq!(s.next(), Some((1, Some(t0 + Duration::from_millis(10)))));
        s.sent(1, t0 + Duration::from_millis(95));
        assert_eq!(s.next(), Some((0, Some(t0 + Duration::from_millis(100)))));
    }

    #[test]
    fn items_of_one_period_stay_on_one_grid_and_go_out_together() {
        let mut s = schedule(vec![item(50), item(50), item(50)]);
        let t0 = Instant::now();
        let ms = |n: f64| t0 + Duration::from_secs_f64(n / 1000.0);
        // The first round, one after the other's answer.
        s.sent(0, ms(0.0));
        s.sent(1, ms(0.3));
        s.sent(2, ms(0.6));
        let due: Vec<_> = (0..3).map(|i| s.due(i).map(|(at, _)| at)).collect();
        assert_eq!(due, [Some(ms(50.0)); 3], "one wake-up for all three");
        // A poll sent a little late does not push the next one back…
        s.sent(0, ms(57.0));
        assert_eq!(s.due(0).map(|(at, _)| at), Some(ms(100.0)));
        // …one later than a quarter period starts its grid afresh.
        s.sent(1, ms(63.0));
        assert_eq!(s.due(1).map(|(at, _)| at), Some(ms(113.0)));
    }

    /// A link too slow for the plan (20 ms a transaction, 9600 Bd, for
    /// three polls at 20 Hz and eight at 5 Hz) still polls the fast items
    /// about twice as often as the slow ones, as it did before the grid.
    #[test]
    fn on_a_link_too_slow_for_the_plan_fast_items_keep_their_turns() {
        let mut items: Vec<PollItem> = (0..3).map(|_| item(50)).collect();
        items.extend((0..8).map(|_| item(200)));
        let mut s = schedule(items);
        let mut now = Instant::now();
        let mut sent = [0u32; 11];
        for _ in 0..500 {
            let (index, due) = s.next().expect("an item");
            now = due.map_or(now, |due| due.max(now));
            s.sent(index, now);
            sent[index] += 1;
            now += Duration::from_millis(20);
        }
        let fast: u32 = sent[..3].iter().sum::<u32>() / 3;
        let slow: u32 = sent[3..].iter().sum::<u32>() / 8;
        assert!(fast * 10 >= slow * 18, "fast {fast}, slow {slow}: {sent:?}");
    }

    #[test]
    fn grid_points_never_panic() {
        let t0 = Instant::now();
        let step = Duration::from_millis(50);
        let ms = Duration::from_millis;
        assert_eq!(grid_point(t0, step, t0 + ms(12)), t0);
        assert_eq!(grid_point(t0, step, t0 + ms(13)), t0 + ms(13));
        assert_eq!(grid_point(t0, Duration::ZERO, t0 + ms(1)), t0 + ms(1));
        assert_eq!(grid_point(t0 + step, step, t0), t0, "sent before due");
        assert_eq!(grid_point(t0, Duration::MAX, t0 + ms(1)), t0);
    }

    #[test]
    fn an_empty_plan_has_nothing_due() {
        assert!(schedule(Vec::new()).next().is_none());
    }

    #[test]
    fn results_reach_the_sink() {
        struct Log(Arc<Mutex<Vec<usize>>>);
        impl PollSink for Log {
            fn record(&mut self, index: usize, _: Result<&Answer, &DeviceError>) {
                self.0.lock().map(|mut v| v.push(index)).ok();
            }
        }
        let log = Arc::new(Mutex::new(Vec::new()));
        let mut s = PollSchedule::new(PollPlan {
            items: vec![item(0)],
            sink: Box::new(Log(log.clone())),
        });
        s.record(0, Err(&DeviceError::Closed));
        assert_eq!(*log.lock().expect("log"), [0]);
    }
}
