//! Property tests of the TMCL typed commands and the console line syntax:
//! encode/decode and format/parse round trips, and no panics on any input.

use axterm::protocol::tmcl::catalog::COMMANDS;
use axterm::protocol::tmcl::{
    CalcFamily, CalcOp, ClearFlag, Command, Condition, EventMode, MoveMode, OperandCode, Request,
    RfsAction, StatusQuery, VersionFormat, WaitCondition, format_command, parse_line,
    parse_line_with, parse_syntax, validate,
};
use proptest::prelude::*;
use proptest::sample::select;
use proptest::strategy::Union;

fn code<T: OperandCode + std::fmt::Debug>() -> impl Strategy<Value = T> {
    select(T::ALL)
}

fn calc_op(family: CalcFamily) -> impl Strategy<Value = CalcOp> {
    select(family.ops())
}

/// Every typed command (not [`Command::Raw`]), with any field values.
fn typed_command() -> impl Strategy<Value = Command> {
    use Command::*;
    let b = any::<u8>;
    let v = any::<i32>;
    let arms: Vec<BoxedStrategy<Command>> = vec![
        (b(), v())
            .prop_map(|(motor, velocity)| Ror { motor, velocity })
            .boxed(),
        (b(), v())
            .prop_map(|(motor, velocity)| Rol { motor, velocity })
            .boxed(),
        b().prop_map(|motor| Mst { motor }).boxed(),
        (code::<MoveMode>(), b(), v())
            .prop_map(|(mode, motor, target)| Mvp {
                mode,
                motor,
                target,
            })
            .boxed(),
        (b(), b(), v())
            .prop_map(|(param, motor, value)| Sap {
                param,
                motor,
                value,
            })
            .boxed(),
        (b(), b())
            .prop_map(|(param, motor)| Gap { param, motor })
            .boxed(),
        (b(), b())
            .prop_map(|(param, motor)| Stap { param, motor })
            .boxed(),
        (b(), b())
            .prop_map(|(param, motor)| Rsap { param, motor })
            .boxed(),
        (b(), b(), v())
            .prop_map(|(param, bank, value)| Sgp { param, bank, value })
            .boxed(),
        (b(), b())
            .prop_map(|(param, bank)| Ggp { param, bank })
            .boxed(),
        (b(), b())
            .prop_map(|(param, bank)| Stgp { param, bank })
            .boxed(),
        (b(), b())
            .prop_map(|(param, bank)| Rsgp { param, bank })
            .boxed(),
        (code::<RfsAction>(), b())
            .prop_map(|(action, motor)| Rfs { action, motor })
            .boxed(),
        (b(), b(), v())
            .prop_map(|(port, bank, value)| Sio { port, bank, value })
            .boxed(),
        (b(), b())
            .prop_map(|(port, bank)| Gio { port, bank })
            .boxed(),
        (calc_op(CalcFamily::Accumulator), v())
            .prop_map(|(op, operand)| Calc { op, operand })
            .boxed(),
        v().prop_map(|value| Comp { value }).boxed(),
        (code::<Condition>(), v())
            .prop_map(|(condition, address)| Jc { condition, address })
            .boxed(),
        v().prop_map(|address| Ja { address }).boxed(),
        v().prop_map(|address| Csub { address }).boxed(),
        Just(Rsub).boxed(),
        b().prop_map(|interrupt| Ei { interrupt }).boxed(),
        b().prop_map(|interrupt| Di { interrupt }).boxed(),
        (code::<WaitCondition>(), b(), v())
            .prop_map(|(condition, motor, ticks)| Wait {
                condition,
                motor,
                ticks,
            })
            .boxed(),
        Just(Stop).boxed(),
        (b(), b(), v())
            .prop_map(|(coordinate, motor, position)| Sco {
                coordinate,
                motor,
                position,
            })
            .boxed(),
        (b(), b())
            .prop_map(|(coordinate, motor)| Gco { coordinate, motor })
            .boxed(),
        (b(), b())
            .prop_map(|(coordinate, motor)| Cco { coordinate, motor })
            .boxed(),
        calc_op(CalcFamily::XRegister)
            .prop_map(|op| Calcx { op })
            .boxed(),
        (b(), b())
            .prop_map(|(param, motor)| Aap { param, motor })
            .boxed(),
        (b(), b())
            .prop_map(|(param, bank)| Agp { param, bank })
            .boxed(),
        code::<ClearFlag>().prop_map(|flag| Cle { flag }).boxed(),
        (b(), v())
            .prop_map(|(interrupt, address)| Vect { interrupt, address })
            .boxed(),
        Just(Reti).boxed(),
        (b(), b())
            .prop_map(|(coordinate, motor)| Aco { coordinate, motor })
            .boxed(),
        (calc_op(CalcFamily::UserVariable), b(), b())
            .prop_map(|(op, var1, var2)| Calcvv { op, var1, var2 })
            .boxed(),
        (calc_op(CalcFamily::UserVariable), b())
            .prop_map(|(op, var)| Calcva { op, var })
            .boxed(),
        (calc_op(CalcFamily::UserVariable), b())
            .prop_map(|(op, var)| Calcav { op, var })
            .boxed(),
        (calc_op(CalcFamily::UserVariable), b())
            .prop_map(|(op, var)| Calcvx { op, var })
            .boxed(),
        (calc_op(CalcFamily::UserVariable), b())
            .prop_map(|(op, var)| Calcxv { op, var })
            .boxed(),
        (calc_op(CalcFamily::DirectValue), b(), v())
            .prop_map(|(op, var, value)| Calcv { op, var, value })
            .boxed(),
        (code::<MoveMode>(), b())
            .prop_map(|(mode, motor)| Mvpa { mode, motor })
            .boxed(),
        v().prop_map(|address| Rst { address }).boxed(),
        (b(), v())
            .prop_map(|(var, address)| Djnz { var, address })
            .boxed(),
        b().prop_map(|motor| Rola { motor }).boxed(),
        b().prop_map(|motor| Rora { motor }).boxed(),
        v().prop_map(|value| Siv { value }).boxed(),
        Just(Giv).boxed(),
        Just(Aiv).boxed(),
        (0u8..8, b(), b(), v())
            .prop_map(|(number, kind, motor_bank, value)| UserFunction {
                number,
                kind,
                motor_bank,
                value,
            })
            .boxed(),
        (code::<Condition>(), v())
            .prop_map(|(condition, address)| Call { condition, address })
            .boxed(),
        Just(StopApplication).boxed(),
        proptest::option::of(v())
            .prop_map(|start| RunApplication { start })
            .boxed(),
        Just(StepApplication).boxed(),
        Just(ResetApplication).boxed(),
        v().prop_map(|address| EnterDownload { address }).boxed(),
        Just(ExitDownload).boxed(),
        v().prop_map(|address| ReadMemory { address }).boxed(),
        code::<StatusQuery>()
            .prop_map(|query| ApplicationStatus { query })
            .boxed(),
        code::<VersionFormat>()
            .prop_map(|format| FirmwareVersion { format })
            .boxed(),
        Just(FactoryReset).boxed(),
        (code::<EventMode>(), v())
            .prop_map(|(mode, motor_mask)| TargetReachedEvent { mode, motor_mask })
            .boxed(),
        Just(SoftwareReset).boxed(),
    ];
    Union::new(arms)
}

