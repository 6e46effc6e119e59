//! Which key chords reach axterm at all. A keymap may name a chord the
//! terminal never sends as such: the terminal sends the bytes of another
//! key for it, or bytes crossterm (the terminal library) reads as
//! something that is no key. Such a binding can never fire; the built-in
//! keymaps must have none (tests/builtin_files.rs checks every binding).
//!
//! The terminals this holds for are the ones a technician meets: xterm
//! and what imitates it (VTE, Konsole, Windows Terminal, PuTTY with
//! TERM=xterm), with tmux or screen in between, in their default modes —
//! axterm asks for no extended keyboard protocol (kitty's, xterm's
//! `modifyOtherKeys`), so keys arrive as the legacy encodings:
//! - a modified F1–F4, arrow, Home or End as `ESC [ 1 ; m X`;
//! - the other modified keys as `ESC [ n ; m ~`;
//! - Alt with a key as `ESC` before the key's bytes (xterm needs
//!   `metaSendsEscape`, which tmux and the others do by default);
//! - Ctrl with a character as its C0 control code, where it has one.
//!
//! Chords that do not survive this (each rule says why):
//! - F3 with any modifier: `ESC [ 1 ; m R` is also the cursor position
//!   report (`ESC [ row ; col R`), and crossterm reads it as that, so the
//!   key never arrives (issue 11: Shift-F3 did nothing in xterm or tmux).
//! - F13–F24: these terminals have no such keys; they send Shift/Ctrl
//!   with F1–F12 instead, which arrive as that.
//! - Ctrl with anything but a letter or space: ctrl-1, ctrl-9, ctrl-0,
//!   ctrl-. send the plain character; ctrl-2 sends NUL (read as
//!   ctrl-space), ctrl-3 ESC, ctrl-8 DEL (Backspace); ctrl-4…7 and ctrl
//!   with punctuation depend on the keyboard layout.
//! - Ctrl-H: many terminals send its byte (BS, 0x08) for Backspace.
//!   (Ctrl-I, Ctrl-M and Ctrl-[ are Tab, Enter and Esc; the keymap parser
//!   refuses them already.)
//! - Esc with any modifier: Esc is sent alone, Alt-Esc as two Escs.
//! - Ctrl-Enter, Shift-Enter, Ctrl-Tab, Ctrl-Shift-Tab, Ctrl-Backspace,
//!   Shift-Backspace: sent as the unmodified key (Ctrl-Backspace as
//!   Ctrl-H). Alt-Shift-Tab: `ESC ESC [ Z`, read as Esc and two characters.
//! - Shift-PageUp, Shift-PageDown, Shift-Insert: xterm and most terminals
//!   keep them for their own scrollback and paste.
//! - Alt-`[` and Alt-`O`: `ESC [` and `ESC O` begin the escape sequences
//!   of other keys.
//!
//! Not judged here: keys a desktop claims for itself (F11 full screen,
//! F10 a menu, Alt-Tab), which depend on its settings, and Ctrl-S/Ctrl-Q
//! (flow control a serial console on the way may eat), which
//! tests/builtin_files.rs keeps out of the built-in keymaps.

use super::keymap::{Key, KeyChord, Modifiers};

/// Why a terminal cannot deliver `chord` to axterm; `None` when it can.
pub fn why_undeliverable(chord: KeyChord) -> Option<&'static str> {
    let m = chord.modifiers();
    let modified = m != Modifiers::NONE;
    match chord.key() {
        Key::F(3) if modified => Some(
            "a modified F3 is sent as ESC [1;mR, which reads as a cursor position report: \
             the key never arrives",
        ),
        Key::F(n) if n > 12 => Some(
            "terminals have no F13-F24 of their own: they send Shift or Ctrl with F1-F12, \
             which arrive as that",
        ),
        Key::Char('h') if m.ctrl => {
            Some("many terminals send Backspace as ctrl-h (0x08): the two cannot be told apart")
        }
        Key::Char(c) if m.ctrl && !(c.is_ascii_lowercase() || c == ' ') => Some(
            "ctrl with anything but a letter or space sends the plain character, another \
             key's code, or what the keyboard layout makes of it",
        ),
        Key::Char('[') if m.alt => {
            Some("alt-[ is ESC [, the start of other keys' escape sequences")
        }
        Key::Char('O') if m.alt => {
            Some("alt-O is ESC O, the start of other keys' escape sequences")
        }
        Key::Esc if modified => Some("Esc is sent alone whatever is held (alt-esc as Esc twice)"),
        Key::Enter if m.ctrl || m.shift => {
            Some("terminals send ctrl-enter and shift-enter as Enter")
        }
        Key::Tab if m.ctrl => {
            Some("terminals send ctrl-tab as Tab (and ctrl-shift-tab as Shift-Tab)")
        }
        Key::Tab if m.alt && m.shift => {
            Some("alt-shift-tab is ESC ESC [ Z, read as Esc and two characters")
        }
        Key::Backspace if m.ctrl || m.shift => {
            Some("terminals send ctrl-backspace as ctrl-h and shift-backspace as Backspace")
        }
        Key::PageUp | Key::PageDown | Key::Insert if m.shift => Some(
            "xterm and most terminals keep shift-pageup, shift-pagedown and shift-insert for \
             their own scrollback and paste",
        ),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chord(text: &str) -> KeyChord {
        text.parse().unwrap_or_else(|e| panic!("{text}: {e}"))
    }

    #[test]
    fn a_modified_f3_never_arrives_a_plain_one_does() {
        for text in ["shift-f3", "ctrl-f3", "alt-f3", "ctrl-shift-f3"] {
            let why = why_undeliverable(chord(text));
            assert!(
                why.is_some_and(|w| w.contains("cursor position report")),
                "{text}: {why:?}"
            );
        }
        assert_eq!(why_undeliverable(chord("f3")), None);
        for text in [
            "shift-f1", "shift-f2", "ctrl-f4", "shift-f4", "ctrl-f5", "alt-f12",
        ] {
            assert_eq!(why_undeliverable(chord(text)), None, "{text}");
        }
    }

    #[test]
    fn chords_sent_as_another_key_are_named() {
        for text in [
            "f13",
            "shift-f24",
            "ctrl-0",
            "ctrl-1",
            "ctrl-.",
            "ctrl--",
            "ctrl-h",
            "alt-esc",
            "shift-esc",
            "ctrl-enter",
            "shift-enter",
            "ctrl-tab",
            "ctrl-shift-tab",
            "alt-shift-tab",
            "ctrl-backspace",
            "shift-backspace",
            "shift-pageup",
            "shift-pagedown",
            "shift-insert",
            "alt-[",
            "alt-O",
        ] {
            assert!(why_undeliverable(chord(text)).is_some(), "{text}");
        }
    }

    #[test]
    fn what_the_legacy_encodings_carry_is_deliverable() {
        for text in [
            "a",
            "A",
            "+",
            "space",
            "ctrl-a",
            "ctrl-z",
            "ctrl-space",
            "ctrl-alt-x",
            "alt-1",
            "alt-A",
            "alt-o",
            "alt-enter",
            "alt-backspace",
            "alt-tab",
            "shift-tab",
            "ctrl-home",
            "ctrl-end",
            "shift-up",
            "ctrl-pageup",
            "pageup",
            "insert",
            "esc",
            "f12",
        ] {
            assert_eq!(why_undeliverable(chord(text)), None, "{text}");
        }
    }
}
