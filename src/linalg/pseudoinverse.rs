//! The pseudoinverse of a symmetric positive semi-definite 3×3 matrix in closed form (adjugate,
//! null vector), with its numerical rank: `(W Wᵀ)⁺` of the wheel and coil allocators
//! ([`crate::control::wheels`]) and `(HᵀH)⁻¹` of the tile least squares
//! ([`crate::determination::least_squares`]).
//!
//! # Symbols
//! | name | symbol | meaning |
//! |---|---|---|
//! | `g` | `G` | the matrix, a sum of outer products `Σ aₖ aₖᵀ` (a Gram matrix) |
//! | `scale` | `s` | the power of two with `s·tr G ∈ [1, 2)` (an exact scaling) |
//! | `a` | `A = s·G` | the scaled matrix, entries `a_ij` |
//! | `c` | `C = adj A` | its adjugate (the cofactors `c_ij`; symmetric) |
//! | `trace`, `minors` | `t = tr A`, `m = tr C` | `λ₁ + λ₂ + λ₃` and `λ₁λ₂ + λ₁λ₃ + λ₂λ₃` |
//! | `d1` | `d₁ = a_pp` | the first pivot (the largest diagonal entry of `A`) |
//! | `d1d2`, `d1_det` | `d₁d₂`, `d₁·det A` | the second and third pivots `d₂, d₃` through `d₁d₂d₃ = det A` |
//! | `cqq`, `crr`, `cqr` | `c_qq, c_rr, c_qr` | the cofactors of the two other indices `q, r` |
//! | `rel_tol` | `τ` | the caller's relative threshold on the eigenvalues |
//!
//! `λ₁ ≥ λ₂ ≥ λ₃ ≥ 0` are the eigenvalues of `A` (never computed).
//!
//! # Rank decision
//! The rank is that of the Cholesky factorisation with complete (diagonal) pivoting stopped at
//! the first pivot below `τ` times the first one (N. J. Higham, "Analysis of the Cholesky
//! decomposition of a semi-definite matrix", in *Reliable Numerical Computation*, Oxford
//! University Press, 1990; *Accuracy and Stability of Numerical Algorithms*, 2nd ed., SIAM
//! 2002, ch. 10). With `p` the index of the largest diagonal entry and `q, r` the two others,
//! the Schur complement of the first pivot is `S = [c_rr −c_qr; −c_qr c_qq]/d₁` (its entries
//! are 2×2 minors of `A` over `d₁`), so the pivots come from the cofactors:
//! ```text
//! d₁ = a_pp,   d₁d₂ = max(c_qq, c_rr),   d₁·det A = d₁²·det S = c_qq·c_rr − c_qr²
//! d₃ = det S/d₂                                         (d₁·d₂·d₃ = det A)
//! rank 0  if t = 0 (G = 0)
//! rank 1  if 2·d₂ ≤ τ·d₁
//! rank 2  if 2·d₂ > τ·d₁ and d₃ ≤ τ·d₁
//! rank 3  if 2·d₂ > τ·d₁ and d₃ > τ·d₁
//! ```
//! (tested as `2·d₁d₂ > τ·d₁²` and `d₁·det A > τ·d₁²·d₁d₂`, without a division). This is the
//! rule "an eigenvalue below `τ·λ₁` is zero" up to a bounded factor. By Cauchy's interlacing
//! (`S⁻¹` is a principal submatrix of `A⁻¹`, a 2×2 principal minor is at most `λ₁λ₂`),
//! ```text
//! λ₁/3 ≤ d₁ ≤ λ₁,   λ₂/2 ≤ d₂ ≤ 3λ₂,   λ₃ ≤ d₃ ≤ 6λ₃
//! ⇒  λ₂/λ₁ ≤ 2d₂/d₁ ≤ 18·λ₂/λ₁,    λ₃/λ₁ ≤ d₃/d₁ ≤ 18·λ₃/λ₁
//! ```
//! so an eigenvalue above `τ·λ₁` always counts and one at or below `τ·λ₁/18` never does (the
//! unit test `rank_decision_brackets_the_eigenvalue_ratio` checks both on matrices with
//! prescribed f64 eigenvalues across the thresholds). The pivots are computed stably: the
//! entries of `S` carry an error of a few `ε·d₁` whatever the other eigenvalues, so `d₂/d₁`
//! and `d₃/d₁` are within a few ε of their exact values. (The determinant by a cofactor
//! expansion, `a₁₁c₁₁ + a₁₂c₁₂ + a₁₃c₁₃`, or the invariants `m/t²`, `det A/(m·t)`, would not
//! do: their error of a few `ε·λ₁³` swamps `λ₁λ₂λ₃` as soon as `λ₂ ≪ λ₁`; tried first, the
//! test on `det A/(m·t)` gave rank 3 to a matrix with `λ₂/λ₁ = 1.2e-5`, `λ₃/λ₁ = 6.4e-6` at
//! τ = 1e-5.)
//!
//! # Pseudoinverse
//! With `s` exact, `G⁺ = s·A⁺` and (Cayley–Hamilton on the range of `A`)
//! ```text
//! rank 3:  A⁺ = A⁻¹ = C / det A,   det A = (c_qq·c_rr − c_qr²)/d₁
//! rank 2:  A⁺ = (t·P − A) / m,     P = I − n nᵀ = I − c cᵀ/(cᵀc)
//! rank 1:  A⁺ = A / t²
//! rank 0:  A⁺ = 0
//! ```
//! At rank 2, `C = λ₁λ₂·n nᵀ` (n the unit null vector of `A`): its largest column `c` (the one
//! with the largest diagonal entry; a cross product of two rows of `A`) gives the projector `P`
//! onto the range without a square root, and on the range `A` has the eigenvalues `λ₁, λ₂`
//! with `λ₁ + λ₂ = t` and `λ₁λ₂ = m`, so `(t·I − A)/m` inverts it there (`(t − λ₁)/m = 1/λ₁`).
//! At rank 1, `A = t·v vᵀ`. Each case ends with one division of six entries. A rank-deficient
//! `G` rounded in f32 has a small `λ₃ ≤ 18τ·λ₁` (its noise), which moves the rank-2 result by
//! about `λ₃/λ₂` relative.
//!
//! # Accuracy (f32)
//! The determinant is the stable product of the pivots; the cofactors are 2×2 minors with an
//! absolute error of a few `ε·λ₁²`. The normwise relative error of `A⁻¹` is then a few
//! `ε·(λ₁/λ₂ + λ₁/λ₃)` (`ε·κ`, as a Cholesky inverse), that of the rank-2 result a few
//! `ε·λ₁/λ₂`, plus the error the caller made forming `G`. Measured (unit test
//! `matches_f64_on_random_matrices`, 300 000 random matrices, nonzero eigenvalue ratios
//! 1e-4..1): max-entry relative error against the f64 pseudoinverse ≤ 1.6·ε·κ at rank 3,
//! 3.3·ε·κ at rank 2 and 2.6·ε at rank 1 (κ = λ₁/λ_r, λ_r the smallest nonzero eigenvalue;
//! ε = 2⁻²³). On the geometries of [`crate::tiles`] (every subset of working tiles or wheels)
//! the callers' docs give the measured bounds.
//!
//! # Range
//! `tr G` must lie in `[2⁻¹²⁶, 2¹²⁶)` (`[1.2e-38, 8.5e37]`), which holds for any sum of outer
//! products of vectors with `1.1e-19 ≤ |a| ≤ 9e18`; outside it, or with a NaN or infinite
//! entry, [`PseudoinverseError::OutOfRange`]. `tr G = 0` is the zero matrix (rank 0). No square
//! root, no iteration.

