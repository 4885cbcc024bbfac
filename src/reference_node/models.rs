//! The reference node's models at a step's UTC: SGP4 position, the Sun (the thesis's model,
//! [`crate::env::sun::schlyter`], 46.9″ at most against JPL DE421), the cylindrical shadow
//! ([`crate::env::eclipse::cylindrical_illumination`]) and the IGRF field in TEME through GMST
//! (UT1 ≈ UTC), its coefficients interpolated to the step's date each step (not kept between
//! steps: on the MSP430 that saves `4·F` bytes of RAM for ≈ 40 000 cycles a step).

use super::ReferenceNode;
use crate::env::eclipse::cylindrical_illumination;
use crate::env::igrf::{Igrf, IgrfError};
use crate::env::sun::schlyter;
use crate::linalg::Vec3;
use crate::link::messages::Reference;
use crate::time::{gmst_rad, Epoch, Utc};

impl<const N: usize, const F: usize> ReferenceNode<'_, N, F> {
    /// Orbit, Sun, shadow and field models at `now`, into `r`; their failures returned as the
    /// fault word ([`crate::acs_loop::Faults::bits`]: orbit, model, extrapolated; built here
    /// from the three flags, not through the twelve of `Faults`).
    #[inline(never)]
    pub(super) fn models(&self, now: &Epoch<Utc>, r: &mut Reference) -> u16 {
        // the position and the Sun's direction only (not the velocity, the distance): kept
        // and moved whole, not through copies
        let r_teme_km = self
            .orbit
            .as_ref()
            .and_then(|o| o.propagate(now.span_since(&o.epoch())).ok())
            .map(|o| o.r_teme_km);
        let sun_teme = schlyter::sun(now).ok().map(|s| s.direction);
        let gmst = now.to_ut1(None).ok().map(|ut1| gmst_rad(&ut1));
        let illumination = match (&r_teme_km, &sun_teme) {
            (Some(r), Some(s)) => cylindrical_illumination(r, s).ok(),
            _ => None,
        };
        // the field model fails on its own (a date outside its tables) or at the point
        let mut extrapolated = false;
        let field = self.field_teme(now, r_teme_km.as_ref(), gmst, &mut extrapolated);
        let field_model_failed = matches!(
            field,
            Err(IgrfError::DateOutOfRange { .. }
                | IgrfError::DegreeAboveModel { .. }
                | IgrfError::CapacityTooSmall { .. })
        );
        let model = sun_teme.is_none() || field_model_failed || gmst.is_none();
        let orbit = r_teme_km.is_none();
        r.r_teme_km = r_teme_km;
        r.sun_teme = sun_teme;
        r.illumination = illumination;
        r.b_teme_nt = field.ok().flatten();
        fault_word(orbit, model, extrapolated)
    }

    /// The field in TEME at `r_teme_km` (`None` without a position or GMST) from the
    /// coefficients of the on-board model at `now`, built on this function's stack (out of
    /// line: the `4·F` bytes exist only while the field is evaluated).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    #[cfg_attr(target_arch = "msp430", optimize(size))]
    fn field_teme(
        &self,
        now: &Epoch<Utc>,
        r_teme_km: Option<&Vec3>,
        gmst: Option<f32>,
        extrapolated: &mut bool,
    ) -> Result<Option<Vec3>, IgrfError> {
        let mut slot: Option<Igrf<F>> = None;
        let field = Igrf::emplace_epoch(
            &mut slot,
            self.config.igrf_model.model(),
            now,
            self.config.igrf_degree,
        )?;
        *extrapolated = field.is_extrapolated();
        match (r_teme_km, gmst) {
            // finite by construction: SGP4's position (it refuses one that is not) and GMST
            (Some(r), Some(g)) => field.teme_of_finite(r, g).map(Some),
            _ => Ok(None),
        }
    }
}

/// The fault word of [`crate::acs_loop::Faults::bits`] with only the reference node's flags:
/// bit 2 `orbit`, 3 `model`, 10 `extrapolated`.
fn fault_word(orbit: bool, model: bool, extrapolated: bool) -> u16 {
    u16::from(orbit) << 2 | u16::from(model) << 3 | u16::from(extrapolated) << 10
}

#[cfg(test)]
mod tests {
    use super::fault_word;
    use crate::acs_loop::Faults;

    #[test]
    fn fault_word_is_that_of_faults() {
        for k in 0..8u8 {
            let (orbit, model, extrapolated) = (k & 1 != 0, k & 2 != 0, k & 4 != 0);
            let faults = Faults {
                orbit,
                model,
                extrapolated,
                ..Faults::default()
            };
            assert_eq!(fault_word(orbit, model, extrapolated), faults.bits());
        }
    }
}
