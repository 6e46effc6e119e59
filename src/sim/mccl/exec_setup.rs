//! The setup commands (manual Ch5) and the mode commands (Ch6).
//!
//! Choices (also in [`super::choices`]): LN adds to the enabled limits and
//! LF removes from them (LN0 enables all four, LF0 disables all); ES0 and
//! an OM above 1 on a stepper are parameter errors; SV below MV lowers MV
//! (Ch5 SV note); SQ outside 0–10 V is refused unless in torque mode;
//! SM above 8 (tangential knife) is not simulated.

use super::Mccl;
use super::axis::settings::{Speed, limit_mode_is_valid};
use super::axis::{Mode, Slave};
use super::errors::Code;
use super::execute::{Operand, Target};
use super::interpreter::{Flow, Interpreter};
use super::lexer::Command;

impl Mccl {
    pub(super) fn exec_setup(
        &mut self,
        interp: &mut Interpreter,
        command: &Command,
        target: Target,
        op: &Operand,
    ) -> Result<Flow, Code> {
        // The commands without an axis first.
        match command.mnemonic() {
            "UA" => {
                if usize::try_from(op.int).unwrap_or(usize::MAX) > self.axes.len() {
                    return Err(Code::AXIS_NOT_ASSIGNED);
                }
                interp.default_axis = u8::try_from(op.int).unwrap_or(0);
                return Ok(Flow::Next);
            }
            "UT" => {
                interp.user_time = op.real;
                return Ok(Flow::Next);
            }
            // PWM frequency: nothing to simulate beyond taking it.
            "PK" => return Ok(Flow::Next),
            _ => {}
        }
        let n = target.axis();
        match command.mnemonic() {
            "CM" => return self.contour_mode(n, op.int),
            "SM" => return self.slave_mode(n, op.int),
            _ => {}
        }
        let axis = self.axis_mut(n).ok_or(Code::AXIS_NOT_ASSIGNED)?;
        let real = op.real;
        let s = &mut axis.settings;
        match command.mnemonic() {
            "AG" => s.acceleration_gain = real,
            "AH" => axis.aux_offset = real - axis.shaft.round(),
            "BD" => s.backlash = real,
            "DB" => s.deadband = real,
            "DG" => s.deceleration_gain = real,
            "DH" => {
                let counts = axis.units.to_counts(real);
                axis.redefine(counts - axis.position());
                axis.home_position = counts;
            }
            "DI" => s.negative = op.int == 1,
            "DS" => s.deceleration = real,
            "DT" => s.target_delay = real,
            "EE" => s.encoder_check = u8::try_from(op.int).unwrap_or(0),
            "ES" => {
                if real <= 0.0 {
                    return Err(Code::PARAMETER);
                }
                s.steps_per_count = real;
            }
            "FC" => s.full_current = true,
            "HC" => s.full_current = false,
            "FF" => s.fault_check = false,
            "FN" => s.fault_check = true,
            "FR" => s.derivative_period = op.int,
            "HL" => s.high_limit = real,
            "LL" => s.low_limit = real,
            "HS" => s.speed = Speed::High,
            "MS" => s.speed = Speed::Medium,
            "LS" => s.speed = Speed::Low,
            "IL" => s.integration_limit = real,
            "IO" => s.integral_option = u8::try_from(op.int).unwrap_or(0),
            "LF" => {
                let n = u8::try_from(op.int).unwrap_or(0);
                s.limits &= if n == 0 { 0 } else { !n };
            }
            "LN" => {
                let n = u8::try_from(op.int).unwrap_or(0);
                s.limits |= if n == 0 { 15 } else { n };
            }
            "LM" => {
                if !limit_mode_is_valid(op.int) {
                    return Err(Code::PARAMETER);
                }
                s.limit_mode = u8::try_from(op.int).unwrap_or(0);
            }
            "MV" => s.minimum_velocity = real,
            "OB" => s.output_deadband = real,
            "OM" => {
                if !axis.is_servo() && op.int > 1 {
                    return Err(Code::PARAMETER);
                }
                axis.settings.output_mode = u8::try_from(op.int).unwrap_or(0);
            }
            "OO" => s.output_offset = real,
            "PH" => s.reverse_phase = op.int == 1,
            "SA" => s.acceleration = real,
            "SD" => s.derivative_gain = real,
            "SE" => s.following_limit = real,
            "SG" => s.proportional_gain = real,
            "SI" => s.integral_gain = real,
            "SQ" => {
                if axis.mode != Mode::Torque && real < 0.0 {
                    return Err(Code::PARAMETER);
                }
                axis.settings.torque = real;
            }
            "SS" => s.slave_ratio = real,
            "SV" => {
                s.velocity = real;
                if s.minimum_velocity > real {
                    s.minimum_velocity = real;
                }
            }
            "UK" => s.output_constant = real,
            "UO" | "UR" | "US" | "UZ" => {
                match command.mnemonic() {
                    "UO" => s.units.offset = real,
                    "UR" => s.units.rate = real,
                    "US" => s.units.scale = real,
                    _ => s.units.zero = real,
                }
                axis.units_changed();
            }
            "VA" => s.vector_acceleration = real,
            "VD" => s.vector_deceleration = real,
            "VG" => s.velocity_gain = real,
            "VO" => s.velocity_override = real,
            "VV" => s.vector_velocity = real,
            // ---- modes (Ch6) ----
            "IM" => {
                if ![0, 1, 128].contains(&op.int) {
                    return Err(Code::PARAMETER);
                }
                axis.set_input_mode(u8::try_from(op.int).unwrap_or(0));
            }
            "PM" | "VM" | "GM" | "QM" => {
                let mode = match command.mnemonic() {
                    "PM" => Mode::Position,
                    "VM" => Mode::Velocity,
                    "GM" => Mode::Gain,
                    _ => Mode::Torque,
                };
                self.set_mode(n, mode);
            }
            _ => return Err(Code::NOT_SUPPORTED),
        }
        Ok(Flow::Next)
    }

