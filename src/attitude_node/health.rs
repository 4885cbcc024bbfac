//! The actuators' health from their read-back (issue #31, item 1): a wheel that does not follow
//! its command (stopped, running away, or refusing it) and a coil whose dipole is not the one
//! commanded (open, left on, or refusing) are failed and reported, until the ground returns them
//! to service; a failed wheel that has a twin on its axis leaves its allocation.
//!
//! Where the read-backs come from: the simulator and the processor-in-the-loop images give both
//! (`Simulator`, the PIL mailboxes); a board's drivers through [`crate::hal::bus::DeviceBus`]
//! ([`crate::hal::ReactionWheel::read_momentum_raw`],
//! [`crate::hal::Magnetorquer::read_dipole_raw`]). The flight image's drivers
//! ([`crate::hal::msp430::tile_bus`]) have none yet (the wheel controller's speed register and
//! the coils' current sense are not wired): on that image only refusals are checked.
//!
//! # The checks
//! - **Wheel** (read each step with the tiles, [`crate::hal::TileBus::read_wheel_momentum`]):
//!   a *strike* is a step in which its command was refused, or in which its momentum read back
//!   is more than [`WHEEL_LAG`] of the wheel limit from the momentum commanded and has come
//!   closer to it by less than [`WHEEL_PROGRESS`] of the limit since the step before (a stopped
//!   or running-away wheel; a word pinned at either end of the `i16` range is one too). A wheel
//!   slewing at its torque limit towards a new command is not a strike: the flight wheel's
//!   0.23 mN·m move 23 % of the limit in a one-second period, and the law never integrates more
//!   than the wheels deliver ([`crate::acs_loop::AcsConfig::wheel_torque_nm`]).
//! - **Coil** (read at the start of a step, before the coils are switched off,
//!   [`crate::hal::TileBus::read_coil_dipole`]: the dipole of the previous step's command,
//!   settled for a period against its 0.39 ms time constant): a strike is a read-back more than
//!   [`COIL_TOLERANCE_AM2`] + [`COIL_TOLERANCE_FRACTION`] × |command| from the command (the
//!   tolerance holds the flight coil's 3 % 1σ scale factor at 5σ and its 8-bit PWM quantum),
//!   or a refused command. A step whose command and read-back are both within
//!   [`COIL_TOLERANCE_AM2`] of zero says nothing of an open coil and leaves the count alone.
//! - [`STRIKES_TO_FAIL`] (3) strikes in a row and the actuator is failed: from then on every
//!   step reports [`Faults::actuator`] until the ground returns it to service. A failed wheel
//!   leaves its allocation if another working wheel shares its axis ([`has_twin`]: the others
//!   take its share, and it is commanded to rest); the sole wheel of an axis (the flight cube's
//!   on U) and a coil (each of the three is alone on its axis) stay in, reported: taking one
//!   out would give up its axis for good, also after a transient fault clears. The ground takes
//!   an actuator out with `MARK_FAILED`. A passing check clears the count.
//! - A read-back that fails is reported ([`Faults::device_read`]) and checks nothing that step;
//!   a device without read-back (`Ok(None)`) is never checked.
//! - The ground's `RESTORE` returns a wheel to service with its tile, and a coil by its index
//!   ([`crate::uplink`]); `MARK_FAILED` of a coil fails it and takes it out.
//!
//! The one-image loop ([`crate::acs_loop::AcsLoop`]) and the attitude node hold one
//! [`ActuatorHealth`] each and call the same checks, so the two stay bit for bit the same.

use super::sensing::pinned;
use super::Faults;
use crate::acs_loop::MAX_COILS;
use crate::hal::{ErrorKind, TileBus};
use crate::tiles::{Tile, COIL_LSB_AM2, WHEEL_LSB_NMS};

