//! SGP4 initialisation and propagation from any element set the TLE parser accepts (fields
//! fuzzed within their columns, checksums correct), both gravity models, at fuzzed times.
//! Never panics; a propagated state is finite; the uplink words of an initialised set are
//! accepted and propagate bit for bit as the set itself.
#![no_main]

#[path = "common.rs"]
mod common;

use acs::orbit::sgp4::{Gravity, Sgp4};
use acs::time::TimeSpan;
use acs::tle::Tle;
use arbitrary::{Arbitrary, Unstructured};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let Ok(f) = common::TleFields::arbitrary(&mut u) else {
        return;
    };
    let (l1, l2) = f.lines();
    let Ok(tle) = Tle::parse(&l1, &l2) else {
        return;
    };
    let gravity = if u.arbitrary::<bool>().unwrap_or(false) {
        Gravity::Wgs84
    } else {
        Gravity::Wgs72
    };
    let Ok(s) = Sgp4::new(&tle, gravity) else {
        return;
    };
    let w = Sgp4::from_words(&s.to_words()).expect("the words of an initialised set are accepted");
    for _ in 0..4 {
        let Ok((seconds, nanos)) = u.arbitrary::<(i32, i64)>() else {
            break;
        };
        let span = TimeSpan::new(seconds, nanos);
        common::check_propagation(&s, &w, span, &mut u, &format!("{l1}\n{l2}"));
    }
});
