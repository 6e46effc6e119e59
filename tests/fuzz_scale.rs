//! Fuzzing of every decoder and parser: no input makes axterm panic.
//!
//! For every family in `families::FAMILIES`: its console-line parser
//! (`encode_line`, `FamilyConsole::prepare`, completion and help), its
//! framer, its reply rules and reply reader (`interpret`, status updates,
//! the traffic monitor's decoders), the batch-file parser on its lines;
//! for every simulator in `axterm::families::kinds()`: its request decoder; and the
//! program tools: the TMCL assembler (with includes, listing, image and
//! disassembler) and the A-Script compiler; the parameter-file reader.
//!
//! `cargo test` runs it small ([`fuzz_support::SMOKE_CASES`] inputs per
//! target and family). At scale, by hand (see `fuzz/run`):
//! `AXTERM_FUZZ_CASES=10000000 cargo test --release --test fuzz_scale --
//! --nocapture --test-threads=1`; `AXTERM_FUZZ_SEED` picks another run.

mod fuzz_support;

use std::collections::BTreeMap;
use std::sync::OnceLock;
use std::time::Duration;

use axterm::families::FAMILIES;
use axterm::families::kinds;
use axterm::protocol::cmd4cr::ascript;
use axterm::protocol::console::Answering;
use axterm::protocol::program::NoIncludes;
use axterm::protocol::tmcl::asm::{self, ProgramWord};
use axterm::protocol::wire::Verdict;
use axterm::script::check_script;
use axterm::sim::SimOptions;
use fuzz_support::{
    FamilyCorpus, Report, Rng, assert_no_panics, bend_document, bend_text, cases, chunks,
    noise_text, run, seed, text_of_lines,
};

/// Every family's corpus, built once per test binary.
fn corpora() -> &'static [FamilyCorpus] {
    static CORPORA: OnceLock<Vec<FamilyCorpus>> = OnceLock::new();
    CORPORA.get_or_init(|| {
        FAMILIES
            .iter()
            .map(|family| {
                let corpus = FamilyCorpus::build(family);
                eprintln!("fuzz corpus {}", corpus.summary());
                corpus
            })
            .collect()
    })
}

#[test]
fn every_family_has_a_corpus_to_start_from() {
    for corpus in corpora() {
        // Too few to start from: give the family completion, parameter
        // tables or tests/data/FAMILY-vectors.json.
        assert!(
            corpus.lines.len() >= 5,
            "{}: only {} valid lines found",
            corpus.family.name,
            corpus.lines.len()
        );
        assert!(!corpus.frames.is_empty(), "{}", corpus.summary());
    }
}

#[test]
fn console_lines_never_panic() {
    let reports: Vec<Report> = corpora()
        .iter()
        .map(|corpus| {
            let family = corpus.family;
            let console = family.console;
            run(
                "console-line",
                family.name,
                cases(),
                seed(),
                |rng| {
                    let line = corpus.line(rng);
                    let bounds: Vec<usize> = line
                        .char_indices()
                        .map(|(i, _)| i)
                        .chain([line.len()])
                        .collect();
                    let cursor = rng.pick(&bounds).copied().unwrap_or(0);
                    let address = if rng.chance(80) {
                        corpus.address
                    } else {
                        rng.byte()
                    };
                    (line, cursor, address)
                },
                |(line, cursor, address)| {
                    let _ = (family.encode_line)(line, Some(*address));
                    let _ = (family.encode_line)(line, None);
                    let _ = console.complete(line, *cursor);
                    let _ = console.help(line, *cursor);
                    let Ok(prepared) = console.prepare(line, *address) else {
                        return false;
                    };
                    let _ = (family.show_bytes)(&prepared.bytes);
                    let _ = console.describe_request(&prepared.bytes);
                    true
                },
            )
        })
        .collect();
    assert_no_panics(&reports);
}

