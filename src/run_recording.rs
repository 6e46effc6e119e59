//! A console session written down as an `axterm run` file (`:record
//! FILE`): every line sent with its answer, so that commissioning done
//! once by hand replays on the next machine.
//!
//! - A line that acts is written as it was typed.
//! - A line that reads is written as `:expect LINE == VALUE`, the value it
//!   answered, unless an axis was moving when it was sent (what it read
//!   then depends on timing, so it is written as a plain line with the
//!   answer in a comment).
//! - A wait: when an axis moved after a line that acts, and by the time
//!   the next line was sent a status poll showed it at rest (its "target
//!   reached" flag, its standing motion phase, or its speed 0: the
//!   strongest the family's polls give, [`RestRead`]), the poll line and
//!   the value it read become `:wait-until LINE == VALUE timeout T`.
//! - A line that failed, or was refused before sending, is a comment: it
//!   is not replayed.
//!
//! Pure: the caller hands in what happened (status snapshots, lines and
//! answers, how long since the recording began) and writes the text this
//! returns to the file. Nothing here knows a family: whether a line reads
//! is the family's [`Effect`], the conditions are the session's rest reads.

use std::collections::VecDeque;
use std::time::Duration;

use crate::protocol::console::Effect;
use crate::script::{Action, DEFAULT_WAIT_TIMEOUT, parse_script_line, result_matches};
use crate::session::{AxisMotion, AxisStatus, RestSign};

/// What a recording's header says of the session.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RecordingHeader {
    /// The family's name (`tmcl`) and what it is.
    pub family: String,
    pub family_description: String,
    /// The link as the user named it (`sim tmcm1110`, `/dev/ttyUSB0`).
    pub link: String,
    pub address: u8,
    /// The module's identity (firmware string), if read.
    pub firmware: Option<String>,
    /// When the recording began, as a date and time.
    pub started: String,
}

impl RecordingHeader {
    /// The header: comment lines, then a blank line.
    pub fn text(&self) -> String {
        let firmware = self.firmware.as_deref().unwrap_or("not read");
        format!(
            "# axterm session recording (replay: axterm run CONNECTION FILE)\n\
             # family: {} ({})\n\
             # link: {}, address {}\n\
             # firmware: {firmware}\n\
             # recorded: {}\n\n",
            self.family, self.family_description, self.link, self.address, self.started
        )
    }
}

