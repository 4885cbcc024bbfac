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
pub mod svd;

/// A symmetric 3×3 matrix stored as its upper triangle `(m11, m12, m13, m22, m23, m33)`: the
/// cached operators of the flight loop (`(W Wᵀ)⁺`, `(HᵀH)⁻¹`) in 24 B of RAM instead of 36.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SymMat3([f32; 6]);

impl SymMat3 {
    /// The upper triangle of `m` (the lower one is assumed equal).
    pub fn from_upper(m: &Mat3) -> Self {
        Self([m.m11, m.m12, m.m13, m.m22, m.m23, m.m33])
    }

    /// `M·v`.
    pub fn mul_vec(&self, v: &Vec3) -> Vec3 {
        let [a, b, c, d, e, f] = self.0;
        Vec3::new(
            a * v.x + b * v.y + c * v.z,
            b * v.x + d * v.y + e * v.z,
            c * v.x + e * v.y + f * v.z,
        )
    }
}
