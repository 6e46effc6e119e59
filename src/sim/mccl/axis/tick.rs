//! One 1 kHz tick of an axis: the trajectory generator, the motor (a
//! servo's loop samples at its own rate inside the tick), then what is
//! watched (captures, breakpoint, limits, following error, faults,
//! at target, recording, compare).

use super::capture::Sample;
use super::profile::{Phase, ramp_velocity, trapezoid_step};
use super::servo::{Demand, loop_rate};
use super::settings::AxisKind;
use super::{Axis, AxisInputs, CaptureKind, Mode, TORQUE_SPEED_PER_VOLT, status};

/// Why an axis tripped (its status bits and the reaction).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Trip {
    HardLimitPlus,
    HardLimitMinus,
    SoftLimitHigh,
    SoftLimitLow,
    FollowingError,
    AmpFault,
    EncoderFault,
}

impl Trip {
    fn bits(self) -> u32 {
        match self {
            Trip::HardLimitPlus => status::MOTOR_ERROR | status::HARD_LIMIT_PLUS,
            Trip::HardLimitMinus => status::MOTOR_ERROR | status::HARD_LIMIT_MINUS,
            Trip::SoftLimitHigh => status::MOTOR_ERROR | status::SOFT_LIMIT_HIGH,
            Trip::SoftLimitLow => status::MOTOR_ERROR | status::SOFT_LIMIT_LOW,
            Trip::FollowingError => status::MOTOR_ERROR | status::FOLLOWING_ERROR,
            // Ch5 FN names only bit 9 and the motor turning off.
            Trip::AmpFault => status::AMP_FAULT,
            Trip::EncoderFault => status::MOTOR_ERROR | status::ENCODER_FAULT,
        }
    }
}

/// What a tick brought that the controller acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TickEvents {
    pub trip: Option<Trip>,
    /// Position compare events this tick.
    pub compares: u32,
}

impl Axis {
    /// The trajectory generator for an axis that runs its own (not a slave
    /// or a contour member: the controller moves those).
    pub fn trajectory_tick(&mut self, dt: f64) {
        if !self.motor_on {
            self.optimal = self.position();
            self.velocity = 0.0;
            return;
        }
        match self.mode {
            Mode::Position => self.position_tick(dt),
            Mode::Velocity => self.velocity_tick(dt),
            Mode::Gain => {
                self.optimal = self.target;
                self.velocity = 0.0;
                self.phase = Phase::Idle;
            }
            Mode::Torque => {
                self.optimal = self.position();
                self.target = self.optimal;
                self.velocity = 0.0;
            }
            Mode::Contour(_) => {}
        }
        self.note_direction();
    }

    pub fn note_direction(&mut self) {
        if self.velocity != 0.0 {
            self.negative = self.velocity < 0.0;
        }
    }

    fn position_tick(&mut self, dt: f64) {
        if let Some(plan) = &mut self.plan {
            let (p, v, phase) = plan.step(dt);
            let finished = plan.finished();
            (self.optimal, self.velocity, self.phase) = (p, v, phase);
            if finished {
                self.plan = None;
                self.optimal = self.target;
                self.velocity = 0.0;
                self.phase = Phase::Idle;
                self.stopping = false;
            }
            return;
        }
        if self.optimal == self.target && self.velocity == 0.0 {
            self.phase = Phase::Idle;
            self.stopping = false;
            return;
        }
        let rates = self.rates();
        let (p, v, phase) = trapezoid_step(self.optimal, self.velocity, self.target, &rates, dt);
        (self.optimal, self.velocity, self.phase) = (p, v, phase);
        if phase == Phase::Idle {
            self.stopping = false;
        }
    }

    fn velocity_tick(&mut self, dt: f64) {
        let rates = self.rates();
        let goal = match (self.running, self.settings.negative) {
            (false, _) => 0.0,
            (true, false) => rates.velocity,
            (true, true) => -rates.velocity,
        };
        let mut v = ramp_velocity(
            self.velocity,
            goal,
            rates.acceleration,
            rates.deceleration,
            dt,
        );
        // A stepper starts and stops at its minimum velocity (MV).
        if goal != 0.0 && v.abs() < rates.minimum && v * goal >= 0.0 {
            v = goal.signum() * rates.minimum;
        } else if goal == 0.0 && v.abs() < rates.minimum {
            v = 0.0;
        }
        self.phase = if v == 0.0 {
            Phase::Idle
        } else if v.abs() > self.velocity.abs() {
            Phase::Accelerating
        } else if v.abs() < self.velocity.abs() {
            Phase::Decelerating
        } else {
            Phase::Cruising
        };
        self.velocity = v;
        self.optimal += v * dt;
        // In velocity mode the target is where the generator is, so that a
        // stop completes the trajectory (WS ends when it stands).
        self.target = self.optimal;
        if v == 0.0 {
            self.stopping = false;
        }
    }

