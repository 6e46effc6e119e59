//! The TMCM-1110 parameter tables as data: axis parameters (manual §4
//! Table 16) and global parameters of banks 0, 2 and 3 (§5 Tables 18–20).

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

/// Axis parameters of the TMCM-1110 (§4 Table 16).
pub const AXIS_PARAMS: &[ParamInfo] = &[];

/// Bank 0, module configuration (§5.1 Table 18).
pub const BANK0_PARAMS: &[ParamInfo] = &[];

/// Bank 2, user variables (§5.3 Table 19).
pub const BANK2_PARAMS: &[ParamInfo] = &[];

/// Bank 3, interrupt configuration (§5.4 Table 20).
pub const BANK3_PARAMS: &[ParamInfo] = &[];

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
