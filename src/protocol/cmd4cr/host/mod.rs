//! An A-Script program run from the host (CMD-4CR §2.7, §5), for real
//! hardware: the manual documents no wire format for loading programs
//! into the controller (§2.7.7, §5.1.5 send the user to NPA's Windows
//! utility), so a program written here runs on this side of the cable
//! instead. Each statement that acts becomes the ASCII command of the same
//! meaning ([`ascript::ascii_equivalent`], the translation the simulator's
//! interpreter uses too), sent through the session like a typed line
//! (parsed, validated, at user priority, so the emergency stop goes
//! first); variables, control flow, `GOSUB`, `DELAY` and `SR` stay here;
//! `WAIT[axis]` reads `MST[axis]` until the motion is complete.
//!
//! [`HostProgram::check`] checks the whole source before anything is sent:
//! the compile errors of Table 5-43 and the statements that have no ASCII
//! equivalent ([`ascript::Program::host_problems`]), each as `FILE:LINE:`.
//! [`AScriptRun`] is the run itself as a plain state machine (no I/O, no
//! clock of its own): it says what to send or how long to wait
//! ([`HostStep`]) and is told the answers, so the console drives it
//! through its panes' requests and `Session::run_from_host` drives it
//! directly. Dropping it ends the run: nothing more is sent.
//!
//! Choices where the manual is silent (the simulator's interpreter makes
//! the same ones, so that a program does the same in both):
//! - Every PRG block of the file starts, unless told which: the manual's
//!   multi-thread examples (§5.4.8–§5.4.10) are written to run together,
//!   and §2.7.3 runs the four programs "simultaneously". A PRG not started
//!   can still be started by `SR[n]=1` from one that runs.
//! - The programs take turns statement by statement, one command on the
//!   wire at a time (the bus is master/slave); a `DELAY` or `WAIT` holds
//!   only its own program.
//! - A runtime error is: a command the controller (or the session's
//!   validation) refuses, except `?Error Moving` while no axis holds a
//!   latched error: with an axis moving the statement is done with (Ex 7
//!   re-issues a move in a loop while it runs), with none moving it is
//!   sent again after 20 ms, up to 5 times (the controller was between
//!   two states); a `WAIT[axis]` whose axis stopped with a new latched error
//!   (MST bits 8, 9, 10, 16); a division by zero or a negative shift; a
//!   `GOSUB` to a subroutine that is not there. SUB 31 handles it if the
//!   source has one (§2.7.5), and on its ENDSUB the controller's `SAP`
//!   (read once at the start) says where to go on: 0 the statement that
//!   failed, 1 the first of the program. Without SUB 31, or for an error
//!   inside it, that program stops in the error state; the others go on.
//! - A command that gets no answer (timeout, link lost) ends the whole run:
//!   what the controller did is unknown, and no program of the manual
//!   expects to handle that.
//! - A program whose statements never touch the wire (`WHILE 1=1` /
//!   `ENDWHILE`) is given 256 statements a turn, then the others theirs
//!   and 1 ms of rest, instead of a core.

mod checked;
mod events;

pub use checked::HostProgram;
use checked::list_programs;
pub use events::{HostEnd, HostEvent, HostEventKind, HostStep};

use std::fmt;
use std::sync::Arc;
use std::time::Duration;

use crate::protocol::cmd4cr::ascript::{
    self, Action, Ascii, Op, Operand, PROGRAMS, Program, Statement, VARIABLES,
};
use crate::protocol::cmd4cr::{
    Action as AsciiAction, Axis, ErrorCode, Mst, ProgramControl, Register,
};
use crate::protocol::console::{Reading, ReplyError, ReplyValue};
use crate::protocol::program::{
    self, Answer, AnswerError, HostNews, HostStart, PlaceState, RunningPlace, Tone,
};

/// How often `WAIT[axis]` reads `MST[axis]` while the axis moves: quick
/// enough to go on soon after a move ends, and leaves the line free for
/// the other programs and the status polls in between.
pub const WAIT_POLL: Duration = Duration::from_millis(20);

