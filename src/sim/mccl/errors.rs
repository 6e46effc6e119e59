//! The controller's error codes (manual Ch14) as data, and the rule of
//! which input causes which (the manual gives the table, not the causes:
//! these are the simulator's reading, listed in [`super::choices`]).
//!
//! Positive codes come from reading the text of a line (an unknown
//! mnemonic, a malformed parameter, line noise, a line too long);
//! negative ones from checking or executing a command.

use std::fmt;

/// An MCCL error code, as `?code` reports it and `TE` tells it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Code(pub i32);

impl Code {
    pub const NONE: Code = Code(0);
    /// A two-letter word that is no mnemonic, or no two letters at all.
    pub const UNRECOGNIZED: Code = Code(1);
    /// A parameter that is no number, string or `@n` where one is due; an
    /// empty command; a line breaking the one-RP or DM-with-HM rules.
    pub const BAD_FORMAT: Code = Code(2);
    /// Line noise: a byte that is no 7-bit text in a line.
    pub const IO_ERROR: Code = Code(3);
    pub const TOO_LONG: Code = Code(4);
    /// A value outside the command's range, or a real where an integer is due.
    pub const PARAMETER: Code = Code(-1);
    /// A command the addressed axis' kind does not take ("applies to").
    pub const INVALID_FOR_AXIS: Code = Code(-2);
    pub const NEGATIVE_REPEAT: Code = Code(-3);
    pub const MACRO_DEFINE_NOT_FIRST: Code = Code(-4);
    pub const MACRO_OUT_OF_RANGE: Code = Code(-5);
    pub const MACRO_MISSING: Code = Code(-6);
    pub const CANCELED: Code = Code(-7);
    pub const CONTOUR_NOT_FIRST: Code = Code(-8);
    pub const CONTOUR_PARAMETER: Code = Code(-9);
    pub const CONTOUR_NO_AXIS: Code = Code(-10);
    /// A move or wait on an axis holding a motor error (limit, following error).
    pub const AXIS_ERROR: Code = Code(-13);
    pub const NO_AXIS: Code = Code(-14);
    pub const AXIS_NOT_ASSIGNED: Code = Code(-15);
    pub const AXIS_ALREADY_ASSIGNED: Code = Code(-16);
    pub const AXIS_DUPLICATE: Code = Code(-17);
    pub const NO_MEMORY: Code = Code(-18);
    pub const UNKNOWN_VARIABLE: Code = Code(-19);
    pub const BAD_TASK: Code = Code(-20);
    pub const NOT_SUPPORTED: Code = Code(-21);

    /// The manual's description (Ch14), if the code is one of its table.
    pub fn meaning(self) -> Option<&'static str> {
        CODES
            .iter()
            .find(|(code, _)| *code == self)
            .map(|(_, meaning)| *meaning)
    }
}

impl fmt::Display for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// Ch14 "Controller Error Codes" (−11 and −12 are not in the table).
pub const CODES: &[(Code, &str)] = &[
    (Code(0), "No error"),
    (Code(1), "Unrecognized command"),
    (Code(2), "Bad command format"),
    (Code(3), "I/O error"),
    (Code(4), "Command string too long"),
    (Code(-1), "Command Parameter Error"),
    (Code(-2), "Command Code Invalid"),
    (Code(-3), "Negative Repeat Count"),
    (Code(-4), "Macro Define Command Not First"),
    (Code(-5), "Macro Number Out of Range"),
    (Code(-6), "Macro Doesn't Exist"),
    (Code(-7), "Command Canceled by User"),
    (Code(-8), "Contour Path Command Not First"),
    (Code(-9), "Contour Path Command Parameter Invalid"),
    (Code(-10), "Contour Path Command Doesn't Specify an AXIS"),
    (
        Code(-13),
        "Axis error (over travel error, max. following error exceeded)",
    ),
    (Code(-14), "No axis specified"),
    (Code(-15), "Axis not assigned"),
    (Code(-16), "Axis already assigned"),
    (Code(-17), "Axis duplicate assigned"),
    (Code(-18), "Insufficient memory"),
    (Code(-19), "Unrecognized variable name"),
    (Code(-20), "Invalid background task ID"),
    (Code(-21), "Command not supported"),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_is_chapter_14() {
        assert_eq!(CODES.len(), 24);
        assert_eq!(Code::CANCELED.meaning(), Some("Command Canceled by User"));
        assert_eq!(Code(-11).meaning(), None, "absent from the manual");
        assert_eq!(Code(-12).meaning(), None, "absent from the manual");
    }
}
