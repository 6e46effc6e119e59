//! Macro memory (manual Ch4 "Building MCCL Macro Sequences", Ch10 MD, RM,
//! TM): macros 0–999, each at most 255 bytes, 510K bytes in all; a
//! redefined macro's old bytes are not reused until RM; −18 when full.
//!
//! Byte accounting (the manual gives only "2 bytes (a command with no
//! parameter) to 10 bytes (a command with a 64 bit floating point
//! parameter)"): 2 bytes a command, plus 4 for a 32-bit integer, 8 for a
//! real (or an integer beyond 32 bits), 2 for `@n`, and a string's length
//! plus its terminating NUL. The memory is 510,000 bytes (2000 × 255, the
//! manual's "up to 2000 user defined macros" of 255 bytes).
//!
//! On a MultiFlex ETH the macros are non-volatile: kept in a JSON file
//! (`axterm sim mccl-eth --eeprom FILE`) written whole at every MD and RM
//! and read at start, each macro as the text `TM` lists (re-read with the
//! one lexer). A file that cannot be read is reported and the controller
//! starts with no macros.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::errors::Code;
use super::lexer::{Command, Param, Radix, lex};
use super::program::{self, Origin, Program};
use crate::sim::stored_file::{DisplayPath, StoredFileError, read_json, write_json_whole};

/// Ch4: "Each macro can include as many as 255 bytes".
pub const MACRO_BYTES: usize = 255;
/// Ch4: "a total macro capacity of 510K bytes".
pub const MACRO_MEMORY: usize = 510_000;

/// What a command costs in macro memory.
pub fn cost(command: &Command) -> usize {
    2 + match &command.param {
        Param::None => 0,
        Param::Int(n) if i32::try_from(*n).is_ok() => 4,
        Param::Int(_) | Param::Real(_) => 8,
        Param::Register(_) => 2,
        Param::Text(text) => text.len() + 1,
    }
}

/// One stored macro.
#[derive(Debug, Clone)]
pub struct StoredMacro {
    pub program: Arc<Program>,
    pub bytes: usize,
    /// Its numbers were typed in hex (HM), for reading it back.
    pub hex: bool,
}

impl StoredMacro {
    /// Its commands as TM shows them, after `MC<n>,`.
    pub fn text(&self) -> String {
        self.program
            .commands
            .iter()
            .map(|c| c.text.as_str())
            .collect::<Vec<_>>()
            .join(",")
    }
}

/// The memory's name in messages about its file.
const MEMORY: &str = "macro memory";
const FILE_FORMAT: &str = "axterm MultiFlex simulated macro memory";
const FILE_VERSION: u32 = 1;

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct MacroFile {
    format: String,
    version: u32,
    /// Bytes used, redefined macros' leftovers included.
    used: usize,
    macros: Vec<FileMacro>,
}

#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileMacro {
    number: u16,
    text: String,
    #[serde(default)]
    hex: bool,
}

#[derive(Debug)]
pub struct MacroStore {
    macros: BTreeMap<u16, StoredMacro>,
    used: usize,
    capacity: usize,
    file: Option<PathBuf>,
    problem: Option<StoredFileError>,
    /// The file was there but could not be loaded: never written.
    refused: Option<StoredFileError>,
}

impl MacroStore {
    /// Volatile memory (`None`), or the ETH's file, read if there is one.
    pub fn open(file: Option<PathBuf>) -> MacroStore {
        let mut store = MacroStore {
            macros: BTreeMap::new(),
            used: 0,
            capacity: MACRO_MEMORY,
            file: None,
            problem: None,
            refused: None,
        };
        if let Some(path) = file {
            match load(&path) {
                Ok(Some((macros, used))) => {
                    store.macros = macros;
                    store.used = used;
                    store.file = Some(path);
                }
                Ok(None) => store.file = Some(path),
                // A file that is there but not ours is never written
                // over: the macros are kept in RAM only.
                Err(problem) => store.refused = Some(problem),
            }
        }
        store
    }

    /// Why the file given to [`MacroStore::open`] was refused (it is there
    /// but is not a macro memory of ours), if it was; it is then left
    /// untouched.
    pub fn refused(&self) -> Option<&StoredFileError> {
        self.refused.as_ref()
    }

    /// A smaller memory, for tests of −18.
    pub fn with_capacity(mut self, capacity: usize) -> MacroStore {
        self.capacity = capacity;
        self
    }

