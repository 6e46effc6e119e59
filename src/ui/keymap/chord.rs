//! One key press as a keymap names it: a [`Key`] and its [`Modifiers`],
//! written as text (`ctrl-s`, `shift-f5`, `F12`) and read from terminal
//! events. Chords a terminal cannot send are refused when parsed.

use std::fmt;
use std::str::FromStr;

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

/// A key, without modifiers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Key {
    /// A character as typed (`'a'`, `'A'`, `'+'`, `' '`).
    Char(char),
    /// A function key, 1 to 24.
    F(u8),
    Esc,
    Enter,
    Tab,
    Backspace,
    Delete,
    Insert,
    Home,
    End,
    PageUp,
    PageDown,
    Up,
    Down,
    Left,
    Right,
}

/// Key names in keymap files: the first name of a key is the one written
/// back; the others are accepted.
const KEY_NAMES: &[(&str, Key)] = &[
    ("space", Key::Char(' ')),
    ("esc", Key::Esc),
    ("escape", Key::Esc),
    ("enter", Key::Enter),
    ("return", Key::Enter),
    ("tab", Key::Tab),
    ("backspace", Key::Backspace),
    ("delete", Key::Delete),
    ("del", Key::Delete),
    ("insert", Key::Insert),
    ("ins", Key::Insert),
    ("home", Key::Home),
    ("end", Key::End),
    ("pageup", Key::PageUp),
    ("pgup", Key::PageUp),
    ("pagedown", Key::PageDown),
    ("pgdn", Key::PageDown),
    ("up", Key::Up),
    ("down", Key::Down),
    ("left", Key::Left),
    ("right", Key::Right),
];

/// How keys are shown in the status bar and the help.
const KEY_LABELS: &[(Key, &str)] = &[
    (Key::Char(' '), "Space"),
    (Key::Esc, "Esc"),
    (Key::Enter, "Enter"),
    (Key::Tab, "Tab"),
    (Key::Backspace, "Bksp"),
    (Key::Delete, "Del"),
    (Key::Insert, "Ins"),
    (Key::Home, "Home"),
    (Key::End, "End"),
    (Key::PageUp, "PgUp"),
    (Key::PageDown, "PgDn"),
    (Key::Up, "Up"),
    (Key::Down, "Down"),
    (Key::Left, "Left"),
    (Key::Right, "Right"),
];

/// The highest function key a chord may name.
pub const MAX_FUNCTION_KEY: u8 = 24;

/// Modifier keys held with a key.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct Modifiers {
    pub ctrl: bool,
    pub alt: bool,
    pub shift: bool,
}

impl Modifiers {
    pub const NONE: Modifiers = Modifiers {
        ctrl: false,
        alt: false,
        shift: false,
    };
    pub const CTRL: Modifiers = Modifiers {
        ctrl: true,
        ..Modifiers::NONE
    };
    pub const ALT: Modifiers = Modifiers {
        alt: true,
        ..Modifiers::NONE
    };
    pub const SHIFT: Modifiers = Modifiers {
        shift: true,
        ..Modifiers::NONE
    };
}

/// A key with its modifiers, as a keymap file writes it (`"ctrl-c"`,
/// `"f12"`, `"shift-tab"`, `"alt-1"`, `"pageup"`, `"+"`).
///
/// Chords are kept in one form so that what a terminal reports matches
/// what a file says: a character never carries shift (`"shift-a"` is
/// `"A"`), and a ctrl character is lower case (terminals send the same
/// byte for ctrl-a and ctrl-A).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct KeyChord {
    pub(super) key: Key,
    pub(super) modifiers: Modifiers,
}

/// Why a text is not a key chord.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ChordError {
    #[error("no key given")]
    Empty,
    #[error(
        "unknown key `{0}` (keys: a single character, f1 to f24, esc, enter, tab, backspace, \
         delete, insert, home, end, pageup, pagedown, up, down, left, right, space; \
         modifiers: ctrl-, alt-, shift-)"
    )]
    UnknownKey(String),
    #[error("`{0}` names the modifier `{1}` twice")]
    RepeatedModifier(String, String),
    #[error("f{0}: function keys go from f1 to f{MAX_FUNCTION_KEY}")]
    FunctionKeyOutOfRange(u32),
    #[error("a control character cannot be bound; write the key's name (tab, enter, esc)")]
    ControlCharacter,
    #[error(
        "shift-{0}: write the character the shifted key types instead (such as `!` for \
         shift-1), since that depends on the keyboard layout"
    )]
    ShiftedSymbol(char),
    #[error("ctrl-shift-{0}: most terminals send the same as ctrl-{0}; bind that instead")]
    CtrlShift(char),
    #[error("ctrl-{0}: terminals send the same byte for it as for `{1}`; bind `{1}` instead")]
    SameAs(char, &'static str),
}

