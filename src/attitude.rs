//! Attitude conventions: direction cosine matrices and scalar-first quaternions (seed 000 ch. 5).
//!
//! # The convention, stated once
//! - An attitude is a **DCM `A` that maps reference-frame vectors to body-frame vectors**:
//!   `v_body = A · v_ref` (seed 000 eq. 5.7). Its rows are the body axes expressed in the
//!   reference frame (eq. 5.2). Composition `A'' = A' · A` means "first `A`, then `A'`".
//! - A **quaternion is scalar-first** `(q0, q1, q2, q3)`, `q0 = cos(Φ/2)`,
//!   `(q1, q2, q3) = e · sin(Φ/2)` for a rotation by Φ about the unit axis `e` (eqs. 5.15–5.17),
//!   and its matrix is Shuster/Wertz's passive `A(q)` (eq. 5.18):
//!   ```text
//!   A(q) = [[q0²+q1²−q2²−q3²,  2(q1q2+q0q3),    2(q1q3−q0q2)  ],
//!           [2(q1q2−q0q3),    q0²−q1²+q2²−q3²,  2(q2q3+q0q1)  ],
//!           [2(q1q3+q0q2),    2(q2q3−q0q1),    q0²−q1²−q2²+q3²]]
//!   ```
//! - The **product is Hamilton's** (eq. 5.25 with the thesis's typo `q4 → q0` fixed), and with the
//!   passive `A(q)`: **`A(p ⊗ r) = A(r) · A(p)`**, i.e. in `p ⊗ r` the rotation `p` is performed
//!   first (note 000 §3.7, verified numerically).
//! - Elementary frame rotations `A1, A2, A3` (eq. 5.9) are passive, positive counter-clockwise:
//!   `A3(Φ) = [[cΦ, sΦ, 0], [−sΦ, cΦ, 0], [0, 0, 1]]`.
//!
//! Every function in this crate that takes or returns an attitude links here.
//!
//! nalgebra's own `Quaternion::new(w, i, j, k)` stores `[i, j, k, w]` and its rotations are
//! active; this crate does not use them for attitudes.

use crate::fmath;
use crate::linalg::svd::{self, SvdError};
use crate::linalg::{Mat3, Vec3};

/// Why an attitude could not be built from the data given.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum AttitudeError {
    /// An input is NaN or infinite.
    NonFinite,
    /// The rotation axis has zero length.
    ZeroAxis,
    /// The matrix is too far from rank 3 to define a rotation (its second singular value over
    /// the first is `ratio`).
    Degenerate {
        /// `σ₂/σ₁` of the matrix.
        ratio: f32,
    },
}

impl core::fmt::Display for AttitudeError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NonFinite => write!(f, "NaN or infinite input"),
            Self::ZeroAxis => write!(f, "rotation axis of zero length"),
            Self::Degenerate { ratio } => {
                write!(f, "matrix too close to rank 1 (sigma2/sigma1 = {ratio:e})")
            }
        }
    }
}

/// Euler angles of the 3-2-1 sequence, `A = A1(Φ)·A2(θ)·A3(Ψ)` (first Ψ about axis 3, then θ
/// about the new axis 2, then Φ about the new axis 1; seed 000 §5.3; the Euler angles printed by
/// Simulink's 6DoF block in the thesis's chapter 12). Range: Φ, Ψ in −π..=π, θ in −π/2..=π/2.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Euler321 {
    /// Φ, the last rotation, about axis 1 (roll), rad.
    pub phi_rad: f32,
    /// θ, the second rotation, about axis 2 (pitch), rad.
    pub theta_rad: f32,
    /// Ψ, the first rotation, about axis 3 (yaw), rad.
    pub psi_rad: f32,
}

