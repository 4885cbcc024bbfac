//! Attitude by pseudoinverse, `Aᵀ = G⁺·F`: the thesis's generalised attitude solver (seed 000
//! §8.4, eqs. 8.27–8.31; note 000 §3.8 e), with the thesis's Sun-sensor equation (§8.1,
//! eqs. 8.1–8.2) — the "thesis-compatible" mode of note 000 §7 item 1.
//!
//! **Not physical.** Eq. 8.1 turns each lit tile's sensor angles into that tile's normal in the
//! reference frame, `α_m = RA − a_m`, `β_m = Dec − b_m`, which does not follow from rotation
//! geometry (a single Sun direction cannot fix a face normal). The chapter-12 test data were
//! generated with the inverse formula, so they are self-consistent; this module exists to
//! reproduce them. Flight code uses [`super::sun_sensor`] and [`super::wahba_svd`].
//!
//! # Algorithm
//! Rows, one per lit tile with a working Sun sensor (eqs. 8.1–8.4):
//! ```text
//! F row: ẑ_m (the tile normal in the body frame, row 3 of A_m)
//! G row: (cos α_m cos β_m, sin α_m cos β_m, sin β_m),  α_m = RA − a_m,  β_m = Dec − b_m
//! ```
//! and one magnetic row `B_uvw/|B_uvw|`, `B_ijk/|B_ijk|` (the normalisation is needed to
//! reproduce Test 2, note 000 §3.8 e). Then `F = G·Aᵀ`, so `Aᵀ = G⁺·F` (eq. 8.28) by least
//! squares ([`crate::linalg::lsq`], SVD threshold [`super::least_squares::RANK_REL_TOL`]); with
//! exactly two rows, `f₁ × f₂` and `g₁ × g₂` (not normalised, eq. 8.30) are appended first.
//! The result is **not** re-orthogonalised (that is why the thesis's Test 2 `A_eo` has a
//! diagonal of 1.0024); [`crate::attitude::Dcm::orthonormalize`] does it.
//!
//! | symbol | name |
//! |---|---|
//! | `a_m, b_m` | `readings[m]` ([`SunAngles`], rad) |
//! | `RA, Dec` | `sun_right_ascension_rad`, `sun_declination_rad` (of the Sun model) |
//! | `B_uvw`, `B_ijk` | `magnetic.body`, `magnetic.reference` |
//!
//! # Accuracy
//! Reproduces the thesis's Test 1 and Test 2 (note 000 §4.3–4.4) to 1e-5 on every entry of
//! `A_eo` and `A − A_obtained` (`cargo test --test determination thesis -- --nocapture`).
//! Tests 3 and 4 cannot be reproduced from the printed inputs (note 000 §4.5–4.6).

use super::{DeterminationError, Observation};
use crate::fmath;
use crate::linalg::lsq::QrLeastSquares;
use crate::linalg::{Mat3, Vec3};
use crate::tiles::{SunAngles, Tile};

use super::least_squares::RANK_REL_TOL;

/// The tile normal in the reference frame by the thesis's eqs. 8.1–8.2 (not geometry, see the
/// module docs): `α = RA − a`, `β = Dec − b`, `(cos α cos β, sin α cos β, sin β)`.
pub fn thesis_normal_reference(
    sun_right_ascension_rad: f32,
    sun_declination_rad: f32,
    angles: &SunAngles,
) -> Vec3 {
    let alpha = sun_right_ascension_rad - angles.a_rad;
    let beta = sun_declination_rad - angles.b_rad;
    let (sa, ca) = fmath::sincos(alpha);
    let (sb, cb) = fmath::sincos(beta);
    Vec3::new(ca * cb, sa * cb, sb)
}

/// The raw (not orthogonalised) attitude `A = (G⁺·F)ᵀ` of the thesis's solver, `v_body ≈ A·v_ref`
/// ([`crate::attitude`]). `readings` has one entry per tile (`Some` = lit); `magnetic` is the
/// optional field pair (body from [`super::least_squares::magnetic_field_body`], reference from
/// the field model; any units, both are normalised; its weight is ignored).
pub fn solve(
    tiles: &[Tile],
    readings: &[Option<SunAngles>],
    sun_right_ascension_rad: f32,
    sun_declination_rad: f32,
    magnetic: Option<&Observation>,
) -> Result<Mat3, DeterminationError> {
    if tiles.len() != readings.len() {
        return Err(DeterminationError::LengthMismatch {
            tiles: tiles.len(),
            readings: readings.len(),
        });
    }
    if !(sun_right_ascension_rad.is_finite() && sun_declination_rad.is_finite()) {
        return Err(DeterminationError::NonFinite { index: 0 });
    }
    let mut ls = QrLeastSquares::<3>::new();
    // The first two (g, f) pairs, for the N = 2 cross-product row.
    let mut first: [Option<(Vec3, Vec3)>; 2] = [None, None];
    let mut count = 0usize;
    let mut add =
        |g: Vec3, f: Vec3, ls: &mut QrLeastSquares<3>| -> Result<(), DeterminationError> {
            if let Some(slot) = first.get_mut(count) {
                *slot = Some((g, f));
            }
            count += 1;
            ls.push(&g, &f)?;
            Ok(())
        };
    for (index, (tile, reading)) in tiles.iter().zip(readings.iter()).enumerate() {
        let Some(angles) = reading else { continue };
        if !tile.has_working_sun_sensor() {
            continue;
        }
        if !(angles.a_rad.is_finite() && angles.b_rad.is_finite()) {
            return Err(DeterminationError::NonFinite { index });
        }
        let g = thesis_normal_reference(sun_right_ascension_rad, sun_declination_rad, angles);
        add(g, tile.normal_body(), &mut ls)?;
    }
    if let Some(m) = magnetic {
        let u = super::unit(tiles.len(), m)?;
        add(u.reference, u.body, &mut ls)?;
    }
    match (count, first) {
        (0 | 1, _) => {
            return Err(DeterminationError::TooFewObservations { count, needed: 2 });
        }
        (2, [Some((g1, f1)), Some((g2, f2))]) => {
            // eq. 8.30: a₃ = a₁ × a₂ in both frames.
            ls.push(&g1.cross(&g2), &f1.cross(&f2))?;
        }
        _ => {}
    }
    let a_transpose = ls.solve_full_rank(RANK_REL_TOL)?;
    Ok(a_transpose.transpose())
}
