//! Executing one direct-mode command (manual §3.6) and the answer it gets;
//! the program's commands go through the same code (`perform`) with the
//! program's registers.
//!
//! Decisions where the manual is silent:
//! - Validation order: opcode (2), type code (3), motor/bank (4: motor ≠ 0,
//!   bank not 0/2/3), parameter/port/coordinate number (3), access (read-only
//!   write: [`super::ReadOnlyWrite`]; STAP/RSAP/STGP/RSGP on a parameter
//!   without E: 3), value range from the parameter tables (4). Fields the
//!   manual marks "don't care" are not checked.
//! - "Don't care" reply values are 0. Values the manual documents: GAP, GGP,
//!   GIO, GCO, CCO (the captured position), RFS STATUS (1 while searching),
//!   CALC and CALCV (the operand, §3.6.16/§3.6.41 examples), 138 (mask 1).
//! - Program-flow commands (JA, JC, COMP, CSUB, RSUB, WAIT, STOP, RST, DJNZ,
//!   CALL) have no direct-mode meaning (§3.5.3 Table 8) and answer 6
//!   "command not available" without doing anything, so they cannot disturb
//!   a program's flags (§8.6).
//! - Direct mode has its own calculation registers (A, X, condition
//!   flags): CALC, CALCX, CALCV*, AAP, AGP, ACO, SIV, GIV, AIV, MVPA, ROLA,
//!   RORA and `SIO 255, 2, -1` sent by the host use the host's set, never
//!   the program's. §8.6 says direct-mode commands "do not disturb the flow
//!   of the program", and §3.5.5 already keeps direct-mode reads away from
//!   the accumulator; a host CALC rewriting the A of a running program would
//!   disturb it. 135 types 2/3 report the program's A and X (the IDE's
//!   debugger reads them). GIV in direct mode answers var[X] and loads
//!   nothing, like every direct-mode read (§3.5.5). The interrupt set-up
//!   (EI, DI, VECT) and the error flags (CLE) are module state shared with
//!   the program; RETI in direct mode does nothing.
//! - Command 138: an MVP or MVPA counts, the host's or the program's; SAP 0 does not start a reported move
//!   but retargets one under way. ROR, ROL, MST, ROLA, RORA, RFS START, the
//!   heartbeat stop, SAP 138 (leaving position mode) and a limit/stall/
//!   deviation stop abandon the move: no status-128 message for it. Type 0
//!   is used up by the next MVP even if that move is abandoned. An MVP to
//!   where the motor already is gets its message at the next `advance`.
//! - Download mode: control commands (128–137), 138 and 255 are executed;
//!   every other known opcode is stored unchecked at the memory pointer,
//!   answered with status 101 and value = the address it went to; unknown
//!   opcodes answer 2; beyond the 2048-command memory, 4. The reply is
//!   the same when an injected `corrupt-store` fault stored it wrong.
//! - GP81 code protection: 1/3 make 134 answer 6 "command not available";
//!   2/3 make 132 answer 5 "configuration EEPROM locked". Changing GP81 from
//!   1/3 to 0/2 erases the program first (§5.1).
//! - 134 reply (special, 9 bytes): host address, then the stored command's 7
//!   bytes (opcode, type, motor/bank, value MSB first), then the checksum of
//!   the first 8 bytes. It takes the place of a normal reply's module address,
//!   status, command and value bytes.
//! - 135 types 0/1: value byte 3 = application status (GP128 coding), byte 2
//!   = wait flag (1 while a WAIT holds the program), bytes 1..0 = memory
//!   pointer (type 0) or program counter (type 1). Types 2/3: A, X.
//! - 132 stops a running program; the download starts at the given address.
//!   128/129/130/131 drive the interpreter (`interpreter.rs`): 129 type 1
//!   also empties the subroutine stack; 131 also forgets the interrupt
//!   set-up (`program.rs`).
//! - 137 (value 1234) restores the factory EEPROM, program included, keeps
//!   nothing of the old settings, reboots, and sends nothing. 255 (1234)
//!   sends its reply, then reboots. Other values: 4.

use crate::protocol::tmcl::command::{CalcOp, ClearFlag, OperandCode, RESET_KEY, opcode as op};
use crate::protocol::tmcl::params::{self, ParamInfo};
use crate::protocol::tmcl::units::MAX_INTERNAL;
use crate::protocol::tmcl::validate::{
    COORDINATE_EEPROM, COORDINATES, GIO_PORTS, IoPortMiss, IoPorts, SIO_PORTS, find_io_port,
};
use crate::protocol::tmcl::{FRAME_LEN, Request, Status, checksum};

