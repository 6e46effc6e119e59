//! The standalone-program side of the module (manual §3.3, §3.5.5, §3.6.53,
//! GP128–130): program memory words, application status, program counter,
//! download pointer, the A and X registers and their flags, interrupt set-up.
//! Programs are not executed yet; the state is laid out so an interpreter can
//! step through `memory` from `pc` without restructuring.

use std::cmp::Ordering;

use crate::protocol::tmcl::command::{CalcOp, ClearFlag};

/// Program memory size in commands. The manual does not give it; a public
/// Trinamic TMCL interpreter header for another product uses 2048 (digest
/// D10.2), whose stack depth and coordinate count match this manual.
pub const PROGRAM_MEMORY_SIZE: usize = 2048;

/// Subroutine stack depth (§3.6.20, §8.5).
pub const CALL_STACK_DEPTH: usize = 8;

/// One stored command: the 7-byte binary form of §3.1 without address and
/// checksum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ProgramWord {
    pub opcode: u8,
    pub kind: u8,
    pub motor_bank: u8,
    pub value: i32,
}

impl ProgramWord {
    pub fn to_bytes(self) -> [u8; 7] {
        let v = self.value.to_be_bytes();
        [
            self.opcode,
            self.kind,
            self.motor_bank,
            v[0],
            v[1],
            v[2],
            v[3],
        ]
    }

    pub fn from_bytes(bytes: [u8; 7]) -> Self {
        let [opcode, kind, motor_bank, v3, v2, v1, v0] = bytes;
        ProgramWord {
            opcode,
            kind,
            motor_bank,
            value: i32::from_be_bytes([v3, v2, v1, v0]),
        }
    }

    /// An erased cell: all zeros (opcode 0 is not a TMCL command).
    pub fn is_empty(self) -> bool {
        self == ProgramWord::default()
    }
}

/// GP128 (§5.1 Table 18).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ApplicationStatus {
    Stopped = 0,
    Running = 1,
    Stepping = 2,
    Reset = 3,
}

/// Condition flags set by comparisons and assignments (§3.6.17, §3.6.18).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ConditionFlags {
    /// ZE/NZ: the last result written was zero.
    pub zero: bool,
    /// EQ/NE/GT/GE/LT/LE: the last comparison, left operand against right.
    pub comparison: Option<Ordering>,
}

/// Error flags tested by JC/CALL and cleared by CLE (§3.6.31).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ErrorFlags {
    pub timeout: bool,
    pub external_alarm: bool,
    pub deviation: bool,
    pub position: bool,
    pub shutdown: bool,
}

impl ErrorFlags {
    /// CLE (§3.6.31).
    pub fn clear(&mut self, flag: ClearFlag) {
        match flag {
            ClearFlag::All => *self = ErrorFlags::default(),
            ClearFlag::Eto => self.timeout = false,
            ClearFlag::Eal => self.external_alarm = false,
            ClearFlag::Edv => self.deviation = false,
            ClearFlag::Epo => self.position = false,
            ClearFlag::Esd => self.shutdown = false,
        }
    }
}

/// Interrupt set-up made by VECT, EI and DI (§3.5.6).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Interrupts {
    /// Handler address per interrupt number (VECT).
    pub vectors: std::collections::BTreeMap<u8, u16>,
    /// Interrupt numbers enabled with EI.
    pub enabled: std::collections::BTreeSet<u8>,
    /// EI 255 / DI 255.
    pub globally_enabled: bool,
}

/// The TMCL interpreter's state.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Application {
    pub status: ApplicationStatus,
    /// GP130: address of the command being executed.
    pub pc: u16,
    /// GP129: commands are being stored, not executed.
    pub downloading: bool,
    /// Next address a downloaded command is stored at (135 type 0).
    pub memory_pointer: u16,
    /// A program is held in a WAIT (135 types 0/1 "wait flag").
    pub waiting: bool,
    pub accumulator: i32,
    pub x: i32,
    pub flags: ConditionFlags,
    pub errors: ErrorFlags,
    pub call_stack: Vec<u16>,
    pub interrupts: Interrupts,
}

impl Default for Application {
    fn default() -> Self {
        Application {
            status: ApplicationStatus::Stopped,
            pc: 0,
            downloading: false,
            memory_pointer: 0,
            waiting: false,
            accumulator: 0,
            x: 0,
            flags: ConditionFlags::default(),
            errors: ErrorFlags::default(),
            call_stack: Vec::new(),
            interrupts: Interrupts::default(),
        }
    }
}

