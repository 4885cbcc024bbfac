//! Host-only code (feature `host`): the `acs` command-line tool, host file formats and
//! mission analysis ([`eclipse_search`]).
//!
//! Nothing here is part of the flight build. Host code may use `std` and may allocate, but it
//! still never panics on bad input: every failure is a typed error and an exit code.
#![allow(clippy::indexing_slicing)]

pub mod cli;
pub mod eclipse_search;
pub mod planner;
pub mod sim;
pub mod stk;
