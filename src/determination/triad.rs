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
use crate::attitude::Dcm;
use crate::fmath;
use crate::linalg::Mat3;

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
