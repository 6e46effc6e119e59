//! The motion commands (manual Ch7) and the controller's motion tick.
//!
//! A move (MA, MR, MP, GH, GO) on an axis holding a motor error is refused
//! with −13 until MN (Ch5 LM: the error "will prevent the controller from
//! moving the motor until a Motor oN command is issued"); on an axis in
//! contour mode outside a path command with −9. Choices: backlash
//! compensation (BD/BN/BF) is kept and shown in the status but does not
//! move the simulated motor; MP to a point never learned is −1.

use super::axis::{CaptureKind, Mode, status};
use super::errors::Code;
use super::execute::{Operand, Target};
use super::interpreter::{Flow, Interpreter};
use super::io;
use super::lexer::Command;
use super::{Mccl, TICK_SECONDS};

impl Mccl {
    pub(super) fn exec_motion(
        &mut self,
        interp: &mut Interpreter,
        command: &Command,
        target: Target,
        op: &Operand,
    ) -> Result<Flow, Code> {
        let mnemonic = command.mnemonic();
        match mnemonic {
            "HO" => {
                // Ch7 HO: macro a; with no axis, macro 9.
                let n = match target {
                    Target::Plain(0) => 9,
                    Target::Plain(a) => u16::try_from(a).map_err(|_| Code::MACRO_OUT_OF_RANGE)?,
                    _ => 9,
                };
                return Ok(Flow::Call(self.call(interp, n)?));
            }
            "MN" | "MF" | "AB" | "ST" | "MA" | "LP" | "LT" | "MP" | "GO" => {
                return self.each_axis(target, mnemonic, op);
            }
            "CA" | "CR" | "CD" | "RR" => return Err(Code::CONTOUR_NOT_FIRST),
            "CP" => return self.contour_path(interp, target.axis(), op.int),
            "SN" | "NS" => return self.set_sync(target.axis(), mnemonic == "SN"),
            "FE" => return self.find(target.axis(), CaptureKind::Edge, op.real),
            "FI" => return self.find(target.axis(), CaptureKind::Index, op.real),
            _ => {}
        }
        let n = target.axis();
        let axis = self.axis_mut(n).ok_or(Code::AXIS_NOT_ASSIGNED)?;
        match mnemonic {
            "AF" => {
                axis.aux_armed = Some(op.real);
                axis.aux_found = false;
                axis.latched = (axis.latched | status::LOOKING_AUX) & !status::AUX_FOUND;
            }
            "BC" => {
                if !axis.compare.begin(op.int) {
                    return Err(Code::PARAMETER);
                }
            }
            "BF" => axis.settings.backlash_on = false,
            "BN" => axis.settings.backlash_on = true,
            "CB" => {
                axis.record.start_capturing(op.int);
                axis.latched &= !status::CAPTURED;
            }
            "EL" | "IA" => {
                let kind = if mnemonic == "EL" {
                    CaptureKind::Edge
                } else {
                    CaptureKind::Index
                };
                let counts = axis.units.to_counts(op.real);
                axis.arm_capture(kind, counts);
            }
            "GH" | "MR" => {
                Self::may_move(axis)?;
                let to = if mnemonic == "GH" {
                    axis.home_position
                } else {
                    axis.target + axis.units.distance_to_counts(op.real)
                };
                axis.move_to(to);
            }
            "LC" => {
                let counts = axis.units.to_counts(op.real);
                if !axis.compare.load(counts) {
                    return Err(Code::NO_MEMORY);
                }
            }
            "NC" => axis.compare.increment = axis.units.distance_to_counts(op.real),
            "OC" => {
                if !(0..=3).contains(&(op.int & 0x7F)) || op.int & 0x7C != 0 {
                    return Err(Code::PARAMETER);
                }
                axis.compare.output_mode = u8::try_from(op.int).unwrap_or(0);
            }
            "OP" => axis.compare.period = op.real,
            "PP" => axis.settings.profile = super::axis::profile::Shape::Parabolic,
            "PS" => axis.settings.profile = super::axis::profile::Shape::SCurve,
            "PT" => axis.settings.profile = super::axis::profile::Shape::Trapezoid,
            "PR" => axis
                .record
                .start_recording(usize::try_from(op.int).unwrap_or(0)),
            _ => return Err(Code::NOT_SUPPORTED),
        }
        Ok(Flow::Next)
    }

    /// A move may start on this axis.
    fn may_move(axis: &super::axis::Axis) -> Result<(), Code> {
        if axis.has_motor_error() {
            return Err(Code::AXIS_ERROR);
        }
        if matches!(axis.mode, Mode::Contour(_)) {
            return Err(Code::CONTOUR_PARAMETER);
        }
        Ok(())
    }

