//! From A-Script to the ASCII command set: what a host sends to do what a
//! statement does (§2's availability tables pair each standalone command
//! with its ASCII one), and which statements have no such command, so a
//! host-side run can refuse them before it starts.

use std::fmt;

use super::super::command::{Cmd4crCommand, CommandError, parse_command};
use super::ast::{Action, Axis, Statement, Target, VARIABLES};
use super::commands::Ascii;
use super::program::Program;

/// The ASCII command text that does what `statement` does, its
/// variables given their values from `variables`: `HSPD=20000`, `XV1` →
/// `X1500`, `ECLEARX` → `CLRX`, `SR0=1` → `SACTRL0=1`, `JOGX+` → `JX+`,
/// `HOMEX-6` → `HX-6`. What a host sends after `@ID`.
///
/// A variable may hold a value the command refuses (`HSPD=V1` with V1 =
/// 0): the text is still the command (`HSPD=0`), and the controller
/// answers it with its §4.2 error; [`ascii_command`] checks it first.
///
/// None for what has no ASCII command and is the executor's own work:
/// block structure and control flow, GOSUB, `V[n]=` (variables live with
/// the program), `DELAY` (a timer) and `WAIT[axis]` (poll `MST[axis]`
/// until bits 0–2 are clear, §2.6.2.1). While the move buffer is on, a
/// straight move is queued instead: see [`buffered_move`].
pub fn ascii_equivalent(statement: &Statement, variables: &[i32; VARIABLES]) -> Option<String> {
    translate(statement, variables).map(|c| c.to_string())
}

/// [`ascii_equivalent`] as the typed command of the one ASCII parser
/// ([`parse_command`]), which has read it back: a value out of the
/// command's range gives the parser's error, which is also the
/// controller's §4.2 reply ([`CommandError::reply`]).
pub fn ascii_command(
    statement: &Statement,
    variables: &[i32; VARIABLES],
) -> Option<Result<Cmd4crCommand, CommandError>> {
    translate(statement, variables).map(checked)
}

/// The ASCII command of a statement, its values unchecked.
fn translate(statement: &Statement, variables: &[i32; VARIABLES]) -> Option<Cmd4crCommand> {
    let Statement::Action(action) = statement else {
        return None;
    };
    let command = match action {
        Action::Let { .. } | Action::Delay(_) | Action::Wait(_) => return None,
        Action::Set { command, value } => match command.info.ascii {
            Ascii::Register(register) => Cmd4crCommand::Write {
                register,
                selector: command.selector(),
                value: value.resolve(variables),
            },
            _ => return None,
        },
        Action::Do(command) => match command.info.ascii {
            Ascii::Action(action) => Cmd4crCommand::Action {
                action,
                selector: command.selector(),
            },
            _ => return None,
        },
        Action::Move(targets) => {
            let mut by_axis = [None; 4];
            for t in targets {
                if let Some(slot) = by_axis.get_mut(t.axis.index()) {
                    *slot = Some(t.value.resolve(variables));
                }
            }
            Cmd4crCommand::Move { targets: by_axis }
        }
        Action::Jog { axis, direction } => Cmd4crCommand::Jog {
            axis: *axis,
            direction: *direction,
        },
        Action::Home {
            axis,
            direction,
            mode,
        } => Cmd4crCommand::Home {
            axis: *axis,
            direction: *direction,
            mode: *mode,
        },
        Action::SameInAscii(command) => command.clone(),
    };
    Some(command)
}

/// The command as the ASCII parser reads its text: values in range, the
/// same command back.
fn checked(command: Cmd4crCommand) -> Result<Cmd4crCommand, CommandError> {
    parse_command(&command.to_string())
}

/// A straight move queued while the buffer is on (`BUFON`): the ASCII
/// command text `I[X]:[Y]:[Z]:[speed]` (§2.3.4), the speed being the
/// global high speed in force ("the current global high-speed setting",
/// §2.3.4). None unless the move names X, Y and Z and not U: `I` has
/// exactly those three fields.
pub fn buffered_move(
    targets: &[Target],
    speed: i64,
    variables: &[i32; VARIABLES],
) -> Option<String> {
    buffer_entry(targets, speed, variables).map(|c| c.to_string())
}

