//! The STK `.e` ephemeris reader ([`acs::host::stk::read`]) and its date parser on any text.
//! Never panics; what it reads is written back ([`acs::host::stk::write`]) into a file it reads
//! again with the same number of rows.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let _ = acs::host::stk::parse_date(&text);
    match acs::host::stk::read(&text) {
        Ok(e) => {
            for row in e.rows.iter().take(4) {
                let _ = e.epoch_of(row);
            }
            let again = acs::host::stk::read(&acs::host::stk::write(&e))
                .expect("a written ephemeris reads back");
            assert_eq!(again.rows.len(), e.rows.len());
        }
        Err(err) => {
            let _ = err.to_string();
        }
    }
});
