//! One line of A-Script cut into tokens. Words are split with the command
//! table: a run of capitals is a keyword, a command (`HSPD`), a command and
//! its axis (`HSPDX`, `ECLEARX`, `WAITX`), a circle or arc with its axes and
//! turning sense (`CIRXYP`, `ARCTN`), a move's axis (`X`), an axis and a
//! variable (`XV1`), or a variable (`V12`). Whatever the table does not
//! know, in lower case included (every manual example is in capitals and
//! §5 never says lower case is accepted), is an unknown word. Used by the
//! parser and by syntax highlighting alike, so both read a line the same
//! way.

use std::ops::Range;

use super::super::catalog::Form;
use super::ast::{Axis, Rotation};
use super::commands::{forms, split_last_letter};

/// The words that shape a program (§5.2): blocks, branches, loops, calls.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Keyword {
    Prg,
    End,
    Sub,
    EndSub,
    If,
    ElseIf,
    Else,
    EndIf,
    While,
    EndWhile,
    Gosub,
}

const KEYWORDS: &[(&str, Keyword)] = &[
    ("PRG", Keyword::Prg),
    ("END", Keyword::End),
    ("SUB", Keyword::Sub),
    ("ENDSUB", Keyword::EndSub),
    ("IF", Keyword::If),
    ("ELSEIF", Keyword::ElseIf),
    ("ELSE", Keyword::Else),
    ("ENDIF", Keyword::EndIf),
    ("WHILE", Keyword::While),
    ("ENDWHILE", Keyword::EndWhile),
    ("GOSUB", Keyword::Gosub),
];

impl Keyword {
    pub fn text(self) -> &'static str {
        KEYWORDS
            .iter()
            .find(|(_, k)| *k == self)
            .map_or("?", |(text, _)| text)
    }

    fn from_word(word: &str) -> Option<Keyword> {
        KEYWORDS.iter().find(|(w, _)| *w == word).map(|(_, k)| *k)
    }
}

/// Operators and separators.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Symbol {
    /// `=`: assigns, or compares in a condition.
    Equals,
    /// `==`: not A-Script (T5-43 "Error").
    DoubleEquals,
    NotEqual,
    LessOrEqual,
    GreaterOrEqual,
    Less,
    Greater,
    ShiftLeft,
    ShiftRight,
    Plus,
    Minus,
    Star,
    Slash,
    Percent,
    Ampersand,
    Bar,
    Tilde,
    Colon,
}

const SYMBOLS: &[(&str, Symbol)] = &[
    // Two-character symbols first: `<=` is not `<` then `=`.
    ("==", Symbol::DoubleEquals),
    ("!=", Symbol::NotEqual),
    ("<=", Symbol::LessOrEqual),
    (">=", Symbol::GreaterOrEqual),
    ("<<", Symbol::ShiftLeft),
    (">>", Symbol::ShiftRight),
    ("=", Symbol::Equals),
    ("<", Symbol::Less),
    (">", Symbol::Greater),
    ("+", Symbol::Plus),
    ("-", Symbol::Minus),
    ("*", Symbol::Star),
    ("/", Symbol::Slash),
    ("%", Symbol::Percent),
    ("&", Symbol::Ampersand),
    ("|", Symbol::Bar),
    ("~", Symbol::Tilde),
    (":", Symbol::Colon),
];

/// What a token is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Lex {
    Keyword(Keyword),
    /// A command's name from the table, with the axis letter written after
    /// it if any (`HSPDX`).
    Command {
        name: &'static str,
        axis: Option<Axis>,
    },
    /// `CIRXYP`, `ARCXZN`: the name, two axes, the turning sense.
    Curve {
        name: &'static str,
        axes: [Axis; 2],
        rotation: Rotation,
    },
    /// `CIRTP`, `ARCTN`.
    Helix {
        name: &'static str,
        rotation: Rotation,
    },
    /// A move's axis letter.
    Axis(Axis),
    /// `V12`: the number after V (None if no digits follow; `u64::MAX` if
    /// too many do).
    Variable(Option<u64>),
    /// Digits (None if too large for 64 bits).
    Number(Option<i64>),
    Symbol(Symbol),
    /// Letters that are none of the above.
    Word,
    /// A character A-Script has no use for.
    Other,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Token {
    pub lex: Lex,
    /// Bytes of the line.
    pub span: Range<usize>,
    /// Whether white space comes right before it.
    pub spaced: bool,
}

/// A line's tokens and its `;` comment.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Lexed {
    pub tokens: Vec<Token>,
    pub comment: Option<Range<usize>>,
}