    pub fn get(&self, n: u16) -> Option<&StoredMacro> {
        self.macros.get(&n)
    }

    /// Bytes used, redefined macros' leftovers included.
    pub fn used(&self) -> usize {
        self.used
    }

    /// The last write of the file that failed, or why the file was
    /// refused.
    pub fn problem(&self) -> Option<&StoredFileError> {
        self.problem.as_ref().or(self.refused.as_ref())
    }

    /// MD n: store `body`, replacing macro n (its old bytes stay used).
    pub fn define(&mut self, n: u16, body: Vec<Command>, hex: bool) -> Result<(), Code> {
        let bytes: usize = body.iter().map(cost).sum();
        if bytes > MACRO_BYTES || self.used + bytes > self.capacity {
            return Err(Code::NO_MEMORY);
        }
        self.used += bytes;
        let program = Program::new(body, Origin::Macro(n));
        self.macros.insert(
            n,
            StoredMacro {
                program,
                bytes,
                hex,
            },
        );
        self.write();
        Ok(())
    }

    /// RM: every macro erased, the memory free again.
    pub fn clear(&mut self) {
        self.macros.clear();
        self.used = 0;
        self.write();
    }

    /// TM n: `MC<n>,<commands>`.
    pub fn list(&self, n: u16) -> Option<String> {
        let stored = self.macros.get(&n)?;
        let text = stored.text();
        Some(if text.is_empty() {
            format!("MC{n}")
        } else {
            format!("MC{n},{text}")
        })
    }

    /// TM-1: every macro in order.
    pub fn listing(&self) -> Vec<String> {
        self.macros.keys().filter_map(|&n| self.list(n)).collect()
    }

    fn write(&mut self) {
        let Some(path) = &self.file else {
            return;
        };
        let file = MacroFile {
            format: FILE_FORMAT.to_string(),
            version: FILE_VERSION,
            used: self.used,
            macros: self
                .macros
                .iter()
                .map(|(&number, stored)| FileMacro {
                    number,
                    text: stored.text(),
                    hex: stored.hex,
                })
                .collect(),
        };
        if let Err(source) = write_json_whole(path, &file) {
            self.problem = Some(StoredFileError::Write {
                memory: MEMORY,
                path: DisplayPath(path.clone()),
                source,
            });
        }
    }
}

type Contents = (BTreeMap<u16, StoredMacro>, usize);

fn load(path: &Path) -> Result<Option<Contents>, StoredFileError> {
    let Some(file) = read_json::<MacroFile>(path, MEMORY)? else {
        return Ok(None);
    };
    let content = |problem: String| StoredFileError::Content {
        memory: MEMORY,
        path: DisplayPath(path.to_path_buf()),
        problem,
    };
    if file.format != FILE_FORMAT || file.version != FILE_VERSION {
        return Err(content(format!(
            "it is not a version-{FILE_VERSION} \"{FILE_FORMAT}\" file (format \"{}\", version {})",
            file.format, file.version
        )));
    }
    let mut macros = BTreeMap::new();
    let mut bytes_in_use = 0;
    for entry in file.macros {
        if entry.number > 999 {
            return Err(content(format!("macro {} is outside 0..999", entry.number)));
        }
        let radix = if entry.hex {
            Radix::Hex
        } else {
            Radix::Decimal
        };
        let body = if entry.text.is_empty() {
            Vec::new()
        } else {
            lex(&entry.text, radix).map_err(|e| {
                content(format!(
                    "macro {}: `{}` gives error {} at `{}`",
                    entry.number, entry.text, e.code, e.command
                ))
            })?
        };
        program::check(&body, true).map_err(|m| {
            content(format!(
                "macro {}: error {} at command {}",
                entry.number, m.code, m.at
            ))
        })?;
        let bytes: usize = body.iter().map(cost).sum();
        if bytes > MACRO_BYTES {
            return Err(content(format!(
                "macro {} is over {MACRO_BYTES} bytes",
                entry.number
            )));
        }
        bytes_in_use += bytes;
        let program = Program::new(body, Origin::Macro(entry.number));
        macros.insert(
            entry.number,
            StoredMacro {
                program,
                bytes,
                hex: entry.hex,
            },
        );
    }
    if file.used < bytes_in_use || file.used > MACRO_MEMORY {
        return Err(content(format!(
            "it says {} bytes are used, but its macros take {bytes_in_use}",
            file.used
        )));
    }
    Ok(Some((macros, file.used)))
}

