//! The uplinked SGP4 element set kept in flash across resets: two main-flash segments written
//! alternately, each record sequence-numbered and CRC-protected; at reset the newer valid one
//! is used.
//!
//! # Record (one per 512-byte segment, 16-bit words, little-endian)
//! | word | content |
//! |---|---|
//! | 0 | [`RECORD_MAGIC`], written last (the commit mark) |
//! | 1 | sequence number, +1 per store (wrapping) |
//! | 2 … 117 | the [`ELEMENT_WORDS`] element words of `Sgp4::to_words` (`crate::orbit::sgp4`), each as its low then high half |
//! | 118 | CRC-16/CCITT of words 0–117 as bytes in memory order ([`crc16_ccitt`]) |
//!
//! 119 words, 238 bytes: a record fits one segment, and segments are the erase unit (SLAU056L
//! "Flash Memory Controller", "Flash Memory Segmentation"; SLAS508K §6.8: 512-byte main
//! segments). The two segments must be whole segments outside the image: on the FG4619 map
//! ([`FLIGHT_SEGMENTS`]) 0x2200–0x23FF and 0x2400–0x25FF, the first whole segments of main flash
//! (0x2100–0x21FF is the upper half of a segment whose lower half lies under RAM); the
//! firmware's memory map must then start its code at 0x2600 (or keep 0x2100–0x21FF as a
//! region of its own): 1 KiB of the 57 024 B.
//!
//! # Why a reset never loses both copies
//! A store writes the segment that does *not* hold the newest valid record: erase, then the
//! sequence number, the element words and the CRC, then the magic word last. Until the magic is
//! written that segment is not a valid record (erased words read 0xFFFF), so a reset at any
//! point of the store (after the erase, halfway through the words, before the magic) leaves the
//! newest valid record where it was, untouched; once the magic is written the new record is
//! complete and newer. A segment whose CRC fails (a corrupted or half-erased segment) is
//! ignored. `tests/msp430_drivers.rs` cuts the power after every one of a store's 120 flash
//! operations and checks that the reset finds the old set or the new one, never neither.
//!
//! Sequence numbers compare in serial-number arithmetic (b is newer than a if (b − a) mod 2¹⁶ is
//! in 1 … 32 767): the two copies differ by one, so they never wrap into ambiguity.
//!
//! Cost: a store is one segment erase and 119 word writes, 13.3 ms + 9.8 ms at the flight
//! timing generator ([`super::flash`]); one erase per store, alternating, so each segment sees
//! half the stores: 2 × 10⁴ uplinked element sets within the data sheet's minimum endurance.
//! The caller keeps interrupts disabled during a store (SLAU056 "Flash Memory Access During
//! Write or Erase").

use core::fmt;

use super::flash::{FlashController, FlashError, SEGMENT_BYTES};
use super::Registers;
use crate::orbit::sgp4::{Sgp4, ELEMENT_WORDS};

/// The first word of a complete record.
pub const RECORD_MAGIC: u16 = 0x5E1E;

/// Words in a record: magic, sequence, the element words as halves, CRC.
pub const RECORD_WORDS: usize = 3 + 2 * ELEMENT_WORDS;

/// The segments of the FG4619 map: 0x2200 and 0x2400 (see the [module docs](self)).
pub const FLIGHT_SEGMENTS: [u16; 2] = [0x2200, 0x2400];

/// Byte offset of the CRC word in a record.
const CRC_OFFSET: u16 = 2 * (RECORD_WORDS as u16 - 1);

/// CRC-16/CCITT (polynomial 0x1021, initial value 0xFFFF, no reflection, no final XOR; the
/// "CCITT-FALSE" of the CRC catalogues: check value 0x29B1 for `b"123456789"`): the link's
/// packet error control, [`crate::link::crc16`].
pub use crate::link::crc16::crc16 as crc16_ccitt;

/// One little-endian word into the CRC.
fn crc16_word(crc: u16, word: u16) -> u16 {
    crate::link::crc16::crc16_update(crc, &word.to_le_bytes())
}

/// `b` is newer than `a` in serial-number arithmetic.
fn newer(b: u16, a: u16) -> bool {
    (b.wrapping_sub(a) as i16) > 0
}

/// Why the store could not be used.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StoreError {
    /// The segments are not two distinct 512-byte-aligned segments of main flash below the
    /// vector segment (0xFE00).
    BadSegments,
    /// A flash operation failed.
    Flash(FlashError),
    /// The record written did not read back valid.
    Verify,
}

impl From<FlashError> for StoreError {
    fn from(e: FlashError) -> Self {
        Self::Flash(e)
    }
}

