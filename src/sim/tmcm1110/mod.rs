//! A faithful simulator of the TMCM-1110 StepRocker in direct mode.

pub mod motion;

use std::path::PathBuf;
use std::time::Duration;

use super::SimulatedController;

/// How the simulated module is set up.
#[derive(Debug, Clone)]
pub struct SimConfig {
    /// Module address (GP66), 1 unless told otherwise.
    pub address: u8,
    /// Where the EEPROM image is kept between runs; `None` keeps it in memory.
    pub eeprom_file: Option<PathBuf>,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            address: 1,
            eeprom_file: None,
        }
    }
}

/// The simulated module.
pub struct Tmcm1110 {
    config: SimConfig,
    output: Vec<u8>,
}

impl Tmcm1110 {
    pub fn new(config: SimConfig) -> Self {
        Tmcm1110 {
            config,
            output: Vec::new(),
        }
    }

    pub fn address(&self) -> u8 {
        self.config.address
    }
}

impl SimulatedController for Tmcm1110 {
    fn feed(&mut self, _bytes: &[u8]) {}

    fn advance(&mut self, _dt: Duration) {}

    fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.output)
    }
}
