//! The core's flash (§2.1.7): what `STORE` saves, the Table 2-19 set, read
//! back at power-on. Kept in memory, or in a JSON file (`axterm sim cmd4cr
//! --eeprom FILE`) so that a restarted simulator finds it again.
//!
//! The flash also holds the standalone programs (§2.7.7: they are
//! "written into the flash memory"), kept as their A-Script source.
//!
//! Each entry is named by the command that reads it (`POLX`, `V12`,
//! `SLOAD`), so the file reads like a list of settings and is checked with
//! the one command parser: a key that is not a stored register of the
//! command table, or a value outside its range, rejects the file, and the
//! core starts from factory settings with the problem reported, the file
//! left as it is. Nothing here panics.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use crate::sim::stored_file::{DisplayPath, StoredFileError as FlashError};
use crate::sim::stored_file::{read_json, write_json_whole};

use crate::protocol::cmd4cr::{Cmd4crCommand, parse_command};

/// The memory's name in messages about its file.
const MEMORY: &str = "flash";

const FILE_FORMAT: &str = "axterm CMD-4CR simulated flash";
const FILE_VERSION: u32 = 1;

/// The file layout.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FlashFile {
    format: String,
    version: u32,
    values: BTreeMap<String, i64>,
    /// The A-Script source of the programs, if any were loaded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    program: Option<String>,
}

/// The flash with its optional file.
#[derive(Debug, Default)]
pub struct Flash {
    /// What STORE saved last, by reading command; empty = factory.
    values: BTreeMap<String, i64>,
    /// The A-Script source of the programs.
    program: Option<String>,
    path: Option<PathBuf>,
    problem: Option<FlashError>,
    /// Why the file given could not be loaded; it is then not used.
    refused: Option<FlashError>,
}

impl Flash {
    /// Load `path` if given and present. A missing or empty file is not a
    /// problem: it is written at the first STORE. An unusable one (not
    /// JSON, another program's file, another simulator's) is refused
    /// ([`Flash::refused`]) and never written: the flash is kept in memory
    /// only.
    pub fn open(path: Option<PathBuf>) -> Flash {
        let mut flash = Flash::default();
        if let Some(path) = path {
            match load(&path) {
                Ok(Some((values, program))) => {
                    flash.values = values;
                    flash.program = program;
                }
                Ok(None) => {}
                Err(problem) => {
                    flash.refused = Some(problem);
                    return flash;
                }
            }
            flash.path = Some(path);
        }
        flash
    }

    /// Why the file given to [`Flash::open`] was refused, if it was.
    pub fn refused(&self) -> Option<&FlashError> {
        self.refused.as_ref()
    }

    /// What was stored, by reading command (`POLX` → 7).
    pub fn values(&self) -> &BTreeMap<String, i64> {
        &self.values
    }

    /// STORE: keep `values` and write the file.
    pub fn store(&mut self, values: BTreeMap<String, i64>) {
        self.values = values;
        self.write();
    }

    /// The programs' source.
    pub fn program(&self) -> Option<&str> {
        self.program.as_deref()
    }

    /// Programs written to flash (loaded into the simulator).
    pub fn set_program(&mut self, source: Option<String>) {
        self.program = source;
        self.write();
    }

    /// A problem found with what the flash holds (a stored program that
    /// no longer compiles).
    pub fn report(&mut self, problem: String) {
        let path = self.path.clone().unwrap_or_default();
        self.problem = Some(FlashError::Content {
            memory: MEMORY,
            path: DisplayPath(path),
            problem,
        });
    }

    fn write(&mut self) {
        let Some(path) = &self.path else {
            return;
        };
        let file = FlashFile {
            format: FILE_FORMAT.to_owned(),
            version: FILE_VERSION,
            values: self.values.clone(),
            program: self.program.clone(),
        };
        if let Err(source) = save(path, &file) {
            self.problem = Some(FlashError::Write {
                memory: MEMORY,
                path: DisplayPath(path.clone()),
                source,
            });
        }
    }

