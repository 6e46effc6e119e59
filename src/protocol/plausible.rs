//! Values no module can have sent: a position read that moved further
//! since the last read of the same axis than the family's fastest motion
//! allows. A family whose answers carry no checksum (SIXpack 2, CMD-4CR,
//! MCCL: [`super::console::FamilyConsole::replies_checked`]) cannot tell a
//! damaged digit from a good one; a jump of millions of steps in a few
//! milliseconds it can (issue 19: under corruption a SIXpack 2 position
//! read `-2080262363` straight after `112421`).
//!
//! The rule is pure: the session keeps the last reading of each axis and
//! the time it came, and asks [`judge`] about the next. The speed limit is
//! the family's from its manual ([`TopSpeed`]), not the configured one: a
//! setting changed behind the session's back cannot make a good value
//! look bad.

use std::time::Duration;

/// The fastest any axis of a family can change its position, in the
/// position unit of its reads, per second, and where the manual says so.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TopSpeed {
    pub per_second: f64,
    /// The manual's place for the number, for the message.
    pub source: &'static str,
}

/// A position a read gave, as the family reads it from the value
/// ([`super::console::FamilyConsole::position_read`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PositionRead {
    /// The axis (its index in the family's axis list).
    pub axis: usize,
    pub position: i64,
    /// The module may set this position by itself at any moment (a
    /// reference search runs, whose end makes its switch the new zero):
    /// no jump to or from this reading is judged.
    pub may_jump: bool,
}

/// A reading and when its answer came.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sighting {
    pub read: PositionRead,
    /// When the answer came, on any clock both sightings share.
    pub at: Duration,
    /// How long the read took on the wire: the module took its position
    /// some time in this window before `at`.
    pub round_trip: Duration,
}

/// Some counts of slack on top of the speed limit: a position sampled at
/// a step boundary, an encoder's count of jitter.
const SLACK_COUNTS: f64 = 16.0;

/// How much faster than the limit a jump must look before it is refused:
/// the module's own clock and the host's differ a little.
const MARGIN: f64 = 1.5;

/// Whether `now` can follow `last` for an axis no faster than `top`: the
/// reason it cannot, otherwise. The window is the time between the two
/// answers plus both round trips (each position was taken somewhere in
/// its read's round trip).
pub fn judge(last: &Sighting, now: &Sighting, top: TopSpeed) -> Result<(), String> {
    if last.read.axis != now.read.axis || last.read.may_jump || now.read.may_jump {
        return Ok(());
    }
    let window = now.at.saturating_sub(last.at) + last.round_trip + now.round_trip;
    let moved = (now.read.position - last.read.position).unsigned_abs() as f64;
    let reach = top.per_second * window.as_secs_f64() * MARGIN + SLACK_COUNTS;
    if moved <= reach {
        return Ok(());
    }
    Err(format!(
        "position {} after {} {} ms before: a move of {} in that time is faster than any \
         axis goes ({} per second, {}): a damaged reply",
        now.read.position,
        last.read.position,
        window.as_millis(),
        moved,
        top.per_second,
        top.source
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOP: TopSpeed = TopSpeed {
        per_second: 200_000.0,
        source: "test",
    };

    fn seen(position: i64, at_ms: u64) -> Sighting {
        Sighting {
            read: PositionRead {
                axis: 0,
                position,
                may_jump: false,
            },
            at: Duration::from_millis(at_ms),
            round_trip: Duration::from_millis(5),
        }
    }

    #[test]
    fn a_jump_faster_than_any_axis_goes_is_refused() {
        // Issue 19's reading: 112421, then -2080262363 50 ms later.
        let why = judge(&seen(112_421, 0), &seen(-2_080_262_363, 50), TOP)
            .expect_err("no axis goes that fast");
        assert!(why.contains("-2080262363 after 112421"), "{why}");
        assert!(why.contains("damaged reply"), "{why}");
    }

    #[test]
    fn a_move_at_top_speed_passes_and_so_does_standing_still() {
        // 200 kHz for 60 ms (50 ms apart, 2 × 5 ms round trips) is 12,000.
        assert!(judge(&seen(0, 0), &seen(12_000, 50), TOP).is_ok());
        assert!(judge(&seen(0, 0), &seen(-12_000, 50), TOP).is_ok());
        assert!(judge(&seen(7, 0), &seen(7, 50), TOP).is_ok());
        // Well past the margin: refused.
        assert!(judge(&seen(0, 0), &seen(30_000, 50), TOP).is_err());
    }

    #[test]
    fn a_reading_that_may_jump_or_of_another_axis_is_not_judged() {
        let mut searching = seen(0, 50);
        searching.read.may_jump = true;
        assert!(judge(&seen(9_000_000, 0), &searching, TOP).is_ok());
        assert!(judge(&searching, &seen(9_000_000, 60), TOP).is_ok());
        let mut other = seen(9_000_000, 50);
        other.read.axis = 1;
        assert!(judge(&seen(0, 0), &other, TOP).is_ok());
    }
}
