//! Quaternion kinematics and its closed-form inverse (seed 001 eqs. 2.20, 2.32, 3.17–3.18;
//! note 001 §1.5).
//!
//! # Convention
//! Attitudes follow [`crate::attitude`]: scalar-first `q = (q0, q1, q2, q3)`, passive
//! `A(q)` with `v_body = A(q) · v_ref`, Hamilton product. The body rate ω (rad/s, body axes,
//! relative to the reference frame) enters as
//! ```text
//! q̇ = ½ q ⊗ (0, ω) = ½ Ξ(q) ω,   Ξ(q) = [ −q_vᵀ ; q0 I₃ + [q_v×] ]   (4×3)
//! ```
//! Seed 001 stores the same quaternion **scalar-last** `(q1, q2, q3, q4)` with `q4 = q0`: its
//! `A(q)` (eq. 2.8) is the crate's `A(q)` with `q4 ↔ q0`, and its eq. 2.20 (with the ½ of eq. 2.32)
//! is the equation above. [`from_scalar_last`] and [`to_scalar_last`] are the only conversions.
//!
//! # Inverse
//! `ΞᵀΞ = I₃` for a unit `q`, hence `ω = 2 Ξ(q)ᵀ q̇` and, since `Ξ(q̇)ᵀ q̇ ≡ 0`,
//! `ω̇ = 2 Ξ(q)ᵀ q̈` (note 001 §1.5 \[D\]); in quaternion form `ω = 2 (q* ⊗ q̇)_v`. This replaces
//! the thesis's symbolic inversion with a dynamically dropped equation (no division).
//!
//! # Accuracy (measured, `cargo test --test planning -- --nocapture kinematics`)
//! f32 round trip ω → q̇ → ω: relative error 5e-8 (test bound 4e-7); ω from an f64 central
//! difference of the exact constant-rate rotation: 7e-8 relative (test bound 1e-6).

use crate::attitude::Quaternion;
use crate::fmath;
use crate::linalg::Vec3;

use super::PlanningError;

/// Largest accepted deviation of `|q|` from 1 in the inverse kinematics.
pub const UNIT_TOLERANCE: f32 = 1e-3;

/// Smallest scalar part `q0` accepted by [`complete_from_vector_part`]: below it `q̇0 = −q_v·q̇_v/q0`
/// is ill-conditioned (thesis eq. 3.17 is singular at 180° rotations).
pub const MIN_SCALAR_PART: f32 = 1e-3;

/// A quaternion stored scalar-last as in seed 001 eq. 2.3, `[q1, q2, q3, q4]`, converted to the
/// crate's scalar-first [`Quaternion`] (`q0 = q4`). Not normalised.
pub fn from_scalar_last(q: [f32; 4]) -> Quaternion {
    let [q1, q2, q3, q4] = q;
    Quaternion { q0: q4, q1, q2, q3 }
}

/// The crate's scalar-first [`Quaternion`] stored scalar-last as in seed 001, `[q1, q2, q3, q4]`.
pub fn to_scalar_last(q: &Quaternion) -> [f32; 4] {
    [q.q1, q.q2, q.q3, q.q0]
}

/// The rate of a quaternion (not unit), scalar-first, `q̇ = ½ q ⊗ (0, ω)`.
///
/// `q` is the attitude ([`crate::attitude`] convention), `omega_body_radps` the body rate
/// (rad/s, body axes). Returns `q̇` in 1/s as a scalar-first [`Quaternion`] (not of unit norm).
pub fn quaternion_rate(q: &Quaternion, omega_body_radps: &Vec3) -> Quaternion {
    let w = Quaternion {
        q0: 0.0,
        q1: omega_body_radps.x,
        q2: omega_body_radps.y,
        q3: omega_body_radps.z,
    };
    let d = q.mul(&w);
    Quaternion {
        q0: 0.5 * d.q0,
        q1: 0.5 * d.q1,
        q2: 0.5 * d.q2,
        q3: 0.5 * d.q3,
    }
}

/// `2 Ξ(q)ᵀ x = 2 (q* ⊗ x)_v` for a 4-vector `x`.
fn two_xi_transpose(q: &Quaternion, x: &Quaternion) -> Vec3 {
    let p = q.conjugate().mul(x);
    Vec3::new(2.0 * p.q1, 2.0 * p.q2, 2.0 * p.q3)
}

