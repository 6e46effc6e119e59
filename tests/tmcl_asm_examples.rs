//! Every complete example program of the TMCM-1110 TMCL manual
//! (tests/data/programs, each with its section and corrections in its
//! header) assembles, its labels have the addresses the manual states (or,
//! where it states none, one word per instruction: digest D10), and
//! assemble → disassemble → assemble gives the same bytes. The manual's
//! binary forms of JC, JA, CSUB, VECT, RST, DJNZ and CALL are checked with
//! their labels placed at the addresses those forms assume.

use std::collections::BTreeMap;

use axterm::cli::asm::SourceFiles;
use axterm::protocol::tmcl::asm::{
    AsmErrorKind, NoIncludes, Program, ProgramWord, assemble, disassemble,
};

fn example_path(name: &str) -> String {
    format!("{}/tests/data/programs/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn assemble_example(name: &str) -> Program {
    let path = example_path(name);
    let source = std::fs::read_to_string(&path).expect("example file");
    match assemble(&path, &source, &SourceFiles) {
        Ok(program) => program,
        Err(errors) => panic!("{name} does not assemble: {errors:#?}"),
    }
}

fn symbols(pairs: &[(&str, u16)]) -> BTreeMap<String, u16> {
    pairs.iter().map(|(n, a)| (n.to_string(), *a)).collect()
}

/// The 7 bytes of a word from the manual's hex notation.
fn bytes(hex: &str) -> [u8; 7] {
    let v: Vec<u8> = hex
        .split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).expect("hex byte"))
        .collect();
    v.try_into().expect("seven bytes")
}

fn round_trips(program: &Program) {
    let source = disassemble(&program.words);
    let again = match assemble("disassembled.tmc", &source, &NoIncludes) {
        Ok(p) => p,
        Err(errors) => panic!("disassembly does not assemble: {errors:#?}\n{source}"),
    };
    assert_eq!(again.words, program.words, "{source}");
    assert_eq!(disassemble(&again.words), source);
}

/// A manual example: its file, how many words it assembles to, its labels
/// and their addresses.
struct Example {
    file: &'static str,
    words: usize,
    labels: &'static [(&'static str, u16)],
}

const fn example(
    file: &'static str,
    words: usize,
    labels: &'static [(&'static str, u16)],
) -> Example {
    Example {
        file,
        words,
        labels,
    }
}

const EXAMPLES: &[Example] = &[
    // §2.4: 8 set-up instructions, then the loop (derived).
    example("s2_4_first_program.tmc", 13, &[("Loop", 8)]),
    // §3.5.6.4 (derived).
    example(
        "s3_5_6_4_timer_interrupt.tmc",
        15,
        &[("Loop", 4), ("Timer0Irq", 9), ("Out0Off", 13)],
    ),
    example(
        "s3_5_6_4_timer_interrupt_symbolic.tmc",
        15,
        &[("Loop", 4), ("Timer0Irq", 9), ("Out0Off", 13)],
    ),
    // §3.6.19, §3.6.20, §3.6.29 (derived).
    example("s3_6_19_ja_loop.tmc", 5, &[("Loop", 0)]),
    example("s3_6_20_csub.tmc", 8, &[("Loop", 0), ("SubW", 5)]),
    example("s3_6_29_aap_potentiometer.tmc", 4, &[("Start", 0)]),
    // §3.6.43: "the label Loop is at address 1" (stated).
    example("s3_6_43_djnz_loop.tmc", 5, &[("Loop", 1)]),
    // §8.2, §8.3 (derived).
    example("s8_2_main_loop.tmc", 6, &[("MainLoop", 2)]),
    example("s8_3_symbolic_constants.tmc", 7, &[("MainLoop", 2)]),
    // §8.6: "run command with address 0 … 1 … 2" (stated); the routines
    // follow (derived).
    example(
        "s8_6_host_routines.tmc",
        16,
        &[
            ("Func1", 0),
            ("Func2", 1),
            ("Func3", 2),
            ("Func1Start", 3),
            ("Func2Start", 8),
            ("Func3Start", 12),
        ],
    ),
];

#[test]
fn every_manual_example_assembles_with_its_label_addresses() {
    for Example {
        file,
        words,
        labels,
    } in EXAMPLES
    {
        let program = assemble_example(file);
        assert_eq!(program.words.len(), *words, "{file}");
        assert_eq!(program.symbols, symbols(labels), "{file}");
        assert_eq!(program.lines.len(), *words, "{file}");
        for (address, line) in program.lines.iter().enumerate() {
            assert_eq!(usize::from(line.address), address, "{file}");
        }
    }
}

#[test]
fn every_manual_example_round_trips_through_the_disassembler() {
    for example in EXAMPLES {
        round_trips(&assemble_example(example.file));
    }
}

#[test]
fn the_include_file_form_of_3_5_6_4_is_the_same_program() {
    let plain = assemble_example("s3_5_6_4_timer_interrupt.tmc");
    let symbolic = assemble_example("s3_5_6_4_timer_interrupt_symbolic.tmc");
    assert_eq!(plain.words, symbolic.words);
    assert_eq!(symbolic.constants.get("TI_GLOBAL"), Some(&255));
    // §3.6.34's VECT with interrupt 0 (the printed FF is a copy error, D11).
    assert_eq!(
        plain.words[0].to_bytes(),
        bytes("25 00 00 00 00 00 09"),
        "VECT 0, Timer0Irq"
    );
}

#[test]
fn the_djnz_example_encodes_variable_42_and_loop_at_1() {
    let program = assemble_example("s3_6_43_djnz_loop.tmc");
    // §3.6.43's binary form with the type byte 2Ah = 42 (the manual prints
    // 64h, digest D11).
    assert_eq!(program.words[4].to_bytes(), bytes("31 2A 00 00 00 00 01"));
}

