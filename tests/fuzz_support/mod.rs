//! The generator and runner behind `tests/fuzz_scale.rs`: a seeded
//! pseudo-random source, inputs built from each family's own vocabulary
//! (what its completion offers, its parameter tables, its manual's vectors,
//! what its simulator answers) and then bent (characters and bytes
//! inserted, dropped, flipped, spliced, numbers at the edges of every
//! range), and a runner that counts inputs and panics and times them.
//!
//! Everything is found through `families::FAMILIES` and `axterm::families::kinds()`,
//! so a family registered there is fuzzed without a line here; its
//! manual's vectors are used when `tests/data/FAMILY-vectors.json` exists.
#![allow(dead_code)]

use std::collections::BTreeSet;
use std::fmt::Debug;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

use axterm::protocol::Family;
use axterm::protocol::console::{Answering, PreparedLine};
use axterm::protocol::parameters::ParamOp;
use axterm::protocol::wire::Frame;
use axterm::sim::SimOptions;

/// Inputs per target and family when `AXTERM_FUZZ_CASES` is not set: the
/// smoke form that runs in `cargo test`.
pub const SMOKE_CASES: u64 = 1500;

/// Inputs per target and family: `AXTERM_FUZZ_CASES`, else [`SMOKE_CASES`].
pub fn cases() -> u64 {
    std::env::var("AXTERM_FUZZ_CASES")
        .ok()
        .and_then(|v| v.replace('_', "").parse().ok())
        .unwrap_or(SMOKE_CASES)
}

/// The run's seed: `AXTERM_FUZZ_SEED`, else a fixed one (a run repeats).
pub fn seed() -> u64 {
    std::env::var("AXTERM_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x00A7_7E2F_0220_0001)
}

// ---- randomness ---------------------------------------------------------------

/// SplitMix64: small, fast, and good enough to pick inputs.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// 0..n (0 when n is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next_u64() % n as u64) as usize
        }
    }

    /// True with probability `percent`/100.
    pub fn chance(&mut self, percent: u64) -> bool {
        self.next_u64() % 100 < percent
    }

    pub fn byte(&mut self) -> u8 {
        self.next_u64().to_le_bytes()[0]
    }

    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> Option<&'a T> {
        items.get(self.below(items.len()))
    }
}

// ---- the runner ---------------------------------------------------------------

/// What one target did.
pub struct Report {
    pub inputs: u64,
    /// Inputs the subject took (a line that prepared, a file that
    /// checked, a frame cut): the generator reaches past the first error.
    pub accepted: u64,
    pub panics: Vec<String>,
    pub elapsed: Duration,
}

/// Stop a target after this many panics: the first ones say enough.
const PANICS_KEPT: usize = 10;

/// Feed `cases` inputs made by `make` to `check` (which says whether the
/// subject took the input), each under `catch_unwind`; print the counts,
/// the panics (with their input) and the time as `fuzz TARGET SUBJECT: …`.
pub fn run<I: Debug>(
    target: &str,
    subject: &str,
    cases: u64,
    seed: u64,
    mut make: impl FnMut(&mut Rng) -> I,
    mut check: impl FnMut(&I) -> bool,
) -> Report {
    let mut rng = Rng::new(seed ^ fnv(target) ^ fnv(subject).rotate_left(17));
    let start = Instant::now();
    let mut last_note = start;
    let mut panics = Vec::new();
    let mut inputs = 0;
    let mut accepted = 0;
    while inputs < cases {
        let input = make(&mut rng);
        inputs += 1;
        match catch_unwind(AssertUnwindSafe(|| check(&input))) {
            Ok(took) => accepted += u64::from(took),
            Err(_) => {
                panics.push(format!("input {inputs}: {input:?}"));
                if panics.len() >= PANICS_KEPT {
                    break;
                }
            }
        }
        if inputs % 4096 == 0 && last_note.elapsed() >= Duration::from_secs(60) {
            last_note = Instant::now();
            eprintln!(
                "fuzz {target} {subject}: {inputs} of {cases} after {:.0} s",
                start.elapsed().as_secs_f64()
            );
        }
    }
    let report = Report {
        inputs,
        accepted,
        panics,
        elapsed: start.elapsed(),
    };
    eprintln!(
        "fuzz {target} {subject}: {} inputs ({} taken), {} panics, {:.1} s",
        report.inputs,
        report.accepted,
        report.panics.len(),
        report.elapsed.as_secs_f64()
    );
    for panic in &report.panics {
        eprintln!("  panicked on {panic}");
    }
    report
}

