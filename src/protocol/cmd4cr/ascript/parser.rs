//! One line of A-Script to a [`Statement`], or the Table 5-43 error it
//! would get. Block structure (PRG…END, IF…ENDIF, …) is the program
//! pass's business ([`super::program`]); this file knows lines.
//!
//! Which code an error gets where the manual shows no example is our
//! reading of Table 5-43's descriptions; the choices are listed in the
//! module documentation ([`super`]).

use super::super::catalog::{Form, FormShape};
use super::super::command::Cmd4crCommand;
use super::ast::{
    Action, Address, Axis, BinaryOp, Command, Comparison, Condition, Direction, Expr, Operand,
    Rotation, Statement, Target, Value,
};
use super::commands::{
    ANGLE, CommandInfo, HOME_MODE, I32, POSITION, Shape, ValueRange, ascii_only_command, form,
    forms,
};
use super::errors::ErrorCode;
use super::lexer::{Keyword, Lex, Symbol, Token, lex};

/// What is wrong with a line, and where in it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LineError {
    /// 1-based, in characters.
    pub column: usize,
    pub code: ErrorCode,
    pub detail: String,
}

/// A line read on its own.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParsedLine {
    pub statement: Result<Statement, LineError>,
    /// The keyword the line starts with, even when the rest of it is
    /// wrong: `PRG 9` still opens a program block, `IF V1==2` still opens
    /// an IF, so one mistake does not unbalance every block after it.
    pub keyword: Option<Keyword>,
    /// Where the statement starts (1-based, in characters).
    pub column: usize,
}

/// Parse one line; None if it holds no statement (blank or comment).
pub fn parse_line(line: &str) -> Option<ParsedLine> {
    let tokens = lex(line).tokens;
    let first = tokens.first()?;
    let keyword = match first.lex {
        Lex::Keyword(k) => Some(k),
        _ => None,
    };
    let mut parser = Parser {
        line,
        tokens,
        next: 0,
    };
    let column = parser.column_of(0);
    let statement = parser.statement();
    Some(ParsedLine {
        statement,
        keyword,
        column,
    })
}

/// Where an operand stands, which decides the error it gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Place {
    /// The whole right side of `V[n]=` (T5-43 "Assignment Error").
    Assigned,
    /// Either side of an operator (T5-43 "Operation Argument Error").
    Operation,
    /// Either side of a comparison.
    Condition,
}