/// Euler angles of the 3-1-3 sequence, `A = A3(Ψ)·A1(θ)·A3(Φ)` (seed 000 eqs. 5.27–5.28: first
/// Φ about axis 3, then θ about the new axis 1, then Ψ about the new axis 3). Range: Φ, Ψ in
/// −π..=π, θ in 0..=π.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Euler313 {
    /// Φ, the first rotation, about axis 3, rad.
    pub phi_rad: f32,
    /// θ, the second rotation, about axis 1, rad.
    pub theta_rad: f32,
    /// Ψ, the last rotation, about axis 3, rad.
    pub psi_rad: f32,
}

/// A rotation as a unit axis and an angle (seed 000 eqs. 5.12–5.14): the frame rotates by
/// `angle_rad` about `axis` (counter-clockwise, right hand), `A = cosΦ·I + (1 − cosΦ)·e·eᵀ −
/// sinΦ·[e×]`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct AxisAngle {
    /// Unit rotation axis `e` (the same in both frames).
    pub axis: Vec3,
    /// Rotation angle Φ, rad.
    pub angle_rad: f32,
}

#[cfg(feature = "defmt")]
impl defmt::Format for AxisAngle {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "AxisAngle[{},{},{}; {}]",
            self.axis.x,
            self.axis.y,
            self.axis.z,
            self.angle_rad
        )
    }
}

/// Smallest `σ₂/σ₁` [`Dcm::orthonormalize`] accepts.
pub const ORTHONORMALIZE_MIN_RATIO: f32 = 1.0e-4;

/// A proper rotation as a direction cosine matrix, `v_body = A · v_ref` (see the [module
/// docs](self)).
///
/// The invariant `AAᵀ = I`, `det A = +1` holds to f32 rounding for matrices built by this module;
/// [`Dcm::from_matrix_unchecked`] trusts its caller.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Dcm(Mat3);

#[cfg(feature = "defmt")]
impl defmt::Format for Dcm {
    fn format(&self, f: defmt::Formatter) {
        let m = &self.0;
        defmt::write!(
            f,
            "Dcm[[{},{},{}],[{},{},{}],[{},{},{}]]",
            m.m11,
            m.m12,
            m.m13,
            m.m21,
            m.m22,
            m.m23,
            m.m31,
            m.m32,
            m.m33
        )
    }
}

/// A unit quaternion, scalar first, with the passive Shuster/Wertz matrix (see the [module
/// docs](self)). `q` and `−q` are the same attitude.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Quaternion {
    /// Scalar part, `cos(Φ/2)`.
    pub q0: f32,
    /// Vector part along reference x, `e1 sin(Φ/2)`.
    pub q1: f32,
    /// Vector part along reference y, `e2 sin(Φ/2)`.
    pub q2: f32,
    /// Vector part along reference z, `e3 sin(Φ/2)`.
    pub q3: f32,
}

impl Dcm {
    /// The identity attitude (body axes = reference axes).
    pub fn identity() -> Self {
        Self(Mat3::identity())
    }

    /// Wraps a matrix the caller knows to be a proper rotation (`v_body = A · v_ref`).
    pub const fn from_matrix_unchecked(m: Mat3) -> Self {
        Self(m)
    }

    /// The matrix, `v_body = A · v_ref`.
    pub const fn matrix(&self) -> &Mat3 {
        &self.0
    }

    /// A reference-frame vector expressed in the body frame, `A · v_ref`.
    pub fn to_body(&self, v_ref: &Vec3) -> Vec3 {
        crate::linalg::mat_vec(&self.0, v_ref)
    }

    /// A body-frame vector expressed in the reference frame, `Aᵀ · v_body`.
    pub fn to_reference(&self, v_body: &Vec3) -> Vec3 {
        crate::linalg::mat_vec(&self.0.transpose(), v_body)
    }

    /// The inverse rotation `Aᵀ` (body → reference).
    pub fn transpose(&self) -> Self {
        Self(self.0.transpose())
    }

    /// `self` followed by `next`: the matrix `next · self` (eq. 5.8).
    pub fn then(&self, next: &Self) -> Self {
        Self(next.0 * self.0)
    }

