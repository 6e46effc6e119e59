//! What an A-Script line means: statements, the commands they name, and
//! the expressions and conditions of §2.7.2 and §2.7.6, with the integer
//! semantics both the simulator's interpreter and the host-side runner
//! evaluate them by. Every type prints back as A-Script source.

use std::fmt;

use super::super::catalog::Form;
use super::super::command::{Cmd4crCommand, Selector};
use super::commands::{Ascii, CommandInfo, forms};

pub use super::super::catalog::Axis;
pub use super::super::command::{Direction, Rotation};

/// A standalone command as a statement or operand names it: `HSPDX`,
/// `DI1`, `ABORT`, `SR0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Command {
    pub info: &'static CommandInfo,
    pub address: Address,
}

/// What a command acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Address {
    None,
    Axis(Axis),
    /// An input, output or program number, as written (1-based for I/O).
    Index(u8),
}

impl fmt::Display for Address {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Address::None => Ok(()),
            Address::Axis(axis) => write!(f, "{}", axis.letter()),
            Address::Index(n) => write!(f, "{n}"),
        }
    }
}

impl Command {
    /// The command `name` addressed by `address`, if the standalone set
    /// has that form: `Command::new("MST", Address::Axis(Axis::X))`.
    pub fn new(name: &str, address: Address) -> Option<Command> {
        let info = forms(name).find(|info| match (info.form, address) {
            (Form::Bare, Address::None) | (Form::Axis, Address::Axis(_)) => true,
            (Form::Index { first, last }, Address::Index(n)) => (first..=last).contains(&n),
            _ => false,
        })?;
        Some(Command { info, address })
    }

    pub fn name(&self) -> &'static str {
        self.info.name
    }

    pub fn axis(&self) -> Option<Axis> {
        match self.address {
            Address::Axis(axis) => Some(axis),
            _ => None,
        }
    }

    /// How the ASCII command addresses the same thing.
    pub fn selector(&self) -> Selector {
        match self.address {
            Address::None => Selector::All,
            Address::Axis(axis) => Selector::Axis(axis),
            Address::Index(n) => Selector::Index(n),
        }
    }

    /// The ASCII command of the same meaning, addressed the same way, as
    /// text: `ECLEARX` → `CLRX`, `SR0` → `SACTRL0`, `JOYHSX` → `JSPDX`,
    /// `MSTX` → `MSTX`. None for `WAIT` and `DELAY`, which only a program
    /// has.
    pub fn ascii(&self) -> Option<String> {
        let keyword = self.info.ascii_row()?.keyword;
        Some(format!("{keyword}{}", self.address))
    }

    /// The ASCII command that reads this one (`MSTX`, `DI1`, `HSPD`), for
    /// an executor that asks the controller for an operand's value. None
    /// for what cannot be read.
    pub fn ascii_read(&self) -> Option<Cmd4crCommand> {
        match self.info.ascii {
            Ascii::Register(register) if self.info.readable() => Some(Cmd4crCommand::Read {
                register,
                selector: self.selector(),
            }),
            _ => None,
        }
    }
}

impl fmt::Display for Command {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}", self.info.name, self.address)
    }
}

/// A number or a variable: what a command's value, a move's target or a
/// delay may be (§5.3 "Error not Number of Var").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Value {
    Number(i64),
    Variable(u8),
}

impl Value {
    /// The value, reading variables from `variables` (V0–V99).
    pub fn resolve(self, variables: &[i32; VARIABLES]) -> i64 {
        match self {
            Value::Number(n) => n,
            Value::Variable(v) => variables.get(usize::from(v)).copied().map_or(0, i64::from),
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Number(n) => write!(f, "{n}"),
            Value::Variable(v) => write!(f, "V{v}"),
        }
    }
}

/// How many standalone variables there are (§2.7.6: V0–V99).
pub const VARIABLES: usize = 100;

/// One side of an operation or a comparison.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Operand {
    Number(i64),
    Variable(u8),
    /// A readable command: `MSTX`, `DI1`, `HSPD`.
    Read(Command),
}

impl fmt::Display for Operand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Operand::Number(n) => write!(f, "{n}"),
            Operand::Variable(v) => write!(f, "V{v}"),
            Operand::Read(c) => write!(f, "{c}"),
        }
    }
}

/// The operators of Table 2-32 that take two operands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinaryOp {
    Add,
    Subtract,
    Multiply,
    /// Integer division, rounding down.
    Divide,
    Modulus,
    ShiftRight,
    ShiftLeft,
    And,
    Or,
}

