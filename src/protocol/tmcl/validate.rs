//! Checks a command against the TMCM-1110 before it is sent: one axis,
//! parameter numbers, ranges and access of §4/§5, banks, I/O ports of
//! §3.6.14/§3.6.15, coordinates, interrupts of Table 12, and the operand
//! ranges of §3.6.x. Raw frames are not checked: they are the way to send
//! anything.

use std::ops::RangeInclusive;

use super::command::{CalcFamily, CalcOp, Command, GLOBAL_INTERRUPT, INTERRUPTS, MoveMode};
use super::line::LineError;
use super::params::{self, ParamInfo, ValueRange};
use super::units::MAX_INTERNAL;

/// The only motor of the module.
pub const MOTOR: u8 = 0;

/// The motor field of SCO/GCO that selects the EEPROM copy forms (§3.6.24,
/// §3.6.25).
pub const COORDINATE_EEPROM: u8 = 255;

/// Coordinate numbers (§3.6.24: "up to 20 position values" plus the RAM-only
/// coordinate 0).
pub const COORDINATES: RangeInclusive<u8> = 0..=20;

/// Bank 2 holds the user variables (§5.3).
const USER_VARIABLE_BANK: u8 = 2;

/// One group of I/O ports of SIO (§3.6.14) or GIO (§3.6.15).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IoPorts {
    pub bank: u8,
    pub ports: RangeInclusive<u8>,
    /// What SIO may write (unused for GIO).
    pub values: ValueRange,
    pub description: &'static str,
}

/// Ports SIO may set (§3.6.14).
pub const SIO_PORTS: &[IoPorts] = &[
    IoPorts {
        bank: 2,
        ports: 0..=7,
        values: ValueRange::span(0, 1),
        description: "digital output",
    },
    IoPorts {
        bank: 2,
        ports: 255..=255,
        values: ValueRange::span(-1, 255),
        description: "all digital outputs: bit vector, -1 = accumulator",
    },
    IoPorts {
        bank: 0,
        ports: 0..=0,
        values: ValueRange::span(0, 63),
        description: "pull-up resistors: bit vector",
    },
];

/// Ports GIO may read (§3.6.15).
pub const GIO_PORTS: &[IoPorts] = &[
    IoPorts {
        bank: 0,
        ports: 0..=6,
        values: ValueRange::span(0, 1),
        description: "digital input",
    },
    IoPorts {
        bank: 0,
        ports: 255..=255,
        values: ValueRange::span(0, 255),
        description: "all digital inputs",
    },
    IoPorts {
        bank: 1,
        ports: 0..=0,
        values: ValueRange::span(0, 65535),
        description: "analog input AIN0",
    },
    IoPorts {
        bank: 2,
        ports: 0..=7,
        values: ValueRange::span(0, 1),
        description: "digital output state",
    },
];

