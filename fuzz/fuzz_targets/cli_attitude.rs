//! `acs attitude`'s stdin JSON through the three solvers
//! ([`acs::host::cli::attitude::solve_text`]). Never panics.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&m, rest)) = data.split_first() else {
        return;
    };
    let text = String::from_utf8_lossy(rest);
    let method = ["svd", "quest", "triad"][usize::from(m % 3)];
    match acs::host::cli::attitude::solve_text(&text, method) {
        Ok(out) => assert!(
            !out.contains("NaN") && !out.contains("inf"),
            "{text}: {out}"
        ),
        Err(e) => {
            let _ = e.exit_code();
        }
    }
});
