//! The servo loop of an Analog Command Axis and the motor it drives.
//!
//! The controller (manual Ch5): the PID-FF filter runs at the loop rate of
//! HS (4 kHz), MS (2 kHz) or LS (1 kHz); each sample it reads the encoder,
//! takes the following error e = optimal − actual (Ch8 TF) and outputs
//!
//! ```text
//! volts = SG·e                                  proportional, V/count (Ch5 SG)
//!       + SD·(e − e[FR+1 samples ago])          derivative over the derivative
//!                                               sampling period (FR+1)·T (Ch5 FR)
//!       + SI·clamp(Σe, ±IL)                     integral; nothing while IL = 0;
//!                                               Σe in counts × samples (Ch5 SI, IL, IO)
//!       + VG·v + AG·a (accelerating) or DG·a (decelerating)
//!                                               feed-forward of the trajectory's
//!                                               velocity and acceleration (Ch5 VG, AG, DG;
//!                                               none in contour mode)
//! ```
//!
//! then PH reverses it, OB and OO add, and it is limited to SQ and to the
//! ±10 V of the amplifier command (Ch2 "Analog Command Axis").
//!
//! The motor (the manual has none; the simulator's [`Plant`]): the amplifier
//! turns volts into acceleration, the load has viscous and Coulomb friction:
//!
//! ```text
//! dv/dt = gain·volts − viscous·v − coulomb·sign(v)
//! ```
//!
//! with stiction: standing, the shaft stays until gain·|volts| exceeds the
//! Coulomb term. The defaults ([`Plant::DEFAULT`]) make the manual's own
//! example gains (SG 0.04, SD 0.2, FR 0, HS) well damped: a 20-count step
//! overshoots by about 4 % and settles in under 10 ms; at cruise the
//! viscous term asks 4 V at 100000 counts/s, a following error of 100
//! counts at SG 0.04 (the 1 ms lag of the earlier model).

use super::settings::Speed;

/// The amplifier command range, volts (Ch2: ±10 V analog command).
pub const AMPLIFIER_VOLTS: f64 = 10.0;

/// The loop rate of a servo, samples per second (Ch5 HS 4 kHz, MS 2 kHz,
/// LS 1 kHz).
pub fn loop_rate(speed: Speed) -> f64 {
    match speed {
        Speed::High => 4000.0,
        Speed::Medium => 2000.0,
        Speed::Low => 1000.0,
    }
}

/// The sample period, seconds.
pub fn sample_period(speed: Speed) -> f64 {
    1.0 / loop_rate(speed)
}

/// The motor and load behind the amplifier, in encoder counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plant {
    /// Acceleration per volt of command, counts/s² per V.
    pub gain: f64,
    /// Viscous friction, 1/s (deceleration per count/s of speed).
    pub viscous: f64,
    /// Coulomb friction, counts/s².
    pub coulomb: f64,
}

impl Plant {
    /// 10⁷ counts/s² per volt, viscous 400/s (2.5 ms mechanical time
    /// constant), Coulomb friction worth 5 mV of command.
    pub const DEFAULT: Plant = Plant {
        gain: 1.0e7,
        viscous: 400.0,
        coulomb: 0.005 * 1.0e7,
    };

    /// Advance the shaft (`position`, `velocity`) by `dt` seconds under a
    /// constant command of `volts`: exact for the linear part in a few
    /// sub-steps, the Coulomb term holding a standing shaft.
    pub fn advance(&self, position: &mut f64, velocity: &mut f64, volts: f64, dt: f64) {
        const SUBSTEPS: usize = 4;
        let h = dt / SUBSTEPS as f64;
        let drive = self.gain * volts;
        for _ in 0..SUBSTEPS {
            let v = *velocity;
            if v == 0.0 && drive.abs() <= self.coulomb {
                continue;
            }
            let direction = if v != 0.0 { v.signum() } else { drive.signum() };
            let net = drive - self.coulomb * direction;
            let (next, moved) = if self.viscous > 0.0 {
                let terminal = net / self.viscous;
                let decay = (-self.viscous * h).exp();
                let next = terminal + (v - terminal) * decay;
                (
                    next,
                    terminal * h + (v - terminal) * (1.0 - decay) / self.viscous,
                )
            } else {
                (v + net * h, (v + net * h / 2.0) * h)
            };
            if v != 0.0 && next * v < 0.0 && drive.abs() <= self.coulomb {
                // Friction stops it; it does not push it back.
                *position += v * h / 2.0;
                *velocity = 0.0;
            } else {
                *position += moved;
                *velocity = next;
            }
        }
    }
}

