//! The TMCL interpreter: executes the stored program on virtual time,
//! interleaved with the axis, timers and inputs (manual §3.5, §3.6.16–3.6.50,
//! §3.6.53, §8).
//!
//! Execution model: the module is a single interpreter that needs
//! [`SimConfig::instruction_time`](super::SimConfig) per command (default
//! [`DEFAULT_INSTRUCTION_TIME`]). A command takes effect at the start of its
//! slot; the axis, timers and inputs run during the slot. Direct-mode
//! commands are answered as they arrive, between program commands (§8.6).
//! While a WAIT holds the program the module looks at its condition every
//! [`PROGRAM_POLL`], and exactly at the WAIT's end or timeout. So one
//! `advance(dt)` executes at most `dt / instruction_time` commands plus the
//! polls: a program that loops for ever never hangs it.
//!
//! Decisions where the manual is silent:
//! - Reading commands load A in a program (§3.5.5): GAP, GGP, GIO, GCO
//!   (not its EEPROM-copy form with motor 255), GIV and RFS STATUS. CCO only
//!   captures the position (its §3.6.26 internal function names no A). Every
//!   write to A, X or a CALCV* variable sets the zero flag from the value;
//!   COMP and the COMP types set the comparison and the zero flag.
//! - A command whose direct-mode form would answer an error (wrong type,
//!   motor ≠ 0, a value out of range, a read-only parameter) does nothing
//!   in a program, which goes on with the next command: there is no one to
//!   send the status to.
//! - Program errors stop the program (GP128 = 0) with the PC on the
//!   offending command, and [`ProgramFault`] tells which: an unknown opcode
//!   or an empty cell (a program that runs into erased memory), a jump,
//!   call, RST or DJNZ target outside 0..2047, and running past address
//!   2047. CSUB/CALL with a full stack (8, §3.6.20) and RSUB with an empty
//!   one are ignored as the manual says; RETI outside a handler too.
//! - DJNZ jumps while the decremented variable is not zero (its §3.6.43
//!   internal function; the description's "greater than zero" differs only
//!   for negative start values).
//! - WAIT (§3.6.22): TICKS waits value × 10 ms from its start; POS until the
//!   axis stands on its target in position mode (AP8 = 1, not moving, no
//!   reference search); REFSW while the home switch reads active (AP9);
//!   LIMSW while either limit switch does (AP10/AP11); RFS until no
//!   reference search runs. A condition that already holds ends the WAIT at
//!   once. A timeout sets ETO; a TICKS wait ending sets nothing. A negative
//!   value (or A < 0 with −1) counts as 0. POS..RFS with motor ≠ 0 do
//!   nothing.
//! - STOP leaves the PC on the STOP. 128 stops with the PC where it is; a
//!   WAIT it interrupts is executed afresh by 129 type 0.
//! - 130 executes one command at the next slot, then GP128 reads 0; a WAIT
//!   stepped into keeps GP128 at 2 until it ends. Interrupts are served only
//!   while running (129), never in single steps, so a step executes exactly
//!   the command at the PC.
//! - Interrupt entry (§3.5.6.2) saves A, X, the condition flags, the PC and
//!   a WAIT in progress, which goes on after RETI with its original end; the
//!   error flags are module state and are not saved. A handler starts with
//!   the interrupted registers. The subroutine stack depth at entry is
//!   restored by RETI.
//! - The program does not run while download mode is on (GP129 = 1).

use std::time::Duration;

use crate::protocol::tmcl::Request;
use crate::protocol::tmcl::command::{Condition, OperandCode, WaitCondition, opcode as op};

use super::Tmcm1110;
use super::commands::{self, Mode};
use super::execute::Caller;
use super::interrupts::{self, Source};
use super::motion::{self, AxisEvent, Switch};
use super::program::{
    ApplicationStatus, CALL_STACK_DEPTH, InterruptedContext, PROGRAM_MEMORY_SIZE, ProgramWord, Wait,
};

/// Time the simulated module needs per program command. The manual gives
/// no figure. The StepRocker keeps its program in EEPROM (status 101,
/// "loaded into TMCL program EEPROM"): fetching one 7-byte command over SPI
/// plus its interpretation is taken as 50 µs, 20 000 commands per second.
pub const DEFAULT_INSTRUCTION_TIME: Duration = Duration::from_micros(50);

/// The shortest instruction time the simulator accepts: bounds the work of
/// one `advance`.
pub const MIN_INSTRUCTION_TIME: Duration = Duration::from_micros(1);

/// How often a waiting program looks at its condition and the axis events
/// (the motion model's supervision tick).
pub const PROGRAM_POLL: Duration = motion::TICK;

/// One WAIT tick (§3.6.22: "one tick is 10 milliseconds").
pub const WAIT_TICK: Duration = Duration::from_millis(10);

