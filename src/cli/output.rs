//! How `exec` and `run` show a line's result: its value (or `ok`) on a line
//! of its own, or one JSON object per line for programs.

use clap::ValueEnum;
use serde_json::{Value, json};

use crate::protocol::Family;
use crate::session::{LineResult, ReplyValue, SessionError};

/// Output format of the scriptable front ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum Format {
    /// One line per result: the value, or `ok`.
    #[default]
    Text,
    /// One JSON object per result.
    Json,
}

/// The JSON object for one line's outcome: the line as given, request and
/// reply bytes as the family shows them, the status, the value, whether it
/// succeeded, and the round trip in microseconds. A value read from a
/// family whose answers carry no checksum
/// ([`crate::protocol::console::FamilyConsole::replies_checked`]) is marked
/// `"unchecked": true`: nothing on the wire vouches for its digits.
pub fn json_outcome(
    family: &Family,
    line: &str,
    outcome: &Result<LineResult, SessionError>,
) -> Value {
    let hex = |bytes: &[u8]| (family.show_bytes)(bytes);
    match outcome {
        Ok(result) => {
            let mut object = json!({
                "line": line,
                "command": result.line,
                "request": hex(&result.request),
                "reply": hex(&result.reply),
                "status": result.status,
                "value": json_value(&result.value),
                "ok": true,
                "elapsed_us": u64::try_from(result.elapsed.as_micros()).unwrap_or(u64::MAX),
            });
            if read_unchecked(family, result) {
                object["unchecked"] = json!(true);
            }
            object
        }
        Err(error) => {
            let elapsed = match error {
                SessionError::Reply { elapsed, .. } => {
                    Some(u64::try_from(elapsed.as_micros()).unwrap_or(u64::MAX))
                }
                _ => None,
            };
            json!({
                "line": line,
                "request": error.request().map(hex),
                "reply": error.reply().map(hex),
                "status": error.status(),
                "value": Value::Null,
                "ok": false,
                "error": error.to_string(),
                "elapsed_us": elapsed,
            })
        }
    }
}

/// A check of a run file (`:expect`, `:wait-until`) as it ended.
pub struct CheckOutcome<'a> {
    /// `expect` or `wait-until`.
    pub directive: &'a str,
    /// The console line checked, as the file gives it.
    pub line: &'a str,
    /// Its line in the file (1-based).
    pub line_number: usize,
    /// The value it had to have, as the file gives it.
    pub expected: &'a str,
    /// The last reading of the line (for `:wait-until`, the one that
    /// matched or the last before the deadline).
    pub last: &'a Result<LineResult, SessionError>,
    pub ok: bool,
}

/// The JSON object for a check: the directive, the line and its place,
/// the value expected and the value read (`null` when the line failed,
/// with its error), and whether it passed.
pub fn json_check(check: &CheckOutcome) -> Value {
    let mut object = json!({
        "directive": check.directive,
        "line": check.line,
        "line_number": check.line_number,
        "expected": check.expected,
        "ok": check.ok,
    });
    match check.last {
        Ok(result) => {
            object["command"] = json!(result.line);
            object["actual"] = json_value(&result.value);
        }
        Err(error) => {
            object["actual"] = Value::Null;
            object["error"] = json!(error.to_string());
        }
    }
    object
}

fn json_value(value: &ReplyValue) -> Value {
    match value {
        ReplyValue::None => Value::Null,
        ReplyValue::Number(n) => json!(n),
        ReplyValue::Text(text) => json!(text),
    }
}

/// Print one line's outcome: the result on stdout (text: the value or `ok`;
/// nothing for a failure), the error on stderr after `context`.
pub fn print_outcome(
    format: Format,
    family: &Family,
    line: &str,
    context: &str,
    outcome: &Result<LineResult, SessionError>,
) {
    match format {
        Format::Text => {
            if let Ok(result) = outcome {
                println!("{}", result.value);
                if let Some(note) = unchecked_note(family, line, result) {
                    eprintln!("{context}{note}");
                }
            }
        }
        Format::Json => println!("{}", json_outcome(family, line, outcome)),
    }
    if let Err(error) = outcome {
        eprintln!("{context}{error}");
    }
}

/// The text front ends' mark of a value nothing on the wire vouches for
/// (a family whose replies carry no checksum). It goes to stderr, not on
/// the value's line: scripts that parse the bare value on stdout keep
/// working, and a person at the terminal still sees it.
pub fn unchecked_note(family: &Family, line: &str, result: &LineResult) -> Option<String> {
    read_unchecked(family, result)
        .then(|| format!("{line}: unchecked (the reply carries no checksum)"))
}

