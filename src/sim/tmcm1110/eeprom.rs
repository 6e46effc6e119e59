//! The module's EEPROM (manual §3.6.7, §3.6.8, §3.6.11, §3.6.12, §3.6.24,
//! §5.1, §5.3, §3.6.53): storable (E) axis parameters, the auto-stored bank-0
//! settings, user variables 0..55, coordinates 1..20 and the TMCL program.
//! Optionally kept in a JSON file so that a restarted simulator finds it
//! again. A file that cannot be read or makes no sense is reported and the
//! module starts from factory settings, keeping its EEPROM in memory only:
//! that file is refused, never written over. Nothing here panics.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use crate::sim::stored_file::{DisplayPath, StoredFileError as EepromError};
use crate::sim::stored_file::{read_json, write_json_whole};

use crate::protocol::tmcl::params::{self, ParamInfo};

use super::defaults;
use super::motion::Axis;
use super::program::{PROGRAM_MEMORY_SIZE, ProgramWord};

/// The memory's name in messages about its file.
const MEMORY: &str = "EEPROM";

/// User variables 0..55 have EEPROM backing (§5.3).
pub const STORED_USER_VARIABLES: usize = 56;
/// Coordinates 1..20 have EEPROM backing; coordinate 0 is RAM only (§3.6.24).
pub const STORED_COORDINATES: usize = 20;

/// The `format` field of the file, so a wrong file is recognised as such.
const FILE_FORMAT: &str = "axterm TMCM-1110 simulated EEPROM";
const FILE_VERSION: u32 = 1;

/// Axis parameters with access E (§4 Table 16).
pub fn storable_axis_params() -> impl Iterator<Item = u8> {
    numbers_where(params::AXIS_PARAMS, |p| p.access.eeprom)
}

/// Bank-0 parameters SGP writes through to EEPROM (access A, §5.1).
pub fn auto_stored_globals() -> impl Iterator<Item = u8> {
    numbers_where(params::BANK0_PARAMS, |p| p.access.auto_stored)
}

fn numbers_where(
    table: &'static [ParamInfo],
    keep: fn(&ParamInfo) -> bool,
) -> impl Iterator<Item = u8> {
    table
        .iter()
        .filter(move |p| keep(p))
        .flat_map(|p| p.numbers.clone())
}

/// What the EEPROM holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EepromImage {
    /// Storable axis parameters by number.
    pub axis: BTreeMap<u8, i32>,
    /// Auto-stored bank-0 parameters by number.
    pub globals: BTreeMap<u8, i32>,
    pub user_variables: [i32; STORED_USER_VARIABLES],
    /// Coordinates 1..20 at index 0..19.
    pub coordinates: [i32; STORED_COORDINATES],
    /// The TMCL program, `PROGRAM_MEMORY_SIZE` words.
    pub program: Vec<ProgramWord>,
}

impl EepromImage {
    /// The factory image: what command 137 restores.
    pub fn factory(address: u8) -> Self {
        let fresh = Axis::new();
        EepromImage {
            axis: storable_axis_params()
                .map(|n| (n, defaults::axis_factory_value(n, &fresh)))
                .collect(),
            globals: auto_stored_globals()
                .map(|n| (n, defaults::bank0_factory_value(n, address)))
                .collect(),
            user_variables: [0; STORED_USER_VARIABLES],
            coordinates: [0; STORED_COORDINATES],
            program: vec![ProgramWord::default(); PROGRAM_MEMORY_SIZE],
        }
    }

    /// Coordinate `number` (1..20) as stored.
    pub fn coordinate(&self, number: u8) -> Option<i32> {
        let index = usize::from(number).checked_sub(1)?;
        self.coordinates.get(index).copied()
    }

    pub fn set_coordinate(&mut self, number: u8, value: i32) {
        if let Some(slot) = usize::from(number)
            .checked_sub(1)
            .and_then(|i| self.coordinates.get_mut(i))
        {
            *slot = value;
        }
    }

    fn to_file(&self) -> EepromFile {
        let used = self
            .program
            .iter()
            .rposition(|w| !w.is_empty())
            .map_or(0, |last| last + 1);
        EepromFile {
            format: FILE_FORMAT.to_owned(),
            version: FILE_VERSION,
            axis_parameters: self.axis.clone(),
            global_parameters: self.globals.clone(),
            user_variables: self.user_variables.to_vec(),
            coordinates: self.coordinates.to_vec(),
            program: self.program[..used].iter().map(|w| w.to_bytes()).collect(),
        }
    }

