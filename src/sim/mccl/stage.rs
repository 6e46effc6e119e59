//! The demo stage of the MultiFlex simulator (off until `LIMITS=right` or
//! `LIMITS=swapped`; `STAGE=off` takes it away again): every axis drives a
//! linear carriage whose switches close its axis inputs (Ch9 Table 1) by
//! where the shaft is, and whose hard end stops hold the shaft.
//!
//! The manual gives no stage; the layout is this simulator's choice: limit
//! switches from ±[`LIMIT_AT`] outward, a coarse home (servo) / home sensor
//! (stepper) switch over [`HOME_SPAN`], end stops at ±[`END_STOP_AT`], all
//! in shaft units (counts of a servo, steps of a stepper) from where the
//! shaft was at power-up. What a closed limit input does is the
//! controller's (Ch5 LN, LM): with the limit on (LN) and the motor
//! commanded toward that switch it trips the axis and turns it off, stops
//! it abruptly or decelerates it (LM 0, 1, 2); the other switch does not
//! stop it. A switch closes its input electrically (conducting), so CH/CL
//! and LM + 128 read it as for a level driven from outside. Each axis'
//! switches close its own inputs only: the channels axes n and n + 4
//! share (Table 1) are not ORed between two stages.

/// Where the + limit switch starts closing (and the − one at −LIMIT_AT).
pub const LIMIT_AT: f64 = 50_000.0;
/// The mechanical end stops, 10,000 beyond each limit switch.
pub const END_STOP_AT: f64 = 60_000.0;
/// The home switch: closed from −500 to +500.
pub const HOME_SPAN: (f64, f64) = (-500.0, 500.0);

/// The switches of one stage at one shaft position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Switches {
    /// The input the controller reads as limit + is closed.
    pub limit_plus: bool,
    pub limit_minus: bool,
    pub home: bool,
}

/// The stage on every axis and how its end switches are wired.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stage {
    /// The + end closes the limit − input and the − end the + one.
    pub swapped: bool,
}

impl Stage {
    /// Which inputs the carriage closes with the shaft at `shaft`.
    pub fn switches(&self, shaft: f64) -> Switches {
        let plus_end = shaft >= LIMIT_AT;
        let minus_end = shaft <= -LIMIT_AT;
        let (limit_plus, limit_minus) = if self.swapped {
            (minus_end, plus_end)
        } else {
            (plus_end, minus_end)
        };
        Switches {
            limit_plus,
            limit_minus,
            home: (HOME_SPAN.0..=HOME_SPAN.1).contains(&shaft),
        }
    }

    /// The end stops, in shaft units.
    pub fn end_stops(&self) -> (f64, f64) {
        (-END_STOP_AT, END_STOP_AT)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ends_close_their_own_inputs_or_the_others_when_swapped() {
        let right = Stage { swapped: false };
        assert!(right.switches(0.0).home);
        assert_eq!(right.switches(600.0), Switches::default());
        let plus = right.switches(LIMIT_AT);
        assert!(plus.limit_plus && !plus.limit_minus);
        assert!(!right.switches(LIMIT_AT - 1.0).limit_plus);
        assert!(right.switches(-LIMIT_AT).limit_minus);
        let swapped = Stage { swapped: true };
        let plus = swapped.switches(LIMIT_AT + 10.0);
        assert!(plus.limit_minus && !plus.limit_plus);
        assert!(swapped.switches(-LIMIT_AT).limit_plus);
        assert_eq!(swapped.end_stops(), (-END_STOP_AT, END_STOP_AT));
    }
}
