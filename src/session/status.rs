//! Axis status snapshots and the poll sink that keeps them.
//!
//! Reading TMCL AP207 clears the module's error flags (§4 Table 16), and a
//! motion command clears them too: a flag seen once exists nowhere but
//! here. So errors are latched in the snapshot until the user acknowledges
//! exactly the flags they were shown.
//!
//! The sink also measures how often the status is refreshed in full (the
//! link's speed, not the cadence asked for, decides it: a CMD-4CR at 9600
//! Bd reads its four axes about eight times a second, not 20), so that
//! the console can show what it really gets.

use std::collections::VecDeque;
use std::fmt;
use std::sync::Arc;
use std::time::Duration;

use tokio::sync::watch;
use tokio::time::Instant;

use crate::device::{Answer, DeviceError, PollSink};
use crate::protocol::Family;
use crate::protocol::console::{
    AxisFlag, AxisUpdate, LinkContext, MotionPhase, MoveMode, ReplyValue, StatusPoll, SwitchKind,
    interpret_line,
};
use crate::protocol::settings::SettingsCache;

/// What the console knows of one axis. `None` until first read.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct AxisStatus {
    pub position: Option<i64>,
    pub target: Option<i64>,
    /// How a move line's target operand is meant, where the module has a
    /// mode for it ([`AxisUpdate::MoveMode`]).
    pub move_mode: Option<MoveMode>,
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
    /// What the axis is doing, where the module says (else the console
    /// reads it from the speed).
    pub phase: Option<MotionPhase>,
    pub left_switch: Option<bool>,
    pub right_switch: Option<bool>,
    pub home_switch: Option<bool>,
    /// Motor load reading (TMCL AP206: 0 = highest load).
    pub load: Option<i64>,
    /// Commanded minus actual position, where the family reads it (MCCL
    /// `TF`).
    pub following_error: Option<i64>,
    /// Error flags seen since the user last acknowledged them, in the
    /// family's table order, each once. Never cleared by a later reading.
    pub errors: Vec<AxisFlag>,
    /// What the driver reports at the last reading.
    pub driver_flags: Option<Vec<AxisFlag>>,
    /// How often the axis's fast-changing status (position, speed, state)
    /// has lately been read in full; `None` until measured or while
    /// polling is off.
    pub refresh: Option<RefreshRate>,
    /// The status polls that say whether the axis is at rest, each with
    /// what its latest reading said: the evidence a session recording
    /// turns into `:wait-until LINE == VALUE` (see [`RestRead`]).
    pub rest_reads: Vec<RestRead>,
    /// Lines read with the status because someone watches them
    /// ([`crate::session::Session::watch`]), in the order asked for.
    pub watched: Vec<WatchedValue>,
}

/// What a status poll says of an axis being at rest, from the weakest
/// evidence to the strongest.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum RestSign {
    /// Its speed ([`AxisUpdate::Speed`] 0): weak, since a module may still
    /// read 0 just after a move was started.
    Speed,
    /// Where it is ([`AxisUpdate::Position`]): the value read last, at
    /// rest or not; it says the axis is at rest only when the status as a
    /// whole does ([`AxisStatus::motion`]).
    Position,
    /// The motion phase the module reports ([`MotionPhase::Standing`]).
    Phase,
    /// The module's own "at the target" flag ([`AxisUpdate::Reached`]).
    Reached,
}

/// One status poll line that says whether an axis is at rest, and what
/// its latest reading said. Changes only when the axis starts or stops
/// (or moves: a position), so it wakes no one while a motor stands.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RestRead {
    /// The poll line in the family's canonical form (`GAP 8, 0`).
    pub line: String,
    pub sign: RestSign,
    /// The reading as printed (`1`), when it showed the axis at rest
    /// (always, for [`RestSign::Position`]); `None` when it showed it
    /// moving (or short of its target, for [`RestSign::Reached`]).
    pub at_rest: Option<String>,
}

impl RestRead {
    /// What one update says of the axis being at rest, if anything.
    pub fn sign_of(update: &AxisUpdate) -> Option<(RestSign, bool)> {
        match update {
            AxisUpdate::Reached(reached) => Some((RestSign::Reached, *reached)),
            AxisUpdate::Phase(phase) => Some((RestSign::Phase, *phase == MotionPhase::Standing)),
            AxisUpdate::Speed(speed) => Some((RestSign::Speed, *speed == 0)),
            AxisUpdate::Position(_) => Some((RestSign::Position, true)),
            _ => None,
        }
    }
}