    /// Check a file's contents and lay them over the factory image (entries
    /// a file lacks keep their factory values).
    fn from_file(file: EepromFile, factory: EepromImage) -> Result<Self, String> {
        if file.format != FILE_FORMAT || file.version != FILE_VERSION {
            return Err(format!(
                "it is not a version-{FILE_VERSION} \"{FILE_FORMAT}\" file (format \"{}\", version {})",
                file.format, file.version
            ));
        }
        let mut image = factory;
        for (number, value) in file.axis_parameters {
            // Values are the axis model's business; only the numbers are checked.
            match image.axis.get_mut(&number) {
                Some(slot) => *slot = value,
                None => return Err(format!("axis parameter {number} cannot be stored")),
            }
        }
        for (number, value) in file.global_parameters {
            let Some(slot) = image.globals.get_mut(&number) else {
                return Err(format!("global parameter {number} of bank 0 is not stored"));
            };
            // A wrong address or baud rate would make the module unreachable.
            if let Some(info) = params::global_param(0, number)
                && !info.accepts_wire(value)
            {
                return Err(format!(
                    "global parameter {number} ({}) holds {value}, outside {}",
                    info.name, info.range
                ));
            }
            *slot = value;
        }
        image.user_variables = file.user_variables.try_into().map_err(|v: Vec<i32>| {
            format!(
                "it holds {} user variables, the EEPROM has {STORED_USER_VARIABLES}",
                v.len()
            )
        })?;
        image.coordinates = file.coordinates.try_into().map_err(|v: Vec<i32>| {
            format!(
                "it holds {} coordinates, the EEPROM has {STORED_COORDINATES} (1..20)",
                v.len()
            )
        })?;
        if file.program.len() > PROGRAM_MEMORY_SIZE {
            return Err(format!(
                "its program has {} commands, the memory holds {PROGRAM_MEMORY_SIZE}",
                file.program.len()
            ));
        }
        for (slot, bytes) in image.program.iter_mut().zip(file.program) {
            *slot = ProgramWord::from_bytes(bytes);
        }
        Ok(image)
    }
}

/// The file layout (JSON). Program words are the 7-byte command form
/// `[opcode, type, motor/bank, value MSB … LSB]`; trailing empty words are
/// left out.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct EepromFile {
    format: String,
    version: u32,
    axis_parameters: BTreeMap<u8, i32>,
    global_parameters: BTreeMap<u8, i32>,
    user_variables: Vec<i32>,
    coordinates: Vec<i32>,
    program: Vec<[u8; 7]>,
}

/// The EEPROM with its optional backing file.
#[derive(Debug)]
pub struct Eeprom {
    pub image: EepromImage,
    path: Option<PathBuf>,
    /// Writes are collected instead of written (during a program download,
    /// which stores up to 2048 commands one by one).
    deferred: bool,
    dirty: bool,
    problem: Option<EepromError>,
    /// Why the file given could not be loaded; it is then not used.
    refused: Option<EepromError>,
}

impl Eeprom {
    /// Load `path` if given and present; otherwise, or if it is unusable,
    /// start from `factory`. A missing or empty file is not a problem: it
    /// is written on the first change. An unusable one (not JSON, another
    /// program's file, another simulator's) is refused ([`Eeprom::refused`])
    /// and never written: the EEPROM is kept in memory only.
    pub fn open(path: Option<PathBuf>, factory: EepromImage) -> Self {
        let mut eeprom = Eeprom {
            image: factory.clone(),
            path: None,
            deferred: false,
            dirty: false,
            problem: None,
            refused: None,
        };
        if let Some(path) = path {
            match load(&path, factory) {
                Ok(Some(image)) => eeprom.image = image,
                Ok(None) => {}
                Err(problem) => {
                    eeprom.refused = Some(problem);
                    return eeprom;
                }
            }
            eeprom.path = Some(path);
        }
        eeprom
    }

    /// The last problem with the file, if any.
    pub fn problem(&self) -> Option<&EepromError> {
        self.problem.as_ref().or(self.refused.as_ref())
    }

    /// Why the file given to [`Eeprom::open`] was refused, if it was.
    pub fn refused(&self) -> Option<&EepromError> {
        self.refused.as_ref()
    }

    /// Record that the image changed: write it out now, or later if deferred.
    pub fn changed(&mut self) {
        self.dirty = true;
        if !self.deferred {
            self.flush();
        }
    }

    /// Collect writes (`true`) or write what was collected and stop
    /// collecting (`false`).
    pub fn defer_writes(&mut self, defer: bool) {
        self.deferred = defer;
        if !defer {
            self.flush();
        }
    }

    /// Write the image to the file if it changed since the last write.
    pub fn flush(&mut self) {
        if !self.dirty {
            return;
        }
        self.dirty = false;
        let Some(path) = &self.path else {
            return;
        };
        if let Err(source) = save(path, &self.image) {
            self.problem = Some(EepromError::Write {
                memory: MEMORY,
                path: DisplayPath(path.clone()),
                source,
            });
        }
    }
}

impl Drop for Eeprom {
    fn drop(&mut self) {
        self.flush();
    }
}

fn load(path: &Path, factory: EepromImage) -> Result<Option<EepromImage>, EepromError> {
    let Some(file) = read_json::<EepromFile>(path, MEMORY)? else {
        return Ok(None);
    };
    EepromImage::from_file(file, factory)
        .map(Some)
        .map_err(|problem| EepromError::Content {
            memory: MEMORY,
            path: DisplayPath(path.to_path_buf()),
            problem,
        })
}

