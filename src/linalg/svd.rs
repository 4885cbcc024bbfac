//! Singular value decomposition of a tall m×3 matrix (m ≤ [`MAX_ROWS`]) by one-sided Jacobi
//! rotations, its pseudoinverse, and the nearest rotation to a 3×3 matrix.
//!
//! # Method
//! One-sided Jacobi (Hestenes 1958; Demmel and Veselić, *Jacobi's method is more accurate than
//! QR*, SIAM J. Matrix Anal. Appl. 13(4), 1992): plane rotations `J` applied to
//! the columns of `M` until they are mutually orthogonal, `M·V = W`, `V = J₁J₂…` orthogonal.
//! Then `σⱼ = |wⱼ|` and `uⱼ = wⱼ/σⱼ`, so `M = U·Σ·Vᵀ` (the thin SVD). For a pair of columns
//! `(p, q)` with `α = |w_p|²`, `β = |w_q|²`, `γ = w_p·w_q`:
//! ```text
//! ζ = (β − α)/(2γ),  t = sign(ζ)/(|ζ| + √(1 + ζ²)),  c = 1/√(1 + t²),  s = c·t
//! w_p ← c·w_p − s·w_q,   w_q ← s·w_p + c·w_q          (and the same on the columns of V)
//! ```
//! makes `w_p·w_q = 0`. Sweeps over the pairs (1,2), (1,3), (2,3) stop when no pair has
//! `|γ| > 4ε·√(αβ)` (ε = `f32::EPSILON`) or after [`MAX_SWEEPS`] sweeps (Jacobi converges
//! quadratically once the columns are nearly orthogonal; at the cap the columns are orthogonal
//! to rounding anyway, so the result is returned, not an error).
//!
//! One-sided Jacobi never forms `MᵀM`, so small singular values keep their relative accuracy
//! (the error of a least-squares solution grows like `ε·κ`, not `ε·κ²` as with the normal
//! equations).
//!
//! # Pseudoinverse (seed 000 eqs. 8.17–8.18)
//! `M⁺ = V·Σ⁺·Uᵀ`, where `Σ⁺` inverts the singular values above `rel_tol·σ_max` and zeroes the
//! others. It is applied without storing `U`: `M⁺·y = Σⱼ vⱼ (wⱼ·y)/σⱼ²`.
//!
//! # Cost
//! Allocation-free; the working copy of the matrix is 3 × `M` f32 on the stack (144 B for
//! `M` = [`MAX_ROWS`], 36 B for the 3×3 matrices the crate's solvers decompose) plus `V`.
//! No recursion; every loop is bounded by `M` and [`MAX_SWEEPS`].

use crate::fmath;
use crate::linalg::{cross, div, dot, finite3, lin3, norm, scale, sub_scaled, Mat3, Vec3};

/// The default row capacity of [`ThinSvd`] (12 tiles or 12 two-axis rows). The crate's own
/// solvers use `ThinSvd<3>` (the 3×3 triangular factor of [`crate::linalg::lsq`], or the
/// attitude profile matrix), whose working copy is 36 B instead of 144 B.
pub const MAX_ROWS: usize = 12;

/// Iteration cap of the Jacobi sweeps.
pub const MAX_SWEEPS: u8 = 12;

/// Orthogonality tolerance of the sweeps, in units of `f32::EPSILON`.
const ORTHO_TOL: f32 = 4.0 * f32::EPSILON;

/// Why a decomposition or a solve was refused.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SvdError {
    /// More rows than the decomposition's capacity.
    TooManyRows {
        /// Rows given.
        rows: usize,
    },
    /// An entry of the matrix or of the right-hand side is NaN or infinite.
    NonFinite,
    /// The right-hand side does not have one entry (or row) per row of the matrix.
    RhsLength {
        /// Rows of the matrix.
        rows: usize,
        /// Entries of the right-hand side.
        rhs: usize,
    },
    /// The matrix has fewer significant singular values than the operation needs.
    RankDeficient {
        /// Singular values above the threshold.
        rank: u8,
        /// The ratio `σ_min/σ_max` of the singular value that fell below the threshold.
        ratio: f32,
    },
}

