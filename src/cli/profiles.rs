//! Named connections: `axterm @line3` opens the links saved under `line3`
//! in a profile file, as tio's `tio <name>` does. An argument `@NAME` is
//! replaced by the equivalent connection options before the command line
//! is parsed, so it goes wherever those options go (`axterm exec @line3
//! 'GAP 4, 0'`, `axterm run @line3 file.txt`).
//!
//! The file is TOML in the platform config directory (`profiles.toml`
//! beside the user's themes/ and keymaps/), or the one `--profiles FILE`
//! or `AXTERM_PROFILES=FILE` names:
//!
//! ```toml
//! [bench]
//! sim = "tmcm1110"
//!
//! [line3]
//! port = "usb-FTDI_FT232R_USB_UART_A50285BI-if00-port0"
//! protocol = "tmcl"
//! baud = 57600
//! address = 3
//!
//! [cell2]                       # several links: one table each, in order
//! links = [
//!   { port = "/dev/ttyUSB0", protocol = "cmd4cr", baud = 9600 },
//!   { tcp = "10.0.0.7:4001", protocol = "mccl" },
//! ]
//! ```
//!
//! Several links become the options repeated in order (`--port A
//! --protocol cmd4cr … --tcp B --protocol mccl`); the command line takes
//! them where it takes several links.
//!
//! Expansion and the file's reading are pure; [`expand_command_line`]
//! is given the file's text by the caller.

use std::ffi::OsString;
use std::path::PathBuf;

/// The environment variable naming the profile file.
pub const PROFILES_ENV: &str = "AXTERM_PROFILES";
/// The option naming the profile file.
pub const PROFILES_OPTION: &str = "--profiles";
/// The file's name in the config directory.
pub const PROFILES_FILE: &str = "profiles.toml";

/// The keys a link of a profile may have, each the connection option of
/// that name.
const LINK_KEYS: &[&str] = &[
    "sim", "port", "tcp", "protocol", "baud", "address", "timeout",
];
/// The keys that say where a link is; a link has exactly one.
const WHERE_KEYS: &[&str] = &["sim", "port", "tcp"];

/// One saved link: the connection options it stands for, in order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SavedLink {
    /// (`sim`, `tmcm1110`), (`baud`, `9600`)…, the place first.
    pub options: Vec<(String, String)>,
}

/// A named connection: one link or several.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Profile {
    pub name: String,
    pub links: Vec<SavedLink>,
}

impl Profile {
    /// The command-line options it stands for.
    pub fn arguments(&self) -> Vec<String> {
        self.links
            .iter()
            .flat_map(|link| {
                link.options
                    .iter()
                    .flat_map(|(key, value)| [format!("--{key}"), value.clone()])
            })
            .collect()
    }
}

/// The profiles of a file, by name.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ProfileBook {
    pub profiles: Vec<Profile>,
}

impl ProfileBook {
    /// Read a profile file's text; an error names the profile and key
    /// that is wrong.
    pub fn parse(text: &str) -> Result<ProfileBook, String> {
        let table: toml::Table = toml::from_str(text)
            .map_err(|e| format!("not a TOML profile file: {}", e.message()))?;
        let mut profiles = Vec::new();
        for (name, value) in &table {
            let toml::Value::Table(entry) = value else {
                return Err(format!(
                    "profile `{name}`: give a table ([{name}] with sim, port or tcp…)"
                ));
            };
            let links = match entry.get("links") {
                Some(toml::Value::Array(links)) => {
                    if let Some(other) = entry.keys().find(|k| *k != "links") {
                        return Err(format!(
                            "profile `{name}`: `{other}` beside `links`: put it in each link"
                        ));
                    }
                    if links.is_empty() {
                        return Err(format!("profile `{name}`: `links` is empty"));
                    }
                    links
                        .iter()
                        .enumerate()
                        .map(|(i, link)| match link {
                            toml::Value::Table(link) => {
                                saved_link(&format!("profile `{name}` link {}", i + 1), link)
                            }
                            _ => Err(format!(
                                "profile `{name}` link {}: give a table {{ port = … }}",
                                i + 1
                            )),
                        })
                        .collect::<Result<Vec<_>, _>>()?
                }
                Some(_) => {
                    return Err(format!(
                        "profile `{name}`: `links` is a list of tables [{{ sim = … }}, …]"
                    ));
                }
                None => vec![saved_link(&format!("profile `{name}`"), entry)?],
            };
            profiles.push(Profile {
                name: name.clone(),
                links,
            });
        }
        Ok(ProfileBook { profiles })
    }

    pub fn find(&self, name: &str) -> Option<&Profile> {
        self.profiles.iter().find(|p| p.name == name)
    }

    /// The names, for messages.
    pub fn names(&self) -> String {
        if self.profiles.is_empty() {
            return "none".into();
        }
        let names: Vec<&str> = self.profiles.iter().map(|p| p.name.as_str()).collect();
        names.join(", ")
    }
}

