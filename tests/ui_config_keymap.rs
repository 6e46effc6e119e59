//! Loading keymaps: user files override the built-ins action by action,
//! the emergency stop resolves in every pane and beats every pane binding,
//! conflicts and a missing emergency stop are refused, and a broken file
//! gives a message naming file, line and key, with the built-in used
//! instead.

use axterm::ui::config::{ConfigProblem, ProblemKind};
use axterm::ui::keymap::{
    Action, Context, KeyChord, Keymap, choose_keymap, load_keymap, parse_keymap,
};
use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};
use tempfile::TempDir;

fn chord(text: &str) -> KeyChord {
    text.parse().unwrap_or_else(|e| panic!("{text}: {e}"))
}

fn press(text: &str) -> KeyEvent {
    chord(text).to_event()
}

fn builtin(name: &str) -> Keymap {
    Keymap::builtin(name).expect("a built-in keymap")
}

fn config_dir_with(files: &[(&str, &str)]) -> TempDir {
    let dir = tempfile::tempdir().expect("a temporary directory");
    for (path, content) in files {
        let path = dir.path().join(path);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).expect("create the folder");
        }
        std::fs::write(&path, content).expect("write the file");
    }
    dir
}

fn user(name: &str, text: &str) -> Keymap {
    let dir = config_dir_with(&[(&format!("keymaps/{name}.toml"), text)]);
    let loaded = load_keymap(name, Some(dir.path()));
    if let Some(problem) = loaded.problem {
        panic!("{problem}");
    }
    loaded.value
}

/// Loads `name` from a config directory holding `keymaps/NAME.toml` with
/// `text`, expecting a problem; checks the fallback and returns the problem.
fn broken(name: &str, text: &str, fallback: &str) -> ConfigProblem {
    let dir = config_dir_with(&[(&format!("keymaps/{name}.toml"), text)]);
    let loaded = load_keymap(name, Some(dir.path()));
    let problem = loaded.problem.expect("a problem with the file");
    assert_eq!(problem.kind, ProblemKind::Invalid);
    assert_eq!(
        problem.file,
        dir.path().join("keymaps").join(format!("{name}.toml"))
    );
    assert_eq!(loaded.value, builtin(fallback), "falls back to {fallback}");
    assert_eq!(
        problem.fallback,
        format!("the built-in keymap `{fallback}`")
    );
    problem
}

/// The one error of `problem`: line, key and message.
fn only_error(problem: &ConfigProblem) -> (usize, &str, &str) {
    assert_eq!(problem.errors.len(), 1, "{problem}");
    let e = &problem.errors[0];
    (
        e.line.expect("a line"),
        e.key.as_deref().expect("a key"),
        e.message.as_str(),
    )
}

#[test]
fn without_user_files_the_builtins_load() {
    let dir = config_dir_with(&[]);
    for name in Keymap::builtin_names() {
        let loaded = load_keymap(name, Some(dir.path()));
        assert!(loaded.problem.is_none(), "{name}");
        assert_eq!(loaded.value, builtin(name));
    }
    assert_eq!(
        choose_keymap(None, Some(dir.path())).value,
        builtin("default")
    );
    assert_eq!(choose_keymap(Some("vim"), None).value, builtin("vim"));
}

#[test]
fn a_user_file_overrides_the_builtin_action_by_action() {
    let keymap = user("default", "[global]\nhelp = \"alt-h\"\nclear_errors = []\n");
    assert_eq!(
        keymap.action_for(Context::Command, &press("alt-h")),
        Some(Action::Help)
    );
    // Replaced, not added to: F1 no longer helps.
    assert_eq!(keymap.action_for(Context::Axis, &press("f1")), None);
    // Unbound.
    assert_eq!(keymap.action_for(Context::Axis, &press("f8")), None);
    assert!(keymap.chords(Context::Axis, Action::ClearErrors).is_empty());
    // Everything else is the built-in's.
    assert_eq!(
        keymap.action_for(Context::Editor, &press("f2")),
        Some(Action::EditorSave)
    );
    assert_eq!(
        keymap.action_for(Context::Axis, &press("f10")),
        Some(Action::Quit)
    );
    assert_eq!(
        keymap.hint(Context::Axis, Action::Help).as_deref(),
        Some("Alt-h Help")
    );
}

