//! Protocol knowledge of every controller family: frames, typed commands,
//! console line syntax, parameter tables. No I/O here.

pub mod ascii;
pub mod cmd4cr;
pub mod console;
pub mod mccl;
pub mod parameters;
pub mod program;
pub mod sixpack2;
pub mod tmcl;
pub mod wire;

use console::FamilyConsole;

/// One controller family as the command line knows it. A new family adds
/// one entry to [`FAMILIES`], its simulators included.
pub struct Family {
    /// Name on the command line (`axterm encode tmcl …`).
    pub name: &'static str,
    pub description: &'static str,
    /// Parse and validate a console line and return the bytes it becomes on
    /// the wire for a module at `address` (the family's default when `None`).
    pub encode_line: fn(line: &str, address: Option<u8>) -> Result<Vec<u8>, String>,
    /// Show bytes of this family the way a technician reads them.
    pub show_bytes: fn(bytes: &[u8]) -> String,
    /// What the session layer needs of the family: its wire format, how a
    /// line is sent and its answer read, emergency stop, status polling.
    pub console: &'static dyn FamilyConsole,
    /// The built-in simulators of controllers of this family (`--sim
    /// NAME`), in the order the connect screen offers them.
    pub simulators: &'static [crate::sim::SimKind],
}

/// Every protocol family axterm speaks.
pub const FAMILIES: &[Family] = &[
    Family {
        name: "tmcl",
        description: "Trinamic TMCL (TMCM-1110 StepRocker), 9-byte binary frames",
        encode_line: |line, address| {
            let command = tmcl::parse_line(line).map_err(|e| e.to_string())?;
            Ok(command
                .to_request(address.unwrap_or(tmcl::DEFAULT_MODULE_ADDRESS))
                .to_bytes()
                .to_vec())
        },
        show_bytes: tmcl::to_hex,
        console: &tmcl::TmclConsole,
        simulators: &[crate::sim::tmcm1110::KIND],
    },
    Family {
        name: "cmd4cr",
        description: "Nippon Pulse CMD-4CR (4 axes), ASCII lines @ID…CR",
        encode_line: cmd4cr::encode_line,
        show_bytes: cmd4cr::show_bytes,
        console: &cmd4cr::Cmd4crConsole,
        simulators: &[crate::sim::cmd4cr::KIND],
    },
    Family {
        name: "sixpack2",
        description: "Trinamic SIXpack 2 (6 axes), 9-byte binary frames without checksum",
        encode_line: sixpack2::encode_line,
        show_bytes: sixpack2::to_hex,
        console: &sixpack2::Sixpack2Console::AUTO,
        simulators: &[crate::sim::sixpack2::KIND],
    },
    Family {
        name: "mccl",
        description: "PMC MultiFlex MCCL (up to 8 axes), ASCII lines with echo and prompt",
        encode_line: mccl::encode_line,
        show_bytes: mccl::show_bytes,
        console: &mccl::MclConsole::DEFAULT,
        simulators: &[crate::sim::mccl::KIND_PCI, crate::sim::mccl::KIND_ETH],
    },
];

/// The family called `name` (case-insensitive).
pub fn find_family(name: &str) -> Option<&'static Family> {
    FAMILIES.iter().find(|f| f.name.eq_ignore_ascii_case(name))
}

/// Names of every family, for error messages.
pub fn family_names() -> String {
    FAMILIES
        .iter()
        .map(|f| f.name)
        .collect::<Vec<_>>()
        .join(", ")
}
