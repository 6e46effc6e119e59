//! What a host run says: the next step it needs, how it ended, and the
//! events a console shows as it goes.

use super::*;

/// What the run needs done next.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum HostStep {
    /// Send this console line; call [`AScriptRun::on_reply`] with its answer.
    Send(String),
    /// Call [`AScriptRun::on_wake`] after this long.
    Wake(Duration),
    /// The run is over.
    Finished(HostEnd),
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct HostEnd {
    /// The programs that stopped in the error state, and why.
    pub failures: Vec<String>,
    /// A command that got no answer ended the run.
    pub lost: Option<String>,
    /// Programs left paused with nothing running to continue them.
    pub paused: Vec<u8>,
}

impl HostEnd {
    /// Every program ran to its END.
    pub fn ok(&self) -> bool {
        self.failures.is_empty() && self.lost.is_none() && self.paused.is_empty()
    }
}

impl fmt::Display for HostEnd {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(lost) = &self.lost {
            return write!(f, "the run ended: {lost}");
        }
        if !self.failures.is_empty() {
            return write!(f, "{}", self.failures.join("; "));
        }
        if !self.paused.is_empty() {
            return write!(
                f,
                "{} left paused, nothing running can continue it",
                list_programs(&self.paused)
            );
        }
        f.write_str("every program ran to its END")
    }
}

/// Something worth telling the user, from program `program`'s source line
/// `line`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HostEvent {
    /// None for news of the run as a whole.
    pub program: Option<u8>,
    pub line: usize,
    pub kind: HostEventKind,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum HostEventKind {
    Started,
    /// The program reached its END.
    Finished,
    /// A statement that acts was sent as `sent` and answered `answer`.
    Sent {
        statement: String,
        sent: String,
        answer: String,
    },
    /// `?Error Moving` with no latched error anywhere: carried on.
    Busy {
        statement: String,
        sent: String,
    },
    /// `SR[target]=…`.
    Controlled {
        target: u8,
        control: ProgramControl,
    },
    /// A runtime error, handled by SUB 31.
    Handler {
        reason: String,
    },
    /// A runtime error that stopped the program (error state).
    Failed {
        reason: String,
    },
    /// SAP could not be read: SUB 31 returns to the failed statement.
    Note(String),
}

impl fmt::Display for HostEvent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let program = self
            .program
            .map_or_else(String::new, |n| format!("PRG {n} "));
        let at = format!("{program}line {}", self.line);
        match &self.kind {
            HostEventKind::Started => write!(f, "{program}started from the host"),
            HostEventKind::Finished => write!(f, "{program}reached END (line {})", self.line),
            HostEventKind::Sent {
                statement,
                sent,
                answer,
            } if statement == sent => write!(f, "{at}: {sent} → {answer}"),
            HostEventKind::Sent {
                statement,
                sent,
                answer,
            } => write!(f, "{at}: {statement} as {sent} → {answer}"),
            HostEventKind::Busy { statement, sent } => write!(
                f,
                "{at}: {statement} ({sent}) found its axis busy, no error latched: went on"
            ),
            HostEventKind::Controlled { target, control } => {
                write!(f, "{at}: {} PRG {target}", control.verb())
            }
            HostEventKind::Handler { reason } => {
                write!(f, "{at}: {reason}; SUB 31 handles it")
            }
            HostEventKind::Failed { reason } => {
                write!(f, "{at}: {reason}; {program}stopped (error state)")
            }
            HostEventKind::Note(text) => write!(f, "{at}: {text}"),
        }
    }
}

impl HostEvent {
    /// How the console should show it.
    pub fn tone(&self) -> Tone {
        match &self.kind {
            HostEventKind::Started | HostEventKind::Finished | HostEventKind::Controlled { .. } => {
                Tone::Headline
            }
            HostEventKind::Sent { .. } => Tone::Plain,
            HostEventKind::Busy { .. } => Tone::Minor,
            HostEventKind::Handler { .. } | HostEventKind::Note(_) => Tone::Warning,
            HostEventKind::Failed { .. } => Tone::Error,
        }
    }
}

impl From<HostEnd> for program::HostEnd {
    fn from(end: HostEnd) -> program::HostEnd {
        program::HostEnd {
            ok: end.ok(),
            summary: end.to_string(),
        }
    }
}
