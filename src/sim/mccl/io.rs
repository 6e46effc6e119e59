//! Digital channels 1–64 and analog channels 1–8 (manual Ch9), and the
//! default assignment of the axis inputs (Ch9 Table 1).
//!
//! Each channel has an electrical level (an input's is driven from outside,
//! an output's set by CN/CF) and a polarity (CH high true, the default, or
//! CL low true); "on" is the level read through the polarity. CH/CL do not
//! change an output's level (Ch9 CH note 1), so its on/off reading flips.

use super::errors::Code;

pub const CHANNELS: usize = 64;
/// Channels 1–32 are inputs (16 TTL, 16 opto), 33–64 outputs.
pub const LAST_INPUT: u8 = 32;
pub const ANALOG_CHANNELS: usize = 8;
/// A/D reading of 0 V: "-10V=0, 0.0V=32768 and +10V=65536" (Ch8 TA).
pub const ANALOG_ZERO: u16 = 32768;

/// The channels of one axis (Ch9 Table 1). Axes n and n + 4 share their
/// opto inputs, as the table and the I/O dialog (Fig. 8: axis 1 servo and
/// axis 5 stepper both on 17–20) show. The table names axis 3 and 4 as
/// the home of channels 21 and 25; read as axes 6 and 7 (digest §19 #21).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AxisChannels {
    pub axis: u8,
    /// Coarse home (servo) or home sensor (stepper).
    pub home: u8,
    pub limit_plus: u8,
    pub limit_minus: u8,
    pub fault: u8,
    /// The TTL capture input (channels 1, 5, 9, 13).
    pub capture: u8,
    /// The TTL compare output (33 for axes 1–4, 41 for 5–8).
    pub compare: u8,
}

const fn channels(axis: u8, opto: u8, capture: u8, compare: u8) -> AxisChannels {
    AxisChannels {
        axis,
        home: opto,
        limit_plus: opto + 1,
        limit_minus: opto + 2,
        fault: opto + 3,
        capture,
        compare,
    }
}

pub const AXIS_CHANNELS: [AxisChannels; 8] = [
    channels(1, 17, 1, 33),
    channels(2, 21, 1, 33),
    channels(3, 25, 5, 33),
    channels(4, 29, 5, 33),
    channels(5, 17, 9, 41),
    channels(6, 21, 9, 41),
    channels(7, 25, 13, 41),
    channels(8, 29, 13, 41),
];

/// The channels of `axis` (1–8).
pub fn channels_of(axis: u8) -> Option<&'static AxisChannels> {
    AXIS_CHANNELS.iter().find(|c| c.axis == axis)
}

/// The other axes wired to the same opto channel as this input.
pub fn axes_on_channel(channel: u8) -> Vec<u8> {
    AXIS_CHANNELS
        .iter()
        .filter(|c| [c.home, c.limit_plus, c.limit_minus, c.fault].contains(&channel))
        .map(|c| c.axis)
        .collect()
}

#[derive(Debug, Clone, PartialEq)]
pub struct Io {
    /// Electrical level of channel n at index n − 1 (high / conducting /
    /// sinking).
    level: [bool; CHANNELS],
    low_true: [bool; CHANNELS],
    /// A/D readings, 0–65535.
    pub analog_in: [u16; ANALOG_CHANNELS],
    /// OA: the last value written to each analog output.
    pub analog_out: [f64; ANALOG_CHANNELS],
}

impl Default for Io {
    fn default() -> Self {
        Io {
            level: [false; CHANNELS],
            low_true: [false; CHANNELS],
            analog_in: [ANALOG_ZERO; ANALOG_CHANNELS],
            analog_out: [0.0; ANALOG_CHANNELS],
        }
    }
}

fn slot(channel: u8) -> Option<usize> {
    usize::from(channel)
        .checked_sub(1)
        .filter(|&i| i < CHANNELS)
}

