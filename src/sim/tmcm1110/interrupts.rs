//! Where the TMCM-1110's interrupts come from (manual §3.5.6.1 Table 12,
//! §5.4 Table 20): three timers, the axis events and edges on the stop
//! switches and the general-purpose inputs. The interpreter (`interpreter.rs`)
//! serves the requests; `program.rs` keeps vectors, enables and requests.
//!
//! Decisions where the manual is silent:
//! - A source raises a request only while a program runs or steps, and only
//!   if it is enabled (EI n) and has a vector; a request waits (at most one
//!   per source) while interrupts are globally off or a handler runs, and is
//!   served when that ends. DI n, 128, STOP and 131 drop waiting requests.
//! - Timer n counts from the moment its period (GP n, bank 3, in ms) is
//!   written; 0 turns it off. A period the simulator slept through while no
//!   program ran raises nothing.
//! - Stop switch edges (GP 27/28, bank 3) are edges of the logical switch
//!   state AP11/AP10 (after GP79 polarity): "low→high" = the switch becomes
//!   active.
//! - "Input 0..5" (GP 39..44, bank 3; interrupts 39..44) are GIO bank-0
//!   ports 1..6 (PWMD0..2, PWMU0..2): the six general-purpose digital lines.
//!   AIN0 (port 0) is an analog input and raises none. Levels are those GIO
//!   reads (an output line reads its latch), sampled between commands.

use std::time::Duration;

/// What raises an interrupt.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// Timer 0..2, period in bank 3 parameter 0..2.
    Timer(u8),
    /// Axis 0 reached its target position.
    TargetReached,
    /// StallGuard stop of axis 0.
    Stall,
    /// Encoder deviation stop of axis 0.
    Deviation,
    /// Left stop switch edge, trigger in bank 3 parameter 27.
    LeftSwitch,
    /// Right stop switch edge, trigger in bank 3 parameter 28.
    RightSwitch,
    /// Edge on a general-purpose input (GIO bank-0 port), trigger in bank 3
    /// parameter = the interrupt number.
    Input { port: u8 },
}

/// One interrupt of §3.5.6.1 Table 12 and what raises it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InterruptSource {
    pub number: u8,
    pub source: Source,
}

const fn source(number: u8, source: Source) -> InterruptSource {
    InterruptSource { number, source }
}

/// Every interrupt source of the module (§3.5.6.1 Table 12; 255 is the
/// global switch, not a source).
pub const INTERRUPT_SOURCES: &[InterruptSource] = &[
    source(0, Source::Timer(0)),
    source(1, Source::Timer(1)),
    source(2, Source::Timer(2)),
    source(3, Source::TargetReached),
    source(15, Source::Stall),
    source(21, Source::Deviation),
    source(27, Source::LeftSwitch),
    source(28, Source::RightSwitch),
    source(39, Source::Input { port: 1 }),
    source(40, Source::Input { port: 2 }),
    source(41, Source::Input { port: 3 }),
    source(42, Source::Input { port: 4 }),
    source(43, Source::Input { port: 5 }),
    source(44, Source::Input { port: 6 }),
];

/// The interrupt a source raises.
pub fn interrupt_of(wanted: Source) -> Option<u8> {
    INTERRUPT_SOURCES
        .iter()
        .find(|s| s.source == wanted)
        .map(|s| s.number)
}

/// Number of timers (interrupts 0..2).
pub const TIMERS: usize = 3;

/// Whether a level change fires under a bank-3 trigger setting (§5.4 Table
/// 20: 0 off, 1 low→high, 2 high→low, 3 both).
pub fn edge_fires(trigger: i32, rising: bool) -> bool {
    match trigger {
        1 => rising,
        2 => !rising,
        3 => true,
        _ => false,
    }
}

/// The three interrupt timers.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Timers {
    /// Period and next expiry (virtual time since power-up) of each running
    /// timer.
    running: [Option<(Duration, Duration)>; TIMERS],
}

impl Timers {
    /// SGP n, 3, period: (re)start timer n at `now`; 0 stops it. The period
    /// is an unsigned 32-bit millisecond count (§5.4: 0..4294967295), sent
    /// as its two's-complement bit pattern.
    pub fn set_period(&mut self, timer: usize, period_ms: i32, now: Duration) {
        if let Some(slot) = self.running.get_mut(timer) {
            let period = Duration::from_millis(u64::from(period_ms as u32));
            *slot = (!period.is_zero()).then(|| (period, now.saturating_add(period)));
        }
    }

    /// The next expiry of any timer.
    pub fn next_due(&self) -> Option<Duration> {
        self.running.iter().flatten().map(|&(_, due)| due).min()
    }

    /// The timers that have expired by `now`, each reported once however
    /// many periods passed; their next expiry moves past `now`.
    pub fn expired(&mut self, now: Duration) -> Vec<u8> {
        let mut fired = Vec::new();
        for (index, slot) in self.running.iter_mut().enumerate() {
            if let Some((period, due)) = slot
                && *due <= now
            {
                let behind = now.saturating_sub(*due).as_nanos();
                let periods = behind / period.as_nanos().max(1) + 1;
                let skip = period.saturating_mul(u32::try_from(periods).unwrap_or(u32::MAX));
                *due = due.saturating_add(skip);
                fired.push(index as u8);
            }
        }
        fired
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::tmcl::command::{GLOBAL_INTERRUPT, INTERRUPTS};

    #[test]
    fn every_interrupt_of_table_12_has_a_source() {
        for info in INTERRUPTS.iter().filter(|i| i.number != GLOBAL_INTERRUPT) {
            assert!(
                INTERRUPT_SOURCES.iter().any(|s| s.number == info.number),
                "interrupt {} ({})",
                info.number,
                info.source
            );
        }
        assert_eq!(INTERRUPT_SOURCES.len(), INTERRUPTS.len() - 1);
        assert_eq!(interrupt_of(Source::Input { port: 6 }), Some(44));
        assert_eq!(interrupt_of(Source::Input { port: 0 }), None, "AIN0");
    }

    #[test]
    fn trigger_settings_select_edges() {
        assert!(!edge_fires(0, true) && !edge_fires(0, false));
        assert!(edge_fires(1, true) && !edge_fires(1, false));
        assert!(!edge_fires(2, true) && edge_fires(2, false));
        assert!(edge_fires(3, true) && edge_fires(3, false));
        assert!(!edge_fires(4, true));
    }

    #[test]
    fn timers_fire_once_per_period_and_catch_up() {
        let ms = Duration::from_millis;
        let mut timers = Timers::default();
        assert_eq!(timers.next_due(), None);
        timers.set_period(0, 100, ms(5));
        timers.set_period(2, 30, ms(0));
        assert_eq!(timers.next_due(), Some(ms(30)));
        assert_eq!(timers.expired(ms(29)), Vec::<u8>::new());
        assert_eq!(timers.expired(ms(30)), vec![2]);
        assert_eq!(timers.next_due(), Some(ms(60)));
        // Slept through several periods: one report, next expiry ahead.
        assert_eq!(timers.expired(ms(200)), vec![0, 2]);
        assert_eq!(timers.next_due(), Some(ms(205)));
        timers.set_period(0, 0, ms(200));
        assert_eq!(timers.next_due(), Some(ms(210)));
        // 4294967295 ms arrives as -1.
        timers.set_period(1, -1, ms(0));
        timers.set_period(2, 0, ms(0));
        assert_eq!(timers.next_due(), Some(ms(4_294_967_295)));
    }
}
