//! What a reply says (§7): its fields read by the command's reply layout,
//! action codes by name, the `$30` reference inputs and jumpers, the `$43`
//! unit information.
//!
//! A reply's value, as the console prints it and a batch file's `:expect`
//! compares it, is its fields as `name=value` words in frame order, the
//! echoed motor or channel left out (the request says it):
//! `posact=10000 action=ramp stop=0`. [`ReplyFields::parse_value`] reads
//! that text back, for the status display.

use super::catalog::{CommandSpec, Field, FieldKind, action_from_token, action_token, activity};
use super::command::{field_value, format_mask, format_value};
use super::frame::{PARAMS, Reply, Request};
use super::line::parse_mask;

/// The fields of a reply, by name, in frame order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReplyFields {
    pub spec: &'static CommandSpec,
    pub values: Vec<(&'static Field, i64)>,
}

/// Why a reply does not answer a request.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Mismatch {
    #[error("it echoes command ${found:02X}, not ${sent:02X}")]
    Command { sent: u8, found: u8 },
    #[error("it is for {field} {found}, not {sent}")]
    Echo {
        field: &'static str,
        sent: u8,
        found: u8,
    },
    #[error("its address byte is ${found:02X}, the request's response address ${sent:02X}")]
    ResponseAddress { sent: u8, found: u8 },
    #[error("${0:02X} does not answer (§7)")]
    NoReply(u8),
}

/// Whether `reply` answers `request`: the same command, the same motor or
/// channel where the reply echoes it (§6.2.2.3: "should be the same
/// number as the sent"), the request's response address in front where
/// there is an address byte.
pub fn check_answers(request: &Request, reply: &Reply) -> Result<&'static CommandSpec, Mismatch> {
    if reply.command != request.command {
        return Err(Mismatch::Command {
            sent: request.command,
            found: reply.command,
        });
    }
    let spec = super::catalog::by_code(request.command)
        .filter(|s| s.answers())
        .ok_or(Mismatch::NoReply(request.command))?;
    if let Some(found) = reply.response_address {
        let sent = spec
            .response_field()
            .map_or(0, |f| request.params[f.offset]);
        if found != sent {
            return Err(Mismatch::ResponseAddress { sent, found });
        }
    }
    if let Some(echo) = echoed(spec) {
        let (sent, found) = (request.params[echo.offset], reply.params[echo.offset]);
        if sent != found {
            return Err(Mismatch::Echo {
                field: echo.name,
                sent,
                found,
            });
        }
    }
    Ok(spec)
}

/// The reply field that echoes the request's motor or channel.
fn echoed(spec: &CommandSpec) -> Option<&'static Field> {
    spec.reply?
        .iter()
        .find(|f| f.offset == 0 && matches!(f.kind, FieldKind::Motor | FieldKind::Channel))
}

impl ReplyFields {
    /// The fields of a reply to `spec`.
    pub fn read(spec: &'static CommandSpec, params: &[u8; PARAMS]) -> Option<ReplyFields> {
        let layout = spec.reply?;
        Some(ReplyFields {
            spec,
            values: layout.iter().map(|f| (f, field_value(f, params))).collect(),
        })
    }

    /// A value no SIXpack 2 sends, if the reply has one: an action code
    /// §7.2 does not list. With no checksum over the frame (§7.1), such a
    /// value is the only sign of a damaged reply.
    pub fn impossible(&self) -> Option<String> {
        self.values.iter().find_map(|&(field, value)| {
            let listed = u8::try_from(value).ok().and_then(activity).is_some();
            (field.kind == FieldKind::Action && !listed)
                .then(|| format!("{} {value} is no action code of §7.2", field.name))
        })
    }

    /// The value of the field called `name`.
    pub fn get(&self, name: &str) -> Option<i64> {
        self.values
            .iter()
            .find(|(f, _)| f.name == name)
            .map(|(_, v)| *v)
    }

    /// The reply's value as the console prints it: `name=value` words,
    /// the echo left out.
    pub fn value_text(&self) -> String {
        let echo = echoed(self.spec);
        let mut words = Vec::new();
        for &(field, value) in &self.values {
            if echo.is_some_and(|e| std::ptr::eq(e, field)) {
                continue;
            }
            match field.kind {
                FieldKind::Action => words.push(format!(
                    "{}={}",
                    field.name,
                    action_token(u8::try_from(value).unwrap_or(u8::MAX))
                )),
                FieldKind::InputsAndJumpers => {
                    words.push(format!("refs={}", format_mask(value & 0x3F)));
                    words.push(format!("jp1={}", (value >> 6) & 1));
                    words.push(format!("jp2={}", (value >> 7) & 1));
                }
                _ => words.push(format!("{}={}", field.name, format_value(field, value))),
            }
        }
        words.join(" ")
    }

