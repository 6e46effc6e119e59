//! PMC MultiFlex MCCL (Motion Control Command Language Reference Manual
//! rev. 3.0): its ASCII command interface. Pure code: bytes and meanings,
//! no I/O.
//!
//! A line is commands `[axis]MM[parameter]` separated by commas, ended by a
//! CR (Ch2); the controller echoes it, prints what its reporting commands
//! report, and sends its prompt `>` when the line is done (Ch13 PC). The
//! command set is data ([`catalog::COMMANDS`], Ch3–Ch13); [`parse_line`]
//! is the one parser of command text; [`check`] holds the rules a line must
//! keep; [`reply`] reads answers; [`profile`] describes the interface where
//! the manual leaves it open (digest §3.2); [`console`] keeps it per link
//! ([`MclContext`]: the connect probe, `DM`/`HM`, `PC`, `EN`/`EF`);
//! [`wire`] is what the device task needs (the prompt, the quiet guard,
//! answers told apart by their echo); [`tool`] and [`plan`] are text files
//! and macros as a program tool (check, colours, download verified by
//! `TM`, upload by `TM-1`, the macro manager).

pub mod assist;
pub mod catalog;
pub mod check;
pub mod console;
pub mod io;
pub mod jog;
pub mod line;
pub mod machine;
pub mod parameter_set;
pub mod plan;
pub mod profile;
pub mod reply;
pub mod status;
pub mod tool;
pub mod traffic;
pub mod tune;
pub mod tuning;
pub mod units;
pub mod wire;

pub use catalog::{COMMANDS, CommandSpec};
pub use check::{CheckContext, Diagnostic, Severity, check_file, check_line, check_text};
pub use console::{MclConsole, MclContext, StopMotion};
pub use line::{Command, Line, NumberBase, ParseError, ParseErrors, Value, parse_line};
pub use machine::{AxisKind, DEFAULT_MACHINE, Machine};
pub use profile::{Echo, LinkProfile, LinkState, PromptPer};
pub use reply::{AnswerRule, ErrorReply, Reply, ReplyProblem, read_reply};
pub use tool::{MacroStore, MclTool};

/// The MultiFlex MCCL family's entry (registered in [`crate::families`]).
pub static FAMILY: crate::protocol::Family = crate::protocol::Family {
    name: "mccl",
    description: "PMC MultiFlex MCCL (up to 8 axes), ASCII lines with echo and prompt",
    encode_line,
    show_bytes,
    console: &MclConsole::DEFAULT,
};

use crate::protocol::console::FamilyConsole;

/// `axterm encode mccl LINE`: the bytes the line becomes (the interface has
/// no bus address; any given must be 0).
pub fn encode_line(
    line: &str,
    address: Option<u8>,
) -> Result<Vec<u8>, crate::protocol::line_error::LineError> {
    MclConsole::DEFAULT
        .prepare(line, address.unwrap_or(console::ADDRESS))
        .map(|prepared| prepared.bytes)
}

/// Bytes as a technician reads them: printable characters as they are, CR
/// and LF as `\r` and `\n`, Escape and the rest as `\xNN`.
pub fn show_bytes(bytes: &[u8]) -> String {
    crate::protocol::ascii::show_bytes(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_encodes_to_its_canonical_text_and_a_cr() {
        assert_eq!(
            encode_line("1mr1000", None).map_err(|e| e.to_string()),
            Ok(b"1MR1000\r".to_vec())
        );
        assert_eq!(show_bytes(b"1TP\r\x1b"), "1TP\\r\\x1B");
        assert!(encode_line("1MR1000", Some(3)).is_err());
        assert!(encode_line("1XX", None).is_err());
    }

    mod properties {
        use super::*;
        use crate::protocol::mccl::machine::DEFAULT_MACHINE;
        use proptest::prelude::*;

        const CONTEXT: CheckContext = CheckContext {
            machine: &DEFAULT_MACHINE,
            profile: &LinkProfile::MANUAL,
        };

        /// One command as a technician might type it.
        fn command() -> impl Strategy<Value = String> {
            let mnemonic =
                proptest::sample::select(COMMANDS.iter().map(|c| c.mnemonic).collect::<Vec<_>>());
            let axis = proptest::option::of(0u8..10);
            let value = prop_oneof![
                Just(String::new()),
                (-100_000i64..100_000).prop_map(|n| n.to_string()),
                (-1000.0f64..1000.0).prop_map(|v| format!("{v:.3}")),
                (0u32..1200).prop_map(|r| format!("@{r}")),
                "[A-Za-z0-9 %,;.]{0,8}".prop_map(|s| format!("\"{s}\"")),
            ];
            (axis, mnemonic, value, any::<bool>()).prop_map(|(axis, m, v, lower)| {
                let m = if lower {
                    m.to_ascii_lowercase()
                } else {
                    m.to_string()
                };
                format!("{}{m}{v}", axis.map_or(String::new(), |a| a.to_string()))
            })
        }

        proptest! {
            #[test]
            fn parsing_and_checking_never_panic(text in "\\PC{0,60}") {
                for base in [NumberBase::Decimal, NumberBase::Hex] {
                    let _ = check_text(&text, base, &CONTEXT);
                }
                let _ = encode_line(&text, None);
            }

            #[test]
            fn mccl_soup_never_panics(text in "[0-9A-Za-z@\",.;\\- ТВКо]{0,40}") {
                let _ = check_text(&text, NumberBase::Decimal, &CONTEXT);
            }

            #[test]
            fn what_parses_formats_to_text_that_parses_the_same(
                commands in proptest::collection::vec(command(), 1..6),
                spaced in any::<bool>(),
            ) {
                let text = commands.join(if spaced { ", " } else { "," });
                if let Ok(line) = parse_line(&text, NumberBase::Decimal) {
                    let canonical = line.to_string();
                    let again = parse_line(&canonical, NumberBase::Decimal);
                    prop_assert_eq!(again.as_ref(), Ok(&line));
                    prop_assert_eq!(again.map(|l| l.to_string()), Ok(canonical));
                }
            }

            #[test]
            fn every_generated_command_parses(c in command()) {
                // Strings may hold commas and semicolons; numbers are numbers.
                prop_assert!(parse_line(&c, NumberBase::Decimal).is_ok(), "{}", c);
            }
        }
    }
}