use super::commands::{self, Mode};
use super::eeprom::{EepromImage, STORED_USER_VARIABLES};
use super::io::MODE_MASK;
use super::motion::Axis;
use super::program::{ApplicationStatus, PROGRAM_MEMORY_SIZE, ProgramWord, Registers, calculate};
use super::{
    Answer, FIRMWARE_VERSION_NUMBER, FIRMWARE_VERSION_STRING, GP_CODE_PROTECTION,
    GP_COORDINATE_STORAGE, GP_END_SWITCH_POLARITY, GP_IO_MODE, MOTOR_MASK, TargetReachedRequest,
    Tmcm1110,
};

/// GP128..GP133, GP255: bank-0 values the module computes or keeps in RAM.
const GP_APPLICATION_STATUS: u8 = 128;
const GP_DOWNLOAD_MODE: u8 = 129;
const GP_PROGRAM_COUNTER: u8 = 130;
const GP_TICK_TIMER: u8 = 132;
const GP_RANDOM: u8 = 133;
const GP_SUPPRESS_REPLY: u8 = 255;
/// AP1 actual position, AP138 ramp mode, AP207 error flags.
const AP_ACTUAL_POSITION: u8 = 1;
const AP_RAMP_MODE: u8 = 138;
const AP_ERROR_FLAGS: u8 = 207;

type Outcome = Result<i32, Status>;

impl Tmcm1110 {
    /// Execute a request whose checksum and address were accepted.
    pub(super) fn execute(&mut self, request: Request) -> Answer {
        let Some(info) = commands::command(request.command) else {
            return Answer::error(Status::INVALID_COMMAND);
        };
        let mode = commands::mode(info);
        if self.app.downloading && mode != Mode::Control {
            return self.store_command(request);
        }
        if !commands::type_accepted(info, request.kind) {
            return Answer::error(Status::WRONG_TYPE);
        }
        match mode {
            Mode::ProgramFlow => Answer::error(Status::NOT_AVAILABLE),
            Mode::Control => self.control(request),
            Mode::Direct => self.perform(request, Caller::Host).into(),
        }
    }