/// Why the interpreter stopped a program on its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgramFault {
    /// The command at `address` has an opcode the module does not know (0
    /// is an empty cell).
    UnknownCommand { address: u16, opcode: u8 },
    /// The command at `address` jumps, calls or restarts at `target`,
    /// outside the program memory.
    TargetOutsideMemory { address: u16, target: i32 },
    /// The command at the last address was executed and did not jump.
    EndOfMemory,
}

impl std::fmt::Display for ProgramFault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            ProgramFault::UnknownCommand { address, opcode: 0 } => {
                write!(f, "program ran into empty memory at address {address}")
            }
            ProgramFault::UnknownCommand { address, opcode } => {
                write!(f, "unknown command {opcode} at address {address}")
            }
            ProgramFault::TargetOutsideMemory { address, target } => write!(
                f,
                "command at address {address} jumps to {target}, outside 0..{}",
                PROGRAM_MEMORY_SIZE - 1
            ),
            ProgramFault::EndOfMemory => write!(
                f,
                "program ran past the last address {}",
                PROGRAM_MEMORY_SIZE - 1
            ),
        }
    }
}

impl Tmcm1110 {
    /// Let `dt` of virtual time pass: axis, timers, inputs and the program,
    /// interleaved.
    pub(super) fn pass_time(&mut self, dt: Duration) {
        if dt.is_zero() {
            // Delivers what is due now (a 138 report of a move that started
            // on its target).
            self.run_axis(Duration::ZERO);
        }
        let mut remaining = dt;
        loop {
            self.program_instant();
            if remaining.is_zero() {
                break;
            }
            let step = self.next_step(remaining);
            self.run_axis(step);
            self.uptime = self.uptime.saturating_add(step);
            self.app.busy = self.app.busy.saturating_sub(step);
            remaining -= step;
        }
    }

    /// How far time may run before the interpreter must look again.
    fn next_step(&self, remaining: Duration) -> Duration {
        let mut step = remaining;
        if self.app.is_active() {
            let until = |at: Duration| at.saturating_sub(self.uptime);
            if self.app.busy.is_zero() {
                step = step.min(PROGRAM_POLL);
            } else {
                step = step.min(self.app.busy);
            }
            if let Some(deadline) = self.app.wait.and_then(|w| w.deadline) {
                step = step.min(until(deadline));
            }
            if let Some(due) = self.timers.next_due() {
                step = step.min(until(due));
            }
        }
        // Everything due now was handled by `program_instant`, so the step
        // is positive; the floor only guards the loop.
        step.max(Duration::from_nanos(1)).min(remaining)
    }

    /// Everything that happens at one instant: input edges, timers, the
    /// WAIT, an interrupt entry and at most one program command.
    fn program_instant(&mut self) {
        self.watch_inputs();
        for timer in self.timers.expired(self.uptime) {
            if let Some(number) = interrupts::interrupt_of(Source::Timer(timer)) {
                self.raise(number);
            }
        }
        self.check_wait();
        if !self.app.is_active() || !self.app.busy.is_zero() {
            return;
        }
        if self.app.status == ApplicationStatus::Running {
            self.enter_interrupt();
        }
        if self.app.wait.is_some() {
            return;
        }
        self.execute_instruction();
        self.app.busy = self.config.instruction_time.max(MIN_INSTRUCTION_TIME);
    }

    /// A source fired: a request if a program runs (see `interrupts.rs`).
    pub(super) fn raise(&mut self, number: u8) {
        if self.app.is_active() {
            self.app.interrupts.request(number);
        }
    }

    /// React to what the axis reported (interrupts 3, 15, 21, 27, 28; the
    /// deviation stop also sets EDV).
    pub(super) fn axis_interrupts(&mut self, event: AxisEvent) {
        let source = match event {
            AxisEvent::TargetReached => Source::TargetReached,
            AxisEvent::StallStop => Source::Stall,
            AxisEvent::DeviationStop => {
                self.app.errors.deviation = true;
                Source::Deviation
            }
            AxisEvent::SwitchChanged { switch, active } => {
                let source = match switch {
                    Switch::Left => Source::LeftSwitch,
                    Switch::Right => Source::RightSwitch,
                    Switch::Home => return,
                };
                let Some(number) = interrupts::interrupt_of(source) else {
                    return;
                };
                if interrupts::edge_fires(self.interrupt_parameter(number), active) {
                    self.raise(number);
                }
                return;
            }
            AxisEvent::LimitStop(_) | AxisEvent::ReferenceSearchDone => return,
        };
        if let Some(number) = interrupts::interrupt_of(source) {
            self.raise(number);
        }
    }

    /// Bank-3 parameter `number` (trigger settings, timer periods).
    fn interrupt_parameter(&self, number: u8) -> i32 {
        self.interrupt_config.get(&number).copied().unwrap_or(0)
    }

