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
    let finite = |v: &Vec3| v.iter().all(|x| x.is_finite());
    if !finite(axis_body)
        || !finite(omega_body_radps)
        || !gains.kp_nm.is_finite()
        || !gains.kd_nms.is_finite()
        || sun_body.is_some_and(|s| !finite(s))
    {
        return Err(TrackingError::NotFinite);
    }
    if !(gains.kp_nm >= 0.0) || !(gains.kd_nms >= 0.0) {
        return Err(TrackingError::NegativeGain);
    }
    let damping = -omega_body_radps * gains.kd_nms;
    let Some(s) = sun_body else {
        return Ok(damping);
    };
    let (Some(s), Some(a)) = (unit(s), unit(axis_body)) else {
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
    Ok(linalg::lin2(&cross, gains.kp_nm, &damping, 1.0))
}

/// `v/|v|`, or `None` for a zero vector (nalgebra's `try_normalize(0.0)`, same operations).
fn unit(v: &Vec3) -> Option<Vec3> {
    let n = linalg::norm(v);
    if !(n > 0.0) {
        None
    } else {
        Some(linalg::div(v, n))
    }
}
