//! The stuck-gyro watch (`docs/faults.md`, finding 2): a gyro whose word stops changing while
//! the filter keeps correcting the attitude about its axis is held out of the rate, reported,
//! and its axis's rate is left to the filter's gyro-bias state.
//!
//! # The rule
//! - Per tile, the reads in a row that repeated its gyro's word exactly (a missed read neither
//!   extends nor breaks a run), and the filter's attitude corrections about its axis summed over
//!   the run (the error state's `δθ` the Sun's and the field's updates applied,
//!   [`Mekf::correction_rad`]).
//! - **Held** as stuck when the run reaches [`STUCK_REPEATS`] (15) reads and the sum reaches
//!   [`STUCK_DRIFT_RAD`] (0.1°) in magnitude; **released** when its word changes.
//! - A step's correction counts only if the filter was *settled* before it: its attitude's
//!   largest 1σ within the same 0.1° ([`Mekf::attitude_within`]). A correction the filter's own
//!   uncertainty explains (the first updates after a start from TRIAD, at 0.05 rad; the end of
//!   an eclipse or of a link outage) is no evidence against a gyro. Without it, a still,
//!   noise-free gyro (constant words) was held by the first update after a start (0.2–0.37°
//!   about each axis in `tests/modes.rs`' rig) and its bias walk ended the estimate 16 steps
//!   later.
//! - While held: every step it is read reports [`super::Faults::device_read`]; the reading is
//!   kept, but the MEKF's gyro-bias covariance along the axis grows by
//!   ([`RATE_WALK_RADPS_PER_SQRT_S`], 2e-2 rad/s/√s)²·Δt a step (the bias state then carries
//!   the body rate about that axis, driven by the Sun and the field), and the laws get the
//!   gyros' rate less the filter's bias ([`StuckGyros::filter_step`]).
//! - The watch runs once a step, after the filter's step: the step's word, then the step's
//!   correction, then the limits.
//!
//! # The thresholds (measured on branch `stuck`, `tests/stuck_experiment.rs` there, with the
//! prototype of this watch: `f32` sums of the quaternion difference between the estimate before
//! the step propagated and the one after)
//! - Repetition alone is not enough: the noise-free sensors of the thesis scenario repeat words
//!   up to 255 reads (181 733 steps of its campaign with a word repeated ≥ 10 times); the ideal
//!   truth's 1-LSB noise repeats a word with probability ≈ 0.28 a step (runs of up to 13 in its
//!   dispersed `detumble` campaign, 12 in `tracking`); the realistic gyro's 2.6 LSB ≈ 0.11 a
//!   step (runs of up to 7; 15 in a row ≈ 4e-15). At 10 repeats one step of the ideal
//!   `detumble` campaign (30 runs) was held (its corrections 0.135°): hence 15.
//! - The corrections over a run of ≥ 10 repeated words reached 0.063° in the noise-free thesis
//!   campaign (0.135° once in the ideal `detumble` campaign, whose runs never reach 15): hence
//!   0.1°. A stuck U gyro (the cube's only one on U) passes it within its first 15 reads.
//! - The walk: the stuck U gyro's pointing stays under 1.6° from 5e-3 to 5e-2 rad/s/√s (22.7° at
//!   1e-1, 77° at 3e-4). Rejected: a gyro-bias bound (a stuck gyro's bias estimate stays under
//!   2.3e-4 rad/s, nominal `detumble` reaches 2.5e-3), the gate's refusals (the first 32 s after
//!   the fault, nominal runs of up to 19 steps), dropping the held gyro (the rate about U lost:
//!   160.9°).
//! - No gyro held in any nominal scenario of either truth, nor in the dispersed campaigns
//!   (seed 1: `tracking` 200 realistic, 100 ideal; `detumble` 50 realistic, 30 ideal; `slew`
//!   100; `thesis-slew` 100 ideal).
//!
//! # Measured (`tests/faults.rs`, this implementation)
//! Stuck −U gyro (300–600 s): held from 315 s to the clear (`device_read` 285 of 300 steps),
//! worst pointing 0.960° during, 0.491° after (before: 86.0°, no report); +W (tile 2) from
//! 328 s, 0.611° / 0.505°; +V (tile 1) from 346 s, 0.709° / 0.526°. No gyro held (a print on
//! the hold, not kept) in any of the eight built-in scenarios under either truth, nor in the
//! dispersed campaigns (seed 1) `tracking` (200 runs realistic, 100 ideal), `detumble` (50
//! realistic, 30 ideal), `slew` (100) and `thesis-slew` (100 ideal: noise-free sensors).
//!
//! # State
//! 5 B a tile (30 B for the flight's six tiles; the prototype's `f32` sums and `u32` mask took
//! 48 B): the last word (`i16`), the run (`u8`, saturating at [`STUCK_REPEATS`]; [`HELD`] once
//! held: no mask) and the sum (the upper half of its `f32`, a bfloat16: the sum is added and
//! compared in `f32`, then stored truncated to 8 significant bits, at most 2⁻⁷ of itself low
//! each step: over a run to the limit, the stored sum is within 15·2⁻⁷·0.1° ≈ 0.012° of the
//! `f32` sum); and the filter's correction of the step, [`Mekf::correction_rad`] (12 B).
//!
//! # Flash (the attitude node's MSP430 image)
//! +1 126 B (43 290 → 44 416 B), the node's stack +46 B, its worst step +3 663 cycles without
//! the multiplier (`firmware/msp430-bench`). Measured against the shapes tried: the sum as an `i16` count of 1e-6 rad (a saturating
//! `f32` → `i16` conversion: +208 B), as an `f32` (+12 B of state, the node's stack +54 B, over
//! its RAM line), and the watch in two passes, the words before the filter and the sums after
//! (+78 B).
//!
//! The one-image loop ([`crate::acs_loop::AcsLoop`]) and the attitude node hold one
//! [`StuckGyros`] each and call the same functions, so the two stay bit for bit the same.

