//! The file a simulator keeps its non-volatile memory in (the TMCM-1110's
//! EEPROM, the CMD-4CR's flash): JSON, written whole through a rename, and
//! the problems with it worded for the user. A problem never stops the
//! simulator: it starts with factory settings, or keeps settings in memory.

use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;
use serde::de::DeserializeOwned;

/// Something went wrong with a simulator's memory file. `memory` names the
/// memory ("EEPROM", "flash").
#[derive(Debug, thiserror::Error)]
pub enum StoredFileError {
    #[error(
        "cannot read the simulated {memory} file {path}: {source}; started with factory settings"
    )]
    Read {
        memory: &'static str,
        path: DisplayPath,
        source: std::io::Error,
    },
    #[error(
        "the simulated {memory} file {path} is not valid JSON of the expected shape: {source}; started with factory settings"
    )]
    Parse {
        memory: &'static str,
        path: DisplayPath,
        source: serde_json::Error,
    },
    #[error(
        "the simulated {memory} file {path} was rejected: {problem}; started with factory settings"
    )]
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

/// Read the memory file at `path`: `None` when there is none yet.
pub(crate) fn read_json<T: DeserializeOwned>(
    path: &Path,
    memory: &'static str,
) -> Result<Option<T>, StoredFileError> {
    let display = || DisplayPath(path.to_path_buf());
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
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

/// Write the memory file through a temporary file and a rename, so an
/// interrupted write never leaves half a file behind.
pub(crate) fn write_json_whole<T: Serialize>(path: &Path, value: &T) -> std::io::Result<()> {
    let text = serde_json::to_string_pretty(value).map_err(std::io::Error::other)?;
    let mut temporary = path.as_os_str().to_owned();
    temporary.push(".tmp");
    let temporary = PathBuf::from(temporary);
    std::fs::write(&temporary, text)?;
    std::fs::rename(&temporary, path)
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
            message.starts_with("the simulated flash file "),
            "{message}"
        );
        assert!(
            message.ends_with("started with factory settings"),
            "{message}"
        );
        write_json_whole(&path, &vec![1, 2]).expect("write whole");
        assert_eq!(
            read_json::<Vec<i64>>(&path, "flash").expect("read"),
            Some(vec![1, 2])
        );
    }
}
