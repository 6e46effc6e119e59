//! The assembler refuses bad programs with file:line:column messages that
//! say what was expected, and lists every error, not just the first.

use std::collections::BTreeMap;

use axterm::protocol::tmcl::asm::{
    AsmError, AsmErrorKind, MAX_INCLUDE_DEPTH, NoIncludes, PROGRAM_MEMORY_WORDS, Program,
    SourceLoader, assemble,
};
use axterm::protocol::tmcl::{Command, LineError};

fn errors(source: &str) -> Vec<AsmError> {
    match assemble("prog.tmc", source, &NoIncludes) {
        Ok(program) => panic!("assembled: {program:?}"),
        Err(errors) => errors,
    }
}

fn only_error(source: &str) -> AsmError {
    let mut all = errors(source);
    assert_eq!(all.len(), 1, "{all:#?}");
    all.remove(0)
}

fn place(error: &AsmError) -> (&str, usize, usize) {
    (error.file.as_str(), error.line, error.column)
}

fn ok(source: &str) -> Program {
    match assemble("prog.tmc", source, &NoIncludes) {
        Ok(program) => program,
        Err(errors) => panic!("{errors:#?}"),
    }
}

fn files(entries: &[(&str, &str)]) -> BTreeMap<String, String> {
    entries
        .iter()
        .map(|(path, text)| (path.to_string(), text.to_string()))
        .collect()
}

#[test]
fn an_unknown_mnemonic_is_located_and_the_expected_forms_named() {
    let e = only_error("STOP\n  MOVE 0, 1000 // go\n");
    assert_eq!(place(&e), ("prog.tmc", 2, 3));
    assert_eq!(
        e.to_string(),
        "prog.tmc:2:3: `MOVE` is not a TMCL command: expected a mnemonic (MVP, SAP, JA…), \
         a label `Name:`, a constant `Name = value` or `#include File`"
    );
    // A label without its colon gets a hint.
    let e = &errors("Loop\nJA Loop")[0];
    assert!(
        e.message().ends_with("(a label needs a colon: `Loop:`)"),
        "{e}"
    );
}

#[test]
fn a_missing_operand_points_past_the_end_and_shows_the_syntax() {
    let e = only_error("Loop:   JC GE   // no target");
    assert_eq!(place(&e), ("prog.tmc", 1, 14));
    assert_eq!(
        e.message(),
        "JC: missing <label> (syntax: JC <condition>, <label>)"
    );
    let e = only_error("SAP 4, 0");
    assert_eq!(
        (e.column, e.message().as_str()),
        (
            9,
            "SAP: missing <value> (syntax: SAP <parameter>, <motor>, <value>)"
        )
    );
}

#[test]
fn an_undefined_label_is_named_with_a_near_miss() {
    let all = errors("Loop: MVP ABS, 0, 1000\nJA Lop\nJA loop\nCSUB Elsewhere");
    let shown: Vec<String> = all.iter().map(ToString::to_string).collect();
    assert_eq!(
        shown,
        [
            "prog.tmc:2:4: JA: undefined label `Lop` (did you mean `Loop`?)",
            "prog.tmc:3:4: JA: undefined label `loop` (did you mean `Loop`?)",
            "prog.tmc:4:6: CSUB: undefined label `Elsewhere`",
        ]
    );
    assert!(matches!(
        &all[2].kind,
        AsmErrorKind::UndefinedLabel { name, suggestion: None, .. } if name == "Elsewhere"
    ));
}

#[test]
fn an_undefined_constant_names_the_operand() {
    let e = only_error("MaxSpeed = 1000\nSAP 4, 0, MaxSped");
    assert_eq!(place(&e), ("prog.tmc", 2, 11));
    assert_eq!(
        e.message(),
        "SAP: <value> `MaxSped` is not a number or a defined constant or label \
         (did you mean `MaxSpeed`?)"
    );
}

