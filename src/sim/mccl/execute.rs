//! Executing one command: the checks every command goes through (is it
//! simulated, may a task run it, which axis, is its parameter right), the
//! dispatch to the group that does it, and the flow commands of Ch10 and
//! Ch12 (conditionals, jumps, repeat, waits, macros, tasks).

use std::sync::Arc;

use super::Mccl;
use super::axis::CaptureKind;
use super::commands::{AxisUse, CommandSpec, Group, ParamKind};
use super::errors::Code;
use super::interpreter::{Flow, Interpreter, Wait};
use super::lexer::{Command, Param};
use super::program::{self, Origin, Program};
use super::values::{Value, precision_digits};

/// The axes a command acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// A command without an axis; the axis in force, for the few that
    /// read one anyway (ID, RB…RD, HO).
    Plain(u32),
    One(u8),
    All,
}

impl Target {
    /// The one axis (only [`Target::One`] reaches commands of one axis).
    pub fn axis(self) -> u8 {
        match self {
            Target::One(a) => a,
            Target::Plain(a) => u8::try_from(a).unwrap_or(0),
            Target::All => 0,
        }
    }
}

/// A command's parameter, checked against its kind.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Operand {
    /// A parameter was typed.
    pub given: bool,
    pub real: f64,
    pub int: i64,
    /// As a register would hold it (AL, AA…).
    pub value: Value,
    pub text: Option<String>,
    /// Reporting precision: decimals.
    pub digits: u8,
}

impl Mccl {
    pub(super) fn execute(
        &mut self,
        interp: &mut Interpreter,
        command: &Command,
    ) -> Result<Flow, Code> {
        let spec = command.spec;
        if !spec.simulated {
            return Err(Code::NOT_SUPPORTED);
        }
        // Ch4: "With the exception of reporting commands ..., any MCCL
        // commands can be executed in a background task."
        if spec.reports && interp.task.is_some() {
            return Err(Code::NOT_SUPPORTED);
        }
        let target = self.target(interp, command)?;
        let op = self.operand(interp, command)?;
        if (spec.reports || command.is("OT") || command.is("OD")) && self.link.congested() {
            return Ok(Flow::Retry(Wait::Transmit));
        }
        match spec.group {
            Group::Setup | Group::Mode => self.exec_setup(interp, command, target, &op),
            Group::Motion => self.exec_motion(interp, command, target, &op),
            Group::Reporting => self.exec_report(interp, command, target, &op),
            Group::Register | Group::Io | Group::Misc => {
                self.exec_register(interp, command, target, &op)
            }
            Group::Macro | Group::Sequence => self.exec_flow(interp, command, target, &op),
        }
    }

    /// The axis rules of Ch2 and the "applies to" line of the command.
    fn target(&self, interp: &mut Interpreter, command: &Command) -> Result<Target, Code> {
        let axis = interp.axis_for(command);
        let spec = command.spec;
        if spec.axis == AxisUse::None {
            return Ok(Target::Plain(axis));
        }
        if axis == 0 {
            return match spec.axis {
                AxisUse::OneOrAll => Ok(Target::All),
                _ => Err(Code::NO_AXIS),
            };
        }
        let n = u8::try_from(axis)
            .ok()
            .filter(|&n| usize::from(n) <= self.axes.len())
            .ok_or(Code::AXIS_NOT_ASSIGNED)?;
        if !self.applies(spec, n) {
            return Err(Code::INVALID_FOR_AXIS);
        }
        Ok(Target::One(n))
    }

    /// The command applies to the kind of axis n ("applies to"); IM128
    /// lets an open-loop stepper take the PID settings (Ch6 IM).
    pub(super) fn applies(&self, spec: &CommandSpec, n: u8) -> bool {
        let Some(axis) = self.axis(n) else {
            return false;
        };
        let applies = spec.applies;
        if axis.is_servo() {
            applies.servo()
        } else if axis.is_closed_loop_stepper() {
            applies.closed_loop()
        } else {
            applies.open_loop()
                || axis.settings.input_mode == 128
                    && spec.group == Group::Setup
                    && applies.closed_loop()
        }
    }

