//! What the core does with a command (§4.1 Table 4-40): the parsed
//! command of [`parse_command`] turned into reads and writes of the core's
//! state and calls of the motion engine, and the answer it sends. Also
//! STORE and the power-on load of the flash, which go through the same
//! reads and writes of the registers Table 2-19 names (the command table's
//! `stored` rows).

use std::collections::BTreeMap;

use crate::protocol::cmd4cr::catalog::{Form, Format, Kind};
use crate::protocol::cmd4cr::command::format_value;
use crate::protocol::cmd4cr::{
    Action, Axis, COMMANDS, Cmd4crCommand, ErrorCode, ErrorReply, Register, Rotation, Selector,
    parse_command,
};

use super::io::with_bit;
use super::motion::{BufferedMove, Refusal, Start};
use super::{Cmd4cr, FIRMWARE_VERSION, flash};
use crate::protocol::cmd4cr::ProgramControl;

/// A value read.
pub(super) enum Value {
    Int(i64),
    Fields(Vec<i64>),
    Text(String),
}

impl From<Refusal> for ErrorCode {
    fn from(refusal: Refusal) -> ErrorCode {
        refusal.code()
    }
}

fn flag(on: bool) -> i64 {
    i64::from(on)
}

fn bit(word: u64, n: u8) -> i64 {
    let n = u32::from(n.saturating_sub(1));
    i64::from(n < 64 && (word >> n) & 1 != 0)
}

/// A value the parser checked against the register's range, as `u32`.
fn unsigned(value: i64) -> u32 {
    u32::try_from(value.clamp(0, i64::from(u32::MAX))).unwrap_or(0)
}

fn small(value: i64) -> u8 {
    u8::try_from(value.clamp(0, 255)).unwrap_or(0)
}

/// Index n (1-based, as the manual numbers DI/DO/EO/IO/AI/PWM/JLIM) to a
/// 0-based slot.
fn slot(n: u8) -> usize {
    usize::from(n.saturating_sub(1))
}

impl Cmd4cr {
    /// The answer line (without CR) to command text.
    pub(super) fn answer(&mut self, text: &str) -> String {
        let command = match parse_command(text) {
            Ok(command) => command,
            Err(e) => return e.reply().line(),
        };
        match self.execute(&command) {
            Ok(Some(value)) => value,
            Ok(None) => self.config.write_reply.clone(),
            Err(ErrorCode::UnknownCommand) => ErrorReply::UnknownCommand(text.to_string()).line(),
            Err(code) => ErrorReply::Known(code).line(),
        }
    }

    fn execute(&mut self, command: &Cmd4crCommand) -> Result<Option<String>, ErrorCode> {
        match *command {
            Cmd4crCommand::Read { register, selector } => {
                let format = command.reply_format().unwrap_or(Format::Integer);
                Ok(Some(match self.read(register, selector)? {
                    Value::Int(v) => format_value(v, format),
                    Value::Fields(fields) => fields
                        .iter()
                        .map(ToString::to_string)
                        .collect::<Vec<_>>()
                        .join(":"),
                    Value::Text(text) => text,
                }))
            }
            Cmd4crCommand::Write {
                register,
                selector,
                value,
            } => self.write(register, selector, value).map(|()| None),
            Cmd4crCommand::Action { action, selector } => self.act(action, selector).map(|()| None),
            Cmd4crCommand::Move { targets } => {
                let targets = Axis::ALL
                    .into_iter()
                    .zip(targets)
                    .filter_map(|(axis, t)| t.map(|t| (axis, t)))
                    .collect();
                self.motion.start(Start::Position { targets })?;
                Ok(None)
            }
            Cmd4crCommand::Jog { axis, direction } => {
                self.motion.start(Start::Jog { axis, direction })?;
                Ok(None)
            }
            Cmd4crCommand::Home {
                axis,
                direction,
                mode,
            } => {
                self.motion.start(Start::Home {
                    axis,
                    direction,
                    mode,
                })?;
                Ok(None)
            }
            Cmd4crCommand::ZMove { axis, direction } => {
                self.motion.start(Start::ZMove { axis, direction })?;
                Ok(None)
            }
            Cmd4crCommand::NewTarget { axis, target } => {
                self.motion.change_target(axis, target)?;
                Ok(None)
            }
            Cmd4crCommand::Circle {
                axes: [a, b],
                rotation,
                centre: [c1, c2],
            } => self.arc((a, b), rotation, (c1, c2), None, None),
            Cmd4crCommand::Arc {
                axes: [a, b],
                rotation,
                centre: [c1, c2],
                angle,
            } => self.arc((a, b), rotation, (c1, c2), Some(angle), None),
            Cmd4crCommand::HelicalCircle {
                rotation,
                centre: [c1, c2],
                z,
            } => self.arc((Axis::X, Axis::Y), rotation, (c1, c2), None, Some(z)),
            Cmd4crCommand::HelicalArc {
                rotation,
                centre: [c1, c2],
                angle,
                z,
            } => self.arc((Axis::X, Axis::Y), rotation, (c1, c2), Some(angle), Some(z)),
            Cmd4crCommand::BufferMove { target, speed } => {
                self.motion.buffer_push(BufferedMove::Linear {
                    target,
                    speed: unsigned(speed),
                })?;
                Ok(None)
            }
        }
    }

