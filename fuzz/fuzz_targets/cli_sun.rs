//! `acs sun`'s stdin: each line an ISO 8601 UTC timestamp ([`acs::host::cli::sun::parse_utc_iso`]),
//! then the two Sun models at the instant, as the tool runs them. Never panics.
#![no_main]

use acs::env::sun::{precise, schlyter};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    for line in text.lines().take(8) {
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        if let Ok(epoch) = acs::host::cli::sun::parse_utc_iso(t) {
            let _ = schlyter::sun(&epoch);
            let _ = precise::sun(&epoch);
            if let Ok(tt) = epoch.to_tt_extrapolated() {
                let _ = acs::frames::teme_to_j2000_matrix::<f64>(&tt);
            }
        }
    }
});