    /// The motor: a servo's loop runs its samples of this tick (and PR
    /// records each); a stepper's shaft turns with its steps unless stalled.
    pub fn drive_tick(&mut self, dt: f64) {
        if self.kind == AxisKind::Servo {
            self.servo_tick(dt);
            return;
        }
        if !self.motor_on {
            return;
        }
        let scale = if self.is_closed_loop_stepper() {
            self.settings.steps_per_count.max(1e-9)
        } else {
            1.0
        };
        let steps = (self.optimal * scale).round();
        let delta = steps - self.steps;
        self.steps = steps;
        if !self.stalled {
            self.shaft += delta;
            // At an end stop the steps are lost: the counter counts on.
            self.hold_at_end_stop();
        }
    }

    /// An end stop of the stage holds the shaft: it stands at the stop
    /// whatever the motor asks. `true` if it did.
    pub fn hold_at_end_stop(&mut self) -> bool {
        let Some((low, high)) = self.end_stops else {
            return false;
        };
        let held = self.shaft.clamp(low, high);
        if held == self.shaft {
            return false;
        }
        self.shaft = held;
        true
    }

    /// The loop samples of one trajectory tick (Ch5 HS/MS/LS): the
    /// set-point steps from the last tick's optimal position to this one's
    /// (in gain mode it jumps: no profile), the PID-FF law drives the
    /// plant, PR takes a sample. A following error beyond SE ends the
    /// samples; [`Axis::check_tick`] then trips the axis.
    fn servo_tick(&mut self, dt: f64) {
        let rate = loop_rate(self.settings.speed);
        let samples = ((rate * dt).round() as usize).max(1);
        let period = dt / samples as f64;
        let from = if self.mode == Mode::Gain {
            self.optimal
        } else {
            self.servo.setpoint
        };
        let acceleration = (self.velocity - self.servo.last_velocity) / dt;
        self.servo.last_velocity = self.velocity;
        let gains = self.gains();
        let limit = self.units.distance_to_counts(self.settings.following_limit);
        let complete = self.trajectory_complete();
        let step = (self.optimal - from) / samples as f64;
        for k in 1..=samples {
            // The encoder is read at the start of the sample, against the
            // set-point of that instant; the sample ends one step on.
            let read_at = from + step * (k - 1) as f64;
            let setpoint = from + step * k as f64;
            self.servo.setpoint = setpoint;
            let closed = self.motor_on && self.mode != Mode::Torque;
            if closed {
                let demand = Demand {
                    error: read_at - self.position(),
                    velocity: self.velocity,
                    acceleration,
                    complete,
                };
                let volts = self.servo.law(&gains, &demand);
                self.servo.output = self.shape_output(volts);
                let plant = self.servo.plant;
                // A stalled shaft (an input) does not turn, whatever the
                // amplifier asks.
                if !self.stalled {
                    plant.advance(
                        &mut self.shaft,
                        &mut self.servo.speed,
                        self.servo.output,
                        period,
                    );
                    // The stop takes the shaft's momentum: it stands,
                    // and the loop winds up against it until SE trips.
                    if self.hold_at_end_stop() {
                        self.servo.speed = 0.0;
                    }
                }
            } else if self.motor_on && self.mode == Mode::Torque && !self.stalled {
                self.shaft += self.settings.torque * TORQUE_SPEED_PER_VOLT * period;
                self.hold_at_end_stop();
            }
            let sample = Sample {
                actual: self.position(),
                optimal: setpoint,
                output: self.output_voltage(),
                aux: self.aux_position(),
            };
            self.record.tick(sample);
            let error = setpoint - self.position();
            if closed && limit > 0.0 && error.abs() > limit {
                break;
            }
        }
        if self.stalled {
            self.servo.speed = 0.0;
        }
    }

    /// The watched conditions after the motion of this tick; `from` is the
    /// position before it.
    pub fn check_tick(&mut self, dt: f64, from: f64, inputs: AxisInputs) -> TickEvents {
        let here = self.position();
        self.check_captures(from, here, &inputs);
        self.check_breakpoint(here);
        let trip = self.check_trips(&inputs);
        if let Some(trip) = trip {
            self.trip(trip);
        }
        if self.kind == AxisKind::Servo {
            let within = (self.position() - self.target).abs()
                <= self.units.distance_to_counts(self.settings.deadband);
            if self.motor_on && self.trajectory_complete() && within {
                self.settled = Some(self.settled.unwrap_or(0.0) + dt);
            } else {
                self.settled = None;
            }
        }
        let sample = self.sample();
        // A servo records at its loop rate in [`Axis::servo_tick`].
        if self.kind != AxisKind::Servo {
            self.record.tick(sample);
        }
        if inputs.capture && !self.previous_inputs.capture && self.record.capture(sample) {
            self.latched |= status::CAPTURED;
        }
        let compares = self.compare.check(from, here);
        self.previous_inputs = inputs;
        TickEvents { trip, compares }
    }

    pub fn sample(&self) -> Sample {
        Sample {
            actual: self.position(),
            optimal: self.optimal,
            output: self.output_voltage(),
            aux: self.aux_position(),
        }
    }