    /// The parameter, checked against the command's kind and range.
    fn operand(&self, interp: &Interpreter, command: &Command) -> Result<Operand, Code> {
        let mut op = Operand {
            given: command.param != Param::None,
            ..Operand::default()
        };
        // The value of a number or register, and whether it came as a real.
        let number = |param: &Param| -> Result<(Value, bool), Code> {
            match param {
                Param::None => Ok((Value::Int(0), false)),
                Param::Int(n) => Ok((
                    i32::try_from(*n).map_or(Value::Double(*n as f64), Value::Int),
                    false,
                )),
                Param::Real(x) => Ok((Value::Double(*x), true)),
                Param::Register(r) => {
                    let value = self.register(interp, *r).ok_or(Code::PARAMETER)?;
                    Ok((value, false))
                }
                Param::Text(_) => Err(Code::BAD_FORMAT),
            }
        };
        match command.spec.param {
            ParamKind::None => {}
            ParamKind::Real { min, max } => {
                let (value, _) = number(&command.param)?;
                op.value = value;
                op.real = value.as_f64();
                op.int = value.rounded().into();
                if !(min..=max).contains(&op.real) {
                    return Err(Code::PARAMETER);
                }
            }
            ParamKind::Int { min, max } => {
                op.int = match &command.param {
                    Param::Int(n) => *n,
                    Param::Real(_) => return Err(Code::PARAMETER),
                    other => i64::from(number(other)?.0.rounded()),
                };
                if !(min..=max).contains(&op.int) {
                    return Err(Code::PARAMETER);
                }
                op.real = op.int as f64;
                op.value = i32::try_from(op.int).map_or(Value::Double(op.real), Value::Int);
            }
            ParamKind::Text => match &command.param {
                Param::Text(text) => op.text = Some(text.clone()),
                _ => return Err(Code::BAD_FORMAT),
            },
            ParamKind::OptionalText => match &command.param {
                Param::Text(text) => op.text = Some(text.clone()),
                Param::None => {}
                _ => return Err(Code::BAD_FORMAT),
            },
            ParamKind::HelpTopic => match &command.param {
                Param::Text(text) => op.text = Some(text.clone()),
                Param::None | Param::Int(0) => op.int = 0,
                Param::Int(1) => op.int = 1,
                _ => return Err(Code::PARAMETER),
            },
            ParamKind::Precision => {
                let (value, _) = number(&command.param)?;
                op.digits = precision_digits(value.as_f64()).ok_or(Code::PARAMETER)?;
            }
            ParamKind::RegisterPrecision => {
                let (value, _) = number(&command.param)?;
                let value = value.as_f64();
                let register = value.trunc();
                if !(0.0..=999.0).contains(&register) {
                    return Err(Code::PARAMETER);
                }
                op.int = register as i64;
                // 5.3 − 5 is 0.2999…: the tenths digit, rounded.
                let tenths = ((value - register) * 10.0).round() / 10.0;
                op.digits = precision_digits(tenths).ok_or(Code::PARAMETER)?;
            }
        }
        Ok(op)
    }

