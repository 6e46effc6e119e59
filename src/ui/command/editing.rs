//! The input line's keys: editing, history, completion and the keys that
//! submit or leave it.

use super::*;

impl CommandPane {
    pub(super) fn edit_key(&mut self, key: &KeyEvent, view: &View) -> Outcome {
        if self.confirming.is_some() {
            return self.confirm_key(key, view);
        }
        let action = view.keymap.action_for(Context::Command, key);
        // While the controller runs a line: the cancel key aborts it, Space
        // on an empty line pauses or resumes it (the bytes it takes, Ch2).
        if let Some(busy) = &self.busy {
            if action == Some(Action::Cancel) {
                return Outcome::request(Request::AbortLine);
            }
            if key.code == KeyCode::Char(' ') && self.input.is_empty() && busy.pausable {
                return Outcome::request(Request::PauseLine);
            }
        }
        if action != Some(Action::Complete) {
            self.completing = None;
            self.hint = None;
        }
        match action {
            Some(Action::Submit) => return self.submit(view),
            Some(Action::Complete) => self.complete(view),
            Some(Action::Help) => self.help_here(view),
            Some(Action::Cancel) => {
                if let Some(name) = self.stop_host_run() {
                    self.say(
                        Role::Warning,
                        format!("host run of {name} stopped: nothing more of it is sent"),
                    );
                    return Outcome::Handled(
                        self.end_run(RunEnding::Cancelled).into_iter().collect(),
                    );
                } else if self.batch.take().is_some() {
                    self.batch_wake = None;
                    self.say(Role::Warning, "batch stopped");
                    return Outcome::Handled(
                        self.end_run(RunEnding::Cancelled).into_iter().collect(),
                    );
                } else {
                    self.set_input(String::new());
                }
            }
            Some(Action::HistoryPrevious) => {
                if let Some(line) = self.history.older(&self.input).map(str::to_string) {
                    self.set_input(line);
                }
            }
            Some(Action::HistoryNext) => {
                if let Some(line) = self.history.newer() {
                    self.set_input(line);
                }
            }
            Some(Action::ScrollUp) => self.scroll = self.scroll.saturating_add(1),
            Some(Action::ScrollDown) => self.scroll = self.scroll.saturating_sub(1),
            Some(Action::ScrollPageUp) => self.scroll = self.scroll.saturating_add(PAGE),
            Some(Action::ScrollPageDown) => self.scroll = self.scroll.saturating_sub(PAGE),
            Some(Action::ScrollTop) => self.scroll = usize::MAX,
            Some(Action::ScrollBottom) => self.scroll = 0,
            Some(Action::ClearOutput) => {
                self.output.clear();
                self.scroll = 0;
            }
            // Global actions this pane has no use for go to the app.
            Some(_) => return Outcome::Ignored,
            None => return self.edit_text(key),
        }
        Outcome::redraw()
    }

    /// Keys that edit the line itself.
    pub(super) fn edit_text(&mut self, key: &KeyEvent) -> Outcome {
        let ctrl = key.modifiers.contains(KeyModifiers::CONTROL);
        let alt = key.modifiers.contains(KeyModifiers::ALT);
        match key.code {
            KeyCode::Char('a') if ctrl => self.cursor = 0,
            KeyCode::Char('e') if ctrl => self.cursor = self.input.len(),
            KeyCode::Char('u') if ctrl => {
                self.input.drain(..self.cursor);
                self.cursor = 0;
            }
            KeyCode::Char('k') if ctrl => self.input.truncate(self.cursor),
            KeyCode::Char('w') if ctrl => {
                let before = self.input.get(..self.cursor).unwrap_or("");
                let trimmed = before.trim_end_matches([' ', ',']);
                let start = trimmed.rfind([' ', ',']).map_or(0, |i| i + 1);
                self.input.drain(start..self.cursor);
                self.cursor = start;
            }
            KeyCode::Char(c) if !ctrl && !alt => {
                self.input.insert(self.cursor, c);
                self.cursor += c.len_utf8();
            }
            KeyCode::Backspace => {
                if let Some(c) = self
                    .input
                    .get(..self.cursor)
                    .and_then(|s| s.chars().next_back())
                {
                    self.cursor -= c.len_utf8();
                    self.input.remove(self.cursor);
                }
            }
            KeyCode::Delete => {
                if self.cursor < self.input.len() {
                    self.input.remove(self.cursor);
                }
            }
            KeyCode::Left => {
                if let Some(c) = self
                    .input
                    .get(..self.cursor)
                    .and_then(|s| s.chars().next_back())
                {
                    self.cursor -= c.len_utf8();
                }
            }
            KeyCode::Right => {
                if let Some(c) = self.input.get(self.cursor..).and_then(|s| s.chars().next()) {
                    self.cursor += c.len_utf8();
                }
            }
            KeyCode::Home => self.cursor = 0,
            KeyCode::End => self.cursor = self.input.len(),
            _ => return Outcome::Ignored,
        }
        Outcome::redraw()
    }
}