use crate::determination::mekf::{self, Mekf, MekfConfig, StepInputs, UpdateOutcome};
use crate::linalg::{dot, Vec3};
use crate::tiles::Tile;

/// Reads in a row repeating a gyro's word before it can be held as stuck.
pub const STUCK_REPEATS: u8 = 15;
/// The filter's attitude corrections about a gyro's axis, summed over its run of repeated words,
/// from which the run is a stuck gyro, not a constant rate, rad (0.1°).
pub const STUCK_DRIFT_RAD: f32 = 1.745e-3;
/// The random walk of the gyro bias along a held gyro's axis, rad/s/√s.
pub const RATE_WALK_RADPS_PER_SQRT_S: f32 = 2.0e-2;
/// The run of a held gyro.
pub const HELD: u8 = u8::MAX;

/// A sum as stored: the upper half of its `f32` (truncated; see the [module docs](self)).
fn narrow(sum: f32) -> u16 {
    (sum.to_bits() >> 16) as u16
}

/// A stored sum as an `f32` (exact).
fn widen(stored: u16) -> f32 {
    f32::from_bits(u32::from(stored) << 16)
}

/// The stuck-gyro watch of at most `N` tiles (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct StuckGyros<const N: usize> {
    /// Each gyro's last word.
    last: [i16; N],
    /// Each gyro's corrections summed over its run, rad, as stored ([`narrow`]).
    drift: [u16; N],
    /// Each gyro's repeats in a row (0: its last word was new), or [`HELD`].
    repeats: [u8; N],
}

impl<const N: usize> Default for StuckGyros<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> StuckGyros<N> {
    /// Nothing seen yet.
    pub const fn new() -> Self {
        Self {
            last: [0; N],
            drift: [0; N],
            repeats: [0; N],
        }
    }

    /// Bit `i`: gyro `i` is held as stuck (telemetry).
    pub fn held_mask(&self) -> u32 {
        self.repeats
            .iter()
            .rev()
            .fold(0, |m, r| (m << 1) | u32::from(*r == HELD))
    }

    /// True if gyro `i` is held as stuck.
    pub fn is_held(&self, i: usize) -> bool {
        self.repeats.get(i) == Some(&HELD)
    }

    /// The filter's step ([`mekf::step`]) and the watch after it; returns the filter's outcome
    /// and true if a gyro read this step is held (reported as [`super::Faults::device_read`]).
    ///
    /// `gyro` holds the step's gyro words (bit `i` of `read`: tile `i`'s was read); `law_rate`,
    /// the gyros' rate, becomes the rate the laws use: with a gyro held, less the filter's gyro
    /// bias ([`Mekf::rate_body_radps`]; with none held the bias, ≤ 1e-4 rad/s, is left in).
    ///
    /// After the filter's step, each gyro read this step: a new word starts a new run; a
    /// repeated one lengthens its run and adds the step's attitude correction about its axis
    /// ([`Mekf::correction_rad`]; none on a start, without an estimate or while the filter is
    /// not settled) to the run's sum, and
    /// is held when both reach their limits (see the [module docs](self)); a held gyro's
    /// bias covariance walks ([`Mekf::inflate_gyro_bias`]) for the next step.
    #[cfg_attr(target_arch = "msp430", inline(always))]
    pub fn filter_step(
        &mut self,
        tiles: &[Tile],
        (gyro, read): (&[i16; N], u32),
        config: &MekfConfig,
        estimate: &mut Option<Mekf>,
        inputs: &StepInputs,
        law_rate: &mut Option<Vec3>,
    ) -> (UpdateOutcome, bool) {
        // a correction the filter expected (its attitude 1σ before the step past the limit: a
        // start converging, an eclipse's end) is not evidence against a gyro
        let settled = estimate
            .as_ref()
            .is_some_and(|e| e.attitude_within(STUCK_DRIFT_RAD));
        let outcome = mekf::step(config, estimate, inputs);
        let held = self.watch(
            tiles,
            (gyro, read),
            estimate.as_mut(),
            settled && !outcome.started,
            inputs.dt_s,
        );
        if let (true, Some(w), Some(e)) = (held, law_rate.as_mut(), estimate.as_ref()) {
            *w = e.rate_body_radps(w);
        }
        (outcome, held)
    }

