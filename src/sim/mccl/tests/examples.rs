//! The manual's example lines and text files (mccl-vectors.json): every
//! line reads, and the downloadable files run as a host would send them
//! (comments stripped, a line at a time, each to its prompt).

use super::*;
use crate::sim::mccl::axis::status;
use crate::sim::mccl::lexer::{Radix, lex};

const VECTORS: &str = include_str!("../../../../tests/data/mccl-vectors.json");

fn vectors() -> Vec<serde_json::Value> {
    let all: serde_json::Value = serde_json::from_str(VECTORS).expect("vectors");
    all.as_array().cloned().unwrap_or_default()
}

/// A line without its `;` comment (outside quotes, Ch4 "Downloading MCCL
/// Text Files"), trimmed.
fn without_comment(line: &str) -> &str {
    let mut quoted = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => quoted = !quoted,
            ';' if !quoted => return line[..i].trim(),
            _ => {}
        }
    }
    line.trim()
}

/// The command lines of a vector's `send`: comments and blank lines and
/// keystrokes (`<Enter>`) left out.
fn command_lines(send: &str) -> Vec<&str> {
    send.lines()
        .map(without_comment)
        .filter(|l| !l.is_empty() && !l.starts_with('<'))
        .collect()
}

/// The manual prints these with OCR look-alikes kept (the note says so):
/// `5D10`, `N0`, `1G0` are no commands, and the simulator says so.
fn ocr_kept(vector: &serde_json::Value) -> bool {
    let note = vector["note"].as_str().unwrap_or_default().to_lowercase();
    note.contains("as printed") && note.contains("ocr")
}

#[test]
fn every_example_line_of_the_manual_reads() {
    let mut read = 0;
    for (i, vector) in vectors().iter().enumerate() {
        let send = vector["send"].as_str().unwrap_or_default();
        for line in command_lines(send) {
            match lex(line, Radix::Decimal) {
                Ok(_) => read += 1,
                Err(e) if ocr_kept(vector) => assert_eq!(e.code.0, 1, "{i} {line}"),
                Err(e) => panic!("vector {i}: {line}: {e:?}"),
            }
        }
    }
    assert!(read > 400, "{read} lines");
}

/// Download `lines` as WinControl's File-Open would: each line to its
/// prompt, calling `while_running` every millisecond a line runs; the
/// error replies.
fn download(
    s: &mut Session,
    lines: &[&str],
    mut while_running: impl FnMut(&mut Session, u64),
) -> Vec<String> {
    let mut errors = Vec::new();
    for line in lines {
        let mut out = s.typed(&format!("{line}\r"));
        let mut ms = 0;
        while s.sim.busy() {
            while_running(s, ms);
            out.push_str(&s.advance_ms(1));
            ms += 1;
            assert!(ms < 30_000, "{line} still runs");
        }
        errors.extend(
            out.split("\r\n")
                .filter(|l| l.starts_with('?'))
                .map(str::to_string),
        );
    }
    errors
}

fn vector_lines(index: usize) -> Vec<String> {
    let all = vectors();
    command_lines(all[index]["send"].as_str().unwrap_or_default())
        .into_iter()
        .map(str::to_string)
        .collect()
}

#[test]
fn the_multitasking_example_file_runs() {
    // Vector 28 (Ch4 "MCCL Multi-Tasking"), as printed: `AR@100` stores the
    // task ID through R100 (which holds 0, so into the accumulator
    // itself): ET@100 then names task 0 and fails in the task, which
    // ends with it (digest §19 #5).
    let mut s = Session::new();
    s.quiet(&["1MN,1SE0"]);
    let lines = vector_lines(28);
    let lines: Vec<&str> = lines.iter().map(String::as_str).collect();
    assert_eq!(download(&mut s, &lines, |_, _| {}), Vec::<String>::new());
    s.advance_ms(100);
    assert!(s.tell("1TV") > 0.0, "axis 1 runs in velocity mode");
    s.drive("IN4=1");
    s.advance_ms(500);
    assert_eq!(s.tell("1TV"), 0.0, "stopped by the task");
    assert_eq!(s.line("TR10"), ["01 1"]);
    assert_eq!(s.sim.task_count(), 0);
}

#[test]
fn the_capture_example_loops_until_ten_positions_are_captured() {
    // Vector 201 (Ch7 CB): the last line loops until status bit 5.
    let mut s = Session::new();
    s.quiet(&["1MN,1SE0"]);
    let lines = vector_lines(201);
    let lines: Vec<&str> = lines.iter().map(String::as_str).collect();
    // The capture input (channel 1) pulses every 10 ms while it loops.
    let errors = download(&mut s, &lines, |s, ms| {
        s.drive(if ms % 10 < 5 { "IN1=1" } else { "IN1=0" });
    });
    assert_eq!(errors, Vec::<String>::new());
    assert_eq!(s.line("1CG,TR0"), ["01 10"]);
}

#[test]
fn the_part_count_file_calls_mc100_before_defining_it() {
    // Vector 425 (Ch13 OT), as printed: MC10 comes first and is -6.
    let mut s = Session::new();
    let lines = vector_lines(425);
    let lines: Vec<&str> = lines.iter().map(String::as_str).collect();
    assert_eq!(download(&mut s, &lines, |_, _| {}), ["?-6 MC10"]);
    // `\n` is a line feed (Ch4), and the prompt follows.
    assert_eq!(s.line("MC100"), ["The part count = 0 \n"]);
}

#[test]
fn the_manuals_index_homing_routine_homes_axis_1() {
    // Vector 257 (Ch7 IA): downloaded, then 1HO runs macro 1. The test is
    // the machine: the coarse home flag (channel 17) is on from 20000
    // counts up; the index marks are every 2000 counts at 500. The routine
    // finds the flag, backs out of it, comes back slowly and takes the
    // first index inside it (20500), which becomes 1000.
    let mut s = Session::new();
    let lines = vector_lines(257);
    let lines: Vec<&str> = lines.iter().map(String::as_str).collect();
    assert_eq!(download(&mut s, &lines, |_, _| {}), Vec::<String>::new());
    let stage = |s: &mut Session, _ms: u64| {
        let position = s.sim.axis(1).map_or(0.0, |a| a.position());
        let on = position >= 20_000.0;
        s.drive(if on { "IN17=1" } else { "IN17=0" });
    };
    assert_eq!(download(&mut s, &["1HO"], stage), Vec::<String>::new());
    let ts = s.status(1);
    assert_eq!(ts & status::HOMED, status::HOMED, "TS {ts:#x}");
    // MD14 moves to the index, now 1000.
    let at = s.tell("1TP");
    assert!((at - 1000.0).abs() <= 5.0, "{at}");
    assert_eq!(s.tell("1TZ"), 1000.0, "the index, where it was seen");
}

#[test]
fn the_ocr_files_are_refused_where_the_glyphs_are() {
    // Vectors 229 and 241 keep '5D10', 'N0', '1G0': error 1 on those lines.
    for index in [229, 241] {
        let mut s = Session::new();
        let lines = vector_lines(index);
        let lines: Vec<&str> = lines.iter().map(String::as_str).collect();
        let errors = download(&mut s, &lines, |_, _| {});
        assert!(!errors.is_empty());
        assert!(errors.iter().all(|e| e.starts_with("?1 ")), "{errors:?}");
    }
}
