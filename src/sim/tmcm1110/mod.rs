//! A faithful simulator of the TMCM-1110 StepRocker in TMCL direct mode
//! and standalone mode (firmware V1.12 manual, §3, §4, §5, §6.2, §8): stored
//! programs run on virtual time (`interpreter.rs`) beside direct-mode
//! commands.
//!
//! A plain state machine: bytes in ([`SimulatedController::feed`]), virtual
//! time ([`SimulatedController::advance`]), bytes out
//! ([`SimulatedController::take_output`]). No clock, no sleeping, no I/O
//! except the optional EEPROM file.
//!
//! Choices where the manual is silent (each is also noted at the code that
//! makes it):
//! - Framing: TMCL has no start byte; a partial frame is dropped after
//!   [`SimConfig::frame_gap`] of silence (default 10 ms, about ten character
//!   times at 9600 baud). Frames for another address (GP66, or GP87 if not 0)
//!   are ignored silently, whatever their checksum. Replies carry the host
//!   address GP76 and the address the command was sent to.
//! - Error replies carry the received opcode and value 0; so does the reply
//!   to a wrong checksum. Check order: checksum 1, opcode 2, type 3,
//!   motor/bank 4, parameter number 3, access ([`ReadOnlyWrite`]), value 4.
//! - GP255 = 1 suppresses every reply except those of GAP, GGP and GIO,
//!   errors included; the status-128 message of command 138 is still sent
//!   (the host asked for it; it answers no command). A reply follows the
//!   settings in force after its command: `SGP 255, 0, 1` gets none, and
//!   the reply to `SGP 76` already carries the new host address.
//! - GP66 changes take effect with the next frame. `SimConfig::address` is
//!   the factory value; a GP66 kept in the EEPROM file wins over it.
//! - Timing units the manual leaves open: GP68 heartbeat in ms; GP75
//!   (telegram pause) is stored but replies are not delayed.
//! - See the submodules and `execute.rs` for the per-command decisions.

mod commands;
pub mod defaults;
pub mod eeprom;
mod execute;
pub mod inputs;
pub mod interpreter;
pub mod interrupts;
pub mod io;
pub mod motion;
pub mod program;

#[cfg(test)]
mod tests;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Duration;

use crate::protocol::tmcl::command::opcode;
use crate::protocol::tmcl::{FRAME_LEN, FrameAssembler, Reply, Request, Status, checksum};

use super::SimulatedController;
use eeprom::{Eeprom, EepromError, EepromImage};
use interpreter::{DEFAULT_INSTRUCTION_TIME, MIN_INSTRUCTION_TIME, ProgramFault};
use interrupts::Timers;
use io::{INPUT_PORTS, Io};
use motion::{Axis, AxisEvent, SwitchLayout};
use program::{Application, ApplicationStatus, Registers};

/// The simulator as `--sim tmcm1110` names it.
pub const KIND: super::SimKind = super::SimKind {
    name: "tmcm1110",
    description: "Trinamic TMCM-1110 StepRocker (TMCL, 1 axis)",
    build: |options| {
        let mut config = SimConfig::default();
        if let Some(address) = options.address {
            config.address = address;
        }
        config.eeprom_file = options.eeprom_file.clone();
        let mut sim = Tmcm1110::new(config);
        if let Some(address) = options.address {
            sim.set_module_address(address);
        }
        Box::new(sim)
    },
    input_names: || super::inputs::names(inputs::INPUTS),
    input_help: || super::inputs::help_lines(inputs::INPUTS),
    eeprom_refusal: None,
};

/// The firmware version string of command 136 type 0: module number, 'V',
/// version digits (digest D4, from sibling Trinamic manuals).
pub const FIRMWARE_VERSION_STRING: &[u8; 8] = b"1110V112";

/// Command 136 type 1: byte 3..2 = module type 1110 (0x0456), byte 1 = major
/// version 1, byte 0 = minor version 12, the layout of Trinamic's published
/// TMCL interpreters (the manual gives none).
pub const FIRMWARE_VERSION_NUMBER: i32 = (1110 << 16) | (1 << 8) | 12;

/// What a write to a read-only parameter answers: the manual does not say
/// (digest D12.4). Trinamic's published interpreters list only writable
/// parameters in their SAP switch, so a read-only one falls through to
/// "wrong type" (3); the default follows them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ReadOnlyWrite {
    /// Status 3 "wrong type".
    #[default]
    WrongType,
    /// Status 4 "invalid value".
    InvalidValue,
}