    /// The last problem with the file, if any.
    pub fn problem(&self) -> Option<&FlashError> {
        self.problem.as_ref().or(self.refused.as_ref())
    }
}

/// Check that `key` reads a stored register and `value` is in its range.
pub fn check_entry(key: &str, value: i64) -> Result<Cmd4crCommand, String> {
    let command = parse_command(key).map_err(|e| format!("entry `{key}`: {e}"))?;
    let spec = command.spec();
    if !matches!(command, Cmd4crCommand::Read { .. }) || !spec.stored {
        return Err(format!(
            "entry `{key}` is not a setting STORE saves (§2.1.7 Table 2-19)"
        ));
    }
    if let Some(values) = spec.values
        && !values.contains(value)
    {
        return Err(format!(
            "entry `{key}` holds {value}, outside {}..{}",
            values.min, values.max
        ));
    }
    Ok(command)
}

/// What a flash file holds: the stored values and the programs' source.
type Contents = (BTreeMap<String, i64>, Option<String>);

fn load(path: &Path) -> Result<Option<Contents>, FlashError> {
    let display = || DisplayPath(path.to_path_buf());
    let Some(file) = read_json::<FlashFile>(path, MEMORY)? else {
        return Ok(None);
    };
    let content = |problem| FlashError::Content {
        memory: MEMORY,
        path: display(),
        problem,
    };
    if file.format != FILE_FORMAT || file.version != FILE_VERSION {
        return Err(content(format!(
            "it is not a version-{FILE_VERSION} \"{FILE_FORMAT}\" file (format \"{}\", version {})",
            file.format, file.version
        )));
    }
    for (key, &value) in &file.values {
        check_entry(key, value).map_err(content)?;
    }
    Ok(Some((file.values, file.program)))
}

fn save(path: &Path, file: &FlashFile) -> std::io::Result<()> {
    write_json_whole(path, file)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stored_values_survive_a_restart() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("flash.json");
        let mut flash = Flash::open(Some(path.clone()));
        assert!(flash.values().is_empty());
        flash.store(BTreeMap::from([
            ("POLX".to_string(), 5),
            ("V3".to_string(), -7),
        ]));
        assert!(flash.problem().is_none());
        let again = Flash::open(Some(path));
        assert_eq!(again.values().get("POLX"), Some(&5));
        assert_eq!(again.values().get("V3"), Some(&-7));
    }

    #[test]
    fn a_bad_file_is_reported_and_ignored() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("flash.json");
        for (text, expect) in [
            ("not json", "not valid JSON"),
            (
                r#"{"format":"axterm CMD-4CR simulated flash","version":1,"values":{"HSPDX":5}}"#,
                "not a setting STORE saves",
            ),
            (
                r#"{"format":"axterm CMD-4CR simulated flash","version":1,"values":{"DB":9}}"#,
                "outside 1..5",
            ),
            (
                r#"{"format":"something else","version":1,"values":{}}"#,
                "is not a version-1",
            ),
        ] {
            std::fs::write(&path, text).expect("write");
            let mut flash = Flash::open(Some(path.clone()));
            assert!(flash.values().is_empty());
            let problem = flash.refused().map(|p| p.to_string()).unwrap_or_default();
            assert!(problem.contains(expect), "{problem}");
            // STORE keeps the values in memory; the file is left alone.
            flash.store(BTreeMap::from([("POLX".to_string(), 5)]));
            assert_eq!(flash.values().get("POLX"), Some(&5));
            assert_eq!(std::fs::read_to_string(&path).expect("read"), text);
        }
    }

    #[test]
    fn an_empty_file_is_taken_as_a_new_one() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("flash.json");
        std::fs::write(&path, "").expect("write");
        let mut flash = Flash::open(Some(path.clone()));
        assert!(flash.problem().is_none());
        flash.store(BTreeMap::from([("POLX".to_string(), 5)]));
        assert_eq!(Flash::open(Some(path)).values().get("POLX"), Some(&5));
    }
}