#[test]
fn a_duplicate_label_names_the_first_definition() {
    let e = only_error("Loop: STOP\n  STOP\n  Loop:\nJA Loop");
    assert_eq!(place(&e), ("prog.tmc", 3, 3));
    assert_eq!(
        e.message(),
        "duplicate label `Loop`: already defined at prog.tmc:1:1"
    );
    // Labels and constants share one name space.
    let e = only_error("Speed = 5\nSpeed: STOP");
    assert_eq!(
        e.to_string(),
        "prog.tmc:2:1: `Speed` is already a constant (at prog.tmc:1:1): give this label another name"
    );
    let e = only_error("Speed: STOP\nSpeed = 5");
    assert!(e.message().starts_with("`Speed` is already a label"), "{e}");
}

#[test]
fn an_out_of_range_value_points_at_its_operand() {
    let e = only_error("ROL 0, 51200");
    assert_eq!(place(&e), ("prog.tmc", 1, 8));
    assert_eq!(e.message(), "ROL: velocity 51200 outside -2047..2047");
    assert!(matches!(
        &e.kind,
        AsmErrorKind::Operand(line) if matches!(**line, LineError::OutOfRange { .. })
    ));
    // Through a constant: the constant's name in the instruction.
    let e = only_error("Fast = 3000\nSAP 4, 0, Fast");
    assert_eq!((e.line, e.column), (2, 11));
    assert!(e.message().contains("3000 outside 1..2047"), "{e}");
    // Other refusals of the module's tables point at their operand too.
    assert_eq!(only_error("MST 1").column, 5);
    assert_eq!(only_error("GAP 99, 0").column, 5);
    assert_eq!(only_error("SIO 9, 2, 1").column, 5);
    assert_eq!(only_error("GAP 1, 0 0").column, 10);
    assert_eq!(only_error("SAP 4,, 0").column, 7);
    assert_eq!(only_error("EI 4").column, 4);
    assert_eq!(only_error("CALC SWAP, 1").column, 6);
    assert_eq!(only_error("256 0 0 0").column, 1);
}

#[test]
fn jump_targets_stay_inside_program_memory() {
    let e = only_error("JA 2048");
    assert_eq!(place(&e), ("prog.tmc", 1, 4));
    assert_eq!(
        e.message(),
        "JA: address 2048 outside program memory 0..2047"
    );
    let e = only_error("Far = 5000\nSTOP\nVECT 0, Far");
    assert_eq!((e.line, e.column), (3, 9));
    assert!(matches!(
        e.kind,
        AsmErrorKind::AddressOutsideMemory { address: 5000, .. }
    ));
    let e = only_error("DJNZ 3, -1");
    assert!(matches!(
        e.kind,
        AsmErrorKind::AddressOutsideMemory { address: -1, .. }
    ));
    assert_eq!(ok("JA 2047").words.len(), 1);
}

#[test]
fn a_program_longer_than_memory_is_refused_once() {
    let full = "STOP\n".repeat(PROGRAM_MEMORY_WORDS);
    assert_eq!(ok(&full).words.len(), PROGRAM_MEMORY_WORDS);
    let over = format!("{full}STOP\nSTOP\n");
    let e = only_error(&over);
    assert_eq!((e.line, e.column), (PROGRAM_MEMORY_WORDS + 1, 1));
    assert_eq!(e.kind, AsmErrorKind::ProgramTooLong);
}

#[test]
fn control_commands_cannot_be_stored() {
    let e = only_error("STOP\nRUNAPP 0");
    assert_eq!(place(&e), ("prog.tmc", 2, 1));
    assert!(
        e.message()
            .starts_with("RUNAPP is a direct-mode control command (§3.6.53)")
    );
    let e = only_error("132 0 0 0");
    assert!(
        e.message()
            .starts_with("instruction 132 (DOWNLOAD) is a direct-mode control command"),
        "{e}"
    );
    // Any other raw frame is stored as written.
    let program = ok("200 1 2 -3\n22 0 0 Here\nHere:");
    assert_eq!(
        program.words[0].command(),
        Command::Raw {
            command: 200,
            kind: 1,
            motor_bank: 2,
            value: -3
        }
    );
    assert_eq!(program.words[1].value, 2);
}

