//! The initialised element set as 32-bit words, for the uplink ([`Sgp4::to_words`] on the
//! ground, [`Sgp4::from_words`] on board).

use super::{finite32, FullDrag, Sgp4, Sgp4Error};
use crate::orbit::{Phase, PHASE_BITS};

/// Number of 32-bit words of an initialised element set ([`Sgp4::to_words`]).
pub const ELEMENT_WORDS: usize = 58;

/// Format tag of [`Sgp4::to_words`] (word 0): "S4", layout version 1.
const WORDS_TAG: u32 = 0x5334_0001;

/// Index of the full-drag flag word (0 or 1).
const FLAG_WORD: usize = 44;

/// Checksum of words `0..ELEMENT_WORDS − 1` of [`Sgp4::to_words`] (the last word): each word
/// rotated in by 5 bits, `c ← rotl(c, 5) ⊕ w` from `0x0acc5a7e` (a corrupted or truncated
/// uplink is refused; the link layer's CRC is the real protection). A change δ of word k
/// changes it by δ rotated left by 5·(56 − k), which lets the ground locate a single bad word.
pub fn words_checksum(words: &[u32]) -> u32 {
    words
        .iter()
        .fold(0x0acc_5a7e_u32, |c, w| c.rotate_left(5) ^ *w)
}

/// Reads the words in order, checking each; remembers the first bad index, and whether a
/// phase's fixed-point part was out of range.
struct WordReader<'a> {
    words: core::slice::Iter<'a, u32>,
    index: u8,
    bad: Option<u8>,
    phase_out_of_range: bool,
}

impl WordReader<'_> {
    /// The next word (0 past the end, which marks it bad).
    fn word(&mut self) -> u32 {
        let w = self.words.next().copied();
        if w.is_none() {
            self.mark(self.index);
        }
        self.index = self.index.saturating_add(1);
        w.unwrap_or(0)
    }
    fn mark(&mut self, index: u8) {
        if self.bad.is_none() {
            self.bad = Some(index);
        }
    }
    /// The next word as a finite f32 (else marked bad), stored in `x`.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn f32(&mut self, x: &mut f32) {
        let index = self.index;
        *x = f32::from_bits(self.word());
        if !finite32(*x) {
            self.mark(index);
        }
    }
    /// The next two words (high first) as an `i64`, stored in `x`, noting one outside
    /// −2⁴⁷..=2⁴⁷ (half a turn, [`Phase`]'s range) in `phase_out_of_range`. Tested on the
    /// 32-bit words: the value is in range when its high word, signed, is in −2¹⁵..2¹⁵, or it is
    /// exactly 2⁴⁷ (high word 2¹⁵, low word 0).
    fn fixed(&mut self, x: &mut i64) {
        const HALF_TURN_HI: u32 = 1 << (PHASE_BITS - 1 - 32);
        let hi = self.word();
        let lo = self.word();
        let in_range =
            2 * HALF_TURN_HI > hi.wrapping_add(HALF_TURN_HI) || (hi == HALF_TURN_HI && lo == 0);
        if !in_range {
            self.phase_out_of_range = true;
        }
        *x = ((u64::from(hi) << 32) | u64::from(lo)) as i64;
    }
    /// The next phase, stored in `p` part by part ([`Phase::raw_mut`]): its fixed-point parts
    /// checked by [`WordReader::fixed`], its rate by [`WordReader::f32`].
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn phase(&mut self, p: &mut Phase) {
        let (at_epoch, rate_fx, rate_turns) = p.raw_mut();
        self.fixed(at_epoch);
        self.fixed(rate_fx);
        self.f32(rate_turns);
    }
}

/// Writes the words in order.
struct WordWriter<'a> {
    words: core::slice::IterMut<'a, u32>,
}

impl WordWriter<'_> {
    fn word(&mut self, w: u32) {
        if let Some(slot) = self.words.next() {
            *slot = w;
        }
    }
    fn f32(&mut self, x: f32) {
        self.word(x.to_bits());
    }
    fn i64(&mut self, x: i64) {
        self.word((x as u64 >> 32) as u32);
        self.word(x as u64 as u32);
    }
    fn phase(&mut self, p: &Phase) {
        let (at_epoch, rate_fx, rate_turns) = p.raw();
        self.i64(at_epoch);
        self.i64(rate_fx);
        self.f32(rate_turns);
    }
}

impl Sgp4 {
    /// The initialised element set as [`ELEMENT_WORDS`] 32-bit words, to be uplinked when the
    /// initialisation runs on the ground ([`Sgp4::from_words`] on board): a format tag, the
    /// epoch (day, second, nanosecond), the initialised constants and phases, the full-drag
    /// flag and terms (zero when absent), and a checksum.
    ///
    /// Initialisation on the host and on the MSP430 gives the same bits (checked by the
    /// firmware benchmark, `firmware/msp430-bench`), so the words do not depend on where they
    /// were made.
    pub fn to_words(&self) -> [u32; ELEMENT_WORDS] {
        let mut words = [0u32; ELEMENT_WORDS];
        let mut w = WordWriter {
            words: words.iter_mut(),
        };
        w.word(WORDS_TAG);
        w.word(self.epoch.day() as u32);
        w.word(self.epoch.second_of_day());
        w.word(self.epoch.nano());
        for x in [
            self.radius_km,
            self.xke,
            self.j2,
            self.ao_km,
            self.v_scale_kmps,
        ] {
            w.f32(x);
        }
        for p in [
            &self.mean_anomaly,
            &self.arg_perigee,
            &self.node,
            &self.arg_latitude,
        ] {
            w.phase(p);
        }
        for x in [
            self.no,
            self.ao,
            self.ecco,
            self.bstar,
            self.cosio,
            self.sinio,
            self.con41,
            self.x1mth2,
            self.x7thm1,
            self.cc1,
            self.cc4,
            self.nodecf,
            self.t2cof,
            self.xlcof,
            self.aycof,
        ] {
            w.f32(x);
        }
        w.word(u32::from(self.full_drag.is_some()));
        let d = self.full_drag.unwrap_or(FullDrag::ZERO);
        for x in [
            d.d2, d.d3, d.d4, d.t3cof, d.t4cof, d.t5cof, d.cc5, d.omgcof, d.xmcof, d.eta, d.delmo,
            d.sinmao,
        ] {
            w.f32(x);
        }
        let (body, last) = words.split_at_mut(ELEMENT_WORDS - 1);
        if let Some(sum) = last.first_mut() {
            *sum = words_checksum(body);
        }
        words
    }

