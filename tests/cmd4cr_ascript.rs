//! The manual's A-Script, from the worked examples file
//! (tests/data/cmd4cr-vectors.json, copied from the shared protocol
//! digest): every example program of §5.4 (as corrected there for OCR
//! damage) compiles clean, every operator example of Table 2-32 compiles,
//! every "Incorrect Code Example" of Table 5-43 gets its documented error
//! on the right line, and the programs translate to the ASCII commands a
//! host would send.

use axterm::protocol::cmd4cr::ascript::{
    Action, ERROR_CODES, ErrorCode, Op, Program, Statement, TokenClass, VARIABLES, ascii_command,
    ascii_equivalent, buffered_move, buffered_move_command, check, compile, tokens,
};
use axterm::protocol::cmd4cr::parse_command;
use serde_json::Value;

fn vectors() -> Vec<Value> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/cmd4cr-vectors.json"
    );
    let text = std::fs::read_to_string(path).expect("vectors file");
    match serde_json::from_str(&text).expect("vectors JSON") {
        Value::Array(entries) => entries,
        other => panic!("not a list: {other}"),
    }
}

/// Entries carrying an A-Script program or fragment.
fn programs() -> Vec<Value> {
    vectors()
        .into_iter()
        .filter(|e| e.get("program").is_some())
        .collect()
}

fn text<'a>(entry: &'a Value, key: &str) -> &'a str {
    entry.get(key).and_then(Value::as_str).unwrap_or("")
}

fn example(section: &str) -> Program {
    let entry = programs()
        .into_iter()
        .find(|e| text(e, "section") == section && e.get("title").is_some())
        .unwrap_or_else(|| panic!("no example {section}"));
    compile(text(&entry, "program")).unwrap_or_else(|e| panic!("{section}: {e:#?}"))
}

#[test]
fn every_example_program_of_5_4_compiles_without_errors_or_warnings() {
    let examples: Vec<Value> = programs()
        .into_iter()
        .filter(|e| e.get("title").is_some())
        .collect();
    assert_eq!(examples.len(), 10);
    for entry in &examples {
        let section = text(entry, "section");
        assert!(entry.get("expected_error").is_some_and(Value::is_null));
        let diagnostics = check(text(entry, "program"));
        assert!(diagnostics.is_empty(), "{section}: {diagnostics:#?}");
        let program = compile(text(entry, "program")).unwrap_or_default();
        assert!(program.host_problems().is_empty(), "{section}");
    }
}

#[test]
fn the_examples_blocks_are_where_the_manual_puts_them() {
    let blocks = |p: &Program| {
        let programs: Vec<u8> = p.program_numbers().collect();
        let subs: Vec<u8> = (0..32).filter(|&n| p.subroutine(n).is_some()).collect();
        (programs, subs)
    };
    assert_eq!(blocks(&example("5.4.1")), (vec![0], vec![]));
    assert_eq!(blocks(&example("5.4.2")), (vec![1], vec![]));
    assert_eq!(blocks(&example("5.4.5")), (vec![2], vec![]));
    assert_eq!(blocks(&example("5.4.6")), (vec![0], vec![1]));
    assert_eq!(blocks(&example("5.4.7")), (vec![2], vec![31]));
    assert_eq!(blocks(&example("5.4.8")), (vec![0, 1], vec![]));
    assert_eq!(blocks(&example("5.4.9")), (vec![0, 1], vec![1, 31]));
    let ten = example("5.4.10");
    assert_eq!(blocks(&ten), (vec![1, 3], vec![1, 2, 7, 31]));
    assert_eq!(ten.program(1).map(|e| e.line), Some(1));
    assert_eq!(ten.subroutine(31).map(|e| e.line), Some(72));
}

#[test]
fn the_operator_examples_of_table_2_32_compile_inside_a_program() {
    let fragments: Vec<Value> = programs()
        .into_iter()
        .filter(|e| text(e, "section") == "2.7.6")
        .collect();
    assert_eq!(fragments.len(), 10);
    for entry in fragments {
        let fragment = text(&entry, "program");
        let source = format!("PRG 0\n{fragment}\nEND\n");
        let program = compile(&source).unwrap_or_else(|e| panic!("{fragment}: {e:#?}"));
        let Some(Statement::Action(Action::Let { variable: 1, value })) =
            program.statements.get(1).map(|s| &s.statement)
        else {
            panic!("{fragment}: {:?}", program.statements);
        };
        assert_eq!(format!("V1={value}"), fragment);
    }
}

