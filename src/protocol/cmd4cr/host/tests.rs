//! The host run against scripted answers: what is sent, in what order,
//! and how answers steer it. Time is a number here (`now` is handed in).

use super::*;

fn answer(line: &str, value: ReplyValue) -> Answer {
    Answer {
        line: line.to_string(),
        frames: Vec::new(),
        result: Ok(Reading {
            status: None,
            value,
        }),
    }
}

fn refused(line: &str, reply: &str) -> Answer {
    Answer {
        line: line.to_string(),
        frames: Vec::new(),
        result: Err(AnswerError::Reply(ReplyError::Refused {
            module: "controller 01".into(),
            line: line.to_string(),
            reply: reply.to_string(),
            meaning: "scripted".into(),
        })),
    }
}

/// What a scripted controller answers to `line`.
type Script<'a> = dyn FnMut(&str) -> Answer + 'a;

/// Run `source` to its end (at most `limit` lines sent); every line sent,
/// the waits in between as `wait N ms`, the end, the events.
fn run_with(
    source: &str,
    start: Option<&[u8]>,
    limit: usize,
    script: &mut Script,
) -> (Vec<String>, HostEnd, Vec<String>) {
    let checked = HostProgram::check("p.asc", source, start).expect("checks");
    let mut run = AScriptRun::new(&checked);
    let mut now = Duration::ZERO;
    let mut log = Vec::new();
    let mut events = Vec::new();
    let mut step = run.start(now);
    for _ in 0..limit * 4 {
        events.extend(run.take_events().iter().map(ToString::to_string));
        step = match step {
            HostStep::Send(line) => {
                log.push(line.clone());
                if log.len() > limit {
                    panic!("more than {limit} lines sent: {log:?}");
                }
                let result = script(&line);
                run.on_reply(&result, now)
            }
            HostStep::Wake(after) => {
                log.push(format!("wait {} ms", after.as_millis()));
                now += after;
                run.on_wake(now)
            }
            HostStep::Finished(end) => {
                assert!(run.finished());
                return (log, end, events);
            }
        };
    }
    panic!("no end: {log:?}");
}

