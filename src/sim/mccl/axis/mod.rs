//! One simulated axis: its settings, the trajectory generator's optimal
//! position, the motor behind it (a servo under its PID-FF loop, or a
//! stepper open or closed loop), limits, homing captures and the status
//! words.
//!
//! Positions inside are encoder counts (servo, closed-loop stepper) or
//! steps (open-loop stepper), as `f64`; the commands convert from and to
//! user units ([`settings::Units`]). Time is the trajectory generator's
//! 1 kHz tick ([`tick`]); a servo's loop runs inside it at its HS/MS/LS
//! rate ([`servo`]).
//!
//! The motor models (the manual gives no motor equations; the choices are
//! listed in [`crate::sim::mccl::choices`]):
//! - a servo's shaft is a [`servo::Plant`] (inertia, viscous and Coulomb
//!   friction, ±10 V amplifier) driven by the manual's PID-FF law (Ch5 SG,
//!   SD, FR, SI, IL, IO, VG, AG, DG) at 4, 2 or 1 kHz (Ch5 HS, MS, LS); it
//!   trails a move (TF, SE trips) and settles into DB after it (WT, DT);
//!   the encoder reads the shaft rounded to a count;
//! - a stepper's shaft turns with every step unless it is stalled (an
//!   input); open loop, its position is the step count; closed loop
//!   (IM1), the encoder reads the shaft in counts of ES steps, and the
//!   trajectory runs in encoder counts.

pub mod capture;
pub mod profile;
pub mod servo;
pub mod settings;
pub mod status;
pub mod tick;

use profile::{Phase, Plan, Rates, Shape};
use settings::{AxisKind, Settings, Units};

pub use capture::{Compare, Record};

/// Torque mode: the unloaded servo runs at this many counts per second per
/// volt of SQ (the manual gives no load model).
pub const TORQUE_SPEED_PER_VOLT: f64 = 1000.0;

/// The default spacing of encoder index marks, in counts, and where the
/// first one is: one mark a revolution of a 500-line encoder (×4).
pub const INDEX_PERIOD: f64 = 2000.0;
pub const INDEX_PHASE: f64 = 500.0;

/// The trajectory mode (Ch6; trajectory status word n = 128).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    Position,
    Velocity,
    Gain,
    Torque,
    /// Contour mode in the group of this controlling axis.
    Contour(u8),
}

/// Master/slave gearing (SM), referenced to both optimal positions when
/// it was issued.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slave {
    pub master: u8,
    pub master_start: f64,
    pub own_start: f64,
}

/// What an armed capture looks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaptureKind {
    /// The encoder index (IA, FI): servos and closed-loop steppers.
    Index,
    /// The home sensor edge (EL, FE): open-loop steppers.
    Edge,
}

/// Homing by capture (Ch7 IA/WI/FI, EL/WE/FE): armed, captured, stored
/// for the next MN.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Homing {
    /// Armed, with the position the captured point is to become.
    pub armed: Option<(CaptureKind, f64)>,
    /// The captured raw position and the value it is to become.
    pub captured: Option<(f64, f64)>,
    /// WI/WE stored the capture: the next MN redefines the position.
    pub stored: bool,
}

/// An IP/IR/WP/WR breakpoint, in counts, and on which side it was set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Breakpoint {
    pub at: f64,
    pub from_below: bool,
}

/// The inputs an axis reads this tick, as logical levels after CH/CL (and
/// LM + 128 for the hard limits).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AxisInputs {
    pub limit_plus: bool,
    pub limit_minus: bool,
    /// Coarse home (servo) or the stepper home sensor.
    pub home: bool,
    pub fault: bool,
    /// The capture input of the axis (Ch9 channels 1, 5, 9, 13).
    pub capture: bool,
}

