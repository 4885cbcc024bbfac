//! Fixed-size f32 linear algebra types shared by the whole crate (nalgebra, no allocation).
//!
//! Vectors are columns. Frames are not in the type; they are in the variable names
//! (`r_teme_km`, `b_body_nt`, …).

/// A 3-vector of f32.
pub type Vec3 = nalgebra::Vector3<f32>;
/// A 3×3 matrix of f32, row-major constructor `Mat3::new(m11, m12, …)`.
pub type Mat3 = nalgebra::Matrix3<f32>;
/// A 2-vector of f32.
pub type Vec2 = nalgebra::Vector2<f32>;
/// A 3-vector of f64 (one-time initialisation and host code only).
pub type Vec3d = nalgebra::Vector3<f64>;
/// A 3×3 matrix of f64 (one-time initialisation and host code only).
pub type Mat3d = nalgebra::Matrix3<f64>;

pub mod lsq;
pub mod pseudoinverse;
pub mod svd;

// Small 3-vector kernels, out of line on the MSP430. nalgebra's operators are generic and
// inlined at every use; on a 16-bit core without FPU each inlined f32 operation is a helper
// call plus 8–12 register moves, so a cross product inlined costs ~90 B of flash where a call
// to `cross` costs ~12. Each kernel evaluates exactly the expression (operands and order of the
// operations) nalgebra's operator does, so results are bit-identical to it.

/// Every component of `v` is finite.
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn finite3(v: &Vec3) -> bool {
    arr(v).iter().all(|x| x.is_finite())
}

/// The components of `v` as an array, in place.
#[inline(always)]
pub(crate) fn arr(v: &Vec3) -> &[f32; 3] {
    let [a] = &v.data.0;
    a
}

/// `(f(a₁, b₁), f(a₂, b₂), f(a₃, b₃))`: the body of the component-wise kernels below, written
/// out (as a loop over the components it is 254 B smaller in the attitude image but costs
/// ≈ 1 000 cycles in each of several phases of its step).
#[inline(always)]
fn zip_map(a: &Vec3, b: &Vec3, f: impl Fn(f32, f32) -> f32) -> Vec3 {
    let ([a1, a2, a3], [b1, b2, b3]) = (arr(a), arr(b));
    Vec3::new(f(*a1, *b1), f(*a2, *b2), f(*a3, *b3))
}

/// `(a₁b₁ + a₂b₂) + a₃b₃` with `a₁`, `a₂`, `a₃` read where they are (a vector, a row of a
/// matrix, a row of three columns, a row of the filter's packed covariance): the one kernel of
/// every three-term product below, its four arguments in registers on the MSP430.
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn dot3(a1: &f32, a2: &f32, a3: &f32, b: &Vec3) -> f32 {
    a1 * b.x + a2 * b.y + a3 * b.z
}

/// `a·b = (a₁b₁ + a₂b₂) + a₃b₃` (nalgebra's `dot` and `norm_squared`).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn dot(a: &Vec3, b: &Vec3) -> f32 {
    dot3(&a.x, &a.y, &a.z, b)
}

/// `|v| = √(v·v)` (nalgebra's `norm`: both square roots are correctly rounded).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn norm(v: &Vec3) -> f32 {
    crate::fmath::sqrt(dot(v, v))
}

/// `a × b` (nalgebra's `cross`).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn cross(a: &Vec3, b: &Vec3) -> Vec3 {
    Vec3::new(
        a.y * b.z - a.z * b.y,
        a.z * b.x - a.x * b.z,
        a.x * b.y - a.y * b.x,
    )
}

/// `−v` (nalgebra's `-v`: each component's sign flipped, exact).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn neg(v: &Vec3) -> Vec3 {
    Vec3::new(-v.x, -v.y, -v.z)
}

/// `a − b` (nalgebra's `a - b`).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn sub(a: &Vec3, b: &Vec3) -> Vec3 {
    zip_map(a, b, |a, b| a - b)
}

/// `v/k`, one division per component (nalgebra's `v / k`).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn div(v: &Vec3, k: f32) -> Vec3 {
    zip_map(v, v, |x, _| x / k)
}

