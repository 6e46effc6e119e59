//! Inputs of a simulated controller driven from outside, by a short text
//! setting `NAME=VALUE` (`IO5=1`, `AI1=1650`, `IN3=open`): what a
//! technician trying axterm on a simulator types where on a machine a
//! switch would close (`--input`, the served simulator's standard input,
//! the console's `:sim-input`).
//!
//! Each simulator lists its inputs as a table of [`InputRow`]s (which
//! names, which values, what it is); [`parse`] reads a setting against
//! such a table and the simulator applies what it names. Pure: no I/O.

use std::fmt;

/// The names one row of inputs answers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Names {
    /// A stem and a number, `DI1`..`DI4`.
    Numbered {
        stem: &'static str,
        first: u8,
        last: u8,
    },
    /// Names of their own, `ALMX`, `ALMY`, …; the n-th is input n.
    Listed(&'static [&'static str]),
}

/// What may follow the `=`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Values {
    /// `1` (or `on`) and `0` (or `off`).
    OnOff,
    /// As [`Values::OnOff`], or `word`: not driven from outside, as
    /// `meaning` says (`open`: nothing connected).
    OnOffOr {
        word: &'static str,
        meaning: &'static str,
    },
    /// A whole number `0..=max`, in `unit`.
    Number { max: u32, unit: &'static str },
    /// As [`Values::Number`], or `word`: not driven from outside, as
    /// `meaning` says (`stage`: where the simulated carriage is sets it).
    NumberOr {
        max: u32,
        unit: &'static str,
        word: &'static str,
        meaning: &'static str,
    },
    /// One of these words (any case), or its position in the list from 0.
    Choice(&'static [&'static str]),
}

impl Values {
    /// What the values look like after `NAME=` in a list of settings.
    fn pattern(self) -> String {
        match self {
            Values::OnOff => "0|1".into(),
            Values::OnOffOr { word, .. } => format!("0|1|{word}"),
            Values::Number { max, unit } => format!("<{unit} 0..{max}>"),
            Values::NumberOr {
                max, unit, word, ..
            } => format!("<{unit} 0..{max}>|{word}"),
            Values::Choice(words) => words.join("|"),
        }
    }

    /// What the values are, in words, for an error.
    fn wanted(self) -> String {
        match self {
            Values::OnOff => "1 (on) or 0 (off)".into(),
            Values::OnOffOr { word, meaning } => format!("1 (on), 0 (off) or {word} ({meaning})"),
            Values::Number { max, unit } => format!("a whole number of {unit}, 0..{max}"),
            Values::NumberOr {
                max,
                unit,
                word,
                meaning,
            } => format!("a whole number of {unit}, 0..{max}, or {word} ({meaning})"),
            Values::Choice(words) => format!(
                "one of {} (or 0..{})",
                words.join(", "),
                words.len().saturating_sub(1)
            ),
        }
    }
}

/// One kind of input of a simulator: its names, values, and what it is.
/// `T` says to the simulator which input it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InputRow<T: 'static> {
    pub input: T,
    pub names: Names,
    pub values: Values,
    /// One line for help: what the input is and does.
    pub what: &'static str,
}

impl<T> InputRow<T> {
    /// `DI1..DI4=0|1`, `ALMX|ALMY|ALMZ|ALMU=0|1`.
    pub fn pattern(&self) -> String {
        let names = match self.names {
            Names::Numbered { stem, first, last } if first == last => format!("{stem}{first}"),
            Names::Numbered { stem, first, last } => format!("{stem}{first}..{stem}{last}"),
            Names::Listed(names) => names.join("|"),
        };
        format!("{names}={}", self.values.pattern())
    }

    /// Every name of the row, in order.
    fn names(&self) -> Vec<String> {
        match self.names {
            Names::Numbered { stem, first, last } => {
                (first..=last).map(|n| format!("{stem}{n}")).collect()
            }
            Names::Listed(names) => names.iter().map(|n| n.to_string()).collect(),
        }
    }

    /// Which of the row's inputs `name` (upper case) is: the number of a
    /// numbered one, else the position in the list, from 0.
    fn find(&self, name: &str) -> Option<u8> {
        match self.names {
            Names::Numbered { stem, first, last } => {
                let digits = name.strip_prefix(stem)?;
                if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
                    return None;
                }
                digits
                    .parse::<u8>()
                    .ok()
                    .filter(|n| (first..=last).contains(n))
            }
            Names::Listed(names) => names
                .iter()
                .position(|n| *n == name)
                .and_then(|i| u8::try_from(i).ok()),
        }
    }
}

