//! Colours of the console: a [`Theme`] gives every [`Role`] (ordinary
//! text, borders, the emergency stop badge, sent and received traffic,
//! lamps, gauges, program source…) a ratatui [`Style`].
//!
//! Themes are TOML files. The built-ins in `themes/` are compiled in; a
//! user's `themes/NAME.toml` in the platform config directory overrides
//! the built-in of the same name. A file may give only some roles: the
//! rest come from its `base` (a built-in name), which defaults to the
//! built-in of the same name, else to `dark`. Each role is a short style
//! text, git-config style:
//!
//! ```toml
//! base = "dark"
//! [styles]
//! normal = "#d0d0d0 on #1c1c1c"   # foreground on background
//! error = "light_red bold"         # colour and modifiers, any order
//! selection = "reversed"           # modifiers alone
//! ```
//!
//! `NO_COLOR` (set and not empty, per no-color.org) selects the `mono`
//! built-in, which uses only bold, dim, reversed and underlined, unless a
//! theme is named explicitly (`--theme`): per no-color.org, an explicit
//! choice wins over the environment.

use std::collections::BTreeMap;
use std::ffi::OsStr;
use std::path::Path;

use ratatui::style::{Color, Modifier, Style};
use serde::Deserialize;
use toml::Spanned;

use super::config::{self, ConfigError, ConfigKind, Loaded, load_config};

/// What a piece of the screen is, for colouring. The TUI styles
/// everything through these.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Role {
    Normal,
    Muted,
    Accent,
    Title,
    Border,
    BorderFocused,
    StatusBar,
    StatusKey,
    Emergency,
    Ok,
    Warning,
    Error,
    Selection,
    Changed,
    Matched,
    Prompt,
    Sent,
    Received,
    Poll,
    GaugeFill,
    GaugeEmpty,
    LampOn,
    LampOff,
    LampAlarm,
    CodeMnemonic,
    CodeLabel,
    CodeNumber,
    CodeComment,
    CodeGutter,
    CodeCurrent,
    CodeError,
    PlotAxes,
    Plot1,
    Plot2,
    Plot3,
    Plot4,
}

/// A role's name in theme files and what it colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RoleInfo {
    pub role: Role,
    pub name: &'static str,
    pub purpose: &'static str,
}

const fn role(role: Role, name: &'static str, purpose: &'static str) -> RoleInfo {
    RoleInfo {
        role,
        name,
        purpose,
    }
}

/// Every role, in [`Role`] order.
#[rustfmt::skip]
pub const ROLES: &[RoleInfo] = &[
    role(Role::Normal, "normal", "ordinary text on the screen's background (give both: `fg on bg`)"),
    role(Role::Muted, "muted", "hints, units, values of lesser interest"),
    role(Role::Accent, "accent", "what deserves the eye: the focused item, links between panes"),
    role(Role::Title, "title", "pane titles"),
    role(Role::Border, "border", "borders of panes without the focus"),
    role(Role::BorderFocused, "border_focused", "the border of the pane with the focus"),
    role(Role::StatusBar, "status_bar", "the status bar line"),
    role(Role::StatusKey, "status_key", "key names in the status bar and the help"),
    role(Role::Emergency, "emergency", "the emergency stop key in the status bar, and stop messages"),
    role(Role::Ok, "ok", "success: a reply with status OK, a finished transfer"),
    role(Role::Warning, "warning", "warnings: a limit switch hit, a value out of the usual range"),
    role(Role::Error, "error", "errors: a rejected command, a timeout, a broken file"),
    role(Role::Selection, "selection", "the selected row of a list or table"),
    role(Role::Changed, "changed", "a value that changed since the last poll"),
    role(Role::Matched, "matched", "the part of a name that matches a filter or completion"),
    role(Role::Prompt, "prompt", "the command line prompt"),
    role(Role::Sent, "sent", "traffic: what the console sent"),
    role(Role::Received, "received", "traffic: what the controller replied"),
    role(Role::Poll, "poll", "traffic: the console's own status polls"),
    role(Role::GaugeFill, "gauge_fill", "the filled part of a gauge (its foreground fills)"),
    role(Role::GaugeEmpty, "gauge_empty", "the unfilled part of a gauge"),
    role(Role::LampOn, "lamp_on", "a status lamp that is on (switch closed, target reached)"),
    role(Role::LampOff, "lamp_off", "a status lamp that is off"),
    role(Role::LampAlarm, "lamp_alarm", "a lamp that is on and means trouble (stall, overtemperature)"),
    role(Role::CodeMnemonic, "code_mnemonic", "program editor: instruction mnemonics"),
    role(Role::CodeLabel, "code_label", "program editor: labels"),
    role(Role::CodeNumber, "code_number", "program editor: numbers and constants"),
    role(Role::CodeComment, "code_comment", "program editor: comments"),
    role(Role::CodeGutter, "code_gutter", "program editor: line numbers and addresses"),
    role(Role::CodeCurrent, "code_current", "program editor: the line the program counter is on"),
    role(Role::CodeError, "code_error", "program editor: a line that does not assemble"),
    role(Role::PlotAxes, "plot_axes", "plot axes and their labels"),
    role(Role::Plot1, "plot_1", "first plotted signal"),
    role(Role::Plot2, "plot_2", "second plotted signal"),
    role(Role::Plot3, "plot_3", "third plotted signal"),
    role(Role::Plot4, "plot_4", "fourth plotted signal"),
];

