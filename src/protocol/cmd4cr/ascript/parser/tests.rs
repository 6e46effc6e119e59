use super::*;
use crate::protocol::cmd4cr::ascript::ast::Address;

fn parsed(line: &str) -> Statement {
    match parse_line(line).map(|p| p.statement) {
        Some(Ok(statement)) => statement,
        other => panic!("{line:?}: {other:?}"),
    }
}

fn action(line: &str) -> Action {
    match parsed(line) {
        Statement::Action(action) => action,
        other => panic!("{line:?} is not an action: {other:?}"),
    }
}

fn error(line: &str) -> LineError {
    match parse_line(line).map(|p| p.statement) {
        Some(Err(error)) => error,
        other => panic!("{line:?} parsed: {other:?}"),
    }
}

fn code(line: &str) -> ErrorCode {
    error(line).code
}

fn command(name: &str, address: Address) -> Command {
    Command::new(name, address).unwrap_or_else(|| panic!("no {name} {address:?}"))
}

#[test]
fn block_lines_and_keywords() {
    assert_eq!(parsed("PRG 0"), Statement::Prg(0));
    assert_eq!(parsed("PRG3"), Statement::Prg(3));
    assert_eq!(parsed("SUB 31"), Statement::Sub(31));
    assert_eq!(parsed("GOSUB 7"), Statement::Gosub(7));
    assert_eq!(parsed("  ENDSUB   ; done"), Statement::EndSub);
    assert_eq!(parsed("ELSE"), Statement::Else);
    assert!(parse_line("   ; only a comment").is_none());
    assert!(parse_line("").is_none());
}

#[test]
fn conditions_compare_numbers_variables_and_readable_commands() {
    let di1 = Operand::Read(command("DI", Address::Index(1)));
    assert_eq!(
        parsed("IF DI1=1"),
        Statement::If(Condition {
            left: di1,
            op: Comparison::Equal,
            right: Operand::Number(1)
        })
    );
    assert_eq!(
        parsed("WHILE V30 < 10"),
        Statement::While(Condition {
            left: Operand::Variable(30),
            op: Comparison::Less,
            right: Operand::Number(10)
        })
    );
    assert_eq!(
        parsed("ELSEIF V2!=-3"),
        Statement::ElseIf(Condition {
            left: Operand::Variable(2),
            op: Comparison::NotEqual,
            right: Operand::Number(-3)
        })
    );
    for (text, op) in [
        (">", Comparison::Greater),
        (">=", Comparison::GreaterOrEqual),
        ("<=", Comparison::LessOrEqual),
    ] {
        let Statement::If(c) = parsed(&format!("IF PX{text}100")) else {
            panic!("{text}");
        };
        assert_eq!(c.op, op);
        assert_eq!(c.left, Operand::Read(command("P", Address::Axis(Axis::X))));
    }
}

#[test]
fn assignments_to_variables_take_one_operation() {
    assert_eq!(
        action("V1=MSTX&1024"),
        Action::Let {
            variable: 1,
            value: Expr::Binary {
                left: Operand::Read(command("MST", Address::Axis(Axis::X))),
                op: BinaryOp::And,
                right: Operand::Number(1024)
            }
        }
    );
    assert_eq!(
        action("V1=~V2"),
        Action::Let {
            variable: 1,
            value: Expr::Not(Operand::Variable(2))
        }
    );
    assert_eq!(
        action("V1 = -5"),
        Action::Let {
            variable: 1,
            value: Expr::Operand(Operand::Number(-5))
        }
    );
    assert_eq!(
        action("V1=V2--5"),
        Action::Let {
            variable: 1,
            value: Expr::Binary {
                left: Operand::Variable(2),
                op: BinaryOp::Subtract,
                right: Operand::Number(-5)
            }
        }
    );
    for op in BinaryOp::ALL {
        let Action::Let {
            value: Expr::Binary { op: got, .. },
            ..
        } = action(&format!("V1=V2{op}3"))
        else {
            panic!("{op}");
        };
        assert_eq!(got, op);
    }
}

