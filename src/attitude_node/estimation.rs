//! Step phase 4: the body field, rate and Sun direction from the tiles, the attitude by Wahba's
//! SVD from the Sun and field pairs (body, and TEME from the REF), filtered with the gyros
//! ([`crate::determination::complementary`]), and the node's copy of the clock.
//!
//! Attitudes are `v_body = A(q) · v_ref`, reference TEME of date ([`crate::attitude`]).

use super::sensing::Readings;
use super::{AttitudeNode, Faults};
use crate::acs_loop::StepReport;
use crate::attitude::Quaternion;
use crate::determination::complementary::{self, FilterConfig};
use crate::determination::least_squares::{angular_rate_body_cached, magnetic_field_body_cached};
use crate::determination::sun_sensor::sun_direction_body;
use crate::determination::{wahba_svd, Observation};
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
    /// Step phase 4: body field, rate and Sun direction from the tiles, attitude by Wahba's SVD
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
        let mut b_body_nt = self.field_body(readings);
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
        if let (Some(b), Some(m2)) = (&b_body_nt, self.last_field_nt2) {
            if !magnitude_within(b, m2, tolerance) {
                b_body_nt = None;
            }
        }
        let omega = self.rate_body(readings);
        faults.field = b_body_nt.is_none();
        faults.rate = omega.is_none();
        // without a REF, the last one's shadow: no Sun reading believed if it was the umbra
        let in_umbra = self.last_umbra;
        let sun_body = if in_umbra {
            None
        } else {
            self.sun_body(readings)
        };
        let (sun_teme, b_teme_nt) = reference.map_or((None, None), |r| (r.sun_teme, r.b_teme_nt));
        let measured = match (sun_body, b_body_nt, sun_teme, b_teme_nt) {
            (Some(s_b), Some(b_b), Some(s_r), Some(b_r)) => self.measure(&s_b, &s_r, &b_b, &b_r),
            _ => None,
        };
        // the node's copy of the clock: the REF's UTC, or one period on without a REF (a
        // REF after a gap of the link then follows by one period, no clock fault)
        let elapsed = match reference {
            Some(r) => self.clock.map(|t| r.utc.seconds_since_f32(&t)),
            None => None,
        };
        self.clock = match reference {
            Some(r) => Some(r.utc),
            None => self.clock.map(|t| t.add(self.period)),
        };
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
        let filter = FilterConfig {
            gain: self.config.filter_gain,
            max_propagation_s: self.config.max_propagation_s,
        };
        self.estimate = complementary::update(&filter, self.estimate, measured, omega, dt);
        let attitude = self.estimate.map(|e| e.attitude);
        faults.attitude = attitude.is_none();
        report.b_body_nt = b_body_nt;
        report.omega_body_radps = omega;
        report.sun_body = sun_body;
        report.measured_attitude = measured;
        report.attitude = attitude;
        dt
    }

    /// The attitude measured by Wahba's SVD from the Sun and field pairs (body, reference TEME),
    /// weighted as configured; out of line (its temporaries off the determination's frame).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn measure(
        &self,
        sun_body: &Vec3,
        sun_teme: &Vec3,
        b_body_nt: &Vec3,
        b_teme_nt: &Vec3,
    ) -> Option<Quaternion> {
        let (w_sun, w_mag) = self.config.weights;
        let sun = Observation {
            body: *sun_body,
            reference: *sun_teme,
            weight: w_sun,
        };
        let field = Observation {
            body: *b_body_nt,
            reference: *b_teme_nt,
            weight: w_mag,
        };
        wahba_svd::solve_pair(&sun, &field)
            .ok()
            .map(|s| s.quaternion)
    }

    /// The body field from the magnetometers (least squares, cached operator), nT. Out of line,
    /// as [`Self::rate_body`] and [`Self::sun_body`]: each converts its readings in its own frame.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn field_body(&mut self, readings: &Readings<N>) -> Option<Vec3> {
        let tiles = self.config.tiles.as_slice();
        let mag = readings.mag_nt();
        let mag = mag.get(..tiles.len())?;
        magnetic_field_body_cached(&mut self.mag_solver, tiles, mag).ok()
    }

    /// The body rate from the gyros (least squares, cached operator), rad/s.
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn rate_body(&mut self, readings: &Readings<N>) -> Option<Vec3> {
        let tiles = self.config.tiles.as_slice();
        let gyro = readings.gyro_radps();
        let gyro = gyro.get(..tiles.len())?;
        angular_rate_body_cached(&mut self.gyro_solver, tiles, gyro).ok()
    }

    /// The Sun direction in body axes from the lit tiles' sensors (unit).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    fn sun_body(&self, readings: &Readings<N>) -> Option<Vec3> {
        let tiles = self.config.tiles.as_slice();
        let sun = readings.sun_rad();
        sun_direction_body(tiles, sun.get(..tiles.len())?).ok()
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
