//! A-Script, the CMD-4CR's standalone language (manual §2.7 and §5): the
//! command set as data, a line lexer and parser to an AST, a checker that
//! reports the compile errors of Table 5-43 with their line numbers, the
//! program compiled into steps an interpreter runs, the ASCII command each
//! statement corresponds to, and token classes for an editor's colours.
//! Pure: no I/O.
//!
//! - [`compile`] a source into a [`Program`] (or every [`CompileError`]);
//!   [`check`] lists errors and warnings for an editor.
//! - [`Program::steps`] is the compiled program: [`Op`]s with resolved jump
//!   targets; [`Program::program`] and [`Program::subroutine`] give where
//!   PRG n and SUB n start, [`Program::error_handler`] SUB 31.
//! - [`Expr::evaluate`] and [`Condition::evaluate`] compute as the
//!   controller does, so every executor agrees.
//! - [`ascii_equivalent`] is the ASCII text a statement becomes (`ECLEARX`
//!   → `CLRX`), [`ascii_command`] the typed command of the one ASCII parser
//!   ([`super::parse_command`]); [`Program::host_problems`] lists what has
//!   none.
//! - [`tokens`] colours a line ([`TokenClass`]).
//!
//! ```text
//! source     := { line '\n' }
//! line       := [ statement ] [ ';' comment ]
//! statement  := 'PRG' n | 'END' | 'SUB' n | 'ENDSUB'          n: PRG 0-3, SUB 0-31
//!             | 'IF' cond | 'ELSEIF' cond | 'ELSE' | 'ENDIF'
//!             | 'WHILE' cond | 'ENDWHILE' | 'GOSUB' n
//!             | 'V'n '=' expr                                V0-V99
//!             | command '=' value                            HSPD=20000, DO1=V2, SR0=1
//!             | 'DELAY=' value | 'WAIT'axis | action         ABORTX, ABS, BUFON, ECLEARX
//!             | move | 'JOG'axis dir | 'HOME'axis dir mode | 'ZMOVE'axis dir
//!             | 'CIR'axis axis rot c ':' c | 'ARC'axis axis rot c ':' c ':' θ
//!             | 'CIRT' rot c ':' c ':' z | 'ARCT' rot c ':' c ':' θ ':' z
//! move       := { axis target }                              X1000Y-5, XV1 (adjacent)
//! value      := number | 'V'n                                T5-43 "Error not Number of Var"
//! expr       := operand | '~' operand | operand op operand    op: + - * / % >> << & |
//! cond       := operand cmp operand                          cmp: = != > < >= <=
//! operand    := number | 'V'n | readable command             MSTX, DI1, HSPD
//! ```
//!
//! Where the manual is silent, these are our readings (each is tested):
//!
//! - Every example is in capitals and §5 never says lower case is
//!   accepted: lower case is an "Unknown Error" with a hint. Spaces may
//!   separate a keyword from its number or condition and surround `=` and
//!   operators (`IO = 0`, `WHILE V30 < 10`, `GOSUB 1`); a command word, its
//!   axis or index and a move's or circle's numbers are written together
//!   as in ASCII (`HOMEX-6`, `X1000Y2000`, `CIRXYP1000:0`).
//! - One operation per line: the manual never shows two (T2-32, digest
//!   §5.3) and gives no precedence, so a second operator is a "Token
//!   Error" rather than a guess; conditions compare two operands and take
//!   no operation (Ex 7 computes `V2=V1&7` before `IF V2!=0`).
//! - A command is set from a number or a variable (`DO=PX` is "Error not
//!   Number of Var"); an operation there gets the same code. `DELAY` takes
//!   a number or a variable; anything else is a "Token Error"
//!   (`DELAY=V1+200`). A move target may be a variable (`XV1`, Ex 6); the
//!   numbers of CIR, ARC, CIRT, ARCT and the homing mode may not ("same
//!   syntax as ASCII", §2.3.4).
//! - Codes for errors Table 5-43 gives no example of: an index out of
//!   range is a "BIT Error" (`DI5`, `IO33`, `PWM3`), except SR's, which is
//!   a program number ("Error PRG"); a value out of its range is an
//!   "Assignment Error" (`DO1=2`, `HOMEX-13`, `X200000000`); setting a
//!   read-only command is "= Error" (`MSTX=0`); structure errors without a
//!   code of their own (ENDIF without IF, a second ELSE, statements outside
//!   any block, PRG 0 defined twice, `==`) are "Error"; words the command
//!   set does not have are "Unknown Error", naming the standalone command
//!   to use when an ASCII-only one is written (`CLRX` → `ECLEAR[axis]`).
//! - A closer left out is reported at its opener's line, once, when the
//!   block around it ends (`PRG 0` / `WHILE 1=1` / `END` is one "Missing
//!   ENDWHILE" on line 2).
//! - GOSUB to a subroutine the source does not define compiles with a
//!   warning: the controller reports the error when the call runs (§2.7.4).
//! - A command's values are those of the ASCII command it pairs with
//!   ([`CommandInfo::ascii_row`]), so the checker and the ASCII parser
//!   agree; the access (read, write) is the standalone table's.
//! - Arithmetic is 32-bit signed: `+ - *` wrap, `/` rounds down (T2-32)
//!   and `%` follows it, shifts by 32 or more leave sign bits, a negative
//!   shift or a division by zero is a runtime error ([`ArithmeticError`]).

mod ascii;
mod ast;
mod commands;
mod errors;
mod highlight;
mod lexer;
mod parser;
mod program;

pub use ascii::{
    HostProblem, ascii_command, ascii_equivalent, buffered_move, buffered_move_command,
};
pub use ast::{
    Action, Address, ArithmeticError, Axis, BinaryOp, Command, Comparison, Condition, Direction,
    EvalError, Expr, Operand, Rotation, Statement, Target, VARIABLES, Value,
};
pub use commands::{
    Ascii, AsciiOnly, COMMANDS, CommandInfo, Shape, ValueRange, ascii_only_command, form, forms,
    is_command,
};
pub use errors::{CompileError, Diagnostic, ERROR_CODES, ErrorCode, ErrorCodeInfo, Warning};
pub use highlight::{TokenClass, tokens};
pub use program::{
    ERROR_HANDLER, Entry, Op, PROGRAMS, Program, SUBROUTINES, SourceStatement, Step, check, compile,
};

/// Parse one line on its own (no block context): its statement, None for
/// a blank or comment line, or the error it would get, reported on line 1.
pub fn parse_statement(line: &str) -> Result<Option<Statement>, CompileError> {
    match parser::parse_line(line) {
        None => Ok(None),
        Some(parsed) => parsed.statement.map(Some).map_err(|e| CompileError {
            line: 1,
            column: e.column,
            code: e.code,
            detail: e.detail,
        }),
    }
}
