//! The program image file. The manual documents no export format of the
//! TMCL-IDE, so axterm uses a plain text one that a technician can read and
//! diff:
//!
//! ```text
//! // TMCL program image: 3 words, 7 bytes each (instruction, type, motor/bank, value MSB first)
//! 02 00 00 00 00 03 E8  // 0
//! 1B 00 00 00 00 01 F4  // 1
//! 03 00 00 00 00 00 00  // 2
//! ```
//!
//! One program word per line, address 0 first: seven hex bytes separated
//! by white space, in the order download mode stores them (§3.6.53: the
//! frame without module address and checksum). `//` starts a comment (the
//! address comments are only for the reader); blank lines are ignored.

use std::fmt::Write;

use super::super::hex::to_hex;
use super::{PROGRAM_MEMORY_WORDS, ProgramWord};

/// The image file of `words`.
pub fn format_image(words: &[ProgramWord]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "// TMCL program image: {} word{}, {} bytes each (instruction, type, motor/bank, \
         value MSB first)",
        words.len(),
        if words.len() == 1 { "" } else { "s" },
        ProgramWord::LEN
    );
    for (address, word) in words.iter().enumerate() {
        let _ = writeln!(out, "{}  // {address}", to_hex(&word.to_bytes()));
    }
    out
}

/// One thing wrong with an image file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {kind}")]
pub struct ImageError {
    /// 1-based.
    pub line: usize,
    pub kind: ImageErrorKind,
}

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ImageErrorKind {
    #[error("`{found}` is not a hex byte: expected two hex digits such as 0A")]
    NotAByte { found: String },
    #[error(
        "{count} byte{} where a program word has {}: instruction, type, motor/bank and four \
         value bytes",
        if *.count == 1 { "" } else { "s" },
        ProgramWord::LEN
    )]
    WrongLength { count: usize },
    #[error("more than the {PROGRAM_MEMORY_WORDS} words of program memory")]
    TooLong,
}

/// The words of an image file, or every line that is wrong.
pub fn parse_image(text: &str) -> Result<Vec<ProgramWord>, Vec<ImageError>> {
    let mut words = Vec::new();
    let mut errors = Vec::new();
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    for (index, line) in text.lines().enumerate() {
        let line_number = index + 1;
        let code = line
            .find("//")
            .map_or(line, |i| line.get(..i).unwrap_or(""));
        let fields: Vec<&str> = code.split_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        let mut bytes = Vec::with_capacity(ProgramWord::LEN);
        let mut bad = false;
        for field in &fields {
            match parse_byte(field) {
                Some(b) => bytes.push(b),
                None => {
                    errors.push(ImageError {
                        line: line_number,
                        kind: ImageErrorKind::NotAByte {
                            found: field.to_string(),
                        },
                    });
                    bad = true;
                    break;
                }
            }
        }
        if bad {
            continue;
        }
        let Ok(bytes) = <[u8; ProgramWord::LEN]>::try_from(bytes) else {
            errors.push(ImageError {
                line: line_number,
                kind: ImageErrorKind::WrongLength {
                    count: fields.len(),
                },
            });
            continue;
        };
        if words.len() == PROGRAM_MEMORY_WORDS {
            errors.push(ImageError {
                line: line_number,
                kind: ImageErrorKind::TooLong,
            });
            break;
        }
        words.push(ProgramWord::from_bytes(bytes));
    }
    if errors.is_empty() {
        Ok(words)
    } else {
        Err(errors)
    }
}

fn parse_byte(field: &str) -> Option<u8> {
    if field.len() != 2 || !field.chars().all(|c| c.is_ascii_hexdigit()) {
        return None;
    }
    u8::from_str_radix(field, 16).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn word(opcode: u8, kind: u8, motor_bank: u8, value: i32) -> ProgramWord {
        ProgramWord {
            opcode,
            kind,
            motor_bank,
            value,
        }
    }

    #[test]
    fn images_are_hex_lines_with_address_comments() {
        let words = [word(2, 0, 0, 1000), word(22, 0, 0, -1)];
        let text = format_image(&words);
        assert_eq!(
            text,
            "// TMCL program image: 2 words, 7 bytes each (instruction, type, motor/bank, \
             value MSB first)\n\
             02 00 00 00 00 03 E8  // 0\n\
             16 00 00 FF FF FF FF  // 1\n"
        );
        assert_eq!(parse_image(&text), Ok(words.to_vec()));
    }

    #[test]
    fn lower_case_blank_lines_and_comments_are_fine() {
        let text = "\n  // header\n1b 01 00 00 00 00 00 // wait\r\n\t\n";
        assert_eq!(parse_image(text), Ok(vec![word(0x1B, 1, 0, 0)]));
        assert_eq!(parse_image(""), Ok(vec![]));
    }

    #[test]
    fn every_bad_line_is_reported() {
        let text =
            "02 00 00 00 00 03\n02 00 00 00 00 03 E8 00\nZZ 00 00 00 00 00 00\n2 0 0 0 0 0 0\n";
        let errors = parse_image(text).unwrap_err();
        let shown: Vec<String> = errors.iter().map(ToString::to_string).collect();
        assert_eq!(
            shown,
            [
                "line 1: 6 bytes where a program word has 7: instruction, type, motor/bank \
                 and four value bytes",
                "line 2: 8 bytes where a program word has 7: instruction, type, motor/bank \
                 and four value bytes",
                "line 3: `ZZ` is not a hex byte: expected two hex digits such as 0A",
                "line 4: `2` is not a hex byte: expected two hex digits such as 0A",
            ]
        );
    }

    #[test]
    fn program_memory_bounds_the_image() {
        let full = format_image(&vec![ProgramWord::default(); PROGRAM_MEMORY_WORDS]);
        assert_eq!(
            parse_image(&full).map(|w| w.len()),
            Ok(PROGRAM_MEMORY_WORDS)
        );
        let over = format!("{full}00 00 00 00 00 00 00\n");
        let errors = parse_image(&over).unwrap_err();
        assert_eq!(errors.len(), 1);
        assert_eq!(errors[0].kind, ImageErrorKind::TooLong);
    }
}
