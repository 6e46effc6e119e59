//! The commissioning sheet: what the technician hands over after a run.
//! A pure function of the run's facts ([`Sheet`]): a self-contained HTML
//! page ([`sheet_html`]) and JSON ([`sheet_json`], schema in
//! `docs/sheet.schema.json`). The front ends gather the facts; nothing
//! here reads a clock, a file or a device.

pub mod facts;
pub mod html;
pub mod json;
pub mod svg;

pub use facts::*;
pub use html::{escape, sheet_html};
pub use json::{SCHEMA_ID, SCHEMA_VERSION, sheet_json};
pub use svg::plot_svg;