/// The rest after a turn in which some program only computed.
pub const YIELD: Duration = Duration::from_millis(1);

/// Statements a program runs in one turn without touching the wire.
const LOCAL_BUDGET: usize = 256;

/// Times a statement refused as moving while no axis moves is sent again.
const RESENDS: u32 = 5;

/// The MST bits of errors latched until `CLR` (§2.6.2.1, footnote 6).
const LATCHED_ERRORS: u32 = (1 << 8) | (1 << 9) | (1 << 10) | (1 << 16);

/// What holds a program.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Hold {
    Delay {
        until: Duration,
    },
    /// `WAIT[axis]`: the latched errors seen at its first read.
    Axis {
        axis: Axis,
        errors_before: Option<u32>,
        next_read: Duration,
    },
    /// Refused as moving while nothing moves: send it again then.
    Again {
        until: Duration,
    },
}

/// Inside SUB 31: where the error happened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Handler {
    failed_step: usize,
    depth: usize,
}

/// One program.
#[derive(Debug, Clone)]
struct Thread {
    /// PRG n's first step; `None` when the file has no PRG n.
    entry: Option<usize>,
    state: PlaceState,
    pc: usize,
    stack: Vec<usize>,
    hold: Option<Hold>,
    handler: Option<Handler>,
    /// Values read for the statement at `pc`, in operand order.
    values: Vec<i32>,
    /// When it was paused: a DELAY does not run on while paused.
    paused_at: Option<Duration>,
    /// Times the statement at `pc` was sent again (see `busy`).
    resent: u32,
}

impl Thread {
    fn restart(&mut self, state: PlaceState) {
        self.state = state;
        self.pc = self.entry.unwrap_or(0);
        self.stack.clear();
        self.hold = None;
        self.handler = None;
        self.values.clear();
        self.paused_at = None;
        self.resent = 0;
    }

    fn next(&mut self, to: usize) {
        self.pc = to;
        self.hold = None;
        self.values.clear();
        self.resent = 0;
    }
}

/// What the answer in flight is for.
#[derive(Debug, Clone)]
enum Asked {
    /// SAP, read at the start.
    Sap,
    /// A value the statement at the program's `pc` needs.
    Value { thread: usize },
    /// The statement's command.
    Act {
        thread: usize,
        statement: String,
        sent: String,
    },
    /// `MST` for `WAIT[axis]`.
    Wait { thread: usize },
    /// After `?Error Moving`: is an error latched anywhere? MST of axis
    /// `axis` (X..U in turn).
    Busy {
        thread: usize,
        axis: usize,
        statement: String,
        sent: String,
        refusal: String,
        /// An axis read so far is moving.
        moving: bool,
    },
}

/// What a statement still needs before it can be evaluated.
enum Need {
    Nothing,
    Read(Turn),
    /// It cannot be: a runtime error was raised.
    Failed,
}

/// What a program's turn came to.
enum Turn {
    Send(String, Asked),
    /// Held until then.
    Until(Duration),
    /// Used up its statements for this turn.
    Yielded,
    /// Not running.
    Out,
}

/// An A-Script host run under way. See the module documentation.
#[derive(Debug)]
pub struct AScriptRun {
    program: Arc<Program>,
    threads: Vec<Thread>,
    variables: [i32; VARIABLES],
    /// `SAP` (0 back to the failed statement, 1 to the program's start).
    sap: i64,
    /// BUFON was sent and BUFOFF not since (§2.3.4): moves are queued.
    buffer_on: bool,
    asked: Option<Asked>,
    /// The program whose turn comes next.
    turn: usize,
    failures: Vec<String>,
    events: Vec<HostEvent>,
    started: bool,
    finished: bool,
    /// A program was started or continued during the round of turns.
    woken: bool,
}