/// How a line sent came out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineOutcome<'a> {
    /// Answered with success; the value as printed (`ok`, `1000`).
    Answered(&'a str),
    /// Sent, and the module refused it, answered nonsense or nothing.
    Failed(&'a str),
    /// Refused before anything was sent.
    NotSent(&'a str),
}

/// What the recording watches of one axis between lines.
#[derive(Debug, Clone, Default)]
struct AxisWatch {
    /// Position and target when a line that acts was sent: the axis took
    /// part in it if either changes (or it is seen moving).
    baseline: Option<Baseline>,
    moved: bool,
    /// When the line that acts was sent.
    started_at: Duration,
    /// How long after that the axis was first seen at rest.
    settled_after: Option<Duration>,
    /// An emergency stop came since: where the axis comes to rest then
    /// depends on timing, so its wait is on a sign of rest that does not
    /// (its phase, its speed 0), never on its position.
    stopped: bool,
}

type Baseline = (Option<i64>, Option<i64>);

/// The axes as they stood when a line was sent, until its answer comes.
#[derive(Debug, Clone)]
struct Sent {
    baselines: Vec<Baseline>,
    at: Duration,
}

/// A piece of the file in the order of what happened: a line sent (its
/// text once answered) or the waits before it.
#[derive(Debug, Clone)]
struct Piece {
    /// The caller's name for the line sent (none for waits).
    id: Option<u64>,
    sent: Option<Sent>,
    /// The text, once known.
    text: Option<String>,
}

/// The recording's memory between lines.
#[derive(Debug, Clone, Default)]
pub struct RunRecorder {
    axes: Vec<AxisWatch>,
    /// The latest status seen.
    status: Vec<AxisStatus>,
    /// What is not written yet, in the order lines were sent: a line
    /// refused at once is answered before one sent earlier, and is
    /// written after it all the same.
    pieces: VecDeque<Piece>,
    /// Lines written (not comments, not waits).
    lines: usize,
    waits: usize,
}

/// Standing still, whether or not on the target.
fn at_rest(status: &AxisStatus) -> bool {
    matches!(
        status.motion(),
        AxisMotion::AtTarget | AxisMotion::StoppedShort | AxisMotion::Stopped
    )
}

/// A comment line for text that may hold line breaks.
fn comment(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        out.push_str("# ");
        out.push_str(line);
        out.push('\n');
    }
    if out.is_empty() {
        out.push_str("#\n");
    }
    out
}

/// The timeout a replay gives a wait that took `took` by hand: twice as
/// long, in whole seconds, and never less than the default of `:wait-until`.
fn wait_timeout(took: Option<Duration>) -> Duration {
    let doubled = took.unwrap_or_default().saturating_mul(2);
    let seconds = doubled.as_secs() + u64::from(doubled.subsec_nanos() > 0);
    Duration::from_secs(seconds).max(DEFAULT_WAIT_TIMEOUT)
}

impl RunRecorder {
    pub fn new() -> RunRecorder {
        RunRecorder::default()
    }

    /// Lines recorded to be replayed (not comments), and waits.
    pub fn counts(&self) -> (usize, usize) {
        (self.lines, self.waits)
    }

    /// A status snapshot, `now` after the recording began.
    pub fn observe(&mut self, status: &[AxisStatus], now: Duration) {
        self.status = status.to_vec();
        self.watch(now);
    }

    /// Compare the latest status with each watched axis's baseline.
    fn watch(&mut self, now: Duration) {
        if self.axes.len() < self.status.len() {
            self.axes.resize_with(self.status.len(), AxisWatch::default);
        }
        for (watch, axis) in self.axes.iter_mut().zip(&self.status) {
            let Some((position, target)) = watch.baseline else {
                continue;
            };
            let moving = axis.motion() == AxisMotion::Moving;
            // A value first read after the line is no move.
            let differs = |then: Option<i64>, now: Option<i64>| matches!((then, now), (Some(a), Some(b)) if a != b);
            if moving || differs(position, axis.position) || differs(target, axis.target) {
                watch.moved = true;
            }
            if moving {
                watch.settled_after = None;
            } else if watch.moved && watch.settled_after.is_none() && at_rest(axis) {
                watch.settled_after = Some(now.saturating_sub(watch.started_at));
            }
        }
    }

    /// Lines sent whose answers will never come (the emergency stop
    /// dropped them): forget them. Returns what can be written now.
    pub fn forget_unanswered(&mut self) -> String {
        self.pieces.retain(|p| p.text.is_some());
        self.ready()
    }

    /// The recording ends: the waits the technician made since the last
    /// line (an axis that came to rest after it, an emergency stop
    /// above all) are written too, so that a replay ends where the
    /// recording did, no axis moving. Returns what can be written now.
    pub fn finish(&mut self) -> String {
        let mut text = self.ready();
        text.push_str(&self.waits_made());
        text
    }

    /// The emergency stop's lines and how each came out, `now` after the
    /// recording began: written as the lines they are, as sent (they are
    /// what happened, and a replay must stop the axes there too), each
    /// after the waits made before it like any line that acts; a stop line
    /// that failed or was never sent is a comment. Returns what can be
    /// written now.
    pub fn emergency_stop(&mut self, lines: &[(&str, LineOutcome)], now: Duration) -> String {
        let mut text = self.forget_unanswered();
        text.push_str(&self.waits_made());
        text.push_str(if lines.is_empty() {
            "# emergency stop here: no stop line was sent\n"
        } else {
            "# emergency stop here: the stop lines it sent\n"
        });
        for &(line, outcome) in lines {
            let line = line.trim();
            text.push_str(&match outcome {
                LineOutcome::Answered(_) => {
                    self.line_text(line, None, Some(Effect::Acts), outcome, now)
                }
                LineOutcome::Failed(why) => {
                    comment(&format!("stop line failed, not replayed: {line}  ({why})"))
                }
                LineOutcome::NotSent(why) => {
                    comment(&format!("stop line not sent: {line}  ({why})"))
                }
            });
        }
        for watch in &mut self.axes {
            watch.stopped = true;
        }
        text
    }

    /// The text of the pieces at the front that are complete.
    fn ready(&mut self) -> String {
        let mut text = String::new();
        while let Some(piece) = self.pieces.front_mut() {
            let Some(done) = piece.text.take() else {
                break;
            };
            text.push_str(&done);
            self.pieces.pop_front();
        }
        text
    }

    /// Line `id` (the caller's name for it) is about to be sent, `now`
    /// after the recording began: the waits the technician made since the
    /// last line go before it. Returns what can be written now.
    pub fn before_line(&mut self, id: u64, now: Duration) -> String {
        let waits = self.waits_made();
        self.pieces.push_back(Piece {
            id: None,
            sent: None,
            text: Some(waits),
        });
        self.pieces.push_back(Piece {
            id: Some(id),
            sent: Some(Sent {
                baselines: self.status.iter().map(|a| (a.position, a.target)).collect(),
                at: now,
            }),
            text: None,
        });
        self.ready()
    }

    fn waits_made(&mut self) -> String {
        let mut text = String::new();
        for (watch, axis) in self.axes.iter_mut().zip(&self.status) {
            if !watch.moved || !at_rest(axis) {
                continue;
            }
            let took = watch.settled_after;
            let stopped = watch.stopped;
            *watch = AxisWatch::default();
            let evidence = if stopped {
                axis.rest_evidence().and_then(|_| {
                    axis.rest_reads
                        .iter()
                        .filter(|r| r.at_rest.is_some() && r.sign != RestSign::Position)
                        .max_by_key(|r| r.sign)
                })
            } else {
                axis.rest_evidence()
            };
            let Some(evidence) = evidence else {
                continue;
            };
            let Some(value) = evidence.at_rest.as_deref() else {
                continue;
            };
            let timeout = wait_timeout(took);
            let wait = format!(
                ":wait-until {} == {value} timeout {}s",
                evidence.line,
                timeout.as_secs()
            );
            let round_trips = matches!(
                parse_script_line(&wait),
                Ok(Some(Action::WaitUntil { line, value: v, .. }))
                    if line == evidence.line && result_matches(value, &v)
            );
            if round_trips {
                text.push_str(&wait);
                text.push('\n');
                self.waits += 1;
            } else {
                text.push_str(&comment(&format!(
                    "waited until {} read {value} (not writable as :wait-until)",
                    evidence.line
                )));
            }
        }
        text
    }

    /// The answer to line `id`, `line` as typed, whose family says it
    /// `effect`s (`None`: it did not parse), `now` after the recording
    /// began. Returns what can be written now.
    pub fn answered(
        &mut self,
        id: u64,
        line: &str,
        effect: Option<Effect>,
        outcome: LineOutcome,
        now: Duration,
    ) -> String {
        let piece = self.pieces.iter().position(|p| p.id == Some(id));
        let sent = piece.and_then(|i| self.pieces.get_mut(i)?.sent.take());
        let text = self.line_text(line.trim(), sent, effect, outcome, now);
        match piece.and_then(|i| self.pieces.get_mut(i)) {
            Some(piece) => piece.text = Some(text),
            // Sent before the recording began: written in answer order.
            None => self.pieces.push_back(Piece {
                id: None,
                sent: None,
                text: Some(text),
            }),
        }
        self.ready()
    }

    fn line_text(
        &mut self,
        line: &str,
        sent: Option<Sent>,
        effect: Option<Effect>,
        outcome: LineOutcome,
        now: Duration,
    ) -> String {
        let value = match outcome {
            LineOutcome::Answered(value) => value,
            LineOutcome::Failed(why) => return comment(&format!("failed: {line}  ({why})")),
            LineOutcome::NotSent(why) => return comment(&format!("not sent: {line}  ({why})")),
        };
        self.lines += 1;
        if effect == Some(Effect::Reads) {
            return self.read(line, value);
        }
        // Any axis not yet seen moving may move now: watched from where
        // it stood when the line went out (a poll may have shown it
        // moving before this answer came).
        let sent = sent.unwrap_or(Sent {
            baselines: self.status.iter().map(|a| (a.position, a.target)).collect(),
            at: now,
        });
        for (watch, baseline) in self.axes.iter_mut().zip(&sent.baselines) {
            if !watch.moved {
                *watch = AxisWatch {
                    baseline: Some(*baseline),
                    started_at: sent.at,
                    ..AxisWatch::default()
                };
            }
        }
        self.watch(now);
        format!("{line}\n")
    }

    fn read(&self, line: &str, value: &str) -> String {
        if let Some(axis) = self
            .status
            .iter()
            .position(|a| a.motion() == AxisMotion::Moving)
        {
            return format!(
                "{line}\n{}",
                comment(&format!(
                    "answered {value} while axis {axis} moved: not checked on replay"
                ))
            );
        }
        let expect = format!(":expect {line} == {value}");
        let round_trips = matches!(
            parse_script_line(&expect),
            Ok(Some(Action::Expect { line: l, value: v })) if l == line && result_matches(value, &v)
        );
        if round_trips {
            format!("{expect}\n")
        } else {
            format!("{line}\n{}", comment(&format!("answered: {value}")))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::console::MotionPhase;
    use crate::script::parse_script;
    use crate::session::RestRead;
    use proptest::prelude::*;

    const S: fn(u64) -> Duration = Duration::from_secs;

    fn standing(position: i64, target: i64, reached_read: Option<&str>) -> AxisStatus {
        let mut status = AxisStatus {
            position: Some(position),
            target: Some(target),
            speed: Some(0),
            reached: Some(position == target),
            ..AxisStatus::default()
        };
        status.note_rest(RestRead {
            line: "GAP 8, 0".into(),
            sign: RestSign::Reached,
            at_rest: reached_read.map(str::to_string),
        });
        status
    }

    fn moving(position: i64, target: i64) -> AxisStatus {
        AxisStatus {
            position: Some(position),
            target: Some(target),
            speed: Some(500),
            reached: Some(false),
            phase: Some(MotionPhase::Constant),
            ..AxisStatus::default()
        }
    }

    #[test]
    fn the_header_names_family_link_firmware_and_time() {
        let header = RecordingHeader {
            family: "tmcl".into(),
            family_description: "Trinamic TMCL".into(),
            link: "sim tmcm1110".into(),
            address: 1,
            firmware: Some("1110V112".into()),
            started: "2025-03-07 14:05:09 UTC".into(),
        }
        .text();
        assert!(
            header.contains("# family: tmcl (Trinamic TMCL)\n"),
            "{header}"
        );
        assert!(
            header.contains("# link: sim tmcm1110, address 1\n"),
            "{header}"
        );
        assert!(header.contains("# firmware: 1110V112\n"), "{header}");
        assert!(
            header.contains("# recorded: 2025-03-07 14:05:09 UTC\n"),
            "{header}"
        );
        assert_eq!(parse_script(&header), Ok(Vec::new()), "all comments");
    }

    /// Send `line` at `at` and take its answer at once: the waits written
    /// before it, and what is written for it.
    fn send(
        r: &mut RunRecorder,
        line: &str,
        effect: Effect,
        outcome: LineOutcome,
        at: Duration,
    ) -> (String, String) {
        let id = next_id();
        let waits = r.before_line(id, at);
        (waits, r.answered(id, line, Some(effect), outcome, at))
    }

    fn next_id() -> u64 {
        use std::sync::atomic::{AtomicU64, Ordering};
        static NEXT: AtomicU64 = AtomicU64::new(0);
        NEXT.fetch_add(1, Ordering::Relaxed)
    }

    fn act(r: &mut RunRecorder, line: &str, at: Duration) -> String {
        let (waits, text) = send(r, line, Effect::Acts, LineOutcome::Answered("ok"), at);
        assert_eq!(text, format!("{line}\n"));
        waits
    }

    #[test]
    fn reads_become_expectations_and_lines_that_act_stay_as_typed() {
        let mut r = RunRecorder::new();
        r.observe(&[standing(0, 0, Some("1"))], S(0));
        let a = send(
            &mut r,
            "SAP 4, 0, 1000",
            Effect::Acts,
            LineOutcome::Answered("ok"),
            S(1),
        );
        let b = send(
            &mut r,
            "GAP 4, 0",
            Effect::Reads,
            LineOutcome::Answered("1000"),
            S(2),
        );
        assert_eq!(a, (String::new(), "SAP 4, 0, 1000\n".into()));
        assert_eq!(b, (String::new(), ":expect GAP 4, 0 == 1000\n".into()));
        assert_eq!(r.counts(), (2, 0));
    }

    #[test]
    fn failed_and_refused_lines_are_comments_that_do_not_replay() {
        let mut r = RunRecorder::new();
        let (_, failed) = send(
            &mut r,
            "SAP 6, 0, 200",
            Effect::Acts,
            LineOutcome::Failed("module 1 rejected SAP 6, 0, 200: invalid value (status 4)"),
            S(0),
        );
        r.before_line(7, S(0));
        let refused = r.answered(
            7,
            "BOGUS",
            None,
            LineOutcome::NotSent("unknown\ncommand"),
            S(0),
        );
        assert_eq!(
            failed,
            "# failed: SAP 6, 0, 200  (module 1 rejected SAP 6, 0, 200: invalid value (status 4))\n"
        );
        assert_eq!(refused, "# not sent: BOGUS  (unknown\n# command)\n");
        assert_eq!(parse_script(&(failed + &refused)), Ok(Vec::new()));
        assert_eq!(r.counts(), (0, 0));
    }

    #[test]
    fn a_move_waited_for_becomes_a_wait_until_on_the_poll_that_showed_it() {
        let mut r = RunRecorder::new();
        r.observe(&[standing(0, 0, Some("1"))], S(0));
        act(&mut r, "MVP ABS, 0, 5000", S(1));
        r.observe(&[moving(100, 5000)], S(2));
        r.observe(&[moving(3000, 5000)], S(4));
        r.observe(&[standing(5000, 5000, Some("1"))], S(8));
        // Seven seconds by hand: a replay may take 14.
        assert_eq!(
            act(&mut r, "SAP 4, 0, 10", S(9)),
            ":wait-until GAP 8, 0 == 1 timeout 14s\n"
        );
        // Said once.
        assert_eq!(act(&mut r, "SAP 4, 0, 20", S(10)), "");
        assert_eq!(r.counts(), (3, 1));
    }

    #[test]
    fn a_move_over_before_its_answer_came_is_waited_for_by_its_position() {
        let mut r = RunRecorder::new();
        r.observe(&[standing(0, 0, Some("1"))], S(0));
        r.before_line(1, S(0));
        // A poll saw it arrive before the answer was taken.
        r.observe(&[standing(10, 10, Some("1"))], S(0));
        r.answered(
            1,
            "MVP REL, 0, 10",
            Some(Effect::Acts),
            LineOutcome::Answered("ok"),
            S(0),
        );
        assert_eq!(
            act(&mut r, "SAP 4, 0, 10", S(1)),
            ":wait-until GAP 8, 0 == 1 timeout 10s\n"
        );
    }

    #[test]
    fn no_wait_when_nothing_moved_or_the_axis_still_moves() {
        let mut r = RunRecorder::new();
        r.observe(&[standing(0, 0, Some("1"))], S(0));
        act(&mut r, "SAP 4, 0, 1000", S(0));
        r.observe(&[standing(0, 0, Some("1"))], S(1));
        assert_eq!(
            act(&mut r, "MVP ABS, 0, 900", S(2)),
            "",
            "a setting moves nothing"
        );
        r.observe(&[moving(10, 900)], S(3));
        // A read meanwhile: the technician did not wait, and what it read
        // is not checked on replay.
        let read = send(
            &mut r,
            "GAP 1, 0",
            Effect::Reads,
            LineOutcome::Answered("10"),
            S(3),
        );
        assert_eq!(
            read,
            (
                String::new(),
                "GAP 1, 0\n# answered 10 while axis 0 moved: not checked on replay\n".into()
            )
        );
        // It settles before the line after: that one waits.
        r.observe(&[standing(900, 900, Some("1"))], S(4));
        assert_eq!(
            act(&mut r, "SAP 4, 0, 10", S(5)),
            ":wait-until GAP 8, 0 == 1 timeout 10s\n"
        );
    }

    #[test]
    fn a_stop_short_of_the_target_waits_on_the_best_sign_of_rest() {
        let mut r = RunRecorder::new();
        r.observe(&[standing(0, 0, Some("1"))], S(0));
        act(&mut r, "MVP ABS, 0, 900", S(0));
        r.observe(&[moving(10, 900)], S(1));
        let mut stopped = standing(400, 900, None);
        stopped.note_rest(RestRead {
            line: "GAP 3, 0".into(),
            sign: RestSign::Speed,
            at_rest: Some("0".into()),
        });
        r.observe(&[stopped], S(2));
        assert_eq!(
            act(&mut r, "SAP 4, 0, 10", S(3)),
            ":wait-until GAP 3, 0 == 0 timeout 10s\n"
        );
    }

    #[test]
    fn lines_the_emergency_stop_dropped_are_forgotten() {
        let mut r = RunRecorder::new();
        r.observe(&[standing(0, 0, Some("1"))], S(0));
        assert_eq!(r.before_line(1, S(0)), "");
        assert_eq!(r.forget_unanswered(), "");
        // The next line's answer is taken against its own baseline.
        act(&mut r, "MVP ABS, 0, 50", S(1));
        r.observe(&[standing(50, 50, Some("1"))], S(2));
        assert_eq!(
            act(&mut r, "SAP 4, 0, 10", S(3)),
            ":wait-until GAP 8, 0 == 1 timeout 10s\n"
        );
    }

    #[test]
    fn the_emergency_stop_is_written_as_the_stop_lines_it_sent() {
        let mut r = RunRecorder::new();
        r.observe(&[standing(0, 0, Some("1"))], S(0));
        act(&mut r, "MVP REL, 0, 5000", S(1));
        r.observe(&[moving(100, 5000)], S(2));
        // A line waiting for its answer when the stop came is dropped.
        assert_eq!(r.before_line(7, S(2)), "");
        let written = r.emergency_stop(
            &[
                ("MST 0", LineOutcome::Answered("ok")),
                ("STOPAPP", LineOutcome::Failed("no reply within 200 ms")),
                ("MST 0", LineOutcome::NotSent("not connected")),
            ],
            S(3),
        );
        assert_eq!(
            written,
            "# emergency stop here: the stop lines it sent\n\
             MST 0\n\
             # stop line failed, not replayed: STOPAPP  (no reply within 200 ms)\n\
             # stop line not sent: MST 0  (not connected)\n"
        );
        assert_eq!(r.counts(), (2, 0), "the move and the stop line");
        // The axis comes to rest after the stop: the next line waits for
        // it, as the end of the recording does.
        let mut short = standing(2000, 5000, None);
        // Where it came to rest depends on when the stop came: not waited on.
        short.note_rest(RestRead {
            line: "GAP 1, 0".into(),
            sign: RestSign::Position,
            at_rest: Some("2000".into()),
        });
        short.note_rest(RestRead {
            line: "GAP 3, 0".into(),
            sign: RestSign::Speed,
            at_rest: Some("0".into()),
        });
        r.observe(&[short], S(4));
        let mut ended = r.clone();
        assert_eq!(
            act(&mut r, "SAP 4, 0, 10", S(5)),
            ":wait-until GAP 3, 0 == 0 timeout 10s\n"
        );
        assert_eq!(ended.finish(), ":wait-until GAP 3, 0 == 0 timeout 10s\n");
    }

    #[test]
    fn pieces_are_written_in_the_order_lines_were_sent() {
        let mut r = RunRecorder::new();
        r.observe(&[standing(0, 0, Some("1"))], S(0));
        assert_eq!(r.before_line(1, S(0)), "");
        assert_eq!(r.before_line(2, S(0)), "");
        // The second is refused at once; it waits for the first.
        let refused = r.answered(
            2,
            "SAP 6, 0, 999",
            None,
            LineOutcome::NotSent("range"),
            S(0),
        );
        assert_eq!(refused, "");
        let both = r.answered(
            1,
            "SAP 4, 0, 9",
            Some(Effect::Acts),
            LineOutcome::Answered("ok"),
            S(0),
        );
        assert_eq!(both, "SAP 4, 0, 9\n# not sent: SAP 6, 0, 999  (range)\n");
        // An answer to a line sent before the recording began.
        let early = r.answered(
            99,
            "GAP 1, 0",
            Some(Effect::Reads),
            LineOutcome::Answered("0"),
            S(0),
        );
        assert_eq!(early, ":expect GAP 1, 0 == 0\n");
    }

    #[test]
    fn a_value_first_read_after_a_line_is_no_move() {
        let mut r = RunRecorder::new();
        r.observe(&[AxisStatus::default()], S(0));
        act(&mut r, "EO=15", S(0));
        r.observe(&[standing(300, 300, Some("1"))], S(1));
        assert_eq!(act(&mut r, "SAP 4, 0, 10", S(2)), "");
    }

    #[test]
    fn values_that_would_not_read_back_are_kept_as_comments() {
        let mut r = RunRecorder::new();
        let (_, odd) = send(
            &mut r,
            "A == B",
            Effect::Reads,
            LineOutcome::Answered("1"),
            S(0),
        );
        assert_eq!(odd, "A == B\n# answered: 1\n");
        let (_, empty) = send(
            &mut r,
            "GFW",
            Effect::Reads,
            LineOutcome::Answered(""),
            S(0),
        );
        assert_eq!(empty, "GFW\n# answered: \n");
    }

    /// A wait is written on a status poll line: for every family, each
    /// one reads again as a console line that only reads, as
    /// `:wait-until` wants.
    #[test]
    fn every_familys_status_polls_are_lines_a_wait_until_takes() {
        for family in crate::families::FAMILIES {
            let address = family.console.default_address();
            for poll in family.console.status_queries(address) {
                let wait = format!(":wait-until {} == 0 timeout 10s", poll.line.canonical);
                let checked = crate::script::check_script("f", &wait, family, address);
                assert!(checked.is_ok(), "{}: {wait}: {checked:?}", family.name);
            }
        }
    }

    proptest! {
        /// Whatever is answered, the recording is a file `axterm run`
        /// parses, and a read's expectation matches what was read.
        #[test]
        fn every_recording_parses_and_expects_what_was_read(
            lines in proptest::collection::vec(("[A-Z]{2,4}( [0-9]{1,3}(, [0-9]{1,3})?)?", any::<bool>(), "\\PC{0,12}", 0u8..3), 1..12),
        ) {
            let mut r = RunRecorder::new();
            let mut file = String::new();
            for (line, reads, value, kind) in &lines {
                let effect = Some(if *reads { Effect::Reads } else { Effect::Acts });
                let outcome = match kind {
                    0 => LineOutcome::Answered(value),
                    1 => LineOutcome::Failed(value),
                    _ => LineOutcome::NotSent(value),
                };
                let id = next_id();
                file.push_str(&r.before_line(id, S(0)));
                let text = r.answered(id, line, effect, outcome, S(0));
                if let (Ok(steps), true, 0) = (parse_script(&text), *reads, kind)
                    && let Some(Action::Expect { value: v, .. }) = steps.first().map(|s| &s.action)
                {
                    prop_assert!(result_matches(value, v));
                }
                file.push_str(&text);
            }
            prop_assert!(parse_script(&file).is_ok(), "{}", file);
        }
    }
}
