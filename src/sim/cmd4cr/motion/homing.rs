//! The thirteen homing modes of Appendix A (T A-45 and the "Operation 1"
//! sequences of A.1..A.13) and the Z-move of §2.2.5.1, as data: each mode
//! is a list of legs, each leg runs until its trigger and then does what
//! the appendix says.
//!
//! Home detection is edge-triggered (pin table note 7): a leg waiting for
//! the home switch reacts to it turning on, not to it being on. That is why
//! "Operation 2" (started on the switch) and "Operation 3" (started away
//! from it) run on to the end limit, where the ordinary limit stop ends the
//! search.
//!
//! Choices where the manual is silent (digest §4.4, §8.3):
//! - `Zset` sets both counters, P and E, to 0 at the trigger position.
//! - The A.6 detail table of mode 5 repeats mode 6; T A-45 and the A.6
//!   prose are followed.
//! - A leg triggered by the end limit stops immediately and latches the
//!   limit error like any limit stop (IERR=0); A.7's note says the ERC
//!   output clears the limit flag in the homing direction, so with ERC bit 1
//!   set the flag is cleared when homing completes.
//! - `ZMOVE` accelerates to HSPD like every other move and stops at once on
//!   its ZCNT+1-th index pulse.

/// How fast a leg runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Speed {
    /// Accelerate from LSPD to HSPD (or stay at the speed a previous leg
    /// left it at and accelerate from there).
    High,
    /// Constant LSPD.
    Low,
}

/// Which way a leg runs, relative to the commanded homing direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Way {
    Forward,
    Reverse,
}

/// What ends a leg.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Trigger {
    /// The home switch turning on.
    HomeOn,
    /// The home switch turning off (after having been on during this leg
    /// or at its start).
    HomeOff,
    /// The end limit in the direction of travel turning on.
    Limit,
    /// The end limit behind turning off.
    LimitOff,
    /// The ZCNT+1-th Z index pulse of this leg.
    Index,
}

/// What happens at the trigger.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Then {
    /// Stop at once.
    Stop,
    /// Decelerate to LSPD and stop.
    Decelerate,
    /// Decelerate to LSPD and run on into the next leg.
    SlowDown,
    /// Run on at the current speed into the next leg.
    Pass,
}

/// One leg of a homing sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Leg {
    pub speed: Speed,
    pub way: Way,
    pub until: Trigger,
    pub then: Then,
    /// Set the counters to zero at the trigger ("zero position is set").
    pub zero: bool,
}

const fn leg(speed: Speed, way: Way, until: Trigger, then: Then, zero: bool) -> Leg {
    Leg {
        speed,
        way,
        until,
        then,
        zero,
    }
}

use Speed::{High, Low};
use Then::{Decelerate, Pass, SlowDown, Stop};
use Trigger::{HomeOff, HomeOn, Index, Limit, LimitOff};
use Way::{Forward, Reverse};

/// One homing mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Procedure {
    pub mode: u8,
    /// T A-45 columns, for the help text and the console.
    pub uses_home: bool,
    pub uses_limit: bool,
    pub uses_index: bool,
    pub legs: &'static [Leg],
    /// Finish with a positioning move back to counter 0 (modes 9..12).
    pub return_to_zero: bool,
}

