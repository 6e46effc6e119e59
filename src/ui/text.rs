//! Text cut to a column's width, the way every pane shows what does not fit.

/// `text` cut to `width` characters, its last one an ellipsis when cut.
pub fn fit(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        return text.to_string();
    }
    if width == 0 {
        return String::new();
    }
    let mut out: String = text.chars().take(width - 1).collect();
    out.push('…');
    out
}

/// `text` in rows of at most `width` characters, broken at spaces where
/// it can be (a word longer than a row is cut): help read on a narrow
/// pane, not `until of` / `f`. An empty text is one empty row.
pub fn wrap(text: &str, width: usize) -> Vec<String> {
    let width = width.max(1);
    let mut rows = Vec::new();
    let mut rest: Vec<char> = text.chars().collect();
    while rest.len() > width {
        // The last space that leaves something on this row; the spaces
        // at the break are dropped.
        let cut = rest[..=width]
            .iter()
            .rposition(|c| *c == ' ')
            .filter(|at| rest[..*at].iter().any(|c| *c != ' '));
        let (row, next) = match cut {
            Some(at) => (at, at + 1),
            None => (width, width),
        };
        rows.push(
            rest[..row]
                .iter()
                .collect::<String>()
                .trim_end()
                .to_string(),
        );
        let skip = rest[next..].iter().take_while(|c| **c == ' ').count();
        rest.drain(..next + skip);
    }
    if !rest.is_empty() || rows.is_empty() {
        rows.push(rest.into_iter().collect());
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 19, point 9: help wrapped mid-word (`until of│f`).
    #[test]
    fn wrapping_breaks_at_spaces_and_cuts_only_words_longer_than_a_row() {
        assert_eq!(
            wrap("record lines until off", 18),
            ["record lines until", "off"]
        );
        assert_eq!(wrap("  :echo TEXT  show", 12), ["  :echo TEXT", "show"]);
        assert_eq!(wrap("0123456789abc de", 5), ["01234", "56789", "abc", "de"]);
        assert_eq!(wrap("", 5), [""]);
        assert_eq!(wrap("fits", 4), ["fits"]);
        for row in wrap(
            "the module's program language (SIXpack 2: SendToPack lines)",
            9,
        ) {
            assert!(row.chars().count() <= 9, "{row}");
        }
    }

    #[test]
    fn text_that_fits_is_kept_and_longer_text_ends_in_an_ellipsis() {
        assert_eq!(fit("MVP ABS", 7), "MVP ABS");
        assert_eq!(fit("MVP ABS", 5), "MVP …");
        assert_eq!(fit("µsteps", 3), "µs…");
        assert_eq!(fit("anything", 1), "…");
        assert_eq!(fit("anything", 0), "");
    }
}
