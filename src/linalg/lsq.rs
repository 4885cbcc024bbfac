//! Streaming linear least squares with three unknowns by Givens QR, for any number of rows in
//! constant memory, solved through the SVD of the 3×3 triangular factor.
//!
//! # Method
//! Each row `aᵢᵀ x ≈ yᵢ` is folded into an upper-triangular `R` (3×3) and `z = Qᵀy` (3 rows of
//! `K` right-hand sides) by three Givens rotations (Golub and Van Loan, *Matrix Computations*:
//! Givens rotations and QR updating): for k = 1, 2, 3
//! ```text
//! ρ = √(R_kk² + a_k²),  c = R_kk/ρ,  s = a_k/ρ
//! R_k ← c·R_k + s·aᵀ,  aᵀ ← −s·R_k + c·aᵀ,  z_k ← c·z_k + s·y,  y ← −s·z_k + c·y
//! ```
//! in Gentleman's square-root-free form (W. M. Gentleman, *Least squares computations by Givens
//! transformations without square roots*, J. Inst. Maths Applics 12, 1973): `R = D^½·R̄` and
//! `z = D^½·z̄` with `R̄` unit upper triangular, and the incoming row carried as `δ^½·(a, y)`
//! (δ = 1 at first). The same rotation is then, for each k with `a_k ≠ 0`,
//! ```text
//! d' = d_k + δ·a_k²,  c̄ = d_k/d',  s̄ = δ·a_k/d',  δ ← δ·c̄,  d_k ← d'
//! R̄_k ← c̄·R̄_k + s̄·aᵀ,  aᵀ ← aᵀ − a_k·R̄_k,  z̄_k ← c̄·z̄_k + s̄·y,  y ← y − a_k·z̄_k
//! ```
//! (the old `R̄_k`, `z̄_k` on the right): two divisions and no square root per rotation (a
//! square root costs 3 852 cycles on the MSP430, a division 417). `R = D^½·R̄` is formed once
//! for the SVD (three square roots).
//! Since `M = Q·R`, `M⁺ = R⁺·Qᵀ` (also when `M` is rank deficient), so `x = R⁺ z` with `R⁺`
//! from the one-sided Jacobi SVD of [`crate::linalg::svd`], singular values below
//! `rel_tol·σ₁` treated as zero (seed 000 eqs. 8.16–8.18).
//!
//! # Why not the normal equations
//! `MᵀM x = Mᵀy` costs the same on a 3×3 matrix but squares the condition number (error
//! `ε·κ²`); the Givens update keeps `ε·κ` and still needs only 12 + 3K floats of state,
//! whatever the number of tiles.

use nalgebra::SVector;

use crate::fmath;
use crate::linalg::svd::{SvdError, ThinSvd};
use crate::linalg::{finite3, lin2, scale, sub_scaled, Mat3, Vec3};

/// A least-squares problem `M·X ≈ Y` with 3 unknowns per column and `K` right-hand sides,
/// accumulated row by row.
#[derive(Clone, Debug)]
pub struct QrLeastSquares<const K: usize> {
    /// Rows of `R̄` (unit diagonal; entries left of it are 0).
    r: [Vec3; 3],
    /// `D` (the squared diagonal of `R`).
    d: [f32; 3],
    /// Rows of `z̄`.
    z: [SVector<f32, K>; 3],
    rows: u32,
}

impl<const K: usize> Default for QrLeastSquares<K> {
    fn default() -> Self {
        Self::new()
    }
}

