//! Simulated controllers. Each is a plain state machine driven by bytes in
//! (`feed`) and virtual time (`advance`); what it answers is collected with
//! `take_output`. Nothing here sleeps or touches a clock, so tests are
//! deterministic; the real-time servers in `cli` drive them from the wall clock.

use std::time::Duration;

pub mod tmcm1110;

/// A controller that can stand behind a link in place of hardware.
pub trait SimulatedController: Send {
    /// Bytes arriving from the host, in order, possibly split anywhere.
    fn feed(&mut self, bytes: &[u8]);
    /// Let `dt` of virtual time pass (motion, timers, delayed replies).
    fn advance(&mut self, dt: Duration);
    /// Bytes the controller has sent since the last call.
    fn take_output(&mut self) -> Vec<u8>;
}

/// Options common to every simulator kind.
#[derive(Debug, Clone, Default)]
pub struct SimOptions {
    /// Module address on the simulated bus; the family's default when `None`.
    pub address: Option<u8>,
    /// File keeping the simulated EEPROM/flash between runs.
    pub eeprom_file: Option<std::path::PathBuf>,
}

/// One built-in simulator: its name on the command line and how to make it.
pub struct SimKind {
    pub name: &'static str,
    pub description: &'static str,
    pub build: fn(&SimOptions) -> Box<dyn SimulatedController>,
}

/// Every built-in simulator. A new family adds one line here.
pub const SIM_KINDS: &[SimKind] = &[SimKind {
    name: "tmcm1110",
    description: "Trinamic TMCM-1110 StepRocker (TMCL, 1 axis)",
    build: |options| {
        let mut config = tmcm1110::SimConfig::default();
        if let Some(address) = options.address {
            config.address = address;
        }
        config.eeprom_file = options.eeprom_file.clone();
        Box::new(tmcm1110::Tmcm1110::new(config))
    },
}];

/// The simulator called `name` (case-insensitive), if there is one.
pub fn find_kind(name: &str) -> Option<&'static SimKind> {
    SIM_KINDS.iter().find(|k| k.name.eq_ignore_ascii_case(name))
}

/// Names of every simulator, for error messages and help.
pub fn kind_names() -> String {
    SIM_KINDS
        .iter()
        .map(|k| k.name)
        .collect::<Vec<_>>()
        .join(", ")
}
