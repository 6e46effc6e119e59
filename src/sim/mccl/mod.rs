//! A simulator of the PMC MultiFlex controllers' ASCII command interface
//! (MCCL Reference Manual rev. 3.0): the echo and prompt of the port, the
//! command interpreter with compound lines, macros, background tasks and
//! registers, and up to eight axes (by default 1–4 servo, 5 stepper, as
//! the manual's examples use them) stepped on the trajectory generator's
//! 1 kHz.
//!
//! A plain state machine like the other simulators: bytes in
//! ([`SimulatedController::feed`]), virtual time
//! ([`SimulatedController::advance`]), bytes out
//! ([`SimulatedController::take_output`]). Nothing here sleeps; the only
//! I/O is the MultiFlex ETH's macro file.
//!
//! The command interpreter is this simulator's own reading of the manual
//! (not the host codec of `protocol/mccl`): the two check each other.
//! Where the manual is silent, the choice made is in [`choices::CHOICES`],
//! printed by [`SimulatedController::help`] and docs/mccl.md.
//!
//! Files: [`link`] the port (echo, line editing, prompt, errors);
//! [`lexer`] reading a line; [`commands`] the command table; [`program`]
//! placement rules; [`interpreter`] running sequences (frames, waits,
//! the round robin); [`execute`] the checks every command goes through and
//! the flow, macro and task commands; `exec_setup`, `exec_motion`,
//! `exec_report`, `exec_register` what the other groups do; [`axis`] the
//! axis models (profiles, servo lag, stepper, limits, homing, status
//! words); [`contour`] contour groups; [`io`] channels and the default
//! channel map; [`registers`] shared registers, scratch pad, motor-table
//! variables; [`values`] register values and number formats; [`printf`]
//! OT/OD; [`macros`] macro memory and the ETH file; [`tasks`] background
//! tasks; [`text`] VE, ID and HE; [`choices`] what the manual leaves open;
//! [`inputs`] what can be driven from outside.

pub mod axis;
pub mod choices;
pub mod commands;
mod contour;
pub mod errors;
mod exec_motion;
mod exec_register;
mod exec_report;
mod exec_setup;
mod execute;
pub mod inputs;
mod interpreter;
pub mod io;
pub mod lexer;
pub mod link;
pub mod macros;
mod printf;
mod program;
mod registers;
pub mod stage;
mod tasks;
mod text;
pub mod values;

#[cfg(test)]
mod tests;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use super::SimulatedController;
use super::faults::{FaultPlan, FaultRecord};
use axis::settings::AxisKind;
use axis::{Axis, AxisInputs};
use contour::Contours;
use errors::Code;
use interpreter::{Interpreter, SliceEnd};
use io::Io;
use lexer::{Command, Param, lex};
use link::{Activity, Keyed, Link, LinkProfile, PromptGranularity};
use macros::MacroStore;
use program::{Origin, Program};
use registers::{Registers, Scratch};
use tasks::Tasks;

/// The simulator as `--sim mccl` names it. MultiFlex PCI and ETH differ
/// in one thing the host can see: the ETH keeps its macros (non-volatile,
/// `--eeprom FILE`), the PCI loses them at a reset. Two kinds of one
/// family, as the two products are.
pub const KIND_PCI: super::SimKind = super::SimKind {
    name: "mccl",
    description: "PMC MultiFlex PCI (MCCL ASCII, axes 1-4 servo, 5 stepper; volatile macros)",
    build: |_| Box::new(Mccl::new(SimConfig::pci())),
    input_names: || super::inputs::names(inputs::INPUTS),
    input_help: || super::inputs::help_lines(inputs::INPUTS),
    eeprom_refusal: Some(PCI_KEEPS_NOTHING),
};

/// The simulator as `--sim mccl-eth` names it (see [`KIND_PCI`]).
pub const KIND_ETH: super::SimKind = super::SimKind {
    name: "mccl-eth",
    description: "PMC MultiFlex ETH (MCCL ASCII, axes 1-4 servo, 5 stepper; macros kept in --eeprom FILE)",
    build: |options| Box::new(Mccl::new(SimConfig::eth(options.eeprom_file.clone()))),
    input_names: || super::inputs::names(inputs::INPUTS),
    input_help: || super::inputs::help_lines(inputs::INPUTS),
    eeprom_refusal: None,
};

