//! Property tests of the CMD-4CR simulator: whatever arrives, it never
//! panics, answers each frame for its ID with exactly one line, and keeps
//! quiet for every other ID.

use std::time::Duration;

use axterm::protocol::cmd4cr::catalog::{Access, Form};
use axterm::protocol::cmd4cr::{COMMANDS, command::format_value};
use axterm::sim::SimulatedController;
use axterm::sim::cmd4cr::{Cmd4cr, SimConfig};
use proptest::prelude::*;

fn sim() -> Cmd4cr {
    Cmd4cr::new(SimConfig::default())
}

/// A command of the table with a value from its range, or a motion
/// command with random numbers.
fn command() -> impl Strategy<Value = String> {
    let rows = COMMANDS.len();
    (0..rows, 0..4usize, any::<u8>(), any::<i64>(), any::<bool>()).prop_map(
        |(row, axis, index, raw, write)| {
            let row = &COMMANDS[row];
            let letter = ['X', 'Y', 'Z', 'U'][axis];
            let selector = match row.form {
                Form::Bare => String::new(),
                Form::Axis => letter.to_string(),
                Form::Index { first, last } => (first + index % (last - first + 1)).to_string(),
                Form::Motion => {
                    let n = raw % 300_000;
                    return match row.keyword {
                        "" => format!("{letter}{n}"),
                        "J" => format!("J{letter}{}", if write { '+' } else { '-' }),
                        "H" => format!("H{letter}+{}", index % 13),
                        "ZMOVE" => format!("ZMOVE{letter}-"),
                        "T" => format!("T{letter}{n}"),
                        "CIR" => format!("CIRXYP{n}:{}", n / 3),
                        "ARC" => format!("ARCXUN{n}:0:{}", (raw % 360_000).abs()),
                        "CIRT" => format!("CIRTN0:{n}:5"),
                        "ARCT" => format!("ARCTP{n}:0:90000:-5"),
                        _ => format!("I{n}:0:{}:{}", -n, 1 + (raw % 10_000).abs()),
                    };
                }
            };
            let base = format!("{}{selector}", row.keyword);
            match (row.access, row.values) {
                (Access::Write | Access::ReadWrite, Some(v)) if write || !row.access.reads() => {
                    let span = (v.max - v.min).unsigned_abs().saturating_add(1);
                    let value = v.min.saturating_add((raw.unsigned_abs() % span) as i64);
                    format!("{base}={}", format_value(value, v.format))
                }
                _ => base,
            }
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Bytes of any kind, split anywhere, with time passing between.
    #[test]
    fn arbitrary_bytes_never_panic(
        chunks in prop::collection::vec(
            (prop::collection::vec(any::<u8>(), 0..40), 0u64..50), 0..40)
    ) {
        let mut sim = sim();
        for (bytes, ms) in chunks {
            sim.feed(&bytes);
            sim.advance(Duration::from_millis(ms));
            let out = sim.take_output();
            prop_assert!(out.is_empty() || out.ends_with(b"\r"));
        }
    }

    /// Any printable text as a command: one reply line for ID 01, none for
    /// ID 02.
    #[test]
    fn any_text_gets_one_reply(text in "[ -~]{0,70}") {
        let mut sim = sim();
        let text: String = text.chars().filter(|&c| c != '@').collect();
        sim.feed(format!("@02{text}\r").as_bytes());
        prop_assert!(sim.take_output().is_empty());
        sim.feed(format!("@01{text}\r").as_bytes());
        let out = sim.take_output();
        prop_assert_eq!(out.iter().filter(|&&b| b == b'\r').count(), 1, "{:?}", text);
        prop_assert!(out.ends_with(b"\r"));
    }

    /// Sequences of valid commands with time between: no panic, one reply
    /// each, never `?Unknown Command` for what the parser accepts.
    #[test]
    fn valid_commands_are_all_answered(
        steps in prop::collection::vec((command(), 0u64..300), 1..40)
    ) {
        let mut sim = sim();
        for (text, ms) in steps {
            sim.feed(format!("@01{text}\r").as_bytes());
            let out = String::from_utf8(sim.take_output()).expect("ASCII");
            prop_assert!(out.ends_with('\r') && out.matches('\r').count() == 1, "{text}: {out:?}");
            prop_assert!(!out.starts_with("?Unknown"), "{text}: {out:?}");
            sim.advance(Duration::from_millis(ms));
        }
        sim.power_cycle();
        // A stored ID=nn acts now.
        sim.feed(format!("@{:02}PP\r", sim.id()).as_bytes());
        prop_assert!(sim.take_output().ends_with(b"\r"));
    }
}
