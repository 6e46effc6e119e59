//! The register commands (manual Ch11), the I/O commands (Ch9) and the
//! miscellaneous commands (Ch13).
//!
//! Choices (also in [`super::choices`]): AV's angles are radians; AV1
//! writes the accumulator's digits into the scratch pad and loads their
//! address; AV25 truncates; FT/FD load 0 when the scratch pad is full (as
//! ME does); EN/EF turn the port's echo on/off (their parameter, not
//! documented, is ignored); DW is taken and does nothing; RT without an
//! axis resets the controller and ends the line that issued it.

use super::Mccl;
use super::errors::Code;
use super::execute::{Operand, Target};
use super::interpreter::{Flow, Interpreter};
use super::lexer::{Command, Radix};
use super::printf::{self, Argument};
use super::registers::{self, Width};
use super::values::{Arithmetic, Bitwise, Value, round_to_i32};

/// A unary operation of AV.
type Evaluation = fn(f64) -> f64;

/// AV n (Ch11): the unary operations that give a double.
const EVALUATIONS: &[(i64, Evaluation)] = &[
    (2, |x| -x),
    (3, f64::abs),
    (4, f64::ceil),
    (5, f64::floor),
    (6, f64::fract),
    (7, f64::round),
    (8, |x| x * x),
    (9, f64::sqrt),
    (10, f64::sin),
    (11, f64::cos),
    (12, f64::tan),
    (13, f64::asin),
    (14, f64::acos),
    (15, f64::atan),
    (16, f64::sinh),
    (17, f64::cosh),
    (18, f64::tanh),
    (19, f64::exp),
    (20, f64::ln),
    (21, f64::log10),
    (22, |_| std::f64::consts::PI),
    (23, |_| std::f64::consts::TAU),
    (24, |_| std::f64::consts::FRAC_PI_2),
];

impl Mccl {
    pub(super) fn exec_register(
        &mut self,
        interp: &mut Interpreter,
        command: &Command,
        target: Target,
        op: &Operand,
    ) -> Result<Flow, Code> {
        let acc = interp.accumulator();
        match command.mnemonic() {
            // ---- registers (Ch11) ----
            "AA" => interp.set_accumulator(acc.arithmetic(Arithmetic::Add, op.value)),
            "AS" => interp.set_accumulator(acc.arithmetic(Arithmetic::Subtract, op.value)),
            "AM" => interp.set_accumulator(acc.arithmetic(Arithmetic::Multiply, op.value)),
            "AD" => interp.set_accumulator(acc.arithmetic(Arithmetic::Divide, op.value)),
            "AN" => interp.set_accumulator(acc.bitwise(Bitwise::And, op.value)),
            "AO" => interp.set_accumulator(acc.bitwise(Bitwise::Or, op.value)),
            "AE" => interp.set_accumulator(acc.bitwise(Bitwise::ExclusiveOr, op.value)),
            "AC" => interp.set_accumulator(Value::Int(!acc.rounded())),
            "AL" => interp.set_accumulator(op.value),
            "SL" => interp.set_accumulator(Value::Int(((acc.rounded() as u32) << op.int) as i32)),
            "SR" => interp.set_accumulator(Value::Int(((acc.rounded() as u32) >> op.int) as i32)),
            "AR" => {
                let n = u32::try_from(op.int).map_err(|_| Code::PARAMETER)?;
                if !self.set_register(interp, n, acc) {
                    return Err(Code::PARAMETER);
                }
            }
            "RA" => {
                let n = u32::try_from(op.int).map_err(|_| Code::PARAMETER)?;
                let value = self.register(interp, n).ok_or(Code::PARAMETER)?;
                interp.set_accumulator(value);
            }
            "AV" => {
                let value = self.evaluate(acc, op.int);
                interp.set_accumulator(value);
            }
            "AX" | "GX" => {
                let axis = self.axis(target.axis()).ok_or(Code::AXIS_NOT_ASSIGNED)?;
                let value = if command.is("AX") {
                    axis.aux_index
                } else {
                    axis.aux_position()
                };
                interp.set_accumulator(Value::Int(round_to_i32(value)));
            }
            "GA" => {
                let i = usize::try_from(op.int - 1).unwrap_or(0);
                let value = self.io.analog_in.get(i).copied().unwrap_or(0);
                interp.set_accumulator(Value::Int(i32::from(value)));
            }
            "OA" => {
                let i = usize::try_from(op.int - 1).unwrap_or(0);
                if let Some(slot) = self.io.analog_out.get_mut(i) {
                    *slot = acc.as_f64();
                }
            }
            "GU" => interp.set_accumulator(Value::Int(i32::from(interp.default_axis))),
            "LU" => {
                let name = op.text.as_deref().unwrap_or_default();
                let token = registers::look_up(name).ok_or(Code::UNKNOWN_VARIABLE)?;
                interp.set_accumulator(Value::Int(i32::try_from(token).unwrap_or(0)));
            }
            "RB" | "RW" | "RL" | "RV" | "RD" => {
                let width = width_of(command.mnemonic());
                let value = self.read_memory(target, op.int, width)?;
                interp.set_accumulator(value);
            }
            "WB" | "WW" | "WL" | "WV" | "WD" => {
                if registers::variable_of(op.int).is_some() {
                    // The motor tables are not written ("factory use only").
                    return Err(Code::NOT_SUPPORTED);
                }
                let address = usize::try_from(op.int).map_err(|_| Code::PARAMETER)?;
                if !self
                    .scratch
                    .write(address, width_of(command.mnemonic()), acc)
                {
                    return Err(Code::PARAMETER);
                }
            }
            "TR" => return self.tell_register(interp, target, op.int, op.digits),
            // ---- I/O (Ch9) ----
            "CN" | "CF" => {
                let channel = u8::try_from(op.int).map_err(|_| Code::PARAMETER)?;
                self.io.set_output(channel, command.is("CN"))?;
            }
            "CH" | "CL" => {
                let channel = u8::try_from(op.int).map_err(|_| Code::PARAMETER)?;
                self.io.set_polarity(channel, command.is("CL"));
            }
            // ---- miscellaneous (Ch13) ----
            "DM" => self.link.radix = Radix::Decimal,
            "HM" => self.link.radix = Radix::Hex,
            "DW" => {}
            "EN" => self.link.profile.echo = true,
            "EF" => self.link.profile.echo = false,
            "PC" => self.link.prompt = u8::try_from(op.int).unwrap_or(0),
            "ME" => {
                let size = usize::try_from(op.int).unwrap_or(0);
                let address = self.scratch.allocate(size).unwrap_or(0);
                interp.set_accumulator(Value::Int(i32::try_from(address).unwrap_or(0)));
            }
            "FM" => {
                let address = usize::try_from(op.int).unwrap_or(0);
                if !self.scratch.free(address) {
                    return Err(Code::PARAMETER);
                }
            }
            "OT" | "OD" | "FT" | "FD" => {
                let format = op.text.as_deref().unwrap_or_default();
                let argument = if matches!(command.mnemonic(), "OT" | "FT") {
                    Argument::Integer(i64::from(acc.rounded_toward_zero()))
                } else {
                    Argument::Double(acc.as_f64())
                };
                let text = printf::format(format, argument);
                if matches!(command.mnemonic(), "OT" | "OD") {
                    self.link.write(text.as_bytes());
                } else {
                    let address = self.scratch.store_text(&text).unwrap_or(0);
                    interp.set_accumulator(Value::Int(i32::try_from(address).unwrap_or(0)));
                }
            }
            "HE" => return self.exec_report(interp, command, target, op),
            "RT" => return Ok(self.reset_command(interp, target)),
            _ => return Err(Code::NOT_SUPPORTED),
        }
        Ok(Flow::Next)
    }