#[test]
fn commands_are_set_from_a_number_or_a_variable() {
    assert_eq!(
        action("HSPD=20000"),
        Action::Set {
            command: command("HSPD", Address::None),
            value: Value::Number(20000)
        }
    );
    assert_eq!(
        action("IO = 0"),
        Action::Set {
            command: command("IO", Address::None),
            value: Value::Number(0)
        }
    );
    assert_eq!(
        action("DO1=V3"),
        Action::Set {
            command: command("DO", Address::Index(1)),
            value: Value::Variable(3)
        }
    );
    assert_eq!(
        action("SR0=1"),
        Action::Set {
            command: command("SR", Address::Index(0)),
            value: Value::Number(1)
        }
    );
    assert_eq!(
        action("PX=-134217728"),
        Action::Set {
            command: command("P", Address::Axis(Axis::X)),
            value: Value::Number(-134_217_728)
        }
    );
    assert_eq!(action("DELAY=V3"), Action::Delay(Value::Variable(3)));
    assert_eq!(action("DELAY=3000"), Action::Delay(Value::Number(3000)));
}

#[test]
fn motion_statements() {
    assert_eq!(action("WAITY"), Action::Wait(Axis::Y));
    assert_eq!(
        action("ECLEARX"),
        Action::Do(command("ECLEAR", Address::Axis(Axis::X)))
    );
    assert_eq!(action("ABORT"), Action::Do(command("ABORT", Address::None)));
    assert_eq!(
        action("XV1"),
        Action::Move(vec![Target {
            axis: Axis::X,
            value: Value::Variable(1)
        }])
    );
    assert_eq!(
        action("X-20000Y15000"),
        Action::Move(vec![
            Target {
                axis: Axis::X,
                value: Value::Number(-20000)
            },
            Target {
                axis: Axis::Y,
                value: Value::Number(15000)
            }
        ])
    );
    assert_eq!(
        action("HOMEX-6"),
        Action::Home {
            axis: Axis::X,
            direction: Direction::Minus,
            mode: 6
        }
    );
    assert_eq!(
        action("JOGU+"),
        Action::Jog {
            axis: Axis::U,
            direction: Direction::Plus
        }
    );
    assert_eq!(
        action("ZMOVEZ-"),
        Action::SameInAscii(Cmd4crCommand::ZMove {
            axis: Axis::Z,
            direction: Direction::Minus
        })
    );
    assert_eq!(
        action("ARCXYN288899:267403:95000"),
        Action::SameInAscii(Cmd4crCommand::Arc {
            axes: [Axis::X, Axis::Y],
            rotation: Rotation::CounterClockwise,
            centre: [288_899, 267_403],
            angle: 95000
        })
    );
    assert_eq!(
        action("CIRXZP-1000:1000"),
        Action::SameInAscii(Cmd4crCommand::Circle {
            axes: [Axis::X, Axis::Z],
            rotation: Rotation::Clockwise,
            centre: [-1000, 1000]
        })
    );
    assert_eq!(
        action("CIRTN1:2:3"),
        Action::SameInAscii(Cmd4crCommand::HelicalCircle {
            rotation: Rotation::CounterClockwise,
            centre: [1, 2],
            z: 3
        })
    );
    assert_eq!(
        action("ARCTP1:2:3:-4"),
        Action::SameInAscii(Cmd4crCommand::HelicalArc {
            rotation: Rotation::Clockwise,
            centre: [1, 2],
            angle: 3,
            z: -4
        })
    );
}

#[test]
fn every_statement_prints_back_as_source_that_parses_the_same() {
    for line in [
        "PRG 2",
        "END",
        "SUB 31",
        "ENDSUB",
        "IF DI1=1",
        "ELSEIF V2!=0",
        "ELSE",
        "ENDIF",
        "WHILE V30<10",
        "ENDWHILE",
        "GOSUB 7",
        "V1=MSTX&1024",
        "V1=~V2",
        "V1=V2%-5",
        "HSPDX=5000",
        "IO1=1",
        "SR3=0",
        "DELAY=700",
        "WAITX",
        "ABORTX",
        "BUFON",
        "X1000Y-100Z100U5",
        "XV1",
        "JOGX-",
        "HOMEY+12",
        "ZMOVEU+",
        "CIRXYP487659:562431",
        "ARCXYN288899:267403:95000",
        "CIRTP1:-2:3",
        "ARCTN1:2:3:4",
    ] {
        let statement = parsed(line);
        assert_eq!(statement.to_string(), line);
        assert_eq!(parsed(&statement.to_string()), statement);
    }
}

#[test]
fn lower_case_and_ascii_only_words_get_a_hint() {
    let e = error("hspd=100");
    assert_eq!(e.code, ErrorCode::UnknownError);
    assert!(
        e.detail.contains("capitals (`HSPD=100`)") || e.detail.contains("`HSPD`"),
        "{e:?}"
    );
    let e = error("CLRX");
    assert_eq!(e.code, ErrorCode::UnknownError);
    assert!(
        e.detail.ends_with("in a program write ECLEAR[axis]"),
        "{e:?}"
    );
    let e = error("POLX=7");
    assert!(
        e.detail.contains("standalone programs do not have"),
        "{e:?}"
    );
    assert_eq!(code("10=64"), ErrorCode::UnknownError);
    assert_eq!(code("é"), ErrorCode::UnknownError);
}

