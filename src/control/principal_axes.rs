//! Principal axes of inertia by cyclic Jacobi rotations (seed 000 ch. 9, eqs. 9.18–9.22;
//! note 000 §3.9 and §7.9).
//!
//! # Inputs and outputs
//! | name | meaning | unit, frame |
//! |---|---|---|
//! | `inertia_body` | inertia tensor `I` about the centre of mass | kg·m², body UVW |
//! | `e` | `E`: rows are the principal axes A, B, C expressed in UVW, `v_abc = E · v_uvw` | — |
//! | `moments` | `I' = diag(I_a, I_b, I_c) = E · I · Eᵀ` (the thesis prints `I = E I' Eᵀ`, a typo) | kg·m² |
//!
//! # Ordering rule (the thesis's, note 000 §3.9)
//! Row k of `E` is the eigenvector closest to body axis k (the assignment of eigenvectors to axes
//! that maximises the sum of `|E_kk|` over the six permutations), its sign makes `E_kk > 0`,
//! and `E` is right-handed (`row1 × row2 = row3`); if the signs leave `det E = −1`, the row with
//! the smallest `|E_kk|` is negated (its diagonal is then the only negative one, and tiny).
//!
//! # Algorithm and accuracy
//! Cyclic Jacobi (Golub & Van Loan, *Matrix Computations*, §8.5): plane rotations that zero the
//! off-diagonal terms one at a time, at most [`MAX_SWEEPS`] sweeps, stopping when the
//! off-diagonal norm is below `4 ε_f32` times the diagonal norm. Jacobi is accurate for nearly
//! degenerate tensors (the thesis's `I_a` and `I_c` differ by 0.6 %). In f32 the eigenvectors of a
//! pair of moments that differ by `gap` can only be known to about `ε · ‖I‖ / gap`, because the
//! tensor itself is rounded to f32: for the thesis tensor that is 6e-8 · 7.3e-3 / 4.1e-5 ≈ 1e-5.
//! The test `tests/control.rs` holds `E` within 2e-5 of the thesis's printed matrix
//! (worst element 2.2e-6 measured) and `I'` within 1e-6 relative (2.9e-7 measured).

use core::fmt;

use crate::fmath;
use crate::linalg::{Mat3, Vec3};

/// Maximum number of Jacobi sweeps (each sweep visits the three planes). Convergence is
/// quadratic: four sweeps suffice for f32 on every tensor tried.
pub const MAX_SWEEPS: usize = 12;

/// Errors of [`principal_axes`] and [`symmetric_eigen`].
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum PrincipalAxesError {
    /// An element of the tensor is NaN or infinite.
    NotFinite,
    /// The tensor is not symmetric: the largest asymmetry `|I_ij − I_ji|` is given.
    NotSymmetric(f32),
    /// A principal moment is not positive, or the moments violate the triangle inequality
    /// `I_a + I_b ≥ I_c` (eqs. 9.13–9.16): not the inertia of a physical body.
    NotPhysical(Vec3Moments),
    /// Jacobi did not converge within [`MAX_SWEEPS`] sweeps (not seen for finite input).
    NoConvergence,
}

/// Three principal moments, kg·m² (carried by [`PrincipalAxesError::NotPhysical`]).
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Vec3Moments(pub [f32; 3]);

impl fmt::Display for PrincipalAxesError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotFinite => write!(f, "inertia tensor has a NaN or infinite element"),
            Self::NotSymmetric(d) => {
                write!(f, "inertia tensor not symmetric (|I_ij - I_ji| = {d})")
            }
            Self::NotPhysical(m) => write!(f, "principal moments {:?} kg·m² are not physical", m.0),
            Self::NoConvergence => write!(f, "Jacobi eigen-decomposition did not converge"),
        }
    }
}

/// The principal axes of a body: `E` (rows = axes A, B, C in body UVW) and the moments.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PrincipalAxes {
    /// `E`: rows are the principal axes in body UVW, `v_abc = E · v_uvw`.
    pub e: Mat3,
    /// `(I_a, I_b, I_c)`, kg·m², in the order of the rows of `E`.
    pub moments: Vec3,
    /// The body inertia tensor `I` (kg·m², UVW) the axes were computed from.
    pub inertia_body: Mat3,
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi: returns `(values, vectors)`
/// with `m = V · diag(values) · Vᵀ`, eigenvectors in the **columns** of `V`, unordered.
///
/// Symmetric input is required (`|m_ij − m_ji|` ≤ 1e-6 relative to the largest element); the
/// symmetric part is used.
pub fn symmetric_eigen(m: &Mat3) -> Result<(Vec3, Mat3), PrincipalAxesError> {
    if m.iter().any(|x| !x.is_finite()) {
        return Err(PrincipalAxesError::NotFinite);
    }
    let scale = m
        .iter()
        .fold(0.0f32, |acc, x| fmath::max(acc, fmath::abs(*x)));
    let asym = (m - m.transpose())
        .iter()
        .fold(0.0f32, |acc, x| fmath::max(acc, fmath::abs(*x)));
    if asym > 1e-6 * scale {
        return Err(PrincipalAxesError::NotSymmetric(asym));
    }
    let mut a = symmetric_part(m);
    let mut v = Mat3::identity();
    if scale == 0.0 {
        return Ok((Vec3::zeros(), v));
    }
    for _ in 0..MAX_SWEEPS {
        let off = a.m12 * a.m12 + a.m13 * a.m13 + a.m23 * a.m23;
        let diag = a.m11 * a.m11 + a.m22 * a.m22 + a.m33 * a.m33;
        if (4.0 * f32::EPSILON) * (4.0 * f32::EPSILON) * diag >= off {
            return Ok((Vec3::new(a.m11, a.m22, a.m33), v));
        }
        for plane in [Plane::P12, Plane::P13, Plane::P23] {
            let j = givens(&a, plane);
            a = product(&product(&j.transpose(), &a), &j);
            // keep the iterate exactly symmetric
            a = symmetric_part(&a);
            v = product(&v, &j);
        }
    }
    Err(PrincipalAxesError::NoConvergence)
}

