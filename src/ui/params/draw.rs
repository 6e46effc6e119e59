//! Drawing the parameter table: the rows in columns fitted to the width,
//! the footer, the differences before an import.

use super::*;
use crate::protocol::parameters::ParamRole;

impl ParamsPane {
    /// The value column of a row: the value as the family writes it in
    /// its unit ([`ParameterSet::value_text`]), else what is known of it.
    fn value_text(&self, row: &ParamRow, view: &View) -> (String, Role) {
        let key = (row.scope, row.number);
        let reading = self
            .in_flight
            .as_ref()
            .is_some_and(|(_, j)| (j.row.scope, j.row.number) == key && j.op == ParamOp::Read);
        match self.cell(row) {
            _ if !row.access.read && !self.remembers_writes => ("write-only".into(), Role::Muted),
            Some(Cell::Value(v)) => {
                let changed = self.first.get(&key).is_some_and(|first| *first != v);
                (
                    Self::parameters(view).map_or_else(|| v.to_string(), |p| p.value_text(row, v)),
                    if changed { Role::Changed } else { Role::Normal },
                )
            }
            Some(Cell::Unknown(_)) => match self.known.get(row.scope, row.number) {
                Some(_) => ("since reset".into(), Role::Warning),
                None => ("not written".into(), Role::Muted),
            },
            Some(Cell::Unreadable(_)) => ("unreadable".into(), Role::Warning),
            Some(Cell::NoAnswer(_)) => ("no answer".into(), Role::Error),
            None if reading => ("reading".into(), Role::Muted),
            None => ("·".into(), Role::Muted),
        }
    }

    /// The real-world value of a row, else its note if that fits `width`
    /// (a longer one shows under the table for the selected row).
    fn physical_text(&self, row: &ParamRow, view: &View, width: usize) -> String {
        let Some(Cell::Value(v)) = self.cell(row) else {
            return String::new();
        };
        if let Some(text) = self.real_text(row, v, view) {
            return text;
        }
        self.note(row, view)
            .filter(|note| note.chars().count() <= width)
            .unwrap_or_default()
    }

    /// A row's value in real-world units: pps or rpm, or in the axis's
    /// own unit when those are shown (its mechanics and the family's unit
    /// law, with the values read of the other rows).
    fn real_text(&self, row: &ParamRow, value: i64, view: &View) -> Option<String> {
        let parameters = Self::parameters(view)?;
        if !self.axis_units {
            return parameters
                .physical(row, value, self.unit, &self.axis_value(row.scope))
                .map(|p| p.to_string());
        }
        let session = view.session?;
        let law = session.family.console.units()?;
        let quantity = law.row_quantity(row)?;
        let Scope::Axis(axis) = row.scope else {
            return None;
        };
        let mechanics = session.mechanics.get(axis)?;
        let value_of = |scope: Scope, number: u16| {
            self.value(scope, number)
                .or_else(|| session.settings.value(scope, number))
        };
        let converted = crate::protocol::units::to_units(
            law,
            mechanics,
            axis,
            quantity,
            value as f64,
            &value_of,
        )
        .ok()?;
        Some(
            crate::protocol::units::InUnits {
                value: converted,
                quantity,
                unit: &mechanics.unit,
            }
            .to_string(),
        )
    }

    /// What the family says a row's value means beyond its number (a
    /// per-axis speed of 0: the global one; a bit word: its fields).
    fn note(&self, row: &ParamRow, view: &View) -> Option<String> {
        let Some(Cell::Value(v)) = self.cell(row) else {
            return None;
        };
        let value_of = |scope: Scope, number: u16| self.value(scope, number);
        Self::parameters(view)?.value_note(row, v, &value_of)
    }