#[test]
fn framers_never_panic() {
    let reports: Vec<Report> = corpora()
        .iter()
        .map(|corpus| {
            let family = corpus.family;
            let wire = family.console.wire();
            run(
                "framer",
                family.name,
                cases(),
                seed(),
                |rng| {
                    let stream = corpus.stream(rng);
                    let discard_after = rng.below(stream.len() + 2);
                    (stream, discard_after)
                },
                |(stream, discard_after)| {
                    let mut framer = wire.framer();
                    let mut cut = false;
                    for (index, chunk) in stream.iter().enumerate() {
                        for frame in framer.push(chunk) {
                            cut = true;
                            let _ = wire.unsolicited(&frame);
                            let _ = (family.show_bytes)(&frame);
                        }
                        let _ = framer.take_skipped();
                        let _ = framer.pending();
                        if index == *discard_after {
                            let _ = framer.discard_pending();
                        }
                    }
                    let _ = wire.silence(Some(Duration::from_micros(1042)));
                    cut
                },
            )
        })
        .collect();
    assert_no_panics(&reports);
}

#[test]
fn reply_readers_never_panic() {
    let reports: Vec<Report> = corpora()
        .iter()
        .map(|corpus| {
            let family = corpus.family;
            let console = family.console;
            let wire = console.wire();
            run(
                "reply-reader",
                family.name,
                cases(),
                seed(),
                |rng| {
                    let index = rng.below(corpus.lines.len());
                    let answer = corpus.answers.get(index).cloned().unwrap_or_default();
                    let mut frames = Vec::new();
                    for _ in 0..=rng.below(4) {
                        let frame = match (rng.below(3), rng.pick(&answer)) {
                            (0, Some(real)) => real.clone(),
                            (1, Some(real)) => {
                                let mut frame = real.clone();
                                for _ in 0..=rng.below(2) {
                                    frame = fuzz_support::bend_bytes(rng, &frame);
                                }
                                frame
                            }
                            _ => corpus.frame(rng),
                        };
                        frames.push(frame);
                    }
                    let request = corpus.frame(rng);
                    let request = fuzz_support::bend_bytes(rng, &request);
                    (index, frames, request)
                },
                |(index, frames, request)| {
                    let Some((_, line)) = corpus.lines.get(*index) else {
                        return false;
                    };
                    let mut read = false;
                    // As the device task matches an answer, frame by frame.
                    let rule = match &line.answering {
                        Answering::Reply(rule)
                        | Answering::MaybeReply(rule)
                        | Answering::Later { rule, .. } => Some(rule),
                        Answering::Nothing => None,
                    };
                    let mut accepted = Vec::new();
                    for frame in frames {
                        let _ = console.describe_reply(frame, Some(&line.bytes));
                        let _ = console.describe_reply(frame, None);
                        let Some(rule) = rule else {
                            let _ = wire.unsolicited(frame);
                            continue;
                        };
                        match rule.examine(&accepted, frame) {
                            Verdict::Complete | Verdict::CompleteIfQuiet => {
                                accepted.push(frame.clone());
                                if let Ok(reading) = console.interpret(line, &accepted) {
                                    let _ = console.status_update(line, &reading);
                                    read = true;
                                }
                                accepted.clear();
                            }
                            Verdict::Continue => accepted.push(frame.clone()),
                            Verdict::NotMine => {
                                let _ = wire.unsolicited(frame);
                            }
                        }
                    }
                    if matches!(line.answering, Answering::MaybeReply(_)) {
                        let _ = console.interpret(line, &[]);
                    }
                    let _ = console.describe_request(request);
                    read
                },
            )
        })
        .collect();
    assert_no_panics(&reports);
}

#[test]
fn batch_files_never_panic() {
    const DURATIONS: &[&str] = &[
        "500ms",
        "2s",
        "1.5s",
        "1m",
        "0s",
        "0ms",
        "-1s",
        "1e3s",
        "ms",
        "1 s",
        "18446744073709551616ms",
        "99999999999m",
        "0.0000001s",
        "NaNs",
        "infs",
    ];
    let reports: Vec<Report> = corpora()
        .iter()
        .map(|corpus| {
            let family = corpus.family;
            run(
                "batch-file",
                family.name,
                cases(),
                seed(),
                |rng| {
                    let text = text_of_lines(rng, 12, |rng| {
                        let line = corpus.line(rng);
                        let number = rng.pick(fuzz_support::EDGE_NUMBERS).copied().unwrap_or("0");
                        let duration = rng.pick(DURATIONS).copied().unwrap_or("1s");
                        let directive = match rng.below(12) {
                            0 => format!(":expect {line} == {number}"),
                            1 => format!(":wait-until {line} == {number} timeout {duration}"),
                            2 => format!(":wait-until {line} == {number}"),
                            3 => format!(":sleep {duration}"),
                            4 => format!(":echo {line}"),
                            5 => format!("# {line}"),
                            6 => format!("// {line}"),
                            7 => String::new(),
                            8 => format!(":{}", noise_text(rng, 12)),
                            _ => return line,
                        };
                        if rng.chance(30) {
                            bend_text(rng, &directive, &corpus.words)
                        } else {
                            directive
                        }
                    });
                    (text, rng.byte())
                },
                |(text, address)| {
                    let _ = check_script("fuzz.txt", text, family, *address);
                    check_script("fuzz.txt", text, family, corpus.address).is_ok()
                },
            )
        })
        .collect();
    assert_no_panics(&reports);
}