impl ReadOnlyWrite {
    pub fn status(self) -> Status {
        match self {
            ReadOnlyWrite::WrongType => Status::WRONG_TYPE,
            ReadOnlyWrite::InvalidValue => Status::INVALID_VALUE,
        }
    }
}

/// How the simulated module is set up.
#[derive(Debug, Clone)]
pub struct SimConfig {
    /// Factory module address (GP66), 1 unless told otherwise. An EEPROM file
    /// that already holds GP66 keeps its own value (check [`Tmcm1110::address`]).
    pub address: u8,
    /// Where the EEPROM image is kept between runs; `None` keeps it in memory.
    pub eeprom_file: Option<PathBuf>,
    /// Answer to SAP/SGP on a read-only parameter.
    pub read_only_write: ReadOnlyWrite,
    /// Line silence after which a partial frame is dropped.
    pub frame_gap: Duration,
    /// Time the interpreter needs per program command (at least
    /// [`MIN_INSTRUCTION_TIME`]); the manual gives no figure.
    pub instruction_time: Duration,
}

/// Default [`SimConfig::frame_gap`]: about ten character times at 9600 baud.
pub const DEFAULT_FRAME_GAP: Duration = Duration::from_millis(10);

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            address: 1,
            eeprom_file: None,
            read_only_write: ReadOnlyWrite::default(),
            frame_gap: DEFAULT_FRAME_GAP,
            instruction_time: DEFAULT_INSTRUCTION_TIME,
        }
    }
}

/// Whether command 138 asked for a target-position-reached message (§3.6.52).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TargetReachedRequest {
    #[default]
    Off,
    /// Type 0: for the next MVP only.
    NextMove,
    /// Type 1: for every MVP.
    EveryMove,
}

/// The command-138 bookkeeping.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct TargetReport {
    request: TargetReachedRequest,
    /// An MVP/MVPA is under way whose arrival must be reported.
    awaiting: bool,
    /// That MVP started at its target already: report at the next advance.
    arrived_at_start: bool,
}

/// A simulated input the module cannot have.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum InputError {
    #[error(
        "digital input port {0} does not exist: GIO bank 0 has ports 1..6 (port 0 is AIN0, set it with the analog value)"
    )]
    NoSuchPort(u8),
}

/// A snapshot of what the module is doing, for tests and the console.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModuleView {
    /// GP66.
    pub module_address: u8,
    /// GP76.
    pub host_address: u8,
    pub actual_position: i32,
    pub target_position: i32,
    pub actual_speed: i32,
    /// AP138: 0 position, 1 soft, 2 velocity.
    pub ramp_mode: i32,
    pub position_reached: bool,
    pub reference_search_active: bool,
    /// Output latches, bit n = SIO bank-2 port n.
    pub outputs: u8,
    /// Pull-up mask (SIO 0, 0).
    pub pull_ups: u8,
    /// GP78 direction mask.
    pub io_mode: i32,
    /// AIN0 ADC value.
    pub analog_input: u16,
    pub application_status: ApplicationStatus,
    pub program_counter: u16,
    /// The program's accumulator and X register (135 types 2 and 3).
    pub accumulator: i32,
    pub x_register: i32,
    /// A WAIT holds the program.
    pub waiting: bool,
    /// Subroutine return addresses on the stack.
    pub call_depth: usize,
    /// The interrupt whose handler runs now.
    pub handling_interrupt: Option<u8>,
    /// Why the interpreter last stopped a program on its own.
    pub program_fault: Option<ProgramFault>,
    pub download_mode: bool,
    /// GP255.
    pub replies_suppressed: bool,
    pub target_reached_request: TargetReachedRequest,
    /// Virtual time since the last power-up or reset.
    pub uptime: Duration,
}

