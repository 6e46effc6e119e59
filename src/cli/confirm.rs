//! What the batch front ends (`exec`, `run`) say about a line before
//! anything is sent: the family's warnings, which go to stderr and stop
//! nothing, and the lines the family wants confirmed (a reset, a baud
//! change, a motion that starts at once), which a batch sends only when
//! told `--yes`. A front end that finds one unconfirmed sends nothing at
//! all.

use crate::protocol::console::{FamilyConsole, PreparedLine, Reading, ReplyValue};
use crate::protocol::settings::SettingsCache;

/// What a front end must say about one line.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Cautions {
    /// Printed on stderr; the line is still sent.
    pub warnings: Vec<String>,
    /// Why the line is not sent: it needs a confirmation that `--yes` did
    /// not give.
    pub refusal: Option<String>,
}

/// The cautions about `line` for a batch given `--yes` or not, its
/// cross-field warnings against `known` (what the lines before it wrote).
pub fn cautions(
    console: &dyn FamilyConsole,
    line: &PreparedLine,
    known: &SettingsCache,
    yes: bool,
) -> Cautions {
    let refusal = console
        .confirmation(line)
        .filter(|_| !yes)
        .map(|why| format!("not sent without --yes: {why}"));
    Cautions {
        warnings: console
            .warnings(line, known)
            .into_iter()
            .map(|w| format!("warning: {w}"))
            .collect(),
        refusal,
    }
}

/// What `known` becomes once `line` is sent, judged before anything is
/// sent (a batch's lines are checked together first): the settings it
/// writes, or none known after a line that resets the module.
pub fn after_line(console: &dyn FamilyConsole, line: &PreparedLine, known: &mut SettingsCache) {
    let sent = Reading {
        status: None,
        value: ReplyValue::None,
    };
    if let Some(why) = console.settings_lost(line, &sent) {
        known.forget(&why);
    }
    known.record(&console.settings_written(line));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::families::find_family;

    fn of(family: &str, line: &str, yes: bool) -> Cautions {
        let console = find_family(family).expect("a family").console;
        let prepared = console
            .prepare(line, console.default_address())
            .expect("a valid line");
        cautions(console, &prepared, &SettingsCache::default(), yes)
    }

    #[test]
    fn a_line_to_confirm_is_refused_without_yes_and_sent_with_it() {
        let refused = of("sixpack2", "HardwareReset", false);
        let why = refused.refusal.expect("refused");
        assert!(
            why.starts_with("not sent without --yes: every setting"),
            "{why}"
        );
        assert_eq!(of("sixpack2", "HardwareReset", true).refusal, None);
        assert_eq!(
            of("sixpack2", "StartRamp 0 100", false),
            Cautions::default()
        );
    }

    #[test]
    fn warnings_are_said_either_way() {
        let said = of("sixpack2", "SetPeakCurrent 1 10", true);
        assert_eq!(said.warnings.len(), 1);
        assert!(said.warnings[0].starts_with("warning: the peak current of motors 0 and 1"));
        assert_eq!(said.refusal, None);
    }

    #[test]
    fn cross_field_warnings_know_what_the_lines_before_wrote() {
        let console = find_family("sixpack2").expect("a family").console;
        let prepared = |line: &str| console.prepare(line, 0).expect("a valid line");
        let amax = prepared("SetAMaxVMax 0 500 400");
        let mut known = SettingsCache::default();
        let said = cautions(console, &amax, &known, false);
        assert!(
            said.warnings[0].contains("vstart 5 (factory value"),
            "{:?}",
            said.warnings
        );
        after_line(console, &prepared("SetVMinVStart 0 4 8 2"), &mut known);
        assert_eq!(cautions(console, &amax, &known, false), Cautions::default());
        after_line(console, &prepared("HardwareReset"), &mut known);
        assert_eq!(cautions(console, &amax, &known, false).warnings.len(), 1);
    }

    #[test]
    fn families_without_cautions_are_unchanged() {
        assert_eq!(of("tmcl", "MVP ABS, 0, 1000", false), Cautions::default());
        assert_eq!(of("cmd4cr", "STORE", false), Cautions::default());
    }
}