use super::SymMat3;

/// The pseudoinverse of a symmetric 3×3 matrix and its numerical rank.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SymPseudoinverse {
    /// `G⁺` (`G⁻¹` at rank 3).
    pub pinv: SymMat3,
    /// The numerical rank of `G` (0..=3), see the [module docs](self).
    pub rank: u8,
}

/// Why the pseudoinverse was refused.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum PseudoinverseError {
    /// An entry is NaN or infinite, or the trace is negative or outside `[2⁻¹²⁶, 2¹²⁶)`.
    OutOfRange,
}

impl core::fmt::Display for PseudoinverseError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::OutOfRange => write!(f, "matrix entry NaN, infinite or out of range"),
        }
    }
}

/// The power of two `s` with `s·trace ∈ [1, 2)`, for a trace in `[2⁻¹²⁶, 2¹²⁶)` (`None`
/// outside: negative, NaN, subnormal or too large).
fn power_of_two_scale(trace: f32) -> Option<f32> {
    // trace = ±2^(e − 127)·1.f with the biased exponent e (0: subnormal, 255: infinite or
    // NaN); for e in 1..=252, s = 2^(127 − e) is the normal f32 of biased exponent 254 − e
    let biased = (trace.to_bits() >> 23) & 0xff;
    if trace.is_sign_negative() || biased == 0 || biased > 252 {
        return None;
    }
    Some(f32::from_bits((254 - biased) << 23))
}

