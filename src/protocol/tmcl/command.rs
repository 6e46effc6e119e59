//! Every TMCL command of the TMCM-1110 manual as a typed value (§3.4
//! Table 5, §3.5.7 Table 13, §3.6.x, control commands §3.6.53 Table 14,
//! command 138 §3.6.52), and the conversion to and from a [`Request`].
//!
//! Encoding is total: every [`Command`] becomes a frame. Decoding never
//! fails: a frame that is not exactly the typed form of a command (unknown
//! opcode, a code outside its table, a "don't care" field that is not 0)
//! comes back as [`Command::Raw`], so `to_request(from_request(r)) == r`
//! for every frame.

use super::frame::Request;

/// Instruction numbers (byte 1) of §3.4 Table 5, §3.5.7 Table 13 and
/// §3.6.52/§3.6.53. The per-command "Binary Representation" tables misprint
/// some of them (ROR as 2, CALL as 21, GIV/AIV as 55); these are the numbers
/// the manual's examples use.
pub mod opcode {
    pub const ROR: u8 = 1;
    pub const ROL: u8 = 2;
    pub const MST: u8 = 3;
    pub const MVP: u8 = 4;
    pub const SAP: u8 = 5;
    pub const GAP: u8 = 6;
    pub const STAP: u8 = 7;
    pub const RSAP: u8 = 8;
    pub const SGP: u8 = 9;
    pub const GGP: u8 = 10;
    pub const STGP: u8 = 11;
    pub const RSGP: u8 = 12;
    pub const RFS: u8 = 13;
    pub const SIO: u8 = 14;
    pub const GIO: u8 = 15;
    pub const CALC: u8 = 19;
    pub const COMP: u8 = 20;
    pub const JC: u8 = 21;
    pub const JA: u8 = 22;
    pub const CSUB: u8 = 23;
    pub const RSUB: u8 = 24;
    pub const EI: u8 = 25;
    pub const DI: u8 = 26;
    pub const WAIT: u8 = 27;
    pub const STOP: u8 = 28;
    pub const SCO: u8 = 30;
    pub const GCO: u8 = 31;
    pub const CCO: u8 = 32;
    pub const CALCX: u8 = 33;
    pub const AAP: u8 = 34;
    pub const AGP: u8 = 35;
    pub const CLE: u8 = 36;
    pub const VECT: u8 = 37;
    pub const RETI: u8 = 38;
    pub const ACO: u8 = 39;
    pub const CALCVV: u8 = 40;
    pub const CALCVA: u8 = 41;
    pub const CALCAV: u8 = 42;
    pub const CALCVX: u8 = 43;
    pub const CALCXV: u8 = 44;
    pub const CALCV: u8 = 45;
    pub const MVPA: u8 = 46;
    pub const RST: u8 = 48;
    pub const DJNZ: u8 = 49;
    pub const ROLA: u8 = 50;
    pub const RORA: u8 = 51;
    pub const SIV: u8 = 55;
    pub const GIV: u8 = 56;
    pub const AIV: u8 = 57;
    /// UF0; UF1..UF7 follow (§3.6.51: 64..71).
    pub const UF0: u8 = 64;
    pub const UF7: u8 = 71;
    pub const CALL: u8 = 80;
    pub const STOP_APPLICATION: u8 = 128;
    pub const RUN_APPLICATION: u8 = 129;
    pub const STEP_APPLICATION: u8 = 130;
    pub const RESET_APPLICATION: u8 = 131;
    pub const ENTER_DOWNLOAD: u8 = 132;
    pub const EXIT_DOWNLOAD: u8 = 133;
    pub const READ_MEMORY: u8 = 134;
    pub const APPLICATION_STATUS: u8 = 135;
    pub const FIRMWARE_VERSION: u8 = 136;
    pub const FACTORY_RESET: u8 = 137;
    pub const TARGET_REACHED_EVENT: u8 = 138;
    pub const SOFTWARE_RESET: u8 = 255;
}

/// The value commands 137 and 255 must carry to take effect (§3.6.53
/// Table 14: "set to 1234").
pub const RESET_KEY: i32 = 1234;

/// An operand that the manual writes as a symbol with a fixed number
/// (`ABS`, `ZE`, `TICKS`…). Implemented by every code enum of this module.
pub trait OperandCode: Copy + Sized + 'static {
    /// Every value, in code order.
    const ALL: &'static [Self];
    /// The number that goes into the frame.
    fn code(self) -> u8;
    /// The manual's symbol, upper case.
    fn keyword(self) -> &'static str;

    fn from_code(code: u8) -> Option<Self> {
        Self::ALL.iter().copied().find(|v| v.code() == code)
    }

    /// Case-insensitive lookup of a symbol.
    fn from_keyword(word: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .copied()
            .find(|v| v.keyword().eq_ignore_ascii_case(word))
    }
}