/// `v·k` (nalgebra's `v * k`).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn scale(v: &Vec3, k: f32) -> Vec3 {
    zip_map(v, v, |x, _| x * k)
}

/// `a·x + b·y` (nalgebra's `a * x + b * y`; `a * x − b * y` is `lin2(a, x, b, −y)` exactly).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn lin2(a: &Vec3, x: f32, b: &Vec3, y: f32) -> Vec3 {
    zip_map(a, b, |a, b| a * x + b * y)
}

/// `a − b·k` (nalgebra's `a - b * k`).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn sub_scaled(a: &Vec3, b: &Vec3, k: f32) -> Vec3 {
    zip_map(a, b, |a, b| a - b * k)
}

/// `(a·x + b·y) + c·z`: the product `[a b c]·(x, y, z)` of the matrix with columns `a`, `b`,
/// `c` (nalgebra's matrix-vector product, and each column of its matrix-matrix product, sums
/// in this order).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn lin3(a: &Vec3, b: &Vec3, c: &Vec3, x: f32, y: f32, z: f32) -> Vec3 {
    columns_vec(arr(a), arr(b), arr(c), &Vec3::new(x, y, z))
}

/// `m·v` (nalgebra's `m * v`: row i is `(m_i1·v₁ + m_i2·v₂) + m_i3·v₃`).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn mat_vec(m: &Mat3, v: &Vec3) -> Vec3 {
    let [a, b, c] = &m.data.0;
    columns_vec(a, b, c, v)
}

/// `[a b c]·v`, row by row with [`dot3`] (the common body of [`lin3`] and [`mat_vec`]).
#[cfg_attr(target_arch = "msp430", inline(never))]
fn columns_vec(a: &[f32; 3], b: &[f32; 3], c: &[f32; 3], v: &Vec3) -> Vec3 {
    let ([a1, a2, a3], [b1, b2, b3], [c1, c2, c3]) = (a, b, c);
    Vec3::new(
        dot3(a1, b1, c1, v),
        dot3(a2, b2, c2, v),
        dot3(a3, b3, c3, v),
    )
}

/// `mᵀ` (nalgebra's `m.transpose()`), without indexing.
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn transpose(m: &Mat3) -> Mat3 {
    Mat3::new(
        m.m11, m.m21, m.m31, m.m12, m.m22, m.m32, m.m13, m.m23, m.m33,
    )
}

/// `a·b` (nalgebra's `a * b`: entry (i, j) is `(a_i1·b_1j + a_i2·b_2j) + a_i3·b_3j`, column by
/// column). Out of line and without indexing: nalgebra's product, once not inlined (at
/// `opt-level = "z"`), keeps a bounds check and so a panic path.
#[cfg_attr(target_arch = "msp430", inline(never))]
pub(crate) fn mat_mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let c1 = mat_vec(a, &Vec3::new(b.m11, b.m21, b.m31));
    let c2 = mat_vec(a, &Vec3::new(b.m12, b.m22, b.m32));
    let c3 = mat_vec(a, &Vec3::new(b.m13, b.m23, b.m33));
    Mat3::new(c1.x, c2.x, c3.x, c1.y, c2.y, c3.y, c1.z, c2.z, c3.z)
}

/// A symmetric 3×3 matrix stored as its upper triangle `(m11, m12, m13, m22, m23, m33)`: the
/// cached operators of the flight loop (`(W Wᵀ)⁺`, `(HᵀH)⁻¹`) in 24 B of RAM instead of 36.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SymMat3([f32; 6]);

impl SymMat3 {
    /// The zero matrix.
    pub const fn zeros() -> Self {
        Self([0.0; 6])
    }

    /// The upper triangle of `m` (the lower one is assumed equal).
    pub fn from_upper(m: &Mat3) -> Self {
        Self([m.m11, m.m12, m.m13, m.m22, m.m23, m.m33])
    }

    /// The full symmetric matrix.
    pub fn to_mat3(&self) -> Mat3 {
        let [a, b, c, d, e, f] = self.0;
        Mat3::new(a, b, c, b, d, e, c, e, f)
    }

