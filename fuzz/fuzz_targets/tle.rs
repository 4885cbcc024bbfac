//! The TLE parser ([`acs::tle::Tle`]) on any text: with and without the name line, checksums
//! verified and ignored, and on two well-formed lines of fuzzed fields. Never panics; what it
//! accepts passes its own validation.
#![no_main]

#[path = "common.rs"]
mod common;

use acs::tle::{Checksum, Tle};
use arbitrary::{Arbitrary, Unstructured};
use libfuzzer_sys::fuzz_target;

fn accepted(t: Result<Tle, acs::tle::TleError>) {
    match t {
        Ok(tle) => {
            assert!(tle.validate().is_ok(), "{tle:?}");
            let _ = acs::orbit::sgp4::Sgp4::new(&tle, acs::orbit::sgp4::Gravity::Wgs72);
        }
        Err(e) => {
            let _ = e.to_string();
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    if mode & 1 == 1 {
        // structured: correct columns and checksums, fuzzed values
        let mut u = Unstructured::new(rest);
        let Ok(f) = common::TleFields::arbitrary(&mut u) else {
            return;
        };
        let (l1, l2) = f.lines();
        accepted(Tle::parse(&l1, &l2));
        accepted(Tle::parse_text(&format!("ISS (ZARYA)\n{l1}\n{l2}\n")));
        return;
    }
    let text = String::from_utf8_lossy(rest);
    accepted(Tle::parse_text(&text));
    let mut lines = text.lines();
    let (a, b, c) = (lines.next(), lines.next(), lines.next());
    if let (Some(a), Some(b)) = (a, b) {
        accepted(Tle::parse(a, b));
        accepted(Tle::parse_with(None, a, b, Checksum::Ignore));
        if let Some(c) = c {
            accepted(Tle::parse_with_name(a, b, c));
            accepted(Tle::parse_with(Some(a), b, c, Checksum::Ignore));
        }
    }
});