impl Application {
    /// Command 131 (§3.6.53): stop, PC and stack pointer to zero, A and X to
    /// zero, all flags cleared. GP128 then reads 3 "reset".
    pub fn reset(&mut self) {
        self.status = ApplicationStatus::Reset;
        self.pc = 0;
        self.waiting = false;
        self.accumulator = 0;
        self.x = 0;
        self.flags = ConditionFlags::default();
        self.errors = ErrorFlags::default();
        self.call_stack.clear();
    }

    /// Record a value written to A, X or a variable: the zero flag follows it
    /// (the §3.5.6.4 example jumps on NZ right after a GIO).
    pub fn note_result(&mut self, value: i32) {
        self.flags.zero = value == 0;
    }

    /// Record a comparison `left` against `right`.
    pub fn note_comparison(&mut self, left: i32, right: i32) {
        self.flags.comparison = Some(left.cmp(&right));
        self.flags.zero = left == right;
    }
}

/// `target op operand` for the CALC-family operations that produce a value
/// (§3.6.16, §3.6.28, §3.6.36–3.6.41; ADD..LOAD). NOT inverts the operand, as
/// CALCVV's "copy logical inverted <var2> to <var1>"; CALC and CALCV pass the
/// target as operand to invert it in place. 32-bit arithmetic wraps.
/// Division or modulo by zero leaves the target unchanged: the manual does
/// not say what the firmware does, and nothing may panic. SWAP and COMP
/// return `None`: they are not assignments.
pub fn calculate(op: CalcOp, target: i32, operand: i32) -> Option<i32> {
    Some(match op {
        CalcOp::Add => target.wrapping_add(operand),
        CalcOp::Sub => target.wrapping_sub(operand),
        CalcOp::Mul => target.wrapping_mul(operand),
        CalcOp::Div | CalcOp::Mod if operand == 0 => target,
        CalcOp::Div => target.wrapping_div(operand),
        CalcOp::Mod => target.wrapping_rem(operand),
        CalcOp::And => target & operand,
        CalcOp::Or => target | operand,
        CalcOp::Xor => target ^ operand,
        CalcOp::Not => !operand,
        CalcOp::Load => operand,
        CalcOp::Swap | CalcOp::Comp => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn program_words_round_trip_big_endian() {
        let word = ProgramWord {
            opcode: 4,
            kind: 1,
            motor_bank: 0,
            value: -10000,
        };
        assert_eq!(word.to_bytes(), [4, 1, 0, 0xFF, 0xFF, 0xD8, 0xF0]);
        assert_eq!(ProgramWord::from_bytes(word.to_bytes()), word);
        assert!(ProgramWord::default().is_empty());
    }

    #[test]
    fn calculations_wrap_and_invert_the_operand() {
        assert_eq!(calculate(CalcOp::Mul, 3, -5000), Some(-15000));
        assert_eq!(calculate(CalcOp::Not, 7, 0), Some(-1));
        assert_eq!(calculate(CalcOp::Sub, i32::MIN, 1), Some(i32::MAX));
        assert_eq!(calculate(CalcOp::Load, 1, 2), Some(2));
        assert_eq!(calculate(CalcOp::Swap, 1, 2), None);
        assert_eq!(calculate(CalcOp::Comp, 1, 2), None);
    }

    #[test]
    fn division_edge_cases_do_not_panic() {
        assert_eq!(calculate(CalcOp::Div, 10, 0), Some(10));
        assert_eq!(calculate(CalcOp::Mod, 10, 0), Some(10));
        assert_eq!(calculate(CalcOp::Div, i32::MIN, -1), Some(i32::MIN));
        assert_eq!(calculate(CalcOp::Mod, i32::MIN, -1), Some(0));
        assert_eq!(calculate(CalcOp::Div, -7, 2), Some(-3));
    }

    #[test]
    fn cle_clears_one_flag_or_all() {
        let mut flags = ErrorFlags {
            timeout: true,
            deviation: true,
            ..ErrorFlags::default()
        };
        flags.clear(ClearFlag::Eto);
        assert!(!flags.timeout && flags.deviation);
        flags.clear(ClearFlag::All);
        assert_eq!(flags, ErrorFlags::default());
    }

    #[test]
    fn reset_clears_registers_and_reports_status_3() {
        let mut app = Application {
            accumulator: 5,
            x: 6,
            pc: 40,
            ..Application::default()
        };
        app.call_stack.push(3);
        app.errors.timeout = true;
        app.reset();
        assert_eq!(app.status as i32, 3);
        assert_eq!((app.accumulator, app.x, app.pc), (0, 0, 0));
        assert!(app.call_stack.is_empty());
        assert!(!app.errors.timeout);
    }
}
