//! The A-Script interpreter (§2.7, §5): runs the compiled steps of the
//! loaded source ([`crate::protocol::cmd4cr::ascript::compile`]) in the
//! four program threads and the GS thread, on the motion engine's ticks.
//!
//! A statement that acts is carried out as the ASCII command of the same
//! meaning ([`ascii_equivalent`], the translation the host-side runner
//! uses too), through the same command execution as the wire, so a program
//! and a host sending the same commands get the same result. Variables,
//! control flow, `DELAY` and `WAIT[axis]` are the interpreter's own.
//!
//! Choices where the manual is silent (digest §5, §8.3):
//! - Every running thread executes one step per 100 µs tick, in the order
//!   PRG0, PRG1, PRG2, PRG3, GS; a `DELAY` or `WAIT` holds only its thread.
//! - A runtime error is: a command answered with an error, except
//!   `?Error Moving` for an axis that is merely busy (a program re-issuing
//!   a move in a loop, as Ex 7 does, must not fail); a `WAIT[axis]` whose
//!   axis stopped with a new error flag (limit, alarm, EMG); a division by
//!   zero or negative shift; a GOSUB to a subroutine that is not there.
//! - On a runtime error the thread runs SUB 31 if the source has one
//!   (§2.7.5); on its ENDSUB, `SAP`=0 goes back to the step that failed
//!   ("the last executed line"), `SAP`=1 to the first step of the program.
//!   An error inside SUB 31, or without one, stops the thread in the error
//!   state (SASTAT 4).

use std::time::Duration;

use crate::protocol::cmd4cr::ascript::{
    Action, CompileError, Op, Operand, Statement, ascii_equivalent, buffered_move, compile,
};
use crate::protocol::cmd4cr::{Axis, Cmd4crCommand, ErrorCode, parse_command};

use super::Cmd4cr;
use super::motion::TICK;
use super::motion::axis::mst;
use super::programs::{Handler, PROGRAM_SLOTS, ProgramStatus, Wait};
use super::wire::Value;

/// What a step did to its thread.
enum Next {
    /// Go on with this step.
    Goto(usize),
    /// Hold at this step with a wait.
    Hold(Wait),
    /// The thread ended (END, or the GS subroutine returned).
    Finished,
    /// A runtime error at this step.
    Fail(String),
}

impl Cmd4cr {
    /// Compile A-Script `source` and load it: its PRG blocks become the
    /// programs of SASTAT/SACTRL, its SUB blocks what GOSUB and GS call.
    /// Every thread stops. The source is kept in the flash (programs live
    /// there, §2.7.7).
    pub fn load_program(&mut self, source: &str) -> Result<(), Vec<CompileError>> {
        let program = compile(source)?;
        self.programs.load(program);
        self.flash.set_program(Some(source.to_string()));
        Ok(())
    }

    /// One step of every running thread.
    pub(super) fn run_threads(&mut self) {
        for n in 0..=PROGRAM_SLOTS {
            self.step_thread(n);
        }
    }

    fn step_thread(&mut self, n: usize) {
        let Some(source) = self.programs.source.clone() else {
            return;
        };
        let Some(thread) = self.programs.threads.get(n) else {
            return;
        };
        if thread.status != ProgramStatus::Running {
            return;
        }
        let pc = thread.pc;
        let next = match thread.wait {
            Some(wait) => self.waiting(wait, pc),
            None => match source.step(pc) {
                None => Next::Finished,
                Some(step) => match &step.op {
                    Op::Action(action) => self.perform(action, pc),
                    Op::JumpUnless { condition, to } => {
                        match condition.evaluate(&mut |o| self.operand(o)) {
                            Ok(true) => Next::Goto(pc + 1),
                            Ok(false) => Next::Goto(*to),
                            Err(e) => Next::Fail(format!("line {}: {e}", step.line)),
                        }
                    }
                    Op::Jump { to } => Next::Goto(*to),
                    Op::Call { sub } => match source.subroutine(*sub) {
                        Some(entry) => {
                            if let Some(t) = self.programs.threads.get_mut(n) {
                                t.stack.push(pc + 1);
                            }
                            Next::Goto(entry.start)
                        }
                        None => Next::Fail(format!(
                            "line {}: GOSUB {sub}: subroutine {sub} is not defined",
                            step.line
                        )),
                    },
                    Op::Return => self.return_from(n),
                    Op::End => Next::Finished,
                },
            },
        };
        let line = source.step(pc).map_or(0, |s| s.line);
        let handler = source.error_handler().map(|e| e.start);
        let Some(thread) = self.programs.threads.get_mut(n) else {
            return;
        };
        // A step may have stopped or restarted its own thread (SR).
        if thread.status != ProgramStatus::Running || thread.pc != pc {
            return;
        }
        match next {
            Next::Goto(to) => {
                thread.pc = to;
                thread.wait = None;
            }
            Next::Hold(wait) => thread.wait = Some(wait),
            Next::Finished => {
                thread.status = ProgramStatus::Idle;
                thread.wait = None;
            }
            Next::Fail(reason) => match (handler, thread.handler) {
                (Some(start), None) => {
                    thread.handler = Some(Handler {
                        failed_step: pc,
                        depth: thread.stack.len(),
                    });
                    thread.wait = None;
                    thread.pc = start;
                }
                _ => {
                    thread.status = ProgramStatus::Error;
                    thread.wait = None;
                    thread.fault = Some(if reason.starts_with("line") {
                        reason
                    } else {
                        format!("line {line}: {reason}")
                    });
                }
            },
        }
    }