    /// How wide the numbers, values and real-world values of every row
    /// of the tables are, so that their columns cut none.
    fn widest(&self, view: &View) -> Widest {
        let rows = || self.tables.iter().flat_map(|t| t.rows.iter());
        let widest = |texts: &mut dyn Iterator<Item = String>| {
            texts.map(|t| t.chars().count()).max().unwrap_or(0)
        };
        let real = |row: &ParamRow| {
            let Some(Cell::Value(v)) = self.cell(row) else {
                return None;
            };
            self.real_text(row, v, view)
        };
        Widest {
            number: widest(&mut rows().map(|r| r.number.to_string())),
            value: widest(&mut rows().map(|r| self.value_text(r, view).0)),
            unit: widest(&mut rows().map(|r| r.unit.to_string())),
            range: widest(&mut rows().map(|r| {
                Self::parameters(view).map_or_else(|| r.range.to_string(), |p| p.range_text(r))
            })),
            real: widest(&mut rows().filter_map(real)),
        }
    }

    fn row_line(
        &self,
        row: &ParamRow,
        columns: &Columns,
        selected: bool,
        view: &View,
    ) -> Line<'static> {
        let theme = view.theme;
        let base = if selected {
            theme.style(if view.focused {
                Role::Selection
            } else {
                Role::Accent
            })
        } else {
            Style::default()
        };
        let on = |role: Role| {
            if selected { base } else { theme.style(role) }
        };
        let mut spans = vec![Span::styled(
            format!("{:>w$} ", row.number, w = columns.number),
            on(Role::Muted),
        )];
        spans.extend(name_spans(
            &row.name,
            &self.filter,
            columns.name,
            on(Role::Normal),
            on(Role::Matched),
        ));
        let (value, role) = self.value_text(row, view);
        // The column is as wide as the widest value: a number is never cut.
        spans.push(Span::styled(
            format!(" {:>w$}", fit(&value, columns.value), w = columns.value),
            on(role),
        ));
        spans.push(Span::styled(
            format!(" {:<w$}", fit(row.unit, columns.unit), w = columns.unit),
            on(Role::Muted),
        ));
        if columns.real > 0 {
            let real = self.physical_text(row, view, columns.real);
            spans.push(Span::styled(
                format!(" {:>w$}", fit(&real, columns.real), w = columns.real),
                on(Role::Accent),
            ));
        }
        if columns.range > 0 {
            let range =
                Self::parameters(view).map_or_else(|| row.range.to_string(), |p| p.range_text(row));
            spans.push(Span::styled(
                format!(" {:<w$}", fit(&range, columns.range), w = columns.range),
                on(Role::Muted),
            ));
        }
        spans.push(Span::styled(
            format!(" {:<4}", row.access.to_string()),
            on(Role::Muted),
        ));
        if columns.description > 0 {
            spans.push(Span::styled(
                format!(" {}", fit(row.description, columns.description)),
                on(Role::Muted),
            ));
        }
        Line::from(spans).style(base)
    }

    fn heading(columns: &Columns) -> String {
        let mut text = format!(
            "{:>n$} {:<w$}",
            "No",
            "Name",
            n = columns.number,
            w = columns.name
        );
        text.push_str(&format!(
            " {:>w$} {:<u$}",
            "Value",
            "Unit",
            w = columns.value,
            u = columns.unit
        ));
        if columns.real > 0 {
            text.push_str(&format!(" {:>w$}", "Real", w = columns.real));
        }
        if columns.range > 0 {
            text.push_str(&format!(" {:<w$}", "Range", w = columns.range));
        }
        text.push_str(" Acc.");
        if columns.description > 0 {
            text.push_str(" Description");
        }
        text
    }

    fn status_text(&self, view: &View) -> String {
        let rows = self.shown_rows().len();
        let mut parts = vec![match view.session.and_then(Snapshot::selected_axis) {
            Some(axis) => format!("{} · {}", counted(rows, "parameter"), axis.name),
            None => counted(rows, "parameter"),
        }];
        if !self.filter.is_empty() {
            parts.push(format!("filter \"{}\"", self.filter));
        }
        if self.progress.total > 0 {
            parts.push(format!(
                "busy {}/{}",
                self.progress.done, self.progress.total
            ));
        }
        parts.push(match (self.axis_units, self.unit) {
            (true, _) => "real: axis units".into(),
            (false, SpeedUnit::Pps) => "real: pps".into(),
            (false, SpeedUnit::Rpm) => "real: rpm".into(),
        });
        parts.join(" · ")
    }

    /// The footer: a prompt while typing, else the message, else the
    /// selected row's details and the keys.
    fn footer(&self, view: &View, width: usize) -> Vec<(Line<'static>, Option<usize>)> {
        let theme = view.theme;
        let key = |action| key_label(view.keymap, Context::Parameters, action);
        let cmd = |action| key_label(view.keymap, Context::Command, action);
        let prompt = |label: String, field: &Field, hint: String| {
            let column = label.chars().count() + field.cursor_column();
            (
                Line::from(vec![
                    Span::styled(label, theme.style(Role::Prompt)),
                    Span::styled(field.text().to_string(), theme.style(Role::Normal)),
                    Span::styled(format!("  {hint}"), theme.style(Role::Muted)),
                ]),
                Some(column),
            )
        };
        let range_text = |row: &ParamRow| {
            Self::parameters(view).map_or_else(|| row.range.to_string(), |p| p.range_text(row))
        };
        let mut lines = Vec::new();
        match &self.mode {
            Mode::Edit { row, field } => lines.push(prompt(
                format!("{} = ", row.name),
                field,
                format!(
                    "{} {} · {} writes, {} cancels",
                    range_text(row),
                    row.unit,
                    cmd(Action::Submit),
                    cmd(Action::Cancel)
                ),
            )),
            Mode::Filter(field) => lines.push(prompt(
                "filter: ".into(),
                field,
                format!(
                    "{} keeps it, {} clears it",
                    cmd(Action::Submit),
                    cmd(Action::Cancel)
                ),
            )),
            Mode::File { purpose, field } => {
                let label = match purpose {
                    FileUse::Export => "export to: ",
                    FileUse::Import => "import from: ",
                    FileUse::Compare => "compare with: ",
                };
                lines.push(prompt(
                    label.into(),
                    field,
                    format!("{} · {} cancels", cmd(Action::Submit), cmd(Action::Cancel)),
                ));
            }
            Mode::Browse | Mode::Diff(_) => {}
        }
        // A message (a refusal naming the line to type instead) wraps
        // rather than losing its end.
        if let Some((role, text)) = &self.message {
            for part in wrap(text, width, MESSAGE_ROWS) {
                lines.push((Line::styled(part, theme.style(*role)), None));
            }
        }
        if let (Mode::Browse, Some(row)) = (&self.mode, self.selected_row()) {
            let mut detail = format!("{}: {} {}", row.name, range_text(row), row.access);
            if let Some(default) = row.default {
                detail.push_str(&format!(", default {default}"));
            }
            match self.cell(row) {
                Some(Cell::Unreadable(why) | Cell::NoAnswer(why)) => {
                    detail.push_str(&format!(" · {why}"));
                }
                // What is known of a value the module cannot be asked for.
                Some(Cell::Unknown(why)) => {
                    detail.push_str(&format!(" · {why} · {}", row.description));
                }
                Some(Cell::Value(_)) if !row.access.read => {
                    detail.push_str(&format!(
                        " · written this session, never read back · {}",
                        row.description
                    ));
                }
                _ => detail.push_str(&format!(" · {}", row.description)),
            }
            lines.push((
                Line::styled(fit(&detail, width), theme.style(Role::Muted)),
                None,
            ));
            for part in self
                .note(row, view)
                .map(|note| wrap(&note, width, NOTE_ROWS))
                .unwrap_or_default()
            {
                lines.push((Line::styled(part, theme.style(Role::Accent)), None));
            }
            lines.push((
                Line::styled(
                    fit(
                        &format!(
                            "{} edit · {} store · {} restore · {} refresh · {} filter · {} export · {} import · {} diff",
                            key(Action::ParameterEdit),
                            key(Action::ParameterStore),
                            key(Action::ParameterRestore),
                            key(Action::ParameterRefresh),
                            key(Action::ParameterFilter),
                            key(Action::ParameterExport),
                            key(Action::ParameterImport),
                            key(Action::ParameterDiff),
                        ),
                        width,
                    ),
                    theme.style(Role::Muted),
                ),
                None,
            ));
        }
        lines
    }

    fn render_diff(&self, diff: &Diff, frame: &mut Frame, area: Rect, view: &View) {
        let theme = view.theme;
        let width = usize::from(area.width);
        let key = |action| key_label(view.keymap, Context::Parameters, action);
        let verb = if diff.import { "Import" } else { "Compare" };
        let mut lines = vec![Line::styled(
            fit(
                &format!(
                    "{verb} {}: {} differ, {} the same",
                    diff.path.display(),
                    diff.comparison.differences.len(),
                    diff.comparison.same.len()
                ),
                width,
            ),
            theme.style(Role::Title),
        )];
        let writable = diff
            .comparison
            .differences
            .iter()
            .filter(|d| d.row.role == ParamRole::Setting)
            .count();
        let hint = if diff.import && writable > 0 {
            format!(
                "{} writes the {} below, {} drops them; nothing is written yet",
                key(Action::ParameterWrite),
                counted(writable, "file value"),
                key(Action::Cancel)
            )
        } else {
            format!("{} closes", key(Action::Cancel))
        };
        lines.push(Line::styled(fit(&hint, width), theme.style(Role::Accent)));
        let mut body: Vec<Line> = Vec::new();
        for d in &diff.comparison.differences {
            let device = match &d.module {
                Cell::Value(v) => v.to_string(),
                Cell::Unreadable(_) => "unreadable".into(),
                Cell::NoAnswer(_) => "no answer".into(),
                Cell::Unknown(_) => "unknown".into(),
            };
            let label = match d.row.scope {
                Scope::Axis(n) => format!("axis {n} #{}", d.row.number),
                Scope::Bank(n) => format!("bank {n} #{}", d.row.number),
            };
            let mut text = format!(
                "{label:<12} {:<28} module {device:>11} → file {:>11}",
                fit(&d.row.name, 28),
                d.file
            );
            if d.row.role == ParamRole::Link {
                text.push_str("  (link setting: not written)");
            }
            let role = if d.row.role == ParamRole::Setting {
                Role::Changed
            } else {
                Role::Warning
            };
            body.push(Line::styled(fit(&text, width), theme.style(role)));
        }
        for problem in &diff.problems {
            body.push(Line::styled(
                fit(problem, width),
                theme.style(Role::Warning),
            ));
        }
        if body.is_empty() {
            body.push(Line::styled(
                "the module holds every value of the file",
                theme.style(Role::Ok),
            ));
        }
        lines.extend(body.into_iter().skip(diff.scroll));
        frame.render_widget(Paragraph::new(lines), area);
    }

    /// Draw the pane into `area`.
    pub(super) fn draw(&mut self, frame: &mut Frame, area: Rect, view: &View) {
        if area.height == 0 || area.width == 0 {
            return;
        }
        self.follow(view);
        let theme = view.theme;
        let width = usize::from(area.width);
        if view.session.is_none() {
            frame.render_widget(
                Paragraph::new(Line::styled(
                    "not connected: the parameters show once a module is",
                    theme.style(Role::Muted),
                )),
                area,
            );
            return;
        }
        if let Mode::Diff(diff) = &self.mode {
            self.render_diff(diff, frame, area, view);
            return;
        }
        if self.tables.is_empty() {
            let family = view.session.map_or("", |s| s.family.name);
            frame.render_widget(
                Paragraph::new(Line::styled(
                    format!("the {family} family has no parameter tables"),
                    theme.style(Role::Muted),
                )),
                area,
            );
            return;
        }
        let footer = self.footer(view, width);
        let footer_rows = footer.len().min(usize::from(area.height).saturating_sub(3));
        let body_rows = usize::from(area.height).saturating_sub(2 + footer_rows);
        self.page = body_rows.max(1);
        let columns = Columns::for_widths(width, self.widest(view));
        let mut lines = vec![
            Line::styled(
                fit(&self.status_text(view), width),
                theme.style(Role::Muted),
            ),
            Line::styled(
                fit(&Self::heading(&columns), width),
                theme.style(Role::Title),
            ),
        ];
        let items = self.items();
        let rows = items.iter().filter(|i| matches!(i, Item::Row(..))).count();
        self.selected = self.selected.min(rows.saturating_sub(1));
        // Where the selected row is among the lines; keep it in view (and
        // its table's header too when at the top).
        let mut seen = 0;
        let selected_line = items
            .iter()
            .position(|item| {
                if let Item::Row(..) = item {
                    seen += 1;
                    seen == self.selected + 1
                } else {
                    false
                }
            })
            .unwrap_or(0);
        if selected_line < self.offset + 1 {
            self.offset = selected_line.saturating_sub(1);
        }
        if body_rows > 0 && selected_line >= self.offset + body_rows {
            self.offset = selected_line + 1 - body_rows;
        }
        let mut row_index = items
            .iter()
            .take(self.offset)
            .filter(|i| matches!(i, Item::Row(..)))
            .count();
        for item in items.iter().skip(self.offset).take(body_rows) {
            match *item {
                Item::Header(t) => {
                    let title = self.tables.get(t).map_or("", |table| table.title.as_str());
                    lines.push(Line::styled(
                        fit(&format!("── {title} ──"), width),
                        theme.style(Role::Title),
                    ));
                }
                Item::Row(t, r) => {
                    if let Some(row) = self.tables.get(t).and_then(|table| table.rows.get(r)) {
                        lines.push(self.row_line(row, &columns, row_index == self.selected, view));
                    }
                    row_index += 1;
                }
            }
        }
        while lines.len() < 2 + body_rows {
            lines.push(Line::raw(""));
        }
        let mut cursor = None;
        for (i, (line, column)) in footer.into_iter().take(footer_rows).enumerate() {
            if let Some(column) = column {
                cursor = Some((column, 2 + body_rows + i));
            }
            lines.push(line);
        }
        frame.render_widget(Paragraph::new(lines), area);
        if view.focused
            && let Some((column, row)) = cursor
        {
            let x = area.x + (column.min(width.saturating_sub(1)) as u16);
            let y = area.y + (row as u16).min(area.height - 1);
            frame.set_cursor_position(Position::new(x, y));
        }
    }
}

