//! Property tests of the A-Script checker: generated statements print and
//! parse back to themselves; generated well-nested programs compile with
//! every jump inside the program and every block entry on its own line; no
//! line or source, however broken, makes the lexer, parser, checker or
//! highlighter panic, and the highlighter's pieces always cover the line.

use axterm::protocol::cmd4cr::ascript::{
    Action, Address, Axis, BinaryOp, COMMANDS, Command, Comparison, Condition, Direction, Expr, Op,
    Operand, Rotation, Shape, Statement, Target, VARIABLES, Value, ascii_command, check, compile,
    parse_statement, tokens,
};
use axterm::protocol::cmd4cr::catalog::Form;
use axterm::protocol::cmd4cr::{Cmd4crCommand, parse_command};
use proptest::prelude::*;
use proptest::sample::select;

fn axis() -> impl Strategy<Value = Axis> {
    select(Axis::ALL.to_vec())
}

/// Every form of every command the table has, addressed in range.
fn commands(keep: fn(&Command) -> bool) -> Vec<Command> {
    let mut all = Vec::new();
    for info in COMMANDS {
        let addresses: Vec<Address> = match info.form {
            Form::Bare => vec![Address::None],
            Form::Axis => Axis::ALL.into_iter().map(Address::Axis).collect(),
            Form::Index { first, last } => (first..=last).map(Address::Index).collect(),
            Form::Motion => vec![],
        };
        for address in addresses {
            if let Some(command) = Command::new(info.name, address)
                && keep(&command)
            {
                all.push(command);
            }
        }
    }
    all
}

fn operand() -> impl Strategy<Value = Operand> {
    prop_oneof![
        any::<i32>().prop_map(|n| Operand::Number(n.into())),
        (0u8..100).prop_map(Operand::Variable),
        select(commands(
            |c| c.info.readable() && c.info.shape != Shape::Variable
        ))
        .prop_map(Operand::Read),
    ]
}

fn value(min: i64, max: i64) -> impl Strategy<Value = Value> {
    prop_oneof![
        (min..=max).prop_map(Value::Number),
        (0u8..100).prop_map(Value::Variable),
    ]
}

fn condition() -> impl Strategy<Value = Condition> {
    (operand(), select(Comparison::ALL.to_vec()), operand())
        .prop_map(|(left, op, right)| Condition { left, op, right })
}

fn expr() -> impl Strategy<Value = Expr> {
    prop_oneof![
        operand().prop_map(Expr::Operand),
        operand().prop_map(Expr::Not),
        (operand(), select(BinaryOp::ALL.to_vec()), operand())
            .prop_map(|(left, op, right)| Expr::Binary { left, op, right }),
    ]
}

fn direction() -> impl Strategy<Value = Direction> {
    select(vec![Direction::Plus, Direction::Minus])
}

fn rotation() -> impl Strategy<Value = Rotation> {
    select(vec![Rotation::Clockwise, Rotation::CounterClockwise])
}

const POSITION: (i64, i64) = (-134_217_728, 134_217_727);

fn position() -> impl Strategy<Value = i64> {
    POSITION.0..=POSITION.1
}

fn two_axes() -> impl Strategy<Value = [Axis; 2]> {
    (axis(), axis()).prop_filter_map("two different axes", |(a, b)| (a != b).then_some([a, b]))
}

fn set() -> impl Strategy<Value = Action> {
    select(commands(|c| {
        c.info.writable() && c.info.shape != Shape::Variable
    }))
    .prop_flat_map(|command| {
        let range = command.info.values().map_or((0, 0), |r| (r.min, r.max));
        value(range.0, range.1).prop_map(move |value| Action::Set { command, value })
    })
}

