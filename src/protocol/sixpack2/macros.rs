//! SQPack macro files (§5.4.6, digest D8): one call a line,
//! `SendToPack ( adr, cmd, p0, p1, p2, p3, p4, p5, p6 )`, "the parameters
//! are hexadecimal" — nine byte values, `$` optional, as SQPack's Macro
//! Processor Window records them and as §5.5.3 prints them
//! (`SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)`, sometimes
//! with a full stop after it).
//!
//! The manual shows no other kind of line. Where it is silent axterm
//! chooses: blank lines are skipped, `#` and `//` lines are comments
//! (axterm's own; SQPack writes none, and axterm's recorder writes none
//! either), any other line is warned about and skipped. A frame whose
//! command §7 documents is checked like a typed one (its values in range);
//! one whose command it does not is sent as written, with a warning.
//! Nothing is known of an extension for these files: `.sqm` and `.mac`
//! open as macros.

use std::fmt;

use super::catalog::motor_name;
use super::caution;
use super::command::Command;
use super::frame::{REQUEST_LEN, Request};
use super::line::{canonical, hex_byte, send_to_pack};
use crate::protocol::settings::SettingsCache;

/// File extensions of macro files (axterm's choice: the manual names
/// none).
pub const EXTENSIONS: &[&str] = &["sqm", "mac"];

/// The call every frame line makes.
const CALL: &str = "SendToPack";

/// A line of a macro file as read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MacroLine {
    Blank,
    /// `#` or `//` (axterm's own).
    Comment,
    /// A frame, and where each of its nine values starts on the line
    /// (1-based, in characters).
    Frame {
        request: Request,
        columns: [usize; REQUEST_LEN],
    },
    /// A `SendToPack` call that is not a frame: what is wrong, where.
    Bad {
        column: usize,
        message: String,
    },
    /// Any other line: skipped, with a warning.
    Other,
}

/// The 1-based character column of byte `at` of `text`.
fn column(text: &str, at: usize) -> usize {
    text.get(..at)
        .map_or(1, |before| before.chars().count() + 1)
}

/// Read one line of a macro file.
pub fn read_line(text: &str) -> MacroLine {
    let body = text.trim();
    if body.is_empty() {
        return MacroLine::Blank;
    }
    if body.starts_with('#') || body.starts_with("//") {
        return MacroLine::Comment;
    }
    let start = text.len() - text.trim_start().len();
    let is_call = text
        .get(start..start + CALL.len())
        .is_some_and(|head| head.eq_ignore_ascii_case(CALL));
    if !is_call {
        return MacroLine::Other;
    }
    let bad = |at: usize, message: String| MacroLine::Bad {
        column: column(text, at),
        message,
    };
    let mut at = start + CALL.len();
    at += text[at..].len() - text[at..].trim_start().len();
    if !text[at..].starts_with('(') {
        return bad(at, format!("expected `(` after {CALL}"));
    }
    at += 1;
    let Some(close) = text[at..].find(')').map(|i| at + i) else {
        return bad(text.len(), "expected `)` to close the call".into());
    };
    // What follows the call: nothing, or the `;` or `.` of a print.
    let rest = &text[close + 1..];
    let tail = rest.trim();
    let tail = tail.strip_prefix([';', '.']).unwrap_or(tail).trim();
    if !tail.is_empty() {
        let offset = close + 1 + (rest.len() - rest.trim_start().len());
        return bad(offset, format!("unexpected `{tail}` after the call"));
    }
    // The values and where each starts.
    let mut values: Vec<(usize, &str)> = Vec::new();
    let mut from = at;
    for piece in text[at..close].split(',') {
        let lead = piece.len() - piece.trim_start().len();
        values.push((from + lead, piece.trim()));
        from += piece.len() + 1;
    }
    if values.len() != REQUEST_LEN {
        let at = values.get(REQUEST_LEN).map_or(close, |(at, _)| *at);
        return bad(
            at,
            format!(
                "a frame has 9 values (adr, cmd, p0..p6), this one {}",
                values.len()
            ),
        );
    }
    let mut bytes = [0; REQUEST_LEN];
    let mut columns = [0; REQUEST_LEN];
    for (i, (at, value)) in values.iter().enumerate() {
        match hex_byte(value) {
            Ok(byte) => bytes[i] = byte,
            Err(message) => return bad(*at, message.to_string()),
        }
        columns[i] = column(text, *at);
    }
    match Request::from_bytes(&bytes) {
        Some(request) => MacroLine::Frame { request, columns },
        None => bad(at, "not 9 bytes".into()),
    }
}