#[test]
fn every_incorrect_code_example_of_table_5_43_gets_its_error_on_its_line() {
    let fragments: Vec<Value> = programs()
        .into_iter()
        .filter(|e| text(e, "section") == "5.3")
        .collect();
    assert_eq!(fragments.len(), ERROR_CODES.len());
    for entry in fragments {
        let fragment = text(&entry, "program");
        let expected = ErrorCode::from_text(text(&entry, "expected_error"))
            .unwrap_or_else(|| panic!("unknown code in {entry}"));
        let (source, line) = match text(&entry, "placement") {
            "statement" => (format!("PRG 0\n    {fragment}\nEND\n"), 2),
            _ => (format!("{fragment}\n"), 1),
        };
        let errors = compile(&source).err().unwrap_or_default();
        assert_eq!(errors.len(), 1, "{fragment}: {errors:#?}");
        assert_eq!(
            (errors[0].line, errors[0].code),
            (line, expected),
            "{fragment}"
        );
        assert!(
            errors[0]
                .to_string()
                .starts_with(&format!("line {line}: {}: ", expected.text())),
            "{}",
            errors[0]
        );
        // The table as data agrees with the examples file.
        assert_eq!(expected.info().example, fragment);
    }
}

#[test]
fn the_conversions_misreadings_are_not_a_script() {
    // What the converted manual printed before the corrections the
    // examples file lists: each is refused, none enshrined.
    for (misprint, code) in [
        ("FO=1", ErrorCode::UnknownError),
        ("FNDIF", ErrorCode::UnknownError),
        ("FLSFIF DI2=1", ErrorCode::UnknownError),
        ("10=64", ErrorCode::UnknownError),
        ("ENDSU 3", ErrorCode::UnknownError),
        ("ENDOLL WAITX", ErrorCode::UnknownError),
    ] {
        let errors = compile(&format!("PRG 0\n{misprint}\nEND"))
            .err()
            .unwrap_or_default();
        assert_eq!(
            errors.first().map(|e| (e.line, e.code)),
            Some((2, code)),
            "{misprint}"
        );
    }
}

#[test]
fn example_1_is_the_ascii_sequence_a_host_would_send() {
    let program = example("5.4.1");
    let variables = [0; VARIABLES];
    let sent: Vec<Option<String>> = program
        .statements
        .iter()
        .map(|s| ascii_equivalent(&s.statement, &variables))
        .collect();
    let expected = [
        None,
        Some("HSPD=20000"),
        Some("LSPD=1000"),
        Some("ACC=300"),
        Some("EO=1"),
        Some("X1000"),
        None, // WAITX: poll MSTX
        Some("X0"),
        None,
        None,
    ];
    assert_eq!(sent, expected.map(|s| s.map(String::from)));
}

#[test]
fn standalone_names_become_their_ascii_commands() {
    let mut variables = [0; VARIABLES];
    variables[1] = 1500;
    let ascii = |line: &str| {
        let program = compile(&format!("PRG 0\n{line}\nEND")).unwrap_or_default();
        program
            .statements
            .get(1)
            .and_then(|s| ascii_equivalent(&s.statement, &variables))
    };
    for (line, expected) in [
        ("XV1", Some("X1500")),
        ("ECLEARX", Some("CLRX")),
        ("SR0=1", Some("SACTRL0=1")),
        ("JOGX+", Some("JX+")),
        ("HOMEX-6", Some("HX-6")),
        ("ZMOVEY-", Some("ZMOVEY-")),
        ("BUFON", Some("BO")),
        ("BUFOFF", Some("BF")),
        ("ISTART", Some("BSTART")),
        ("SYNONX", Some("SYNOX")),
        ("SYNOFFX", Some("SYNFX")),
        ("SYNCFGX=1", Some("SYNCX=1")),
        ("SYNPOSX=V1", Some("SYNPX=1500")),
        ("JOYENA=1", Some("JENA=1")),
        ("JOYHSX=100", Some("JSPDX=100")),
        ("JOYDELY=5", Some("JDELY=5")),
        ("MPGEX=1", Some("MPEX=1")),
        ("DO1=1", Some("DO1=1")),
        ("STORE", Some("STORE")),
        ("CIRXYP487659:562431", Some("CIRXYP487659:562431")),
        ("ARCTN0:0:90000:500", Some("ARCTN0:0:90000:500")),
        ("DELAY=100", None),
        ("WAITY", None),
        ("V2=V1+1", None),
        ("GOSUB 0", None),
    ] {
        assert_eq!(ascii(line).as_deref(), expected, "{line}");
    }
}

#[test]
fn every_statement_of_the_examples_is_a_command_the_ascii_parser_reads_back() {
    let mut variables = [0; VARIABLES];
    // Example 6 moves to V1: give it a value a move takes.
    variables[1] = 1000;
    let mut translated = 0;
    for entry in programs().iter().filter(|e| e.get("title").is_some()) {
        let program = compile(text(entry, "program")).unwrap_or_default();
        for s in &program.statements {
            if let Some(command) = ascii_command(&s.statement, &variables) {
                let command = command.unwrap_or_else(|e| panic!("{}: {e}", s.statement));
                assert_eq!(parse_command(&command.to_string()), Ok(command.clone()));
                assert_eq!(
                    ascii_equivalent(&s.statement, &variables),
                    Some(command.to_string())
                );
                translated += 1;
            }
        }
    }
    assert!(translated > 100, "{translated}");
}

