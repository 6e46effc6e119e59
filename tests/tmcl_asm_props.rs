//! Property tests of the TMCL assembler and disassembler: generated valid
//! programs assemble to the expected words and round-trip byte-identical
//! through the disassembler; any image the assembler can hold round-trips;
//! no input makes the assembler, the disassembler or the image reader
//! panic.

use axterm::protocol::tmcl::asm::{
    NoIncludes, PROGRAM_MEMORY_WORDS, ProgramWord, assemble, check_program_command, disassemble,
    format_image, parse_image,
};
use axterm::protocol::tmcl::catalog::{COMMANDS, Usage};
use axterm::protocol::tmcl::command::{GLOBAL_INTERRUPT, INTERRUPTS};
use axterm::protocol::tmcl::params::{
    AXIS_PARAMS, BANK0_PARAMS, BANK2_PARAMS, BANK3_PARAMS, ParamInfo, ValueRange,
};
use axterm::protocol::tmcl::validate::{GIO_PORTS, IoPorts, SIO_PORTS};
use axterm::protocol::tmcl::{
    CalcFamily, CalcOp, ClearFlag, Command, Condition, MoveMode, OperandCode, RfsAction,
    WaitCondition, format_command, validate,
};
use proptest::prelude::*;
use proptest::sample::{Index, select};

fn code<T: OperandCode + std::fmt::Debug>() -> impl Strategy<Value = T> {
    select(T::ALL)
}

fn calc_op(family: CalcFamily) -> impl Strategy<Value = CalcOp> {
    select(family.ops())
}

/// A value of the parameter's range, as the frame carries it.
fn param_value(info: &'static ParamInfo) -> BoxedStrategy<i32> {
    let to_wire = move |v: i64| info.wire_value(v).unwrap_or(0);
    match info.range {
        ValueRange::Span { min, max } => (min..=max).prop_map(to_wire).boxed(),
        ValueRange::OneOf(values) => select(values).prop_map(to_wire).boxed(),
    }
}

/// (parameter number, its row) for every row accepted by `filter`.
fn param_numbers(
    table: &'static [ParamInfo],
    filter: fn(&ParamInfo) -> bool,
) -> Vec<(u8, &'static ParamInfo)> {
    table
        .iter()
        .filter(|p| filter(p))
        .flat_map(|p| p.numbers.clone().map(move |n| (n, p)))
        .collect()
}

fn axis_param(filter: fn(&ParamInfo) -> bool) -> impl Strategy<Value = (u8, &'static ParamInfo)> {
    select(param_numbers(AXIS_PARAMS, filter))
}

fn global_param(
    filter: fn(&ParamInfo) -> bool,
) -> impl Strategy<Value = (u8, u8, &'static ParamInfo)> {
    let mut all = Vec::new();
    for (bank, table) in [(0u8, BANK0_PARAMS), (2, BANK2_PARAMS), (3, BANK3_PARAMS)] {
        all.extend(
            param_numbers(table, filter)
                .into_iter()
                .map(|(n, p)| (n, bank, p)),
        );
    }
    select(all)
}

fn io_port(table: &'static [IoPorts]) -> impl Strategy<Value = (&'static IoPorts, u8)> {
    select(table.to_vec()).prop_flat_map(|group| {
        let group: &'static IoPorts = table
            .iter()
            .find(|g| **g == group)
            .expect("group of the table");
        (Just(group), group.ports.clone())
    })
}