/// Whether `result` holds a value nothing on the wire vouches for
/// ([`crate::session::read_unchecked`]).
fn read_unchecked(family: &Family, result: &LineResult) -> bool {
    crate::session::read_unchecked(family.console, result)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::find_family;
    use crate::protocol::console::ReplyError;
    use std::time::Duration;

    /// Issue 19: the text output's stderr note marks a value read without a
    /// checksum, never a write's ok nor a checked family's value.
    #[test]
    fn text_note_marks_unchecked_values_only() {
        let checked = find_family("tmcl").expect("tmcl");
        let unchecked = find_family("sixpack2").expect("sixpack2");
        let result = |reply: &[u8], value| LineResult {
            line: "PX".into(),
            request: Vec::new(),
            reply: reply.to_vec(),
            status: None,
            value,
            elapsed: Duration::from_micros(900),
            attempts: 1,
        };
        let read = result(b"5\r", ReplyValue::Number(5));
        let write = result(b"OK\r", ReplyValue::None);
        // A frame that gets no reply (SIXpack 2 `SetPeakCurrent`): "sent"
        // is no value read.
        let sent = result(b"", ReplyValue::Text("sent".into()));
        assert!(unchecked_note(unchecked, "x", &read).is_some());
        assert!(unchecked_note(unchecked, "x", &write).is_none());
        assert!(unchecked_note(unchecked, "x", &sent).is_none());
        assert!(unchecked_note(checked, "x", &read).is_none());
    }

    /// Issue 19: a SIXpack 2 position read printed a corrupted value as
    /// plain ok. A value read from a family without a checksum says so;
    /// a write's `ok` has no value to vouch for.
    #[test]
    fn json_marks_values_read_without_a_checksum() {
        let result = |value| {
            Ok(LineResult {
                line: "PX".into(),
                request: b"@01PX\r".to_vec(),
                reply: b"112421\r".to_vec(),
                status: None,
                value,
                elapsed: Duration::from_micros(900),
                attempts: 1,
            })
        };
        for name in ["cmd4cr", "sixpack2", "mccl"] {
            let family = find_family(name).unwrap();
            let read = json_outcome(family, "PX", &result(ReplyValue::Number(112421)));
            assert_eq!(read["unchecked"], true, "{name}");
            let write = json_outcome(family, "PX", &result(ReplyValue::None));
            assert_eq!(write.get("unchecked"), None, "{name}");
        }
    }

    #[test]
    fn json_carries_every_field() {
        let family = find_family("tmcl").unwrap();
        let ok = Ok(LineResult {
            line: "GAP 4, 0".into(),
            request: vec![1, 6, 4, 0, 0, 0, 0, 0, 11],
            reply: vec![2, 1, 100, 6, 0, 0, 4, 0xD2, 0x4F],
            status: Some(100),
            value: ReplyValue::Number(1234),
            elapsed: Duration::from_micros(1500),
            attempts: 1,
        });
        let object = json_outcome(family, "gap 4 0", &ok);
        assert_eq!(
            object.get("unchecked"),
            None,
            "TMCL replies carry a checksum"
        );
        assert_eq!(object["line"], "gap 4 0");
        assert_eq!(object["command"], "GAP 4, 0");
        assert_eq!(object["request"], "01 06 04 00 00 00 00 00 0B");
        assert_eq!(object["reply"], "02 01 64 06 00 00 04 D2 4F");
        assert_eq!(object["status"], 100);
        assert_eq!(object["value"], 1234);
        assert_eq!(object["ok"], true);
        assert_eq!(object["elapsed_us"], 1500);

        let refused: Result<LineResult, SessionError> = Err(SessionError::Reply {
            error: Box::new(ReplyError::Rejected {
                module: "module 1".into(),
                line: "SAP 6, 0, 200".into(),
                status: 4,
                meaning: "invalid value".into(),
            }),
            request: vec![1, 5, 6, 0, 0, 0, 0, 200, 212],
            reply: vec![2, 1, 4, 5, 0, 0, 0, 0, 12],
            elapsed: Duration::from_micros(10),
        });
        let object = json_outcome(family, "SAP 6, 0, 200", &refused);
        assert_eq!(object["ok"], false);
        assert_eq!(object["status"], 4);
        assert_eq!(object["value"], Value::Null);
        assert_eq!(object["reply"], "02 01 04 05 00 00 00 00 0C");
        assert_eq!(
            object["error"],
            "module 1 rejected SAP 6, 0, 200: invalid value (status 4)"
        );
    }
}
