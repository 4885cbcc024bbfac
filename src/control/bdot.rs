//! B-dot detumbling (Stickler & Alfriend 1976; seed 002 ch. 3 context; issue #7 item 4).
//!
//! A magnetorquer dipole opposed to the rate of change of the body-frame field removes
//! rotational energy:
//! ```text
//! from the magnetometer:  m = −k Ḃ_body,   Ḃ ≈ (B_k − B_{k−1}) / Δt
//! from the gyros:         m =  k (ω × B_body)   (Ḃ_body ≈ −ω × B_body for a slowly varying field)
//! ```
//! With `τ = m × B`, the gyro form gives `ω·τ = k [(ω·B)² − |ω|²|B|²] ≤ 0`: the law never adds
//! rotational energy (tested as a property). The component of ω along B cannot be damped at that
//! instant; the orbit turns B and damps it over time.
//!
//! # Units and gains
//! | name | meaning | unit |
//! |---|---|---|
//! | `gain` | `k` | A·m² per (T/s) for the magnetometer form, A·m² per (rad/s · T) for the gyro form |
//! | `b_body_nt` | field, body frame | nT |
//! | `dt_s` | sample interval | s |
//! | `max_dipole_am2` | per-axis coil limit | A·m² |
//!
//! A usual choice is `k = 2 ω_orb (1 + sin ξ) I_min / |B|²` (Avanzini & Giulietti 2012), with
//! ξ the orbit's inclination to the geomagnetic equator; the output is saturated per axis keeping
//! its direction ([`super::magnetorquer::saturate_dipole`]).

use crate::control::magnetorquer::{saturate_dipole, MagnetorquerError};
use crate::linalg::{self, Vec3};

/// Nanotesla to tesla.
const NT_TO_T: f32 = 1e-9;

/// Configuration of the B-dot law.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BdotConfig {
    /// Gain `k` (see the [module docs](self) for its unit in each form).
    pub gain: f32,
    /// Per-axis dipole limit, A·m².
    #[cfg_attr(feature = "defmt", defmt(Debug2Format))]
    pub max_dipole_am2: Vec3,
}

/// State of the magnetometer-derivative form: the previous field sample.
#[derive(Copy, Clone, Debug, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BdotState {
    #[cfg_attr(feature = "defmt", defmt(Debug2Format))]
    previous_b_nt: Option<Vec3>,
}

impl BdotState {
    /// Forgets the previous sample (after a gap, a mode change or while the torquers disturbed
    /// the magnetometer).
    pub fn reset(&mut self) {
        self.previous_b_nt = None;
    }

    /// One step of `m = −k Ḃ` from a new field sample `b_body_nt` taken `dt_s` after the
    /// previous one. Returns `Ok(None)` on the first sample (no derivative yet: torquers off).
    /// On error the state is reset, so a bad sample never enters a later derivative.
    pub fn update(
        &mut self,
        config: &BdotConfig,
        b_body_nt: &Vec3,
        dt_s: f32,
    ) -> Result<Option<Vec3>, MagnetorquerError> {
        if !linalg::finite3(b_body_nt) || !dt_s.is_finite() || !config.gain.is_finite() {
            self.reset();
            return Err(MagnetorquerError::NotFinite);
        }
        if !(dt_s > 0.0) || !(config.gain >= 0.0) {
            self.reset();
            return Err(MagnetorquerError::InvalidParameter);
        }
        let previous = self.previous_b_nt.replace(*b_body_nt);
        let Some(prev) = previous else {
            return Ok(None);
        };
        let b_dot_t_per_s = linalg::scale(&linalg::sub(b_body_nt, &prev), NT_TO_T / dt_s);
        // `(−Ḃ)·k` is `Ḃ·(−k)` exactly (a product's sign is its factors'; a NaN is refused)
        let m = linalg::scale(&b_dot_t_per_s, -config.gain);
        saturate_dipole(&m, &config.max_dipole_am2).map(|(m, _)| Some(m))
    }
}

/// The gyro form `m = k (ω × B)` (A·m²), saturated per axis keeping direction.
pub fn bdot_from_rates(
    config: &BdotConfig,
    omega_body_radps: &Vec3,
    b_body_nt: &Vec3,
) -> Result<Vec3, MagnetorquerError> {
    if !linalg::finite3(omega_body_radps) || !linalg::finite3(b_body_nt) || !config.gain.is_finite()
    {
        return Err(MagnetorquerError::NotFinite);
    }
    if !(config.gain >= 0.0) {
        return Err(MagnetorquerError::InvalidParameter);
    }
    let b_t = linalg::scale(b_body_nt, NT_TO_T);
    let m = linalg::scale(&linalg::cross(omega_body_radps, &b_t), config.gain);
    saturate_dipole(&m, &config.max_dipole_am2).map(|(m, _)| m)
}
