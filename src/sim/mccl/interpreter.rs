//! Running command sequences (manual Ch2, Ch10, Ch12): the foreground
//! interpreter of the port and each background task are an
//! [`Interpreter`] — a stack of sequences being run (a line, the macros it
//! called), its own R0–R9, default axis (UA) and time unit (UT), and what
//! it waits for. [`super::Mccl::run_slice`] runs one for a few commands.
//!
//! The rules, as the manual gives them:
//! - the axis of a command is the last one given earlier in the same line
//!   or macro; none given yet is the default axis (UA, 0 = all) (Ch2);
//! - a conditional (IB IC IE IF IG IN IS IU) true goes on with the next
//!   command; false skips two and goes on at the third (Ch12); DF/DN false
//!   skip the rest of the line or macro;
//! - JP n jumps to command n (0-based) of the line or macro, JR n by n
//!   from itself (JR0 is itself);
//! - RP n runs everything before it n + 1 times, forever for 0;
//! - BK ends the line or macro (a called macro returns; a task ends);
//! - MC calls (returns after), MJ jumps (no return), HO calls macro a.
//!
//! Choices (also in [`super::choices`]): a called macro starts without an
//! axis (its commands use the ones they give, else UA); commands after RP
//! run once after the last repetition; calls nest 32 deep (deeper is −18).

use std::sync::Arc;

use super::Mccl;
use super::errors::Code;
use super::lexer::{Command, Param};
use super::link::PromptGranularity;
use super::program::{Origin, Program};
use super::registers::LOCAL_REGISTERS;
use super::values::Value;

/// How deep macro calls nest before −18.
pub const MOST_NESTED: usize = 32;

/// RP's count in a running sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Repeat {
    Forever,
    Left(u64),
}

/// One sequence being run.
#[derive(Debug, Clone)]
pub struct Frame {
    pub program: Arc<Program>,
    pub pc: usize,
    /// The last axis given in this sequence, if any yet.
    pub axis: Option<u32>,
    pub repeat: Option<Repeat>,
}

impl Frame {
    fn new(program: Arc<Program>) -> Frame {
        Frame {
            program,
            pc: 0,
            axis: None,
            repeat: None,
        }
    }
}

/// What an interpreter waits for before its next command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Wait {
    /// The tick count (WA, and the dwell of WS / WT).
    Until(u64),
    /// WS: trajectory complete on axis n (0 all), then `dwell` seconds.
    Stopped {
        axis: u8,
        dwell: f64,
        errors_before: u32,
    },
    /// WT: at target, then `dwell` seconds.
    AtTarget {
        axis: u8,
        dwell: f64,
        errors_before: u32,
    },
    /// WP / WR: the breakpoint (status bit 6).
    Breakpoint { axis: u8 },
    /// WN / WF.
    Channel { channel: u8, on: bool },
    /// FI / FE / WI / WE: the capture, then kept for MN.
    Capture { axis: u8 },
    /// The port's transmit buffer is full.
    Transmit,
}

/// What a command does to the flow of its sequence.
#[derive(Debug, Clone)]
pub enum Flow {
    Next,
    Jump(usize),
    /// Skip this many commands after this one.
    Skip(usize),
    /// The rest of the sequence is skipped (BK, DF/DN false).
    EndFrame,
    Call(Arc<Program>),
    Replace(Arc<Program>),
    /// Go on with the next command once the wait is over.
    Wait(Wait),
    /// Run this command again once the wait is over.
    Retry(Wait),
    /// ET of the task itself.
    EndTask,
    /// BK"text": go on single stepping.
    Break,
}

/// How a slice of an interpreter ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SliceEnd {
    /// Its commands for this slice ran.
    Budget,
    Waiting,
    /// Nothing left to run.
    Finished,
    Failed {
        code: Code,
        command: String,
    },
    EndTask,
    /// BK"text" turned single stepping on.
    Stepping,
}

/// A foreground interpreter or a task.
#[derive(Debug, Clone)]
pub struct Interpreter {
    pub frames: Vec<Frame>,
    /// R0 (the accumulator) to R9.
    pub locals: [Value; LOCAL_REGISTERS],
    /// UA.
    pub default_axis: u8,
    /// UT: seconds per dwell unit.
    pub user_time: f64,
    pub wait: Option<Wait>,
    /// The command that is waiting, as an error would name it.
    pub waiting_command: String,
    /// NP.
    pub priority: u8,
    /// The task ID; `None` for the foreground.
    pub task: Option<i32>,
}

impl Default for Interpreter {
    fn default() -> Self {
        Interpreter::foreground()
    }
}

