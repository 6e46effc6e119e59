//! The compile errors of §5.3 (Table 5-43), in the manual's words, and the
//! diagnostics the checker reports with them.

use std::fmt;

/// One row of Table 5-43: an error code as the controller's compiler names
/// it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ErrorCode {
    UnknownError,
    BitError,
    TokenError,
    EqualsError,
    AssignmentError,
    OperationArgumentError,
    NotNumberOrVar,
    VarRangeError,
    MissingEquals,
    ErrorGosub,
    ErrorSubNumber,
    ErrorSub,
    ErrorEndsub,
    ErrorPrg,
    ErrorPrgNumber,
    MissingEnd,
    MissingEndwhile,
    MissingEndif,
    Error,
}

/// What Table 5-43 says of a code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ErrorCodeInfo {
    pub code: ErrorCode,
    /// The code as the manual writes it: `Missing ENDWHILE`.
    pub text: &'static str,
    pub description: &'static str,
    /// The manual's "Incorrect Code Example" (for the missing-closer codes
    /// the opener alone: the closer the converted table prints is the one
    /// that is missing, digest §5.5).
    pub example: &'static str,
}

const fn code(
    code: ErrorCode,
    text: &'static str,
    description: &'static str,
    example: &'static str,
) -> ErrorCodeInfo {
    ErrorCodeInfo {
        code,
        text,
        description,
        example,
    }
}

/// Table 5-43, A-Script error codes, in the manual's order.
#[rustfmt::skip]
pub const ERROR_CODES: &[ErrorCodeInfo] = &[
    code(ErrorCode::UnknownError, "Unknown Error", "Command cannot be recognized", "PRGA"),
    code(ErrorCode::BitError, "BIT Error", "Specified bit does not exist", "DO10=1"),
    code(ErrorCode::TokenError, "Token Error", "Syntax error", "DELAY=V1+200"),
    code(ErrorCode::EqualsError, "= Error", "Incorrect assignment formula", "V2+1=V3"),
    code(ErrorCode::AssignmentError, "Assignment Error", "Invalid value specified", "V1= ABS"),
    code(ErrorCode::OperationArgumentError, "Operation Argument Error", "Invalid command specified", "V1=V2+ABS"),
    code(ErrorCode::NotNumberOrVar, "Error not Number of Var", "Invalid specification method", "DO=PX"),
    code(ErrorCode::VarRangeError, "Var Range Error", "Exceeds the defined variable range", "V200=1"),
    code(ErrorCode::MissingEquals, "Missing =", "Assignment operator '=' cannot be found", "HSPD*1000"),
    code(ErrorCode::ErrorGosub, "Error GOSUB", "Specified value is outside the range for GOSUB", "GOSUB900"),
    code(ErrorCode::ErrorSubNumber, "Error SUB Number", "Subroutine number is not valid", "GOSUB DI1"),
    code(ErrorCode::ErrorSub, "Error SUB", "Specified value is outside the range for SUB", "SUB5000"),
    code(ErrorCode::ErrorEndsub, "Error ENDSUB", "ENDSUB is missing", "SUB 1"),
    code(ErrorCode::ErrorPrg, "Error PRG", "Specified value is outside the range for PRG", "PRG200"),
    code(ErrorCode::ErrorPrgNumber, "Error PRG Number", "Program number is not valid", "PRG XI3"),
    code(ErrorCode::MissingEnd, "Missing END", "END for PRG missing", "PRG 0"),
    code(ErrorCode::MissingEndwhile, "Missing ENDWHILE", "ENDWHILE for WHILE missing", "WHILE 1=1"),
    code(ErrorCode::MissingEndif, "Missing ENDIF", "ENDIF for IF missing", "IF 1=1"),
    OTHER_SYNTAX_ERRORS,
];

const OTHER_SYNTAX_ERRORS: ErrorCodeInfo =
    code(ErrorCode::Error, "Error", "Other syntax errors", "V1==V2");

impl ErrorCode {
    /// Its row of Table 5-43.
    pub fn info(self) -> &'static ErrorCodeInfo {
        // Every code has a row (a unit test walks them all); the fallback
        // is the table's catch-all row.
        ERROR_CODES
            .iter()
            .find(|row| row.code == self)
            .unwrap_or(&OTHER_SYNTAX_ERRORS)
    }

    /// The code in the manual's words.
    pub fn text(self) -> &'static str {
        self.info().text
    }

    /// The code whose text is `text` (as the manual writes it).
    pub fn from_text(text: &str) -> Option<ErrorCode> {
        ERROR_CODES
            .iter()
            .find(|row| row.text == text)
            .map(|row| row.code)
    }
}

impl fmt::Display for ErrorCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.text())
    }
}

/// A line that would not compile: the manual's error code, where, and what
/// exactly is wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {code}: {detail}")]
pub struct CompileError {
    /// 1-based.
    pub line: usize,
    /// 1-based, in characters: where the offending piece starts.
    pub column: usize,
    pub code: ErrorCode,
    /// What was found and what was expected.
    pub detail: String,
}

/// Something that compiles but will likely not do what was meant.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: warning: {message}")]
pub struct Warning {
    /// 1-based.
    pub line: usize,
    pub column: usize,
    pub message: String,
}

/// An error or a warning, for an editor that marks lines.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Diagnostic {
    Error(CompileError),
    Warning(Warning),
}

impl Diagnostic {
    pub fn line(&self) -> usize {
        match self {
            Diagnostic::Error(e) => e.line,
            Diagnostic::Warning(w) => w.line,
        }
    }

    pub fn column(&self) -> usize {
        match self {
            Diagnostic::Error(e) => e.column,
            Diagnostic::Warning(w) => w.column,
        }
    }

    pub fn is_error(&self) -> bool {
        matches!(self, Diagnostic::Error(_))
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Diagnostic::Error(e) => e.fmt(f),
            Diagnostic::Warning(w) => w.fmt(f),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_has_its_own_row_and_text() {
        let codes = [
            ErrorCode::UnknownError,
            ErrorCode::BitError,
            ErrorCode::TokenError,
            ErrorCode::EqualsError,
            ErrorCode::AssignmentError,
            ErrorCode::OperationArgumentError,
            ErrorCode::NotNumberOrVar,
            ErrorCode::VarRangeError,
            ErrorCode::MissingEquals,
            ErrorCode::ErrorGosub,
            ErrorCode::ErrorSubNumber,
            ErrorCode::ErrorSub,
            ErrorCode::ErrorEndsub,
            ErrorCode::ErrorPrg,
            ErrorCode::ErrorPrgNumber,
            ErrorCode::MissingEnd,
            ErrorCode::MissingEndwhile,
            ErrorCode::MissingEndif,
            ErrorCode::Error,
        ];
        assert_eq!(codes.len(), ERROR_CODES.len());
        for c in codes {
            assert_eq!(c.info().code, c);
            assert_eq!(ErrorCode::from_text(c.text()), Some(c));
        }
    }

    #[test]
    fn an_error_reads_with_its_line_and_the_manuals_wording() {
        let e = CompileError {
            line: 7,
            column: 5,
            code: ErrorCode::MissingEndwhile,
            detail: "the WHILE on line 7 has no ENDWHILE before END on line 9".into(),
        };
        assert_eq!(
            e.to_string(),
            "line 7: Missing ENDWHILE: the WHILE on line 7 has no ENDWHILE before END on line 9"
        );
    }
}