/// Commands a program may hold that are not jumps, with valid operands.
fn plain_command() -> impl Strategy<Value = Command> {
    use Command::*;
    let v = any::<i32>;
    let b = any::<u8>;
    let coordinate = || 0u8..=20;
    let arms: Vec<BoxedStrategy<Command>> = vec![
        (-2047i32..=2047)
            .prop_map(|velocity| Ror { motor: 0, velocity })
            .boxed(),
        (-2047i32..=2047)
            .prop_map(|velocity| Rol { motor: 0, velocity })
            .boxed(),
        Just(Mst { motor: 0 }).boxed(),
        (code::<MoveMode>(), v())
            .prop_map(|(mode, target)| Mvp {
                mode,
                motor: 0,
                target: if mode == MoveMode::Coord {
                    target.rem_euclid(21)
                } else {
                    target
                },
            })
            .boxed(),
        axis_param(|p| p.access.write)
            .prop_flat_map(|(param, info)| {
                param_value(info).prop_map(move |value| Sap {
                    param,
                    motor: 0,
                    value,
                })
            })
            .boxed(),
        axis_param(|p| p.access.read)
            .prop_map(|(param, _)| Gap { param, motor: 0 })
            .boxed(),
        axis_param(|p| p.access.eeprom)
            .prop_map(|(param, _)| Stap { param, motor: 0 })
            .boxed(),
        axis_param(|p| p.access.eeprom)
            .prop_map(|(param, _)| Rsap { param, motor: 0 })
            .boxed(),
        axis_param(|p| p.access.write)
            .prop_map(|(param, _)| Aap { param, motor: 0 })
            .boxed(),
        global_param(|p| p.access.write)
            .prop_flat_map(|(param, bank, info)| {
                param_value(info).prop_map(move |value| Sgp { param, bank, value })
            })
            .boxed(),
        global_param(|p| p.access.read)
            .prop_map(|(param, bank, _)| Ggp { param, bank })
            .boxed(),
        global_param(|p| p.access.write)
            .prop_map(|(param, bank, _)| Agp { param, bank })
            .boxed(),
        (0u8..=55).prop_map(|param| Stgp { param, bank: 2 }).boxed(),
        (0u8..=55).prop_map(|param| Rsgp { param, bank: 2 }).boxed(),
        code::<RfsAction>()
            .prop_map(|action| Rfs { action, motor: 0 })
            .boxed(),
        io_port(SIO_PORTS)
            .prop_flat_map(|(group, port)| {
                let values = match group.values {
                    ValueRange::Span { min, max } => min..=max,
                    ValueRange::OneOf(_) => 0..=0,
                };
                values.prop_map(move |value| Sio {
                    port,
                    bank: group.bank,
                    value: i32::try_from(value).unwrap_or(0),
                })
            })
            .boxed(),
        io_port(GIO_PORTS)
            .prop_map(|(group, port)| Gio {
                port,
                bank: group.bank,
            })
            .boxed(),
        (calc_op(CalcFamily::Accumulator), v())
            .prop_map(|(op, operand)| Calc { op, operand })
            .boxed(),
        v().prop_map(|value| Comp { value }).boxed(),
        Just(Rsub).boxed(),
        select(INTERRUPTS)
            .prop_map(|i| Ei {
                interrupt: i.number,
            })
            .boxed(),
        select(INTERRUPTS)
            .prop_map(|i| Di {
                interrupt: i.number,
            })
            .boxed(),
        (code::<WaitCondition>(), -1i32..=i32::MAX)
            .prop_map(|(condition, ticks)| Wait {
                condition,
                motor: 0,
                ticks,
            })
            .boxed(),
        Just(Stop).boxed(),
        (coordinate(), v())
            .prop_map(|(coordinate, position)| Sco {
                coordinate,
                motor: 0,
                position,
            })
            .boxed(),
        coordinate()
            .prop_map(|coordinate| Sco {
                coordinate,
                motor: 255,
                position: 0,
            })
            .boxed(),
        (coordinate(), select(vec![0u8, 255]))
            .prop_map(|(coordinate, motor)| Gco { coordinate, motor })
            .boxed(),
        coordinate()
            .prop_map(|coordinate| Cco {
                coordinate,
                motor: 0,
            })
            .boxed(),
        coordinate()
            .prop_map(|coordinate| Aco {
                coordinate,
                motor: 0,
            })
            .boxed(),
        calc_op(CalcFamily::XRegister)
            .prop_map(|op| Calcx { op })
            .boxed(),
        code::<ClearFlag>().prop_map(|flag| Cle { flag }).boxed(),
        Just(Reti).boxed(),
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
        code::<MoveMode>()
            .prop_map(|mode| Mvpa { mode, motor: 0 })
            .boxed(),
        Just(Rola { motor: 0 }).boxed(),
        Just(Rora { motor: 0 }).boxed(),
        v().prop_map(|value| Siv { value }).boxed(),
        Just(Giv).boxed(),
        Just(Aiv).boxed(),
        (0u8..=7, b(), b(), v())
            .prop_map(|(number, kind, motor_bank, value)| UserFunction {
                number,
                kind,
                motor_bank,
                value,
            })
            .boxed(),
    ];
    proptest::strategy::Union::new(arms)
}

