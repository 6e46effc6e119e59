//! Trinamic TMCL as spoken by the TMCM-1110 StepRocker (firmware V1.12
//! manual). Pure code: bytes and meanings, no I/O.

pub mod command;
pub mod frame;
pub mod line;
pub mod params;
pub mod units;

pub use frame::{ChecksumError, FRAME_LEN, FrameAssembler, Reply, Request, Status, checksum};
