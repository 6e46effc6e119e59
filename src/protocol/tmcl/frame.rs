//! TMCL binary frames (manual §3.1, §3.2): 9-byte requests and replies,
//! 8-bit additive checksum, 32-bit values MSB first.

use std::fmt;

/// Every TMCL frame on RS-232/RS-485/USB is nine bytes (§3.1, §3.2).
pub const FRAME_LEN: usize = 9;

/// 8-bit sum of all bytes, the TMCL checksum rule (§3.1.1): sum every byte
/// before the checksum, address included, keep the low 8 bits.
pub fn checksum(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0u8, |sum, b| sum.wrapping_add(*b))
}

/// A host → module frame (§3.1 Table 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Request {
    /// Module (target) address, byte 0.
    pub address: u8,
    /// Instruction number, byte 1.
    pub command: u8,
    /// Type: parameter number, sub-function, condition…, byte 2.
    pub kind: u8,
    /// Motor or bank, byte 3.
    pub motor_bank: u8,
    /// Signed 32-bit value, bytes 4..7, MSB first.
    pub value: i32,
}

impl Request {
    pub fn to_bytes(&self) -> [u8; FRAME_LEN] {
        assemble(
            [self.address, self.command, self.kind, self.motor_bank],
            self.value,
        )
    }

    /// Decode nine bytes, checking the checksum.
    pub fn from_bytes(bytes: &[u8; FRAME_LEN]) -> Result<Self, ChecksumError> {
        verify_checksum(bytes)?;
        Ok(Self::from_bytes_unchecked(bytes))
    }

    /// Decode nine bytes without looking at the checksum byte.
    pub fn from_bytes_unchecked(bytes: &[u8; FRAME_LEN]) -> Self {
        Request {
            address: bytes[0],
            command: bytes[1],
            kind: bytes[2],
            motor_bank: bytes[3],
            value: i32::from_be_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]),
        }
    }
}

/// A module → host frame (§3.2 Table 3). The host address comes first; the
/// command-138 tables of §3.6.52 print the two addresses the other way round,
/// which the digest (D1.2) flags as a misprint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Reply {
    /// Reply (host) address, byte 0 (GP76, 2 in every example).
    pub host_address: u8,
    /// Module address, byte 1.
    pub module_address: u8,
    /// Status code, byte 2.
    pub status: Status,
    /// Echo of the executed command's opcode, byte 3.
    pub command: u8,
    /// Value, bytes 4..7, MSB first.
    pub value: i32,
}

impl Reply {
    pub fn to_bytes(&self) -> [u8; FRAME_LEN] {
        assemble(
            [
                self.host_address,
                self.module_address,
                self.status.0,
                self.command,
            ],
            self.value,
        )
    }

    pub fn from_bytes(bytes: &[u8; FRAME_LEN]) -> Result<Self, ChecksumError> {
        verify_checksum(bytes)?;
        Ok(Self::from_bytes_unchecked(bytes))
    }

    pub fn from_bytes_unchecked(bytes: &[u8; FRAME_LEN]) -> Self {
        Reply {
            host_address: bytes[0],
            module_address: bytes[1],
            status: Status(bytes[2]),
            command: bytes[3],
            value: i32::from_be_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]),
        }
    }
}

/// Four header bytes, the value MSB first, and the checksum.
fn assemble(header: [u8; 4], value: i32) -> [u8; FRAME_LEN] {
    let mut out = [0u8; FRAME_LEN];
    out[..4].copy_from_slice(&header);
    out[4..8].copy_from_slice(&value.to_be_bytes());
    out[8] = checksum(&out[..8]);
    out
}

/// The frame's last byte is not the sum of the others.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("wrong checksum: frame carries {found:#04x}, its bytes sum to {expected:#04x}")]
pub struct ChecksumError {
    pub expected: u8,
    pub found: u8,
}

fn verify_checksum(bytes: &[u8; FRAME_LEN]) -> Result<(), ChecksumError> {
    let expected = checksum(&bytes[..8]);
    if expected == bytes[8] {
        Ok(())
    } else {
        Err(ChecksumError {
            expected,
            found: bytes[8],
        })
    }
}

/// A reply status code (§3.2.1 Table 4, plus 128 from §3.6.52).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Status(pub u8);

impl Status {
    pub const WRONG_CHECKSUM: Status = Status(1);
    pub const INVALID_COMMAND: Status = Status(2);
    pub const WRONG_TYPE: Status = Status(3);
    pub const INVALID_VALUE: Status = Status(4);
    pub const EEPROM_LOCKED: Status = Status(5);
    pub const NOT_AVAILABLE: Status = Status(6);
    pub const OK: Status = Status(100);
    pub const LOADED: Status = Status(101);
    pub const TARGET_REACHED: Status = Status(128);

    /// True for the codes that mean the command was accepted.
    pub fn is_success(self) -> bool {
        matches!(self.0, 100 | 101 | 128)
    }

    /// The manual's meaning of the code; unknown codes (other Trinamic
    /// firmwares define more) are described generically, never rejected.
    pub fn meaning(self) -> &'static str {
        match self.0 {
            1 => "wrong checksum",
            2 => "invalid command",
            3 => "wrong type",
            4 => "invalid value",
            5 => "configuration EEPROM locked",
            6 => "command not available",
            100 => "successfully executed, no error",
            101 => "command loaded into TMCL program EEPROM",
            128 => "target position reached",
            _ => "unknown status code",
        }
    }
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", self.0, self.meaning())
    }
}

