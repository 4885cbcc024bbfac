//! Optimal attitude from weighted vector pairs by QUEST (Shuster and Oh, *Three-axis attitude
//! determination from vector observations*, J. Guidance and Control 4(1), 1981, pp. 70–77; equation
//! numbers are not cited because the paper was not at hand: the formulas below are the standard
//! statement of the method and are checked numerically by the tests).
//!
//! # Method
//! Davenport's q-method: the optimal quaternion (scalar first, [`crate::attitude`]) is the
//! eigenvector of the largest eigenvalue λ_max of
//! ```text
//! K = [[σ, zᵀ], [z, S − σI]],  S = B + Bᵀ,  σ = tr B,  z = (B23 − B32, B31 − B13, B12 − B21)
//! ```
//! with `B = Σ aᵢ b̂ᵢ r̂ᵢᵀ` (weights normalised to Σaᵢ = 1, so λ_max = 1 − L_min ≤ 1).
//! QUEST finds λ_max by Newton's method on the characteristic equation (Shuster and
//! Oh)
//! ```text
//! λ⁴ − (a + b)λ² − cλ + (ab + cσ − d) = 0,
//! a = σ² − κ,  b = σ² + zᵀz,  c = Δ + zᵀSz,  d = zᵀS²z,  κ = tr(adj S),  Δ = det S
//! ```
//! from λ = Σaᵢ = 1, at most [`MAX_NEWTON`] steps, stopping when the step is below
//! [`NEWTON_TOL`] (a few f32 ulps of 1). The eigenvector is then a column of `adj(K − λI)`:
//! Shuster's `(γ, x)`, `γ = (λ + σ)α − Δ`, `x = (αI + βS + S²)z`, is its first column. That
//! column vanishes when the rotation is near 180° (γ → 0), which Shuster and Oh avoid by the
//! method of sequential rotations (solving for the attitude relative to a frame rotated by 180°
//! about x, y or z). Rotating by 180° about axis k swaps the roles of `q0` and `qk`, i.e.
//! selects column k of the same adjugate; here the column of the largest diagonal entry
//! `adj_kk ∝ q_k²` is taken (the longest column: the same choice, made with the largest pivot,
//! as in DCM → quaternion). The adjugate entries are 3×3 minors expanded over the twelve 2×2
//! minors of rows 0–1 and 2–3 of the symmetric `K − λI` (45 multiplications for the four
//! diagonal entries and the chosen column). The chosen λ is refined once by the
//! Rayleigh quotient `qᵀKq` (error second order in that of q) and the column recomputed.
//!
//! | symbol | name |
//! |---|---|
//! | `B`, `S`, `σ`, `z` | `b`, `s`, `sigma`, `z` |
//! | `K` | rows `k0..k3` |
//! | `a, b, c, d` of the characteristic equation | `ca, cb, cc, cd` |
//!
//! [`solve`] adds one Gauss–Newton step on Wahba's loss ([`super::refine`]), which removes
//! the f32 rounding of the characteristic polynomial and of the adjugate; [`solve_raw`] is
//! QUEST alone.
//!
//! # Validity and accuracy
//! Needs two non-parallel directions: the chosen adjugate column, which equals
//! `|q_k|·Π_{j≠max}(λ_max − λ_j)` (≥ half the product of the eigenvalue gaps), must be at least
//! [`MIN_PIVOT`]. Measured on the 200 problems of `tests/data/attitude/wahba.json`: see the
//! `docs/accuracy.md` and `cargo test --test determination wahba -- --nocapture`.

use nalgebra::Vector4;

use super::{
    attitude_profile, loss, refine_units, DeterminationError, Observation, Solution, Units,
};
use crate::attitude::Quaternion;
use crate::fmath;
use crate::linalg::{Mat3, Vec3};

/// Newton iteration cap.
pub const MAX_NEWTON: u8 = 10;
/// Newton stops when |Δλ| ≤ this (λ ≈ 1): four f32 ulps of 1.
pub const NEWTON_TOL: f32 = 4.0 * f32::EPSILON;
/// Smallest accepted length of the chosen adjugate column (see the module docs).
pub const MIN_PIVOT: f32 = 1.0e-4;