/// A watched line of an axis and the number it last answered (`None`
/// until it did, or when its answer is no number).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WatchedValue {
    /// The line in the family's canonical form (`GAP 206, 0`).
    pub line: String,
    pub value: Option<i64>,
    /// The whole answer, for a reading that is no single number (a
    /// SIXpack 2 `$30` answer's fields); `None` until it answered.
    pub reply: Option<ReplyValue>,
}

/// Full status refreshes a second, to a hundredth.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct RefreshRate {
    centihertz: u32,
}

impl RefreshRate {
    pub const ZERO: RefreshRate = RefreshRate { centihertz: 0 };

    /// The rate of one refresh every `interval` (zero for a zero or an
    /// endless interval).
    pub fn every(interval: Duration) -> RefreshRate {
        let seconds = interval.as_secs_f64();
        if seconds <= 0.0 || !seconds.is_finite() {
            return RefreshRate::ZERO;
        }
        let centihertz = (100.0 / seconds).round().min(f64::from(u32::MAX));
        RefreshRate {
            centihertz: centihertz as u32,
        }
    }

    pub fn per_second(self) -> f64 {
        f64::from(self.centihertz) / 100.0
    }

    /// Whether `other` differs enough from this one to be worth showing:
    /// by 2 % or more, or one of them is zero and the other not. Smaller
    /// wobbles would wake the console for nothing.
    fn differs(self, other: RefreshRate) -> bool {
        let (a, b) = (self.centihertz, other.centihertz);
        if a == 0 || b == 0 {
            return a != b;
        }
        a.abs_diff(b).saturating_mul(50) >= a.max(b)
    }
}

impl fmt::Display for RefreshRate {
    /// `7.3/s`, `20/s` from 10 a second.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let hz = self.per_second();
        if hz >= 10.0 {
            write!(f, "{hz:.0}/s")
        } else {
            write!(f, "{hz:.1}/s")
        }
    }
}

/// Rounds of the fast poll items measured over about this long.
const REFRESH_WINDOW: Duration = Duration::from_secs(2);

/// Counts full rounds of a poll plan's fast items (every one of them
/// answered once since the last round) and how often they come.
#[derive(Debug)]
pub(crate) struct RefreshMeter {
    /// Whether each item of the plan counts (the fast ones; all of them if
    /// none is fast).
    counts: Vec<bool>,
    /// Items of the round in progress not answered yet.
    waiting: Vec<bool>,
    /// When recent rounds were complete, oldest first.
    rounds: VecDeque<Instant>,
    /// The rate last published.
    shown: Option<RefreshRate>,
}

impl RefreshMeter {
    pub(crate) fn new(polls: &[StatusPoll]) -> RefreshMeter {
        let any_fast = polls.iter().any(|p| p.fast);
        let counts: Vec<bool> = polls.iter().map(|p| p.fast || !any_fast).collect();
        RefreshMeter {
            waiting: counts.clone(),
            counts,
            rounds: VecDeque::new(),
            shown: None,
        }
    }

    /// Item `index` was answered (`answered`) or failed at `now`. Returns
    /// the rate to publish when it changed enough to show.
    pub(crate) fn record(
        &mut self,
        index: usize,
        answered: bool,
        now: Instant,
    ) -> Option<RefreshRate> {
        if answered && let Some(waiting) = self.waiting.get_mut(index) {
            *waiting = false;
            if !self.waiting.contains(&true) {
                self.waiting.clone_from(&self.counts);
                // After a stall the rounds before it say nothing of now.
                if self.rate(now) == Some(RefreshRate::ZERO) {
                    self.rounds.clear();
                }
                self.rounds.push_back(now);
                while self.rounds.len() > 2
                    && self
                        .rounds
                        .front()
                        .is_some_and(|&first| now.saturating_duration_since(first) > REFRESH_WINDOW)
                {
                    self.rounds.pop_front();
                }
            }
        }
        let rate = self.rate(now)?;
        let show = self.shown.is_none_or(|shown| shown.differs(rate));
        show.then(|| {
            self.shown = Some(rate);
            rate
        })
    }