/// Fail with every panic of `reports`.
pub fn assert_no_panics(reports: &[Report]) {
    let panics: Vec<&String> = reports.iter().flat_map(|r| &r.panics).collect();
    assert!(panics.is_empty(), "{} panics:\n{panics:#?}", panics.len());
}

fn fnv(text: &str) -> u64 {
    text.bytes().fold(0xCBF2_9CE4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01B3)
    })
}

// ---- what inputs are made of ---------------------------------------------------

/// Numbers at the edges of every range a manual or a parser has.
pub const EDGE_NUMBERS: &[&str] = &[
    "0",
    "1",
    "-1",
    "-0",
    "+5",
    "7",
    "99",
    "100",
    "127",
    "128",
    "255",
    "256",
    "-128",
    "-129",
    "32767",
    "32768",
    "65535",
    "65536",
    "8388607",
    "-8388608",
    "134217727",
    "-134217728",
    "2147483647",
    "2147483648",
    "-2147483648",
    "-2147483649",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "9223372036854775808",
    "-9223372036854775808",
    "-9223372036854775809",
    "18446744073709551616",
    "340282366920938463463374607431768211456",
    "0x",
    "0x0",
    "0xFF",
    "0x7FFFFFFF",
    "0x80000000",
    "0xFFFFFFFF",
    "0x100000000",
    "0xFFFFFFFFFFFFFFFFFF",
    "$FF",
    "1e9",
    "1.5",
    "-.5",
    ".",
    "00000000000000000000000001",
    "\u{0663}",
    "\u{FF11}",
];

/// Characters that separate, quote, end or confuse.
pub const PUNCTUATION: &[&str] = &[
    " ",
    ",",
    ", ",
    "=",
    "==",
    "?",
    "@",
    "\t",
    ";",
    ":",
    "//",
    "#",
    "-",
    "+",
    "*",
    "/",
    "%",
    "(",
    ")",
    "[",
    "]",
    "{",
    "}",
    "<",
    ">",
    "!",
    "&",
    "|",
    "^",
    "~",
    "\"",
    "'",
    "\\",
    ".",
    "\r",
    "\n",
    "\r\n",
    "\0",
    "\u{7F}",
    "\u{1B}[A",
    "\u{A0}",
    "\u{FEFF}",
    "\u{200B}",
    "é",
    "ß",
    "ǅ",
    "İ",
    "\u{301}",
    "😀",
    "𝄞",
    "中",
    "\u{FFFD}",
    "\u{10FFFF}",
];

/// What one family's inputs are made of.
pub struct FamilyCorpus {
    pub family: &'static Family,
    /// The module address lines are prepared for.
    pub address: u8,
    /// Console lines that prepare, with what they became.
    pub lines: Vec<(String, PreparedLine)>,
    /// For each of `lines`, the frames a simulator of the family answered
    /// (empty without a simulator, or when it did not answer).
    pub answers: Vec<Vec<Frame>>,
    /// Every frame seen: requests, answers, the manual's vectors.
    pub frames: Vec<Vec<u8>>,
    /// Words of the family: names, operands, symbols, numbers.
    pub words: Vec<String>,
    /// Lines of text from the manual's vectors (requests, programs).
    pub texts: Vec<String>,
}