impl AScriptRun {
    pub fn new(checked: &HostProgram) -> AScriptRun {
        let program = Arc::clone(&checked.program);
        let threads = (0..PROGRAMS)
            .map(|n| {
                let entry = u8::try_from(n)
                    .ok()
                    .and_then(|n| program.program(n))
                    .map(|e| e.start);
                let running = u8::try_from(n).is_ok_and(|n| checked.start.contains(&n));
                Thread {
                    entry,
                    state: if running && entry.is_some() {
                        PlaceState::Running
                    } else {
                        PlaceState::Idle
                    },
                    pc: entry.unwrap_or(0),
                    stack: Vec::new(),
                    hold: None,
                    handler: None,
                    values: Vec::new(),
                    paused_at: None,
                    resent: 0,
                }
            })
            .collect();
        AScriptRun {
            program,
            threads,
            variables: [0; VARIABLES],
            sap: 0,
            buffer_on: false,
            asked: None,
            turn: 0,
            failures: Vec::new(),
            events: Vec::new(),
            started: false,
            finished: false,
            woken: false,
        }
    }

    /// The first step. SUB 31's return needs the controller's `SAP`: it is
    /// read first when the program has a SUB 31.
    pub fn start(&mut self, now: Duration) -> HostStep {
        self.started = true;
        for n in 0..self.threads.len() {
            if self.state(n) == PlaceState::Running {
                let line = self.line_at(n);
                self.event(n, line, HostEventKind::Started);
            }
        }
        if self.program.error_handler().is_some() {
            self.asked = Some(Asked::Sap);
            return HostStep::Send("SAP".to_string());
        }
        self.next(now)
    }

    /// The answer to the last [`HostStep::Send`].
    pub fn on_reply(&mut self, result: &Answer, now: Duration) -> HostStep {
        let Some(asked) = self.asked.take() else {
            return self.next(now);
        };
        if let Err(AnswerError::Lost { reason, .. }) = &result.result {
            return self.lose(format!("{} got no answer: {reason}", result.line));
        }
        match asked {
            Asked::Sap => match number(result) {
                Ok(value) => self.sap = value,
                Err(why) => {
                    self.sap = 0;
                    let line = self.program.error_handler().map_or(0, |e| e.line);
                    self.events.push(HostEvent {
                        program: None,
                        line,
                        kind: HostEventKind::Note(format!(
                            "SAP could not be read ({why}): SUB 31 returns to the statement that failed"
                        )),
                    });
                }
            },
            Asked::Value { thread } => match number(result) {
                // Registers are 32-bit (IO, V); wider values wrap.
                Ok(value) => {
                    if let Some(t) = self.threads.get_mut(thread) {
                        t.values.push(value as i32);
                    }
                }
                Err(why) => self.fail(thread, why),
            },
            Asked::Act {
                thread,
                statement,
                sent,
            } => match &result.result {
                Ok(answer) => {
                    let line = self.line_at(thread);
                    self.event(
                        thread,
                        line,
                        HostEventKind::Sent {
                            statement,
                            sent,
                            answer: answer.value.to_string(),
                        },
                    );
                    self.advance(thread);
                }
                Err(error) if is_error_moving(error) => {
                    self.asked = Some(Asked::Busy {
                        thread,
                        axis: 0,
                        statement,
                        sent,
                        refusal: result.error_text().unwrap_or_default(),
                        moving: false,
                    });
                    return HostStep::Send("MSTX".to_string());
                }
                Err(_) => {
                    let error = result.error_text().unwrap_or_default();
                    self.fail(thread, format!("`{statement}` was refused: {error}"))
                }
            },
            Asked::Wait { thread } => match number(result) {
                Ok(value) => self.waited(thread, Mst::from_value(value), now),
                Err(why) => self.fail(thread, why),
            },
            Asked::Busy {
                thread,
                axis,
                statement,
                sent,
                refusal,
                moving,
            } => match number(result) {
                Ok(value) if Mst::from_value(value).blocking_error() => {
                    let letter = Axis::from_index(axis).map_or('?', Axis::letter);
                    self.fail(
                        thread,
                        format!(
                            "`{statement}` was refused: {refusal}, and MST{letter} = {value} holds a latched error"
                        ),
                    );
                }
                Ok(value) => {
                    let moving = moving || !Mst::from_value(value).complete();
                    if let Some(next) = Axis::from_index(axis + 1) {
                        self.asked = Some(Asked::Busy {
                            thread,
                            axis: axis + 1,
                            statement,
                            sent,
                            refusal,
                            moving,
                        });
                        return HostStep::Send(format!("MST{}", next.letter()));
                    }
                    self.busy(thread, statement, sent, refusal, moving, now);
                }
                Err(why) => self.fail(thread, why),
            },
        }
        self.next(now)
    }

