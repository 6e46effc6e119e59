//! Syntax colours for TMCL program source, line by line: what each piece
//! of a line is, in the assembler's syntax (`Label:`, `Name = value`,
//! `#include`, an instruction, `//` comments; see
//! [`crate::protocol::tmcl::asm`]). Never fails: text it does not
//! recognise is plain.

use std::collections::BTreeSet;
use std::ops::Range;

/// What a piece of source is, for its colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Token {
    Plain,
    /// The instruction's first word, or a `#` directive.
    Mnemonic,
    /// A label being declared, or named as an operand.
    Label,
    /// A number, or a constant's name.
    Number,
    Comment,
}

/// Label and constant names declared anywhere in the source, so that
/// operands naming them get their colour.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Names {
    pub labels: BTreeSet<String>,
    pub constants: BTreeSet<String>,
}

impl Names {
    /// The names declared in `lines`.
    pub fn declared<'a>(lines: impl IntoIterator<Item = &'a str>) -> Names {
        let mut names = Names::default();
        for line in lines {
            let code = code_of(line);
            let mut rest = code.trim_start();
            if let Some((name, value)) = rest.split_once('=')
                && is_name(name.trim())
                && !value.trim().is_empty()
            {
                names.constants.insert(name.trim().to_string());
                continue;
            }
            while let Some((label, after)) = leading_label(rest) {
                names.labels.insert(label.to_string());
                rest = after.trim_start();
            }
        }
        names
    }
}

fn is_name(word: &str) -> bool {
    let mut chars = word.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

fn is_number(word: &str) -> bool {
    let digits = word.strip_prefix(['-', '+']).unwrap_or(word);
    if let Some(hex) = digits
        .strip_prefix("0x")
        .or_else(|| digits.strip_prefix("0X"))
        .or_else(|| digits.strip_prefix('$'))
    {
        return !hex.is_empty() && hex.chars().all(|c| c.is_ascii_hexdigit());
    }
    !digits.is_empty() && digits.chars().all(|c| c.is_ascii_digit())
}

/// The line without its comment.
fn code_of(line: &str) -> &str {
    line.find("//")
        .and_then(|at| line.get(..at))
        .unwrap_or(line)
}

/// `Name:` at the start of `text`: the name and what follows the colon.
fn leading_label(text: &str) -> Option<(&str, &str)> {
    let (name, after) = text.split_once(':')?;
    is_name(name).then_some((name, after))
}

/// The pieces of `line` (byte ranges, in order, covering the whole line)
/// and what each is.
pub fn highlight(line: &str, names: &Names) -> Vec<(Range<usize>, Token)> {
    let mut pieces = Vec::new();
    let code_end = line.find("//").unwrap_or(line.len());
    let code = line.get(..code_end).unwrap_or("");
    let trimmed = code.trim_start();
    let mut at = code.len() - trimmed.len();
    let push = |pieces: &mut Vec<(Range<usize>, Token)>, range: Range<usize>, token| {
        if !range.is_empty() {
            pieces.push((range, token));
        }
    };
    push(&mut pieces, 0..at, Token::Plain);
    if trimmed.starts_with('#') {
        let end = trimmed
            .find(char::is_whitespace)
            .map_or(code.len(), |n| at + n);
        push(&mut pieces, at..end, Token::Mnemonic);
        push(&mut pieces, end..code.len(), Token::Plain);
    } else if let Some((name, _)) = trimmed.split_once('=')
        && is_name(name.trim())
    {
        let name_end = at + name.trim_end().len();
        push(&mut pieces, at..name_end, Token::Number);
        words(line, name_end, code.len(), names, false, &mut pieces);
    } else {
        let mut rest = trimmed;
        while let Some((label, after)) = leading_label(rest) {
            let colon = at + label.len() + 1;
            push(&mut pieces, at..colon, Token::Label);
            let next = after.trim_start();
            let next_at = colon + (after.len() - next.len());
            push(&mut pieces, colon..next_at, Token::Plain);
            at = next_at;
            rest = next;
        }
        words(line, at, code.len(), names, true, &mut pieces);
    }
    push(&mut pieces, code_end..line.len(), Token::Comment);
    pieces
}

/// Colour the words of `line[start..end]`: the first is the mnemonic when
/// `instruction`, then numbers and declared names.
fn words(
    line: &str,
    start: usize,
    end: usize,
    names: &Names,
    instruction: bool,
    pieces: &mut Vec<(Range<usize>, Token)>,
) {
    let Some(text) = line.get(start..end) else {
        return;
    };
    let mut first = instruction;
    let mut plain_from = start;
    let is_separator = |c: char| c.is_whitespace() || c == ',' || c == '=';
    let mut offset = 0;
    for word in text.split(is_separator) {
        let word_at = start + offset;
        offset += word.len()
            + text
                .get(offset + word.len()..)
                .map_or(0, |r| r.chars().next().map_or(0, char::len_utf8));
        if word.is_empty() {
            continue;
        }
        let token = if first {
            first = false;
            Token::Mnemonic
        } else if is_number(word) || names.constants.contains(word) {
            Token::Number
        } else if names.labels.contains(word) {
            Token::Label
        } else {
            continue;
        };
        if plain_from < word_at {
            pieces.push((plain_from..word_at, Token::Plain));
        }
        pieces.push((word_at..word_at + word.len(), token));
        plain_from = word_at + word.len();
    }
    if plain_from < end {
        pieces.push((plain_from..end, Token::Plain));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tokens<'a>(line: &'a str, names: &Names) -> Vec<(&'a str, Token)> {
        highlight(line, names)
            .into_iter()
            .filter(|(_, t)| *t != Token::Plain)
            .map(|(r, t)| (line.get(r).unwrap_or("?"), t))
            .collect()
    }

    #[test]
    fn an_instruction_with_a_label_numbers_and_a_comment() {
        let names = Names::declared(["Loop: MVP ABS, 0, Far // go", "Far = 51200"]);
        assert_eq!(
            tokens("Loop: MVP ABS, 0, Far // go", &names),
            [
                ("Loop:", Token::Label),
                ("MVP", Token::Mnemonic),
                ("0", Token::Number),
                ("Far", Token::Number),
                ("// go", Token::Comment),
            ]
        );
        assert_eq!(
            tokens("  JA Loop", &names),
            [("JA", Token::Mnemonic), ("Loop", Token::Label)]
        );
        assert_eq!(
            tokens("Far = 0x1F", &names),
            [("Far", Token::Number), ("0x1F", Token::Number)]
        );
        assert_eq!(
            tokens("#include \"x.tmc\"", &names),
            [("#include", Token::Mnemonic)]
        );
    }

    #[test]
    fn the_pieces_cover_every_line_whatever_it_holds() {
        let names = Names::declared(["A:"]);
        for line in [
            "",
            "  ",
            "::",
            "a:b:c",
            "é: MVP ,, -",
            "//",
            "x = ",
            "#",
            "A: A: JA A",
        ] {
            let pieces = highlight(line, &names);
            let mut at = 0;
            for (range, _) in &pieces {
                assert_eq!(range.start, at, "{line:?}: {pieces:?}");
                at = range.end;
            }
            assert_eq!(at, line.len(), "{line:?}: {pieces:?}");
        }
    }
}
