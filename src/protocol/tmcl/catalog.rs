//! The TMCL command catalogue as data: every mnemonic of §3.4 Table 5 and
//! §3.5.7 Table 13, the control commands of §3.6.53 Table 14 and command
//! 138 (§3.6.52) under console names, with their operands. The console line
//! parser and formatter ([`super::line`]) are driven by this table; help and
//! tab completion read it too.

use super::command::{
    CalcFamily, ClearFlag, Condition, EventMode, MoveMode, OperandCode, RfsAction, StatusQuery,
    VersionFormat, WaitCondition, opcode,
};
use super::params::{self, ParamInfo};

/// The frame field an operand is written to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    /// Byte 2, "Type".
    Type,
    /// Byte 3, "Motor/Bank".
    MotorBank,
    /// Bytes 4..7, the signed 32-bit value.
    Value,
}

/// A set of symbolic codes an operand accepts (besides their numbers).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CodeSet {
    MoveMode,
    RfsAction,
    Calc(CalcFamily),
    Condition,
    WaitCondition,
    ClearFlag,
    StatusQuery,
    VersionFormat,
    EventMode,
}

fn entries_of<T: OperandCode>() -> Vec<(&'static str, u8)> {
    T::ALL.iter().map(|v| (v.keyword(), v.code())).collect()
}

impl CodeSet {
    /// Every (symbol, code) pair of the set, in code order.
    pub fn entries(self) -> Vec<(&'static str, u8)> {
        match self {
            CodeSet::MoveMode => entries_of::<MoveMode>(),
            CodeSet::RfsAction => entries_of::<RfsAction>(),
            CodeSet::Calc(family) => family
                .ops()
                .iter()
                .map(|op| (op.keyword(), op.code()))
                .collect(),
            CodeSet::Condition => entries_of::<Condition>(),
            CodeSet::WaitCondition => entries_of::<WaitCondition>(),
            CodeSet::ClearFlag => entries_of::<ClearFlag>(),
            CodeSet::StatusQuery => entries_of::<StatusQuery>(),
            CodeSet::VersionFormat => entries_of::<VersionFormat>(),
            CodeSet::EventMode => entries_of::<EventMode>(),
        }
    }

    /// The code of a symbol, case-insensitively.
    pub fn code_of(self, word: &str) -> Option<u8> {
        self.entries()
            .into_iter()
            .find(|(k, _)| k.eq_ignore_ascii_case(word))
            .map(|(_, c)| c)
    }

    /// The symbol of a code, if the set has it.
    pub fn keyword_of(self, code: u8) -> Option<&'static str> {
        self.entries()
            .into_iter()
            .find(|(_, c)| *c == code)
            .map(|(k, _)| k)
    }

    /// "ABS (0), REL (1), COORD (2)", for error messages and help.
    pub fn describe(self) -> String {
        self.entries()
            .iter()
            .map(|(k, c)| format!("{k} ({c})"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// What an operand accepts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OperandKind {
    /// A number 0..255 (parameter, motor, bank, port, variable…).
    Byte,
    /// A signed 32-bit number; hex may give the bit pattern.
    Number,
    /// The value of the parameter named by the type field (SAP, SGP): a
    /// signed 32-bit number, except for parameters read back as unsigned
    /// 32-bit (bank-3 timer periods 0..4294967295, §5.4 Table 20), whose
    /// decimal values go up to their maximum. Hex gives the bit pattern.
    ParamValue(ParamTable),
    /// A program address: a number, or a label through a symbol resolver.
    Label,
    /// A symbol of the set, or its number.
    Code(CodeSet),
    /// Only 0: written in the manual's form `GCO 0, 255, 0` but not sent.
    Zero,
}

/// The parameter table a [`OperandKind::ParamValue`] belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamTable {
    /// Axis parameters (§4 Table 16); the motor/bank field is the motor.
    Axis,
    /// Global parameters (§5 Tables 18–20); the motor/bank field is the bank.
    Global,
}

impl ParamTable {
    /// The row of parameter `number` (the type field) with `motor_bank` as
    /// the frame carries it, if the TMCM-1110 has one.
    pub fn param(self, number: u8, motor_bank: u8) -> Option<&'static ParamInfo> {
        match self {
            ParamTable::Axis => params::axis_param(number),
            ParamTable::Global => params::global_param(motor_bank, number),
        }
    }
}

