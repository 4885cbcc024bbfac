//! Magnetic torque allocation with the uncontrollable component made explicit (seed 001
//! eqs. 2.39, 3.19–3.23, saturation 3.3/4.12) and the magnetorquer-first hybrid law with
//! reaction wheels (seed 001 §2.5, eqs. 2.44 and 3.24 with the note's `h_sat → h_rw` fix).
//!
//! # Magnetic law
//! ```text
//! m̃ = (b × τ_id)/|b|²              (3.20, via control::magnetorquer::dipole_for_torque)
//! τ_lost = b̂ (b̂·τ_id)               (3.23: the thesis's "τ_⊥", the part ALONG b, never producible)
//! m* = sat(m̃),  τ_mag = m* × b      (3.3; per-axis clip as the thesis, or direction-keeping)
//! ```
//! # Hybrid law (magnetorquers first)
//! With wheels of total momentum `h_rw` (body axes) the body obeys (2.44)
//! `I ω̇ + ω × I ω = m × b − ḣ_rw − ω × h_rw`; the wheels make up `τ_w = τ_id − τ_mag`:
//! ```text
//! ḣ_rw = −τ_w − ω × h_rw,   each wheel's motor torque |ḣ_m| ≤ τ̃_rw (direction-keeping scale)
//! ```
//! allocated with [`crate::control::wheels::allocate`] (torque mode).
//!
//! Fields are in nT (crate unit), torques N·m, dipoles A·m², body axes.

use crate::control::magnetorquer::{self, MagnetorquerError};
use crate::control::wheels::{self, Wheel, WheelError};
use crate::linalg::Vec3;

use super::PlanningError;

/// How a dipole above the coil limit is brought back.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DipoleSaturation {
    /// Clip each axis to ±limit (seed 001's Modelica `saturation`): the torque stays ⊥ b but
    /// turns within that plane.
    PerAxisClip,
    /// Scale the whole dipole (keeps the torque direction;
    /// [`crate::control::magnetorquer::saturate_dipole`]).
    KeepDirection,
}

/// The result of the magnetic allocation.
#[derive(Copy, Clone, Debug, PartialEq)]
// no defmt::Format: nalgebra's Vec3 does not implement it
pub struct MagneticAllocation {
    /// Commanded dipole after saturation, A·m², body.
    pub dipole_am2: Vec3,
    /// Torque the dipole produces, `m* × b`, N·m, body.
    pub torque_nm: Vec3,
    /// The component of the request along b, `b̂(b̂·τ)`, that no dipole can produce, N·m.
    pub lost_along_b_nm: Vec3,
    /// Largest `|m̃_i| / m_max,i` before saturation (> 1 means saturated).
    pub saturation_ratio: f32,
}

fn map_mag(e: MagnetorquerError) -> PlanningError {
    match e {
        MagnetorquerError::WeakField(b) => PlanningError::WeakField(b),
        MagnetorquerError::InvalidParameter => PlanningError::InvalidParameter,
        _ => PlanningError::NotFinite,
    }
}

fn map_wheel(e: WheelError) -> PlanningError {
    match e {
        WheelError::NotFinite => PlanningError::NotFinite,
        _ => PlanningError::InvalidParameter,
    }
}

/// Allocates the torque `torque_nm` (N·m, body) to three orthogonal coils in the field
/// `b_body_nt` (nT, body) with per-axis limits `m_max_am2` (see the [module docs](self)).
pub fn magnetic(
    torque_nm: &Vec3,
    b_body_nt: &Vec3,
    m_max_am2: &Vec3,
    saturation: DipoleSaturation,
) -> Result<MagneticAllocation, PlanningError> {
    if !m_max_am2.iter().all(|x| x.is_finite()) {
        return Err(PlanningError::NotFinite);
    }
    if m_max_am2.iter().any(|m| *m <= 0.0) {
        return Err(PlanningError::InvalidParameter);
    }
    let m_ideal = magnetorquer::dipole_for_torque(torque_nm, b_body_nt).map_err(map_mag)?;
    let achievable = magnetorquer::project_torque(torque_nm, b_body_nt).map_err(map_mag)?;
    let ratio = m_ideal
        .iter()
        .zip(m_max_am2.iter())
        .fold(0.0f32, |r, (m, max)| r.max(m.abs() / max));
    let dipole_am2 = match saturation {
        DipoleSaturation::PerAxisClip => m_ideal.zip_map(m_max_am2, |m, max| m.clamp(-max, max)),
        DipoleSaturation::KeepDirection => {
            magnetorquer::saturate_dipole(&m_ideal, m_max_am2)
                .map_err(map_mag)?
                .0
        }
    };
    Ok(MagneticAllocation {
        dipole_am2,
        torque_nm: magnetorquer::torque_of_dipole(&dipole_am2, b_body_nt),
        lost_along_b_nm: torque_nm - achievable,
        saturation_ratio: ratio,
    })
}

/// The result of the hybrid allocation over `N` wheels.
#[derive(Copy, Clone, Debug, PartialEq)]
// no defmt::Format: nalgebra's Vec3 does not implement it
pub struct HybridAllocation<const N: usize> {
    /// The magnetic part (allocated first).
    pub magnetic: MagneticAllocation,
    /// Motor torque of each wheel along its axis, `ḣ_m`, N·m, after saturation.
    pub wheel_torque_nm: [f32; N],
    /// Factor (0..=1) the wheel torques were scaled by to respect their limits.
    pub wheel_scale: f32,
    /// Torque the body receives from both actuators, N·m, body
    /// (`m* × b − Σ ḣ_m ẑ_m − ω × h_rw`).
    pub delivered_nm: Vec3,
    /// Requested minus delivered, N·m (zero when neither actuator saturates).
    pub shortfall_nm: Vec3,
}

/// Magnetorquers first, wheels for the rest (see the [module docs](self)).
///
/// `torque_nm`: the torque the body must receive (`I ω̇ + ω × I ω`, N·m, body);
/// `wheels`: spin axes and **torque** limits (N·m); `h_rw_body`: current total wheel momentum,
/// kg·m²/s, body; `omega_body_radps`: body rate.
pub fn hybrid<const N: usize>(
    torque_nm: &Vec3,
    b_body_nt: &Vec3,
    m_max_am2: &Vec3,
    saturation: DipoleSaturation,
    wheels_torque_limited: &[Wheel; N],
    h_rw_body: &Vec3,
    omega_body_radps: &Vec3,
) -> Result<HybridAllocation<N>, PlanningError> {
    let magnetic = magnetic(torque_nm, b_body_nt, m_max_am2, saturation)?;
    if !h_rw_body
        .iter()
        .chain(omega_body_radps.iter())
        .all(|x| x.is_finite())
    {
        return Err(PlanningError::NotFinite);
    }
    let tau_w = torque_nm - magnetic.torque_nm;
    let gyro = omega_body_radps.cross(h_rw_body);
    // allocate() gives each wheel the opposite of the body vector: ḣ_m = −ẑ_m·(...), i.e.
    // Σ ḣ_m ẑ_m = −(τ_w + ω × h_rw) for a spanning set.
    let alloc = wheels::allocate(wheels_torque_limited, &(tau_w + gyro)).map_err(map_wheel)?;
    let from_wheels = wheels::body_vector(wheels_torque_limited, &alloc.wheel) - gyro;
    let delivered_nm = magnetic.torque_nm + from_wheels;
    Ok(HybridAllocation {
        magnetic,
        wheel_torque_nm: alloc.wheel,
        wheel_scale: alloc.scale,
        delivered_nm,
        shortfall_nm: torque_nm - delivered_nm,
    })
}