impl Io {
    /// Power-up: outputs off and every channel high true; the wiring of
    /// the inputs (their levels) and the A/D inputs stay.
    pub fn reset(&mut self) {
        let inputs: Vec<bool> = self.level[..usize::from(LAST_INPUT)].to_vec();
        let analog = self.analog_in;
        *self = Io::default();
        self.level[..usize::from(LAST_INPUT)].copy_from_slice(&inputs);
        self.analog_in = analog;
    }

    /// The channel reads on (TC, IN, IF, WN, WF, DN, DF, the axis inputs).
    pub fn is_on(&self, channel: u8) -> bool {
        slot(channel).is_some_and(|i| self.level[i] != self.low_true[i])
    }

    /// CN / CF: an output on or off. Inputs cannot be set (−1).
    pub fn set_output(&mut self, channel: u8, on: bool) -> Result<(), Code> {
        let i = slot(channel)
            .filter(|_| channel > LAST_INPUT)
            .ok_or(Code::PARAMETER)?;
        self.level[i] = on != self.low_true[i];
        Ok(())
    }

    /// Drive an input's electrical level from outside.
    pub fn drive_input(&mut self, channel: u8, level: bool) -> bool {
        match slot(channel).filter(|_| channel <= LAST_INPUT) {
            Some(i) => {
                self.level[i] = level;
                true
            }
            None => false,
        }
    }

    pub fn level(&self, channel: u8) -> bool {
        slot(channel).is_some_and(|i| self.level[i])
    }

    /// CH (`low_true` false) or CL; channel 0 is every channel.
    pub fn set_polarity(&mut self, channel: u8, low_true: bool) {
        if channel == 0 {
            self.low_true = [low_true; CHANNELS];
        } else if let Some(i) = slot(channel) {
            self.low_true[i] = low_true;
        }
    }

    pub fn is_low_true(&self, channel: u8) -> bool {
        slot(channel).is_some_and(|i| self.low_true[i])
    }

    /// TC0: inputs 1–32 as a 32-bit word, channel n at bit n − 1.
    pub fn inputs_word(&self) -> u32 {
        (1..=LAST_INPUT)
            .filter(|&c| self.is_on(c))
            .fold(0, |word, c| word | 1 << (c - 1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_map_follows_table_1() {
        let axis1 = channels_of(1).expect("axis 1");
        assert_eq!(
            (axis1.home, axis1.limit_plus, axis1.limit_minus, axis1.fault),
            (17, 18, 19, 20)
        );
        let axis5 = channels_of(5).expect("axis 5");
        assert_eq!(
            (axis5.home, axis5.limit_plus),
            (17, 18),
            "shared with axis 1"
        );
        assert_eq!(channels_of(4).map(|c| c.limit_minus), Some(31));
        assert_eq!(axes_on_channel(18), [1, 5]);
        assert_eq!(
            channels_of(7).map(|c| (c.capture, c.compare)),
            Some((13, 41))
        );
    }

    #[test]
    fn low_true_inverts_the_reading_not_the_level() {
        let mut io = Io::default();
        assert!(io.drive_input(17, true));
        assert!(io.is_on(17));
        io.set_polarity(17, true);
        assert!(!io.is_on(17), "CL17: conducting reads off");
        assert!(io.set_output(33, true).is_ok());
        assert!(io.level(33));
        io.set_polarity(0, true);
        assert!(!io.is_on(33), "CL0 flips the reading of every channel");
        assert!(io.level(33), "the output's level stays (Ch9 CH note 1)");
        assert_eq!(io.set_output(5, true), Err(Code::PARAMETER), "an input");
        assert!(!io.drive_input(33, true), "an output");
    }

    #[test]
    fn tc0_packs_the_inputs() {
        let mut io = Io::default();
        io.drive_input(1, true);
        io.drive_input(32, true);
        assert_eq!(io.inputs_word(), 1 | 1 << 31);
    }
}