    /// A [`HostStep::Wake`] came due.
    pub fn on_wake(&mut self, now: Duration) -> HostStep {
        if self.asked.is_some() {
            // Still waiting for an answer: nothing else may go.
            return HostStep::Wake(WAIT_POLL);
        }
        self.next(now)
    }

    /// The events since the last call, oldest first.
    pub fn take_events(&mut self) -> Vec<HostEvent> {
        std::mem::take(&mut self.events)
    }

    /// The variables as the host holds them (V0–V99).
    pub fn variables(&self) -> &[i32; VARIABLES] {
        &self.variables
    }

    /// Every program of the file, with its state and line.
    pub fn threads(&self) -> Vec<RunningPlace> {
        (0..self.threads.len())
            .filter(|&n| self.threads.get(n).is_some_and(|t| t.entry.is_some()))
            .filter_map(|n| {
                Some(RunningPlace {
                    program: u8::try_from(n).ok()?,
                    state: self.state(n),
                    line: self.line_at(n),
                })
            })
            .collect()
    }

    /// Whether the run is over.
    pub fn finished(&self) -> bool {
        self.finished
    }

    fn state(&self, n: usize) -> PlaceState {
        self.threads.get(n).map_or(PlaceState::Idle, |t| t.state)
    }

    fn line_at(&self, n: usize) -> usize {
        self.threads
            .get(n)
            .and_then(|t| self.program.step(t.pc))
            .map_or(0, |s| s.line)
    }

    fn event(&mut self, thread: usize, line: usize, kind: HostEventKind) {
        self.events.push(HostEvent {
            program: u8::try_from(thread).ok(),
            line,
            kind,
        });
    }

    fn lose(&mut self, why: String) -> HostStep {
        self.finished = true;
        HostStep::Finished(HostEnd {
            failures: std::mem::take(&mut self.failures),
            lost: Some(why),
            paused: Vec::new(),
        })
    }

    /// On with the statement after the one at `pc`.
    fn advance(&mut self, thread: usize) {
        if let Some(t) = self.threads.get_mut(thread) {
            let pc = t.pc;
            t.next(pc + 1);
        }
    }

    /// A runtime error of `thread`: SUB 31, or the error state (§2.7.5).
    fn fail(&mut self, thread: usize, reason: String) {
        let line = self.line_at(thread);
        let handler = self.program.error_handler().map(|e| e.start);
        let Some(t) = self.threads.get_mut(thread) else {
            return;
        };
        match (handler, t.handler) {
            (Some(start), None) => {
                t.handler = Some(Handler {
                    failed_step: t.pc,
                    depth: t.stack.len(),
                });
                t.next(start);
                self.event(thread, line, HostEventKind::Handler { reason });
            }
            _ => {
                t.state = PlaceState::Error;
                t.hold = None;
                t.values.clear();
                self.failures
                    .push(format!("PRG {thread} line {line}: {reason}"));
                self.event(thread, line, HostEventKind::Failed { reason });
            }
        }
    }

    /// The MST read by a `WAIT[axis]`.
    fn waited(&mut self, thread: usize, mst: Mst, now: Duration) {
        let Some(t) = self.threads.get_mut(thread) else {
            return;
        };
        let Some(Hold::Axis {
            axis,
            errors_before,
            ..
        }) = t.hold
        else {
            return;
        };
        let errors = mst.0 & LATCHED_ERRORS;
        let before = errors_before.unwrap_or(errors);
        if !mst.complete() {
            t.hold = Some(Hold::Axis {
                axis,
                errors_before: Some(before),
                next_read: now + WAIT_POLL,
            });
            return;
        }
        if errors & !before != 0 {
            self.fail(
                thread,
                format!(
                    "WAIT{}: the axis stopped with an error (MST {})",
                    axis.letter(),
                    mst.0
                ),
            );
        } else {
            self.advance(thread);
        }
    }