pub use link::{Eol, ErrorText};

/// Why `axterm sim mccl --eeprom FILE` is refused: the MultiFlex PCI keeps
/// its macros in volatile memory, lost at a reset; the ETH keeps them
/// (the `mccl-eth` kind).
pub const PCI_KEEPS_NOTHING: &str = "a MultiFlex PCI keeps its macros in volatile memory, \
     lost at every reset; simulate a MultiFlex ETH (mccl-eth) to keep them in a file";

/// The trajectory generator's period (Ch7 BC: "executes every
/// milisecond").
pub const TICK: Duration = Duration::from_millis(1);
const TICK_SECONDS: f64 = 0.001;

/// Background tasks switch every 250 µs (Ch4 "MCCL Multi-Tasking"): four
/// slices a tick, each running up to this many commands of one
/// interpreter (the manual gives no command time).
pub const SLICES_PER_TICK: usize = 4;
pub const COMMANDS_PER_SLICE: usize = 10;

/// The two MultiFlex families (Ch4 "Building MCCL Macro Sequences").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Model {
    /// MultiFlex PCI: "all controller memory is volatile", macros are
    /// lost at a reset.
    Pci,
    /// MultiFlex ETH: macros kept in non-volatile memory until RM.
    Eth,
}

/// How the simulated controller is set up.
#[derive(Debug, Clone)]
pub struct SimConfig {
    pub model: Model,
    /// The axes 1… and their kinds (at most 8).
    pub axes: Vec<AxisKind>,
    pub link: LinkProfile,
    /// ETH only: the file holding the non-volatile macros (`--eeprom`).
    pub macro_file: Option<PathBuf>,
}

impl SimConfig {
    /// The manual's machine: axes 1–4 servo, axis 5 stepper.
    pub fn default_axes() -> Vec<AxisKind> {
        let mut axes = vec![AxisKind::Servo; 4];
        axes.push(AxisKind::Stepper);
        axes
    }

    pub fn pci() -> SimConfig {
        SimConfig {
            model: Model::Pci,
            axes: SimConfig::default_axes(),
            link: LinkProfile::default(),
            macro_file: None,
        }
    }

    pub fn eth(macro_file: Option<PathBuf>) -> SimConfig {
        SimConfig {
            model: Model::Eth,
            macro_file,
            ..SimConfig::pci()
        }
    }
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig::pci()
    }
}

/// The `corrupt-store=N` fault: the N-th macro stored on this connection
/// keeps one parameter changed, and the reply says all is well.
#[derive(Debug, Clone)]
struct StoreFault {
    nth: u64,
    stored: u64,
    record: FaultRecord,
}

/// The simulated MultiFlex controller.
pub struct Mccl {
    config: SimConfig,
    axes: Vec<Axis>,
    io: Io,
    registers: Registers,
    scratch: Scratch,
    macros: MacroStore,
    tasks: Tasks,
    foreground: Interpreter,
    link: Link,
    /// Point memory (LP/LT/MP): 256 points of every axis, counts.
    points: Vec<Vec<Option<f64>>>,
    contours: Contours,
    /// Time not yet ticked.
    clock: Duration,
    /// Ticks since power-up.
    ticks: u64,
    /// Whose turn it is in the round-robin (0 the foreground).
    turn: usize,
    store_fault: Option<StoreFault>,
    /// The demo stage, off until `LIMITS=` (see [`stage`]).
    stage: Option<stage::Stage>,
}

impl Mccl {
    pub fn new(config: SimConfig) -> Mccl {
        let axes = config
            .axes
            .iter()
            .take(8)
            .zip(1..)
            .map(|(&kind, n)| Axis::new(n, kind))
            .collect::<Vec<_>>();
        let file = match config.model {
            Model::Eth => config.macro_file.clone(),
            Model::Pci => None,
        };
        let count = axes.len();
        Mccl {
            macros: MacroStore::open(file),
            axes,
            io: Io::default(),
            registers: Registers::default(),
            scratch: Scratch::default(),
            tasks: Tasks::default(),
            foreground: Interpreter::foreground(),
            link: Link::new(config.link),
            points: vec![vec![None; count]; 256],
            contours: Contours::default(),
            clock: Duration::ZERO,
            ticks: 0,
            turn: 0,
            store_fault: None,
            stage: None,
            config,
        }
    }

