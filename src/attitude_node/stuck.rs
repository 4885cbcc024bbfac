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
//! - While held: every step reports [`super::Faults::device_read`]; the reading is kept, but the
//!   MEKF's gyro-bias covariance along the axis grows by ([`RATE_WALK_RADPS_PER_SQRT_S`],
//!   2e-2 rad/s/√s)²·Δt a step (the bias state then carries the body rate about that axis,
//!   driven by the Sun and the field), and the laws get the gyros' rate less the bias component
//!   along the axis ([`StuckGyros::filter_step`]).
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
//! worst pointing 0.891° during, 0.482° after (before: 86.0°, no report); +W (tile 2) from
//! 329 s, 0.607° / 0.486°; +V (tile 1) from 346 s, 0.593° / 0.505°. No gyro held (a counter on
//! the hold, not kept) in any of the eight nominal scenarios under either truth, nor in the
//! first 30 runs (seed 1) of the `tracking` (realistic, ideal), `detumble` (realistic, ideal),
//! `thesis-slew` (ideal) and `slew` campaigns (1.47 million steps).
//!
//! # State
//! 5 B a tile (30 B for the flight's six tiles; the prototype's `f32` sums and `u32` mask took
//! 48 B): the last word (`i16`), the run (`u8`, saturating at [`STUCK_REPEATS`]; [`HELD`] once
//! held: no mask) and the sum (`i16` in [`DRIFT_LSB_RAD`], saturating: ±1.9°); and the filter's
//! correction of the step, [`Mekf::correction_rad`] (12 B).
//!
//! The one-image loop ([`crate::acs_loop::AcsLoop`]) and the attitude node hold one
//! [`StuckGyros`] each and call the same functions, so the two stay bit for bit the same.

use crate::determination::mekf::{self, Mekf, MekfConfig, StepInputs, UpdateOutcome};
use crate::linalg::{dot, sub_scaled, Vec3};
use crate::tiles::Tile;

/// Reads in a row repeating a gyro's word before it can be held as stuck.
pub const STUCK_REPEATS: u8 = 15;
/// The filter's attitude corrections about a gyro's axis, summed over its run of repeated words,
/// from which the run is a stuck gyro, not a constant rate, rad (0.1°).
pub const STUCK_DRIFT_RAD: f32 = 1.745e-3;
/// The unit of the summed corrections, rad.
pub const DRIFT_LSB_RAD: f32 = 1.0e-6;
/// The random walk of the gyro bias along a held gyro's axis, rad/s/√s.
pub const RATE_WALK_RADPS_PER_SQRT_S: f32 = 2.0e-2;
/// The run of a held gyro.
pub const HELD: u8 = u8::MAX;

/// [`STUCK_DRIFT_RAD`] in [`DRIFT_LSB_RAD`].
const DRIFT_LIMIT: i16 = 1_745;

