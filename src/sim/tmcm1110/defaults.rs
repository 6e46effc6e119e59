//! Factory values the manual does not state. Where the parameter tables
//! (`protocol::tmcl::params`) carry a manual default, that wins; motion
//! parameters take the axis model's power-up values; what is left comes from
//! here, and the simulator's help line lists it.

use crate::protocol::tmcl::params;

use super::motion::Axis;

/// Which parameter space a simulator default belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    Axis,
    Bank0,
}

/// A factory value chosen by the simulator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SimDefault {
    pub scope: Scope,
    pub number: u8,
    pub value: i32,
    pub why: &'static str,
}

const fn axis(number: u8, value: i32, why: &'static str) -> SimDefault {
    SimDefault {
        scope: Scope::Axis,
        number,
        value,
        why,
    }
}

const fn bank0(number: u8, value: i32, why: &'static str) -> SimDefault {
    SimDefault {
        scope: Scope::Bank0,
        number,
        value,
        why,
    }
}

/// The simulator's choices (GP66 comes from `SimConfig::address`).
pub const SIM_DEFAULTS: &[SimDefault] = &[
    axis(7, 8, "standby current, §4 says keep it low"),
    axis(162, 2, "chopper blank time"),
    axis(165, 3, "hysteresis end"),
    axis(166, 3, "hysteresis start"),
    axis(167, 5, "off time (0 would switch the driver off)"),
    bank0(76, 2, "host address of every manual example"),
];

/// Module address GP66.
pub const GP_SERIAL_ADDRESS: u8 = 66;

fn sim_default(scope: Scope, number: u8) -> Option<i32> {
    SIM_DEFAULTS
        .iter()
        .find(|d| d.scope == scope && d.number == number)
        .map(|d| d.value)
}

fn table_default(info: Option<&params::ParamInfo>) -> Option<i32> {
    info.and_then(|p| p.default)
        .and_then(|v| i32::try_from(v).ok())
}

/// Factory value of axis parameter `number`. `fresh` is an axis model just
/// powered up, which knows its own defaults.
pub fn axis_factory_value(number: u8, fresh: &Axis) -> i32 {
    if Axis::owns_param(number) {
        return fresh.param(number);
    }
    table_default(params::axis_param(number))
        .or_else(|| sim_default(Scope::Axis, number))
        .unwrap_or(0)
}

/// Factory value of bank-0 parameter `number`.
pub fn bank0_factory_value(number: u8, address: u8) -> i32 {
    if number == GP_SERIAL_ADDRESS {
        return i32::from(address);
    }
    table_default(params::global_param(0, number))
        .or_else(|| sim_default(Scope::Bank0, number))
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simulator_defaults_apply_where_nothing_else_does() {
        let fresh = Axis::new();
        assert_eq!(axis_factory_value(167, &fresh), 5);
        assert_eq!(bank0_factory_value(76, 1), 2);
        assert_eq!(bank0_factory_value(GP_SERIAL_ADDRESS, 7), 7);
        // A parameter nobody gives a default for starts at 0.
        assert_eq!(axis_factory_value(213, &fresh), 0);
    }

    #[test]
    fn motion_parameters_come_from_the_axis_model() {
        let mut fresh = Axis::new();
        fresh.set_param(4, 321);
        assert_eq!(axis_factory_value(4, &fresh), 321);
    }
}