impl core::fmt::Display for SvdError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::TooManyRows { rows } => {
                write!(f, "{rows} rows, more than the capacity")
            }
            Self::NonFinite => write!(f, "NaN or infinite entry"),
            Self::RhsLength { rows, rhs } => {
                write!(f, "matrix has {rows} rows but the right-hand side {rhs}")
            }
            Self::RankDeficient { rank, ratio } => write!(
                f,
                "rank {rank}: singular value ratio {ratio:e} below the threshold"
            ),
        }
    }
}

/// The thin SVD `M = U·Σ·Vᵀ` of an m×3 matrix, m ≤ `M` (default [`MAX_ROWS`]), singular
/// values in descending order. `U` is kept as `W = M·V = U·Σ` (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct ThinSvd<const M: usize = MAX_ROWS> {
    w: [[f32; M]; 3],
    v: [Vec3; 3],
    sigma: [f32; 3],
    rows: usize,
}

/// `a·b` over the columns' rows (one copy for every row capacity `M`).
#[cfg_attr(target_arch = "msp430", inline(never))]
fn dot_rows(a: &[f32], b: &[f32]) -> f32 {
    a.iter().zip(b.iter()).map(|(x, y)| x * y).sum()
}

/// `(p, q) ← (c·p − s·q, s·p + c·q)` elementwise.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn rotate_pair(p: &mut [f32], q: &mut [f32], c: f32, s: f32) {
    for (p, q) in p.iter_mut().zip(q.iter_mut()) {
        let (a, b) = (*p, *q);
        *p = c * a - s * b;
        *q = s * a + c * b;
    }
}

/// One Jacobi rotation of the column pair `(wp, wq)` and of `(vp, vq)`. Returns whether it
/// rotated. (Over slices: one copy for every row capacity.)
#[cfg_attr(target_arch = "msp430", inline(never))]
fn rotate(wp: &mut [f32], wq: &mut [f32], vp: &mut Vec3, vq: &mut Vec3) -> bool {
    let alpha = dot_rows(wp, wp);
    let beta = dot_rows(wq, wq);
    let gamma = dot_rows(wp, wq);
    // Rotate only if |γ| > 4ε·√(αβ), compared squared (no square root).
    let g2 = gamma * gamma;
    if g2.is_nan() || (ORTHO_TOL * alpha) * (ORTHO_TOL * beta) >= g2 {
        return false;
    }
    // ζ = (β − α)/(2γ), t = sign(ζ)/(|ζ| + √(1 + ζ²)) (t = 1/(2ζ) where ζ² would overflow).
    let zeta = (beta - alpha) / (2.0 * gamma);
    let abs_zeta = fmath::abs(zeta);
    let t_abs = if abs_zeta > 1.0e15 {
        0.5 / abs_zeta
    } else {
        1.0 / (abs_zeta + fmath::sqrt(1.0 + zeta * zeta))
    };
    let t = if zeta >= 0.0 { t_abs } else { -t_abs };
    let c = 1.0 / fmath::sqrt(1.0 + t * t);
    let s = c * t;
    rotate_pair(wp, wq, c, s);
    rotate_pair(vp.as_mut_slice(), vq.as_mut_slice(), c, s);
    true
}

impl<const M: usize> ThinSvd<M> {
    /// Decomposes the matrix whose rows are `rows` (at most `M`).
    pub fn new(rows: &[Vec3]) -> Result<Self, SvdError> {
        if rows.len() > M {
            return Err(SvdError::TooManyRows { rows: rows.len() });
        }
        if !rows.iter().all(finite3) {
            return Err(SvdError::NonFinite);
        }
        // Worked on in place (no copies of the columns: stack).
        let mut w = [[0.0f32; M]; 3];
        let mut v = [Vec3::x(), Vec3::y(), Vec3::z()];
        {
            let [w0, w1, w2] = &mut w;
            let [v0, v1, v2] = &mut v;
            for (r, (a, (b, c))) in rows
                .iter()
                .zip(w0.iter_mut().zip(w1.iter_mut().zip(w2.iter_mut())))
            {
                *a = r.x;
                *b = r.y;
                *c = r.z;
            }
            for _ in 0..MAX_SWEEPS {
                let r01 = rotate(w0, w1, v0, v1);
                let r02 = rotate(w0, w2, v0, v2);
                let r12 = rotate(w1, w2, v1, v2);
                if !(r01 || r02 || r12) {
                    break;
                }
            }
        }
        let mut s = w.each_ref().map(|wj| fmath::sqrt(dot_rows(wj, wj)));
        // Sort descending (three compare-and-swaps).
        for (i, j) in [(0usize, 1usize), (1, 2), (0, 1)] {
            let (si, sj) = match (s.get(i), s.get(j)) {
                (Some(a), Some(b)) => (*a, *b),
                _ => continue,
            };
            if sj > si {
                s.swap(i, j);
                w.swap(i, j);
                v.swap(i, j);
            }
        }
        if !s.iter().all(|x| x.is_finite()) {
            return Err(SvdError::NonFinite);
        }
        Ok(Self {
            w,
            v,
            sigma: s,
            rows: rows.len(),
        })
    }

