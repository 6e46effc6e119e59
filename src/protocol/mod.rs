//! Protocol knowledge of every controller family: frames, typed commands,
//! console line syntax, parameter tables. No I/O here.

pub mod tmcl;