/// Check `command` against the TMCM-1110. [`Command::Raw`] always passes.
pub fn validate(command: &Command) -> Result<(), LineError> {
    use Command::*;
    let name = mnemonic(command);
    match *command {
        Ror { motor, velocity } | Rol { motor, velocity } => {
            motor_zero(&name, motor)?;
            let limit = i64::from(MAX_INTERNAL);
            in_span(&name, "velocity", i64::from(velocity), -limit, limit, None)
        }
        Mst { motor } | Rola { motor } | Rora { motor } | Rfs { motor, .. } => {
            motor_zero(&name, motor)
        }
        Mvp {
            mode,
            motor,
            target,
        } => {
            motor_zero(&name, motor)?;
            if mode == MoveMode::Coord {
                coordinate(&name, "coordinate", i64::from(target))?;
            }
            Ok(())
        }
        Mvpa { motor, .. } => motor_zero(&name, motor),
        Sap {
            param,
            motor,
            value,
        } => {
            let context = format!("{name} {param}");
            motor_zero(&context, motor)?;
            let info = axis_param(&context, param)?;
            writable(&context, info)?;
            param_value(&context, info, value)
        }
        Gap { param, motor } => {
            let context = format!("{name} {param}");
            motor_zero(&context, motor)?;
            readable(&context, axis_param(&context, param)?)
        }
        Stap { param, motor } | Rsap { param, motor } => {
            let context = format!("{name} {param}");
            motor_zero(&context, motor)?;
            storable(&context, axis_param(&context, param)?)
        }
        Aap { param, motor } => {
            let context = format!("{name} {param}");
            motor_zero(&context, motor)?;
            writable(&context, axis_param(&context, param)?)
        }
        Sgp { param, bank, value } => {
            let context = format!("{name} {param}");
            let info = global_param(&context, bank, param)?;
            writable(&context, info)?;
            param_value(&context, info, value)
        }
        Ggp { param, bank } => {
            let context = format!("{name} {param}");
            readable(&context, global_param(&context, bank, param)?)
        }
        Agp { param, bank } => {
            let context = format!("{name} {param}");
            writable(&context, global_param(&context, bank, param)?)
        }
        Stgp { param, bank } | Rsgp { param, bank } => {
            let context = format!("{name} {param}");
            if bank != USER_VARIABLE_BANK {
                return Err(LineError::NotOneOf {
                    context,
                    operand: "bank".to_string(),
                    value: bank.to_string(),
                    allowed: USER_VARIABLE_BANK.to_string(),
                    note: Some("only user variables can be stored and restored".to_string()),
                });
            }
            storable(&context, global_param(&context, bank, param)?)
        }
        Sio { port, bank, value } => {
            let group = io_port(&name, SIO_PORTS, port, bank)?;
            if group.values.contains(i64::from(value)) {
                Ok(())
            } else {
                Err(LineError::OutOfRange {
                    context: format!("{name} {port}, {bank}"),
                    operand: "value".to_string(),
                    value: value.to_string(),
                    allowed: group.values.to_string(),
                    note: Some(group.description.to_string()),
                })
            }
        }
        Gio { port, bank } => io_port(&name, GIO_PORTS, port, bank).map(|_| ()),
        Calc { op, .. } => calc_op(&name, CalcFamily::Accumulator, op),
        Calcx { op } => calc_op(&name, CalcFamily::XRegister, op),
        Calcvv { op, .. }
        | Calcva { op, .. }
        | Calcav { op, .. }
        | Calcvx { op, .. }
        | Calcxv { op, .. } => calc_op(&name, CalcFamily::UserVariable, op),
        Calcv { op, .. } => calc_op(&name, CalcFamily::DirectValue, op),
        Jc { address, .. }
        | Ja { address }
        | Csub { address }
        | Call { address, .. }
        | Rst { address }
        | Djnz { address, .. }
        | EnterDownload { address }
        | ReadMemory { address }
        | RunApplication {
            start: Some(address),
        } => program_address(&name, address),
        Ei { interrupt } | Di { interrupt } => interrupt_number(&name, interrupt, true),
        Vect { interrupt, address } => {
            interrupt_number(&name, interrupt, false)?;
            program_address(&name, address)
        }
        Wait { motor, ticks, .. } => {
            motor_zero(&name, motor)?;
            in_span(
                &name,
                "ticks",
                i64::from(ticks),
                -1,
                i64::from(i32::MAX),
                Some("-1 = accumulator"),
            )
        }
        Sco {
            coordinate: number,
            motor,
            position,
        } => {
            coordinate(&name, "coordinate", i64::from(number))?;
            coordinate_motor(&name, motor)?;
            if motor == COORDINATE_EEPROM && position != 0 {
                return Err(LineError::OutOfRange {
                    context: name,
                    operand: "position".to_string(),
                    value: position.to_string(),
                    allowed: "0".to_string(),
                    note: Some("motor 255 copies coordinates to EEPROM".to_string()),
                });
            }
            Ok(())
        }
        Gco {
            coordinate: number,
            motor,
        } => {
            coordinate(&name, "coordinate", i64::from(number))?;
            coordinate_motor(&name, motor)
        }
        Cco {
            coordinate: number,
            motor,
        }
        | Aco {
            coordinate: number,
            motor,
        } => {
            coordinate(&name, "coordinate", i64::from(number))?;
            motor_zero(&name, motor)
        }
        UserFunction { number, .. } => {
            in_span(&name, "user function", i64::from(number), 0, 7, None)
        }
        TargetReachedEvent { motor_mask, .. } => {
            if motor_mask == 1 {
                Ok(())
            } else {
                Err(LineError::NotOneOf {
                    context: name,
                    operand: "mask".to_string(),
                    value: motor_mask.to_string(),
                    allowed: "1".to_string(),
                    note: Some("bit 0 = motor 0, the only motor".to_string()),
                })
            }
        }
        Comp { .. }
        | Rsub
        | Stop
        | Cle { .. }
        | Reti
        | Siv { .. }
        | Giv
        | Aiv
        | StopApplication
        | RunApplication { start: None }
        | StepApplication
        | ResetApplication
        | ExitDownload
        | ApplicationStatus { .. }
        | FirmwareVersion { .. }
        | FactoryReset
        | SoftwareReset
        | Raw { .. } => Ok(()),
    }
}

