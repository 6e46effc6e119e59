//! SIXpack 2 frames on RS-232/RS-485 (§6.1.1, §6.2, §7).
//!
//! A request is always 9 bytes, `ADDR CMD P0..P6`, with unused bytes sent
//! as `$00` and no checksum, delimiter or length byte; multi-byte fields
//! are least significant byte first. A reply is, by the letter of the
//! manual, 8 bytes `CMD P0..P6`: the echoed command and no address byte
//! (§6.2.2.3's pseudocode reads exactly that). Whether a unit puts the
//! response address in front, mirroring the request (9 bytes), is not
//! known (digest D1.4): [`ReplyFraming`] offers both and a mode that
//! tells them apart.

use std::fmt;

use super::catalog::is_replying;

/// Bytes of a request (§6.1.1).
pub const REQUEST_LEN: usize = 9;

/// Parameter bytes P0..P6 of a request or a reply.
pub const PARAMS: usize = 7;

/// The response address the console puts in its queries: no replying
/// command is `$00`, so an address-first reply is never taken for an
/// address-less one (digest D1.4).
pub const CONSOLE_RESPONSE_ADDRESS: u8 = 0;

/// One request as sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Request {
    /// The unit address (rotary switches, or `$42`).
    pub address: u8,
    pub command: u8,
    pub params: [u8; PARAMS],
}

impl Request {
    pub fn to_bytes(&self) -> [u8; REQUEST_LEN] {
        let mut bytes = [0; REQUEST_LEN];
        bytes[0] = self.address;
        bytes[1] = self.command;
        bytes[2..].copy_from_slice(&self.params);
        bytes
    }

    /// Nine bytes as a request; `None` for any other length.
    pub fn from_bytes(bytes: &[u8]) -> Option<Request> {
        let bytes: &[u8; REQUEST_LEN] = bytes.try_into().ok()?;
        let mut params = [0; PARAMS];
        params.copy_from_slice(&bytes[2..]);
        Some(Request {
            address: bytes[0],
            command: bytes[1],
            params,
        })
    }
}

/// How a unit's replies are framed on RS-232/RS-485 (digest D1.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ReplyFraming {
    /// 8 bytes, `CMD P0..P6`: the manual's own reading (§6.2.2.3, §7).
    Cmd8,
    /// 9 bytes, `RESPADDR CMD P0..P6`, mirroring the request; plausible,
    /// unconfirmed.
    Addr9,
    /// Either: a reply that starts with a replying command is `Cmd8`, one
    /// that starts with `$00` (the console's response address) followed
    /// by one is `Addr9`.
    #[default]
    Auto,
}

impl ReplyFraming {
    pub const ALL: [ReplyFraming; 3] =
        [ReplyFraming::Cmd8, ReplyFraming::Addr9, ReplyFraming::Auto];

    /// The name as a setting is written.
    pub fn name(self) -> &'static str {
        match self {
            ReplyFraming::Cmd8 => "cmd8",
            ReplyFraming::Addr9 => "addr9",
            ReplyFraming::Auto => "auto",
        }
    }

    pub fn from_name(name: &str) -> Option<ReplyFraming> {
        ReplyFraming::ALL
            .into_iter()
            .find(|f| f.name().eq_ignore_ascii_case(name))
    }
}

impl fmt::Display for ReplyFraming {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One reply as received.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Reply {
    /// The address byte in front, in the 9-byte form.
    pub response_address: Option<u8>,
    /// The echoed command.
    pub command: u8,
    pub params: [u8; PARAMS],
}

/// Why received bytes are not a reply.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReplyFrameError {
    #[error("{len} bytes: a reply has 8 (CMD P0..P6){addr9}", addr9 = if *.framing == ReplyFraming::Cmd8 { "" } else { " or 9 (ADDR CMD P0..P6)" })]
    Length { len: usize, framing: ReplyFraming },
    #[error("it starts with ${0:02X}, which is no command that answers (§7)")]
    NotAReply(u8),
    #[error("the address byte ${found:02X} in front should be $00, the console's response address")]
    Address { found: u8 },
}

impl Reply {
    /// Read a frame cut by the framer under `framing`.
    pub fn parse(frame: &[u8], framing: ReplyFraming) -> Result<Reply, ReplyFrameError> {
        let length = || ReplyFrameError::Length {
            len: frame.len(),
            framing,
        };
        let (response_address, body) = match (framing, frame.len()) {
            (ReplyFraming::Cmd8 | ReplyFraming::Auto, 8) => (None, frame),
            (ReplyFraming::Addr9, 9) => (Some(frame[0]), &frame[1..]),
            (ReplyFraming::Auto, 9) => {
                if frame[0] != CONSOLE_RESPONSE_ADDRESS {
                    return Err(ReplyFrameError::Address { found: frame[0] });
                }
                (Some(frame[0]), &frame[1..])
            }
            _ => return Err(length()),
        };
        let command = body[0];
        if !is_replying(command) {
            return Err(ReplyFrameError::NotAReply(command));
        }
        let mut params = [0; PARAMS];
        params.copy_from_slice(&body[1..]);
        Ok(Reply {
            response_address,
            command,
            params,
        })
    }

