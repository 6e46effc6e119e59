//! Axis status snapshots and the poll sink that keeps them.
//!
//! Reading TMCL AP207 clears the module's error flags (§4 Table 16), and a
//! motion command clears them too: a flag seen once exists nowhere but
//! here. So errors are latched in the snapshot until the user acknowledges
//! exactly the flags they were shown.

use std::sync::Arc;

use tokio::sync::watch;

use crate::device::{Answer, DeviceError, PollSink};
use crate::protocol::Family;
use crate::protocol::console::{AxisFlag, AxisUpdate, StatusPoll, SwitchKind};

/// What the console knows of one axis. `None` until first read.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct AxisStatus {
    pub position: Option<i64>,
    pub target: Option<i64>,
    pub speed: Option<i64>,
    /// The fastest the axis moves when positioning: its own maximum, or
    /// the module-wide one where its own reads 0.
    pub max_speed: Option<i64>,
    /// The axis's own maximum as read ([`AxisUpdate::MaxSpeed`]).
    pub own_max_speed: Option<i64>,
    /// The module-wide maximum, where the family has one
    /// ([`AxisUpdate::GlobalMaxSpeed`]).
    pub global_max_speed: Option<i64>,
    /// Standing at the target.
    pub reached: Option<bool>,
    pub left_switch: Option<bool>,
    pub right_switch: Option<bool>,
    pub home_switch: Option<bool>,
    /// Motor load reading (TMCL AP206: 0 = highest load).
    pub load: Option<i64>,
    /// Error flags seen since the user last acknowledged them, in the
    /// family's table order, each once. Never cleared by a later reading.
    pub errors: Vec<AxisFlag>,
    /// What the driver reports at the last reading.
    pub driver_flags: Option<Vec<AxisFlag>>,
}

impl AxisStatus {
    /// Take in one reading. Error flags only ever add up here.
    pub fn apply(&mut self, update: AxisUpdate) {
        match update {
            AxisUpdate::Position(v) => self.position = Some(v),
            AxisUpdate::Target(v) => self.target = Some(v),
            AxisUpdate::Speed(v) => self.speed = Some(v),
            AxisUpdate::MaxSpeed(v) => {
                self.own_max_speed = Some(v);
                self.max_speed = self.effective_max_speed();
            }
            AxisUpdate::GlobalMaxSpeed(v) => {
                self.global_max_speed = Some(v);
                self.max_speed = self.effective_max_speed();
            }
            AxisUpdate::Reached(v) => self.reached = Some(v),
            AxisUpdate::Switch(SwitchKind::Left, v) => self.left_switch = Some(v),
            AxisUpdate::Switch(SwitchKind::Right, v) => self.right_switch = Some(v),
            AxisUpdate::Switch(SwitchKind::Home, v) => self.home_switch = Some(v),
            AxisUpdate::Load(v) => self.load = Some(v),
            AxisUpdate::Errors(flags) => {
                for flag in flags {
                    if !self.errors.contains(&flag) {
                        self.errors.push(flag);
                    }
                }
            }
            AxisUpdate::DriverFlags(flags) => self.driver_flags = Some(flags),
        }
    }

    /// The axis's own maximum, unless it is 0 (or not read yet) and a
    /// module-wide one is known.
    fn effective_max_speed(&self) -> Option<i64> {
        match (self.own_max_speed, self.global_max_speed) {
            (Some(0) | None, Some(global)) => Some(global),
            (own, _) => own,
        }
    }

    /// Forget the error flags the user has seen; any that arrived since
    /// stay.
    pub fn acknowledge(&mut self, seen: &[AxisFlag]) {
        self.errors.retain(|flag| !seen.contains(flag));
    }
}

/// The shared snapshots: written by the poll sink (in the device task) and
/// by the session (replies to the user's own reads, acknowledgements),
/// read by whoever subscribes.
pub(crate) type StatusBoard = Arc<watch::Sender<Vec<AxisStatus>>>;

/// Applies an update to the board, if `axis` exists.
/// Subscribers are woken only when a value changed: a console polling a
/// motor at rest then has nothing to do.
pub(crate) fn post(board: &StatusBoard, axis: usize, update: AxisUpdate) {
    board.send_if_modified(|axes| {
        let Some(status) = axes.get_mut(axis) else {
            return false;
        };
        let before = status.clone();
        status.apply(update);
        *status != before
    });
}

/// Receives the device task's poll results and posts them.
pub(crate) struct StatusSink {
    pub family: &'static Family,
    pub polls: Vec<StatusPoll>,
    pub board: StatusBoard,
}

