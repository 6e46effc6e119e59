//! What theme and keymap files share: where a user's own files live, how
//! they are read, and how a mistake in one is reported (file, line,
//! column, key) so the console can show it and carry on with a built-in.

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The platform configuration directory of axterm (`~/.config/axterm` on
/// Linux, `~/Library/Application Support/axterm` on macOS,
/// `%APPDATA%\axterm\config` on Windows), or `None` when the platform
/// names no home directory. User themes live in its `themes/`, user
/// keymaps in its `keymaps/`.
pub fn platform_config_dir() -> Option<PathBuf> {
    directories::ProjectDirs::from("", "", "axterm").map(|dirs| dirs.config_dir().to_path_buf())
}

/// A theme or keymap as loaded, with the problem met on the way, if any
/// (the value is then the built-in fallback the problem names).
#[derive(Debug, Clone)]
pub struct Loaded<T> {
    pub value: T,
    pub problem: Option<ConfigProblem>,
}

/// What kind of problem a [`ConfigProblem`] is, so a front end can treat a
/// misspelt `--theme` name as bad usage if it wants to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProblemKind {
    /// No built-in and no user file has the asked-for name.
    NotFound,
    /// The user file exists but could not be read (permissions, not UTF-8).
    Unreadable,
    /// The user file was read but is wrong: TOML syntax, an unknown key,
    /// colour, key name or action, a conflict, a missing emergency stop.
    Invalid,
}

/// One mistake in a file, and where it is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ConfigError {
    /// 1-based line, when the mistake has a place in the file.
    pub line: Option<usize>,
    /// 1-based column (in characters) on that line.
    pub column: Option<usize>,
    /// The TOML key concerned, with its section: `styles.accent`,
    /// `global.quit`.
    pub key: Option<String>,
    pub message: String,
}

impl ConfigError {
    /// A mistake with no place in a file.
    pub(crate) fn general(message: impl Into<String>) -> Self {
        ConfigError {
            line: None,
            column: None,
            key: None,
            message: message.into(),
        }
    }

    /// A mistake at byte offset `span.start` of `text`, about `key`.
    pub(crate) fn at(
        text: &str,
        span: Range<usize>,
        key: &str,
        message: impl Into<String>,
    ) -> Self {
        let (line, column) = line_column(text, span.start);
        ConfigError {
            line: Some(line),
            column: Some(column),
            key: Some(key.to_string()),
            message: message.into(),
        }
    }

    /// A TOML syntax or shape error from the `toml` crate, placed by its
    /// span; the key is read from the line it points at, since the crate
    /// does not expose the key path of its errors.
    pub(crate) fn from_toml(text: &str, error: &toml::de::Error) -> Self {
        // serde speaks of fields; a technician edits keys and sections.
        let message = error
            .message()
            .trim()
            .replace("unknown field", "unknown section or key");
        match error.span() {
            Some(span) => {
                let (line, column) = line_column(text, span.start);
                ConfigError {
                    line: Some(line),
                    column: Some(column),
                    key: key_on_line(text, line),
                    message,
                }
            }
            None => ConfigError::general(message),
        }
    }
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.line, self.column) {
            (Some(line), Some(column)) => write!(f, "{line}:{column}: ")?,
            (Some(line), None) => write!(f, "{line}: ")?,
            _ => {}
        }
        if let Some(key) = &self.key {
            write!(f, "{key}: ")?;
        }
        f.write_str(&self.message)
    }
}

/// A user's theme or keymap file that could not be used, every mistake
/// found in it, and what the console uses instead.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ConfigProblem {
    pub kind: ProblemKind,
    /// The file concerned (for [`ProblemKind::NotFound`], where it was
    /// looked for).
    pub file: PathBuf,
    /// At least one; in file order.
    pub errors: Vec<ConfigError>,
    /// What is used instead, e.g. "the built-in theme `dark`".
    pub fallback: String,
}

impl fmt::Display for ConfigProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let file = self.file.display();
        for error in &self.errors {
            match (error.line, error.column) {
                (Some(line), Some(column)) => write!(f, "{file}:{line}:{column}: ")?,
                (Some(line), None) => write!(f, "{file}:{line}: ")?,
                _ => write!(f, "{file}: ")?,
            }
            if let Some(key) = &error.key {
                write!(f, "{key}: ")?;
            }
            writeln!(f, "{}", error.message)?;
        }
        write!(f, "using {} instead", self.fallback)
    }
}