/// The command's name for messages ("SAP", "RUNAPP", "raw frame").
fn mnemonic(command: &Command) -> String {
    let name = if command.is_raw() {
        None
    } else {
        super::catalog::command_by_opcode(command.opcode()).map(|c| c.name)
    };
    name.unwrap_or("raw frame").to_string()
}

fn motor_zero(context: &str, motor: u8) -> Result<(), LineError> {
    if motor == MOTOR {
        Ok(())
    } else {
        Err(LineError::NoSuchMotor {
            context: context.to_string(),
            motor,
        })
    }
}

fn coordinate_motor(context: &str, motor: u8) -> Result<(), LineError> {
    if motor == MOTOR || motor == COORDINATE_EEPROM {
        Ok(())
    } else {
        Err(LineError::NotOneOf {
            context: context.to_string(),
            operand: "motor".to_string(),
            value: motor.to_string(),
            allowed: format!("{MOTOR}, {COORDINATE_EEPROM}"),
            note: Some("255 = copy between RAM and EEPROM".to_string()),
        })
    }
}

fn in_span(
    context: &str,
    operand: &str,
    value: i64,
    min: i64,
    max: i64,
    note: Option<&str>,
) -> Result<(), LineError> {
    if (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(LineError::OutOfRange {
            context: context.to_string(),
            operand: operand.to_string(),
            value: value.to_string(),
            allowed: format!("{min}..{max}"),
            note: note.map(str::to_string),
        })
    }
}

fn coordinate(context: &str, operand: &str, value: i64) -> Result<(), LineError> {
    in_span(
        context,
        operand,
        value,
        i64::from(*COORDINATES.start()),
        i64::from(*COORDINATES.end()),
        None,
    )
}

fn program_address(context: &str, address: i32) -> Result<(), LineError> {
    in_span(
        context,
        "address",
        i64::from(address),
        0,
        i64::from(i32::MAX),
        None,
    )
}

fn calc_op(context: &str, family: CalcFamily, op: super::command::CalcOp) -> Result<(), LineError> {
    use super::command::OperandCode;
    if family.allows(op) {
        Ok(())
    } else {
        Err(LineError::NotOneOf {
            context: context.to_string(),
            operand: "operation".to_string(),
            value: op.keyword().to_string(),
            allowed: family
                .ops()
                .iter()
                .map(|o: &CalcOp| o.keyword())
                .collect::<Vec<_>>()
                .join(", "),
            note: None,
        })
    }
}

fn interrupt_number(context: &str, number: u8, global_allowed: bool) -> Result<(), LineError> {
    let known = INTERRUPTS
        .iter()
        .any(|i| i.number == number && (global_allowed || i.number != GLOBAL_INTERRUPT));
    if known {
        return Ok(());
    }
    let allowed = INTERRUPTS
        .iter()
        .filter(|i| global_allowed || i.number != GLOBAL_INTERRUPT)
        .map(|i| i.number.to_string())
        .collect::<Vec<_>>()
        .join(", ");
    Err(LineError::NotOneOf {
        context: context.to_string(),
        operand: "interrupt".to_string(),
        value: number.to_string(),
        allowed,
        note: Some("manual Table 12".to_string()),
    })
}

fn axis_param(context: &str, number: u8) -> Result<&'static ParamInfo, LineError> {
    params::axis_param(number).ok_or_else(|| LineError::UnknownParameter {
        context: context.to_string(),
        table: "axis parameter".to_string(),
        number,
    })
}

