//! The plot pane's picker: what the selected axis can plot (its status
//! values, then the axis parameters of the family's table, as `:plot add`
//! finds them), narrowed by typing a name or a number, drawn over the
//! plot. The pane toggles the chosen one; the picker only lists, filters
//! and moves.

use ratatui::Frame;
use ratatui::crossterm::event::KeyEvent;
use ratatui::layout::{Position, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Clear, Paragraph};

use super::Quantity;
use crate::ui::field::Field;
use crate::ui::keymap::{Action, Context};
use crate::ui::pane::{View, key_label};
use crate::ui::text::fit;
use crate::ui::theme::Role;

/// The list of what one axis can plot.
#[derive(Debug, Clone)]
pub(super) struct Picker {
    /// The axis listed (an index into the snapshot's axes).
    pub axis: usize,
    axis_name: String,
    choices: Vec<Quantity>,
    filter: Field,
    /// Index into the choices that pass the filter.
    selected: usize,
    /// The first row shown.
    offset: usize,
    /// Rows the last drawing had room for: a page.
    page: usize,
}

impl Picker {
    pub fn new(axis: usize, axis_name: &str, choices: Vec<Quantity>) -> Picker {
        Picker {
            axis,
            axis_name: axis_name.to_string(),
            choices,
            filter: Field::default(),
            selected: 0,
            offset: 0,
            page: 10,
        }
    }

    /// The choices that pass the filter, in list order.
    pub fn shown(&self) -> Vec<&Quantity> {
        let filter = self.filter.text().trim().to_lowercase();
        self.choices
            .iter()
            .filter(|q| matches(q, &filter))
            .collect()
    }

    /// The choice under the cursor.
    pub fn chosen(&self) -> Option<Quantity> {
        self.shown().get(self.selected).map(|q| (*q).clone())
    }

    /// Move the cursor by `by` rows (stops at the ends).
    fn step(&mut self, by: isize) {
        let last = self.shown().len().saturating_sub(1);
        self.selected = self.selected.saturating_add_signed(by).min(last);
    }

    /// A key while the picker is open, looked up as on the command line
    /// (letters are filter text): true if it moved or filtered. Enter and
    /// Esc are the pane's.
    pub fn key(&mut self, action: Option<Action>, key: &KeyEvent) -> bool {
        let page = self.page.max(1) as isize;
        match action {
            Some(Action::HistoryPrevious | Action::ScrollUp) => self.step(-1),
            Some(Action::HistoryNext | Action::ScrollDown) => self.step(1),
            Some(Action::ScrollPageUp) => self.step(-page),
            Some(Action::ScrollPageDown) => self.step(page),
            Some(Action::ScrollTop) => self.selected = 0,
            Some(Action::ScrollBottom) => self.step(isize::MAX),
            _ => {
                if !self.filter.edit(key) {
                    return false;
                }
                self.selected = 0;
            }
        }
        true
    }

    /// Pasted text joins the filter.
    pub fn paste(&mut self, text: &str) {
        self.filter.insert_str(text.lines().next().unwrap_or(""));
        self.selected = 0;
    }