impl FamilyCorpus {
    pub fn build(family: &'static Family) -> FamilyCorpus {
        let console = family.console;
        let address = console.default_address();
        let mut words = BTreeSet::new();
        let mut lines = BTreeSet::new();
        explore_completions(family, address, &mut words, &mut lines);
        for line in console.emergency_stop(address) {
            lines.insert(line.canonical);
        }
        lines.insert(console.identify(address).canonical);
        for poll in console.status_queries(address) {
            lines.insert(poll.line.canonical);
        }
        for axis in console.axes() {
            lines.extend(console.stop_axis_line(axis.number));
            lines.extend(console.clear_errors_line(axis.number));
        }
        if let Some(parameters) = console.parameters() {
            for axis in console.axes() {
                for table in parameters.tables(axis.number) {
                    for row in table.rows {
                        words.insert(row.name.clone());
                        let value = row.default.unwrap_or(0);
                        for op in [
                            ParamOp::Read,
                            ParamOp::Write(value),
                            ParamOp::Store,
                            ParamOp::Restore,
                        ] {
                            if let Ok(line) = parameters.line(&row, op) {
                                lines.insert(line);
                            }
                        }
                    }
                }
            }
        }
        let (vector_texts, vector_frames) = vectors(family.name);
        for text in &vector_texts {
            for line in text.lines() {
                lines.insert(line.trim().to_string());
            }
        }
        let mut prepared = Vec::new();
        for line in lines {
            for word in line.split([' ', ',', '=']).filter(|w| !w.is_empty()) {
                words.insert(word.to_string());
            }
            if let Ok(p) = console.prepare(&line, address) {
                prepared.push((line, p));
            }
        }
        let answers: Vec<Vec<Frame>> = prepared
            .iter()
            .map(|(_, line)| simulator_answer(family, address, line))
            .collect();
        let mut frames: Vec<Vec<u8>> = vector_frames;
        frames.extend(prepared.iter().map(|(_, p)| p.bytes.clone()));
        frames.extend(answers.iter().flatten().cloned());
        frames.sort();
        frames.dedup();
        words.extend(EDGE_NUMBERS.iter().map(|s| (*s).to_string()));
        FamilyCorpus {
            family,
            address,
            lines: prepared,
            answers,
            frames,
            words: words.into_iter().collect(),
            texts: vector_texts,
        }
    }

    pub fn summary(&self) -> String {
        format!(
            "{}: {} valid lines, {} answered by a simulator, {} frames, {} words",
            self.family.name,
            self.lines.len(),
            self.answers.iter().filter(|a| !a.is_empty()).count(),
            self.frames.len(),
            self.words.len()
        )
    }

    /// A console line: a valid one bent, words spliced, or noise.
    pub fn line(&self, rng: &mut Rng) -> String {
        match rng.below(10) {
            0..=3 => {
                let mut line = self.valid_line(rng);
                for _ in 0..rng.below(4) {
                    line = bend_text(rng, &line, &self.words);
                }
                line
            }
            4 => self.valid_line(rng),
            5 | 6 => {
                let mut line = String::new();
                for _ in 0..=rng.below(6) {
                    if !line.is_empty() {
                        line.push_str(
                            rng.pick(&[" ", ", ", ",", "=", "", " ", "\t"])
                                .copied()
                                .unwrap_or(" "),
                        );
                    }
                    line.push_str(self.word(rng));
                }
                line
            }
            7 => {
                let text = rng.pick(&self.texts).cloned().unwrap_or_default();
                bend_text(rng, &text, &self.words)
            }
            8 => noise_text(rng, 40),
            _ => String::from_utf8_lossy(&noise_bytes(rng, 40)).into_owned(),
        }
    }

    pub fn valid_line(&self, rng: &mut Rng) -> String {
        rng.pick(&self.lines)
            .map(|(line, _)| line.clone())
            .unwrap_or_default()
    }

    pub fn word(&self, rng: &mut Rng) -> &str {
        if rng.chance(15) {
            rng.pick(PUNCTUATION).copied().unwrap_or(",")
        } else {
            rng.pick(&self.words).map_or("", String::as_str)
        }
    }