fn save(path: &Path, image: &EepromImage) -> std::io::Result<()> {
    write_json_whole(path, &image.to_file())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_survives_a_file_round_trip() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("eeprom.json");
        let mut image = EepromImage::factory(1);
        image.user_variables[55] = -7;
        image.set_coordinate(20, 1234);
        image.program[3] = ProgramWord {
            opcode: 4,
            kind: 0,
            motor_bank: 0,
            value: 90000,
        };
        save(&path, &image).expect("save");
        let loaded = load(&path, EepromImage::factory(1)).expect("load");
        assert_eq!(loaded, Some(image));
    }

    #[test]
    fn a_missing_file_is_no_problem() {
        let dir = tempfile::tempdir().expect("temp dir");
        let eeprom = Eeprom::open(Some(dir.path().join("none.json")), EepromImage::factory(1));
        assert!(eeprom.problem().is_none());
        assert_eq!(eeprom.image, EepromImage::factory(1));
    }

    #[test]
    fn garbage_is_refused_factory_settings_used_and_the_file_left_alone() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("eeprom.json");
        std::fs::write(&path, "{ not json").expect("write");
        let mut eeprom = Eeprom::open(Some(path.clone()), EepromImage::factory(1));
        let message = eeprom.refused().map(|p| p.to_string()).unwrap_or_default();
        assert!(message.contains("not valid JSON"), "{message}");
        assert!(
            message.contains("is not a simulated EEPROM file"),
            "{message}"
        );
        assert_eq!(eeprom.image, EepromImage::factory(1));
        // A change is kept in memory; the file is not written over.
        eeprom.image.user_variables[0] = 42;
        eeprom.changed();
        drop(eeprom);
        assert_eq!(std::fs::read(&path).expect("read"), b"{ not json");
    }

    #[test]
    fn an_empty_file_is_taken_as_a_new_one() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("eeprom.json");
        std::fs::write(&path, "").expect("write");
        let mut eeprom = Eeprom::open(Some(path.clone()), EepromImage::factory(1));
        assert!(eeprom.problem().is_none());
        eeprom.image.user_variables[0] = 42;
        eeprom.changed();
        let loaded = load(&path, EepromImage::factory(1)).expect("load");
        assert_eq!(loaded.map(|i| i.user_variables[0]), Some(42));
    }

    #[test]
    fn wrong_shapes_are_rejected_with_the_reason() {
        let file = |users: usize, program: usize| EepromFile {
            format: FILE_FORMAT.to_owned(),
            version: FILE_VERSION,
            axis_parameters: BTreeMap::new(),
            global_parameters: BTreeMap::new(),
            user_variables: vec![0; users],
            coordinates: vec![0; STORED_COORDINATES],
            program: vec![[0; 7]; program],
        };
        let err = EepromImage::from_file(file(3, 0), EepromImage::factory(1)).unwrap_err();
        assert!(err.contains("3 user variables"), "{err}");
        let err = EepromImage::from_file(
            file(STORED_USER_VARIABLES, PROGRAM_MEMORY_SIZE + 1),
            EepromImage::factory(1),
        )
        .unwrap_err();
        assert!(err.contains("2049 commands"), "{err}");
        let mut unknown = file(STORED_USER_VARIABLES, 0);
        unknown.axis_parameters.insert(1, 5);
        let err = EepromImage::from_file(unknown, EepromImage::factory(1)).unwrap_err();
        assert!(err.contains("axis parameter 1 cannot be stored"), "{err}");
        let mut foreign = file(STORED_USER_VARIABLES, 0);
        foreign.format = "something else".into();
        assert!(EepromImage::from_file(foreign, EepromImage::factory(1)).is_err());
    }

    #[test]
    fn deferred_writes_happen_on_release() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("eeprom.json");
        let mut eeprom = Eeprom::open(Some(path.clone()), EepromImage::factory(1));
        eeprom.defer_writes(true);
        eeprom.image.user_variables[0] = 42;
        eeprom.changed();
        assert!(!path.exists());
        eeprom.defer_writes(false);
        let loaded = load(&path, EepromImage::factory(1)).expect("load");
        assert_eq!(loaded.map(|i| i.user_variables[0]), Some(42));
    }

    #[test]
    fn an_unwritable_file_is_reported() {
        let dir = tempfile::tempdir().expect("temp dir");
        // A directory where the file should be: writing must fail.
        let path = dir.path().join("eeprom.json");
        std::fs::create_dir_all(path.join("x")).expect("dir");
        let mut eeprom = Eeprom::open(None, EepromImage::factory(1));
        eeprom.path = Some(path);
        eeprom.changed();
        let message = eeprom.problem().map(|p| p.to_string()).unwrap_or_default();
        assert!(message.contains("cannot write"), "{message}");
    }

    #[test]
    fn coordinates_are_numbered_from_one() {
        let mut image = EepromImage::factory(1);
        image.set_coordinate(1, 11);
        image.set_coordinate(0, 99); // RAM only: ignored
        image.set_coordinate(21, 99);
        assert_eq!(image.coordinate(1), Some(11));
        assert_eq!(image.coordinate(0), None);
        assert_eq!(image.coordinate(21), None);
        assert_eq!(image.coordinates.iter().filter(|&&c| c == 99).count(), 0);
    }
}
