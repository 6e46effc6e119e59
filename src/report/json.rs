//! The sheet as JSON, described by the versioned schema in
//! `docs/sheet.schema.json` ([`SCHEMA_ID`], [`SCHEMA_VERSION`]): the
//! facts as they are, each module's verdict and the sheet's, and each
//! setting's `differs` flag, so a reader need not recompute them.

use serde_json::{Value, json};

use super::facts::{ModuleSheet, Sheet};

/// The schema's `$id`.
pub const SCHEMA_ID: &str = "urn:axterm:commissioning-sheet:1";
/// Bumped when a field changes meaning or goes away.
pub const SCHEMA_VERSION: u32 = 1;

pub fn sheet_json(sheet: &Sheet) -> Value {
    json!({
        "$schema": SCHEMA_ID,
        "version": SCHEMA_VERSION,
        "run_file": sheet.run_file,
        "operator": sheet.operator,
        "axterm_version": sheet.axterm_version,
        "started_utc": sheet.started_utc,
        "ended_utc": sheet.ended_utc,
        "verdict": sheet.verdict(),
        "modules": sheet.modules.iter().map(module_json).collect::<Vec<_>>(),
    })
}

fn module_json(module: &ModuleSheet) -> Value {
    let mut value = serde_json::to_value(module).unwrap_or(Value::Null);
    if let Some(rows) = value
        .pointer_mut("/settings/rows")
        .and_then(Value::as_array_mut)
    {
        for (row, fact) in rows.iter_mut().zip(&module.settings.rows) {
            if let Value::Object(map) = row {
                map.insert("differs".into(), Value::Bool(fact.differs()));
            }
        }
    }
    if let Value::Object(map) = &mut value {
        map.insert(
            "verdict".into(),
            serde_json::to_value(module.verdict()).unwrap_or(Value::Null),
        );
    }
    value
}