/// Whether an operand may be left out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Presence {
    Required,
    /// May be left out; then this value is used.
    Default(i64),
    /// May be left out; when given, the type field becomes this code (129
    /// "run application": type 1 = from the given address).
    SetsType(u8),
}

/// One operand of a console line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Operand {
    /// The manual's name, as in `<motor>`.
    pub name: &'static str,
    pub field: Field,
    pub kind: OperandKind,
    pub presence: Presence,
}

/// Where a command is meant to be used (§3.5, §3.6.x).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Usage {
    /// Direct mode and TMCL programs.
    DirectAndStandalone,
    /// Intended for TMCL programs (the manual: "standalone mode only" or
    /// "mainly"); a module still executes it in direct mode.
    Standalone,
    /// Direct mode only: control commands, 138, 255 (no mnemonic).
    DirectOnly,
    /// Customer-specific firmware extension (UF0..UF7).
    UserDefined,
}

/// One row of the catalogue.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CommandInfo {
    /// Mnemonic, or the console name of a command without one.
    pub name: &'static str,
    pub opcode: u8,
    /// Console syntax, `[..]` = optional.
    pub syntax: &'static str,
    pub summary: &'static str,
    /// Manual section.
    pub section: &'static str,
    pub usage: Usage,
    pub operands: &'static [Operand],
    /// The value field when no operand fills it (1234 for 137 and 255).
    pub fixed_value: i32,
}

const fn req(name: &'static str, field: Field, kind: OperandKind) -> Operand {
    Operand {
        name,
        field,
        kind,
        presence: Presence::Required,
    }
}

const fn opt(name: &'static str, field: Field, kind: OperandKind, default: i64) -> Operand {
    Operand {
        name,
        field,
        kind,
        presence: Presence::Default(default),
    }
}

use Field::{MotorBank, Type, Value};
use OperandKind::{Byte, Code, Label, Number, ParamValue, Zero};
use Usage::{DirectAndStandalone as Both, DirectOnly, Standalone, UserDefined};

const MOTOR: Operand = req("motor", MotorBank, Byte);
const AXIS_PARAM: Operand = req("parameter", Type, Byte);
const GLOBAL_PARAM: Operand = req("parameter", Type, Byte);
const BANK: Operand = req("bank", MotorBank, Byte);
const COORDINATE: Operand = req("coordinate", Type, Byte);
const ADDRESS: Operand = req("label", Value, Label);
const CONDITION: Operand = req("condition", Type, Code(CodeSet::Condition));
const VAR_OP: Operand = req(
    "operation",
    Type,
    Code(CodeSet::Calc(CalcFamily::UserVariable)),
);
const VAR: Operand = req("var", MotorBank, Byte);
const INTERRUPT: Operand = req("interrupt", Type, Byte);
const MOVE_MODE: Operand = req("mode", Type, Code(CodeSet::MoveMode));
const USER_FUNCTION: &[Operand] = &[
    opt("type", Type, Byte, 0),
    opt("motor/bank", MotorBank, Byte, 0),
    opt("value", Value, Number, 0),
];

const fn row(
    name: &'static str,
    opcode: u8,
    syntax: &'static str,
    summary: &'static str,
    section: &'static str,
    usage: Usage,
    operands: &'static [Operand],
) -> CommandInfo {
    CommandInfo {
        name,
        opcode,
        syntax,
        summary,
        section,
        usage,
        operands,
        fixed_value: 0,
    }
}