impl std::error::Error for ConfigProblem {}

/// 1-based line and column (in characters) of byte `offset` in `text`;
/// an offset past the end or inside a character counts up to it.
pub(crate) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut line = 1;
    let mut column = 1;
    for (at, c) in text.char_indices() {
        if at >= offset {
            break;
        }
        if c == '\n' {
            line += 1;
            column = 1;
        } else {
            column += 1;
        }
    }
    (line, column)
}

/// The key a line of `text` is about: the one a `key = value` line sets,
/// with the section of the nearest `[header]` above it (`styles.accent`),
/// or the section a `[header]` line opens. `None` for lines that name no
/// key (a comment, a stray word).
fn key_on_line(text: &str, line: usize) -> Option<String> {
    let plain = |s: &str| {
        !s.is_empty()
            && s.chars()
                .all(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.'))
    };
    fn header(line: &str) -> Option<&str> {
        let inner = line.trim().strip_prefix('[')?.split(']').next()?.trim();
        let plain = !inner.is_empty()
            && inner
                .chars()
                .all(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.'));
        plain.then_some(inner)
    }
    let lines: Vec<&str> = text.lines().collect();
    let index = line.checked_sub(1)?;
    let here = lines.get(index)?.trim();
    if let Some(section) = header(here) {
        return Some(section.to_string());
    }
    let (key, _) = here.split_once('=')?;
    let key = key.trim().trim_matches('"');
    if !plain(key) {
        return None;
    }
    let section = lines.iter().take(index).rev().find_map(|l| header(l));
    Some(match section {
        Some(section) => format!("{section}.{key}"),
        None => key.to_string(),
    })
}

/// Whether `name` can be a theme or keymap name: it becomes a file name
/// (`NAME.toml`), so no separators, no leading dot, nothing strange.
pub(crate) fn is_valid_name(name: &str) -> bool {
    !name.is_empty()
        && !name.starts_with('.')
        && name
            .chars()
            .all(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | '.'))
}

/// A user's file of a kind (`themes`, `keymaps`) and name, as found.
pub(crate) enum UserFile {
    Absent,
    Text { path: PathBuf, text: String },
    Unreadable { path: PathBuf, reason: String },
}

/// Where the user file `NAME.toml` of `kind` would be.
pub(crate) fn user_file_path(config_dir: &Path, kind: &str, name: &str) -> PathBuf {
    config_dir.join(kind).join(format!("{name}.toml"))
}

pub(crate) fn read_user_file(config_dir: Option<&Path>, kind: &str, name: &str) -> UserFile {
    let Some(dir) = config_dir else {
        return UserFile::Absent;
    };
    if !is_valid_name(name) {
        return UserFile::Absent;
    }
    let path = user_file_path(dir, kind, name);
    match crate::files::read_text(&path) {
        Ok(text) => UserFile::Text { path, text },
        Err(e) if e.is_not_found() => UserFile::Absent,
        Err(e) => UserFile::Unreadable {
            path,
            reason: format!("cannot be read: {e}"),
        },
    }
}

/// Errors in file order (line, then column; placeless ones last).
/// What the loader needs to know of one kind of configuration file
/// (themes, keymaps).
pub(crate) struct ConfigKind<T> {
    /// Folder under the config directory, and the file kind in messages.
    pub folder: &'static str,
    pub noun: &'static str,
    /// The built-in used when a name is neither built in nor a user file.
    pub default_name: &'static str,
    pub builtin: fn(&str) -> Option<T>,
    pub builtin_names: fn() -> Vec<&'static str>,
    /// The default built-in (what a name that is not built in falls back to).
    pub last_resort: fn() -> T,
    pub parse: fn(&str, &str) -> Result<T, Vec<ConfigError>>,
}

/// The file `name` of `kind`: the user's `FOLDER/NAME.toml` in
/// `config_dir` over the built-in of that name. A user file that cannot be
/// used gives a [`ConfigProblem`] and the built-in of that name (else the
/// default).
pub(crate) fn load_config<T: Clone>(
    kind: &ConfigKind<T>,
    name: &str,
    config_dir: Option<&Path>,
) -> Loaded<T> {
    let builtin = (kind.builtin)(name);
    let fallback_name = if builtin.is_some() {
        name
    } else {
        kind.default_name
    };
    let fallback = || builtin.clone().unwrap_or_else(kind.last_resort);
    let problem = |problem_kind, file, errors| ConfigProblem {
        kind: problem_kind,
        file,
        errors,
        fallback: format!("the built-in {} `{fallback_name}`", kind.noun),
    };
    let failed = |problem_kind, file, errors| Loaded {
        value: fallback(),
        problem: Some(problem(problem_kind, file, errors)),
    };
    match read_user_file(config_dir, kind.folder, name) {
        UserFile::Absent => match &builtin {
            Some(value) => Loaded {
                value: value.clone(),
                problem: None,
            },
            None => {
                let file = match config_dir {
                    Some(dir) => user_file_path(dir, kind.folder, name),
                    None => Path::new(kind.folder).join(format!("{name}.toml")),
                };
                let message = format!(
                    "no {} named `{name}`: not a built-in ({}) and no such file",
                    kind.noun,
                    (kind.builtin_names)().join(", ")
                );
                failed(
                    ProblemKind::NotFound,
                    file,
                    vec![ConfigError::general(message)],
                )
            }
        },
        UserFile::Unreadable { path, reason } => failed(
            ProblemKind::Unreadable,
            path,
            vec![ConfigError::general(reason)],
        ),
        UserFile::Text { path, text } => match (kind.parse)(name, &text) {
            Ok(value) => Loaded {
                value,
                problem: None,
            },
            Err(errors) => failed(ProblemKind::Invalid, path, errors),
        },
    }
}

/// Which built-in a user's file of `kind` builds on (themes and keymaps
/// layer alike): the `base` it names, which must be a built-in, else the
/// built-in of its own `name`, else the kind's default. `text` is the
/// file, for the place of a bad `base`.
pub(crate) fn base_name<'a, T>(
    kind: &ConfigKind<T>,
    base: Option<&'a (String, std::ops::Range<usize>)>,
    name: &'a str,
    text: &str,
) -> Result<&'a str, Vec<ConfigError>> {
    let names = (kind.builtin_names)();
    match base {
        Some((base, span)) => {
            if !names.contains(&base.as_str()) {
                return Err(vec![ConfigError::at(
                    text,
                    span.clone(),
                    "base",
                    format!(
                        "no built-in {} named `{base}` (built-ins: {})",
                        kind.noun,
                        names.join(", ")
                    ),
                )]);
            }
            Ok(base.as_str())
        }
        None if names.contains(&name) => Ok(name),
        None => Ok(kind.default_name),
    }
}