/// The one upper-case form of a letter, if it has exactly one.
fn upper(c: char) -> Option<char> {
    let mut up = c.to_uppercase();
    match (up.next(), up.next()) {
        (Some(u), None) if u != c || c.is_uppercase() => Some(u),
        _ => None,
    }
}

impl KeyChord {
    /// The chord of `key` with `modifiers`, in the one form chords are
    /// kept in; refused where a terminal could not report it as written.
    pub fn new(key: Key, modifiers: Modifiers) -> Result<KeyChord, ChordError> {
        let mut modifiers = modifiers;
        let key = match key {
            Key::Char(c) => {
                if c.is_control() {
                    return Err(ChordError::ControlCharacter);
                }
                let mut c = c;
                if modifiers.shift {
                    if modifiers.ctrl && c.is_ascii_alphabetic() {
                        return Err(ChordError::CtrlShift(c.to_ascii_lowercase()));
                    }
                    c = upper(c).ok_or(ChordError::ShiftedSymbol(c))?;
                    modifiers.shift = false;
                }
                if modifiers.ctrl {
                    c = c.to_ascii_lowercase();
                    // The C0 control codes: ctrl-i is 0x09 (tab), ctrl-m
                    // 0x0D (enter), ctrl-[ 0x1B (esc).
                    let same = match c {
                        'i' => Some("tab"),
                        'm' => Some("enter"),
                        '[' => Some("esc"),
                        _ => None,
                    };
                    if let Some(same) = same {
                        return Err(ChordError::SameAs(c, same));
                    }
                }
                Key::Char(c)
            }
            Key::F(n) => {
                if n == 0 || n > MAX_FUNCTION_KEY {
                    return Err(ChordError::FunctionKeyOutOfRange(u32::from(n)));
                }
                Key::F(n)
            }
            other => other,
        };
        Ok(KeyChord { key, modifiers })
    }

    /// A key alone.
    pub fn plain(key: Key) -> Result<KeyChord, ChordError> {
        KeyChord::new(key, Modifiers::NONE)
    }

    pub fn key(self) -> Key {
        self.key
    }

    pub fn modifiers(self) -> Modifiers {
        self.modifiers
    }

    /// A printable character without ctrl or alt: text, where text is
    /// typed.
    pub fn is_text(self) -> bool {
        matches!(self.key, Key::Char(_)) && !self.modifiers.ctrl && !self.modifiers.alt
    }

    /// The chord of a key event from the terminal; `None` for keys no
    /// chord names (media keys, lone modifiers) and for super, hyper and
    /// meta, which keymaps do not use.
    pub fn from_event(event: &KeyEvent) -> Option<KeyChord> {
        let m = event.modifiers;
        if m.intersects(KeyModifiers::SUPER | KeyModifiers::HYPER | KeyModifiers::META) {
            return None;
        }
        let mut modifiers = Modifiers {
            ctrl: m.contains(KeyModifiers::CONTROL),
            alt: m.contains(KeyModifiers::ALT),
            shift: m.contains(KeyModifiers::SHIFT),
        };
        let key = match event.code {
            KeyCode::Char(c) if c.is_control() => return None,
            KeyCode::Char(c) => {
                // Terminals differ in whether they add shift to a shifted
                // character; the character itself says it. Ctrl chords
                // are case-blind at the terminal (one byte for both).
                let c = if modifiers.ctrl {
                    c.to_ascii_lowercase()
                } else if modifiers.shift {
                    upper(c).unwrap_or(c)
                } else {
                    c
                };
                modifiers.shift = false;
                Key::Char(c)
            }
            KeyCode::BackTab => {
                modifiers.shift = true;
                Key::Tab
            }
            KeyCode::F(n) if (1..=MAX_FUNCTION_KEY).contains(&n) => Key::F(n),
            KeyCode::Esc => Key::Esc,
            KeyCode::Enter => Key::Enter,
            KeyCode::Tab => Key::Tab,
            KeyCode::Backspace => Key::Backspace,
            KeyCode::Delete => Key::Delete,
            KeyCode::Insert => Key::Insert,
            KeyCode::Home => Key::Home,
            KeyCode::End => Key::End,
            KeyCode::PageUp => Key::PageUp,
            KeyCode::PageDown => Key::PageDown,
            KeyCode::Up => Key::Up,
            KeyCode::Down => Key::Down,
            KeyCode::Left => Key::Left,
            KeyCode::Right => Key::Right,
            _ => return None,
        };
        Some(KeyChord { key, modifiers })
    }

