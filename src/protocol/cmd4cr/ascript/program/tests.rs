use super::*;
use crate::protocol::cmd4cr::ascript::ast::{Expr, VARIABLES};

fn compiled(source: &str) -> Program {
    compile(source).unwrap_or_else(|errors| panic!("{errors:#?}"))
}

fn errors(source: &str) -> Vec<(usize, ErrorCode)> {
    match compile(source) {
        Ok(program) => panic!("compiled: {program:#?}"),
        Err(errors) => errors.into_iter().map(|e| (e.line, e.code)).collect(),
    }
}

/// Follow a program's steps the way an interpreter would (no motion: the
/// lines of the actions run are recorded), with `inputs` as the values of
/// every command read.
fn run(program: &Program, prg: u8, inputs: i32, budget: usize) -> (Vec<usize>, [i32; VARIABLES]) {
    let mut variables = [0; VARIABLES];
    let mut ran = Vec::new();
    let mut returns = Vec::new();
    let mut pc = program.program(prg).map(|e| e.start).unwrap_or(usize::MAX);
    for _ in 0..budget {
        let Some(step) = program.step(pc) else {
            break;
        };
        let mut value_of = |o: &Operand| match o {
            Operand::Variable(v) => Ok::<_, ()>(variables[usize::from(*v)]),
            _ => Ok(inputs),
        };
        pc = match &step.op {
            Op::Action(Action::Let { variable, value }) => {
                let v: Result<i32, _> = Expr::evaluate(value, &mut value_of);
                variables[usize::from(*variable)] = v.unwrap_or(0);
                pc + 1
            }
            Op::Action(_) => {
                ran.push(step.line);
                pc + 1
            }
            Op::JumpUnless { condition, to } => {
                if condition.evaluate(&mut value_of) == Ok(true) {
                    pc + 1
                } else {
                    *to
                }
            }
            Op::Jump { to } => *to,
            Op::Call { sub } => {
                returns.push(pc + 1);
                program.subroutine(*sub).map_or(usize::MAX, |e| e.start)
            }
            Op::Return => returns.pop().unwrap_or(usize::MAX),
            Op::End => break,
        };
    }
    (ran, variables)
}

#[test]
fn an_if_chain_runs_exactly_one_branch() {
    let program = compiled(
        "PRG 0\n\
         IF DI=1\n\
             X1\n\
         ELSEIF DI=2\n\
             X2\n\
         ELSEIF DI=3\n\
             X3\n\
         ELSE\n\
             X4\n\
         ENDIF\n\
         X5\n\
         END\n",
    );
    assert_eq!(run(&program, 0, 1, 100).0, [3, 11]);
    assert_eq!(run(&program, 0, 2, 100).0, [5, 11]);
    assert_eq!(run(&program, 0, 3, 100).0, [7, 11]);
    assert_eq!(run(&program, 0, 9, 100).0, [9, 11]);
    // IF 1, ELSEIF 2 (its end-of-branch jump and its test), ELSE 1,
    // ENDIF none: the compiled lines of §2.7.7.
    let lines: Vec<usize> = program.steps.iter().map(|s| s.line).collect();
    assert_eq!(lines, [2, 3, 4, 4, 5, 6, 6, 7, 8, 9, 11, 12]);
}

#[test]
fn an_if_without_else_skips_to_its_endif() {
    let program = compiled("PRG 1\nIF DI1=1\nX1\nENDIF\nX2\nEND");
    assert_eq!(run(&program, 1, 1, 100).0, [3, 5]);
    assert_eq!(run(&program, 1, 0, 100).0, [5]);
}

#[test]
fn a_counted_loop_runs_its_body_as_often_as_its_condition_holds() {
    let program = compiled(
        "PRG 1\n\
         V1=0\n\
         WHILE V1<10\n\
             X0\n\
             V1=V1+1\n\
         ENDWHILE\n\
         X9\n\
         END\n",
    );
    let (ran, variables) = run(&program, 1, 0, 1000);
    assert_eq!(ran.iter().filter(|&&l| l == 4).count(), 10);
    assert_eq!(ran.last(), Some(&7));
    assert_eq!(variables[1], 10);
}