impl Default for Plant {
    fn default() -> Self {
        Plant::DEFAULT
    }
}

/// The state of the servo loop and its motor.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Servo {
    pub plant: Plant,
    /// Shaft speed, counts/s.
    pub speed: f64,
    /// Σe, limited to ±IL.
    pub integral: f64,
    /// Following errors of the last samples, newest last (the derivative
    /// looks FR + 1 back).
    pub errors: Vec<f64>,
    /// The optimal position at the last loop sample (the set-point is
    /// interpolated between trajectory ticks).
    pub setpoint: f64,
    /// The trajectory's speed at the last trajectory tick (AG/DG).
    pub last_velocity: f64,
    /// The command output of the last sample, volts (DQ, ID4).
    pub output: f64,
}

/// The gains the loop reads, in the units of Ch5 (volts, counts, samples).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Gains {
    pub proportional: f64,
    pub derivative: f64,
    /// FR: the derivative looks this + 1 samples back.
    pub derivative_period: usize,
    pub integral: f64,
    pub integration_limit: f64,
    /// IO: 0 always, 1 frozen while the trajectory runs, 2 zeroed at a
    /// start and off until the trajectory completes.
    pub integral_option: u8,
    pub velocity: f64,
    pub acceleration: f64,
    pub deceleration: f64,
}

/// What the trajectory asks of one sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Demand {
    pub error: f64,
    /// Trajectory speed, counts/s.
    pub velocity: f64,
    /// Trajectory acceleration, counts/s² (0 in contour mode).
    pub acceleration: f64,
    /// The trajectory is complete (status bit 3), for IO.
    pub complete: bool,
}

impl Servo {
    pub fn new() -> Servo {
        Servo::default()
    }

    /// MN from off, MF, a trip: the loop forgets its history.
    pub fn clear(&mut self, setpoint: f64) {
        self.integral = 0.0;
        self.errors.clear();
        self.setpoint = setpoint;
        self.output = 0.0;
        self.speed = 0.0;
    }