/// The Davenport matrix `K` (scalar-first ordering), symmetric: its upper triangle.
#[derive(Copy, Clone)]
struct Davenport {
    k00: f32,
    k01: f32,
    k02: f32,
    k03: f32,
    k11: f32,
    k12: f32,
    k13: f32,
    k22: f32,
    k23: f32,
    k33: f32,
}

impl Davenport {
    fn new(b: &Mat3) -> Self {
        let sigma = b.trace();
        Self {
            k00: sigma,
            k01: b.m23 - b.m32,
            k02: b.m31 - b.m13,
            k03: b.m12 - b.m21,
            k11: 2.0 * b.m11 - sigma,
            k12: b.m12 + b.m21,
            k13: b.m13 + b.m31,
            k22: 2.0 * b.m22 - sigma,
            k23: b.m23 + b.m32,
            k33: 2.0 * b.m33 - sigma,
        }
    }

    /// `K·q`.
    fn mul(&self, q: &Vector4<f32>) -> Vector4<f32> {
        let k = self;
        Vector4::new(
            k.k00 * q.x + k.k01 * q.y + k.k02 * q.z + k.k03 * q.w,
            k.k01 * q.x + k.k11 * q.y + k.k12 * q.z + k.k13 * q.w,
            k.k02 * q.x + k.k12 * q.y + k.k22 * q.z + k.k23 * q.w,
            k.k03 * q.x + k.k13 * q.y + k.k23 * q.z + k.k33 * q.w,
        )
    }
}

/// The column of `adj(K − λI)` with the largest diagonal entry (the unnormalised eigenvector
/// of λ: `adj(K − λI) = c·q·qᵀ` at an eigenvalue, so that column is the one of the largest
/// `|q_k|`, the longest). `N = K − λI` is symmetric; its cofactors are 3×3 minors expanded
/// along one row over the six 2×2 minors of rows 0–1 (`s`) or rows 2–3 (`c`): 24
/// multiplications for the minors, 12 for the four diagonal cofactors, 9 for the rest of the
/// chosen column.
fn eigenvector(k: &Davenport, lambda: f32) -> Vector4<f32> {
    let (n00, n01, n02, n03) = (k.k00 - lambda, k.k01, k.k02, k.k03);
    let (n11, n12, n13) = (k.k11 - lambda, k.k12, k.k13);
    let (n22, n23) = (k.k22 - lambda, k.k23);
    let n33 = k.k33 - lambda;
    // 2×2 minors of rows 0, 1 (s_ij, columns i < j) and of rows 2, 3 (c_ij).
    let s01 = n00 * n11 - n01 * n01;
    let s02 = n00 * n12 - n02 * n01;
    let s03 = n00 * n13 - n03 * n01;
    let s12 = n01 * n12 - n02 * n11;
    let s13 = n01 * n13 - n03 * n11;
    let s23 = n02 * n13 - n03 * n12;
    let c01 = n02 * n13 - n12 * n03;
    let c02 = n02 * n23 - n22 * n03;
    let c03 = n02 * n33 - n23 * n03;
    let c12 = n12 * n23 - n22 * n13;
    let c13 = n12 * n33 - n23 * n13;
    let c23 = n22 * n33 - n23 * n23;
    // Principal minors M_kk (the diagonal of the adjugate).
    let m00 = n11 * c23 - n12 * c13 + n13 * c12;
    let m11 = n00 * c23 - n02 * c03 + n03 * c02;
    let m22 = n03 * s13 - n13 * s03 + n33 * s01;
    let m33 = n02 * s12 - n12 * s02 + n22 * s01;
    let (a0, a1, a2, a3) = (
        fmath::abs(m00),
        fmath::abs(m11),
        fmath::abs(m22),
        fmath::abs(m33),
    );
    // Column k = the cofactors of row k, C_kj = (−1)^(k+j)·M_kj.
    if a0 >= a1 && a0 >= a2 && a0 >= a3 {
        // rows 1, 2, 3
        Vector4::new(
            m00,
            -(n01 * c23 - n12 * c03 + n13 * c02),
            n01 * c13 - n11 * c03 + n13 * c01,
            -(n01 * c12 - n11 * c02 + n12 * c01),
        )
    } else if a1 >= a2 && a1 >= a3 {
        // rows 0, 2, 3
        Vector4::new(
            -(n01 * c23 - n02 * c13 + n03 * c12),
            m11,
            -(n00 * c13 - n01 * c03 + n03 * c01),
            n00 * c12 - n01 * c02 + n02 * c01,
        )
    } else if a2 >= a3 {
        // rows 0, 1, 3
        Vector4::new(
            n13 * s23 - n23 * s13 + n33 * s12,
            -(n03 * s23 - n23 * s03 + n33 * s02),
            m22,
            -(n03 * s12 - n13 * s02 + n23 * s01),
        )
    } else {
        // rows 0, 1, 2
        Vector4::new(
            -(n12 * s23 - n22 * s13 + n23 * s12),
            n02 * s23 - n22 * s03 + n23 * s02,
            -(n02 * s13 - n12 * s03 + n23 * s01),
            m33,
        )
    }
}

