//! The TMCM-1110 parameter tables as data: axis parameters (manual §4
//! Table 16) and global parameters of banks 0, 2 and 3 (§5 Tables 18–20).

mod global;
pub use global::{BANK0_PARAMS, BANK2_PARAMS, BANK3_PARAMS};

use std::fmt;
use std::ops::RangeInclusive;

/// What a host may do with a parameter (§4 Table 15, §5 Table 17).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Access {
    /// R: readable with GAP/GGP.
    pub read: bool,
    /// W: writable with SAP/SGP (and AAP/AGP).
    pub write: bool,
    /// E: can be stored to / restored from EEPROM with STAP/RSAP or STGP/RSGP.
    pub eeprom: bool,
    /// A: bank-0 parameter that SGP writes through to EEPROM automatically (§5.1).
    pub auto_stored: bool,
}

impl Access {
    pub const R: Access = Access {
        read: true,
        write: false,
        eeprom: false,
        auto_stored: false,
    };
    pub const RW: Access = Access {
        read: true,
        write: true,
        eeprom: false,
        auto_stored: false,
    };
    pub const RWE: Access = Access {
        read: true,
        write: true,
        eeprom: true,
        auto_stored: false,
    };
    pub const RWA: Access = Access {
        read: true,
        write: true,
        eeprom: false,
        auto_stored: true,
    };
}

impl fmt::Display for Access {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.read {
            f.write_str("R")?;
        }
        if self.write {
            f.write_str("W")?;
        }
        if self.eeprom {
            f.write_str("E")?;
        }
        if self.auto_stored {
            f.write_str("A")?;
        }
        Ok(())
    }
}

/// The values a parameter accepts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ValueRange {
    /// Every value from `min` to `max` inclusive.
    Span { min: i64, max: i64 },
    /// Only the listed values (e.g. reference search mode, AP193).
    OneOf(&'static [i64]),
}

impl ValueRange {
    pub const fn span(min: i64, max: i64) -> Self {
        ValueRange::Span { min, max }
    }

    pub fn contains(&self, value: i64) -> bool {
        match self {
            ValueRange::Span { min, max } => (*min..=*max).contains(&value),
            ValueRange::OneOf(values) => values.contains(&value),
        }
    }
}

impl fmt::Display for ValueRange {
    /// `0..255`, or the listed values separated by commas.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ValueRange::Span { min, max } => write!(f, "{min}..{max}"),
            ValueRange::OneOf(values) => {
                let list: Vec<String> = values.iter().map(|v| v.to_string()).collect();
                f.write_str(&list.join(", "))
            }
        }
    }
}

/// The unit of a parameter's raw value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unit {
    /// A plain number, flag or code.
    None,
    /// Microsteps.
    Microsteps,
    /// TMC429 internal velocity units (§6.1.1); convert with the pulse divisor.
    VelocityInternal,
    /// TMC429 internal acceleration units (§6.1.2); convert with both divisors.
    AccelerationInternal,
    /// Milliseconds.
    Milliseconds,
    /// Units of 10 ms (AP214, WAIT ticks).
    TenMilliseconds,
    /// Encoder steps.
    EncoderSteps,
}

impl Unit {
    /// Short label for tables; empty for [`Unit::None`].
    pub fn label(self) -> &'static str {
        match self {
            Unit::None => "",
            Unit::Microsteps => "µsteps",
            Unit::VelocityInternal => "int (vel)",
            Unit::AccelerationInternal => "int (acc)",
            Unit::Milliseconds => "ms",
            Unit::TenMilliseconds => "10 ms",
            Unit::EncoderSteps => "enc steps",
        }
    }
}

/// One row of a manual parameter table. A row may cover several numbers
/// (user variables 0..55, input trigger transitions 39..44).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParamInfo {
    pub numbers: RangeInclusive<u8>,
    pub name: &'static str,
    pub range: ValueRange,
    pub unit: Unit,
    pub access: Access,
    /// The factory default, only where the manual states one.
    pub default: Option<i64>,
    /// One line, from the manual's description.
    pub description: &'static str,
    /// Manual section the row comes from.
    pub section: &'static str,
}

