//! When each item of a poll plan is due.
//!
//! Each item comes due on a grid of its period, laid from the plan's first
//! poll: a poll sent late (the timer woke late, the items before it in the
//! burst were answered first, the line was busy) does not push the next
//! one back. Items of one period therefore stay together and go out as
//! one burst, one after the other's answer, after a single timer wake-up;
//! scheduled from each item's own send time they drifted apart by a round
//! trip each, and a console polling one axis woke for almost every poll on
//! its own.
//!
//! Which of the items due goes first is still decided by their send
//! times: the one whose last send plus period lies furthest back. On a
//! link too slow for the plan every item is due all the time, and going
//! by the grid there would favour the items of long periods, whose grid
//! points lag furthest behind.
//!
//! An urgent item ([`PollItem::urgent`]) goes before every other item
//! due, in its own plan and in the others' on the link: it is a switch
//! the technician is looking at, and waiting its turn behind a round of
//! every axis's status took longer than the 200 ms a lamp may lag on a
//! 9600 Bd line (a SIXpack 2's fourteen items, about 350 ms). Its period
//! alone limits what it takes of the line.
//!
//! Several modules on one link (a multi-drop bus) each poll by a plan of
//! their own ([`PollOwner`]): [`PollPlans`] takes them in turn, the owner
//! after the one served last that has an item due, so that on a link too
//! slow for them all each module gets an equal share of the polls, and
//! one module's short periods cannot starve another's. Within a plan the
//! rule above picks the item.

use std::time::Duration;

use tokio::time::Instant;

use super::{Answer, DeviceError, PollItem, PollOwner, PollPlan};

/// An item of one owner's plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct PollKey {
    pub owner: PollOwner,
    pub index: usize,
}

/// Every owner's plan on one link, served in turn.
#[derive(Default)]
pub(super) struct PollPlans {
    /// In the order the owners first set a plan.
    schedules: Vec<(PollOwner, PollSchedule)>,
    /// The owner of the last poll sent.
    last_served: Option<PollOwner>,
}

impl PollPlans {
    /// Replace `owner`'s plan (`None`: it polls no more).
    pub(super) fn set(&mut self, owner: PollOwner, plan: Option<PollPlan>) {
        let at = self.schedules.iter().position(|(o, _)| *o == owner);
        match (at, plan) {
            (Some(at), Some(plan)) => {
                if let Some(entry) = self.schedules.get_mut(at) {
                    entry.1 = PollSchedule::new(plan);
                }
            }
            (None, Some(plan)) => self.schedules.push((owner, PollSchedule::new(plan))),
            (Some(at), None) => {
                self.schedules.remove(at);
            }
            (None, None) => {}
        }
    }

    /// The item to poll next and when it is due: of the owners with an
    /// item due at `now`, the first after the one served last (each
    /// owner's own choice of item), the first with an urgent item due
    /// before that; when none is due, the item that comes due first.
    pub(super) fn next(&self, now: Instant) -> Option<(PollKey, Option<Instant>)> {
        let count = self.schedules.len();
        let start = self
            .last_served
            .and_then(|owner| self.schedules.iter().position(|(o, _)| *o == owner))
            .map_or(0, |at| at + 1);
        let mut earliest: Option<(Instant, PollKey)> = None;
        let mut first_due: Option<(PollKey, Option<Instant>)> = None;
        for turn in 0..count {
            let Some((owner, schedule)) = self.schedules.get((start + turn) % count) else {
                continue;
            };
            let Some((index, due)) = schedule.next(now) else {
                continue;
            };
            let key = PollKey {
                owner: *owner,
                index,
            };
            match due {
                Some(at) if at > now => {
                    if earliest.is_none_or(|(first, _)| at < first) {
                        earliest = Some((at, key));
                    }
                }
                // A schedule offers its urgent items first.
                _ if schedule.is_urgent(index) => return Some((key, due)),
                _ => {
                    first_due.get_or_insert((key, due));
                }
            }
        }
        first_due.or(earliest.map(|(at, key)| (key, Some(at))))
    }

    fn schedule(&self, owner: PollOwner) -> Option<&PollSchedule> {
        self.schedules
            .iter()
            .find_map(|(o, s)| (*o == owner).then_some(s))
    }

    fn schedule_mut(&mut self, owner: PollOwner) -> Option<&mut PollSchedule> {
        self.schedules
            .iter_mut()
            .find_map(|(o, s)| (*o == owner).then_some(s))
    }

    pub(super) fn item(&self, key: PollKey) -> Option<&PollItem> {
        self.schedule(key.owner)?.item(key.index)
    }

    /// Item `key` is being sent now.
    pub(super) fn sent(&mut self, key: PollKey, now: Instant) -> Option<&PollItem> {
        self.last_served = Some(key.owner);
        self.schedule_mut(key.owner)?.sent(key.index, now)
    }

