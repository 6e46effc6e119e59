//! Trinamic TMCL as spoken by the TMCM-1110 StepRocker (firmware V1.12
//! manual). Pure code: bytes and meanings, no I/O.

pub mod asm;
pub mod assist;
pub mod catalog;
pub mod command;
pub mod console;
pub mod frame;
pub mod hex;
pub mod io;
pub mod jog;
pub mod line;
pub mod parameter_set;
pub mod params;
pub mod plan;
pub mod tool;
pub mod traffic;
pub mod transfer;
pub mod tune;
pub mod tuning;
pub mod units;
pub mod validate;
pub mod wire;

pub use catalog::{COMMANDS, CommandInfo, command_by_opcode, find_command};
pub use command::{
    CalcFamily, CalcOp, ClearFlag, Command, Condition, EventMode, MoveMode, OperandCode, RfsAction,
    StatusQuery, VersionFormat, WaitCondition,
};
pub use console::TmclConsole;
pub use frame::{ChecksumError, FRAME_LEN, FrameAssembler, Reply, Request, Status, checksum};
pub use hex::to_hex;
pub use line::{
    ConstantValue, LineError, SymbolResolver, format_command, parse_constant, parse_line,
    parse_line_with, parse_number, parse_syntax,
};
pub use validate::validate;
pub use wire::{TmclReplyRule, TmclWire};

/// The TMCL family's entry (registered in [`crate::families`]).
pub static FAMILY: crate::protocol::Family = crate::protocol::Family {
    name: "tmcl",
    description: "Trinamic TMCL (TMCM-1110 StepRocker), 9-byte binary frames",
    encode_line: |line, address| {
        let command = parse_line(line)?;
        Ok(command
            .to_request(address.unwrap_or(DEFAULT_MODULE_ADDRESS))
            .to_bytes()
            .to_vec())
    },
    show_bytes: to_hex,
    console: &TmclConsole,
};

/// The module address every manual example uses and modules ship with (GP66).
pub const DEFAULT_MODULE_ADDRESS: u8 = 1;
