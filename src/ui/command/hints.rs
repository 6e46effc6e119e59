//! What the pane draws under its output: the wrapped lines and the hint
//! rows (completion candidates, the syntax of the command being typed).

use super::*;

impl CommandPane {
    /// The output rows wrapped to `width`, newest last.
    pub(super) fn wrapped(&self, width: usize) -> Vec<(Role, String)> {
        let width = width.max(1);
        let mut rows = Vec::new();
        for line in &self.output {
            rows.extend(
                crate::ui::text::wrap(&line.text, width)
                    .into_iter()
                    .map(|row| (line.role, row)),
            );
        }
        rows
    }

    /// The rows under the output: completion candidates, or a hint.
    pub(super) fn hint_rows(&self, view: &View, width: usize) -> Vec<Line<'static>> {
        let theme = view.theme;
        if let Some(confirming) = &self.confirming {
            let mut rows: Vec<Line> = confirming
                .reasons
                .iter()
                .map(|why| Line::styled(fit(why, width), theme.style(Role::Warning)))
                .collect();
            let what = match &confirming.then {
                Deferred::Line(line) => format!("send {line}?"),
                Deferred::Batch { batch, .. } => format!("run {}?", batch.name()),
                Deferred::Host { file, .. } => format!("run {file}?"),
            };
            rows.push(Line::styled(
                fit(
                    &format!(
                        "{what} y sends, n or {} does not",
                        key_label(view.keymap, Context::Command, Action::Cancel)
                    ),
                    width,
                ),
                theme.style(Role::Accent),
            ));
            return rows;
        }
        if let Some(c) = &self.completing {
            let mut rows: Vec<Line> = Vec::new();
            let mut row: Vec<Span> = Vec::new();
            let mut used = 0;
            for (i, candidate) in c.candidates.iter().enumerate() {
                let note = fit(&candidate.note, 28);
                let cell = if note.is_empty() {
                    candidate.text.clone()
                } else {
                    format!("{} {note}", candidate.text)
                };
                let cell_width = cell.chars().count() + 3;
                if used + cell_width > width && !row.is_empty() {
                    rows.push(Line::from(std::mem::take(&mut row)));
                    used = 0;
                    if rows.len() == CANDIDATE_ROWS {
                        break;
                    }
                }
                let style = if c.chosen == Some(i) {
                    theme.style(Role::Selection)
                } else {
                    theme.style(Role::Accent)
                };
                row.push(Span::styled(candidate.text.clone(), style));
                if !note.is_empty() {
                    row.push(Span::styled(format!(" {note}"), theme.style(Role::Muted)));
                }
                row.push(Span::raw("   "));
                used += cell_width;
            }
            if !row.is_empty() && rows.len() < CANDIDATE_ROWS {
                rows.push(Line::from(row));
            }
            return rows;
        }
        if let Some(hint) = &self.hint {
            return vec![Line::styled(hint.text.clone(), theme.style(hint.role))];
        }
        if let Some(busy) = &self.busy {
            let abort = key_label(view.keymap, Context::Command, Action::Cancel);
            let family = self.busy_family.and_then(find_family);
            let text = busy::hint(busy, family, &abort);
            return vec![Line::styled(fit(&text, width), theme.style(Role::Warning))];
        }
        // The syntax of the command being typed.
        if let Some(family) = self.family(view)
            && !self.input.trim().is_empty()
            && !self.input.starts_with(':')
            && self.explained.as_deref() != Some(self.input.as_str())
            && let Some(first) = family.console.help(&self.input, 0).first()
        {
            return vec![Line::styled(first.clone(), theme.style(Role::Muted))];
        }
        if let Some(host) = &self.host {
            return vec![Line::styled(
                format!(
                    "{}: {} stops it",
                    host.describe(),
                    key_label(view.keymap, Context::Command, Action::Cancel)
                ),
                theme.style(Role::Warning),
            )];
        }
        if let Some(batch) = &self.batch {
            let _ = batch;
            return vec![Line::styled(
                format!(
                    "batch running: {} stops it",
                    key_label(view.keymap, Context::Command, Action::Cancel)
                ),
                theme.style(Role::Warning),
            )];
        }
        Vec::new()
    }
}