/// Every command, in instruction-number order.
#[rustfmt::skip]
pub const COMMANDS: &[CommandInfo] = &[
    row("ROR", opcode::ROR, "ROR <motor>, <velocity>",
        "Rotate right (position counter increases) with the given velocity [int]",
        "3.6.1", Both, &[MOTOR, req("velocity", Value, Number)]),
    row("ROL", opcode::ROL, "ROL <motor>, <velocity>",
        "Rotate left (position counter decreases) with the given velocity [int]",
        "3.6.2", Both, &[MOTOR, req("velocity", Value, Number)]),
    row("MST", opcode::MST, "MST <motor>", "Stop the motor (soft stop)",
        "3.6.3", Both, &[MOTOR]),
    row("MVP", opcode::MVP, "MVP ABS|REL|COORD, <motor>, <position|offset|coordinate>",
        "Move to an absolute position, by an offset, or to a stored coordinate",
        "3.6.4", Both, &[MOVE_MODE, MOTOR, req("position|offset|coordinate", Value, Number)]),
    row("SAP", opcode::SAP, "SAP <parameter>, <motor>, <value>",
        "Set an axis parameter (RAM)", "3.6.5", Both,
        &[AXIS_PARAM, MOTOR, req("value", Value, ParamValue(ParamTable::Axis))]),
    row("GAP", opcode::GAP, "GAP <parameter>, <motor>", "Get an axis parameter",
        "3.6.6", Both, &[AXIS_PARAM, MOTOR]),
    row("STAP", opcode::STAP, "STAP <parameter>, <motor>",
        "Store an axis parameter in EEPROM", "3.6.7", Both, &[AXIS_PARAM, MOTOR]),
    row("RSAP", opcode::RSAP, "RSAP <parameter>, <motor>",
        "Restore an axis parameter from EEPROM", "3.6.8", Both, &[AXIS_PARAM, MOTOR]),
    row("SGP", opcode::SGP, "SGP <parameter>, <bank>, <value>",
        "Set a global parameter (bank 0 module settings, 2 user variables, 3 interrupts)",
        "3.6.9", Both,
        &[GLOBAL_PARAM, BANK, req("value", Value, ParamValue(ParamTable::Global))]),
    row("GGP", opcode::GGP, "GGP <parameter>, <bank>", "Get a global parameter",
        "3.6.10", Both, &[GLOBAL_PARAM, BANK]),
    row("STGP", opcode::STGP, "STGP <parameter>, <bank>",
        "Store a user variable (bank 2) in EEPROM", "3.6.11", Both, &[GLOBAL_PARAM, BANK]),
    row("RSGP", opcode::RSGP, "RSGP <parameter>, <bank>",
        "Restore a user variable (bank 2) from EEPROM", "3.6.12", Both,
        &[GLOBAL_PARAM, BANK]),
    row("RFS", opcode::RFS, "RFS START|STOP|STATUS, <motor>",
        "Start, stop or query the reference search", "3.6.13", Both,
        &[req("action", Type, Code(CodeSet::RfsAction)), MOTOR]),
    row("SIO", opcode::SIO, "SIO <port>, <bank>, <value>",
        "Set a digital output (bank 2) or the pull-ups (bank 0)", "3.6.14", Both,
        &[req("port", Type, Byte), BANK, req("value", Value, Number)]),
    row("GIO", opcode::GIO, "GIO <port>, <bank>",
        "Get a digital input (bank 0), analog input (bank 1) or output state (bank 2)",
        "3.6.15", Both, &[req("port", Type, Byte), BANK]),
    row("CALC", opcode::CALC, "CALC <operation>, <operand>",
        "Accumulator := accumulator <operation> operand (ADD..LOAD)", "3.6.16", Standalone,
        &[req("operation", Type, Code(CodeSet::Calc(CalcFamily::Accumulator))),
          req("operand", Value, Number)]),
    row("COMP", opcode::COMP, "COMP <value>",
        "Compare the accumulator with a value (sets the condition flags)", "3.6.17",
        Standalone, &[req("value", Value, Number)]),
    row("JC", opcode::JC, "JC <condition>, <label>", "Jump if the condition holds",
        "3.6.18", Standalone, &[CONDITION, ADDRESS]),
    row("JA", opcode::JA, "JA <label>", "Jump always", "3.6.19", Standalone, &[ADDRESS]),
    row("CSUB", opcode::CSUB, "CSUB <label>", "Call a subroutine", "3.6.20", Standalone,
        &[ADDRESS]),
    row("RSUB", opcode::RSUB, "RSUB", "Return from a subroutine", "3.6.21", Standalone, &[]),
    row("EI", opcode::EI, "EI <interrupt>",
        "Enable an interrupt (255 = all interrupt processing)", "3.6.32", Standalone,
        &[INTERRUPT]),
    row("DI", opcode::DI, "DI <interrupt>",
        "Disable an interrupt (255 = all interrupt processing)", "3.6.33", Standalone,
        &[INTERRUPT]),
    row("WAIT", opcode::WAIT, "WAIT TICKS|POS|REFSW|LIMSW|RFS, <motor>, <ticks>",
        "Wait for an event or a number of 10 ms ticks (timeout 0 = none, -1 = accumulator)",
        "3.6.22", Standalone,
        &[req("condition", Type, Code(CodeSet::WaitCondition)), MOTOR,
          req("ticks", Value, Number)]),
    row("STOP", opcode::STOP, "STOP", "End the TMCL program", "3.6.23", Standalone, &[]),
    row("SCO", opcode::SCO, "SCO <coordinate>, <motor>, <position>",
        "Set a coordinate (motor 255: copy to EEPROM)", "3.6.24", Both,
        &[COORDINATE, MOTOR, req("position", Value, Number)]),
    row("GCO", opcode::GCO, "GCO <coordinate>, <motor>",
        "Get a coordinate (motor 255: copy from EEPROM)", "3.6.25", Both,
        &[COORDINATE, MOTOR, opt("0", Value, Zero, 0)]),
    row("CCO", opcode::CCO, "CCO <coordinate>, <motor>",
        "Capture the actual position into a coordinate", "3.6.26", Both, &[COORDINATE, MOTOR]),
    row("CALCX", opcode::CALCX, "CALCX <operation>",
        "Calculate with the accumulator and the X register (ADD..SWAP)", "3.6.28",
        Standalone, &[req("operation", Type, Code(CodeSet::Calc(CalcFamily::XRegister)))]),
    row("AAP", opcode::AAP, "AAP <parameter>, <motor>",
        "Copy the accumulator to an axis parameter", "3.6.29", Standalone,
        &[AXIS_PARAM, MOTOR]),
    row("AGP", opcode::AGP, "AGP <parameter>, <bank>",
        "Copy the accumulator to a global parameter", "3.6.30", Standalone,
        &[GLOBAL_PARAM, BANK]),
    row("CLE", opcode::CLE, "CLE ALL|ETO|EAL|EDV|EPO|ESD", "Clear error flags", "3.6.31",
        Standalone, &[req("flag", Type, Code(CodeSet::ClearFlag))]),
    row("VECT", opcode::VECT, "VECT <interrupt>, <label>", "Define an interrupt vector",
        "3.6.34", Standalone, &[INTERRUPT, ADDRESS]),
    row("RETI", opcode::RETI, "RETI", "Return from an interrupt handler", "3.6.35",
        Standalone, &[]),
    row("ACO", opcode::ACO, "ACO <coordinate>, <motor>",
        "Copy the accumulator to a coordinate", "3.6.27", Standalone, &[COORDINATE, MOTOR]),
    row("CALCVV", opcode::CALCVV, "CALCVV <operation>, <var1>, <var2>",
        "var1 := var1 <operation> var2 (user variables)", "3.6.36", Standalone,
        &[VAR_OP, req("var1", MotorBank, Byte), req("var2", Value, Byte)]),
    row("CALCVA", opcode::CALCVA, "CALCVA <operation>, <var>",
        "var := var <operation> accumulator", "3.6.37", Standalone, &[VAR_OP, VAR]),
    row("CALCAV", opcode::CALCAV, "CALCAV <operation>, <var>",
        "accumulator := accumulator <operation> var", "3.6.38", Standalone, &[VAR_OP, VAR]),
    row("CALCVX", opcode::CALCVX, "CALCVX <operation>, <var>",
        "var := var <operation> X register", "3.6.39", Standalone, &[VAR_OP, VAR]),
    row("CALCXV", opcode::CALCXV, "CALCXV <operation>, <var>",
        "X register := X register <operation> var", "3.6.40", Standalone, &[VAR_OP, VAR]),
    row("CALCV", opcode::CALCV, "CALCV <operation>, <var>, <value>",
        "var := var <operation> value (no SWAP)", "3.6.41", Standalone,
        &[req("operation", Type, Code(CodeSet::Calc(CalcFamily::DirectValue))), VAR,
          req("value", Value, Number)]),
    row("MVPA", opcode::MVPA, "MVPA ABS|REL|COORD, <motor>",
        "Move to the position (offset, coordinate) in the accumulator", "3.6.45", Standalone,
        &[MOVE_MODE, MOTOR]),
    row("RST", opcode::RST, "RST <label>",
        "Reset the interpreter and restart the program at a label", "3.6.42", Standalone,
        &[ADDRESS]),
    row("DJNZ", opcode::DJNZ, "DJNZ <var>, <label>",
        "Decrement a user variable and jump if it is not zero", "3.6.43", Standalone,
        &[req("var", Type, Byte), ADDRESS]),
    row("ROLA", opcode::ROLA, "ROLA <motor>",
        "Rotate left with the velocity in the accumulator", "3.6.46", Standalone, &[MOTOR]),
    row("RORA", opcode::RORA, "RORA <motor>",
        "Rotate right with the velocity in the accumulator", "3.6.47", Standalone, &[MOTOR]),
    row("SIV", opcode::SIV, "SIV <value>",
        "Set the user variable indexed by the X register", "3.6.48", Standalone,
        &[req("value", Value, Number)]),
    row("GIV", opcode::GIV, "GIV",
        "Get the user variable indexed by the X register", "3.6.49", Standalone, &[]),
    row("AIV", opcode::AIV, "AIV",
        "Copy the accumulator to the user variable indexed by the X register", "3.6.50",
        Standalone, &[]),
    row("UF0", opcode::UF0, "UF0 [<type>, <motor/bank>, <value>]",
        "User function 0 (customer-specific firmware)", "3.6.51", UserDefined, USER_FUNCTION),
    row("UF1", opcode::UF0 + 1, "UF1 [<type>, <motor/bank>, <value>]",
        "User function 1 (customer-specific firmware)", "3.6.51", UserDefined, USER_FUNCTION),
    row("UF2", opcode::UF0 + 2, "UF2 [<type>, <motor/bank>, <value>]",
        "User function 2 (customer-specific firmware)", "3.6.51", UserDefined, USER_FUNCTION),
    row("UF3", opcode::UF0 + 3, "UF3 [<type>, <motor/bank>, <value>]",
        "User function 3 (customer-specific firmware)", "3.6.51", UserDefined, USER_FUNCTION),
    row("UF4", opcode::UF0 + 4, "UF4 [<type>, <motor/bank>, <value>]",
        "User function 4 (customer-specific firmware)", "3.6.51", UserDefined, USER_FUNCTION),
    row("UF5", opcode::UF0 + 5, "UF5 [<type>, <motor/bank>, <value>]",
        "User function 5 (customer-specific firmware)", "3.6.51", UserDefined, USER_FUNCTION),
    row("UF6", opcode::UF0 + 6, "UF6 [<type>, <motor/bank>, <value>]",
        "User function 6 (customer-specific firmware)", "3.6.51", UserDefined, USER_FUNCTION),
    row("UF7", opcode::UF7, "UF7 [<type>, <motor/bank>, <value>]",
        "User function 7 (customer-specific firmware)", "3.6.51", UserDefined, USER_FUNCTION),
    row("CALL", opcode::CALL, "CALL <condition>, <label>",
        "Call a subroutine if the condition holds", "3.6.44", Standalone,
        &[CONDITION, ADDRESS]),
    row("STOPAPP", opcode::STOP_APPLICATION, "STOPAPP",
        "Stop the running TMCL program (control command 128)", "3.6.53", DirectOnly, &[]),
    row("RUNAPP", opcode::RUN_APPLICATION, "RUNAPP [<address>]",
        "Run the TMCL program from the current address, or from <address> (129)",
        "3.6.53", DirectOnly,
        &[Operand {
            name: "address",
            field: Value,
            kind: Label,
            presence: Presence::SetsType(1),
        }]),
    row("STEPAPP", opcode::STEP_APPLICATION, "STEPAPP",
        "Execute only the next program command (130)", "3.6.53", DirectOnly, &[]),
    row("RESETAPP", opcode::RESET_APPLICATION, "RESETAPP",
        "Stop the program and reset PC, stack, accumulator, X and flags (131)", "3.6.53",
        DirectOnly, &[]),
    row("DOWNLOAD", opcode::ENTER_DOWNLOAD, "DOWNLOAD [<address>]",
        "Enter download mode: store the following commands from <address> (default 0) (132)",
        "3.6.53", DirectOnly, &[opt("address", Value, Label, 0)]),
    row("ENDDOWNLOAD", opcode::EXIT_DOWNLOAD, "ENDDOWNLOAD",
        "Leave download mode (133)", "3.6.53", DirectOnly, &[]),
    row("READMEM", opcode::READ_MEMORY, "READMEM <address>",
        "Read one program memory location (134)", "3.6.53", DirectOnly,
        &[req("address", Value, Label)]),
    row("APPSTATUS", opcode::APPLICATION_STATUS, "APPSTATUS [MODE|PC|ACCU|X]",
        "Get the application status, program counter, accumulator or X register (135)",
        "3.6.53", DirectOnly, &[opt("query", Type, Code(CodeSet::StatusQuery), 0)]),
    row("VERSION", opcode::FIRMWARE_VERSION, "VERSION [STRING|BINARY]",
        "Get the firmware version (136)", "3.6.53", DirectOnly,
        &[opt("format", Type, Code(CodeSet::VersionFormat), 0)]),
    CommandInfo {
        fixed_value: super::command::RESET_KEY,
        ..row("FACTORYRESET", opcode::FACTORY_RESET, "FACTORYRESET",
            "Restore the factory settings in EEPROM; the module sends no reply (137, value 1234)",
            "3.6.53", DirectOnly, &[])
    },
    row("TARGETEVENT", opcode::TARGET_REACHED_EVENT, "TARGETEVENT [ONCE|ALWAYS] [<mask>]",
        "Ask for an extra reply when the next (ONCE) or every (ALWAYS, default) MVP \
         reaches its target; mask 1 = motor 0 (138)",
        "3.6.52", DirectOnly,
        &[opt("mode", Type, Code(CodeSet::EventMode), 1),
          opt("mask", Value, Number, 1)]),
    CommandInfo {
        fixed_value: super::command::RESET_KEY,
        ..row("RESET", opcode::SOFTWARE_RESET, "RESET",
            "Restart the module like a power cycle; the reply may be lost (255, value 1234)",
            "3.6.53", DirectOnly, &[])
    },
];