    /// Hand a poll's result to its owner's sink (if the owner still has
    /// the plan: plans change only between polls, see the device task).
    pub(super) fn record(&mut self, key: PollKey, result: Result<&Answer, &DeviceError>) {
        if let Some(schedule) = self.schedule_mut(key.owner) {
            schedule.record(key.index, result);
        }
    }
}

/// An item's last send.
#[derive(Debug, Clone, Copy)]
struct Sent {
    /// The last point of the item's grid at or before the send.
    grid: Instant,
    at: Instant,
    /// The number of the send, across items.
    number: u64,
}

/// A poll plan and when each of its items was last sent.
pub(super) struct PollSchedule {
    plan: PollPlan,
    /// `None`: never polled, due at once.
    last: Vec<Option<Sent>>,
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

    fn every(&self, index: usize) -> Duration {
        self.plan
            .items
            .get(index)
            .map_or(Duration::ZERO, |item| item.every)
    }

    fn is_urgent(&self, index: usize) -> bool {
        self.plan.items.get(index).is_some_and(|item| item.urgent)
    }

    /// When item `index` comes due: `None` never polled (at once), else
    /// one period after the grid point of its last send.
    fn due(&self, index: usize) -> Option<Instant> {
        let last = (*self.last.get(index)?)?;
        Some(last.grid + self.every(index))
    }

    /// The item to poll next and when it is due. Of the items due at `now`
    /// (urgent ones first, then never-polled ones, in order) the one whose last send plus
    /// period lies furthest back, the one sent longest ago on a tie, so
    /// that items take turns even when answers take no time at all; when
    /// none is due, the one that comes due first.
    pub(super) fn next(&self, now: Instant) -> Option<(usize, Option<Instant>)> {
        let items = 0..self.plan.items.len();
        let waiting = items
            .clone()
            .filter(|&index| self.due(index).is_none_or(|at| at <= now))
            .min_by_key(|&index| {
                let last = self.last.get(index).copied().flatten();
                let turn = last.map(|sent| (sent.at + self.every(index), sent.number));
                (!self.is_urgent(index), last.is_some(), turn, index)
            });
        if let Some(index) = waiting {
            return Some((index, self.due(index)));
        }
        items
            .filter_map(|index| {
                let number = self.last.get(index).copied().flatten()?.number;
                Some((self.due(index)?, number, index))
            })
            .min()
            .map(|(at, _, index)| (index, Some(at)))
    }

    /// Item `index` of the plan.
    pub(super) fn item(&self, index: usize) -> Option<&PollItem> {
        self.plan.items.get(index)
    }

    /// Item `index` is being sent now.
    pub(super) fn sent(&mut self, index: usize, now: Instant) -> Option<&PollItem> {
        self.sends += 1;
        let origin = *self.origin.get_or_insert(now);
        let item = self.plan.items.get(index)?;
        let last = self.last.get_mut(index)?;
        let from = last.map_or(origin, |sent| sent.grid);
        *last = Some(Sent {
            grid: grid_point(from, item.every, now),
            at: now,
            number: self.sends,
        });
        Some(item)
    }

    pub(super) fn record(&mut self, index: usize, result: Result<&Answer, &DeviceError>) {
        self.plan.sink.record(index, result);
    }
}

