//! Whatever arrives, the simulator does not panic, and a line that has
//! stopped running has ended with the prompt.

use proptest::prelude::*;

use super::*;
use crate::sim::mccl::commands::COMMANDS;

/// A command from the table with an axis and a parameter, valid or not.
fn command() -> impl Strategy<Value = String> {
    (
        proptest::option::of(0u8..10),
        // PC is left out: PC0 would take the prompt away.
        proptest::sample::select(
            COMMANDS
                .iter()
                .map(|c| c.mnemonic)
                .filter(|&m| m != "PC")
                .collect::<Vec<_>>(),
        ),
        prop_oneof![
            Just(String::new()),
            (-2000i64..2000).prop_map(|n| n.to_string()),
            (-10.0f64..10.0).prop_map(|x| format!("{x:.3}")),
            (0u32..1100).prop_map(|r| format!("@{r}")),
            "[A-Z%d ]{0,6}".prop_map(|s| format!("\"{s}\"")),
        ],
    )
        .prop_map(|(axis, mnemonic, param)| {
            format!(
                "{}{mnemonic}{param}",
                axis.map(|a| a.to_string()).unwrap_or_default()
            )
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_lines_end_with_a_prompt_or_keep_running(
        lines in proptest::collection::vec(proptest::collection::vec(command(), 1..5), 1..6)
    ) {
        let mut s = Session::new();
        s.quiet(&["1MN,2MN,3MN,4MN,5MN"]);
        for commands in lines {
            let line = commands.join(",");
            let mut out = s.typed(&format!("{line}\r"));
            out.push_str(&s.advance_ms(20));
            if s.sim.busy() {
                // Blocked (a wait, an endless RP): Escape ends it.
                out.push_str(&s.typed("\x1b"));
            }
            prop_assert!(!s.sim.busy());
            // The line ended with its prompt (a task it started may print
            // after it).
            prop_assert!(out.contains("\r\n>") || out.ends_with('>'), "{line}: {out:?}");
            s.advance_ms(5);
            let _ = s.sim.take_output();
        }
    }

    #[test]
    fn no_bytes_panic_it(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let mut s = Session::new();
        s.sim.feed(&bytes);
        s.advance_ms(10);
        s.sim.feed(b"\x1b");
        s.sim.feed(b"\r");
        s.advance_ms(1);
    }
}
