//! The standalone-program side of the module (manual §3.3, §3.5.5, §3.6.53,
//! GP128–130): program memory words, application status, program counter,
//! download pointer, the A and X registers and their flags, interrupt set-up.
//! The interpreter that executes it is `interpreter.rs`.

use std::cmp::Ordering;
use std::collections::{BTreeMap, BTreeSet};
use std::time::Duration;

use crate::protocol::tmcl::command::{
    CalcOp, ClearFlag, Condition, GLOBAL_INTERRUPT, WaitCondition,
};

/// Program memory size in commands and the stored word: the protocol's
/// (the manual does not give the size; digest D10.2 takes 2048 from a
/// public Trinamic interpreter header whose stack depth and coordinate
/// count match this manual).
pub use crate::protocol::tmcl::asm::{PROGRAM_MEMORY_WORDS as PROGRAM_MEMORY_SIZE, ProgramWord};

/// Subroutine stack depth (§3.6.20, §8.5).
pub const CALL_STACK_DEPTH: usize = 8;

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
    /// `None` after a reset: then none of the six conditions holds.
    pub comparison: Option<Ordering>,
}

/// Error flags tested by JC/CALL and cleared by CLE (§3.6.31). They belong
/// to the module, not to a register set: a WAIT timeout sets ETO, an
/// encoder deviation stop sets EDV, and a CLE from the host clears them as
/// one from the program does.
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

/// The calculation registers (§3.5.5): accumulator, X register and the
/// condition flags. The program has one set; the host's direct-mode
/// calculations have their own (see `execute.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Registers {
    pub accumulator: i32,
    pub x: i32,
    pub flags: ConditionFlags,
}

impl Registers {
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

    /// Load A with a value a command read (§3.5.5).
    pub fn load(&mut self, value: i32) {
        self.accumulator = value;
        self.note_result(value);
    }

    /// Whether a JC/CALL condition holds (§3.6.18, §3.6.44). ZE/NZ test the
    /// zero flag that assignments and comparisons set; EQ..LE test the last
    /// comparison only, so a calculation between a COMP and its jumps keeps
    /// them (the §3.6.44 example calls RunLeft, which multiplies A by −1,
    /// between `CALL LT` and `CALL GT` on the same COMP). The error
    /// conditions read the module's error flags.
    pub fn holds(&self, condition: Condition, errors: &ErrorFlags) -> bool {
        let ordering = self.flags.comparison;
        match condition {
            Condition::Ze => self.flags.zero,
            Condition::Nz => !self.flags.zero,
            Condition::Eq => ordering == Some(Ordering::Equal),
            Condition::Ne => ordering.is_some_and(Ordering::is_ne),
            Condition::Gt => ordering == Some(Ordering::Greater),
            Condition::Ge => ordering.is_some_and(Ordering::is_ge),
            Condition::Lt => ordering == Some(Ordering::Less),
            Condition::Le => ordering.is_some_and(Ordering::is_le),
            Condition::Eto => errors.timeout,
            Condition::Eal => errors.external_alarm,
            Condition::Edv => errors.deviation,
            Condition::Epo => errors.position,
        }
    }
}

/// What a WAIT holds the program for (§3.6.22).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Wait {
    pub condition: WaitCondition,
    /// Virtual time since power-up when the wait ends: the end of a TICKS
    /// wait, the timeout of the others (`None`: no timeout).
    pub deadline: Option<Duration>,
}

/// What an interrupt handler interrupted (§3.5.6.2): restored by RETI.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InterruptedContext {
    /// The interrupt being handled.
    pub number: u8,
    pub registers: Registers,
    /// The address the program continues at.
    pub pc: u16,
    /// A WAIT the program was held in; it goes on waiting after RETI.
    pub wait: Option<Wait>,
    /// Subroutine stack depth at entry: RETI drops what the handler left.
    pub call_depth: usize,
}

/// Interrupt set-up made by VECT, EI and DI, and the requests waiting for
/// their handlers (§3.5.6).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Interrupts {
    /// Handler address per interrupt number (VECT).
    pub vectors: BTreeMap<u8, u16>,
    /// Interrupt numbers enabled with EI.
    pub enabled: BTreeSet<u8>,
    /// EI 255 / DI 255.
    pub globally_enabled: bool,
    /// Requests not yet handled, at most one per source; the lowest number
    /// is served first (§5.4: lower number, higher priority).
    pub pending: BTreeSet<u8>,
    /// The handler running now, if any (§3.5.6.2: no nesting).
    pub handling: Option<InterruptedContext>,
}