/// One link's table, its keys in the order of [`LINK_KEYS`].
fn saved_link(what: &str, table: &toml::Table) -> Result<SavedLink, String> {
    if let Some(unknown) = table.keys().find(|k| !LINK_KEYS.contains(&k.as_str())) {
        return Err(format!(
            "{what}: unknown key `{unknown}` (known: {}, or links = [...])",
            LINK_KEYS.join(", ")
        ));
    }
    let places: Vec<&str> = WHERE_KEYS
        .iter()
        .copied()
        .filter(|k| table.contains_key(*k))
        .collect();
    if places.len() != 1 {
        return Err(format!(
            "{what}: give exactly one of sim, port and tcp (it has {})",
            if places.is_empty() {
                "none".to_string()
            } else {
                places.join(" and ")
            }
        ));
    }
    let mut options = Vec::new();
    for key in LINK_KEYS {
        let Some(value) = table.get(*key) else {
            continue;
        };
        let text = match value {
            toml::Value::String(text) if !text.trim().is_empty() => text.trim().to_string(),
            toml::Value::Integer(n) if *n >= 0 => n.to_string(),
            _ => {
                return Err(format!(
                    "{what}: `{key}` is {}: give {}",
                    value.type_str(),
                    match *key {
                        "baud" | "timeout" => "a whole number",
                        "address" => "a number or a list such as \"1-4\"",
                        _ => "a non-empty string",
                    }
                ));
            }
        };
        if matches!(*key, "baud" | "timeout") && !matches!(value, toml::Value::Integer(_)) {
            return Err(format!("{what}: `{key}` is a string: give a whole number"));
        }
        options.push(((*key).to_string(), text));
    }
    Ok(SavedLink { options })
}

/// Whether an argument is a profile reference `@NAME` (letters, digits,
/// `-`, `_`, `.`).
fn reference(argument: &OsString) -> Option<&str> {
    let name = argument.to_str()?.strip_prefix('@')?;
    let valid = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
    valid.then_some(name)
}

/// The profile file the command line or the environment names
/// (`--profiles FILE`, `--profiles=FILE`, else `env`), if any.
pub fn named_file(args: &[OsString], env: Option<OsString>) -> Option<PathBuf> {
    let mut given = None;
    let mut words = args.iter();
    while let Some(word) = words.next() {
        if word == "--" {
            break;
        }
        if word == PROFILES_OPTION {
            given = words.next().map(PathBuf::from);
        } else if let Some(path) = word
            .to_str()
            .and_then(|w| w.strip_prefix(PROFILES_OPTION)?.strip_prefix('='))
        {
            given = Some(PathBuf::from(path));
        }
    }
    given.or_else(|| env.filter(|e| !e.is_empty()).map(PathBuf::from))
}

/// Whether the command line has a profile reference to expand.
pub fn has_references(args: &[OsString]) -> bool {
    args.iter()
        .skip(1)
        .take_while(|a| *a != "--")
        .any(|a| reference(a).is_some())
}

/// The command line with every `@NAME` (before a `--`, after the program
/// name) replaced by its profile's options; `book` is the profile file
/// read (`name` for messages), or why it could not be.
pub fn expand_command_line(
    args: Vec<OsString>,
    book: Result<&ProfileBook, String>,
    file_name: &str,
) -> Result<Vec<OsString>, String> {
    if !has_references(&args) {
        return Ok(args);
    }
    let book = book?;
    let mut out = Vec::with_capacity(args.len());
    let mut literal = false;
    for (index, argument) in args.into_iter().enumerate() {
        if argument == "--" {
            literal = true;
        }
        match reference(&argument).filter(|_| index > 0 && !literal) {
            Some(name) => {
                let profile = book.find(name).ok_or_else(|| {
                    format!(
                        "no profile `{name}` in {file_name} (profiles there: {})",
                        book.names()
                    )
                })?;
                out.extend(profile.arguments().into_iter().map(OsString::from));
            }
            None => out.push(argument),
        }
    }
    Ok(out)
}

