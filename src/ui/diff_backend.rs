//! A crossterm backend that writes only what changed on the screen.
//!
//! ratatui hands the backend the cells that differ from the last frame;
//! crossterm's own backend then spends more on the frame than on the
//! cells: every frame ends with four resets (`ESC[39m ESC[49m ESC[59m
//! ESC[0m`, 19 bytes) even when no cell changed, the cursor is shown (or
//! hidden) and moved again each frame although it is where it was, and a
//! jump to another cell of the same row is a full `ESC[row;colH`. With a
//! moving axis drawn 20 times a second that was about 45 of the 75 bytes
//! of each frame (bench/console_cost.py).
//!
//! [`DiffBackend`] draws the same cells with the same colours and
//! attributes, but
//! - writes nothing at all for a frame without changed cells;
//! - ends a frame that set colours or attributes with one `ESC[0m`, which
//!   resets all of them;
//! - moves along a row with `ESC[colG` (the row is known: the last cell
//!   drawn was on it) and skips the move to the very next cell;
//! - shows, hides and places the cursor only when that changes anything.

use std::io::{self, Write};

use ratatui::backend::{Backend, ClearType, CrosstermBackend, IntoCrossterm, WindowSize};
use ratatui::buffer::Cell;
use ratatui::crossterm::cursor::{Hide, MoveTo, MoveToColumn, Show};
use ratatui::crossterm::queue;
use ratatui::crossterm::style::{
    Attribute, Colors, ContentStyle, Print, SetAttribute, SetAttributes, SetColors,
};
use ratatui::layout::{Position, Size};
use ratatui::style::{Color, Modifier, Style};

/// A backend over `W` (the terminal) that writes only what changed.
pub struct DiffBackend<W: Write> {
    inner: CrosstermBackend<W>,
    /// Whether the terminal shows the cursor, as far as this backend made
    /// it (`None`: not known yet).
    cursor_shown: Option<bool>,
    /// Where the terminal's cursor is, when known: after drawing cells it
    /// is wherever the last one left it.
    cursor_at: Option<Position>,
}

impl<W: Write> DiffBackend<W> {
    pub fn new(writer: W) -> DiffBackend<W> {
        DiffBackend {
            inner: CrosstermBackend::new(writer),
            cursor_shown: None,
            cursor_at: None,
        }
    }
}

/// The attributes of `modifier` as crossterm writes them.
fn attributes(modifier: Modifier) -> SetAttributes {
    let style: ContentStyle = Style::default().add_modifier(modifier).into_crossterm();
    SetAttributes(style.attributes)
}

impl<W: Write> Backend for DiffBackend<W> {
    type Error = io::Error;