/// Something wrong in a macro file, where it is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MacroProblem {
    /// 1-based.
    pub line: usize,
    /// 1-based, in characters.
    pub column: usize,
    pub message: String,
    pub error: bool,
}

impl fmt::Display for MacroProblem {
    /// `LINE:COLUMN: message` (`warning: …` for a warning).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = if self.error { "" } else { "warning: " };
        write!(f, "{}:{}: {kind}{}", self.line, self.column, self.message)
    }
}

/// One frame of a checked macro.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MacroFrame {
    /// 1-based line of the file.
    pub line: usize,
    pub request: Request,
    /// Whether the unit answers it (a query or a service command).
    pub answers: bool,
    /// Why it needs the user's confirmation (digest D9), if it does.
    pub confirm: Option<String>,
}

/// A macro file checked: its frames and every problem, in line order.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct MacroCheck {
    pub frames: Vec<MacroFrame>,
    pub problems: Vec<MacroProblem>,
}

impl MacroCheck {
    pub fn errors(&self) -> impl Iterator<Item = &MacroProblem> {
        self.problems.iter().filter(|p| p.error)
    }
}

/// Check a whole macro file: every frame line read and its command's
/// values checked, the D9 warnings (the cross-field ones against what the
/// frames before wrote), the lines to confirm.
pub fn check(source: &str) -> MacroCheck {
    let mut checked = MacroCheck::default();
    let mut known = SettingsCache::default();
    for (index, text) in source.lines().enumerate() {
        let line = index + 1;
        let problem = |column: usize, message: String, error: bool| MacroProblem {
            line,
            column,
            message,
            error,
        };
        let (request, columns) = match read_line(text) {
            MacroLine::Blank | MacroLine::Comment => continue,
            MacroLine::Other => {
                checked.problems.push(problem(
                    1,
                    format!(
                        "not a {CALL}(…) call: skipped (the manual shows no other line in a macro, \
                         §5.4.6; `#` starts a comment)"
                    ),
                    false,
                ));
                continue;
            }
            MacroLine::Bad { column, message } => {
                checked.problems.push(problem(column, message, true));
                continue;
            }
            MacroLine::Frame { request, columns } => (request, columns),
        };
        let command = match Command::from_request(&request) {
            Ok(command) => command,
            Err(range) => {
                // The column of the first byte of the field out of range.
                let at = super::catalog::by_code(request.command)
                    .and_then(|spec| spec.field(range.field))
                    .map_or(columns[1], |(_, field)| columns[2 + field.offset]);
                checked.problems.push(problem(at, range.to_string(), true));
                continue;
            }
        };
        for warning in caution::warnings(&request, &super::console::known_of(&known)) {
            checked.problems.push(problem(columns[1], warning, false));
        }
        if request.command == 0xCC {
            known.forget("HardwareReset");
        }
        known.record(&super::parameter_set::written_by(&request));
        checked.frames.push(MacroFrame {
            line,
            request,
            answers: command.as_ref().is_some_and(|c| c.spec.answers()),
            confirm: caution::confirmation(&request),
        });
    }
    checked
}

