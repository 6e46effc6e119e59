//! Nippon Pulse Commander core CMD-4CR (manual V1.0, firmware V126BL):
//! its ASCII protocol over RS-485. Pure code: bytes and meanings, no I/O.
//!
//! A frame is `@`, the two-digit controller ID, the command and CR; the
//! answer is one line ended by CR (§3.2.2). The command set is data
//! ([`catalog::COMMANDS`], §4.1 Table 4-40); [`parse_command`] is the one
//! parser of command text, for the console and the simulator alike.

pub mod ascript;
pub mod assist;
pub mod catalog;
pub mod command;
pub mod console;
pub mod host;
pub mod io;
pub mod jog;
pub mod parameter_set;
pub mod program_control;
pub mod reply;
pub mod tool;
pub mod traffic;
pub mod units;
pub mod wire;

use std::fmt;

pub use catalog::{Action, Axis, COMMANDS, CommandSpec, Register};
pub use command::{Cmd4crCommand, CommandError, Direction, Rotation, Selector, parse_command};
pub use console::Cmd4crConsole;
pub use program_control::ProgramControl;
pub use reply::{Answer, ErrorCode, ErrorReply, Mst, parse_answer};
pub use wire::Cmd4crWire;

/// The CMD-4CR family's entry (registered in [`crate::families`]).
pub static FAMILY: crate::protocol::Family = crate::protocol::Family {
    name: "cmd4cr",
    description: "Nippon Pulse CMD-4CR (4 axes), ASCII lines @ID…CR",
    encode_line,
    show_bytes,
    console: &Cmd4crConsole,
};

/// The ID every controller ships with (§2.1.1.1).
pub const DEFAULT_ID: u8 = 1;

/// IDs run 00–99 (§2.1.1.1 "must be within the range [00-99]"; the same
/// section's "up to 64 devices" is how many a host handles, digest §10.3).
pub const MAX_ID: u8 = 99;

const START: u8 = b'@';
const CR: u8 = b'\r';

/// The bytes of a frame: `@`, the ID in two digits, the command text, CR.
/// An ID above 99 is written as it is (three digits), which no controller
/// answers to; [`encode`] refuses it.
pub fn frame(id: u8, text: &str) -> Vec<u8> {
    let mut bytes = format!("@{id:02}{text}").into_bytes();
    bytes.push(CR);
    bytes
}

/// Why a command cannot be framed for a controller.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FrameError {
    #[error("controller ID {0} is outside 00..99 (§2.1.1.1)")]
    Id(u8),
    #[error(transparent)]
    Command(#[from] CommandError),
}

impl crate::protocol::line_error::FamilyLineError for FrameError {
    fn mistake(&self) -> crate::protocol::line_error::Mistake {
        match self {
            FrameError::Id(_) => crate::protocol::line_error::Mistake::Address,
            FrameError::Command(error) => error.mistake(),
        }
    }
}

/// Parse `text` and frame it for the controller with `id`.
pub fn encode(id: u8, text: &str) -> Result<(Cmd4crCommand, Vec<u8>), FrameError> {
    if id > MAX_ID {
        return Err(FrameError::Id(id));
    }
    let command = parse_command(text)?;
    let bytes = frame(id, &command.to_string());
    Ok((command, bytes))
}

/// A frame as the controller receives it: the ID and the command text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Request {
    pub id: u8,
    /// Everything after the ID, as sent.
    pub text: String,
}

/// Why received bytes are not a frame.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RequestError {
    #[error("a frame starts with `@`")]
    NoStart,
    #[error("`@` must be followed by the two-digit controller ID")]
    NoId,
    #[error("the command is not ASCII text")]
    NotText,
}

/// Read a received line (its CR, if still there, is ignored): `@01PX` is
/// ID 1, command `PX`.
pub fn parse_request(line: &[u8]) -> Result<Request, RequestError> {
    let line = line.strip_suffix(&[CR]).unwrap_or(line);
    let rest = line.strip_prefix(&[START]).ok_or(RequestError::NoStart)?;
    let (tens, ones) = match rest {
        [t, o, ..] if t.is_ascii_digit() && o.is_ascii_digit() => (t - b'0', o - b'0'),
        _ => return Err(RequestError::NoId),
    };
    let text = rest.get(2..).unwrap_or_default();
    let text = std::str::from_utf8(text)
        .ok()
        .filter(|t| t.is_ascii())
        .ok_or(RequestError::NotText)?;
    Ok(Request {
        id: tens * 10 + ones,
        text: text.to_string(),
    })
}

