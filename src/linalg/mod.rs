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