fn action() -> impl Strategy<Value = Action> {
    prop_oneof![
        ((0u8..100), expr()).prop_map(|(variable, value)| Action::Let { variable, value }),
        set(),
        select(commands(|c| c.info.shape == Shape::Action)).prop_map(Action::Do),
        value(0, i64::from(i32::MAX)).prop_map(Action::Delay),
        axis().prop_map(Action::Wait),
        proptest::sample::subsequence(Axis::ALL.to_vec(), 1..=4)
            .prop_shuffle()
            .prop_flat_map(|axes| {
                let n = axes.len();
                (
                    Just(axes),
                    proptest::collection::vec(value(POSITION.0, POSITION.1), n),
                )
            })
            .prop_map(|(axes, values)| Action::Move(
                axes.into_iter()
                    .zip(values)
                    .map(|(axis, value)| Target { axis, value })
                    .collect()
            )),
        (axis(), direction()).prop_map(|(axis, direction)| Action::Jog { axis, direction }),
        (axis(), direction(), 0u8..=12).prop_map(|(axis, direction, mode)| Action::Home {
            axis,
            direction,
            mode
        }),
        (axis(), direction()).prop_map(|(axis, direction)| Action::SameInAscii(
            Cmd4crCommand::ZMove { axis, direction }
        )),
        (two_axes(), rotation(), position(), position()).prop_map(|(axes, rotation, a, b)| {
            Action::SameInAscii(Cmd4crCommand::Circle {
                axes,
                rotation,
                centre: [a, b],
            })
        }),
        (
            two_axes(),
            rotation(),
            position(),
            position(),
            0..=360_000i64
        )
            .prop_map(|(axes, rotation, a, b, angle)| Action::SameInAscii(
                Cmd4crCommand::Arc {
                    axes,
                    rotation,
                    centre: [a, b],
                    angle,
                }
            )),
        (rotation(), position(), position(), position()).prop_map(|(rotation, a, b, z)| {
            Action::SameInAscii(Cmd4crCommand::HelicalCircle {
                rotation,
                centre: [a, b],
                z,
            })
        }),
        (
            rotation(),
            position(),
            position(),
            0..=360_000i64,
            position()
        )
            .prop_map(|(rotation, a, b, angle, z)| Action::SameInAscii(
                Cmd4crCommand::HelicalArc {
                    rotation,
                    centre: [a, b],
                    angle,
                    z,
                }
            )),
    ]
}

fn statement() -> impl Strategy<Value = Statement> {
    prop_oneof![
        (0u8..4).prop_map(Statement::Prg),
        Just(Statement::End),
        (0u8..32).prop_map(Statement::Sub),
        Just(Statement::EndSub),
        condition().prop_map(Statement::If),
        condition().prop_map(Statement::ElseIf),
        Just(Statement::Else),
        Just(Statement::EndIf),
        condition().prop_map(Statement::While),
        Just(Statement::EndWhile),
        (0u8..32).prop_map(Statement::Gosub),
        action().prop_map(Statement::Action),
    ]
}

/// A well-nested block body, as source lines.
fn body(depth: u32) -> BoxedStrategy<Vec<String>> {
    let simple = action().prop_map(|a| vec![a.to_string()]);
    if depth == 0 {
        return proptest::collection::vec(simple, 0..4)
            .prop_map(|v| v.concat())
            .boxed();
    }
    let inner = body(depth - 1);
    let if_chain = (
        condition(),
        inner.clone(),
        proptest::collection::vec((condition(), inner.clone()), 0..3),
        proptest::option::of(inner.clone()),
    )
        .prop_map(|(c, then, elseifs, otherwise)| {
            let mut lines = vec![format!("IF {c}")];
            lines.extend(then);
            for (c, b) in elseifs {
                lines.push(format!("ELSEIF {c}"));
                lines.extend(b);
            }
            if let Some(b) = otherwise {
                lines.push("ELSE".into());
                lines.extend(b);
            }
            lines.push("ENDIF".into());
            lines
        });
    let while_loop = (condition(), inner).prop_map(|(c, b)| {
        let mut lines = vec![format!("WHILE {c}")];
        lines.extend(b);
        lines.push("ENDWHILE".into());
        lines
    });
    proptest::collection::vec(
        prop_oneof![3 => simple, 1 => if_chain, 1 => while_loop],
        0..5,
    )
    .prop_map(|v| v.concat())
    .boxed()
}

/// PRG 0–3 and some SUBs, each with a well-nested body.
fn source() -> impl Strategy<Value = String> {
    (
        proptest::sample::subsequence((0u8..4).collect::<Vec<_>>(), 0..=4),
        proptest::sample::subsequence((0u8..32).collect::<Vec<_>>(), 0..4),
        proptest::collection::vec(body(2), 8),
    )
        .prop_map(|(programs, subs, bodies)| {
            let mut lines = Vec::new();
            let mut bodies = bodies.into_iter();
            for n in programs {
                lines.push(format!("PRG {n}"));
                lines.extend(bodies.next().unwrap_or_default());
                lines.push("END".into());
            }
            for n in subs {
                lines.push(format!("SUB {n}"));
                lines.extend(bodies.next().unwrap_or_default());
                lines.push("ENDSUB".into());
            }
            lines.join("\n")
        })
}

