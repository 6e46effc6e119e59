//! Unit conversions of manual §6.1: TMC429 internal velocity and
//! acceleration units ↔ microsteps per second (pps), pps², rps and rpm.