impl fmt::Display for StoreError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::BadSegments => f.write_str("element store: bad segments"),
            Self::Flash(e) => write!(f, "element store: {e}"),
            Self::Verify => f.write_str("element store: record did not verify"),
        }
    }
}

/// The element store over two flash segments.
pub struct ElementStore<R> {
    flash: FlashController<R>,
    segments: [u16; 2],
}

impl<R: Registers> ElementStore<R> {
    /// The store in `segments` (their start addresses), written through `flash`.
    pub fn new(flash: FlashController<R>, segments: [u16; 2]) -> Result<Self, StoreError> {
        let [a, b] = segments;
        let ok = |s: u16| s.is_multiple_of(SEGMENT_BYTES) && s >= 0x1200 && 0xFE00 > s;
        if !(ok(a) && ok(b) && a != b) {
            return Err(StoreError::BadSegments);
        }
        Ok(Self { flash, segments })
    }

    /// Gives the flash controller back.
    pub fn release(self) -> FlashController<R> {
        self.flash
    }

    /// The sequence number of the valid record in segment `base`, if it holds one.
    fn valid(&mut self, base: u16) -> Option<u16> {
        if self.flash.read_word(base) != RECORD_MAGIC {
            return None;
        }
        let mut crc = 0xFFFF;
        let mut offset = 0;
        while CRC_OFFSET > offset {
            crc = crc16_word(crc, self.flash.read_word(base + offset));
            offset += 2;
        }
        (self.flash.read_word(base + CRC_OFFSET) == crc).then(|| self.flash.read_word(base + 2))
    }

    /// The newest valid record: its segment's index and its sequence number.
    fn newest(&mut self) -> Option<(usize, u16)> {
        let [a, b] = self.segments;
        match (self.valid(a), self.valid(b)) {
            (Some(sa), Some(sb)) if newer(sb, sa) => Some((1, sb)),
            (Some(sa), _) => Some((0, sa)),
            (None, Some(sb)) => Some((1, sb)),
            (None, None) => None,
        }
    }

    /// Reads the newest valid element set into `words`; its sequence number, or `None` (and
    /// `words` untouched) if neither segment holds a valid record.
    pub fn load(&mut self, words: &mut [u32; ELEMENT_WORDS]) -> Option<u16> {
        let (index, seq) = self.newest()?;
        let base = self.segments.get(index).copied()?;
        let mut offset = base + 4;
        for w in words.iter_mut() {
            let lo = self.flash.read_word(offset);
            let hi = self.flash.read_word(offset + 2);
            *w = u32::from(lo) | (u32::from(hi) << 16);
            offset += 4;
        }
        Some(seq)
    }

    /// The element set at reset: SGP4 of the newest valid record's words if they check out
    /// (`Sgp4::from_words`), with the record's sequence number; else SGP4 of `fallback` (the
    /// image's words) and no sequence number (`None` for the set too if those do not check
    /// out either). The words' 232 B live in this call's frame only.
    pub fn orbit_or(&mut self, fallback: &[u32; ELEMENT_WORDS]) -> (Option<Sgp4>, Option<u16>) {
        let mut words = [0u32; ELEMENT_WORDS];
        if let Some(seq) = self.load(&mut words) {
            if let Ok(orbit) = Sgp4::from_words(&words) {
                return (Some(orbit), Some(seq));
            }
        }
        (Sgp4::from_words(fallback).ok(), None)
    }

    /// Stores `words` as the newest record (in the segment not holding the newest valid one),
    /// then checks it reads back valid; the new sequence number.
    pub fn store(&mut self, words: &[u32; ELEMENT_WORDS]) -> Result<u16, StoreError> {
        let (target, seq) = match self.newest() {
            Some((index, seq)) => (1 - index, seq.wrapping_add(1)),
            None => (0, 0),
        };
        let base = self
            .segments
            .get(target)
            .copied()
            .ok_or(StoreError::BadSegments)?;
        self.flash.erase_segment(base)?;
        let mut crc = crc16_word(crc16_word(0xFFFF, RECORD_MAGIC), seq);
        self.flash.write_word(base + 2, seq)?;
        let mut offset = base + 4;
        for &w in words {
            for half in [w as u16, (w >> 16) as u16] {
                crc = crc16_word(crc, half);
                self.flash.write_word(offset, half)?;
                offset += 2;
            }
        }
        self.flash.write_word(base + CRC_OFFSET, crc)?;
        // the commit mark
        self.flash.write_word(base, RECORD_MAGIC)?;
        if self.valid(base) != Some(seq) {
            return Err(StoreError::Verify);
        }
        Ok(seq)
    }
}