    /// Draw over `area` (the pane's inside below its head line); rows for
    /// which `plotted` holds are marked.
    pub fn render(
        &mut self,
        frame: &mut Frame,
        area: Rect,
        view: &View,
        plotted: impl Fn(&Quantity) -> bool,
    ) {
        let theme = view.theme;
        if area.width < 8 || area.height < 3 {
            return;
        }
        let key = |action| key_label(view.keymap, Context::Command, action);
        let block = Block::bordered()
            .border_style(theme.style(Role::BorderFocused))
            .style(theme.style(Role::Normal))
            .title(Span::styled(
                format!(" {}: what to plot ", self.axis_name),
                theme.style(Role::Title),
            ))
            .title_bottom(Span::styled(
                format!(
                    " {} plot/unplot · {} close · type to filter ",
                    key(Action::Submit),
                    key(Action::Cancel)
                ),
                theme.style(Role::Muted),
            ));
        let inner = block.inner(area);
        frame.render_widget(Clear, area);
        frame.render_widget(block, area);
        if inner.height == 0 || inner.width == 0 {
            return;
        }
        let width = usize::from(inner.width);
        let prompt = "filter: ";
        let filter_line = Line::from(vec![
            Span::styled(prompt, theme.style(Role::Prompt)),
            Span::styled(
                fit(self.filter.text(), width.saturating_sub(prompt.len())),
                theme.style(Role::Normal),
            ),
        ]);
        frame.render_widget(Paragraph::new(filter_line), Rect { height: 1, ..inner });
        if view.focused {
            let column = (prompt.len() + self.filter.cursor_column()).min(width - 1);
            frame.set_cursor_position(Position::new(inner.x + column as u16, inner.y));
        }
        let rows = usize::from(inner.height.saturating_sub(1));
        self.page = rows;
        let count = self.shown().len();
        self.selected = self.selected.min(count.saturating_sub(1));
        if self.selected < self.offset {
            self.offset = self.selected;
        } else if rows > 0 && self.selected >= self.offset + rows {
            self.offset = self.selected + 1 - rows;
        }
        self.offset = self.offset.min(count.saturating_sub(rows));
        let shown = self.shown();
        let mut lines: Vec<Line> = shown
            .iter()
            .enumerate()
            .skip(self.offset)
            .take(rows)
            .map(|(n, quantity)| {
                let here = n == self.selected;
                // The marks are characters, so that the mono theme and a
                // screen reader tell plotted and selected rows apart.
                let mark = if plotted(quantity) { "[x]" } else { "[ ]" };
                let number = match quantity {
                    Quantity::Parameter { number, .. } => format!("{number:>4}"),
                    Quantity::Status(_) => "    ".to_string(),
                };
                let name = match quantity {
                    Quantity::Parameter { name, .. } => name.clone(),
                    Quantity::Status(value) => format!("{} (status)", value.name()),
                };
                let text = format!("{} {mark} {number} {name}", if here { '›' } else { ' ' });
                let role = if here { Role::Selection } else { Role::Normal };
                Line::styled(fit(&text, width), theme.style(role))
            })
            .collect();
        if shown.is_empty() {
            lines.push(Line::styled(
                fit(
                    &format!("  nothing matches `{}`", self.filter.text()),
                    width,
                ),
                theme.style(Role::Muted),
            ));
        }
        frame.render_widget(
            Paragraph::new(lines),
            Rect {
                y: inner.y + 1,
                height: inner.height - 1,
                ..inner
            },
        );
    }
}

/// Whether a choice passes the filter: its name holds it, or (a
/// parameter) its number begins with it.
fn matches(quantity: &Quantity, filter: &str) -> bool {
    if filter.is_empty() {
        return true;
    }
    match quantity {
        Quantity::Status(value) => value.name().contains(filter),
        Quantity::Parameter { number, name, .. } => {
            name.to_lowercase().contains(filter) || number.to_string().starts_with(filter)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::StatusValue;
    use super::*;
    use ratatui::crossterm::event::{KeyCode, KeyModifiers};

    fn parameter(number: u16, name: &str) -> Quantity {
        Quantity::Parameter {
            number,
            name: name.into(),
            line: format!("GAP {number}, 0"),
        }
    }

    fn typed(picker: &mut Picker, text: &str) {
        for c in text.chars() {
            picker.key(None, &KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE));
        }
    }

    #[test]
    fn typing_narrows_by_name_or_by_the_start_of_a_number() {
        let mut picker = Picker::new(
            0,
            "motor 0",
            vec![
                Quantity::Status(StatusValue::Position),
                Quantity::Status(StatusValue::Load),
                parameter(6, "Maximum current"),
                parameter(206, "Actual load value"),
                parameter(20, "Right limit switch"),
            ],
        );
        assert_eq!(picker.shown().len(), 5);
        typed(&mut picker, "LOAD");
        assert_eq!(
            picker.shown(),
            [
                &Quantity::Status(StatusValue::Load),
                &parameter(206, "Actual load value")
            ]
        );
        let mut picker = Picker::new(0, "motor 0", picker.choices.clone());
        typed(&mut picker, "20");
        assert_eq!(
            picker.shown(),
            [
                &parameter(206, "Actual load value"),
                &parameter(20, "Right limit switch")
            ]
        );
        picker.key(Some(Action::HistoryNext), &KeyEvent::from(KeyCode::Down));
        assert_eq!(picker.chosen(), Some(parameter(20, "Right limit switch")));
        // The cursor stops at the ends.
        picker.key(Some(Action::HistoryNext), &KeyEvent::from(KeyCode::Down));
        assert_eq!(picker.chosen(), Some(parameter(20, "Right limit switch")));
        picker.key(Some(Action::ScrollTop), &KeyEvent::from(KeyCode::Home));
        picker.key(Some(Action::HistoryPrevious), &KeyEvent::from(KeyCode::Up));
        assert_eq!(picker.chosen(), Some(parameter(206, "Actual load value")));
        typed(&mut picker, "x");
        assert_eq!(picker.chosen(), None);
    }
}
