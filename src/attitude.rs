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
use crate::linalg::{Mat3, Vec3};

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
        self.0 * v_ref
    }

    /// A body-frame vector expressed in the reference frame, `Aᵀ · v_body`.
    pub fn to_reference(&self, v_body: &Vec3) -> Vec3 {
        self.0.transpose() * v_body
    }

    /// The inverse rotation `Aᵀ` (body → reference).
    pub fn transpose(&self) -> Self {
        Self(self.0.transpose())
    }

    /// `self` followed by `next`: the matrix `next · self` (eq. 5.8).
    pub fn then(&self, next: &Self) -> Self {
        Self(next.0 * self.0)
    }

    /// The unit quaternion of this attitude (eqs. 5.19–5.20), with the largest-pivot branch: of
    /// `4q0² = 1 + A11 + A22 + A33`, `4q1² = 1 + A11 − A22 − A33`, … the largest is taken as the
    /// square root and the other components come from the off-diagonal sums and differences,
    /// so no division by a small number occurs. The sign is chosen so that the pivot component
    /// is positive; the result is normalised. Convention: [module docs](self).
    pub fn to_quaternion(&self) -> Quaternion {
        let a = &self.0;
        let t0 = 1.0 + a.m11 + a.m22 + a.m33;
        let t1 = 1.0 + a.m11 - a.m22 - a.m33;
        let t2 = 1.0 - a.m11 + a.m22 - a.m33;
        let t3 = 1.0 - a.m11 - a.m22 + a.m33;
        let q = if t0 >= t1 && t0 >= t2 && t0 >= t3 {
            let q0 = 0.5 * fmath::sqrt(t0);
            let k = 0.25 / q0;
            Quaternion {
                q0,
                q1: (a.m23 - a.m32) * k,
                q2: (a.m31 - a.m13) * k,
                q3: (a.m12 - a.m21) * k,
            }
        } else if t1 >= t2 && t1 >= t3 {
            let q1 = 0.5 * fmath::sqrt(t1);
            let k = 0.25 / q1;
            Quaternion {
                q0: (a.m23 - a.m32) * k,
                q1,
                q2: (a.m12 + a.m21) * k,
                q3: (a.m13 + a.m31) * k,
            }
        } else if t2 >= t3 {
            let q2 = 0.5 * fmath::sqrt(t2);
            let k = 0.25 / q2;
            Quaternion {
                q0: (a.m31 - a.m13) * k,
                q1: (a.m12 + a.m21) * k,
                q2,
                q3: (a.m23 + a.m32) * k,
            }
        } else {
            let q3 = 0.5 * fmath::sqrt(t3);
            let k = 0.25 / q3;
            Quaternion {
                q0: (a.m12 - a.m21) * k,
                q1: (a.m13 + a.m31) * k,
                q2: (a.m23 + a.m32) * k,
                q3,
            }
        };
        Quaternion::new_normalize(q.q0, q.q1, q.q2, q.q3).unwrap_or(Quaternion::IDENTITY)
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
        if !n2.is_finite() || n2 <= 0.0 {
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