/// Where the profile file is: as `args` or the environment name it, else
/// `profiles.toml` in `config_dir`.
pub fn locate(
    args: &[OsString],
    env: Option<OsString>,
    config_dir: Option<PathBuf>,
) -> Option<PathBuf> {
    named_file(args, env).or_else(|| config_dir.map(|dir| dir.join(PROFILES_FILE)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const FILE: &str = r#"
[bench]
sim = "tmcm1110"

[line3]
port = "usb-FTDI_FT232R_USB_UART_A50285BI-if00-port0"
protocol = "tmcl"
baud = 57600
address = 3

[cell2]
links = [
  { port = "/dev/ttyUSB0", protocol = "cmd4cr", baud = 9600, address = "1-4" },
  { tcp = "10.0.0.7:4001", protocol = "mccl", timeout = 500 },
]
"#;

    fn os(words: &[&str]) -> Vec<OsString> {
        words.iter().map(OsString::from).collect()
    }

    fn expand(words: &[&str]) -> Result<Vec<OsString>, String> {
        let book = ProfileBook::parse(FILE).expect("parses");
        expand_command_line(os(words), Ok(&book), "profiles.toml")
    }

    #[test]
    fn a_profile_becomes_its_connection_options_where_it_stands() {
        assert_eq!(
            expand(&["axterm", "@line3"]),
            Ok(os(&[
                "axterm",
                "--port",
                "usb-FTDI_FT232R_USB_UART_A50285BI-if00-port0",
                "--protocol",
                "tmcl",
                "--baud",
                "57600",
                "--address",
                "3",
            ]))
        );
        // With a subcommand, before or after it.
        assert_eq!(
            expand(&["axterm", "exec", "@bench", "GAP 4, 0"]),
            Ok(os(&["axterm", "exec", "--sim", "tmcm1110", "GAP 4, 0"]))
        );
    }

    #[test]
    fn several_links_become_the_options_repeated_in_order() {
        assert_eq!(
            expand(&["axterm", "@cell2"]),
            Ok(os(&[
                "axterm",
                "--port",
                "/dev/ttyUSB0",
                "--protocol",
                "cmd4cr",
                "--baud",
                "9600",
                "--address",
                "1-4",
                "--tcp",
                "10.0.0.7:4001",
                "--protocol",
                "mccl",
                "--timeout",
                "500",
            ]))
        );
    }

    #[test]
    fn an_unknown_name_lists_the_names_there_are() {
        assert_eq!(
            expand(&["axterm", "@line4"]),
            Err("no profile `line4` in profiles.toml (profiles there: bench, cell2, line3)".into())
        );
    }

    #[test]
    fn nothing_is_read_or_changed_without_a_reference() {
        let words = os(&[
            "axterm", "exec", "--sim", "cmd4cr", "me@host", "@", "--", "@bench",
        ]);
        // The file is not even needed.
        assert_eq!(
            expand_command_line(words.clone(), Err("unreadable".into()), "f"),
            Ok(words)
        );
        // After `--` a reference is an argument like any other.
        assert_eq!(
            expand(&["axterm", "run", "@bench", "--", "@bench"]),
            Ok(os(&["axterm", "run", "--sim", "tmcm1110", "--", "@bench"]))
        );
        // A reference with no file to look in says why.
        assert_eq!(
            expand_command_line(os(&["axterm", "@bench"]), Err("no such file".into()), "f"),
            Err("no such file".into())
        );
    }

    #[test]
    fn bad_files_say_which_profile_and_key() {
        for (text, needle) in [
            (
                "[a]\nsim = \"x\"\nport = \"y\"\n",
                "profile `a`: give exactly one of sim, port and tcp (it has sim and port)",
            ),
            ("[a]\nprotocol = \"tmcl\"\n", "(it has none)"),
            (
                "[a]\nsim = \"x\"\nprot = 1\n",
                "profile `a`: unknown key `prot`",
            ),
            (
                "[a]\nsim = \"x\"\nbaud = \"fast\"\n",
                "`baud` is a string: give a whole number",
            ),
            (
                "[a]\nsim = \"x\"\nbaud = -1\n",
                "`baud` is integer: give a whole number",
            ),
            ("[a]\nlinks = []\n", "`links` is empty"),
            ("[a]\nlinks = [1]\n", "profile `a` link 1: give a table"),
            (
                "[a]\nbaud = 5\nlinks = [{ sim = \"x\" }]\n",
                "`baud` beside `links`",
            ),
            ("a = 1\n", "profile `a`: give a table"),
            ("[a\n", "not a TOML profile file"),
        ] {
            let error = ProfileBook::parse(text).expect_err(text);
            assert!(error.contains(needle), "{text}: {error}");
        }
    }

    #[test]
    fn the_file_is_named_by_the_option_before_the_environment() {
        let env = Some(OsString::from("/etc/env.toml"));
        assert_eq!(
            named_file(&os(&["axterm", "@a"]), env.clone()),
            Some("/etc/env.toml".into())
        );
        assert_eq!(
            named_file(&os(&["axterm", "--profiles", "p.toml", "@a"]), env.clone()),
            Some("p.toml".into())
        );
        assert_eq!(
            named_file(&os(&["axterm", "--profiles=q.toml", "@a"]), env),
            Some("q.toml".into())
        );
        assert_eq!(
            named_file(&os(&["axterm", "@a"]), Some(OsString::new())),
            None
        );
    }

    proptest! {
        #[test]
        fn parsing_never_panics(text in "\\PC{0,200}") {
            let _ = ProfileBook::parse(&text);
        }

        #[test]
        fn expansion_keeps_every_other_argument_in_place(
            words in proptest::collection::vec("[a-z@ -]{0,8}", 0..8),
        ) {
            let mut args = vec!["axterm".to_string()];
            args.extend(words.iter().filter(|w| reference(&OsString::from(w.as_str())).is_none()).cloned());
            let args: Vec<OsString> = args.into_iter().map(OsString::from).collect();
            let book = ProfileBook::parse(FILE).expect("parses");
            prop_assert_eq!(expand_command_line(args.clone(), Ok(&book), "f"), Ok(args));
        }
    }
}
