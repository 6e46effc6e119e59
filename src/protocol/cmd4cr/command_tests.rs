use super::*;

fn parse(text: &str) -> Cmd4crCommand {
    parse_command(text).unwrap_or_else(|e| panic!("{text}: {e}"))
}

fn canonical(text: &str) -> String {
    parse(text).to_string()
}

fn error(text: &str) -> CommandError {
    match parse_command(text) {
        Ok(command) => panic!("{text} parsed as {command:?}"),
        Err(e) => e,
    }
}

#[test]
fn reads_writes_and_actions_of_every_selector() {
    assert_eq!(
        parse("PX"),
        Cmd4crCommand::Read {
            register: Register::P,
            selector: Selector::Axis(Axis::X)
        }
    );
    assert_eq!(
        parse("HSPDX=5000"),
        Cmd4crCommand::Write {
            register: Register::Hspd,
            selector: Selector::Axis(Axis::X),
            value: 5000
        }
    );
    assert_eq!(
        parse("HSPD=5000"),
        Cmd4crCommand::Write {
            register: Register::Hspd,
            selector: Selector::All,
            value: 5000
        }
    );
    assert_eq!(
        parse("SACTRL0=1"),
        Cmd4crCommand::Write {
            register: Register::Sactrl,
            selector: Selector::Index(0),
            value: 1
        }
    );
    assert_eq!(
        parse("STOP"),
        Cmd4crCommand::Action {
            action: Action::Stop,
            selector: Selector::All
        }
    );
    assert_eq!(
        parse("GS31"),
        Cmd4crCommand::Action {
            action: Action::CallSub,
            selector: Selector::Index(31)
        }
    );
    assert_eq!(
        parse("DI"),
        Cmd4crCommand::Read {
            register: Register::Di,
            selector: Selector::All
        }
    );
    assert_eq!(
        parse("V99=-2147483648"),
        Cmd4crCommand::Write {
            register: Register::V,
            selector: Selector::Index(99),
            value: -2_147_483_648
        }
    );
}

#[test]
fn motion_commands_have_their_own_syntax() {
    assert_eq!(
        parse("X1000Y-2000"),
        Cmd4crCommand::Move {
            targets: [Some(1000), Some(-2000), None, None]
        }
    );
    assert_eq!(
        parse("JX-"),
        Cmd4crCommand::Jog {
            axis: Axis::X,
            direction: Direction::Minus
        }
    );
    assert_eq!(
        parse("HY-1"),
        Cmd4crCommand::Home {
            axis: Axis::Y,
            direction: Direction::Minus,
            mode: 1
        }
    );
    assert_eq!(
        parse("ZMOVEU+"),
        Cmd4crCommand::ZMove {
            axis: Axis::U,
            direction: Direction::Plus
        }
    );
    assert_eq!(
        parse("TX-500"),
        Cmd4crCommand::NewTarget {
            axis: Axis::X,
            target: -500
        }
    );
    assert_eq!(
        parse("CIRXZP1000:1000"),
        Cmd4crCommand::Circle {
            axes: [Axis::X, Axis::Z],
            rotation: Rotation::Clockwise,
            centre: [1000, 1000]
        }
    );
    assert_eq!(
        parse("ARCXYN0:0:90000"),
        Cmd4crCommand::Arc {
            axes: [Axis::X, Axis::Y],
            rotation: Rotation::CounterClockwise,
            centre: [0, 0],
            angle: 90000
        }
    );
    assert_eq!(
        parse("CIRTN5:-5:300"),
        Cmd4crCommand::HelicalCircle {
            rotation: Rotation::CounterClockwise,
            centre: [5, -5],
            z: 300
        }
    );
    assert_eq!(
        parse("ARCTP1:2:45000:-7"),
        Cmd4crCommand::HelicalArc {
            rotation: Rotation::Clockwise,
            centre: [1, 2],
            angle: 45000,
            z: -7
        }
    );
    assert_eq!(
        parse("I1000:2000:3000:5000"),
        Cmd4crCommand::BufferMove {
            target: [1000, 2000, 3000],
            speed: 5000
        }
    );
}