    /// Perform a motion, parameter, I/O, coordinate, calculation or
    /// interrupt set-up command for `caller`, whose registers it uses. The
    /// reply value is what a direct-mode reply carries; a program loads A
    /// from it for the reading commands (`interpreter.rs`).
    pub(super) fn perform(&mut self, r: Request, caller: Caller) -> Outcome {
        let (kind, motor, value) = (r.kind, r.motor_bank, r.value);
        let accumulator = self.registers(caller).accumulator;
        match r.command {
            op::ROR => self.rotate(motor, value),
            op::ROL => self.rotate(motor, value.checked_neg().ok_or(Status::INVALID_VALUE)?),
            op::MST => {
                only_motor_zero(motor)?;
                self.axis.clear_error_flags();
                self.axis.stop();
                self.abandon_move_report();
                Ok(0)
            }
            op::MVP => self.move_to_position(kind, motor, value),
            op::SAP => self.set_axis_parameter(kind, motor, value),
            op::GAP => self.get_axis_parameter(kind, motor),
            op::STAP => self.store_axis_parameter(kind, motor),
            op::RSAP => self.restore_axis_parameter(kind, motor),
            op::SGP => self.set_global_parameter(kind, motor, value),
            op::GGP => self.get_global_parameter(kind, motor),
            op::STGP => self.store_global_parameter(kind, motor),
            op::RSGP => self.restore_global_parameter(kind, motor),
            op::RFS => self.reference_search(kind, motor),
            op::SIO => self.set_output(kind, motor, value, accumulator),
            op::GIO => self.get_input(kind, motor),
            op::CALC => {
                let calc = calc_op(kind)?;
                let registers = self.registers(caller);
                let a = registers.accumulator;
                // NOT inverts the accumulator itself; the operand is unused.
                let operand = if calc == CalcOp::Not { a } else { value };
                if let Some(result) = calculate(calc, a, operand) {
                    registers.accumulator = result;
                    registers.note_result(result);
                }
                Ok(value)
            }
            op::COMP => {
                self.registers(caller).note_comparison(accumulator, value);
                Ok(0)
            }
            op::CALCX => {
                calculate_with_x(self.registers(caller), kind)?;
                Ok(0)
            }
            op::AAP => {
                self.set_axis_parameter(kind, motor, accumulator)?;
                Ok(0)
            }
            op::AGP => {
                self.set_global_parameter(kind, motor, accumulator)?;
                Ok(0)
            }
            op::CLE => {
                let flag = ClearFlag::from_code(kind).ok_or(Status::WRONG_TYPE)?;
                self.app.errors.clear(flag);
                Ok(0)
            }
            op::EI | op::DI => {
                self.app.interrupts.enable(kind, r.command == op::EI);
                Ok(0)
            }
            op::VECT => {
                let address = program_address(value)?;
                self.app.interrupts.vectors.insert(kind, address);
                Ok(0)
            }
            // Nothing to return from in direct mode; the program's RETI is
            // the interpreter's.
            op::RETI => Ok(0),
            op::SCO => self.set_coordinate(kind, motor, value),
            op::GCO => self.get_coordinate(kind, motor),
            op::CCO => {
                let position = self.axis.param(AP_ACTUAL_POSITION);
                self.capture_coordinate(kind, motor, position)?;
                Ok(position)
            }
            op::ACO => {
                self.capture_coordinate(kind, motor, accumulator)?;
                Ok(0)
            }
            op::CALCVV => {
                let other = u8::try_from(value).map_err(|_| Status::INVALID_VALUE)?;
                let operand = self.user_variable(other);
                self.calculate_variable(kind, motor, Operand::Variable(other, operand), caller)?;
                Ok(0)
            }
            op::CALCVA => {
                self.calculate_variable(kind, motor, Operand::Accumulator, caller)?;
                Ok(0)
            }
            op::CALCVX => {
                self.calculate_variable(kind, motor, Operand::X, caller)?;
                Ok(0)
            }
            op::CALCAV => {
                self.calculate_register(kind, motor, Register::Accumulator, caller)?;
                Ok(0)
            }
            op::CALCXV => {
                self.calculate_register(kind, motor, Register::X, caller)?;
                Ok(0)
            }
            op::CALCV => {
                self.calculate_variable(kind, motor, Operand::Value(value), caller)?;
                Ok(value)
            }
            op::MVPA => self.move_to_position(kind, motor, accumulator),
            op::RORA => self.rotate(motor, accumulator),
            op::ROLA => self.rotate(
                motor,
                accumulator.checked_neg().ok_or(Status::INVALID_VALUE)?,
            ),
            // §3.6.48–3.6.50: ignored when X is outside 0..255.
            op::SIV => {
                if let Some(slot) = self.indexed_variable(caller) {
                    *slot = value;
                }
                Ok(0)
            }
            op::GIV => Ok(self.indexed_variable(caller).map_or(0, |v| *v)),
            op::AIV => {
                if let Some(slot) = self.indexed_variable(caller) {
                    *slot = accumulator;
                }
                Ok(0)
            }
            _ => Err(Status::INVALID_COMMAND),
        }
    }

    /// The register set a caller's calculations use.
    pub(super) fn registers(&mut self, caller: Caller) -> &mut Registers {
        match caller {
            Caller::Host => &mut self.host_registers,
            Caller::Program => &mut self.app.registers,
        }
    }

    // ---- motion -------------------------------------------------------

    fn rotate(&mut self, motor: u8, velocity: i32) -> Outcome {
        only_motor_zero(motor)?;
        if !(-MAX_INTERNAL..=MAX_INTERNAL).contains(&velocity) {
            return Err(Status::INVALID_VALUE);
        }
        self.axis.clear_error_flags();
        self.axis.rotate(velocity);
        self.abandon_move_report();
        Ok(0)
    }

    /// MVP/MVPA ABS, REL (to the actual position, 32-bit wrap-around as the
    /// §3.6.4 note describes) and COORD.
    fn move_to_position(&mut self, kind: u8, motor: u8, value: i32) -> Outcome {
        only_motor_zero(motor)?;
        let actual = self.axis.param(AP_ACTUAL_POSITION);
        let target = match kind {
            0 => value,
            1 => actual.wrapping_add(value),
            _ => {
                let number = u8::try_from(value)
                    .ok()
                    .filter(|n| COORDINATES.contains(n))
                    .ok_or(Status::INVALID_VALUE)?;
                self.coordinates[usize::from(number)]
            }
        };
        self.axis.clear_error_flags();
        self.axis.move_to(target);
        self.arm_move_report(target == actual);
        Ok(0)
    }