#[test]
fn simulators_never_panic_on_what_they_are_sent() {
    let reports: Vec<Report> = kinds()
        .filter_map(|kind| {
            let family = axterm::families::family_of(kind)?;
            let corpus = corpora().iter().find(|c| c.family.name == family.name)?;
            let inputs = (kind.input_names)();
            Some(run(
                "simulator",
                kind.name,
                cases(),
                seed(),
                |rng| {
                    let mut steps = Vec::new();
                    for _ in 0..=rng.below(4) {
                        let bytes = match rng.below(3) {
                            0 => corpus
                                .lines
                                .get(rng.below(corpus.lines.len()))
                                .map(|(_, p)| p.bytes.clone())
                                .unwrap_or_default(),
                            _ => corpus.frame(rng),
                        };
                        let setting = rng.chance(5).then(|| {
                            let name = rng.pick(&inputs).cloned().unwrap_or_default();
                            bend_text(rng, &format!("{name}=1"), &corpus.words)
                        });
                        steps.push((chunks(rng, &bytes), rng.below(30) as u64, setting));
                    }
                    steps
                },
                |steps| {
                    let mut sim = (kind.build)(&SimOptions {
                        address: Some(corpus.address),
                        eeprom_file: None,
                    });
                    let mut answered = false;
                    for (chunks, millis, setting) in steps {
                        for chunk in chunks {
                            sim.feed(chunk);
                        }
                        if let Some(setting) = setting {
                            let _ = sim.drive_input(setting);
                        }
                        sim.advance(Duration::from_millis(*millis));
                        answered |= !sim.take_output().is_empty();
                    }
                    answered
                },
            ))
        })
        .collect();
    assert_no_panics(&reports);
}

/// Lines of TMCL program source: the manual's example programs, the
/// family's valid console lines, labels, constants and includes.
fn tmcl_program_lines() -> &'static (Vec<String>, BTreeMap<String, String>) {
    static LINES: OnceLock<(Vec<String>, BTreeMap<String, String>)> = OnceLock::new();
    LINES.get_or_init(|| {
        let dir = format!("{}/tests/data/programs", env!("CARGO_MANIFEST_DIR"));
        let mut lines = Vec::new();
        let mut files = BTreeMap::new();
        for entry in std::fs::read_dir(&dir)
            .expect("tests/data/programs")
            .flatten()
        {
            let name = entry.file_name().to_string_lossy().into_owned();
            let text = std::fs::read_to_string(entry.path()).expect("program");
            lines.extend(text.lines().map(str::to_string));
            files.insert(name, text);
        }
        if let Some(tmcl) = corpora().iter().find(|c| c.family.name == "tmcl") {
            lines.extend(tmcl.lines.iter().map(|(l, _)| l.clone()));
        }
        lines.extend(
            [
                "Loop:",
                "  JA Loop",
                "Speed = 1000",
                "Max = 0x7FFFFFFF",
                "Alias = Speed",
                "Sub: RSUB",
                "CSUB Sub",
                "#include a.inc",
                "#include \"b.inc\"",
                "#include cycle.inc",
                "#include missing.inc",
                "#include ../up.inc",
                "#include",
                "#pragma x",
                "// comment",
                "STOP",
            ]
            .map(str::to_string),
        );
        files.insert("a.inc".into(), "Inc: SAP 4, 0, Speed\nRSUB\n".into());
        files.insert("b.inc".into(), "#include a.inc\nSpeed = 1000\n".into());
        files.insert("cycle.inc".into(), "#include cycle.inc\n".into());
        (lines, files)
    })
}