    /// `?Error Moving` and no error latched. An axis that moves is why:
    /// the statement is done with (Ex 7 sends X2000 on every pass of its
    /// loop while X moves there). With every axis complete the controller
    /// is between two states (a move just ended or not yet begun): the
    /// statement is sent again a little later, a few times. Sending it
    /// again is safe: the controller refused it, so it did nothing.
    fn busy(
        &mut self,
        thread: usize,
        statement: String,
        sent: String,
        refusal: String,
        moving: bool,
        now: Duration,
    ) {
        let line = self.line_at(thread);
        if moving {
            self.event(thread, line, HostEventKind::Busy { statement, sent });
            self.advance(thread);
            return;
        }
        let Some(t) = self.threads.get_mut(thread) else {
            return;
        };
        if t.resent >= RESENDS {
            let tries = t.resent + 1;
            self.fail(
                thread,
                format!("`{statement}` was refused {tries} times: {refusal}, though no axis moves"),
            );
            return;
        }
        t.resent += 1;
        t.hold = Some(Hold::Again {
            until: now + WAIT_POLL,
        });
    }

    /// Take turns until something must be sent, or everything waits.
    fn next(&mut self, now: Duration) -> HostStep {
        if self.finished {
            return HostStep::Finished(HostEnd::default());
        }
        if !self.started {
            return self.start(now);
        }
        let count = self.threads.len();
        let mut until: Option<Duration> = None;
        let mut yielded = false;
        // A program started (or continued) by another during a round may
        // have had its place in it already: it gets another round.
        for _ in 0..=count {
            self.woken = false;
            until = None;
            yielded = false;
            for i in 0..count {
                let n = (self.turn + i) % count;
                match self.take_turn(n, now) {
                    Turn::Send(line, asked) => {
                        self.turn = (n + 1) % count;
                        self.asked = Some(asked);
                        return HostStep::Send(line);
                    }
                    Turn::Until(at) => until = Some(until.map_or(at, |u| u.min(at))),
                    Turn::Yielded => yielded = true,
                    Turn::Out => {}
                }
            }
            if !self.woken {
                break;
            }
        }
        let running = (0..count).any(|n| self.state(n) == PlaceState::Running);
        if running && yielded {
            return HostStep::Wake(YIELD);
        }
        if running && let Some(at) = until {
            return HostStep::Wake(at.saturating_sub(now));
        }
        self.finished = true;
        let paused: Vec<u8> = (0..count)
            .filter(|&n| self.state(n) == PlaceState::Paused)
            .filter_map(|n| u8::try_from(n).ok())
            .collect();
        HostStep::Finished(HostEnd {
            failures: std::mem::take(&mut self.failures),
            lost: None,
            paused,
        })
    }

