//! Step phase 4: the body field, rate and Sun direction from the tiles; the attitude by TRIAD
//! ([`crate::determination::triad::pair_quaternion`]) from the Sun and field pairs (body, and
//! TEME from the REF), which starts the attitude filter ([`crate::determination::mekf`]: the
//! gyros propagate it, the Sun, with the REF's albedo, and the field update it); the node's
//! copy of the clock.
//!
//! Attitudes are `v_body = A(q) · v_ref`, reference TEME of date ([`crate::attitude`]).

use super::sensing::Readings;
use super::{AttitudeNode, Faults};
use crate::acs_loop::StepReport;
use crate::determination::least_squares::{self, solve_cached};
use crate::determination::mekf::{self, StepInputs, SunObservation};
use crate::determination::sun_sensor::{incidence_inv_cos2, sun_direction_body};
use crate::env::eclipse::Shadow;
use crate::linalg::{dot, Vec3};
use crate::link::messages::Reference;

/// The largest relative difference between the magnitude of the field the magnetometers give
/// and the model's that the loop accepts (a field further off is no measurement, reported as
/// [`Faults::field`]: a coil left on, a magnetometer's offset or scale gone wrong). The campaigns'
/// dispersed spacecraft stay within 5.3 % (60 runs, 596 000 steps: magnetometer offsets and
/// scale, the spacecraft's fields, the degree-8 model flown then); a coil left on at 0.2 A·m²
/// reaches 168 %.
pub const FIELD_MAGNITUDE_TOLERANCE: f32 = 0.1;

/// How fast the field's magnitude may change along the orbit, as a fraction a second: without a
/// REF the magnitude check widens from [`FIELD_MAGNITUDE_TOLERANCE`] by this much a second since
/// the last REF (a quarter of a low orbit, ≈ 1 400 s, halves or doubles `|B|`: 0.07 %/s on
/// average; a coil left on, +168 %, is still refused for the first 26 minutes).
pub const FIELD_MAGNITUDE_DRIFT_PER_S: f32 = 1.0e-3;

/// True if `|b|²` is within `(1 ± tolerance)²` of `model_nt2` (false for a NaN).
#[cfg_attr(target_arch = "msp430", inline(never))]
fn magnitude_within(b: &Vec3, model_nt2: f32, tolerance: f32) -> bool {
    let measured = dot(b, b);
    // a tolerance beyond 1 takes the lower bound to 0, not back up
    let (low, high) = (crate::fmath::max(1.0 - tolerance, 0.0), 1.0 + tolerance);
    measured >= low * low * model_nt2 && high * high * model_nt2 >= measured
}

