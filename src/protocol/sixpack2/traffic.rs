//! SIXpack 2 frames as the traffic monitor shows them: a request as its
//! console line and unit, a reply as what its fields say, read in the
//! light of the request it answers.

use super::catalog::{by_code, motor_name};
use super::command::Command;
use super::frame::{Reply, ReplyFraming, Request};
use super::line::canonical;
use super::reply::{ReplyFields, check_answers};

/// A request in words: its console line, the unit and the motor it is
/// for, and whether the unit will answer.
pub fn describe_request(bytes: &[u8]) -> String {
    let Some(request) = Request::from_bytes(bytes) else {
        return format!(
            "not a SIXpack 2 request: {} bytes, a request has 9",
            bytes.len()
        );
    };
    let line = canonical(&request);
    let about = match Command::from_request(&request) {
        Ok(Some(command)) => {
            let motor = command
                .motor()
                .map(|m| format!(", {}", motor_name(i64::from(m))))
                .unwrap_or_default();
            let answer = if command.spec.answers() {
                ""
            } else {
                ", not acknowledged"
            };
            format!("{motor}{answer}")
        }
        Ok(None) => ", a command §7 does not list".into(),
        Err(e) => format!(": {e}"),
    };
    format!("{line} to unit {}{about}", request.address)
}

/// A reply in words. `request`, the last frame sent, decides whether it
/// answers it; one that does not (a delayed `$28`, a late poll) is read on
/// its own.
pub fn describe_reply(bytes: &[u8], request: Option<&[u8]>, framing: ReplyFraming) -> String {
    let reply = match Reply::parse(bytes, framing) {
        Ok(reply) => reply,
        Err(e) => return format!("not a SIXpack 2 reply: {e}"),
    };
    let Some(spec) = by_code(reply.command) else {
        return format!("${:02X}: no such command", reply.command);
    };
    let said = ReplyFields::read(spec, &reply.params)
        .map(|f| f.describe())
        .unwrap_or_default();
    let request = request.and_then(Request::from_bytes);
    match request.map(|r| (r, check_answers(&r, &reply))) {
        Some((_, Ok(_))) | None => format!("{}: {said}", spec.mnemonic),
        Some((sent, Err(mismatch))) => format!(
            "{}: {said} (not an answer to {}: {mismatch})",
            spec.mnemonic,
            canonical(&sent)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_read_as_their_line() {
        assert_eq!(
            describe_request(&[0, 0x23, 0, 0x10, 0x27, 0, 0, 0, 0]),
            "StartRamp 0 10000 to unit 0, motor 0 (Motor 1), not acknowledged"
        );
        assert_eq!(
            describe_request(&[3, 0x20, 5, 0, 0, 0, 0, 0, 0]),
            "GetPositionAndActivity 5 to unit 3, motor 5 (Motor 6)"
        );
        assert_eq!(
            describe_request(&[0, 0x1A, 0, 0x20, 0, 0, 0, 0, 0]),
            "SendToPack($00, $1A, $00, $20, $00, $00, $00, $00, $00) to unit 0, a command §7 does \
             not list"
        );
        assert!(
            describe_request(&[0, 0x23, 9, 0, 0, 0, 0, 0, 0])
                .ends_with("motno 9 is outside 0..5 (Motor 1..6)")
        );
        assert!(describe_request(&[1, 2]).starts_with("not a SIXpack 2 request: 2 bytes"));
    }

    #[test]
    fn replies_read_in_the_light_of_the_request() {
        let sent = [0, 0x20, 1, 0, 0, 0, 0, 0, 0];
        assert_eq!(
            describe_reply(
                &[0x20, 1, 0x10, 0x27, 0, 0, 5, 0],
                Some(&sent),
                ReplyFraming::Auto
            ),
            "GetPositionAndActivity: motor 1 (Motor 2) · posact 10000 µsteps · action 5 ramp · \
             stop 0"
        );
        let late = describe_reply(
            &[0x28, 0, 0, 0, 0, 0, 15, 0],
            Some(&sent),
            ReplyFraming::Auto,
        );
        assert!(
            late.starts_with("GetAllActivities: m0 0 inactive"),
            "{late}"
        );
        assert!(late.contains("m5 15 rotation"), "{late}");
        assert!(
            late.ends_with(
                "(not an answer to GetPositionAndActivity 1: it echoes command $28, not $20)"
            ),
            "{late}"
        );
        assert!(
            describe_reply(&[0x23, 0, 0, 0, 0, 0, 0, 0], None, ReplyFraming::Cmd8)
                .starts_with("not a SIXpack 2 reply: it starts with $23")
        );
        let unit = describe_reply(&[0x43, 148, 0, 30, 1, 0, 0, 0], None, ReplyFraming::Auto);
        assert_eq!(
            unit,
            "GetUnitInformation: firmware V1.4.8 · reset 0 · temperature 30 °C · serial 1"
        );
    }
}
