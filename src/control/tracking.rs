//! Quaternion-feedback tracking control with reaction wheels (Wie, Weiss & Arapostathis 1989,
//! "Quaternion feedback regulator for spacecraft eigenaxis rotations", JGCD 12(3); Wie,
//! *Space Vehicle Dynamics and Control*, §7.3). The thesis left closed-loop tracking as future
//! work (note 000 §1.1).
//!
//! Attitudes follow [`crate::attitude`]: `A(q)` maps reference to body; the body attitude obeys
//! `q̇ = ½ q ⊗ (0, ω)` with ω in body axes.
//!
//! # Law
//! ```text
//! q_e = q_t* ⊗ q                      (A(q_e) = A(q) A(q_t)ᵀ: target body → actual body)
//! ω_e = ω − A(q_e) ω_t
//! τ   = −K_p sign(q_e0) q_e,vec − K_d ω_e + ω × (I ω + h_w)
//! ```
//! `τ` is the torque the body must receive (N·m, body axes); the wheels produce it by
//! `ḣ_w = −τ` (allocate with [`super::wheels::allocate`]). The gyroscopic term cancels the
//! coupling `ω × (Iω + h_w)` of `I ω̇ = τ_ext − ω × (Iω + h_w) − ḣ_w`.
//!
//! # Stability
//! With positive-definite diagonal `K_p`, `K_d` and the gyroscopic compensation, the closed loop
//! is globally asymptotically stable about `q_e = ±1` (Lyapunov function
//! `V = ½ ω_eᵀ I ω_e + k (1 − |q_e0|)` for `K_p = k I`, Wie et al. 1989); `sign(q_e0)` takes the
//! shorter way round (no unwinding). [`TrackingGains::from_bandwidth`] sets
//! `K_p = 2 ω_n² I`, `K_d = 2 ζ ω_n I` (per axis, small-angle natural frequency `ω_n` in rad/s
//! and damping `ζ`), because `q_e,vec ≈ θ/2` for small errors.

use core::fmt;

use crate::attitude::Quaternion;
use crate::linalg::{arr, finite3, mat_vec, Mat3, Vec3};

/// Gains of the law, per body axis.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TrackingGains {
    /// `K_p`, N·m per unit of quaternion vector part.
    #[cfg_attr(feature = "defmt", defmt(Debug2Format))]
    pub kp_nm: Vec3,
    /// `K_d`, N·m·s/rad.
    #[cfg_attr(feature = "defmt", defmt(Debug2Format))]
    pub kd_nms: Vec3,
}

/// Errors of the tracking law.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum TrackingError {
    /// An input is NaN or infinite.
    NotFinite,
    /// A gain is negative.
    NegativeGain,
}

impl fmt::Display for TrackingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotFinite => write!(f, "tracking input is NaN or infinite"),
            Self::NegativeGain => write!(f, "tracking gain is negative"),
        }
    }
}

impl TrackingGains {
    /// `K_p = 2 ω_n² I_kk`, `K_d = 2 ζ ω_n I_kk` from the diagonal of the body inertia
    /// (kg·m²), the natural frequency `omega_n_radps` and the damping ratio `zeta`.
    ///
    /// A `const fn`, so that a flight configuration can be a `static` in flash.
    pub const fn from_bandwidth(inertia_body: &Mat3, omega_n_radps: f32, zeta: f32) -> Self {
        // the diagonal, from the column-major storage (`inertia_body.diagonal()` is not const)
        let [[i11, _, _], [_, i22, _], [_, _, i33]] = inertia_body.data.0;
        let kp = 2.0 * omega_n_radps * omega_n_radps;
        let kd = 2.0 * zeta * omega_n_radps;
        Self {
            kp_nm: Vec3::new(i11 * kp, i22 * kp, i33 * kp),
            kd_nms: Vec3::new(i11 * kd, i22 * kd, i33 * kd),
        }
    }
}

/// The attitude error `q_e = q_t* ⊗ q`, sign chosen so that `q_e0 ≥ 0` (the shorter way).
pub fn attitude_error(q: &Quaternion, q_target: &Quaternion) -> Quaternion {
    let e = q_target.conjugate().mul(q);
    if !(e.q0 >= 0.0) {
        Quaternion {
            q0: -e.q0,
            q1: -e.q1,
            q2: -e.q2,
            q3: -e.q3,
        }
    } else {
        e
    }
}

/// The body torque (N·m, body axes) of the quaternion-feedback law (see the [module
/// docs](self)). `omega_target_radps` is the target's rate in the target body frame,
/// `h_wheels` the wheels' total momentum in body axes (kg·m²/s).
pub fn tracking_torque(
    gains: &TrackingGains,
    inertia_body: &Mat3,
    q: &Quaternion,
    omega_body_radps: &Vec3,
    q_target: &Quaternion,
    omega_target_radps: &Vec3,
    h_wheels: &Vec3,
) -> Result<Vec3, TrackingError> {
    // an input NaN or infinite makes the torque so (every input enters it through products and
    // sums, never a comparison alone; `tests/control_laws.rs` poisons each): one check of the
    // result, not of the 32 inputs (156 B less of MSP430 code)
    let e = attitude_error(q, q_target);
    let e_vec = Vec3::new(e.q1, e.q2, e.q3);
    let omega_e = crate::linalg::sub(omega_body_radps, &e.to_dcm().to_body(omega_target_radps));
    let gyroscopic = crate::linalg::cross(
        omega_body_radps,
        &(mat_vec(inertia_body, omega_body_radps) + h_wheels),
    );
    // τᵢ = (−K_p,i e_i − K_d,i ω_e,i) + gyroscopicᵢ, one loop over the axes
    let mut tau = Vec3::zeros();
    let terms = arr(&gains.kp_nm)
        .iter()
        .zip(arr(&e_vec))
        .zip(arr(&gains.kd_nms).iter().zip(arr(&omega_e)))
        .zip(arr(&gyroscopic));
    for (t, (((kp, e), (kd, w)), g)) in tau.iter_mut().zip(terms) {
        *t = -(kp * e) - kd * w + g;
    }
    if !finite3(&tau) {
        return Err(TrackingError::NotFinite);
    }
    // (finite here)
    if negative(&gains.kp_nm) || negative(&gains.kd_nms) {
        return Err(TrackingError::NegativeGain);
    }
    Ok(tau)
}

/// A component of `v` is below zero (or NaN), out of line on the MSP430: two uses.
#[cfg_attr(target_arch = "msp430", inline(never))]
fn negative(v: &Vec3) -> bool {
    !arr(v).iter().all(|x| *x >= 0.0)
}