pub(crate) fn sort_errors(errors: &mut [ConfigError]) {
    errors.sort_by_key(|e| (e.line.is_none(), e.line, e.column));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_count_characters_from_one() {
        let text = "a = 1\nbé = \"x\"\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 6), (2, 1));
        // 'é' is two bytes; the '=' after it is the 4th character.
        assert_eq!(line_column(text, 10), (2, 4));
        assert_eq!(line_column(text, 1000), (3, 1));
    }

    #[test]
    fn the_key_of_a_line_carries_its_section() {
        let text = "name = \"x\"\n[styles]\n# note\naccent = \"red\n";
        assert_eq!(key_on_line(text, 1).as_deref(), Some("name"));
        assert_eq!(key_on_line(text, 4).as_deref(), Some("styles.accent"));
        assert_eq!(key_on_line(text, 2).as_deref(), Some("styles"));
        assert_eq!(key_on_line(text, 3), None);
        assert_eq!(key_on_line(text, 99), None);
    }

    #[test]
    fn names_are_plain_file_names() {
        assert!(is_valid_name("high-contrast"));
        assert!(is_valid_name("my_theme.v2"));
        assert!(!is_valid_name(""));
        assert!(!is_valid_name("../etc"));
        assert!(!is_valid_name("a/b"));
        assert!(!is_valid_name(".hidden"));
    }

    #[test]
    fn a_problem_lists_file_line_column_key_and_fallback() {
        let problem = ConfigProblem {
            kind: ProblemKind::Invalid,
            file: PathBuf::from("themes/mine.toml"),
            errors: vec![ConfigError {
                line: Some(4),
                column: Some(10),
                key: Some("styles.accent".into()),
                message: "unknown colour `chartreuse`".into(),
            }],
            fallback: "the built-in theme `dark`".into(),
        };
        assert_eq!(
            problem.to_string(),
            "themes/mine.toml:4:10: styles.accent: unknown colour `chartreuse`\n\
             using the built-in theme `dark` instead"
        );
    }
}