    /// Sample the general-purpose inputs and raise interrupts 39..44 on the
    /// configured edges.
    fn watch_inputs(&mut self) {
        let io_mode = self.global(super::GP_IO_MODE);
        for source in interrupts::INTERRUPT_SOURCES {
            let Source::Input { port } = source.source else {
                continue;
            };
            let Some(level) = self.io.input(port, io_mode) else {
                continue;
            };
            let Some(seen) = self.input_levels.get_mut(usize::from(port)) else {
                continue;
            };
            if *seen != level {
                *seen = level;
                if interrupts::edge_fires(self.interrupt_parameter(source.number), level) {
                    self.raise(source.number);
                }
            }
        }
    }

    /// The input levels as they are now (power-up: no edge yet).
    pub(super) fn sample_inputs(&mut self) {
        let io_mode = self.global(super::GP_IO_MODE);
        for (port, seen) in self.input_levels.iter_mut().enumerate() {
            *seen = u8::try_from(port)
                .ok()
                .and_then(|p| self.io.input(p, io_mode))
                .unwrap_or(false);
        }
    }

    // ---- interrupts ---------------------------------------------------

    /// Serve the highest-priority request (§3.5.6.2, §5.4).
    fn enter_interrupt(&mut self) {
        let Some((number, address)) = self.app.interrupts.next_request() else {
            return;
        };
        let app = &mut self.app;
        app.interrupts.pending.remove(&number);
        app.interrupts.handling = Some(InterruptedContext {
            number,
            registers: app.registers,
            pc: app.pc,
            wait: app.wait.take(),
            call_depth: app.call_stack.len(),
        });
        app.pc = address;
    }

    /// RETI (§3.6.35): back to what the handler interrupted.
    fn return_from_interrupt(&mut self) {
        match self.app.interrupts.handling.take() {
            Some(context) => {
                let app = &mut self.app;
                app.registers = context.registers;
                app.pc = context.pc;
                app.wait = context.wait;
                app.call_stack.truncate(context.call_depth);
            }
            None => self.next_command(),
        }
    }

    // ---- commands -------------------------------------------------------

    /// Execute the command at the PC.
    fn execute_instruction(&mut self) {
        let address = self.app.pc;
        let word = self
            .eeprom
            .image
            .program
            .get(usize::from(address))
            .copied()
            .unwrap_or_default();
        let known =
            commands::command(word.opcode).filter(|info| commands::mode(info) != Mode::Control);
        match known {
            None => self.fault(ProgramFault::UnknownCommand {
                address,
                opcode: word.opcode,
            }),
            // A type the command does not know: the command does nothing.
            Some(info) if !commands::type_accepted(info, word.kind) => self.next_command(),
            Some(info) if commands::mode(info) == Mode::ProgramFlow => self.flow(word),
            Some(_) => self.standalone(word),
        }
        if self.app.status == ApplicationStatus::Stepping && self.app.wait.is_none() {
            self.app.status = ApplicationStatus::Stopped;
        }
    }

    /// A command that also exists in direct mode, executed by the program.
    fn standalone(&mut self, word: ProgramWord) {
        match word.opcode {
            op::RETI => return self.return_from_interrupt(),
            // §3.6.49: A := var[X]; ignored when X is outside 0..255.
            op::GIV => {
                let index = usize::try_from(self.app.registers.x).ok();
                if let Some(&value) = index.and_then(|i| self.user_variables.get(i)) {
                    self.app.registers.load(value);
                }
                return self.next_command();
            }
            _ => {}
        }
        let request = Request {
            address: self.address(),
            command: word.opcode,
            kind: word.kind,
            motor_bank: word.motor_bank,
            value: word.value,
        };
        if let Ok(value) = self.perform(request, Caller::Program)
            && loads_accumulator(word)
        {
            self.app.registers.load(value);
        }
        self.next_command();
    }

    /// The program-flow commands of §3.5.3 Table 8 and §3.5.7 Table 13.
    fn flow(&mut self, word: ProgramWord) {
        let condition = || Condition::from_code(word.kind);
        match word.opcode {
            op::COMP => {
                let registers = &mut self.app.registers;
                registers.note_comparison(registers.accumulator, word.value);
                self.next_command();
            }
            op::JA => self.jump(word.value),
            op::JC => {
                if condition().is_some_and(|c| self.holds(c)) {
                    self.jump(word.value);
                } else {
                    self.next_command();
                }
            }
            op::CSUB => self.call(word.value),
            op::CALL => {
                if condition().is_some_and(|c| self.holds(c)) {
                    self.call(word.value);
                } else {
                    self.next_command();
                }
            }
            op::RSUB => match self.app.call_stack.pop() {
                Some(call_site) => {
                    self.app.pc = call_site;
                    self.next_command();
                }
                None => self.next_command(),
            },
            op::WAIT => self.start_wait(word),
            op::STOP => self.app.stop(),
            op::RST => {
                if let Some(address) = self.target(word.value) {
                    self.app.restart(address);
                }
            }
            op::DJNZ => {
                let Some(target) = self.target(word.value) else {
                    return;
                };
                let slot = &mut self.user_variables[usize::from(word.kind)];
                *slot = slot.wrapping_sub(1);
                if *slot != 0 {
                    self.app.pc = target;
                } else {
                    self.next_command();
                }
            }
            _ => self.next_command(),
        }
    }