    fn draw<'a, I>(&mut self, content: I) -> io::Result<()>
    where
        I: Iterator<Item = (u16, u16, &'a Cell)>,
    {
        let out = &mut self.inner;
        // The terminal's colours and attributes as this frame left them;
        // each frame starts from the reset the last one ended with.
        let (mut fg, mut bg, mut modifier) = (Color::Reset, Color::Reset, Modifier::empty());
        let mut last: Option<Position> = None;
        for (x, y, cell) in content {
            match last {
                Some(p) if p.y == y && x == p.x + 1 => {}
                Some(p) if p.y == y => queue!(out, MoveToColumn(x))?,
                _ => queue!(out, MoveTo(x, y))?,
            }
            last = Some(Position { x, y });
            if cell.modifier != modifier {
                // Taking attributes away one by one has a code for each;
                // a reset and the new set is shorter and always right (it
                // resets the colours too).
                if !(modifier - cell.modifier).is_empty() {
                    queue!(out, SetAttribute(Attribute::Reset))?;
                    (fg, bg) = (Color::Reset, Color::Reset);
                }
                queue!(out, attributes(cell.modifier))?;
                modifier = cell.modifier;
            }
            if cell.fg != fg || cell.bg != bg {
                queue!(
                    out,
                    SetColors(Colors::new(
                        cell.fg.into_crossterm(),
                        cell.bg.into_crossterm()
                    ))
                )?;
                (fg, bg) = (cell.fg, cell.bg);
            }
            queue!(out, Print(cell.symbol()))?;
        }
        if last.is_some() {
            // Where the last cell left the cursor depends on its width.
            self.cursor_at = None;
        }
        if (fg, bg, modifier) != (Color::Reset, Color::Reset, Modifier::empty()) {
            queue!(out, SetAttribute(Attribute::Reset))?;
        }
        Ok(())
    }

    fn append_lines(&mut self, n: u16) -> io::Result<()> {
        self.cursor_at = None;
        self.inner.append_lines(n)
    }

    fn hide_cursor(&mut self) -> io::Result<()> {
        if self.cursor_shown != Some(false) {
            queue!(self.inner, Hide)?;
            self.cursor_shown = Some(false);
        }
        Ok(())
    }

    fn show_cursor(&mut self) -> io::Result<()> {
        if self.cursor_shown != Some(true) {
            queue!(self.inner, Show)?;
            self.cursor_shown = Some(true);
        }
        Ok(())
    }

    fn get_cursor_position(&mut self) -> io::Result<Position> {
        self.inner.get_cursor_position()
    }

    fn set_cursor_position<P: Into<Position>>(&mut self, position: P) -> io::Result<()> {
        let position = position.into();
        if self.cursor_at != Some(position) {
            queue!(self.inner, MoveTo(position.x, position.y))?;
            self.cursor_at = Some(position);
        }
        Ok(())
    }

    fn clear(&mut self) -> io::Result<()> {
        self.cursor_at = None;
        self.inner.clear()
    }

    fn clear_region(&mut self, clear_type: ClearType) -> io::Result<()> {
        self.cursor_at = None;
        self.inner.clear_region(clear_type)
    }

    fn size(&self) -> io::Result<Size> {
        self.inner.size()
    }

    fn window_size(&mut self) -> io::Result<WindowSize> {
        self.inner.window_size()
    }

    fn flush(&mut self) -> io::Result<()> {
        Backend::flush(&mut self.inner)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ratatui::buffer::Buffer;
    use ratatui::layout::Rect;

    use std::cell::RefCell;
    use std::rc::Rc;

    /// A terminal that keeps what it was sent.
    #[derive(Clone, Default)]
    struct Screen(Rc<RefCell<Vec<u8>>>);

    impl Write for Screen {
        fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
            self.0.borrow_mut().extend_from_slice(bytes);
            Ok(bytes.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    impl Screen {
        /// What it was sent since the last look.
        fn take(&self) -> String {
            String::from_utf8(std::mem::take(&mut *self.0.borrow_mut())).expect("utf-8")
        }
    }

    /// What drawing `next` over `previous` writes.
    fn written(previous: &Buffer, next: &Buffer) -> String {
        let screen = Screen::default();
        let mut backend = DiffBackend::new(screen.clone());
        backend.draw(previous.diff(next).into_iter()).expect("draw");
        screen.take()
    }

    fn buffer(lines: &[&str], style: Style) -> Buffer {
        let mut buffer = Buffer::empty(Rect::new(0, 0, 12, lines.len() as u16));
        for (y, line) in lines.iter().enumerate() {
            buffer.set_string(0, y as u16, line, style);
        }
        buffer
    }

    #[test]
    fn a_frame_without_changed_cells_writes_nothing() {
        let style = Style::default().fg(Color::Rgb(208, 208, 208));
        let screen = buffer(&["pos 1234"], style);
        assert_eq!(written(&screen, &screen.clone()), "");
    }

    #[test]
    fn cells_of_one_row_move_by_column_and_the_frame_ends_with_one_reset() {
        let style = Style::default().fg(Color::Rgb(208, 208, 208));
        let before = buffer(&["pos 1234 ab"], style);
        let after = buffer(&["pos 1299 xb"], style);
        // Columns 6 and 7 are neighbours: one move; column 9 is on the
        // same row: a column move, not a row and column one.
        assert_eq!(
            written(&before, &after),
            "\x1b[1;7H\x1b[38;2;208;208;208;49m99\x1b[10Gx\x1b[0m"
        );
    }

    #[test]
    fn another_row_is_a_full_move_and_plain_cells_need_no_reset() {
        let before = buffer(&["a", "b"], Style::default());
        let after = buffer(&["c", "d"], Style::default());
        assert_eq!(written(&before, &after), "\x1b[1;1Hc\x1b[2;1Hd");
    }

    #[test]
    fn an_attribute_taken_away_resets_and_sets_the_colours_again() {
        let red = Style::default().fg(Color::Red);
        let mut before = buffer(&["ab"], red);
        before.set_string(0, 0, "a", red.add_modifier(Modifier::BOLD));
        let mut after = buffer(&["xy"], red);
        after.set_string(0, 0, "x", red.add_modifier(Modifier::BOLD));
        assert_eq!(
            written(&before, &after),
            "\x1b[1;1H\x1b[1m\x1b[38;5;1;49mx\x1b[0m\x1b[38;5;1;49my\x1b[0m"
        );
    }

    #[test]
    fn the_cursor_is_shown_hidden_and_placed_only_when_that_changes_anything() {
        let screen = Screen::default();
        let mut backend = DiffBackend::new(screen.clone());
        let frame = |b: &mut DiffBackend<Screen>, cells: bool| {
            let before = buffer(&["a"], Style::default());
            let after = buffer(&[if cells { "b" } else { "a" }], Style::default());
            b.draw(before.diff(&after).into_iter()).expect("draw");
            b.show_cursor().expect("show");
            b.set_cursor_position(Position::new(3, 2)).expect("place");
            screen.take()
        };
        assert_eq!(frame(&mut backend, false), "\x1b[?25h\x1b[3;4H");
        assert_eq!(frame(&mut backend, false), "", "nothing changed");
        // Drawing a cell moved the terminal's cursor: it is put back.
        assert_eq!(frame(&mut backend, true), "\x1b[1;1Hb\x1b[3;4H");
        backend.hide_cursor().expect("hide");
        backend.hide_cursor().expect("hide");
        assert_eq!(screen.take(), "\x1b[?25l");
    }
}