    pub fn model(&self) -> Model {
        self.config.model
    }

    /// Axis `n` (1-based), for tests and demos.
    pub fn axis(&self, n: u8) -> Option<&Axis> {
        self.axes.get(usize::from(n).checked_sub(1)?)
    }

    pub fn axis_mut(&mut self, n: u8) -> Option<&mut Axis> {
        self.axes.get_mut(usize::from(n).checked_sub(1)?)
    }

    pub fn io(&self) -> &Io {
        &self.io
    }

    pub fn macros(&self) -> &MacroStore {
        &self.macros
    }

    /// How many background tasks run.
    pub fn task_count(&self) -> usize {
        self.tasks.len()
    }

    /// The port's wire form now.
    pub fn link_profile(&self) -> LinkProfile {
        self.link.profile
    }

    pub fn set_link_profile(&mut self, profile: LinkProfile) {
        self.link.profile = profile;
    }

    /// A line is running on the port (the host must wait for the prompt).
    pub fn busy(&self) -> bool {
        self.link.running()
    }

    /// RT with no axis: every axis, register, task and port setting back to
    /// power-up; on a PCI the macros go too (volatile), on an ETH they stay.
    /// The wiring of the inputs stays.
    pub fn reset(&mut self) {
        for axis in &mut self.axes {
            axis.reset();
        }
        self.io.reset();
        self.registers = Registers::default();
        self.scratch = Scratch::default();
        self.tasks = Tasks::default();
        self.foreground = Interpreter::foreground();
        self.link.reset();
        self.points = vec![vec![None; self.axes.len()]; 256];
        self.contours = Contours::default();
        if self.config.model == Model::Pci {
            self.macros.clear();
        }
    }

    // ---- the port --------------------------------------------------

    fn receive(&mut self, byte: u8) {
        match self.link.key(byte) {
            Keyed::Nothing | Keyed::Pause | Keyed::Resume => {}
            Keyed::EmptyLine => self.link.send_prompt(),
            Keyed::TooLong(_) => self.line_failed(Code::TOO_LONG, ""),
            Keyed::Line(line) => self.start_line(&line),
            Keyed::Abort => {
                let command = self.foreground.current_text();
                self.foreground.stop();
                self.line_failed(Code::CANCELED, &command);
            }
            Keyed::StartStepping => self.show_step(),
            Keyed::StepOnce => self.run_foreground(1),
            Keyed::EndStepping => {}
        }
    }

    /// A line arrived: read it, store a macro, spawn a `GT0` task, or run it.
    fn start_line(&mut self, bytes: &[u8]) {
        // Line noise: bytes that are no 7-bit text (error 3, "I/O error").
        if bytes
            .iter()
            .any(|&b| !(b.is_ascii_graphic() || b == b' ' || b == b'\t'))
        {
            let text = String::from_utf8_lossy(bytes).into_owned();
            self.line_failed(Code::IO_ERROR, text.trim());
            return;
        }
        let text = String::from_utf8_lossy(bytes).into_owned();
        let commands = match lex(&text, self.link.radix) {
            Ok(commands) => commands,
            Err(e) => return self.line_failed(e.code, &e.command),
        };
        let first = &commands[0];
        if first.is("MD") {
            let result = self.define_macro(first, &commands[1..]);
            return self.line_done(result, first);
        }
        if first.is("GT") && matches!(first.param, Param::None | Param::Int(0)) {
            let body = commands[1..].to_vec();
            let result = self.spawn_line_task(body);
            return self.line_done(result, first);
        }
        if let Err(m) = program::check(&commands, false) {
            let text = commands[m.at].text.clone();
            return self.line_failed(m.code, &text);
        }
        self.foreground.begin(Program::new(commands, Origin::Line));
        self.link.activity = Activity::Running;
        self.run_foreground(COMMANDS_PER_SLICE);
    }

    fn line_done(&mut self, result: Result<(), Code>, command: &Command) {
        match result {
            Ok(()) => self.link.send_prompt(),
            Err(code) => self.line_failed(code, &command.text),
        }
    }

    /// Report an error of the foreground and end its line.
    fn line_failed(&mut self, code: Code, command: &str) {
        self.foreground.stop();
        self.link.activity = Activity::Typing;
        self.link.error(code, command);
        self.link.send_prompt();
    }