const ROLE_COUNT: usize = ROLES.len();

impl Role {
    /// Its name in theme files.
    pub fn name(self) -> &'static str {
        ROLES
            .iter()
            .find(|info| info.role == self)
            .map_or("?", |info| info.name)
    }

    /// The role a theme file names, if any.
    pub fn from_name(name: &str) -> Option<Role> {
        ROLES
            .iter()
            .find(|info| info.name == name)
            .map(|info| info.role)
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// The theme used when none is asked for.
pub const DEFAULT_THEME: &str = "dark";
/// The theme `NO_COLOR` selects.
pub const NO_COLOR_THEME: &str = "mono";

/// The built-in themes, compiled in: name and TOML text.
pub const BUILTIN_THEMES: &[(&str, &str)] = &[
    ("dark", include_str!("../../themes/dark.toml")),
    ("light", include_str!("../../themes/light.toml")),
    (
        "high-contrast",
        include_str!("../../themes/high-contrast.toml"),
    ),
    ("mono", include_str!("../../themes/mono.toml")),
];

/// A style for every [`Role`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Theme {
    name: String,
    description: String,
    styles: [Style; ROLE_COUNT],
}

impl Theme {
    pub fn name(&self) -> &str {
        &self.name
    }

    /// One line on what the theme is for, from its file.
    pub fn description(&self) -> &str {
        &self.description
    }

    /// The style of `role`. Styles other than `normal` give only what
    /// differs from ordinary text: draw the screen in `normal` first and
    /// patch the others over it.
    pub fn style(&self, role: Role) -> Style {
        self.styles.get(role.index()).copied().unwrap_or_default()
    }

    /// The background of ordinary text (`Color::Reset`: the terminal's).
    pub fn background(&self) -> Color {
        self.style(Role::Normal).bg.unwrap_or(Color::Reset)
    }

    /// The colour of ordinary text (`Color::Reset`: the terminal's).
    pub fn foreground(&self) -> Color {
        self.style(Role::Normal).fg.unwrap_or(Color::Reset)
    }

    /// Whether the theme sets no colour at all, only modifiers.
    pub fn is_monochrome(&self) -> bool {
        let plain = |c: Option<Color>| matches!(c, None | Some(Color::Reset));
        self.styles.iter().all(|s| plain(s.fg) && plain(s.bg))
    }

    /// The built-in theme `name`.
    pub fn builtin(name: &str) -> Option<Theme> {
        let (name, text) = BUILTIN_THEMES.iter().find(|(n, _)| *n == name)?;
        let draft = read_theme(text).ok()?;
        draft.complete(name).ok()
    }