impl ParamInfo {
    /// The value to put into a frame's 32-bit value field for `value`, or
    /// `None` when the parameter does not accept it. Values above
    /// `i32::MAX` (bank-3 timer periods, §5.4) become their two's-complement
    /// bit pattern.
    pub fn wire_value(&self, value: i64) -> Option<i32> {
        if !self.range.contains(value) {
            return None;
        }
        i32::try_from(value)
            .ok()
            .or_else(|| u32::try_from(value).ok().map(|bits| bits as i32))
    }

    /// Whether a raw frame value (as a device or simulator receives it) is
    /// inside this parameter's range.
    pub fn accepts_wire(&self, raw: i32) -> bool {
        self.range.contains(self.value_from_wire(raw))
    }

    /// The value a user should see for a raw reply value: unsigned
    /// parameters wider than `i32` (bank-3 timer periods, §5.4) are read
    /// back as unsigned, every other parameter as signed.
    pub fn value_from_wire(&self, raw: i32) -> i64 {
        let unsigned_wide = match self.range {
            ValueRange::Span { max, .. } => max > i64::from(i32::MAX),
            ValueRange::OneOf(_) => false,
        };
        if unsigned_wide {
            i64::from(raw as u32)
        } else {
            i64::from(raw)
        }
    }
}

/// A global parameter bank (§5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Bank {
    /// Bank 0: module configuration (§5.1).
    Module = 0,
    /// Bank 2: user variables (§5.3).
    UserVariables = 2,
    /// Bank 3: interrupt configuration (§5.4).
    Interrupts = 3,
}

impl Bank {
    pub fn from_number(bank: u8) -> Option<Bank> {
        match bank {
            0 => Some(Bank::Module),
            2 => Some(Bank::UserVariables),
            3 => Some(Bank::Interrupts),
            _ => None,
        }
    }

    pub fn table(self) -> &'static [ParamInfo] {
        match self {
            Bank::Module => BANK0_PARAMS,
            Bank::UserVariables => BANK2_PARAMS,
            Bank::Interrupts => BANK3_PARAMS,
        }
    }
}

/// Values of 32-bit signed parameters (positions, user variables).
const S32: ValueRange = ValueRange::span(i32::MIN as i64, i32::MAX as i64);

/// A 0/1 flag.
const FLAG: ValueRange = ValueRange::span(0, 1);

const fn span(min: i64, max: i64) -> ValueRange {
    ValueRange::span(min, max)
}

/// AP193 (§4 Table 16, §7.1): modes 1..8; +64 searches the right switch
/// instead of the left (modes 1..4 only, §7.1.1–7.1.4), +128 inverts the
/// home switch (modes 5..8 only, §7.1.5–7.1.8).
const REFERENCE_SEARCH_MODES: &[i64] =
    &[1, 2, 3, 4, 5, 6, 7, 8, 65, 66, 67, 68, 133, 134, 135, 136];

/// Bank-3 timer periods (§5.4 Table 20) are unsigned 32-bit milliseconds
/// (0..4294967295), but the TMCL value field is a signed 32-bit number:
/// periods above 2147483647 travel as their two's-complement bit pattern.
/// The range is what a user types and sees; [`ParamInfo::wire_value`],
/// [`ParamInfo::value_from_wire`] and [`ParamInfo::accepts_wire`] translate
/// to and from the frame's value field.
const TIMER_PERIOD: ValueRange = ValueRange::span(0, u32::MAX as i64);

