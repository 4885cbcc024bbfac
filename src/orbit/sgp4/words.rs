//! The initialised element set as 32-bit words, for the uplink ([`Sgp4::to_words`] on the
//! ground, [`Sgp4::from_words`] on board).

use super::{finite32, FullDrag, Sgp4, Sgp4Error};
use crate::orbit::Phase;

/// Number of 32-bit words of an initialised element set ([`Sgp4::to_words`]).
pub const ELEMENT_WORDS: usize = 58;

/// Format tag of [`Sgp4::to_words`] (word 0): "S4", layout version 1.
const WORDS_TAG: u32 = 0x5334_0001;

/// Checksum of words `0..ELEMENT_WORDS − 1` of [`Sgp4::to_words`] (the last word): each word
/// rotated in by 5 bits, `c ← rotl(c, 5) ⊕ w` from `0x0acc5a7e` (a corrupted or truncated
/// uplink is refused; the link layer's CRC is the real protection). A change δ of word k
/// changes it by δ rotated left by 5·(56 − k), which lets the ground locate a single bad word.
pub fn words_checksum(words: &[u32]) -> u32 {
    words
        .iter()
        .fold(0x0acc_5a7e_u32, |c, w| c.rotate_left(5) ^ *w)
}

/// Reads the words in order, checking each; remembers the first bad index.
struct WordReader<'a> {
    words: core::slice::Iter<'a, u32>,
    index: u8,
    bad: Option<u8>,
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
    /// The next word as a finite f32 (else marked bad).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn f32(&mut self) -> f32 {
        let index = self.index;
        let x = f32::from_bits(self.word());
        if !finite32(x) {
            self.mark(index);
        }
        x
    }
    fn i64(&mut self) -> i64 {
        let hi = self.word();
        let lo = self.word();
        ((u64::from(hi) << 32) | u64::from(lo)) as i64
    }
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn phase(&mut self) -> Phase {
        let at_epoch = self.i64();
        let rate_fx = self.i64();
        let rate_turns = self.f32();
        Phase::from_raw(at_epoch, rate_fx, rate_turns)
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
        let d = self.full_drag.unwrap_or(FullDrag {
            d2: 0.0,
            d3: 0.0,
            d4: 0.0,
            t3cof: 0.0,
            t4cof: 0.0,
            t5cof: 0.0,
            cc5: 0.0,
            omgcof: 0.0,
            xmcof: 0.0,
            eta: 0.0,
            delmo: 0.0,
            sinmao: 0.0,
        });
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
        };
        if r.word() != WORDS_TAG {
            return Err(Sgp4Error::Words { index: 0 });
        }
        let (day, second, nano) = (r.word() as i32, r.word(), r.word());
        let epoch = crate::time::Epoch::from_parts(day, second, nano)
            .map_err(|_| Sgp4Error::Words { index: 1 })?;
        // Each field read straight into the result, in the words' order (struct expressions
        // evaluate their fields as written): no intermediate copies (on the MSP430, 2 B of
        // code per word moved).
        let phase_index = r.index + 5;
        let mut orbit = Self {
            epoch,
            radius_km: r.f32(),
            xke: r.f32(),
            j2: r.f32(),
            ao_km: r.f32(),
            v_scale_kmps: r.f32(),
            mean_anomaly: r.phase(),
            arg_perigee: r.phase(),
            node: r.phase(),
            arg_latitude: r.phase(),
            no: r.f32(),
            ao: r.f32(),
            ecco: r.f32(),
            bstar: r.f32(),
            cosio: r.f32(),
            sinio: r.f32(),
            con41: r.f32(),
            x1mth2: r.f32(),
            x7thm1: r.f32(),
            cc1: r.f32(),
            cc4: r.f32(),
            nodecf: r.f32(),
            t2cof: r.f32(),
            xlcof: r.f32(),
            aycof: r.f32(),
            full_drag: None,
        };
        let flag_index = r.index;
        let flag = r.word();
        let drag = FullDrag {
            d2: r.f32(),
            d3: r.f32(),
            d4: r.f32(),
            t3cof: r.f32(),
            t4cof: r.f32(),
            t5cof: r.f32(),
            cc5: r.f32(),
            omgcof: r.f32(),
            xmcof: r.f32(),
            eta: r.f32(),
            delmo: r.f32(),
            sinmao: r.f32(),
        };
        if let Some(index) = r.bad {
            return Err(Sgp4Error::Words { index });
        }
        orbit.full_drag = match flag {
            0 => None,
            1 => Some(drag),
            _ => return Err(Sgp4Error::Words { index: flag_index }),
        };
        let phases_ok = [
            &orbit.mean_anomaly,
            &orbit.arg_perigee,
            &orbit.node,
            &orbit.arg_latitude,
        ]
        .iter()
        .all(|p| p.in_range());
        if !phases_ok {
            return Err(Sgp4Error::Words { index: phase_index });
        }
        Ok(orbit)
    }
}