    /// The singular values `(σ₁ ≥ σ₂ ≥ σ₃)`.
    pub fn singular_values(&self) -> Vec3 {
        let [a, b, c] = self.sigma;
        Vec3::new(a, b, c)
    }

    /// The right singular vectors as the columns of `V` (a proper or improper orthogonal matrix).
    pub fn v(&self) -> Mat3 {
        let [a, b, c] = self.v;
        Mat3::from_columns(&[a, b, c])
    }

    /// `V·diag(d)·Vᵀ` (as nalgebra's `v * Mat3::from_diagonal(d) * v.transpose()`, bit for
    /// bit): with `d = σ⁻²`, `(MᵀM)⁻¹` of a full-rank `M`.
    pub fn v_diag_vt(&self, d: &Vec3) -> Mat3 {
        let [v1, v2, v3] = &self.v;
        // The columns of V·diag(d), then those of (V·diag(d))·Vᵀ.
        let p1 = lin3(v1, v2, v3, d.x, 0.0, 0.0);
        let p2 = lin3(v1, v2, v3, 0.0, d.y, 0.0);
        let p3 = lin3(v1, v2, v3, 0.0, 0.0, d.z);
        let col = |x: f32, y: f32, z: f32| lin3(&p1, &p2, &p3, x, y, z);
        Mat3::from_columns(&[
            col(v1.x, v2.x, v3.x),
            col(v1.y, v2.y, v3.y),
            col(v1.z, v2.z, v3.z),
        ])
    }

    /// Number of singular values above `rel_tol · σ₁` (0 for the zero matrix).
    pub fn rank(&self, rel_tol: f32) -> u8 {
        let [s1, _, _] = self.sigma;
        let threshold = rel_tol * s1;
        self.sigma.iter().filter(|&&s| s > threshold).count() as u8
    }

    /// Checks that the rank is at least `needed` with the relative threshold `rel_tol`.
    pub fn require_rank(&self, needed: u8, rel_tol: f32) -> Result<(), SvdError> {
        let rank = self.rank(rel_tol);
        if rank >= needed {
            return Ok(());
        }
        let [s1, _, _] = self.sigma;
        let sk = self
            .sigma
            .get(usize::from(rank))
            .copied()
            .unwrap_or_default();
        let ratio = if s1 > 0.0 { sk / s1 } else { 0.0 };
        Err(SvdError::RankDeficient { rank, ratio })
    }

    /// The least-squares, minimum-norm solution `x = M⁺·y` (eq. 8.16), singular values below
    /// `rel_tol · σ₁` treated as zero.
    pub fn solve(&self, y: &[f32], rel_tol: f32) -> Result<Vec3, SvdError> {
        if y.len() != self.rows {
            return Err(SvdError::RhsLength {
                rows: self.rows,
                rhs: y.len(),
            });
        }
        if !y.iter().all(|x| x.is_finite()) {
            return Err(SvdError::NonFinite);
        }
        let [s1, _, _] = self.sigma;
        let threshold = rel_tol * s1;
        let mut x = Vec3::zeros();
        for ((wj, vj), sj) in self.w.iter().zip(self.v.iter()).zip(self.sigma.iter()) {
            if *sj > threshold {
                // (wⱼ·y)/σⱼ² = (uⱼ·y)/σⱼ
                let wy: f32 = wj.iter().zip(y.iter()).map(|(a, b)| a * b).sum();
                x += vj * (wy / (sj * sj));
            }
        }
        Ok(x)
    }