    /// A circle or arc: into the buffer while buffer mode is on (§2.3.4),
    /// at the global HSPD of now; otherwise started.
    fn arc(
        &mut self,
        axes: (Axis, Axis),
        rotation: Rotation,
        centre: (i64, i64),
        end_mdeg: Option<i64>,
        helix_z: Option<i64>,
    ) -> Result<Option<String>, ErrorCode> {
        if self.motion.buffer_status().enabled {
            self.motion.buffer_push(BufferedMove::Arc {
                axes,
                rotation,
                centre,
                end_mdeg,
                helix_z,
                speed: self.motion.global.hspd,
            })?;
        } else {
            self.motion.start(Start::Arc {
                axes,
                rotation,
                centre,
                end_mdeg,
                helix_z,
            })?;
        }
        Ok(None)
    }

    pub(super) fn read(&self, register: Register, selector: Selector) -> Result<Value, ErrorCode> {
        use Register as R;
        use Selector::{All, Axis as A, Index as I};
        let m = &self.motion;
        let g = &m.global;
        let int = |v: i64| Ok(Value::Int(v));
        let per_axis = |axis: Axis| m.axis(axis);
        match (register, selector) {
            (R::Id, _) => int(i64::from(self.id_setting)),
            (R::Ver, _) => Ok(Value::Text(FIRMWARE_VERSION.to_string())),
            (R::Db, _) => int(self.baud_code),
            (R::Ierr, _) => int(flag(g.ignore_errors)),
            (R::Exst, _) => int(flag(g.external_start)),
            (R::Eint, _) => int(flag(g.interpolate)),
            (R::Mm, _) => int(flag(g.incremental)),
            (R::Hspd, All) => int(g.hspd.into()),
            (R::Lspd, All) => int(g.lspd.into()),
            (R::Acc, All) => int(g.acc.into()),
            (R::Dec, All) => int(g.dec.into()),
            (R::Hspd, A(a)) => int(per_axis(a).settings.hspd.into()),
            (R::Lspd, A(a)) => int(per_axis(a).settings.lspd.into()),
            (R::Acc, A(a)) => int(per_axis(a).settings.acc.into()),
            (R::Dec, A(a)) => int(per_axis(a).settings.dec.into()),
            (R::Scv, A(a)) => int(flag(per_axis(a).settings.s_curve)),
            (R::Sspdm, A(a)) => int(per_axis(a).settings.sspdm.into()),
            (R::Zcnt, A(a)) => int(per_axis(a).settings.zcnt.into()),
            (R::P, A(a)) => int(m.position_reading(a)),
            (R::E, A(a)) => int(m.encoder(a)),
            (R::Pp, _) => Ok(Value::Fields(
                Axis::ALL.map(|a| m.position_reading(a)).to_vec(),
            )),
            (R::Ep, _) => Ok(Value::Fields(Axis::ALL.map(|a| m.encoder(a)).to_vec())),
            (R::D, A(a)) => int(per_axis(a).deviation()),
            (R::Mst, A(a)) => int(i64::from(m.status(a))),
            (R::Ps, A(a)) => int(m.pulse_rate_reading(a)),
            (R::Mp, A(a)) => int(self.mpg[a.index()].counter),
            (R::Pol, A(a)) => int(per_axis(a).settings.polarity.into()),
            (R::Eo, All) => int(self.io.enable.into()),
            (R::Eo, I(n)) => int(bit(self.io.enable.into(), n)),
            (R::Eoboot, _) => int(self.io.enable_boot.into()),
            (R::Sde, A(a)) => int(per_axis(a).settings.sde.into()),
            (R::Sdc, A(a)) => int(per_axis(a).settings.sdc.into()),
            (R::Inp, A(a)) => int(flag(per_axis(a).settings.inp)),
            (R::Erc, A(a)) => int(per_axis(a).settings.erc.into()),
            (R::Ercd, A(a)) => int(per_axis(a).settings.ercd.into()),
            (R::Ercp, A(a)) => int(per_axis(a).settings.ercp.into()),
            (R::Di, All) => int(self.io.digital_inputs.into()),
            (R::Di, I(n)) => int(bit(self.io.digital_inputs.into(), n)),
            (R::Dip, _) => int(self.io.input_polarity.into()),
            (R::Do, All) => int(self.outputs().into()),
            (R::Do, I(n)) => int(bit(self.outputs().into(), n)),
            (R::Dop, _) => int(self.io.output_polarity.into()),
            (R::Doboot, _) => int(self.io.output_boot.into()),
            (R::Io, All) => int(self.io.io().into()),
            (R::Io, I(n)) => int(bit(self.io.io().into(), n)),
            (R::Iocfg, _) => int(self.io.io_config.into()),
            (R::Ioboot, _) => int(self.io.io_boot.into()),
            (R::Iop, _) => int(self.io.io_polarity.into()),
            (R::Ai, I(n)) => int(self.io.analog.get(slot(n)).copied().unwrap_or(0).into()),
            (R::Pwm, I(n)) => int(self.io.pwm.get(slot(n)).copied().unwrap_or(0).into()),
            (R::Lts, A(a)) => int(per_axis(a).latch.status as i64),
            (R::Ltp, A(a)) => int(per_axis(a).latch.pulse),
            (R::Lte, A(a)) => int(per_axis(a).latch.encoder),
            (R::Sync, A(a)) => int(i64::from(per_axis(a).sync.config as i32)),
            (R::Synp, A(a)) => int(per_axis(a).sync.position),
            (R::Synmax, A(a)) => int(per_axis(a).sync.window_max),
            (R::Synmin, A(a)) => int(per_axis(a).sync.window_min),
            (R::Syns, A(a)) => int(per_axis(a).sync.status as i64),
            (R::Jena, _) => int(self.joystick.enable),
            (R::Jmax, A(a)) => int(self.joystick.max[a.index()]),
            (R::Jmin, A(a)) => int(self.joystick.min[a.index()]),
            (R::Jtol, A(a)) => int(self.joystick.tolerance[a.index()]),
            (R::Jspd, A(a)) => int(self.joystick.speed[a.index()]),
            (R::Jdel, A(a)) => int(self.joystick.delta[a.index()]),
            (R::Jlim, I(n)) => int(self.joystick.limits.get(slot(n)).copied().unwrap_or(0)),
            (R::Mpe, A(a)) => int(flag(self.mpg[a.index()].enabled)),
            (R::Mpm, A(a)) => int(self.mpg[a.index()].multiplier),
            (R::Mpd, A(a)) => int(self.mpg[a.index()].divider),
            (R::Sl, A(a)) => int(flag(per_axis(a).step_n_loop.enabled)),
            (R::Slr, A(a)) => int(per_axis(a).step_n_loop.ratio),
            (R::Slt, A(a)) => int(per_axis(a).step_n_loop.tolerance),
            (R::Sle, A(a)) => int(per_axis(a).step_n_loop.error_range),
            (R::Sla, A(a)) => int(per_axis(a).step_n_loop.attempts),
            (R::Sls, A(a)) => int(m.loop_status(a).into()),
            (R::Sastat, I(n)) => int(self.programs.status(usize::from(n)) as i64),
            (R::Spc, I(n)) => int(i64::try_from(self.programs.pc(usize::from(n))).unwrap_or(0)),
            (R::Sload, All) => int(self.run_on_boot),
            (R::Sload, I(n)) => int(bit(self.run_on_boot as u64, n + 1)),
            (R::Sap, _) => int(self.sub31_return),
            (R::V, I(n)) => int(self
                .variables
                .get(usize::from(n))
                .copied()
                .unwrap_or(0)
                .into()),
            (R::Bstat, _) => {
                let s = m.buffer_status();
                Ok(Value::Fields(vec![
                    flag(s.enabled),
                    s.start as i64,
                    s.end as i64,
                    s.available as i64,
                ]))
            }
            // Forms the parser does not make (write-only registers).
            _ => Err(ErrorCode::UnknownCommand),
        }
    }

