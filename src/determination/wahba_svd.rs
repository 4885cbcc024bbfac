//! Optimal attitude from weighted vector pairs by the singular value decomposition (Markley,
//! *Attitude determination using vector observations and the singular value decomposition*,
//! J. Astronaut. Sci. 36(3), 1988).
//!
//! # Problem (Wahba 1965)
//! Find the rotation `A` (`v_body = A·v_ref`, [`crate::attitude`]) minimising
//! `L(A) = ½ Σ aᵢ |b̂ᵢ − A r̂ᵢ|² = Σ aᵢ − tr(A Bᵀ)`, with the attitude profile matrix
//! `B = Σ aᵢ b̂ᵢ r̂ᵢᵀ` (Markley 1988).
//!
//! # Solution (Markley 1988)
//! `B = U·S·Vᵀ`, `A = U·diag(1, 1, det U·det V)·Vᵀ`. With three or more observations the SVD
//! is the one-sided Jacobi of
//! [`crate::linalg::svd::nearest_rotation`] (bounded sweeps, allocation-free), which takes the
//! third left singular vector as `u₁ × u₂`, so two observations (rank-2 `B`) are exact.
//!
//! **Two observations** (the flight case: Sun and field). `B = w₁b̂₁r̂₁ᵀ + w₂b̂₂r̂₂ᵀ` has rank 2
//! and its SVD is a 2×2 one. With the orthonormal triads `E = [b̂₁, ê₂, ê₃]`,
//! `ê₃ = b̂₁×b̂₂/s_b`, `ê₂ = ê₃×b̂₁` and `F = [r̂₁, f̂₂, f̂₃]` likewise (`c_b = b̂₁·b̂₂`,
//! `s_b = |b̂₁×b̂₂|`, `c_r`, `s_r` for the reference pair), `B = E·M·Fᵀ` with
//! ```text
//! M = [[w₁ + w₂c_b c_r, w₂c_b s_r], [w₂s_b c_r, w₂s_b s_r]]   (third row and column zero)
//! ```
//! `det M = w₁w₂s_b s_r > 0`, so `d = +1` and `A = E·(Q ⊕ 1)·Fᵀ`, `Q` the rotation of M's polar
//! decomposition: `(cos φ, sin φ) ∥ (m₁₁ + m₂₂, m₂₁ − m₁₂)`, `σ₁ + σ₂ = |(m₁₁ + m₂₂, m₂₁ − m₁₂)|`.
//! `σ₂/σ₁ = ρ` follows from `det M/‖M‖²_F = ρ/(1 + ρ²)`; the loss of the optimum is
//! `Σaᵢ·(1 − σ₁ − σ₂) = 2a₁w₂(1 − cos Δ)/(1 + σ₁ + σ₂)` (`Δ` the difference of the angles of the
//! two pairs, `1 − cos Δ = sin²Δ/(1 + cos Δ)` when `cos Δ > 0`: no cancellation). This never
//! forms `B`, so it keeps the accuracy that rounding `B` to f32 loses (below), and it costs two
//! cross products and three square roots instead of a Jacobi SVD.
//!
//! | symbol | name |
//! |---|---|
//! | `aᵢ`, `b̂ᵢ`, `r̂ᵢ` | [`Observation`] `weight`, `body`, `reference` (normalised here) |
//! | `B` | `attitude_profile` (weights normalised to Σaᵢ = 1) |
//! | `S = diag(s₁, s₂, s₃)` | singular values of `B` |
//!
//! With three or more observations [`solve`] adds one Gauss–Newton step on Wahba's loss
//! ([`super::refine`]): forming `B` in f32 rounds away information that the step recovers from
//! the vectors themselves; [`solve_raw`] is Markley's method alone. With two, `B` is never
//! formed and [`solve`] is [`solve_raw`].
//!
//! # Validity and accuracy
//! Needs two non-parallel directions: `s₂/s₁ ≥` [`MIN_SINGULAR_RATIO`] (for two unit vectors
//! of equal weight at angle θ, `s₂/s₁ = (1 − cos θ)/(1 + cos θ) ≈ θ²/4`, so the threshold
//! refuses pairs closer than about 1.1°: below that, rounding `B` to f32 alone turns the
//! rotation about the common direction by more than 1e-3 rad). Measured on the 200 problems of
//! `tests/data/attitude/wahba.json` (2–6 vectors, 51 of them with two, noise 0–0.01 rad):
//! [`solve`] within 1.8e-5° of the f64 optimum (RMS 5.9e-6°), [`solve_raw`] within 1.6e-5°
//! (`cargo test --test determination wahba -- --nocapture`; `docs/accuracy.md`). MSP430 (no
//! hardware multiplier): 100 601 cycles for two observations, 487 427 for three
//! (`firmware/msp430-bench --groups det`).
//!
//! # Example
//! ```
//! use acs::determination::{wahba_svd, Observation};
//! use acs::linalg::Vec3;
//! // The body frame is the reference frame turned by 90° about z: x_ref is seen along −y_body.
//! let obs = [
//!     Observation { body: -Vec3::y(), reference: Vec3::x(), weight: 1.0 },
//!     Observation { body: Vec3::z(), reference: Vec3::z(), weight: 1.0 },
//! ];
//! let s = wahba_svd::solve(&obs)?;
//! assert!((s.dcm.to_body(&Vec3::x()) + Vec3::y()).norm() < 1e-6);
//! assert!(s.loss < 1e-12);
//! # Ok::<(), acs::determination::DeterminationError>(())
//! ```