    /// A frame as it may arrive: a real one, bent, spliced, or noise.
    pub fn frame(&self, rng: &mut Rng) -> Vec<u8> {
        let real = |rng: &mut Rng| rng.pick(&self.frames).cloned().unwrap_or_default();
        match rng.below(10) {
            0 | 1 => real(rng),
            2..=5 => {
                let mut frame = real(rng);
                for _ in 0..=rng.below(3) {
                    frame = bend_bytes(rng, &frame);
                }
                frame
            }
            6 => {
                let mut frame = real(rng);
                let other = real(rng);
                let cut = rng.below(frame.len() + 1);
                frame.truncate(cut);
                let from = rng.below(other.len() + 1);
                frame.extend_from_slice(other.get(from..).unwrap_or(&[]));
                frame
            }
            7 => {
                let text = self.line(rng);
                let mut bytes = text.into_bytes();
                if rng.chance(50) {
                    bytes.push(b'\r');
                }
                bytes
            }
            _ => noise_bytes(rng, 24),
        }
    }

    /// A byte stream as a link delivers it: frames and noise, cut into
    /// chunks anywhere.
    pub fn stream(&self, rng: &mut Rng) -> Vec<Vec<u8>> {
        let mut bytes = Vec::new();
        for _ in 0..=rng.below(5) {
            bytes.extend(self.frame(rng));
        }
        chunks(rng, &bytes)
    }
}

/// `bytes` cut into pieces of random lengths (some empty).
pub fn chunks(rng: &mut Rng, bytes: &[u8]) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let mut rest = bytes;
    while !rest.is_empty() {
        let n = rng.below(rest.len().min(12) + 1);
        let (piece, tail) = rest.split_at(n);
        out.push(piece.to_vec());
        rest = tail;
    }
    out
}

/// Walk the completion tree from the empty line: names, then operands, a
/// few levels deep; the lines that prepare on the way are kept.
fn explore_completions(
    family: &Family,
    address: u8,
    words: &mut BTreeSet<String>,
    lines: &mut BTreeSet<String>,
) {
    let console = family.console;
    let mut rng = Rng::new(fnv(family.name));
    let mut level = vec![String::new()];
    for depth in 0..5 {
        let mut next = Vec::new();
        for stem in &level {
            let completions = console.complete(stem, stem.len());
            let mut candidates = completions.candidates;
            // Every name at the first level; a sample of operands below.
            let keep = if depth == 0 { usize::MAX } else { 6 };
            while candidates.len() > keep {
                let drop = rng.below(candidates.len());
                candidates.swap_remove(drop);
            }
            if candidates.is_empty() {
                for number in ["0", "1", "100"] {
                    let line = format!("{stem}{number}");
                    if console.prepare(&line, address).is_ok() {
                        lines.insert(line);
                    }
                }
            }
            for candidate in candidates {
                words.insert(candidate.text.clone());
                let mut line = stem.get(..completions.start).unwrap_or("").to_string();
                line.push_str(&candidate.text);
                if console.prepare(&line, address).is_ok() {
                    lines.insert(line.clone());
                }
                line.push_str(completions.separator);
                if !completions.separator.is_empty() {
                    next.push(line);
                }
            }
        }
        level = next;
    }
}

/// Strings and hex frames from `tests/data/FAMILY-vectors.json`, if any.
fn vectors(family: &str) -> (Vec<String>, Vec<Vec<u8>>) {
    let path = format!(
        "{}/tests/data/{family}-vectors.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let Ok(text) = std::fs::read_to_string(path) else {
        return (Vec::new(), Vec::new());
    };
    let Ok(json) = serde_json::from_str::<serde_json::Value>(&text) else {
        return (Vec::new(), Vec::new());
    };
    let mut texts = Vec::new();
    let mut frames = Vec::new();
    collect_strings(&json, &mut texts);
    texts.retain(|s| match hex_bytes(s) {
        Some(bytes) => {
            frames.push(bytes);
            false
        }
        None => true,
    });
    // ASCII families: what is sent and answered, as bytes with its CR.
    frames.extend(
        texts
            .iter()
            .filter(|t| t.len() < 80 && !t.contains('\n'))
            .map(|t| {
                let mut bytes = t.as_bytes().to_vec();
                bytes.push(b'\r');
                bytes
            }),
    );
    (texts, frames)
}