    /// A thread held by DELAY or WAIT, one tick later.
    fn waiting(&self, wait: Wait, pc: usize) -> Next {
        match wait {
            Wait::Delay(left) => {
                let left = left.saturating_sub(TICK);
                if left.is_zero() {
                    Next::Goto(pc + 1)
                } else {
                    Next::Hold(Wait::Delay(left))
                }
            }
            Wait::Axis {
                axis,
                errors_before,
            } => {
                if self.motion.is_busy(axis) {
                    return Next::Hold(wait);
                }
                let errors = self.motion.axis(axis).errors() & mst::BLOCKING_ERRORS;
                if errors & !errors_before != 0 {
                    Next::Fail(format!(
                        "WAIT{}: the axis stopped with an error (MST {})",
                        axis.letter(),
                        self.motion.status(axis)
                    ))
                } else {
                    Next::Goto(pc + 1)
                }
            }
        }
    }

    /// ENDSUB: back to the caller, or out of SUB 31 as SAP says.
    fn return_from(&mut self, n: usize) -> Next {
        let restart = self.sub31_return == 1;
        let Some(thread) = self.programs.threads.get_mut(n) else {
            return Next::Finished;
        };
        if let Some(handler) = thread.handler
            && thread.stack.len() == handler.depth
        {
            thread.handler = None;
            if restart {
                thread.stack.clear();
                return Next::Goto(thread.entry);
            }
            return Next::Goto(handler.failed_step);
        }
        match thread.stack.pop() {
            Some(to) => Next::Goto(to),
            // The end of a subroutine GS started.
            None => Next::Finished,
        }
    }

    /// Carry out an action.
    fn perform(&mut self, action: &Action, pc: usize) -> Next {
        let variables = self.variables;
        let text = match action {
            Action::Let { variable, value } => {
                return match value.evaluate(&mut |o| self.operand(o)) {
                    Ok(v) => {
                        if let Some(slot) = self.variables.get_mut(usize::from(*variable)) {
                            *slot = v;
                        }
                        Next::Goto(pc + 1)
                    }
                    Err(e) => Next::Fail(format!("V{variable}={value}: {e}")),
                };
            }
            Action::Delay(value) => {
                let ms = u64::try_from(value.resolve(&variables)).unwrap_or(0);
                return if ms == 0 {
                    Next::Goto(pc + 1)
                } else {
                    Next::Hold(Wait::Delay(Duration::from_millis(ms)))
                };
            }
            Action::Wait(axis) => {
                let Some(axis) = Axis::from_index(axis.index()) else {
                    return Next::Goto(pc + 1);
                };
                return Next::Hold(Wait::Axis {
                    axis,
                    errors_before: self.motion.axis(axis).errors() & mst::BLOCKING_ERRORS,
                });
            }
            // §2.3.4: in buffer mode a standalone XYZ move is queued at the
            // global high speed.
            Action::Move(targets) if self.motion.buffer_status().enabled => {
                match buffered_move(targets, i64::from(self.motion.global.hspd), &variables) {
                    Some(text) => text,
                    None => {
                        return Next::Fail(format!(
                            "{action}: a buffered move gives X, Y and Z targets (§2.3.4)"
                        ));
                    }
                }
            }
            _ => match ascii_equivalent(&Statement::Action(action.clone()), &variables) {
                Some(text) => text,
                None => return Next::Fail(format!("{action}: no command does this")),
            },
        };
        let reply = self.answer(&text);
        if !reply.starts_with('?') || self.merely_busy(&reply) {
            Next::Goto(pc + 1)
        } else {
            Next::Fail(format!("{action} ({text}) answered {reply}"))
        }
    }

    /// `?Error Moving` while no axis holds an error: the command found its
    /// axis busy, which a program does not count as an error.
    fn merely_busy(&self, reply: &str) -> bool {
        reply == ErrorCode::ErrorMoving.info().reply
            && Axis::ALL
                .iter()
                .all(|&a| self.motion.axis(a).errors() & mst::BLOCKING_ERRORS == 0)
    }

    /// The value of an operand: a number, a variable, or a readable
    /// command read as its ASCII twin (`MSTX`, `DI1`).
    fn operand(&self, operand: &Operand) -> Result<i32, String> {
        match *operand {
            Operand::Number(n) => Ok(n as i32),
            Operand::Variable(v) => Ok(self.variables.get(usize::from(v)).copied().unwrap_or(0)),
            Operand::Read(command) => {
                let text = command
                    .ascii()
                    .ok_or_else(|| format!("{command} cannot be read"))?;
                match parse_command(&text) {
                    Ok(Cmd4crCommand::Read { register, selector }) => {
                        match self.read(register, selector) {
                            // Registers are 32-bit (IO, V); wider values wrap.
                            Ok(Value::Int(v)) => Ok(v as i32),
                            _ => Err(format!("{command} has no single value")),
                        }
                    }
                    _ => Err(format!("{command} cannot be read")),
                }
            }
        }
    }
}