    /// PM, VM, GM, QM: leave contour mode and gearing; a move under way
    /// slows to a stop in the new mode.
    fn set_mode(&mut self, n: u8, mode: Mode) {
        self.leave_contour(n);
        let Some(axis) = self.axis_mut(n) else {
            return;
        };
        let was = axis.mode;
        axis.mode = mode;
        axis.running = false;
        axis.plan = None;
        axis.slave = None;
        match mode {
            Mode::Position if axis.velocity != 0.0 => axis.stop(),
            Mode::Position if was != Mode::Position => axis.target = axis.optimal,
            _ => {}
        }
    }

    /// SM n: gear axis `n` to master `master` at SS (Ch6 SM); SM0 ends it.
    fn slave_mode(&mut self, n: u8, master: i64) -> Result<Flow, Code> {
        if master == 0 {
            if let Some(axis) = self.axis_mut(n) {
                axis.slave = None;
                axis.target = axis.optimal;
                axis.velocity = 0.0;
            }
            return Ok(Flow::Next);
        }
        if master > 8 {
            // Tangential knife control (n = m1 + 16 × m2) is not simulated.
            return Err(Code::NOT_SUPPORTED);
        }
        let master = u8::try_from(master).map_err(|_| Code::PARAMETER)?;
        if master == n {
            return Err(Code::AXIS_DUPLICATE);
        }
        let master_start = self.axis(master).ok_or(Code::AXIS_NOT_ASSIGNED)?.optimal;
        let axis = self.axis_mut(n).ok_or(Code::AXIS_NOT_ASSIGNED)?;
        if axis.slave.is_some_and(|s| s.master != master) {
            return Err(Code::AXIS_ALREADY_ASSIGNED);
        }
        axis.slave = Some(Slave {
            master,
            master_start,
            own_start: axis.optimal,
        });
        axis.plan = None;
        axis.running = false;
        Ok(Flow::Next)
    }
}
