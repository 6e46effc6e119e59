//! `:log FILE`: every frame to a file.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use tokio::sync::{broadcast, mpsc, oneshot};

use super::AppEvent;
use super::runner::Connection;
use crate::device::{Direction, Priority, TrafficKind, TrafficRecord};
use crate::protocol::Family;
use crate::ui::pane::Notice;

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
    start: Option<Instant>,
    frames: u64,
    /// The first write that failed; later frames are counted, not written.
    failure: Option<String>,
}

impl LogWriter {
    fn write(&mut self, record: &TrafficRecord) {
        let start = *self.start.get_or_insert(record.at);
        self.frames += 1;
        if self.failure.is_none()
            && let Err(e) = writeln!(self.out, "{}", log_line(self.family, start, record))
        {
            self.failure = Some(e.to_string());
        }
    }
}

/// One logged frame: milliseconds since the log began, direction, what it
/// was, who asked, the bytes as the family shows them.
pub fn log_line(family: &Family, start: Instant, record: &TrafficRecord) -> String {
    let at = record.at.saturating_duration_since(start).as_secs_f64() * 1000.0;
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
        "{at:>12.3} ms {direction} {kind:<11} {by:<8} {}",
        (family.show_bytes)(&record.bytes)
    )
}
