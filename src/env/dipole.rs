//! Centred (tilted) dipole geomagnetic field: the fallback model and sanity oracle of seed 002.
//!
//! # Source
//! Note 002 §5 (AtmoCube magnetorquer thesis): `B(r) = (M⊕/r³)[3(m̂·r̂)r̂ − m̂]` with
//! M⊕ = 7.96e15 T·m³, "tilted about 11°"; magnitude M⊕/r³ at the magnetic equator and 2M⊕/r³
//! at the magnetic poles. The tilted dipole of a given date is the degree-1 part of IGRF
//! (note 000 §3.5): its potential `V = R³ (g₁¹ x + h₁¹ y + g₁⁰ z)/r³` is the potential
//! `m·r/r³` of the moment
//!
//! ```text
//! m = R³ (g₁¹, h₁¹, g₁⁰)        (Earth-fixed, nT·km³; points to the southern hemisphere)
//! B = −∇(m·r/r³) = (3 (m·r̂) r̂ − m) / r³
//! ```
//!
//! # Symbols
//! | code | paper | meaning |
//! |---|---|---|
//! | `moment_nt_km3` | m = μ₀/(4π)·moment | dipole moment, nT·km³ (numerically equal to T·m³) |
//! | `r_hat` | r̂ | unit position |
//! | `g10`, `g11`, `h11` | g₁⁰, g₁¹, h₁¹ | IGRF degree-1 Gauss coefficients, nT |
//!
//! # Accuracy
//! [`Dipole::from_igrf`] equals IGRF truncated at degree 1 to f32 rounding (measured max
//! relative difference 1.1e-6, 0.05 nT at the surface, `cargo test --test dipole -- --nocapture`).
//! As a model of the real field it is coarse: against full IGRF-14 at 500 km (2025) the
//! direction differs by 8.7° on average and up to 35° (South Atlantic anomaly), the magnitude
//! by up to 73 % (measured, same command). Use it as a fallback
//! when IGRF is unavailable and as an order-of-magnitude oracle, not for attitude
//! determination.
//!
//! # Example
//! ```
//! use acs::env::dipole::Dipole;
//! use acs::linalg::Vec3;
//! // Seed 002's aligned dipole, 600 km above the equator: 2.343e-5 T (note 002 §5 table).
//! let b = Dipole::seed_002().field_nt(&Vec3::new(6978.0, 0.0, 0.0)).unwrap();
//! assert!((b.norm() - 23_430.0).abs() < 10.0);
//! ```

use crate::env::igrf::{Igrf, IgrfError, MIN_RADIUS_KM, REFERENCE_RADIUS_KM};
use crate::frames;
use crate::linalg::Vec3;

/// Seed 002's Earth dipole moment M⊕ = 7.96e15 T·m³, which is 7.96e15 nT·km³.
pub const SEED_002_MOMENT_NT_KM3: f32 = 7.96e15;

/// A centred dipole field, Earth-fixed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dipole {
    /// The moment m (μ₀/4π included), Earth-fixed, nT·km³.
    moment_nt_km3: Vec3,
}

#[cfg(feature = "defmt")]
impl defmt::Format for Dipole {
    fn format(&self, f: defmt::Formatter) {
        let m = &self.moment_nt_km3;
        defmt::write!(f, "Dipole {{ moment_nt_km3: [{}, {}, {}] }}", m.x, m.y, m.z);
    }
}

impl Dipole {
    /// A dipole of moment `moment_nt_km3` (μ₀/4π included, nT·km³ = T·m³), Earth-fixed.
    ///
    /// Errors: [`IgrfError::NotFinite`].
    pub fn new(moment_nt_km3: Vec3) -> Result<Self, IgrfError> {
        for (input, value) in [
            ("moment.x", moment_nt_km3.x),
            ("moment.y", moment_nt_km3.y),
            ("moment.z", moment_nt_km3.z),
        ] {
            if !value.is_finite() {
                return Err(IgrfError::NotFinite { input, value });
            }
        }
        Ok(Self { moment_nt_km3 })
    }