/// Appendix A, modes 0..12.
pub const HOMING_MODES: &[Procedure] = &[
    // A.1: decelerate on home, zero at the trigger; SD makes it approach
    // at LSPD (the generic slow-down handling).
    Procedure {
        mode: 0,
        uses_home: true,
        uses_limit: false,
        uses_index: false,
        legs: &[leg(High, Forward, HomeOn, Decelerate, true)],
        return_to_zero: false,
    },
    // A.2: decelerate on home, back off at LSPD until home turns off,
    // approach again at LSPD and stop on home.
    Procedure {
        mode: 1,
        uses_home: true,
        uses_limit: false,
        uses_index: false,
        legs: &[
            leg(High, Forward, HomeOn, Decelerate, false),
            leg(Low, Reverse, HomeOff, Stop, false),
            leg(Low, Forward, HomeOn, Stop, true),
        ],
        return_to_zero: false,
    },
    // A.3: slow to LSPD on home, stop on the ZCNT-th index.
    Procedure {
        mode: 2,
        uses_home: true,
        uses_limit: false,
        uses_index: true,
        legs: &[
            leg(High, Forward, HomeOn, SlowDown, false),
            leg(Low, Forward, Index, Stop, true),
        ],
        return_to_zero: false,
    },
    // A.4: pass home at HSPD, zero on the index and decelerate.
    Procedure {
        mode: 3,
        uses_home: true,
        uses_limit: false,
        uses_index: true,
        legs: &[
            leg(High, Forward, HomeOn, Pass, false),
            leg(High, Forward, Index, Decelerate, true),
        ],
        return_to_zero: false,
    },
    // A.5: decelerate on home, reverse at LSPD, stop on the index.
    Procedure {
        mode: 4,
        uses_home: true,
        uses_limit: false,
        uses_index: true,
        legs: &[
            leg(High, Forward, HomeOn, Decelerate, false),
            leg(Low, Reverse, Index, Stop, true),
        ],
        return_to_zero: false,
    },
    // A.6: decelerate on home, reverse up to HSPD, zero on the index and
    // decelerate.
    Procedure {
        mode: 5,
        uses_home: true,
        uses_limit: false,
        uses_index: true,
        legs: &[
            leg(High, Forward, HomeOn, Decelerate, false),
            leg(High, Reverse, Index, Decelerate, true),
        ],
        return_to_zero: false,
    },
    // A.7: stop on the end limit, creep off it at LSPD, zero where it opens.
    Procedure {
        mode: 6,
        uses_home: false,
        uses_limit: true,
        uses_index: false,
        legs: &[
            leg(High, Forward, Limit, Stop, false),
            leg(Low, Reverse, LimitOff, Stop, true),
        ],
        return_to_zero: false,
    },
    // A.8: stop on the end limit, reverse at LSPD, stop on the index.
    Procedure {
        mode: 7,
        uses_home: false,
        uses_limit: true,
        uses_index: true,
        legs: &[
            leg(High, Forward, Limit, Stop, false),
            leg(Low, Reverse, Index, Stop, true),
        ],
        return_to_zero: false,
    },
    // A.9: stop on the end limit, reverse up to HSPD, zero on the index and
    // decelerate.
    Procedure {
        mode: 8,
        uses_home: false,
        uses_limit: true,
        uses_index: true,
        legs: &[
            leg(High, Forward, Limit, Stop, false),
            leg(High, Reverse, Index, Decelerate, true),
        ],
        return_to_zero: false,
    },
    // A.10: zero on home and decelerate, then return to 0.
    Procedure {
        mode: 9,
        uses_home: true,
        uses_limit: false,
        uses_index: false,
        legs: &[leg(High, Forward, HomeOn, Decelerate, true)],
        return_to_zero: true,
    },
    // A.11: pass home, zero on the index and decelerate, return to 0.
    Procedure {
        mode: 10,
        uses_home: true,
        uses_limit: false,
        uses_index: true,
        legs: &[
            leg(High, Forward, HomeOn, Pass, false),
            leg(High, Forward, Index, Decelerate, true),
        ],
        return_to_zero: true,
    },
    // A.12: decelerate on home, reverse up to HSPD, zero on the index and
    // decelerate, return to 0.
    Procedure {
        mode: 11,
        uses_home: true,
        uses_limit: false,
        uses_index: true,
        legs: &[
            leg(High, Forward, HomeOn, Decelerate, false),
            leg(High, Reverse, Index, Decelerate, true),
        ],
        return_to_zero: true,
    },
    // A.13: stop on the end limit, reverse up to HSPD, zero on the index
    // and decelerate, return to 0.
    Procedure {
        mode: 12,
        uses_home: false,
        uses_limit: true,
        uses_index: true,
        legs: &[
            leg(High, Forward, Limit, Stop, false),
            leg(High, Reverse, Index, Decelerate, true),
        ],
        return_to_zero: true,
    },
];

/// §2.2.5.1: run at HSPD until the ZCNT+1-th index pulse.
pub const Z_MOVE: Procedure = Procedure {
    mode: u8::MAX,
    uses_home: false,
    uses_limit: false,
    uses_index: true,
    legs: &[leg(High, Forward, Index, Stop, false)],
    return_to_zero: false,
};

/// The procedure of homing mode `mode` (0..12).
pub fn procedure(mode: u8) -> Option<&'static Procedure> {
    HOMING_MODES.iter().find(|p| p.mode == mode)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mode_of_table_a_45_is_there_once() {
        for mode in 0..=12u8 {
            assert_eq!(procedure(mode).map(|p| p.mode), Some(mode));
        }
        assert!(procedure(13).is_none());
        assert_eq!(HOMING_MODES.len(), 13);
    }

    #[test]
    fn the_inputs_match_table_a_45() {
        // (home, limit, index, ending at zero) per mode.
        let table: [(bool, bool, bool, bool); 13] = [
            (true, false, false, false),
            (true, false, false, true),
            (true, false, true, true),
            (true, false, true, false),
            (true, false, true, true),
            (true, false, true, false),
            (false, true, false, true),
            (false, true, true, true),
            (false, true, true, false),
            (true, false, false, true),
            (true, false, true, true),
            (true, false, true, true),
            (false, true, true, true),
        ];
        for (p, &(home, limit, index, zero_end)) in HOMING_MODES.iter().zip(&table) {
            assert_eq!(
                (p.uses_home, p.uses_limit, p.uses_index),
                (home, limit, index)
            );
            let last = p.legs.last().expect("legs");
            // "Zero" ending: stops on the trigger or returns to 0.
            let ends_at_zero = p.return_to_zero || (last.zero && last.then == Then::Stop);
            assert_eq!(ends_at_zero, zero_end, "mode {}", p.mode);
            assert!(p.legs.iter().any(|l| l.zero), "mode {} sets zero", p.mode);
        }
    }
}