/// One axis.
#[derive(Debug, Clone)]
pub struct Axis {
    pub number: u8,
    pub kind: AxisKind,
    pub settings: Settings,
    /// The user units in force.
    pub units: Units,
    pub mode: Mode,
    pub slave: Option<Slave>,
    pub motor_on: bool,
    // ---- trajectory (counts, counts/s) ----
    pub optimal: f64,
    pub velocity: f64,
    pub target: f64,
    pub phase: Phase,
    pub plan: Option<Plan>,
    /// Velocity mode: GO given, not yet stopped.
    pub running: bool,
    /// ST (or a smooth limit stop) under way.
    pub stopping: bool,
    /// Direction of the last motion (status bit 4).
    pub negative: bool,
    // ---- the motor ----
    /// The shaft: counts (servo) or steps (stepper).
    pub shaft: f64,
    /// Steps given (stepper).
    pub steps: f64,
    /// An input holds the shaft still.
    pub stalled: bool,
    /// An input reports an encoder fault.
    pub encoder_fault: bool,
    /// The demo stage's hard end stops, shaft units: the shaft goes no
    /// further (see `sim::mccl::stage`).
    pub end_stops: Option<(f64, f64)>,
    /// Where index marks are, in position counts: phase + k × period.
    pub index_phase: f64,
    pub index_period: f64,
    // ---- status ----
    /// Latched bits of the primary status word.
    pub latched: u32,
    /// Seconds within DB of the target with the trajectory complete, the
    /// last tick included; `None` while not within it.
    pub settled: Option<f64>,
    pub breakpoint: Option<Breakpoint>,
    /// Last breakpoint position set, counts (TB).
    pub breakpoint_at: f64,
    pub homing: Homing,
    /// The index mark latched after a capture (bit 24) until MF/MN.
    pub index_latched: bool,
    /// Where the last captured index was, counts (TZ).
    pub index_position: f64,
    /// Where GH goes: the value of the last DH or homing, counts.
    pub home_position: f64,
    pub previous_inputs: AxisInputs,
    // ---- auxiliary encoder (steppers) ----
    pub aux_offset: f64,
    pub aux_armed: Option<f64>,
    pub aux_found: bool,
    pub aux_index: f64,
    // ---- capture, compare, record ----
    pub record: Record,
    pub compare: Compare,
    /// Contour count (TX) of a controlling axis.
    pub contour_count: u32,
    /// The servo loop and its motor (servos only).
    pub servo: servo::Servo,
}

impl Axis {
    pub fn new(number: u8, kind: AxisKind) -> Axis {
        Axis {
            number,
            kind,
            settings: Settings::factory(kind),
            units: Units::default(),
            mode: Mode::Position,
            slave: None,
            motor_on: false,
            optimal: 0.0,
            velocity: 0.0,
            target: 0.0,
            phase: Phase::Idle,
            plan: None,
            running: false,
            stopping: false,
            negative: false,
            shaft: 0.0,
            steps: 0.0,
            stalled: false,
            encoder_fault: false,
            end_stops: None,
            index_phase: INDEX_PHASE,
            index_period: INDEX_PERIOD,
            latched: 0,
            settled: None,
            breakpoint: None,
            breakpoint_at: 0.0,
            homing: Homing::default(),
            index_latched: false,
            index_position: 0.0,
            home_position: 0.0,
            previous_inputs: AxisInputs::default(),
            aux_offset: 0.0,
            aux_armed: None,
            aux_found: false,
            aux_index: 0.0,
            record: Record::default(),
            compare: Compare::default(),
            contour_count: 0,
            servo: servo::Servo::new(),
        }
    }

    /// RT for one axis: factory settings, motor off, position mode. The
    /// shaft stays where it is; the counters keep counting (the manual
    /// does not say a reset clears them).
    pub fn reset(&mut self) {
        let fresh = Axis::new(self.number, self.kind);
        let (shaft, steps, position) = (self.shaft, self.steps, self.position());
        let plant = self.servo.plant;
        let (stalled, fault, index_phase, index_period) = (
            self.stalled,
            self.encoder_fault,
            self.index_phase,
            self.index_period,
        );
        let end_stops = self.end_stops;
        *self = fresh;
        self.end_stops = end_stops;
        self.shaft = shaft;
        self.steps = steps;
        self.stalled = stalled;
        self.encoder_fault = fault;
        self.index_phase = index_phase;
        self.index_period = index_period;
        self.optimal = position;
        self.target = position;
        self.servo.plant = plant;
        self.servo.setpoint = position;
    }

