//! Recent connections, newest first, kept in a small TOML file in the data
//! directory so that the connect screen offers them next time.
//!
//! ```toml
//! [[connection]]
//! args = ["--port", "/dev/ttyUSB0", "--protocol", "tmcl", "--baud", "9600", "--address", "1"]
//! ```

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// Connections remembered at most.
pub const RECENT_LIMIT: usize = 8;

/// The file's name in the data directory.
pub const RECENT_FILE: &str = "recent-connections.toml";

#[derive(Debug, Default, Serialize, Deserialize)]
struct RecentFile {
    #[serde(default)]
    connection: Vec<Entry>,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
struct Entry {
    args: Vec<String>,
}

/// The recent connections and where they are kept.
#[derive(Debug, Clone, Default)]
pub struct Recents {
    file: Option<PathBuf>,
    entries: Vec<Vec<String>>,
    /// Why the file could not be read, if it could not.
    problem: Option<String>,
}

impl Recents {
    /// The list kept in `dir` (none kept when `None`). A missing file is
    /// an empty list; a broken one too, with the reason in
    /// [`Recents::problem`].
    pub fn load(dir: Option<&Path>) -> Recents {
        let file = dir.map(|d| d.join(RECENT_FILE));
        let mut recents = Recents {
            file: file.clone(),
            ..Recents::default()
        };
        let Some(file) = file else {
            return recents;
        };
        let text = match crate::files::read_text(&file) {
            Ok(text) => text,
            Err(e) if e.is_not_found() => return recents,
            Err(e) => {
                recents.problem = Some(format!("cannot read {}: {e}", file.display()));
                return recents;
            }
        };
        match toml::from_str::<RecentFile>(&text) {
            Ok(parsed) => {
                recents.entries = parsed
                    .connection
                    .into_iter()
                    .map(|e| e.args)
                    .filter(|args| !args.is_empty())
                    .take(RECENT_LIMIT)
                    .collect();
            }
            Err(e) => {
                recents.problem = Some(format!(
                    "{} is broken ({}); it will be rewritten",
                    file.display(),
                    e.message()
                ));
            }
        }
        recents
    }

    /// The connections, newest first.
    pub fn entries(&self) -> &[Vec<String>] {
        &self.entries
    }

    pub fn problem(&self) -> Option<&str> {
        self.problem.as_deref()
    }

    /// Put `args` first (once), keep the newest [`RECENT_LIMIT`], and
    /// write the file.
    pub fn remember(&mut self, args: Vec<String>) -> Result<(), String> {
        if args.is_empty() {
            return Ok(());
        }
        self.entries.retain(|a| *a != args);
        self.entries.insert(0, args);
        self.entries.truncate(RECENT_LIMIT);
        let Some(file) = &self.file else {
            return Ok(());
        };
        let contents = RecentFile {
            connection: self
                .entries
                .iter()
                .map(|args| Entry { args: args.clone() })
                .collect(),
        };
        let text = toml::to_string(&contents)
            .map_err(|e| format!("cannot write the recent connections: {e}"))?;
        if let Some(dir) = file.parent() {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        }
        crate::files::write_atomically(
            file,
            format!("# axterm: recent connections, newest first\n{text}").as_bytes(),
        )
        .map_err(|e| format!("cannot write {}: {e}", file.display()))?;
        self.problem = None;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(text: &str) -> Vec<String> {
        text.split_whitespace().map(str::to_string).collect()
    }

    #[test]
    fn remembered_connections_come_back_newest_first_bounded_and_once() {
        let dir = tempfile::tempdir().expect("temp dir");
        let data = dir.path().join("data");
        let mut recents = Recents::load(Some(&data));
        assert!(recents.entries().is_empty());
        for n in 0..RECENT_LIMIT + 3 {
            recents
                .remember(args(&format!("--port /dev/ttyUSB{n}")))
                .expect("write");
        }
        recents
            .remember(args("--port /dev/ttyUSB5"))
            .expect("write");
        let again = Recents::load(Some(&data));
        assert_eq!(again.entries().len(), RECENT_LIMIT);
        assert_eq!(again.entries()[0], args("--port /dev/ttyUSB5"));
        assert_eq!(
            again.entries()[1],
            args(&format!("--port /dev/ttyUSB{}", RECENT_LIMIT + 2))
        );
        assert_eq!(
            again
                .entries()
                .iter()
                .filter(|a| **a == args("--port /dev/ttyUSB5"))
                .count(),
            1
        );
        assert!(again.problem().is_none());
    }

    #[test]
    fn a_broken_file_is_an_empty_list_with_a_reason() {
        let dir = tempfile::tempdir().expect("temp dir");
        std::fs::write(dir.path().join(RECENT_FILE), "[[connection]\nargs = 3").expect("write");
        let mut recents = Recents::load(Some(dir.path()));
        assert!(recents.entries().is_empty());
        assert!(recents.problem().is_some_and(|p| p.contains("broken")));
        recents.remember(args("--sim tmcm1110")).expect("rewritten");
        assert_eq!(Recents::load(Some(dir.path())).entries().len(), 1);
    }

    #[test]
    fn without_a_directory_nothing_is_written() {
        let mut recents = Recents::load(None);
        recents
            .remember(args("--sim tmcm1110"))
            .expect("kept in memory");
        assert_eq!(recents.entries().len(), 1);
    }
}
