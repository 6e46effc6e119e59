//! `--mechanics FILE`: the axes' own units (issue 20, point 3) for
//! encode, exec, run and the console. The file is a parameter file
//! (`params export` writes the mechanics in force beside the settings)
//! or one holding only `[mechanics.N]` sections.

use std::path::Path;

use crate::protocol::parameter_file::Entry;
use crate::protocol::parameters::Scope;
use crate::protocol::units::{Converted, MechanicsTable, UnitLaw, UnitRefusal, convert_line};

/// A mechanics file as read: the table, and the settings the file holds
/// (what an offline conversion takes for the module's).
#[derive(Debug, Clone, Default)]
pub struct MechanicsFile {
    pub table: MechanicsTable,
    pub settings: Vec<Entry>,
}

impl MechanicsFile {
    /// Read `path`; an error names the file and what is wrong with it.
    pub fn read(path: &Path) -> Result<MechanicsFile, String> {
        let name = path.display();
        let text = crate::files::read_text(path).map_err(|e| format!("mechanics {name}: {e}"))?;
        let (table, settings) =
            MechanicsTable::parse_file(&text).map_err(|e| format!("mechanics {name}: {e}"))?;
        Ok(MechanicsFile { table, settings })
    }

    /// The file's own value of a setting.
    pub fn setting(&self, scope: Scope, number: u16) -> Option<i64> {
        self.settings
            .iter()
            .find(|e| e.scope == scope && e.number == number)
            .map(|e| e.value)
    }

    /// `line` converted offline: the module's settings are the file's own.
    pub fn convert_offline(
        &self,
        law: Option<&dyn UnitLaw>,
        line: &str,
    ) -> Result<Converted, String> {
        convert_line(law, line, &self.table, &|scope, number| self.setting(scope, number)).map_err(
            |e| {
                if e.kind == UnitRefusal::NeedsReading {
                    format!("{e} (offline, the file's [axis.N] and [bank.N] values are the module's settings)")
                } else {
                    e.into()
                }
            },
        )
    }
}

/// The mechanics `--mechanics` names, if any.
pub fn load(path: Option<&Path>) -> Result<Option<MechanicsFile>, String> {
    path.map(MechanicsFile::read).transpose()
}