    fn reference_search(&mut self, kind: u8, motor: u8) -> Outcome {
        only_motor_zero(motor)?;
        match kind {
            0 => {
                self.axis.clear_error_flags();
                self.axis.start_reference_search();
                self.abandon_move_report();
                Ok(0)
            }
            1 => {
                self.axis.stop_reference_search();
                Ok(0)
            }
            _ => Ok(i32::from(self.axis.reference_search_active())),
        }
    }

    /// A new MVP: report its arrival if command 138 asked for it.
    fn arm_move_report(&mut self, already_there: bool) {
        let request = self.report.request;
        self.report.awaiting = request != TargetReachedRequest::Off;
        self.report.arrived_at_start = self.report.awaiting && already_there;
        if request == TargetReachedRequest::NextMove {
            self.report.request = TargetReachedRequest::Off;
        }
    }

    /// The move under way will not reach its target: never report it.
    pub(super) fn abandon_move_report(&mut self) {
        self.report.awaiting = false;
        self.report.arrived_at_start = false;
    }

    // ---- axis parameters ----------------------------------------------

    fn set_axis_parameter(&mut self, number: u8, motor: u8, value: i32) -> Outcome {
        only_motor_zero(motor)?;
        let info = params::axis_param(number).ok_or(Status::WRONG_TYPE)?;
        self.check_write(info, value)?;
        self.write_axis_param(number, value);
        if number == AP_RAMP_MODE && value != 0 {
            self.abandon_move_report();
        }
        Ok(0)
    }

    fn get_axis_parameter(&mut self, number: u8, motor: u8) -> Outcome {
        only_motor_zero(motor)?;
        let info = params::axis_param(number).ok_or(Status::WRONG_TYPE)?;
        if !info.access.read {
            return Err(Status::WRONG_TYPE);
        }
        let value = self.read_axis_param(number);
        if number == AP_ERROR_FLAGS {
            // §4 Table 16: AP207 is cleared when read.
            self.axis.clear_error_flags();
        }
        Ok(value)
    }

    fn store_axis_parameter(&mut self, number: u8, motor: u8) -> Outcome {
        only_motor_zero(motor)?;
        storable(params::axis_param(number))?;
        let value = self.read_axis_param(number);
        self.eeprom.image.axis.insert(number, value);
        self.eeprom.changed();
        Ok(0)
    }

    fn restore_axis_parameter(&mut self, number: u8, motor: u8) -> Outcome {
        only_motor_zero(motor)?;
        storable(params::axis_param(number))?;
        if let Some(value) = self.eeprom.image.axis.get(&number).copied() {
            self.write_axis_param(number, value);
        }
        Ok(0)
    }

    pub(super) fn read_axis_param(&self, number: u8) -> i32 {
        if Axis::owns_param(number) {
            self.axis.param(number)
        } else {
            self.axis_store.get(&number).copied().unwrap_or(0)
        }
    }

    pub(super) fn write_axis_param(&mut self, number: u8, value: i32) {
        if Axis::owns_param(number) {
            self.axis.set_param(number, value);
        } else {
            self.axis_store.insert(number, value);
        }
    }

    /// Access and range of a write, from the parameter table.
    fn check_write(&self, info: &ParamInfo, value: i32) -> Result<(), Status> {
        if !info.access.write {
            return Err(self.config.read_only_write.status());
        }
        if !info.accepts_wire(value) {
            return Err(Status::INVALID_VALUE);
        }
        Ok(())
    }

    // ---- global parameters --------------------------------------------

    fn set_global_parameter(&mut self, number: u8, bank: u8, value: i32) -> Outcome {
        let info = global_info(bank, number)?;
        self.check_write(info, value)?;
        match bank {
            0 => self.set_bank0(number, value),
            2 => self.user_variables[usize::from(number)] = value,
            _ => {
                self.interrupt_config.insert(number, value);
                // Bank 3 parameters 0..2 are the timer periods (§5.4).
                self.timers
                    .set_period(usize::from(number), value, self.uptime);
            }
        }
        Ok(0)
    }

    /// Give the module a new address (GP66), as `SGP 66, 0, address` would:
    /// auto-stored, so it outlives a restart on the same EEPROM file. The
    /// command line's `--address` uses this, so an explicit address wins
    /// over one remembered in the file.
    pub fn set_module_address(&mut self, address: u8) {
        self.set_bank0(super::defaults::GP_SERIAL_ADDRESS, i32::from(address));
    }

