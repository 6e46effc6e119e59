//! Syntax classes for an editor's colours, line by line, from the same
//! lexer the parser reads with. Never fails: what A-Script does not know
//! is [`TokenClass::Invalid`], spaces are [`TokenClass::Plain`], and the
//! pieces cover the whole line.

use std::ops::Range;

use super::lexer::{Keyword, Lex, lex};

/// What a piece of a line is, for its colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TokenClass {
    /// White space.
    Plain,
    /// PRG, END, SUB, ENDSUB: a block's bounds (an editor may give it the
    /// colour the TMCL editor gives labels).
    Block,
    /// IF, ELSEIF, ELSE, ENDIF, WHILE, ENDWHILE, GOSUB.
    Keyword,
    /// A command with its axis (`HSPDX`, `WAITX`, `CIRXYP`) or a move's
    /// axis letter.
    Command,
    /// `V12`.
    Variable,
    Number,
    /// `= != < > <= >= + - * / % >> << & | ~ :`.
    Operator,
    /// `;` to the end of the line.
    Comment,
    /// Words and characters A-Script does not know (lower case included).
    Invalid,
}

/// The pieces of `line`: byte ranges, in order, covering the whole line,
/// and what each is.
pub fn tokens(line: &str) -> Vec<(Range<usize>, TokenClass)> {
    let lexed = lex(line);
    let mut pieces = Vec::with_capacity(lexed.tokens.len() * 2 + 2);
    let mut at = 0;
    let mut push = |range: Range<usize>, class, at: &mut usize| {
        if *at < range.start {
            pieces.push((*at..range.start, TokenClass::Plain));
        }
        *at = range.end;
        pieces.push((range, class));
    };
    for token in &lexed.tokens {
        push(token.span.clone(), class(token.lex), &mut at);
    }
    if let Some(comment) = lexed.comment {
        push(comment, TokenClass::Comment, &mut at);
    }
    if at < line.len() {
        pieces.push((at..line.len(), TokenClass::Plain));
    }
    pieces
}

fn class(lex: Lex) -> TokenClass {
    match lex {
        Lex::Keyword(Keyword::Prg | Keyword::End | Keyword::Sub | Keyword::EndSub) => {
            TokenClass::Block
        }
        Lex::Keyword(_) => TokenClass::Keyword,
        Lex::Command { .. } | Lex::Curve { .. } | Lex::Helix { .. } | Lex::Axis(_) => {
            TokenClass::Command
        }
        Lex::Variable(_) => TokenClass::Variable,
        Lex::Number(_) => TokenClass::Number,
        Lex::Symbol(_) => TokenClass::Operator,
        Lex::Word | Lex::Other => TokenClass::Invalid,
    }
}