    /// Seed 002's dipole: M⊕ = 7.96e15 T·m³ along −z (aligned with the spin axis, pointing
    /// south, so the field points down in the northern hemisphere).
    pub fn seed_002() -> Self {
        Self {
            moment_nt_km3: Vec3::new(0.0, 0.0, -SEED_002_MOMENT_NT_KM3),
        }
    }

    /// The tilted dipole of IGRF at `igrf`'s date: `m = R³ (g₁¹, h₁¹, g₁⁰)`, identical to
    /// IGRF truncated at degree 1.
    pub fn from_igrf(igrf: &Igrf) -> Self {
        let (g10, g11, h11) = igrf.degree_one_nt();
        let r3 = REFERENCE_RADIUS_KM * REFERENCE_RADIUS_KM * REFERENCE_RADIUS_KM;
        Self {
            moment_nt_km3: Vec3::new(g11, h11, g10) * r3,
        }
    }

    /// The moment m, Earth-fixed, nT·km³.
    pub fn moment_nt_km3(&self) -> Vec3 {
        self.moment_nt_km3
    }

    /// Field at the position `r_km` in the frame of the moment (Earth-fixed for
    /// [`Dipole::from_igrf`]; seed 002's aligned dipole is the same in any frame sharing the
    /// z axis, e.g. TEME), nT: `B = (3 (m·r̂) r̂ − m) / r³`.
    ///
    /// Errors: [`IgrfError::NotFinite`], [`IgrfError::BelowSurface`] below
    /// [`MIN_RADIUS_KM`] (the same rule as IGRF).
    pub fn field_nt(&self, r_km: &Vec3) -> Result<Vec3, IgrfError> {
        for (input, value) in [("r_km.x", r_km.x), ("r_km.y", r_km.y), ("r_km.z", r_km.z)] {
            if !value.is_finite() {
                return Err(IgrfError::NotFinite { input, value });
            }
        }
        // Scale first so that no square overflows.
        let scale = crate::fmath::max(crate::fmath::max(r_km.x.abs(), r_km.y.abs()), r_km.z.abs());
        let unit_norm = if scale > 0.0 {
            (r_km / scale).norm()
        } else {
            0.0
        };
        let r = scale * unit_norm;
        if !(r >= MIN_RADIUS_KM) {
            return Err(IgrfError::BelowSurface { radius_km: r });
        }
        let r_hat = (r_km / scale) / unit_norm;
        let m = &self.moment_nt_km3;
        // 1/r³ in two steps (r³ overflows f32 beyond 7e12 km; m/r³ underflows to zero).
        let m_over_r3 = m / r / r / r;
        // B = (3 (m·r̂) r̂ − m) / r³
        Ok(r_hat * (3.0 * m_over_r3.dot(&r_hat)) - m_over_r3)
    }

    /// Field at the TEME position `r_teme_km` when the Greenwich mean sidereal angle is
    /// `gmst_rad` ([`crate::time::gmst_rad`]), as a TEME vector (nT).
    ///
    /// Errors: as [`Dipole::field_nt`], and [`IgrfError::NotFinite`] for `gmst_rad`.
    pub fn field_teme_nt(&self, r_teme_km: &Vec3, gmst_rad: f32) -> Result<Vec3, IgrfError> {
        if !gmst_rad.is_finite() {
            return Err(IgrfError::NotFinite {
                input: "gmst_rad",
                value: gmst_rad,
            });
        }
        let r_ecef_km = frames::teme_to_ecef_position(r_teme_km, gmst_rad);
        let b_ecef_nt = self.field_nt(&r_ecef_km)?;
        Ok(frames::ecef_to_teme_position(&b_ecef_nt, gmst_rad))
    }
}