    fn set_bank0(&mut self, number: u8, value: i32) {
        match number {
            GP_TICK_TIMER => {
                self.tick_base = self.uptime;
                self.tick_offset = u32::try_from(value).unwrap_or(0);
            }
            GP_RANDOM => self.random = seed(value),
            GP_SUPPRESS_REPLY => self.suppress_replies = value == 1,
            _ => {
                if number == GP_CODE_PROTECTION {
                    let old = self.global(GP_CODE_PROTECTION);
                    // §5.1: lifting the read-back protection erases the program first.
                    if matches!(old, 1 | 3) && matches!(value, 0 | 2) {
                        self.eeprom.image.program =
                            vec![ProgramWord::default(); PROGRAM_MEMORY_SIZE];
                    }
                }
                if number == GP_END_SWITCH_POLARITY {
                    self.axis.set_end_switch_polarity_reversed(value == 1);
                }
                // §5.1: SGP writes 64..127 through to EEPROM.
                self.eeprom.image.globals.insert(number, value);
                self.eeprom.changed();
            }
        }
    }

    fn get_global_parameter(&mut self, number: u8, bank: u8) -> Outcome {
        let info = global_info(bank, number)?;
        if !info.access.read {
            return Err(Status::WRONG_TYPE);
        }
        Ok(match bank {
            0 => self.bank0(number),
            2 => self.user_variable(number),
            _ => self.interrupt_config.get(&number).copied().unwrap_or(0),
        })
    }

    fn bank0(&mut self, number: u8) -> i32 {
        match number {
            GP_APPLICATION_STATUS => self.app.status as i32,
            GP_DOWNLOAD_MODE => i32::from(self.app.downloading),
            GP_PROGRAM_COUNTER => i32::from(self.app.pc),
            GP_TICK_TIMER => self.tick_timer(),
            GP_RANDOM => self.next_random(),
            GP_SUPPRESS_REPLY => i32::from(self.suppress_replies),
            _ => self.global(number),
        }
    }

    /// STGP: user variables 0..55 only (§3.6.11, §5.3).
    fn store_global_parameter(&mut self, number: u8, bank: u8) -> Outcome {
        storable(Some(global_info(bank, number)?))?;
        let index = usize::from(number);
        if index < STORED_USER_VARIABLES {
            self.eeprom.image.user_variables[index] = self.user_variables[index];
            self.eeprom.changed();
        }
        Ok(0)
    }

    fn restore_global_parameter(&mut self, number: u8, bank: u8) -> Outcome {
        storable(Some(global_info(bank, number)?))?;
        let index = usize::from(number);
        if let Some(&value) = self.eeprom.image.user_variables.get(index) {
            self.user_variables[index] = value;
        }
        Ok(0)
    }

    fn user_variable(&self, number: u8) -> i32 {
        self.user_variables[usize::from(number)]
    }

    /// xorshift32: deterministic, so tests can rely on the sequence.
    fn next_random(&mut self) -> i32 {
        let mut x = self.random;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.random = x;
        i32::try_from(x & 0x7FFF_FFFF).unwrap_or(0)
    }

    // ---- I/O ----------------------------------------------------------

    fn set_output(&mut self, port: u8, bank: u8, value: i32, accumulator: i32) -> Outcome {
        let group = io_group(SIO_PORTS, port, bank)?;
        if !group.values.contains(i64::from(value)) {
            return Err(Status::INVALID_VALUE);
        }
        // The table above has checked port, bank and value (§3.6.14).
        match (bank, port) {
            // SIO 0, 0, x: pull-up resistors.
            (0, _) => self.io.pull_ups = (value & MODE_MASK) as u8,
            // SIO 255, 2, x: all outputs; -1 takes the accumulator's low byte.
            (_, 255) if value == -1 => self.io.outputs = (accumulator & 0xFF) as u8,
            (_, 255) => self.io.outputs = (value & 0xFF) as u8,
            _ => self.io.set_output(port, value == 1),
        }
        Ok(0)
    }

    fn get_input(&mut self, port: u8, bank: u8) -> Outcome {
        io_group(GIO_PORTS, port, bank)?;
        let io_mode = self.global(GP_IO_MODE);
        // The table above has checked port and bank (§3.6.15).
        let level = match (bank, port) {
            (0, 255) => Some(self.io.all_inputs(io_mode)),
            (0, _) => self.io.input(port, io_mode).map(u8::from),
            (1, _) => return Ok(i32::from(self.io.analog)),
            _ => self.io.output(port).map(u8::from),
        };
        level.map(i32::from).ok_or(Status::WRONG_TYPE)
    }