/// Declares a code enum from one table of `Variant = code, "KEYWORD"` rows.
macro_rules! operand_codes {
    (
        $(#[$meta:meta])*
        pub enum $name:ident {
            $( $(#[$vmeta:meta])* $variant:ident = $code:literal, $keyword:literal; )+
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $name {
            $( $(#[$vmeta])* $variant, )+
        }

        impl OperandCode for $name {
            const ALL: &'static [Self] = &[$($name::$variant),+];

            fn code(self) -> u8 {
                match self { $($name::$variant => $code,)+ }
            }

            fn keyword(self) -> &'static str {
                match self { $($name::$variant => $keyword,)+ }
            }
        }
    };
}

operand_codes! {
    /// Type of MVP and MVPA (§3.6.4, §3.6.45).
    pub enum MoveMode {
        /// Absolute target position.
        Abs = 0, "ABS";
        /// Offset to the actual position.
        Rel = 1, "REL";
        /// A stored coordinate (SCO/CCO/ACO).
        Coord = 2, "COORD";
    }
}

operand_codes! {
    /// Type of RFS (§3.6.13).
    pub enum RfsAction {
        Start = 0, "START";
        Stop = 1, "STOP";
        /// Reply value 0 = no search active.
        Status = 2, "STATUS";
    }
}

operand_codes! {
    /// Arithmetic operation of the CALC family (§3.6.16, §3.6.28,
    /// §3.6.36–3.6.41). Which operations a command accepts depends on the
    /// command: see [`CalcFamily`].
    pub enum CalcOp {
        Add = 0, "ADD";
        Sub = 1, "SUB";
        Mul = 2, "MUL";
        Div = 3, "DIV";
        Mod = 4, "MOD";
        And = 5, "AND";
        Or = 6, "OR";
        Xor = 7, "XOR";
        Not = 8, "NOT";
        Load = 9, "LOAD";
        /// CALCX and CALCVV/VA/AV/VX/XV only.
        Swap = 10, "SWAP";
        /// CALCVV/VA/AV/VX/XV and CALCV only.
        Comp = 11, "COMP";
    }
}

operand_codes! {
    /// Jump/call condition of JC and CALL (§3.6.18, §3.6.44).
    pub enum Condition {
        /// Zero.
        Ze = 0, "ZE";
        /// Not zero.
        Nz = 1, "NZ";
        Eq = 2, "EQ";
        Ne = 3, "NE";
        Gt = 4, "GT";
        Ge = 5, "GE";
        Lt = 6, "LT";
        Le = 7, "LE";
        /// Timeout error flag.
        Eto = 8, "ETO";
        /// External alarm flag.
        Eal = 9, "EAL";
        /// Deviation error flag.
        Edv = 10, "EDV";
        /// Position error flag.
        Epo = 11, "EPO";
    }
}

operand_codes! {
    /// Event a WAIT waits for (§3.6.22).
    pub enum WaitCondition {
        /// Timer ticks of 10 ms.
        Ticks = 0, "TICKS";
        /// Target position reached.
        Pos = 1, "POS";
        /// Reference switch triggered.
        RefSw = 2, "REFSW";
        /// A limit switch triggered.
        LimSw = 3, "LIMSW";
        /// Reference search completed.
        Rfs = 4, "RFS";
    }
}

operand_codes! {
    /// Error flag cleared by CLE (§3.6.31; ESD only appears in the binary
    /// table).
    pub enum ClearFlag {
        All = 0, "ALL";
        Eto = 1, "ETO";
        Eal = 2, "EAL";
        Edv = 3, "EDV";
        Epo = 4, "EPO";
        Esd = 5, "ESD";
    }
}

operand_codes! {
    /// What command 135 "get application status" returns (§3.6.53).
    pub enum StatusQuery {
        /// Mode, wait flag, memory pointer.
        Mode = 0, "MODE";
        /// Mode, wait flag, program counter.
        ProgramCounter = 1, "PC";
        Accumulator = 2, "ACCU";
        XRegister = 3, "X";
    }
}

operand_codes! {
    /// Reply format of command 136 "get firmware version" (§3.6.53).
    pub enum VersionFormat {
        /// Special 9-byte string reply.
        String = 0, "STRING";
        Binary = 1, "BINARY";
    }
}

operand_codes! {
    /// Type of command 138 (§3.6.52): for which MVP commands the module
    /// sends the extra "target position reached" reply.
    pub enum EventMode {
        /// Only the next MVP.
        Once = 0, "ONCE";
        /// Every following MVP (the manual's recommendation).
        Always = 1, "ALWAYS";
    }
}

/// The CALC-like commands differ in which operations they accept.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CalcFamily {
    /// CALC (§3.6.16): ADD..LOAD (0..9).
    Accumulator,
    /// CALCX (§3.6.28): ADD..SWAP (0..10).
    XRegister,
    /// CALCVV, CALCVA, CALCAV, CALCVX, CALCXV (§3.6.36–3.6.40): all (0..11).
    UserVariable,
    /// CALCV (§3.6.41): ADD..LOAD and COMP (0..9, 11); no SWAP.
    DirectValue,
}

use CalcOp::{Add, And, Comp, Div, Load, Mod, Mul, Not, Or, Sub, Swap, Xor};

const ARITHMETIC_OPS: &[CalcOp] = &[Add, Sub, Mul, Div, Mod, And, Or, Xor, Not, Load];
const CALCX_OPS: &[CalcOp] = &[Add, Sub, Mul, Div, Mod, And, Or, Xor, Not, Load, Swap];
const CALCV_OPS: &[CalcOp] = &[Add, Sub, Mul, Div, Mod, And, Or, Xor, Not, Load, Comp];

impl CalcFamily {
    /// The operations this family's binary table lists.
    pub fn ops(self) -> &'static [CalcOp] {
        match self {
            CalcFamily::Accumulator => ARITHMETIC_OPS,
            CalcFamily::XRegister => CALCX_OPS,
            CalcFamily::UserVariable => CalcOp::ALL,
            CalcFamily::DirectValue => CALCV_OPS,
        }
    }

    pub fn allows(self, op: CalcOp) -> bool {
        self.ops().contains(&op)
    }

    /// The operation with type code `code`, if this family has it.
    pub fn op(self, code: u8) -> Option<CalcOp> {
        self.ops().iter().copied().find(|op| op.code() == code)
    }
}

/// One interrupt source of §3.5.6.1 Table 12.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InterruptInfo {
    pub number: u8,
    pub source: &'static str,
}

/// EI 255 / DI 255 switch interrupt processing as a whole (§3.6.32).
pub const GLOBAL_INTERRUPT: u8 = 255;

/// The interrupt vectors of the TMCM-1110 (§3.5.6.1 Table 12).
pub const INTERRUPTS: &[InterruptInfo] = &[
    InterruptInfo {
        number: 0,
        source: "Timer 0",
    },
    InterruptInfo {
        number: 1,
        source: "Timer 1",
    },
    InterruptInfo {
        number: 2,
        source: "Timer 2",
    },
    InterruptInfo {
        number: 3,
        source: "Target position reached 0",
    },
    InterruptInfo {
        number: 15,
        source: "StallGuard axis 0",
    },
    InterruptInfo {
        number: 21,
        source: "Deviation axis 0",
    },
    InterruptInfo {
        number: 27,
        source: "Left stop switch 0",
    },
    InterruptInfo {
        number: 28,
        source: "Right stop switch 0",
    },
    InterruptInfo {
        number: 39,
        source: "Input change 0",
    },
    InterruptInfo {
        number: 40,
        source: "Input change 1",
    },
    InterruptInfo {
        number: 41,
        source: "Input change 2",
    },
    InterruptInfo {
        number: 42,
        source: "Input change 3",
    },
    InterruptInfo {
        number: 43,
        source: "Input change 4",
    },
    InterruptInfo {
        number: 44,
        source: "Input change 5",
    },
    InterruptInfo {
        number: GLOBAL_INTERRUPT,
        source: "Global interrupts",
    },
];

/// A TMCL command. Field names follow the manual's operand names; fields
/// the manual calls "don't care" are not stored and are sent as 0.
///
/// Program addresses (jump targets, labels) are the raw 32-bit value field;
/// the manual gives no program memory size, so only [`super::validate`]
/// narrows them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Command {
    /// ROR (1, §3.6.1): rotate right (position counter increases).
    Ror { motor: u8, velocity: i32 },
    /// ROL (2, §3.6.2): rotate left.
    Rol { motor: u8, velocity: i32 },
    /// MST (3, §3.6.3): soft stop.
    Mst { motor: u8 },
    /// MVP (4, §3.6.4): position, offset or coordinate number.
    Mvp {
        mode: MoveMode,
        motor: u8,
        target: i32,
    },
    /// SAP (5, §3.6.5).
    Sap { param: u8, motor: u8, value: i32 },
    /// GAP (6, §3.6.6).
    Gap { param: u8, motor: u8 },
    /// STAP (7, §3.6.7).
    Stap { param: u8, motor: u8 },
    /// RSAP (8, §3.6.8).
    Rsap { param: u8, motor: u8 },
    /// SGP (9, §3.6.9).
    Sgp { param: u8, bank: u8, value: i32 },
    /// GGP (10, §3.6.10).
    Ggp { param: u8, bank: u8 },
    /// STGP (11, §3.6.11).
    Stgp { param: u8, bank: u8 },
    /// RSGP (12, §3.6.12).
    Rsgp { param: u8, bank: u8 },
    /// RFS (13, §3.6.13).
    Rfs { action: RfsAction, motor: u8 },
    /// SIO (14, §3.6.14).
    Sio { port: u8, bank: u8, value: i32 },
    /// GIO (15, §3.6.15).
    Gio { port: u8, bank: u8 },
    /// CALC (19, §3.6.16): accumulator op operand.
    Calc { op: CalcOp, operand: i32 },
    /// COMP (20, §3.6.17).
    Comp { value: i32 },
    /// JC (21, §3.6.18).
    Jc { condition: Condition, address: i32 },
    /// JA (22, §3.6.19).
    Ja { address: i32 },
    /// CSUB (23, §3.6.20).
    Csub { address: i32 },
    /// RSUB (24, §3.6.21).
    Rsub,
    /// EI (25, §3.6.32).
    Ei { interrupt: u8 },
    /// DI (26, §3.6.33).
    Di { interrupt: u8 },
    /// WAIT (27, §3.6.22): ticks of 10 ms, or a timeout (0 = none); −1 takes
    /// the value from the accumulator.
    Wait {
        condition: WaitCondition,
        motor: u8,
        ticks: i32,
    },
    /// STOP (28, §3.6.23).
    Stop,
    /// SCO (30, §3.6.24); motor 255 is the EEPROM copy form.
    Sco {
        coordinate: u8,
        motor: u8,
        position: i32,
    },
    /// GCO (31, §3.6.25); motor 255 is the EEPROM copy form.
    Gco { coordinate: u8, motor: u8 },
    /// CCO (32, §3.6.26).
    Cco { coordinate: u8, motor: u8 },
    /// CALCX (33, §3.6.28).
    Calcx { op: CalcOp },
    /// AAP (34, §3.6.29).
    Aap { param: u8, motor: u8 },
    /// AGP (35, §3.6.30).
    Agp { param: u8, bank: u8 },
    /// CLE (36, §3.6.31).
    Cle { flag: ClearFlag },
    /// VECT (37, §3.6.34).
    Vect { interrupt: u8, address: i32 },
    /// RETI (38, §3.6.35).
    Reti,
    /// ACO (39, §3.6.27).
    Aco { coordinate: u8, motor: u8 },
    /// CALCVV (40, §3.6.36): var1 in the motor/bank byte, var2 in the value.
    Calcvv { op: CalcOp, var1: u8, var2: u8 },
    /// CALCVA (41, §3.6.37): variable in the motor/bank byte.
    Calcva { op: CalcOp, var: u8 },
    /// CALCAV (42, §3.6.38).
    Calcav { op: CalcOp, var: u8 },
    /// CALCVX (43, §3.6.39).
    Calcvx { op: CalcOp, var: u8 },
    /// CALCXV (44, §3.6.40).
    Calcxv { op: CalcOp, var: u8 },
    /// CALCV (45, §3.6.41).
    Calcv { op: CalcOp, var: u8, value: i32 },
    /// MVPA (46, §3.6.45).
    Mvpa { mode: MoveMode, motor: u8 },
    /// RST (48, §3.6.42).
    Rst { address: i32 },
    /// DJNZ (49, §3.6.43): user variable in the type byte.
    Djnz { var: u8, address: i32 },
    /// ROLA (50, §3.6.46).
    Rola { motor: u8 },
    /// RORA (51, §3.6.47).
    Rora { motor: u8 },
    /// SIV (55, §3.6.48).
    Siv { value: i32 },
    /// GIV (56, §3.6.49).
    Giv,
    /// AIV (57, §3.6.50).
    Aiv,
    /// UF0..UF7 (64..71, §3.6.51): customer-specific, every field user
    /// defined. `number` is 0..=7; higher bits are ignored when encoding.
    UserFunction {
        number: u8,
        kind: u8,
        motor_bank: u8,
        value: i32,
    },
    /// CALL (80, §3.6.44).
    Call { condition: Condition, address: i32 },
    /// 128: stop a running program (§3.6.53).
    StopApplication,
    /// 129: run the program, from the current address (`None`, type 0) or
    /// from `start` (type 1).
    RunApplication { start: Option<i32> },
    /// 130: execute the next program command only.
    StepApplication,
    /// 131: stop and reset the program (PC, stack, A, X, flags).
    ResetApplication,
    /// 132: store the following commands from `address` on.
    EnterDownload { address: i32 },
    /// 133: leave download mode.
    ExitDownload,
    /// 134: read one program memory location.
    ReadMemory { address: i32 },
    /// 135: application status.
    ApplicationStatus { query: StatusQuery },
    /// 136: firmware version.
    FirmwareVersion { format: VersionFormat },
    /// 137: restore factory settings (value 1234; the module sends no reply).
    FactoryReset,
    /// 138 (§3.6.52): request the extra "target position reached" reply.
    TargetReachedEvent { mode: EventMode, motor_mask: i32 },
    /// 255: software reset (value 1234; the reply may be lost).
    SoftwareReset,
    /// Any other frame, sent as given.
    Raw {
        command: u8,
        kind: u8,
        motor_bank: u8,
        value: i32,
    },
}

impl Command {
    /// The frame fields (instruction, type, motor/bank, value).
    pub fn fields(&self) -> (u8, u8, u8, i32) {
        use Command::*;
        use opcode as op;
        match *self {
            Ror { motor, velocity } => (op::ROR, 0, motor, velocity),
            Rol { motor, velocity } => (op::ROL, 0, motor, velocity),
            Mst { motor } => (op::MST, 0, motor, 0),
            Mvp {
                mode,
                motor,
                target,
            } => (op::MVP, mode.code(), motor, target),
            Sap {
                param,
                motor,
                value,
            } => (op::SAP, param, motor, value),
            Gap { param, motor } => (op::GAP, param, motor, 0),
            Stap { param, motor } => (op::STAP, param, motor, 0),
            Rsap { param, motor } => (op::RSAP, param, motor, 0),
            Sgp { param, bank, value } => (op::SGP, param, bank, value),
            Ggp { param, bank } => (op::GGP, param, bank, 0),
            Stgp { param, bank } => (op::STGP, param, bank, 0),
            Rsgp { param, bank } => (op::RSGP, param, bank, 0),
            Rfs { action, motor } => (op::RFS, action.code(), motor, 0),
            Sio { port, bank, value } => (op::SIO, port, bank, value),
            Gio { port, bank } => (op::GIO, port, bank, 0),
            Calc { op: o, operand } => (op::CALC, o.code(), 0, operand),
            Comp { value } => (op::COMP, 0, 0, value),
            Jc { condition, address } => (op::JC, condition.code(), 0, address),
            Ja { address } => (op::JA, 0, 0, address),
            Csub { address } => (op::CSUB, 0, 0, address),
            Rsub => (op::RSUB, 0, 0, 0),
            Ei { interrupt } => (op::EI, interrupt, 0, 0),
            Di { interrupt } => (op::DI, interrupt, 0, 0),
            Wait {
                condition,
                motor,
                ticks,
            } => (op::WAIT, condition.code(), motor, ticks),
            Stop => (op::STOP, 0, 0, 0),
            Sco {
                coordinate,
                motor,
                position,
            } => (op::SCO, coordinate, motor, position),
            Gco { coordinate, motor } => (op::GCO, coordinate, motor, 0),
            Cco { coordinate, motor } => (op::CCO, coordinate, motor, 0),
            Calcx { op: o } => (op::CALCX, o.code(), 0, 0),
            Aap { param, motor } => (op::AAP, param, motor, 0),
            Agp { param, bank } => (op::AGP, param, bank, 0),
            Cle { flag } => (op::CLE, flag.code(), 0, 0),
            Vect { interrupt, address } => (op::VECT, interrupt, 0, address),
            Reti => (op::RETI, 0, 0, 0),
            Aco { coordinate, motor } => (op::ACO, coordinate, motor, 0),
            Calcvv { op: o, var1, var2 } => (op::CALCVV, o.code(), var1, i32::from(var2)),
            Calcva { op: o, var } => (op::CALCVA, o.code(), var, 0),
            Calcav { op: o, var } => (op::CALCAV, o.code(), var, 0),
            Calcvx { op: o, var } => (op::CALCVX, o.code(), var, 0),
            Calcxv { op: o, var } => (op::CALCXV, o.code(), var, 0),
            Calcv { op: o, var, value } => (op::CALCV, o.code(), var, value),
            Mvpa { mode, motor } => (op::MVPA, mode.code(), motor, 0),
            Rst { address } => (op::RST, 0, 0, address),
            Djnz { var, address } => (op::DJNZ, var, 0, address),
            Rola { motor } => (op::ROLA, 0, motor, 0),
            Rora { motor } => (op::RORA, 0, motor, 0),
            Siv { value } => (op::SIV, 0, 0, value),
            Giv => (op::GIV, 0, 0, 0),
            Aiv => (op::AIV, 0, 0, 0),
            UserFunction {
                number,
                kind,
                motor_bank,
                value,
            } => (op::UF0 + (number & 7), kind, motor_bank, value),
            Call { condition, address } => (op::CALL, condition.code(), 0, address),
            StopApplication => (op::STOP_APPLICATION, 0, 0, 0),
            RunApplication { start: None } => (op::RUN_APPLICATION, 0, 0, 0),
            RunApplication { start: Some(a) } => (op::RUN_APPLICATION, 1, 0, a),
            StepApplication => (op::STEP_APPLICATION, 0, 0, 0),
            ResetApplication => (op::RESET_APPLICATION, 0, 0, 0),
            EnterDownload { address } => (op::ENTER_DOWNLOAD, 0, 0, address),
            ExitDownload => (op::EXIT_DOWNLOAD, 0, 0, 0),
            ReadMemory { address } => (op::READ_MEMORY, 0, 0, address),
            ApplicationStatus { query } => (op::APPLICATION_STATUS, query.code(), 0, 0),
            FirmwareVersion { format } => (op::FIRMWARE_VERSION, format.code(), 0, 0),
            FactoryReset => (op::FACTORY_RESET, 0, 0, RESET_KEY),
            TargetReachedEvent { mode, motor_mask } => {
                (op::TARGET_REACHED_EVENT, mode.code(), 0, motor_mask)
            }
            SoftwareReset => (op::SOFTWARE_RESET, 0, 0, RESET_KEY),
            Raw {
                command,
                kind,
                motor_bank,
                value,
            } => (command, kind, motor_bank, value),
        }
    }

    /// The instruction number this command is sent with.
    pub fn opcode(&self) -> u8 {
        self.fields().0
    }

    /// The frame for the module at `address`.
    pub fn to_request(&self, address: u8) -> Request {
        let (command, kind, motor_bank, value) = self.fields();
        Request {
            address,
            command,
            kind,
            motor_bank,
            value,
        }
    }

    /// The typed command a frame carries, or [`Command::Raw`] when the frame
    /// is not exactly a typed form. Never fails; the address is ignored.
    pub fn from_request(request: &Request) -> Command {
        let Request {
            command,
            kind,
            motor_bank,
            value,
            ..
        } = *request;
        decode(command, kind, motor_bank, value).unwrap_or(Command::Raw {
            command,
            kind,
            motor_bank,
            value,
        })
    }

    /// True for [`Command::Raw`].
    pub fn is_raw(&self) -> bool {
        matches!(self, Command::Raw { .. })
    }
}

/// The typed form of a frame, if it has one. "Don't care" fields must be 0:
/// otherwise re-encoding the typed form would change the frame.
fn decode(command: u8, t: u8, m: u8, v: i32) -> Option<Command> {
    use Command::*;
    use opcode as op;
    // Which of type, motor/bank and value must be zero for a typed form.
    let zero = |type_zero: bool, motor_zero: bool, value_zero: bool| {
        (!type_zero || t == 0) && (!motor_zero || m == 0) && (!value_zero || v == 0)
    };
    let calc = |family: CalcFamily| family.op(t);
    let cmd = match command {
        op::ROR if zero(true, false, false) => Ror {
            motor: m,
            velocity: v,
        },
        op::ROL if zero(true, false, false) => Rol {
            motor: m,
            velocity: v,
        },
        op::MST if zero(true, false, true) => Mst { motor: m },
        op::MVP => Mvp {
            mode: MoveMode::from_code(t)?,
            motor: m,
            target: v,
        },
        op::SAP => Sap {
            param: t,
            motor: m,
            value: v,
        },
        op::GAP if zero(false, false, true) => Gap { param: t, motor: m },
        op::STAP if zero(false, false, true) => Stap { param: t, motor: m },
        op::RSAP if zero(false, false, true) => Rsap { param: t, motor: m },
        op::SGP => Sgp {
            param: t,
            bank: m,
            value: v,
        },
        op::GGP if zero(false, false, true) => Ggp { param: t, bank: m },
        op::STGP if zero(false, false, true) => Stgp { param: t, bank: m },
        op::RSGP if zero(false, false, true) => Rsgp { param: t, bank: m },
        op::RFS if zero(false, false, true) => Rfs {
            action: RfsAction::from_code(t)?,
            motor: m,
        },
        op::SIO => Sio {
            port: t,
            bank: m,
            value: v,
        },
        op::GIO if zero(false, false, true) => Gio { port: t, bank: m },
        op::CALC if zero(false, true, false) => Calc {
            op: calc(CalcFamily::Accumulator)?,
            operand: v,
        },
        op::COMP if zero(true, true, false) => Comp { value: v },
        op::JC if zero(false, true, false) => Jc {
            condition: Condition::from_code(t)?,
            address: v,
        },
        op::JA if zero(true, true, false) => Ja { address: v },
        op::CSUB if zero(true, true, false) => Csub { address: v },
        op::RSUB if zero(true, true, true) => Rsub,
        op::EI if zero(false, true, true) => Ei { interrupt: t },
        op::DI if zero(false, true, true) => Di { interrupt: t },
        op::WAIT => Wait {
            condition: WaitCondition::from_code(t)?,
            motor: m,
            ticks: v,
        },
        op::STOP if zero(true, true, true) => Stop,
        op::SCO => Sco {
            coordinate: t,
            motor: m,
            position: v,
        },
        op::GCO if zero(false, false, true) => Gco {
            coordinate: t,
            motor: m,
        },
        op::CCO if zero(false, false, true) => Cco {
            coordinate: t,
            motor: m,
        },
        op::CALCX if zero(false, true, true) => Calcx {
            op: calc(CalcFamily::XRegister)?,
        },
        op::AAP if zero(false, false, true) => Aap { param: t, motor: m },
        op::AGP if zero(false, false, true) => Agp { param: t, bank: m },
        op::CLE if zero(false, true, true) => Cle {
            flag: ClearFlag::from_code(t)?,
        },
        op::VECT if zero(false, true, false) => Vect {
            interrupt: t,
            address: v,
        },
        op::RETI if zero(true, true, true) => Reti,
        op::ACO if zero(false, false, true) => Aco {
            coordinate: t,
            motor: m,
        },
        op::CALCVV => Calcvv {
            op: calc(CalcFamily::UserVariable)?,
            var1: m,
            var2: u8::try_from(v).ok()?,
        },
        op::CALCVA if zero(false, false, true) => Calcva {
            op: calc(CalcFamily::UserVariable)?,
            var: m,
        },
        op::CALCAV if zero(false, false, true) => Calcav {
            op: calc(CalcFamily::UserVariable)?,
            var: m,
        },
        op::CALCVX if zero(false, false, true) => Calcvx {
            op: calc(CalcFamily::UserVariable)?,
            var: m,
        },
        op::CALCXV if zero(false, false, true) => Calcxv {
            op: calc(CalcFamily::UserVariable)?,
            var: m,
        },
        op::CALCV => Calcv {
            op: calc(CalcFamily::DirectValue)?,
            var: m,
            value: v,
        },
        op::MVPA if zero(false, false, true) => Mvpa {
            mode: MoveMode::from_code(t)?,
            motor: m,
        },
        op::RST if zero(true, true, false) => Rst { address: v },
        op::DJNZ if zero(false, true, false) => Djnz { var: t, address: v },
        op::ROLA if zero(true, false, true) => Rola { motor: m },
        op::RORA if zero(true, false, true) => Rora { motor: m },
        op::SIV if zero(true, true, false) => Siv { value: v },
        op::GIV if zero(true, true, true) => Giv,
        op::AIV if zero(true, true, true) => Aiv,
        op::UF0..=op::UF7 => UserFunction {
            number: command - op::UF0,
            kind: t,
            motor_bank: m,
            value: v,
        },
        op::CALL if zero(false, true, false) => Call {
            condition: Condition::from_code(t)?,
            address: v,
        },
        op::STOP_APPLICATION if zero(true, true, true) => StopApplication,
        op::RUN_APPLICATION if zero(false, true, false) => match t {
            0 if v == 0 => RunApplication { start: None },
            1 => RunApplication { start: Some(v) },
            _ => return None,
        },
        op::STEP_APPLICATION if zero(true, true, true) => StepApplication,
        op::RESET_APPLICATION if zero(true, true, true) => ResetApplication,
        op::ENTER_DOWNLOAD if zero(true, true, false) => EnterDownload { address: v },
        op::EXIT_DOWNLOAD if zero(true, true, true) => ExitDownload,
        op::READ_MEMORY if zero(true, true, false) => ReadMemory { address: v },
        op::APPLICATION_STATUS if zero(false, true, true) => ApplicationStatus {
            query: StatusQuery::from_code(t)?,
        },
        op::FIRMWARE_VERSION if zero(false, true, true) => FirmwareVersion {
            format: VersionFormat::from_code(t)?,
        },
        op::FACTORY_RESET if zero(true, true, false) && v == RESET_KEY => FactoryReset,
        op::TARGET_REACHED_EVENT if zero(false, true, false) => TargetReachedEvent {
            mode: EventMode::from_code(t)?,
            motor_mask: v,
        },
        op::SOFTWARE_RESET if zero(true, true, false) && v == RESET_KEY => SoftwareReset,
        _ => return None,
    };
    Some(cmd)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn req(command: u8, kind: u8, motor_bank: u8, value: i32) -> Request {
        Request {
            address: 1,
            command,
            kind,
            motor_bank,
            value,
        }
    }

    #[test]
    fn ror_example_of_3_6_1_encodes_motor_and_velocity() {
        let frame = Command::Ror {
            motor: 0,
            velocity: 1000,
        }
        .to_request(1)
        .to_bytes();
        assert_eq!(
            frame,
            [0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x03, 0xE8, 0xED]
        );
    }

    #[test]
    fn calcvv_puts_var1_in_motor_byte_and_var2_in_value() {
        let r = Command::Calcvv {
            op: CalcOp::Sub,
            var1: 65,
            var2: 42,
        }
        .to_request(1);
        assert_eq!((r.kind, r.motor_bank, r.value), (1, 65, 42));
    }

    #[test]
    fn dont_care_fields_that_are_not_zero_decode_as_raw() {
        // JA with a type byte: not the typed form, so it must stay raw to
        // re-encode to the same bytes.
        let r = req(opcode::JA, 5, 0, 10);
        assert!(Command::from_request(&r).is_raw());
        assert_eq!(Command::from_request(&r).to_request(1), r);
        assert_eq!(
            Command::from_request(&req(opcode::JA, 0, 0, 10)),
            Command::Ja { address: 10 }
        );
    }

    #[test]
    fn calc_families_accept_only_their_operations() {
        // CALC has no SWAP (10); CALCX has SWAP but no COMP (11); CALCV has
        // COMP but no SWAP; the variable family has all twelve.
        assert!(Command::from_request(&req(opcode::CALC, 10, 0, 0)).is_raw());
        assert_eq!(
            Command::from_request(&req(opcode::CALCX, 10, 0, 0)),
            Command::Calcx { op: CalcOp::Swap }
        );
        assert!(Command::from_request(&req(opcode::CALCX, 11, 0, 0)).is_raw());
        assert!(Command::from_request(&req(opcode::CALCV, 10, 3, 0)).is_raw());
        assert_eq!(
            Command::from_request(&req(opcode::CALCV, 11, 3, 7)),
            Command::Calcv {
                op: CalcOp::Comp,
                var: 3,
                value: 7
            }
        );
        assert_eq!(
            Command::from_request(&req(opcode::CALCVA, 10, 3, 0)),
            Command::Calcva {
                op: CalcOp::Swap,
                var: 3
            }
        );
    }

    #[test]
    fn calcvv_var2_outside_a_byte_is_raw() {
        assert!(Command::from_request(&req(opcode::CALCVV, 0, 1, 256)).is_raw());
        assert!(Command::from_request(&req(opcode::CALCVV, 0, 1, -1)).is_raw());
    }

    #[test]
    fn reset_commands_need_the_key() {
        assert_eq!(
            Command::from_request(&req(255, 0, 0, 1234)),
            Command::SoftwareReset
        );
        assert!(Command::from_request(&req(255, 0, 0, 1)).is_raw());
        assert_eq!(
            Command::from_request(&req(137, 0, 0, 1234)),
            Command::FactoryReset
        );
        assert_eq!(Command::FactoryReset.to_request(1).value, 1234);
    }

    #[test]
    fn run_application_type_selects_start_address() {
        assert_eq!(
            Command::from_request(&req(129, 0, 0, 0)),
            Command::RunApplication { start: None }
        );
        assert_eq!(
            Command::from_request(&req(129, 1, 0, 2)),
            Command::RunApplication { start: Some(2) }
        );
        assert!(Command::from_request(&req(129, 0, 0, 2)).is_raw());
        assert!(Command::from_request(&req(129, 2, 0, 0)).is_raw());
    }

    #[test]
    fn user_functions_cover_64_to_71() {
        let c = Command::from_request(&req(71, 1, 2, 3));
        assert_eq!(
            c,
            Command::UserFunction {
                number: 7,
                kind: 1,
                motor_bank: 2,
                value: 3
            }
        );
        assert!(Command::from_request(&req(72, 0, 0, 0)).is_raw());
    }

    #[test]
    fn unassigned_opcodes_are_raw() {
        for code in [
            0u8, 16, 17, 18, 29, 47, 52, 53, 54, 58, 63, 72, 79, 81, 127, 139, 254,
        ] {
            assert!(
                Command::from_request(&req(code, 0, 0, 0)).is_raw(),
                "{code}"
            );
        }
    }

    #[test]
    fn code_enums_look_up_keywords_case_insensitively() {
        assert_eq!(MoveMode::from_keyword("rel"), Some(MoveMode::Rel));
        assert_eq!(
            WaitCondition::from_keyword("RefSw"),
            Some(WaitCondition::RefSw)
        );
        assert_eq!(Condition::from_code(11), Some(Condition::Epo));
        assert_eq!(Condition::from_code(12), None);
        assert_eq!(ClearFlag::Esd.code(), 5);
    }
}
