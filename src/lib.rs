//! axterm: a terminal console for commissioning stepper and servo axes.
//!
//! Layers, data flowing down and back up (see the house plan):
//! `cli` and `ui` (front ends) → `session` (what the console knows of a controller)
//! → `device` (the async task owning a link) → `link` (byte transports)
//! → `sim` (simulated controllers). `protocol` is pure code used by all;
//! `ui` holds the console's themes and keymaps. `files` is the one way
//! any of them reads a file a user names or writes a file.

pub mod cli;
pub mod device;
pub mod families;
pub mod files;
pub mod link;
pub mod protocol;
pub mod report;
pub mod run_recording;
pub mod script;
pub mod session;
pub mod sim;
pub mod ui;
pub mod wall_clock;
