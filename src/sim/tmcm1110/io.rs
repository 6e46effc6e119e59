//! General-purpose I/O of the StepRocker (manual §3.6.14, §3.6.15, §6.2):
//! output latches, pull-ups, the GP78 direction mask, simulated input levels
//! and the analog input AIN0.

/// One general-purpose line and the numbers it goes by. The same physical
/// line has different port numbers in GIO bank 0 and SIO/GIO bank 2, and a
/// third bit position in the pull-up and GP78 masks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IoLine {
    pub name: &'static str,
    /// Port in GIO bank 0 (digital inputs, §3.6.15).
    pub input_port: Option<u8>,
    /// Port in SIO/GIO bank 2 (digital outputs, §3.6.14).
    pub output_port: Option<u8>,
    /// Bit in the pull-up mask (SIO 0, 0) and in GP78 (§6.2 Table 21).
    pub mode_bit: Option<u8>,
}

const fn line(
    name: &'static str,
    input_port: Option<u8>,
    output_port: Option<u8>,
    mode_bit: Option<u8>,
) -> IoLine {
    IoLine {
        name,
        input_port,
        output_port,
        mode_bit,
    }
}

/// The StepRocker's general-purpose lines (§3.6.14, §3.6.15, §6.2 Table 21).
pub const IO_LINES: &[IoLine] = &[
    line("AIN0", Some(0), None, None),
    line("OpenDrain1", None, Some(0), None),
    line("OpenDrain2", None, Some(1), None),
    line("PWMU0", Some(4), Some(2), Some(0)),
    line("PWMU1", Some(5), Some(3), Some(1)),
    line("PWMU2", Some(6), Some(4), Some(2)),
    line("PWMD0", Some(1), Some(5), Some(3)),
    line("PWMD1", Some(2), Some(6), Some(4)),
    line("PWMD2", Some(3), Some(7), Some(5)),
];

/// Number of output ports in bank 2 (0..7).
pub const OUTPUT_PORTS: u8 = 8;
/// Number of input ports in bank 0 (0..6).
pub const INPUT_PORTS: u8 = 7;
/// Pull-ups are all on at power-up (§3.6.14).
pub const PULL_UPS_AT_POWER_UP: u8 = 0b11_1111;
/// Mask of the six bidirectional lines in the pull-up and GP78 masks.
pub const MODE_MASK: i32 = 0b11_1111;
/// AIN0 read as a digital input (GIO 0, 0) is 1 from this ADC value on.
/// The manual gives no threshold; half the 16-bit scale is the simulator's.
pub const AIN0_DIGITAL_THRESHOLD: u16 = 32768;

/// The line behind a GIO bank-0 port.
pub fn input_line(port: u8) -> Option<&'static IoLine> {
    IO_LINES.iter().find(|l| l.input_port == Some(port))
}

/// The line behind a SIO/GIO bank-2 port.
pub fn output_line(port: u8) -> Option<&'static IoLine> {
    IO_LINES.iter().find(|l| l.output_port == Some(port))
}

/// The module's I/O state. Input levels belong to the simulated world
/// outside the module, so a reset keeps them; latches and pull-ups are
/// module state and return to their power-up values.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Io {
    /// Output latches, bit n = bank-2 port n.
    pub outputs: u8,
    /// Pull-up resistors, bit order of §3.6.14 (bit set = on).
    pub pull_ups: u8,
    /// Levels driven onto the input lines from outside, by GIO bank-0 port
    /// (index 1..6; AIN0 at index 0 is derived from `analog`). `None` = open
    /// (nothing connected): the pull-up decides.
    pub external: [Option<bool>; INPUT_PORTS as usize],
    /// AIN0 ADC value, 0..65535.
    pub analog: u16,
}

impl Default for Io {
    fn default() -> Self {
        Io {
            outputs: 0,
            pull_ups: PULL_UPS_AT_POWER_UP,
            external: [None; INPUT_PORTS as usize],
            analog: 0,
        }
    }
}