    fn holds(&self, condition: Condition) -> bool {
        self.app.registers.holds(condition, &self.app.errors)
    }

    /// A program address from a command's value, or a fault.
    fn target(&mut self, value: i32) -> Option<u16> {
        let target = u16::try_from(value)
            .ok()
            .filter(|&a| usize::from(a) < PROGRAM_MEMORY_SIZE);
        if target.is_none() {
            self.fault(ProgramFault::TargetOutsideMemory {
                address: self.app.pc,
                target: value,
            });
        }
        target
    }

    fn jump(&mut self, value: i32) {
        if let Some(address) = self.target(value) {
            self.app.pc = address;
        }
    }

    /// CSUB / a CALL whose condition holds: ignored with a full stack.
    fn call(&mut self, value: i32) {
        let Some(address) = self.target(value) else {
            return;
        };
        if self.app.call_stack.len() >= CALL_STACK_DEPTH {
            return self.next_command();
        }
        self.app.call_stack.push(self.app.pc);
        self.app.pc = address;
    }

    /// On to the next address; past the last one the program stops.
    fn next_command(&mut self) {
        let next = usize::from(self.app.pc) + 1;
        match u16::try_from(next) {
            Ok(pc) if next < PROGRAM_MEMORY_SIZE => self.app.pc = pc,
            _ => self.fault(ProgramFault::EndOfMemory),
        }
    }

    fn fault(&mut self, fault: ProgramFault) {
        self.app.stop();
        self.program_fault = Some(fault);
    }

    // ---- WAIT -------------------------------------------------------------

    fn start_wait(&mut self, word: ProgramWord) {
        let Some(condition) = WaitCondition::from_code(word.kind) else {
            return self.next_command();
        };
        if condition != WaitCondition::Ticks && word.motor_bank != 0 {
            return self.next_command();
        }
        let ticks = if word.value == -1 {
            self.app.registers.accumulator
        } else {
            word.value
        };
        let ticks = u32::try_from(ticks).unwrap_or(0);
        let span = WAIT_TICK.saturating_mul(ticks);
        let deadline = (condition == WaitCondition::Ticks || ticks != 0)
            .then(|| self.uptime.saturating_add(span));
        self.app.wait = Some(Wait {
            condition,
            deadline,
        });
        self.check_wait();
    }

    /// End the WAIT if its condition holds or its time is up.
    fn check_wait(&mut self) {
        let Some(wait) = self.app.wait else {
            return;
        };
        let met = match wait.condition {
            WaitCondition::Ticks => false,
            WaitCondition::Pos => self.standing_on_target(),
            WaitCondition::RefSw => self.axis.switch(Switch::Home),
            WaitCondition::LimSw => {
                self.axis.switch(Switch::Left) || self.axis.switch(Switch::Right)
            }
            WaitCondition::Rfs => !self.axis.reference_search_active(),
        };
        let expired = wait.deadline.is_some_and(|d| self.uptime >= d);
        if !met && !expired {
            return;
        }
        if !met && wait.condition != WaitCondition::Ticks {
            self.app.errors.timeout = true;
        }
        self.app.wait = None;
        self.next_command();
        if self.app.status == ApplicationStatus::Stepping {
            self.app.status = ApplicationStatus::Stopped;
        }
    }

    /// WAIT POS: in position mode, on the target, at rest.
    fn standing_on_target(&self) -> bool {
        !self.axis.reference_search_active()
            && self.axis.param(AP_RAMP_MODE) != RAMP_VELOCITY
            && !self.axis.is_moving()
            && self.axis.param(AP_POSITION_REACHED) == 1
    }
}

const AP_POSITION_REACHED: u8 = 8;
const AP_RAMP_MODE: u8 = 138;
const RAMP_VELOCITY: i32 = 2;

/// Whether a successful command loads its reply value into A in a program.
fn loads_accumulator(word: ProgramWord) -> bool {
    match word.opcode {
        op::GAP | op::GGP | op::GIO => true,
        op::GCO => word.motor_bank != crate::protocol::tmcl::validate::COORDINATE_EEPROM,
        op::RFS => word.kind == crate::protocol::tmcl::RfsAction::Status.code(),
        _ => false,
    }
}

#[cfg(test)]
mod tests;