/// A frame in words, shown beside its line: the console line it is
/// (`SetMotorParameters 0 10000 NullLeft,MechRef (Motor 1)`), for a unit
/// other than 0 with its address, or what is odd about it.
pub fn decode(request: &Request) -> String {
    let unit = if request.address == 0 {
        String::new()
    } else {
        format!("unit {}: ", request.address)
    };
    match Command::from_request(request) {
        Ok(Some(command)) => {
            let mut text = format!("{unit}{command}");
            if let Some(motor) = command.motor() {
                let name = motor_name(i64::from(motor));
                if let Some((_, manual)) = name.split_once('(') {
                    text.push_str(&format!(" ({}", manual.trim()));
                }
            }
            let stray = Command::stray_bytes(command.spec, &request.params);
            if !stray.is_empty() {
                text.push_str(&format!(" [{} not $00]", stray.join(", ")));
            }
            text
        }
        Ok(None) => format!(
            "{unit}${:02X}: not in the instruction set (§7), sent as written",
            request.command
        ),
        Err(range) => format!("{unit}{range}"),
    }
}

/// The decoded form of a line of a macro file, if it is a frame.
pub fn decode_line(text: &str) -> Option<String> {
    match read_line(text) {
        MacroLine::Frame { request, .. } => Some(decode(&request)),
        _ => None,
    }
}

/// The macro line that sends `bytes` again, as SQPack writes it
/// (§5.5.3); `None` for anything but a 9-byte request.
pub fn record_line(bytes: &[u8]) -> Option<String> {
    Request::from_bytes(bytes).map(|request| send_to_pack(&request))
}