/// `G⁺` and the numerical rank of the symmetric positive semi-definite `g` (a Gram matrix),
/// eigenvalues below the relative threshold `rel_tol` treated as zero (see the
/// [module docs](self) for the rank decision and the formulas).
pub fn symmetric_pseudoinverse(
    g: &SymMat3,
    rel_tol: f32,
) -> Result<SymPseudoinverse, PseudoinverseError> {
    let entries = g.0;
    if !entries.iter().all(|x| x.is_finite()) {
        return Err(PseudoinverseError::OutOfRange);
    }
    let [g11, _, _, g22, _, g33] = entries;
    let trace_g = g11 + g22 + g33;
    if trace_g == 0.0 {
        return Ok(SymPseudoinverse {
            pinv: SymMat3::zeros(),
            rank: 0,
        });
    }
    let scale = power_of_two_scale(trace_g).ok_or(PseudoinverseError::OutOfRange)?;
    // A = s·G (exact). The entry-wise formulas below are loops over the packed entries and
    // tables of indices (one copy of each formula in the MSP430 code, not six), with the
    // operations of each entry in the order the formulas give
    let mut a = entries;
    for x in &mut a {
        *x *= scale;
    }
    let [a11, _, _, a22, _, a33] = a;
    let trace = a11 + a22 + a33;
    // C = adj A: the cofactors (C = Cᵀ), c = a_i·a_j − a_k·a_l by COFACTORS
    // (a `for` loop: `array::map` is unrolled, six copies of the formula)
    let mut c = [0.0f32; 6];
    for (cp, [i, j, k, l]) in c.iter_mut().zip(COFACTORS.iter()) {
        *cp = entry(&a, *i) * entry(&a, *j) - entry(&a, *k) * entry(&a, *l);
    }
    let [c11, c12, c13, c22, c23, c33] = c;
    // first pivot d₁ = a_pp (the largest diagonal entry; d₁ ≥ t/3 > 0) and the cofactors of
    // the other two indices: S = [c_rr −c_qr; −c_qr c_qq]/d₁
    let (d1, cqq, crr, cqr) = if a11 >= a22 && a11 >= a33 {
        (a11, c22, c33, c23)
    } else if a22 >= a33 {
        (a22, c11, c33, c13)
    } else {
        (a33, c11, c22, c12)
    };
    // d₁·d₂ = max(c_qq, c_rr), d₁²·d₂·d₃ = d₁²·det S = d₁·det A
    let d1d2 = if cqq >= crr { cqq } else { crr };
    let d1_det = cqq * crr - cqr * cqr;
    // rank (a NaN threshold gives rank 1): 2·d₂ > τ·d₁, d₃ > τ·d₁
    let rank: u8 = if 2.0 * d1d2 > rel_tol * (d1 * d1) {
        if d1_det > rel_tol * (d1 * d1) * d1d2 {
            3
        } else {
            2
        }
    } else {
        1
    };
    let (mut x, divisor) = match rank {
        1 => {
            // A⁺ = A / t²
            (a, trace * trace)
        }
        2 => {
            // A⁺ = (t·P − A)/m, P = I − c cᵀ/(cᵀc), c the largest column of C
            let column = if c11 >= c22 && c11 >= c33 {
                0
            } else if c22 >= c33 {
                1
            } else {
                2
            };
            let n = COLUMNS
                .get(column)
                .copied()
                .unwrap_or_default()
                .map(|i| entry(&c, i));
            let [n1, n2, n3] = n;
            // t·P − A = t·I − k·c cᵀ − A, k = t/(cᵀc): entry (i, j) is
            // t − kᵢ·n_j − a_ij on the diagonal, −(kᵢ·n_j) − a_ij off it
            let k = trace / (n1 * n1 + n2 * n2 + n3 * n3);
            let kn = n.map(|ni| k * ni);
            let mut x = [0.0f32; 6];
            for (xp, [p, i, j]) in x.iter_mut().zip(PACKED.iter()) {
                let kinj = entry(&kn, *i) * entry(&n, *j);
                let t_p = if i == j { trace - kinj } else { -kinj };
                *xp = t_p - entry(&a, *p);
            }
            (x, c11 + c22 + c33)
        }
        _ => {
            // A⁻¹ = C / det A
            (c, d1_det / d1)
        }
    };
    // G⁺ = s·A⁺ (the multiplication by s is exact)
    for xij in &mut x {
        *xij = *xij / divisor * scale;
    }
    Ok(SymPseudoinverse {
        pinv: SymMat3(x),
        rank,
    })
}