/// The simulated module.
pub struct Tmcm1110 {
    config: SimConfig,
    assembler: FrameAssembler,
    /// Silence on the line since the last byte, while a partial frame waits.
    silence: Duration,
    axis: Axis,
    /// Axis parameters the motion model does not own.
    axis_store: BTreeMap<u8, i32>,
    /// Bank 2, all 256 user variables.
    user_variables: [i32; 256],
    /// Bank 3, interrupt configuration (RAM only, 0 at power-up).
    interrupt_config: BTreeMap<u8, i32>,
    /// Coordinates 0..20 in RAM.
    coordinates: [i32; 21],
    io: Io,
    app: Application,
    /// A, X and flags of direct-mode calculations: a program's registers are
    /// its own (§8.6, see `execute.rs`).
    host_registers: Registers,
    /// Interrupt timers 0..2 (bank 3 parameters 0..2).
    timers: Timers,
    /// Input levels last seen, by GIO bank-0 port, for interrupts 39..44.
    input_levels: [bool; INPUT_PORTS as usize],
    program_fault: Option<ProgramFault>,
    eeprom: Eeprom,
    report: TargetReport,
    /// GP255.
    suppress_replies: bool,
    /// Time since power-up; GP132 counts its milliseconds from `tick_base`.
    uptime: Duration,
    tick_base: Duration,
    tick_offset: u32,
    /// GP133 generator state.
    random: u32,
    /// Time since the last command with a correct checksum (GP68).
    since_command: Duration,
    heartbeat_expired: bool,
    /// Reboot once the current reply has gone out (command 255).
    reboot_requested: bool,
    /// A reboot happened while handling the current input.
    rebooted: bool,
    output: Vec<u8>,
    /// An injected fault: a downloaded word to store corrupted.
    store_fault: Option<StoreFault>,
}

/// The `corrupt-store=N` fault: the N-th word stored in download mode
/// since it was armed gets one bit flipped, and the reply says nothing of
/// it. It stands for a failing EEPROM cell, which only reading the word
/// back (134) can show.
#[derive(Debug, Clone)]
struct StoreFault {
    /// Which word, counting from 1.
    nth: u64,
    /// Words stored since it was armed.
    stored: u64,
    record: crate::sim::faults::FaultRecord,
}

impl StoreFault {
    /// Count one stored word; the value to store instead, if this is the one.
    fn corrupt(&mut self, value: i32) -> i32 {
        self.stored += 1;
        if self.stored != self.nth {
            return value;
        }
        self.record.note_corrupted_store();
        // The lowest value bit: any single flipped bit makes the word
        // differ, and this one leaves every other field as sent.
        value ^ 1
    }
}

/// Seed of the GP133 generator at power-up (any non-zero value).
const RANDOM_SEED: u32 = 0x2545_F491;

impl Tmcm1110 {
    pub fn new(config: SimConfig) -> Self {
        let eeprom = Eeprom::open(
            config.eeprom_file.clone(),
            EepromImage::factory(config.address),
        );
        let mut sim = Tmcm1110 {
            config,
            assembler: FrameAssembler::new(),
            silence: Duration::ZERO,
            axis: Axis::new(),
            axis_store: BTreeMap::new(),
            user_variables: [0; 256],
            interrupt_config: BTreeMap::new(),
            coordinates: [0; 21],
            io: Io::default(),
            app: Application::default(),
            host_registers: Registers::default(),
            timers: Timers::default(),
            input_levels: [false; INPUT_PORTS as usize],
            program_fault: None,
            eeprom,
            report: TargetReport::default(),
            suppress_replies: false,
            uptime: Duration::ZERO,
            tick_base: Duration::ZERO,
            tick_offset: 0,
            random: RANDOM_SEED,
            since_command: Duration::ZERO,
            heartbeat_expired: false,
            reboot_requested: false,
            rebooted: false,
            output: Vec::new(),
            store_fault: None,
        };
        sim.power_up();
        sim
    }

    /// The module address it answers to (GP66).
    pub fn address(&self) -> u8 {
        self.global_u8(defaults::GP_SERIAL_ADDRESS)
    }

    /// The last problem with the EEPROM file (unreadable, invalid, or not
    /// writable), if any.
    pub fn eeprom_problem(&self) -> Option<&EepromError> {
        self.eeprom.problem()
    }

    /// Write the EEPROM file now if it has unwritten changes (they are held
    /// back during a program download).
    pub fn flush_eeprom(&mut self) {
        self.eeprom.flush();
    }

    /// Drive digital input `port` (GIO bank 0, 1..6) high, low, or leave it
    /// open (`None`: its pull-up decides).
    pub fn set_input(&mut self, port: u8, level: Option<bool>) -> Result<(), InputError> {
        match self.io.external.get_mut(usize::from(port)) {
            Some(slot) if port != 0 => {
                *slot = level;
                Ok(())
            }
            _ => Err(InputError::NoSuchPort(port)),
        }
    }

