//! The line the controller is busy with, as the command pane shows it: a
//! line that runs until its answer (an MCCL wait, repeat or macro call)
//! holds the controller, which takes nothing else meanwhile but the
//! line's abort and pause bytes. The pane says so above the prompt, and
//! its keys abort it (the cancel key, Escape by default) or pause and
//! resume it (Space, on an empty command line: the byte the controller
//! itself takes for it).

use crate::device::Busy;
use crate::protocol::Family;

/// How the pane names the busy line: its bytes as the family shows them,
/// without the line end.
fn line_of(busy: &Busy, family: Option<&Family>) -> String {
    let shown = family.map_or_else(
        || String::from_utf8_lossy(&busy.bytes).into_owned(),
        |f| (f.show_bytes)(&busy.bytes),
    );
    shown.trim_end_matches("\\r").trim().to_string()
}

/// The row above the prompt while the controller is busy.
pub(super) fn hint(busy: &Busy, family: Option<&Family>, abort_key: &str) -> String {
    let line = line_of(busy, family);
    if busy.aborting {
        format!("aborting {line}: waiting for the controller's answer")
    } else if busy.paused {
        format!("paused {line}: Space resumes, {abort_key} aborts")
    } else if busy.pausable {
        format!("busy {line}: {abort_key} aborts, Space pauses (polling waits)")
    } else {
        format!("busy {line}: {abort_key} aborts (polling waits)")
    }
}

/// What the status bar says while the controller is busy.
pub(super) fn activity(busy: &Busy, family: Option<&Family>) -> String {
    let state = if busy.aborting {
        "ABORTING"
    } else if busy.paused {
        "PAUSED"
    } else {
        "BUSY"
    };
    format!("{state} {}", line_of(busy, family))
}
