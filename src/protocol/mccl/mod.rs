//! PMC MultiFlex MCCL (Motion Control Command Language Reference Manual
//! rev. 3.0): its ASCII command interface. Pure code: bytes and meanings,
//! no I/O.

pub mod catalog;
pub mod check;
pub mod line;
pub mod machine;
pub mod profile;
pub mod reply;
pub mod status;