#[test]
fn nested_loops_and_branches_keep_their_own_targets() {
    let program = compiled(
        "PRG 3\n\
         V1=0\n\
         WHILE V1<3\n\
             V2=0\n\
             WHILE V2<2\n\
                 IF V2=1\n\
                     X1\n\
                 ENDIF\n\
                 V2=V2+1\n\
             ENDWHILE\n\
             V1=V1+1\n\
         ENDWHILE\n\
         END\n",
    );
    let (ran, variables) = run(&program, 3, 0, 1000);
    assert_eq!(ran, [7, 7, 7]);
    assert_eq!((variables[1], variables[2]), (3, 2));
}

#[test]
fn subroutines_are_called_and_return_after_the_gosub() {
    let program = compiled(
        "PRG 0\n\
         GOSUB 1\n\
         X2\n\
         END\n\
         SUB 1\n\
         X1\n\
         ENDSUB\n\
         SUB 31\n\
         ECLEARX\n\
         ENDSUB\n",
    );
    assert_eq!(run(&program, 0, 0, 100).0, [6, 3]);
    assert_eq!(program.subroutine(1).map(|e| e.line), Some(5));
    assert_eq!(program.error_handler().map(|e| e.line), Some(8));
    assert_eq!(
        program
            .error_handler()
            .and_then(|e| program.step(e.start))
            .map(|s| s.line),
        Some(9)
    );
    assert_eq!(program.program_numbers().collect::<Vec<_>>(), [0]);
    assert!(program.warnings.is_empty());
}

#[test]
fn a_gosub_to_a_missing_subroutine_compiles_with_a_warning() {
    let program = compiled("PRG 0\nGOSUB 5\nEND");
    assert_eq!(program.warnings.len(), 1);
    assert_eq!(program.warnings[0].line, 2);
    assert!(
        program.warnings[0]
            .message
            .starts_with("GOSUB 5: there is no SUB 5")
    );
    let diagnostics = check("PRG 0\nGOSUB 5\nEND\nSUB 40\nENDSUB");
    let kinds: Vec<(usize, bool)> = diagnostics
        .iter()
        .map(|d| (d.line(), d.is_error()))
        .collect();
    assert_eq!(kinds, [(2, false), (4, true)]);
}

#[test]
fn a_missing_closer_is_reported_at_its_opener_once() {
    assert_eq!(
        errors("PRG 0\nWHILE 1=1\nEND"),
        [(2, ErrorCode::MissingEndwhile)]
    );
    assert_eq!(errors("PRG 0\nIF 1=1\nEND"), [(2, ErrorCode::MissingEndif)]);
    assert_eq!(errors("PRG 0\nX1"), [(1, ErrorCode::MissingEnd)]);
    assert_eq!(errors("SUB 1\nX1"), [(1, ErrorCode::ErrorEndsub)]);
    // A new block ends the one before it.
    assert_eq!(
        errors("PRG 0\nIF 1=1\nPRG 1\nEND"),
        [(1, ErrorCode::MissingEnd), (2, ErrorCode::MissingEndif)]
    );
    // A closer for an outer block closes what is open inside it.
    assert_eq!(
        errors("PRG 0\nIF 1=1\nWHILE 1=1\nENDIF\nEND"),
        [(3, ErrorCode::MissingEndwhile)]
    );
    assert_eq!(
        errors("PRG 0\nWHILE 1=1\nIF 1=1\nENDWHILE\nEND"),
        [(3, ErrorCode::MissingEndif)]
    );
    let e = compile("PRG 0\n  WHILE 1=1\nEND").err().unwrap_or_default();
    assert_eq!(
        e.first().map(ToString::to_string).as_deref(),
        Some("line 2: Missing ENDWHILE: the WHILE on line 2 has no ENDWHILE before END on line 3")
    );
    assert_eq!(e.first().map(|e| e.column), Some(3));
}

