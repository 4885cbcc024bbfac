//! Host-only code (feature `host`): the `acs` command-line tool, host file formats and
//! mission analysis ([`eclipse_search`]).
//!
//! Nothing here is part of the flight build. Host code may use `std` and may allocate, but it
//! still never panics on bad input: every failure is a typed error and an exit code.
#![allow(clippy::indexing_slicing)]

pub mod cli;
pub mod dictionary;
pub mod eclipse_search;
pub mod link;
pub mod planner;
pub mod sim;
pub mod stk;

/// An epoch as ISO 8601 UTC to the millisecond (`2009-06-16T00:00:00.000Z`).
pub fn iso_utc_ms(e: &crate::time::Epoch<crate::time::Utc>) -> String {
    let c = e.to_calendar();
    format!(
        "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z",
        c.year,
        c.month,
        c.day,
        c.hour,
        c.minute,
        c.second,
        c.nano / 1_000_000
    )
}