    /// Read a value text of a reply to `spec` back: each field's value, by
    /// the field's name (the `$30` inputs as `refs`, `jp1`, `jp2`).
    pub fn parse_value(spec: &'static CommandSpec, text: &str) -> Option<Vec<(&'static str, i64)>> {
        let layout = spec.reply?;
        let mut values = Vec::new();
        for word in text.split_whitespace() {
            let (name, value) = word.split_once('=')?;
            let value = if name == "refs" {
                parse_mask(value).ok()?
            } else if let Some(field) = layout.iter().find(|f| f.name == name) {
                match field.kind {
                    FieldKind::Action => i64::from(action_from_token(value)?),
                    _ => super::line::parse_value(field, value).ok()?,
                }
            } else if matches!(name, "jp1" | "jp2") {
                value.parse().ok()?
            } else {
                return None;
            };
            let name = layout
                .iter()
                .map(|f| f.name)
                .chain(["refs", "jp1", "jp2"])
                .find(|n| *n == name)?;
            values.push((name, value));
        }
        Some(values)
    }

    /// The reply in words, for the traffic monitor: every field with its
    /// meaning where it has one.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        for &(field, value) in &self.values {
            let text = match field.kind {
                FieldKind::Motor => super::catalog::motor_name(value),
                FieldKind::Channel => format!("channel {value}"),
                FieldKind::Action => {
                    let code = u8::try_from(value).unwrap_or(u8::MAX);
                    match activity(code) {
                        Some(a) => format!("{} {value} {}", field.name, a.name),
                        None => format!("{} {value} (not in §7.2)", field.name),
                    }
                }
                FieldKind::InputsAndJumpers => format!(
                    "reference inputs {} · JP1 {} · JP2 {} ({})",
                    format_mask(value & 0x3F),
                    (value >> 6) & 1,
                    (value >> 7) & 1,
                    jumper_baud(value)
                ),
                _ if field.name == "firmware" => format!("firmware {}", firmware_version(value)),
                _ if field.unit.is_empty() => {
                    format!("{} {}", field.name, format_value(field, value))
                }
                _ => format!(
                    "{} {} {}",
                    field.name,
                    format_value(field, value),
                    field.unit
                ),
            };
            parts.push(text);
        }
        parts.join(" · ")
    }
}

/// `148` → `V1.4.8` (§7.4 "e.g. 148=V1.4.8").
pub fn firmware_version(revision: i64) -> String {
    format!(
        "V{}.{}.{}",
        revision / 100,
        (revision / 10) % 10,
        revision % 10
    )
}

