//! A faithful simulator of the Nippon Pulse Commander core CMD-4CR.

pub mod motion;
