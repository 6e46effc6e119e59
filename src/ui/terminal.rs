//! The terminal as the console uses it: raw mode, the alternate screen,
//! bracketed paste and (optionally) the mouse, always given back: on quit
//! (the guard is dropped), on panic (a hook restores it before the panic
//! message is printed, so the message is readable), and on SIGTERM/SIGHUP
//! (the loop ends and the guard is dropped).

use std::io::{self, IsTerminal, Write};
use std::sync::Once;
use std::sync::atomic::{AtomicBool, Ordering};

use ratatui::crossterm::event::{
    self, DisableBracketedPaste, DisableFocusChange, DisableMouseCapture, EnableBracketedPaste,
    EnableFocusChange, EnableMouseCapture, Event,
};
use ratatui::crossterm::execute;
use ratatui::crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};
use tokio::sync::mpsc;

/// Whether the terminal is in the console's mode, so the panic hook and
/// the guard restore it once only.
static ACTIVE: AtomicBool = AtomicBool::new(false);
/// Whether mouse capture was turned on.
static MOUSE: AtomicBool = AtomicBool::new(false);
static HOOK: Once = Once::new();

/// Holds the terminal in the console's mode; dropping it restores it.
pub struct TerminalGuard(());

impl TerminalGuard {
    /// Raw mode, alternate screen, bracketed paste, and mouse capture if
    /// `mouse`.
    pub fn enter(mouse: bool) -> io::Result<TerminalGuard> {
        install_panic_hook();
        enable_raw_mode()?;
        ACTIVE.store(true, Ordering::SeqCst);
        let mut out = io::stdout();
        // Focus changes: a jog held in the bring-up pane stops when the
        // terminal loses the focus (no key release ever comes).
        let entered = execute!(
            out,
            EnterAlternateScreen,
            EnableBracketedPaste,
            EnableFocusChange
        )
        .and_then(|()| {
            if mouse {
                MOUSE.store(true, Ordering::SeqCst);
                execute!(out, EnableMouseCapture)
            } else {
                Ok(())
            }
        });
        if let Err(e) = entered {
            restore();
            return Err(e);
        }
        Ok(TerminalGuard(()))
    }
}

impl Drop for TerminalGuard {
    fn drop(&mut self) {
        restore();
    }
}

/// Give the terminal back as it was (idempotent).
pub fn restore() {
    if !ACTIVE.swap(false, Ordering::SeqCst) {
        return;
    }
    let _ = disable_raw_mode();
    let mut out = io::stdout();
    // Escape sequences only to a terminal: a file or pipe has no alternate
    // screen to leave.
    if !out.is_terminal() {
        MOUSE.store(false, Ordering::SeqCst);
        return;
    }
    if MOUSE.swap(false, Ordering::SeqCst) {
        let _ = execute!(out, DisableMouseCapture);
    }
    let _ = execute!(
        out,
        DisableFocusChange,
        DisableBracketedPaste,
        LeaveAlternateScreen,
        ratatui::crossterm::cursor::Show
    );
    let _ = out.flush();
}

fn install_panic_hook() {
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            restore();
            previous(info);
        }));
    });
}

/// Terminal events on a channel, read by a thread of their own: ratatui's
/// crossterm re-export does not carry crossterm's `event-stream` feature,
/// so the reads block in a thread instead of an async stream. The thread
/// blocks in `read` (no polling timeout, so no wakeups while idle) and
/// ends when the channel's receiver is gone and the next event comes, or
/// with the process.
pub fn spawn_reader() -> mpsc::UnboundedReceiver<Event> {
    let (tx, rx) = mpsc::unbounded_channel();
    std::thread::Builder::new()
        .name("terminal-input".into())
        .spawn(move || {
            while let Ok(event) = event::read() {
                if tx.send(event).is_err() {
                    break;
                }
            }
        })
        .ok();
    rx
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_gives_the_terminal_back_before_its_message_is_printed() {
        install_panic_hook();
        ACTIVE.store(true, Ordering::SeqCst);
        let outcome = std::panic::catch_unwind(|| panic!("a bug while the console is up"));
        assert!(outcome.is_err());
        assert!(
            !ACTIVE.load(Ordering::SeqCst),
            "the hook restored the terminal"
        );
        // Restoring twice does nothing.
        restore();
        assert!(!ACTIVE.load(Ordering::SeqCst));
    }
}