/// NP's default (Ch10: "By default all MultiFlex tasks are issued with
/// priority of 100").
pub const DEFAULT_PRIORITY: u8 = 100;

impl Interpreter {
    pub fn foreground() -> Interpreter {
        Interpreter {
            frames: Vec::new(),
            locals: [Value::Int(0); LOCAL_REGISTERS],
            default_axis: 0,
            user_time: 1.0,
            wait: None,
            waiting_command: String::new(),
            priority: DEFAULT_PRIORITY,
            task: None,
        }
    }

    /// A task running `program`, with the parent's UA (so a generic macro
    /// runs on the axis the parent chose) and its ID in R0.
    pub fn task(id: i32, program: Arc<Program>, default_axis: u8) -> Interpreter {
        let mut task = Interpreter::foreground();
        task.task = Some(id);
        task.default_axis = default_axis;
        task.locals[0] = Value::Int(id);
        task.begin(program);
        task
    }

    pub fn begin(&mut self, program: Arc<Program>) {
        self.frames = vec![Frame::new(program)];
        self.wait = None;
    }

    /// Abandon whatever runs.
    pub fn stop(&mut self) {
        self.frames.clear();
        self.wait = None;
    }

    pub fn accumulator(&self) -> Value {
        self.locals[0]
    }

    pub fn set_accumulator(&mut self, value: Value) {
        self.locals[0] = value;
    }

    /// The command running or next to run, as an error names it.
    pub fn current_text(&self) -> String {
        if self.wait.is_some() {
            return self.waiting_command.clone();
        }
        self.frames
            .last()
            .and_then(|f| f.program.commands.get(f.pc))
            .map(|c| c.text.clone())
            .unwrap_or_default()
    }

    /// The single-step display (Ch4): `{C<index>,M<macro>} <command> <`,
    /// RP marked `[REPEAT]`; `{C<index>}` in a typed line.
    pub fn step_display(&self) -> Option<String> {
        let frame = self.frames.last()?;
        let command = frame.program.commands.get(frame.pc)?;
        let place = match frame.program.origin {
            Origin::Macro(n) => format!("{{C{},M{n}}}", frame.pc),
            Origin::Line => format!("{{C{}}}", frame.pc),
        };
        let repeat = if command.is("RP") { " [REPEAT]" } else { "" };
        Some(format!("{place} {}{repeat} <", command.text))
    }

    /// The axis a command acts on: the one it gives, else the last given
    /// in its sequence, else UA.
    pub fn axis_for(&mut self, command: &Command) -> u32 {
        let frame = self.frames.last_mut();
        match (command.axis, frame) {
            (Some(axis), Some(frame)) => {
                frame.axis = Some(axis);
                axis
            }
            (Some(axis), None) => axis,
            (
                None,
                Some(Frame {
                    axis: Some(axis), ..
                }),
            ) => *axis,
            (None, _) => u32::from(self.default_axis),
        }
    }
}

impl Mccl {
    /// Run `interp` for up to `budget` commands.
    pub(super) fn run_slice(&mut self, interp: &mut Interpreter, budget: usize) -> SliceEnd {
        for _ in 0..budget {
            if interp.wait.is_some() {
                match self.poll_wait(interp) {
                    WaitState::Pending => return SliceEnd::Waiting,
                    WaitState::Failed(code) => {
                        return SliceEnd::Failed {
                            code,
                            command: std::mem::take(&mut interp.waiting_command),
                        };
                    }
                    WaitState::Over => {
                        interp.wait = None;
                        self.command_done(interp);
                    }
                }
            }
            // Sequences that ran out return to their caller.
            loop {
                let Some(frame) = interp.frames.last() else {
                    return SliceEnd::Finished;
                };
                if frame.pc < frame.program.commands.len() {
                    break;
                }
                interp.frames.pop();
                // A called macro returned: the command that called it is done.
                if !interp.frames.is_empty() {
                    self.command_done(interp);
                }
            }
            let Some(frame) = interp.frames.last() else {
                return SliceEnd::Finished;
            };
            let program = frame.program.clone();
            let command = &program.commands[frame.pc];
            let flow = match self.execute(interp, command) {
                Ok(flow) => flow,
                Err(code) => {
                    return SliceEnd::Failed {
                        code,
                        command: command.text.clone(),
                    };
                }
            };
            let Some(frame) = interp.frames.last_mut() else {
                return SliceEnd::Finished;
            };
            match flow {
                Flow::Next => frame.pc += 1,
                Flow::Jump(to) => frame.pc = to,
                Flow::Skip(n) => frame.pc += 1 + n,
                Flow::EndFrame => {
                    interp.frames.pop();
                }
                Flow::Call(called) => {
                    frame.pc += 1;
                    interp.frames.push(Frame::new(called));
                    continue;
                }
                Flow::Replace(jumped) => {
                    interp.frames.pop();
                    interp.frames.push(Frame::new(jumped));
                    continue;
                }
                Flow::Wait(wait) => {
                    frame.pc += 1;
                    interp.wait = Some(wait);
                    interp.waiting_command = command.text.clone();
                    continue;
                }
                Flow::Retry(wait) => {
                    interp.wait = Some(wait);
                    interp.waiting_command = command.text.clone();
                    continue;
                }
                Flow::EndTask => return SliceEnd::EndTask,
                Flow::Break => {
                    frame.pc += 1;
                    return SliceEnd::Stepping;
                }
            }
            self.command_done(interp);
        }
        SliceEnd::Budget
    }