    /// Elementary frame rotation about axis 1 (x) by `phi_rad`, `A1(Φ)` (eq. 5.9).
    pub fn a1(phi_rad: f32) -> Self {
        let (s, c) = fmath::sincos(phi_rad);
        Self(Mat3::new(1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c))
    }

    /// Elementary frame rotation about axis 2 (y) by `phi_rad`, `A2(Φ)` (eq. 5.9).
    pub fn a2(phi_rad: f32) -> Self {
        let (s, c) = fmath::sincos(phi_rad);
        Self(Mat3::new(c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c))
    }

    /// Elementary frame rotation about axis 3 (z) by `phi_rad`, `A3(Φ)` (eq. 5.9).
    pub fn a3(phi_rad: f32) -> Self {
        let (s, c) = fmath::sincos(phi_rad);
        Self(Mat3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0))
    }

    /// The quaternion of this attitude (seed 000 eqs. 5.19–5.20), by the largest-pivot branch:
    /// of `q0², q1², q2², q3²` (proportional to `1 + tr A`, `1 + A11 − A22 − A33`, …) the
    /// largest is taken from its square root and the other three from the off-diagonal sums and
    /// differences divided by it, so no division by a small number occurs (Shepperd 1978).
    /// The result is normalised and has `q0 ≥ 0`. Convention: [module docs](self).
    ///
    /// Accuracy (f32): round trip `q → A → q` within 2.4e-7 per component over 20 000 random
    /// quaternions including the near-180° cases (`tests/attitude.rs`).
    pub fn to_quaternion(&self) -> Quaternion {
        let m = &self.0;
        let tr = m.m11 + m.m22 + m.m33;
        // Pivots 4·qk² (up to the common +1).
        let p0 = tr;
        let p1 = m.m11 - m.m22 - m.m33;
        let p2 = -m.m11 + m.m22 - m.m33;
        let p3 = -m.m11 - m.m22 + m.m33;
        // The largest pivot's component `k`, the pivot, and the three off-diagonal pairs whose
        // sums are the other components times 4·qk, in component order: qk = ½√(1 + pivot)
        // (q0 = ½√(1 + tr A), q1 = ½√(1 + A11 − A22 − A33), …), then q1 = (A23 − A32)/(4q0), …
        // A pair is two indices into the column-major elements (A_rc at r + 3c, from 0) and
        // whether the second is subtracted: `a − b` as the sum `a + (−b)`, the same IEEE 754
        // operation (the MSP430's soft-float subtraction flips the sign and adds), so one
        // shared tail serves the four branches.
        let (k, pivot, pairs): (usize, f32, &[(u8, u8, bool); 3]) =
            if p0 >= p1 && p0 >= p2 && p0 >= p3 {
                // (A23 − A32, A31 − A13, A12 − A21)
                (0, p0, &[(7, 5, true), (2, 6, true), (3, 1, true)])
            } else if p1 >= p2 && p1 >= p3 {
                // (A23 − A32, A12 + A21, A13 + A31)
                (1, p1, &[(7, 5, true), (3, 1, false), (6, 2, false)])
            } else if p2 >= p3 {
                // (A31 − A13, A12 + A21, A23 + A32)
                (2, p2, &[(2, 6, true), (3, 1, false), (7, 5, false)])
            } else {
                // (A12 − A21, A13 + A31, A23 + A32)
                (3, p3, &[(3, 1, true), (6, 2, false), (7, 5, false)])
            };
        let qk = 0.5 * fmath::sqrt(1.0 + pivot);
        let scale = 0.25 / qk;
        let a = m.as_slice();
        let at = |i: u8| a.get(usize::from(i)).copied().unwrap_or(0.0);
        let mut q = [qk; 4];
        let mut pairs = pairs.iter();
        for (j, out) in q.iter_mut().enumerate() {
            if j != k {
                if let Some(&(x, y, minus)) = pairs.next() {
                    let y = if minus { -at(y) } else { at(y) };
                    *out = (at(x) + y) * scale;
                }
            }
        }
        let [q0, q1, q2, q3] = q;
        // `q0 ≥ 0`: the sign flipped by negation, which is what multiplying by −1 gives bit for
        // bit (IEEE 754; a NaN, whatever its sign, gives the identity below either way), without
        // four multiplications (a soft-float library call each on the MSP430)
        let (q0, q1, q2, q3) = if q0 >= 0.0 {
            (q0, q1, q2, q3)
        } else {
            (-q0, -q1, -q2, -q3)
        };
        Quaternion::new_normalize(q0, q1, q2, q3).unwrap_or(Quaternion::IDENTITY)
    }

    /// The attitude of 3-2-1 Euler angles, `A = A1(Φ)·A2(θ)·A3(Ψ)` ([`Euler321`]).
    pub fn from_euler_321(e: &Euler321) -> Self {
        Self(Self::a1(e.phi_rad).0 * Self::a2(e.theta_rad).0 * Self::a3(e.psi_rad).0)
    }

    /// The 3-2-1 Euler angles of this attitude ([`Euler321`]): `Φ = atan2(A23, A33)`,
    /// `θ = atan2(−A13, (A1(Φ)ᵀA)33)`, `Ψ = atan2(−(A1(Φ)ᵀA)21, (A1(Φ)ᵀA)22)`. Ψ is taken from
    /// the matrix with the Φ rotation removed, so the three angles always rebuild `A` (at
    /// θ = ±90°, where only Φ ∓ Ψ is defined, Φ comes from rounding and Ψ absorbs it).
    pub fn to_euler_321(&self) -> Euler321 {
        let m = &self.0;
        let phi = fmath::atan2(m.m23, m.m33);
        let (s, c) = fmath::sincos(phi);
        // Rows 2 and 3 of A1(Φ)ᵀ·A = A2(θ)·A3(Ψ): row 2 = (−sΨ, cΨ, 0), (row 3)₃ = cθ.
        let r21 = c * m.m21 - s * m.m31;
        let r22 = c * m.m22 - s * m.m32;
        let r33 = s * m.m23 + c * m.m33;
        Euler321 {
            phi_rad: phi,
            theta_rad: fmath::atan2(-m.m13, r33),
            psi_rad: fmath::atan2(-r21, r22),
        }
    }

    /// The attitude of 3-1-3 Euler angles, `A = A3(Ψ)·A1(θ)·A3(Φ)` ([`Euler313`]).
    pub fn from_euler_313(e: &Euler313) -> Self {
        Self(Self::a3(e.psi_rad).0 * Self::a1(e.theta_rad).0 * Self::a3(e.phi_rad).0)
    }

    /// The 3-1-3 Euler angles of this attitude ([`Euler313`]): `Φ = atan2(A31, −A32)` (eq. 5.28
    /// with the quadrant kept), θ and Ψ from `A·A3(Φ)ᵀ = A3(Ψ)·A1(θ)`, so the angles always
    /// rebuild `A` (at θ = 0 or π only Φ ± Ψ is defined).
    pub fn to_euler_313(&self) -> Euler313 {
        let m = &self.0;
        let phi = fmath::atan2(m.m31, -m.m32);
        let (s, c) = fmath::sincos(phi);
        // Columns of A·A3(Φ)ᵀ: col 1 = (cΨ, −sΨ, 0), col 2 = (sΨcθ, cΨcθ, −sθ).
        let r11 = c * m.m11 + s * m.m12;
        let r21 = c * m.m21 + s * m.m22;
        let r32 = -s * m.m31 + c * m.m32;
        Euler313 {
            phi_rad: phi,
            theta_rad: fmath::atan2(-r32, m.m33),
            psi_rad: fmath::atan2(-r21, r11),
        }
    }

    /// The attitude of a rotation by `angle_rad` about `axis` (normalised here; eq. 5.13).
    pub fn from_axis_angle(axis: &Vec3, angle_rad: f32) -> Result<Self, AttitudeError> {
        Ok(Quaternion::from_axis_angle(axis, angle_rad)?.to_dcm())
    }

    /// Axis and angle of this attitude, angle in 0..=π (through [`Dcm::to_quaternion`], so it is
    /// accurate at small angles and at π, unlike `acos((tr A − 1)/2)`).
    pub fn to_axis_angle(&self) -> AxisAngle {
        self.to_quaternion().to_axis_angle()
    }

    /// The rotation angle (0..=π, rad) between this attitude and `other`: the angle of
    /// `other · selfᵀ`, from the skew part of the product (not its trace, which loses all
    /// precision at small angles). Measured error (f32): ≤ 6e-7 rad over 2000 random pairs with
    /// angles from 0 to π (`cargo test --test attitude -- --nocapture`).
    pub fn angle_to(&self, other: &Self) -> f32 {
        Self(other.0 * self.0.transpose()).to_axis_angle().angle_rad
    }

    /// The proper rotation nearest to a near-rotation `m` in the Frobenius norm: the orthogonal
    /// polar factor `U·diag(1, 1, det U·det V)·Vᵀ` of `m = U·Σ·Vᵀ` (one-sided Jacobi SVD,
    /// [`crate::linalg::svd`]). Use it on a matrix that drifted from orthogonality or on the
    /// raw output of the thesis solver. Errors: NaN/∞ entries, or `σ₂/σ₁` below
    /// [`ORTHONORMALIZE_MIN_RATIO`].
    pub fn orthonormalize(m: &Mat3) -> Result<Self, AttitudeError> {
        match svd::nearest_rotation(m, ORTHONORMALIZE_MIN_RATIO) {
            Ok((r, _)) => Ok(Self(r)),
            Err(SvdError::RankDeficient { ratio, .. }) => Err(AttitudeError::Degenerate { ratio }),
            Err(_) => Err(AttitudeError::NonFinite),
        }
    }

    /// `det A`, which is +1 for a proper rotation (a quick validity check, seed 000 §5.1).
    pub fn determinant(&self) -> f32 {
        self.0.determinant()
    }

    /// `max |AAᵀ − I|` over the entries: the orthogonality defect.
    pub fn orthogonality_error(&self) -> f32 {
        (self.0 * self.0.transpose() - Mat3::identity()).amax()
    }
}

