//! The built-in theme and keymap files ship as valid TOML with the keys
//! every console needs (the emergency stop above all).

fn parse(text: &str, file: &str) -> toml::Table {
    text.parse::<toml::Table>()
        .unwrap_or_else(|e| panic!("{file} is not valid TOML: {e}"))
}

#[test]
fn the_default_keymap_binds_the_emergency_stop() {
    let keymap = parse(
        include_str!("../keymaps/default.toml"),
        "keymaps/default.toml",
    );
    let stop = keymap
        .get("global")
        .and_then(|g| g.get("emergency_stop"))
        .and_then(|k| k.as_str());
    assert_eq!(stop, Some("f12"));
}

#[test]
fn the_dark_theme_names_its_colours() {
    let theme = parse(include_str!("../themes/dark.toml"), "themes/dark.toml");
    assert_eq!(theme.get("name").and_then(|n| n.as_str()), Some("dark"));
    let colors = theme.get("colors").and_then(|c| c.as_table());
    for role in ["background", "foreground", "error", "emergency"] {
        assert!(
            colors.is_some_and(|c| c.contains_key(role)),
            "themes/dark.toml has no colour for {role}"
        );
    }
}
