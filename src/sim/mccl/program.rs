//! A command sequence the interpreter runs (a typed line, a macro, the
//! rest of a `GT0` line) and the placement rules checked before any of it
//! runs (manual Ch2, Ch7 CP, Ch10 MD, Ch12 RP, Ch13 DM/HM).

use std::sync::Arc;

use super::errors::Code;
use super::lexer::Command;

/// Where a sequence came from (what single stepping and BK show).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    Line,
    Macro(u16),
}

#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    pub commands: Vec<Command>,
    pub origin: Origin,
}

impl Program {
    pub fn new(commands: Vec<Command>, origin: Origin) -> Arc<Program> {
        Arc::new(Program { commands, origin })
    }
}

/// A placement rule broken: the code and the index of the command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Misplaced {
    pub code: Code,
    pub at: usize,
}

/// The rules for a sequence (the body of a macro, or a line without MD):
/// MD only first (−4, and never inside a body), CP only first (−8), one RP
/// (Ch12 "There can be only one RP command"), not both DM and HM. The last
/// two have no code of their own; they are reported as bad format (2).
pub fn check(commands: &[Command], is_body: bool) -> Result<(), Misplaced> {
    let mut repeats = 0;
    let (mut decimal, mut hex) = (false, false);
    for (at, command) in commands.iter().enumerate() {
        let misplaced = |code| Err(Misplaced { code, at });
        match command.mnemonic() {
            "MD" if at > 0 || is_body => return misplaced(Code::MACRO_DEFINE_NOT_FIRST),
            "CP" if at > 0 => return misplaced(Code::CONTOUR_NOT_FIRST),
            "RP" => {
                repeats += 1;
                if repeats > 1 {
                    return misplaced(Code::BAD_FORMAT);
                }
            }
            "DM" => decimal = true,
            "HM" => hex = true,
            _ => {}
        }
        if decimal && hex {
            return misplaced(Code::BAD_FORMAT);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::mccl::lexer::{Radix, lex};

    fn checked(line: &str, is_body: bool) -> Result<(), (i32, usize)> {
        let commands = lex(line, Radix::Decimal).expect("lexes");
        check(&commands, is_body).map_err(|m| (m.code.0, m.at))
    }

    #[test]
    fn placement_rules() {
        assert_eq!(checked("2MR1000,WS0.5,MR-1000,WS0.5,RP6", false), Ok(()));
        assert_eq!(checked("MD3,1MR1000", false), Ok(()));
        assert_eq!(checked("1MN,MD3,1MR1000", false), Err((-4, 1)));
        assert_eq!(checked("MD4", true), Err((-4, 0)), "MD inside a macro");
        assert_eq!(checked("1CP1,1MA10000,2MA20000", false), Ok(()));
        assert_eq!(checked("1MN,1CP1,1MA100", false), Err((-8, 1)));
        assert_eq!(checked("1TP,RP2,RP3", false), Err((2, 2)));
        assert_eq!(checked("DM,1TS,HM", false), Err((2, 2)));
    }
}