/// A command that takes a program address, with the address left to fill.
#[derive(Debug, Clone, Copy)]
enum Jump {
    Ja,
    Jc(Condition),
    Csub,
    Call(Condition),
    Djnz(u8),
    Rst,
    Vect(u8),
}

impl Jump {
    fn command(self, address: i32) -> Command {
        match self {
            Jump::Ja => Command::Ja { address },
            Jump::Jc(condition) => Command::Jc { condition, address },
            Jump::Csub => Command::Csub { address },
            Jump::Call(condition) => Command::Call { condition, address },
            Jump::Djnz(var) => Command::Djnz { var, address },
            Jump::Rst => Command::Rst { address },
            Jump::Vect(interrupt) => Command::Vect { interrupt, address },
        }
    }

    fn line(self, label: &str) -> String {
        match self {
            Jump::Ja => format!("JA {label}"),
            Jump::Jc(c) => format!("JC {}, {label}", c.keyword()),
            Jump::Csub => format!("CSUB {label}"),
            Jump::Call(c) => format!("CALL {}, {label}", c.keyword()),
            Jump::Djnz(var) => format!("DJNZ {var}, {label}"),
            Jump::Rst => format!("RST {label}"),
            Jump::Vect(i) => format!("VECT {i}, {label}"),
        }
    }
}

fn jump() -> impl Strategy<Value = Jump> {
    let vectors: Vec<u8> = INTERRUPTS
        .iter()
        .map(|i| i.number)
        .filter(|n| *n != GLOBAL_INTERRUPT)
        .collect();
    prop_oneof![
        Just(Jump::Ja),
        code::<Condition>().prop_map(Jump::Jc),
        Just(Jump::Csub),
        code::<Condition>().prop_map(Jump::Call),
        any::<u8>().prop_map(Jump::Djnz),
        Just(Jump::Rst),
        select(vectors).prop_map(Jump::Vect),
    ]
}

#[derive(Debug, Clone)]
enum Instruction {
    Plain { command: Command, lower_case: bool },
    Jump { jump: Jump, target: Index },
}

fn instruction() -> impl Strategy<Value = Instruction> {
    prop_oneof![
        3 => (plain_command(), any::<bool>())
            .prop_map(|(command, lower_case)| Instruction::Plain { command, lower_case }),
        1 => (jump(), any::<Index>()).prop_map(|(jump, target)| Instruction::Jump { jump, target }),
    ]
}

/// The source of a generated program and the words it must give.
fn program_source(instructions: &[Instruction]) -> (String, Vec<ProgramWord>) {
    let len = instructions.len();
    let targets: Vec<Option<usize>> = instructions
        .iter()
        .map(|i| match i {
            Instruction::Jump { target, .. } => Some(target.index(len + 1)),
            Instruction::Plain { .. } => None,
        })
        .collect();
    let label = |address: usize| format!("Target{address}");
    let mut source = String::new();
    let mut words = Vec::new();
    for (address, (instruction, target)) in instructions.iter().zip(&targets).enumerate() {
        if targets.contains(&Some(address)) {
            source.push_str(&format!("{}:\n", label(address)));
        }
        let (line, command) = match (instruction, target) {
            (Instruction::Jump { jump, .. }, Some(t)) => (
                jump.line(&label(*t)),
                jump.command(i32::try_from(*t).unwrap()),
            ),
            (
                Instruction::Plain {
                    command,
                    lower_case,
                },
                _,
            ) => {
                let text = format_command(command);
                let text = if *lower_case {
                    text.to_lowercase()
                } else {
                    text
                };
                (text, *command)
            }
            (Instruction::Jump { .. }, None) => unreachable!("every jump has a target"),
        };
        source.push_str(&format!("    {line}   // word {address}\n"));
        words.push(ProgramWord::from(command));
    }
    if targets.contains(&Some(len)) {
        source.push_str(&format!("{}:\n", label(len)));
    }
    (source, words)
}

/// Instruction numbers a program may hold (control commands are executed
/// during a download, §3.6.53).
fn storable_opcode() -> impl Strategy<Value = u8> {
    any::<u8>().prop_filter("not a control command", |op| {
        !COMMANDS
            .iter()
            .any(|c| c.opcode == *op && c.usage == Usage::DirectOnly)
    })
}