#[test]
fn a_user_keymap_of_a_new_name_inherits_default_or_its_base() {
    let mine = user("mine", "[traffic]\npause_traffic = \"z\"\n");
    assert_eq!(mine.name(), "mine");
    assert_eq!(
        mine.action_for(Context::Traffic, &press("z")),
        Some(Action::PauseTraffic)
    );
    assert_eq!(mine.action_for(Context::Traffic, &press("space")), None);
    assert_eq!(
        mine.action_for(Context::Editor, &press("f9")),
        Some(Action::EditorAssemble)
    );

    let vimmish = user("vimmish", "base = \"vim\"\n[plot]\nplot_pause = \"p\"\n");
    assert_eq!(
        vimmish.action_for(Context::Plot, &press("p")),
        Some(Action::PlotPause)
    );
    assert_eq!(
        vimmish.action_for(Context::Parameters, &press("j")),
        Some(Action::SelectNext)
    );
}

#[test]
fn a_moved_emergency_stop_works_in_every_pane_and_shows_in_the_status_bar() {
    let keymap = user(
        "default",
        "[global]\nemergency_stop = [\"ctrl-x\", \"f12\"]\n",
    );
    for context in Context::ALL {
        for key in ["ctrl-x", "f12"] {
            assert_eq!(
                keymap.action_for(context, &press(key)),
                Some(Action::EmergencyStop),
                "{key} in {context}"
            );
        }
    }
    assert_eq!(keymap.emergency_stop(), chord("ctrl-x"));
    assert_eq!(keymap.stop_hint(), "Ctrl-X STOP");
    assert_eq!(
        keymap.chords(Context::Editor, Action::EmergencyStop),
        [chord("ctrl-x"), chord("f12")]
    );
}

#[test]
fn global_keys_are_looked_up_before_the_pane_s() {
    let keymap = builtin("default");
    // In the command line, `up` recalls history; F6 moves on from anywhere.
    assert_eq!(
        keymap.action_for(Context::Command, &press("up")),
        Some(Action::HistoryPrevious)
    );
    assert_eq!(
        keymap.action_for(Context::Editor, &press("f6")),
        Some(Action::NextPane)
    );
    // The same key means different things in different panes.
    assert_eq!(
        keymap.action_for(Context::Axis, &press("space")),
        Some(Action::AxisStop)
    );
    assert_eq!(
        keymap.action_for(Context::Plot, &press("space")),
        Some(Action::PlotPause)
    );
    assert_eq!(keymap.action_for(Context::Command, &press("space")), None);
    // Context::Global alone sees only the global keys.
    assert_eq!(keymap.action_for(Context::Global, &press("space")), None);
    assert_eq!(
        keymap.action_for(Context::Global, &press("f12")),
        Some(Action::EmergencyStop)
    );
}

#[test]
fn key_releases_do_nothing() {
    let keymap = builtin("default");
    let mut release = press("f12");
    release.kind = KeyEventKind::Release;
    assert_eq!(keymap.action_for(Context::Editor, &release), None);
    let mut repeat = press("f12");
    repeat.kind = KeyEventKind::Repeat;
    assert_eq!(
        keymap.action_for(Context::Editor, &repeat),
        Some(Action::EmergencyStop)
    );
}

#[test]
fn terminal_reports_of_one_key_match_one_binding() {
    let keymap = builtin("default");
    // crossterm reports shift-tab as BackTab, with or without shift.
    for m in [KeyModifiers::SHIFT, KeyModifiers::NONE] {
        let event = KeyEvent::new(KeyCode::BackTab, m);
        assert_eq!(
            keymap.action_for(Context::Axis, &event),
            Some(Action::PreviousPane)
        );
    }
    let vim = builtin("vim");
    for m in [KeyModifiers::SHIFT, KeyModifiers::NONE] {
        let event = KeyEvent::new(KeyCode::Char('G'), m);
        assert_eq!(
            vim.action_for(Context::Traffic, &event),
            Some(Action::ScrollBottom)
        );
    }
}