    /// [`Self::filter_step`]'s watch after the filter's step (`count`: the step's correction
    /// counts towards the sums).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn watch(
        &mut self,
        tiles: &[Tile],
        (gyro, mut read): (&[i16; N], u32),
        mut estimate: Option<&mut Mekf>,
        count: bool,
        dt_s: f32,
    ) -> bool {
        let walk = RATE_WALK_RADPS_PER_SQRT_S * RATE_WALK_RADPS_PER_SQRT_S * dt_s;
        let mut any = false;
        for (t, (word, (last, (drift, repeats)))) in tiles.iter().zip(
            gyro.iter().zip(
                self.last
                    .iter_mut()
                    .zip(self.drift.iter_mut().zip(self.repeats.iter_mut())),
            ),
        ) {
            let here = read & 1 != 0;
            read >>= 1;
            if !here {
                continue;
            }
            let n = t.normal_body();
            if *last != *word {
                (*last, *drift, *repeats) = (*word, 0, 0);
            } else if *repeats != HELD {
                *repeats = core::cmp::min(*repeats + 1, STUCK_REPEATS);
                let mut sum = widen(*drift);
                if let (true, Some(e)) = (count, estimate.as_deref()) {
                    sum += dot(&e.correction_rad, &n);
                    *drift = narrow(sum);
                }
                if *repeats == STUCK_REPEATS && sum.abs() >= STUCK_DRIFT_RAD {
                    *repeats = HELD;
                }
            }
            if *repeats == HELD {
                any = true;
                if let Some(e) = estimate.as_deref_mut() {
                    e.inflate_gyro_bias(&n, walk);
                }
            }
        }
        any
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The watch's state for the flight's six tiles: 30 B.
    #[test]
    fn state_size() {
        assert_eq!(core::mem::size_of::<StuckGyros<6>>(), 30);
    }

    /// A stored sum is its `f32` truncated to 8 significant bits: never larger in magnitude,
    /// at most 2⁻⁷ of itself smaller; exact on the way back.
    #[test]
    fn stored_sum() {
        let mut x = 1.0e-9_f32;
        while x < 1.0 {
            for v in [x, -x] {
                let back = widen(narrow(v));
                assert!(
                    back.abs() <= v.abs() && v.abs() - back.abs() <= v.abs() / 128.0,
                    "{v}"
                );
                assert_eq!(widen(narrow(back)), back);
            }
            x *= 1.037;
        }
        assert_eq!(widen(narrow(0.0)), 0.0);
    }

    /// A run: held at the 15th repeat with the sum past the limit, released by a new word; a
    /// missed read neither extends nor breaks the run; without an estimate the sums stay.
    #[test]
    fn held_and_released() {
        let tiles = crate::tiles::CUBE_THESIS;
        let tiles = &tiles[..2];
        let mut w = StuckGyros::<2>::new();
        assert!(!w.watch(tiles, (&[5, 7], 0b11), None, true, 1.0));
        for k in 1..=20u8 {
            w.drift = [narrow(2.0 * STUCK_DRIFT_RAD), narrow(0.5 * STUCK_DRIFT_RAD)];
            // a missed read of tile 0 every fifth step
            let read = if k % 5 == 0 { 0b10 } else { 0b11 };
            let any = w.watch(tiles, (&[5, 7], read), None, true, 1.0);
            let reads0 = k - k / 5;
            assert_eq!(w.is_held(0), reads0 >= STUCK_REPEATS, "{k}");
            assert!(!w.is_held(1));
            assert_eq!(any, w.is_held(0) && read & 1 != 0);
        }
        assert!(w.is_held(0));
        assert!(!w.watch(tiles, (&[6, 7], 0b11), None, true, 1.0));
        assert!(!w.is_held(0));
        assert_eq!((w.repeats[0], w.drift[0]), (0, 0));
        assert_eq!(w.repeats[1], STUCK_REPEATS);
    }
}