/// Strikes in a row that fail an actuator.
pub const STRIKES_TO_FAIL: u8 = 3;
/// A wheel further than this fraction of its limit from its command is lagging.
pub const WHEEL_LAG: f32 = 0.2;
/// A lagging wheel that comes closer to its command by less than this fraction of its limit in
/// a step is not following it.
pub const WHEEL_PROGRESS: f32 = 0.05;
/// A coil's read-back may differ from its command by this much, A·m² (0.5 % of the flight
/// limit, 1.3 quanta of its 8-bit PWM)…
pub const COIL_TOLERANCE_AM2: f32 = 0.001;
/// …plus this fraction of the command.
pub const COIL_TOLERANCE_FRACTION: f32 = 0.15;

/// Bit `i` as a mask (0 beyond 31). Out of line on the MSP430 (a 32-bit shift is a helper
/// call there): one copy for the node's tile, wheel and coil masks.
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(super) fn mask(i: usize) -> u32 {
    1u32.checked_shl(i as u32).unwrap_or(0)
}

/// The cosine above which two wheels share an axis (8.1°).
const TWIN_COSINE: f32 = 0.99;

/// True if a tile other than `tile` with a wheel `working(j, tile_j)` has its wheel on the same
/// axis line (parallel or opposite: the flight cube's +V and −V).
pub fn has_twin(tiles: &[Tile], tile: usize, working: impl Fn(usize, &Tile) -> bool) -> bool {
    let Some(n) = tiles.get(tile).map(Tile::normal_body) else {
        return false;
    };
    tiles.iter().enumerate().any(|(j, t)| {
        j != tile
            && working(j, t)
            && crate::fmath::abs(crate::linalg::dot(&t.normal_body(), &n)) > TWIN_COSINE
    })
}

/// The wheels' and coils' health for at most `N` ≤ 32 tiles (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct ActuatorHealth<const N: usize> {
    /// Bit `i`: tile `i`'s wheel is failed; bit `24 + c`: coil `c` is.
    failed: u32,
    /// Bit `i`: tile `i`'s wheel is out of the allocation; bit `24 + c`: coil `c` is.
    out: u32,
    /// Bit `i`: tile `i`'s wheel refused its last command; bit `24 + c`: coil `c` did.
    refused: u32,
    /// Strikes in a row of each wheel.
    wheel_strikes: [u8; N],
    /// Strikes in a row of each coil.
    coil_strikes: [u8; MAX_COILS],
    /// Each wheel's read-back at its last check ([`UNKNOWN`]: none).
    wheel_read: [i16; N],
    /// Each coil's last accepted command, A·m² (the coils-off of every step included).
    coil_am2: [f32; MAX_COILS],
}

/// A word no check compares with (no read-back yet): `i16::MIN`, which a valid read-back never
/// is.
const UNKNOWN: i16 = i16::MIN;

impl<const N: usize> Default for ActuatorHealth<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> ActuatorHealth<N> {
    /// Every actuator in its allocation, nothing known yet.
    pub const fn new() -> Self {
        Self {
            failed: 0,
            out: 0,
            refused: 0,
            wheel_strikes: [0; N],
            coil_strikes: [0; MAX_COILS],
            wheel_read: [UNKNOWN; N],
            coil_am2: [0.0; MAX_COILS],
        }
    }

    /// The actuators' failed and out-of-allocation masks: bit `i` tile `i`'s wheel, bit
    /// `24 + c` coil `c` (telemetry).
    pub fn masks(&self) -> (u32, u32) {
        (self.failed, self.out)
    }

    /// Each tile's wheel read-back word at its last check (1e-7 kg·m²/s,
    /// [`crate::tiles::WHEEL_LSB_NMS`]); `i16::MIN` if none yet.
    pub fn wheel_reads(&self) -> &[i16; N] {
        &self.wheel_read
    }

    /// True if tile `tile`'s wheel is in its allocation.
    pub fn wheel_in(&self, tile: usize) -> bool {
        self.out & mask(tile) == 0
    }

    /// True if coil `coil` is in its allocation.
    pub fn coil_in(&self, coil: usize) -> bool {
        self.out & mask(24 + coil) == 0
    }

    /// True if tile `tile`'s wheel is failed (in its allocation or not).
    pub fn wheel_failed(&self, tile: usize) -> bool {
        self.failed & mask(tile) != 0
    }

    /// True if coil `coil` is failed (in its allocation or not).
    pub fn coil_failed(&self, coil: usize) -> bool {
        self.failed & mask(24 + coil) != 0
    }