    /// The names of the built-in themes.
    pub fn builtin_names() -> impl Iterator<Item = &'static str> {
        BUILTIN_THEMES.iter().map(|(name, _)| *name)
    }

    /// The default built-in; if that were ever broken (the tests see that
    /// it is not), the terminal's own colours.
    fn fallback() -> Theme {
        Theme::builtin(DEFAULT_THEME).unwrap_or_else(|| Theme {
            name: DEFAULT_THEME.to_string(),
            description: String::new(),
            styles: [Style::new(); ROLE_COUNT],
        })
    }
}

/// Whether a `NO_COLOR` value asks for no colour: present and not empty
/// (no-color.org).
pub fn no_color_requested(value: Option<&OsStr>) -> bool {
    value.is_some_and(|v| !v.is_empty())
}

/// Whether this process's environment has `NO_COLOR` set and not empty.
pub fn no_color_in_env() -> bool {
    no_color_requested(std::env::var_os("NO_COLOR").as_deref())
}

/// The theme the console starts with: `flag` (the `--theme` value) when
/// given, else `mono` when `no_color`, else `dark`; looked up in
/// `config_dir` first, then among the built-ins. Never fails: a problem
/// comes back beside the fallback theme.
pub fn choose_theme(
    flag: Option<&str>,
    no_color: bool,
    config_dir: Option<&Path>,
) -> Loaded<Theme> {
    let name = match flag {
        Some(name) => name,
        None if no_color => NO_COLOR_THEME,
        None => DEFAULT_THEME,
    };
    load_theme(name, config_dir)
}

/// The theme `name`: the user's `themes/NAME.toml` in `config_dir` over
/// the built-in of that name. A user file that cannot be used gives a
/// [`ConfigProblem`] and the built-in of that name (else `dark`).
pub fn load_theme(name: &str, config_dir: Option<&Path>) -> Loaded<Theme> {
    load_config(&THEMES, name, config_dir)
}

/// Themes as the configuration loader knows them.
const THEMES: ConfigKind<Theme> = ConfigKind {
    folder: "themes",
    noun: "theme",
    default_name: DEFAULT_THEME,
    builtin: Theme::builtin,
    builtin_names: || Theme::builtin_names().collect(),
    last_resort: Theme::fallback,
    parse: parse_theme,
};

/// Parses a user's theme file named `name`: roles it leaves out come from
/// its `base` (a built-in), by default the built-in of the same name, else
/// `dark`. Every mistake found is returned, in file order.
pub fn parse_theme(name: &str, text: &str) -> Result<Theme, Vec<ConfigError>> {
    let draft = read_theme(text)?;
    let base_name = config::base_name(&THEMES, draft.base.as_ref(), name, text)?;
    let base = Theme::builtin(base_name).unwrap_or_else(Theme::fallback);
    let mut styles = base.styles;
    for (slot, style) in styles.iter_mut().zip(draft.styles) {
        if let Some(style) = style {
            *slot = style;
        }
    }
    Ok(Theme {
        name: name.to_string(),
        description: draft.description.unwrap_or(base.description),
        styles,
    })
}

/// A theme file as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ThemeFile {
    /// Informational: the file name is the theme's name.
    #[serde(default, rename = "name")]
    _name: Option<String>,
    #[serde(default)]
    description: Option<String>,
    #[serde(default)]
    base: Option<Spanned<String>>,
    #[serde(default)]
    styles: BTreeMap<Spanned<String>, Spanned<String>>,
}

/// A theme file read: the roles it gives, and its base.
struct ThemeDraft {
    description: Option<String>,
    base: Option<(String, std::ops::Range<usize>)>,
    styles: [Option<Style>; ROLE_COUNT],
}

impl ThemeDraft {
    /// The theme, if the file gives every role (built-ins must).
    fn complete(self, name: &str) -> Result<Theme, Vec<String>> {
        let missing: Vec<String> = ROLES
            .iter()
            .zip(&self.styles)
            .filter(|(_, style)| style.is_none())
            .map(|(info, _)| info.name.to_string())
            .collect();
        if !missing.is_empty() {
            return Err(missing);
        }
        Ok(Theme {
            name: name.to_string(),
            description: self.description.unwrap_or_default(),
            styles: self.styles.map(Option::unwrap_or_default),
        })
    }
}