/// The level a setting drives an input to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    On,
    Off,
    /// Not driven from outside: the row's [`Values::OnOffOr`] word.
    Released,
    Number(u32),
    /// The position of a [`Values::Choice`] word.
    Choice(u8),
}

impl Level {
    /// On or off; `None` for the others.
    pub fn is_on(self) -> Option<bool> {
        match self {
            Level::On => Some(true),
            Level::Off => Some(false),
            _ => None,
        }
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Level::On => f.write_str("on"),
            Level::Off => f.write_str("off"),
            Level::Released => f.write_str("released"),
            Level::Number(n) => write!(f, "{n}"),
            Level::Choice(n) => write!(f, "{n}"),
        }
    }
}

/// A setting read against a simulator's table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Setting<T: 'static> {
    pub row: &'static InputRow<T>,
    /// The number of a numbered input (`5` of `IO5`), else its position in
    /// the row's list from 0 (`1` of `ALMY`).
    pub which: u8,
    pub level: Level,
}

impl<T> Setting<T> {
    /// The input's name as the table spells it (`IO5`, `ALMY`).
    pub fn name(&self) -> String {
        match self.row.names {
            Names::Numbered { stem, .. } => format!("{stem}{}", self.which),
            Names::Listed(names) => names
                .get(usize::from(self.which))
                .map_or_else(String::new, |n| n.to_string()),
        }
    }
}

/// Why a setting was not taken. Every message names what was typed and,
/// where the name was the trouble, lists the inputs there are.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SettingError {
    /// No `=` or nothing on one side of it.
    NotNameValue {
        text: String,
        example: String,
        inputs: String,
    },
    /// No input of that name.
    UnknownName { name: String, inputs: String },
    /// The input exists; the value does not fit it.
    BadValue {
        name: String,
        value: String,
        wanted: String,
    },
    /// The simulator cannot drive this input now (an IO set as output).
    Refused { name: String, why: String },
}

impl fmt::Display for SettingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SettingError::NotNameValue {
                text,
                example,
                inputs,
            } => write!(
                f,
                "`{text}` is no input setting: give NAME=VALUE, e.g. {example}; the inputs are {inputs}"
            ),
            SettingError::UnknownName { name, inputs } => {
                write!(f, "there is no input `{name}`: the inputs are {inputs}")
            }
            SettingError::BadValue {
                name,
                value,
                wanted,
            } => write!(f, "{name} takes {wanted}, not `{value}`"),
            SettingError::Refused { name, why } => write!(f, "{name} cannot be driven: {why}"),
        }
    }
}

impl std::error::Error for SettingError {}

/// Read `text` (`NAME=VALUE`; names in any case, blanks around either
/// side allowed) against `table`.
pub fn parse<T>(table: &'static [InputRow<T>], text: &str) -> Result<Setting<T>, SettingError> {
    let text = text.trim();
    let not_a_setting = || SettingError::NotNameValue {
        text: text.to_string(),
        example: example(table),
        inputs: summary(table),
    };
    let (name, value) = text.split_once('=').ok_or_else(not_a_setting)?;
    let (name, value) = (name.trim().to_ascii_uppercase(), value.trim());
    if name.is_empty() || value.is_empty() {
        return Err(not_a_setting());
    }
    let (row, which) = table
        .iter()
        .find_map(|row| row.find(&name).map(|which| (row, which)))
        .ok_or_else(|| SettingError::UnknownName {
            name: name.clone(),
            inputs: summary(table),
        })?;
    let lower = value.to_ascii_lowercase();
    let level = match (row.values, lower.as_str()) {
        (Values::OnOff | Values::OnOffOr { .. }, "1" | "on") => Some(Level::On),
        (Values::OnOff | Values::OnOffOr { .. }, "0" | "off") => Some(Level::Off),
        (Values::OnOffOr { word, .. }, released) if released.eq_ignore_ascii_case(word) => {
            Some(Level::Released)
        }
        (Values::NumberOr { word, .. }, released) if released.eq_ignore_ascii_case(word) => {
            Some(Level::Released)
        }
        (Values::Number { max, .. } | Values::NumberOr { max, .. }, _) => lower
            .parse::<u32>()
            .ok()
            .filter(|n| *n <= max)
            .map(Level::Number),
        (Values::Choice(words), _) => words
            .iter()
            .position(|w| w.eq_ignore_ascii_case(&lower))
            .or_else(|| lower.parse::<usize>().ok().filter(|&i| i < words.len()))
            .and_then(|i| u8::try_from(i).ok())
            .map(Level::Choice),
        _ => None,
    };
    let level = level.ok_or_else(|| SettingError::BadValue {
        name: name.clone(),
        value: value.to_string(),
        wanted: row.values.wanted(),
    })?;
    Ok(Setting { row, which, level })
}

