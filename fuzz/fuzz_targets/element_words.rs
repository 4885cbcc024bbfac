//! The uplink element words ([`Sgp4::from_words`]): any 58 words, and the words of a real
//! element set with fuzzed changes (checksum repaired or not). Never panics; an accepted set
//! writes words that are accepted again and propagates to a finite state or a typed error.
#![no_main]

#[path = "common.rs"]
mod common;

use acs::orbit::sgp4::{words_checksum, Sgp4, ELEMENT_WORDS};
use acs::time::TimeSpan;
use arbitrary::Unstructured;
use libfuzzer_sys::fuzz_target;

fn words(u: &mut Unstructured) -> arbitrary::Result<[u32; ELEMENT_WORDS]> {
    let mut w = [0u32; ELEMENT_WORDS];
    if u.arbitrary::<bool>()? {
        for x in w.iter_mut() {
            *x = u.arbitrary()?;
        }
    } else {
        w = common::orbit().to_words();
        for _ in 0..u.int_in_range(1..=4u8)? {
            let i = u.choose_index(ELEMENT_WORDS - 1)?;
            w[i] = match u.int_in_range(0..=2u8)? {
                0 => u.arbitrary()?,
                1 => u.arbitrary::<f32>()?.to_bits(),
                _ => w[i] ^ (1 << u.int_in_range(0..=31u32)?),
            };
        }
    }
    if u.arbitrary::<bool>()? {
        let (body, last) = w.split_at_mut(ELEMENT_WORDS - 1);
        last[0] = words_checksum(body);
    }
    Ok(w)
}

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let Ok(w) = words(&mut u) else {
        return;
    };
    let Ok(s) = Sgp4::from_words(&w) else {
        return;
    };
    let again = Sgp4::from_words(&s.to_words()).expect("written words are accepted again");
    let _ = s.epoch();
    for _ in 0..4 {
        let Ok(seconds) = u.arbitrary::<i32>() else {
            break;
        };
        let span = TimeSpan::from_whole_seconds(seconds);
        common::check_propagation(&s, &again, span, &mut u, "re-read words");
    }
});
