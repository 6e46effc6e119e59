//! Every example line and reply of the MCCL manual
//! (tests/data/mccl-vectors.json, digest §20): the lines parse, format to
//! their canonical text, parse back the same, check without errors and
//! encode to that text and a CR; the replies read as the manual prints
//! them, after the echo and before the prompt, in the number base the
//! examples before them set (DM/HM).
//!
//! Where the manual misprints a line or a reply, the misprint is not
//! enshrined: it is checked to be refused, with the reason (the list
//! `MISPRINTS` names each and why).

use axterm::protocol::mccl::check::check_file;
use axterm::protocol::mccl::line::comment_start;
use axterm::protocol::mccl::reply::{Printed, ReplyProblem};
use axterm::protocol::mccl::status::{StatusWord, StatusWordKind};
use axterm::protocol::mccl::{
    CheckContext, DEFAULT_MACHINE, LinkProfile, LinkState, NumberBase, Severity, check_text,
    encode_line, parse_line, read_reply,
};
use serde_json::Value;
use std::collections::BTreeSet;

struct Vector {
    index: usize,
    section: String,
    send: String,
    reply: Option<String>,
    note: String,
}

fn vectors() -> Vec<Vector> {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/mccl-vectors.json"
    ))
    .expect("the vectors file");
    let entries: Vec<Value> = serde_json::from_str(&text).expect("JSON");
    entries
        .iter()
        .enumerate()
        .filter_map(|(index, e)| {
            let text = |key: &str| e.get(key).and_then(Value::as_str).map(str::to_string);
            Some(Vector {
                index,
                section: text("section")?,
                send: text("send")?,
                reply: text("reply"),
                note: text("note").unwrap_or_default(),
            })
        })
        .collect()
}

const CONTEXT: CheckContext = CheckContext {
    machine: &DEFAULT_MACHINE,
    profile: &LinkProfile::MANUAL,
};

/// Lines the manual misprints, and why they are not a line to send.
const MISPRINTS: &[(&str, &str)] = &[
    // Ch5 FR: "n = integer >= 0", period (n + 1) × sample period; these
    // examples give seconds (digest §19 #13).
    ("1FR0.00025", "FR takes an integer"),
    ("2FR0.0015", "FR takes an integer"),
    // Ch5 EI: "issuing it via WinControl will cause a malfunction".
    ("1EI9", "malfunction"),
];

/// Keystrokes, not lines (`<Enter>`, `<Esc>`, `<Space>`).
fn is_keystroke(send: &str) -> bool {
    send.starts_with('<') && send.ends_with('>')
}

/// Text files print their lines with `;` comments; the sends with OCR
/// glyphs kept "exactly as printed" (digest §20) are checked apart.
fn is_file(v: &Vector) -> bool {
    v.send.contains('\n') || v.send.trim_start().starts_with(';')
}

fn as_printed(v: &Vector) -> bool {
    is_file(v) && v.note.contains("OCR glyph")
}

/// The text in upper case and without blanks, except inside strings.
fn upper_outside_strings(text: &str) -> String {
    let mut out = String::new();
    let mut in_string = false;
    for c in text.chars() {
        if c == '"' {
            in_string = !in_string;
        }
        if in_string {
            out.push(c);
        } else if c != ' ' {
            out.push(c.to_ascii_uppercase());
        }
    }
    out
}

#[test]
fn every_line_of_the_manual_parses_formats_checks_and_encodes() {
    let mut seen = 0;
    for v in vectors() {
        if is_keystroke(&v.send) || is_file(&v) {
            continue;
        }
        let where_ = format!("#{} {} `{}`", v.index, v.section, v.send);
        let line =
            parse_line(&v.send, NumberBase::Decimal).unwrap_or_else(|e| panic!("{where_}: {e}"));
        let canonical = line.to_string();
        assert_eq!(canonical, upper_outside_strings(&v.send), "{where_}");
        assert_eq!(
            parse_line(&canonical, NumberBase::Decimal).as_ref(),
            Ok(&line),
            "{where_}"
        );
        let errors: Vec<String> = check_text(&v.send, NumberBase::Decimal, &CONTEXT)
            .into_iter()
            .filter(|d| d.severity == Severity::Error)
            .map(|d| d.message)
            .collect();
        if let Some((_, why)) = MISPRINTS.iter().find(|(send, _)| *send == v.send) {
            assert!(
                errors.iter().any(|e| e.contains(why)),
                "{where_}: {errors:?}"
            );
            let refused = encode_line(&v.send, None).expect_err(&where_).to_string();
            assert!(refused.contains(why), "{where_}: {refused}");
            continue;
        }
        assert!(errors.is_empty(), "{where_}: {errors:?}");
        match encode_line(&v.send, None) {
            Ok(bytes) => assert_eq!(bytes, format!("{canonical}\r").into_bytes(), "{where_}"),
            // The console reads every line in decimal: it does not send
            // HM, which would switch the lines after it to hexadecimal.
            Err(e) => assert!(
                canonical == "HM" && e.to_string().contains("hexadecimal"),
                "{where_}: {e}"
            ),
        }
        seen += 1;
    }
    assert!(seen > 370, "{seen} single lines");
}