struct Parser<'a> {
    line: &'a str,
    tokens: Vec<Token>,
    next: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.next)
    }

    fn peek_lex(&self) -> Option<Lex> {
        self.peek().map(|t| t.lex)
    }

    /// The next token if it follows the previous one with no space.
    fn peek_adjacent(&self) -> Option<Lex> {
        self.peek().filter(|t| !t.spaced).map(|t| t.lex)
    }

    fn bump(&mut self) -> Option<Token> {
        let token = self.tokens.get(self.next).cloned();
        if token.is_some() {
            self.next += 1;
        }
        token
    }

    fn text(&self, token: &Token) -> &str {
        self.line.get(token.span.clone()).unwrap_or("")
    }

    /// The source from token `from` to the end of the last token.
    fn text_from(&self, from: usize) -> &str {
        match (self.tokens.get(from), self.tokens.last()) {
            (Some(a), Some(b)) => self.line.get(a.span.start..b.span.end).unwrap_or(""),
            _ => "",
        }
    }

    /// The whole statement as written.
    fn statement_text(&self) -> &str {
        self.text_from(0)
    }

    fn column_at(&self, byte: usize) -> usize {
        self.line.get(..byte).map_or(1, |s| s.chars().count() + 1)
    }

    /// Column of token `index`, or just past the last token.
    fn column_of(&self, index: usize) -> usize {
        match self.tokens.get(index) {
            Some(t) => self.column_at(t.span.start),
            None => self.column_at(self.tokens.last().map_or(0, |t| t.span.end)),
        }
    }

    fn error_at(&self, index: usize, code: ErrorCode, detail: String) -> LineError {
        LineError {
            column: self.column_of(index),
            code,
            detail,
        }
    }

    /// An error at the token just taken.
    fn error_here(&self, code: ErrorCode, detail: String) -> LineError {
        self.error_at(self.next.saturating_sub(1), code, detail)
    }

    /// An error at the next token (or the end of the line).
    fn error_next(&self, code: ErrorCode, detail: String) -> LineError {
        self.error_at(self.next, code, detail)
    }

    fn has_later(&self, symbol: Symbol) -> bool {
        self.tokens
            .get(self.next..)
            .is_some_and(|rest| rest.iter().any(|t| t.lex == Lex::Symbol(symbol)))
    }

    /// Nothing may follow `what`.
    fn expect_end(&self, what: &str) -> Result<(), LineError> {
        if self.peek().is_none() {
            return Ok(());
        }
        Err(self.error_next(
            ErrorCode::TokenError,
            format!("unexpected `{}` after `{what}`", self.text_from(self.next)),
        ))
    }

    /// A `==` anywhere from here on is T5-43's example of "Error".
    fn refuse_double_equals(&self) -> Result<(), LineError> {
        let at = self.tokens.get(self.next..).and_then(|rest| {
            rest.iter()
                .position(|t| t.lex == Lex::Symbol(Symbol::DoubleEquals))
        });
        match at {
            Some(offset) => Err(self.error_at(
                self.next + offset,
                ErrorCode::Error,
                "`==` is not A-Script: a single `=` compares (Table 2-30)".into(),
            )),
            None => Ok(()),
        }
    }

    /// Take the `=` of an assignment. Without it: `==` is "Error", an
    /// expression left of a later `=` is "= Error" (`V2+1=V3`), and no `=`
    /// at all is `missing` ("Missing =" for `HSPD*1000`).
    fn expect_equals(&mut self, missing: impl FnOnce(&Self) -> LineError) -> Result<(), LineError> {
        match self.peek_lex() {
            Some(Lex::Symbol(Symbol::Equals)) => {
                self.bump();
                Ok(())
            }
            Some(Lex::Symbol(Symbol::DoubleEquals)) => self.refuse_double_equals(),
            Some(_) if self.has_later(Symbol::Equals) => Err(self.error_at(
                0,
                ErrorCode::EqualsError,
                format!(
                    "the left of `=` must be one variable or command, not `{}`",
                    self.left_of_equals()
                ),
            )),
            _ => Err(missing(self)),
        }
    }

    fn statement(&mut self) -> Result<Statement, LineError> {
        let Some(first) = self.bump() else {
            return Err(self.error_next(ErrorCode::Error, "empty statement".into()));
        };
        match first.lex {
            Lex::Keyword(k) => self.keyword(k),
            Lex::Command { name, axis } => self.command_statement(name, axis),
            Lex::Curve {
                name,
                axes,
                rotation,
            } => self.curve(name, Some(axes), rotation),
            Lex::Helix { name, rotation } => self.curve(name, None, rotation),
            Lex::Axis(axis) => self.movement(axis),
            Lex::Variable(index) => self.variable_statement(index),
            Lex::Number(_) | Lex::Symbol(_) | Lex::Word | Lex::Other => Err(self.unknown(&first)),
        }
    }

    /// T5-43 "Unknown Error" for a token that names nothing A-Script has,
    /// with the likely reason.
    fn unknown(&self, token: &Token) -> LineError {
        let text = self.text(token);
        let detail = match token.lex {
            Lex::Word => {
                let upper = text.to_ascii_uppercase();
                let known_in_capitals = lex(&upper)
                    .tokens
                    .first()
                    .is_some_and(|t| t.lex != Lex::Word);
                if upper != text && known_in_capitals {
                    format!("`{text}`: A-Script is written in capitals (`{upper}`)")
                } else if let Some(ascii) = ascii_only_command(text) {
                    match ascii.instead {
                        Some(instead) => format!(
                            "`{text}` is an ASCII command, not an A-Script one: in a program write {instead}"
                        ),
                        None => format!(
                            "`{text}` is an ASCII command that standalone programs do not have (§2: no Standalone form)"
                        ),
                    }
                } else {
                    format!("`{text}` is not an A-Script command or keyword")
                }
            }
            Lex::Number(_) => format!("a statement cannot start with a number (`{text}`)"),
            _ => format!("`{text}` is not an A-Script command or keyword"),
        };
        LineError {
            column: self.column_at(token.span.start),
            code: ErrorCode::UnknownError,
            detail,
        }
    }

    fn keyword(&mut self, keyword: Keyword) -> Result<Statement, LineError> {
        let word = keyword.text();
        match keyword {
            Keyword::Prg => self
                .block_number(
                    word,
                    "program",
                    3,
                    ErrorCode::ErrorPrg,
                    ErrorCode::ErrorPrgNumber,
                )
                .map(Statement::Prg),
            Keyword::Sub => self
                .block_number(
                    word,
                    "subroutine",
                    31,
                    ErrorCode::ErrorSub,
                    ErrorCode::ErrorSubNumber,
                )
                .map(Statement::Sub),
            Keyword::Gosub => self
                .block_number(
                    word,
                    "subroutine",
                    31,
                    ErrorCode::ErrorGosub,
                    ErrorCode::ErrorSubNumber,
                )
                .map(Statement::Gosub),
            Keyword::End => self.expect_end(word).map(|()| Statement::End),
            Keyword::EndSub => self.expect_end(word).map(|()| Statement::EndSub),
            Keyword::Else => self.expect_end(word).map(|()| Statement::Else),
            Keyword::EndIf => self.expect_end(word).map(|()| Statement::EndIf),
            Keyword::EndWhile => self.expect_end(word).map(|()| Statement::EndWhile),
            Keyword::If => self.condition(word).map(Statement::If),
            Keyword::ElseIf => self.condition(word).map(Statement::ElseIf),
            Keyword::While => self.condition(word).map(Statement::While),
        }
    }

    /// The number after PRG, SUB or GOSUB: out of range is `range_code`
    /// (`PRG200`, `GOSUB900`), not a number at all is `number_code`
    /// (`PRG XI3`, `GOSUB DI1`).
    fn block_number(
        &mut self,
        word: &str,
        what: &str,
        max: i64,
        range_code: ErrorCode,
        number_code: ErrorCode,
    ) -> Result<u8, LineError> {
        let Some(token) = self.bump() else {
            return Err(self.error_next(
                number_code,
                format!("{word} needs a {what} number 0-{max}: `{word} 0`"),
            ));
        };
        let n = match token.lex {
            Lex::Number(Some(n)) if (0..=max).contains(&n) => n,
            Lex::Number(_) => {
                let text = self.text(&token);
                return Err(self.error_here(
                    range_code,
                    format!("{word} {text}: {what} numbers are 0-{max}"),
                ));
            }
            _ => {
                let rest = self.text_from(self.next - 1);
                return Err(self.error_here(
                    number_code,
                    format!("`{rest}` is not a {what} number: write {word} and a number 0-{max}"),
                ));
            }
        };
        self.expect_end(&format!("{word} {n}"))?;
        u8::try_from(n).map_err(|_| self.error_here(range_code, format!("{word} {n}")))
    }

    /// `operand comparison operand` (Table 2-30).
    fn condition(&mut self, word: &str) -> Result<Condition, LineError> {
        if self.peek().is_none() {
            return Err(self.error_next(
                ErrorCode::Error,
                format!("{word} needs a condition, such as `{word} DI1=1` (Table 2-30)"),
            ));
        }
        self.refuse_double_equals()?;
        let start = self.next;
        let left = self.operand(Place::Condition)?;
        let Some(token) = self.bump() else {
            return Err(self.error_next(
                ErrorCode::Error,
                format!(
                    "`{}` is not a condition: compare it with =, !=, >, <, >= or <= (Table 2-30)",
                    self.text_from(start)
                ),
            ));
        };
        let op = match token.lex {
            Lex::Symbol(s) => match comparison(s) {
                Some(op) => op,
                None if binary(s).is_some() => {
                    return Err(self.error_here(
                        ErrorCode::TokenError,
                        format!(
                            "`{}`: a condition compares two values (Table 2-30); compute the operation into a variable first",
                            self.text_from(start)
                        ),
                    ));
                }
                None => {
                    return Err(self.error_here(
                        ErrorCode::Error,
                        format!("`{}` is not a comparison", self.text(&token)),
                    ));
                }
            },
            _ => {
                return Err(self.error_here(
                    ErrorCode::Error,
                    format!(
                        "expected =, !=, >, <, >= or <= after `{left}`, found `{}`",
                        self.text(&token)
                    ),
                ));
            }
        };
        let right = self.operand(Place::Condition)?;
        if let Some(Lex::Symbol(s)) = self.peek_lex()
            && binary(s).is_some()
        {
            return Err(self.error_next(
                ErrorCode::TokenError,
                format!(
                    "`{}`: a condition compares two values (Table 2-30); compute the operation into a variable first",
                    self.text_from(start)
                ),
            ));
        }
        let condition = Condition { left, op, right };
        self.expect_end(&format!("{word} {condition}"))?;
        Ok(condition)
    }

    /// A number, variable or readable command.
    fn operand(&mut self, place: Place) -> Result<Operand, LineError> {
        if let Some(number) = self.signed_number(I32) {
            return number.map(Operand::Number);
        }
        let Some(token) = self.bump() else {
            let (code, detail) = match place {
                Place::Assigned => (
                    ErrorCode::AssignmentError,
                    "nothing after `=`: give a number, a variable, a readable command or one operation (Table 2-32)",
                ),
                Place::Operation => (
                    ErrorCode::OperationArgumentError,
                    "the operator has nothing on its right",
                ),
                Place::Condition => (ErrorCode::Error, "nothing to compare with"),
            };
            return Err(self.error_next(code, detail.into()));
        };
        let invalid = |parser: &Self, what: String| {
            let code = match place {
                Place::Assigned => ErrorCode::AssignmentError,
                Place::Operation => ErrorCode::OperationArgumentError,
                Place::Condition => ErrorCode::Error,
            };
            parser.error_here(code, what)
        };
        match token.lex {
            Lex::Symbol(Symbol::Minus) => {
                Err(invalid(self, "`-` must be followed by a number".into()))
            }
            Lex::Variable(index) => self.variable_index(index).map(Operand::Variable),
            Lex::Command { name, axis } => {
                let command = self.command(name, axis)?;
                if command.info.readable() {
                    return Ok(Operand::Read(command));
                }
                let code = match place {
                    Place::Assigned => ErrorCode::AssignmentError,
                    Place::Operation | Place::Condition => ErrorCode::OperationArgumentError,
                };
                Err(self.error_at(
                    self.next
                        .saturating_sub(1 + usize::from(index_taken(&command))),
                    code,
                    not_a_value(&command),
                ))
            }
            Lex::Word | Lex::Other => Err(self.unknown(&token)),
            Lex::Symbol(Symbol::DoubleEquals | Symbol::Equals) => Err(self.error_here(
                ErrorCode::Error,
                "`==` is not A-Script: a single `=` compares (Table 2-30)".into(),
            )),
            _ => {
                let text = self.text(&token).to_string();
                Err(invalid(self, format!("`{text}` is not a value")))
            }
        }
    }

    /// A number written next, with its minus sign if any, within `range`
    /// (T5-43 "Assignment Error" outside it). None, taking nothing, when
    /// no number comes next.
    fn signed_number(&mut self, range: ValueRange) -> Option<Result<i64, LineError>> {
        let start = self.next;
        let negative = self.peek_lex() == Some(Lex::Symbol(Symbol::Minus));
        let digits = self.tokens.get(start + usize::from(negative))?;
        let Lex::Number(n) = digits.lex else {
            return None;
        };
        if negative && digits.spaced {
            return None;
        }
        self.next = start + usize::from(negative) + 1;
        let value = n.map(|n| if negative { -n } else { n });
        Some(match value {
            Some(v) if range.contains(v) => Ok(v),
            _ => Err(self.error_at(
                start,
                ErrorCode::AssignmentError,
                format!("{} is outside {range}", self.text_between(start, self.next)),
            )),
        })
    }

    /// The source of tokens `from..to`.
    fn text_between(&self, from: usize, to: usize) -> &str {
        match (
            self.tokens.get(from),
            to.checked_sub(1).and_then(|i| self.tokens.get(i)),
        ) {
            (Some(a), Some(b)) if a.span.start <= b.span.end => {
                self.line.get(a.span.start..b.span.end).unwrap_or("")
            }
            _ => "",
        }
    }

    /// V0–V99 (T5-43 "Var Range Error" otherwise).
    fn variable_index(&self, index: Option<u64>) -> Result<u8, LineError> {
        match index {
            Some(n) if n < 100 => u8::try_from(n).map_err(|_| self.var_range(index)),
            _ => Err(self.var_range(index)),
        }
    }

    fn var_range(&self, index: Option<u64>) -> LineError {
        let detail = match index {
            None => "V needs a number: the variables are V0-V99".to_string(),
            Some(_) => format!(
                "`{}`: the variables are V0-V99",
                self.tokens
                    .get(self.next.saturating_sub(1))
                    .map_or("", |t| self.text(t))
            ),
        };
        self.error_here(ErrorCode::VarRangeError, detail)
    }

    /// The command a name (and the axis or index after it) stands for.
    fn command(&mut self, name: &'static str, axis: Option<Axis>) -> Result<Command, LineError> {
        let indexed = form(name, FormShape::Index);
        if axis.is_none()
            && let Some(info) = indexed
            && let Some(Lex::Number(n)) = self.peek_adjacent()
        {
            self.bump();
            let Form::Index { first, last } = info.form else {
                return Err(self.error_here(ErrorCode::UnknownError, name.into()));
            };
            return match n {
                Some(n) if (i64::from(first)..=i64::from(last)).contains(&n) => Ok(Command {
                    info,
                    address: Address::Index(u8::try_from(n).unwrap_or(first)),
                }),
                _ => {
                    let written = self.text_between(self.next - 1, self.next);
                    Err(self.error_at(
                        self.next.saturating_sub(2),
                        index_code(name, true),
                        format!("`{name}{written}`: {name} has {first}-{last}"),
                    ))
                }
            };
        }
        let (kind, address) = match axis {
            Some(axis) => (FormShape::Axis, Address::Axis(axis)),
            None => (FormShape::Bare, Address::None),
        };
        // CIR, ARC, CIRT, ARCT alone: their syntax is the parser's
        // business (`CIRXYP…` is lexed whole).
        let motion = || forms(name).find(|c| c.form == Form::Motion && axis.is_none());
        if let Some(info) = form(name, kind).or_else(motion) {
            return Ok(Command { info, address });
        }
        let (code, detail) = if form(name, FormShape::Axis).is_some() {
            (
                ErrorCode::UnknownError,
                format!("`{name}` needs an axis: {name}X, {name}Y, {name}Z or {name}U"),
            )
        } else if let Some(CommandInfo {
            form: Form::Index { first, last },
            ..
        }) = indexed
        {
            (
                index_code(name, false),
                format!("`{name}` needs a number {first}-{last}: {name}{first}"),
            )
        } else {
            (ErrorCode::UnknownError, format!("`{name}` takes no axis"))
        };
        Err(self.error_here(code, detail))
    }

    fn command_statement(
        &mut self,
        name: &'static str,
        axis: Option<Axis>,
    ) -> Result<Statement, LineError> {
        let command = self.command(name, axis)?;
        let action = match command.info.shape {
            Shape::Register(_) => return self.set(command),
            Shape::Action => {
                self.expect_end(&command.to_string())?;
                Action::Do(command)
            }
            Shape::Wait => {
                self.expect_end(&command.to_string())?;
                Action::Wait(self.axis_of(&command)?)
            }
            Shape::Delay => Action::Delay(self.delay(&command)?),
            Shape::Jog => {
                let direction = self.direction(&command)?;
                self.expect_end(&format!("{command}{}", direction.sign()))?;
                Action::Jog {
                    axis: self.axis_of(&command)?,
                    direction,
                }
            }
            Shape::ZMove => {
                let direction = self.direction(&command)?;
                self.expect_end(&format!("{command}{}", direction.sign()))?;
                Action::SameInAscii(Cmd4crCommand::ZMove {
                    axis: self.axis_of(&command)?,
                    direction,
                })
            }
            Shape::Home => self.home(&command)?,
            Shape::Circle | Shape::Arc | Shape::HelixCircle | Shape::HelixArc => {
                return Err(self.error_here(
                    ErrorCode::TokenError,
                    format!(
                        "`{name}` needs its axes and P (CW) or N (CCW): {}",
                        example(command.info.shape)
                    ),
                ));
            }
            Shape::Variable => return Err(self.error_here(ErrorCode::UnknownError, name.into())),
        };
        Ok(Statement::Action(action))
    }

    fn axis_of(&self, command: &Command) -> Result<Axis, LineError> {
        command.axis().ok_or_else(|| {
            self.error_here(
                ErrorCode::UnknownError,
                format!("`{command}` needs an axis"),
            )
        })
    }

    /// `NAME=value` for a register (and what goes wrong with it).
    fn set(&mut self, command: Command) -> Result<Statement, LineError> {
        if !command.info.writable() {
            let only_read = |parser: &Self| {
                parser.error_at(
                    0,
                    ErrorCode::Error,
                    format!(
                        "`{command}` only returns a value: use it in an assignment (V1={command}) or a condition (IF {command}=1)"
                    ),
                )
            };
            return Err(match self.expect_equals(only_read) {
                Ok(()) => self.error_at(
                    0,
                    ErrorCode::EqualsError,
                    format!("`{command}` returns a value and cannot be set"),
                ),
                Err(e) => e,
            });
        }
        let at = self.next;
        self.expect_equals(|parser| {
            parser.error_at(
                at,
                ErrorCode::MissingEquals,
                format!(
                    "`{}`: set {command} with `=`, e.g. {command}={}",
                    parser.statement_text(),
                    command.info.values().map_or(0, |r| r.min.max(0))
                ),
            )
        })?;
        let value = self.value(&command)?;
        Ok(Statement::Action(Action::Set { command, value }))
    }

    /// The source left of the first `=`.
    fn left_of_equals(&self) -> &str {
        let end = self
            .tokens
            .iter()
            .position(|t| t.lex == Lex::Symbol(Symbol::Equals))
            .unwrap_or(self.tokens.len());
        match (
            self.tokens.first(),
            end.checked_sub(1).and_then(|i| self.tokens.get(i)),
        ) {
            (Some(a), Some(b)) => self.line.get(a.span.start..b.span.end).unwrap_or(""),
            _ => "",
        }
    }

    /// The right of `NAME=`: a number or a variable, nothing else (T5-43
    /// "Error not Number of Var": `DO=PX`).
    fn value(&mut self, command: &Command) -> Result<Value, LineError> {
        let range = command.info.values().unwrap_or(I32);
        let start = self.next;
        if let Some(number) = self.signed_number(range) {
            let number = number.map_err(|e| {
                let written = self.text_between(start, self.next);
                with_detail(e, format!("{command}={written}: {command} takes {range}"))
            })?;
            return self.after_value(command, start, Value::Number(number));
        }
        let Some(token) = self.bump() else {
            return Err(self.error_next(
                ErrorCode::AssignmentError,
                format!("nothing after `{command}=`: give a number ({range}) or a variable"),
            ));
        };
        let value = match token.lex {
            Lex::Variable(index) => Value::Variable(self.variable_index(index)?),
            Lex::Command { name, axis } => {
                let read = self.command(name, axis)?;
                let (code, detail) = if read.info.readable() {
                    (
                        ErrorCode::NotNumberOrVar,
                        format!(
                            "`{command}={read}`: a command is set from a number or a variable; read {read} into a variable first (V1={read}, then {command}=V1)"
                        ),
                    )
                } else {
                    (ErrorCode::AssignmentError, not_a_value(&read))
                };
                return Err(self.error_at(start, code, detail));
            }
            Lex::Word | Lex::Other => return Err(self.unknown(&token)),
            Lex::Symbol(Symbol::DoubleEquals | Symbol::Equals) => {
                return Err(self.error_here(
                    ErrorCode::Error,
                    "`==` is not A-Script: a single `=` sets a value".into(),
                ));
            }
            Lex::Symbol(Symbol::Tilde) => return Err(self.not_number_or_var(command, start)),
            _ => {
                return Err(self.error_here(
                    ErrorCode::AssignmentError,
                    format!("`{}` is not a value for {command}", self.text(&token)),
                ));
            }
        };
        self.after_value(command, start, value)
    }

    /// Nothing may follow a command's value; an operator makes it an
    /// operation, which a command is not set from.
    fn after_value(
        &self,
        command: &Command,
        start: usize,
        value: Value,
    ) -> Result<Value, LineError> {
        match self.peek_lex() {
            None => Ok(value),
            Some(Lex::Symbol(s)) if binary(s).is_some() => {
                Err(self.not_number_or_var(command, start))
            }
            Some(_) => self
                .expect_end(&format!("{command}={value}"))
                .map(|()| value),
        }
    }

    fn not_number_or_var(&self, command: &Command, start: usize) -> LineError {
        self.error_at(
            start,
            ErrorCode::NotNumberOrVar,
            format!(
                "`{command}={}`: a command is set from a number or a variable, not an operation; compute it into a variable first (V1=…, then {command}=V1)",
                self.text_from(start)
            ),
        )
    }

    /// `DELAY=ms`: a number or a variable (T5-43 "Token Error":
    /// `DELAY=V1+200`).
    fn delay(&mut self, command: &Command) -> Result<Value, LineError> {
        self.expect_equals(|parser| {
            parser.error_next(
                ErrorCode::MissingEquals,
                format!(
                    "`{}`: write DELAY=ms, e.g. DELAY=100",
                    parser.statement_text()
                ),
            )
        })?;
        let start = self.next;
        let rest = self.text_from(start).to_string();
        let token_error = |parser: &Self| {
            parser.error_at(
                start,
                ErrorCode::TokenError,
                format!("DELAY takes a number of ms or a variable, not `{rest}`"),
            )
        };
        let range = command.info.values().unwrap_or(I32);
        let value = match self.signed_number(range) {
            Some(number) => Value::Number(
                number
                    .map_err(|e| with_detail(e, format!("DELAY={rest}: a delay takes {range}")))?,
            ),
            None => match self.bump().map(|t| t.lex) {
                Some(Lex::Variable(index)) => Value::Variable(self.variable_index(index)?),
                _ => return Err(token_error(self)),
            },
        };
        if self.peek().is_some() {
            return Err(token_error(self));
        }
        Ok(value)
    }

    /// The `+` or `-` right after JOGX, HOMEX, ZMOVEX.
    fn direction(&mut self, command: &Command) -> Result<Direction, LineError> {
        let direction = match self.peek_adjacent() {
            Some(Lex::Symbol(Symbol::Plus)) => Direction::Plus,
            Some(Lex::Symbol(Symbol::Minus)) => Direction::Minus,
            _ => {
                return Err(self.error_next(
                    ErrorCode::TokenError,
                    format!("`{command}` needs a direction + or - right after it: {command}+"),
                ));
            }
        };
        self.bump();
        Ok(direction)
    }

    /// `HOME[axis][+/-][mode]`, mode 0–12 (Appendix A).
    fn home(&mut self, command: &Command) -> Result<Action, LineError> {
        let direction = self.direction(command)?;
        let written = format!("{command}{}", direction.sign());
        let Some(Lex::Number(n)) = self.peek_adjacent() else {
            return Err(self.error_next(
                ErrorCode::TokenError,
                format!("`{written}` needs a homing mode 0-12 (Appendix A): {written}0"),
            ));
        };
        self.bump();
        let mode = match n {
            Some(n) if HOME_MODE.contains(n) => u8::try_from(n).unwrap_or(0),
            _ => {
                return Err(self.error_here(
                    ErrorCode::AssignmentError,
                    format!(
                        "`{written}{}`: the homing modes are 0-12 (Appendix A)",
                        self.text_between(self.next - 1, self.next)
                    ),
                ));
            }
        };
        self.expect_end(&format!("{written}{mode}"))?;
        Ok(Action::Home {
            axis: self.axis_of(command)?,
            direction,
            mode,
        })
    }

    /// `X1000`, `X-20000Y15000`, `XV1`: axes with adjacent targets.
    fn movement(&mut self, first: Axis) -> Result<Statement, LineError> {
        let mut targets: Vec<Target> = Vec::new();
        let mut axis = first;
        loop {
            let letter = axis.letter();
            if targets.iter().any(|t| t.axis == axis) {
                return Err(self.error_here(
                    ErrorCode::Error,
                    format!("{letter} appears twice in one move"),
                ));
            }
            let number = match self.peek_adjacent() {
                Some(_) => self.signed_number(POSITION),
                None => None,
            };
            let value = match (number, self.peek_adjacent()) {
                (Some(number), _) => Value::Number(number.map_err(|e| {
                    with_detail(e, format!("{letter}: positions are {POSITION} (§1.2)"))
                })?),
                (None, Some(Lex::Variable(index))) => {
                    self.bump();
                    Value::Variable(self.variable_index(index)?)
                }
                (None, _) => {
                    return Err(self.error_next(
                        ErrorCode::TokenError,
                        format!(
                            "`{letter}` needs a target right after it: {letter}1000 or {letter}V1"
                        ),
                    ));
                }
            };
            targets.push(Target { axis, value });
            match self.peek_adjacent() {
                Some(Lex::Axis(next)) => {
                    self.bump();
                    axis = next;
                }
                _ => break,
            }
        }
        let written = Action::Move(targets);
        self.expect_end(&written.to_string())?;
        Ok(Statement::Action(written))
    }

    /// `CIRXYP c1:c2`, `ARCXYN c1:c2:θ`, `CIRTP c1:c2:z`, `ARCTN c1:c2:θ:z`
    /// (§2.3.2, §2.3.3), numbers only, as the ASCII syntax they share.
    fn curve(
        &mut self,
        name: &'static str,
        axes: Option<[Axis; 2]>,
        rotation: Rotation,
    ) -> Result<Statement, LineError> {
        let kind = forms(name).next().map_or(Shape::Circle, |c| c.shape);
        let word = self
            .statement_text()
            .split(':')
            .next()
            .unwrap_or("")
            .to_string();
        if let Some([a, b]) = axes
            && a == b
        {
            return Err(self.error_here(
                ErrorCode::Error,
                format!("`{word}`: {name} needs two different axes"),
            ));
        }
        let fields: &[(&str, ValueRange)] = match kind {
            Shape::Arc => &[("C1", POSITION), ("C2", POSITION), ("θ", ANGLE)],
            Shape::HelixCircle => &[("C1", POSITION), ("C2", POSITION), ("Z", POSITION)],
            Shape::HelixArc => &[
                ("C1", POSITION),
                ("C2", POSITION),
                ("θ", ANGLE),
                ("Z", POSITION),
            ],
            _ => &[("C1", POSITION), ("C2", POSITION)],
        };
        let syntax = fields
            .iter()
            .map(|(f, _)| format!("[{f}]"))
            .collect::<Vec<_>>()
            .join(":");
        let mut values = Vec::with_capacity(fields.len());
        for (i, (field, range)) in fields.iter().enumerate() {
            if i > 0 {
                if self.peek_adjacent() != Some(Lex::Symbol(Symbol::Colon)) {
                    return Err(self.error_next(
                        ErrorCode::TokenError,
                        format!("`{word}` needs {syntax}: {}", example(kind)),
                    ));
                }
                self.bump();
            }
            let number = match self.peek_adjacent() {
                Some(_) => self.signed_number(*range),
                None => None,
            };
            match (number, self.peek_adjacent()) {
                (Some(number), _) => {
                    values.push(number.map_err(|e| {
                        with_detail(e, format!("{word}: {field} is outside {range}"))
                    })?)
                }
                (None, Some(Lex::Variable(_))) => {
                    return Err(self.error_next(
                        ErrorCode::TokenError,
                        format!("`{word}` takes numbers only (§2.3.2): {}", example(kind)),
                    ));
                }
                (None, _) => {
                    return Err(self.error_next(
                        ErrorCode::TokenError,
                        format!("`{word}` needs {syntax}: {}", example(kind)),
                    ));
                }
            }
        }
        let v = |i: usize| values.get(i).copied().unwrap_or(0);
        let command = match (kind, axes) {
            (Shape::Arc, Some(axes)) => Cmd4crCommand::Arc {
                axes,
                rotation,
                centre: [v(0), v(1)],
                angle: v(2),
            },
            (Shape::HelixCircle, _) => Cmd4crCommand::HelicalCircle {
                rotation,
                centre: [v(0), v(1)],
                z: v(2),
            },
            (Shape::HelixArc, _) => Cmd4crCommand::HelicalArc {
                rotation,
                centre: [v(0), v(1)],
                angle: v(2),
                z: v(3),
            },
            (_, axes) => Cmd4crCommand::Circle {
                axes: axes.unwrap_or([Axis::X, Axis::Y]),
                rotation,
                centre: [v(0), v(1)],
            },
        };
        let action = Action::SameInAscii(command);
        self.expect_end(&action.to_string())?;
        Ok(Statement::Action(action))
    }

    /// A line starting with `V[n]`: `V1=expr`.
    fn variable_statement(&mut self, index: Option<u64>) -> Result<Statement, LineError> {
        let variable = self.variable_index(index)?;
        self.expect_equals(|parser| {
            parser.error_next(
                ErrorCode::MissingEquals,
                format!(
                    "`{}`: set V{variable} with `=`, e.g. V{variable}=0",
                    parser.statement_text()
                ),
            )
        })?;
        let value = self.expression()?;
        Ok(Statement::Action(Action::Let { variable, value }))
    }

    /// The right of `V[n]=`: an operand, `~operand`, or one operation of
    /// Table 2-32.
    fn expression(&mut self) -> Result<Expr, LineError> {
        if self.peek().is_none() {
            return self.operand(Place::Assigned).map(Expr::Operand);
        }
        self.refuse_double_equals()?;
        let start = self.next;
        if self.peek_lex() == Some(Lex::Symbol(Symbol::Tilde)) {
            self.bump();
            let operand = self.operand(Place::Operation)?;
            self.one_operation(start)?;
            return Ok(Expr::Not(operand));
        }
        let left = match self.operand(Place::Assigned) {
            Ok(left) => left,
            Err(e) => {
                // The same operand is an "Operation Argument Error" when an
                // operator follows it (`V1=ABS+1`).
                let operator_follows =
                    matches!(self.peek_lex(), Some(Lex::Symbol(s)) if binary(s).is_some());
                if e.code == ErrorCode::AssignmentError && operator_follows {
                    self.next = start;
                    self.operand(Place::Operation)?;
                }
                return Err(e);
            }
        };
        let Some(token) = self.peek().cloned() else {
            return Ok(Expr::Operand(left));
        };
        let op = match token.lex {
            Lex::Symbol(s) => match binary(s) {
                Some(op) => op,
                None if comparison(s).is_some() => {
                    return Err(self.error_next(
                        ErrorCode::TokenError,
                        format!(
                            "`{}` compares: an assignment takes one operation of Table 2-32 (+ - * / % >> << & | ~)",
                            self.text(&token)
                        ),
                    ));
                }
                None => {
                    return Err(self.error_next(
                        ErrorCode::TokenError,
                        format!("unexpected `{}` after `{left}`", self.text_from(self.next)),
                    ));
                }
            },
            _ => {
                return Err(self.error_next(
                    ErrorCode::TokenError,
                    format!("unexpected `{}` after `{left}`", self.text_from(self.next)),
                ));
            }
        };
        self.bump();
        let right = self.operand(Place::Operation)?;
        self.one_operation(start)?;
        Ok(Expr::Binary { left, op, right })
    }

    /// Nothing may follow an operation: the manual never writes two on a
    /// line (T2-32; digest §5.3), so we do not guess a precedence.
    fn one_operation(&self, start: usize) -> Result<(), LineError> {
        if self.peek().is_none() {
            return Ok(());
        }
        Err(self.error_next(
            ErrorCode::TokenError,
            format!(
                "`{}`: one operation per line (Table 2-32); split it, e.g. V1=V2+V3 then V1=V1+V4",
                self.text_from(start)
            ),
        ))
    }
}