    /// Drive one input by a setting typed from outside (`IN3=1`,
    /// `PWMD2=open`, `AIN0=302`; the names in [`inputs::INPUTS`]): what now
    /// holds, or what was wrong with it.
    pub fn drive_input(&mut self, text: &str) -> Result<String, crate::sim::inputs::SettingError> {
        use crate::sim::inputs::{Level, SettingError};
        let setting = inputs::parse(text)?;
        if setting.row.input == inputs::Input::Load {
            let percent = match setting.level {
                Level::Number(n) => u8::try_from(n.min(100)).unwrap_or(100),
                _ => 0,
            };
            self.axis.set_load_percent(percent);
            return Ok(format!(
                "LOAD {percent} % of the torque at the AP6 current{}",
                if percent >= 100 {
                    ": the motor stalls"
                } else {
                    ""
                }
            ));
        }
        if setting.row.input == inputs::Input::Limits {
            let swapped = crate::sim::inputs::limits_swapped(setting.level);
            self.axis.set_limits_swapped(swapped);
            return Ok(if swapped {
                "LIMITS swapped: the + end closes the left limit input, the − end the right one"
                    .into()
            } else {
                "LIMITS right: the + end closes the right limit input, the − end the left one"
                    .into()
            });
        }
        let Some(port) = inputs::port_of(&setting) else {
            let value = match setting.level {
                Level::Number(n) => u16::try_from(n).unwrap_or(u16::MAX),
                _ => 0,
            };
            self.set_analog_input(value);
            return Ok(format!("AIN0 {value}"));
        };
        self.set_input(port, setting.level.is_on())
            .map_err(|e| SettingError::Refused {
                name: setting.name(),
                why: e.to_string(),
            })?;
        let line = io::input_line(port);
        let name = line.map_or("", |l| l.name);
        let said = match setting.level {
            Level::Released => format!("IN{port} ({name}) open: its pull-up decides"),
            level => format!("IN{port} ({name}) {level}"),
        };
        // A bidirectional line GP78 makes an output reads its own latch
        // (see `Io::input`): the level waits until it is an input again.
        Ok(match line.and_then(|l| l.mode_bit) {
            Some(bit) if self.global(GP_IO_MODE) & (1 << bit) != 0 => format!(
                "{said}; an output now (GP78 bit {bit}): GIO reads its latch until it is an input again"
            ),
            _ => said,
        })
    }

    /// The load on the simulated motor, percent of its torque at the AP6
    /// run current (clamped to 100, a stall): what `LOAD=` sets. AP206,
    /// AP208 bit 0, the stop on stall and CoolStep follow it
    /// ([`motion::stallguard`]).
    pub fn set_load_percent(&mut self, percent: u8) {
        self.axis.set_load_percent(percent);
    }

    /// Set the AIN0 ADC value (GIO 0, 1; also read digitally as GIO 0, 0).
    pub fn set_analog_input(&mut self, value: u16) {
        self.io.analog = value;
    }

    /// Where the simulated machine's switches are.
    pub fn switch_layout_mut(&mut self) -> &mut SwitchLayout {
        self.axis.layout_mut()
    }

    /// The axis model, read-only.
    pub fn axis(&self) -> &Axis {
        &self.axis
    }

    /// What the module is doing now.
    pub fn view(&self) -> ModuleView {
        ModuleView {
            module_address: self.address(),
            host_address: self.host_address(),
            actual_position: self.axis.param(1),
            target_position: self.axis.param(0),
            actual_speed: self.axis.param(3),
            ramp_mode: self.axis.param(138),
            position_reached: self.axis.param(8) != 0,
            reference_search_active: self.axis.reference_search_active(),
            outputs: self.io.outputs,
            pull_ups: self.io.pull_ups,
            io_mode: self.global(GP_IO_MODE),
            analog_input: self.io.analog,
            application_status: self.app.status,
            program_counter: self.app.pc,
            accumulator: self.app.registers.accumulator,
            x_register: self.app.registers.x,
            waiting: self.app.wait.is_some(),
            call_depth: self.app.call_stack.len(),
            handling_interrupt: self.app.interrupts.handling.as_ref().map(|c| c.number),
            program_fault: self.program_fault,
            download_mode: self.app.downloading,
            replies_suppressed: self.suppress_replies,
            target_reached_request: self.report.request,
            uptime: self.uptime,
        }
    }