#[test]
fn text_files_send_their_lines_without_comments() {
    let mut files = 0;
    for v in vectors()
        .into_iter()
        .filter(|v| is_file(v) && !as_printed(v))
    {
        files += 1;
        let found = check_file(&v.send, &CONTEXT, &BTreeSet::new());
        let errors: Vec<_> = found
            .iter()
            .filter(|(_, d)| d.severity == Severity::Error)
            .collect();
        assert!(errors.is_empty(), "#{}: {errors:?}", v.index);
        for raw in v.send.lines() {
            let body = raw[..comment_start(raw).unwrap_or(raw.len())].trim();
            if body.is_empty() {
                continue;
            }
            let bytes =
                encode_line(raw, None).unwrap_or_else(|e| panic!("#{} `{raw}`: {e}", v.index));
            assert!(
                !bytes.contains(&b';'),
                "comments are not sent: #{} {raw}",
                v.index
            );
            assert_eq!(bytes.last(), Some(&b'\r'));
        }
    }
    assert_eq!(files, 4, "Ch4 multitasking, Ch7 CB and IA, Ch13 OT");
}

#[test]
fn text_files_download_line_by_line_as_the_program_tool_checks_them() {
    use axterm::protocol::console::{Reading, ReplyValue};
    use axterm::protocol::mccl::MclTool;
    use axterm::protocol::program::{Answer, NoIncludes, PlanStep, ProgramTool};
    for v in vectors()
        .into_iter()
        .filter(|v| is_file(v) && !as_printed(v))
    {
        let checked = MclTool.check("manual.mccl", &v.send, &NoIncludes);
        let program = checked
            .program
            .unwrap_or_else(|| panic!("#{}: {:?}", v.index, checked.problems));
        let expected: Vec<Vec<u8>> = v
            .send
            .lines()
            .filter(|raw| {
                !raw[..comment_start(raw).unwrap_or(raw.len())]
                    .trim()
                    .is_empty()
            })
            .map(|raw| encode_line(raw, None).expect("encodes"))
            .collect();
        assert_eq!(program.size(), expected.len(), "#{}", v.index);
        let mut plan = program
            .download(0, Default::default())
            .expect("a download plan");
        let mut sent = Vec::new();
        while sent.len() < expected.len() {
            let PlanStep::Send(line) = plan.next() else {
                panic!("#{}: stopped after {sent:?}", v.index);
            };
            sent.push(line.line.bytes);
            plan.answer(Answer {
                line: String::new(),
                frames: Vec::new(),
                result: Ok(Reading {
                    status: None,
                    value: ReplyValue::None,
                }),
            });
        }
        assert_eq!(sent, expected, "#{}: one line at a time, in order", v.index);
    }
}

#[test]
fn files_printed_with_ocr_glyphs_are_refused_with_the_fix() {
    let printed: Vec<Vector> = vectors().into_iter().filter(as_printed).collect();
    assert_eq!(printed.len(), 2, "the FE and FI homing files (Ch7)");
    for v in printed {
        let found = check_file(&v.send, &CONTEXT, &BTreeSet::new());
        let errors: Vec<&str> = found
            .iter()
            .filter(|(_, d)| d.severity == Severity::Error)
            .map(|(_, d)| d.message.as_str())
            .collect();
        assert!(!errors.is_empty(), "#{}", v.index);
        for error in &errors {
            assert!(error.contains("did you mean"), "#{}: {error}", v.index);
        }
        assert!(
            errors
                .iter()
                .any(|e| e.contains("`N0`") && e.contains("`NO`"))
        );
    }
}

