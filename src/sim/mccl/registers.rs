//! The shared registers R10–R999, the scratch pad memory (ME/FM, Wx/Rx,
//! FT/FD, DE) and the motor-table variables LU looks up (manual Ch4
//! "Reading Data from Controller Memory", "MultiFlex Scratch Pad Memory").
//!
//! R0–R9 belong to each interpreter (the foreground of the port and every
//! task: Ch4 "local" registers), so they live in
//! [`super::interpreter::Interpreter`].
//!
//! LU gives a token, not a real address (the layout is internal): a number
//! above the scratch pad that `aRx@0` turns into the variable of axis a.
//! Writing to a token is not simulated (Wx are "for factory use only").

use super::axis::Axis;
use super::axis::status::{StatusWord, Surroundings};
use super::values::Value;

pub const REGISTERS: usize = 1000;
/// R0–R9 are each interpreter's own.
pub const LOCAL_REGISTERS: usize = 10;
/// Ch4: "By default this scratch pad memory area is 64KB".
pub const SCRATCH_BYTES: usize = 65536;
/// The first address ME gives (0 means "no memory", Ch13 ME).
const FIRST_ADDRESS: usize = 16;
/// LU tokens start here, above every scratch address.
pub const TOKEN_BASE: i64 = 0x0004_0000;

#[derive(Debug, Clone)]
pub struct Registers {
    global: Vec<Value>,
}

impl Default for Registers {
    fn default() -> Self {
        Registers {
            global: vec![Value::Int(0); REGISTERS],
        }
    }
}

impl Registers {
    /// R`n` for n ≥ 10.
    pub fn get(&self, n: usize) -> Option<Value> {
        (n >= LOCAL_REGISTERS).then(|| self.global.get(n).copied())?
    }

    pub fn set(&mut self, n: usize, value: Value) -> bool {
        match self.global.get_mut(n).filter(|_| n >= LOCAL_REGISTERS) {
            Some(slot) => {
                *slot = value;
                true
            }
            None => false,
        }
    }
}

/// How wide a memory read or write is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Width {
    Byte,
    Word,
    Long,
    Float,
    Double,
}

impl Width {
    pub fn bytes(self) -> usize {
        match self {
            Width::Byte => 1,
            Width::Word => 2,
            Width::Long | Width::Float => 4,
            Width::Double => 8,
        }
    }

    /// `value` as this width stores it, read back (a long of a double is
    /// truncated, a word keeps its low 16 bits).
    pub fn convert(self, value: f64) -> Value {
        let integer = if value.is_finite() {
            value.trunc().clamp(i64::MIN as f64, i64::MAX as f64) as i64
        } else {
            0
        };
        match self {
            Width::Byte => Value::Int(i32::from(integer as u8)),
            Width::Word => Value::Int(i32::from(integer as u16)),
            Width::Long => Value::Int(integer as i32),
            Width::Float => Value::Float(value as f32),
            Width::Double => Value::Double(value),
        }
    }
}

/// The scratch pad: 64 KB, blocks given by ME and freed by FM.
#[derive(Debug, Clone)]
pub struct Scratch {
    bytes: Vec<u8>,
    /// Allocated blocks (start, length), by start.
    blocks: Vec<(usize, usize)>,
}

impl Default for Scratch {
    fn default() -> Self {
        Scratch {
            bytes: vec![0; SCRATCH_BYTES],
            blocks: Vec::new(),
        }
    }
}

impl Scratch {
    /// ME n: the first address of n free bytes (first fit), or `None`.
    pub fn allocate(&mut self, n: usize) -> Option<usize> {
        if n == 0 {
            return None;
        }
        let mut start = FIRST_ADDRESS;
        for &(at, len) in &self.blocks {
            if at >= start + n {
                break;
            }
            start = start.max(at + len);
        }
        if start + n > SCRATCH_BYTES {
            return None;
        }
        let at = self.blocks.partition_point(|&(a, _)| a < start);
        self.blocks.insert(at, (start, n));
        Some(start)
    }

    /// FM n: n must be an address ME gave.
    pub fn free(&mut self, address: usize) -> bool {
        match self.blocks.iter().position(|&(a, _)| a == address) {
            Some(i) => {
                self.blocks.remove(i);
                true
            }
            None => false,
        }
    }

