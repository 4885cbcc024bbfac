//! `acs plan`'s manoeuvre description (JSON): parsed and checked
//! ([`acs::host::cli::plan::request`]) as the tool does before it plans (the planning itself is
//! an optimisation of seconds, not an input parser). Never panics.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(r) = acs::host::cli::plan::request(&text, "fuzz.json") {
        let p = &r.problem;
        assert!(p.duration_s > 0.0 && p.duration_s.is_finite());
        let _ = p.field_nt(p.duration_s * 0.5);
    }
});