/// The `corrupt-store` fault: change the first integer parameter of
/// `body` by one, text and value alike; `false` if it has none.
pub fn corrupt(body: &mut [Command]) -> bool {
    for command in body.iter_mut() {
        if let Param::Int(n) = command.param {
            let changed = n ^ 1;
            let axis = command.axis.map(|a| a.to_string()).unwrap_or_default();
            command.param = Param::Int(changed);
            command.text = format!("{axis}{}{changed}", command.spec.mnemonic);
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn body(text: &str) -> Vec<Command> {
        lex(text, Radix::Decimal).expect("lexes")
    }

    #[test]
    fn commands_cost_2_to_10_bytes() {
        let costs: Vec<usize> = body("NO,1MR1000,1WS.1,AL@10,OT\"ab\",AL5000000000")
            .iter()
            .map(cost)
            .collect();
        assert_eq!(costs, [2, 6, 10, 4, 5, 10]);
    }

    #[test]
    fn a_macro_over_255_bytes_is_minus_18() {
        let mut store = MacroStore::open(None);
        // 25 commands of 10 bytes: 250, fits; 26: 260, does not.
        let fits = vec!["1WS.5"; 25].join(",");
        assert_eq!(store.define(1, body(&fits), false), Ok(()));
        let over = vec!["1WS.5"; 26].join(",");
        assert_eq!(store.define(2, body(&over), false), Err(Code::NO_MEMORY));
        assert_eq!(store.used(), 250);
    }

    #[test]
    fn redefining_leaks_until_rm() {
        // Ch10 MD: "the memory space occupied by the previous version of the
        // macro will not be reused until a Reset Macro command is issued".
        let mut store = MacroStore::open(None).with_capacity(25);
        assert_eq!(store.define(3, body("1MR1000,1MR-1000"), false), Ok(()));
        assert_eq!(store.define(3, body("1MR1000,1MR-1000"), false), Ok(()));
        assert_eq!(store.used(), 24);
        assert_eq!(store.define(3, body("NO"), false), Err(Code::NO_MEMORY));
        store.clear();
        assert_eq!(store.used(), 0);
        assert_eq!(store.define(3, body("NO"), false), Ok(()));
        assert_eq!(store.list(3).as_deref(), Some("MC3,NO"));
    }

    #[test]
    fn the_eth_file_keeps_macros_and_a_bad_one_is_reported() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("macros.json");
        {
            let mut store = MacroStore::open(Some(path.clone()));
            assert_eq!(store.define(10, body("1MR1000,WS.1"), false), Ok(()));
            let hex = lex("1MA0FF", Radix::Hex).expect("lexes");
            assert_eq!(store.define(11, hex, true), Ok(()));
        }
        let store = MacroStore::open(Some(path.clone()));
        assert!(store.problem().is_none(), "{:?}", store.problem());
        assert_eq!(store.listing(), ["MC10,1MR1000,WS.1", "MC11,1MA0FF"]);
        assert_eq!(
            store.get(11).map(|m| m.program.commands[0].param.clone()),
            Some(Param::Int(255))
        );
        assert_eq!(store.used(), 22);
        std::fs::write(
            &path,
            r#"{"format":"axterm MultiFlex simulated macro memory","version":1,"used":6,"macros":[{"number":1,"text":"1XX5"}]}"#,
        )
        .expect("write");
        let mut store = MacroStore::open(Some(path.clone()));
        assert!(store.listing().is_empty());
        let problem = store.refused().map(ToString::to_string).unwrap_or_default();
        assert!(
            problem.contains("macro 1: `1XX5` gives error 1"),
            "{problem}"
        );
        // A refused file is never written over.
        let before = std::fs::read(&path).expect("read");
        assert_eq!(store.define(12, body("1MR5"), false), Ok(()));
        assert_eq!(std::fs::read(&path).expect("read"), before);
    }

    #[test]
    fn corrupting_changes_the_first_integer() {
        let mut commands = body("NO,1MR1000,2MR7");
        assert!(corrupt(&mut commands));
        assert_eq!(commands[1].text, "1MR1001");
        assert_eq!(commands[1].param, Param::Int(1001));
        assert!(!corrupt(&mut body("NO,WS.5")));
    }
}