    /// The element set [`Sgp4::to_words`] wrote, checked: the format tag, the checksum, the
    /// epoch, every constant finite, the phases in range and the drag flag 0 or 1, else
    /// [`Sgp4Error::Words`] with the first bad word. Propagation from it is bit for bit that of
    /// the element set that wrote it.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub fn from_words(words: &[u32; ELEMENT_WORDS]) -> Result<Self, Sgp4Error> {
        let (body, last) = words.split_at(ELEMENT_WORDS - 1);
        if last.first() != Some(&words_checksum(body)) {
            return Err(Sgp4Error::Words {
                index: (ELEMENT_WORDS - 1) as u8,
            });
        }
        let mut r = WordReader {
            words: body.iter(),
            index: 0,
            bad: None,
            phase_out_of_range: false,
        };
        if r.word() != WORDS_TAG {
            return Err(Sgp4Error::Words { index: 0 });
        }
        let (day, second, nano) = (r.word() as i32, r.word(), r.word());
        let epoch = crate::time::Epoch::from_parts(day, second, nano)
            .map_err(|_| Sgp4Error::Words { index: 1 })?;
        let phase_index = r.index + 5;
        let flag_index = FLAG_WORD as u8;
        let flag = words[FLAG_WORD];
        // the fields read in the words' order into a zeroed set, the drag terms always (the
        // flag word drops them below)
        let mut orbit = Self {
            epoch,
            radius_km: 0.0,
            xke: 0.0,
            j2: 0.0,
            ao_km: 0.0,
            v_scale_kmps: 0.0,
            mean_anomaly: Phase::ZERO,
            arg_perigee: Phase::ZERO,
            node: Phase::ZERO,
            arg_latitude: Phase::ZERO,
            no: 0.0,
            ao: 0.0,
            ecco: 0.0,
            bstar: 0.0,
            cosio: 0.0,
            sinio: 0.0,
            con41: 0.0,
            x1mth2: 0.0,
            x7thm1: 0.0,
            cc1: 0.0,
            cc4: 0.0,
            nodecf: 0.0,
            t2cof: 0.0,
            xlcof: 0.0,
            aycof: 0.0,
            full_drag: None,
        };
        orbit.read_fields(&mut r);
        if let Some(index) = r.bad {
            return Err(Sgp4Error::Words { index });
        }
        match flag {
            0 => orbit.full_drag = None,
            1 => {}
            _ => return Err(Sgp4Error::Words { index: flag_index }),
        }
        // a phase's fixed-point parts beyond half a turn (checked as they were read)
        if r.phase_out_of_range {
            return Err(Sgp4Error::Words { index: phase_index });
        }
        Ok(orbit)
    }

    /// Reads the fields after the epoch in the words' order (the reader marks a non-finite
    /// f32 and notes a phase out of range) into `self`, the drag terms always (set to `Some`).
    ///
    /// Out of line and through `&mut self`, each field is stored as soon as it is read: built
    /// as one struct expression, the MSP430 code held every field on the stack and then copied
    /// it (16 B more code per f32; reference image −426 B). The reader writes each field through
    /// a reference to it, a phase too (returned, each was copied in by `memcpy`).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn read_fields(&mut self, r: &mut WordReader) {
        let o = self;
        r.f32(&mut o.radius_km);
        r.f32(&mut o.xke);
        r.f32(&mut o.j2);
        r.f32(&mut o.ao_km);
        r.f32(&mut o.v_scale_kmps);
        r.phase(&mut o.mean_anomaly);
        r.phase(&mut o.arg_perigee);
        r.phase(&mut o.node);
        r.phase(&mut o.arg_latitude);
        r.f32(&mut o.no);
        r.f32(&mut o.ao);
        r.f32(&mut o.ecco);
        r.f32(&mut o.bstar);
        r.f32(&mut o.cosio);
        r.f32(&mut o.sinio);
        r.f32(&mut o.con41);
        r.f32(&mut o.x1mth2);
        r.f32(&mut o.x7thm1);
        r.f32(&mut o.cc1);
        r.f32(&mut o.cc4);
        r.f32(&mut o.nodecf);
        r.f32(&mut o.t2cof);
        r.f32(&mut o.xlcof);
        r.f32(&mut o.aycof);
        let _flag = r.word();
        let d = o.full_drag.insert(FullDrag::ZERO);
        r.f32(&mut d.d2);
        r.f32(&mut d.d3);
        r.f32(&mut d.d4);
        r.f32(&mut d.t3cof);
        r.f32(&mut d.t4cof);
        r.f32(&mut d.t5cof);
        r.f32(&mut d.cc5);
        r.f32(&mut d.omgcof);
        r.f32(&mut d.xmcof);
        r.f32(&mut d.eta);
        r.f32(&mut d.delmo);
        r.f32(&mut d.sinmao);
    }
}