/// Every setting pattern of `table`, for help and errors:
/// `DI1..DI4=0|1, AI1..AI2=<mV 0..3300>`.
pub fn summary<T>(table: &[InputRow<T>]) -> String {
    table
        .iter()
        .map(InputRow::pattern)
        .collect::<Vec<_>>()
        .join(", ")
}

/// A setting of the first input, for an error: `DI1=1`, `AI1=1650`.
fn example<T>(table: &[InputRow<T>]) -> String {
    let Some(row) = table.first() else {
        return "NAME=1".into();
    };
    let name = row.names().into_iter().next().unwrap_or_default();
    match row.values {
        Values::Number { max, .. } | Values::NumberOr { max, .. } => {
            format!("{name}={}", max / 2)
        }
        Values::OnOff | Values::OnOffOr { .. } => format!("{name}=1"),
        Values::Choice(words) => format!("{name}={}", words.first().unwrap_or(&"0")),
    }
}

/// The values of the `LIMITS` setting every simulator with a stage has:
/// its end switches wired the right way (the + end closes the input the
/// controller reads as its + limit) or swapped (the + end closes the −
/// input and the − end the + one), to try the wiring check on.
pub const LIMITS_WIRING: Values = Values::Choice(&["right", "swapped"]);

/// The `LIMITS` setting's value as "swapped": `Level::Choice(1)`.
pub fn limits_swapped(level: Level) -> bool {
    level == Level::Choice(1)
}

/// Every input name of `table`, for completion.
pub fn names<T>(table: &[InputRow<T>]) -> Vec<String> {
    table.iter().flat_map(InputRow::names).collect()
}