impl Interrupts {
    /// A source fired: remember it if it is enabled and has a vector.
    pub fn request(&mut self, number: u8) {
        if self.enabled.contains(&number) && self.vectors.contains_key(&number) {
            self.pending.insert(number);
        }
    }

    /// EI n / DI n (255 = the global switch). Disabling a source drops its
    /// request.
    pub fn enable(&mut self, number: u8, on: bool) {
        if number == GLOBAL_INTERRUPT {
            self.globally_enabled = on;
        } else if on {
            self.enabled.insert(number);
        } else {
            self.enabled.remove(&number);
            self.pending.remove(&number);
        }
    }

    /// The request to serve now: interrupts on, no handler running, the
    /// lowest pending number.
    pub fn next_request(&self) -> Option<(u8, u16)> {
        if !self.globally_enabled || self.handling.is_some() {
            return None;
        }
        self.pending
            .iter()
            .find_map(|n| self.vectors.get(n).map(|&address| (*n, address)))
    }
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
    /// The WAIT holding the program (135 types 0/1 "wait flag").
    pub wait: Option<Wait>,
    /// The program's registers.
    pub registers: Registers,
    pub errors: ErrorFlags,
    pub call_stack: Vec<u16>,
    pub interrupts: Interrupts,
    /// Time until the interpreter is ready for its next command.
    pub busy: Duration,
}

impl Default for Application {
    fn default() -> Self {
        Application {
            status: ApplicationStatus::Stopped,
            pc: 0,
            downloading: false,
            memory_pointer: 0,
            wait: None,
            registers: Registers::default(),
            errors: ErrorFlags::default(),
            call_stack: Vec::new(),
            interrupts: Interrupts::default(),
            busy: Duration::ZERO,
        }
    }
}

impl Application {
    /// Command 131 (§3.6.53): stop, PC and stack pointer to zero, A and X to
    /// zero, all flags cleared. GP128 then reads 3 "reset". The simulator
    /// also forgets the interrupt set-up (vectors, enables, requests,
    /// a handler in progress): the manual does not say, and a program
    /// downloaded after a reset must not inherit handlers pointing into the
    /// old one.
    pub fn reset(&mut self) {
        self.status = ApplicationStatus::Reset;
        self.pc = 0;
        self.wait = None;
        self.registers = Registers::default();
        self.errors = ErrorFlags::default();
        self.call_stack.clear();
        self.interrupts = Interrupts::default();
        self.busy = Duration::ZERO;
    }

    /// RST (§3.6.42): "the subroutine stack, the interrupt stack and the
    /// registers are cleared", then the program goes on at `address`.
    /// Vectors, enables and waiting requests stay: the program restarts, the
    /// set-up it made is still valid.
    pub fn restart(&mut self, address: u16) {
        self.pc = address;
        self.wait = None;
        self.registers = Registers::default();
        self.errors = ErrorFlags::default();
        self.call_stack.clear();
        self.interrupts.handling = None;
    }

    /// 129 type 1: start afresh at `address` (§8.6: a host calls a routine
    /// through a jump table). The subroutine stack and a handler in progress
    /// are dropped, as a new start leaves nothing to return to; the registers
    /// stay.
    pub fn run_from(&mut self, address: u16) {
        self.pc = address;
        self.wait = None;
        self.call_stack.clear();
        self.interrupts.handling = None;
    }

    /// True while the interpreter executes commands (run or single step).
    pub fn is_active(&self) -> bool {
        !self.downloading
            && matches!(
                self.status,
                ApplicationStatus::Running | ApplicationStatus::Stepping
            )
    }