/// The packed index, row and column of each entry of a symmetric 3×3 matrix, in the order of
/// [`SymMat3`] (`m11, m12, m13, m22, m23, m33`).
const PACKED: [[usize; 3]; 6] = [
    [0, 0, 0],
    [1, 0, 1],
    [2, 0, 2],
    [3, 1, 1],
    [4, 1, 2],
    [5, 2, 2],
];

/// The packed indices of column 0, 1, 2 of a symmetric 3×3 matrix.
const COLUMNS: [[usize; 3]; 3] = [[0, 1, 2], [1, 3, 4], [2, 4, 5]];

/// The cofactors of a symmetric 3×3 matrix, packed: `c = a_i·a_j − a_k·a_l` for `[i, j, k, l]`
/// (indices of packed entries).
const COFACTORS: [[usize; 4]; 6] = [
    [3, 5, 4, 4], // c11 = a22·a33 − a23·a23
    [2, 4, 1, 5], // c12 = a13·a23 − a12·a33
    [1, 4, 2, 3], // c13 = a12·a23 − a13·a22
    [0, 5, 2, 2], // c22 = a11·a33 − a13·a13
    [1, 2, 0, 4], // c23 = a12·a13 − a11·a23
    [0, 3, 1, 1], // c33 = a11·a22 − a12·a12
];

