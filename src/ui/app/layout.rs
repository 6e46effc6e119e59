//! How the console shares out the screen: the regions, the tabs, the status bar.

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph};

use super::App;
use crate::device::LinkState;
use crate::ui::keymap::Action;
use crate::ui::pane::{Region, View, key_label};
use crate::ui::theme::Role;

/// Below this many rows (or columns) for the panes, every pane is a tab of
/// one region.
pub const TILE_MIN_HEIGHT: u16 = 16;
pub const TILE_MIN_WIDTH: u16 = 40;
/// From this width the side panes get a column of their own.
pub const SIDE_MIN_WIDTH: u16 = 160;
/// Rows the main region keeps at least when the top region is tall.
const MAIN_MIN_HEIGHT: u16 = 10;

/// Which part of the screen a pane is drawn in, after the screen size
/// decided how many parts there are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Slot {
    Top,
    Main,
    Side,
}

impl App {
    /// Draw the whole screen.
    pub fn render(&mut self, frame: &mut Frame) {
        self.dirty = false;
        let area = frame.area();
        // Ordinary text first; every other role patches over it.
        frame.render_widget(Block::default().style(self.theme.style(Role::Normal)), area);
        let [body, status] =
            Layout::vertical([Constraint::Min(1), Constraint::Length(1)]).areas(area);
        self.drawn.clear();
        for (slot, rect) in self.slots(body) {
            let members: Vec<usize> = (0..self.panes.len())
                .filter(|&i| self.slot_of(i, body) == slot)
                .collect();
            let Some(&shown) = members
                .iter()
                .max_by_key(|&&i| self.focused_at.get(i).copied().unwrap_or(0))
            else {
                continue;
            };
            self.render_slot(frame, rect, &members, shown);
        }
        self.render_status(frame, status);
    }

    /// The slots the screen has room for, with their areas.
    fn slots(&self, body: Rect) -> Vec<(Slot, Rect)> {
        let mode = Mode::of(body);
        if mode == Mode::Tabs {
            return vec![(Slot::Main, body)];
        }
        let has = |region: Region| self.panes.iter().any(|p| p.region() == region);
        let mut slots = Vec::new();
        let mut rest = body;
        if has(Region::Top) {
            let view = self.view(false);
            let inner_width = body.width.saturating_sub(2);
            let room = body.height.saturating_sub(MAIN_MIN_HEIGHT);
            let wanted = self
                .panes
                .iter()
                .filter(|p| p.region() == Region::Top)
                .filter_map(|p| p.height_hint(&view, inner_width, room.saturating_sub(2)))
                .max()
                .unwrap_or(body.height / 3)
                .saturating_add(2);
            let top = wanted.min(room);
            let [top_area, below] =
                Layout::vertical([Constraint::Length(top), Constraint::Min(0)]).areas(body);
            slots.push((Slot::Top, top_area));
            rest = below;
        }
        if mode == Mode::Columns && has(Region::Side) && has(Region::Main) {
            let [main, side] =
                Layout::horizontal([Constraint::Percentage(55), Constraint::Percentage(45)])
                    .areas(rest);
            slots.push((Slot::Main, main));
            slots.push((Slot::Side, side));
        } else {
            slots.push((Slot::Main, rest));
        }
        slots
    }

    fn slot_of(&self, index: usize, body: Rect) -> Slot {
        let Some(pane) = self.panes.get(index) else {
            return Slot::Main;
        };
        match (Mode::of(body), pane.region()) {
            (Mode::Tabs, _) => Slot::Main,
            (_, Region::Top) => Slot::Top,
            (Mode::Columns, Region::Side)
                if self.panes.iter().any(|p| p.region() == Region::Main) =>
            {
                Slot::Side
            }
            _ => Slot::Main,
        }
    }

