//! Step phase 5c: the actuators. Wheel momentum allocated over the working wheels and each wheel
//! limited on its own; momentum dumping through the coils; the coils' dipole allocated over the
//! working coils and saturated keeping its direction. The safe state: coils off, wheels holding
//! their momentum.

use super::laws::reported;
use super::modes::ModeState;
use super::{AttitudeNode, Faults};
use crate::acs_loop::MAX_COILS;
use crate::control::magnetorquer::dumping_dipole_to_zero;
use crate::control::wheels::{Allocator, Wheel, WheelAllocation, WheelError};
use crate::hal::TileBus;
use crate::linalg::Vec3;

/// Allocates the body's `−held` (the actuators then hold `held`: the allocator gives them
/// `−W⁺L`) with the cached allocator, rebuilding it first if the working set of `actuators`
/// changed (a failure) or there is none yet. The negation here: one call for the wheels' and
/// the coils'.
fn cached_allocation<const N: usize>(
    cache: &mut Option<Allocator>,
    actuators: &[Wheel; N],
    held: &Vec3,
) -> Result<WheelAllocation<N>, WheelError> {
    if !cache.is_some_and(|a| a.is_for(actuators)) {
        *cache = None;
        *cache = Some(Allocator::new(actuators)?);
    }
    match cache {
        Some(a) => a.allocate_current(actuators, &crate::linalg::neg(held)),
        None => Err(WheelError::StaleAllocator),
    }
}

