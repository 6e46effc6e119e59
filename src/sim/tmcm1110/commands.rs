//! The TMCL instruction set of the TMCM-1110 (manual §3.4 Table 5, §3.5.7
//! Table 13, §3.6.53 Table 14, §3.6.52) as data: which opcodes exist, which
//! type codes each accepts, and how the module treats each in direct mode.

/// How the module treats an instruction that arrives over the interface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Executed in direct mode and storable in a program (motion, parameters,
    /// I/O, coordinates, and the calculation/interrupt-setup commands whose
    /// direct-mode reply the manual documents).
    Direct,
    /// Program flow only (JA, JC, WAIT, …: §3.5.3 "using them in direct mode
    /// does not make sense"). Storable; in direct mode answered with status 6
    /// "command not available" and otherwise ignored.
    ProgramFlow,
    /// TMCL control commands (§3.6.53 Table 14), command 138 (§3.6.52) and the
    /// software reset: direct mode only, executed even in download mode,
    /// never stored.
    Control,
}

/// Which values the type byte may take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TypeField {
    /// "0 (don't care)" in the manual: not checked.
    DontCare,
    /// Type codes 0..=max.
    UpTo(u8),
    /// Exactly the listed codes.
    OneOf(&'static [u8]),
    /// A parameter number, port, coordinate or variable number: the command's
    /// handler checks it against its own table.
    Checked,
}

impl TypeField {
    pub(crate) fn accepts(self, kind: u8) -> bool {
        match self {
            TypeField::DontCare | TypeField::Checked => true,
            TypeField::UpTo(max) => kind <= max,
            TypeField::OneOf(codes) => codes.contains(&kind),
        }
    }
}

/// One TMCL instruction of this module.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct CommandSpec {
    pub opcode: u8,
    /// Mnemonic, or a short name for the control commands that have none.
    pub name: &'static str,
    pub mode: Mode,
    pub types: TypeField,
    /// Manual section.
    pub section: &'static str,
}

/// Interrupt numbers of §3.5.6.1 Table 12, plus 255 (global switch, EI/DI only).
pub(crate) const INTERRUPT_NUMBERS: &[u8] = &[0, 1, 2, 3, 15, 21, 27, 28, 39, 40, 41, 42, 43, 44];
const INTERRUPT_NUMBERS_AND_GLOBAL: &[u8] =
    &[0, 1, 2, 3, 15, 21, 27, 28, 39, 40, 41, 42, 43, 44, 255];

/// CALCV (§3.6.41) lists every operation but SWAP (10).
const CALCV_OPS: &[u8] = &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 11];

const fn spec(
    opcode: u8,
    name: &'static str,
    mode: Mode,
    types: TypeField,
    section: &'static str,
) -> CommandSpec {
    CommandSpec {
        opcode,
        name,
        mode,
        types,
        section,
    }
}

use Mode::{Control, Direct, ProgramFlow};
use TypeField::{Checked, DontCare, OneOf, UpTo};

