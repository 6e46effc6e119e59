//! The built-in themes and keymaps (compiled in from `themes/` and
//! `keymaps/`) load, are complete, and keep their promises: the
//! high-contrast theme uses the 16 ANSI colours only, the mono theme no
//! colour at all, every keymap has F12 as its emergency stop in every pane.

use axterm::ui::keymap::{
    ACTIONS, Action, BUILTIN_KEYMAPS, Context, DEFAULT_KEYMAP, KeyChord, Keymap, parse_keymap,
};
use axterm::ui::theme::{
    BUILTIN_THEMES, DEFAULT_THEME, NO_COLOR_THEME, ROLES, Role, Theme, parse_theme,
};
use ratatui::style::{Color, Modifier};

fn chord(text: &str) -> KeyChord {
    text.parse().unwrap_or_else(|e| panic!("{text}: {e}"))
}

fn theme(name: &str) -> Theme {
    Theme::builtin(name).unwrap_or_else(|| panic!("built-in theme {name} does not load"))
}

fn keymap(name: &str) -> Keymap {
    Keymap::builtin(name).unwrap_or_else(|| panic!("built-in keymap {name} does not load"))
}

#[test]
fn the_builtin_themes_are_the_promised_ones() {
    let names: Vec<&str> = Theme::builtin_names().collect();
    assert_eq!(names, ["dark", "light", "high-contrast", "mono"]);
    assert_eq!(DEFAULT_THEME, "dark");
    assert_eq!(NO_COLOR_THEME, "mono");
}

#[test]
fn every_builtin_theme_parses_and_gives_every_role() {
    for (name, text) in BUILTIN_THEMES {
        // Parsed as a user file would be, to see any mistake spelt out.
        if let Err(errors) = parse_theme(name, text) {
            panic!("themes/{name}.toml: {errors:?}");
        }
        let table: toml::Table = text.parse().expect("valid TOML");
        let styles = table.get("styles").and_then(|s| s.as_table());
        for role in ROLES {
            assert!(
                styles.is_some_and(|s| s.contains_key(role.name)),
                "themes/{name}.toml has no style for {}",
                role.name
            );
        }
        let theme = theme(name);
        assert_eq!(theme.name(), *name);
        assert!(!theme.description().is_empty(), "{name} has no description");
    }
}

#[test]
fn the_high_contrast_theme_uses_the_16_ansi_colours_only() {
    let ansi = |c: Option<Color>| {
        matches!(
            c,
            None | Some(
                Color::Black
                    | Color::Red
                    | Color::Green
                    | Color::Yellow
                    | Color::Blue
                    | Color::Magenta
                    | Color::Cyan
                    | Color::Gray
                    | Color::DarkGray
                    | Color::LightRed
                    | Color::LightGreen
                    | Color::LightYellow
                    | Color::LightBlue
                    | Color::LightMagenta
                    | Color::LightCyan
                    | Color::White
            )
        )
    };
    let theme = theme("high-contrast");
    for role in ROLES {
        let style = theme.style(role.role);
        assert!(ansi(style.fg) && ansi(style.bg), "{}: {style:?}", role.name);
    }
    assert_eq!(theme.background(), Color::Black);
    assert_eq!(theme.foreground(), Color::White);
}

#[test]
fn only_the_mono_theme_is_monochrome() {
    for name in Theme::builtin_names() {
        assert_eq!(theme(name).is_monochrome(), name == "mono", "{name}");
    }
}

#[test]
fn the_mono_theme_keeps_lamps_selection_and_the_stop_key_readable() {
    let mono = theme("mono");
    let has = |role, modifier| mono.style(role).add_modifier.contains(modifier);
    assert!(has(Role::Selection, Modifier::REVERSED));
    assert!(has(Role::StatusBar, Modifier::REVERSED));
    assert!(has(Role::LampOn, Modifier::REVERSED));
    assert!(!has(Role::LampOff, Modifier::REVERSED));
    assert!(has(Role::Emergency, Modifier::REVERSED) && has(Role::Emergency, Modifier::BOLD));
    assert!(has(Role::Error, Modifier::BOLD));
}

#[test]
fn every_theme_tells_apart_what_must_differ() {
    for name in Theme::builtin_names() {
        let t = theme(name);
        let differ = |a: Role, b: Role| {
            assert_ne!(t.style(a), t.style(b), "{name}: {a:?} looks like {b:?}");
        };
        differ(Role::LampOn, Role::LampOff);
        differ(Role::LampAlarm, Role::LampOff);
        differ(Role::Selection, Role::Normal);
        differ(Role::Emergency, Role::Normal);
        differ(Role::Emergency, Role::StatusBar);
        differ(Role::Error, Role::Normal);
        differ(Role::Changed, Role::Normal);
        differ(Role::BorderFocused, Role::Border);
        differ(Role::CodeCurrent, Role::Normal);
    }
}

#[test]
fn the_builtin_keymaps_are_the_promised_ones() {
    let names: Vec<&str> = Keymap::builtin_names().collect();
    assert_eq!(names, ["default", "vim"]);
    assert_eq!(DEFAULT_KEYMAP, "default");
    for (name, text) in BUILTIN_KEYMAPS {
        if let Err(errors) = parse_keymap(name, text) {
            panic!("keymaps/{name}.toml: {errors:?}");
        }
        let keymap = keymap(name);
        assert_eq!(keymap.name(), *name);
        assert!(
            !keymap.description().is_empty(),
            "{name} has no description"
        );
    }
}