/// The row of a mnemonic or console name, case-insensitively.
pub fn find_command(name: &str) -> Option<&'static CommandInfo> {
    COMMANDS.iter().find(|c| c.name.eq_ignore_ascii_case(name))
}

/// The row of an instruction number.
pub fn command_by_opcode(opcode: u8) -> Option<&'static CommandInfo> {
    COMMANDS.iter().find(|c| c.opcode == opcode)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_opcodes_are_unique() {
        for (i, a) in COMMANDS.iter().enumerate() {
            for b in &COMMANDS[i + 1..] {
                assert_ne!(a.name, b.name);
                assert_ne!(a.opcode, b.opcode, "{} and {}", a.name, b.name);
            }
        }
    }

    #[test]
    fn syntax_starts_with_the_name_and_lists_every_operand() {
        for c in COMMANDS {
            assert!(c.syntax.starts_with(c.name), "{}", c.syntax);
            for op in c.operands {
                let shown = match op.kind {
                    OperandKind::Zero => continue,
                    OperandKind::Code(set) => {
                        let symbols: Vec<_> = set.entries().iter().map(|(k, _)| *k).collect();
                        c.syntax.contains(&symbols.join("|"))
                            || c.syntax.contains(&format!("<{}>", op.name))
                    }
                    _ => c.syntax.contains(&format!("<{}>", op.name)),
                };
                assert!(shown, "{}: {}", c.syntax, op.name);
            }
        }
    }

    #[test]
    fn lookup_is_case_insensitive() {
        assert_eq!(find_command("mvp").map(|c| c.opcode), Some(4));
        assert_eq!(find_command("TargetEvent").map(|c| c.opcode), Some(138));
        assert_eq!(command_by_opcode(80).map(|c| c.name), Some("CALL"));
        assert!(find_command("MVPXA").is_none());
    }

    #[test]
    fn code_sets_describe_their_symbols() {
        assert_eq!(CodeSet::MoveMode.describe(), "ABS (0), REL (1), COORD (2)");
        assert_eq!(
            CodeSet::Calc(CalcFamily::DirectValue).code_of("comp"),
            Some(11)
        );
        assert_eq!(CodeSet::Calc(CalcFamily::DirectValue).code_of("SWAP"), None);
        assert_eq!(CodeSet::Calc(CalcFamily::Accumulator).keyword_of(10), None);
    }
}