    /// MD n,…: store the rest of the line as macro n.
    fn define_macro(&mut self, define: &Command, body: &[Command]) -> Result<(), Code> {
        let number = self.macro_number(&self.foreground, &define.param)?;
        if let Err(m) = program::check(body, true) {
            return Err(m.code);
        }
        let mut body = body.to_vec();
        if let Some(fault) = &mut self.store_fault {
            fault.stored += 1;
            if fault.stored == fault.nth && macros::corrupt(&mut body) {
                fault.record.note_corrupted_store();
            }
        }
        self.macros
            .define(number, body, self.link.radix == lexer::Radix::Hex)
    }

    /// Run the foreground for up to `budget` commands, and end its line if
    /// it is done.
    fn run_foreground(&mut self, budget: usize) {
        if !self.link.running() {
            return;
        }
        let mut foreground = std::mem::take(&mut self.foreground);
        let end = self.run_slice(&mut foreground, budget);
        self.foreground = foreground;
        match end {
            SliceEnd::Finished => {
                self.link.activity = Activity::Typing;
                if self.link.profile.prompts == PromptGranularity::Line {
                    self.link.send_prompt();
                }
            }
            SliceEnd::Failed { code, command } => self.line_failed(code, &command),
            SliceEnd::Stepping => {
                self.link.activity = Activity::Stepping;
                self.show_step();
            }
            SliceEnd::Budget | SliceEnd::Waiting | SliceEnd::EndTask => {
                if self.link.activity == Activity::Stepping {
                    self.show_step();
                }
            }
        }
    }

    /// The single-step display (Ch4): `{C<n>,M<m>} <next command> <`.
    fn show_step(&mut self) {
        if let Some(line) = self.foreground.step_display() {
            self.link.write(line.as_bytes());
        }
    }

    // ---- time --------------------------------------------------------

    fn tick(&mut self) {
        self.ticks += 1;
        self.link.drain(TICK_SECONDS);
        self.motion_tick();
        self.schedule();
    }

    /// The interpreters' share of this tick: four 250 µs slices, round
    /// robin over the foreground and the tasks that are not waiting.
    fn schedule(&mut self) {
        let mut slices = SLICES_PER_TICK;
        let mut tried = 0;
        while slices > 0 && tried <= self.tasks.len() {
            let count = self.tasks.len() + 1;
            let who = self.turn % count;
            self.turn = (who + 1) % count;
            let ran = if who == 0 {
                self.foreground_slice()
            } else {
                self.task_slice(who - 1)
            };
            if ran {
                slices -= 1;
                tried = 0;
            } else {
                tried += 1;
            }
        }
    }

    /// A slice of the foreground if it can run: `true` if it used one.
    fn foreground_slice(&mut self) -> bool {
        // Paused or single stepping, it runs only when a key says so.
        if self.link.activity != Activity::Running || !self.wait_over_foreground() {
            return false;
        }
        self.run_foreground(COMMANDS_PER_SLICE);
        true
    }

    fn wait_over_foreground(&mut self) -> bool {
        let mut foreground = std::mem::take(&mut self.foreground);
        let ready = self.ready(&mut foreground);
        self.foreground = foreground;
        ready
    }

    fn task_slice(&mut self, index: usize) -> bool {
        let Some(mut task) = self.tasks.take(index) else {
            return false;
        };
        if !self.ready(&mut task) {
            self.tasks.put_back(task);
            return false;
        }
        let end = self.run_slice(&mut task, COMMANDS_PER_SLICE);
        match end {
            SliceEnd::Budget | SliceEnd::Waiting => self.tasks.put_back(task),
            // A task ends at its last command, BK, ET of itself, or an
            // error (reported nowhere: a task has no port).
            _ => {
                if let Some(id) = task.task {
                    self.tasks.end(id);
                }
            }
        }
        true
    }

    // ---- inputs ------------------------------------------------------

    /// Put every axis on the demo stage (`Some`) or take it away.
    pub fn set_stage(&mut self, stage: Option<stage::Stage>) {
        self.stage = stage;
        let stops = stage.map(|s| s.end_stops());
        for axis in &mut self.axes {
            axis.end_stops = stops;
            axis.hold_at_end_stop();
        }
    }

