//! Bytes that come while no request waits for them: taken in, matched to
//! a late answer or a request's news, or logged as unrelated, stale or
//! garbage.

use super::*;

impl Task {
    /// Process input that has arrived but not been read: no request is in
    /// flight, so every frame is unsolicited or stale.
    pub(super) fn absorb(&mut self, line: &mut Line) -> Result<(), String> {
        loop {
            match line.incoming.try_recv() {
                Ok(input) => self.receive_idle(line, Some(input))?,
                Err(mpsc::error::TryRecvError::Empty) => return Ok(()),
                Err(mpsc::error::TryRecvError::Disconnected) => {
                    return self.receive_idle(line, None);
                }
            }
        }
    }

    pub(super) fn receive_idle(
        &mut self,
        line: &mut Line,
        input: Option<LinkInput>,
    ) -> Result<(), String> {
        match input {
            Some(LinkInput::Bytes(bytes)) => {
                line.heard.add(&bytes);
                let frames = line.take_bytes(&bytes);
                self.log_skipped(line);
                for frame in frames {
                    self.unrelated(line, frame);
                }
                Ok(())
            }
            Some(LinkInput::Lost(reason)) => Err(format!("{}: {reason}", line.name)),
            None => Err(format!("{}: the link closed", line.name)),
        }
    }

    /// A frame that answers no request on the wire: the late answer to an
    /// unanswered attempt (which is then answered), news, or stale.
    pub(super) fn unrelated(&mut self, line: &mut Line, frame: Frame) {
        if let Some(index) = line.late_owner(&frame) {
            line.unanswered.remove(index);
            self.stale(frame);
        } else if !self.news(&frame) {
            self.stale(frame);
        }
    }

    /// Publish `frame` as unsolicited news if the family says it is; false
    /// if it is not.
    pub(super) fn news(&mut self, frame: &[u8]) -> bool {
        let Some(description) = self.wire.unsolicited(frame) else {
            return false;
        };
        self.counters.unsolicited += 1;
        self.publish(
            Direction::Received,
            TrafficKind::Unsolicited,
            frame.to_vec(),
            None,
        );
        let _ = self.out.events.send(DeviceEvent::Unsolicited {
            frame: frame.to_vec(),
            description,
        });
        self.publish_counters();
        true
    }

    /// A well-formed frame nobody waited for (a late answer, discarded).
    pub(super) fn stale(&mut self, frame: Frame) {
        self.counters.stale_frames += 1;
        self.publish(Direction::Received, TrafficKind::Stale, frame, None);
        self.publish_counters();
    }

    /// Once the line has been quiet long enough, a partial frame is
    /// either complete (the framer says silence ends it) or dropped: the
    /// bytes dropped, and the frame.
    pub(super) fn expire_partial(
        &mut self,
        line: &mut Line,
        now: Instant,
    ) -> (Vec<u8>, Option<Frame>) {
        if line.partial_deadline().is_some_and(|at| at <= now) {
            if let Some(frame) = line.framer.complete_on_silence() {
                return (Vec::new(), Some(frame));
            }
            let bytes = line.framer.discard_pending();
            self.log_garbage(line, &bytes);
            return (bytes, None);
        }
        (Vec::new(), None)
    }

    /// Log the bytes the framer stepped over; the bytes.
    pub(super) fn log_skipped(&mut self, line: &mut Line) -> Vec<u8> {
        let bytes = line.framer.take_skipped();
        self.log_garbage(line, &bytes);
        bytes
    }

    pub(super) fn log_garbage(&mut self, line: &mut Line, bytes: &[u8]) {
        if bytes.is_empty() {
            return;
        }
        // The garbage ended with the last byte received.
        line.garbage_at = Some(line.last_rx);
        self.counters.garbage_bytes += u64::try_from(bytes.len()).unwrap_or(u64::MAX);
        self.publish(
            Direction::Received,
            TrafficKind::Garbage,
            bytes.to_vec(),
            None,
        );
        self.publish_counters();
    }
}
