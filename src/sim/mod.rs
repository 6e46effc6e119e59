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
