//! How often each status item is polled: the cadence asked for, and what
//! a line's speed leaves of it to the slow items and to the switches a
//! technician is watching (the urgent items, `device/poll.rs`).

use std::time::Duration;

use crate::protocol::console::StatusPoll;
use crate::protocol::wire::WireFormat;

/// How often status is polled, at most; the link's speed may make it less
/// often. Zero polls as often as the link allows.
///
/// On a slow line the fast items take what the line gives (the device
/// task polls only when nothing else waits, one poll at a time, so a
/// user's line waits for at most the poll on the wire). The slow items
/// would take their share of it too: on a line with a known speed their
/// period is stretched so that they take at most a fortieth of it
/// ([`slow_period`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PollCadence {
    /// Position, speed, target reached.
    pub fast: Duration,
    /// Switches, load, error flags, target.
    pub slow: Duration,
}

impl Default for PollCadence {
    /// 20 Hz for what moves, 5 Hz for the rest: smooth gauges without
    /// spending a slow link on values that rarely change.
    fn default() -> Self {
        PollCadence {
            fast: Duration::from_millis(50),
            slow: Duration::from_millis(200),
        }
    }
}

/// At most this share of a line's time (1 / N) goes to the slow status
/// items (switches, load, error flags, maximum speeds) and watched lines:
/// on a CMD-4CR at 9600 Bd the five HSPD reads at 5 Hz took about a
/// quarter of the line from the positions and speeds, and at a tenth the
/// fast items could reach at most nine tenths of what the wire allows them
/// (`bench/*_refresh.py`: 93 % on a CMD-4CR, 82 % on a MultiFlex at
/// 9600 Bd). A fortieth leaves them 97.5 %; the slow items still come at
/// their cadence on a fast line (at 9600 Bd a CMD-4CR's six take 4 s).
pub const SLOW_SHARE_DIVISOR: u32 = 40;

/// How often the slow items of `polls` are polled at most: as `cadence`
/// asks, or less often where one pass over them would take more than
/// 1/[`SLOW_SHARE_DIVISOR`] of the line (`byte_time`: one byte's wire
/// time, `None` when the link does not say, as over TCP). `wire` says what
/// an exchange costs: its bytes on the busier direction
/// ([`WireFormat::exchange_bytes`]) and the module's turnaround.
pub fn slow_period(
    cadence: PollCadence,
    byte_time: Option<Duration>,
    wire: &dyn WireFormat,
    polls: &[StatusPoll],
) -> Duration {
    let Some(byte_time) = byte_time else {
        return cadence.slow;
    };
    let pass = pass_time(byte_time, wire, polls.iter().filter(|p| !p.fast));
    cadence.slow.max(pass.saturating_mul(SLOW_SHARE_DIVISOR))
}

/// How long one exchange of each of `polls` takes on the wire together.
fn pass_time<'a>(
    byte_time: Duration,
    wire: &dyn WireFormat,
    polls: impl Iterator<Item = &'a StatusPoll>,
) -> Duration {
    polls
        .map(|p| {
            let bytes = u32::try_from(wire.exchange_bytes(&p.line.bytes)).unwrap_or(u32::MAX);
            byte_time
                .saturating_mul(bytes)
                .saturating_add(wire.turnaround())
        })
        .fold(Duration::ZERO, Duration::saturating_add)
}

/// How often a switch a technician is watching is read at least, where
/// the line allows it: half the 200 ms issue 20 gives a lamp to follow
/// its switch on a 9600 Bd line, the other half for the poll already on
/// the wire, the read itself and the screen.
pub const LAMP_PERIOD: Duration = Duration::from_millis(100);

/// The most of a line's time (numerator, denominator) the urgent items
/// take: a quarter is left to the rest, so that positions still move on
/// the screen while a lamp is watched.
pub const URGENT_SHARE_MOST: (u32, u32) = (3, 4);

/// How often the urgent items (the lines watched fast, see
/// `Session::watch_at`) are polled: as often as the fast items where the
/// line has time for it; on a slower line, so that they take at most half
/// of it, or more where that would leave a lamp longer than
/// [`LAMP_PERIOD`] between reads, but never more than
/// [`URGENT_SHARE_MOST`]. At 9600 Bd a SIXpack 2's two switch reads
/// (reference inputs, motor 0's A_In) take about 50 ms: every 100 ms,
/// half the line, where a round of its fourteen items took 350 ms; a
/// MultiFlex's `TC0` (20 bytes back) goes at the fast cadence. Where the
/// link does not say its speed (`byte_time` `None`), the fast cadence.
pub fn urgent_period(
    cadence: PollCadence,
    byte_time: Option<Duration>,
    wire: &dyn WireFormat,
    urgent: &[&StatusPoll],
) -> Duration {
    let Some(byte_time) = byte_time else {
        return cadence.fast;
    };
    let pass = pass_time(byte_time, wire, urgent.iter().copied());
    let (part, whole) = URGENT_SHARE_MOST;
    let half = pass.saturating_mul(2).min(LAMP_PERIOD);
    let most = pass.saturating_mul(whole) / part;
    cadence.fast.max(half).max(most)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::find_family;
    use crate::link::byte_time;

    /// A SIXpack 2's two switch reads, as the bring-up pane watches them
    /// for motor 0 (`GetInputValues 7`, `GetInputValues 0`).
    fn sixpack2_switch_reads() -> (std::sync::Arc<dyn WireFormat>, Vec<StatusPoll>) {
        let family = find_family("sixpack2").expect("sixpack2");
        let console = family.console;
        let reads = ["GetInputValues 7", "GetInputValues 0"]
            .iter()
            .map(|line| StatusPoll {
                axis: 0,
                line: console.prepare(line, 0).expect(line),
                fast: true,
            })
            .collect();
        (console.wire(), reads)
    }

    #[test]
    fn urgent_items_take_half_a_slow_line_more_to_keep_a_lamp_within_its_period() {
        let cadence = PollCadence::default();
        let (wire, reads) = sixpack2_switch_reads();
        let reads: Vec<&StatusPoll> = reads.iter().collect();
        let pass = pass_time(byte_time(9600), wire.as_ref(), reads.iter().copied());
        let period = |baud| urgent_period(cadence, Some(byte_time(baud)), wire.as_ref(), &reads);
        // Fast enough a line: as often as the fast items.
        assert_eq!(period(115_200), cadence.fast);
        assert_eq!(
            urgent_period(cadence, None, wire.as_ref(), &reads),
            cadence.fast
        );
        // At 9600 Bd the two reads take about 50 ms: half the line, each
        // read within LAMP_PERIOD.
        assert!(pass >= Duration::from_millis(45), "{pass:?}");
        assert_eq!(period(9600), (pass * 2).min(LAMP_PERIOD));
        assert!(period(9600) <= LAMP_PERIOD);
        // At 2400 Bd half the line would leave a lamp 400 ms between
        // reads: they take three quarters, and no more.
        let slow = pass_time(byte_time(2400), wire.as_ref(), reads.iter().copied());
        assert_eq!(period(2400), slow * 4 / 3);
        assert!(period(2400) > LAMP_PERIOD);
    }
}
