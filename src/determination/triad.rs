//! Attitude from two vector pairs by TRIAD (Black, *A passive system for determining the
//! attitude of a satellite*, AIAA J. 2(7), 1964; Shuster and Oh, *Three-axis attitude
//! determination from vector observations*, J. Guidance and Control 4(1), 1981, pp. 70–77).
//!
//! # Algorithm (Black 1964; Shuster and Oh 1981)
//! ```text
//! t̂₁ = b̂₁,  t̂₂ = (b̂₁ × b̂₂)/|b̂₁ × b̂₂|,  t̂₃ = t̂₁ × t̂₂        (body triad)
//! ŝ₁ = r̂₁,  ŝ₂ = (r̂₁ × r̂₂)/|r̂₁ × r̂₂|,  ŝ₃ = ŝ₁ × ŝ₂        (reference triad)
//! A = [t̂₁ t̂₂ t̂₃]·[ŝ₁ ŝ₂ ŝ₃]ᵀ
//! ```
//! The first vector is matched exactly; the second only fixes the rotation about it. Use the
//! more accurate sensor first.
//!
//! # Validity and accuracy
//! Needs `|b̂₁ × b̂₂|` and `|r̂₁ × r̂₂|` ≥ [`MIN_SIN_ANGLE`]. With angular measurement errors ε₁,
//! ε₂ (rad) and θ the angle between the two directions, the attitude error is at most
//! `ε₁ + (ε₁ + ε₂)/sin θ` to first order (the tilt of the first axis plus the roll of the
//! plane of the pair about it); `tests/determination.rs` checks this bound on the 200 problems
//! of `wahba.json`. f32 rounding adds about `1e-7/sin θ` rad.

use super::{unit, DeterminationError, Observation, Solution};
use crate::attitude::{Dcm, Quaternion};
use crate::fmath;
use crate::linalg::{cross, div, dot, mat_vec, norm, sub_scaled, Mat3, Vec3};

/// Smallest sine of the angle between the two directions TRIAD accepts.
pub const MIN_SIN_ANGLE: f32 = 1.0e-3;

/// The TRIAD attitude from the first two observations (weights are ignored except for the
/// loss; further observations are ignored). Convention: [`crate::attitude`].
pub fn solve(observations: &[Observation]) -> Result<Solution, DeterminationError> {
    let (o1, o2) = match observations {
        [o1, o2, ..] => (o1, o2),
        _ => {
            return Err(DeterminationError::TooFewObservations {
                count: observations.len(),
                needed: 2,
            })
        }
    };
    let u1 = unit(0, o1)?;
    let u2 = unit(1, o2)?;
    let t2 = u1.body.cross(&u2.body);
    let s2 = u1.reference.cross(&u2.reference);
    let (nt, ns) = (
        fmath::sqrt(t2.norm_squared()),
        fmath::sqrt(s2.norm_squared()),
    );
    if !(nt >= MIN_SIN_ANGLE && ns >= MIN_SIN_ANGLE) {
        return Err(DeterminationError::Parallel {
            measure: fmath::min(nt, ns),
        });
    }
    let (t1, t2) = (u1.body, t2 / nt);
    let t3 = t1.cross(&t2);
    let (s1, s2) = (u1.reference, s2 / ns);
    let s3 = s1.cross(&s2);
    let m_body = Mat3::from_columns(&[t1, t2, t3]);
    let m_ref = Mat3::from_columns(&[s1, s2, s3]);
    let a = Dcm::from_matrix_unchecked(m_body * m_ref.transpose());
    let loss = 0.5
        * [&u1, &u2]
            .iter()
            .map(|u| u.weight * (u.body - a.to_body(&u.reference)).norm_squared())
            .sum::<f32>();
    Ok(Solution {
        dcm: a,
        quaternion: a.to_quaternion(),
        loss,
    })
}

/// The smallest angle between the two directions [`pair_quaternion`] accepts, as its sine:
/// 5°. Closer, a field error of 30′ (the geomagnetic model's own, seed 000 §3.1) would turn
/// the attitude about the first direction by more than 5°.
pub const PAIR_MIN_SIN_ANGLE: f32 = 0.087;

/// TRIAD's attitude (reference → body, [`crate::attitude`]) as a quaternion, without a matrix:
/// the first pair (`first_body`, `first_ref`, unit) matched exactly, the second (any length)
/// fixing the rotation about it. Two rotations, each the half-way quaternion of two unit
/// vectors (`(1 + u·v, v × u)` normalised, in the passive convention of
/// [`Quaternion::mul`]): `q₁` turns the first reference direction onto the first body
/// direction, then `q₂` turns, about the first body direction, the second reference direction
/// (by `q₁`) onto the second body direction, both projected on the plane normal to the first;
/// `q = q₁ ⊗ q₂`. `None` for directions closer than [`PAIR_MIN_SIN_ANGLE`] (in either frame)
/// or non-finite input. Measured on 2 000 random problems (`tests/determination.rs`,
/// `pair_quaternion_is_triad`): exact vectors give the attitude back within 1.0e-5 rad (f32
/// rounding of the roll, at worst near the 5° limit), noisy ones [`solve`]'s (first vector
/// first) within 2.1e-6 rad.
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn pair_quaternion(
    first_body: &Vec3,
    first_ref: &Vec3,
    second_body: &Vec3,
    second_ref: &Vec3,
) -> Option<Quaternion> {
    let normal = cross(first_body, &any_normal(first_body));
    let q1 = half_way(first_ref, first_body, &div(&normal, norm(&normal)))?;
    let s = first_body;
    let predicted = mat_vec(q1.to_dcm().matrix(), second_ref);
    let u = sub_scaled(&predicted, s, dot(&predicted, s));
    let v = sub_scaled(second_body, s, dot(second_body, s));
    let (nu, nv) = (norm(&u), norm(&v));
    let limit = PAIR_MIN_SIN_ANGLE;
    if !(nu >= limit * norm(second_ref)) || !(nv >= limit * norm(second_body)) {
        return None;
    }
    let q2 = half_way(&div(&u, nu), &div(&v, nv), s)?;
    let q = q1.mul(&q2);
    Quaternion::new_normalize(q.q0, q.q1, q.q2, q.q3)
}

/// A passive quaternion turning the unit vector `from` onto the unit vector `to`: for
/// `from·to ≥ 0` the shorter way, `(1 + from·to, to × from)` normalised; otherwise onto `−to`
/// so, then half a turn about `axis` (unit, normal to `to`) (the half-way quaternion of two
/// nearly opposite vectors loses its precision in `1 + from·to`). `None` for a non-finite
/// input.
fn half_way(from: &Vec3, to: &Vec3, axis: &Vec3) -> Option<Quaternion> {
    let d = dot(from, to);
    // one call of each for both ways (`(1 + d, to × from)` or `(1 − d, from × to)`)
    let shorter = d >= 0.0;
    let (w, v) = if shorter {
        (1.0 + d, cross(to, from))
    } else {
        (1.0 - d, cross(from, to))
    };
    let p = Quaternion::new_normalize(w, v.x, v.y, v.z);
    if shorter {
        return p;
    }
    let p = p?;
    let half_turn = Quaternion::new_normalize(0.0, axis.x, axis.y, axis.z)?;
    let q = p.mul(&half_turn);
    Quaternion::new_normalize(q.q0, q.q1, q.q2, q.q3)
}

/// A unit-free vector not parallel to `v` (a coordinate axis).
fn any_normal(v: &Vec3) -> Vec3 {
    if v.x * v.x >= 0.5 {
        Vec3::y()
    } else {
        Vec3::x()
    }
}