/// Words with any fields; some typed, most raw.
fn any_word() -> impl Strategy<Value = ProgramWord> {
    let small = prop_oneof![-3i32..=300, any::<i32>()];
    (
        storable_opcode(),
        prop_oneof![0u8..=12, any::<u8>()],
        prop_oneof![Just(0u8), Just(2), Just(255), any::<u8>()],
        small,
    )
        .prop_map(|(opcode, kind, motor_bank, value)| ProgramWord {
            opcode,
            kind,
            motor_bank,
            value,
        })
}

/// Lines made of the assembler's vocabulary, to reach past the first
/// token.
fn source_line() -> impl Strategy<Value = String> {
    let word = prop_oneof![
        select(COMMANDS.iter().map(|c| c.name).collect::<Vec<_>>()).prop_map(str::to_string),
        select(vec![
            "ABS", "REL", "ZE", "GE", "TICKS", "POS", "ADD", "SWAP", "Loop", "Loop:", "X", "=",
            "#include", "a.inc", ",", ",,", ":", "//", "0x", "$FF", "-", "€", "\t", "\"",
        ])
        .prop_map(str::to_string),
        any::<i64>().prop_map(|n| n.to_string()),
        "[a-zA-Z_][a-zA-Z0-9_.]{0,6}:?",
    ];
    prop::collection::vec(word, 0..7).prop_map(|words| words.join(" "))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn generated_programs_assemble_and_round_trip(
        instructions in prop::collection::vec(instruction(), 1..60)
    ) {
        let (source, expected) = program_source(&instructions);
        let program = assemble("gen.tmc", &source, &NoIncludes)
            .map_err(|e| TestCaseError::fail(format!("{e:#?}\n{source}")))?;
        prop_assert_eq!(&program.words, &expected, "{}", source);
        let text = disassemble(&program.words);
        // Every word of a valid program comes back as a mnemonic.
        prop_assert!(text.lines().skip(1).all(|l| !l.contains("//")), "{}", text);
        let again = assemble("disassembled.tmc", &text, &NoIncludes)
            .map_err(|e| TestCaseError::fail(format!("{e:#?}\n{text}")))?;
        prop_assert_eq!(&again.words, &program.words, "{}", text);
        prop_assert_eq!(disassemble(&again.words), text);
    }

    #[test]
    fn generated_commands_are_valid_program_words(command in plain_command()) {
        prop_assert_eq!(validate(&command), Ok(()));
        prop_assert_eq!(check_program_command(&command), Ok(()));
    }

    #[test]
    fn any_storable_image_round_trips(words in prop::collection::vec(any_word(), 0..80)) {
        let text = disassemble(&words);
        let program = assemble("image.tmc", &text, &NoIncludes)
            .map_err(|e| TestCaseError::fail(format!("{e:#?}\n{text}")))?;
        prop_assert_eq!(program.words, words);
    }

    #[test]
    fn images_round_trip_through_their_file_format(
        words in prop::collection::vec(any::<(u8, u8, u8, i32)>(), 0..40)
    ) {
        let words: Vec<ProgramWord> = words
            .into_iter()
            .map(|(opcode, kind, motor_bank, value)| ProgramWord { opcode, kind, motor_bank, value })
            .collect();
        prop_assert_eq!(parse_image(&format_image(&words)), Ok(words));
    }

    #[test]
    fn no_source_text_makes_the_assembler_panic(
        text in prop_oneof![
            any::<String>(),
            prop::collection::vec(source_line(), 0..12).prop_map(|l| l.join("\n")),
        ]
    ) {
        if let Err(errors) = assemble("fuzz.tmc", &text, &NoIncludes) {
            prop_assert!(!errors.is_empty());
            let lines = text.lines().count().max(1);
            for e in errors {
                prop_assert!(e.line >= 1 && e.line <= lines, "{e}");
                prop_assert!(e.column >= 1, "{e}");
                let width = text.lines().nth(e.line - 1).map_or(0, |l| l.chars().count());
                prop_assert!(e.column <= width + 1, "{e} in {text:?}");
            }
        }
    }

    #[test]
    fn no_image_text_makes_the_reader_or_disassembler_panic(text in any::<String>()) {
        if let Ok(words) = parse_image(&text) {
            prop_assert!(words.len() <= PROGRAM_MEMORY_WORDS);
            let _ = disassemble(&words);
        }
    }
}