    pub fn is_servo(&self) -> bool {
        self.kind == AxisKind::Servo
    }

    /// A stepper with encoder feedback (IM1).
    pub fn is_closed_loop_stepper(&self) -> bool {
        self.kind == AxisKind::Stepper && self.settings.input_mode == 1
    }

    pub fn is_open_loop_stepper(&self) -> bool {
        self.kind == AxisKind::Stepper && self.settings.input_mode != 1
    }

    /// Servo or closed-loop stepper: has a following error.
    pub fn is_closed_loop(&self) -> bool {
        !self.is_open_loop_stepper()
    }

    /// Steps per position count: ES closed loop, else 1.
    fn step_scale(&self) -> f64 {
        if self.is_closed_loop_stepper() {
            self.settings.steps_per_count.max(1e-9)
        } else {
            1.0
        }
    }

    /// The actual position in counts (TP): the encoder of a servo or a
    /// closed-loop stepper, the step count of an open-loop one.
    pub fn position(&self) -> f64 {
        match self.kind {
            AxisKind::Servo => self.shaft.round(),
            AxisKind::Stepper if self.is_closed_loop_stepper() => {
                (self.shaft / self.step_scale()).round()
            }
            AxisKind::Stepper => self.steps.round(),
        }
    }

    /// The auxiliary encoder (a stepper's shaft, read in steps).
    pub fn aux_position(&self) -> f64 {
        self.shaft.round() + self.aux_offset
    }

    pub fn following_error(&self) -> f64 {
        self.optimal - self.position()
    }

    /// The speeds and rates of a move now, in counts and seconds.
    pub fn rates(&self) -> Rates {
        let s = &self.settings;
        let u = &self.units;
        let mut velocity = u.speed_to_counts(s.velocity) * s.velocity_override;
        let mut minimum = 0.0;
        if self.kind == AxisKind::Stepper {
            let (low, high) = s.speed.pulse_range();
            let per_count = self.step_scale();
            velocity = velocity.min(high / per_count);
            minimum = (u.speed_to_counts(s.minimum_velocity).max(low / per_count)).min(velocity);
        }
        Rates {
            velocity,
            acceleration: u.acceleration_to_counts(s.acceleration),
            deceleration: u.acceleration_to_counts(s.deceleration),
            minimum,
        }
    }

    /// The trajectory is done: nothing planned, running or moving, and the
    /// optimal position on the target (status bit 3; a stepper's actual
    /// position must be there too). A motor that is off has none.
    pub fn trajectory_complete(&self) -> bool {
        if !self.motor_on {
            return true;
        }
        if let Mode::Contour(_) = self.mode {
            return self.phase == Phase::Idle && self.optimal == self.target;
        }
        let generated = self.plan.is_none()
            && !self.running
            && self.velocity == 0.0
            && (self.optimal == self.target || self.mode == Mode::Torque);
        match self.kind {
            AxisKind::Servo => generated,
            AxisKind::Stepper => generated && self.position() == self.target.round(),
        }
    }

    /// Status bit 2: a servo within DB for DT, a stepper on its target.
    pub fn at_target(&self) -> bool {
        if !self.motor_on || !self.trajectory_complete() {
            return false;
        }
        match self.kind {
            AxisKind::Servo => self
                .settled
                .is_some_and(|t| t >= self.settings.target_delay - 1e-9),
            AxisKind::Stepper => self.position() == self.target.round(),
        }
    }

    /// Primary status bit 0: a limit, following error or encoder fault
    /// tripped, and no MN since.
    pub fn has_motor_error(&self) -> bool {
        self.latched & status::MOTOR_ERROR != 0
    }