#[test]
fn a_pane_key_held_by_a_global_binding_is_a_conflict_naming_both() {
    let problem = broken("default", "[editor]\neditor_save = \"f12\"\n", "default");
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (2, "editor.editor_save"));
    assert!(message.contains("`f12`"), "{message}");
    assert!(
        message.contains("`emergency_stop` in [global]"),
        "{message}"
    );
    assert!(
        message.contains("`editor_save` in [editor] (line 2)"),
        "{message}"
    );
    assert!(message.contains("could never be used"), "{message}");

    // The other way round: a global key that a built-in pane binding holds.
    let problem = broken("default", "[global]\nhelp = \"f2\"\n", "default");
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (2, "global.help"));
    assert!(message.contains("`help` in [global] (line 2)"), "{message}");
    assert!(
        message.contains("`editor_save` in [editor] (built-in keymap `default`"),
        "{message}"
    );
}

#[test]
fn two_actions_on_one_key_in_one_pane_is_a_conflict_naming_both() {
    let text = "[plot]\nplot_zoom_in = \"x\"\nplot_zoom_out = [\"-\", \"x\"]\n";
    let problem = broken("default", text, "default");
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (3, "plot.plot_zoom_out"));
    assert!(
        message.contains("`plot_zoom_in` in [plot] (line 2)"),
        "{message}"
    );
    assert!(
        message.contains("`plot_zoom_out` in [plot] (line 3)"),
        "{message}"
    );
    assert_eq!(problem.errors[0].column, Some(23));

    // Against the built-in's binding, the user's line is the one named.
    let problem = broken("vim", "[traffic]\nclear_traffic = \"p\"\n", "vim");
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (2, "traffic.clear_traffic"));
    assert!(
        message.contains("`toggle_hide_polls` in [traffic] (built-in keymap `vim`"),
        "{message}"
    );
}

#[test]
fn the_same_action_on_one_key_globally_and_in_a_pane_is_no_conflict() {
    let keymap = user("default", "[traffic]\nquit = \"f10\"\n");
    assert_eq!(
        keymap.action_for(Context::Traffic, &press("f10")),
        Some(Action::Quit)
    );
}

#[test]
fn a_keymap_without_an_emergency_stop_does_not_load() {
    let problem = broken(
        "default",
        "[global]\nquit = \"f10\"\nemergency_stop = []\n",
        "default",
    );
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (3, "global.emergency_stop"));
    assert!(message.contains("no emergency stop"), "{message}");
}

#[test]
fn the_emergency_stop_belongs_in_global_only() {
    let problem = broken(
        "default",
        "[editor]\nemergency_stop = \"ctrl-e\"\n",
        "default",
    );
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (2, "editor.emergency_stop"));
    assert!(message.contains("belongs in [global]"), "{message}");
}

#[test]
fn a_plain_character_cannot_be_global_or_bound_where_text_is_typed() {
    let problem = broken("default", "[global]\nquit = \"q\"\n", "default");
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (2, "global.quit"));
    assert!(message.contains("typed in the command line"), "{message}");

    let problem = broken(
        "default",
        "[editor]\neditor_run = [\"f5\", \"r\"]\n",
        "default",
    );
    let (line, key, message) = only_error(&problem);
    assert_eq!(
        (line, key, problem.errors[0].column),
        (2, "editor.editor_run", Some(21))
    );
    assert!(message.contains("it is text there"), "{message}");
}

#[test]
fn an_unknown_key_name_names_line_column_and_key() {
    let problem = broken(
        "default",
        "[axis]\naxis_stop = [\"space\", \"ctrl-foo\"]\n",
        "default",
    );
    let (line, key, message) = only_error(&problem);
    assert_eq!(
        (line, key, problem.errors[0].column),
        (2, "axis.axis_stop", Some(23))
    );
    assert!(message.contains("`ctrl-foo`"), "{message}");
    assert!(message.contains("unknown key `foo`"), "{message}");

    let problem = broken("default", "[command]\ncomplete = \"ctrl-i\"\n", "default");
    let (_, _, message) = only_error(&problem);
    assert!(message.contains("bind `tab` instead"), "{message}");
}