impl BinaryOp {
    pub const ALL: [BinaryOp; 9] = [
        BinaryOp::Add,
        BinaryOp::Subtract,
        BinaryOp::Multiply,
        BinaryOp::Divide,
        BinaryOp::Modulus,
        BinaryOp::ShiftRight,
        BinaryOp::ShiftLeft,
        BinaryOp::And,
        BinaryOp::Or,
    ];

    pub fn symbol(self) -> &'static str {
        match self {
            BinaryOp::Add => "+",
            BinaryOp::Subtract => "-",
            BinaryOp::Multiply => "*",
            BinaryOp::Divide => "/",
            BinaryOp::Modulus => "%",
            BinaryOp::ShiftRight => ">>",
            BinaryOp::ShiftLeft => "<<",
            BinaryOp::And => "&",
            BinaryOp::Or => "|",
        }
    }

    /// `left op right` on 32-bit signed integers, as a 32-bit controller
    /// computes: `+ - *` wrap; `/` rounds down (T2-32) and `%` is the
    /// remainder that goes with it (the sign of the divisor); a shift by 32
    /// or more leaves only sign bits. The manual gives none of these edge
    /// cases: they are our choice, made once here for every executor.
    pub fn apply(self, left: i32, right: i32) -> Result<i32, ArithmeticError> {
        Ok(match self {
            BinaryOp::Add => left.wrapping_add(right),
            BinaryOp::Subtract => left.wrapping_sub(right),
            BinaryOp::Multiply => left.wrapping_mul(right),
            BinaryOp::Divide => floor_div(left, right)?,
            BinaryOp::Modulus => {
                let quotient = floor_div(left, right)?;
                left.wrapping_sub(quotient.wrapping_mul(right))
            }
            BinaryOp::ShiftRight => {
                let n = shift_count(right)?;
                if n >= 32 { left >> 31 } else { left >> n }
            }
            BinaryOp::ShiftLeft => {
                let n = shift_count(right)?;
                if n >= 32 { 0 } else { left << n }
            }
            BinaryOp::And => left & right,
            BinaryOp::Or => left | right,
        })
    }
}

fn floor_div(left: i32, right: i32) -> Result<i32, ArithmeticError> {
    if right == 0 {
        return Err(ArithmeticError::DivisionByZero);
    }
    let quotient = left.wrapping_div(right);
    let inexact = quotient.wrapping_mul(right) != left;
    Ok(if inexact && ((left < 0) != (right < 0)) {
        quotient - 1
    } else {
        quotient
    })
}

fn shift_count(count: i32) -> Result<u32, ArithmeticError> {
    u32::try_from(count).map_err(|_| ArithmeticError::NegativeShift(count))
}

/// A calculation the controller cannot do; a runtime error of the program
/// (the manual names none: an executor treats it like any other error,
/// SUB 31 or the error state, §2.7.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum ArithmeticError {
    #[error("division by zero")]
    DivisionByZero,
    #[error("shift by a negative count ({0})")]
    NegativeShift(i32),
}

impl fmt::Display for BinaryOp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

/// The right side of `V[n]=`: one operand, `~operand`, or one operation
/// (the manual never shows more than one operator on a line, §2.7.6).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Expr {
    Operand(Operand),
    /// Bitwise NOT.
    Not(Operand),
    Binary {
        left: Operand,
        op: BinaryOp,
        right: Operand,
    },
}

impl Expr {
    /// The operands, left to right.
    pub fn operands(&self) -> Vec<Operand> {
        match *self {
            Expr::Operand(o) | Expr::Not(o) => vec![o],
            Expr::Binary { left, right, .. } => vec![left, right],
        }
    }

    /// The value, with `value_of` giving variables and commands theirs
    /// (numbers need no help). An executor that must ask a controller for
    /// the commands can do so first: [`Expr::operands`] lists them.
    pub fn evaluate<E>(
        &self,
        value_of: &mut impl FnMut(&Operand) -> Result<i32, E>,
    ) -> Result<i32, EvalError<E>> {
        let mut get = |o: &Operand| match *o {
            // The parser keeps literals in expressions within 32 bits.
            Operand::Number(n) => Ok(n as i32),
            _ => value_of(o).map_err(EvalError::Operand),
        };
        match self {
            Expr::Operand(o) => get(o),
            Expr::Not(o) => Ok(!get(o)?),
            Expr::Binary { left, op, right } => {
                let (l, r) = (get(left)?, get(right)?);
                op.apply(l, r).map_err(EvalError::Arithmetic)
            }
        }
    }
}

/// Why an expression has no value.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EvalError<E> {
    #[error(transparent)]
    Arithmetic(ArithmeticError),
    /// `value_of` failed (a controller did not answer, …).
    #[error("{0}")]
    Operand(E),
}

impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Expr::Operand(o) => write!(f, "{o}"),
            Expr::Not(o) => write!(f, "~{o}"),
            Expr::Binary { left, op, right } => write!(f, "{left}{op}{right}"),
        }
    }
}

/// The comparisons of Table 2-30. A single `=` compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Comparison {
    Equal,
    NotEqual,
    Greater,
    Less,
    GreaterOrEqual,
    LessOrEqual,
}

impl Comparison {
    pub const ALL: [Comparison; 6] = [
        Comparison::Equal,
        Comparison::NotEqual,
        Comparison::Greater,
        Comparison::Less,
        Comparison::GreaterOrEqual,
        Comparison::LessOrEqual,
    ];

    pub fn symbol(self) -> &'static str {
        match self {
            Comparison::Equal => "=",
            Comparison::NotEqual => "!=",
            Comparison::Greater => ">",
            Comparison::Less => "<",
            Comparison::GreaterOrEqual => ">=",
            Comparison::LessOrEqual => "<=",
        }
    }

    pub fn holds(self, left: i32, right: i32) -> bool {
        match self {
            Comparison::Equal => left == right,
            Comparison::NotEqual => left != right,
            Comparison::Greater => left > right,
            Comparison::Less => left < right,
            Comparison::GreaterOrEqual => left >= right,
            Comparison::LessOrEqual => left <= right,
        }
    }
}

/// What IF, ELSEIF and WHILE test: `DI1=1`, `V1<10`, `1=1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Condition {
    pub left: Operand,
    pub op: Comparison,
    pub right: Operand,
}

impl Condition {
    pub fn operands(&self) -> [Operand; 2] {
        [self.left, self.right]
    }

    /// Whether the condition holds, `value_of` giving variables and
    /// commands their values (see [`Expr::evaluate`]).
    pub fn evaluate<E>(
        &self,
        value_of: &mut impl FnMut(&Operand) -> Result<i32, E>,
    ) -> Result<bool, E> {
        let mut get = |o: &Operand| match *o {
            Operand::Number(n) => Ok(n as i32),
            _ => value_of(o),
        };
        Ok(self.op.holds(get(&self.left)?, get(&self.right)?))
    }
}

impl fmt::Display for Condition {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}{}", self.left, self.op.symbol(), self.right)
    }
}

/// One axis's target in a move: `X1000`, `XV1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Target {
    pub axis: Axis,
    pub value: Value,
}

/// A statement that does something (everything but block structure and
/// control flow).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Action {
    /// `V1=V2+V3`.
    Let { variable: u8, value: Expr },
    /// `HSPD=20000`, `DO1=V3`, `SR0=1`.
    Set { command: Command, value: Value },
    /// A command done by naming it: `ABORTX`, `ABS`, `BUFON`, `ECLEARX`.
    Do(Command),
    /// `DELAY=ms`.
    Delay(Value),
    /// `WAITX`: wait until the axis has stopped.
    Wait(Axis),
    /// `X1000`, `X1000Y2000`, `XV1`: targets in the order written.
    Move(Vec<Target>),
    /// `JOGX+`.
    Jog { axis: Axis, direction: Direction },
    /// `HOMEX-6`.
    Home {
        axis: Axis,
        direction: Direction,
        mode: u8,
    },
    /// A motion statement written the same way in both command sets, kept
    /// as its ASCII command: `ZMOVEX+`, `CIRXYP1000:0`, `ARCXYN0:0:90000`,
    /// `CIRTP1000:0:500`, `ARCTN0:0:90000:500` (§2.3.4: "The syntax for
    /// these commands is the same in ASCII and standalone mode"; their
    /// values are numbers only, §2.3.2).
    SameInAscii(Cmd4crCommand),
}

impl fmt::Display for Action {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Action::Let { variable, value } => write!(f, "V{variable}={value}"),
            Action::Set { command, value } => write!(f, "{command}={value}"),
            Action::Do(command) => write!(f, "{command}"),
            Action::Delay(value) => write!(f, "DELAY={value}"),
            Action::Wait(axis) => write!(f, "WAIT{}", axis.letter()),
            Action::Move(targets) => targets
                .iter()
                .try_for_each(|t| write!(f, "{}{}", t.axis.letter(), t.value)),
            Action::Jog { axis, direction } => {
                write!(f, "JOG{}{}", axis.letter(), direction.sign())
            }
            Action::Home {
                axis,
                direction,
                mode,
            } => write!(f, "HOME{}{}{mode}", axis.letter(), direction.sign()),
            Action::SameInAscii(command) => write!(f, "{command}"),
        }
    }
}