#[test]
fn a_variable_out_of_a_commands_range_gets_the_ascii_parsers_error() {
    let program = compile("PRG 0\nHSPD=V1\nEND").unwrap_or_default();
    let statement = &program.statements[1].statement;
    let mut variables = [0; VARIABLES];
    assert!(matches!(ascii_command(statement, &variables), Some(Err(_))));
    // The text is still sent as it is: the controller refuses it itself.
    assert_eq!(
        ascii_equivalent(statement, &variables).as_deref(),
        Some("HSPD=0")
    );
    variables[1] = 5000;
    assert_eq!(
        ascii_command(statement, &variables).map(|c| c.map(|c| c.to_string())),
        Some(Ok("HSPD=5000".to_string()))
    );
}

#[test]
fn buffered_moves_become_i_commands_at_the_global_high_speed() {
    let program = example("5.4.2");
    let variables = [0; VARIABLES];
    let mut speed = 0;
    let mut queued = Vec::new();
    for step in &program.steps {
        match &step.op {
            Op::Action(Action::Set { command, value })
                if command.name() == "HSPD" && command.axis().is_none() =>
            {
                speed = value.resolve(&variables);
            }
            Op::Action(Action::Move(targets)) => {
                queued.extend(buffered_move(targets, speed, &variables));
                assert!(matches!(
                    buffered_move_command(targets, speed, &variables),
                    Some(Ok(_))
                ));
            }
            _ => {}
        }
    }
    // The example's comments give the same fields (with a leading "1:").
    assert_eq!(
        queued,
        [
            "I1000:100:100:100",
            "I2000:100:100:200",
            "I3000:100:100:300",
            "I4000:100:100:400",
            "I5000:100:100:500",
            "I3000:100:100:400",
            "I0:100:100:300",
        ]
    );
}

#[test]
fn a_host_cannot_send_what_buffer_mode_has_no_ascii_form_for() {
    let program = compile(
        "PRG 0\n\
         BUFON\n\
         X1Y2Z3\n\
         X1\n\
         X1Y2Z3U4\n\
         CIRXYP0:0\n\
         CIRXUP0:0\n\
         CIRTP0:0:1\n\
         BUFOFF\n\
         X1\n\
         CIRTP0:0:1\n\
         END\n",
    )
    .unwrap_or_default();
    let lines: Vec<usize> = program.host_problems().iter().map(|p| p.line).collect();
    assert_eq!(lines, [4, 5, 7, 8]);
    let first = program.host_problems().first().map(ToString::to_string);
    assert_eq!(
        first.as_deref(),
        Some(
            "line 4: `X1` cannot run from the host: in buffer mode (BUFON on line 2) a move is \
             sent as I[X]:[Y]:[Z]:[speed] (§2.3.4), which needs exactly X, Y and Z targets"
        )
    );
}

#[test]
fn the_editor_colours_a_program_line_by_what_each_piece_is() {
    let line = "        V1=MSTX&1024                 ;Get bit alarm error variable";
    let classes: Vec<(&str, TokenClass)> = tokens(line)
        .into_iter()
        .filter(|(_, c)| *c != TokenClass::Plain)
        .map(|(r, c)| (line.get(r).unwrap_or("?"), c))
        .collect();
    assert_eq!(
        classes,
        [
            ("V1", TokenClass::Variable),
            ("=", TokenClass::Operator),
            ("MSTX", TokenClass::Command),
            ("&", TokenClass::Operator),
            ("1024", TokenClass::Number),
            (";Get bit alarm error variable", TokenClass::Comment),
        ]
    );
    let classes = |line: &'static str| -> Vec<(&'static str, TokenClass)> {
        tokens(line)
            .into_iter()
            .filter(|(_, c)| *c != TokenClass::Plain)
            .map(|(r, c)| (line.get(r).unwrap_or("?"), c))
            .collect()
    };
    assert_eq!(
        classes("PRG 0"),
        [("PRG", TokenClass::Block), ("0", TokenClass::Number)]
    );
    assert_eq!(
        classes("IF DI1=1"),
        [
            ("IF", TokenClass::Keyword),
            ("DI", TokenClass::Command),
            ("1", TokenClass::Number),
            ("=", TokenClass::Operator),
            ("1", TokenClass::Number),
        ]
    );
    assert_eq!(
        classes("XV1 HOMEX-6"),
        [
            ("X", TokenClass::Command),
            ("V1", TokenClass::Variable),
            ("HOMEX", TokenClass::Command),
            ("-", TokenClass::Operator),
            ("6", TokenClass::Number),
        ]
    );
    assert_eq!(
        classes("FNDIF ?"),
        [("FNDIF", TokenClass::Invalid), ("?", TokenClass::Invalid)]
    );
    assert_eq!(classes("ENDSUB"), [("ENDSUB", TokenClass::Block)]);
    assert_eq!(classes("GOSUB 1")[0], ("GOSUB", TokenClass::Keyword));
}