/// The reply of a vector as the controller sends it: the echo of the line
/// sent, the reply lines, the prompt.
fn answer(sent: &str, reply: &str) -> Vec<Vec<u8>> {
    std::iter::once(sent)
        .chain(reply.lines())
        .chain(std::iter::once(">"))
        .map(|l| l.as_bytes().to_vec())
        .collect()
}

/// What a reply line says: a value after its field (a hexadecimal one as
/// its number), or the line itself.
fn expected(reply: &str, base: NumberBase) -> Vec<String> {
    reply
        .lines()
        .map(|l| match l.split_once(' ') {
            Some((field, value))
                if field.len() == 2 && field.bytes().all(|b| b.is_ascii_digit()) =>
            {
                match base {
                    NumberBase::Decimal => value.trim().to_string(),
                    NumberBase::Hex => i64::from_str_radix(value.trim(), 16)
                        .map_or_else(|_| value.to_string(), |n| n.to_string()),
                }
            }
            _ => l.to_string(),
        })
        .collect()
}

#[test]
fn every_reply_of_the_manual_reads_as_printed() {
    let profile = LinkProfile::MANUAL;
    let mut state = LinkState::new(&profile);
    let mut section = String::new();
    let mut read = 0;
    for v in vectors() {
        if v.section != section {
            section = v.section.clone();
            state = LinkState::new(&profile);
        }
        if is_keystroke(&v.send) || is_file(&v) {
            continue;
        }
        let line = parse_line(&v.send, state.base).expect(&v.send);
        let sent = line.to_string();
        let where_ = format!("#{} {} `{}`", v.index, v.section, v.send);
        if let Some(reply) = &v.reply {
            let result = read_reply(&line, &sent, &state, &profile, &answer(&sent, reply));
            if reply.contains("{C") {
                // Single-step displays (Ch4): `{C1,MC10} 1MR1000 <` is no
                // reply of the line; the console does not single-step.
            } else if sent == "1SD.4" {
                // Ch8 TD prints a Set command before the reply (digest §19
                // #19): SD reports nothing, so the line is refused.
                assert!(
                    matches!(result, Err(ReplyProblem::Unexpected { .. })),
                    "{where_}: {result:?}"
                );
            } else if reply == "01 100000409" {
                // Ch8 TS: 9 hex digits for 0x10000409 (digest §19 #18).
                assert!(
                    matches!(result, Err(ReplyProblem::BadValue { .. })),
                    "{where_}: {result:?}"
                );
            } else {
                let reply_read = result.unwrap_or_else(|e| panic!("{where_}: {e}"));
                let got: Vec<String> = reply_read
                    .reports
                    .iter()
                    .flat_map(|r| match &r.printed {
                        Printed::Value(told) => vec![told.value.to_string()],
                        Printed::Text(lines) => lines.clone(),
                    })
                    .collect();
                assert_eq!(got, expected(reply, state.base), "{where_}");
                assert!(reply_read.error.is_none());
                read += 1;
            }
        }
        state.after(&line, &profile);
    }
    assert!(read >= 28, "{read} replies");
}

#[test]
fn the_status_words_printed_decode_bit_by_bit() {
    // Ch8 TS: bit 28 limit + input, bit 10 hard limit +, bit 3 trajectory
    // complete, bit 0 motor error.
    let word = StatusWord::new(StatusWordKind::Primary, 268_436_489);
    assert_eq!(
        word.set_bits().map(|b| b.bit).collect::<Vec<_>>(),
        [0, 3, 10, 28]
    );
    // Ch13 DM/HM: 10 = trajectory complete (bit 3) + motor on (bit 1), in
    // decimal `01 10` and in hex `01 0000000a`.
    let profile = LinkProfile::MANUAL;
    let mut state = LinkState::new(&profile);
    let ts = parse_line("1TS", NumberBase::Decimal).expect("1TS");
    let decimal = read_reply(&ts, "1TS", &state, &profile, &answer("1TS", "01 10")).expect("dm");
    state.after(
        &parse_line("HM", NumberBase::Decimal).expect("HM"),
        &profile,
    );
    let hex = read_reply(&ts, "1TS", &state, &profile, &answer("1TS", "01 0000000a")).expect("hm");
    assert_eq!(decimal.reports, hex.reports);
    // Read in the wrong base, each is refused rather than misread.
    assert!(read_reply(&ts, "1TS", &state, &profile, &answer("1TS", "01 1O")).is_err());
    let dm = LinkState::new(&profile);
    assert!(read_reply(&ts, "1TS", &dm, &profile, &answer("1TS", "01 0000000a")).is_err());
}