    // ---- coordinates --------------------------------------------------

    fn set_coordinate(&mut self, number: u8, motor: u8, value: i32) -> Outcome {
        coordinate_number(number)?;
        match motor {
            0 => self.write_coordinate(number, value),
            // §3.6.24: SCO 0, 255, 0 copies 1..20 to EEPROM, SCO n, 255, 0 one.
            COORDINATE_EEPROM => {
                for n in copy_range(number) {
                    let ram = self.coordinates[usize::from(n)];
                    self.eeprom.image.set_coordinate(n, ram);
                }
                self.eeprom.changed();
            }
            _ => return Err(Status::INVALID_VALUE),
        }
        Ok(0)
    }

    fn get_coordinate(&mut self, number: u8, motor: u8) -> Outcome {
        coordinate_number(number)?;
        match motor {
            0 => Ok(self.coordinates[usize::from(number)]),
            // §3.6.25: GCO 0, 255, 0 copies 1..20 from EEPROM, GCO n, 255, 0 one.
            COORDINATE_EEPROM => {
                for n in copy_range(number) {
                    if let Some(stored) = self.eeprom.image.coordinate(n) {
                        self.coordinates[usize::from(n)] = stored;
                    }
                }
                Ok(0)
            }
            _ => Err(Status::INVALID_VALUE),
        }
    }

    fn capture_coordinate(&mut self, number: u8, motor: u8, value: i32) -> Result<(), Status> {
        coordinate_number(number)?;
        only_motor_zero(motor)?;
        self.write_coordinate(number, value);
        Ok(())
    }

    /// With GP84 = 1 coordinates 1..20 are always stored in EEPROM too.
    fn write_coordinate(&mut self, number: u8, value: i32) {
        self.coordinates[usize::from(number)] = value;
        if number != 0 && self.global(GP_COORDINATE_STORAGE) == 1 {
            self.eeprom.image.set_coordinate(number, value);
            self.eeprom.changed();
        }
    }

    // ---- calculation --------------------------------------------------

    /// CALCVV, CALCVA, CALCVX, CALCV: user variable `var` op operand → var.
    fn calculate_variable(
        &mut self,
        kind: u8,
        var: u8,
        operand: Operand,
        caller: Caller,
    ) -> Result<(), Status> {
        let calc = calc_op(kind)?;
        let index = usize::from(var);
        let current = self.user_variables[index];
        let registers = match caller {
            Caller::Host => &mut self.host_registers,
            Caller::Program => &mut self.app.registers,
        };
        let value = match operand {
            Operand::Variable(_, v) => v,
            Operand::Accumulator => registers.accumulator,
            Operand::X => registers.x,
            // CALCV NOT inverts the variable itself (§3.6.41: value ignored).
            Operand::Value(_) if calc == CalcOp::Not => current,
            Operand::Value(v) => v,
        };
        match calc {
            CalcOp::Comp => registers.note_comparison(current, value),
            CalcOp::Swap => {
                self.user_variables[index] = value;
                match operand {
                    Operand::Variable(other, _) => {
                        self.user_variables[usize::from(other)] = current;
                    }
                    Operand::Accumulator => registers.accumulator = current,
                    Operand::X => registers.x = current,
                    // Not in CALCV's type list: refused before this point.
                    Operand::Value(_) => return Err(Status::WRONG_TYPE),
                }
            }
            _ => {
                if let Some(result) = calculate(calc, current, value) {
                    self.user_variables[index] = result;
                    registers.note_result(result);
                }
            }
        }
        Ok(())
    }

    /// CALCAV, CALCXV: register op user variable `var` → register.
    fn calculate_register(
        &mut self,
        kind: u8,
        var: u8,
        register: Register,
        caller: Caller,
    ) -> Result<(), Status> {
        let calc = calc_op(kind)?;
        let index = usize::from(var);
        let variable = self.user_variables[index];
        let registers = match caller {
            Caller::Host => &mut self.host_registers,
            Caller::Program => &mut self.app.registers,
        };
        let current = match register {
            Register::Accumulator => registers.accumulator,
            Register::X => registers.x,
        };
        let result = match calc {
            CalcOp::Comp => {
                registers.note_comparison(current, variable);
                return Ok(());
            }
            CalcOp::Swap => {
                self.user_variables[index] = current;
                variable
            }
            _ => match calculate(calc, current, variable) {
                Some(result) => {
                    registers.note_result(result);
                    result
                }
                None => current,
            },
        };
        match register {
            Register::Accumulator => registers.accumulator = result,
            Register::X => registers.x = result,
        }
        Ok(())
    }