#[test]
fn the_canonical_text_is_upper_case_without_blanks() {
    assert_eq!(canonical(" hspdx = 5000 "), "HSPDX=5000");
    assert_eq!(canonical("y15000 x-20000"), "X-20000Y15000");
    assert_eq!(canonical("X+100"), "X100");
    assert_eq!(canonical("ID=2"), "ID=02");
    assert_eq!(canonical("SLRX=1.5"), "SLRX=1.5");
    assert_eq!(canonical("SLRX=0.001"), "SLRX=0.001");
    assert_eq!(canonical("SLRY=999.999"), "SLRY=999.999");
    assert_eq!(canonical("SLRZ=2"), "SLRZ=2");
    assert_eq!(canonical("hx+0"), "HX+0");
    assert_eq!(canonical("DI01"), "DI1");
}

#[test]
fn longest_keyword_first() {
    assert_eq!(
        parse("EXST=1"),
        Cmd4crCommand::Write {
            register: Register::Exst,
            selector: Selector::All,
            value: 1
        }
    );
    assert_eq!(
        parse("EX"),
        Cmd4crCommand::Read {
            register: Register::E,
            selector: Selector::Axis(Axis::X)
        }
    );
    assert!(matches!(
        parse("SSPDMX=2"),
        Cmd4crCommand::Write {
            register: Register::Sspdm,
            ..
        }
    ));
    assert!(matches!(
        parse("STORE"),
        Cmd4crCommand::Action {
            action: Action::Store,
            ..
        }
    ));
    assert!(matches!(
        parse("ZCNTX"),
        Cmd4crCommand::Read {
            register: Register::Zcnt,
            ..
        }
    ));
    assert!(matches!(parse("Z-5"), Cmd4crCommand::Move { .. }));
    assert!(matches!(
        parse("INC"),
        Cmd4crCommand::Action {
            action: Action::Inc,
            ..
        }
    ));
    assert!(matches!(
        parse("IO19=1"),
        Cmd4crCommand::Write {
            register: Register::Io,
            selector: Selector::Index(19),
            ..
        }
    ));
}