/// How wide each column is at this width.
#[derive(Debug, Clone, Copy)]
struct Columns {
    /// The widest parameter number (4 for TMCL's; CMD-4CR rows number
    /// their command-table row and index, up to 5 digits).
    number: usize,
    name: usize,
    /// The widest value shown, at least 11.
    value: usize,
    /// The widest unit, at least 9.
    unit: usize,
    real: usize,
    range: usize,
    description: usize,
}

/// How wide the contents of the columns sized by them are.
#[derive(Debug, Clone, Copy)]
struct Widest {
    number: usize,
    value: usize,
    unit: usize,
    range: usize,
    real: usize,
}

impl Columns {
    /// Number (`number` wide, at least 4), value (as wide as the widest,
    /// at least 11: numbers are never cut), unit (as wide as the widest,
    /// at least 9) and access always; the
    /// real-world value (at least 12), the range (whole) and the
    /// description when there is room, in that order.
    fn for_widths(width: usize, widest: Widest) -> Columns {
        let number = widest.number.max(4);
        let value = widest.value.max(11);
        let unit = widest.unit.max(9);
        let real = widest.real.max(12);
        let fixed = number + 1 + value + 1 + unit + 1 + 5;
        const NAME_MIN: usize = 16;
        const NAME_MAX: usize = 34;
        let mut columns = Columns {
            number,
            name: 0,
            value,
            unit,
            real: 0,
            range: 0,
            description: 0,
        };
        let mut room = width.saturating_sub(fixed);
        if room > NAME_MIN + real {
            columns.real = real;
            room -= real + 1;
        }
        // The widest range whole or none, up to a full 32-bit span (23
        // characters): a longer list of values is cut, and without the
        // column, the footer shows the selected row's range whole.
        let range = widest.range.clamp("Range".len(), 23);
        // It leaves the name 28 columns at least.
        if room > 28 + range {
            columns.range = range;
            room -= range + 1;
        }
        if room > NAME_MAX + 20 {
            columns.name = NAME_MAX;
            columns.description = room - NAME_MAX - 1;
        } else {
            columns.name = room.max(1);
        }
        columns
    }