    /// The PID-FF law of one sample, volts before PH, OB, OO and limits.
    pub fn law(&mut self, gains: &Gains, demand: &Demand) -> f64 {
        let e = demand.error;
        let back = gains.derivative_period + 1;
        let previous = if self.errors.len() >= back {
            self.errors[self.errors.len() - back]
        } else {
            self.errors.first().copied().unwrap_or(e)
        };
        self.errors.push(e);
        if self.errors.len() > back {
            let extra = self.errors.len() - back;
            self.errors.drain(..extra);
        }
        let limit = gains.integration_limit.max(0.0);
        match gains.integral_option {
            1 if !demand.complete => {}
            2 if !demand.complete => self.integral = 0.0,
            _ => self.integral = (self.integral + e).clamp(-limit, limit),
        }
        let speeding_up = demand.acceleration * demand.velocity > 0.0;
        let feed_forward_acceleration = if demand.acceleration == 0.0 {
            0.0
        } else if speeding_up {
            gains.acceleration * demand.acceleration
        } else {
            gains.deceleration * demand.acceleration
        };
        gains.proportional * e
            + gains.derivative * (e - previous)
            + gains.integral * self.integral
            + gains.velocity * demand.velocity
            + feed_forward_acceleration
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_loop_rates_are_the_manuals() {
        // Ch5 HS 4 kHz, MS 2 kHz, LS 1 kHz; FR's default period 0.00025 s
        // is one HS sample, FR7 "2 msec" is 8 of them.
        assert_eq!(loop_rate(Speed::High), 4000.0);
        assert_eq!(loop_rate(Speed::Medium), 2000.0);
        assert_eq!(loop_rate(Speed::Low), 1000.0);
        assert_eq!(sample_period(Speed::High), 0.00025);
        assert_eq!(8.0 * sample_period(Speed::High), 0.002);
    }

    #[test]
    fn velocity_gain_gives_the_manuals_minus_one_volt() {
        // Ch5 VG: -0.0001 at 10000 counts/s is -1 V.
        let mut servo = Servo::new();
        let gains = Gains {
            velocity: -0.0001,
            ..Gains::default()
        };
        let demand = Demand {
            velocity: 10_000.0,
            ..Demand::default()
        };
        assert!((servo.law(&gains, &demand) + 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_integral_needs_a_limit_and_stops_at_it() {
        // Ch5 SI: "Integration Limit (IL) command must be set to a nonzero
        // value before integral gain will have any effect."
        let mut servo = Servo::new();
        let mut gains = Gains {
            integral: 0.0065,
            ..Gains::default()
        };
        let demand = Demand {
            error: 10.0,
            complete: true,
            ..Demand::default()
        };
        assert_eq!(servo.law(&gains, &demand), 0.0);
        gains.integration_limit = 50.0;
        let volts: Vec<f64> = (0..8).map(|_| servo.law(&gains, &demand)).collect();
        assert!((volts[0] - 0.065).abs() < 1e-12);
        // 10, 20, … counts × samples until IL 50: 0.0065 × 50 = 0.325 V.
        assert!((volts[7] - 0.325).abs() < 1e-12);
        // IO2: zeroed while the trajectory runs.
        gains.integral_option = 2;
        let moving = Demand {
            complete: false,
            ..demand
        };
        assert_eq!(servo.law(&gains, &moving), 0.0);
    }

    #[test]
    fn the_derivative_looks_fr_plus_one_samples_back() {
        let mut servo = Servo::new();
        let gains = Gains {
            derivative: 0.2,
            derivative_period: 2,
            ..Gains::default()
        };
        let outputs: Vec<f64> = [0.0, 1.0, 2.0, 3.0, 4.0]
            .iter()
            .map(|&error| {
                servo.law(
                    &gains,
                    &Demand {
                        error,
                        ..Demand::default()
                    },
                )
            })
            .collect();
        // At 3 the error 3 samples back was 0; at 4 it was 1.
        assert!((outputs[3] - 0.6).abs() < 1e-12, "{outputs:?}");
        assert!((outputs[4] - 0.6).abs() < 1e-12, "{outputs:?}");
    }

    #[test]
    fn feed_forward_takes_ag_speeding_up_and_dg_slowing_down() {
        let gains = Gains {
            acceleration: 0.001,
            deceleration: 0.002,
            ..Gains::default()
        };
        let mut servo = Servo::new();
        let up = Demand {
            velocity: 100.0,
            acceleration: 1000.0,
            ..Demand::default()
        };
        let down = Demand {
            acceleration: -1000.0,
            ..up
        };
        assert!((servo.law(&gains, &up) - 1.0).abs() < 1e-12);
        assert!((servo.law(&gains, &down) + 2.0).abs() < 1e-12);
    }

    #[test]
    fn friction_holds_a_standing_shaft_and_stops_a_coasting_one() {
        let plant = Plant::DEFAULT;
        let (mut x, mut v) = (0.0, 0.0);
        plant.advance(&mut x, &mut v, 0.004, 0.001);
        assert_eq!((x, v), (0.0, 0.0), "4 mV is below the 5 mV of friction");
        plant.advance(&mut x, &mut v, 1.0, 0.001);
        assert!(x > 0.0 && v > 0.0);
        // Unpowered it coasts to a stop and stays.
        for _ in 0..200 {
            plant.advance(&mut x, &mut v, 0.0, 0.001);
        }
        assert_eq!(v, 0.0);
        // Terminal speed at 4 V: gain × 4 / viscous − friction = 100000 −
        // 125 counts/s.
        for _ in 0..100 {
            plant.advance(&mut x, &mut v, 4.0, 0.001);
        }
        assert!((v - (1.0e5 - 125.0)).abs() < 1.0, "{v}");
    }
}