/// The console line of a frame, for messages.
pub fn line_of(request: &Request) -> String {
    canonical(request)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn frame(text: &str) -> Request {
        match read_line(text) {
            MacroLine::Frame { request, .. } => request,
            other => panic!("{text}: {other:?}"),
        }
    }

    fn bad(text: &str) -> (usize, String) {
        match read_line(text) {
            MacroLine::Bad { column, message } => (column, message),
            other => panic!("{text}: {other:?}"),
        }
    }

    #[test]
    fn the_manuals_lines_read_as_their_bytes() {
        // §5.5.3.2, printed with its full stop.
        let request = frame("SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04).");
        assert_eq!(
            request.to_bytes(),
            [0x00, 0x15, 0x00, 0x10, 0x27, 0x00, 0x00, 0x10, 0x04]
        );
        assert_eq!(
            decode(&request),
            "SetMotorParameters 0 10000 NullLeft,MechRef (Motor 1)"
        );
        // §5.4.6's form: blanks, no `$`; bare values are hex.
        let request = frame("  SendToPack ( 0, 22, 0, 0, 0, 0, 0, 0, 0 );");
        assert_eq!(request.command, 0x22);
        assert_eq!(decode(&request), "StartReferenceSearch 0 (Motor 1)");
        assert_eq!(read_line("sendtopack(0x00,0x43,0,0,0,0,0,0,0)"), {
            let request = frame("SendToPack($00,$43,$00,$00,$00,$00,$00,$00,$00)");
            MacroLine::Frame {
                request,
                columns: [12, 17, 22, 24, 26, 28, 30, 32, 34],
            }
        });
    }

    #[test]
    fn errors_say_where_they_are() {
        assert_eq!(
            bad("SendToPack($00, $15, $00)"),
            (
                25,
                "a frame has 9 values (adr, cmd, p0..p6), this one 3".into()
            )
        );
        assert_eq!(
            bad("SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04, $00)").0,
            57,
            "the tenth value"
        );
        let (column, message) = bad("SendToPack($00, $15, $G0, $10, $27, $00, $00, $10, $04)");
        assert_eq!(column, 22);
        assert!(message.contains("`$G0` is not a hex byte"), "{message}");
        assert_eq!(
            bad("SendToPack($00, $15, $100, $10, $27, $00, $00, $10, $04)").0,
            22
        );
        assert_eq!(bad("SendToPack $00").0, 12);
        assert_eq!(bad("SendToPack($00").1, "expected `)` to close the call");
        assert_eq!(
            bad("SendToPack($00, $43, 0, 0, 0, 0, 0, 0, 0) x"),
            (43, "unexpected `x` after the call".into())
        );
        assert_eq!(read_line(""), MacroLine::Blank);
        assert_eq!(read_line("  # homing"), MacroLine::Comment);
        assert_eq!(read_line("Sleep(100)"), MacroLine::Other);
    }

    #[test]
    fn a_file_is_checked_whole_with_values_warnings_and_confirmations() {
        let checked = check(
            "# §5.5.3.2\n\
             SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04)\n\
             \n\
             SendToPack($00, $22, $00, $00, $00, $00, $00, $00, $00)\n\
             Wait 100\n\
             SendToPack($00, $23, $06, $10, $27, $00, $00, $00, $00)\n\
             SendToPack($00, $20, $00, $00, $00, $00, $00, $00, $00)\n\
             SendToPack($00, $1A, $00, $20, $00, $00, $00, $00, $00)\n",
        );
        let shown: Vec<String> = checked.problems.iter().map(|p| p.to_string()).collect();
        assert_eq!(shown.len(), 3, "{shown:?}");
        assert!(shown[0].starts_with("5:1: warning: not a SendToPack(…) call"));
        assert_eq!(
            shown[1],
            "6:22: StartRamp: motno 6 is outside 0..5 (Motor 1..6)"
        );
        assert!(
            shown[2].starts_with("8:17: warning: $1A is not in the instruction set"),
            "{}",
            shown[2]
        );
        assert_eq!(checked.errors().count(), 1);
        let lines: Vec<usize> = checked.frames.iter().map(|f| f.line).collect();
        assert_eq!(lines, [2, 4, 7, 8]);
        assert!(checked.frames[1].confirm.is_some(), "$22 homes");
        assert!(checked.frames[0].confirm.is_none());
        assert!(checked.frames[2].answers && !checked.frames[0].answers);
        // The cross-field warnings know what the frames before wrote.
        let vstart_8 = "SendToPack($00, $13, $00, $04, $00, $08, $00, $02, $00)\n";
        let amax_500 = "SendToPack($00, $14, $00, $F4, $01, $90, $01, $00, $00)\n";
        assert_eq!(check(amax_500).problems.len(), 1);
        assert!(check(&format!("{vstart_8}{amax_500}")).problems.is_empty());
    }

    #[test]
    fn a_recorded_line_reads_back_as_its_bytes() {
        let bytes = [0x03, 0x23, 0x05, 0xF0, 0xD8, 0xFF, 0xFF, 0x00, 0x00];
        let line = record_line(&bytes).expect("a request");
        assert_eq!(
            line,
            "SendToPack($03, $23, $05, $F0, $D8, $FF, $FF, $00, $00)"
        );
        assert_eq!(frame(&line).to_bytes(), bytes);
        assert_eq!(
            decode_line(&line).as_deref(),
            Some("unit 3: StartRamp 5 -10000 (Motor 6)")
        );
        assert_eq!(record_line(&bytes[..8]), None);
    }

    proptest! {
        #[test]
        fn reading_never_panics(text in "\\PC*") {
            let _ = read_line(&text);
            let _ = check(&text);
            let _ = decode_line(&text);
        }

        #[test]
        fn lines_near_the_form_never_panic(
            values in proptest::collection::vec("[ $0-9A-Fa-fxX]{0,4}", 0..12),
            tail in "[ ;.)(,a-z]{0,4}",
        ) {
            let text = format!("SendToPack({}){tail}", values.join(","));
            let _ = read_line(&text);
        }

        #[test]
        fn every_request_written_reads_back(bytes in proptest::array::uniform9(any::<u8>())) {
            let line = record_line(&bytes).expect("nine bytes");
            match read_line(&line) {
                MacroLine::Frame { request, .. } => prop_assert_eq!(request.to_bytes(), bytes),
                other => prop_assert!(false, "{line}: {other:?}"),
            }
        }

        #[test]
        fn a_bad_line_is_located_on_the_line(text in "SendToPack\\([^)]{0,40}\\)[ ;.]{0,2}") {
            if let MacroLine::Bad { column, .. } = read_line(&text) {
                prop_assert!(column >= 1 && column <= text.chars().count() + 1);
            }
        }
    }
}