    /// AV n.
    fn evaluate(&mut self, acc: Value, n: i64) -> Value {
        match n {
            1 => {
                let text = match acc {
                    Value::Int(i) => i.to_string(),
                    real => format!("{:.6}", real.as_f64()),
                };
                let address = self.scratch.store_text(&text).unwrap_or(0);
                Value::Int(i32::try_from(address).unwrap_or(0))
            }
            25 => Value::Int(acc.rounded_toward_zero()),
            _ => {
                let f = EVALUATIONS
                    .iter()
                    .find(|(k, _)| *k == n)
                    .map_or(f64::from as Evaluation, |(_, f)| *f);
                Value::Double(f(acc.as_f64()))
            }
        }
    }

    /// aRx n: a motor-table variable of axis a (a token from LU), or the
    /// scratch pad at address n.
    fn read_memory(&self, target: Target, n: i64, width: Width) -> Result<Value, Code> {
        if let Some(variable) = registers::variable_of(n) {
            // "The Read command must include the axis specifier" (Ch4).
            let axis_number = match target {
                Target::Plain(0) => return Err(Code::NO_AXIS),
                other => other.axis(),
            };
            let around = self.surroundings(axis_number);
            let axis = self.axis(axis_number).ok_or(Code::AXIS_NOT_ASSIGNED)?;
            let value = registers::read_variable(axis, variable.quantity, &around);
            return Ok(width.convert(value));
        }
        let address = usize::try_from(n).map_err(|_| Code::PARAMETER)?;
        self.scratch.read(address, width).ok_or(Code::PARAMETER)
    }

    /// RT: reset one axis, or with none the whole controller, which ends
    /// the line (or the task) that issued it.
    fn reset_command(&mut self, interp: &mut Interpreter, target: Target) -> Flow {
        match target {
            Target::One(n) => {
                self.leave_contour(n);
                if let Some(axis) = self.axis_mut(n) {
                    axis.reset();
                }
                Flow::Next
            }
            _ => {
                self.reset();
                let task = interp.task;
                *interp = Interpreter::foreground();
                if task.is_some() {
                    Flow::EndTask
                } else {
                    Flow::EndFrame
                }
            }
        }
    }
}

fn width_of(mnemonic: &str) -> Width {
    match mnemonic.as_bytes().get(1) {
        Some(b'B') => Width::Byte,
        Some(b'W') => Width::Word,
        Some(b'L') => Width::Long,
        Some(b'V') => Width::Float,
        _ => Width::Double,
    }
}