    pub fn read(&self, address: usize, width: Width) -> Option<Value> {
        let bytes = self.bytes.get(address..address + width.bytes())?;
        Some(match width {
            Width::Byte => Value::Int(i32::from(bytes[0])),
            Width::Word => Value::Int(i32::from(u16::from_le_bytes([bytes[0], bytes[1]]))),
            Width::Long => Value::Int(i32::from_le_bytes(bytes.try_into().ok()?)),
            Width::Float => Value::Float(f32::from_le_bytes(bytes.try_into().ok()?)),
            Width::Double => Value::Double(f64::from_le_bytes(bytes.try_into().ok()?)),
        })
    }

    pub fn write(&mut self, address: usize, width: Width, value: Value) -> bool {
        let data: Vec<u8> = match width {
            Width::Byte => vec![value.rounded() as u8],
            Width::Word => (value.rounded() as u16).to_le_bytes().to_vec(),
            Width::Long => value.rounded().to_le_bytes().to_vec(),
            Width::Float => (value.as_f64() as f32).to_le_bytes().to_vec(),
            Width::Double => value.as_f64().to_le_bytes().to_vec(),
        };
        match self.bytes.get_mut(address..address + data.len()) {
            Some(slot) => {
                slot.copy_from_slice(&data);
                true
            }
            None => false,
        }
    }

    /// A NUL-terminated string in a new block (FT, FD, AV1): its address.
    pub fn store_text(&mut self, text: &str) -> Option<usize> {
        let address = self.allocate(text.len() + 1)?;
        self.bytes[address..address + text.len()].copy_from_slice(text.as_bytes());
        self.bytes[address + text.len()] = 0;
        Some(address)
    }

    /// DE: 256 bytes from `address` (fewer at the end of memory).
    pub fn dump(&self, address: usize) -> &[u8] {
        let end = (address + 256).min(SCRATCH_BYTES);
        self.bytes.get(address..end).unwrap_or_default()
    }
}

/// What a motor-table variable holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    InterruptMask,
    InterruptPending,
    Status,
    AuxStatus,
    PositionAdjustment,
    PositionCount,
    IndexCount,
    OptimalCount,
    TargetCount,
    Backlash,
    EncoderScale,
    EncoderFault,
    MaxError,
    Position,
    Target,
    Optimal,
    Breakpoint,
    Deadband,
    Acceleration,
    Deceleration,
    MinimumVelocity,
    Velocity,
    Scale,
    Offset,
    OutputConstant,
    Rate,
    Zero,
    LowLimit,
    HighLimit,
    TargetDelay,
    CurrentVelocity,
    VelocityGainScaled,
    VelocityGain,
    AccelerationGain,
    DecelerationGain,
    OutputDeadband,
    ProportionalGain,
    DerivativeGain,
    IntegralGain,
    IntegrationLimit,
    Torque,
    OutputOffset,
    VelocityOverride,
    AxisNumber,
    CoefficientMax,
    CoefficientCount,
    Master,
    InputMode,
    IntegralOption,
    DerivativePeriod,
    WaitStop,
    WaitTarget,
}

/// One variable of the motor tables (Ch4), with the width its read uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Variable {
    pub name: &'static str,
    pub width: Width,
    pub quantity: Quantity,
}

const fn var(name: &'static str, width: Width, quantity: Quantity) -> Variable {
    Variable {
        name,
        width,
        quantity,
    }
}

