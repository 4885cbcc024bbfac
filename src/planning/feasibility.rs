//! On-board feasibility check of a planned attitude profile (note 001 §5 item 7; seed 001
//! constraints 3.2–3.5 and the metric ∫τ_⊥² of eqs. 4.13/6.7).
//!
//! At `steps + 1` equally spaced times of the profile: attitude, ω, ω̇ from the spline
//! ([`super::spline::AttitudeSpline::sample`]); the required torque by Euler's equation
//! `τ_id = I ω̇ + ω × I ω` (seed 001 eq. 2.31); the field in body axes `b_body = A(q) b_ref`;
//! then the hybrid allocation ([`super::allocation::hybrid`], magnetic only when `N = 0`).
//! The wheel momenta are integrated (trapezoid) from the start momenta. Reported: dipole
//! saturation, wheel torque and speed limits, the torque lost along the field (peak fraction and
//! `∫|τ_lost|² dt`) and the largest shortfall of the delivered torque.
//!
//! Attitudes follow [`crate::attitude`]. Cost: `steps + 1` spline samples and allocations, each
//! a few hundred flops plus one closed-form 3×3 pseudoinverse ([`crate::linalg::pseudoinverse`])
//! per sample when wheels are present.

use crate::control::wheels::Wheel;
use crate::linalg::{Mat3, Vec3};

use super::allocation::{hybrid, magnetic, DipoleSaturation};
use super::spline::AttitudeSpline;
use super::PlanningError;

/// Largest number of steps accepted (bounds the loop).
pub const MAX_STEPS: u32 = 100_000;

/// The actuators' limits.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Limits<const N: usize> {
    /// Coil dipole limit per body axis, A·m².
    pub m_max_am2: Vec3,
    /// How an over-limit dipole is saturated.
    pub saturation: DipoleSaturation,
    /// Wheels with their motor-torque limits (N·m) in `limit`.
    pub wheels: [Wheel; N],
    /// Largest momentum of each wheel, `J ω̃_rw`, kg·m²/s.
    pub wheel_momentum_max: [f32; N],
}

/// What the check found.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FeasibilityReport<const N: usize> {
    /// Largest `|m̃_i|/m_max,i` required (before saturation).
    pub max_dipole_ratio: f32,
    /// Largest required wheel motor torque over its limit (before saturation).
    pub max_wheel_torque_ratio: f32,
    /// Largest `|h_m|` reached by each wheel, kg·m²/s.
    pub max_wheel_momentum: [f32; N],
    /// Largest `|h_m| / h_max,m` over the wheels.
    pub max_wheel_momentum_ratio: f32,
    /// Largest `|τ_lost| / |τ_id|` (0 when the request is zero).
    pub max_lost_fraction: f32,
    /// `∫ |τ_lost|² dt`, N²·m²·s (seed 001's ∫τ_⊥² metric).
    pub lost_torque_integral: f32,
    /// Largest `|τ_id − τ_delivered|`, N·m.
    pub max_shortfall_nm: f32,
    /// Largest `|τ_id|`, N·m.
    pub max_torque_nm: f32,
}

impl<const N: usize> FeasibilityReport<N> {
    /// The coils saturate somewhere.
    pub fn dipole_saturated(&self) -> bool {
        self.max_dipole_ratio > 1.0
    }
    /// A wheel's torque limit is exceeded somewhere.
    pub fn wheel_torque_exceeded(&self) -> bool {
        self.max_wheel_torque_ratio > 1.0
    }
    /// A wheel's speed (momentum) limit is exceeded somewhere.
    pub fn wheel_speed_exceeded(&self) -> bool {
        self.max_wheel_momentum_ratio > 1.0
    }
}