#[test]
fn the_tmcl_assembler_never_panics() {
    let (lines, files) = tmcl_program_lines();
    let words: Vec<String> = lines
        .iter()
        .flat_map(|l| l.split([' ', ',']).map(str::to_string))
        .filter(|w| !w.is_empty())
        .chain(fuzz_support::EDGE_NUMBERS.iter().map(|s| (*s).to_string()))
        .collect();
    let programs: Vec<&str> = files.values().map(String::as_str).collect();
    let report = run(
        "assembler",
        "tmcl",
        cases(),
        seed(),
        |rng| {
            if rng.chance(10) {
                return (noise_text(rng, 200), true);
            }
            if rng.chance(60) {
                let program = rng.pick(&programs).copied().unwrap_or("");
                return (bend_document(rng, program, lines, &words), rng.chance(5));
            }
            let source = text_of_lines(rng, 24, |rng| {
                let line = rng.pick(lines).cloned().unwrap_or_default();
                if rng.chance(35) {
                    bend_text(rng, &line, &words)
                } else {
                    line
                }
            });
            (source, rng.chance(5))
        },
        |(source, as_image)| {
            if *as_image && let Ok(words) = asm::parse_image(source) {
                let _ = asm::disassemble(&words);
            }
            match asm::assemble("main.tmc", source, files) {
                Ok(program) => {
                    let _ = asm::listing(&program);
                    let image = asm::format_image(&program.words);
                    if let Ok(words) = asm::parse_image(&image) {
                        let _ = asm::disassemble(&words);
                    }
                    true
                }
                Err(errors) => {
                    for error in errors {
                        let _ = error.to_string();
                    }
                    false
                }
            }
        },
    );
    let words_report = run(
        "disassembler",
        "tmcl",
        cases(),
        seed(),
        |rng| {
            let mut words = Vec::new();
            for _ in 0..=rng.below(16) {
                let value = rng.next_u64();
                words.push(ProgramWord {
                    opcode: rng.byte(),
                    kind: rng.byte(),
                    motor_bank: rng.byte(),
                    value: value as i32,
                });
            }
            words
        },
        |words| {
            let text = asm::disassemble(words);
            let _ = asm::parse_image(&asm::format_image(words));
            asm::assemble("disassembled.tmc", &text, &asm::NoIncludes).is_ok()
        },
    );
    assert_no_panics(&[report, words_report]);
}

#[test]
fn the_ascript_compiler_never_panics() {
    let Some(corpus) = corpora().iter().find(|c| c.family.name == "cmd4cr") else {
        return;
    };
    let mut lines: Vec<String> = corpus
        .texts
        .iter()
        .flat_map(|t| t.lines().map(str::to_string))
        .collect();
    lines.extend(corpus.lines.iter().map(|(l, _)| l.clone()));
    lines.extend(
        [
            "PRG 0",
            "PRG 1",
            "PRG 3",
            "PRG 4",
            "END",
            "SUB 1",
            "SUB 31",
            "ENDSUB",
            "GOSUB 1",
            "IF V1=1",
            "ELSEIF V2>3",
            "ELSE",
            "ENDIF",
            "WHILE V1<10",
            "ENDWHILE",
            "V1=V2+3",
            "V99=V0*V1",
            "V1=-2147483648",
            "DELAY=100",
            "WAITX",
            "SR0=1",
            "JUMP 1",
            "; comment",
        ]
        .map(str::to_string),
    );
    let words: Vec<String> = lines
        .iter()
        .flat_map(|l| l.split([' ', '=', ',']).map(str::to_string))
        .filter(|w| !w.is_empty())
        .chain(fuzz_support::EDGE_NUMBERS.iter().map(|s| (*s).to_string()))
        .collect();
    // The manual's example programs (§5.4), whole.
    let programs: Vec<&str> = corpus
        .texts
        .iter()
        .filter(|t| t.contains("PRG") && t.contains("END"))
        .map(String::as_str)
        .collect();
    assert!(!programs.is_empty(), "no A-Script example in the vectors");
    let report = run(
        "ascript-compiler",
        "cmd4cr",
        cases(),
        seed(),
        |rng| {
            if rng.chance(10) {
                return noise_text(rng, 200);
            }
            if rng.chance(60) {
                let program = rng.pick(&programs).copied().unwrap_or("");
                return bend_document(rng, program, &lines, &words);
            }
            text_of_lines(rng, 30, |rng| {
                let line = rng.pick(&lines).cloned().unwrap_or_default();
                if rng.chance(35) {
                    bend_text(rng, &line, &words)
                } else {
                    line
                }
            })
        },
        |source| {
            let _ = ascript::tokens(source.lines().next().unwrap_or(""));
            ascript::compile(source).is_ok()
        },
    );
    assert_no_panics(&[report]);
}