    /// The stored program command at `address`, if the address exists.
    pub fn program_word(&self, address: usize) -> Option<[u8; 7]> {
        self.eeprom.image.program.get(address).map(|w| w.to_bytes())
    }

    /// One line listing the simulator's own choices where the manual gives
    /// no value.
    pub fn help_line(&self) -> String {
        let mut config = self.config.clone();
        config.address = self.address();
        let layout = self.axis.layout();
        format!(
            "{}, {}; inputs driven from outside (--input, a line on the standard input of \
             `axterm sim`, :sim-input): {}",
            help_line(&config),
            describe_layout(layout),
            crate::sim::inputs::summary(inputs::INPUTS)
        )
    }

    // ---- power-up ----------------------------------------------------

    /// Power-up and software reset (§3.6.53, §5.1, §5.3, §3.6.24; digest
    /// D12.3): axis parameters and bank 0 from EEPROM, user variables 0..55
    /// from EEPROM unless GP85 = 1, coordinates from EEPROM only if GP84 = 1,
    /// GP255 = 0, program kept and started if GP77 = 1. The axis model starts
    /// afresh (position counter 0); the simulated machine (switch positions,
    /// input levels, analog value) stays as it was.
    fn power_up(&mut self) {
        let layout = self.axis.layout_mut().clone();
        self.axis = Axis::new();
        *self.axis.layout_mut() = layout;
        let fresh = Axis::new();
        self.axis_store = crate::protocol::tmcl::params::AXIS_PARAMS
            .iter()
            .flat_map(|p| p.numbers.clone())
            .filter(|&n| !Axis::owns_param(n))
            .map(|n| (n, defaults::axis_factory_value(n, &fresh)))
            .collect();
        let stored: Vec<(u8, i32)> = self
            .eeprom
            .image
            .axis
            .iter()
            .map(|(&n, &v)| (n, v))
            .collect();
        for (number, value) in stored {
            self.write_axis_param(number, value);
        }
        self.axis
            .set_end_switch_polarity_reversed(self.global(GP_END_SWITCH_POLARITY) == 1);

        self.user_variables = [0; 256];
        if self.global(GP_DO_NOT_RESTORE_VARIABLES) == 0 {
            let stored = self.eeprom.image.user_variables;
            self.user_variables[..stored.len()].copy_from_slice(&stored);
        }
        self.coordinates = [0; 21];
        if self.global(GP_COORDINATE_STORAGE) == 1 {
            let stored = self.eeprom.image.coordinates;
            self.coordinates[1..].copy_from_slice(&stored);
        }
        self.interrupt_config.clear();
        self.timers = Timers::default();
        self.io.power_up();
        self.sample_inputs();

        // §5.1 GP77, §8.7: the stored program starts at address 0.
        self.app = Application::default();
        self.host_registers = Registers::default();
        self.program_fault = None;
        if self.global(GP_AUTO_START) == 1 {
            self.app.status = ApplicationStatus::Running;
        }
        self.eeprom.defer_writes(false);
        self.report = TargetReport::default();
        self.suppress_replies = false;
        self.uptime = Duration::ZERO;
        self.tick_base = Duration::ZERO;
        self.tick_offset = 0;
        self.random = RANDOM_SEED;
        self.since_command = Duration::ZERO;
        self.heartbeat_expired = false;
        self.reboot_requested = false;
        self.assembler.resync();
        self.silence = Duration::ZERO;
    }

    // ---- framing and replies ----------------------------------------

    /// GP66 or, if set, the secondary address GP87.
    fn answers_to(&self, address: u8) -> bool {
        let secondary = self.global_u8(GP_SECONDARY_ADDRESS);
        address == self.address() || (secondary != 0 && address == secondary)
    }

    fn host_address(&self) -> u8 {
        self.global_u8(GP_HOST_ADDRESS)
    }

    fn handle_frame(&mut self, bytes: [u8; FRAME_LEN]) {
        let request = Request::from_bytes_unchecked(&bytes);
        if !self.answers_to(request.address) {
            return;
        }
        let answer = if checksum(&bytes[..8]) != bytes[8] {
            Answer::error(Status::WRONG_CHECKSUM)
        } else {
            self.since_command = Duration::ZERO;
            self.heartbeat_expired = false;
            self.execute(request)
        };
        self.send(&request, answer);
        if self.reboot_requested {
            self.power_up();
            self.rebooted = true;
        }
    }