    /// True if any actuator is failed.
    pub fn any_failed(&self) -> bool {
        self.failed != 0
    }

    /// Takes tile `tile`'s (failed) wheel out of its allocation.
    pub fn take_wheel_out(&mut self, tile: usize) {
        self.out |= mask(tile);
    }

    /// Returns tile `tile`'s wheel to service (with the tile, [`crate::uplink`]).
    pub fn restore_wheel(&mut self, tile: usize) {
        self.out &= !mask(tile);
        self.failed &= !mask(tile);
        if let Some(s) = self.wheel_strikes.get_mut(tile) {
            *s = 0;
        }
    }

    /// Fails coil `coil` of the `coils` the satellite has and takes it out of its allocation
    /// (`failed`, the ground's `MARK_FAILED`), or returns it to service (`RESTORE`); false
    /// (nothing changed) if there is no such coil.
    pub fn set_coil_failed(&mut self, coil: usize, failed: bool, coils: usize) -> bool {
        if coil >= coils {
            return false;
        }
        let bit = mask(24 + coil);
        if failed {
            self.out |= bit;
            self.failed |= bit;
        } else {
            self.out &= !bit;
            self.failed &= !bit;
        }
        if let Some(s) = self.coil_strikes.get_mut(coil) {
            *s = 0;
        }
        true
    }

    /// Records that tile `tile`'s wheel accepted (`true`) or refused its command this step.
    pub fn wheel_commanded(&mut self, tile: usize, accepted: bool) {
        self.set_refused(mask(tile), !accepted);
    }

    /// Records coil `coil`'s command `m_am2` and whether it was accepted.
    pub fn coil_commanded(&mut self, coil: usize, m_am2: f32, accepted: bool) {
        self.set_refused(mask(24 + coil), !accepted);
        if let Some(m) = self.coil_am2.get_mut(coil) {
            // after a refusal the coil's state is not known: the refusal is the strike
            *m = m_am2;
        }
    }

    fn set_refused(&mut self, bit: u32, refused: bool) {
        if refused {
            self.refused |= bit;
        } else {
            self.refused &= !bit;
        }
    }

    /// Checks tile `tile`'s wheel (in its allocation) from its read-back `read`, its command
    /// in force `commanded_nms` and the wheels' limit `limit_nms`; true if this check failed it
    /// (the caller decides whether it leaves its allocation, [`has_twin`]).
    pub fn check_wheel(
        &mut self,
        tile: usize,
        read: Result<Option<i16>, ErrorKind>,
        commanded_nms: f32,
        limit_nms: f32,
        faults: &mut Faults,
    ) -> bool {
        let refused = self.refused & mask(tile) != 0;
        let (Some(strikes), Some(last)) = (
            self.wheel_strikes.get_mut(tile),
            self.wheel_read.get_mut(tile),
        ) else {
            return false;
        };
        let strike = match read {
            Ok(None) => refused,
            Err(_) => {
                faults.device_read = true;
                return false;
            }
            Ok(Some(w)) => {
                // how far from the command in force now, and how much closer than at the last
                // read (none: no progress)
                let lag = |w: i16| crate::fmath::abs(commanded_nms - f32::from(w) * WHEEL_LSB_NMS);
                let now = lag(w);
                let closer = if *last == UNKNOWN {
                    0.0
                } else {
                    lag(*last) - now
                };
                *last = w;
                let lagging =
                    now > WHEEL_LAG * limit_nms && !(closer >= WHEEL_PROGRESS * limit_nms);
                refused || pinned(w) || lagging
            }
        };
        if strike {
            *strikes = strikes.saturating_add(1);
            let n = *strikes;
            self.fail(n, mask(tile))
        } else {
            *strikes = 0;
            false
        }
    }

    /// Fails actuator bit `bit` at [`STRIKES_TO_FAIL`] strikes; true if it was not failed.
    fn fail(&mut self, strikes: u8, bit: u32) -> bool {
        let newly = strikes >= STRIKES_TO_FAIL && self.failed & bit == 0;
        if newly {
            self.failed |= bit;
        }
        newly
    }