    /// [`Columns::for_widths`] for contents no wider than the least.
    #[cfg(test)]
    fn for_numbers(width: usize, number: usize) -> Columns {
        Columns::for_widths(
            width,
            Widest {
                number,
                value: 0,
                unit: 0,
                range: 23,
                real: 0,
            },
        )
    }
}

/// Footer lines a value's note may take at most.
const NOTE_ROWS: usize = 3;

/// Footer lines a message may take at most.
const MESSAGE_ROWS: usize = 3;

/// `text` in lines of at most `width` characters, broken between words,
/// at most `rows` of them (the last cut with an ellipsis if need be).
fn wrap(text: &str, width: usize, rows: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let needed = line.chars().count() + usize::from(!line.is_empty()) + word.chars().count();
        if !line.is_empty() && needed > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    let rows = rows.max(1);
    if lines.len() > rows {
        let rest = lines.split_off(rows - 1).join(" ");
        lines.push(rest);
    }
    lines.into_iter().map(|l| fit(&l, width)).collect()
}

/// The name in a column of `width`, the part matching `filter` marked.
fn name_spans(
    name: &str,
    filter: &str,
    width: usize,
    normal: Style,
    matched: Style,
) -> Vec<Span<'static>> {
    let shown = fit(name, width);
    let padded = format!("{shown:<width$}");
    let filter = filter.trim().to_lowercase();
    let lower = padded.to_lowercase();
    let found = (!filter.is_empty())
        .then(|| lower.find(&filter))
        .flatten()
        // Lower-casing may change byte lengths outside ASCII: mark only
        // when the offsets still fall on the same characters.
        .filter(|&at| {
            padded.is_char_boundary(at)
                && padded.is_char_boundary(at + filter.len())
                && lower.len() == padded.len()
        });
    match found {
        Some(at) => vec![
            Span::styled(padded[..at].to_string(), normal),
            Span::styled(padded[at..at + filter.len()].to_string(), matched),
            Span::styled(padded[at + filter.len()..].to_string(), normal),
        ],
        None => vec![Span::styled(padded, normal)],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_grow_with_the_width() {
        let narrow = Columns::for_numbers(80, 4);
        assert!(narrow.real > 0 && narrow.range == 0 && narrow.description == 0);
        assert!(narrow.name >= 16, "{narrow:?}");
        let wide = Columns::for_numbers(200, 4);
        assert!(wide.range > 0 && wide.description > 0);
        let tiny = Columns::for_numbers(20, 4);
        assert_eq!(tiny.real, 0);
        assert!(tiny.name >= 1);
        // Wider numbers take their room from the name.
        let five = Columns::for_numbers(80, 5);
        assert_eq!((five.number, five.name + 1), (5, narrow.name));
    }

    #[test]
    fn columns_are_as_wide_as_their_widest_number() {
        let widest = Widest {
            number: 4,
            value: 15,
            unit: 13,
            range: 23,
            real: 14,
        };
        let wide = Columns::for_widths(200, widest);
        assert_eq!(
            (wide.value, wide.unit, wide.real, wide.range),
            (15, 13, 14, 23)
        );
        // No room for the whole range: none, the footer shows it.
        let narrow = Columns::for_widths(100, widest);
        assert_eq!((narrow.value, narrow.range), (15, 0));
    }

    #[test]
    fn names_are_cut_with_an_ellipsis_and_marked_where_they_match() {
        assert_eq!(fit("Maximum positioning speed", 10), "Maximum p…");
        assert_eq!(fit("short", 10), "short");
        let spans = name_spans(
            "Maximum speed",
            "SPEED",
            15,
            Style::default(),
            Style::default(),
        );
        let parts: Vec<&str> = spans.iter().map(|s| s.content.as_ref()).collect();
        assert_eq!(parts, ["Maximum ", "speed", "  "]);
    }

    #[test]
    fn a_note_wraps_between_words_into_a_few_lines() {
        assert_eq!(wrap("one two three", 7, 3), ["one two", "three"]);
        assert_eq!(wrap("one two three four", 7, 2), ["one two", "three …"]);
        assert_eq!(wrap("abcdefghij", 4, 3), ["abc…"]);
        assert_eq!(wrap("", 10, 3), Vec::<String>::new());
        assert_eq!(wrap("a b c", 1, 0), ["…"], "no rows: one, never a panic");
    }
}