use super::{attitude_profile, refine_units, solution, DeterminationError, Observation, Solution};
use super::{unit, Unit, Units};
use crate::attitude::Dcm;
use crate::fmath;
use crate::linalg::svd::{nearest_rotation, SvdError};
use crate::linalg::{cross, div, dot, lin2, lin3, norm, Mat3, Vec3};

/// Smallest `s₂/s₁` of the attitude profile matrix accepted (see the module docs).
pub const MIN_SINGULAR_RATIO: f32 = 1.0e-4;

/// The flight solver. Two observations: the rank-2 SVD of [`solve_raw`] alone (it does not
/// round `B`, so a refinement has nothing to recover); three or more: [`solve_raw`] followed
/// by one Gauss–Newton refinement ([`super::refine`]). Convention: [`crate::attitude`].
pub fn solve(observations: &[Observation]) -> Result<Solution, DeterminationError> {
    let units = Units::new(observations, 2)?;
    if units.len() == 2 {
        let (u1, u2) = units.first_two();
        return two_observations(u1, u2, units.sum_w);
    }
    let raw = profile_svd(&units)?;
    Ok(refine_units(&raw, &units))
}

/// [`solve`] of exactly two observations (the flight loop's Sun and field), bit for bit, without
/// the general path's room for many observations (on the MSP430 that room is stack).
/// Convention: [`crate::attitude`].
pub fn solve_pair(
    first: &Observation,
    second: &Observation,
) -> Result<Solution, DeterminationError> {
    let u1 = unit(0, first)?;
    let u2 = unit(1, second)?;
    // Σaᵢ as [`Units`] sums it (0 + a₁ + a₂ = a₁ + a₂ exactly)
    let sum_w = u1.weight + u2.weight;
    if !sum_w.is_finite() {
        return Err(DeterminationError::NonFinite { index: 0 });
    }
    two_observations(&u1, &u2, sum_w)
}

/// The optimal attitude for `observations` (at least 2, not all parallel): the solution of
/// Wahba's problem by SVD alone (Markley 1988), with its loss. Convention:
/// [`crate::attitude`].
pub fn solve_raw(observations: &[Observation]) -> Result<Solution, DeterminationError> {
    let units = Units::new(observations, 2)?;
    if units.len() == 2 {
        let (u1, u2) = units.first_two();
        return two_observations(u1, u2, units.sum_w);
    }
    profile_svd(&units)
}

/// Markley's solution through the one-sided Jacobi SVD of `B` (not inlined: its frame is not
/// on the stack of the two-observation path).
#[inline(never)]
fn profile_svd(units: &Units) -> Result<Solution, DeterminationError> {
    let b = attitude_profile(units);
    let a = match nearest_rotation(&b, MIN_SINGULAR_RATIO) {
        Ok((a, _)) => a,
        Err(SvdError::RankDeficient { ratio, .. }) => {
            return Err(DeterminationError::Parallel { measure: ratio })
        }
        Err(e) => return Err(DeterminationError::Linalg(e)),
    };
    Ok(solution(Dcm::from_matrix_unchecked(a), units))
}

