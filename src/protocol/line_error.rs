//! Why a console line was refused before anything was sent, typed to the
//! edge: every family's parser has its own error enum naming the command,
//! the operand, its range and the manual section; the family seam
//! ([`crate::protocol::console::FamilyConsole::prepare`],
//! [`crate::protocol::Family::encode_line`]) carries that error as it is,
//! with the kind of mistake a caller may act on. It becomes text only where
//! a technician reads it (the console, the CLI), and the text is the
//! family's own.

use std::fmt;

/// What kind of mistake a refused line holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mistake {
    /// Nothing to send.
    Empty,
    /// Not a command of the family, or not written as the manual writes it.
    Syntax,
    /// An operand outside the range or the choices the manual gives.
    Range,
    /// The line is for a module address the family's modules cannot have,
    /// or not the one this session talks to.
    Address,
    /// A command this console does not send (one that waits for keys it
    /// does not send, one the manual gives no frame for).
    NotSent,
}

/// A family's own parse or validation error, as the seam carries it.
pub trait FamilyLineError: std::error::Error + Send + Sync + 'static {
    /// The kind of mistake.
    fn mistake(&self) -> Mistake;
}

/// A refused console line: the family's typed error inside.
#[derive(Debug)]
pub struct LineError(Box<dyn FamilyLineError>);

impl LineError {
    /// The kind of mistake.
    pub fn mistake(&self) -> Mistake {
        self.0.mistake()
    }

    /// The family's own error, when it is a `T` (`tmcl::LineError`,
    /// `cmd4cr::CommandError`, …).
    pub fn downcast_ref<T: std::error::Error + 'static>(&self) -> Option<&T> {
        let inner: &(dyn std::error::Error + 'static) = self.0.as_ref();
        inner.downcast_ref()
    }
}

impl<E: FamilyLineError> From<E> for LineError {
    fn from(error: E) -> LineError {
        LineError(Box::new(error))
    }
}

impl fmt::Display for LineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.0, f)
    }
}

impl std::error::Error for LineError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.0.source()
    }
}

impl From<LineError> for String {
    fn from(error: LineError) -> String {
        error.to_string()
    }
}