    /// Run program `n` until it must send, waits, or used its turn.
    fn take_turn(&mut self, n: usize, now: Duration) -> Turn {
        for _ in 0..LOCAL_BUDGET {
            let Some(thread) = self.threads.get(n) else {
                return Turn::Out;
            };
            if thread.state != PlaceState::Running {
                return Turn::Out;
            }
            match thread.hold {
                Some(Hold::Delay { until }) => {
                    if now < until {
                        return Turn::Until(until);
                    }
                    self.advance(n);
                    continue;
                }
                Some(Hold::Again { until }) => {
                    if now < until {
                        return Turn::Until(until);
                    }
                    if let Some(t) = self.threads.get_mut(n) {
                        t.hold = None;
                    }
                    continue;
                }
                Some(Hold::Axis {
                    axis, next_read, ..
                }) => {
                    if now < next_read {
                        return Turn::Until(next_read);
                    }
                    return Turn::Send(format!("MST{}", axis.letter()), Asked::Wait { thread: n });
                }
                None => {}
            }
            let pc = thread.pc;
            let program = Arc::clone(&self.program);
            let Some(step) = program.step(pc) else {
                self.end(n);
                return Turn::Out;
            };
            match &step.op {
                Op::Action(action) => {
                    if let Some(turn) = self.act(n, action, now) {
                        return turn;
                    }
                }
                Op::JumpUnless { condition, to } => {
                    match self.read_next(n, &condition.operands()) {
                        Need::Read(turn) => return turn,
                        Need::Failed => continue,
                        Need::Nothing => {}
                    }
                    let mut values = self.operand_values(n);
                    match condition.evaluate(&mut values) {
                        Ok(true) => self.advance(n),
                        Ok(false) => self.jump(n, *to),
                        Err(why) => self.fail(n, why),
                    }
                }
                Op::Jump { to } => self.jump(n, *to),
                Op::Call { sub } => match program.subroutine(*sub) {
                    Some(entry) => {
                        if let Some(t) = self.threads.get_mut(n) {
                            t.stack.push(pc + 1);
                            t.next(entry.start);
                        }
                    }
                    None => self.fail(
                        n,
                        format!("GOSUB {sub}: subroutine {sub} is not defined (§2.7.4)"),
                    ),
                },
                Op::Return => self.return_from(n),
                Op::End => {
                    self.end(n);
                    return Turn::Out;
                }
            }
        }
        Turn::Yielded
    }

    fn jump(&mut self, n: usize, to: usize) {
        if let Some(t) = self.threads.get_mut(n) {
            t.next(to);
        }
    }

    fn end(&mut self, n: usize) {
        let line = self.line_at(n);
        if let Some(t) = self.threads.get_mut(n) {
            t.state = PlaceState::Idle;
            t.hold = None;
        }
        self.event(n, line, HostEventKind::Finished);
    }

    /// ENDSUB: back to the caller, or out of SUB 31 as SAP says.
    fn return_from(&mut self, n: usize) {
        let restart = self.sap == 1;
        let Some(t) = self.threads.get_mut(n) else {
            return;
        };
        if let Some(handler) = t.handler
            && t.stack.len() == handler.depth
        {
            t.handler = None;
            if restart {
                t.stack.clear();
                let entry = t.entry.unwrap_or(0);
                t.next(entry);
            } else {
                t.next(handler.failed_step);
            }
            return;
        }
        match t.stack.pop() {
            Some(to) => t.next(to),
            None => {
                // ENDSUB with nothing to return to: a SUB reached by
                // falling off a PRG cannot happen (blocks are separate),
                // so this is the end of the program.
                self.end(n);
            }
        }
    }

    /// What the statement at program `n`'s `pc` still needs of
    /// `operands`: the read of the first command whose value it does not
    /// have yet.
    fn read_next(&mut self, n: usize, operands: &[Operand]) -> Need {
        let have = self.threads.get(n).map_or(0, |t| t.values.len());
        let command = operands
            .iter()
            .filter_map(|o| match o {
                Operand::Read(command) => Some(*command),
                _ => None,
            })
            .nth(have);
        let Some(command) = command else {
            return Need::Nothing;
        };
        match command.ascii_read() {
            Some(read) => Need::Read(Turn::Send(read.to_string(), Asked::Value { thread: n })),
            // The checker lets only readable commands into expressions;
            // should one slip through, it is a runtime error.
            None => {
                self.fail(n, format!("{command} cannot be read"));
                Need::Failed
            }
        }
    }

    /// The values of the operands, in order, for `evaluate`.
    fn operand_values(&self, n: usize) -> impl FnMut(&Operand) -> Result<i32, String> + use<> {
        let read: Vec<i32> = self
            .threads
            .get(n)
            .map(|t| t.values.clone())
            .unwrap_or_default();
        let variables = self.variables;
        let mut next_read = 0;
        move |operand: &Operand| match *operand {
            Operand::Number(value) => Ok(value as i32),
            Operand::Variable(v) => Ok(variables.get(usize::from(v)).copied().unwrap_or(0)),
            Operand::Read(command) => {
                let value = read
                    .get(next_read)
                    .copied()
                    .ok_or_else(|| format!("{command} was not read"));
                next_read += 1;
                value
            }
        }
    }