    /// Checks coil `coil` (in its allocation) from its read-back `read` at the start of a step;
    /// true if this check failed it.
    pub fn check_coil(
        &mut self,
        coil: usize,
        read: Result<Option<i16>, ErrorKind>,
        faults: &mut Faults,
    ) -> bool {
        let refused = self.refused & mask(24 + coil) != 0;
        let (Some(strikes), Some(&m_cmd)) =
            (self.coil_strikes.get_mut(coil), self.coil_am2.get(coil))
        else {
            return false;
        };
        let strike = match read {
            Ok(None) => Some(refused),
            Err(_) => {
                faults.device_read = true;
                return false;
            }
            Ok(Some(w)) => {
                let m_read = f32::from(w) * COIL_LSB_AM2;
                let tolerance =
                    COIL_TOLERANCE_AM2 + COIL_TOLERANCE_FRACTION * crate::fmath::abs(m_cmd);
                if refused || pinned(w) || crate::fmath::abs(m_cmd - m_read) > tolerance {
                    Some(true)
                } else if crate::fmath::abs(m_cmd) > COIL_TOLERANCE_AM2
                    || crate::fmath::abs(m_read) > COIL_TOLERANCE_AM2
                {
                    Some(false)
                } else {
                    // nothing commanded, nothing read: says nothing of an open coil
                    None
                }
            }
        };
        match strike {
            Some(true) => {
                *strikes = strikes.saturating_add(1);
                let n = *strikes;
                self.fail(n, mask(24 + coil))
            }
            Some(false) => {
                *strikes = 0;
                false
            }
            None => false,
        }
    }