    // ---- commands --------------------------------------------------

    /// MN (Ch7): if off, target and optimal take the current position; the
    /// latched errors clear; user units and a stored homing capture apply.
    pub fn motor_on(&mut self) {
        self.units = self.settings.units;
        if let (true, Some((raw, value))) = (self.homing.stored, self.homing.captured) {
            self.redefine(value - raw);
            self.home_position = value;
            self.latched |= status::HOMED;
            self.latched &= !status::FOUND;
            self.homing = Homing::default();
        }
        if !self.motor_on {
            let position = self.position();
            self.optimal = position;
            self.target = position;
            self.velocity = 0.0;
            self.plan = None;
            self.running = false;
            self.stopping = false;
            self.phase = Phase::Idle;
            self.servo.clear(position);
            if self.kind == AxisKind::Stepper {
                self.steps = (position * self.step_scale()).round();
                if self.is_closed_loop_stepper() {
                    self.steps = self.shaft.round();
                }
            }
        }
        self.motor_on = true;
        self.latched &= !status::CLEARED_BY_MOTOR_ON;
        self.index_latched = false;
    }

    /// MF: output off; the trajectory ends where the shaft is.
    pub fn motor_off(&mut self) {
        self.motor_on = false;
        self.velocity = 0.0;
        self.plan = None;
        self.running = false;
        self.stopping = false;
        self.phase = Phase::Idle;
        self.optimal = self.position();
        self.settled = None;
        self.index_latched = false;
        // The simulator holds the shaft where the amplifier let go (no
        // coasting), as its earlier model did.
        self.servo.clear(self.optimal);
    }

    /// A new target (MA, MR, MP, GH): only the target if the motor is off
    /// (Ch7 MA); otherwise the move starts at once.
    pub fn move_to(&mut self, target: f64) {
        self.target = target;
        self.stopping = false;
        if !self.motor_on {
            return;
        }
        match self.mode {
            Mode::Position => {
                let at_rest = self.velocity == 0.0 && self.plan.is_none();
                self.plan = match self.settings.profile {
                    Shape::Trapezoid => None,
                    shape if at_rest => Plan::new(shape, self.optimal, target, &self.rates()),
                    // A PS/PP move given a new target goes on as a trapezoid.
                    _ => None,
                };
                self.settled = None;
            }
            Mode::Gain => {
                self.optimal = target;
                self.settled = None;
            }
            _ => {}
        }
    }

    /// ST (Ch7): decelerate at DS. In position mode the target becomes the
    /// point where it stops, so that WS ends there.
    pub fn stop(&mut self) {
        match self.mode {
            Mode::Velocity => {
                self.running = false;
                self.stopping = self.velocity != 0.0;
            }
            Mode::Position if self.motor_on => {
                let d = self.rates().deceleration.max(1e-9);
                let v = self.velocity;
                self.plan = None;
                self.target = self.optimal + v.signum() * v * v / (2.0 * d);
                self.stopping = v != 0.0;
            }
            _ => {}
        }
    }

    /// AB (Ch7): stop at once; the target becomes the present position.
    pub fn abort(&mut self) {
        let here = self.position();
        self.plan = None;
        self.running = false;
        self.stopping = false;
        self.velocity = 0.0;
        self.phase = Phase::Idle;
        self.target = here;
        self.optimal = here;
        self.servo.setpoint = here;
        if self.kind == AxisKind::Stepper && !self.is_closed_loop_stepper() {
            self.steps = here;
        }
    }

    /// GO in velocity mode: run in DI's direction at SV.
    pub fn go(&mut self) {
        if self.mode == Mode::Velocity && self.motor_on {
            self.running = true;
            self.stopping = false;
        }
    }