/// Cut `line` into tokens. Never fails: what A-Script does not know
/// becomes [`Lex::Word`] or [`Lex::Other`].
pub fn lex(line: &str) -> Lexed {
    let mut lexed = Lexed::default();
    let mut at = 0;
    let mut spaced = false;
    while let Some(rest) = line.get(at..) {
        let Some(c) = rest.chars().next() else {
            break;
        };
        if c == ';' {
            lexed.comment = Some(at..line.len());
            break;
        }
        if c.is_whitespace() {
            at += c.len_utf8();
            spaced = true;
            continue;
        }
        let mut push = |lex, len: usize| {
            lexed.tokens.push(Token {
                lex,
                span: at..at + len,
                spaced,
            });
            at += len;
        };
        if c.is_ascii_digit() {
            let digits = leading(rest, |c| c.is_ascii_digit());
            push(Lex::Number(digits.parse().ok()), digits.len());
        } else if c.is_ascii_alphabetic() {
            let word = leading(rest, |c| c.is_ascii_alphabetic());
            match classify(word) {
                Word::One(lex) => push(lex, word.len()),
                Word::Variable => {
                    let len = variable_len(rest, word.len());
                    push(variable(rest, word.len(), len), len);
                }
                Word::AxisThenVariable(axis) => {
                    push(Lex::Axis(axis), 1);
                    spaced = false;
                    let rest = rest.get(1..).unwrap_or("");
                    let len = variable_len(rest, 1);
                    lexed.tokens.push(Token {
                        lex: variable(rest, 1, len),
                        span: at..at + len,
                        spaced,
                    });
                    at += len;
                }
            }
        } else if let Some((text, symbol)) = SYMBOLS.iter().find(|(s, _)| rest.starts_with(s)) {
            push(Lex::Symbol(*symbol), text.len());
        } else {
            push(Lex::Other, c.len_utf8());
        }
        spaced = false;
    }
    lexed
}

/// The longest start of `text` whose characters all pass `keep`.
fn leading(text: &str, keep: impl Fn(char) -> bool) -> &str {
    let end = text.find(|c| !keep(c)).unwrap_or(text.len());
    text.get(..end).unwrap_or("")
}

/// Length of `V` and its digits, `letters` being the V's length (1).
fn variable_len(text: &str, letters: usize) -> usize {
    letters + leading(text.get(letters..).unwrap_or(""), |c| c.is_ascii_digit()).len()
}

fn variable(text: &str, letters: usize, len: usize) -> Lex {
    let digits = text.get(letters..len).unwrap_or("");
    Lex::Variable(if digits.is_empty() {
        None
    } else {
        Some(digits.parse().unwrap_or(u64::MAX))
    })
}

enum Word {
    One(Lex),
    /// `V`, its digits to follow.
    Variable,
    /// `XV`: an axis, then `V` and its digits.
    AxisThenVariable(Axis),
}

fn classify(word: &str) -> Word {
    // Every manual example is in capitals; §5 never says lower case is
    // accepted (the ASCII parser, by contrast, takes it).
    if !word.chars().all(|c| c.is_ascii_uppercase()) {
        return Word::One(Lex::Word);
    }
    if let Some(keyword) = Keyword::from_word(word) {
        return Word::One(Lex::Keyword(keyword));
    }
    if word == "V" {
        return Word::Variable;
    }
    if let Some(info) = forms(word).next() {
        return Word::One(Lex::Command {
            name: info.name,
            axis: None,
        });
    }
    if let Some(lex) = curve(word) {
        return Word::One(lex);
    }
    if let Some((name, last)) = split_last_letter(word)
        && let Some(axis) = Axis::from_letter(last)
        && let Some(info) = forms(name).find(|c| c.form == Form::Axis)
    {
        return Word::One(Lex::Command {
            name: info.name,
            axis: Some(axis),
        });
    }
    let mut chars = word.chars();
    match (chars.next().and_then(Axis::from_letter), chars.as_str()) {
        (Some(axis), "") => Word::One(Lex::Axis(axis)),
        (Some(axis), "V") => Word::AxisThenVariable(axis),
        _ => Word::One(Lex::Word),
    }
}

fn rotation(letter: char) -> Option<Rotation> {
    match letter {
        'P' => Some(Rotation::Clockwise),
        'N' => Some(Rotation::CounterClockwise),
        _ => None,
    }
}

