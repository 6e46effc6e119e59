//! Which instructions the simulated firmware knows and how it treats them in
//! direct mode. The instruction set itself is the protocol's catalogue
//! (`protocol::tmcl::catalog`, manual §3.4 Table 5, §3.5.7 Table 13,
//! §3.6.53 Table 14, §3.6.52); this module adds the simulator's decisions.

use crate::protocol::tmcl::catalog::{self, CommandInfo, Field, OperandKind, Presence, Usage};
use crate::protocol::tmcl::command::{GLOBAL_INTERRUPT, INTERRUPTS, opcode};

/// How the module treats an instruction that arrives over the interface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Executed in direct mode and storable in a program: motion,
    /// parameters, I/O, coordinates, and the calculation and interrupt set-up
    /// commands whose direct-mode reply the manual documents (§3.6.16–3.6.50).
    Direct,
    /// Program flow only (§3.5.3: "using them in direct mode does not make
    /// sense"). Storable; in direct mode answered with status 6 "command not
    /// available" and otherwise ignored.
    ProgramFlow,
    /// Control commands (§3.6.53), 138 (§3.6.52) and 255: direct mode only,
    /// executed even in download mode, never stored.
    Control,
}

/// Commands with no direct-mode meaning: the branch commands of §3.5.3
/// Table 8 ("using them in direct mode does not make sense"), COMP among
/// them — a direct-mode COMP would rewrite the condition flags of a running
/// program, which direct-mode commands must not disturb (§8.6) — and, the
/// simulator's choice, the program-flow extensions RST, DJNZ and CALL
/// (§3.5.7 Table 13).
const PROGRAM_FLOW: &[u8] = &[
    opcode::COMP,
    opcode::JC,
    opcode::JA,
    opcode::CSUB,
    opcode::RSUB,
    opcode::WAIT,
    opcode::STOP,
    opcode::RST,
    opcode::DJNZ,
    opcode::CALL,
];

/// Opcodes whose replies GP255 = 1 does not suppress (§5.1 Table 18).
pub(crate) const NEVER_SUPPRESSED: &[u8] = &[opcode::GAP, opcode::GGP, opcode::GIO];

/// The instruction with this opcode, if the firmware has it. The user
/// functions UF0–UF7 (§3.6.51) exist only in customer-specific firmware: a
/// standard module answers them like any unknown opcode.
pub(crate) fn command(opcode: u8) -> Option<&'static CommandInfo> {
    catalog::command_by_opcode(opcode).filter(|c| c.usage != Usage::UserDefined)
}

pub(crate) fn mode(info: &CommandInfo) -> Mode {
    if info.usage == Usage::DirectOnly {
        Mode::Control
    } else if PROGRAM_FLOW.contains(&info.opcode) {
        Mode::ProgramFlow
    } else {
        Mode::Direct
    }
}

/// Whether the type byte is one the instruction knows. Symbolic type
/// operands (ABS/REL/COORD, ADD..COMP, ZE..EPO, …) must be one of their
/// codes; interrupt numbers must be in §3.5.6.1 Table 12 (255, the global
/// switch, only for EI/DI); 129 accepts 0 and 1. Parameter, port,
/// coordinate and variable numbers are checked by the command's handler,
/// and "don't care" types are not checked.
pub(crate) fn type_accepted(info: &CommandInfo, kind: u8) -> bool {
    if matches!(info.opcode, opcode::EI | opcode::DI | opcode::VECT) {
        let global_allowed = info.opcode != opcode::VECT;
        return INTERRUPTS
            .iter()
            .any(|i| i.number == kind && (global_allowed || kind != GLOBAL_INTERRUPT));
    }
    info.operands.iter().all(|operand| {
        if let Presence::SetsType(code) = operand.presence {
            return kind == 0 || kind == code;
        }
        match (operand.field, operand.kind) {
            (Field::Type, OperandKind::Code(set)) => set.keyword_of(kind).is_some(),
            _ => true,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn accepts(opcode: u8, kind: u8) -> bool {
        command(opcode).is_some_and(|c| type_accepted(c, kind))
    }

    #[test]
    fn user_functions_and_gaps_are_unknown() {
        for opcode in (64..=71).chain([0, 16, 29, 47, 52, 81, 127, 139, 254]) {
            assert!(
                command(opcode).is_none(),
                "opcode {opcode} should be unknown"
            );
        }
        assert!(command(opcode::CALL).is_some());
    }

    #[test]
    fn modes_follow_the_manual_sections() {
        let mode_of = |op| command(op).map(mode);
        assert_eq!(mode_of(opcode::JA), Some(Mode::ProgramFlow));
        // §3.5.3 Table 8 lists COMP with the branch commands.
        assert_eq!(mode_of(opcode::COMP), Some(Mode::ProgramFlow));
        assert_eq!(mode_of(opcode::CALC), Some(Mode::Direct));
        assert_eq!(mode_of(opcode::CALCV), Some(Mode::Direct));
        assert_eq!(mode_of(opcode::ROR), Some(Mode::Direct));
        assert_eq!(mode_of(opcode::TARGET_REACHED_EVENT), Some(Mode::Control));
        assert_eq!(mode_of(opcode::SOFTWARE_RESET), Some(Mode::Control));
    }

    #[test]
    fn type_codes_come_from_the_catalogue() {
        assert!(accepts(opcode::CALCV, 11));
        assert!(!accepts(opcode::CALCV, 10));
        assert!(accepts(opcode::MVP, 2));
        assert!(!accepts(opcode::MVP, 3));
        assert!(accepts(opcode::RUN_APPLICATION, 1));
        assert!(!accepts(opcode::RUN_APPLICATION, 2));
        assert!(accepts(opcode::ROR, 200), "don't care");
        assert!(accepts(opcode::SAP, 200), "checked by the handler");
    }

    #[test]
    fn interrupt_numbers_come_from_table_12() {
        assert!(accepts(opcode::EI, 255));
        assert!(accepts(opcode::EI, 44));
        assert!(!accepts(opcode::EI, 4));
        assert!(accepts(opcode::VECT, 3));
        assert!(!accepts(opcode::VECT, 255));
    }
}
