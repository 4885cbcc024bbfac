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
//! selects column k of the same adjugate; here all four columns are formed (as generalised
//! cross products of three rows of `K − λI`) and the longest is kept: the same choice,
//! made with the largest pivot, as in DCM → quaternion. The chosen λ is refined once by the
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
//! Needs two non-parallel directions: the longest adjugate column, which equals
//! `|q_k|·Π_{j≠max}(λ_max − λ_j)` (≥ half the product of the eigenvalue gaps), must be at least
//! [`MIN_PIVOT`]. Measured on the 200 problems of `../shared/ref/attitude/wahba.json`: see the
//! README and `cargo test --test determination wahba -- --nocapture`.

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

/// The 3×3 determinant of the columns `a, b, c`.
fn det3(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    a.dot(&b.cross(&c))
}

/// The generalised cross product of three 4-vectors: orthogonal to all three, with components
/// the signed 3×3 minors.
fn cross4(a: &Vector4<f32>, b: &Vector4<f32>, c: &Vector4<f32>) -> Vector4<f32> {
    // Columns of the 3×4 matrix [a; b; c] without the component index.
    let col = |f: fn(&Vector4<f32>) -> f32| Vec3::new(f(a), f(b), f(c));
    let c0 = col(|v| v.x);
    let c1 = col(|v| v.y);
    let c2 = col(|v| v.z);
    let c3 = col(|v| v.w);
    Vector4::new(
        det3(c1, c2, c3),
        -det3(c0, c2, c3),
        det3(c0, c1, c3),
        -det3(c0, c1, c2),
    )
}

/// The Davenport matrix rows `K` (scalar-first ordering).
fn davenport(b: &Mat3) -> [Vector4<f32>; 4] {
    let s = b + b.transpose();
    let sigma = b.trace();
    let z = Vec3::new(b.m23 - b.m32, b.m31 - b.m13, b.m12 - b.m21);
    [
        Vector4::new(sigma, z.x, z.y, z.z),
        Vector4::new(z.x, s.m11 - sigma, s.m12, s.m13),
        Vector4::new(z.y, s.m21, s.m22 - sigma, s.m23),
        Vector4::new(z.z, s.m31, s.m32, s.m33 - sigma),
    ]
}

/// The longest column of `adj(K − λI)` (unnormalised eigenvector of λ).
fn eigenvector(k: &[Vector4<f32>; 4], lambda: f32) -> Vector4<f32> {
    let [k0, k1, k2, k3] = k;
    let m0 = k0 - Vector4::new(lambda, 0.0, 0.0, 0.0);
    let m1 = k1 - Vector4::new(0.0, lambda, 0.0, 0.0);
    let m2 = k2 - Vector4::new(0.0, 0.0, lambda, 0.0);
    let m3 = k3 - Vector4::new(0.0, 0.0, 0.0, lambda);
    let candidates = [
        cross4(&m1, &m2, &m3),
        cross4(&m0, &m2, &m3),
        cross4(&m0, &m1, &m3),
        cross4(&m0, &m1, &m2),
    ];
    candidates
        .iter()
        .fold(Vector4::zeros(), |best: Vector4<f32>, c| {
            if c.norm_squared() > best.norm_squared() {
                *c
            } else {
                best
            }
        })
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
        if fmath::abs(step) <= NEWTON_TOL {
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

/// QUEST's attitude (loss not evaluated).
fn quest(units: &Units) -> Result<Solution, DeterminationError> {
    let b = attitude_profile(units);
    let k = davenport(&b);
    let lambda = lambda_max(&b);
    let v = eigenvector(&k, lambda);
    let n2 = v.norm_squared();
    let pivot = fmath::sqrt(n2);
    if !pivot.is_finite() || pivot < MIN_PIVOT {
        return Err(DeterminationError::Parallel { measure: pivot });
    }
    // One Rayleigh-quotient refinement of λ, then the eigenvector again.
    let q = v * (1.0 / pivot);
    let [k0, k1, k2, k3] = &k;
    let kq = Vector4::new(k0.dot(&q), k1.dot(&q), k2.dot(&q), k3.dot(&q));
    let v = eigenvector(&k, q.dot(&kq));
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