fn raw_command() -> impl Strategy<Value = Command> {
    any::<(u8, u8, u8, i32)>().prop_map(|(command, kind, motor_bank, value)| Command::Raw {
        command,
        kind,
        motor_bank,
        value,
    })
}

fn any_request() -> impl Strategy<Value = Request> {
    any::<(u8, u8, u8, u8, i32)>().prop_map(|(address, command, kind, motor_bank, value)| Request {
        address,
        command,
        kind,
        motor_bank,
        value,
    })
}

/// Lines that look like console lines: a catalogue name or a number, then
/// operands drawn from symbols, numbers in several notations, and junk.
fn line_like() -> impl Strategy<Value = String> {
    let names: Vec<&'static str> = COMMANDS.iter().map(|c| c.name).collect();
    let head = prop_oneof![
        select(names).prop_map(str::to_string),
        any::<i64>().prop_map(|n| n.to_string()),
        "[a-zA-Z]{1,8}",
    ];
    let operand = prop_oneof![
        any::<i64>().prop_map(|n| n.to_string()),
        any::<u32>().prop_map(|n| format!("0x{n:X}")),
        any::<u64>().prop_map(|n| format!("${n:x}")),
        select(vec![
            "ABS", "rel", "COORD", "ZE", "EPO", "TICKS", "SWAP", "COMP", "LOAD", "ALL", "ESD",
            "PC", "X", "BINARY", "ONCE", "ALWAYS", "Loop", "-", "+", "$", "0x", "//", "€", "",
        ])
        .prop_map(str::to_string),
        "\\PC{0,6}",
    ];
    let separator = select(vec![" ", ",", ", ", " , ", ",,", "\t", ""]);
    (head, proptest::collection::vec((separator, operand), 0..6)).prop_map(|(head, rest)| {
        let mut line = head;
        for (sep, op) in rest {
            line.push_str(sep);
            line.push_str(&op);
        }
        line
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn typed_commands_survive_encode_and_decode(command in typed_command(), address in any::<u8>()) {
        let request = command.to_request(address);
        prop_assert_eq!(request.address, address);
        prop_assert_eq!(Command::from_request(&request), command);
        let bytes = request.to_bytes();
        prop_assert_eq!(Request::from_bytes(&bytes), Ok(request));
    }

    #[test]
    fn raw_commands_keep_their_frame(command in raw_command()) {
        let request = command.to_request(1);
        prop_assert_eq!(Command::from_request(&request).to_request(1), request);
    }

    #[test]
    fn every_frame_decodes_and_reencodes_unchanged(request in any_request()) {
        let command = Command::from_request(&request);
        prop_assert_eq!(command.to_request(request.address), request);
    }

    #[test]
    fn formatted_commands_parse_back(command in prop_oneof![typed_command(), raw_command()]) {
        let line = format_command(&command);
        prop_assert_eq!(parse_syntax(&line, None), Ok(command), "{}", line);
    }

    #[test]
    fn decoded_frames_format_and_parse_back(request in any_request()) {
        let command = Command::from_request(&request);
        let line = format_command(&command);
        prop_assert_eq!(parse_syntax(&line, None), Ok(command), "{}", line);
    }

    /// §5.4: timer periods print unsigned and parse back to the same bits.
    /// (Rarely drawn by `typed_command`: bank 3, parameters 0..2.)
    #[test]
    fn timer_periods_format_unsigned_and_parse_back(param in 0u8..=2, value in any::<i32>()) {
        let command = Command::Sgp { param, bank: 3, value };
        let line = format_command(&command);
        prop_assert_eq!(&line, &format!("SGP {param}, 3, {}", value as u32));
        prop_assert_eq!(parse_line(&line), Ok(command), "{}", line);
    }

    #[test]
    fn every_timer_period_encodes_its_bits(period in any::<u32>()) {
        let command = parse_line(&format!("SGP 1, 3, {period}"));
        prop_assert_eq!(command.map(|c| c.to_request(1).value), Ok(period as i32));
    }

    #[test]
    fn validation_never_panics(command in prop_oneof![typed_command(), raw_command()]) {
        let _ = validate(&command);
    }

    #[test]
    fn parser_never_panics_on_arbitrary_text(line in any::<String>()) {
        let _ = parse_syntax(&line, None);
        let _ = parse_line(&line);
    }

    #[test]
    fn parser_never_panics_on_line_like_text(line in line_like(), constant in any::<i64>()) {
        let symbols = move |name: &str| name.len().is_multiple_of(2).then_some(constant);
        let _ = parse_line(&line);
        let _ = parse_line_with(&line, &symbols);
        if let Ok(command) = parse_syntax(&line, Some(&symbols)) {
            // Whatever parses, formats to a line that parses to the same command.
            let canonical = format_command(&command);
            prop_assert_eq!(parse_syntax(&canonical, None), Ok(command), "{} → {}", line, canonical);
        }
    }
}