/// Writes answer OK; reads answer from `reads` (line, value) in order of
/// appearance, the last value of a line repeating.
fn controller<'a>(reads: &'a [(&'a str, i64)]) -> impl FnMut(&str) -> Answer + 'a {
    let mut used = vec![false; reads.len()];
    move |line: &str| {
        let matching: Vec<usize> = (0..reads.len()).filter(|&i| reads[i].0 == line).collect();
        match matching.iter().find(|&&i| !used[i]).or(matching.last()) {
            Some(&i) => {
                used[i] = true;
                answer(line, ReplyValue::Number(reads[i].1))
            }
            None => answer(line, ReplyValue::None),
        }
    }
}

#[test]
fn example_1_sends_each_statement_and_waits_by_reading_mst() {
    let source =
        "PRG 0\n HSPD=20000\n LSPD=1000\n ACC=300\n EO=1\n X1000\n WAITX\n X0\n WAITX\nEND\n";
    let (log, end, events) = run_with(
        source,
        None,
        20,
        &mut controller(&[("MSTX", 1), ("MSTX", 4), ("MSTX", 0), ("MSTX", 0)]),
    );
    assert_eq!(
        log,
        [
            "HSPD=20000",
            "LSPD=1000",
            "ACC=300",
            "EO=1",
            "X1000",
            "MSTX",
            "wait 20 ms",
            "MSTX",
            "wait 20 ms",
            "MSTX",
            "X0",
            "MSTX"
        ]
    );
    assert!(end.ok(), "{end}");
    assert_eq!(
        events.first().map(String::as_str),
        Some("PRG 0 started from the host")
    );
    assert!(
        events.contains(&"PRG 0 line 6: X1000 → ok".to_string()),
        "{events:?}"
    );
    assert_eq!(
        events.last().map(String::as_str),
        Some("PRG 0 reached END (line 10)")
    );
}

#[test]
fn variables_and_loops_stay_on_the_host() {
    // Example 4's loop with a variable target (Ex 6: XV1).
    let source =
        "PRG 1\n V1=0\n WHILE V1<3000\n  XV1\n  V1=V1+1000\n ENDWHILE\n V2=V1/7\n X V2\nEND\n";
    let source = source.replace("X V2", "XV2");
    let (log, end, _) = run_with(&source, None, 10, &mut controller(&[]));
    assert_eq!(log, ["X0", "X1000", "X2000", "X428"]);
    assert!(end.ok());
}

#[test]
fn commands_in_expressions_and_conditions_are_read_from_the_controller() {
    let source = "PRG 0\n V1=MSTX&7\n IF DI1=1\n  DO1=V1\n ELSEIF V1>PX\n  DO1=0\n ENDIF\nEND\n";
    let (log, _, _) = run_with(
        source,
        None,
        10,
        &mut controller(&[("MSTX", 13), ("DI1", 1)]),
    );
    assert_eq!(log, ["MSTX", "DI1", "DO1=5"]);
    let (log, _, _) = run_with(
        source,
        None,
        10,
        &mut controller(&[("MSTX", 13), ("DI1", 0), ("PX", 2)]),
    );
    assert_eq!(log, ["MSTX", "DI1", "PX", "DO1=0"]);
}

#[test]
fn a_refused_command_runs_sub_31_and_sap_says_where_to_go_on() {
    let source = "PRG 0\n X1000\n DO1=1\nEND\nSUB 31\n ECLEARX\nENDSUB\n";
    for (sap, expected) in [
        // SAP 0: back to the statement that failed.
        (0, ["SAP", "X1000", "CLRX", "X1000", "DO1=1"]),
        // SAP 1: back to the first statement of the program.
        (1, ["SAP", "X1000", "CLRX", "X1000", "DO1=1"]),
    ] {
        let mut first = true;
        let (log, end, events) = run_with(source, None, 10, &mut |line: &str| match line {
            "SAP" => answer(line, ReplyValue::Number(sap)),
            "X1000" if first => {
                first = false;
                refused(line, "?Limit Error")
            }
            _ => answer(line, ReplyValue::None),
        });
        assert_eq!(log, expected, "SAP {sap}");
        assert!(end.ok(), "{end}");
        assert!(
            events.iter().any(|e| e.contains("SUB 31 handles it")),
            "{events:?}"
        );
    }
    // Where the two differ: the failed statement is not the first.
    let source = "PRG 0\n DO2=1\n X1000\nEND\nSUB 31\n ECLEARX\nENDSUB\n";
    for (sap, expected) in [
        (0, vec!["SAP", "DO2=1", "X1000", "CLRX", "X1000"]),
        (1, vec!["SAP", "DO2=1", "X1000", "CLRX", "DO2=1", "X1000"]),
    ] {
        let mut first = true;
        let (log, _, _) = run_with(source, None, 10, &mut |line: &str| match line {
            "SAP" => answer(line, ReplyValue::Number(sap)),
            "X1000" if first => {
                first = false;
                refused(line, "?Limit Error")
            }
            _ => answer(line, ReplyValue::None),
        });
        assert_eq!(log, expected, "SAP {sap}");
    }
}

#[test]
fn without_sub_31_the_program_stops_in_the_error_state_and_the_others_go_on() {
    let source = "PRG 0\n X1000\n DO1=1\nEND\nPRG 1\n DO2=1\n DO3=1\nEND\n";
    let (log, end, events) = run_with(source, None, 10, &mut |line: &str| match line {
        "X1000" => refused(line, "?Limit Error"),
        _ => answer(line, ReplyValue::None),
    });
    // The programs take turns, one command each.
    assert_eq!(log, ["X1000", "DO2=1", "DO3=1"]);
    assert!(!end.ok());
    assert_eq!(end.failures.len(), 1);
    assert!(
        end.failures[0].starts_with("PRG 0 line 2: `X1000` was refused"),
        "{end}"
    );
    assert!(
        events.iter().any(|e| e.contains("stopped (error state)")),
        "{events:?}"
    );
}

#[test]
fn a_busy_axis_is_no_error_unless_an_error_is_latched() {
    let source = "PRG 0\n X2000\n DO1=1\nEND\n";
    let busy = |latched: i64| {
        move |line: &str| match line {
            "X2000" => refused(line, "?Error Moving"),
            "MSTZ" => answer(line, ReplyValue::Number(latched)),
            // X moves (at constant speed).
            "MSTX" => answer(line, ReplyValue::Number(4)),
            "MSTY" | "MSTU" => answer(line, ReplyValue::Number(0)),
            _ => answer(line, ReplyValue::None),
        }
    };
    let (log, end, events) = run_with(source, None, 10, &mut busy(0));
    assert_eq!(log, ["X2000", "MSTX", "MSTY", "MSTZ", "MSTU", "DO1=1"]);
    assert!(end.ok());
    assert!(events.iter().any(|e| e.contains("went on")), "{events:?}");
    let (log, end, _) = run_with(source, None, 10, &mut busy(1024));
    assert_eq!(log, ["X2000", "MSTX", "MSTY", "MSTZ"]);
    assert!(end.failures[0].contains("MSTZ = 1024"), "{end}");
}

#[test]
fn refused_as_moving_while_nothing_moves_is_sent_again_a_little_later() {
    let source = "PRG 0\n X1000\n DO1=1\nEND\n";
    let idle = ["MSTX", "MSTY", "MSTZ", "MSTU"];
    let mut refusals = 2;
    let (log, end, _) = run_with(source, None, 20, &mut |line: &str| match line {
        "X1000" if refusals > 0 => {
            refusals -= 1;
            refused(line, "?Error Moving")
        }
        _ if idle.contains(&line) => answer(line, ReplyValue::Number(0)),
        _ => answer(line, ReplyValue::None),
    });
    let mut expected: Vec<&str> = Vec::new();
    for _ in 0..2 {
        expected.push("X1000");
        expected.extend(idle);
        expected.push("wait 20 ms");
    }
    expected.extend(["X1000", "DO1=1"]);
    assert_eq!(log, expected);
    assert!(end.ok(), "{end}");
    // Not for ever.
    let (log, end, _) = run_with(source, None, 40, &mut |line: &str| match line {
        "X1000" => refused(line, "?Error Moving"),
        _ => answer(line, ReplyValue::Number(0)),
    });
    assert_eq!(log.iter().filter(|l| *l == "X1000").count(), 6);
    assert!(end.failures[0].contains("refused 6 times"), "{end}");
}

#[test]
fn a_wait_fails_when_the_axis_stops_with_a_new_latched_error() {
    let source = "PRG 0\n X1000\n WAITX\n DO1=1\nEND\n";
    // An alarm error latched before the wait is not the wait's.
    let (log, end, _) = run_with(
        source,
        None,
        10,
        &mut controller(&[("MSTX", 1024 + 4), ("MSTX", 1024)]),
    );
    assert_eq!(log, ["X1000", "MSTX", "wait 20 ms", "MSTX", "DO1=1"]);
    assert!(end.ok(), "{end}");
    // A +limit error that came while moving is.
    let (log, end, _) = run_with(
        source,
        None,
        10,
        &mut controller(&[("MSTX", 4), ("MSTX", 256 + 16)]),
    );
    assert_eq!(log, ["X1000", "MSTX", "wait 20 ms", "MSTX"]);
    assert!(
        end.failures[0].contains("WAITX: the axis stopped with an error (MST 272)"),
        "{end}"
    );
}

#[test]
fn sr_starts_stops_pauses_and_continues_programs_on_the_host() {
    // Example 8's shape: PRG 1 runs PRG 0, which is not started by itself.
    let source = "PRG 0\n DO1=1\n DELAY=50\n DO1=0\nEND\n\
                  PRG 1\n SR0=1\n DELAY=20\n SR0=2\n DELAY=100\n SR0=3\nEND\n";
    let (log, end, events) = run_with(source, Some(&[1]), 20, &mut controller(&[]));
    assert_eq!(
        log,
        [
            // Started, PRG 0 runs at once, not a round later.
            "DO1=1",
            "wait 20 ms",
            // Paused 20 ms into its 50 ms DELAY for 100 ms: the 30 ms left
            // run on only once continued, as on the controller.
            "wait 100 ms",
            "wait 30 ms",
            "DO1=0"
        ]
    );
    assert!(end.ok(), "{end}");
    assert!(
        events.iter().any(|e| e == "PRG 1 line 7: starts PRG 0"),
        "{events:?}"
    );
    assert!(
        events.iter().any(|e| e == "PRG 1 line 9: pauses PRG 0"),
        "{events:?}"
    );
    assert!(
        events.iter().any(|e| e == "PRG 1 line 11: continues PRG 0"),
        "{events:?}"
    );
    // SR0=0 stops it for good; a program stopping itself ends there.
    let source = "PRG 0\n DELAY=50\n DO1=0\nEND\nPRG 1\n SR0=0\n SR1=0\n DO2=1\nEND\n";
    let (log, end, _) = run_with(source, None, 5, &mut controller(&[]));
    assert_eq!(log, Vec::<String>::new());
    assert!(end.ok(), "{end}");
}

#[test]
fn a_program_left_paused_ends_the_run_and_says_so() {
    let source = "PRG 0\n DELAY=10\n DO1=1\nEND\nPRG 1\n SR0=2\nEND\n";
    let (log, end, _) = run_with(source, None, 10, &mut controller(&[]));
    assert_eq!(log, Vec::<String>::new());
    assert_eq!(end.paused, [0]);
    assert!(end.to_string().contains("PRG 0 left paused"), "{end}");
}

#[test]
fn delays_and_subroutines() {
    let source = "PRG 0\n GOSUB 2\n DELAY=V3\n GOSUB 2\nEND\nSUB 2\n V3=V3+250\n DO1=V3\nENDSUB\n";
    let (log, end, _) = run_with(source, None, 10, &mut controller(&[]));
    assert_eq!(log, ["DO1=250", "wait 250 ms", "DO1=500"]);
    assert!(end.ok());
}

#[test]
fn arithmetic_errors_and_missing_subroutines_are_runtime_errors() {
    let (_, end, _) = run_with("PRG 0\n V1=5/V2\nEND\n", None, 5, &mut controller(&[]));
    assert!(end.failures[0].contains("division by zero"), "{end}");
    let (_, end, _) = run_with("PRG 0\n GOSUB 4\nEND\n", None, 5, &mut controller(&[]));
    assert!(
        end.failures[0].contains("subroutine 4 is not defined"),
        "{end}"
    );
}

#[test]
fn a_command_without_an_answer_ends_the_whole_run() {
    let source = "PRG 0\n X1000\n DO1=1\nEND\nPRG 1\n DO2=1\nEND\n";
    let (log, end, _) = run_with(source, None, 5, &mut |line: &str| Answer {
        line: line.to_string(),
        frames: Vec::new(),
        result: Err(AnswerError::Lost {
            address: 1,
            reason: "no reply within 100 ms".into(),
        }),
    });
    assert_eq!(log, ["X1000"]);
    assert!(
        end.lost
            .as_deref()
            .is_some_and(|l| l.contains("X1000 got no answer")),
        "{end}"
    );
}

#[test]
fn a_loop_that_never_touches_the_wire_rests_between_turns() {
    let source = "PRG 0\n WHILE 1=1\n ENDWHILE\nEND\nPRG 1\n DO1=1\nEND\n";
    let checked = HostProgram::check("p.asc", source, None).expect("checks");
    let mut run = AScriptRun::new(&checked);
    let now = Duration::ZERO;
    // PRG 0 spins its budget, then PRG 1 gets its turn.
    assert_eq!(run.start(now), HostStep::Send("DO1=1".into()));
    assert_eq!(
        run.on_reply(&answer("DO1=1", ReplyValue::None), now),
        HostStep::Wake(YIELD)
    );
    assert_eq!(run.on_wake(now + YIELD), HostStep::Wake(YIELD));
}

#[test]
fn buffered_moves_go_as_i_at_the_global_high_speed() {
    let source = "PRG 1\n BUFON\n HSPD=300\n X1000Y100Z100\n ISTART\n BUFOFF\n X0\nEND\n";
    let (log, end, _) = run_with(source, None, 10, &mut controller(&[("HSPD", 300)]));
    assert_eq!(
        log,
        [
            "BO",
            "HSPD=300",
            "HSPD",
            "I1000:100:100:300",
            "BSTART",
            "BF",
            "X0"
        ]
    );
    assert!(end.ok());
}

#[test]
fn the_check_lists_every_problem_with_file_and_line_before_anything_runs() {
    let problems =
        HostProgram::check("p.asc", "PRG 0\n V200=1\n DO10=1\nEND\n", None).expect_err("errors");
    assert_eq!(problems.len(), 2, "{problems:?}");
    assert!(
        problems[0].starts_with("p.asc:2: Var Range Error"),
        "{}",
        problems[0]
    );
    assert!(
        problems[1].starts_with("p.asc:3: BIT Error"),
        "{}",
        problems[1]
    );
    let problems = HostProgram::check("p.asc", "PRG 0\n BUFON\n X1000\nEND\n", None)
        .expect_err("no ASCII equivalent");
    assert!(
        problems[0].starts_with("p.asc:3: `X1000` cannot run from the host"),
        "{problems:?}"
    );
    let problems =
        HostProgram::check("p.asc", "PRG 1\nEND\n", Some(&[0, 1])).expect_err("no PRG 0");
    assert!(
        problems[0].contains("there is no PRG 0 to start (the file defines PRG 1)"),
        "{problems:?}"
    );
    let problems = HostProgram::check("p.asc", "SUB 1\nENDSUB\n", None).expect_err("no PRG");
    assert!(problems[0].contains("no PRG block"), "{problems:?}");
    let checked = HostProgram::check("p.asc", "PRG 2\n GOSUB 9\nEND\nPRG 0\nEND\n", None)
        .expect("a warning is no error");
    assert_eq!(checked.start(), [0, 2]);
    assert_eq!(checked.started(), "PRG 0 and PRG 2");
    assert!(
        checked.warnings()[0].starts_with("p.asc:2: warning:"),
        "{:?}",
        checked.warnings()
    );
}

#[test]
fn the_threads_show_where_each_program_is() {
    let checked = HostProgram::check(
        "p.asc",
        "PRG 0\n DO1=1\nEND\nPRG 3\n DELAY=5\nEND\n",
        Some(&[3]),
    )
    .expect("checks");
    let mut run = AScriptRun::new(&checked);
    let now = Duration::ZERO;
    assert_eq!(run.start(now), HostStep::Wake(Duration::from_millis(5)));
    assert_eq!(
        run.threads(),
        [
            RunningPlace {
                program: 0,
                state: PlaceState::Idle,
                line: 2
            },
            RunningPlace {
                program: 3,
                state: PlaceState::Running,
                line: 5
            },
        ]
    );
}

mod arbitrary_answers {
    use super::*;
    use proptest::prelude::*;

    /// What a controller (or a broken link) may answer.
    fn any_answer() -> impl Strategy<Value = Answer> {
        prop_oneof![
            any::<i64>().prop_map(|n| answer("X", ReplyValue::Number(n))),
            Just(answer("X", ReplyValue::None)),
            "[ -~]{0,12}".prop_map(|t| answer("X", ReplyValue::Text(t))),
            "\\?[ -~]{0,12}".prop_map(|r| refused("X", &r)),
            Just(refused("X", "?Error Moving")),
            Just(Answer {
                line: "X".into(),
                frames: Vec::new(),
                result: Err(AnswerError::Refused("out of range".into())),
            }),
        ]
    }

    const PROGRAMS: &[&str] = &[
        "PRG 0\n HSPD=V1\n X1000\n WAITX\n V2=MSTX&7\n IF V2!=0\n  DO1=1\n ENDIF\n V3=V4/V2\nEND\nSUB 31\n ECLEARX\nENDSUB\n",
        "PRG 0\n WHILE DI1=1\n  XV1\n  WAITX\n  V1=V1+PX\n ENDWHILE\nEND\nPRG 1\n SR0=V5\n DELAY=V6\n GOSUB 2\nEND\nSUB 2\n V7=~AI1\nENDSUB\n",
        "PRG 2\n BUFON\n X1Y2Z3\n ISTART\n WAITX\n BUFOFF\nEND\n",
    ];

    proptest! {
        #[test]
        fn no_answer_breaks_the_run(
            which in 0..PROGRAMS.len(),
            answers in proptest::collection::vec(any_answer(), 0..60),
            waits in proptest::collection::vec(0u64..500, 0..60),
        ) {
            let checked = HostProgram::check("p.asc", PROGRAMS[which], None).expect("checks");
            let mut run = AScriptRun::new(&checked);
            let mut now = Duration::ZERO;
            let mut answers = answers.into_iter();
            let mut waits = waits.into_iter();
            let mut step = run.start(now);
            for _ in 0..200 {
                let _ = run.take_events();
                let _ = run.threads();
                step = match step {
                    HostStep::Send(_) => match answers.next() {
                        Some(result) => run.on_reply(&result, now),
                        None => break,
                    },
                    HostStep::Wake(after) => {
                        now += after + Duration::from_millis(waits.next().unwrap_or(0));
                        run.on_wake(now)
                    }
                    HostStep::Finished(end) => {
                        let _ = end.to_string();
                        break;
                    }
                };
            }
        }
    }
}