/// Every instruction the TMCM-1110 firmware V1.12 knows. Opcodes missing here
/// (16–18, 29, 47, 52–54, 58–79 including the user functions UF0–UF7 of a
/// standard firmware, 81–127, 139–254) answer status 2 "invalid command".
pub(crate) const COMMANDS: &[CommandSpec] = &[
    spec(1, "ROR", Direct, DontCare, "§3.6.1"),
    spec(2, "ROL", Direct, DontCare, "§3.6.2"),
    spec(3, "MST", Direct, DontCare, "§3.6.3"),
    spec(4, "MVP", Direct, UpTo(2), "§3.6.4"),
    spec(5, "SAP", Direct, Checked, "§3.6.5"),
    spec(6, "GAP", Direct, Checked, "§3.6.6"),
    spec(7, "STAP", Direct, Checked, "§3.6.7"),
    spec(8, "RSAP", Direct, Checked, "§3.6.8"),
    spec(9, "SGP", Direct, Checked, "§3.6.9"),
    spec(10, "GGP", Direct, Checked, "§3.6.10"),
    spec(11, "STGP", Direct, Checked, "§3.6.11"),
    spec(12, "RSGP", Direct, Checked, "§3.6.12"),
    spec(13, "RFS", Direct, UpTo(2), "§3.6.13"),
    spec(14, "SIO", Direct, Checked, "§3.6.14"),
    spec(15, "GIO", Direct, Checked, "§3.6.15"),
    spec(19, "CALC", Direct, UpTo(9), "§3.6.16"),
    spec(20, "COMP", Direct, DontCare, "§3.6.17"),
    spec(21, "JC", ProgramFlow, UpTo(11), "§3.6.18"),
    spec(22, "JA", ProgramFlow, DontCare, "§3.6.19"),
    spec(23, "CSUB", ProgramFlow, DontCare, "§3.6.20"),
    spec(24, "RSUB", ProgramFlow, DontCare, "§3.6.21"),
    spec(
        25,
        "EI",
        Direct,
        OneOf(INTERRUPT_NUMBERS_AND_GLOBAL),
        "§3.6.32",
    ),
    spec(
        26,
        "DI",
        Direct,
        OneOf(INTERRUPT_NUMBERS_AND_GLOBAL),
        "§3.6.33",
    ),
    spec(27, "WAIT", ProgramFlow, UpTo(4), "§3.6.22"),
    spec(28, "STOP", ProgramFlow, DontCare, "§3.6.23"),
    spec(30, "SCO", Direct, Checked, "§3.6.24"),
    spec(31, "GCO", Direct, Checked, "§3.6.25"),
    spec(32, "CCO", Direct, Checked, "§3.6.26"),
    spec(33, "CALCX", Direct, UpTo(10), "§3.6.28"),
    spec(34, "AAP", Direct, Checked, "§3.6.29"),
    spec(35, "AGP", Direct, Checked, "§3.6.30"),
    spec(36, "CLE", Direct, UpTo(5), "§3.6.31"),
    spec(37, "VECT", Direct, OneOf(INTERRUPT_NUMBERS), "§3.6.34"),
    spec(38, "RETI", Direct, DontCare, "§3.6.35"),
    spec(39, "ACO", Direct, Checked, "§3.6.27"),
    spec(40, "CALCVV", Direct, UpTo(11), "§3.6.36"),
    spec(41, "CALCVA", Direct, UpTo(11), "§3.6.37"),
    spec(42, "CALCAV", Direct, UpTo(11), "§3.6.38"),
    spec(43, "CALCVX", Direct, UpTo(11), "§3.6.39"),
    spec(44, "CALCXV", Direct, UpTo(11), "§3.6.40"),
    spec(45, "CALCV", Direct, OneOf(CALCV_OPS), "§3.6.41"),
    spec(46, "MVPA", Direct, UpTo(2), "§3.6.45"),
    spec(48, "RST", ProgramFlow, DontCare, "§3.6.42"),
    spec(49, "DJNZ", ProgramFlow, DontCare, "§3.6.43"),
    spec(50, "ROLA", Direct, DontCare, "§3.6.46"),
    spec(51, "RORA", Direct, DontCare, "§3.6.47"),
    spec(55, "SIV", Direct, DontCare, "§3.6.48"),
    spec(56, "GIV", Direct, DontCare, "§3.6.49"),
    spec(57, "AIV", Direct, DontCare, "§3.6.50"),
    spec(80, "CALL", ProgramFlow, UpTo(11), "§3.6.44"),
    spec(128, "stop application", Control, DontCare, "§3.6.53"),
    spec(129, "run application", Control, UpTo(1), "§3.6.53"),
    spec(130, "step application", Control, DontCare, "§3.6.53"),
    spec(131, "reset application", Control, DontCare, "§3.6.53"),
    spec(132, "enter download mode", Control, DontCare, "§3.6.53"),
    spec(133, "exit download mode", Control, DontCare, "§3.6.53"),
    spec(134, "read program memory", Control, DontCare, "§3.6.53"),
    spec(135, "get application status", Control, UpTo(3), "§3.6.53"),
    spec(136, "get firmware version", Control, UpTo(1), "§3.6.53"),
    spec(
        137,
        "restore factory settings",
        Control,
        DontCare,
        "§3.6.53",
    ),
    spec(
        138,
        "request target position reached event",
        Control,
        UpTo(1),
        "§3.6.52",
    ),
    spec(255, "software reset", Control, DontCare, "§3.6.53"),
];