    fn send(&mut self, request: &Request, answer: Answer) {
        let exempt = commands::NEVER_SUPPRESSED.contains(&request.command);
        if self.suppress_replies && !exempt {
            return;
        }
        match answer {
            Answer::Reply { status, value } => {
                let reply = Reply {
                    host_address: self.host_address(),
                    module_address: request.address,
                    status,
                    command: request.command,
                    value,
                };
                self.output.extend_from_slice(&reply.to_bytes());
            }
            Answer::Special(bytes) => self.output.extend_from_slice(&bytes),
            Answer::Silent => {}
        }
    }

    /// §3.6.52: the additional reply once the motor has reached its target.
    fn send_target_reached(&mut self) {
        let reply = Reply {
            host_address: self.host_address(),
            module_address: self.address(),
            status: Status::TARGET_REACHED,
            command: opcode::TARGET_REACHED_EVENT,
            value: MOTOR_MASK,
        };
        self.output.extend_from_slice(&reply.to_bytes());
    }

    // ---- time --------------------------------------------------------

    /// Run the axis for `dt` and react to what it reports.
    fn run_axis(&mut self, dt: Duration) {
        if self.report.awaiting && self.report.arrived_at_start {
            self.report = TargetReport {
                awaiting: false,
                arrived_at_start: false,
                ..self.report
            };
            self.send_target_reached();
        }
        let mut events = Vec::new();
        self.axis.advance(dt, &mut events);
        for event in events {
            self.axis_interrupts(event);
            match event {
                AxisEvent::TargetReached => {
                    if self.report.awaiting {
                        self.report.awaiting = false;
                        self.send_target_reached();
                    }
                }
                // The motor stopped short of its target: that move will
                // never be reported (a later MVP may be).
                AxisEvent::LimitStop(_) | AxisEvent::StallStop | AxisEvent::DeviationStop => {
                    self.abandon_move_report();
                }
                AxisEvent::ReferenceSearchDone | AxisEvent::SwitchChanged { .. } => {}
            }
        }
    }

    /// GP68 in ms (unit assumed: the manual gives none); 0 = off.
    fn heartbeat_limit(&self) -> Option<Duration> {
        let ms = u64::try_from(self.global(GP_SERIAL_HEARTBEAT)).unwrap_or(0);
        (ms > 0).then(|| Duration::from_millis(ms))
    }

    /// GP132: milliseconds since power-up, plus what SGP 132 set, 31 bits.
    fn tick_timer(&self) -> i32 {
        let ms = self.uptime.saturating_sub(self.tick_base).as_millis();
        let ticks = (ms as u32).wrapping_add(self.tick_offset) & 0x7FFF_FFFF;
        i32::try_from(ticks).unwrap_or(0)
    }

    // ---- parameter storage ------------------------------------------

    fn global(&self, number: u8) -> i32 {
        self.eeprom.image.globals.get(&number).copied().unwrap_or(0)
    }

    fn global_u8(&self, number: u8) -> u8 {
        u8::try_from(self.global(number)).unwrap_or(0)
    }
}

/// The motor bit mask of this one-axis module (§3.6.52).
const MOTOR_MASK: i32 = 1;

const GP_SERIAL_HEARTBEAT: u8 = 68;
const GP_HOST_ADDRESS: u8 = 76;
const GP_AUTO_START: u8 = 77;
const GP_IO_MODE: u8 = 78;
const GP_END_SWITCH_POLARITY: u8 = 79;
const GP_CODE_PROTECTION: u8 = 81;
const GP_COORDINATE_STORAGE: u8 = 84;
const GP_DO_NOT_RESTORE_VARIABLES: u8 = 85;
const GP_SECONDARY_ADDRESS: u8 = 87;

/// What the module sends back for one command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Answer {
    Reply {
        status: Status,
        value: i32,
    },
    /// A 9-byte frame of its own layout (136 type 0, 134).
    Special([u8; FRAME_LEN]),
    /// Nothing at all (137).
    Silent,
}

impl Answer {
    fn ok(value: i32) -> Self {
        Answer::Reply {
            status: Status::OK,
            value,
        }
    }

    fn error(status: Status) -> Self {
        Answer::Reply { status, value: 0 }
    }
}

impl From<Result<i32, Status>> for Answer {
    fn from(result: Result<i32, Status>) -> Self {
        match result {
            Ok(value) => Answer::ok(value),
            Err(status) => Answer::error(status),
        }
    }
}