    /// The bytes as a unit sends them: 9 with the address byte in front
    /// when there is one, else 8.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut bytes = Vec::with_capacity(REQUEST_LEN);
        bytes.extend(self.response_address);
        bytes.push(self.command);
        bytes.extend_from_slice(&self.params);
        bytes
    }
}

/// `[0x00, 0x23]` → `"00 23"`: bytes as SQPack shows them (§5.4.5).
pub fn to_hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Little-endian bytes of `value`, `width` of them (two's complement).
pub fn put_le(params: &mut [u8; PARAMS], offset: usize, width: usize, value: i64) {
    let bytes = value.to_le_bytes();
    for (i, b) in bytes.iter().take(width).enumerate() {
        if let Some(slot) = params.get_mut(offset + i) {
            *slot = *b;
        }
    }
}

/// The value of `width` little-endian bytes at `offset`, sign-extended
/// when `signed`.
pub fn get_le(params: &[u8; PARAMS], offset: usize, width: usize, signed: bool) -> i64 {
    let mut value: u64 = 0;
    for i in (0..width).rev() {
        value = (value << 8) | u64::from(params.get(offset + i).copied().unwrap_or(0));
    }
    let bits = 8 * width as u32;
    if signed && bits < 64 && value & (1 << (bits - 1)) != 0 {
        (value as i64) - (1i64 << bits)
    } else {
        value as i64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_request_is_nine_bytes_address_first() {
        let request = Request {
            address: 0,
            command: 0x23,
            params: [0, 0x10, 0x27, 0, 0, 0, 0],
        };
        assert_eq!(to_hex(&request.to_bytes()), "00 23 00 10 27 00 00 00 00");
        assert_eq!(Request::from_bytes(&request.to_bytes()), Some(request));
        assert_eq!(Request::from_bytes(&[0; 8]), None);
    }

    #[test]
    fn values_are_least_significant_byte_first() {
        let mut params = [0; PARAMS];
        put_le(&mut params, 1, 4, 500_000);
        assert_eq!(params, [0, 0x20, 0xA1, 0x07, 0, 0, 0]);
        assert_eq!(get_le(&params, 1, 4, true), 500_000);
        put_le(&mut params, 1, 4, -1);
        assert_eq!(get_le(&params, 1, 4, true), -1);
        assert_eq!(get_le(&params, 1, 4, false), 0xFFFF_FFFF);
        put_le(&mut params, 1, 2, -511);
        assert_eq!(get_le(&params, 1, 2, true), -511);
        assert_eq!(&params[1..3], &[0x01, 0xFE]);
        // Out of the seven bytes: ignored, never a panic.
        put_le(&mut params, 6, 4, 0x0102_0304);
        assert_eq!(params[6], 0x04);
        assert_eq!(get_le(&params, 6, 4, false), 4);
    }

    #[test]
    fn replies_read_in_each_framing() {
        let cmd8 = [0x20, 0, 0x10, 0x27, 0, 0, 5, 0];
        let reply = Reply::parse(&cmd8, ReplyFraming::Cmd8).expect("cmd8");
        assert_eq!((reply.response_address, reply.command), (None, 0x20));
        assert_eq!(reply.to_bytes(), cmd8.to_vec());
        assert_eq!(Reply::parse(&cmd8, ReplyFraming::Auto), Ok(reply));
        assert!(Reply::parse(&cmd8, ReplyFraming::Addr9).is_err());

        let mut addr9 = vec![7];
        addr9.extend_from_slice(&cmd8);
        let reply = Reply::parse(&addr9, ReplyFraming::Addr9).expect("addr9");
        assert_eq!(reply.response_address, Some(7));
        assert_eq!(reply.to_bytes(), addr9);
        assert_eq!(
            Reply::parse(&addr9, ReplyFraming::Auto),
            Err(ReplyFrameError::Address { found: 7 })
        );
        addr9[0] = 0;
        assert!(Reply::parse(&addr9, ReplyFraming::Auto).is_ok());

        let error = Reply::parse(&[0x23, 0, 0, 0, 0, 0, 0, 0], ReplyFraming::Cmd8).unwrap_err();
        assert_eq!(
            error.to_string(),
            "it starts with $23, which is no command that answers (§7)"
        );
        let error = Reply::parse(&[0x20; 5], ReplyFraming::Auto).unwrap_err();
        assert_eq!(
            error.to_string(),
            "5 bytes: a reply has 8 (CMD P0..P6) or 9 (ADDR CMD P0..P6)"
        );
    }

    #[test]
    fn framings_have_names() {
        for framing in ReplyFraming::ALL {
            assert_eq!(ReplyFraming::from_name(framing.name()), Some(framing));
        }
        assert_eq!(ReplyFraming::default(), ReplyFraming::Auto);
        assert_eq!(ReplyFraming::from_name("ADDR9"), Some(ReplyFraming::Addr9));
    }
}