    /// Carry out an action: `None` when done here (on with the next
    /// statement in the same turn), else what the turn came to.
    fn act(&mut self, n: usize, action: &Action, now: Duration) -> Option<Turn> {
        match action {
            Action::Let { variable, value } => {
                match self.read_next(n, &value.operands()) {
                    Need::Read(turn) => return Some(turn),
                    Need::Failed => return None,
                    Need::Nothing => {}
                }
                let mut values = self.operand_values(n);
                match value.evaluate(&mut values) {
                    Ok(v) => {
                        if let Some(slot) = self.variables.get_mut(usize::from(*variable)) {
                            *slot = v;
                        }
                        self.advance(n);
                    }
                    Err(e) => self.fail(n, format!("V{variable}={value}: {e}")),
                }
                None
            }
            Action::Delay(value) => {
                let ms = u64::try_from(value.resolve(&self.variables)).unwrap_or(0);
                if ms == 0 {
                    self.advance(n);
                    return None;
                }
                let until = now + Duration::from_millis(ms);
                if let Some(t) = self.threads.get_mut(n) {
                    t.hold = Some(Hold::Delay { until });
                }
                Some(Turn::Until(until))
            }
            Action::Wait(axis) => {
                if let Some(t) = self.threads.get_mut(n) {
                    t.hold = Some(Hold::Axis {
                        axis: *axis,
                        errors_before: None,
                        next_read: now,
                    });
                }
                Some(Turn::Send(
                    format!("MST{}", axis.letter()),
                    Asked::Wait { thread: n },
                ))
            }
            Action::Set { command, value }
                if command.info.ascii == Ascii::Register(Register::Sactrl) =>
            {
                let code = value.resolve(&self.variables);
                let target = match command.address {
                    ascript::Address::Index(t) => t,
                    _ => 0,
                };
                match ProgramControl::from_code(code) {
                    Some(control) => {
                        let line = self.line_at(n);
                        self.advance(n);
                        self.control(n, line, target, control, now);
                    }
                    None => self.fail(
                        n,
                        format!("{action}: {code} is no program control (0..3, T2-33)"),
                    ),
                }
                None
            }
            // §2.3.4: while the buffer is on, a straight move is queued at
            // the global high speed in force, read from the controller.
            Action::Move(targets) if self.buffer_on => {
                let Some(speed) = self.threads.get(n).and_then(|t| t.values.first().copied())
                else {
                    return Some(Turn::Send("HSPD".to_string(), Asked::Value { thread: n }));
                };
                match ascript::buffered_move(targets, i64::from(speed), &self.variables) {
                    Some(sent) => Some(Turn::Send(
                        sent.clone(),
                        Asked::Act {
                            thread: n,
                            statement: action.to_string(),
                            sent,
                        },
                    )),
                    None => {
                        self.fail(
                            n,
                            format!("{action}: a buffered move gives X, Y and Z targets (§2.3.4)"),
                        );
                        None
                    }
                }
            }
            _ => {
                let statement = Statement::Action(action.clone());
                match ascript::ascii_equivalent(&statement, &self.variables) {
                    Some(sent) => {
                        if let Action::Do(command) = action {
                            match command.info.ascii {
                                Ascii::Action(AsciiAction::BufferOn) => self.buffer_on = true,
                                Ascii::Action(AsciiAction::BufferOff) => self.buffer_on = false,
                                _ => {}
                            }
                        }
                        Some(Turn::Send(
                            sent.clone(),
                            Asked::Act {
                                thread: n,
                                statement: action.to_string(),
                                sent,
                            },
                        ))
                    }
                    None => {
                        self.fail(n, format!("{action}: no ASCII command does this"));
                        None
                    }
                }
            }
        }
    }

