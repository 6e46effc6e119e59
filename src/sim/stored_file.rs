//! The file a simulator keeps its non-volatile memory in (the TMCM-1110's
//! EEPROM, the CMD-4CR's flash): JSON, written whole and atomically
//! ([`crate::files::write_atomically`]), and the problems with it worded
//! for the user. A problem never stops the simulator: it starts with
//! factory settings, or keeps settings in memory. A file that is there
//! but cannot be loaded (not JSON, another simulator's, another program's
//! file) is never written over: the simulator keeps its memory in RAM only
//! and reports the file as refused (`axterm sim` then serves nothing).

use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;
use serde::de::DeserializeOwned;

/// Something went wrong with a simulator's memory file. `memory` names the
/// memory ("EEPROM", "flash").
#[derive(Debug, thiserror::Error)]
pub enum StoredFileError {
    #[error("cannot read the simulated {memory} file {path}: {source}")]
    Read {
        memory: &'static str,
        path: DisplayPath,
        source: crate::files::ReadError,
    },
    #[error(
        "{path} is not a simulated {memory} file of this simulator: it is not valid JSON of the expected shape ({source})"
    )]
    Parse {
        memory: &'static str,
        path: DisplayPath,
        source: serde_json::Error,
    },
    #[error("the simulated {memory} file {path} was rejected: {problem}")]
    Content {
        memory: &'static str,
        path: DisplayPath,
        problem: String,
    },
    #[error(
        "cannot write the simulated {memory} file {path}: {source}; the settings are kept in memory only"
    )]
    Write {
        memory: &'static str,
        path: DisplayPath,
        source: std::io::Error,
    },
}

/// A path in an error message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DisplayPath(pub PathBuf);

impl fmt::Display for DisplayPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0.display())
    }
}

/// Read the memory file at `path`: `None` when there is none yet, or an
/// empty one (a file made for it, `touch eeprom.json`).
pub(crate) fn read_json<T: DeserializeOwned>(
    path: &Path,
    memory: &'static str,
) -> Result<Option<T>, StoredFileError> {
    let display = || DisplayPath(path.to_path_buf());
    let text = match crate::files::read_text(path) {
        Ok(text) if text.trim().is_empty() => return Ok(None),
        Ok(text) => text,
        Err(e) if e.is_not_found() => return Ok(None),
        Err(source) => {
            return Err(StoredFileError::Read {
                memory,
                path: display(),
                source,
            });
        }
    };
    serde_json::from_str(&text)
        .map(Some)
        .map_err(|source| StoredFileError::Parse {
            memory,
            path: display(),
            source,
        })
}

/// Write the memory file whole and atomically, so an interrupted write
/// never leaves half a file behind, and two simulators on one file never
/// mix their writes.
pub(crate) fn write_json_whole<T: Serialize>(path: &Path, value: &T) -> std::io::Result<()> {
    let text = serde_json::to_string_pretty(value).map_err(std::io::Error::other)?;
    crate::files::write_atomically(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_file_yet_is_no_error_and_a_bad_one_is_named() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("memory.json");
        let none: Option<Vec<i64>> = read_json(&path, "flash").expect("no file is fine");
        assert!(none.is_none());
        std::fs::write(&path, "not json").expect("write");
        let error = read_json::<Vec<i64>>(&path, "flash").expect_err("bad file");
        let message = error.to_string();
        assert!(
            message.ends_with(
                "memory.json is not a simulated flash file of this simulator: it is not valid \
                 JSON of the expected shape (expected ident at line 1 column 2)"
            ),
            "{message}"
        );
        std::fs::write(&path, " \n").expect("write");
        let empty: Option<Vec<i64>> = read_json(&path, "flash").expect("empty is fine");
        assert!(empty.is_none());
        write_json_whole(&path, &vec![1, 2]).expect("write whole");
        assert_eq!(
            read_json::<Vec<i64>>(&path, "flash").expect("read"),
            Some(vec![1, 2])
        );
    }
}