    /// Rounds a second over the last ones; zero when none has come for
    /// much longer than they used to take (polls failing).
    fn rate(&self, now: Instant) -> Option<RefreshRate> {
        let (&first, &last) = (self.rounds.front()?, self.rounds.back()?);
        let gaps = u32::try_from(self.rounds.len().checked_sub(1)?).ok()?;
        if gaps == 0 {
            return None;
        }
        let interval = last.saturating_duration_since(first) / gaps;
        let stale = REFRESH_WINDOW.max(interval.saturating_mul(3));
        if now.saturating_duration_since(last) > stale {
            return Some(RefreshRate::ZERO);
        }
        Some(RefreshRate::every(interval))
    }
}

impl AxisStatus {
    /// Take in one reading. Error flags only ever add up here.
    pub fn apply(&mut self, update: AxisUpdate) {
        match update {
            AxisUpdate::Position(v) => self.position = Some(v),
            AxisUpdate::Target(v) => self.target = Some(v),
            // Not guessed: without the mode (or, for a step, a position)
            // the target is unknown.
            AxisUpdate::MoveTarget(operand) => {
                self.target = match self.move_mode {
                    Some(MoveMode::Absolute) => Some(operand),
                    Some(MoveMode::Incremental) => {
                        self.position.and_then(|p| p.checked_add(operand))
                    }
                    None => None,
                }
            }
            AxisUpdate::MoveMode(mode) => self.move_mode = mode,
            AxisUpdate::TargetUnknown => self.target = None,
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
            AxisUpdate::Phase(phase) => self.phase = Some(phase),
            AxisUpdate::Switch(SwitchKind::Left, v) => self.left_switch = Some(v),
            AxisUpdate::Switch(SwitchKind::Right, v) => self.right_switch = Some(v),
            AxisUpdate::Switch(SwitchKind::Home, v) => self.home_switch = Some(v),
            AxisUpdate::Load(v) => self.load = Some(v),
            AxisUpdate::FollowingError(v) => self.following_error = Some(v),
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

    /// Keep what the latest reading of a rest read's line said.
    pub fn note_rest(&mut self, read: RestRead) {
        match self.rest_reads.iter_mut().find(|r| r.line == read.line) {
            Some(known) => *known = read,
            None => self.rest_reads.push(read),
        }
    }

    /// The strongest evidence that the axis is at rest now, if it is
    /// ([`AxisStatus::motion`]): the poll line and the value it read —
    /// the module's reached flag or standing phase where a poll says so,
    /// else where the axis stands, else its speed 0.
    pub fn rest_evidence(&self) -> Option<&RestRead> {
        if !matches!(
            self.motion(),
            AxisMotion::AtTarget | AxisMotion::StoppedShort | AxisMotion::Stopped
        ) {
            return None;
        }
        self.rest_reads
            .iter()
            .filter(|r| r.at_rest.is_some())
            .max_by_key(|r| r.sign)
    }

    /// Forget the error flags the user has seen; any that arrived since
    /// stay.
    pub fn acknowledge(&mut self, seen: &[AxisFlag]) {
        self.errors.retain(|flag| !seen.contains(flag));
    }

    /// What the axis does, from its readings: whether it moves comes from
    /// the motion phase the module reports, else from the speed; standing,
    /// it is at its target when the module says so (TMCL AP8, CMD-4CR
    /// motion complete) or its position is the target, and short of it
    /// otherwise — an emergency stop, a stop key, a switch or a stall
    /// ended the move before it got there. Standing with neither a
    /// target nor such a flag known, it has stopped, and nothing says
    /// where it meant to go. A reached flag read before the
    /// speed fell to 0 does not make a standing axis moving.
    pub fn motion(&self) -> AxisMotion {
        let standing = match (self.phase, self.speed) {
            (Some(phase), _) => phase == MotionPhase::Standing,
            (None, Some(speed)) => speed == 0,
            (None, None) => {
                return match self.reached {
                    Some(true) => AxisMotion::AtTarget,
                    _ => AxisMotion::Unknown,
                };
            }
        };
        if !standing {
            return AxisMotion::Moving;
        }
        let on_target = match (self.position, self.target) {
            (Some(position), Some(target)) => Some(position == target),
            _ => None,
        };
        match (self.reached, on_target) {
            (Some(true), _) | (_, Some(true)) => AxisMotion::AtTarget,
            (Some(false), _) | (None, Some(false)) => AxisMotion::StoppedShort,
            (None, None) => AxisMotion::Stopped,
        }
    }
}

/// What an axis does ([`AxisStatus::motion`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisMotion {
    /// Not enough read yet to tell.
    Unknown,
    Moving,
    /// Standing at its target (a family that reports no target: standing
    /// with its motion complete).
    AtTarget,
    /// Standing short of its target: stopped before it got there.
    StoppedShort,
    /// Standing, with no target known and no flag of the module's saying
    /// whether it was reached.
    Stopped,
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

/// Notes what a status poll said of an axis being at rest, waking
/// subscribers only when that changed.
pub(crate) fn post_rest(board: &StatusBoard, axis: usize, read: RestRead) {
    board.send_if_modified(|axes| {
        let Some(status) = axes.get_mut(axis) else {
            return false;
        };
        if status.rest_reads.contains(&read) {
            return false;
        }
        status.note_rest(read);
        true
    });
}

/// Sets every axis's refresh rate.
pub(crate) fn post_refresh(board: &StatusBoard, rate: Option<RefreshRate>) {
    board.send_if_modified(|axes| {
        let mut changed = false;
        for status in axes.iter_mut().filter(|s| s.refresh != rate) {
            status.refresh = rate;
            changed = true;
        }
        changed
    });
}

/// Sets the value of a watched line of `axis`, adding the line if new.
pub(crate) fn post_watched(
    board: &StatusBoard,
    axis: usize,
    line: &str,
    reply: Option<ReplyValue>,
) {
    let value = match &reply {
        Some(ReplyValue::Number(n)) => Some(*n),
        _ => None,
    };
    board.send_if_modified(|axes| {
        let Some(status) = axes.get_mut(axis) else {
            return false;
        };
        match status.watched.iter_mut().find(|w| w.line == line) {
            Some(watched) if watched.reply == reply => false,
            Some(watched) => {
                watched.value = value;
                watched.reply = reply;
                true
            }
            None => {
                status.watched.push(WatchedValue {
                    line: line.to_string(),
                    value,
                    reply,
                });
                true
            }
        }
    });
}

/// Drops a watched line of `axis`.
pub(crate) fn forget_watched(board: &StatusBoard, axis: usize, line: &str) {
    board.send_if_modified(|axes| {
        let Some(status) = axes.get_mut(axis) else {
            return false;
        };
        let before = status.watched.len();
        status.watched.retain(|w| w.line != line);
        status.watched.len() != before
    });
}

/// Receives the device task's poll results and posts them.
pub(crate) struct StatusSink {
    pub family: &'static Family,
    pub polls: Vec<StatusPoll>,
    pub board: StatusBoard,
    pub meter: RefreshMeter,
    /// The family's per-link state the polls were adapted to.
    pub context: Option<Arc<dyn LinkContext>>,
    /// The settings the session knows were written, which some readings
    /// are read in the light of.
    pub settings: Option<watch::Receiver<SettingsCache>>,
    /// Watched lines, polled after the status items: index
    /// `polls.len() + n` is `watched[n]`.
    pub watched: Vec<StatusPoll>,
    /// Watched lines a status item reads already (a CMD-4CR's `MSTX`):
    /// not polled twice; the status item's answer is theirs too.
    pub shared: Vec<(usize, StatusPoll)>,
}

impl StatusSink {
    pub(crate) fn new(
        family: &'static Family,
        polls: Vec<StatusPoll>,
        board: StatusBoard,
        context: Option<Arc<dyn LinkContext>>,
        settings: Option<watch::Receiver<SettingsCache>>,
    ) -> Self {
        StatusSink {
            meter: RefreshMeter::new(&polls),
            family,
            polls,
            board,
            context,
            settings,
            watched: Vec::new(),
            shared: Vec::new(),
        }
    }

    /// The same, polling `watched` lines after the status items.
    pub(crate) fn with_watched(mut self, watched: Vec<StatusPoll>) -> Self {
        self.watched = watched;
        self
    }

    /// The same, posting the answers of status item `index` for each
    /// watched line of `shared` too.
    pub(crate) fn with_shared(mut self, shared: Vec<(usize, StatusPoll)>) -> Self {
        self.shared = shared;
        self
    }

    /// The answer to watched line `n`.
    fn post_watched(&self, n: usize, result: Result<&Answer, &DeviceError>) {
        if let Some(watch) = self.watched.get(n) {
            self.post_watch(watch, result);
        }
    }

    /// The answer to `watch`'s line, posted with its number.
    fn post_watch(&self, watch: &StatusPoll, result: Result<&Answer, &DeviceError>) {
        let Ok(answer) = result else {
            return;
        };
        let console = self.family.console;
        let Ok(reading) = interpret_line(
            console,
            &watch.line,
            &answer.frames,
            self.context.as_deref(),
        ) else {
            return;
        };
        post_watched(
            &self.board,
            watch.axis,
            &watch.line.canonical,
            Some(reading.value),
        );
    }

    /// The reading of item `index`, if it answered with one.
    fn post_reading(&self, index: usize, result: Result<&Answer, &DeviceError>) -> bool {
        // A failed poll leaves the last known values: the link state tells
        // the user the link is gone, and the next poll tries again.
        let (Some(poll), Ok(answer)) = (self.polls.get(index), result) else {
            return false;
        };
        let console = self.family.console;
        let context = self.context.as_deref();
        let Ok(reading) = interpret_line(console, &poll.line, &answer.frames, context) else {
            return false;
        };
        let updates = match &self.settings {
            Some(settings) => console.status_update_known(&poll.line, &reading, &settings.borrow()),
            None => console.status_update(&poll.line, &reading),
        };
        // The strongest sign of rest this reading gives of each axis.
        let mut rests: Vec<(usize, RestSign, bool)> = Vec::new();
        for (axis, update) in &updates {
            let Some((sign, at_rest)) = RestRead::sign_of(update) else {
                continue;
            };
            match rests.iter_mut().find(|(a, _, _)| a == axis) {
                Some(known) if known.1 < sign => *known = (*axis, sign, at_rest),
                Some(_) => {}
                None => rests.push((*axis, sign, at_rest)),
            }
        }
        for (axis, update) in updates {
            post(&self.board, axis, update);
        }
        for (axis, sign, at_rest) in rests {
            let read = RestRead {
                line: poll.line.canonical.clone(),
                sign,
                at_rest: at_rest.then(|| reading.value.to_string()),
            };
            post_rest(&self.board, axis, read);
        }
        true
    }
}

impl PollSink for StatusSink {
    fn record(&mut self, index: usize, result: Result<&Answer, &DeviceError>) {
        if let Some(n) = index.checked_sub(self.polls.len()) {
            self.post_watched(n, result);
            return;
        }
        let answered = self.post_reading(index, result);
        for (_, watch) in self.shared.iter().filter(|(i, _)| *i == index) {
            self.post_watch(watch, result);
        }
        if let Some(rate) = self.meter.record(index, answered, Instant::now()) {
            post_refresh(&self.board, Some(rate));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_move_target_is_read_in_the_axis_move_mode_or_left_unknown() {
        let mut axis = AxisStatus {
            position: Some(1000),
            phase: Some(MotionPhase::Standing),
            ..AxisStatus::default()
        };
        // No mode known: no target guessed, and a stop says only stopped.
        axis.apply(AxisUpdate::MoveTarget(500));
        assert_eq!(axis.target, None);
        assert_eq!(axis.motion(), AxisMotion::Stopped);
        axis.apply(AxisUpdate::MoveMode(Some(MoveMode::Incremental)));
        axis.apply(AxisUpdate::MoveTarget(500));
        assert_eq!(axis.target, Some(1500), "a step from where it stands");
        assert_eq!(axis.motion(), AxisMotion::StoppedShort);
        axis.apply(AxisUpdate::MoveMode(Some(MoveMode::Absolute)));
        axis.apply(AxisUpdate::MoveTarget(1000));
        assert_eq!(axis.target, Some(1000));
        assert_eq!(axis.motion(), AxisMotion::AtTarget);
        // At the target's position, the module still waiting for an input
        // before the move completes: not reached yet.
        axis.apply(AxisUpdate::Phase(MotionPhase::Waiting));
        assert_eq!(axis.motion(), AxisMotion::Moving);
        axis.apply(AxisUpdate::Phase(MotionPhase::Standing));
        axis.apply(AxisUpdate::TargetUnknown);
        assert_eq!(axis.target, None);
        // A step from a position never read is no target either.
        let mut unread = AxisStatus {
            move_mode: Some(MoveMode::Incremental),
            ..AxisStatus::default()
        };
        unread.apply(AxisUpdate::MoveTarget(500));
        assert_eq!(unread.target, None);
        unread.apply(AxisUpdate::MoveMode(None));
        assert_eq!(unread.move_mode, None);
    }

    #[test]
    fn motion_says_what_the_axis_does_not_whether_it_got_there() {
        let axis = |speed: Option<i64>, reached: Option<bool>, position, target| AxisStatus {
            speed,
            reached,
            position,
            target,
            ..AxisStatus::default()
        };
        use AxisMotion::*;
        // Moving towards the target, then there.
        assert_eq!(
            axis(Some(1500), Some(false), Some(10), Some(90)).motion(),
            Moving
        );
        assert_eq!(
            axis(Some(0), Some(true), Some(90), Some(90)).motion(),
            AtTarget
        );
        // After an emergency stop: speed 0, the flag clear, short of it.
        assert_eq!(
            axis(Some(0), Some(false), Some(50), Some(90)).motion(),
            StoppedShort
        );
        assert_eq!(
            axis(Some(0), None, Some(50), Some(90)).motion(),
            StoppedShort
        );
        // The flag read a moment before the position reached the target.
        assert_eq!(
            axis(Some(0), Some(false), Some(90), Some(90)).motion(),
            AtTarget
        );
        // Turning in velocity mode whatever the flag says.
        assert_eq!(
            axis(Some(-200), Some(true), Some(5), Some(5)).motion(),
            Moving
        );
        // Not read enough.
        assert_eq!(axis(None, None, None, None).motion(), Unknown);
        assert_eq!(axis(None, Some(false), Some(1), Some(2)).motion(), Unknown);
        assert_eq!(axis(None, Some(true), None, None).motion(), AtTarget);
        // Standing, with nothing to say whether at a target: stopped.
        assert_eq!(axis(Some(0), None, None, None).motion(), Stopped);
        // A module that reports its phase: that decides, not the speed.
        let mut cmd4cr = axis(Some(0), Some(false), None, None);
        cmd4cr.phase = Some(MotionPhase::Decelerating);
        assert_eq!(cmd4cr.motion(), Moving);
        cmd4cr.phase = Some(MotionPhase::Standing);
        assert_eq!(cmd4cr.motion(), StoppedShort);
    }
    use crate::families::find_family;
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
            StatusSink::new(family, polls, Arc::new(board), None, None),
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
    fn the_polls_that_show_an_axis_at_rest_are_kept_with_the_value_they_read() {
        let (mut sink, mut status) = sink();
        let reached = index_of(&sink, "GAP 8, 0");
        let speed = index_of(&sink, "GAP 3, 0");
        let evidence = |status: &watch::Receiver<Vec<AxisStatus>>| {
            status.borrow()[0]
                .rest_evidence()
                .map(|r| (r.line.clone(), r.at_rest.clone()))
        };
        // Moving: neither poll shows it at rest.
        sink.record(reached, Ok(&answer(0)));
        sink.record(speed, Ok(&answer(1500)));
        assert_eq!(evidence(&status), None);
        // The speed falls to 0 short of the target: at rest by its speed.
        sink.record(speed, Ok(&answer(0)));
        assert_eq!(
            evidence(&status),
            Some(("GAP 3, 0".into(), Some("0".into())))
        );
        // Where it stands says more than a speed of 0.
        let position = index_of(&sink, "GAP 1, 0");
        sink.record(position, Ok(&answer(700)));
        assert_eq!(
            evidence(&status),
            Some(("GAP 1, 0".into(), Some("700".into())))
        );
        // The module's own flag wins over the speed.
        sink.record(reached, Ok(&answer(1)));
        assert_eq!(
            evidence(&status),
            Some(("GAP 8, 0".into(), Some("1".into())))
        );
        // A reading saying the same again wakes no one.
        status.borrow_and_update();
        sink.record(reached, Ok(&answer(1)));
        assert!(!status.has_changed().unwrap_or(true));
        // Off again: the flag clears, where it stands is all there is.
        sink.record(reached, Ok(&answer(0)));
        assert_eq!(
            evidence(&status),
            Some(("GAP 1, 0".into(), Some("700".into())))
        );
        sink.record(speed, Ok(&answer(-20)));
        assert_eq!(evidence(&status), None, "moving again");
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
    fn a_following_error_is_kept_as_read() {
        let mut axis = AxisStatus::default();
        assert_eq!(axis.following_error, None);
        axis.apply(AxisUpdate::FollowingError(-12));
        assert_eq!(axis.following_error, Some(-12));
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

    /// A meter over `fast` fast items and one slow item (the last).
    fn meter(fast: usize) -> RefreshMeter {
        let family = find_family("tmcl").expect("tmcl");
        let any = family.console.status_queries(1).remove(0);
        let polls: Vec<StatusPoll> = (0..=fast)
            .map(|i| StatusPoll {
                fast: i < fast,
                ..any.clone()
            })
            .collect();
        RefreshMeter::new(&polls)
    }

    /// Answer every fast item once, the round ending at `at`.
    fn round(meter: &mut RefreshMeter, fast: usize, at: Instant) -> Option<RefreshRate> {
        (0..fast).fold(None, |_, i| meter.record(i, true, at))
    }

    #[test]
    fn a_refresh_is_every_fast_item_answered_once() {
        let mut m = meter(3);
        let t0 = Instant::now();
        let ms = Duration::from_millis;
        assert_eq!(round(&mut m, 3, t0), None, "one round is no rate yet");
        // The slow item and two of three fast ones: no round yet.
        assert_eq!(m.record(3, true, t0 + ms(50)), None);
        assert_eq!(m.record(0, true, t0 + ms(60)), None);
        assert_eq!(m.record(0, true, t0 + ms(70)), None);
        assert_eq!(m.record(1, true, t0 + ms(80)), None);
        // A failed poll does not count.
        assert_eq!(m.record(2, false, t0 + ms(90)), None);
        let rate = m.record(2, true, t0 + ms(125));
        assert_eq!(rate, Some(RefreshRate::every(ms(125))));
        assert_eq!(rate.map(RefreshRate::per_second), Some(8.0));
        // Steady rounds every 125 ms: nothing new to show.
        for k in 2..10 {
            assert_eq!(round(&mut m, 3, t0 + ms(125 * k)), None);
        }
        // Faster: shown as the average over the last 2 s moves, in steps
        // of 2 % or more, until it settles.
        let mut shown = Vec::new();
        for k in 1..=30 {
            shown.extend(round(&mut m, 3, t0 + ms(1125 + 100 * k)));
        }
        let shown: Vec<String> = shown.iter().map(ToString::to_string).collect();
        assert!(shown.len() > 2, "{shown:?}");
        assert_eq!(shown.last().map(String::as_str), Some("10/s"), "{shown:?}");
    }

    #[test]
    fn failing_polls_bring_the_rate_to_zero() {
        let mut m = meter(1);
        let t0 = Instant::now();
        let ms = Duration::from_millis;
        m.record(0, true, t0);
        assert!(m.record(0, true, t0 + ms(100)).is_some());
        assert_eq!(m.record(0, false, t0 + ms(1000)), None, "not stale yet");
        assert_eq!(
            m.record(0, false, t0 + ms(2200)),
            Some(RefreshRate::ZERO),
            "nothing came back for longer than the window"
        );
        // Answers again: the rounds before the stall do not count.
        assert_eq!(m.record(0, true, t0 + ms(2300)), None);
        assert_eq!(
            m.record(0, true, t0 + ms(2400)).map(|r| r.to_string()),
            Some("10/s".into())
        );
    }

    #[test]
    fn rates_read_with_sensible_precision() {
        let rate = |ms| RefreshRate::every(Duration::from_millis(ms)).to_string();
        assert_eq!(rate(137), "7.3/s");
        assert_eq!(rate(50), "20/s");
        assert_eq!(rate(0), "0.0/s");
        assert_eq!(
            RefreshRate::every(Duration::MAX).to_string(),
            "0.0/s",
            "never panics"
        );
        assert!(
            !RefreshRate::every(Duration::from_millis(100))
                .differs(RefreshRate::every(Duration::from_millis(101)))
        );
        assert!(RefreshRate::ZERO.differs(RefreshRate::every(Duration::from_secs(100))));
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