    /// A command of the foreground's line finished: with prompts per
    /// command, the prompt.
    fn command_done(&mut self, interp: &Interpreter) {
        if interp.task.is_none()
            && interp.frames.len() <= 1
            && self.link.profile.prompts == PromptGranularity::Command
        {
            self.link.send_prompt();
        }
    }

    // ---- flow commands (Ch10, Ch12) -----------------------------------

    /// The register an `@n` parameter or AR/RA/TR names.
    pub(super) fn register(&self, interp: &Interpreter, n: u32) -> Option<Value> {
        let n = usize::try_from(n).ok()?;
        if n < LOCAL_REGISTERS {
            Some(interp.locals[n])
        } else {
            self.registers.get(n)
        }
    }

    pub(super) fn set_register(&mut self, interp: &mut Interpreter, n: u32, value: Value) -> bool {
        let Ok(n) = usize::try_from(n) else {
            return false;
        };
        if n < LOCAL_REGISTERS {
            interp.locals[n] = value;
            true
        } else {
            self.registers.set(n, value)
        }
    }

    /// A macro number parameter: 0–999 (−5 outside).
    pub(super) fn macro_number(&self, interp: &Interpreter, param: &Param) -> Result<u16, Code> {
        let n = match param {
            Param::None => 0,
            Param::Int(n) => *n,
            Param::Register(r) => {
                i64::from(self.register(interp, *r).ok_or(Code::PARAMETER)?.rounded())
            }
            Param::Real(_) => return Err(Code::PARAMETER),
            Param::Text(_) => return Err(Code::BAD_FORMAT),
        };
        u16::try_from(n)
            .ok()
            .filter(|&n| n <= 999)
            .ok_or(Code::MACRO_OUT_OF_RANGE)
    }

    /// The sequence of macro `n` (−6 if there is none).
    pub(super) fn macro_sequence(&self, n: u16) -> Result<Arc<Program>, Code> {
        super::macro_program(&self.macros, n).ok_or(Code::MACRO_MISSING)
    }

    /// MC, MJ, HO, GT: the macro to run.
    pub(super) fn call(&self, interp: &Interpreter, n: u16) -> Result<Arc<Program>, Code> {
        if interp.frames.len() >= MOST_NESTED {
            return Err(Code::NO_MEMORY);
        }
        self.macro_sequence(n)
    }

    /// RP n.
    pub(super) fn repeat(&mut self, interp: &mut Interpreter, n: i64) -> Result<Flow, Code> {
        if n < 0 {
            return Err(Code::NEGATIVE_REPEAT);
        }
        let Some(frame) = interp.frames.last_mut() else {
            return Ok(Flow::Next);
        };
        let repeat = frame.repeat.unwrap_or(if n == 0 {
            Repeat::Forever
        } else {
            Repeat::Left(n.unsigned_abs())
        });
        match repeat {
            Repeat::Forever => {
                frame.repeat = Some(Repeat::Forever);
                Ok(Flow::Jump(0))
            }
            Repeat::Left(0) => {
                frame.repeat = None;
                Ok(Flow::Next)
            }
            Repeat::Left(left) => {
                frame.repeat = Some(Repeat::Left(left - 1));
                Ok(Flow::Jump(0))
            }
        }
    }

    /// JP n (absolute) or JR n (relative to itself).
    pub(super) fn jump(interp: &Interpreter, n: i64, relative: bool) -> Result<Flow, Code> {
        let Some(frame) = interp.frames.last() else {
            return Ok(Flow::Next);
        };
        let to = if relative { frame.pc as i64 + n } else { n };
        let len = frame.program.commands.len() as i64;
        if !(0..=len).contains(&to) {
            return Err(Code::PARAMETER);
        }
        Ok(Flow::Jump(usize::try_from(to).unwrap_or(0)))
    }

