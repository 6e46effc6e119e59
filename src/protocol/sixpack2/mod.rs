//! Trinamic SIXpack 2, a six-axis stepper controller (manual revision
//! 1.10): its 9-byte binary protocol over RS-232/RS-485. Pure code: bytes
//! and meanings, no I/O.
//!
//! A request is `ADDR CMD P0..P6` with no checksum, LSB first (§6.2, §7);
//! only the queries `$20 $21 $28 $30 $43 $44` and the service commands
//! answer, with `CMD P0..P6` (digest D1.4; [`ReplyFraming`] also offers
//! the address-first form). The instruction set is data
//! ([`catalog::COMMANDS`]); [`parse_line`] is the one parser of console
//! lines, mnemonics and pasted SQPack `SendToPack(…)` frames alike.

pub mod assist;
pub mod catalog;
pub mod caution;
pub mod command;
pub mod console;
pub mod frame;
pub mod io;
pub mod jog;
pub mod line;
pub mod macros;
pub mod parameter_set;
pub mod reply;
pub mod tool;
pub mod traffic;
pub mod units;
pub mod wire;

pub use catalog::{COMMANDS, CommandSpec, Field, FieldKind, MOTORS};
pub use command::{Command, RangeError};
pub use console::{FACTORY_BAUD, Sixpack2Console};
pub use frame::{REQUEST_LEN, Reply, ReplyFraming, Request, to_hex};
pub use line::{DEFAULT_ADDRESS, LineError, ParsedLine, canonical, parse_line, send_to_pack};
pub use reply::ReplyFields;
pub use wire::{Sixpack2Framer, Sixpack2ReplyRule, Sixpack2Wire};

/// The family entry for a console with its reply framing.
pub const fn family(console: &'static Sixpack2Console) -> crate::protocol::Family {
    crate::protocol::Family {
        name: "sixpack2",
        description: "Trinamic SIXpack 2 (6 axes), 9-byte binary frames without checksum",
        encode_line,
        show_bytes: to_hex,
        console,
    }
}

/// The family reading replies in either form (the default).
pub static FAMILY_AUTO: crate::protocol::Family = family(&Sixpack2Console::AUTO);
/// The family reading 8-byte replies only (§6.2.2.3 taken literally).
pub static FAMILY_CMD8: crate::protocol::Family = family(&Sixpack2Console::CMD8);
/// The family reading replies with the response address in front.
pub static FAMILY_ADDR9: crate::protocol::Family = family(&Sixpack2Console::ADDR9);

/// `axterm encode sixpack2 LINE`: the 9 bytes of a line for the unit at
/// `address` (a mnemonic line: the factory address 0 when `None`; a
/// frame keeps its own address byte, which must match one given).
pub fn encode_line(
    line: &str,
    address: Option<u8>,
) -> Result<Vec<u8>, crate::protocol::line_error::LineError> {
    Ok(parse_line(line, address)?.request.to_bytes().to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_gives_the_frame_or_names_the_operand() {
        assert_eq!(
            encode_line("StartRamp 0 10000", None)
                .map(|b| to_hex(&b))
                .map_err(|e| e.to_string()),
            Ok("00 23 00 10 27 00 00 00 00".into())
        );
        assert_eq!(
            encode_line("StartRamp 0 10000", Some(2))
                .map(|b| to_hex(&b))
                .map_err(|e| e.to_string()),
            Ok("02 23 00 10 27 00 00 00 00".into())
        );
        assert_eq!(
            encode_line("StartRamp 6 100", None).map_err(|e| e.to_string()),
            Err("StartRamp: motno 6 is outside 0..5 (Motor 1..6)".into())
        );
    }
}