impl<const N: usize> AttitudeNode<'_, N> {
    /// Step phase 4: body field, rate and Sun direction from the tiles, attitude by TRIAD
    /// (with the REF's Sun and field, if this step has one), filtered; returns the seconds the
    /// laws integrate.
    #[inline(never)]
    pub(super) fn determine(
        &mut self,
        readings: &Readings<N>,
        reference: Option<&Reference>,
        dt_s: f32,
        faults: &mut Faults,
        report: &mut StepReport,
    ) -> f32 {
        // the body field and the Sun straight into the report (on the MSP430 each copy of an
        // option is a `memcpy`); the filter's inputs borrow them
        report.b_body_nt = self.field_body(readings);
        // the model's |B|² and the tolerance: the REF's; without a REF the last one's, the
        // tolerance widening with the time since
        if let Some(r) = reference {
            self.last_field_nt2 = r.b_teme_nt.map(|m| dot(&m, &m));
            self.last_umbra = r.illumination.is_some_and(|i| i.shadow == Shadow::Umbra);
        }
        let tolerance = match reference {
            Some(_) => FIELD_MAGNITUDE_TOLERANCE,
            None => {
                let since_s = f32::from(self.without_reference) * self.config.control_period_s;
                FIELD_MAGNITUDE_TOLERANCE + FIELD_MAGNITUDE_DRIFT_PER_S * since_s
            }
        };
        if let (Some(b), Some(m2)) = (&report.b_body_nt, self.last_field_nt2) {
            if !magnitude_within(b, m2, tolerance) {
                report.b_body_nt = None;
            }
        }
        let omega = self.rate_body(readings);
        faults.field = report.b_body_nt.is_none();
        faults.rate = omega.is_none();
        // without a REF, the last one's shadow: no Sun reading believed if it was the umbra
        report.sun_body = None;
        let sun_variance = if self.last_umbra {
            0.0
        } else {
            self.sun_body(readings, &mut report.sun_body)
        };
        // the estimate's albedo before a clock fault below drops the estimate
        let albedo = self.estimate.as_ref().map_or(0.0, |e| e.albedo);
        // the node's copy of the clock: the REF's UTC, or one period on without a REF (a
        // REF after a gap of the link then follows by one period, no clock fault)
        // (in place: on the MSP430 each copy of an `Option<Epoch>` is a `memcpy`)
        let mut elapsed = None;
        match reference {
            Some(r) => {
                if let Some(t) = &self.clock {
                    elapsed = Some(r.utc.seconds_since_f32_small(t));
                }
                self.clock = Some(r.utc);
            }
            None => {
                if let Some(t) = &mut self.clock {
                    *t = t.add_nonnegative(self.period);
                }
            }
        }
        // A step is one control period: a gap of any other size or sign (a clock correction, a
        // reset) must not be integrated into the wheels (a +60 s correction once kicked a
        // tracking satellite to 1.8 °/s). It restarts the filter and the B-dot derivative,
        // reported, and the laws integrate one nominal period.
        let period = self.config.control_period_s;
        let dt = match elapsed {
            None => dt_s,
            Some(e) if e > 0.0 && period + period >= e => e,
            Some(_) => {
                faults.clock = true;
                self.estimate = None;
                self.bdot.reset();
                period
            }
        };
        // the filter's inputs built in place (on the MSP430 each copy of an option is a
        // `memcpy`)
        let mut inputs = StepInputs {
            omega_body_radps: omega,
            sun: None,
            field: None,
            mag_tiles: self.mag_solver.as_ref().map_or(0, |s| s.tiles()),
            gyro_tiles: self.gyro_solver.as_ref().map_or(0, |s| s.tiles()),
            dt_s: dt,
        };
        // the Sun as the sensors see it, with the albedo
        let sun_teme = reference.and_then(|r| r.sun_teme.as_ref().map(|s| (r, s)));
        if let (Some(body), Some((r, s))) = (&report.sun_body, sun_teme) {
            let fraction = r.illumination.map_or(1.0, |i| i.fraction);
            let (reference_teme, d_reference_d_albedo) =
                mekf::sun_reference(s, fraction, r.albedo_teme.as_ref(), albedo);
            inputs.sun = Some(SunObservation {
                body: *body,
                reference_teme,
                d_reference_d_albedo,
                variance_rad2: sun_variance,
            });
        }
        if let (Some(b), Some(m)) = (
            &report.b_body_nt,
            reference.and_then(|r| r.b_teme_nt.as_ref()),
        ) {
            inputs.field = Some((*b, *m));
        }
        // the gyros' own rate: a law's command must not depend on the filter's state (a REF
        // lost changes the estimate, not the commands of a mode without attitude); the bias
        // left in the rate (≤ 1e-4 rad/s) moves the tracking law's equilibrium by ζ·b/ω_n ≈
        // 0.01°; about a gyro held as stuck, the filter's bias is the rate
        // ([`crate::attitude_node::stuck`])
        report.omega_body_radps = omega;
        let (outcome, held) = self.stuck.filter_step(
            self.config.tiles.as_slice(),
            (&readings.gyro, readings.gyro_read),
            &self.config.filter,
            &mut self.estimate,
            &inputs,
            &mut report.omega_body_radps,
        );
        faults.device_read |= held;
        report.refused_measurements = outcome.refused;
        // written in place, then copied once (on the MSP430 each copy is a `memcpy`)
        report.attitude = None;
        report.attitude_sigma_rad = None;
        if let Some(e) = &self.estimate {
            report.attitude = Some(e.attitude);
            report.attitude_sigma_rad = Some(e.attitude_sigma_rad());
        }
        faults.attitude = report.attitude.is_none();
        report.measured_attitude = if outcome.started {
            report.attitude
        } else {
            None
        };
        dt
    }

    /// The body field from the magnetometers (`field`, nT) or the body rate from the gyros
    /// (rad/s): least squares with the cached operator. One copy of the solver's call for
    /// both (their readings differ in kind only); out of line, as [`Self::sun_body`]: it
    /// converts its readings in its own frame.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn tile_solve(&mut self, readings: &Readings<N>, field: bool) -> Option<Vec3> {
        let tiles = self.config.tiles.as_slice();
        let (mag, gyro);
        let (cache, r) = if field {
            mag = readings.mag_nt();
            (
                &mut self.mag_solver,
                least_squares::Readings::Field(mag.get(..tiles.len())?),
            )
        } else {
            gyro = readings.gyro_radps();
            (
                &mut self.gyro_solver,
                least_squares::Readings::Rate(gyro.get(..tiles.len())?),
            )
        };
        solve_cached(cache, tiles, r).ok()
    }

    /// The body field from the magnetometers (least squares, cached operator), nT.
    fn field_body(&mut self, readings: &Readings<N>) -> Option<Vec3> {
        self.tile_solve(readings, true)
    }

    /// The body rate from the gyros (least squares, cached operator), rad/s.
    fn rate_body(&mut self, readings: &Readings<N>) -> Option<Vec3> {
        self.tile_solve(readings, false)
    }

    /// The Sun direction in body axes from the lit tiles' sensors (unit) into `sun_body` (left
    /// as it is without one); returns the Sun observation's variance per axis, rad², from the
    /// lit sensors' incidence ([`mekf::sun_variance_rad2`]), 0 without a direction. One
    /// conversion of the sensors' angles for both.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn sun_body(&self, readings: &Readings<N>, sun_body: &mut Option<Vec3>) -> f32 {
        let tiles = self.config.tiles.as_slice();
        let sun = readings.sun_rad();
        let Some(lit) = sun.get(..tiles.len()) else {
            return 0.0;
        };
        let Ok(body) = sun_direction_body(tiles, lit) else {
            return 0.0;
        };
        let body = sun_body.insert(body);
        let (sum, n) = incidence_inv_cos2(tiles, lit, body);
        mekf::sun_variance_rad2(&self.config.filter, sum, n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Without a REF the tolerance widens past 1: the lower bound stays at 0 (it once came back
    /// up, `(1 − t)²`, and refused good fields after 15 minutes without a link).
    #[test]
    fn a_tolerance_beyond_one_takes_the_lower_bound_to_zero() {
        let b = Vec3::new(30_000.0, 0.0, 0.0);
        let m2 = 40_000.0f32 * 40_000.0;
        assert!(!magnitude_within(&b, m2, 0.1));
        assert!(magnitude_within(&b, m2, 0.3));
        for tolerance in [1.0, 1.5, 2.5] {
            assert!(magnitude_within(&b, m2, tolerance), "{tolerance}");
            assert!(magnitude_within(&(b * 0.01), m2, tolerance), "{tolerance}");
        }
        assert!(!magnitude_within(&(b * 10.0), m2, 1.5));
        assert!(!magnitude_within(&Vec3::new(f32::NAN, 0.0, 0.0), m2, 2.0));
    }
}