#[test]
fn constants_need_numbers_and_keep_their_value() {
    let all = errors("A =\nB = 1+2\nC = 4294967296\nD = Later\nLater = 1\nE = 1\nE = 2");
    let shown: Vec<String> = all.iter().map(ToString::to_string).collect();
    assert_eq!(
        shown,
        [
            "prog.tmc:1:4: constant `A` needs a value after `=`: a decimal \
             -2147483648..4294967295, a hex 0x0..0xFFFFFFFF or an earlier constant",
            "prog.tmc:2:5: constant `B`: `1+2` is not a decimal -2147483648..4294967295, \
             a hex 0x0..0xFFFFFFFF or an earlier constant",
            "prog.tmc:3:5: constant `C`: `4294967296` is not a decimal \
             -2147483648..4294967295, a hex 0x0..0xFFFFFFFF or an earlier constant",
            "prog.tmc:4:5: constant `D`: `Later` is not a decimal -2147483648..4294967295, \
             a hex 0x0..0xFFFFFFFF or an earlier constant",
            "prog.tmc:7:1: constant `E` = 2 contradicts its definition = 1 at prog.tmc:6:1",
        ]
    );
}

#[test]
fn constants_reach_what_the_manual_allows() {
    // A timer period above i32::MAX (§5.4 Table 20), in decimal or hex.
    let program = ok("Long = 4294967295\nHex = 0xFFFFFFFF\nSGP 0, 3, Long\nSGP 1, 3, Hex");
    assert_eq!(program.words[0].value, -1);
    assert_eq!(program.words[1].value, -1);
    assert_eq!(program.constants.get("Long"), Some(&4_294_967_295));
    // A hex constant is a bit pattern where a signed value goes, as a hex
    // literal is; a decimal above i32::MAX is not.
    assert_eq!(ok("M = $FFFFFFFF\nSAP 0, 0, M").words[0].value, -1);
    let e = only_error("Big = 3000000000\nSGP 0, 2, Big");
    assert!(
        e.message().contains("outside -2147483648..2147483647"),
        "{e}"
    );
    // Constants may name earlier constants, and go into byte operands.
    let program = ok("Var = 42\nCounter = Var\nSGP Counter, 2, 100\nL: DJNZ Counter, L");
    assert_eq!(program.words[0].kind, 42);
    assert_eq!(program.words[1].kind, 42);
}

#[test]
fn includes_are_relative_to_the_including_file() {
    let loader = files(&[
        (
            "prog/lib/params.inc",
            "#include ../more/axis.inc\nSpeed = 1000",
        ),
        ("prog/more/axis.inc", "Motor = 0\nHelper: RSUB"),
    ]);
    let source = "#include lib/params.inc\nCSUB Helper\nROR Motor, Speed";
    let program = assemble("prog/main.tmc", source, &loader).unwrap();
    assert_eq!(program.symbols.get("Helper"), Some(&0));
    let places: Vec<(&str, usize)> = program
        .lines
        .iter()
        .map(|l| (l.file.as_str(), l.line))
        .collect();
    assert_eq!(
        places,
        [
            ("prog/more/axis.inc", 2),
            ("prog/main.tmc", 2),
            ("prog/main.tmc", 3)
        ]
    );
    // A file included twice only repeats identical constants: harmless.
    let loader = files(&[("c.inc", "Motor = 0")]);
    let twice = "#include c.inc\n#include c.inc\nMST Motor";
    assert!(assemble("main.tmc", twice, &loader).is_ok());
}