fn read_theme(text: &str) -> Result<ThemeDraft, Vec<ConfigError>> {
    let file: ThemeFile =
        toml::from_str(text).map_err(|e| vec![ConfigError::from_toml(text, &e)])?;
    let mut errors = Vec::new();
    let mut styles = [None; ROLE_COUNT];
    for (role_name, spec) in &file.styles {
        let key = format!("styles.{}", role_name.get_ref());
        let Some(role) = Role::from_name(role_name.get_ref()) else {
            errors.push(ConfigError::at(
                text,
                role_name.span(),
                &key,
                format!(
                    "unknown role `{}` (roles: {})",
                    role_name.get_ref(),
                    ROLES.iter().map(|r| r.name).collect::<Vec<_>>().join(", ")
                ),
            ));
            continue;
        };
        match parse_style(spec.get_ref()) {
            Ok(style) => {
                if let Some(slot) = styles.get_mut(role.index()) {
                    *slot = Some(style);
                }
            }
            Err(message) => errors.push(ConfigError::at(text, spec.span(), &key, message)),
        }
    }
    if !errors.is_empty() {
        config::sort_errors(&mut errors);
        return Err(errors);
    }
    Ok(ThemeDraft {
        description: file.description,
        base: file.base.map(|b| {
            let span = b.span();
            (b.into_inner(), span)
        }),
        styles,
    })
}

/// The 16 ANSI colours and the terminal's own, by name. Names are matched
/// ignoring case, `_` and `-`, so `light_green`, `LightGreen` and
/// `light-green` are one colour.
const NAMED_COLORS: &[(&str, Color)] = &[
    ("black", Color::Black),
    ("red", Color::Red),
    ("green", Color::Green),
    ("yellow", Color::Yellow),
    ("blue", Color::Blue),
    ("magenta", Color::Magenta),
    ("cyan", Color::Cyan),
    ("gray", Color::Gray),
    ("grey", Color::Gray),
    ("darkgray", Color::DarkGray),
    ("darkgrey", Color::DarkGray),
    ("lightred", Color::LightRed),
    ("lightgreen", Color::LightGreen),
    ("lightyellow", Color::LightYellow),
    ("lightblue", Color::LightBlue),
    ("lightmagenta", Color::LightMagenta),
    ("lightcyan", Color::LightCyan),
    ("white", Color::White),
    ("default", Color::Reset),
    ("reset", Color::Reset),
];

const MODIFIERS: &[(&str, Modifier)] = &[
    ("bold", Modifier::BOLD),
    ("dim", Modifier::DIM),
    ("italic", Modifier::ITALIC),
    ("underlined", Modifier::UNDERLINED),
    ("underline", Modifier::UNDERLINED),
    ("reversed", Modifier::REVERSED),
    ("reverse", Modifier::REVERSED),
    ("crossed_out", Modifier::CROSSED_OUT),
];

const COLOUR_HELP: &str = "colours: black, red, green, yellow, blue, magenta, cyan, gray, dark_gray, \
     light_red, light_green, light_yellow, light_blue, light_magenta, light_cyan, white, \
     default, #rrggbb, indexed:N; modifiers: bold, dim, italic, underlined, reversed, crossed_out";

/// A colour: one of the 16 ANSI names (`light_cyan`), `default` (the
/// terminal's own), `#rrggbb`, or `indexed:N` (0–255).
pub fn parse_color(word: &str) -> Result<Color, String> {
    if let Some(hex) = word.strip_prefix('#') {
        let valid = hex.len() == 6 && hex.chars().all(|c| c.is_ascii_hexdigit());
        let channel = |at: usize| {
            hex.get(at..at + 2)
                .and_then(|h| u8::from_str_radix(h, 16).ok())
        };
        return match (valid, channel(0), channel(2), channel(4)) {
            (true, Some(r), Some(g), Some(b)) => Ok(Color::Rgb(r, g, b)),
            _ => Err(format!(
                "`{word}` is not a colour: write six hex digits after `#`, as in #1c1c1c"
            )),
        };
    }
    let lower = word.to_ascii_lowercase();
    if let Some(number) = lower.strip_prefix("indexed:") {
        return number.parse::<u8>().map(Color::Indexed).map_err(|_| {
            format!("`{word}` is not a colour: indexed colours are indexed:0 to indexed:255")
        });
    }
    let folded: String = lower.chars().filter(|c| !matches!(c, '_' | '-')).collect();
    NAMED_COLORS
        .iter()
        .find(|(name, _)| *name == folded)
        .map(|(_, color)| *color)
        .ok_or_else(|| format!("unknown colour `{word}` ({COLOUR_HELP})"))
}

