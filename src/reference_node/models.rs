//! The reference node's models at a step's UTC: SGP4 position, the Sun (the thesis's model,
//! [`crate::env::sun::schlyter`], 46.9″ at most against JPL DE421), the cylindrical shadow
//! ([`crate::env::eclipse::cylindrical_illumination`]) and the IGRF field in TEME through GMST
//! (UT1 ≈ UTC), its coefficients interpolated to the step's date each step (not kept between
//! steps: on the MSP430 that saves `4·F` bytes of RAM for ≈ 40 000 cycles a step).

use super::ReferenceNode;
use crate::acs_loop::Faults;
use crate::env::eclipse::cylindrical_illumination;
use crate::env::igrf::{Igrf, IgrfError};
use crate::env::sun::schlyter;
use crate::linalg::Vec3;
use crate::link::messages::Reference;
use crate::time::{gmst_rad, Epoch, Utc};

impl<const N: usize, const F: usize> ReferenceNode<'_, N, F> {
    /// Orbit, Sun, shadow and field models at `now`; their failures in `faults` (orbit, model,
    /// extrapolated).
    #[inline(never)]
    pub(super) fn models(&self, now: &Epoch<Utc>, faults: &mut Faults, r: &mut Reference) {
        // the position and the Sun's direction only (not the velocity, the distance): kept
        // and moved whole, not through copies
        let r_teme_km = self
            .orbit
            .as_ref()
            .and_then(|o| o.propagate(now.span_since(&o.epoch())).ok())
            .map(|o| o.r_teme_km);
        faults.orbit = r_teme_km.is_none();
        let sun_teme = schlyter::sun(now).ok().map(|s| s.direction);
        let gmst = now.to_ut1(None).ok().map(|ut1| gmst_rad(&ut1));
        let illumination = match (&r_teme_km, &sun_teme) {
            (Some(r), Some(s)) => cylindrical_illumination(r, s).ok(),
            _ => None,
        };
        // the field model fails on its own (a date outside its tables) or at the point
        let field = self.field_teme(now, r_teme_km.as_ref(), gmst, faults);
        let field_model_failed = matches!(
            field,
            Err(IgrfError::DateOutOfRange { .. }
                | IgrfError::DegreeAboveModel { .. }
                | IgrfError::CapacityTooSmall { .. })
        );
        faults.model = sun_teme.is_none() || field_model_failed || gmst.is_none();
        r.r_teme_km = r_teme_km;
        r.sun_teme = sun_teme;
        r.illumination = illumination;
        r.b_teme_nt = field.ok().flatten();
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
        faults: &mut Faults,
    ) -> Result<Option<Vec3>, IgrfError> {
        let mut slot: Option<Igrf<F>> = None;
        let field = Igrf::emplace_epoch(
            &mut slot,
            self.config.igrf_model.model(),
            now,
            self.config.igrf_degree,
        )?;
        faults.extrapolated = field.is_extrapolated();
        match (r_teme_km, gmst) {
            // finite by construction: SGP4's position (it refuses one that is not) and GMST
            (Some(r), Some(g)) => field.teme_of_finite(r, g).map(Some),
            _ => Ok(None),
        }
    }
}