/// [`buffered_move`] as the typed command the ASCII parser has read back
/// (see [`ascii_command`]).
pub fn buffered_move_command(
    targets: &[Target],
    speed: i64,
    variables: &[i32; VARIABLES],
) -> Option<Result<Cmd4crCommand, CommandError>> {
    buffer_entry(targets, speed, variables).map(checked)
}

fn buffer_entry(
    targets: &[Target],
    speed: i64,
    variables: &[i32; VARIABLES],
) -> Option<Cmd4crCommand> {
    let target = |axis| {
        targets
            .iter()
            .find(|t| t.axis == axis)
            .map(|t| t.value.resolve(variables))
    };
    if targets.len() != 3 {
        return None;
    }
    let target = [target(Axis::X)?, target(Axis::Y)?, target(Axis::Z)?];
    Some(Cmd4crCommand::BufferMove { target, speed })
}

/// A statement a host cannot carry out with ASCII commands.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HostProblem {
    /// 1-based.
    pub line: usize,
    pub statement: String,
    pub reason: String,
}

impl fmt::Display for HostProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {}: `{}` cannot run from the host: {}",
            self.line, self.statement, self.reason
        )
    }
}

impl Program {
    /// The statements that have no ASCII equivalent, for a host-side run to
    /// report before it starts. Every standalone command has one (§2's
    /// tables), except moves while the buffer is on (§2.3.4): a buffered
    /// straight move is ASCII `I[X]:[Y]:[Z]:[speed]`, so one that does not
    /// give exactly X, Y and Z cannot be sent; CIR and ARC are queued as
    /// written but only on X, Y and Z; CIRT and ARCT cannot be queued.
    ///
    /// Buffer mode is followed in source order within each PRG or SUB
    /// (BUFON to BUFOFF), not along every path a run could take: a
    /// subroutine called between BUFON and BUFOFF is read as unbuffered.
    pub fn host_problems(&self) -> Vec<HostProblem> {
        let mut problems = Vec::new();
        let mut buffer_on: Option<usize> = None;
        for s in &self.statements {
            let Statement::Action(action) = &s.statement else {
                if matches!(s.statement, Statement::Prg(_) | Statement::Sub(_)) {
                    buffer_on = None;
                }
                continue;
            };
            match action {
                Action::Do(command) if command.name() == "BUFON" => buffer_on = Some(s.line),
                Action::Do(command) if command.name() == "BUFOFF" => buffer_on = None,
                _ => {}
            }
            let Some(since) = buffer_on else {
                continue;
            };
            let reason = match action {
                Action::Move(targets) => {
                    let mut axes: Vec<Axis> = targets.iter().map(|t| t.axis).collect();
                    axes.sort();
                    if axes == [Axis::X, Axis::Y, Axis::Z] {
                        continue;
                    }
                    format!(
                        "in buffer mode (BUFON on line {since}) a move is sent as I[X]:[Y]:[Z]:[speed] (§2.3.4), which needs exactly X, Y and Z targets"
                    )
                }
                // §2.3.4: CIR and ARC are buffered with the same syntax in
                // both sets, but the buffer moves X, Y and Z only.
                Action::SameInAscii(
                    Cmd4crCommand::Circle { axes, .. } | Cmd4crCommand::Arc { axes, .. },
                ) => {
                    if !axes.contains(&Axis::U) {
                        continue;
                    }
                    format!(
                        "in buffer mode (BUFON on line {since}) only X, Y and Z can move (§2.3.4)"
                    )
                }
                Action::SameInAscii(
                    Cmd4crCommand::HelicalCircle { .. } | Cmd4crCommand::HelicalArc { .. },
                ) => format!(
                    "in buffer mode (BUFON on line {since}) only linear, circular and arc moves of X, Y and Z are queued (§2.3.4); CIRT and ARCT use U"
                ),
                _ => continue,
            };
            problems.push(HostProblem {
                line: s.line,
                statement: s.statement.to_string(),
                reason,
            });
        }
        problems
    }
}
