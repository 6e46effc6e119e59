//! CMD-4CR frames as the traffic monitor shows them: a request as its
//! command and controller ID, a reply as what it says, read in the light
//! of the request it answers (an MST word by its bits, a POL word by its
//! fields, PP by axis, an error by its §4.2 meaning).

use super::catalog::{Format, Register};
use super::command::{Cmd4crCommand, parse_command};
use super::reply::{Answer, AnswerError, Mst, describe_pol, parse_answer};
use super::{ControllerId, parse_request};

/// A request in words: its command and the controller it goes to.
pub fn describe_request(bytes: &[u8]) -> String {
    match parse_request(bytes) {
        Ok(request) => match parse_command(&request.text) {
            Ok(command) => format!("{command} to {}", ControllerId(request.id)),
            Err(e) => format!("{} to {}: {e}", request.text, ControllerId(request.id)),
        },
        Err(e) => format!("not a CMD-4CR frame: {e}"),
    }
}

/// A reply in words. `request`, the last frame sent, decides how it reads.
pub fn describe_reply(bytes: &[u8], request: Option<&[u8]>) -> String {
    let text = String::from_utf8_lossy(bytes);
    let text = text.trim();
    let command = request
        .and_then(|r| parse_request(r).ok())
        .and_then(|r| parse_command(&r.text).ok());
    let format = command.as_ref().and_then(Cmd4crCommand::reply_format);
    match parse_answer(text, format) {
        Err(AnswerError::Refused(error)) => error.to_string(),
        Err(AnswerError::Unreadable { .. }) => {
            format!("`{text}`: not an answer to {}", name(command.as_ref()))
        }
        Ok(Answer::Done(_)) => format!("{} done", name(command.as_ref())),
        Ok(Answer::Integer(value)) => integer(command.as_ref(), value),
        Ok(Answer::Thousandths(_, text) | Answer::Text(text)) => {
            format!("{} = {text}", name(command.as_ref()))
        }
        Ok(Answer::Fields(values, _)) => {
            let names = match format {
                Some(Format::Fields(names)) => names,
                _ => &[],
            };
            let fields: Vec<String> = names
                .iter()
                .zip(&values)
                .map(|(name, value)| format!("{name} {value}"))
                .collect();
            format!("{}: {}", name(command.as_ref()), fields.join(" · "))
        }
    }
}

fn name(command: Option<&Cmd4crCommand>) -> String {
    command.map_or_else(|| "the request".to_string(), ToString::to_string)
}

fn integer(command: Option<&Cmd4crCommand>, value: i64) -> String {
    let Some(command) = command else {
        return value.to_string();
    };
    match command {
        Cmd4crCommand::Read {
            register: Register::Mst,
            ..
        } => format!("{command} = {value}: {}", Mst::from_value(value).describe()),
        Cmd4crCommand::Read {
            register: Register::Pol,
            ..
        } => describe_pol(value),
        _ => {
            let unit = command.spec().values.map_or("", |v| v.unit);
            if unit.is_empty() {
                format!("{command} = {value}")
            } else {
                format!("{command} = {value} {unit}")
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_read_as_their_command() {
        assert_eq!(
            describe_request(b"@01HSPDX=5000\r"),
            "HSPDX=5000 to controller 01"
        );
        assert!(describe_request(b"@01FOO\r").starts_with("FOO to controller 01: `FOO` is not"));
        assert!(describe_request(b"PX\r").starts_with("not a CMD-4CR frame"));
    }

    #[test]
    fn replies_read_in_the_light_of_the_request() {
        assert_eq!(
            describe_reply(b"5000", Some(b"@01HSPDX\r")),
            "HSPDX = 5000 pps"
        );
        assert_eq!(describe_reply(b"OK", Some(b"@01STORE\r")), "STORE done");
        assert_eq!(
            describe_reply(b"1:2:3:4", Some(b"@01PP\r")),
            "PP: X 1 · Y 2 · Z 3 · U 4"
        );
        assert_eq!(
            describe_reply(b"3", Some(b"@01MSTX\r")),
            "MSTX = 3: accel, decel"
        );
        assert!(describe_reply(b"7", Some(b"@01POLX\r")).starts_with("POL 7: "));
        assert!(
            describe_reply(b"?Buffer Full", Some(b"@01I1:2:3:4\r"))
                .contains("all 100 registers are full")
        );
        assert_eq!(
            describe_reply(b"OK", Some(b"@01PX\r")),
            "`OK`: not an answer to PX"
        );
        assert_eq!(describe_reply(b"OK", None), "the request done");
    }
}
