//! Position latch (§2.1.3.2.1) and synchronisation output (§2.1.3.2.2) of
//! one axis.
//!
//! The latch input of axis n is DIn (X←DI1 … U←DI4, T2-3); on its rising
//! edge the armed latch copies P and E (`LTP`, `LTE`) and `LTS` becomes 2.
//!
//! The `SYNC[axis]` word's encoding is not in the manual (digest §0); the
//! only example is `SYNCX=1` for "output on at position". Our encoding,
//! stated in the simulator's help:
//! - bits 0..2, the condition: 1 counter = SYNP (the output turns on when
//!   the counter reaches SYNP and stays on), 2 counter > SYNP, 3 counter <
//!   SYNP (on while the condition holds), 4 continuous (a pulse every SYNP
//!   counts, counted in [`Sync::pulses`]); 0 = no condition;
//! - bit 3: compare the encoder counter E instead of the pulse counter P.

/// `LTS` values (T2-4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LatchStatus {
    #[default]
    Off = 0,
    Armed = 1,
    Triggered = 2,
}

/// The position latch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Latch {
    pub status: LatchStatus,
    /// `LTP`: the pulse counter at the trigger.
    pub pulse: i64,
    /// `LTE`: the encoder counter at the trigger.
    pub encoder: i64,
}

impl Latch {
    /// `LT[axis]=on`.
    pub fn enable(&mut self, on: bool) {
        self.status = if on {
            LatchStatus::Armed
        } else {
            LatchStatus::Off
        };
    }

    /// The latch input rose with the counters at these values.
    pub fn trigger(&mut self, pulse: i64, encoder: i64) {
        if self.status == LatchStatus::Armed {
            self.pulse = pulse;
            self.encoder = encoder;
            self.status = LatchStatus::Triggered;
        }
    }
}

/// `SYNS` values (T2-7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SyncStatus {
    #[default]
    Disabled = 0,
    Waiting = 1,
    Met = 2,
}

/// The condition of `SYNC[axis]` (our encoding, see the module).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SyncCondition {
    None,
    AtPosition,
    Above,
    Below,
    Continuous,
}

/// The synchronisation output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Sync {
    /// `SYNC[axis]`, raw.
    pub config: u32,
    /// `SYNP[axis]`.
    pub position: i64,
    /// `SYNMIN[axis]`, `SYNMAX[axis]`.
    pub window_min: i64,
    pub window_max: i64,
    /// `SYNO` / `SYNF`.
    pub enabled: bool,
    /// `SYNWO` / `SYNWF`.
    pub window: bool,
    pub status: SyncStatus,
    /// The output level (DOn while sync is on).
    pub output: bool,
    /// Pulses output in continuous mode since `SYNO`.
    pub pulses: u64,
}

impl Sync {
    pub fn condition(&self) -> SyncCondition {
        match self.config & 7 {
            1 => SyncCondition::AtPosition,
            2 => SyncCondition::Above,
            3 => SyncCondition::Below,
            4 => SyncCondition::Continuous,
            _ => SyncCondition::None,
        }
    }

    /// Compare the encoder counter rather than the pulse counter.
    pub fn uses_encoder(&self) -> bool {
        self.config & 8 != 0
    }

    /// `SYNO[axis]`, with the counter it compares now.
    pub fn enable(&mut self, counter: i64) {
        self.enabled = true;
        self.output = false;
        self.pulses = 0;
        self.status = SyncStatus::Waiting;
        self.compare(counter, counter);
    }

    /// `SYNF[axis]`: output and window off.
    pub fn disable(&mut self) {
        self.enabled = false;
        self.window = false;
        self.output = false;
        self.status = SyncStatus::Disabled;
    }

    /// The compared counter went from `from` to `to`.
    pub fn compare(&mut self, from: i64, to: i64) {
        if !self.enabled {
            return;
        }
        let (low, high) = (from.min(to), from.max(to));
        match self.condition() {
            SyncCondition::None => {}
            SyncCondition::AtPosition => {
                if low <= self.position && self.position <= high {
                    self.output = true;
                    self.status = SyncStatus::Met;
                }
            }
            SyncCondition::Above | SyncCondition::Below => {
                let met = if self.condition() == SyncCondition::Above {
                    to > self.position
                } else {
                    to < self.position
                };
                self.output = met;
                self.status = if met {
                    SyncStatus::Met
                } else {
                    SyncStatus::Waiting
                };
            }
            SyncCondition::Continuous => {
                if self.position <= 0 || from == to {
                    return;
                }
                // Multiples of SYNP passed, `from` excluded.
                let step = self.position;
                let crossed = if to > from {
                    to.div_euclid(step) - from.div_euclid(step)
                } else {
                    (from - 1).div_euclid(step) - (to - 1).div_euclid(step)
                };
                let inside = !self.window || (self.window_min <= to && to <= self.window_max);
                if crossed > 0 && inside {
                    self.pulses += crossed.unsigned_abs();
                    self.status = SyncStatus::Met;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_position_turns_on_and_stays_on() {
        // §4.3.8: SYNCX=1, SYNPX=5000, SYNOX, X5000.
        let mut sync = Sync {
            config: 1,
            position: 5000,
            ..Sync::default()
        };
        sync.enable(0);
        assert_eq!(sync.status, SyncStatus::Waiting);
        sync.compare(0, 4999);
        assert!(!sync.output);
        sync.compare(4999, 5000);
        assert!(sync.output);
        assert_eq!(sync.status, SyncStatus::Met);
        sync.compare(5000, 6000);
        assert!(sync.output);
        sync.disable();
        assert!(!sync.output);
        assert_eq!(sync.status, SyncStatus::Disabled);
    }

    #[test]
    fn continuous_counts_every_interval_inside_the_window() {
        let mut sync = Sync {
            config: 4,
            position: 100,
            window_min: 200,
            window_max: 400,
            ..Sync::default()
        };
        sync.enable(0);
        sync.compare(0, 350);
        assert_eq!(sync.pulses, 3);
        sync.window = true;
        sync.compare(350, 500);
        assert_eq!(sync.pulses, 3, "outside the window");
        sync.compare(500, 390);
        assert_eq!(sync.pulses, 4);
    }

    #[test]
    fn the_latch_takes_the_counters_once_armed() {
        let mut latch = Latch::default();
        latch.trigger(5, 6);
        assert_eq!(latch.status, LatchStatus::Off);
        latch.enable(true);
        latch.trigger(5, 6);
        assert_eq!(
            (latch.status, latch.pulse, latch.encoder),
            (LatchStatus::Triggered, 5, 6)
        );
        latch.trigger(7, 8);
        assert_eq!(latch.pulse, 5);
    }
}