#[test]
fn indexes_outside_their_range_are_bit_errors_except_programs() {
    assert_eq!(code("DI5"), ErrorCode::BitError);
    assert_eq!(code("V1=DI5"), ErrorCode::BitError);
    assert_eq!(code("IO33=1"), ErrorCode::BitError);
    assert_eq!(code("PWM3=50"), ErrorCode::BitError);
    assert_eq!(code("AI=1"), ErrorCode::BitError);
    assert_eq!(code("SR4=1"), ErrorCode::ErrorPrg);
    assert_eq!(code("SR=1"), ErrorCode::ErrorPrgNumber);
    let e = error("  DO10=1");
    assert_eq!((e.column, e.detail.as_str()), (3, "`DO10`: DO has 1-4"));
}

#[test]
fn an_axis_is_required_where_the_command_has_only_axis_forms() {
    let e = error("V1=MST");
    assert_eq!(e.code, ErrorCode::UnknownError);
    assert_eq!(e.detail, "`MST` needs an axis: MSTX, MSTY, MSTZ or MSTU");
    assert_eq!(code("WAIT"), ErrorCode::UnknownError);
    // ABS has no axis form, so ABSX is no word at all.
    assert_eq!(code("ABSX"), ErrorCode::UnknownError);
}

#[test]
fn values_outside_their_range_are_assignment_errors() {
    for line in [
        "DO1=2",
        "EO=16",
        "HSPD=0",
        "HSPD=6553501",
        "PWM1=0",
        "SR0=4",
        "SSPDMX=8",
        "HOMEX-13",
        "X200000000",
        "V1=2147483648",
        "DELAY=-5",
        "CIRXYP200000000:0",
        "IO=4294967296",
    ] {
        assert_eq!(code(line), ErrorCode::AssignmentError, "{line}");
    }
    assert_eq!(error("HSPD=0").detail, "HSPD=0: HSPD takes 1..6553500 pps");
    // Per-axis speeds take 0: "use the global value" (§2.1.4).
    assert!(matches!(action("HSPDX=0"), Action::Set { .. }));
    assert!(matches!(action("IO=4294967295"), Action::Set { .. }));
}

#[test]
fn reading_and_writing_where_the_command_does_not_allow_it() {
    assert_eq!(code("MSTX=0"), ErrorCode::EqualsError);
    assert_eq!(code("DI1"), ErrorCode::Error);
    assert_eq!(code("V1=SSPDX"), ErrorCode::AssignmentError);
    assert_eq!(code("IF SSPDX=1"), ErrorCode::OperationArgumentError);
    assert_eq!(code("IF ABS=1"), ErrorCode::OperationArgumentError);
    assert_eq!(code("V1=ABS+1"), ErrorCode::OperationArgumentError);
    assert_eq!(code("HSPD=ABS"), ErrorCode::AssignmentError);
    assert_eq!(code("HSPD=V1+1"), ErrorCode::NotNumberOrVar);
    assert_eq!(code("HSPD=~V1"), ErrorCode::NotNumberOrVar);
    assert_eq!(code("HSPD="), ErrorCode::AssignmentError);
    assert_eq!(code("V1="), ErrorCode::AssignmentError);
    assert_eq!(code("V1=V2+"), ErrorCode::OperationArgumentError);
}

#[test]
fn missing_equals_and_malformed_assignments() {
    assert_eq!(code("HSPD"), ErrorCode::MissingEquals);
    assert_eq!(code("HSPD1000"), ErrorCode::MissingEquals);
    assert_eq!(code("V1"), ErrorCode::MissingEquals);
    assert_eq!(code("DELAY 100"), ErrorCode::MissingEquals);
    assert_eq!(code("HSPD+1=5"), ErrorCode::EqualsError);
    assert_eq!(code("HSPD==5"), ErrorCode::Error);
    assert_eq!(code("V=1"), ErrorCode::VarRangeError);
    assert_eq!(code("V1=V150"), ErrorCode::VarRangeError);
    assert_eq!(code("XV100"), ErrorCode::VarRangeError);
    assert_eq!(code("DELAY=V100"), ErrorCode::VarRangeError);
    assert_eq!(code("V1=V2=V3"), ErrorCode::TokenError);
}

