//! A one-line text field for panes that take typed text for a moment (a
//! parameter value, a filter, a file name): the editing keys a shell line
//! has, nothing more. Submit and cancel are the pane's business, through
//! the keymap's [`super::keymap::Context::Command`] actions.

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

/// Text being typed and where the cursor is (a byte offset on a char
/// boundary).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Field {
    text: String,
    cursor: usize,
}

impl Field {
    /// A field holding `text`, the cursor at its end.
    pub fn new(text: impl Into<String>) -> Field {
        let text = text.into();
        Field {
            cursor: text.len(),
            text,
        }
    }

    pub fn text(&self) -> &str {
        &self.text
    }

    /// Characters before the cursor, for placing the terminal's cursor.
    pub fn cursor_column(&self) -> usize {
        self.text.get(..self.cursor).unwrap_or("").chars().count()
    }

    pub fn insert_str(&mut self, text: &str) {
        let text: String = text.chars().filter(|c| !c.is_control()).collect();
        self.text.insert_str(self.cursor, &text);
        self.cursor += text.len();
    }

    /// Apply an editing key; false if it is not one.
    pub fn edit(&mut self, key: &KeyEvent) -> bool {
        let ctrl = key.modifiers.contains(KeyModifiers::CONTROL);
        let alt = key.modifiers.contains(KeyModifiers::ALT);
        match key.code {
            KeyCode::Char('a') if ctrl => self.cursor = 0,
            KeyCode::Char('e') if ctrl => self.cursor = self.text.len(),
            KeyCode::Char('u') if ctrl => {
                self.text.drain(..self.cursor);
                self.cursor = 0;
            }
            KeyCode::Char('k') if ctrl => self.text.truncate(self.cursor),
            KeyCode::Char(c) if !ctrl && !alt => {
                self.text.insert(self.cursor, c);
                self.cursor += c.len_utf8();
            }
            KeyCode::Backspace => {
                if let Some(c) = self.before().chars().next_back() {
                    self.cursor -= c.len_utf8();
                    self.text.remove(self.cursor);
                }
            }
            KeyCode::Delete => {
                if self.cursor < self.text.len() {
                    self.text.remove(self.cursor);
                }
            }
            KeyCode::Left => {
                if let Some(c) = self.before().chars().next_back() {
                    self.cursor -= c.len_utf8();
                }
            }
            KeyCode::Right => {
                if let Some(c) = self.text.get(self.cursor..).and_then(|s| s.chars().next()) {
                    self.cursor += c.len_utf8();
                }
            }
            KeyCode::Home => self.cursor = 0,
            KeyCode::End => self.cursor = self.text.len(),
            _ => return false,
        }
        true
    }

    fn before(&self) -> &str {
        self.text.get(..self.cursor).unwrap_or("")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(code: KeyCode) -> KeyEvent {
        KeyEvent::new(code, KeyModifiers::NONE)
    }

    #[test]
    fn edits_like_a_shell_line() {
        let mut field = Field::new("12");
        assert!(field.edit(&key(KeyCode::Char('µ'))));
        assert_eq!(field.text(), "12µ");
        field.edit(&key(KeyCode::Left));
        field.edit(&key(KeyCode::Backspace));
        assert_eq!(field.text(), "1µ");
        assert_eq!(field.cursor_column(), 1);
        field.edit(&key(KeyCode::Home));
        field.edit(&key(KeyCode::Delete));
        field.insert_str("9\n8");
        assert_eq!(field.text(), "98µ");
        field.edit(&KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL));
        assert_eq!(field.text(), "µ");
        assert!(!field.edit(&key(KeyCode::F(5))));
        // Nothing breaks at the ends.
        field.edit(&key(KeyCode::End));
        field.edit(&key(KeyCode::Right));
        field.edit(&key(KeyCode::Delete));
        field.edit(&key(KeyCode::Home));
        field.edit(&key(KeyCode::Backspace));
        field.edit(&key(KeyCode::Left));
        assert_eq!(field.text(), "µ");
    }
}
