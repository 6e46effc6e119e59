//! The console's look and keys: [`theme`] gives every part of the screen a
//! style, [`keymap`] turns key presses into actions, per pane; [`config`]
//! finds the user's own files and reports what is wrong with them. The
//! TUI is built on these.

pub mod config;
pub mod keymap;
pub mod theme;