impl Io {
    /// Module-side state back to power-up values, outside levels kept.
    pub fn power_up(&mut self) {
        self.outputs = 0;
        self.pull_ups = PULL_UPS_AT_POWER_UP;
    }

    /// GIO bank 0: the level of input port `port`. A line configured as an
    /// output in GP78 reads back what the module drives on it (the manual
    /// does not say; the pin carries the output level). An open input reads
    /// 1 with its pull-up on, 0 with it off.
    pub fn input(&self, port: u8, io_mode: i32) -> Option<bool> {
        let line = input_line(port)?;
        if port == 0 {
            return Some(self.analog >= AIN0_DIGITAL_THRESHOLD);
        }
        if let (Some(bit), Some(out_port)) = (line.mode_bit, line.output_port)
            && io_mode & (1 << bit) != 0
        {
            return Some(self.outputs & (1 << out_port) != 0);
        }
        let external = self.external.get(usize::from(port)).copied().flatten();
        Some(external.unwrap_or_else(|| {
            line.mode_bit
                .is_some_and(|bit| self.pull_ups & (1 << bit) != 0)
        }))
    }

    /// GIO 255, 0: every input port as a bit vector, bit n = port n.
    pub fn all_inputs(&self, io_mode: i32) -> u8 {
        (0..INPUT_PORTS).fold(0, |bits, port| {
            if self.input(port, io_mode) == Some(true) {
                bits | (1 << port)
            } else {
                bits
            }
        })
    }

    /// GIO bank 2: the latch of output port `port`.
    pub fn output(&self, port: u8) -> Option<bool> {
        (port < OUTPUT_PORTS).then(|| self.outputs & (1 << port) != 0)
    }

    /// SIO bank 2: set one output latch.
    pub fn set_output(&mut self, port: u8, on: bool) {
        if port < OUTPUT_PORTS {
            if on {
                self.outputs |= 1 << port;
            } else {
                self.outputs &= !(1 << port);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_port_maps_to_exactly_one_line() {
        for port in 0..INPUT_PORTS {
            assert_eq!(
                IO_LINES
                    .iter()
                    .filter(|l| l.input_port == Some(port))
                    .count(),
                1
            );
        }
        for port in 0..OUTPUT_PORTS {
            assert_eq!(
                IO_LINES
                    .iter()
                    .filter(|l| l.output_port == Some(port))
                    .count(),
                1
            );
        }
        assert_eq!(input_line(1).map(|l| l.name), Some("PWMD0"));
        assert_eq!(output_line(2).map(|l| l.name), Some("PWMU0"));
    }

    #[test]
    fn open_inputs_follow_their_pull_ups() {
        let mut io = Io::default();
        // GP78 = 0: every bidirectional line is an input.
        assert_eq!(io.input(1, 0), Some(true));
        io.pull_ups = 0;
        assert_eq!(io.input(1, 0), Some(false));
        io.external[1] = Some(true);
        assert_eq!(io.input(1, 0), Some(true));
    }

    #[test]
    fn a_line_set_as_output_reads_its_latch() {
        let mut io = Io::default();
        io.external[4] = Some(false); // PWMU0, GIO port 4
        // GP78 bit 0 makes PWMU0 an output; it is SIO port 2.
        io.set_output(2, true);
        assert_eq!(io.input(4, 1), Some(true));
        assert_eq!(io.input(4, 0), Some(false));
    }

    #[test]
    fn ain0_digital_uses_the_threshold() {
        let mut io = Io {
            analog: AIN0_DIGITAL_THRESHOLD - 1,
            ..Io::default()
        };
        assert_eq!(io.input(0, 0), Some(false));
        io.analog = AIN0_DIGITAL_THRESHOLD;
        assert_eq!(io.input(0, 0), Some(true));
        assert_eq!(io.all_inputs(0) & 1, 1);
    }

    #[test]
    fn ports_outside_the_tables_read_nothing() {
        let io = Io::default();
        assert_eq!(io.input(7, 0), None);
        assert_eq!(io.output(8), None);
    }
}
