//! The reference node's uplinked element set kept in flash across resets (flight build, feature
//! `pil` off): [`acs::hal::msp430::element_store`] in the two main-flash segments
//! `FLIGHT_SEGMENTS` (0x2200–0x23FF, 0x2400–0x25FF), which the node map
//! `memory-fg4619-node.x` keeps out of the image.
//!
//! - At reset ([`ElementFlash::orbit_at_reset`]) the newer valid record of the two is loaded
//!   (8.5 ms) and its words read as SGP4 (`Sgp4::from_words`, which checks them whole); without
//!   a valid record, or with words that do not check out, the image's element words
//!   ([`crate::flight_elements::FLIGHT_ELEMENT_WORDS`]) are the fall-back, as in the PIL build.
//! - When the ground's ELEMENTS command is accepted ([`acs::uplink::apply_reference`] returned
//!   `Ok`: the words checked out and the node flies them), [`ElementFlash::keep`] writes them as
//!   the next record, into the segment that does not hold the newest (erase and 119 word
//!   writes: about 42 ms, 23 ms of them flash operations with the interrupts disabled,
//!   [`crate::periph::without_interrupts`]). A reset at any point of it leaves the older record
//!   valid (the store's commit order).
//!
//! `ELEMENT_STORE` (two words, for a debugger or a later telemetry): word 0 the record loaded at
//! reset (0: none, the image's words; 1 + its sequence number otherwise, wrapping), word 1 the
//! outcome of the last store (0: none yet, 1: stored and verified, 2: failed; the set stays in
//! use either way, only its copy for the next reset is missing).

use acs::hal::msp430::element_store::{ElementStore, FLIGHT_SEGMENTS};
use acs::hal::msp430::flash::{FlashConfig, FlashController};
use acs::orbit::sgp4::{Sgp4, ELEMENT_WORDS};

use crate::flight_elements::FLIGHT_ELEMENT_WORDS;
use crate::mmio::Mmio;

/// The record loaded at reset and the last store's outcome (see the [module docs](self)).
#[no_mangle]
static mut ELEMENT_STORE: [u16; 2] = [0; 2];

/// Writes word `i` of `ELEMENT_STORE`.
fn publish(i: usize, value: u16) {
    if i < 2 {
        // SAFETY: single-threaded, no handler touches it; `i` within the array; volatile: read
        // from outside the program.
        unsafe { core::ptr::write_volatile((&raw mut ELEMENT_STORE as *mut u16).add(i), value) }
    }
}

/// The element store of the flight map (see the [module docs](self)).
pub struct ElementFlash {
    store: Option<ElementStore<Mmio>>,
}

impl ElementFlash {
    /// The store over `FLIGHT_SEGMENTS`, its flash controller's timing generator set (MCLK ÷ 22:
    /// the clocks must be set up first, [`crate::periph::init_clocks`]).
    pub fn open() -> Self {
        let flash = FlashController::new(Mmio, FlashConfig::FLIGHT);
        Self {
            store: ElementStore::new(flash, FLIGHT_SEGMENTS).ok(),
        }
    }

    /// The element set at reset: the newer valid record's, else the image's words (`None` if
    /// neither checks out), as [`ElementStore::orbit_or`] gives it, with one buffer for both
    /// (the image's words copied in, the record's loaded over them): `Sgp4::from_words` has two
    /// call sites, not three. Out of line: the words' 232 B live in its frame only.
    #[inline(never)]
    pub fn orbit_at_reset(&mut self) -> Option<Sgp4> {
        let mut words = FLIGHT_ELEMENT_WORDS;
        let seq = self.store.as_mut().and_then(|store| store.load(&mut words));
        match (Sgp4::from_words(&words), seq) {
            (Ok(orbit), seq) => {
                if let Some(seq) = seq {
                    publish(0, seq.wrapping_add(1));
                }
                Some(orbit)
            }
            // the record's words did not check out: the image's
            (Err(_), Some(_)) => Sgp4::from_words(&FLIGHT_ELEMENT_WORDS).ok(),
            (Err(_), None) => None,
        }
    }

    /// Keeps `words` (an element set the node accepted) as the next record.
    #[inline(never)]
    pub fn keep(&mut self, words: &[u32; ELEMENT_WORDS]) {
        let stored = match self.store.as_mut() {
            Some(store) => crate::periph::without_interrupts(|| store.store(words).is_ok()),
            None => false,
        };
        publish(1, if stored { 1 } else { 2 });
    }
}
