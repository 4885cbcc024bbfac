//! Attitude determination (seed 000 chapter 8; note 000 §3.8, §7 items 1–4).
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A · v_ref`, scalar-first quaternions.
//!
//! | module | what | source |
//! |---|---|---|
//! | [`least_squares`] | body magnetic field from two-axis magnetometers, body rate from one-axis gyros | seed 000 §8.2–8.3, eqs. 8.14–8.25 |
//! | [`sun_sensor`] | Sun direction in the body frame from the lit tiles' sensor angles | note 000 §7 item 1 |
//! | [`thesis`] | the thesis's generalised solver `Aᵀ = G⁺F` (with its Sun-sensor equation) | seed 000 §8.4, eqs. 8.1–8.2, 8.27–8.31 |
//! | [`wahba_svd`] | optimal attitude from weighted vector pairs by SVD | Markley 1988 |
//! | [`quest`] | the same by QUEST | Shuster and Oh 1981 |
//! | [`triad`] | attitude from two vector pairs | Black 1964; Shuster and Oh 1981 |
//!
//! The physically correct chain is: [`least_squares::magnetic_field_body`] and
//! [`sun_sensor::sun_direction_body`] give two body vectors; the field and Sun models give the
//! same two directions in the reference frame; [`wahba_svd`] (or [`quest`], [`triad`]) gives
//! the attitude. The [`thesis`] solver is kept to reproduce the thesis's tests: its Sun-sensor
//! equation is not geometry (note 000 §0 item 6).

pub mod least_squares;
pub mod quest;
pub mod sun_sensor;
pub mod thesis;
pub mod triad;
pub mod wahba_svd;

use crate::attitude::{Dcm, Quaternion};
use crate::linalg::svd::SvdError;
use crate::linalg::{Mat3, Vec3};

/// Why an attitude (or a body vector) could not be determined.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum DeterminationError {
    /// Fewer observations than the method needs.
    TooFewObservations {
        /// Observations given (or usable).
        count: usize,
        /// Observations needed.
        needed: usize,
    },
    /// Observation `index` has a NaN or infinite component or weight.
    NonFinite {
        /// Index of the observation.
        index: usize,
    },
    /// Observation `index` has a zero-length vector.
    ZeroVector {
        /// Index of the observation.
        index: usize,
    },
    /// Observation `index` has a weight that is not strictly positive.
    BadWeight {
        /// Index of the observation.
        index: usize,
        /// The weight.
        weight: f32,
    },
    /// The observed directions are (numerically) parallel: the rotation about them is not
    /// determined. `measure` is the method's degeneracy measure (`σ₂/σ₁` of the attitude
    /// profile matrix, or `|b₁ × b₂|` for TRIAD).
    Parallel {
        /// The degeneracy measure that fell below the method's threshold.
        measure: f32,
    },
    /// The working tiles do not span the space: the least-squares matrix has rank `rank` < 3.
    NotObservable {
        /// Numerical rank (relative threshold [`least_squares::RANK_REL_TOL`]).
        rank: u8,
    },
    /// The readings do not have one entry per tile.
    LengthMismatch {
        /// Number of tiles.
        tiles: usize,
        /// Number of readings.
        readings: usize,
    },
    /// No working Sun sensor is lit.
    NoSunSensorLit,
    /// Too many rows for the fixed-size linear algebra, or non-finite data inside it.
    Linalg(SvdError),
}

impl From<SvdError> for DeterminationError {
    fn from(e: SvdError) -> Self {
        match e {
            SvdError::RankDeficient { rank, .. } => Self::NotObservable { rank },
            other => Self::Linalg(other),
        }
    }
}

impl core::fmt::Display for DeterminationError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::TooFewObservations { count, needed } => {
                write!(f, "{count} observations, at least {needed} needed")
            }
            Self::NonFinite { index } => write!(f, "observation {index}: NaN or infinite value"),
            Self::ZeroVector { index } => write!(f, "observation {index}: zero-length vector"),
            Self::BadWeight { index, weight } => {
                write!(f, "observation {index}: weight {weight} is not > 0")
            }
            Self::Parallel { measure } => write!(
                f,
                "observed directions are parallel (degeneracy measure {measure:e})"
            ),
            Self::NotObservable { rank } => {
                write!(f, "working tiles span only {rank} dimensions, 3 needed")
            }
            Self::LengthMismatch { tiles, readings } => {
                write!(f, "{tiles} tiles but {readings} readings")
            }
            Self::NoSunSensorLit => write!(f, "no working Sun sensor is lit"),
            Self::Linalg(e) => write!(f, "linear algebra: {e}"),
        }
    }
}

/// One vector observation: the same direction measured in the body frame and known (modelled)
/// in the reference frame, with a weight (Wahba's `aᵢ`; for the optimal covariance use
/// `aᵢ = σᵢ⁻²` with σᵢ the measurement's angular noise in rad). Vectors need not be unit: every
/// solver normalises them.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Observation {
    /// The direction measured in the body frame.
    pub body: Vec3,
    /// The same direction in the reference frame.
    pub reference: Vec3,
    /// Weight `aᵢ > 0`.
    pub weight: f32,
}

#[cfg(feature = "defmt")]
impl defmt::Format for Observation {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "Observation[body ({},{},{}), ref ({},{},{}), w {}]",
            self.body.x,
            self.body.y,
            self.body.z,
            self.reference.x,
            self.reference.y,
            self.reference.z,
            self.weight
        )
    }
}

/// An attitude solution, `v_body = A · v_ref` (see [`crate::attitude`]).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Solution {
    /// The attitude matrix, a proper rotation (det = +1 to f32 rounding).
    pub dcm: Dcm,
    /// The same attitude as a unit quaternion, `q0 ≥ 0`.
    pub quaternion: Quaternion,
    /// Wahba's loss `L(A) = ½ Σ aᵢ |b̂ᵢ − A·r̂ᵢ|²` of this attitude (unit vectors), evaluated
    /// from the residuals (no cancellation): 0 for consistent data.
    pub loss: f32,
}

/// Validated observations: unit vectors and weights.
pub(crate) struct Unit {
    pub body: Vec3,
    pub reference: Vec3,
    pub weight: f32,
}

/// Checks and normalises observation `index`.
pub(crate) fn unit(index: usize, o: &Observation) -> Result<Unit, DeterminationError> {
    if !(o
        .body
        .iter()
        .chain(o.reference.iter())
        .all(|x| x.is_finite())
        && o.weight.is_finite())
    {
        return Err(DeterminationError::NonFinite { index });
    }
    if o.weight <= 0.0 {
        return Err(DeterminationError::BadWeight {
            index,
            weight: o.weight,
        });
    }
    let (nb, nr) = (o.body.norm(), o.reference.norm());
    if nb <= 0.0 || nr <= 0.0 {
        return Err(DeterminationError::ZeroVector { index });
    }
    Ok(Unit {
        body: o.body / nb,
        reference: o.reference / nr,
        weight: o.weight,
    })
}

/// The attitude profile matrix `B = Σ aᵢ b̂ᵢ r̂ᵢᵀ` (Markley 1988) with weights normalised to
/// `Σ aᵢ = 1` (so its entries are O(1) whatever the caller's weight scale), after validating
/// every observation. Needs at least `needed` observations.
pub(crate) fn attitude_profile(
    observations: &[Observation],
    needed: usize,
) -> Result<Mat3, DeterminationError> {
    if observations.len() < needed {
        return Err(DeterminationError::TooFewObservations {
            count: observations.len(),
            needed,
        });
    }
    let mut sum_w = 0.0f32;
    for (i, o) in observations.iter().enumerate() {
        sum_w += unit(i, o)?.weight;
    }
    if !sum_w.is_finite() {
        return Err(DeterminationError::NonFinite { index: 0 });
    }
    let mut b = Mat3::zeros();
    for (i, o) in observations.iter().enumerate() {
        let u = unit(i, o)?;
        b += u.body * u.reference.transpose() * (u.weight / sum_w);
    }
    Ok(b)
}

/// Wahba's loss `½ Σ aᵢ |b̂ᵢ − A r̂ᵢ|²` of `a` over already validated observations.
pub(crate) fn loss(a: &Dcm, observations: &[Observation]) -> f32 {
    observations
        .iter()
        .enumerate()
        .filter_map(|(i, o)| unit(i, o).ok())
        .map(|u| 0.5 * u.weight * (u.body - a.to_body(&u.reference)).norm_squared())
        .sum()
}

/// Smallest `σ₃/σ₁` of the Fisher information matrix [`covariance_rad2`] inverts.
pub const COVARIANCE_MIN_RATIO: f32 = 1.0e-6;

/// The attitude-error covariance (rad², body frame) of the optimal solution, from the Fisher
/// information `F = Σ aᵢ (I − b̂ᵢ b̂ᵢᵀ)`, `P = F⁻¹` (the Fisher information
/// of Shuster and Oh 1981 and Markley 1988). It assumes `aᵢ = σᵢ⁻²` with σᵢ each vector's angular measurement noise (rad, per
/// axis): scale it by the ratio if the weights are only relative. The attitude error `δθ`
/// (small rotation, body frame) has covariance `P`; the 1σ error about body axis k is `√P_kk`.
/// Errors as for the solvers (at least two non-parallel directions).
pub fn covariance_rad2(observations: &[Observation]) -> Result<Mat3, DeterminationError> {
    if observations.len() < 2 {
        return Err(DeterminationError::TooFewObservations {
            count: observations.len(),
            needed: 2,
        });
    }
    let mut fisher = Mat3::zeros();
    for (i, o) in observations.iter().enumerate() {
        let u = unit(i, o)?;
        fisher += (Mat3::identity() - u.body * u.body.transpose()) * u.weight;
    }
    if !fisher.iter().all(|x| x.is_finite()) {
        return Err(DeterminationError::NonFinite { index: 0 });
    }
    let rows = [
        Vec3::new(fisher.m11, fisher.m12, fisher.m13),
        Vec3::new(fisher.m21, fisher.m22, fisher.m23),
        Vec3::new(fisher.m31, fisher.m32, fisher.m33),
    ];
    let svd = crate::linalg::svd::ThinSvd::<3>::new(&rows)?;
    let s = svd.singular_values();
    if s.z <= COVARIANCE_MIN_RATIO * s.x {
        return Err(DeterminationError::Parallel {
            measure: if s.x > 0.0 { s.z / s.x } else { 0.0 },
        });
    }
    // F is symmetric positive definite: F⁻¹ = V Σ⁻¹ Vᵀ.
    let v = svd.v();
    let inv = Mat3::from_diagonal(&Vec3::new(1.0 / s.x, 1.0 / s.y, 1.0 / s.z));
    Ok(v * inv * v.transpose())
}

/// Largest correction (rad) [`refine`] applies.
pub const REFINE_MAX_STEP_RAD: f32 = 0.01;

/// One Gauss–Newton step on Wahba's loss from an attitude close to the optimum (the final
/// step of [`wahba_svd::solve`] and [`quest::solve`]; not part of Markley's or Shuster's
/// papers). With `A' = (I − [δθ×])·A` (δθ a small rotation in the body frame),
/// ```text
/// g = Σ aᵢ (A r̂ᵢ) × b̂ᵢ   (the exact gradient of L at A)
/// H = Σ aᵢ (I − b̂ᵢ b̂ᵢᵀ)  (its Hessian up to terms of the size of the residuals)
/// δθ = −H⁻¹ g,   q' = q ⊗ (1, δθ/2) normalised   (A(q ⊗ p) = A(p)·A(q))
/// ```
/// `g` is formed from the residual cross products, which f32 holds to full relative precision,
/// whereas the attitude profile matrix `B` (and Davenport's `K`) round the data at the level of
/// their largest entries: on the 200 problems of `wahba.json` the step takes Markley's SVD from
/// 1.57e-4° to 4.2e-5° of the f64 optimum (max), and QUEST from 7.1e-4° to 4.5e-5° (README). Since `g` vanishes
/// exactly at the optimum, the step cannot move away from it more than the neglected Hessian
/// terms (relative size = the residuals) times the starting error. (Accepting the step only
/// if the f32 loss decreases was tried and is worse: the loss cannot resolve steps of 1e-6
/// rad.) Skipped if `H` is singular or the step exceeds [`REFINE_MAX_STEP_RAD`].
pub fn refine(start: &Solution, observations: &[Observation]) -> Solution {
    let mut sum_w = 0.0f32;
    let mut g = Vec3::zeros();
    let mut h = Mat3::zeros();
    for (i, o) in observations.iter().enumerate() {
        let Ok(u) = unit(i, o) else {
            return *start;
        };
        sum_w += u.weight;
        g += start.dcm.to_body(&u.reference).cross(&u.body) * u.weight;
        h += (Mat3::identity() - u.body * u.body.transpose()) * u.weight;
    }
    if !(sum_w > 0.0 && sum_w.is_finite()) {
        return *start;
    }
    // Scale-free: divide both by Σaᵢ (δθ is unchanged).
    let Some(h_inv) = (h / sum_w).try_inverse() else {
        return *start;
    };
    let half_step = h_inv * (g / sum_w) * -0.5;
    // Only a refinement: a step beyond REFINE_MAX_STEP_RAD means the start was not near the
    // optimum (it cannot happen after SVD or QUEST); keep the start then.
    if half_step.norm().partial_cmp(&(0.5 * REFINE_MAX_STEP_RAD)) != Some(core::cmp::Ordering::Less)
    {
        return *start;
    }
    let dq = Quaternion {
        q0: 1.0,
        q1: half_step.x,
        q2: half_step.y,
        q3: half_step.z,
    };
    let p = start.quaternion.mul(&dq);
    let Some(q) = Quaternion::new_normalize(p.q0, p.q1, p.q2, p.q3) else {
        return *start;
    };
    solution(q.canonical().to_dcm(), observations)
}

/// Packs a rotation matrix into a [`Solution`].
pub(crate) fn solution(a: Dcm, observations: &[Observation]) -> Solution {
    let quaternion = a.to_quaternion();
    Solution {
        dcm: a,
        quaternion,
        loss: loss(&a, observations),
    }
}
