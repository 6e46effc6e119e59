//! The reporting commands (manual Ch8) and TM: Tell replies `AA value`
//! (the axis, or the channel for TC/TA, as two digits), values truncated
//! to the precision asked for, integers in hex after HM.
//!
//! Choices: TR's two-digit field is the axis in force (1 when none; the
//! manual's `TR0` → `01 15` does not say); TE prints the bare code (the
//! manual's `TE -2`); TS bits print 1 or 0; DR/DO/DA print integers and
//! DQ volts with three decimals; recorded samples not taken are −1.

use super::Mccl;
use super::axis::status::{StatusWord, Surroundings, word_of};
use super::commands;
use super::errors::Code;
use super::execute::{Operand, Target};
use super::interpreter::{Flow, Interpreter};
use super::lexer::Command;
use super::text;
use super::values::{Value, fixed, integer, register_text, tell_value};

impl Mccl {
    pub(super) fn exec_report(
        &mut self,
        interp: &mut Interpreter,
        command: &Command,
        target: Target,
        op: &Operand,
    ) -> Result<Flow, Code> {
        let radix = self.link.radix;
        match command.mnemonic() {
            "TE" => {
                let code = self.link.last_error;
                self.link.line(&code.to_string());
                return Ok(Flow::Next);
            }
            "VE" => {
                for line in text::version(self.config.model) {
                    self.link.line(line);
                }
                return Ok(Flow::Next);
            }
            "TA" => {
                let value = self
                    .io
                    .analog_in
                    .get(usize::try_from(op.int - 1).unwrap_or(0))
                    .copied()
                    .unwrap_or(0);
                let field = u32::try_from(op.int).unwrap_or(0);
                self.link.tell(field, &integer(i64::from(value), radix));
                return Ok(Flow::Next);
            }
            "TC" => {
                let channel = u8::try_from(op.int).unwrap_or(0);
                let value = if channel == 0 {
                    i64::from(self.io.inputs_word())
                } else {
                    i64::from(self.io.is_on(channel))
                };
                self.link.tell(u32::from(channel), &integer(value, radix));
                return Ok(Flow::Next);
            }
            "DE" => {
                let start = usize::try_from(op.int).unwrap_or(0);
                let bytes = self.scratch.dump(start).to_vec();
                for (row, chunk) in bytes.chunks(16).enumerate() {
                    let hex: Vec<String> = chunk.iter().map(|b| format!("{b:02x}")).collect();
                    self.link
                        .line(&format!("{:04x}: {}", start + row * 16, hex.join(" ")));
                }
                return Ok(Flow::Next);
            }
            "ID" => return self.information(target, op.int),
            "CG" | "GC" => {
                let axis = self.axis(target.axis()).ok_or(Code::AXIS_NOT_ASSIGNED)?;
                let count = if command.is("CG") {
                    axis.record.samples.len() as u32
                } else {
                    axis.compare.count
                };
                interp.set_accumulator(Value::Int(i32::try_from(count).unwrap_or(i32::MAX)));
                return Ok(Flow::Next);
            }
            "HE" => return self.help_command(op),
            _ => {}
        }
        let n = target.axis();
        let around = self.surroundings(n);
        let axis = self.axis(n).ok_or(Code::AXIS_NOT_ASSIGNED)?;
        let u = &axis.units;
        let s = &axis.settings;
        let field = u32::from(n);
        let value = match command.mnemonic() {
            "TP" => u.to_user(axis.position()),
            "TT" => u.to_user(axis.target),
            "TO" => u.to_user(axis.optimal),
            "TF" => u.distance_to_user(axis.following_error()),
            "TV" => u.speed_to_user(axis.velocity),
            "TB" => u.to_user(axis.breakpoint_at),
            "TZ" => u.to_user(axis.index_position),
            "TD" => s.derivative_gain,
            "TG" => s.proportional_gain,
            "TI" => s.integral_gain,
            "TK" => s.velocity_gain,
            "TL" => s.integration_limit,
            "TQ" => s.torque,
            "AT" => axis.aux_position(),
            "AZ" => axis.aux_index,
            "TX" => {
                let count = i64::from(axis.contour_count);
                self.link.tell(field, &integer(count, radix));
                return Ok(Flow::Next);
            }
            "TS" => {
                let (word, bit) = word_of(op.int).ok_or(Code::PARAMETER)?;
                let bits = axis.status_word(word, &around);
                let shown = match bit {
                    Some(b) => i64::from((bits >> b) & 1),
                    None => i64::from(bits),
                };
                self.link.tell(field, &integer(shown, radix));
                return Ok(Flow::Next);
            }
            "DR" | "DO" | "DQ" | "DA" => {
                let i = usize::try_from(op.int).unwrap_or(usize::MAX);
                let sample = *axis.record.sample(i).ok_or(Code::PARAMETER)?;
                let text = match command.mnemonic() {
                    "DR" => fixed(u.to_user(sample.actual), 0),
                    "DO" => fixed(u.to_user(sample.optimal), 0),
                    "DA" => fixed(sample.aux, 0),
                    _ => format!("{:.3}", sample.output),
                };
                self.link.tell(field, &text);
                return Ok(Flow::Next);
            }
            _ => return Err(Code::NOT_SUPPORTED),
        };
        self.link.tell(field, &tell_value(value, op.digits, radix));
        Ok(Flow::Next)
    }