/// Cuts a byte stream into 9-byte frames. TMCL has no start byte, so the
/// assembler cannot find frame boundaries in the bytes themselves: a caller
/// that sees line silence or garbage calls [`FrameAssembler::resync`] to drop
/// a partial frame. Never panics, whatever it is fed.
#[derive(Debug, Default, Clone)]
pub struct FrameAssembler {
    pending: Vec<u8>,
}

impl FrameAssembler {
    pub fn new() -> Self {
        Self::default()
    }

    /// Append bytes and return every complete 9-byte chunk now available.
    pub fn push(&mut self, bytes: &[u8]) -> Vec<[u8; FRAME_LEN]> {
        self.pending.extend_from_slice(bytes);
        let whole = self.pending.len() / FRAME_LEN * FRAME_LEN;
        let frames = self.pending[..whole]
            .chunks_exact(FRAME_LEN)
            .map(|c| {
                let mut frame = [0u8; FRAME_LEN];
                frame.copy_from_slice(c);
                frame
            })
            .collect();
        self.pending.drain(..whole);
        frames
    }

    /// Bytes of an incomplete frame held back.
    pub fn partial_len(&self) -> usize {
        self.pending.len()
    }

    /// Forget a partial frame (after line silence: the next byte starts a frame).
    pub fn resync(&mut self) {
        self.pending.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gio_example_of_manual_3_6_15() {
        let req = Request {
            address: 1,
            command: 15,
            kind: 0,
            motor_bank: 1,
            value: 0,
        };
        assert_eq!(req.to_bytes(), [0x01, 0x0F, 0x00, 0x01, 0, 0, 0, 0, 0x11]);
        let reply =
            Reply::from_bytes(&[0x02, 0x01, 0x64, 0x0F, 0x00, 0x00, 0x01, 0x2E, 0xA5]).unwrap();
        assert_eq!(reply.status, Status::OK);
        assert_eq!(reply.value, 302);
        assert_eq!(reply.module_address, 1);
        assert_eq!(reply.host_address, 2);
    }

    #[test]
    fn negative_values_are_twos_complement_msb_first() {
        let req = Request {
            address: 1,
            command: 4,
            kind: 1,
            motor_bank: 0,
            value: -10000,
        };
        assert_eq!(
            req.to_bytes(),
            [0x01, 0x04, 0x01, 0x00, 0xFF, 0xFF, 0xD8, 0xF0, 0xCC]
        );
    }

    #[test]
    fn bad_checksum_is_reported_with_both_sums() {
        // §3.6.8 prints this RSAP frame with checksum 0A; its bytes sum to 0F.
        let err = Request::from_bytes(&[0x01, 0x08, 0x06, 0x00, 0, 0, 0, 0, 0x0A]).unwrap_err();
        assert_eq!(
            err,
            ChecksumError {
                expected: 0x0F,
                found: 0x0A
            }
        );
    }

    #[test]
    fn assembler_cuts_split_input_and_resyncs() {
        let frame = Request {
            address: 1,
            command: 6,
            kind: 1,
            motor_bank: 0,
            value: 0,
        }
        .to_bytes();
        let mut asm = FrameAssembler::new();
        assert!(asm.push(&frame[..4]).is_empty());
        assert_eq!(asm.push(&frame[4..]), vec![frame]);
        assert!(asm.push(&[0xAA, 0xBB]).is_empty());
        assert_eq!(asm.partial_len(), 2);
        asm.resync();
        assert_eq!(asm.push(&frame), vec![frame]);
    }

    #[test]
    fn unknown_status_codes_are_described_not_rejected() {
        assert_eq!(Status(7).meaning(), "unknown status code");
        assert!(!Status(7).is_success());
        assert!(Status(101).is_success());
    }

    mod properties {
        use super::super::*;
        use proptest::prelude::*;

        proptest! {
            #[test]
            fn requests_round_trip(address: u8, command: u8, kind: u8, motor_bank: u8, value: i32) {
                let req = Request { address, command, kind, motor_bank, value };
                prop_assert_eq!(Request::from_bytes(&req.to_bytes()), Ok(req));
            }

            #[test]
            fn replies_round_trip(host: u8, module: u8, status: u8, command: u8, value: i32) {
                let reply = Reply {
                    host_address: host,
                    module_address: module,
                    status: Status(status),
                    command,
                    value,
                };
                prop_assert_eq!(Reply::from_bytes(&reply.to_bytes()), Ok(reply));
            }

            #[test]
            fn any_single_corrupted_byte_is_caught(
                value: i32,
                index in 0usize..FRAME_LEN,
                flip in 1u8..=255,
            ) {
                let mut bytes = Request { address: 1, command: 5, kind: 4, motor_bank: 0, value }.to_bytes();
                bytes[index] ^= flip;
                prop_assert!(Request::from_bytes(&bytes).is_err());
            }

            #[test]
            fn assembler_never_panics_and_keeps_every_byte(
                chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..40), 0..20),
            ) {
                let mut asm = FrameAssembler::new();
                let mut fed = 0;
                let mut framed = 0;
                for chunk in &chunks {
                    fed += chunk.len();
                    for frame in asm.push(chunk) {
                        framed += FRAME_LEN;
                        let _ = Reply::from_bytes(&frame);
                        let _ = Request::from_bytes(&frame);
                    }
                }
                prop_assert_eq!(fed, framed + asm.partial_len());
                prop_assert!(asm.partial_len() < FRAME_LEN);
            }
        }
    }
}