    /// DH and a homing MN: every position of the axis moves by `offset`
    /// counts (the counters are redefined; nothing moves).
    pub fn redefine(&mut self, offset: f64) {
        match self.kind {
            AxisKind::Servo => self.shaft += offset,
            AxisKind::Stepper => {
                let scale = self.step_scale();
                self.shaft += offset * scale;
                self.steps += offset * scale;
            }
        }
        self.optimal += offset;
        self.target += offset;
        self.servo.setpoint += offset;
        self.index_phase += offset;
        self.index_position += offset;
        if let Some(b) = &mut self.breakpoint {
            b.at += offset;
        }
    }

    /// Arm a breakpoint at `at` counts (IP, IR, WP, WR); bit 6 clears.
    pub fn set_breakpoint(&mut self, at: f64) {
        self.latched &= !status::BREAKPOINT;
        self.breakpoint_at = at;
        let here = self.position();
        if here == at {
            self.latched |= status::BREAKPOINT;
            self.breakpoint = None;
        } else {
            self.breakpoint = Some(Breakpoint {
                at,
                from_below: here < at,
            });
        }
    }

    /// IA / FI (index) or EL / FE (edge): look for it; bit 17 sets.
    pub fn arm_capture(&mut self, kind: CaptureKind, value: f64) {
        self.homing = Homing {
            armed: Some((kind, value)),
            captured: None,
            stored: false,
        };
        self.latched |= status::LOOKING;
        self.latched &= !status::FOUND;
    }

    /// WI / WE after the capture: keep it for the next MN; bit 17 clears.
    pub fn store_capture(&mut self) {
        self.homing.stored = true;
        self.latched &= !status::LOOKING;
    }

    /// Change the loop of a stepper (IM): the trajectory is re-based on the
    /// position in the new units.
    pub fn set_input_mode(&mut self, mode: u8) {
        self.settings.input_mode = mode;
        let position = self.position();
        self.optimal = position;
        self.target = position;
        self.velocity = 0.0;
        self.plan = None;
    }

    /// A setting of the user units: in force at once while the motor is
    /// off (Ch5 US: "Beginning with firmware rev. 2.8a").
    pub fn units_changed(&mut self) {
        if !self.motor_on {
            self.units = self.settings.units;
        }
    }

    /// Output voltage (DQ, ID4): the servo loop's last output
    /// ([`servo`]); SQ itself in torque mode.
    pub fn output_voltage(&self) -> f64 {
        if !self.motor_on || self.kind != AxisKind::Servo {
            return 0.0;
        }
        if self.mode == Mode::Torque {
            return self.settings.torque;
        }
        self.servo.output
    }

    /// The PID-FF law's volts after PH, OB and OO, limited to SQ and the
    /// amplifier's ±10 V (Ch5 PH, OB, OO, SQ).
    pub fn shape_output(&self, volts: f64) -> f64 {
        let s = &self.settings;
        let mut volts = volts;
        if s.reverse_phase {
            volts = -volts;
        }
        if volts != 0.0 {
            volts += volts.signum() * s.output_deadband;
        }
        let limit = s.torque.abs().min(servo::AMPLIFIER_VOLTS);
        (volts + s.output_offset).clamp(-limit, limit)
    }

    /// The gains of Ch5 as the loop reads them.
    pub fn gains(&self) -> servo::Gains {
        let s = &self.settings;
        let contour = matches!(self.mode, Mode::Contour(_));
        let per_speed = 1.0 / s.output_constant.max(1e-9);
        servo::Gains {
            proportional: s.proportional_gain,
            derivative: s.derivative_gain,
            derivative_period: usize::try_from(s.derivative_period.max(0)).unwrap_or(0),
            integral: s.integral_gain,
            integration_limit: s.integration_limit,
            integral_option: s.integral_option,
            velocity: s.velocity_gain * per_speed,
            // Ch5 AG/DG: "not calculated when a motor is in contour mode".
            acceleration: if contour { 0.0 } else { s.acceleration_gain },
            deceleration: if contour { 0.0 } else { s.deceleration_gain },
        }
    }
}

#[cfg(test)]
mod tests;