    /// DO as it is: the latch, with the outputs in sync use showing the
    /// sync state (T2-6).
    fn outputs(&self) -> u8 {
        let mut mask = 0u8;
        let mut sync = 0u8;
        for axis in Axis::ALL {
            let s = &self.motion.axis(axis).sync;
            if s.enabled {
                mask |= 1 << axis.index();
                if s.output {
                    sync |= 1 << axis.index();
                }
            }
        }
        self.io.outputs(mask, sync)
    }

    fn write(
        &mut self,
        register: Register,
        selector: Selector,
        value: i64,
    ) -> Result<(), ErrorCode> {
        use Register as R;
        use Selector::{All, Axis as A, Index as I};
        let on = value != 0;
        match (register, selector) {
            (R::Id, _) => self.id_setting = small(value),
            (R::Db, _) => self.baud_code = value,
            (R::Ierr, _) => self.motion.global.ignore_errors = on,
            (R::Exst, _) => self.motion.global.external_start = on,
            (R::Eint, _) => self.motion.global.interpolate = on,
            (R::Hspd, All) => self.motion.global.hspd = unsigned(value),
            (R::Lspd, All) => self.motion.global.lspd = unsigned(value),
            (R::Acc, All) => self.motion.global.acc = unsigned(value),
            (R::Dec, All) => self.motion.global.dec = unsigned(value),
            (R::Hspd, A(a)) => self.motion.axis_mut(a).settings.hspd = unsigned(value),
            (R::Lspd, A(a)) => self.motion.axis_mut(a).settings.lspd = unsigned(value),
            (R::Acc, A(a)) => self.motion.axis_mut(a).settings.acc = unsigned(value),
            (R::Dec, A(a)) => self.motion.axis_mut(a).settings.dec = unsigned(value),
            (R::Scv, A(a)) => self.motion.axis_mut(a).settings.s_curve = on,
            (R::Sspdm, A(a)) => self.motion.axis_mut(a).settings.sspdm = small(value),
            (R::Sspd, A(a)) => self.motion.change_speed(a, unsigned(value))?,
            (R::Zcnt, A(a)) => self.motion.axis_mut(a).settings.zcnt = small(value),
            (R::P, A(a)) => {
                self.require_stopped(a)?;
                self.motion.set_counter(a, value);
            }
            (R::E, A(a)) => {
                self.require_stopped(a)?;
                self.motion.set_encoder(a, value);
            }
            (R::Mp, A(a)) => self.mpg[a.index()].counter = value,
            (R::Pol, A(a)) => self.motion.axis_mut(a).settings.polarity = unsigned(value),
            (R::Eo, All) => self.io.enable = small(value),
            (R::Eo, I(n)) => self.io.enable = with_bit(self.io.enable, slot(n) as u32, on),
            (R::Eoboot, _) => self.io.enable_boot = small(value),
            (R::Sde, A(a)) => self.motion.axis_mut(a).settings.sde = small(value),
            (R::Sdc, A(a)) => self.motion.axis_mut(a).settings.sdc = small(value),
            (R::Inp, A(a)) => self.motion.axis_mut(a).settings.inp = on,
            (R::Erc, A(a)) => self.motion.axis_mut(a).settings.erc = small(value),
            (R::Ercd, A(a)) => self.motion.axis_mut(a).settings.ercd = small(value),
            (R::Ercp, A(a)) => self.motion.axis_mut(a).settings.ercp = small(value),
            (R::Dip, _) => self.io.input_polarity = small(value),
            (R::Do, All) => self.io.digital_outputs = small(value),
            (R::Do, I(n)) => {
                self.io.digital_outputs = with_bit(self.io.digital_outputs, slot(n) as u32, on);
            }
            (R::Dop, _) => self.io.output_polarity = small(value),
            (R::Doboot, _) => self.io.output_boot = small(value),
            (R::Io, All) => self.io.io_outputs = unsigned(value),
            (R::Io, I(n)) => {
                self.io.io_outputs = with_bit(self.io.io_outputs, slot(n) as u32, on);
            }
            (R::Iocfg, _) => self.io.io_config = unsigned(value),
            (R::Ioboot, _) => self.io.io_boot = unsigned(value),
            (R::Iop, _) => self.io.io_polarity = small(value),
            (R::Pwm, I(n)) => {
                if let Some(duty) = self.io.pwm.get_mut(slot(n)) {
                    *duty = small(value);
                }
            }
            (R::Lt, A(a)) => self.motion.axis_mut(a).latch.enable(on),
            // The word is 32 bits; negative values keep their bit pattern.
            (R::Sync, A(a)) => self.motion.axis_mut(a).sync.config = value as i32 as u32,
            (R::Synp, A(a)) => self.motion.axis_mut(a).sync.position = value,
            (R::Synmax, A(a)) => self.motion.axis_mut(a).sync.window_max = value,
            (R::Synmin, A(a)) => self.motion.axis_mut(a).sync.window_min = value,
            (R::Jena, _) => {
                self.joystick.enable = value;
                for axis in [Axis::X, Axis::Y] {
                    if value & (1 << axis.index()) != 0 {
                        // §2.5.1: enabling the joystick turns StepNLoop off.
                        self.motion.enable_step_n_loop(axis, false);
                    }
                }
                self.update_manual_control();
            }
            (R::Jmax, A(a)) => self.joystick.max[a.index()] = value,
            (R::Jmin, A(a)) => self.joystick.min[a.index()] = value,
            (R::Jtol, A(a)) => self.joystick.tolerance[a.index()] = value,
            (R::Jspd, A(a)) => self.joystick.speed[a.index()] = value,
            (R::Jdel, A(a)) => self.joystick.delta[a.index()] = value,
            (R::Jlim, I(n)) => {
                if let Some(limit) = self.joystick.limits.get_mut(slot(n)) {
                    *limit = value;
                }
            }
            (R::Mpe, A(a)) => {
                self.mpg[a.index()].enabled = on;
                self.update_manual_control();
            }
            (R::Mpm, A(a)) => self.mpg[a.index()].multiplier = value,
            (R::Mpd, A(a)) => self.mpg[a.index()].divider = value,
            (R::Sl, A(a)) => {
                // §2.5.1: "If joystick control is enabled, StepNLoop is
                // automatically disabled": SL=1 leaves it off (answered like
                // any write; the manual gives no refusal).
                let joystick = a.index() < 2 && self.joystick.enable & (1 << a.index()) != 0;
                self.motion.enable_step_n_loop(a, on && !joystick);
            }
            (R::Slr, A(a)) => self.motion.axis_mut(a).step_n_loop.ratio = value,
            (R::Slt, A(a)) => self.motion.axis_mut(a).step_n_loop.tolerance = value,
            (R::Sle, A(a)) => self.motion.axis_mut(a).step_n_loop.error_range = value,
            (R::Sla, A(a)) => self.motion.axis_mut(a).step_n_loop.attempts = value,
            (R::Sactrl, I(n)) => {
                let control = ProgramControl::from_code(value).ok_or(ErrorCode::InvalidIndex)?;
                self.programs.control(usize::from(n), control)?;
            }
            (R::Sload, All) => self.run_on_boot = value,
            (R::Sload, I(n)) => {
                self.run_on_boot = with_bit(self.run_on_boot as u32, u32::from(n), on).into();
            }
            (R::Sap, _) => self.sub31_return = value,
            (R::V, I(n)) => {
                if let Some(v) = self.variables.get_mut(usize::from(n)) {
                    // The parser keeps V writes within 32 bits (§2.7.6).
                    *v =
                        i32::try_from(value).unwrap_or(if value < 0 { i32::MIN } else { i32::MAX });
                }
            }
            _ => return Err(ErrorCode::UnknownCommand),
        }
        Ok(())
    }