/// λ_max by Newton's method on the characteristic equation (Shuster and Oh).
fn lambda_max(b: &Mat3) -> f32 {
    let s = b + b.transpose();
    let sigma = b.trace();
    let z = Vec3::new(b.m23 - b.m32, b.m31 - b.m13, b.m12 - b.m21);
    // κ = tr(adj S): the sum of the principal 2×2 minors.
    let kappa = s.m22 * s.m33 - s.m23 * s.m32 + s.m11 * s.m33 - s.m13 * s.m31 + s.m11 * s.m22
        - s.m12 * s.m21;
    let delta = s.determinant();
    let sz = s * z;
    let ca = sigma * sigma - kappa;
    let cb = sigma * sigma + z.dot(&z);
    let cc = delta + z.dot(&sz);
    let cd = sz.dot(&sz);
    let c0 = ca * cb + cc * sigma - cd;
    let mut lambda = 1.0f32;
    for _ in 0..MAX_NEWTON {
        let l2 = lambda * lambda;
        let f = l2 * l2 - (ca + cb) * l2 - cc * lambda + c0;
        let df = 4.0 * l2 * lambda - 2.0 * (ca + cb) * lambda - cc;
        if df == 0.0 || !df.is_finite() {
            break;
        }
        let step = f / df;
        lambda -= step;
        if !(fmath::abs(step) > NEWTON_TOL) {
            break;
        }
    }
    lambda
}

/// The optimal attitude for `observations` (at least 2, not all parallel) by QUEST alone
/// (Shuster and Oh's algorithm as described above), with its loss. Convention:
/// [`crate::attitude`].
pub fn solve_raw(observations: &[Observation]) -> Result<Solution, DeterminationError> {
    let units = Units::new(observations, 2)?;
    let mut s = quest(&units)?;
    s.loss = loss(&s.dcm, &units);
    Ok(s)
}

/// QUEST's attitude (loss not evaluated; not inlined, so its frame is gone during the
/// refinement).
#[inline(never)]
fn quest(units: &Units) -> Result<Solution, DeterminationError> {
    let b = attitude_profile(units);
    let k = Davenport::new(&b);
    let lambda = lambda_max(&b);
    let v = eigenvector(&k, lambda);
    let n2 = v.norm_squared();
    let pivot = fmath::sqrt(n2);
    if !pivot.is_finite() || !(pivot >= MIN_PIVOT) {
        return Err(DeterminationError::Parallel { measure: pivot });
    }
    // One Rayleigh-quotient refinement of λ, then the eigenvector again.
    let q = v * (1.0 / pivot);
    let v = eigenvector(&k, q.dot(&k.mul(&q)));
    let quaternion = Quaternion::new_normalize(v.x, v.y, v.z, v.w)
        .ok_or(DeterminationError::Parallel { measure: 0.0 })?
        .canonical();
    Ok(Solution {
        dcm: quaternion.to_dcm(),
        quaternion,
        loss: 0.0,
    })
}

/// [`solve_raw`] followed by one Gauss–Newton refinement ([`super::refine`]): the flight
/// solver. Convention: [`crate::attitude`].
pub fn solve(observations: &[Observation]) -> Result<Solution, DeterminationError> {
    let units = Units::new(observations, 2)?;
    let raw = quest(&units)?;
    Ok(refine_units(&raw, &units))
}
