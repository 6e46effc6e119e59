//! When each item of a poll plan is due.

use tokio::time::Instant;

use super::{Answer, DeviceError, PollItem, PollPlan};

/// A poll plan and when each of its items was last sent.
pub(super) struct PollSchedule {
    plan: PollPlan,
    /// When each item was last sent and the number of that send; `None`:
    /// never polled, due at once.
    last: Vec<Option<(Instant, u64)>>,
    sends: u64,
}

impl PollSchedule {
    pub(super) fn new(plan: PollPlan) -> Self {
        let last = vec![None; plan.items.len()];
        PollSchedule {
            plan,
            last,
            sends: 0,
        }
    }

    /// When item `index` is due (never-polled items at once, others
    /// `every` after their last send), and the number of its last send.
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
        if let Some(last) = self.last.get_mut(index) {
            *last = Some((now, self.sends));
        }
        self.plan.items.get(index)
    }

    pub(super) fn record(&mut self, index: usize, result: Result<&Answer, &DeviceError>) {
        self.plan.sink.record(index, result);
    }
}

#[cfg(test)]
mod tests {
    use std::sync::{Arc, Mutex};
    use std::time::Duration;

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
