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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_that_fits_is_kept_and_longer_text_ends_in_an_ellipsis() {
        assert_eq!(fit("MVP ABS", 7), "MVP ABS");
        assert_eq!(fit("MVP ABS", 5), "MVP …");
        assert_eq!(fit("µsteps", 3), "µs…");
        assert_eq!(fit("anything", 1), "…");
        assert_eq!(fit("anything", 0), "");
    }
}