fn global_param(context: &str, bank: u8, number: u8) -> Result<&'static ParamInfo, LineError> {
    if params::Bank::from_number(bank).is_none() {
        return Err(LineError::NotOneOf {
            context: context.to_string(),
            operand: "bank".to_string(),
            value: bank.to_string(),
            allowed: "0, 2, 3".to_string(),
            note: Some("0 = module settings, 2 = user variables, 3 = interrupts".to_string()),
        });
    }
    params::global_param(bank, number).ok_or_else(|| LineError::UnknownParameter {
        context: context.to_string(),
        table: format!("global parameter in bank {bank} numbered"),
        number,
    })
}

fn writable(context: &str, info: &'static ParamInfo) -> Result<(), LineError> {
    if info.access.write {
        Ok(())
    } else {
        Err(LineError::ReadOnly {
            context: context.to_string(),
            name: info.name,
        })
    }
}

fn readable(context: &str, info: &'static ParamInfo) -> Result<(), LineError> {
    if info.access.read {
        Ok(())
    } else {
        Err(LineError::WriteOnly {
            context: context.to_string(),
            name: info.name,
        })
    }
}

fn storable(context: &str, info: &'static ParamInfo) -> Result<(), LineError> {
    if info.access.eeprom {
        Ok(())
    } else {
        Err(LineError::NotStorable {
            context: context.to_string(),
            name: info.name,
            access: info.access.to_string(),
        })
    }
}

/// A parameter value within its range, read as the parameter reads frame
/// values (bank-3 timer periods are unsigned 32-bit, §5.4).
fn param_value(context: &str, info: &'static ParamInfo, value: i32) -> Result<(), LineError> {
    if info.accepts_wire(value) {
        return Ok(());
    }
    let value = info.value_from_wire(value);
    let (context, operand, value, allowed) = (
        context.to_string(),
        "value".to_string(),
        value.to_string(),
        info.range.to_string(),
    );
    let note = Some(info.name.to_string());
    Err(match info.range {
        ValueRange::Span { .. } => LineError::OutOfRange {
            context,
            operand,
            value,
            allowed,
            note,
        },
        ValueRange::OneOf(_) => LineError::NotOneOf {
            context,
            operand,
            value,
            allowed,
            note,
        },
    })
}

/// Why a port/bank pair is not in an I/O table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IoPortMiss {
    /// The command has no such bank.
    Bank,
    /// The bank exists but has no such port.
    Port,
}

/// The group of [`SIO_PORTS`] or [`GIO_PORTS`] that `port` of `bank`
/// belongs to. Shared by the console's validation and the simulator.
pub fn find_io_port(table: &[IoPorts], port: u8, bank: u8) -> Result<&IoPorts, IoPortMiss> {
    let mut in_bank = table.iter().filter(|g| g.bank == bank).peekable();
    if in_bank.peek().is_none() {
        return Err(IoPortMiss::Bank);
    }
    in_bank
        .find(|g| g.ports.contains(&port))
        .ok_or(IoPortMiss::Port)
}

fn io_port<'t>(
    name: &str,
    table: &'t [IoPorts],
    port: u8,
    bank: u8,
) -> Result<&'t IoPorts, LineError> {
    let miss = match find_io_port(table, port, bank) {
        Ok(group) => return Ok(group),
        Err(miss) => miss,
    };
    let in_bank: Vec<&IoPorts> = table.iter().filter(|g| g.bank == bank).collect();
    if miss == IoPortMiss::Bank {
        let mut banks: Vec<u8> = table.iter().map(|g| g.bank).collect();
        banks.dedup();
        return Err(LineError::NotOneOf {
            context: name.to_string(),
            operand: "bank".to_string(),
            value: bank.to_string(),
            allowed: join(banks.iter()),
            note: None,
        });
    }
    let ports: Vec<String> = in_bank
        .iter()
        .map(|g| {
            if g.ports.start() == g.ports.end() {
                g.ports.start().to_string()
            } else {
                format!("{}..{}", g.ports.start(), g.ports.end())
            }
        })
        .collect();
    Err(LineError::NotOneOf {
        context: name.to_string(),
        operand: "port".to_string(),
        value: port.to_string(),
        allowed: ports.join(", "),
        note: Some(format!("bank {bank}")),
    })
}

