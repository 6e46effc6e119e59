//! Program image → source. Jump, call, vector and restart targets inside
//! the program get synthesised labels (`L_0012:`, the address in decimal
//! as the manual writes addresses); constants are not recovered. A word
//! the assembler would not take back in mnemonic form (an operand outside
//! the module's tables, an unknown instruction, "don't care" fields that
//! are not 0) is written as a raw frame of four numbers with a comment
//! saying why, so that `assemble(disassemble(words)) == words` for every
//! image the assembler can produce.

use std::collections::BTreeSet;
use std::fmt::Write;

use super::super::catalog::{self, OperandKind};
use super::super::command::Command;
use super::super::line::format_command;
use super::super::validate::validate;
use super::{ProgramWord, check_program_command};

/// The label the disassembler gives `address`.
pub fn label_name(address: usize) -> String {
    format!("L_{address:04}")
}

/// How one word is shown.
enum Shown {
    /// Mnemonic form; `target` is the address operand, if the command has one.
    Mnemonic {
        command: Command,
        target: Option<usize>,
    },
    /// Four numbers, with the reason.
    Raw { why: String },
}

fn show(word: ProgramWord) -> Shown {
    let command = word.command();
    let info = catalog::command_by_opcode(word.opcode);
    if command.is_raw() {
        let why = match info {
            Some(info) => format!(
                "not a valid {} (§{}): a field outside its binary form",
                info.name, info.section
            ),
            None => format!("instruction {} is not a TMCL command", word.opcode),
        };
        return Shown::Raw { why };
    }
    if let Err(e) = check_program_command(&command) {
        return Shown::Raw { why: e.to_string() };
    }
    if let Err(e) = validate(&command) {
        return Shown::Raw { why: e.to_string() };
    }
    let takes_address =
        info.is_some_and(|i| i.operands.iter().any(|o| o.kind == OperandKind::Label));
    let target = takes_address
        .then(|| usize::try_from(word.value).ok())
        .flatten();
    Shown::Mnemonic { command, target }
}

/// The source of a program image.
pub fn disassemble(words: &[ProgramWord]) -> String {
    let shown: Vec<Shown> = words.iter().map(|w| show(*w)).collect();
    // A label can stand before any instruction or after the last one.
    let labelled: BTreeSet<usize> = shown
        .iter()
        .filter_map(|s| match s {
            Shown::Mnemonic {
                target: Some(t), ..
            } if *t <= words.len() => Some(*t),
            _ => None,
        })
        .collect();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "// TMCL program, {} word{}, disassembled by axterm",
        words.len(),
        if words.len() == 1 { "" } else { "s" }
    );
    for (address, (word, shown)) in words.iter().zip(&shown).enumerate() {
        if labelled.contains(&address) {
            let _ = writeln!(out, "{}:", label_name(address));
        }
        let line = match shown {
            Shown::Mnemonic { command, target } => {
                let text = format_command(command);
                match target.filter(|t| labelled.contains(t)) {
                    Some(t) => with_label(&text, t),
                    None => text,
                }
            }
            Shown::Raw { why } => format!(
                "{} {} {} {}  // {why}",
                word.opcode, word.kind, word.motor_bank, word.value
            ),
        };
        let _ = writeln!(out, "    {line}");
    }
    if labelled.contains(&words.len()) {
        let _ = writeln!(out, "{}:", label_name(words.len()));
    }
    out
}

/// `JC GE, 10` → `JC GE, L_0010`: the address is always the last operand
/// (JA, JC, CSUB, CALL, DJNZ, RST, VECT).
fn with_label(text: &str, target: usize) -> String {
    match text.rsplit_once(' ') {
        Some((head, last)) if last == target.to_string() => {
            format!("{head} {}", label_name(target))
        }
        _ => text.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::tmcl::asm::{NoIncludes, assemble};

    fn words(source: &str) -> Vec<ProgramWord> {
        match assemble("t.tmc", source, &NoIncludes) {
            Ok(p) => p.words,
            Err(e) => panic!("{e:?}"),
        }
    }

    #[test]
    fn targets_get_labels_and_operands_their_symbols() {
        let image = words("Loop: MVP ABS, 0, 1000\nWAIT POS, 0, 0\nJC GE, Loop\nCSUB End\nEnd:");
        assert_eq!(
            disassemble(&image),
            "// TMCL program, 4 words, disassembled by axterm\n\
             L_0000:\n    MVP ABS, 0, 1000\n    WAIT POS, 0, 0\n    JC GE, L_0000\n    \
             CSUB L_0004\nL_0004:\n"
        );
    }

    #[test]
    fn targets_beyond_the_program_stay_numbers() {
        let image = words("JA 100\nSTOP");
        assert!(disassemble(&image).contains("    JA 100\n"));
    }

    #[test]
    fn words_without_a_valid_mnemonic_are_raw_with_the_reason() {
        let image = [
            ProgramWord {
                opcode: 22,
                kind: 0,
                motor_bank: 0,
                value: 5000,
            },
            ProgramWord {
                opcode: 5,
                kind: 6,
                motor_bank: 0,
                value: 300,
            },
            ProgramWord::default(),
            ProgramWord {
                opcode: 24,
                kind: 1,
                motor_bank: 0,
                value: 0,
            },
        ];
        let text = disassemble(&image);
        let lines: Vec<&str> = text.lines().skip(1).collect();
        assert_eq!(
            lines,
            [
                "    22 0 0 5000  // JA: address 5000 outside program memory 0..2047",
                "    5 6 0 300  // SAP 6: value 300 outside 0..255 (Maximum current)",
                "    0 0 0 0  // instruction 0 is not a TMCL command",
                "    24 1 0 0  // not a valid RSUB (§3.6.21): a field outside its binary form",
            ]
        );
        assert_eq!(words(&text), image);
    }
}