fn collect_strings(value: &serde_json::Value, out: &mut Vec<String>) {
    match value {
        serde_json::Value::String(s) => out.push(s.clone()),
        serde_json::Value::Array(items) => items.iter().for_each(|v| collect_strings(v, out)),
        serde_json::Value::Object(map) => map.values().for_each(|v| collect_strings(v, out)),
        _ => {}
    }
}

/// `"01 05 04 00"` as bytes.
fn hex_bytes(text: &str) -> Option<Vec<u8>> {
    let parts: Vec<&str> = text.split_whitespace().collect();
    if parts.len() < 2 || parts.iter().any(|p| p.len() != 2) {
        return None;
    }
    parts
        .iter()
        .map(|p| u8::from_str_radix(p, 16).ok())
        .collect()
}

/// What a fresh simulator of `family` answers to `line`, cut into frames.
fn simulator_answer(family: &Family, address: u8, line: &PreparedLine) -> Vec<Frame> {
    if matches!(line.answering, Answering::Nothing) {
        return Vec::new();
    }
    let Some(kind) = axterm::families::simulators_of(family).first() else {
        return Vec::new();
    };
    let mut sim = (kind.build)(&SimOptions {
        address: Some(address),
        eeprom_file: None,
    });
    sim.feed(&line.bytes);
    let mut output = Vec::new();
    for _ in 0..20 {
        sim.advance(Duration::from_millis(5));
        output.extend(sim.take_output());
    }
    family.console.wire().framer().push(&output)
}

// ---- bending ------------------------------------------------------------------

/// `text` with one change: a character or word inserted, a run dropped or
/// doubled, a number swapped for an edge value, the case flipped, cut.
pub fn bend_text(rng: &mut Rng, text: &str, words: &[String]) -> String {
    let bounds: Vec<usize> = text
        .char_indices()
        .map(|(i, _)| i)
        .chain([text.len()])
        .collect();
    let at = |rng: &mut Rng| bounds.get(rng.below(bounds.len())).copied().unwrap_or(0);
    let (a, b) = {
        let x = at(rng);
        let y = at(rng);
        (x.min(y), x.max(y))
    };
    let head = text.get(..a).unwrap_or("");
    let middle = text.get(a..b).unwrap_or("");
    let tail = text.get(b..).unwrap_or("");
    match rng.below(9) {
        0 => format!("{head}{}{middle}{tail}", random_char(rng)),
        1 => {
            let word = rng.pick(words).map_or("", String::as_str);
            format!("{head}{word}{middle}{tail}")
        }
        2 => format!(
            "{head}{}{middle}{tail}",
            rng.pick(PUNCTUATION).copied().unwrap_or(",")
        ),
        3 => format!("{head}{tail}"),
        4 => format!("{head}{middle}{middle}{tail}"),
        5 => swap_number(rng, text),
        6 => text
            .chars()
            .map(|c| {
                if rng.chance(30) {
                    if c.is_lowercase() {
                        c.to_ascii_uppercase()
                    } else {
                        c.to_ascii_lowercase()
                    }
                } else {
                    c
                }
            })
            .collect(),
        7 => head.to_string(),
        _ => format!(
            "{head}{}{tail}",
            rng.pick(EDGE_NUMBERS).copied().unwrap_or("0")
        ),
    }
}

/// The first run of digits (and a sign) replaced by an edge number.
fn swap_number(rng: &mut Rng, text: &str) -> String {
    let starts: Vec<usize> = text
        .char_indices()
        .filter(|(_, c)| c.is_ascii_digit())
        .map(|(i, _)| i)
        .collect();
    let Some(&start) = rng.pick(&starts) else {
        return text.to_string();
    };
    let end = text
        .get(start..)
        .and_then(|rest| rest.find(|c: char| !c.is_ascii_alphanumeric()))
        .map_or(text.len(), |n| start + n);
    let number = rng.pick(EDGE_NUMBERS).copied().unwrap_or("0");
    format!(
        "{}{number}{}",
        text.get(..start).unwrap_or(""),
        text.get(end..).unwrap_or("")
    )
}