/// One line per row: the pattern and what the input is.
pub fn help_lines<T>(table: &[InputRow<T>]) -> Vec<String> {
    table
        .iter()
        .map(|row| format!("{}: {}", row.pattern(), row.what))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    enum Probe {
        Switch,
        Pin,
        Volts,
        Mode,
    }

    const TABLE: &[InputRow<Probe>] = &[
        InputRow {
            input: Probe::Switch,
            names: Names::Numbered {
                stem: "S",
                first: 1,
                last: 3,
            },
            values: Values::OnOff,
            what: "a switch",
        },
        InputRow {
            input: Probe::Pin,
            names: Names::Listed(&["PA", "PB"]),
            values: Values::OnOffOr {
                word: "open",
                meaning: "nothing connected",
            },
            what: "a pin",
        },
        InputRow {
            input: Probe::Volts,
            names: Names::Numbered {
                stem: "V",
                first: 0,
                last: 0,
            },
            values: Values::Number {
                max: 500,
                unit: "mV",
            },
            what: "a voltage",
        },
        InputRow {
            input: Probe::Mode,
            names: Names::Listed(&["MODE"]),
            values: Values::Choice(&["slow", "fast"]),
            what: "a mode",
        },
    ];

    fn ok(text: &str) -> (Probe, u8, Level, String) {
        let s = parse(TABLE, text).unwrap_or_else(|e| panic!("{text}: {e}"));
        (s.row.input, s.which, s.level, s.name())
    }

    #[test]
    fn settings_name_an_input_and_a_level() {
        assert_eq!(ok("S2=1"), (Probe::Switch, 2, Level::On, "S2".into()));
        assert_eq!(
            ok(" s3 = off "),
            (Probe::Switch, 3, Level::Off, "S3".into())
        );
        assert_eq!(ok("pb=OPEN"), (Probe::Pin, 1, Level::Released, "PB".into()));
        assert_eq!(ok("PA=on"), (Probe::Pin, 0, Level::On, "PA".into()));
        assert_eq!(
            ok("V0=500"),
            (Probe::Volts, 0, Level::Number(500), "V0".into())
        );
        assert_eq!(
            ok("mode=FAST"),
            (Probe::Mode, 0, Level::Choice(1), "MODE".into())
        );
        assert_eq!(
            ok("MODE=0"),
            (Probe::Mode, 0, Level::Choice(0), "MODE".into())
        );
    }

    #[test]
    fn a_setting_without_name_or_value_is_refused_with_an_example() {
        for text in ["S2", "=1", "S2=", "  "] {
            let e = parse(TABLE, text).expect_err(text);
            assert!(matches!(e, SettingError::NotNameValue { .. }), "{e:?}");
            assert_eq!(
                e.to_string(),
                format!(
                    "`{}` is no input setting: give NAME=VALUE, e.g. S1=1; \
                     the inputs are S1..S3=0|1, PA|PB=0|1|open, V0=<mV 0..500>, MODE=slow|fast",
                    text.trim()
                )
            );
        }
    }

    #[test]
    fn unknown_names_and_numbers_outside_the_row_list_the_inputs() {
        for (text, name) in [
            ("S4=1", "S4"),
            ("S0=1", "S0"),
            ("X=1", "X"),
            ("S+1=1", "S+1"),
        ] {
            let e = parse(TABLE, text).expect_err(text);
            assert_eq!(
                e.to_string(),
                format!(
                    "there is no input `{name}`: the inputs are S1..S3=0|1, PA|PB=0|1|open, V0=<mV 0..500>, MODE=slow|fast"
                )
            );
        }
        assert!(parse(TABLE, "S999=1").is_err(), "no overflow");
    }

    #[test]
    fn values_that_do_not_fit_the_input_say_what_it_takes() {
        let cases = [
            ("S1=2", "S1 takes 1 (on) or 0 (off), not `2`"),
            ("S1=open", "S1 takes 1 (on) or 0 (off), not `open`"),
            (
                "PA=yes",
                "PA takes 1 (on), 0 (off) or open (nothing connected), not `yes`",
            ),
            ("V0=501", "V0 takes a whole number of mV, 0..500, not `501`"),
            ("V0=-1", "V0 takes a whole number of mV, 0..500, not `-1`"),
            ("V0=1.5", "V0 takes a whole number of mV, 0..500, not `1.5`"),
            ("MODE=2", "MODE takes one of slow, fast (or 0..1), not `2`"),
            (
                "MODE=medium",
                "MODE takes one of slow, fast (or 0..1), not `medium`",
            ),
        ];
        for (text, message) in cases {
            let e = parse(TABLE, text).expect_err(text);
            assert!(matches!(e, SettingError::BadValue { .. }), "{e:?}");
            assert_eq!(e.to_string(), message);
        }
    }

    #[test]
    fn names_and_help_come_from_the_table() {
        assert_eq!(names(TABLE), ["S1", "S2", "S3", "PA", "PB", "V0", "MODE"]);
        assert_eq!(
            help_lines(TABLE),
            [
                "S1..S3=0|1: a switch",
                "PA|PB=0|1|open: a pin",
                "V0=<mV 0..500>: a voltage",
                "MODE=slow|fast: a mode"
            ]
        );
    }

    const LEVELS: &[InputRow<Probe>] = &[InputRow {
        input: Probe::Volts,
        names: Names::Numbered {
            stem: "A",
            first: 0,
            last: 1,
        },
        values: Values::NumberOr {
            max: 1023,
            unit: "counts",
            word: "stage",
            meaning: "from where the carriage is",
        },
        what: "a level or the stage's",
    }];

    #[test]
    fn a_number_or_its_word_is_read() {
        let read = |text| parse(LEVELS, text).map(|s| (s.which, s.level));
        assert_eq!(read("A1=1023"), Ok((1, Level::Number(1023))));
        assert_eq!(read("a0=Stage"), Ok((0, Level::Released)));
        let e = parse(LEVELS, "A0=1024").expect_err("above max");
        assert_eq!(
            e.to_string(),
            "A0 takes a whole number of counts, 0..1023, or stage (from where the carriage is), not `1024`"
        );
        assert_eq!(
            help_lines(LEVELS),
            ["A0..A1=<counts 0..1023>|stage: a level or the stage's"]
        );
        let e = parse(LEVELS, "A0").expect_err("no value");
        assert!(e.to_string().contains("e.g. A0=511"), "{e}");
    }

    #[test]
    fn nothing_typed_panics_the_parser() {
        for text in ["=", "==", "S1==1", "é=1", "S١=1", "\u{0}=\u{0}", "S1=1=1"] {
            let _ = parse(TABLE, text);
        }
    }
}
