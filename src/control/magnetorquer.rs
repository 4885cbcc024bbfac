//! Magnetorquer laws: torque projection, the two-coil laws of seed 002, dipole saturation that
//! keeps direction, coil currents, and wheel momentum dumping (note 002 §4.1–4.4, §8.5).
//!
//! # Physics
//! A dipole `m` (A·m²) in the field `B` (T) feels the torque `τ = m × B` (note 002 §4.1): only the
//! part of a desired torque orthogonal to `B` can be produced (note 002 §4.3),
//! ```text
//! τ_achievable = τ − (τ·B̂) B̂,        m = (B × τ) / |B|²       (m·B = 0, m × B = τ_achievable)
//! ```
//! Fields are in **nT** at the interface (the crate's unit); the functions convert to tesla.
//!
//! # Symbols
//! | name | note 002 | unit |
//! |---|---|---|
//! | `torque_nm` | `T_mi`, desired torque | N·m, body |
//! | `b_body_nt` | `B` | nT, body |
//! | `dipole_am2` | `M` | A·m², body |

use core::fmt;

use crate::fmath;
use crate::linalg::{self, Vec3};

/// Nanotesla to tesla.
const NT_TO_T: f32 = 1e-9;

/// Smallest field magnitude the laws accept, nT: below it (far weaker than anywhere in LEO,
/// 18 000–65 000 nT) the dipole needed would be unbounded.
pub const MIN_FIELD_NT: f32 = 100.0;

/// Errors of the magnetorquer laws.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum MagnetorquerError {
    /// An input is NaN or infinite.
    NotFinite,
    /// The field (or the component a two-coil law divides by) is below [`MIN_FIELD_NT`], nT.
    WeakField(f32),
    /// A limit, a number of turns or an area is not positive.
    InvalidParameter,
}

impl fmt::Display for MagnetorquerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotFinite => write!(f, "magnetorquer input is NaN or infinite"),
            Self::WeakField(b) => write!(f, "field component {b} nT too weak for the law"),
            Self::InvalidParameter => write!(f, "magnetorquer parameter not positive"),
        }
    }
}

fn finite(v: &Vec3) -> bool {
    linalg::finite3(v)
}

/// The part of `torque_nm` a magnetorquer can produce in the field `b_body_nt`:
/// `τ − (τ·B̂)B̂` (note 002 §4.3), N·m.
pub fn project_torque(torque_nm: &Vec3, b_body_nt: &Vec3) -> Result<Vec3, MagnetorquerError> {
    if !finite(torque_nm) || !finite(b_body_nt) {
        return Err(MagnetorquerError::NotFinite);
    }
    let b_norm = b_body_nt.norm();
    if !(b_norm >= MIN_FIELD_NT) {
        return Err(MagnetorquerError::WeakField(b_norm));
    }
    let b_hat = b_body_nt / b_norm;
    Ok(torque_nm - b_hat * torque_nm.dot(&b_hat))
}

/// The dipole that produces the achievable part of `torque_nm`: `m = B × τ / |B|²` (note 002
/// §4.3), A·m², body frame. `m·B = 0` and `m × B = project_torque(τ, B)`.
pub fn dipole_for_torque(torque_nm: &Vec3, b_body_nt: &Vec3) -> Result<Vec3, MagnetorquerError> {
    if !finite(torque_nm) || !finite(b_body_nt) {
        return Err(MagnetorquerError::NotFinite);
    }
    let b_norm = linalg::norm(b_body_nt);
    if !(b_norm >= MIN_FIELD_NT) {
        return Err(MagnetorquerError::WeakField(b_norm));
    }
    // out-of-line kernels: nalgebra's `b_t.cross(τ) / |b_t|²`, the same operations
    let b_t = linalg::scale(b_body_nt, NT_TO_T);
    Ok(linalg::div(
        &linalg::cross(&b_t, torque_nm),
        linalg::dot(&b_t, &b_t),
    ))
}

/// The torque a dipole produces, `τ = m × B`, N·m.
pub fn torque_of_dipole(dipole_am2: &Vec3, b_body_nt: &Vec3) -> Vec3 {
    dipole_am2.cross(&(b_body_nt * NT_TO_T))
}

/// The thesis's two-coil law with coils on x and z (`m_y = 0`, note 002 §4.4):
/// `m_z = −τ_x / B_y`, `m_x = τ_z / B_y`; returns the dipole and the unavoidable residual
/// `τ_y,res = −(B_z τ_z + B_x τ_x) / B_y` (N·m). Singular as `B_y → 0`: a typed error below
/// [`MIN_FIELD_NT`].
pub fn dipole_two_coil_xz(
    torque_nm: &Vec3,
    b_body_nt: &Vec3,
) -> Result<(Vec3, f32), MagnetorquerError> {
    if !finite(torque_nm) || !finite(b_body_nt) {
        return Err(MagnetorquerError::NotFinite);
    }
    if !(b_body_nt.y.abs() >= MIN_FIELD_NT) {
        return Err(MagnetorquerError::WeakField(b_body_nt.y));
    }
    let b = b_body_nt * NT_TO_T;
    let m = Vec3::new(torque_nm.z / b.y, 0.0, -torque_nm.x / b.y);
    let residual_y = -(b.z * torque_nm.z + b.x * torque_nm.x) / b.y;
    Ok((m, residual_y))
}

