//! STAND-IN until the keymap loader lands (branch `uiconf`): the console's
//! global actions and their default keys (as in `keymaps/default.toml`).

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

/// What a global key does, whichever pane has the focus.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Action {
    EmergencyStop,
    Quit,
    Help,
    NextPane,
    PreviousPane,
}

/// Keys to actions.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Keymap {
    name: String,
    global: Vec<(KeyCode, KeyModifiers, Action)>,
}

impl Default for Keymap {
    fn default() -> Keymap {
        Keymap {
            name: "default".into(),
            global: vec![
                (KeyCode::F(12), KeyModifiers::NONE, Action::EmergencyStop),
                (KeyCode::Char('q'), KeyModifiers::CONTROL, Action::Quit),
                (KeyCode::F(1), KeyModifiers::NONE, Action::Help),
                (KeyCode::Tab, KeyModifiers::NONE, Action::NextPane),
                // The command pane keeps Tab for completion.
                (KeyCode::F(6), KeyModifiers::NONE, Action::NextPane),
                (KeyCode::BackTab, KeyModifiers::SHIFT, Action::PreviousPane),
            ],
        }
    }
}

impl Keymap {
    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn builtin(name: &str) -> Option<Keymap> {
        (name == "default").then(Keymap::default)
    }

    /// The global action bound to `key`, if any.
    pub fn global_action(&self, key: &KeyEvent) -> Option<Action> {
        self.global
            .iter()
            .find(|(code, modifiers, _)| *code == key.code && key.modifiers == *modifiers)
            .map(|(_, _, action)| *action)
    }

    /// How the key of `action` is written ("F12", "Ctrl-Q").
    pub fn key_name(&self, action: Action) -> String {
        self.global
            .iter()
            .find(|(_, _, a)| *a == action)
            .map(|(code, modifiers, _)| describe_key(*code, *modifiers))
            .unwrap_or_else(|| "(unbound)".into())
    }
}

/// A key as the status bar shows it.
pub fn describe_key(code: KeyCode, modifiers: KeyModifiers) -> String {
    let mut text = String::new();
    if modifiers.contains(KeyModifiers::CONTROL) {
        text.push_str("Ctrl-");
    }
    if modifiers.contains(KeyModifiers::ALT) {
        text.push_str("Alt-");
    }
    match code {
        KeyCode::F(n) => text.push_str(&format!("F{n}")),
        KeyCode::Char(c) => text.push(c.to_ascii_uppercase()),
        KeyCode::Tab => text.push_str("Tab"),
        KeyCode::BackTab => text.push_str("Shift-Tab"),
        KeyCode::Esc => text.push_str("Esc"),
        KeyCode::Enter => text.push_str("Enter"),
        other => text.push_str(&format!("{other:?}")),
    }
    text
}