impl Quaternion {
    /// The identity attitude.
    pub const IDENTITY: Self = Self {
        q0: 1.0,
        q1: 0.0,
        q2: 0.0,
        q3: 0.0,
    };

    /// A quaternion from its four components, scalar first, normalised. `None` if the norm is
    /// zero or not finite.
    pub fn new_normalize(q0: f32, q1: f32, q2: f32, q3: f32) -> Option<Self> {
        let n2 = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3;
        if !n2.is_finite() || !(n2 > 0.0) {
            return None;
        }
        let k = 1.0 / fmath::sqrt(n2);
        Some(Self {
            q0: q0 * k,
            q1: q1 * k,
            q2: q2 * k,
            q3: q3 * k,
        })
    }

    /// The conjugate (the inverse rotation), eq. 5.24.
    pub fn conjugate(&self) -> Self {
        Self {
            q0: self.q0,
            q1: -self.q1,
            q2: -self.q2,
            q3: -self.q3,
        }
    }

    /// The Hamilton product `self ⊗ r` (eq. 5.25, typo fixed). `A(p ⊗ r) = A(r) · A(p)`: the
    /// rotation `self` is performed first, then `r`.
    pub fn mul(&self, r: &Self) -> Self {
        let p = self;
        Self {
            q0: p.q0 * r.q0 - p.q1 * r.q1 - p.q2 * r.q2 - p.q3 * r.q3,
            q1: p.q1 * r.q0 + p.q2 * r.q3 - p.q3 * r.q2 + p.q0 * r.q1,
            q2: -p.q1 * r.q3 + p.q2 * r.q0 + p.q3 * r.q1 + p.q0 * r.q2,
            q3: p.q1 * r.q2 - p.q2 * r.q1 + p.q3 * r.q0 + p.q0 * r.q3,
        }
    }