    /// The user variable X points at, if X is 0..255 (§3.6.48–3.6.50).
    fn indexed_variable(&mut self, caller: Caller) -> Option<&mut i32> {
        let index = usize::try_from(self.registers(caller).x).ok()?;
        self.user_variables.get_mut(index)
    }

    // ---- control commands (§3.6.53, §3.6.52) ---------------------------

    fn control(&mut self, r: Request) -> Answer {
        match r.command {
            op::STOP_APPLICATION => {
                self.app.stop();
                Answer::ok(0)
            }
            op::RUN_APPLICATION => {
                if r.kind == 1 {
                    match program_address(r.value) {
                        Ok(address) => self.app.run_from(address),
                        Err(status) => return Answer::error(status),
                    }
                }
                self.app.status = ApplicationStatus::Running;
                self.program_fault = None;
                Answer::ok(0)
            }
            op::STEP_APPLICATION => {
                self.app.status = ApplicationStatus::Stepping;
                self.program_fault = None;
                Answer::ok(0)
            }
            op::RESET_APPLICATION => {
                self.app.reset();
                self.program_fault = None;
                Answer::ok(0)
            }
            op::ENTER_DOWNLOAD => self.enter_download(r.value).into(),
            op::EXIT_DOWNLOAD => {
                self.app.downloading = false;
                self.eeprom.defer_writes(false);
                Answer::ok(0)
            }
            op::READ_MEMORY => self.read_program(r.value),
            op::APPLICATION_STATUS => Answer::ok(self.application_status(r.kind)),
            op::FIRMWARE_VERSION => {
                if r.kind == 0 {
                    let mut bytes = [0u8; FRAME_LEN];
                    bytes[0] = self.host_address();
                    bytes[1..].copy_from_slice(FIRMWARE_VERSION_STRING);
                    Answer::Special(bytes)
                } else {
                    Answer::ok(FIRMWARE_VERSION_NUMBER)
                }
            }
            op::FACTORY_RESET => {
                if r.value != RESET_KEY {
                    return Answer::error(Status::INVALID_VALUE);
                }
                self.eeprom.image = EepromImage::factory(self.config.address);
                self.eeprom.changed();
                self.reboot_requested = true;
                Answer::Silent
            }
            op::TARGET_REACHED_EVENT => {
                if r.value != MOTOR_MASK {
                    return Answer::error(Status::INVALID_VALUE);
                }
                self.report.request = if r.kind == 0 {
                    TargetReachedRequest::NextMove
                } else {
                    TargetReachedRequest::EveryMove
                };
                Answer::ok(MOTOR_MASK)
            }
            op::SOFTWARE_RESET => {
                if r.value != RESET_KEY {
                    return Answer::error(Status::INVALID_VALUE);
                }
                self.reboot_requested = true;
                Answer::ok(0)
            }
            _ => Answer::error(Status::INVALID_COMMAND),
        }
    }

    fn enter_download(&mut self, start: i32) -> Outcome {
        if matches!(self.global(GP_CODE_PROTECTION), 2 | 3) {
            return Err(Status::EEPROM_LOCKED);
        }
        let start = program_address(start)?;
        if matches!(
            self.app.status,
            ApplicationStatus::Running | ApplicationStatus::Stepping
        ) {
            self.app.stop();
        }
        self.app.downloading = true;
        self.app.memory_pointer = start;
        self.eeprom.defer_writes(true);
        Ok(0)
    }

    fn store_command(&mut self, r: Request) -> Answer {
        let address = self.app.memory_pointer;
        let Some(slot) = self.eeprom.image.program.get_mut(usize::from(address)) else {
            return Answer::error(Status::INVALID_VALUE);
        };
        let value = match self.store_fault.as_mut() {
            Some(fault) => fault.corrupt(r.value),
            None => r.value,
        };
        *slot = ProgramWord {
            opcode: r.command,
            kind: r.kind,
            motor_bank: r.motor_bank,
            value,
        };
        self.app.memory_pointer = address.saturating_add(1);
        self.eeprom.changed();
        Answer::Reply {
            status: Status::LOADED,
            value: i32::from(address),
        }
    }