/// `CIRXYP`, `ARCZUN`, `CIRTP`, `ARCTN`.
fn curve(word: &str) -> Option<Lex> {
    for name in ["CIRT", "ARCT"] {
        if let Some(rest) = word.strip_prefix(name) {
            let mut chars = rest.chars();
            if let (Some(r), None) = (chars.next().and_then(rotation), chars.next()) {
                let name = forms(name).next()?.name;
                return Some(Lex::Helix { name, rotation: r });
            }
        }
    }
    for name in ["CIR", "ARC"] {
        if let Some(rest) = word.strip_prefix(name) {
            let mut chars = rest.chars();
            let a = chars.next().and_then(Axis::from_letter);
            let b = chars.next().and_then(Axis::from_letter);
            let r = chars.next().and_then(rotation);
            if let (Some(a), Some(b), Some(r), None) = (a, b, r, chars.next()) {
                let name = forms(name).next()?.name;
                return Some(Lex::Curve {
                    name,
                    axes: [a, b],
                    rotation: r,
                });
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lexes(line: &str) -> Vec<(&str, Lex)> {
        lex(line)
            .tokens
            .into_iter()
            .map(|t| (line.get(t.span).unwrap_or("?"), t.lex))
            .collect()
    }

    fn command(name: &'static str, axis: Option<Axis>) -> Lex {
        Lex::Command { name, axis }
    }

    #[test]
    fn words_split_into_commands_axes_and_variables() {
        assert_eq!(
            lexes("HOMEX-6"),
            [
                ("HOMEX", command("HOME", Some(Axis::X))),
                ("-", Lex::Symbol(Symbol::Minus)),
                ("6", Lex::Number(Some(6))),
            ]
        );
        assert_eq!(
            lexes("XV1"),
            [("X", Lex::Axis(Axis::X)), ("V1", Lex::Variable(Some(1)))]
        );
        assert_eq!(
            lexes("X-20000Y15000"),
            [
                ("X", Lex::Axis(Axis::X)),
                ("-", Lex::Symbol(Symbol::Minus)),
                ("20000", Lex::Number(Some(20000))),
                ("Y", Lex::Axis(Axis::Y)),
                ("15000", Lex::Number(Some(15000))),
            ]
        );
        assert_eq!(lexes("EX")[0].1, command("E", Some(Axis::X)));
        assert_eq!(lexes("EO")[0].1, command("EO", None));
        assert_eq!(lexes("LTPX")[0].1, command("LTP", Some(Axis::X)));
        assert_eq!(lexes("WAITY")[0].1, command("WAIT", Some(Axis::Y)));
        assert_eq!(lexes("DO10")[1].1, Lex::Number(Some(10)));
        assert_eq!(lexes("ELSEIF")[0].1, Lex::Keyword(Keyword::ElseIf));
    }

    #[test]
    fn circles_and_arcs_carry_their_axes_and_sense() {
        assert_eq!(
            lexes("CIRXYP487659:562431")[0].1,
            Lex::Curve {
                name: "CIR",
                axes: [Axis::X, Axis::Y],
                rotation: Rotation::Clockwise
            }
        );
        assert_eq!(
            lexes("ARCTN0")[0].1,
            Lex::Helix {
                name: "ARCT",
                rotation: Rotation::CounterClockwise
            }
        );
        assert_eq!(lexes("CIRXYQ")[0].1, Lex::Word);
    }

    #[test]
    fn unknown_words_lower_case_and_stray_characters_are_kept_as_such() {
        assert_eq!(lexes("PRGA")[0].1, Lex::Word);
        assert_eq!(lexes("hspd")[0].1, Lex::Word);
        assert_eq!(lexes("é")[0].1, Lex::Other);
        assert_eq!(lexes("V")[0].1, Lex::Variable(None));
        assert_eq!(
            lexes("V99999999999999999999999")[0].1,
            Lex::Variable(Some(u64::MAX))
        );
        assert_eq!(lexes("99999999999999999999")[0].1, Lex::Number(None));
    }

    #[test]
    fn symbols_take_two_characters_when_they_can() {
        let symbols: Vec<Lex> = lexes("== != <= >= << >> = < > ~ | :")
            .into_iter()
            .map(|(_, l)| l)
            .collect();
        assert_eq!(
            symbols,
            [
                Symbol::DoubleEquals,
                Symbol::NotEqual,
                Symbol::LessOrEqual,
                Symbol::GreaterOrEqual,
                Symbol::ShiftLeft,
                Symbol::ShiftRight,
                Symbol::Equals,
                Symbol::Less,
                Symbol::Greater,
                Symbol::Tilde,
                Symbol::Bar,
                Symbol::Colon,
            ]
            .map(Lex::Symbol)
        );
    }

    #[test]
    fn spacing_and_comments_are_recorded() {
        let lexed = lex("  IO = 0   ;All outputs off");
        let spaced: Vec<bool> = lexed.tokens.iter().map(|t| t.spaced).collect();
        assert_eq!(spaced, [true, true, true]);
        assert_eq!(lexed.comment, Some(11..27));
        let lexed = lex("XV1");
        assert!(lexed.tokens.iter().all(|t| !t.spaced));
    }
}