#[test]
fn the_host_routines_start_at_the_jump_table() {
    let program = assemble_example("s8_6_host_routines.tmc");
    // 129 type 1 with address 0, 1, 2 lands on JA FuncNStart.
    for (address, start) in [(0, 3), (1, 8), (2, 12)] {
        let word = program.words[address];
        assert_eq!((word.opcode, word.value), (22, start));
    }
}

#[test]
fn symbolic_constants_give_the_same_words_as_numbers() {
    let symbolic = assemble_example("s8_3_symbolic_constants.tmc");
    let numbers = "SAP 4, 0, 2047\nSAP 5, 0, 2047\nMainLoop:\nMVP ABS, 0, 500000\n\
                   WAIT POS, 0, 0\nMVP ABS, 0, 0\nWAIT POS, 0, 0\nJA MainLoop\n";
    let plain = assemble("n.tmc", numbers, &NoIncludes).unwrap();
    assert_eq!(symbolic.words, plain.words);
}

/// Without the corrections in their headers, the examples fail the way the
/// digest says they would.
#[test]
fn the_manuals_misprints_are_refused() {
    let errors = |source: &str| assemble("m.tmc", source, &NoIncludes).unwrap_err();
    // §3.6.43 as printed: REL in the motor operand.
    let e = errors("SGP 42, 2, 100\nLoop:\nMVP ABS, REL, 51200\nDJNZ 42, Loop");
    assert!(
        matches!(&e[0].kind, AsmErrorKind::UndefinedSymbol { name, .. } if name == "REL"),
        "{e:?}"
    );
    assert_eq!((e[0].line, e[0].column), (3, 10));
    // §8.2 as printed: pps values above 2047.
    let e = errors("SAP 4, 0, 50000\nSAP 5, 0, 10000");
    assert_eq!(e.len(), 2);
    assert!(
        e[0].to_string()
            .ends_with("value 50000 outside 1..2047 (Maximum positioning speed)")
    );
    assert!(e[1].to_string().contains("value 10000 outside 1..2047"));
}

/// (section, the manual's fragment with its "…" as a `...` line, index of
/// the word, its bytes as the manual prints them or as digest D11 corrects
/// them). The `...` becomes as many STOPs as put the label where the
/// binary form assumes it.
const BINARY_FORMS: &[(&str, &str, usize, &str)] = &[
    (
        "3.6.18 JC GE, Label at 10",
        "GAP 1, 0\nCOMP 1000\nJC GE, Label\n...\nLabel: ROL 0, 1000",
        2,
        "15 05 00 00 00 00 0A",
    ),
    (
        "3.6.19 JA Loop at 10",
        "...\nLoop:\nMVP ABS, 0, 51200\nWAIT POS, 0, 0\nMVP ABS, 0, 0\nWAIT POS, 0, 0\nJA Loop",
        14,
        "16 00 00 00 00 00 0A",
    ),
    (
        "3.6.20 CSUB SubW at 100",
        "Loop:\nMVP ABS, 0, 10000\nCSUB SubW\nMVP ABS, 0, 0\nCSUB SubW\nJA Loop\n...\n\
         SubW:\nWAIT POS, 0, 0\nWAIT TICKS, 0, 50\nRSUB",
        1,
        "17 00 00 00 00 00 64",
    ),
    (
        "3.6.34 VECT 0, Timer0Irq at 50 (type 00, D11)",
        "VECT 0, Timer0Irq\n...\nTimer0Irq:\nSIO 0, 2, 1\nRETI",
        0,
        "25 00 00 00 00 00 32",
    ),
    (
        "3.6.35 RETI (type 00, D11)",
        "RETI",
        0,
        "26 00 00 00 00 00 00",
    ),
    (
        "3.6.42 RST Entry at 10",
        "...\nEntry:\nMVP ABS, 0, 51200\nCSUB Subroutine\nSTOP\nSubroutine:\nRST Entry\nRSUB",
        13,
        "30 00 00 00 00 00 0A",
    ),
    (
        // The manual does not show MotorStop and RunRight: their CALLs are
        // left out.
        "3.6.44 CALL LT, RunLeft at 100",
        "Loop:\nGIO 0, 1\nCALC SUB, 512\nCOMP 0\nCALL LT, RunLeft\nJA Loop\n...\n\
         RunLeft:\nCALC MUL, -1\nROLA 0\nRSUB",
        3,
        "50 06 00 00 00 00 64",
    ),
];

/// `fragment` with its `...` line replaced by STOPs so that the label after
/// it is at `target`.
fn padded(fragment: &str, target: i32) -> String {
    let Some((head, tail)) = fragment.split_once("...\n") else {
        return fragment.to_string();
    };
    let instructions = head.lines().filter(|l| !l.trim().ends_with(':')).count();
    let count = usize::try_from(target).unwrap() - instructions;
    format!("{head}{}{tail}", "STOP\n".repeat(count))
}

#[test]
fn binary_forms_of_the_manual_match_with_labels_where_it_assumes() {
    for (section, fragment, index, hex) in BINARY_FORMS {
        let expected = bytes(hex);
        let target = ProgramWord::from_bytes(expected).value;
        let source = padded(fragment, target);
        let program = match assemble("binary.tmc", &source, &NoIncludes) {
            Ok(p) => p,
            Err(errors) => panic!("{section}: {errors:#?}"),
        };
        assert_eq!(program.words[*index].to_bytes(), expected, "{section}");
        round_trips(&program);
    }
}
