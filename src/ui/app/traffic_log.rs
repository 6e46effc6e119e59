//! `:log FILE`: every frame to a file, each line with its wall-clock time
//! (UTC) and the milliseconds since the log began.

use std::io::Write;
use std::path::Path;
use std::sync::mpsc as std_mpsc;
use std::time::{Instant, SystemTime};

use tokio::sync::{broadcast, mpsc, watch};

use super::AppEvent;
use super::runner::Connection;
use crate::device::{Direction, Priority, TrafficKind, TrafficRecord};
use crate::protocol::Family;
use crate::ui::pane::Notice;
use crate::wall_clock::CivilTime;

/// A log of every frame to a file (`:log FILE`): a task per link takes
/// its frames from the device's traffic stream and hands them to one
/// thread that writes the file, so no file write waits on the runtime.
pub(super) struct TrafficLog {
    stop: watch::Sender<bool>,
}

/// What a link's reader hands the writer.
enum Logged {
    Frame {
        family: &'static Family,
        link: Option<String>,
        record: TrafficRecord,
    },
    /// The link's stream ran ahead of the reader.
    Missed(u64),
}

impl TrafficLog {
    /// Start logging the traffic of `links` (one connection of each link:
    /// the modules of a bus share theirs) to `path`, each line naming its
    /// link when there are several; the writer reports when it ends.
    pub(super) fn start(
        path: &Path,
        existing: crate::files::Existing,
        links: &[&Connection],
        internal: &mpsc::UnboundedSender<AppEvent>,
    ) -> Result<TrafficLog, String> {
        let mut streams = Vec::new();
        for connection in links {
            if let Some(traffic) = connection.controller.traffic() {
                let label = (links.len() > 1).then(|| format!("L{}", connection.link + 1));
                streams.push((label, connection.controller.family(), traffic));
            }
        }
        if streams.is_empty() {
            return Err("this connection has no traffic to log".into());
        }
        let file = crate::files::open_growing(path, existing)
            .map_err(|e| format!("cannot log to {}: {e}", path.display()))?;
        let (stop, stopped) = watch::channel(false);
        let (to_writer, logged) = std_mpsc::channel();
        for (label, family, traffic) in streams {
            tokio::spawn(read_link(
                traffic,
                family,
                label,
                to_writer.clone(),
                stopped.clone(),
            ));
        }
        let name = path.display().to_string();
        let report = internal.clone();
        // Ends when every reader has (each drops its sender).
        std::thread::spawn(move || {
            let mut log = LogWriter {
                out: std::io::LineWriter::new(file),
                start: None,
                frames: 0,
                failure: None,
            };
            for logged in logged {
                match logged {
                    Logged::Frame {
                        family,
                        link,
                        record,
                    } => log.write(family, link.as_deref(), &record),
                    Logged::Missed(n) => {
                        log.failure.get_or_insert(format!(
                            "{n} frames were missed (the disk was too slow)"
                        ));
                    }
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
        let _ = self.stop.send(true);
    }
}

/// Hand one link's frames to the writer until told to stop (then
/// everything that link sent before the stop) or the link is gone.
async fn read_link(
    mut traffic: broadcast::Receiver<TrafficRecord>,
    family: &'static Family,
    link: Option<String>,
    to_writer: std_mpsc::Sender<Logged>,
    mut stopped: watch::Receiver<bool>,
) {
    let frame = |record| Logged::Frame {
        family,
        link: link.clone(),
        record,
    };
    loop {
        tokio::select! {
            _ = stopped.changed() => {
                while let Ok(record) = traffic.try_recv() {
                    let _ = to_writer.send(frame(record));
                }
                return;
            }
            record = traffic.recv() => {
                let logged = match record {
                    Ok(record) => frame(record),
                    Err(broadcast::error::RecvError::Lagged(n)) => Logged::Missed(n),
                    Err(broadcast::error::RecvError::Closed) => return,
                };
                if to_writer.send(logged).is_err() {
                    return;
                }
            }
        }
    }
}

struct LogWriter {
    out: std::io::LineWriter<std::fs::File>,
    /// The first frame's instant and the wall-clock time then.
    start: Option<(Instant, SystemTime)>,
    frames: u64,
    /// The first write that failed; later frames are counted, not written.
    failure: Option<String>,
}

impl LogWriter {
    fn write(&mut self, family: &Family, link: Option<&str>, record: &TrafficRecord) {
        let (start, wall) = *self
            .start
            .get_or_insert_with(|| (record.at, SystemTime::now()));
        self.frames += 1;
        if self.failure.is_none()
            && let Err(e) = writeln!(self.out, "{}", log_line(family, link, start, wall, record))
        {
            self.failure = Some(e.to_string());
        }
    }
}

/// One logged frame: its wall-clock time (UTC, from `wall`, the time at
/// `start`), milliseconds since the log began, its link when there are
/// several (`L2`), direction, what it was, who asked, the bytes as the
/// family shows them.
pub fn log_line(
    family: &Family,
    link: Option<&str>,
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
    let link = link.map_or(String::new(), |link| format!("{link} "));
    format!(
        "{stamp} {at:>12.3} ms {link}{direction} {kind:<11} {by:<8} {}",
        (family.show_bytes)(&record.bytes)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, UNIX_EPOCH};

    #[test]
    fn a_line_carries_its_wall_clock_time_and_the_milliseconds_since_the_start() {
        let family = crate::families::find_family("tmcl").expect("tmcl");
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
            log_line(family, None, start, wall, &record),
            "2025-01-01T00:00:00.001Z        2.000 ms <- answer      -        02 01 64 06 00 00 00 00 6D"
        );
    }
}