fn join<T: ToString>(items: impl Iterator<Item = T>) -> String {
    items.map(|i| i.to_string()).collect::<Vec<_>>().join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::tmcl::line::parse_line;

    #[test]
    fn ror_velocity_is_limited_to_2047() {
        assert!(parse_line("ROR 0, 2047").is_ok());
        assert!(parse_line("ROL 0, -2047").is_ok());
        let err = parse_line("ROL 0, 51200").unwrap_err();
        assert_eq!(err.to_string(), "ROL: velocity 51200 outside -2047..2047");
    }

    #[test]
    fn only_motor_0_exists() {
        let err = parse_line("MST 1").unwrap_err();
        assert_eq!(
            err.to_string(),
            "MST: motor 1 does not exist: the TMCM-1110 has one axis, motor 0"
        );
        assert!(parse_line("RORA 0").is_ok());
    }

    #[test]
    fn coordinates_are_0_to_20() {
        assert!(parse_line("MVP COORD, 0, 20").is_ok());
        assert!(parse_line("MVP COORD, 0, 21").is_err());
        assert!(parse_line("MVP ABS, 0, 21").is_ok());
        assert!(parse_line("SCO 21, 0, 5").is_err());
        assert!(parse_line("SCO 0, 255, 0").is_ok());
        assert!(parse_line("SCO 3, 255, 7").is_err());
        assert!(parse_line("GCO 0, 255, 0").is_ok());
        assert!(parse_line("CCO 3, 255").is_err());
        assert!(parse_line("ACO 20, 0").is_ok());
    }

    #[test]
    fn io_ports_follow_3_6_14_and_3_6_15() {
        assert!(parse_line("SIO 7, 2, 1").is_ok());
        assert!(parse_line("SIO 255, 2, -1").is_ok());
        assert!(parse_line("SIO 255, 2, 255").is_ok());
        assert!(parse_line("SIO 0, 0, 63").is_ok());
        let err = parse_line("SIO 255, 2, 256").unwrap_err();
        assert!(err.to_string().contains("outside -1..255"), "{err}");
        assert!(parse_line("SIO 0, 2, 2").is_err());
        let err = parse_line("SIO 8, 2, 1").unwrap_err();
        assert_eq!(
            err.to_string(),
            "SIO: port 8 is not one of 0..7, 255 (bank 2)"
        );
        assert!(parse_line("SIO 0, 1, 1").is_err());
        assert!(parse_line("GIO 255, 0").is_ok());
        assert!(parse_line("GIO 0, 1").is_ok());
        assert!(parse_line("GIO 1, 1").is_err());
        assert!(parse_line("GIO 7, 0").is_err());
        assert!(parse_line("GIO 255, 2").is_err());
    }

    #[test]
    fn wait_takes_minus_one_at_least() {
        assert!(parse_line("WAIT TICKS, 0, -1").is_ok());
        let err = parse_line("WAIT POS, 0, -2").unwrap_err();
        assert!(err.to_string().contains("ticks -2 outside -1.."), "{err}");
    }

    #[test]
    fn interrupts_come_from_table_12() {
        assert!(parse_line("EI 255").is_ok());
        assert!(parse_line("DI 44").is_ok());
        assert!(parse_line("EI 4").is_err());
        assert!(parse_line("VECT 27, 100").is_ok());
        assert!(parse_line("VECT 255, 100").is_err());
    }

    #[test]
    fn addresses_are_not_negative() {
        assert!(parse_line("JA -1").is_err());
        assert!(parse_line("RUNAPP -5").is_err());
        assert!(parse_line("RUNAPP 5").is_ok());
    }

    #[test]
    fn target_event_mask_is_motor_0_only() {
        assert!(parse_line("TARGETEVENT ONCE").is_ok());
        assert!(parse_line("TARGETEVENT ALWAYS, 3").is_err());
    }

    #[test]
    fn typed_commands_built_with_a_foreign_operation_are_refused() {
        let err = validate(&Command::Calc {
            op: CalcOp::Swap,
            operand: 0,
        })
        .unwrap_err();
        assert!(err.to_string().starts_with("CALC: operation SWAP"), "{err}");
    }

    #[test]
    fn raw_frames_pass() {
        assert!(parse_line("5 6 1 300").is_ok());
    }
}
