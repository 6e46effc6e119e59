//! Values in an axis's own units on a connected module: the settings a
//! family's unit law converts with are read from the module (or, where it
//! reads none back, taken from what this session wrote), then the line is
//! converted ([`crate::protocol::units`]). Generic: the family gives the
//! law and its parameter set, nothing here names a family.

use std::collections::HashMap;

use super::Session;
use super::params::{ModuleValue, read_values};
use crate::protocol::parameters::Scope;
use crate::protocol::settings::SettingsCache;
use crate::protocol::units::{
    Converted, MechanicsTable, UnitRefusal, axes_needed, check_line, convert_line, has_units,
};

impl Session {
    /// `line` with its unit values turned raw under this module's current
    /// settings, read now (reads only: nothing of the line is sent), or as
    /// `earlier` has them: what the lines before it in a batch write, not
    /// sent yet (a family whose lines say what they write, SIXpack 2). A
    /// line without unit values comes back as it is; an error names the
    /// value and what is wrong, and the line must not be sent.
    pub async fn convert_units(
        &self,
        line: &str,
        mechanics: &MechanicsTable,
        earlier: &SettingsCache,
    ) -> Result<Converted, String> {
        let console = self.family().console;
        let law = console.units();
        if !has_units(law, line) {
            return Ok(Converted {
                line: line.to_string(),
                notes: Vec::new(),
            });
        }
        check_line(law, line, mechanics)?;
        let mut values: HashMap<(Scope, u16), ModuleValue> = HashMap::new();
        if let (Some(law), Some(parameters)) = (law, console.parameters()) {
            for axis in axes_needed(law, line) {
                let wanted = law.inputs(axis);
                let rows: Vec<_> = parameters
                    .tables(axis)
                    .into_iter()
                    .flat_map(|t| t.rows)
                    .filter(|r| wanted.contains(&(r.scope, r.number)))
                    .filter(|r| earlier.value(r.scope, r.number).is_none())
                    .collect();
                values.extend(read_values(self, parameters, &rows).await);
            }
        }
        convert_line(law, line, mechanics, &|scope, number| {
            earlier
                .value(scope, number)
                .or_else(|| values.get(&(scope, number)).and_then(ModuleValue::value))
        })
        .map_err(|e| {
            // Say why a setting the law needed is not known.
            let why: Vec<String> = values
                .values()
                .filter_map(|v| match v {
                    ModuleValue::Unreadable(why) | ModuleValue::Unknown(why) => Some(why.clone()),
                    _ => None,
                })
                .collect();
            if e.kind == UnitRefusal::NeedsReading && !why.is_empty() {
                format!("{e} ({})", why.join("; "))
            } else {
                e.into()
            }
        })
    }
}
