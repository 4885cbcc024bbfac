//! Air-core magnetorquer sizing (seed 002 §3.6–3.7; note 002 §6.1 and §8.4).
//!
//! # Equations (note 002 §6.1)
//! | quantity | formula |
//! |---|---|
//! | wire cross-section | `a_w = π d² / 4` |
//! | resistance | `R = N p σ / a_w` (p = loop perimeter) |
//! | current at power | `I = √(P / R)` |
//! | dipole | `M = N I A μ_r` (air core: `μ_r = 1`) |
//! | dipole at fixed power | `M = α √N A`, `α = √(P a_w / (p σ))` (amperes) |
//! | turns for a dipole | `N = (M / (α A))²` |
//! | coil mass | `m = ρ_Cu a_w N p` |
//! | torque (M ⟂ B) | `T = M B` |
//!
//! SI units throughout (m, m², W, Ω, A, A·m², T, kg). Design-time functions, cheap enough for
//! on-board checks. `tests/control_sizing.rs` reproduces Tables 3.2–3.7 of the thesis (note 002
//! §6): turns, torques, currents, resistances and masses to half a unit of their last printed
//! digit; the dipole columns of Tables 3.4–3.6 to one unit, because they are internally
//! inconsistent by that much (the thesis mostly truncates: 0.1008 is printed 0.100, yet 0.1495
//! is printed 0.150; 24 of 70 entries differ from the formula by more than half a unit, all by
//! less than one), and their torques are the thesis's `M_printed · B`.

use core::f32::consts::PI;

use crate::fmath;

/// Resistivity of copper used by the thesis, Ω·m (temperature unspecified, note 002 §9.16).
pub const SIGMA_CU_OHM_M: f32 = 1.6e-8;
/// Density of copper, kg/m³.
pub const RHO_CU_KG_M3: f32 = 8.93e3;

/// Cross-section of a round wire of diameter `d_m`, m².
pub fn wire_area_m2(d_m: f32) -> f32 {
    PI * d_m * d_m / 4.0
}

/// Coil resistance `N p σ / a_w`, Ω.
pub fn coil_resistance_ohm(
    turns: f32,
    perimeter_m: f32,
    wire_area_m2: f32,
    sigma_ohm_m: f32,
) -> f32 {
    turns * perimeter_m * sigma_ohm_m / wire_area_m2
}

/// Current at a dissipated power, `√(P/R)`, A.
pub fn current_at_power_a(power_w: f32, resistance_ohm: f32) -> f32 {
    fmath::sqrt(power_w / resistance_ohm)
}

/// `α = √(P a_w / (p σ))`, A: the dipole at fixed power is `α √N A`.
pub fn alpha_a(power_w: f32, wire_area_m2: f32, perimeter_m: f32, sigma_ohm_m: f32) -> f32 {
    fmath::sqrt(power_w * wire_area_m2 / (perimeter_m * sigma_ohm_m))
}

/// Dipole of `turns` turns at `power_w`, `α √N A`, A·m².
pub fn dipole_at_power_am2(
    turns: f32,
    power_w: f32,
    wire_area_m2: f32,
    perimeter_m: f32,
    sigma_ohm_m: f32,
    area_m2: f32,
) -> f32 {
    alpha_a(power_w, wire_area_m2, perimeter_m, sigma_ohm_m) * fmath::sqrt(turns) * area_m2
}

/// Turns for a dipole at the power that sets `alpha`, `(M / (α A))²` (real-valued: round up to
/// build the coil).
pub fn turns_for_dipole(dipole_am2: f32, alpha_a: f32, area_m2: f32) -> f32 {
    let k = dipole_am2 / (alpha_a * area_m2);
    k * k
}

/// Coil mass `ρ a_w N p`, kg.
pub fn coil_mass_kg(turns: f32, wire_area_m2: f32, perimeter_m: f32, rho_kg_m3: f32) -> f32 {
    rho_kg_m3 * wire_area_m2 * turns * perimeter_m
}

/// Dipole `N I A μ_r`, A·m².
pub fn dipole_am2(turns: f32, current_a: f32, area_m2: f32, mu_r: f32) -> f32 {
    turns * current_a * area_m2 * mu_r
}

/// Largest torque of a dipole in a field (M ⟂ B), `M B`, N·m.
pub fn max_torque_nm(dipole_am2: f32, b_t: f32) -> f32 {
    dipole_am2 * b_t
}