    fn read_program(&mut self, address: i32) -> Answer {
        if matches!(self.global(GP_CODE_PROTECTION), 1 | 3) {
            return Answer::error(Status::NOT_AVAILABLE);
        }
        let word = match program_address(address) {
            Ok(a) => self.eeprom.image.program[usize::from(a)],
            Err(status) => return Answer::error(status),
        };
        let mut bytes = [0u8; FRAME_LEN];
        bytes[0] = self.host_address();
        bytes[1..8].copy_from_slice(&word.to_bytes());
        bytes[8] = checksum(&bytes[..8]);
        Answer::Special(bytes)
    }

    fn application_status(&self, kind: u8) -> i32 {
        let app = &self.app;
        let pointer = if kind == 0 {
            app.memory_pointer
        } else {
            app.pc
        };
        match kind {
            0 | 1 => {
                let waiting = app.wait.is_some();
                ((app.status as i32) << 24) | (i32::from(waiting) << 16) | i32::from(pointer)
            }
            2 => app.registers.accumulator,
            _ => app.registers.x,
        }
    }
}

/// CALCX (§3.6.28): A op X for 0..7, NOT inverts X, LOAD copies A to X,
/// SWAP exchanges them.
fn calculate_with_x(registers: &mut Registers, kind: u8) -> Result<(), Status> {
    match calc_op(kind)? {
        CalcOp::Not => registers.x = !registers.x,
        CalcOp::Load => registers.x = registers.accumulator,
        CalcOp::Swap => std::mem::swap(&mut registers.accumulator, &mut registers.x),
        calc => {
            if let Some(result) = calculate(calc, registers.accumulator, registers.x) {
                registers.accumulator = result;
                registers.note_result(result);
            }
        }
    }
    Ok(())
}

/// Who a command comes from: the host (direct mode) or the stored program.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Caller {
    Host,
    Program,
}

/// The other side of a CALCV*-family operation on a user variable.
#[derive(Debug, Clone, Copy)]
enum Operand {
    /// CALCVV: variable number and its value.
    Variable(u8, i32),
    Accumulator,
    X,
    /// CALCV: the command's value.
    Value(i32),
}

#[derive(Debug, Clone, Copy)]
enum Register {
    Accumulator,
    X,
}

fn only_motor_zero(motor: u8) -> Result<(), Status> {
    if motor == 0 {
        Ok(())
    } else {
        Err(Status::INVALID_VALUE)
    }
}

/// The operation of a CALC-family type byte (the command's own subset was
/// checked against the catalogue already).
fn calc_op(kind: u8) -> Result<CalcOp, Status> {
    CalcOp::from_code(kind).ok_or(Status::WRONG_TYPE)
}

/// Bank 0/2/3 (else 4) and a parameter the bank has (else 3).
fn global_info(bank: u8, number: u8) -> Result<&'static ParamInfo, Status> {
    if params::Bank::from_number(bank).is_none() {
        return Err(Status::INVALID_VALUE);
    }
    params::global_param(bank, number).ok_or(Status::WRONG_TYPE)
}

/// STAP/RSAP/STGP/RSGP need a parameter with access E.
fn storable(info: Option<&ParamInfo>) -> Result<(), Status> {
    match info {
        Some(info) if info.access.eeprom => Ok(()),
        _ => Err(Status::WRONG_TYPE),
    }
}

fn coordinate_number(number: u8) -> Result<(), Status> {
    if COORDINATES.contains(&number) {
        Ok(())
    } else {
        Err(Status::WRONG_TYPE)
    }
}

/// Coordinate 0 in an EEPROM copy form means "all of 1..20".
fn copy_range(number: u8) -> std::ops::RangeInclusive<u8> {
    if number == 0 {
        1..=*COORDINATES.end()
    } else {
        number..=number
    }
}

/// A program memory address, 0..2047 (else 4).
fn program_address(value: i32) -> Result<u16, Status> {
    u16::try_from(value)
        .ok()
        .filter(|&a| usize::from(a) < PROGRAM_MEMORY_SIZE)
        .ok_or(Status::INVALID_VALUE)
}

/// GP133 seed; the generator needs a non-zero state.
fn seed(value: i32) -> u32 {
    match value as u32 {
        0 => 1,
        s => s,
    }
}

/// The SIO/GIO port group, or the status the module answers (§3.2.1): an
/// unknown bank is an invalid value, an unknown port a wrong type.
fn io_group(table: &[IoPorts], port: u8, bank: u8) -> Result<&IoPorts, Status> {
    find_io_port(table, port, bank).map_err(|miss| match miss {
        IoPortMiss::Bank => Status::INVALID_VALUE,
        IoPortMiss::Port => Status::WRONG_TYPE,
    })
}
