//! The lines typed before, per protocol family, kept in the data
//! directory (`history-FAMILY.txt`) and recalled with Up/Down.

use std::fs::{self, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

/// History entries kept per family.
const HISTORY_LIMIT: usize = 1000;

/// Past lines of one family, newest last.
#[derive(Debug, Default)]
pub(super) struct History {
    entries: Vec<String>,
    /// Position while browsing with Up/Down.
    browsing: Option<usize>,
    /// What was typed before browsing began.
    draft: String,
    file: Option<PathBuf>,
}

impl History {
    /// Load `family`'s history from `dir` (missing or unreadable: empty).
    pub(super) fn load(dir: Option<&Path>, family: &str) -> History {
        let file = dir.map(|d| d.join(format!("history-{family}.txt")));
        let mut entries: Vec<String> = file
            .as_ref()
            .and_then(|f| crate::files::read_text(f).ok())
            .map(|text| {
                text.lines()
                    .filter(|l| !l.trim().is_empty())
                    .map(str::to_string)
                    .collect()
            })
            .unwrap_or_default();
        if entries.len() > HISTORY_LIMIT {
            entries.drain(..entries.len() - HISTORY_LIMIT);
            // Keep the file from growing without end.
            if let Some(f) = &file {
                let _ = crate::files::write_atomically(f, (entries.join("\n") + "\n").as_bytes());
            }
        }
        History {
            entries,
            file,
            ..History::default()
        }
    }

    /// Remember a line, in memory and on disk.
    pub(super) fn push(&mut self, line: &str) -> Result<(), String> {
        self.browsing = None;
        if line.trim().is_empty() || self.entries.last().is_some_and(|l| l == line) {
            return Ok(());
        }
        self.entries.push(line.to_string());
        let Some(file) = &self.file else {
            return Ok(());
        };
        let written = file
            .parent()
            .map_or(Ok(()), fs::create_dir_all)
            .and_then(|()| OpenOptions::new().create(true).append(true).open(file))
            .and_then(|mut f| writeln!(f, "{line}"));
        written.map_err(|e| format!("history not saved to {}: {e}", file.display()))
    }

    pub(super) fn older(&mut self, current: &str) -> Option<&str> {
        let at = match self.browsing {
            None => {
                self.draft = current.to_string();
                self.entries.len().checked_sub(1)?
            }
            Some(at) => at.checked_sub(1)?,
        };
        self.browsing = Some(at);
        self.entries.get(at).map(String::as_str)
    }

    pub(super) fn newer(&mut self) -> Option<String> {
        let at = self.browsing? + 1;
        if at >= self.entries.len() {
            self.browsing = None;
            return Some(std::mem::take(&mut self.draft));
        }
        self.browsing = Some(at);
        self.entries.get(at).cloned()
    }
}