    /// The quaternion of a rotation by `angle_rad` about `axis` (normalised here):
    /// `q0 = cos(Φ/2)`, `(q1, q2, q3) = e·sin(Φ/2)` (eqs. 5.15–5.17).
    pub fn from_axis_angle(axis: &Vec3, angle_rad: f32) -> Result<Self, AttitudeError> {
        if !angle_rad.is_finite() || !axis.iter().all(|x| x.is_finite()) {
            return Err(AttitudeError::NonFinite);
        }
        let n = axis.norm();
        if !(n > 0.0) {
            return Err(AttitudeError::ZeroAxis);
        }
        let e = axis / n;
        let (s, c) = fmath::sincos(0.5 * angle_rad);
        Ok(Self {
            q0: c,
            q1: e.x * s,
            q2: e.y * s,
            q3: e.z * s,
        })
    }

    /// Axis and angle, angle in 0..=π: `Φ = 2·atan2(|q_v|, |q0|)`, `e = ±q_v/|q_v|` (sign
    /// chosen with `q0` so that Φ ≤ π). For the identity (Φ = 0) the axis is reference x.
    pub fn to_axis_angle(&self) -> AxisAngle {
        let v = Vec3::new(self.q1, self.q2, self.q3);
        let n = v.norm();
        let s = if self.q0 >= 0.0 { 1.0 } else { -1.0 };
        if !(n > 0.0) {
            return AxisAngle {
                axis: Vec3::x(),
                angle_rad: 0.0,
            };
        }
        AxisAngle {
            axis: v * (s / n),
            angle_rad: 2.0 * fmath::atan2(n, fmath::abs(self.q0)),
        }
    }