impl<const N: usize> AttitudeNode<'_, N> {
    /// Total commanded wheel momentum in body axes, kg·m²/s.
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    pub(super) fn wheels_body(&self) -> Vec3 {
        let mut acc = Vec3::zeros();
        for (i, (t, h)) in self
            .config
            .tiles
            .iter()
            .zip(self.wheel_h.iter())
            .enumerate()
        {
            if self.has_working_wheel(i, t) {
                acc += crate::linalg::scale(&t.normal_body(), *h);
            }
        }
        acc
    }

    /// Puts every actuator in the safe state: coils off, wheels hold their momentum.
    pub fn safe<B: TileBus>(&mut self, bus: &mut B) -> Faults {
        self.coils_off(bus, false)
    }

    /// Switches the coils off; with `check`, each coil is first checked from its read-back
    /// (step phase 1, [`super::health::ActuatorHealth::coils_off`]).
    pub(super) fn coils_off<B: TileBus>(&mut self, bus: &mut B, check: bool) -> Faults {
        self.health.coils_off(self.config.coils.len(), bus, check)
    }

    /// Step phase 5c: wheel momentum (the target, or the momentum in force re-sent: it stops
    /// failed tiles' wheels), momentum dumping through the coils outside detumble, coil dipole.
    /// `dipole` holds the law's dipole and receives the dipole commanded, `h_wheels` the
    /// wheels' total momentum now commanded (body): in place, in the step's report (on the
    /// MSP430 each copy of a vector is a `memcpy`).
    #[inline(never)]
    pub(super) fn actuate<B: TileBus>(
        &mut self,
        bus: &mut B,
        b_body_nt: Option<&Vec3>,
        (dipole, h_wheels): (&mut Vec3, &mut Vec3),
        h_target: Option<&Vec3>,
        faults: &mut Faults,
    ) {
        let h = h_target.copied().unwrap_or_else(|| self.wheels_body());
        faults.saturated |= self.command_wheels(bus, &h, faults);
        // a failed actuator is reported every step until the ground restores it
        faults.actuator |= self.health.any_failed();
        // what the wheels now hold: dumped through the coils and reported
        *h_wheels = self.wheels_body();
        if !matches!(self.mode, ModeState::Detumble)
            && self.config.dumping_gain_per_s > 0.0
            && self.have_wheels()
        {
            if let Some(b) = b_body_nt {
                let dump = dumping_dipole_to_zero(h_wheels, self.config.dumping_gain_per_s, b).ok();
                *dipole += reported(dump, faults);
            }
        }
        let m = *dipole;
        *dipole = self.command_coils(bus, &m, faults);
    }

    /// True if any tile has a working wheel.
    pub(super) fn have_wheels(&self) -> bool {
        self.config
            .tiles
            .iter()
            .enumerate()
            .any(|(i, t)| self.has_working_wheel(i, t))
    }

    /// Allocates a total body momentum to the wheels (the wheels hold `h`, the body the
    /// opposite) and commands them, each wheel limited on its own. Returns true if one was
    /// limited. A limit that is not positive commands nothing (reported in `faults.law`).
    fn command_wheels<B: TileBus>(&mut self, bus: &mut B, h: &Vec3, faults: &mut Faults) -> bool {
        // allocated without a limit, then each wheel limited on its own: a wheel at its limit
        // stays there and the others keep the momentum they were asked to hold (scaling the
        // whole allocation would take momentum from wheels the law never asked to change)
        let limit = self.config.wheel_limit_nms;
        if !(limit > 0.0) {
            // no wheel can hold anything: none is commanded (they hold), reported
            faults.law = true;
            return false;
        }
        // all zero (one `memset`): an entry beyond the tiles is not working, its axis and
        // limit never read
        let mut wheels = [Wheel {
            axis_body: Vec3::zeros(),
            limit: 0.0,
            working: false,
        }; N];
        for (i, (w, t)) in wheels.iter_mut().zip(self.config.tiles.iter()).enumerate() {
            *w = Wheel {
                axis_body: t.normal_body(),
                limit: f32::MAX,
                working: self.has_working_wheel(i, t),
            };
        }
        // the allocator gives the wheels −W⁺L: ask for the body momentum −h so they hold +h;
        // with no working wheel every wheel is commanded to stop; on any other refusal (a NaN
        // target...) no wheel is commanded: they hold the momentum in force, reported
        // by reference: on the MSP430 each copy of the allocation is a `memcpy`
        let allocation = cached_allocation(&mut self.wheel_allocator, &wheels, h);
        let alloc = match &allocation {
            Ok(a) => Some(a),
            Err(WheelError::NoWorkingWheel) => None,
            Err(_) => {
                faults.law = true;
                return false;
            }
        };
        let mut saturated = false;
        for (i, (cmd, (tile, wheel))) in self
            .wheel_h
            .iter_mut()
            .zip(self.config.tiles.iter().zip(wheels.iter()))
            .enumerate()
        {
            if !tile.equipment.reaction_wheel {
                continue;
            }
            let value = match &alloc {
                Some(a) if wheel.working => {
                    let h = a.wheel.get(i).copied().unwrap_or(0.0);
                    if crate::fmath::abs(h) > limit {
                        saturated = true;
                        libm::copysignf(limit, h)
                    } else {
                        h
                    }
                }
                _ => 0.0,
            };
            *cmd = value;
            let accepted = bus.set_wheel_momentum(i, value).is_ok();
            self.health.wheel_commanded(i, accepted);
            faults.actuator |= !accepted;
        }
        saturated
    }

    /// Allocates a body dipole to the coils (least squares over their axes, saturated keeping
    /// direction) and commands them; returns the dipole commanded.
    fn command_coils<B: TileBus>(&mut self, bus: &mut B, m: &Vec3, faults: &mut Faults) -> Vec3 {
        // all zero, as the wheels' in `command_wheels`
        let mut coils = [Wheel {
            axis_body: Vec3::zeros(),
            limit: 0.0,
            working: false,
        }; MAX_COILS];
        for (i, (c, cfg)) in coils.iter_mut().zip(self.config.coils.iter()).enumerate() {
            *c = Wheel {
                working: cfg.working && self.health.coil_in(i),
                ..*cfg
            };
        }
        // by reference, as in `command_wheels`
        let allocation = cached_allocation(&mut self.coil_allocator, &coils, m);
        let alloc = match &allocation {
            Ok(a) => a,
            Err(e) => {
                // the coils stay off (`safe`); a refused dipole is reported
                faults.law |= !matches!(e, WheelError::NoWorkingWheel);
                return Vec3::zeros();
            }
        };
        faults.saturated |= !(alloc.scale >= 1.0);
        let mut produced = Vec3::zeros();
        for (i, (value, coil)) in alloc.wheel.iter().zip(coils.iter()).enumerate() {
            if coil.working {
                let accepted = bus.set_dipole(i, *value).is_ok();
                self.health.coil_commanded(i, *value, accepted);
                faults.actuator |= !accepted;
                produced += crate::linalg::scale(&coil.axis_body, *value);
            }
        }
        produced
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 19 item 5, wheel saturation: a momentum one wheel cannot hold is limited on that
    /// wheel alone, and the wheels the request did not change keep their momentum (before, the
    /// whole allocation was scaled down, so they gave theirs up to the body).
    #[test]
    fn saturation_limits_the_wheel_not_the_store() {
        use crate::acs_loop::AcsConfig;
        use crate::hal::ErrorKind;
        struct Wheels([Option<f32>; 6]);
        impl TileBus for Wheels {
            fn read_sun(&mut self, _: usize) -> Result<Option<[i16; 2]>, ErrorKind> {
                Err(ErrorKind::Other)
            }
            fn read_magnetometer(&mut self, _: usize) -> Result<[i16; 2], ErrorKind> {
                Err(ErrorKind::Other)
            }
            fn read_gyro(&mut self, _: usize) -> Result<i16, ErrorKind> {
                Err(ErrorKind::Other)
            }
            fn set_wheel_momentum(&mut self, tile: usize, h_nms: f32) -> Result<(), ErrorKind> {
                let slot = self.0.get_mut(tile).ok_or(ErrorKind::Other)?;
                *slot = Some(h_nms);
                Ok(())
            }
            fn set_dipole(&mut self, _: usize, _: f32) -> Result<(), ErrorKind> {
                Ok(())
            }
            fn delay_us(&mut self, _: u32) {}
        }
        let config = &crate::flight::CONFIG;
        let limit = config.wheel_limit_nms;
        let mut acs = AttitudeNode::<{ crate::flight::TILES }>::new(config).unwrap();
        let mut bus = Wheels([None; 6]);
        let mut faults = Faults::default();
        // the two z wheels hold 0.8 of their limit each
        let h0 = Vec3::new(0.0, 0.0, 1.6 * limit);
        assert!(!acs.command_wheels(&mut bus, &h0, &mut faults));
        let before = bus.0;
        // three limits more about x, which has one wheel
        let h1 = h0 + Vec3::new(3.0 * limit, 0.0, 0.0);
        assert!(acs.command_wheels(&mut bus, &h1, &mut faults));
        assert!(!faults.law);
        for (i, tile) in config.tiles.iter().enumerate() {
            let n = tile.normal_body();
            if !tile.equipment.reaction_wheel {
                assert_eq!(bus.0[i], None);
            } else if n.z.abs() > 0.99 {
                assert_eq!(bus.0[i], before[i], "tile {i}: z wheel changed");
                assert!(bus.0[i].is_some_and(|h| (h.abs() - 0.8 * limit).abs() < 1e-9));
            } else if n.x.abs() > 0.99 {
                assert_eq!(bus.0[i].map(f32::abs), Some(limit), "tile {i}: x wheel");
            }
        }
        assert_eq!(acs.wheels_body().z, h0.z);
        // a negative limit (a NaN one is refused by `AttitudeNode::new`): nothing commanded, reported
        let bad = AcsConfig {
            wheel_limit_nms: -1.0,
            ..config.clone()
        };
        let mut acs = AttitudeNode::<{ crate::flight::TILES }>::new(&bad).unwrap();
        let mut bus = Wheels([None; 6]);
        let mut faults = Faults::default();
        assert!(!acs.command_wheels(&mut bus, &h0, &mut faults));
        assert!(faults.law);
        assert_eq!(bus.0, [None; 6]);
    }
}