    /// `M⁺·Z` for `K` right-hand sides given as one row `zᵢ` per row of `M` (3×K result),
    /// singular values below `rel_tol · σ₁` treated as zero.
    pub fn solve_matrix<const K: usize>(
        &self,
        z: &[nalgebra::SVector<f32, K>],
        rel_tol: f32,
    ) -> Result<nalgebra::SMatrix<f32, 3, K>, SvdError> {
        if z.len() != self.rows {
            return Err(SvdError::RhsLength {
                rows: self.rows,
                rhs: z.len(),
            });
        }
        if z.iter().any(|r| !r.iter().all(|x| x.is_finite())) {
            return Err(SvdError::NonFinite);
        }
        let [s1, _, _] = self.sigma;
        let threshold = rel_tol * s1;
        let mut x = nalgebra::SMatrix::<f32, 3, K>::zeros();
        for ((wj, vj), sj) in self.w.iter().zip(self.v.iter()).zip(self.sigma.iter()) {
            if *sj > threshold {
                // wⱼᵀ·Z = Σᵢ wᵢⱼ zᵢᵀ
                let wz = wj
                    .iter()
                    .zip(z.iter())
                    .fold(nalgebra::SVector::<f32, K>::zeros(), |acc, (a, zi)| {
                        acc + zi * *a
                    });
                // x += vⱼ·(wⱼᵀZ)/σⱼ², column by column ((vᵢ·wzₖ)/σⱼ², as nalgebra's
                // `vj * wz.transpose() / (sj * sj)`).
                let s2 = sj * sj;
                for (mut xk, wzk) in x.column_iter_mut().zip(wz.iter()) {
                    xk += div(&scale(vj, *wzk), s2);
                }
            }
        }
        Ok(x)
    }

    /// The left singular vector `uⱼ` (j = 0, 1, 2) of a matrix with 3 rows, or `None` for a
    /// zero singular value, a bad index or a matrix with more rows.
    fn left3(&self, j: usize) -> Option<Vec3> {
        let wj = self.w.get(j)?;
        let sj = *self.sigma.get(j)?;
        if self.rows != 3 || !(sj > 0.0) {
            return None;
        }
        match wj.get(..3)? {
            [a, b, c] => Some(div(&Vec3::new(*a, *b, *c), sj)),
            _ => None,
        }
    }
}