/// The stuck-gyro watch of at most `N` tiles (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct StuckGyros<const N: usize> {
    /// Each gyro's last word.
    last: [i16; N],
    /// Each gyro's corrections summed over its run, [`DRIFT_LSB_RAD`].
    drift: [i16; N],
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

    /// True if tile `i`'s gyro is held as stuck.
    pub fn is_held(&self, i: usize) -> bool {
        self.repeats.get(i) == Some(&HELD)
    }

    /// Counts this step's gyro words (`gyro`, bit `i` of `read`: tile `i`'s was read) against
    /// the last ones, holds and releases (see the [module docs](self)); true if a gyro read
    /// this step is held (reported as [`super::Faults::device_read`]).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn observe(&mut self, gyro: &[i16; N], read: u32) -> bool {
        let mut any = false;
        let mut read = read;
        for (word, (last, (drift, repeats))) in gyro.iter().zip(
            self.last
                .iter_mut()
                .zip(self.drift.iter_mut().zip(self.repeats.iter_mut())),
        ) {
            let here = read & 1 != 0;
            read >>= 1;
            if !here {
                continue;
            }
            if *last != *word {
                (*last, *drift, *repeats) = (*word, 0, 0);
            } else if *repeats != HELD {
                *repeats = core::cmp::min(*repeats + 1, STUCK_REPEATS);
                if *repeats == STUCK_REPEATS && drift.unsigned_abs() >= DRIFT_LIMIT as u16 {
                    *repeats = HELD;
                }
            }
            any |= *repeats == HELD;
        }
        any
    }

    /// The filter's step ([`mekf::step`]) and the watch after it; returns the filter's outcome.
    /// `law_rate`, the gyros' rate, becomes the rate the laws use: less the filter's gyro bias
    /// along each held gyro's axis (the rest of the bias, ≤ 1e-4 rad/s, is left in as with no
    /// gyro held).
    ///
    /// After the step, each repeating gyro's sum takes the step's attitude correction about its
    /// axis ([`Mekf::correction_rad`]; none on a start or without an estimate), and
    /// the held gyros' bias covariance walks ([`Mekf::inflate_gyro_bias`]) for the next step's
    /// propagation and updates.
    #[cfg_attr(target_arch = "msp430", inline(always))]
    pub fn filter_step(
        &mut self,
        tiles: &[Tile],
        config: &MekfConfig,
        estimate: &mut Option<Mekf>,
        inputs: &StepInputs,
        law_rate: &mut Option<Vec3>,
    ) -> UpdateOutcome {
        let outcome = mekf::step(config, estimate, inputs);
        self.after_step(
            tiles,
            estimate.as_mut(),
            outcome.started,
            inputs.dt_s,
            law_rate,
        );
        outcome
    }

    /// [`Self::filter_step`]'s watch after the filter's step.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn after_step(
        &mut self,
        tiles: &[Tile],
        mut estimate: Option<&mut Mekf>,
        started: bool,
        dt_s: f32,
        law_rate: &mut Option<Vec3>,
    ) {
        let walk = RATE_WALK_RADPS_PER_SQRT_S * RATE_WALK_RADPS_PER_SQRT_S * dt_s;
        for (t, (drift, repeats)) in tiles
            .iter()
            .zip(self.drift.iter_mut().zip(self.repeats.iter()))
        {
            let n = t.normal_body();
            // a new word zeroed the sum (`observe`); a held gyro's is not used
            match (estimate.as_deref_mut(), *repeats) {
                (Some(e), HELD) => {
                    if let Some(w) = law_rate {
                        *w = sub_scaled(w, &n, dot(&n, &e.gyro_bias_radps));
                    }
                    e.inflate_gyro_bias(&n, walk);
                }
                (Some(e), 1..) if !started => {
                    // `as` saturates (NaN: 0)
                    let c = dot(&e.correction_rad, &n) * (1.0 / DRIFT_LSB_RAD);
                    *drift = drift.saturating_add(c as i16);
                }
                _ => {}
            }
        }
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

    /// [`DRIFT_LIMIT`] is [`STUCK_DRIFT_RAD`] in [`DRIFT_LSB_RAD`].
    #[test]
    fn drift_limit() {
        assert_eq!(
            DRIFT_LIMIT,
            (STUCK_DRIFT_RAD / DRIFT_LSB_RAD).round() as i16
        );
    }

    /// A run: held at the 15th repeat with the sum past the limit, released by a new word; a
    /// missed read neither extends nor breaks the run.
    #[test]
    fn held_and_released() {
        let mut w = StuckGyros::<2>::new();
        assert!(!w.observe(&[5, 7], 0b11));
        for k in 1..=20u8 {
            w.drift = [DRIFT_LIMIT, DRIFT_LIMIT - 1];
            // a missed read of tile 0 every fifth step
            let read = if k % 5 == 0 { 0b10 } else { 0b11 };
            let any = w.observe(&[5, 7], read);
            let reads0 = k - k / 5;
            assert_eq!(w.is_held(0), reads0 >= STUCK_REPEATS, "{k}");
            assert!(!w.is_held(1));
            assert_eq!(any, w.is_held(0) && read & 1 != 0);
        }
        assert!(w.is_held(0));
        assert!(!w.observe(&[6, 7], 0b11));
        assert!(!w.is_held(0));
        assert_eq!((w.repeats[0], w.drift[0]), (0, 0));
        assert_eq!(w.repeats[1], STUCK_REPEATS);
    }
}