    /// The commands that take axis 0 as every axis (Ch2, Ch7).
    fn each_axis(&mut self, target: Target, mnemonic: &str, op: &Operand) -> Result<Flow, Code> {
        let numbers: Vec<u8> = match target {
            Target::One(n) => vec![n],
            _ => self.axes.iter().map(|a| a.number).collect(),
        };
        let every = !matches!(target, Target::One(_));
        let point = usize::try_from(op.int).unwrap_or(0);
        // Refuse before anything moves.
        if matches!(mnemonic, "MA" | "MP" | "GO") {
            for &n in &numbers {
                let axis = self.axis(n).ok_or(Code::AXIS_NOT_ASSIGNED)?;
                let contour_go =
                    mnemonic == "GO" && matches!(axis.mode, Mode::Contour(c) if c == n);
                if axis.has_motor_error() {
                    return Err(Code::AXIS_ERROR);
                }
                if matches!(axis.mode, Mode::Contour(_)) && !contour_go && !every {
                    return Err(Code::CONTOUR_PARAMETER);
                }
                let learned = self
                    .points
                    .get(point)
                    .and_then(|p| p.get(usize::from(n) - 1))
                    .is_some_and(Option::is_some);
                if mnemonic == "MP" && !every && !learned {
                    return Err(Code::PARAMETER);
                }
            }
        }
        for n in numbers {
            if (mnemonic == "ST" || mnemonic == "AB")
                && matches!(self.axis(n).map(|a| a.mode), Some(Mode::Contour(_)))
            {
                self.stop_group_of(n, false);
                continue;
            }
            if mnemonic == "GO" && self.contour_go(n) {
                continue;
            }
            let stored = self
                .points
                .get(point)
                .and_then(|p| p.get(usize::from(n) - 1))
                .copied()
                .flatten();
            let Some(axis) = self.axis_mut(n) else {
                continue;
            };
            let contour = matches!(axis.mode, Mode::Contour(_));
            match mnemonic {
                "MN" => axis.motor_on(),
                "MF" => axis.motor_off(),
                "AB" => axis.abort(),
                "ST" => axis.stop(),
                "GO" => axis.go(),
                "MA" if !contour => {
                    let to = axis.units.to_counts(op.real);
                    axis.move_to(to);
                }
                "MP" if !contour => {
                    if let Some(to) = stored {
                        axis.move_to(to);
                    }
                }
                "LP" | "LT" => {
                    let value = if mnemonic == "LP" {
                        axis.position()
                    } else {
                        axis.target
                    };
                    if let Some(slot) = self
                        .points
                        .get_mut(point)
                        .and_then(|p| p.get_mut(usize::from(n) - 1))
                    {
                        *slot = Some(value);
                    }
                }
                _ => {}
            }
        }
        Ok(Flow::Next)
    }

    /// One tick of motion: trajectories, contour paths, gearing, motors,
    /// then what is watched on each axis.
    pub(super) fn motion_tick(&mut self) {
        let dt = TICK_SECONDS;
        let before: Vec<f64> = self.axes.iter().map(|a| a.position()).collect();
        for axis in &mut self.axes {
            if axis.slave.is_none() && !matches!(axis.mode, Mode::Contour(_)) {
                axis.trajectory_tick(dt);
            }
        }
        self.contour_tick(dt);
        for i in 0..self.axes.len() {
            let Some(slave) = self.axes[i].slave else {
                continue;
            };
            let master = self
                .axes
                .get(usize::from(slave.master).saturating_sub(1))
                .map(|m| (m.optimal, m.velocity));
            let axis = &mut self.axes[i];
            if let (Some((optimal, velocity)), true) = (master, axis.motor_on) {
                let ratio = axis.settings.slave_ratio;
                axis.optimal = slave.own_start + ratio * (optimal - slave.master_start);
                axis.velocity = ratio * velocity;
                axis.target = axis.optimal;
                axis.note_direction();
            }
        }
        for axis in &mut self.axes {
            axis.drive_tick(dt);
        }
        for (i, &from) in before.iter().enumerate() {
            let n = self.axes[i].number;
            let inputs = self.axis_inputs(n);
            let off_on_trip = self.axes[i].settings.limit_mode & 3 == 0;
            let events = self.axes[i].check_tick(dt, from, inputs);
            if events.trip.is_some() && matches!(self.axes[i].mode, Mode::Contour(_)) {
                self.stop_group_of(n, off_on_trip);
            }
            if events.compares > 0 {
                self.compare_output(i, events.compares);
            }
            self.one_shot_tick(i, dt);
        }
    }

    /// Drive the axis' compare output for `events` compare events (Ch7 BC,
    /// OC: static, toggle, one-shot; + 128 inverts).
    fn compare_output(&mut self, i: usize, events: u32) {
        let axis = &mut self.axes[i];
        let Some(channel) = io::channels_of(axis.number).map(|c| c.compare) else {
            return;
        };
        let mode = axis.compare.output_mode;
        let inverted = mode & 128 != 0;
        let active = match mode & 3 {
            0 => return,
            1 => true,
            2 => {
                let now = self.io.is_on(channel) != inverted;
                if events % 2 == 1 { !now } else { now }
            }
            _ => {
                axis.compare.pulse_left = axis.compare.period;
                true
            }
        };
        let _ = self.io.set_output(channel, active != inverted);
    }

    /// The end of a one-shot compare pulse.
    fn one_shot_tick(&mut self, i: usize, dt: f64) {
        let axis = &mut self.axes[i];
        if axis.compare.pulse_left <= 0.0 {
            return;
        }
        axis.compare.pulse_left -= dt;
        if axis.compare.pulse_left <= 1e-9 {
            axis.compare.pulse_left = 0.0;
            let inverted = axis.compare.output_mode & 128 != 0;
            if let Some(c) = io::channels_of(axis.number) {
                let _ = self.io.set_output(c.compare, inverted);
            }
        }
    }
}