/// Bytes as a technician reads an ASCII frame: printable characters as
/// they are, CR and LF as `\r` and `\n`, anything else as `\xNN`.
pub fn show_bytes(bytes: &[u8]) -> String {
    crate::protocol::ascii::show_bytes(bytes)
}

/// `axterm encode cmd4cr LINE`: the frame for the controller `id` (01
/// when `None`).
pub fn encode_line(
    line: &str,
    id: Option<u8>,
) -> Result<Vec<u8>, crate::protocol::line_error::LineError> {
    Ok(encode(id.unwrap_or(DEFAULT_ID), line)?.1)
}

/// A frame's ID for messages: `controller 01`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ControllerId(pub u8);

impl fmt::Display for ControllerId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "controller {:02}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_is_at_id_command_cr() {
        assert_eq!(frame(1, "POLX"), b"@01POLX\r".to_vec());
        assert_eq!(frame(42, "STORE"), b"@42STORE\r".to_vec());
        let (_, bytes) = encode(1, "hspdx = 5000").expect("valid");
        assert_eq!(bytes, b"@01HSPDX=5000\r".to_vec());
        assert_eq!(encode(100, "PX").unwrap_err(), FrameError::Id(100));
        assert!(matches!(
            encode(1, "PQ").unwrap_err(),
            FrameError::Command(_)
        ));
    }

    #[test]
    fn requests_read_back() {
        assert_eq!(
            parse_request(b"@01POLX\r"),
            Ok(Request {
                id: 1,
                text: "POLX".into()
            })
        );
        assert_eq!(
            parse_request(b"@99"),
            Ok(Request {
                id: 99,
                text: String::new()
            })
        );
        assert_eq!(parse_request(b"01PX"), Err(RequestError::NoStart));
        assert_eq!(parse_request(b"@1PX"), Err(RequestError::NoId));
        assert_eq!(parse_request(b"@"), Err(RequestError::NoId));
        assert_eq!(parse_request(b"@01P\xFF"), Err(RequestError::NotText));
    }

    #[test]
    fn bytes_show_escaped() {
        assert_eq!(show_bytes(b"@01PX\r"), "@01PX\\r");
        assert_eq!(show_bytes(b"a\\\n\x07"), "a\\\\\\n\\x07");
    }

    #[test]
    fn ids_read_as_two_digits() {
        assert_eq!(ControllerId(1).to_string(), "controller 01");
    }

    mod properties {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            #[test]
            fn parsing_never_panics(text in "\\PC{0,40}") {
                let _ = parse_command(&text);
            }

            #[test]
            fn ascii_soup_never_panics(text in "[@0-9A-Z:=+\\-. a-z]{0,30}") {
                if let Ok(command) = parse_command(&text) {
                    // What parses writes back to text that parses the same.
                    let canonical = command.to_string();
                    prop_assert_eq!(parse_command(&canonical), Ok(command));
                }
            }

            #[test]
            fn requests_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..40)) {
                let _ = parse_request(&bytes);
                let shown = show_bytes(&bytes);
                prop_assert!(shown.is_ascii());
            }

            #[test]
            fn replies_never_panic(line in "\\PC{0,70}") {
                let _ = reply::ErrorReply::parse(&line);
                for format in [
                    None,
                    Some(catalog::Format::Integer),
                    Some(catalog::Format::Thousandths),
                    Some(catalog::Format::Fields(&["X", "Y", "Z", "U"])),
                    Some(catalog::Format::Text),
                ] {
                    let _ = parse_answer(&line, format);
                }
                if let Some(error) = reply::ErrorReply::parse(&line) {
                    prop_assert!(error.line().len() <= reply::MAX_REPLY_TEXT);
                }
            }
        }
    }
}