/// Where the simulated machine's switches are, for the help line.
fn describe_layout(layout: &SwitchLayout) -> String {
    let place = |p: Option<i64>| p.map_or_else(|| "none".to_string(), |p| p.to_string());
    let home = layout
        .home
        .map_or_else(|| "none".to_string(), |(from, to)| format!("{from}..{to}"));
    let stops = layout.end_stops.map_or_else(
        || "none".to_string(),
        |(low, high)| format!("{low} and {high}"),
    );
    let wired = if layout.limits_swapped {
        "swapped (the + end closes the left limit input)"
    } else {
        "right"
    };
    format!(
        "left limit at {}, right limit at {}, end switches actuated for {} beyond that, \
         home switch over {}, end stops at {stops} (µsteps); limit switches wired {wired}",
        place(layout.left_limit),
        place(layout.right_limit),
        layout.end_switch_width.max(0),
        home
    )
}

/// The simulator's help line: its defaults where the manual gives none.
pub fn help_line(config: &SimConfig) -> String {
    let motion_choices = motion::MOTION_DEFAULTS
        .iter()
        .filter(|d| !d.from_manual)
        .map(|d| format!("AP{} {}", d.number, d.value));
    let module_choices = defaults::SIM_DEFAULTS.iter().map(|d| {
        let prefix = match d.scope {
            defaults::Scope::Axis => "AP",
            defaults::Scope::Bank0 => "GP",
        };
        format!("{prefix}{} {}", d.number, d.value)
    });
    let chosen: Vec<String> = motion_choices.chain(module_choices).collect();
    format!(
        "TMCM-1110 simulator (firmware {}): address {}, {}, program memory {} commands, \
         {} µs per program command, frame gap {} ms, read-only writes answer {}, \
         GP68 heartbeat in ms, AIN0 digital from {}, StallGuard2 AP206 = |AP3|/2 × (1 − load) \
         + {} × AP174 (load as a fraction of the torque at the actual current; 0 at a stall), \
         CoolStep lower threshold 32 × AP172, upper + 32 × (AP170 + 1), one measurement per {} ms",
        String::from_utf8_lossy(FIRMWARE_VERSION_STRING),
        config.address,
        chosen.join(", "),
        program::PROGRAM_MEMORY_SIZE,
        config
            .instruction_time
            .max(MIN_INSTRUCTION_TIME)
            .as_micros(),
        config.frame_gap.as_millis(),
        config.read_only_write.status().0,
        io::AIN0_DIGITAL_THRESHOLD,
        motion::stallguard::THRESHOLD_STEP,
        motion::TICK.as_millis(),
    )
}

impl SimulatedController for Tmcm1110 {
    fn refused_memory_file(&self) -> Option<String> {
        self.eeprom.refused().map(ToString::to_string)
    }

    fn help(&self) -> String {
        self.help_line()
    }

    fn drive_input(&mut self, setting: &str) -> Result<String, String> {
        Tmcm1110::drive_input(self, setting).map_err(|e| e.to_string())
    }

    fn feed(&mut self, bytes: &[u8]) {
        if bytes.is_empty() {
            return;
        }
        self.silence = Duration::ZERO;
        for frame in self.assembler.push(bytes) {
            self.handle_frame(frame);
            if self.rebooted {
                // Bytes that arrive while the CPU restarts are lost.
                self.rebooted = false;
                break;
            }
        }
    }

    fn advance(&mut self, dt: Duration) {
        if self.assembler.partial_len() > 0 {
            self.silence = self.silence.saturating_add(dt);
            if self.silence >= self.config.frame_gap {
                self.assembler.resync();
                self.silence = Duration::ZERO;
            }
        }
        let mut remaining = dt;
        if let Some(limit) = self.heartbeat_limit()
            && !self.heartbeat_expired
        {
            let until_stop = limit.saturating_sub(self.since_command);
            if until_stop <= remaining {
                // §5.1 GP68: no command within the limit stops the motor.
                self.pass_time(until_stop);
                remaining -= until_stop;
                self.axis.stop();
                self.abandon_move_report();
                self.heartbeat_expired = true;
            }
        }
        self.since_command = self.since_command.saturating_add(dt);
        self.pass_time(remaining);
    }

    fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.output)
    }

    fn arm_faults(&mut self, plan: &crate::sim::faults::FaultPlan) {
        self.store_fault = plan.corrupt_store.map(|nth| StoreFault {
            nth,
            stored: 0,
            record: plan.record.clone(),
        });
    }
}