/// `a · b`: nalgebra's 3×3 product, kept out of line on the MSP430 so that the Jacobi sweep
/// holds one copy of it instead of three (the same operations: the same result, bit for bit).
#[cfg_attr(target_arch = "msp430", inline(never))]
fn product(a: &Mat3, b: &Mat3) -> Mat3 {
    a * b
}

/// `(m + mᵀ)/2`, out of line on the MSP430 like [`product`].
#[cfg_attr(target_arch = "msp430", inline(never))]
fn symmetric_part(m: &Mat3) -> Mat3 {
    (m + m.transpose()) * 0.5
}

/// The three coordinate planes a Jacobi rotation acts in.
#[derive(Copy, Clone)]
enum Plane {
    P12,
    P13,
    P23,
}

/// The Jacobi rotation `J` of `plane` that zeroes `a_pq` in `Jᵀ a J` (Golub & Van Loan alg. 8.5.1).
fn givens(a: &Mat3, plane: Plane) -> Mat3 {
    let (app, aqq, apq) = match plane {
        Plane::P12 => (a.m11, a.m22, a.m12),
        Plane::P13 => (a.m11, a.m33, a.m13),
        Plane::P23 => (a.m22, a.m33, a.m23),
    };
    if apq == 0.0 {
        return Mat3::identity();
    }
    // τ = (a_qq − a_pp) / (2 a_pq); t = sign(τ) / (|τ| + √(1 + τ²)), the smaller root
    let tau = (aqq - app) / (2.0 * apq);
    let t = if tau.is_finite() {
        let t_abs = 1.0 / (fmath::abs(tau) + fmath::sqrt(1.0 + tau * tau));
        if tau >= 0.0 {
            t_abs
        } else {
            -t_abs
        }
    } else {
        0.0
    };
    let c = 1.0 / fmath::sqrt(1.0 + t * t);
    let s = t * c;
    match plane {
        Plane::P12 => Mat3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0),
        Plane::P13 => Mat3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c),
        Plane::P23 => Mat3::new(1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c),
    }
}

/// The six assignments of eigenvector columns to body axes.
const PERMUTATIONS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

/// The principal axes of `inertia_body` (kg·m², UVW) ordered and signed by the thesis's rule
/// (see the [module docs](self)).
pub fn principal_axes(inertia_body: &Mat3) -> Result<PrincipalAxes, PrincipalAxesError> {
    let (values, vectors) = symmetric_eigen(inertia_body)?;
    let columns = [
        vectors.column(0).into_owned(),
        vectors.column(1).into_owned(),
        vectors.column(2).into_owned(),
    ];
    let vals = [values.x, values.y, values.z];
    // choose the permutation maximising Σ |component of column p_k on axis k|
    let mut best = [0usize, 1, 2];
    let mut best_score = f32::NEG_INFINITY;
    for p in PERMUTATIONS {
        let score: f32 = p
            .iter()
            .enumerate()
            .map(|(k, &col)| {
                columns
                    .get(col)
                    .and_then(|c| c.get(k))
                    .map_or(0.0, |x| fmath::abs(*x))
            })
            .sum();
        if score > best_score {
            best_score = score;
            best = p;
        }
    }
    let mut rows = [Vec3::zeros(); 3];
    let mut moments = [0.0f32; 3];
    for (k, (row, moment)) in rows.iter_mut().zip(moments.iter_mut()).enumerate() {
        let col = best.get(k).copied().unwrap_or(k);
        let v = columns.get(col).copied().unwrap_or_else(Vec3::zeros);
        let diag = v.get(k).copied().unwrap_or(0.0);
        *row = if diag >= 0.0 { v } else { -v };
        *moment = vals.get(col).copied().unwrap_or(0.0);
    }
    let [r1, r2, r3] = rows;
    let mut e = Mat3::from_rows(&[r1.transpose(), r2.transpose(), r3.transpose()]);
    if !(e.determinant() >= 0.0) {
        // flip the row with the smallest diagonal: the only way to keep the others positive
        let d = [fmath::abs(e.m11), fmath::abs(e.m22), fmath::abs(e.m33)];
        let k = if d[1] >= d[0] && d[2] >= d[0] {
            0
        } else if d[2] >= d[1] {
            1
        } else {
            2
        };
        let mut row = e.row_mut(k);
        row.neg_mut();
    }
    let [ia, ib, ic] = moments;
    let physical = ia > 0.0
        && ib > 0.0
        && ic > 0.0
        && ia + ib >= ic * (1.0 - 1e-5)
        && ia + ic >= ib * (1.0 - 1e-5)
        && ib + ic >= ia * (1.0 - 1e-5);
    if !physical {
        return Err(PrincipalAxesError::NotPhysical(Vec3Moments(moments)));
    }
    Ok(PrincipalAxes {
        e,
        moments: Vec3::new(ia, ib, ic),
        inertia_body: *inertia_body,
    })
}