/// The rotation `R` that maximises `tr(Rᵀ·B)`: the solution of Wahba's problem for the attitude
/// profile matrix `B` (Markley 1988, `R = U·diag(1, 1, det U·det V)·Vᵀ`), and equally the proper
/// rotation nearest to `B` in the Frobenius norm (the orthogonal polar factor, with the sign of
/// the smallest singular direction flipped if `det B < 0`).
///
/// Returns `R` and the singular values `(σ₁, σ₂, σ₃)` of `B`. Needs rank ≥ 2:
/// `σ₂ > min_ratio · σ₁`, else [`SvdError::RankDeficient`]. The third left singular vector is
/// taken as `u₁ × u₂`, so a rank-2 `B` (two observations) is handled exactly.
pub fn nearest_rotation(b: &Mat3, min_ratio: f32) -> Result<(Mat3, Vec3), SvdError> {
    let rows = [
        Vec3::new(b.m11, b.m12, b.m13),
        Vec3::new(b.m21, b.m22, b.m23),
        Vec3::new(b.m31, b.m32, b.m33),
    ];
    let svd = ThinSvd::<3>::new(&rows)?;
    svd.require_rank(2, min_ratio)?;
    let (u1, u2) = match (svd.left3(0), svd.left3(1)) {
        (Some(a), Some(b)) => (a, b),
        _ => {
            return Err(SvdError::RankDeficient {
                rank: 0,
                ratio: 0.0,
            })
        }
    };
    // Re-orthogonalise u₂ against u₁ (Gram–Schmidt, one step) and complete right-handed.
    // (Divided, not multiplied by the reciprocal: one rounding per component.)
    let u1 = div(&u1, norm(&u1));
    let u2 = sub_scaled(&u2, &u1, dot(&u1, &u2));
    let u2 = div(&u2, norm(&u2));
    let u3 = cross(&u1, &u2);
    let [v1, v2, v3] = svd.v;
    let det_v = dot(&cross(&v1, &v2), &v3);
    let d = if det_v >= 0.0 { 1.0 } else { -1.0 };
    // R = u₁v₁ᵀ + u₂v₂ᵀ + d·u₃v₃ᵀ: column j is [u₁ u₂ u₃]·(v₁ⱼ, v₂ⱼ, d·v₃ⱼ) (d = ±1: exact).
    let col = |x: f32, y: f32, z: f32| lin3(&u1, &u2, &u3, x, y, z * d);
    let r = Mat3::from_columns(&[
        col(v1.x, v2.x, v3.x),
        col(v1.y, v2.y, v3.y),
        col(v1.z, v2.z, v3.z),
    ]);
    Ok((r, svd.singular_values()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `v_diag_vt` and `solve_matrix` give the bits of the nalgebra expressions they replaced.
    #[test]
    fn kernel_forms_are_bit_identical_to_nalgebra() {
        let mut seed = 0x9e37_79b9u32;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
        };
        for n in 0..2_000 {
            let rows: Vec<Vec3> = (0..3 + n % 4)
                .map(|_| Vec3::new(next(), next(), next()))
                .collect();
            let svd = ThinSvd::<12>::new(&rows).unwrap();
            let d = Vec3::new(next(), next(), next());
            let v = svd.v();
            let expected = v * Mat3::from_diagonal(&d) * v.transpose();
            let bits = |m: &Mat3| m.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&svd.v_diag_vt(&d)), bits(&expected));
            let z: Vec<nalgebra::SVector<f32, 2>> = rows
                .iter()
                .map(|_| nalgebra::SVector::<f32, 2>::new(next(), next()))
                .collect();
            let mut x = nalgebra::SMatrix::<f32, 3, 2>::zeros();
            for ((wj, vj), sj) in svd.w.iter().zip(svd.v.iter()).zip(svd.sigma.iter()) {
                if *sj > 1e-5 * svd.sigma[0] {
                    let wz = wj
                        .iter()
                        .zip(z.iter())
                        .fold(nalgebra::SVector::<f32, 2>::zeros(), |acc, (a, zi)| {
                            acc + zi * *a
                        });
                    x += vj * wz.transpose() / (sj * sj);
                }
            }
            let got = svd.solve_matrix(&z, 1e-5).unwrap();
            assert_eq!(
                got.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                x.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
            );
        }
    }

    #[test]
    fn reconstructs_and_orders() {
        let rows = [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-1.0, 0.5, 2.0),
            Vec3::new(0.3, -0.7, 0.1),
            Vec3::new(4.0, 1.0, -2.0),
        ];
        let svd = ThinSvd::<12>::new(&rows).unwrap();
        let s = svd.singular_values();
        assert!(s.x >= s.y && s.y >= s.z && s.z > 0.0);
        // M⁺ M = I for full column rank.
        for e in [Vec3::x(), Vec3::y(), Vec3::z()] {
            let y: Vec<f32> = rows.iter().map(|r| r.dot(&e)).collect();
            let x = svd.solve(&y, 1e-6).unwrap();
            assert!((x - e).norm() < 1e-5, "{x:?} vs {e:?}");
        }
        let v = svd.v();
        assert!((v.transpose() * v - Mat3::identity()).norm() < 1e-6);
    }

    #[test]
    fn rank_deficient() {
        let rows = [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let svd = ThinSvd::<12>::new(&rows).unwrap();
        assert_eq!(svd.rank(1e-6), 2);
        assert!(matches!(
            svd.require_rank(3, 1e-6),
            Err(SvdError::RankDeficient { rank: 2, .. })
        ));
        let x = svd.solve(&[2.0, 3.0], 1e-6).unwrap();
        assert!((x - Vec3::new(2.0, 3.0, 0.0)).norm() < 1e-6);
    }

    #[test]
    fn refuses_bad_input() {
        let rows = [Vec3::new(f32::NAN, 0.0, 0.0)];
        assert_eq!(ThinSvd::<12>::new(&rows).unwrap_err(), SvdError::NonFinite);
        let many = [Vec3::x(); 13];
        assert!(matches!(
            ThinSvd::<12>::new(&many),
            Err(SvdError::TooManyRows { rows: 13 })
        ));
    }
}