    /// A key press event a terminal would report for this chord (as
    /// crossterm reports shift-tab: `BackTab` with shift).
    pub fn to_event(self) -> KeyEvent {
        let mut m = KeyModifiers::NONE;
        if self.modifiers.ctrl {
            m |= KeyModifiers::CONTROL;
        }
        if self.modifiers.alt {
            m |= KeyModifiers::ALT;
        }
        if self.modifiers.shift {
            m |= KeyModifiers::SHIFT;
        }
        let code = match self.key {
            Key::Char(c) => KeyCode::Char(c),
            Key::F(n) => KeyCode::F(n),
            Key::Esc => KeyCode::Esc,
            Key::Enter => KeyCode::Enter,
            Key::Tab if self.modifiers.shift => KeyCode::BackTab,
            Key::Tab => KeyCode::Tab,
            Key::Backspace => KeyCode::Backspace,
            Key::Delete => KeyCode::Delete,
            Key::Insert => KeyCode::Insert,
            Key::Home => KeyCode::Home,
            Key::End => KeyCode::End,
            Key::PageUp => KeyCode::PageUp,
            Key::PageDown => KeyCode::PageDown,
            Key::Up => KeyCode::Up,
            Key::Down => KeyCode::Down,
            Key::Left => KeyCode::Left,
            Key::Right => KeyCode::Right,
        };
        KeyEvent::new(code, m)
    }

    /// How the status bar and the help show it: `F12`, `Ctrl-C`,
    /// `Shift-Tab`, `Alt-1`, `PgUp`.
    pub fn label(self) -> String {
        let mut label = String::new();
        if self.modifiers.ctrl {
            label.push_str("Ctrl-");
        }
        if self.modifiers.alt {
            label.push_str("Alt-");
        }
        if self.modifiers.shift {
            label.push_str("Shift-");
        }
        match self.key {
            Key::F(n) => label.push_str(&format!("F{n}")),
            Key::Char(c) if c != ' ' => {
                if self.modifiers.ctrl {
                    label.extend(c.to_uppercase());
                } else {
                    label.push(c);
                }
            }
            key => {
                let name = KEY_LABELS
                    .iter()
                    .find(|(k, _)| *k == key)
                    .map_or("?", |(_, name)| *name);
                label.push_str(name);
            }
        }
        label
    }
}

impl fmt::Display for KeyChord {
    /// The form keymap files use, which parses back to the same chord.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.modifiers.ctrl {
            f.write_str("ctrl-")?;
        }
        if self.modifiers.alt {
            f.write_str("alt-")?;
        }
        if self.modifiers.shift {
            f.write_str("shift-")?;
        }
        match self.key {
            Key::F(n) => write!(f, "f{n}"),
            Key::Char(c) if c != ' ' => write!(f, "{c}"),
            key => {
                let name = KEY_NAMES
                    .iter()
                    .find(|(_, k)| *k == key)
                    .map_or("?", |(name, _)| *name);
                f.write_str(name)
            }
        }
    }
}

impl FromStr for KeyChord {
    type Err = ChordError;

    fn from_str(text: &str) -> Result<KeyChord, ChordError> {
        let mut modifiers = Modifiers::NONE;
        let mut rest = text;
        // Modifiers end in `-`; a lone `-` after them is the minus key
        // (`ctrl--`).
        while let Some((word, tail)) = rest.split_once('-') {
            if tail.is_empty() {
                break;
            }
            let lower = word.to_ascii_lowercase();
            let (flag, name) = match lower.as_str() {
                "ctrl" | "control" => (&mut modifiers.ctrl, "ctrl"),
                "alt" => (&mut modifiers.alt, "alt"),
                "shift" => (&mut modifiers.shift, "shift"),
                _ => break,
            };
            if *flag {
                return Err(ChordError::RepeatedModifier(
                    text.to_string(),
                    name.to_string(),
                ));
            }
            *flag = true;
            rest = tail;
        }
        // crossterm's name for shift-tab.
        if rest.eq_ignore_ascii_case("backtab") {
            if modifiers.shift {
                return Err(ChordError::RepeatedModifier(
                    text.to_string(),
                    "shift".to_string(),
                ));
            }
            modifiers.shift = true;
            rest = "tab";
        }
        let key = parse_key(rest)?;
        KeyChord::new(key, modifiers)
    }
}

fn parse_key(text: &str) -> Result<Key, ChordError> {
    let mut chars = text.chars();
    match (chars.next(), chars.next()) {
        (None, _) => return Err(ChordError::Empty),
        (Some(c), None) => return Ok(Key::Char(c)),
        _ => {}
    }
    let lower = text.to_ascii_lowercase();
    if let Some((_, key)) = KEY_NAMES.iter().find(|(name, _)| *name == lower) {
        return Ok(*key);
    }
    if let Some(digits) = lower.strip_prefix('f')
        && !digits.is_empty()
        && digits.chars().all(|c| c.is_ascii_digit())
    {
        let n: u32 = digits.parse().unwrap_or(u32::MAX);
        return match u8::try_from(n) {
            Ok(n) if (1..=MAX_FUNCTION_KEY).contains(&n) => Ok(Key::F(n)),
            _ => Err(ChordError::FunctionKeyOutOfRange(n)),
        };
    }
    Err(ChordError::UnknownKey(text.to_string()))
}