    /// Switches the `coils` coils off through `bus`; with `check`, each coil in its allocation
    /// is first checked from its read-back, the dipole of the previous step's command (step
    /// phase 1). The coils' commands that failed are reported in the faults returned.
    pub fn coils_off<B: TileBus>(&mut self, coils: usize, bus: &mut B, check: bool) -> Faults {
        let mut faults = Faults::default();
        for i in 0..coils {
            if check && self.coil_in(i) {
                self.check_coil(i, bus.read_coil_dipole(i), &mut faults);
            }
            let accepted = bus.set_dipole(i, 0.0).is_ok();
            self.coil_commanded(i, 0.0, accepted);
            faults.actuator |= !accepted;
        }
        faults
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tiles::cube_thesis;

    const LIMIT: f32 = 1.0e-3;

    fn word(h_nms: f32) -> Result<Option<i16>, ErrorKind> {
        Ok(Some((h_nms / WHEEL_LSB_NMS) as i16))
    }

    /// A wheel that follows, slews towards its command at its torque limit, or lags once is
    /// never failed; one that stays more than 20 % of its limit away and does not come 5 %
    /// closer a step is failed at the third such step; a passing check clears the count.
    #[test]
    fn wheel_lagging_three_steps_is_failed() {
        let mut h = ActuatorHealth::<2>::new();
        let mut f = Faults::default();
        // following, then a step command slewed at 23 % of the limit a step
        assert!(!h.check_wheel(0, word(1e-4), 1e-4, LIMIT, &mut f));
        for k in 0..4 {
            let read = 1e-4 + 2.3e-4 * k as f32;
            assert!(!h.check_wheel(0, word(read), 1e-3, LIMIT, &mut f), "{k}");
        }
        // stopped: 0 read against 8e-4 commanded
        assert!(!h.check_wheel(0, word(0.0), 8e-4, LIMIT, &mut f));
        assert!(!h.check_wheel(0, word(0.0), 8e-4, LIMIT, &mut f));
        assert!(h.check_wheel(0, word(0.0), 8e-4, LIMIT, &mut f));
        assert!(h.wheel_failed(0) && h.any_failed() && h.wheel_in(0));
        // failed once: not again
        assert!(!h.check_wheel(0, word(0.0), 8e-4, LIMIT, &mut f));
        h.take_wheel_out(0);
        assert!(!h.wheel_in(0));
        h.restore_wheel(0);
        assert!(h.wheel_in(0) && !h.any_failed());
        // two lagging steps, then one that follows: the count starts again
        assert!(!h.check_wheel(1, word(0.0), 8e-4, LIMIT, &mut f));
        assert!(!h.check_wheel(1, word(0.0), 8e-4, LIMIT, &mut f));
        assert!(!h.check_wheel(1, word(8e-4), 8e-4, LIMIT, &mut f));
        assert!(!h.check_wheel(1, word(0.0), 8e-4, LIMIT, &mut f));
        assert!(!h.check_wheel(1, word(0.0), 8e-4, LIMIT, &mut f));
        assert!(!h.wheel_failed(1));
        assert!(!f.device_read);
    }

    /// Refusals strike with or without a read-back; a failed read-back is reported and checks
    /// nothing (the refusal waits for the next read); a word at the range's end strikes.
    #[test]
    fn refusals_failed_reads_and_pinned_words() {
        let mut h = ActuatorHealth::<1>::new();
        let mut f = Faults::default();
        for k in 0..3 {
            h.wheel_commanded(0, false);
            if k == 1 {
                assert!(!h.check_wheel(0, Err(ErrorKind::Bus), 0.0, LIMIT, &mut f));
                assert!(f.device_read);
            }
            assert_eq!(
                h.check_wheel(0, Ok(None), 0.0, LIMIT, &mut f),
                k == 2,
                "{k}"
            );
        }
        let mut h = ActuatorHealth::<1>::new();
        for _ in 0..2 {
            assert!(!h.check_wheel(0, Ok(Some(i16::MAX)), 0.0, LIMIT, &mut f));
        }
        assert!(h.check_wheel(0, Ok(Some(i16::MIN)), 0.0, LIMIT, &mut f));
    }

    fn dipole(m_am2: f32) -> Result<Option<i16>, ErrorKind> {
        Ok(Some((m_am2 / COIL_LSB_AM2) as i16))
    }

    /// A coil within its tolerance (0.001 A·m² + 15 %) passes; an open or left-on coil strikes
    /// when the command or the read-back says something; steps with neither leave the count.
    #[test]
    fn coil_open_and_left_on() {
        let mut h = ActuatorHealth::<1>::new();
        let mut f = Faults::default();
        // 14 % scale error and a quantum: passes
        h.coil_commanded(0, 0.1, true);
        assert!(!h.check_coil(0, dipole(0.1 * 1.14 + 0.0008), &mut f));
        // open: 0.01 commanded, nothing read; steps with nothing commanded in between
        for k in 0..3 {
            h.coil_commanded(0, 0.01, true);
            assert_eq!(h.check_coil(0, dipole(0.0), &mut f), k == 2, "{k}");
            h.coil_commanded(0, 0.0, true);
            assert!(!h.check_coil(0, dipole(0.0), &mut f));
        }
        assert!(h.coil_failed(0) && h.coil_in(0));
        assert!(h.set_coil_failed(0, false, 1));
        assert!(!h.any_failed());
        // left on: 0.2 read with nothing commanded
        for k in 0..3 {
            h.coil_commanded(0, 0.0, true);
            assert_eq!(h.check_coil(0, dipole(0.2), &mut f), k == 2, "{k}");
        }
        // the ground's MARK_FAILED takes it out
        assert!(h.set_coil_failed(0, true, 1));
        assert!(!h.set_coil_failed(1, true, 1));
        assert!(!h.coil_in(0) && h.coil_failed(0));
    }

    /// On the thesis cube the −U wheel (tile 3) has no twin; +V/−V and +W/−W are twins; a
    /// twin out of service does not count.
    #[test]
    fn twins_on_the_thesis_cube() {
        let tiles = cube_thesis();
        let all = |_: usize, t: &Tile| t.equipment.reaction_wheel;
        assert!(!has_twin(&tiles, 3, all));
        assert!(has_twin(&tiles, 1, all) && has_twin(&tiles, 4, all));
        assert!(has_twin(&tiles, 2, all) && has_twin(&tiles, 5, all));
        assert!(!has_twin(&tiles, 1, |j, t| all(j, t) && j != 4));
        assert!(!has_twin(&tiles, 9, all));
    }
}
