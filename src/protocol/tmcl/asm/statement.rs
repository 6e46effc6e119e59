//! One source line of a TMCL program, taken apart into what it declares
//! (digest D10, the TMCL-IDE's source syntax as the manual's examples show
//! it): labels `Name:` (alone or before an instruction), a constant
//! `Name = value`, a `#include File`, an instruction, or nothing. Columns
//! are 1-based character positions in the line, for error messages.

use crate::protocol::tmcl::line::is_symbol_name;

/// A piece of a line and the column it starts at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Spanned<'a> {
    pub text: &'a str,
    pub column: usize,
}

/// What a line says.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Statement<'a> {
    /// White space and comments only.
    Empty,
    /// `#include File` (quotes around the name are allowed).
    Include { name: Spanned<'a> },
    /// `#include` without a name.
    IncludeWithoutName { column: usize },
    /// `#something` other than `#include`.
    UnknownDirective { directive: Spanned<'a> },
    /// `Name = value`; `value` is empty when nothing follows the `=`.
    Constant {
        name: Spanned<'a>,
        value: Spanned<'a>,
    },
    /// Labels, then an instruction (its text without the comment), either
    /// of which may be missing but not both.
    Code {
        labels: Vec<Spanned<'a>>,
        instruction: Option<Spanned<'a>>,
    },
}

/// The column of byte offset `at` in `line`.
pub fn column_of(line: &str, at: usize) -> usize {
    line.get(..at)
        .map_or(1, |before| before.chars().count() + 1)
}

/// Take a source line apart. Never fails: what is not a label, constant or
/// directive is an instruction, and the console-line parser judges it.
pub fn classify(line: &str) -> Statement<'_> {
    let code_end = line.find("//").unwrap_or(line.len());
    let code = line.get(..code_end).unwrap_or(line).trim_end();
    let start = code.len() - code.trim_start().len();
    let Some(rest) = code.get(start..).filter(|r| !r.is_empty()) else {
        return Statement::Empty;
    };
    let span = |offset: usize, text| Spanned {
        text,
        column: column_of(line, offset),
    };
    if let Some(directive) = rest.strip_prefix('#') {
        return classify_directive(line, start, directive);
    }
    // Labels: `Name:` repeated.
    let mut labels = Vec::new();
    let mut at = start;
    loop {
        let remaining = code.get(at..).unwrap_or("");
        let Some((name, after_colon)) = leading_label(remaining) else {
            break;
        };
        labels.push(span(at, name));
        let next = at + after_colon;
        let skipped = code.get(next..).unwrap_or("");
        at = next + (skipped.len() - skipped.trim_start().len());
    }
    let remaining = code.get(at..).unwrap_or("");
    if labels.is_empty()
        && let Some((name, value_offset)) = constant_definition(remaining)
    {
        let value = remaining.get(value_offset..).unwrap_or("").trim();
        return Statement::Constant {
            name: span(at, name),
            value: span(at + value_offset, value),
        };
    }
    let instruction = (!remaining.is_empty()).then(|| span(at, remaining));
    Statement::Code {
        labels,
        instruction,
    }
}

fn classify_directive<'a>(line: &'a str, hash: usize, directive: &'a str) -> Statement<'a> {
    let word_len = directive
        .find(char::is_whitespace)
        .unwrap_or(directive.len());
    let word = directive.get(..word_len).unwrap_or(directive);
    if !word.eq_ignore_ascii_case("include") {
        return Statement::UnknownDirective {
            directive: Spanned {
                text: line.get(hash..hash + 1 + word_len).unwrap_or(word),
                column: column_of(line, hash),
            },
        };
    }
    let after = directive.get(word_len..).unwrap_or("");
    let name = after.trim();
    let name_offset = hash + 1 + word_len + (after.len() - after.trim_start().len());
    let (name, name_offset) = match name.strip_prefix('"').and_then(|n| n.strip_suffix('"')) {
        Some(inner) => (inner.trim(), name_offset + 1),
        None => (name, name_offset),
    };
    if name.is_empty() {
        return Statement::IncludeWithoutName {
            column: column_of(line, hash),
        };
    }
    Statement::Include {
        name: Spanned {
            text: name,
            column: column_of(line, name_offset),
        },
    }
}

/// `Name:` at the start of `text`: the name and the offset after the colon.
/// White space may stand between the name and the colon.
fn leading_label(text: &str) -> Option<(&str, usize)> {
    let name_len = text
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '.'))
        .unwrap_or(text.len());
    let name = text.get(..name_len)?;
    if !is_symbol_name(name) {
        return None;
    }
    let after = text.get(name_len..)?;
    let colon = name_len + (after.len() - after.trim_start().len());
    text.get(colon..)?
        .starts_with(':')
        .then_some((name, colon + 1))
}

/// `Name = …` at the start of `text`: the name and the offset of the value.
fn constant_definition(text: &str) -> Option<(&str, usize)> {
    let name_len = text
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '.'))
        .unwrap_or(text.len());
    let name = text.get(..name_len)?;
    if !is_symbol_name(name) {
        return None;
    }
    let after = text.get(name_len..)?;
    let equals = name_len + (after.len() - after.trim_start().len());
    if !text.get(equals..)?.starts_with('=') {
        return None;
    }
    let value = text.get(equals + 1..)?;
    Some((name, equals + 1 + (value.len() - value.trim_start().len())))
}