    /// The logical inputs of axis `n` (1-based) now.
    pub fn axis_inputs(&self, n: u8) -> AxisInputs {
        let Some(channels) = io::channels_of(n) else {
            return AxisInputs::default();
        };
        let inverted = self
            .axis(n)
            .is_some_and(|a| a.settings.hard_limits_inverted());
        let closed = match (self.stage, self.axis(n)) {
            (Some(stage), Some(axis)) => stage.switches(axis.shaft),
            _ => stage::Switches::default(),
        };
        // A stage switch conducts like a level driven from outside; the
        // channel's polarity (CH/CL) reads it.
        let on = |channel: u8, closed: bool| {
            (self.io.level(channel) || closed) != self.io.is_low_true(channel)
        };
        AxisInputs {
            limit_plus: on(channels.limit_plus, closed.limit_plus) != inverted,
            limit_minus: on(channels.limit_minus, closed.limit_minus) != inverted,
            home: on(channels.home, closed.home),
            fault: self.io.is_on(channels.fault),
            capture: self.io.is_on(channels.capture),
        }
    }

    /// Help: what is simulated and every choice made where the manual is
    /// silent.
    pub fn help_line(&self) -> String {
        let kinds: Vec<String> = self
            .axes
            .iter()
            .map(|a| {
                format!(
                    "{} {}",
                    a.number,
                    match a.kind {
                        AxisKind::Servo => "servo",
                        AxisKind::Stepper => "stepper",
                    }
                )
            })
            .collect();
        let model = match self.config.model {
            Model::Pci => {
                "MultiFlex PCI simulator (MCCL ASCII): volatile memory, macros lost at RT; \
                 --eeprom is not used (the ETH kind, mccl-eth, keeps macros)"
                    .to_string()
            }
            Model::Eth => match (&self.config.macro_file, self.macros.problem()) {
                (Some(_), Some(problem)) => {
                    format!("MultiFlex ETH simulator (MCCL ASCII): non-volatile macros; {problem}")
                }
                (Some(path), None) => format!(
                    "MultiFlex ETH simulator (MCCL ASCII): non-volatile macros kept in {}",
                    path.display()
                ),
                (None, _) => "MultiFlex ETH simulator (MCCL ASCII): non-volatile macros \
                              (kept across RT; give --eeprom FILE to keep them between runs)"
                    .to_string(),
            },
        };
        format!(
            "{model}; axes {}; choices where the manual is silent: {}; \
             inputs driven from outside (--input, a line on the standard input of `axterm sim`, :sim-input): {}",
            kinds.join(", "),
            choices::summary(),
            super::inputs::summary(inputs::INPUTS),
        )
    }
}

impl SimulatedController for Mccl {
    fn refused_memory_file(&self) -> Option<String> {
        self.macros.refused().map(ToString::to_string)
    }

    fn feed(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.receive(byte);
        }
    }

    fn advance(&mut self, dt: Duration) {
        self.clock += dt;
        while self.clock >= TICK {
            self.clock -= TICK;
            self.tick();
        }
    }

    fn take_output(&mut self) -> Vec<u8> {
        self.link.take_output()
    }

    fn help(&self) -> String {
        self.help_line()
    }

    fn arm_faults(&mut self, plan: &FaultPlan) {
        self.store_fault = plan.corrupt_store.map(|nth| StoreFault {
            nth,
            stored: 0,
            record: plan.record.clone(),
        });
    }

    /// The port sends at the line's rate: a Tell waits for room in the
    /// transmit buffer at that rate, so a line of Tells runs for as long as
    /// its answer takes on the wire (and Escape can cut it short).
    fn line_byte_time(&mut self, byte_time: Option<Duration>) {
        if let Some(each) = byte_time.filter(|t| !t.is_zero()) {
            self.link.profile.output_rate = 1.0 / each.as_secs_f64();
        }
    }

    fn drive_input(&mut self, setting: &str) -> Result<String, String> {
        Mccl::drive_input(self, setting).map_err(|e| e.to_string())
    }
}

/// The shared program a macro number names, for the interpreter.
fn macro_program(macros: &MacroStore, n: u16) -> Option<Arc<Program>> {
    macros.get(n).map(|m| m.program.clone())
}
