//! Unit conversions of manual §6.1: TMC429 internal velocity and
//! acceleration units ↔ microsteps per second (pps), pps², full steps, rps
//! and rpm.

/// The TMC429 motion controller clock in the §6.1 formulas (16·10⁶).
pub const CLOCK_HZ: f64 = 16.0e6;

/// Largest magnitude of an internal velocity or acceleration value (§6.1.1).
pub const MAX_INTERNAL: i32 = 2047;

/// §6.1.1 equation (1): internal velocity → microsteps per second.
/// `pulse_div` is axis parameter 154 (0..13).
pub fn velocity_to_pps(velocity_int: i32, pulse_div: u8) -> f64 {
    CLOCK_HZ * f64::from(velocity_int) / (pow2(i32::from(pulse_div)) * 2048.0 * 32.0)
}

/// Inverse of [`velocity_to_pps`], rounded to the nearest internal unit and
/// clamped to ±2047.
pub fn pps_to_velocity(pps: f64, pulse_div: u8) -> i32 {
    let raw = pps * pow2(i32::from(pulse_div)) * 2048.0 * 32.0 / CLOCK_HZ;
    clamp_internal(raw)
}

/// §6.1.2 equation (3): internal acceleration → microsteps per second².
/// `ramp_div` is axis parameter 153, `pulse_div` axis parameter 154.
pub fn acceleration_to_pps2(accel_int: i32, ramp_div: u8, pulse_div: u8) -> f64 {
    CLOCK_HZ * CLOCK_HZ * f64::from(accel_int)
        / pow2(i32::from(ramp_div) + i32::from(pulse_div) + 29)
}

/// Inverse of [`acceleration_to_pps2`], rounded and clamped to ±2047.
pub fn pps2_to_acceleration(pps2: f64, ramp_div: u8, pulse_div: u8) -> i32 {
    let raw = pps2 * pow2(i32::from(ramp_div) + i32::from(pulse_div) + 29) / (CLOCK_HZ * CLOCK_HZ);
    clamp_internal(raw)
}

/// §6.1.3: the acceleration values usable for positioning ramps (MVP) with
/// the given divisors, as (lower, upper) internal units. Velocity mode is not
/// limited by this window. The lower limit may be a fraction (e.g. 0.25)
/// when the ramp divisor is below the pulse divisor.
pub fn positioning_acceleration_window(ramp_div: u8, pulse_div: u8) -> (f64, f64) {
    let diff = i32::from(ramp_div) - i32::from(pulse_div);
    let lower = pow2(diff - 1);
    let upper = (pow2(diff + 12) - 1.0).min(f64::from(MAX_INTERNAL));
    (lower, upper)
}

/// §6.1.1 equation (2): microstep frequency → full-step frequency, with
/// axis parameter 140 (microstep resolution exponent, 0..8).
pub fn pps_to_fullsteps(pps: f64, microstep_resolution: u8) -> f64 {
    pps / pow2(i32::from(microstep_resolution))
}

/// §6.1.4: microsteps per second → revolutions per second, for a motor of
/// `fullsteps_per_rev` full steps (200 for most 1.8° motors).
pub fn pps_to_rps(pps: f64, fullsteps_per_rev: u32, microstep_resolution: u8) -> f64 {
    pps / (f64::from(fullsteps_per_rev) * pow2(i32::from(microstep_resolution)))
}

/// §6.1.4: microsteps per second → revolutions per minute.
pub fn pps_to_rpm(pps: f64, fullsteps_per_rev: u32, microstep_resolution: u8) -> f64 {
    pps_to_rps(pps, fullsteps_per_rev, microstep_resolution) * 60.0
}

/// §6.1.4 inverse: revolutions per minute → microsteps per second.
pub fn rpm_to_pps(rpm: f64, fullsteps_per_rev: u32, microstep_resolution: u8) -> f64 {
    rpm / 60.0 * f64::from(fullsteps_per_rev) * pow2(i32::from(microstep_resolution))
}

fn pow2(exponent: i32) -> f64 {
    2f64.powi(exponent)
}

fn clamp_internal(raw: f64) -> i32 {
    let limit = f64::from(MAX_INTERNAL);
    raw.round().clamp(-limit, limit) as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tolerance: f64) -> bool {
        (a - b).abs() <= tolerance
    }

    #[test]
    fn velocity_example_of_6_1_1() {
        // "a velocity value of 1678 and a pulse divisor of 3 … approximately 51208.5pps"
        let pps = velocity_to_pps(1678, 3);
        assert!(close(pps, 51208.5, 0.1), "{pps}");
        assert_eq!(pps_to_velocity(pps, 3), 1678);
        assert_eq!(pps_to_velocity(51200.0, 3), 1678);
    }

    #[test]
    fn acceleration_example_of_6_1_2() {
        // "an acceleration value of 100 … ramp divisor of 7 … pulse divisor of 3
        // … approximately 46566pps²"
        let pps2 = acceleration_to_pps2(100, 7, 3);
        assert!(close(pps2, 46566.0, 1.0), "{pps2}");
        assert_eq!(pps2_to_acceleration(pps2, 7, 3), 100);
    }

    #[test]
    fn rpm_example_of_6_1_4() {
        // "a 200 fullsteps motor and a microstep setting of 256 … 51200pps will
        // result in 1rps (60rpm)"
        assert!(close(pps_to_rps(51200.0, 200, 8), 1.0, 1e-12));
        assert!(close(pps_to_rpm(51200.0, 200, 8), 60.0, 1e-9));
        assert!(close(rpm_to_pps(60.0, 200, 8), 51200.0, 1e-9));
        assert!(close(pps_to_fullsteps(51200.0, 8), 200.0, 1e-12));
    }

    #[test]
    fn acceleration_window_of_6_1_3() {
        // rd = pd: 2^-1 .. 2^12 − 1 = 4095, capped at 2047.
        assert_eq!(positioning_acceleration_window(3, 3), (0.5, 2047.0));
        // rd − pd = 4: 8 .. capped.
        assert_eq!(positioning_acceleration_window(7, 3), (8.0, 2047.0));
        // rd − pd = −3: 1/16 .. 511.
        assert_eq!(positioning_acceleration_window(0, 3), (0.0625, 511.0));
    }

    #[test]
    fn inverse_conversions_clamp_to_the_internal_range() {
        assert_eq!(pps_to_velocity(1.0e9, 0), 2047);
        assert_eq!(pps_to_velocity(-1.0e9, 0), -2047);
        assert_eq!(pps2_to_acceleration(1.0e12, 0, 0), 2047);
    }
}