/// Axis parameters of the TMCM-1110 (§4 Table 16).
///
/// Where Table 16 and other parts of the manual disagree, Table 16 wins:
/// AP4 and AP5 are RWE here although §2.3 Table 1 prints RW, and AP5 starts
/// at 1 although §6.1.2 says 0..2047. One exception: AP6 is storable as
/// the manual's own STAP/RSAP examples store it (§3.6.7, §3.6.8), where
/// Table 16 prints RW; its row says so. Rows whose cells were lost or mangled
/// in the PDF conversion carry a comment saying how they were read.
pub const AXIS_PARAMS: &[ParamInfo] = &[
    ParamInfo {
        numbers: 0..=0,
        name: "Target position",
        range: S32,
        unit: Unit::Microsteps,
        access: Access::RW,
        default: None,
        description: "The desired target position in position mode (MVP writes it)",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 1..=1,
        name: "Actual position",
        range: S32,
        unit: Unit::Microsteps,
        access: Access::RW,
        default: None,
        description: "The actual position; stop the motor before overwriting it, normally only to set a reference",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 2..=2,
        name: "Target speed",
        range: span(-2047, 2047),
        unit: Unit::VelocityInternal,
        access: Access::RW,
        default: None,
        description: "The desired speed in velocity mode; not valid in position mode",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 3..=3,
        name: "Actual speed",
        range: span(-2047, 2047),
        unit: Unit::VelocityInternal,
        access: Access::R,
        default: None,
        description: "The actual speed of the motor",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 4..=4,
        name: "Maximum positioning speed",
        range: span(1, 2047),
        unit: Unit::VelocityInternal,
        access: Access::RWE,
        default: None,
        description: "The maximum speed used for positioning ramps",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 5..=5,
        name: "Maximum acceleration",
        range: span(1, 2047),
        unit: Unit::AccelerationInternal,
        access: Access::RWE,
        default: None,
        description: "Maximum acceleration on ramp-up and deceleration on ramp-down; also used in velocity mode",
        section: "§4 Table 16",
    },
    // The manual disagrees with itself: §4 Table 16 prints RW (not
    // storable), while its own examples of §3.6.7 ("Store axis parameter
    // #6") and §3.6.8 ("Restore axis parameter #6") store and restore AP6,
    // and the run current is what every TMCL-IDE user stores. The examples
    // win here (storable); the section field says so.
    ParamInfo {
        numbers: 6..=6,
        name: "Maximum current",
        range: span(0, 255),
        unit: Unit::None,
        access: Access::RWE,
        default: None,
        description: "Motor current while running; 255 = 100 % of the module maximum, effective in 32 steps of 8",
        section: "§4 Table 16 prints RW; E per the STAP/RSAP examples of §3.6.7/§3.6.8",
    },
    ParamInfo {
        numbers: 7..=7,
        name: "Standby current",
        range: span(0, 255),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Motor current at standstill (after the AP214 delay); keep as low as possible",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 8..=8,
        name: "Position reached flag",
        range: FLAG,
        unit: Unit::None,
        access: Access::R,
        default: None,
        description: "1 when actual position and target position are equal",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 9..=9,
        name: "Home switch state",
        range: FLAG,
        unit: Unit::None,
        access: Access::R,
        default: None,
        description: "The logical state of the home switch input",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 10..=10,
        name: "Right limit switch state",
        range: FLAG,
        unit: Unit::None,
        access: Access::R,
        default: None,
        description: "The logical state of the right limit switch input",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 11..=11,
        name: "Left limit switch state",
        range: FLAG,
        unit: Unit::None,
        access: Access::R,
        default: None,
        description: "The logical state of the left limit switch input",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 12..=12,
        name: "Right limit switch disable",
        range: FLAG,
        unit: Unit::None,
        access: Access::RWE,
        default: None,
        description: "0 = switch active (stops the motor), 1 = switch ignored",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 13..=13,
        name: "Left limit switch disable",
        range: FLAG,
        unit: Unit::None,
        access: Access::RWE,
        default: None,
        description: "0 = switch active (stops the motor), 1 = switch ignored",
        section: "§4 Table 16",
    },
    // §4 Table 16: description mangled ("1). Defaul der to rea ... set lower");
    // the fragments hint at a default of 1, not stated clearly enough to enshrine.
    ParamInfo {
        numbers: 130..=130,
        name: "Minimum speed",
        range: span(1, 2047),
        unit: Unit::VelocityInternal,
        access: Access::RWE,
        default: None,
        description: "Minimum ramp speed; higher reaches the target faster (description mangled in the manual)",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 135..=135,
        name: "Actual acceleration",
        range: span(-2047, 2047),
        unit: Unit::AccelerationInternal,
        access: Access::R,
        default: None,
        description: "The current acceleration",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 138..=138,
        name: "Ramp mode",
        range: span(0, 2),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "0 position mode (trapezoid ramps), 1 soft mode, 2 velocity mode; set by ROR, ROL, MST, MVP",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 140..=140,
        name: "Microstep resolution",
        range: span(0, 8),
        unit: Unit::None,
        access: Access::RW,
        default: Some(8),
        description: "2^n microsteps per full step: 0 full step .. 8 = 256 microsteps; use at least 3 (8 microsteps)",
        section: "§4 Table 16; default §6.1.4",
    },
    ParamInfo {
        numbers: 149..=149,
        name: "Soft stop flag",
        range: FLAG,
        unit: Unit::None,
        access: Access::RWE,
        default: None,
        description: "On a stop switch: 0 hard stop, 1 soft stop with the deceleration ramp",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 153..=153,
        name: "Ramp divisor",
        range: span(0, 13),
        unit: Unit::None,
        access: Access::RWE,
        default: None,
        description: "Acceleration scaling exponent; change in steps of one and only at standstill",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 154..=154,
        name: "Pulse divisor",
        range: span(0, 13),
        unit: Unit::None,
        access: Access::RWE,
        default: None,
        description: "Velocity scaling exponent; change in steps of one and only at standstill",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 160..=160,
        name: "Step interpolation enable",
        range: FLAG,
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "With 16 microsteps only: run each microstep as 16 steps of 1/256",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 161..=161,
        name: "Double step enable",
        range: FLAG,
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Execute each microstep twice; meant for the step/direction input",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 162..=162,
        name: "Chopper blank time",
        range: span(0, 3),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Comparator blank time; normally leave at the default",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 163..=163,
        name: "Constant TOff mode",
        range: FLAG,
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Chopper mode: 0 spreadCycle, 1 classic constant off time",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 164..=164,
        name: "Disable fast decay comparator",
        range: FLAG,
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Classic constant off time: 1 = don't end fast decay by the current comparator",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 165..=165,
        name: "Chopper hysteresis end / fast decay time",
        range: span(0, 15),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "spreadCycle: hysteresis end; classic constant off time: fast decay time",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 166..=166,
        name: "Chopper hysteresis start / sine wave offset",
        range: span(0, 8),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "spreadCycle: hysteresis start (offset to the end); classic constant off time: sine wave offset",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 167..=167,
        name: "Chopper off time (TOff)",
        range: span(0, 15),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "N_CLK = 12 + 32 * TOff (minimum 64 clocks); 0 switches all driver transistors off (free-wheel)",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 168..=168,
        name: "SmartEnergy current minimum (SEIMIN)",
        range: FLAG,
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "CoolStep lower current limit: 0 = 1/2 of CS, 1 = 1/4 of CS",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 169..=169,
        name: "SmartEnergy current down step",
        range: span(0, 3),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "StallGuard2 readings above the upper threshold per current decrement: 32, 8, 2, 1",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 170..=170,
        name: "SmartEnergy hysteresis",
        range: span(0, 15),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Distance between the lower and upper StallGuard2 thresholds",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 171..=171,
        name: "SmartEnergy current up step",
        range: span(0, 3),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Current increment per StallGuard2 reading below the lower threshold: 1, 2, 4, 8",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 172..=172,
        name: "SmartEnergy hysteresis start",
        range: span(0, 15),
        unit: Unit::None,
        access: Access::RW,
        default: Some(0),
        description: "Lower StallGuard2 threshold; 0 turns CoolStep off",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 173..=173,
        name: "StallGuard2 filter enable",
        range: FLAG,
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "0 standard mode, 1 filtered (one measurement per four full steps)",
        section: "§4 Table 16",
    },
    // §4 Table 16: "Zero is the starting value" reads as tuning advice, not a stated default.
    ParamInfo {
        numbers: 174..=174,
        name: "StallGuard2 threshold",
        range: span(-64, 63),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Signed StallGuard2 threshold; lower is more sensitive, 0 is the starting value",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 175..=175,
        name: "Slope control high side",
        range: span(0, 3),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Driver output slope: 0 lowest .. 3 fastest",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 176..=176,
        name: "Slope control low side",
        range: span(0, 3),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Driver output slope: 0 lowest .. 3 fastest",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 177..=177,
        name: "Short protection disable",
        range: FLAG,
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "0 short-to-GND protection on, 1 off",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 178..=178,
        name: "Short detection timer",
        range: span(0, 3),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Short circuit detection time: 0 3.2 us, 1 1.6 us, 2 1.2 us, 3 0.8 us",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 179..=179,
        name: "Vsense",
        range: FLAG,
        unit: Unit::None,
        access: Access::R,
        default: None,
        description: "Full-scale sense resistor voltage: 0 = 1/18 VDD, 1 = 1/36 VDD; do not change",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 180..=180,
        name: "SmartEnergy actual current",
        range: span(0, 31),
        unit: Unit::None,
        access: Access::R,
        default: None,
        description: "Current scale chosen by CoolStep: (n + 1)/32 of CS",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 181..=181,
        name: "Stop on stall",
        range: span(0, 2047),
        unit: Unit::VelocityInternal,
        access: Access::RW,
        default: None,
        description: "Above this speed the motor stops when the StallGuard2 load value reaches 0",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 182..=182,
        name: "SmartEnergy threshold speed",
        range: span(0, 2047),
        unit: Unit::VelocityInternal,
        access: Access::RW,
        default: None,
        description: "CoolStep is enabled above this speed",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 183..=183,
        name: "SmartEnergy slow run current",
        range: span(0, 255),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Motor current below the AP182 threshold speed; 255 = 100 %",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 184..=184,
        name: "Random TOff mode",
        range: FLAG,
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Chopper off time: 0 fixed, 1 random",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 193..=193,
        name: "Reference search mode",
        range: ValueRange::OneOf(REFERENCE_SEARCH_MODES),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Modes 1..8; +64 (modes 1..4) searches the right switch instead, +128 (modes 5..8) inverts the home switch",
        section: "§4 Table 16; §7.1",
    },
    ParamInfo {
        numbers: 194..=194,
        name: "Reference search speed",
        range: span(0, 2047),
        unit: Unit::VelocityInternal,
        access: Access::RW,
        default: None,
        description: "Speed for roughly searching the reference switch",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 195..=195,
        name: "Reference switch speed",
        range: span(0, 2047),
        unit: Unit::VelocityInternal,
        access: Access::RW,
        default: None,
        description: "Speed for locating the switching point; should be slower than AP194",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 196..=196,
        name: "End switch distance",
        range: S32,
        unit: Unit::Microsteps,
        access: Access::R,
        default: None,
        description: "Distance between the end switches after RFS in mode 2 or 3",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 197..=197,
        name: "Last reference position",
        range: S32,
        unit: Unit::Microsteps,
        access: Access::R,
        default: None,
        description: "Position just before reference search set the counter to zero",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 200..=200,
        name: "Boost current",
        range: span(0, 255),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Current during acceleration and deceleration; 0 = use AP6",
        section: "§4 Table 16",
    },
    // §4 Table 16: range and unit cells lost. 0..65535 assumed (16-bit like AP214);
    // the unit is not stated (10 ms like AP214 is likely, unverified).
    ParamInfo {
        numbers: 204..=204,
        name: "Freewheeling",
        range: span(0, 65535),
        unit: Unit::None,
        access: Access::RWE,
        default: Some(0),
        description: "Delay after the velocity reaches zero before motor power is cut; 0 = never (range and unit lost in the manual)",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 206..=206,
        name: "Actual load value",
        range: span(0, 1023),
        unit: Unit::None,
        access: Access::R,
        default: None,
        description: "StallGuard2 load reading",
        section: "§4 Table 16",
    },
    // §4 Table 16: range cell lost; the value combines flags 1 and 2.
    ParamInfo {
        numbers: 207..=207,
        name: "Extended error flags",
        range: span(0, 3),
        unit: Unit::None,
        access: Access::R,
        default: None,
        description: "Bit 0 StallGuard error, bit 1 deviation error; cleared when read or by a motion command",
        section: "§4 Table 16",
    },
    // §4 Table 16: range cell lost; the value combines flag bits 0..7.
    ParamInfo {
        numbers: 208..=208,
        name: "TMC262 error flags",
        range: span(0, 255),
        unit: Unit::None,
        access: Access::R,
        default: None,
        description: "Bits: 0 stallGuard, 1 overtemp, 2 pre-warning, 3/4 short A/B, 5/6 open load A/B, 7 standstill",
        section: "§4 Table 16",
    },
    // §4 Table 16 gives the unit as [µsteps] (the prescaler of AP210 scales encoder counts).
    ParamInfo {
        numbers: 209..=209,
        name: "Encoder position",
        range: S32,
        unit: Unit::Microsteps,
        access: Access::RW,
        default: None,
        description: "Encoder counter value",
        section: "§4 Table 16",
    },
    // §4 Table 16 says "See section 6.3"; §6.3 Table 22 lists values up to 32768 and
    // Table 23 adds flag bits 2..4, so 0..65535 covers every documented setting.
    ParamInfo {
        numbers: 210..=210,
        name: "Encoder prescaler",
        range: span(0, 65535),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Prescaler p/512 with special functions in bits 2..4 (§6.3 Tables 22, 23)",
        section: "§4 Table 16; §6.3",
    },
    // §4 Table 16: range cell mangled; only "2147483647 [encoder steps]" survived,
    // the text says 0 switches the function off.
    ParamInfo {
        numbers: 212..=212,
        name: "Maximum encoder deviation",
        range: span(0, 2147483647),
        unit: Unit::EncoderSteps,
        access: Access::RW,
        default: None,
        description: "Stop the motor when AP1 and AP209 differ by more than this; 0 = off",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 213..=213,
        name: "Group index",
        range: span(0, 255),
        unit: Unit::None,
        access: Access::RW,
        default: None,
        description: "Motors with the same index share ROL, ROR, MST, MVP and RFS commands",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 214..=214,
        name: "Power down delay",
        range: span(1, 65535),
        unit: Unit::TenMilliseconds,
        access: Access::RWE,
        default: Some(200),
        description: "Standstill time before switching to standby current (200 = 2 s)",
        section: "§4 Table 16",
    },
    ParamInfo {
        numbers: 254..=254,
        name: "Step/direction mode",
        range: FLAG,
        unit: Unit::None,
        access: Access::RWE,
        default: None,
        description: "0 normal; 1 step/direction input with automatic standstill current reduction",
        section: "§4 Table 16",
    },
];

/// The row describing axis parameter `number`, if the module has it.
pub fn axis_param(number: u8) -> Option<&'static ParamInfo> {
    AXIS_PARAMS.iter().find(|p| p.numbers.contains(&number))
}

/// The row describing global parameter `number` of `bank`, if it exists.
pub fn global_param(bank: u8, number: u8) -> Option<&'static ParamInfo> {
    Bank::from_number(bank)?
        .table()
        .iter()
        .find(|p| p.numbers.contains(&number))
}

/// Look an axis parameter up by name, case-insensitively (for completion
/// and `:help`).
pub fn axis_param_by_name(name: &str) -> Option<&'static ParamInfo> {
    AXIS_PARAMS
        .iter()
        .find(|p| p.name.eq_ignore_ascii_case(name))
}

/// Look a global parameter of `bank` up by name, case-insensitively.
pub fn global_param_by_name(bank: u8, name: &str) -> Option<&'static ParamInfo> {
    Bank::from_number(bank)?
        .table()
        .iter()
        .find(|p| p.name.eq_ignore_ascii_case(name))
}

#[cfg(test)]
mod tests;
