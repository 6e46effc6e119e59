//! What a commissioning sheet ([`crate::report`]) asks of the module
//! itself: its settings against the family's factory defaults, read the
//! same way for `axterm run --report` (after the run) and the console's
//! `:report` (when it is given). Generic over the family: the rows and
//! their defaults are the family's parameter tables.

use std::collections::HashSet;

use super::Session;
use super::params::{ModuleValue, read_values};
use crate::protocol::parameters::{ParamOp, ParamRow, Scope};
use crate::report::{SettingRow, Settings};

/// `axis 0`, `bank 2`.
fn scope_name(scope: Scope) -> String {
    match scope {
        Scope::Axis(n) => format!("axis {n}"),
        Scope::Bank(n) => format!("bank {n}"),
    }
}

/// Each setting of the family's tables that has a factory default, read
/// from the module; a module that stops answering is not asked the rest.
/// Stored when a line that succeeded is the family's store line of one of
/// its settings.
pub async fn read_settings(session: &Session, sent: &[String]) -> Settings {
    let family = session.family();
    let Some(parameters) = family.console.parameters() else {
        return Settings::default();
    };
    let mut seen = HashSet::new();
    let mut rows: Vec<ParamRow> = Vec::new();
    let mut store_lines = HashSet::new();
    // By the axes' own numbers: MCCL counts its axes from 1.
    for axis in family.console.axes() {
        for table in parameters.tables(axis.number) {
            for row in table.rows {
                if !seen.insert((row.scope, row.number)) {
                    continue;
                }
                if let Ok(line) = parameters.line(&row, ParamOp::Store)
                    && let Ok(prepared) = family.console.prepare(&line, session.address())
                {
                    store_lines.insert(prepared.canonical);
                }
                if row.default.is_some() {
                    rows.push(row);
                }
            }
        }
    }
    let mut silent = false;
    let mut settings = Vec::new();
    for row in rows {
        let value = if silent {
            ModuleValue::NoAnswer("not read: the module stopped answering".into())
        } else {
            read_values(session, parameters, std::slice::from_ref(&row))
                .await
                .remove(&(row.scope, row.number))
                .unwrap_or_else(|| ModuleValue::NoAnswer("not read".into()))
        };
        silent |= matches!(value, ModuleValue::NoAnswer(_));
        // The family's own writing of a value, where it is not the raw
        // number.
        let text =
            |raw: i64| Some(parameters.value_text(&row, raw)).filter(|t| *t != raw.to_string());
        settings.push(SettingRow {
            scope: scope_name(row.scope),
            number: row.number,
            name: row.name.clone(),
            value: value.value(),
            note: value.why_not().map(str::to_string),
            factory_default: row.default,
            unit: row.unit.to_string(),
            value_text: value.value().and_then(text),
            default_text: row.default.and_then(text),
        });
    }
    Settings {
        parameter_file: None,
        rows: settings,
        eeprom_stored: sent.iter().any(|line| store_lines.contains(line)),
        read: None,
    }
}