#[test]
fn every_builtin_keymap_binds_every_action() {
    for name in Keymap::builtin_names() {
        let keymap = keymap(name);
        for action in ACTIONS {
            let bound = Context::ALL
                .iter()
                .any(|c| !keymap.chords(*c, action.action).is_empty());
            assert!(bound, "keymap {name} has no key for {}", action.name);
        }
    }
}

#[test]
fn f12_is_the_emergency_stop_in_every_pane_of_every_builtin_keymap() {
    let f12 = chord("f12").to_event();
    for name in Keymap::builtin_names() {
        let keymap = keymap(name);
        assert_eq!(keymap.emergency_stop(), chord("f12"), "{name}");
        assert_eq!(keymap.stop_hint(), "F12 STOP", "{name}");
        for context in Context::ALL {
            assert_eq!(
                keymap.action_for(context, &f12),
                Some(Action::EmergencyStop),
                "{name}, {context}"
            );
            assert_eq!(
                keymap.hint(context, Action::EmergencyStop).as_deref(),
                Some("F12 STOP")
            );
        }
    }
}

#[test]
fn no_builtin_keymap_binds_what_terminals_swallow() {
    // XON/XOFF flow control (ctrl-q, ctrl-s) and job control (ctrl-z) can
    // be eaten on the way, and ctrl-h is backspace on some terminals.
    let swallowed = ["ctrl-q", "ctrl-s", "ctrl-z", "ctrl-h"].map(chord);
    for name in Keymap::builtin_names() {
        for binding in keymap(name).bindings() {
            for chord in &binding.chords {
                assert!(
                    !swallowed.contains(chord),
                    "keymap {name} binds {chord} to {}",
                    binding.action
                );
            }
        }
    }
}

/// Every binding of every built-in keymap is a key a terminal delivers:
/// xterm or one like it, tmux or screen between, legacy key encodings (what
/// axterm asks for), read by crossterm. The rule, with the reason for
/// each chord it refuses, is `axterm::ui::key_delivery`; in short: no F3
/// with a modifier (`ESC [1;2R` is read as a cursor position report, so
/// Shift-F3 never arrived), no F13-F24, ctrl only with a letter (not h)
/// or space, no modified Esc, no ctrl-/shift-Enter, ctrl-Tab,
/// alt-shift-Tab, ctrl-/shift-Backspace, no shift-PageUp/PageDown/Insert
/// (the terminal's scrollback and paste), no alt-[ or alt-O (the start of
/// escape sequences).
#[test]
fn every_builtin_binding_is_a_key_a_terminal_delivers() {
    use axterm::ui::key_delivery::why_undeliverable;
    // The rule refuses what issue 11 found, and what the encodings lose.
    for lost in [
        "shift-f3",
        "ctrl-f3",
        "f13",
        "ctrl-0",
        "ctrl-enter",
        "shift-pageup",
        "alt-[",
    ] {
        assert!(why_undeliverable(chord(lost)).is_some(), "{lost}");
    }
    let mut checked = 0;
    for name in Keymap::builtin_names() {
        for binding in keymap(name).bindings() {
            for chord in &binding.chords {
                checked += 1;
                if let Some(why) = why_undeliverable(*chord) {
                    panic!(
                        "keymap {name} binds {chord} to {} in [{}]: {why}",
                        binding.action, binding.context
                    );
                }
            }
        }
    }
    assert!(checked > 100, "only {checked} chords checked");
}

#[test]
fn upload_sits_beside_download_and_verify_on_a_key_that_arrives() {
    let keymap = keymap("default");
    let key = |action| keymap.chords(Context::Editor, action);
    assert_eq!(key(Action::EditorDownload), [chord("f4")]);
    assert_eq!(key(Action::EditorVerify), [chord("shift-f4")]);
    assert_eq!(key(Action::EditorUpload), [chord("ctrl-f4")]);
    assert_eq!(
        keymap.action_for(Context::Editor, &chord("ctrl-f4").to_event()),
        Some(Action::EditorUpload)
    );
}

#[test]
fn the_default_keymap_quits_on_f10_and_ctrl_c_only_cancels_a_line() {
    let keymap = keymap("default");
    let ctrl_c = chord("ctrl-c").to_event();
    for context in Context::ALL {
        assert_eq!(
            keymap.action_for(context, &chord("f10").to_event()),
            Some(Action::Quit)
        );
        let expected = (context == Context::Command).then_some(Action::Cancel);
        assert_eq!(keymap.action_for(context, &ctrl_c), expected, "{context}");
    }
}

#[test]
fn typed_characters_stay_text_in_the_command_line_and_the_editor() {
    for name in Keymap::builtin_names() {
        let keymap = keymap(name);
        for context in [Context::Command, Context::Editor] {
            for c in ['q', 'j', '?', '/', ' ', 'G', '1', '+'] {
                let event = KeyChord::plain(axterm::ui::keymap::Key::Char(c))
                    .expect("a plain character")
                    .to_event();
                assert_eq!(
                    keymap.action_for(context, &event),
                    None,
                    "{name}, {context}, {c:?}"
                );
            }
        }
    }
}
