//! `acs igrf`'s stdin CSV: each line parsed ([`acs::host::cli::igrf::parse_row`]) and evaluated
//! ([`acs::host::cli::igrf::row_output`]) in both coordinate forms and at a fuzzed degree, as
//! the tool does. Never panics; a row that is evaluated gives finite components.
#![no_main]

use acs::env::igrf::Degree;
use acs::host::cli::igrf::{parse_row, row_output};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&flags, rest)) = data.split_first() else {
        return;
    };
    let geocentric = flags & 1 == 1;
    let Ok(degree) = Degree::new(1 + (flags >> 1) % 13) else {
        return;
    };
    let text = String::from_utf8_lossy(rest);
    let mut seen = false;
    for (i, line) in text.lines().take(8).enumerate() {
        match parse_row(i + 1, line, geocentric, &mut seen) {
            Ok(Some(values)) => {
                if let Ok(row) = row_output(i + 1, values, geocentric, degree) {
                    assert!(row.iter().all(|x| x.is_finite()), "{line}: {row:?}");
                }
            }
            Ok(None) => {}
            Err(e) => {
                let _ = e.exit_code();
            }
        }
    }
});
