//! Properties of key chords, style texts and file reading: chords written
//! back parse to themselves, terminal events round-trip, and no text (a
//! user's file, a chord, a style) makes the readers panic.

use axterm::ui::keymap::{Key, KeyChord, MAX_FUNCTION_KEY, Modifiers, parse_keymap};
use axterm::ui::theme::{parse_style, parse_theme};
use proptest::prelude::*;

fn key() -> impl Strategy<Value = Key> {
    prop_oneof![
        any::<char>().prop_map(Key::Char),
        prop::sample::select(vec!['a', 'Z', '-', '+', ' ', '?', '/', '1', 'é', 'ß'])
            .prop_map(Key::Char),
        (1..=MAX_FUNCTION_KEY).prop_map(Key::F),
        prop::sample::select(vec![
            Key::Esc,
            Key::Enter,
            Key::Tab,
            Key::Backspace,
            Key::Delete,
            Key::Insert,
            Key::Home,
            Key::End,
            Key::PageUp,
            Key::PageDown,
            Key::Up,
            Key::Down,
            Key::Left,
            Key::Right,
        ]),
    ]
}

fn modifiers() -> impl Strategy<Value = Modifiers> {
    (any::<bool>(), any::<bool>(), any::<bool>()).prop_map(|(ctrl, alt, shift)| Modifiers {
        ctrl,
        alt,
        shift,
    })
}

/// Every chord a keymap can hold.
fn chord() -> impl Strategy<Value = KeyChord> {
    (key(), modifiers()).prop_filter_map("not a chord", |(k, m)| KeyChord::new(k, m).ok())
}

/// Texts that look like chords, to reach the parser's corners.
fn chord_like_text() -> impl Strategy<Value = String> {
    let part = prop::sample::select(vec![
        "ctrl-", "alt-", "shift-", "control-", "Ctrl-", "-", "f", "F1", "f24", "f25", "backtab",
        "tab", "space", "a", "A", "[", "é", "pgup", "x", "", "1", "ctrl",
    ]);
    prop::collection::vec(part, 0..5).prop_map(|parts| parts.concat())
}

proptest! {
    #[test]
    fn a_chord_written_back_parses_to_itself(chord in chord()) {
        let written = chord.to_string();
        prop_assert_eq!(written.parse::<KeyChord>(), Ok(chord), "{}", written);
        prop_assert!(!chord.label().is_empty());
    }

    #[test]
    fn a_chord_pressed_is_the_chord(chord in chord()) {
        prop_assert_eq!(KeyChord::from_event(&chord.to_event()), Some(chord));
    }

    #[test]
    fn any_text_either_parses_to_a_chord_that_writes_back_or_is_refused(
        text in prop_oneof![chord_like_text(), any::<String>()]
    ) {
        if let Ok(chord) = text.parse::<KeyChord>() {
            prop_assert_eq!(chord.to_string().parse::<KeyChord>(), Ok(chord));
        }
    }

    #[test]
    fn a_style_text_means_its_words_whatever_the_spacing(
        words in prop::collection::vec(
            prop_oneof![
                prop::sample::select(vec![
                    "on", "bold", "Reversed", "dim", "red", "light_cyan", "#1c1c1c", "indexed:7",
                    "default", "blod", "#12", "indexed:300",
                ]).prop_map(str::to_string),
                "[^ \t\n\r]{1,6}",
            ],
            0..5,
        ),
        gap in "[ \t]{1,3}",
    ) {
        let tight = parse_style(&words.join(" "));
        let loose = parse_style(&format!("{gap}{}{gap}", words.join(&gap)));
        // Messages quote the text as written; the meaning is the same.
        prop_assert_eq!(tight.as_ref().ok(), loose.as_ref().ok());
        prop_assert_eq!(tight.is_err(), loose.is_err());
        if let Err(message) = tight {
            prop_assert!(!message.is_empty());
        }
    }

    #[test]
    fn theme_and_keymap_files_never_panic_and_errors_have_places(
        text in prop_oneof![
            any::<String>(),
            // Near misses of real files, so the readers get past TOML.
            (prop::sample::select(vec!["[styles]", "[global]", "[plot]", "base = ", "[axis]"]),
             "[a-z_]{0,12}", prop::sample::select(vec![" = ", "="]), any::<String>())
                .prop_map(|(h, k, eq, v)| format!("{h}\n{k}{eq}\"{}\"\n", v.replace(['"', '\\'], ""))),
        ]
    ) {
        for errors in [parse_theme("t", &text).err(), parse_keymap("k", &text).err()].into_iter().flatten() {
            prop_assert!(!errors.is_empty());
            for e in &errors {
                prop_assert!(e.line.is_none_or(|l| l >= 1 && l <= text.lines().count().max(1) + 1));
                prop_assert!(!e.message.is_empty());
            }
        }
    }
}