fn random_char(rng: &mut Rng) -> char {
    match rng.below(4) {
        0 => char::from(rng.byte() & 0x7F),
        1 => char::from(0x20 + rng.byte() % 0x5F),
        2 => char::from_u32(rng.next_u64() as u32 % 0x3000).unwrap_or('?'),
        _ => char::from_u32(rng.next_u64() as u32 % 0x11_0000).unwrap_or('\u{FFFD}'),
    }
}

/// Up to `max` characters of anything.
pub fn noise_text(rng: &mut Rng, max: usize) -> String {
    (0..rng.below(max + 1)).map(|_| random_char(rng)).collect()
}

/// Up to `max` bytes of anything.
pub fn noise_bytes(rng: &mut Rng, max: usize) -> Vec<u8> {
    (0..rng.below(max + 1)).map(|_| rng.byte()).collect()
}

/// `bytes` with one change: a bit flipped, a byte set to an edge value,
/// inserted, dropped, a run doubled, cut.
pub fn bend_bytes(rng: &mut Rng, bytes: &[u8]) -> Vec<u8> {
    let mut out = bytes.to_vec();
    let at = rng.below(out.len() + 1);
    match rng.below(7) {
        0 if at < out.len() => out[at] ^= 1 << rng.below(8),
        1 if at < out.len() => {
            out[at] = *rng
                .pick(&[0x00, 0x01, 0x7F, 0x80, 0xFF, b'\r', b'\n', b'@', b'?', b'-'])
                .unwrap_or(&0);
        }
        2 => out.insert(at, rng.byte()),
        3 if at < out.len() => {
            out.remove(at);
        }
        4 => {
            let end = (at + rng.below(6)).min(out.len());
            let run = out.get(at..end).unwrap_or(&[]).to_vec();
            out.splice(at..at, run);
        }
        5 => out.truncate(at),
        _ => {
            if let Some(byte) = out.get_mut(at) {
                *byte = rng.byte();
            } else {
                out.push(rng.byte());
            }
        }
    }
    out
}

/// A multi-line text made of `line`s: a batch file, a program.
pub fn text_of_lines(
    rng: &mut Rng,
    max_lines: usize,
    mut line: impl FnMut(&mut Rng) -> String,
) -> String {
    let mut text = String::new();
    for _ in 0..=rng.below(max_lines) {
        text.push_str(&line(rng));
        text.push_str(
            rng.pick(&["\n", "\n", "\n", "\r\n", "\r"])
                .copied()
                .unwrap_or("\n"),
        );
    }
    if rng.chance(20) {
        text.pop();
    }
    text
}

/// A whole document (a program, a file) with a few line-level changes: a
/// line bent, dropped, doubled, swapped, or one from `pool` put in.
pub fn bend_document(rng: &mut Rng, text: &str, pool: &[String], words: &[String]) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for _ in 0..rng.below(4) {
        let at = rng.below(lines.len());
        match rng.below(6) {
            0 | 1 => {
                if let Some(line) = lines.get_mut(at) {
                    *line = bend_text(rng, line, words);
                }
            }
            2 if at < lines.len() => {
                lines.remove(at);
            }
            3 => {
                if let Some(line) = lines.get(at).cloned() {
                    lines.insert(at, line);
                }
            }
            4 => {
                let other = rng.below(lines.len());
                if at < lines.len() && other < lines.len() {
                    lines.swap(at, other);
                }
            }
            _ => {
                let line = rng.pick(pool).cloned().unwrap_or_default();
                lines.insert(at.min(lines.len()), line);
            }
        }
    }
    let mut out = lines.join(rng.pick(&["\n", "\n", "\r\n"]).copied().unwrap_or("\n"));
    if rng.chance(80) {
        out.push('\n');
    }
    out
}