#[test]
fn errors_say_what_is_wrong() {
    assert_eq!(error(""), CommandError::Empty);
    assert!(matches!(error("FOO"), CommandError::Unknown(t) if t == "FOO"));
    assert!(matches!(error("EXS"), CommandError::Unknown(_)));
    let missing = error("SYNO").to_string();
    assert!(
        missing.contains("needs an axis") && missing.contains("SYNO[axis]"),
        "{missing}"
    );
    assert!(matches!(
        error("SSPDM=2"),
        CommandError::MissingAxis {
            keyword: "SSPDM",
            ..
        }
    ));
    assert!(matches!(error("HSPDW"), CommandError::NotAnAxis { .. }));
    assert!(matches!(error("DI5"), CommandError::InvalidIndex { .. }));
    assert!(matches!(error("V100=1"), CommandError::InvalidIndex { .. }));
    assert!(matches!(error("SACTRL"), CommandError::MissingIndex { .. }));
    let hint = error("SAP1").to_string();
    assert!(hint.contains("SAP=1"), "{hint}");
    assert!(matches!(error("HSPD5000"), CommandError::NoIndex { .. }));
    assert!(matches!(error("MSTX=3"), CommandError::ReadOnly { .. }));
    assert!(matches!(error("SSPDX"), CommandError::WriteOnly { .. }));
    assert!(matches!(error("STOP=1"), CommandError::TakesNoValue { .. }));
    assert!(matches!(error("HSPD="), CommandError::MissingValue { .. }));
    assert!(matches!(
        error("HSPD=fast"),
        CommandError::NotANumber { .. }
    ));
    let range = error("EO=16").to_string();
    assert!(range.contains("16") && range.contains("0..15"), "{range}");
    assert!(matches!(error("SLRX=0"), CommandError::OutOfRange { .. }));
    assert!(matches!(
        error("SLRX=1.2345"),
        CommandError::NotANumber { .. }
    ));
    assert!(matches!(error("HX+13"), CommandError::OutOfRange { .. }));
    assert!(error("H-1").to_string().contains("H[axis][+/-][mode]"));
    assert!(matches!(error("JX"), CommandError::Syntax { .. }));
    assert!(matches!(error("JX+1"), CommandError::Syntax { .. }));
    assert!(matches!(error("X1000X5"), CommandError::Syntax { .. }));
    assert!(matches!(
        error("X134217728"),
        CommandError::OutOfRange { .. }
    ));
    assert!(matches!(error("CIRXXP1:1"), CommandError::Syntax { .. }));
    assert!(matches!(error("CIRXYP1"), CommandError::Syntax { .. }));
    assert!(matches!(
        error("ARCXYP0:0:360001"),
        CommandError::OutOfRange { .. }
    ));
    assert!(matches!(error("I1:2:3"), CommandError::Syntax { .. }));
    assert!(matches!(error("X=5"), CommandError::Unknown(_)));
    assert!(matches!(error("JX+=1"), CommandError::Syntax { .. }));
    assert!(matches!(error("PXé"), CommandError::Unknown(_)));
    let framed = error("@01PX");
    assert!(
        framed.to_string().contains("without `@` and the ID"),
        "{framed}"
    );
    assert_eq!(framed.reply(), ErrorReply::UnknownCommand("@01PX".into()));
}

#[test]
fn only_an_index_out_of_range_is_invalid_index() {
    assert_eq!(
        error("DO5=1").reply(),
        ErrorReply::Known(ErrorCode::InvalidIndex)
    );
    assert_eq!(
        error("foo").reply(),
        ErrorReply::UnknownCommand("foo".into())
    );
    assert_eq!(
        error("EO=16").reply(),
        ErrorReply::UnknownCommand("EO=16".into())
    );
}

#[test]
fn numbers_parse_as_the_manual_writes_them() {
    assert_eq!(parse_integer("-20000"), Some(-20000));
    assert_eq!(parse_integer("+5"), Some(5));
    assert_eq!(parse_integer("0x10"), None);
    assert_eq!(parse_integer("-"), None);
    assert_eq!(parse_integer("99999999999999999999"), None);
    assert_eq!(parse_thousandths("1.5"), Some(1500));
    assert_eq!(parse_thousandths(".25"), Some(250));
    assert_eq!(parse_thousandths("-0.001"), Some(-1));
    assert_eq!(parse_thousandths("3"), Some(3000));
    assert_eq!(parse_thousandths("."), None);
    assert_eq!(parse_thousandths("1.2.3"), None);
    assert_eq!(format_value(1500, Format::Thousandths), "1.5");
    assert_eq!(format_value(-1, Format::Thousandths), "-0.001");
    assert_eq!(format_value(7, Format::TwoDigits), "07");
}

#[test]
fn every_row_has_a_command_that_round_trips() {
    for row in COMMANDS {
        let selector = match row.form {
            Form::Bare => "".to_string(),
            Form::Axis => "Y".to_string(),
            Form::Index { last, .. } => last.to_string(),
            Form::Motion => continue,
        };
        let base = format!("{}{selector}", row.keyword);
        let text = match (row.access, row.values) {
            (crate::protocol::cmd4cr::catalog::Access::Write, Some(v)) => {
                format!("{base}={}", format_value(v.max, v.format))
            }
            _ => base,
        };
        let command = parse(&text);
        assert_eq!(command.spec(), row, "{text}");
        assert_eq!(command.to_string(), text);
        assert_eq!(parse(&command.to_string()), command);
    }
}