#[test]
fn closers_and_branches_without_their_opener() {
    assert_eq!(errors("PRG 0\nENDIF\nEND"), [(2, ErrorCode::Error)]);
    assert_eq!(errors("PRG 0\nENDWHILE\nEND"), [(2, ErrorCode::Error)]);
    assert_eq!(errors("PRG 0\nELSE\nEND"), [(2, ErrorCode::Error)]);
    assert_eq!(errors("PRG 0\nELSEIF 1=1\nEND"), [(2, ErrorCode::Error)]);
    assert_eq!(errors("END"), [(1, ErrorCode::Error)]);
    assert_eq!(errors("ENDSUB"), [(1, ErrorCode::Error)]);
    assert_eq!(
        errors("PRG 0\nIF 1=1\nELSE\nELSE\nENDIF\nEND"),
        [(4, ErrorCode::Error)]
    );
    assert_eq!(
        errors("PRG 0\nIF 1=1\nELSE\nELSEIF 1=2\nENDIF\nEND"),
        [(4, ErrorCode::Error)]
    );
    // END inside a SUB: reported, and the SUB still needs its ENDSUB.
    assert_eq!(errors("SUB 1\nEND\nENDSUB"), [(2, ErrorCode::Error)]);
    assert_eq!(errors("PRG 1\nENDSUB\nEND"), [(2, ErrorCode::Error)]);
}

#[test]
fn code_outside_blocks_and_blocks_defined_twice() {
    assert_eq!(errors("X1000"), [(1, ErrorCode::Error)]);
    assert_eq!(
        errors("PRG 0\nEND\nWAITX\nPRG 0\nEND"),
        [(3, ErrorCode::Error), (4, ErrorCode::Error)]
    );
    let e = compile("SUB 2\nENDSUB\nSUB 2\nENDSUB")
        .err()
        .unwrap_or_default();
    assert_eq!(
        e.first().map(|e| e.detail.as_str()),
        Some("SUB 2 is already defined on line 1")
    );
}

#[test]
fn a_wrong_line_keeps_its_block_structure() {
    // The header is wrong but the block still ends at its ENDSUB.
    assert_eq!(errors("SUB5000\nX1\nENDSUB"), [(1, ErrorCode::ErrorSub)]);
    // The condition is wrong but the IF still needs its ENDIF.
    assert_eq!(
        errors("PRG 0\nIF V1==2\nX1\nENDIF\nEND"),
        [(2, ErrorCode::Error)]
    );
    // A wrong line gets its own error, not a missing closer as well.
    assert_eq!(errors("PRG 0\nWHILE\nEND"), [(2, ErrorCode::Error)]);
    assert_eq!(errors("PRG200\nX1"), [(1, ErrorCode::ErrorPrg)]);
    // Every error is reported, in line order.
    assert_eq!(
        errors("PRG 0\nFOO\nDO10=1\nV200=1\nEND"),
        [
            (2, ErrorCode::UnknownError),
            (3, ErrorCode::BitError),
            (4, ErrorCode::VarRangeError)
        ]
    );
}

#[test]
fn every_block_starts_where_its_steps_do() {
    let program =
        compiled("\r\n; header\r\nPRG 2\r\nX1\r\nEND\r\nPRG 0\r\nEND\r\nSUB 0\r\nENDSUB\r\n");
    assert_eq!(program.program(2), Some(Entry { line: 3, start: 0 }));
    assert_eq!(program.program(0), Some(Entry { line: 6, start: 2 }));
    assert_eq!(program.subroutine(0), Some(Entry { line: 8, start: 3 }));
    assert_eq!(program.program(1), None);
    assert_eq!(program.program(9), None);
    assert_eq!(
        program.steps.iter().map(|s| &s.op).collect::<Vec<_>>(),
        [
            &Op::Action(match parse_line("X1").map(|p| p.statement) {
                Some(Ok(Statement::Action(a))) => a,
                _ => panic!(),
            }),
            &Op::End,
            &Op::End,
            &Op::Return
        ]
    );
    assert_eq!(program.statements.len(), 7);
}

#[test]
fn an_empty_source_compiles_to_nothing() {
    let program = compiled("");
    assert!(program.steps.is_empty() && program.program_numbers().next().is_none());
    assert!(check("; nothing\n\n").is_empty());
}