    /// TR n (Register group, reports).
    pub(super) fn tell_register(
        &mut self,
        interp: &Interpreter,
        target: Target,
        n: i64,
        digits: u8,
    ) -> Result<Flow, Code> {
        let register = u32::try_from(n).map_err(|_| Code::PARAMETER)?;
        let value = self.register(interp, register).ok_or(Code::PARAMETER)?;
        let field = match target {
            Target::Plain(0) => 1,
            other => u32::from(other.axis()).max(1),
        };
        // TRn.p (Ch4): with a precision, as the Tell commands print.
        let text = match digits {
            0 => register_text(value, self.link.radix),
            digits => tell_value(value.as_f64(), digits, self.link.radix),
        };
        self.link.tell(field, &text);
        Ok(Flow::Next)
    }

    /// TM n: macro n as `MC<n>,<commands>` (Ch8 TM example), −1 all of them.
    pub(super) fn tell_macros(&mut self, n: i64) -> Result<Flow, Code> {
        let lines = if n == -1 {
            self.macros.listing()
        } else {
            let number = u16::try_from(n).map_err(|_| Code::MACRO_OUT_OF_RANGE)?;
            vec![self.macros.list(number).ok_or(Code::MACRO_MISSING)?]
        };
        for line in lines {
            self.link.line(&line);
        }
        Ok(Flow::Next)
    }

    /// ID n: the formatted pages of Ch8 ID.
    fn information(&mut self, target: Target, n: i64) -> Result<Flow, Code> {
        let lines = if n == 7 {
            text::tasks(&self.tasks.ids())
        } else {
            let number = match target {
                Target::Plain(0) => return Err(Code::NO_AXIS),
                Target::Plain(a) => u8::try_from(a).map_err(|_| Code::AXIS_NOT_ASSIGNED)?,
                other => other.axis(),
            };
            let around = self.surroundings(number);
            let axis = self.axis(number).ok_or(Code::AXIS_NOT_ASSIGNED)?;
            match n {
                0 => text::primary(axis, &around),
                1 => text::auxiliary(axis, &around),
                2 => text::motor_table(axis),
                3 => text::internal_table(axis),
                4 => text::filter(axis),
                5 => text::encoder_faults(axis),
                _ => text::io_assignment(axis),
            }
        };
        for line in lines {
            self.link.line(&line);
        }
        Ok(Flow::Next)
    }

    /// HE0, HE1, HE"mm".
    fn help_command(&mut self, op: &Operand) -> Result<Flow, Code> {
        let lines = match &op.text {
            Some(mnemonic) => {
                let spec = commands::find(&mnemonic.to_ascii_uppercase()).ok_or(Code::PARAMETER)?;
                vec![text::describe(spec)]
            }
            None if op.int == 1 => text::variables(),
            None => text::mnemonics(),
        };
        for line in lines {
            self.link.line(&line);
        }
        Ok(Flow::Next)
    }

    /// What the status words of axis `n` show from around it.
    pub(super) fn surroundings(&self, n: u8) -> Surroundings {
        let (sync_on, sync_ready) = self.sync_state(n);
        Surroundings {
            inputs: self.axis_inputs(n),
            sync_on,
            sync_ready,
        }
    }

    /// The primary status word of axis `n` (tests, UI demos).
    pub fn status(&self, n: u8) -> Option<u32> {
        let around = self.surroundings(n);
        self.axis(n)
            .map(|a| a.status_word(StatusWord::Primary, &around))
    }
}