    /// The rotation angle (0..=π, rad) between the attitudes `self` and `other`:
    /// `2·atan2(|(q_self* ⊗ q_other)_v|, |(…)_0|)`.
    pub fn angle_to(&self, other: &Self) -> f32 {
        self.conjugate().mul(other).to_axis_angle().angle_rad
    }

    /// The same attitude with `q0 ≥ 0` (`q` and `−q` are the same rotation).
    pub fn canonical(&self) -> Self {
        if !(self.q0 >= 0.0) {
            Self {
                q0: -self.q0,
                q1: -self.q1,
                q2: -self.q2,
                q3: -self.q3,
            }
        } else {
            *self
        }
    }

    /// The Euclidean norm √(q0² + q1² + q2² + q3²) (eq. 5.26), 1 for an attitude.
    pub fn norm(&self) -> f32 {
        fmath::sqrt(self.q0 * self.q0 + self.q1 * self.q1 + self.q2 * self.q2 + self.q3 * self.q3)
    }

    /// The quaternion of a DCM, largest-pivot branch ([`Dcm::to_quaternion`]).
    pub fn from_dcm(a: &Dcm) -> Self {
        a.to_quaternion()
    }

    /// The passive matrix `A(q)` (eq. 5.18), `v_body = A(q) · v_ref`.
    pub fn to_dcm(&self) -> Dcm {
        let (q0, q1, q2, q3) = (self.q0, self.q1, self.q2, self.q3);
        Dcm(Mat3::new(
            q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3,
            2.0 * (q1 * q2 + q0 * q3),
            2.0 * (q1 * q3 - q0 * q2),
            2.0 * (q1 * q2 - q0 * q3),
            q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3,
            2.0 * (q2 * q3 + q0 * q1),
            2.0 * (q1 * q3 + q0 * q2),
            2.0 * (q2 * q3 - q0 * q1),
            q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3,
        ))
    }
}