#[test]
fn an_unknown_action_or_one_in_the_wrong_section_is_named() {
    let problem = broken("vim", "[plot]\nzoom = \"z\"\n", "vim");
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (2, "plot.zoom"));
    assert!(message.contains("unknown action `zoom`"), "{message}");

    let problem = broken("vim", "[axis]\neditor_save = \"x\"\n", "vim");
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (2, "axis.editor_save"));
    assert!(message.contains("it belongs in [editor]"), "{message}");
}

#[test]
fn toml_mistakes_are_named_with_line_and_key() {
    let problem = broken(
        "default",
        "[global]\nhelp = \"f1\nquit = \"f10\"\n",
        "default",
    );
    let (line, key, _) = only_error(&problem);
    assert_eq!((line, key), (2, "global.help"));

    let problem = broken("default", "[gobal]\nhelp = \"f1\"\n", "default");
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (1, "gobal"));
    assert!(
        message.contains("unknown section or key `gobal`"),
        "{message}"
    );

    let problem = broken("default", "[global]\nhelp = 1\n", "default");
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (2, "global.help"));
    assert!(message.contains(r#"a key such as "f12""#), "{message}");

    let problem = broken("default", "base = \"emacs\"\n", "default");
    let (line, key, message) = only_error(&problem);
    assert_eq!((line, key), (1, "base"));
    assert!(
        message.contains("no built-in keymap named `emacs`"),
        "{message}"
    );
}

#[test]
fn a_broken_user_keymap_of_a_new_name_falls_back_to_default() {
    let problem = broken("mine", "[global]\nquit = \"q\"\n", "default");
    let shown = problem.to_string();
    let file = problem.file.display().to_string();
    assert!(
        shown.starts_with(&format!("{file}:2:8: global.quit: ")),
        "{shown}"
    );
    assert!(
        shown.ends_with("using the built-in keymap `default` instead"),
        "{shown}"
    );
}

#[test]
fn every_mistake_of_a_file_is_listed_in_file_order() {
    let text = "[plot]\nzoom = \"z\"\n[axis]\naxis_stop = \"ctrl-\"\n[global]\nquit = \"q\"\n";
    let problem = broken("default", text, "default");
    let lines: Vec<Option<usize>> = problem.errors.iter().map(|e| e.line).collect();
    assert_eq!(lines, [Some(2), Some(4), Some(6)]);
}

#[test]
fn an_unknown_keymap_name_is_a_problem_and_default_is_used() {
    let dir = config_dir_with(&[]);
    let loaded = load_keymap("emacs", Some(dir.path()));
    let problem = loaded.problem.expect("a problem");
    assert_eq!(problem.kind, ProblemKind::NotFound);
    assert!(
        problem.errors[0]
            .message
            .contains("no keymap named `emacs`")
    );
    assert_eq!(loaded.value, builtin("default"));
}

#[test]
fn parse_keymap_reads_without_files() {
    let keymap = parse_keymap("x", "[plot]\nplot_zoom_reset = \"ctrl-0\"\n").expect("valid");
    assert_eq!(
        keymap.action_for_chord(Context::Plot, chord("ctrl-0")),
        Some(Action::PlotZoomReset)
    );
    assert_eq!(keymap.action_for_chord(Context::Plot, chord("0")), None);
}

#[test]
fn bindings_list_every_section_for_the_help() {
    let keymap = builtin("default");
    let editor: Vec<Action> = keymap
        .bindings()
        .iter()
        .filter(|b| b.context == Context::Editor)
        .map(|b| b.action)
        .collect();
    assert!(editor.contains(&Action::EditorStep));
    let stop = keymap
        .bindings()
        .iter()
        .find(|b| b.action == Action::EmergencyStop)
        .expect("an emergency stop binding");
    assert_eq!(
        (stop.context, stop.chords.as_slice()),
        (Context::Global, &[chord("f12")][..])
    );
    assert_eq!(
        keymap.hint(Context::Editor, Action::EditorRun).as_deref(),
        Some("F5 Run")
    );
    assert_eq!(keymap.hint(Context::Axis, Action::EditorRun), None);
}
