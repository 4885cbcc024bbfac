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
//! `B = U·S·Vᵀ`, `A = U·diag(1, 1, det U·det V)·Vᵀ`. The SVD is the one-sided Jacobi of
//! [`crate::linalg::svd::nearest_rotation`] (bounded sweeps, allocation-free), which takes the
//! third left singular vector as `u₁ × u₂`, so two observations (rank-2 `B`) are exact.
//!
//! | symbol | name |
//! |---|---|
//! | `aᵢ`, `b̂ᵢ`, `r̂ᵢ` | [`Observation`] `weight`, `body`, `reference` (normalised here) |
//! | `B` | `attitude_profile` (weights normalised to Σaᵢ = 1) |
//! | `S = diag(s₁, s₂, s₃)` | singular values of `B` |
//!
//! [`solve`] adds one Gauss–Newton step on Wahba's loss ([`super::refine`]): forming `B` in
//! f32 rounds away information that the step recovers from the vectors themselves;
//! [`solve_raw`] is Markley's method alone.
//!
//! # Validity and accuracy
//! Needs two non-parallel directions: `s₂/s₁ ≥` [`MIN_SINGULAR_RATIO`] (for two unit vectors
//! of equal weight at angle θ, `s₂/s₁ = (1 − cos θ)/(1 + cos θ) ≈ θ²/4`, so the threshold
//! refuses pairs closer than about 1.1°: below that, rounding `B` to f32 alone turns the
//! rotation about the common direction by more than 1e-3 rad). Measured on the 200 problems of
//! `../shared/ref/attitude/wahba.json` (2–6 vectors, noise 0–0.01 rad): see the README and
//! `cargo test --test determination wahba -- --nocapture`.
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

use super::{attitude_profile, solution, DeterminationError, Observation, Solution};
use crate::attitude::Dcm;
use crate::linalg::svd::{nearest_rotation, SvdError};

/// Smallest `s₂/s₁` of the attitude profile matrix accepted (see the module docs).
pub const MIN_SINGULAR_RATIO: f32 = 1.0e-4;

/// [`solve_raw`] followed by one Gauss–Newton refinement ([`super::refine`]): the flight
/// solver. Convention: [`crate::attitude`].
pub fn solve(observations: &[Observation]) -> Result<Solution, DeterminationError> {
    let raw = solve_raw(observations)?;
    Ok(super::refine(&raw, observations))
}

/// The optimal attitude for `observations` (at least 2, not all parallel): the solution of
/// Wahba's problem by SVD alone (Markley 1988), with its loss. Convention:
/// [`crate::attitude`].
pub fn solve_raw(observations: &[Observation]) -> Result<Solution, DeterminationError> {
    let b = attitude_profile(observations, 2)?;
    let a = match nearest_rotation(&b, MIN_SINGULAR_RATIO) {
        Ok((a, _)) => a,
        Err(SvdError::RankDeficient { ratio, .. }) => {
            return Err(DeterminationError::Parallel { measure: ratio })
        }
        Err(e) => return Err(DeterminationError::Linalg(e)),
    };
    Ok(solution(Dcm::from_matrix_unchecked(a), observations))
}