/// The instruction with this opcode, if the module has it.
pub(crate) fn command(opcode: u8) -> Option<&'static CommandSpec> {
    COMMANDS.iter().find(|c| c.opcode == opcode)
}

/// Opcodes whose replies GP255 = 1 does not suppress (§5.1 Table 18).
pub(crate) const NEVER_SUPPRESSED: &[u8] = &[op::GAP, op::GGP, op::GIO];

/// Opcode numbers the simulator refers to by name.
pub(crate) mod op {
    pub const ROR: u8 = 1;
    pub const ROL: u8 = 2;
    pub const MST: u8 = 3;
    pub const MVP: u8 = 4;
    pub const SAP: u8 = 5;
    pub const GAP: u8 = 6;
    pub const STAP: u8 = 7;
    pub const RSAP: u8 = 8;
    pub const SGP: u8 = 9;
    pub const GGP: u8 = 10;
    pub const STGP: u8 = 11;
    pub const RSGP: u8 = 12;
    pub const RFS: u8 = 13;
    pub const SIO: u8 = 14;
    pub const GIO: u8 = 15;
    pub const CALC: u8 = 19;
    pub const COMP: u8 = 20;
    pub const EI: u8 = 25;
    pub const DI: u8 = 26;
    pub const SCO: u8 = 30;
    pub const GCO: u8 = 31;
    pub const CCO: u8 = 32;
    pub const CALCX: u8 = 33;
    pub const AAP: u8 = 34;
    pub const AGP: u8 = 35;
    pub const CLE: u8 = 36;
    pub const VECT: u8 = 37;
    pub const RETI: u8 = 38;
    pub const ACO: u8 = 39;
    pub const CALCVV: u8 = 40;
    pub const CALCVA: u8 = 41;
    pub const CALCAV: u8 = 42;
    pub const CALCVX: u8 = 43;
    pub const CALCXV: u8 = 44;
    pub const CALCV: u8 = 45;
    pub const MVPA: u8 = 46;
    pub const ROLA: u8 = 50;
    pub const RORA: u8 = 51;
    pub const SIV: u8 = 55;
    pub const GIV: u8 = 56;
    pub const AIV: u8 = 57;
    pub const STOP_APPLICATION: u8 = 128;
    pub const RUN_APPLICATION: u8 = 129;
    pub const STEP_APPLICATION: u8 = 130;
    pub const RESET_APPLICATION: u8 = 131;
    pub const ENTER_DOWNLOAD: u8 = 132;
    pub const EXIT_DOWNLOAD: u8 = 133;
    pub const READ_PROGRAM: u8 = 134;
    pub const APPLICATION_STATUS: u8 = 135;
    pub const FIRMWARE_VERSION: u8 = 136;
    pub const FACTORY_RESET: u8 = 137;
    pub const TARGET_REACHED_EVENT: u8 = 138;
    pub const SOFTWARE_RESET: u8 = 255;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn opcodes_are_unique_and_named_constants_exist_in_the_table() {
        for (i, a) in COMMANDS.iter().enumerate() {
            assert!(
                COMMANDS[i + 1..].iter().all(|b| b.opcode != a.opcode),
                "opcode {} listed twice",
                a.opcode
            );
        }
        for opcode in [op::ROR, op::CALCV, op::AIV, op::TARGET_REACHED_EVENT, 255] {
            assert!(command(opcode).is_some(), "opcode {opcode} missing");
        }
    }

    #[test]
    fn user_functions_and_gaps_are_unknown() {
        for opcode in (64..=71).chain([0, 16, 29, 47, 52, 81, 127, 139, 254]) {
            assert!(
                command(opcode).is_none(),
                "opcode {opcode} should be unknown"
            );
        }
    }

    #[test]
    fn type_fields_accept_what_the_manual_lists() {
        let calcv = command(op::CALCV).map(|c| c.types);
        assert_eq!(calcv.map(|t| t.accepts(11)), Some(true));
        assert_eq!(calcv.map(|t| t.accepts(10)), Some(false));
        let mvp = command(op::MVP).map(|c| c.types);
        assert_eq!(mvp.map(|t| t.accepts(2)), Some(true));
        assert_eq!(mvp.map(|t| t.accepts(3)), Some(false));
        assert!(TypeField::DontCare.accepts(200));
    }
}
