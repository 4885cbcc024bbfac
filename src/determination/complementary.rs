//! The gyro-aided complementary attitude filter of the ACS loop ([`crate::acs_loop`], step 3).
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A(q) · v_ref`, quaternions scalar-first.
//!
//! One update, with the body rate `ω` (rad/s) over `Δt` (s):
//! 1. **Predict** with the kinematics `q̇ = ½ q ⊗ (0, ω)` (seed 000 §5, eq. 5.25 for `⊗`) to
//!    first order: `p = q ⊗ (1, ½ω Δt)`, renormalised.
//! 2. **Correct** towards the measurement `m` (a Wahba solution): `δ = p* ⊗ m` is the rotation
//!    still to do, in body axes; take the fraction `k` of its vector part on the shorter way
//!    (`sign(δ₀)`): `q = p ⊗ (1, k·sign(δ₀)·δ_v)`, renormalised. For a correction of angle `θ`
//!    this turns by `2·atan(k·sin(θ/2))` towards the measurement: `≈ kθ` for small `θ`.
//!
//! Without a rate there is no prediction: the next measurement restarts the estimate. Without a
//! measurement the prediction is kept for at most `max_propagation_s` (it bridges short gaps,
//! e.g. eclipse entry), then the estimate is dropped.
//!
//! | symbol | name |
//! |---|---|
//! | `q`, `p`, `m` | estimate, prediction, measurement |
//! | `ω`, `Δt` | `omega_body_radps`, `dt_s` |
//! | `k` | [`FilterConfig::gain`] |
//!
//! **Accuracy** (f32, measured by `cargo test --test complementary -- --nocapture`): over 100
//! predictions at 0.031 rad/s, Δt = 1 s, the f32 estimate stays within 1.07e-6 rad of the same
//! scheme in f64; the scheme itself lags the exact rotation by `(|ω|Δt)³/12` per step (2.4e-4
//! rad after the 100 steps: a property of the first-order prediction, not of f32). A correction
//! turns by `2·atan(k·sin(θ/2))` within 2.1e-8 rad.
//!
//! **Cost** on the MSP430: `firmware/msp430-bench --groups parts`, case "step: attitude filter"
//! (`docs/firmware.md`).

use crate::attitude::Quaternion;
use crate::linalg::Vec3;

/// Gains and limits of the filter.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FilterConfig {
    /// `k`: the fraction (0 < k ≤ 1) of the measured correction taken per update.
    pub gain: f32,
    /// Seconds a prediction is kept without a measurement.
    pub max_propagation_s: f32,
}

/// The filtered attitude (reference → body, see [`crate::attitude`]) and the seconds since it
/// last saw a measurement.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Estimate {
    /// The attitude quaternion, unit, scalar-first.
    pub attitude: Quaternion,
    /// Seconds since the last measurement.
    pub age_s: f32,
}

/// One update of the estimate (see the [module docs](self)): `None` when there is no estimate
/// (no measurement yet, a prediction older than `max_propagation_s`, or a non-finite result).
#[cfg_attr(target_arch = "msp430", inline(never))]
pub fn update(
    config: &FilterConfig,
    estimate: Option<Estimate>,
    measured: Option<Quaternion>,
    omega_body_radps: Option<Vec3>,
    dt_s: f32,
) -> Option<Estimate> {
    let predicted = match (estimate, omega_body_radps) {
        (Some(e), Some(w)) => {
            let half = w * (0.5 * dt_s);
            let dq = Quaternion {
                q0: 1.0,
                q1: half.x,
                q2: half.y,
                q3: half.z,
            };
            let p = e.attitude.mul(&dq);
            Quaternion::new_normalize(p.q0, p.q1, p.q2, p.q3).map(|p| Estimate {
                attitude: p,
                age_s: e.age_s + dt_s,
            })
        }
        _ => None,
    };
    match (predicted, measured) {
        (Some(p), Some(m)) => {
            // δ = p* ⊗ m, the correction in body axes; take a fraction of it
            let d = p.attitude.conjugate().mul(&m);
            let sign = if d.q0 >= 0.0 { 1.0 } else { -1.0 };
            let k = config.gain * sign;
            let c = Quaternion {
                q0: 1.0,
                q1: k * d.q1,
                q2: k * d.q2,
                q3: k * d.q3,
            };
            let q = p.attitude.mul(&c);
            Quaternion::new_normalize(q.q0, q.q1, q.q2, q.q3).map(|q| Estimate {
                attitude: q,
                age_s: 0.0,
            })
        }
        (None, Some(m)) => Some(Estimate {
            attitude: m,
            age_s: 0.0,
        }),
        (Some(p), None) if config.max_propagation_s >= p.age_s => Some(p),
        _ => None,
    }
}
