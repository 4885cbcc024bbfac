//! Attitude determination (seed 000 chapter 8; note 000 §3.8, §7 items 1–4).
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A · v_ref`, scalar-first quaternions.
//!
//! | module | what | source |
//! |---|---|---|
//! | [`mekf`] | multiplicative extended Kalman filter: attitude, gyro bias, magnetometer bias (the flight estimator) | Lefferts, Markley and Shuster 1982; Markley and Crassidis 2014 §6.2.4 |
//! | [`least_squares`] | body magnetic field from two-axis magnetometers, body rate from one-axis gyros | seed 000 §8.2–8.3, eqs. 8.14–8.25 |
//! | [`sun_sensor`] | Sun direction in the body frame from the lit tiles' sensor angles | note 000 §7 item 1 |
//! | [`pseudoinverse`] | attitude by pseudoinverse, `Aᵀ = G⁺F`: the thesis's generalised solver (with its Sun-sensor equation) | seed 000 §8.4, eqs. 8.1–8.2, 8.27–8.31 |
//! | [`wahba_svd`] | optimal attitude from weighted vector pairs by SVD | Markley 1988 |
//! | [`quest`] | the same by QUEST | Shuster and Oh 1981 |
//! | [`triad`] | attitude from two vector pairs | Black 1964; Shuster and Oh 1981 |
//!
//! The physically correct chain is: [`least_squares::magnetic_field_body`] and
//! [`sun_sensor::sun_direction_body`] give two body vectors; the field and Sun models give the
//! same two directions in the reference frame; [`wahba_svd`] (or [`quest`], [`triad`]) gives
//! the attitude. The [`pseudoinverse`] solver is kept to reproduce the thesis's tests: its Sun-sensor
//! equation is not geometry (note 000 §0 item 6).

pub mod least_squares;
pub mod mekf;
pub mod pseudoinverse;
pub mod quest;
pub mod sun_sensor;
pub mod triad;
pub mod wahba_svd;

use crate::attitude::{Dcm, Quaternion};
use crate::fmath;
use crate::linalg::svd::SvdError;
use crate::linalg::{div, dot, finite3, mat_vec, Mat3, Vec3};

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
        /// Numerical rank (relative threshold [`least_squares::RANK_REL_TOL`] on the singular
        /// values, or [`least_squares::GRAM_REL_TOL`] on the eigenvalues of the Gram matrix
        /// for the cached operator).
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
    /// Wahba's loss `L(A) = ½ Σ aᵢ |b̂ᵢ − A·r̂ᵢ|²` of this attitude (unit vectors), without
    /// cancellation (0 for consistent data): from the residuals ([`triad`],
    /// [`quest::solve_raw`], [`wahba_svd::solve_raw`] with three or more vectors), in closed
    /// form at the optimum ([`wahba_svd`] with two vectors), or as the Gauss–Newton model's
    /// value after [`refine`] ([`quest::solve`], [`wahba_svd::solve`] with three or more).
    /// On `wahba.json` all are within `1e-6 + 1e-3·L` of the f64 optimum's loss.
    pub loss: f32,
}

/// A validated observation: unit vectors and weight.
#[derive(Copy, Clone)]
pub(crate) struct Unit {
    pub body: Vec3,
    pub reference: Vec3,
    pub weight: f32,
}

impl Unit {
    /// Placeholder (weight 0: contributes nothing to any sum).
    const ZERO: Self = Self {
        body: Vec3::new(0.0, 0.0, 0.0),
        reference: Vec3::new(0.0, 0.0, 0.0),
        weight: 0.0,
    };
}

/// `v/|v|` given `|v|² > 0` (`fmath::sqrt`; nalgebra's `normalize` calls `libm`). Three
/// divisions rather than a reciprocal and three products: one rounding per component, for
/// about the same cycles on the MSP430 (417 per division, 266 per product).
pub(crate) fn scaled_unit(v: &Vec3, norm_squared: f32) -> Vec3 {
    div(v, fmath::sqrt(norm_squared))
}

/// Checks and normalises observation `index`. A vector whose squared length overflows f32
/// (`|v|` > 1.8e19) is refused as [`DeterminationError::NonFinite`], one whose squared length
/// underflows to 0 (`|v|` < 1e-19 or so) as [`DeterminationError::ZeroVector`].
pub(crate) fn unit(index: usize, o: &Observation) -> Result<Unit, DeterminationError> {
    if !(finite3(&o.body) && finite3(&o.reference) && o.weight.is_finite()) {
        return Err(DeterminationError::NonFinite { index });
    }
    if !(o.weight > 0.0) {
        return Err(DeterminationError::BadWeight {
            index,
            weight: o.weight,
        });
    }
    let (nb2, nr2) = (dot(&o.body, &o.body), dot(&o.reference, &o.reference));
    // sums of squares of finite numbers: 0, positive or +∞, never NaN (`!(nb2 > 0.0)` here lets
    // LLVM turn the finiteness test below into two comparison calls: +92 B on the MSP430)
    if nb2 == 0.0 || nr2 == 0.0 {
        return Err(DeterminationError::ZeroVector { index });
    }
    if !(nb2.is_finite() && nr2.is_finite()) {
        return Err(DeterminationError::NonFinite { index });
    }
    Ok(Unit {
        body: scaled_unit(&o.body, nb2),
        reference: scaled_unit(&o.reference, nr2),
        weight: o.weight,
    })
}

/// How many normalised observations [`Units`] keeps (the others are normalised again when
/// iterated): two (the flight case, Sun and field), 2 × 28 B of stack.
pub(crate) const CACHED_UNITS: usize = 2;

/// The observations, validated once and normalised (the first [`CACHED_UNITS`] kept), with
/// the sum of their weights.
pub(crate) struct Units<'a> {
    observations: &'a [Observation],
    cache: [Unit; CACHED_UNITS],
    /// `Σ aᵢ` (finite, > 0).
    pub sum_w: f32,
}

impl<'a> Units<'a> {
    /// Validates every observation (at least `needed` of them, and at least one).
    pub(crate) fn new(
        observations: &'a [Observation],
        needed: usize,
    ) -> Result<Self, DeterminationError> {
        if core::cmp::max(needed, 1) > observations.len() {
            return Err(DeterminationError::TooFewObservations {
                count: observations.len(),
                needed,
            });
        }
        let mut cache = [Unit::ZERO; CACHED_UNITS];
        let mut sum_w = 0.0f32;
        for (i, o) in observations.iter().enumerate() {
            let u = unit(i, o)?;
            sum_w += u.weight;
            if let Some(slot) = cache.get_mut(i) {
                *slot = u;
            }
        }
        if !sum_w.is_finite() {
            return Err(DeterminationError::NonFinite { index: 0 });
        }
        Ok(Self {
            observations,
            cache,
            sum_w,
        })
    }

    /// The normalised observations in order (already validated: cannot fail).
    pub(crate) fn iter(&self) -> impl Iterator<Item = Unit> + '_ {
        self.observations
            .iter()
            .enumerate()
            .map(|(i, o)| match self.cache.get(i) {
                Some(u) => *u,
                None => unit(i, o).unwrap_or(Unit::ZERO),
            })
    }

    /// The first two (cached) observations.
    pub(crate) fn first_two(&self) -> (&Unit, &Unit) {
        let [u1, u2, ..] = &self.cache;
        (u1, u2)
    }

    /// Number of observations.
    pub(crate) fn len(&self) -> usize {
        self.observations.len()
    }
}

/// The attitude profile matrix `B = Σ aᵢ b̂ᵢ r̂ᵢᵀ` (Markley 1988) with weights normalised to
/// `Σ aᵢ = 1` (so its entries are O(1) whatever the caller's weight scale).
pub(crate) fn attitude_profile(units: &Units) -> Mat3 {
    let mut b = Mat3::zeros();
    for u in units.iter() {
        b += (u.body * u.weight) * u.reference.transpose();
    }
    b * (1.0 / units.sum_w)
}

/// Wahba's loss `½ Σ aᵢ |b̂ᵢ − A r̂ᵢ|²` of `a`, from the residuals (no cancellation).
pub(crate) fn loss(a: &Dcm, units: &Units) -> f32 {
    0.5 * units
        .iter()
        .map(|u| {
            let d = u.body - mat_vec(a.matrix(), &u.reference);
            u.weight * dot(&d, &d)
        })
        .sum::<f32>()
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
    if 2 > observations.len() {
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
    if !(s.z > COVARIANCE_MIN_RATIO * s.x) {
        return Err(DeterminationError::Parallel {
            measure: if s.x > 0.0 { s.z / s.x } else { 0.0 },
        });
    }
    // F is symmetric positive definite: F⁻¹ = V Σ⁻¹ Vᵀ.
    Ok(svd.v_diag_vt(&Vec3::new(1.0 / s.x, 1.0 / s.y, 1.0 / s.z)))
}

/// Largest correction (rad) [`refine`] applies.
pub const REFINE_MAX_STEP_RAD: f32 = 0.01;

/// One Gauss–Newton step on Wahba's loss from an attitude close to the optimum (the final
/// step of [`wahba_svd::solve`] with three or more observations and of [`quest::solve`]; not
/// part of Markley's or Shuster's papers). With `A' = (I − [δθ×])·A` (δθ a small rotation in
/// the body frame),
/// ```text
/// g = Σ aᵢ (A r̂ᵢ) × b̂ᵢ   (the exact gradient of L at A)
/// H = Σ aᵢ (I − b̂ᵢ b̂ᵢᵀ)  (its Hessian up to terms of the size of the residuals)
/// δθ = −H⁻¹ g,   q' = q ⊗ (1, δθ/2) normalised   (A(q ⊗ p) = A(p)·A(q))
/// L(A') = L(A) + ½ gᵀδθ  (the Gauss–Newton model's value at its minimum)
/// ```
/// `g` is formed from the residual cross products, which f32 holds to full relative precision,
/// whereas the attitude profile matrix `B` (and Davenport's `K`) round the data at the level of
/// their largest entries: on the 200 problems of `wahba.json` the step takes Markley's SVD and
/// QUEST to a few 1e-5° of the f64 optimum (`docs/accuracy.md`). Since `g` vanishes exactly at the
/// optimum, the step cannot move away from it more than the neglected Hessian terms (relative
/// size = the residuals) times the starting error. (Accepting the step only if the f32 loss decreases
/// was tried and is worse: the loss cannot resolve steps of 1e-6 rad.) `H⁻¹g` is its adjugate
/// times `g` over its determinant; `q'` is normalised by `1 − ½|δθ/2|²` (exact to f32 for the
/// steps allowed). Skipped if `H` is singular or the step exceeds [`REFINE_MAX_STEP_RAD`].
/// The loss of the result is the model's (one pass over the observations instead of two; its
/// error is third order in the step).
pub fn refine(start: &Solution, observations: &[Observation]) -> Solution {
    match Units::new(observations, 1) {
        Ok(units) => refine_units(start, &units),
        Err(_) => *start,
    }
}

