//! The editor's safety copy: the text being edited, with its file and the
//! language it is written in, written to the data directory shortly after
//! each change, so that a crash, a dropped SSH session or a killed process
//! loses nothing, and the text comes back in its own language. Written
//! atomically (a temporary file beside it, then a rename), so the copy on
//! disk is always a whole one: the old or the new, never half of each.

use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use serde::{Deserialize, Serialize};

use crate::wall_clock::CivilTime;

/// The safety copy's file name in the data directory.
pub const AUTOSAVE_FILE: &str = "editor-autosave.json";

/// What the safety copy holds.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Autosave {
    /// The file the text belongs to, if it had a name.
    pub file: Option<PathBuf>,
    /// When it was written, in seconds since 1970 (UTC).
    pub written: u64,
    pub text: String,
    /// The program tool's name the text is written for ("TMCL"); copies
    /// written before languages were kept have none.
    #[serde(default)]
    pub language: Option<String>,
}

impl Autosave {
    pub fn now(file: Option<PathBuf>, text: String) -> Autosave {
        let written = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        Autosave {
            file,
            written,
            text,
            language: None,
        }
    }

    /// The same copy, of text written in `language`.
    pub fn in_language(mut self, language: &str) -> Autosave {
        self.language = Some(language.to_string());
        self
    }

    /// The file's name for the recovery message ("untitled" if none).
    pub fn file_label(&self) -> String {
        self.file
            .as_ref()
            .map_or_else(|| "untitled".to_string(), |f| f.display().to_string())
    }
}

/// Where the safety copy lives in `data_dir`.
pub fn autosave_path(data_dir: &Path) -> PathBuf {
    data_dir.join(AUTOSAVE_FILE)
}

/// Write `copy` to `data_dir` atomically.
pub fn write_autosave(data_dir: &Path, copy: &Autosave) -> Result<(), String> {
    let json = serde_json::to_string(copy)
        .map_err(|e| format!("cannot keep a safety copy of the text: {e}"))?;
    std::fs::create_dir_all(data_dir)
        .map_err(|e| format!("cannot create {}: {e}", data_dir.display()))?;
    let path = autosave_path(data_dir);
    crate::files::write_atomically(&path, json.as_bytes())
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The safety copy in `data_dir`, if there is a readable one.
pub fn read_autosave(data_dir: &Path) -> Option<Autosave> {
    let text = crate::files::read_text(autosave_path(data_dir)).ok()?;
    serde_json::from_str(&text).ok()
}

/// Forget the safety copy (the text was saved, or discarded).
pub fn remove_autosave(data_dir: &Path) -> Result<(), String> {
    let path = autosave_path(data_dir);
    match std::fs::remove_file(&path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(format!("cannot remove {}: {e}", path.display())),
    }
}

/// Seconds since 1970 as `YYYY-MM-DD HH:MM UTC`.
pub fn utc_time(seconds: u64) -> String {
    let at = CivilTime::since_epoch(std::time::Duration::from_secs(seconds));
    format!(
        "{:04}-{:02}-{:02} {:02}:{:02} UTC",
        at.year, at.month, at.day, at.hour, at.minute
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_are_civil_dates() {
        assert_eq!(utc_time(0), "1970-01-01 00:00 UTC");
        assert_eq!(utc_time(951_782_400), "2000-02-29 00:00 UTC");
        assert_eq!(utc_time(1_700_000_000), "2023-11-14 22:13 UTC");
    }

    #[test]
    fn a_copy_is_written_whole_and_read_back() {
        let dir = tempfile::tempdir().expect("temp dir");
        let copy = Autosave {
            file: Some(PathBuf::from("prog.tmc")),
            written: 5,
            text: "MVP ABS, 0, 1\n".into(),
            language: Some("TMCL".into()),
        };
        write_autosave(dir.path(), &copy).expect("written");
        assert_eq!(read_autosave(dir.path()), Some(copy));
        // Nothing left beside it.
        let files: Vec<_> = std::fs::read_dir(dir.path())
            .expect("dir")
            .filter_map(Result::ok)
            .map(|e| e.file_name())
            .collect();
        assert_eq!(files, [AUTOSAVE_FILE]);
        remove_autosave(dir.path()).expect("removed");
        assert_eq!(read_autosave(dir.path()), None);
        remove_autosave(dir.path()).expect("removing twice is fine");
    }

    #[test]
    fn a_damaged_copy_is_no_copy() {
        let dir = tempfile::tempdir().expect("temp dir");
        std::fs::write(autosave_path(dir.path()), "{\"file\": nul").expect("write");
        assert_eq!(read_autosave(dir.path()), None);
    }
}