/// Component `k` (0, 1, 2) of a 3-vector, without indexing.
fn comp(v: &Vec3, k: usize) -> f32 {
    match k {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

/// Sets component `k` (0, 1, 2) of a 3-vector.
fn set_comp(v: &mut Vec3, k: usize, x: f32) {
    match k {
        0 => v.x = x,
        1 => v.y = x,
        _ => v.z = x,
    }
}

impl<const K: usize> QrLeastSquares<K> {
    /// An empty problem.
    pub fn new() -> Self {
        Self {
            r: [Vec3::x(), Vec3::y(), Vec3::z()],
            d: [0.0; 3],
            z: [SVector::zeros(); 3],
            rows: 0,
        }
    }

    /// Number of rows folded in.
    pub fn rows(&self) -> u32 {
        self.rows
    }

    /// Folds in the row `aᵀ·X = yᵀ`. Non-finite rows are refused, and so are rows whose
    /// squares leave f32's range (`|a_k|` beyond about 1e19, or a weight `δ·a_k²` underflowing
    /// to 0 on an empty row of `R`).
    pub fn push(&mut self, a: &Vec3, y: &SVector<f32, K>) -> Result<(), SvdError> {
        if !(finite3(a) && y.iter().all(|v| v.is_finite())) {
            return Err(SvdError::NonFinite);
        }
        let mut a = *a;
        let mut y = *y;
        let mut delta = 1.0f32;
        for (k, ((rk, dk), zk)) in self
            .r
            .iter_mut()
            .zip(self.d.iter_mut())
            .zip(self.z.iter_mut())
            .enumerate()
        {
            let ak = comp(&a, k);
            // δ = 0: the row is used up (it landed on an empty row of R).
            if ak == 0.0 || delta == 0.0 {
                continue;
            }
            let wa = delta * ak;
            let d_new = *dk + wa * ak;
            if !d_new.is_finite() || !(d_new > 0.0) {
                // |a| beyond ~1e19 or below ~1e-19 (squares out of f32's range).
                return Err(SvdError::NonFinite);
            }
            let c = *dk / d_new;
            let s = wa / d_new;
            delta *= c;
            *dk = d_new;
            let (r_old, z_old) = (*rk, *zk);
            *rk = lin2(&r_old, c, &a, s);
            set_comp(rk, k, 1.0);
            a = sub_scaled(&a, &r_old, ak);
            *zk = z_old * c + y * s;
            y -= z_old * ak;
        }
        self.rows = self.rows.saturating_add(1);
        Ok(())
    }

    /// `R = D^½·R̄` and `z = D^½·z̄`.
    fn factor(&self) -> ([Vec3; 3], [SVector<f32, K>; 3]) {
        let mut r = self.r;
        let mut z = self.z;
        for ((rk, zk), dk) in r.iter_mut().zip(z.iter_mut()).zip(self.d.iter()) {
            let sk = fmath::sqrt(*dk);
            *rk = scale(rk, sk);
            *zk *= sk;
        }
        (r, z)
    }

    /// The singular values of `M` (equal to those of `R`) and its SVD.
    fn svd(&self) -> Result<(ThinSvd<3>, [SVector<f32, K>; 3]), SvdError> {
        let (r, z) = self.factor();
        Ok((ThinSvd::<3>::new(&r)?, z))
    }

    /// The rank of `M` with the relative threshold `rel_tol` on its singular values.
    pub fn rank(&self, rel_tol: f32) -> Result<u8, SvdError> {
        Ok(self.svd()?.0.rank(rel_tol))
    }

    /// The singular values `σ₁ ≥ σ₂ ≥ σ₃` of `M`.
    pub fn singular_values(&self) -> Result<Vec3, SvdError> {
        Ok(self.svd()?.0.singular_values())
    }

    /// The minimum-norm least-squares solution `X = M⁺·Y` (3×K), requiring rank 3 with the
    /// relative threshold `rel_tol` ([`SvdError::RankDeficient`] otherwise).
    pub fn solve_full_rank(&self, rel_tol: f32) -> Result<nalgebra::SMatrix<f32, 3, K>, SvdError> {
        let (svd, z) = self.svd()?;
        svd.require_rank(3, rel_tol)?;
        svd.solve_matrix(&z, rel_tol)
    }

    /// `(MᵀM)⁻¹ = V·Σ⁻²·Vᵀ` from the SVD of the triangular factor, requiring rank 3 with the
    /// relative threshold `rel_tol` (as [`Self::solve_full_rank`]): with it, later right-hand
    /// sides of the same rows are solved as `X = (MᵀM)⁻¹·(MᵀY)` without redoing the QR.
    pub fn inverse_gram(&self, rel_tol: f32) -> Result<Mat3, SvdError> {
        let (svd, _) = self.svd()?;
        svd.require_rank(3, rel_tol)?;
        let s = svd.singular_values();
        let d = Vec3::new(1.0 / (s.x * s.x), 1.0 / (s.y * s.y), 1.0 / (s.z * s.z));
        Ok(svd.v_diag_vt(&d))
    }

    /// The minimum-norm least-squares solution `X = M⁺·Y` (3×K), singular values below
    /// `rel_tol·σ₁` treated as zero (no rank requirement).
    pub fn solve(&self, rel_tol: f32) -> Result<nalgebra::SMatrix<f32, 3, K>, SvdError> {
        let (svd, z) = self.svd()?;
        svd.solve_matrix(&z, rel_tol)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_exact_solution_and_pinv() {
        let x_true = Vec3::new(1.5, -2.0, 0.25);
        let rows = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.3, 0.4, 0.5),
            Vec3::new(-1.0, 2.0, 1.0),
            Vec3::new(0.0, 0.0, -1.0),
        ];
        let mut ls = QrLeastSquares::<1>::new();
        for r in &rows {
            ls.push(r, &SVector::<f32, 1>::new(r.dot(&x_true))).unwrap();
        }
        let x = ls.solve_full_rank(1e-5).unwrap();
        assert!((x.column(0) - x_true).norm() < 1e-5, "{x}");
        // Rank deficient: only x and y observed.
        let mut ls = QrLeastSquares::<1>::new();
        ls.push(&Vec3::x(), &SVector::<f32, 1>::new(2.0)).unwrap();
        ls.push(&Vec3::y(), &SVector::<f32, 1>::new(3.0)).unwrap();
        assert_eq!(ls.rank(1e-5).unwrap(), 2);
        assert!(ls.solve_full_rank(1e-5).is_err());
        let x = ls.solve(1e-5).unwrap();
        assert!((x.column(0) - Vec3::new(2.0, 3.0, 0.0)).norm() < 1e-6);
    }
}
