//! Loading themes: user files in the config directory override the
//! built-ins, a partial file inherits, NO_COLOR selects the monochrome
//! theme, and a broken file gives a message naming file, line and key,
//! with the built-in used instead.

use std::path::Path;

use axterm::ui::config::{ConfigProblem, ProblemKind};
use axterm::ui::theme::{ROLES, Role, Theme, choose_theme, load_theme, parse_theme};
use ratatui::style::{Color, Modifier};
use tempfile::TempDir;

fn config_dir_with(files: &[(&str, &[u8])]) -> TempDir {
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

fn builtin(name: &str) -> Theme {
    Theme::builtin(name).expect("a built-in theme")
}

/// Loads `name` from a config directory holding `themes/NAME.toml` with
/// `text`, expecting a problem; returns it and checks the fallback.
fn broken(name: &str, text: &str, fallback: &str) -> ConfigProblem {
    let dir = config_dir_with(&[(&format!("themes/{name}.toml"), text.as_bytes())]);
    let loaded = load_theme(name, Some(dir.path()));
    let problem = loaded.problem.expect("a problem with the file");
    assert_eq!(problem.kind, ProblemKind::Invalid);
    assert_eq!(
        problem.file,
        dir.path().join("themes").join(format!("{name}.toml"))
    );
    assert_eq!(loaded.value, builtin(fallback), "falls back to {fallback}");
    assert_eq!(problem.fallback, format!("the built-in theme `{fallback}`"));
    problem
}

fn first_error(problem: &ConfigProblem) -> (Option<usize>, Option<usize>, Option<&str>, &str) {
    let e = problem.errors.first().expect("at least one error");
    (e.line, e.column, e.key.as_deref(), e.message.as_str())
}

#[test]
fn without_user_files_the_builtins_load() {
    let dir = config_dir_with(&[]);
    for name in Theme::builtin_names() {
        let loaded = load_theme(name, Some(dir.path()));
        assert!(loaded.problem.is_none(), "{name}");
        assert_eq!(loaded.value, builtin(name));
    }
    // No config directory at all (no home): the same.
    let loaded = load_theme("light", None);
    assert!(loaded.problem.is_none());
    assert_eq!(loaded.value, builtin("light"));
}

#[test]
fn a_user_file_overrides_the_builtin_of_its_name_role_by_role() {
    let dir = config_dir_with(&[(
        "themes/dark.toml",
        b"[styles]\naccent = \"red\"\nselection = \"reversed\"\n",
    )]);
    let loaded = load_theme("dark", Some(dir.path()));
    assert!(loaded.problem.is_none(), "{:?}", loaded.problem);
    let theme = loaded.value;
    let dark = builtin("dark");
    assert_eq!(theme.style(Role::Accent).fg, Some(Color::Red));
    assert_eq!(
        theme.style(Role::Selection).add_modifier,
        Modifier::REVERSED
    );
    assert_eq!(theme.style(Role::Selection).bg, None);
    for role in ROLES {
        if !matches!(role.role, Role::Accent | Role::Selection) {
            assert_eq!(
                theme.style(role.role),
                dark.style(role.role),
                "{}",
                role.name
            );
        }
    }
    assert_eq!(theme.name(), "dark");
}

#[test]
fn a_user_theme_of_a_new_name_inherits_dark_or_its_base() {
    let dir = config_dir_with(&[
        (
            "themes/plant.toml",
            b"[styles]\nemergency = \"bold yellow on red\"\n",
        ),
        (
            "themes/office.toml",
            b"base = \"light\"\ndescription = \"office\"\n[styles]\nok = \"green\"\n",
        ),
    ]);
    let plant = load_theme("plant", Some(dir.path()));
    assert!(plant.problem.is_none());
    assert_eq!(plant.value.name(), "plant");
    assert_eq!(plant.value.style(Role::Emergency).fg, Some(Color::Yellow));
    assert_eq!(plant.value.background(), builtin("dark").background());

    let office = load_theme("office", Some(dir.path()));
    assert!(office.problem.is_none());
    assert_eq!(office.value.style(Role::Ok).fg, Some(Color::Green));
    assert_eq!(
        office.value.style(Role::Error),
        builtin("light").style(Role::Error)
    );
    assert_eq!(office.value.description(), "office");
}

#[test]
fn choosing_a_theme_honours_the_flag_then_no_color_then_the_default() {
    let dir = config_dir_with(&[]);
    let dir = Some(dir.path());
    assert_eq!(choose_theme(None, false, dir).value, builtin("dark"));
    let no_color = choose_theme(None, true, dir).value;
    assert_eq!(no_color, builtin("mono"));
    assert!(no_color.is_monochrome());
    // no-color.org: an explicit choice wins over the environment.
    assert_eq!(
        choose_theme(Some("light"), true, dir).value,
        builtin("light")
    );
    assert_eq!(
        choose_theme(Some("high-contrast"), false, dir).value,
        builtin("high-contrast")
    );
}

#[test]
fn an_unknown_theme_name_is_a_problem_and_dark_is_used() {
    let dir = config_dir_with(&[]);
    let loaded = load_theme("solarized", Some(dir.path()));
    let problem = loaded.problem.expect("a problem");
    assert_eq!(problem.kind, ProblemKind::NotFound);
    assert_eq!(
        problem.file,
        dir.path().join("themes").join("solarized.toml")
    );
    assert!(
        problem.errors[0]
            .message
            .contains("no theme named `solarized`")
    );
    assert!(problem.errors[0].message.contains("high-contrast"));
    assert_eq!(loaded.value, builtin("dark"));
    // A name that is no file name is not looked for on disk.
    let loaded = load_theme("../dark", Some(dir.path()));
    assert_eq!(loaded.problem.map(|p| p.kind), Some(ProblemKind::NotFound));
}

#[test]
fn a_toml_syntax_error_names_file_line_column_and_key() {
    let problem = broken(
        "dark",
        "# my colours\n[styles]\naccent = \"red\nok = \"green\"\n",
        "dark",
    );
    let (line, column, key, _) = first_error(&problem);
    assert_eq!(line, Some(3));
    assert!(column.is_some());
    assert_eq!(key, Some("styles.accent"));
    let shown = problem.to_string();
    let file = problem.file.display().to_string();
    assert!(shown.starts_with(&format!("{file}:3:")), "{shown}");
    assert!(shown.contains("styles.accent: "), "{shown}");
    assert!(
        shown.ends_with("using the built-in theme `dark` instead"),
        "{shown}"
    );
}

#[test]
fn an_unknown_colour_names_line_column_key_and_colour() {
    let problem = broken(
        "light",
        "[styles]\nok = \"green\"\nwarning = \"bold chartreuse\"\n",
        "light",
    );
    assert_eq!(
        first_error(&problem),
        (
            Some(3),
            Some(11),
            Some("styles.warning"),
            first_error(&problem).3
        )
    );
    assert!(first_error(&problem).3.contains("`chartreuse`"));
    let problem = broken("dark", "[styles]\nnormal = \"#12345 on black\"\n", "dark");
    assert_eq!(first_error(&problem).0, Some(2));
    assert!(first_error(&problem).3.contains("#12345"));
}

#[test]
fn an_unknown_role_or_section_is_named() {
    let problem = broken("dark", "[styles]\nacent = \"red\"\n", "dark");
    let (line, column, key, message) = first_error(&problem);
    assert_eq!(
        (line, column, key),
        (Some(2), Some(1), Some("styles.acent"))
    );
    assert!(message.contains("unknown role `acent`"), "{message}");

    let problem = broken(
        "dark",
        "name = \"dark\"\n\n[colours]\naccent = \"red\"\n",
        "dark",
    );
    let (line, _, key, message) = first_error(&problem);
    assert_eq!((line, key), (Some(3), Some("colours")));
    assert!(
        message.contains("unknown section or key `colours`"),
        "{message}"
    );
}

#[test]
fn a_value_of_the_wrong_type_is_named() {
    let problem = broken("dark", "[styles]\naccent = 3\n", "dark");
    let (line, _, key, message) = first_error(&problem);
    assert_eq!((line, key), (Some(2), Some("styles.accent")));
    assert!(message.contains("string"), "{message}");
}

#[test]
fn files_with_windows_line_ends_read_the_same() {
    let theme = parse_theme("dark", "[styles]\r\naccent = \"red\"\r\n").expect("valid");
    assert_eq!(theme.style(Role::Accent).fg, Some(Color::Red));
    let errors = parse_theme("dark", "[styles]\r\nok = \"green\"\r\nerror = \"x\"\r\n")
        .expect_err("an unknown colour");
    assert_eq!(
        (errors[0].line, errors[0].column, errors[0].key.as_deref()),
        (Some(3), Some(9), Some("styles.error"))
    );
}

#[test]
fn a_base_that_is_no_builtin_is_named() {
    let problem = broken(
        "mine",
        "base = \"drak\"\n[styles]\nok = \"green\"\n",
        "dark",
    );
    let (line, column, key, message) = first_error(&problem);
    assert_eq!((line, column, key), (Some(1), Some(8), Some("base")));
    assert!(message.contains("`drak`"), "{message}");
}

#[test]
fn every_mistake_of_a_file_is_listed_in_file_order() {
    let problem = broken(
        "high-contrast",
        "[styles]\nzz = \"red\"\naccent = \"blod\"\nok = \"on\"\n",
        "high-contrast",
    );
    let lines: Vec<Option<usize>> = problem.errors.iter().map(|e| e.line).collect();
    assert_eq!(lines, [Some(2), Some(3), Some(4)]);
    assert_eq!(problem.to_string().lines().count(), 4);
}

#[test]
fn a_file_that_is_not_text_is_unreadable_and_the_builtin_is_used() {
    let dir = config_dir_with(&[("themes/dark.toml", b"[styles]\naccent = \"\xff\xfe\"\n")]);
    let loaded = load_theme("dark", Some(dir.path()));
    let problem = loaded.problem.expect("a problem");
    assert_eq!(problem.kind, ProblemKind::Unreadable);
    assert!(problem.errors[0].message.contains("UTF-8"));
    assert_eq!(loaded.value, builtin("dark"));
}

#[test]
fn parse_theme_is_the_same_reading_without_files() {
    let theme = parse_theme("x", "[styles]\nmuted = \"indexed:244 italic\"\n").expect("valid");
    assert_eq!(theme.style(Role::Muted).fg, Some(Color::Indexed(244)));
    assert!(
        theme
            .style(Role::Muted)
            .add_modifier
            .contains(Modifier::ITALIC)
    );
    let errors = parse_theme("x", "[styles]\nmuted = \"indexed:300\"\n").expect_err("invalid");
    assert_eq!(errors[0].key.as_deref(), Some("styles.muted"));
}

#[test]
fn the_platform_config_dir_ends_in_axterm() {
    // Only where the platform has a home; the name is what matters.
    if let Some(dir) = axterm::ui::config::platform_config_dir() {
        let named_axterm = dir
            .components()
            .any(|c| c.as_os_str() == Path::new("axterm").as_os_str());
        assert!(named_axterm, "{}", dir.display());
    }
}