impl PollSink for StatusSink {
    fn record(&mut self, index: usize, result: Result<&Answer, &DeviceError>) {
        // A failed poll leaves the last known values: the link state tells
        // the user the link is gone, and the next poll tries again.
        let (Some(poll), Ok(answer)) = (self.polls.get(index), result) else {
            return;
        };
        let console = self.family.console;
        let Ok(reading) = console.interpret(&poll.line, &answer.frames) else {
            return;
        };
        for (axis, update) in console.status_update(&poll.line, &reading) {
            post(&self.board, axis, update);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::find_family;
    use crate::protocol::tmcl::{Reply, Status};
    use std::time::Duration;

    fn answer(value: i32) -> Answer {
        Answer {
            frames: vec![
                Reply {
                    host_address: 2,
                    module_address: 1,
                    status: Status::OK,
                    command: 6,
                    value,
                }
                .to_bytes()
                .to_vec(),
            ],
            elapsed: Duration::ZERO,
            attempts: 1,
        }
    }

    fn sink() -> (StatusSink, watch::Receiver<Vec<AxisStatus>>) {
        let family = find_family("tmcl").expect("tmcl");
        let polls = family.console.status_queries(1);
        let (board, status) = watch::channel(vec![AxisStatus::default()]);
        (
            StatusSink {
                family,
                polls,
                board: Arc::new(board),
            },
            status,
        )
    }

    fn index_of(sink: &StatusSink, canonical: &str) -> usize {
        sink.polls
            .iter()
            .position(|p| p.line.canonical == canonical)
            .expect("polled")
    }

    #[test]
    fn error_flags_stay_latched_after_the_module_cleared_them() {
        let (mut sink, status) = sink();
        let flags = index_of(&sink, "GAP 207, 0");
        sink.record(flags, Ok(&answer(1)));
        // Reading AP207 cleared it: the next poll reads 0.
        sink.record(flags, Ok(&answer(0)));
        sink.record(flags, Err(&DeviceError::Closed));
        let errors: Vec<_> = status.borrow()[0].errors.iter().map(|f| f.name).collect();
        assert_eq!(errors, ["stall"]);
        sink.record(flags, Ok(&answer(2)));
        sink.record(flags, Ok(&answer(3)));
        let errors: Vec<_> = status.borrow()[0].errors.iter().map(|f| f.name).collect();
        assert_eq!(errors, ["stall", "deviation"]);
    }

    #[test]
    fn acknowledging_clears_only_the_flags_seen() {
        let (mut sink, status) = sink();
        let flags = index_of(&sink, "GAP 207, 0");
        sink.record(flags, Ok(&answer(1)));
        let seen = status.borrow()[0].errors.clone();
        // A deviation arrives after the user looked.
        sink.record(flags, Ok(&answer(2)));
        sink.board.send_modify(|axes| axes[0].acknowledge(&seen));
        let errors: Vec<_> = status.borrow()[0].errors.iter().map(|f| f.name).collect();
        assert_eq!(errors, ["deviation"]);
    }

    #[test]
    fn readings_update_their_fields_and_failures_keep_the_last_values() {
        let (mut sink, status) = sink();
        let position = index_of(&sink, "GAP 1, 0");
        let reached = index_of(&sink, "GAP 8, 0");
        let left = index_of(&sink, "GAP 11, 0");
        sink.record(position, Ok(&answer(-500)));
        sink.record(reached, Ok(&answer(1)));
        sink.record(left, Ok(&answer(1)));
        sink.record(
            position,
            Err(&DeviceError::Timeout {
                timeout: Duration::from_millis(10),
                attempts: 1,
            }),
        );
        let axis = status.borrow()[0].clone();
        assert_eq!(axis.position, Some(-500));
        assert_eq!(axis.reached, Some(true));
        assert_eq!(axis.left_switch, Some(true));
        assert_eq!(axis.right_switch, None);
    }

    #[test]
    fn a_reading_that_changes_nothing_wakes_no_one() {
        let (mut sink, mut status) = sink();
        let position = index_of(&sink, "GAP 1, 0");
        sink.record(position, Ok(&answer(7)));
        assert!(status.has_changed().unwrap_or(false));
        status.borrow_and_update();
        sink.record(position, Ok(&answer(7)));
        assert!(
            !status.has_changed().unwrap_or(true),
            "the same value again"
        );
        sink.record(position, Ok(&answer(8)));
        assert!(status.has_changed().unwrap_or(false));
    }

    #[test]
    fn an_own_maximum_of_zero_falls_back_to_the_module_wide_one() {
        let mut axis = AxisStatus::default();
        axis.apply(AxisUpdate::MaxSpeed(0));
        assert_eq!(axis.max_speed, Some(0), "no module-wide maximum known");
        axis.apply(AxisUpdate::GlobalMaxSpeed(5000));
        assert_eq!(axis.max_speed, Some(5000));
        axis.apply(AxisUpdate::MaxSpeed(800));
        assert_eq!(axis.max_speed, Some(800), "its own wins");
        axis.apply(AxisUpdate::GlobalMaxSpeed(6000));
        assert_eq!(axis.max_speed, Some(800));
        axis.apply(AxisUpdate::MaxSpeed(0));
        assert_eq!(axis.max_speed, Some(6000));
        let mut fresh = AxisStatus::default();
        fresh.apply(AxisUpdate::GlobalMaxSpeed(100));
        assert_eq!(fresh.max_speed, Some(100), "until its own is read");
    }

    #[test]
    fn nonsense_from_the_device_changes_nothing() {
        let (mut sink, status) = sink();
        let garbage = Answer {
            frames: vec![vec![0xFF; 3]],
            elapsed: Duration::ZERO,
            attempts: 1,
        };
        for index in 0..sink.polls.len() + 2 {
            sink.record(index, Ok(&garbage));
        }
        assert_eq!(status.borrow()[0], AxisStatus::default());
    }
}