    /// The first index mark passed going from `from` to `to` (the one at
    /// `from` itself does not count).
    fn mark_between(&self, from: f64, to: f64) -> Option<f64> {
        if from == to || self.index_period <= 0.0 {
            return None;
        }
        let period = self.index_period;
        let k = if to > from {
            ((from - self.index_phase) / period).floor() + 1.0
        } else {
            ((from - self.index_phase) / period).ceil() - 1.0
        };
        let mark = self.index_phase + k * period;
        let passed = if to > from { mark <= to } else { mark >= to };
        passed.then_some(mark)
    }

    fn check_captures(&mut self, from: f64, here: f64, inputs: &AxisInputs) {
        if let Some((kind, value)) = self.homing.armed {
            let captured = match kind {
                CaptureKind::Index => self.mark_between(from, here),
                CaptureKind::Edge => (inputs.home && !self.previous_inputs.home).then_some(here),
            };
            if let Some(at) = captured {
                self.homing.armed = None;
                self.homing.captured = Some((at, value));
                self.latched |= status::FOUND;
                self.index_latched = true;
                if kind == CaptureKind::Index {
                    self.index_position = at;
                }
            }
        }
        if let Some(value) = self.aux_armed {
            let aux_from = from * self.shaft_per_count();
            let aux_here = self.shaft.round();
            if let Some(mark) = self.mark_between(aux_from, aux_here) {
                self.aux_offset = value - mark;
                self.aux_index = value;
                self.aux_armed = None;
                self.aux_found = true;
                self.latched = (self.latched | status::AUX_FOUND) & !status::LOOKING_AUX;
            }
        }
    }

    /// Shaft units (steps) per position count.
    fn shaft_per_count(&self) -> f64 {
        if self.is_closed_loop_stepper() {
            self.settings.steps_per_count.max(1e-9)
        } else {
            1.0
        }
    }

    fn check_breakpoint(&mut self, here: f64) {
        if let Some(b) = self.breakpoint {
            let reached = if b.from_below {
                here >= b.at
            } else {
                here <= b.at
            };
            if reached {
                self.latched |= status::BREAKPOINT;
                self.breakpoint = None;
            }
        }
    }

    /// The direction the axis is being commanded in: +1, −1 or 0.
    pub fn commanded_direction(&self) -> f64 {
        if self.velocity != 0.0 {
            return self.velocity.signum();
        }
        match self.mode {
            Mode::Velocity if self.running => {
                if self.settings.negative {
                    -1.0
                } else {
                    1.0
                }
            }
            Mode::Position | Mode::Gain if self.target != self.optimal => {
                (self.target - self.optimal).signum()
            }
            Mode::Gain if self.target != self.position() => {
                (self.target - self.position()).signum()
            }
            _ => 0.0,
        }
    }

    fn check_trips(&self, inputs: &AxisInputs) -> Option<Trip> {
        if !self.motor_on {
            return None;
        }
        let s = &self.settings;
        if s.fault_check && inputs.fault {
            return Some(Trip::AmpFault);
        }
        if s.encoder_check == 1 && self.encoder_fault && self.is_closed_loop() {
            return Some(Trip::EncoderFault);
        }
        if self.has_motor_error() {
            return None;
        }
        let direction = self.commanded_direction();
        let contour = matches!(self.mode, Mode::Contour(_));
        if s.limits & 1 != 0 && inputs.limit_plus && direction > 0.0 {
            return Some(Trip::HardLimitPlus);
        }
        if s.limits & 2 != 0 && inputs.limit_minus && direction < 0.0 {
            return Some(Trip::HardLimitMinus);
        }
        // Ch5 HL/LL: "the desired or true position" beyond the limit while
        // commanded toward it; in contour mode whatever the direction.
        let here = self.position();
        let high = self.units.to_counts(s.high_limit);
        let low = self.units.to_counts(s.low_limit);
        if s.limits & 4 != 0 && (self.optimal > high || here > high) && (direction > 0.0 || contour)
        {
            return Some(Trip::SoftLimitHigh);
        }
        if s.limits & 8 != 0 && (self.optimal < low || here < low) && (direction < 0.0 || contour) {
            return Some(Trip::SoftLimitLow);
        }
        let limit = self.units.distance_to_counts(s.following_limit);
        if self.is_closed_loop()
            && self.mode != Mode::Torque
            && limit > 0.0
            && self.following_error().abs() > limit
        {
            return Some(Trip::FollowingError);
        }
        None
    }

    /// React to a trip: latch its bits and turn off, stop at once or
    /// decelerate (Ch5 LM for limits; off for the others).
    pub fn trip(&mut self, trip: Trip) {
        self.latched |= trip.bits();
        let action = match trip {
            Trip::HardLimitPlus | Trip::HardLimitMinus => self.settings.hard_limit_action(),
            Trip::SoftLimitHigh | Trip::SoftLimitLow => self.settings.soft_limit_action(),
            _ => 0,
        };
        match action {
            0 => self.motor_off(),
            1 => self.abort(),
            // A contour member is stopped by its group.
            _ => self.stop(),
        }
    }
}