    /// Ticks a dwell of `n` dwell units lasts.
    pub(super) fn dwell_until(&self, interp: &Interpreter, n: f64) -> u64 {
        let seconds = (n * interp.user_time).max(0.0);
        self.ticks + (seconds * 1000.0 - 1e-9).ceil().max(0.0) as u64
    }

    fn poll_wait(&mut self, interp: &mut Interpreter) -> WaitState {
        let Some(wait) = interp.wait else {
            return WaitState::Over;
        };
        match wait {
            Wait::Until(tick) => WaitState::over_if(self.ticks >= tick),
            Wait::Stopped {
                axis,
                dwell,
                errors_before,
            } => {
                if let Some(code) = self.new_axis_error(axis, errors_before) {
                    return WaitState::Failed(code);
                }
                if !self.axes_stopped(axis) {
                    return WaitState::Pending;
                }
                self.then_dwell(interp, dwell)
            }
            Wait::AtTarget {
                axis,
                dwell,
                errors_before,
            } => {
                if let Some(code) = self.new_axis_error(axis, errors_before) {
                    return WaitState::Failed(code);
                }
                if !self.axis(axis).is_some_and(|a| a.at_target()) {
                    return WaitState::Pending;
                }
                self.then_dwell(interp, dwell)
            }
            Wait::Breakpoint { axis } => WaitState::over_if(
                self.axis(axis)
                    .is_some_and(|a| a.latched & super::axis::status::BREAKPOINT != 0),
            ),
            Wait::Channel { channel, on } => WaitState::over_if(self.io.is_on(channel) == on),
            Wait::Capture { axis } => {
                let Some(a) = self.axis_mut(axis) else {
                    return WaitState::Over;
                };
                if a.homing.captured.is_some() {
                    a.store_capture();
                    WaitState::Over
                } else {
                    WaitState::Pending
                }
            }
            Wait::Transmit => WaitState::over_if(!self.link.congested()),
        }
    }

    /// After WS/WT's condition: the dwell, if any.
    fn then_dwell(&self, interp: &mut Interpreter, dwell: f64) -> WaitState {
        if dwell > 0.0 {
            interp.wait = Some(Wait::Until(self.dwell_until(interp, dwell)));
            WaitState::Pending
        } else {
            WaitState::Over
        }
    }

    /// Axis `n` (0 every axis) has the trajectory complete.
    pub(super) fn axes_stopped(&self, n: u8) -> bool {
        if n == 0 {
            self.axes.iter().all(|a| a.trajectory_complete())
        } else {
            self.axis(n).is_none_or(|a| a.trajectory_complete())
        }
    }

    /// The error bits (motor error, amp fault) of axis n (0 all) now, to
    /// tell a trip during a wait from one before it.
    pub(super) fn axis_errors(&self, n: u8) -> u32 {
        use super::axis::status::{AMP_FAULT, MOTOR_ERROR};
        self.axes
            .iter()
            .filter(|a| n == 0 || a.number == n)
            .fold(0, |bits, a| {
                let k = 2 * u32::from(a.number.saturating_sub(1));
                bits | u32::from(a.latched & MOTOR_ERROR != 0) << k
                    | u32::from(a.latched & AMP_FAULT != 0) << (k + 1)
            })
    }

    /// −13 if an axis waited on tripped since the wait began (Ch14 "Axis
    /// error (over travel error, max. following error exceeded)").
    fn new_axis_error(&self, n: u8, before: u32) -> Option<Code> {
        let now = self.axis_errors(n);
        (now & !before != 0).then_some(Code::AXIS_ERROR)
    }

    /// The interpreter may run now: no wait, or its wait is over (a task
    /// waiting gets no CPU, Ch4).
    pub(super) fn ready(&mut self, interp: &mut Interpreter) -> bool {
        if interp.frames.is_empty() && interp.wait.is_none() {
            return interp.task.is_none();
        }
        if interp.wait.is_none() {
            return true;
        }
        match self.poll_wait(interp) {
            WaitState::Pending => false,
            WaitState::Over => {
                interp.wait = None;
                self.command_done(interp);
                true
            }
            // The slice polls again and reports it.
            WaitState::Failed(_) => true,
        }
    }
}

/// Where a wait stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum WaitState {
    Pending,
    Over,
    Failed(Code),
}

impl WaitState {
    fn over_if(done: bool) -> WaitState {
        if done {
            WaitState::Over
        } else {
            WaitState::Pending
        }
    }
}
