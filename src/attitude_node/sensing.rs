//! Step phase 3: reading the tiles' sensors, raw, and taking a tile out of service when its
//! devices keep failing (unless the whole bus is failing).

use super::health::has_twin;
use super::{AttitudeNode, Faults};
use crate::hal::TileBus;
use crate::linalg::Vec2;
use crate::tiles::{RawGyro, RawMagnetometer, RawSunAngles};

/// Consecutive read failures after which a tile is marked failed.
pub const FAILURES_TO_MARK_FAILED: u8 = 3;

/// Per-tile readings of one step, raw as the bus delivered them (the HAL's formats), with a bit
/// per tile for each device that gave one (`sun`: the sensor sees the Sun): 12 B a tile instead
/// of 32 B of converted options, and the conversions happen in the phase that uses them (on the
/// MSP430 the readings live under every phase of the step).
pub(super) struct Readings<const N: usize> {
    pub(super) sun: [[i16; 2]; N],
    pub(super) mag: [[i16; 2]; N],
    pub(super) gyro: [i16; N],
    pub(super) sun_seen: u32,
    pub(super) mag_read: u32,
    pub(super) gyro_read: u32,
}

/// A raw word at either end of the `i16` range (a failed read, and an actuator's read-back that
/// strikes: [`super::health`]).
pub(super) fn pinned(x: i16) -> bool {
    x == i16::MAX || x == i16::MIN
}

/// The telemetry code of a failed read of `device` (1 Sun sensor, 2 magnetometer, 3 gyro, 4
/// wheel): the device in the high nibble, the error's [`crate::hal::ErrorKind::code`] in the
/// low (`None`: a pinned word, out of range).
fn part_error(device: u8, e: Option<crate::hal::ErrorKind>) -> u8 {
    device << 4 | e.map_or(3, crate::hal::ErrorKind::code)
}

/// Bit `i` of `mask` (false beyond 31).
pub(super) fn bit(mask: u32, i: usize) -> bool {
    mask & super::health::mask(i) != 0
}

impl<const N: usize> Readings<N> {
    /// The Sun angles of the tiles that see the Sun, rad.
    pub(super) fn sun_rad(&self) -> [Option<crate::tiles::SunAngles>; N] {
        let mut out = [None; N];
        for (i, (o, [a, b])) in out.iter_mut().zip(self.sun.iter()).enumerate() {
            if bit(self.sun_seen, i) {
                *o = Some(RawSunAngles { a: *a, b: *b }.to_rad());
            }
        }
        out
    }

    /// The magnetometer readings, nT.
    pub(super) fn mag_nt(&self) -> [Option<Vec2>; N] {
        let mut out = [None; N];
        for (i, (o, [x, y])) in out.iter_mut().zip(self.mag.iter()).enumerate() {
            if bit(self.mag_read, i) {
                *o = Some(RawMagnetometer { x: *x, y: *y }.to_nt());
            }
        }
        out
    }

    /// The gyro readings, rad/s.
    pub(super) fn gyro_radps(&self) -> [Option<f32>; N] {
        let mut out = [None; N];
        for (i, (o, w)) in out.iter_mut().zip(self.gyro.iter()).enumerate() {
            if bit(self.gyro_read, i) {
                *o = Some(RawGyro(*w).to_radps());
            }
        }
        out
    }
}

impl<const N: usize> AttitudeNode<'_, N> {
    /// Step phase 3: reads every working tile (see the module docs), counting read failures. A
    /// tile is marked failed at [`FAILURES_TO_MARK_FAILED`] failures in a row only if some
    /// device answered in the previous step: when none does, the bus is failing, not the tiles
    /// (a bus-wide burst once took every tile out of service for good), and a sole tile left in
    /// service with sensors is never marked.
    #[inline(never)]
    pub(super) fn read_tiles<B: TileBus>(
        &mut self,
        bus: &mut B,
        faults: &mut Faults,
    ) -> Readings<N> {
        let mut r = Readings {
            sun: [[0; 2]; N],
            mag: [[0; 2]; N],
            gyro: [0; N],
            sun_seen: 0,
            mag_read: 0,
            gyro_read: 0,
        };
        let config = self.config;
        // a device answered this step
        let mut any_read = false;
        for (i, (tile, (sun, (mag, gyro)))) in config
            .tiles
            .iter()
            .zip(
                r.sun
                    .iter_mut()
                    .zip(r.mag.iter_mut().zip(r.gyro.iter_mut())),
            )
            .enumerate()
        {
            if !self.is_working(i) {
                continue;
            }
            let here = super::health::mask(i);
            let mut failed = false;
            // the last failed read's device and kind (0: none this step)
            let mut error = 0;
            // a word pinned at either end of the i16 range is no reading (a saturated device
            // or a stuck line: no physical Sun angle, field or rate reaches it): a failed read
            if tile.equipment.sun_sensor {
                match bus.read_sun(i) {
                    Ok(Some([a, b])) if !pinned(a) && !pinned(b) => {
                        *sun = [a, b];
                        r.sun_seen |= here;
                        any_read = true;
                    }
                    Ok(None) => any_read = true,
                    r => {
                        failed = true;
                        error = part_error(1, r.err());
                    }
                }
            }
            if tile.equipment.magnetometer {
                match bus.read_magnetometer(i) {
                    Ok([x, y]) if !pinned(x) && !pinned(y) => {
                        *mag = [x, y];
                        r.mag_read |= here;
                        any_read = true;
                    }
                    r => {
                        failed = true;
                        error = part_error(2, r.err());
                    }
                }
            }
            if tile.equipment.gyro {
                match bus.read_gyro(i) {
                    Ok(w) if !pinned(w) => {
                        *gyro = w;
                        r.gyro_read |= here;
                        any_read = true;
                    }
                    r => {
                        failed = true;
                        error = part_error(3, r.err());
                    }
                }
            }
            if tile.equipment.reaction_wheel && self.health.wheel_in(i) {
                let commanded = self.wheel_h.get(i).copied().unwrap_or(0.0);
                let read = bus.read_wheel_momentum(i);
                if let Err(e) = read {
                    error = part_error(4, Some(e));
                }
                let limit = config.wheel_limit_nms;
                if self.health.check_wheel(i, read, commanded, limit, faults)
                    && has_twin(&config.tiles, i, |j, t| self.has_working_wheel(j, t))
                {
                    self.health.take_wheel_out(i);
                }
            }
            if let (Some(last), true) = (self.last_error.get_mut(i), error != 0) {
                *last = error;
            }
            if let Some(count) = self.failures.get_mut(i) {
                if failed {
                    faults.device_read = true;
                    *count = count.saturating_add(1);
                    if *count >= FAILURES_TO_MARK_FAILED && self.bus_answered {
                        // out of service from this step on: its readings of this step too
                        self.failed |= here;
                        r.sun_seen &= !here;
                        r.mag_read &= !here;
                        r.gyro_read &= !here;
                    }
                } else {
                    *count = 0;
                }
            }
        }
        self.bus_answered = any_read;
        r
    }
}