/// Every family's program tool (TMCL programs, A-Script, SQPack macro
/// files, MCCL text files…) checks, colours and annotates any text without
/// a panic: documents of the family's own lines, of what the tool records
/// for the frames it is sent, and the manual's texts, bent.
#[test]
fn program_tools_never_panic() {
    let mut reports = Vec::new();
    for corpus in corpora() {
        let Some(tool) = corpus.family.console.program() else {
            continue;
        };
        let mut lines: Vec<String> = corpus.lines.iter().map(|(l, _)| l.clone()).collect();
        lines.extend(
            corpus
                .lines
                .iter()
                .filter_map(|(_, prepared)| tool.record(&prepared.bytes)),
        );
        lines.extend(
            corpus
                .texts
                .iter()
                .flat_map(|t| t.lines().map(str::to_string)),
        );
        let words: Vec<String> = corpus
            .words
            .iter()
            .cloned()
            .chain(fuzz_support::EDGE_NUMBERS.iter().map(|s| (*s).to_string()))
            .collect();
        let texts: Vec<&str> = corpus.texts.iter().map(String::as_str).collect();
        reports.push(run(
            "program-tool",
            corpus.family.name,
            cases(),
            seed(),
            |rng| {
                if rng.chance(10) {
                    return noise_text(rng, 200);
                }
                if rng.chance(30)
                    && let Some(text) = rng.pick(&texts)
                {
                    return bend_document(rng, text, &lines, &words);
                }
                text_of_lines(rng, 30, |rng| {
                    let line = rng.pick(&lines).cloned().unwrap_or_default();
                    if rng.chance(35) {
                        bend_text(rng, &line, &words)
                    } else {
                        line
                    }
                })
            },
            |source| {
                let checked = tool.check("fuzz", source, &NoIncludes);
                let shown: Vec<String> = source.lines().map(str::to_string).collect();
                let _ = tool.highlight(&shown, 0..shown.len());
                let _ = tool.annotations(&shown, 0..shown.len());
                for (row, line) in shown.iter().enumerate().take(4) {
                    let _ = tool.variable_on_line(line, row % (line.len() + 1));
                }
                checked.program.is_some()
            },
        ));
    }
    assert_no_panics(&reports);
}

#[test]
fn parameter_files_never_panic() {
    use axterm::protocol::parameter_file::{Exported, parse, render};
    // Files as the console writes them, for every family with parameters.
    let mut lines: Vec<String> = Vec::new();
    let mut files: Vec<String> = Vec::new();
    for corpus in corpora() {
        let console = corpus.family.console;
        let Some(parameters) = console.parameters() else {
            continue;
        };
        for axis in console.axes() {
            let tables = parameters.tables(axis.number);
            let rows: Vec<Exported> = tables
                .iter()
                .flat_map(|t| &t.rows)
                .map(|row| Exported {
                    row,
                    value: Ok(row.default.unwrap_or(0)),
                })
                .collect();
            let text = render(corpus.family.name, &["fuzz".to_string()], &rows);
            lines.extend(text.lines().map(str::to_string));
            files.push(text);
        }
    }
    lines.sort();
    lines.dedup();
    lines.extend(
        [
            "x = [1, 2]",
            "y = { a = 1 }",
            "z = \"text\"",
            "w = 1.5",
            "[axis.999]",
            "[bank]",
        ]
        .map(str::to_string),
    );
    let words = &corpora()[0].words;
    let report = run(
        "parameter-file",
        "every family",
        cases(),
        seed(),
        |rng: &mut Rng| {
            if rng.chance(70) {
                let file = rng.pick(&files).cloned().unwrap_or_default();
                return bend_document(rng, &file, &lines, words);
            }
            text_of_lines(rng, 16, |rng| {
                let line = rng.pick(&lines).cloned().unwrap_or_default();
                if rng.chance(40) {
                    bend_text(rng, &line, words)
                } else {
                    line
                }
            })
        },
        |text| parse(text).is_ok_and(|file| !file.entries.is_empty()),
    );
    assert_no_panics(&[report]);
}