/// Ch4's tables: long, double, float, word (the headings of the second
/// and third are displaced in the text; double and float assigned as the
/// digest reads them, with `LU"POSITION",3RD@0` reading a double).
pub const VARIABLES: &[Variable] = &[
    var("INTMASK", Width::Long, Quantity::InterruptMask),
    var("INTPEND", Width::Long, Quantity::InterruptPending),
    var("STATUS", Width::Long, Quantity::Status),
    var("AUXSTAT", Width::Long, Quantity::AuxStatus),
    var("CITADS", Width::Long, Quantity::PositionAdjustment),
    var("POSCOUNT", Width::Long, Quantity::PositionCount),
    var("IDXCOUNT", Width::Long, Quantity::IndexCount),
    var("CMDCOUNT", Width::Long, Quantity::OptimalCount),
    var("TGTCOUNT", Width::Long, Quantity::TargetCount),
    var("BACKLASH", Width::Double, Quantity::Backlash),
    var("ENCSCALE", Width::Double, Quantity::EncoderScale),
    var("ENCODERFLT", Width::Double, Quantity::EncoderFault),
    var("MAXERROR", Width::Double, Quantity::MaxError),
    var("POSITION", Width::Double, Quantity::Position),
    var("TARGET", Width::Double, Quantity::Target),
    var("OPTIMAL", Width::Double, Quantity::Optimal),
    var("BRKPOS", Width::Double, Quantity::Breakpoint),
    var("POSDBAND", Width::Double, Quantity::Deadband),
    var("PGMACC", Width::Double, Quantity::Acceleration),
    var("PGMDEC", Width::Double, Quantity::Deceleration),
    var("MINVEL", Width::Double, Quantity::MinimumVelocity),
    var("PGMVEL", Width::Double, Quantity::Velocity),
    var("SCALE", Width::Double, Quantity::Scale),
    var("OFFSET", Width::Double, Quantity::Offset),
    var("OUTCONST", Width::Double, Quantity::OutputConstant),
    var("RATE", Width::Double, Quantity::Rate),
    var("ZERO", Width::Double, Quantity::Zero),
    var("LOLIM", Width::Double, Quantity::LowLimit),
    var("HILIM", Width::Double, Quantity::HighLimit),
    var("TGTDELAY", Width::Double, Quantity::TargetDelay),
    var("CURVEL", Width::Double, Quantity::CurrentVelocity),
    var("VELGAIN", Width::Double, Quantity::VelocityGainScaled),
    var("KVEL", Width::Float, Quantity::VelocityGain),
    var("KACC", Width::Float, Quantity::AccelerationGain),
    var("KDEC", Width::Float, Quantity::DecelerationGain),
    var("OUTDBAND", Width::Float, Quantity::OutputDeadband),
    var("KPOS", Width::Float, Quantity::ProportionalGain),
    var("KDER", Width::Float, Quantity::DerivativeGain),
    var("KINT", Width::Float, Quantity::IntegralGain),
    var("ILIM", Width::Float, Quantity::IntegrationLimit),
    var("MAXTRQ", Width::Float, Quantity::Torque),
    var("OUTOFFSET", Width::Float, Quantity::OutputOffset),
    var("VELOVRD", Width::Float, Quantity::VelocityOverride),
    var("AXISNUM", Width::Word, Quantity::AxisNumber),
    var("COEFMAX", Width::Word, Quantity::CoefficientMax),
    var("COEFCNT", Width::Word, Quantity::CoefficientCount),
    var("MASTER", Width::Word, Quantity::Master),
    var("INPUTMODE", Width::Word, Quantity::InputMode),
    var("INTEGRALOPT", Width::Word, Quantity::IntegralOption),
    var("SFREQ", Width::Word, Quantity::DerivativePeriod),
    var("WAITSTOP", Width::Word, Quantity::WaitStop),
    var("WAITTARGET", Width::Word, Quantity::WaitTarget),
];

/// LU"name": the token of the variable (names in any case).
pub fn look_up(name: &str) -> Option<i64> {
    VARIABLES
        .iter()
        .position(|v| v.name.eq_ignore_ascii_case(name))
        .map(|i| TOKEN_BASE + i as i64 * 8)
}

/// The variable a token names.
pub fn variable_of(token: i64) -> Option<&'static Variable> {
    let offset = token.checked_sub(TOKEN_BASE)?;
    if offset % 8 != 0 {
        return None;
    }
    VARIABLES.get(usize::try_from(offset / 8).ok()?)
}