/// Lines made of A-Script's own pieces, in any order.
fn scrambled_line() -> impl Strategy<Value = String> {
    let piece = select(vec![
        "PRG",
        "END",
        "SUB",
        "ENDSUB",
        "IF",
        "ELSEIF",
        "ELSE",
        "ENDIF",
        "WHILE",
        "ENDWHILE",
        "GOSUB",
        "V",
        "V1",
        "X",
        "XV",
        "HSPD",
        "HSPDX",
        "DO",
        "DI",
        "SR",
        "DELAY",
        "WAITX",
        "HOMEX",
        "JOGY",
        "CIRXYP",
        "ARCTN",
        "=",
        "==",
        "!=",
        "<",
        ">>",
        "+",
        "-",
        "~",
        "|",
        ":",
        "0",
        "7",
        "99999999999999999999999",
        " ",
        ";",
        "é",
        "(",
        "\t",
    ]);
    proptest::collection::vec(piece, 0..12).prop_map(|v| v.concat())
}

proptest! {
    #[test]
    fn statements_print_and_parse_back_to_themselves(statement in statement()) {
        let text = statement.to_string();
        prop_assert_eq!(parse_statement(&text), Ok(Some(statement)), "{}", text);
    }

    #[test]
    fn every_literal_statement_is_an_ascii_command_or_none(statement in statement()) {
        // A variable's value is checked when it runs; literals are checked
        // against the ASCII parser here.
        let literal = match &statement {
            Statement::Action(Action::Set { value, .. }) => matches!(value, Value::Number(_)),
            Statement::Action(Action::Move(targets)) => {
                targets.iter().all(|t| matches!(t.value, Value::Number(_)))
            }
            _ => true,
        };
        if let (true, Some(command)) = (literal, ascii_command(&statement, &[0; VARIABLES])) {
            let command = command.map_err(|e| e.to_string());
            prop_assert!(command.is_ok(), "{}: {:?}", statement, command);
            let command = command.unwrap_or_else(|_| unreachable!());
            prop_assert_eq!(parse_command(&command.to_string()), Ok(command));
        }
    }

    #[test]
    fn well_nested_programs_compile_with_every_jump_inside(source in source()) {
        let program = compile(&source);
        prop_assert!(program.is_ok(), "{:#?}\n{}", program, source);
        let program = program.unwrap_or_default();
        let steps = program.steps.len();
        for step in &program.steps {
            if let Op::JumpUnless { to, .. } | Op::Jump { to } = step.op {
                prop_assert!(to < steps, "{:?} in {}", step, source);
            }
        }
        for entry in program.programs.iter().chain(&program.subroutines).flatten() {
            prop_assert!(entry.start < steps);
            prop_assert!(program.steps[entry.start].line > entry.line);
        }
        // A compiled block's last step is its END or ENDSUB.
        let last = program.steps.last().map(|s| &s.op);
        prop_assert!(steps == 0 || matches!(last, Some(Op::End | Op::Return)));
    }

    #[test]
    fn any_line_is_parsed_and_coloured_without_panicking(line in "\\PC{0,40}") {
        let _ = parse_statement(&line);
        let pieces = tokens(&line);
        let mut at = 0;
        for (range, _) in &pieces {
            prop_assert_eq!(range.start, at);
            prop_assert!(range.end > range.start);
            prop_assert!(line.get(range.clone()).is_some());
            at = range.end;
        }
        prop_assert_eq!(at, line.len());
    }

    #[test]
    fn scrambled_sources_are_checked_without_panicking(
        lines in proptest::collection::vec(scrambled_line(), 0..16)
    ) {
        let source = lines.join("\n");
        let diagnostics = check(&source);
        for d in &diagnostics {
            prop_assert!(d.line() >= 1 && d.line() <= lines.len().max(1));
            prop_assert!(d.column() >= 1);
        }
        prop_assert_eq!(
            compile(&source).is_ok(),
            !diagnostics.iter().any(|d| d.is_error())
        );
        for line in &lines {
            let _ = tokens(line);
        }
    }
}