/// Checks the profile `plan` over its whole interval in `steps` steps.
///
/// `inertia_body`: kg·m²; `b_ref_nt(t_s)`: the field in the reference frame (nT) at time `t_s`
/// of the profile (the caller's model: IGRF, dipole...); `h_wheels_start`: each wheel's momentum
/// at the start, kg·m²/s.
pub fn check<const K: usize, const N: usize, F: FnMut(f32) -> Vec3>(
    plan: &AttitudeSpline<K>,
    inertia_body: &Mat3,
    mut b_ref_nt: F,
    limits: &Limits<N>,
    h_wheels_start: &[f32; N],
    steps: u32,
) -> Result<FeasibilityReport<N>, PlanningError> {
    if steps == 0 || steps > MAX_STEPS {
        return Err(PlanningError::InvalidParameter);
    }
    if !inertia_body.iter().all(|x| x.is_finite()) {
        return Err(PlanningError::NotFinite);
    }
    if limits
        .wheel_momentum_max
        .iter()
        .any(|h| !h.is_finite() || *h <= 0.0)
    {
        return Err(PlanningError::InvalidParameter);
    }
    let (t0, t1) = plan.interval();
    let dt = (t1 - t0) / steps as f32;
    let mut h = *h_wheels_start;
    let mut report = FeasibilityReport {
        max_dipole_ratio: 0.0,
        max_wheel_torque_ratio: 0.0,
        max_wheel_momentum: [0.0; N],
        max_wheel_momentum_ratio: 0.0,
        max_lost_fraction: 0.0,
        lost_torque_integral: 0.0,
        max_shortfall_nm: 0.0,
        max_torque_nm: 0.0,
    };
    let mut prev_lost2 = 0.0f32;
    let mut prev_hdot = [0.0f32; N];
    for i in 0..=steps {
        let t = if i == steps { t1 } else { t0 + dt * i as f32 };
        let s = plan.sample(t)?;
        let w = s.omega_radps;
        let tau = inertia_body * s.omega_dot_radps2 + w.cross(&(inertia_body * w));
        let b_ref = b_ref_nt(t);
        if !b_ref.iter().all(|x| x.is_finite()) {
            return Err(PlanningError::NotFinite);
        }
        let b_body = s.jet.q.to_dcm().to_body(&b_ref);
        let h_body = limits
            .wheels
            .iter()
            .zip(h.iter())
            .fold(Vec3::zeros(), |acc, (wh, hm)| acc + wh.axis_body * *hm);
        let (mag, hdot, wheel_ratio, delivered) = if N == 0 {
            let m = magnetic(&tau, &b_body, &limits.m_max_am2, limits.saturation)?;
            (m, [0.0f32; N], 0.0f32, m.torque_nm)
        } else {
            let a = hybrid(
                &tau,
                &b_body,
                &limits.m_max_am2,
                limits.saturation,
                &limits.wheels,
                &h_body,
                &w,
            )?;
            // required |ḣ_m| / limit before the direction-keeping scale
            let after = a
                .wheel_torque_nm
                .iter()
                .zip(limits.wheels.iter())
                .filter(|(_, wh)| wh.working && wh.limit > 0.0)
                .fold(0.0f32, |r, (t, wh)| r.max(t.abs() / wh.limit));
            let ratio = if a.wheel_scale > 0.0 {
                after / a.wheel_scale
            } else {
                f32::INFINITY
            };
            (a.magnetic, a.wheel_torque_nm, ratio, a.delivered_nm)
        };
        report.max_dipole_ratio = report.max_dipole_ratio.max(mag.saturation_ratio);
        report.max_wheel_torque_ratio = report.max_wheel_torque_ratio.max(wheel_ratio);
        let tau_norm = tau.norm();
        report.max_torque_nm = report.max_torque_nm.max(tau_norm);
        let lost = mag.lost_along_b_nm.norm();
        if tau_norm > 0.0 {
            report.max_lost_fraction = report.max_lost_fraction.max(lost / tau_norm);
        }
        report.max_shortfall_nm = report.max_shortfall_nm.max((tau - delivered).norm());
        let lost2 = lost * lost;
        if i > 0 {
            report.lost_torque_integral += 0.5 * (lost2 + prev_lost2) * dt;
            for (hm, (d_now, d_prev)) in h.iter_mut().zip(hdot.iter().zip(prev_hdot.iter())) {
                *hm += 0.5 * (d_now + d_prev) * dt;
            }
        }
        for ((mx, hm), hmax) in report
            .max_wheel_momentum
            .iter_mut()
            .zip(h.iter())
            .zip(limits.wheel_momentum_max.iter())
        {
            *mx = mx.max(hm.abs());
            report.max_wheel_momentum_ratio = report.max_wheel_momentum_ratio.max(hm.abs() / hmax);
        }
        prev_lost2 = lost2;
        prev_hdot = hdot;
    }
    Ok(report)
}