/// `σ₂/σ₁` of a 2×2 matrix from `x = det/‖·‖²_F = ρ/(1 + ρ²)` (error path only).
fn ratio_from_invariants(x: f32) -> f32 {
    if !(x > 0.0) {
        return 0.0;
    }
    let d = 1.0 - 4.0 * x * x;
    2.0 * x / (1.0 + fmath::sqrt(if d > 0.0 { d } else { 0.0 }))
}

/// The rank-2 SVD of `B` for two observations (see the module docs), with the loss of the
/// optimum in closed form.
#[inline(never)]
fn two_observations(u1: &Unit, u2: &Unit, sum_w: f32) -> Result<Solution, DeterminationError> {
    let k = 1.0 / sum_w;
    let (w1, w2) = (u1.weight * k, u2.weight * k);
    let nb = cross(&u1.body, &u2.body);
    let nr = cross(&u1.reference, &u2.reference);
    let (sb, sr) = (norm(&nb), norm(&nr));
    let (cb, cr) = (dot(&u1.body, &u2.body), dot(&u1.reference, &u2.reference));
    // M = Eᵀ B F (upper 2×2 block; the third row and column are zero).
    let m11 = w1 + w2 * cb * cr;
    let m12 = w2 * cb * sr;
    let m21 = w2 * sb * cr;
    let m22 = w2 * sb * sr;
    let det = w1 * m22;
    let fro = m11 * m11 + m12 * m12 + m21 * m21 + m22 * m22;
    // σ₂/σ₁ = ρ ≥ MIN ⟺ det/fro = ρ/(1 + ρ²) ≥ MIN/(1 + MIN²).
    let x_min = MIN_SINGULAR_RATIO / (1.0 + MIN_SINGULAR_RATIO * MIN_SINGULAR_RATIO);
    if !(fro > 0.0 && det >= x_min * fro) {
        let x = if fro > 0.0 { det / fro } else { 0.0 };
        return Err(DeterminationError::Parallel {
            measure: ratio_from_invariants(x),
        });
    }
    // The rotation part of M's polar decomposition: (cos φ, sin φ) ∥ (m11 + m22, m21 − m12),
    // and σ₁ + σ₂ = |(m11 + m22, m21 − m12)|.
    let (x, y) = (m11 + m22, m21 - m12);
    let rho = fmath::sqrt(x * x + y * y);
    let kr = 1.0 / rho;
    let (c, s) = (x * kr, y * kr);
    let e1 = &u1.body;
    let e3 = div(&nb, sb);
    let e2 = cross(&e3, e1);
    let f1 = &u1.reference;
    let f3 = div(&nr, sr);
    let f2 = cross(&f3, f1);
    // G = [g₁ g₂ e₃] = [e₁cos φ + e₂sin φ, e₂cos φ − e₁sin φ, e₃], A = G·Fᵀ: column j of A is
    // G·(f₁ⱼ, f₂ⱼ, f₃ⱼ).
    let g1 = lin2(e1, c, &e2, s);
    let g2 = lin2(&e2, c, e1, -s);
    let col = |j: &Vec3| lin3(&g1, &g2, &e3, j.x, j.y, j.z);
    let a = Mat3::from_columns(&[
        col(&Vec3::new(f1.x, f2.x, f3.x)),
        col(&Vec3::new(f1.y, f2.y, f3.y)),
        col(&Vec3::new(f1.z, f2.z, f3.z)),
    ]);
    // L = Σaᵢ·(1 − σ₁ − σ₂) = Σaᵢ·2w₁w₂(1 − cos Δ)/(1 + σ₁ + σ₂) (Δ = θ_b − θ_r), with
    // 1 − cos Δ = sin²Δ/(1 + cos Δ) when cos Δ > 0 (no cancellation).
    let cos_d = cb * cr + sb * sr;
    let sin_d = sb * cr - cb * sr;
    let one_minus_cos = if cos_d > 0.0 {
        sin_d * sin_d / (1.0 + cos_d)
    } else {
        1.0 - cos_d
    };
    let loss = 2.0 * w1 * u2.weight * one_minus_cos / (1.0 + rho);
    let dcm = Dcm::from_matrix_unchecked(a);
    Ok(Solution {
        dcm,
        quaternion: dcm.to_quaternion(),
        loss,
    })
}