    /// `SR[target]=control` from program `by` (T2-33, as SACTRL does it on
    /// the controller: start leaves a running program running, and starts
    /// a paused one over).
    fn control(
        &mut self,
        by: usize,
        line: usize,
        target: u8,
        control: ProgramControl,
        now: Duration,
    ) {
        let index = usize::from(target);
        let Some(t) = self.threads.get_mut(index) else {
            return;
        };
        // SR to a program the file does not define changes nothing.
        if t.entry.is_none() {
            return;
        }
        let before = t.state;
        match (control, before) {
            (ProgramControl::Stop, _) => t.restart(PlaceState::Idle),
            (ProgramControl::Start, PlaceState::Running) => {}
            (ProgramControl::Start, _) => t.restart(PlaceState::Running),
            (ProgramControl::Pause, PlaceState::Running) => {
                t.state = PlaceState::Paused;
                t.paused_at = Some(now);
            }
            (ProgramControl::Continue, PlaceState::Paused) => {
                t.state = PlaceState::Running;
                // The time it was paused does not count to its DELAY.
                if let (Some(paused_at), Some(Hold::Delay { until })) = (t.paused_at, t.hold) {
                    t.hold = Some(Hold::Delay {
                        until: until + now.saturating_sub(paused_at),
                    });
                }
                t.paused_at = None;
            }
            _ => {}
        }
        let after = t.state;
        if after == PlaceState::Running && before != PlaceState::Running {
            self.woken = true;
        }
        if before != after || control == ProgramControl::Stop {
            self.event(by, line, HostEventKind::Controlled { target, control });
        }
    }
}

/// The number an answer carries.
fn number(answer: &Answer) -> Result<i64, String> {
    match &answer.result {
        Ok(Reading {
            value: ReplyValue::Number(n),
            ..
        }) => Ok(*n),
        Ok(other) => Err(format!(
            "{} answered `{}`, not a number",
            answer.line, other.value
        )),
        Err(_) => Err(answer.error_text().unwrap_or_default()),
    }
}

/// `?Error Moving` (§4.2): the command found its axis moving.
fn is_error_moving(error: &AnswerError) -> bool {
    matches!(
        error,
        AnswerError::Reply(ReplyError::Refused { reply, .. })
            if reply == ErrorCode::ErrorMoving.info().reply
    )
}

fn generic(step: HostStep) -> program::HostStep {
    match step {
        HostStep::Send(line) => program::HostStep::Send(line),
        HostStep::Wake(after) => program::HostStep::Wake(after),
        HostStep::Finished(end) => program::HostStep::Finished(end.into()),
    }
}

impl program::HostRun for AScriptRun {
    fn start(&mut self, now: Duration) -> program::HostStep {
        generic(AScriptRun::start(self, now))
    }

    fn on_answer(&mut self, answer: &Answer, now: Duration) -> program::HostStep {
        generic(self.on_reply(answer, now))
    }

    fn on_wake(&mut self, now: Duration) -> program::HostStep {
        generic(AScriptRun::on_wake(self, now))
    }

    fn take_news(&mut self) -> Vec<HostNews> {
        self.take_events()
            .iter()
            .map(|event| HostNews {
                tone: event.tone(),
                text: event.to_string(),
            })
            .collect()
    }

    fn places(&self) -> Vec<RunningPlace> {
        self.threads()
    }

    fn variables(&self) -> &[i32] {
        AScriptRun::variables(self)
    }

    fn place_name(&self, program: u8) -> String {
        format!("PRG {program}")
    }
}

/// `source` checked for a run from the host and started, as the A-Script
/// tool offers it ([`program::ProgramTool::host_run`]).
pub fn start_host_run(
    name: &str,
    source: &str,
    start: Option<&[u8]>,
) -> Result<HostStart, Vec<String>> {
    let checked = HostProgram::check(name, source, start)?;
    Ok(HostStart {
        run: Box::new(AScriptRun::new(&checked)),
        name: checked.name().to_string(),
        warnings: checked.warnings().to_vec(),
        started: checked.started(),
        confirm: Vec::new(),
    })
}

#[cfg(test)]
mod tests;