/// The last point at or before `now` of the grid through `from` with step
/// `every`; `now` itself for a zero step (as often as the link allows) or
/// a `now` before `from`.
fn grid_point(from: Instant, every: Duration, now: Instant) -> Instant {
    let step = every.as_nanos();
    if step == 0 || now < from {
        return now;
    }
    let behind = now.duration_since(from).as_nanos();
    let offset = behind - behind % step;
    u64::try_from(offset).map_or(now, |offset| from + Duration::from_nanos(offset))
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
                hold: None,
                cut_short: None,
            },
            every: Duration::from_millis(every_ms),
            urgent: false,
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
            let (index, _) = s.next(t0).expect("an item");
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
        assert_eq!(s.next(t0), Some((1, Some(t0 + Duration::from_millis(10)))));
        let later = t0 + Duration::from_millis(95);
        s.sent(1, later);
        assert_eq!(
            s.next(later),
            Some((0, Some(t0 + Duration::from_millis(100))))
        );
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
        let due: Vec<_> = (0..3).map(|i| s.due(i)).collect();
        assert_eq!(due, [Some(ms(50.0)); 3], "one wake-up for all three");
        // A poll sent late does not push the next one back, however late
        // within its period (a hiccup does not split the burst for good)…
        s.sent(0, ms(57.0));
        assert_eq!(s.due(0), Some(ms(100.0)));
        s.sent(2, ms(90.0));
        assert_eq!(s.due(2), Some(ms(100.0)));
        // …and one that missed a whole period takes the next grid point.
        s.sent(1, ms(160.0));
        assert_eq!(s.due(1), Some(ms(200.0)));
    }

    /// A link too slow for the plan (20 ms a transaction, 9600 Bd, for
    /// three polls at 20 Hz and eight at 5 Hz) still polls the fast items
    /// about twice as often as the slow ones, as it did before the grid
    /// (going by the grid, 5.0 Hz against 4.4 Hz).
    #[test]
    fn on_a_link_too_slow_for_the_plan_fast_items_keep_their_turns() {
        let mut items: Vec<PollItem> = (0..3).map(|_| item(50)).collect();
        items.extend((0..8).map(|_| item(200)));
        let mut s = schedule(items);
        let mut now = Instant::now();
        let mut sent = [0u32; 11];
        for _ in 0..500 {
            let (index, due) = s.next(now).expect("an item");
            now = due.map_or(now, |due| due.max(now));
            s.sent(index, now);
            sent[index] += 1;
            now += Duration::from_millis(20);
        }
        let fast: u32 = sent[..3].iter().sum::<u32>() / 3;
        let slow: u32 = sent[3..].iter().sum::<u32>() / 8;
        assert!(fast * 10 >= slow * 18, "fast {fast}, slow {slow}: {sent:?}");
    }

    fn urgent(every_ms: u64) -> PollItem {
        PollItem {
            urgent: true,
            ..item(every_ms)
        }
    }

    /// The longest time between two sends of item `watched` of `owner`
    /// over `sends` polls of 25 ms each (9 bytes each way at 9600 Bd and
    /// a turnaround), every item as early as it is due.
    fn longest_gap(
        plans: &mut PollPlans,
        owner: PollOwner,
        watched: usize,
        sends: usize,
    ) -> Duration {
        let mut now = Instant::now();
        let mut last: Option<Instant> = None;
        let mut longest = Duration::ZERO;
        for _ in 0..sends {
            let (key, due) = plans.next(now).expect("an item");
            now = due.map_or(now, |due| due.max(now));
            plans.sent(key, now);
            if key
                == (PollKey {
                    owner,
                    index: watched,
                })
            {
                if let Some(before) = last {
                    longest = longest.max(now - before);
                }
                last = Some(now);
            }
            now += Duration::from_millis(25);
        }
        longest
    }

    /// A SIXpack 2's twelve fast items at 9600 Bd and its switch read,
    /// urgent every 100 ms: the switch is read every 100 ms and one
    /// exchange at most, where its turn in the round of thirteen came
    /// 325 ms apart or more.
    #[test]
    fn an_urgent_item_goes_before_the_overdue_ones_at_its_period() {
        let plan = |switch: PollItem| {
            let mut items: Vec<PollItem> = (0..12).map(|_| item(50)).collect();
            items.push(switch);
            PollPlan {
                items,
                sink: Box::new(Nowhere),
            }
        };
        let owner = PollOwner::new();
        let mut plans = PollPlans::default();
        plans.set(owner, Some(plan(urgent(100))));
        let gap = longest_gap(&mut plans, owner, 12, 400);
        assert!(gap <= Duration::from_millis(125), "urgent: {gap:?}");
        plans.set(owner, Some(plan(item(100))));
        let gap = longest_gap(&mut plans, owner, 12, 400);
        assert!(gap >= Duration::from_millis(325), "in its turn: {gap:?}");
    }

    /// On a bus, a module's urgent item does not wait for the other
    /// modules' turns.
    #[test]
    fn an_urgent_item_goes_before_other_owners_turns() {
        let watched = PollOwner::new();
        let mut plans = PollPlans::default();
        for _ in 0..3 {
            plans.set(
                PollOwner::new(),
                Some(PollPlan {
                    items: (0..4).map(|_| item(50)).collect(),
                    sink: Box::new(Nowhere),
                }),
            );
        }
        let mut items: Vec<PollItem> = (0..4).map(|_| item(50)).collect();
        items.push(urgent(100));
        plans.set(
            watched,
            Some(PollPlan {
                items,
                sink: Box::new(Nowhere),
            }),
        );
        let gap = longest_gap(&mut plans, watched, 4, 400);
        assert!(gap <= Duration::from_millis(125), "urgent: {gap:?}");
    }

    #[test]
    fn grid_points_never_panic_and_fall_at_or_before_now() {
        let t0 = Instant::now();
        let step = Duration::from_millis(50);
        let ms = Duration::from_millis;
        assert_eq!(grid_point(t0, step, t0 + ms(149)), t0 + 2 * step);
        assert_eq!(grid_point(t0, step, t0 + 3 * step), t0 + 3 * step);
        assert_eq!(grid_point(t0, Duration::ZERO, t0 + step), t0 + step);
        assert_eq!(grid_point(t0 + step, step, t0), t0, "now before the grid");
        assert_eq!(grid_point(t0, Duration::MAX, t0 + step), t0);
    }

    #[test]
    fn an_empty_plan_has_nothing_due() {
        assert!(schedule(Vec::new()).next(Instant::now()).is_none());
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