#[test]
fn an_include_cycle_is_refused_with_its_chain() {
    let loader = files(&[
        ("dir/a.inc", "A = 1\n#include b.inc"),
        ("dir/b.inc", "// b\n  #include a.inc"),
    ]);
    let errors = assemble("dir/main.tmc", "#include a.inc\nSTOP", &loader).unwrap_err();
    assert_eq!(errors.len(), 1, "{errors:#?}");
    assert_eq!(place(&errors[0]), ("dir/b.inc", 2, 12));
    assert_eq!(
        errors[0].message(),
        "include cycle: dir/a.inc -> dir/b.inc -> dir/a.inc"
    );
    // A file including itself.
    let errors = assemble("self.tmc", "#include ./self.tmc", &files(&[])).unwrap_err();
    assert!(matches!(
        &errors[0].kind,
        AsmErrorKind::IncludeCycle { chain } if chain == &["self.tmc", "self.tmc"]
    ));
}

/// A loader that always finds one more file, one directory deeper.
struct Bottomless;

impl SourceLoader for Bottomless {
    fn load(&self, _path: &str) -> Result<String, axterm::protocol::program::LoadError> {
        Ok("#include deeper/x.inc".to_string())
    }
}

#[test]
fn includes_nest_only_so_deep() {
    let errors = assemble("main.tmc", "#include x.inc", &Bottomless).unwrap_err();
    assert_eq!(errors.len(), 1);
    assert_eq!(errors[0].kind, AsmErrorKind::IncludeTooDeep);
    assert_eq!(
        errors[0].file.matches("deeper").count(),
        MAX_INCLUDE_DEPTH - 2
    );
}

#[test]
fn include_problems_are_named() {
    let all = match assemble(
        "main.tmc",
        "#include missing.inc\n#include\n#define X 1\n#include \"q.inc\"",
        &files(&[("q.inc", "Q = 1")]),
    ) {
        Ok(_) => panic!("assembled"),
        Err(e) => e,
    };
    let shown: Vec<String> = all.iter().map(ToString::to_string).collect();
    assert_eq!(
        shown,
        [
            "main.tmc:1:10: cannot include `missing.inc`: no such file",
            "main.tmc:2:1: #include needs a file name: `#include File.inc`",
            "main.tmc:3:1: unknown directive `#define`: the only directive is `#include File`",
        ]
    );
}

#[test]
fn every_error_is_listed_in_source_order_across_files() {
    let loader = files(&[("sub.inc", "Bad: FOO\nROL 0, 9999")]);
    let source = "JA Nowhere\n#include sub.inc\nMST 3\nBad:";
    let errors = assemble("main.tmc", source, &loader).unwrap_err();
    let places: Vec<(&str, usize, usize)> = errors.iter().map(place).collect();
    assert_eq!(
        places,
        [
            ("main.tmc", 1, 4),
            ("sub.inc", 1, 6),
            ("sub.inc", 2, 8),
            ("main.tmc", 3, 5),
            ("main.tmc", 4, 1),
        ]
    );
}

#[test]
fn labels_may_share_an_address_and_end_the_program() {
    let program = ok("\u{feff}Start: Again:\r\nSTOP\r\nEnd:\r\n");
    assert_eq!(program.symbols.get("Start"), Some(&0));
    assert_eq!(program.symbols.get("Again"), Some(&0));
    assert_eq!(program.symbols.get("End"), Some(&1));
    assert_eq!(program.lines[0].text, "STOP");
}

#[test]
fn mnemonics_and_symbols_are_case_insensitive_names_are_not() {
    let program = ok("loop: mvp abs, 0, 10\nwait pos 0 0\njc ge loop");
    assert_eq!(program.words[2].to_bytes(), [0x15, 5, 0, 0, 0, 0, 0]);
    let e = only_error("Loop: STOP\nJA LOOP");
    assert!(matches!(e.kind, AsmErrorKind::UndefinedLabel { .. }));
}