/// A style text: an optional foreground colour, `on` and a background
/// colour, and modifiers, in any order: `"bold white on red"`,
/// `"on #3a3a3a"`, `"reversed"`, `""` (the terminal's defaults).
pub fn parse_style(spec: &str) -> Result<Style, String> {
    let mut style = Style::new();
    let mut words = spec.split_whitespace();
    while let Some(word) = words.next() {
        if word.eq_ignore_ascii_case("on") {
            let Some(colour) = words.next() else {
                return Err(format!(
                    "`{spec}`: `on` must be followed by a background colour"
                ));
            };
            if style.bg.is_some() {
                return Err(format!("`{spec}` gives two background colours"));
            }
            style = style.bg(parse_color(colour)?);
        } else if let Some((_, modifier)) = MODIFIERS
            .iter()
            .find(|(name, _)| name.eq_ignore_ascii_case(word))
        {
            style = style.add_modifier(*modifier);
        } else {
            let colour = parse_color(word)
                .map_err(|_| format!("unknown colour or modifier `{word}` ({COLOUR_HELP})"))?;
            if style.fg.is_some() {
                return Err(format!(
                    "`{spec}` gives two foreground colours (write `on` before a background colour)"
                ));
            }
            style = style.fg(colour);
        }
    }
    Ok(style)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_role_table_follows_the_enum_order() {
        for (index, info) in ROLES.iter().enumerate() {
            assert_eq!(info.role.index(), index, "{}", info.name);
            assert_eq!(Role::from_name(info.name), Some(info.role));
            assert_eq!(info.role.name(), info.name);
        }
    }

    #[test]
    fn colours_by_name_hex_and_index() {
        assert_eq!(parse_color("light_green"), Ok(Color::LightGreen));
        assert_eq!(parse_color("LightGreen"), Ok(Color::LightGreen));
        assert_eq!(parse_color("dark-grey"), Ok(Color::DarkGray));
        assert_eq!(parse_color("#1C1c00"), Ok(Color::Rgb(0x1c, 0x1c, 0)));
        assert_eq!(parse_color("indexed:236"), Ok(Color::Indexed(236)));
        assert_eq!(parse_color("default"), Ok(Color::Reset));
        for bad in [
            "#12345",
            "#1234567",
            "#gg0000",
            "#ééé",
            "indexed:256",
            "chartreuse",
            "",
        ] {
            assert!(parse_color(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn style_texts_give_colours_and_modifiers_in_any_order() {
        assert_eq!(
            parse_style("bold white on red"),
            Ok(Style::new()
                .fg(Color::White)
                .bg(Color::Red)
                .add_modifier(Modifier::BOLD))
        );
        assert_eq!(
            parse_style("on #3a3a3a"),
            Ok(Style::new().bg(Color::Rgb(0x3a, 0x3a, 0x3a)))
        );
        assert_eq!(
            parse_style("reversed underlined"),
            Ok(Style::new().add_modifier(Modifier::REVERSED | Modifier::UNDERLINED))
        );
        assert_eq!(parse_style(""), Ok(Style::new()));
    }

    #[test]
    fn style_texts_that_make_no_sense_are_refused() {
        for bad in [
            "red blue",
            "on",
            "white on red on blue",
            "blod",
            "red on chartreuse",
        ] {
            assert!(parse_style(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn no_color_counts_only_when_set_and_not_empty() {
        assert!(!no_color_requested(None));
        assert!(!no_color_requested(Some(OsStr::new(""))));
        assert!(no_color_requested(Some(OsStr::new("1"))));
        assert!(no_color_requested(Some(OsStr::new("0"))));
    }
}