    /// `M ← M + a aᵀ` (a Gram matrix `Σ a aᵀ` is accumulated row by row; entry `(i, j)` adds
    /// `aᵢ·aⱼ`, as nalgebra's `a * a.transpose()` does).
    #[cfg_attr(target_arch = "msp430", inline(never))]
    pub fn add_outer(&mut self, a: &Vec3) {
        let a = arr(a);
        let mut m = self.0.iter_mut();
        for (i, ai) in a.iter().enumerate() {
            for aj in a.get(i..).unwrap_or(&[]) {
                if let Some(m) = m.next() {
                    *m += ai * aj;
                }
            }
        }
    }

    /// `M·v` (row i: `(m_i1·v₁ + m_i2·v₂) + m_i3·v₃`).
    pub fn mul_vec(&self, v: &Vec3) -> Vec3 {
        let [a, b, c, d, e, f] = &self.0;
        Vec3::new(dot3(a, b, c, v), dot3(b, d, e, v), dot3(c, e, f, v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f32 values with exact zeros of both signs, ones, and wide and narrow magnitudes.
    fn values(seed: &mut u32) -> f32 {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 17;
        *seed ^= *seed << 5;
        let x = (*seed >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0;
        match *seed % 8 {
            0 => 0.0,
            1 => -0.0,
            2 => 1.0,
            3 => x * 1.0e6,
            4 => x * 1.0e-6,
            _ => x,
        }
    }

    fn bits(v: &Vec3) -> [u32; 3] {
        [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
    }

    /// Every kernel gives the bits of the nalgebra expression it replaces (signed zeros
    /// included), so the callers' results did not change.
    #[test]
    fn kernels_are_bit_identical_to_nalgebra() {
        let mut seed = 0x1234_5678u32;
        for _ in 0..20_000 {
            let mut v = || Vec3::new(values(&mut seed), values(&mut seed), values(&mut seed));
            let (a, b, c) = (v(), v(), v());
            let m = Mat3::from_columns(&[a, b, c]);
            let (x, y, z) = (values(&mut seed), values(&mut seed), values(&mut seed));
            assert_eq!(dot(&a, &b).to_bits(), a.dot(&b).to_bits());
            assert_eq!(dot(&a, &a).to_bits(), a.norm_squared().to_bits());
            assert_eq!(norm(&a).to_bits(), a.norm().to_bits());
            assert_eq!(bits(&cross(&a, &b)), bits(&a.cross(&b)));
            if x != 0.0 {
                assert_eq!(bits(&div(&a, x)), bits(&(a / x)));
            }
            assert_eq!(bits(&scale(&a, x)), bits(&(a * x)));
            assert_eq!(bits(&neg(&a)), bits(&(-a)));
            assert_eq!(bits(&sub(&a, &b)), bits(&(a - b)));
            assert_eq!(bits(&lin2(&a, x, &b, y)), bits(&(a * x + b * y)));
            assert_eq!(bits(&lin2(&a, x, &b, -y)), bits(&(a * x - b * y)));
            assert_eq!(bits(&sub_scaled(&a, &b, x)), bits(&(a - b * x)));
            let abc = Vec3::new(x, y, z);
            assert_eq!(bits(&lin3(&a, &b, &c, x, y, z)), bits(&(m * abc)));
            assert_eq!(bits(&mat_vec(&m, &abc)), bits(&(m * abc)));
            assert_eq!(
                bits(&mat_vec(&transpose(&m), &abc)),
                bits(&(m.transpose() * abc))
            );
            let n = Mat3::from_columns(&[c, a, b]) * x;
            let mbits = |m: &Mat3| m.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(mbits(&mat_mul(&m, &n)), mbits(&(m * n)));
            assert_eq!(
                mbits(&mat_mul(&m, &transpose(&n))),
                mbits(&(m * n.transpose()))
            );
            let s = SymMat3::from_upper(&(m + m.transpose()));
            let full = Mat3::new(
                s.0[0], s.0[1], s.0[2], s.0[1], s.0[3], s.0[4], s.0[2], s.0[4], s.0[5],
            );
            assert_eq!(bits(&s.mul_vec(&abc)), bits(&(full * abc)));
        }
    }
}