/// [`refine`] over validated observations.
pub(crate) fn refine_units(start: &Solution, units: &Units) -> Solution {
    let a = &start.dcm;
    let mut g = Vec3::zeros();
    let mut l2 = 0.0f32;
    // S = Σ aᵢ b̂ᵢ b̂ᵢᵀ (symmetric: six entries); H = (Σ aᵢ)·I − S.
    let (mut s11, mut s12, mut s13, mut s22, mut s23, mut s33) = (0.0f32, 0.0, 0.0, 0.0, 0.0, 0.0);
    for u in units.iter() {
        let ar = mat_vec(a.matrix(), &u.reference);
        let d = u.body - ar;
        l2 += u.weight * d.norm_squared();
        // (A r̂) × b̂ = (A r̂) × (b̂ − A r̂)
        g += ar.cross(&d) * u.weight;
        let wb = u.body * u.weight;
        s11 += wb.x * u.body.x;
        s12 += wb.x * u.body.y;
        s13 += wb.x * u.body.z;
        s22 += wb.y * u.body.y;
        s23 += wb.y * u.body.z;
        s33 += wb.z * u.body.z;
    }
    // Scale-free: divide H and g by Σaᵢ (δθ is unchanged).
    let k = 1.0 / units.sum_w;
    let (h11, h22, h33) = (1.0 - s11 * k, 1.0 - s22 * k, 1.0 - s33 * k);
    let (h12, h13, h23) = (-s12 * k, -s13 * k, -s23 * k);
    let gk = g * k;
    // adj(H) (symmetric) and det H.
    let c11 = h22 * h33 - h23 * h23;
    let c12 = h13 * h23 - h12 * h33;
    let c13 = h12 * h23 - h13 * h22;
    let c22 = h11 * h33 - h13 * h13;
    let c23 = h12 * h13 - h11 * h23;
    let c33 = h11 * h22 - h12 * h12;
    let det = h11 * c11 + h12 * c12 + h13 * c13;
    if !(det > 0.0 && det.is_finite()) {
        return *start;
    }
    // δθ/2 = −½ H⁻¹ g
    let f = -0.5 / det;
    let half_step = Vec3::new(
        (c11 * gk.x + c12 * gk.y + c13 * gk.z) * f,
        (c12 * gk.x + c22 * gk.y + c23 * gk.z) * f,
        (c13 * gk.x + c23 * gk.y + c33 * gk.z) * f,
    );
    // Only a refinement: a step beyond REFINE_MAX_STEP_RAD means the start was not near the
    // optimum (it cannot happen after SVD or QUEST); keep the start then.
    let h2 = half_step.norm_squared();
    let limit = 0.5 * REFINE_MAX_STEP_RAD;
    if !h2.is_finite() || h2 >= limit * limit {
        return *start;
    }
    let dq = Quaternion {
        q0: 1.0,
        q1: half_step.x,
        q2: half_step.y,
        q3: half_step.z,
    };
    // |q ⊗ dq|² = 1 + |δθ/2|²: 1/√(1 + x) = 1 − x/2 + 3x²/8 − …, and 3x²/8 < 3e-11 here.
    let p = start.quaternion.mul(&dq);
    let n = 1.0 - 0.5 * h2;
    let q = Quaternion {
        q0: p.q0 * n,
        q1: p.q1 * n,
        q2: p.q2 * n,
        q3: p.q3 * n,
    }
    .canonical();
    // L(A') = L(A) + gᵀδθ + ½ δθᵀHδθ = L(A) + ½ gᵀδθ at δθ = −H⁻¹g (unnormalised g).
    let model = 0.5 * l2 + g.dot(&half_step);
    Solution {
        dcm: q.to_dcm(),
        quaternion: q,
        loss: if model > 0.0 { model } else { 0.0 },
    }
}

/// Packs a rotation matrix into a [`Solution`] with its loss over `units`.
pub(crate) fn solution(a: Dcm, units: &Units) -> Solution {
    let quaternion = a.to_quaternion();
    Solution {
        dcm: a,
        quaternion,
        loss: loss(&a, units),
    }
}
