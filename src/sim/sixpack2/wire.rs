//! The SIXpack 2's side of the serial line (§6.1.1): 9-byte frames that
//! must arrive whole within the packet timeout ($41) and are abandoned on a
//! BREAK; replies sent only after the transmitter switch-over delay ($40),
//! as 8 bytes `CMD P0..P6` or, as a choice, 9 with the response address
//! first (digest D1.4).

use std::collections::VecDeque;
use std::time::Duration;

use super::choices::ReplyFraming;
use super::command::REQUEST_LEN;

/// Assembles request frames from bytes as they arrive.
#[derive(Debug, Default)]
pub struct Receiver {
    partial: Vec<u8>,
    /// When the partial frame's first byte arrived.
    started: Duration,
    /// Partial frames dropped (timeout or BREAK), for tests and help.
    dropped: u64,
}

impl Receiver {
    /// `byte` arrived at `now`; a frame when it completes one. A partial
    /// frame whose `timeout` had run out is dropped first, and this byte
    /// starts the next ("The command word always has to be completely
    /// transmitted during a parameterized timeout", §6.1.1: so the
    /// timeout runs from the frame's first byte).
    pub fn byte(
        &mut self,
        byte: u8,
        now: Duration,
        timeout: Option<Duration>,
    ) -> Option<[u8; REQUEST_LEN]> {
        self.expire(now, timeout);
        if self.partial.is_empty() {
            self.started = now;
        }
        self.partial.push(byte);
        if self.partial.len() < REQUEST_LEN {
            return None;
        }
        let frame = std::mem::take(&mut self.partial);
        frame.try_into().ok()
    }

    /// When the partial frame runs out of time, if there is one.
    pub fn deadline(&self, timeout: Option<Duration>) -> Option<Duration> {
        if self.partial.is_empty() {
            return None;
        }
        timeout.map(|t| self.started + t)
    }

    /// Drop the partial frame if its time is up at `now`.
    pub fn expire(&mut self, now: Duration, timeout: Option<Duration>) {
        if self
            .deadline(timeout)
            .is_some_and(|deadline| now >= deadline)
        {
            self.drop_partial();
        }
    }

    /// A BREAK: the frame in progress "will be aborted and not
    /// interpreted" (§6.1.1).
    pub fn line_break(&mut self) {
        self.drop_partial();
    }

    /// Forget everything (a reset).
    pub fn clear(&mut self) {
        self.partial.clear();
    }

    /// Bytes of a frame received so far.
    pub fn pending(&self) -> usize {
        self.partial.len()
    }

    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    fn drop_partial(&mut self) {
        if !self.partial.is_empty() {
            self.partial.clear();
            self.dropped += 1;
        }
    }
}

/// A reply: the echoed command and its seven parameter bytes.
pub fn reply_bytes(framing: ReplyFraming, respond_to: u8, code: u8, fields: [u8; 7]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(REQUEST_LEN);
    if framing == ReplyFraming::Addr9 {
        bytes.push(respond_to);
    }
    bytes.push(code);
    bytes.extend_from_slice(&fields);
    bytes
}

/// Replies waiting for their time on the line, in order.
#[derive(Debug, Default)]
pub struct Outbox {
    queue: VecDeque<(Duration, Vec<u8>)>,
}

impl Outbox {
    /// Send `bytes` at `due`, after whatever is queued before it.
    pub fn push(&mut self, due: Duration, bytes: Vec<u8>) {
        let after = self.queue.back().map_or(due, |(last, _)| due.max(*last));
        self.queue.push_back((after, bytes));
    }

    /// When the next reply is due.
    pub fn next_due(&self) -> Option<Duration> {
        self.queue.front().map(|(due, _)| *due)
    }

    /// Every reply due by `now`, appended to `out`.
    pub fn release(&mut self, now: Duration, out: &mut Vec<u8>) {
        while let Some((due, _)) = self.queue.front() {
            if *due > now {
                break;
            }
            if let Some((_, bytes)) = self.queue.pop_front() {
                out.extend_from_slice(&bytes);
            }
        }
    }

    pub fn clear(&mut self) {
        self.queue.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: Duration = Duration::from_millis(1);

    #[test]
    fn nine_bytes_make_a_frame_in_any_pieces() {
        let mut r = Receiver::default();
        let timeout = Some(50 * MS);
        for (i, byte) in (1..=8u8).enumerate() {
            assert_eq!(r.byte(byte, i as u32 * MS, timeout), None);
        }
        assert_eq!(
            r.byte(9, 8 * MS, timeout),
            Some([1, 2, 3, 4, 5, 6, 7, 8, 9])
        );
        assert_eq!(r.pending(), 0);
    }

    #[test]
    fn the_timeout_runs_from_the_first_byte() {
        let mut r = Receiver::default();
        let timeout = Some(10 * MS);
        r.byte(0xAA, Duration::ZERO, timeout);
        for n in 1..8u32 {
            r.byte(0, n * MS, timeout);
        }
        assert_eq!(r.deadline(timeout), Some(10 * MS));
        // The ninth byte at 10 ms is too late: the eight are dropped and it
        // starts a frame of its own.
        assert_eq!(r.byte(7, 10 * MS, timeout), None);
        assert_eq!((r.pending(), r.dropped()), (1, 1));
        r.expire(20 * MS, timeout);
        assert_eq!((r.pending(), r.dropped()), (0, 2));
        // Without a timeout a partial frame waits for ever.
        r.byte(1, Duration::ZERO, None);
        r.expire(Duration::from_secs(3600), None);
        assert_eq!(r.pending(), 1);
    }

    #[test]
    fn a_break_abandons_the_frame_in_progress() {
        let mut r = Receiver::default();
        for byte in [0, 0x20, 0] {
            r.byte(byte, Duration::ZERO, None);
        }
        r.line_break();
        assert_eq!((r.pending(), r.dropped()), (0, 1));
        r.line_break();
        assert_eq!(r.dropped(), 1, "nothing to abandon");
    }

    #[test]
    fn replies_keep_their_order_and_wait_for_their_time() {
        let mut o = Outbox::default();
        o.push(6 * MS, vec![1]);
        o.push(2 * MS, vec![2]);
        let mut out = Vec::new();
        o.release(5 * MS, &mut out);
        assert!(out.is_empty());
        o.release(6 * MS, &mut out);
        assert_eq!(out, [1, 2]);
    }

    #[test]
    fn addr9_puts_the_response_address_first() {
        assert_eq!(reply_bytes(ReplyFraming::Cmd8, 5, 0x43, [1; 7]).len(), 8);
        assert_eq!(
            reply_bytes(ReplyFraming::Addr9, 5, 0x43, [1; 7]),
            [5, 0x43, 1, 1, 1, 1, 1, 1, 1]
        );
    }
}
