//! Sun-pointing safe mode: turn a body axis (the solar-array normal) to the Sun and damp the
//! rates; in eclipse, rate damping only (issue #7 item 4; the thesis has no safe mode).
//!
//! # Law
//! With `ŝ` the measured Sun direction and `â` the axis to point, both unit vectors in body axes:
//! ```text
//! τ = K_p (â × ŝ) − K_d ω          (Sun visible)
//! τ = −K_d ω                       (eclipse: no Sun)
//! ```
//! Rotating the body by `δθ ∝ â × ŝ` moves the body-frame Sun direction by
//! `ŝ × (â × ŝ) = â − ŝ (â·ŝ)`, toward `â`. At the unstable equilibrium `â = −ŝ` the cross
//! product vanishes; the law then uses a fixed axis perpendicular to `â` to leave it.
//! `K_p` (N·m) and `K_d` (N·m·s/rad) positive: stable about `â = ŝ` (the pointing error angle
//! obeys a damped pendulum equation `I θ̈ + K_d θ̇ + K_p sin θ = 0` about a fixed axis).
//! With magnetorquers only, pass the torque to [`super::magnetorquer::dipole_for_torque`].

use crate::control::tracking::TrackingError;
use crate::linalg::{self, Vec3};

/// `â·ŝ` below which the Sun is taken as behind the pointing axis (176°).
const ANTI_ALIGNED_COS: f32 = -0.998;

/// Gains of the sun-safe law.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SunSafeGains {
    /// `K_p`, N·m.
    pub kp_nm: f32,
    /// `K_d`, N·m·s/rad.
    pub kd_nms: f32,
}

/// The sun-safe torque (N·m, body). `sun_body` is the measured unit Sun direction in body axes,
/// `None` in eclipse (then rate damping only); `axis_body` the unit axis to point.
pub fn sun_safe_torque(
    gains: &SunSafeGains,
    sun_body: Option<&Vec3>,
    axis_body: &Vec3,
    omega_body_radps: &Vec3,
) -> Result<Vec3, TrackingError> {
    // an input NaN or infinite fails its unit vector or makes the torque so (`K_p`, which
    // the eclipse's torque leaves out, checked itself; `tests/control_laws.rs` poisons each
    // input): one check of the result, not of the 11 inputs
    let Some(a) = unit(axis_body) else {
        return Err(TrackingError::NotFinite);
    };
    // `(−ω)·K_d` is `ω·(−K_d)` exactly (a product's sign is its factors')
    let damping = linalg::scale(omega_body_radps, -gains.kd_nms);
    let tau = match sun_body {
        None => damping,
        Some(s) => {
            let Some(s) = unit(s) else {
                return Err(TrackingError::NotFinite);
            };
            let cross = if !(linalg::dot(&a, &s) >= ANTI_ALIGNED_COS) {
                // leave the unstable equilibrium about an axis perpendicular to â
                let helper = if !(a.x.abs() >= 0.9) {
                    Vec3::x()
                } else {
                    Vec3::y()
                };
                let c = linalg::cross(&a, &helper);
                linalg::div(&c, linalg::norm(&c))
            } else {
                linalg::cross(&a, &s)
            };
            // `cross·K_p + damping` (the damping term times 1 is itself)
            linalg::lin2(&cross, gains.kp_nm, &damping, 1.0)
        }
    };
    if !(linalg::finite3(&tau) && gains.kp_nm.is_finite()) {
        return Err(TrackingError::NotFinite);
    }
    if !(gains.kp_nm >= 0.0) || !(gains.kd_nms >= 0.0) {
        return Err(TrackingError::NegativeGain);
    }
    Ok(tau)
}

/// `v/|v|`, or `None` for a zero or non-finite `v` (nalgebra's `try_normalize(0.0)`, same
/// operations).
fn unit(v: &Vec3) -> Option<Vec3> {
    let n = linalg::norm(v);
    if !(n > 0.0 && n.is_finite()) {
        None
    } else {
        Some(linalg::div(v, n))
    }
}