/// The RS-232/485 rate the jumpers of a `$30` P4 byte select, read as
/// 1 = fitted (Table 5.1; the manual does not state the polarity, digest
/// D1.1).
pub fn jumper_baud(inputs: i64) -> String {
    let (jp1, jp2) = ((inputs >> 6) & 1 == 1, (inputs >> 7) & 1 == 1);
    let baud = match (jp1, jp2) {
        (true, true) => 9600,
        (false, true) => 57600,
        (true, false) => 38400,
        (false, false) => 19200,
    };
    format!("{baud} Bd if 1 means fitted")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::sixpack2::catalog::by_name;

    fn spec(name: &str) -> &'static CommandSpec {
        by_name(name).expect("a command")
    }

    fn request(name: &str, params: [u8; 7]) -> Request {
        Request {
            address: 0,
            command: spec(name).code,
            params,
        }
    }

    fn reply(command: u8, params: [u8; 7]) -> Reply {
        Reply {
            response_address: None,
            command,
            params,
        }
    }

    #[test]
    fn position_replies_read_as_section_6_2_2_3_reads_them() {
        let fields =
            ReplyFields::read(spec("GetPositionAndActivity"), &[2, 0x10, 0x27, 0, 0, 5, 1])
                .expect("a reply");
        assert_eq!(fields.get("posact"), Some(10_000));
        assert_eq!(fields.get("action"), Some(5));
        assert_eq!(fields.value_text(), "posact=10000 action=ramp stop=1");
        assert_eq!(
            fields.describe(),
            "motor 2 (Motor 3) · posact 10000 µsteps · action 5 ramp · stop 1"
        );
        let negative = ReplyFields::read(
            spec("GetPositionAndActivity"),
            &[0, 0xFF, 0xFF, 0xFF, 0xFF, 0, 0],
        )
        .expect("a reply");
        assert_eq!(negative.get("posact"), Some(-1));
    }

    #[test]
    fn value_texts_read_back() {
        let cases: [(&str, [u8; 7]); 5] = [
            ("GetPositionAndActivity", [2, 0x10, 0x27, 0, 0, 23, 1]),
            ("GetVelocityAndActivity", [1, 0x01, 0xFE, 15, 0, 0, 0]),
            ("GetAllActivities", [0, 5, 10, 15, 25, 30, 0]),
            ("GetInputValues", [0, 0xFF, 0x03, 1, 0b1100_1001, 1, 0]),
            ("GetUnitInformation", [148, 1, 0xE7, 0x39, 0x30, 0, 0]),
        ];
        for (name, params) in cases {
            let fields = ReplyFields::read(spec(name), &params).expect("a reply");
            let text = fields.value_text();
            let back = ReplyFields::parse_value(spec(name), &text).expect("reads back");
            for (field, value) in back {
                if let Some(expected) = fields.get(field) {
                    assert_eq!(value, expected, "{name} {field} in {text}");
                }
            }
        }
        let inputs = ReplyFields::read(
            spec("GetInputValues"),
            &[0, 0xFF, 0x03, 1, 0b1100_1001, 1, 0],
        )
        .expect("a reply");
        assert_eq!(
            inputs.value_text(),
            "analog=1023 ref=1 refs=0,3 jp1=1 jp2=1 ttlio1=1"
        );
        assert!(
            inputs
                .describe()
                .contains("JP1 1 · JP2 1 (9600 Bd if 1 means fitted)")
        );
        let unit = ReplyFields::read(
            spec("GetUnitInformation"),
            &[148, 1, 0xE7, 0x39, 0x30, 0, 0],
        )
        .expect("a reply");
        assert_eq!(
            unit.value_text(),
            "firmware=148 reset=1 temperature=-25 serial=12345"
        );
        assert!(
            unit.describe()
                .starts_with("firmware V1.4.8 · reset 1 · temperature -25 °C")
        );
        assert_eq!(
            ReplyFields::parse_value(spec("GetUnitInformation"), "bogus"),
            None
        );
        assert_eq!(
            ReplyFields::parse_value(spec("StartRamp"), "posact=1"),
            None
        );
    }

    #[test]
    fn a_reply_must_echo_command_motor_and_address() {
        let sent = request("GetPositionAndActivity", [3, 0, 0, 0, 0, 0, 0]);
        assert!(check_answers(&sent, &reply(0x20, [3, 0, 0, 0, 0, 0, 0])).is_ok());
        assert_eq!(
            check_answers(&sent, &reply(0x20, [4, 0, 0, 0, 0, 0, 0])),
            Err(Mismatch::Echo {
                field: "motno",
                sent: 3,
                found: 4
            })
        );
        assert_eq!(
            check_answers(&sent, &reply(0x21, [3, 0, 0, 0, 0, 0, 0])),
            Err(Mismatch::Command {
                sent: 0x20,
                found: 0x21
            })
        );
        let mut addressed = reply(0x20, [3, 0, 0, 0, 0, 0, 0]);
        addressed.response_address = Some(9);
        assert!(matches!(
            check_answers(&sent, &addressed),
            Err(Mismatch::ResponseAddress { sent: 0, found: 9 })
        ));
        // $28 carries no echo: its P0 is motor 0's action.
        let all = request("GetAllActivities", [0, 0x3F, 0, 0, 0, 0, 0]);
        assert!(check_answers(&all, &reply(0x28, [5, 0, 0, 0, 0, 0, 0])).is_ok());
        let ramp = request("StartRamp", [0; 7]);
        assert_eq!(
            check_answers(&ramp, &reply(0x23, [0; 7])),
            Err(Mismatch::NoReply(0x23))
        );
    }

    #[test]
    fn firmware_and_jumpers() {
        assert_eq!(firmware_version(148), "V1.4.8");
        assert_eq!(jumper_baud(0), "19200 Bd if 1 means fitted");
        assert_eq!(jumper_baud(0x80), "57600 Bd if 1 means fitted");
    }
}