    fn view(&self, focused: bool) -> View<'_> {
        View {
            theme: &self.theme,
            keymap: &self.keymap,
            session: self.snapshot.as_ref(),
            modules: &self.modules,
            module: self.module,
            focused,
            shown: true,
        }
    }

    /// A bordered slot: its title is the shown pane's, or a tab strip when
    /// several panes share the slot.
    fn render_slot(&mut self, frame: &mut Frame, area: Rect, members: &[usize], shown: usize) {
        let focused = shown == self.focus;
        let theme = &self.theme;
        let border = theme.style(if focused {
            Role::BorderFocused
        } else {
            Role::Border
        });
        let view = View {
            theme,
            keymap: &self.keymap,
            session: self.snapshot.as_ref(),
            modules: &self.modules,
            module: self.module,
            focused,
            shown: true,
        };
        let full = |index: usize, pane: &dyn crate::ui::pane::Pane| {
            if members.len() > 1 {
                format!("{} {}", index + 1, pane.title(&view))
            } else {
                pane.title(&view)
            }
        };
        // When the strip does not fit the border (eight tabs at 80
        // columns), the tabs not shown keep the first word of their title,
        // then only their number, so the one shown is always seen whole.
        let first_word = |index: usize, pane: &dyn crate::ui::pane::Pane| {
            let title = pane.title(&view);
            let word = title
                .split_whitespace()
                .next()
                .unwrap_or_default()
                .to_string();
            format!("{} {word}", index + 1)
        };
        let room = usize::from(area.width.saturating_sub(2));
        let strip_with = |label: &dyn Fn(usize, &dyn crate::ui::pane::Pane) -> String| {
            members
                .iter()
                .filter_map(|&i| {
                    let pane = self.panes.get(i)?;
                    Some(if i == shown {
                        full(i, pane.as_ref())
                    } else {
                        label(i, pane.as_ref())
                    })
                })
                .map(|text| text.chars().count())
                .sum::<usize>()
                + 3 * members.len().saturating_sub(1)
                // The space before the first tab (the one after the last
                // may be cut).
                + 1
        };
        let shortening = if strip_with(&full) <= room {
            0
        } else if strip_with(&first_word) <= room {
            1
        } else {
            2
        };
        let mut title = vec![Span::raw(" ")];
        for (n, &index) in members.iter().enumerate() {
            let Some(pane) = self.panes.get(index) else {
                continue;
            };
            if n > 0 {
                title.push(Span::styled(" │ ", border));
            }
            let text = match shortening {
                _ if index == shown => full(index, pane.as_ref()),
                0 => full(index, pane.as_ref()),
                1 => first_word(index, pane.as_ref()),
                _ => (index + 1).to_string(),
            };
            let style = if index == shown {
                theme.style(Role::Title)
            } else {
                theme.style(Role::Muted)
            };
            title.push(Span::styled(text, style));
        }
        title.push(Span::raw(" "));
        let block = Block::default()
            .borders(Borders::ALL)
            .border_style(border)
            .title(Line::from(title));
        let inner = block.inner(area);
        frame.render_widget(block, area);
        if let Some(pane) = self.panes.get_mut(shown) {
            pane.render(frame, inner, &view);
        }
        self.drawn.push((shown, area));
    }

    fn render_status(&self, frame: &mut Frame, area: Rect) {
        let theme = &self.theme;
        let bar = theme.style(Role::StatusBar);
        let key = theme.style(Role::StatusKey);
        let mut spans = vec![
            Span::styled(
                format!(" {} ", self.keymap.stop_hint()),
                theme.style(Role::Emergency),
            ),
            Span::styled(" ", bar),
        ];
        if let Some((_, stop)) = &self.last_stop {
            spans.push(Span::styled(format!("{stop} │ "), bar));
        }
        for activity in self.panes.iter().filter_map(|p| p.activity()) {
            spans.push(Span::styled(activity, key));
            spans.push(Span::styled(" │ ", bar));
        }
        match &self.snapshot {
            Some(s) => {
                let state = match &s.link {
                    LinkState::Connected { .. } => "connected".to_string(),
                    LinkState::Disconnected {
                        reason,
                        attempts: 0,
                        ..
                    } => format!("LOST: {reason}"),
                    LinkState::Disconnected {
                        reason, attempts, ..
                    } => format!("LOST, reconnecting (attempt {attempts} failed): {reason}"),
                    LinkState::Closed => "closed".to_string(),
                };
                // With several modules, which one lines go to.
                let module = if self.modules.len() > 1 {
                    format!("module {}/{} ", self.module + 1, self.modules.len())
                } else {
                    String::new()
                };
                spans.push(Span::styled(
                    format!("{module}{} #{} {state} │ ", s.link_name, s.address),
                    bar,
                ));
                let poll = match &self.busy {
                    // Nothing is polled while the controller runs a line.
                    Some(_) if s.poll.is_some() => crate::ui::axes::SUSPENDED.to_string(),
                    _ => crate::ui::axes::poll_text(s),
                };
                spans.push(Span::styled(format!("{poll} │ "), bar));
                if let Some(axis) = s.selected_axis().filter(|_| s.axes.len() > 1) {
                    spans.push(Span::styled(format!("axis {} │ ", axis.name), bar));
                }
            }
            None => spans.push(Span::styled("not connected │ ", bar)),
        }
        let context = self.context();
        let hints = vec![
            Span::styled(key_label(&self.keymap, context, Action::Quit), key),
            Span::styled(" quit ", bar),
            Span::styled(key_label(&self.keymap, context, Action::Help), key),
            Span::styled(" help", bar),
        ];
        // The quit and help keys never fall off: what comes before them is
        // cut to leave them room.
        let room = usize::from(area.width).saturating_sub(width_of(&hints));
        let mut spans = if width_of(&spans) > room {
            let mut kept = cut(spans, room.saturating_sub(1));
            kept.push(Span::styled(" ", bar));
            kept
        } else {
            spans
        };
        spans.extend(hints);
        let line = Line::from(spans).style(bar);
        frame.render_widget(Paragraph::new(line).style(Style::default()), area);
    }
}

/// Columns `spans` take.
fn width_of(spans: &[Span]) -> usize {
    spans.iter().map(|s| s.content.chars().count()).sum()
}

/// `spans` cut to `room` columns, the last one kept ending in an ellipsis.
fn cut(spans: Vec<Span<'static>>, room: usize) -> Vec<Span<'static>> {
    let mut left = room;
    let mut kept = Vec::new();
    for span in spans {
        let width = span.content.chars().count();
        if width <= left {
            left -= width;
            kept.push(span);
            continue;
        }
        if left > 0 {
            let text = crate::ui::text::fit(&span.content, left);
            kept.push(Span::styled(text, span.style));
        }
        break;
    }
    kept
}

/// How the screen is shared out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// One pane at a time, as tabs (80×24).
    Tabs,
    /// The top region over the main region.
    Rows,
    /// The top region over main and side columns.
    Columns,
}

impl Mode {
    fn of(body: Rect) -> Mode {
        if body.width < TILE_MIN_WIDTH || body.height < TILE_MIN_HEIGHT {
            Mode::Tabs
        } else if body.width < SIDE_MIN_WIDTH {
            Mode::Rows
        } else {
            Mode::Columns
        }
    }
}
