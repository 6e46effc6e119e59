//! TMCL frames as the traffic monitor shows them: a request as its console
//! line, a reply as its status meaning and value, read in the light of the
//! request it answers.

use super::command::{Command, VersionFormat};
use super::console::reply_value;
use super::frame::{FRAME_LEN, Reply, Request};
use super::line::format_command;
use crate::protocol::console::ReplyValue;

/// A request in words: its console line and the module it goes to.
pub fn describe_request(bytes: &[u8]) -> String {
    match <&[u8; FRAME_LEN]>::try_from(bytes) {
        Ok(frame) => request_words(frame),
        Err(_) => not_a_frame(bytes),
    }
}

/// A reply in words: status meaning and value. `request`, the last
/// request sent, decides how the value reads (and names the command).
pub fn describe_reply(bytes: &[u8], request: Option<&[u8]>) -> String {
    match <&[u8; FRAME_LEN]>::try_from(bytes) {
        Ok(frame) => reply_words(frame, request),
        Err(_) => not_a_frame(bytes),
    }
}

fn not_a_frame(bytes: &[u8]) -> String {
    format!(
        "{} bytes: not a TMCL frame ({FRAME_LEN} bytes)",
        bytes.len()
    )
}

fn request_words(frame: &[u8; FRAME_LEN]) -> String {
    match Request::from_bytes(frame) {
        Ok(request) => format!(
            "{} to module {}",
            format_command(&Command::from_request(&request)),
            request.address
        ),
        Err(e) => format!("request with a {e}"),
    }
}

fn reply_words(frame: &[u8; FRAME_LEN], request: Option<&[u8]>) -> String {
    let request = request
        .and_then(|r| <&[u8; FRAME_LEN]>::try_from(r).ok())
        .map(Request::from_bytes_unchecked);
    let command = request.as_ref().map(Command::from_request);
    // §3.6.53 / digest D4: the version string comes as the host address and
    // eight ASCII characters, no checksum.
    if let Some(Command::FirmwareVersion {
        format: VersionFormat::String,
    }) = command
        && Reply::from_bytes(frame).is_err()
    {
        let text: String = frame[1..]
            .iter()
            .map(|&b| {
                if b.is_ascii_graphic() || b == b' ' {
                    char::from(b)
                } else {
                    '?'
                }
            })
            .collect();
        return format!("version \"{}\"", text.trim());
    }
    let reply = match Reply::from_bytes(frame) {
        Ok(reply) => reply,
        Err(e) => return format!("reply with a {e}"),
    };
    let answers = request
        .as_ref()
        .is_some_and(|r| r.command == reply.command && r.address == reply.module_address);
    let name = match command {
        Some(c) if answers => format_command(&c)
            .split_whitespace()
            .next()
            .unwrap_or("")
            .trim_end_matches(',')
            .to_string(),
        _ => format!("command {}", reply.command),
    };
    let status = format!("{} {}", reply.status.0, reply.status.meaning());
    if !reply.status.is_success() {
        return format!("{name} from module {}: {status}", reply.module_address);
    }
    let value = match command {
        Some(c) if answers => reply_value(&c, reply.value),
        _ => ReplyValue::Number(i64::from(reply.value)),
    };
    match value {
        ReplyValue::None => format!("{name} from module {}: {status}", reply.module_address),
        value => format!(
            "{name} from module {}: {value} ({status})",
            reply.module_address
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::tmcl::{Status, parse_line};

    fn request(line: &str) -> [u8; FRAME_LEN] {
        parse_line(line).expect("line").to_request(1).to_bytes()
    }

    fn reply(status: u8, command: u8, value: i32) -> [u8; FRAME_LEN] {
        Reply {
            host_address: 2,
            module_address: 1,
            status: Status(status),
            command,
            value,
        }
        .to_bytes()
    }

    #[test]
    fn requests_read_as_console_lines() {
        assert_eq!(
            describe_request(&request("GAP 4, 0")),
            "GAP 4, 0 to module 1"
        );
        assert_eq!(
            describe_request(&request("MVP ABS, 0, 1000")),
            "MVP ABS, 0, 1000 to module 1"
        );
        let mut bad = request("GAP 4, 0");
        bad[8] ^= 1;
        assert!(describe_request(&bad).contains("wrong checksum"));
        assert!(describe_request(&[1, 2]).contains("2 bytes"));
    }

    #[test]
    fn replies_read_as_status_and_value_of_their_request() {
        let gap = request("GAP 4, 0");
        assert_eq!(
            describe_reply(&reply(100, 6, 1234), Some(&gap)),
            "GAP from module 1: 1234 (100 successfully executed, no error)"
        );
        let sap = request("SAP 4, 0, 1234");
        assert_eq!(
            describe_reply(&reply(100, 5, 1234), Some(&sap)),
            "SAP from module 1: 100 successfully executed, no error"
        );
        assert_eq!(
            describe_reply(&reply(4, 5, 0), Some(&sap)),
            "SAP from module 1: 4 invalid value"
        );
        // Timer periods read back unsigned (§5.4).
        let ggp = request("GGP 0, 3");
        assert!(describe_reply(&reply(100, 10, -1), Some(&ggp)).contains("4294967295"));
        // With no request to go by, the command is named by its number.
        assert_eq!(
            describe_reply(&reply(100, 6, 7), None),
            "command 6 from module 1: 7 (100 successfully executed, no error)"
        );
    }

    #[test]
    fn the_version_string_reads_as_text() {
        let version = request("VERSION");
        let mut frame = [0u8; FRAME_LEN];
        frame[0] = 2;
        frame[1..].copy_from_slice(b"1110V112");
        assert_eq!(
            describe_reply(&frame, Some(&version)),
            "version \"1110V112\""
        );
    }
}