/// The value of `quantity` on `axis`, in its table's units (positions and
/// speeds in user units; the raw counts in counts).
pub fn read_variable(axis: &Axis, quantity: Quantity, around: &Surroundings) -> f64 {
    let s = &axis.settings;
    let u = &axis.units;
    let bool_value = |b: bool| if b { 1.0 } else { 0.0 };
    match quantity {
        Quantity::InterruptMask | Quantity::InterruptPending => 0.0,
        Quantity::Status => f64::from(axis.status_word(StatusWord::Primary, around)),
        Quantity::AuxStatus => f64::from(axis.status_word(StatusWord::Auxiliary, around)),
        Quantity::PositionAdjustment => 0.0,
        Quantity::PositionCount => axis.position(),
        Quantity::IndexCount => axis.index_position,
        Quantity::OptimalCount => axis.optimal.round(),
        Quantity::TargetCount => axis.target.round(),
        Quantity::Backlash => s.backlash,
        Quantity::EncoderScale => s.steps_per_count,
        Quantity::EncoderFault => bool_value(axis.encoder_fault),
        Quantity::MaxError => s.following_limit,
        Quantity::Position => u.to_user(axis.position()),
        Quantity::Target => u.to_user(axis.target),
        Quantity::Optimal => u.to_user(axis.optimal),
        Quantity::Breakpoint => u.to_user(axis.breakpoint_at),
        Quantity::Deadband => s.deadband,
        Quantity::Acceleration => s.acceleration,
        Quantity::Deceleration => s.deceleration,
        Quantity::MinimumVelocity => s.minimum_velocity,
        Quantity::Velocity => s.velocity,
        Quantity::Scale => s.units.scale,
        Quantity::Offset => s.units.offset,
        Quantity::OutputConstant => s.output_constant,
        Quantity::Rate => s.units.rate,
        Quantity::Zero => s.units.zero,
        Quantity::LowLimit => s.low_limit,
        Quantity::HighLimit => s.high_limit,
        Quantity::TargetDelay => s.target_delay,
        Quantity::CurrentVelocity => u.speed_to_user(axis.velocity),
        Quantity::VelocityGainScaled | Quantity::VelocityGain => s.velocity_gain,
        Quantity::AccelerationGain => s.acceleration_gain,
        Quantity::DecelerationGain => s.deceleration_gain,
        Quantity::OutputDeadband => s.output_deadband,
        Quantity::ProportionalGain => s.proportional_gain,
        Quantity::DerivativeGain => s.derivative_gain,
        Quantity::IntegralGain => s.integral_gain,
        Quantity::IntegrationLimit => s.integration_limit,
        Quantity::Torque => s.torque,
        Quantity::OutputOffset => s.output_offset,
        Quantity::VelocityOverride => s.velocity_override,
        Quantity::AxisNumber => f64::from(axis.number),
        Quantity::CoefficientMax | Quantity::CoefficientCount => 0.0,
        Quantity::Master => axis.slave.map_or(0.0, |m| f64::from(m.master)),
        Quantity::InputMode => f64::from(s.input_mode),
        Quantity::IntegralOption => f64::from(s.integral_option),
        Quantity::DerivativePeriod => s.derivative_period as f64,
        Quantity::WaitStop | Quantity::WaitTarget => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn r0_to_r9_are_not_global() {
        let mut registers = Registers::default();
        assert_eq!(registers.get(9), None);
        assert!(!registers.set(0, Value::Int(1)));
        assert!(registers.set(999, Value::Double(1.5)));
        assert_eq!(registers.get(999), Some(Value::Double(1.5)));
        assert_eq!(registers.get(1000), None);
    }

    #[test]
    fn scratch_blocks_are_first_fit_and_freed_by_address() {
        let mut scratch = Scratch::default();
        let a = scratch.allocate(100).expect("room");
        let b = scratch.allocate(100).expect("room");
        assert_eq!((a, b), (16, 116));
        assert!(scratch.free(a));
        assert!(!scratch.free(a), "freed already");
        assert_eq!(scratch.allocate(50), Some(16), "reuses the hole");
        assert_eq!(scratch.allocate(SCRATCH_BYTES), None);
        assert!(scratch.write(b, Width::Double, Value::Double(2.5)));
        assert_eq!(scratch.read(b, Width::Double), Some(Value::Double(2.5)));
        assert!(scratch.write(b, Width::Word, Value::Int(-1)));
        assert_eq!(scratch.read(b, Width::Word), Some(Value::Int(65535)));
        assert_eq!(scratch.read(SCRATCH_BYTES - 2, Width::Long), None);
    }

    #[test]
    fn lu_tokens_name_the_manuals_variables() {
        let status = look_up("status").expect("STATUS");
        assert_eq!(variable_of(status).map(|v| v.name), Some("STATUS"));
        assert_eq!(
            look_up("POSITION").and_then(variable_of).map(|v| v.width),
            Some(Width::Double)
        );
        assert_eq!(look_up("NOSUCH"), None);
        assert_eq!(variable_of(TOKEN_BASE + 3), None);
        assert!(TOKEN_BASE > SCRATCH_BYTES as i64);
    }
}