    /// The macro and sequence commands (Ch10, Ch12).
    fn exec_flow(
        &mut self,
        interp: &mut Interpreter,
        command: &Command,
        target: Target,
        op: &Operand,
    ) -> Result<Flow, Code> {
        let acc = interp.accumulator();
        let condition = |holds: bool| Ok(if holds { Flow::Next } else { Flow::Skip(2) });
        let channel = || u8::try_from(op.int).unwrap_or(0);
        match command.mnemonic() {
            "BK" => self.break_here(interp, op),
            "ET" => {
                let id = i32::try_from(op.int).map_err(|_| Code::BAD_TASK)?;
                if interp.task == Some(id) {
                    return Ok(Flow::EndTask);
                }
                if self.tasks.end(id) {
                    Ok(Flow::Next)
                } else {
                    Err(Code::BAD_TASK)
                }
            }
            "GT" => {
                let n = self.macro_number(interp, &command.param)?;
                let program = self.macro_sequence(n)?;
                self.spawn(interp, program)?;
                Ok(Flow::Next)
            }
            "MC" => {
                let n = self.macro_number(interp, &command.param)?;
                Ok(Flow::Call(self.call(interp, n)?))
            }
            "MJ" => {
                let n = self.macro_number(interp, &command.param)?;
                Ok(Flow::Replace(self.macro_sequence(n)?))
            }
            // MD anywhere but first (Ch10): the placement check stops it
            // before; here for safety.
            "MD" => Err(Code::MACRO_DEFINE_NOT_FIRST),
            "NO" => Ok(Flow::Next),
            "NP" => {
                interp.priority = u8::try_from(op.int).unwrap_or(interp.priority);
                Ok(Flow::Next)
            }
            "RM" => {
                self.macros.clear();
                Ok(Flow::Next)
            }
            "TM" => self.tell_macros(op.int),
            "DF" => Ok(if self.io.is_on(channel()) {
                Flow::EndFrame
            } else {
                Flow::Next
            }),
            "DN" => Ok(if self.io.is_on(channel()) {
                Flow::Next
            } else {
                Flow::EndFrame
            }),
            "IB" => condition(acc.as_f64() < op.real),
            "IE" => condition(acc.as_f64() == op.real),
            "IG" => condition(acc.as_f64() > op.real),
            "IU" => condition(acc.as_f64() != op.real),
            "IC" => condition(acc.rounded() & (1 << op.int) == 0),
            "IS" => condition(acc.rounded() & (1 << op.int) != 0),
            "IF" => condition(!self.io.is_on(channel())),
            "IN" => condition(self.io.is_on(channel())),
            "IP" | "IR" | "WP" | "WR" => {
                let n = target.axis();
                let axis = self.axis_mut(n).ok_or(Code::AXIS_NOT_ASSIGNED)?;
                let at = if command.is("IR") || command.is("WR") {
                    axis.target + axis.units.distance_to_counts(op.real)
                } else {
                    axis.units.to_counts(op.real)
                };
                axis.set_breakpoint(at);
                Ok(if command.is("WP") || command.is("WR") {
                    Flow::Wait(Wait::Breakpoint { axis: n })
                } else {
                    Flow::Next
                })
            }
            "JP" => Mccl::jump(interp, op.int, false),
            "JR" => Mccl::jump(interp, op.int, true),
            "RP" => self.repeat(interp, op.int),
            "WA" => Ok(if op.real > 0.0 {
                Flow::Wait(Wait::Until(self.dwell_until(interp, op.real)))
            } else {
                Flow::Next
            }),
            "WE" | "WI" => {
                let n = target.axis();
                let axis = self.axis_mut(n).ok_or(Code::AXIS_NOT_ASSIGNED)?;
                if axis.homing.captured.is_some() {
                    axis.store_capture();
                    Ok(Flow::Next)
                } else if axis.homing.armed.is_some() {
                    Ok(Flow::Wait(Wait::Capture { axis: n }))
                } else {
                    // Nothing armed: nothing to wait for (the simulator's choice).
                    axis.latched &= !super::axis::status::LOOKING;
                    Ok(Flow::Next)
                }
            }
            "WF" | "WN" => Ok(Flow::Wait(Wait::Channel {
                channel: channel(),
                on: command.is("WN"),
            })),
            "WS" => {
                let axis = target.axis();
                Ok(Flow::Wait(Wait::Stopped {
                    axis,
                    dwell: op.real,
                    errors_before: self.axis_errors(axis),
                }))
            }
            "WT" => {
                let axis = target.axis();
                Ok(Flow::Wait(Wait::AtTarget {
                    axis,
                    dwell: op.real,
                    errors_before: self.axis_errors(axis),
                }))
            }
            _ => Err(Code::NOT_SUPPORTED),
        }
    }

    /// BK: end the line or macro; BK"text" prints where it broke and the
    /// text, and single steps from there (Ch4 "Single Stepping MCCL
    /// Programs"; not in a task).
    fn break_here(&mut self, interp: &Interpreter, op: &Operand) -> Result<Flow, Code> {
        let Some(text) = &op.text else {
            return Ok(Flow::EndFrame);
        };
        if interp.task.is_some() {
            return Err(Code::NOT_SUPPORTED);
        }
        let (pc, origin) = interp
            .frames
            .last()
            .map_or((0, Origin::Line), |f| (f.pc, f.program.origin));
        let place = match origin {
            Origin::Macro(n) => format!("BREAK AT COMMAND {pc}, MACRO {n}"),
            Origin::Line => format!("BREAK AT COMMAND {pc}"),
        };
        self.link.line(&place);
        self.link.line(text);
        Ok(Flow::Break)
    }

    /// GT: a new task; its ID into the accumulator of the parent (and the
    /// child, [`Interpreter::task`]).
    pub(super) fn spawn(
        &mut self,
        parent: &mut Interpreter,
        program: Arc<Program>,
    ) -> Result<i32, Code> {
        let id = self.tasks.spawn(program, parent.default_axis)?;
        parent.set_accumulator(Value::Int(id));
        Ok(id)
    }

    /// `GT0` first on a line: the rest of the line runs as a task (Ch4);
    /// `GT0` alone runs macro 0.
    pub(super) fn spawn_line_task(&mut self, body: Vec<Command>) -> Result<(), Code> {
        let program = if body.is_empty() {
            self.macro_sequence(0)?
        } else {
            program::check(&body, false).map_err(|m| m.code)?;
            Program::new(body, Origin::Line)
        };
        let mut foreground = std::mem::take(&mut self.foreground);
        let result = self.spawn(&mut foreground, program);
        self.foreground = foreground;
        result.map(|_| ())
    }

    /// FI/FE: arm the capture and wait for it (then kept for MN).
    pub(super) fn find(&mut self, n: u8, kind: CaptureKind, value: f64) -> Result<Flow, Code> {
        let axis = self.axis_mut(n).ok_or(Code::AXIS_NOT_ASSIGNED)?;
        let counts = axis.units.to_counts(value);
        axis.arm_capture(kind, counts);
        Ok(Flow::Wait(Wait::Capture { axis: n }))
    }
}
