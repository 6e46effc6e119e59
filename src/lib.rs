//! axterm: a terminal console for commissioning stepper and servo axes.
//!
//! Layers (see README): `protocol` (pure codecs and tables), `sim`
//! (simulated controllers), and the front ends in `cli`.

pub mod cli;
pub mod protocol;
pub mod sim;
