//! `acs sim FILE`: a scenario file ([`acs::host::sim::scenario_file::parse`]). Never panics; an
//! accepted file gives a scenario with a finite duration of at least one period, the attitudes
//! the file gave unit (to f64 rounding) and those it did not exactly the base scenario's, finite
//! command times and an element set that initialises.
#![no_main]

use acs::host::sim::scenario_file::{parse, MAX_DURATION_S};
use acs::host::sim::scenarios::by_name;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(s) = parse(&text) {
        // an accepted file is JSON with a built-in base and no repeated key
        let file: serde_json::Value = serde_json::from_str(&text).expect("accepted, so JSON");
        let base = file["base"]
            .as_str()
            .and_then(by_name)
            .expect("accepted, so a built-in base")
            .expect("a built-in scenario builds");
        assert!(s.duration_s.is_finite() && s.duration_s >= s.dt_s && s.duration_s <= MAX_DURATION_S);
        let unit = |q: &[f64; 4]| (q.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-9;
        if file.get("initial_attitude").is_some() {
            assert!(unit(&s.initial.0));
        } else {
            assert_eq!(s.initial.0, base.initial.0);
        }
        if file.get("target").is_some() {
            assert!(s.target.as_ref().is_none_or(unit));
        } else {
            assert_eq!(s.target, base.target);
        }
        assert!(s.initial.1.iter().all(|x| x.is_finite()));
        assert!(s.commands.iter().all(|(t, _)| t.is_finite() && *t >= 0.0));
        assert!(s.orbit().is_ok());
    }
});
