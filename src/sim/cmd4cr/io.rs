//! General I/O of the core (§2.1.3.2, §2.1.3.3, §2.2.1): enable outputs
//! EO, high-speed inputs DI and outputs DO, the 32 configurable I/O, the
//! analog inputs and the PWM outputs, with their power-on values.
//!
//! Levels are logical (1 = on); the polarity settings DIP, DOP and IOP are
//! kept and reported but do not invert what the simulated wiring shows
//! (the simulated inputs are set as logical levels too).
//!
//! Choices where the manual is silent:
//! - `IOCFG` at power-on is 0xFFFF0000: IO1..IO16 inputs, IO17..IO32
//!   outputs, so that §4.3.9 (read IO5, write IO19) works on a new
//!   simulator; a write takes effect at once.
//! - Writing an IO bit configured as input changes its output latch only
//!   (it shows once the bit is made an output); the write is answered OK.
//! - Writing a DO bit whose sync output is on changes its latch only: the
//!   output stays under sync control until SYNF (§2.1.3.2.2: it "cannot be
//!   manually controlled").
//! - PWM duty at power-on: 50 %; analog inputs read 0 mV until set.

/// Power-on IOCFG (our choice, see above).
pub const DEFAULT_IOCFG: u32 = 0xFFFF_0000;
/// Power-on PWM duty, % (our choice).
pub const DEFAULT_PWM: u8 = 50;

/// The I/O block.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Io {
    /// `EO`, bit n = axis n.
    pub enable: u8,
    /// `EOBOOT`.
    pub enable_boot: u8,
    /// DI1..DI4 as wired (bit 0 = DI1).
    pub digital_inputs: u8,
    /// `DIP`.
    pub input_polarity: u8,
    /// The DO latch (bit 0 = DO1); outputs in sync use show the sync state.
    pub digital_outputs: u8,
    /// `DOP`.
    pub output_polarity: u8,
    /// `DOBOOT`.
    pub output_boot: u8,
    /// The IO output latch.
    pub io_outputs: u32,
    /// IO inputs as wired.
    pub io_inputs: u32,
    /// `IOCFG`: bit = 1 output.
    pub io_config: u32,
    /// `IOBOOT`.
    pub io_boot: u32,
    /// `IOP`.
    pub io_polarity: u8,
    /// AI1, AI2 in mV.
    pub analog: [u16; 2],
    /// PWM1, PWM2 duty in %.
    pub pwm: [u8; 2],
}

impl Default for Io {
    fn default() -> Self {
        Io {
            enable: 0,
            enable_boot: 0,
            digital_inputs: 0,
            input_polarity: 0,
            digital_outputs: 0,
            output_polarity: 0,
            output_boot: 0,
            io_outputs: 0,
            io_inputs: 0,
            io_config: DEFAULT_IOCFG,
            io_boot: 0,
            io_polarity: 0,
            analog: [0; 2],
            pwm: [DEFAULT_PWM; 2],
        }
    }
}

impl Io {
    /// `IO`: outputs from the latch, inputs from the wiring.
    pub fn io(&self) -> u32 {
        (self.io_outputs & self.io_config) | (self.io_inputs & !self.io_config)
    }

    /// `DO`, with the outputs in sync use (`mask`) showing `sync` instead.
    pub fn outputs(&self, sync_mask: u8, sync: u8) -> u8 {
        (self.digital_outputs & !sync_mask) | (sync & sync_mask)
    }

    /// Power-on: outputs from their boot values (§2.1.5); what is wired
    /// stays wired.
    pub fn power_up(&mut self) {
        self.enable = self.enable_boot;
        self.digital_outputs = self.output_boot;
        self.io_outputs = self.io_boot;
    }
}

/// Set or clear bit `n` of `word`.
pub fn with_bit<T>(word: T, n: u32, on: bool) -> T
where
    T: Copy
        + std::ops::BitOr<Output = T>
        + std::ops::BitAnd<Output = T>
        + std::ops::Not<Output = T>
        + std::ops::Shl<u32, Output = T>
        + From<u8>,
{
    let bit = T::from(1u8) << n;
    if on { word | bit } else { word & !bit }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn io_reads_outputs_from_the_latch_and_inputs_from_the_wiring() {
        let mut io = Io {
            // IO5 on.
            io_inputs: with_bit(0u32, 4, true),
            io_outputs: with_bit(0u32, 18, true) | with_bit(0u32, 2, true),
            ..Io::default()
        };
        // IO19 is an output (shows), IO3 an input (its latch does not).
        assert_eq!(io.io(), (1 << 4) | (1 << 18));
        io.io_config = 0;
        assert_eq!(io.io(), 1 << 4);
    }

    #[test]
    fn sync_outputs_override_the_latch() {
        let io = Io {
            digital_outputs: 0b0110,
            ..Io::default()
        };
        assert_eq!(io.outputs(0b0001, 0b0001), 0b0111);
        assert_eq!(io.outputs(0b0010, 0b0000), 0b0100);
    }

    #[test]
    fn power_up_takes_the_boot_values() {
        let mut io = Io {
            enable: 0xF,
            enable_boot: 3,
            output_boot: 5,
            io_boot: 0x8000_0000,
            ..Io::default()
        };
        io.power_up();
        assert_eq!(
            (io.enable, io.digital_outputs, io.io_outputs),
            (3, 5, 0x8000_0000)
        );
    }
}