/// One line's statement.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Statement {
    /// `PRG n`: program n (0–3) starts.
    Prg(u8),
    /// `END`: the program ends.
    End,
    /// `SUB n`: subroutine n (0–31) starts; SUB 31 handles errors.
    Sub(u8),
    EndSub,
    If(Condition),
    ElseIf(Condition),
    Else,
    EndIf,
    While(Condition),
    EndWhile,
    /// `GOSUB n`.
    Gosub(u8),
    Action(Action),
}

impl fmt::Display for Statement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Statement::Prg(n) => write!(f, "PRG {n}"),
            Statement::End => f.write_str("END"),
            Statement::Sub(n) => write!(f, "SUB {n}"),
            Statement::EndSub => f.write_str("ENDSUB"),
            Statement::If(c) => write!(f, "IF {c}"),
            Statement::ElseIf(c) => write!(f, "ELSEIF {c}"),
            Statement::Else => f.write_str("ELSE"),
            Statement::EndIf => f.write_str("ENDIF"),
            Statement::While(c) => write!(f, "WHILE {c}"),
            Statement::EndWhile => f.write_str("ENDWHILE"),
            Statement::Gosub(n) => write!(f, "GOSUB {n}"),
            Statement::Action(a) => write!(f, "{a}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn division_rounds_down_and_modulus_follows_it() {
        let div = |a, b| BinaryOp::Divide.apply(a, b);
        let rem = |a, b| BinaryOp::Modulus.apply(a, b);
        assert_eq!(div(7, 2), Ok(3));
        assert_eq!(div(-7, 2), Ok(-4));
        assert_eq!(div(7, -2), Ok(-4));
        assert_eq!(div(-8, 2), Ok(-4));
        assert_eq!(rem(7, 5), Ok(2));
        assert_eq!(rem(-7, 5), Ok(3));
        assert_eq!(div(1, 0), Err(ArithmeticError::DivisionByZero));
        assert_eq!(rem(1, 0), Err(ArithmeticError::DivisionByZero));
        assert_eq!(div(i32::MIN, -1), Ok(i32::MIN));
    }

    #[test]
    fn arithmetic_wraps_like_32_bit_registers_and_shifts_saturate() {
        assert_eq!(BinaryOp::Add.apply(i32::MAX, 1), Ok(i32::MIN));
        assert_eq!(BinaryOp::Multiply.apply(65536, 65536), Ok(0));
        assert_eq!(BinaryOp::ShiftLeft.apply(1, 2), Ok(4));
        assert_eq!(BinaryOp::ShiftLeft.apply(1, 40), Ok(0));
        assert_eq!(BinaryOp::ShiftRight.apply(-8, 1), Ok(-4));
        assert_eq!(BinaryOp::ShiftRight.apply(-8, 99), Ok(-1));
        assert_eq!(
            BinaryOp::ShiftRight.apply(8, -1),
            Err(ArithmeticError::NegativeShift(-1))
        );
        assert_eq!(BinaryOp::And.apply(0b1110, 0b0111), Ok(0b0110));
        assert_eq!(BinaryOp::Or.apply(0b1000, 0b0001), Ok(0b1001));
    }

    #[test]
    fn an_expression_asks_only_for_what_is_not_a_number() {
        let expr = Expr::Binary {
            left: Operand::Variable(2),
            op: BinaryOp::And,
            right: Operand::Number(7),
        };
        let mut asked = Vec::new();
        let value = expr.evaluate(&mut |o: &Operand| {
            asked.push(*o);
            Ok::<_, ()>(13)
        });
        assert_eq!(value, Ok(5));
        assert_eq!(asked, [Operand::Variable(2)]);
        assert_eq!(
            Expr::Not(Operand::Number(0)).evaluate(&mut |_| Err(())),
            Ok(-1)
        );
        let failing = Expr::Operand(Operand::Variable(1)).evaluate(&mut |_| Err("no reply"));
        assert_eq!(failing, Err(EvalError::Operand("no reply")));
    }

    #[test]
    fn a_condition_compares_as_table_2_30_says() {
        let c = |left, op, right| Condition {
            left: Operand::Number(left),
            op,
            right: Operand::Number(right),
        };
        let holds = |c: Condition| c.evaluate(&mut |_| Err::<i32, ()>(())).unwrap_or(false);
        assert!(holds(c(1, Comparison::Equal, 1)));
        assert!(holds(c(1, Comparison::NotEqual, 2)));
        assert!(holds(c(3, Comparison::Greater, 2)));
        assert!(holds(c(2, Comparison::Less, 3)));
        assert!(holds(c(3, Comparison::GreaterOrEqual, 3)));
        assert!(holds(c(3, Comparison::LessOrEqual, 3)));
        assert!(!holds(c(4, Comparison::LessOrEqual, 3)));
    }
}