    /// Joystick or MPG control keeps motion commands off an axis.
    fn update_manual_control(&mut self) {
        for axis in Axis::ALL {
            let joystick = axis.index() < 2 && self.joystick.enable & (1 << axis.index()) != 0;
            let mpg = self.mpg[axis.index()].enabled;
            self.motion.axis_mut(axis).manual_control = joystick || mpg;
        }
    }

    fn require_stopped(&self, axis: Axis) -> Result<(), ErrorCode> {
        if self.motion.stopped_normally(axis) {
            Ok(())
        } else {
            Err(ErrorCode::ErrorMoving)
        }
    }

    fn act(&mut self, action: Action, selector: Selector) -> Result<(), ErrorCode> {
        let axis = match selector {
            Selector::Axis(a) => Some(a),
            _ => None,
        };
        match action {
            Action::Store => self.store(),
            Action::Estop => self.motion.emergency_stop(),
            Action::Abs => self.motion.global.incremental = false,
            Action::Inc => self.motion.global.incremental = true,
            Action::Stop => self.motion.stop(axis),
            Action::Abort => self.motion.abort(axis),
            Action::Clr => {
                if let Some(a) = axis {
                    self.motion.clear_errors(a);
                }
            }
            Action::BufferOn => self.motion.set_buffer(true),
            Action::BufferOff => self.motion.set_buffer(false),
            Action::BufferStart => self.motion.buffer_start()?,
            Action::SyncOn | Action::SyncOff | Action::SyncWindowOn | Action::SyncWindowOff => {
                let Some(a) = axis else {
                    return Err(ErrorCode::UnknownCommand);
                };
                let (pulse, encoder) = (self.motion.counter(a), self.motion.encoder(a));
                let sync = &mut self.motion.axis_mut(a).sync;
                match action {
                    Action::SyncOn => {
                        let counter = if sync.uses_encoder() { encoder } else { pulse };
                        sync.enable(counter);
                    }
                    Action::SyncOff => sync.disable(),
                    Action::SyncWindowOn => sync.window = true,
                    _ => sync.window = false,
                }
            }
            Action::CallSub => {
                let n = match selector {
                    Selector::Index(n) => usize::from(n),
                    _ => return Err(ErrorCode::InvalidIndex),
                };
                self.programs.call_subroutine(n)?;
            }
        }
        Ok(())
    }

