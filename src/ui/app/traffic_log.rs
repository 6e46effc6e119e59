//! `:log FILE`: every frame to a file, each line with its wall-clock time
//! (UTC) and the milliseconds since the log began.

use std::io::Write;
use std::path::Path;
use std::time::{Instant, SystemTime};

use tokio::sync::{broadcast, mpsc, oneshot};

use super::AppEvent;
use super::runner::Connection;
use crate::device::{Direction, Priority, TrafficKind, TrafficRecord};
use crate::protocol::Family;
use crate::ui::pane::Notice;
use crate::wall_clock::CivilTime;

/// A log of every frame to a file (`:log FILE`), written by a task of its
/// own from the device's traffic stream.
pub(super) struct TrafficLog {
    stop: oneshot::Sender<()>,
}

impl TrafficLog {
    /// Start logging `connection`'s traffic to `path`; the task reports
    /// when it ends.
    pub(super) fn start(
        path: &Path,
        connection: &Connection,
        internal: &mpsc::UnboundedSender<AppEvent>,
    ) -> Result<TrafficLog, String> {
        let Some(mut traffic) = connection.controller.traffic() else {
            return Err("this connection has no traffic to log".into());
        };
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(|e| format!("cannot log to {}: {e}", path.display()))?;
        let out = std::io::LineWriter::new(file);
        let family = connection.controller.family();
        let name = path.display().to_string();
        let (stop, mut stopped) = oneshot::channel();
        let report = internal.clone();
        tokio::spawn(async move {
            let mut log = LogWriter {
                out,
                family,
                start: None,
                frames: 0,
                failure: None,
            };
            loop {
                tokio::select! {
                    _ = &mut stopped => {
                        // Everything sent before the stop is written.
                        while let Ok(record) = traffic.try_recv() {
                            log.write(&record);
                        }
                        break;
                    }
                    record = traffic.recv() => match record {
                        Ok(record) => log.write(&record),
                        Err(broadcast::error::RecvError::Lagged(n)) => {
                            log.failure
                                .get_or_insert(format!("{n} frames were missed (the disk was too slow)"));
                        }
                        Err(broadcast::error::RecvError::Closed) => break,
                    },
                }
            }
            let frames = log.frames;
            let notice = match log.failure {
                None => Notice::info(format!("log {name} closed: {frames} frames")),
                Some(e) => Notice::error(format!("log {name} closed after {frames} frames: {e}")),
            };
            let _ = report.send(AppEvent::Notice(notice));
        });
        Ok(TrafficLog { stop })
    }

    pub(super) fn stop(self) {
        let _ = self.stop.send(());
    }
}

struct LogWriter {
    out: std::io::LineWriter<std::fs::File>,
    family: &'static Family,
    /// The first frame's instant and the wall-clock time then.
    start: Option<(Instant, SystemTime)>,
    frames: u64,
    /// The first write that failed; later frames are counted, not written.
    failure: Option<String>,
}

impl LogWriter {
    fn write(&mut self, record: &TrafficRecord) {
        let (start, wall) = *self
            .start
            .get_or_insert_with(|| (record.at, SystemTime::now()));
        self.frames += 1;
        if self.failure.is_none()
            && let Err(e) = writeln!(self.out, "{}", log_line(self.family, start, wall, record))
        {
            self.failure = Some(e.to_string());
        }
    }
}

/// One logged frame: its wall-clock time (UTC, from `wall`, the time at
/// `start`), milliseconds since the log began, direction, what it was,
/// who asked, the bytes as the family shows them.
pub fn log_line(
    family: &Family,
    start: Instant,
    wall: SystemTime,
    record: &TrafficRecord,
) -> String {
    let since = record.at.saturating_duration_since(start);
    let stamp = CivilTime::of(wall + since).stamp();
    let at = since.as_secs_f64() * 1000.0;
    let direction = match record.direction {
        Direction::Sent => "->",
        Direction::Received => "<-",
    };
    let kind = match record.kind {
        TrafficKind::Request => "request",
        TrafficKind::Answer => "answer",
        TrafficKind::Unsolicited => "unsolicited",
        TrafficKind::Stale => "stale",
        TrafficKind::Garbage => "garbage",
    };
    let by = match record.priority {
        Some(Priority::EmergencyStop) => "stop",
        Some(Priority::User) => "user",
        Some(Priority::Transfer) => "transfer",
        Some(Priority::Poll) => "poll",
        None => "-",
    };
    format!(
        "{stamp} {at:>12.3} ms {direction} {kind:<11} {by:<8} {}",
        (family.show_bytes)(&record.bytes)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, UNIX_EPOCH};

    #[test]
    fn a_line_carries_its_wall_clock_time_and_the_milliseconds_since_the_start() {
        let family = crate::protocol::find_family("tmcl").expect("tmcl");
        let start = Instant::now();
        // 2024-12-31 23:59:59.999 UTC at the start.
        let wall = UNIX_EPOCH + Duration::from_millis(1_735_689_599_999);
        let record = TrafficRecord {
            at: start + Duration::from_millis(2),
            direction: Direction::Received,
            kind: TrafficKind::Answer,
            bytes: vec![2, 1, 100, 6, 0, 0, 0, 0, 109],
            priority: None,
        };
        assert_eq!(
            log_line(family, start, wall, &record),
            "2025-01-01T00:00:00.001Z        2.000 ms <- answer      -        02 01 64 06 00 00 00 00 6D"
        );
    }
}