/// The code for a bad or missing index after `name`: SR's index is a
/// program number, every other index a bit (`DO10`).
fn index_code(name: &str, given: bool) -> ErrorCode {
    match (name, given) {
        ("SR", true) => ErrorCode::ErrorPrg,
        ("SR", false) => ErrorCode::ErrorPrgNumber,
        _ => ErrorCode::BitError,
    }
}

fn index_taken(command: &Command) -> bool {
    matches!(command.address, Address::Index(_))
}

fn not_a_value(command: &Command) -> String {
    match command.info.shape {
        Shape::Register(_) => format!("`{command}` can only be set, not read"),
        _ => format!("`{command}` is a command, not a value"),
    }
}

fn with_detail(mut error: LineError, detail: String) -> LineError {
    error.detail = detail;
    error
}

fn example(kind: Shape) -> &'static str {
    match kind {
        Shape::Arc => "ARCXYP0:0:90000",
        Shape::HelixCircle => "CIRTP1000:0:500",
        Shape::HelixArc => "ARCTP0:0:90000:500",
        _ => "CIRXYP1000:0",
    }
}

fn comparison(symbol: Symbol) -> Option<Comparison> {
    Some(match symbol {
        Symbol::Equals => Comparison::Equal,
        Symbol::NotEqual => Comparison::NotEqual,
        Symbol::Greater => Comparison::Greater,
        Symbol::Less => Comparison::Less,
        Symbol::GreaterOrEqual => Comparison::GreaterOrEqual,
        Symbol::LessOrEqual => Comparison::LessOrEqual,
        _ => return None,
    })
}

fn binary(symbol: Symbol) -> Option<BinaryOp> {
    Some(match symbol {
        Symbol::Plus => BinaryOp::Add,
        Symbol::Minus => BinaryOp::Subtract,
        Symbol::Star => BinaryOp::Multiply,
        Symbol::Slash => BinaryOp::Divide,
        Symbol::Percent => BinaryOp::Modulus,
        Symbol::ShiftRight => BinaryOp::ShiftRight,
        Symbol::ShiftLeft => BinaryOp::ShiftLeft,
        Symbol::Ampersand => BinaryOp::And,
        Symbol::Bar => BinaryOp::Or,
        _ => return None,
    })
}

#[cfg(test)]
mod tests;