fn check_unit(q: &Quaternion) -> Result<(), PlanningError> {
    let all = [q.q0, q.q1, q.q2, q.q3];
    if !all.iter().all(|x| x.is_finite()) {
        return Err(PlanningError::NotFinite);
    }
    let n = q.norm();
    if fmath::abs(n - 1.0) > UNIT_TOLERANCE {
        return Err(PlanningError::NotUnit(n));
    }
    Ok(())
}

fn finite4(q: &Quaternion) -> bool {
    [q.q0, q.q1, q.q2, q.q3].iter().all(|x| x.is_finite())
}

/// The body rate (rad/s, body axes) from the attitude `q` ([`crate::attitude`]) and its rate
/// `q_dot` (1/s, scalar-first): `ω = 2 Ξ(q)ᵀ q̇` (note 001 §1.5).
pub fn body_rate(q: &Quaternion, q_dot: &Quaternion) -> Result<Vec3, PlanningError> {
    check_unit(q)?;
    if !finite4(q_dot) {
        return Err(PlanningError::NotFinite);
    }
    Ok(two_xi_transpose(q, q_dot))
}

/// The body angular acceleration (rad/s², body axes) from the attitude `q`
/// ([`crate::attitude`]) and its second derivative `q_ddot` (1/s²): `ω̇ = 2 Ξ(q)ᵀ q̈`, exact
/// along a unit-norm path (note 001 §1.5).
pub fn body_acceleration(q: &Quaternion, q_ddot: &Quaternion) -> Result<Vec3, PlanningError> {
    body_rate(q, q_ddot)
}

/// A quaternion and its first two derivatives (scalar-first, [`crate::attitude`]).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct QuaternionJet {
    /// The attitude (unit).
    pub q: Quaternion,
    /// `q̇`, 1/s.
    pub q_dot: Quaternion,
    /// `q̈`, 1/s².
    pub q_ddot: Quaternion,
}

/// Completes a quaternion from its vector part as seed 001 eq. 3.17, `q0 = +√(1 − |q_v|²)`, with
/// the derivatives `q̇0 = −q_v·q̇_v / q0`, `q̈0 = −(|q̇_v|² + q_v·q̈_v + q̇0²) / q0` (differentiating
/// `|q|² = 1`). `q0 ≥ 0` restricts the path to rotations up to 180° from the reference; an
/// error when `q0 <` [`MIN_SCALAR_PART`] (the thesis's singularity) or `|q_v| > 1`.
pub fn complete_from_vector_part(
    qv: &Vec3,
    qv_dot: &Vec3,
    qv_ddot: &Vec3,
) -> Result<QuaternionJet, PlanningError> {
    if [qv, qv_dot, qv_ddot]
        .iter()
        .any(|v| !v.iter().all(|x| x.is_finite()))
    {
        return Err(PlanningError::NotFinite);
    }
    let s2 = 1.0 - qv.norm_squared();
    if s2 < MIN_SCALAR_PART * MIN_SCALAR_PART {
        return Err(PlanningError::VectorPartTooLong(qv.norm()));
    }
    let q0 = fmath::sqrt(s2);
    let q0_dot = -qv.dot(qv_dot) / q0;
    let q0_ddot = -(qv_dot.norm_squared() + qv.dot(qv_ddot) + q0_dot * q0_dot) / q0;
    Ok(QuaternionJet {
        q: Quaternion {
            q0,
            q1: qv.x,
            q2: qv.y,
            q3: qv.z,
        },
        q_dot: Quaternion {
            q0: q0_dot,
            q1: qv_dot.x,
            q2: qv_dot.y,
            q3: qv_dot.z,
        },
        q_ddot: Quaternion {
            q0: q0_ddot,
            q1: qv_ddot.x,
            q2: qv_ddot.y,
            q3: qv_ddot.z,
        },
    })
}

/// Body rate and acceleration (rad/s, rad/s², body axes) of a [`QuaternionJet`].
pub fn rates_of_jet(jet: &QuaternionJet) -> Result<(Vec3, Vec3), PlanningError> {
    Ok((
        body_rate(&jet.q, &jet.q_dot)?,
        body_acceleration(&jet.q, &jet.q_ddot)?,
    ))
}