    /// STORE: every register of Table 2-19 into flash (§2.1.7).
    fn store(&mut self) {
        let mut values = BTreeMap::new();
        for row in COMMANDS.iter().filter(|row| row.stored) {
            let Kind::Register(register) = row.kind else {
                continue;
            };
            for selector in selectors(row.form) {
                if let Ok(Value::Int(value)) = self.read(register, selector) {
                    let key = Cmd4crCommand::Read { register, selector }.to_string();
                    values.insert(key, value);
                }
            }
        }
        self.flash.store(values);
    }

    /// Power-on: the stored registers from flash.
    pub(super) fn load_flash(&mut self) {
        let entries: Vec<(String, i64)> = self
            .flash
            .values()
            .iter()
            .map(|(k, &v)| (k.clone(), v))
            .collect();
        for (key, value) in entries {
            if let Ok(Cmd4crCommand::Read { register, selector }) = flash::check_entry(&key, value)
            {
                // Checked against the register's range: the write cannot fail.
                let _ = self.write(register, selector, value);
            }
        }
        self.update_manual_control();
    }
}

/// Every selector of a command-table form.
fn selectors(form: Form) -> Vec<Selector> {
    match form {
        Form::Bare => vec![Selector::All],
        Form::Axis => Axis::ALL.map(Selector::Axis).to_vec(),
        Form::Index { first, last } => (first..=last).map(Selector::Index).collect(),
        Form::Motion => Vec::new(),
    }
}