    /// The program stops (128, STOP, a program error): a WAIT is abandoned
    /// (129 executes it afresh) and waiting interrupt requests are dropped.
    pub fn stop(&mut self) {
        self.status = ApplicationStatus::Stopped;
        self.wait = None;
        self.interrupts.pending.clear();
        self.busy = Duration::ZERO;
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
    use crate::protocol::tmcl::command::OperandCode;

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
    fn reset_clears_registers_interrupts_and_reports_status_3() {
        let mut app = Application {
            registers: Registers {
                accumulator: 5,
                x: 6,
                ..Registers::default()
            },
            pc: 40,
            ..Application::default()
        };
        app.call_stack.push(3);
        app.errors.timeout = true;
        app.interrupts.vectors.insert(0, 9);
        app.interrupts.enable(0, true);
        app.reset();
        assert_eq!(app.status as i32, 3);
        assert_eq!(
            (app.registers.accumulator, app.registers.x, app.pc),
            (0, 0, 0)
        );
        assert!(app.call_stack.is_empty());
        assert!(!app.errors.timeout);
        assert!(app.interrupts.vectors.is_empty());
    }

    #[test]
    fn restart_keeps_the_interrupt_set_up() {
        let mut app = Application::default();
        app.interrupts.vectors.insert(0, 9);
        app.interrupts.enable(0, true);
        app.interrupts.handling = Some(InterruptedContext {
            number: 0,
            registers: Registers::default(),
            pc: 3,
            wait: None,
            call_depth: 0,
        });
        app.registers.accumulator = 7;
        app.call_stack.push(1);
        app.restart(12);
        assert_eq!(app.pc, 12);
        assert_eq!(app.registers, Registers::default());
        assert!(app.call_stack.is_empty());
        assert!(app.interrupts.handling.is_none());
        assert_eq!(app.interrupts.vectors.get(&0), Some(&9));
        assert!(app.interrupts.enabled.contains(&0));
    }

    #[test]
    fn conditions_read_zero_flag_comparison_and_errors() {
        let mut registers = Registers::default();
        let errors = ErrorFlags::default();
        let holding = |r: &Registers, e: &ErrorFlags| -> Vec<Condition> {
            Condition::ALL
                .iter()
                .copied()
                .filter(|c| r.holds(*c, e))
                .collect()
        };
        // After a reset no comparison exists: only NZ holds.
        assert_eq!(holding(&registers, &errors), [Condition::Nz]);
        registers.note_comparison(3, 5);
        assert_eq!(
            holding(&registers, &errors),
            [Condition::Nz, Condition::Ne, Condition::Lt, Condition::Le]
        );
        // An assignment moves the zero flag only.
        registers.load(0);
        assert_eq!(
            holding(&registers, &errors),
            [Condition::Ze, Condition::Ne, Condition::Lt, Condition::Le]
        );
        registers.note_comparison(5, 5);
        assert_eq!(
            holding(&registers, &errors),
            [Condition::Ze, Condition::Eq, Condition::Ge, Condition::Le]
        );
        registers.note_comparison(6, 5);
        let errors = ErrorFlags {
            timeout: true,
            external_alarm: true,
            deviation: true,
            position: true,
            shutdown: false,
        };
        assert_eq!(
            holding(&registers, &errors),
            [
                Condition::Nz,
                Condition::Ne,
                Condition::Gt,
                Condition::Ge,
                Condition::Eto,
                Condition::Eal,
                Condition::Edv,
                Condition::Epo
            ]
        );
    }

    #[test]
    fn requests_need_enable_and_vector_and_are_served_lowest_first() {
        let mut interrupts = Interrupts::default();
        interrupts.request(3);
        assert!(interrupts.pending.is_empty(), "not enabled");
        interrupts.enable(3, true);
        interrupts.request(3);
        assert!(interrupts.pending.is_empty(), "no vector");
        for (number, address) in [(3, 30), (0, 10), (39, 40)] {
            interrupts.vectors.insert(number, address);
            interrupts.enable(number, true);
            interrupts.request(number);
        }
        assert_eq!(interrupts.next_request(), None, "globally disabled");
        interrupts.enable(GLOBAL_INTERRUPT, true);
        assert_eq!(interrupts.next_request(), Some((0, 10)));
        interrupts.enable(0, false);
        assert_eq!(
            interrupts.next_request(),
            Some((3, 30)),
            "DI drops the request"
        );
        interrupts.handling = Some(InterruptedContext {
            number: 3,
            registers: Registers::default(),
            pc: 0,
            wait: None,
            call_depth: 0,
        });
        assert_eq!(interrupts.next_request(), None, "no nesting");
    }
}