/// The operands of an instruction split as the console-line parser splits
/// them (commas and white space), with their columns, for pointing at the
/// operand an error is about.
pub fn tokens<'a>(instruction: Spanned<'a>) -> Vec<Spanned<'a>> {
    let mut out = Vec::new();
    let mut start: Option<usize> = None;
    let text = instruction.text;
    let push = |out: &mut Vec<Spanned<'a>>, s: usize, e: usize| {
        if let Some(t) = text.get(s..e) {
            out.push(Spanned {
                text: t,
                column: instruction.column + column_of(text, s) - 1,
            });
        }
    };
    for (i, ch) in text.char_indices() {
        if ch == ',' || ch.is_whitespace() {
            if let Some(s) = start.take() {
                push(&mut out, s, i);
            }
        } else if start.is_none() {
            start = Some(i);
        }
    }
    if let Some(s) = start {
        push(&mut out, s, text.len());
    }
    out
}

/// The column of the comma that leaves an operand empty (`SAP 4,,0`, a
/// trailing or leading comma), if there is one.
pub fn empty_operand_column(instruction: Spanned<'_>) -> Option<usize> {
    let text = instruction.text;
    // A comma needs an operand on each side; the mnemonic does not count
    // as one on the left.
    let mut operands_before = 0usize;
    let mut in_token = false;
    let mut tokens_seen = 0usize;
    let mut comma_pending = true;
    for (i, ch) in text.char_indices() {
        if ch == ',' {
            in_token = false;
            if comma_pending || operands_before == 0 {
                return Some(instruction.column + column_of(text, i) - 1);
            }
            comma_pending = true;
        } else if ch.is_whitespace() {
            in_token = false;
        } else if !in_token {
            in_token = true;
            tokens_seen += 1;
            // Raw frames have no mnemonic: their first token is an operand.
            let head_is_operand =
                tokens_seen == 1 && (ch.is_ascii_digit() || matches!(ch, '-' | '+' | '$'));
            if tokens_seen > 1 || head_is_operand {
                operands_before += 1;
            }
            comma_pending = false;
        }
    }
    if comma_pending && tokens_seen > 0 && text.trim_end().ends_with(',') {
        let at = text.trim_end().len() - 1;
        return Some(instruction.column + column_of(text, at) - 1);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sp(text: &str, column: usize) -> Spanned<'_> {
        Spanned { text, column }
    }

    #[test]
    fn labels_stand_alone_or_before_an_instruction() {
        assert_eq!(
            classify(" Loop:"),
            Statement::Code {
                labels: vec![sp("Loop", 2)],
                instruction: None
            }
        );
        assert_eq!(
            classify("Func1: JA Func1Start  // first"),
            Statement::Code {
                labels: vec![sp("Func1", 1)],
                instruction: Some(sp("JA Func1Start", 8))
            }
        );
        assert_eq!(
            classify("A : B:ROL 0, 1000"),
            Statement::Code {
                labels: vec![sp("A", 1), sp("B", 5)],
                instruction: Some(sp("ROL 0, 1000", 7))
            }
        );
    }

    #[test]
    fn constants_directives_and_comments() {
        assert_eq!(
            classify("MaxSpeed = 50000 // pps"),
            Statement::Constant {
                name: sp("MaxSpeed", 1),
                value: sp("50000", 12)
            }
        );
        assert_eq!(
            classify("X="),
            Statement::Constant {
                name: sp("X", 1),
                value: sp("", 3)
            }
        );
        assert_eq!(
            classify("  #include Interrupts.inc"),
            Statement::Include {
                name: sp("Interrupts.inc", 12)
            }
        );
        assert_eq!(
            classify("#INCLUDE \"My File.inc\""),
            Statement::Include {
                name: sp("My File.inc", 11)
            }
        );
        assert_eq!(
            classify("#include // nothing"),
            Statement::IncludeWithoutName { column: 1 }
        );
        assert_eq!(
            classify("#define X 1"),
            Statement::UnknownDirective {
                directive: sp("#define", 1)
            }
        );
        assert_eq!(classify("   // just a comment"), Statement::Empty);
        assert_eq!(classify(""), Statement::Empty);
    }

    #[test]
    fn columns_count_characters() {
        assert_eq!(
            classify("\u{e4}: STOP"),
            Statement::Code {
                labels: vec![],
                instruction: Some(sp("\u{e4}: STOP", 1))
            }
        );
        let t = tokens(sp("SAP 4,0 ,  1000", 3));
        let cols: Vec<_> = t.iter().map(|s| (s.text, s.column)).collect();
        assert_eq!(cols, [("SAP", 3), ("4", 7), ("0", 9), ("1000", 14)]);
    }

    #[test]
    fn empty_operands_are_located() {
        assert_eq!(empty_operand_column(sp("SAP 4,,0", 1)), Some(7));
        assert_eq!(empty_operand_column(sp("SAP 4, 0, 1,", 5)), Some(16));
        assert_eq!(empty_operand_column(sp("SAP ,4", 1)), Some(5));
        assert_eq!(empty_operand_column(sp("1,,0 0", 1)), Some(3));
        assert_eq!(empty_operand_column(sp("SAP 4, 0, 1", 1)), None);
    }
}