/// AtmoCube's actual two-coil law, coils on x and y (`m_z = 0`, note 002 §4.4 \[derived\]):
/// `m_y = τ_x / B_z`, `m_x = −τ_y / B_z`; returns the dipole and the residual
/// `τ_z,res = −(B_y τ_y + B_x τ_x) / B_z` (N·m). Singular at the magnetic equator (`B_z → 0`).
pub fn dipole_two_coil_xy(
    torque_nm: &Vec3,
    b_body_nt: &Vec3,
) -> Result<(Vec3, f32), MagnetorquerError> {
    if !finite(torque_nm) || !finite(b_body_nt) {
        return Err(MagnetorquerError::NotFinite);
    }
    if !(b_body_nt.z.abs() >= MIN_FIELD_NT) {
        return Err(MagnetorquerError::WeakField(b_body_nt.z));
    }
    let b = b_body_nt * NT_TO_T;
    let m = Vec3::new(-torque_nm.y / b.z, torque_nm.x / b.z, 0.0);
    let residual_z = -(b.y * torque_nm.y + b.x * torque_nm.x) / b.z;
    Ok((m, residual_z))
}

/// Scales a dipole so that no axis exceeds its coil's limit, keeping the direction (all
/// components scaled by the same factor). Returns the dipole and the factor (0..=1).
pub fn saturate_dipole(
    dipole_am2: &Vec3,
    max_per_axis_am2: &Vec3,
) -> Result<(Vec3, f32), MagnetorquerError> {
    if !finite(dipole_am2) || !finite(max_per_axis_am2) {
        return Err(MagnetorquerError::NotFinite);
    }
    // the components read in place (a copy of the pairs costs 122 B of MSP430 code)
    let mut scale = 1.0f32;
    for (m, max) in linalg::arr(dipole_am2)
        .iter()
        .zip(linalg::arr(max_per_axis_am2))
    {
        if !(*max > 0.0) {
            return Err(MagnetorquerError::InvalidParameter);
        }
        let size = fmath::abs(*m);
        if size > *max {
            scale = fmath::min(scale, max / size);
        }
    }
    Ok((linalg::scale(dipole_am2, scale), scale))
}

/// Coil currents `I_i = m_i / (N A)` for air-core coils of `turns` turns and area `area_m2`
/// (note 002 §4.1), A.
pub fn coil_currents(
    dipole_am2: &Vec3,
    turns: f32,
    area_m2: f32,
) -> Result<Vec3, MagnetorquerError> {
    if !finite(dipole_am2) || !turns.is_finite() || !area_m2.is_finite() {
        return Err(MagnetorquerError::NotFinite);
    }
    if !(turns > 0.0) || !(area_m2 > 0.0) {
        return Err(MagnetorquerError::InvalidParameter);
    }
    Ok(dipole_am2 / (turns * area_m2))
}

/// Wheel momentum dumping: the dipole whose torque removes the excess wheel momentum,
/// `m = B × (−k (h − h_target)) / |B|²` (note 002 §8.5 \[derived\]). `h_wheels` is the total
/// wheel angular momentum in body axes (kg·m²/s) and `gain_per_s` is `k` (1/s). The magnetic
/// torque acts on the body; the wheel controller absorbs it, so the wheels slow down: the
/// external torque `τ = −k Δh` drains the stored momentum at rate `k` (the part along `B`
/// cannot be dumped at this instant).
pub fn dumping_dipole(
    h_wheels: &Vec3,
    h_target: &Vec3,
    gain_per_s: f32,
    b_body_nt: &Vec3,
) -> Result<Vec3, MagnetorquerError> {
    if !gain_per_s.is_finite() || !finite(h_wheels) || !finite(h_target) {
        return Err(MagnetorquerError::NotFinite);
    }
    if !(gain_per_s > 0.0) {
        return Err(MagnetorquerError::InvalidParameter);
    }
    // `(−Δh)·k` is `Δh·(−k)` exactly (a product's sign is its factors')
    let torque = linalg::scale(&linalg::sub(h_wheels, h_target), -gain_per_s);
    dipole_for_torque(&torque, b_body_nt)
}

/// [`dumping_dipole`] to a zero target (`h_target = 0`: all the wheels' momentum dumped),
/// bit-equal to it: `h − 0` is `h` exactly (`−0 − 0` is `−0`), so the torque is `h·(−k)`
/// without the subtraction.
pub fn dumping_dipole_to_zero(
    h_wheels: &Vec3,
    gain_per_s: f32,
    b_body_nt: &Vec3,
) -> Result<Vec3, MagnetorquerError> {
    if !gain_per_s.is_finite() || !finite(h_wheels) {
        return Err(MagnetorquerError::NotFinite);
    }
    if !(gain_per_s > 0.0) {
        return Err(MagnetorquerError::InvalidParameter);
    }
    let torque = linalg::scale(h_wheels, -gain_per_s);
    dipole_for_torque(&torque, b_body_nt)
}
