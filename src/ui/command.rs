//! The command pane: a direct-mode console line editor and its output.

use ratatui::Frame;
use ratatui::crossterm::event::{KeyCode, KeyModifiers};
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::Paragraph;

use super::pane::{Input, Outcome, Pane, PaneEvent, Region, Request, View};
use super::theme::Role;

/// The console line editor.
#[derive(Debug, Default)]
pub struct CommandPane {
    input: String,
    output: Vec<(Role, String)>,
}

impl CommandPane {
    pub fn new() -> CommandPane {
        CommandPane::default()
    }
}

impl Pane for CommandPane {
    fn name(&self) -> &'static str {
        "command"
    }

    fn title(&self, _view: &View) -> String {
        "Command".into()
    }

    fn region(&self) -> Region {
        Region::Main
    }

    fn render(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        let rows = usize::from(area.height.saturating_sub(1));
        let skip = self.output.len().saturating_sub(rows);
        let mut lines: Vec<Line> = self
            .output
            .iter()
            .skip(skip)
            .map(|(role, text)| Line::styled(text.clone(), view.theme.style(*role)))
            .collect();
        lines.push(Line::styled(
            format!("> {}", self.input),
            view.theme.style(Role::Prompt),
        ));
        frame.render_widget(Paragraph::new(lines), area);
    }

    fn handle_input(&mut self, input: &Input, _view: &View) -> Outcome {
        let Input::Key(key) = input else {
            return Outcome::Ignored;
        };
        match key.code {
            KeyCode::Char(c) if !key.modifiers.contains(KeyModifiers::CONTROL) => {
                self.input.push(c);
                Outcome::redraw()
            }
            KeyCode::Backspace => {
                self.input.pop();
                Outcome::redraw()
            }
            KeyCode::Enter => {
                let line = std::mem::take(&mut self.input);
                self.output.push((Role::Normal, format!("> {line}")));
                Outcome::request(Request::Send {
                    lines: vec![line],
                    tag: 0,
                })
            }
            _ => Outcome::Ignored,
        }
    }

    fn on_event(&mut self, event: &PaneEvent, _view: &View) -> Outcome {
        match event {
            PaneEvent::Reply { result, .. } => {
                match result {
                    Ok(r) => self.output.push((Role::Ok, r.value.to_string())),
                    Err(e) => self.output.push((Role::Error, e.to_string())),
                }
                Outcome::redraw()
            }
            PaneEvent::Notice(n) => {
                self.output.push((Role::Normal, n.text.clone()));
                Outcome::redraw()
            }
            _ => Outcome::Ignored,
        }
    }
}
