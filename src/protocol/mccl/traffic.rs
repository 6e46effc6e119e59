//! MCCL traffic as the monitor shows it: a line sent as its commands, the
//! abort and pause bytes by name; a frame received as the echo, the prompt,
//! an error with its Ch14 meaning, or a Tell reply read in the light of the
//! line it answers (a status word by its bits).

use super::catalog::Output;
use super::line::{Line, NumberBase, parse_line};
use super::profile::{CR, ESCAPE, LinkProfile, SPACE};
use super::reply::{ErrorReply, parse_told};
use super::status::{StatusSelector, StatusWord, describe_bit};

/// Commands named in full before the rest are summed up.
const NAMED: usize = 4;

fn sent_text(bytes: &[u8]) -> String {
    let bytes = bytes.strip_suffix(&[CR]).unwrap_or(bytes);
    String::from_utf8_lossy(bytes).into_owned()
}

/// A request in words.
pub fn describe_request(bytes: &[u8]) -> String {
    match bytes {
        [ESCAPE] => return "Escape: aborts the line running (Ch2)".into(),
        [SPACE] => return "Space: pauses the line running, or resumes it (Ch2)".into(),
        [CR] => return "a bare CR: the controller runs its last line again (Ch2)".into(),
        _ => {}
    }
    let text = sent_text(bytes);
    match parse_line(&text, NumberBase::Decimal) {
        Ok(line) => {
            let mut parts: Vec<String> = line
                .commands
                .iter()
                .enumerate()
                .take(NAMED)
                .map(|(index, command)| {
                    let axis = match line.axis_of(index).number() {
                        Some(axis) if command.spec.axis != super::catalog::AxisRule::None => {
                            format!(" (axis {axis})")
                        }
                        _ => String::new(),
                    };
                    format!("{} {}{axis}", command.mnemonic(), command.spec.name)
                })
                .collect();
            if line.commands.len() > NAMED {
                parts.push(format!("{} more", line.commands.len() - NAMED));
            }
            format!("{text}: {}", parts.join(", "))
        }
        Err(e) => format!("{text}: {e}"),
    }
}

/// The one command of `line` that prints a value, if it has exactly one.
fn single_tell(line: &Line) -> Option<usize> {
    let mut tells = line
        .commands
        .iter()
        .enumerate()
        .filter(|(_, c)| c.spec.output == Output::Value)
        .map(|(i, _)| i);
    let first = tells.next()?;
    tells.next().is_none().then_some(first)
}

/// A frame received, read in the light of `request` (the last line sent).
pub fn describe_reply(bytes: &[u8], request: Option<&[u8]>, profile: &LinkProfile) -> String {
    let text = String::from_utf8_lossy(bytes);
    let text = text.trim();
    if profile.prompt.is_some_and(|p| bytes == [p]) {
        return "prompt: the line is done".into();
    }
    let sent = request.map(sent_text);
    if let Some(sent) = &sent
        && !sent.is_empty()
        && let Some(rest) = text.strip_prefix(sent.as_str())
    {
        return match ErrorReply::parse(rest) {
            Some(error) => format!("echo, then {error}"),
            None if rest.trim().is_empty() => "echo of the line".into(),
            None => format!("echo, then `{}`", rest.trim()),
        };
    }
    if let Some(error) = ErrorReply::parse(text) {
        return error.to_string();
    }
    let line = sent
        .as_deref()
        .and_then(|s| parse_line(s, NumberBase::Decimal).ok());
    let Ok(told) = parse_told(text, NumberBase::Decimal) else {
        return format!("output: {text}");
    };
    let field = told.field.map_or(String::new(), |f| format!(" of {f:02}"));
    let Some((line, index)) = line.as_ref().and_then(|l| Some((l, single_tell(l)?))) else {
        return format!("value{field}: {}", told.value);
    };
    let command = &line.commands[index];
    let what = format!("{}{field} = {}", command.mnemonic(), told.value);
    if command.mnemonic() != "TS" {
        return what;
    }
    let selector = command
        .number()
        .and_then(|n| StatusSelector::from_parameter(n as i64));
    match (selector, u32::try_from(told.value.rounded())) {
        (Some(StatusSelector::Word(kind)), Ok(value)) => {
            format!("{what}: {}", StatusWord::new(kind, value))
        }
        (Some(StatusSelector::Bit(kind, bit)), _) => match describe_bit(kind, bit) {
            Some(described) => format!("{what}: {}", described.meaning),
            None => format!("{what}: reserved bit {bit}"),
        },
        _ => what,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reply(bytes: &str, request: &str) -> String {
        describe_reply(
            bytes.as_bytes(),
            Some(request.as_bytes()),
            &LinkProfile::MANUAL,
        )
    }

    #[test]
    fn requests_read_as_their_commands() {
        assert_eq!(
            describe_request(b"1TP,TV,TS\r"),
            "1TP,TV,TS: TP Tell Position (axis 1), TV Tell Velocity (axis 1), TS Tell Status \
             (axis 1)"
        );
        assert_eq!(
            describe_request(b"2MR1000,WS0.5,MR-1000,WS0.5,RP6\r"),
            "2MR1000,WS0.5,MR-1000,WS0.5,RP6: MR Move Relative (axis 2), WS Wait for Stop \
             (axis 2), MR Move Relative (axis 2), WS Wait for Stop (axis 2), 1 more"
        );
        assert_eq!(
            describe_request(b"\x1b"),
            "Escape: aborts the line running (Ch2)"
        );
        assert!(describe_request(b" ").starts_with("Space"));
        assert!(describe_request(b"\r").contains("last line again"));
        assert!(describe_request(b"1XX\r").contains("XX is not an MCCL command"));
    }

    #[test]
    fn replies_read_in_the_light_of_the_line() {
        assert_eq!(reply(">", "1TP\r"), "prompt: the line is done");
        assert_eq!(reply("1TP", "1TP\r"), "echo of the line");
        assert_eq!(
            reply("MC10?-6", "MC10\r"),
            "echo, then error ?-6 (Macro Doesn't Exist, Ch14)"
        );
        assert_eq!(
            reply("?-6", "MC10\r"),
            "error ?-6 (Macro Doesn't Exist, Ch14)"
        );
        assert_eq!(reply("01 997", "1TP\r"), "TP of 01 = 997");
        assert_eq!(
            reply("01 268436489", "1TS0\r"),
            "TS of 01 = 268436489: motor error, trajectory complete, hard limit +, limit + in"
        );
        assert_eq!(
            reply("01 1", "1TS3\r"),
            "TS of 01 = 1: Trajectory Complete (Optimal = Target)"
        );
        assert_eq!(reply("01 5", "1TP,TV\r"), "value of 01: 5");
        assert_eq!(
            reply("MFX-PCI1440-3-A Motion Controller", "VE\r"),
            "output: MFX-PCI1440-3-A Motion Controller"
        );
        assert_eq!(
            describe_reply(b"01 5", None, &LinkProfile::MANUAL),
            "value of 01: 5"
        );
    }
}