/// Entry `i` of `v` (the indices come from the tables above: always in range).
fn entry<const N: usize>(v: &[f32; N], i: usize) -> f32 {
    v.get(i).copied().unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Vec3;
    use nalgebra::{Matrix3, Vector3};

    /// Measured bounds of `matches_f64_on_random_matrices`, error / (ε·κ).
    const BOUND_RANK1: f64 = 3.0;
    const BOUND_RANK2: f64 = 4.0;
    const BOUND_RANK3: f64 = 2.0;

    /// Tiny deterministic generator (xorshift64*), uniform in [0, 1).
    struct Rng(u64);
    impl Rng {
        fn f(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
        }
        fn rotation(&mut self) -> Matrix3<f64> {
            let v = Vector3::new(self.f() - 0.5, self.f() - 0.5, self.f() - 0.5);
            let axis = nalgebra::Unit::new_normalize(v);
            nalgebra::Rotation3::from_axis_angle(&axis, self.f() * 3.0).into_inner()
        }
    }

    /// The f32 symmetric matrix (upper triangle) of an f64 one.
    fn sym32(m: &Matrix3<f64>) -> SymMat3 {
        SymMat3::from_upper(&m.map(|x| x as f32))
    }

    /// The f64 pseudoinverse of the symmetric `m`, eigenvalues below `1e-9·λ₁` dropped.
    fn pinv64(m: &Matrix3<f64>) -> (Matrix3<f64>, u8) {
        let e = m.symmetric_eigen();
        let lmax = e.eigenvalues.amax();
        let mut p = Matrix3::zeros();
        let mut rank = 0;
        for k in 0..3 {
            if e.eigenvalues[k] > 1e-9 * lmax {
                let v = e.eigenvectors.column(k);
                p += v * v.transpose() / e.eigenvalues[k];
                rank += 1;
            }
        }
        (p, rank)
    }

    fn rel_err(p: &SymMat3, reference: &Matrix3<f64>) -> f64 {
        let p64 = p.to_mat3().map(f64::from);
        (p64 - reference).amax() / reference.amax()
    }

    /// The rank decision brackets the eigenvalue ratios as the module docs state: on matrices
    /// `R diag(λ) Rᵀ` with f64 eigenvalues chosen around the thresholds (the eigenvalues of
    /// the f32 matrix checked), an eigenvalue above `τ·λ₁` always counts and one at or below
    /// `τ·λ₁/18` never does (a margin of 10 % on each bound, 16 ε at τ = 1e-5, for the
    /// rounding of the pivots).
    #[test]
    fn rank_decision_brackets_the_eigenvalue_ratio() {
        let mut rng = Rng(17);
        let tol = 1.0e-5f32;
        let t = f64::from(tol);
        for _ in 0..20_000 {
            let r = rng.rotation();
            let l1 = 10f64.powf(rng.f() * 8.0 - 4.0);
            // ratios spread over [τ/100, 100τ] (log-uniform), small λ₂ with λ₃ = 0, and
            // well-separated ones
            let ratio = |rng: &mut Rng| t * 10f64.powf(rng.f() * 4.0 - 2.0);
            let (r2, r3) = match rng.0 % 5 {
                0 => (rng.f().max(0.01), ratio(&mut rng)),
                1 => (ratio(&mut rng), 0.0),
                2 => {
                    let r2 = ratio(&mut rng);
                    (r2, r2 * rng.f())
                }
                3 => (10f64.powf(-rng.f() * 4.0), ratio(&mut rng)),
                _ => (rng.f().max(0.01), rng.f().max(0.01)),
            };
            let (r2, r3) = (r2.max(r3), r2.min(r3));
            let m = r * Matrix3::from_diagonal(&Vector3::new(l1, l1 * r2, l1 * r3)) * r.transpose();
            let p = symmetric_pseudoinverse(&sym32(&m), tol).unwrap();
            // the eigenvalues of the f32 matrix itself (its rounding moves them by ~ε·λ₁)
            let e = sym32(&m).to_mat3().map(f64::from).symmetric_eigen();
            let mut l = [e.eigenvalues[0], e.eigenvalues[1], e.eigenvalues[2]];
            l.sort_by(|a, b| b.total_cmp(a));
            let (q2, q3) = (l[1] / l[0], l[2] / l[0]);
            let counted = |q: f64| q > t * 1.1;
            let dropped = |q: f64| q <= t / 18.0 * 0.9;
            if counted(q3) {
                assert_eq!(p.rank, 3, "λ₂/λ₁ {q2:e} λ₃/λ₁ {q3:e}");
            }
            if dropped(q3) {
                assert!(p.rank < 3, "λ₂/λ₁ {q2:e} λ₃/λ₁ {q3:e}");
            }
            if counted(q2) {
                assert!(p.rank >= 2, "λ₂/λ₁ {q2:e} λ₃/λ₁ {q3:e}");
            }
            if dropped(q2) {
                assert_eq!(p.rank, 1, "λ₂/λ₁ {q2:e} λ₃/λ₁ {q3:e}");
            }
        }
    }

    /// On random matrices of rank 3, 2 and 1 (nonzero eigenvalue ratios log-uniform in
    /// [1e-4, 1], scales 1e-12..1e12), the normwise (max-entry) relative error of `G⁺` against
    /// the f64 pseudoinverse is at most `K·ε·κ`, κ = λ₁/λ_r the ratio of the largest to the
    /// smallest nonzero eigenvalue, with the `K` of each rank printed and asserted. The
    /// reference is the f64 pseudoinverse of the f32 matrix at rank 3 and of the exact low-rank
    /// matrix below (the f32 rounding adds eigenvalues of ~ε·λ₁ that the threshold removes).
    #[test]
    fn matches_f64_on_random_matrices() {
        let mut rng = Rng(3);
        let mut worst = [0f64; 4];
        let eps = f64::from(f32::EPSILON);
        for i in 0..300_000 {
            let r = rng.rotation();
            let l1 = 10f64.powf(rng.f() * 24.0 - 12.0);
            let rank = 1 + i % 3;
            let mut ratio = || 10f64.powf(-4.0 * rng.f());
            let (q2, q3) = (ratio(), ratio());
            let (q2, q3) = match rank {
                1 => (0.0, 0.0),
                2 => (q2, 0.0),
                _ => (q2.max(q3), q2.min(q3)),
            };
            let m = r * Matrix3::from_diagonal(&Vector3::new(l1, l1 * q2, l1 * q3)) * r.transpose();
            let g = sym32(&m);
            let p = symmetric_pseudoinverse(&g, 1e-5).unwrap();
            assert_eq!(usize::from(p.rank), rank, "{q2:e} {q3:e}");
            let (reference, _) = if rank == 3 {
                pinv64(&g.to_mat3().map(f64::from))
            } else {
                pinv64(&m)
            };
            let kappa = match rank {
                1 => 1.0,
                2 => 1.0 / q2,
                _ => 1.0 / q3,
            };
            let e = rel_err(&p.pinv, &reference) / (eps * kappa);
            worst[rank] = worst[rank].max(e);
        }
        println!(
            "symmetric pseudoinverse vs f64, error / (ε·κ): rank 1 {:.2}, rank 2 {:.2}, rank 3 {:.2}",
            worst[1], worst[2], worst[3]
        );
        assert!(worst[1] <= BOUND_RANK1 && worst[2] <= BOUND_RANK2 && worst[3] <= BOUND_RANK3);
    }

    /// Exact cases stay exact (the scaling is a power of two): the cube's wheels, with and
    /// without the U wheel, and a single axis.
    #[test]
    fn exact_cases() {
        let diag = |a: f32, b: f32, c: f32| SymMat3([a, 0.0, 0.0, b, 0.0, c]);
        let p = symmetric_pseudoinverse(&diag(1.0, 2.0, 2.0), 1e-5).unwrap();
        assert_eq!((p.pinv, p.rank), (diag(1.0, 0.5, 0.5), 3));
        let p = symmetric_pseudoinverse(&diag(0.0, 2.0, 2.0), 1e-5).unwrap();
        assert_eq!((p.pinv, p.rank), (diag(0.0, 0.5, 0.5), 2));
        let p = symmetric_pseudoinverse(&diag(0.0, 0.0, 4.0), 1e-5).unwrap();
        assert_eq!((p.pinv, p.rank), (diag(0.0, 0.0, 0.25), 1));
        let p = symmetric_pseudoinverse(&diag(0.0, 0.0, 0.0), 1e-5).unwrap();
        assert_eq!((p.pinv, p.rank), (diag(0.0, 0.0, 0.0), 0));
        // applied: (1, 1, 1) → (1, 0.5, 0.5)
        let v = symmetric_pseudoinverse(&diag(1.0, 2.0, 2.0), 1e-5)
            .unwrap()
            .pinv
            .mul_vec(&Vec3::new(1.0, 1.0, 1.0));
        assert_eq!(v, Vec3::new(1.0, 0.5, 0.5));
    }

    /// NaN, infinite, negative-trace and out-of-range matrices are refused; the range limits
    /// themselves are accepted.
    #[test]
    fn out_of_range() {
        let diag = |a: f32, b: f32, c: f32| SymMat3([a, 0.0, 0.0, b, 0.0, c]);
        for bad in [
            diag(f32::NAN, 1.0, 1.0),
            diag(f32::INFINITY, 1.0, 1.0),
            SymMat3([1.0, f32::NAN, 0.0, 1.0, 0.0, 1.0]),
            diag(-1.0, 0.0, 0.0),
            diag(1e-39, 0.0, 0.0),
            diag(3e38, 3e38, 0.0),
            diag(8.6e37, 0.0, 0.0),
        ] {
            assert_eq!(
                symmetric_pseudoinverse(&bad, 1e-5),
                Err(PseudoinverseError::OutOfRange),
                "{bad:?}"
            );
        }
        for (x, inv) in [
            (f32::MIN_POSITIVE, 1.0 / f32::MIN_POSITIVE),
            (2.8e37, 1.0 / 2.8e37),
        ] {
            let p = symmetric_pseudoinverse(&diag(x, x, x), 1e-5).unwrap();
            assert_eq!(p.rank, 3);
            let got = p.pinv.to_mat3().m11;
            assert!((got - inv).abs() <= 1e-6 * inv, "{got:e} {inv:e}");
        }
    }
}
