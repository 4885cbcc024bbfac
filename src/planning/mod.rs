//! Attitude trajectory planning with magnetorquers and reaction wheels: the on-board pieces of
//! seed 001 (Donati 2010, *Pianificazione di traiettorie di assetto per piccoli satelliti*;
//! note 001 §5 "Directly usable onboard").
//!
//! - [`kinematics`]: quaternion kinematics `q̇ = ½ q ⊗ (0, ω)` and its closed-form inverse
//!   `ω = 2 Ξ(q)ᵀ q̇`, `ω̇ = 2 Ξ(q)ᵀ q̈` (note 001 §1.5), with the conversions from seed 001's
//!   scalar-last storage.
//! - [`spline`]: the clamped cubic spline (eqs. 4.15–4.20, reconstructed 4.18–4.19) and the
//!   attitude profile built from three of them (eqs. 3.15–3.17).
//! - [`allocation`]: the magnetic allocation law with the torque lost along the field made
//!   explicit (eqs. 3.20–3.23) and the magnetorquer-first hybrid law with wheels (§2.5).
//! - [`feasibility`]: the on-board check of a planned profile (note 001 §5 item 7).
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A(q) · v_ref`, quaternions scalar-first.
//! The ground planner that optimises the profile is `host::planner` (host feature).

pub mod allocation;
pub mod feasibility;
pub mod kinematics;
pub mod spline;

use core::fmt;

/// Errors of the planning functions.
#[derive(Copy, Clone, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum PlanningError {
    /// An input is NaN or infinite.
    NotFinite,
    /// A quaternion is not of unit norm (its norm).
    NotUnit(f32),
    /// The quaternion vector part is too long for `q0 = √(1 − |q_v|²)` (its norm).
    VectorPartTooLong(f32),
    /// Fewer than two knots, or more than the capacity (the number given).
    KnotCount(usize),
    /// Knot times not strictly increasing (the index of the first offending knot).
    KnotsNotIncreasing(usize),
    /// An evaluation time outside the spline's interval, s.
    OutOfRange(f32),
    /// The field is too weak for magnetic allocation, nT.
    WeakField(f32),
    /// A limit or parameter is not positive.
    InvalidParameter,
}

impl fmt::Display for PlanningError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotFinite => write!(f, "planning input is NaN or infinite"),
            Self::NotUnit(n) => write!(f, "quaternion norm {n} is not 1"),
            Self::VectorPartTooLong(n) => {
                write!(
                    f,
                    "quaternion vector part of norm {n} leaves no scalar part"
                )
            }
            Self::KnotCount(n) => write!(f, "{n} knots: need at least 2 and at most the capacity"),
            Self::KnotsNotIncreasing(i) => write!(f, "knot {i} is not after the previous one"),
            Self::OutOfRange(t) => write!(f, "time {t} s outside the spline's interval"),
            Self::WeakField(b) => write!(f, "field {b} nT too weak for magnetic allocation"),
            Self::InvalidParameter => write!(f, "planning limit or parameter not positive"),
        }
    }
}