#[test]
fn more_than_one_operation_is_a_token_error() {
    let e = error("V1=V2+V3+V4");
    assert_eq!(e.code, ErrorCode::TokenError);
    assert_eq!(e.column, 9);
    assert_eq!(code("V1=V2<V3"), ErrorCode::TokenError);
    assert_eq!(code("IF V1+1=2"), ErrorCode::TokenError);
    assert_eq!(code("IF V1=2+1"), ErrorCode::TokenError);
    assert_eq!(code("DELAY=100 200"), ErrorCode::TokenError);
}

#[test]
fn malformed_conditions() {
    assert_eq!(code("IF"), ErrorCode::Error);
    assert_eq!(code("WHILE V1"), ErrorCode::Error);
    assert_eq!(code("IF V1 V2"), ErrorCode::Error);
    assert_eq!(code("IF V1=="), ErrorCode::Error);
    assert_eq!(code("IF V1<"), ErrorCode::Error);
    assert_eq!(code("IF V1=1 X"), ErrorCode::TokenError);
}

#[test]
fn malformed_motion() {
    assert_eq!(code("JOGX"), ErrorCode::TokenError);
    assert_eq!(code("JOGX +"), ErrorCode::TokenError);
    assert_eq!(code("HOMEX-"), ErrorCode::TokenError);
    assert_eq!(code("HOMEX6"), ErrorCode::TokenError);
    assert_eq!(code("X"), ErrorCode::TokenError);
    assert_eq!(code("X 1000"), ErrorCode::TokenError);
    assert_eq!(code("X-"), ErrorCode::TokenError);
    assert_eq!(code("X1000 Y2000"), ErrorCode::TokenError);
    assert_eq!(code("X1000X5"), ErrorCode::Error);
    assert_eq!(code("CIRXXP1:2"), ErrorCode::Error);
    assert_eq!(code("CIRXYP1"), ErrorCode::TokenError);
    assert_eq!(code("CIRXYP1:V2"), ErrorCode::TokenError);
    // A V right after the sense letter makes one unknown word.
    assert_eq!(code("CIRXYPV1:2"), ErrorCode::UnknownError);
    assert_eq!(code("ARCXYP1:2"), ErrorCode::TokenError);
    assert_eq!(code("CIR"), ErrorCode::TokenError);
    assert_eq!(code("ABS 5"), ErrorCode::TokenError);
    assert_eq!(code("END X"), ErrorCode::TokenError);
    assert_eq!(code("WAITX Y"), ErrorCode::TokenError);
}

#[test]
fn block_numbers() {
    assert_eq!(code("PRG 4"), ErrorCode::ErrorPrg);
    assert_eq!(code("PRG 99999999999999999999"), ErrorCode::ErrorPrg);
    assert_eq!(code("PRG"), ErrorCode::ErrorPrgNumber);
    assert_eq!(code("PRG -1"), ErrorCode::ErrorPrgNumber);
    assert_eq!(code("PRG 1 2"), ErrorCode::TokenError);
    assert_eq!(code("SUB 32"), ErrorCode::ErrorSub);
    assert_eq!(code("SUB X"), ErrorCode::ErrorSubNumber);
    assert_eq!(code("GOSUB 32"), ErrorCode::ErrorGosub);
    assert_eq!(code("GOSUB V1"), ErrorCode::ErrorSubNumber);
    // The keyword is kept for the block structure, whatever follows it.
    assert_eq!(
        parse_line("PRG XI3").and_then(|p| p.keyword),
        Some(Keyword::Prg)
    );
}

#[test]
fn messages_quote_what_was_written() {
    assert_eq!(
        error("GOSUB DI1").detail,
        "`DI1` is not a subroutine number: write GOSUB and a number 0-31"
    );
    assert_eq!(
        error("IF V1+1=2").detail,
        "`V1+1=2`: a condition compares two values (Table 2-30); compute the operation into a variable first"
    );
    assert_eq!(
        error("V2+1=V3").detail,
        "the left of `=` must be one variable or command, not `V2+1`"
    );
    assert_eq!(
        error("DO=PX").detail,
        "`DO=PX`: a command is set from a number or a variable; read PX into a variable first (V1=PX, then DO=V1)"
    );
    assert_eq!(
        error("PRG 200 X").detail,
        "PRG 200: program numbers are 0-3"
    );
    let e = error("DELAY=-5");
    assert_eq!(
        (e.column, e.detail.as_str()),
        (7, "DELAY=-5: a delay takes 0..2147483647 ms")
    );
}
