//! `acs sim FILE`: a scenario file ([`acs::host::sim::scenario_file::parse`]). Never panics; an
//! accepted file gives a scenario with a finite duration of at least one period, unit attitudes
//! (to f32 rounding),
//! finite command times and an element set that initialises.
#![no_main]

use acs::host::sim::scenario_file::{parse, MAX_DURATION_S};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(s) = parse(&text) {
        assert!(s.duration_s.is_finite() && s.duration_s >= s.dt_s && s.duration_s <= MAX_DURATION_S);
        // unit to the f32 rounding the built-in scenarios' attitudes carry (a file's are exact)
        let unit = |q: &[f64; 4]| (q.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-6;
        assert!(unit(&s.initial.0));
        assert!(s.target.as_ref().is_none_or(unit));
        assert!(s.initial.1.iter().all(|x| x.is_finite()));
        assert!(s.commands.iter().all(|(t, _)| t.is_finite() && *t >= 0.0));
        assert!(s.orbit().is_ok());
    }
});
